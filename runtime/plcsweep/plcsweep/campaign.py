"""The campaign file (docs/campaigns.md): a base cell config, parameters to
vary, fault schedules, the run length and the checks; and its expansion
into scenarios, each a full cell config with a stable hash.

Every value a parameter or fault sets is an override applied to the base
config's YAML tree by path before plcrun builds the cell config from it:
`devices.scale.params.noise`, `programs.Cell.init.target_kg`,
`tasks.main.period`. In a list (tasks, programs, devices, plugins) a path
segment names the item by its `name:`. A path must exist in the base
config, except the last key inside `params:` or `init:` (their values have
defaults), and an `init:` or `params:` mapping itself.
"""

import hashlib
import json
import os
import random

import yaml

from . import iec_time
from . import yaml_nodes as Y
from .yaml_nodes import CampaignError

SAMPLINGS = ("grid", "random", "lhs")
CHECK_KINDS = ("always", "at_end", "eventually")
# Filled in by the sim plugin's link fault switch (docs/config.md).
LINK_KEYS = ("link_down_at", "link_down_for")


class Param:
    """One parameter: a path and its values (a list, or a range)."""

    def __init__(self, path, node, values=None, lo=None, hi=None, steps=None, integer=False,
                 duration=False):
        self.path, self.node = path, node
        self.values, self.lo, self.hi, self.steps = values, lo, hi, steps
        self.integer, self.duration = integer, duration

    def grid_points(self):
        if self.values is not None:
            return list(self.values)
        if self.steps == 1:
            return [self._out(self.lo)]
        return [self._out(self.lo + (self.hi - self.lo) * i / (self.steps - 1))
                for i in range(self.steps)]

    def at(self, u):
        """The value at quantile u in [0, 1): a list's item, a range's point."""
        if self.values is not None:
            return self.values[min(int(u * len(self.values)), len(self.values) - 1)]
        if self.steps:
            pts = self.grid_points()
            return pts[min(int(u * len(pts)), len(pts) - 1)]
        return self._out(self.lo + (self.hi - self.lo) * u)

    def _out(self, x):
        if self.duration:
            return iec_time.format_ns(int(round(x / 10**6)) * 10**6 if abs(x) >= 10**6
                                      else int(round(x)))
        if self.integer:
            return int(round(x))
        # 6 significant digits: the same text (and hash) on every machine.
        return float("%.6g" % x)


class Fault:
    """A named fault: device param overrides, on in a share of scenarios."""

    def __init__(self, name, node, device, params, probability):
        self.name, self.node, self.device = name, node, device
        self.params = params  # [(key, key node, spec)]: spec is value | ('uniform', lo, hi, dur) | ('factor', f)
        self.probability = probability


class Campaign:
    def __init__(self):
        self.file = ""
        self.name = ""
        self.base_file = ""
        self.base_root = None  # the base config's node tree
        self.duration_ns = 0
        self.duration_text = ""
        self.seed = 0
        self.sampling = "grid"
        self.samples = 0
        self.params = []
        self.faults = []
        self.checks = []  # [{name, kind, severity, condition}]
        self.checks_data = []  # the checks: list as data (hashed)
        self.outputs = []
        self.text = ""


def _number(file, node, key):
    if not Y.is_scalar(node):
        raise CampaignError(file, node, "key '%s' must be a single value" % key)
    v = Y.to_python(node)
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise CampaignError(file, node, "key '%s': '%s' is not a number" % (key, node.value))
    return v


def _duration(file, node, key):
    if not Y.is_scalar(node):
        raise CampaignError(file, node, "key '%s' must be a single value" % key)
    ns = iec_time.parse(node.value)
    if ns is None:
        raise CampaignError(file, node, "key '%s': '%s' is not a duration (e.g. 10s, T#1m30s)"
                            % (key, node.value))
    return ns


def _check_keys(file, node, allowed, what):
    for key, knode, _ in Y.items(node):
        if key not in allowed:
            raise CampaignError(file, knode, "unknown key '%s' in %s (expected one of: %s)"
                                % (key, what, ", ".join(sorted(allowed))))


