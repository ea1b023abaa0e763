"""The paper's 65 % over three gyros: the improvement claim judged over triples of units.

Paper 004 reports its improvement over three gyros. Beside the per-unit claim
(:data:`.claims.CLAIMS`, ``004.improvement_65pct``), the units are grouped in consecutive triples
(seeds s, s+1, s+2 from the run's first seed; a last incomplete group is left out) and each
triple is one "paper": its improvement is the mean of its three gyros' held-out improvements,
``mean_i 100 (1 - after_i / before_i)`` [%], turned into the before/after ratio
``1 / (1 - mean / 100)`` and judged with the per-unit claim's comparator. A triple is testable
when all three units show the thermal effect (:data:`.claims.THERMAL_PRECONDITION`) and have a
held-out ratio; otherwise it counts as precondition-absent.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from gyrobench.scenarios.claims import verdict, wilson_interval

from .claims import CLAIMS, THERMAL_PRECONDITION
from .results import UnitResult

__all__ = ["TripleResult", "judge_triples"]

_CLAIM = next(c for c in CLAIMS if c.id == "004.improvement_65pct")


@dataclass(frozen=True, slots=True, kw_only=True)
class TripleResult:
    """The 65 % claim over triples of units.

    ``seeds`` are the triples' first seeds; ``ratios`` their before/after ratio from the mean
    improvement (None where the triple is not testable).

    Attributes
    ----------
    seeds : tuple of int
        The triples' first seeds.
    ratios : tuple of float or None
        Their before/after ratios (None: not testable).
    testable : int
        Testable triples.
    holds : int
        Those where the claim holds.
    precondition_absent : int
        Triples lacking the precondition.
    """

    seeds: tuple[int, ...]
    ratios: tuple[float | None, ...]
    testable: int
    holds: int
    precondition_absent: int

    @property
    def interval95(self) -> tuple[float, float] | None:
        return wilson_interval(self.holds, self.testable) if self.testable else None

    @property
    def verdict(self) -> str:
        return verdict(self.holds, self.testable)

    @property
    def median(self) -> float | None:
        r = [x for x in self.ratios if x is not None]
        return float(np.median(r)) if r else None

    def as_dict(self) -> dict[str, object]:
        iv = self.interval95
        return {
            "claim": _CLAIM.id,
            "triples": len(self.seeds),
            "first_seeds": list(self.seeds),
            "ratios": list(self.ratios),
            "testable": self.testable,
            "holds": self.holds,
            "precondition_absent": self.precondition_absent,
            "interval95": list(iv) if iv else None,
            "verdict": self.verdict,
            "median": self.median,
            "paper_value": _CLAIM.paper_value,
        }


def _ratio(group: Sequence[UnitResult]) -> float | None:
    """Before/after ratio of the triple's mean improvement; None where a unit cannot test it."""
    pct = []
    for u in group:
        q = u.quantities
        r = q.get("heldout_ratio")
        if r is None or not np.isfinite(r) or not THERMAL_PRECONDITION.present_in(q):
            return None
        pct.append(100.0 * (1.0 - 1.0 / r))
    mean = float(np.mean(pct))
    return 1.0 / (1.0 - mean / 100.0) if mean < 100.0 else None


def judge_triples(units: Sequence[UnitResult]) -> TripleResult:
    """The 65 % claim over consecutive triples of ``units`` (in the order given).

    Parameters
    ----------
    units : sequence of UnitResult
        The units' results, in order.

    Returns
    -------
    TripleResult
        The claim over the triples.
    """
    groups = [units[i : i + 3] for i in range(0, len(units) - len(units) % 3, 3)]
    ratios = tuple(_ratio(g) for g in groups)
    ok = [r for r in ratios if r is not None]
    return TripleResult(
        seeds=tuple(int(g[0].seed) for g in groups),
        ratios=ratios,
        testable=len(ok),
        holds=sum(_CLAIM.comparator.holds(r) for r in ok),
        precondition_absent=len(ratios) - len(ok),
    )
