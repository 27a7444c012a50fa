#!/usr/bin/env bash
# Proof on a real car (docs/real_car.md): the comma2k19 2017 Toyota RAV4 segment (60 s, highway on-ramp) through the
# offline vehicle-inputs front end and the wear replay, with the checks a reviewer makes and their plots.
#   1. scripts/comma2k19_to_bag.py: sensor bag on the topic contract (imu, joint_states, odom, /tf_static with the
#      estimated IMU mount) + pose_velocity (the fused pose's velocity in base_link, the sideslip reference)
#   2. tread_wear_vehicle_inputs: sensors -> wheels/<name>/{load,slip,speed} (config/vehicle_rav4_2017.yaml)
#   3. tread_wear_replay: wear per wheel (config/vehicle_wheels.yaml: the package's 205/55 R16 tire file)
#   4. checks + plots (/usr/bin/python3, numpy, matplotlib): loads vs weight, slip ratios by driving phase, slip
#      angles vs the fused pose, wear per wheel -> OUT_DIR/real_car_checks.json and OUT_DIR/real_car_*.png
# Usage: scripts/real_car_demo.sh [OUT_DIR]   (default out/real_car; tools from $TREAD_WEAR_BIN, default
#        _build/devel/lib/tread_wear, the README's build; extra converter options in
#        $REAL_CAR_CONVERT_ARGS, e.g. "--mount-yaw-deg 0.82" for the mount-yaw sensitivity of docs/real_car.md)
set -euo pipefail
repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "${repo_root}"
export PATH="/usr/bin:${PATH}"
out_dir="${1:-out/real_car}"
mkdir -p "${out_dir}"
bin="${TREAD_WEAR_BIN:-_build/devel/lib/tread_wear}"
for tool in tread_wear_vehicle_inputs tread_wear_replay; do
  [[ -x ${bin}/${tool} ]] || { echo "[real_car] ERROR: ${tool} not built (set TREAD_WEAR_BIN)" >&2; exit 1; }
done

vehicle=config/vehicle_rav4_2017.yaml
radius=0.35          # nominal rolling radius [m] (225/65 R17), the converter's and the estimator's
steering_ratio=14.5  # end-to-end specification (config/vehicle_rav4_2017.yaml)

echo "[real_car] 1/4 converting data/real/comma2k19_rav4_segment -> ${out_dir}/rav4_sensors.bag"
/usr/bin/python3 scripts/comma2k19_to_bag.py --out "${out_dir}/rav4_sensors.bag" --rolling-radius "${radius}" \
  --report "${out_dir}/conversion.json" ${REAL_CAR_CONVERT_ARGS:-} | tee "${out_dir}/conversion.log"

echo "[real_car] 2/4 front end: ${bin}/tread_wear_vehicle_inputs (100 Hz)"
"${bin}/tread_wear_vehicle_inputs" "${out_dir}/rav4_sensors.bag" "${out_dir}/rav4_inputs.bag" --vehicle "${vehicle}" \
  --rate-hz 100 --wheel-radius "${radius}" --steering-ratio "${steering_ratio}" | tee "${out_dir}/vehicle_inputs.log"

echo "[real_car] 3/4 wear replay (config/vehicle_wheels.yaml, 100 Hz)"
"${bin}/tread_wear_replay" "${out_dir}/rav4_inputs.bag" --wheels config/vehicle_wheels.yaml --rate-hz 100 \
  --out-rate-hz 10 --out "${out_dir}/rav4_wear.bag" --summary "${out_dir}/rav4_summary.json" \
  --timeseries "${out_dir}/rav4_timeseries.csv" --timeseries-rate-hz 10 --quiet | tee "${out_dir}/replay.log"

echo "[real_car] 4/4 checks and plots -> ${out_dir}"
/usr/bin/python3 - "${out_dir}" "${vehicle}" "${steering_ratio}" <<'PY'
import json
import math
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import rosbag
import yaml

