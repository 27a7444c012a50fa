#!/usr/bin/python3
"""Convert the comma2k19 RAV4 segment (data/real/comma2k19_rav4_segment/) into a sensor bag on the topic contract
of tread_wear_vehicle_inputs (docs/real_car.md):

  imu           sensor_msgs/Imu         frame imu_link, REP-103 axes (x forward, y left, z up), specific force incl.
                                        gravity [m/s^2], angular velocity [rad/s] (the phone's bias-corrected gyro)
  joint_states  sensor_msgs/JointState  velocities [rad/s] of wheel_{front,rear}_{left,right}_joint = CAN wheel
                                        speed [m/s] / nominal rolling radius; position [rad] of steering_wheel_joint
                                        (one message per CAN sample, wheels and steering-wheel angle together)
  odom          nav_msgs/Odometry       frame odom, child base_link, twist.twist.linear.x = CAN vehicle speed [m/s]
  /tf_static    tf2_msgs/TFMessage      base_link -> imu_link: the phone's mounting rotation estimated here
  pose_velocity geometry_msgs/TwistStamped  reference only: the fused pose's velocity in base_link [m/s]
                                        (ECEF velocity -> device frame with the pose quaternion -> base_link with
                                        the mount); angular part 0

Stamps: the log's t (device boot time, s). Only numpy and python3-rosbag (Debian packages); nav_msgs is generated
from /usr/share/nav_msgs/msg when python3-nav-msgs is not installed.

Mount estimate (IMU -> body, R_m = Rz(yaw) Ry(pitch) Rx(roll), the tf's rotation): on a 10 Hz grid of 1 s
averages, the body-frame specific force the car must have felt is f_b = (dv/dt + g sin(grade), v r, g cos(grade))
with dv/dt from the CAN speed, r the gyro yaw rate and the road grade from the fused pose's velocity (vertical over
horizontal, independent of the pose's orientation). R_m is the rotation that best maps the phone's specific force
onto f_b (Wahba's problem, SVD): gravity fixes roll and pitch, the speed changes (+-1.5 m/s^2) fix the yaw.
Cross-check printed: the same angles from the fused pose's orientation (device attitude relative to the road and
to the direction of travel).

Usage: scripts/comma2k19_to_bag.py [--data DIR] --out OUT.bag [--rolling-radius 0.35] [--report checks.json]
"""
import argparse
import json
import math
import os
import sys

import numpy as np
import rosbag
import rospy
from geometry_msgs.msg import TransformStamped, TwistStamped
from sensor_msgs.msg import Imu, JointState
from tf2_msgs.msg import TFMessage

GRAVITY = 9.81
WHEEL_JOINTS = ["wheel_front_left_joint", "wheel_front_right_joint", "wheel_rear_left_joint",
                "wheel_rear_right_joint"]
STEERING_JOINT = "steering_wheel_joint"
FRD_TO_FLU = np.diag([1.0, -1.0, -1.0])  # (forward, right, down) -> (forward, left, up)
# Phone on the windscreen behind the mirror, relative to base_link = the CoG (as the estimator reads the tf):
# an estimate from the RAV4's geometry (front axle 1.09 m ahead of the CoG, windscreen base about 0.4 m behind it,
# mirror about 1.35 m above the road, CoG 0.62 m). Used only for the lever-arm terms, which are small here.
IMU_POSITION_ESTIMATE_M = (0.70, 0.0, 0.70)


def odometry_class():
    """nav_msgs/Odometry: the installed module, or one generated from the message definitions in /usr/share."""
    try:
        from nav_msgs.msg import Odometry
        return Odometry
    except ImportError:
        pass
    import genmsg
    import genmsg.msg_loader
    import genpy.dynamic
    ctx = genmsg.MsgContext.create_default()
    search = {p: [os.path.join("/usr/share", p, "msg")] for p in ("nav_msgs", "geometry_msgs", "std_msgs")}
    spec = genmsg.msg_loader.load_msg_by_type(ctx, "nav_msgs/Odometry", search)
    genmsg.msg_loader.load_depends(ctx, spec, search)
    full_text = genmsg.compute_full_text(ctx, spec)
    return genpy.dynamic.generate_dynamic("nav_msgs/Odometry", full_text)["nav_msgs/Odometry"]


