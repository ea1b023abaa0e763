"""Environment profiles: what the rate table and the thermal chamber do over time.

Building blocks only; the papers' protocols are composed from them in
``scenarios``. Everything is SI: time [s], rate [rad/s], temperature [K].

A profile is a continuous piecewise-linear function of time,
:class:`PiecewiseLinear`, built from contiguous segments. Two builders cover the
test equipment:

* :func:`thermal_profile` -- a chamber program of ramps (at a rate or to a
  temperature in a given time) and soaks (holds);
* :func:`rate_steps` -- a rate-table program: dwell at each rate, with
  acceleration-limited transitions between rates, plus the settled window of
  each dwell (where a test averages the output).

Shaker profiles (sine sweeps, random vibration) live in :mod:`gyrobench.sim.shaker`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.base.ranges import Constraint, FieldRange, as_array, shown, validate

__all__ = ["PiecewiseLinear", "Ramp", "Soak", "thermal_profile", "RateSteps", "rate_steps"]


def _finite(name: str, v: float) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)) or not math.isfinite(v):
        raise ValueError(f"{name} must be a finite number; got {v!r}")
    return float(v)


def _positive(name: str, v: float, unit: str) -> float:
    v = _finite(name, v)
    if v <= 0:
        raise ValueError(f"{name} must be > 0 {unit}; got {v!r}")
    return v


def _is_array(v: object) -> bool:
    return isinstance(v, np.ndarray)


def _first_fall(t: NDArray[np.float64]) -> tuple[float, float]:
    """The first pair of times that does not increase."""
    i = int(np.flatnonzero(np.diff(t) <= 0)[0])
    return float(t[i]), float(t[i + 1])


@dataclass(frozen=True, slots=True)
class PiecewiseLinear:
    """A continuous piecewise-linear profile through knots ``(times[i], values[i])``.

    Parameters
    ----------
    times : ndarray
        Knot times [s], strictly increasing (a step is two knots a tiny time apart).
    values : ndarray
        Values at the knots [SI unit of the quantity].

    Notes
    -----
    Between knots the value is interpolated linearly; before the first knot and
    after the last it is held. Its derivative is piecewise constant:
    (values[i+1] - values[i]) / (times[i+1] - times[i]) on each segment.
    """

    times: NDArray[np.float64]
    values: NDArray[np.float64]

    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "times and values are 1-D of equal length >= 1",
            lambda c: _is_array(c.times) and _is_array(c.values) and c.times.ndim == 1
            and c.times.shape == c.values.shape and c.times.size >= 1,
            lambda c: f"times and values must be 1-D arrays of equal length >= 1 [s], [SI]; got "
            f"{shown(c.times)} and {shown(c.values)}",
        ),
        Constraint(
            "times and values are finite",
            lambda c: bool(np.all(np.isfinite(c.times)) and np.all(np.isfinite(c.values))),
            lambda c: f"times and values must be finite [s], [SI]; got {shown(c.times)} and {shown(c.values)}",
        ),
        Constraint(
            "times strictly increasing",
            lambda c: not np.any(np.diff(c.times) <= 0),
            lambda c: "times must be strictly increasing [s]; got {!r} then {!r} s".format(*_first_fall(c.times)),
        ),
    )

    def __post_init__(self) -> None:
        object.__setattr__(self, "times", as_array(self.times))
        object.__setattr__(self, "values", as_array(self.values))
        validate(self)  # the declared constraints above

    @property
    def duration(self) -> float:
        """Time of the last knot minus the first [s]."""
        return float(self.times[-1] - self.times[0])

    def __call__(self, t: ArrayLike) -> NDArray[np.float64]:
        """Values at times ``t`` [s]."""
        return np.interp(np.asarray(t, dtype=float), self.times, self.values)

    def derivative(self, t: ArrayLike) -> NDArray[np.float64]:
        """Slope at times ``t`` [unit/s] (right-continuous at knots; 0 outside)."""
        t = np.asarray(t, dtype=float)
        slopes = np.diff(self.values) / np.diff(self.times)
        i = np.searchsorted(self.times, t, side="right") - 1
        inside = (i >= 0) & (i < len(slopes))
        out = np.zeros_like(t)
        out[inside] = slopes[i[inside]]
        return out

    @classmethod
    def from_segments(
        cls, segments: Sequence[tuple[float, float, float, float]], *, tol: float = 1e-9
    ) -> PiecewiseLinear:
        """Build from explicit segments ``(t_start, t_end, v_start, v_end)``.

        Consecutive segments must touch in time and value: a gap, an overlap or a
        jump raises ``ValueError`` naming the segment.
        """
        if not segments:
            raise ValueError("segments must hold at least one (t_start, t_end, v_start, v_end); got none")
        times: list[float] = []
        values: list[float] = []
        for k, seg in enumerate(segments):
            if len(seg) != 4:
                raise ValueError(f"segment {k} must be (t_start, t_end, v_start, v_end); got {seg!r}")
            t0, t1, v0, v1 = (_finite(f"segment {k} element", x) for x in seg)
            if t1 <= t0:
                raise ValueError(f"segment {k} must end after it starts; got t_start={t0!r} s, t_end={t1!r} s")
            if k:
                if abs(t0 - times[-1]) > tol * max(1.0, abs(t0)):
                    kind = "a gap" if t0 > times[-1] else "an overlap"
                    raise ValueError(
                        f"segment {k} starts at {t0!r} s but segment {k - 1} ends at {times[-1]!r} s: "
                        f"{kind} in the profile"
                    )
                if abs(v0 - values[-1]) > tol * max(1.0, abs(v0)):
                    raise ValueError(
                        f"segment {k} starts at value {v0!r} but segment {k - 1} ends at {values[-1]!r}: "
                        "a jump in the profile"
                    )
                times.append(t1)
                values.append(v1)
            else:
                times += [t0, t1]
                values += [v0, v1]
        return cls(np.array(times), np.array(values))


@dataclass(frozen=True, slots=True, kw_only=True)
class Ramp:
    """Chamber ramp to ``target`` [K] at ``rate`` [K/s] (sign taken from the direction) or over ``duration`` [s].

    Parameters
    ----------
    target : float
        Temperature at the end of the ramp [K].
    rate : float, optional
        Ramp rate [K/s], > 0; its sign is taken from the direction. Give ``rate`` or ``duration``.
    duration : float, optional
        Ramp duration [s], > 0.
    """

    target: float
    rate: float | None = None
    duration: float | None = None

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "target": FieldRange(-math.inf, math.inf, "K", "the temperature the ramp ends at"),
        "rate": FieldRange(-math.inf, math.inf, "K/s", "ramp rate, either sign (None: given by duration)"),
        "duration": FieldRange(0, math.inf, "s", "ramp time (None: given by rate)", low_open=True),
    }
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "exactly one of rate, duration",
            lambda c: (c.rate is None) != (c.duration is None),
            lambda c: f"rate [K/s] / duration [s]: give exactly one of rate or duration; got rate={c.rate!r}, "
            f"duration={c.duration!r}",
        ),
        Constraint(
            "rate != 0",
            lambda c: c.rate != 0,
            lambda c: f"rate must be > 0 K/s in magnitude; got {c.rate!r}",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above


@dataclass(frozen=True, slots=True, kw_only=True)
class Soak:
    """Hold the current temperature for ``duration`` [s].

    Parameters
    ----------
    duration : float
        Hold time [s], > 0.
    """

    duration: float

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "duration": FieldRange(0, math.inf, "s", "time held at the last temperature", low_open=True),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared spec above


def thermal_profile(start: float, steps: Sequence[Ramp | Soak], *, t0: float = 0.0) -> PiecewiseLinear:
    """A chamber program: start at ``start`` [K] and run ramps and soaks in order.

    Returns
    -------
    PiecewiseLinear
        Chamber temperature [K] against time [s], from ``t0`` to the end of the last step.

    Parameters
    ----------
    start : float
        Initial chamber temperature [K].
    steps : sequence of Ramp or Soak
        The program.
    t0 : float
        Start time [s].

    Examples
    --------
    >>> from gyrobench.base import units
    >>> p = thermal_profile(units.celsius(-10.0), [Soak(duration=3600.0),
    ...     Ramp(target=units.celsius(40.0), rate=10.0 / 3600.0)])
    >>> p.duration / 3600.0, round(float(units.to_celsius(p(p.times[-1]))), 9)
    (6.0, 40.0)
    """
    temp = _finite("start", start)
    if not steps:
        raise ValueError("steps must hold at least one Ramp or Soak; got none")
    times, values = [float(t0)], [temp]
    for k, s in enumerate(steps):
        if isinstance(s, Soak):
            times.append(times[-1] + s.duration)
            values.append(temp)
        elif isinstance(s, Ramp):
            delta = s.target - temp
            if delta == 0:
                raise ValueError(f"step {k}: Ramp to {s.target!r} K from the same temperature; use Soak")
            if s.duration is not None:
                dur = s.duration
            else:
                assert s.rate is not None  # Ramp.__post_init__ requires a duration or a rate
                dur = abs(delta) / abs(s.rate)
            temp = float(s.target)
            times.append(times[-1] + dur)
            values.append(temp)
        else:
            raise TypeError(f"step {k} must be a Ramp or a Soak; got {type(s).__name__}")
    return PiecewiseLinear(np.array(times), np.array(values))


@dataclass(frozen=True, slots=True)
class RateSteps:
    """A rate-table program and the settled window of each dwell.

    Attributes
    ----------
    profile : PiecewiseLinear
        Table rate [rad/s] over time.
    rates : ndarray
        Commanded rate of each dwell [rad/s].
    windows : ndarray, shape (n_rates, 2)
        [start, end) times [s] of the settled part of each dwell, where the
        output is averaged.
    """

    profile: PiecewiseLinear
    rates: NDArray[np.float64]
    windows: NDArray[np.float64]


def rate_steps(
    rates: ArrayLike,
    *,
    dwell: float,
    settle: float,
    acceleration: float,
    lead_in: float = 0.0,
    t0: float = 0.0,
) -> RateSteps:
    """A rate table stepping through ``rates`` [rad/s] with acceleration-limited transitions.

    Returns
    -------
    RateSteps
        The rate profile [rad/s] against time [s] with the dwell windows to average.

    Parameters
    ----------
    rates : array_like
        Commanded rates in order [rad/s].
    dwell : float
        Time spent at each rate once reached [s], including ``settle``.
    settle : float
        Part of each dwell discarded before averaging [s], 0 <= settle < dwell.
    acceleration : float
        Table angular acceleration during transitions [rad/s^2], > 0.
    lead_in : float
        Time at zero rate before the first transition (warm-up) [s].
    t0 : float
        Start time [s].

    Notes
    -----
    Between dwells the rate changes linearly at ``acceleration``: the transition
    from w_a to w_b lasts |w_b - w_a| / acceleration. The profile starts and ends
    at rest (0 rad/s).
    """
    w = np.asarray(rates, dtype=float)
    if w.ndim != 1 or len(w) < 1 or not np.all(np.isfinite(w)):
        raise ValueError(f"rates must be a 1-D array of finite values [rad/s]; got {rates!r}")
    dwell = _positive("dwell", dwell, "s")
    acc = _positive("acceleration", acceleration, "rad/s^2")
    settle = _finite("settle", settle)
    if not 0 <= settle < dwell:
        raise ValueError(f"settle must satisfy 0 <= settle < dwell = {dwell} s; got {settle!r}")
    lead_in = _finite("lead_in", lead_in)
    if lead_in < 0:
        raise ValueError(f"lead_in must be >= 0 s; got {lead_in!r}")
    times, values = [float(t0)], [0.0]
    if lead_in > 0:
        times.append(t0 + lead_in)
        values.append(0.0)
    windows: list[tuple[float, float]] = []
    for target in np.append(w, 0.0):
        dv = abs(target - values[-1])
        if dv > 0:
            times.append(times[-1] + dv / acc)
            values.append(float(target))
        if len(windows) < len(w):
            start = times[-1]
            times.append(start + dwell)
            values.append(float(target))
            windows.append((start + settle, start + dwell))
    return RateSteps(PiecewiseLinear(np.array(times), np.array(values)), w, np.array(windows))