out_dir, vehicle_path, steering_ratio = sys.argv[1], sys.argv[2], float(sys.argv[3])
veh = yaml.safe_load(open(vehicle_path))
m, g, L, lf = veh["mass_kg"], veh["gravity_mps2"], veh["wheelbase_m"], veh["cog_to_front_axle_m"]
lr, tf, tr, h = L - lf, veh["track_front_m"], veh["track_rear_m"], veh["cog_height_m"]
W = ["front_left", "front_right", "rear_left", "rear_right"]
POS = {"front_left": (lf, tf / 2), "front_right": (lf, -tf / 2), "rear_left": (-lr, tr / 2), "rear_right": (-lr, -tr / 2)}


def read(path, topics):
    data = {t: [] for t in topics}
    with rosbag.Bag(path) as bag:
        for topic, msg, _ in bag.read_messages(topics=topics + ["/" + t for t in topics]):
            data[topic.lstrip("/")].append(msg)
    return data


# --- sensors and reference ---
s = read(os.path.join(out_dir, "rav4_sensors.bag"), ["imu", "joint_states", "odom", "pose_velocity", "tf_static"])
q = s["tf_static"][0].transforms[0].transform.rotation
x_, y_, z_, w_ = q.x, q.y, q.z, q.w
R_m = np.array([[1 - 2 * (y_ * y_ + z_ * z_), 2 * (x_ * y_ - w_ * z_), 2 * (x_ * z_ + w_ * y_)],
                [2 * (x_ * y_ + w_ * z_), 1 - 2 * (x_ * x_ + z_ * z_), 2 * (y_ * z_ - w_ * x_)],
                [2 * (x_ * z_ - w_ * y_), 2 * (y_ * z_ + w_ * x_), 1 - 2 * (x_ * x_ + y_ * y_)]])
t_imu = np.array([k.header.stamp.to_sec() for k in s["imu"]])
gyr = np.array([[k.angular_velocity.x, k.angular_velocity.y, k.angular_velocity.z] for k in s["imu"]]) @ R_m.T
t_js = np.array([k.header.stamp.to_sec() for k in s["joint_states"]])
sw = np.array([k.position[k.name.index("steering_wheel_joint")] for k in s["joint_states"]])
wrad = np.array([[k.velocity[k.name.index("wheel_%s_joint" % n)] for n in W] for k in s["joint_states"]])
t_od = np.array([k.header.stamp.to_sec() for k in s["odom"]])
v_can = np.array([k.twist.twist.linear.x for k in s["odom"]])
t_pv = np.array([k.header.stamp.to_sec() for k in s["pose_velocity"]])
v_pose = np.array([[k.twist.linear.x, k.twist.linear.y] for k in s["pose_velocity"]])
t0 = t_od[0]


def smooth(t, x, width):
    cs = np.concatenate([[0.0], np.cumsum(x)])
    i0, i1 = np.searchsorted(t, t - width / 2), np.searchsorted(t, t + width / 2)
    return (cs[i1] - cs[i0]) / np.maximum(i1 - i0, 1)


v_can_s = smooth(t_od, v_can, 1.0)
a_can = (np.interp(t_od + 0.5, t_od, v_can) - np.interp(t_od - 0.5, t_od, v_can)) / 1.0  # dv/dt over 1 s [m/s^2]
r_s = smooth(t_imu, gyr[:, 2], 0.5)  # body yaw rate [rad/s]

