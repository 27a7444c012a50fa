#!/usr/bin/python3
"""Publishes synthetic inputs (load, slip, speed) for tread_wear_node's wheels at a fixed rate.

For demos, the rviz screenshot and the CPU measurement (docs/node.md); not a vehicle model (the drive
generator tread_wear_drive is). A passenger car in a steady left curve with a slowly oscillating slip angle:
load 4000 N +- 10 %, speed 15 m/s, slip angle -2 deg +- 1.5 deg (period 4 s), slip ratio 0.02, curvature 1/100 m.
Needs the package's Python messages: source <build>/devel/setup.bash first.
"""
import argparse
import math

import rospy
from tread_wear.msg import WheelLoad, WheelSlip, WheelSpeed


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--wheels", default="front_left,front_right,rear_left,rear_right",
                        help="comma-separated wheel names (topics wheels/<name>/...)")
    parser.add_argument("--rate", type=float, default=100.0, help="publish rate per input [Hz]")
    parser.add_argument("--duration", type=float, default=0.0, help="stop after this many seconds (0 = run)")
    args = parser.parse_args(rospy.myargv()[1:])
    rospy.init_node("publish_wheel_inputs")
    pubs = []
    for name in args.wheels.split(","):
        pubs.append((rospy.Publisher("wheels/%s/load" % name, WheelLoad, queue_size=10),
                     rospy.Publisher("wheels/%s/slip" % name, WheelSlip, queue_size=10),
                     rospy.Publisher("wheels/%s/speed" % name, WheelSpeed, queue_size=10)))
    rate = rospy.Rate(args.rate)
    start = rospy.Time.now()
    while not rospy.is_shutdown():
        now = rospy.Time.now()
        t = (now - start).to_sec()
        if args.duration > 0 and t > args.duration:
            break
        for k, (pl, ps, pv) in enumerate(pubs):
            phase = 0.5 * k
            load = WheelLoad(load_n=4000.0 * (1.0 + 0.1 * math.sin(0.5 * t + phase)))
            slip = WheelSlip(slip_angle_rad=math.radians(-2.0 + 1.5 * math.sin(2.0 * math.pi * t / 4.0 + phase)),
                             slip_ratio=0.02, path_curvature_per_m=0.01)
            speed = WheelSpeed(speed_mps=15.0)
            for msg in (load, slip, speed):
                msg.header.stamp = now
            pl.publish(load)
            ps.publish(slip)
            pv.publish(speed)
        rate.sleep()


if __name__ == "__main__":
    main()
