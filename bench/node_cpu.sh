#!/bin/bash
# CPU use of tread_wear_node for 4 wheels at 100 Hz (docs/node.md, "CPU use"): a private master, the node with
# config/vehicle_wheels.yaml (passenger tire, update_rate_hz 100), synthetic inputs for all 4 wheels at 100 Hz
# (scripts/publish_wheel_inputs.py: 1,200 messages/s), rviz not subscribed. After a warm-up, the node's CPU time
# (utime + stime of /proc/<pid>/stat) over the window, and the input publisher's for comparison.
# Usage: bench/node_cpu.sh [BUILD_DIR] [PRESET] [WINDOW_S]     (defaults: _build, standard, 30)
set -eo pipefail
REPO="$(cd "$(dirname "$0")/.." && pwd)"
BUILD="$(cd "${1:-$REPO/_build}" && pwd)"
PRESET="${2:-standard}"
WINDOW_S="${3:-30}"
export PATH=/usr/bin:$PATH   # Debian's python3 for the ROS tools
# shellcheck disable=SC1091
source "$BUILD/devel/setup.bash"
PORT=$((20000 + RANDOM % 20000))
export ROS_MASTER_URI=http://127.0.0.1:$PORT ROS_IP=127.0.0.1 ROS_HOME="$BUILD/ros_home"
mkdir -p "$ROS_HOME"
WORK="$(mktemp -d)"
PIDS=""
cleanup() { for p in $PIDS; do kill "$p" 2>/dev/null || true; done; wait 2>/dev/null || true; rm -rf "$WORK"; }
trap cleanup EXIT

roscore -p "$PORT" > "$WORK/roscore.log" 2>&1 & PIDS="$PIDS $!"
for _ in $(seq 50); do rostopic list > /dev/null 2>&1 && break; sleep 0.2; done
rosparam load "$REPO/config/vehicle_wheels.yaml" /tread_wear_node
rosparam set /tread_wear_node/config_dir "$REPO/config"
rosparam set /tread_wear_node/update_rate_hz 100
rosparam set /tread_wear_node/preset "$PRESET"
"$BUILD/devel/lib/tread_wear/tread_wear_node" __name:=tread_wear_node > "$WORK/node.log" 2>&1 &
NODE=$!; PIDS="$PIDS $NODE"
"$REPO/scripts/publish_wheel_inputs.py" --rate 100 > "$WORK/inputs.log" 2>&1 &
INPUTS=$!; PIDS="$PIDS $INPUTS"
sleep 8   # warm-up: connections, first evaluations, timing of the presets

ticks() { awk '{print $14 + $15}' "/proc/$1/stat"; }
hz=$(getconf CLK_TCK)
node0=$(ticks $NODE); inputs0=$(ticks $INPUTS); load0=$(cut -d' ' -f1 /proc/loadavg)
sleep "$WINDOW_S"
node1=$(ticks $NODE); inputs1=$(ticks $INPUTS); load1=$(cut -d' ' -f1 /proc/loadavg)
# The update loop's own diagnostics: key/value pairs of the "update loop" status.
loop=$(timeout 5 rostopic echo -n 1 /diagnostics 2>/dev/null | awk '
  /name: / { in_loop = index($0, "update loop") > 0 }
  in_loop && /key: / { sub(/.*key: /, ""); gsub(/"/, ""); key = $0 }
  in_loop && /value: / && key != "" { sub(/.*value: /, ""); gsub(/"/, ""); printf "%s%s = %s", sep, key, $0; sep = "; "; key = "" }' || true)
rate=$(timeout 8 rostopic hz -w 200 /wear 2>/dev/null | grep -m1 "average rate" || true)
awk -v n=$((node1 - node0)) -v i=$((inputs1 - inputs0)) -v hz="$hz" -v w="$WINDOW_S" -v p="$PRESET" \
    -v l0="$load0" -v l1="$load1" -v loop="$loop" -v rate="$rate" 'BEGIN {
  printf "preset %s, 4 wheels x 100 Hz, %d s window, load average %s -> %s\n", p, w, l0, l1
  printf "tread_wear_node CPU: %.1f %% of one core\n", 100 * n / hz / w
  printf "input publisher CPU: %.1f %% of one core (for comparison)\n", 100 * i / hz / w
  printf "update loop diagnostics: %s\n", loop
  printf "/wear %s\n", rate
}'
