"""One interface over the device models: a :class:`Sensor` spec draws a unit, a unit simulates.

Every technology the scenarios use is reachable through the same two calls::

    unit = sensor.realize(rng)                      # one unit of the production population
    rec = unit.simulate(environment, fs=fs, rng=rng)  # one record (:class:`Recording`)

with the inputs in one :class:`Environment` under the same names for every device:
``true_rate`` [rad/s] about the sense axis, ``temperature`` [K] (the chamber / ambient the
unit sits in), ``specific_force`` [m/s^2] along the sense axis. Each may be a number, a
profile (a callable of time [s], e.g. :class:`gyrobench.sim.environment.PiecewiseLinear`)
or a 1-D array sampled at the output rate (one value per output sample). SI throughout.

This module is an additive layer: the adapters call the models' own ``realize`` and
``simulate`` unchanged (:mod:`gyrobench.sim.fog2d`, :mod:`gyrobench.sim.mems_resonator`,
:mod:`gyrobench.sim.rlg`, :mod:`gyrobench.sim.rlg_cavity`), whose equations, units and
references are stated in their docstrings and in docs/physics.md (3.8-3.9 FOG, 5.1 MEMS,
6 RLG). Every record's truth holds ``true_rate`` [rad/s]; a model that does not respond to
an input (the FOG and RLG models have no g-sensitive term) states so in the record's
metadata (``ignored_inputs``). Where the model keeps its error components, the metadata
``error_components`` names the truth channels whose sum is ``rate - true_rate`` (empty for
the MEMS slow flow, which does not split its output).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from numbers import Real
from typing import Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from gyrobench.base.validate import check_fs, check_rng, positive_number
from gyrobench.io.recording import Channel, Recording
from gyrobench.sim import mems_resonator as mr
from gyrobench.sim.environment import PiecewiseLinear
from gyrobench.sim.fog2d import FOG2DSpec, FOG2DUnit
from gyrobench.sim.rlg import RLGSpec, RLGUnit
from gyrobench.sim.rlg_cavity import CavityRLG, CavityRLGSpec

__all__ = [
    "Environment",
    "Profile",
    "SensorUnit",
    "Sensor",
    "FogSensor",
    "FogSensorUnit",
    "MemsSensor",
    "MemsSensorUnit",
    "RlgSensor",
    "RlgSensorUnit",
    "FOG_ERROR_COMPONENTS",
    "RLG_ERROR_COMPONENTS",
]

Profile = Callable[[NDArray[np.float64]], NDArray[np.float64]]
"""A quantity as a function of time [s] -> its SI value (vectorised)."""

Input = float | Profile | NDArray[np.float64]


def _check_input(name: str, v: object, unit: str, *, optional: bool = False) -> None:
    if v is None and optional:
        return
    if callable(v):
        return
    if isinstance(v, Real) and not isinstance(v, bool):
        if not math.isfinite(float(v)):
            raise ValueError(f"Environment.{name} must be finite [{unit}]; got {v!r}")
        return
    if isinstance(v, np.ndarray):
        if v.ndim != 1 or not np.all(np.isfinite(v)):
            raise ValueError(f"Environment.{name} must be a finite 1-D array [{unit}]; got shape {v.shape}")
        return
    raise TypeError(
        f"Environment.{name} must be a number, a callable of time or a 1-D array [{unit}]; got {type(v).__name__}"
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

    Notes
    -----
    An array holds one value per output sample (length ``floor(duration * fs)``), taken at
    the sample centres t_k = (k + 1/2)/fs; a callable is evaluated where the model needs it.
    """

    duration: float
    true_rate: Input = 0.0
    temperature: Input | None = None
    specific_force: Input = 0.0

    def __post_init__(self) -> None:
        positive_number("Environment.duration", self.duration, "s")
        _check_input("true_rate", self.true_rate, "rad/s")
        _check_input("temperature", self.temperature, "K", optional=True)
        _check_input("specific_force", self.specific_force, "m/s^2")

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
        v = getattr(self, name)
        return isinstance(v, Real) and float(v) == 0.0


@runtime_checkable
class SensorUnit(Protocol):
    """One drawn unit: simulates a record of its output in an environment."""

    def simulate(self, environment: Environment, *, fs: float, rng: np.random.Generator) -> Recording:
        """One record at output rate ``fs`` [Hz]; truth holds ``true_rate`` [rad/s]."""
        ...


