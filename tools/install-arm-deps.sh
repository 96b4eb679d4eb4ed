#!/usr/bin/env bash
# Installs what `make test-arm` needs, only what is missing: Debian's arm64
# cross toolchain and qemu's user-mode emulator. Nothing of the target
# architecture comes from apt (no `dpkg --add-architecture`): the libraries
# built for the ARM tests need Eigen and nlohmann-json, both header-only and
# Architecture: all, and GoogleTest is compiled for arm64 from Debian's
# sources in /usr/src/googletest (package googletest, which `make deps`
# installs with libgtest-dev). qemu-user rather than qemu-user-static: the
# tests name the emulator themselves (no binfmt registration needed), and it
# is a quarter of the size (99 MB against 379 MB installed).
set -euo pipefail
packages=(crossbuild-essential-arm64 qemu-user googletest cmake libeigen3-dev nlohmann-json3-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "install-arm-deps: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
