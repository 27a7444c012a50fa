#!/usr/bin/env bash
# Every test under AddressSanitizer and UndefinedBehaviorSanitizer (a separate study, not part of CI): the set-up of
# scripts/run_tests.sh, then a second build in _build_sanitize (RelWithDebInfo, -fsanitize=address,undefined, any
# undefined behaviour fatal) and ctest there. Leaks are checked in the core tests; the ROS processes exit with
# roscpp's own allocations alive, so the rostests run without the leak check. About 10 min to build and 10 min to
# test on 2 cores. Exit code: 0 when both ctest runs pass.
set -euo pipefail
repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "${repo_root}/scripts/setup.sh"

export PATH="/usr/bin:${PATH}"
build_dir="${repo_root}/_build_sanitize"
flags="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined"
cmake -S "${repo_root}" -B "${build_dir}" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS="${flags}" \
  -DCMAKE_EXE_LINKER_FLAGS="${flags}" -DCMAKE_SHARED_LINKER_FLAGS="${flags}"
cmake --build "${build_dir}" -j2

export ROS_IP="${ROS_IP:-127.0.0.1}"
export ROS_HOME="${build_dir}/ros_home"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
echo "[run_sanitizers] core tests, leak check on"
ASAN_OPTIONS="detect_leaks=1:halt_on_error=1" ctest --test-dir "${build_dir}" --output-on-failure -j2 -E rostest
echo "[run_sanitizers] rostests, leak check off"
ASAN_OPTIONS="detect_leaks=0:halt_on_error=1" ctest --test-dir "${build_dir}" --output-on-failure -j2 -R rostest
