"""The Earth's rotation rate seen by a gyro's sense axis at a latitude, and the papers' labs.

All angles in rad, rates in rad/s (SI). In the local level frame east-north-up (ENU) the
Earth's rate is

    Omega_ie = Omega_E (0, cos(phi), sin(phi))                                   [rad/s]

(phi geodetic latitude). A sense axis at azimuth psi (from north, positive toward east) and
elevation e (above the horizontal) has the ENU unit vector
u = (cos e sin psi, cos e cos psi, sin e), so the rate it senses is

    Omega_s = u . Omega_ie = Omega_E (cos(phi) cos(e) cos(psi) + sin(phi) sin(e))  [rad/s]

Closed forms (tests): horizontal north axis Omega_E cos(phi); vertical up Omega_E sin(phi);
horizontal east 0; north^2 + up^2 = Omega_E^2.

References
----------
IERS Conventions (2010), IERS Technical Note 36, Table 1.1: nominal mean angular velocity of
the Earth omega = 7.292115e-5 rad/s (the WGS 84 value, NIMA TR8350.2 Table 3.1, is the same
7292115e-11 rad/s). Level-frame decomposition: Titterton & Weston, Strapdown Inertial
Navigation Technology, 2nd ed. (2004), sec. 3.5 (Earth-rate components in the local
geographic frame).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from numbers import Real

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.base import units

__all__ = [
    "EARTH_RATE",
    "Site",
    "BEIJING",
    "NANJING",
    "HARBIN",
    "PAPER_SITES",
    "earth_rate_components",
    "sensed_earth_rate",
]

#: nominal mean angular velocity of the Earth [rad/s] (IERS TN 36 Table 1.1; WGS 84)
EARTH_RATE: float = units.EARTH_RATE


@dataclass(frozen=True, slots=True, kw_only=True)
class Site:
    """A laboratory location.

    Parameters
    ----------
    name : str
        Label.
    latitude : float
        Geodetic latitude [rad], in [-pi/2, pi/2].
    source : str
        Where the latitude comes from.
    """

    name: str
    latitude: float
    source: str = ""

    def __post_init__(self) -> None:
        v = self.latitude
        if (
            isinstance(v, bool)
            or not isinstance(v, Real)
            or not (math.isfinite(v) and abs(v) <= math.pi / 2)
        ):
            raise ValueError(f"Site.latitude must be finite in [-pi/2, pi/2] rad; got {v!r}")


#: Beijing (papers 001: BISTU, postcode 100101; 004: Beijing Institute of Automatic Control
#: Equipment, postcode 100074). City latitude 39.9 N (approximate, +-0.1 deg covers both
#: institutes); the papers print the city and postcode, not coordinates.
BEIJING = Site(
    name="Beijing",
    latitude=units.deg(39.9),
    source="papers 001 and 004 affiliation lines (Beijing 100101 / 100074); city latitude "
    "39.9 N, approximate (+-0.1 deg)",
)
#: Nanjing (paper 000: Southeast University, postcode 210096, printed in its affiliation line;
#: Sipailou campus ~32.06 N, approximate +-0.05 deg). Issue 17 assumed Beijing for 000; the
#: paper's Chinese text says Nanjing.
NANJING = Site(
    name="Nanjing",
    latitude=units.deg(32.06),
    source="paper 000 affiliation line (Southeast University, Nanjing 210096); campus "
    "latitude 32.06 N, approximate (+-0.05 deg)",
)
#: Harbin (paper 003: Harbin Engineering University); latitude 45.8 N, approximate (+-0.05 deg).
HARBIN = Site(
    name="Harbin",
    latitude=units.deg(45.8),
    source="paper 003 affiliation (Harbin Engineering University); latitude 45.8 N, "
    "approximate (+-0.05 deg)",
)

#: each paper's lab, from the affiliation its text prints
PAPER_SITES: dict[str, Site] = {"000": NANJING, "001": BEIJING, "003": HARBIN, "004": BEIJING}


def _angle(name: str, v: ArrayLike) -> NDArray[np.float64]:
    a = np.asarray(v, dtype=float)
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be finite [rad]; got {v!r}")
    return a


def earth_rate_components(latitude: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(north, up) components of the Earth's rate at a geodetic latitude [rad] -> [rad/s].

    north = Omega_E cos(phi), up = Omega_E sin(phi); the east component is 0.

    >>> n, u = earth_rate_components(0.0)
    >>> float(n) == EARTH_RATE, float(u)
    (True, 0.0)
    """
    phi = _angle("latitude", latitude)
    if np.any(np.abs(phi) > math.pi / 2):
        raise ValueError(f"latitude must be in [-pi/2, pi/2] rad; got {latitude!r}")
    return EARTH_RATE * np.cos(phi), EARTH_RATE * np.sin(phi)


def sensed_earth_rate(
    latitude: ArrayLike, *, azimuth: ArrayLike = 0.0, elevation: ArrayLike = 0.0
) -> NDArray[np.float64]:
    """Earth-rate component along a sense axis [rad/s].

    Parameters
    ----------
    latitude : float or array
        Geodetic latitude phi [rad].
    azimuth : float or array
        Azimuth psi of the axis from north, positive toward east [rad].
    elevation : float or array
        Elevation e of the axis above the local horizontal [rad] (pi/2: vertical up).

    Returns
    -------
    ndarray
        Omega_E (cos(phi) cos(e) cos(psi) + sin(phi) sin(e)) [rad/s].

    >>> from gyrobench.base import units
    >>> round(units.to_deg_per_h(float(sensed_earth_rate(units.deg(45.8)))), 3)
    10.486
    """
    north, up = earth_rate_components(latitude)
    psi = _angle("azimuth", azimuth)
    e = _angle("elevation", elevation)
    return north * np.cos(e) * np.cos(psi) + up * np.sin(e)
