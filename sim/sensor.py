"""The one device interface: a spec draws a unit, a unit simulates a record in an environment.

Every device model (:class:`gyrobench.sim.fog2d.FOG2DSpec` and its
:class:`~gyrobench.sim.fog2d.FOG2DUnit`, :class:`gyrobench.sim.fog_loop.ClosedLoopFOG`,
:class:`gyrobench.sim.mems_population.MemsResonatorSpec` and its
:class:`~gyrobench.sim.mems_resonator.MemsResonator`, :class:`gyrobench.sim.rlg.RLGSpec`,
:class:`gyrobench.sim.rlg_cavity.CavityRLGSpec`, and the datasheet parts of
:mod:`gyrobench.sim.parts`) answers the same two calls::

    unit = spec.realize(rng=rng)                      # one unit of the production population
    rec = unit.simulate(environment, fs=fs, rng=rng)  # one record (Recording)

with the inputs in one :class:`Environment` under the same names for every device:
``true_rate`` [rad/s] about the sense axis, ``temperature`` [K] (the chamber or ambient the
unit sits in), ``specific_force`` [m/s^2] along the sense axis and ``vibration`` (a shaker run,
:class:`gyrobench.sim.shaker.ShakerSignal`). Each of the first three may be a number, a profile
(a callable of time [s], e.g. :class:`gyrobench.sim.environment.PiecewiseLinear`) or a 1-D
array sampled at the output rate (one value per output sample). SI throughout.

Every record follows one schema (docs/recording.md): channel ``output`` [rad/s]; truth
``true_rate`` [rad/s] and the error components that the metadata's ``error_components``
names, whose sum is ``output - true_rate``; the environment and the model's state in
``inputs``, other rates it computed in ``detail``. A model that does not respond to an input
names it in the record's metadata (``ignored_inputs``). The models' equations, units and
references are in their own docstrings and in docs/physics.md.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from numbers import Real
from typing import ClassVar, Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from gyrobench.base.ranges import Constraint, FieldRange, shown, validate
from gyrobench.base.validate import check_fs, check_rng
from gyrobench.io.recording import Recording
from gyrobench.sim.environment import PiecewiseLinear
from gyrobench.sim.shaker import ShakerSignal

__all__ = [
    "Environment",
    "Profile",
    "SensorUnit",
    "Sensor",
    "check_call",
    "chamber_program",
    "held",
    "with_metadata",
    "FOG_ERROR_COMPONENTS",
    "RLG_ERROR_COMPONENTS",
]

Profile = Callable[[NDArray[np.float64]], NDArray[np.float64]]
"""A quantity as a function of time [s] -> its SI value (vectorised)."""

Input = float | Profile | NDArray[np.float64]


def _input_kind(v: object, *, optional: bool) -> bool:
    """Whether an input is of a kind :class:`Environment` takes: a number, a callable, an array."""
    return (v is None and optional) or callable(v) or isinstance(v, np.ndarray) or (
        isinstance(v, Real) and not isinstance(v, bool)
    )


def _input_value(v: object, *, columns: bool) -> bool:
    """Whether an input of a valid kind holds a valid value: finite; an array 1-D (or (n, k)), non-empty."""
    if isinstance(v, np.ndarray):
        return v.ndim in ((1, 2) if columns else (1,)) and v.size > 0 and bool(np.all(np.isfinite(v)))
    return not isinstance(v, Real) or math.isfinite(float(v))


def _input_constraints(
    name: str, unit: str, *, optional: bool = False, columns: bool = False
) -> tuple[Constraint, ...]:
    """The declared constraints of one input of :class:`Environment`: its kind, then its value."""
    shape = "1-D or (n, k)" if columns else "1-D"
    kinds = f"a number, a callable of time or a {shape} array" + (" or None" if optional else "")
    return (
        Constraint(
            f"{name} is {kinds}",
            lambda c: _input_kind(getattr(c, name), optional=optional),
            lambda c: f"{name} must be {kinds} [{unit}]; got {type(getattr(c, name)).__name__}",
            TypeError,
        ),
        Constraint(
            f"{name} is finite",
            lambda c: _input_value(getattr(c, name), columns=columns),
            lambda c: (
                f"{name} must be a finite {shape} array [{unit}]; got {shown(getattr(c, name))}"
                if isinstance(getattr(c, name), np.ndarray)
                else f"{name} must be finite [{unit}]; got {getattr(c, name)!r}"
            ),
        ),
    )


@dataclass(frozen=True, slots=True)
class Environment:
    """What the test equipment does to a unit over one record (SI).

    Parameters
    ----------
    duration : float
        Record length [s], > 0.
    true_rate : float, callable or ndarray
        Rate of the table about the sense axis [rad/s] (the Earth's rate is added by the
        models that model it). Default 0.
    temperature : float, callable, ndarray or None
        Chamber / ambient temperature [K]; None: the model's reference temperature.
    specific_force : float, callable or ndarray
        Specific force along the sense axis [m/s^2] (+9.8 at rest with the axis up). Default 0.
    vibration : ShakerSignal or None
        A shaker run (table acceleration at the shaker's own sample rate, covering the record
        from t = 0), for the models with a vibration response; None: no vibration.

    Notes
    -----
    An array holds one value per output sample (length ``floor(duration * fs)``), taken at
    the sample centres t_k = (k + 1/2)/fs; a callable is evaluated where the model needs it.

    ``true_rate`` may also be an (n, k) array: k independent segments of ``duration`` each, one
    per column, run side by side from the same state (a rate table's dwells, each settled from
    rest). Only a model that says so in its ``simulate`` takes it (:func:`check_call` with
    ``columns=True``); its record holds the segments one after another, column by column.
    """

    duration: float
    true_rate: Input = 0.0
    temperature: Input | None = None
    specific_force: Input = 0.0
    vibration: ShakerSignal | None = None

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "duration": FieldRange(0, math.inf, "s", "record length", low_open=True),
    }
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        *_input_constraints("true_rate", "rad/s", columns=True),
        *_input_constraints("temperature", "K", optional=True),
        *_input_constraints("specific_force", "m/s^2"),
        Constraint(
            "vibration is a ShakerSignal or None",
            lambda c: c.vibration is None or isinstance(c.vibration, ShakerSignal),
            lambda c: f"vibration must be a sim.shaker.ShakerSignal or None; got {type(c.vibration).__name__}",
            TypeError,
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above

    @property
    def columns(self) -> int:
        """The number k of independent segments: the columns of an (n, k) ``true_rate``, else 1."""
        v = self.true_rate
        return int(v.shape[1]) if isinstance(v, np.ndarray) and v.ndim == 2 else 1

    def n_samples(self, fs: float) -> int:
        """Samples of a record at ``fs`` [Hz]: floor(duration fs)."""
        return int(math.floor(self.duration * fs + 1e-9))

    def sampled(self, name: str, fs: float, default: float = 0.0) -> NDArray[np.float64]:
        """Input ``name`` at the sample centres t_k = (k + 1/2)/fs [SI unit of the input]."""
        n = self.n_samples(fs)
        v = getattr(self, name)
        if v is None:
            return np.full(n, float(default))
        if isinstance(v, np.ndarray):
            if len(v) != n:
                raise ValueError(
                    f"Environment.{name} as an array must have floor(duration * fs) = {n} samples; got {len(v)}"
                )
            return np.asarray(v, dtype=float)
        if callable(v):
            return np.asarray(v((np.arange(n) + 0.5) / fs), dtype=float).reshape(n)
        return np.full(n, float(v))

    def profile(self, name: str, fs: float) -> float | Profile | None:
        """Input ``name`` as a model takes it: a number, a callable, or None (model default).

        An array becomes the zero-order hold of its samples over their intervals
        [k/fs, (k + 1)/fs).
        """
        v = getattr(self, name)
        if isinstance(v, np.ndarray):
            samples = self.sampled(name, fs)
            n = len(samples)

            def hold(t: NDArray[np.float64]) -> NDArray[np.float64]:
                k = np.clip(np.floor(np.asarray(t, dtype=float) * fs).astype(int), 0, n - 1)
                return samples[k]

            return hold
        if isinstance(v, Real):
            return float(v)
        return v

    def is_zero(self, name: str) -> bool:
        """True when input ``name`` is the number 0 (or None: no such input acts)."""
        v = getattr(self, name)
        return v is None or (isinstance(v, Real) and float(v) == 0.0)

    def ignored(self, *names: str) -> list[str]:
        """The inputs among ``names`` that are set (not zero or None): a model lists those it ignores."""
        return [name for name in names if not self.is_zero(name)]


@runtime_checkable
class SensorUnit(Protocol):
    """One drawn unit: simulates a record of its output in an environment."""

    def simulate(self, environment: Environment, *, fs: float, rng: np.random.Generator) -> Recording:
        """One record at output rate ``fs`` [Hz]; truth holds ``true_rate`` [rad/s]."""
        ...


@runtime_checkable
class Sensor(Protocol):
    """A production population of one design: draws units."""

    def realize(self, *, rng: np.random.Generator) -> SensorUnit:
        """Draw one unit."""
        ...


FOG_ERROR_COMPONENTS = (
    "scale_factor_error",
    "loop_error",
    "nonreciprocal",
    "strain_nonreciprocity",
    "rectification",
    "optical_noise",
    "ieee_noise",
)
"""Truth channels of a FOG record whose sum is output - true_rate (:meth:`ClosedLoopFOG.simulate`)."""

RLG_ERROR_COMPONENTS = ("turn_on_bias", "thermal_bias", "flicker_rrw", "dither_random_walk", "quantization")
"""Truth channels of an RLG record whose sum is output - true_rate (the cavity model adds ``scale_factor_error``)."""


def check_call(environment: object, fs: object, rng: object, *, columns: bool = False) -> float:
    """Check the arguments every ``simulate(environment, *, fs, rng)`` takes; returns ``fs`` [Hz].

    Parameters
    ----------
    environment : object
        The environment (an :class:`Environment`).
    fs : object
        The output rate [Hz].
    rng : object
        The random generator (a :class:`numpy.random.Generator`).
    columns : bool
        The calling model runs independent segments (an (n, k) ``true_rate``); False refuses them.

    Returns
    -------
    float
        ``fs`` [Hz].

    Raises
    ------
    TypeError
        ``environment`` is not an :class:`Environment` or ``rng`` not a Generator.
    ValueError
        ``fs`` is not a finite number > 0 Hz, or ``true_rate`` has columns the model does not run.
    """
    if not isinstance(environment, Environment):
        raise TypeError(f"environment must be a gyrobench.sim.sensor.Environment; got {type(environment).__name__}")
    check_rng(rng)
    if environment.columns > 1 and not columns:
        raise ValueError(
            "Environment.true_rate must be 1-D for this model (it runs no independent segments); "
            f"got shape {np.asarray(environment.true_rate).shape}"
        )
    return check_fs(fs)


def with_metadata(rec: Recording, *, name: str | None = None, **extra: object) -> Recording:
    """``rec`` with ``extra`` added to its metadata (and renamed to ``name`` when given).

    Parameters
    ----------
    rec : Recording
        The recording.
    name : str, optional
        Its new name.
    **extra : object
        Metadata entries to add.

    Returns
    -------
    Recording
        A new recording (``rec`` is not changed).
    """
    return dataclasses.replace(rec, metadata={**rec.metadata, **extra}, name=rec.name if name is None else name)


def held(value: float) -> Profile:
    """The constant profile t -> ``value`` (vectorised).

    Parameters
    ----------
    value : float
        The value (SI).

    Returns
    -------
    callable
        t -> an array of ``value`` shaped like t.
    """
    const = float(value)

    def _held(t: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.full(np.shape(t), const)

    return _held


def chamber_program(environment: Environment, fs: float, default: float) -> PiecewiseLinear:
    """The environment's temperature as a chamber program over [0, duration] [K].

    A number (or None: ``default``) is held; a :class:`PiecewiseLinear` is taken as it is;
    an array is linear between its sample centres (held before the first and after the last);
    any other callable is sampled at the sample centres the same way.

    Parameters
    ----------
    environment : Environment
        The environment.
    fs : float
        The output rate [Hz] (the sample centres of an array or callable).
    default : float
        Temperature held when the environment gives none [K].

    Returns
    -------
    PiecewiseLinear
        Temperature [K] against time [s].
    """
    v = environment.temperature
    if isinstance(v, PiecewiseLinear):
        return v
    if v is None or isinstance(v, Real):
        temp = float(default if v is None else v)
        return PiecewiseLinear(np.array([0.0, environment.duration]), np.array([temp, temp]))
    temps = environment.sampled("temperature", fs)
    centres = (np.arange(len(temps)) + 0.5) / fs
    knots = np.concatenate(([0.0], centres, [environment.duration])).astype(np.float64)
    return PiecewiseLinear(knots, np.concatenate(([temps[0]], temps, [temps[-1]])).astype(np.float64))
