"""Paper 000's device glue: one drawn FOG on the shaker, and its closed-form steady bias.

The gyro is :class:`gyrobench.sim.fog_loop.ClosedLoopFOG` with the unit spread of
:class:`~.config.FogSpec`; the shaker profiles are the config's :meth:`~.config.Config.sweep`
and :meth:`~.config.Config.fixed`.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.base import units
from gyrobench.io.recording import Channel, Recording
from gyrobench.sim.fog_loop import ClosedLoopFOG
from gyrobench.sim.mount_coning import MountConing
from gyrobench.sim.sensor import Environment, with_metadata
from gyrobench.sim.shaker import Phased, SineSweep, moving_span

from .config import Config

__all__ = [
    "draw_mount",
    "draw_unit",
    "padded_mount_rate",
    "record_on_table",
    "steady_mount_bias",
    "steady_vibration_bias",
    "true_bias_at_bins",
]


def steady_vibration_bias(fog: ClosedLoopFOG, f: ArrayLike, a: ArrayLike) -> NDArray[np.float64]:
    """Steady rectified bias [deg/h] under a sine table acceleration ``a`` [m/s^2] at ``f`` [Hz].

    The only first-order DC term of the closed-loop FOG under vibration is the intensity-phase
    correlation m(t) phi_res(t)/SF0 (sim.fog_loop, docs/physics.md 4.1); for a = A cos(w t),
    m = Re(L A e^{jwt}) and phi_res/SF0 = Re((1 - H)(S + Rk) A e^{jwt}), whose mean is

        b(f) = (A^2/2) Re[L(f) conj((1 - H(f)) (S(f) + Rk(f)))]

    (L loss, S strain-rate, Rk rocking spectra per unit acceleration, H the loop); the strain
    and rocking tones themselves are zero-mean. Passes the loop and the output averaging with
    gain H(0) = sinc(0) = 1.

    Parameters
    ----------
    fog : ClosedLoopFOG
        The unit.
    f : array_like
        Frequencies [Hz].
    a : array_like
        Acceleration amplitudes [m/s^2].

    Returns
    -------
    ndarray
        The rectified bias [deg/h].
    """
    f = np.asarray(f, dtype=float)
    spec = fog.vibration_spectra(f)
    h = fog.loop.transfer(f)
    resid = (1.0 - h) * (spec["strain"] + spec["rocking"])
    b = 0.5 * np.asarray(a, dtype=float) ** 2 * np.real(spec["loss"] * np.conj(resid))
    return units.to_deg_per_h(b)


def steady_mount_bias(mount: MountConing | None, f: ArrayLike, a: ArrayLike) -> NDArray[np.float64]:
    """Mean coning rate of the mount [deg/h] under a sine acceleration.

    Mean coning rate of the mount [deg/h] under a sine ``a`` [m/s^2] at ``f`` [Hz]
    (:meth:`~gyrobench.sim.mount_coning.MountConing.mean_rate`; 0 without a mount).

    Parameters
    ----------
    mount : MountConing or None
        The mount (None: 0).
    f : array_like
        Frequencies [Hz].
    a : array_like
        Acceleration amplitudes [m/s^2].

    Returns
    -------
    ndarray
        The mean rate [deg/h].
    """
    if mount is None:
        return np.zeros(np.broadcast(np.asarray(f, float), np.asarray(a, float)).shape)
    return units.to_deg_per_h(mount.mean_rate(f, a))


def draw_unit(config: Config, seed: int) -> ClosedLoopFOG:
    """The FOG of unit ``seed`` (child 3 of the seed's generator; 0-2: records, centres).

    Parameters
    ----------
    config : Config
        The configuration.
    seed : int
        The unit's seed.

    Returns
    -------
    ClosedLoopFOG
        The unit's gyro.
    """
    return config.fog.draw(np.random.default_rng(seed).spawn(4)[3])


def draw_mount(config: Config, seed: int) -> MountConing | None:
    """The mount of unit ``seed`` (child 4 of the seed's generator).

    Parameters
    ----------
    config : Config
        The configuration.
    seed : int
        The unit's seed.

    Returns
    -------
    MountConing or None
        The unit's mount (None: the spec has none).
    """
    return config.fog.draw_mount(np.random.default_rng(seed).spawn(5)[4])


def padded_mount_rate(mount: MountConing, acceleration: NDArray[np.float64], fs: float) -> NDArray[np.float64]:
    """The mount's coning rate over a span at rest at both ends, zero-padded for a fast FFT.

    :meth:`~gyrobench.sim.mount_coning.MountConing.rate` of a span that starts and ends at rest,
    zero-padded to a length whose FFT is fast (:func:`scipy.fft.next_fast_len`, factors 2, 3, 5).

    The span's own length may hold a large prime factor (961,618 = 2 x 7 x 68,687 at the default
    dwell), where the transform is ~35x slower. The padding adds table rest after the span, so
    the circular response differs from the unpadded one only by the modes' ring-down that wraps
    around: with 30 ring-down times of rest at each end (the caller's pad) that is below e^-30
    (1e-13) of the response, besides rounding. Returns the rate [rad/s] on the span's samples.

    Parameters
    ----------
    mount : MountConing
        The mount.
    acceleration : ndarray
        Table acceleration over the span [m/s^2].
    fs : float
        Its sample rate [Hz].

    Returns
    -------
    ndarray
        The rate about the sense axis over the span [rad/s].
    """
    from scipy.fft import next_fast_len

    n = len(acceleration)
    padded = np.zeros(next_fast_len(n, real=True))
    padded[:n] = acceleration
    return mount.rate(padded, fs)[:n]


def _block_mean_coning(
    mount: MountConing, acceleration: NDArray[np.float64], n: int, m: int, fs: float
) -> NDArray[np.float64]:
    """The mount's coning rate [rad/s] on the shaker grid (``fs`` [Hz]), averaged over each of the ``n``
    output intervals of ``m`` grid samples; computed only where the table moves, plus 30 ring-down
    times (e^-30) each side, and held only over the output intervals that span touches."""
    coning = np.zeros(n)
    moving = moving_span(acceleration[: n * m])
    if moving is not None:
        f_min = min(mount.x.frequency, mount.y.frequency)
        q_max = max(mount.x.quality, mount.y.quality)
        pad = int(np.ceil(30.0 * q_max / (np.pi * f_min) * fs))
        j0, j1 = max(0, moving[0] - pad), min(n * m, moving[1] + 1 + pad)
        b0, b1 = j0 // m, -(-j1 // m)
        fast = np.zeros((b1 - b0) * m)
        fast[j0 - b0 * m : j1 - b0 * m] = padded_mount_rate(mount, acceleration[j0:j1], fs)
        coning[b0:b1] = fast.reshape(-1, m).mean(axis=1)
    return coning


def record_on_table(
    fog: ClosedLoopFOG,
    prof: Phased,
    config: Config,
    rng: np.random.Generator,
    name: str,
    mount: MountConing | None = None,
) -> tuple[Recording, dict[str, Channel], dict[str, Channel]]:
    """One record of ``fog`` on the shaker profile, with the controller log at the output rate.

    With a ``mount``, its coning rate (a true rate about the sense axis, computed on the shaker's
    grid and averaged over each output interval, as the integrate-and-dump output does) is added
    to the output and, as an error component, to the truth (``truth/coning_rate``, zero without a
    mount; part of ``detail/vibration_bias``).

    Parameters
    ----------
    fog : ClosedLoopFOG
        The unit.
    prof : Phased
        The shaker profile.
    config : Config
        The configuration.
    rng : numpy.random.Generator
        The record's stream.
    name : str
        The record's name.
    mount : MountConing or None
        The unit's mount.

    Returns
    -------
    tuple of (Recording, dict, dict)
        The simulated record, its output channels with the controller log added, and its truth
        channels with the mount's coning rate and the vibration bias, at the output rate.
    """
    r_shaker, r_fog = rng.spawn(2)
    spec = config.fog
    fs_out = spec.output_rate_hz
    n, m = int(math.floor(float(prof.duration) * fs_out + 1e-9)), int(round(spec.physics_rate_hz / fs_out))
    # the shaker's grid-rate arrays live only while they are read: the controller log and the
    # mount's coning first, then the FOG (whose output-rate record is then the only large array)
    sh = prof.sample(spec.physics_rate_hz, rng=r_shaker)
    centre = np.arange(n) * m + m // 2
    on = sh.on[centre].astype(float)
    freq = np.where(on > 0.5, np.nan_to_num(sh.frequency[centre], nan=0.0), 0.0)
    amplitude = sh.amplitude[centre]
    coning = np.zeros(n) if mount is None else _block_mean_coning(mount, sh.acceleration, n, m, spec.physics_rate_hz)
    rec = with_metadata(fog.simulate(Environment(prof.duration, vibration=sh), fs=fs_out, rng=r_fog), name=name)
    del sh
    if rec.n_samples != n:
        raise RuntimeError(f"record_on_table: the FOG record has {rec.n_samples} samples, expected {n}")
    tr = rec.truth
    vib_err = tr["strain_nonreciprocity"].data + tr["rectification"].data + tr["loop_error"].data
    channels = dict(rec.channels)
    if mount is not None:
        out = channels["output"]
        channels["output"] = Channel(out.data + coning, out.unit, out.description + " (+ mount coning)")
        vib_err = vib_err + coning
    channels["shaker_frequency"] = Channel(freq, "Hz", "drive frequency (0 when off)")
    channels["shaker_amplitude"] = Channel(amplitude, "m/s^2", "acceleration envelope")
    channels["shaker_on"] = Channel(on, "1", "1 while the shaker drives")
    truth = dict(tr)
    truth["coning_rate"] = Channel(coning, "rad/s", "mount coning rate about the sense axis (true rate)")
    truth["vibration_bias"] = Channel(
        vib_err, "rad/s", "vibration error: strain nonreciprocity + rectification + loop error + mount coning"
    )
    return rec, channels, truth


def true_bias_at_bins(
    fb: np.ndarray, config: Config, fog: ClosedLoopFOG, mount: MountConing | None = None
) -> np.ndarray:
    """The true steady vibration bias [deg/h] at sweep frequencies.

    The true steady vibration bias [deg/h] at sweep frequencies ``fb`` (steady amplitude there):
    the loop's rectification plus the mount's coning.

    Parameters
    ----------
    fb : ndarray
        Frequencies [Hz].
    config : Config
        The configuration (the sweep's amplitude there).
    fog : ClosedLoopFOG
        The unit.
    mount : MountConing or None
        Its mount.

    Returns
    -------
    ndarray
        The loop's rectification plus the mount's coning [deg/h].
    """
    s = config.sweep().vibration
    assert isinstance(s, SineSweep)  # Config.sweep() builds the swept-sine profile
    t_of_f = (
        np.log(fb / s.f_start) / np.log(s.f_end / s.f_start) * s.duration
        if s.spacing == "log"
        else (fb - s.f_start) / (s.f_end - s.f_start) * s.duration
    )
    a_b = s.amplitude(np.clip(t_of_f, s.ramp_time, s.duration - s.ramp_time))
    return steady_vibration_bias(fog, fb, a_b) + steady_mount_bias(mount, fb, a_b)
