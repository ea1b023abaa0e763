"""IEEE Std 952 rate-noise model: closed-form Allan variance and fast, chunkable generation.

All parameters are in SI (see :mod:`gyrobench.base.units`); field units enter only through
:meth:`NoiseModel.from_datasheet`.

The model is a sum of independent processes, each generated from its own child
random stream (fixed slots of ``rng.spawn(64)``) so that adding a term never
changes another term's samples:

=========================  ====================  ==========================================
term                       field                 two-sided rate PSD S(f)
=========================  ====================  ==========================================
quantization Q             ``quantization``       (4 Q^2/tau0) sin^2(pi f tau0)  [rad]
angle random walk N        ``angle_random_walk``  N^2  [rad/sqrt(s)]
bias instability B         ``bias_instability``   B^2/(2 pi f) inside ``flicker_band``  [rad/s]
rate random walk K         ``rate_random_walk``   (K/(2 pi f))^2  [rad/s/sqrt(s)]
rate ramp R                ``rate_ramp``          R t (deterministic)  [rad/s^2]
Gauss-Markov (sigma, Tc)   ``gauss_markov``       2 sigma^2 Tc/(1 + (2 pi f Tc)^2)
sinusoid (A, f0, phase)    ``sinusoids``          (A^2/4)[delta(f-f0) + delta(f+f0)]
=========================  ====================  ==========================================

Discretisation (what a sample is), and the Allan variance that goes with it
---------------------------------------------------------------------------
Sample k (k = 0, 1, ...) sits at t_k = t0 + k tau0, tau0 = 1/fs.

* Q: white angle error e_k, uniform on [-q/2, q/2) with q = sqrt(12) Q (the
  rounding error of a pulse-counting readout; variance Q^2), differenced:
  y_k = (e_k - e_{k-1})/tau0 (drawn as q u_k, u ~ U[0, 1): the offset cancels).
  AVAR = 3 Q^2/tau^2 exactly at every tau = m tau0.
* N: y_k = N sqrt(fs) eps_k (the mean of white rate noise over the sample
  interval). AVAR = N^2/tau exactly.
* K: the point-sampled random walk x_k = x_{k-1} + K sqrt(tau0) eps_k. Its AVAR
  at tau = m tau0 is NOT the continuous K^2 tau/3 but (DERIVED, sum of squared
  weights of the increments in the difference of two block means)
  ``K^2 tau/3 * (1 + 1/(2 m^2))`` (1.5x at m = 1, +3 % at m = 4), which
  :meth:`NoiseModel.theoretical_avar` returns.
* Gauss-Markov: exact AR(1) point samples (phi = exp(-tau0/Tc), stationary
  start). AVAR at tau = m tau0 is the exact discrete expression of
  :func:`ar1_avar` (it tends to the continuous docs/physics.md 1.2 formula for Tc >> tau0).
* B: a sum of Gauss-Markov poles (below), each with the exact discrete AVAR.
* ramp R t_k and sinusoids A sin(2 pi f0 t_k + phase) are point values; the
  sampled sinusoid's AVAR is the continuous one times (x/sin x)^2,
  x = pi f0 tau0 (DERIVED: block means of a sampled sine are Dirichlet sums), so
  its zeros stay at tau = k/f0.

Bias instability (flicker) by a pole sum, generated at several rates
--------------------------------------------------------------------
B is realised as M independent first-order Gauss-Markov processes with
correlation times T_i = T_min r^i, r = sqrt(10) (two poles per decade) and
stationary variances sigma_i^2 = B^2 ln(r)/pi (docs/physics.md section 2, GM-sum
weights); T_min = sqrt(r)/(2 pi f_high) (midpoint rule: the first pole stands
for the slice of ln T starting at 1/(2 pi f_high)), T_max >= 1/(2 pi f_low);
f_high is capped at fs/2. Computed for the sampled pole sum (see
``tests/sim/test_noise.py``): with f_high = fs/2 (default) its PSD equals
B^2/(2 pi f) within +-0.15 dB from 9 f_low to fs/3 (+-0.5 dB from 2.8 f_low to
0.42 fs), and its ADEV equals the plateau 0.6643 B within +-1 % for
3.5/fs <= tau <= 0.014/f_low (+-0.3 % for 5.2/fs <= tau <= 0.0042/f_low): with the
default band (1e-6 Hz, inf) at fs = 100 Hz that is 0.035 s .. 3.9 h, 5.6
decades. A user f_high below fs/2 is a first-order roll-off (-3 dB at f_high),
not the brick wall of :func:`flicker_avar`. :meth:`NoiseModel.theoretical_avar`
returns the exact discrete AVAR of this pole sum, not the brick-wall formula.

Generation spends one normal draw per output sample on all the fast poles
together and 1/15 of a draw on all the slow ones:

* poles are grouped in levels l = 0, 1, ...; level l runs at step
  h_l = 16^l tau0 and holds the poles with 256 h_l <= T_i < 4096 h_l (level 0:
  every T_i < 4096 tau0, i.e. 8 poles in 4 second-order sections when f_high = fs/2);
* the poles of one level are generated together as ONE ARMA process driven by
  one white sequence, with exactly the power spectrum of the sum of those
  independent AR(1) poles (spectral factorisation, :func:`_sum_of_ar1_as_arma`),
  started in its stationary state (discrete Lyapunov equation);
* a coarse level is linearly interpolated onto the next finer level's grid
  (knots on the fine grid, so nested interpolation equals direct interpolation),
  plus a discrete Brownian bridge (zero at the coarse knots) whose rate is the sum
  of 2 sigma_i^2/T_i over the coarser poles: on scales << T_i a pole is a Brownian
  motion, and motion = interpolated knots + independent bridges (Levy construction).
  Between the full-rate grid and the first decimated level the bridge costs one
  draw per sample; it is added only when the decimated poles' Brownian rate exceeds
  1e-3 of the full-rate poles' (always when f_high is so low that no pole runs at
  full rate), not for the default band, where the fast poles dominate short tau.

Decimation error (documented, not in ``theoretical_avar``), evaluated exactly from
the phase-averaged autocovariances (``tests/sim/test_noise.py``): a pole interpolated
from knots every h with its bridge has the AVAR of the full-rate pole to 2.5e-6
relative at T/h = 256 (O((h/T)^2)); without the bridge it would lose up to 94 % of
its AVAR at tau << h. For the default band (no full-rate bridge) the generated
flicker AVAR is below that of the full-rate pole sum by less than 0.1 % of the
flicker AVAR at every tau (ADEV < 0.05 %), far below the scatter of any realistic
record. Values are otherwise exact: the level filters realise the spectral factors
to ~1e-9 (second-order sections pairing slow with fast roots).

Cost (``benchmarks/bench_noise.py``; CPU time per sample in units of one
``standard_normal`` draw, one core): Q 0.35 (one uniform draw scaled in place, one
difference), N 1.1 (one draw scaled in place), B 2.4 (one draw, four second-order sections,
interpolation, 1/15 draw for the slow levels), K 1.5 (one draw, a cumulative sum), R 0.15;
the five-term model about 5.5 (0.18 x the plain-draw rate). N, B and K each draw from their
own child stream (so adding a term leaves the others' samples unchanged), which bounds any
generator of these values below 1/3 of the plain-draw rate. When a core is idle the next
block's draws are made in a worker thread (``_PREFETCH``, never changing the values): measured
0.22 x the plain-draw rate in wall time on the 2-core machine (0.15 x without the thread).

References
----------
IEEE Std 952-1997 Annex C; docs/physics.md sections 1-2; N. J. Kasdin, "Discrete
simulation of colored noise and stochastic processes and 1/f^alpha power law
noise generation", Proc. IEEE 83(5), 1995; W. A. Riley, NIST SP 1065 (2008).
"""

