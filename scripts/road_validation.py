#!/usr/bin/env python3
"""The model's side of every published road-wear relation in docs/road_validation.md.

Each scenario is one `tread_wear_drive` bag replayed by `tread_wear_replay` (the node's estimator), so the figures
are what a user gets end to end. Writes OUT/road_validation.json (every scenario's summary figures and every
relation's model value and verdict) and prints the relations table.

Usage: scripts/road_validation.py [--out DIR] [--preset standard] [--bin _build/devel/lib/tread_wear]
Runtime: about 4 minutes on 2 cores (preset standard).
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
VEHICLE = "config/vehicle_passenger_car.yaml"
WHEELS = "config/vehicle_wheels.yaml"
FRONT = ("front_left", "front_right")
REAR = ("rear_left", "rear_right")
STEADY_S = 60.0  # duration of every steady manoeuvre [s]

# Published relations: (key, relation, published range [lo, hi] of the model quantity, unit, sources).
# The ranges are the sources' own numbers (docs/road_validation.md gives the derivation of each).
PUBLISHED = {
    "level_per_tire": ([14.5, 40.0], "mg/km per tire", "ADAC 2022; Pohrt 2019; the paper's Introduction"),
    "level_per_tonne": ([52.0, 82.0], "mg/km/t", "OeAMTC 2024 (160 tyre tests)"),
    "cruise_130_over_80": ([1.0, math.inf], "ratio", "Pohrt 2019 (lower speed is the most effective measure)"),
    "cornering_exponent": ([2.0, 4.0], "exponent", "Veith 1986 (DSN, a_y^2); RCT 46(4):821 (1973), 2-4"),
    "longitudinal_exponent": ([2.0, 4.0], "exponent", "Schallamach & Turner 1960 (energy ~ F^2/C)"),
    "front_rear_fwd": ([1.0, 2.0], "ratio", "TST 1(1):17 (1973); tyre-trade rotation guidance (up to 2:1)"),
    "rear_front_rwd": ([1.0, math.inf], "ratio", "TST 1(1):17 (1973): RWD wears both axles more evenly"),
    "urban_over_motorway": ([1.49, 1.54], "ratio", "EMEP/EEA guidebook S_T(V); Beddows & Harrison 2021"),
    "rural_over_motorway": ([1.16, 1.36], "ratio", "EMEP/EEA guidebook S_T(V); Beddows & Harrison 2021"),
    "mass_elasticity": ([0.37, 1.0], "exponent", "Beddows & Harrison 2021 (0.43 +0.10/-0.06); per-tonne norm (1)"),
    "aggressive_over_calm": ([1.0, math.inf], "ratio", "Emissions Analytics 2022; BTMA; Auto Express (2.5x twisty)"),
    "free_rolling_30_over_5": ([0.5, 2.0], "ratio", "no published cruise-speed effect (Pohrt 2019): within x2"),
    "side_force_exponent": ([2.0, 4.0], "exponent", "RCT 46(4):821 (1973), 2-4; Schallamach & Turner 1960"),
}
TIRE = "config/tires/passenger_205_55_r16.yaml"
TIRE_LOAD_N = 4000.0  # about the passenger car's static wheel load


def run(cmd, stdin=None):
    result = subprocess.run(cmd, cwd=REPO, capture_output=True, text=True, input=stdin)
    if result.returncode != 0:
        sys.exit(f"[road_validation] failed ({result.returncode}): {' '.join(cmd)}\n{result.stderr}")
    return result.stdout


class Scenarios:
    def __init__(self, args):
        self.bin, self.out, self.preset = args.bin, args.out, getattr(args, "preset", "standard")
        self.results = {}

    def drive(self, name, drive_args, vehicle=VEHICLE):
        """One drive bag through the replay; returns per-wheel mg/km, the mean, distance and the phases."""
        bag = os.path.join(self.out, name + ".bag")
        summary = os.path.join(self.out, name + ".json")
        run([os.path.join(self.bin, "tread_wear_drive"), "--vehicle", vehicle, "--out", bag] + drive_args)
        run([os.path.join(self.bin, "tread_wear_replay"), bag, "--wheels", WHEELS, "--rate-hz", "50",
             "--preset", self.preset, "--quiet", "--summary", summary])
        os.remove(bag)
        s = json.load(open(os.path.join(REPO, summary)))
        wheels = {w["name"]: w["mg_per_km"] for w in s["wheels"]}
        r = {"wheels_mg_per_km": wheels, "mean_mg_per_km": s["mean_mg_per_km"], "duration_s": s["duration_s"],
             "vehicle_mg_per_km": sum(wheels.values()),
             "front_mg_per_km": sum(wheels[w] for w in FRONT) / 2, "rear_mg_per_km": sum(wheels[w] for w in REAR) / 2,
             "phases_mg_per_km": {p["name"]: p["mean_mg_per_km"] for p in s.get("phases", [])}}
        self.results[name] = r
        print(f"[road_validation] {name:<24} {r['vehicle_mg_per_km']:10.4f} mg/km per vehicle", flush=True)
        return r


def slope(xs, ys):
    """Least-squares slope of ln y over ln x."""
    lx, ly = [math.log(x) for x in xs], [math.log(y) for y in ys]
    mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sum((a - mx) ** 2 for a in lx)


def tire_points(bin_dir, preset, rows):
    """tread_wear_eval on (speed, slip angle) rows of the road tire at TIRE_LOAD_N, straight, no slip ratio."""
    text = "speed_mps,slip_angle_rad,slip_ratio,path_radius_m,load_n\n" + "".join(
        f"{v!r},{a!r},0,0,{TIRE_LOAD_N!r}\n" for v, a in rows)
    out = run([os.path.join(bin_dir, "tread_wear_eval"), "--params", TIRE, "--preset", preset, "-"], stdin=text)
    return list(csv.DictReader(out.splitlines()))


def tire_relations(bin_dir, preset):
    """Free-rolling wear per km at 30 over 5 m/s, and the exponent of wear against side force at 20 m/s where
    |Fy| is 0.1-0.3 Fz (the tire alone, tread_wear_eval)."""
    free = tire_points(bin_dir, preset, [(5.0, 0.0), (30.0, 0.0)])
    w5, w30 = (float(r["wear_rate_kg_per_m"]) for r in free)
    ratio = w30 / w5 if w5 > 0 else math.inf
    alphas = [0.002 * k for k in range(1, 40)]
    pts = [r for r in tire_points(bin_dir, preset, [(20.0, a) for a in alphas])
           if 0.1 <= abs(float(r["fy_n"])) / TIRE_LOAD_N <= 0.3]
    exponent = slope([abs(float(r["fy_n"])) for r in pts], [float(r["wear_rate_kg_per_m"]) for r in pts])
    return ratio, exponent, {"free_rolling_kg_per_m": {"5": w5, "30": w30},
                             "side_force_points": [(float(r["fy_n"]), float(r["wear_rate_kg_per_m"])) for r in pts]}


def eea_speed_factor(v_kmh):
    """EMEP/EEA guidebook speed correction S_T(V) of tyre wear at mean trip speed V."""
    if v_kmh < 40.0:
        return 1.39
    return 0.902 if v_kmh > 90.0 else -0.00974 * v_kmh + 1.78


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default="out/road_validation")
    parser.add_argument("--preset", default="standard")
    parser.add_argument("--bin", default=os.environ.get("TREAD_WEAR_BIN", "_build/devel/lib/tread_wear"))
    args = parser.parse_args()
    os.makedirs(os.path.join(REPO, args.out), exist_ok=True)
    sc = Scenarios(args)
    mass_kg = 1450.0  # config/vehicle_passenger_car.yaml

    wltc = sc.drive("wltc", [])
    rwd = sc.drive("wltc_rwd", ["--drive-layout", "rear"])
    masses = [1200.0, 1450.0, 1800.0, 2200.0]
    by_mass = [sc.drive(f"wltc_mass_{int(m)}", ["--mass-kg", str(m)])["vehicle_mg_per_km"] for m in masses]
    styles = {s: sc.drive(f"style_{s}", ["--style", s]) for s in ("calm", "normal", "aggressive")}
    cruise_kmh = [30.0, 50.0, 80.0, 100.0, 120.0, 130.0]
    cruise = [sc.drive(f"cruise_{int(v)}", ["--manoeuvre", "cruise", "--speed-kmh", str(v),
                                             "--duration-s", str(STEADY_S)])["vehicle_mg_per_km"] for v in cruise_kmh]
    ay = [1.0, 1.5, 2.0, 3.0, 4.0]
    circle = [sc.drive(f"circle_{a}", ["--manoeuvre", "circle", "--speed-kmh", "60", "--lateral-accel", str(a),
                                       "--duration-s", str(STEADY_S)])["vehicle_mg_per_km"] for a in ay]
    cruise_60 = sc.drive("cruise_60", ["--manoeuvre", "cruise", "--speed-kmh", "60",
                                       "--duration-s", str(STEADY_S)])["vehicle_mg_per_km"]
    ax = [0.5, 1.0, 2.0, 3.0]
    accel = [sc.drive(f"accel_{a}", ["--manoeuvre", "accel", "--low-speed-kmh", "30", "--high-speed-kmh", "70",
                                     "--accel-mps2", str(a), "--decel-mps2", str(a), "--duration-s", "120"])
             ["vehicle_mg_per_km"] for a in ax]

    phases = wltc["phases_mg_per_km"]
    free_ratio, fy_exponent, tire_series = tire_relations(args.bin, args.preset)
    model = {
        "level_per_tire": wltc["mean_mg_per_km"],
        "level_per_tonne": wltc["vehicle_mg_per_km"] / (mass_kg / 1000.0),
        "cruise_130_over_80": cruise[cruise_kmh.index(130.0)] / cruise[cruise_kmh.index(80.0)],
        "cornering_exponent": slope(ay, [c - cruise_60 for c in circle]),
        "longitudinal_exponent": slope(ax, accel),
        "front_rear_fwd": wltc["front_mg_per_km"] / wltc["rear_mg_per_km"],
        "rear_front_rwd": rwd["rear_mg_per_km"] / rwd["front_mg_per_km"],
        "urban_over_motorway": phases["Low"] / phases["Extra High"],
        "rural_over_motorway": phases["High"] / phases["Extra High"],
        "mass_elasticity": slope(masses, by_mass),
        "aggressive_over_calm": styles["aggressive"]["vehicle_mg_per_km"] / styles["calm"]["vehicle_mg_per_km"],
        "free_rolling_30_over_5": free_ratio,
        "side_force_exponent": fy_exponent,
    }
    relations = {}
    print("\n| relation | published | model | inside |\n|---|---|---|---|")
    for key, value in model.items():
        (lo, hi), unit, source = PUBLISHED[key]
        inside = lo <= value <= hi
        relations[key] = {"model": value, "published": [lo, hi if math.isfinite(hi) else None], "unit": unit,
                          "source": source, "inside": inside}
        hi_text = f"{hi:g}" if math.isfinite(hi) else "inf"
        print(f"| {key} | [{lo:g}, {hi_text}] {unit} | {value:.3f} | {'yes' if inside else 'no'} |")
    eea = {name: eea_speed_factor(v) / eea_speed_factor(91.7)
           for name, v in (("Low", 18.9), ("Medium", 39.5), ("High", 56.7), ("Extra High", 91.7))}
    document = {"preset": args.preset, "relations": relations, "scenarios": sc.results,
                "series": {"cruise_kmh": cruise_kmh, "cruise_vehicle_mg_per_km": cruise, "circle_ay_mps2": ay,
                           "circle_vehicle_mg_per_km": circle, "cruise_60_vehicle_mg_per_km": cruise_60,
                           "accel_ax_mps2": ax, "accel_vehicle_mg_per_km": accel, "mass_kg": masses,
                           "mass_vehicle_mg_per_km": by_mass,
                           "wltc_phase_over_extra_high": {k: v / phases["Extra High"] for k, v in phases.items()},
                           "eea_phase_over_extra_high": eea, "tire": tire_series}}
    with open(os.path.join(REPO, args.out, "road_validation.json"), "w") as f:
        json.dump(document, f, indent=1, sort_keys=True)
    inside = sum(r["inside"] for r in relations.values())
    print(f"\n[road_validation] {inside} of {len(relations)} relations inside the published range; "
          f"{os.path.join(args.out, 'road_validation.json')}")


if __name__ == "__main__":
    main()
