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
is what the analysis gives when there is nothing to find); a method claim that holds on the
units while its control pass-rate interval overlaps the units' is an **identity of the
analysis**, flagged and not counted as reproduced. :attr:`ClaimResult.status` gives the
final word.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from gyrobench.scenarios.claim_tally import ClaimTally, DeviationEffect, deviation_effect, tally

__all__ = [
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
    "below",
    "evaluate",
    "finite_median",
    "tally",
    "in_range",
    "is_true",
    "verdict",
    "wilson_interval",
    "within_factor",
]

#: z for a two-sided 95 % interval
_Z95 = 1.959963984540054

#: a verdict whose 95 % interval ends within this of 50 % is provisional
PROVISIONAL_MARGIN = 0.05

#: a claim's role (see the module docstring)
ROLES = ("device", "method", "extension")
Role = Literal["device", "method", "extension"]

#: the final word on a judged claim (:attr:`ClaimResult.status`)
STATUSES = (
    "device matched",
    "device not matched",
    "reproduced",
    "contradicted",
    "identity of the analysis",
    "not reproducible on this device",
    "undecided",
    "not testable",
)


@dataclass(frozen=True, slots=True, kw_only=True)
class Comparator:
    """How a unit's quantity is judged against the paper. Build with the functions below."""

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
    """Two-sided: ``value / factor <= q <= value * factor`` (``value`` > 0, ``factor`` > 1)."""
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"within_factor value must be finite and > 0; got {value!r}")
    if not (math.isfinite(factor) and factor > 1):
        raise ValueError(f"within_factor factor must be finite and > 1; got {factor!r}")
    return Comparator(kind="within_factor", lo=value / factor, hi=value * factor)


def in_range(lo: float, hi: float) -> Comparator:
    """Two-sided band ``lo <= q <= hi``."""
    if not lo < hi:
        raise ValueError(f"in_range needs lo < hi; got lo={lo!r}, hi={hi!r}")
    return Comparator(kind="in_range", lo=lo, hi=hi)


def above(x: float) -> Comparator:
    """One-sided: ``q > x``."""
    return Comparator(kind="above", lo=float(x))


def below(x: float) -> Comparator:
    """One-sided: ``q < x``."""
    return Comparator(kind="below", hi=float(x))


def is_true() -> Comparator:
    """Per-unit yes/no: the quantity is 1.0 when the statement holds, 0.0 when it fails."""
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
    """

    text: str
    quantity: str
    comparator: Comparator

    def present(self, q: float | None) -> bool:
        """Whether a unit whose precondition quantity is ``q`` shows the effect (None: it does not)."""
        return q is not None and self.comparator.holds(q)


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

    def __post_init__(self) -> None:
        if self.role not in ROLES:
            raise ValueError(f"claim {self.id!r}: role must be one of {ROLES}; got {self.role!r}")
        if self.role == "device" and self.precondition is not None:
            raise ValueError(
                f"claim {self.id!r}: a device claim states what the device shows; it takes no precondition"
            )
        if self.kind not in ("calibrated", "emergent"):
            raise ValueError(f"claim {self.id!r}: kind must be 'calibrated' or 'emergent'; got {self.kind!r}")
        if (self.kind == "calibrated") != bool(self.calibrated_input):
            raise ValueError(
                f"claim {self.id!r}: calibrated_input must be given exactly when kind is 'calibrated'; "
                f"got kind={self.kind!r}, calibrated_input={self.calibrated_input!r}"
            )


@dataclass(frozen=True, slots=True, kw_only=True)
class Deviation:
    """A departure from the protocol the paper states (or a choice where it states nothing).

    ``variant`` names a config variant of the scenario (``variant_config(config, variant)``)
    that runs the paper's protocol instead of ours; ``gyrobench reproduce --deviations`` runs
    it over the units and the report prints the measured change of every claim's pass count.
    ``effect`` is legacy free text; new deviations leave it empty so that no number in a
    deviation is hand-written.
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
    """A claim judged on the control units (the paper's effect switched off; no precondition)."""

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

    @property
    def pass_rate(self) -> float | None:
        """``holds / testable``; None when no unit could test the claim."""
        return self.holds / self.testable if self.testable else None

    @property
    def interval95(self) -> tuple[float, float] | None:
        """95 % Wilson score interval of the pass rate."""
        return wilson_interval(self.holds, self.testable) if self.testable else None

    @property
    def verdict(self) -> str:
        """``"holds for most units"``, ``"fails for most units"``, ``"undecided"``, ``"not testable"``."""
        return verdict(self.holds, self.testable)

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
    def identity(self) -> bool:
        """Holds on the units and about as often on the control (overlapping 95 % intervals)."""
        if self.verdict != "holds for most units" or self.control is None or not self.control.testable:
            return False
        lo, hi = self.interval95 or (0.0, 1.0)
        clo, chi = self.control.interval95 or (0.0, 1.0)
        return clo <= hi and lo <= chi

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
            return "identity of the analysis"
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
            "units": self.units,
            "testable": self.testable,
            "holds": self.holds,
            "pass_rate": self.pass_rate,
            "interval95": list(self.interval95) if self.interval95 else None,
            "median": self.median,
            "spread": list(self.spread) if self.spread else None,
            "verdict": self.verdict,
            "role": c.role,
            "status": self.status,
            "provisional": self.provisional,
            "precondition": None if pre is None else {
                "text": pre.text, "quantity": pre.quantity, "comparator": pre.comparator.text()},
            "precondition_absent": self.precondition_absent,
            "misses": {"below": self.misses_below, "above": self.misses_above, "direction": self.miss_direction},
            "identity": self.identity,
            "control": None if self.control is None else self.control.as_dict(),
        }


