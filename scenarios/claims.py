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
"""

from __future__ import annotations

import functools
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar, Literal

import numpy as np
from numpy.typing import NDArray

from gyrobench.base.ranges import Constraint, validate
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

#: z for a two-sided 95 % interval
_Z95 = 1.959963984540054

#: a verdict whose 95 % interval ends within this of 50 % is provisional
PROVISIONAL_MARGIN = 0.05

#: false-alarm rate of the two-sided Fisher exact test of "the units pass as often as the control"
CONTROL_ALPHA = 0.05

#: a claim's role (see the module docstring)
ROLES = ("device", "method", "extension")
Role = Literal["device", "method", "extension"]

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
class Comparator:
    """How a unit's quantity is judged against the paper. Build with the functions below.

    Parameters
    ----------
    kind : {"within_factor", "in_range", "above", "below", "is_true"}
        The kind of judgement.
    lo, hi : float
        The band's ends (-inf / inf where one-sided).
    """

    kind: Literal["within_factor", "in_range", "above", "below", "is_true"]
    lo: float = -math.inf
    hi: float = math.inf

    def holds(self, q: float) -> bool:
        """Whether quantity ``q`` (a number; +-inf is judged as a value) satisfies the comparator."""
        if self.kind == "is_true":
            return bool(q == 1.0)
        if self.kind == "above":
            return bool(q > self.lo)
        if self.kind == "below":
            return bool(q < self.hi)
        return bool(self.lo <= q <= self.hi)

    def miss(self, q: float) -> str | None:
        """For a ``q`` (not NaN) the comparator rejects: ``"below"`` or ``"above"`` its band
        (``"false"`` for a yes/no claim); None when it holds."""
        if self.holds(q):
            return None
        if self.kind == "is_true":
            return "false"
        return "below" if q < self.lo or (self.kind == "above" and q <= self.lo) else "above"

    def as_dict(self) -> dict[str, Any]:
        """The comparator as data, for a referee to recount a pass: ``kind`` and the band ``lo``, ``hi``
        (``"above"``: q > lo; ``"below"``: q < hi; ``"is_true"``: q == 1; otherwise lo <= q <= hi)."""
        return {"kind": self.kind, "lo": self.lo, "hi": self.hi}

    def text(self, unit: str = "") -> str:
        """One phrase, e.g. ``"within 2x of 15.71 % (7.855 to 31.42)"``."""
        u = f" {unit}" if unit else ""
        if self.kind == "is_true":
            return "true for the unit"
        if self.kind == "above":
            return f"> {self.lo:.4g}{u}"
        if self.kind == "below":
            return f"< {self.hi:.4g}{u}"
        if self.kind == "within_factor":
            centre = math.sqrt(self.lo * self.hi)
            factor = math.sqrt(self.hi / self.lo)
            return f"within {factor:.3g}x of {centre:.4g}{u} ({self.lo:.4g} to {self.hi:.4g})"
        return f"between {self.lo:.4g} and {self.hi:.4g}{u}"


def within_factor(value: float, factor: float = 2.0) -> Comparator:
    """Two-sided: ``value / factor <= q <= value * factor`` (``value`` > 0, ``factor`` > 1).

    Parameters
    ----------
    value : float
        The paper's value, > 0.
    factor : float
        The factor, > 1.

    Returns
    -------
    Comparator
        Holds when ``value / factor <= q <= value * factor``.
    """
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"within_factor value must be finite and > 0; got {value!r}")
    if not (math.isfinite(factor) and factor > 1):
        raise ValueError(f"within_factor factor must be finite and > 1; got {factor!r}")
    return Comparator(kind="within_factor", lo=value / factor, hi=value * factor)


def in_range(lo: float, hi: float) -> Comparator:
    """Two-sided band ``lo <= q <= hi``.

    Parameters
    ----------
    lo, hi : float
        The band's ends, lo <= hi.

    Returns
    -------
    Comparator
        Holds when ``lo <= q <= hi``.
    """
    if not lo < hi:
        raise ValueError(f"in_range needs lo < hi; got lo={lo!r}, hi={hi!r}")
    return Comparator(kind="in_range", lo=lo, hi=hi)


def above(x: float) -> Comparator:
    """One-sided: ``q > x``.

    Parameters
    ----------
    x : float
        The threshold.

    Returns
    -------
    Comparator
        Holds when ``q > x``.
    """
    return Comparator(kind="above", lo=float(x))


def below(x: float) -> Comparator:
    """One-sided: ``q < x``.

    Parameters
    ----------
    x : float
        The threshold.

    Returns
    -------
    Comparator
        Holds when ``q < x``.
    """
    return Comparator(kind="below", hi=float(x))


def is_true() -> Comparator:
    """Per-unit yes/no: the quantity is 1.0 when the statement holds, 0.0 when it fails.

    Returns
    -------
    Comparator
        Holds when the quantity is 1.0.
    """
    return Comparator(kind="is_true")


@dataclass(frozen=True, slots=True, kw_only=True)
class Precondition:
    """The per-unit condition under which a claim can be judged: "the unit shows the effect".

    Parameters
    ----------
    text : str
        The condition in words, e.g. ``"the vibration bias exceeds 3 sigma of the 10-s scatter"``.
    quantity : str
        Key of the unit's ``quantities`` the comparator reads (e.g. the bias-to-scatter ratio).
    comparator : Comparator
        Present when the comparator holds on the unit's value (not None or NaN; +-inf is a value).
    also : tuple of Precondition
        Further conditions the unit must meet as well (each on its own quantity).
    """

    text: str
    quantity: str
    comparator: Comparator
    also: tuple[Precondition, ...] = ()

    def _own_holds(self, q: float | None) -> bool:
        """This condition alone on the value ``q`` (None: not met); never the whole precondition."""
        return q is not None and self.comparator.holds(q)

    def present_in(self, unit: Mapping[str, Any], claim_id: str = "") -> bool:
        """Whether the unit's quantities meet this condition and every one of ``also``."""
        return self._own_holds(_finite(unit.get(self.quantity), claim_id)) and all(
            p.present_in(unit, claim_id) for p in self.also
        )

    def as_dict(self) -> dict[str, Any]:
        return {"text": self.text, "quantity": self.quantity, "comparator": self.comparator.text(),
                "criterion": self.comparator.as_dict(), "also": [p.as_dict() for p in self.also]}


