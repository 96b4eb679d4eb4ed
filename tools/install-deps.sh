#!/usr/bin/env bash
# Installs the Debian packages stridemap builds with, only those missing.
set -euo pipefail
packages=(
  build-essential cmake pkg-config ccache
  libeigen3-dev libyaml-cpp-dev libcli11-dev nlohmann-json3-dev libpng-dev zlib1g-dev
  libopencv-imgproc-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  clang libclang-rt-14-dev
  pybind11-dev python3-dev python3-numpy python3-pytest
  # ROS 1 (docs/ros.md): the node, map --bag and their tests; roscore comes
  # with ros-core. rosbag's headers include Debian's pluginlib, which is
  # ROS 2's and needs rcpputils, rcutils and ament_index_cpp's headers.
  ros-core libroscpp-dev librosbag-dev libtf2-ros-dev libtf2-msgs-dev libtopic-tools-dev
  libsensor-msgs-dev libnav-msgs-dev libgeometry-msgs-dev libvisualization-msgs-dev
  libdiagnostic-msgs-dev libstd-srvs-dev librcpputils-dev librcutils-dev libament-index-cpp-dev
  # grid_map_msgs' headers: Debian's gencpp (system Python) and the .msg
  # files of std_msgs and geometry_msgs, which they use
  python3-gencpp python3-genmsg ros-std-msgs ros-geometry-msgs
  # rostopic echo / rosservice call of the node's topics and services, headless
  python3-sensor-msgs python3-nav-msgs python3-visualization-msgs python3-diagnostic-msgs python3-std-srvs
  python3-tf2-msgs  # rostopic echo /tf
  chromium  # the report page's browser test (tests/browser); about 50 s to install
)
# npm fetches the report page's three.js at build time (web/package-lock.json).
# Debian's nodejs and npm, unless a Node.js with npm is installed already.
if ! command -v npm >/dev/null 2>&1; then
  packages+=(nodejs npm)
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
