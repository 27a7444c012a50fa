#!/usr/bin/env bash
# Instructions per evaluation inside BrushWearModel::evaluate (callgrind; independent of the machine's load), per
# preset, on the two grids of scripts/compare_outputs.sh (rig: grosch_wheel.yaml, road: passenger_205_55_r16.yaml).
#
#   bench/eval_instructions.sh BIN_DIR CONDITIONS_DIR    # from the repo root; CONDITIONS_DIR = OUT_DIR/eval of
#                                                        # `scripts/compare_outputs.sh run` (conditions_{rig,road}.csv)
# Prints one markdown row per preset: instructions per evaluation on the rig and the road grid.
set -euo pipefail
[[ $# -eq 2 ]] || { sed -n 5,6p "${BASH_SOURCE[0]}" | sed 's/^# *//' >&2; exit 2; }
bin="$(realpath -e "$1")"
conditions="$(realpath -e "$2")"
work="$(mktemp -d)"
trap 'rm -rf "${work}"' EXIT
# per_eval GRID TIRE PRESET: instructions collected inside evaluate, over the grid's rows
per_eval() {
  local rows
  rows=$(($(wc -l <"${conditions}/conditions_$1.csv") - 1))
  valgrind --tool=callgrind --callgrind-out-file="${work}/cg.out" --toggle-collect='*BrushWearModel::evaluate*' \
    "${bin}/tread_wear_eval" --params "$2" --preset "$3" "${conditions}/conditions_$1.csv" >/dev/null 2>"${work}/log" ||
    { cat "${work}/log" >&2; exit 1; }
  awk -v n="${rows}" '/^summary:/ { printf "%.0f", $2 / n }' "${work}/cg.out"
}
echo "| preset | rig [instructions/eval] | road [instructions/eval] |"
echo "|---|---|---|"
for preset in fast standard fine; do
  echo "| ${preset} | $(per_eval rig config/tires/grosch_wheel.yaml "${preset}") |" \
    "$(per_eval road config/tires/passenger_205_55_r16.yaml "${preset}") |"
done
