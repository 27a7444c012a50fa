"""Per-vehicle and fleet-level diagnosis from workshop readings (docs/fleet.md, "Diagnosis").

The diagnosis tool (tread_wear_diagnose --bag, docs/diagnosis.md) reads one bag of drives with tread-depth or mass
checkpoints per wheel. This module writes that bag from the fleet layout (assemble_bag): a vehicle's drives in date
order, re-stamped one after the other (the drive bags all start at the same bag time), with each workshop reading as
a checkpoint between the last drive of its date and the next drive, and the vehicle's covariates as `measured/
covariate` strings. The fleet-level input pools every vehicle on one tire file into one bag: the vehicles one after
the other in time, each wheel renamed `<vehicle>_<wheel>` (a segment is keyed by its wheel's name), the covariates
(and `vehicle`) set at the start of each vehicle's block, so that every segment carries its own vehicle's values.
One diagnosis per vehicle and per pool runs as a task (diagnose_job), cached by content like the replays.
"""
import csv
import glob
import hashlib
import json
import math
import os
import re
import shutil
import tempfile

from . import tasks

DIAGNOSE_TOOL = "tread_wear_diagnose"
RESULT_VERSION = 1
GAP_S = 10.0  # idle bag time between two drives; the checkpoints sit in these gaps [s]
START_S = 1000.0  # bag time of an assembled bag's first message [s]
INPUT_KINDS = ("load", "slip", "speed", "tread_temperature")
DEVIATION_Z = 3.0  # |z| of a vehicle's mean residual under the pooled model that marks it as deviating


class ReadingsProblem(Exception):
    """Why a vehicle's readings cannot be diagnosed (the message names the file, the wheel and the dates)."""


def wheel_topics(wheels_path):
    """{wheel: {input kind: bag topic without the leading slash}} of a replay wheel configuration."""
    import yaml

    with open(wheels_path) as f:
        wheels = yaml.safe_load(f)["wheels"]
    keys = {"load": "load_topic", "slip": "slip_topic", "speed": "speed_topic",
            "tread_temperature": "temperature_topic"}
    return {str(w["name"]): {kind: str(w.get(keys[kind], f"wheels/{w['name']}/{kind}")).lstrip("/")
                             for kind in INPUT_KINDS} for w in wheels}


def reading_plan(vehicle, outcomes):
    """What a vehicle's diagnosis reads: the wheels with at least two readings, each wheel's readings by date, and
    the drives between the first and the last reading. ReadingsProblem when there is nothing to diagnose or a
    reading cannot be a checkpoint (a second reading of a wheel on one date, no drive between two readings, a depth or
    mass that does not fall)."""
    source = os.path.join(vehicle.directory, "readings.csv")
    if not vehicle.readings:
        raise ReadingsProblem(f"{vehicle.vehicle_id}: no workshop readings ({source} missing or empty)")
    by_wheel = {}
    for date, wheel, value in vehicle.readings:
        if date in by_wheel.setdefault(wheel, {}):
            raise ReadingsProblem(f"{source}: wheel {wheel} has two readings on {date.isoformat()}")
        by_wheel[wheel][date] = value
    drive_dates = [date for date, _ in vehicle.bags]
    unit = "mm" if vehicle.reading_kind == "tread_depth_mm" else "kg"
    readings = {}
    for wheel, values in by_wheel.items():
        dates = sorted(values)
        for before, after in zip(dates, dates[1:]):
            if not any(before < d <= after for d in drive_dates):
                raise ReadingsProblem(f"{source}: wheel {wheel}: no drive between the readings of "
                                      f"{before.isoformat()} and {after.isoformat()}")
            if not values[after] < values[before]:
                raise ReadingsProblem(f"{source}: wheel {wheel}: {values[after]:g} {unit} on {after.isoformat()} is "
                                      f"not below {values[before]:g} {unit} on {before.isoformat()} (a segment "
                                      f"needs a loss)")
        if len(dates) >= 2:
            readings[wheel] = [(d, values[d]) for d in dates]
    if not readings:
        raise ReadingsProblem(f"{source}: no wheel has two readings with drives between them")
    first = min(r[0][0] for r in readings.values())
    last = max(r[-1][0] for r in readings.values())
    drives = [(date, bag) for date, bag in vehicle.bags if first < date <= last]
    failed = [bag for _, bag in drives if "error" in outcomes.get(bag, {"error": "not replayed"})]
    if failed:
        raise ReadingsProblem(f"{failed[0]}: the drive bag failed its replay "
                              f"({outcomes.get(failed[0], {}).get('error', 'not replayed')})")
    tires = {tire.path for name, tire in vehicle.wheels if name in readings}
    if len({tasks.file_sha256(p) for p in tires}) > 1:
        raise ReadingsProblem(f"{vehicle.vehicle_id}: the read wheels are on different tire files "
                              f"({', '.join(sorted(tires))}); a diagnosis takes one")
    tire = next(tire for name, tire in vehicle.wheels if name in readings)
    return {"vehicle": vehicle.vehicle_id, "tire": tire.path, "kind": vehicle.reading_kind, "readings": readings,
            "drives": drives, "topics": wheel_topics(vehicle.wheels_path), "covariates": vehicle.covariates,
            "readings_sha256": hashlib.sha256(json.dumps(
                {w: [(d.isoformat(), v) for d, v in r] for w, r in sorted(readings.items())}).encode()).hexdigest()}


