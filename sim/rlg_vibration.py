"""Vibration of a mechanically dithered RLG: the dither flexure's axial-to-torsional coupling, left unstripped.

All SI: acceleration [m/s^2], angle [rad], rate [rad/s], frequency [Hz].

A ring laser gyro has no first-order g-sensitivity: a linear acceleration does not change the
Sagnac beat (Aronowitz, "The laser gyro", Laser Applications vol. 1 (1971); Chow et al., Rev.
Mod. Phys. 57, 61 (1985)). What a shaker along the sense axis does reach is the dither
mechanism. The block hangs on the dither flexure, a torsion spring about the sense axis with
stiffness k_t = I w_d^2 (I the block's moment of inertia, w_d = 2 pi f_d the dither frequency).
If the flexure's axial load path is not exactly on its axis (hub machining, spoke asymmetry),
an axial acceleration a puts a torque M a e on the block (M the block's mass, e the effective
lever arm) and twists it relative to the case:

    theta_v = c H_d(f) a,   c = e / (r_g^2 w_d^2),   H_d = 1 / (1 - (f/f_d)^2 + j f/(Q_d f_d))   [rad]

(r_g = sqrt(I/M) the radius of gyration; H_d the base-excited torsion mode with unit static
gain.) The beat counts the block's inertial angle, so the twist is in the counts. The dither
stripper subtracts the pickoff's measure of the block-to-case angle, but through its band-pass
around f_d (the pickoff signal is filtered to the dither line; unity gain and zero phase at
f_d, so the dither itself is stripped as :mod:`gyrobench.sim.rlg` models it):

    B(f) = (j f/(Q_s f_d)) / (1 - (f/f_d)^2 + j f/(Q_s f_d))

so the part of the twist the stripper does not remove, (1 - B) theta_v, is an angle error of
the output. The output is the angle increment over each interval 1/fs, so the sample k error is
exactly

    e_k = fs [phi(t_{k+1}) - phi(t_k)],   phi = (1 - B) theta_v                                 [rad/s]

(phi computed on the shaker's sample grid by FFT: circular, exact for the sampled record; a
vibration that stops before the record ends rings down in ~Q_d/(pi f_d), 0.08 s for the
defaults). Under a sine of amplitude A at f << f_d the error is a tone of amplitude
2 c A sin(pi f/fs) fs |1 - B(f)| |H_d(f)| -> c A w |1 - B| sinc(f/fs) (zero mean: a bounded
angle, no bias). At f = f_d, B = 1: a twist at the dither frequency is stripped.

What is left out (the cavity model has no term for them): the pickoff's own frequency
response and gain error; backscatter-phase (lock-in) modulation by mirror motion; path-length
control disturbance and mode hops under vibration; coning and sculling of the block on its
mount (a mount's rocking is a true rate of the gyro, not an error of it); the dither reaction
on a compliant case.

Defaults (ASSUMED: no RLG sheet read prints a vibration figure): e = 10 um (a flexure-hub
tolerance), r_g = 0.04 m (a block with a 0.14 m triangular cavity, radius of gyration of a
0.11 m diameter disc), Q_d = 100 (a metal dither flexure in a sealed case), Q_s = 1 (a broad
stripper band-pass). With the default 400 Hz dither: c = 1.0e-9 rad/(m/s^2); a 2 g, 20 Hz sine
gives a 2.5e-6 rad/s (0.51 deg/h) tone before the output average.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.base.ranges import FieldRange, validate
from gyrobench.sim.shaker import ShakerSignal

__all__ = ["DitherMount", "dither_mount_error"]


@dataclass(frozen=True, slots=True, kw_only=True)
class DitherMount:
    """The dither flexure's axial-to-torsional coupling and the stripper's band-pass (module docstring).

    Parameters
    ----------
    offset : float
        e, effective lever arm of the axial inertial force about the dither axis [m] (ASSUMED
        10 um; 0: an ideal flexure, no vibration error).
    gyration_radius : float
        r_g = sqrt(I/M) of the dithered block [m] (ASSUMED 0.04 m).
    dither_quality : float
        Q_d of the dither torsion mode [-] (ASSUMED 100).
    stripper_quality : float
        Q_s of the dither stripper's band-pass around f_d [-] (ASSUMED 1).
    """

    offset: float = 10e-6
    gyration_radius: float = 0.04
    dither_quality: float = 100.0
    stripper_quality: float = 1.0

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "offset": FieldRange(-1e-2, 1e-2, "m", "lever arm of the axial load about the dither axis", True, True),
        "gyration_radius": FieldRange(0, 1.0, "m", "radius of gyration of the block", low_open=True),
        "dither_quality": FieldRange(0.5, 1e7, "1", "Q of the dither torsion mode", low_open=True),
        "stripper_quality": FieldRange(0, 1e7, "1", "Q of the stripper band-pass", low_open=True),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared specs above

    def coupling(self, dither_frequency: float) -> float:
        """c = e / (r_g^2 w_d^2): static twist per unit axial acceleration [rad/(m/s^2)]."""
        w_d = 2.0 * math.pi * dither_frequency
        return self.offset / (self.gyration_radius**2 * w_d**2)

    def response(self, f: ArrayLike, dither_frequency: float) -> NDArray[np.complex128]:
        """(1 - B(f)) c H_d(f): unstripped twist per unit axial acceleration at ``f`` [Hz] [rad/(m/s^2)]."""
        r = np.asarray(f, dtype=float) / dither_frequency
        h_d = 1.0 / (1.0 - r**2 + 1j * r / self.dither_quality)
        jb = 1j * r / self.stripper_quality
        b = jb / (1.0 - r**2 + jb)
        return np.asarray(self.coupling(dither_frequency) * (1.0 - b) * h_d, dtype=np.complex128)


def dither_mount_error(
    mount: DitherMount, dither_frequency: float, shaker: ShakerSignal, n: int, fs: float
) -> NDArray[np.float64]:
    """The output error of the unstripped flexure twist, one value per output sample [rad/s].

    Parameters
    ----------
    mount : DitherMount
        The coupling and the stripper.
    dither_frequency : float
        f_d [Hz].
    shaker : ShakerSignal
        Table acceleration along the sense axis, from t = 0 at an integer multiple m of ``fs``,
        covering the record (>= n m samples).
    n : int
        Output samples.
    fs : float
        Output rate [Hz].

    Returns
    -------
    ndarray
        e_k = fs [phi(t_{k+1}) - phi(t_k)], phi = (1 - B) c H_d a (module docstring).

    Raises
    ------
    ValueError
        The shaker's rate is not an integer multiple of ``fs`` or it does not cover the record.
    """
    if not isinstance(shaker, ShakerSignal):
        raise TypeError(f"shaker must be a sim.shaker.ShakerSignal; got {type(shaker).__name__}")
    m = int(round(shaker.fs / fs))
    if m < 1 or abs(m * fs - shaker.fs) > 1e-9 * shaker.fs:
        raise ValueError(f"shaker.fs must be an integer multiple of fs = {fs!r} Hz; got {shaker.fs!r} Hz")
    if len(shaker.acceleration) < n * m:
        raise ValueError(f"shaker must cover the record: >= {n * m} samples; got {len(shaker.acceleration)}")
    if mount.offset == 0.0:
        return np.zeros(n)
    a = np.asarray(shaker.acceleration[: n * m], dtype=float)
    f = np.asarray(np.fft.rfftfreq(len(a), 1.0 / shaker.fs), dtype=np.float64)
    spectrum = np.asarray(np.fft.rfft(a), dtype=np.complex128) * mount.response(f, dither_frequency)
    phi = np.fft.irfft(spectrum, len(a))
    edges = np.concatenate((phi[::m], phi[:1]))  # phi at t_k = k/fs, k = 0..n (circular: t_n wraps to t_0)
    return np.asarray(np.diff(edges) * fs, dtype=np.float64)
