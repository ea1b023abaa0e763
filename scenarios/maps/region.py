"""The paper-consistent region of a family and every method claim's verdict over it.

**Constraints.** Each device fact a paper reports is a :class:`Constraint`: a key of the units'
``quantities``, a :class:`~gyrobench.scenarios.claims.Comparator` whose band is the fact's
tolerance (stated in data, e.g. 1 - adjusted R^2 within a factor 2 of 0.03) and the fact's
source. A point satisfies a constraint when the **median over its units** of the quantity
(:func:`~gyrobench.scenarios.claims.finite_median`: None, NaN and inf skipped) satisfies the
comparator; a point whose units give no finite value does not satisfy it. The **region** is the
set of points satisfying every constraint. Two constraints **conflict** when each is satisfied
on some point and never both on one point; a constraint satisfied on no point is unsatisfiable
on the family. An empty region is reported as a finding naming the facts (:func:`region_finding`).

**Claims.** At each point each method claim is judged over the point's units by
:func:`~gyrobench.scenarios.claims.evaluate` (its precondition applies; no control population
is run for a map). A point **holds** a claim when more than half of its testable units pass
(strictly: 2 of 3, 2 of 4 does not), **fails** it otherwise, and cannot test it when no unit
could. Over the region the verdict is "holds on k of n region points", n the region points that
could test the claim, with the exact (Clopper-Pearson) 95 % interval of k/n
(:func:`scipy.stats.binomtest`, ``proportion_ci(method="exact")``); where it fails, which way:
the comparator's :meth:`~gyrobench.scenarios.claims.Comparator.miss` of each failing region
point's median quantity, counted ("below", "above" its band, or "false").

**Sensitivity.** (Of each claim's pass rate, and of each constraint's point medians.) A structured
Sobol design (:func:`scipy.stats.sobol_indices`) needs N (d + 2)
evaluations; a map's budget is one unstructured design, so each parameter is ranked by the
absolute Spearman rank correlation (:func:`scipy.stats.spearmanr`) of its value with the
point's pass rate of the claim over all points that could test it (a rank measure: the same for
the value and its logarithm). This is a screening of monotone effects, not a variance
decomposition: a parameter acting non-monotonically, or only through an interaction, ranks low.

**Covariates.** A family may name quantities of the units that are no reported fact but that a
claim needs (paper 003's T x dT share of the drift): each point's median of each
(:class:`Covariate`) is kept, with each claim's Spearman rank correlation against it, so a claim
can be read against the quantity it rests on.

**Nominal device and medoid.** The family's nominal device (the default ``reproduce``'s,
:attr:`~.family.Family.nominal`) runs as one more point with its own seeds: its constraint
medians, whether it lies in the region (every constraint satisfied) and each claim's verdict on
it are reported beside the region's. The region's **medoid** is the region point with the least
sum of Euclidean distances, in the design's unit coordinates (log parameters in their
logarithm), to the other region points (ties: the lowest index): a region device to name when
the nominal lies outside.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.stats import binomtest, spearmanr

from gyrobench.scenarios.claims import Claim, Comparator, evaluate, finite_median

from .family import Design, Family
from .findings import conflicts, nominal_text, region_finding
from .refine import Refinement

__all__ = [
    "MAP_FORMAT",
    "ClaimMap",
    "Constraint",
    "Covariate",
    "MapResult",
    "Nominal",
    "Sensitivity",
    "analyse",
    "conflicts",
    "medoid",
    "nominal_text",
    "region_finding",
]

#: map.json's format marker (the output-safety rule recognises a file whose first key names it)
MAP_FORMAT = "gyrobench-map-1"


@dataclass(frozen=True, slots=True, kw_only=True)
class Constraint:
    """One device fact the paper reports, as a condition on a point's units.

    Attributes
    ----------
    id : str
        Short name (``"004.adj_r2"``).
    fact : str
        The fact and its tolerance in words.
    source : str
        Where the paper reports it.
    quantity : str
        Key of the units' ``quantities``.
    comparator : Comparator
        The fact's band (its tolerance).
    """

    id: str
    fact: str
    source: str
    quantity: str
    comparator: Comparator

    def holds(self, median: float) -> bool:
        """Whether a point whose units' median quantity is ``median`` satisfies the fact (NaN: no)."""
        return math.isfinite(median) and self.comparator.holds(median)


