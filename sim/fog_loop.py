"""Closed-loop interferometric FOG: square-wave bias modulation, serrodyne feedback, V_2pi loop.

All quantities SI: phase [rad], rate [rad/s], time [s]. Equations: PHYSICS-models.md section 1
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
and V_2pi control); Arditty & Lefevre, "Closed-loop fiber gyroscope with a phase ramp",
Opt. Lett. 6(8) 401 (1981). PHYSICS-models.md 1.1-1.4 (the formulas above, derived and
checked numerically there).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from numbers import Integral, Real

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.sim.fog import sagnac_scale_factor
from gyrobench.sim.fog_optics import SPEED_OF_LIGHT, OpticalBudget, arw_from_phase_psd

__all__ = ["LoopSpec", "LoopRun", "run_loop", "gain_error_scale_factor"]

_TWO_PI = 2.0 * math.pi


def _real(owner: str, name: str, v: object, unit: str, lo: float | None = None, hi: float | None = None) -> float:
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
        Fibre group index n_g [-] (1.468, SMF at 1550 nm; typical).
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

    def __post_init__(self) -> None:
        o = "LoopSpec"
        _real(o, "length", self.length, "m", 0.0)
        _real(o, "diameter", self.diameter, "m", 0.0)
        _real(o, "wavelength", self.wavelength, "m", 0.0)
        _real(o, "group_index", self.group_index, "-", 1.0)
        _real(o, "bias_phase", self.bias_phase, "rad", 0.0, math.pi)
        _real(o, "gain_loop_gain", self.gain_loop_gain, "-", 0.0, 1.0)
        _real(o, "modulator_gain_error", self.modulator_gain_error, "-", -0.5, 0.5)
        if isinstance(self.delay, bool) or not isinstance(self.delay, Integral) or self.delay not in (1, 2):
            raise ValueError(f"LoopSpec.delay must be 1 or 2 transits; got {self.delay!r}")
        gmax = 2.0 if self.delay == 1 else 1.0
        _real(o, "loop_gain", self.loop_gain, "-", 0.0)
        if not self.stable:
            raise ValueError(
                f"LoopSpec.loop_gain must give a stable loop (delay {self.delay}: below ~{gmax:g}); "
                f"got {self.loop_gain!r}"
            )
        for name in ("gain_loop", "reset_blanking"):
            if not isinstance(getattr(self, name), bool):
                raise TypeError(f"LoopSpec.{name} must be a bool; got {getattr(self, name)!r}")

    # ----------------------------------------------------------------- optics
    @property
    def scale_factor(self) -> float:
        """SF0 = 2 pi L D / (lambda c) [s] (sim.fog.sagnac_scale_factor)."""
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
        return float(brentq(lambda x: abs(self.transfer(x)) - 1 / math.sqrt(2), f[i - 1] if i else 1e-9, f[i]))

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
        variance s^2 (M - c) and lag-1 covariance s^2 c/2 (exact for M > memory of h).
        """
        h = self.impulse_response()
        r = np.correlate(h, h, mode="full")
        lag = np.arange(-(len(h) - 1), len(h))
        return float(np.sum(np.abs(lag) * r))

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
    blanked it is 1/(1 + eps). PHYSICS-models.md 1.3.

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
        return np.where(phi == 0, 1.0 / (1.0 + eps - math.sin(_TWO_PI * eps) / _TWO_PI), -delta / phi)


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
) -> LoopRun:
    """Full-rate closed loop, one step per transit (validation reference; ~1-2 us per transit).

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
    last_reset = 0
    cos = math.cos
    two_pi = _TWO_PI
    blanking = spec.reset_blanking
    phil = phi.tolist()
    noisel = noise.tolist()
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
        i_k = 1.0 + cos(phil[k] + gm * g2 * (dr + b * pb)) + noisel[k]
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
        # rate loop: integrator on e_{k+1-d}
        u = e if d == 1 else e_prev
        if not (blanking and (reset or last_reset)):
            delta -= g * u
        e_prev = e
        last_reset = reset
    rate = -(out_delta.reshape(-1, m).sum(axis=1)) * tau / spec.scale_factor / (m * tau)
    return LoopRun(fs=1.0 / (m * tau), rate=rate, delta=out_delta, resets=out_reset, dac_gain=out_g2)

