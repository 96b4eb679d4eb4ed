#!/usr/bin/env python3
"""The rocky walk over many rocky terrains: a distribution, not one scene.

Makes N variants of scenes/rocky_mockup.yaml (the same generator: another
terrain seed, so other ground relief and other boulders; every second one
walks the path mirrored left-right), runs `stridemap experiment rocky-walk`
on each with the options given after `--`, and prints the median, 90th
percentile and worst of the whole-walk RMS error, the offset-free RMS and
the sensor-height error. Simulated results.

  tools/rocky_walk_distribution.py --bin build/bin/stridemap --out /tmp/dist --terrains 10 \\
      --label fused -- --reference map-fused --calibrate-attitude on

With --random, the terrains are `stridemap scene random --kind rocky --seed
N` for N = first..first+terrains-1 instead (their own ground, boulders and
path). --sensor structured-light walks Ragno's camera and stripe (no mixed
pixels: they are the URG's). The mean offset's distribution is over its
absolute value.
"""
import argparse
import json
import os
import re
import subprocess
import sys


def mirrored_path(scene_text):
    """The scene's walk_path with y and every turn negated."""
    path = scene_text[scene_text.index("\nwalk_path:") + 1:]
    path = re.sub(r" *#.*", "", path)
    path = re.sub(r"y_m: (-?[0-9.]+)", lambda m: "y_m: %g" % -float(m.group(1)), path)
    path = re.sub(r"(turn_deg|yaw_deg): (-?[0-9.]+)", lambda m: "%s: %g" % (m.group(1), -float(m.group(2))), path)
    return path


def variant(scene_text, k):
    text = re.sub(r"(\n  seed: )\d+", lambda m: m.group(1) + str(100 + k), scene_text, count=1)
    if k % 2 == 1:
        text = text[:text.index("\nwalk_path:") + 1] + mirrored_path(scene_text)
    return text


def percentile(values, q):
    ordered = sorted(values)
    position = q * (len(ordered) - 1)
    low = int(position)
    high = min(low + 1, len(ordered) - 1)
    return ordered[low] + (ordered[high] - ordered[low]) * (position - low)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--bin", required=True)
    parser.add_argument("--scene", default="scenes/rocky_mockup.yaml")
    parser.add_argument("--out", required=True, help="a new folder for the scenes and runs")
    parser.add_argument("--terrains", type=int, default=10)
    parser.add_argument("--label", default="run")
    parser.add_argument("--random", action="store_true", help="terrains from `scene random --kind rocky`")
    parser.add_argument("--first", type=int, default=1, help="the first terrain's seed (walk seed too)")
    parser.add_argument("--sensor", choices=["urg", "structured-light"], default="urg")
    parser.add_argument("rest", nargs=argparse.REMAINDER, help="-- then rocky-walk options")
    args = parser.parse_args()
    extra = args.rest[1:] if args.rest[:1] == ["--"] else args.rest
    with open(args.scene) as f:
        scene_text = f.read()
    os.makedirs(args.out, exist_ok=True)
    rows = []
    under_soles = []
    for k in range(args.first - 1, args.first - 1 + args.terrains):
        scene = os.path.join(args.out, "terrain_%02d.yaml" % k)
        if not os.path.exists(scene):
            if args.random:
                subprocess.run([args.bin, "scene", "random", "--kind", "rocky", "--seed", str(k + 1), "--out", scene],
                               check=True, stdout=subprocess.DEVNULL)
            else:
                with open(scene, "w") as f:
                    f.write(variant(scene_text, k))
        out = os.path.join(args.out, args.label, "terrain_%02d" % k)
        summary_path = os.path.join(out, "rocky-walk-" + args.sensor, "summary.json")
        if not os.path.exists(summary_path):
            sensor = ["--sensor", args.sensor] + (["--mixed-pixels", "on"] if args.sensor == "urg" else [])
            command = [args.bin, "experiment", "rocky-walk"] + sensor + ["--scene", scene, "--seed", str(k + 1),
                       "--sweep", "none", "--quiet", "--out", out] + extra
            subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
        with open(summary_path) as f:
            s = json.load(f)
        rows.append((s["map"]["rms_error_m"], s["map"]["rms_error_offset_free_m"], s["pose_rms"]["sensor_height_m"],
                     s["map"]["mean_error_m"]))
        if "fused_under_soles" in s:
            under_soles.append(s["fused_under_soles"]["mean_error_m"])
        print("%s terrain %02d: RMS %.1f mm, offset-free %.1f mm, mean %+.1f mm, sensor height %.1f mm"
              % (args.label, k, rows[-1][0] * 1e3, rows[-1][1] * 1e3, rows[-1][3] * 1e3, rows[-1][2] * 1e3), flush=True)
    result = {"label": args.label, "terrains": len(rows), "options": extra, "source": "simulation"}
    for i, name in enumerate(["rms_error_m", "rms_error_offset_free_m", "sensor_height_rms_m", "abs_mean_error_m"]):
        values = [abs(r[i]) for r in rows]
        result[name] = {"median": percentile(values, 0.5), "p90": percentile(values, 0.9), "worst": max(values)}
        print("%s %s: median %.1f mm, 90th pct %.1f mm, worst %.1f mm" % (
            args.label, name, result[name]["median"] * 1e3, result[name]["p90"] * 1e3, result[name]["worst"] * 1e3))
    if under_soles:
        # Signed: the bias an h_ref read under the feet inherits from the map alone.
        mean = sum(under_soles) / len(under_soles)
        sd = (sum((v - mean) ** 2 for v in under_soles) / max(1, len(under_soles) - 1)) ** 0.5
        result["fused_under_soles_m"] = {"median": percentile(under_soles, 0.5), "mean": mean, "sd": sd,
                                         "walks": len(under_soles)}
        print("%s fused layer under the true soles, per walk (signed): median %+.2f mm, mean %+.2f mm, sd %.2f mm"
              % (args.label, percentile(under_soles, 0.5) * 1e3, mean * 1e3, sd * 1e3))
    with open(os.path.join(args.out, args.label + ".json"), "w") as f:
        json.dump(result, f, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