@runtime_checkable
class Sensor(Protocol):
    """A production population of one design: draws units."""

    def realize(self, rng: np.random.Generator) -> SensorUnit:
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


def _check_common(fs: float, rng: object) -> float:
    check_rng(rng)
    return check_fs(fs)


def _with_meta(rec: Recording, **extra: object) -> Recording:
    return Recording(
        fs=rec.fs,
        channels=rec.channels,
        truth=rec.truth,
        t0=rec.t0,
        metadata={**rec.metadata, **extra},
        name=rec.name,
    )


# ---------------------------------------------------------------------------------------------
# FOG: closed loop on the (r, z) coil


@dataclass(frozen=True, slots=True)
class FogSensor:
    """Closed-loop FOG on the (r, z) coil (:class:`gyrobench.sim.fog2d.FOG2DSpec`) as a :class:`Sensor`.

    Parameters
    ----------
    spec : FOG2DSpec
        The FOG population.
    """

    spec: FOG2DSpec

    def __post_init__(self) -> None:
        if not isinstance(self.spec, FOG2DSpec):
            raise TypeError(f"FogSensor.spec must be a FOG2DSpec; got {type(self.spec).__name__}")

    def realize(self, rng: np.random.Generator) -> FogSensorUnit:
        """Draw one coil (:meth:`FOG2DSpec.realize`)."""
        return FogSensorUnit(self.spec.realize(rng=rng))


@dataclass(frozen=True, slots=True)
class FogSensorUnit:
    """One FOG2D unit behind :class:`SensorUnit` (:meth:`gyrobench.sim.fog2d.FOG2DUnit.simulate`).

    The environment's temperature is the chamber program: a number (held over the record),
    a :class:`PiecewiseLinear`, or an array (sampled at fs, linear between the sample
    centres); None holds the spec's scale-factor reference temperature. The model has no
    g-sensitive term: ``specific_force`` does not act (metadata ``ignored_inputs``).

    Parameters
    ----------
    unit : FOG2DUnit
        The drawn unit.
    """

    unit: FOG2DUnit

    def _chamber(self, env: Environment, fs: float) -> PiecewiseLinear:
        v = env.temperature
        if isinstance(v, PiecewiseLinear):
            return v
        if v is None or isinstance(v, Real):
            temp = self.unit.spec.scale_factor_ref_temperature if v is None else float(v)
            return PiecewiseLinear(np.array([0.0, env.duration]), np.array([temp, temp]))
        if isinstance(v, np.ndarray):
            temps = env.sampled("temperature", fs)
            centres = (np.arange(len(temps)) + 0.5) / fs
            knots = np.concatenate(([0.0], centres, [env.duration])).astype(np.float64)
            return PiecewiseLinear(knots, np.concatenate(([temps[0]], temps, [temps[-1]])).astype(np.float64))
        raise TypeError(
            "Environment.temperature for the FOG must be a number, a PiecewiseLinear or an array; "
            f"got {type(v).__name__}"
        )

    def simulate(self, environment: Environment, *, fs: float, rng: np.random.Generator) -> Recording:
        """One chamber run over ``environment.duration`` at ``fs`` [Hz] (class docstring)."""
        fs = _check_common(fs, rng)
        if not isinstance(environment, Environment):
            raise TypeError(f"environment must be an Environment; got {type(environment).__name__}")
        rec = self.unit.simulate(
            self._chamber(environment, fs),
            fs=fs,
            rng=rng,
            true_rate=environment.profile("true_rate", fs),  # type: ignore[arg-type]
        )
        ignored = [] if environment.is_zero("specific_force") else ["specific_force"]
        truth = {**rec.truth, "true_rate": rec.truth["rate"]}
        rec = Recording(fs=rec.fs, channels=rec.channels, truth=truth, t0=rec.t0, metadata=rec.metadata, name=rec.name)
        return _with_meta(rec, ignored_inputs=ignored, error_components=list(FOG_ERROR_COMPONENTS))


# ---------------------------------------------------------------------------------------------
# MEMS: vibratory gyro from resonator physics


