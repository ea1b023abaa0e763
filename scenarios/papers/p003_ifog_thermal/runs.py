"""Paper 003's chamber runs: simulated, block-averaged, masked to what the paper records.

:func:`simulate` runs one drawn FOG unit through every chamber run of the protocol
(identification twice, validation 1 and 2); :func:`prepare` reduces a recording to what
the analysis uses (:class:`Run`: 100-s block means of the logged output and coil
temperature, and of the simulator's truth for diagnostics and figures).
:func:`compensation_task` hands the same runs to ``gyrobench bench``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from gyrobench.analysis.features import block_means, thermal_features
from gyrobench.base import units
from gyrobench.io.recording import Recording
from gyrobench.scenarios.base import CompensationTask, HeldOutRun
from gyrobench.sim.environment import PiecewiseLinear
from gyrobench.sim.fog2d import FOG2DUnit
from gyrobench.sim.sensor import Environment, with_metadata

from .config import FEATURES_IMPROVED, NAME, Config

__all__ = [
    "IDENTIFICATION_SEGMENTS",
    "Run",
    "chamber_runs",
    "compensation_task",
    "features",
    "identification_segments",
    "memory_estimate",
    "prepare",
    "record_mask",
    "reference_deg_h",
    "realize_unit",
    "score_mse",
    "simulate",
]

_H = units.HOUR
_MIN = units.MINUTE

#: the folds of the RBF selection: segments of an identification run
IDENTIFICATION_SEGMENTS = ("settle", "heat + hold", "cool + hold")


def chamber_runs(config: Config) -> list[tuple[str, PiecewiseLinear, float]]:
    """(name, chamber profile, true rate [rad/s]) of every run, in order.

    Parameters
    ----------
    config : Config
        The configuration.

    Returns
    -------
    list of (str, PiecewiseLinear, float)
        (name, chamber profile, true rate [rad/s]) per run.
    """
    ident = config.identification_profile()
    v1 = config.validation_profile(config.validation1_rate_degC_per_h / _H)
    v2 = config.validation_profile(config.validation2_rate_degC_per_min / _MIN)
    a = units.deg_per_h(config.validation2_true_rate_deg_h)
    out = [("ident_1", ident, 0.0), ("ident_2", ident, 0.0)]
    out += [(f"val1_run{i + 1}", v1, 0.0) for i in range(config.validation1_runs)]
    out += [(f"val2_run{i + 1}", v2, a) for i in range(config.validation2_runs)]
    return out


def realize_unit(config: Config, rng: np.random.Generator) -> FOG2DUnit:
    """One drawn FOG unit of the configured build.

    Parameters
    ----------
    config : Config
        The configuration.
    rng : numpy.random.Generator
        The unit's stream.

    Returns
    -------
    FOG2DUnit
        The unit.
    """
    return config.fog_spec().realize(rng=rng)


def simulate(config: Config, seed: int) -> list[Recording]:
    """All runs of the experiment with one FOG unit: 2 identification, validation 1 and 2 runs.

    Parameters
    ----------
    config : Config
        The configuration.
    seed : int
        The unit's seed.

    Returns
    -------
    list of Recording
        The runs, in order.
    """
    root = np.random.default_rng(seed)
    rng_unit, rng_runs = root.spawn(2)
    unit = realize_unit(config, rng_unit)
    runs = chamber_runs(config)
    recs = []
    for (name, prof, rate), rng in zip(runs, rng_runs.spawn(len(runs)), strict=True):
        rng_setup, rng_fog = rng.spawn(2)
        # run-to-run mounting/airflow: the housing lag differs a little between chamber runs
        factor = max(0.5, 1.0 + config.housing_lag_run_rms * rng_setup.standard_normal())
        run_unit = replace(unit, chamber_scale=1.0 / factor)
        env = Environment(prof.duration, temperature=prof, true_rate=rate)
        recs.append(
            with_metadata(
                run_unit.simulate(env, fs=config.fs_hz, rng=rng_fog),
                name=name,
                scenario=NAME,
                seed=seed,
                run=name,
                housing_time_constant_s=config.housing_time_constant_min * _MIN * factor,
            )
        )
    return recs


def memory_estimate(config: Config) -> float:
    """Peak memory of one unit's ``experiment`` or :func:`simulate` [bytes], before allocating.

    Per unit (one worker process); the runner multiplies it by the units it runs at once
    (:func:`gyrobench.scenarios.runner.units.check_unit_memory`). With ``N = sum_runs duration fs_hz``
    samples in all the unit's chamber runs (:func:`chamber_runs`), ``m = max_runs duration /
    thermal_step_s`` thermal steps in the longest run and ``g`` thermal nodes of the coil
    grid (``(grid_spool + grid_pack_r + 1)(grid_pack_z + 2) + 1``, 121 by default)::

        bytes = 1.1 x (168 N + 80 g m + 10e6)

    168 B = 21 float64 series per sample: :func:`simulate` returns every run's recording (2
    channels; ~19 truth series: the closed loop's parts -- true, table and Earth rate,
    scale-factor error, nonreciprocal input, loop error, optical and IEEE-952 noise and its
    terms -- and the coil's Shupe and T x dT terms, noise sum and four temperatures) and
    ``experiment`` holds them all while it block-averages them; 80 B = 10 float64
    (steps x nodes) arrays of the modal thermal solution of one run (~5 measured, doubled for
    the convergence check at dt / 2 when the chamber knots are off the step grid). 10 MB the
    rest; 1.1 the margin. MEASURED (peak RSS increase, one BLAS thread;
    tests/scenarios/test_memory_estimates.py; on the closed-loop FOG): 55 MB at the
    default (N = 2.5e5, m = 1470), 419 MB at fs_hz = 10, 132 MB with validation1_runs = 20
    and identification_hold_h = 8 (N = 7.2e5, m = 3630), 117 MB at thermal_step_s = 2
    (m = 14700, on the grid: ~5 arrays), 84 MB at thermal_step_s = 7 (m = 4200, off the
    grid: ~9.3 arrays), simulate and experiment alike; the formula is 1.2-2.1 x these.
    Floats: never an overflow. O(1) in the run counts (the issue-32 ``validation1_runs = 2e7``
    took 165 s and 3.8 GB when it listed every run).

    Parameters
    ----------
    config : Config
        The configuration.

    Returns
    -------
    float
        Bytes.
    """
    # O(1) in the run counts: the runs of one kind share one chamber profile (chamber_runs), so
    # each kind's duration is computed once and multiplied by its count
    ident = float(config.identification_profile().duration)
    v1 = float(config.validation_profile(config.validation1_rate_degC_per_h / _H).duration)
    v2 = float(config.validation_profile(config.validation2_rate_degC_per_min / _MIN).duration)
    spec = config.coil_spec()
    nodes = (spec.grid_spool + spec.grid_pack_r + 1) * (spec.grid_pack_z + 2) + 1
    n = (2.0 * ident + config.validation1_runs * v1 + config.validation2_runs * v2) * float(config.fs_hz)
    m = max(ident, v1, v2) / float(config.thermal_step_s)
    return 1.1 * (168.0 * n + 80.0 * nodes * m + 10e6)


@dataclass(frozen=True, slots=True)
class Run:
    """One chamber run at the analysis rate (block means of the recording).

    Attributes
    ----------
    name : str
        The run's name.
    t_h : ndarray
        Block-centre times from the start [h].
    T : ndarray
        Logged coil temperature [degC].
    output : ndarray
        Output [deg/h].
    truth : ndarray
        The simulator's true rate [deg/h] (diagnostics only).
    drift : ndarray
        The true coil thermal drift [deg/h] (figures only).
    fs : float
        Analysis rate [Hz].
    reference : float
        The reference a [deg/h].
    scored : ndarray of bool or None
        The samples the paper records or scores.
    """

    name: str
    t_h: NDArray[np.float64]  # block-centre times from the start of the run [h]
    T: NDArray[np.float64]  # logged coil temperature [degC]
    output: NDArray[np.float64]  # [deg/h]
    truth: NDArray[np.float64]  # simulator's true rate [deg/h] (diagnostics only)
    drift: NDArray[np.float64]  # simulator's true coil thermal drift [deg/h] (figures only)
    fs: float  # analysis rate [Hz]
    reference: float  # the turntable reference a [deg/h] the paper scores against
    scored: NDArray[np.bool_] | None = None  # samples the paper records / scores (record_mask)


def reference_deg_h(config: Config, name: str) -> float:
    """The paper's reference a [deg/h]: 0 (turntable pointing north), validation 2: eq. (24).

    Parameters
    ----------
    config : Config
        The configuration.
    name : str
        The run's name.

    Returns
    -------
    float
        a [deg/h].
    """
    return float(config.validation2_true_rate_deg_h) if name.startswith("val2") else 0.0


def prepare(rec: Recording, config: Config) -> Run:
    """Block means of what the test logs (and of the truth) at the analysis rate.

    Parameters
    ----------
    rec : Recording
        A run's record.
    config : Config
        The configuration.

    Returns
    -------
    Run
        The run at the analysis rate.
    """
    b = config.analysis_block_s

    def bm(x):
        return block_means(x, rec.fs, block_s=b)

    n = len(bm(rec["output"]))
    run = Run(
        name=rec.name,
        t_h=(np.arange(n, dtype=float) + 0.5) * b / _H,
        T=units.to_celsius(bm(rec["coil_temperature"])),
        output=units.to_deg_per_h(bm(rec["output"])),
        truth=units.to_deg_per_h(bm(rec["truth/true_rate"])),
        drift=units.to_deg_per_h(bm(rec["detail/thermal_drift"])),
        fs=1.0 / b,
        reference=reference_deg_h(config, rec.name),
    )
    return replace(run, scored=record_mask(config, run))


def features(run: Run, config: Config, *, product: bool = True) -> NDArray[np.float64]:
    """(T [degC], dT/dt [degC/s][, T x dT/dt]) of the run, from the logged temperature only.

    dT/dt by ``config.derivative_estimator``: a Savitzky-Golay derivative over
    ``derivative_window_s`` (``gyrobench.analysis.features.thermal_features``) or the central
    difference of the analysis-rate samples.

    Parameters
    ----------
    run : Run
        The run.
    config : Config
        The configuration (the derivative estimator).
    product : bool
        Include T x dT/dt.

    Returns
    -------
    ndarray
        One row per sample.
    """
    if config.derivative_estimator == "savgol":
        return thermal_features(run.T, run.fs, window_s=config.derivative_window_s, product=product)
    T = np.asarray(run.T, dtype=float)
    dT = np.gradient(T) * run.fs  # central difference of the analysis-rate samples [degC/s]
    return np.column_stack([T, dT] + ([T * dT] if product else []))


def identification_segments(config: Config, t_h: NDArray[np.float64]) -> NDArray[np.int_]:
    """Segment (0 settle, 1 heat + hold, 2 cool + hold) of each time ``t_h`` [h] of an ident. run.

    The boundaries are knots of the chamber program (``Config.identification_profile``),
    known before any data are seen: the end of the -10 degC settle and the end of the
    40 degC hold.

    Parameters
    ----------
    config : Config
        The configuration.
    t_h : ndarray
        Times [h].

    Returns
    -------
    ndarray of int
        0, 1 or 2 per time.
    """
    knots_h = np.asarray(config.identification_profile().times, dtype=float) / _H
    knots_h = knots_h - knots_h[0]
    return np.digitize(np.asarray(t_h, dtype=float), [knots_h[2], knots_h[4]])


def record_mask(config: Config, run: Run) -> NDArray[np.bool_]:
    """Samples of ``run`` the paper records (identification) or scores (validation).

    Identification: from the chamber reaching -10 degC (experiment step 2), unless
    ``record_cooldown``. Validation: until the end of the heating ramp (validation step 2
    records the heating), unless ``score_final_soak``.

    Parameters
    ----------
    config : Config
        The configuration.
    run : Run
        The run.

    Returns
    -------
    ndarray of bool
        Per sample.
    """
    if run.name.startswith("ident"):
        knots = config.identification_profile().times
        start_h = (knots[1] - knots[0]) / _H
        return np.ones(len(run.t_h), bool) if config.record_cooldown else run.t_h >= start_h
    if config.score_final_soak:
        return np.ones(len(run.t_h), bool)
    rate = (
        config.validation1_rate_degC_per_h / _H
        if run.name.startswith("val1")
        else config.validation2_rate_degC_per_min / _MIN
    )
    knots = config.validation_profile(rate).times
    return run.t_h <= (knots[2] - knots[0]) / _H


def score_mse(compensated: NDArray[np.float64], run: HeldOutRun) -> dict[str, float]:
    """MSE [(deg/h)^2] and RMS [deg/h] of compensated output against the true rate (the bench).

    Parameters
    ----------
    compensated : ndarray
        Compensated output of a held-out run [deg/h].
    run : HeldOutRun
        The run (its true rate).

    Returns
    -------
    dict of str to float
        MSE [(deg/h)^2] and RMS [deg/h].
    """
    err = np.asarray(compensated, dtype=float) - run.truth
    m = float(np.mean(err**2))
    return {"mse": m, "rms": math.sqrt(m)}


def compensation_task(config: Config, seed: int) -> CompensationTask:
    """Training = identification run 1; held out = identification run 2 and every validation run.

    The bench's task: the whole runs, target output - truth.
    ``groups_train``: each training row's segment of the identification run
    (:func:`identification_segments`: 0 settle, 1 heat + hold, 2 cool + hold, from the chamber
    program's knots, known before any data), the folds of the paper's leave-one-segment-out
    selection of the RBF's spread and neuron count. The bench passes them only to compensators
    whose ``fit`` takes ``groups`` (:mod:`gyrobench.scenarios.bench`).

    Parameters
    ----------
    config : Config
        The configuration.
    seed : int
        The unit's seed.

    Returns
    -------
    CompensationTask
        Training and held-out runs.
    """
    runs = [prepare(r, config) for r in simulate(config, seed)]
    train = runs[0]
    held = tuple(
        HeldOutRun(label=r.name, X=features(r, config), output=r.output, truth=r.truth) for r in runs[1:]
    )
    return CompensationTask(
        scenario=NAME,
        feature_names=FEATURES_IMPROVED,
        X_train=features(train, config),
        y_train=train.output - train.truth,
        heldout=held,
        target="error",
        unit="deg/h",
        scorer=score_mse,
        groups_train=identification_segments(config, train.t_h),
    )
