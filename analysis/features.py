"""Regressors computed from logged channels: temperature, its smoothed rate, products, block means.

These are methods for any recording: they take plain arrays and a sample rate.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import signal

__all__ = ["smoothed_derivative", "block_means", "thermal_features"]


def _check_1d(name: str, x: ArrayLike) -> NDArray[np.float64]:
    a = np.asarray(x, dtype=float)
    if a.ndim != 1:
        raise ValueError(f"{name} must be 1-D; got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        bad = int(np.flatnonzero(~np.isfinite(a))[0])
        raise ValueError(f"{name} must be finite; got {a[bad]!r} at index {bad}")
    return a


def _check_fs(fs: float) -> float:
    if isinstance(fs, bool) or not isinstance(fs, (int, float)) or not (math.isfinite(fs) and fs > 0):
        raise ValueError(f"fs must be a finite number > 0 Hz; got {fs!r}")
    return float(fs)


def smoothed_derivative(x: ArrayLike, fs: float, *, window_s: float) -> NDArray[np.float64]:
    """Time derivative of a noisy slow signal by a Savitzky-Golay filter.

    Parameters
    ----------
    x : array_like
        Samples (e.g. temperature [K]).
    fs : float
        Sample rate [Hz].
    window_s : float
        Smoothing window [s]; at least 3 samples, odd number of samples used.

    Returns
    -------
    ndarray
        dx/dt [unit of x per second], same length as ``x``.

    Notes
    -----
    Local quadratic least-squares fit over the window (Savitzky & Golay, Anal.
    Chem. 36(8), 1964), evaluated for the first derivative; edges by fitting the
    first/last window (``mode="interp"``). A pure ramp a + b t returns b exactly.
    """
    a = _check_1d("x", x)
    fs = _check_fs(fs)
    if not (math.isfinite(window_s) and window_s > 0):
        raise ValueError(f"window_s must be > 0 s; got {window_s!r}")
    w = max(5, int(round(window_s * fs)) | 1)
    if w > len(a):
        raise ValueError(f"window_s = {window_s} s spans {w} samples but x has only {len(a)}")
    return signal.savgol_filter(a, w, polyorder=2, deriv=1, delta=1.0 / fs, mode="interp")


def block_means(x: ArrayLike, fs: float, *, block_s: float) -> NDArray[np.float64]:
    """Means of consecutive non-overlapping blocks of ``block_s`` seconds (the incomplete tail is dropped).

    Parameters
    ----------
    x : array_like
        The record (any unit).
    fs : float
        Sample rate [Hz].
    block_s : float
        Block length [s] (rounded to whole samples).

    Returns
    -------
    ndarray
        One mean per complete block, in the unit of ``x``.

    Raises
    ------
    ValueError
        If the record is shorter than one block.
    """
    a = _check_1d("x", x)
    fs = _check_fs(fs)
    m = int(round(block_s * fs))
    if m < 1:
        raise ValueError(f"block_s must span at least one sample at fs = {fs} Hz; got {block_s!r}")
    k = len(a) // m
    if k < 1:
        raise ValueError(f"record of {len(a)} samples is shorter than one block of {m} samples ({block_s} s)")
    return a[: k * m].reshape(k, m).mean(axis=1)


def thermal_features(
    temperature: ArrayLike, fs: float, *, window_s: float = 300.0, product: bool = True
) -> NDArray[np.float64]:
    """The columns (T, dT/dt, T x dT/dt) used by temperature-drift models (paper 003).

    Parameters
    ----------
    temperature : array_like
        Logged temperature [K or degC, as the caller prefers; the model is fitted in it].
    fs : float
        Sample rate [Hz].
    window_s : float
        Smoothing window of the derivative [s].
    product : bool
        Include the T x dT/dt column (the "improved" model); False gives the
        traditional (T, dT/dt) model.

    Returns
    -------
    ndarray, shape (n, 3) or (n, 2)
    """
    t = _check_1d("temperature", temperature)
    dt = smoothed_derivative(t, fs, window_s=window_s)
    cols = [t, dt] + ([t * dt] if product else [])
    return np.column_stack(cols)
