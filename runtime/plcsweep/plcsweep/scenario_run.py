"""One scenario, run where the executor puts it (a local process, a Dask
worker): plcrun in virtual time with the campaign's checks. Standard
library only, so a Dask worker needs nothing but Python and plcrun.

A failing scenario is run a second time with --record (runs are
deterministic, so recording every scenario and deleting the passing ones
would write ~40 MB per 10-minute scenario for nothing); the second run's
verdict must equal the first one byte for byte, else the scenario is
reported as not deterministic. Its folder under failures/ holds the cell
config, the recording, the verdict and a debugger command file that puts
`plcrun --replay ... --debug` at the failing scan (goto).
"""

import json
import os
import shutil
import socket
import subprocess
import tempfile
import time

# plcrun's exit codes (runtime/plcrun/cli.hpp).
RC_PASSED, RC_RUNTIME_FAILURE, RC_BAD_CONFIG, RC_CHECK_FAILED = 0, 1, 2, 3


def verdict_without_timing(verdict):
    """The part of plcrun's --results-json that depends on the config alone."""
    return {k: v for k, v in verdict.items() if k != "timing"}


def canonical(verdict):
    return json.dumps(verdict_without_timing(verdict), sort_keys=True, separators=(",", ":"))


def _plcrun(task, workdir, results, record=None):
    cmd = [task["plcrun"], os.path.join(workdir, "cell.yaml"), "--virtual", "--quiet",
           "--for", task["duration"], "--checks", task["checks_file"], "--results-json", results]
    if record:
        cmd += ["--record", record]
    t0 = time.monotonic()
    p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                       timeout=task.get("timeout_s"))
    wall = time.monotonic() - t0
    verdict = None
    if p.returncode in (RC_PASSED, RC_CHECK_FAILED) and os.path.exists(results):
        with open(results, encoding="utf-8") as f:
            verdict = json.load(f)
    return p.returncode, verdict, wall, p.stderr[-2000:]


def first_failure(verdict):
    """(scan, check) of the earliest failed check of severity error."""
    best = None
    for c in verdict.get("checks", []):
        if not c["passed"] and c["severity"] == "error":
            if best is None or c["first_fail_scan"] < best[0]:
                best = (c["first_fail_scan"], c)
    return best


def _write_failure_dir(task, workdir, verdict, record):
    dest = os.path.join(task["out_dir"], "failures", task["hash"])
    tmp = dest + ".tmp-%d" % os.getpid()
    shutil.rmtree(tmp, ignore_errors=True)
    os.makedirs(tmp)
    shutil.copy(os.path.join(workdir, "cell.yaml"), os.path.join(tmp, "cell.yaml"))
    shutil.move(record, os.path.join(tmp, "failure.plcrec"))
    with open(os.path.join(tmp, "verdict.json"), "w", encoding="utf-8") as f:
        json.dump(verdict, f, indent=1, sort_keys=True)
    scan, check = first_failure(verdict)
    names = " ".join(sorted({v for c in verdict["checks"] for v in _paths(c["condition"])}))
    with open(os.path.join(tmp, "to-failure.cmd"), "w", encoding="utf-8") as f:
        f.write("# scenario %s: check '%s' (%s %s) failed at scan %d, t=%s s\n"
                % (task["hash"], check["name"], check["kind"], check["condition"], scan,
                   check["first_fail_time_s"]))
        f.write("# plcrun cell.yaml --replay failure.plcrec --commands to-failure.cmd --debug\n")
        if names:
            f.write("watch %s\n" % names)
        f.write("goto %d\n" % scan)
    # Replaces an earlier attempt's folder whole (a worker killed after it
    # wrote one, then the scenario retried elsewhere).
    shutil.rmtree(dest, ignore_errors=True)
    os.rename(tmp, dest)
    return dest


def _paths(condition):
    """Variable paths in a condition (for the debugger's watch list)."""
    out = []
    word = ""
    for ch in condition + " ":
        if ch.isalnum() or ch in "._[]%":
            word += ch
        else:
            if "." in word and not word[0].isdigit() and not word.startswith("%"):
                out.append(word)
            word = ""
    return out


def run_scenario(task):
    """task: hash, index, config_text, duration, checks_file, plcrun, out_dir,
    record_failures, verify_failures. Returns the result record (a dict)."""
    result = {"hash": task["hash"], "index": task["index"], "params": task["params"],
              "faults": task["faults"], "host": socket.gethostname(), "pid": os.getpid()}
    workdir = tempfile.mkdtemp(prefix="plcsweep-%s-" % task["hash"])
    try:
        with open(os.path.join(workdir, "cell.yaml"), "w", encoding="utf-8") as f:
            f.write(task["config_text"])
        rc, verdict, wall, err = _plcrun(task, workdir, os.path.join(workdir, "verdict.json"))
        result["wall_s"] = wall
        if verdict is None:
            result.update(status="error", rc=rc, error=err.strip().splitlines()[-1:] or [""])
            result["error"] = result["error"][0]
            return result
        result.update(status="passed" if rc == RC_PASSED else "failed", rc=rc,
                      verdict=verdict_without_timing(verdict),
                      plcrun_wall_s=verdict.get("timing", {}).get("wall_s"))
        if rc == RC_CHECK_FAILED and task.get("record_failures", True):
            record = os.path.join(workdir, "failure.plcrec")
            rc2, verdict2, wall2, err2 = _plcrun(task, workdir,
                                                 os.path.join(workdir, "verdict2.json"), record)
            result["record_wall_s"] = wall2
            if verdict2 is None or rc2 != rc or canonical(verdict2) != canonical(verdict):
                result["status"] = "nondeterministic"
                result["error"] = "the recorded re-run gave another verdict (rc %d)" % rc2
            else:
                result["failure_dir"] = _write_failure_dir(task, workdir, verdict, record)
        return result
    except subprocess.TimeoutExpired:
        result.update(status="error", rc=-1, error="timed out after %s s" % task.get("timeout_s"))
        return result
    finally:
        shutil.rmtree(workdir, ignore_errors=True)
