"""Power of the bench's gate, worked out before anything is computed.

The gate tests ``m`` primary scores (:mod:`gyrobench.scenarios.bench.primary`) on ``n`` paired
seeds, Holm-adjusted at ``alpha``: for each score, whether the *mean* changed by more than the
equivalence margin (the ratio of the mean scores, candidate over baseline, against
``1 +- margin``), by the paired Student t test of the per-seed contrast
``c_s - b_s -+ margin |b_s|`` (:func:`~gyrobench.scenarios.bench.margin.margin_test`), one-sided on
each side at ``alpha / 2``. Everything here is worked out for that test, from one formula
(:func:`detection_power`).

- :func:`min_attainable_p`: the fewest seeds the gate accepts. With ``n`` seeds no test whose level
  holds for every distribution of the per-seed contrast symmetric about zero can go below
  ``2 / 2**n`` (given the contrasts' sizes, their ``2**n`` sign patterns are equally likely), and
  Holm's first step multiplies it by ``m``. Below that the t test's level would rest on normality
  alone.
- :func:`seeds_needed`: the fewest seeds with ``m * 2 / 2**n < alpha``.
- :func:`check_power`: refuse (:class:`UnderpoweredError`, a ``ValueError``: exit 2) fewer seeds,
  in one line naming the seeds needed.
- :func:`detection_power`, :func:`seeds_for_change` / :func:`detectable_change`: the probability
  that ``n`` seeds detect a mean shift ``delta`` beyond the margin of a score whose per-seed
  contrast has standard deviation ``sigma`` (the noncentral t), the seeds that detect it with
  power ``power``, and the shift ``n`` seeds detect; :func:`auto_seeds` is ``--seeds auto``.
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
    "TEST",
    "AutoSeeds",
    "Detectable",
    "UnderpoweredError",
    "UnderpoweredWarning",
    "auto_seeds",
    "check_power",
    "detectable_change",
    "detection_power",
    "partial_spread",
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
#: the gate's test, as the comparison and the baseline file state it
TEST = (
    "paired t test of the mean change (ratio of the mean scores, candidate / baseline) against the "
    "equivalence margin, one-sided at alpha/2 on each side"
)
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
    """Smallest Holm-adjusted p of ``m`` distribution-free paired tests on ``n`` seeds.

    ``min(1, m * 2 / 2**n)``: given the sizes of the ``n`` per-seed contrasts, a test whose level
    holds for every distribution symmetric about zero sees their ``2**n`` sign patterns as equally
    likely, so the most extreme one (all of one sign) has probability ``2**-n`` per side, and
    Holm's first step multiplies the smallest p by ``m``. The gate refuses seeds that cannot go
    below ``alpha`` (:func:`check_power`): with fewer, its t test's level would rest on the
    normality of the contrasts alone.

    Parameters
    ----------
    n : int
        Paired seeds.
    m : int
        Primary scores.

    Returns
    -------
    float
        min(1, m 2 / 2^n).
    """
    _check_counts(n, m)
    return min(1.0, m * 2.0 / 2.0**n) if n < 1100 else 0.0


def seeds_needed(m: int, alpha: float) -> int:
    """Fewest paired seeds ``n`` with ``m * 2 / 2**n < alpha`` (the gate can fire at all).

    Parameters
    ----------
    m : int
        Primary scores.
    alpha : float
        Family-wise level.

    Returns
    -------
    int
        The fewest seeds n.
    """
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
    """``"... smallest attainable p ... = 0.188 >= alpha 0.05"`` for ``n`` seeds, ``m`` scores.

    Parameters
    ----------
    n : int
        Paired seeds.
    m : int
        Primary scores.
    alpha : float
        Family-wise level.

    Returns
    -------
    str
        The statement.
    """
    p = min_attainable_p(n, m)
    return (
        f"with {n} paired seed(s) and {m} primary score(s) the smallest p a distribution-free "
        f"two-sided paired test can reach, Holm-adjusted, is {m} x 2/2^{n} = {p:.3g} "
        f"{'>=' if p >= alpha else '<'} alpha {alpha:g}"
    )


def check_power(
    n: int, m: int, alpha: float, *, allow_underpowered: bool = False, seeds_flag: str = "--seeds",
    allow_flag: str = "--allow-underpowered",
) -> str:
    """Refuse a gate that can never report a regression; return the warning when allowed.

    Returns ``""`` when ``n`` seeds can reach ``alpha`` with ``m`` primary scores, else the
    one-line warning (``"WARNING: underpowered: ..."``) if ``allow_underpowered``.

    Parameters
    ----------
    n : int
        Paired seeds.
    m : int
        Primary scores.
    alpha : float
        Family-wise level.
    allow_underpowered : bool
        Warn instead of refusing.
    seeds_flag, allow_flag : str
        The flags named in the messages.

    Returns
    -------
    str
        ``""``, or the warning when allowed.

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


