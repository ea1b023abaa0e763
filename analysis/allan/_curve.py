"""The Allan-family deviation curve with its confidence band, and the noise identification."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.analysis.allan._blas import _single_blas
from gyrobench.analysis.allan._checks import _check_fs, _check_rate
from gyrobench.analysis.allan._kinds import STATISTICS, Statistic, _check_kind, _edf
from gyrobench.analysis.allan._noise_id import _identify
from gyrobench.analysis.allan._octave import _deviation_overlapping, _octave_overlapping, _phase
from gyrobench.analysis.allan._results import AllanCurve
from gyrobench.analysis.allan._taus import _resolve_m


def _deviation_allantools(kind: str, y: NDArray[np.float64], fs: float, ms: NDArray[np.int64]) -> NDArray[np.float64]:
    """The ``kind`` deviation at m = ``ms`` by its allantools function (:attr:`Statistic.allantools`)."""
    import allantools

    name = STATISTICS[kind].allantools
    assert name is not None  # only kinds that allantools computes come here
    taus, dev, _, ns = getattr(allantools, name)(y, rate=fs, data_type="freq", taus=ms / fs)
    got = np.rint(np.asarray(taus) * fs).astype(np.int64)
    if not np.array_equal(got, ms):  # allantools drops taus with < 2 terms; _resolve_m prevents that
        raise RuntimeError(f"allantools returned m = {got} for requested m = {ms}")
    return np.asarray(dev, dtype=float)



def deviation_bounds(dev: NDArray[np.float64], edf: NDArray[np.float64], confidence: float):
    """(low, high): two-sided ``confidence`` bounds of Allan-family deviations ``dev`` with ``edf``
    equivalent degrees of freedom, from the chi-square law (NIST SP 1065 eq. 45;
    allantools.ci.confidence_interval, vectorised)."""
    from gyrobench.analysis.allan._chi2 import gammaincinv_pq  # numpy only: no scipy.special import

    p = (1.0 - confidence) / 2.0
    edf = np.asarray(edf, dtype=float)
    # both quantiles in one solve: chi2_isf(p, edf) (upper tail) then chi2_ppf(p, edf)
    half = np.concatenate((edf.ravel(), edf.ravel())) / 2.0
    upper = np.repeat([True, False], edf.size)
    q = 2.0 * gammaincinv_pq(half, p, upper=upper)
    lo = dev * np.sqrt(edf / q[: edf.size].reshape(edf.shape))
    hi = dev * np.sqrt(edf / q[edf.size :].reshape(edf.shape))
    return lo, hi


def identify_noise(
    rate: ArrayLike, fs: float, taus: Any = "octave", *, kind: str = "overlapping"
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Dominant power-law noise type at each tau by the lag-1 autocorrelation method.

    Parameters
    ----------
    rate : array_like
        Rate samples [any unit].
    fs : float
        Sample rate [Hz].
    taus : str or array_like
        As in :func:`allan_deviation`.
    kind : str
        Statistic the identification serves (sets the maximum number of differences and the
        valid range of alpha).

    Returns
    -------
    tau : ndarray
        Cluster times [s].
    alpha : ndarray of int
        Exponent of S_y(f) ~ f^alpha: +2 white phase (quantization), 0 white rate (ARW),
        -1 flicker rate (bias instability), -2 random-walk rate (RRW).

    Notes
    -----
    The algorithm is allantools.ci.autocorr_noise_id for frequency data (Riley & Greenhall
    2004): average the rate over non-overlapping blocks of m samples, remove a line, and
    difference until the lag-1 autocorrelation r1 gives rho = r1/(1+r1) < 0.25 (at most
    dmax = 2 times, 3 for Hadamard); alpha = -round(2 rho) - 2 d. Differences from
    allantools: vectorised (allantools loops in Python), block means taken from the
    integrated rate, and at most the first 65536 block means are used (the standard error
    of r1 is then ~1/256 = 0.004, far inside the 0.25 decision margin). Where fewer than
    30 block means exist the alpha of the nearest shorter tau is carried over (Stable32
    switches to the B1 ratio there; carrying keeps the edf monotone). alpha is clipped to
    [-2, 2] (Allan, total) or [-4, 2] (Hadamard), the range the edf formulas accept.
    """
    y = _check_rate(rate)
    fs = _check_fs(fs)
    _check_kind(kind)
    ms = _resolve_m(taus, fs, y.size, kind)
    return ms / fs, _identify(_phase(y), ms, kind)


