"""Scores against truth: MSE, RMS, bias stability over averaging blocks, improvement ratios,
and IEEE 952 noise fits of the segments of a record (e.g. static -> vibration -> static)."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.analysis.allan import TERMS, NoiseFit, allan_deviation, fit_noise
from gyrobench.analysis.features import _check_fs, block_means

__all__ = ["mse", "rms", "bias_stability", "improvement_pct", "SegmentFit", "segment_noise_fits"]


def _pair(estimate: ArrayLike, truth: ArrayLike | None) -> NDArray[np.float64]:
    a = np.asarray(estimate, dtype=np.float64)
    if truth is not None:
        b = np.asarray(truth, dtype=np.float64)
        if a.shape != b.shape:
            raise ValueError(
                f"estimate and truth must have the same shape; got {a.shape} and {b.shape}"
            )
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
    (GJB 2426A-2004; docs/physics.md 6.5). For white noise B_s = ADEV(block_s).

    Raises
    ------
    ValueError
        If fewer than two blocks fit in the record.
    """
    f = block_means(rate, fs, block_s=block_s)
    if len(f) < 2:
        raise ValueError(
            f"bias stability needs at least 2 blocks of {block_s} s; the record holds {len(f)}"
        )
    return float(np.std(f, ddof=1))


def improvement_pct(before: float, after: float) -> float:
    """Relative reduction (before - after)/before in percent."""
    if not before > 0:
        raise ValueError(f"before must be > 0; got {before!r}")
    return 100.0 * (before - after) / before


# ---------------------------------------------------------------------------------- segments
@dataclass(frozen=True, slots=True, kw_only=True)
class SegmentFit:
    """The IEEE 952 noise fit of one segment of a record.

    Attributes
    ----------
    name : str
        The segment's key as given to :func:`segment_noise_fits`.
    start, stop : int
        Sample indices: the segment is ``rate[start:stop]``.
    fs : float
        Sample rate [Hz].
    fit : NoiseFit
        Coefficients (each with 68 % and 95 % intervals, or "not identifiable" with a
        one-sided 95 % upper bound) in the units implied by the rate unit
        (:mod:`gyrobench.analysis.allan`), and the fitted curve.
    """

    name: str
    start: int
    stop: int
    fs: float
    fit: NoiseFit

    @property
    def duration(self) -> float:
        """Segment length [s]."""
        return (self.stop - self.start) / self.fs


def _segment_slice(name: str, seg, n: int, fs: float) -> tuple[int, int]:
    """[start, stop) sample indices of a segment given as (t0, t1) [s] or as a boolean mask."""
    arr = np.asarray(seg)
    if arr.dtype == bool:
        if arr.shape != (n,):
            raise ValueError(
                f"segment {name!r}: a mask must have the record's length {n}; got shape {arr.shape}"
            )
        idx = np.flatnonzero(arr)
        if idx.size == 0:
            return 0, 0
        if idx[-1] - idx[0] + 1 != idx.size:
            raise ValueError(
                f"segment {name!r}: the mask must select one contiguous run of samples "
                f"(an Allan variance needs evenly spaced samples); got {idx.size} samples "
                f"spread over [{idx[0]}, {idx[-1]}]"
            )
        return int(idx[0]), int(idx[-1]) + 1
    if arr.shape != (2,) or not np.issubdtype(arr.dtype, np.number):
        raise TypeError(f"segment {name!r} must be (start_s, end_s) or a boolean mask; got {seg!r}")
    t0, t1 = (float(v) for v in arr)
    if not (math.isfinite(t0) and math.isfinite(t1) and 0.0 <= t0 < t1):
        raise ValueError(
            f"segment {name!r} must satisfy 0 <= start < end [s]; got ({t0!r}, {t1!r})"
        )
    a, b = int(round(t0 * fs)), int(round(t1 * fs))
    if b > n:
        raise ValueError(
            f"segment {name!r} ends at {t1!r} s, after the record's end at {n / fs!r} s"
        )
    return a, b


