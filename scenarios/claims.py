"""A paper's claims as data, judged over a population of simulated units.

A paper scenario states every checkable claim of its paper once, as a :class:`Claim`:
the paper's sentence, where it stands, whether an input of the simulation was set
from it (``calibrated``) or nothing was set to make it hold (``emergent``), the
paper's value, and one :class:`Comparator` with its tolerance. The scenario's
``experiment(config, seed)`` simulates one unit (each seed is another unit, with its
own noise and its own drawn parameters) and returns the unit's ``quantities``: one
number per claim (``None`` or NaN where that unit cannot test it). :func:`evaluate`
then judges each claim over the units: how many could test it, on how many it holds,
the pass rate with its 95 % Wilson interval, and the median and spread of the
reproduced quantity.

Comparators (written once per claim, chosen from the paper's wording)
---------------------------------------------------------------------
``within_factor(paper_value, 2)``
    the paper gives a number: holds when ``paper/2 <= q <= 2 paper`` (two-sided).
``in_range(lo, hi)``
    the paper gives a band, e.g. "about an order of magnitude" = ``in_range(3, 30)``
    on the ratio.
``above(x)`` / ``below(x)``
    the paper's statement is one-sided ("higher", "lower", "more than 0.2 deg/h").
``is_true()``
    a yes/no statement per unit ("improved beats traditional in every run"); the
    quantity is 1.0 (holds) or 0.0 (fails).

Verdicts
--------
"holds for most units" only when the Wilson interval's lower end is above 50 %;
"fails for most units" when its upper end is below 50 %; otherwise "undecided". A verdict
whose interval ends within :data:`PROVISIONAL_MARGIN` (5 percentage points) of 50 % is
**provisional**: a unit or two more could flip it. A calibrated claim is reported with its
verdict but never counted as reproduced.

Roles, preconditions and the control
------------------------------------
Every claim has a ``role``:

``device``
    what the paper reports about its device under test (raw nonlinearity, drift level, the
    vibration-phase rise): what the simulation's device is matched to, shown as "device
    matched" or not, never counted as reproduced;
``method``
    what the paper's method achieves on that device: the paper's contribution, the claims
    that count;
``extension``
    ours (dense sweeps, scoring against the truth): tallied apart.

A method (or extension) claim may state a :class:`Precondition`, as data: the per-unit
condition under which it can be judged ("the vibration bias exceeds 3 sigma of the
scatter"). A unit without it counts as ``precondition_absent``, not as a fail; a claim whose
precondition is absent on most units is "not reproducible on this device".

A paper scenario also runs a **control population**: the same seeds with the paper's effect
switched off. Each claim is judged on the control too (without its precondition: the point
is what the analysis gives when there is nothing to find). The rule is two-sided: a method or
extension claim whose pass rates on the units and on the control are not distinguishable by
Fisher's exact test (two-sided, at :data:`CONTROL_ALPHA`) is **no different from the
control** (when it holds or is undecided on the units); one that passes significantly *less*
often on the units than on the control is **below the control**, whatever its verdict; only a
claim that holds on the units *and* passes there significantly more often than on the control
counts as reproduced, and a claim failing on the units and on the control stays contradicted.
:attr:`ClaimResult.status` gives the final word.

The records (:class:`Claim`, :class:`Comparator` and its factories, :class:`Precondition`,
:class:`Deviation`) live in :mod:`gyrobench.scenarios.claim_records`, the statistics (Wilson
interval, verdict, Fisher test, group-sequential ``z``) in :mod:`gyrobench.scenarios.claim_stats`;
both are re-exported here, so ``gyrobench.scenarios.claims`` stays the one import.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from gyrobench.scenarios.claim_records import (
    ROLES,
    Claim,
    Comparator,
    Deviation,
    Precondition,
    Role,  # noqa: F401  (the papers type their claims with it, imported from here)
    _finite,
    above,
    below,
    in_range,
    is_true,
    within_factor,
)
from gyrobench.scenarios.claim_stats import (
    _Z95,
    _percentile,
    control_test,
    finite_median,
    sequential_error,
    sequential_z,
    verdict,
    wilson_interval,
)
from gyrobench.scenarios.claim_tally import ClaimTally, DeviationEffect, deviation_effect, tally

__all__ = [
    "CONTROL_ALPHA",
    "PROVISIONAL_MARGIN",
    "ROLES",
    "STATUSES",
    "Claim",
    "ClaimResult",
    "Comparator",
    "ClaimTally",
    "ControlResult",
    "Deviation",
    "DeviationEffect",
    "Precondition",
    "deviation_effect",
    "above",
    "control_test",
    "below",
    "evaluate",
    "finite_median",
    "tally",
    "in_range",
    "is_true",
    "sequential_error",
    "sequential_z",
    "verdict",
    "wilson_interval",
    "within_factor",
]

#: a verdict whose 95 % interval ends within this of 50 % is provisional
PROVISIONAL_MARGIN = 0.05

#: false-alarm rate of the two-sided Fisher exact test of "the units pass as often as the control"
CONTROL_ALPHA = 0.05

#: the final word on a judged claim (:attr:`ClaimResult.status`)
STATUSES = (
    "device matched",
    "device not matched",
    "reproduced",
    "contradicted",
    "no different from the control",
    "below the control",
    "not reproducible on this device",
    "undecided",
    "not testable",
)



@dataclass(frozen=True, slots=True, kw_only=True)
class ControlResult:
    """A claim judged on the control units (the paper's effect switched off; no precondition).

    Parameters
    ----------
    units : int
        Control units run.
    testable : int
        Those that could test the claim.
    holds : int
        Those where it holds.
    """

    units: int
    testable: int
    holds: int

    @property
    def pass_rate(self) -> float | None:
        return self.holds / self.testable if self.testable else None

    @property
    def interval95(self) -> tuple[float, float] | None:
        return wilson_interval(self.holds, self.testable) if self.testable else None

    def as_dict(self) -> dict[str, Any]:
        return {
            "units": self.units,
            "testable": self.testable,
            "holds": self.holds,
            "pass_rate": self.pass_rate,
            "interval95": list(self.interval95) if self.interval95 else None,
        }


@dataclass(frozen=True, slots=True, kw_only=True)
class ClaimResult:
    """A claim judged over units (the results.json ``claims`` entry, see :meth:`as_dict`).

    ``precondition_absent`` units lacked the claim's precondition (they are not in
    ``testable``); ``misses_below`` / ``misses_above`` count the testable units whose quantity
    fell below / above the comparator's band; ``control`` is the claim on the control units.

    Parameters
    ----------
    claim : Claim
        The claim judged.
    units : int
        Units run.
    testable : int
        Units that could test it (quantity present, precondition met).
    holds : int
        Testable units where it holds.
    median : float or None
        Median of the testable units' quantity (None: none testable).
    spread : tuple of float or None
        Interquartile range (25th, 75th percentile) of that quantity.
    precondition_absent : int
        Units that lacked the claim's precondition.
    misses_below, misses_above : int
        Testable units whose quantity fell below / above the comparator's band.
    control : ControlResult or None
        The claim on the control units (None: no control run).
    z : float
        z of the Wilson interval the verdict uses.
    """

    claim: Claim
    units: int
    testable: int
    holds: int
    median: float | None
    spread: tuple[float, float] | None
    precondition_absent: int = 0
    misses_below: int = 0
    misses_above: int = 0
    control: ControlResult | None = None
    z: float = _Z95

    @property
    def pass_rate(self) -> float | None:
        """``holds / testable``; None when no unit could test the claim."""
        return self.holds / self.testable if self.testable else None

    @property
    def interval95(self) -> tuple[float, float] | None:
        """Wilson score interval of the pass rate: 95 % at a fixed unit count; with ``--units auto``
        the group-sequential one (``z`` from :func:`sequential_z`)."""
        return wilson_interval(self.holds, self.testable, self.z) if self.testable else None

    @property
    def verdict(self) -> str:
        """``"holds for most units"``, ``"fails for most units"``, ``"undecided"``, ``"not testable"``."""
        return verdict(self.holds, self.testable, self.z)

    @property
    def provisional(self) -> bool:
        """A holds/fails verdict whose interval ends within :data:`PROVISIONAL_MARGIN` of 50 %."""
        iv = self.interval95
        if iv is None:
            return False
        v = self.verdict
        return (v == "holds for most units" and iv[0] < 0.5 + PROVISIONAL_MARGIN) or (
            v == "fails for most units" and iv[1] > 0.5 - PROVISIONAL_MARGIN
        )

    @property
    def control_p_value(self) -> float | None:
        """Two-sided Fisher exact p-value of the units' and the control's pass counts (:func:`control_test`);
        None without a control or a unit or control unit that could test the claim."""
        if self.control is None or not self.control.testable or not self.testable:
            return None
        return control_test(self.holds, self.testable, self.control.holds, self.control.testable)

    @property
    def identity(self) -> bool:
        """The units' pass rate is not significantly above the control's (Fisher's exact test,
        two-sided, at :data:`CONTROL_ALPHA`): no different from it, or below it. A claim that
        fails on the units is flagged only when it is significantly below the control (a
        contradiction on the units stands when the control fails it too). False without a
        control that could test the claim."""
        p = self.control_p_value
        if p is None:
            return False
        if self.verdict == "fails for most units":  # a contradiction stands unless the control holds more
            return p < CONTROL_ALPHA and not self._above_control()
        return p >= CONTROL_ALPHA or not self._above_control()

    def _above_control(self) -> bool:
        c = self.control
        return c is not None and self.holds * c.testable > c.holds * self.testable

    @property
    def precondition_mostly_absent(self) -> bool:
        """The claim's precondition is absent on more than half the units."""
        return self.claim.precondition is not None and 2 * self.precondition_absent > self.units

    @property
    def status(self) -> str:
        """The final word (one of :data:`STATUSES`), by role; see the module docstring."""
        v = self.verdict
        if self.claim.role == "device":
            return {"holds for most units": "device matched", "fails for most units": "device not matched"}.get(v, v)
        if self.precondition_mostly_absent:
            return "not reproducible on this device"
        if self.identity:
            p = self.control_p_value
            below = p is not None and p < CONTROL_ALPHA and not self._above_control()
            return "below the control" if below else "no different from the control"
        return {"holds for most units": "reproduced", "fails for most units": "contradicted"}.get(v, v)

    @property
    def miss_direction(self) -> str | None:
        """``"below"`` / ``"above"`` the band where most misses fall, ``"both"``; None without misses."""
        if not (self.misses_below or self.misses_above):
            return None
        if self.misses_below and self.misses_above:
            return "below" if self.misses_below > 2 * self.misses_above else (
                "above" if self.misses_above > 2 * self.misses_below else "both")
        return "below" if self.misses_below else "above"

    def as_dict(self) -> dict[str, Any]:
        c = self.claim
        pre = c.precondition
        return {
            "id": c.id,
            "paper": c.paper,
            "where": c.where,
            "statement": c.statement,
            "kind": c.kind,
            "calibrated_input": c.calibrated_input,
            "paper_value": c.paper_value,
            "unit": c.unit,
            "comparator": c.comparator.text(c.unit),
            "criterion": c.comparator.as_dict(),
            "quantity": c.quantity,
            "units": self.units,
            "testable": self.testable,
            "holds": self.holds,
            "pass_rate": self.pass_rate,
            "interval95": list(self.interval95) if self.interval95 else None,
            "interval_z": self.z,
            "median": self.median,
            "spread": list(self.spread) if self.spread else None,
            "verdict": self.verdict,
            "role": c.role,
            "status": self.status,
            "provisional": self.provisional,
            "precondition": None if pre is None else pre.as_dict(),
            "precondition_absent": self.precondition_absent,
            "misses": {"below": self.misses_below, "above": self.misses_above, "direction": self.miss_direction},
            "identity": self.identity,
            "same_effect_as": c.same_effect_as,
            "control": None if self.control is None else self.control.as_dict(),
            "control_test": None if self.control_p_value is None else {
                "test": "Fisher exact, two-sided", "alpha": CONTROL_ALPHA, "p_value": self.control_p_value,
                "no_different": self.identity},
        }



