"""Rigid-body motion of an IMU block on the Earth: attitude, body angular rate, specific force.

Frames: ``n`` is the local-level north-east-down frame at the start point (latitude phi,
height h), ``b`` the body frame of the block. A trajectory gives, at any time t [s], the body
attitude C_nb(t) (body to navigation), the body rate omega_nb^b(t) [rad/s] and the velocity
v^n(t) and acceleration a^n(t) = dv^n/dt [m/s, m/s^2]. What an ideal IMU senses is

    omega_ib^b = omega_nb^b + C_bn (omega_ie^n + omega_en^n)                              [rad/s]
    f^b        = C_bn (a^n + (2 omega_ie^n + omega_en^n) x v^n - g^n)                     [m/s^2]

    omega_ie^n = Omega_E [cos phi, 0, -sin phi],
    omega_en^n = [v_E/(R_N + h), -v_N/(R_M + h), -v_E tan(phi)/(R_N + h)],
    g^n        = [0, 0, gamma(phi, h)]

(Titterton & Weston, Strapdown Inertial Navigation Technology, 2nd ed. (2004), eqs. 3.38 and
3.53 with the plumb-bob gravity of 3.89), with the WGS84 Earth rate Omega_E, radii R_M, R_N and
Somigliana's normal gravity gamma(phi) less the free-air gradient 3.086e-6 /s^2 x h
(NIMA TR8350.2, 3rd ed. (2000), eq. 4-1 and sec. 4.3; :class:`gyrobench.sim.earth.Site`).
Stated simplification: phi and h are held at the start point's (a record's change of latitude,
|v_N| t / R_M, changes omega_ie by Omega_E |dphi|, 1e-7 of it per 0.6 m north; the tool does
not integrate position).

An IMU delivers increments: dtheta_k = integral over [t_k, t_k + T] of omega_ib^b and
dv_k = integral of f^b (T = 1/fs), and a rate output is dtheta_k / T. :func:`increments` forms
them by Gauss-Legendre quadrature of the motion's own closed form: ``GAUSS_NODES`` nodes on each
sample interval, each split at the motion's breakpoints (where the rate or acceleration jumps),
exact for integrands polynomial of degree 2 GAUSS_NODES - 1 and, for the smooth trigonometric
integrands of a rotation, in error below (|omega| T)^(2 GAUSS_NODES) / (2 GAUSS_NODES)! relative:
1e-16 for |omega| T <= 1 rad. The integrals themselves are exact, not a first-order sum, so the
coning and sculling content of real motion is in the increments.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import ClassVar, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.base import units
from gyrobench.base.memory import check_memory
from gyrobench.base.ranges import Constraint, FieldRange, as_array, as_tuple, finite_array, shown, validate
from gyrobench.base.validate import check_fs
from gyrobench.sim.earth import Site

__all__ = [
    "GAUSS_NODES",
    "Motion",
    "Segment",
    "SegmentedMotion",
    "ConingMotion",
    "RockingMotion",
    "SampledMotion",
    "Increments",
    "increments",
    "rotation_matrix",
    "segments_from_table",
]

#: Gauss-Legendre nodes per sample interval (module docstring)
GAUSS_NODES = 8
_GL_X, _GL_W = np.polynomial.legendre.leggauss(GAUSS_NODES)


def rotation_matrix(rotvec: ArrayLike) -> NDArray[np.float64]:
    """exp([a x]) for rotation vectors ``a`` of shape (..., 3) (Rodrigues), shape (..., 3, 3).

    Parameters
    ----------
    rotvec : array_like, shape (..., 3)
        Rotation vectors [rad] (axis times angle).

    Returns
    -------
    ndarray, shape (..., 3, 3)
        I + sin|a|/|a| [a x] + (1 - cos|a|)/|a|^2 [a x]^2, with the series below |a| = 1e-4.
    """
    a = np.asarray(rotvec, dtype=float)
    th2 = np.sum(a * a, axis=-1)
    th = np.sqrt(th2)
    small = th < 1e-4
    safe = np.where(small, 1.0, th)
    s = np.where(small, 1 - th2 / 6 + th2 * th2 / 120, np.sin(safe) / safe)
    c = np.where(small, 0.5 - th2 / 24 + th2 * th2 / 720, (1 - np.cos(safe)) / np.where(small, 1.0, th2))
    k = np.zeros(a.shape[:-1] + (3, 3))
    k[..., 0, 1], k[..., 0, 2] = -a[..., 2], a[..., 1]
    k[..., 1, 0], k[..., 1, 2] = a[..., 2], -a[..., 0]
    k[..., 2, 0], k[..., 2, 1] = -a[..., 1], a[..., 0]
    eye = np.broadcast_to(np.eye(3), k.shape)
    return eye + s[..., None, None] * k + c[..., None, None] * (k @ k)


@runtime_checkable
class Motion(Protocol):
    """A trajectory: the block's attitude, body rate, velocity and acceleration at any time."""

    @property
    def duration(self) -> float:
        """Length [s] (read-only: the motions are frozen dataclasses)."""
        ...

    def breakpoints(self) -> NDArray[np.float64]:
        """Times [s] in (0, duration) where the rate or acceleration may jump."""
        ...

    def state(
        self, t: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """(C_nb (n, 3, 3), omega_nb^b (n, 3) [rad/s], v^n (n, 3) [m/s], a^n (n, 3) [m/s^2]) at ``t``."""
        ...


def _vec3(owner: str, name: str, v: object, unit: str) -> NDArray[np.float64]:
    a = np.asarray(v, dtype=float) if not isinstance(v, str) else None
    if a is None or a.shape != (3,) or not np.all(np.isfinite(a)):
        raise ValueError(f"{owner}.{name} must be 3 finite numbers [{unit}]; got {v!r}")
    return a


@dataclass(frozen=True, slots=True, kw_only=True)
class Segment:
    """One segment of a motion definition: constant body rate and navigation-frame acceleration.

    Parameters
    ----------
    duration : float
        Segment length [s], > 0.
    rate : array_like, shape (3,)
        Body angular rate omega_nb^b [rad/s], constant over the segment.
    acceleration : array_like, shape (3,)
        a^n = dv^n/dt in north, east, down [m/s^2], constant over the segment.
    """

    duration: float
    rate: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    acceleration: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "duration": FieldRange(0, math.inf, "s", "segment length", low_open=True),
    }
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        finite_array("rate", (3,), "rad/s"),
        finite_array("acceleration", (3,), "m/s^2"),
    )

    def __post_init__(self) -> None:
        object.__setattr__(self, "rate", as_array(self.rate))
        object.__setattr__(self, "acceleration", as_array(self.acceleration))
        validate(self)  # the declared specs and constraints above


