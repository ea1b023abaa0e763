"""False-alarm rate of fit_noise's misfit test on records that follow the model.

For each seed a record of the five-term model of coverage_fit.py (Q, N, B, K and R each in
charge of about a decade of tau) is generated, its overlapping ADEV (octave taus up to T/4)
is fitted with ``gyrobench.analysis.allan.fit_noise``, and we count how often the p-value
of the goodness-of-fit test falls below 1e-2 and 1e-3: a test that is right about its own
law flags those fractions of the seeds. Reported with exact (Clopper-Pearson) 95 % intervals.

Beside the test fit_noise uses (chi2 = sum of squared standardised residuals against the
exact law of that quadratic form under the fit's hat matrix), the statistic it used before
(r' V^-1 r against chi2(dof), dof = points - kept terms) is evaluated on the same fit, so
one run measures both. ``--tau-min auto`` fits from the data-found range (the CLI default;
its misfit-driven trimming uses the current statistic only).

Run: ``python benchmarks/misfit_false_alarm.py [--seeds 1000] [--hours 4] [--fs 10]
[--tau-min none|auto] [--workers 1]``.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def one(job: tuple[int, float, float, str]) -> tuple[float, float]:
    """(p-value of fit_noise, p-value of the former r' V^-1 r ~ chi2(dof) statistic) of one seed."""
    from coverage_fit import model
    from scipy import special

    from gyrobench.analysis.allan import allan_deviation, fit_noise

    seed, fs, hours, tau_min = job
    n = int(round(hours * 3600 * fs))
    y = model().generate(n, fs, rng=np.random.default_rng([20261124, seed]))
    fit = fit_noise(allan_deviation(y, fs), tau_min=None if tau_min == "none" else tau_min)
    r = fit.curve.variance[fit.used] - fit.avar(fit.tau_used)
    v = fit.point_covariance
    d = np.sqrt(np.diag(v))
    rn = r / d
    old = float(rn @ np.linalg.lstsq(v / np.outer(d, d), rn, rcond=1e-12)[0])
    return fit.p_value, float(special.chdtrc(fit.dof, old)) if fit.dof > 0 else float("nan")


def interval(k: int, n: int, level: float = 0.95) -> tuple[float, float]:
    """Clopper-Pearson interval of a binomial proportion k/n."""
    from scipy import stats

    a = (1 - level) / 2
    lo = stats.beta.ppf(a, k, n - k + 1) if k > 0 else 0.0
    hi = stats.beta.ppf(1 - a, k + 1, n - k) if k < n else 1.0
    return float(lo), float(hi)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seeds", type=int, default=1000)
    p.add_argument("--hours", type=float, default=4.0)
    p.add_argument("--fs", type=float, default=10.0)
    p.add_argument("--tau-min", choices=("none", "auto"), default="none")
    p.add_argument("--workers", type=int, default=1)
    a = p.parse_args(argv)
    t0 = time.perf_counter()
    jobs = [(s, a.fs, a.hours, a.tau_min) for s in range(a.seeds)]
    if a.workers > 1:
        with ProcessPoolExecutor(a.workers) as ex:
            res = np.array(list(ex.map(one, jobs, chunksize=8)))
    else:
        res = np.array([one(j) for j in jobs])
    n = len(res)
    print(
        f"misfit false alarms: {n} seeds of the coverage_fit.py model, {a.hours:g} h at {a.fs:g} Hz, "
        f"tau_min={a.tau_min}, {time.perf_counter() - t0:.0f} s"
    )
    for name, col in (("fit_noise (sum z^2, exact law)", 0), ("former r'V^-1 r ~ chi2(dof)", 1)):
        if a.tau_min == "auto" and col == 1:
            print(f"  {name:34}: not comparable with tau_min=auto (its trimming used the current test)")
            continue
        parts = []
        for level in (1e-2, 1e-3):
            k = int(np.sum(res[:, col] < level))
            lo, hi = interval(k, n)
            parts.append(f"p < {level:g}: {k}/{n} = {100 * k / n:.2f} % (95 % CI {100 * lo:.2f}-{100 * hi:.2f} %)")
        print(f"  {name:34}: " + "; ".join(parts))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