from __future__ import annotations

import functools
import math
import os
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field, fields
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import linalg, optimize, signal, special

from gyrobench.base import units
from gyrobench.base.ranges import Constraint, FieldRange, shown, validate
from gyrobench.base.validate import check_fs as _check_fs
from gyrobench.base.validate import nonneg_coefficient

__all__ = [
    "GaussMarkov",
    "Sinusoid",
    "NoiseModel",
    "NoiseStream",
    "flicker_avar",
    "ar1_avar",
    "gm_avar",
]

#: child-stream slots: a term always draws from the same slot, whatever else the model holds
_SLOT_QUANT, _SLOT_ARW, _SLOT_FLICKER, _SLOT_RRW, _SLOT_GM0 = 0, 1, 2, 3, 8
_N_SLOTS = 64
_LN2 = math.log(2.0)

#: flicker pole ratio (two poles per decade)
_POLE_RATIO = math.sqrt(10.0)
#: a pole is generated at step h only if its correlation time is >= _DECIM_MARGIN * h
_DECIM_MARGIN = 256
#: add the full-rate Brownian bridge of the decimated poles when their Brownian rate exceeds
#: this fraction of the full-rate poles' (always when there are no full-rate poles)
_BRIDGE_REL = 1e-3
#: rate ratio between consecutive flicker levels
_LEVEL_RATIO = 16
_MAX_LEVELS = 32
#: samples per internal block (keeps the working set in cache; has no effect on values)
_BLOCK = 1 << 16
#: compute the next block's quantization draws and flicker term in a worker thread while the
#: caller does the rest (:meth:`NoiseStream._blocks`): True, False, or "auto" (only when a core
#: looks idle: 1-min load average < cpu count - 1). Has no effect on values; measured to help
#: on an idle 2-core machine and to hurt on a saturated one.
_PREFETCH: bool | str = "auto"
_EXECUTOR = None
#: the sources drawn in the worker thread with the flicker term (:meth:`NoiseStream._ahead`)
_AHEAD = frozenset({"q", "fl"})
#: largest batch of knots a decimated flicker level generates ahead
_COARSE_BATCH = 1 << 15


def _use_prefetch() -> bool:
    if _PREFETCH != "auto":
        return bool(_PREFETCH)
    try:
        return os.getloadavg()[0] < (os.cpu_count() or 1) - 1
    except (OSError, AttributeError):
        return False


def _forget_executor_in_child() -> None:
    # a forked child inherits the executor object but not its thread: start afresh
    global _EXECUTOR
    _EXECUTOR = None


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_executor_in_child)


def _executor():
    global _EXECUTOR
    if _EXECUTOR is None:
        from concurrent.futures import ThreadPoolExecutor

        _EXECUTOR = ThreadPoolExecutor(max_workers=1, thread_name_prefix="sim-noise-draws")
    return _EXECUTOR


#: largest noise coefficient accepted [SI]: its square and the variances built from it stay
#: far from float64 overflow (1.8e308), so a wrong unit fails here, not as a NaN downstream
_MAX_COEFFICIENT = 1e100


# ---------------------------------------------------------------------------- closed forms
def _g_series(r: NDArray[np.float64]) -> NDArray[np.float64]:
    """g(r) = 2r - 3 + 4 e^{-r} - e^{-2r}, accurate for all r >= 0 (series below r = 0.5).

    g(r) = sum_{k>=3} (-1)^k (4 - 2^k) r^k / k!  (= 2r^3/3 - r^4/2 + ...).
    """
    r = np.asarray(r, dtype=float)
    out = np.empty_like(r)
    small = r < 0.5
    rs = r[small]
    acc = np.zeros_like(rs)
    term = rs**3 / 6.0  # r^k/k! for k = 3
    for k in range(3, 24):
        acc += (-1) ** k * (4.0 - 2.0**k) * term
        term = term * rs / (k + 1)
    out[small] = acc
    rl = r[~small]
    out[~small] = 2.0 * rl + 4.0 * np.expm1(-rl) - np.expm1(-2.0 * rl)
    return out


def _sinh_minus_x(u: NDArray[np.float64]) -> NDArray[np.float64]:
    """sinh(u) - u without cancellation."""
    u = np.asarray(u, dtype=float)
    out = np.empty_like(u)
    small = u < 0.1
    us = u[small]
    out[small] = us**3 / 6.0 * (1.0 + us**2 / 20.0 * (1.0 + us**2 / 42.0 * (1.0 + us**2 / 72.0)))
    out[~small] = np.sinh(u[~small]) - u[~small]
    return out


def gm_avar(tau: ArrayLike, sigma: float, tc: float) -> NDArray[np.float64]:
    """Continuous-time Allan variance of a first-order Gauss-Markov process [rad^2/s^2].

    sigma^2 g(r)/r^2, r = tau/Tc, g(r) = 2r - 3 + 4e^{-r} - e^{-2r}; equal to
    docs/physics.md 1.2 (qc Tc)^2/tau [1 - Tc/(2tau)(3 - 4e^{-r} + e^{-2r})] with
    qc^2 = 2 sigma^2/Tc, evaluated without cancellation at small r.

    Parameters
    ----------
    tau : array_like
        Cluster times [s].
    sigma : float
        Standard deviation of the process [rad/s].
    tc : float
        Correlation time Tc [s].

    Returns
    -------
    ndarray
        sigma^2(tau) [rad^2/s^2].
    """
    r = np.asarray(tau, dtype=float) / tc
    return sigma**2 * _g_series(r) / r**2


