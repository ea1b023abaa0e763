"""The gate's equivalence margin: the signed-rank test against it, and what a comparison's seeds
detect from the observed per-seed differences.

The margin (``--min-change``, :data:`~gyrobench.scenarios.bench.power.DEFAULT_MIN_CHANGE`) is
relative to each seed's baseline score: a change within it is never a regression, however
significant (:func:`margin_test`). :func:`observed_detectable` gives, per primary score, the
relative change the compared seeds detect with power 0.8, from the spread of the observed
relative differences; a comparison that detects only more than twice the margin is
*underpowered* and says so on its first line.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from gyrobench.scenarios.bench.power import detectable_change, min_attainable_p, seeds_for_change, std_upper_bound
from gyrobench.scenarios.bench.seeds import seed_text
from gyrobench.scenarios.bench.statistics import hodges_lehmann, signed_rank

__all__ = ["DetectableChange", "comparison_note", "margin_test", "observed_detectable", "power_line"]


def margin_test(d: np.ndarray, b: np.ndarray, direction: int, margin: float) -> tuple[float, float]:
    """(two-sided p, sign) of the signed-rank test of the paired differences ``d`` against the
    equivalence margin ``margin`` (relative to each seed's baseline ``|b|``).

    Without a direction or a margin, the plain test on ``d``. Otherwise the side the shift lies
    on is tested against the margin's edge: a worse shift on ``d + direction margin |b|`` (zero
    at a change of exactly the margin), a better one on ``d - direction margin |b|``; the sign
    is returned only when the test finds the change beyond the edge on that side (else 0: within
    the margin, "unchanged" however significant)."""
    if direction == 0 or margin <= 0 or d.size == 0:
        return signed_rank(d)
    tol = margin * np.abs(b)
    worse = hodges_lehmann(d) * direction < 0
    edge = d + direction * tol if worse else d - direction * tol
    p, sign = signed_rank(edge)
    beyond = sign * direction < 0 if worse else sign * direction > 0
    return p, (sign if beyond else 0.0)


@dataclass(frozen=True, slots=True, kw_only=True)
class DetectableChange:
    """What a comparison's seeds detect on one primary score, from the observed spread.

    ``change`` is the relative change detected with power 0.8 (``margin`` plus the shift beyond
    it; ``inf``: cannot tell, fewer than two seeds); ``sigma`` the standard deviation of the
    relative per-seed differences and ``sigma_upper`` its upper confidence bound
    (:func:`~gyrobench.scenarios.bench.power.std_upper_bound`), from which ``change`` and
    ``seeds_needed`` (the seeds that detect twice the margin) are computed. ``underpowered``:
    ``change`` is more than twice the margin.
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
    """Per primary score: the relative change these seeds detect with power
    :data:`~gyrobench.scenarios.bench.power.DEFAULT_POWER`, ``margin`` plus the shift beyond it
    :func:`~gyrobench.scenarios.bench.power.detectable_change` gives for the upper confidence
    bound (:func:`~gyrobench.scenarios.bench.power.std_upper_bound`) of the standard deviation
    of the observed relative differences ``(c_s - b_s) / |b_s|``, and the seeds that detect a change
    of twice the margin (:func:`~gyrobench.scenarios.bench.power.seeds_for_change`)."""
    out = []
    m = max(1, len(gates))
    for name in gates:
        b, c = base.values(name, seeds), cand.values(name, seeds)
        ok = np.isfinite(b) & np.isfinite(c) & (b != 0)
        rel = (c[ok] - b[ok]) / np.abs(b[ok])
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
    """One line: the relative change a comparison's seeds detect on each primary score; it starts
    with ``WARNING: underpowered`` when that is more than twice the margin ("" without scores)."""
    if not detectable:
        return ""
    parts = [_change_text(d, alpha) for d in detectable]
    weak = [d for d in detectable if d.underpowered]
    head = (
        f"detectable change at {detectable[0].n} seeds (power 0.8, alpha {alpha:g}, margin "
        f"{100 * margin:g} %, from the upper bound of the observed per-seed differences' spread): "
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
    """The comparison's caveats in one line: baseline seeds left out, different configurations,
    too few seeds for any change to be significant."""
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
            f"only {n_min} paired seeds: the smallest attainable Holm-adjusted p over the "
            f"{len(gated)} primary score(s) is {min_attainable_p(n_min, len(gated)):.3g} >= alpha "
            f"{alpha:g}, so no change can be significant; use more seeds"
        )
    return "; ".join(notes)
