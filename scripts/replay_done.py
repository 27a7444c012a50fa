#!/usr/bin/python3
"""Ends a replay (launch/replay.launch, exit_at_end:=true) once tread_wear_node has processed the whole bag.

rosbag play exits as soon as it has handed its last message to its publishers; what they still hold for the node is
lost with the process. replay.launch therefore keeps the player alive (--keep-alive) and runs this node as the
required one: it exits when the node's `wear` is stamped at the bag's end (under simulated time the wheels' outputs
carry the input time they have stepped to), or when that stamp has not moved for --idle-s of wall time after the
clock passed the bag's end (a wheel whose inputs end early). Needs the package's Python messages.
"""
import argparse
import time

import rosbag
import rospy
from tread_wear.msg import VehicleWear


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("bag")
    parser.add_argument("--idle-s", type=float, default=5.0, help="wall time without progress after the end [s]")
    args, _ = parser.parse_known_args(rospy.myargv()[1:])
    with rosbag.Bag(args.bag) as bag:
        end_s = bag.get_end_time()
    rospy.init_node("replay_done")
    state = {"stamp": 0.0, "moved": time.monotonic()}

    def on_wear(msg):
        stamp = msg.header.stamp.to_sec()
        if stamp != state["stamp"]:
            state["stamp"], state["moved"] = stamp, time.monotonic()

    rospy.Subscriber("wear", VehicleWear, on_wear, queue_size=10)
    # The wheels step every update period: the last step falls up to one period before the bag's last stamp.
    period_s = 1.0 / rospy.get_param("tread_wear_node/update_rate_hz", 100.0)
    while not rospy.is_shutdown():
        time.sleep(0.1)
        if state["stamp"] >= end_s - period_s - 1e-6:
            break
        past_end = rospy.get_time() >= end_s
        if past_end and time.monotonic() - state["moved"] > args.idle_s:
            rospy.logwarn("replay_done: the wheels stopped at %.3f s of bag time, %.3f s before its end",
                          state["stamp"], end_s - state["stamp"])
            break
    # One more publication cycle, so that the last step is on `wear` for whoever records it.
    time.sleep(2.0 * period_s + 0.1)


if __name__ == "__main__":
    main()