@dataclass(frozen=True, slots=True, kw_only=True)
class Covariate:
    """A quantity of the units a claim rests on, reported per point (no constraint).

    Attributes
    ----------
    quantity : str
        Key of the units' ``quantities``.
    label : str
        Axis label with its unit, e.g. ``"T x dT share of the drift [-]"``.
    definition : str
        What it measures and why the claims need it.
    """

    quantity: str
    label: str
    definition: str


@dataclass(frozen=True, slots=True, kw_only=True)
class Nominal:
    """The nominal device run as one more point of the map.

    Attributes
    ----------
    values : dict
        Its value of each open parameter (field units).
    unit_coordinates : tuple of float
        The same in the design's unit coordinates.
    seeds : tuple of int
        Its units' seeds.
    constraint_medians : tuple of float
        Its median of each constraint's quantity.
    satisfied : tuple of bool
        Each constraint satisfied.
    covariate_medians : tuple of float
        Its median of each covariate.
    holds, testable : tuple of int
        Per claim: its passing and testable units.
    medians : tuple of float
        Per claim: its median quantity over the testable units (NaN: none).
    verdicts : tuple of str
        Per claim: ``"holds"``, ``"fails"`` or ``"not testable"``.
    """

    values: dict[str, float]
    unit_coordinates: tuple[float, ...]
    seeds: tuple[int, ...]
    constraint_medians: tuple[float, ...]
    satisfied: tuple[bool, ...]
    covariate_medians: tuple[float, ...]
    holds: tuple[int, ...]
    testable: tuple[int, ...]
    medians: tuple[float, ...]
    verdicts: tuple[str, ...]

    @property
    def in_region(self) -> bool:
        """Whether the nominal device satisfies every constraint."""
        return all(self.satisfied)


@dataclass(frozen=True, slots=True, kw_only=True)
class Sensitivity:
    """One parameter's Spearman rank correlation with a claim's pass rate (or a fact's medians) over the points.

    Parameters
    ----------
    field : str
        The parameter's Config field.
    rho : float or None
        Spearman's rho (None: fewer than 3 points, or a constant response).
    p_value : float or None
        Its two-sided p-value (:func:`scipy.stats.spearmanr`).
    points : int
        Points the correlation is over.
    """

    field: str
    rho: float | None
    p_value: float | None
    points: int


@dataclass(frozen=True, slots=True, kw_only=True)
class ClaimMap:
    """One claim over the family: each point's result, the region verdict, the sensitivity ranking.

    Attributes
    ----------
    claim : Claim
    holds, testable : tuple of int
        Each point's passing and testable units.
    medians : tuple of float
        Each point's median quantity over its testable units (NaN: none).
    point_verdicts : tuple of str
        Each point's ``"holds"``, ``"fails"`` or ``"not testable"`` (see the module).
    region_k, region_n : int
        Region points holding the claim, region points that could test it.
    interval95 : tuple of float or None
        Clopper-Pearson interval of k/n (None when n = 0).
    misses : dict
        Failing region points by the side their median misses on.
    sensitivity : tuple of Sensitivity
        Every parameter, the largest |rho| first (None rho last, in parameter order).
    family_k, family_n : int
        The same count over every point of the family, region or not (what the claim does where
        the paper's facts do not hold; no verdict about the paper's device).
    """

    claim: Claim
    holds: tuple[int, ...]
    testable: tuple[int, ...]
    medians: tuple[float, ...]
    point_verdicts: tuple[str, ...]
    region_k: int
    region_n: int
    interval95: tuple[float, float] | None
    misses: dict[str, int]
    sensitivity: tuple[Sensitivity, ...]
    family_k: int = 0
    family_n: int = 0

    def pass_rates(self) -> tuple[float, ...]:
        """Each point's holds / testable (NaN where no unit could test the claim)."""
        return tuple(h / t if t else math.nan for h, t in zip(self.holds, self.testable, strict=True))

    def verdict_text(self) -> str:
        """``"holds on k of n region points [lo, hi]"`` (or why there is no verdict)."""
        if self.region_n == 0:
            return "no region point could test it"
        lo, hi = self.interval95 or (math.nan, math.nan)
        text = f"holds on {self.region_k} of {self.region_n} region points [{100 * lo:.0f} %, {100 * hi:.0f} %]"
        if self.region_k < self.region_n:
            text += "; misses " + ", ".join(f"{k} {v}" for k, v in sorted(self.misses.items()) if v)
        return text


