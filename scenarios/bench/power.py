"""Power of the bench's gate, worked out before anything is computed.

The gate tests ``m`` primary scores (:mod:`gyrobench.scenarios.bench.primary`) with the
two-sided Wilcoxon signed-rank test on ``n`` paired seeds, Holm-adjusted at ``alpha``.

- :func:`min_attainable_p`: the smallest p the gate can ever report. The exact signed-rank
  distribution puts probability ``2**-n`` on "every difference positive", so the smallest
  two-sided p is ``2 / 2**n``; Holm's first step multiplies it by ``m``.
- :func:`seeds_needed`: the fewest seeds with ``m * 2 / 2**n < alpha``.
- :func:`check_power`: refuse (:class:`UnderpoweredError`, a ``ValueError``: exit 2) a gate
  that can never fire, in one line naming the seeds needed.
- :func:`seeds_for_change` / :func:`detectable_change`: the seeds that detect a shift
  ``delta`` of a score with seed-to-seed spread ``sigma`` (power ``power``), and the shift
  ``n`` seeds detect; :func:`auto_seeds` is ``--seeds auto``.
- :func:`std_upper_bound`: the spread those are given. A standard deviation estimated from a
  few seeds of a heavy-tailed score is more often too small than too large (the rare large
  seed is missing), and a campaign sized from it falls short of its power; every seed count
  and detectable change the bench states is computed from the one-sided
  :data:`SPREAD_CONFIDENCE` upper confidence bound of the spread instead (Bonett 2006,
  which widens with the sample's kurtosis).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

__all__ = [
    "DEFAULT_MIN_CHANGE",
    "DEFAULT_POWER",
    "SPREAD_CONFIDENCE",
    "WILCOXON_ARE",
    "AutoSeeds",
    "Detectable",
    "UnderpoweredError",
    "UnderpoweredWarning",
    "auto_seeds",
    "check_power",
    "detectable_change",
    "min_attainable_p",
    "power_statement",
    "seeds_for_change",
    "seeds_needed",
    "spread",
    "std_upper_bound",
]

#: the gate's equivalence margin (``--min-change``), relative to the baseline's score: a change
#: within it is never a regression; ``--seeds auto`` sizes a campaign to detect twice it
DEFAULT_MIN_CHANGE = 0.05
#: the probability of detecting that change ``--seeds auto`` asks for
DEFAULT_POWER = 0.80
#: lower bound of the asymptotic relative efficiency of the signed-rank test to the paired t
#: test over all symmetric distributions (Hodges and Lehmann 1956: 108/125 = 0.864)
WILCOXON_ARE = 108 / 125
#: one-sided confidence of the upper bound on a standard deviation (:func:`std_upper_bound`)
#: from which seed counts and detectable changes are computed. Chosen by simulation: sized from
#: 16 seeds of a lognormal score (shape 1, kurtosis 114), a campaign reaches power 0.90 with
#: this bound and 0.60 with the sample standard deviation (the tests check both against 0.8)
SPREAD_CONFIDENCE = 0.95


class UnderpoweredError(ValueError):
    """The gate cannot reach ``alpha`` with these seeds and scores (bad input: exit 2)."""


class UnderpoweredWarning(UserWarning):
    """A gate allowed to run although its seeds cannot reach ``alpha``: it cannot fail."""


def min_attainable_p(n: int, m: int) -> float:
    """Smallest Holm-adjusted p of ``m`` two-sided signed-rank tests on ``n`` paired seeds.

    ``min(1, m * 2 / 2**n)``: the exact null distribution gives the most extreme outcome (all
    ``n`` differences of one sign) probability ``2**-n`` per side, and Holm's first step
    multiplies the smallest p by ``m``.
    """
    _check_counts(n, m)
    return min(1.0, m * 2.0 / 2.0**n) if n < 1100 else 0.0


def seeds_needed(m: int, alpha: float) -> int:
    """Fewest paired seeds ``n`` with ``m * 2 / 2**n < alpha`` (the gate can fire at all)."""
    _check_counts(1, m)
    _check_alpha(alpha)
    n = 1
    while m * 2.0 / 2.0**n >= alpha:
        n += 1
    return n


def _check_counts(n: int, m: int) -> None:
    if isinstance(n, bool) or not isinstance(n, int) or n < 0:
        raise ValueError(f"number of seeds must be an integer >= 0; got {n!r}")
    if isinstance(m, bool) or not isinstance(m, int) or m < 1:
        raise ValueError(f"number of gated scores must be an integer >= 1; got {m!r}")


def _check_alpha(alpha: float) -> None:
    if not (isinstance(alpha, (int, float)) and 0 < alpha < 1):
        raise ValueError(f"alpha must be in (0, 1); got {alpha!r}")


def power_statement(n: int, m: int, alpha: float) -> str:
    """``"... smallest attainable p ... = 0.188 >= alpha 0.05"`` for ``n`` seeds, ``m`` scores."""
    p = min_attainable_p(n, m)
    return (
        f"with {n} paired seed(s) and {m} primary score(s) the smallest attainable p of the "
        f"two-sided Wilcoxon signed-rank test, Holm-adjusted, is {m} x 2/2^{n} = {p:.3g} "
        f"{'>=' if p >= alpha else '<'} alpha {alpha:g}"
    )


def check_power(
    n: int, m: int, alpha: float, *, allow_underpowered: bool = False, seeds_flag: str = "--seeds",
    allow_flag: str = "--allow-underpowered",
) -> str:
    """Refuse a gate that can never report a regression; return the warning when allowed.

    Returns ``""`` when ``n`` seeds can reach ``alpha`` with ``m`` primary scores, else the
    one-line warning (``"WARNING: underpowered: ..."``) if ``allow_underpowered``.

    Raises
    ------
    UnderpoweredError
        If ``n`` seeds cannot reach ``alpha`` and ``allow_underpowered`` is false; the
        message names the seeds needed.
    """
    _check_alpha(alpha)
    if min_attainable_p(n, m) < alpha:
        return ""
    need = seeds_needed(m, alpha)
    what = (
        f"{seeds_flag}: {power_statement(n, m, alpha)}, so no regression can ever be reported; "
        f"use at least {need} seeds ({seeds_flag} 0:{need})"
    )
    if not allow_underpowered:
        raise UnderpoweredError(f"{what}, or {allow_flag} to run anyway")
    return f"WARNING: underpowered: {what}; running anyway ({allow_flag}): this gate cannot fail"


def _normal_quantile(q: float) -> float:
    from scipy import stats

    return float(stats.norm.ppf(q))


def seeds_for_change(
    sigma: float, delta: float, m: int, alpha: float, *, power: float = DEFAULT_POWER
) -> int:
    """Paired seeds the gate needs to detect a shift ``delta`` of one of ``m`` primary scores.

    Parameters
    ----------
    sigma : float
        Standard deviation of the per-seed paired differences [score unit].
    delta : float
        Shift to detect [score unit], > 0.
    m, alpha : int, float
        Primary scores and family-wise level (Holm, whose first step is Bonferroni ``alpha/m``).
    power : float
        Probability of detecting the shift.

    Notes
    -----
    The paired t test needs ``n_t = ((z_{1-alpha/(2m)} + z_{power}) sigma / delta)**2`` seeds
    (normal approximation, two-sided at the Bonferroni level); the signed-rank test needs at
    most ``n_t / 0.864`` (its asymptotic relative efficiency is >= 108/125 for every symmetric
    distribution; Hodges and Lehmann 1956). The result is never below :func:`seeds_needed`,
    the fewest seeds with which the exact test can reach ``alpha`` at all.

    References
    ----------
    J. L. Hodges, E. L. Lehmann, "The efficiency of some nonparametric competitors of the
    t-test", Annals of Mathematical Statistics 27(2), 1956.
    """
    if not (math.isfinite(sigma) and sigma >= 0):
        raise ValueError(f"sigma must be finite and >= 0; got {sigma!r}")
    if not (math.isfinite(delta) and delta > 0):
        raise ValueError(f"delta must be finite and > 0; got {delta!r}")
    if not 0 < power < 1:
        raise ValueError(f"power must be in (0, 1); got {power!r}")
    floor = seeds_needed(m, alpha)
    z = _normal_quantile(1 - alpha / (2 * m)) + _normal_quantile(power)
    n_t = (z * sigma / delta) ** 2
    return max(floor, math.ceil(n_t / WILCOXON_ARE))


def detectable_change(
    sigma: float, n: int, m: int, alpha: float, *, power: float = DEFAULT_POWER
) -> float:
    """The shift [score unit] ``n`` paired seeds detect with probability ``power`` (inverse of
    :func:`seeds_for_change`); ``inf`` if ``n`` seeds cannot reach ``alpha`` at all."""
    if min_attainable_p(n, m) >= alpha:
        return math.inf
    z = _normal_quantile(1 - alpha / (2 * m)) + _normal_quantile(power)
    return z * sigma / math.sqrt(WILCOXON_ARE * n)


@dataclass(frozen=True, slots=True, kw_only=True)
class Detectable:
    """What a baseline's seeds can detect on one primary score (stored in the baseline file).

    ``change`` [``unit``] is detected with probability ``power`` at ``alpha`` by a comparison
    whose per-seed differences are as spread as ``std_upper`` (the :data:`SPREAD_CONFIDENCE`
    upper bound of the seed-to-seed ``std``, :func:`std_upper_bound`); ``relative`` is
    ``change / |mean|``; both ``inf`` when the seeds cannot reach ``alpha``.
    """

    name: str
    unit: str
    mean: float
    std: float
    std_upper: float
    n: int
    change: float
    relative: float


@dataclass(frozen=True, slots=True, kw_only=True)
class AutoSeeds:
    """The seed count ``--seeds auto`` chose and why (``reason``, one line)."""

    n: int
    reason: str


def auto_seeds(
    m: int,
    alpha: float,
    *,
    spreads: Mapping[str, tuple[float, float, float]] | None = None,
    units: Mapping[str, str] | None = None,
    min_change: float = DEFAULT_MIN_CHANGE,
    power: float = DEFAULT_POWER,
) -> AutoSeeds:
    """``--seeds auto``: the seeds that detect a relative change of twice the margin
    ``min_change`` (a shift of ``min_change`` beyond it) of every primary score.

    Parameters
    ----------
    m, alpha : int, float
        Primary scores and family-wise level.
    spreads : mapping of str to (float, float, float), optional
        Each primary score's (mean, sample std, upper bound of the std) over the baseline's
        seeds (:func:`spread`, :func:`std_upper_bound`).
    units : mapping of str to str, optional
        Each score's unit, for the reason line.
    min_change : float
        The equivalence margin, a fraction of the mean.
    power : float
        Probability of detecting a change of twice the margin.

    Returns
    -------
    AutoSeeds
        The largest of the per-score counts :func:`seeds_for_change` gives for the shift
        ``min_change |mean|`` beyond the margin and the spread ``std_upper``, and the reason.

    Notes
    -----
    The per-seed paired difference is assumed as spread as the baseline's seed-to-seed values:
    conservative when the new compensator's per-seed scores follow the baseline's (positively
    correlated). That spread is taken at its one-sided :data:`SPREAD_CONFIDENCE` upper bound
    (:func:`std_upper_bound`), not at the sample std, which from a small baseline of a
    heavy-tailed score is usually too small: the count then reaches ``power`` over baselines,
    not only for the lucky ones. Without a baseline (``spreads`` None) the change is assumed
    larger than the seed-to-seed spread (every seed moves the same way), so only the exact
    test's floor (:func:`seeds_needed`) applies; the reason says so.
    """
    if not (isinstance(min_change, (int, float)) and 0 < min_change < 10):
        raise ValueError(f"min_change must be in (0, 10) (a fraction of the mean); got {min_change!r}")
    floor = seeds_needed(m, alpha)
    how = (
        f"two-sided Wilcoxon signed-rank, Holm over {m} primary score(s), alpha {alpha:g}, "
        f"power {power:g}"
    )
    if not spreads:
        return AutoSeeds(
            n=floor,
            reason=(
                f"--seeds auto: {floor} seeds, the fewest with which the gate can fire ({how}); no "
                "baseline, so it assumed a change larger than the seed-to-seed spread (every seed "
                "worse): give --baseline to size the campaign from the baseline's spread"
            ),
        )
    n, worst = floor, ""
    for name, (mean, std, upper) in spreads.items():
        delta = min_change * abs(mean)
        if not math.isfinite(delta) or delta <= 0 or not math.isfinite(upper):
            continue
        need = seeds_for_change(upper, delta, m, alpha, power=power)
        if need > n or not worst:
            n = max(n, need)
            unit = (units or {}).get(name, "")
            u = f" {unit}" if unit else ""
            worst = (
                f"{name} (mean {mean:.4g}{u}, seed-to-seed std {std:.3g}{u}, "
                f"{100 * SPREAD_CONFIDENCE:g} % upper bound {upper:.3g}{u})"
            )
    return AutoSeeds(
        n=n,
        reason=(
            f"--seeds auto: {n} seeds detect a {200 * min_change:g} % change (twice the {100 * min_change:g} % "
            f"margin) of {worst} ({how}; "
            "assuming per-seed differences as spread as the baseline's seeds, at the upper bound)"
        ),
    )


def spread(values: Sequence[float] | np.ndarray) -> tuple[float, float]:
    """(mean, sample std) of the finite ``values`` (std NaN for fewer than two)."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if v.size == 0:
        return math.nan, math.nan
    return float(np.mean(v)), float(np.std(v, ddof=1)) if v.size > 1 else math.nan


