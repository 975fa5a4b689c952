"""plcsweep: scenario campaigns of a cell in virtual time (docs/campaigns.md).

  plcsweep run CAMPAIGN.yaml [--out DIR] [--executor local|local:N|dask://HOST:PORT]
  plcsweep expand CAMPAIGN.yaml         the scenarios as JSON lines, nothing run
  plcsweep report DIR                   the report of a campaign's results again

Exit codes: 0 the campaign ran (failed checks are results, see the summary),
1 scenarios could not run (errors) or a determinism re-run disagreed,
2 a bad campaign file or command line.
"""

import argparse
import json
import os
import random
import shutil
import subprocess
import sys
import tempfile
import time

from . import campaign as C
from . import executors, iec_time, progress, results, scenario_run, summary
from .yaml_nodes import CampaignError


def default_plcrun():
    here = os.path.dirname(os.path.abspath(sys.argv[0]))
    cand = os.path.join(here, "plcrun")
    if os.path.exists(cand):
        return cand
    return shutil.which("plcrun") or "plcrun"


def make_task(c, s, args, checks_file):
    return {"hash": s.hash, "index": s.index, "params": s.params, "faults": s.faults,
            "config_text": s.config_text, "duration": c.duration_text,
            "checks_file": checks_file, "plcrun": args.plcrun, "out_dir": args.out,
            "record_failures": not args.no_record, "timeout_s": args.timeout}


def validate(c, scenarios, args, checks_file):
    """One scan of the first scenario of each combination of faults: plcrun
    checks the config, the models' params and the checks before anything
    long starts."""
    seen = set()
    for s in scenarios:
        key = tuple(sorted(s.faults))
        if key in seen or len(seen) >= 16:
            continue
        seen.add(key)
        err = validate_one(c, s, args, checks_file)
        if err:
            return err
    return None


def validate_one(c, scenario, args, checks_file):
    with tempfile.TemporaryDirectory(prefix="plcsweep-validate-") as d:
        cfg = os.path.join(d, "cell.yaml")
        with open(cfg, "w", encoding="utf-8") as f:
            f.write(scenario.config_text)
        try:
            p = subprocess.run([args.plcrun, cfg, "--virtual", "--quiet", "--cycles", "1",
                                "--checks", checks_file], stdout=subprocess.DEVNULL,
                               stderr=subprocess.PIPE, text=True, timeout=120)
        except OSError as e:
            return "cannot run plcrun '%s': %s" % (args.plcrun, e.strerror)
        if p.returncode == scenario_run.RC_BAD_CONFIG:
            # The checks file is the campaign's copy: name the campaign itself.
            msg = p.stderr.strip().replace(checks_file, c.file)
            if cfg in msg:
                msg = msg.replace(cfg, "scenario %s (the base config %s with the campaign's "
                                  "overrides)" % (scenario.hash, c.base_file))
                msg += "\n" + "\n".join("  %s = %s  (%s:%d)" % (p_, v, c.file, w.start_mark.line + 1)
                                        for p_, v, w in scenario.overrides)
            return msg
    return None


def select_sample(scenarios, store, n, seed):
    done = [s for s in scenarios if s.hash in store.records and
            store.records[s.hash]["status"] in ("passed", "failed")]
    rng = random.Random("%d:determinism" % seed)
    return rng.sample(done, min(n, len(done)))


def determinism_check(c, sample, args, checks_file, store):
    """Runs each sampled scenario again and compares plcrun's verdicts byte
    for byte (final values, check results, the digest of every variable)."""
    tasks = [dict(make_task(c, s, args, checks_file), record_failures=False) for s in sample]
    mismatches = []
    for r in run_tasks(tasks, args):
        first = store.records[r["hash"]]
        a = json.dumps(first.get("verdict"), sort_keys=True)
        b = json.dumps(r.get("verdict"), sort_keys=True)
        if a != b:
            mismatches.append(r["hash"])
    out = {"sampled": [s.hash for s in sample], "mismatches": mismatches}
    with open(os.path.join(args.out, "determinism.json"), "w", encoding="utf-8") as f:
        json.dump(out, f, indent=1)
    return out


def run_tasks(tasks, args):
    kind, where = executors.parse(args.executor)
    if kind == "local":
        return executors.run_local(tasks, args.jobs or where)
    return executors.run_dask(tasks, where)