def ar1_avar(
    m: ArrayLike, u: float | ArrayLike, var: float | ArrayLike = 1.0
) -> NDArray[np.float64]:
    """Exact overlapping-AVAR expectation of point samples of a Gauss-Markov process.

    Parameters
    ----------
    m : array_like
        Cluster size tau/tau0 (>= 1; evaluated analytically for real m).
    u : float or array_like
        tau0/Tc (sampling step over correlation time), > 0.
    var : float or array_like
        Stationary variance sigma^2 [rad^2/s^2].

    Returns
    -------
    ndarray
        AVAR [rad^2/s^2], broadcast over ``m`` and ``u``.

    Notes
    -----
    x_k = phi x_{k-1} + sigma sqrt(1-phi^2) eps_k, phi = e^{-u}, autocovariance
    sigma^2 phi^|j|. With D(n) = Var(sum_{k=1}^n x_k) the overlapping AVAR is
    (4 D(m) - D(2m))/(2 m^2) (DERIVED: theta-second difference). Written
    without cancellation (DERIVED from D(n) = sigma^2 [n coth(u/2) -
    (1 - phi^n)/(2 sinh^2(u/2))]):

        AVAR/sigma^2 = [ m (sinh u - u)/(2 sinh^2(u/2)) + g(m u)/(4 sinh^2(u/2)) ] / m^2,

    g(r) = 2r - 3 + 4e^{-r} - e^{-2r}. For u -> 0 at fixed m u = tau/Tc it tends
    to the continuous sigma^2 g(r)/r^2 (:func:`gm_avar`); for u -> inf to sigma^2/m
    (white). The rate-random-walk limit (u -> 0, qc^2 = 2 sigma^2/Tc fixed) gives
    K^2 tau/3 (1 + 1/(2 m^2)).
    """
    m = np.asarray(m, dtype=float)
    u = np.minimum(np.asarray(u, dtype=float), 50.0)
    m, u = np.broadcast_arrays(m, u)
    s2 = np.sinh(u / 2.0) ** 2
    return (
        np.asarray(var) * (m * _sinh_minus_x(u) / (2.0 * s2) + _g_series(m * u) / (4.0 * s2)) / m**2
    )


def _flicker_kernel(x: NDArray[np.float64]) -> NDArray[np.float64]:
    """F(x) = Int_0^x sin^4 u / u^3 du, closed form (docs/physics.md 1.3).

    F(x) = ln2 - sin^3 x (sin x + 4 x cos x)/(2 x^2) + Ci(2x) - Ci(4x); F(0) = 0;
    for x < 1e-3 the series F ~ x^2/2 avoids cancellation.
    """
    x = np.asarray(x, dtype=float)
    out = np.empty_like(x)
    small = x < 1e-3
    xs = x[small]
    out[small] = xs**2 / 2.0
    xl = x[~small]
    with np.errstate(invalid="ignore"):
        s, c = np.sin(xl), np.cos(xl)
        out[~small] = (
            _LN2
            - s**3 * (s + 4.0 * xl * c) / (2.0 * xl**2)
            + special.sici(2.0 * xl)[1]
            - special.sici(4.0 * xl)[1]
        )
    out[np.isinf(x)] = _LN2
    return out


def flicker_avar(tau: ArrayLike, b: float, f_low: float, f_high: float) -> NDArray[np.float64]:
    """Allan variance of ideal (brick-wall) band-limited flicker rate noise.

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
    F(x) = Int_0^x sin^4 u/u^3 du (docs/physics.md 1.3). For f_low -> 0 and
    f_high tau >> 1 this tends to (2 ln 2/pi) B^2 = 0.4413 B^2; for tau << 1/f_high
    (f_low = 0) to pi B^2 f_high^2 tau^2. This is the IEEE reference curve; the
    generator realises the smooth-edged pole sum of :meth:`NoiseModel.flicker_poles`.

    Returns
    -------
    ndarray
        sigma^2(tau) [rad^2/s^2].
    """
    tau = np.asarray(tau, dtype=float)
    return (2.0 * b**2 / np.pi) * (
        _flicker_kernel(np.pi * f_high * tau) - _flicker_kernel(np.pi * f_low * tau)
    )


