"""A paper's claims as records: what the paper states and how one unit's quantity is judged.

:class:`Claim` (the paper's sentence, its role, its value and one :class:`Comparator`),
:class:`Precondition` (the per-unit condition under which a method claim can be judged) and
:class:`Deviation` (where our protocol differs from the paper's) are data only; the comparator
factories (:func:`within_factor`, :func:`in_range`, :func:`above`, :func:`below`,
:func:`is_true`) build the one comparison a claim is judged by. Judging claims over a
population of units is :func:`gyrobench.scenarios.claims.evaluate`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar, Literal

import numpy as np

from gyrobench.base.ranges import Constraint, validate

__all__ = [
    "ROLES",
    "Claim",
    "Comparator",
    "Deviation",
    "Precondition",
    "above",
    "below",
    "in_range",
    "is_true",
    "within_factor",
]

#: a claim's role (see the module docstring)
ROLES = ("device", "method", "extension")
Role = Literal["device", "method", "extension"]


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