def write_meta(out, meta):
    tmp = os.path.join(out, "run.json.tmp")
    with open(tmp, "w", encoding="utf-8") as f:
        json.dump(meta, f, indent=1)
    os.replace(tmp, os.path.join(out, "run.json"))


def cmd_run(args):
    try:
        c = C.load(args.campaign)
        if args.samples is not None:
            if c.sampling == "grid":
                raise CampaignError(c.file, None, "--samples applies to sampling random or lhs")
            c.samples = args.samples
        if args.duration is not None:
            ns = iec_time.parse(args.duration)
            if not ns or ns <= 0:
                print("plcsweep: --duration: '%s' is not a duration" % args.duration,
                      file=sys.stderr)
                return 2
            c.duration_ns, c.duration_text = ns, iec_time.format_ns(ns)
        scenarios = C.expand(c)
    except CampaignError as e:
        print(e, file=sys.stderr)
        return 2
    if args.limit is not None:
        scenarios = scenarios[:args.limit]
    if not scenarios:
        print("plcsweep: the campaign has no scenarios", file=sys.stderr)
        return 2
    args.out = os.path.abspath(args.out or os.path.splitext(os.path.basename(c.file))[0] + ".out")
    os.makedirs(args.out, exist_ok=True)
    checks_file = os.path.join(args.out, "campaign.yaml")
    with open(checks_file, "w", encoding="utf-8") as f:
        f.write(c.text)
    try:
        executors.parse(args.executor)
    except ValueError as e:
        print("plcsweep: --executor: %s" % e, file=sys.stderr)
        return 2
    err = validate(c, scenarios, args, checks_file)
    if err:
        print(err, file=sys.stderr)
        return 2
    store = results.ResultStore(args.out)
    pending = [s for s in scenarios if not store.done(s.hash)]
    print("plcsweep: campaign '%s': %d scenarios of %s (virtual time), %d already done, "
          "executor %s" % (c.name, len(scenarios), c.duration_text, len(scenarios) - len(pending),
                           args.executor or "local"), file=sys.stderr)
    meta = {"campaign": c.name, "file": os.path.abspath(c.file), "scenarios": len(scenarios),
            "duration": c.duration_text, "samples": c.samples, "executor": args.executor or "local",
            "elapsed_s": None, "run_now": len(pending)}
    # Written before the scenarios run, so that `plcsweep report` works on
    # the results of a run that was interrupted.
    write_meta(args.out, meta)
    t0 = time.monotonic()
    bar = progress.Progress(len(pending))
    try:
        for r in run_tasks([make_task(c, s, args, checks_file) for s in pending], args):
            store.add(r)
            bar.update(r["status"])
    except KeyboardInterrupt:
        bar.finish()
        store.close()
        results.write_csv(args.out, c, scenarios, store.records)
        print("plcsweep: interrupted after %d of %d scenarios; `plcsweep run` again resumes, "
              "`plcsweep report %s` reports those"
              % (sum(1 for s in pending if s.hash in store.records), len(pending), args.out),
              file=sys.stderr)
        return 130
    bar.finish()
    meta["elapsed_s"] = time.monotonic() - t0
    # A worker that died while it wrote a failure's folder left it half
    # done under a temporary name; the retry wrote the whole one.
    fdir = os.path.join(args.out, "failures")
    if os.path.isdir(fdir):
        for name in os.listdir(fdir):
            if ".tmp-" in name:
                shutil.rmtree(os.path.join(fdir, name), ignore_errors=True)
    rc = 0
    det = None
    if args.determinism_sample > 0:
        sample = select_sample(scenarios, store, args.determinism_sample, c.seed)
        det = determinism_check(c, sample, args, checks_file, store)
        print("plcsweep: determinism: %d scenarios run again, %d differ%s"
              % (len(det["sampled"]), len(det["mismatches"]),
                 (": " + " ".join(det["mismatches"])) if det["mismatches"] else ""),
              file=sys.stderr)
        if det["mismatches"]:
            rc = 1
    store.close()
    results.write_csv(args.out, c, scenarios, store.records)
    write_meta(args.out, meta)
    recs = [store.records[s.hash] for s in scenarios if s.hash in store.records]
    if any(r["status"] in ("error", "nondeterministic") for r in recs):
        rc = 1
    if not args.no_report:
        from . import report  # matplotlib: loaded only for a report
        path = report.write(args.out, c, scenarios, store.records, meta)
        print("plcsweep: report %s" % path, file=sys.stderr)
    print(summary.text(c, scenarios, store.records, meta), end="")
    return rc