def _name_part(text):
    return re.sub(r"[^A-Za-z0-9_]", "_", str(text))


def _write_block(bag, plan, prefix, covariates, cursor):
    """One vehicle's drives and checkpoints from bag time `cursor` on; returns the cursor after them."""
    import rosbag
    import rospy
    from std_msgs.msg import Float64, String

    kind_topic = "tread_depth" if plan["kind"] == "tread_depth_mm" else "mass"
    scale = 1e-3 if plan["kind"] == "tread_depth_mm" else 1.0  # the bag's checkpoints are SI: m or kg
    for name, value in sorted(covariates.items()):
        bag.write("measured/covariate", String(data=f"{name}={value}"), rospy.Time.from_sec(cursor))
    cursor += 1.0
    pending = {wheel: list(values) for wheel, values in plan["readings"].items()}

    def checkpoints(before=None):
        """The pending readings dated before `before` (all without): taken after that date's drives."""
        nonlocal cursor
        for wheel in sorted(pending):
            while pending[wheel] and (before is None or pending[wheel][0][0] < before):
                _, value = pending[wheel].pop(0)
                bag.write(f"wheels/{prefix}{wheel}/measured/{kind_topic}", Float64(data=value * scale),
                          rospy.Time.from_sec(cursor))
        cursor += GAP_S

    topics = {topic: f"wheels/{prefix}{wheel}/{kind}" for wheel in plan["readings"]
              for kind, topic in plan["topics"][wheel].items()}
    wanted = list(topics) + ["/" + t for t in topics]
    for date, path in plan["drives"]:
        checkpoints(date)
        with rosbag.Bag(path) as drive:
            start = last = None
            for topic, msg, t in drive.read_messages(topics=wanted, raw=True):
                start = t.to_sec() if start is None else start
                last = cursor + t.to_sec() - start
                bag.write(topics[topic.lstrip("/")], msg, rospy.Time.from_sec(last), raw=True)
        cursor = (last if last is not None else cursor) + GAP_S
    checkpoints()
    return cursor


def assemble_bag(out_path, blocks):
    """Writes the diagnosis bag of `blocks` [(plan, wheel prefix, covariates)], one block after the other in time."""
    import rosbag

    cursor = START_S
    with rosbag.Bag(out_path, "w") as bag:
        for plan, prefix, covariates in blocks:
            cursor = _write_block(bag, plan, prefix, covariates, cursor) + GAP_S
    return out_path


