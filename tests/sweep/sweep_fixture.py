"""Shared set-up of the plcsweep tests that run plcrun: where the binaries
are, a small campaign of the filling cell, running plcsweep as a process."""

import atexit
import os
import shutil
import subprocess
import sys
import tempfile
import textwrap

SOURCE = os.environ.get("PLC_SOURCE_DIR",
                        os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))
BIN = os.environ.get("PLC_BIN_DIR", os.path.join(SOURCE, "build", "bin"))
PLCRUN = os.path.join(BIN, "plcrun")
PLCSWEEP = os.path.join(BIN, "plcsweep")
CELL = os.path.join(SOURCE, "programs", "filling_cell", "cell.yaml")

# Four scenarios (a grid): two target weights, the safety module's link cut
# for 300 ms at 8 s or not. The F-host's watchdog is 100 ms, so the cut
# passivates it: `passivated_only_at_start` fails in the two scenarios
# with the cut, at the scan where QBAD comes back after the first container.
SMALL = textwrap.dedent("""\
    campaign: small
    base: %s
    duration: 10s
    parameters:
      - path: programs.Cell.init.target_kg
        values: [5.0, 12.0]
    faults:
      - name: safety_cut
        device: safety
        probability: 0.5
        link_down_at: 8s
        link_down_for: 300ms
    checks:
      - name: passivated_only_at_start
        always: "NOT Cell.guard.QBAD OR Cell.containers = 0"
      - name: some_containers
        severity: warning
        eventually: "Cell.containers >= 1"
    outputs: [Cell.containers, Cell.dose.LastNet]
    """)


def temp_dir():
    d = tempfile.mkdtemp(prefix="plcsweep-test-")
    atexit.register(shutil.rmtree, d, True)
    return d


def write_campaign(d, text=None, name="small.yaml"):
    p = os.path.join(d, name)
    with open(p, "w", encoding="utf-8") as f:
        f.write(text if text is not None else SMALL % CELL)
    return p


def plcsweep(*args, timeout=600):
    """(exit code, stdout, stderr) of `plcsweep ARGS`."""
    p = subprocess.run([sys.executable, PLCSWEEP] + list(args), stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True, timeout=timeout)
    return p.returncode, p.stdout, p.stderr


def read(path):
    with open(path, encoding="utf-8") as f:
        return f.read()
