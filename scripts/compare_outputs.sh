#!/usr/bin/env bash
# Proves that a refactor changes no result: run the package's tools from two builds, then compare every output.
#
#   scripts/compare_outputs.sh run BIN_DIR OUT_DIR    # from the repo root; BIN_DIR e.g. _build/devel/lib/tread_wear
#   scripts/compare_outputs.sh compare DIR_A DIR_B    # exit 1 if any file differs (scripts/compare_outputs.py)
#
# `run` writes only into OUT_DIR (new or empty; the tools read config/, data/, examples/ relative to the repo
# root) and covers (about 2-3 min on 2 cores):
#   main/       the main job (scripts/wltc_main_job.sh without plots): tread_wear_drive WLTC bag, then
#               tread_wear_replay -> wltc_summary.json, wltc_timeseries.csv, and both bags
#   eval/       tread_wear_eval on a grid of operating points (speed incl. the low-speed convention, slip angle,
#               slip ratio, straight/curved path, load, tread temperature) for every preset and every
#               config/tires/*.yaml, plus grosch_wheel with the Eq 25 temperature factor switched on
#   diagnose/   tread_wear_diagnose on examples/diagnosis (run table and, with the build's python messages,
#               its rosbag) and on data/paper/table3_runs.csv (docs/diagnosis.md), without plots
#   calibrate/  tread_wear_calibrate: the wear-law fit of scripts/reproduce_paper.sh (wear_literal) and the
#               3-parameter mechanics fit without cross-validation (docs/calibration.md, --robust-se run)
#   extra/      tread_wear_compare (docs/table3.md), tread_wear_reference_models (Table 5),
#               tread_wear_wear_characteristics (Section 4.3 CSVs)
#   logs/       console output of every tool (not compared: wall times, absolute paths)
# `compare`: JSON/CSV numbers equal or within 1e-12 relative, every other file byte-identical; the few keys
# that hold wall times or paths are ignored (listed in compare_outputs.py).
set -euo pipefail
export PATH="/usr/bin:${PATH}"  # Debian's python3 (rosbag messages for make_bag.py), not pyenv's
export PYTHONDONTWRITEBYTECODE=1
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
  for t in drive replay eval diagnose calibrate compare reference_models wear_characteristics; do
    [[ -x ${bin}/tread_wear_${t} ]] || die "${bin}/tread_wear_${t} was not built"
  done
  mkdir -p "${out}"/{main,eval/tires,diagnose,calibrate,extra,logs}
  # tool NAME ARGS...: runs BIN_DIR/tread_wear_NAME, console output to logs/<log>.log ($log, default NAME)
  tool() { local t=$1; shift; "${bin}/tread_wear_${t}" "$@" >"${out}/logs/${log:-$t}.log" 2>&1 ||
           die "tread_wear_${t} failed (exit $?), see ${out}/logs/${log:-$t}.log"; }

  step "1. main job: WLTC drive and replay (scripts/wltc_main_job.sh, no plots)"
  log=drive tool drive --profile data/wltc_class3b.csv --vehicle config/vehicle_passenger_car.yaml \
    --rate-hz 50 --out "${out}/main/wltc_drive.bag"
  log=replay tool replay "${out}/main/wltc_drive.bag" --wheels config/vehicle_wheels.yaml --rate-hz 50 \
    --out-rate-hz 10 --out "${out}/main/wltc_wear.bag" --summary "${out}/main/wltc_summary.json" \
    --timeseries "${out}/main/wltc_timeseries.csv" --quiet

  step "2. tread_wear_eval: every preset x every tire file"
  # Operating grids (round numbers, ISO axes): the rig's (Grosch wheel, docs/table3.md) and a road's
  # (passenger tire, docs/drive.md). 0.05 m/s is below the 0.1 m/s low-speed floor; the temperature cycles
  # through unknown, cold and hot (it acts only with temperature_enabled, see eval/tires/).
  grid() {  # grid SPEEDS ALPHAS KAPPAS RADII LOADS
    local i=0 temps=("" 25 90) v a k r f
    echo "speed_mps,slip_angle_rad,slip_ratio,path_radius_m,load_n,tread_temperature_c"
    for v in $1; do for a in $2; do for k in $3; do for r in $4; do for f in $5; do
      echo "${v},${a},${k},${r},${f},${temps[i++ % 3]}"
    done; done; done; done; done
  }
  grid "0.05 1 3" "0 -0.0872664626 -0.2617993878 0.1745329252" "0 -0.05 0.1" "0 0.06" "50 100 150" \
    >"${out}/eval/conditions_rig.csv"
  grid "0.05 5 30" "0 0.02 -0.06 0.15" "0 -0.03 0.08" "0 50" "1500 4000 7000" >"${out}/eval/conditions_road.csv"
  sed 's/^\(  temperature_enabled:\) false/\1 true/' config/tires/grosch_wheel.yaml \
    >"${out}/eval/tires/grosch_wheel_thermal.yaml"
  grep -q '^  temperature_enabled: true' "${out}/eval/tires/grosch_wheel_thermal.yaml" ||
    die "cannot switch on temperature_enabled in a copy of config/tires/grosch_wheel.yaml"
  local tire name conditions preset
  for tire in config/tires/*.yaml "${out}/eval/tires/grosch_wheel_thermal.yaml"; do
    name="$(basename "${tire}" .yaml)"
    case "${name}" in passenger*) conditions=road ;; *) conditions=rig ;; esac
    for preset in fast standard fine reference; do
      "${bin}/tread_wear_eval" --params "${tire}" --preset "${preset}" "${out}/eval/conditions_${conditions}.csv" \
        >"${out}/eval/${name}_${preset}.csv" 2>>"${out}/logs/eval.log" || die "tread_wear_eval ${name} ${preset} failed"
    done
  done

  step "3. tread_wear_diagnose: examples/diagnosis and Table 3"
  log=diagnose_polishing tool diagnose --params config/tires/grosch_wheel.yaml \
    --runs examples/diagnosis/polishing_runs.csv --report "${out}/diagnose/polishing" --no-plots
  log=diagnose_table3 tool diagnose --params config/tires/grosch_wheel.yaml --runs data/paper/table3_runs.csv \
    --report "${out}/diagnose/table3" --no-plots
  # The example as a rosbag (examples/diagnosis/README.md) needs the build's python messages.
  local py="${bin}/../../lib/python3/dist-packages"
  if [[ -d ${py}/tread_wear ]]; then
    PYTHONPATH="${py}${PYTHONPATH:+:${PYTHONPATH}}" /usr/bin/python3 examples/diagnosis/make_bag.py \
      examples/diagnosis/polishing_runs.csv "${out}/diagnose/polishing.bag" >"${out}/logs/make_bag.log" 2>&1 ||
      die "make_bag.py failed, see ${out}/logs/make_bag.log"
    log=diagnose_polishing_bag tool diagnose --params config/tires/grosch_wheel.yaml \
      --bag "${out}/diagnose/polishing.bag" --report "${out}/diagnose/polishing_bag" --no-plots
  else
    step "   no ${py}/tread_wear: rosbag variant skipped"
  fi

  step "4. tread_wear_calibrate (scripts/reproduce_paper.sh's wear_literal; mechanics without CV)"
  log=calibrate_wear_literal tool calibrate --params config/tires/grosch_wheel.yaml \
    --runs data/paper/table3_runs.csv --grid 200,16 --fit w1,w2,w3,w4 --orientation literal \
    --json "${out}/calibrate/wear_literal.json" --out-params "${out}/calibrate/wear_literal.yaml"
  log=calibrate_fy3_literal tool calibrate --params config/tires/grosch_wheel.yaml \
    --runs data/paper/table3_runs.csv --grid 200,16 --fit k_y0,k_y1,c_y --target side_force \
    --orientation literal --no-cv --robust-se --json "${out}/calibrate/fy3_literal_no_cv.json" \
    --out-params "${out}/calibrate/fy3_literal_no_cv.yaml"

  step "5. tread_wear_compare, tread_wear_reference_models, tread_wear_wear_characteristics"
  "${bin}/tread_wear_compare" --params config/tires/grosch_wheel.yaml --runs data/paper/table3_runs.csv \
    --orientation both --preset reference --csv "${out}/extra/table3_compare.csv" \
    >"${out}/extra/table3_compare.txt" 2>"${out}/logs/compare.log" || die "tread_wear_compare failed"
  log=reference_models tool reference_models --params config/tires/grosch_wheel.yaml \
    --runs data/paper/table3_runs.csv --grid 200,16 --out-dir "${out}/extra/reference_models"
  log=wear_characteristics tool wear_characteristics --params config/tires/grosch_wheel_calibrated.yaml \
    --out-dir "${out}/extra/wear_characteristics"
  step "done: $(find "${out}" -type f -not -path '*/logs/*' | wc -l) output files in ${out}"
}

case "${1:-}" in
  run) [[ $# -eq 3 ]] || usage; run_all "$2" "$3" ;;
  compare) [[ $# -eq 3 ]] || usage; exec /usr/bin/python3 "${here}/compare_outputs.py" "$2" "$3" ;;
  *) usage ;;
esac
