"""Paper 004's simulated gyros and chamber runs, and their 100-s blocks.

One unit = one gyro drawn from :class:`gyrobench.sim.rlg_cavity.CavityRLGSpec`
(:meth:`Config.spec`) with its own two turn-ons (fit, held-out), each a full chamber
program (:meth:`Config.chamber`). :func:`runs` reduces each run to the 100-s block means the
regression uses (:func:`gyrobench.analysis.thermal_regression.two_sensor_blocks` on the
logged T1/T2), with the truth the experiment scores against.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace

import numpy as np
from numpy.typing import NDArray

from gyrobench.analysis.features import block_means
from gyrobench.analysis.thermal_regression import two_sensor_blocks
from gyrobench.base import units
from gyrobench.io.recording import Recording
from gyrobench.sim.rlg_cavity import CavityRLG
from gyrobench.sim.sensor import Environment, with_metadata

from . import NAME
from .config import Config

__all__ = ["Blocks", "memory_estimate", "runs", "simulate", "unit_and_streams"]


def unit_and_streams(
    config: Config, seed: int
) -> tuple[CavityRLG, tuple[np.random.Generator, np.random.Generator]]:
    """The gyro of unit ``seed`` and the streams of its two turn-ons (fit, held-out).

    Parameters
    ----------
    config : Config
        The configuration.
    seed : int
        The unit's seed.

    Returns
    -------
    tuple of (CavityRLG, (Generator, Generator))
        The gyro and its two turn-ons' streams.
    """
    r_unit, r_fit, r_held = np.random.default_rng(seed).spawn(3)
    gyro = config.spec().realize(rng=r_unit, label=f"unit {seed}")
    return gyro, (r_fit, r_held)


def simulate(config: Config, seed: int) -> list[Recording]:
    """The unit's two chamber runs (fit, held-out): pulse-count output, logged T1/T2, truth.

    Parameters
    ----------
    config : Config
        The configuration.
    seed : int
        The unit's seed.

    Returns
    -------
    list of Recording
        The fitting and held-out runs.
    """
    gyro, streams = unit_and_streams(config, seed)
    prof = config.chamber()
    recs = []
    for kind, r in zip(("fit", "heldout"), streams, strict=True):
        env = Environment(prof.duration, temperature=prof)
        rec = with_metadata(gyro.simulate(env, fs=config.fs_hz, rng=r), name=f"unit{seed}_{kind}")
        meta = dict(rec.metadata)
        meta.update({"scenario": NAME, "seed": seed, "unit": seed, "run": kind})
        recs.append(replace(rec, metadata=meta))
    return recs


def memory_estimate(config: Config) -> float:
    """Peak memory of one unit's :func:`simulate` or ``experiment`` [bytes], before allocating.

    Per unit (one worker process); the runner multiplies it by the units it runs at once
    (:func:`gyrobench.scenarios.runner.units.check_unit_memory`). With ``N = 2 duration(chamber())
    fs_hz`` samples in the unit's two chamber runs::

        bytes = 1.1 x (232 N + 20e6)

    232 B = 29 float64 series per sample: :func:`simulate` holds both runs' recordings (the
    counts, dither, temperatures and truth channels, 26 series per run sample) with the
    generator's working copies; ``experiment`` holds one run at a time before its
    100-s block means (~39 series per sample of one run, 19.5 per sample of N). 20 MB is
    the rest; 1.1 the margin. MEASURED (peak RSS increase, one BLAS thread;
    tests/scenarios/test_memory_estimates.py): simulate 202 / 490 / 626 MB and experiment
    142 / 347 / 420 MB at the default (N = 9.0e5), fs_hz = 25 (N = 2.25e6) and
    ramp_c_per_min = 0.1 with high_soak_min = 240 (N = 2.88e6); the formula is 1.2-1.25 x
    simulate's and 1.7-1.8 x experiment's. Floats: never an overflow.

    Parameters
    ----------
    config : Config
        The configuration.

    Returns
    -------
    float
        Bytes.
    """
    n = 2.0 * float(config.chamber().duration) * float(config.fs_hz)
    return 1.1 * (232.0 * n + 20e6)


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Blocks:
    """One chamber run as 100-s block means (``Config.block_s``), with its truth.

    Attributes
    ----------
    t_h : ndarray
        Block centres [h].
    X : ndarray
        (n, 11) regressors x1..x11 on the logged T1, T2 [degC, degC/s].
    output : ndarray
        Mean output [deg/h].
    truth : ndarray
        Mean true rate [deg/h].
    thermal : ndarray
        Mean true thermal bias [deg/h].
    t1, t2 : ndarray
        Logged housing and cavity temperatures [degC].
    chamber : ndarray
        Chamber [degC].
    mode : ndarray
        PLC mode index at each block's end.
    lock_in : ndarray
        Mean lock-in rate [deg/s].
    hops_up, hops_down : ndarray
        Block temperature at heating and cooling hops [degC].
    """

    t_h: NDArray[np.float64]  # block centre [h]
    X: NDArray[np.float64]  # (n, 11) regressors x1..x11 on the logged T1, T2 [degC, degC/s]
    output: NDArray[np.float64]  # mean output [deg/h]
    truth: NDArray[np.float64]  # mean true rate [deg/h]
    thermal: NDArray[np.float64]  # mean true thermal bias [deg/h]
    t1: NDArray[np.float64]  # logged housing [degC]
    t2: NDArray[np.float64]  # logged cavity [degC]
    chamber: NDArray[np.float64]  # [degC]
    mode: NDArray[np.float64]  # PLC mode index at the end of each block
    lock_in: NDArray[np.float64]  # mean lock-in rate [deg/s]
    hops_up: NDArray[np.float64]  # block (mean of nodes A, B) temperature at heating hops [degC]
    hops_down: NDArray[np.float64]  # ... at cooling hops [degC]


def _hop_temperatures(rec: Recording) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Block temperatures [degC] at the PLC's mode hops, on heating and on cooling."""
    tb = 0.5 * (np.asarray(rec["inputs/T2"]) + np.asarray(rec["inputs/T_block_b"]))
    j = np.flatnonzero(np.diff(np.asarray(rec["inputs/mode"]))) + 1
    heating = tb[j] > tb[j - 1]
    return units.to_celsius(tb[j][heating]), units.to_celsius(tb[j][~heating])


