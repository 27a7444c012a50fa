"""tread_wear_fleet_generate: a synthetic fleet in the fleet layout (docs/fleet.md, "Synthetic fleet").

Vehicles alternate between the package's two cars (compact: config/vehicle_passenger_car.yaml on 205/55 R16 tires;
suv: config/vehicle_ford_kuga.yaml on 225/60 R18 tires), cycle through the driving styles calm, normal and
aggressive, and carry a random payload. Every day each vehicle drives --drives-per-day drives, each a window of the
WLTC class 3b from one of its stops (a drive of --drive-s seconds, then braking at 1.5 m/s^2 to a stop), written by
tread_wear_drive with the vehicle's style, mass and a seed of its own: the vehicle physics is the C++ one. The
readings (tread depth per wheel, every --readings-every-days days at the day's end, and before the first drive) are
the replay's own wear times --truth-scale plus a gauge error of --gauge-sigma-mm: a fleet whose answer is known.
"""
import argparse
import concurrent.futures
import copy
import csv
import datetime
import json
import os
import random
import shutil
import subprocess
import sys
import tempfile

import yaml

from . import diagnosis, layout, tasks
from .cli import find_bin_dir

KINDS = {
    "compact": {"vehicle": "vehicle_passenger_car.yaml", "wheels": "vehicle_wheels.yaml",
                "tire": "passenger_205_55_r16.yaml"},
    "suv": {"vehicle": "vehicle_ford_kuga.yaml", "wheels": "vehicle_wheels_kuga.yaml", "tire": "suv_225_60_r18.yaml"},
}
STYLES = ("calm", "normal", "aggressive")
CONCEAL_TOOL = "tread_wear_conceal"
STOP_DECEL_KMH_PER_S = 5.4  # 1.5 m/s^2: the calm style's braking
MAX_PAYLOAD_KG = 400.0


def wltc_speeds(share_dir):
    """The WLTC class 3b speeds [km/h], one per second."""
    with open(os.path.join(share_dir, "data", "wltc_class3b.csv")) as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))
    return [float(row[1]) for row in rows[1:]]


def drive_profile(speeds, start, drive_s):
    """A window of the cycle from a stop at `start`, ended by braking to a stop: [(time_s, speed_kmh)]."""
    window = speeds[start:start + drive_s]
    while window[-1] > 0.0:
        window.append(max(0.0, window[-1] - STOP_DECEL_KMH_PER_S))
    window += [0.0, 0.0]
    return list(enumerate(window))


