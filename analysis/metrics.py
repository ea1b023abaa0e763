"""Scores against truth: MSE, RMS, bias stability over averaging blocks, improvement ratios."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from analysis.features import block_means

__all__ = ["mse", "rms", "bias_stability", "improvement_pct"]


def _pair(a: ArrayLike, b: ArrayLike | None):
    a = np.asarray(a, dtype=float)
    if b is not None:
        b = np.asarray(b, dtype=float)
        if a.shape != b.shape:
            raise ValueError(f"estimate and truth must have the same shape; got {a.shape} and {b.shape}")
        a = a - b
    if a.size == 0:
        raise ValueError("need at least one sample; got an empty array")
    if not np.all(np.isfinite(a)):
        raise ValueError("values must be finite; got NaN or inf")
    return a


def mse(estimate: ArrayLike, truth: ArrayLike | None = None) -> float:
    """Mean squared error of ``estimate - truth`` (or of ``estimate`` when truth is None)."""
    e = _pair(estimate, truth)
    return float(np.mean(e**2))


def rms(estimate: ArrayLike, truth: ArrayLike | None = None) -> float:
    """Root mean square of ``estimate - truth``."""
    return math.sqrt(mse(estimate, truth))


def bias_stability(rate: ArrayLike, fs: float, *, block_s: float = 100.0) -> float:
    """Bias stability: sample standard deviation (1 sigma, n - 1) of ``block_s`` block means.

    Parameters
    ----------
    rate : array_like
        Gyro output (any unit; the result has the same unit).
    fs : float
        Sample rate [Hz].
    block_s : float
        Averaging time [s] (10 s or 100 s in GJB 2426A practice).

    Notes
    -----
    B_s = sqrt(1/(n-1) sum_i (F_i - Fbar)^2), F_i = mean of block i
    (GJB 2426A-2004; PHYSICS.md 6.5). For white noise B_s = ADEV(block_s).

    Raises
    ------
    ValueError
        If fewer than two blocks fit in the record.
    """
    f = block_means(rate, fs, block_s=block_s)
    if len(f) < 2:
        raise ValueError(f"bias stability needs at least 2 blocks of {block_s} s; the record holds {len(f)}")
    return float(np.std(f, ddof=1))


def improvement_pct(before: float, after: float) -> float:
    """Relative reduction (before - after)/before in percent."""
    if not before > 0:
        raise ValueError(f"before must be > 0; got {before!r}")
    return 100.0 * (before - after) / before
