#!/usr/bin/env python3
"""The slowest tests of a `make check` log, per stage, as a Markdown table.

Usage: slowest_tests.py CHECK_LOG [COUNT]

Reads the ctest lines (`Test #N: name ... Passed 12.34 sec`) of each stage
of `.ci/run` and prints the COUNT tests (default 20) whose times summed
over the stages are largest, with each stage's time (docs/reliability.md,
"The slowest tests").
"""
import re
import sys

STAGE = re.compile(r"^=== stage: (.*) ===$")
TEST = re.compile(r"Test +#\d+: (\S+) \.*\s+(?:\*\*\*)?\w+.*?([0-9.]+) sec")
COLUMNS = [("make test", "make test"), ("make test-sanitize", "ASan + UBSan"),
           ("make test-tsan", "TSan"), ("make test-arm", "ARM")]


def main() -> int:
    if len(sys.argv) not in (2, 3):
        print(__doc__.strip(), file=sys.stderr)
        return 2
    count = int(sys.argv[2]) if len(sys.argv) == 3 else 20
    times: dict[str, dict[str, float]] = {}
    stage = None
    try:
        with open(sys.argv[1], encoding="utf-8", errors="replace") as log:
            for line in log:
                if m := STAGE.match(line.strip()):
                    stage = m.group(1)
                elif stage and (m := TEST.search(line)):
                    times.setdefault(m.group(1), {})[stage] = float(m.group(2))
    except OSError as error:
        print(f"slowest_tests.py: cannot read {sys.argv[1]}: {error.strerror}", file=sys.stderr)
        return 2
    if not times:
        print(f"slowest_tests.py: {sys.argv[1]}: no ctest result lines", file=sys.stderr)
        return 1
    ranked = sorted(times.items(), key=lambda item: -sum(item[1].values()))[:count]
    print("| test | " + " | ".join(title for _, title in COLUMNS) + " |")
    print("|---|" + "---|" * len(COLUMNS))
    for name, by_stage in ranked:
        cells = [f"{by_stage[s]:.1f}" if s in by_stage else "" for s, _ in COLUMNS]
        print(f"| `{name}` | " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