def _segment_starts(
    segs: tuple[Segment, ...], attitude: NDArray[np.float64], velocity: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Each segment's start time [s], attitude C_nb and velocity v^n [m/s], from the exact kinematics."""
    durations = np.array([s.duration for s in segs])
    starts = np.concatenate(([0.0], np.cumsum(durations)[:-1]))
    c0 = np.empty((len(segs), 3, 3))
    v0 = np.empty((len(segs), 3))
    c, v = rotation_matrix(attitude), velocity.copy()
    for j, s in enumerate(segs):
        c0[j], v0[j] = c, v
        c = c @ rotation_matrix(s.rate * s.duration)
        v = v + s.acceleration * s.duration
    return starts, c0, v0


@dataclass(frozen=True, slots=True)
class SegmentedMotion:
    """A motion definition as segments of constant body rate and acceleration (exact kinematics).

    On segment j, starting at t_j with attitude C_j and velocity v_j:
    C_nb(t) = C_j exp([omega_j x](t - t_j)) and v^n(t) = v_j + a_j (t - t_j), exactly.

    Parameters
    ----------
    segments : sequence of Segment
        The motion, in order.
    attitude : array_like, shape (3,)
        Initial attitude as a rotation vector of C_nb [rad] (zero: body axes along north, east,
        down).
    velocity : array_like, shape (3,)
        Initial velocity v^n [m/s].
    """

    segments: tuple[Segment, ...]
    attitude: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    velocity: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    _starts: NDArray[np.float64] = field(init=False, repr=False)
    _c0: NDArray[np.float64] = field(init=False, repr=False)
    _v0: NDArray[np.float64] = field(init=False, repr=False)

    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "segments is a non-empty sequence of Segment",
            lambda c: isinstance(c.segments, tuple) and len(c.segments) > 0
            and all(isinstance(s, Segment) for s in c.segments),
            lambda c: f"segments must be a non-empty sequence of Segment; got {shown(c.segments)}",
            TypeError,
        ),
        finite_array("attitude", (3,), "rad"),
        finite_array("velocity", (3,), "m/s"),
    )

    def __post_init__(self) -> None:
        object.__setattr__(self, "segments", as_tuple(self.segments))
        object.__setattr__(self, "attitude", as_array(self.attitude))
        object.__setattr__(self, "velocity", as_array(self.velocity))
        validate(self)  # the declared constraints above
        starts, c0, v0 = _segment_starts(self.segments, self.attitude, self.velocity)
        object.__setattr__(self, "_starts", starts)
        object.__setattr__(self, "_c0", c0)
        object.__setattr__(self, "_v0", v0)

    @property
    def duration(self) -> float:
        """Total length [s]."""
        return float(sum(s.duration for s in self.segments))

    def breakpoints(self) -> NDArray[np.float64]:
        """The segments' start times after the first [s]."""
        return self._starts[1:].copy()

    def state(self, t):
        """(C_nb, omega_nb^b, v^n, a^n) at times ``t`` [s] (class docstring)."""
        t = np.asarray(t, dtype=float)
        j = np.clip(np.searchsorted(self._starts, t, side="right") - 1, 0, len(self.segments) - 1)
        rates = np.array([s.rate for s in self.segments])[j]
        acc = np.array([s.acceleration for s in self.segments])[j]
        dt = t - self._starts[j]
        c = self._c0[j] @ rotation_matrix(rates * dt[:, None])
        v = self._v0[j] + acc * dt[:, None]
        return c, rates, v, acc


