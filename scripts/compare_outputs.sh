#!/usr/bin/env bash
# Proves that a refactor changes no result: run the package's tools from two builds, then compare every output.
#
#   scripts/compare_outputs.sh run BIN_DIR OUT_DIR    # from the repo root; BIN_DIR e.g. _build/devel/lib/tread_wear
#   scripts/compare_outputs.sh compare DIR_A DIR_B    # exit 1 if any file differs (scripts/compare_outputs.py)
#
# `run` reads config/, data/ and examples/ relative to the repo root, writes only into OUT_DIR (new or empty)
# and covers, in about 1.5 min on 2 cores (75-100 s measured):
#   main/       the main job, scripts/wltc_main_job.sh without its plots: tread_wear_drive writes the WLTC drive
#               bag, tread_wear_replay -> wltc_summary.json, wltc_timeseries.csv, wltc_wear.bag
#   eval/       tread_wear_eval on a grid of operating points (speed incl. the < 0.1 m/s low-speed convention,
#               slip angle, slip ratio, straight and curved path, load, tread temperature) for every preset and
#               every config/tires/*.yaml, plus a copy of grosch_wheel.yaml with the Eq 25 temperature factor on;
#               the reference preset (CVODE, ~0.1 s a row) on every third row only
#   diagnose/   tread_wear_diagnose on examples/diagnosis (its run table, and its rosbag made by make_bag.py)
#               and on data/paper/table3_runs.csv (docs/diagnosis.md), without plots
#   calibrate/  tread_wear_calibrate: scripts/reproduce_paper.sh's wear-law fit (wear_literal, with
#               cross-validation) and its 3-parameter mechanics fit in docs/calibration.md's quick form
#               (--no-cv --robust-se); JSON, fitted YAML and the printed report
#   extra/      tread_wear_compare (docs/table3.md), tread_wear_reference_models (Table 5),
#               tread_wear_wear_characteristics (Section 4.3 CSVs)
#   logs/       console output of the other tools (not compared: wall times, OUT_DIR's absolute path)
# `compare`: JSON/CSV numbers equal or within 1e-12 relative, every other file byte-identical; the keys that hold
# wall times or a path are ignored (IGNORED_KEYS, IGNORED_TEXT in compare_outputs.py).
set -euo pipefail
export PATH="/usr/bin:${PATH}"  # Debian's python3 (rosbag for make_bag.py), not pyenv's
export PYTHONDONTWRITEBYTECODE=1  # nothing written next to the build's python messages
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"

usage() { sed -n '4,5p' "${BASH_SOURCE[0]}" | sed 's/^# *//' >&2; exit 2; }
die() { echo "compare_outputs: $*" >&2; exit 1; }
step() { printf '[compare_outputs %4ds] %s\n' "${SECONDS}" "$*"; }

