"""tread_wear_fleet: replay every drive bag of a fleet on Dask distributed, then reduce per vehicle and fleet-wide.

  tread_wear_fleet FLEET_DIR --out DIR [--scheduler ADDRESS] [--workers N] [--diagnose [--diagnosis-preset P]]

Without --scheduler it starts a local cluster of N workers in this process (each task runs the replay as its own
process, so they run in parallel); with --scheduler it uses the running cluster at ADDRESS (tcp://host:8786), whose
workers must see FLEET_DIR, DIR and the package's binaries at the same paths (docs/fleet.md). Outputs in DIR:
bags.csv, daily.csv, wheels.csv, failures.csv, fleet.json and the plots; the per-bag cache in DIR/cache. With
--diagnose also each vehicle's and the fleet's diagnosis from the workshop readings (tread_wear_diagnose, one task
each): diagnosis.csv, fleet.json's `diagnosis`, the reports in DIR/diagnosis/<name>/.
Exit status 0, 1 when a bag or a diagnosis failed (the rest is complete), 2 on bad usage or layout.
"""
import argparse
import os
import shutil
import sys

from . import diagnosis, engine, layout, outputs, reductions, tasks


def find_bin_dir(explicit=None, tool=tasks.REPLAY_TOOL):
    """The directory of the package's C++ tools: --bin, $TREAD_WEAR_BIN, the running script's directory (catkin's
    devel or install space), PATH, then this checkout's _build/devel."""
    here = os.path.dirname(os.path.abspath(__file__))
    candidates = [explicit, os.environ.get("TREAD_WEAR_BIN"), os.path.dirname(os.path.abspath(sys.argv[0])),
                  os.path.dirname(shutil.which(tool) or ""),
                  os.path.join(here, "..", "..", "_build", "devel", "lib", "tread_wear")]
    for candidate in candidates:
        if candidate and os.access(os.path.join(candidate, tool), os.X_OK):
            return os.path.abspath(candidate)
    if explicit:
        raise layout.FleetError(f"--bin {explicit}: no executable {tool} there")
    raise layout.FleetError(f"{tool} not found: pass --bin DIR or set TREAD_WEAR_BIN (_build/devel/lib/tread_wear)")


def build_jobs(vehicles, bin_dir, replay_args):
    """One job per bag, with its vehicle's replay identity (tasks.payload_id)."""
    jobs = []
    for vehicle in vehicles:
        config_id = tasks.payload_id(bin_dir, vehicle.wheels_path, {tire.path for _, tire in vehicle.wheels},
                                     replay_args)
        jobs.extend({"bag": bag, "vehicle": vehicle.vehicle_id,
                     "wheels_path": vehicle.wheels_path, "config_id": config_id,
                     "replay_args": list(replay_args)} for _, bag in vehicle.bags)
    return jobs


def run_fleet(fleet_dir, out_dir, scheduler=None, workers=2, serial=False, bin_dir=None, replay_args=(),
              plots=True, progress=True, diagnose_args=None):
    """Runs the whole fleet; returns the fleet document (reductions.fleet_reduction)."""
    vehicles = layout.read_fleet(fleet_dir)
    bin_dir = find_bin_dir(bin_dir)
    os.makedirs(out_dir, exist_ok=True)
    cache_dir = os.path.join(os.path.abspath(out_dir), "cache")
    jobs = build_jobs(vehicles, bin_dir, replay_args)
    outcomes, counts = engine.run_jobs(jobs, bin_dir, cache_dir, scheduler=scheduler, workers=workers, serial=serial,
                                       progress=progress)
    document = reductions.fleet_reduction(vehicles, outcomes, counts)
    if diagnose_args is not None:
        if not os.access(os.path.join(bin_dir, diagnosis.DIAGNOSE_TOOL), os.X_OK):
            raise layout.FleetError(f"{bin_dir}: no executable {diagnosis.DIAGNOSE_TOOL} (needed by --diagnose)")
        document["diagnosis"] = diagnosis.run_diagnoses(vehicles, outcomes, out_dir, bin_dir, scheduler=scheduler,
                                                        workers=workers, serial=serial, diagnose_args=diagnose_args,
                                                        progress=progress)
    outputs.write_tables(out_dir, document, vehicles, outcomes, os.path.abspath(fleet_dir))
    if plots:
        outputs.write_plots(out_dir, document)
    return document


