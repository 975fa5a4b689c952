#!/usr/bin/env python3
"""The plant core against an outside reference: scipy.signal.

Runs tests/plant/plant_reference_main.cpp's binary (plant_reference) on
plants made here and compares its numbers with scipy's, computed now (no
committed numbers):

  * the ZOH matrices Phi and Gamma of random stable state-space plants
    (1..20 states, 1..3 inputs, 1..2 outputs, sample times 1 ms .. 1 s)
    against scipy.signal.cont2discrete(method='zoh');
  * their step responses (states and outputs over hundreds of samples)
    against scipy.signal.dlsim on scipy's own matrices;
  * plants with dead time per input, whole and fractional samples, against
    scipy.signal.lsim (continuous, zero-order-hold input on a grid that
    holds every sample instant and every dead time: exact at the samples);
  * transfer functions (first, second and third order, with zeros, proper,
    an integrator, with dead time) against cont2discrete + dlsim and lsim;
  * an unstable plant refused.

Tolerances (stated in the README and docs/config.md):
  matrices        max |ours - scipy| <= 1e-12 x max(1, max |scipy|)
  step responses  max |ours - scipy| <= 1e-9 x max(1, max |scipy response|)
Exit status 0 when every case agrees; the report names the worst case.
"""
import argparse
import math
import subprocess
import sys

try:
    import numpy as np
    from scipy import signal
except ImportError as e:  # the Debian packages python3-numpy and python3-scipy
    print(f"scipy_reference: {e}; install python3-scipy and python3-numpy (scripts/setup)")
    sys.exit(1)

MATRIX_TOL = 1e-12
RESPONSE_TOL = 1e-9


def run(binary, text):
    p = subprocess.run([binary], input=text, capture_output=True, text=True, check=False)
    return p.returncode, p.stdout, p.stderr


def parse(out, n, m, steps):
    lines = out.strip().split("\n")
    phi = np.array(lines[0].split(), dtype=float).reshape(n, n)
    g0 = np.array(lines[1].split(), dtype=float).reshape(n, m)
    g1 = np.array(lines[2].split(), dtype=float).reshape(n, m)
    xs, ys = [], []
    for line in lines[3:3 + steps]:
        x, y = line.split("|")
        xs.append(np.array(x.split(), dtype=float))
        ys.append(np.array(y.split(), dtype=float))
    return phi, g0, g1, np.array(xs), np.array(ys)


def fmt(a):
    return " ".join(repr(float(v)) for v in np.asarray(a).ravel())


class Report:
    def __init__(self):
        self.failures = 0
        self.cases = 0
        self.worst = {"matrix": (0.0, ""), "response": (0.0, "")}

    def check(self, kind, name, ours, ref):
        self.cases += 1
        ref = np.asarray(ref, dtype=float)
        ours = np.asarray(ours, dtype=float)
        if ours.shape != ref.shape:
            print(f"FAIL {name}: shape {ours.shape} != scipy {ref.shape}")
            self.failures += 1
            return
        scale = max(1.0, float(np.max(np.abs(ref))) if ref.size else 1.0)
        err = float(np.max(np.abs(ours - ref))) / scale if ref.size else 0.0
        tol = MATRIX_TOL if kind == "matrix" else RESPONSE_TOL
        if err > self.worst[kind][0]:
            self.worst[kind] = (err, name)
        if not err <= tol:
            print(f"FAIL {name}: relative error {err:.3e} > {tol:.0e}")
            self.failures += 1


def stable_matrix(rng, n):
    # Negative definite symmetric part plus a skew part: every eigenvalue
    # has a negative real part, and many are complex (oscillating modes).
    m = rng.standard_normal((n, n))
    s = rng.standard_normal((n, n))
    a = -(m @ m.T) / n - 0.05 * np.eye(n) + (s - s.T) * 0.7
    return a * rng.uniform(0.2, 5.0)


def ss_case(rep, binary, rng, n, m, p, h_ns, delays_ns, steps, name):
    a = stable_matrix(rng, n)
    b = rng.standard_normal((n, m))
    c = rng.standard_normal((p, n))
    d = rng.standard_normal((p, m)) * (rng.uniform() < 0.5)
    text = (f"ss {n} {m} {p} {h_ns} {fmt(a)} {fmt(b)} {fmt(c)} {fmt(d)} "
            f"{' '.join(str(x) for x in delays_ns)} {steps}\n")
    rc, out, err = run(binary, text)
    if rc != 0:
        print(f"FAIL {name}: plant_reference exit {rc}: {out}{err}")
        rep.failures += 1
        return
    phi, g0, g1, xs, ys = parse(out, n, m, steps)
    h = h_ns * 1e-9
    if not any(delays_ns):
        ad, bd, _, _, _ = signal.cont2discrete((a, b, c, d), h, method="zoh")
        rep.check("matrix", f"{name} Phi", phi, ad)
        rep.check("matrix", f"{name} Gamma", g0, bd)
        rep.check("matrix", f"{name} Gamma1", g1, np.zeros_like(bd))
        u = np.ones((steps + 1, m))
        _, yout, xout = signal.dlsim((ad, bd, c, d, h), u)
        rep.check("response", f"{name} x", xs, xout[1:])
        rep.check("response", f"{name} y", ys, yout[1:])
    else:
        xr, yr = lsim_delayed(a, b, c, d, h_ns, delays_ns, steps)
        rep.check("response", f"{name} x", xs, xr)
        rep.check("response", f"{name} y", ys, yr)


