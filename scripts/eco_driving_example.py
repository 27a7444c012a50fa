#!/usr/bin/env python3
"""Eco-driving example (docs/eco_driving.md): what driving costs in tread, as a planner would ask.

1. The WLTC route driven calmly and aggressively (tread_wear_drive --style, tread_wear_replay): wear per wheel.
2. Wear per km against steady cruise speed, and against the driver's acceleration limit on the WLTC route.
3. A planner choosing between candidate speed profiles over one 600 m stretch (start, a 60 m radius bend, stop)
   by their wear cost (tread_wear_trajectory_cost, direct evaluation).
Writes OUT/eco_driving.json and OUT/eco_*.png; prints the tables.

Usage: scripts/eco_driving_example.py [--out DIR] [--bin _build/devel/lib/tread_wear]    (about 3 minutes)
"""
import argparse
import csv
import io
import json
import math
import os

import matplotlib

from road_validation import Scenarios, run

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
VEHICLE = "config/vehicle_passenger_car.yaml"
WHEELS = ["front_left", "front_right", "rear_left", "rear_right"]


def trajectory_costs(args, rows):
    """rows: (trajectory_id, time_s, speed_mps, accel_mps2, curvature_per_m) -> {id: cost row}."""
    text = "trajectory_id,time_s,speed_mps,accel_mps2,curvature_per_m\n" + "".join(
        f"{r[0]},{r[1]:.3f},{r[2]:.6f},{r[3]:.6f},{r[4]:.8f}\n" for r in rows)
    out = run([os.path.join(args.bin, "tread_wear_trajectory_cost"), "--vehicle", VEHICLE, "--wheels",
               "config/vehicle_wheels.yaml", "-"], stdin=text)
    return {r["trajectory_id"]: r for r in csv.DictReader(io.StringIO(out))}