@dataclass(frozen=True, slots=True)
class MemsSensor:
    """Resonator-physics MEMS population (:class:`gyrobench.sim.mems_resonator.MemsResonatorSpec`).

    Parameters
    ----------
    spec : MemsResonatorSpec
    temperature_block : float
        Length [s] of the blocks over which a varying temperature is held at its block mean
        (:class:`MemsSensorUnit`). Default 1 s.
    noise, adc, flicker : bool
        As :func:`gyrobench.sim.mems_resonator.simulate`.
    """

    spec: mr.MemsResonatorSpec
    temperature_block: float = 1.0
    noise: bool = True
    adc: bool = True
    flicker: bool = True

    def __post_init__(self) -> None:
        if not isinstance(self.spec, mr.MemsResonatorSpec):
            raise TypeError(f"MemsSensor.spec must be a MemsResonatorSpec; got {type(self.spec).__name__}")
        positive_number("MemsSensor.temperature_block", self.temperature_block, "s")

    def realize(self, rng: np.random.Generator) -> MemsSensorUnit:
        """Draw one unit (:meth:`MemsResonatorSpec.realize`)."""
        return MemsSensorUnit(
            self.spec.realize(rng=rng),
            temperature_block=float(self.temperature_block),
            noise=self.noise,
            adc=self.adc,
            flicker=self.flicker,
        )


@dataclass(frozen=True, slots=True)
class MemsSensorUnit:
    """One MEMS resonator unit behind :class:`SensorUnit` (slow flow, :func:`mems_resonator.simulate`).

    Inputs are taken at the sample centres and held over each output interval (the slow
    flow's zero-order hold). A constant temperature (number or None: the unit's T0) runs the
    record in one call. A varying temperature (array or callable) is quasi-static: the
    record is cut into blocks of ``temperature_block`` seconds, each simulated at its mean
    temperature from the noise-free equilibrium of its first rate, with its own child
    stream of ``rng``. Exact when the temperature is constant over a block; the loop's
    transient at a block start (settling ~ a few 1/(loop bandwidth), ms) and the 1/f
    term's memory across blocks are lost, so choose blocks long against both the loop's
    settling and the thermal time constant's resolution needed.

    Parameters
    ----------
    unit : MemsResonator
        The drawn resonator.
    temperature_block : float
        Length of a block at one temperature when the temperature varies [s].
    noise : bool
        Simulate the noise sources (False: noise-free).
    adc : bool
        Quantize the output with the unit's ADC.
    flicker : bool
        Include the 1/f (bias-instability) term.
    """

    unit: mr.MemsResonator
    temperature_block: float = 1.0
    noise: bool = True
    adc: bool = True
    flicker: bool = True

    def simulate(self, environment: Environment, *, fs: float, rng: np.random.Generator) -> Recording:
        """One record at ``fs`` [Hz]: channel ``rate`` [rad/s].

        Truth: ``true_rate`` [rad/s], ``temperature`` [K], ``specific_force`` [m/s^2].
        """
        fs = _check_common(fs, rng)
        if not isinstance(environment, Environment):
            raise TypeError(f"environment must be an Environment; got {type(environment).__name__}")
        n = environment.n_samples(fs)
        if n < 2:
            raise ValueError(f"duration * fs must give >= 2 samples; got {environment.duration!r} s at {fs!r} Hz")
        rate = environment.sampled("true_rate", fs)
        force = environment.sampled("specific_force", fs)
        temp = environment.sampled("temperature", fs, default=self.unit.reference_temperature)
        out = np.empty(n)
        kw = dict(noise=self.noise, adc=self.adc, flicker=self.flicker)
        if np.all(temp == temp[0]):
            res = mr.simulate(self.unit, rate, fs=fs, rng=rng, temperature=float(temp[0]), specific_force=force, **kw)
            out[:] = res.output
            blocks = 1
        else:
            m = max(2, int(round(self.temperature_block * fs)))
            starts = list(range(0, n, m))
            if n - starts[-1] < 2 and len(starts) > 1:  # a last block of one sample joins the one before
                starts.pop()
            stops = starts[1:] + [n]
            for (a, b), child in zip(zip(starts, stops, strict=True), rng.spawn(len(starts)), strict=True):
                res = mr.simulate(
                    self.unit,
                    rate[a:b],
                    fs=fs,
                    rng=child,
                    temperature=float(np.mean(temp[a:b])),
                    specific_force=force[a:b],
                    **kw,
                )
                out[a:b] = res.output
            blocks = len(starts)
        return Recording(
            fs=fs,
            channels={
                "rate": Channel(out, "rad/s", "gyro output"),
                "temperature": Channel(temp, "K", "die temperature (as driven)"),
            },
            truth={
                "true_rate": Channel(rate, "rad/s", "input rate about the sense axis"),
                "temperature": Channel(temp, "K", "die temperature"),
                "specific_force": Channel(force, "m/s^2", "specific force along the sense axis"),
            },
            t0=0.5 / fs,
            metadata={
                "model": "gyrobench.sim.sensor.MemsSensorUnit -> gyrobench.sim.mems_resonator.simulate",
                "temperature_blocks": blocks,
                "ignored_inputs": [],
                "error_components": [],
            },
            name="mems",
        )


