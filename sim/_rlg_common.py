"""What the two ring-laser-gyro models share: validation, scale factor, the statistical mode.

Private: import the public names from :mod:`gyrobench.sim.rlg` (parametric thermal bias,
:class:`~gyrobench.sim.rlg.RLGUnit`) and :mod:`gyrobench.sim.rlg_cavity` (cavity mechanisms,
:class:`~gyrobench.sim.rlg_cavity.CavityRLG`). Both models count pulses the same way; they
differ only in what drives the count (turn-on and thermal bias, the dither random-walk
coefficient, the scale-factor ratio) and in the temperatures their two sensors read. This
module holds the common part once, so a fix to counting, dither stripping or the recording
layout reaches both models.

All parameters are SI: angles [rad], rates [rad/s], time [s], temperature [K].

Statistical mode (docs/physics.md 6.3 and 6.6), sample k covering [k/fs, (k+1)/fs):

    theta_k = sum_{j<k} (r_j (Omega_j + b_on + b_T,j + f_j) + N_j sqrt(fs) eps_j) / fs
    d_k = theta_D (1 + sigma eps'_k) sin(phi_k),   phi_k ~ U(0, 2 pi)
    c_k = floor((theta_k + d_k) / q)
    output_k = (q (c_k - c_{k-1}) - (d_k - d_{k-1})) fs

Omega input rate, b_on turn-on bias, b_T thermal bias, f flicker and rate random walk
(:class:`gyrobench.sim.noise.NoiseModel`), N the random walk left by dithering through
lock-in [rad/sqrt(s)], r the scale-factor ratio K_j/K (1 when absent), theta_D and sigma
the dither amplitude and its jitter, q the pulse weight [rad/count]. Each effect draws from
its own child stream of ``rng.spawn(6)``: turn-on, flicker, random walk, dither, housing
sensor, cavity sensor (in that order; the turn-on stream is the model's).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any, NamedTuple, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.base.ranges import Constraint
from gyrobench.base.validate import check_rng as _check_rng
from gyrobench.base.validate import positive_field as _pos
from gyrobench.base.validate import real_field as _num
from gyrobench.io.recording import Channel, Recording, package_version
from gyrobench.sim.noise import NoiseModel
from gyrobench.sim.sensor import RLG_ERROR_COMPONENTS, Environment, check_call, held, with_metadata

if TYPE_CHECKING:
    from gyrobench.sim.rlg import CavityGeometry, Dither, TemperatureSensor

#: the dither peak rate must exceed this multiple of the lock-in rate (statistical model validity)
DITHER_LOCK_IN_MARGIN = 10.0


# ============================================================================ validation
def _dither_low_rate(dither: Dither) -> float:
    """The dither peak rate at -3 sigma of its amplitude jitter [rad/s]."""
    return dither.peak_rate * (1.0 - 3.0 * dither.amplitude_jitter)


def dither_margin(
    lock_in: Callable[[Any], float], what: str, context: Callable[[Any], str] | None = None
) -> Constraint:
    """The declared constraint that a spec's dither clears its lock-in by the margin.

    Below ``DITHER_LOCK_IN_MARGIN`` x lock-in at -3 sigma of the amplitude jitter the gyro
    sits in lock-in for a large part of each cycle and the statistical mode does not apply.

    Parameters
    ----------
    lock_in : callable
        ``lock_in(spec) -> float``: the lock-in rate [rad/s] the dither must clear.
    what : str
        How the message names that lock-in (``"lock-in rate"``).
    context : callable, optional
        ``context(spec) -> str`` appended to the message (the dither or the scatter).

    Returns
    -------
    Constraint
        For the spec's ``CONSTRAINTS``; its message names the dither's low peak rate, the
        margin, the lock-in and its value [rad/s].
    """

    def holds(c: Any) -> bool:
        return bool(_dither_low_rate(c.dither) >= DITHER_LOCK_IN_MARGIN * lock_in(c))

    def message(c: Any) -> str:
        tail = context(c) if context is not None else ""
        return (
            f"dither amplitude too small for lock-in: peak dither rate at -3 sigma jitter "
            f"{_dither_low_rate(c.dither)!r} rad/s must be >= {DITHER_LOCK_IN_MARGIN:g} x {what} "
            f"{lock_in(c)!r} rad/s{tail}"
        )

    return Constraint(f"dither peak rate at -3 sigma >= {DITHER_LOCK_IN_MARGIN:g} x {what}", holds, message)


def _chamber_samples(
    owner: str, chamber: ArrayLike, fs: float
) -> tuple[NDArray[np.float64], float]:
    """Chamber temperatures [K] as a 1-D array of >= 2 samples, and the step 1/fs [s]."""
    tc = np.asarray(chamber, dtype=float)
    h = 1.0 / _pos(owner, "fs", fs, "Hz")
    if tc.ndim != 1 or len(tc) < 2:
        raise ValueError(f"chamber must be 1-D with >= 2 samples; got shape {tc.shape}")
    return tc, h


def _sensor_pair(
    sensor: TemperatureSensor, offset_spread: float, rng: np.random.Generator
) -> tuple[TemperatureSensor, TemperatureSensor]:
    """Housing and cavity sensors of a unit: ``sensor``, offsets of std ``offset_spread`` [K]."""
    offs = offset_spread * rng.standard_normal(2)
    return (
        replace(sensor, offset=sensor.offset + offs[0]),
        replace(sensor, offset=sensor.offset + offs[1]),
    )


# ============================================================================ scale factor
class _CavityScale:
    """Scale factor and pulse weight of a unit's cavity geometry (both RLG models' units).

    A unit of either model is a frozen dataclass with a ``geometry`` field; these two
    properties read it (for :class:`gyrobench.sim.rlg_cavity.CavityRLG`, at T_ref and mode 0).
    """

    __slots__ = ()
    geometry: CavityGeometry

    @property
    def scale_factor(self) -> float:
        """K = 4A/(lambda P) of the geometry [counts/rad]."""
        return self.geometry.scale_factor

    @property
    def pulse_weight(self) -> float:
        """q = 1/K [rad/count]."""
        return self.geometry.pulse_weight

    def simulate(self, environment: Environment, *, fs: float, rng: np.random.Generator) -> Recording:
        """One record at ``fs`` [Hz] from the statistical mode; the gyro is switched on at t = 0.

        Parameters
        ----------
        environment : Environment
            ``temperature``: the chamber air [K] (None: :data:`DEFAULT_CHAMBER` held; an array
            is held over each sample interval); ``true_rate`` [rad/s] about the sense axis. The
            models have no g-sensitive term: a set ``specific_force`` is listed in the metadata's
            ``ignored_inputs``. ``vibration`` (a shaker run along the sense axis from t = 0, at an
            integer multiple of ``fs``) twists the block on its dither flexure when the unit has a
            ``dither_mount`` (:mod:`gyrobench.sim.rlg_vibration`): the unstripped part is the term
            ``dither_mount_vibration``; a unit without one lists it in ``ignored_inputs``.
        fs : float
            Count sampling rate [Hz], at most f_d / 4.
        rng : numpy.random.Generator
            The record's streams.

        Returns
        -------
        Recording
            Channels ``output`` [rad/s], ``counts``, ``dither_angle``, ``T1`` (housing) and ``T2``
            (cavity) [K]; truth ``true_rate`` and the terms named in the metadata's
            ``error_components`` (summing to ``output - true_rate``); inputs: the model's
            temperatures and states (mode index, path length, scale-factor ratio); detail: the
            thermal bias's mechanisms and the lock-in rate.
        """
        fs = check_call(environment, fs, rng)
        rate = environment.profile("true_rate", fs) or 0.0
        rec = self._record(chamber_of(environment, fs), environment.duration, fs, rng=rng, rate=rate)
        rec, components = self._with_model_terms(rec)
        mount = getattr(self, "dither_mount", None)
        if environment.vibration is not None and mount is not None:
            f_d = float(getattr(self, "dither").frequency)  # noqa: B009 (the units with a dither_mount have a dither)
            rec, components = _with_dither_mount(rec, components, mount, f_d, environment.vibration)
            ignored = environment.ignored("specific_force")
        else:
            ignored = environment.ignored("specific_force", "vibration")
        return with_metadata(rec, ignored_inputs=ignored, error_components=components)

    def _record(
        self,
        chamber: Callable[[NDArray[np.float64]], NDArray[np.float64]],
        duration: float,
        fs: float,
        *,
        rng: np.random.Generator,
        rate: float | Callable[[NDArray[np.float64]], NDArray[np.float64]] = 0.0,
    ) -> Recording:
        raise NotImplementedError  # each model's statistical mode

    def _with_model_terms(self, rec: Recording) -> tuple[Recording, list[str]]:
        """The record with any model-specific truth terms, and the components that close it."""
        return rec, list(RLG_ERROR_COMPONENTS)


def _with_dither_mount(rec: Recording, components: list[str], mount: object, dither_frequency: float,
                       shaker: object) -> tuple[Recording, list[str]]:
    """``rec`` with the dither flexure's unstripped twist (:mod:`gyrobench.sim.rlg_vibration`) added.

    The term ``dither_mount_vibration`` [rad/s] joins the output and the error components.
    """
    from gyrobench.sim.rlg_vibration import dither_mount_error

    err = dither_mount_error(mount, dither_frequency, shaker, rec.n_samples, rec.fs)  # type: ignore[arg-type]
    out = rec.channels["output"]
    channels = {**rec.channels, "output": Channel(np.asarray(out.data) + err, out.unit, out.description)}
    truth = {**rec.truth, "dither_mount_vibration": Channel(
        err, "rad/s", "the dither flexure's axial-to-torsional twist under vibration, unstripped (1 - B) part")}
    return replace(rec, channels=channels, truth=truth), [*components, "dither_mount_vibration"]


# ============================================================================ statistical mode
class _CountingUnit(Protocol):
    """What the statistical mode reads from a unit."""

    @property
    def dither(self) -> Dither: ...
    @property
    def pulse_weight(self) -> float: ...
    @property
    def bias_instability(self) -> float: ...
    @property
    def rate_random_walk(self) -> float: ...
    @property
    def sensor_housing(self) -> TemperatureSensor: ...
    @property
    def sensor_cavity(self) -> TemperatureSensor: ...


class _Run(NamedTuple):
    """A validated run: ``n`` samples at ``fs`` [Hz], the ``n + 1`` sample boundaries [s],
    the chamber temperature there [K], and the six child streams (turn-on first)."""

    owner: str
    fs: float
    n: int
    t_grid: NDArray[np.float64]
    chamber: NDArray[np.float64]
    streams: list[np.random.Generator]

    @property
    def turn_on_rng(self) -> np.random.Generator:
        """The stream of the model's turn-on draws."""
        return self.streams[0]


