"""The Allan-family statistics, one record each: formula, term count, tau limits, edf, fit constants.

Adding a statistic is one :class:`Statistic` entry in :data:`STATISTICS`: everything that
depends on the kind (the estimator, the number of terms, the largest m, the automatic tau
list's stop ratio, the edf, the noise-identification range and, for the statistics the
noise fit accepts, the constants of its ramp cross term) is read from the record.

References
----------
W. J. Riley, "Handbook of Frequency Stability Analysis", NIST SP 1065 (2008);
C. A. Greenhall and W. J. Riley, "Uncertainty of stability variances based on finite
differences", PTTI 2003; W. J. Riley, "The evolution of frequency stability analysis
software" (Stable32 stop ratios, Table III).
"""

from __future__ import annotations

import functools
import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gyrobench.analysis.allan._edf import _edf_greenhall, _edf_greenhall_many, _edf_stein


def _distinct(a: NDArray[Any]) -> NDArray[Any]:
    """The sorted distinct values of integer array ``a`` (flattened): ``numpy.unique(a)`` without numpy.ma.

    numpy 2's plain ``unique`` asks ``numpy.ma.is_masked``, which imports numpy.ma (~10 ms CPU) on
    a process's first call, a third of a whole 2e5-sample curve.
    """
    s = np.sort(np.asarray(a).ravel())
    return s[np.concatenate(([True], s[1:] != s[:-1]))] if s.size else s

__all__ = ["KINDS", "STATISTICS", "FitConstants", "Statistic"]


@dataclass(frozen=True, slots=True, kw_only=True)
class FitConstants:
    """What :func:`gyrobench.analysis.allan.fit_noise` needs of a statistic it can fit.

    The ramp x noise cross term (see ``_covariance._ramp_cross_sd``): the variance of the
    difference of the two end window averages of the rate a lag L apart is, per noise term
    (C the AVAR coefficients), (4/3) C_Q / tau^2 (/ m when ``q_per_m``), ``n_factor`` C_N / tau,
    (C_B / ln 2) (ln(L/tau) + ``flicker_end_c``) and 3 C_K (L - ``k_offset`` tau).

    Attributes
    ----------
    lag : callable
        (n, m, tau) -> L [s], the lag between the end windows (before the floor L >= tau).
    q_per_m : bool
        Whether the quantization variance is divided by m (overlapping windows).
    n_factor : float
        White-noise factor: 4/3 (triangular 2-tau window) or 2 (tau box).
    k_offset : float
        Random-walk offset: 7/15 (triangular window) or 1/3 (box).
    flicker_end_c : float
        c in Var = (2 B^2/pi)(ln(L/tau) + c) for flicker rate averaged by the window (L >> tau):
        c = 2 Int_0^inf sin^2(lam u) w(u)/u du - ln lam for lam -> inf, w = sinc^4 or sinc^2
        (evaluated numerically; the box value is 3/2 to 7 digits).
    finite_record : bool
        Whether the point correlations get the exact finite-record and quantization-kurtosis
        corrections (``_covariance._finite_record_delta``, derived for the overlapping AVAR).
    """

    lag: Callable[[int, NDArray[np.float64], NDArray[np.float64]], NDArray[np.float64]]
    q_per_m: bool
    n_factor: float
    k_offset: float
    flicker_end_c: float
    finite_record: bool


@dataclass(frozen=True, slots=True, kw_only=True)
class Statistic:
    """One Allan-family statistic of n rate samples (n + 1 phase points).

    Attributes
    ----------
    name : str
        The ``kind`` name.
    formula : str
        Where the estimator is defined (NIST SP 1065 equation).
    differences : int
        d, the order of the phase difference (2 Allan, 3 Hadamard).
    stop_ratio : int
        Stable32 stop ratio: automatic tau lists stop at m <= n / ratio.
    n_terms : callable
        (n, m) -> number of terms (differences) each estimate averages, as allantools and
        Stable32 count them.
    max_m : callable
        n -> largest m with at least 2 terms (closed form of n_terms(n, m) >= 2; a test checks).
    samples_needed : callable
        m -> about how many samples a tau of m samples needs (for the refusal message).
    allantools : str or None
        allantools function computing the deviation; None: computed here (overlapping).
    edf : callable
        (alpha, m, n) -> equivalent degrees of freedom; may raise or return nan where the
        formula has no value (then, with ``edf_fallback``, Stein's approximation or the term
        count is used).
    edf_fallback : bool
        Whether a missing edf falls back (False: the formula's value is used as it is).
    edf_many : callable or None
        (alpha, ms, n) -> the edf at every m of ``ms`` at once, nan where ``edf`` would raise or
        has no value (those entries then go through ``edf`` and its fallback); None: ``edf``
        one m at a time.
    fit : FitConstants or None
        For statistics :func:`gyrobench.analysis.allan.fit_noise` accepts (an Allan variance);
        None for the others.
    """

    name: str
    formula: str
    differences: int
    stop_ratio: int
    n_terms: Callable[[int, NDArray[np.int64]], NDArray[np.int64]]
    max_m: Callable[[int], int]
    samples_needed: Callable[[int], int]
    allantools: str | None
    edf: Callable[[int, int, int], float]
    edf_fallback: bool = True
    edf_many: Callable[[int, NDArray[np.int64], int], NDArray[np.float64]] | None = None
    fit: FitConstants | None = None

    @property
    def alpha_min(self) -> int:
        """Smallest noise exponent alpha the edf formulas accept: -2 (Allan, total), -4 (Hadamard)."""
        return -4 if self.differences == 3 else -2

    @property
    def noise_id_dmax(self) -> int:
        """Largest number of differences of the lag-1 ACF noise identification: 2, 3 for Hadamard."""
        return 3 if self.differences == 3 else 2