# --- the front end's output ---
topics = ["wheels/%s/%s" % (n, q_) for n in W for q_ in ("load", "slip", "speed")]
o = read(os.path.join(out_dir, "rav4_inputs.bag"), topics)
est = {}
for n in W:
    est[n] = {
        "t_load": np.array([k.header.stamp.to_sec() for k in o["wheels/%s/load" % n]]),
        "load": np.array([k.load_n for k in o["wheels/%s/load" % n]]),
        "t_slip": np.array([k.header.stamp.to_sec() for k in o["wheels/%s/slip" % n]]),
        "alpha": np.array([k.slip_angle_rad for k in o["wheels/%s/slip" % n]]),
        "kappa": np.array([k.slip_ratio for k in o["wheels/%s/slip" % n]]),
        "t_speed": np.array([k.header.stamp.to_sec() for k in o["wheels/%s/speed" % n]]),
        "speed": np.array([k.speed_mps for k in o["wheels/%s/speed" % n]]),
    }
checks = {"vehicle": {"file": vehicle_path, "mass_kg": m, "weight_n": m * g}, "steering_ratio": steering_ratio}

# 1. loads sum to the weight, per sample (stamps common to the four wheels)
common = set(est[W[0]]["t_load"].round(6))
for n in W[1:]:
    common &= set(est[n]["t_load"].round(6))
tl = np.array(sorted(common))
loads = np.array([np.interp(tl, est[n]["t_load"], est[n]["load"]) for n in W]).T
err = (loads.sum(1) - m * g) / (m * g) * 100.0
a_at = np.interp(tl, t_od, a_can)
front_share = loads[:, :2].sum(1) / loads.sum(1)
dfz_meas = loads[:, 2:].sum(1) - loads.sum(1) * lf / L  # rear axle load above its static share [N]
checks["loads"] = {
    "samples": int(len(tl)),
    "sum_error_pct_mean": float(err.mean()), "sum_error_pct_rms": float(np.sqrt((err ** 2).mean())),
    "sum_error_pct_worst": float(err[np.argmax(np.abs(err))]),
    "static_front_share_model": lr / L, "front_share_mean": float(front_share.mean()),
    "front_share_min": float(front_share.min()), "front_share_max": float(front_share.max()),
    "load_transfer_vs_can_accel_slope_n_per_mps2": float(np.polyfit(a_at, dfz_meas, 1)[0]),
    "load_transfer_model_m_h_over_L_n_per_mps2": m * h / L,
    "mean_load_n": {n: float(loads[:, i].mean()) for i, n in enumerate(W)},
}

# 2. slip ratios by phase (CAN dv/dt, 1 s average); raw check: front/rear wheel-speed ratio - 1 (sensor only)
ts_ = est[W[0]]["t_slip"]
kap = np.array([np.interp(ts_, est[n]["t_slip"], est[n]["kappa"]) for n in W]).T
a_s = np.interp(ts_, t_od, a_can)
v_s = np.interp(ts_, t_od, v_can_s)
raw_fr = smooth(t_js, (wrad[:, 0] + wrad[:, 1]) / (wrad[:, 2] + wrad[:, 3]) - 1.0, 1.0)
raw_at = np.interp(ts_, t_js, raw_fr)
phases = {"accelerating (a > 0.5 m/s^2)": a_s > 0.5, "coasting (|a| < 0.25 m/s^2)": np.abs(a_s) < 0.25,
          "decelerating (a < -0.5 m/s^2)": a_s < -0.5}
checks["slip_ratio"] = {}
for name, sel in phases.items():
    if not sel.any():
        continue
    checks["slip_ratio"][name] = {
        "share_of_time": float(sel.mean()), "mean_accel_mps2": float(a_s[sel].mean()),
        "front_mean": float(kap[sel, :2].mean()), "rear_mean": float(kap[sel, 2:].mean()),
        "front_minus_rear_mean": float(kap[sel, :2].mean() - kap[sel, 2:].mean()),
        "raw_front_over_rear_wheel_speed_minus_1": float(raw_at[sel].mean()),
        "per_wheel_mean": {n: float(kap[sel, i].mean()) for i, n in enumerate(W)},
    }
