#!/usr/bin/python3
"""Measured road wear per wheel (LEON-T, IDIADA, Ford Kuga) against this package's model and a friction-work peer.

Usage: scripts/leon_t_validation.py [--measurements CSV] [--out DIR] [--laps N] [--jobs N] [--no-plots]
                                    [--fit-adhesion] [--tire YAML] [--vehicle YAML] [--wheels YAML]
                                    [--corner-lateral-accel-mps2 A] [--steer-transition-s T] [--mirror]

Every test section of the programme (data/leon_t_idiada) is built as a drive (tread_wear_drive --programme), written
as a bag and replayed through the node's estimator (tread_wear_replay), at each scenario's vehicle mass, with the
tire file as it is and with its adhesion term off. Per test, a wheel's prediction is its wear over the test's
sections per km. Calibration (the only fitted numbers): one abrasivity factor per tyre brand, the ratio of the
brand's measured Standard Run-in vehicle total to the model's; High load and High temperature take LingLong
Standard's factor, so they predict the change of load and temperature. The friction-work peer (the data authors'
kind of model: sum of force x slip velocity per km and wheel, one coefficient per tyre) is calibrated the same way.

Writes DIR/predictions.csv (tyre_brand, scenario, test, wheel, measured_mean_mg_per_km, measured_sd_mg_per_km,
n_repeats, predicted_mg_per_km), DIR/comparison.csv (the same rows with the paper's model, the model with the
adhesion term and the friction-work peer), DIR/summary.md (the tables of docs/measured_road_wear.md) and, unless
--no-plots, DIR/leon_t_<test>.png. The measurements CSV may hold repeats (columns tyre_brand, scenario, wheel, test,
repeat, abrasion_mg_per_km, as data/leon_t_idiada/abrasion_per_wheel.csv) or means (the first eight columns of
predictions.csv); brands it has not seen need only their Standard Run-in.
--fit-adhesion fits the tire file's adhesion coefficient (one number for all brands) on the Standard brands of the
measurements, prints it with its leave-one-brand-out errors, and changes nothing.
"""
import argparse
import concurrent.futures
import csv
import json
import math
import os
import re
import subprocess
import sys
import tempfile
from collections import defaultdict

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.environ.get("TREAD_WEAR_BIN", os.path.join(REPO, "_build", "devel", "lib", "tread_wear"))
WHEELS = ["FL", "FR", "RL", "RR"]
WHEEL_NAMES = {"FL": "front_left", "FR": "front_right", "RL": "rear_left", "RR": "rear_right"}
TESTS = ["Run-in", "Rural", "Motorway", "Urban"]
CALIBRATION_TEST = "Run-in"
REFERENCE_SCENARIO = "Standard"
REFERENCE_BRAND = "LingLong"  # the factor the other scenarios take (the rule)


def fail(message):
    sys.exit("leon_t_validation: " + message)


