"""Ring laser gyro: geometry, lock-in, dither, pulse counting, two-node thermal model, thermal bias.

All parameters are in SI: angles [rad], rates [rad/s], time [s], temperature [K],
lengths [m]. Field units appear only in :func:`RLGSpec.from_datasheet`.

The model, effect by effect (docs/physics.md section 6):

* **Scale factor and pulse weight** from the cavity geometry (:class:`CavityGeometry`):
  K = 4 A / (lambda P) [beat cycles per rad], pulse weight q = 1/K [rad per count]
  (Aronowitz, "The laser gyro", in Laser Applications vol. 1, 1971).
* **Lock-in** by the Adler equation for the beat phase psi [rad],
  d psi/dt = 2 pi K (Omega - Omega_L sin psi); integrated by :func:`integrate_adler`
  (fixed-step RK4, used by tests and short records only). Below lock-in the phase
  locks (no pulses); above, the mean beat is K sqrt(Omega^2 - Omega_L^2).
* **Mechanical dither** theta_d = theta_D a_m sin(2 pi f_d t) with a random amplitude
  factor a_m = 1 + sigma eps_m drawn per dither cycle (:class:`Dither`). Each rate
  reversal passes through lock-in and leaves a random angle error; the result is a
  random walk of coefficient N = Omega_L / sqrt(2 pi K Omega_D) [rad/sqrt(s)]
  (docs/physics.md 6.3, stationary-phase analysis; verified against the integration in
  tests/sim/test_rlg.py).
* **Pulse counting** c_k = floor((theta_k + theta_d,k)/q): the output is counts, the
  dither angle is stripped after counting, so quantization comes from counting
  (white angle noise of std q/sqrt(12) once the dither randomizes the angle across q).
* **Fast statistical mode** (:meth:`RLGUnit.simulate`) for long records: true angle =
  integral of (input + bias + flicker/RRW) + a random walk of coefficient N_dither,
  then counted and stripped as above. It assumes a randomized dither: the dynamic
  lock-in bands of an unrandomized dither (K Omega = integer x f_d) and the lock-in
  scale-factor nonlinearity are not in this mode (use :func:`integrate_adler`).
* **Two-node thermal model** (:func:`two_node_temperatures`): housing T1 driven by the
  chamber, cavity T2 driven by the housing, each first order, with self-heating
  from power-on.
* **Thermal bias** from physical mechanisms (:class:`ThermalBias`): cavity temperature
  (mirror backscatter / Fresnel drag), the housing-cavity gradient that unbalances the
  two discharge legs (Langmuir gas flow; its coefficient depends on gas temperature),
  and the heat flux entering the housing during a temperature change (gas-flow
  transient, with a quadratic part).
* **Temperature sensors** with offset, white noise and resolution (:class:`TemperatureSensor`).

Unit-to-unit variation: :class:`RLGSpec` is the datasheet budget with the spread of
every parameter; ``spec.realize(rng=rng)`` draws one unit (:class:`RLGUnit`), so three drawn
gyros differ as three real ones would. Turn-on to turn-on variation (bias repeatability
and the discharge-current balance set at each start) is drawn in each ``simulate``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import signal

from gyrobench.base import units
from gyrobench.base.ranges import Constraint, FieldRange, as_array, shown, validate
from gyrobench.base.validate import nonneg_field as _nonneg
from gyrobench.io.recording import Channel, Recording
from gyrobench.sim._rlg_common import (
    DITHER_LOCK_IN_MARGIN,
    _CavityScale,
    _chamber_samples,
    _check_rng,
    _finish_run,
    _num,
    _pos,
    _sensor_pair,
    _start_run,
    _Terms,
    _Wording,
    dither_margin,
)
from gyrobench.sim.noise import NoiseModel
from gyrobench.sim.rlg_vibration import DitherMount

__all__ = [
    "HENE_WAVELENGTH",
    "DITHER_LOCK_IN_MARGIN",
    "CavityGeometry",
    "beat_frequency",
    "integrate_adler",
    "count_pulses",
    "Dither",
    "DitherRealization",
    "dither_arw",
    "TwoNodeThermal",
    "two_node_temperatures",
    "ThermalBias",
    "THERMAL_BIAS_CALIBRATED",
    "TemperatureSensor",
    "RLGSpec",
    "RLGUnit",
]

#: He-Ne laser wavelength [m]
HENE_WAVELENGTH = 632.8e-9
# DITHER_LOCK_IN_MARGIN (imported above) lives in gyrobench.sim._rlg_common, shared with rlg_cavity


# ============================================================================ geometry
def _is_pairs(v: object) -> bool:
    """Whether ``v`` is a float array of (x, y) rows."""
    return isinstance(v, np.ndarray) and v.ndim == 2 and v.shape[1] == 2


def _pairs(v: Any) -> tuple[tuple[float, float], ...]:
    """The validated mirror positions as a tuple of float pairs, in path order."""
    return tuple((float(x), float(y)) for x, y in v)


@dataclass(frozen=True, slots=True, kw_only=True)
class CavityGeometry:
    """Closed polygonal laser cavity in a plane; the beam path joins the mirrors in order.

    Parameters
    ----------
    vertices : tuple of (x, y)
        Mirror positions [m], at least 3, in path order.
    wavelength : float
        Laser wavelength lambda [m]; He-Ne 632.8 nm by default.

    Notes
    -----
    Enclosed area A by the shoelace formula (absolute value), path length P = sum of
    the sides. Sagnac beat (docs/physics.md 6.1):

        Delta nu = K Omega,   K = 4 A / (lambda P)   [cycles/rad]
        pulse weight q = 1/K = lambda P / (4 A)       [rad/count]
        quantization coefficient Q = q / sqrt(12)    [rad]

    Equilateral triangle of side s: K = s/(sqrt(3) lambda); square: K = s/lambda.

    Raises
    ------
    ValueError
        If the enclosed area is not > 0 m^2 (e.g. collinear mirrors) or lambda <= 0.

    Examples
    --------
    >>> g = CavityGeometry.triangle(0.10)
    >>> round(g.scale_factor), round(units.to_arcsec(g.pulse_weight), 3)
    (91237, 2.261)
    """

    vertices: tuple[tuple[float, float], ...]
    wavelength: float = HENE_WAVELENGTH

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "wavelength": FieldRange(0, math.inf, "m", "laser wavelength (He-Ne 632.8 nm)", low_open=True),
    }
    #: the mirrors enclose an area (not collinear)
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "vertices is a sequence of (x, y) pairs",
            lambda c: isinstance(c.vertices, np.ndarray),
            lambda c: f"vertices must be a sequence of (x, y) pairs [m]; got {shown(c.vertices)}",
            TypeError,
        ),
        Constraint(
            ">= 3 vertices",
            lambda c: _is_pairs(c.vertices) and c.vertices.shape[0] >= 3,
            lambda c: f"vertices must hold >= 3 (x, y) pairs [m]; got shape {c.vertices.shape}",
        ),
        Constraint(
            "vertices finite",
            lambda c: bool(np.all(np.isfinite(c.vertices))),
            lambda c: f"vertices must be finite [m]; got {_pairs(c.vertices)!r}",
        ),
        Constraint(
            "area > 0 m^2",
            lambda c: c.area > 1e-30,
            lambda c: f"area must be > 0 m^2 (mirrors not collinear); got {c.area!r} m^2",
        ),
    )

    def __post_init__(self) -> None:
        object.__setattr__(self, "vertices", as_array(self.vertices))
        validate(self)  # the declared specs and constraints above
        object.__setattr__(self, "vertices", _pairs(self.vertices))

    @classmethod
    def triangle(cls, side: float, *, wavelength: float = HENE_WAVELENGTH) -> CavityGeometry:
        """Equilateral triangle of side ``side`` [m]."""
        s = _num("CavityGeometry.triangle", "side", side)
        if s <= 0:
            raise ValueError(
                f"CavityGeometry area must be > 0 m^2: triangle side must be > 0 m; got {side!r}"
            )
        return cls(
            vertices=((0.0, 0.0), (s, 0.0), (s / 2.0, s * math.sqrt(3.0) / 2.0)),
            wavelength=wavelength,
        )

    @classmethod
    def square(cls, side: float, *, wavelength: float = HENE_WAVELENGTH) -> CavityGeometry:
        """Square of side ``side`` [m]."""
        s = _num("CavityGeometry.square", "side", side)
        if s <= 0:
            raise ValueError(
                f"CavityGeometry area must be > 0 m^2: square side must be > 0 m; got {side!r}"
            )
        return cls(vertices=((0.0, 0.0), (s, 0.0), (s, s), (0.0, s)), wavelength=wavelength)

    @property
    def area(self) -> float:
        """Enclosed area A [m^2] (shoelace)."""
        v = np.asarray(self.vertices)
        x, y = v[:, 0], v[:, 1]
        return float(abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))) / 2.0)

    @property
    def perimeter(self) -> float:
        """Optical path length P [m]."""
        v = np.asarray(self.vertices)
        return float(np.sum(np.hypot(*(np.roll(v, -1, axis=0) - v).T)))

    @property
    def scale_factor(self) -> float:
        """K = 4A/(lambda P) [beat cycles (counts) per rad]."""
        return 4.0 * self.area / (self.wavelength * self.perimeter)

    @property
    def pulse_weight(self) -> float:
        """q = lambda P/(4A) [rad per count]."""
        return 1.0 / self.scale_factor

    @property
    def quantization(self) -> float:
        """IEEE quantization coefficient Q = q/sqrt(12) [rad] (white-angle model, valid with dither)."""
        return self.pulse_weight / math.sqrt(12.0)


# ============================================================================ lock-in (Adler)
def beat_frequency(
    rate: ArrayLike, *, scale_factor: float, lock_in_rate: float
) -> NDArray[np.float64]:
    """Mean beat frequency of the Adler equation at a constant input rate [Hz].

    Parameters
    ----------
    rate : array_like
        Input rate Omega [rad/s].
    scale_factor : float
        K [counts/rad], > 0.
    lock_in_rate : float
        Omega_L [rad/s], >= 0.

    Returns
    -------
    ndarray
        f_beat [Hz], signed.

    Notes
    -----
    For d psi/dt = 2 pi K (Omega - Omega_L sin psi) and |Omega| > Omega_L the phase
    slips with period 1/(K sqrt(Omega^2 - Omega_L^2)), so

        f_beat = K sign(Omega) sqrt(Omega^2 - Omega_L^2),   0 for |Omega| <= Omega_L.
    """
    w = np.asarray(rate, dtype=float)
    k = _pos("beat_frequency", "scale_factor", scale_factor, "counts/rad")
    wl = _nonneg("beat_frequency", "lock_in_rate", lock_in_rate, "rad/s")
    return k * np.sign(w) * np.sqrt(np.maximum(w * w - wl * wl, 0.0))


def integrate_adler(
    rate: Callable[[float], ArrayLike],
    duration: float,
    *,
    scale_factor: float,
    lock_in_rate: float | ArrayLike,
    dt: float,
    psi0: ArrayLike = 0.0,
    sample_every: int = 1,
) -> NDArray[np.float64]:
    """Integrate the Adler equation for the beat phase by fixed-step RK4.

    Parameters
    ----------
    rate : callable t -> array
        Input (body) rate Omega(t) [rad/s] including any dither; may return an array
        (one value per realization, broadcast against ``psi0``).
    duration : float
        Integration time [s]; rounded to a whole number of steps.
    scale_factor : float
        K [counts/rad].
    lock_in_rate : float or array
        Omega_L [rad/s] (per realization if an array).
    dt : float
        Step [s]. It must resolve the fastest beat: choose dt <= 1/(16 K max|Omega|)
        (RK4 phase error per beat cycle ~ (2 pi K |Omega| dt)^5 / 120).
    psi0 : float or array
        Initial phase [rad]; an array integrates many realizations at once.
    sample_every : int
        Return psi every this many steps.

    Returns
    -------
    ndarray, shape (n_steps // sample_every + 1, *psi0.shape)
        psi [rad] at t = 0, sample_every dt, ...

    Notes
    -----
    d psi/dt = 2 pi K (Omega(t) - Omega_L sin psi)  (Adler 1946; docs/physics.md 6.2).
    The number of laser pulses counted up to t is floor(psi(t)/(2 pi)) (:func:`count_pulses`).
    """
    k = _pos("integrate_adler", "scale_factor", scale_factor, "counts/rad")
    h = _pos("integrate_adler", "dt", dt, "s")
    dur = _pos("integrate_adler", "duration", duration, "s")
    if not (isinstance(sample_every, (int, np.integer)) and sample_every >= 1):
        raise ValueError(f"sample_every must be an integer >= 1; got {sample_every!r}")
    wl = np.asarray(lock_in_rate, dtype=float)
    if np.any(~np.isfinite(wl)) or np.any(wl < 0):
        raise ValueError(f"lock_in_rate must be finite and >= 0 rad/s; got {lock_in_rate!r}")
    n_steps = int(round(dur / h))
    psi = np.array(
        np.broadcast_to(
            np.asarray(psi0, dtype=float), np.broadcast_shapes(np.shape(psi0), wl.shape)
        )
    )
    two_pi_k = 2.0 * math.pi * k

    def f(t: float, p: NDArray[np.float64]) -> NDArray[np.float64]:
        return two_pi_k * (np.asarray(rate(t), dtype=float) - wl * np.sin(p))

    out = np.empty((n_steps // sample_every + 1, *psi.shape))
    out[0] = psi
    j = 1
    for i in range(n_steps):
        t = i * h
        k1 = f(t, psi)
        k2 = f(t + h / 2, psi + (h / 2) * k1)
        k3 = f(t + h / 2, psi + (h / 2) * k2)
        k4 = f(t + h, psi + h * k3)
        psi = psi + (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
        if (i + 1) % sample_every == 0:
            out[j] = psi
            j += 1
    return out


def count_pulses(psi: ArrayLike) -> NDArray[np.float64]:
    """Pulses counted in each interval between successive phase samples.

    Parameters
    ----------
    psi : array_like
        Beat phase at successive samples [rad].

    Returns
    -------
    ndarray
        Signed pulse counts per interval (one fewer than the samples).

    Notes
    -----
    A counter advances by one at each 2 pi of beat phase: c_k = floor(psi_k / 2 pi);
    the output is c_k - c_{k-1} (signed, up/down counter).
    """
    c = np.floor(np.asarray(psi, dtype=float) / (2.0 * math.pi))
    return np.diff(c, axis=0)


# ============================================================================ dither
@dataclass(frozen=True, slots=True, kw_only=True)
class Dither:
    """Mechanical body dither with a random amplitude.

    Parameters
    ----------
    frequency : float
        f_d [Hz].
    amplitude : float
        Nominal peak dither angle theta_D [rad].
    amplitude_jitter : float
        Relative std sigma of the per-cycle amplitude factor a_m = 1 + sigma eps_m
        (amplitude noise injected to break dynamic lock-in), in [0, 0.3].

    Notes
    -----
    theta_d(t) = theta_D a_m sin(2 pi f_d t) for t in [m/f_d, (m+1)/f_d): the amplitude
    changes where the angle crosses zero, so the angle is continuous; the rate
    Omega_d = 2 pi f_d theta_D a_m cos(2 pi f_d t) has peak Omega_D = 2 pi f_d theta_D.
    """

    frequency: float
    amplitude: float
    amplitude_jitter: float = 0.1

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "frequency": FieldRange(0, math.inf, "Hz", "body dither frequency", low_open=True),
        "amplitude": FieldRange(0, math.inf, "rad", "dither angle amplitude (peak)", low_open=True),
        "amplitude_jitter": FieldRange(0, 0.3, "1", "relative amplitude jitter between cycles"),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared specs above

    @property
    def peak_rate(self) -> float:
        """Omega_D = 2 pi f_d theta_D [rad/s]."""
        return 2.0 * math.pi * self.frequency * self.amplitude

    def draw(
        self, n_cycles: int, *, rng: np.random.Generator, size: int | tuple[int, ...] = ()
    ) -> DitherRealization:
        """Draw the amplitude factors of ``n_cycles`` cycles (per realization if ``size``)."""
        _check_rng(rng)
        if not (isinstance(n_cycles, (int, np.integer)) and n_cycles >= 1):
            raise ValueError(f"n_cycles must be an integer >= 1; got {n_cycles!r}")
        shape = (
            (int(n_cycles), *np.atleast_1d(size).astype(int)) if size != () else (int(n_cycles),)
        )
        a = 1.0 + self.amplitude_jitter * rng.standard_normal(shape)
        return DitherRealization(dither=self, factors=np.maximum(a, 0.05))


@dataclass(frozen=True, slots=True)
class DitherRealization:
    """One drawn dither history: ``factors[m]`` multiplies the amplitude of cycle m.

    Parameters
    ----------
    dither : Dither
        The dither drawn.
    factors : ndarray
        Amplitude factor a_m of each cycle (per realization along the trailing axes) [-].
    """

    dither: Dither
    factors: NDArray[np.float64]

    def _cycle(self, t: float) -> tuple[NDArray[np.float64], float]:
        m = min(int(math.floor(t * self.dither.frequency)), len(self.factors) - 1)
        return self.factors[max(m, 0)], 2.0 * math.pi * self.dither.frequency * t

    def angle(self, t: float) -> NDArray[np.float64]:
        """theta_d(t) [rad]."""
        a, ph = self._cycle(t)
        return self.dither.amplitude * a * math.sin(ph)

    def rate(self, t: float) -> NDArray[np.float64]:
        """Omega_d(t) [rad/s]."""
        a, ph = self._cycle(t)
        return self.dither.peak_rate * a * math.cos(ph)

    def expected_angle_variance(
        self, *, scale_factor: float, lock_in_rate: float, n_crossings: int
    ) -> NDArray[np.float64]:
        """Angle-error variance [rad^2] after the first ``n_crossings`` rate reversals.

        Notes
        -----
        Per reversal of cycle m (stationary phase, docs/physics.md 6.3):
        var(delta theta) = Omega_L^2 / (2 K Omegadot_m), Omegadot_m = (2 pi f_d)^2 theta_D a_m;
        reversals at t = (m + 1/4)/f_d and (m + 3/4)/f_d, two per cycle.
        """
        w = (2.0 * math.pi * self.dither.frequency) ** 2 * self.dither.amplitude
        cyc = np.arange(n_crossings) // 2
        omegadot = w * self.factors[cyc]
        return np.sum(lock_in_rate**2 / (2.0 * scale_factor * omegadot), axis=0)


def dither_arw(*, scale_factor: float, lock_in_rate: float, dither: Dither) -> float:
    """Angle random walk left by dithering through lock-in [rad/sqrt(s)].

    Parameters
    ----------
    scale_factor : float
        K [counts/rad], > 0.
    lock_in_rate : float
        Omega_L [rad/s], >= 0.
    dither : Dither
        The body dither (f_d, theta_D, amplitude jitter sigma).

    Returns
    -------
    float
        N [rad/sqrt(s)].

    Notes
    -----
    N = Omega_L / sqrt(2 pi K Omega_D) (docs/physics.md 6.3): 2 f_d independent lock-in
    crossings per second, each with variance Omega_L^2/(2 K Omegadot),
    Omegadot = 2 pi f_d Omega_D. The amplitude jitter adds E[1/a] ~ 1 + sigma^2, which
    is included.
    """
    k = _pos("dither_arw", "scale_factor", scale_factor, "counts/rad")
    wl = _nonneg("dither_arw", "lock_in_rate", lock_in_rate, "rad/s")
    return wl * math.sqrt(
        (1.0 + dither.amplitude_jitter**2) / (2.0 * math.pi * k * dither.peak_rate)
    )


# ============================================================================ thermal model
@dataclass(frozen=True, slots=True, kw_only=True)
class TwoNodeThermal:
    """Housing (T1) and cavity (T2) temperatures driven by the chamber.

    Parameters
    ----------
    tau_housing : float
        tau_1 [s], housing to chamber air.
    tau_cavity : float
        tau_2 [s], cavity block to housing.
    heating_housing : float
        H_1 [K], steady-state rise of the housing above the chamber once powered
        (electronics, high-voltage supply).
    heating_cavity : float
        H_2 [K], steady-state rise of the cavity above the housing (discharge power).

    Notes
    -----
    dT1/dt = (T_ch(t) + H_1 - T1)/tau_1,   dT2/dt = (T1 + H_2 - T2)/tau_2,
    with T1(0) = T2(0) = T_ch(0) (unit soaked unpowered, switched on at t = 0).
    Discretization (:func:`two_node_temperatures`): first-order-hold (input linear
    between samples), exact for the housing node when the chamber profile is
    piecewise linear with knots on the sample grid; for the cavity node T1 is taken
    linear between samples (error <= dt^2 max|d2T1/dt2|/8).
    """

    tau_housing: float = 600.0
    tau_cavity: float = 900.0
    heating_housing: float = 4.0
    heating_cavity: float = 1.5

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "tau_housing": FieldRange(0, math.inf, "s", "housing-to-chamber time constant tau_1", low_open=True),
        "tau_cavity": FieldRange(0, math.inf, "s", "cavity-to-housing time constant tau_2", low_open=True),
        "heating_housing": FieldRange(-math.inf, math.inf, "K", "steady self-heating H_1 of the housing"),
        "heating_cavity": FieldRange(-math.inf, math.inf, "K", "steady self-heating H_2 of the cavity"),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared specs above


def _first_order_foh(
    u: NDArray[np.float64], x0: float, tau: float, h: float
) -> NDArray[np.float64]:
    """x' = (u - x)/tau with u linear between samples: exact discrete recursion.

    x_{k+1} = phi x_k + b0 u_{k+1} + b1 u_k, phi = exp(-h/tau),
    b0 = 1 - tau (1 - phi)/h, b1 = tau (1 - phi)/h - phi.
    """
    phi = math.exp(-h / tau)
    g = tau * (-math.expm1(-h / tau)) / h
    b = np.array([1.0 - g, g - phi])
    a = np.array([1.0, -phi])
    # state such that y[0] = x0 with the recursion started from u[0]: lfilter form on u[1:]
    zi = np.array([phi * x0 + b[1] * u[0]])
    y, _ = signal.lfilter(b, a, u[1:], zi=zi)
    return np.concatenate(([x0], y))


def two_node_temperatures(
    chamber: NDArray[np.float64], fs: float, thermal: TwoNodeThermal
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Housing and cavity temperatures [K] at the samples of ``chamber`` [K], sampled at ``fs`` [Hz].

    See :class:`TwoNodeThermal` for the equations. The unit is powered at the first sample.

    Parameters
    ----------
    chamber : ndarray
        Chamber temperature at the samples [K], >= 2 samples.
    fs : float
        Sample rate [Hz].
    thermal : TwoNodeThermal
        The thermal model.

    Returns
    -------
    tuple of ndarray
        (T1, T2): housing and cavity temperatures [K] at the samples.
    """
    tc, h = _chamber_samples("two_node_temperatures", chamber, fs)
    t1 = _first_order_foh(tc + thermal.heating_housing, tc[0], thermal.tau_housing, h)
    t2 = _first_order_foh(t1 + thermal.heating_cavity, tc[0], thermal.tau_cavity, h)
    return t1, t2


# ============================================================================ thermal bias
@dataclass(frozen=True, slots=True, kw_only=True)
class ThermalBias:
    """Bias from temperature mechanisms of a dithered He-Ne RLG [rad/s].

    Parameters
    ----------
    cavity : float
        k_c [rad/s/K]: cavity (block) temperature coefficient -- mirror backscatter
        and Fresnel-drag changes as the block and mirrors expand.
    cavity_quadratic : float
        k_cc [rad/s/K^2]: curvature of the same (not in the linear candidate set).
    gradient : float
        k_g [rad/s/K]: housing-cavity gradient G = T1 - T2 heats the two discharge legs
        unequally -> discharge-current imbalance -> Langmuir gas flow.
    flux : float
        k_f [rad/s per K/s]: heat flux entering through the housing during a
        temperature change (proportional to dT1/dt) sets up a transient gas-flow
        asymmetry in the discharge capillaries.
    flux_quadratic : float
        k_ff [rad/s per (K/s)^2]: second-order part of the flux effect.
    gas_temperature_coefficient : float
        alpha [1/K]: relative change of the Langmuir-flow coefficients with gas
        temperature (viscosity, mobility), applied to the gradient and flux terms.
    reference_temperature : float
        T_ref [K].

    Notes
    -----
    b_T = k_c (T2 - T_ref) + k_cc (T2 - T_ref)^2
        + [1 + alpha (T2 - T_ref)] (k_g (T1 - T2) + k_f dT1/dt) + k_ff (dT1/dt)^2

    Mechanisms after Aronowitz & Lim (IEEE J. Quantum Electron. 1979, Langmuir flow)
    and paper 004 (unequal discharge legs in a non-uniform temperature field);
    sizes are not published: every default is 0; :data:`THERMAL_BIAS_CALIBRATED` is a set
    CALIBRATED to paper 004's ~65 % improvement (docs/physics.md 6.4, 9). No paper scenario
    uses this model (paper 004 runs on :mod:`gyrobench.sim.rlg_cavity`); a claim judged on it
    would be calibrated.
    """

    cavity: float = 0.0
    cavity_quadratic: float = 0.0
    gradient: float = 0.0
    flux: float = 0.0
    flux_quadratic: float = 0.0
    gas_temperature_coefficient: float = 0.0
    reference_temperature: float = units.celsius(25.0)

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "cavity": FieldRange(-math.inf, math.inf, "rad/s/K", "cavity temperature coefficient k_c (signed)"),
        "cavity_quadratic": FieldRange(-math.inf, math.inf, "rad/s/K^2", "its curvature k_cc (signed)"),
        "gradient": FieldRange(-math.inf, math.inf, "rad/s/K", "housing-cavity gradient coefficient k_g (signed)"),
        "flux": FieldRange(-math.inf, math.inf, "rad/s/(K/s)", "heat-flux coefficient k_f (signed)"),
        "flux_quadratic": FieldRange(-math.inf, math.inf, "rad/s/(K/s)^2", "second-order flux k_ff (signed)"),
        "gas_temperature_coefficient": FieldRange(-math.inf, math.inf, "1/K", "alpha of the Langmuir flow"),
        "reference_temperature": FieldRange(-math.inf, math.inf, "K", "T_ref of the coefficients"),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared specs above

    def components(
        self, t1: ArrayLike, t2: ArrayLike, dt1: ArrayLike
    ) -> dict[str, NDArray[np.float64]]:
        """Each mechanism's bias [rad/s] given true T1, T2 [K] and dT1/dt [K/s]."""
        t1, t2, dt1 = (np.asarray(a, dtype=float) for a in (t1, t2, dt1))
        d2 = t2 - self.reference_temperature
        gas = 1.0 + self.gas_temperature_coefficient * d2
        return {
            "bias_cavity_temperature": self.cavity * d2 + self.cavity_quadratic * d2 * d2,
            "bias_discharge_gradient": gas * self.gradient * (t1 - t2),
            "bias_heat_flux": gas * self.flux * dt1 + self.flux_quadratic * dt1 * dt1,
        }

    def __call__(self, t1: ArrayLike, t2: ArrayLike, dt1: ArrayLike) -> NDArray[np.float64]:
        """Total thermal bias [rad/s]."""
        c = self.components(t1, t2, dt1)
        return np.asarray(sum(c.values()), dtype=np.float64)


#: thermal-bias sizes CALIBRATED (not sourced) to paper 004's ~65 % improvement
#: (docs/physics.md 6.4, 9): over a -40..+65 degC chamber cycle at 1 degC/3 min the raw 100-s
#: bias stability (~0.06 deg/h) is about 4x the noise floor (~0.015 deg/h: dither random walk
#: 0.002 deg/sqrt(h) -> 0.012 deg/h and count quantization 0.007 deg/h over 100 s), so the
#: compensated value is ~1/3 of the raw one. Cavity 7.5e-4 deg/h/K and 4e-6 deg/h/K^2, gradient
#: 6e-3 deg/h/K, flux 0.095 deg/h per K/min and 0.19 deg/h per (K/min)^2, gas coefficient
#: 0.005/K. A labelled example set, not :class:`RLGSpec`'s default.
THERMAL_BIAS_CALIBRATED = ThermalBias(
    cavity=units.deg_per_h(7.5e-4),
    cavity_quadratic=units.deg_per_h(4e-6),
    gradient=units.deg_per_h(6e-3),
    flux=units.deg_per_h(0.095) * units.MINUTE,
    flux_quadratic=units.deg_per_h(0.19) * units.MINUTE**2,
    gas_temperature_coefficient=0.005,
)


# ============================================================================ sensors
@dataclass(frozen=True, slots=True, kw_only=True)
class TemperatureSensor:
    """A logged temperature channel: offset, white noise, then rounding to the resolution.

    Parameters
    ----------
    offset : float
        Calibration offset [K] (drawn per unit).
    noise : float
        White noise std [K] per sample.
    resolution : float
        LSB [K]; 0 for none.

    Notes
    -----
    T_meas = resolution * round((T + offset + noise eps)/resolution).
    """

    offset: float = 0.0
    noise: float = 0.02
    resolution: float = 0.01

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "offset": FieldRange(-math.inf, math.inf, "K", "calibration offset of this sensor (signed)"),
        "noise": FieldRange(0, math.inf, "K", "white-noise std per sample, >= 0"),
        "resolution": FieldRange(0, math.inf, "K", "LSB of the logged value; 0 for none"),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared specs above

    def measure(self, temperature: ArrayLike, *, rng: np.random.Generator) -> NDArray[np.float64]:
        """Logged values [K] of the true ``temperature`` [K]."""
        _check_rng(rng)
        t = np.asarray(temperature, dtype=float)
        y = t + self.offset + self.noise * rng.standard_normal(t.shape)
        if self.resolution > 0:
            y = self.resolution * np.round(y / self.resolution)
        return y


# ============================================================================ spec and unit
#: how this model describes the recording channels common to both RLG models
_WORDING = _Wording(
    dither_angle="dither angle at the end of each sample (pick-off)",
    housing_sensor="housing temperature sensor",
    cavity_sensor="cavity temperature sensor",
    turn_on_bias="constant bias of this turn-on",
    dither_random_walk="random walk from dithering through lock-in",
    quantization="rate error from pulse counting",
)


def _lognormal(rng: np.random.Generator, nominal: float, spread: float) -> float:
    """Positive draw nominal * exp(spread * eps - spread^2/2), eps ~ N(0, 1): mean = nominal, relative std ~ spread."""
    return float(nominal * math.exp(spread * rng.standard_normal() - 0.5 * spread * spread))


@dataclass(frozen=True, slots=True, kw_only=True)
class RLGUnit(_CavityScale):
    """One drawn ring laser gyro (all SI). Build with :meth:`RLGSpec.realize`.

    Parameters
    ----------
    geometry : CavityGeometry
    lock_in_rate : float
        Omega_L [rad/s].
    dither : Dither
    bias : float
        Constant (turn-on mean) bias [rad/s].
    thermal : TwoNodeThermal
    thermal_bias : ThermalBias
    bias_instability : float
        B [rad/s], flicker (IEEE 952), added to the rate before counting.
    rate_random_walk : float
        K [rad/s/sqrt(s)].
    bias_repeatability : float
        Turn-on to turn-on std of the constant bias [rad/s].
    flow_repeatability : float
        Turn-on to turn-on relative std of the gradient and flux coefficients
        (discharge-current balance set anew at every start).
    sensor_housing, sensor_cavity : TemperatureSensor
    label : str
    dither_mount : DitherMount or None
        The dither flexure's axial-to-torsional coupling and the stripper's band-pass: the
        vibration error (:mod:`gyrobench.sim.rlg_vibration`; ASSUMED defaults). None: a shaker
        run is ignored (listed in ``ignored_inputs``).

    Raises
    ------
    ValueError
        If the dither peak rate at -3 sigma of its amplitude jitter is below
        ``DITHER_LOCK_IN_MARGIN`` x Omega_L: the gyro would sit in lock-in for a
        large part of each cycle and the statistical model would not apply.
    """

    geometry: CavityGeometry
    lock_in_rate: float
    dither: Dither
    bias: float = 0.0
    thermal: TwoNodeThermal = field(default_factory=TwoNodeThermal)
    thermal_bias: ThermalBias = field(default_factory=ThermalBias)
    bias_instability: float = 0.0
    rate_random_walk: float = 0.0
    bias_repeatability: float = 0.0
    flow_repeatability: float = 0.0
    sensor_housing: TemperatureSensor = field(default_factory=TemperatureSensor)
    sensor_cavity: TemperatureSensor = field(default_factory=TemperatureSensor)
    label: str = "RLG"
    dither_mount: DitherMount | None = field(default_factory=DitherMount)

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "lock_in_rate": FieldRange(0, math.inf, "rad/s", "lock-in threshold Omega_L, >= 0"),
        "bias": FieldRange(-math.inf, math.inf, "rad/s", "constant (turn-on mean) bias, signed"),
        "bias_instability": FieldRange(0, math.inf, "rad/s", "flicker coefficient B (IEEE 952), >= 0"),
        "rate_random_walk": FieldRange(0, math.inf, "rad/s/sqrt(s)", "rate random walk K, >= 0"),
        "bias_repeatability": FieldRange(0, math.inf, "rad/s", "turn-on to turn-on bias std, >= 0"),
        "flow_repeatability": FieldRange(0, math.inf, "1", "turn-on relative std of the gas-flow terms, >= 0"),
    }
    #: the dither must clear the lock-in (statistical mode) and span the pulse weight (quantization)
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        dither_margin(
            lambda c: c.lock_in_rate,
            "lock-in rate",
            lambda c: f" (dither amplitude {c.dither.amplitude!r} rad at {c.dither.frequency!r} Hz)",
        ),
        Constraint(
            "dither amplitude >= 10 pulse weights",
            lambda c: c.dither.amplitude >= 10.0 * c.geometry.pulse_weight,
            lambda c: f"dither amplitude must be >= 10 pulse weights ({10 * c.geometry.pulse_weight!r} rad) "
            f"to randomize the count quantization; got {c.dither.amplitude!r} rad",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above

    # -------------------------------------------------------------- derived
    # scale_factor K [counts/rad] and pulse_weight q [rad/count]: from _CavityScale
    @property
    def angle_random_walk(self) -> float:
        """N from dithering through lock-in [rad/sqrt(s)] (:func:`dither_arw`)."""
        return dither_arw(
            scale_factor=self.scale_factor, lock_in_rate=self.lock_in_rate, dither=self.dither
        )

    def noise_model(self) -> NoiseModel:
        """The IEEE 952 model the statistical output follows (Q from counting, N from dither)."""
        return NoiseModel(
            quantization=self.geometry.quantization,
            angle_random_walk=self.angle_random_walk,
            bias_instability=self.bias_instability,
            rate_random_walk=self.rate_random_walk,
        )

    # -------------------------------------------------------------- simulation
    def temperatures(
        self, chamber: ArrayLike, fs: float
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """True housing and cavity temperatures [K] for chamber samples [K] at ``fs`` [Hz]."""
        return two_node_temperatures(np.asarray(chamber, dtype=float), fs, self.thermal)

    def _record(
        self,
        chamber: Callable[[NDArray[np.float64]], NDArray[np.float64]],
        duration: float,
        fs: float,
        *,
        rng: np.random.Generator,
        rate: float | Callable[[NDArray[np.float64]], NDArray[np.float64]] = 0.0,
        name: str = "rlg",
    ) -> Recording:
        """Fast statistical mode: pulse counts at ``fs`` over a thermal run.

        Parameters
        ----------
        chamber : callable t -> K
            Chamber air temperature [K] (e.g. :func:`gyrobench.sim.environment.thermal_profile`).
            The gyro is switched on at t = 0.
        duration : float
            Record length [s].
        fs : float
            Count sampling rate [Hz]; must be <= f_d / 4 so each sample spans several
            dither cycles (the dither phase at the samples is then taken as random).
        rng : numpy.random.Generator
        rate : float or callable t -> rad/s
            True input rate about the sense axis [rad/s].
        name : str

        Returns
        -------
        Recording
            channels ``output`` [rad/s] (counts x q minus the dither-angle increment, times
            fs), ``counts`` [counts per sample, dither included], ``dither_angle`` [rad],
            ``T1``, ``T2`` [K] (logged); truth ``true_rate``, ``T1``, ``T2``, ``thermal_bias``
            and each mechanism, ``turn_on_bias``, ``flicker_rrw``, ``dither_random_walk``,
            ``quantization`` (rate error from counting) [rad/s].

        Notes
        -----
        theta_k = sum_{j<k} (Omega_j + b_j) / fs + N sqrt(1/fs) sum_{j<k} eps_j
        d_k = theta_D a_k sin(phi_k), a_k = 1 + sigma eps'_k, phi_k ~ U(0, 2 pi)
        c_k = floor((theta_k + d_k)/q);  output_k = (q (c_k - c_{k-1}) - (d_k - d_{k-1})) fs.
        Each effect draws from its own child stream.
        """
        run = _start_run("RLGUnit.simulate", self.dither, chamber, duration, fs, rng)
        fs, tch = run.fs, run.chamber
        t1, t2 = self.temperatures(tch, fs)
        dt1 = (
            tch + self.thermal.heating_housing - t1
        ) / self.thermal.tau_housing  # exact dT1/dt of the model
        # turn-on draws: constant bias and the discharge-current balance
        r_turnon = run.turn_on_rng
        b_on = self.bias + self.bias_repeatability * r_turnon.standard_normal()
        flow = 1.0 + self.flow_repeatability * r_turnon.standard_normal(2)
        tb = replace(
            self.thermal_bias,
            gradient=self.thermal_bias.gradient * flow[0],
            flux=self.thermal_bias.flux * flow[1],
        )
        comps = tb.components(t1, t2, dt1)
        bias_mid = {
            k: 0.5 * (v[1:] + v[:-1]) for k, v in comps.items()
        }  # trapezoid over each sample
        thermal = np.asarray(sum(bias_mid.values()), dtype=np.float64)
        terms = _Terms(
            turn_on_bias=b_on,
            thermal_bias=thermal,
            random_walk=self.angle_random_walk,
            scale_ratio=None,
            t_housing=t1[:-1],
            t_cavity=t2[:-1],
            truth={
                "T1": Channel(t1[:-1], "K", "true housing temperature"),
                "T2": Channel(t2[:-1], "K", "true cavity temperature"),
                "chamber": Channel(tch[:-1], "K", "chamber air temperature"),
                "thermal_bias": Channel(thermal, "rad/s", "sum of the thermal mechanisms"),
            },
            truth_last={
                k: Channel(v, "rad/s", f"thermal mechanism {k}") for k, v in bias_mid.items()
            },
            metadata={
                "model": "gyrobench.sim.rlg statistical mode",
                "unit": self.label,
                "unit_parameters_si": self,
                "scale_factor_counts_per_rad": self.scale_factor,
                "pulse_weight_rad": self.pulse_weight,
                "angle_random_walk_rad_sqrt_s": self.angle_random_walk,
                "turn_on_flow_factors": flow.tolist(),
            },
        )
        return _finish_run(self, run, rate, terms, _WORDING, name)

    def adler_counts(
        self,
        rate: Callable[[float], ArrayLike],
        duration: float,
        *,
        fs: float,
        dt: float,
        psi0: ArrayLike = 0.0,
    ) -> NDArray[np.float64]:
        """Pulse counts per output sample from the integrated Adler equation (tests, short records).

        ``rate(t)`` is the total body rate [rad/s] including any dither; counts are
        taken every 1/fs [s] (1/fs must be a multiple of ``dt``).
        """
        every = int(round(1.0 / (fs * dt)))
        if every < 1 or abs(every * dt * fs - 1.0) > 1e-9:
            raise ValueError(f"1/fs must be a whole multiple of dt; got fs={fs!r} Hz, dt={dt!r} s")
        psi = integrate_adler(
            rate,
            duration,
            scale_factor=self.scale_factor,
            lock_in_rate=self.lock_in_rate,
            dt=dt,
            psi0=psi0,
            sample_every=every,
        )
        return count_pulses(psi)


def _default_geometry() -> CavityGeometry:
    """The default cavity of both RLG specs: equilateral triangle of side 0.14 m, He-Ne."""
    return CavityGeometry.triangle(0.14)


def _default_dither() -> Dither:
    """The default dither of both RLG specs: 400 Hz x 150 arcsec, 10 % amplitude jitter."""
    return Dither(frequency=400.0, amplitude=units.arcsec(150.0), amplitude_jitter=0.1)


@dataclass(frozen=True, slots=True, kw_only=True)
class RLGSpec:
    """A ring-laser-gyro budget (nominal values, SI) and the unit-to-unit spread of each.

    Parameters
    ----------
    geometry : CavityGeometry
    lock_in_rate : float
        Nominal Omega_L [rad/s]; unit spread ``lock_in_spread`` (log-normal, relative).
    dither : Dither
    bias_spread : float
        Std of a unit's constant bias [rad/s].
    thermal : TwoNodeThermal
        Nominal thermal constants; time constants and heating vary by ``thermal_spread`` (relative).
    thermal_bias : ThermalBias
        Nominal mechanism sizes; magnitudes vary by ``mechanism_spread`` (log-normal,
        relative); signs are those of the nominal (a design property: which discharge
        leg the incoming heat reaches first is fixed by the block layout).
    lock_in_spread : float
        Relative (log-normal) unit-to-unit spread of the lock-in rate [-].
    thermal_spread : float
        Relative (log-normal) spread of the thermal time constants and heating [-].
    mechanism_spread : float
        Relative (log-normal) spread of the thermal-bias mechanism sizes [-].
    bias_instability, rate_random_walk, bias_repeatability, flow_repeatability : float
        See :class:`RLGUnit`.
    sensor : TemperatureSensor
        Noise and resolution of both sensors.
    sensor_offset_spread : float
        Std of each sensor's drawn calibration offset [K].
    dither_mount : DitherMount or None
        See :class:`RLGUnit` (no unit-to-unit spread: ASSUMED defaults, no source prints them).

    Notes
    -----
    Defaults describe a high-precision mechanically dithered He-Ne RLG: triangle of
    side 0.14 m (pulse weight 1.61 arcsec), lock-in 0.05 deg/s, dither 400 Hz x 150
    arcsec (Omega_D ~ 105 deg/s) -> N ~ 0.002 deg/sqrt(h); flicker B 0.002 deg/h.
    No thermal-bias mechanism by default (``ThermalBias()``, every size 0): no source prints
    their sizes. :data:`THERMAL_BIAS_CALIBRATED` is the set tuned to paper 004's ~65 %
    improvement (CALIBRATED, not a source; pass it as ``thermal_bias`` to use it). Turn-on
    repeatability of the gas-flow coefficients, 20 % (unverified), makes a model fitted on one
    turn-on worse on the next, as paper 004's adjusted R^2 0.97 beside a 65 % improvement
    suggests. Spreads (one production batch, screened at acceptance): lock-in 10 %,
    mechanisms 15 %, thermal constants 10 %.
    """

    geometry: CavityGeometry = field(default_factory=_default_geometry)
    lock_in_rate: float = units.deg_per_s(0.05)
    lock_in_spread: float = 0.1
    dither: Dither = field(default_factory=_default_dither)
    bias_spread: float = units.deg_per_h(0.5)
    thermal: TwoNodeThermal = field(default_factory=TwoNodeThermal)
    thermal_spread: float = 0.1
    thermal_bias: ThermalBias = field(default_factory=ThermalBias)
    mechanism_spread: float = 0.15
    bias_instability: float = units.deg_per_h(0.002)
    rate_random_walk: float = 0.0
    bias_repeatability: float = units.deg_per_h(0.01)
    flow_repeatability: float = 0.2
    sensor: TemperatureSensor = field(default_factory=TemperatureSensor)
    sensor_offset_spread: float = 0.2
    dither_mount: DitherMount | None = field(default_factory=DitherMount)

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "lock_in_rate": FieldRange(0, math.inf, "rad/s", "nominal lock-in threshold Omega_L, >= 0"),
        "lock_in_spread": FieldRange(0, math.inf, "1", "relative (log-normal) unit spread of the lock-in"),
        "bias_spread": FieldRange(0, math.inf, "rad/s", "std of a unit's constant bias"),
        "thermal_spread": FieldRange(0, math.inf, "1", "relative unit spread of the thermal constants"),
        "mechanism_spread": FieldRange(0, math.inf, "1", "relative (log-normal) spread of the mechanism sizes"),
        "bias_instability": FieldRange(0, math.inf, "rad/s", "flicker coefficient B (IEEE 952), >= 0"),
        "rate_random_walk": FieldRange(0, math.inf, "rad/s/sqrt(s)", "rate random walk K, >= 0"),
        "bias_repeatability": FieldRange(0, math.inf, "rad/s", "turn-on to turn-on bias std, >= 0"),
        "flow_repeatability": FieldRange(0, math.inf, "1", "turn-on relative std of the gas-flow terms, >= 0"),
        "sensor_offset_spread": FieldRange(0, math.inf, "K", "std of the drawn sensor offsets"),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared specs above
        self.nominal()  # the nominal unit validates itself (dither vs lock-in and pulse weight)

    def nominal(self, label: str = "nominal") -> RLGUnit:
        """The unit at the nominal values (no spread)."""
        return RLGUnit(
            geometry=self.geometry,
            lock_in_rate=self.lock_in_rate,
            dither=self.dither,
            thermal=self.thermal,
            thermal_bias=self.thermal_bias,
            bias_instability=self.bias_instability,
            rate_random_walk=self.rate_random_walk,
            bias_repeatability=self.bias_repeatability,
            flow_repeatability=self.flow_repeatability,
            sensor_housing=self.sensor,
            sensor_cavity=self.sensor,
            label=label,
            dither_mount=self.dither_mount,
        )

    def realize(self, *, rng: np.random.Generator, label: str = "RLG") -> RLGUnit:
        """Draw one unit: lock-in, thermal constants, mechanism sizes and sensor offsets vary.

        Draws use one child stream per group (lock-in, thermal, mechanisms, sensors), so
        changing one spread leaves the other draws unchanged.
        """
        _check_rng(rng)
        r_lock, r_th, r_mech, r_sens = rng.spawn(4)
        th, tb = self.thermal, self.thermal_bias
        s = self.thermal_spread
        thermal = TwoNodeThermal(
            tau_housing=_lognormal(r_th, th.tau_housing, s),
            tau_cavity=_lognormal(r_th, th.tau_cavity, s),
            heating_housing=_lognormal(r_th, th.heating_housing, s)
            if th.heating_housing > 0
            else th.heating_housing,
            heating_cavity=_lognormal(r_th, th.heating_cavity, s)
            if th.heating_cavity > 0
            else th.heating_cavity,
        )
        m = self.mechanism_spread
        mech = ThermalBias(
            cavity=tb.cavity * _lognormal(r_mech, 1.0, m),
            cavity_quadratic=tb.cavity_quadratic * _lognormal(r_mech, 1.0, m),
            gradient=tb.gradient * _lognormal(r_mech, 1.0, m),
            flux=tb.flux * _lognormal(r_mech, 1.0, m),
            flux_quadratic=tb.flux_quadratic * _lognormal(r_mech, 1.0, m),
            gas_temperature_coefficient=tb.gas_temperature_coefficient * _lognormal(r_mech, 1.0, m),
            reference_temperature=tb.reference_temperature,
        )
        housing, cavity = _sensor_pair(self.sensor, self.sensor_offset_spread, r_sens)
        return RLGUnit(
            geometry=self.geometry,
            lock_in_rate=_lognormal(r_lock, self.lock_in_rate, self.lock_in_spread),
            dither=self.dither,
            bias=self.bias_spread * r_lock.standard_normal(),
            thermal=thermal,
            thermal_bias=mech,
            bias_instability=self.bias_instability,
            rate_random_walk=self.rate_random_walk,
            bias_repeatability=self.bias_repeatability,
            flow_repeatability=self.flow_repeatability,
            sensor_housing=housing,
            sensor_cavity=cavity,
            label=label,
            dither_mount=self.dither_mount,
        )