def stretch_profile(accel, cruise_kmh, bend_kmh, decel, length_m=600.0, bend_start_m=250.0, bend_len_m=94.0,
                    radius_m=60.0, dt=0.1):
    """Speed profile over the stretch: accelerate at `accel` to the cruise speed, slow to `bend_kmh` for the bend
    (at `decel`), cruise through it, accelerate back, brake at `decel` to stop at the end. Returns samples."""
    v_c, v_b = cruise_kmh / 3.6, min(bend_kmh, cruise_kmh) / 3.6

    def v_max(s):  # the highest speed allowed at s by the targets
        return v_b if bend_start_m <= s <= bend_start_m + bend_len_m else v_c

    n = int(length_m / 0.5) + 1
    s_grid = [i * 0.5 for i in range(n)]
    v = [v_max(s) for s in s_grid]
    v[0] = v[-1] = 0.0
    for i in range(1, n):  # forward pass: acceleration limit
        v[i] = min(v[i], math.sqrt(v[i - 1] ** 2 + 2 * accel * 0.5))
    for i in range(n - 2, -1, -1):  # backward pass: deceleration limit
        v[i] = min(v[i], math.sqrt(v[i + 1] ** 2 + 2 * decel * 0.5))
    samples, t, s = [], 0.0, 0.0
    while s < length_m - 0.5:
        i = min(int(s / 0.5), n - 2)
        f = (s - s_grid[i]) / 0.5
        speed = v[i] + f * (v[i + 1] - v[i])
        a = (v[i + 1] ** 2 - v[i] ** 2) / (2 * 0.5)
        kappa = 1.0 / radius_m if bend_start_m <= s <= bend_start_m + bend_len_m else 0.0
        samples.append((t, speed, a, kappa))
        s += max(speed, 0.3) * dt
        t += dt
    return samples


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default="out/eco_driving")
    parser.add_argument("--bin", default=os.environ.get("TREAD_WEAR_BIN", "_build/devel/lib/tread_wear"))
    args = parser.parse_args()
    os.makedirs(os.path.join(REPO, args.out), exist_ok=True)
    scenarios = Scenarios(args)

    def drive_and_replay(name, drive_args):
        r = scenarios.drive(name, drive_args)
        return r["wheels_mg_per_km"], r["duration_s"]

    result = {}

    # 1. Calm and aggressive on the same route.
    styles = {s: drive_and_replay(f"style_{s}", ["--style", s]) for s in ("calm", "aggressive")}
    ratio = {w: styles["aggressive"][0][w] / styles["calm"][0][w] for w in WHEELS}
    result["styles"] = {s: {"mg_per_km": styles[s][0], "duration_s": styles[s][1]} for s in styles}
    result["aggressive_over_calm"] = ratio
    print("| wheel | calm mg/km | aggressive mg/km | ratio |\n|---|---|---|---|")
    for w in WHEELS:
        print(f"| {w} | {styles['calm'][0][w]:.2f} | {styles['aggressive'][0][w]:.2f} | {ratio[w]:.2f} |")
    print(f"durations: calm {styles['calm'][1]:.0f} s, aggressive {styles['aggressive'][1]:.0f} s")

    # 2a. Steady cruise speed (planner's direct cost of a 10 s steady trajectory per speed).
    speeds = [30, 50, 70, 90, 110, 130, 150]
    rows = [(f"v{v}", t, v / 3.6, 0.0, 0.0) for v in speeds for t in (0.0, 10.0)]
    cruise = trajectory_costs(args, rows)
    cruise_mg = [float(cruise[f"v{v}"]["wear_per_distance_kg_per_m"]) * 1e9 for v in speeds]
    result["cruise"] = {"speed_kmh": speeds, "vehicle_mg_per_km": cruise_mg}
    # 2b. The driver's acceleration limit on the WLTC route (braking 2.5, cornering 3.0 m/s^2 held).
    limits = [1.0, 1.5, 2.0, 2.5, 3.0]
    by_limit = [sum(drive_and_replay(f"accel_{a}", ["--max-accel-mps2", str(a), "--max-decel-mps2", "2.5",
                                                          "--max-lateral-accel-mps2", "3.0"])[0].values()) / 4
                for a in limits]
    result["accel_limit"] = {"max_accel_mps2": limits, "mean_mg_per_km_per_tire": by_limit}
    print("\ncruise [km/h]: " + ", ".join(f"{v}: {m:.3f}" for v, m in zip(speeds, cruise_mg)) + " mg/km per vehicle")
    print("accel limit [m/s^2]: " + ", ".join(f"{a}: {m:.2f}" for a, m in zip(limits, by_limit)) + " mg/km per tire")

    # 3. Candidate speed profiles over the stretch.
    candidates = {"gentle": (1.0, 50, 30, 1.5), "brisk": (2.5, 50, 35, 3.0), "fast_bend": (2.0, 50, 45, 2.5),
                  "slow_bend": (2.0, 50, 25, 2.5), "cruise_60": (1.5, 60, 35, 2.0), "cruise_40": (1.5, 40, 30, 2.0)}
    rows = []
    for name, c in candidates.items():
        rows += [(name,) + s for s in stretch_profile(*c)]
    costs = trajectory_costs(args, rows)
    table = []
    for name, (accel, cruise_kmh, bend_kmh, decel) in candidates.items():
        r = costs[name]
        table.append({"candidate": name, "accel_mps2": accel, "cruise_kmh": cruise_kmh, "bend_kmh": bend_kmh,
                      "decel_mps2": decel, "duration_s": float(r["duration_s"]),
                      "wear_mg": float(r["total_wear_kg"]) * 1e6,
                      "front_share": (float(r["wear_front_left_kg"]) + float(r["wear_front_right_kg"])) /
                      float(r["total_wear_kg"])})
    budget_s = 60.0
    feasible = [t for t in table if t["duration_s"] <= budget_s]
    choice = min(feasible, key=lambda t: t["wear_mg"])
    result["planner"] = {"candidates": table, "time_budget_s": budget_s, "choice": choice["candidate"]}
    print("\n| candidate | a_x / bend / cruise | time [s] | wear [mg] | front share |\n|---|---|---|---|---|")
    for t in table:
        print(f"| {t['candidate']} | {t['accel_mps2']} m/s^2 / {t['bend_kmh']} / {t['cruise_kmh']} km/h | "
              f"{t['duration_s']:.1f} | {t['wear_mg']:.3f} | {t['front_share']:.2f} |")
    print(f"planner's choice within {budget_s:.0f} s: {choice['candidate']}")

    with open(os.path.join(REPO, args.out, "eco_driving.json"), "w") as f:
        json.dump(result, f, indent=1)
    fig, ax = plt.subplots(1, 3, figsize=(15, 4))
    x = range(len(WHEELS))
    ax[0].bar([i - 0.2 for i in x], [styles["calm"][0][w] for w in WHEELS], 0.4, label="calm")
    ax[0].bar([i + 0.2 for i in x], [styles["aggressive"][0][w] for w in WHEELS], 0.4, label="aggressive")
    ax[0].set_xticks(list(x), WHEELS, rotation=20)
    ax[0].set_ylabel("wear [mg/km]")
    ax[0].set_title("WLTC route, calm vs aggressive")
    ax[0].legend()
    ax[1].semilogy(speeds, cruise_mg, "o-", label="steady cruise (vehicle)")
    ax[1].set_xlabel("speed [km/h]")
    ax[1].set_ylabel("wear [mg/km per vehicle]")
    ax2 = ax[1].twiny()
    ax2.plot(limits, [m * 4 for m in by_limit], "s--", color="C1", label="WLTC route vs accel limit")
    ax2.set_xlabel("acceleration limit [m/s^2] (squares)")
    ax[1].set_title("cruise speed and acceleration limit", pad=28)
    for t in table:
        ax[2].plot(t["duration_s"], t["wear_mg"], "o")
        ax[2].annotate(t["candidate"], (t["duration_s"], t["wear_mg"]))
    ax[2].axvline(budget_s, color="grey", ls=":")
    ax[2].set_xlabel("travel time [s]")
    ax[2].set_ylabel("wear of the stretch [mg, 4 tires]")
    ax[2].set_title(f"planner's candidates (choice: {choice['candidate']})")
    fig.tight_layout()
    fig.savefig(os.path.join(REPO, args.out, "eco_driving.png"), dpi=90)
    print(f"\n[eco] {os.path.join(args.out, 'eco_driving.json')}, {os.path.join(args.out, 'eco_driving.png')}")


if __name__ == "__main__":
    main()