def lsim_delayed(a, b, c, d, h_ns, delays_ns, steps):
    """Continuous response to unit steps delayed by delays_ns, at t = k h
    (k = 1..steps), by lsim with a zero-order-hold input on a uniform grid
    whose spacing divides the sample time and every dead time (so the input
    switches exactly on grid points and lsim is exact there). y uses the
    input held up to the sample instant (linear_plant.hpp)."""
    m = b.shape[1]
    g = h_ns
    for x in delays_ns:
        if x:
            g = math.gcd(g, x)
    t_ns = np.arange(0, steps * h_ns + 1, g, dtype=np.int64)
    u = np.zeros((len(t_ns), m))
    for i, l in enumerate(delays_ns):
        u[:, i] = (t_ns >= l).astype(float)
    _, _, x = signal.lsim((a, b, c, np.zeros_like(d)), u, t_ns * 1e-9, interp=False)
    x = x.reshape(len(t_ns), -1)
    xs = x[[k * h_ns // g for k in range(1, steps + 1)]]
    # The input just before t = k h: a delayed step is on when k h > L.
    ul = np.array([[1.0 if k * h_ns > l else 0.0 for l in delays_ns] for k in range(1, steps + 1)])
    ys = xs @ c.T + ul @ d.T
    return xs, ys


def tf_case(rep, binary, num, den, h_ns, delay_ns, steps, name):
    text = (f"tf {len(num)} {len(den)} {h_ns} {fmt(num)} {fmt(den)} {delay_ns} {steps}\n")
    rc, out, err = run(binary, text)
    if rc != 0:
        print(f"FAIL {name}: plant_reference exit {rc}: {out}{err}")
        rep.failures += 1
        return
    lines = out.strip().split("\n")
    ys = np.array([float(line.split("|")[1]) for line in lines[3:3 + steps]])
    h = h_ns * 1e-9
    if delay_ns == 0:
        # Through state space: cont2discrete of a (num, den) pair converts
        # the discrete plant back to polynomials, whose conditioning (a
        # BadCoefficients warning for the third order) costs scipy's side
        # about 1e-9; the realisation differs from ours, the response not.
        a, b, c, d = signal.tf2ss(num, den)
        ad, bd, cd, dd, _ = signal.cont2discrete((a, b, c, d), h, method="zoh")
        _, yout, _ = signal.dlsim((ad, bd, cd, dd, h), np.ones((steps + 1, 1)))
        rep.check("response", f"{name} y", ys, np.squeeze(yout)[1:])
    else:
        a, b, c, d = signal.tf2ss(num, den)
        _, yr = lsim_delayed(a, b, c, d, h_ns, [delay_ns], steps)
        rep.check("response", f"{name} y", ys, yr[:, 0])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--binary", required=True)
    ap.add_argument("--seed", type=int, default=2025)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    rep = Report()

    ms = 1_000_000
    for n in (1, 2, 3, 5, 8, 12, 20):
        for h_ns in (1 * ms, 10 * ms, 100 * ms, 1000 * ms):
            m = int(rng.integers(1, 4))
            p = int(rng.integers(1, 3))
            ss_case(rep, args.binary, rng, n, m, p, h_ns, [0] * m, 300, f"ss n={n} m={m} p={p} h={h_ns}ns")
    for n in (1, 3, 6):
        for delays in ([5 * ms, 0], [7_300_000, 12_500_000], [250 * ms, 3_330_000]):
            ss_case(rep, args.binary, rng, n, 2, 2, 10 * ms, delays, 200,
                    f"ss dead time n={n} L={delays}ns")
    tfs = [
        ([2.0], [3.0, 1.0], "first order"),
        ([0.7], [6.0, 5.5, 1.0], "two lags"),
        ([12.0], [1.0, 1.2, 4.0], "oscillating"),
        ([1.0, 2.0], [1.0, 1.0], "proper (D != 0)"),
        ([0.5, 1.0], [2.0, 3.0, 4.0, 1.0], "third order with a zero"),
        ([0.5], [1.0, 0.0], "integrator"),
    ]
    for num, den, label in tfs:
        tf_case(rep, args.binary, num, den, 10 * ms, 0, 500, f"tf {label}")
        tf_case(rep, args.binary, num, den, 10 * ms, 123_400_000, 500, f"tf {label} L=0.1234s")

    rc, out, _ = run(args.binary, "ss 1 1 1 1000000 0.5 1 1 0 0 10\n")
    rep.cases += 1
    if rc != 1 or not out.startswith("error A: the plant is unstable"):
        print(f"FAIL unstable plant not refused: exit {rc}: {out}")
        rep.failures += 1

    print(f"scipy {__import__('scipy').__version__}, numpy {np.__version__}: {rep.cases} comparisons, "
          f"{rep.failures} failed")
    for kind, (err, name) in rep.worst.items():
        print(f"  worst {kind}: {err:.3e} ({name})")
    return 1 if rep.failures else 0


if __name__ == "__main__":
    sys.exit(main())
