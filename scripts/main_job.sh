#!/usr/bin/env bash
# Same set-up as scripts/run_tests.sh (install what is missing, build into _build), then the main job on the
# bundled data. Arguments are passed on to the main job: [OUT_DIR] [extra tread_wear_replay arguments].
set -euo pipefail
repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "${repo_root}/scripts/setup.sh"

cd "${repo_root}"
export PATH="/usr/bin:${PATH}"

# ---- main job (the one place to change it) -------------------------------------------------------------
# A compact car drives the bundled WLTC class 3b cycle: drive bag, offline replay through the node's
# estimator, per-wheel table (mg/km, stick/slide, WLTC phases) and PNG plots in out/ (docs/drive.md).
# The paper's Table 3 reproduction: scripts/reproduce_paper.sh and tread_wear_compare (docs/table3.md).
main_job=(bash scripts/wltc_main_job.sh)
# ---------------------------------------------------------------------------------------------------------

echo "[main_job] ${main_job[*]} $*"
exec "${main_job[@]}" "$@"