def _check_spread(sigma: float, power: float) -> None:
    if not (math.isfinite(sigma) and sigma >= 0 and 0 < power < 1):
        raise ValueError(f"sigma must be finite and >= 0 and power in (0, 1); got {sigma!r}, {power!r}")


def detection_power(sigma: float, delta: float, n: int, m: int, alpha: float) -> float:
    """Probability that ``n`` paired seeds detect a mean shift ``delta`` beyond the margin.

    Parameters
    ----------
    sigma : float
        Standard deviation of the per-seed contrast the gate tests [score unit], > 0.
    delta : float
        True mean shift beyond the margin [score unit], >= 0.
    n : int
        Paired seeds, >= 2.
    m, alpha : int, float
        Primary scores and family-wise level (Holm, whose first step is Bonferroni ``alpha/m``).

    Returns
    -------
    float
        The probability.

    Notes
    -----
    The gate calls a regression when the one-sided paired t statistic of the contrast
    (:func:`~gyrobench.scenarios.bench.margin.margin_test`) exceeds ``t_{1-alpha/(2m), n-1}``.
    For normal contrasts the statistic follows the noncentral t with ``n - 1`` degrees of
    freedom and noncentrality ``delta sqrt(n) / sigma``, so the power is

        P = 1 - F_{nct}(t_{1-alpha/(2m), n-1}; n - 1, delta sqrt(n) / sigma),

    exact for normal contrasts and the large-``n`` power for any contrast of finite variance: the
    one formula behind every seed count and detectable change the bench states.

    References
    ----------
    J. Cohen, "Statistical power analysis for the behavioral sciences", 2nd ed., 1988, ch. 2.
    """
    from scipy import stats

    if sigma == 0:
        return 1.0 if delta > 0 else 0.0
    crit = float(stats.t.ppf(1 - alpha / (2 * m), n - 1))
    return float(stats.nct.sf(crit, n - 1, delta * math.sqrt(n) / sigma))


def partial_spread(std: float, mean: float, change: float) -> float:
    """Spread of the per-seed contrast when a relative ``change`` of the mean is carried by half the seeds.

    Parameters
    ----------
    std : float
        The seed-to-seed spread of the score [score unit] (its upper bound, :func:`std_upper_bound`).
    mean : float
        The score's mean [score unit].
    change : float
        The relative change of the mean [-].

    Returns
    -------
    float
        ``sqrt(std**2 + (change |mean|)**2)`` [score unit].

    Notes
    -----
    The sizing's design case: a random half of the seeds worse by ``2 change``, the others
    unchanged. Its per-seed change ``2 change |mean| B`` (``B`` fair Bernoulli) has standard
    deviation ``change |mean|``, added in quadrature to the seeds' own spread. A change carried
    by fewer seeds, or more uneven, is detected with less than the stated power (the
    comparison's detectable change, from the observed spread, then says so).
    """
    return math.hypot(std, change * abs(mean))


def seeds_for_change(
    sigma: float, delta: float, m: int, alpha: float, *, power: float = DEFAULT_POWER
) -> int:
    """Paired seeds the gate needs to detect a mean shift ``delta`` of one of ``m`` primary scores.

    Parameters
    ----------
    sigma : float
        Standard deviation of the per-seed contrast [score unit].
    delta : float
        Mean shift beyond the margin to detect [score unit], > 0.
    m, alpha : int, float
        Primary scores and family-wise level.
    power : float
        Probability of detecting the shift.

    Returns
    -------
    int
        The fewest seeds whose :func:`detection_power` reaches ``power``, never below
        :func:`seeds_needed` (the fewest the gate accepts at all).
    """
    _check_spread(sigma, power)
    if not (math.isfinite(delta) and delta > 0):
        raise ValueError(f"delta must be finite and > 0; got {delta!r}")
    floor = max(2, seeds_needed(m, alpha))
    if detection_power(sigma, delta, floor, m, alpha) >= power:
        return floor
    hi = max(floor + 1, math.ceil(((_normal_quantile(1 - alpha / (2 * m)) + _normal_quantile(power))
                                   * sigma / delta) ** 2))  # the normal approximation, a start
    while detection_power(sigma, delta, hi, m, alpha) < power:
        hi *= 2
    lo = floor  # power(lo) < power <= power(hi)
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if detection_power(sigma, delta, mid, m, alpha) >= power:
            hi = mid
        else:
            lo = mid
    return hi


