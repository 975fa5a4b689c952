#!/usr/bin/python3
"""Scenario campaigns (plcsweep, docs/campaigns.md): throughput and overheads
on the filling cell, 10 simulated minutes per scenario. Prints
`name: value unit` lines like the other benchmarks.

  tests/bench/bench_sweep.py [--scenarios N] [--duration 10m] [--no-dask]

Uses build/bin/plcrun and build/bin/plcsweep (scripts/build first) and the
first N scenarios of programs/filling_cell/campaign/filling_campaign.yaml.
Measures, each over the same N scenarios:
  bare        plcrun SCENARIO --for D, one after the other
  checks      the same with the campaign's --checks (3 conditions per scan)
  record      the same with --record: what recording every scenario would cost
  sweep_1     plcsweep run --executor local:1 (--no-record, no determinism
              re-runs, no report): the runner's overhead per scenario against
              `checks`, its fixed cost taken out
  fixed       the same command again into the same folder: every scenario is
              done, so it does only what a campaign pays once (expansion of
              the campaign's 1,000 scenarios, validation, the results files)
  local       plcsweep run --executor local (one process per core)
  dask        plcsweep run against a dask-scheduler with one single-threaded
              dask-worker per core, on loopback
The per-core figures are CPU seconds per scenario (user + system, plcrun
included): on a shared machine the figure that other load inflates least.
They leave out the fixed costs (plcsweep's start-up; on Dask the cluster's
start-up), which are printed on their own; the Dask figure includes what
the scheduler and the workers spend while the campaign runs (their CPU
clocks from /proc, before and after).
"""

import argparse
import json
import os
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BIN = os.environ.get("PLC_BIN_DIR", os.path.join(ROOT, "build", "bin"))
CAMPAIGN = os.path.join(ROOT, "programs", "filling_cell", "campaign", "filling_campaign.yaml")
sys.path.insert(0, os.path.join(ROOT, "runtime", "plcsweep"))

from plcsweep import campaign as C  # noqa: E402
from plcsweep import iec_time  # noqa: E402


def cpu():
    """CPU seconds (user + sys) of every child process waited for so far:
    on a shared machine the figure that load does not inflate."""
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def line(name, value, unit):
    print("%s: %s %s" % (name, ("%.4g" % value) if isinstance(value, float) else value, unit),
          flush=True)


def run_plain(scenarios, duration, tmp, extra):
    """Wall seconds of plcrun over every scenario, one after the other."""
    total = 0.0
    sizes = []
    c0 = cpu()
    for s in scenarios:
        cfg = os.path.join(tmp, "cell.yaml")
        with open(cfg, "w") as f:
            f.write(s.config_text)
        args = [a.replace("{rec}", os.path.join(tmp, "r.plcrec")) for a in extra]
        t0 = time.monotonic()
        p = subprocess.run([os.path.join(BIN, "plcrun"), cfg, "--virtual", "--quiet", "--for",
                            duration] + args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                           text=True)
        total += time.monotonic() - t0
        if p.returncode not in (0, 3):
            sys.exit("plcrun failed: " + p.stderr)
        if os.path.exists(os.path.join(tmp, "r.plcrec")):
            sizes.append(os.path.getsize(os.path.join(tmp, "r.plcrec")))
            os.remove(os.path.join(tmp, "r.plcrec"))
    return total, cpu() - c0, sizes