def _range_bounds(file, node, key):
    """[lo, hi] of numbers or durations: (lo, hi, is_duration)."""
    if not Y.is_seq(node) or len(node.value) != 2:
        raise CampaignError(file, node, "key '%s' must be [low, high]" % key)
    a, b = node.value
    da, db = iec_time.parse(a.value) if Y.is_scalar(a) else None, \
        iec_time.parse(b.value) if Y.is_scalar(b) else None
    if da is not None and db is not None and not _is_plain_number(a):
        lo, hi, dur = da, db, True
    else:
        lo, hi, dur = _number(file, a, key), _number(file, b, key), False
    if hi < lo:
        raise CampaignError(file, node, "key '%s': the high end is below the low end" % key)
    return lo, hi, dur


def _is_plain_number(n):
    v = Y.to_python(n)
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _parse_param(file, node):
    if not Y.is_map(node):
        raise CampaignError(file, node, "a parameter must be a mapping (path:, values: | range:)")
    _check_keys(file, node, {"path", "values", "range", "integer"}, "a parameter")
    pnode = Y.get(node, "path")
    if pnode is None or not Y.is_scalar(pnode) or not pnode.value:
        raise CampaignError(file, node, "a parameter needs a 'path' (e.g. devices.scale.params.noise)")
    vnode, rnode = Y.get(node, "values"), Y.get(node, "range")
    if (vnode is None) == (rnode is None):
        raise CampaignError(file, node, "parameter '%s' needs exactly one of values:, range:"
                            % pnode.value)
    inode = Y.get(node, "integer")
    integer = bool(Y.to_python(inode)) if inode is not None else False
    if vnode is not None:
        if not Y.is_seq(vnode) or not vnode.value:
            raise CampaignError(file, vnode, "key 'values' must be a non-empty list")
        vals = []
        for v in vnode.value:
            if not Y.is_scalar(v):
                raise CampaignError(file, v, "a parameter value must be a single value")
            vals.append(Y.to_python(v))
        return Param(pnode.value, pnode, values=vals)
    if not Y.is_map(rnode):
        raise CampaignError(file, rnode, "key 'range' must be {from: A, to: B[, steps: N]}")
    _check_keys(file, rnode, {"from", "to", "steps"}, "a range")
    fnode, tnode = Y.get(rnode, "from"), Y.get(rnode, "to")
    if fnode is None or tnode is None:
        raise CampaignError(file, rnode, "a range needs from: and to:")
    seq = yaml.SequenceNode("tag:yaml.org,2002:seq", [fnode, tnode],
                            start_mark=rnode.start_mark, end_mark=rnode.end_mark)
    lo, hi, dur = _range_bounds(file, seq, "range")
    steps = None
    snode = Y.get(rnode, "steps")
    if snode is not None:
        steps = _number(file, snode, "steps")
        if not isinstance(steps, int) or steps < 1 or steps > 100000:
            raise CampaignError(file, snode, "key 'steps': out of range [1, 100000]")
    return Param(pnode.value, pnode, lo=lo, hi=hi, steps=steps, integer=integer, duration=dur)


def _parse_fault_value(file, key, vnode):
    if Y.is_map(vnode):
        _check_keys(file, vnode, {"uniform", "factor"}, "a fault value")
        if len(vnode.value) != 1:
            raise CampaignError(file, vnode, "a fault value is a value, {uniform: [A, B]} or "
                                "{factor: F}")
        (k, knode, v), = Y.items(vnode)
        if k == "uniform":
            lo, hi, dur = _range_bounds(file, v, "uniform")
            return ("uniform", lo, hi, dur)
        return ("factor", _number(file, v, "factor"))
    if not Y.is_scalar(vnode):
        raise CampaignError(file, vnode, "fault key '%s' must be a single value" % key)
    return Y.to_python(vnode)


