"""IEC 61131 durations as plcrun reads them (runtime/src/iec_literal.cpp):
T#1m30s, 10s, 1.5s, 250ms, 20us, T#1d2h. Integer nanoseconds, so a duration
hashes and compares exactly."""

import re

_UNITS = [("ms", 10**6), ("us", 10**3), ("ns", 1), ("d", 86400 * 10**9),
          ("h", 3600 * 10**9), ("m", 60 * 10**9), ("s", 10**9)]
_PART = re.compile(r"([0-9_]+(?:\.[0-9_]*)?)(ms|us|ns|d|h|m|s)_?")


def parse(text):
    """Nanoseconds of an IEC duration, or None when it is not one."""
    if not isinstance(text, str):
        return None
    v = text.strip().lower()
    for prefix in ("ltime#", "time#", "lt#", "t#"):
        if v.startswith(prefix):
            v = v[len(prefix):]
            break
    neg = v.startswith("-")
    if neg:
        v = v[1:]
    if not v:
        return None
    total = 0
    pos = 0
    while pos < len(v):
        m = _PART.match(v, pos)
        if not m:
            return None
        num = m.group(1).replace("_", "")
        if not num or num == ".":
            return None
        unit = dict(_UNITS)[m.group(2)]
        # Exact for whole numbers; a fraction is rounded as plcrun rounds it.
        if "." in num:
            whole, frac = num.split(".")
            total += int(whole or "0") * unit + round(float("0." + (frac or "0")) * unit)
        else:
            total += int(num) * unit
        pos = m.end()
    return -total if neg else total


def format_ns(ns):
    """The shortest exact text plcrun reads back as `ns`: 10s, 250ms, 1500us."""
    if ns == 0:
        return "0ms"
    sign = "-" if ns < 0 else ""
    n = abs(ns)
    for unit, scale in (("s", 10**9), ("ms", 10**6), ("us", 10**3), ("ns", 1)):
        if n % scale == 0:
            return "%s%d%s" % (sign, n // scale, unit)
    return "%s%dns" % (sign, n)