@dataclass(frozen=True, slots=True, kw_only=True)
class Claim:
    """One checkable statement of a paper.

    Parameters
    ----------
    id : str
        Stable identifier, ``"<paper>.<short name>"``, e.g. ``"001.raw_kn"``.
    paper : str
        The paper's key in :mod:`gyrobench.scenarios.papers` (``"000"`` ... ``"004"``).
    where : str
        Table, figure or section of the paper, e.g. ``"Table 3"``, ``"Sec. 4, conclusion"``.
    statement : str
        The paper's claim in one sentence.
    kind : "calibrated" or "emergent"
        ``calibrated`` when an input of the simulation was set from this number or chosen
        so that the claim holds (name it in ``calibrated_input``); ``emergent`` when
        nothing was set to make it hold.
    quantity : str
        Key of the unit's ``quantities`` the comparator reads.
    comparator : Comparator
        How a unit's quantity is judged.
    paper_value : float, optional
        The paper's number, in ``unit``.
    unit : str
        Field unit of the quantity and of ``paper_value`` (``"%"``, ``"deg/h"``, ``"x"``...).
    calibrated_input : str, optional
        For a calibrated claim: the input and how it was set.
    role : "device", "method" or "extension"
        See the module docstring. Default ``"method"``.
    precondition : Precondition, optional
        For a method or extension claim: when a unit can judge it.
    same_effect_as : str, optional
        The id of the claim that shows the same effect of the simulation (e.g. two quantities
        of one offset): the claim is judged and shown but counted once, with that claim (the
        group's lead), in the tally.
    """

    id: str
    paper: str
    where: str
    statement: str
    kind: Literal["calibrated", "emergent"]
    quantity: str
    comparator: Comparator
    paper_value: float | None = None
    unit: str = ""
    calibrated_input: str | None = None
    role: Role = "method"
    precondition: Precondition | None = None
    same_effect_as: str | None = None

    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "same_effect_as names another claim",
            lambda c: c.same_effect_as is None or c.same_effect_as != c.id,
            lambda c: f"same_effect_as must name another claim; got its own id {c.id!r}",
        ),
        Constraint(
            "a device claim takes no precondition",
            lambda c: c.role != "device" or c.precondition is None,
            lambda c: f"precondition must be None for a device claim (it states what the device shows); got "
            f"{c.precondition!r} (claim {c.id!r})",
        ),
        Constraint(
            "calibrated_input given exactly when kind is 'calibrated'",
            lambda c: (c.kind == "calibrated") == bool(c.calibrated_input),
            lambda c: f"calibrated_input must be given exactly when kind is 'calibrated'; got kind={c.kind!r}, "
            f"calibrated_input={c.calibrated_input!r} (claim {c.id!r})",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # kind and role from their Literal annotations, then the constraints above


@dataclass(frozen=True, slots=True, kw_only=True)
class Deviation:
    """A departure from the protocol the paper states (or a choice where it states nothing).

    ``variant`` names a config variant of the scenario (``variant_config(config, variant)``)
    that runs the paper's protocol instead of ours; ``gyrobench reproduce --deviations`` runs
    it over the units and the report prints the measured change of every claim's pass count.
    ``effect`` is legacy free text; new deviations leave it empty so that no number in a
    deviation is hand-written.

    Parameters
    ----------
    paper : str
        The paper's key.
    what : str
        The protocol step concerned.
    paper_says : str
        What the paper states (or that it states nothing).
    we_do : str
        What the scenario does instead.
    reason : str
        Why.
    effect : str
        Free text; empty for new deviations (the measured change is reported instead).
    variant : str or None
        The config variant that runs the paper's protocol (None: none).
    """

    paper: str
    what: str
    paper_says: str
    we_do: str
    reason: str
    effect: str = ""
    variant: str | None = None


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


def _finite(v: Any, claim_id: str) -> float | None:
    """The quantity as a float, None when the unit cannot test the claim (None, NaN).

    +-inf is a value, judged like any other (a ratio over a zero denominator: the quantity is
    there on one side only).

    Anything but a number (a string, a list) is a bug in the scenario's ``experiment``,
    not an untestable unit: TypeError.
    """
    if v is None:
        return None
    if not isinstance(v, int | float | np.integer | np.floating | np.bool_):
        raise TypeError(
            f"claim {claim_id!r}: a unit's quantity must be a number, None or NaN; "
            f"got {type(v).__name__} {v!r}"
        )
    f = float(v)
    return None if math.isnan(f) else f


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