def _coefficient(unit: str, what: str, *, low_open: bool = False) -> FieldRange:
    """The declared range of a noise coefficient: >= 0 (> 0 when ``low_open``) and <= 1e100 SI."""
    return FieldRange(
        0, _MAX_COEFFICIENT, unit, f"{what}; <= 1e100 SI: no gyro comes near it, and the variances square it",
        low_open=low_open,
    )


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
    Continuous AVAR (docs/physics.md 1.2, qc^2 = 2 sigma^2/Tc):
    (qc Tc)^2/tau [1 - Tc/(2 tau)(3 - 4 e^{-tau/Tc} + e^{-2 tau/Tc})]; the sampled
    process follows :func:`ar1_avar` (:meth:`avar_sampled`).
    """

    sigma: float
    correlation_time: float

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "sigma": _coefficient("rad/s", "stationary standard deviation"),
        "correlation_time": _coefficient("s", "correlation time Tc", low_open=True),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared specs above

    def avar(self, tau: ArrayLike) -> NDArray[np.float64]:
        """Continuous-time Allan variance [rad^2/s^2] at cluster times ``tau`` [s]."""
        return gm_avar(tau, self.sigma, self.correlation_time)

    def avar_sampled(self, tau: ArrayLike, fs: float) -> NDArray[np.float64]:
        """Allan variance [rad^2/s^2] of the process sampled at ``fs`` [Hz]; :func:`ar1_avar`."""
        m = np.asarray(tau, dtype=float) * fs
        return ar1_avar(m, 1.0 / (fs * self.correlation_time), self.sigma**2)


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

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "amplitude": _coefficient("rad/s", "amplitude A"),
        "frequency": _coefficient("Hz", "frequency f0", low_open=True),
        "phase": FieldRange(-math.inf, math.inf, "rad", "phase at t = 0"),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared specs above

    def avar(self, tau: ArrayLike) -> NDArray[np.float64]:
        """Continuous AVAR = A^2 (sin^2(pi f0 tau)/(pi f0 tau))^2 (docs/physics.md 1.2)."""
        x = np.pi * self.frequency * np.asarray(tau, dtype=float)
        return self.amplitude**2 * (np.sin(x) ** 2 / x) ** 2

    def avar_sampled(self, tau: ArrayLike, fs: float) -> NDArray[np.float64]:
        """AVAR of the point-sampled sine: A^2 sin^4(pi f0 tau)/(m sin(pi f0/fs))^2, m = tau fs.

        Phase-averaged (DERIVED: a block mean of m samples is a Dirichlet sum
        sin(m x)/(m sin x) times a sine, x = pi f0/fs); equals :meth:`avar` times
        (x/sin x)^2, and is 0 when f0 is a multiple of fs (the samples are constant).
        """
        tau = np.asarray(tau, dtype=float)
        m = tau * fs
        sx = math.sin(math.pi * self.frequency / fs)
        if abs(sx) < 1e-15:
            return np.zeros_like(tau)
        return self.amplitude**2 * np.sin(np.pi * self.frequency * tau) ** 4 / (m * sx) ** 2


# ---------------------------------------------------------------------------- flicker machinery
def _pole_times(f_low: float, f_high: float) -> NDArray[np.float64]:
    """Pole correlation times T_i = T_min r^i [s] up to T_max >= 1/(2 pi f_low).

    T_min = sqrt(r)/(2 pi f_high).

    Each pole stands for a slice of width ln r in ln T centred on T_i (midpoint
    rule), so the first slice starts at T_min/sqrt(r) = 1/(2 pi f_high).
    """
    t_min = math.sqrt(_POLE_RATIO) / (2.0 * math.pi * f_high)
    t_max = 1.0 / (2.0 * math.pi * f_low)
    n_poles = max(1, int(math.ceil(math.log(t_max / t_min) / math.log(_POLE_RATIO) - 1e-9)) + 1)
    return np.asarray(t_min * _POLE_RATIO ** np.arange(n_poles), dtype=np.float64)


def _sum_of_ar1_as_arma(u: NDArray[np.float64], var: NDArray[np.float64]):
    """One ARMA(P, P-1) filter whose output has the spectrum of P independent AR(1) poles.

    Parameters
    ----------
    u : ndarray
        h/T_i for each pole (step over correlation time), > 0, distinct.
    var : ndarray
        Stationary variances sigma_i^2.

    Returns
    -------
    b, a : ndarray
        lfilter coefficients (unit-variance white input).
    rho, phi, u : ndarray
        Partial-fraction form H(z) = sum_i rho_i/(1 - phi_i z^-1) (poles sorted by u).
    zeta, g : ndarray, float
        Zeros and gain: H(z) = g prod(1 - zeta_k z^-1)/prod(1 - phi_i z^-1).

    Notes
    -----
    With v = cos(omega) - 1, each pole's spectrum is
    sigma_i^2 (1-phi_i^2)/|1 - phi_i e^{-i omega}|^2 = c_i/(w_i - v),
    c_i = sigma_i^2 sinh(u_i), w_i = 2 sinh^2(u_i/2). The sum sum_i c_i/(w_i - v)
    increases monotonically between consecutive w_i, so its numerator has exactly
    one root x_k in each gap (found by bracketing, robust however close the poles
    are to 1); each root gives a zero zeta_k = exp(-2 asinh(sqrt(x_k/2))) inside
    the unit circle. Hence S = g^2 |prod(1 - zeta_k z^-1)|^2/|prod(1 - phi_i z^-1)|^2
    with g^2 = 2 sum(c_i) prod(phi_i)/prod(zeta_k): the minimum-phase spectral
    factor (DERIVED).
    """
    order = np.argsort(u)
    u = np.asarray(u, dtype=float)[order]
    var = np.asarray(var, dtype=float)[order]
    w = 2.0 * np.sinh(u / 2.0) ** 2
    c = var * np.sinh(u)
    p = len(u)
    mu = np.empty(p - 1)
    for k in range(p - 1):
        lo, hi = w[k], w[k + 1]
        gap = hi - lo

        def f(x: float) -> float:
            return float(np.sum(c / (w - x)))

        a_, b_ = lo + gap * 1e-13, hi - gap * 1e-13
        x = optimize.brentq(f, a_, b_, xtol=gap * 1e-15, rtol=4 * np.finfo(float).eps, maxiter=400)
        mu[k] = 2.0 * math.asinh(math.sqrt(x / 2.0))
    phi = np.exp(-u)
    zeta = np.exp(-mu)
    g = math.exp(0.5 * (math.log(2.0 * float(np.sum(c))) - float(np.sum(u)) + float(np.sum(mu))))
    b = g * np.poly(zeta) if p > 1 else np.array([g])
    a = np.poly(phi)
    # residues: rho_i = g prod_k (1 - zeta_k/phi_i) / prod_{m != i} (1 - phi_m/phi_i),
    # differences of roots via expm1
    rho = np.empty(p)
    for i in range(p):
        num = np.prod(np.exp(-mu) * np.expm1(mu - u[i]) / phi[i]) if p > 1 else 1.0
        others = np.delete(u, i)
        den = np.prod(np.exp(-others) * np.expm1(others - u[i]) / phi[i]) if p > 1 else 1.0
        rho[i] = g * num / den
    return b, a, rho, phi, u, zeta, g


def _sos_from_roots(zeta: NDArray, phi: NDArray, g: float) -> NDArray[np.float64]:
    """Second-order sections pairing the slowest with the fastest pole (and zero).

    Roots far apart keep each section's coefficients well conditioned: a pole at
    1 - 1e-3 is then realised to ~1e-13 relative, where one direct-form
    polynomial of order 8 moves it by ~1e-3 (measured).
    """
    p = len(phi)
    n_sec = (p + 1) // 2
    sos = np.zeros((n_sec, 6))
    zs = np.sort(zeta)[::-1]  # slowest (closest to 1) first
    ps = np.sort(phi)[::-1]
    nz_ = len(zs)
    zero_groups = [[zs[i], zs[nz_ - 1 - i]] for i in range(nz_ // 2)] + (
        [[zs[nz_ // 2]]] if nz_ % 2 else []
    )
    for s in range(n_sec):
        poles = [ps[s]] + ([ps[p - 1 - s]] if p - 1 - s != s else [])
        zeros = zero_groups[s] if s < len(zero_groups) else []
        a = np.poly(poles)
        b = np.poly(zeros) if zeros else np.array([1.0])
        sos[s, : len(b)] = b
        sos[s, 3 : 3 + len(a)] = a
    sos[0, :3] *= g
    return sos


def _sos_state_space(sos: NDArray) -> tuple[NDArray, NDArray]:
    """(A, B) of the scipy.signal.sosfilt state z = [z0_1, z1_1, z0_2, ...] (DF2T per section).

    Section s: y = b0 x + z0; z0' = b1 x - a1 y + z1; z1' = b2 x - a2 y; x_1 = eps, x_{s+1} = y_s.
    Rows are linear forms over [z; eps].
    """
    n_sec = sos.shape[0]
    n = 2 * n_sec
    a_mat = np.zeros((n, n + 1))
    x = np.zeros(n + 1)
    x[n] = 1.0  # input eps
    for s in range(n_sec):
        b0, b1, b2, _, a1, a2 = sos[s]
        z0 = np.zeros(n + 1)
        z0[2 * s] = 1.0
        z1 = np.zeros(n + 1)
        z1[2 * s + 1] = 1.0
        y = b0 * x + z0
        a_mat[2 * s] = b1 * x - a1 * y + z1
        a_mat[2 * s + 1] = b2 * x - a2 * y
        x = y
    return a_mat[:, :n], a_mat[:, n]


def _stationary_sos_zi(sos: NDArray, eps: NDArray) -> NDArray[np.float64]:
    """A sosfilt state drawn from the filter's stationary distribution (``eps`` ~ N(0, I)).

    Sigma = A Sigma A^T + B B^T (discrete Lyapunov equation), z = V sqrt(Lambda) eps.
    """
    a_mat, b_vec = _sos_state_space(sos)
    cov = linalg.solve_discrete_lyapunov(a_mat, np.outer(b_vec, b_vec))
    cov = 0.5 * (cov + cov.T)
    lam, vec = np.linalg.eigh(cov)
    z = vec @ (np.sqrt(np.clip(lam, 0.0, None)) * eps)
    return z.reshape(sos.shape[0], 2)


class _ArmaGen:
    """Sequential ARMA output from its own stream, started stationary; chunk-invariant."""

    def __init__(self, u: NDArray, var: NDArray, rng: np.random.Generator) -> None:
        _, _, _, phi, _, zeta, g = _sum_of_ar1_as_arma(u, var)
        self.sos = _sos_from_roots(zeta, phi, g)
        self.rng = rng
        self.zi = _stationary_sos_zi(self.sos, rng.standard_normal(2 * self.sos.shape[0]))

    def next(self, n: int, eps: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
        """The next ``n`` outputs; ``eps`` = the next ``n`` draws of ``self.rng`` if pre-drawn."""
        if eps is None:
            eps = self.rng.standard_normal(n)
        y, self.zi = signal.sosfilt(self.sos, eps, zi=self.zi)
        return y


class _Bridge:
    """Discrete Brownian bridges on consecutive intervals of ``ratio`` steps, zero at the knots.

    Row a holds B_0..B_{ratio-1} of interval a: W_j = sum of j steps ~ N(0, step_std^2),
    B_j = W_j - (j/ratio) W_ratio. Rows are drawn in order from ``rng`` (batch-invariant).
    """

    def __init__(self, ratio: int, step_std: float, rng: np.random.Generator) -> None:
        self.ratio, self.std, self.rng = ratio, step_std, rng
        self.rows = np.empty((0, ratio))
        self.row0 = 0
        self.batch = 1
        self.w = np.arange(1, ratio) / ratio

    def get(self, a0: int, a1: int) -> NDArray[np.float64]:
        """Rows for intervals a0..a1 (inclusive); a0 must not decrease between calls."""
        if a0 < self.row0:  # internal invariant: requests only move forward
            raise RuntimeError(f"bridge asked for interval {a0}; rows below {self.row0} are gone")
        end = self.row0 + len(self.rows)
        if a1 >= end:
            self.batch = min(max(1, _COARSE_BATCH // self.ratio), max(self.batch * 2, a1 + 1 - end))
            k = max(a1 + 1 - end, self.batch)
            walk = self.rng.normal(0.0, self.std, (k, self.ratio))
            np.cumsum(walk, axis=1, out=walk)
            rows = np.empty((k, self.ratio))
            rows[:, 0] = 0.0
            rows[:, 1:] = walk[:, :-1] - self.w[None, :] * walk[:, -1:]
            self.rows = np.concatenate([self.rows[a0 - self.row0 :], rows])
            self.row0 = a0
        out = self.rows[a0 - self.row0 : a1 + 1 - self.row0]
        self.rows = self.rows[a0 - self.row0 :]
        self.row0 = a0
        return out


class _CoarseLevel:
    """A decimated flicker level: its own ARMA plus the (interpolated) coarser levels.

    S[j] (j = 0, 1, ...) is the level's value at knot j; knots are ``ratio``
    samples of the next finer grid apart. ``get(j0, j1)`` returns S[j0:j1];
    requests must have non-decreasing j0 (values below j0 are then dropped).
    ``bridge`` (optional) adds the Brownian-bridge part of the coarser poles
    between the coarser knots.
    """

    def __init__(
        self,
        gen: _ArmaGen,
        coarser: _CoarseLevel | None,
        ratio_to_coarser: int,
        bridge: _Bridge | None = None,
    ) -> None:
        self.gen = gen
        self.coarser = coarser
        self.ratio = ratio_to_coarser
        self.bridge = bridge
        self.s = np.empty(0)
        self.s0 = 0  # index of s[0]
        self.batch = 16

    def get(self, j0: int, j1: int) -> NDArray[np.float64]:
        if j0 < self.s0:  # internal invariant: requests only move forward
            raise RuntimeError(f"flicker level asked for knot {j0}; knots below {self.s0} are gone")
        end = self.s0 + len(self.s)
        if j1 > end:
            # generate ahead in geometrically growing batches (few filter calls on long runs,
            # little waste on short ones); the values do not depend on the batch sizes
            self.batch = min(_COARSE_BATCH, max(self.batch * 2, j1 - end))
            stop = max(j1, end + self.batch)
            new = self.gen.next(stop - end)
            if self.coarser is not None:
                _interp_from(self.coarser, end, stop, self.ratio, out=new, bridge=self.bridge)
            self.s = np.concatenate([self.s[j0 - self.s0 :], new])
            self.s0 = j0
        out = self.s[j0 - self.s0 : j1 - self.s0]
        self.s = self.s[j0 - self.s0 :]
        self.s0 = j0
        return out


def _interp_from(
    level: _CoarseLevel,
    e: int,
    j1: int,
    ratio: int,
    out: NDArray[np.float64] | None = None,
    bridge: _Bridge | None = None,
):
    """Linear interpolation of ``level`` (knots every ``ratio`` samples) at fine indices [e, j1).

    Fine sample j = a ratio + r takes S[a] + (r/ratio)(S[a+1] - S[a]) (+ bridge row a,
    column r): the same arithmetic whatever the request boundaries. Added into ``out`` if given.
    """
    a0 = e // ratio
    a1 = (j1 - 1) // ratio
    s = level.get(a0, a1 + 2)
    w = np.arange(ratio) / ratio
    cov = np.multiply.outer(s[1:] - s[:-1], w)
    cov += s[:-1, None]
    if bridge is not None:
        cov += bridge.get(a0, a1)
    off = e - a0 * ratio
    fine = cov.reshape(-1)[off : off + (j1 - e)]
    if out is None:
        return fine
    out += fine
    return out


class _Flicker:
    """Multi-rate generator of the flicker pole sum (see the module docstring)."""

    def __init__(self, tc: NDArray, var: NDArray, dt: float, rng: np.random.Generator) -> None:
        ratio_t = tc / dt
        level = np.where(
            ratio_t < _DECIM_MARGIN * _LEVEL_RATIO,
            0,
            np.floor(np.log(ratio_t / _DECIM_MARGIN) / math.log(_LEVEL_RATIO) + 1e-12).astype(int),
        )
        level = np.maximum(level, 0)
        if level.max() >= _MAX_LEVELS:
            raise ValueError(
                f"flicker band too wide for {_MAX_LEVELS} levels; "
                f"got T_max/dt = {ratio_t.max():.3g}"
            )
        subs = rng.spawn(
            2 * _MAX_LEVELS
        )  # [0, L): level innovations, [L, 2L): bridges below level l
        diffusion = 2.0 * var / tc  # q_i [rad^2/s^3]: the Brownian rate of pole i on scales << T_i
        self.fine: _ArmaGen | None = None
        coarse: _CoarseLevel | None = None
        prev_l = 0
        for lv in sorted(set(level.tolist()), reverse=True):
            sel = level == lv
            step = _LEVEL_RATIO**lv
            gen = _ArmaGen(dt * step / tc[sel], var[sel], subs[lv])
            if lv == 0:
                self.fine = gen
            else:
                bridge = None
                if coarse is not None:
                    ratio = _LEVEL_RATIO ** (prev_l - lv)
                    q = float(np.sum(diffusion[level > lv]))
                    bridge = _Bridge(ratio, math.sqrt(q * dt * step), subs[_MAX_LEVELS + lv])
                else:
                    ratio = 1
                coarse = _CoarseLevel(gen, coarse, ratio, bridge)
                prev_l = lv
        self.coarse = coarse
        self.coarse_ratio = _LEVEL_RATIO**prev_l if coarse is not None else 1
        # bridge between the full-rate grid and the first decimated level: needed when the
        # decimated poles' Brownian rate is not negligible next to the full-rate poles'
        self.fine_bridge = None
        if coarse is not None:
            q_dec = float(np.sum(diffusion[level > 0]))
            q_fine = float(np.sum(diffusion[level == 0]))
            if q_dec > _BRIDGE_REL * q_fine:
                self.fine_bridge = _Bridge(
                    self.coarse_ratio, math.sqrt(q_dec * dt), subs[_MAX_LEVELS]
                )
        self.k = 0

    def next(self, n: int, eps: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
        """The next ``n`` samples; ``eps``: pre-drawn innovations of the full-rate level."""
        if self.fine is not None:
            y = self.fine.next(n, eps)
            if self.coarse is not None:
                _interp_from(
                    self.coarse,
                    self.k,
                    self.k + n,
                    self.coarse_ratio,
                    out=y,
                    bridge=self.fine_bridge,
                )
        else:
            assert self.coarse is not None  # __init__ builds a fine or a coarse level, or both
            y = _interp_from(
                self.coarse, self.k, self.k + n, self.coarse_ratio, bridge=self.fine_bridge
            ).copy()
        self.k += n
        return y


def _tuple_of(name: str, kind: type) -> Constraint:
    """The declared constraint that field ``name`` is a tuple of ``kind`` (a TypeError otherwise)."""

    def holds(c: Any) -> bool:
        v = getattr(c, name)
        return isinstance(v, tuple) and all(isinstance(t, kind) for t in v)

    def message(c: Any) -> str:
        return f"{name} must be a tuple of {kind.__name__}; got {shown(getattr(c, name))}"

    return Constraint(f"{name} is a tuple of {kind.__name__}", holds, message, TypeError)


@dataclass(frozen=True, slots=True, kw_only=True)
class NoiseModel:
    """IEEE Std 952 rate-noise model; every field in SI (see :mod:`gyrobench.base.units`).

    Parameters
    ----------
    quantization : float
        Q [rad]. White (uniform) angle noise of std Q, differenced: AVAR 3 Q^2/tau^2.
    angle_random_walk : float
        N [rad/sqrt(s)]. White rate noise, two-sided PSD N^2: AVAR N^2/tau.
    bias_instability : float
        B [rad/s]. Flicker rate noise, PSD B^2/(2 pi f) over ``flicker_band``
        (pole sum, module docstring): AVAR plateau (2 ln2/pi) B^2, ADEV minimum 0.664 B.
    rate_random_walk : float
        K [rad/s/sqrt(s)]. Integrated white rate noise: AVAR K^2 tau/3 (sampled:
        times 1 + 1/(2 m^2)).
    rate_ramp : float
        R [rad/s^2]. Deterministic ramp R t: AVAR R^2 tau^2/2.
    flicker_band : tuple of float
        (f_low, f_high) [Hz], the band over which the bias-instability PSD is 1/f.
        f_high is capped at fs/2 when generating. Default (1e-6 Hz, inf): ADEV
        flat within +-1 % for 3.5/fs <= tau <= 0.014/f_low = 3.9 h.
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

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "quantization": _coefficient("rad", "Q"),
        "angle_random_walk": _coefficient("rad/sqrt(s)", "N"),
        "bias_instability": _coefficient("rad/s", "B"),
        "rate_random_walk": _coefficient("rad/s/sqrt(s)", "K"),
        "rate_ramp": _coefficient("rad/s^2", "R"),
        "flicker_band": FieldRange(
            0, math.inf, "Hz", "(f_low, f_high) of the 1/f band; f_high may be inf (fs/2)", low_open=True, infinite=True
        ),
        "bias": FieldRange(-math.inf, math.inf, "rad/s", "constant bias b0, either sign"),
    }
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "0 < f_low < f_high, f_low finite",
            lambda c: len(c.flicker_band) == 2 and math.isfinite(c.flicker_band[0])
            and c.flicker_band[0] < c.flicker_band[1],
            lambda c: f"flicker_band must satisfy 0 < f_low < f_high [Hz]; got {c.flicker_band!r}",
        ),
        _tuple_of("gauss_markov", GaussMarkov),
        _tuple_of("sinusoids", Sinusoid),
        Constraint(
            f"at most {_N_SLOTS - _SLOT_GM0} gauss_markov terms",
            lambda c: len(c.gauss_markov) <= _N_SLOTS - _SLOT_GM0,
            lambda c: f"gauss_markov holds at most {_N_SLOTS - _SLOT_GM0} terms; got {len(c.gauss_markov)}",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above

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
            nonneg_coefficient("NoiseModel.from_datasheet", name, v, _MAX_COEFFICIENT)
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
        """The five coefficients in field units.

        Q arcsec, N deg/sqrt(h), B deg/h, K deg/h/sqrt(h), R deg/h^2.
        """
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

    def flicker_poles(self, fs: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The Gauss-Markov poles realising the bias instability at ``fs`` [Hz].

        Returns
        -------
        tc : ndarray
            Correlation times T_i = T_min sqrt(10)^i [s], T_min = 1/(2 pi f_high).
        sigma : ndarray
            Stationary std of each pole [rad/s], sigma_i^2 = B^2 ln(sqrt 10)/pi
            (docs/physics.md 2). Empty arrays when B = 0.
        """
        if self.bias_instability == 0:
            return np.empty(0), np.empty(0)
        tc = _pole_times(*self.effective_flicker_band(fs))
        sig = np.full(len(tc), self.bias_instability * math.sqrt(math.log(_POLE_RATIO) / math.pi))
        return tc, sig

    def term_avars(self, tau: ArrayLike, *, fs: float) -> dict[str, NDArray[np.float64]]:
        """Each term's Allan variance [rad^2/s^2], keyed like :meth:`components`."""
        _check_fs(fs)
        tau = np.asarray(tau, dtype=float)
        if np.any(~(tau > 0)):
            raise ValueError("tau must be > 0 s everywhere")
        m = tau * fs
        out: dict[str, NDArray[np.float64]] = {}
        if self.quantization > 0:
            out["quantization"] = 3.0 * self.quantization**2 / tau**2
        if self.angle_random_walk > 0:
            out["angle_random_walk"] = self.angle_random_walk**2 / tau
        if self.bias_instability > 0:
            tc, sig = self.flicker_poles(fs)
            out["bias_instability"] = np.sum(
                ar1_avar(m[..., None], 1.0 / (fs * tc), sig**2), axis=-1
            )
        if self.rate_random_walk > 0:
            out["rate_random_walk"] = self.rate_random_walk**2 * tau / 3.0 * (1.0 + 0.5 / m**2)
        if self.rate_ramp > 0:
            out["rate_ramp"] = self.rate_ramp**2 * tau**2 / 2.0
        for i, gm in enumerate(self.gauss_markov):
            out[f"gauss_markov_{i}"] = gm.avar_sampled(tau, fs)
        for i, s in enumerate(self.sinusoids):
            out[f"sinusoid_{i}"] = s.avar_sampled(tau, fs)
        return out

    def theoretical_avar(self, tau: ArrayLike, *, fs: float) -> NDArray[np.float64]:
        """Closed-form Allan variance [rad^2/s^2] of what :meth:`generate` produces at ``fs``.

        Parameters
        ----------
        tau : array_like
            Cluster times [s], > 0; exact at tau = m/fs (m = 1, 2, ...), for other
            tau the same analytic expressions are evaluated at real m = tau fs.
        fs : float
            Sample rate [Hz] (> 0).

        Notes
        -----
        Independent terms add in AVAR:
        3Q^2/tau^2 + N^2/tau + sum_i ar1_avar(m, tau0/T_i, sigma_i^2) (flicker poles)
        + K^2 tau/3 (1 + 1/(2m^2)) + R^2 tau^2/2 + Gauss-Markov (:func:`ar1_avar`)
        + sampled sinusoids (:meth:`Sinusoid.avar_sampled`). See the module docstring
        for the discretisation of each term and the (< 0.1 %) flicker decimation error
        this expression leaves out. The ideal brick-wall flicker curve is
        :func:`flicker_avar`.
        """
        terms = self.term_avars(tau, fs=fs)
        tau = np.asarray(tau, dtype=float)
        avar = np.zeros(tau.shape)
        for v in terms.values():
            avar = avar + v
        return avar

    # ------------------------------------------------------------------ generation
    def stream(self, fs: float, *, rng: np.random.Generator, t0: float = 0.0) -> NoiseStream:
        """A :class:`NoiseStream` yielding this model's samples chunk by chunk."""
        return NoiseStream(self, fs, rng=rng, t0=t0)

    def generate(
        self, n: int, fs: float, *, rng: np.random.Generator, t0: float = 0.0
    ) -> NDArray[np.float64]:
        """``n`` rate-error samples [rad/s] at ``fs`` [Hz]; equal to any chunking of a stream."""
        return self.stream(fs, rng=rng, t0=t0).take(n)

    def components(
        self, n: int, fs: float, *, rng: np.random.Generator, t0: float = 0.0
    ) -> dict[str, NDArray[np.float64]]:
        """Each term's samples (the truth a Recording keeps); they sum to :meth:`generate`."""
        return self.stream(fs, rng=rng, t0=t0).take_components(n)


def _scaled(draw: Callable[[int], NDArray[np.float64]], scale: float, n: int) -> NDArray[np.float64]:
    """``n`` draws of ``draw`` times ``scale``, in place.

    Bit for bit ``Generator.uniform(0, scale, n)`` for ``draw = Generator.random`` and
    ``Generator.normal(0, scale, n)`` for ``draw = Generator.standard_normal``: numpy computes those
    as ``0 + scale x`` from the same draws x (equal values; a -0.0 product would become +0.0).
    """
    x = draw(n)
    x *= scale
    return x


class NoiseStream:
    """Chunked generator for a :class:`NoiseModel`; state carried between chunks.

    The concatenation of ``take(n1)``, ``take(n2)``, ... equals ``take(n1 + n2 + ...)``
    bit for bit: every process draws sequentially from its own child stream,
    every recursion (random walk, AR(1)/ARMA filters) carries its state, and the
    decimated flicker levels keep the coarse knots they still need.

    Parameters
    ----------
    model : NoiseModel
        The noise terms.
    fs : float
        Sample rate [Hz].
    rng : numpy.random.Generator
        The stream's generator (each process gets its own child stream).
    t0 : float
        Time of the first sample [s].
    """

    def __init__(
        self, model: NoiseModel, fs: float, *, rng: np.random.Generator, t0: float = 0.0
    ) -> None:
        if not isinstance(rng, np.random.Generator):
            raise TypeError(f"rng must be a numpy.random.Generator; got {type(rng).__name__}")
        _check_fs(fs)
        if not math.isfinite(t0):
            raise ValueError(f"t0 must be finite [s]; got {t0!r}")
        self.model = model
        self.fs = float(fs)
        self.dt = 1.0 / self.fs
        self.t0 = float(t0)
        self._k = 0  # samples emitted so far
        children = rng.spawn(_N_SLOTS)
        self._rng = children
        m = model
        # quantization: uniform angle error of std Q on [-q/2, q/2), q = sqrt(12) Q;
        # the previous value is carried
        # (drawn as c u, u ~ U[0, 1), c = q fs: the offset -q/2 cancels in the difference)
        self._q_step = math.sqrt(12.0) * m.quantization
        self._q_prev = (
            children[_SLOT_QUANT].uniform(0.0, self._q_step * self.fs)
            if m.quantization > 0
            else 0.0
        )
        self._arw_gain = m.angle_random_walk * math.sqrt(self.fs)
        self._flicker = None
        if m.bias_instability > 0:
            tc, sig = m.flicker_poles(self.fs)
            self._flicker = _Flicker(tc, sig**2, self.dt, children[_SLOT_FLICKER])
        self._rrw = 0.0
        self._rrw_gain = m.rate_random_walk * math.sqrt(self.dt)
        self._gm = []
        for i, gm in enumerate(m.gauss_markov):
            phi = math.exp(-self.dt / gm.correlation_time)
            gain = gm.sigma * math.sqrt(-math.expm1(-2.0 * self.dt / gm.correlation_time))
            state = gm.sigma * children[_SLOT_GM0 + i].standard_normal()
            self._gm.append([phi, gain, state])
        # full-rate random draws, in a fixed order; drawn block by block, possibly one block ahead
        # by a worker thread (numpy releases the GIL while filling), never changing their values
        # (``_scaled`` draws exactly what Generator.uniform(0, c) and Generator.normal(0, c) return,
        # in less time: the core arithmetic 0 + c x is the same)
        self._sources: list[tuple[str, Callable[[int], Any]]] = []
        q_scale = self._q_step * self.fs  # rate step per unit of uniform angle draw
        if m.quantization > 0:
            self._sources.append(("q", functools.partial(_scaled, children[_SLOT_QUANT].random, q_scale)))
        if m.angle_random_walk > 0:
            self._sources.append(
                ("arw", functools.partial(_scaled, children[_SLOT_ARW].standard_normal, self._arw_gain))
            )
        if self._flicker is not None and self._flicker.fine is not None:
            self._sources.append(("fl", self._flicker.fine.rng.standard_normal))
        if m.rate_random_walk > 0:
            self._sources.append(
                ("rrw", functools.partial(_scaled, children[_SLOT_RRW].standard_normal, self._rrw_gain))
            )
        for i in range(len(m.gauss_markov)):
            self._sources.append((f"gm{i}", children[_SLOT_GM0 + i].standard_normal))

    def _ahead(self, n: int) -> dict[str, NDArray[np.float64]]:
        """The part of a block the worker thread can do: Q's draws and the whole flicker term.

        Both touch only their own streams and state, so running them for the next block while
        the caller works on the current one changes no value.
        """
        d = {key: fn(n) for key, fn in self._sources if key in _AHEAD}
        if self._flicker is not None:
            d["bias_instability"] = self._flicker.next(n, d.pop("fl", None))
        return d

    def _now(self, n: int) -> dict[str, NDArray[np.float64]]:
        """The draws of the other streams (N, K, the Gauss-Markov terms), made by the caller."""
        return {key: fn(n) for key, fn in self._sources if key not in _AHEAD}

    def _blocks(self, n: int) -> Iterator[tuple[int, dict[str, NDArray[np.float64]]]]:
        """(block size, its pre-drawn random numbers and flicker term) for the next ``n`` samples.

        With more than one block, the next block's :meth:`_ahead` part runs in a worker thread
        while the caller draws and processes the rest of the current one (about half the work
        each for the five-term model); each stream is drawn sequentially either way, so the
        values do not depend on whether the thread runs.
        """
        sizes = [min(_BLOCK, n - s) for s in range(0, n, _BLOCK)]
        if len(sizes) <= 1 or not _use_prefetch() or not self._sources:
            for k in sizes:
                yield k, {**self._ahead(k), **self._now(k)}
            return
        ex = _executor()
        fut = ex.submit(self._ahead, sizes[0])
        try:
            for i, k in enumerate(sizes):
                ahead = fut.result()
                fut = ex.submit(self._ahead, sizes[i + 1]) if i + 1 < len(sizes) else None
                yield k, {**ahead, **self._now(k)}
        finally:
            if (
                fut is not None
            ):  # abandoned mid-way: let the worker finish before anyone draws again
                fut.result()

    def _terms(
        self, n: int, d: dict[str, NDArray[np.float64]]
    ) -> Iterator[tuple[str, NDArray[np.float64]]]:
        """The next ``n`` samples of every present term (one internal block), in a fixed order."""
        m = self.model
        if m.quantization > 0:
            e = d["q"]  # uniform angle error, already in rate units (times fs)
            y = np.empty(n)
            y[0] = e[0] - self._q_prev
            np.subtract(e[1:], e[:-1], out=y[1:])
            self._q_prev = e[-1]
            yield "quantization", y
        if m.angle_random_walk > 0:
            yield "angle_random_walk", d["arw"]
        if self._flicker is not None:
            yield "bias_instability", d["bias_instability"]
        if m.rate_random_walk > 0:
            steps = d["rrw"]
            steps[0] += self._rrw  # carry folded into the first step: same rounding as one-shot
            np.cumsum(steps, out=steps)
            self._rrw = steps[-1]
            yield "rate_random_walk", steps
        if m.rate_ramp > 0:
            ramp = np.arange(self._k, self._k + n, dtype=float)
            ramp *= m.rate_ramp * self.dt
            ramp += m.rate_ramp * self.t0
            yield "rate_ramp", ramp  # R t_k, t_k = t0 + k/fs
        t = np.arange(self._k, self._k + n, dtype=float) if m.sinusoids else np.zeros(0)
        t *= self.dt
        t += self.t0
        for i, st in enumerate(self._gm):
            phi, gain, state = st
            x, _ = signal.lfilter([gain], [1.0, -phi], d[f"gm{i}"], zi=[phi * state])
            st[2] = x[-1]
            yield f"gauss_markov_{i}", x
        for i, s in enumerate(m.sinusoids):
            yield f"sinusoid_{i}", s.amplitude * np.sin(2.0 * np.pi * s.frequency * t + s.phase)
        if m.bias != 0:
            yield "bias", np.full(n, m.bias)
        self._k += n

    @staticmethod
    def _check_n(n: int) -> None:
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)):
            raise TypeError(f"n must be an integer number of samples; got {n!r}")
        if n < 0:
            raise ValueError(f"n must be >= 0 samples; got {n!r}")

    def take_components(self, n: int) -> dict[str, NDArray[np.float64]]:
        """The next ``n`` samples of every present term [rad/s], by term name."""
        self._check_n(n)
        parts: dict[str, list[NDArray[np.float64]]] = {}
        for k, d in self._blocks(n):
            for name, v in self._terms(k, d):
                parts.setdefault(name, []).append(v)
        if n == 0:
            return {name: np.empty(0) for name in self._names()}
        return {name: (v[0] if len(v) == 1 else np.concatenate(v)) for name, v in parts.items()}

    def _names(self) -> list[str]:
        m = self.model
        names = [
            f.name
            for f in fields(m)
            if f.name
            in (
                "quantization",
                "angle_random_walk",
                "bias_instability",
                "rate_random_walk",
                "rate_ramp",
            )
            and getattr(m, f.name) > 0
        ]
        names += [f"gauss_markov_{i}" for i in range(len(m.gauss_markov))]
        names += [f"sinusoid_{i}" for i in range(len(m.sinusoids))]
        if m.bias != 0:
            names.append("bias")
        return names

    def take(self, n: int) -> NDArray[np.float64]:
        """The next ``n`` samples of the summed rate error [rad/s].

        Terms are added in :meth:`take_components` order (the same rounding).
        """
        self._check_n(n)
        total = np.zeros(n)
        done = 0
        for k, d in self._blocks(n):
            acc = total[done : done + k]
            for _, v in self._terms(k, d):
                acc += v
            done += k
        return total

    def chunks(self, n: int, chunk: int = 1 << 20) -> Iterator[NDArray[np.float64]]:
        """Yield the next ``n`` samples in chunks of at most ``chunk`` samples."""
        self._check_n(n)
        if isinstance(chunk, bool) or not isinstance(chunk, (int, np.integer)) or chunk <= 0:
            raise ValueError(f"chunk must be an integer > 0 samples; got {chunk!r}")
        left = n
        while left > 0:
            k = min(chunk, left)
            yield self.take(k)
            left -= k