def pool_prefix(vehicle_id):
    """The wheel-name prefix of a vehicle in a pooled bag (a ROS name: letters, digits, underscores)."""
    return _name_part(vehicle_id) + "_"


def tool_id(bin_dir, diagnose_args):
    """Identity of the diagnosis tool, the package's libraries and the options (hex SHA-256)."""
    digest = hashlib.sha256(f"diagnosis {RESULT_VERSION} gap {GAP_S}\n".encode())
    libraries = sorted(glob.glob(os.path.join(os.path.dirname(os.path.abspath(bin_dir)), "libtread_wear_*.so*")))
    for path in [os.path.join(bin_dir, DIAGNOSE_TOOL)] + libraries:
        digest.update(f"{os.path.basename(path)} {tasks.file_sha256(path)}\n".encode())
    digest.update(json.dumps(list(diagnose_args)).encode())
    return digest.hexdigest()


def job_key(job, outcomes, tool):
    """Cache key of a diagnosis job: its blocks' drive bags (their replay's SHA-256), readings, tire file, wheel
    prefixes and covariates, and the tool's identity."""
    digest = hashlib.sha256(f"{tool} {job['cv_groups']}\n".encode())
    digest.update(tasks.file_sha256(job["tire"]).encode())
    for plan, prefix, covariates in job["blocks"]:
        digest.update(json.dumps([plan["vehicle"], prefix, {k: str(v) for k, v in covariates.items()},
                                  plan["readings_sha256"], plan["topics"],
                                  [outcomes[bag]["result"]["bag_sha256"] for _, bag in plan["drives"]]],
                                 sort_keys=True).encode())
    return digest.hexdigest()


def verdict(document):
    """The part of a diagnosis.json that the fleet keeps: the verdict and its numbers, no timings."""
    cv_before, cv_after = document.get("cv_rmser_before", {}), document.get("cv_rmser_after", {})
    return {"explanation": document["explanation"], "mismatch_found": document["mismatch_found"],
            "terms": [t["name"] for t in document["explanation_terms"]],
            "parameters": {name: {"value": p["value"], "std_error": p["std_error"], "unit": p["unit"]}
                           for name, p in document["parameters"].items()},
            "held_out_wear_rmser_before": cv_before.get("wear"), "held_out_wear_rmser_after": cv_after.get("wear"),
            "cv_scheme": document["cv_scheme"], "segments": document["runs"],
            "located": sorted({e["covariate"] for e in document["located"] if "covariate" in e}),
            "close_alternatives": [a["model"] for a in document["close_alternatives"]],
            "wear_noise_rsd": document["noise_left"]["wear_rsd"],
            "preset": document["numerics"].get("preset") if isinstance(document["numerics"], dict) else None}


def wear_residuals(residuals_csv):
    """[(wheel, relative wear residual after the final model)] per segment of a report's residuals.csv."""
    with open(residuals_csv, newline="") as f:
        return [(row["wheel"], float(row["residual_wear_after"])) for row in csv.DictReader(f)
                if row.get("residual_wear_after")]


def deviations(residuals, prefixes):
    """Per vehicle of a pool, the mean relative wear residual under the pooled model, n and z = mean / (s / sqrt(n))
    with s the residuals' RMS over the pool (the noise the pooled model leaves); deviating when |z| > DEVIATION_Z."""
    if not residuals:
        return {}
    s = math.sqrt(sum(r * r for _, r in residuals) / len(residuals))
    out = {}
    for vehicle, prefix in prefixes.items():
        mine = [r for wheel, r in residuals if wheel.startswith(prefix)]
        if not mine:
            continue
        mean = sum(mine) / len(mine)
        z = mean / (s / math.sqrt(len(mine))) if s > 0 else 0.0
        out[vehicle] = {"segments": len(mine), "mean_wear_residual": mean, "z": z, "deviates": abs(z) > DEVIATION_Z}
    return out


