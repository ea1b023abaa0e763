"""Training pairs from a swept-sine record: means of the signal over drive-frequency bins.

A sine sweep logs the drive frequency beside the gyro output; a bias-versus-frequency model
(RBF network, polynomial) is trained on the output's mean in each frequency bin rather than on
every sample, so each frequency weighs the same whatever the sweep rate (seed paper 000,
Sec. 4: the bias curve of the sweep against its frequency).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["bin_means"]


def bin_means(
    f: ArrayLike, y: ArrayLike, *, lo: float, hi: float, width: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Means of ``f`` and ``y`` over frequency bins [lo, lo + width), ... covering [lo, hi].

    Parameters
    ----------
    f : array_like, shape (n,)
        Drive frequency of each sample [Hz] (any unit; ``lo``, ``hi``, ``width`` in the same).
    y : array_like, shape (n,)
        The signal at each sample (any unit).
    lo, hi : float
        Range the bin edges ``lo, lo + width, ...`` cover (the last edge is the first >= hi);
        samples outside the edges are ignored. Must be finite with ``lo < hi``.
    width : float
        Bin width. Must be finite and > 0.

    Returns
    -------
    f_mean, y_mean : ndarray, shape (n_bins,)
        Mean frequency and mean signal of each kept bin, in increasing frequency.

    Raises
    ------
    ValueError
        If ``f`` and ``y`` are not 1-D of the same length, or ``lo``, ``hi``, ``width`` are
        out of range.

    Notes
    -----
    Empty bins are dropped. A bin holding fewer than half the median count of the non-empty
    bins (a partial bin at the end of the data) is merged into its lower neighbour (the upper
    one for the first bin), so that no training pair rests on a handful of samples. The means
    are sums over counts (``numpy.bincount``), so every sample weighs the same.

    Examples
    --------
    >>> import numpy as np
    >>> f = np.repeat([1.2, 2.5, 3.7], 4)
    >>> fm, ym = bin_means(f, 2.0 * f, lo=1.0, hi=4.0, width=1.0)
    >>> bool(np.allclose(ym, 2.0 * fm))
    True
    """
    f = np.asarray(f, dtype=float)
    y = np.asarray(y, dtype=float)
    if f.ndim != 1 or f.shape != y.shape:
        raise ValueError(f"f and y must be 1-D of the same length; got shapes {f.shape} and {y.shape}")
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise ValueError(f"lo and hi must be finite with lo < hi; got lo={lo!r}, hi={hi!r}")
    if not (math.isfinite(width) and width > 0):
        raise ValueError(f"width must be finite and > 0; got {width!r}")
    edges = np.arange(lo, hi + width, width)
    idx = np.digitize(f, edges) - 1
    ok = (idx >= 0) & (idx < len(edges) - 1)
    cnt = np.bincount(idx[ok], minlength=len(edges) - 1)
    sf = np.bincount(idx[ok], f[ok], minlength=len(edges) - 1)
    sy = np.bincount(idx[ok], y[ok], minlength=len(edges) - 1)
    keep = cnt > 0
    cnt, sf, sy = cnt[keep].astype(float), sf[keep], sy[keep]
    small = np.flatnonzero(cnt < 0.5 * np.median(cnt)) if cnt.size > 1 else np.array([], dtype=int)
    for i in small[::-1]:  # from the top, so indices below stay valid
        j = i - 1 if i > 0 else i + 1
        cnt[j] += cnt[i]
        sf[j] += sf[i]
        sy[j] += sy[i]
        cnt[i] = 0.0
    keep = cnt > 0
    return sf[keep] / cnt[keep], sy[keep] / cnt[keep]
