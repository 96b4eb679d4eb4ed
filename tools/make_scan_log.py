#!/usr/bin/python3
"""Writes a synthetic URG-04LX scan log (docs/live.md format) and a matching
pose file, for measuring `stridemap map --log` on logs of any length
(docs/performance.md). The scans are the ground 0.45 m ahead with a ripple
that changes from scan to scan; the robot walks at 0.3 m/s. Deterministic.

    tools/make_scan_log.py --scans 6000 --log /tmp/run.log --poses /tmp/run.poses
"""
import argparse
import zlib


def line(body):
    return "%s *%08x\n" % (body, zlib.crc32(body.encode()) & 0xFFFFFFFF)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scans", type=int, required=True)
    parser.add_argument("--log", required=True)
    parser.add_argument("--poses", required=True)
    args = parser.parse_args()
    t0 = 1733065200.0
    with open(args.log, "x") as log:
        log.write(line("stridemap-urg-log 1"))
        log.write(line("device /dev/ttyACM0"))
        log.write(line("sensor %r" % t0))
        for key, value in [("VEND", "Hokuyo Automatic Co.,Ltd."), ("PROD", "SOKUIKI Sensor URG-04LX"),
                           ("FIRM", "3.3.00"), ("PROT", "SCIP 2.0"), ("SERI", "H0000")]:
            log.write(line("vv %s:%s" % (key, value)))
        for key, value in [("MODL", "URG-04LX(Hokuyo Automatic Co.,Ltd.)"), ("DMIN", "20"), ("DMAX", "5600"),
                           ("ARES", "1024"), ("AMIN", "44"), ("AMAX", "725"), ("AFRT", "384"), ("SCAN", "600")]:
            log.write(line("pp %s:%s" % (key, value)))
        for k in range(args.scans):
            t = t0 + 0.1 * k + 0.05
            values = " ".join(str(420 + (k * 7 + i * 13) % 60) for i in range(682))
            log.write(line("scan %d %r %r %d %d 0 %d 44 1 682 %s" % (k, t, t + 0.01, (100 * k) % (1 << 24), 100 * k,
                                                                    1 if k == 0 else 0, values)))
    with open(args.poses, "x") as poses:
        poses.write("# stridemap poses: time_s x_m y_m yaw_rad pitch_rad roll_rad\n")
        for k in range(2 * args.scans + 4):
            poses.write("%r %r 0 0 0 0\n" % (t0 + 0.05 * k, 0.015 * k))


if __name__ == "__main__":
    main()
