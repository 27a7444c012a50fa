#!/usr/bin/python3
"""Plots the Section 4.3 wear characteristics (Figs 13, 15, 17 of the paper) from the CSV files written by
tread_wear_wear_characteristics. Debian's matplotlib (python3-matplotlib), no other dependency.

usage: scripts/plot_wear_characteristics.py [DIR]   (default docs/figures; PNGs are written next to the CSVs)
"""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        return [{k: (float(v) if v not in ("", "nan") else float("nan")) for k, v in row.items()}
                for row in csv.DictReader(f)]


def rising_branch(points):
    """Points up to the grip peak (the paper's Figs 15/17 stay below it)."""
    out = []
    for p in points:
        if out and p["side_force_n"] < out[-1]["side_force_n"]:
            break
        out.append(p)
    return out


def sweep_plot(ax, rows, key, label_fmt, rising_only=False):
    groups = defaultdict(list)
    for r in rows:
        groups[r[key]].append(r)
    for value, pts in sorted(groups.items()):
        pts = rising_branch(pts) if rising_only else pts
        ax.plot([p["side_force_n"] for p in pts], [p["wear_rate_g_per_km"] for p in pts], label=label_fmt % value)
    ax.set_xlabel("side force Fy [N]")
    ax.set_ylabel("global wear rate W_r [g/km]")
    ax.set_yscale("log")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()


def at_side_force_plot(ax, d, variable, key):
    """W_r over `key` at each required side force (wc_wear_at_side_force.csv rows of one swept variable)."""
    groups = defaultdict(list)
    for r in [r for r in read_text(d + "/wc_wear_at_side_force.csv") if r["variable"] == variable]:
        groups[float(r["side_force_n"])].append((float(r[key]), float(r["wear_rate_g_per_km"])))
    for fy, pts in sorted(groups.items()):
        ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", label="Fy = %g N" % fy)


def finish_at_side_force_plot(ax, xlabel, title):
    ax.set_xlabel(xlabel)
    ax.set_ylabel("global wear rate W_r [g/km]")
    ax.set_yscale("log")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(title)


def main():
    d = sys.argv[1] if len(sys.argv) > 1 else "docs/figures"
    load_sweep = read(d + "/wc_load_sweep.csv")
    speed_sweep = read(d + "/wc_speed_sweep.csv")
    optimal_load = read(d + "/wc_optimal_load.csv")
    vm = read(d + "/wc_vm_condition.csv")

    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.5))
    sweep_plot(a, load_sweep, "load_n", "Fz = %g N")
    a.set_title("Fig 13a: W_r over side force, v0 = 2 m/s, R_t = 60 mm")
    at_side_force_plot(b, d, "load", "load_n")
    b.plot([r["optimal_load_n"] for r in optimal_load], [r["wear_rate_g_per_km"] for r in optimal_load], "k--",
           marker="x", label="optimal load (interpolated)")
    finish_at_side_force_plot(b, "vertical load Fz [N]", "Fig 13b: W_r over load at a required side force")
    fig.tight_layout()
    fig.savefig(d + "/wc_fig13_load.png", dpi=120)

    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.5))
    sweep_plot(a, speed_sweep, "speed_mps", "v0 = %g m/s", rising_only=True)
    a.set_title("Fig 15a: W_r over side force, Fz = 75 N")
    at_side_force_plot(b, d, "speed", "speed_mps")
    finish_at_side_force_plot(b, "speed v0 [m/s]", "Fig 15b: W_r over speed at a required side force")
    fig.tight_layout()
    fig.savefig(d + "/wc_fig15_speed.png", dpi=120)

    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    sweep_plot(ax, speed_sweep, "speed_mps", "v0 = %g m/s", rising_only=True)
    ax.plot([r["side_force_n"] for r in vm], [r["wear_rate_g_per_km"] for r in vm], "--", color="purple",
            marker="s", label="v0 sin(alpha) = v_m")
    ax.legend(fontsize=7)
    ax.set_title("Fig 17: W_r over side force and speed, Fz = 75 N")
    fig.tight_layout()
    fig.savefig(d + "/wc_fig17_vm.png", dpi=120)


def read_text(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


if __name__ == "__main__":
    main()
