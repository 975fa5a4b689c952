"""Instructions per simulated ms of the example cells, counted by callgrind.

plcrun runs a cell in virtual time, so the instructions it executes repeat
from run to run to within about 1 % (the runtime's helper threads, e.g.
the watchdog's, add a few instructions that vary: 0.1 % of the filling
cells' thousands per ms, 1 % of the conveyor's 48): unlike a time, the count shows what
a change costs on a shared, loaded machine. Per cell: (instructions of `plcrun CELL
--virtual --for 3s -q` - those of `--for 1s`) / 2,000 (the conveyor: 21 s,
/ 20,000), so that start-up and shut-down cancel out. scripts/bench prints these figures,
scripts/perf-baseline records them in tests/perf/instructions.baseline and
the ctest PerfInstructions.ExampleCells (tests/perf) compares with them.
"""
import concurrent.futures
import os
import pathlib
import re
import shlex
import subprocess
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[1]

# (figure, config, long run in s): the cells whose instructions per
# simulated ms are counted, as (long run - 1 s run) / (long - 1) s. The
# conveyor (48 per ms, one 10 ms task) runs 21 s: over 2 s the few thousand
# instructions by which runs differ were 4 % of its count, over 20 s 0.4 %.
CG_CELLS = [("demo_instr_per_sim_ms", "programs/demo/cell.yaml", 3),
            ("filling_instr_per_sim_ms", "programs/filling_cell/cell.yaml", 3),
            ("filling_profinet_instr_per_sim_ms", "programs/filling_cell/cell_profinet.yaml", 3),
            ("conveyor_instr_per_sim_ms", "programs/conveyor/cell.yaml", 21)]

SHORT_S = 1


class CallgrindError(RuntimeError):
    pass


def run_callgrind(program, what, valgrind="valgrind", main_thread=False):
    """Instructions of `program` (a list: the executable and its arguments,
    "{tmp}" in them a temporary folder) under callgrind: of the whole
    process, or with main_thread of its main thread alone
    (--separate-threads). `what` names the run in errors."""
    with tempfile.TemporaryDirectory(prefix="plc-callgrind-") as tmp:
        out = pathlib.Path(tmp) / "callgrind.out"
        cmd = [valgrind, "--tool=callgrind", f"--callgrind-out-file={out}",
               *(["--separate-threads=yes"] if main_thread else []),
               *[a.replace("{tmp}", tmp) for a in program]]
        p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if p.returncode != 0:
            raise CallgrindError(f"{shlex.join(cmd)} failed with exit code {p.returncode}:\n"
                                 f"{p.stderr[-2000:]}")
        result = pathlib.Path(f"{out}-01") if main_thread else out
        if not result.exists():
            raise CallgrindError(f"callgrind wrote no file {result.name}")
        text = result.read_text(errors="replace")
    m = re.search(r"^summary: (\d+)", text, re.M) or re.search(r"^totals: (\d+)", text, re.M)
    if not m:
        raise CallgrindError(f"no instruction total in callgrind's output of {what}")
    return int(m.group(1))


def callgrind_ir(bin_dir, config, seconds, valgrind="valgrind", extra=(), main_thread=False):
    """Instructions of `plcrun CONFIG --virtual --for SECONDS [EXTRA]` under
    callgrind: of the whole process, or with main_thread of plcrun's main
    thread alone (--separate-threads; the scan thread in virtual time).
    "{tmp}" in `extra` is a temporary folder (for files the run writes)."""
    program = [str(pathlib.Path(bin_dir) / "plcrun"), str(ROOT / config), "--virtual", "--for",
               f"{seconds}s", "-q", *extra]
    return run_callgrind(program, config, valgrind, main_thread)


def instr_per_sim_ms(bin_dir, cells=None, jobs=None, valgrind="valgrind"):
    """{figure: instructions per simulated ms} of `cells` (default CG_CELLS).
    The 2 x len(cells) callgrind runs go `jobs` at a time (default: one per
    core): each is single-threaded work, and the counts do not depend on
    what runs beside them."""
    cells = CG_CELLS if cells is None else cells
    jobs = jobs or os.cpu_count() or 1
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        runs = {(name, s): pool.submit(callgrind_ir, bin_dir, config, s, valgrind)
                for name, config, long_s in cells for s in (long_s, SHORT_S)}
        return {name: (runs[(name, long_s)].result() - runs[(name, SHORT_S)].result()) /
                ((long_s - SHORT_S) * 1000) for name, _, long_s in cells}