@dataclass(frozen=True, slots=True, kw_only=True)
class MapResult:
    """A map: the design, each point's constraint medians and membership, each claim over the family.

    Attributes
    ----------
    family : Family
    design : Design
    seeds : tuple of tuple of int
        Each point's unit seeds.
    constraints : tuple of Constraint
    constraint_medians : tuple of tuple of float
        ``[i][c]``: point i's median of constraint c's quantity.
    satisfied : tuple of tuple of bool
        ``[i][c]``: point i satisfies constraint c.
    claims : tuple of ClaimMap
    covariates : tuple of Covariate
        Quantities reported per point beside the claims.
    covariate_medians : tuple of tuple of float
        ``[i][v]``: point i's median of covariate v.
    nominal : Nominal or None
        The nominal device run as one more point (None: not run).
    refinement : Refinement or None
        The second stage's plan (:mod:`.refine`; None: not considered).
    """

    family: Family
    design: Design
    seeds: tuple[tuple[int, ...], ...]
    constraints: tuple[Constraint, ...]
    constraint_medians: tuple[tuple[float, ...], ...]
    satisfied: tuple[tuple[bool, ...], ...]
    claims: tuple[ClaimMap, ...]
    covariates: tuple[Covariate, ...] = ()
    covariate_medians: tuple[tuple[float, ...], ...] = ()
    nominal: Nominal | None = None
    refinement: Refinement | None = None

    @property
    def region(self) -> tuple[int, ...]:
        """Indices of the points satisfying every constraint."""
        return tuple(i for i, row in enumerate(self.satisfied) if all(row))

    @property
    def medoid(self) -> int | None:
        """The region's medoid (:func:`medoid`), None when the region is empty."""
        return medoid(self.design.unit, self.region)

    def covariate_sensitivity(self, claim: int, covariate: int) -> tuple[float | None, float | None, int]:
        """Spearman's rho (and p-value) of claim ``claim``'s pass rate with covariate ``covariate``'s
        point medians, over the points where both are finite; (None, None, n) when either is constant
        or fewer than 3 points remain."""
        rates = self.claims[claim].pass_rates()
        cov = [row[covariate] for row in self.covariate_medians]
        ok = [i for i in range(len(rates)) if math.isfinite(rates[i]) and math.isfinite(cov[i])]
        if len(ok) < 3:
            return None, None, len(ok)
        x = np.asarray([cov[i] for i in ok])
        y = np.asarray([rates[i] for i in ok])
        if np.ptp(x) == 0 or np.ptp(y) == 0:
            return None, None, len(ok)
        res = spearmanr(x, y)
        return float(res.statistic), float(res.pvalue), len(ok)

    def constraint_sensitivity(self, j: int) -> tuple[Sensitivity, ...]:
        """Every parameter's Spearman rank correlation with constraint ``j``'s point medians (finite ones)."""
        return _sensitivity(self.family, self.design, [row[j] for row in self.constraint_medians])

    def counts(self, stage: int | None = None) -> dict[str, int]:
        """Per constraint: the points satisfying it (of one ``stage`` only, when given)."""
        rows = [r for i, r in enumerate(self.satisfied) if stage is None or self.design.stage_of(i) == stage]
        return {c.id: sum(row[j] for row in rows) for j, c in enumerate(self.constraints)}

    def stages(self) -> dict[str, dict[str, Any]]:
        """Per stage (``"1"``, and ``"2"`` when refined): its points, its region points, its constraint counts."""
        out = {}
        for st in sorted({self.design.stage_of(i) for i in range(len(self.design))}):
            pts = [i for i in range(len(self.design)) if self.design.stage_of(i) == st]
            out[str(st)] = {"points": len(pts), "region": sum(all(self.satisfied[i]) for i in pts),
                            "constraint_counts": self.counts(st)}
        return out

    def as_dict(self) -> dict[str, Any]:
        """map.json: ``format`` first (the output-safety marker), then everything a referee recounts from."""
        region = set(self.region)
        points = []
        for i, values in enumerate(self.design.values):
            points.append({
                "index": i,
                "stage": self.design.stage_of(i),
                "parameters": values,
                "unit_coordinates": [float(x) for x in self.design.unit[i]],
                "seeds": list(self.seeds[i]),
                "constraint_medians": {c.id: _num(self.constraint_medians[i][j])
                                       for j, c in enumerate(self.constraints)},
                "constraints_satisfied": {c.id: self.satisfied[i][j] for j, c in enumerate(self.constraints)},
                "in_region": i in region,
                "covariate_medians": {v.quantity: _num(self.covariate_medians[i][j])
                                      for j, v in enumerate(self.covariates)},
                "claims": {m.claim.id: {"holds": m.holds[i], "testable": m.testable[i],
                                        "pass_rate": _num(m.pass_rates()[i]), "median": _num(m.medians[i]),
                                        "verdict": m.point_verdicts[i]} for m in self.claims},
            })
        return {
            "format": MAP_FORMAT,
            "family": self.family.as_dict(),
            "design": {"method": self.design.method, "seed": self.design.seed, "points": len(self.design),
                       "units_per_point": len(self.seeds[0]) if self.seeds else 0},
            "rules": {
                "constraint": "a point satisfies a constraint when the median over its units of the quantity "
                              "(finite values only) satisfies the comparator",
                "region": "the points satisfying every constraint",
                "point_verdict": "holds when more than half of the point's testable units pass",
                "interval": "Clopper-Pearson exact 95 % (scipy.stats.binomtest)",
                "sensitivity": "|Spearman rho| of the parameter with the point's pass rate (scipy.stats.spearmanr), "
                               "over the points that could test the claim; a screening of monotone effects",
            },
            "constraints": [{"id": c.id, "fact": c.fact, "source": c.source, "quantity": c.quantity,
                             "comparator": c.comparator.text(), "kind": c.comparator.kind,
                             "lo": _num(c.comparator.lo), "hi": _num(c.comparator.hi),
                             "sensitivity": [{"field": s.field, "rho": s.rho, "p_value": s.p_value, "points": s.points}
                                             for s in self.constraint_sensitivity(j)]}
                            for j, c in enumerate(self.constraints)],
            "constraint_counts": self.counts(),
            "refinement": None if self.refinement is None else self.refinement.as_dict(),
            "stages": self.stages(),
            "conflicts": [list(p) for p in conflicts(self)],
            "region": list(self.region),
            "finding": region_finding(self),
            "medoid": None if self.medoid is None else {"index": self.medoid,
                                                        "parameters": self.design.values[self.medoid]},
            "nominal": self._nominal_dict(),
            "nominal_text": nominal_text(self),
            "covariates": [{"quantity": v.quantity, "label": v.label, "definition": v.definition,
                            "claims": {m.claim.id: dict(zip(("rho", "p_value", "points"),
                                                            self.covariate_sensitivity(k, j), strict=True))
                                       for k, m in enumerate(self.claims)}}
                           for j, v in enumerate(self.covariates)],
            "claims": [{
                "id": m.claim.id, "statement": m.claim.statement, "quantity": m.claim.quantity,
                "comparator": m.claim.comparator.text(m.claim.unit), "paper_value": m.claim.paper_value,
                "region_holds": m.region_k, "region_testable": m.region_n,
                "interval95": None if m.interval95 is None else list(m.interval95),
                "misses": m.misses, "verdict": m.verdict_text(),
                "family_holds": m.family_k, "family_testable": m.family_n,
                "nominal": None if self.nominal is None else {
                    "holds": self.nominal.holds[k], "testable": self.nominal.testable[k],
                    "median": _num(self.nominal.medians[k]), "verdict": self.nominal.verdicts[k]},
                "sensitivity": [{"field": s.field, "rho": s.rho, "p_value": s.p_value, "points": s.points}
                                for s in m.sensitivity],
            } for k, m in enumerate(self.claims)],
            "points": points,
        }

    def _nominal_dict(self) -> dict[str, Any] | None:
        """map.json's ``nominal``: the nominal device's point, in the region or not, and the medoid's
        distance from it (unit coordinates)."""
        n = self.nominal
        if n is None:
            return None
        med = self.medoid
        dist = None if med is None else float(np.linalg.norm(self.design.unit[med] - np.asarray(n.unit_coordinates)))
        return {
            "parameters": n.values, "unit_coordinates": list(n.unit_coordinates), "seeds": list(n.seeds),
            "constraint_medians": {c.id: _num(n.constraint_medians[j]) for j, c in enumerate(self.constraints)},
            "constraints_satisfied": {c.id: n.satisfied[j] for j, c in enumerate(self.constraints)},
            "covariate_medians": {v.quantity: _num(n.covariate_medians[j]) for j, v in enumerate(self.covariates)},
            "in_region": n.in_region, "distance_to_medoid": dist,
        }


