"""Paper 001's rate-table runs: the simulated power-ons, their dwell means, records and memory.

Protocol (paper section 3): after warm-up the table steps through 21 rates, +3600 -> -3600
deg/s in 360 deg/s steps; the output is sampled at 200 Hz and averaged over 1-2 min of each
settled dwell (here 60 s after 0.5 s settling). A unit is ``n_fit_runs`` runs the
compensators are fitted on, then ``n_heldout_runs`` further power-ons they never see. Each
run's dwells are independent columns of one slow-flow call (the rebalance loop settles in
ms, so a dwell's mean does not depend on the previous rate).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from gyrobench.analysis.scale_factor import dwell_means
from gyrobench.base import units
from gyrobench.io.recording import Channel, Recording, package_version
from gyrobench.sim.mems_resonator import MemsResonator
from gyrobench.sim.sensor import Environment

from . import NAME
from .config import Config
from .device import STATIC_CHUNK, device_spec, draw_unit, rate_authority_dps, rate_transfer
from .results import Trace

__all__ = [
    "Run",
    "dense_rates",
    "run_means",
    "memory_estimate",
    "rate_means",
    "simulate",
    "simulate_runs",
    "trace",
]


@dataclass(frozen=True, slots=True)
class Run:
    """One rate-table run: the power-on, its die temperature [K], the output (n, k) [rad/s].

    Parameters
    ----------
    unit : MemsResonator
        The power-on.
    temperature : float
        Its die temperature [K].
    output : ndarray
        Its output (n, k) [rad/s], one column per table rate.
    """

    unit: MemsResonator
    temperature: float
    output: NDArray[np.float64]


def simulate_runs(config: Config, seed: int) -> list[Run]:
    """Unit ``seed``'s runs: realize the unit, then per run its ambient, power-on and noise.

    Each run goes through the device interface: ``unit.simulate(environment, fs=, rng=)``
    (:meth:`gyrobench.sim.mems_resonator.MemsResonator.simulate`) with the table's rates as
    the columns of an (n, k) ``true_rate``, one independent dwell per column at the run's
    die temperature, with ``error_split="total"``: only the output is read, so the record's
    second, noise-free slow flow is not run (the output is the same bit for bit).

    Parameters
    ----------
    config : Config
        The paper's protocol and device.
    seed : int
        The unit's seed.

    Returns
    -------
    list of Run
        The ``n_fit_runs`` fitting runs, then the held-out runs; each output (n, k) [rad/s],
        one column per table rate.

    Notes
    -----
    The unit comes from the first child stream of ``numpy.random.default_rng(seed)``; each
    run has its own child of the second (ambient temperature, power-on, noise).
    """
    unit = draw_unit(device_spec(config), seed)
    _, r_runs = np.random.default_rng(seed).spawn(2)
    w = units.deg_per_s(np.asarray(config.rates_dps, dtype=float))
    n = int(round(config.settle_s * config.fs_hz)) + int(round(config.average_s * config.fs_hz))
    col = np.ascontiguousarray(np.broadcast_to(w, (n, w.size)))
    transfer = rate_transfer(config)
    out = []
    for rr in r_runs.spawn(config.n_fit_runs + config.n_heldout_runs):
        r_amb, r_on, r_sim = rr.spawn(3)
        temp = units.celsius(config.ambient_c + config.ambient_spread_c * r_amb.standard_normal())
        on = unit.power_on(rng=r_on)
        # only the output is read here (a record's split is :func:`_recording`'s): no noise-free run
        rec = replace(on, error_split="total").simulate(
            Environment(n / config.fs_hz, true_rate=col, temperature=temp), fs=config.fs_hz, rng=r_sim
        )
        dwells = np.ascontiguousarray(rec["output"].reshape(w.size, n).T)  # the record holds dwell after dwell
        out.append(Run(on, float(temp), transfer(dwells)))
    return out


def run_means(config: Config, run: Run) -> NDArray[np.float64]:
    """Mean output over each settled dwell [deg/s] (the paper's per-rate measured output).

    Parameters
    ----------
    config : Config
        The configuration.
    run : Run
        A run.

    Returns
    -------
    ndarray
        One mean per table rate [deg/s].
    """
    n_settle = int(round(config.settle_s * config.fs_hz))
    return units.to_deg_per_s(run.output[n_settle:].mean(axis=0))


def dense_rates(config: Config) -> NDArray[np.float64]:
    """The dense sweep's rates [deg/s]: every ``dense_step_dps`` across the table's span.

    Parameters
    ----------
    config : Config
        The configuration.

    Returns
    -------
    ndarray
        The rates [deg/s].
    """
    lo, hi = min(config.rates_dps), max(config.rates_dps)
    return np.arange(lo, hi + 0.5 * config.dense_step_dps, config.dense_step_dps)


def trace(config: Config, run: Run) -> Trace:
    """A 1 Hz trace of a run (dwells in table order) for the report's figure.

    Parameters
    ----------
    config : Config
        The configuration.
    run : Run
        A run.

    Returns
    -------
    Trace
        The trace.
    """
    n, k = run.output.shape
    step = max(1, int(round(config.fs_hz)))
    y = run.output.T.reshape(-1)[::step]
    table = np.repeat(np.asarray(config.rates_dps, dtype=float), n)[::step]
    return Trace(
        time_s=np.arange(y.size) * step / config.fs_hz,
        table_dps=table,
        output_dps=units.to_deg_per_s(y),
    )


def _recording(config: Config, run: Run, *, index: int, role: str, seed: int) -> Recording:
    """A run as a record: the dwells one after another in table order.

    The error splits in two components: ``deterministic_error``, the error of the same run of
    the same power-on without noise (its ``idealization="noise_free"`` twin through
    ``simulate``, then the same rate transfer: scale factor and its nonlinearity, bias,
    quadrature, rails, ADC), and ``noise``, the record minus that noise-free run.
    """
    n, k = run.output.shape
    w = units.deg_per_s(np.asarray(config.rates_dps, dtype=float))
    rate = np.repeat(w, n)
    n_settle = int(round(config.settle_s * config.fs_hz))
    windows = [[j * n + n_settle, (j + 1) * n] for j in range(k)]
    quiet = replace(run.unit, idealization="noise_free", error_split="total")  # draws nothing from its rng
    calm_rec = quiet.simulate(
        Environment(n / config.fs_hz, true_rate=np.ascontiguousarray(np.broadcast_to(w, (n, k))),
                    temperature=run.temperature),
        fs=config.fs_hz, rng=np.random.default_rng(0),
    )
    calm_runs = np.ascontiguousarray(calm_rec["output"].reshape(k, n).T)  # the record holds dwell after dwell
    calm = rate_transfer(config)(calm_runs).T.reshape(-1)
    out = run.output.T.reshape(-1)
    temperature = np.full(n * k, run.temperature)  # one array for the logged channel and the input
    return Recording(
        fs=config.fs_hz,
        channels={
            "output": Channel(out, "rad/s", "gyro output"),
            "table_rate": Channel(rate, "rad/s", "rate-table rate"),
            "temperature": Channel(temperature, "K", "die temperature"),
        },
        truth={
            "true_rate": Channel(rate, "rad/s", "table rate (truth; the table's own array)"),
            "deterministic_error": Channel(calm - rate, "rad/s", "the noise-free run's error: scale factor and "
                                           "nonlinearity, bias, quadrature, rails, ADC"),
            "noise": Channel(out - calm, "rad/s", "the record minus its noise-free run: Brownian, pick-off and "
                             "1/f noise through the read-out"),
        },
        inputs={"temperature": Channel(temperature, "K", "die temperature")},
        metadata={
            "error_components": ["deterministic_error", "noise"],
            "scenario": NAME,
            "seed": seed,
            "run": index,
            "role": role,
            "variant": config.variant,
            "rates_dps": list(config.rates_dps),
            "windows_samples": windows,
            "die_temperature_c": float(units.to_celsius(run.temperature)),
            "turn_on_bias_dps": float(units.to_deg_per_s(run.unit.turn_on_bias)),
            "scale_factor_error_ppm": float(units.to_ppm(run.unit.turn_on_scale_factor)),
            "rate_authority_dps": rate_authority_dps(run.unit),
            "version": package_version(),
        },
        name=f"{role}_run{index}",
    )


def simulate(config: Config, seed: int) -> list[Recording]:
    """Unit ``seed``'s runs as records: the ``n_fit_runs`` fitting runs then the held-out runs.

    The unit is drawn from the first child stream of ``numpy.random.default_rng(seed)``; each
    run has its own child of the second (ambient temperature, power-on, noise).

    Parameters
    ----------
    config : Config
        The configuration.
    seed : int
        The unit's seed.

    Returns
    -------
    list of Recording
        One record per run, dwell after dwell in table order.
    """
    return [
        _recording(
            config, run, index=i, role="fit" if i < config.n_fit_runs else "heldout", seed=seed
        )
        for i, run in enumerate(simulate_runs(config, seed))
    ]


def rate_means(rec: Recording) -> NDArray[np.float64]:
    """Mean output over each settled window of a record [deg/s] (``analysis.scale_factor.dwell_means``).

    Parameters
    ----------
    rec : Recording
        A run's record (:func:`simulate`).

    Returns
    -------
    ndarray
        One mean per window [deg/s].
    """
    return dwell_means(units.to_deg_per_s(rec["output"]), rec.metadata["windows_samples"])


def memory_estimate(config: Config) -> float:
    """Peak memory of one unit's experiment or :func:`simulate` [bytes], before allocating.

    Per unit (one worker process); the runner multiplies it by the units it runs at once
    (:func:`gyrobench.scenarios.runner.units.check_unit_memory`). With ``n_run = (settle_s +
    average_s) fs_hz len(rates_dps)`` samples in one run (one slow-flow call of
    ``MemsResonator.simulate``) and ``N = n_run (n_fit_runs + n_heldout_runs)`` in all::

        bytes = 1.1 x (32 N + 376 max(n_run, 200 STATIC_CHUNK) + 20e6)

    32 B per sample of every run: :func:`simulate`'s records keep five distinct float64 series
    (output, table rate = true rate, temperature = its input, the two error components), the
    experiment only the output; 32 B is FITTED between the two measured peaks (the estimate
    must bound both, within 2.5x); 376 B = 47 float64 working series of the slow-flow call
    running, a rate-table run or a block of :data:`~.device.STATIC_CHUNK` rates of a noise-free
    sweep (:func:`~.device.static_output`: the dense sweep and the joins' sweep are bounded by the
    block whatever their length); 20 MB the rest (fits, figure data); 1.1 is the margin.
    MEASURED (peak RSS increase, one BLAS thread; tests/scenarios/test_memory_estimates.py),
    simulate / experiment: 106 / 104 MB at the default (N = 1.0e6), 387 / 387 MB at
    average_s = 240 (N = 4.0e6), 263 / 170-206 MB at fs_hz = 400 with n_fit_runs = 6
    (N = 3.6e6); the formula gives 163, 582 and 357 MB.
    Floats: an absurd record gives a huge (or infinite) estimate, never an overflow.

    Parameters
    ----------
    config : Config
        The configuration.

    Returns
    -------
    float
        Bytes.
    """
    n_run = (float(config.settle_s) + float(config.average_s)) * config.fs_hz
    n_run *= len(config.rates_dps)
    n_all = n_run * (config.n_fit_runs + config.n_heldout_runs)
    return 1.1 * (32.0 * n_all + 376.0 * max(n_run, 200.0 * STATIC_CHUNK) + 20e6)
