#!/usr/bin/env bash
# Runs every Google Benchmark program of a build; figures go in docs/performance.md.
set -euo pipefail
build_dir=${1:-build}
status=0
for bench in "$build_dir"/bin/*_bench; do
  [ -x "$bench" ] || continue
  echo "== $(basename "$bench")"
  "$bench" --benchmark_min_time=0.5 || status=1
done
exit $status