# ---------------------------------------------------------------------------------- public: curve
@_single_blas
def allan_deviation(
    rate: ArrayLike,
    fs: float,
    *,
    taus: str | ArrayLike = "octave",
    kind: str = "overlapping",
    confidence: float = 0.683,
    alpha: int | ArrayLike | None = None,
) -> AllanCurve:
    """Allan-family deviation of rate samples with confidence bounds.

    Parameters
    ----------
    rate : array_like, shape (n,)
        Rate samples y_k [any unit u], one every 1/fs. A constant offset is irrelevant.
    fs : float
        Sample rate [Hz], > 0.
    taus : {"octave", "decade", "all"} or array_like
        Cluster times. "octave": m = 1, 2, 4, ...; "decade": m = 1, 2, 4, 10, 20, 40, ...;
        "all": every m. Automatic lists stop at m <= n / r with Stable32's stop ratio r
        (4 overlapping, modified and overlapping Hadamard; 5 standard and Hadamard; 2 total),
        i.e. tau <= T/4 for the default. An array gives tau [s], each a multiple of 1/fs,
        with at least 2 terms each (total: tau <= T/2).
    kind : str
        "overlapping" (default, NIST SP 1065 eq. 11), "standard" (eq. 7), "modified"
        (eq. 14), "hadamard" (eq. 18), "overlapping_hadamard" (eq. 20), "total" (eq. 25,
        without bias correction, as allantools).
    confidence : float
        Two-sided confidence level of the bounds, in (0, 1); 0.683 = one sigma.
    alpha : int, array_like of int, or None
        Power-law noise exponent (S_y ~ f^alpha) at each tau for the edf: +2 quantization,
        0 ARW, -1 bias instability, -2 RRW. None (default) identifies it from the data
        by the lag-1 autocorrelation (:func:`identify_noise`).

    Returns
    -------
    AllanCurve

    Raises
    ------
    ValueError
        Non-finite samples (the first bad index is named), fs <= 0, unknown ``kind`` or
        ``taus`` string, a tau that is not a multiple of 1/fs or needs more samples.

    Notes
    -----
    With phase x_k = sum_{i<k} (y_i - ybar) (the integrated rate), the overlapping AVAR is

        sigma^2(m tau0) = 1 / (2 m^2 (n + 1 - 2m)) sum_k (x_{k+2m} - 2 x_{k+m} + x_k)^2

    (here x in rate*samples, so no tau0). At octave taus (m = 2^j, the default) it is
    computed without the cumulative sum: with S_m[k] = x_{k+m} - x_k the moving sum of m
    rates, the second difference is S_m[k+m] - S_m[k] and S_2m[k] = S_m[k] + S_m[k+m], so one
    float64 array of n moving sums is updated in place (which also avoids the phase's
    cancellation on long drifting records); the first 12 octaves take one pass over the
    data, block by block in cache, and each later pass does two octaves. Above 3.4e7
    samples the octaves from m = 4096 on run by residue groups of k mod 4096 instead, each
    group carried through all of them and dropped (n/16 floats per thread; see
    ``_later_streamed``), so memory is the input plus ~n/8 floats. Other taus use one
    blockwise pass per tau over the float64 cumulative sum (one n-array plus a few MB of
    buffers). It agrees with allantools.oadev(data_type="freq") to rounding (a test pins
    1e-9 relative). The other statistics call allantools (adev, mdev, hdev, ohdev, totdev).

    A constant rate (zero variance, e.g. an all-zero record) is legal input: its deviation
    is 0 at every tau (and so are the bounds; alpha is reported as 0). :func:`fit_noise`
    rejects such a curve.

    Bounds: edf from Greenhall & Riley for the Allan and Hadamard kinds (computed here,
    equal to allantools.ci.edf_greenhall to 1e-12; for alpha = -4 Hadamard, where allantools'
    table lookup fails, from the paper's Table 2 row), allantools.ci.edf_greenhall for the
    modified kind, NIST SP 1065 Table 7 (allantools.ci.edf_totdev) for total;
    then sigma^2 edf / chi2_{1-p/2}(edf) <= sigma_true^2 <= sigma^2 edf / chi2_{p/2}(edf)
    (NIST SP 1065 eq. 45).

    Examples
    --------
    >>> import numpy as np
    >>> y = np.random.default_rng(0).standard_normal(4096)
    >>> c = allan_deviation(y, fs=1.0)
    >>> [int(m) for m in c.m]
    [1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024]
    >>> bool(abs(c.deviation[0] - 1.0) < 0.05)
    True
    """
    y = _check_rate(rate)
    fs = _check_fs(fs)
    stat = _check_kind(kind)
    _check_confidence(confidence)
    n = y.size
    if n < 2:
        raise ValueError(f"rate has too few samples: need at least 2; got {n}")
    ms = _resolve_m(taus, fs, n, kind)
    dev, al = _deviation(stat, y, fs, ms, identify=alpha is None)
    if alpha is not None:
        al = _given_alpha(stat, alpha, ms)
    assert al is not None  # identified above, or given as alpha
    edf = _edf(kind, al, ms, n)
    low, high = deviation_bounds(dev, edf, float(confidence))
    return AllanCurve(
        tau=ms / fs,
        deviation=dev,
        low=low,
        high=high,
        n_terms=stat.n_terms(n, ms),
        edf=edf,
        kind=kind,
        confidence=float(confidence),
        fs=fs,
        n_samples=n,
        alpha=np.array(al, dtype=np.int64),
    )


