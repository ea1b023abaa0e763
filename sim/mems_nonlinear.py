"""Static rate transfers of a MEMS rate channel: the Duffing sense beam and a PHENOMENOLOGICAL amplifier curve.

The read-out of a high-range part from its physics (the biased sense electrodes, the pick-off's
1/(g - y), the front end's rail, with quadrature and manufacturing tolerances) is
:mod:`gyrobench.sim.mems_readout`; paper 001's default device uses it. This module keeps two
static, odd, strictly monotone, invertible rate transfers (docs/physics.md 5.2): the Duffing
sense mode in rate units (its harmonic balance is checked against a full integration of its
equation of motion, ``mems.sense_stiffening_full_ode``), and the Rapp amplifier curve, a FITTED
phenomenological shape with no read-out behind it (paper 001's labelled variant ``"rapp"``).
SI inside: rates in rad/s.

1. **Sense-beam stiffening (Duffing).** The sense mode, driven off resonance by the Coriolis
   force of a drive motion x = X0 cos(w t) (mode split, w_y > w),

       m y'' + c y' + k_y y + k3 y^3 = F cos(w t),   F = 2 m w X0 Omega   [N],

   has, to first harmonic balance (y = A cos(w t - phi)),

       A^2 [(dk + 3/4 k3 A^2)^2 + (c w)^2] = F^2,   dk = m (w_y^2 - w^2) > 0   [N/m].

   For k3 > 0 (hardening beams, e.g. doubly clamped flexures stretching) the left side grows
   strictly with A, so A(F) is single valued, monotone and compressive (no jump: the drive is
   far below the sense resonance). With the damping term neglected (c w << dk, i.e. the mode
   split is many sense bandwidths) and the normalisation v = A/A_c, u = Omega/Omega_d,

       v + v^3 = u,   A_c^2 = 4 dk / (3 k3),   Omega_d = dk A_c / (2 m w X0)   [rad/s],

   solved in closed form (Cardano, one real root), and the amplitude read out at the
   small-signal scale factor gives the rate Omega_d v(Omega / Omega_d) = Omega - Omega^3 /
   Omega_d^2 + O(Omega^5). References: Nayfeh & Mook, *Nonlinear Oscillations* (Wiley 1979),
   ch. 4 (Duffing, harmonic balance); Kaajakari et al., "Nonlinear limits for single-crystal
   silicon microresonators", J. Microelectromech. Syst. 13(5):715-724, 2004 (spring
   nonlinearity of MEMS resonators); Acar & Shkel, *MEMS Vibratory Gyroscopes* (Springer
   2009), ch. 2 (open-loop sense response to the Coriolis force).
2. **Amplifier-curve compression (Rapp; phenomenological).** A smooth compression of the
   shape of a solid-state amplifier's, with no sense chain behind it; the memoryless Rapp
   characteristic of solid-state amplifiers (C. Rapp, 1991; as given in Ghannouchi, Hammi &
   Helaoui, *Behavioral Modeling and Predistortion of Wideband Wireless Transmitters*, Wiley
   2015, eq. 4.45) in rate units:

       y = x / (1 + |x / Omega_s|^(2p))^(1/(2p)),   |y| < Omega_s,

   strictly increasing, with the explicit inverse x = y / (1 - |y / Omega_s|^(2p))^(1/(2p)),
   leading term x - x^(2p+1) / (2p Omega_s^(2p)); p sets how sharply it bends (p -> inf is a
   hard clip, which is never reached: |y| < Omega_s for every finite x).

The rate transfer is ``rapp(Omega_d v(Omega / Omega_d))``: small-signal scale factor 1, leading
cubic coefficient -1/Omega_d^2 (for p > 1), monotone over every rate. Either mechanism is
switched off with an infinite critical rate.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.base.ranges import Constraint, FieldRange, validate

__all__ = [
    "DuffingSense",
    "RateTransfer",
    "duffing_normalized",
    "rapp",
    "rapp_inverse",
]


def duffing_normalized(u: ArrayLike) -> NDArray[np.float64]:
    """The real root v of ``v + v^3 = u`` (Cardano; odd, strictly increasing, v ~ u - u^3).

    Parameters
    ----------
    u : array_like
        Normalised Coriolis force (rate / Omega_d) [-], finite.

    Returns
    -------
    numpy.ndarray
        Normalised sense amplitude v [-].
    """
    u = np.asarray(u, dtype=float)
    if not np.all(np.isfinite(u)):
        raise ValueError("duffing_normalized u must be finite; got a non-finite value")
    s = np.sqrt(0.25 * u * u + 1.0 / 27.0)
    # cbrt(u/2 + s) + cbrt(u/2 - s), written to avoid cancellation at small u:
    # cbrt(a) - cbrt(b) with a b = 1/27, so the second term is -1/(3 cbrt(a))
    a = np.cbrt(0.5 * np.abs(u) + s)
    v = np.sign(u) * (a - 1.0 / (3.0 * a))
    # the difference cancels at small |u| (absolute error ~1e-16): two Newton steps on
    # v + v^3 - u (derivative 1 + 3 v^2 >= 1) restore full relative precision
    for _ in range(2):
        v = v - (v + v**3 - u) / (1.0 + 3.0 * v * v)
    return v


def rapp(x: ArrayLike, saturation: float, order: float) -> NDArray[np.float64]:
    """Rapp compression ``x / (1 + |x/saturation|^(2 order))^(1/(2 order))`` (units of x).

    Parameters
    ----------
    x : array_like
        Input (any unit).
    saturation : float
        Saturation level s (units of x), > 0; inf passes x unchanged.
    order : float
        Smoothness p [-], >= 1 (large p approaches a hard clip).

    Returns
    -------
    ndarray
        The compressed values, |rapp(x)| < s (units of x).
    """
    _check_rapp(saturation, order)
    x = np.asarray(x, dtype=float)
    if math.isinf(saturation):
        return x.copy()
    r = np.abs(x / saturation) ** (2.0 * order)
    return x / (1.0 + r) ** (1.0 / (2.0 * order))


def rapp_inverse(y: ArrayLike, saturation: float, order: float) -> NDArray[np.float64]:
    """Inverse of :func:`rapp` for ``|y| < saturation``: ``y / (1 - |y/s|^(2p))^(1/(2p))``.

    Parameters
    ----------
    y : array_like
        Compressed values, |y| < saturation (units of the input).
    saturation : float
        Saturation level s, > 0.
    order : float
        Smoothness p [-], >= 1.

    Returns
    -------
    ndarray
        x with rapp(x) = y.
    """
    _check_rapp(saturation, order)
    y = np.asarray(y, dtype=float)
    if math.isinf(saturation):
        return y.copy()
    r = np.abs(y / saturation) ** (2.0 * order)
    if np.any(r >= 1.0):
        raise ValueError(
            f"rapp_inverse y must satisfy |y| < saturation = {saturation!r}; got max |y| {np.max(np.abs(y))!r}"
        )
    return y / (1.0 - r) ** (1.0 / (2.0 * order))


def _check_rapp(saturation: float, order: float) -> None:
    if not (saturation > 0):
        raise ValueError(f"rapp saturation must be > 0 (inf: off); got {saturation!r}")
    if not (math.isfinite(order) and order >= 1.0):
        raise ValueError(f"rapp order must be finite and >= 1; got {order!r}")


@dataclass(frozen=True, slots=True, kw_only=True)
class DuffingSense:
    """An open-loop sense mode with cubic (hardening) stiffness, driven by the Coriolis force.

    Parameters
    ----------
    mass : float
        Modal (= Coriolis) mass m [kg].
    drive_omega, sense_omega : float
        Drive frequency w and sense natural frequency w_y [rad/s], w_y > w (mode split).
    sense_q : float
        Sense quality factor Q_y [-] (c = m w_y / Q_y).
    k3 : float
        Cubic stiffness [N/m^3], >= 0.
    drive_amplitude : float
        X0 [m].
    """

    mass: float
    drive_omega: float
    sense_omega: float
    sense_q: float
    k3: float
    drive_amplitude: float

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "mass": FieldRange(0, math.inf, "kg", "modal (Coriolis) mass m", low_open=True),
        "drive_omega": FieldRange(0, math.inf, "rad/s", "drive frequency w", low_open=True),
        "sense_omega": FieldRange(0, math.inf, "rad/s", "sense natural frequency w_y (> w: constraint)", low_open=True),
        "sense_q": FieldRange(0, math.inf, "1", "sense quality factor Q_y", low_open=True),
        "k3": FieldRange(0, math.inf, "N/m^3", "cubic (hardening) stiffness, >= 0"),
        "drive_amplitude": FieldRange(0, math.inf, "m", "drive amplitude X0", low_open=True),
    }
    #: the sense mode sits above the drive (a positive detuning stiffness)
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "sense_omega > drive_omega",
            lambda c: c.sense_omega > c.drive_omega,
            lambda c: f"sense_omega must exceed drive_omega = {c.drive_omega!r} rad/s; got {c.sense_omega!r}",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above

    @property
    def detuning_stiffness(self) -> float:
        """dk = m (w_y^2 - w^2) [N/m]."""
        return self.mass * (self.sense_omega**2 - self.drive_omega**2)

    @property
    def damping(self) -> float:
        """c = m w_y / Q_y [kg/s]."""
        return self.mass * self.sense_omega / self.sense_q

    def coriolis_force(self, rate: ArrayLike) -> NDArray[np.float64]:
        """F = 2 m w X0 Omega [N] for rates Omega [rad/s]."""
        return 2.0 * self.mass * self.drive_omega * self.drive_amplitude * np.asarray(rate, dtype=float)

    @property
    def critical_rate(self) -> float:
        """Omega_d = dk A_c / (2 m w X0) [rad/s] with A_c^2 = 4 dk / (3 k3) (inf when k3 = 0)."""
        if self.k3 == 0:
            return math.inf
        a_c = math.sqrt(4.0 * self.detuning_stiffness / (3.0 * self.k3))
        return self.detuning_stiffness * a_c / (2.0 * self.mass * self.drive_omega * self.drive_amplitude)

    def amplitude(self, rate: ArrayLike) -> NDArray[np.float64]:
        """Signed first-harmonic amplitude A [m] with damping, from the harmonic-balance equation.

        Solves ``A^2 [(dk + 3/4 k3 A^2)^2 + (c w)^2] = F^2`` (monotone in A^2) by Newton's method
        on A from the undamped closed form; ``sign(A) = sign(Omega)``.
        """
        f = np.abs(self.coriolis_force(rate))
        dk, cw = self.detuning_stiffness, self.damping * self.drive_omega
        k = 0.75 * self.k3
        # start: the undamped root scaled down by the damping's small-signal factor
        if self.k3 > 0:
            a_c = math.sqrt(dk / k)
            a = a_c * duffing_normalized(f / (dk * a_c)) * dk / math.hypot(dk, cw)
        else:
            a = f / math.hypot(dk, cw)
        for _ in range(50):
            g = dk + k * a * a
            h = a * a * (g * g + cw * cw) - f * f
            dh = 2.0 * a * (g * g + cw * cw) + a * a * 2.0 * g * 2.0 * k * a
            step = np.where(dh > 0, h / np.where(dh > 0, dh, 1.0), 0.0)
            a = a - step
            if np.all(np.abs(step) <= 1e-15 * np.maximum(np.abs(a), 1e-300)):
                break
        return np.sign(np.asarray(rate, dtype=float)) * a


@dataclass(frozen=True, slots=True, kw_only=True)
class RateTransfer:
    """The composed rate transfer ``rapp(Omega_d v(Omega / Omega_d); Omega_s, p)`` [rad/s -> rad/s].

    Parameters
    ----------
    duffing_rate : float
        Omega_d [rad/s] (:attr:`DuffingSense.critical_rate`), > 0; inf switches it off.
    rail_rate : float
        Omega_s, the front end's saturation in rate units [rad/s], > 0; inf switches it off.
    rail_order : float
        Rapp smoothness p [-], >= 1.
    """

    duffing_rate: float = math.inf
    rail_rate: float = math.inf
    rail_order: float = 2.0

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "duffing_rate": FieldRange(0, math.inf, "rad/s", "Duffing critical rate; inf: off", True, infinite=True),
        "rail_rate": FieldRange(0, math.inf, "rad/s", "front-end saturation Omega_s; inf: off", True, infinite=True),
        "rail_order": FieldRange(1, math.inf, "1", "Rapp smoothness p, >= 1"),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared specs above

    @property
    def is_linear(self) -> bool:
        """True when both mechanisms are off (the identity)."""
        return math.isinf(self.duffing_rate) and math.isinf(self.rail_rate)

    @property
    def cubic_coefficient(self) -> float:
        """Leading cubic coefficient a3 of ``y = Omega + a3 Omega^3 + ...`` [s^2/rad^2]."""
        a3 = 0.0 if math.isinf(self.duffing_rate) else -1.0 / self.duffing_rate**2
        if self.rail_order == 1.0 and not math.isinf(self.rail_rate):
            a3 -= 0.5 / self.rail_rate**2
        return a3

    def __call__(self, rate: ArrayLike) -> NDArray[np.float64]:
        """Output rate [rad/s] for sensed rates ``rate`` [rad/s] (finite)."""
        w = np.asarray(rate, dtype=float)
        if not math.isinf(self.duffing_rate):
            w = self.duffing_rate * duffing_normalized(w / self.duffing_rate)
        return rapp(w, self.rail_rate, self.rail_order)

    def inverse(self, output: ArrayLike) -> NDArray[np.float64]:
        """The sensed rate [rad/s] giving ``output`` (|output| below the rail rate)."""
        v = rapp_inverse(output, self.rail_rate, self.rail_order)
        if math.isinf(self.duffing_rate):
            return v
        x = v / self.duffing_rate
        return self.duffing_rate * (x + x**3)