def cmd_expand(args):
    try:
        c = C.load(args.campaign)
        if args.samples is not None and c.sampling != "grid":
            c.samples = args.samples
        scenarios = C.expand(c)
    except CampaignError as e:
        print(e, file=sys.stderr)
        return 2
    try:
        for s in scenarios:
            line = {"index": s.index, "hash": s.hash, "params": s.params, "faults": s.faults}
            if args.config:
                line["config"] = s.config_text
            print(json.dumps(line, sort_keys=True))
        sys.stdout.flush()
    except BrokenPipeError:
        # The reader has what it wanted (`| head`); Python's flush of
        # stdout at exit would fail again, so stdout goes nowhere now.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    return 0


def cmd_report(args):
    """The report of a results folder again (e.g. after a resumed run was
    interrupted): the campaign as it was run (OUT/campaign.yaml, its base
    taken from where the campaign file was)."""
    try:
        with open(os.path.join(args.dir, "run.json"), encoding="utf-8") as f:
            meta = json.load(f)
        with open(os.path.join(args.dir, "campaign.yaml"), encoding="utf-8") as f:
            text = f.read()
    except OSError as e:
        print("plcsweep: %s is not a results folder (%s)" % (args.dir, e), file=sys.stderr)
        return 2
    try:
        c = C.parse(text, meta["file"])
        if meta.get("duration"):
            c.duration_ns = iec_time.parse(meta["duration"])
            c.duration_text = meta["duration"]
        if meta.get("samples"):
            c.samples = meta["samples"]
        scenarios = C.expand(c)
    except CampaignError as e:
        print(e, file=sys.stderr)
        return 2
    store = results.ResultStore(args.dir)
    store.close()
    # The scenarios that run had (its --limit), those not run yet counted.
    scenarios = scenarios[:meta.get("scenarios", len(scenarios))]
    from . import report  # matplotlib: loaded only for a report
    print("plcsweep: report %s" % report.write(args.dir, c, scenarios, store.records, meta),
          file=sys.stderr)
    print(summary.text(c, scenarios, store.records, meta), end="")
    return 0


def main(argv=None):
    ap = argparse.ArgumentParser(prog="plcsweep", description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run", help="expand the campaign and run its scenarios")
    r.add_argument("campaign")
    r.add_argument("--out", help="results folder (default: CAMPAIGN.out in the current folder)")
    r.add_argument("--executor", default="local",
                   help="local (a process per core), local:N, or dask://HOST:PORT")
    r.add_argument("--jobs", type=int, help="processes of the local executor")
    r.add_argument("--plcrun", default=default_plcrun(),
                   help="the plcrun to run (on Dask: its path on the workers)")
    r.add_argument("--samples", type=int, help="override the campaign's samples (random, lhs)")
    r.add_argument("--limit", type=int, help="run only the first N scenarios of the expansion")
    r.add_argument("--duration", help="override the campaign's duration (e.g. 30s)")
    r.add_argument("--determinism-sample", type=int, default=3,
                   help="scenarios run a second time and compared bit for bit (default 3, 0 = none)")
    r.add_argument("--no-record", action="store_true",
                   help="do not record failing scenarios for replay")
    r.add_argument("--no-report", action="store_true", help="no PNG/HTML report")
    r.add_argument("--timeout", type=float, default=None,
                   help="wall seconds after which one scenario counts as an error")
    e = sub.add_parser("expand", help="print the scenarios (JSON lines), run nothing")
    e.add_argument("campaign")
    e.add_argument("--samples", type=int)
    e.add_argument("--config", action="store_true", help="include each scenario's cell config")
    p = sub.add_parser("report", help="write the report of a results folder again")
    p.add_argument("dir")
    args = ap.parse_args(argv)
    if args.cmd == "run":
        if args.jobs is not None and args.jobs < 1:
            ap.error("--jobs must be at least 1")
        return cmd_run(args)
    if args.cmd == "expand":
        return cmd_expand(args)
    return cmd_report(args)