def _greenhall(d: int, overlapping: bool) -> Callable[[int, int, int], float]:
    """Greenhall-Riley edf of an unmodified Allan (d = 2) or Hadamard (d = 3) variance, computed here."""

    def edf(alpha: int, m: int, n: int) -> float:
        return _edf_greenhall(int(alpha), d, int(m), n + 1, overlapping)

    return edf


def _greenhall_many(d: int, overlapping: bool) -> Callable[[int, NDArray[np.int64], int], NDArray[np.float64]]:
    """:func:`_greenhall` at many m at once (:func:`_edf_greenhall_many`; nan where it has no value)."""

    def edf_many(alpha: int, ms: NDArray[np.int64], n: int) -> NDArray[np.float64]:
        return _edf_greenhall_many(int(alpha), d, ms, n + 1, overlapping)

    return edf_many


def _edf_modified(alpha: int, m: int, n: int) -> float:
    """Greenhall-Riley edf of the modified Allan variance (case 1 of the paper; allantools)."""
    from allantools import ci as _atci

    return float(_atci.edf_greenhall(alpha=int(alpha), d=2, m=int(m), N=n + 1, overlapping=True, modified=True))


def _edf_total(alpha: int, m: int, n: int) -> float:
    """edf of the total deviation (NIST SP 1065 Table 7; allantools.ci.edf_totdev)."""
    from allantools import ci as _atci

    return float(_atci.edf_totdev(n, m, alpha))


