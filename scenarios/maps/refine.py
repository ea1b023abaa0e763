"""A map's second stage: more points where the region is small, around its points or its closest misses.

The first stage is the space-filling design (:func:`~.family.design`, N points). When its region
holds fewer than :func:`refine_threshold` points (``max(2, N // 8)``: under an eighth of the
design, and at least 2), a second batch is placed, deterministically, from the first stage's
results alone:

* **Seeds.** The region's points when it is not empty; otherwise the :data:`CLOSEST_MISSES`
  points that satisfy the most constraints, ranked by :func:`miss_key`: most constraints
  satisfied, then fewest constraints with no finite median, then the least summed distance to the
  missed facts' bands (:func:`band_distance`), then the lowest index.
* **Boxes.** Around each seed a cube of side :data:`BOX_SIDE` in the design's unit coordinates
  (log parameters in their logarithm), centred on the seed and shifted to lie inside [0, 1]^d:
  the design's cube shrunk 4 times on every axis.
* **Points.** Each box gets ``2**m`` scrambled Sobol points (Owen scrambling, the first
  ``2**m`` of base 2, ``m = floor(log2(N / seeds))``; :class:`scipy.stats.qmc.Sobol` seeded with
  ``(design seed, 2, seed's rank)``), so the second stage has about N points. A unit coordinate
  maps to a value as in the first stage (rounded to a parameter's grid step).

The second stage's points take the point indices after the first stage's (``N, N + 1, ...``), so
their unit seeds (:func:`~.run.unit_seed`) and the unit store's run ids depend on the first
stage's results only: a refined map is resumable and gives the same bits on any executor. The
second stage is skipped (with the reason) when its indices would reach
:data:`~.run.NOMINAL_POINT`. Its points are not space-filling over the family: counts over the
whole family mix the two stages, so the region is also counted per stage.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.stats import qmc

from gyrobench.scenarios.claims import Comparator

from .family import MAX_POINTS, Design, Family

__all__ = ["BOX_SIDE", "CLOSEST_MISSES", "REFINE_DIVISOR", "Refinement", "band_distance", "joined", "miss_key",
           "plan_refinement", "refine_threshold"]

#: the side of each second-stage box in unit coordinates (the family's cube shrunk 4 times)
BOX_SIDE = 0.25
#: how many closest misses seed the second stage when the first stage's region is empty
CLOSEST_MISSES = 4
#: the first-stage region size below which the second stage runs is max(2, N // REFINE_DIVISOR)
REFINE_DIVISOR = 8


def refine_threshold(n: int) -> int:
    """The region size under which a first stage of ``n`` points is refined: ``max(2, n // 8)``.

    Parameters
    ----------
    n : int
        The first stage's points.

    Returns
    -------
    int
        A region of fewer points than this is refined.
    """
    return max(2, n // REFINE_DIVISOR)


def band_distance(comparator: Comparator, median: float) -> float:
    """How far a point's median lies from a fact's band, in the band's own scale (0 inside it).

    ``in_range``: the gap over the band's width; ``within_factor``: the gap in the logarithm over
    the band's log-width (inf for a median <= 0); ``above`` / ``below``: the gap over the bound's
    magnitude (1 when the bound is 0); ``is_true``: 1 - median (the median of 0/1 outcomes). A
    median that is not finite is infinitely far.

    Parameters
    ----------
    comparator : Comparator
        The fact's band.
    median : float
        The point's median of the fact's quantity.

    Returns
    -------
    float
        The distance (>= 0; inf when the median is not finite).
    """
    v = float(median)
    if not math.isfinite(v):
        return math.inf
    if comparator.holds(v):
        return 0.0
    lo, hi, kind = comparator.lo, comparator.hi, comparator.kind
    if kind == "is_true":
        return max(1.0 - v, 0.0)
    if kind == "within_factor":
        if v <= 0:
            return math.inf
        return max(math.log(lo / v), math.log(v / hi), 0.0) / math.log(hi / lo)
    if kind == "in_range":
        return max(lo - v, v - hi, 0.0) / (hi - lo)
    bound = lo if kind == "above" else hi
    gap = (lo - v) if kind == "above" else (v - hi)
    return max(gap, 0.0) / (abs(bound) or 1.0)


def miss_key(comparators: Sequence[Comparator], medians: Sequence[float],
             satisfied: Sequence[bool], index: int) -> tuple[int, int, float, int]:
    """The closest-miss ranking key of one point (smaller ranks first; the module).

    Parameters
    ----------
    comparators : sequence of Comparator
        Each constraint's band.
    medians : sequence of float
        The point's median of each constraint's quantity.
    satisfied : sequence of bool
        Each constraint satisfied.
    index : int
        The point's index (the last tie-break).

    Returns
    -------
    tuple
        (-constraints satisfied, constraints with no finite median, summed finite distance of the
        missed ones, index).
    """
    d = [band_distance(c, m) for c, m, ok in zip(comparators, medians, satisfied, strict=True) if not ok]
    return (-sum(bool(s) for s in satisfied), sum(not math.isfinite(x) for x in d),
            float(sum(x for x in d if math.isfinite(x))), int(index))


@dataclass(frozen=True, slots=True, kw_only=True)
class Refinement:
    """The second stage's plan: why it runs (or not), its seeds, boxes and points.

    Attributes
    ----------
    first_points : int
        The first stage's points.
    first_region : int
        Its region's size.
    threshold : int
        :func:`refine_threshold` of ``first_points``.
    triggered : bool
        The second stage runs.
    reason : str
        Why it runs, or why not, in one sentence.
    basis : str
        ``"region"``, ``"closest misses"`` or ``""`` (not triggered).
    seeds : tuple of int
        The first-stage points the boxes are centred on.
    box_lows : tuple of tuple of float
        Each box's lower corner in unit coordinates (side :data:`BOX_SIDE`).
    design : Design or None
        The second stage's points (None: not triggered).
    """

    first_points: int
    first_region: int
    threshold: int
    triggered: bool
    reason: str
    basis: str = ""
    seeds: tuple[int, ...] = ()
    box_lows: tuple[tuple[float, ...], ...] = ()
    design: Design | None = None

    def as_dict(self) -> dict[str, object]:
        """map.json's ``refinement`` (the rule's constants, the seeds and boxes; the points are in ``points``)."""
        return {
            "rule": (f"refine when the first stage's region holds fewer than max(2, N // {REFINE_DIVISOR}) points: "
                     f"{BOX_SIDE:g}-side boxes (unit coordinates) around the region's points, or, when it is "
                     f"empty, around the {CLOSEST_MISSES} closest misses (most constraints satisfied, then fewest "
                     "facts without a finite median, then the least summed band distance); 2**floor(log2(N / "
                     "seeds)) scrambled Sobol points a box"),
            "first_points": self.first_points, "first_region": self.first_region, "threshold": self.threshold,
            "triggered": self.triggered, "reason": self.reason, "basis": self.basis, "seeds": list(self.seeds),
            "box_side": BOX_SIDE, "box_lows": [list(b) for b in self.box_lows],
            "points": 0 if self.design is None else len(self.design),
        }


def plan_refinement(family: Family, first: Design, comparators: Sequence[Comparator],
                    medians: Sequence[Sequence[float]], satisfied: Sequence[Sequence[bool]]) -> Refinement:
    """The second stage a first stage's results call for (rules: the module).

    Parameters
    ----------
    family : Family
        The family.
    first : Design
        The first stage's points.
    comparators : sequence of Comparator
        The constraints' bands, in constraint order.
    medians : sequence of sequence of float
        ``[i][c]``: first-stage point i's median of constraint c's quantity.
    satisfied : sequence of sequence of bool
        ``[i][c]``: point i satisfies constraint c.

    Returns
    -------
    Refinement
        The plan (``design`` None when the second stage does not run).
    """
    n = len(first)
    region = [i for i, row in enumerate(satisfied) if all(row)]
    threshold = refine_threshold(n)
    if len(region) >= threshold:
        return Refinement(triggered=False, reason=f"the region holds {len(region)} of {n} points, not fewer than "
                          f"{threshold}: no second stage", first_points=n, first_region=len(region),
                          threshold=threshold)
    if region:
        seeds, basis = region, "region"
    else:
        ranked = sorted(range(n), key=lambda i: miss_key(comparators, medians[i], satisfied[i], i))
        seeds, basis = ranked[:min(CLOSEST_MISSES, n)], "closest misses"
    m = int(math.floor(math.log2(max(n // len(seeds), 1))))
    total = len(seeds) * 2 ** m
    if n + total > MAX_POINTS:
        return Refinement(triggered=False, reason=f"a second stage of {total} points would take point indices past "
                          f"{MAX_POINTS - 1} (the nominal device's): not run", basis=basis, seeds=tuple(seeds),
                          first_points=n, first_region=len(region), threshold=threshold)
    d = len(family.parameters)
    lows, rows = [], []
    for rank, s in enumerate(seeds):
        low = np.clip(first.unit[s] - BOX_SIDE / 2.0, 0.0, 1.0 - BOX_SIDE)
        u = qmc.Sobol(d, scramble=True, rng=np.random.default_rng((first.seed, 2, rank))).random_base2(m)
        lows.append(tuple(float(x) for x in low))
        rows.append(low + BOX_SIDE * u)
    unit = np.vstack(rows)
    values = tuple({p.field: p.value(float(x)) for p, x in zip(family.parameters, row, strict=True)} for row in unit)
    second = Design(method="sobol boxes", seed=first.seed, unit=unit, values=values)
    what = f"its {len(region)} point(s)" if region else f"the {len(seeds)} closest misses"
    reason = (f"the region holds {len(region)} of {n} points, fewer than {threshold}: {total} more points in "
              f"{BOX_SIDE:g}-side boxes around {what} ({', '.join(map(str, seeds))})")
    return Refinement(triggered=True, reason=reason, basis=basis, seeds=tuple(seeds), box_lows=tuple(lows),
                      design=second, first_points=n, first_region=len(region), threshold=threshold)


def joined(first: Design, second: Design | None) -> Design:
    """Both stages as one design (the first stage's points first), its ``stage`` per point.

    Parameters
    ----------
    first : Design
        The first stage.
    second : Design or None
        The second stage (None: the first alone).

    Returns
    -------
    Design
        The points of both, ``method`` and ``seed`` the first stage's.
    """
    if second is None:
        return first
    return Design(method=first.method, seed=first.seed, unit=np.vstack([first.unit, second.unit]),
                  values=first.values + second.values, stage=(1,) * len(first) + (2,) * len(second))