run_all() {
  [[ -f package.xml && -d config/tires && -d data/paper ]] || die "run it from the repository root"
  local bin out
  bin="$(realpath -e "$1")" || die "no BIN_DIR $1"
  mkdir -p "$2"
  out="$(realpath -e "$2")"
  [[ -z "$(ls -A "${out}")" ]] || die "OUT_DIR ${out} is not empty"
  local t
  for t in drive replay eval diagnose calibrate compare reference_models wear_characteristics; do
    [[ -x ${bin}/tread_wear_${t} ]] || die "${bin}/tread_wear_${t} was not built"
  done
  mkdir -p "${out}"/{main,eval/tires,diagnose,calibrate,extra/reference_models,extra/wear_characteristics,logs}
  # tool NAME STDOUT_FILE ARGS...: runs BIN_DIR/tread_wear_NAME; stderr goes to logs/NAME.stderr
  tool() {
    local name=$1 stdout=$2
    shift 2
    "${bin}/tread_wear_${name}" "$@" >"${stdout}" 2>>"${out}/logs/${name}.stderr" ||
      die "tread_wear_${name} failed (exit $?): see ${out}/logs/${name}.stderr"
  }

  step "1. main job: WLTC drive and replay (scripts/wltc_main_job.sh, no plots)"
  tool drive "${out}/logs/drive.log" --profile data/wltc_class3b.csv --vehicle config/vehicle_passenger_car.yaml \
    --rate-hz 50 --out "${out}/main/wltc_drive.bag"
  tool replay "${out}/logs/replay.log" "${out}/main/wltc_drive.bag" --wheels config/vehicle_wheels.yaml \
    --rate-hz 50 --out-rate-hz 10 --out "${out}/main/wltc_wear.bag" --summary "${out}/main/wltc_summary.json" \
    --timeseries "${out}/main/wltc_timeseries.csv" --quiet

  step "2. tread_wear_eval: every preset x every tire file"
  # Operating grids (ISO axes): the rig's for the Grosch wheel files (docs/table3.md: 1-3 m/s, 5-15 deg,
  # 50-150 N, R = 60 mm) and a road's for the road tires (passenger, SUV; docs/drive.md). The tread temperature cycles through
  # unknown, 25 and 90 degC; it acts only with temperature_enabled (eval/tires/grosch_wheel_thermal.yaml).
  grid() {  # grid SPEEDS SLIP_ANGLES SLIP_RATIOS PATH_RADII LOADS
    local i=0 temps=("" 25 90) v a k r f
    echo "speed_mps,slip_angle_rad,slip_ratio,path_radius_m,load_n,tread_temperature_c"
    for v in $1; do for a in $2; do for k in $3; do for r in $4; do for f in $5; do
      echo "${v},${a},${k},${r},${f},${temps[i++ % 3]}"
    done; done; done; done; done
  }
  grid "0.05 1 3" "0 -0.0872664626 -0.2617993878 0.1745329252" "0 -0.05 0.1" "0 0.06" "50 100 150" \
    >"${out}/eval/conditions_rig.csv"
  grid "0.05 5 30" "0 0.02 -0.06 0.15" "0 -0.03 0.08" "0 -50" "1500 4000 7000" >"${out}/eval/conditions_road.csv"
  local c
  for c in rig road; do  # header and every third row: 72 of 216 conditions
    awk 'NR == 1 || NR % 3 == 2' "${out}/eval/conditions_${c}.csv" >"${out}/eval/conditions_${c}_reference.csv"
  done
  sed 's/^\(  temperature_enabled:\) false/\1 true/' config/tires/grosch_wheel.yaml \
    >"${out}/eval/tires/grosch_wheel_thermal.yaml"
  grep -q '^  temperature_enabled: true' "${out}/eval/tires/grosch_wheel_thermal.yaml" ||
    die "cannot switch temperature_enabled on in a copy of config/tires/grosch_wheel.yaml"
  local tire name grid preset conditions
  for tire in config/tires/*.yaml "${out}/eval/tires/grosch_wheel_thermal.yaml"; do
    name="$(basename "${tire}" .yaml)"
    case "${name}" in passenger* | suv*) grid=road ;; *) grid=rig ;; esac
    for preset in fast standard fine reference; do
      conditions="${out}/eval/conditions_${grid}.csv"
      [[ ${preset} == reference ]] && conditions="${out}/eval/conditions_${grid}_reference.csv"
      tool eval "${out}/eval/${name}_${preset}.csv" --params "${tire}" --preset "${preset}" "${conditions}"
    done
  done

  step "3. tread_wear_diagnose: examples/diagnosis (run table and rosbag) and Table 3"
  tool diagnose "${out}/logs/diagnose_polishing.log" --params config/tires/grosch_wheel.yaml \
    --runs examples/diagnosis/polishing_runs.csv --report "${out}/diagnose/polishing" --no-plots
  tool diagnose "${out}/logs/diagnose_table3.log" --params config/tires/grosch_wheel.yaml \
    --runs data/paper/table3_runs.csv --report "${out}/diagnose/table3" --no-plots
  # The example as a rosbag (examples/diagnosis/README.md) needs the build's python messages (devel/lib/python3).
  local py="${bin}/../python3/dist-packages"
  [[ -d ${py}/tread_wear ]] || die "no python messages in ${py} (expected next to BIN_DIR in the devel space)"
  PYTHONPATH="${py}${PYTHONPATH:+:${PYTHONPATH}}" /usr/bin/python3 examples/diagnosis/make_bag.py \
    examples/diagnosis/polishing_runs.csv "${out}/diagnose/polishing.bag" >"${out}/logs/make_bag.log" 2>&1 ||
    die "examples/diagnosis/make_bag.py failed: see ${out}/logs/make_bag.log"
  tool diagnose "${out}/logs/diagnose_polishing_bag.log" --params config/tires/grosch_wheel.yaml \
    --bag "${out}/diagnose/polishing.bag" --report "${out}/diagnose/polishing_bag" --no-plots

  step "4. tread_wear_calibrate: wear law (with cross-validation), mechanics (quick form)"
  tool calibrate "${out}/calibrate/wear_literal.txt" --params config/tires/grosch_wheel.yaml \
    --runs data/paper/table3_runs.csv --grid 200,16 --fit w1,w2,w3,w4 --orientation literal \
    --json "${out}/calibrate/wear_literal.json" --out-params "${out}/calibrate/wear_literal.yaml"
  tool calibrate "${out}/calibrate/fy3_literal_quick.txt" --params config/tires/grosch_wheel.yaml \
    --runs data/paper/table3_runs.csv --grid 200,16 --fit k_y0,k_y1,c_y --target side_force \
    --orientation literal --no-cv --robust-se --json "${out}/calibrate/fy3_literal_quick.json" \
    --out-params "${out}/calibrate/fy3_literal_quick.yaml"

  step "5. tread_wear_compare, tread_wear_reference_models, tread_wear_wear_characteristics"
  tool compare "${out}/extra/table3_compare.txt" --params config/tires/grosch_wheel.yaml \
    --runs data/paper/table3_runs.csv --orientation both --preset reference --csv "${out}/extra/table3_compare.csv"
  tool reference_models "${out}/logs/reference_models.log" --params config/tires/grosch_wheel.yaml \
    --runs data/paper/table3_runs.csv --grid 200,16 --out-dir "${out}/extra/reference_models"
  tool wear_characteristics "${out}/logs/wear_characteristics.log" \
    --params config/tires/grosch_wheel_calibrated.yaml --out-dir "${out}/extra/wear_characteristics"
  step "done: $(find "${out}" -type f -not -path "${out}/logs/*" | wc -l) output files in ${out}"
}

case "${1:-}" in
  run) [[ $# -eq 3 ]] || usage; run_all "$2" "$3" ;;
  compare) [[ $# -eq 3 ]] || usage; exec /usr/bin/python3 "${here}/compare_outputs.py" "$2" "$3" ;;
  *) usage ;;
esac
