"""Paper 000's figures (matplotlib, Agg): drawn from one unit's :class:`~.results.FigureData` only."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from .config import Config
from .results import CompensationTraces, ModelTraces, MultiscaleTraces, RecordTraces, SplitTraces

__all__ = [
    "fig_compensation",
    "fig_models",
    "fig_multiscale",
    "fig_records",
    "fig_spectrum_cwt",
    "fig_split",
]


def fig_records(d: RecordTraces, config: Config) -> Any:
    """Figure 1: both records (block means), static -> vibration -> static.

    Parameters
    ----------
    d : RecordTraces
        The traces.
    config : Config
        The configuration.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.0, 5.0))
    for i, (key, title) in enumerate(
        (
            ("sweep", f"(a) sweep {config.sweep_start_hz:g}-{config.sweep_end_hz:g} Hz"),
            ("fixed", f"(b) fixed {config.fixed_hz:g} Hz"),
        )
    ):
        ax = fig.add_subplot(2, 1, i + 1)
        ax.plot(d.t, getattr(d, key), lw=0.6)
        ax.set_ylabel("rate [deg/h]")
        ax.set_title(title, fontsize=9)
    ax.set_xlabel("time [s]")
    fig.tight_layout()
    return fig


def fig_spectrum_cwt(rate_deg_h: NDArray[np.float32], fs: float) -> Any:
    """Figure 2: FFT amplitude spectrum and continuous-wavelet map of a record [deg/h] at ``fs`` [Hz].

    Parameters
    ----------
    rate_deg_h : ndarray
        The record [deg/h].
    fs : float
        Its sample rate [Hz].

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    from matplotlib.figure import Figure

    from gyrobench.analysis.wavelet import amplitude_spectrum, cwt_map

    y = np.asarray(rate_deg_h, dtype=float)
    f, a = amplitude_spectrum(y, fs)
    tf = cwt_map(y, fs, n_frequencies=32, f_min=0.5)
    fig = Figure(figsize=(8.0, 6.0))
    ax1 = fig.add_subplot(2, 1, 1)
    ax1.semilogy(f[1:], a[1:], lw=0.4)
    ax1.set_xlabel("frequency [Hz]")
    ax1.set_ylabel("amplitude [deg/h]")
    ax1.set_title("(a) FFT amplitude spectrum: no time information", fontsize=9)
    ax2 = fig.add_subplot(2, 1, 2)
    rel = tf.magnitude / np.median(
        tf.magnitude, axis=1, keepdims=True
    )  # each frequency against its median
    pc = ax2.pcolormesh(
        tf.time, tf.frequency, 20 * np.log10(rel + 1e-12), shading="nearest", cmap="viridis"
    )
    ax2.set_yscale("log")
    ax2.set_xlabel("time [s]")
    ax2.set_ylabel("pseudo-frequency [Hz]")
    ax2.set_title(
        "(c) continuous wavelet transform (complex Morlet): |W| against its median at each frequency; "
        "EMD panel omitted",
        fontsize=9,
    )
    fig.colorbar(pc, ax=ax2, label="[dB]")
    fig.tight_layout()
    return fig


def fig_multiscale(d: MultiscaleTraces, config: Config) -> Any:
    """Figure 3: the sweep's deepest approximation and the rms envelope of each detail.

    Parameters
    ----------
    d : MultiscaleTraces
        The traces.
    config : Config
        The configuration.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.0, 8.0))
    ax = fig.add_subplot()
    t = d.t
    rows = [(f"a{config.level}", d.a)] + [
        (f"d{j}", d.d_rms[j - 1]) for j in range(config.level, 0, -1)
    ]
    for i, (label, x) in enumerate(rows):
        xb = x - np.median(x)
        span = np.ptp(xb) or 1.0
        ax.plot(t, i + 0.8 * xb / span, lw=0.6)
        ax.text(t[-1] * 1.01, i, label, fontsize=8, va="center")
    ax.set_yticks([])
    ax.set_xlabel("time [s]")
    ax.set_title(
        f"Sweep record, db4 {config.level}-level Mallat decomposition: a{config.level} and rms envelope "
        "of each detail (each trace scaled to its own range)",
        fontsize=9,
    )
    fig.tight_layout()
    return fig


