#!/usr/bin/env bash
# Sensitivity of the WLTC mean wear [mg/km per tire] to vehicle, route and tire assumptions (docs/drive.md).
# One drive + replay per variant (preset fast by default: the ratios, not the level, are the result).
# Usage: scripts/drive_sensitivity.sh [OUT_DIR] [PRESET]    (bin dir: TREAD_WEAR_BIN, default _build/devel/lib/tread_wear)
set -euo pipefail
repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "${repo_root}"
bin="${TREAD_WEAR_BIN:-_build/devel/lib/tread_wear}"
out="${1:-out/sensitivity}"
preset="${2:-fast}"
mkdir -p "${out}"
vehicle=config/vehicle_passenger_car.yaml
tire=config/tires/passenger_205_55_r16.yaml

variant() {  # name, vehicle file, tire file, extra drive args...
  local name=$1 veh=$2 tyre=$3; shift 3
  sed "s|tires/passenger_205_55_r16.yaml|$(realpath "${tyre}")|" config/vehicle_wheels.yaml > "${out}/${name}_wheels.yaml"
  "${bin}/tread_wear_drive" --vehicle "${veh}" --out "${out}/${name}.bag" "$@" > /dev/null
  "${bin}/tread_wear_replay" "${out}/${name}.bag" --wheels "${out}/${name}_wheels.yaml" --rate-hz 50 --preset "${preset}" \
    --quiet --summary "${out}/${name}.json" > /dev/null
  rm -f "${out}/${name}.bag"
  /usr/bin/python3 -c "import json,sys; s=json.load(open('${out}/${name}.json')); w={x['name']:x['mg_per_km'] for x in s['wheels']}; \
print(f\"{'${name}':<22} mean {s['mean_mg_per_km']:7.2f} mg/km  front {(w['front_left']+w['front_right'])/2:7.2f}  rear {(w['rear_left']+w['rear_right'])/2:7.2f}\")"
}
scaled() {  # file key factor -> copy with key scaled
  /usr/bin/python3 - "$@" <<'PY'
import re, sys
path, key, factor, dest = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4]
text = open(path).read()
text, n = re.subn(rf"^(\s*{key}:\s*)([-0-9.eE+]+)", lambda m: f"{m.group(1)}{float(m.group(2)) * factor:.6g}", text, flags=re.M)
assert n == 1, key
open(dest, "w").write(text)
PY
}
variant baseline "${vehicle}" "${tire}"
scaled "${vehicle}" mass_kg 1.1 "${out}/mass_plus10.yaml";   variant mass_plus10 "${out}/mass_plus10.yaml" "${tire}"
scaled "${vehicle}" mass_kg 0.9 "${out}/mass_minus10.yaml";  variant mass_minus10 "${out}/mass_minus10.yaml" "${tire}"
variant ay_limit_2.5 "${vehicle}" "${tire}" --lateral-accel-limit 2.5
variant ay_limit_3.5 "${vehicle}" "${tire}" --lateral-accel-limit 3.5
variant route_seed_2 "${vehicle}" "${tire}" --seed 2
# Stiffer tire (k_y, hence k_x = phi k_y) with the car's slip estimates kept consistent with it (+10 % too).
scaled "${tire}" k_y0_MPa_per_mm 1.1 "${out}/ky_plus10.yaml"
scaled "${vehicle}" cornering_stiffness_front_per_rad 1.1 "${out}/c_plus10.yaml"
scaled "${out}/c_plus10.yaml" cornering_stiffness_rear_per_rad 1.1 "${out}/c_plus10.yaml"
scaled "${out}/c_plus10.yaml" longitudinal_slip_stiffness 1.1 "${out}/c_plus10.yaml"
variant stiffness_plus10 "${out}/c_plus10.yaml" "${out}/ky_plus10.yaml"
scaled "${tire}" mu_m 0.9 "${out}/mu_minus10.yaml"; scaled "${out}/mu_minus10.yaml" mu_0 0.9 "${out}/mu_minus10.yaml"
variant friction_minus10 "${vehicle}" "${out}/mu_minus10.yaml"
sed 's/drive_layout: front/drive_layout: rear/' "${vehicle}" > "${out}/rwd.yaml"; variant rear_wheel_drive "${out}/rwd.yaml" "${tire}"
