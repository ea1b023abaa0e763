"""Documented ranges of numeric configuration fields (:class:`FieldRange`) and the one-line
refusal of a value outside them. Here in ``sim`` so the simulator's dataclasses that a scenario's
configuration nests can state theirs (``sim`` never imports ``scenarios``); re-exported by
:mod:`gyrobench.base.ranges`. Kept free of numpy so the command line's flag types can use
it without importing anything heavy (``gyrobench --help`` imports only the standard library)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

__all__ = ["FieldRange", "check_ranges", "field_range", "range_error"]


@dataclass(frozen=True, slots=True)
class FieldRange:
    """The documented valid range of one numeric configuration field, in the field's own unit.

    A scenario's ``Config`` (and any dataclass nested in it) states these as the class
    attribute ``RANGES: ClassVar[Mapping[str, FieldRange]]``, one per numeric field; the
    configuration layer (:func:`gyrobench.scenarios.registry.override`) and the config's own
    ``__post_init__`` (:func:`check_ranges`) refuse a value outside it in one line naming the
    field, the range and the unit. Declare it as
    ``RANGES: ClassVar[Mapping[str, FieldRange]] = {...}`` (``ClassVar`` imported from
    :mod:`typing` in that module, so the dataclass does not take it for a field). The bounds
    are physical (what the model is valid for) or practical (what one run can hold), as
    ``why`` says.

    Parameters
    ----------
    low, high : float
        Bounds, in ``unit``; each inclusive unless ``low_open`` / ``high_open``.
    unit : str
        The field's unit as a user writes it (``"m"``, ``"degC/min"``, ``"1"`` for a pure number).
    why : str
        What sets the bounds (shown by nothing; read by a maintainer and the meta-test's failures).
    integer : bool
        The field holds an integer count.
    """

    low: float
    high: float
    unit: str
    why: str = ""
    low_open: bool = False
    high_open: bool = False
    integer: bool = False

    def contains(self, value: float) -> bool:
        """True when ``value`` is a finite number inside the range."""
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            return False
        if isinstance(value, int) and abs(value) > 2**63 - 1:  # never converted to float (10**400)
            return False
        v = float(value)
        if not math.isfinite(v):
            return False
        above = v > self.low if self.low_open else v >= self.low
        below = v < self.high if self.high_open else v <= self.high
        return above and below

    def text(self) -> str:
        """The range as a user reads it: ``"(0, 1e+05] m"``."""
        lo, hi = ("(" if self.low_open else "["), (")" if self.high_open else "]")
        kind = "an integer in " if self.integer else ""
        return f"{kind}{lo}{self.low:g}, {self.high:g}{hi} {self.unit}".rstrip()


def field_range(config_type: type, name: str) -> FieldRange | None:
    """The documented :class:`FieldRange` of field ``name`` of the dataclass ``config_type`` (None
    when it states none)."""
    ranges = getattr(config_type, "RANGES", None) or {}
    return ranges.get(name)


def range_error(owner: str, name: str, rng: FieldRange, value: Any) -> ValueError:
    """The one-line error for ``value`` outside ``rng`` (a huge integer shown by its size only)."""
    shown = f"an integer of {len(str(abs(value)))} digits" if isinstance(value, int) and abs(value) > 10**30 else (
        repr(value)
    )
    return ValueError(f"{owner}.{name} must be {rng.text()}; got {shown}")


def check_ranges(config: Any) -> None:
    """Refuse, in one line, any field of the dataclass ``config`` outside its documented range
    (:class:`FieldRange`, the class attribute ``RANGES``). A None value (an optional field left
    unset) passes; a tuple is checked element by element.

    Raises
    ------
    ValueError
        Naming the field, its range with unit and the value.
    """
    cls = type(config)
    for name, rng in (getattr(cls, "RANGES", None) or {}).items():
        value = getattr(config, name)
        values = value if isinstance(value, tuple) else (value,)
        for i, v in enumerate(values):
            if v is None:
                continue
            key = f"{name}[{i}]" if isinstance(value, tuple) else name
            if not rng.contains(v) or (rng.integer and not isinstance(v, int)):
                raise range_error(cls.__name__, key, rng, v)