def vehicle_plan(index, rng, kinds=tuple(KINDS)):
    """Kind, style and payload of vehicle `index`."""
    return kinds[index % len(kinds)], STYLES[(index // len(kinds)) % len(STYLES)], round(
        rng.uniform(0.0, MAX_PAYLOAD_KG))


def write_vehicle(directory, share_dir, kind, style, payload_kg):
    """The vehicle's files: vehicle.yaml, the package's wheel configuration, tire and vehicle parameter files."""
    files = KINDS[kind]
    os.makedirs(os.path.join(directory, "tires"), exist_ok=True)
    os.makedirs(os.path.join(directory, layout.DRIVES_DIR), exist_ok=True)
    shutil.copy(os.path.join(share_dir, "config", files["wheels"]), os.path.join(directory, "wheels.yaml"))
    shutil.copy(os.path.join(share_dir, "config", "tires", files["tire"]), os.path.join(directory, "tires"))
    shutil.copy(os.path.join(share_dir, "config", files["vehicle"]), directory)
    with open(os.path.join(share_dir, "config", files["vehicle"])) as f:
        mass_kg = float(yaml.safe_load(f)["mass_kg"]) + payload_kg
    meta = {"covariates": {"kind": kind, "style": style, "payload_kg": payload_kg}, "wheels": "wheels.yaml",
            "vehicle_params": files["vehicle"], "mass_kg": mass_kg}
    with open(os.path.join(directory, layout.VEHICLE_FILE), "w") as f:
        f.write("# Synthetic vehicle (tread_wear_fleet_generate); layout: docs/fleet.md\n")
        yaml.safe_dump(meta, f, sort_keys=False)
    return mass_kg


def _drive(bin_dir, directory, params, profile, style, mass_kg, seed, rate_hz, bag):
    with tempfile.NamedTemporaryFile("w", suffix=".csv", dir=directory, delete=False) as f:
        f.write("time_s,speed_kmh\n" + "".join(f"{t:.1f},{v:.2f}\n" for t, v in profile))
    try:
        subprocess.run([os.path.join(bin_dir, "tread_wear_drive"), "--profile", f.name, "--style", style,
                        "--vehicle", params, "--mass-kg", f"{mass_kg:g}", "--seed", str(seed),
                        "--rate-hz", f"{rate_hz:g}", "--out", bag], check=True, stdout=subprocess.DEVNULL)
    finally:
        os.remove(f.name)


def reading_days(vehicle, every_days):
    """The dates of the readings: the day before the first drive, then every every_days-th day of drives."""
    days = sorted({date for date, _ in vehicle.bags})
    return [days[0] - datetime.timedelta(days=1)] + days[every_days - 1::every_days]


def replayed_losses(vehicle, outcomes, dates):
    """{(wheel, reading date): the replay's mass loss up to the end of that date [kg]}."""
    loss = {}
    for date, bag in vehicle.bags:
        for w in outcomes[bag]["result"]["wheels"]:
            loss[(w["name"], date)] = loss.get((w["name"], date), 0.0) + w["mass_loss_kg"]
    return {(name, day): sum(kg for (wheel, d), kg in loss.items() if wheel == name and d <= day)
            for name, _ in vehicle.wheels for day in dates}


def concealed_losses(vehicle, dates, bin_dir, effect, magnitude, preset):
    """{(wheel, reading date): the true mass loss up to that date [kg]} with `effect` hidden: the proving module's
    truth of the vehicle's drive segments between the reading dates (tread_wear_conceal --bag on the diagnosis input
    that tread_wear_fleet --diagnose assembles, with placeholder readings that only delimit the segments)."""
    vehicle = copy.copy(vehicle)
    vehicle.readings = [(day, name, 10.0 - 0.001 * k) for name, _ in vehicle.wheels for k, day in enumerate(dates)]
    vehicle.reading_kind = "tread_depth_mm"
    plan = diagnosis.reading_plan(vehicle, {bag: {"result": {}} for _, bag in vehicle.bags})
    with tempfile.TemporaryDirectory(dir=vehicle.directory) as scratch:
        bag = diagnosis.assemble_bag(os.path.join(scratch, "input.bag"), [(plan, "", {})])
        segments = os.path.join(scratch, "segments.csv")
        command = [os.path.join(bin_dir, CONCEAL_TOOL), "--params", plan["tire"], "--effect", effect, "--bag", bag,
                   "--segments", segments, "--answer", os.path.join(scratch, "answer.json"),
                   "--generator-preset", preset]
        if magnitude is not None:
            command += ["--magnitude", f"{magnitude!r}"]
        run = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, check=False)
        if run.returncode != 0:
            raise RuntimeError(f"{CONCEAL_TOOL} on {vehicle.vehicle_id}: {run.stderr.strip()}")
        with open(segments) as f:
            rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
        with open(os.path.join(scratch, "answer.json")) as f:
            answer = json.load(f)
    cumulative = {}
    for name, _ in vehicle.wheels:
        lost = [float(r["true_mass_loss_kg"]) for r in sorted((r for r in rows if r["wheel"] == name),
                                                              key=lambda r: int(r["segment"]))]
        if len(lost) != len(dates) - 1:
            raise RuntimeError(f"{CONCEAL_TOOL} on {vehicle.vehicle_id}: {len(lost)} segments of wheel {name}, "
                               f"expected {len(dates) - 1}")
        for k, day in enumerate(dates):
            cumulative[(name, day)] = sum(lost[:k])
    return cumulative, answer