# the tire's longitudinal slip stiffness the sensors imply: accelerating minus coasting, front-rear wheel-speed
# difference against the added drive force per front-axle load, C_kappa/Fz = (m da / Fz_f) / d(slip)
acc_, coa_ = phases["accelerating (a > 0.5 m/s^2)"], phases["coasting (|a| < 0.25 m/s^2)"]
if acc_.any() and coa_.any():
    da = a_s[acc_].mean() - a_s[coa_].mean()
    dslip = raw_at[acc_].mean() - raw_at[coa_].mean()
    checks["slip_ratio"]["implied_slip_stiffness_per_load"] = float((m * da / (m * g * lr / L)) / dslip)
    checks["slip_ratio"]["model_slip_stiffness_per_load"] = veh["longitudinal_slip_stiffness"]
pf = np.polyfit(a_s, kap[:, :2].mean(1) - kap[:, 2:].mean(1), 1)
checks["slip_ratio"]["front_minus_rear_vs_accel_slope_per_mps2"] = float(pf[0])
checks["slip_ratio"]["raw_front_over_rear_vs_accel_slope_per_mps2"] = float(np.polyfit(a_s, raw_at, 1)[0])

# 3. slip angles vs the fused pose: alpha_ref,i = atan2(v_y + r x_i, v_x - r y_i) - delta_i (pose v, gyro r,
#    steering-wheel angle / ratio); body sideslip beta_ref = atan2(v_y, v_x) vs the estimator's, recovered from its
#    rear slip angles (rear wheels unsteered): beta_est = atan(tan(alpha_r) (1 - r y/v) ...) ~ alpha_r,mean + r l_r / v
tp = ts_[(ts_ >= t_pv[0]) & (ts_ <= t_pv[-1])]
vx = np.interp(tp, t_pv, smooth(t_pv, v_pose[:, 0], 0.5))
vy = np.interp(tp, t_pv, smooth(t_pv, v_pose[:, 1], 0.5))
r_p = np.interp(tp, t_imu, r_s)
delta = np.interp(tp, t_js, smooth(t_js, sw, 0.2)) / steering_ratio
checks["slip_angle_deg"] = {}
alpha_ref, alpha_est = {}, {}
for i, n in enumerate(W):
    x_i, y_i = POS[n]
    alpha_ref[n] = np.degrees(np.arctan2(vy + r_p * x_i, vx - r_p * y_i) - (delta if x_i > 0 else 0.0))
    alpha_est[n] = np.degrees(np.interp(tp, est[n]["t_slip"], est[n]["alpha"]))
    d = alpha_est[n] - alpha_ref[n]
    checks["slip_angle_deg"][n] = {
        "est_mean": float(alpha_est[n].mean()), "ref_mean": float(alpha_ref[n].mean()),
        "diff_mean": float(d.mean()), "diff_rms": float(np.sqrt((d ** 2).mean())),
        "diff_rms_mean_removed": float(d.std()), "est_std": float(alpha_est[n].std()),
        "ref_std": float(alpha_ref[n].std()),
        "corr": float(np.corrcoef(alpha_est[n], alpha_ref[n])[0, 1])}
beta_ref = np.degrees(np.arctan2(vy, vx))
alpha_r_est = np.radians((alpha_est["rear_left"] + alpha_est["rear_right"]) / 2)
beta_est = np.degrees(np.arctan(np.tan(alpha_r_est) + r_p * lr / np.maximum(vx, 1.0)))
d = beta_est - beta_ref
checks["sideslip_deg"] = {"ref_mean": float(beta_ref.mean()), "ref_std": float(beta_ref.std()),
                          "ref_min": float(beta_ref.min()), "ref_max": float(beta_ref.max()),
                          "est_mean": float(beta_est.mean()), "est_std": float(beta_est.std()),
                          "diff_mean": float(d.mean()), "diff_rms": float(np.sqrt((d ** 2).mean())),
                          "diff_rms_mean_removed": float(d.std()),
                          "corr": float(np.corrcoef(beta_est, beta_ref)[0, 1])}

