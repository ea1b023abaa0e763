"""Paper 000's experiment: one unit (one seed) simulated and carried through the whole analysis.

:func:`experiment` returns a typed :class:`~.results.UnitResult` (no formatting, no verdicts);
:func:`simulate` gives the unit's two recordings with truth; :func:`memory_estimate` the peak
memory of one unit. Seed streams: ``default_rng(seed).spawn(4)``: children 0 and 1 the two
records, 2 the RBF centres' order, 3 the drawn unit.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import asdict

import numpy as np
from numpy.typing import NDArray

from gyrobench.analysis.wavelet import MultiscaleDecomposition, decompose
from gyrobench.base import units
from gyrobench.io.recording import Recording
from gyrobench.sim.fog_loop import ClosedLoopFOG
from gyrobench.sim.mount_coning import MountConing
from gyrobench.sim.shaker import Phased

from . import NAME
from .config import Config, split_level_m
from .device import draw_mount, draw_unit, record_on_table
from .pipeline import (
    BiasModels,
    bias_model_scores,
    block_means,
    compensated,
    decomposition_table,
    edges_and_offsets,
    fit_bias_models,
    phase_table,
    shortest_tau_rise,
    split_band_coefficients,
    tone_free_m,
)
from .results import (
    CompensationTable,
    CompensationTraces,
    FigureData,
    ModelTraces,
    MultiscaleTraces,
    RecordTraces,
    SplitTraces,
    UnitResult,
    unit_quantities,
)

__all__ = ["REPORT_UNITS", "SLIM_FIELDS", "experiment", "memory_estimate", "simulate"]

#: the report's figures draw the first unit only (:func:`gyrobench.scenarios.runner.units.run_paper`)
REPORT_UNITS = 1
#: the fields only the report's figures read: stored emptied for every other unit (the whole
#: fixed-frequency record, 2.4 MB a unit, is most of a unit's result)
SLIM_FIELDS = ("figures",)


def memory_estimate(config: Config) -> float:
    """Peak memory of one unit's :func:`simulate` or :func:`experiment` [bytes], before allocating.

    Per unit (one worker process); the runner multiplies it by the units it runs at once
    (:func:`gyrobench.scenarios.runner.units.check_unit_memory`). With ``T`` the record length
    (static + vibration + static) [s], ``T_v`` the vibration phase [s] and ``f_p`` the shaker
    grid rate ``fog.physics_rate_hz`` [Hz], for the unit's two records (swept and fixed sine)::

        bytes = 1.2 x f_p x (80 T + 160 T_v)

    MEASURED (peak RSS increase of a forked child, one BLAS thread; the harness of
    tests/scenarios/test_memory_estimates.py; 2026-12-01): simulate 522 MB at the default
    (T = 1500 s, T_v = 300 s, f_p = 3200 Hz), 964 MB with T_v = 900 s, 1395 MB with 2400-s static
    phases; experiment 361, 737, 875 MB (it keeps of the sweep only the channels it reads while
    the dwell runs; simulate returns both whole records). A least-squares fit of simulate's three
    gives 78 B per grid sample of the whole records and 152 B more per grid sample of vibration
    (the FOG's vibration transforms and the mount's coning on the vibration span); experiment's,
    45 and 151 B. The formula is 1.24-1.26 x simulate's peaks and 1.6-2.0 x experiment's.
    Floats: never an overflow.

    Parameters
    ----------
    config : Config
        The configuration.

    Returns
    -------
    float
        Bytes.
    """
    t_total = float(config.static_before_s) + float(config.vibration_s) + float(config.static_after_s)
    return 1.2 * float(config.fog.physics_rate_hz) * (80.0 * t_total + 160.0 * float(config.vibration_s))


def _records(config: Config, seed: int, record_seed: int | None = None) -> Iterator[Recording]:
    """The unit's two records, one at a time: (a) the sweep, then (b) the fixed dwell."""
    r_sweep, r_fixed = np.random.default_rng(seed if record_seed is None else record_seed).spawn(2)
    fog, mount = draw_unit(config, seed), draw_mount(config, seed)
    for key, prof, rng in (("sweep", config.sweep(), r_sweep), ("fixed", config.fixed(), r_fixed)):
        yield _record(config, seed, key, prof, rng, fog, mount)  # no local keeps a yielded record alive


def _record(
    config: Config, seed: int, key: str, prof: Phased, rng: np.random.Generator, fog: ClosedLoopFOG,
    mount: MountConing | None,
) -> Recording:
    """One record of the unit (``key`` "sweep" or "fixed"), with the scenario's metadata."""
    rec, channels, truth = record_on_table(fog, prof, config, rng, f"fog_vibration_{key}", mount)
    meta = dict(rec.metadata)
    meta.update({"scenario": NAME, "record": key, "seed": seed, "config": asdict(config)})
    meta["mode_frequencies_hz"] = [md.frequency for md in fog.modes]
    meta["error_components"] = [*meta["error_components"], "coning_rate"]  # the mount's, added to the output
    return Recording(fs=rec.fs, channels=channels, truth=truth, t0=rec.t0, metadata=meta, name=rec.name,
                     inputs=rec.inputs, detail=rec.detail)


