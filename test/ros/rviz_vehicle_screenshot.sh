#!/bin/bash
# Headless rviz screenshot of the whole car (docs/rviz_vehicle.png): a private master, launch/vehicle.launch
# (vehicle_inputs_node + tread_wear_node, speed_source:=twist, no state or radius file), synthetic sensors of a steady
# left circle (test/ros/publish_vehicle_sensors.py) and rviz with config/tread_wear.rviz under Xvfb.
# Usage: test/ros/rviz_vehicle_screenshot.sh [BUILD_DIR] [OUT.png]      (defaults: _build, docs/rviz_vehicle.png)
# Needs: rviz xvfb xauth imagemagick (apt), built vehicle_inputs_node and tread_wear_node.
set -eo pipefail
REPO="$(cd "$(dirname "$0")/../.." && pwd)"
BUILD="$(cd "${1:-$REPO/_build}" && pwd)"
OUT="${2:-$REPO/docs/rviz_vehicle.png}"
export PATH=/usr/bin:$PATH   # Debian's python3 for the ROS tools
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
roslaunch tread_wear vehicle.launch speed_source:=twist radius_file:="$WORK/radii.json" state_file:="$WORK/state.json" > "$WORK/launch.log" 2>&1 &
PIDS="$PIDS $!"
"$REPO/test/ros/publish_vehicle_sensors.py" --speed 15 --radius 40 > "$WORK/sensors.log" 2>&1 & PIDS="$PIDS $!"
xvfb-run -a -s "-screen 0 1200x800x24" bash -c "
  rviz -d '$REPO/config/tread_wear.rviz' > '$WORK/rviz.log' 2>&1 &
  RVIZ=\$!
  sleep 14
  import -window root '$WORK/shot.png'
  kill \$RVIZ"
/usr/bin/convert "$WORK/shot.png" -trim +repage "$OUT"
echo "wrote $OUT"