@dataclass(frozen=True, slots=True, kw_only=True)
class _Terms:
    """What a model feeds into the count, per sample (n values unless stated).

    turn_on_bias [rad/s] (scalar); thermal_bias [rad/s]; random_walk N [rad/sqrt(s)]
    (scalar, or per sample); scale_ratio K_j/K (None: 1); t_housing, t_cavity: the true
    temperatures [K] the two sensors read; truth: the model's truth channels, placed after
    ``true_rate``; truth_last: placed after the common ones; metadata (``version`` is added).
    """

    turn_on_bias: float
    thermal_bias: NDArray[np.float64]
    random_walk: float | NDArray[np.float64]
    scale_ratio: NDArray[np.float64] | None
    t_housing: NDArray[np.float64]
    t_cavity: NDArray[np.float64]
    truth: dict[str, Channel]
    truth_last: dict[str, Channel]
    metadata: dict[str, Any]


@dataclass(frozen=True, slots=True, kw_only=True)
class _Wording:
    """Descriptions of the common channels that each model words its own way."""

    dither_angle: str
    housing_sensor: str
    cavity_sensor: str
    turn_on_bias: str
    dither_random_walk: str
    quantization: str


def _start_run(
    owner: str,
    dither: Dither,
    chamber: Callable[[NDArray[np.float64]], NDArray[np.float64]],
    duration: float,
    fs: float,
    rng: np.random.Generator,
) -> _Run:
    """Validate a statistical-mode run, spawn its streams and sample the chamber.

    ``fs`` must be <= f_d / 4 so each sample spans several dither cycles (the dither phase at
    the samples is then taken as random); ``duration x fs`` must give >= 2 samples.
    """
    _check_rng(rng)
    fs = _pos(owner, "fs", fs, "Hz")
    dur = _pos(owner, "duration", duration, "s")
    if fs > dither.frequency / 4.0:
        raise ValueError(
            f"fs must be <= dither frequency / 4 = {dither.frequency / 4.0!r} Hz in the "
            f"statistical mode; got {fs!r}"
        )
    n = int(round(dur * fs))
    if n < 2:
        raise ValueError(f"duration x fs must give >= 2 samples; got {n}")
    streams = rng.spawn(6)
    t_grid = np.arange(n + 1) / fs  # angle at sample boundaries; sample k covers [t_k, t_{k+1})
    tch = np.asarray(chamber(t_grid), dtype=float)
    return _Run(owner, fs, n, t_grid, tch, streams)


