#!/bin/bash
# Headless rviz screenshot of tread_wear_node's contact-patch markers (docs/rviz_patch.png).
# Starts a private master, the node with config/vehicle_wheels.yaml, synthetic inputs
# (scripts/publish_wheel_inputs.py) and rviz with config/tread_wear_patch.rviz under Xvfb, then grabs the screen.
# Usage: scripts/rviz_screenshot.sh [BUILD_DIR] [OUT.png]      (defaults: _build, docs/rviz_patch.png)
# Needs: rviz xvfb xauth imagemagick (apt), a built tread_wear_node.
set -eo pipefail
REPO="$(cd "$(dirname "$0")/.." && pwd)"
BUILD="$(cd "${1:-$REPO/_build}" && pwd)"
OUT="${2:-$REPO/docs/rviz_patch.png}"
export PATH=/usr/bin:$PATH   # Debian's python3 for the ROS tools (a pyenv python3 has no ROS modules)
# shellcheck disable=SC1091
source "$BUILD/devel/setup.bash"
PORT=$((20000 + RANDOM % 20000))
export ROS_MASTER_URI=http://127.0.0.1:$PORT ROS_IP=127.0.0.1 ROS_HOME="$BUILD/ros_home"
mkdir -p "$ROS_HOME"
WORK="$(mktemp -d)"
cleanup() { for p in $PIDS; do kill "$p" 2>/dev/null || true; done; wait 2>/dev/null || true; rm -rf "$WORK"; }
trap cleanup EXIT
PIDS=""
roscore -p "$PORT" > "$WORK/roscore.log" 2>&1 & PIDS="$PIDS $!"
for _ in $(seq 50); do rostopic list > /dev/null 2>&1 && break; sleep 0.2; done
roslaunch tread_wear tread_wear.launch state_file:="$WORK/state.json" > "$WORK/node.log" 2>&1 & PIDS="$PIDS $!"
"$REPO/scripts/publish_wheel_inputs.py" --rate 50 > "$WORK/inputs.log" 2>&1 & PIDS="$PIDS $!"
xvfb-run -a -s "-screen 0 1200x800x24" bash -c "
  rviz -d '$REPO/config/tread_wear_patch.rviz' > '$WORK/rviz.log' 2>&1 &
  RVIZ=\$!
  sleep 12
  import -window root '$WORK/shot.png'
  kill \$RVIZ"
/usr/bin/convert "$WORK/shot.png" -trim +repage "$OUT"
echo "wrote $OUT"