# The debugger's cost on the scan thread: the filling cell (one task of
# 1 ms: one scan per simulated ms) with a trace of 100 of its variables, and
# with a recording, against the plain cell; callgrind --separate-threads
# counts the scan thread (plcrun's main thread in virtual time) apart from
# the writer threads that format the trace and write the recording.
DEBUG_CELL = "programs/filling_cell/cell.yaml"
DEBUG_LONG_S = 3


def trace_vars(bin_dir, config, n=100):
    """The first n scalar, unlocated variables of `plcrun CONFIG --list-vars`."""
    p = subprocess.run([str(pathlib.Path(bin_dir) / "plcrun"), str(ROOT / config), "--list-vars"],
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        raise CallgrindError(f"plcrun {config} --list-vars failed: {p.stderr[-500:]}")
    names = [line.split()[0] for line in p.stdout.splitlines()
             if line.strip() and "%" not in line and "STRING" not in line]
    if len(names) < n:
        raise CallgrindError(f"{config} has {len(names)} traceable variables, not {n}")
    return names[:n]


def debugger_scan_costs(bin_dir, jobs=None, valgrind="valgrind"):
    """{figure: scan-thread instructions per scan} of a trace of 100
    variables and of a recording, each over the plain cell."""
    modes = {"plain": [],
             "trace100_scan_thread_instr_per_scan":
                 ["--trace", "{tmp}/trace.csv", "--trace-vars",
                  ",".join(trace_vars(bin_dir, DEBUG_CELL))],
             "record_scan_thread_instr_per_scan": ["--record", "{tmp}/cell.rec"]}
    jobs = jobs or os.cpu_count() or 1
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        runs = {(name, s): pool.submit(callgrind_ir, bin_dir, DEBUG_CELL, s, valgrind, extra, True)
                for name, extra in modes.items() for s in (DEBUG_LONG_S, SHORT_S)}
        per_ms = {name: (runs[(name, DEBUG_LONG_S)].result() - runs[(name, SHORT_S)].result()) /
                  ((DEBUG_LONG_S - SHORT_S) * 1000) for name in modes}
    return {name: per_ms[name] - per_ms["plain"] for name in modes if name != "plain"}


# The same two costs on the cell bench_debugger times (its own program of
# 100 variables that change every scan, with the default 5 KB image, the
# debugger attached): `bench_debugger --count-scans MODE N` runs N scans
# and nothing else; (scans of the long run - those of the short) / their
# difference, against the idle debugger, scan thread only.
BENCH_SCANS = (2000, 6000)


def bench_cell_ir(bin_dir, mode, scans, valgrind="valgrind"):
    program = [str(pathlib.Path(bin_dir) / "bench_debugger"), "--count-scans", mode, str(scans)]
    return run_callgrind(program, f"bench_debugger {mode}", valgrind, main_thread=True)


def bench_cell_scan_costs(bin_dir, jobs=None, valgrind="valgrind"):
    """{figure: scan-thread instructions per scan} of a trace of the 100
    variables and of a recording on bench_debugger's cell."""
    modes = {"idle": None, "trace100_bench_cell_instr_per_scan": "trace",
             "record_bench_cell_instr_per_scan": "record"}
    short, long_ = BENCH_SCANS
    jobs = jobs or os.cpu_count() or 1
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        runs = {(name, n): pool.submit(bench_cell_ir, bin_dir, mode or "idle", n, valgrind)
                for name, mode in modes.items() for n in BENCH_SCANS}
        per_scan = {name: (runs[(name, long_)].result() - runs[(name, short)].result()) /
                    (long_ - short) for name in modes}
    return {name: per_scan[name] - per_scan["idle"] for name in modes if name != "idle"}