def diagnose_job(job, bin_dir, cache_dir, report_dir, diagnose_args):
    """Runs one diagnosis (or takes its cached result): assembles the bag, runs tread_wear_diagnose with one thread,
    keeps its report (diagnosis.json, report.md, residuals.csv) in report_dir. Returns {name, cached, result | error,
    cpu_s}; the result is written to cache_dir/<key>.json through a temporary file and os.replace."""
    entry = os.path.join(cache_dir, job["key"] + ".json")
    if os.path.exists(entry):
        with open(entry) as f:
            return {"name": job["name"], "cached": True, "result": json.load(f), "cpu_s": 0.0}
    os.makedirs(cache_dir, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=cache_dir, prefix=".diagnose-") as scratch:
        bag = assemble_bag(os.path.join(scratch, "input.bag"), job["blocks"])
        report = os.path.join(scratch, "report")
        command = [os.path.join(bin_dir, DIAGNOSE_TOOL), "--params", job["tire"], "--bag", bag, "--report", report,
                   "--no-plots", "--quiet", "--jobs", "1"] + list(diagnose_args)
        if job["cv_groups"]:
            command += ["--cv-groups", job["cv_groups"]]
        run, cpu_s = tasks.run_tool(command)
        if run.returncode != 0:
            return {"name": job["name"], "cached": False,
                    "error": tasks.tool_reason(run.stderr, run.returncode, DIAGNOSE_TOOL), "cpu_s": cpu_s}
        with open(os.path.join(report, "diagnosis.json")) as f:
            result = verdict(json.load(f))
        if job["prefixes"]:
            result["deviations"] = deviations(wear_residuals(os.path.join(report, "residuals.csv")), job["prefixes"])
        os.makedirs(report_dir, exist_ok=True)
        for name in ("diagnosis.json", "report.md", "residuals.csv"):
            shutil.copy(os.path.join(report, name), os.path.join(report_dir, name))
        partial = os.path.join(scratch, "entry.json")
        with open(partial, "w") as f:
            json.dump(result, f, sort_keys=True)
        os.replace(partial, entry)
    return {"name": job["name"], "cached": False, "result": result, "cpu_s": cpu_s}


def plan_jobs(vehicles, outcomes, bin_dir, diagnose_args):
    """The diagnosis jobs (one per vehicle with usable readings, one per pool: the vehicles on one tire file) and
    the vehicles skipped with their reason."""
    tool = tool_id(bin_dir, diagnose_args)
    jobs, skipped, pools = [], [], {}
    for vehicle in vehicles:
        try:
            plan = reading_plan(vehicle, outcomes)
        except ReadingsProblem as e:
            skipped.append({"vehicle": vehicle.vehicle_id, "reason": str(e)})
            continue
        jobs.append({"name": vehicle.vehicle_id, "scope": "vehicle", "tire": plan["tire"], "cv_groups": None,
                     "blocks": [(plan, "", dict(vehicle.covariates))], "prefixes": {}})
        pools.setdefault(tasks.file_sha256(plan["tire"]), []).append((vehicle, plan))
    for members in pools.values():
        tire = members[0][1]["tire"]
        name = "fleet" if len(pools) == 1 else "fleet_" + os.path.splitext(os.path.basename(tire))[0]
        # Every block sets every covariate of the pool (a covariate message holds until the next one of its name).
        names = {name for v, _ in members for name in v.covariates}
        blocks = [(plan, pool_prefix(v.vehicle_id), {**{n: "unknown" for n in names}, **v.covariates,
                                                      "vehicle": v.vehicle_id}) for v, plan in members]
        jobs.append({"name": name, "scope": "fleet", "tire": tire, "blocks": blocks,
                     "cv_groups": "vehicle" if len(members) >= 2 else None,
                     "prefixes": {v.vehicle_id: pool_prefix(v.vehicle_id) for v, _ in members}})
    for job in jobs:
        job["key"] = job_key(job, outcomes, tool)
        job["vehicles"] = [plan["vehicle"] for plan, _, _ in job["blocks"]]
    return jobs, skipped