def segment_noise_fits(
    rate: ArrayLike,
    fs: float,
    segments: Mapping[str, tuple[float, float] | ArrayLike]
    | Sequence[tuple[float, float] | ArrayLike],
    *,
    terms: Sequence[str] = TERMS,
    min_m: int = 1,
) -> dict[str, SegmentFit]:
    """Fit the IEEE 952 noise terms to each segment of a rate record separately.

    Parameters
    ----------
    rate : array_like, shape (n,)
        Rate samples [any unit u], one every 1/fs.
    fs : float
        Sample rate [Hz], > 0.
    segments : mapping or sequence
        Each segment as ``(start_s, end_s)`` [s from the first sample; end exclusive] or as
        a boolean mask of length n selecting one contiguous run. A sequence is keyed
        ``"1"``, ``"2"``, ... in order.
    terms : sequence of str
        The terms to fit (:func:`gyrobench.analysis.allan.fit_noise`).
    min_m : int
        Smallest cluster size: the overlapping Allan deviation is taken at the octave
        cluster sizes m = min_m, 2 min_m, 4 min_m, ... <= n_segment / 4 (tau = m/fs).
        Use m >= 2^j for a wavelet approximation A_j, which is smooth below 2^j samples
        by construction.

    Returns
    -------
    dict of str to SegmentFit
        In the order of ``segments``.

    Raises
    ------
    ValueError
        A segment outside the record, a mask that is not one contiguous run, or a segment
        too short for the fit: it needs ``len(terms)`` octave taus between min_m and n/4,
        i.e. ``n >= 4 * min_m * 2**(len(terms) - 1)`` samples (the message names the
        segment, its length and the minimum).
    TypeError
        A segment that is neither a pair of times nor a boolean mask.

    Notes
    -----
    Each segment is fitted on its own samples only (no sample of a neighbouring segment
    enters any cluster): AVAR at tau = m/fs uses the overlapping estimator (NIST SP 1065
    eq. 11) and the joint weighted NNLS fit of :func:`gyrobench.analysis.allan.fit_noise`, whose
    intervals follow from the chi-square statistics of the AVAR points. Cut switching
    transients out by choosing the segment bounds (a guard after each edge).

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> y = np.concatenate([rng.normal(0, 1.0, 4096), rng.normal(0, 3.0, 4096)])
    >>> fits = segment_noise_fits(y, 1.0, [(0, 4096), (4096, 8192)], terms=("N",))
    >>> [round(f.fit.coefficients["N"].value, 1) for f in fits.values()]
    [1.0, 3.0]
    """
    y = np.asarray(rate, dtype=float)
    if y.ndim != 1:
        raise ValueError(f"rate must be 1-D; got shape {y.shape}")
    fs = _check_fs(fs)
    if isinstance(min_m, bool) or not isinstance(min_m, (int, np.integer)) or min_m < 1:
        raise ValueError(f"min_m must be an integer >= 1 sample; got {min_m!r}")
    if isinstance(terms, str):
        terms = (terms,)
    items = (
        list(segments.items())
        if isinstance(segments, Mapping)
        else [(str(i), s) for i, s in enumerate(segments, start=1)]
    )
    if not items:
        raise ValueError("segments must name at least one segment; got none")
    n_min = 4 * int(min_m) * 2 ** (len(tuple(terms)) - 1)
    out: dict[str, SegmentFit] = {}
    for name, seg in items:
        a, b = _segment_slice(str(name), seg, y.size, fs)
        n = b - a
        if n < n_min:
            raise ValueError(
                f"segment {name!r} holds {n} samples ({n / fs:g} s); fitting {len(tuple(terms))} "
                f"terms on octave taus from m = {min_m} to n/4 needs >= {n_min} samples "
                f"({n_min / fs:g} s)"
            )
        ms = [m for m in (int(min_m) * 2**k for k in range(64)) if m <= n // 4]
        curve = allan_deviation(y[a:b], fs, taus=np.array(ms, dtype=float) / fs)
        out[str(name)] = SegmentFit(
            name=str(name), start=a, stop=b, fs=fs, fit=fit_noise(curve, terms=terms)
        )
    return out
