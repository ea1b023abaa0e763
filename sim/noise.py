"""IEEE Std 952 rate-noise model: closed-form Allan variance and generation.

All parameters are in SI (see :mod:`sim.units`); field units enter only through
:meth:`NoiseModel.from_datasheet`.

The model is a sum of independent processes, each generated from its own child
random stream so that adding a term never changes another term's samples:

=========================  ==================  ===============================
term                       field               two-sided rate PSD S(f)
=========================  ==================  ===============================
quantization Q             ``quantization``     (2 pi f)^2 tau0 Q^2  [rad]
angle random walk N        ``angle_random_walk`` N^2  [rad/sqrt(s)]
bias instability B         ``bias_instability`` B^2/(2 pi f), f_lo <= f <= f_hi  [rad/s]
rate random walk K         ``rate_random_walk`` (K/(2 pi f))^2  [rad/s/sqrt(s)]
rate ramp R                ``rate_ramp``        R t (deterministic)  [rad/s^2]
Gauss-Markov (sigma, Tc)   ``gauss_markov``     2 sigma^2 Tc/(1 + (2 pi f Tc)^2)
sinusoid (A, f0, phase)    ``sinusoids``        (A^2/4)[delta(f-f0) + delta(f+f0)]
=========================  ==================  ===============================

References
----------
IEEE Std 952-1997 Annex C; PHYSICS.md sections 1-2; N. J. Kasdin, "Discrete
simulation of colored noise and stochastic processes and 1/f^alpha power law
noise generation", Proc. IEEE 83(5), 1995.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass, field, fields

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import signal, special

from sim import units

__all__ = ["GaussMarkov", "Sinusoid", "NoiseModel", "NoiseStream", "flicker_avar"]

#: child-stream slots: a term always draws from the same slot, whatever else the model holds
_SLOT_QUANT, _SLOT_ARW, _SLOT_FLICKER, _SLOT_RRW, _SLOT_GM0 = 0, 1, 2, 3, 8
_N_SLOTS = 64
_LN2 = math.log(2.0)


def _check_nonneg(owner: str, name: str, v: float) -> None:
    if isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)):
        raise TypeError(f"{owner}.{name} must be a real number; got {v!r}")
    if not (math.isfinite(v) and v >= 0.0):
        raise ValueError(f"{owner}.{name} must be finite and >= 0; got {v!r}")


@dataclass(frozen=True, slots=True, kw_only=True)
class GaussMarkov:
    """First-order Gauss-Markov rate noise.

    Parameters
    ----------
    sigma : float
        Stationary standard deviation [rad/s].
    correlation_time : float
        Correlation time Tc [s], > 0.

    Notes
    -----
    x_k = phi x_{k-1} + sigma sqrt(1 - phi^2) eps_k, phi = exp(-dt/Tc): the exact
    discretisation, started from the stationary distribution.
    AVAR (PHYSICS.md 1.2, qc^2 = 2 sigma^2/Tc):
    (qc Tc)^2/tau [1 - Tc/(2 tau)(3 - 4 e^{-tau/Tc} + e^{-2 tau/Tc})].
    """

    sigma: float
    correlation_time: float

    def __post_init__(self) -> None:
        _check_nonneg("GaussMarkov", "sigma", self.sigma)
        _check_nonneg("GaussMarkov", "correlation_time", self.correlation_time)
        if self.correlation_time == 0:
            raise ValueError(f"GaussMarkov.correlation_time must be > 0 s; got {self.correlation_time!r}")

    def avar(self, tau: NDArray[np.float64]) -> NDArray[np.float64]:
        """Allan variance [rad^2/s^2] at cluster times ``tau`` [s]."""
        tc = self.correlation_time
        qc2 = 2.0 * self.sigma**2 / tc
        r = tau / tc
        return qc2 * tc**2 / tau * (1.0 - (3.0 - 4.0 * np.exp(-r) + np.exp(-2.0 * r)) / (2.0 * r))


@dataclass(frozen=True, slots=True, kw_only=True)
class Sinusoid:
    """Deterministic sinusoidal rate error A sin(2 pi f0 t + phase).

    Parameters
    ----------
    amplitude : float
        A [rad/s].
    frequency : float
        f0 [Hz], > 0.
    phase : float
        [rad].
    """

    amplitude: float
    frequency: float
    phase: float = 0.0

    def __post_init__(self) -> None:
        _check_nonneg("Sinusoid", "amplitude", self.amplitude)
        _check_nonneg("Sinusoid", "frequency", self.frequency)
        if self.frequency == 0:
            raise ValueError(f"Sinusoid.frequency must be > 0 Hz; got {self.frequency!r}")
        if not math.isfinite(self.phase):
            raise ValueError(f"Sinusoid.phase must be finite; got {self.phase!r}")

    def avar(self, tau: NDArray[np.float64]) -> NDArray[np.float64]:
        """AVAR = A^2 (sin^2(pi f0 tau)/(pi f0 tau))^2 (PHYSICS.md 1.2)."""
        x = np.pi * self.frequency * tau
        return self.amplitude**2 * (np.sin(x) ** 2 / x) ** 2


def _flicker_kernel(x: NDArray[np.float64]) -> NDArray[np.float64]:
    """F(x) = Int_0^x sin^4 u / u^3 du, closed form (PHYSICS.md 1.3).

    F(x) = ln2 - sin^3 x (sin x + 4 x cos x)/(2 x^2) + Ci(2x) - Ci(4x); F(0) = 0;
    for x < 1e-3 the series F ~ x^2/2 avoids cancellation.
    """
    x = np.asarray(x, dtype=float)
    out = np.empty_like(x)
    small = x < 1e-3
    xs = x[small]
    out[small] = xs**2 / 2.0
    xl = x[~small]
    s, c = np.sin(xl), np.cos(xl)
    out[~small] = (
        _LN2 - s**3 * (s + 4.0 * xl * c) / (2.0 * xl**2) + special.sici(2.0 * xl)[1] - special.sici(4.0 * xl)[1]
    )
    out[np.isinf(x)] = _LN2
    return out


def flicker_avar(tau: ArrayLike, b: float, f_low: float, f_high: float) -> NDArray[np.float64]:
    """Allan variance of band-limited flicker rate noise.

    Parameters
    ----------
    tau : array_like
        Cluster times [s].
    b : float
        Bias-instability coefficient B [rad/s].
    f_low, f_high : float
        Band edges [Hz] of the two-sided PSD S(f) = B^2/(2 pi f).

    Notes
    -----
    sigma^2(tau) = 4 Int_{f_low}^{f_high} S(f) sin^4(pi f tau)/(pi f tau)^2 df
                 = (2 B^2/pi) [F(pi f_high tau) - F(pi f_low tau)],
    F(x) = Int_0^x sin^4 u/u^3 du (PHYSICS.md 1.3). For f_low -> 0 and
    f_high tau >> 1 this tends to (2 ln 2/pi) B^2 = 0.4413 B^2.
    """
    tau = np.asarray(tau, dtype=float)
    return (2.0 * b**2 / np.pi) * (_flicker_kernel(np.pi * f_high * tau) - _flicker_kernel(np.pi * f_low * tau))


@dataclass(frozen=True, slots=True, kw_only=True)
class NoiseModel:
    """IEEE Std 952 rate-noise model; every field in SI (see :mod:`sim.units`).

    Parameters
    ----------
    quantization : float
        Q [rad]. White angle noise of std Q, differenced: AVAR 3 Q^2/tau^2.
    angle_random_walk : float
        N [rad/sqrt(s)]. White rate noise, two-sided PSD N^2: AVAR N^2/tau.
    bias_instability : float
        B [rad/s]. Flicker rate noise, PSD B^2/(2 pi f) over ``flicker_band``:
        AVAR plateau (2 ln2/pi) B^2, ADEV minimum 0.664 B.
    rate_random_walk : float
        K [rad/s/sqrt(s)]. Integrated white rate noise: AVAR K^2 tau/3.
    rate_ramp : float
        R [rad/s^2]. Deterministic ramp R t: AVAR R^2 tau^2/2.
    flicker_band : tuple of float
        (f_low, f_high) [Hz], the band over which the bias-instability PSD is 1/f.
        f_high is capped at fs/2 when generating. Default (1e-6 Hz, inf): flat
        ADEV from ~1.6/f_high up to ~0.05/f_low = 14 h.
    gauss_markov : tuple of GaussMarkov
        Extra first-order Gauss-Markov terms.
    sinusoids : tuple of Sinusoid
        Deterministic sinusoidal terms.
    bias : float
        Constant bias b0 [rad/s] (invisible to Allan variance).

    Examples
    --------
    >>> import numpy as np
    >>> m = NoiseModel.from_datasheet(angle_random_walk=0.01, bias_instability=0.05)
    >>> y = m.generate(1000, fs=100.0, rng=np.random.default_rng(1))
    >>> y.shape
    (1000,)
    """

    quantization: float = 0.0
    angle_random_walk: float = 0.0
    bias_instability: float = 0.0
    rate_random_walk: float = 0.0
    rate_ramp: float = 0.0
    flicker_band: tuple[float, float] = (1e-6, math.inf)
    gauss_markov: tuple[GaussMarkov, ...] = field(default_factory=tuple)
    sinusoids: tuple[Sinusoid, ...] = field(default_factory=tuple)
    bias: float = 0.0

    def __post_init__(self) -> None:
        for f in fields(self):
            if f.name in ("quantization", "angle_random_walk", "bias_instability", "rate_random_walk", "rate_ramp"):
                _check_nonneg("NoiseModel", f.name, getattr(self, f.name))
        lo, hi = self.flicker_band
        if not (0.0 < lo < hi):
            raise ValueError(f"NoiseModel.flicker_band must satisfy 0 < f_low < f_high [Hz]; got {self.flicker_band!r}")
        if not math.isfinite(self.bias):
            raise ValueError(f"NoiseModel.bias must be finite [rad/s]; got {self.bias!r}")
        for name, kind in (("gauss_markov", GaussMarkov), ("sinusoids", Sinusoid)):
            terms = getattr(self, name)
            if not isinstance(terms, tuple) or not all(isinstance(t, kind) for t in terms):
                raise TypeError(f"NoiseModel.{name} must be a tuple of {kind.__name__}; got {terms!r}")
        if len(self.gauss_markov) > _N_SLOTS - _SLOT_GM0:
            raise ValueError(
                f"NoiseModel.gauss_markov holds at most {_N_SLOTS - _SLOT_GM0} terms; got {len(self.gauss_markov)}"
            )

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_datasheet(
        cls,
        *,
        quantization: float = 0.0,
        angle_random_walk: float = 0.0,
        bias_instability: float = 0.0,
        rate_random_walk: float = 0.0,
        rate_ramp: float = 0.0,
        bias: float = 0.0,
        **kwargs,
    ) -> NoiseModel:
        """Build a model from field units.

        Parameters
        ----------
        quantization : float
            Q [arcsec].
        angle_random_walk : float
            N [deg/sqrt(h)].
        bias_instability : float
            B [deg/h] (the IEEE coefficient, i.e. ADEV minimum / 0.664).
        rate_random_walk : float
            K [deg/h/sqrt(h)].
        rate_ramp : float
            R [deg/h^2].
        bias : float
            Constant bias [deg/h].
        **kwargs
            ``flicker_band``, ``gauss_markov``, ``sinusoids`` passed through (SI).
        """
        unknown = set(kwargs) - {"flicker_band", "gauss_markov", "sinusoids"}
        if unknown:
            raise TypeError(f"NoiseModel.from_datasheet got unknown keyword(s) {sorted(unknown)}")
        for name, v in (
            ("quantization", quantization),
            ("angle_random_walk", angle_random_walk),
            ("bias_instability", bias_instability),
            ("rate_random_walk", rate_random_walk),
            ("rate_ramp", rate_ramp),
        ):
            _check_nonneg("NoiseModel.from_datasheet", name, v)
        return cls(
            quantization=units.arcsec(quantization),
            angle_random_walk=units.deg_per_sqrt_h(angle_random_walk),
            bias_instability=units.deg_per_h(bias_instability),
            rate_random_walk=units.deg_per_h_per_sqrt_h(rate_random_walk),
            rate_ramp=units.deg_per_h2(rate_ramp),
            bias=units.deg_per_h(bias),
            **kwargs,
        )

    def to_datasheet(self) -> dict[str, float]:
        """The five coefficients in field units: Q arcsec, N deg/sqrt(h), B deg/h, K deg/h/sqrt(h), R deg/h^2."""
        return {
            "Q": units.to_arcsec(self.quantization),
            "N": units.to_deg_per_sqrt_h(self.angle_random_walk),
            "B": units.to_deg_per_h(self.bias_instability),
            "K": units.to_deg_per_h_per_sqrt_h(self.rate_random_walk),
            "R": units.to_deg_per_h2(self.rate_ramp),
        }

    # ------------------------------------------------------------------ theory
    def effective_flicker_band(self, fs: float) -> tuple[float, float]:
        """The flicker band actually generated at sample rate ``fs`` [Hz]: f_high capped at fs/2."""
        lo, hi = self.flicker_band
        return lo, min(hi, fs / 2.0)

    def theoretical_avar(self, tau: ArrayLike, *, fs: float) -> NDArray[np.float64]:
        """Closed-form Allan variance [rad^2/s^2] at cluster times ``tau`` [s].

        Parameters
        ----------
        tau : array_like
            Cluster times [s], > 0 (normally multiples of 1/fs).
        fs : float
            Sample rate [Hz]: sets the quantization tau0 and the flicker band cap.

        Notes
        -----
        Sum of the term AVARs of PHYSICS.md 1.2 (independent terms add in AVAR):
        3Q^2/tau^2 + N^2/tau + flicker_avar(tau, B, band) + K^2 tau/3 + R^2 tau^2/2
        + Gauss-Markov and sinusoid terms.
        """
        tau = np.asarray(tau, dtype=float)
        if np.any(~(tau > 0)):
            raise ValueError("tau must be > 0 s everywhere")
        avar = (
            3.0 * self.quantization**2 / tau**2
            + self.angle_random_walk**2 / tau
            + self.rate_random_walk**2 * tau / 3.0
            + self.rate_ramp**2 * tau**2 / 2.0
        )
        if self.bias_instability > 0:
            avar = avar + flicker_avar(tau, self.bias_instability, *self.effective_flicker_band(fs))
        for gm in self.gauss_markov:
            avar = avar + gm.avar(tau)
        for s in self.sinusoids:
            avar = avar + s.avar(tau)
        return avar

    # ------------------------------------------------------------------ generation
    def stream(self, fs: float, *, rng: np.random.Generator, t0: float = 0.0) -> NoiseStream:
        """A :class:`NoiseStream` yielding this model's samples chunk by chunk."""
        return NoiseStream(self, fs, rng=rng, t0=t0)

    def generate(self, n: int, fs: float, *, rng: np.random.Generator, t0: float = 0.0) -> NDArray[np.float64]:
        """``n`` rate-error samples [rad/s] at ``fs`` [Hz]; identical to any chunking of :meth:`stream`."""
        return self.stream(fs, rng=rng, t0=t0).take(n)

    def components(
        self, n: int, fs: float, *, rng: np.random.Generator, t0: float = 0.0
    ) -> dict[str, NDArray[np.float64]]:
        """Each term's samples separately (the truth a Recording keeps); they sum to :meth:`generate`."""
        return self.stream(fs, rng=rng, t0=t0).take_components(n)