def _input_rate(
    run: _Run, rate: float | Callable[[NDArray[np.float64]], NDArray[np.float64]]
) -> NDArray[np.float64]:
    """True input rate [rad/s] of each sample: a constant, or a callable at the sample centres."""
    n, fs = run.n, run.fs
    if callable(rate):
        return np.asarray(rate(run.t_grid[:-1] + 0.5 / fs), dtype=float) * np.ones(n)
    return np.full(n, _num(run.owner, "rate", rate))


def _finish_run(
    unit: _CountingUnit,
    run: _Run,
    rate: float | Callable[[NDArray[np.float64]], NDArray[np.float64]],
    terms: _Terms,
    wording: _Wording,
    name: str,
) -> Recording:
    """Count pulses driven by the input rate and the model's ``terms``; the recording.

    Channels ``output`` [rad/s] (dither stripped), ``counts``, ``dither_angle`` [rad], ``T1``,
    ``T2`` [K] (sensors); truth ``true_rate``, the model's channels, ``turn_on_bias``,
    ``flicker_rrw``, ``dither_random_walk``, ``quantization`` [rad/s], then
    ``terms.truth_last``. Equations in the module docstring.
    """
    n, fs = run.n, run.fs
    _, r_noise, r_arw, r_dither, r_t1, r_t2 = run.streams
    noise = NoiseModel(
        bias_instability=unit.bias_instability, rate_random_walk=unit.rate_random_walk
    )
    flick = (
        noise.generate(n, fs, rng=r_noise)
        if (unit.bias_instability > 0 or unit.rate_random_walk > 0)
        else np.zeros(n)
    )
    w_in = _input_rate(run, rate)
    arw = terms.random_walk * math.sqrt(fs) * r_arw.standard_normal(n)
    drive = w_in + terms.turn_on_bias + terms.thermal_bias + flick
    total = (drive if terms.scale_ratio is None else terms.scale_ratio * drive) + arw
    theta = np.concatenate(([0.0], np.cumsum(total) / fs))
    dither = unit.dither
    d = dither.amplitude * (1.0 + dither.amplitude_jitter * r_dither.standard_normal(n + 1))
    d = d * np.sin(r_dither.uniform(0.0, 2.0 * math.pi, n + 1))
    q = unit.pulse_weight
    counts = np.diff(np.floor((theta + d) / q))
    out = (q * counts - np.diff(d)) * fs
    quant = out - np.diff(theta) * fs
    t1m = unit.sensor_housing.measure(terms.t_housing, rng=r_t1)
    t2m = unit.sensor_cavity.measure(terms.t_cavity, rng=r_t2)
    truth = {
        "true_rate": Channel(w_in, "rad/s", "input rate about the sense axis"),
        **terms.truth,
        "turn_on_bias": Channel(np.full(n, terms.turn_on_bias), "rad/s", wording.turn_on_bias),
        "flicker_rrw": Channel(flick, "rad/s", "bias instability and rate random walk"),
        "dither_random_walk": Channel(arw, "rad/s", wording.dither_random_walk),
        "quantization": Channel(quant, "rad/s", wording.quantization),
        **terms.truth_last,
    }
    return Recording(
        fs=fs,
        channels={
            "output": Channel(out, "rad/s", "dither-stripped gyro output"),
            "counts": Channel(counts, "counts", "pulses per sample (dither included)"),
            "dither_angle": Channel(d[1:], "rad", wording.dither_angle),
            "T1": Channel(t1m, "K", wording.housing_sensor),
            "T2": Channel(t2m, "K", wording.cavity_sensor),
        },
        truth=truth,
        metadata={**terms.metadata, "version": package_version()},
        name=name,
    )


#: chamber air temperature [K] an RLG record holds when its environment gives none (20 degC)
DEFAULT_CHAMBER = 293.15


def chamber_of(environment: Environment, fs: float) -> Callable[[NDArray[np.float64]], NDArray[np.float64]]:
    """The environment's temperature as the chamber-air profile t -> K an RLG model takes.

    A number is held; None holds :data:`DEFAULT_CHAMBER`; an array is held over each sample
    interval; a callable is taken as it is.
    """
    temp = environment.profile("temperature", fs)
    if temp is None:
        return held(DEFAULT_CHAMBER)
    if isinstance(temp, float):
        return held(temp)
    return temp