# 4. wheel speeds vs CAN speed and the pose's speed
checks["speed"] = {}
for n in W:
    vc = np.interp(est[n]["t_speed"], t_od, v_can)
    checks["speed"][n] = {"minus_can_mean_mps": float((est[n]["speed"] - vc).mean()),
                          "minus_can_rms_mps": float(np.sqrt(((est[n]["speed"] - vc) ** 2).mean()))}

# 5. wear
summ = json.load(open(os.path.join(out_dir, "rav4_summary.json")))
checks["wear"] = {w["name"]: {"mg_per_km": w["mg_per_km"], "mass_loss_mg": w["mass_loss_kg"] * 1e6,
                              "distance_m": w["distance_m"], "slide_fraction_mean": w["slide_fraction_mean"],
                              "samples_rejected": w["samples_rejected"], "unaccounted_time_s": w["unaccounted_time_s"]}
                  for w in summ["wheels"]}
checks["wear"]["mean_mg_per_km"] = summ["mean_mg_per_km"]
# bursts: 0.1 s steps whose wear rate exceeds 3x the wheel's median; their share of the time and of the loss
ts = np.genfromtxt(os.path.join(out_dir, "rav4_timeseries.csv"), delimiter=",", names=True)
rate = np.array([ts["%s_wear_rate_mg_per_s" % n] for n in W]).T
burst = (rate > 3.0 * np.median(rate, 0)).any(1)
dts = np.gradient(ts["time_s"])
checks["wear"]["bursts"] = {
    "time_share": float(burst.mean()),
    "loss_share": {n: float((rate[burst, i] * dts[burst]).sum() / (rate[:, i] * dts).sum()) for i, n in enumerate(W)},
    "times_s": [round(float(x), 1) for x in ts["time_s"][burst] - t0]}
checks["conversion"] = json.load(open(os.path.join(out_dir, "conversion.json")))
with open(os.path.join(out_dir, "real_car_checks.json"), "w") as fh:
    json.dump(checks, fh, indent=2)
    fh.write("\n")

# --- report ---
L_ = checks["loads"]
print("loads: sum vs m g = %.0f N over %d samples: error mean %+.3f %%, RMS %.3f %%, worst %+.3f %%"
      % (m * g, L_["samples"], L_["sum_error_pct_mean"], L_["sum_error_pct_rms"], L_["sum_error_pct_worst"]))
print("       front share mean %.3f (static %.3f), range %.3f..%.3f; rear transfer %.0f N per m/s^2 (m h/L = %.0f)"
      % (L_["front_share_mean"], L_["static_front_share_model"], L_["front_share_min"], L_["front_share_max"],
         L_["load_transfer_vs_can_accel_slope_n_per_mps2"], L_["load_transfer_model_m_h_over_L_n_per_mps2"]))
for name, c in checks["slip_ratio"].items():
    if isinstance(c, dict):
        print("slip ratio, %-30s %4.0f %% of time, a %+.2f: front %+.5f rear %+.5f (front-rear %+.5f; raw wheel "
              "speeds front/rear-1 %+.5f)" % (name, 100 * c["share_of_time"], c["mean_accel_mps2"], c["front_mean"],
                                               c["rear_mean"], c["front_minus_rear_mean"],
                                               c["raw_front_over_rear_wheel_speed_minus_1"]))
if "implied_slip_stiffness_per_load" in checks["slip_ratio"]:
    print("slip stiffness implied by the wheel speeds (accelerating - coasting): C_kappa/Fz = %.1f (vehicle file %.1f)"
          % (checks["slip_ratio"]["implied_slip_stiffness_per_load"], veh["longitudinal_slip_stiffness"]))
for n in W:
    c = checks["slip_angle_deg"][n]
    print("slip angle %-11s est mean %+.3f std %.3f | ref mean %+.3f std %.3f | diff RMS %.3f, mean removed %.3f, "
          "corr %.2f deg" % (n, c["est_mean"], c["est_std"], c["ref_mean"], c["ref_std"], c["diff_rms"],
                             c["diff_rms_mean_removed"], c["corr"]))