def fig_split(d: SplitTraces, config: Config) -> Any:
    """Figure 4: the approximations (bias) and reconstructed details of the sweep.

    Parameters
    ----------
    d : SplitTraces
        The traces.
    config : Config
        The configuration.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.0, 7.0))
    j = config.bias_level
    traces = [
        (f"a{config.train_level} (trained on)", d.t_mean, d.a_train),
        (f"a{j} (bias)", d.t_mean, d.a_bias),
        (f"d{j}", d.t_sample, d.d_j),
        ("d1", d.t_sample, d.d1),
        (f"d = d1+...+d{j}", d.t_sample, d.d),
    ]
    for i, (label, t, x) in enumerate(traces):
        ax = fig.add_subplot(len(traces), 1, i + 1)
        ax.plot(t, x, lw=0.5 if label.startswith("a") else 0.3)
        ax.set_ylabel(label, fontsize=8)
        if i < len(traces) - 1:
            ax.set_xticklabels([])
    ax.set_xlabel("time [s]")
    fig.suptitle(
        "Sweep record: low-frequency approximations (bias) and reconstructed details [deg/h]",
        fontsize=9,
    )
    fig.tight_layout()
    return fig


def fig_models(d: ModelTraces, neurons: int, config: Config) -> Any:
    """Figure 6: the RBF and LS bias models against vibration frequency.

    Parameters
    ----------
    d : ModelTraces
        The traces.
    neurons : int
        The RBF network's size, for the legend.
    config : Config
        The configuration.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.0, 4.8))
    ax = fig.add_subplot()
    ax.plot(
        d.f_bins,
        d.y_bins,
        ".",
        ms=2.5,
        color="tab:blue",
        label=f"a{config.train_level} bias (1 Hz bins)",
    )
    ax.plot(d.f_bins, d.truth_bins, "k--", lw=0.8, label="true rectified bias")
    ax.plot(
        d.ff,
        d.rbf,
        color="tab:red",
        lw=1,
        label=f"RBF ({config.rbf_centres} centres, {neurons} neurons)",
    )
    ax.plot(d.ff, d.ls, color="tab:green", lw=1.2, label=f"{config.ls_order}th-order LS")
    ax.set_xlabel("vibration frequency [Hz]")
    ax.set_ylabel("bias [deg/h]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(
        "Bias against vibration frequency: RBF network vs least-squares polynomial", fontsize=9
    )
    return fig


def fig_compensation(d: CompensationTraces, config: Config) -> Any:
    """Figures 7-8: denoising and bias compensation of the fixed-frequency record.

    Parameters
    ----------
    d : CompensationTraces
        The traces.
    config : Config
        The configuration.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.0, 6.5))
    ax = fig.add_subplot(2, 1, 1)
    ax.plot(d.t, d.original, lw=0.3, color="tab:blue", label="original")
    ax.plot(
        d.t, d.denoised, lw=0.8, color="tab:red", label=f"denoised (a{config.bias_level})"
    )
    ax.set_ylabel("rate [deg/h]")
    ax.legend(fontsize=8)
    ax.set_title(
        f"Fig. 7: {config.fixed_hz:g} Hz record, original and after removing drift + noise",
        fontsize=9,
    )
    ax2 = fig.add_subplot(2, 1, 2)
    ax2.plot(d.t, d.denoised, lw=0.8, color="tab:blue", label="denoised (bias error)")
    ax2.plot(d.t, d.rbf, lw=0.8, color="tab:red", label="RBF-compensated")
    ax2.plot(d.t, d.ls, lw=0.8, color="tab:green", alpha=0.8, label="LS-compensated")
    ax2.set_xlabel("time [s]")
    ax2.set_ylabel("rate [deg/h]")
    ax2.legend(fontsize=8)
    ax2.set_title("Fig. 8: bias compensation during vibration", fontsize=9)
    fig.tight_layout()
    return fig

