#!/usr/bin/python3
"""Replay throughput of `stridemap map --log` and `map --bag`: scans per
second of CPU on one core and peak memory, on synthetic recordings of two
lengths (tools/make_scan_log.py, tools/make_scan_bag.py). `make
bench-compare` prints it after the contenders' tables (docs/performance.md).

The rate is taken between the two lengths, (long - short) scans over
(long - short) CPU seconds, so that start-up and writing the outputs, the
same for both, drop out. The peak memory of both runs shows whether it
grows with the recording's length.

    tools/replay_throughput.py --tool build/bin/stridemap --scans 2000,20000
    tools/replay_throughput.py --tool build/bin/stridemap --config fused.yaml   # map's --config
"""
import argparse
import os
import subprocess
import sys
import tempfile

TOOLS = os.path.dirname(os.path.abspath(__file__))


class ReplayError(Exception):
    pass


def run_measured(command, what):
    """Runs command; returns (user + system CPU seconds, peak RSS in MB)."""
    try:
        child = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    except OSError as error:
        raise ReplayError("%s: cannot start %s: %s" % (what, command[0], error.strerror))
    output = child.stdout.read()
    _, status, usage = os.wait4(child.pid, 0)
    child.returncode = os.waitstatus_to_exitcode(status)
    if child.returncode != 0:
        raise ReplayError("%s failed (exit %d): %s\n%s" % (what, child.returncode, " ".join(command),
                                                         output.decode(errors="replace")[-2000:]))
    return usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024.0


def make_log(scans, work):
    log = os.path.join(work, "r%d.log" % scans)
    poses = os.path.join(work, "r%d.poses" % scans)
    subprocess.run([sys.executable, os.path.join(TOOLS, "make_scan_log.py"), "--scans", str(scans),
                    "--log", log, "--poses", poses], check=True)
    return ["--log", log, "--poses", poses]


def make_bag(scans, work):
    bag = os.path.join(work, "r%d.bag" % scans)
    subprocess.run([sys.executable, os.path.join(TOOLS, "make_scan_bag.py"), "--scans", str(scans),
                    "--bag", bag], check=True)
    return ["--bag", bag, "--scan-topic", "/scan", "--tf"]


def bag_available(tool):
    """A bag needs Debian's python3-rosbag to write and a tool built with ROS to read."""
    try:
        import rosbag  # noqa: F401
    except ImportError:
        return False, "no python3-rosbag"
    help_text = subprocess.run([tool, "map", "--help"], capture_output=True, text=True).stdout
    if "--bag" not in help_text:
        return False, "the tool was built without ROS"
    return True, ""


def measure(tool, source, make_input, lengths, work, config):
    runs = []
    for scans in lengths:
        arguments = make_input(scans, work) + (["--config", config] if config else [])
        out = os.path.join(work, "%s_out_%d" % (source, scans))
        cpu_s, peak_mb = run_measured([tool, "map", *arguments, "--out", out, "--quiet"],
                                      "map --%s of %d scans" % (source, scans))
        runs.append((scans, cpu_s, peak_mb))
    (short_scans, short_s, _), (long_scans, long_s, _) = runs[0], runs[-1]
    # A difference at or below the clock's resolution would give no rate at all.
    rate = (long_scans - short_scans) / (long_s - short_s) if long_s - short_s > 0.005 else float("nan")
    return runs, rate


def parse_lengths(text):
    try:
        lengths = [int(part) for part in text.split(",")]
    except ValueError:
        raise ReplayError("--scans %s: give two whole numbers of scans, short,long (e.g. 2000,20000)" % text)
    if len(lengths) != 2 or lengths[0] < 1 or lengths[1] <= lengths[0]:
        raise ReplayError("--scans %s: give two lengths, short,long, with 1 <= short < long" % text)
    return lengths


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tool", required=True, help="the stridemap program (e.g. build/bin/stridemap)")
    parser.add_argument("--scans", default="2000,20000", help="the two recording lengths, short,long")
    parser.add_argument("--bag", choices=["auto", "on", "off"], default="auto",
                        help="time map --bag too: auto (when rosbag and a ROS build are there), on (fail without), off")
    parser.add_argument("--work", help="folder for the recordings and maps (default: a temporary one, removed)")
    parser.add_argument("--config", help="a mapper configuration for every map run (docs/config.md)")
    args = parser.parse_args()
    try:
        lengths = parse_lengths(args.scans)
        if not (os.path.isfile(args.tool) and os.access(args.tool, os.X_OK)):
            raise ReplayError("--tool %s: not an executable file" % args.tool)
        if args.config is not None and not os.path.isfile(args.config):
            raise ReplayError("--config %s: not a file" % args.config)
        sources = [("log", make_log)]
        bag_note = ""
        if args.bag != "off":
            available, why = bag_available(args.tool)
            if available:
                sources.append(("bag", make_bag))
            elif args.bag == "on":
                raise ReplayError("--bag on: cannot time map --bag: %s" % why)
            else:
                bag_note = "map --bag not timed: %s" % why
        with tempfile.TemporaryDirectory(prefix="stridemap-replay-") as scratch:
            work = args.work or scratch
            if args.work:
                os.makedirs(work, exist_ok=True)
            print("| replay | scans | CPU [s] | peak RSS [MB] | scans/s past start-up |")
            print("| --- | --- | --- | --- | --- |")
            for source, make_input in sources:
                runs, rate = measure(args.tool, source, make_input, lengths, work, args.config)
                for index, (scans, cpu_s, peak_mb) in enumerate(runs):
                    shown_rate = "%.0f" % rate if index == len(runs) - 1 else ""
                    print("| map --%s | %d | %.2f | %.1f | %s |" % (source, scans, cpu_s, peak_mb, shown_rate))
        if bag_note:
            print(bag_note)
    except subprocess.CalledProcessError as error:
        print("replay_throughput: writing a recording failed (exit %d): %s" % (error.returncode, " ".join(error.cmd)),
              file=sys.stderr)
        return 1
    except ReplayError as error:
        print("replay_throughput: %s" % error, file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
