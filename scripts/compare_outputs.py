#!/usr/bin/python3
"""Compares two output directories written by `scripts/compare_outputs.sh run` (standard library only).

usage: compare_outputs.py DIR_A DIR_B

Every file in either directory is checked (a file present on one side only is a difference):
  *.json  same structure, keys and strings; numbers equal or within REL_TOL relative (|a-b| / max(|a|,|b|))
  *.csv   same rows and columns; cells that parse as numbers as above, other cells equal
  others  (txt, md, yaml, bag, ...) byte-identical
Prints one line per file (max relative difference for JSON/CSV), lists the files that differ and exits 1 if any.
"""
import csv
import filecmp
import json
import math
import os
import re
import sys

REL_TOL = 1e-12

# Skipped on purpose: the tools' console logs, which print wall and CPU times (tread_wear_replay's progress
# and speed lines) and the output directory's absolute path ("report: /abs/OUT/..."). Every result they
# print is also in a compared file.
SKIP_DIRS = {"logs"}

# Keys ignored in one file only: tread_wear_replay writes timings and the input bag's path (which contains
# OUT_DIR) into its summary (tread_wear_replay's main() and replaySummaryToJson).
# tread_wear_diagnose writes the wall time of each step and each solver-error check (`timings`, `numerics`).
DIAGNOSES = ("diagnose/polishing", "diagnose/polishing_bag", "diagnose/table3")
IGNORED_KEYS = {
    "main/wltc_summary.json": {"wall_time_s", "speedup", "bag_read_s", "compute_cpu_s", "input"},
    **{f"{d}/diagnosis.json": {"seconds", "total_seconds"} for d in DIAGNOSES},
}

# Text ignored in one file only, each pattern's match but its two groups blanked: tread_wear_diagnose --bag names
# the bag by the path it was given, which lies in OUT_DIR ("Recordings: `/abs/OUT/diagnose/polishing.bag` (36
# runs; ...)"); every report.md gives wall times: of a solver-error check ("... (0.157 s)") and of each step (the
# third column of "Time per step" and its total), not their brush evaluations.
WALL_TIMES = [
    re.compile(rb"(?m)(\()[0-9.e+-]+( s\)$)"),
    re.compile(rb"(?m)^(\| [^|\n]+ \| (?:fast|standard|fine|reference) \| )[0-9.e+-]+( \| [0-9]+ \|)$"),
    re.compile(rb"(?m)^(\| \*\*total\*\* \| \| \*\*)[0-9.e+-]+(\*\* \| \|)$"),
]
IGNORED_TEXT = {f"{d}/report.md": WALL_TIMES for d in DIAGNOSES}
IGNORED_TEXT["diagnose/polishing_bag/report.md"] = [re.compile(rb"(?m)^(Recordings: `)[^`]*(`)")] + WALL_TIMES


def rel_diff(a, b):
    if a == b or (math.isnan(a) and math.isnan(b)):
        return 0.0
    if math.isinf(a) or math.isinf(b) or math.isnan(a) or math.isnan(b):
        return math.inf
    return abs(a - b) / max(abs(a), abs(b))


def as_number(cell):
    try:
        return float(cell)
    except ValueError:
        return None


class Result:
    def __init__(self):
        self.max_rel = 0.0     # largest relative difference of two numbers
        self.beyond = 0        # numbers further apart than REL_TOL
        self.mismatch = []     # structural or non-numeric differences (first few kept)

    def number(self, a, b):
        d = rel_diff(a, b)
        self.max_rel = max(self.max_rel, d)
        self.beyond += d > REL_TOL

    def differ(self, where):
        self.mismatch.append(where)


