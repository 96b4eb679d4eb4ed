#!/usr/bin/env bash
# Runs the fuzzers of a fuzz build (`make fuzz`), each for a bounded time,
# starting from its seed corpus and its regressions. New inputs collect in
# BUILD_DIR/fuzz-corpus/<target>/ (kept between runs), crashes in
# BUILD_DIR/fuzz-artifacts/<target>/. Exits 1 if any fuzzer found a bug.
#
#   fuzz/run.sh BUILD_DIR SECONDS_EACH [TARGET...]
set -euo pipefail
build_dir=$1
seconds=$2
shift 2
root=$(cd "$(dirname "$0")" && pwd)
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  for bin in "$build_dir"/bin/*_fuzz; do
    [ -x "$bin" ] && targets+=("$(basename "$bin" _fuzz)")
  done
fi
if [ ${#targets[@]} -eq 0 ]; then
  echo "fuzz/run.sh: no fuzzers in $build_dir/bin (build the stridemap_fuzzers target)" >&2
  exit 2
fi
status=0
for target in "${targets[@]}"; do
  bin="$build_dir/bin/${target}_fuzz"
  work="$build_dir/fuzz-corpus/$target"
  artifacts="$build_dir/fuzz-artifacts/$target"
  log="$build_dir/fuzz-logs/$target.log"
  mkdir -p "$work" "$artifacts" "$(dirname "$log")"
  args=(-max_total_time="$seconds" -timeout=25 -rss_limit_mb=2048 -print_final_stats=1
        -artifact_prefix="$artifacts/")
  [ -f "$root/dicts/$target.dict" ] && args+=(-dict="$root/dicts/$target.dict")
  dirs=("$work" "$root/corpus/$target")
  [ -d "$root/regressions/$target" ] && dirs+=("$root/regressions/$target")
  # libFuzzer stops itself after SECONDS_EACH; the timeout only bounds a
  # fuzzer that hangs while reporting (e.g. leak checking a huge heap).
  if timeout --kill-after=10 $((seconds + 120)) "$bin" "${args[@]}" "${dirs[@]}" >"$log" 2>&1; then
    runs=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
    cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*$' || echo "?")
    echo "fuzz $target: ok, $runs inputs in ${seconds}s, coverage $cov edges"
  else
    status=1
    echo "fuzz $target: FOUND A BUG (log: $log)"
    tail -n 40 "$log"
    echo "fuzz $target: the input is in $artifacts/; fix the bug, then add the input to fuzz/regressions/$target/"
  fi
done
exit $status
