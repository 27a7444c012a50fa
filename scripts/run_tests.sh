#!/usr/bin/env bash
# Same set-up as scripts/main_job.sh (install what is missing, build into _build), then every test through ctest.
# Exit code: ctest's (0 = all tests passed).
set -euo pipefail
repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "${repo_root}/scripts/setup.sh"

export PATH="/usr/bin:${PATH}"
# rostests start their own master; keep their node URIs on loopback and their logs inside the build dir.
export ROS_IP="${ROS_IP:-127.0.0.1}"
export ROS_HOME="${repo_root}/_build/ros_home"
echo "[run_tests] ctest --test-dir _build --output-on-failure -j2"
exec ctest --test-dir "${repo_root}/_build" --output-on-failure -j2