def evaluate(
    claims: Sequence[Claim],
    units: Sequence[Mapping[str, Any]],
    control: Sequence[Mapping[str, Any]] | None = None,
    *,
    z: float = _Z95,
) -> list[ClaimResult]:
    """Judge every claim over the units' ``quantities`` mappings (and over the control's).

    A unit whose quantity is missing, None or NaN cannot test that claim (+-inf is judged); a unit
    that lacks the claim's precondition is counted in ``precondition_absent`` and cannot
    test it either. A quantity that is not a number raises TypeError (a bug in the
    experiment). The spread is the interquartile range (25th and 75th percentiles) of the
    testable units' quantities. ``control`` (the same seeds with the paper's effect switched
    off) is judged without the precondition. ``z``: of the verdict's Wilson interval (1.96 for a
    fixed number of units; :func:`sequential_z` when units are added until claims are decided).

    Parameters
    ----------
    claims : sequence of Claim
        The claims.
    units : sequence of mapping
        Each unit's ``quantities`` (claim quantity -> number or None).
    control : sequence of mapping or None
        The control units' quantities (None: no control).
    z : float
        z of the Wilson interval of the verdicts.

    Returns
    -------
    list of ClaimResult
        One per claim, in order.
    """
    out = []
    for c in claims:
        values, absent = [], 0
        for u in units:
            v = _finite(u.get(c.quantity), c.id)
            if c.precondition is not None and not c.precondition.present_in(u, c.id):
                absent += 1
                continue
            if v is not None:
                values.append(v)
        misses = [m for v in values if (m := c.comparator.miss(v)) is not None]
        arr = np.asarray(values, float)
        out.append(
            ClaimResult(
                claim=c,
                units=len(units),
                testable=len(values),
                holds=len(values) - len(misses),
                median=float(np.median(arr)) if values else None,
                spread=(_percentile(arr, 25), _percentile(arr, 75)) if values else None,
                precondition_absent=absent,
                misses_below=misses.count("below"),
                misses_above=misses.count("above"),
                control=None if control is None else _judge_control(c, control),
                z=z,
            )
        )
    return out


def _judge_control(c: Claim, control: Sequence[Mapping[str, Any]]) -> ControlResult:
    values = [v for u in control if (v := _finite(u.get(c.quantity), c.id)) is not None]
    return ControlResult(units=len(control), testable=len(values), holds=sum(c.comparator.holds(v) for v in values))
