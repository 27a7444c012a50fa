#!/usr/bin/env bash
# Same set-up as scripts/run_tests.sh (install what is missing, build into _build), then the main job on the
# bundled data. Extra arguments are passed on to the main job's tool.
set -euo pipefail
repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "${repo_root}/scripts/setup.sh"

cd "${repo_root}"
export PATH="/usr/bin:${PATH}"
bin="_build/devel/lib/tread_wear"

# ---- main job (the one place to change it) -------------------------------------------------------------
# The model on the paper's Table 3 rig conditions, predicted vs measured, both turn-slip orientations.
main_job=("${bin}/tread_wear_compare" --params config/tires/grosch_wheel.yaml --runs data/paper/table3_runs.csv
          --orientation both)
# ---------------------------------------------------------------------------------------------------------

[[ -x ${main_job[0]} ]] || { echo "[main_job] ERROR: ${main_job[0]} was not built" >&2; exit 1; }
echo "[main_job] ${main_job[*]}"
exec "${main_job[@]}" "$@"