def simulate(config: Config, seed: int, record_seed: int | None = None) -> list[Recording]:
    """Record (a) the sweep and (b) the fixed dwell of one drawn FOG (static, vibration, static).

    The unit (its FOG and mount) is drawn from ``seed``; the records' noise and shaker from
    ``record_seed`` (default ``seed``): another record_seed is another run of the same unit.

    Parameters
    ----------
    config : Config
        The configuration.
    seed : int
        The unit's seed.
    record_seed : int or None
        The records' seed (None: ``seed``).

    Returns
    -------
    list of Recording
        The sweep record and the fixed-dwell record.
    """
    return list(_records(config, seed, record_seed))


#: what :func:`experiment` reads of each record (channels; ``group/name`` of the other groups)
_USED = {"sweep": (("output", "shaker_frequency", "shaker_on"), ()),
         "fixed": (("output", "shaker_frequency", "shaker_on"),
                   ("detail/vibration_bias", "truth/optical_noise", "detail/ieee_quantization",
                    "detail/ieee_angle_random_walk"))}


def _slim(rec: Recording, key: str) -> Recording:
    """``rec`` holding only what :func:`experiment` reads: the same arrays, the rest released."""
    chans, others = _USED[key]
    held = rec.columns()
    kept: dict[str, dict] = {"truth": {}, "inputs": {}, "detail": {}}
    for path in others:
        if path in held:
            group, name = path.split("/", 1)
            kept[group][name] = held[path]
    return Recording(fs=rec.fs, channels={k: rec.channels[k] for k in chans}, t0=rec.t0, name=rec.name,
                     metadata={k: v for k, v in rec.metadata.items() if k != "error_components"}, **kept)


def experiment(config: Config, seed: int) -> UnitResult:
    """Simulate one unit (``seed``) through the paper's whole analysis; no formatting, no verdicts.

    Returns the unit's ``quantities`` (one number per claim quantity, None where this unit
    cannot test it), the coefficient tables, the bias-model scores, the offsets and what the
    report's figures draw (downsampled traces and the fixed-frequency record).

    Parameters
    ----------
    config : Config
        The configuration.
    seed : int
        The unit's seed.

    Returns
    -------
    UnitResult
        The unit's quantities, tables, scores and figure data.
    """
    records = _records(config, seed)
    sweep = _slim(next(records), "sweep")  # the sweep's other channels are released before the dwell runs
    fixed = _slim(next(records), "fixed")
    rng_centres = np.random.default_rng(seed).spawn(3)[2]  # simulate() uses children 0 and 1
    fs = fixed.fs
    phases = phase_table(fixed["output"], fs, config.fixed().phase_bounds, guard_s=config.guard_s)
    dec_s = decompose(units.to_deg_per_h(sweep["output"]), fs, wavelet=config.wavelet, level=config.level)
    decomposition = decomposition_table(sweep, dec_s, config)
    bm = fit_bias_models(sweep, config, dec_s, draw_unit(config, seed), rng=rng_centres, mount=draw_mount(config, seed))
    scores = bias_model_scores(bm)
    dec_f = decompose(units.to_deg_per_h(fixed["output"]), fs, wavelet=config.wavelet, level=config.level)
    sig = compensated(fixed, dec_f, bm, config)
    m = split_level_m(config)
    # N of Table 3 where the dwell's aliased tones leave no variance: the raw record carries them, the
    # a_j-based columns (denoised, compensated) carry nothing above fs / 2^(j+1); the full range in the
    # n_full_tau variant. The control (same fixed_hz, 0 g) takes the same range.
    band = {k: fs / 2.0 if k == "original" else fs / 2 ** (config.bias_level + 1) for k in sig}
    n_m = {k: tone_free_m(config.fixed_hz, fs, band_hz=band[k]) if config.n_tone_free else 1 for k in sig}
    table3 = {k: split_band_coefficients(units.deg_per_h(v), fs, m, n_min_m=n_m[k]) for k, v in sig.items()}
    compensation = CompensationTable(
        original=table3["original"], denoised=table3["denoised"], rbf=table3["rbf"], ls=table3["ls"]
    )
    offsets = edges_and_offsets(sig, fixed, config)
    quantities = unit_quantities(
        phases,
        decomposition,
        compensation,
        scores,
        offsets,
        shortest_tau_rise=shortest_tau_rise(fixed["output"], fs, config.fixed().phase_bounds, guard_s=config.guard_s),
    )
    quantities.update(denoising_against_truth(fixed, dec_f, config))
    return UnitResult(
        seed=int(seed),
        quantities=quantities,
        phases=phases,
        decomposition=decomposition,
        compensation=compensation,
        bias_models=scores,
        offsets=offsets,
        figures=_figure_data(sweep, fixed, dec_s, sig, bm, config),
    )


