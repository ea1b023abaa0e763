"""Paper 000's device glue: one drawn FOG on the shaker, and its closed-form steady bias.

The gyro is :class:`gyrobench.sim.fog_loop.ClosedLoopFOG` with the unit spread of
:class:`~.config.FogSpec`; the shaker profiles are the config's :meth:`~.config.Config.sweep`
and :meth:`~.config.Config.fixed`.
"""

from __future__ import annotations

import numpy as np
from gyrobench.sim import units
from gyrobench.sim.fog_loop import ClosedLoopFOG
from gyrobench.sim.recording import Channel, Recording
from gyrobench.sim.shaker import Phased, SineSweep
from numpy.typing import ArrayLike, NDArray

from .config import Config

__all__ = ["draw_unit", "record_on_table", "steady_vibration_bias", "true_bias_at_bins"]


def steady_vibration_bias(fog: ClosedLoopFOG, f: ArrayLike, a: ArrayLike) -> NDArray[np.float64]:
    """Steady rectified bias [deg/h] under a sine table acceleration ``a`` [m/s^2] at ``f`` [Hz].

    The only first-order DC term of the closed-loop FOG under vibration is the intensity-phase
    correlation m(t) phi_res(t)/SF0 (sim.fog_loop, docs/physics.md 4.1); for a = A cos(w t),
    m = Re(L A e^{jwt}) and phi_res/SF0 = Re((1 - H)(S + Rk) A e^{jwt}), whose mean is

        b(f) = (A^2/2) Re[L(f) conj((1 - H(f)) (S(f) + Rk(f)))]

    (L loss, S strain-rate, Rk rocking spectra per unit acceleration, H the loop); the strain
    and rocking tones themselves are zero-mean. Passes the loop and the output averaging with
    gain H(0) = sinc(0) = 1.
    """
    f = np.asarray(f, dtype=float)
    spec = fog.vibration_spectra(f)
    h = fog.loop.transfer(f)
    resid = (1.0 - h) * (spec["strain"] + spec["rocking"])
    b = 0.5 * np.asarray(a, dtype=float) ** 2 * np.real(spec["loss"] * np.conj(resid))
    return units.to_deg_per_h(b)


def draw_unit(config: Config, seed: int) -> ClosedLoopFOG:
    """The FOG of unit ``seed`` (child 3 of the seed's generator; 0-2: records, centres)."""
    return config.fog.draw(np.random.default_rng(seed).spawn(4)[3])


def record_on_table(
    fog: ClosedLoopFOG, prof: Phased, config: Config, rng: np.random.Generator, name: str
) -> tuple[Recording, dict[str, Channel], dict[str, Channel]]:
    """One record of ``fog`` on the shaker profile, with the controller log at the output rate."""
    r_shaker, r_fog = rng.spawn(2)
    spec = config.fog
    sh = prof.sample(spec.physics_rate_hz, rng=r_shaker)
    rec = fog.simulate(prof.duration, spec.output_rate_hz, rng=r_fog, shaker=sh, name=name)
    n, m = rec.n_samples, int(round(spec.physics_rate_hz / spec.output_rate_hz))
    centre = np.arange(n) * m + m // 2
    on = sh.on[centre].astype(float)
    freq = np.where(on > 0.5, np.nan_to_num(sh.frequency[centre], nan=0.0), 0.0)
    tr = rec.truth
    vib_err = tr["strain_nonreciprocity"].data + tr["rectification"].data + tr["loop_error"].data
    channels = dict(rec.channels)
    channels["shaker_frequency"] = Channel(freq, "Hz", "drive frequency (0 when off)")
    channels["shaker_amplitude"] = Channel(sh.amplitude[centre], "m/s^2", "acceleration envelope")
    channels["shaker_on"] = Channel(on, "1", "1 while the shaker drives")
    truth = dict(tr)
    truth["vibration_bias"] = Channel(
        vib_err, "rad/s", "vibration error: strain nonreciprocity + rectification + loop error"
    )
    return rec, channels, truth


def true_bias_at_bins(fb: np.ndarray, config: Config, fog: ClosedLoopFOG) -> np.ndarray:
    """The true steady rectified bias [deg/h] at sweep frequencies ``fb`` (steady amplitude there)."""
    s = config.sweep().vibration
    assert isinstance(s, SineSweep)  # Config.sweep() builds the swept-sine profile
    t_of_f = (
        np.log(fb / s.f_start) / np.log(s.f_end / s.f_start) * s.duration
        if s.spacing == "log"
        else (fb - s.f_start) / (s.f_end - s.f_start) * s.duration
    )
    a_b = s.amplitude(np.clip(t_of_f, s.ramp_time, s.duration - s.ramp_time))
    return steady_vibration_bias(fog, fb, a_b)
