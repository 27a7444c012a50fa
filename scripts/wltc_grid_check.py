#!/usr/bin/python3
"""Grid convergence of a drive's wear figure: the drive bag's inputs, subsampled, evaluated on finer grids.

Reads every STRIDE-th input sample of each wheel of a drive bag (tread_wear_drive), evaluates the operating points
with tread_wear_eval at the fast and standard presets and at marcher grids (--grid NXxNS), and prints per grid the
mg/km per wheel and their mean: sum(W_r V) / sum(V) over the samples (equal time steps). The replay integrates
the same model in time; this check only compares grids on identical points (docs/passenger_tire.md, "Grid convergence").

Usage: scripts/wltc_grid_check.py DRIVE.bag [--params TIRE.yaml] [--stride 50] [--grids 400x16,1600x32,6400x32]
  (bin dir: TREAD_WEAR_BIN, default _build/devel/lib/tread_wear; needs python3-rosbag and the built messages)
"""
import argparse
import csv
import io
import os
import subprocess
import sys

import rosbag

WHEELS = ("front_left", "front_right", "rear_left", "rear_right")
HEADER = "speed_mps,slip_angle_rad,slip_ratio,path_radius_m,load_n\n"


def operating_points(bag_path, stride):
    """Per wheel the CSV rows of every stride-th speed sample, with the latest load and slip before it."""
    latest, count, rows = {}, {w: 0 for w in WHEELS}, {w: [] for w in WHEELS}
    with rosbag.Bag(bag_path) as bag:
        for topic, msg, _ in bag.read_messages(topics=[f"/wheels/{w}/{k}" for w in WHEELS
                                                        for k in ("load", "slip", "speed")]):
            _, _, wheel, kind = topic.split("/")
            latest[(wheel, kind)] = msg
            if kind != "speed" or (wheel, "load") not in latest or (wheel, "slip") not in latest:
                continue
            count[wheel] += 1
            if (count[wheel] - 1) % stride:
                continue
            slip, load = latest[(wheel, "slip")], latest[(wheel, "load")]
            radius = 0.0 if slip.path_curvature_per_m == 0.0 else 1.0 / slip.path_curvature_per_m
            rows[wheel].append(f"{msg.speed_mps!r},{slip.slip_angle_rad!r},{slip.slip_ratio!r},{radius!r},"
                               f"{load.load_n!r}\n")
    return rows


def mg_per_km(binary, params, rows, option):
    out = subprocess.run([binary, "--params", params] + option + ["-"], input=HEADER + "".join(rows),
                         capture_output=True, text=True, check=True).stdout
    wear = speed = 0.0
    for r in csv.DictReader(io.StringIO(out)):
        wear += float(r["wear_rate_kg_per_s"])
        speed += float(r["speed_mps"])
    return wear / speed * 1e9  # kg/m -> mg/km


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("bag")
    parser.add_argument("--params", default="config/tires/passenger_205_55_r16.yaml")
    parser.add_argument("--stride", type=int, default=50, help="every N-th input sample (50 = 1 Hz of a 50 Hz bag)")
    parser.add_argument("--grids", default="200x16,400x16,800x32,1600x32,3200x32,6400x32")
    args = parser.parse_args()
    binary = os.path.join(os.environ.get("TREAD_WEAR_BIN", "_build/devel/lib/tread_wear"), "tread_wear_eval")
    rows = operating_points(args.bag, args.stride)
    print(f"{args.bag}: {sum(len(r) for r in rows.values())} operating points, tire {args.params}")
    print("| grid | " + " | ".join(WHEELS) + " | mean mg/km |")
    print("|---|" + "---|" * (len(WHEELS) + 1))
    options = [("fast", ["--preset", "fast"]), ("standard", ["--preset", "standard"])]
    options += [(g, ["--grid", g]) for g in args.grids.split(",")]
    for name, option in options:
        values = [mg_per_km(binary, args.params, rows[w], option) for w in WHEELS]
        print(f"| {name} | " + " | ".join(f"{v:.3f}" for v in values) + f" | {sum(values) / len(values):.3f} |",
              flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