c = checks["sideslip_deg"]
print("sideslip beta: est mean %+.3f std %.3f | pose ref mean %+.3f std %.3f | diff mean %+.3f, RMS mean removed "
      "%.3f deg, corr %.2f" % (c["est_mean"], c["est_std"], c["ref_mean"], c["ref_std"], c["diff_mean"],
                               c["diff_rms_mean_removed"], c["corr"]))
for n in W:
    c = checks["wear"][n]
    print("wear %-11s %8.3f mg/km  (%.3f mg over %.0f m, slide %.4f)" % (n, c["mg_per_km"], c["mass_loss_mg"],
                                                                      c["distance_m"], c["slide_fraction_mean"]))

# --- plots ---
def shade(ax):
    for sel, col in ((a_s > 0.5, "tab:green"), (a_s < -0.5, "tab:red")):
        edges = np.flatnonzero(np.diff(np.concatenate([[0], sel.astype(int), [0]])))
        for b, e in zip(edges[::2], edges[1::2]):
            ax.axvspan(ts_[b] - t0, ts_[e - 1] - t0, color=col, alpha=0.12, lw=0)


cols = {"front_left": "tab:blue", "front_right": "tab:orange", "rear_left": "tab:green", "rear_right": "tab:red"}
fig, ax = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
ax[0].plot(t_od - t0, v_can, "k", lw=1.5, label="CAN speed")
ax[0].plot(t_pv - t0, np.hypot(v_pose[:, 0], v_pose[:, 1]), "m--", lw=1, label="fused pose speed")
for n in W:
    ax[0].plot(est[n]["t_speed"] - t0, est[n]["speed"], lw=0.7, color=cols[n], label="estimated %s" % n)
ax[0].set_ylabel("speed [m/s]"); ax[0].legend(fontsize=7, ncol=2); ax[0].grid(alpha=0.3); shade(ax[0])
ax[1].plot(t_od - t0, a_can, "k", lw=1, label="CAN dv/dt (1 s)")
ax[1].set_ylabel("dv/dt [m/s^2]"); ax[1].set_xlabel("t [s]"); ax[1].grid(alpha=0.3); shade(ax[1]); ax[1].legend(fontsize=7)
fig.suptitle("comma2k19 RAV4: speeds (green: accelerating, red: decelerating)")
fig.tight_layout(); fig.savefig(os.path.join(out_dir, "real_car_speed.png"), dpi=110); plt.close(fig)

fig, ax = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
for i, n in enumerate(W):
    ax[0].plot(tl - t0, loads[:, i], lw=0.8, color=cols[n], label=n)
ax[0].axhline(m * g * lr / L / 2, color="gray", ls=":", label="static front"); ax[0].axhline(m * g * lf / L / 2, color="gray", ls="--", label="static rear")
ax[0].set_ylabel("wheel load [N]"); ax[0].legend(fontsize=7, ncol=3); ax[0].grid(alpha=0.3)
ax[1].plot(tl - t0, err, "k", lw=0.8); ax[1].set_ylabel("sum of loads - m g [% of m g]"); ax[1].set_xlabel("t [s]")
ax[1].grid(alpha=0.3)
fig.suptitle("Estimated wheel loads; their sum against the weight (m = %.0f kg)" % m)
fig.tight_layout(); fig.savefig(os.path.join(out_dir, "real_car_loads.png"), dpi=110); plt.close(fig)

fig, ax = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
for i, n in enumerate(W):
    ax[0].plot(ts_ - t0, smooth(ts_, kap[:, i], 0.5), lw=0.8, color=cols[n], label=n + " (0.5 s mean)")
