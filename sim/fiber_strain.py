"""Vibration of a FOG from mechanics: shaker -> structural mode -> strain along the fibre -> phase.

All SI: acceleration [m/s^2], strain [-], phase [rad], rate [rad/s], z along the fibre [m].

Time-varying nonreciprocity (docs/physics.md 4.1, derived there): a change db(z, t) of the
propagation constant per unit length is crossed at t - z/v by the wave that entered at z = L
and at t - (L - z)/v by the wave that entered at z = 0 (v = c/n_g, both detected at t); their
phase difference (the former minus the latter, the orientation used throughout) is

    dphi(t) = int_0^L [db(z, t - z/v) - db(z, t - (L - z)/v)] dz
    harmonic db = B(z) e^{jwt}:  dphi = 2j e^{-jw tau/2} int_0^L B(z) sin(a (L - 2z)) dz,
                                 a = w/(2v), tau = L/v                       (exact)
    w tau << 1:                  dphi ~ (1/v) int_0^L d(db)/dt (L - 2z) dz

Exact kernel: dphi = (jw/v) e^{-jw tau/2} W(w) B-amplitude, with the frequency-dependent weight

    W(w) = (1/a) int_0^L psi(z) sin(a (L - 2z)) dz -> W = int psi (L - 2z) dz as a -> 0  [m^2]

closed forms (:func:`segment_kernel`, :func:`linear_kernel`): a segment [z0, z1] gives
(cos(a (L - 2 z1)) - cos(a (L - 2 z0)))/(2 a^2); psi = z/L gives
-L^2 (sin x - x cos x)/(2 x^3), x = a L (docs/physics.md 4.1). The factor e^{-jw tau/2} (a
delay of half a transit) is exact for every shape; the remaining small-tau error is
|W(w) - W| <= (a L)^2/6 int |psi| |L - 2z| dz (sin x/x = 1 - x^2/6 + ..., |x| <= a L),
relative to W at most (w tau/2)^2/6 for a shape of one sign of (L - 2z) (6e-5 at 1.2 kHz,
1 km).

Axial strain eps changes the optical path per unit length by n xi eps (xi = 1 -
(n^2/2)[p12 - nu (p11 + p12)] = 0.788 for fused silica: p11 = 0.121, p12 = 0.270, nu = 0.17,
n = 1.444, the phase index of fused silica at 1550 nm, Malitson, JOSA 55, 1205 (1965)), so
db = k0 n xi eps and, divided by SF = 2 pi L D/(lambda c), the rate-equivalent error is

    Omega_eps(t) = (n_g n xi / (L D)) int_0^L eps_dot(z, t) (L - 2z) dz                 [rad/s]

It follows the strain RATE: a harmonic strain at w gives an error proportional to w, 90 deg
ahead of the strain (less the half-transit delay w tau/2), zero-mean at first order.

Structural mode k (base excitation by the table acceleration a, unit static gain):

    x_k = H_k a,   H_k(s) = w_k^2 / (s^2 + s w_k/Q_k + w_k^2)                    [m/s^2]
    eps(z, t) = kappa_k psi_k(z) x_k(t)           (kappa_k: strain per m/s^2, psi_k: shape)
    Omega_eps,k = (n_g n xi / (L D)) kappa_k W_k dx_k/dt,   W_k = int psi_k (L - 2z) dz   [m^2]
    rocking about the sense axis: Omega_rock,k = theta_k dx_k/dt       (true rate, theta_k
                                                                          rad per m/s^2)
    loss modulation (pigtail microbending): m(t) = sum_k mu_k x_k        [-]

Weights (closed forms, tests): psi uniform -> W = 0; psi = z/L -> W = -L^2/6; a segment
[z0, z0 + l] -> W = l (L - 2 z0 - l).

References
----------
docs/physics.md 4.1 (kernel derived there); Lefevre, The Fiber-Optic Gyroscope, 2nd ed.
(2014), sec. 3.2 (reciprocity and time-varying perturbations: the (L - 2z) weighting shared with
the Shupe effect); Shupe, Appl. Opt. 19(5) 654 (1980); elasto-optic factor: Bertholds &
Dandliker, J. Lightwave Technol. 6(1) 17 (1988) (strain sensitivity of optical fibres).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from numbers import Real
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.base.ranges import Constraint, FieldRange, validate

__all__ = [
    "ELASTO_OPTIC_FACTOR",
    "elasto_optic_factor",
    "segment_weight",
    "shape_weight",
    "strain_rate_coefficient",
    "exact_strain_phase",
    "segment_kernel",
    "linear_kernel",
    "StrainMode",
]


def elasto_optic_factor(n: float, p11: float, p12: float, poisson: float) -> float:
    """xi = 1 - (n^2/2) [p12 - nu (p11 + p12)]: phase change per unit axial strain over n (docs/physics.md 3.5)."""
    return 1.0 - 0.5 * n * n * (p12 - poisson * (p11 + p12))


#: xi = 1 - (n^2/2)[p12 - nu (p11 + p12)] for fused silica at n = 1.444 (p11 = 0.121,
#: p12 = 0.270, nu = 0.17; docs/physics.md 4.1): 0.788 [-]
ELASTO_OPTIC_FACTOR = elasto_optic_factor(1.444, 0.121, 0.270, 0.17)


def segment_weight(z0: float, length: float, fibre_length: float) -> float:
    """W = int_{z0}^{z0+l} (L - 2z) dz = l (L - 2 z0 - l) [m^2] for a uniformly strained segment."""
    if not (0.0 <= z0 and length > 0 and z0 + length <= fibre_length * (1 + 1e-12)):
        raise ValueError(
            f"segment [z0, z0 + length] must lie in [0, {fibre_length!r}] m; got z0={z0!r}, "
            f"length={length!r}"
        )
    return length * (fibre_length - 2.0 * z0 - length)


def shape_weight(
    shape: Callable[[NDArray[np.float64]], NDArray[np.float64]],
    fibre_length: float,
    *,
    n: int = 200001,
) -> float:
    """W = int_0^L psi(z) (L - 2z) dz [m^2] (composite Simpson rule on n points, n odd)."""
    from scipy.integrate import simpson

    if n < 3 or n % 2 == 0:
        raise ValueError(f"n must be an odd integer >= 3; got {n!r}")
    z = np.linspace(0.0, fibre_length, n)
    return float(simpson(np.asarray(shape(z), dtype=float) * (fibre_length - 2.0 * z), x=z))


def strain_rate_coefficient(
    length: float,
    diameter: float,
    group_index: float,
    index: float = 1.444,
    xi: float = ELASTO_OPTIC_FACTOR,
) -> float:
    """K = n_g n xi / (L D) [1/m^2]: Omega_eps = K int eps_dot (L - 2z) dz."""
    return group_index * index * xi / (length * diameter)


def exact_strain_phase(
    strain: Callable[[NDArray[np.float64], NDArray[np.float64]], NDArray[np.float64]],
    t: ArrayLike,
    *,
    length: float,
    wavelength: float,
    group_index: float,
    index: float = 1.444,
    xi: float = ELASTO_OPTIC_FACTOR,
    nz: int = 4001,
) -> NDArray[np.float64]:
    """Phase difference [rad] by the two-crossing-time integral, no small-tau approximation.

    dphi(t) = k0 n xi int_0^L [eps(z, t - z/v) - eps(z, t - (L - z)/v)] dz (Simpson in z),
    with ``strain(z, t)`` evaluated on broadcast arrays (z column, t row) (the wave entered
    at L minus the wave entered at 0: small-tau limit +(k0 n xi/v) int eps_dot (L - 2z) dz).
    """
    from scipy.integrate import simpson

    from gyrobench.sim.fog_optics import SPEED_OF_LIGHT

    v = SPEED_OF_LIGHT / group_index
    k0 = 2.0 * math.pi / wavelength
    z = np.linspace(0.0, length, nz)[:, None]
    tt = np.atleast_1d(np.asarray(t, dtype=float))[None, :]
    diff = strain(z, tt - z / v) - strain(z, tt - (length - z) / v)
    return k0 * index * xi * np.asarray(simpson(diff, x=z[:, 0], axis=0), dtype=float)


def _wavenumber(f: ArrayLike, group_index: float) -> NDArray[np.float64]:
    """a = w/(2v) = pi f n_g / c [1/m]."""
    from gyrobench.sim.fog_optics import SPEED_OF_LIGHT

    return np.pi * np.asarray(f, dtype=float) * group_index / SPEED_OF_LIGHT


def _half_transit(f: ArrayLike, fibre_length: float, group_index: float) -> NDArray[np.complex128]:
    """e^{-j w tau/2}, tau = n_g L / c."""
    return np.exp(-1j * _wavenumber(f, group_index) * fibre_length)


def segment_kernel(
    z0: float, length: float, fibre_length: float, f: ArrayLike, group_index: float
) -> NDArray[np.complex128]:
    """Exact weight e^{-jw tau/2} W(w) [m^2] of a uniform strain over [z0, z0 + l] at ``f`` [Hz].

    W(w) = (cos(a (L - 2 z1)) - cos(a (L - 2 z0)))/(2 a^2), z1 = z0 + l, a = pi f n_g/c;
    -> l (L - 2 z0 - l) (:func:`segment_weight`) as f -> 0 (evaluated by a series there).
    """
    w0 = segment_weight(z0, length, fibre_length)
    a = _wavenumber(f, group_index)
    u0, u1 = fibre_length - 2.0 * z0, fibre_length - 2.0 * (z0 + length)
    big = a > 0.0  # the product form has no cancellation; a = 0 takes the limit
    with np.errstate(divide="ignore", invalid="ignore"):
        # cos A - cos B = -2 sin((A + B)/2) sin((A - B)/2): no cancellation at small a
        exact = -np.sin(a * (u1 + u0) / 2) * np.sin(a * (u1 - u0) / 2) / a**2
    # series: sin x sin y/a^2 = (u1+u0)(u1-u0)/4 (1 - a^2 ((u1+u0)^2 + (u1-u0)^2)/24)
    series = w0 * (1.0 - a**2 * ((u1 + u0) ** 2 + (u1 - u0) ** 2) / 24.0)
    return np.where(big, exact, series) * _half_transit(f, fibre_length, group_index)


def linear_kernel(fibre_length: float, f: ArrayLike, group_index: float) -> NDArray[np.complex128]:
    """Exact weight e^{-jw tau/2} W(w) [m^2] of the shape psi = z/L at ``f`` [Hz].

    W(w) = -L^2 (sin x - x cos x)/(2 x^3), x = a L; below x = 0.1 its series
    -L^2/6 (1 - x^2/10 + x^4/280) (next term x^6/15120 < 1e-10 there; the closed form would
    lose digits to cancellation).
    """
    L = fibre_length
    x = _wavenumber(f, group_index) * L
    big = x > 0.1
    with np.errstate(divide="ignore", invalid="ignore"):
        exact = -(L**2) * (np.sin(x) - x * np.cos(x)) / (2.0 * x**3)
    series = -(L**2) / 6.0 * (1.0 - x**2 / 10.0 + x**4 / 280.0)
    return np.where(big, exact, series) * _half_transit(f, fibre_length, group_index)


def _real(owner: str, name: str, v: object, unit: str, *, positive: bool = False) -> float:
    if isinstance(v, bool) or not isinstance(v, Real):
        raise TypeError(f"{owner}.{name} must be a real number [{unit}]; got {v!r}")
    x = float(v)
    if not math.isfinite(x) or (positive and x <= 0):
        raise ValueError(
            f"{owner}.{name} must be finite{' and > 0' if positive else ''} [{unit}]; got {v!r}"
        )
    return x


@dataclass(frozen=True, slots=True, kw_only=True)
class StrainMode:
    """One structural mode and how it reaches the interferometer.

    Parameters
    ----------
    frequency : float
        f_k [Hz].
    quality : float
        Q_k [-], > 0.5.
    strain : float
        kappa_k: fibre strain amplitude per unit modal acceleration [1/(m/s^2)].
    weight : float
        W_k = int psi_k(z) (L - 2z) dz [m^2] of the mode's strain shape along the fibre.
    rocking : float
        theta_k: rotation about the sense axis per unit modal acceleration [rad/(m/s^2)].
    loss : float
        mu_k: relative detected-power modulation per unit modal acceleration [1/(m/s^2)].
    segment : (float, float) or None
        (z0, l) [m]: the mode strains the fibre uniformly over [z0, z0 + l] (``weight`` must
        then be l (L - 2 z0 - l) for the coil it is used on); the strain term then uses the
        exact transit-time kernel (:func:`segment_kernel`). None: only W is known, and the
        kernel is W e^{-jw tau/2} (delay exact, amplitude to the bound in the module notes).
    """

    frequency: float
    quality: float
    strain: float = 0.0
    weight: float = 0.0
    rocking: float = 0.0
    loss: float = 0.0
    segment: tuple[float, float] | None = None

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "frequency": FieldRange(0, math.inf, "Hz", "the mode's resonance f_k", low_open=True),
        "quality": FieldRange(0.5, math.inf, "1", "quality factor Q_k; > 0.5, an underdamped mode", low_open=True),
        "strain": FieldRange(-math.inf, math.inf, "1/(m/s^2)", "fibre strain amplitude per modal acceleration"),
        "weight": FieldRange(-math.inf, math.inf, "m^2", "the (L - 2z) weighted strain integral W_k"),
        "rocking": FieldRange(-math.inf, math.inf, "rad/(m/s^2)", "sense-axis rotation per modal acceleration"),
        "loss": FieldRange(-math.inf, math.inf, "1/(m/s^2)", "detected-power modulation per modal acceleration"),
        "segment": FieldRange(0, math.inf, "m", "(z0, l): the uniformly strained stretch of fibre"),
    }
    #: the constraints across fields (:class:`~gyrobench.base.ranges.Constraint`)
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "segment is None or (z0, l) with l > 0",
            lambda c: c.segment is None or (isinstance(c.segment, tuple) and len(c.segment) == 2 and c.segment[1] > 0),
            lambda c: f"segment must be a (z0, l) tuple [m] with l > 0; got {c.segment!r}",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above

    def kernel(
        self, f: ArrayLike, fibre_length: float, group_index: float
    ) -> NDArray[np.complex128]:
        """e^{-jw tau/2} W(w) [m^2] at ``f`` [Hz]: exact for a ``segment``, else W e^{-jw tau/2}.

        Raises ValueError when ``segment`` and ``weight`` disagree (relative 1e-9) for this L.
        """
        if self.segment is None:
            return self.weight * _half_transit(f, fibre_length, group_index)
        z0, ln = self.segment
        w0 = segment_weight(z0, ln, fibre_length)
        if abs(w0 - self.weight) > 1e-9 * max(abs(w0), 1e-300):
            raise ValueError(
                f"StrainMode.weight must equal l (L - 2 z0 - l) = {w0!r} m^2 for its segment "
                f"on a {fibre_length!r} m coil; got {self.weight!r}"
            )
        return segment_kernel(z0, ln, fibre_length, f, group_index)

    def response(self, f: ArrayLike) -> NDArray[np.complex128]:
        """H_k(j 2 pi f) = 1/(1 - r^2 + j r/Q), r = f/f_k."""
        r = np.asarray(f, dtype=float) / self.frequency
        return np.asarray(1.0 / (1.0 - r**2 + 1j * r / self.quality), dtype=np.complex128)
