#!/usr/bin/python3
"""Plots of a mismatch diagnosis (docs/diagnosis.md): residuals before and after the selected extension against the
covariate that located the mismatch, per output, and measured against predicted.

usage: plot_diagnosis.py REPORT_DIR   (reads REPORT_DIR/diagnosis.json and REPORT_DIR/residuals.csv)
"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

LEVEL_COLUMNS = {"predicted_side_force": "predicted_side_force_n_before",
                 "predicted_wear": "predicted_wear_kg_per_m_before"}
UNITS = {"side_force": ("side force", "N", 1.0), "wear": ("wear rate", "g/km", 1e6)}


def number(text):
    try:
        return float(text)
    except ValueError:
        return None


def main(report_dir):
    with open(os.path.join(report_dir, "diagnosis.json")) as f:
        verdict = json.load(f)
    with open(os.path.join(report_dir, "residuals.csv")) as f:
        rows = list(csv.DictReader(f))
    after_label = verdict["explanation"] if verdict["explanation"] not in ("none", "unexplained") else "base"
    for output, covariate in verdict.get("plot_covariates", {}).items():
        column = LEVEL_COLUMNS.get(covariate, covariate)
        fig, ax = plt.subplots(figsize=(6.4, 4.2))
        phases = [("before", "o", "base model"), ("after", "x", after_label)]
        for term in verdict.get("empirical_terms", []):  # an empirical term of this output (not physics)
            if term["output"] == output and rows and "residual_%s_empirical" % output in rows[0]:
                phases.append(("empirical", "+", "empirical (not physics): %s" % term["form"]))
        for phase, marker, label in phases:
            xs, ys, cats = [], [], []
            for r in rows:
                y = number(r["residual_%s_%s" % (output, phase)])
                if y is None:
                    continue
                x = number(r[column])
                if x is None:
                    cats.append(r[column])
                    x = None
                xs.append(x if x is not None else r[column])
                ys.append(100.0 * y)
            if xs and all(isinstance(x, float) for x in xs):
                ax.plot(xs, ys, marker, linestyle="none", label=label, alpha=0.8)
            else:
                levels = sorted(set(str(x) for x in xs))
                ax.plot([levels.index(str(x)) for x in xs], ys, marker, linestyle="none", label=label, alpha=0.8)
                ax.set_xticks(range(len(levels)))
                ax.set_xticklabels(levels, rotation=30, ha="right", fontsize=8)
        ax.axhline(0.0, color="0.5", linewidth=0.8)
        ax.set_xlabel(covariate)
        ax.set_ylabel("%s error ratio predicted/measured - 1 [%%]" % UNITS[output][0])
        ax.set_title("%s residuals against %s" % (UNITS[output][0], covariate))
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(report_dir, "residuals_%s.png" % output), dpi=110)
        plt.close(fig)

    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    for ax, output, meas_col, before_col, after_col in (
            (axes[0], "side_force", "measured_side_force_n", "predicted_side_force_n_before",
             "predicted_side_force_n_after"),
            (axes[1], "wear", "measured_wear_kg_per_m", "predicted_wear_kg_per_m_before",
             "predicted_wear_kg_per_m_after")):
        name, unit, scale = UNITS[output]
        pts = [(number(r[meas_col]), number(r[before_col]), number(r[after_col])) for r in rows]
        pts = [p for p in pts if p[0] is not None]
        if not pts:
            ax.set_visible(False)
            continue
        m = [scale * p[0] for p in pts]
        ax.plot(m, [scale * p[1] for p in pts], "o", label="base model", alpha=0.8)
        ax.plot(m, [scale * p[2] for p in pts], "x", label=after_label, alpha=0.8)
        lo, hi = min(m), max(m)
        ax.plot([lo, hi], [lo, hi], color="0.5", linewidth=0.8)
        ax.set_xlabel("measured %s [%s]" % (name, unit))
        ax.set_ylabel("predicted %s [%s]" % (name, unit))
        ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(report_dir, "measured_vs_predicted.png"), dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