#: the fast noise of the output: the loop's optical noise and the IEEE-952 quantization and angle
#: random walk terms (truth channels); the rest of the output is the true signal
_FAST_NOISE = ("truth/optical_noise", "detail/ieee_quantization", "detail/ieee_angle_random_walk")


def denoising_against_truth(fixed: Recording, dec: MultiscaleDecomposition, config: Config) -> dict[str, float]:
    """How the a_j approximation of the 500 Hz record splits it, against the simulator's truth [-].

    n = the fast noise (:data:`_FAST_NOISE`), s = output - n (the true signal: rates, biases, drift,
    the vibration error) [deg/h]; a_j is linear, so a_j(output) = a_j(s) + a_j(n).
    ``t2_a6_noise_left``: var(a_j(n)) / var(n), the share of the fast noise left in a_j;
    ``t2_a6_signal_lost``: on 1-s means (the time scale of the bias signal; a_j keeps what lies below
    fs / 2^(j+1), 3.1 Hz at the default), mean((a_j(s) - s)^2) / var(s), the share of the true
    signal's variance a_j loses or distorts there (the vibration error's aliased tones average out
    of 1-s means, the offset steps and the drift stay). Both over the whole record.
    """
    fs, j = fixed.fs, config.bias_level
    held = fixed.columns()
    present = [k for k in _FAST_NOISE if k in held]
    if not present:  # no fast noise in the record: nothing to remove
        return {"t2_a6_noise_left": math.nan, "t2_a6_signal_lost": math.nan}
    n = sum(units.to_deg_per_h(held[k].data) for k in present)
    s = units.to_deg_per_h(fixed["output"]) - n
    a_n = decompose(n, fs, wavelet=config.wavelet, level=config.level).approx(j)
    k = max(1, int(round(fs)))
    s1, a1 = block_means(s, k), block_means(dec.approx(j) - a_n, k)
    return {
        "t2_a6_noise_left": float(np.var(a_n) / np.var(n)),
        "t2_a6_signal_lost": float(np.mean((a1 - s1) ** 2) / np.var(s1)),
    }


def _f32(x: object) -> NDArray[np.float32]:
    return np.asarray(x, dtype=np.float32)


def _figure_data(
    sweep: Recording,
    fixed: Recording,
    dec_s: MultiscaleDecomposition,
    sig: dict[str, np.ndarray],
    bm: BiasModels,
    config: Config,
) -> FigureData:
    """Downsampled traces for figures 1, 3, 4, 6, 7-8 (float32, well under 1 MB per unit) and the
    whole fixed-frequency record [deg/h] for figure 2 (float32, 4 bytes a sample: 2.4 MB at the
    default; its spectrum and wavelet map are drawn by the report)."""
    k = max(1, len(fixed.time) // 4000)
    km = max(1, len(sweep.time) // 3000)
    ks = max(1, len(sweep.time) // 4000)
    kc = max(1, len(fixed.time) // 15000)
    j = config.bias_level
    ff = np.linspace(bm.f_bins[0], bm.f_bins[-1], 2000)
    return FigureData(
        records=RecordTraces(
            t=_f32(block_means(fixed.time, k)),
            sweep=_f32(block_means(units.to_deg_per_h(sweep["output"]), k)),
            fixed=_f32(block_means(sig["original"], k)),
        ),
        multiscale=MultiscaleTraces(
            t=_f32(block_means(sweep.time, km)),
            a=_f32(block_means(dec_s.approximation, km)),
            d_rms=_f32([np.sqrt(block_means(dec_s.detail(i) ** 2, km)) for i in range(1, dec_s.level + 1)]),
        ),
        split=SplitTraces(
            t_mean=_f32(block_means(sweep.time, ks)),
            t_sample=_f32(sweep.time[::ks]),
            a_train=_f32(block_means(dec_s.approx(config.train_level), ks)),
            a_bias=_f32(block_means(dec_s.approx(j), ks)),
            d_j=_f32(dec_s.detail(j)[::ks]),
            d1=_f32(dec_s.detail(1)[::ks]),
            d=_f32(dec_s.detail_sum(j)[::ks]),
        ),
        models=ModelTraces(
            f_bins=_f32(bm.f_bins),
            y_bins=_f32(bm.y_bins),
            truth_bins=_f32(bm.truth_bins),
            ff=_f32(ff),
            rbf=_f32(bm.rbf(ff)),
            ls=_f32(bm.ls(ff)),
        ),
        compensation=CompensationTraces(
            t=_f32(fixed.time[::kc]),
            original=_f32(sig["original"][::kc]),
            denoised=_f32(sig["denoised"][::kc]),
            rbf=_f32(sig["rbf"][::kc]),
            ls=_f32(sig["ls"][::kc]),
        ),
        fixed_rate=_f32(sig["original"]),
        fs=float(fixed.fs),
    )
