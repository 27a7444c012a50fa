#!/usr/bin/env bash
# The main job on real-looking data: a compact car drives the WLTC class 3b cycle; per-wheel tread wear.
# Run after the set-up of scripts/main_job.sh (build in _build). Steps: generate the drive bag (tread_wear_drive),
# replay it offline through the node's estimator (tread_wear_replay), print the per-wheel table and write plots.
# Usage: scripts/wltc_main_job.sh [OUT_DIR] [extra tread_wear_replay arguments, e.g. --preset fast]
# Outputs in OUT_DIR (default out/): wltc_drive.bag, wltc_wear.bag, wltc_summary.json, wltc_timeseries.csv,
# wltc_speed.png, wltc_wear_rate.png, wltc_cumulative_loss.png. Model and numbers: docs/drive.md.
set -euo pipefail
repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "${repo_root}"
export PATH="/usr/bin:${PATH}"
bin="${TREAD_WEAR_BIN:-_build/devel/lib/tread_wear}"
out_dir="${1:-out}"
[[ $# -gt 0 ]] && shift
mkdir -p "${out_dir}"

for tool in tread_wear_drive tread_wear_replay; do
  [[ -x ${bin}/${tool} ]] || { echo "[wltc] ERROR: ${bin}/${tool} was not built" >&2; exit 1; }
done

drive="${out_dir}/wltc_drive.bag"
echo "[wltc] generating the WLTC class 3b drive (50 Hz, 4 wheels) -> ${drive}"
"${bin}/tread_wear_drive" --profile data/wltc_class3b.csv --vehicle config/vehicle_passenger_car.yaml \
  --rate-hz 50 --out "${drive}"

echo "[wltc] replaying through the node's estimator (config/vehicle_wheels.yaml, 50 Hz updates)"
"${bin}/tread_wear_replay" "${drive}" --wheels config/vehicle_wheels.yaml --rate-hz 50 --out-rate-hz 10 \
  --out "${out_dir}/wltc_wear.bag" --summary "${out_dir}/wltc_summary.json" \
  --timeseries "${out_dir}/wltc_timeseries.csv" "$@"

/usr/bin/python3 scripts/plot_drive.py --summary "${out_dir}/wltc_summary.json" \
  --timeseries "${out_dir}/wltc_timeseries.csv" --out-dir "${out_dir}" --prefix wltc_
