#!/usr/bin/python3
"""The LEON-T measured tests as input of tread_wear_diagnose (docs/leon_t_diagnosis.md).

Usage: scripts/leon_t_diagnosis_input.py --out DIR [--programme DIR] [--measurements CSV] [--sets B/S,...]
                                         [--vehicle YAML] [--rate-hz 10] [--check-only]

For each tyre brand and scenario of the measurements (a "set": LingLong/Standard, LingLong/High load, ...) one drive
bag DIR/<brand>_<scenario>.bag, and DIR/all.bag with every set one after the other: the four tests (Run-in, Rural,
Motorway, Urban) in that order, each made of its test sections (test_sections.csv, AbrasionTest), each section a
drive of tread_wear_drive --programme at the scenario's mass (vehicle.csv). Laps per section: the programme's laps
over the fewest of its test, rounded half to even, at least 1 (Run-in 1, Rural 1/2/2, Motorway 1, Urban 3/1/5/6), so
the sections keep about the programme's distance shares within a test (the laps of a section are alike).

Mass checkpoints (wheels/<w>/measured/mass, std_msgs/Float64, kg) per wheel at the start and after each test. The
per-km equivalence: the loss of wheel w over test t is the measured mean abrasion of w in t over the repeats
(abrasion_per_wheel.csv, mg/km) times the distance w rolled in the drive's test t (its speed integrated with the
trapezoid rule). So tread_wear_diagnose's measured wear rate (loss / integrated distance) is the measured mg/km.
Masses are a running total from 10 kg per wheel (a new set continues from the last, as only differences are read).
Recorded covariates (measured/covariate, std_msgs/String "name=value", diagnosis_bag.h): test, brand, scenario and
set, from the checkpoint that starts each test; the reader adds wheel.

Errors (exit 1, naming the file, line and column): missing or extra columns, a value that is not a positive finite
number, a set without the four tests on each of the four wheels, an unknown scenario. --check-only stops after
reading and prints the plan.
"""
import argparse
import csv
import math
import os
import subprocess
import sys
from collections import defaultdict

from leon_t_validation import read_csv, scenario_masses  # one reader of the programme's tables

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.environ.get("TREAD_WEAR_BIN", os.path.join(REPO, "_build", "devel", "lib", "tread_wear"))
WHEELS = {"FL": "front_left", "FR": "front_right", "RL": "rear_left", "RR": "rear_right"}
TESTS = ["Run-in", "Rural", "Motorway", "Urban"]
COLUMNS = ["tyre_brand", "scenario", "wheel", "test", "repeat", "abrasion_mg_per_km"]
START_MASS_KG = 10.0
GAP_S = 5.0  # between sections: no input (the segmenter skips it); checkpoints in the middle of a gap


def fail(message):
    sys.exit("leon_t_diagnosis_input: " + message)


def read_measurements(path):
    """{(brand, scenario): {(wheel, test): mean mg/km}}, every set complete."""
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader, None)
        if header != COLUMNS:
            fail("%s: line 1: columns %s, expected %s" % (path, ",".join(header or []), ",".join(COLUMNS)))
        values = defaultdict(list)
        for line, row in enumerate(reader, start=2):
            if len(row) != len(COLUMNS):
                fail("%s: line %d: %d fields, expected %d" % (path, line, len(row), len(COLUMNS)))
            brand, scenario, wheel, test, _, value = row
            if wheel not in WHEELS:
                fail("%s: line %d: column wheel: '%s' is not one of %s" % (path, line, wheel, "/".join(WHEELS)))
            if test not in TESTS:
                fail("%s: line %d: column test: '%s' is not one of %s" % (path, line, test, "/".join(TESTS)))
            try:
                x = float(value)
            except ValueError:
                x = float("nan")
            if not (math.isfinite(x) and x > 0):
                fail("%s: line %d: column abrasion_mg_per_km: '%s' must be a positive finite number" %
                     (path, line, value))
            values[(brand, scenario, wheel, test)].append(x)
    sets = defaultdict(dict)
    for (brand, scenario, wheel, test), xs in values.items():
        sets[(brand, scenario)][(wheel, test)] = sum(xs) / len(xs)
    if not sets:
        fail(path + ": no measurements")
    for key, means in sorted(sets.items()):
        missing = ["%s %s" % (w, t) for t in TESTS for w in WHEELS if (w, t) not in means]
        if missing:
            fail("%s: %s/%s has no runs for %s: every set needs the four tests on the four wheels" %
                 (path, key[0], key[1], ", ".join(missing)))
    return sets


def plan_sections(programme):
    """{test: [(section, laps)]}: laps proportional to the programme's, the fewest at 1 (round half to even)."""
    rows = read_csv(os.path.join(programme, "test_sections.csv"))
    plan = {}
    for test in TESTS:
        sections = [(r["Test section"], int(r["Number of laps"])) for r in rows if r["AbrasionTest"] == test]
        if not sections:
            fail("%s/test_sections.csv: no section of test %s" % (programme, test))
        fewest = min(n for _, n in sections)
        plan[test] = [(s, max(1, round(n / fewest))) for s, n in sections]
    return plan


def section_bag(args, section, laps, mass, cache):
    path = os.path.join(cache, "%s_%d_%d.bag" % (section, laps, round(mass)))
    if not os.path.exists(path):
        cmd = [os.path.join(BIN, "tread_wear_drive"), "--programme", args.programme, "--section", section,
               "--laps", str(laps), "--vehicle", args.vehicle, "--mass-kg", repr(mass), "--rate-hz",
               repr(args.rate_hz), "--out", path + ".tmp"]
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            fail("%s failed: %s" % (" ".join(cmd), r.stderr.strip()))
        os.replace(path + ".tmp", path)
    return path


