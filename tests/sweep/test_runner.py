"""plcsweep run with the local executor: results, a failing check's
recording that replays to the same failure, resume, the determinism check,
located errors, the report."""

import json
import os
import signal
import subprocess
import sys
import time
import unittest

import sweep_fixture as F


class LocalCampaign(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = F.temp_dir()
        cls.campaign = F.write_campaign(cls.dir)
        cls.out = os.path.join(cls.dir, "out")
        cls.rc, cls.stdout, cls.stderr = F.plcsweep(
            "run", cls.campaign, "--out", cls.out, "--executor", "local:2",
            "--determinism-sample", "2")

    def records(self):
        with open(os.path.join(self.out, "results.jsonl"), encoding="utf-8") as f:
            return [json.loads(line) for line in f]

    def test_runs_every_scenario_and_fails_those_with_the_cut(self):
        self.assertEqual(self.rc, 0, self.stderr)
        rows = F.read(os.path.join(self.out, "results.csv")).splitlines()
        self.assertEqual(len(rows), 5, rows)
        self.assertTrue(rows[0].startswith("index,hash,status,programs.Cell.init.target_kg,"
                                           "fault:safety_cut,failed_checks,"), rows[0])
        status = {r["index"]: r["status"] for r in self.records()}
        # Grid order: target 5 (no cut, cut), target 12 (no cut, cut).
        self.assertEqual(status, {0: "passed", 1: "failed", 2: "passed", 3: "failed"})
        self.assertIn("passed 2, failed 2", self.stdout)
        self.assertIn("passivated_only_at_start     error    2", self.stdout)

    def test_a_failure_is_recorded_and_replays_to_the_same_failure(self):
        failed = [r for r in self.records() if r["status"] == "failed"]
        self.assertEqual(len(failed), 2)
        for r in failed:
            d = r["failure_dir"]
            for name in ("cell.yaml", "failure.plcrec", "to-failure.cmd", "verdict.json"):
                self.assertTrue(os.path.exists(os.path.join(d, name)), name)
            # The recording, replayed with the same checks: the same verdict.
            res = os.path.join(self.dir, "replayed.json")
            p = subprocess.run([F.PLCRUN, os.path.join(d, "cell.yaml"), "--quiet", "--replay",
                                os.path.join(d, "failure.plcrec"), "--checks",
                                os.path.join(self.out, "campaign.yaml"), "--results-json", res],
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                               timeout=300)
            self.assertEqual(p.returncode, 3, p.stdout)
            self.assertIn("replay: ", p.stdout)
            self.assertIn(", 0 with different outputs", p.stdout)
            replayed = json.loads(F.read(res))
            replayed.pop("timing")
            self.assertEqual(replayed, r["verdict"])
            # The debugger session goes straight to the failing scan: the
            # condition holds one scan before and not at it.
            scan = [c for c in r["verdict"]["checks"] if not c["passed"]][0]["first_fail_scan"]
            cmds = F.read(os.path.join(d, "to-failure.cmd"))
            self.assertIn("goto %d\n" % scan, cmds)
            probe = os.path.join(self.dir, "probe.cmd")
            with open(probe, "w", encoding="utf-8") as f:
                f.write(cmds + "print Cell.guard.QBAD Cell.containers\ngoto %d\n"
                        "print Cell.guard.QBAD\nquit\n" % (scan - 1))
            p = subprocess.run([F.PLCRUN, os.path.join(d, "cell.yaml"), "--replay",
                                os.path.join(d, "failure.plcrec"), "--commands", probe],
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                               timeout=300)
            self.assertEqual(p.returncode, 0, p.stdout)
            # What each `print` answered (the watch list prints at every stop).
            at, before = p.stdout.split("] > print Cell.guard.QBAD")[1:3]
            self.assertIn("\nCell.guard.QBAD = TRUE", at, p.stdout)
            self.assertNotIn("\nCell.containers = 0 ", at, p.stdout)
            self.assertIn("\nCell.guard.QBAD = FALSE", before, p.stdout)

    def test_determinism_sample_agrees(self):
        det = json.loads(F.read(os.path.join(self.out, "determinism.json")))
        self.assertEqual(len(det["sampled"]), 2)
        self.assertEqual(det["mismatches"], [])

    def test_report_is_self_contained(self):
        html = F.read(os.path.join(self.out, "report", "report.html"))
        self.assertGreaterEqual(html.count("src='data:image/png;base64,iVBOR"), 4)
        self.assertNotIn("src='report", html)
        for name in ("param-1.png", "faults.png", "output-1.png", "output-2.png", "wall.png",
                     "summary.txt"):
            self.assertTrue(os.path.exists(os.path.join(self.out, "report", name)), name)
        # `plcsweep report` writes it again from the results folder alone.
        os.remove(os.path.join(self.out, "report", "report.html"))
        rc, stdout, err = F.plcsweep("report", self.out)
        self.assertEqual(rc, 0, err)
        self.assertIn("passed 2, failed 2", stdout)
        self.assertTrue(os.path.exists(os.path.join(self.out, "report", "report.html")))


class Resume(unittest.TestCase):
    def test_a_second_run_skips_finished_scenarios_and_a_cut_record_is_run_again(self):
        d = F.temp_dir()
        c = F.write_campaign(d)
        out = os.path.join(d, "out")
        rc, _, err = F.plcsweep("run", c, "--out", out, "--executor", "local:2",
                                "--determinism-sample", "0", "--no-report")
        self.assertEqual(rc, 0, err)
        csv1 = F.read(os.path.join(out, "results.csv"))
        rc, _, err = F.plcsweep("run", c, "--out", out, "--determinism-sample", "0",
                                "--no-report")
        self.assertEqual(rc, 0, err)
        self.assertIn("4 scenarios of 10s (virtual time), 4 already done", err)
        self.assertEqual(json.loads(F.read(os.path.join(out, "run.json")))["run_now"], 0)
        # A crash in the middle of writing the last record: that scenario is
        # run again, the others are not, and the results are the same.
        path = os.path.join(out, "results.jsonl")
        lines = F.read(path).splitlines(keepends=True)
        with open(path, "w", encoding="utf-8") as f:
            f.writelines(lines[:-1])
            f.write(lines[-1][:40])
        rc, _, err = F.plcsweep("run", c, "--out", out, "--determinism-sample", "0",
                                "--no-report")
        self.assertEqual(rc, 0, err)
        self.assertIn("3 already done", err)
        self.assertEqual(F.read(os.path.join(out, "results.csv")), csv1)


class Interrupted(unittest.TestCase):
    def test_ctrl_c_keeps_the_finished_scenarios_reports_them_and_a_rerun_resumes(self):
        d = F.temp_dir()
        c = F.write_campaign(d)
        out = os.path.join(d, "out")
        # One scenario at a time, 3 virtual minutes each (a few tenths of a
        # second): the interrupt lands after the first record.
        run = subprocess.Popen([sys.executable, F.PLCSWEEP, "run", c, "--out", out, "--executor",
                                "local:1", "--duration", "3m", "--no-record",
                                "--determinism-sample", "0", "--no-report"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               start_new_session=True)
        results = os.path.join(out, "results.jsonl")
        t0 = time.monotonic()
        done_at_interrupt = None
        while run.poll() is None and time.monotonic() - t0 < 300:
            n = len(F.read(results).splitlines()) if os.path.exists(results) else 0
            if n >= 1:
                os.killpg(run.pid, signal.SIGINT)  # Ctrl-C: the whole process group
                done_at_interrupt = n
                break
            time.sleep(0.02)
        _, err = run.communicate(timeout=300)
        interrupted_err = err
        self.assertIsNotNone(done_at_interrupt, "the campaign ended before the interrupt: " + err)
        self.assertLess(done_at_interrupt, 4, "the interrupt came after the last scenario")
        self.assertEqual(run.returncode, 130, err)
        kept = len(F.read(results).splitlines())
        self.assertLess(kept, 4)
        # The report of what finished, from the results folder alone.
        rc, stdout, err = F.plcsweep("report", out)
        self.assertEqual(rc, 0, err)
        self.assertIn("== campaign 'small': 4 scenarios of 180s virtual time ==", stdout)
        self.assertIn("not run %d" % (4 - kept), stdout)
        self.assertTrue(os.path.exists(os.path.join(out, "report", "report.html")))
        self.assertIn("interrupted after %d of 4 scenarios" % kept, interrupted_err)
        # Running it again runs only the rest.
        rc, _, err = F.plcsweep("run", c, "--out", out, "--duration", "3m", "--no-record",
                                "--determinism-sample", "0", "--no-report")
        self.assertEqual(rc, 0, err)
        self.assertIn("%d already done" % kept, err)
        self.assertEqual(len(F.read(os.path.join(out, "results.csv")).splitlines()), 5)


class Determinism(unittest.TestCase):
    def test_a_stored_result_that_differs_is_caught(self):
        d = F.temp_dir()
        c = F.write_campaign(d)
        out = os.path.join(d, "out")
        rc, _, err = F.plcsweep("run", c, "--out", out, "--limit", "2", "--executor", "local:2",
                                "--determinism-sample", "0", "--no-report")
        self.assertEqual(rc, 0, err)
        path = os.path.join(out, "results.jsonl")
        recs = [json.loads(x) for x in F.read(path).splitlines()]
        recs[0]["verdict"]["state_digest"] = "0000000000000000"
        with open(path, "w", encoding="utf-8") as f:
            f.write("".join(json.dumps(r) + "\n" for r in recs))
        rc, _, err = F.plcsweep("run", c, "--out", out, "--limit", "2",
                                "--determinism-sample", "2", "--no-report")
        self.assertEqual(rc, 1, err)
        self.assertIn("determinism: 2 scenarios run again, 1 differ: %s" % recs[0]["hash"], err)


class DemoCampaign(unittest.TestCase):
    def test_the_filling_cells_demo_campaign_reduced_for_ci(self):
        """programs/filling_cell/campaign: 20 of its 1,000 scenarios, 30 s each
        (the README shows the full run's report)."""
        d = F.temp_dir()
        out = os.path.join(d, "out")
        campaign = os.path.join(F.SOURCE, "programs", "filling_cell", "campaign",
                                "filling_campaign.yaml")
        rc, stdout, err = F.plcsweep("run", campaign, "--out", out, "--samples", "20",
                                     "--duration", "30s", "--determinism-sample", "2")
        self.assertEqual(rc, 0, err)
        self.assertIn("== campaign 'filling_demo': 20 scenarios of 30s virtual time ==", stdout)
        self.assertIn("determinism: 2 scenarios run again, 0 differ", err)
        rows = F.read(os.path.join(out, "results.csv")).splitlines()
        self.assertEqual(len(rows), 21)
        self.assertTrue(os.path.exists(os.path.join(out, "report", "report.html")))
        self.assertTrue(os.path.exists(os.path.join(out, "report", "pairs.png")))


class Errors(unittest.TestCase):
    def test_an_unknown_variable_in_a_check_names_the_campaign_line(self):
        d = F.temp_dir()
        text = (F.SMALL % F.CELL).replace("Cell.containers = 0", "Cell.boxes = 0")
        c = F.write_campaign(d, text)
        rc, _, err = F.plcsweep("run", c, "--out", os.path.join(d, "out"))
        self.assertEqual(rc, 2, err)
        self.assertTrue(err.startswith(c + ":15:13: check 'passivated_only_at_start': "), err)
        self.assertIn("Cell.boxes", err)

    def test_expand_into_a_reader_that_stops_early_ends_quietly(self):
        """`plcsweep expand CAMPAIGN | head`: the closed pipe ends the
        listing, without a Python traceback."""
        d = F.temp_dir()
        text = (F.SMALL % F.CELL).replace("values: [5.0, 12.0]",
                                          "range: {from: 5.0, to: 15.0, steps: 500}")
        c = F.write_campaign(d, text)
        p = subprocess.Popen([sys.executable, F.PLCSWEEP, "expand", c, "--config"],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.assertIn('"index": 0', p.stdout.readline())
        p.stdout.close()  # 1,000 configs of ~2 kB: more than a pipe buffers
        err = p.stderr.read()
        p.stderr.close()
        self.assertEqual(p.wait(timeout=120), 0, err)
        self.assertEqual(err, "")

    def test_a_bad_model_param_names_the_overrides(self):
        d = F.temp_dir()
        text = (F.SMALL % F.CELL).replace("link_down_for: 300ms", "link_down_for: 0ms")
        c = F.write_campaign(d, text)
        rc, _, err = F.plcsweep("run", c, "--out", os.path.join(d, "out"), "--limit", "2")
        self.assertEqual(rc, 2, err)
        self.assertIn("link_down_for", err)
        self.assertIn("(%s:12)" % c, err)


if __name__ == "__main__":
    unittest.main()