ax[0].set_ylabel("estimated slip ratio [-]"); ax[0].legend(fontsize=7, ncol=2); ax[0].grid(alpha=0.3); shade(ax[0])
ax[1].plot(ts_ - t0, smooth(ts_, kap[:, :2].mean(1) - kap[:, 2:].mean(1), 1.0), lw=1, color="tab:blue",
           label="estimate: front - rear (1 s mean)")
ax[1].plot(ts_ - t0, raw_at, "k", lw=1, label="sensors: front/rear wheel speed - 1 (1 s mean)")
ax[1].set_ylabel("[-]"); ax[1].set_xlabel("t [s]"); ax[1].legend(fontsize=7); ax[1].grid(alpha=0.3); shade(ax[1])
fig.suptitle("Slip ratios (green: accelerating, red: decelerating)")
fig.tight_layout(); fig.savefig(os.path.join(out_dir, "real_car_slip_ratio.png"), dpi=110); plt.close(fig)

fig, ax = plt.subplots(3, 1, figsize=(9, 8), sharex=True)
for k, (n1, n2) in enumerate((("front_left", "front_right"), ("rear_left", "rear_right"))):
    for n in (n1, n2):
        ax[k].plot(tp - t0, alpha_est[n], lw=0.8, color=cols[n], label="estimated " + n)
        ax[k].plot(tp - t0, alpha_ref[n] - alpha_ref[n].mean(), lw=0.8, ls="--", color=cols[n],
                   label="pose reference %s, its mean %+.2f removed" % (n, alpha_ref[n].mean()))
    ax[k].set_ylabel("slip angle [deg]"); ax[k].legend(fontsize=7, ncol=2); ax[k].grid(alpha=0.3)
ax[2].plot(tp - t0, beta_est, "tab:blue", lw=0.8, label="estimated (from the rear slip angles)")
ax[2].plot(tp - t0, beta_ref - beta_ref.mean(), "k", lw=0.8,
           label="fused pose atan2(v_y, v_x), its mean %+.2f removed" % beta_ref.mean())
ax[2].set_ylabel("sideslip [deg]"); ax[2].set_xlabel("t [s]"); ax[2].legend(fontsize=7); ax[2].grid(alpha=0.3)
fig.suptitle("Slip angles and sideslip against the fused pose's lateral velocity\n(reference means removed: "
             "the mount-yaw offset between the accelerometer and the pose's device frame)", fontsize=10)
fig.tight_layout(); fig.savefig(os.path.join(out_dir, "real_car_slip_angle.png"), dpi=110); plt.close(fig)

fig, ax = plt.subplots(1, 2, figsize=(10, 4))
for n in W:
    ax[0].plot(ts["time_s"] - t0, ts["%s_loss_mg" % n], color=cols[n], label=n)
ax[0].set_xlabel("t [s] from the segment's start"); ax[0].set_ylabel("cumulative loss [mg]"); ax[0].legend(fontsize=7); ax[0].grid(alpha=0.3)
ax[1].bar(range(4), [checks["wear"][n]["mg_per_km"] for n in W], color=[cols[n] for n in W])
ax[1].set_xticks(range(4)); ax[1].set_xticklabels([n.replace("_", "\n") for n in W], fontsize=8)
ax[1].set_ylabel("wear over the segment [mg/km]"); ax[1].grid(alpha=0.3, axis="y")
fig.suptitle("Tread wear per wheel, comma2k19 RAV4 segment (tire file: 205/55 R16)")
fig.tight_layout(); fig.savefig(os.path.join(out_dir, "real_car_wear.png"), dpi=110); plt.close(fig)
b_ = checks["wear"]["bursts"]
print("wear bursts (rate > 3x median): %.1f %% of the time, %s of the loss, at t = %s s"
      % (100 * b_["time_share"], ", ".join("%.0f %%" % (100 * b_["loss_share"][n]) for n in W), b_["times_s"]))
print("wrote %s/real_car_checks.json and real_car_{speed,loads,slip_ratio,slip_angle,wear}.png" % out_dir)
PY
