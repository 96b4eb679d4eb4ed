#!/usr/bin/env bash
# The URG emulator as a roslaunch node (launch/demo.launch): roslaunch
# appends __name:= and __log:= to a node's arguments, which the CLI would
# refuse, so they stop here. Usage: emulated_urg_node.sh CLI WORK_DIR SCENE
set -euo pipefail
if [ $# -lt 3 ]; then
  echo "usage: $0 STRIDEMAP_CLI WORK_DIR SCENE" >&2
  exit 2
fi
cli="$1" work="$2" scene="$3"
mkdir -p "$work"
rm -f "$work/poses.txt"
exec "$cli" emulate-urg --scene "$scene" --motion cart-rail --link "$work/urg" \
  --poses-out "$work/poses.txt" --poses-rate-hz 100
