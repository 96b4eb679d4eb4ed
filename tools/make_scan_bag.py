#!/usr/bin/python3
"""Writes a ROS 1 bag of synthetic URG-04LX scans on /scan with TF
(map -> base_link each scan, base_link -> laser on /tf_static), for timing
`stridemap map --bag` on bags of any length (docs/performance.md). The
scans see the ground about 0.5 m away with a ripple that changes from scan
to scan; the robot moves 0.3 m/s. Deterministic. Needs Debian's python3-rosbag.

    tools/make_scan_bag.py --scans 20000 --bag /tmp/run.bag
    build/bin/stridemap map --bag /tmp/run.bag --scan-topic /scan --tf --out /tmp/bag_map
"""
import argparse
import math
import os

import rosbag
import rospy
from geometry_msgs.msg import TransformStamped
from sensor_msgs.msg import LaserScan
from tf2_msgs.msg import TFMessage

T0 = 1733065200.0


def transform(time_s, parent, child, x_m, z_m, pitch_rad):
    t = TransformStamped()
    t.header.stamp = rospy.Time.from_sec(time_s)
    t.header.frame_id = parent
    t.child_frame_id = child
    t.transform.translation.x = x_m
    t.transform.translation.z = z_m
    t.transform.rotation.y = math.sin(pitch_rad / 2)
    t.transform.rotation.w = math.cos(pitch_rad / 2)
    return t


def scan(time_s, k):
    s = LaserScan()
    s.header.stamp = rospy.Time.from_sec(time_s)
    s.header.frame_id = "laser"
    s.angle_min = -2.0862  # the URG-04LX's 682 steps of 0.3516 deg
    s.angle_increment = 0.00613592
    s.angle_max = s.angle_min + 681 * s.angle_increment
    s.range_min, s.range_max, s.scan_time = 0.02, 5.6, 0.1
    s.ranges = [0.5 + 0.01 * math.sin(0.1 * b + k) for b in range(682)]
    return s


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scans", type=int, required=True)
    parser.add_argument("--bag", required=True)
    args = parser.parse_args()
    # As make_scan_log.py: a file already there is someone's, never replaced.
    if os.path.lexists(args.bag):
        parser.error("--bag %s: already exists; give a new file" % args.bag)
    with rosbag.Bag(args.bag, "w") as bag:
        bag.write("/tf_static", TFMessage([transform(T0, "base_link", "laser", 0.1, 0.3, 0.6)]), rospy.Time.from_sec(T0))
        for k in range(args.scans):
            t = T0 + 0.1 * k
            for dt in (-0.05, 0.0):  # a pose before each scan and one at it
                trunk = transform(t + dt, "map", "base_link", 0.03 * k + 0.3 * dt, 0.0, 0.0)
                bag.write("/tf", TFMessage([trunk]), rospy.Time.from_sec(t + dt))
            bag.write("/scan", scan(t, k), rospy.Time.from_sec(t + 0.001))


if __name__ == "__main__":
    main()
