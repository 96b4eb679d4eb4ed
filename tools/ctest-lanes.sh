#!/usr/bin/env bash
# Runs a build folder's tests in two lanes at once (docs/reliability.md,
# "The check's time"): the tests labelled `waits`, which spend most of their
# time waiting (a live run against the emulator in real time, roscore and
# the node), in a lane of their own beside the rest, which keep JOBS
# processes busy. On two cores a waiting test held one of ctest's two slots
# while using a fifth of a core. The side lane's output follows the main
# lane's; the run fails when either lane does.
#
#   tools/ctest-lanes.sh BUILD_DIR JOBS [LABELS_REGEX [EXCLUDE_REGEX [CTEST_ARGS...]]]
#
# LABELS_REGEX: run only tests with a label matching it (ctest -L); empty or
# absent: every test. EXCLUDE_REGEX: leave out tests with a label matching
# it (ctest -LE; `waits` is added to it for the main lane). CTEST_ARGS go to
# both lanes (e.g. -E NAME_REGEX).
set -uo pipefail
if [ $# -lt 2 ]; then
  echo "usage: $0 BUILD_DIR JOBS [LABELS_REGEX [EXCLUDE_REGEX [CTEST_ARGS...]]]" >&2
  exit 2
fi
build=$1 jobs=$2 labels=${3:-} exclude=${4:-}
shift $(($# < 4 ? $# : 4))
cd "$build" || exit 2
side_log=$(mktemp "${TMPDIR:-/tmp}/stridemap-ctest-waits.XXXXXX")
trap 'rm -f "$side_log"' EXIT

include=()
[ -n "$labels" ] && include=(-L "$labels")
side_exclude=()
[ -n "$exclude" ] && side_exclude=(-LE "$exclude")
main_exclude="^waits\$"
[ -n "$exclude" ] && main_exclude="^waits\$|$exclude"

# -L twice selects tests that match both; the roscore tests hold a lock, so
# the side lane runs them one after another whatever its -j.
ctest --output-on-failure -j 2 -L '^waits$' "${include[@]}" "${side_exclude[@]}" "$@" > "$side_log" 2>&1 &
side=$!
# A signal to this script stops the side lane too.
trap 'kill "$side" 2>/dev/null; rm -f "$side_log"' EXIT
ctest --output-on-failure -j "$jobs" "${include[@]}" -LE "$main_exclude" "$@"
main_status=$?
wait "$side"
side_status=$?
echo "--- the tests that mostly wait, run beside the others (label waits) ---"
cat "$side_log"
if [ "$main_status" -ne 0 ] || [ "$side_status" -ne 0 ]; then
  echo "ctest-lanes: tests failed (main lane exit $main_status, waiting lane exit $side_status)" >&2
  exit 1
fi