@dataclass(frozen=True, slots=True)
class ConingMotion:
    """Classical coning: the rotation vector a(t) = beta [cos w t, sin w t, 0] of C_nb(t).

    Its body rate has the closed form (Savage, Strapdown Analytics (2000), sec. 7.1.1.1; from
    omega = J_r(a) da/dt with |a| = beta and a . da/dt = 0)

        omega_nb^b(t) = w sin(beta) [-sin w t, cos w t, 0] - w (1 - cos beta) [0, 0, 1].

    Parameters
    ----------
    half_angle : float
        beta [rad], 0 < beta < pi.
    frequency : float
        Coning frequency w / (2 pi) [Hz], > 0.
    duration : float
        Length [s], > 0.
    """

    half_angle: float
    frequency: float
    duration: float

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "half_angle": FieldRange(0, math.pi, "rad", "coning half-angle beta", low_open=True, high_open=True),
        "frequency": FieldRange(0, math.inf, "Hz", "coning frequency", low_open=True),
        "duration": FieldRange(0, math.inf, "s", "motion length", low_open=True),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared specs above

    def breakpoints(self) -> NDArray[np.float64]:
        """None: the motion is smooth."""
        return np.zeros(0)

    def state(self, t):
        """(C_nb, omega_nb^b, v^n = 0, a^n = 0) at ``t`` [s] (class docstring)."""
        t = np.asarray(t, dtype=float)
        w, b = 2 * math.pi * self.frequency, self.half_angle
        a = b * np.stack([np.cos(w * t), np.sin(w * t), np.zeros_like(t)], axis=-1)
        rate = np.stack(
            [
                -w * math.sin(b) * np.sin(w * t),
                w * math.sin(b) * np.cos(w * t),
                np.full_like(t, -w * (1 - math.cos(b))),
            ],
            axis=-1,
        )
        zeros = np.zeros((len(t), 3))
        return rotation_matrix(a), rate, zeros, zeros


@dataclass(frozen=True, slots=True)
class RockingMotion:
    """Rocking about the body x axis: C_nb(t) = R_x(A sin w t), omega_nb^b = [A w cos w t, 0, 0].

    At rest otherwise; the sensed specific force is gravity rotating in the body y-z plane,
    whose increments over whole periods have a closed form in Bessel functions (the sculling
    check of tests/sim/test_trajectory.py).

    Parameters
    ----------
    amplitude : float
        A [rad], > 0.
    frequency : float
        w / (2 pi) [Hz], > 0.
    duration : float
        Length [s], > 0.
    """

    amplitude: float
    frequency: float
    duration: float

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "amplitude": FieldRange(0, math.inf, "rad", "rocking amplitude A", low_open=True),
        "frequency": FieldRange(0, math.inf, "Hz", "rocking frequency", low_open=True),
        "duration": FieldRange(0, math.inf, "s", "motion length", low_open=True),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared specs above

    def breakpoints(self) -> NDArray[np.float64]:
        """None: the motion is smooth."""
        return np.zeros(0)

    def state(self, t):
        """(C_nb, omega_nb^b, v^n = 0, a^n = 0) at ``t`` [s] (class docstring)."""
        t = np.asarray(t, dtype=float)
        w = 2 * math.pi * self.frequency
        theta = self.amplitude * np.sin(w * t)
        rotvec = np.stack([theta, np.zeros_like(t), np.zeros_like(t)], axis=-1)
        rate = np.stack([self.amplitude * w * np.cos(w * t), np.zeros_like(t), np.zeros_like(t)], axis=-1)
        zeros = np.zeros((len(t), 3))
        return rotation_matrix(rotvec), rate, zeros, zeros


