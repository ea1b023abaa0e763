"""Shaker profiles: what an electrodynamic vibration table does to the gyro's mount.

Building blocks only (the papers' protocols are composed in ``scenarios``).
Everything is SI: time [s], frequency [Hz], acceleration [m/s^2], displacement [m].

* :class:`SineSweep` -- linear or logarithmic sine sweep at a constant
  acceleration amplitude, displacement-limited at low frequency;
* :class:`FixedSine` -- a dwell at one frequency;
* :class:`RandomVibration` -- Gaussian random vibration from a PSD in g^2/Hz
  (breakpoints with log-log interpolation, as test standards write them),
  with the low-frequency shaping a displacement-limited shaker applies;
* :class:`Phased` -- a record static -> vibration -> static;
* :func:`interval_mean_acceleration` -- a profile as one sensor input per output
  sample (the mean over each output interval), placed in a longer record: what
  ``Environment.specific_force`` takes.

Every profile samples to a :class:`ShakerSignal` (acceleration time series plus
the instantaneous frequency and envelope a shaker controller logs) with
``profile.sample(fs, rng=...)``.

Controller error
----------------
A real controller holds the acceleration amplitude only to a few percent. Sine
profiles take ``control_error`` (fractional rms of the amplitude) and
``control_time`` (its correlation time [s]); the amplitude is multiplied by
(1 + e(t)) with e a first-order Gauss-Markov process (exact discretisation,
started from its stationary distribution). Default 0: an ideal controller.

Displacement limit
------------------
A sine of amplitude a [m/s^2] at f [Hz] needs peak displacement
d = a / (2 pi f)^2. A shaker with stroke limit d_max [m peak] cannot follow a
constant-acceleration sweep below f_c = sqrt(a/d_max)/(2 pi); the controller
then runs a constant-displacement segment: amplitude(f) = min(a, d_max (2 pi f)^2).
For random vibration the PSD below a corner f_c is multiplied by (f/f_c)^4
(constant displacement PSD), f_c chosen so that 3 sigma of the displacement
equals d_max (3 sigma taken as the peak, the usual rule for Gaussian drive).

References
----------
docs/physics.md section 4 (sweep phases, PSD synthesis, NAVMAT P-9492 spectrum);
MIL-STD-810G Method 514.6; IEC 60068-2-6 (sine) and 60068-2-64 (random).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any, ClassVar, Literal, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.base import memory, units
from gyrobench.base.ranges import Constraint, FieldRange, as_array, shown, validate
from gyrobench.base.validate import check_fs as _check_fs
from gyrobench.base.validate import check_rng as _check_rng
from gyrobench.base.validate import real_number

__all__ = [
    "ShakerSignal",
    "moving_span",
    "VibrationProfile",
    "SineSweep",
    "FixedSine",
    "RandomVibration",
    "Phased",
    "OVERSAMPLING",
    "ShakerWindowError",
    "interval_mean_acceleration",
    "record_signal",
    "psd_from_breakpoints",
    "grms",
    "sweep_phase",
    "sweep_frequency",
]


def _real(owner: str, name: str, v, unit: str, *, positive: bool = False, nonneg: bool = False) -> float:
    v = real_number(f"{owner}.{name}", v, unit)
    if positive and v <= 0:
        raise ValueError(f"{owner}.{name} must be > 0 {unit}; got {v!r}")
    if nonneg and v < 0:
        raise ValueError(f"{owner}.{name} must be >= 0 {unit}; got {v!r}")
    return v


def moving_span(acceleration: NDArray[np.float64]) -> tuple[int, int] | None:
    """(first, last) index of the nonzero samples of ``acceleration``, None when all are zero.

    The same indices as ``np.flatnonzero(acceleration)[[0, -1]]`` without building the index
    array (a shaker grid holds millions of samples).

    Parameters
    ----------
    acceleration : ndarray
        Table acceleration samples [m/s^2] (any real array; only where it is nonzero matters).

    Returns
    -------
    tuple of int or None
        (first, last) index of a nonzero sample, both inclusive; None when every sample is zero
        or there is none.
    """
    moving = np.asarray(acceleration) != 0
    if moving.size == 0:
        return None
    first = int(np.argmax(moving))
    if not moving[first]:
        return None
    return first, moving.size - 1 - int(np.argmax(moving[::-1]))


@dataclass(frozen=True, slots=True)
class ShakerSignal:
    """A sampled shaker run: the acceleration and what the controller logs.

    Attributes
    ----------
    fs : float
        Sample rate [Hz].
    acceleration : ndarray
        Table acceleration a(t) along the shaking axis [m/s^2].
    frequency : ndarray
        Instantaneous drive frequency [Hz]; NaN where none is defined (static
        phases, random vibration).
    amplitude : ndarray
        Acceleration envelope [m/s^2]: the sine amplitude, or sqrt(2) x the rms
        for random vibration (the sine of equal mean square); 0 when off.
    on : ndarray of bool
        True while the shaker drives.
    t0 : float
        Time of the first sample [s].
    """

    fs: float
    acceleration: NDArray[np.float64]
    frequency: NDArray[np.float64]
    amplitude: NDArray[np.float64]
    on: NDArray[np.bool_]
    t0: float = 0.0

    @property
    def time(self) -> NDArray[np.float64]:
        """Sample times [s]."""
        return self.t0 + np.arange(len(self.acceleration)) / self.fs


@runtime_checkable
class VibrationProfile(Protocol):
    """What every shaker profile provides."""

    @property
    def duration(self) -> float: ...  # [s]

    @property
    def max_frequency(self) -> float: ...  # highest drive frequency [Hz]

    def sample(self, fs: float, *, rng: np.random.Generator, t0: float = 0.0) -> ShakerSignal: ...


# --------------------------------------------------------------------------- sine sweeps
def sweep_frequency(t: ArrayLike, f_start: float, f_end: float, duration: float, spacing: str) -> NDArray[np.float64]:
    """Instantaneous frequency [Hz] of a sweep at times ``t`` [s] from its start.

    log: f(t) = f1 (f2/f1)^(t/Ts); linear: f(t) = f1 + (f2 - f1) t/Ts.

    Parameters
    ----------
    t : array_like
        Time from the sweep's start [s].
    f_start, f_end : float
        Start and end frequency f1, f2 [Hz].
    duration : float
        Sweep time Ts [s].
    spacing : {"log", "linear"}
        Logarithmic or linear sweep.

    Returns
    -------
    ndarray
        f(t) [Hz].
    """
    t = np.asarray(t, dtype=float)
    if spacing == "log":
        return f_start * (f_end / f_start) ** (t / duration)
    return f_start + (f_end - f_start) * t / duration


def sweep_phase(t: ArrayLike, f_start: float, f_end: float, duration: float, spacing: str) -> NDArray[np.float64]:
    """Phase [rad] of a sweep, the exact integral of 2 pi f(t) (docs/physics.md 4).

    log: 2 pi f1 Ts/ln(f2/f1) ((f2/f1)^(t/Ts) - 1); linear: 2 pi (f1 t + (f2 - f1) t^2/(2 Ts)).
    A log sweep with f2 = f1 degenerates to 2 pi f1 t.

    Parameters
    ----------
    t : array_like
        Time from the sweep's start [s].
    f_start, f_end : float
        Start and end frequency f1, f2 [Hz].
    duration : float
        Sweep time Ts [s].
    spacing : {"log", "linear"}
        Logarithmic or linear sweep.

    Returns
    -------
    ndarray
        phi(t) [rad].
    """
    t = np.asarray(t, dtype=float)
    if spacing == "log":
        if f_end == f_start:
            return 2.0 * np.pi * f_start * t
        lr = math.log(f_end / f_start)
        return 2.0 * np.pi * f_start * duration / lr * np.expm1(lr * t / duration)
    return 2.0 * np.pi * (f_start * t + (f_end - f_start) * t**2 / (2.0 * duration))


def _control_factor(n: int, fs: float, error: float, corr_time: float, rng: np.random.Generator) -> NDArray:
    """1 + e(t), e first-order Gauss-Markov of std ``error`` and correlation time ``corr_time``."""
    if error == 0 or n == 0:
        return np.ones(n)
    from scipy import signal

    phi = math.exp(-1.0 / (fs * corr_time))
    gain = error * math.sqrt(-math.expm1(-2.0 / (fs * corr_time)))
    eps = rng.standard_normal(n)
    x0 = error * rng.standard_normal()
    x, _ = signal.lfilter([gain], [1.0, -phi], eps, zi=[phi * x0])
    return 1.0 + x


def _displacement_limited(amp: float, f: NDArray[np.float64], d_max: float | None) -> NDArray[np.float64]:
    """min(a, d_max (2 pi f)^2) [m/s^2]."""
    a = np.full_like(f, amp)
    if d_max is not None:
        a = np.minimum(a, d_max * (2.0 * np.pi * f) ** 2)
    return a


def _taper(t: NDArray[np.float64], duration: float, ramp: float) -> NDArray[np.float64]:
    """Raised-cosine soft start/stop of length ``ramp`` [s] at both ends (1 inside)."""
    if ramp <= 0:
        return np.ones_like(t)
    w = np.ones_like(t)
    up = t < ramp
    w[up] = 0.5 * (1.0 - np.cos(np.pi * t[up] / ramp))
    down = t > duration - ramp
    w[down] = 0.5 * (1.0 - np.cos(np.pi * (duration - t[down]) / ramp))
    return w


_INF = math.inf
#: the specs the shaker profiles share (:class:`~gyrobench.base.ranges.FieldRange`, SI); a profile
#: states no upper bounds: the memory estimate refuses a run too long to hold
_PROFILE_SPECS: dict[str, FieldRange] = {
    "duration": FieldRange(0, _INF, "s", "length of the vibration phase", low_open=True),
    "acceleration": FieldRange(0, _INF, "m/s^2", "acceleration amplitude (peak); 0: the table does not move"),
    "max_displacement": FieldRange(0, _INF, "m", "shaker stroke limit (peak); None: unlimited", low_open=True),
    "ramp_time": FieldRange(0, _INF, "s", "raised-cosine soft start and stop; 0: abrupt"),
    "control_error": FieldRange(0, _INF, "-", "fractional rms amplitude error of the controller"),
    "control_time": FieldRange(0, _INF, "s", "correlation time of the controller error", low_open=True),
}

#: the soft start and stop fit in the phase
_RAMP_FITS = Constraint(
    "2 ramp_time <= duration",
    lambda c: 2 * c.ramp_time <= c.duration,
    lambda c: f"ramp_time must be <= duration/2 = {c.duration / 2} s; got {c.ramp_time!r}",
)


@dataclass(frozen=True, slots=True, kw_only=True)
class SineSweep:
    """A sine sweep from ``f_start`` to ``f_end`` at constant acceleration amplitude.

    Parameters
    ----------
    f_start, f_end : float
        Start and end frequency [Hz], > 0 (a downward sweep is allowed).
    duration : float
        Sweep time Ts [s], > 0.
    acceleration : float
        Acceleration amplitude (peak) [m/s^2], >= 0; see :func:`gyrobench.base.units.g`.
    spacing : {"log", "linear"}
        Logarithmic (constant octaves per minute) or linear sweep.
    max_displacement : float or None
        Shaker stroke limit [m, peak]; None = unlimited. Below
        f_c = sqrt(a/d_max)/(2 pi) the amplitude is d_max (2 pi f)^2.
    ramp_time : float
        Raised-cosine soft start and stop [s] (a controller never switches a
        full-level drive on in one cycle). 0 = abrupt.
    control_error : float
        Fractional rms amplitude error of the controller [-], >= 0.
    control_time : float
        Correlation time of the controller error [s], > 0.

    Notes
    -----
    a(t) = A(f(t)) w(t) (1 + e(t)) sin(phi(t)), with phi(t) from
    :func:`sweep_phase`, A the displacement-limited amplitude, w the taper and
    e the controller error.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrobench.base import units
    >>> s = SineSweep(f_start=1.0, f_end=500.0, duration=600.0, acceleration=units.g(2.0))
    >>> round(s.octaves_per_minute, 3)
    0.897
    """

    f_start: float
    f_end: float
    duration: float
    acceleration: float
    spacing: Literal["log", "linear"] = "log"
    max_displacement: float | None = None
    ramp_time: float = 0.0
    control_error: float = 0.0
    control_time: float = 10.0

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "f_start": FieldRange(0, _INF, "Hz", "start frequency of the sweep", low_open=True),
        "f_end": FieldRange(0, _INF, "Hz", "end frequency of the sweep (below f_start: downward)", low_open=True),
        **_PROFILE_SPECS,
    }
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (_RAMP_FITS,)

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above

    @property
    def max_frequency(self) -> float:
        """Highest drive frequency [Hz]."""
        return max(self.f_start, self.f_end)

    @property
    def octaves_per_minute(self) -> float:
        """Sweep rate [octave/min] (mean rate for a linear sweep)."""
        return abs(math.log2(self.f_end / self.f_start)) / (self.duration / 60.0)

    def frequency(self, t: ArrayLike) -> NDArray[np.float64]:
        """Instantaneous frequency [Hz] at times ``t`` [s] from the sweep start."""
        return sweep_frequency(t, self.f_start, self.f_end, self.duration, self.spacing)

    def amplitude(self, t: ArrayLike) -> NDArray[np.float64]:
        """Commanded acceleration envelope [m/s^2] (displacement limit and taper, no controller error)."""
        t = np.asarray(t, dtype=float)
        return _displacement_limited(self.acceleration, self.frequency(t), self.max_displacement) * _taper(
            t, self.duration, self.ramp_time
        )

    def sample(self, fs: float, *, rng: np.random.Generator, t0: float = 0.0) -> ShakerSignal:
        """Sample the sweep at ``fs`` [Hz] over [0, duration).

        Raises
        ------
        ValueError
            If the highest sweep frequency is not below the Nyquist frequency fs/2.
        """
        fs = _check_fs(fs)
        rng = _check_rng(rng)
        if self.max_frequency >= fs / 2:
            raise ValueError(
                f"SineSweep up to {self.max_frequency!r} Hz needs fs > {2 * self.max_frequency!r} Hz (Nyquist); "
                f"got fs={fs!r} Hz"
            )
        n = int(round(self.duration * fs))
        t = np.arange(n) / fs
        f = self.frequency(t)
        amp = self.amplitude(t) * _control_factor(n, fs, self.control_error, self.control_time, rng)
        acc = amp * np.sin(sweep_phase(t, self.f_start, self.f_end, self.duration, self.spacing))
        return ShakerSignal(fs, acc, f, amp, np.ones(n, dtype=bool), float(t0))


@dataclass(frozen=True, slots=True, kw_only=True)
class FixedSine:
    """A sine dwell: constant frequency and acceleration amplitude.

    Parameters
    ----------
    frequency : float
        [Hz], > 0.
    duration : float
        [s], > 0.
    acceleration : float
        Amplitude (peak) [m/s^2], >= 0.
    max_displacement : float or None
        Shaker stroke limit [m, peak]; None = unlimited (as :class:`SineSweep`).
    ramp_time : float
        Raised-cosine soft start and stop [s], <= duration/2.
    control_error : float
        Fractional rms amplitude error of the controller [-], >= 0.
    control_time : float
        Correlation time of the controller error [s], > 0.
    phase : float
        Initial phase [rad].

    Notes
    -----
    a(t) = A w(t) (1 + e(t)) sin(2 pi f t + phase), A = min(a, d_max (2 pi f)^2).
    """

    frequency: float
    duration: float
    acceleration: float
    max_displacement: float | None = None
    ramp_time: float = 0.0
    control_error: float = 0.0
    control_time: float = 10.0
    phase: float = 0.0

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "frequency": FieldRange(0, _INF, "Hz", "the dwell's frequency", low_open=True),
        **_PROFILE_SPECS,
        "phase": FieldRange(-_INF, _INF, "rad", "initial phase of the sine"),
    }
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (_RAMP_FITS,)

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above

    @property
    def max_frequency(self) -> float:
        return float(self.frequency)

    def amplitude(self, t: ArrayLike) -> NDArray[np.float64]:
        """Commanded acceleration envelope [m/s^2]."""
        t = np.asarray(t, dtype=float)
        f = np.full_like(t, self.frequency)
        envelope = _taper(t, self.duration, self.ramp_time)
        return _displacement_limited(self.acceleration, f, self.max_displacement) * envelope

    def sample(self, fs: float, *, rng: np.random.Generator, t0: float = 0.0) -> ShakerSignal:
        """Sample the dwell at ``fs`` [Hz]; raises ValueError if ``frequency`` >= fs/2."""
        fs = _check_fs(fs)
        rng = _check_rng(rng)
        if self.frequency >= fs / 2:
            raise ValueError(
                f"FixedSine at {self.frequency!r} Hz needs fs > {2 * self.frequency!r} Hz (Nyquist); got fs={fs!r} Hz"
            )
        n = int(round(self.duration * fs))
        t = np.arange(n) / fs
        amp = self.amplitude(t) * _control_factor(n, fs, self.control_error, self.control_time, rng)
        acc = amp * np.sin(2.0 * np.pi * self.frequency * t + self.phase)
        return ShakerSignal(fs, acc, np.full(n, float(self.frequency)), amp, np.ones(n, dtype=bool), float(t0))


# --------------------------------------------------------------------------- random vibration
def psd_from_breakpoints(
    breakpoints: Sequence[tuple[float, float]], f: ArrayLike
) -> NDArray[np.float64]:
    """A test-standard PSD [g^2/Hz] at frequencies ``f`` [Hz] from breakpoints (f_i, G_i).

    Straight lines on log-log axes between breakpoints (a slope of m dB/oct is
    G ~ f^(m/3.0103)); 0 outside [f_first, f_last].

    Parameters
    ----------
    breakpoints : sequence of (float, float)
        (f_i [Hz], G_i [g^2/Hz]) in increasing frequency.
    f : array_like
        Frequencies [Hz].

    Returns
    -------
    ndarray
        G(f) [g^2/Hz].

    Examples
    --------
    >>> nav = [(20, 0.01), (80, 0.04), (350, 0.04), (2000, 0.007)]
    >>> round(float(psd_from_breakpoints(nav, [80.0, 200.0])[1]), 12)
    0.04
    """
    bp = np.asarray(breakpoints, dtype=float)
    if bp.ndim != 2 or bp.shape[1] != 2 or len(bp) < 2:
        raise ValueError(f"breakpoints must be >= 2 pairs (f [Hz], G [g^2/Hz]); got {breakpoints!r}")
    if np.any(bp[:, 0] <= 0) or np.any(np.diff(bp[:, 0]) <= 0):
        raise ValueError(f"breakpoint frequencies must be > 0 Hz and strictly increasing; got {bp[:, 0].tolist()!r}")
    if np.any(bp[:, 1] <= 0) or not np.all(np.isfinite(bp)):
        raise ValueError(f"breakpoint PSD levels must be finite and > 0 g^2/Hz; got {bp[:, 1].tolist()!r}")
    f = np.asarray(f, dtype=float)
    out = np.zeros_like(f)
    inside = (f >= bp[0, 0]) & (f <= bp[-1, 0])
    out[inside] = np.exp(np.interp(np.log(f[inside]), np.log(bp[:, 0]), np.log(bp[:, 1])))
    return out


def grms(breakpoints: Sequence[tuple[float, float]]) -> float:
    """Overall rms acceleration [g] of a breakpoint PSD: sqrt(Int G df), exact per log-log segment.

    On a segment G = G1 (f/f1)^s: Int = G1 f1/(s+1) ((f2/f1)^(s+1) - 1), or G1 f1 ln(f2/f1) for s = -1.

    Parameters
    ----------
    breakpoints : sequence of (float, float)
        (f_i [Hz], G_i [g^2/Hz]) in increasing frequency.

    Returns
    -------
    float
        The rms acceleration [g].

    Examples
    --------
    >>> round(grms([(20, 0.01), (80, 0.04), (350, 0.04), (2000, 0.007)]), 2)
    6.06
    """
    bp = np.asarray(breakpoints, dtype=float)
    psd_from_breakpoints(breakpoints, bp[:1, 0])  # validation
    total = 0.0
    for (f1, g1), (f2, g2) in zip(bp[:-1], bp[1:], strict=True):
        s = math.log(g2 / g1) / math.log(f2 / f1)
        if abs(s + 1.0) < 1e-12:
            total += g1 * f1 * math.log(f2 / f1)
        else:
            total += g1 * f1 / (s + 1.0) * ((f2 / f1) ** (s + 1.0) - 1.0)
    return math.sqrt(total)


def _float_pairs(bp: Any) -> tuple[tuple[float, float], ...]:
    """Validated breakpoints as a tuple of (f, G) float pairs."""
    return tuple((float(f), float(g)) for f, g in bp)


@dataclass(frozen=True, slots=True, kw_only=True)
class RandomVibration:
    """Gaussian random vibration with a breakpoint PSD.

    Parameters
    ----------
    breakpoints : tuple of (f [Hz], G [g^2/Hz])
        The test spectrum (field units, as standards print it).
    duration : float
        [s], > 0.
    max_displacement : float or None
        Shaker stroke limit [m, peak]; the PSD is shaped below a corner f_c by
        (f/f_c)^4 so that 3 sigma of the displacement equals it.

    Notes
    -----
    Synthesis (docs/physics.md 4): on the FFT grid f_k = k fs/n,
    a(t) = sum_k A_k cos(2 pi f_k t + phi_k), A_k = sqrt(2 G(f_k) df) g0,
    phi_k uniform, done by an inverse real FFT; the variance is sum_k G(f_k) df g0^2.
    Displacement PSD = G(f) g0^2 / (2 pi f)^4.
    """

    breakpoints: tuple[tuple[float, float], ...]
    duration: float
    max_displacement: float | None = None

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "duration": _PROFILE_SPECS["duration"],
        "max_displacement": _PROFILE_SPECS["max_displacement"],
    }
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            ">= 2 breakpoints (f, G)",
            lambda c: isinstance(c.breakpoints, np.ndarray) and c.breakpoints.ndim == 2
            and c.breakpoints.shape[1] == 2 and len(c.breakpoints) >= 2,
            lambda c: f"breakpoints must be >= 2 pairs (f [Hz], G [g^2/Hz]); got {shown(c.breakpoints)}",
        ),
        Constraint(
            "breakpoint frequencies > 0 Hz, strictly increasing",
            lambda c: bool(np.all(c.breakpoints[:, 0] > 0) and np.all(np.diff(c.breakpoints[:, 0]) > 0)),
            lambda c: "breakpoints must have frequencies > 0 Hz, strictly increasing; "
            f"got {c.breakpoints[:, 0].tolist()!r}",
        ),
        Constraint(
            "breakpoint PSD levels finite, > 0 g^2/Hz",
            lambda c: bool(np.all(c.breakpoints[:, 1] > 0) and np.all(np.isfinite(c.breakpoints))),
            lambda c: f"breakpoints must have PSD levels finite and > 0 g^2/Hz; got {c.breakpoints[:, 1].tolist()!r}",
        ),
    )

    def __post_init__(self) -> None:
        object.__setattr__(self, "breakpoints", as_array(self.breakpoints))
        validate(self)  # the declared specs and constraints above
        object.__setattr__(self, "breakpoints", _float_pairs(self.breakpoints))

    @property
    def max_frequency(self) -> float:
        return self.breakpoints[-1][0]

    @property
    def grms(self) -> float:
        """Overall rms [g] of the unshaped spectrum."""
        return grms(self.breakpoints)

    def shaped_psd(self, f: ArrayLike) -> NDArray[np.float64]:
        """The PSD the shaker actually plays [g^2/Hz], displacement shaping included."""
        f = np.asarray(f, dtype=float)
        g = psd_from_breakpoints(self.breakpoints, f)
        fc = self.displacement_corner()
        if fc > 0:
            low = (f < fc) & (f > 0)
            g[low] *= (f[low] / fc) ** 4
        return g

    def displacement_corner(self) -> float:
        """Corner f_c [Hz] of the displacement shaping (0 when the limit is not reached)."""
        if self.max_displacement is None:
            return 0.0
        f = np.geomspace(self.breakpoints[0][0], self.breakpoints[-1][0], 4000)
        g = psd_from_breakpoints(self.breakpoints, f) * units.g(1.0) ** 2

        def sigma_d(fc: float) -> float:
            gg = g if fc <= 0 else np.where(f < fc, g * (f / fc) ** 4, g)
            return math.sqrt(np.trapezoid(gg / (2 * np.pi * f) ** 4, f))

        if 3.0 * sigma_d(0.0) <= self.max_displacement:
            return 0.0
        lo, hi = f[0], f[-1]
        if 3.0 * sigma_d(hi) > self.max_displacement:
            raise ValueError(
                f"RandomVibration.max_displacement = {self.max_displacement!r} m cannot be met by shaping below "
                f"{hi:g} Hz; raise the stroke limit"
            )
        for _ in range(60):
            mid = math.sqrt(lo * hi)
            if 3.0 * sigma_d(mid) > self.max_displacement:
                lo = mid
            else:
                hi = mid
        return hi

    def sample(self, fs: float, *, rng: np.random.Generator, t0: float = 0.0) -> ShakerSignal:
        """A Gaussian realisation at ``fs`` [Hz]; raises ValueError if the PSD extends to fs/2 or beyond."""
        fs = _check_fs(fs)
        rng = _check_rng(rng)
        if self.max_frequency >= fs / 2:
            raise ValueError(
                f"RandomVibration up to {self.max_frequency!r} Hz needs fs > {2 * self.max_frequency!r} Hz (Nyquist); "
                f"got fs={fs!r} Hz"
            )
        n = int(round(self.duration * fs))
        fk = np.fft.rfftfreq(n, 1.0 / fs)
        df = fs / n
        amp = np.sqrt(2.0 * self.shaped_psd(fk) * df) * units.g(1.0)
        amp[0] = 0.0
        phi = rng.uniform(0.0, 2.0 * np.pi, len(fk))
        acc = np.fft.irfft(amp * np.exp(1j * phi) * (n / 2.0), n)
        rms_equiv = math.sqrt(2.0 * float(np.sum(amp**2) / 2.0))
        return ShakerSignal(fs, acc, np.full(n, np.nan), np.full(n, rms_equiv), np.ones(n, dtype=bool), float(t0))


# --------------------------------------------------------------------------- phased record
@dataclass(frozen=True, slots=True, kw_only=True)
class Phased:
    """A record static -> vibration -> static (seed 000's three phases).

    Parameters
    ----------
    vibration : SineSweep, FixedSine or RandomVibration
        What the shaker plays in phase 2.
    static_before, static_after : float
        Durations of phases 1 and 3 [s], >= 0.
    """

    vibration: VibrationProfile = field()
    static_before: float = 0.0
    static_after: float = 0.0

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "static_before": FieldRange(0, _INF, "s", "static phase before the vibration"),
        "static_after": FieldRange(0, _INF, "s", "static phase after the vibration"),
    }
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "vibration is a shaker profile",
            lambda c: isinstance(c.vibration, VibrationProfile),
            lambda c: f"vibration must be a shaker profile; got {type(c.vibration).__name__}",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above

    @property
    def duration(self) -> float:
        return self.static_before + self.vibration.duration + self.static_after

    @property
    def max_frequency(self) -> float:
        return self.vibration.max_frequency

    @property
    def phase_bounds(self) -> tuple[tuple[float, float], tuple[float, float], tuple[float, float]]:
        """[start, end) of phases 1, 2, 3 [s] from the record start."""
        t1 = self.static_before
        t2 = t1 + self.vibration.duration
        return (0.0, t1), (t1, t2), (t2, self.duration)

    def sample(self, fs: float, *, rng: np.random.Generator, t0: float = 0.0) -> ShakerSignal:
        """The whole record at ``fs`` [Hz]: zero acceleration, NaN frequency and ``on`` False when static."""
        fs = _check_fs(fs)
        vib = self.vibration.sample(fs, rng=rng)
        n1 = int(round(self.static_before * fs))
        n3 = int(round(self.static_after * fs))

        def pad(x, fill):
            return np.concatenate([np.full(n1, fill, dtype=x.dtype), x, np.full(n3, fill, dtype=x.dtype)])

        return ShakerSignal(
            fs,
            pad(vib.acceleration, 0.0),
            pad(vib.frequency, np.nan),
            pad(vib.amplitude, 0.0),
            pad(vib.on, False),
            float(t0),
        )


# --------------------------------------------------------------------------- output-rate input
#: :func:`interval_mean_acceleration` samples a profile at >= this many times its highest
#: frequency (twice the Nyquist rate) before averaging over each output interval
OVERSAMPLING = 4.0


class ShakerWindowError(ValueError):
    """The vibration does not lie inside the record (:func:`interval_mean_acceleration`).

    ``start`` and ``end`` [s] of the vibration, the record's ``duration`` [s] and output rate
    ``fs`` [Hz] are kept, so a caller can name them in its own words.

    Parameters
    ----------
    start, end : float
        Start and end of the vibration [s].
    duration : float
        The record's duration [s].
    fs : float
        The record's output rate [Hz].
    """

    def __init__(self, start: float, end: float, duration: float, fs: float) -> None:
        self.start, self.end, self.duration, self.fs = start, end, duration, fs
        super().__init__(
            f"start + vibration.duration = {end:g} s must lie inside the record (0, {duration:g}] s and hold "
            f">= 1 output sample at {fs:g} Hz"
        )


def _record_window(
    name: str, vibration: object, duration: float, fs: float, rng: object, start: float
) -> tuple[float, np.random.Generator, int, int, int]:
    """Check a shaker record's inputs and place the vibration in it: (fs, rng, n, k0, n_v).

    n = floor(duration fs) output intervals, k0 = round(start fs) and n_v = round(T_v fs), the
    placement :func:`interval_mean_acceleration` and :func:`record_signal` share; the record's
    memory is checked first, in floats (duration fs may overflow to inf: refused, not an
    OverflowError). Raises TypeError/ValueError naming ``name``'s parameter, or
    :class:`ShakerWindowError` when the vibration does not lie inside the record.
    """
    if not isinstance(vibration, (SineSweep, FixedSine, RandomVibration)):
        raise TypeError(
            f"vibration must be a SineSweep, FixedSine or RandomVibration; got {type(vibration).__name__}"
        )
    duration = _real(name, "duration", duration, "s", positive=True)
    fs = _check_fs(fs)
    gen = _check_rng(rng)
    start = _real(name, "start", start, "s", nonneg=True)
    memory.check_memory(memory.series_bytes(duration * fs), f"the shaker record of {duration * fs:.3g} output samples",
                        hint="shorten the record or lower the sample rate")
    if start + vibration.duration > duration + 2.0 / fs:  # outside whatever the roundings (start fs may overflow)
        raise ShakerWindowError(start, start + vibration.duration, duration, fs)
    n = int(math.floor(duration * fs + 1e-9))
    k0 = int(round(start * fs))
    n_vib = int(round(vibration.duration * fs))
    if n_vib < 1 or k0 + n_vib > n:
        raise ShakerWindowError(start, start + vibration.duration, duration, fs)
    return fs, gen, n, k0, n_vib


def interval_mean_acceleration(
    vibration: SineSweep | FixedSine | RandomVibration,
    *,
    duration: float,
    fs: float,
    rng: np.random.Generator,
    start: float = 0.0,
) -> NDArray[np.float64]:
    """The shaker's acceleration as one mean per output interval of a record [m/s^2].

    The array a sensor model takes as its specific-force input
    (:class:`gyrobench.sim.sensor.Environment` ``specific_force``: one value per output
    sample, floor(duration fs) of them); add a static part (1 g with the axis up) to it.

    Parameters
    ----------
    vibration : SineSweep, FixedSine or RandomVibration
        What the shaker plays; its ``duration`` [s] is rounded to whole output intervals
        (Notes).
    duration : float
        Length of the whole record [s], > 0.
    fs : float
        Output sample rate of the record [Hz], > 0.
    rng : numpy.random.Generator
        The shaker's own stream (random vibration's phases, a sine controller's error).
    start : float
        Time of the vibration's start in the record [s], >= 0 (default 0). The record is
        static (0 m/s^2) before and after the vibration.

    Returns
    -------
    ndarray
        a_k [m/s^2], k = 0 .. floor(duration fs) - 1: the mean acceleration over the output
        interval [k/fs, (k + 1)/fs).

    Raises
    ------
    TypeError
        If ``vibration`` is not one of the three profiles or ``rng`` not a Generator.
    ValueError
        If ``duration``, ``fs`` or ``start`` is out of range, if the vibration does not lie
        inside the record with >= 1 output sample (:class:`ShakerWindowError`), or if the record
        or the oversampled vibration would not fit in memory
        (:class:`gyrobench.base.memory.MemoryLimitError`).

    Notes
    -----
    With n = floor(duration fs), k0 = round(start fs), n_v = round(T_v fs) (T_v the
    vibration's duration) and m = max(1, ceil(:data:`OVERSAMPLING` f_max / fs)), the profile is
    sampled at m fs over [0, n_v/fs) (its duration set to n_v/fs, so the window holds whole
    output intervals) and

        a_k = (1/m) sum_{j=0}^{m-1} a_v((k - k0)/fs + j/(m fs))   for k0 <= k < k0 + n_v,
        a_k = 0                                                    otherwise.

    The mean is what an integrating output (each sample the increment over its interval)
    sees: a tone A cos(2 pi f t + phi) becomes A |H(f)| cos(2 pi f k/fs + phi + arg H(f)) with

        H(f) = (1/m) sum_j exp(i 2 pi f j/(m fs))
             = exp(i pi f (m - 1)/(m fs)) sin(pi f/fs) / (m sin(pi f/(m fs))),

    which tends to sinc(f/fs) as m grows and is 0 at the multiples of fs: a vibration above
    fs/2 still folds into the output band, but attenuated by |H| (<= 1/(pi f/fs) for
    f >= fs/2 in the limit), not at its full level as a point sampler would fold it.

    References
    ----------
    docs/physics.md sections 3.8 (the integrate-and-dump output average sinc(f/fs)) and 4
    (the shaker); Oppenheim & Schafer, Discrete-Time Signal Processing, 3rd ed., ch. 2 (the
    frequency response of the moving-average system).

    Examples
    --------
    >>> import numpy as np
    >>> from gyrobench.base import units
    >>> dwell = FixedSine(frequency=5.0, duration=4.0, acceleration=units.g(0.5))
    >>> a = interval_mean_acceleration(dwell, duration=10.0, fs=100.0, start=2.0, rng=np.random.default_rng(0))
    >>> len(a), bool(np.all(a[:200] == 0) and np.all(a[600:] == 0)), round(float(a[205]), 6)
    (1000, True, 4.903325)
    """
    fs, rng, n, k0, n_vib = _record_window("interval_mean_acceleration", vibration, duration, fs, rng, start)
    m = max(1, math.ceil(OVERSAMPLING * vibration.max_frequency / fs))
    memory.check_memory(memory.series_bytes(n_vib * m, 4), f"the shaker's vibration sampled at {m * fs:g} Hz",
                        hint="shorten the vibration")
    vib = replace(vibration, duration=n_vib / fs)
    acc = vib.sample(m * fs, rng=rng).acceleration
    out = np.zeros(n)
    out[k0:k0 + n_vib] = acc[: n_vib * m].reshape(n_vib, m).mean(axis=1)
    return out


def record_signal(
    vibration: SineSweep | FixedSine | RandomVibration,
    *,
    duration: float,
    fs: float,
    rng: np.random.Generator,
    start: float = 0.0,
) -> ShakerSignal:
    """The shaker's table acceleration over a whole record, for the device models' vibration input.

    What :class:`gyrobench.sim.sensor.Environment` ``vibration`` takes: the profile placed in the
    record as :func:`interval_mean_acceleration` places it (the same k0 = round(start fs) and
    n_v = round(T_v fs) output intervals, static before and after), sampled at m fs with
    m = the smallest EVEN integer >= max(2, ceil(:data:`OVERSAMPLING` f_max / fs)) (the
    closed-loop FOG's reduced form needs an even multiple of the output rate), from t = 0 over
    floor(duration fs) output intervals. With the same ``rng`` state and an even m of
    :func:`interval_mean_acceleration`, its block means are that function's values; a sine
    without controller error is the same signal at any m.

    Parameters
    ----------
    vibration : SineSweep, FixedSine or RandomVibration
        What the shaker plays.
    duration : float
        Length of the whole record [s], > 0.
    fs : float
        Output sample rate of the record [Hz], > 0.
    rng : numpy.random.Generator
        The shaker's own stream.
    start : float
        Time of the vibration's start in the record [s], >= 0.

    Returns
    -------
    ShakerSignal
        n m samples at m fs from t = 0 (frequency NaN and ``on`` False while static).

    Raises
    ------
    TypeError, ValueError
        As :func:`interval_mean_acceleration` (:class:`ShakerWindowError` when the vibration
        does not lie inside the record).
    """
    fs, rng, n, k0, n_vib = _record_window("record_signal", vibration, duration, fs, rng, start)
    m = max(2, math.ceil(OVERSAMPLING * vibration.max_frequency / fs))
    m += m % 2
    memory.check_memory(memory.series_bytes(n * m, 4), f"the shaker's table acceleration sampled at {m * fs:g} Hz",
                        hint="shorten the record or lower the sample rate")
    vib = replace(vibration, duration=n_vib / fs)
    return Phased(vibration=vib, static_before=k0 / fs, static_after=(n - k0 - n_vib) / fs).sample(m * fs, rng=rng)
