"""Named conversions between field units and SI.

All of gyrobench works in SI inside: rad, rad/s, s, K, m/s^2. Field units
(deg/h, deg/sqrt(h), arcsec, degC, ppm, g) appear only at the edges: specs built
from datasheets, command-line flags and report tables. Every conversion lives
here, as a pair of named functions or a named constant, so that a unit is never
written as a bare number anywhere else.

References
----------
IEEE Std 952-1997, Annex C (units of the noise coefficients); docs/physics.md section 0.

Examples
--------
>>> from gyrobench.base import units
>>> round(units.deg_per_h(1.0), 10)   # 1 deg/h in rad/s
4.8481e-06
>>> units.to_deg_per_h(units.deg_per_h(15.0))
15.0
"""

from __future__ import annotations

import math
import re
import typing
from collections.abc import Callable

import numpy as np

#: one degree [rad]
DEG = math.pi / 180.0
#: one arcsecond [rad]
ARCSEC = DEG / 3600.0
#: one hour [s]
HOUR = 3600.0
#: one minute [s]
MINUTE = 60.0
#: standard gravity [m/s^2]
G0 = 9.80665
#: 0 degC in kelvin [K]
ZERO_CELSIUS = 273.15
#: Earth's rotation rate [rad/s] (sidereal)
EARTH_RATE = 7.292115e-5
#: speed of light in vacuum [m/s] (exact, SI)
SPEED_OF_LIGHT = 299_792_458.0
#: Boltzmann constant [J/K] (exact, SI 2019)
BOLTZMANN = 1.380649e-23
#: elementary charge [C] (exact, SI 2019)
ELEMENTARY_CHARGE = 1.602176634e-19

_SQRT_HOUR = math.sqrt(HOUR)


def _scale(x, k):
    return np.multiply(x, k) if isinstance(x, np.ndarray) else x * k


# --- angle -------------------------------------------------------------------
def deg(x):
    """Degrees -> rad."""
    return _scale(x, DEG)


def to_deg(x):
    """rad -> degrees."""
    return _scale(x, 1.0 / DEG)


def arcsec(x):
    """Arcseconds -> rad."""
    return _scale(x, ARCSEC)


def to_arcsec(x):
    """rad -> arcseconds."""
    return _scale(x, 1.0 / ARCSEC)


# --- rate --------------------------------------------------------------------
def deg_per_s(x):
    """deg/s -> rad/s."""
    return _scale(x, DEG)


def to_deg_per_s(x):
    """rad/s -> deg/s."""
    return _scale(x, 1.0 / DEG)


def deg_per_h(x):
    """deg/h -> rad/s (1 deg/h = 4.8481e-6 rad/s)."""
    return _scale(x, DEG / HOUR)


def to_deg_per_h(x):
    """rad/s -> deg/h."""
    return _scale(x, HOUR / DEG)


# --- noise coefficients (IEEE 952) ---------------------------------------------
def deg_per_sqrt_h(x):
    """Angle random walk deg/sqrt(h) -> rad/sqrt(s) (1 deg/sqrt(h) = 2.9089e-4 rad/sqrt(s))."""
    return _scale(x, DEG / _SQRT_HOUR)


def to_deg_per_sqrt_h(x):
    """Angle random walk rad/sqrt(s) -> deg/sqrt(h)."""
    return _scale(x, _SQRT_HOUR / DEG)


def deg_per_h_per_sqrt_h(x):
    """Rate random walk deg/h/sqrt(h) -> rad/s/sqrt(s) (1 unit = 8.0802e-8 rad/s^1.5)."""
    return _scale(x, DEG / HOUR / _SQRT_HOUR)


def to_deg_per_h_per_sqrt_h(x):
    """Rate random walk rad/s/sqrt(s) -> deg/h/sqrt(h)."""
    return _scale(x, HOUR * _SQRT_HOUR / DEG)


def deg_per_h2(x):
    """Rate ramp deg/h^2 -> rad/s^2 (1 deg/h^2 = 1.3467e-9 rad/s^2)."""
    return _scale(x, DEG / HOUR**2)


def to_deg_per_h2(x):
    """Rate ramp rad/s^2 -> deg/h^2."""
    return _scale(x, HOUR**2 / DEG)


