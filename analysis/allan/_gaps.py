"""The overlapping Allan deviation of a record with gaps: each contiguous piece's sums pooled per tau."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.analysis.allan._checks import _check_fs, _check_rate
from gyrobench.analysis.allan._curve import _check_confidence, deviation_bounds
from gyrobench.analysis.allan._kinds import _edf
from gyrobench.analysis.allan._noise_id import _identify
from gyrobench.analysis.allan._octave import _phase
from gyrobench.analysis.allan._results import AllanCurve
from gyrobench.analysis.allan._taus import _resolve_m


def allan_deviation_gaps(
    pieces: Sequence[ArrayLike],
    fs: float,
    *,
    taus: str | ArrayLike = "octave",
    confidence: float = 0.683,
) -> AllanCurve:
    """Overlapping Allan deviation of a record broken by gaps, from its contiguous pieces.

    Parameters
    ----------
    pieces : sequence of array_like
        The contiguous runs of rate samples y_k [any unit u], each sampled every 1/fs, in
        record order; a gap (missing samples) lies between two consecutive pieces. A piece
        shorter than 2m + 1 samples contributes nothing at that m.
    fs : float
        Sample rate [Hz], > 0.
    taus : {"octave", "decade", "all"} or array_like
        As in :func:`allan_deviation`, resolved for the total number of samples n = sum n_j
        (the tau list of the same record without its gaps); a tau at which the pieces hold
        fewer than 2 terms in all is dropped.
    confidence : float
        Two-sided confidence level of the bounds, in (0, 1).

    Returns
    -------
    AllanCurve
        Kind "overlapping"; ``n_terms`` the pooled term counts, ``n_samples`` = n.

    Raises
    ------
    ValueError
        No piece, a piece with non-finite samples, fs <= 0, or no tau with 2 terms.

    Notes
    -----
    With x^(j) the phase (integrated rate, mean of piece j removed) of piece j and
    T_j(m) = n_j + 1 - 2m its number of second differences, the pooled overlapping AVAR is

        sigma^2(m tau0) = sum_j S_j(m) / (2 m^2 sum_j T_j(m)),
        S_j(m) = sum_k (x^(j)_{k+2m} - 2 x^(j)_{k+m} + x^(j)_k)^2,

    the NIST SP 1065 eq. 11 estimator with only the differences that lie inside one piece:
    no difference spans a gap. Each term has the same expectation sigma^2(tau) whatever its
    piece (stationary noise), so the pooled mean is unbiased; with one piece it is eq. 11.
    The edf is the sum of the pieces' Greenhall-Riley edfs (exact for independent pieces,
    a slight overstatement for pieces correlated across a short gap); alpha is identified
    on the longest piece (:func:`identify_noise`), carried to the taus it is too short for.
    The per-piece phase recursion costs one pass over the piece per tau. ``edf_scale`` is the
    pieces' white-noise edf over that of one record of n samples: the fit weights each tau by
    what the pieces long enough for it hold.

    References
    ----------
    NIST SP 1065 (Riley 2008), eq. 11 and sec. 5.2.10 (gaps: "the analysis should be done
    over the contiguous segments"); Greenhall & Riley, PTTI 2003 (edf).

    Examples
    --------
    >>> import numpy as np
    >>> y = np.random.default_rng(0).standard_normal(4096)
    >>> c = allan_deviation_gaps([y[:2000], y[2001:]], fs=1.0)
    >>> bool(abs(c.deviation[0] - 1.0) < 0.05)
    True
    """
    fs = _check_fs(fs)
    _check_confidence(confidence)
    ys = [_check_rate(p) for p in pieces]
    if not ys:
        raise ValueError("pieces must hold at least one contiguous run of samples; got none")
    lengths = np.array([y.size for y in ys], dtype=np.int64)
    n = int(lengths.sum())
    ms = _resolve_m(taus, fs, n, "overlapping")
    terms = np.maximum(lengths[None, :] + 1 - 2 * ms[:, None], 0).sum(axis=1)
    keep = terms >= 2
    if not np.any(keep):
        raise ValueError(
            f"pieces of {lengths.tolist()} samples hold no tau with 2 terms (the longest needs 2m + 1 samples)"
        )
    ms, terms = ms[keep], terms[keep]
    sums = np.zeros(ms.size)
    edf = np.zeros(ms.size)
    white = np.zeros(ms.size)  # the pieces' white-noise edf at each m (for the fit's edf_scale)
    longest = ys[int(np.argmax(lengths))]
    alpha = _alpha(longest, ms)
    for y in ys:
        x = _phase(y)
        ok = ms <= (y.size - 1) // 2  # at least 2 terms in this piece (1 term has no edf)
        for i in np.flatnonzero(ok):
            sums[i] += _second_difference_sum(x, int(ms[i]))
        if np.any(ok):
            edf[ok] += _edf("overlapping", alpha[ok], ms[ok], y.size)
            white[ok] += _edf("overlapping", np.zeros(int(ok.sum()), dtype=np.int64), ms[ok], y.size)
        one = ms == y.size // 2  # exactly one term (n_j = 2m): its sum, 1 degree of freedom
        for i in np.flatnonzero(one & ~ok):
            sums[i] += _second_difference_sum(x, int(ms[i]))
            edf[i] += 1.0
            white[i] += 1.0
    avar = sums / (2.0 * ms.astype(float) ** 2 * terms)
    dev = np.sqrt(avar)
    low, high = deviation_bounds(dev, edf, float(confidence))
    return AllanCurve(
        tau=ms / fs,
        deviation=dev,
        low=low,
        high=high,
        n_terms=terms.astype(np.int64),
        edf=edf,
        kind="overlapping",
        confidence=float(confidence),
        fs=fs,
        n_samples=n,
        alpha=alpha,
        edf_scale=None if len(ys) == 1 else np.minimum(white / _edf("overlapping", np.zeros(ms.size, dtype=np.int64),
                                                                     ms, n), 1.0),
    )


def _second_difference_sum(x: NDArray[np.float64], m: int) -> float:
    """sum_k (x_{k+2m} - 2 x_{k+m} + x_k)^2 over the phase ``x`` (n + 1 points)."""
    d = x[2 * m :] - 2.0 * x[m:-m] + x[: x.size - 2 * m]
    return float(np.dot(d, d))


def _alpha(y: NDArray[np.float64], ms: NDArray[np.int64]) -> NDArray[np.int64]:
    """Noise exponent at each m, identified on ``y`` where it is long enough, else carried from below."""
    fit = ms <= (y.size - 1) // 2
    out = np.zeros(ms.size, dtype=np.int64)
    if np.any(fit):
        out[fit] = _identify(_phase(y), ms[fit], "overlapping")
        last = int(out[fit][-1])
        out[~fit] = last
    return out
