#!/usr/bin/python3
"""Fleet-level against single-vehicle diagnosis on the same hidden effect (docs/fleet.md, "Fleet-level diagnosis:
what pooling resolves"; issue 35's target).

  bench/fleet_diagnosis_study.py [--effect contact_time_wear] [--magnitude 3e-6] [--seeds 1,2,3] [--controls 1,2,3]
      [--vehicles 9] [--days 3] [--drive-s 300] [--gauge-sigma-mm 2e-5] [--generator-preset fast]
      [--diagnosis-preset fast] [--max-terms 1] [--workers 2] [--keep DIR] [--bin DIR]

Per seed: a synthetic fleet of compact cars (tread_wear_fleet_generate --kinds compact: one tire file, so one pool),
the styles calm, normal and aggressive in turn, whose readings are the model's wear with --effect hidden at
--magnitude (a control fleet of each --controls seed: --conceal none), then tread_wear_fleet --diagnose. A fleet is
right when its pooled verdict names the effect (a control: `none`); each vehicle's verdict is counted apart. Prints
one line per fleet and a summary table (markdown), with the wall time and the load average before and after.
The diagnoses take at most --max-terms terms and compute no detection limits (the verdict only), to keep a fleet at
minutes.
"""
import argparse
import os
import shutil
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "python"))

from tread_wear_fleet import cli, generate  # noqa: E402


def loadavg():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def one_fleet(work, seed, effect, args, bin_dir):
    """Generates and diagnoses one fleet; returns (pooled verdict, [vehicle verdicts], pooled entry, wall s)."""
    fleet, out = os.path.join(work, f"{effect}_{seed}"), os.path.join(work, f"{effect}_{seed}_out")
    shutil.rmtree(fleet, ignore_errors=True)
    shutil.rmtree(out, ignore_errors=True)
    start = time.monotonic()
    generate.generate(fleet, os.path.join(HERE, ".."), bin_dir, vehicles=args.vehicles, days=args.days,
                      drive_s=args.drive_s, seed=seed, gauge_sigma_mm=args.gauge_sigma_mm, jobs=args.workers,
                      conceal=(effect, args.magnitude if effect != "none" else None, args.generator_preset),
                      kinds=("compact",))
    document = cli.run_fleet(fleet, out, workers=args.workers, bin_dir=bin_dir, plots=False, progress=False,
                             diagnose_args=["--preset", args.diagnosis_preset, "--max-terms", str(args.max_terms),
                                            "--detection-power", "0"])
    section = document["diagnosis"]
    (pool,) = section["fleet"]
    return pool, section["vehicles"], section["skipped"], time.monotonic() - start


def describe(entry):
    if "error" in entry:
        return "FAILED " + entry["error"]
    terms = {k: v for k, v in entry["parameters"].items() if k not in ("w3_scale", "mu_scale")}
    values = " ".join(f"{k}={v['value']:.3g}+-{(v['std_error'] or 0):.2g}" for k, v in terms.items())
    return f"{entry['explanation']} {values}".strip()


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--effect", default="contact_time_wear")
    parser.add_argument("--magnitude", type=float, default=3e-6)
    parser.add_argument("--seeds", default="1,2,3", help="fleets with the hidden effect")
    parser.add_argument("--controls", default="1,2,3", help="fleets without (--conceal none); empty: none")
    parser.add_argument("--vehicles", type=int, default=9)
    parser.add_argument("--days", type=int, default=3)
    parser.add_argument("--drive-s", type=int, default=300)
    parser.add_argument("--gauge-sigma-mm", type=float, default=2e-5)
    parser.add_argument("--generator-preset", default="fast")
    parser.add_argument("--diagnosis-preset", default="fast")
    parser.add_argument("--max-terms", type=int, default=1, help="tread_wear_diagnose --max-terms")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--keep", metavar="DIR", help="write the fleets and outputs here and keep them")
    parser.add_argument("--bin", metavar="DIR")
    args = parser.parse_args()
    bin_dir = cli.find_bin_dir(args.bin)
    work = args.keep or tempfile.mkdtemp(prefix="fleet_diagnosis_study_")
    os.makedirs(work, exist_ok=True)
    cases = [(int(s), args.effect) for s in args.seeds.split(",") if s] + \
            [(int(s), "none") for s in args.controls.split(",") if s]
    print(f"load average before: {loadavg()}", flush=True)
    rows = []
    try:
        for seed, effect in cases:
            pool, vehicles, skipped, wall_s = one_fleet(work, seed, effect, args, bin_dir)
            named = sum(1 for v in vehicles if v.get("explanation") == effect)
            others = sorted({v.get("explanation", "failed") for v in vehicles} - {effect})
            rows.append((seed, effect, pool, named, len(vehicles), others, wall_s))
            print(f"seed {seed} hidden {effect}: fleet ({pool.get('segments')} segments) {describe(pool)}; "
                  f"vehicles naming it {named}/{len(vehicles)} (other verdicts: {', '.join(others) or '-'}); "
                  f"deviating: {sorted(v for v, d in pool.get('deviations', {}).items() if d['deviates']) or '-'}; "
                  f"skipped {len(skipped)}; {wall_s:.0f} s; load {loadavg()}", flush=True)
    finally:
        if not args.keep:
            shutil.rmtree(work, ignore_errors=True)
    print("\n| hidden effect | seed | fleet verdict (pooled) | vehicles naming the effect | vehicles' other verdicts |"
          " wall |\n|---|---|---|---|---|---|")
    for seed, effect, pool, named, n, others, wall_s in rows:
        print(f"| {effect} | {seed} | {describe(pool)} | {named}/{n} | {', '.join(others) or '-'} | {wall_s:.0f} s |")
    print(f"\nload average after: {loadavg()}")


if __name__ == "__main__":
    main()
