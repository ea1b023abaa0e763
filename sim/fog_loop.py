"""Closed-loop interferometric FOG: square-wave bias modulation, serrodyne feedback, V_2pi loop.

All quantities SI: phase [rad], rate [rad/s], time [s]. Equations: docs/physics.md 3.8
(derived there from first principles), docs/physics.md 3.8.

Interferometer and modulation (one step per transit time tau = n_g L / c)
-----------------------------------------------------------------------------
The phase modulator at one coil end applies phi_m(k) = G (R_k + b_k phi_b / 2) in transit k
(b_k = +1, -1, ... alternating: a square wave at the proper frequency f_p = 1/(2 tau)); the
two waves see it one transit apart, so the phase difference is

    x_k + b_k G phi_b,   x_k = phi_s(k) + G dR_k,   dR_k = R_k - R_{k-1}

with phi_s the Sagnac phase SF Omega (plus any nonreciprocal phase), R the digital ramp
(wrapped to [0, 2 pi): dR_k = delta_k - 2 pi r_k, r_k = +-1 on a reset) and G the true
modulator gain relative to its nominal value (G = G_m g_2, g_2 the DAC gain the second loop
sets). Normalised detector samples (current / (i0/2)):

    I_k = 1 + cos(x_k + b_k G phi_b) + n_k

Two-tap demodulation e_k = -b_k (I_k - I_{k-1}) / (2 sin phi_b) = (sin x_k + sin x_{k-1})/2 for
G = 1. Rate loop (integrator, d transits of delay): delta_{k+1} = delta_k - g e_{k+1-d}.
Second loop (V_2pi control, reset-error demodulation, integral control): after a reset in
transit k, g_2 += k_2 r_k (e_k + e_{k+1}); the reset transit's phase error is -2 pi r_k (G - 1).

Output: the ramp's angle increments. Each transit the loop adds delta_k to the ramp (resets
remove whole 2 pi, counted), i.e. an angle -delta_k tau / SF0; integrate-and-dump over the
output period T_o gives the output rate sample (1/T_o) sum_k (-delta_k tau / SF0).

Linearised loop (G = 1, sin x = x):

    G_ol(z) = g z^-d (1 + z^-1)/2 / (1 - z^-1),   H(z) = G_ol / (1 + G_ol),   -delta = H phi_s

H(1) = 1 (no steady-state error); small g: f_3dB ~ g/(2 pi tau). Default g = 0.1, d = 1 for a
1 km coil: f_3dB = 3.4 kHz (computed by :meth:`LoopSpec.bandwidth`).

Reduced form (long records; :class:`ClosedLoopFOG`) -- see that class.

References
----------
H. C. Lefevre, The Fiber-Optic Gyroscope, 2nd ed. (Artech House, 2014), ch. 3 (reciprocity,
proper frequency, square-wave biasing) and ch. 6 (closed-loop, digital phase ramp, 2 pi reset
and V_2pi control); H. J. Arditty & H. C. Lefevre, "Sagnac effect in fiber gyroscopes",
Opt. Lett. 6(8) 401 (1981) (the Sagnac phase, independent of the fibre's index).
docs/physics.md 3.8 (the formulas above, derived and checked numerically there).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from numbers import Integral, Real
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.base.ranges import Constraint, FieldRange, validate
from gyrobench.io.recording import Channel, Recording, package_version
from gyrobench.sim.earth import BEIJING, sensed_earth_rate
from gyrobench.sim.fiber_strain import StrainMode, segment_weight, strain_rate_coefficient
from gyrobench.sim.fog_optics import SPEED_OF_LIGHT, OpticalBudget, arw_from_phase_psd
from gyrobench.sim.noise import NoiseModel
from gyrobench.sim.sensor import FOG_ERROR_COMPONENTS, Environment, check_call, with_metadata
from gyrobench.sim.shaker import ShakerSignal, moving_span

__all__ = [
    "sagnac_scale_factor",
    "LoopSpec",
    "LoopRun",
    "run_loop",
    "gain_error_scale_factor",
    "loop_average",
    "ClosedLoopFOG",
]

_TWO_PI = 2.0 * math.pi


def sagnac_scale_factor(length: float, diameter: float, wavelength: float) -> float:
    """Compute the optical Sagnac scale factor of a fibre coil.

    SF = 2 pi L D / (lambda c), so that the Sagnac phase is Delta phi = SF Omega
    (docs/physics.md 3.1; H. C. Lefevre, *The Fiber-Optic Gyroscope*, ch. 2).

    Parameters
    ----------
    length : float
        Fibre length L [m].
    diameter : float
        Mean coil diameter D [m].
    wavelength : float
        Mean source wavelength lambda in vacuum [m].

    Returns
    -------
    float
        SF [s] (rad of phase per rad/s of rate).

    Examples
    --------
    >>> round(sagnac_scale_factor(1000.0, 0.1, 1550e-9), 3)
    1.352
    """
    for name, v in (("length", length), ("diameter", diameter), ("wavelength", wavelength)):
        if not (isinstance(v, Real) and math.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be a finite number > 0 m; got {v!r}")
    return 2 * math.pi * length * diameter / (wavelength * SPEED_OF_LIGHT)


def _real(
    owner: str, name: str, v: object, unit: str, lo: float | None = None, hi: float | None = None
) -> float:
    if isinstance(v, bool) or not isinstance(v, Real):
        raise TypeError(f"{owner}.{name} must be a real number [{unit}]; got {v!r}")
    x = float(v)
    if not math.isfinite(x) or (lo is not None and x <= lo) or (hi is not None and x >= hi):
        rng = f"in ({lo}, {hi})" if hi is not None else f"> {lo}"
        raise ValueError(f"{owner}.{name} must be finite and {rng} {unit}; got {v!r}")
    return x


@dataclass(frozen=True, slots=True, kw_only=True)
class LoopSpec:
    """Coil, modulation and loop parameters of a closed-loop IFOG (SI).

    Parameters
    ----------
    length : float
        Coil fibre length L [m].
    diameter : float
        Mean coil diameter D [m].
    wavelength : float
        Source mean wavelength lambda [m].
    group_index : float
        Fibre group index n_g [-] (1.468: Corning SMF-28 product information, effective group
        index 1.4682 at 1550 nm).
    bias_phase : float
        Modulation depth phi_b [rad] (square wave +-phi_b/2 at f_p; pi/2 default).
    loop_gain : float
        Normalised integrator gain g [-] (per transit, error normalised to sin x).
    delay : int
        Transits between a detector sample and the ramp step it changes (1 or 2).
    gain_loop : bool
        Second (V_2pi) loop on.
    gain_loop_gain : float
        k_2 [-], integrator gain of the V_2pi loop per reset.
    modulator_gain_error : float
        eps = G_m - 1: the modulator's true gain relative to the DAC's nominal V_2pi [-].
    reset_blanking : bool
        Skip the rate-loop update on samples that contain a reset transit.
    """

    length: float = 1000.0
    diameter: float = 0.10
    wavelength: float = 1550e-9
    group_index: float = 1.468
    bias_phase: float = math.pi / 2
    loop_gain: float = 0.1
    delay: int = 1
    gain_loop: bool = True
    gain_loop_gain: float = 0.02
    modulator_gain_error: float = 0.0
    reset_blanking: bool = False

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "length": FieldRange(0, 1e5, "m", "fibre coils are 0.1-10 km; 100 km bounds the transit time", low_open=True),
        "diameter": FieldRange(0, 10, "m", "mean coil diameter; a coil is centimetres to a metre", low_open=True),
        "wavelength": FieldRange(2e-7, 1e-5, "m", "optical sources through fibre: UV to mid-IR"),
        "group_index": FieldRange(1, 5, "1", "n_g > 1 (__post_init__); silica ~1.47", low_open=True),
        "bias_phase": FieldRange(0, math.pi, "rad", "modulation depth in (0, pi) (__post_init__)", True, True),
        "loop_gain": FieldRange(0, 2, "1", "stable for g < 2 (delay 1) or < 1 (delay 2; __post_init__)", True, True),
        "delay": FieldRange(1, 2, "transits", "the loop model holds a 1- or 2-transit delay", integer=True),
        "gain_loop_gain": FieldRange(0, 1, "1", "V_2pi loop integrator gain in (0, 1) (__post_init__)", True, True),
        "modulator_gain_error": FieldRange(-0.5, 0.5, "1", "G_m - 1 within +-50 % (__post_init__)", True, True),
    }

    #: the constraints across fields (:class:`~gyrobench.base.ranges.Constraint`)
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "loop_gain gives a stable loop",
            lambda c: c.stable,
            lambda c: f"loop_gain must give a stable loop (delay {c.delay}: below "
            f"~{2.0 if c.delay == 1 else 1.0:g}); got {c.loop_gain!r}",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above

    # ----------------------------------------------------------------- optics
    @property
    def scale_factor(self) -> float:
        """SF0 = 2 pi L D / (lambda c) [s] (:func:`sagnac_scale_factor`)."""
        return sagnac_scale_factor(self.length, self.diameter, self.wavelength)

    @property
    def transit_time(self) -> float:
        """tau = n_g L / c [s]."""
        return self.group_index * self.length / SPEED_OF_LIGHT

    @property
    def proper_frequency(self) -> float:
        """f_p = 1/(2 tau) [Hz]."""
        return 1.0 / (2.0 * self.transit_time)

    @property
    def angle_quantum(self) -> float:
        """One 2 pi of ramp as output angle, 2 pi tau / SF0 = n_g lambda / D [rad]."""
        return _TWO_PI * self.transit_time / self.scale_factor

    # ----------------------------------------------------------------- loop
    def _poly(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(b, a) of H(z) in powers of z^-1."""
        g, d = self.loop_gain, self.delay
        num = np.zeros(d + 2)
        num[d] += g / 2
        num[d + 1] += g / 2
        den = np.zeros(d + 2)
        den[0], den[1] = 1.0, -1.0
        den = den + num
        return num, den

    @property
    def stable(self) -> bool:
        """All closed-loop poles inside the unit circle."""
        _, a = self._poly()
        return bool(np.all(np.abs(np.roots(a)) < 1.0))

    def transfer(self, f: ArrayLike) -> NDArray[np.complex128]:
        """Closed-loop H(e^{j 2 pi f tau}) from Sagnac phase to -delta at frequency ``f`` [Hz]."""
        z1 = np.exp(-2j * np.pi * np.asarray(f, dtype=float) * self.transit_time)
        b, a = self._poly()
        num = sum(c * z1**i for i, c in enumerate(b))
        den = sum(c * z1**i for i, c in enumerate(a))
        return np.asarray(num / den, dtype=np.complex128)

    def bandwidth(self) -> float:
        """-3 dB frequency of |H| [Hz] (first crossing of 1/sqrt(2) below f_p)."""
        from scipy.optimize import brentq

        f = np.linspace(0.0, self.proper_frequency, 20001)[1:]
        m = np.abs(self.transfer(f)) - 1 / math.sqrt(2)
        i = int(np.argmax(m < 0))
        return float(
            brentq(
                lambda x: abs(self.transfer(x)) - 1 / math.sqrt(2), f[i - 1] if i else 1e-9, f[i]
            )
        )

    def impulse_response(self, n: int | None = None) -> NDArray[np.float64]:
        """h_k of H(z), k = 0..n-1 (default: until |h| < 1e-16 of its peak)."""
        from scipy.signal import lfilter

        if n is None:
            r = float(np.max(np.abs(np.roots(self._poly()[1]))))
            n = int(math.ceil(40.0 / max(1e-12, -math.log(r)))) + 8
        x = np.zeros(n)
        x[0] = 1.0
        b, a = self._poly()
        return np.asarray(lfilter(b, a, x), dtype=float)

    def block_noise_correction(self) -> float:
        """c = sum_l |l| r_h(l), r_h the autocorrelation of h [transits].

        A block sum of M transits of H-filtered white noise (per-transit variance s^2) has
        variance s^2 (M - c) and lag-1 covariance s^2 c/2 when M exceeds the loop's memory
        (:meth:`block_noise_moments` gives the exact values for any M).
        """
        h = self.impulse_response()
        r = np.correlate(h, h, mode="full")
        lag = np.arange(-(len(h) - 1), len(h))
        return float(np.sum(np.abs(lag) * r))

    def block_noise_moments(self, m: int) -> tuple[float, float]:
        """Exact (variance, lag-1 covariance) of block sums of M transits of H-filtered unit
        white noise: sum_{|l|<M} (M - |l|) r(l) and sum_{l=1}^{2M-1} min(l, 2M - l) r(l)."""
        h = self.impulse_response()
        r = np.correlate(h, h, mode="full")
        lag = np.arange(-(len(h) - 1), len(h))
        al = np.abs(lag)
        var = float(np.sum(np.where(al < m, m - al, 0) * r))
        cov = float(
            np.sum(np.where((lag >= 1) & (lag <= 2 * m - 1), np.minimum(lag, 2 * m - lag), 0) * r)
        )
        return var, cov

    def noise_phase_psd(self, optics: OpticalBudget) -> float:
        """One-sided equivalent phase-noise PSD of the budget at this loop's bias [rad^2/Hz]."""
        return optics.phase_psd(self.bias_phase, self.wavelength)["total"]

    def arw(self, optics: OpticalBudget) -> float:
        """Angle random walk of the budget, N = sqrt(S_phi/2)/SF0 [rad/sqrt(s)]."""
        return arw_from_phase_psd(self.noise_phase_psd(optics), self.scale_factor)