def std_upper_bound(values: Sequence[float] | np.ndarray, confidence: float = SPREAD_CONFIDENCE) -> float:
    """One-sided upper confidence bound of the standard deviation of the finite ``values``.

    Bonett's interval, which does not assume normality: with ``n`` values, sample variance
    ``s**2``, ``z`` the standard normal ``confidence`` quantile and ``c = n / (n - z)``,

        sigma_U = sqrt(c s**2 exp(z se)),   se = c sqrt((k - (n - 3) / n) / (n - 1)),

    where ``k = n sum (y - m)**4 / (sum (y - ybar)**2)**2`` is the kurtosis estimate about the
    mean ``m`` trimmed by ``1 / (2 sqrt(n - 4))`` at each end (the plain mean for ``n <= 4``).
    A heavy-tailed sample (large ``k``) gets a wider bound; for normal values it is close to the
    chi-square bound ``s sqrt((n - 1) / chi2_{1-confidence, n-1})``.

    Parameters
    ----------
    values : sequence of float
        The sample (non-finite values are left out), in any unit.
    confidence : float
        One-sided confidence of the bound, in [0.5, 1).

    Returns
    -------
    float
        The bound, in the unit of ``values``: NaN for fewer than two values, ``inf`` when
        ``n <= z`` (too few values for the small-sample factor ``c``), 0 for constant values.

    References
    ----------
    D. G. Bonett, "Approximate confidence interval for standard deviation of nonnormal
    distributions", Computational Statistics & Data Analysis 50(3), 775-782, 2006.
    """
    from scipy import stats

    if not 0.5 <= confidence < 1:
        raise ValueError(f"confidence must be in [0.5, 1); got {confidence!r}")
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    n = int(v.size)
    if n < 2:
        return math.nan
    ss = float(np.sum((v - v.mean()) ** 2))
    if ss == 0:
        return 0.0
    z = _normal_quantile(confidence)
    if n <= z:
        return math.inf
    centre = float(stats.trim_mean(v, 1 / (2 * math.sqrt(n - 4)))) if n > 4 else float(v.mean())
    kurtosis = n * float(np.sum((v - centre) ** 4)) / ss**2
    c = n / (n - z)
    se = c * math.sqrt(max(kurtosis - (n - 3) / n, 0.0) / (n - 1))
    return math.sqrt(c * ss / (n - 1) * math.exp(z * se))
