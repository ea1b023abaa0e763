"""The statistics a claim is judged by: the Wilson interval of a pass rate, the verdict it gives,
the Fisher exact test against the control, the group-sequential ``z`` and the medians of the
reproduced quantities.

Each function is a plain function of counts (or of numbers), so the records in
:mod:`gyrobench.scenarios.claim_records` stay data and the numbers can be checked on their own.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "control_test",
    "finite_median",
    "sequential_error",
    "sequential_z",
    "verdict",
    "wilson_interval",
]

#: z for a two-sided 95 % interval
_Z95 = 1.959963984540054


def wilson_interval(k: int, n: int, z: float = _Z95) -> tuple[float, float]:
    """Wilson score interval for a binomial proportion ``k / n``.

    ``(p + z^2/2n -+ z sqrt(p(1-p)/n + z^2/4n^2)) / (1 + z^2/n)``, ``p = k/n``
    (Wilson, J. Am. Stat. Assoc. 22, 209 (1927); Brown, Cai & DasGupta, Stat. Sci. 16,
    101 (2001), eq. 4).

    Parameters
    ----------
    k : int
        Successes.
    n : int
        Trials, >= 1.
    z : float
        Standard normal quantile of the two-sided level.

    Returns
    -------
    tuple of float
        (low, high) of the proportion.
    """
    if isinstance(n, bool) or not (isinstance(n, int | np.integer) and n > 0):
        raise ValueError(f"n must be an integer > 0; got {n!r}")
    if isinstance(k, bool) or not (isinstance(k, int | np.integer) and 0 <= k <= n):
        raise ValueError(f"k must be an integer in [0, n={n}]; got {k!r}")
    p = k / n
    denom = 1.0 + z * z / n
    centre = (p + z * z / (2 * n)) / denom
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / denom
    # the ends are exactly 0 at k = 0 and exactly 1 at k = n (rounding gives +-1 ulp otherwise)
    lo = 0.0 if k == 0 else max(0.0, centre - half)
    hi = 1.0 if k == n else min(1.0, centre + half)
    return lo, hi


@functools.lru_cache(maxsize=65536)
def control_test(holds: int, testable: int, control_holds: int, control_testable: int) -> float:
    """Two-sided p-value of Fisher's exact test that the units and the control pass equally often.

    The 2 x 2 table [[holds, testable - holds], [control_holds, control_testable - control_holds]]
    (``scipy.stats.fisher_exact``, conditional on the margins; Fisher, Statistical Methods for
    Research Workers (1934) sec. 21.02); 1.0 when either row is empty.

    Parameters
    ----------
    holds, testable : int
        The units' pass count and testable count.
    control_holds, control_testable : int
        The control's.

    Returns
    -------
    float
        The two-sided p-value.
    """
    if testable <= 0 or control_testable <= 0:
        return 1.0
    from scipy.stats import fisher_exact

    table = [[holds, testable - holds], [control_holds, control_testable - control_holds]]
    return float(fisher_exact(table, alternative="two-sided").pvalue)


def verdict(holds: int, testable: int, z: float = _Z95) -> str:
    """The summary's word for a pass count (see the module docstring); ``z`` of the Wilson interval.

    Parameters
    ----------
    holds : int
        Units where the claim holds.
    testable : int
        Units that could test it.
    z : float
        z of the Wilson interval.

    Returns
    -------
    str
        ``"holds for most units"``, ``"fails for most units"``, ``"undecided"``, or
        ``"not testable"`` when no unit could test it.
    """
    if testable == 0:
        return "not testable"
    lo, hi = wilson_interval(holds, testable, z)
    if lo > 0.5:
        return "holds for most units"
    if hi < 0.5:
        return "fails for most units"
    return "undecided"


def _decided(k: NDArray[np.int_], n: int, z: float) -> NDArray[np.bool_]:
    """Whether the Wilson interval (``z``) of k of n excludes 50 % (vectorized :func:`verdict`)."""
    p = k / n
    denom = 1.0 + z * z / n
    centre = (p + z * z / (2 * n)) / denom
    half = z * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / denom
    return (centre - half > 0.5) | (centre + half < 0.5)


def sequential_error(looks: Sequence[int], z: float) -> float:
    """Exact chance that a claim of true pass rate 50 % is decided at any of several looks.

    Exact probability that a claim whose true pass rate is 50 % is decided (holds or fails) at any
    of the ``looks`` (unit counts, increasing) when each look judges it by the Wilson interval at ``z``.

    Dynamic programming over the binomial count of the units seen: the paths still undecided after
    each look are convolved with the next batch's Binomial(n_{k+1} - n_k, 1/2) and the mass that
    crosses the boundary is summed (the group-sequential crossing probability; Jennison & Turnbull,
    Group Sequential Methods (2000) sec. 19.2, for a binomial response).

    Parameters
    ----------
    looks : sequence of int
        Unit counts at each look, increasing.
    z : float
        z of the Wilson interval each look judges by.

    Returns
    -------
    float
        The probability of deciding (holds or fails) at some look.
    """
    from scipy.stats import binom

    alive = np.array([1.0])
    prev, crossed = 0, 0.0
    for n in looks:
        step = binom.pmf(np.arange(n - prev + 1), n - prev, 0.5)
        alive = np.convolve(alive, step)
        dec = _decided(np.arange(n + 1), n, z)
        crossed += float(alive[dec].sum())
        alive = np.where(dec, 0.0, alive)
        prev = n
    return crossed


@functools.lru_cache(maxsize=32)
def sequential_z(looks: tuple[int, ...], alpha: float = 0.05) -> float:
    """The constant Wilson z (a Pocock-type boundary) that keeps :func:`sequential_error` at or below
    ``alpha`` over ``looks``: the smallest such z to 1e-4 (bisection on [1.5, 6]; the error is a
    step function of z, non-increasing). One look: at or below 1.96 where the binomial's
    discreteness already keeps the error below alpha.

    Pocock, Biometrika 64, 191 (1977): one critical value at every look of a group-sequential test;
    here chosen from the exact binomial crossing probability instead of the normal approximation.
    """
    if not looks or any(b <= a for a, b in zip(looks[:-1], looks[1:], strict=False)) or looks[0] < 1:
        raise ValueError(f"looks must be increasing unit counts >= 1; got {looks!r}")
    lo, hi = 1.5, 6.0
    if sequential_error(looks, hi) > alpha:
        raise ValueError(f"no Wilson z <= {hi} keeps the error at or below alpha = {alpha!r} over looks {looks!r}")
    while hi - lo > 1e-4:
        mid = 0.5 * (lo + hi)
        if sequential_error(looks, mid) <= alpha:
            hi = mid
        else:
            lo = mid
    return hi


def _percentile(v: np.ndarray, q: float) -> float:
    """np.percentile's linear interpolation, with +-inf ends kept (numpy gives inf - inf = NaN)."""
    s = np.sort(v)
    h = (len(s) - 1) * q / 100.0
    i = int(math.floor(h))
    j = min(i + 1, len(s) - 1)
    a, b = float(s[i]), float(s[j])
    if h == i or a == b:
        return a
    if math.isinf(a) or math.isinf(b):
        return a if math.isinf(a) else b
    return float(np.percentile(v, q))


def finite_median(values: Iterable[Any]) -> float:
    """Median of the finite numbers among ``values`` (None, NaN and inf skipped); NaN if none.

    The one median the scenario reports use for per-unit figures, so an untestable unit
    (None or NaN) never turns a reported median into NaN or an error.

    Parameters
    ----------
    values : iterable
        Numbers, None or NaN.

    Returns
    -------
    float
        The median of the finite ones; NaN if none.
    """
    v = [float(x) for x in values if x is not None and math.isfinite(float(x))]
    return float(np.median(v)) if v else math.nan
