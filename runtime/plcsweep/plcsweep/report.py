"""The campaign report in OUT/report/: PNG plots (matplotlib, Debian's
python3-matplotlib) and one self-contained HTML page with the images
inlined as base64, next to the summary text.

  param-N.png    per parameter: passed and failed scenarios over its values
  output-N.png   per output: histogram of its final value over all scenarios
  pairs.png      the first two numeric parameters, each scenario a point
  wall.png       wall time per scenario
"""

import base64
import html
import json
import os

from . import iec_time, summary


def _numeric(v):
    if isinstance(v, bool):
        return float(v)
    if isinstance(v, (int, float)):
        return float(v)
    ns = iec_time.parse(v) if isinstance(v, str) else None
    return ns / 1e9 if ns is not None else None


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


OK, BAD = "#2a9d8f", "#e63946"


def _param_plot(plt, path, values, ok, file):
    fig, ax = plt.subplots(figsize=(6.4, 3.6), dpi=100)
    nums = [_numeric(v) for v in values]
    distinct = sorted(set(values), key=lambda v: (_numeric(v) is None, _numeric(v) or 0, str(v)))
    if all(n is not None for n in nums) and len(distinct) > 12:
        lo, hi = min(nums), max(nums)
        bins = 20 if hi > lo else 1
        ax.hist([[n for n, g in zip(nums, ok) if g], [n for n, g in zip(nums, ok) if not g]],
                bins=bins, stacked=True, color=[OK, BAD], label=["passed", "failed"])
        if any(isinstance(v, str) for v in values):
            ax.set_xlabel(path + " (s)")
        else:
            ax.set_xlabel(path)
    else:
        labels = [str(v) for v in distinct]
        p = [sum(1 for v, g in zip(values, ok) if v == d and g) for d in distinct]
        f = [sum(1 for v, g in zip(values, ok) if v == d and not g) for d in distinct]
        xs = range(len(distinct))
        ax.bar(xs, p, color=OK, label="passed")
        ax.bar(xs, f, bottom=p, color=BAD, label="failed")
        ax.set_xticks(list(xs))
        ax.set_xticklabels(labels, rotation=30 if len(labels) > 6 else 0, ha="right"
                           if len(labels) > 6 else "center")
        ax.set_xlabel(path)
    ax.set_ylabel("scenarios")
    ax.set_title("pass/fail over %s" % path)
    ax.legend()
    fig.tight_layout()
    fig.savefig(file)
    plt.close(fig)


def _output_plot(plt, name, vals, ok, file):
    fig, ax = plt.subplots(figsize=(6.4, 3.6), dpi=100)
    good = [v for v, g in zip(vals, ok) if v is not None and g]
    bad = [v for v, g in zip(vals, ok) if v is not None and not g]
    allv = good + bad
    if allv:
        lo, hi = min(allv), max(allv)
        ax.hist([good, bad], bins=30 if hi > lo else 1, stacked=True, color=[OK, BAD],
                label=["passed", "failed"])
        ax.legend()
    ax.set_xlabel("final value of " + name)
    ax.set_ylabel("scenarios")
    ax.set_title("histogram: " + name)
    fig.tight_layout()
    fig.savefig(file)
    plt.close(fig)


def _pairs_plot(plt, px, py, xs, ys, ok, file):
    fig, ax = plt.subplots(figsize=(6.4, 4.2), dpi=100)
    ax.scatter([x for x, g in zip(xs, ok) if g], [y for y, g in zip(ys, ok) if g], s=8,
               color=OK, label="passed")
    ax.scatter([x for x, g in zip(xs, ok) if not g], [y for y, g in zip(ys, ok) if not g], s=12,
               color=BAD, marker="x", label="failed")
    ax.set_xlabel(px)
    ax.set_ylabel(py)
    ax.set_title("scenarios over %s and %s" % (px.rsplit(".", 1)[-1], py.rsplit(".", 1)[-1]))
    ax.legend()
    fig.tight_layout()
    fig.savefig(file)
    plt.close(fig)


def _wall_plot(plt, walls, file):
    fig, ax = plt.subplots(figsize=(6.4, 3.2), dpi=100)
    ax.hist(walls, bins=30, color="#457b9d")
    ax.set_xlabel("wall time per scenario (s)")
    ax.set_ylabel("scenarios")
    ax.set_title("scenario wall times")
    fig.tight_layout()
    fig.savefig(file)
    plt.close(fig)


