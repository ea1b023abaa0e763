"""The gate's test against its equivalence margin, and what a comparison's seeds detect.

The gate judges the *mean* of each primary score: the relative change of the mean,
``R = mean(c) / mean(b) - 1`` over the paired seeds, against the margin (``--min-change``,
:data:`~gyrobench.scenarios.bench.power.DEFAULT_MIN_CHANGE`, relative to the baseline's mean).
A change within the margin is never a regression, however significant (:func:`margin_test`).
:func:`observed_detectable` gives, per primary score, the relative change the compared seeds
detect with power 0.8, from the spread of the same per-seed contrast the test uses; a
comparison that detects only more than twice the margin is *underpowered* and says so on its
first line.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from gyrobench.scenarios.bench.power import detectable_change, min_attainable_p, seeds_for_change, std_upper_bound
from gyrobench.scenarios.bench.seeds import seed_text
from gyrobench.scenarios.bench.statistics import score_direction

__all__ = ["DetectableChange", "comparison_note", "margin_contrast", "margin_test", "observed_detectable", "power_line"]


def margin_contrast(d: np.ndarray, b: np.ndarray, direction: int, margin: float, *, worse: bool) -> np.ndarray:
    """The per-seed contrast whose mean is zero at a change of the mean of exactly the margin.

    ``d + direction margin |b|`` for the worse side, ``d - direction margin |b|`` for the better
    one: for a lower-is-better score, ``c_s - b_s - margin |b_s|``, whose mean is
    ``mean|b| (R - margin)`` with ``R`` the relative change of the mean score (for scores > 0).

    Parameters
    ----------
    d : ndarray
        Paired differences ``c_s - b_s``.
    b : ndarray
        Each seed's baseline score.
    direction : int
        -1 (lower is better) or +1.
    margin : float
        The relative equivalence margin.
    worse : bool
        The side tested: worse (a regression) or better.

    Returns
    -------
    ndarray
        The contrast.
    """
    tol = margin * np.abs(b)
    return d + direction * tol if worse else d - direction * tol


def margin_test(d: np.ndarray, b: np.ndarray, direction: int, margin: float) -> tuple[float, float]:
    """The paired t test of the mean change against an equivalence margin.

    (p, sign) of the test that the mean score moved by more than ``margin`` (relative to the
    baseline's mean ``|b|``) on the side the mean difference ``mean(d)`` lies on.

    Parameters
    ----------
    d : ndarray
        Paired differences ``c_s - b_s``.
    b : ndarray
        Each seed's baseline score.
    direction : int
        -1 or +1 (0: unknown; then the plain two-sided test of ``mean(d) = 0``).
    margin : float
        The relative equivalence margin (0: the plain test).

    Returns
    -------
    tuple of float
        (p, sign): ``p = min(1, 2 p1)`` with ``p1`` the one-sided p that the change is beyond the
        margin on that side, and the sign of ``mean(d)`` when it is beyond (else 0: within the
        margin, "unchanged" however significant).

    Notes
    -----
    On the side the mean difference lies on, the contrast ``e_s`` (:func:`margin_contrast`) has
    mean ``mean|b| (R - margin)`` (worse side) with ``R = mean(c)/mean(b) - 1``, so ``E e = 0``
    is exactly "the mean changed by the margin" (the Fieller form of a test of a ratio of means:
    no linearisation). With ``ebar`` and ``s`` its mean and standard deviation over the ``n``
    seeds, ``t = ebar sqrt(n) / s`` and ``p1`` is the Student t tail beyond ``t`` with ``n - 1``
    degrees of freedom; the gate calls a change when the Holm-adjusted ``p`` is below
    ``alpha``, i.e. when the one-sided ``1 - alpha/2`` confidence bound of the change lies beyond
    the margin (``alpha/2`` per side: both "regressed" and "improved" are reported). Constant
    contrasts (``s = 0``) are beyond the margin on every seed or on none (the same compensator).
    ``p`` is never below ``2 / 2**n``, the smallest p a test whose level holds for every contrast
    distribution symmetric about zero can reach
    (:func:`~gyrobench.scenarios.bench.power.min_attainable_p`): with fewer seeds than the gate
    accepts it cannot fire, and a p beyond that would rest on the normality of the contrasts alone.

    Assumptions: independent seeds (each seed's simulation is its own), and a mean that is
    nearly normal over ``n`` seeds. The t test is exact for normal contrasts and its level
    holds as ``n`` grows for any contrast of finite variance; for a skewed contrast with few
    seeds its one-sided level is off by a term in the skewness over ``sqrt(n)`` (Hall 1992,
    section 3.5): below alpha/2 when the contrast is right-skewed or symmetric (rare seeds much
    worse, or a random part of the seeds worse), above it when the contrast is left-skewed
    (most seeds somewhat worse, a few much better). Measured on lognormal toys (the tests and
    docs/bench.md): at most 0.025 right-skewed and symmetric, 0.042-0.057 left-skewed, at
    12-200 seeds, so the false-alarm rate at a change of exactly the margin is at most about
    alpha.

    References
    ----------
    P. Hall, "The bootstrap and Edgeworth expansion", Springer, 1992.
    E. C. Fieller, "Some problems in interval estimation", Journal of the Royal Statistical
    Society B 16(2), 175-185, 1954.
    """
    from scipy import stats

    d = np.asarray(d, dtype=float)
    n = int(d.size)
    mean_d = float(np.mean(d)) if n else 0.0
    if direction == 0 or margin <= 0:
        e, toward = d, float(np.sign(mean_d))  # the plain test, on the mean difference's side
    else:
        worse = direction * mean_d < 0
        e = margin_contrast(d, np.asarray(b, dtype=float), direction, margin, worse=worse)
        toward = float(-direction if worse else direction)  # the sign of e's mean beyond the margin
    if n == 0 or toward == 0:
        return 1.0, 0.0
    ebar = float(np.mean(e))
    s = float(np.std(e, ddof=1)) if n > 1 else math.nan
    floor = 2.0 ** (1 - n)  # the smallest p a distribution-free test reaches (power.min_attainable_p)
    if not s > 0:  # one seed, or constant contrasts: beyond the margin on every seed, or not
        return (floor, float(np.sign(mean_d))) if n > 1 and toward * ebar > 0 else (1.0, 0.0)
    t = toward * ebar * math.sqrt(n) / s
    p = max(floor, min(1.0, 2 * float(stats.t.sf(t, n - 1))))
    return p, (float(np.sign(mean_d)) if t > 0 else 0.0)


@dataclass(frozen=True, slots=True, kw_only=True)
class DetectableChange:
    """What a comparison's seeds detect on one primary score, from the observed spread.

    ``change`` is the relative change detected with power 0.8 (``margin`` plus the shift beyond
    it; ``inf``: cannot tell, fewer than two seeds); ``sigma`` the standard deviation of the
    per-seed contrast the test judges (:func:`margin_contrast`, worse side) over the baseline's
    mean ``|b|``, and ``sigma_upper`` its upper confidence bound
    (:func:`~gyrobench.scenarios.bench.power.std_upper_bound`), from which ``change`` and
    ``seeds_needed`` (the seeds that detect twice the margin) are computed. ``underpowered``:
    ``change`` is more than twice the margin.

    Attributes
    ----------
    name : str
        The primary score.
    n : int
        Paired seeds.
    sigma : float
        Std of the per-seed contrast over the baseline's mean [-].
    sigma_upper : float
        Its upper confidence bound [-].
    change : float
        The relative change detected with power 0.8 [-] (inf: cannot tell).
    margin : float
        The equivalence margin [-].
    seeds_needed : int
        Seeds that detect twice the margin.
    """

    name: str
    n: int
    sigma: float
    sigma_upper: float
    change: float
    margin: float
    seeds_needed: int

    @property
    def underpowered(self) -> bool:
        return self.margin > 0 and not self.change <= 2 * self.margin


def observed_detectable(
    base: Any, cand: Any, seeds: Sequence[int], gates: Sequence[str], alpha: float, margin: float
) -> tuple[DetectableChange, ...]:
    """The relative change a comparison's seeds detect on each primary score.

    Per primary score: the relative change these seeds detect with power
    :data:`~gyrobench.scenarios.bench.power.DEFAULT_POWER`, ``margin`` plus the shift beyond it
    :func:`~gyrobench.scenarios.bench.power.detectable_change` gives for the upper confidence
    bound (:func:`~gyrobench.scenarios.bench.power.std_upper_bound`) of the standard deviation
    of the contrast :func:`margin_test` judges on the worse side (:func:`margin_contrast`: for a
    lower-is-better score ``c_s - b_s - margin |b_s|``) over the baseline's mean ``|b|``, and the
    seeds that detect a change of twice the margin
    (:func:`~gyrobench.scenarios.bench.power.seeds_for_change`). The direction of each score is
    its name's (:func:`~gyrobench.scenarios.bench.statistics.score_direction`; lower is better
    when unknown).

    Parameters
    ----------
    base, cand : Campaign
        The baseline and candidate campaigns.
    seeds : sequence of int
        The paired seeds.
    gates : sequence of str
        The primary scores.
    alpha : float
        Family-wise level.
    margin : float
        The equivalence margin.

    Returns
    -------
    tuple of DetectableChange
        One per primary score.
    """
    out = []
    m = max(1, len(gates))
    for name in gates:
        b, c = base.values(name, seeds), cand.values(name, seeds)
        ok = np.isfinite(b) & np.isfinite(c)
        scale = float(np.mean(np.abs(b[ok]))) if ok.any() else 0.0
        direction = score_direction(name) or -1
        rel = margin_contrast(c[ok] - b[ok], b[ok], direction, margin, worse=True) / scale if scale > 0 else b[:0]
        n = int(rel.size)
        sigma = float(np.std(rel, ddof=1)) if n > 1 else math.nan
        upper = std_upper_bound(rel)
        if not math.isfinite(upper):
            change, need = math.inf, 0
        else:
            change = margin + detectable_change(upper, n, m, alpha)
            need = seeds_for_change(upper, margin, m, alpha) if margin > 0 else 0
        out.append(DetectableChange(
            name=name, n=n, sigma=sigma, sigma_upper=upper, change=change, margin=margin, seeds_needed=need,
        ))
    return tuple(out)


def power_line(detectable: Sequence[DetectableChange], alpha: float, margin: float) -> str:
    """One line: the relative change a comparison's seeds detect on each primary score.

    One line: the relative change a comparison's seeds detect on each primary score; it starts
    with ``WARNING: underpowered`` when that is more than twice the margin ("" without scores).

    Parameters
    ----------
    detectable : sequence of DetectableChange
        Per primary score.
    alpha : float
        Family-wise level.
    margin : float
        The equivalence margin.

    Returns
    -------
    str
        One line.
    """
    if not detectable:
        return ""
    parts = [_change_text(d, alpha) for d in detectable]
    weak = [d for d in detectable if d.underpowered]
    head = (
        f"detectable change at {detectable[0].n} seeds (power 0.8, alpha {alpha:g}, margin "
        f"{100 * margin:g} %, mean change, from the upper bound of the observed per-seed spread): "
        f"{', '.join(parts)}"
    )
    if not weak:
        return head
    need = max(d.seeds_needed for d in weak)
    more = f"; about {need} seeds detect a change of {200 * margin:g} %" if need else ""
    return f"WARNING: underpowered: {head}: more than twice the margin{more}"


def _change_text(d: DetectableChange, alpha: float) -> str:
    """``name 12.3 %``, or why no change is detectable on that score."""
    if math.isfinite(d.change):
        return f"{d.name} {100 * d.change:.3g} %"
    if d.n > 1 and math.isfinite(d.sigma):
        return f"{d.name} (none: {d.n} seeds cannot reach alpha {alpha:g})"
    return f"{d.name} (not estimable: {d.n} finite paired seed(s))"


def comparison_note(scores: Sequence[Any], dropped: Sequence[int], *, same_config: bool, alpha: float) -> str:
    """The comparison's caveats in one line.

    The comparison's caveats in one line: baseline seeds left out, different configurations,
    too few seeds for any change to be significant.

    Parameters
    ----------
    scores : sequence of ScoreComparison
        The scores compared.
    dropped : sequence of int
        Baseline seeds left out.
    same_config : bool
        Both campaigns ran one configuration.
    alpha : float
        Family-wise level.

    Returns
    -------
    str
        One line ("" when nothing to say).
    """
    notes = []
    if dropped:
        notes.append(
            f"baseline seeds {seed_text(dropped)} have non-finite scores and are not compared"
        )
    if not same_config:
        notes.append("the two campaigns ran different scenario configurations")
    gated = [s for s in scores if s.primary]
    n_min = min(s.n for s in gated)
    if min_attainable_p(n_min, len(gated)) >= alpha:
        notes.append(
            f"only {n_min} paired seeds: the smallest p a distribution-free test reaches, Holm-adjusted "
            f"over the {len(gated)} primary score(s), is {min_attainable_p(n_min, len(gated)):.3g} >= "
            f"alpha {alpha:g}, so no change can be significant; use more seeds"
        )
    return "; ".join(notes)