def gain_error_scale_factor(
    phase: ArrayLike, eps: float, *, reset_blanking: bool = False, iterations: int = 60
) -> NDArray[np.float64]:
    """Mean-output scale-factor ratio (output / input) of the rate loop with modulator gain 1 + eps.

    Solves the loop's null condition for the mean demodulated error with resets in the
    loop: normal transits at x_n, a fraction f = |delta|/(2 pi) of reset transits at
    x_n - 2 pi s eps (s = sign(delta)):

        (1 - f) sin(x_n) + f sin(x_n - 2 pi s eps) = 0,   x_n = phi_s + (1 + eps) delta

    (fixed-point iteration). To first order in f the ratio -delta/phi_s is
    1/(1 + eps - sin(2 pi eps)/(2 pi)) = 1 - (2/3) pi^2 eps^3 + ...; with reset samples
    blanked it is 1/(1 + eps). docs/physics.md 3.8.

    Not included: with G != 1 the modulation depth is G phi_b and the two-tap demodulator
    keeps a term -b_k cos(G phi_b)(cos x_k - cos x_{k-1})/(2 sin phi_b); at a reset it adds
    b_k cos(G phi_b)(1 - cos 2 pi eps)/sin(phi_b) to the error, whose mean depends on the
    modulation parity of the reset transits (set by the rate). Its scale-factor effect is
    bounded by |cos(G phi_b)| (1 - cos 2 pi eps) / (2 pi sin phi_b) (39 ppm at eps = 0.02,
    phi_b = pi/2; 0.13 % at 3 pi/4) [derived; the full loop stays inside it, test_fog_loop].

    Parameters
    ----------
    phase : array
        Sagnac phase phi_s [rad], |phi_s| < pi.
    eps : float
        Modulator gain error G - 1 [-].
    reset_blanking : bool
        Reset transits blanked from the demodulation: the ratio is then 1/(1 + eps).
    iterations : int
        Fixed-point iterations of the null condition.

    Returns
    -------
    ndarray
        The ratio -delta/phi_s [-] per phase (its first-order limit at phi_s = 0).
    """
    phi = np.asarray(phase, dtype=float)
    if reset_blanking:
        return np.full_like(phi, 1.0 / (1.0 + eps))
    delta = -phi / (1.0 + eps)
    for _ in range(iterations):
        f = np.abs(delta) / _TWO_PI
        s = np.sign(delta)
        # x_n from tan(x_n) = f sin(2 pi s eps) / (1 - f + f cos(2 pi s eps))
        xn = np.arctan2(f * np.sin(_TWO_PI * s * eps), 1.0 - f + f * np.cos(_TWO_PI * eps))
        delta = (xn - phi) / (1.0 + eps)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(
            phi == 0, 1.0 / (1.0 + eps - math.sin(_TWO_PI * eps) / _TWO_PI), -delta / phi
        )