def _valid_times(t: object) -> bool:
    """Whether ``t`` is a 1-D float array of >= 4 finite, strictly increasing times from 0."""
    return (
        isinstance(t, np.ndarray) and t.ndim == 1 and len(t) >= 4 and bool(np.all(np.isfinite(t)))
        and bool(np.all(np.diff(t) > 0)) and t[0] == 0.0
    )


def _finite_rows(a: object, m: int, k: int) -> bool:
    """Whether ``a`` is a finite float array of shape (m, k)."""
    return isinstance(a, np.ndarray) and a.shape == (m, k) and bool(np.all(np.isfinite(a)))


def _continuous_unit(q: NDArray[np.float64]) -> NDArray[np.float64]:
    """The quaternions normalised, each sign flip between samples undone (a new array)."""
    q = q / np.linalg.norm(q, axis=1)[:, None]
    flips = np.cumprod(np.where(np.sum(q[1:] * q[:-1], axis=1) < 0, -1.0, 1.0))
    q[1:] *= flips[:, None]
    return q


@dataclass(frozen=True, slots=True)
class SampledMotion:
    """A trajectory from samples: time, attitude quaternion and velocity.

    The samples come e.g. from a CSV of a navigation solution or a motion-capture system.

    Between the samples the quaternion's four components and the velocity's three are cubic
    splines (not-a-knot; scipy.interpolate.CubicSpline), the quaternion renormalised; the body
    rate is omega_nb^b = 2 vec(q* (x) dq/dt) / |q|^2 and a^n = dv^n/dt from the same splines
    (Savage, Strapdown Analytics (2000), eq. 3.2.4-3). The samples' own accuracy bounds the
    result: the splines are exact for motions whose quaternion and velocity are cubic in t, and
    their error elsewhere falls as the sample interval to the fourth power.

    Parameters
    ----------
    times : array_like, shape (m,)
        Sample times [s], strictly increasing, from 0 (m >= 4).
    quaternions : array_like, shape (m, 4)
        q_nb as (w, x, y, z) (scalar first; body to NED), any sign convention continuous in
        time (a sign flip between samples is undone).
    velocities : array_like, shape (m, 3)
        v^n in north, east, down [m/s].
    """

    times: NDArray[np.float64]
    quaternions: NDArray[np.float64]
    velocities: NDArray[np.float64]
    _q: object = field(init=False, repr=False)
    _v: object = field(init=False, repr=False)

    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "times: >= 4 finite, strictly increasing, from 0",
            lambda c: _valid_times(c.times),
            lambda c: f"times must be >= 4 finite, strictly increasing times [s] from 0; got {shown(c.times)}",
        ),
        Constraint(
            "quaternions (m, 4) and velocities (m, 3), finite",
            lambda c: _finite_rows(c.quaternions, len(c.times), 4) and _finite_rows(c.velocities, len(c.times), 3),
            lambda c: f"quaternions must be ({len(c.times)}, 4) and velocities ({len(c.times)}, 3), finite; "
            f"got {shown(c.quaternions)} and {shown(c.velocities)}",
        ),
        Constraint(
            "|q| within 1e-3 of 1",
            lambda c: bool(np.all(np.abs(np.linalg.norm(c.quaternions, axis=1) - 1) <= 1e-3)),
            lambda c: "quaternions must be unit quaternions (|q| within 1e-3 of 1); got |q| from "
            f"{np.linalg.norm(c.quaternions, axis=1).min():.6g} to {np.linalg.norm(c.quaternions, axis=1).max():.6g}",
        ),
    )

    def __post_init__(self) -> None:
        from scipy.interpolate import CubicSpline

        object.__setattr__(self, "times", as_array(self.times))
        object.__setattr__(self, "quaternions", as_array(self.quaternions))
        object.__setattr__(self, "velocities", as_array(self.velocities))
        validate(self)  # the declared constraints above
        q = _continuous_unit(self.quaternions)
        object.__setattr__(self, "quaternions", q)
        object.__setattr__(self, "_q", CubicSpline(self.times, q, axis=0))
        object.__setattr__(self, "_v", CubicSpline(self.times, self.velocities, axis=0))

    @property
    def duration(self) -> float:
        """The last sample's time [s]."""
        return float(self.times[-1])

    def breakpoints(self) -> NDArray[np.float64]:
        """The sample times inside the record (where the splines' third derivatives jump)."""
        return self.times[1:-1].copy()

    def state(self, t):
        """(C_nb, omega_nb^b, v^n, a^n) at ``t`` [s] from the splines (class docstring)."""
        t = np.asarray(t, dtype=float)
        q = self._q(t)  # type: ignore[operator]
        dq = self._q(t, 1)  # type: ignore[operator]
        n2 = np.sum(q * q, axis=1)
        w, x, y, z = (q[:, i] for i in range(4))
        dw, dx, dy, dz = (dq[:, i] for i in range(4))
        # 2 vec(conj(q) (x) dq) / |q|^2
        rate = 2 * np.stack([w * dx - x * dw - y * dz + z * dy,
                             w * dy + x * dz - y * dw - z * dx,
                             w * dz - x * dy + y * dx - z * dw], axis=-1) / n2[:, None]
        qn = q / np.sqrt(n2)[:, None]
        w, x, y, z = (qn[:, i] for i in range(4))
        c = np.empty((len(t), 3, 3))
        c[:, 0, 0], c[:, 0, 1], c[:, 0, 2] = 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)
        c[:, 1, 0], c[:, 1, 1], c[:, 1, 2] = 2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)
        c[:, 2, 0], c[:, 2, 1], c[:, 2, 2] = 2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)
        return c, rate, self._v(t), self._v(t, 1)  # type: ignore[operator]