def _parse_fault(file, node):
    if not Y.is_map(node):
        raise CampaignError(file, node, "a fault must be a mapping (name:, device:, ...)")
    _check_keys(file, node, {"name", "device", "probability", "params"} | set(LINK_KEYS),
                "a fault")
    nnode, dnode = Y.get(node, "name"), Y.get(node, "device")
    if nnode is None or not Y.is_scalar(nnode) or not nnode.value:
        raise CampaignError(file, node, "a fault needs a 'name'")
    if dnode is None or not Y.is_scalar(dnode):
        raise CampaignError(file, node, "fault '%s' needs a 'device'" % nnode.value)
    prob = 1.0
    pn = Y.get(node, "probability")
    if pn is not None:
        prob = _number(file, pn, "probability")
        if not 0 <= prob <= 1:
            raise CampaignError(file, pn, "key 'probability': out of range [0, 1]")
    params = []
    for key, knode, v in Y.items(node):
        if key in LINK_KEYS:
            spec = _parse_fault_value(file, key, v)
            if not isinstance(spec, tuple) and iec_time.parse(str(spec)) is None:
                raise CampaignError(file, v, "key '%s': '%s' is not a duration" % (key, v.value))
            params.append((key, knode, spec))
    pnode = Y.get(node, "params")
    if pnode is not None:
        if not Y.is_map(pnode):
            raise CampaignError(file, pnode, "key 'params' must be a mapping of parameter: value")
        for key, knode, v in Y.items(pnode):
            params.append((key, knode, _parse_fault_value(file, key, v)))
    if not params:
        raise CampaignError(file, node, "fault '%s' changes nothing (link_down_at:, params:)"
                            % nnode.value)
    if "link_down_for" in [p[0] for p in params] and "link_down_at" not in [p[0] for p in params]:
        raise CampaignError(file, node, "fault '%s': link_down_for needs link_down_at"
                            % nnode.value)
    return Fault(nnode.value, nnode, dnode.value, params, prob)


def _parse_checks(file, node, root_mark):
    if node is None:
        raise CampaignError(file, root_mark, "missing key 'checks' (a list of checks)")
    if not Y.is_seq(node):
        raise CampaignError(file, node, "key 'checks' must be a list")
    out = []
    for c in node.value:
        if not Y.is_map(c):
            raise CampaignError(file, c, "a check must be a mapping")
        d = {"name": None, "kind": None, "severity": "error", "condition": None}
        for key, knode, v in Y.items(c):
            if key == "name":
                d["name"] = v.value
            elif key == "severity":
                d["severity"] = v.value
            elif key in CHECK_KINDS:
                d["kind"], d["condition"] = key, v.value
        # plcrun --checks validates the rest (keys, conditions) at these lines.
        out.append(d)
    return out


def load(path):
    with open(path, encoding="utf-8") as f:
        text = f.read()
    return parse(text, path)


