#!/usr/bin/env bash
# The CPU each compile and link of a build takes, for finding where a cold
# check's time goes (docs/reliability.md, "The check's time").
#
# As a compiler launcher it runs the command and appends "user system wall
# folder output" to $STRIDEMAP_COMPILE_LOG:
#   export STRIDEMAP_COMPILE_LOG=$PWD/compiles.log
#   CMAKE_CXX_COMPILER_LAUNCHER=$PWD/tools/time-compiles.sh \
#   CMAKE_CXX_LINKER_LAUNCHER=$PWD/tools/time-compiles.sh CCACHE_DISABLE=1 bash .ci/run
# (the environment's launcher replaces ccache: cmake/StridemapCompilerCache.cmake).
# With --summary LOG it prints the CPU seconds per build folder and the total.
set -uo pipefail

if [[ "${1:-}" == "--summary" ]]; then
  log=${2:?usage: time-compiles.sh --summary LOG}
  [[ -r "$log" ]] || { echo "time-compiles.sh: cannot read $log" >&2; exit 2; }
  # The build folder: the last folder on the path whose name starts with "build".
  awk '{ cpu = $1 + $2; n = split($4, part, "/"); build = "?";
         for (i = 1; i <= n; ++i) if (part[i] ~ /^build/) build = part[i]
         sum[build] += cpu; total += cpu }
       END { for (b in sum) printf "%9.1f s  %s\n", sum[b], b; printf "%9.1f s  all\n", total }' "$log" | sort -rn
  exit 0
fi

log=${STRIDEMAP_COMPILE_LOG:?time-compiles.sh: set STRIDEMAP_COMPILE_LOG to the log file}
output=?
previous=
for argument in "$@"; do
  [[ "$previous" == "-o" ]] && output=$argument
  previous=$argument
done
times=$(mktemp) || exit 1
# bash's own `time`: user and system CPU of the command and its children.
TIMEFORMAT='%U %S %R'
{ time "$@" 2>&3 3>&-; } 3>&2 2>"$times"
status=$?
# One line per command, appended whole: two compiles at once do not interleave.
printf '%s %s %s\n' "$(tail -n 1 "$times")" "$PWD" "$output" >> "$log"
rm -f "$times"
exit "$status"
