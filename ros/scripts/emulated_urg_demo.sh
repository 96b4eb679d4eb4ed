#!/usr/bin/env bash
# The whole robot stack without hardware (docs/ros.md): roscore, the URG
# emulator on a pseudo-terminal (a cart on the rail over the boxes scene),
# the URG bridge (LaserScan + TF from the emulator's true poses) and
# stridemap_node. Ctrl-C stops them all (each by its process id).
# Watch it in RViz: rviz -d ros/rviz/stridemap.rviz; headless:
# rostopic echo /diagnostics. Usage: ros/scripts/emulated_urg_demo.sh [BUILD_DIR]
set -euo pipefail
here="$(cd "$(dirname "$0")/../.." && pwd)"
build="${1:-$here/build}"
work="$(mktemp -d "${TMPDIR:-/tmp}/stridemap_demo_XXXXXX")"
pids=()
stop() {
  trap - EXIT INT TERM  # a signal then the exit would stop everything twice
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do kill "${pids[i]}" 2>/dev/null || true; done
  wait 2>/dev/null || true
  echo "stopped; logs and the saved map in $work"
}
trap stop EXIT INT TERM
export ROS_MASTER_URI="${ROS_MASTER_URI:-http://localhost:11311}"
if ! rostopic list >/dev/null 2>&1; then
  port="${ROS_MASTER_URI##*:}"
  roscore -p "${port%%/*}" >"$work/roscore.log" 2>&1 &
  pids+=($!)
  for _ in $(seq 100); do rostopic list >/dev/null 2>&1 && break; sleep 0.2; done
fi
"$build/bin/stridemap" emulate-urg --scene "$here/scenes/cart_rail_boxes.yaml" --motion cart-rail \
  --link "$work/urg" --poses-out "$work/poses.txt" --poses-rate-hz 100 >"$work/emulator.log" 2>&1 &
pids+=($!)
for _ in $(seq 100); do [ -e "$work/urg" ] && break; sleep 0.1; done
"$build/bin/stridemap_urg_bridge" _device:="$work/urg" _poses_file:="$work/poses.txt" >"$work/bridge.log" 2>&1 &
pids+=($!)
echo "stridemap_node mapping the emulated URG; Ctrl-C to stop. Save the map: rosservice call /stridemap_node/save_map"
"$build/bin/stridemap_node" _scan_topic:=/scan _map_file:="$work/emulated.smap" &
pids+=($!)
wait "${pids[-1]}"
