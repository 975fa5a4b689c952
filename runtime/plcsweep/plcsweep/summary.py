"""The campaign's summary: scenarios, passed, failed by check, the slowest,
and where each failure's recording is."""

import os


def stats(c, scenarios, records):
    recs = [(s, records[s.hash]) for s in scenarios if s.hash in records]
    by_status = {}
    for _, r in recs:
        by_status[r["status"]] = by_status.get(r["status"], 0) + 1
    by_check = {ch["name"]: 0 for ch in c.checks}
    for _, r in recs:
        for ch in (r.get("verdict") or {}).get("checks", []):
            if not ch["passed"]:
                by_check[ch["name"]] = by_check.get(ch["name"], 0) + 1
    slowest = sorted(recs, key=lambda sr: -sr[1].get("wall_s", 0))[:5]
    return recs, by_status, by_check, slowest


def describe(s):
    parts = ["%s=%s" % (p.rsplit(".", 1)[-1] if "." in p else p, v) for p, v in s.params.items()]
    parts += ["%s%s" % (f, "" if not v else "(" + ", ".join("%s=%s" % kv for kv in v.items()) + ")")
              for f, v in s.faults.items()]
    return " ".join(parts)


def text(c, scenarios, records, meta):
    recs, by_status, by_check, slowest = stats(c, scenarios, records)
    sev = {ch["name"]: ch.get("severity", "error") for ch in c.checks}
    out = ["== campaign '%s': %d scenarios of %s virtual time ==" %
           (c.name, len(scenarios), meta.get("duration", c.duration_text))]
    out.append("passed %d, failed %d, not deterministic %d, errors %d, not run %d" % (
        by_status.get("passed", 0), by_status.get("failed", 0),
        by_status.get("nondeterministic", 0), by_status.get("error", 0),
        len(scenarios) - len(recs)))
    if meta.get("elapsed_s") is not None:
        out.append("wall time %.1f s for %d scenarios run now (executor %s)" % (
            meta["elapsed_s"], meta.get("run_now", 0), meta.get("executor", "local")))
    out.append("failed, by check:")
    for name, n in by_check.items():
        out.append("  %-28s %-8s %d" % (name, sev.get(name, "error"), n))
    out.append("slowest:")
    for s, r in slowest:
        out.append("  %s  %.2f s  %s" % (s.hash, r.get("wall_s", 0), describe(s)))
    fails = [(s, r) for s, r in recs if r.get("failure_dir")]
    if fails:
        out.append("failures recorded (replay: plcrun DIR/cell.yaml --replay DIR/failure.plcrec "
                   "--commands DIR/to-failure.cmd --debug):")
        for s, r in fails[:10]:
            out.append("  %s" % os.path.relpath(r["failure_dir"]))
        if len(fails) > 10:
            out.append("  ... and %d more under failures/" % (len(fails) - 10))
    errs = [(s, r) for s, r in recs if r["status"] == "error"]
    for s, r in errs[:5]:
        out.append("error %s: %s" % (s.hash, r.get("error", "")))
    return "\n".join(out) + "\n"
