"""Input validators shared by the :mod:`gyrobench.sim` models (one place, one wording).

Each raises with one line naming the parameter, the constraint and the value (STYLE.md):
a TypeError when the value is not of the right kind, a ValueError when it is out of range.
The messages are the ones the models' tests match on.
"""

from __future__ import annotations

import math
from numbers import Real

import numpy as np

__all__ = ["check_rng", "check_fs", "real_number", "positive_number"]


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