def read_measurements(path):
    """{(brand, scenario, test, wheel): (mean, sd, n)} from repeats or from means."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        fail(path + ": no rows")
    columns = set(rows[0])
    out = {}
    if {"tyre_brand", "scenario", "wheel", "test", "abrasion_mg_per_km"} <= columns:
        values = defaultdict(list)
        for i, r in enumerate(rows, start=2):
            try:
                v = float(r["abrasion_mg_per_km"])
            except ValueError:
                fail("%s:%d: abrasion_mg_per_km '%s' is not a number" % (path, i, r["abrasion_mg_per_km"]))
            if not math.isfinite(v) or v < 0:
                fail("%s:%d: abrasion_mg_per_km %s must be finite and >= 0" % (path, i, v))
            values[(r["tyre_brand"], r["scenario"], r["test"], r["wheel"])].append(v)
        for key, v in values.items():
            mean = sum(v) / len(v)
            sd = math.sqrt(sum((x - mean) ** 2 for x in v) / (len(v) - 1)) if len(v) > 1 else 0.0
            out[key] = (mean, sd, len(v))
    elif {"tyre_brand", "scenario", "test", "wheel", "measured_mean_mg_per_km", "measured_sd_mg_per_km",
          "n_repeats"} <= columns:
        for i, r in enumerate(rows, start=2):
            try:
                out[(r["tyre_brand"], r["scenario"], r["test"], r["wheel"])] = (
                    float(r["measured_mean_mg_per_km"]), float(r["measured_sd_mg_per_km"]), int(r["n_repeats"]))
            except ValueError as e:
                fail("%s:%d: %s" % (path, i, e))
    else:
        fail(path + ": needs the columns of abrasion_per_wheel.csv or of predictions.csv")
    for key in out:
        if key[3] not in WHEELS:
            fail("%s: wheel '%s' is not one of %s" % (path, key[3], WHEELS))
        if key[2] not in TESTS:
            fail("%s: test '%s' is not one of %s" % (path, key[2], TESTS))
    return out


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def scenario_masses(programme):
    return {r["Scenario"]: float(r["Mass (kg)"]) for r in read_csv(os.path.join(programme, "vehicle.csv"))
            if r["Vehicle brand"] == "Ford"}


def adhesion_off(tire_path, tmp):
    """A copy of the tire file with the adhesion term off (the paper's model)."""
    text = open(tire_path).read()
    off, n = re.subn(r"(\n\s*adhesion_mg_per_kJ:\s*)[-+0-9.eE]+", r"\g<1>0", text)
    path = os.path.join(tmp, "tire_adhesion_off.yaml")
    with open(path, "w") as f:
        f.write(off if n else text)
    return path


def wheels_config(wheels_path, tire_path, tmp, name):
    """The wheel configuration with every wheel on tire_path (absolute)."""
    text = re.sub(r"tire_params:\s*[^,}\s]+", "tire_params: " + tire_path, open(wheels_path).read())
    path = os.path.join(tmp, name)
    with open(path, "w") as f:
        f.write(text)
    return path


def run(cmd):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        fail("%s failed (%d):\n%s%s" % (" ".join(cmd), p.returncode, p.stdout, p.stderr))
    return p.stdout


def simulate(job):
    """One section at one mass: drive bag, two replays. Per wheel: mg/km (file, off), friction work J/m."""
    args, section, mass, laps, configs, tmp = job
    bag = os.path.join(tmp, "%s_%d.bag" % (section, round(mass)))
    run([os.path.join(BIN, "tread_wear_drive"), "--programme", args.programme, "--section", section, "--laps",
         str(laps), "--vehicle", args.vehicle, "--mass-kg", repr(mass), "--rate-hz", repr(args.rate_hz), "--out", bag,
         "--corner-lateral-accel-mps2", repr(args.corner_lateral_accel_mps2), "--steer-transition-s",
         repr(args.steer_transition_s)] + (["--mirror"] if args.mirror else [])
        + (["--slow-for-corners"] if args.slow_for_corners else []))
    result = {}
    for variant, config in configs.items():
        summary = bag[:-4] + "_" + variant + ".json"
        run([os.path.join(BIN, "tread_wear_replay"), bag, "--wheels", config, "--rate-hz", repr(args.rate_hz),
             "--summary", summary, "--threads", "1"])
        with open(summary) as f:
            s = json.load(f)
        if not s.get("complete", False):
            fail("%s: replay incomplete: %s" % (summary, s.get("incomplete_reason", "")))
        for w in s["wheels"]:
            entry = result.setdefault(w["name"], {})
            entry[variant] = w["mg_per_km"]
            entry["friction_j_per_m"] = w["friction_work_j"] / w["distance_m"]
    os.remove(bag)
    return (section, mass), result


def per_test(programme, sims, mass):
    """{test: {wheel: {variant: per km}}}: sections weighted by their full programme distance (laps x lap)."""
    sectors = defaultdict(float)
    for r in read_csv(os.path.join(programme, "sectors.csv")):
        sectors[r["Track"]] += float(r["Distance (m)"])
    out = {}
    for test in TESTS:
        sections = [r for r in read_csv(os.path.join(programme, "test_sections.csv")) if r["AbrasionTest"] == test]
        weights = {r["Test section"]: int(r["Number of laps"]) * sectors[r["Track"]] for r in sections}
        total = sum(weights.values())
        out[test] = {}
        for wheel in WHEELS:
            name = WHEEL_NAMES[wheel]
            out[test][wheel] = {v: sum(weights[s] * sims[(s, mass)][name][v] for s in weights) / total
                                for v in ("model", "paper", "friction_j_per_m")}
    return out


def geo_error(pairs):
    """Geometric mean of max(p/m, m/p) over (predicted, measured) pairs."""
    logs = [abs(math.log(p / m)) for p, m in pairs if p > 0 and m > 0]
    return math.exp(sum(logs) / len(logs)) if logs else float("nan")


def predictions(measured, tests_by_scenario, variant, adhesion_scale=1.0):
    """{key: predicted} for every measured key, calibrated per brand on its Standard Run-in vehicle total."""
    def unit(scenario, test, wheel):
        t = tests_by_scenario[scenario][test][wheel]
        if variant == "friction":
            return t["friction_j_per_m"]
        if variant == "paper":
            return t["paper"]
        return t["paper"] + adhesion_scale * (t["model"] - t["paper"])

    factors = {}
    for brand in {k[0] for k in measured}:
        keys = [(brand, REFERENCE_SCENARIO, CALIBRATION_TEST, w) for w in WHEELS]
        if all(k in measured for k in keys):
            factors[brand] = sum(measured[k][0] for k in keys) / sum(
                unit(REFERENCE_SCENARIO, CALIBRATION_TEST, w) for w in WHEELS)
    out = {}
    for key in measured:
        brand, scenario = key[0], key[1]
        factor = factors.get(brand) if scenario == REFERENCE_SCENARIO else factors.get(REFERENCE_BRAND)
        if factor is None:
            continue
        out[key] = factor * unit(scenario, key[2], key[3])
    return out, factors


def figures(measured, predicted, scenario=REFERENCE_SCENARIO):
    """Per brand of the scenario: vehicle-total ratio and front/rear ratio per test, per-wheel geometric error."""
    rows = []
    for brand in sorted({k[0] for k in measured if k[1] == scenario}):
        row = {"brand": brand}
        pairs_all, pairs_blind = [], []
        for test in TESTS:
            keys = [(brand, scenario, test, w) for w in WHEELS]
            if not all(k in measured and k in predicted for k in keys):
                continue
            m = [measured[k][0] for k in keys]
            p = [predicted[k] for k in keys]
            row[test + "_total"] = sum(p) / sum(m)
            row[test + "_front_rear"] = ((p[0] + p[1]) / (p[2] + p[3])) / ((m[0] + m[1]) / (m[2] + m[3]))
            pairs_all += list(zip(p, m))
            if test != CALIBRATION_TEST:
                pairs_blind += list(zip(p, m))
        row["geo_all"] = geo_error(pairs_all)
        row["geo_blind"] = geo_error(pairs_blind)
        rows.append(row)
    return rows


def fit_adhesion(measured, tests_by_scenario):
    """The adhesion scale minimising the squared log error over the Standard brands' blind tests (golden section)."""
    def cost(scale, brands):
        sub = {k: v for k, v in measured.items() if k[0] in brands and k[1] == REFERENCE_SCENARIO}
        pred, _ = predictions(sub, tests_by_scenario, "model", scale)
        return sum(math.log(pred[k] / sub[k][0]) ** 2 for k in pred if k[2] != CALIBRATION_TEST and sub[k][0] > 0)

    def argmin(brands):
        lo, hi = math.log(1e-3), math.log(1e3)
        g = (math.sqrt(5) - 1) / 2
        for _ in range(80):
            a, b = hi - g * (hi - lo), lo + g * (hi - lo)
            if cost(math.exp(a), brands) < cost(math.exp(b), brands):
                hi = b
            else:
                lo = a
        return math.exp(0.5 * (lo + hi))

    brands = sorted({k[0] for k in measured if k[1] == REFERENCE_SCENARIO})
    best = argmin(brands)
    print("adhesion scale fitted on %s: %.4g x the tire file's coefficient" % (", ".join(brands), best))
    for held in brands:
        scale = argmin([b for b in brands if b != held])
        pred, _ = predictions(measured, tests_by_scenario, "model", scale)
        row = figures({k: v for k, v in measured.items() if k[0] == held}, pred)[0]
        print("  leave %s out: scale %.4g, its blind per-wheel error x%.2f" % (held, scale, row["geo_blind"]))
    return best


def fmt(x):
    return "-" if x is None or (isinstance(x, float) and math.isnan(x)) else "%.2f" % x


def summary_tables(measured, variants):
    lines = []
    for scenario in sorted({k[1] for k in measured}):
        lines.append("### %s\n" % scenario)
        lines.append("| brand | model | " + " | ".join("%s total" % t for t in TESTS) + " | " +
                     " | ".join("%s F/R" % t for t in TESTS) + " | per-wheel error (blind tests) | (all tests) |")
        lines.append("|---" * (2 + 2 * len(TESTS) + 2) + "|")
        for name, pred in variants.items():
            for row in figures(measured, pred, scenario):
                lines.append("| %s | %s | " % (row["brand"], name) +
                             " | ".join(fmt(row.get(t + "_total")) for t in TESTS) + " | " +
                             " | ".join(fmt(row.get(t + "_front_rear")) for t in TESTS) +
                             " | x%s | x%s |" % (fmt(row["geo_blind"]), fmt(row["geo_all"])))
        lines.append("")
    return "\n".join(lines)


def plot(measured, predicted, out_dir):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    markers = {"FL": "o", "FR": "s", "RL": "^", "RR": "v"}
    for test in TESTS:
        keys = sorted(k for k in measured if k[2] == test and k in predicted)
        if not keys:
            continue
        fig, ax = plt.subplots(figsize=(6, 5))
        brands = sorted({(k[0], k[1]) for k in keys})
        colours = {b: "C%d" % i for i, b in enumerate(brands)}
        for k in keys:
            m, sd, _ = measured[k]
            ax.errorbar(m, predicted[k], xerr=sd, fmt=markers[k[3]], color=colours[(k[0], k[1])], capsize=2)
        for b in brands:
            ax.plot([], [], "o", color=colours[b], label="%s %s" % b)
        for w, mk in markers.items():
            ax.plot([], [], mk, color="grey", label=w)
        top = max(max(measured[k][0] + measured[k][1] for k in keys), max(predicted[k] for k in keys)) * 1.1
        ax.plot([0, top], [0, top], "k-", lw=0.8)
        ax.plot([0, top], [0, top * 1.5], "k:", lw=0.6)
        ax.plot([0, top], [0, top / 1.5], "k:", lw=0.6)
        ax.set_xlim(0, top)
        ax.set_ylim(0, top)
        ax.set_xlabel("measured [mg/km per tyre] (bars: repeat SD)")
        ax.set_ylabel("predicted [mg/km per tyre]")
        ax.set_title("LEON-T %s: per wheel (dotted: x1.5)" % test)
        ax.legend(fontsize=7, loc="upper left")
        fig.tight_layout()
        fig.savefig(os.path.join(out_dir, "leon_t_%s.png" % test.replace("-", "_").lower()), dpi=110)
        plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--measurements", default=os.path.join(REPO, "data", "leon_t_idiada", "abrasion_per_wheel.csv"))
    ap.add_argument("--out", default=os.path.join(REPO, "out", "leon_t"))
    ap.add_argument("--programme", default=os.path.join(REPO, "data", "leon_t_idiada"))
    ap.add_argument("--vehicle", default=os.path.join(REPO, "config", "vehicle_ford_kuga.yaml"))
    ap.add_argument("--wheels", default=os.path.join(REPO, "config", "vehicle_wheels_kuga.yaml"))
    ap.add_argument("--tire", default=os.path.join(REPO, "config", "tires", "suv_225_60_r18.yaml"))
    ap.add_argument("--laps", type=int, default=3, help="laps per section (they are alike; default 3)")
    ap.add_argument("--rate-hz", type=float, default=50.0)
    ap.add_argument("--slow-for-corners", action="store_true",
                    help="keep the corners' radii and slow to the corner bound (tread_wear_drive --slow-for-corners)")
    ap.add_argument("--corner-lateral-accel-mps2", type=float, default=4.0,
                    help="the driver's bound in corners (tread_wear_drive; default 4)")
    ap.add_argument("--steer-transition-s", type=float, default=1.0, help="clothoids into corners (default 1 s)")
    ap.add_argument("--mirror", action="store_true", help="drive every corner the other way")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--no-plots", action="store_true")
    ap.add_argument("--fit-adhesion", action="store_true")
    args = ap.parse_args()
    if args.laps < 1 or args.jobs < 1 or not args.rate_hz > 0:
        fail("--laps and --jobs must be >= 1, --rate-hz > 0")
    for tool in ("tread_wear_drive", "tread_wear_replay"):
        if not os.access(os.path.join(BIN, tool), os.X_OK):
            fail("%s/%s is not built (bash scripts/setup.sh)" % (BIN, tool))
    measured = read_measurements(args.measurements)
    masses = scenario_masses(args.programme)
    scenarios = sorted({k[1] for k in measured})
    for s in scenarios:
        if s not in masses:
            fail("scenario '%s' has no mass in %s/vehicle.csv" % (s, args.programme))
    os.makedirs(args.out, exist_ok=True)
    sections = read_csv(os.path.join(args.programme, "test_sections.csv"))
    needed = [r for r in sections if r["AbrasionTest"] in TESTS]
    with tempfile.TemporaryDirectory(prefix="leon_t_") as tmp:
        configs = {"model": wheels_config(args.wheels, os.path.abspath(args.tire), tmp, "wheels_model.yaml"),
                   "paper": wheels_config(args.wheels, adhesion_off(args.tire, tmp), tmp, "wheels_paper.yaml")}
        jobs = [(args, r["Test section"], mass, min(args.laps, int(r["Number of laps"])), configs, tmp)
                for mass in sorted({masses[s] for s in scenarios}) for r in needed]
        sims = {}
        with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
            for i, (key, result) in enumerate(pool.map(simulate, jobs), start=1):
                sims[key] = result
                print("[leon_t] %d/%d %s at %.0f kg" % (i, len(jobs), key[0], key[1]), file=sys.stderr)
    tests_by_scenario = {s: per_test(args.programme, sims, masses[s]) for s in scenarios}
    if args.fit_adhesion:
        fit_adhesion(measured, tests_by_scenario)
        return
    model, factors = predictions(measured, tests_by_scenario, "model")
    paper, _ = predictions(measured, tests_by_scenario, "paper")
    friction, friction_factors = predictions(measured, tests_by_scenario, "friction")
    with open(os.path.join(args.out, "predictions.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["tyre_brand", "scenario", "test", "wheel", "measured_mean_mg_per_km", "measured_sd_mg_per_km",
                    "n_repeats", "predicted_mg_per_km"])
        for k in sorted(model):
            w.writerow(list(k) + ["%.4f" % measured[k][0], "%.4f" % measured[k][1], measured[k][2], "%.4f" % model[k]])
    with open(os.path.join(args.out, "comparison.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["tyre_brand", "scenario", "test", "wheel", "measured_mean_mg_per_km", "model_mg_per_km",
                    "paper_model_mg_per_km", "friction_work_mg_per_km", "friction_work_j_per_m"])
        for k in sorted(model):
            t = tests_by_scenario[k[1]][k[2]][k[3]]
            w.writerow(list(k) + ["%.4f" % measured[k][0], "%.4f" % model[k], "%.4f" % paper.get(k, float("nan")),
                                  "%.4f" % friction.get(k, float("nan")), "%.4f" % t["friction_j_per_m"]])
    text = ["# LEON-T per-wheel wear: measured against predicted\n",
            "Abrasivity factors (Standard Run-in vehicle total / model): " +
            ", ".join("%s %.3g" % (b, factors[b]) for b in sorted(factors)) + "; friction-work coefficients " +
            ", ".join("%s %.3g mg/kJ" % (b, friction_factors[b]) for b in sorted(friction_factors)) + ".\n",
            "Ratios are predicted / measured (1 = exact); F/R = the front/rear ratio predicted over measured; the "
            "per-wheel error is the geometric mean of max(p/m, m/p) over the wheels of the blind tests (Rural, "
            "Motorway, Urban) and of all four tests.\n",
            summary_tables(measured, {"model": model, "paper's model": paper, "friction work": friction})]
    with open(os.path.join(args.out, "summary.md"), "w") as f:
        f.write("\n".join(text))
    print("\n".join(text))
    if not args.no_plots:
        plot(measured, model, args.out)
    print("[leon_t] wrote %s/predictions.csv, comparison.csv, summary.md%s" %
          (args.out, "" if args.no_plots else ", leon_t_*.png"))


if __name__ == "__main__":
    main()