def _num(x: float) -> float | None:
    """A number for JSON: NaN and inf become None (strict JSON has neither)."""
    return float(x) if x is not None and math.isfinite(x) else None


def point_verdict(holds: int, testable: int) -> str:
    """``"holds"`` when more than half of the testable units pass, ``"fails"`` otherwise, or ``"not testable"``."""
    if testable == 0:
        return "not testable"
    return "holds" if 2 * holds > testable else "fails"


def clopper_pearson(k: int, n: int) -> tuple[float, float]:
    """The exact 95 % interval of k/n (:func:`scipy.stats.binomtest`)."""
    ci = binomtest(k, n).proportion_ci(confidence_level=0.95, method="exact")
    return float(ci.low), float(ci.high)


def _sensitivity(family: Family, design: Design, rates: Sequence[float]) -> tuple[Sensitivity, ...]:
    ok = [i for i, r in enumerate(rates) if math.isfinite(r)]
    out = []
    for j, p in enumerate(family.parameters):
        rho = pv = None
        if len(ok) >= 3:
            x = design.unit[ok, j]
            y = np.asarray([rates[i] for i in ok])
            if np.ptp(y) > 0:
                res = spearmanr(x, y)
                rho, pv = float(res.statistic), float(res.pvalue)
        out.append(Sensitivity(field=p.field, rho=rho, p_value=pv, points=len(ok)))
    return tuple(sorted(out, key=lambda s: -abs(s.rho) if s.rho is not None else math.inf))


