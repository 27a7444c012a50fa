#!/usr/bin/python3
"""Synthetic sensors of the passenger car (config/vehicle_passenger_car.yaml) for vehicle_inputs_node demos and the
rviz screenshot (test/ros/rviz_vehicle_screenshot.sh): sensor_msgs/Imu on `imu` (frame imu_link, mounted at the CoG,
/tf_static base_link -> imu_link), sensor_msgs/JointState on `joint_states` (wheel velocities [rad/s], steering-wheel
position [rad]) and geometry_msgs/TwistWithCovarianceStamped on `speed` (run the node with speed_source:=twist).
Drives a steady circle: --speed [m/s], --radius [m] (> 0 left, 0 = straight), at --rate [Hz]. Header stamps = now."""
import argparse
import math

import rospy
from geometry_msgs.msg import TransformStamped, TwistWithCovarianceStamped
from sensor_msgs.msg import Imu, JointState
from tf2_msgs.msg import TFMessage

M, L, LF, H, TF, TR, G, R_WHEEL, I_S = 1450.0, 2.64, 1.06, 0.55, 1.55, 1.52, 9.81, 0.31, 15.0
JOINTS = ["wheel_front_left_joint", "wheel_front_right_joint", "wheel_rear_left_joint", "wheel_rear_right_joint"]


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--speed", type=float, default=15.0)
    parser.add_argument("--radius", type=float, default=40.0)
    parser.add_argument("--rate", type=float, default=100.0)
    args, _ = parser.parse_known_args(rospy.myargv()[1:])
    rospy.init_node("publish_vehicle_sensors")
    imu_pub = rospy.Publisher("imu", Imu, queue_size=50)
    joint_pub = rospy.Publisher("joint_states", JointState, queue_size=50)
    speed_pub = rospy.Publisher("speed", TwistWithCovarianceStamped, queue_size=50)
    tf_pub = rospy.Publisher("/tf_static", TFMessage, queue_size=1, latch=True)
    t = TransformStamped()
    t.header.stamp = rospy.Time.now()
    t.header.frame_id = "base_link"
    t.child_frame_id = "imu_link"
    t.transform.translation.z = H
    t.transform.rotation.w = 1.0
    tf_pub.publish(TFMessage([t]))
    v = args.speed
    r = v / args.radius if args.radius != 0.0 else 0.0
    delta = math.atan(L * r / v) if v > 0 else 0.0
    lr = L - LF
    xs, ys = [LF, LF, -lr, -lr], [TF / 2, -TF / 2, TR / 2, -TR / 2]
    rate = rospy.Rate(args.rate)
    while not rospy.is_shutdown():
        now = rospy.Time.now()
        imu = Imu()
        imu.header.stamp = now
        imu.header.frame_id = "imu_link"
        imu.linear_acceleration.y = v * r
        imu.linear_acceleration.z = G
        imu.angular_velocity.z = r
        imu.orientation_covariance[0] = -1.0
        imu_pub.publish(imu)
        js = JointState()
        js.header.stamp = now
        js.name = JOINTS + ["steering_wheel_joint"]
        js.velocity = [math.hypot(v - r * y, r * x) / R_WHEEL for x, y in zip(xs, ys)] + [0.0]
        js.position = [0.0] * 4 + [I_S * delta]
        joint_pub.publish(js)
        sp = TwistWithCovarianceStamped()
        sp.header.stamp = now
        sp.header.frame_id = "base_link"
        sp.twist.twist.linear.x = v
        speed_pub.publish(sp)
        rate.sleep()


if __name__ == "__main__":
    main()