def parse(text, path):
    c = Campaign()
    c.file, c.text = path, text
    root = Y.compose(text, path)
    if root is None:
        raise CampaignError(path, None, "the campaign file is empty")
    if not Y.is_map(root):
        raise CampaignError(path, root, "the campaign must be a mapping (key: value)")
    _check_keys(path, root, {"campaign", "base", "duration", "seed", "sampling", "samples",
                             "parameters", "faults", "checks", "outputs"}, "the campaign")
    n = Y.get(root, "campaign")
    c.name = n.value if n is not None else os.path.splitext(os.path.basename(path))[0]
    bnode = Y.get(root, "base")
    if bnode is None or not Y.is_scalar(bnode):
        raise CampaignError(path, root, "missing key 'base' (the cell config the scenarios vary)")
    c.base_file = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(path)),
                                                bnode.value))
    try:
        with open(c.base_file, encoding="utf-8") as f:
            base_text = f.read()
    except OSError as e:
        raise CampaignError(path, bnode, "cannot read the base config '%s': %s"
                            % (bnode.value, e.strerror)) from None
    c.base_root = Y.compose(base_text, c.base_file)
    if c.base_root is None or not Y.is_map(c.base_root):
        raise CampaignError(path, bnode, "the base config '%s' is not a cell config" % bnode.value)
    dnode = Y.get(root, "duration")
    if dnode is None:
        raise CampaignError(path, root, "missing key 'duration' (virtual time per scenario, e.g. 10m)")
    c.duration_ns = _duration(path, dnode, "duration")
    if c.duration_ns <= 0:
        raise CampaignError(path, dnode, "key 'duration' must be positive")
    c.duration_text = iec_time.format_ns(c.duration_ns)
    snode = Y.get(root, "seed")
    if snode is not None:
        c.seed = _number(path, snode, "seed")
        if not isinstance(c.seed, int):
            raise CampaignError(path, snode, "key 'seed' must be an integer")
    mnode = Y.get(root, "sampling")
    if mnode is not None:
        c.sampling = mnode.value
        if c.sampling not in SAMPLINGS:
            raise CampaignError(path, mnode, "key 'sampling': '%s' is not one of %s"
                                % (c.sampling, ", ".join(SAMPLINGS)))
    nnode = Y.get(root, "samples")
    if nnode is not None:
        c.samples = _number(path, nnode, "samples")
        if not isinstance(c.samples, int) or not 1 <= c.samples <= 10**7:
            raise CampaignError(path, nnode, "key 'samples': out of range [1, 10000000]")
    if c.sampling != "grid" and nnode is None:
        raise CampaignError(path, mnode, "sampling '%s' needs 'samples: N'" % c.sampling)
    if c.sampling == "grid" and nnode is not None:
        raise CampaignError(path, nnode, "'samples' applies to sampling random or lhs; a grid "
                            "has every combination")
    pl = Y.get(root, "parameters")
    if pl is not None:
        if not Y.is_seq(pl):
            raise CampaignError(path, pl, "key 'parameters' must be a list")
        c.params = [_parse_param(path, p) for p in pl.value]
    fl = Y.get(root, "faults")
    if fl is not None:
        if not Y.is_seq(fl):
            raise CampaignError(path, fl, "key 'faults' must be a list")
        c.faults = [_parse_fault(path, f) for f in fl.value]
    names = set()
    for f in c.faults:
        if f.name in names:
            raise CampaignError(path, f.node, "duplicate fault name '%s'" % f.name)
        names.add(f.name)
    cnode = Y.get(root, "checks")
    c.checks = _parse_checks(path, cnode, root)
    c.checks_data = Y.to_python(cnode)
    onode = Y.get(root, "outputs")
    if onode is not None:
        if not Y.is_seq(onode):
            raise CampaignError(path, onode, "key 'outputs' must be a list of variable paths")
        c.outputs = [o.value for o in onode.value]
    # Every path must resolve in the base config (before anything runs).
    probe = _copy(c.base_root)
    for p in c.params:
        _set_path(c, probe, p.path, p.node, "0")
    for f in c.faults:
        for key, knode, spec in f.params:
            if isinstance(spec, tuple) and spec[0] == "factor":
                _base_number(c, "devices.%s.params.%s" % (f.device, key), knode)
            _set_path(c, probe, "devices.%s.params.%s" % (f.device, key), knode, "0")
    return c


# ------------------------------------------------------------------ overrides

def _copy(node):
    if Y.is_map(node):
        return yaml.MappingNode(node.tag, [(k, _copy(v)) for k, v in node.value],
                                start_mark=node.start_mark, end_mark=node.end_mark,
                                flow_style=node.flow_style)
    if Y.is_seq(node):
        return yaml.SequenceNode(node.tag, [_copy(v) for v in node.value],
                                 start_mark=node.start_mark, end_mark=node.end_mark,
                                 flow_style=node.flow_style)
    return yaml.ScalarNode(node.tag, node.value, start_mark=node.start_mark,
                           end_mark=node.end_mark, style=node.style)


