"""Input validators shared by the :mod:`gyrobench.sim` models (one place, one wording).

Each raises with one line naming the parameter, the constraint and the value (STYLE.md):
a TypeError when the value is not of the right kind, a ValueError when it is out of range.
The messages are the ones the models' tests match on.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from numbers import Real

import numpy as np

__all__ = [
    "check_rng",
    "check_fs",
    "real_number",
    "positive_number",
    "real_field",
    "positive_field",
    "nonneg_field",
    "nonneg_fields",
    "number_where",
    "nonneg_coefficient",
]


def check_rng(rng: object) -> np.random.Generator:
    """``rng`` itself if it is a :class:`numpy.random.Generator`, else TypeError."""
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator; got {type(rng).__name__}")
    return rng


def check_fs(fs: object, name: str = "fs") -> float:
    """A sample rate as a float [Hz]: TypeError if not a real number, ValueError unless finite and > 0."""
    if isinstance(fs, bool) or not isinstance(fs, Real):
        raise TypeError(f"{name} must be a real number [Hz]; got {fs!r}")
    x = float(fs)
    if not (math.isfinite(x) and x > 0):
        raise ValueError(f"{name} must be a finite number > 0 Hz; got {fs!r}")
    return x


def real_number(where: str, v: object, unit: str | None = None) -> float:
    """``v`` as a finite float: TypeError "{where} must be a real number [unit]", ValueError "... must be finite".

    ``where`` names the parameter (``"Owner.field"``); ``unit`` (e.g. ``"rad/s"``) is shown in
    brackets when given.
    """
    u = f" [{unit}]" if unit else ""
    if isinstance(v, bool) or not isinstance(v, Real):
        raise TypeError(f"{where} must be a real number{u}; got {v!r}")
    x = float(v)
    if not math.isfinite(x):
        raise ValueError(f"{where} must be finite{u}; got {v!r}")
    return x


def positive_number(where: str, v: object, unit: str) -> float:
    """``v`` as a float, finite and > 0: ValueError "{where} must be a finite number > 0 {unit}" otherwise."""
    if isinstance(v, bool) or not isinstance(v, Real) or not (math.isfinite(float(v)) and float(v) > 0):
        raise ValueError(f"{where} must be a finite number > 0 {unit}; got {v!r}")
    return float(v)


def real_field(owner: str, name: str, v: object) -> float:
    """``owner.name`` as a finite float: :func:`real_number` with ``where = owner.name``, no unit."""
    return real_number(f"{owner}.{name}", v)


def positive_field(owner: str, name: str, v: object, unit: str) -> float:
    """:func:`real_field`, then ValueError "{owner}.{name} must be > 0 {unit}" unless > 0."""
    x = real_field(owner, name, v)
    if x <= 0:
        raise ValueError(f"{owner}.{name} must be > 0 {unit}; got {v!r}")
    return x


def nonneg_field(owner: str, name: str, v: object, unit: str) -> float:
    """:func:`real_field`, then ValueError "{owner}.{name} must be >= 0 {unit}" unless >= 0."""
    x = real_field(owner, name, v)
    if x < 0:
        raise ValueError(f"{owner}.{name} must be >= 0 {unit}; got {v!r}")
    return x


def nonneg_fields(owner: str, obj: object, names: tuple[str, ...], unit: str) -> None:
    """:func:`nonneg_field` on each named attribute of ``obj`` (``unit``: for the message)."""
    for name in names:
        nonneg_field(owner, name, getattr(obj, name), unit)


def number_where(owner: str, name: str, v: object, cond: str, unit: str, ok: Callable[[float], bool]) -> float:
    """``v`` as a float if it is a finite real number with ``ok(v)``; else ValueError
    "{owner}.{name} must be {cond} {unit}" (``cond`` words the predicate, e.g. "> 0")."""
    if isinstance(v, bool) or not isinstance(v, Real) or not math.isfinite(v) or not ok(float(v)):
        raise ValueError(f"{owner}.{name} must be {cond} {unit}; got {v!r}")
    return float(v)


def nonneg_coefficient(owner: str, name: str, v: object, maximum: float) -> None:
    """A noise coefficient [SI]: TypeError unless a real number; ValueError unless finite,
    >= 0 and <= ``maximum`` (its square and the variances built from it must stay finite)."""
    if isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)):
        raise TypeError(f"{owner}.{name} must be a real number; got {v!r}")
    if not (math.isfinite(v) and v >= 0.0):
        raise ValueError(f"{owner}.{name} must be finite and >= 0; got {v!r}")
    if v > maximum:
        raise ValueError(
            f"{owner}.{name} must be <= {maximum:g} (SI; no gyro comes near it, and the "
            f"variances square it); got {v!r}"
        )