def _claim_map(claim: Claim, units: Sequence[Sequence[Mapping[str, Any]]], region: Sequence[int],
               family: Family, design: Design) -> ClaimMap:
    results = [evaluate([claim], list(u))[0] for u in units]
    holds = tuple(r.holds for r in results)
    testable = tuple(r.testable for r in results)
    medians = tuple(math.nan if r.median is None else float(r.median) for r in results)
    verdicts = tuple(point_verdict(h, t) for h, t in zip(holds, testable, strict=True))
    tested = [i for i in region if verdicts[i] != "not testable"]
    k = sum(verdicts[i] == "holds" for i in tested)
    misses: dict[str, int] = {}
    for i in tested:
        if verdicts[i] == "fails":
            side = claim.comparator.miss(medians[i]) if math.isfinite(medians[i]) else None
            side = side or "within band (median passes, most units miss)"
            misses[side] = misses.get(side, 0) + 1
    rates = [h / t if t else math.nan for h, t in zip(holds, testable, strict=True)]
    return ClaimMap(
        claim=claim, holds=holds, testable=testable, medians=medians, point_verdicts=verdicts,
        region_k=k, region_n=len(tested), interval95=clopper_pearson(k, len(tested)) if tested else None,
        misses=misses, sensitivity=_sensitivity(family, design, rates),
        family_k=sum(v == "holds" for v in verdicts), family_n=sum(v != "not testable" for v in verdicts),
    )


