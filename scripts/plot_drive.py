#!/usr/bin/python3
"""Per-wheel wear table and plots of a replayed drive (tread_wear_replay --summary/--timeseries).

Prints: mg/km, total mg, mean stick and slide fractions per wheel, the share of each wheel's wear by drive
phase (WLTC: Low, Medium, High, Extra High), front/rear axle means. Writes PNGs: speed profile, wear rate per
wheel over time, cumulative loss per wheel. Uses Debian's python3-matplotlib (Agg backend, no display).
"""
import argparse
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def table(summary):
    wheels = summary["wheels"]
    phases = [p["name"] for p in summary.get("phases", [])]
    head = f"{'wheel':<12} {'mg/km':>8} {'total mg':>10} {'stick':>7} {'slide':>7}"
    head += "".join(f" {p[:10]:>10}" for p in phases)
    lines = [head, "-" * len(head)]
    for w in wheels:
        row = (f"{w['name']:<12} {w['mg_per_km']:8.2f} {w['mass_loss_kg'] * 1e6:10.1f} "
               f"{w['stick_fraction_mean']:7.4f} {w['slide_fraction_mean']:7.4f}")
        row += "".join(f" {100 * p['share']:9.1f}%" for p in w.get("phases", []))
        lines.append(row)
    lines.append("-" * len(head))
    mean = summary["mean_mg_per_km"]
    row = f"{'mean/total':<12} {mean:8.2f} {summary['total_mass_loss_kg'] * 1e6:10.1f} {'':>7} {'':>7}"
    row += "".join(f" {100 * p['share']:9.1f}%" for p in summary.get("phases", []))
    lines.append(row)
    axle = {}
    for w in wheels:
        key = "front" if w["name"].startswith("front") else "rear" if w["name"].startswith("rear") else None
        if key:
            axle.setdefault(key, []).append(w["mg_per_km"])
    if axle:
        lines.append("axles: " + ", ".join(f"{k} {sum(v) / len(v):.2f} mg/km" for k, v in axle.items()))
    if phases:
        lines.append("phases (mean per tire): " + ", ".join(
            f"{p['name']} {p['mean_mg_per_km']:.2f} mg/km over {p['distance_m'] / 1000:.2f} km"
            for p in summary["phases"]))
    lines.append(f"complete: {summary['complete']}; replay {summary['duration_s']:.0f} s in "
                 f"{summary['wall_time_s']:.2f} s ({summary['speedup']:.0f}x real time, preset {summary['preset']})")
    return "\n".join(lines)


def read_timeseries(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {key: [float(r[key]) for r in rows] for key in rows[0]} if rows else {}


def shade_phases(ax, summary):
    for i, p in enumerate(summary.get("phases", [])):
        ax.axvspan(p["start_s"], p["end_s"], color="0.92" if i % 2 == 0 else "white", zorder=0)
        ax.text(0.5 * (p["start_s"] + p["end_s"]), 1.0, p["name"], transform=ax.get_xaxis_transform(),
                ha="center", va="bottom", fontsize=8)


def plots(summary, ts, out_dir, prefix):
    names = [w["name"] for w in summary["wheels"]]
    t = ts["time_s"]
    written = []

    fig, ax = plt.subplots(figsize=(10, 3.5))
    shade_phases(ax, summary)
    ax.plot(t, ts["speed_kmh"], color="k", lw=0.8)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("speed [km/h]")
    ax.set_title(f"Speed profile ({summary.get('drive', {}).get('profile', 'drive')})", pad=14)
    written.append(save(fig, out_dir, prefix + "speed.png"))

    fig, ax = plt.subplots(figsize=(10, 4))
    shade_phases(ax, summary)
    for n in names:
        ax.plot(t, [1000.0 * x for x in ts[f"{n}_wear_rate_mg_per_s"]], lw=0.7, label=n)
    ax.set_yscale("symlog", linthresh=1.0)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("wear rate [ug/s] (1 s means)")
    ax.set_title("Tread wear rate per wheel", pad=14)
    ax.legend(ncol=4, fontsize=8)
    written.append(save(fig, out_dir, prefix + "wear_rate.png"))

    fig, ax = plt.subplots(figsize=(10, 4))
    shade_phases(ax, summary)
    for n in names:
        ax.plot(t, ts[f"{n}_loss_mg"], lw=1.2, label=n)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("cumulative tread loss [mg]")
    ax.set_title("Cumulative tread mass loss per wheel", pad=14)
    ax.legend(fontsize=8)
    written.append(save(fig, out_dir, prefix + "cumulative_loss.png"))
    return written


def save(fig, out_dir, name):
    path = os.path.join(out_dir, name)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--summary", required=True, help="summary JSON of tread_wear_replay")
    parser.add_argument("--timeseries", help="time series CSV of tread_wear_replay (plots need it)")
    parser.add_argument("--out-dir", default="out", help="directory of the PNG files")
    parser.add_argument("--prefix", default="", help="prefix of the PNG file names")
    args = parser.parse_args()
    with open(args.summary) as f:
        summary = json.load(f)
    if not summary.get("complete", False):
        print(f"ERROR: the replay is not complete: {summary.get('incomplete_reason', 'unknown reason')}",
              file=sys.stderr)
        return 1
    print(table(summary))
    if args.timeseries:
        os.makedirs(args.out_dir, exist_ok=True)
        for path in plots(summary, read_timeseries(args.timeseries), args.out_dir, args.prefix):
            print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