def diagnose_args(args):
    """tread_wear_diagnose's options from the command line's --diagnosis-* options."""
    out = ["--preset", args.diagnosis_preset]
    if args.diagnosis_max_terms is not None:
        out += ["--max-terms", str(args.diagnosis_max_terms)]
    if args.diagnosis_detection_power is not None:
        out += ["--detection-power", repr(args.diagnosis_detection_power)]
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(prog="tread_wear_fleet", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("fleet_dir", metavar="FLEET_DIR", help="the fleet (layout: docs/fleet.md)")
    parser.add_argument("--out", required=True, metavar="DIR", help="output directory (and its cache/)")
    parser.add_argument("--scheduler", metavar="ADDRESS", help="a running Dask scheduler, e.g. tcp://host:8786")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1, metavar="N",
                        help="workers of the local cluster (without --scheduler), one replay each [default: cores]")
    parser.add_argument("--serial", action="store_true", help="no Dask: every bag in this process, in order")
    parser.add_argument("--preset", choices=("fast", "standard", "fine", "reference"),
                        help="wear model preset instead of each vehicle's wheel configuration's")
    parser.add_argument("--bin", metavar="DIR", help="directory of tread_wear_replay [default: found, see --help]")
    parser.add_argument("--diagnose", action="store_true",
                        help="also diagnose every vehicle with readings and the fleet (docs/fleet.md, Diagnosis)")
    parser.add_argument("--diagnosis-preset", choices=("auto", "fast", "standard", "fine", "reference"),
                        default="auto", help="tread_wear_diagnose --preset [default: auto]")
    parser.add_argument("--diagnosis-max-terms", type=int, metavar="N",
                        help="tread_wear_diagnose --max-terms [default: the tool's, 2]")
    parser.add_argument("--diagnosis-detection-power", type=float, metavar="X",
                        help="tread_wear_diagnose --detection-power (0: no detection limits) [default: the tool's]")
    parser.add_argument("--no-plots", action="store_true")
    parser.add_argument("--quiet", action="store_true", help="no progress")
    args = parser.parse_args(argv)
    if args.workers < 1:
        parser.error("--workers must be >= 1")
    if args.scheduler and args.serial:
        parser.error("--scheduler and --serial exclude each other")
    try:
        document = run_fleet(args.fleet_dir, args.out, scheduler=args.scheduler, workers=args.workers,
                             serial=args.serial, bin_dir=args.bin,
                             replay_args=["--preset", args.preset] if args.preset else [],
                             plots=not args.no_plots, progress=not args.quiet,
                             diagnose_args=diagnose_args(args) if args.diagnose else None)
    except layout.FleetError as e:
        print(f"tread_wear_fleet: {e}", file=sys.stderr)
        return 2
    run = document["run"]
    print(f"{run['bags']} bags: {run['replayed']} replayed, {run['cached']} cached, {run['failed']} failed "
          f"({run['wall_s']:.1f} s wall, {run['replay_cpu_s']:.1f} s replay CPU); outputs in {args.out}")
    for failure in document["failures"]:
        print(f"  FAILED {os.path.relpath(failure['bag'], args.fleet_dir)}: {failure['reason']}", file=sys.stderr)
    for v in document["vehicles"]:
        worst = min((w for w in v["wheels"] if w["model_km_to_limit"] is not None),
                    key=lambda w: w["model_km_to_limit"], default=None)
        limit = (f", {worst['wheel']} at the limit in {worst['model_km_to_limit']:.0f} km "
                 f"({worst['model_date_at_limit'] or 'beyond 9999'})" if worst else "")
        rate = "-" if v["mean_mg_per_km"] is None else f"{v['mean_mg_per_km']:.2f}"
        print(f"  {v['vehicle']}: {v['replayed_bags']}/{v['bags']} bags, {rate} mg/km{limit}"
              f"{'  OUTLIER' if v.get('outlier') else ''}")
    section = document.get("diagnosis")
    if section:
        for e in section["vehicles"] + section["fleet"]:
            what = e.get("explanation") or "FAILED: " + e.get("error", "")
            print(f"  diagnosis {e['name']} ({e.get('segments') or 0} segments): {what}"
                  f"{' ' + diagnosis.term_values(e) if e.get('terms') else ''}")
        for s in section["skipped"]:
            print(f"  diagnosis {s['vehicle']}: skipped: {s['reason']}")
        deviating = sorted(v for pool in section["fleet"] for v, d in pool.get("deviations", {}).items()
                           if d["deviates"])
        if deviating:
            print(f"  deviating from the pooled model: {', '.join(deviating)}")
    return 1 if document["failures"] or (section and section["run"]["failed"]) else 0