def compare_json(a, b, res, ignored, where="$"):
    if isinstance(a, dict) and isinstance(b, dict):
        keys_a, keys_b = set(a) - ignored, set(b) - ignored
        for k in sorted(keys_a ^ keys_b):
            res.differ(f"{where}.{k}: key on one side only")
        for k in sorted(keys_a & keys_b):
            compare_json(a[k], b[k], res, ignored, f"{where}.{k}")
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            res.differ(f"{where}: {len(a)} vs {len(b)} items")
        for i, (x, y) in enumerate(zip(a, b)):
            compare_json(x, y, res, ignored, f"{where}[{i}]")
    elif (isinstance(a, (int, float)) and isinstance(b, (int, float))
          and not isinstance(a, bool) and not isinstance(b, bool)):
        res.number(float(a), float(b))
    elif a != b:
        res.differ(f"{where}: {a!r} vs {b!r}")


def compare_csv(path_a, path_b, res):
    with open(path_a, newline="") as fa, open(path_b, newline="") as fb:
        rows_a, rows_b = list(csv.reader(fa)), list(csv.reader(fb))
    if len(rows_a) != len(rows_b):
        res.differ(f"{len(rows_a)} vs {len(rows_b)} rows")
    for r, (ra, rb) in enumerate(zip(rows_a, rows_b), start=1):
        if len(ra) != len(rb):
            res.differ(f"line {r}: {len(ra)} vs {len(rb)} columns")
        for c, (x, y) in enumerate(zip(ra, rb), start=1):
            nx, ny = as_number(x), as_number(y)
            if nx is not None and ny is not None:
                res.number(nx, ny)
            elif x != y:
                res.differ(f"line {r} column {c}: {x!r} vs {y!r}")


def files(root):
    out = set()
    for d, subdirs, names in os.walk(root):
        rel = os.path.relpath(d, root)
        if rel == ".":
            subdirs[:] = [s for s in subdirs if s not in SKIP_DIRS]
        out.update(os.path.normpath(os.path.join(rel, n)) for n in names)
    return out


def main(argv):
    if len(argv) != 3 or not all(os.path.isdir(d) for d in argv[1:]):
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    dir_a, dir_b = argv[1], argv[2]
    fa, fb = files(dir_a), files(dir_b)
    differing = []
    for rel in sorted(fa | fb):
        if rel not in fa or rel not in fb:
            print(f"DIFF  {rel}: only in {dir_a if rel in fa else dir_b}")
            differing.append(rel)
            continue
        pa, pb = os.path.join(dir_a, rel), os.path.join(dir_b, rel)
        res = Result()
        if rel.endswith(".json"):
            with open(pa) as f1, open(pb) as f2:
                compare_json(json.load(f1), json.load(f2), res, IGNORED_KEYS.get(rel, set()))
            detail = f"max rel diff {res.max_rel:.3g}"
        elif rel.endswith(".csv"):
            compare_csv(pa, pb, res)
            detail = f"max rel diff {res.max_rel:.3g}"
        elif rel in IGNORED_TEXT:
            with open(pa, "rb") as f1, open(pb, "rb") as f2:
                blank = [f.read() for f in (f1, f2)]
            for pattern in IGNORED_TEXT[rel]:
                blank = [pattern.sub(rb"\1<ignored>\2", text) for text in blank]
            if blank[0] != blank[1]:
                res.differ("bytes differ")
            detail = "byte-identical but for the ignored paths and wall times" if not res.mismatch else ""
        else:
            if not filecmp.cmp(pa, pb, shallow=False):
                res.differ("bytes differ")
            detail = "byte-identical" if not res.mismatch else ""
        ok = res.beyond == 0 and not res.mismatch
        if res.beyond:
            detail += f", {res.beyond} numbers beyond {REL_TOL:g}"
        if res.mismatch:
            detail += (", " if detail else "") + "; ".join(res.mismatch[:3])
            if len(res.mismatch) > 3:
                detail += f"; ... ({len(res.mismatch)} differences)"
        print(f"{'ok  ' if ok else 'DIFF'}  {rel}: {detail}")
        if not ok:
            differing.append(rel)
    print(f"\n{len(fa | fb)} files compared, {len(differing)} differ")
    for rel in differing:
        print(f"  differs: {rel}")
    return 1 if differing else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