def run_diagnoses(vehicles, outcomes, out_dir, bin_dir, scheduler=None, workers=2, serial=False, diagnose_args=(),
                  progress=True, retries=1):
    """Every vehicle's and pool's diagnosis on the engine; returns the document's `diagnosis` section."""
    from . import engine

    jobs, skipped = plan_jobs(vehicles, outcomes, bin_dir, diagnose_args)
    cache_dir = os.path.join(os.path.abspath(out_dir), "cache", "diagnosis")
    report_root = os.path.join(os.path.abspath(out_dir), "diagnosis")
    named = [(job["name"], (job, bin_dir, cache_dir, os.path.join(report_root, job["name"]), list(diagnose_args)))
             for job in jobs]
    bar = engine.Progress(len(jobs), enabled=progress, unit="diagnoses")
    if serial or not jobs:
        results = {}
        for name, args in named:
            results[name] = diagnose_job(*args)
            bar.update(results[name])
    else:
        results = engine.map_tasks(diagnose_job, named, scheduler, workers, retries,
                                   lambda name, outcome: bar.update(outcome),
                                   lambda name, e: {"name": name, "cached": False,
                                                    "error": f"task failed: {type(e).__name__}: {e}"})
    entries = []
    for job in jobs:
        outcome = results[job["name"]]
        entry = {"name": job["name"], "scope": job["scope"], "tire": os.path.basename(job["tire"]),
                 "vehicles": job["vehicles"], "cached": outcome["cached"]}
        entry.update({"error": outcome["error"]} if "error" in outcome else outcome["result"])
        entries.append(entry)
    return {"vehicles": [e for e in entries if e["scope"] == "vehicle"],
            "fleet": [e for e in entries if e["scope"] == "fleet"], "skipped": skipped,
            "run": {"diagnoses": len(jobs), "cached": sum(1 for e in entries if e["cached"]),
                    "failed": sum(1 for e in entries if "error" in e),
                    "cpu_s": sum(r.get("cpu_s", 0.0) for r in results.values())}}


def term_values(entry):
    """'name=value+-se' of the explanation's own parameters (not the base levels w3_scale and mu_scale)."""
    return ";".join(f"{name}={p['value']:.6g}+-{p['std_error']:.2g}" if p["std_error"] is not None else
                    f"{name}={p['value']:.6g}" for name, p in sorted(entry.get("parameters", {}).items())
                    if name not in ("w3_scale", "mu_scale"))


def diagnosis_rows(section):
    """diagnosis.csv: one row per vehicle (diagnosed, failed or skipped) and per pool."""
    deviation = {v: d for pool in section["fleet"] for v, d in pool.get("deviations", {}).items()}
    for e in section["vehicles"] + section["fleet"]:
        d = deviation.get(e["name"], {}) if e["scope"] == "vehicle" else {}
        yield [e["scope"], e["name"], e["tire"], len(e["vehicles"]), e.get("segments"), e.get("explanation", ""),
               term_values(e), e.get("parameters", {}).get("w3_scale", {}).get("value"),
               e.get("held_out_wear_rmser_before"), e.get("held_out_wear_rmser_after"), e.get("cv_scheme", ""),
               d.get("mean_wear_residual"), d.get("z"), int(d["deviates"]) if d else None, e.get("error", "")]
    for s in section["skipped"]:
        yield ["vehicle", s["vehicle"], "", 1, None, "", "", None, None, None, "", None, None, None,
               "skipped: " + s["reason"]]


DIAGNOSIS_HEADER = ["scope", "name", "tire", "vehicles", "segments", "explanation", "term_parameters", "w3_scale",
                    "held_out_wear_rmser_before", "held_out_wear_rmser_after", "cv_scheme",
                    "pooled_mean_wear_residual", "pooled_residual_z", "deviates", "error"]
