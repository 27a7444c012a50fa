#!/usr/bin/python3
"""Grid convergence of the brush wear model for one tire file over a drive's operating envelope (docs/passenger_tire.md).

Evaluates the envelope (loads, slip angles, slip ratios, speeds; straight and a 12 m junction turn) with
tread_wear_eval at the fast and standard presets and at a sequence of marcher grids (--grid NXxNS), and prints
per grid the largest change against the finest grid: W_r relative, Fx and Fy relative to max(|F_ref|, 0.005 Fz)
(the force floor of docs/performance.md), with the worst condition. A grid-convergent model shows errors that
fall steadily with refinement; an ill-posed one (unstable steady sliding) shows W_r growing with refinement.

Usage: scripts/grid_convergence.py --params FILE [--grids 200x16,400x16,...] [--point V,ALPHA_DEG,KAPPA,FZ]...
  (bin dir: TREAD_WEAR_BIN, default _build/devel/lib/tread_wear)
"""
import argparse
import csv
import io
import math
import os
import subprocess
import sys

HEADER = "speed_mps,slip_angle_rad,slip_ratio,path_radius_m,load_n\n"


def envelope():
    """The drive's operating envelope: loads 2-7 kN, |alpha| <= 6 deg, kappa in [-0.2, 0.2], V 0.5-40 m/s."""
    rows = []
    for fz in (2000.0, 4500.0, 7000.0):
        for alpha_deg in (0.0, 2.0, 6.0):
            for kappa in (-0.2, -0.05, 0.0, 0.05, 0.2):
                for v in (0.5, 2.0, 10.0, 40.0):
                    rows.append((v, math.radians(alpha_deg), kappa, 0.0, fz))
    # Junction turns (R = 12 m) at urban speeds, with the rear and front slip angles of the drive.
    for fz in (2000.0, 7000.0):
        for alpha_deg in (-6.0, -2.0):
            for kappa in (-0.05, 0.05):
                for v in (0.5, 2.0, 6.0):
                    rows.append((v, math.radians(alpha_deg), kappa, 12.0, fz))
    return rows


def evaluate(binary, params, rows, grid=None, preset=None):
    text = HEADER + "".join(f"{v!r},{a!r},{k!r},{r!r},{fz!r}\n" for v, a, k, r, fz in rows)
    args = [binary, "--params", params]
    args += ["--grid", grid] if grid else ["--preset", preset]
    out = subprocess.run(args + ["-"], input=text, capture_output=True, text=True, check=True).stdout
    return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(io.StringIO(out))]


def errors(results, reference):
    worst = {"W_r": (0.0, None), "Fx": (0.0, None), "Fy": (0.0, None)}
    for r, ref in zip(results, reference):
        floor = 0.005 * ref["load_n"]
        cand = {
            "W_r": abs(r["wear_rate_kg_per_m"] / ref["wear_rate_kg_per_m"] - 1.0),
            "Fx": abs(r["fx_n"] - ref["fx_n"]) / max(abs(ref["fx_n"]), floor),
            "Fy": abs(r["fy_n"] - ref["fy_n"]) / max(abs(ref["fy_n"]), floor),
        }
        for key, value in cand.items():
            if value > worst[key][0]:
                worst[key] = (value, ref)
    return worst


def describe(ref):
    if ref is None:
        return "-"
    turn = f", R {ref['path_radius_m']:g} m" if ref["path_radius_m"] else ""
    return (f"Fz {ref['load_n'] / 1000:g} kN, alpha {math.degrees(ref['slip_angle_rad']):g} deg, "
            f"kappa {ref['slip_ratio']:g}, V {ref['speed_mps']:g} m/s{turn}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--params", required=True)
    parser.add_argument("--grids", default="200x16,400x16,800x16,1600x16,3200x16")
    parser.add_argument("--point", action="append", default=[],
                        help="extra W_r-per-grid line for V,ALPHA_DEG,KAPPA,FZ (e.g. 0.5,0,-0.2,6000)")
    args = parser.parse_args()
    binary = os.path.join(os.environ.get("TREAD_WEAR_BIN", "_build/devel/lib/tread_wear"), "tread_wear_eval")
    rows = envelope()
    grids = args.grids.split(",")
    runs = [(p, evaluate(binary, args.params, rows, preset=p)) for p in ("fast", "standard")]
    runs += [(g, evaluate(binary, args.params, rows, grid=g)) for g in grids]
    reference = runs[-1][1]
    print(f"{args.params}: {len(rows)} conditions, reference grid {grids[-1]}")
    print("| grid | W_r | worst W_r condition | Fx | Fy |")
    print("|---|---:|---|---:|---:|")
    for name, results in runs[:-1]:
        e = errors(results, reference)
        print(f"| {name} | {100 * e['W_r'][0]:.2f}% | {describe(e['W_r'][1])} | "
              f"{100 * e['Fx'][0]:.2f}% | {100 * e['Fy'][0]:.2f}% |")
    for point in args.point:
        v, alpha_deg, kappa, fz = (float(x) for x in point.split(","))
        row = [(v, math.radians(alpha_deg), kappa, 0.0, fz)]
        values = [evaluate(binary, args.params, row, preset=p)[0]["wear_rate_kg_per_m"] for p in ("fast", "standard")]
        values += [evaluate(binary, args.params, row, grid=g)[0]["wear_rate_kg_per_m"] for g in grids]
        print(f"W_r [kg/m] at V {v:g} m/s, alpha {alpha_deg:g} deg, kappa {kappa:g}, Fz {fz:g} N: " +
              ", ".join(f"{n} {w:.4g}" for n, w in zip(["fast", "standard"] + grids, values)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
