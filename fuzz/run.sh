#!/usr/bin/env bash
# Runs the fuzzers of a fuzz build (`make fuzz`), each for a bounded time,
# starting from its seed corpus and its regressions. New inputs collect in
# BUILD_DIR/fuzz-corpus/<target>/ (kept between runs), crashes in
# BUILD_DIR/fuzz-artifacts/<target>/. Exits 1 if any fuzzer found a bug.
#
#   [FUZZ_JOBS=N] [FUZZ_SEED=S] fuzz/run.sh BUILD_DIR SECONDS_EACH [TARGET...]
# FUZZ_JOBS fuzzers run side by side (default 1). Without FUZZ_SEED each run
# explores new inputs (libFuzzer picks a seed); with it, every run from the
# same corpus tries the same inputs in the same order, so a gate such as CI
# gives the verdict the developer's `make check` gave.
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
jobs_max=${FUZZ_JOBS:-1}
[[ "$jobs_max" =~ ^[1-9][0-9]*$ ]] || { echo "fuzz/run.sh: FUZZ_JOBS must be a whole number >= 1, got '$jobs_max'" >&2; exit 2; }
seed=${FUZZ_SEED:-}
[[ -z "$seed" || "$seed" =~ ^[1-9][0-9]{0,8}$ ]] || { echo "fuzz/run.sh: FUZZ_SEED must be a whole number from 1 to 999999999, got '$seed'" >&2; exit 2; }
results="$build_dir/fuzz-logs/results"
rm -rf "$results"
mkdir -p "$results"

# One fuzzer; its verdict goes to a file so that fuzzers can run side by side
# and still be reported in a fixed order.
fuzz_one() {
  local target=$1
  local bin="$build_dir/bin/${target}_fuzz"
  local work="$build_dir/fuzz-corpus/$target"
  local artifacts="$build_dir/fuzz-artifacts/$target"
  local log="$build_dir/fuzz-logs/$target.log"
  mkdir -p "$work" "$artifacts"
  local args=(-max_total_time="$seconds" -timeout=25 -rss_limit_mb=2048 -print_final_stats=1
              -artifact_prefix="$artifacts/")
  [ -f "$root/dicts/$target.dict" ] && args+=(-dict="$root/dicts/$target.dict")
  [ -n "$seed" ] && args+=(-seed="$seed")
  local dirs=("$work" "$root/corpus/$target")
  [ -d "$root/regressions/$target" ] && dirs+=("$root/regressions/$target")
  # libFuzzer stops itself after SECONDS_EACH; the timeout only bounds a
  # fuzzer that hangs while reporting (e.g. leak checking a huge heap).
  if timeout --kill-after=10 $((seconds + 120)) "$bin" "${args[@]}" "${dirs[@]}" >"$log" 2>&1; then
    local runs cov
    runs=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
    cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*$' || echo "?")
    echo "fuzz $target: ok, $runs inputs in ${seconds}s, coverage $cov edges" >"$results/$target.ok"
  else
    {
      echo "fuzz $target: FOUND A BUG (log: $log)"
      tail -n 40 "$log"
      echo "fuzz $target: the input is in $artifacts/; fix the bug, then add the input to fuzz/regressions/$target/"
    } >"$results/$target.bug"
  fi
}

echo "fuzz: ${#targets[@]} targets, ${seconds}s each, $jobs_max at a time, seed ${seed:-chosen by each fuzzer}"
for target in "${targets[@]}"; do
  if [ ! -x "$build_dir/bin/${target}_fuzz" ]; then
    echo "fuzz/run.sh: no fuzzer '$target' in $build_dir/bin" >&2
    exit 2
  fi
  while [ "$(jobs -rp | wc -l)" -ge "$jobs_max" ]; do wait -n || true; done
  fuzz_one "$target" &
done
wait

status=0
for target in "${targets[@]}"; do
  if [ -f "$results/$target.ok" ]; then
    cat "$results/$target.ok"
  else
    status=1
    cat "$results/$target.bug" 2>/dev/null || echo "fuzz $target: no verdict (the runner itself failed)"
  fi
done
exit $status
