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
    """Check that a random generator is a :class:`numpy.random.Generator`.

    Parameters
    ----------
    rng : object
        The generator to check.

    Returns
    -------
    numpy.random.Generator
        ``rng`` itself.

    Raises
    ------
    TypeError
        If ``rng`` is anything else (the legacy ``RandomState`` included).
    """
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator; got {type(rng).__name__}")
    return rng


def check_fs(fs: object, name: str = "fs") -> float:
    """Check a sample rate.

    Parameters
    ----------
    fs : object
        The sample rate [Hz].
    name : str
        The parameter named in the message.

    Returns
    -------
    float
        ``fs`` as a float [Hz].

    Raises
    ------
    TypeError
        If ``fs`` is not a real number (a bool is not).
    ValueError
        Unless ``fs`` is finite and > 0.
    """
    if isinstance(fs, bool) or not isinstance(fs, Real):
        raise TypeError(f"{name} must be a real number [Hz]; got {fs!r}")
    x = float(fs)
    if not (math.isfinite(x) and x > 0):
        raise ValueError(f"{name} must be a finite number > 0 Hz; got {fs!r}")
    return x


def real_number(where: str, v: object, unit: str | None = None) -> float:
    """Check that a value is a finite real number.

    Parameters
    ----------
    where : str
        The parameter named in the message (``"Owner.field"``).
    v : object
        The value.
    unit : str, optional
        Its unit (e.g. ``"rad/s"``), shown in brackets in the message when given.

    Returns
    -------
    float
        ``v`` as a float.

    Raises
    ------
    TypeError
        ``"{where} must be a real number [unit]"`` if ``v`` is not a real number (a bool is not).
    ValueError
        ``"{where} must be finite [unit]"`` if ``v`` is NaN or infinite.
    """
    u = f" [{unit}]" if unit else ""
    if isinstance(v, bool) or not isinstance(v, Real):
        raise TypeError(f"{where} must be a real number{u}; got {v!r}")
    x = float(v)
    if not math.isfinite(x):
        raise ValueError(f"{where} must be finite{u}; got {v!r}")
    return x


def positive_number(where: str, v: object, unit: str) -> float:
    """Check that a value is a finite number > 0.

    Parameters
    ----------
    where : str
        The parameter named in the message.
    v : object
        The value.
    unit : str
        Its unit, for the message.

    Returns
    -------
    float
        ``v`` as a float.

    Raises
    ------
    ValueError
        ``"{where} must be a finite number > 0 {unit}"`` otherwise.
    """
    if isinstance(v, bool) or not isinstance(v, Real) or not (math.isfinite(float(v)) and float(v) > 0):
        raise ValueError(f"{where} must be a finite number > 0 {unit}; got {v!r}")
    return float(v)


def real_field(owner: str, name: str, v: object) -> float:
    """Check that a field of an object is a finite real number.

    Parameters
    ----------
    owner : str
        The object named in the message (e.g. ``"NoiseModel"``).
    name : str
        The field named in the message.
    v : object
        The field's value.

    Returns
    -------
    float
        ``v`` as a float (:func:`real_number` with ``where = owner.name``).
    """
    return real_number(f"{owner}.{name}", v)


def positive_field(owner: str, name: str, v: object, unit: str) -> float:
    """Check that a field is a finite number > 0.

    Parameters
    ----------
    owner : str
        The object named in the message (e.g. ``"NoiseModel"``).
    name : str
        The field named in the message.
    v : object
        The field's value.
    unit : str
        Its unit, for the message.

    Returns
    -------
    float
        ``v`` as a float.

    Raises
    ------
    TypeError, ValueError
        As :func:`real_field`; ValueError ``"{owner}.{name} must be > 0 {unit}"`` unless > 0.
    """
    x = real_field(owner, name, v)
    if x <= 0:
        raise ValueError(f"{owner}.{name} must be > 0 {unit}; got {v!r}")
    return x


def nonneg_field(owner: str, name: str, v: object, unit: str) -> float:
    """Check that a field is a finite number >= 0.

    Parameters
    ----------
    owner : str
        The object named in the message (e.g. ``"NoiseModel"``).
    name : str
        The field named in the message.
    v : object
        The field's value.
    unit : str
        Its unit, for the message.

    Returns
    -------
    float
        ``v`` as a float.

    Raises
    ------
    TypeError, ValueError
        As :func:`real_field`; ValueError ``"{owner}.{name} must be >= 0 {unit}"`` unless >= 0.
    """
    x = real_field(owner, name, v)
    if x < 0:
        raise ValueError(f"{owner}.{name} must be >= 0 {unit}; got {v!r}")
    return x


def nonneg_fields(owner: str, obj: object, names: tuple[str, ...], unit: str) -> None:
    """Check that several fields of an object are finite numbers >= 0.

    Parameters
    ----------
    owner : str
        The object named in the message.
    obj : object
        The object whose attributes are checked.
    names : tuple of str
        The attributes, each checked by :func:`nonneg_field`.
    unit : str
        Their unit, for the message.

    Raises
    ------
    TypeError, ValueError
        As :func:`nonneg_field`, for the first field that fails.
    """
    for name in names:
        nonneg_field(owner, name, getattr(obj, name), unit)


def number_where(owner: str, name: str, v: object, cond: str, unit: str, ok: Callable[[float], bool]) -> float:
    """Check that a field is a finite real number satisfying a condition.

    Parameters
    ----------
    owner : str
        The object named in the message (e.g. ``"NoiseModel"``).
    name : str
        The field named in the message.
    v : object
        The field's value.
    cond : str
        The condition in words, for the message (e.g. ``"> 0"``, ``"in (0, 1)"``).
    unit : str
        The unit, for the message.
    ok : callable
        ``ok(float(v)) -> bool``, the condition itself.

    Returns
    -------
    float
        ``v`` as a float.

    Raises
    ------
    ValueError
        ``"{owner}.{name} must be {cond} {unit}"`` if ``v`` is not a finite real number or
        ``ok(v)`` is false.
    """
    if isinstance(v, bool) or not isinstance(v, Real) or not math.isfinite(v) or not ok(float(v)):
        raise ValueError(f"{owner}.{name} must be {cond} {unit}; got {v!r}")
    return float(v)


def nonneg_coefficient(owner: str, name: str, v: object, maximum: float) -> None:
    """Check a noise coefficient [SI].

    Parameters
    ----------
    owner : str
        The object named in the message (e.g. ``"NoiseModel"``).
    name : str
        The field named in the message.
    v : object
        The coefficient [SI].
    maximum : float
        The largest value allowed [SI]: its square and the variances built from it must stay
        finite.

    Raises
    ------
    TypeError
        Unless ``v`` is a real number.
    ValueError
        Unless ``v`` is finite, >= 0 and <= ``maximum``.
    """
    if isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)):
        raise TypeError(f"{owner}.{name} must be a real number; got {v!r}")
    if not (math.isfinite(v) and v >= 0.0):
        raise ValueError(f"{owner}.{name} must be finite and >= 0; got {v!r}")
    if v > maximum:
        raise ValueError(
            f"{owner}.{name} must be <= {maximum:g} (SI; no gyro comes near it, and the "
            f"variances square it); got {v!r}"
        )