def _flicker_poles(b: float, f_low: float, f_high: float, dt: float) -> tuple[NDArray, NDArray]:
    """Gauss-Markov poles approximating B^2/(2 pi f) over [f_low, f_high].

    Two poles per decade of correlation time, T_i = T_min r^i, r = sqrt(10), each
    with stationary variance sigma_i^2 = B^2 ln(r)/pi (PHYSICS.md 2, GM-sum
    weights, DERIVED there): ADEV within 0.4 % of the ideal plateau and PSD ripple
    +-0.05 dB inside the band. T_min = 1/(2 pi f_high), T_max = 1/(2 pi f_low).
    """
    r = math.sqrt(10.0)
    t_min = 1.0 / (2.0 * math.pi * f_high)
    t_max = 1.0 / (2.0 * math.pi * f_low)
    n_poles = max(1, int(math.ceil(math.log(t_max / t_min) / math.log(r) - 1e-9)) + 1)
    tc = t_min * r ** np.arange(n_poles)
    sig = np.full(n_poles, b * math.sqrt(math.log(r) / math.pi))
    del dt
    return tc, sig


class NoiseStream:
    """Chunked generator for a :class:`NoiseModel`; state carried between chunks.

    The concatenation of ``take(n1)``, ``take(n2)``, ... equals ``take(n1 + n2 + ...)``
    bit for bit: every process draws sequentially from its own child stream and
    every recursion carries its state.
    """

    def __init__(self, model: NoiseModel, fs: float, *, rng: np.random.Generator, t0: float = 0.0) -> None:
        if not isinstance(rng, np.random.Generator):
            raise TypeError(f"rng must be a numpy.random.Generator; got {type(rng).__name__}")
        if not (isinstance(fs, (int, float)) and math.isfinite(fs) and fs > 0):
            raise ValueError(f"fs must be a finite number > 0 Hz; got {fs!r}")
        self.model = model
        self.fs = float(fs)
        self.dt = 1.0 / self.fs
        self.t0 = float(t0)
        self._k = 0  # samples emitted so far
        children = rng.spawn(_N_SLOTS)
        self._rng = children
        m = model
        # quantization: previous angle error
        self._q_prev = m.quantization * children[_SLOT_QUANT].standard_normal() if m.quantization > 0 else 0.0
        # flicker as a GM sum
        if m.bias_instability > 0:
            lo, hi = m.effective_flicker_band(self.fs)
            self._fl_tc, fl_sig = _flicker_poles(m.bias_instability, lo, hi, self.dt)
            self._fl_phi = np.exp(-self.dt / self._fl_tc)
            self._fl_gain = fl_sig * np.sqrt(-np.expm1(-2.0 * self.dt / self._fl_tc))
            self._fl_state = fl_sig * children[_SLOT_FLICKER].standard_normal(len(self._fl_tc))
        self._rrw = 0.0
        self._gm_state = [
            gm.sigma * children[_SLOT_GM0 + i].standard_normal() for i, gm in enumerate(m.gauss_markov)
        ]

    def take_components(self, n: int) -> dict[str, NDArray[np.float64]]:
        """The next ``n`` samples of every present term [rad/s], by term name."""
        if not (isinstance(n, (int, np.integer)) and n >= 0):
            raise ValueError(f"n must be an integer >= 0; got {n!r}")
        m, fs, dt = self.model, self.fs, self.dt
        out: dict[str, NDArray[np.float64]] = {}
        t = self.t0 + (self._k + np.arange(n)) * dt
        if m.quantization > 0:
            e = m.quantization * self._rng[_SLOT_QUANT].standard_normal(n)
            y = np.empty(n)
            if n:
                y[0] = e[0] - self._q_prev
                y[1:] = np.diff(e)
                self._q_prev = e[-1]
            out["quantization"] = y * fs
        if m.angle_random_walk > 0:
            out["angle_random_walk"] = m.angle_random_walk * math.sqrt(fs) * self._rng[_SLOT_ARW].standard_normal(n)
        if m.bias_instability > 0:
            eps = self._rng[_SLOT_FLICKER].standard_normal((n, len(self._fl_tc)))
            y = np.zeros(n)
            for i, (phi, gain) in enumerate(zip(self._fl_phi, self._fl_gain)):
                xi, zf = signal.lfilter([gain], [1.0, -phi], eps[:, i], zi=[phi * self._fl_state[i]])
                if n:
                    self._fl_state[i] = xi[-1]
                y += xi
            out["bias_instability"] = y
        if m.rate_random_walk > 0:
            steps = m.rate_random_walk * math.sqrt(dt) * self._rng[_SLOT_RRW].standard_normal(n)
            if n:
                steps[0] += self._rrw  # carry folded into the first step: same rounding as one-shot
            x = np.cumsum(steps)
            if n:
                self._rrw = x[-1]
            out["rate_random_walk"] = x
        if m.rate_ramp > 0:
            out["rate_ramp"] = m.rate_ramp * t
        for i, gm in enumerate(m.gauss_markov):
            phi = math.exp(-dt / gm.correlation_time)
            gain = gm.sigma * math.sqrt(-math.expm1(-2.0 * dt / gm.correlation_time))
            eps = self._rng[_SLOT_GM0 + i].standard_normal(n)
            x, _ = signal.lfilter([gain], [1.0, -phi], eps, zi=[phi * self._gm_state[i]])
            if n:
                self._gm_state[i] = x[-1]
            out[f"gauss_markov_{i}"] = x
        for i, s in enumerate(m.sinusoids):
            out[f"sinusoid_{i}"] = s.amplitude * np.sin(2.0 * np.pi * s.frequency * t + s.phase)
        if m.bias != 0:
            out["bias"] = np.full(n, m.bias)
        self._k += n
        return out

    def take(self, n: int) -> NDArray[np.float64]:
        """The next ``n`` samples of the summed rate error [rad/s]."""
        comps = self.take_components(n)
        total = np.zeros(n)
        for v in comps.values():
            total += v
        return total

    def chunks(self, n: int, chunk: int = 1 << 20) -> Iterator[NDArray[np.float64]]:
        """Yield the next ``n`` samples in chunks of at most ``chunk`` samples."""
        if chunk <= 0:
            raise ValueError(f"chunk must be > 0 samples; got {chunk!r}")
        left = n
        while left > 0:
            k = min(chunk, left)
            yield self.take(k)
            left -= k
