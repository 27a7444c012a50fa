#!/usr/bin/python3
"""Scaling of tread_wear_fleet on the synthetic fleet (docs/fleet.md, "Measured"): one local Dask worker against
two, and the engine's overhead at one worker against the same bags replayed serially in this process.

  bench/fleet_scaling.py [--fleet DIR] [--vehicles 8] [--days 3] [--drive-s 600] [--repeat 2] [--bin DIR]

Without --fleet it generates the fleet into a temporary directory (tread_wear_fleet_generate, no readings). Each
run writes to a fresh output directory (no cache). Prints wall times, bags and drive seconds per wall second, the
2-worker speed-up and the engine's overhead at one worker (wall time against serial, and the CPU of this process
itself, whose replays are child processes), with the load average before and after.
"""
import argparse
import os
import shutil
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))

from tread_wear_fleet import cli, generate  # noqa: E402


def timed_run(fleet, work, name, bin_dir, **engine):
    out = os.path.join(work, name)
    shutil.rmtree(out, ignore_errors=True)
    start, before = time.monotonic(), os.times()
    document = cli.run_fleet(fleet, out, bin_dir=bin_dir, plots=False, progress=False, **engine)
    wall_s, after = time.monotonic() - start, os.times()
    if document["run"]["replayed"] != document["run"]["bags"]:
        raise RuntimeError(f"{name}: {document['run']}")
    # CPU of this process alone (the engine and the reductions; the replays are child processes): load-independent.
    document["run"]["own_cpu_s"] = (after.user + after.system) - (before.user + before.system)
    return wall_s, document


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--fleet", help="an existing fleet directory [default: generate one]")
    parser.add_argument("--vehicles", type=int, default=8)
    parser.add_argument("--days", type=int, default=3)
    parser.add_argument("--drive-s", type=int, default=600)
    parser.add_argument("--repeat", type=int, default=2, help="runs of each configuration; the best counts")
    parser.add_argument("--bin", help="directory of the package's tools")
    args = parser.parse_args()
    bin_dir = cli.find_bin_dir(args.bin)
    source = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    work = tempfile.mkdtemp(prefix="fleet_bench_")
    try:
        fleet = args.fleet
        if fleet is None:
            fleet = os.path.join(work, "fleet")
            generate.generate(fleet, source, bin_dir, vehicles=args.vehicles, days=args.days, drive_s=args.drive_s,
                              jobs=2, readings=False)
        start = time.monotonic()
        import distributed  # noqa: F401  (its import, once per command, is reported apart from the runs)
        print(f"import of Dask distributed: {time.monotonic() - start:.2f} s (once per command)")
        print(f"load average before: {open('/proc/loadavg').read().split()[:3]}")
        best = {}
        for _ in range(args.repeat):
            for name, engine in (("serial", {"serial": True}), ("1 worker", {"workers": 1}),
                                 ("2 workers", {"workers": 2})):
                wall_s, document = timed_run(fleet, work, name.replace(" ", "_"), bin_dir, **engine)
                if name not in best or wall_s < best[name][0]:
                    best[name] = (wall_s, document)
        bags = best["serial"][1]["run"]["bags"]
        durations = sum(v["drive_time_s"] for v in best["serial"][1]["vehicles"])
        for name, (wall_s, document) in best.items():
            print(f"{name:10s} {wall_s:7.2f} s wall  {bags / wall_s:6.2f} bags/s  {durations / wall_s:7.0f}x real "
                  f"time  (replay CPU {document['run']['replay_cpu_s']:.1f} s, this process "
                  f"{document['run']['own_cpu_s']:.2f} CPU s)")
        speedup = best["1 worker"][0] / best["2 workers"][0]
        overhead = best["1 worker"][0] / best["serial"][0] - 1.0
        engine_cpu = best["1 worker"][1]["run"]["own_cpu_s"] - best["serial"][1]["run"]["own_cpu_s"]
        engine_share = engine_cpu / best["serial"][1]["run"]["replay_cpu_s"]
        print(f"2 workers / 1 worker: {speedup:.2f}x; overhead of the engine at 1 worker: {100 * overhead:.1f} % of "
              f"the wall time, {engine_cpu:.2f} CPU s = {100 * engine_share:.1f} % of the replays' CPU "
              f"({bags} bags, {durations:.0f} s of driving)")
        print(f"load average after: {open('/proc/loadavg').read().split()[:3]}")
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