def detectable_change(
    sigma: float, n: int, m: int, alpha: float, *, power: float = DEFAULT_POWER
) -> float:
    """The mean shift beyond the margin that a number of paired seeds detects with a given power.

    The shift [score unit] whose :func:`detection_power` at ``n`` seeds is ``power`` (inverse of
    :func:`seeds_for_change`); ``inf`` if the gate does not accept ``n`` seeds
    (:func:`min_attainable_p` >= ``alpha``).

    Parameters
    ----------
    sigma : float
        Std of the per-seed contrast [score unit].
    n : int
        Paired seeds.
    m : int
        Primary scores.
    alpha : float
        Family-wise level.
    power : float
        Detection probability.

    Returns
    -------
    float
        The shift [score unit].
    """
    from scipy import optimize

    _check_spread(sigma, power)
    if n < 2 or min_attainable_p(n, m) >= alpha:
        return math.inf
    if sigma == 0:
        return 0.0
    z = _normal_quantile(1 - alpha / (2 * m)) + _normal_quantile(power)
    hi = 2 * z * sigma / math.sqrt(n)
    while detection_power(sigma, hi, n, m, alpha) < power:
        hi *= 2
    return float(optimize.brentq(
        lambda delta: detection_power(sigma, delta, n, m, alpha) - power, 0.0, hi, xtol=1e-12 * hi, rtol=1e-12
    ))


@dataclass(frozen=True, slots=True, kw_only=True)
class Detectable:
    """What a baseline's seeds can detect on one primary score (stored in the baseline file).

    ``change`` [``unit``] is detected with probability ``power`` at ``alpha`` by a comparison
    whose per-seed differences are as spread as ``std_upper`` (the :data:`SPREAD_CONFIDENCE`
    upper bound of the seed-to-seed ``std``, :func:`std_upper_bound`); ``relative`` is
    ``change / |mean|``; both ``inf`` when the seeds cannot reach ``alpha``.

    Attributes
    ----------
    name : str
        The primary score.
    unit : str
        Its unit.
    mean : float
        Its mean over the baseline's seeds.
    std : float
        Its seed-to-seed std.
    std_upper : float
        The upper confidence bound of ``std`` (:func:`std_upper_bound`).
    n : int
        Seeds.
    change : float
        The shift detected [unit].
    relative : float
        ``change`` over |mean|.
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
    """The seed count ``--seeds auto`` chose and why (``reason``, one line).

    Attributes
    ----------
    n : int
        The seed count.
    reason : str
        Why, one line.
    """

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
    """The seed count ``--seeds auto`` chooses.

    ``--seeds auto``: the seeds that detect a relative change of twice the margin
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
        ``min_change |mean|`` beyond the margin and the spread
        ``partial_spread(std_upper, mean, 2 min_change)`` (:func:`partial_spread`: the change
        carried by a random half of the seeds), and the reason.

    Notes
    -----
    The per-seed contrast the gate tests (``c_s - b_s - min_change |b_s|``) is assumed as spread
    as the baseline's seed-to-seed values: conservative when the new compensator's per-seed
    scores follow the baseline's (positively correlated; a change by the same factor on every
    seed, or on a random part of the seeds, of less than the score's own spread). That spread is
    taken at its one-sided :data:`SPREAD_CONFIDENCE` upper bound (:func:`std_upper_bound`), not
    at the sample std, which from a small baseline of a
    heavy-tailed score is usually too small: the count then reaches ``power`` over baselines,
    not only for the lucky ones. Without a baseline (``spreads`` None) the change is assumed
    larger than the seed-to-seed spread (every seed moves the same way), so only the gate's
    floor (:func:`seeds_needed`) applies; the reason says so.
    """
    if not (isinstance(min_change, (int, float)) and 0 < min_change < 10):
        raise ValueError(f"min_change must be in (0, 10) (a fraction of the mean); got {min_change!r}")
    floor = seeds_needed(m, alpha)
    how = (
        f"paired t test of the mean change against the margin, Holm over {m} primary score(s), "
        f"alpha {alpha:g}, power {power:g}"
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
        need = seeds_for_change(partial_spread(upper, mean, 2 * min_change), delta, m, alpha, power=power)
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
            "assuming per-seed contrasts as spread as the baseline's seeds, at the upper bound, plus "
            "the spread of a change carried by half the seeds)"
        ),
    )


def spread(values: Sequence[float] | np.ndarray) -> tuple[float, float]:
    """(mean, sample std) of the finite ``values`` (std NaN for fewer than two).

    Parameters
    ----------
    values : sequence of float or ndarray
        Values.

    Returns
    -------
    tuple of float
        (mean, sample std).
    """
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
