"""A progress bar with the ETA on stderr: redrawn in place on a terminal
(at most 10 times a second), a plain line every 10 s into a log."""

import sys
import time


def _hms(s):
    s = int(s)
    if s >= 3600:
        return "%dh%02dm" % (s // 3600, s % 3600 // 60)
    if s >= 60:
        return "%dm%02ds" % (s // 60, s % 60)
    return "%ds" % s


class Progress:
    def __init__(self, total, stream=None, width=30):
        self.total, self.done, self.failed, self.errors = total, 0, 0, 0
        self.stream = stream or sys.stderr
        self.tty = self.stream.isatty()
        self.width = width
        self.t0 = time.monotonic()
        self.last = 0.0

    def line(self, now=None):
        now = time.monotonic() if now is None else now
        el = now - self.t0
        frac = self.done / self.total if self.total else 1.0
        fill = int(frac * self.width)
        rate = self.done / el if el > 0 else 0.0
        eta = (self.total - self.done) / rate if rate > 0 else None
        return "[%s%s] %d/%d  %d failed%s  %.1f/min  elapsed %s  ETA %s" % (
            "#" * fill, "." * (self.width - fill), self.done, self.total, self.failed,
            ("  %d errors" % self.errors) if self.errors else "", rate * 60, _hms(el),
            _hms(eta) if eta is not None else "?")

    def update(self, status):
        self.done += 1
        if status in ("failed", "nondeterministic"):
            self.failed += 1
        elif status == "error":
            self.errors += 1
        now = time.monotonic()
        if now - self.last < (0.1 if self.tty else 10.0) and self.done < self.total:
            return
        self.last = now
        if self.tty:
            self.stream.write("\r\033[K" + self.line(now))
        else:
            self.stream.write(self.line(now) + "\n")
        self.stream.flush()

    def finish(self):
        if self.tty:
            self.stream.write("\n")
            self.stream.flush()