def _blocks(rec: Recording, config: Config) -> Blocks:
    fs, b = rec.fs, config.block_s

    def bm(x: NDArray[np.float64]) -> NDArray[np.float64]:
        return block_means(x, fs, block_s=b)

    logged = two_sensor_blocks(
        units.to_celsius(rec["T1"]),
        units.to_celsius(rec["T2"]),
        fs,
        block_s=b,
        window_s=config.derivative_window_s,
    )
    step = int(round(b * fs))
    up, down = _hop_temperatures(rec)
    return Blocks(
        t_h=np.asarray((np.arange(len(logged.t1)) + 0.5) * b / units.HOUR, dtype=np.float64),
        X=logged.X,
        output=bm(units.to_deg_per_h(rec["output"])),
        truth=bm(units.to_deg_per_h(rec["truth/true_rate"])),
        thermal=bm(units.to_deg_per_h(rec["truth/thermal_bias"])),
        t1=logged.t1,
        t2=logged.t2,
        chamber=bm(units.to_celsius(rec["inputs/chamber"])),
        mode=np.asarray(rec["inputs/mode"])[step - 1 :: step][: len(logged.t1)],
        lock_in=bm(units.to_deg_per_s(rec["detail/lock_in_rate"])),
        hops_up=up,
        hops_down=down,
    )


def _drop_prewarm(b: Blocks, n: int) -> Blocks:
    """``b`` without its first ``n`` blocks (the pre-warm), block times from the record's start."""
    if n == 0:
        return b
    kw = {f.name: getattr(b, f.name) for f in fields(b)}
    for k in ("X", "output", "truth", "thermal", "t1", "t2", "chamber", "mode", "lock_in"):
        kw[k] = kw[k][n:]
    kw["t_h"] = b.t_h[n:] - b.t_h[n] + b.t_h[0]
    return Blocks(**kw)


def runs(config: Config, seed: int, *, mode_hops: bool = True) -> tuple[CavityRLG, Blocks, Blocks]:
    """The unit's gyro and its fitting and held-out runs as 100-s blocks.

    ``mode_hops=False``: the same gyro and draws with a PLC of unlimited travel (no hops).
    With ``Config.prewarm_min`` > 0 the first ``Config.prewarm_blocks()`` blocks (the gyro
    powered at the first chamber temperature) are dropped; the regressors' derivative windows
    at the record's start see the pre-warm part. Mode hops during it stay in ``hops_up``,
    ``hops_down``.

    Parameters
    ----------
    config : Config
        The configuration.
    seed : int
        The unit's seed.
    mode_hops : bool
        False: a PLC of unlimited travel (no hops), same draws.

    Returns
    -------
    tuple of (CavityRLG, Blocks, Blocks)
        The gyro, its fitting run and its held-out run.
    """
    gyro, streams = unit_and_streams(config, seed)
    prof = config.chamber()
    env = Environment(prof.duration, temperature=prof)
    run_gyro = replace(gyro, mode_hops=mode_hops)
    n = config.prewarm_blocks()
    fit, held = (_drop_prewarm(_blocks(run_gyro.simulate(env, fs=config.fs_hz, rng=r), config), n) for r in streams)
    return gyro, fit, held
