"""Paper 000's analysis steps on one unit's records: Allan tables, bias models, compensation, offsets.

Each step takes recordings or arrays and returns typed results (:mod:`.results`) or arrays;
:func:`~.experiment.experiment` chains them. The RBF network with randomly fixed centres is
:class:`gyrobench.analysis.compensation.random_rbf.RandomCentreRBF`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gyrobench.analysis.allan import allan_deviation, avar_to_coefficient, fit_noise
from gyrobench.analysis.compensation.random_rbf import RandomCentreRBF
from gyrobench.analysis.metrics import segment_noise_fits
from gyrobench.analysis.sweep import bin_means
from gyrobench.analysis.wavelet import MultiscaleDecomposition
from gyrobench.base import units
from gyrobench.io.recording import Recording
from gyrobench.scenarios.reports.allan import TERMS, coefficients_json
from gyrobench.sim.fog_loop import ClosedLoopFOG
from gyrobench.sim.mount_coning import MountConing

from .config import Config, split_level_m
from .device import true_bias_at_bins
from .results import BiasModelScores, Coefficients, Decomposition, Offsets, PhaseTable, zero_safe_ratio

__all__ = [
    "BiasModels",
    "bias_model_scores",
    "block_means",
    "compensated",
    "decomposition_table",
    "edge_spike_ratio",
    "edges_and_offsets",
    "fit_bias_models",
    "phase_table",
    "predict_on",
    "shortest_tau_rise",
    "split_band_coefficients",
    "tone_free_m",
]


def tone_free_m(drive_hz: float, fs: float, *, band_hz: float | None = None, max_m: int = 2**20) -> int:
    """Smallest octave cluster size m [samples] at which the drive's tones leave no Allan variance.

    A sine drive at f reaches an integrate-and-dump output at ``fs`` as tones at f and 2f (the
    strain and rocking tones, the coning and rectification harmonic), each aliased to
    f_a = |f_k - fs round(f_k / fs)|; a tone's ADEV A sin^2(pi f_a tau) / (pi f_a tau) (IEEE Std
    952-1997, C.1) vanishes at tau = k / f_a, i.e. where m f_a / fs is a whole number. Returns the
    smallest m = 1, 2, 4, ... <= ``max_m`` where that holds for every f_a the signal carries: nonzero
    (a tone aliased to 0 Hz is a constant over each output interval) and below ``band_hz`` [Hz]
    (default fs/2; a wavelet approximation a_j carries nothing above fs/2^(j+1)). 1 when no tone is
    carried or no octave is tone-free (the fit keeps the full range). 4 for 500 Hz at 400 Hz (tones
    at 100 and 200 Hz); 1 for a6 of that record (band 1.6 Hz).

    Parameters
    ----------
    drive_hz : float
        The drive frequency [Hz].
    fs : float
        The output rate [Hz].
    band_hz : float or None
        Half-width of each tone's band [Hz] (None: the module's).
    max_m : int
        The largest cluster size considered.

    Returns
    -------
    int
        m [samples].

    Raises
    ------
    ValueError
        ``drive_hz`` < 0, ``fs`` or ``band_hz`` not > 0 (finite), or ``max_m`` not an integer >= 1.
    """

    def bad(v: float, zero_ok: bool) -> bool:
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            return True
        return v < 0 if zero_ok else v <= 0

    for name, v, zero_ok in (("drive_hz", drive_hz, True), ("fs", fs, False), ("band_hz", band_hz, False)):
        if v is not None and bad(v, zero_ok):
            raise ValueError(f"tone_free_m: {name} must be finite and {'>=' if zero_ok else '>'} 0 Hz; got {v!r}")
    if isinstance(max_m, bool) or not isinstance(max_m, int) or max_m < 1:
        raise ValueError(f"tone_free_m: max_m must be an integer >= 1; got {max_m!r}")
    top = fs / 2.0 if band_hz is None else band_hz
    aliased = [abs(f - fs * round(f / fs)) for f in (drive_hz, 2.0 * drive_hz)]
    aliased = [a for a in aliased if 1e-9 * fs < a <= top]
    m = 1
    while m <= max_m:
        if all(abs(m * a / fs - round(m * a / fs)) < 1e-9 for a in aliased):
            return m
        m *= 2
    return 1


def split_band_coefficients(
    rate_rad_s: NDArray[np.float64], fs: float, min_m: int, *, n_min_m: int = 1
) -> Coefficients:
    """Allan coefficients with each term fitted on its own tau band.

    Q from the fit on the full tau range, N from the fit on tau >= ``n_min_m``/fs, B, K and R from the
    fit on tau >= min_m/fs (field units).

    Used for wavelet-processed signals and what they are compared with: an approximation
    A_j has no content above fs/2^(j+1), so its short-tau ADEV measures the filter (slope +1,
    read as a spurious R); the low-frequency terms are read where A_j is faithful, the
    high-frequency terms where they live. ``n_min_m`` (:func:`tone_free_m`) starts N's fit where a
    sine drive's aliased tones leave no Allan variance: N is read from the white-noise region, as
    the IEEE 952 read-off does, not from points the tones make a misfit of (1, or fewer than five
    octaves from there: the full range).
    Each entry carries its ``tau_min_s`` and the fit's point value ``fit_value`` (set also for a
    term the record does not identify).

    Parameters
    ----------
    rate_rad_s : ndarray
        The signal [rad/s].
    fs : float
        Its sample rate [Hz].
    min_m : int
        Shortest cluster size of the B, K, R fit [samples].
    n_min_m : int
        Shortest cluster size of the N fit [samples].

    Returns
    -------
    Coefficients
        Q from the full range, N from tau >= n_min_m/fs, B, K, R from tau >= min_m/fs.
    """
    y = np.asarray(rate_rad_s, dtype=float)
    octaves = [2**k for k in range(64) if 2**k <= y.size // 4]
    curve = allan_deviation(y, fs, taus=np.array(octaves, dtype=float) / fs)
    if sum(m >= n_min_m for m in octaves) < len(TERMS):  # too few tone-free octaves for the fit: full range
        n_min_m = 1
    # one curve for the three fits: each fits the octave points from its own tau_min
    fits = {"Q": fit_noise(curve)}
    fits["low"] = fit_noise(curve, tau_min=min_m / fs) if min_m > 1 else fits["Q"]
    fits["N"] = fit_noise(curve, tau_min=n_min_m / fs) if n_min_m > 1 else fits["Q"]
    tables = {k: coefficients_json(f) for k, f in fits.items()}
    out = {}
    for t in TERMS:
        k = t if t in ("Q", "N") else "low"
        d = dict(tables[k][t])
        d["tau_min_s"] = {"Q": 1, "N": n_min_m}.get(t, min_m) / fs
        # the fit's point value whether or not the term is identifiable (what a table of the fit prints)
        d["fit_value"] = units.coefficient_to_field(t, avar_to_coefficient(t, fits[k].avar_coefficients[t]))
        out[t] = d
    return Coefficients.from_mapping(out)


def phase_table(
    rate: NDArray[np.float64], fs: float, bounds: Sequence[tuple[float, float]], *, guard_s: float = 0.0
) -> PhaseTable:
    """Table 1: Allan coefficients (field units) of the three [start, end) phases [s] of a rate record [rad/s].

    ``guard_s`` is cut after each phase's start (except the first) so switching
    transients stay out of the steady phases.

    Parameters
    ----------
    rate : ndarray
        The rate record [rad/s].
    fs : float
        Its sample rate [Hz].
    bounds : sequence of (float, float)
        The three phases' [start, end) [s].
    guard_s : float
        Cut after each phase's start but the first [s].

    Returns
    -------
    PhaseTable
        Table 1.
    """
    if len(bounds) != 3:
        raise ValueError(f"phase_table needs 3 phases (static, vibration, static); got {len(bounds)}")
    segs = {
        str(i): (t0 + (guard_s if i > 1 else 0.0), t1) for i, (t0, t1) in enumerate(bounds, start=1)
    }
    fits = {
        k: Coefficients.from_mapping(coefficients_json(f.fit)) for k, f in segment_noise_fits(rate, fs, segs).items()
    }
    return PhaseTable(phase1=fits["1"], phase2=fits["2"], phase3=fits["3"])


def shortest_tau_rise(
    rate: NDArray[np.float64], fs: float, bounds: Sequence[tuple[float, float]], *, guard_s: float = 0.0
) -> float:
    """Table 1's rise as the vibration phase's record shows it: ADEV at tau = 1/fs, phase 2 over the static phases.

    What a vibration phase's Allan table measures (paper 000 fits the raw record): the sine
    vibration reaches the output as tones aliased into its band; a tone of amplitude A0 at f has
    sigma(tau) = A0 sin^2(pi f tau) / (pi f tau) (IEEE Std 952-1997, Annex C, sinusoidal noise), a 1/tau envelope the
    IEEE fit reads as quantization Q, and zero at tau = k/f, so the octave taus beyond the
    aliased tone's period see only the static noise; the rectified bias is constant within the
    phase and adds no Allan variance. The rise is therefore found where Q dominates the static
    phases, at the shortest cluster time. Returns phase 2's lower 95 % bound over the larger
    upper 95 % bound of phases 1 and 3 at tau = 1/fs (> 1: phase 2 is higher at 95 %); the
    phases are cut as in :func:`phase_table`. ``rate`` in any unit (the ratio is unitless).

    Parameters
    ----------
    rate : ndarray
        The rate record [rad/s].
    fs : float
        Its sample rate [Hz].
    bounds : sequence of (float, float)
        The three phases' [start, end) [s].
    guard_s : float
        Cut after each phase's start but the first [s].

    Returns
    -------
    float
        The vibration phase's ADEV at tau = 1/fs over the static phases' [-].
    """
    if len(bounds) != 3:
        raise ValueError(f"shortest_tau_rise needs 3 phases (static, vibration, static); got {len(bounds)}")
    curves = []
    for i, (t0, t1) in enumerate(bounds, start=1):
        a, b = int(round((t0 + (guard_s if i > 1 else 0.0)) * fs)), int(round(t1 * fs))
        curves.append(allan_deviation(rate[a:b], fs, taus=[1.0 / fs], confidence=0.95))
    static_high = max(float(curves[0].high[0]), float(curves[2].high[0]))
    return zero_safe_ratio(float(curves[1].low[0]), static_high)


def _near_edges(on: np.ndarray, fs: float, width_s: float) -> np.ndarray:
    """True within ``width_s`` [s] of any switching edge of the boolean ``on``."""
    edges = np.flatnonzero(np.diff(on.astype(np.int8))) + 1
    near = np.zeros_like(on)
    w = int(round(width_s * fs))
    for e in edges:
        near[max(0, e - w) : e + w] = True
    return near


def predict_on(
    fn: Callable[[NDArray[np.float64]], Any], f: np.ndarray, on: np.ndarray, lo: float, hi: float
) -> np.ndarray:
    """Model bias [deg/h] while ``on``, 0 otherwise; inputs clipped to the training range [lo, hi] Hz.

    Parameters
    ----------
    fn : callable
        The model, frequency [Hz] -> bias [deg/h].
    f : ndarray
        Drive frequency per sample [Hz].
    on : ndarray of bool
        Where the shaker runs.
    lo, hi : float
        The training range [Hz].

    Returns
    -------
    ndarray
        The bias [deg/h].
    """
    out = np.zeros(len(f))
    if on.any():
        u, inv = np.unique(np.clip(f[on], lo, hi), return_inverse=True)
        out[on] = np.asarray(fn(u), dtype=float).reshape(-1)[inv]
    return out


def _phase_mask(rec: Recording) -> tuple[np.ndarray, np.ndarray]:
    on = rec["shaker_on"] > 0.5
    first_on = int(np.argmax(on)) if on.any() else len(on)
    static1 = np.zeros_like(on)
    static1[:first_on] = True
    return on, static1


def block_means(x: np.ndarray, k: int) -> np.ndarray:
    """Means of consecutive blocks of ``k`` samples (a partial last block is dropped).

    Parameters
    ----------
    x : ndarray
        Samples.
    k : int
        Block length [samples].

    Returns
    -------
    ndarray
        The block means.
    """
    n = len(x) // k * k
    return x[:n].reshape(-1, k).mean(axis=1)


@dataclass(frozen=True)
class BiasModels:
    """The fitted bias-vs-frequency models and their training data (deg/h, Hz).

    Attributes
    ----------
    f_bins : ndarray
        Training bins' frequencies [Hz].
    y_bins : ndarray
        Their mean target bias [deg/h].
    truth_bins : ndarray
        The true bias there [deg/h].
    rbf : callable
        The RBF model, frequency [Hz] -> bias [deg/h].
    rbf_neurons : int
        Its size.
    ls : numpy.polynomial.Polynomial
        The least-squares polynomial model.
    static_mean : float
        Mean of the static phase [deg/h].
    """

    f_bins: np.ndarray
    y_bins: np.ndarray
    truth_bins: np.ndarray
    rbf: Callable[[np.ndarray], np.ndarray]
    rbf_neurons: int
    ls: np.polynomial.Polynomial
    static_mean: float


def _predict_column(model: Any, u: np.ndarray) -> np.ndarray:
    """A fitted sklearn-style regressor on a 1-D input (one column)."""
    return np.asarray(model.predict(np.asarray(u, dtype=float).reshape(-1, 1)), dtype=float)


def fit_bias_models(
    rec: Recording,
    config: Config,
    dec: MultiscaleDecomposition,
    fog: ClosedLoopFOG,
    *,
    rng: np.random.Generator,
    mount: MountConing | None = None,
) -> BiasModels:
    """RBF and 4th-order LS models of the a_{train_level} bias [deg/h] against drive frequency [Hz] (a sweep).

    Parameters
    ----------
    rec : Recording
        The sweep record.
    config : Config
        The configuration.
    dec : MultiscaleDecomposition
        Its decomposition.
    fog : ClosedLoopFOG
        The unit (its true bias at the bins).
    rng : numpy.random.Generator
        The RBF centres' stream.
    mount : MountConing or None
        The unit's mount.

    Returns
    -------
    BiasModels
        The fitted models and their training data.
    """
    fs = rec.fs
    bias = dec.approx(config.train_level)
    on, static1 = _phase_mask(rec)
    static_mean = float(np.mean(bias[static1])) if static1.any() else 0.0
    lo, hi = (
        min(config.sweep_start_hz, config.sweep_end_hz),
        max(config.sweep_start_hz, config.sweep_end_hz),
    )
    use = on & ~_near_edges(on, fs, config.train_edge_s)
    fb, yb = bin_means(rec["shaker_frequency"][use], bias[use] - static_mean, lo=lo, hi=hi, width=config.bin_width_hz)
    rbf: Callable[[np.ndarray], np.ndarray]
    if config.rbf_centres == "random":
        net = RandomCentreRBF(
            spread=config.rbf_spread_hz,
            goal=config.rbf_goal_deg_h2,
            max_neurons=config.rbf_max_neurons,
            random_state=rng,
        ).fit(fb[:, None], yb)
        rbf, neurons = partial(_predict_column, net), int(net.n_neurons_)
    else:
        from gyrobench.analysis.compensation.rbf import RBFNetwork

        ols = RBFNetwork(
            spread=config.rbf_spread_hz,
            goal=config.rbf_goal_deg_h2,
            max_neurons=config.rbf_max_neurons,
        ).fit(fb[:, None], yb)
        rbf, neurons = partial(_predict_column, ols), int(ols.n_neurons_)
    ls = np.polynomial.Polynomial.fit(fb, yb, config.ls_order)
    return BiasModels(fb, yb, true_bias_at_bins(fb, config, fog, mount), rbf, neurons, ls, static_mean)


def decomposition_table(sweep: Recording, dec: MultiscaleDecomposition, config: Config) -> Decomposition:
    """Allan coefficients of the sweep record, its a_j bias part and its d1..d_j drift + noise part.

    Parameters
    ----------
    sweep : Recording
        The sweep record.
    dec : MultiscaleDecomposition
        Its decomposition.
    config : Config
        The configuration.

    Returns
    -------
    Decomposition
        Table 2.
    """
    fs, j, m = sweep.fs, config.bias_level, split_level_m(config)
    return Decomposition(
        original=split_band_coefficients(sweep["output"], fs, m),
        bias=split_band_coefficients(units.deg_per_h(dec.approx(j)), fs, m),
        drift_noise=split_band_coefficients(units.deg_per_h(dec.detail_sum(j)), fs, m),
    )


def bias_model_scores(bm: BiasModels) -> BiasModelScores:
    """MSE of each model against its training targets (the paper's measure) and against the true bias.

    Parameters
    ----------
    bm : BiasModels
        The fitted models.

    Returns
    -------
    BiasModelScores
        Their MSEs.
    """
    pr, pl = np.asarray(bm.rbf(bm.f_bins), float), bm.ls(bm.f_bins)
    return BiasModelScores(
        rbf_vs_target=float(np.mean((pr - bm.y_bins) ** 2)),
        ls_vs_target=float(np.mean((pl - bm.y_bins) ** 2)),
        rbf_vs_truth=float(np.mean((pr - bm.truth_bins) ** 2)),
        ls_vs_truth=float(np.mean((pl - bm.truth_bins) ** 2)),
        target_vs_truth=float(np.mean((bm.y_bins - bm.truth_bins) ** 2)),
        rbf_neurons=int(bm.rbf_neurons),
        n_bins=int(bm.f_bins.size),
        training_range_hz=(float(bm.f_bins[0]), float(bm.f_bins[-1])),
        peak_bias_frequency_hz=float(bm.f_bins[int(np.argmax(np.abs(bm.y_bins)))]),
        true_peak_bias_frequency_hz=float(bm.f_bins[int(np.argmax(np.abs(bm.truth_bins)))]),
    )


def compensated(
    fixed: Recording, dec: MultiscaleDecomposition, bm: BiasModels, config: Config
) -> dict[str, np.ndarray]:
    """Original, denoised (a_j) and RBF-/LS-compensated 500 Hz record [deg/h].

    Parameters
    ----------
    fixed : Recording
        The fixed-frequency record.
    dec : MultiscaleDecomposition
        Its decomposition.
    bm : BiasModels
        The bias models.
    config : Config
        The configuration.

    Returns
    -------
    dict of str to ndarray
        ``original``, ``denoised``, ``rbf``, ``ls`` [deg/h].
    """
    on = fixed["shaker_on"] > 0.5
    den = dec.approx(config.bias_level)
    f = fixed["shaker_frequency"]
    lo, hi = float(bm.f_bins[0]), float(bm.f_bins[-1])
    return {
        "original": units.to_deg_per_h(fixed["output"]),
        "denoised": den,
        "rbf": den - predict_on(bm.rbf, f, on, lo, hi),
        "ls": den - predict_on(bm.ls, f, on, lo, hi),
    }


def _phase_index(fixed: Recording, config: Config) -> tuple[np.ndarray, np.ndarray]:
    """Per sample: phase 0/1/2 (before, during, after the shaker runs) and whether it is steady.

    Steady = at least ``guard_s`` from every switching edge and from both ends of the record
    (where the wavelet approximation has boundary artefacts).
    """
    on = fixed["shaker_on"] > 0.5
    idx = np.zeros(len(on), dtype=np.int8)
    if on.any():
        first, last = int(np.argmax(on)), len(on) - int(np.argmax(on[::-1]))
        idx[first:last], idx[last:] = 1, 2
    steady = ~_near_edges(on, fixed.fs, config.guard_s)
    g = int(round(config.guard_s * fixed.fs))
    steady[:g], steady[len(steady) - g :] = False, False
    return idx, steady


def edge_spike_ratio(
    x: np.ndarray, on: np.ndarray, idx: np.ndarray, steady: np.ndarray, w: int
) -> float:
    """How far the on/off edges of a compensated record stand out of its steady vibration phase.

    dev = |x - median of the steady part of the sample's phase|. For each switching edge e,
    the largest dev in [e - w, e + w); the reference is the 95th percentile of the largest dev
    in consecutive windows of the same length 2w of the steady vibration phase. Returns the
    smaller of the edges' ratios (> 1: every edge exceeds 95 % of equally long steady windows);
    NaN when the record has no edge or no full steady window.

    Parameters
    ----------
    x : ndarray
        A compensated record [deg/h].
    on : ndarray of bool
        Where the shaker runs.
    idx : ndarray of int
        Each sample's phase index.
    steady : ndarray of bool
        The steady samples of each phase.
    w : int
        Half-width of an edge window [samples].

    Returns
    -------
    float
        The largest edge deviation over the steady reference [-].
    """
    level = np.array(
        [
            np.median(x[steady & (idx == p)]) if (steady & (idx == p)).any() else np.nan
            for p in range(3)
        ]
    )
    dev = np.abs(x - level[idx])
    edges = np.flatnonzero(np.diff(on.astype(np.int8))) + 1
    vib = dev[steady & (idx == 1)]
    n_win = vib.size // (2 * w)
    if edges.size == 0 or n_win < 1:
        return math.nan
    ref = float(np.percentile(vib[: n_win * 2 * w].reshape(n_win, 2 * w).max(axis=1), 95))
    return float(min(np.max(dev[max(0, e - w) : e + w]) for e in edges) / ref)


def edges_and_offsets(sig: Mapping[str, np.ndarray], fixed: Recording, config: Config) -> Offsets:
    """Figures 7-8 in numbers: bias offsets during vibration, their scatter, spikes at the edges.

    offset_x = mean over the steady vibration phase minus mean over the steady phase 1 of
    signal x [deg/h]; scatter = std of ``offset_block_s`` block means of the original's steady
    phase 1 [deg/h]; spike ratio: :func:`edge_spike_ratio` of the RBF-compensated record with
    half-window ``edge_window_s``.

    Parameters
    ----------
    sig : mapping of str to ndarray
        The compensated signals (:func:`compensated`).
    fixed : Recording
        The fixed-frequency record.
    config : Config
        The configuration.

    Returns
    -------
    Offsets
        The offsets, scatter and edge spikes.
    """
    idx, steady = _phase_index(fixed, config)
    s1, s2 = steady & (idx == 0), steady & (idx == 1)
    out: dict[str, float] = {}
    for k in ("denoised", "rbf", "ls"):
        out[f"offset_{k}"] = (
            float(np.mean(sig[k][s2]) - np.mean(sig[k][s1])) if s1.any() and s2.any() else math.nan
        )
    kb = max(1, int(round(config.offset_block_s * fixed.fs)))
    blocks = block_means(sig["original"][s1], kb)
    out["static_scatter"] = float(np.std(blocks, ddof=1)) if blocks.size > 2 else math.nan
    out["edge_spike_ratio"] = edge_spike_ratio(
        sig["rbf"],
        fixed["shaker_on"] > 0.5,
        idx,
        steady,
        max(1, int(round(config.edge_window_s * fixed.fs))),
    )
    vb = units.to_deg_per_h(fixed["detail/vibration_bias"])
    for k in (
        "rbf",
        "ls",
    ):  # diagnostic: mean of (model bias - true vibration bias) over the steady vibration
        out[f"residual_vs_truth_{k}"] = (
            float(np.mean((sig["denoised"] - sig[k])[s2] - vb[s2])) if s2.any() else math.nan
        )
    out["true_bias_steady"] = float(np.mean(vb[s2])) if s2.any() else math.nan
    return Offsets(**out)

