"""The kind of a log's column (gyro or accelerometer) from its name, its unit and its magnitude; ``--units``
per kind."""

from __future__ import annotations

import re

import numpy as np
from numpy.typing import NDArray

from gyrobench.io.logs._names import _ACCEL_NAME, _GYRO_NAME, _RATE_ALIASES, ACCEL_UNITS

#: ``--units`` keys -> the quantity of the columns they apply to
UNIT_KEYS = {"gyro": "rate", "accel": "accel"}
#: standard gravity [m/s^2] (CGPM 1901)
G0 = 9.80665
#: a column typed only by a bare ``--units`` rate unit is refused as a gyro when its mean is within this
#: fraction of 1 g (in m/s^2 or in g) and its scatter below it: gravity on an accelerometer axis
GRAVITY_TOLERANCE = 0.15
#: an untyped column whose name ends in an axis letter (``x``, ``imu.y``, ``col_z``) may be a gyro or
#: accelerometer axis: ``--all-axes`` analyses it (with a unit) or refuses it, never drops it
_AXIS_LIKE = re.compile(r"(^|[^a-z])[xyz]$", re.IGNORECASE)


def parse_units(text: str | None) -> dict[str, str]:
    """``--units``: one unit (``deg/s``: the columns of its kind) or units per kind (``gyro=deg/s,accel=g``).

    Returns
    -------
    dict
        quantity ("rate" or "accel") -> unit; a bare unit maps to the kind it measures (an
        unknown unit to "rate", where the conversion names the valid ones) and the key
        ``"bare"`` -> "1" marks it as given without a kind.

    Raises
    ------
    ValueError
        An unknown key, a key twice, or a unit of the other kind under a key, in one line.
    """
    if text is None:
        return {}
    text = text.strip()
    if "=" not in text:
        u = _RATE_ALIASES.get(text, text)
        return {"accel" if u in ACCEL_UNITS else "rate": u, "bare": "1"}
    out: dict[str, str] = {}
    for part in text.split(","):
        key, sep, unit = (s.strip() for s in part.partition("="))
        if not sep or key not in UNIT_KEYS or not unit:
            raise ValueError(
                f"--units must be one unit (e.g. deg/s) or kind=unit pairs such as gyro=deg/s,accel=g "
                f"(kinds: {'|'.join(UNIT_KEYS)}); got {text!r}"
            )
        q = UNIT_KEYS[key]
        if q in out:
            raise ValueError(f"--units gives the {key} unit twice; got {text!r}")
        unit = _RATE_ALIASES.get(unit, unit)
        if (q == "accel") != (unit in ACCEL_UNITS):
            want = f"one of {sorted(ACCEL_UNITS)}" if q == "accel" else "a rate unit (deg/s, deg/h, rad/s, ...)"
            raise ValueError(f"--units {key}= must be {want}; got {unit!r}")
        out[q] = unit
    return out


def kind_by_name(name: str) -> str | None:
    """"rate" or "accel" when the column's name says so (``gyro_x``, ``omega_y``, ``accel_z``, ``ax``), else None."""
    if _GYRO_NAME.search(name):
        return "rate"
    if _ACCEL_NAME.search(name):
        return "accel"
    return None


def axis_like(name: str) -> bool:
    """Whether an untyped column's name ends in an axis letter (it may be a gyro or accelerometer axis)."""
    return bool(_AXIS_LIKE.search(name))


def gravity_like(x: NDArray[np.float64]) -> str | None:
    """The unit in which the column reads 1 g ("m/s^2" or "g") when its mean is within :data:`GRAVITY_TOLERANCE`
    of it and its scatter is below that tolerance (a static accelerometer axis along gravity), else None."""
    if x.size == 0 or not np.isfinite(np.sum(x)):  # a non-finite sample is refused later, naming it
        return None
    mean = abs(float(np.mean(x)))
    spread = float(np.std(x))
    for unit, g in (("m/s^2", G0), ("g", 1.0)):
        if abs(mean - g) <= GRAVITY_TOLERANCE * g and spread <= GRAVITY_TOLERANCE * g:
            return unit
    return None