# ---------------------------------------------------------------------------------------------
# RLG: statistical (rlg) and cavity (rlg_cavity) models


@dataclass(frozen=True, slots=True)
class RlgSensor:
    """RLG population, either :class:`gyrobench.sim.rlg.RLGSpec` or :class:`gyrobench.sim.rlg_cavity.CavityRLGSpec`.

    Parameters
    ----------
    spec : RLGSpec or CavityRLGSpec
        The RLG population.
    """

    spec: RLGSpec | CavityRLGSpec

    def __post_init__(self) -> None:
        if not isinstance(self.spec, (RLGSpec, CavityRLGSpec)):
            raise TypeError(f"RlgSensor.spec must be an RLGSpec or CavityRLGSpec; got {type(self.spec).__name__}")

    def realize(self, rng: np.random.Generator) -> RlgSensorUnit:
        """Draw one unit (the spec's ``realize``)."""
        return RlgSensorUnit(self.spec.realize(rng=rng))


@dataclass(frozen=True, slots=True)
class RlgSensorUnit:
    """One RLG unit behind :class:`SensorUnit` (its ``simulate``: gyro switched on at t = 0).

    The environment's temperature is the chamber air [K] (None: 293.15 K held); an array is
    held over each sample interval. The models have no g-sensitive term: ``specific_force``
    does not act (metadata ``ignored_inputs``).

    Parameters
    ----------
    unit : RLGUnit or CavityRLG
        The drawn unit.
    """

    unit: RLGUnit | CavityRLG

    def simulate(self, environment: Environment, *, fs: float, rng: np.random.Generator) -> Recording:
        """One record at ``fs`` [Hz] (truth ``true_rate`` and the model's components)."""
        fs = _check_common(fs, rng)
        if not isinstance(environment, Environment):
            raise TypeError(f"environment must be an Environment; got {type(environment).__name__}")
        temp = environment.profile("temperature", fs)
        if temp is None:
            temp = 293.15
        chamber: Profile
        if isinstance(temp, float):
            const = temp

            def _held(t: NDArray[np.float64]) -> NDArray[np.float64]:
                return np.full(np.shape(t), const)

            chamber = _held
        else:
            chamber = temp
        rec = self.unit.simulate(
            chamber,
            environment.duration,
            fs,
            rng=rng,
            rate=environment.profile("true_rate", fs),  # type: ignore[arg-type]
        )
        ignored = [] if environment.is_zero("specific_force") else ["specific_force"]
        if "scale_factor_ratio" not in rec.truth:
            return _with_meta(rec, ignored_inputs=ignored, error_components=list(RLG_ERROR_COMPONENTS))
        tr = rec.truth
        drive = sum(tr[k].data for k in ("true_rate", "turn_on_bias", "thermal_bias", "flicker_rrw"))
        sf_err = (tr["scale_factor_ratio"].data - 1.0) * drive
        truth = {
            **tr,
            "scale_factor_error": Channel(
                sf_err, "rad/s", "(K/K_ref - 1) x (true rate + turn-on, thermal and flicker bias)"
            ),
        }
        rec = Recording(fs=rec.fs, channels=rec.channels, truth=truth, t0=rec.t0, metadata=rec.metadata, name=rec.name)
        return _with_meta(
            rec, ignored_inputs=ignored, error_components=[*RLG_ERROR_COMPONENTS, "scale_factor_error"]
        )