def read_section(path):
    """[(t, topic, msg)] of the wheels' input topics, sorted; and per wheel the trapezoid distance [m]."""
    import rosbag
    out, speeds = [], defaultdict(list)
    with rosbag.Bag(path) as bag:
        for topic, msg, t in bag.read_messages():
            parts = topic.strip("/").split("/")
            if len(parts) == 3 and parts[0] == "wheels" and parts[2] in ("load", "slip", "speed"):
                out.append((t.to_sec(), topic, msg))
                if parts[2] == "speed":
                    speeds[parts[1]].append((t.to_sec(), msg.speed_mps))
    distance = {w: sum(0.5 * (a[1] + b[1]) * (b[0] - a[0]) for a, b in zip(s, s[1:])) for w, s in speeds.items()}
    return out, distance


class Writer:
    """One output bag: sections appended in time, checkpoints and covariates between them."""

    def __init__(self, path):
        import rosbag
        self.bag = rosbag.Bag(path, "w")
        self.t = 1000.0  # bag time of the next section's start
        self.mass = {w: START_MASS_KG for w in WHEELS.values()}

    def section(self, messages):
        import rospy
        t0 = messages[0][0]
        for t, topic, msg in messages:
            stamp = rospy.Time.from_sec(self.t + (t - t0))
            msg.header.stamp = stamp
            self.bag.write(topic, msg, stamp)
        self.t += messages[-1][0] - t0 + GAP_S

    def checkpoint(self, losses_kg, covariates, masses=True):
        import rospy
        from std_msgs.msg import Float64, String
        stamp = rospy.Time.from_sec(self.t - 0.5 * GAP_S)
        for w in self.mass if masses else []:
            self.mass[w] -= losses_kg.get(w, 0.0)
            self.bag.write("/wheels/%s/measured/mass" % w, Float64(self.mass[w]), stamp)
        for name, value in covariates:
            self.bag.write("/measured/covariate", String("%s=%s" % (name, value)), stamp)

    def close(self):
        self.bag.close()


def write_set(writers, key, means, plan, sections, continues):
    """continues[i]: writer i already has a checkpoint where this set starts (the last set's final one)."""
    brand, scenario = key
    test_labels = lambda test: [("test", test), ("brand", brand), ("scenario", scenario),
                                ("set", "%s/%s" % (brand, scenario))]
    for w, c in zip(writers, continues):
        w.checkpoint({}, test_labels(TESTS[0]), masses=not c)
    for k, test in enumerate(TESTS):
        distance = defaultdict(float)
        for section, laps in plan[test]:
            messages, dist = sections[(section, laps)]
            for w in writers:
                w.section(messages)
            for wheel, d in dist.items():
                distance[wheel] += d
        losses = {WHEELS[c]: means[(c, test)] * 1e-6 * distance[WHEELS[c]] / 1000.0 for c in WHEELS}
        following = test_labels(TESTS[k + 1]) if k + 1 < len(TESTS) else []
        for w in writers:
            w.checkpoint(losses, following)
        print("  %s/%s %-8s %7.2f km  mg/km FL %.1f FR %.1f RL %.1f RR %.1f" %
              (brand, scenario, test, distance["front_left"] / 1000.0, means[("FL", test)], means[("FR", test)],
               means[("RL", test)], means[("RR", test)]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", required=True)
    ap.add_argument("--programme", default=os.path.join(REPO, "data", "leon_t_idiada"))
    ap.add_argument("--measurements", default=None, help="default: PROGRAMME/abrasion_per_wheel.csv")
    ap.add_argument("--sets", default="", help="brand/scenario,... (default: every set of the measurements)")
    ap.add_argument("--vehicle", default=os.path.join(REPO, "config", "vehicle_ford_kuga.yaml"))
    ap.add_argument("--rate-hz", type=float, default=10.0)
    ap.add_argument("--check-only", action="store_true")
    args = ap.parse_args()
    if not args.rate_hz > 0:
        fail("--rate-hz must be > 0")
    measurements = args.measurements or os.path.join(args.programme, "abrasion_per_wheel.csv")
    sets = read_measurements(measurements)
    if args.sets:
        wanted = [tuple(s.split("/", 1)) for s in args.sets.split(",")]
        for s in wanted:
            if s not in sets:
                fail("--sets: '%s' has no measurements in %s" % ("/".join(s), measurements))
        sets = {s: sets[s] for s in wanted}
    masses = scenario_masses(args.programme)
    for brand, scenario in sets:
        if scenario not in masses:
            fail("scenario '%s' has no mass in %s/vehicle.csv" % (scenario, args.programme))
    plan = plan_sections(args.programme)
    for test in TESTS:
        print("%-8s %s" % (test, ", ".join("%s x%d" % sl for sl in plan[test])))
    if args.check_only:
        print("sets: " + ", ".join("%s/%s" % s for s in sorted(sets)))
        return
    os.makedirs(os.path.join(args.out, "sections"), exist_ok=True)
    combined = Writer(os.path.join(args.out, "all.bag"))
    for n, key in enumerate(sorted(sets)):
        mass = masses[key[1]]
        sections = {sl: read_section(section_bag(args, sl[0], sl[1], mass, os.path.join(args.out, "sections")))
                    for test in TESTS for sl in plan[test]}
        own = Writer(os.path.join(args.out, "%s_%s.bag" % (key[0], key[1].replace(" ", "_"))))
        # In all.bag a set starts where the last ended: its first checkpoint is the last set's final one.
        write_set([own, combined], key, sets[key], plan, sections, [False, n > 0])
        own.close()
    combined.close()
    print("wrote %s/all.bag and one bag per set" % args.out)


if __name__ == "__main__":
    main()