@dataclass(frozen=True, slots=True)
class LoopRun:
    """Result of :func:`run_loop`.

    Attributes
    ----------
    fs : float
        Output rate 1/(M tau) [Hz].
    rate : ndarray
        Output rate samples, angle increment / T_o [rad/s].
    delta : ndarray
        Ramp step per transit [rad] (length n).
    resets : ndarray of int
        Reset sign per transit (0, +1 wrap down, -1 wrap up).
    dac_gain : ndarray
        g_2 per transit (the V_2pi loop's state).
    """

    fs: float
    rate: NDArray[np.float64]
    delta: NDArray[np.float64]
    resets: NDArray[np.int8]
    dac_gain: NDArray[np.float64]


def run_loop(
    spec: LoopSpec,
    phase: ArrayLike,
    *,
    samples_per_output: int,
    optics: OpticalBudget | None = None,
    rng: np.random.Generator | None = None,
    initial_ramp: float = 0.0,
    intensity: ArrayLike | None = None,
) -> LoopRun:
    """Full-rate closed loop, one step per transit (validation reference; ~0.5 us CPU per transit).

    Parameters
    ----------
    spec : LoopSpec
    phase : array, shape (n,)
        Nonreciprocal phase per transit [rad]: SF Omega plus any other (strain) phase.
    samples_per_output : int
        M transits per output sample (output rate 1/(M tau)); n must be a multiple of M.
    optics : OpticalBudget, optional
        Detector noise from the budget (white, per-transit variance S_i / (2 tau) at the bias
        point); None: noise-free.
    rng : numpy.random.Generator
        Required when ``optics`` is given.
    initial_ramp : float
        Ramp register at k = -1 [rad], in [0, 2 pi).
    intensity : array, shape (n,), optional
        Relative detected-power modulation m_k per transit [-] (loss modulation, e.g. pigtail
        microbending): I_k = (1 + m_k)(1 + cos(...)) + n_k.

    Returns
    -------
    LoopRun
        The output rate samples at 1/(M tau) and the loop's per-transit state.
    """
    phi = np.asarray(phase, dtype=float)
    if phi.ndim != 1 or not np.all(np.isfinite(phi)):
        raise ValueError("phase must be a finite 1-D array [rad]")
    m = samples_per_output
    if isinstance(m, bool) or not isinstance(m, Integral) or m < 1 or len(phi) % m:
        raise ValueError(
            f"samples_per_output must be an int >= 1 dividing len(phase) = {len(phi)}; got {m!r}"
        )
    n = len(phi)
    tau = spec.transit_time
    pb = spec.bias_phase
    sinpb = math.sin(pb)
    if optics is not None:
        if not isinstance(rng, np.random.Generator):
            raise TypeError(f"rng must be a numpy.random.Generator; got {type(rng).__name__}")
        psd = sum(optics.current_psd(pb, spec.wavelength).values())
        sigma = math.sqrt(psd / (2.0 * tau)) / (optics.peak_current / 2.0)
        noise = sigma * rng.standard_normal(n)
    else:
        noise = np.zeros(n)
    g = spec.loop_gain
    d = spec.delay
    k2 = spec.gain_loop_gain if spec.gain_loop else 0.0
    gm = 1.0 + spec.modulator_gain_error
    g2 = 1.0
    ramp = float(initial_ramp)
    out_delta = np.empty(n)
    out_reset = np.zeros(n, dtype=np.int8)
    out_g2 = np.empty(n)
    prev_i = 1.0 + math.cos(pb)  # sample before the record: locked at zero residual
    delta = 0.0  # ramp step of the coming transit
    e_prev = 0.0
    pending = 0  # sign of a reset whose second demodulator tap is still to come
    e_acc = 0.0
    last_reset = 0  # reset of transit k - 1
    reset_2 = 0  # reset of transit k - 2
    cos = math.cos
    two_pi = _TWO_PI
    blanking = spec.reset_blanking
    phil = phi.tolist()
    noisel = noise.tolist()
    if intensity is None:
        gainl = [1.0] * n
    else:
        mod = np.asarray(intensity, dtype=float)
        if mod.shape != phi.shape or not np.all(np.isfinite(mod)) or np.any(mod <= -1):
            raise ValueError("intensity must be a finite array like phase with values > -1")
        gainl = (1.0 + mod).tolist()
    for k in range(n):
        b = 1.0 if (k & 1) == 0 else -1.0
        r = ramp + delta
        reset = 0
        if r >= two_pi:
            r -= two_pi
            reset = 1
        elif r < 0.0:
            r += two_pi
            reset = -1
        dr = r - ramp
        ramp = r
        i_k = gainl[k] * (1.0 + cos(phil[k] + gm * g2 * (dr + b * pb))) + noisel[k]
        e = -b * (i_k - prev_i) / (2.0 * sinpb)
        prev_i = i_k
        out_delta[k] = delta
        out_reset[k] = reset
        out_g2[k] = g2
        # V_2pi loop: the reset transit's error sits in the two taps e_k and e_{k+1}
        if pending:
            g2 += k2 * pending * (e_acc + e)
            pending = 0
        if reset and k2:
            pending = reset
            e_acc = e
        # rate loop: integrator on e_{k+1-d}, which holds transits k+1-d and k-d; blanking
        # skips it when either was a reset transit
        if d == 1:
            u, holds_reset = e, reset or last_reset
        else:
            u, holds_reset = e_prev, last_reset or reset_2
        if not (blanking and holds_reset):
            delta -= g * u
        e_prev = e
        reset_2 = last_reset
        last_reset = reset
    rate = -(out_delta.reshape(-1, m).sum(axis=1)) * tau / spec.scale_factor / (m * tau)
    return LoopRun(
        fs=1.0 / (m * tau), rate=rate, delta=out_delta, resets=out_reset, dac_gain=out_g2
    )