def load(data_dir, name):
    return np.load(os.path.join(data_dir, name))


def quat_to_rot(q):
    """(w, x, y, z) rows -> rotation matrices (device -> ECEF for the comma2k19 pose)."""
    w, x, y, z = q.T
    r = np.empty((len(q), 3, 3))
    r[:, 0, 0] = 1 - 2 * (y * y + z * z); r[:, 0, 1] = 2 * (x * y - w * z); r[:, 0, 2] = 2 * (x * z + w * y)
    r[:, 1, 0] = 2 * (x * y + w * z); r[:, 1, 1] = 1 - 2 * (x * x + z * z); r[:, 1, 2] = 2 * (y * z - w * x)
    r[:, 2, 0] = 2 * (x * z - w * y); r[:, 2, 1] = 2 * (y * z + w * x); r[:, 2, 2] = 1 - 2 * (x * x + y * y)
    return r


def rot_to_quat(r):
    """Rotation matrix -> (x, y, z, w)."""
    w = math.sqrt(max(0.0, 1.0 + r[0, 0] + r[1, 1] + r[2, 2])) / 2.0
    x = math.copysign(math.sqrt(max(0.0, 1.0 + r[0, 0] - r[1, 1] - r[2, 2])) / 2.0, r[2, 1] - r[1, 2])
    y = math.copysign(math.sqrt(max(0.0, 1.0 - r[0, 0] + r[1, 1] - r[2, 2])) / 2.0, r[0, 2] - r[2, 0])
    z = math.copysign(math.sqrt(max(0.0, 1.0 - r[0, 0] - r[1, 1] + r[2, 2])) / 2.0, r[1, 0] - r[0, 1])
    return x, y, z, w


def euler_deg(r):
    """R = Rz(yaw) Ry(pitch) Rx(roll) -> (roll, pitch, yaw) [deg]."""
    return (math.degrees(math.atan2(r[2, 1], r[2, 2])), math.degrees(-math.asin(max(-1.0, min(1.0, r[2, 0])))),
            math.degrees(math.atan2(r[1, 0], r[0, 0])))


def enu_basis(ecef):
    """WGS-84 geodetic east, north, up unit vectors (ECEF) at each position."""
    a, e2 = 6378137.0, 6.69437999014e-3
    x, y, z = ecef.T
    lon = np.arctan2(y, x)
    p = np.hypot(x, y)
    lat = np.arctan2(z, p * (1 - e2))
    for _ in range(6):
        n = a / np.sqrt(1 - e2 * np.sin(lat) ** 2)
        h = p / np.cos(lat) - n
        lat = np.arctan2(z, p * (1 - e2 * n / (n + h)))
    sl, cl, so, co = np.sin(lat), np.cos(lat), np.sin(lon), np.cos(lon)
    east = np.stack([-so, co, 0 * so], 1)
    north = np.stack([-sl * co, -sl * so, cl], 1)
    up = np.stack([cl * co, cl * so, sl], 1)
    return east, north, up, np.degrees(lat[0]), np.degrees(lon[0])


def window_mean(t, x, grid, width):
    """Mean of the samples of x within +-width/2 of each grid time."""
    cs = np.concatenate([np.zeros((1,) + x.shape[1:]), np.cumsum(x, 0)])
    i0 = np.searchsorted(t, grid - width / 2)
    i1 = np.searchsorted(t, grid + width / 2)
    n = np.maximum(i1 - i0, 1)
    return (cs[i1] - cs[i0]) / (n[:, None] if x.ndim > 1 else n)


def wahba(a, b):
    """Rotation R minimising sum |b_k - R a_k|^2."""
    u, _, vt = np.linalg.svd(a.T @ b)
    d = np.diag([1.0, 1.0, np.linalg.det(vt.T @ u.T)])
    return vt.T @ d @ u.T


