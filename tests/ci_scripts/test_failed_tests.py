#!/usr/bin/env python3
"""scripts/failed-tests.py against ctest logs written here in ctest's own
format (LastTestsFailed.log: 'N:NAME' lines; LastTest.log: one block per
test between 'N/M Testing: NAME' and '<end of output>'): it must name each
failed test, show its first gtest failure and its tail, leave passed tests
out, and print nothing for a folder whose last run had no failure."""
import pathlib
import subprocess
import sys
import tempfile

SCRIPT = sys.argv[1]


def block(n, name, lines, passed):
    out = [f"{n}/3 Testing: {name}", f"{n}/3 Test: {name}", "Command: x", "Directory: /",
           f'"{name}" start time: Dec 03 07:00 UTC', "Output:", "-" * 58, *lines,
           "<end of output>", "Test time =   0.01 sec", "-" * 58,
           "Test Passed." if passed else "Test Failed.", f'"{name}" end time: Dec 03 07:00 UTC', ""]
    return "\n".join(out)


def run(build):
    p = subprocess.run([sys.executable, SCRIPT, str(build), "--lines", "3"],
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        sys.exit(f"FAIL: exit {p.returncode}: {p.stderr}")
    return p.stdout


failures = []
with tempfile.TemporaryDirectory() as tmp:
    build = pathlib.Path(tmp)
    t = build / "Testing" / "Temporary"
    t.mkdir(parents=True)
    gtest = [f"noise {i}" for i in range(20)] + ["a.cpp:7: Failure", "Expected: 1", "Which is: 2"] + \
            [f"after {i}" for i in range(20)]
    t.joinpath("LastTest.log").write_text(
        "Start testing: Dec 03 07:00 UTC\n" + "-" * 58 + "\n" +
        block(1, "Good.Passes", ["fine"], True) +
        block(2, "Bad.Fails", gtest, False) +
        block(3, "Param/Crash.Dies/1-byte object <00>", ["start", "Segmentation fault"], False))
    t.joinpath("LastTestsFailed.log").write_text(
        "2:Bad.Fails\n3:Param/Crash.Dies/1-byte object <00>\n")
    out = run(build)
    for want in ["2 test(s)", "-- Bad.Fails", "a.cpp:7: Failure", "Expected: 1", "after 19",
                 "-- Param/Crash.Dies/1-byte object <00>", "Segmentation fault"]:
        if want not in out:
            failures.append(f"missing {want!r}")
    for unwanted in ["Good.Passes", "noise 0", "after 5"]:
        if unwanted in out:
            failures.append(f"should not show {unwanted!r}")
    t.joinpath("LastTestsFailed.log").unlink()
    if run(build) != "":
        failures.append("printed something for a run without failures")

if failures:
    print("output checks failed:\n  " + "\n  ".join(failures))
    sys.exit(1)
print("ok: failed tests named with their first failure and tail; passed ones left out")