#: every statistic :func:`gyrobench.analysis.allan.allan_deviation` computes, by kind
STATISTICS: dict[str, Statistic] = {
    s.name: s
    for s in (
        Statistic(
            name="overlapping",
            formula="NIST SP 1065 eq. 11",
            differences=2,
            stop_ratio=4,
            n_terms=lambda n, m: (n + 1) - 2 * m,
            max_m=lambda n: (n - 1) // 2,  # n + 1 - 2m >= 2
            samples_needed=lambda m: m * 2 + 1,
            allantools=None,
            edf=_greenhall(2, True),
            edf_many=_greenhall_many(2, True),
            fit=FitConstants(
                lag=lambda n, m, tau: (n + 1 - 2 * m) * tau / m,
                q_per_m=True,
                n_factor=4.0 / 3.0,
                k_offset=7.0 / 15.0,
                flicker_end_c=1.15914,
                finite_record=True,
            ),
        ),
        Statistic(
            name="standard",
            formula="NIST SP 1065 eq. 7",
            differences=2,
            stop_ratio=5,
            n_terms=lambda n, m: np.maximum(((n + 1) - 2 * m + m - 1) // m, 0),
            max_m=lambda n: n // 3,  # phase points 0, m, 2m, 3m <= n
            samples_needed=lambda m: m * 2 + 1,
            allantools="adev",
            edf=_greenhall(2, False),
            edf_many=_greenhall_many(2, False),
            fit=FitConstants(
                lag=lambda n, m, tau: (np.floor(n / m) - 1.0) * tau,
                q_per_m=False,
                n_factor=2.0,
                k_offset=1.0 / 3.0,
                flicker_end_c=1.5,
                finite_record=False,
            ),
        ),
        Statistic(
            name="modified",
            formula="NIST SP 1065 eq. 14",
            differences=2,
            stop_ratio=4,
            n_terms=lambda n, m: (n + 1) - 3 * m + 1,
            max_m=lambda n: n // 3,  # n + 2 - 3m >= 2
            samples_needed=lambda m: m * 2 + 1,
            allantools="mdev",
            edf=_edf_modified,
        ),
        Statistic(
            name="hadamard",
            formula="NIST SP 1065 eq. 18",
            differences=3,
            stop_ratio=5,
            n_terms=lambda n, m: np.maximum(((n + 1) - 3 * m + m - 1) // m, 0),
            max_m=lambda n: n // 4,  # phase points 0 .. 4m <= n
            samples_needed=lambda m: m * 3 + 1,
            allantools="hdev",
            edf=_greenhall(3, False),
            edf_many=_greenhall_many(3, False),
        ),
        Statistic(
            name="overlapping_hadamard",
            formula="NIST SP 1065 eq. 20",
            differences=3,
            stop_ratio=4,
            n_terms=lambda n, m: (n + 1) - 3 * m,
            max_m=lambda n: (n - 1) // 3,  # n + 1 - 3m >= 2
            samples_needed=lambda m: m * 3 + 1,
            allantools="ohdev",
            edf=_greenhall(3, True),
            edf_many=_greenhall_many(3, True),
        ),
        Statistic(
            name="total",
            formula="NIST SP 1065 eq. 25 (without bias correction, as allantools)",
            differences=2,
            stop_ratio=2,
            n_terms=lambda n, m: np.full_like(m, n - 1),
            max_m=lambda n: n // 2,
            samples_needed=lambda m: m * 2,
            allantools="totdev",
            edf=_edf_total,
            edf_fallback=False,
        ),
    )
}
#: statistics :func:`gyrobench.analysis.allan.allan_deviation` computes
KINDS = tuple(STATISTICS)
#: statistics :func:`gyrobench.analysis.allan.fit_noise` accepts (an Allan variance)
_FIT_KINDS = tuple(s.name for s in STATISTICS.values() if s.fit is not None)


def _check_kind(kind: Any) -> Statistic:
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {KINDS}; got {kind!r}")
    return STATISTICS[kind]


def _n_terms(kind: str, n: int, m: NDArray[np.int64]) -> NDArray[np.int64]:
    """Number of terms each estimate averages, for n rate samples (n + 1 phase points)."""
    return STATISTICS[kind].n_terms(n, m)


def _max_m(kind: str, n: int) -> int:
    """Largest m with at least 2 terms for n rate samples (total deviation: tau <= T/2).

    Closed forms of ``_n_terms(kind, n, m) >= 2`` (a test checks them against the counts).
    """
    return STATISTICS[kind].max_m(n)


@functools.lru_cache(maxsize=4096)
def _edf_one(kind: str, alpha: int, m: int, n: int) -> float:
    """Equivalent degrees of freedom of one estimate (n rate samples, n + 1 phase points)."""
    stat = STATISTICS[kind]
    if not stat.edf_fallback:
        return stat.edf(alpha, m, n)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            e = stat.edf(alpha, m, n)
    except (NotImplementedError, AssertionError, ZeroDivisionError):  # pragma: no cover - tiny records
        e = float("nan")
    if not (math.isfinite(e) and e > 0):
        # Greenhall has no formula for white PM with fewer than d + 1 terms: fall back to Stein's
        # approximation (NIST SP 1065 Table 5) and, failing that, the term count
        e = _edf_stein(n + 1, m, alpha) if stat.differences == 2 else float("nan")
        if not (math.isfinite(e) and e > 0):
            e = float(max(_n_terms(kind, n, np.array([m]))[0], 1))
    return e


def _edf(kind: str, alpha: NDArray[np.int64], ms: NDArray[np.int64], n: int) -> NDArray[np.float64]:
    """Edf of every estimate (alpha[i], ms[i]) of n rate samples; see :func:`_edf_one`.

    Statistics with ``edf_many`` get every m of one alpha in one call (a fit asks for ~80 of
    them: one at a time they cost ~4 ms on a fresh process, the largest first-call cost of a
    fit on a 2e5-sample record); entries it leaves without a value go through :func:`_edf_one`.
    """
    stat = STATISTICS[kind]
    alpha = np.asarray(alpha)
    out = np.empty(ms.size)
    if stat.edf_many is not None and ms.size:
        with np.errstate(all="ignore"):
            for a in _distinct(alpha):
                sel = alpha == a
                out[sel] = stat.edf_many(int(a), ms[sel], n)
        for j in np.flatnonzero(~(np.isfinite(out) & (out > 0))):
            out[j] = _edf_one(kind, int(alpha[j]), int(ms[j]), n)
        return out
    cache: dict[tuple[int, int], float] = {}
    for i, (a, m) in enumerate(zip(alpha, ms, strict=True)):
        key = (int(a), int(m))
        if key not in cache:
            cache[key] = _edf_one(kind, int(a), int(m), n)
        out[i] = cache[key]
    return out