def stamp(t):
    return rospy.Time.from_sec(float(t))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--data", default=os.path.join(here, "..", "data", "real", "comma2k19_rav4_segment"))
    ap.add_argument("--out", required=True, help="output bag")
    ap.add_argument("--rolling-radius", type=float, default=0.35,
                    help="nominal rolling radius [m] that turns CAN wheel speed [m/s] into rad/s (225/65 R17: "
                         "0.35 m; the estimator learns the true one)")
    ap.add_argument("--report", help="write the mount estimate and the data checks as JSON here")
    ap.add_argument("--mount-yaw-deg", type=float,
                    help="publish this mount yaw instead of the estimate (sensitivity studies; roll and pitch kept)")
    args = ap.parse_args()
    d = args.data

    t_acc, acc = load(d, "processed_log/IMU/accelerometer/t"), load(d, "processed_log/IMU/accelerometer/value")
    t_gyr, gyr = load(d, "processed_log/IMU/gyro/t"), load(d, "processed_log/IMU/gyro/value")
    t_spd, spd = load(d, "processed_log/CAN/speed/t"), load(d, "processed_log/CAN/speed/value")[:, 0]
    t_whl, whl = load(d, "processed_log/CAN/wheel_speed/t"), load(d, "processed_log/CAN/wheel_speed/value")
    t_ste, ste = load(d, "processed_log/CAN/steering_angle/t"), load(d, "processed_log/CAN/steering_angle/value")
    t_pos = load(d, "global_pose/frame_times")
    pos, vel, quat = (load(d, "global_pose/frame_positions"), load(d, "global_pose/frame_velocities"),
                      load(d, "global_pose/frame_orientations"))
    for name, t in (("accelerometer", t_acc), ("gyro", t_gyr), ("speed", t_spd), ("wheel_speed", t_whl),
                    ("steering", t_ste), ("pose", t_pos)):
        if not np.all(np.diff(t) > 0):
            sys.exit("comma2k19_to_bag: %s stamps are not increasing" % name)
    if not np.array_equal(t_acc, t_gyr):
        sys.exit("comma2k19_to_bag: accelerometer and gyro stamps differ")

    # --- axes: phone (forward, right, down) -> REP-103 (forward, left, up) ---
    f_imu = acc @ FRD_TO_FLU.T
    w_imu = gyr @ FRD_TO_FLU.T

    # --- fused pose: device frame velocity, road grade, device attitude relative to the road ---
    r_dev = quat_to_rot(quat)                                  # device (FRD) -> ECEF
    east, north, up, lat0, lon0 = enu_basis(pos)
    v_dev = np.einsum("nji,nj->ni", r_dev, vel) @ FRD_TO_FLU.T  # velocity in the device axes, FLU
    v_enu = np.stack([(vel * east).sum(1), (vel * north).sum(1), (vel * up).sum(1)], 1)
    grade_pose = np.arctan2(v_enu[:, 2], np.hypot(v_enu[:, 0], v_enu[:, 1]))
    heading = np.unwrap(np.arctan2(v_enu[:, 0], v_enu[:, 1]))  # from north, clockwise [rad]
    up_dev = np.einsum("nji,nj->ni", r_dev, up) @ FRD_TO_FLU.T  # local up in device FLU axes
    dev_pitch = np.degrees(np.arcsin(np.clip(up_dev[:, 0], -1, 1)))  # nose up > 0, relative to level
    dev_roll = np.degrees(np.arctan2(up_dev[:, 1], up_dev[:, 2]))    # REP-103 roll (left side up > 0)

    # --- mount estimate on a 10 Hz grid of 1 s averages ---
    t0 = max(t_acc[0], t_spd[0], t_pos[0]) + 1.0
    t1 = min(t_acc[-1], t_spd[-1], t_pos[-1]) - 1.0
    grid = np.arange(t0, t1, 0.1)
    f_g = window_mean(t_acc, f_imu, grid, 1.0)
    w_g = window_mean(t_gyr, w_imu, grid, 1.0)
    v_g = window_mean(t_spd, spd, grid, 1.0)
    dv_g = np.gradient(v_g, grid)
    grade_g = window_mean(grid, np.interp(grid, t_pos, grade_pose), grid, 1.0)
    r_m = np.eye(3)
    for _ in range(3):  # the yaw rate in f_b,y = v r uses the mount; converges in two passes
        yaw_rate = (w_g @ r_m.T)[:, 2]
        f_b = np.stack([dv_g + GRAVITY * np.sin(grade_g), v_g * yaw_rate, GRAVITY * np.cos(grade_g)], 1)
        r_m = wahba(f_g, f_b)
    roll, pitch, yaw = euler_deg(r_m)
    resid = f_g @ r_m.T - f_b
    # gravity-only (roll, pitch): the mean specific force direction, mean dv/dt and grade removed
    f_lvl = f_g.mean(0)
    pitch_g = math.degrees(math.atan2(-f_lvl[0], f_lvl[2])) + math.degrees(np.mean(
        (dv_g + GRAVITY * np.sin(grade_g)) / GRAVITY))
    roll_g = math.degrees(math.atan2(f_lvl[1], f_lvl[2]))
    # repeatability of the yaw: the same fit on each half of the segment
    half = len(grid) // 2
    yaw_halves = [euler_deg(wahba(f_g[s_], f_b[s_]))[2] for s_ in (slice(0, half), slice(half, None))]
    # pose cross-check: device attitude minus road grade, and the velocity direction in the device axes
    fwd = np.hypot(v_dev[:, 0], v_dev[:, 1]) > 5.0
    # in the mount's convention (REP-103: pitch > 0 nose down, yaw > 0 device x left of the car's x):
    pose_pitch_rel = float(-np.mean(dev_pitch[fwd] - np.degrees(grade_pose[fwd])))  # relative to the road's grade
    pose_roll = float(np.mean(dev_roll[fwd]))  # relative to level: includes the road's crossfall
    pose_yaw = float(-np.degrees(np.mean(np.arctan2(v_dev[fwd, 1], v_dev[fwd, 0]))))  # if the sideslip is 0

    print("comma2k19_to_bag: data %s (lat %.5f, lon %.5f), %.1f s" % (os.path.normpath(d), lat0, lon0,
                                                                       t_spd[-1] - t_spd[0]))
    print("mount estimate (IMU -> base_link, R = Rz(yaw) Ry(pitch) Rx(roll)): roll %.2f deg, pitch %.2f deg, "
          "yaw %.2f deg" % (roll, pitch, yaw))
    print("  method: Wahba fit of the phone's 1 s-averaged specific force onto (dv/dt + g sin(grade), v r, "
          "g cos(grade)), CAN speed, pose grade; residual RMS x %.3f y %.3f z %.3f m/s^2"
          % tuple(np.sqrt((resid ** 2).mean(0))))
    print("  gravity direction alone: roll %.2f, pitch %.2f deg; yaw fitted on each half of the segment: %.2f, %.2f deg"
          % (roll_g, pitch_g, yaw_halves[0], yaw_halves[1]))
    print("  fused pose cross-check (the pose's device frame, same convention): pitch relative to the road's grade "
          "%.2f deg, roll relative to level (includes crossfall) %.2f deg, yaw from the direction of travel (sideslip "
          "taken as 0) %.2f deg" % (pose_pitch_rel, pose_roll, pose_yaw))

    if args.mount_yaw_deg is not None:
        dyaw = math.radians(args.mount_yaw_deg) - math.atan2(r_m[1, 0], r_m[0, 0])
        rz = np.array([[math.cos(dyaw), -math.sin(dyaw), 0.0], [math.sin(dyaw), math.cos(dyaw), 0.0], [0, 0, 1.0]])
        r_m = rz @ r_m
        print("  OVERRIDE: mount yaw set to %.2f deg (--mount-yaw-deg); published roll %.2f, pitch %.2f, yaw %.2f deg"
              % ((args.mount_yaw_deg,) + euler_deg(r_m)))

    # --- data checks ---
    whl_at_spd = np.array([np.interp(t_spd, t_whl, whl[:, i]) for i in range(4)]).T
    moving = spd > 5.0
    ratio = (whl_at_spd[moving] / spd[moving, None]).mean(0)
    rms = np.sqrt(((whl_at_spd[moving] - spd[moving, None]) ** 2).mean(0))
    f_body = f_imu @ r_m.T
    w_body = w_imu @ r_m.T
    heading_rate = np.gradient(heading, t_pos)
    yaw_pose = np.interp(grid, t_pos, heading_rate) * -1.0  # clockwise heading -> REP-103 yaw rate (left > 0)
    yaw_gyr = (w_g @ r_m.T)[:, 2]
    dv_corr = float(np.corrcoef((f_g @ r_m.T)[:, 0], dv_g)[0, 1])
    ste_g = window_mean(t_ste, ste, grid, 1.0)
    v_pose_g = window_mean(t_pos, np.linalg.norm(vel, axis=1), grid, 1.0)
    checks = {
        "data": {"t_start_s": float(t_spd[0]), "duration_s": float(t_spd[-1] - t_spd[0]),
                 "speed_min_mps": float(spd.min()), "speed_max_mps": float(spd.max()),
                 "steering_wheel_min_deg": float(ste.min()), "steering_wheel_max_deg": float(ste.max()),
                 "heading_change_deg": float(np.degrees(heading[-1] - heading[0])),
                 "grade_min_deg": float(np.degrees(grade_pose.min())),
                 "grade_max_deg": float(np.degrees(grade_pose.max()))},
        "mount_deg": {"roll": roll, "pitch": pitch, "yaw": yaw,
                      "residual_rms_mps2": [float(x) for x in np.sqrt((resid ** 2).mean(0))],
                      "gravity_only_roll": roll_g, "gravity_only_pitch": pitch_g,
                      "yaw_first_half": yaw_halves[0], "yaw_second_half": yaw_halves[1],
                      "pose_pitch_relative_to_road": pose_pitch_rel, "pose_roll": pose_roll,
                      "pose_travel_direction_yaw": pose_yaw},
        "wheel_speed_over_can_speed": {"mean_ratio_fl_fr_rl_rr": [float(x) for x in ratio],
                                       "rms_difference_mps": [float(x) for x in rms]},
        "pose_speed_minus_can_speed_mps": {
            "mean": float(np.mean(v_pose_g - v_g)), "rms": float(np.sqrt(np.mean((v_pose_g - v_g) ** 2)))},
        "gravity": {"specific_force_norm_mean_mps2": float(np.linalg.norm(f_imu, axis=1).mean()),
                    "body_fz_mean_mps2": float(f_body[:, 2].mean())},
        "axes": {"corr_body_fx_vs_can_dvdt": dv_corr,
                 "gyro_yaw_rate_vs_pose_heading_rate_corr": float(np.corrcoef(yaw_gyr, yaw_pose)[0, 1]),
                 "gyro_yaw_rate_minus_pose_rms_radps": float(np.sqrt(np.mean((yaw_gyr - yaw_pose) ** 2))),
                 "yaw_rate_vs_steering_corr": float(np.corrcoef(yaw_gyr, ste_g)[0, 1])},
        "rolling_radius_nominal_m": args.rolling_radius,
        "imu_position_estimate_m": list(IMU_POSITION_ESTIMATE_M),
    }
    print("checks: wheel/CAN speed ratio FL %.4f FR %.4f RL %.4f RR %.4f (above 5 m/s), RMS difference %s m/s"
          % (tuple(ratio) + (np.array2string(rms, precision=3),)))
    print("        fused-pose speed - CAN speed: mean %+.3f, RMS %.3f m/s"
          % (checks["pose_speed_minus_can_speed_mps"]["mean"], checks["pose_speed_minus_can_speed_mps"]["rms"]))
    print("        |f| mean %.3f m/s^2, body f_z mean %.3f m/s^2 (gravity, up > 0)"
          % (checks["gravity"]["specific_force_norm_mean_mps2"], checks["gravity"]["body_fz_mean_mps2"]))
    print("        corr(body f_x, CAN dv/dt) %.3f; corr(gyro yaw rate, pose heading rate) %.3f, RMS diff %.4f rad/s;"
          " corr(yaw rate, steering) %.3f" % (dv_corr, checks["axes"]["gyro_yaw_rate_vs_pose_heading_rate_corr"],
                                               checks["axes"]["gyro_yaw_rate_minus_pose_rms_radps"],
                                               checks["axes"]["yaw_rate_vs_steering_corr"]))

    # --- the bag ---
    odometry = odometry_class()
    out = []
    for k in range(len(t_acc)):
        m = Imu()
        m.header.stamp = stamp(t_acc[k]); m.header.frame_id = "imu_link"
        m.orientation_covariance[0] = -1.0  # no orientation
        m.linear_acceleration.x, m.linear_acceleration.y, m.linear_acceleration.z = (float(x) for x in f_imu[k])
        m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z = (float(x) for x in w_imu[k])
        out.append((t_acc[k], "imu", m))
    ste_rad = np.radians(np.interp(t_whl, t_ste, ste))  # steering-wheel angle at the wheel-speed stamps
    for k in range(len(t_whl)):
        m = JointState()
        m.header.stamp = stamp(t_whl[k])
        m.name = WHEEL_JOINTS + [STEERING_JOINT]
        m.position = [0.0, 0.0, 0.0, 0.0, float(ste_rad[k])]  # wheel positions unknown (not used)
        m.velocity = [float(x) / args.rolling_radius for x in whl[k]] + [0.0]
        out.append((t_whl[k], "joint_states", m))
    for k in range(len(t_spd)):
        m = odometry()
        m.header.stamp = stamp(t_spd[k]); m.header.frame_id = "odom"; m.child_frame_id = "base_link"
        m.pose.pose.orientation.w = 1.0
        m.twist.twist.linear.x = float(spd[k])
        out.append((t_spd[k], "odom", m))
    v_base = v_dev @ r_m.T
    for k in range(len(t_pos)):
        m = TwistStamped()
        m.header.stamp = stamp(t_pos[k]); m.header.frame_id = "base_link"
        m.twist.linear.x, m.twist.linear.y, m.twist.linear.z = (float(x) for x in v_base[k])
        out.append((t_pos[k], "pose_velocity", m))
    tf = TransformStamped()
    t_first = min(t_acc[0], t_whl[0], t_spd[0], t_pos[0])
    tf.header.stamp = stamp(t_first); tf.header.frame_id = "base_link"; tf.child_frame_id = "imu_link"
    tf.transform.translation.x, tf.transform.translation.y, tf.transform.translation.z = IMU_POSITION_ESTIMATE_M
    qx, qy, qz, qw = rot_to_quat(r_m)
    tf.transform.rotation.x, tf.transform.rotation.y, tf.transform.rotation.z, tf.transform.rotation.w = qx, qy, qz, qw
    out.append((t_first, "/tf_static", TFMessage(transforms=[tf])))
    out.sort(key=lambda e: (e[0], e[1] != "/tf_static"))
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    with rosbag.Bag(args.out, "w") as bag:
        for t, topic, m in out:
            bag.write(topic, m, stamp(t))
    # self-check: the contract's topics, types and counts as written
    expected = {"imu": ("sensor_msgs/Imu", len(t_acc)), "joint_states": ("sensor_msgs/JointState", len(t_whl)),
                "odom": ("nav_msgs/Odometry", len(t_spd)), "/tf_static": ("tf2_msgs/TFMessage", 1),
                "pose_velocity": ("geometry_msgs/TwistStamped", len(t_pos))}
    with rosbag.Bag(args.out) as bag:
        info = bag.get_type_and_topic_info().topics
    for topic, (msg_type, count) in expected.items():
        if topic not in info or info[topic].msg_type != msg_type or info[topic].message_count != count:
            sys.exit("comma2k19_to_bag: %s in %s is not %s x %d: %s" % (topic, args.out, msg_type, count,
                                                                       info.get(topic)))
    print("wrote %s: imu %d, joint_states %d, odom %d, pose_velocity %d, /tf_static 1 (rolling radius %.3f m)"
          % (args.out, len(t_acc), len(t_whl), len(t_spd), len(t_pos), args.rolling_radius))
    if args.report:
        os.makedirs(os.path.dirname(os.path.abspath(args.report)), exist_ok=True)
        with open(args.report, "w") as fh:
            json.dump(checks, fh, indent=2)
            fh.write("\n")


if __name__ == "__main__":
    main()