def write(out_dir, c, scenarios, records, meta):
    plt = _plt()
    rep = os.path.join(out_dir, "report")
    os.makedirs(rep, exist_ok=True)
    rows = [(s, records[s.hash]) for s in scenarios if s.hash in records and
            records[s.hash]["status"] != "error"]
    ok = [r["status"] == "passed" for _, r in rows]
    images = []
    for i, p in enumerate(c.params):
        f = os.path.join(rep, "param-%d.png" % (i + 1))
        _param_plot(plt, p.path, [s.params.get(p.path) for s, _ in rows], ok, f)
        images.append(("Parameter " + p.path, f))
    if c.faults:
        f = os.path.join(rep, "faults.png")
        vals = ["+".join(sorted(s.faults)) or "none" for s, _ in rows]
        _param_plot(plt, "faults on", vals, ok, f)
        images.append(("Faults", f))
    for i, o in enumerate(c.outputs):
        f = os.path.join(rep, "output-%d.png" % (i + 1))
        vals = [((r.get("verdict") or {}).get("outputs", {}).get(o) or {}).get("final")
                for _, r in rows]
        _output_plot(plt, o, vals, ok, f)
        images.append(("Output " + o, f))
    numeric = [p for p in c.params
               if all(_numeric(s.params.get(p.path)) is not None for s, _ in rows)]
    if len(numeric) >= 2 and rows:
        f = os.path.join(rep, "pairs.png")
        px, py = numeric[0].path, numeric[1].path
        _pairs_plot(plt, px, py, [_numeric(s.params[px]) for s, _ in rows],
                    [_numeric(s.params[py]) for s, _ in rows], ok, f)
        images.append(("Scenarios over two parameters", f))
    if rows:
        f = os.path.join(rep, "wall.png")
        _wall_plot(plt, [r.get("wall_s", 0) for _, r in rows], f)
        images.append(("Wall time", f))
    text = summary.text(c, scenarios, records, meta)
    with open(os.path.join(rep, "summary.txt"), "w", encoding="utf-8") as fh:
        fh.write(text)
    det = None
    dpath = os.path.join(out_dir, "determinism.json")
    if os.path.exists(dpath):
        with open(dpath, encoding="utf-8") as fh:
            det = json.load(fh)
    page = _html(c, text, images, det, rows)
    path = os.path.join(rep, "report.html")
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(page)
    return path


def _html(c, text, images, det, rows):
    e = html.escape
    parts = ["<!DOCTYPE html><html><head><meta charset='utf-8'><title>campaign %s</title>"
             % e(c.name),
             "<style>body{font-family:sans-serif;max-width:1000px;margin:2em auto}"
             "pre{background:#f4f4f4;padding:1em;overflow-x:auto}"
             "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:2px 6px;"
             "font-size:90%}img{max-width:100%}</style></head><body>",
             "<h1>Campaign %s</h1>" % e(c.name),
             "<p>base config <code>%s</code>, %d checks</p>" % (e(c.base_file), len(c.checks)),
             "<h2>Summary</h2><pre>%s</pre>" % e(text)]
    if det is not None:
        parts.append("<p>Determinism: %d scenarios run twice, %d differ.</p>"
                     % (len(det["sampled"]), len(det["mismatches"])))
    parts.append("<h2>Checks</h2><table><tr><th>name</th><th>kind</th><th>severity</th>"
                 "<th>condition</th></tr>")
    for ch in c.checks:
        parts.append("<tr><td>%s</td><td>%s</td><td>%s</td><td><code>%s</code></td></tr>" % (
            e(str(ch["name"])), e(str(ch["kind"])), e(str(ch["severity"])),
            e(str(ch["condition"]))))
    parts.append("</table>")
    for title, f in images:
        with open(f, "rb") as fh:
            b64 = base64.b64encode(fh.read()).decode()
        parts.append("<h2>%s</h2><img alt='%s' src='data:image/png;base64,%s'>"
                     % (e(title), e(title), b64))
    failed = [(s, r) for s, r in rows if r["status"] != "passed"][:50]
    if failed:
        parts.append("<h2>Failed scenarios (first 50)</h2><table><tr><th>hash</th>"
                     "<th>failed checks</th><th>parameters and faults</th></tr>")
        for s, r in failed:
            names = [ch["name"] for ch in (r.get("verdict") or {}).get("checks", [])
                     if not ch["passed"]]
            parts.append("<tr><td><code>%s</code></td><td>%s</td><td>%s</td></tr>" % (
                e(s.hash), e(", ".join(names)), e(summary.describe(s))))
        parts.append("</table>")
    parts.append("</body></html>\n")
    return "\n".join(parts)