# ============================================================================ the unit
def _default_modes() -> tuple[StrainMode, ...]:
    # ASSUMED values (no paper number, no measured unit). Sizes chosen so that the largest
    # strain tone at 2 g is a few deg/h at the pigtail resonance, the order vibration tests of
    # navigation-grade FOGs report, and the coil mode adds ~0.1 deg/h at 500 Hz: axial strain
    # of the core is small because bending strain vanishes on the fibre's neutral axis.
    # - coil mode 1.2 kHz, Q 15: 2e-12 strain per m/s^2 with 1e-3 of the linear-ramp weight
    #   L^2/6 left after the quadrupolar winding;
    # - pigtail 300 Hz, Q 30: 0.5 m at the coil end (W = l (L - l)), 3e-12 strain per m/s^2,
    #   microbending loss 1e-6 per m/s^2;
    # - fixture mode 900 Hz, Q 10: rocking 1e-8 rad per m/s^2 about the sense axis (true rate).
    length = 1000.0
    return (
        StrainMode(frequency=1200.0, quality=15.0, strain=2e-12, weight=1e-3 * length**2 / 6),
        StrainMode(
            frequency=300.0,
            quality=30.0,
            strain=3e-12,
            weight=segment_weight(0.0, 0.5, length),
            loss=1e-6,
            segment=(0.0, 0.5),
        ),
        StrainMode(frequency=900.0, quality=10.0, rocking=1e-8),
    )


def _smooth_blocks(nb: int, m: int, n: int) -> int:
    """Smallest block count >= ``nb`` (at most ``n``) whose ``nb * m`` samples are 5-smooth."""
    from scipy.fft import next_fast_len

    for k in range(nb, n + 1):
        if next_fast_len(k * m, real=True) == k * m:
            return k
    return nb


