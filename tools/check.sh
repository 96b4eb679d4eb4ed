#!/usr/bin/env bash
# `make check`: what CI runs (.ci/run), in a fresh clone of HEAD beside this
# checkout, so that uncommitted changes and this checkout's build folders
# play no part. The clone goes to CHECK_DIR (default: a new folder under
# the system's temporary folder); the log, with each stage's wall time, to
# CHECK_DIR/check.log and the terminal, then the 20 slowest tests. The clone is kept for a look at its
# builds; it is this command's own folder, so a later check may replace it.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
if [ -n "$(git -C "$root" status --porcelain --untracked-files=no)" ]; then
  echo "check: uncommitted changes in $root are not checked (a fresh clone of HEAD is)" >&2
fi
dir=${CHECK_DIR:-$(mktemp -d "${TMPDIR:-/tmp}/stridemap-check.XXXXXX")}
if [ -e "$dir/.stridemap-check" ]; then
  rm -rf "$dir"  # a clone an earlier check made (it left the marker)
elif [ -e "$dir" ] && [ -n "$(ls -A "$dir")" ]; then
  echo "check: $dir is not empty and was not made by make check; give another CHECK_DIR" >&2
  exit 2
fi
mkdir -p "$dir"
git clone --quiet --no-hardlinks "$root" "$dir/stridemap"
touch "$dir/.stridemap-check"
head=$(git -C "$dir/stridemap" rev-parse --short HEAD)
echo "check: .ci/run in a fresh clone of $head at $dir/stridemap (log: $dir/check.log)"
set +e
(cd "$dir/stridemap" && bash .ci/run) 2>&1 | tee "$dir/check.log"
status=${PIPESTATUS[0]}
set -e
echo "check: stage times of $head"
grep -E '^=== (stage passed|stage FAILED|all stages)' "$dir/check.log" | sed 's/^=== /  /; s/ ===$//'
echo "check: the 20 slowest tests, seconds per stage (docs/reliability.md)"
python3 "$root/tools/slowest_tests.py" "$dir/check.log" 20 || true
exit "$status"
