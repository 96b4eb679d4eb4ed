#!/usr/bin/env bash
# White and black objects under structured light (simulated): the cart-rail
# image path over cart_rail_narrow.yaml with every object's reflectance set
# to each value, at each light level, with each exposure mode. Prints one
# line per run: the share of visible stripe columns detected and the worst
# |extent error| of the objects (or "missed" when one is not found).
# Usage: tools/stripe_reflectance_sweep.sh BUILD_BIN OUT_DIR [SEEDS]
set -euo pipefail
bin=${1:?stridemap binary}; out=${2:?output folder}; seeds=${3:-1}
# Never write over what a user already has: the folder must be new or empty.
if [ -e "$out" ] && [ -n "$(ls -A "$out" 2>/dev/null)" ]; then
  echo "stripe_reflectance_sweep: $out: the output folder exists and is not empty; give a new one" >&2
  exit 2
fi
mkdir -p "$out"
scene_src="$(dirname "$0")/../scenes/cart_rail_narrow.yaml"
printf "%-10s %-11s %6s %5s %10s %10s\n" exposure reflectance lux seed detected worst_ext
for r in 0.1 0.3 0.5 0.7 0.9; do
  scene="$out/narrow_r$r.yaml"
  # the floor keeps its 0.5; every object gets r
  sed -E "/^(boxes|cylinders):/,\$ s/reflectance: [0-9.]+/reflectance: $r/" "$scene_src" > "$scene"
  for exposure in auto highlight; do
    for lux in 50 300 1000; do
      for seed in $seeds; do
        run="$out/run_${exposure}_${r}_${lux}_$seed"
        "$bin" experiment cart-rail --sensor structured-light --scene "$scene" --lux "$lux" --exposure "$exposure" \
          --seed "$seed" --out "$run" --quiet > "$run.txt"
        detected=$(grep -o '[0-9.]* % of the [0-9]* visible' "$run.txt" | cut -d' ' -f1)
        worst=$(awk '/not found/ {m=1} {for (i = 1; i <= NF; i++) if (($i == "length" || $i == "width") && i + 3 <= NF) {e = $(i + 3); if (e < 0) e = -e; if (e > w) w = e}} END {print m ? "missed" : w}' "$run.txt")
        printf "%-10s %-11s %6s %5s %9s%% %10s\n" "$exposure" "$r" "$lux" "$seed" "$detected" "$worst"
      done
    done
  done
done