def write_readings(vehicle, cumulative_loss_kg, dates, truth_scale, sigma_mm, rng, truth):
    """readings.csv of one vehicle: the tire file's depth less truth_scale x the cumulative loss, plus gauge noise."""
    rows = []
    for name, tire in vehicle.wheels:
        for day in dates:
            lost_kg = cumulative_loss_kg[(name, day)]
            depth_mm = (tire.tread_depth_m - truth_scale * lost_kg / tire.mass_per_depth_kg_per_m()) * 1e3
            rows.append((day.isoformat(), name, f"{depth_mm + rng.gauss(0.0, sigma_mm):.7f}"))
    with open(os.path.join(vehicle.directory, layout.READINGS_FILE), "w") as f:
        f.write(f"# synthetic: depth = new - {truth_scale:g} x {truth} + N(0, {sigma_mm:g} mm)\n")
        f.write("date,wheel,tread_depth_mm\n" + "".join(",".join(r) + "\n" for r in sorted(rows)))


def generate(out_dir, share_dir, bin_dir, vehicles=8, days=2, drives_per_day=1, drive_s=60, rate_hz=10.0, seed=1,
             start_date=datetime.date(2026, 1, 5), readings_every_days=1, truth_scale=1.0, gauge_sigma_mm=0.002,
             jobs=1, readings=True, conceal=None, kinds=tuple(KINDS)):
    """Writes the fleet; returns its truth (vehicle plans and settings) as also written to FLEET_DIR/truth.json.
    conceal: (effect, magnitude or None, generator preset) to write the readings from the model's wear with a hidden
    library effect instead of the replay's."""
    rng = random.Random(seed)
    speeds = wltc_speeds(share_dir)
    stops = [t for t in range(len(speeds) - drive_s) if speeds[t] == 0.0 and speeds[t + 1] > 0.0]
    truth = {"seed": seed, "truth_scale": truth_scale, "gauge_sigma_mm": gauge_sigma_mm, "vehicles": {}}
    drives = []
    for i in range(vehicles):
        kind, style, payload_kg = vehicle_plan(i, rng, kinds)
        vehicle_id = f"v{i:03d}"
        directory = os.path.join(out_dir, vehicle_id)
        mass_kg = write_vehicle(directory, share_dir, kind, style, payload_kg)
        truth["vehicles"][vehicle_id] = {"kind": kind, "style": style, "payload_kg": payload_kg, "mass_kg": mass_kg}
        for day in range(days):
            date = start_date + datetime.timedelta(days=day)
            for k in range(drives_per_day):
                bag = os.path.join(directory, layout.DRIVES_DIR, f"{date.isoformat()}_{k}.bag")
                profile = drive_profile(speeds, rng.choice(stops), drive_s)
                drives.append((bin_dir, directory, os.path.join(directory, KINDS[kind]["vehicle"]), profile, style,
                               mass_kg, seed * 100003 + i * 1009 + day * 7 + k, rate_hz, bag))
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        list(pool.map(lambda d: _drive(*d), drives))
    if readings:
        fleet = layout.read_fleet(out_dir)
        with tempfile.TemporaryDirectory() as cache:
            def replay(job):
                vehicle, bag = job
                return bag, tasks.replay_bag(bag, vehicle.wheels_path, bin_dir, cache, "generate")

            with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
                outcomes = dict(pool.map(replay, [(v, bag) for v in fleet for _, bag in v.bags]))
        failed = [o for o in outcomes.values() if "error" in o]
        if failed:
            raise RuntimeError(f"replay of a generated bag failed: {failed[0]['bag']}: {failed[0]['error']}")
        dates = {v.vehicle_id: reading_days(v, readings_every_days) for v in fleet}
        if conceal is None:
            losses = {v.vehicle_id: replayed_losses(v, outcomes, dates[v.vehicle_id]) for v in fleet}
            what = "replayed wear"
        else:
            with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
                done = list(pool.map(lambda v: concealed_losses(v, dates[v.vehicle_id], bin_dir, *conceal), fleet))
            losses = {v.vehicle_id: loss for v, (loss, _) in zip(fleet, done)}
            truth["conceal"] = {"effect": conceal[0], "generator_preset": conceal[2],
                                "answer": {k: done[0][1][k] for k in ("effect", "primary", "primary_value",
                                                                      "magnitude")}}
            what = f"the model's wear with {conceal[0]} hidden (tread_wear_conceal --bag)"
        for vehicle in fleet:
            write_readings(vehicle, losses[vehicle.vehicle_id], dates[vehicle.vehicle_id], truth_scale,
                           gauge_sigma_mm, rng, what)
    with open(os.path.join(out_dir, "truth.json"), "w") as f:
        json.dump(truth, f, indent=1, sort_keys=True)
    return truth