@dataclass(frozen=True, slots=True)
class Increments:
    """An ideal IMU's output over a motion: increments per sample interval, and their truth.

    Attributes
    ----------
    fs : float
        Output rate [Hz].
    dtheta : ndarray, shape (n, 3)
        Angle increments, the integral of omega_ib^b over each interval [rad].
    dv : ndarray, shape (n, 3)
        Velocity increments, the integral of f^b over each interval [m/s].
    attitude : ndarray, shape (n + 1, 3, 3)
        C_nb at the interval edges k/fs.
    velocity : ndarray, shape (n + 1, 3)
        v^n at the interval edges [m/s].
    """

    fs: float
    dtheta: NDArray[np.float64]
    dv: NDArray[np.float64]
    attitude: NDArray[np.float64]
    velocity: NDArray[np.float64]

    @property
    def rate(self) -> NDArray[np.float64]:
        """Interval-mean body rate dtheta fs [rad/s], shape (n, 3)."""
        return self.dtheta * self.fs

    @property
    def specific_force(self) -> NDArray[np.float64]:
        """Interval-mean specific force dv fs [m/s^2], shape (n, 3)."""
        return self.dv * self.fs


def _sensed(motion: Motion, site: Site, t: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    c_nb, w_nb, v, a = motion.state(t)
    c_bn = np.swapaxes(c_nb, -1, -2)
    w_ie = site.earth_rate_n
    w_en = site.transport_rate_n(v)
    w_in = w_ie + w_en
    w_ib = w_nb + np.einsum("nij,nj->ni", c_bn, w_in)
    g = np.array([0.0, 0.0, site.gravity])
    f_n = a + np.cross(2 * w_ie + w_en, v) - g
    return w_ib, np.einsum("nij,nj->ni", c_bn, f_n)


def increments(motion: Motion, fs: float, *, site: Site | None = None, chunk: int = 1 << 15) -> Increments:
    """The ideal increments of a motion at output rate ``fs`` (module docstring: scheme and error).

    Parameters
    ----------
    motion : Motion
        The trajectory (:class:`SegmentedMotion`, :class:`ConingMotion`, :class:`RockingMotion`
        or any object with ``duration``, ``breakpoints()`` and ``state(t)``).
    fs : float
        Output rate [Hz]; the record has floor(duration fs) intervals.
    site : Site, optional
        Latitude and height (default: the equator at sea level, Earth rotating).
    chunk : int
        Intervals evaluated at once (bounds the memory to ~2 kB per interval).

    Returns
    -------
    Increments
        dtheta, dv per interval and the attitude and velocity at the interval edges.
    """
    fs = check_fs(fs)
    site = site or Site()
    if not isinstance(motion, Motion):
        raise TypeError(f"motion must have duration, breakpoints() and state(t); got {type(motion).__name__}")
    n = int(math.floor(motion.duration * fs + 1e-9))
    if n < 1:
        raise ValueError(f"duration * fs must give >= 1 interval; got {motion.duration!r} s at {fs!r} Hz")
    check_memory(8.0 * n * (3 + 3 + 9 + 3) * 2, f"an IMU record of {n} samples")
    # Sub-intervals in each sample's own time u = t - k/fs, so that an interval is exactly
    # [0, 1/fs] unless a breakpoint splits it: its length never carries the rounding of t.
    T = 1.0 / fs
    bps = np.asarray(motion.breakpoints(), dtype=float)
    bps = bps[(bps > 0) & (bps < n / fs)]
    bp_owner = np.minimum(np.floor(bps * fs).astype(np.int64), n - 1)
    bp_u = np.clip(bps - bp_owner / fs, 0.0, T)
    owner = np.concatenate([np.arange(n), bp_owner, np.arange(n)])
    local = np.concatenate([np.zeros(n), bp_u, np.full(n, T)])
    order = np.lexsort((local, owner))
    owner, local = owner[order], local[order]
    keep = owner[1:] == owner[:-1]
    sub_owner = owner[:-1][keep]
    lo_u, hi_u = local[:-1][keep], local[1:][keep]
    dtheta = np.zeros((n, 3))
    dv = np.zeros((n, 3))
    for lo in range(0, len(sub_owner), chunk):
        hi = min(lo + chunk, len(sub_owner))
        own = sub_owner[lo:hi]
        mid, half = (lo_u[lo:hi] + hi_u[lo:hi]) / 2, (hi_u[lo:hi] - lo_u[lo:hi]) / 2
        t = (own / fs + mid)[:, None] + half[:, None] * _GL_X[None, :]
        w_ib, f_b = _sensed(motion, site, t.ravel())
        wts = (half[:, None] * _GL_W[None, :]).ravel()[:, None]
        k = hi - lo
        first = np.flatnonzero(np.r_[True, own[1:] != own[:-1]])  # owners are sorted
        dtheta[own[first]] += np.add.reduceat((w_ib * wts).reshape(k, GAUSS_NODES, 3).sum(axis=1), first, axis=0)
        dv[own[first]] += np.add.reduceat((f_b * wts).reshape(k, GAUSS_NODES, 3).sum(axis=1), first, axis=0)
    edges = np.arange(n + 1) / fs
    att = np.empty((n + 1, 3, 3))
    vel = np.empty((n + 1, 3))
    for lo in range(0, n + 1, chunk):
        c, _, v, _ = motion.state(edges[lo : lo + chunk])
        att[lo : lo + chunk], vel[lo : lo + chunk] = c, v
    return Increments(fs=fs, dtheta=dtheta, dv=dv, attitude=att, velocity=vel)


def segments_from_table(rows: Sequence[dict]) -> tuple[Segment, ...]:
    """Segments from a motion definition in field units (the TOML profile's ``[[motion]]`` tables).

    Each row takes ``duration_s``, ``rate_dps`` (3 numbers, body x, y, z [deg/s]) and
    ``acceleration_mps2`` (3 numbers, north, east, down [m/s^2]); the last two default to 0.

    Parameters
    ----------
    rows : sequence of dict
        The ``[[motion]]`` tables.

    Returns
    -------
    tuple of Segment
        The segments, in order.
    """
    out = []
    for i, row in enumerate(rows):
        where = f"motion[{i}]"
        unknown = set(row) - {"duration_s", "rate_dps", "acceleration_mps2"}
        if unknown:
            raise ValueError(
                f"{where} has unknown keys {sorted(unknown)}; it takes duration_s, rate_dps, acceleration_mps2"
            )
        if "duration_s" not in row:
            raise ValueError(f"{where} needs duration_s [s]")
        rate = _vec3(where, "rate_dps", row.get("rate_dps", [0.0, 0.0, 0.0]), "deg/s")
        if np.any(np.abs(rate) > 1e5):
            raise ValueError(f"{where}.rate_dps must be within +-1e5 deg/s; got {row['rate_dps']!r}")
        acc = _vec3(where, "acceleration_mps2", row.get("acceleration_mps2", [0.0, 0.0, 0.0]), "m/s^2")
        if np.any(np.abs(acc) > 1e5):
            raise ValueError(f"{where}.acceleration_mps2 must be within +-1e5 m/s^2; got {row['acceleration_mps2']!r}")
        out.append(Segment(duration=row["duration_s"], rate=units.deg_per_s(rate), acceleration=acc))
    return tuple(out)