def _resolve(c, root, path, where, create_last):
    """The parent mapping and key of `path` in `root`; creates a missing
    init:/params: mapping and a missing last key inside one when
    create_last. Errors name the campaign line `where`."""
    parts = path.split(".")
    node = root
    walked = []
    for i, seg in enumerate(parts[:-1]):
        walked.append(seg)
        if Y.is_seq(node):
            found = None
            for item in node.value:
                if Y.is_map(item):
                    nm = Y.get(item, "name")
                    if nm is not None and nm.value == seg:
                        found = item
            if found is None and seg.isdigit() and int(seg) < len(node.value):
                found = node.value[int(seg)]
            if found is None:
                raise CampaignError(c.file, where, "path '%s': no item named '%s' in '%s' of the "
                                    "base config %s" % (path, seg, ".".join(walked[:-1]),
                                                        c.base_file))
            node = found
        elif Y.is_map(node):
            nxt = Y.get(node, seg)
            if nxt is None and create_last and seg in ("init", "params") and i == len(parts) - 2:
                nxt = yaml.MappingNode("tag:yaml.org,2002:map", [])
                node.value.append((Y.scalar_node(seg), nxt))
            if nxt is None:
                raise CampaignError(c.file, where, "path '%s': the base config %s has no '%s'"
                                    % (path, c.base_file, ".".join(walked)))
            node = nxt
        else:
            raise CampaignError(c.file, where, "path '%s': '%s' in the base config %s is a single "
                                "value, not a mapping or list" % (path, ".".join(walked), c.base_file))
    last = parts[-1]
    if not Y.is_map(node):
        raise CampaignError(c.file, where, "path '%s': '%s' in the base config is not a mapping"
                            % (path, ".".join(parts[:-1])))
    if Y.get(node, last) is None and not (create_last and parts[-2:-1] and
                                          parts[-2] in ("init", "params")):
        raise CampaignError(c.file, where, "path '%s': the base config %s has no '%s'"
                            % (path, c.base_file, path))
    return node, last


def _set_path(c, root, path, where, value):
    node, last = _resolve(c, root, path, where, True)
    new = Y.scalar_node(value)
    for i, (k, v) in enumerate(node.value):
        if k.value == last:
            if not Y.is_scalar(v):
                raise CampaignError(c.file, where, "path '%s' is a mapping or list in the base "
                                    "config, not a single value" % path)
            node.value[i] = (k, new)
            return
    node.value.append((Y.scalar_node(last), new))


def _base_number(c, path, where):
    node, last = _resolve(c, c.base_root, path, where, False)
    v = Y.get(node, last)
    x = Y.to_python(v)
    if isinstance(x, bool) or not isinstance(x, (int, float)):
        raise CampaignError(c.file, where, "a factor needs a number at '%s' in the base config"
                            % path)
    return x


# ------------------------------------------------------------------ expansion

class Scenario:
    def __init__(self, index, params, faults, overrides):
        self.index = index
        self.params = params          # path -> value
        self.faults = faults          # fault name -> {key: value}
        self.overrides = overrides    # [(path, value, where)]
        self.config_text = ""
        self.hash = ""


def _draw(spec, rng):
    if isinstance(spec, tuple) and spec[0] == "uniform":
        _, lo, hi, dur = spec
        x = lo + (hi - lo) * rng.random()
        if dur:  # whole milliseconds (finer than any scan of a 1 ms task is noise)
            return iec_time.format_ns(int(round(x / 10**6)) * 10**6)
        return float("%.6g" % x)
    return spec


def _param_rows(c):
    """One {path: value} per scenario, in a fixed order."""
    if not c.params:
        return [{}] if c.sampling == "grid" else [{} for _ in range(c.samples)]
    if c.sampling == "grid":
        rows = [{}]
        for p in c.params:
            rows = [dict(r, **{p.path: v}) for r in rows for v in p.grid_points()]
        return rows
    rng = random.Random("%d:params" % c.seed)
    n = c.samples
    rows = [{} for _ in range(n)]
    for p in c.params:
        if c.sampling == "random":
            us = [rng.random() for _ in range(n)]
        else:  # Latin hypercube: one draw in each of n equal strata, shuffled
            perm = list(range(n))
            rng.shuffle(perm)
            us = [(perm[i] + rng.random()) / n for i in range(n)]
        for i in range(n):
            rows[i][p.path] = p.at(us[i])
    return rows


def _fault_sets(c, n_rows):
    """For each scenario: the faults that are on. A grid runs every
    combination of the faults whose probability is below 1 (on and off); a
    sample switches each one on with its probability."""
    if c.sampling == "grid":
        optional = [f for f in c.faults if f.probability < 1]
        always = [f.name for f in c.faults if f.probability >= 1]
        combos = [[]]
        for f in optional:
            combos = [x + y for x in combos for y in ([], [f.name])]
        return [always + cmb for cmb in combos]
    rng = random.Random("%d:faults" % c.seed)
    out = []
    for _ in range(n_rows):
        out.append([f.name for f in c.faults if rng.random() < f.probability])
    return out