def wilson_interval(k: int, n: int, z: float = _Z95) -> tuple[float, float]:
    """Wilson score interval for a binomial proportion ``k / n``.

    ``(p + z^2/2n -+ z sqrt(p(1-p)/n + z^2/4n^2)) / (1 + z^2/n)``, ``p = k/n``
    (Wilson, J. Am. Stat. Assoc. 22, 209 (1927); Brown, Cai & DasGupta, Stat. Sci. 16,
    101 (2001), eq. 4).
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


def verdict(holds: int, testable: int) -> str:
    """The summary's word for a pass count (see the module docstring)."""
    if testable == 0:
        return "not testable"
    lo, hi = wilson_interval(holds, testable)
    if lo > 0.5:
        return "holds for most units"
    if hi < 0.5:
        return "fails for most units"
    return "undecided"


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
    """
    v = [float(x) for x in values if x is not None and math.isfinite(float(x))]
    return float(np.median(v)) if v else math.nan


def evaluate(
    claims: Sequence[Claim],
    units: Sequence[Mapping[str, Any]],
    control: Sequence[Mapping[str, Any]] | None = None,
) -> list[ClaimResult]:
    """Judge every claim over the units' ``quantities`` mappings (and over the control's).

    A unit whose quantity is missing, None or NaN cannot test that claim (+-inf is judged); a unit
    that lacks the claim's precondition is counted in ``precondition_absent`` and cannot
    test it either. A quantity that is not a number raises TypeError (a bug in the
    experiment). The spread is the interquartile range (25th and 75th percentiles) of the
    testable units' quantities. ``control`` (the same seeds with the paper's effect switched
    off) is judged without the precondition.
    """
    out = []
    for c in claims:
        values, absent = [], 0
        for u in units:
            v = _finite(u.get(c.quantity), c.id)
            if c.precondition is not None and not c.precondition.present(
                _finite(u.get(c.precondition.quantity), c.id)
            ):
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
            )
        )
    return out


def _judge_control(c: Claim, control: Sequence[Mapping[str, Any]]) -> ControlResult:
    values = [v for u in control if (v := _finite(u.get(c.quantity), c.id)) is not None]
    return ControlResult(units=len(control), testable=len(values), holds=sum(c.comparator.holds(v) for v in values))