def main(argv=None):
    parser = argparse.ArgumentParser(prog="tread_wear_fleet_generate", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", required=True, metavar="FLEET_DIR")
    parser.add_argument("--vehicles", type=int, default=8)
    parser.add_argument("--days", type=int, default=2)
    parser.add_argument("--drives-per-day", type=int, default=1)
    parser.add_argument("--drive-s", type=int, default=60, help="cycle window of a drive before its final stop [s]")
    parser.add_argument("--rate-hz", type=float, default=10.0, help="sample rate of the bags' inputs [Hz]")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--readings-every-days", type=int, default=1)
    parser.add_argument("--truth-scale", type=float, default=1.0, help="true wear / replayed wear in the readings")
    parser.add_argument("--gauge-sigma-mm", type=float, default=0.002, help="gauge error of a reading [mm]")
    parser.add_argument("--kinds", default=",".join(KINDS),
                        help=f"the vehicles' kinds in turn [default: {','.join(KINDS)}]")
    parser.add_argument("--no-readings", action="store_true")
    parser.add_argument("--conceal", metavar="EFFECT",
                        help="readings from the model's wear with this library effect hidden (tread_wear_conceal "
                             "--list; none: the model's wear as the diagnosis predicts it) instead of the replay's")
    parser.add_argument("--magnitude", type=float, help="the hidden effect's size [default: the term's default]")
    parser.add_argument("--generator-preset", choices=("fast", "standard", "fine", "reference"), default="fine",
                        help="preset of the model that generates the readings with --conceal [default: fine]")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="drives written at once")
    parser.add_argument("--bin", metavar="DIR", help="directory of tread_wear_drive and tread_wear_replay")
    parser.add_argument("--share", metavar="DIR", help="the package's source tree (config/, data/) [default: found]")
    args = parser.parse_args(argv)
    checks = {"--vehicles": args.vehicles >= 1, "--days": args.days >= 1, "--drives-per-day": args.drives_per_day >= 1,
              "--drive-s": 10 <= args.drive_s <= 1500, "--rate-hz": args.rate_hz > 0,
              "--readings-every-days": args.readings_every_days >= 1, "--truth-scale": args.truth_scale > 0,
              "--gauge-sigma-mm": args.gauge_sigma_mm >= 0, "--jobs": args.jobs >= 1}
    for option, ok in checks.items():
        if not ok:
            parser.error(f"{option} out of range (see --help)")
    share = args.share or os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
    if not os.path.isfile(os.path.join(share, "data", "wltc_class3b.csv")):
        parser.error(f"{share}: not the package's source tree (no data/wltc_class3b.csv): pass --share")
    kinds = tuple(args.kinds.split(","))
    if not kinds or any(k not in KINDS for k in kinds):
        parser.error(f"--kinds: a comma-separated list of {', '.join(KINDS)}")
    if args.conceal and args.no_readings:
        parser.error("--conceal hides an effect in the readings: it does not go with --no-readings")
    if args.magnitude is not None and not args.conceal:
        parser.error("--magnitude needs --conceal")
    if os.path.exists(args.out) and os.listdir(args.out):
        parser.error(f"{args.out} exists and is not empty")
    try:
        bin_dir = find_bin_dir(args.bin, "tread_wear_drive")
        truth = generate(args.out, share, bin_dir, args.vehicles, args.days, args.drives_per_day, args.drive_s,
                         args.rate_hz, args.seed, readings_every_days=args.readings_every_days,
                         truth_scale=args.truth_scale, gauge_sigma_mm=args.gauge_sigma_mm, jobs=args.jobs,
                         readings=not args.no_readings,
                         conceal=(args.conceal, args.magnitude, args.generator_preset) if args.conceal else None,
                         kinds=kinds)
    except (layout.FleetError, RuntimeError, subprocess.CalledProcessError) as e:
        print(f"tread_wear_fleet_generate: {e}", file=sys.stderr)
        return 2
    print(f"{args.out}: {len(truth['vehicles'])} vehicles x {args.days} days x {args.drives_per_day} drives")
    return 0