def deg_per_s_per_sqrt_hz(x):
    """Noise density deg/s/sqrt(Hz) (IEEE two-sided, = ADEV at 1 s) -> rad/sqrt(s)."""
    return _scale(x, DEG)


# --- temperature, acceleration, ratios ------------------------------------------
def celsius(x):
    """degC -> K."""
    return np.add(x, ZERO_CELSIUS) if isinstance(x, np.ndarray) else x + ZERO_CELSIUS


def to_celsius(x):
    """K -> degC."""
    return np.subtract(x, ZERO_CELSIUS) if isinstance(x, np.ndarray) else x - ZERO_CELSIUS


def g(x):
    """Acceleration in standard g -> m/s^2."""
    return _scale(x, G0)


def to_g(x):
    """m/s^2 -> standard g."""
    return _scale(x, 1.0 / G0)


def ppm(x):
    """Parts per million -> ratio."""
    return _scale(x, 1e-6)


def to_ppm(x):
    """Ratio -> parts per million."""
    return _scale(x, 1e6)


#: rate units accepted at the edges (CLI, CSV import): name -> factor to rad/s
RATE_UNITS: dict[str, float] = {
    "rad/s": 1.0,
    "deg/s": DEG,
    "deg/h": DEG / HOUR,
    "mrad/s": 1e-3,
    "urad/s": 1e-6,
}


def rate_to_si(x, unit: str):
    """Convert a rate from a named unit (see ``RATE_UNITS``) to rad/s.

    Raises
    ------
    ValueError
        If ``unit`` is not one of ``RATE_UNITS``.
    """
    try:
        k = RATE_UNITS[unit]
    except KeyError:
        raise ValueError(
            f"rate unit must be one of {sorted(RATE_UNITS)}; got {unit!r}"
        ) from None
    return _scale(x, k)


_DURATION = re.compile(r"^\s*([0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)\s*(h|hr|min|m|s|ms)?\s*$")
_DURATION_FACTOR = {"h": HOUR, "hr": HOUR, "min": MINUTE, "m": MINUTE, "s": 1.0, "ms": 1e-3, None: 1.0}


def parse_duration(text: str) -> float:
    """Parse a duration such as ``"10h"``, ``"30min"``, ``"600s"`` or ``"600"`` into seconds.

    Raises
    ------
    ValueError
        If the text is not a positive number with an optional unit h, min, s or ms.

    Examples
    --------
    >>> parse_duration("10h"), parse_duration("30min"), parse_duration("2.5")
    (36000.0, 1800.0, 2.5)
    """
    m = _DURATION.match(str(text))
    if not m:
        raise ValueError(
            f"duration must be a number with an optional unit h, min, s or ms (e.g. 10h, 30min, 600s); got {text!r}"
        )
    value = float(m.group(1)) * _DURATION_FACTOR[m.group(2)]
    if not value > 0:
        raise ValueError(f"duration must be > 0 s; got {text!r}")
    return value


#: IEEE-952 coefficient name -> (field unit, SI -> field function, field -> SI function)
COEFFICIENT_FIELD_UNITS: dict[str, tuple[str, Callable[[float], float], Callable[[float], float]]] = {
    "Q": ("arcsec", to_arcsec, arcsec),
    "N": ("deg/sqrt(h)", to_deg_per_sqrt_h, deg_per_sqrt_h),
    "B": ("deg/h", to_deg_per_h, deg_per_h),
    "K": ("deg/h/sqrt(h)", to_deg_per_h_per_sqrt_h, deg_per_h_per_sqrt_h),
    "R": ("deg/h^2", to_deg_per_h2, deg_per_h2),
}


@typing.overload
def coefficient_to_field(name: str, value: float) -> float: ...
@typing.overload
def coefficient_to_field(name: str, value: None) -> None: ...
def coefficient_to_field(name: str, value: float | None) -> float | None:
    """An IEEE-952 coefficient (Q, N, B, K, R) from SI to its field unit; ``None`` passes through.

    >>> round(coefficient_to_field("N", deg_per_sqrt_h(0.01)), 12)
    0.01
    """
    if name not in COEFFICIENT_FIELD_UNITS:
        raise ValueError(f"coefficient name must be one of {list(COEFFICIENT_FIELD_UNITS)}; got {name!r}")
    return None if value is None else COEFFICIENT_FIELD_UNITS[name][1](value)
