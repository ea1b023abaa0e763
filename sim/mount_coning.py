"""Coning rectification from two rocking modes of a gyro's mount under linear vibration.

A gyro bolted to a fixture on a linear shaker rocks about the two axes x, y perpendicular to
its sense axis z wherever the fixture/mount has rocking modes (an off-centre mass on a
compliant mount). Each mode k is a damped oscillator driven by the table acceleration a(t):

    theta_k(f) = c_k f_k^2 / (f_k^2 - f^2 + j f f_k / Q_k) * a(f)          [rad],

with ``compliance`` c_k [rad per m/s^2] its quasi-static tilt per unit acceleration, f_k [Hz]
its frequency and Q_k its quality factor. Two angular oscillations about x and y that are not
in phase are coning motion.

Sign convention: theta = (theta_x, theta_y, 0) is the rotation vector of the body (the gyro)
relative to the table, each angle right-handed about the table's x and y axes; the attitude is
C = exp([theta x]) (body to table). The body-frame angular rate, vee(C^T dC/dt), is what a gyro
fixed to the body reads; the space-frame rate vee(dC/dt C^T) is its image in table axes. To
second order in theta (the commutation term of the rotation vector; Bortz, IEEE Trans. AES-7(1)
61 (1971); Savage, Strapdown Analytics, 2000, sec. 7.1.1.1; the two frames differ in the sign
of the term)

    Omega_z(t) = s (1/2) (theta_x dtheta_y/dt - theta_y dtheta_x/dt)        [rad/s],
    s = -1 in the body frame (the default, ``frame="body"``), +1 in the space frame,

a true rotation rate, so a FOG with its axis along z reads it. Under a sine a = A cos(2 pi f t)
with complex mode responses X = theta_x/A, Y = theta_y/A its mean is

    Omega_z_mean = s (1/2) A^2 (2 pi f) Im(X conj(Y))                        [rad/s],

a DC rate (rectified; plus a zero-mean tone at 2f). Checked against the exact rotation
kinematics (products of rotation matrices, no small-angle expansion) in
:mod:`gyrobench.scenarios.checks.mount_coning`. It is largest between the two modes'
frequencies, where their phases differ most, and vanishes when both respond in phase (equal
modes or f far from both). No mode is assumed here: the caller gives them
(:class:`MountConing`; paper 000 identifies them in
:mod:`gyrobench.scenarios.papers.p000_fog_vibration.identify`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from numbers import Real
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.base.ranges import FieldChoice, FieldRange, validate

__all__ = ["FRAMES", "MountConing", "RockingMode"]

#: the frames a coning rate can be given in: "body" (what a gyro on the body reads) or "space"
FRAMES = ("body", "space")


def _check(owner: str, name: str, v: object, unit: str, *, allow_zero: bool = False) -> None:
    if isinstance(v, bool) or not isinstance(v, Real):
        raise TypeError(f"{owner}.{name} must be a real number [{unit}]; got {v!r}")
    x = float(v)
    if not (math.isfinite(x) and (x >= 0 if allow_zero else x > 0)):
        raise ValueError(f"{owner}.{name} must be finite and {'>=' if allow_zero else '>'} 0 {unit}; got {v!r}")


@dataclass(frozen=True, slots=True, kw_only=True)
class RockingMode:
    """One rocking mode of the mount (SI): ``frequency`` [Hz], ``quality`` [-], ``compliance`` [rad/(m/s^2)].

    Parameters
    ----------
    frequency : float
        Natural frequency [Hz].
    quality : float
        Quality factor [-].
    compliance : float
        Rocking angle per unit table acceleration [rad/(m/s^2)].
    """

    frequency: float
    quality: float
    compliance: float

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "frequency": FieldRange(0, 1e5, "Hz", "a mount's rocking mode: tens of Hz to kHz", low_open=True),
        "quality": FieldRange(0, 1e6, "1", "mode quality factor, > 0", low_open=True),
        # a mount's is ~1e-6; the identification evaluates modes per unit compliance scale (factors of a few)
        "compliance": FieldRange(0, 100, "rad/(m/s^2)", "rocking angle per acceleration"),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared specs above

    def response(self, f: ArrayLike) -> NDArray[np.complex128]:
        """theta / a at frequency ``f`` [Hz]: c f0^2 / (f0^2 - f^2 + j f f0/Q) [rad/(m/s^2)]."""
        f = np.asarray(f, dtype=float)
        f0 = self.frequency
        return self.compliance * f0**2 / (f0**2 - f**2 + 1j * f * f0 / self.quality)


@dataclass(frozen=True, slots=True, kw_only=True)
class MountConing:
    """Two rocking modes, about x and about y (both perpendicular to the sense axis z).

    ``frame``: ``"body"`` (default) gives the rate a gyro on the body reads, ``"space"`` the
    same rotation in table axes (the opposite sign; module docstring).

    Parameters
    ----------
    x, y : RockingMode
        The rocking modes about x and about y.
    frame : {"body", "space"}
        The axes the rate is given in.
    """

    x: RockingMode
    y: RockingMode
    frame: str = "body"

    #: the declared specs of the fields (:func:`gyrobench.base.ranges.validate`)
    RANGES: ClassVar[Mapping[str, FieldChoice]] = {
        "frame": FieldChoice(FRAMES, "the frame the coning rate is given in"),
    }

    @property
    def sign(self) -> float:
        """s of the module docstring: -1 in the body frame, +1 in the space frame."""
        return -1.0 if self.frame == "body" else 1.0

    def __post_init__(self) -> None:
        validate(self)  # x and y must be RockingModes

    def mean_rate(self, f: ArrayLike, a: ArrayLike) -> NDArray[np.float64]:
        """Mean coning rate about z [rad/s] under a sine of frequency ``f`` [Hz] and amplitude ``a``
        [m/s^2]: s (1/2) a^2 (2 pi f) Im(X conj(Y)) (module docstring)."""
        f = np.asarray(f, dtype=float)
        a = np.asarray(a, dtype=float)
        x, y = self.x.response(f), self.y.response(f)
        return self.sign * 0.5 * a**2 * 2.0 * math.pi * f * np.imag(x * np.conj(y))

    def rate(self, acceleration: ArrayLike, fs: float) -> NDArray[np.float64]:
        """Coning rate about z [rad/s] of a sampled table acceleration [m/s^2] at ``fs`` [Hz].

        theta_x, theta_y and their derivatives by the modes' transfer functions on the record's
        (circular) Fourier transform; Omega_z = s (theta_x theta_y' - theta_y theta_x') / 2. The
        record should start and end at rest (a shaker profile with static phases does).
        """
        _check("MountConing", "fs", fs, "Hz")
        acc = np.asarray(acceleration, dtype=float)
        if acc.ndim != 1:
            raise ValueError(f"acceleration must be a 1-D array; got shape {acc.shape}")
        n = acc.size
        f = np.fft.rfftfreq(n, 1.0 / fs)
        spec = np.fft.rfft(acc)
        jw = 2j * math.pi * f
        hx, hy = self.x.response(f) * spec, self.y.response(f) * spec
        tx, ty = np.fft.irfft(hx, n), np.fft.irfft(hy, n)
        dx, dy = np.fft.irfft(jw * hx, n), np.fft.irfft(jw * hy, n)
        return self.sign * 0.5 * (tx * dy - ty * dx)
