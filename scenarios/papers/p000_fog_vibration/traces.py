"""Paper 000's figure data: what the report's figures draw of one unit (float32 traces).

Typed frozen dataclasses, one per figure, gathered in :class:`FigureData` (a field of
:class:`~.results.UnitResult`); :mod:`.results` re-exports them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = ["CompensationTraces", "FigureData", "ModelTraces", "MultiscaleTraces", "RecordTraces", "SplitTraces"]

F32 = NDArray[np.float32]


@dataclass(frozen=True, slots=True, kw_only=True)
class RecordTraces:
    """Figure 1: block means [deg/h] of both records at times ``t`` [s].

    Attributes
    ----------
    t : ndarray
        Times [s].
    sweep, fixed : ndarray
        Block means of each record [deg/h].
    """

    t: F32
    sweep: F32
    fixed: F32


@dataclass(frozen=True, slots=True, kw_only=True)
class MultiscaleTraces:
    """Figure 3: the sweep's deepest approximation and each detail's rms envelope [deg/h].

    Attributes
    ----------
    t : ndarray
        Times [s].
    a : ndarray
        The deepest approximation [deg/h].
    d_rms : ndarray
        Each detail's rms envelope [deg/h].
    """

    t: F32
    a: F32
    d_rms: F32  # shape (level, n): row i is detail i + 1


@dataclass(frozen=True, slots=True, kw_only=True)
class SplitTraces:
    """Figure 4: approximations (block means at ``t_mean``) and details (samples at ``t_sample``).

    Attributes
    ----------
    t_mean : ndarray
        Times of the block means [s].
    t_sample : ndarray
        Times of the samples [s].
    a_train : ndarray
        The training approximation [deg/h].
    a_bias : ndarray
        The bias approximation [deg/h].
    d_j : ndarray
        The deepest detail [deg/h].
    d1 : ndarray
        The first detail [deg/h].
    d : ndarray
        The details' sum [deg/h].
    """

    t_mean: F32
    t_sample: F32
    a_train: F32
    a_bias: F32
    d_j: F32
    d1: F32
    d: F32


@dataclass(frozen=True, slots=True, kw_only=True)
class ModelTraces:
    """Figure 6: training bins, true bias there, and both models on the grid ``ff`` [Hz, deg/h].

    Attributes
    ----------
    f_bins : ndarray
        Training bins [Hz].
    y_bins : ndarray
        Their targets [deg/h].
    truth_bins : ndarray
        The true bias there [deg/h].
    ff : ndarray
        The frequency grid [Hz].
    rbf, ls : ndarray
        Both models on the grid [deg/h].
    """

    f_bins: F32
    y_bins: F32
    truth_bins: F32
    ff: F32
    rbf: F32
    ls: F32


@dataclass(frozen=True, slots=True, kw_only=True)
class CompensationTraces:
    """Figures 7-8: every k-th sample [deg/h] of the fixed record at each stage.

    Attributes
    ----------
    t : ndarray
        Times [s].
    original, denoised, rbf, ls : ndarray
        The record at each stage [deg/h].
    """

    t: F32
    original: F32
    denoised: F32
    rbf: F32
    ls: F32


@dataclass(frozen=True, slots=True, kw_only=True)
class FigureData:
    """Everything the report's figures draw (float32).

    Everything the report's figures draw (float32; ``fixed_rate`` is the whole fixed-frequency
    record [deg/h] at ``fs`` [Hz], for figure 2's spectrum and wavelet map).

    Attributes
    ----------
    records : RecordTraces
        Figure 1.
    multiscale : MultiscaleTraces
        Figure 3.
    split : SplitTraces
        Figure 4.
    models : ModelTraces
        Figure 6.
    compensation : CompensationTraces
        Figures 7-8.
    fixed_rate : ndarray
        The whole fixed-frequency record [deg/h] (figure 2).
    fs : float
        Its sample rate [Hz].
    """

    records: RecordTraces
    multiscale: MultiscaleTraces
    split: SplitTraces
    models: ModelTraces
    compensation: CompensationTraces
    fixed_rate: F32
    fs: float