def expand(c, plcrun_dir=None):
    """Every scenario of the campaign, with its config text and hash."""
    rows = _param_rows(c)
    sets = _fault_sets(c, len(rows))
    pairs = ([(r, s) for r in rows for s in sets] if c.sampling == "grid"
             else list(zip(rows, sets)))
    by_name = {f.name: f for f in c.faults}
    out = []
    for idx, (row, on) in enumerate(pairs):
        rng = random.Random("%d:scenario:%d" % (c.seed, idx))
        overrides = [(p.path, row[p.path], p.node) for p in c.params]
        faults = {}
        for name in on:
            f = by_name[name]
            vals = {}
            for key, knode, spec in f.params:
                path = "devices.%s.params.%s" % (f.device, key)
                if isinstance(spec, tuple) and spec[0] == "factor":
                    base = dict((o[0], o[1]) for o in overrides).get(path)
                    if base is None:
                        base = _base_number(c, path, knode)
                    v = float("%.12g" % (float(base) * spec[1]))
                else:
                    v = _draw(spec, rng)
                vals[key] = v
                overrides.append((path, v, knode))
            faults[name] = vals
        s = Scenario(idx, dict(row), faults, overrides)
        s.config_text, hashed = scenario_config(c, overrides)
        s.hash = scenario_hash(c, hashed)
        out.append(s)
    return out


def scenario_config(c, overrides):
    """The base config with the overrides, as YAML text a plcrun can run from
    any folder: relative library paths made absolute; no retain: (each
    scenario starts cold, a shared retain file would couple them) and no
    hmi: (nobody watches a campaign's scenarios live). Returns the text and
    the data the hash is computed from."""
    root = _copy(c.base_root)
    for path, value, where in overrides:
        _set_path(c, root, path, where, value)
    base_dir = os.path.dirname(c.base_file)
    kept = []
    libs_as_written = None
    for k, v in root.value:
        if k.value in ("retain", "hmi"):
            continue
        if k.value == "libraries" and Y.is_seq(v):
            libs_as_written = Y.to_python(v)
            for item in v.value:
                if Y.is_scalar(item) and not os.path.isabs(item.value):
                    item.value = os.path.normpath(os.path.join(base_dir, item.value))
        if k.value in ("plugins", "devices") and Y.is_seq(v):
            for item in v.value:
                params = Y.get(item, "params") if Y.is_map(item) else None
                if params is not None and Y.is_map(params):
                    _absolute_file_params(params, base_dir)
        kept.append((k, v))
    root.value = kept
    # Hashed as data with the library paths as the base config writes them,
    # so a checkout in another folder has the same scenario hashes.
    data = Y.to_python(root)
    if libs_as_written is not None:
        data["libraries"] = libs_as_written
    return Y.dump(root), data


def _absolute_file_params(params, base_dir):
    """A plugin's or device's file parameter (gsdml:, ...) is taken from the
    config's folder (plc/config_path.hpp); the scenario's config is
    elsewhere, so a relative one that names a file there is made absolute."""
    for _, v in params.value:
        if (Y.is_scalar(v) and v.tag.endswith(":str") and v.value and
                not os.path.isabs(v.value) and
                os.path.isfile(os.path.join(base_dir, v.value))):
            v.value = os.path.normpath(os.path.join(base_dir, v.value))


def scenario_hash(c, config_data):
    """sha256 of everything that decides a scenario's result: the cell config
    as data (so formatting does not matter), the run length, the checks and
    outputs. The first 16 hex digits."""
    doc = {
        "config": config_data,
        "duration_ns": c.duration_ns,
        "checks": c.checks_data,
        "outputs": c.outputs,
    }
    blob = json.dumps(doc, sort_keys=True, separators=(",", ":"), default=str)
    return hashlib.sha256(blob.encode()).hexdigest()[:16]


def check_names(c):
    return [ch["name"] for ch in c.checks]