def run_sweep(n, duration, out, executor):
    c0 = cpu()
    t0 = time.monotonic()
    p = subprocess.run([sys.executable, os.path.join(BIN, "plcsweep"), "run", CAMPAIGN, "--out",
                        out, "--limit", str(n), "--duration", duration, "--executor", executor,
                        "--no-record", "--determinism-sample", "0", "--no-report"],
                       stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    wall = time.monotonic() - t0
    if p.returncode != 0:
        sys.exit("plcsweep failed: " + p.stderr)
    with open(os.path.join(out, "run.json")) as f:
        loop = json.load(f)["elapsed_s"]
    return wall, loop, cpu() - c0  # the whole command; the scenarios' loop alone; CPU


def proc_cpu(pids):
    """CPU seconds of these processes and of their children they waited
    for (a worker's plcrun runs), from /proc/PID/stat."""
    tick = os.sysconf("SC_CLK_TCK")
    total = 0
    for pid in pids:
        with open("/proc/%d/stat" % pid) as f:
            fields = f.read().rsplit(")", 1)[1].split()
        total += sum(int(x) for x in fields[11:15])  # utime stime cutime cstime
    return total / tick


def start_dask(tmp, workers):
    sched_file = os.path.join(tmp, "scheduler.json")
    log = open(os.path.join(tmp, "dask.log"), "w")
    procs = [subprocess.Popen(["dask-scheduler", "--host", "127.0.0.1", "--port", "0",
                               "--no-dashboard", "--scheduler-file", sched_file],
                              stdout=log, stderr=subprocess.STDOUT, start_new_session=True)]
    t0 = time.monotonic()
    while not os.path.exists(sched_file) and time.monotonic() - t0 < 120:
        time.sleep(0.1)
    with open(sched_file) as f:
        address = json.load(f)["address"]
    for i in range(workers):
        procs.append(subprocess.Popen(
            ["dask-worker", address, "--host", "127.0.0.1", "--nthreads", "1", "--no-nanny",
             "--no-dashboard", "--local-directory", os.path.join(tmp, "w%d" % i)],
            stdout=log, stderr=subprocess.STDOUT, start_new_session=True))
    from distributed import Client
    with Client(address, timeout="60s") as c:
        c.wait_for_workers(workers, timeout=120)
    return address, procs


def stop(procs):
    for p in reversed(procs):
        if p.poll() is None:
            p.send_signal(signal.SIGTERM)
    for p in procs:
        try:
            p.wait(timeout=30)
        except subprocess.TimeoutExpired:
            p.kill()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenarios", type=int, default=8)
    ap.add_argument("--duration", default="10m")
    ap.add_argument("--no-dask", action="store_true")
    a = ap.parse_args()
    cores = os.cpu_count() or 1
    c = C.load(CAMPAIGN)
    c.duration_ns = iec_time.parse(a.duration)
    c.duration_text = iec_time.format_ns(c.duration_ns)
    scenarios = C.expand(c)[:a.scenarios]
    n = len(scenarios)
    scans = c.duration_ns // 10**6  # the filling cell's one 1 ms task
    tmp = tempfile.mkdtemp(prefix="bench-sweep-")
    try:
        line("sweep_scenarios", n, "scenarios of %s" % c.duration_text)
        line("sweep_cores", cores, "cores")
        line("sweep_load_before", os.getloadavg()[0], "(1-min load average)")
        bare, bare_cpu, _ = run_plain(scenarios, c.duration_text, tmp, [])
        line("sweep_bare_plcrun_wall_per_scenario", bare / n, "s")
        line("sweep_bare_plcrun_cpu_per_scenario", bare_cpu / n, "s")
        line("sweep_bare_scenarios_per_min_per_core", 60 * n / bare_cpu, "scenarios/min (CPU)")
        checks, checks_cpu, _ = run_plain(scenarios, c.duration_text, tmp,
                                          ["--checks", CAMPAIGN])
        line("sweep_checks_cpu_per_scenario", checks_cpu / n, "s")
        line("sweep_checks_overhead_per_scan", (checks_cpu - bare_cpu) / n / scans * 1e9,
             "ns (CPU; 3 conditions, 5 outputs)")
        rec, rec_cpu, sizes = run_plain(scenarios, c.duration_text, tmp,
                                        ["--checks", CAMPAIGN, "--record", "{rec}"])
        line("sweep_record_overhead_per_scenario", (rec_cpu - checks_cpu) / n, "s (CPU)")
        line("sweep_record_bytes_per_scenario", sum(sizes) / len(sizes) / 1e6, "MB")
        one_out = os.path.join(tmp, "one")
        one, loop, one_cpu = run_sweep(n, c.duration_text, one_out, "local:1")
        fixed, _, fixed_cpu = run_sweep(n, c.duration_text, one_out, "local:1")
        line("sweep_local1_wall_per_scenario", loop / n, "s")
        line("sweep_runner_overhead_per_scenario", (one_cpu - fixed_cpu - checks_cpu) / n * 1000,
             "ms (CPU; plcsweep local:1 against plcrun --checks)")
        line("sweep_runner_fixed_cost", fixed_cpu, "s (CPU, once per campaign: expand 1,000 "
             "scenarios, validate, write the results)")
        line("sweep_runner_fixed_cost_wall", fixed, "s")
        # Throughput: the wall time of the scenario loop (whole machine, other
        # load included) and CPU per scenario (per core), fixed costs out.
        _, local, local_cpu = run_sweep(n, c.duration_text, os.path.join(tmp, "local"), "local")
        local_cpu -= fixed_cpu
        line("sweep_local_scenarios_per_min", 60 * n / local, "scenarios/min (wall, %d cores)"
             % cores)
        line("sweep_local_cpu_per_scenario", local_cpu / n, "s")
        line("sweep_local_scenarios_per_min_per_core", 60 * n / local_cpu,
             "scenarios/min (CPU)")
        if not a.no_dask:
            c0 = cpu()
            address, procs = start_dask(tmp, cores)
            try:
                pids = [p.pid for p in procs]
                k0 = proc_cpu(pids)
                dask_out = os.path.join(tmp, "dask")
                executor = "dask://" + address[len("tcp://"):]
                _, dask, client_cpu = run_sweep(n, c.duration_text, dask_out, executor)
                k1 = proc_cpu(pids)
                _, _, client_fixed = run_sweep(n, c.duration_text, dask_out, executor)
            finally:
                stop(procs)
            dask_cpu = k1 - k0 + client_cpu - client_fixed
            line("sweep_dask_scenarios_per_min", 60 * n / dask, "scenarios/min (wall, %d workers)"
                 % cores)
            line("sweep_dask_cpu_per_scenario", dask_cpu / n, "s (scheduler and workers included)")
            line("sweep_dask_scenarios_per_min_per_core", 60 * n / dask_cpu,
                 "scenarios/min (CPU)")
            # Reaped: everything the cluster spent, start-up included.
            line("sweep_dask_cluster_fixed_cost", cpu() - c0 - client_cpu - client_fixed
                 - (k1 - k0), "s (CPU: scheduler and workers start and stop)")
        line("sweep_load_after", os.getloadavg()[0], "(1-min load average)")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
