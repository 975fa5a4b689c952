#!/usr/bin/env python3
"""The instruction-count guard (ctest PerfInstructions.ExampleCells): each
example cell's instructions per simulated ms (callgrind,
scripts/cell_instructions.py) against tests/perf/instructions.baseline.
Fails when a cell costs more than 10 % over its baseline; warns (passes)
when one costs more than 10 % less, asking for a re-record
(scripts/perf-baseline) so that the guard stays tight.

  check_instructions.py --bin build/bin [--baseline FILE] [--jobs N]
"""
import argparse
import pathlib
import shutil
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
sys.dont_write_bytecode = True  # no __pycache__ in the source tree
import cell_instructions  # noqa: E402  (scripts/cell_instructions.py)

TOLERANCE = 0.10


def read_baseline(path):
    """{figure: instructions per simulated ms}, and the commit it names."""
    figures, commit = {}, "unknown"
    for n, line in enumerate(pathlib.Path(path).read_text().splitlines(), 1):
        if line.startswith("# commit:"):
            commit = line.split(":", 1)[1].strip()
        body = line.split("#", 1)[0].split()
        if not body:
            continue
        if len(body) != 2:
            sys.exit(f"{path}:{n}: expected `figure instructions`, got {line!r}")
        figures[body[0]] = float(body[1])
    return figures, commit


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", required=True, help="folder of plcrun")
    ap.add_argument("--baseline", default=str(ROOT / "tests/perf/instructions.baseline"))
    ap.add_argument("--jobs", type=int, help="callgrind runs at a time (default: cores)")
    a = ap.parse_args()
    if shutil.which("valgrind") is None:
        sys.exit("FAIL: valgrind is not installed (scripts/setup installs it)")
    baseline, commit = read_baseline(a.baseline)
    missing = [name for name, _, _ in cell_instructions.CG_CELLS if name not in baseline]
    if missing:
        sys.exit(f"FAIL: {a.baseline} lacks {', '.join(missing)}: scripts/perf-baseline")
    try:
        measured = cell_instructions.instr_per_sim_ms(a.bin, jobs=a.jobs)
    except cell_instructions.CallgrindError as e:
        sys.exit(f"FAIL: {e}")
    print(f"instructions per simulated ms, baseline from commit {commit} ({a.baseline})")
    print(f"{'cell':<36} {'baseline':>10} {'measured':>10} {'change':>8}")
    dearer, cheaper = [], []
    for name, config, _ in cell_instructions.CG_CELLS:
        base, now = baseline[name], measured[name]
        change = now / base - 1
        print(f"{name:<36} {base:>10.0f} {now:>10.0f} {change:>+8.1%}  {config}")
        if change > TOLERANCE:
            dearer.append(name)
        elif change < -TOLERANCE:
            cheaper.append(name)
    if cheaper:
        print(f"WARNING: {', '.join(cheaper)} got more than {TOLERANCE:.0%} cheaper: re-record "
              "the baseline (scripts/perf-baseline) so that the guard stays tight")
    if dearer:
        print(f"FAIL: {', '.join(dearer)} cost more than {TOLERANCE:.0%} over the baseline; "
              "make it cheaper again, or if the cost is meant, re-record (scripts/perf-baseline) "
              "and say why in the commit")
        return 1
    print("OK: every cell within +10 % of its baseline")
    return 0


if __name__ == "__main__":
    sys.exit(main())
