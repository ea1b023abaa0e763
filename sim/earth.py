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
from collections.abc import Mapping
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.base import units
from gyrobench.base.ranges import FieldRange, validate

__all__ = [
    "EARTH_RATE",
    "Site",
    "BEIJING",
    "NANJING",
    "HARBIN",
    "PAPER_SITES",
    "earth_rate_components",
    "sensed_earth_rate",
    "normal_gravity",
    "WGS84_A",
    "WGS84_E2",
]

#: nominal mean angular velocity of the Earth [rad/s] (IERS TN 36 Table 1.1; WGS 84)
EARTH_RATE: float = units.EARTH_RATE


#: WGS84 semi-major axis [m] and first eccentricity squared (NIMA TR8350.2, tables 3.1 and 3.3)
WGS84_A = 6378137.0
WGS84_E2 = 6.69437999014e-3
#: Somigliana's constants: equatorial normal gravity [m/s^2] and k (NIMA TR8350.2, table 3.4)
_GAMMA_E = 9.7803253359
_SOMIGLIANA_K = 1.931852652458e-3
#: free-air gradient of normal gravity [1/s^2] (NIMA TR8350.2, sec. 4.3, first order in h)
_FREE_AIR = 3.086e-6


def normal_gravity(latitude: float, height: float = 0.0) -> float:
    """gamma(phi, h) = gamma_e (1 + k sin^2 phi) / sqrt(1 - e^2 sin^2 phi) - 3.086e-6 h [m/s^2].

    Parameters
    ----------
    latitude : float
        Geodetic latitude phi [rad].
    height : float
        Height above the ellipsoid h [m].

    Returns
    -------
    float
        WGS84 normal gravity (NIMA TR8350.2 eq. 4-1, free-air term of sec. 4.3).

    Examples
    --------
    >>> round(normal_gravity(0.0), 7), round(normal_gravity(math.pi / 2), 7)
    (9.7803253, 9.8321849)
    """
    s2 = math.sin(latitude) ** 2
    return _GAMMA_E * (1 + _SOMIGLIANA_K * s2) / math.sqrt(1 - WGS84_E2 * s2) - _FREE_AIR * height


@dataclass(frozen=True, slots=True, kw_only=True)
class Site:
    """A location on the Earth: a laboratory, or where an IMU's motion starts.

    Parameters
    ----------
    name : str
        Label.
    latitude : float
        Geodetic latitude phi [rad], in [-pi/2, pi/2].
    source : str
        Where the latitude comes from.
    height : float
        Height above the WGS84 ellipsoid [m], within -1e4..1e5 m.
    earth_rotation : bool
        False switches the Earth's rate and the Coriolis and transport terms off (a
        non-rotating Earth) in :mod:`gyrobench.sim.trajectory`.
    """

    name: str = ""
    latitude: float = 0.0
    source: str = ""
    height: float = 0.0
    earth_rotation: bool = True

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "latitude": FieldRange(-math.pi / 2, math.pi / 2, "rad", "geodetic latitude, pole to pole"),
        "height": FieldRange(-1e4, 1e5, "m", "height above the ellipsoid: the deepest mine to the stratosphere"),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared specs above

    @property
    def gravity(self) -> float:
        """gamma(phi, h) [m/s^2] (:func:`normal_gravity`)."""
        return normal_gravity(self.latitude, self.height)

    @property
    def earth_rate_n(self) -> NDArray[np.float64]:
        """omega_ie^n = Omega_E [cos phi, 0, -sin phi] in north, east, down [rad/s] (zero without rotation)."""
        if not self.earth_rotation:
            return np.zeros(3)
        return EARTH_RATE * np.array([math.cos(self.latitude), 0.0, -math.sin(self.latitude)])

    def transport_rate_n(self, v_n: NDArray[np.float64]) -> NDArray[np.float64]:
        """omega_en^n = [v_E/(R_N + h), -v_N/(R_M + h), -v_E tan(phi)/(R_N + h)] for ``v_n`` (..., 3) [m/s].

        Parameters
        ----------
        v_n : ndarray, shape (..., 3)
            Velocity in north, east, down [m/s].

        Returns
        -------
        ndarray, shape (..., 3)
            The transport rate [rad/s] (Titterton & Weston 2004, eq. 3.55), with the WGS84
            radii of curvature R_M, R_N at the site.
        """
        if not self.earth_rotation:
            return np.zeros_like(v_n)
        if abs(self.latitude) >= math.pi / 2 - 1e-9:
            raise ValueError("the transport rate is not defined at a pole: Site.latitude must be inside +-pi/2")
        s2 = math.sin(self.latitude) ** 2
        r_n = WGS84_A / math.sqrt(1 - WGS84_E2 * s2) + self.height
        r_m = WGS84_A * (1 - WGS84_E2) / (1 - WGS84_E2 * s2) ** 1.5 + self.height
        out = np.empty_like(v_n)
        out[..., 0] = v_n[..., 1] / r_n
        out[..., 1] = -v_n[..., 0] / r_m
        out[..., 2] = -v_n[..., 1] * math.tan(self.latitude) / r_n
        return out


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
#: Sipailou campus ~32.06 N, approximate +-0.05 deg). The paper's Chinese text says Nanjing,
#: not Beijing.
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
    """Compute the north and up components of the Earth's rate at a latitude.

    north = Omega_E cos(phi), up = Omega_E sin(phi); the east component is 0
    (Omega_E = :data:`EARTH_RATE`, the sidereal rate).

    Parameters
    ----------
    latitude : array_like
        Geodetic latitude phi [rad].

    Returns
    -------
    north, up : ndarray
        The components [rad/s].

    Examples
    --------
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
