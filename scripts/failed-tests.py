#!/usr/bin/env python3
"""Prints the tests that failed in a ctest build folder's last run, each with
the last lines of its output, so that a CI log whose head is cut off still
ends with what failed and why.

    scripts/failed-tests.py BUILD_DIR [--lines N]

Reads BUILD_DIR/Testing/Temporary/LastTestsFailed.log (the failed names) and
LastTest.log (every test's output; ctest writes both on each run). Prints
nothing when the last run had no failure. Exit code 0 unless the folder's
logs cannot be read.
"""
import argparse
import pathlib
import sys


def failed_names(tmp: pathlib.Path) -> list[str]:
    path = tmp / "LastTestsFailed.log"
    if not path.exists():
        return []
    names = []
    for line in path.read_text(errors="replace").splitlines():
        # "1188:Suite.Name"
        _, _, name = line.partition(":")
        if name:
            names.append(name.strip())
    return names


def outputs(tmp: pathlib.Path, wanted: set[str]) -> dict[str, list[str]]:
    """The output lines of each wanted test, from LastTest.log's blocks
    ('N/M Testing: NAME' ... 'Output:' / dashes ... '<end of output>')."""
    path = tmp / "LastTest.log"
    found: dict[str, list[str]] = {}
    if not path.exists():
        return found
    current = None
    in_output = False
    for line in path.read_text(errors="replace").splitlines():
        if " Testing: " in line and line.split(" ", 1)[0].count("/") == 1:
            name = line.split(" Testing: ", 1)[1].strip()
            current = name if name in wanted else None
            in_output = False
            continue
        if current is None:
            continue
        if line == "Output:":
            in_output = True
            found[current] = []
            continue
        if line.startswith("<end of output>"):
            in_output = False
            current = None
            continue
        if in_output:
            found[current].append(line)
    return found


def excerpt(lines: list[str], n: int) -> list[str]:
    """The first gtest failure with what follows it, then the tail; or, with
    no gtest failure in the output (a crash, a timeout), only the tail."""
    first = next((i for i, l in enumerate(lines) if ": Failure" in l), None)
    if first is None or first >= len(lines) - n:
        return lines[-n:]
    head = lines[first:first + n]
    tail = lines[max(first + n, len(lines) - n):]
    return head + (["..."] if first + n < len(lines) - n else []) + tail


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("build_dir")
    parser.add_argument("--lines", type=int, default=25)
    args = parser.parse_args()
    tmp = pathlib.Path(args.build_dir) / "Testing" / "Temporary"
    names = failed_names(tmp)
    if not names:
        return 0
    texts = outputs(tmp, set(names))
    print(f"== failed in {args.build_dir}: {len(names)} test(s) ==")
    for name in names:
        lines = [l for l in texts.get(name, []) if not l.startswith("-----")]
        print(f"-- {name} ({len(lines)} output lines)")
        for line in excerpt(lines, args.lines):
            print(f"   {line[:300]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