def loop_average(
    spectrum: NDArray[np.complex128],
    n_phys: int,
    fs_phys: float,
    fs: float,
    loop: LoopSpec | None,
    *,
    weight: NDArray[np.complex128] | None = None,
) -> NDArray[np.float64]:
    """Output-rate samples of a physics-rate signal given by its rfft ``spectrum``.

    Applies the loop's H(e^{j 2 pi f tau}) (``loop`` None: no loop) and the integrate-and-dump
    average over T_o = 1/fs (sinc(f T_o)), and samples at the block centres
    t_j = (j + 1/2) T_o: exact for the periodic band-limited record. ``fs_phys`` must be an
    even integer multiple of ``fs``. ``weight``: that product sinc(f T_o) H on the rfft grid,
    when the caller already has it (several signals of one record); ``loop`` is then unused.

    Parameters
    ----------
    spectrum : ndarray of complex
        rfft of the physics-rate signal (``n_phys`` samples).
    n_phys : int
        Samples of the physics-rate record.
    fs_phys : float
        Physics rate [Hz], an even integer multiple of ``fs``.
    fs : float
        Output rate [Hz].
    loop : LoopSpec or None
        The loop whose H is applied; None: no loop.
    weight : ndarray of complex, optional
        sinc(f T_o) H on the rfft grid, precomputed.

    Returns
    -------
    ndarray
        The output-rate samples (n_phys fs / fs_phys of them), in the signal's unit.
    """
    m = int(round(fs_phys / fs))
    if m < 2 or m % 2 or abs(m * fs - fs_phys) > 1e-9 * fs_phys or n_phys % m:
        raise ValueError(
            f"physics rate must be an even integer multiple of fs = {fs!r} Hz with whole blocks; "
            f"got {fs_phys!r} Hz, {n_phys} samples"
        )
    if weight is None:
        f = np.fft.rfftfreq(n_phys, 1.0 / fs_phys)
        weight = np.sinc(f / fs) * (1.0 if loop is None else loop.transfer(f))
    return np.fft.irfft(spectrum * weight, n_phys)[np.arange(n_phys // m) * m + m // 2]


def _profile(name: str, v, t: NDArray, default: float) -> NDArray[np.float64]:
    if v is None:
        return np.full(len(t), default)
    if callable(v):
        out = np.asarray(v(t), dtype=float).reshape(len(t))
    elif isinstance(v, Real) and not isinstance(v, bool):
        out = np.full(len(t), float(v))
    else:
        raise TypeError(
            f"{name} must be a number or a callable of time [s]; got {type(v).__name__}"
        )
    if not np.all(np.isfinite(out)):
        raise ValueError(f"{name} must be finite")
    return out


def _strain_modes(modes: object, loop: LoopSpec) -> None:
    """Refuse modes that are not a tuple of :class:`StrainMode`, or a segment mode whose weight
    does not fit the coil of ``loop`` (:meth:`StrainMode.kernel`).

    Parameters
    ----------
    modes : object
        The unit's structural modes.
    loop : LoopSpec
        The unit's loop (its fibre length and group index).

    Raises
    ------
    TypeError
        ``modes`` is not a tuple of StrainMode.
    ValueError
        A segment mode's weight differs from l (L - 2 z0 - l) for this coil.
    """
    if not isinstance(modes, tuple) or not all(isinstance(m, StrainMode) for m in modes):
        raise TypeError(f"ClosedLoopFOG.modes must be a tuple of StrainMode; got {type(modes).__name__}")
    for m in modes:
        m.kernel(0.0, loop.length, loop.group_index)


@dataclass(frozen=True, slots=True, kw_only=True)
class ClosedLoopFOG:
    """One closed-loop IFOG unit in its reduced (output-rate) form, for long records.

    Parameters
    ----------
    loop : LoopSpec
        Coil, modulation and loop.
    optics : OpticalBudget
        Source, losses, detector: the white (ARW) noise.
    noise : NoiseModel
        Additive IEEE-952 terms for what the optics do not produce (bias, B, K, R, Q);
        default none.
    diameter_tempco : float
        alpha_D, hoop expansion of the mean winding diameter [1/K] (15 ppm/K: ASSUMED for
        paper 000's unit; paper 003 takes it from its coil's composite-cylinder model,
        22.7 ppm/K for an aluminium spool, :mod:`gyrobench.sim.fog2d`).
    wavelength_tempco : float
        (1/lambda) dlambda/dT of the source mean wavelength [1/K] (5 ppm/K: ASSUMED for an
        unstabilised Er ASE source, whose mean-wavelength stability is its reason for use in
        FOGs, Wysocki et al., J. Lightwave Technol. 12(3) 550 (1994)).
    reference_temperature : float
        Temperature at which SF = SF0 [K].
    modes : tuple of StrainMode
        Structural modes (:mod:`gyrobench.sim.fiber_strain`); defaults ASSUMED (no paper or
        measured unit) and sized for the default 1 km coil (their weights W do not follow ``loop.length``).
    index : float
        Phase index n of the fibre for the strain term [-] (fused silica at 1550 nm, 1.444,
        Malitson 1965).
    latitude, azimuth, elevation : float
        Site latitude and sense-axis azimuth (from north, toward east) and elevation [rad]
        (:func:`gyrobench.sim.earth.sensed_earth_rate`); default horizontal north at Beijing.

    Notes
    -----
    Reduced form (output period T_o = 1/fs, M = T_o/tau transits per sample):

    * slow inputs (table rate, Earth rate, a nonreciprocal phase such as the coil's thermal
      Shupe term) are evaluated at the block centres and pass with H(0) = 1; the loop's delay
      (d tau ~ 5 us) moves an angle Omega d tau between blocks, neglected; for an input
      linear over a block the block mean equals the centre value; the loop delays a slow
      input by tau/g (49 us for the default loop, computed from :meth:`LoopSpec.transfer`)
      and |H(f)| - 1 = -3.8e-8 at 1 Hz, both neglected;
    * scale factor: output = Omega SF(T)/SF0 with SF ~ N D^2 / lambda:
      SF(T)/SF0 = (1 + alpha_D dT_coil)^2 / (1 + alpha_lambda dT_source); with the V_2pi loop
      on, its settled state (gain error 0); off, :func:`gain_error_scale_factor`;
    * vibration: on the shaker's physics-rate grid (an even integer multiple of fs), in the
      frequency domain (exact for the sampled, band-limited record, circular): modal response,
      strain-rate nonreciprocity (j w with the exact transit-time kernel e^{-jw tau/2} W(w),
      :meth:`StrainMode.kernel`) and rocking rate (j w), loop transfer H(e^{jw tau}),
      loop residual (1 - H) phi, rectification +m(t) phi_res(t)/SF0 (intensity-phase
      correlation, docs/physics.md 4.1) passed through H, then the integrate-and-dump
      average over T_o (sinc(f T_o)) sampled at the block centres -- aliasing as the
      electronics' decimation does it. The j w factor is an ideal band-limited derivative:
      an abrupt shaker onset (``ramp_time = 0``) rings (Gibbs) on both sides of the edge,
      ~1e-3 deg/h rms for a 2 g, 500 Hz start; give the profile a ramp. Random (PSD)
      vibration: the samples' variance is int |G|^2 S_a df
      (:meth:`vibration_error_variance`, folded PSD :meth:`vibration_error_psd`);
    * optical white noise: block sums of the H-filtered per-transit phase noise, an MA(1)
      with variance s^2 (M - c) and lag-1 covariance s^2 c/2 (c from
      :meth:`LoopSpec.block_noise_correction`; s^2 = S_phi/(2 tau) (tau/SF0)^2): the full
      loop's second-order statistics exactly (M > loop memory); ARW = sqrt(S_phi/2)/SF0.
    """

    loop: LoopSpec = field(default_factory=LoopSpec)
    optics: OpticalBudget = field(default_factory=OpticalBudget)
    noise: NoiseModel = field(default_factory=NoiseModel)
    diameter_tempco: float = 15e-6
    wavelength_tempco: float = 5e-6
    reference_temperature: float = 293.15
    modes: tuple[StrainMode, ...] = field(default_factory=_default_modes)
    index: float = 1.444
    latitude: float = BEIJING.latitude
    azimuth: float = 0.0
    elevation: float = 0.0

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "diameter_tempco": FieldRange(-1e-3, 1e-3, "1/K", "relative coil diameter tempco (silica ~0.5e-6)", True, True),
        "wavelength_tempco": FieldRange(-1e-3, 1e-3, "1/K", "relative source wavelength tempco", True, True),
        "reference_temperature": FieldRange(0, math.inf, "K", "T0 of the tempcos", low_open=True),
        "index": FieldRange(1, math.inf, "1", "fibre phase index n, > 1", low_open=True),
        "latitude": FieldRange(-math.pi / 2 - 1e-15, math.pi / 2 + 1e-15, "rad", "site latitude", True, True),
        "azimuth": FieldRange(-1e3, 1e3, "rad", "sense-axis azimuth (any angle; bounded to stay finite)", True, True),
        "elevation": FieldRange(-1e3, 1e3, "rad", "sense-axis elevation (any angle; bounded)", True, True),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared specs above (and the types of loop, optics and noise)
        _strain_modes(self.modes, self.loop)  # each mode is a StrainMode that fits this coil

    @property
    def scale_factor(self) -> float:
        """SF0 [s]."""
        return self.loop.scale_factor

    @property
    def earth_rate(self) -> float:
        """Earth-rate component along the sense axis [rad/s]."""
        return float(
            sensed_earth_rate(self.latitude, azimuth=self.azimuth, elevation=self.elevation)
        )

    @property
    def arw(self) -> float:
        """Angle random walk of the optical budget [rad/sqrt(s)]."""
        return self.loop.arw(self.optics)

    @property
    def scale_factor_tempco(self) -> float:
        """(1/SF) dSF/dT = 2 alpha_D - (1/lambda) dlambda/dT [1/K] (coil and source together)."""
        return 2.0 * self.diameter_tempco - self.wavelength_tempco

    def scale_factor_ratio(
        self, coil_temperature: ArrayLike, source_temperature: ArrayLike
    ) -> NDArray[np.float64]:
        """SF(T)/SF0 = (1 + alpha_D dT_c)^2 / (1 + alpha_lambda dT_s) [-]."""
        dc = np.asarray(coil_temperature, dtype=float) - self.reference_temperature
        ds = np.asarray(source_temperature, dtype=float) - self.reference_temperature
        return (1.0 + self.diameter_tempco * dc) ** 2 / (1.0 + self.wavelength_tempco * ds)

    def strain_coefficient(self) -> float:
        """K = n_g n xi/(L D) [1/m^2] (``fiber_strain.strain_rate_coefficient``)."""
        lp = self.loop
        return strain_rate_coefficient(lp.length, lp.diameter, lp.group_index, self.index)

    def vibration_spectra(self, f: ArrayLike) -> dict[str, NDArray[np.complex128]]:
        """Per unit table acceleration at ``f`` [Hz]: strain rate error, rocking rate [rad/s per
        m/s^2] and loss modulation [1/(m/s^2)] (complex amplitudes, before the loop).

        Strain: K kappa_k jw H_k(f) e^{-jw tau/2} W_k(w) with the exact transit-time kernel
        (:meth:`StrainMode.kernel`: closed form for a mode with a ``segment``; W_k and the
        half-transit delay otherwise).
        """
        f = np.asarray(f, dtype=float)
        jw = 2j * np.pi * f
        k = self.strain_coefficient()
        lp = self.loop
        z = np.zeros(f.shape, dtype=np.complex128)
        out = {"strain": z.copy(), "rocking": z.copy(), "loss": z.copy()}
        for m in self.modes:
            h = m.response(f)
            if m.strain:
                kern = m.kernel(f, lp.length, lp.group_index)
                out["strain"] += k * m.strain * jw * h * kern
            out["rocking"] += m.rocking * jw * h
            out["loss"] += m.loss * h
        return out

    def vibration_transfer(
        self, f: ArrayLike, fs: float, term: str = "strain"
    ) -> NDArray[np.complex128]:
        """G(f): table acceleration -> output-rate error before sampling [rad/s per m/s^2].

        G = V(f) H(e^{jw tau}) sinc(f/fs) with V the ``term`` of :meth:`vibration_spectra`
        ("strain" or "rocking"), or for "loop_error" V_rock (H - 1) sinc(f/fs) (the rocking
        through the loop minus its true value).
        """
        f = np.asarray(f, dtype=float)
        spec = self.vibration_spectra(f)
        h = self.loop.transfer(f)
        if term == "strain":
            v = spec["strain"] * h
        elif term == "rocking":
            v = spec["rocking"] * h
        elif term == "loop_error":
            v = spec["rocking"] * (h - 1.0)
        else:
            raise ValueError(f"term must be 'strain', 'rocking' or 'loop_error'; got {term!r}")
        return np.asarray(v * np.sinc(f / fs), dtype=np.complex128)

    def vibration_error_psd(
        self,
        accel_psd: Callable[[NDArray[np.float64]], NDArray[np.float64]],
        fs: float,
        f_max: float,
        *,
        term: str = "strain",
        n: int = 4001,
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """One-sided PSD of the output samples' vibration error under random vibration.

        For a stationary table acceleration of one-sided PSD S_a(f) [(m/s^2)^2/Hz] (zero above
        ``f_max``), the output samples at ``fs`` (block means, taken every 1/fs) have the
        folded (aliased) one-sided PSD on [0, fs/2]

            S_y(f) = sum_{k >= 0} |G(f + k fs)|^2 S_a(f + k fs)
                     + sum_{k >= 1} |G(k fs - f)|^2 S_a(k fs - f)      [(rad/s)^2/Hz]

        (G from :meth:`vibration_transfer`), whose integral over [0, fs/2] is the variance
        int_0^inf |G|^2 S_a df (:meth:`vibration_error_variance`). Returns (f, S_y) on ``n``
        points. docs/physics.md 4.1.
        """
        fs = _real("vibration_error_psd", "fs", fs, "Hz", 0.0)
        f_max = _real("vibration_error_psd", "f_max", f_max, "Hz", 0.0)
        fo = np.linspace(0.0, fs / 2, n)
        s = np.zeros(n)
        for k in range(int(math.ceil(f_max / fs)) + 1):
            for ff in (k * fs + fo, (k + 1) * fs - fo):
                ok = ff <= f_max
                if np.any(ok):
                    g = self.vibration_transfer(ff[ok], fs, term)
                    s[ok] += np.abs(g) ** 2 * np.asarray(accel_psd(ff[ok]), dtype=float)
        return fo, s

    def vibration_error_variance(
        self,
        accel_psd: Callable[[NDArray[np.float64]], NDArray[np.float64]],
        fs: float,
        f_max: float,
        *,
        term: str = "strain",
        df: float = 0.02,
    ) -> float:
        """Var of the output samples' vibration error: int_0^f_max |G(f)|^2 S_a(f) df [(rad/s)^2].

        Trapezoid on a uniform grid of step <= ``df`` [Hz] (the modes' half-power widths
        f_k/Q_k are >= 10 Hz by default: relative error ~ (df Q/f)^2 / 12).
        """
        f_max = _real("vibration_error_variance", "f_max", f_max, "Hz", 0.0)
        f = np.linspace(0.0, f_max, int(math.ceil(f_max / df)) + 1)
        g = self.vibration_transfer(f, fs, term)
        return float(np.trapezoid(np.abs(g) ** 2 * np.asarray(accel_psd(f), dtype=float), f))

    def simulate(self, environment: Environment, *, fs: float, rng: np.random.Generator) -> Recording:
        """A record at output rate ``fs`` [Hz] over ``environment.duration`` (reduced form; class Notes).

        Parameters
        ----------
        environment : Environment
            ``true_rate``: table rate about the sense axis [rad/s] (the Earth's rate is added);
            ``temperature``: the unit's temperature [K], which both the coil's winding
            diameter (alpha_D) and the source's mean wavelength (alpha_lambda) follow (None:
            the reference temperature, no scale-factor change); ``vibration``: the shaker run
            (its sample rate an even multiple of ``fs``, covering the record from t = 0). The
            loop-only model has no static g-sensitivity: a set ``specific_force`` is listed in
            the metadata's ``ignored_inputs``.
        fs : float
            Output rate [Hz], at most 1/(100 tau).
        rng : numpy.random.Generator
            Two child streams: optical noise, IEEE-952 terms.

        Returns
        -------
        Recording
            Channel ``output`` [rad/s] (and the shaker's logged frequency and amplitude with a
            vibration); truth ``true_rate`` and the terms named in the metadata's
            ``error_components``, which sum to ``output - true_rate``; detail: the table, Earth
            and rocking rates and the IEEE-952 terms ``ieee_<term>`` of ``ieee_noise``.
        """
        fs = check_call(environment, fs, rng)
        temp = environment.profile("temperature", fs)
        rec = self._record(
            environment.duration,
            fs,
            rng=rng,
            true_rate=environment.profile("true_rate", fs) or 0.0,
            shaker=environment.vibration,
            coil_temperature=temp,
            source_temperature=temp,
        )
        return with_metadata(
            rec, ignored_inputs=environment.ignored("specific_force"), error_components=list(FOG_ERROR_COMPONENTS)
        )

    def _record(
        self,
        duration: float,
        fs: float,
        *,
        rng: np.random.Generator,
        true_rate: float | Callable[[NDArray[np.float64]], NDArray[np.float64]] = 0.0,
        shaker: ShakerSignal | None = None,
        coil_temperature: float
        | Callable[[NDArray[np.float64]], NDArray[np.float64]]
        | None = None,
        source_temperature: float
        | Callable[[NDArray[np.float64]], NDArray[np.float64]]
        | None = None,
        nonreciprocal_rate: float
        | Callable[[NDArray[np.float64]], NDArray[np.float64]]
        | None = None,
        t0: float = 0.0,
        name: str = "fog_loop",
        metadata: dict | None = None,
    ) -> Recording:
        """The reduced-form record with every input explicit (:meth:`simulate`; used by :mod:`gyrobench.sim.fog2d`).

        Parameters
        ----------
        true_rate : float or callable
            Table rate about the sense axis [rad/s] (the Earth's rate is added).
        shaker : ShakerSignal, optional
            Table acceleration at a physics rate that is an even multiple of ``fs``, covering
            the record (``round(duration * shaker.fs)`` samples from ``t0``).
        coil_temperature, source_temperature : float or callable, optional
            [K]; default the reference temperature (no scale-factor change). The coil's is
            the temperature its winding diameter follows (alpha_D), the source's the one its
            mean wavelength follows (alpha_lambda).
        nonreciprocal_rate : float or callable, optional
            A slow nonreciprocal phase at the loop's input besides the Sagnac phase, as its
            rate equivalent phi_nr/SF0 [rad/s] (e.g. the coil's thermal Shupe and T x dT
            terms, :mod:`gyrobench.sim.fog2d`). It adds to the Sagnac phase SF(T) Omega and
            passes the loop like it (H(0) = 1, the gain error's ratio); it is a phase, so
            SF(T)/SF0 does not scale it. Default 0.
        rng : numpy.random.Generator
            Two child streams: optical noise, IEEE-952 terms.
        """
        if not isinstance(rng, np.random.Generator):
            raise TypeError(f"rng must be a numpy.random.Generator; got {type(rng).__name__}")
        dur = _real("simulate", "duration", duration, "s", 0.0)
        fs = _real("simulate", "fs", fs, "Hz", 0.0)
        n = int(math.floor(dur * fs + 1e-9))
        if n < 2:
            raise ValueError(f"duration * fs must give >= 2 samples; got {dur!r} s at {fs!r} Hz")
        lp = self.loop
        sf0 = lp.scale_factor
        tau = lp.transit_time
        t_o = 1.0 / fs
        if t_o < 100 * tau:
            raise ValueError(
                f"fs must be <= 1/(100 tau) = {1 / (100 * tau):.6g} Hz for the reduced form; "
                f"got {fs!r}"
            )
        tc = t0 + (np.arange(n) + 0.5) * t_o
        omega_table = _profile("true_rate", true_rate, tc, 0.0)
        earth = np.full(n, self.earth_rate)
        r_t = self.scale_factor_ratio(
            _profile("coil_temperature", coil_temperature, tc, self.reference_temperature),
            _profile("source_temperature", source_temperature, tc, self.reference_temperature),
        )
        slow = omega_table + earth
        nonrec = _profile("nonreciprocal_rate", nonreciprocal_rate, tc, 0.0)
        if lp.gain_loop or lp.modulator_gain_error == 0.0:
            r_g = np.ones(n)
        else:
            r_g = gain_error_scale_factor(
                sf0 * (r_t * slow + nonrec),
                lp.modulator_gain_error,
                reset_blanking=lp.reset_blanking,
            )
        vib = self._vibration(shaker, n, fs, t0) if shaker is not None else None
        zeros = np.zeros(n)
        rock_true = vib["rock_true"] if vib else zeros
        rock_out = vib["rock_out"] if vib else zeros
        strain = vib["strain"] if vib else zeros
        rect = vib["rect"] if vib else zeros
        rng_opt, rng_ieee = rng.spawn(2)
        optical = self._optical_noise(n, fs, rng_opt)
        ieee_parts = self.noise.components(n, fs, rng=rng_ieee, t0=t0)
        ieee = np.zeros(n)
        for part in ieee_parts.values():
            ieee = ieee + part
        true = slow + rock_true
        sf_err = slow * (r_t * r_g - 1.0) + rock_out * (r_t - 1.0) + nonrec * (r_g - 1.0)
        loop_err = rock_out - rock_true
        output = true + sf_err + loop_err + nonrec + strain + rect + optical + ieee
        rs = "rad/s"
        truth = {
            "true_rate": Channel(
                true, rs, "true rate about the sense axis (table + Earth + rocking), block mean"
            ),
            "table_rate": Channel(omega_table, rs, "table rate"),
            "earth_rate": Channel(earth, rs, "Earth-rate component along the sense axis"),
            "rocking_rate": Channel(
                rock_true, rs, "fixture rocking about the sense axis (true rate)"
            ),
            "scale_factor_error": Channel(
                sf_err,
                rs,
                "true rate x (SF(T) SF(eps)/SF0 - 1) + nonreciprocal input x (SF(eps) - 1)",
            ),
            "nonreciprocal": Channel(
                nonrec, rs, "slow nonreciprocal input phase / SF0 (e.g. the coil's thermal term)"
            ),
            "loop_error": Channel(
                loop_err, rs, "rocking through the loop's finite bandwidth minus its true value"
            ),
            "strain_nonreciprocity": Channel(
                strain, rs, "strain-rate nonreciprocity (L - 2z kernel) through the loop"
            ),
            "rectification": Channel(
                rect, rs, "intensity-phase correlation +m phi_res/SF0 through the loop"
            ),
            "optical_noise": Channel(
                optical, rs, "shot + excess RIN + thermal, through the loop (ARW)"
            ),
            "ieee_noise": Channel(ieee, rs, "additive IEEE-952 terms (NoiseModel, incl. its bias)"),
            **{
                f"ieee_{k}": Channel(v, rs, f"IEEE-952 term {k} (part of ieee_noise)")
                for k, v in ieee_parts.items()
            },
        }
        channels = {"output": Channel(output, rs, "FOG output: ramp angle increments / T_o")}
        if shaker is not None:
            m = int(round(shaker.fs / fs))
            centre = slice(m // 2, n * m, m)  # the block centres
            freq = shaker.frequency[centre]
            defined = np.isfinite(freq)
            channels["vibration_frequency"] = Channel(
                np.where(defined, freq, 0.0), "Hz", "shaker drive frequency (controller log; 0 where none is defined: "
                "off, or random vibration)"
            )
            channels["vibration_on"] = Channel(shaker.on[centre].astype(np.float64), "1", "1 while the shaker drives")
            channels["vibration_amplitude"] = Channel(
                shaker.amplitude[: n * m].reshape(n, m)[:, m // 2],
                "m/s^2",
                "shaker acceleration envelope",
            )
        meta = {
            "model": "gyrobench.sim.fog_loop.ClosedLoopFOG (reduced form)",
            "scale_factor_s": sf0,
            "transit_time_s": tau,
            "loop_gain": lp.loop_gain,
            "loop_bandwidth_hz": lp.bandwidth(),
            "arw_rad_per_sqrt_s": self.arw,
            "earth_rate_rad_per_s": self.earth_rate,
            "latitude_rad": self.latitude,
            "package_version": package_version(),
            **(metadata or {}),
        }
        return Recording(
            fs=fs, channels=channels, truth=truth, t0=float(t0), metadata=meta, name=name
        )

    def _optical_noise(self, n: int, fs: float, rng: np.random.Generator) -> NDArray[np.float64]:
        lp = self.loop
        tau = lp.transit_time
        m = 1.0 / (fs * tau)
        c = lp.block_noise_correction()
        s_phi = lp.noise_phase_psd(self.optics)
        sigma = math.sqrt(s_phi / (2.0 * tau)) * tau / lp.scale_factor  # per-transit angle [rad]
        a = (math.sqrt(m) + math.sqrt(m - 2 * c)) / 2
        b = (math.sqrt(m) - math.sqrt(m - 2 * c)) / 2
        e = rng.standard_normal(n + 1)
        return sigma * (a * e[1:] + b * e[:-1]) * fs

    def _vibration(
        self, shaker: ShakerSignal, n: int, fs: float, t0: float
    ) -> dict[str, NDArray[np.float64]]:
        if not isinstance(shaker, ShakerSignal):
            raise TypeError(
                f"shaker must be a sim.shaker.ShakerSignal; got {type(shaker).__name__}"
            )
        m = int(round(shaker.fs / fs))
        if m < 2 or m % 2 or abs(m * fs - shaker.fs) > 1e-9 * shaker.fs:
            raise ValueError(
                f"shaker.fs must be an even integer multiple of fs = {fs!r} Hz; "
                f"got {shaker.fs!r} Hz"
            )
        if len(shaker.acceleration) < n * m or abs(shaker.t0 - t0) > 0.5 / shaker.fs:
            raise ValueError(
                f"shaker must cover the record: >= {n * m} samples from t0 = {t0!r} s; "
                f"got {len(shaker.acceleration)} from {shaker.t0!r} s"
            )
        # Only the span where the table moves, plus a ring-down margin, is transformed: the
        # modes decay as exp(-pi f_k t / Q_k); 30 Q_k/(pi f_k) leaves e^-30 (1e-13) to wrap
        # around the circular transform. The rest of the record has no vibration term.
        span = moving_span(shaker.acceleration[: n * m])
        res = {k: np.zeros(n) for k in ("rock_true", "rock_out", "strain", "rect")}
        if span is None:
            return res
        ring = max((30.0 * md.quality / (math.pi * md.frequency) for md in self.modes), default=0.0)
        pad = int(math.ceil(ring * fs)) + 2
        j0 = max(0, span[0] // m - pad)
        j1 = min(n, span[1] // m + 1 + pad)
        # Widen the span to a 5-smooth transform length (a prime-sized FFT is ~10x slower);
        # the extra blocks hold table acceleration (zero outside the vibration), no new term.
        nb = _smooth_blocks(j1 - j0, m, n)
        j0 = max(0, min(j0, n - nb))
        j1 = min(n, j0 + nb)
        # Arrays of the span's transform are reused in place and released once read (the same
        # operations in the same order: the values do not change, the peak memory falls).
        a = shaker.acceleration[j0 * m : j1 * m]
        nn = len(a)
        f = np.fft.rfftfreq(nn, 1.0 / shaker.fs)
        spec = self.vibration_spectra(f)
        big_a = np.fft.rfft(a)
        h = self.loop.transfer(f)
        sf0 = self.loop.scale_factor
        avg = np.sinc(f / fs)  # integrate-and-dump; with H once for every term of the record
        del f
        w_loop, w_open = avg * h, avg.astype(np.complex128)
        del avg

        def out(x: NDArray[np.complex128], w: NDArray[np.complex128]) -> NDArray[np.float64]:
            return loop_average(x, nn, shaker.fs, fs, None, weight=w)

        u_rock = spec.pop("rocking")
        u_rock *= big_a  # spec["rocking"] * big_a
        u_strain = spec.pop("strain")
        u_strain *= big_a
        res["rock_true"][j0:j1] = out(u_rock, w_open)
        del w_open
        res["rock_out"][j0:j1] = out(u_rock, w_loop)
        res["strain"][j0:j1] = out(u_strain, w_loop)
        if any(md.loss for md in self.modes):
            np.add(u_rock, u_strain, out=u_strain)  # u_rock + u_strain
            del u_rock
            np.subtract(1.0, h, out=h)  # 1 - H
            h *= u_strain  # (1 - H) (u_rock + u_strain)
            del u_strain
            phi_res = sf0 * np.fft.irfft(h, nn)
            del h
            loss_spec = spec.pop("loss")
            loss_spec *= big_a  # spec["loss"] * big_a
            loss = np.fft.irfft(loss_spec, nn)
            del loss_spec, big_a
            res["rect"][j0:j1] = out(np.fft.rfft(loss * phi_res / sf0), w_loop)
        return res