def analyse(
    family: Family,
    design: Design,
    seeds: Sequence[Sequence[int]],
    units: Sequence[Sequence[Mapping[str, Any]]],
    constraints: Sequence[Constraint],
    claims: Sequence[Claim],
    *,
    covariates: Sequence[Covariate] = (),
    nominal_seeds: Sequence[int] = (),
    nominal_units: Sequence[Mapping[str, Any]] | None = None,
    refinement: Refinement | None = None,
) -> MapResult:
    """The map of claims over a design's points and the region of the constraints (rules: the module).

    Parameters
    ----------
    family : Family
        The family the design covers.
    design : Design
        The points.
    seeds : sequence of sequence of int
        Each point's unit seeds.
    units : sequence of sequence of mapping
        Each point's units' ``quantities``.
    constraints : sequence of Constraint
        The paper's device facts (at least one).
    claims : sequence of Claim
        The claims to map.
    covariates : sequence of Covariate
        Quantities reported per point beside the claims.
    nominal_seeds : sequence of int
        The nominal device's unit seeds.
    nominal_units : sequence of mapping, optional
        The nominal device's units' ``quantities`` (None: not run; the family has no nominal point).
    refinement : Refinement, optional
        The second stage's plan, when the design holds one (:mod:`.refine`).

    Returns
    -------
    MapResult
        The region, the counts and each claim over the family.
    """
    if len(units) != len(design):
        raise ValueError(f"a map needs one list of units per point; got {len(units)} for {len(design)} points")
    if not constraints:
        raise ValueError("a map needs at least one constraint (a device fact the paper reports)")
    med = tuple(_medians(constraints, pts) for pts in units)
    sat = tuple(tuple(c.holds(m) for c, m in zip(constraints, row, strict=True)) for row in med)
    region = [i for i, row in enumerate(sat) if all(row)]
    nominal = None
    if nominal_units is not None:
        if family.nominal is None:
            raise ValueError(f"family of paper {family.paper}: its base configuration is no point of the family")
        nominal = _nominal(family, constraints, claims, covariates, nominal_seeds, nominal_units)
    return MapResult(
        family=family, design=design, seeds=tuple(tuple(s) for s in seeds), constraints=tuple(constraints),
        constraint_medians=med, satisfied=sat,
        claims=tuple(_claim_map(c, units, region, family, design) for c in claims),
        covariates=tuple(covariates), covariate_medians=tuple(_medians(covariates, pts) for pts in units),
        nominal=nominal, refinement=refinement,
    )


def _medians(keyed: Sequence[Constraint] | Sequence[Covariate],
             units: Sequence[Mapping[str, Any]]) -> tuple[float, ...]:
    """Each constraint's (or covariate's) finite median over one point's units (NaN: none finite)."""
    return tuple(finite_median(u.get(c.quantity) for u in units) for c in keyed)


def _nominal(family: Family, constraints: Sequence[Constraint], claims: Sequence[Claim],
             covariates: Sequence[Covariate], seeds: Sequence[int], units: Sequence[Mapping[str, Any]]) -> Nominal:
    """The nominal device's constraints, covariates and claim verdicts over its units."""
    values = family.nominal or {}
    med = _medians(constraints, units)
    results = [evaluate([c], list(units))[0] for c in claims]
    holds = tuple(r.holds for r in results)
    testable = tuple(r.testable for r in results)
    return Nominal(
        values=values, unit_coordinates=tuple(p.coordinate(values[p.field]) for p in family.parameters),
        seeds=tuple(int(s) for s in seeds), constraint_medians=med,
        satisfied=tuple(c.holds(m) for c, m in zip(constraints, med, strict=True)),
        covariate_medians=_medians(covariates, units), holds=holds, testable=testable,
        medians=tuple(math.nan if r.median is None else float(r.median) for r in results),
        verdicts=tuple(point_verdict(h, t) for h, t in zip(holds, testable, strict=True)),
    )


def medoid(unit: np.ndarray, members: Sequence[int]) -> int | None:
    """The member point with the least sum of Euclidean distances to the other members.

    Parameters
    ----------
    unit : ndarray, shape (N, d)
        Every design point's unit coordinates.
    members : sequence of int
        The indices to choose among (the region).

    Returns
    -------
    int or None
        The medoid's index (the lowest on a tie); None when ``members`` is empty.
    """
    idx = list(members)
    if not idx:
        return None
    x = np.asarray(unit, float)[idx]
    total = np.sqrt(((x[:, None, :] - x[None, :, :]) ** 2).sum(axis=-1)).sum(axis=1)
    return idx[int(np.argmin(total))]
