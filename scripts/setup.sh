#!/usr/bin/env bash
# Idempotent set-up for Debian 12 (bookworm), down to a bare `debootstrap --variant=minbase` system:
# installs the Debian packages that are missing (apt, only when something is missing), then configures and
# builds the package with plain CMake into <repo>/_build (Release).
#
# Not `build/`: rosrun skips everything under <pkgroot>/build (docs/setup.md).
# Environment: TREAD_WEAR_JOBS (parallel build jobs, default: nproc).
set -euo pipefail

# The one list of Debian packages the package needs to build, test and run. Add new dependencies here.
TREAD_WEAR_APT_PACKAGES=(
  # toolchain
  build-essential cmake pkg-config
  # ROS 1 (Debian's own packages; see docs/setup.md)
  ros-base-dev catkin ros-message-generation rosbash
  ros-std-msgs libstd-srvs-dev ros-geometry-msgs ros-sensor-msgs ros-visualization-msgs libnav-msgs-dev libtf2-msgs-dev
  libtf2-ros-dev libtf2-eigen-dev librosbag-dev libroslz4-dev libbz2-dev librostest-dev python3-rostest
  libdiagnostic-updater-dev libdynamic-reconfigure-config-init-mutex-dev python3-dynamic-reconfigure
  libmessage-filters-dev python3-rosbag python3-roslaunch
  python3-std-msgs python3-geometry-msgs python3-sensor-msgs python3-visualization-msgs
  python3-tf2-msgs python3-diagnostic-msgs python3-nav-msgs
  # numerics, I/O, tests, benchmarks
  libsundials-dev libeigen3-dev libceres-dev libyaml-cpp-dev libmuparser-dev nlohmann-json3-dev libgtest-dev libbenchmark-dev
  libboost-dev
  # plotting scripts
  python3-matplotlib python3-numpy
  # the fleet layer (tread_wear_fleet, docs/fleet.md): Dask distributed, an existing distributed engine
  python3-distributed
  # CI's check of the ROS package files (catkin_lint in .ci/run)
  catkin-lint
)

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${repo_root}/_build"
export DEBIAN_FRONTEND=noninteractive
# Debian's python (catkin_pkg, genmsg, empy) must win over any pyenv/venv python3 earlier on PATH.
export PATH="/usr/bin:${PATH}"

step_start=${SECONDS}
say() { printf '[setup %4ds] %s\n' "$((SECONDS - step_start))" "$*"; }
die() { printf '[setup] ERROR: %s\n' "$*" >&2; exit 1; }

command -v dpkg-query >/dev/null && command -v apt-get >/dev/null ||
  die "dpkg-query/apt-get not found: this script supports Debian 12 (bookworm) only."

# A package counts as installed only when its dpkg status ends in "installed"; unknown names print nothing.
installed="$(dpkg-query -W -f='${Package} ${Status}\n' "${TREAD_WEAR_APT_PACKAGES[@]}" 2>/dev/null |
             awk '$4 == "installed" {print $1}' || true)"
missing=()
for package in "${TREAD_WEAR_APT_PACKAGES[@]}"; do
  grep -qxF "${package}" <<<"${installed}" || missing+=("${package}")
done

# Runs a command as root: directly when we are root, else through sudo if it is installed.
as_root() {
  if [[ ${EUID} -eq 0 ]]; then
    "$@"
  else
    command -v sudo >/dev/null || die "'$*' needs root, this is not root and sudo is not installed: run this" \
      "script as root."
    sudo env DEBIAN_FRONTEND=noninteractive "$@"
  fi
}

if ((${#missing[@]} > 0)); then
  say "installing ${#missing[@]} missing Debian package(s): ${missing[*]}"
  as_root apt-get update -q
  as_root apt-get install -y -q --no-install-recommends "${missing[@]}"
  say "apt done"
else
  say "all ${#TREAD_WEAR_APT_PACKAGES[@]} Debian packages already installed"
fi

# roslaunch and rostest resolve "localhost". Installed Debian systems and containers have /etc/hosts; a bare
# debootstrap tree has none. Only then write Debian's default; an existing file is never edited.
if ! getent hosts localhost >/dev/null; then
  [[ -e /etc/hosts ]] && die "'localhost' does not resolve: add '127.0.0.1 localhost' to /etc/hosts (ROS needs it)."
  say "no /etc/hosts: writing Debian's default (127.0.0.1 localhost) so that ROS can resolve localhost"
  printf '127.0.0.1\tlocalhost\n::1\t\tlocalhost ip6-localhost ip6-loopback\n' | as_root tee /etc/hosts >/dev/null
fi

jobs="${TREAD_WEAR_JOBS:-$(nproc)}"
say "configuring ${build_dir} (Release)"
mkdir -p "${build_dir}"
cmake -S "${repo_root}" -B "${build_dir}" -DCMAKE_BUILD_TYPE=Release \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 -DPython3_EXECUTABLE=/usr/bin/python3 >"${build_dir}/configure.log" 2>&1 ||
  { cat "${build_dir}/configure.log" >&2; die "cmake configure failed (log above)"; }
say "building with ${jobs} job(s)"
cmake --build "${build_dir}" -j "${jobs}"
say "build done: binaries in ${build_dir}/devel/lib/tread_wear"
