#!/usr/bin/env bash
# Proof on known truth of the vehicle-inputs front end (docs/vehicle_inputs.md, "Proof on known truth: the WLTC
# drive bag"): the WLTC class 3b drive is written with what the car's sensors would have measured
# (tread_wear_drive --sensors: tilted, biased, noisy IMU; quantised wheel speeds on radii 1 % larger than nominal;
# steering-wheel angle; lagged odometry), the sensors go through tread_wear_vehicle_inputs, which prints its
# per-wheel errors against the true inputs of the same bag, and both the true and the estimated inputs are replayed
# (tread_wear_replay, as scripts/wltc_main_job.sh) for the WLTC wear per wheel. Then the same sensors without any
# wheel speed (--no-wheel-speeds: speed from odometry and IMU, slip ratios from the force demand) for the wear per
# wheel against the full-sensor estimate and the truth (target: within 10 %).
# Usage: scripts/vehicle_inputs_proof.sh [OUT_DIR] [extra tread_wear_replay arguments, e.g. --preset fast]
# Build first: tread_wear_drive, tread_wear_vehicle_inputs, tread_wear_replay in TREAD_WEAR_BIN
# (default _build/devel/lib/tread_wear). Outputs in OUT_DIR (default out/proof): wltc_sensors.bag,
# wltc_front_end.bag, wltc_no_wheel_speeds.bag, truth_summary.json, front_end_summary.json,
# no_wheel_speeds_summary.json, vehicle_inputs.log, no_wheel_speeds.log. About 2.5 min.
set -euo pipefail
repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "${repo_root}"
export PATH="/usr/bin:${PATH}"
bin="${TREAD_WEAR_BIN:-_build/devel/lib/tread_wear}"
out_dir="${1:-out/proof}"
[[ $# -gt 0 ]] && shift
mkdir -p "${out_dir}"
for tool in tread_wear_drive tread_wear_vehicle_inputs tread_wear_replay; do
  [[ -x ${bin}/${tool} ]] || { echo "[proof] ERROR: ${bin}/${tool} was not built" >&2; exit 1; }
done

sensors="${out_dir}/wltc_sensors.bag"
front_end="${out_dir}/wltc_front_end.bag"
no_wheels="${out_dir}/wltc_no_wheel_speeds.bag"
echo "[proof] WLTC class 3b drive with its sensors -> ${sensors}"
"${bin}/tread_wear_drive" --profile data/wltc_class3b.csv --vehicle config/vehicle_passenger_car.yaml \
  --rate-hz 50 --sensors --out "${sensors}"
echo "[proof] front end: sensors -> per-wheel inputs -> ${front_end}"
"${bin}/tread_wear_vehicle_inputs" "${sensors}" "${front_end}" --vehicle config/vehicle_passenger_car.yaml \
  --rate-hz 100 --wheel-radius 0.305 --steering-ratio 15 | tee "${out_dir}/vehicle_inputs.log"
echo "[proof] front end without wheel speeds -> ${no_wheels}"
"${bin}/tread_wear_vehicle_inputs" "${sensors}" "${no_wheels}" --vehicle config/vehicle_passenger_car.yaml \
  --rate-hz 100 --wheel-radius 0.305 --steering-ratio 15 --no-wheel-speeds >"${out_dir}/no_wheel_speeds.log"
echo "[proof] replaying the true inputs and the front end's"
"${bin}/tread_wear_replay" "${sensors}" --wheels config/vehicle_wheels.yaml --rate-hz 50 --quiet \
  --summary "${out_dir}/truth_summary.json" "$@"
"${bin}/tread_wear_replay" "${front_end}" --wheels config/vehicle_wheels.yaml --rate-hz 50 --quiet \
  --summary "${out_dir}/front_end_summary.json" "$@"
"${bin}/tread_wear_replay" "${no_wheels}" --wheels config/vehicle_wheels.yaml --rate-hz 50 --quiet \
  --summary "${out_dir}/no_wheel_speeds_summary.json" "$@"

/usr/bin/python3 - "${out_dir}/truth_summary.json" "${out_dir}/front_end_summary.json" \
  "${out_dir}/no_wheel_speeds_summary.json" <<'PY'
import json
import sys

truth, est, blind = (json.load(open(path)) for path in sys.argv[1:4])
print("WLTC wear per wheel, true inputs vs front end (target: within 5 %):")
print("| wheel | true inputs, mg/km | front end, mg/km | difference |")
print("|---|---|---|---|")
worst = 0.0
for t, e in zip(truth["wheels"], est["wheels"]):
    d = e["mg_per_km"] / t["mg_per_km"] - 1.0
    worst = max(worst, abs(d))
    print(f"| {t['name']} | {t['mg_per_km']:.2f} | {e['mg_per_km']:.2f} | {100 * d:+.2f} % |")
d = est["mean_mg_per_km"] / truth["mean_mg_per_km"] - 1.0
print(f"| mean | {truth['mean_mg_per_km']:.2f} | {est['mean_mg_per_km']:.2f} | {100 * d:+.2f} % |")
print(f"[proof] largest wear difference {100 * worst:.2f} % ({'meets' if worst <= 0.05 else 'MISSES'} the 5 % target)")
print()
print("WLTC wear per wheel without wheel speeds (target: within 10 % of the truth):")
print("| wheel | true inputs, mg/km | all sensors, mg/km | no wheel speeds, mg/km | vs all sensors | vs truth |")
print("|---|---|---|---|---|---|")
worst = 0.0
for t, e, b in zip(truth["wheels"], est["wheels"], blind["wheels"]):
    d = b["mg_per_km"] / t["mg_per_km"] - 1.0
    worst = max(worst, abs(d))
    print(f"| {t['name']} | {t['mg_per_km']:.2f} | {e['mg_per_km']:.2f} | {b['mg_per_km']:.2f} | "
          f"{100 * (b['mg_per_km'] / e['mg_per_km'] - 1.0):+.2f} % | {100 * d:+.2f} % |")
print(f"[proof] without wheel speeds: largest wear difference to the truth {100 * worst:.2f} % "
      f"({'meets' if worst <= 0.10 else 'MISSES'} the 10 % target)")
PY