def _check_confidence(confidence: Any) -> None:
    if isinstance(confidence, bool) or not isinstance(confidence, (int, float, np.floating)):
        raise TypeError(f"confidence must be a real number in (0, 1); got {confidence!r}")
    if not (0.0 < float(confidence) < 1.0):
        raise ValueError(f"confidence must be in (0, 1); got {confidence!r}")


def _deviation(
    stat: Statistic, y: NDArray[np.float64], fs: float, ms: NDArray[np.int64], *, identify: bool
) -> tuple[NDArray[np.float64], NDArray[np.int64] | None]:
    """The deviation of ``stat`` at m = ``ms`` and, when ``identify``, the noise type alpha at each m."""
    computed_here = stat.allantools is None  # the overlapping kind
    if computed_here and np.all((ms & (ms - 1)) == 0):  # powers of two: in-place recursion
        return _octave_overlapping(y, ms, identify=identify)
    x = _phase(y) if (computed_here or identify) else None
    if computed_here:
        assert x is not None
        dev = _deviation_overlapping(x, ms)
    else:
        dev = _deviation_allantools(stat.name, y, fs, ms)
    al = None
    if identify:
        assert x is not None
        al = _identify(x, ms, stat.name)
    del x
    return dev, al


def _given_alpha(stat: Statistic, alpha: int | ArrayLike, ms: NDArray[np.int64]) -> NDArray[np.int64]:
    """The user's noise exponents broadcast to the taus, checked against the edf formulas' range."""
    al = np.broadcast_to(np.asarray(alpha), ms.shape).astype(np.int64)
    lo = stat.alpha_min
    if np.any((al < lo) | (al > 2)):
        raise ValueError(f"alpha must be integers in [{lo}, 2] for the {stat.name} deviation; got {alpha!r}")
    return al
