#!/usr/bin/env bash
# Replay throughput per core (docs/fleet.md, "Replay speed"): tread_wear_replay on one bag with one thread, RUNS
# times; prints each run's CPU seconds (user + sys of the whole process: bag read, replay, summary) and drive
# seconds per CPU second, with the load average before and after.
#
#   bench/replay_throughput.sh BAG [RUNS=3] [BIN_DIR=_build/devel/lib/tread_wear] [extra replay args, e.g. --rate-hz 50]
set -euo pipefail
bag=${1:?usage: bench/replay_throughput.sh BAG [RUNS] [BIN_DIR] [replay args]}
runs=${2:-3}
bin=${3:-_build/devel/lib/tread_wear}
shift $(($# < 3 ? $# : 3))
summary=$(mktemp --suffix=.json)
trap 'rm -f "${summary}"' EXIT
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
for ((i = 1; i <= runs; ++i)); do
  cpu=$( { /usr/bin/time -f "%U %S" "${bin}/tread_wear_replay" "${bag}" --threads 1 --quiet --summary "${summary}" \
           "$@" >/dev/null; } 2>&1 | tail -1)
  /usr/bin/python3 - "${summary}" ${cpu} <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
cpu = float(sys.argv[2]) + float(sys.argv[3])
print(f"{s['duration_s']:.0f} s of driving: {cpu:.2f} CPU s in all ({s['duration_s'] / cpu:.0f}x real time per core), "
      f"bag read {s['bag_read_s']:.2f} s wall, replay {s['compute_cpu_s']:.2f} CPU s, {s['update_rate_hz']:g} Hz, "
      f"preset {s['preset']}")
PY
done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
