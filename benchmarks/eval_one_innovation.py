"""Evaluation of a one-innovation generator of the five-term noise (docs/performance.md, noise).

Run by hand: ``python benchmarks/eval_one_innovation.py [--n 4194304]``. Prints (never asserts):

* the steady-state Kalman innovations form of the Gaussian terms N + (full-rate flicker poles)
  + K at 100 Hz (the five-term model of ``bench_noise.py``): ``scipy.linalg.solve_discrete_are``
  with a diagonal A (parallel first-order sections), y = e + sum_i x_i, x_i' = phi_i x_i + g_i e;
* its numerical conditioning: the residual of the Riccati equation and the largest relative
  error of F |H(e^{i w})|^2 against the per-term spectrum over 4000 frequencies (log-spaced
  from 1e-7 cycles/sample, where the random walk and the slowest full-rate pole dominate);
* the finite-record catch: the random walk starts at 0, so the steady-state form reproduces
  the per-term law only with an extra independent constant (the smallest variance delta that
  makes Pi0 - P positive semidefinite), printed as its std and as the equivalent earlier start;
* the cost per sample, in units of one ``standard_normal`` draw, of the pieces any such
  generator needs: one Gaussian and one uniform draw (Q stays uniform), the cascade of the
  9-pole factor through ``scipy.signal.sosfilt`` (5 sections), and, if numba is importable,
  one fused compiled loop doing the recursion, the quantization difference and the sum.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time

import numpy as np
from scipy import linalg, signal

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
FS = 100.0


def best(fn, repeats: int = 5) -> float:
    t = []
    for _ in range(repeats):
        c = time.process_time()
        fn()
        t.append(time.process_time() - c)
    return min(t)


def innovations(fs: float):
    from bench_noise import FIVE

    from gyrobench.sim import noise as nz

    model = nz.NoiseModel.from_datasheet(**FIVE)
    dt = 1.0 / fs
    tc, sig = model.flicker_poles(fs)
    fast = tc / dt < nz._DECIM_MARGIN * nz._LEVEL_RATIO  # the full-rate level of _Flicker
    phi = np.exp(-dt / tc[fast])
    q = sig[fast] ** 2 * -np.expm1(-2.0 * dt / tc[fast])
    r = model.angle_random_walk**2 * fs  # N's per-sample variance
    qk = model.rate_random_walk**2 * dt  # K's per-step variance
    a = np.diag(np.r_[phi, 1.0])
    c = np.ones((1, phi.size + 1))
    qq = np.diag(np.r_[q, qk])
    p = linalg.solve_discrete_are(a.T, c.T, qq, np.array([[r]]))
    f = float((c @ p @ c.T)[0, 0]) + r
    gain = (a @ p @ c.T).ravel() / f
    resid = a @ p @ a.T + qq - (a @ p @ c.T) @ (c @ p @ a.T) / f - p
    w = 2 * np.pi * np.logspace(-7, math.log10(0.5), 4000)
    z1 = np.exp(-1j * w)
    target = r + np.sum(np.r_[q, qk][:, None] / np.abs(1 - np.r_[phi, 1.0][:, None] * z1) ** 2, axis=0)
    h = 1 + np.sum(gain[:, None] * z1 / (1 - np.r_[phi, 1.0][:, None] * z1), axis=0)
    err = np.max(np.abs(f * np.abs(h) ** 2 / target - 1))
    pi0 = np.diag(np.r_[sig[fast] ** 2, qk])  # per-term start: poles stationary, the walk one step in
    m = pi0 - p
    mff, mfk, mkk = m[:-1, :-1], m[:-1, -1], m[-1, -1]
    delta = max(0.0, float(mfk @ np.linalg.solve(mff, mfk) - mkk))
    print(f"full-rate flicker poles {phi.size} (phi {phi.min():.4f} .. {phi.max():.6f}) + the random walk (phi = 1)")
    print(f"Riccati residual / |P|: {np.max(np.abs(resid)) / np.max(np.abs(p)):.1e}; "
          f"max |F |H|^2 / S - 1| over 1e-7 .. 0.5 cycles/sample: {err:.1e}")
    print(f"innovation std {math.sqrt(f):.3e} rad/s vs N's {math.sqrt(r):.3e}; min eig(Pi0 - P) without the offset "
          f"{np.linalg.eigvalsh(m).min():.2e}")
    print(f"extra constant needed for an exact finite-record law: std {math.sqrt(delta):.3e} rad/s "
          f"= {math.degrees(math.sqrt(delta)) * 3600:.3f} deg/h, i.e. the walk started {delta / qk * dt:.0f} s earlier")
    return phi, gain, f


def costs(n: int, phi: np.ndarray, gain: np.ndarray, f: float) -> None:
    g = np.random.default_rng(0)
    out = np.empty(n)
    base = best(lambda: g.standard_normal(n, out=out))
    e = g.standard_normal(n)
    print(f"standard_normal float64: {n / base / 1e6:.1f} M/CPU-s (= 1 draw)")
    print(f"  float32 draw {best(lambda: g.standard_normal(n, dtype=np.float32)) / base:.2f}; "
          f"uniform {best(lambda: g.random(n, out=out)) / base:.2f}")
    sos = np.tile([1.0, -0.9, 0.0, 1.0, -1.5, 0.56], (5, 1))  # 5 stable sections (cost only)
    print(f"  sosfilt, 5 sections: {best(lambda: signal.sosfilt(sos, e)) / base:.2f}")
    try:
        import numba
    except ImportError:
        print("  numba not importable: no fused-loop figure")
        return

    @numba.njit(cache=False)
    def kern(e, u, phi, g, x, sf, cq, uprev, out):  # pragma: no cover - timing only
        for k in range(e.size):
            eps = sf * e[k]
            acc = eps
            for i in range(phi.size):
                acc += x[i]
                x[i] = phi[i] * x[i] + g[i] * eps
            uk = u[k]
            out[k] = acc + cq * (uk - uprev)
            uprev = uk
        return uprev

    u = g.random(n)
    x = np.zeros(phi.size + 1)
    ph = np.r_[phi, 1.0]
    kern(e[:8], u[:8], ph, gain, x, math.sqrt(f), 1.0, 0.0, out[:8])
    k_only = best(lambda: kern(e, u, ph, gain, x, math.sqrt(f), 1.0, 0.0, out)) / base
    r1, r2 = np.random.default_rng(1), np.random.default_rng(2)
    blk = 1 << 16

    def whole() -> None:
        up = 0.0
        for a in range(0, n, blk):
            up = kern(r1.standard_normal(blk), r2.random(blk), ph, gain, x, math.sqrt(f), 1.0, up, out[a:a + blk])

    tot = best(whole) / base
    print(f"  numba {numba.__version__} fused loop alone {k_only:.2f}; with its two draws {tot:.2f} "
          f"-> {1 / tot:.2f}x standard_normal before the slow flicker levels and the ramp")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1 << 22)
    args = ap.parse_args()
    print(f"load average {os.getloadavg()}")
    phi, gain, f = innovations(FS)
    costs(args.n, phi, gain, f)
    return 0


if __name__ == "__main__":
    sys.exit(main())
