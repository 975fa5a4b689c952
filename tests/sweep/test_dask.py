"""The Dask executor against a real cluster on loopback: a dask-scheduler
and two dask-worker processes started here (Debian's python3-distributed),
one of them killed (SIGKILL) while the campaign runs. Its scenario is run
again on the other worker; the results file is the one the local executor
writes, and no scenario is in it twice."""

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
import unittest

import sweep_fixture as F

# Eight scenarios (four targets, the cut on and off) of 60 s virtual time:
# long enough that the kill lands while scenarios are still running.
CAMPAIGN = (F.SMALL % F.CELL).replace("duration: 10s", "duration: 60s").replace(
    "values: [5.0, 12.0]", "values: [5.0, 8.0, 12.0, 16.0]")

# Bound of the campaign on Dask (the whole test takes 50-60 s on a 2-core VM
# at load average 13-20); ctest's TIMEOUT bounds the whole test.
DEADLINE_S = 300


def dask_bin(name):
    return shutil.which(name) or os.path.join("/usr/bin", name)


class DaskCluster:
    """Scheduler and workers on 127.0.0.1 only, no dashboards; stopped by
    close() whatever happened."""

    def __init__(self, d, workers=2):
        self.procs = []
        self.d = d
        sched_file = os.path.join(d, "scheduler.json")
        self.log = open(os.path.join(d, "cluster.log"), "w")
        self.procs.append(self._start([dask_bin("dask-scheduler"), "--host", "127.0.0.1",
                                       "--port", "0", "--no-dashboard", "--scheduler-file",
                                       sched_file]))
        t0 = time.monotonic()
        while not os.path.exists(sched_file):
            if time.monotonic() - t0 > 120:
                raise RuntimeError("dask-scheduler did not start: " + self.tail())
            time.sleep(0.1)
        with open(sched_file) as f:
            self.address = json.load(f)["address"]
        self.workers = []
        for i in range(workers):
            w = self._start([dask_bin("dask-worker"), self.address, "--host", "127.0.0.1",
                             "--nworkers", "1", "--nthreads", "1", "--no-nanny",
                             "--no-dashboard", "--name", "w%d" % i, "--local-directory",
                             os.path.join(d, "w%d" % i)])
            self.workers.append(w)
            self.procs.append(w)
        from distributed import Client
        with Client(self.address, timeout="60s") as c:
            c.wait_for_workers(workers, timeout=120)

    def _start(self, cmd):
        return subprocess.Popen(cmd, stdout=self.log, stderr=subprocess.STDOUT,
                                start_new_session=True)

    def tail(self):
        self.log.flush()
        with open(self.log.name) as f:
            return f.read()[-20000:]

    def close(self):
        for p in reversed(self.procs):
            if p.poll() is None:
                p.send_signal(signal.SIGTERM)
        for p in self.procs:
            try:
                p.wait(timeout=30)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
        self.log.close()


class DaskExecutor(unittest.TestCase):
    def test_a_worker_killed_mid_campaign_changes_nothing_in_the_results(self):
        d = F.temp_dir()
        c = F.write_campaign(d, CAMPAIGN)
        local = os.path.join(d, "local")
        rc, _, err = F.plcsweep("run", c, "--out", local, "--executor", "local:2",
                                "--determinism-sample", "0", "--no-report")
        self.assertEqual(rc, 0, err)

        cluster = DaskCluster(d)
        try:
            out = os.path.join(d, "dask")
            run = subprocess.Popen(
                [sys.executable, F.PLCSWEEP, "run", c, "--out", out, "--executor",
                 "dask://" + cluster.address[len("tcp://"):], "--determinism-sample", "1",
                 "--no-report"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            results = os.path.join(out, "results.jsonl")
            t0 = time.monotonic()
            done_at_kill = None
            while run.poll() is None and time.monotonic() - t0 < DEADLINE_S:
                n = len(F.read(results).splitlines()) if os.path.exists(results) else 0
                if n >= 1:
                    # Both workers are busy with the remaining scenarios:
                    # the worker and its plcrun die as with a machine.
                    os.killpg(cluster.workers[0].pid, signal.SIGKILL)
                    cluster.workers[0].wait()
                    done_at_kill = n
                    break
                time.sleep(0.05)
            try:
                stdout, stderr = run.communicate(timeout=DEADLINE_S)
            except subprocess.TimeoutExpired:
                run.kill()
                run.communicate()
                self.fail("the campaign on Dask took more than %d s: %s" % (DEADLINE_S,
                                                                          cluster.tail()))
            self.assertEqual(run.returncode, 0, stderr + cluster.tail())
            self.assertIsNotNone(done_at_kill, "the campaign ended before the kill")
            self.assertLess(done_at_kill, 8, "the kill came after the last scenario")
            self.assertEqual(F.read(os.path.join(out, "results.csv")),
                             F.read(os.path.join(local, "results.csv")))
            hashes = [json.loads(x)["hash"] for x in F.read(results).splitlines()]
            self.assertEqual(len(hashes), 8)
            self.assertEqual(len(set(hashes)), 8)
            self.assertIn("determinism: 1 scenarios run again, 0 differ", stderr)
            # The scheduler lost the worker with scenarios on it (running and
            # queued; Dask 2022.12's log line) and ran them on the other.
            m = re.search(r"Remove worker <WorkerState '[^']*', name: w0, status: \w+, "
                          r"memory: \d+, processing: (\d+)>", cluster.tail())
            self.assertIsNotNone(m, cluster.tail())
            self.assertGreater(int(m.group(1)), 0, cluster.tail())
            # The recordings of the failures are whole (written once, renamed).
            recs = [json.loads(x) for x in F.read(results).splitlines()]
            for r in recs:
                if r["status"] == "failed":
                    self.assertTrue(os.path.exists(os.path.join(r["failure_dir"],
                                                                "failure.plcrec")))
            self.assertFalse([x for x in os.listdir(os.path.join(out, "failures"))
                              if ".tmp-" in x])
        finally:
            cluster.close()
            if os.environ.get("PLCSWEEP_SHOW_CLUSTER_LOG"):
                print(F.read(os.path.join(d, "cluster.log")))


if __name__ == "__main__":
    unittest.main()
