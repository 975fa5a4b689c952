"""The results of a campaign in its output folder:

  results.jsonl  one record per finished scenario, appended (and fsync'ed)
                 as each one finishes: the resume log. A scenario whose hash
                 is in it is not run again; a record that a crash cut short
                 is ignored.
  results.csv    written at the end, one row per scenario in expansion
                 order, only what the config decides (no wall times, hosts):
                 two runs of a campaign, local or on Dask, give the same bytes.
  timing.csv     hash, wall seconds, host: what differs between runs.
"""

import csv
import io
import json
import os

RESULTS = "results.jsonl"


class ResultStore:
    def __init__(self, out_dir):
        self.out_dir = out_dir
        self.path = os.path.join(out_dir, RESULTS)
        self.records = {}  # hash -> record
        if os.path.exists(self.path):
            with open(self.path, encoding="utf-8") as f:
                for line in f:
                    try:
                        r = json.loads(line)
                    except ValueError:
                        continue  # the line a crash cut short
                    if isinstance(r, dict) and "hash" in r and r.get("status") != "error":
                        self.records[r["hash"]] = r
        self._f = open(self.path, "a", encoding="utf-8")

    def done(self, h):
        return h in self.records

    def add(self, record):
        """Keeps the first record of a hash: a scenario retried after its
        worker died, or reported twice, is written once."""
        if record["hash"] in self.records:
            return False
        self.records[record["hash"]] = record
        self._f.write(json.dumps(record, sort_keys=True) + "\n")
        self._f.flush()
        os.fsync(self._f.fileno())
        return True

    def close(self):
        self._f.close()


def columns(campaign, scenarios):
    params = [p.path for p in campaign.params]
    faults = [f.name for f in campaign.faults]
    checks = [c["name"] for c in campaign.checks]
    return params, faults, checks, list(campaign.outputs)


def _fmt(v):
    if v is None:
        return ""
    if isinstance(v, float):
        return repr(v)
    return str(v)


def write_csv(out_dir, campaign, scenarios, records):
    params, faults, checks, outputs = columns(campaign, scenarios)
    head = (["index", "hash", "status"] + params + ["fault:" + f for f in faults] +
            ["failed_checks"] + ["check:%s:first_fail_s" % c for c in checks] +
            ["final:" + o for o in outputs] + ["min:" + o for o in outputs] +
            ["max:" + o for o in outputs] + ["scans", "sim_time_s", "state_digest"])
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(head)
    timing = io.StringIO()
    tw = csv.writer(timing, lineterminator="\n")
    tw.writerow(["index", "hash", "status", "wall_s", "plcrun_wall_s", "record_wall_s", "host"])
    for s in scenarios:
        r = records.get(s.hash)
        if r is None:
            continue
        v = r.get("verdict") or {}
        by_name = {c["name"]: c for c in v.get("checks", [])}
        outs = v.get("outputs", {})
        row = [s.index, s.hash, r["status"]]
        row += [_fmt(s.params.get(p)) for p in params]
        row += [json.dumps(s.faults[f], sort_keys=True) if f in s.faults else "" for f in faults]
        row += [" ".join(c for c in checks if c in by_name and not by_name[c]["passed"])]
        row += [_fmt(by_name[c].get("first_fail_time_s")) if c in by_name else "" for c in checks]
        for k in ("final", "min", "max"):
            row += [_fmt(outs.get(o, {}).get(k)) for o in outputs]
        row += [_fmt(v.get("scans")), _fmt(v.get("sim_time_s")), v.get("state_digest", "")]
        w.writerow(row)
        tw.writerow([s.index, s.hash, r["status"], "%.4f" % r.get("wall_s", 0),
                     _fmt(r.get("plcrun_wall_s")), _fmt(r.get("record_wall_s")),
                     r.get("host", "")])
    _atomic_write(os.path.join(out_dir, "results.csv"), buf.getvalue())
    _atomic_write(os.path.join(out_dir, "timing.csv"), timing.getvalue())


def _atomic_write(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, path)
