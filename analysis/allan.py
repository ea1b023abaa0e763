"""Allan-family deviations of rate data, their confidence bounds, and the IEEE 952 noise fit.

Everything here works on plain arrays of rate samples in any unit ``u`` (deg/s, rad/s,
fractional frequency, ...) taken at ``fs`` [Hz]; results come out in the units implied by
the input. With tau in seconds the fitted IEEE Std 952 coefficients are

====  ==========================  ========  =====================
name  term                        unit      AVAR term
====  ==========================  ========  =====================
Q     quantization                u*s       3 Q^2 / tau^2
N     angle random walk           u*s^0.5   N^2 / tau
B     bias instability            u         (2 ln2/pi) B^2
K     rate random walk            u/s^0.5   K^2 tau / 3
R     rate ramp                   u/s       R^2 tau^2 / 2
====  ==========================  ========  =====================

(so rate in rad/s gives Q in rad, N in rad/sqrt(s), B in rad/s, K in rad/s/sqrt(s),
R in rad/s^2; conversion to field units happens at the edges, see :mod:`gyrobench.sim.units`).

Three layers:

* :func:`allan_deviation` -> :class:`AllanCurve`: overlapping (default), standard
  (non-overlapping), modified, Hadamard, overlapping Hadamard and total deviation with
  confidence bounds from the equivalent degrees of freedom (edf).
* :func:`fit_noise` -> :class:`NoiseFit`: joint weighted non-negative least squares of the
  five IEEE terms on the Allan variance, each coefficient with 68 % and 95 % intervals or
  "not identifiable from this record" with a 95 % upper bound.
* :func:`slope_readoff`: the IEEE 952 graphical method (and the fixed-slope line fits used
  in the literature), for comparison with published numbers.

References
----------
IEEE Std 952-1997, Annex C. W. J. Riley, "Handbook of Frequency Stability Analysis",
NIST SP 1065 (2008). C. A. Greenhall and W. J. Riley, "Uncertainty of stability variances
based on finite differences", PTTI 2003. W. J. Riley and C. A. Greenhall, "Power law noise
identification using the lag 1 autocorrelation", EFTF 2004. A. Wallin et al., allantools.
docs/physics.md section 1.
"""

from __future__ import annotations

import contextlib
import functools
import math
import os
import threading
import warnings
from collections.abc import Callable, Iterator, Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field, replace
from functools import partial
from statistics import NormalDist
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

# allantools, scipy and threadpoolctl are imported where they are used: importing this module
# (and so ``gyrobench allan --help`` or ``gyrobench list``) costs numpy only

__all__ = [
    "KINDS",
    "TAU_CHOICES",
    "TERMS",
    "AllanCurve",
    "Coefficient",
    "FitRange",
    "NoiseFit",
    "fit_range",
    "bandwidth_range",
    "BANDWIDTH_BIAS",
    "QUANTIZATION_KURTOSIS",
    "lowpass_avar_bias",
    "allan_deviation",
    "fit_noise",
    "identify_noise",
    "slope_readoff",
    "avar_to_coefficient",
    "coefficient_to_avar",
]

#: statistics :func:`allan_deviation` computes
KINDS = ("overlapping", "standard", "modified", "hadamard", "overlapping_hadamard", "total")
#: automatic tau lists
TAU_CHOICES = ("octave", "decade", "all")
#: IEEE 952 terms, in order of their AVAR power of tau
TERMS = ("Q", "N", "B", "K", "R")

#: AVAR = C * tau**power for each term
_POWER = {"Q": -2, "N": -1, "B": 0, "K": 1, "R": 2}
#: C = _SCALE * coefficient**2  (docs/physics.md 1.5)
_FLICKER = 2.0 * math.log(2.0) / math.pi  # 0.4413: flicker AVAR plateau / B^2
_SCALE = {"Q": 3.0, "N": 1.0, "B": _FLICKER, "K": 1.0 / 3.0, "R": 0.5}
#: power-law exponent alpha of S_y(f) (frequency-domain, as in NIST SP 1065) of each term,
#: used to pick the edf formula; the ramp is deterministic and treated as random-walk FM
_ALPHA = {"Q": 2, "N": 0, "B": -1, "K": -2, "R": -2}
#: sqrt(2 ln 2 / pi) = 0.6643: ADEV plateau of unit bias instability
FLICKER_FLOOR = math.sqrt(_FLICKER)

#: Stable32 "stop ratio" per statistic: automatic tau lists stop at m <= N / ratio
#: (W. J. Riley, "The evolution of frequency stability analysis software", Table III)
_STOP_RATIO = {
    "overlapping": 4,
    "standard": 5,
    "modified": 4,
    "hadamard": 5,
    "overlapping_hadamard": 4,
    "total": 2,
}
#: number of differences of phase in each statistic (d = 2 Allan, 3 Hadamard)
_D = {"overlapping": 2, "standard": 2, "modified": 2, "hadamard": 3, "overlapping_hadamard": 3, "total": 2}

#: block size of the overlapping estimator (fits in L2 cache) and the chunk of each dot product:
#: OpenBLAS threads ddot above 10000 elements, which costs far more than it gains here
_BLOCK = 1 << 16
_DOT = 8192
#: OpenBLAS runs a gemm on one thread when m n k <= 65536 * GEMM_MULTITHREAD_THRESHOLD (4)
_GEMM_SINGLE = 65536 * 4
#: worker threads of the overlapping estimator (numpy ufuncs and BLAS release the GIL) and
#: the number of terms below which one thread is used
_THREADS = max(1, min(2, os.cpu_count() or 1))
_THREAD_MIN = 1 << 21
#: fused octave passes (see :func:`_octave_overlapping`): octaves of the first pass, octaves
#: per later pass, values of k per block, and the m from which later passes split k by
#: residue class mod m across threads instead of by range (no tail copies)
_FUSE_FIRST = 12
_FUSE_LATER = 2
_FUSE_BLOCK = 1 << 17
_RESIDUE_MIN = 1 << 18
#: noise identification uses at most this many block averages (see :func:`identify_noise`)
_NOISE_ID_MAX = 1 << 16
_NOISE_ID_MIN = 30

_ONE_SIGMA = math.erf(1.0 / math.sqrt(2.0))  # 0.682689...


# ---------------------------------------------------------------------------------- results
@dataclass(frozen=True, slots=True, kw_only=True)
class AllanCurve:
    """An Allan-family deviation curve with its confidence band.

    Attributes
    ----------
    tau : ndarray
        Cluster times [s], tau = m / fs.
    deviation : ndarray
        Deviation [rate unit].
    low, high : ndarray
        Confidence bounds of the deviation at ``confidence`` [rate unit]
        (chi-square with ``edf`` degrees of freedom, NIST SP 1065 eq. 45).
    n_terms : ndarray
        Number of terms (differences) averaged in each estimate, as allantools/Stable32 count them.
    edf : ndarray
        Equivalent degrees of freedom used for the bounds.
    kind : str
        One of :data:`KINDS`.
    confidence : float
        Two-sided confidence level of ``low``/``high`` (e.g. 0.683).
    fs : float
        Sample rate [Hz].
    n_samples : int
        Number of rate samples the curve was computed from.
    alpha : ndarray or None
        Power-law noise exponent alpha (S_y ~ f^alpha) assumed at each tau for the edf.
    """

    tau: NDArray[np.float64]
    deviation: NDArray[np.float64]
    low: NDArray[np.float64]
    high: NDArray[np.float64]
    n_terms: NDArray[np.int64]
    edf: NDArray[np.float64]
    kind: str
    confidence: float
    fs: float
    n_samples: int
    alpha: NDArray[np.int64] | None = None

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"AllanCurve.kind must be one of {KINDS}; got {self.kind!r}")
        if not (0.0 < self.confidence < 1.0):
            raise ValueError(f"AllanCurve.confidence must be in (0, 1); got {self.confidence!r}")
        if not (math.isfinite(self.fs) and self.fs > 0):
            raise ValueError(f"AllanCurve.fs must be finite and > 0 Hz; got {self.fs!r}")
        n = np.shape(self.tau)
        for name in ("deviation", "low", "high", "n_terms", "edf"):
            if np.shape(getattr(self, name)) != n:
                raise ValueError(
                    f"AllanCurve.{name} must have the shape of tau {n}; got {np.shape(getattr(self, name))}"
                )

    @property
    def variance(self) -> NDArray[np.float64]:
        """The variance, ``deviation**2`` [rate unit^2]."""
        return self.deviation**2

    @property
    def m(self) -> NDArray[np.int64]:
        """Averaging factors m = tau * fs [samples]."""
        return np.rint(self.tau * self.fs).astype(np.int64)


@dataclass(frozen=True, slots=True, kw_only=True)
class Coefficient:
    """One fitted IEEE 952 coefficient.

    Attributes
    ----------
    name : str
        "Q", "N", "B", "K" or "R".
    value : float or None
        Point estimate [unit implied by the rate unit, see module docstring]; None when the
        record cannot show this term (``identifiable`` False).
    ci68, ci95 : tuple of float
        Two-sided 68.27 % and 95 % confidence intervals (always computed, also for
        non-identifiable terms, where the lower end is usually 0).
    identifiable : bool
        True when the term dominates the fitted curve at one tau at least and its 95 %
        interval excludes 0.
    upper_bound : float
        One-sided 95 % upper bound.
    power : int
        The AVAR term is C tau**power: Q -2, N -1, B 0, K 1, R 2.
    """

    name: str
    value: float | None
    ci68: tuple[float, float]
    ci95: tuple[float, float]
    identifiable: bool
    upper_bound: float
    power: int


@dataclass(frozen=True, slots=True, kw_only=True)
class NoiseFit:
    """Result of :func:`fit_noise`.

    Attributes
    ----------
    coefficients : dict of str to Coefficient
        The fitted terms, keyed by name.
    curve : AllanCurve
        The curve that was fitted.
    avar_coefficients : dict of str to float
        Fitted C_n of AVAR = sum_n C_n tau^n (non-negative; 0 for terms the NNLS dropped).
    covariance : ndarray
        Covariance matrix of the C_n, in the order of ``avar_coefficients``.
    iterations : int
        Reweighting iterations performed.
    used : ndarray of bool
        Which points of ``curve`` were fitted (``tau_min <= tau <= tau_max``).
    chi2 : float
        Goodness of fit sum_i r_i^2 / V_ii of the residuals r = A - X C of the fitted points,
        each against its modelled variance V_ii (the V of the intervals); nan without degrees
        of freedom. (Before: r' V^-1 r, which ran 1.3x its nominal law; see :func:`fit_noise`.)
    dof : int
        Degrees of freedom: fitted points minus the terms the fit kept (C_n > 0).
    chi2_expected : float
        E[chi2] if the model holds: the trace of the residuals' modelled correlation
        D^-1 (I - H) V (I - H)' D^-1 (H the fit's hat matrix, D^2 = diag V); the effective
        number of degrees of freedom (nan when dof = 0).
    p_value : float
        P(chi2 >= observed) under the model, from the exact law of chi2 (a Gaussian quadratic
        form sum_k lambda_k chi2_1, lambda the eigenvalues of that correlation) in the
        Liu-Tang-Zhang approximation: small means the five-power-law model does not describe
        the fitted points within their scatter (nan when dof = 0).
    misfit : bool
        ``p_value < misfit_p`` (the level :func:`fit_noise` was given).
    inflation : float
        Factor the standard errors were multiplied by: sqrt(chi2 / chi2_expected) on a misfit
        (the Birge ratio), else 1.
    point_covariance : ndarray
        Modelled covariance V of the fitted AVAR points [rate unit^4] (not inflated).
    range_rule : str
        What set the shortest fitted tau: "user" (a number given as ``tau_min``), "data"
        (the filter-shaped region :func:`fit_range` found, ``tau_min="auto"``), "bandwidth"
        (the stated sensor bandwidth, :func:`bandwidth_range`), or "" (no lower limit). When
        several apply the largest tau_min wins and is named here. ``tau_min="auto"`` may then
        drop further misfitting first points (see :func:`fit_noise`).
    range_reason : str
        One line saying why the fit starts where it does ("" without a lower limit).
    """

    coefficients: dict[str, Coefficient]
    curve: AllanCurve
    avar_coefficients: dict[str, float] = field(default_factory=dict)
    covariance: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 0)))
    iterations: int = 0
    used: NDArray[np.bool_] = field(default_factory=lambda: np.zeros(0, dtype=bool))
    chi2: float = float("nan")
    dof: int = 0
    chi2_expected: float = float("nan")
    p_value: float = float("nan")
    misfit: bool = False
    inflation: float = 1.0
    point_covariance: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 0)))
    range_rule: str = ""
    range_reason: str = ""

    @property
    def tau_used(self) -> NDArray[np.float64]:
        """The cluster times [s] that were fitted."""
        return np.asarray(self.curve.tau)[self.used]

    @property
    def chi2_per_dof(self) -> float:
        """chi2 per effective degree of freedom, chi2 / chi2_expected (~1 when the model holds; nan without dof)."""
        return self.chi2 / self.chi2_expected if self.dof > 0 else float("nan")

    def avar(self, tau: ArrayLike) -> NDArray[np.float64]:
        """Fitted model Allan variance sum_n C_n tau^n at ``tau`` [s] [rate unit^2]."""
        tau = _positive_tau(tau)
        out = np.zeros_like(tau)
        for name in self.avar_coefficients:
            out = out + self.term_avar(name, tau)
        return out

    def interval(self, name: str, level: float) -> tuple[float, float]:
        """Two-sided interval of coefficient ``name`` at confidence ``level`` in (0, 1).

        C_n +- z sqrt(Cov_nn) with z = Phi^-1((1 + level)/2), clipped at 0 and mapped by
        C -> sqrt(C / scale) (the same construction as ``ci68``/``ci95``), e.g. for a test
        at a stated false-alarm rate: ``fit.interval("N", 1 - 1e-6 / 5)``.
        """
        if name not in self.avar_coefficients:
            raise ValueError(f"name must be one of the fitted terms {tuple(self.avar_coefficients)}; got {name!r}")
        if isinstance(level, bool) or not isinstance(level, (int, float, np.floating)):
            raise TypeError(f"level must be a real number in (0, 1); got {level!r}")
        if not (0.0 < level < 1.0):
            raise ValueError(f"level must be a real number in (0, 1); got {level!r}")
        j = list(self.avar_coefficients).index(name)
        z = _NORMAL.inv_cdf(0.5 + float(level) / 2.0)
        c, se = self.avar_coefficients[name], math.sqrt(max(float(self.covariance[j, j]), 0.0))
        return avar_to_coefficient(name, c - z * se), avar_to_coefficient(name, c + z * se)

    def term_avar(self, name: str, tau: ArrayLike) -> NDArray[np.float64]:
        """One term's AVAR asymptote C_n tau^n at ``tau`` [s] (uses the point estimate C_n)."""
        if name not in self.avar_coefficients:
            raise ValueError(f"name must be one of the fitted terms {tuple(self.avar_coefficients)}; got {name!r}")
        tau = _positive_tau(tau)
        return self.avar_coefficients[name] * tau ** float(_POWER[name])


def _positive_tau(tau: ArrayLike) -> NDArray[np.float64]:
    tau = np.asarray(tau, dtype=float)
    if not np.all(np.isfinite(tau) & (tau > 0)):
        raise ValueError(f"tau must be finite and > 0 s; got {tau!r}")
    return tau


def coefficient_to_avar(name: str, value: float) -> float:
    """C_n = scale * value**2 for term ``name`` (3 Q^2, N^2, 0.4413 B^2, K^2/3, R^2/2)."""
    return _SCALE[name] * value * value


def avar_to_coefficient(name: str, c: float) -> float:
    """Inverse of :func:`coefficient_to_avar`; negative ``c`` maps to 0."""
    return math.sqrt(max(c, 0.0) / _SCALE[name])


# ---------------------------------------------------------------------------------- input checks
def _check_rate(rate: ArrayLike) -> NDArray[np.float64]:
    y = np.asarray(rate)
    if y.ndim != 1:
        raise ValueError(f"rate must be a 1-D array of samples; got shape {y.shape}")
    if not (np.issubdtype(y.dtype, np.floating) or np.issubdtype(y.dtype, np.integer)):
        raise TypeError(f"rate must hold real numbers; got dtype {y.dtype}")
    y = np.asarray(y, dtype=np.float64)
    step = 1 << 20  # blockwise: no N-sized boolean temporaries
    for a in range(0, y.size, step):
        finite = np.isfinite(y[a : a + step])
        if not finite.all():
            bad = a + int(np.flatnonzero(~finite)[0])
            total = int(np.count_nonzero(~np.isfinite(y)))
            raise ValueError(
                f"rate must be finite everywhere; got {float(y[bad])!r} at index {bad} "
                f"({total} non-finite sample(s) in total)"
            )
    return y


def _check_fs(fs: Any) -> float:
    if isinstance(fs, bool) or not isinstance(fs, (int, float, np.integer, np.floating)):
        raise TypeError(f"fs must be a real number [Hz]; got {fs!r}")
    fs = float(fs)
    if not (math.isfinite(fs) and fs > 0.0):
        raise ValueError(f"fs must be finite and > 0 Hz; got {fs!r}")
    return fs


def _n_terms(kind: str, n: int, m: NDArray[np.int64]) -> NDArray[np.int64]:
    """Number of terms each estimate averages, for n rate samples (n + 1 phase points)."""
    p = n + 1
    if kind == "overlapping":
        return p - 2 * m
    if kind == "standard":
        return np.maximum((p - 2 * m + m - 1) // m, 0)
    if kind == "modified":
        return p - 3 * m + 1
    if kind == "hadamard":
        return np.maximum((p - 3 * m + m - 1) // m, 0)
    if kind == "overlapping_hadamard":
        return p - 3 * m
    return np.full_like(m, n - 1)  # total


def _max_m(kind: str, n: int) -> int:
    """Largest m with at least 2 terms for n rate samples (total deviation: tau <= T/2).

    Closed forms of ``_n_terms(kind, n, m) >= 2`` (a test checks them against the counts).
    """
    return {
        "overlapping": (n - 1) // 2,  # n + 1 - 2m >= 2
        "standard": n // 3,  # phase points 0, m, 2m, 3m <= n
        "modified": n // 3,  # n + 2 - 3m >= 2
        "hadamard": n // 4,  # phase points 0 .. 4m <= n
        "overlapping_hadamard": (n - 1) // 3,  # n + 1 - 3m >= 2
        "total": n // 2,
    }[kind]


#: taus="all": largest number of (sample, tau) pairs computed, ~1-2 min at the measured
#: 2.8e8 pairs/s of the blockwise per-tau pass (2 shared cores)
_ALL_TAUS_MAX_WORK = 2e10
#: bytes per tau of the curve and its work (tau, m, deviation, bounds, terms, edf, alpha)
_BYTES_PER_TAU = 8 * 10


def _available_memory() -> float:
    """Available physical memory [bytes] (sysconf; inf where the platform does not say)."""
    try:
        return float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):  # pragma: no cover - non-POSIX
        return math.inf


def _check_all_taus(n: int, n_tau: int) -> None:
    """Refuse taus='all' that would not fit in memory or would run for hours, in one line."""
    mem = 8.0 * (n + 1) + _BYTES_PER_TAU * n_tau + 16 * _BLOCK * 8
    avail = _available_memory()
    if mem > 0.8 * avail:
        raise ValueError(
            f"taus='all' on {n} samples means {n_tau} taus and about {mem / 2**30:.3g} GiB, more than 80 % of the "
            f"{avail / 2**30:.3g} GiB available: use taus='octave' or 'decade', or a shorter segment"
        )
    work = float(n) * n_tau
    if work > _ALL_TAUS_MAX_WORK:
        raise ValueError(
            f"taus='all' on {n} samples means {n_tau} taus, {work:.3g} sample-tau pairs (about "
            f"{work / 2.8e8 / 60:.3g} min here; the limit is {_ALL_TAUS_MAX_WORK:.0e}, ~1-2 min): use taus='octave' "
            f"or 'decade', or a shorter segment (n <= {int(math.sqrt(4 * _ALL_TAUS_MAX_WORK))} samples)"
        )


def _resolve_m(taus: Any, fs: float, n: int, kind: str) -> NDArray[np.int64]:
    if isinstance(taus, str):
        if taus not in TAU_CHOICES:
            raise ValueError(f"taus must be one of {TAU_CHOICES} or an array of tau [s]; got {taus!r}")
        m_max = min(n // _STOP_RATIO[kind], _max_m(kind, n))
        if m_max < 1:
            raise ValueError(
                f"rate has too few samples for the {kind} deviation: need at least "
                f"{_STOP_RATIO[kind]} samples for taus={taus!r}; got {n}"
            )
        if taus == "octave":
            m = 2 ** np.arange(int(math.floor(math.log2(m_max))) + 1)
        elif taus == "decade":
            k = int(math.floor(math.log10(m_max)))
            m = np.array([f * 10**j for j in range(k + 1) for f in (1, 2, 4)])
        else:
            _check_all_taus(n, m_max)
            m = np.arange(1, m_max + 1)
        m = m[m <= m_max]
        return m.astype(np.int64)
    t = np.asarray(taus, dtype=float)
    if t.ndim == 0:
        t = t[None]
    if t.ndim != 1 or t.size == 0:
        raise ValueError(f"taus must be one of {TAU_CHOICES} or a non-empty 1-D array of tau [s]; got {taus!r}")
    if not np.all(np.isfinite(t) & (t > 0)):
        raise ValueError(f"taus must be finite and > 0 s; got {t!r}")
    mf = t * fs
    m = np.rint(mf)
    bad = np.abs(mf - m) > 1e-6 * np.maximum(m, 1.0)
    if np.any(bad) or np.any(m < 1):
        i = int(np.flatnonzero(bad | (m < 1))[0])
        raise ValueError(f"taus must be multiples of 1/fs = {1 / fs!r} s; got tau = {float(t[i])!r} s")
    m = np.unique(m.astype(np.int64))
    m_max = _max_m(kind, n)
    if m[-1] > m_max:
        need = int(m[-1]) * _STOP_RATIO[kind] if kind == "total" else int(m[-1]) * (_D[kind]) + 1
        raise ValueError(
            f"rate has too few samples for tau = {float(m[-1] / fs)!r} s (m = {int(m[-1])}) in the {kind} deviation: "
            f"the largest tau with at least 2 terms is {float(m_max / fs)!r} s for {n} samples "
            f"(need about {need} samples)"
        )
    return m


# ---------------------------------------------------------------------------------- estimators
def _phase(y: NDArray[np.float64]) -> NDArray[np.float64]:
    """Integrated rate x_k = sum_{i<k} (y_i - mean y), x_0 = 0, in units of rate*sample (N + 1 points).

    Same sequence of roundings as allantools.frequency2phase (mean removed before the
    cumulative sum, which keeps precision on a large offset), without its 1/fs factor.
    """
    x = np.empty(y.size + 1)
    x[0] = 0.0
    np.subtract(y, y.mean(), out=x[1:])
    np.cumsum(x, out=x)
    return x


def _sumsq(w: NDArray[np.float64]) -> float:
    """sum(w**2) by single-threaded BLAS dot products on chunks of _DOT elements."""
    return float(sum(np.dot(w[c : c + _DOT], w[c : c + _DOT]) for c in range(0, w.size, _DOT)))


def _dot(a: NDArray[np.float64], b: NDArray[np.float64]) -> float:
    """a . b by BLAS dot products on chunks of _DOT elements (OpenBLAS never threads those)."""
    if a.size <= _DOT:
        return float(np.dot(a, b))
    return float(sum(np.dot(a[c : c + _DOT], b[c : c + _DOT]) for c in range(0, a.size, _DOT)))


def _dot_self(w: NDArray[np.float64]) -> float:
    """sum(w**2) in one BLAS call (worker-thread blocks, with the BLAS held to one thread)."""
    return float(np.dot(w, w))


_BLAS_LOCK = threading.Lock()
_blas_users = 0
_blas_limit: Any = None


@functools.lru_cache(maxsize=1)
def _blas_controller() -> Any:
    """One threadpoolctl controller per process: it scans the loaded libraries once (~9 ms)."""
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController()


@contextlib.contextmanager
def _one_blas_thread() -> Iterator[None]:
    """Hold the BLAS to one thread while any caller is inside (reference-counted).

    threadpool_limits is process-wide and restores what it saw on entry, so two overlapping
    plain ``with threadpool_limits(...)`` blocks on different threads can restore in the
    wrong order and leave the BLAS at one thread for good; here the first caller in sets
    the limit and the last one out restores it.
    """
    global _blas_users, _blas_limit
    with _BLAS_LOCK:
        if _blas_users == 0:
            _blas_limit = _blas_controller().limit(limits=1, user_api="blas")
        _blas_users += 1
    try:
        yield
    finally:
        with _BLAS_LOCK:
            _blas_users -= 1
            if _blas_users == 0:
                _blas_limit.restore_original_limits()
                _blas_limit = None


def _segments(n: int) -> list[tuple[int, int]]:
    """Split [0, n) into one contiguous range per worker thread (one range for short records)."""
    k = _THREADS if n >= _THREAD_MIN else 1
    edges = [(n * i) // k for i in range(k + 1)]
    return [(edges[i], edges[i + 1]) for i in range(k) if edges[i + 1] > edges[i]]


def _map(fn, jobs: list) -> list:
    """Run fn over jobs, on threads when there is more than one (numpy releases the GIL)."""
    if len(jobs) == 1:
        return [fn(jobs[0])]
    with ThreadPoolExecutor(len(jobs)) as ex:
        return list(ex.map(fn, jobs))


def _ssq_range(x: NDArray[np.float64], m: int, lo: int, hi: int) -> float:
    """Sum over k in [lo, hi) of (x[k+2m] - 2 x[k+m] + x[k])^2, blockwise (two block buffers)."""
    u = np.empty(min(_BLOCK, hi - lo))
    v = np.empty_like(u)
    s = 0.0
    for a in range(lo, hi, _BLOCK):
        b = min(hi, a + _BLOCK)
        w, z = u[: b - a], v[: b - a]
        np.subtract(x[a + 2 * m : b + 2 * m], x[a + m : b + m], out=w)
        np.subtract(x[a + m : b + m], x[a:b], out=z)
        np.subtract(w, z, out=w)
        s += _sumsq(w)
    return s


def _overlapping_ssq(x: NDArray[np.float64], m: int) -> tuple[float, int]:
    """Sum of squared second differences (x[k+2m] - 2 x[k+m] + x[k]) over all k.

    Blockwise, one pass over ``x`` (split across threads): no O(N) temporaries.
    """
    n = x.size - 2 * m
    return sum(_map(lambda r: _ssq_range(x, m, *r), _segments(n))), n


def _deviation_overlapping(x: NDArray[np.float64], ms: NDArray[np.int64]) -> NDArray[np.float64]:
    dev = np.empty(ms.size)
    for i, m in enumerate(ms):
        s, n = _overlapping_ssq(x, int(m))
        dev[i] = math.sqrt(s / (2.0 * n)) / m
    return dev


def _first_pass(
    y: NDArray[np.float64],
    mean: float,
    out: NDArray[np.float64] | None,
    levels: list[int],
    sums: list[bool],
    ids: dict[int, NDArray[np.float64]],
    lo: int,
    hi: int,
    ssq: Callable[[NDArray[np.float64]], float],
) -> list[float]:
    """The first octaves m = 1, 2, .., M/2 (``levels``) for k in [lo, hi), in one pass over ``y``.

    Block by block (_FUSE_BLOCK values of k plus a halo of M - 1 samples, in cache):
    S_1 = y - mean, then per level sum D_m[k]^2 (where ``sums``), the block means
    ``ids[m][j] = S_m[j m]`` that fall in the block, and S_2m[k] = S_m[k] + S_m[k+m] into
    the other buffer. Every S_m value is the same sum, in the same order, as the one-octave
    recursion. Writes S_M[k] to ``out`` (None when no octave follows). Reads only ``y``, so
    ranges of k can run on threads without sharing anything but disjoint slices of ``out``.
    """
    n = y.size
    big = 2 * levels[-1]  # M
    halo = big - 1  # S_M[k] and every D_m[k], m <= M/2, read y[k .. k + M - 1]
    cur = np.empty(min(_FUSE_BLOCK, hi - lo) + halo)
    nxt = np.empty_like(cur)
    acc = [0.0] * len(levels)
    for a in range(lo, hi, _FUSE_BLOCK):
        b = min(hi, a + _FUSE_BLOCK)
        size = min(n, b + halo) - a  # u[i] = S_m[a + i] for i < size
        u, v = cur, nxt
        np.subtract(y[a : a + size], mean, out=u[:size])
        for i, m in enumerate(levels):
            z = ids.get(m)
            if z is not None:
                j0, j1 = -(-a // m), min(-(-b // m), z.size)
                if j1 > j0:
                    z[j0:j1] = u[j0 * m - a : (j1 - 1) * m - a + 1 : m]
            c = min(b, n + 1 - 2 * m) - a  # D_m terms with k in the block
            if sums[i] and c > 0:
                np.subtract(u[m : m + c], u[:c], out=v[:c])
                acc[i] += ssq(v[:c])
            size -= m
            if size <= 0 or (out is None and i == len(levels) - 1):  # no S_2m at k >= a, or not needed
                break
            np.add(u[:size], u[m : m + size], out=v[:size])
            u, v = v, u
        if out is not None:
            c = min(b, n + 1 - big) - a  # valid S_M
            if c > 0:
                out[a : a + c] = u[:c]
    return acc


def _later_pass(
    s_arr: NDArray[np.float64],
    m: int,
    g: int,
    sums: list[bool],
    write: bool,
    ssq: Callable[[NDArray[np.float64]], float],
    job: tuple[list[tuple[int, int]], int, NDArray[np.float64] | None],
) -> list[float]:
    """Octaves m, 2m, .., 2^(g-1) m in one in-place pass over S_m, for k in the runs of ``job``.

    With T_0[j] = S_m[k + j m] (j < 2^g, views of ``s_arr``), T_{l+1}[i] = T_l[2i] +
    T_l[2i+1] = S_{2^(l+1) m}[k + i 2^(l+1) m]: the same sums in the same order as g
    one-octave steps. D at level l is T_l[1] - T_l[0]; T_g[0] = S_{2^g m}[k] is written
    over S_m[k] when ``write``. Returns sum D^2 per level (0 where ``sums`` is False).

    ``job`` = (runs, hi, tail). Each run [a, b) of k is processed in ascending k, so every
    read of S_m[k + j m] precedes the write at that index. A range of k ending at ``hi``
    reads the values from ``hi`` on, which the next thread's range overwrites, from
    ``tail`` (s_arr[hi : hi + (2^g - 1) m] copied before the pass). With one block of
    residues mod m per thread (runs [q m + r0, q m + r1)) every read stays in the thread's
    own indices and ``tail`` is None.
    """
    runs, hi, tail = job
    n = s_arr.size
    acc = [0.0] * g
    width = min(_FUSE_BLOCK, max(b - a for a, b in runs))
    d = np.empty(width)
    tree = [[np.empty(width) for _ in range(1 << (g - lv))] for lv in range(1, g)]

    def view(p: int, c: int) -> NDArray[np.float64]:  # S_m[p : p + c] as it was before the pass
        if tail is None or p + c <= hi:
            return s_arr[p : p + c]
        if p >= hi:
            return tail[p - hi : p - hi + c]
        return np.concatenate((s_arr[p:hi], tail[: p + c - hi]))

    for r0, r1 in runs:
        for a in range(r0, r1, _FUSE_BLOCK):
            b = min(r1, a + _FUSE_BLOCK)
            ends = [min(b, n + 1 - 2 * (m << lv)) - a for lv in range(g)]  # D terms per level
            # T_l[i] is needed for k < a + ends[l + bit_length(i) - 1] (i = 0 like i = 1)
            need = [
                [ends[min(lv + max(i.bit_length() - 1, 0), g - 1)] for i in range(1 << (g - lv))]
                for lv in range(g)
            ]
            t = [view(a + j * m, c) for j, c in enumerate(need[0]) if c > 0]
            for lv in range(g):
                c = ends[lv]
                if c <= 0:
                    break
                if sums[lv]:
                    np.subtract(t[1][:c], t[0][:c], out=d[:c])
                    acc[lv] += ssq(d[:c])
                if lv == g - 1:
                    if write:
                        np.add(t[0][:c], t[1][:c], out=s_arr[a : a + c])
                    break
                t = [
                    np.add(t[2 * i][:c2], t[2 * i + 1][:c2], out=tree[lv][i][:c2])
                    for i, c2 in enumerate(need[lv + 1])
                    if c2 > 0
                ]
    return acc


def _later_jobs(
    s_arr: NDArray[np.float64], m: int, g: int, nt: int
) -> list[tuple[list[tuple[int, int]], int, NDArray[np.float64] | None]]:
    """Thread jobs of one :func:`_later_pass` over k in [0, nt): ranges with tails, or residues."""
    segs = _segments(nt)
    k = len(segs)
    if k > 1 and m >= _RESIDUE_MIN:  # thread i: k mod m in [m i / k, m (i + 1) / k)
        edges = [(m * i) // k for i in range(k + 1)]
        return [
            ([(q + lo, min(q + hi, nt)) for q in range(0, nt - lo, m)], 0, None)
            for lo, hi in zip(edges[:-1], edges[1:], strict=True)
        ]
    span = ((1 << g) - 1) * m
    jobs = [([(lo, hi)], hi, s_arr[hi : hi + span].copy()) for lo, hi in segs[:-1]]
    return jobs + [([segs[-1]], 0, None)]


#: above this many bytes of work array (n float64 moving sums) the octaves from 2^_FUSE_FIRST on
#: are computed group by group of residues (see :func:`_later_streamed`) instead of in place
_WORK_BYTES = 256 << 20
#: residue groups of the streamed later octaves, and rows per chunk of their passes
#: (64 groups: a group's moving sums, n/64 floats, stay in the L3 cache through all of its
#: octaves on 1e8 samples; 16 groups ran 3x slower, memory-bound)
_GROUPS = 64
_STREAM_ROWS = 2048


def _later_streamed(
    y: NDArray[np.float64],
    mean: float,
    big: int,
    top: int,
    want: set[int],
    identify: bool,
    ssq: Callable[[NDArray[np.float64]], float],
) -> tuple[dict[int, float], dict[int, NDArray[np.float64] | None]]:
    """Octaves m = big, 2 big, .., top without an n-float work array: by residue groups mod ``big``.

    With B = big, write k = j B + i (0 <= i < B). For every m that is a multiple of B,
    S_m[j B + i] = sum_{l < m/B} S_B[(j + l) B + i] and D_m[j B + i] = S_m[(j + q) B + i] -
    S_m[j B + i] (q = m/B): for a fixed residue i the recursion S_2m = S_m + S_m(+m) runs on
    the decimated sequence Z_i[j] = S_B[j B + i] alone. The residues are split into
    _GROUPS groups of B/_GROUPS columns; a group's Z (n/_GROUPS floats) is built from the
    data and carried through every later octave, then dropped, so the work memory is
    n/_GROUPS floats per thread instead of n (and in cache while it is worked on). S_B[j B + i] is built as the tail of block j
    from i plus the head of block j + 1 before i (block sums of the column groups plus
    cumulative sums inside the group), so it differs from the tree sum of the in-place path
    by rounding only (relative ~1e-16 of the partial sums); every later S_m is the same
    tree as in :func:`_later_pass`. Invalid entries (k + m > n) are NaN and never summed.
    Returns sum D_m^2 per wanted m and, for the noise identification, the block means'
    sums S_m[j m] (j < min(n/m, _NOISE_ID_MAX)) of each wanted m (None below _NOISE_ID_MIN).
    """
    n = y.size
    b = big
    w = b // _GROUPS
    nb_all = -(-n // b) + 1  # blocks, plus one of padding
    octs = []
    mm = b
    while mm <= top:
        octs.append(mm)
        mm <<= 1

    def rows_of(r0: int, r1: int, c0: int = 0, c1: int = b) -> NDArray[np.float64]:
        """Columns c0 .. c1-1 of blocks r0 .. r1-1 of y - mean, shape (r1 - r0, c1 - c0), zero past the end."""
        a0 = r0 * b
        full = min(r1 - r0, max(0, (n - a0) // b))  # rows wholly inside the record
        if full == r1 - r0:
            return y[a0 : r1 * b].reshape(r1 - r0, b)[:, c0:c1] - mean
        out = np.zeros((r1 - r0, c1 - c0))  # (only these columns: a full-width pad was 60 MB)
        if full:
            out[:full] = y[a0 : a0 + full * b].reshape(full, b)[:, c0:c1] - mean
        start = a0 + full * b  # the partial row
        if start + c0 < n:
            seg = y[start + c0 : min(start + c1, n)]
            out[full, : seg.size] = seg - mean
        return out

    # block sums of each column group: gs[j, g] = sum of y - mean over block j, columns of group g
    gs = np.zeros((nb_all, _GROUPS))
    for r0 in range(0, nb_all, 512):
        r1 = min(nb_all, r0 + 512)
        gs[r0:r1] = rows_of(r0, r1).reshape(r1 - r0, _GROUPS, w).sum(axis=2)
    after = np.cumsum(gs[:, ::-1], axis=1)[:, ::-1]  # after[j, g] = sum of groups >= g
    after = np.concatenate((after[:, 1:], np.zeros((nb_all, 1))), axis=1)  # groups > g
    before = np.concatenate((np.zeros((nb_all, 1)), np.cumsum(gs[:, :-1], axis=1)), axis=1)  # groups < g

    def one_group(g: int) -> tuple[dict[int, float], dict[int, NDArray[np.float64] | None]]:
        i0 = g * w
        nj = (n - b - i0) // b + 1  # rows with a valid first column: j B + i0 + B <= n
        z = np.empty((nj, w))
        for r0 in range(0, nj, _STREAM_ROWS):
            r1 = min(nj, r0 + _STREAM_ROWS)
            blk = rows_of(r0, r1 + 1, i0, i0 + w)
            head = np.zeros((r1 - r0 + 1, w + 1))  # head[j, c] = sum of columns i0 .. i0 + c - 1 of block j
            np.cumsum(blk, axis=1, out=head[:, 1:])
            # tail of block j from column i (group sum minus head) plus head of block j + 1 before i
            z[r0:r1] = (after[r0:r1, g, None] + (head[:-1, w, None] - head[:-1, :w])) + (
                before[r0 + 1 : r1 + 1, g, None] + head[1:, :w]
            )
        k_last = (nj - 1) * b + i0 + np.arange(w)  # the last row's k: valid while k + B <= n
        z[nj - 1, k_last + b > n] = np.nan
        acc: dict[int, float] = {}
        ids: dict[int, NDArray[np.float64] | None] = {}
        buf = np.empty((_STREAM_ROWS, w))
        rows = nj
        for mm in octs:
            q = mm // b
            if identify and g == 0 and mm in want:
                nbk = min(n // mm, _NOISE_ID_MAX)
                ids[mm] = z[: nbk * q : q, 0].copy() if nbk >= _NOISE_ID_MIN else None
            full = rows - q - 1  # D rows j with row j + q fully valid
            s_ = 0.0
            nxt = (mm << 1) <= top
            for r0 in range(0, max(full, 0), _STREAM_ROWS):
                r1 = min(full, r0 + _STREAM_ROWS)
                if mm in want:
                    d = np.subtract(z[r0 + q : r1 + q], z[r0:r1], out=buf[: r1 - r0])
                    s_ += ssq(d.ravel())
                if nxt:
                    z[r0:r1] += z[r0 + q : r1 + q]
            if rows - q - 1 >= 0:  # the last D row: row j + q is the partly valid last row
                j = rows - q - 1
                d = z[j + q] - z[j]
                ok = np.isfinite(d)
                if mm in want:
                    s_ += float(np.dot(d[ok], d[ok]))
                if nxt:
                    z[j] += z[j + q]
            if mm in want:
                acc[mm] = s_
            rows = rows - q  # rows past this are not S_2m
        return acc, ids

    accs: dict[int, float] = {mm: 0.0 for mm in octs if mm in want}
    ids_late: dict[int, NDArray[np.float64] | None] = {}
    gs_all = list(range(_GROUPS))
    jobs = [gs_all[t::_THREADS] for t in range(min(_THREADS, _GROUPS))]
    for part in _map(lambda grp: [one_group(g) for g in grp], jobs):
        for acc, ids in part:
            for k_, v in acc.items():
                accs[k_] += v
            ids_late.update(ids)
    return accs, ids_late


def _octave_overlapping(
    y: NDArray[np.float64], ms: NDArray[np.int64], identify: bool
) -> tuple[NDArray[np.float64], NDArray[np.int64] | None]:
    """Overlapping ADEV at power-of-two m by the moving-sum recursion (fast path).

    S_1[k] = y_k - mean(y); D_m[k] = S_m[k+m] - S_m[k] (= x_{k+2m} - 2 x_{k+m} + x_k);
    S_2m[k] = S_m[k] + S_m[k+m]. The octaves are computed in fused passes: the first
    _FUSE_FIRST in one pass over ``y``, block by block in cache (:func:`_first_pass`), which
    writes S_M (M = 2^_FUSE_FIRST) into the one n-float work array; then _FUSE_LATER octaves
    per in-place pass over that array (:func:`_later_pass`). Every S_m is the same
    floating-point sum as in the one-octave-per-pass recursion (so the noise identification
    block means S_m[j m] / m are bit for bit the same); only the order in which the D_m^2
    are added differs (~1e-16 relative).
    Threads split k by range (first pass, small m) or by residue mod m (m >= _RESIDUE_MIN);
    meanwhile the BLAS is held to one thread (threadpoolctl, a scikit-learn dependency: it
    is process-wide, so :func:`_one_blas_thread` counts concurrent callers), so the
    per-block dot products run in parallel on these threads.
    """
    n = y.size
    want = {int(m) for m in ms}
    top = int(ms.max())
    mean = y.mean()
    segs = _segments(n)
    threaded = len(segs) > 1
    ssq = _dot_self if threaded else _sumsq
    dev: dict[int, float] = {}
    alpha: dict[int, int | None] = {}

    def nb_of(m: int) -> int:
        return min(n // m, _NOISE_ID_MAX)

    def finish(levels: list[int], accs: list[list[float]]) -> None:
        for i, m in enumerate(levels):
            if m in want:
                dev[m] = math.sqrt(sum(a[i] for a in accs) / (2.0 * (n + 1 - 2 * m))) / m

    with _one_blas_thread() if threaded else contextlib.nullcontext():
        levels = [1 << i for i in range(_FUSE_FIRST) if (1 << i) <= top]
        m = 2 * levels[-1]  # the first octave after the first pass
        streamed = m <= top and n * 8 > _WORK_BYTES
        s_arr = np.empty(n) if (m <= top and not streamed) else None
        ids = {
            k: np.empty(nb_of(k))
            for k in levels
            if identify and k in want and nb_of(k) >= _NOISE_ID_MIN
        }
        fn = partial(_first_pass, y, mean, s_arr, levels, [k in want for k in levels], ids, ssq=ssq)
        finish(levels, _map(lambda r: fn(*r), segs))
        for k in levels:
            if identify and k in want:
                alpha[k] = _noise_id_blocks(ids[k] / k, 2) if k in ids else None

        if streamed:
            accs, ids_late = _later_streamed(y, mean, m, top, want, identify, ssq)
            later = sorted(accs)
            finish(later, [[accs[k] for k in later]])
            for k, z in ids_late.items():
                alpha[k] = _noise_id_blocks(z / k, 2) if z is not None else None
            m = 2 * top  # done
        while m <= top:
            assert s_arr is not None  # allocated by the first pass whenever m <= top
            g = 1
            while g < _FUSE_LATER and (m << g) <= top:
                g += 1
            levels = [m << lv for lv in range(g)]
            for lv, mm in enumerate(levels):
                if identify and mm in want:
                    nb = nb_of(mm)
                    if nb < _NOISE_ID_MIN:
                        alpha[mm] = None
                        continue
                    z = s_arr[: nb * mm : m].reshape(nb, 1 << lv)  # S_m[j mm + i m]
                    while z.shape[1] > 1:  # the pass's sum tree: S_mm[j mm], bit for bit
                        z = z[:, 0::2] + z[:, 1::2]
                    alpha[mm] = _noise_id_blocks(z[:, 0] / mm, 2)
            sums = [mm in want for mm in levels]
            fn = partial(_later_pass, s_arr, m, g, sums, (m << g) <= top, ssq)
            finish(levels, _map(fn, _later_jobs(s_arr, m, g, n + 1 - 2 * m)))
            m <<= g
    del s_arr
    devs = np.array([dev[int(m)] for m in ms])
    if not identify:
        return devs, None
    out = np.zeros(ms.size, dtype=np.int64)
    last = 0
    for i, m in enumerate(ms):
        a_ = alpha[int(m)]
        if a_ is not None:
            last = int(np.clip(a_, -2, 2))
        out[i] = last
    return devs, out


#: allantools function of each kind it computes here
_ALLANTOOLS = {
    "standard": "adev",
    "modified": "mdev",
    "hadamard": "hdev",
    "overlapping_hadamard": "ohdev",
    "total": "totdev",
}


def _deviation_allantools(kind: str, y: NDArray[np.float64], fs: float, ms: NDArray[np.int64]) -> NDArray[np.float64]:
    import allantools

    taus, dev, _, ns = getattr(allantools, _ALLANTOOLS[kind])(y, rate=fs, data_type="freq", taus=ms / fs)
    got = np.rint(np.asarray(taus) * fs).astype(np.int64)
    if not np.array_equal(got, ms):  # allantools drops taus with < 2 terms; _resolve_m prevents that
        raise RuntimeError(f"allantools returned m = {got} for requested m = {ms}")
    return np.asarray(dev, dtype=float)


# ---------------------------------------------------------------------------------- noise id and edf
def _lag1_acf(z: NDArray[np.float64]) -> float:
    """Lag-1 autocorrelation (Riley & Greenhall 2004 eq. 2), as allantools.ci.lag1_acf, vectorised."""
    d = z - z.mean()
    return _dot(d[:-1], d[1:]) / _dot(d, d)


def _detrend1(z: NDArray[np.float64]) -> NDArray[np.float64]:
    """Remove the least-squares line (allantools.ci.detrend(deg=1), in closed form)."""
    t = np.arange(z.size, dtype=float)
    t -= t.mean()
    zc = z - z.mean()
    return zc - t * (_dot(t, zc) / _dot(t, t))


def _noise_id_blocks(z: NDArray[np.float64], dmax: int) -> int:
    """Lag-1 ACF noise identification (Riley & Greenhall 2004) of block means z of the rate.

    Block means that are exactly a line after detrending (e.g. a constant rate: every
    S_m[j m] is the same sum) have no noise to identify: 0 (white rate) is returned instead
    of a 0/0 autocorrelation. (A noise-free ramp leaves rounding residue, which gets some
    alpha; its deviation is exact, only its bounds depend on that alpha.)
    """
    z = _detrend1(z)
    d = 0
    while True:
        if not np.any(z):
            return 0
        r1 = _lag1_acf(z)
        rho = r1 / (1.0 + r1)
        if rho < 0.25 or d >= dmax:
            return int(-1.0 * np.round(2 * rho) - 2.0 * d)
        z = np.diff(z)
        d += 1


def _noise_id_one(x: NDArray[np.float64], m: int, dmax: int) -> int | None:
    """Lag-1 ACF noise identification at averaging factor m from the phase x (None if < 30 points)."""
    nb = min((x.size - 1) // m, _NOISE_ID_MAX)
    if nb < _NOISE_ID_MIN:
        return None
    return _noise_id_blocks(np.diff(x[: nb * m + 1 : m]) / m, dmax)  # non-overlapping block means


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


def _identify(x: NDArray[np.float64], ms: NDArray[np.int64], kind: str) -> NDArray[np.int64]:
    dmax = 3 if _D[kind] == 3 else 2
    lo = -4 if _D[kind] == 3 else -2
    out = np.zeros(ms.size, dtype=np.int64)
    last = 0
    for i, m in enumerate(ms):
        a = _noise_id_one(x, int(m), dmax)
        if a is not None:
            last = int(np.clip(a, lo, 2))
        out[i] = last
    return out


#: Greenhall & Riley (2003) Table 2: (a0, a1) of 1/edf ~ (a0 - a1/r)/r for unmodified variances
#: at large r, by alpha (+2 .. -4) and d (1, 2, 3); None where alpha + 2d <= 1
_GH_TABLE2: dict[int, tuple[tuple[float, float] | None, ...]] = {
    2: ((3.0 / 2.0, 1.0 / 2.0), (35.0 / 18.0, 1.0), (231.0 / 100.0, 3.0 / 2.0)),
    1: ((78.6, 25.2), (790.0, 410.0), (9950.0, 6520.0)),
    0: ((2.0 / 3.0, 1.0 / 6.0), (2.0 / 3.0, 1.0 / 3.0), (7.0 / 9.0, 1.0 / 2.0)),
    -1: (None, (0.852, 0.375), (0.997, 0.617)),
    -2: (None, (1.079, 0.368), (1.033, 0.607)),
    -3: (None, None, (1.053, 0.553)),
    -4: (None, None, (1.302, 0.535)),
}
#: Greenhall & Riley (2003) Table 3: (b0, b1) of the alpha = +1 (flicker PM) case, by d
_GH_TABLE3 = ((6.0, 4.0), (15.23, 12.0), (47.8, 40.0))
_GH_JMAX = 100


def _gh_sw(t: NDArray[np.float64], alpha: int) -> NDArray[np.float64]:
    """Greenhall & Riley eq. (7): the generalised autocovariance kernel s_w(t) of S_x ~ f^(alpha - 2)."""
    a = np.abs(t)
    if alpha % 2 == 0:  # alpha = 2, 0, -2, -4: -|t|, |t|^3, |t|^5, |t|^7
        return -a if alpha == 2 else a ** (3 - alpha)
    # alpha = 1, -1, -3: t^(3 - alpha) ln|t|, 0 at t = 0
    return t ** (3 - alpha) * np.log(a, out=np.zeros_like(a), where=a > 0.0)


def _gh_sx(t: NDArray[np.float64], f: float, alpha: int) -> NDArray[np.float64]:
    """Eq. (8): the kernel after the F-sample averaging (F = inf: s_w at alpha + 2)."""
    if math.isinf(f):
        return _gh_sw(t, alpha + 2)
    w = _gh_sw(np.stack((t, t - 1.0 / f, t + 1.0 / f)), alpha)
    return f**2 * (2.0 * w[0] - w[1] - w[2])


def _gh_sz(t: NDArray[np.float64], f: float, alpha: int, d: int) -> NDArray[np.float64]:
    """Eq. (9): the kernel after the d-th difference, sum_k (-1)^k C(2d, d+k) s_x(t + k)."""
    sx = _gh_sx(t[None, :] + np.arange(-d, d + 1, dtype=float)[:, None], f, alpha)  # row d + k: t + k
    out = math.comb(2 * d, d) * sx[d]
    for k in range(1, d + 1):
        out = out + (-1) ** k * math.comb(2 * d, d + k) * (sx[d - k] + sx[d + k])
    return out


def _gh_basic_sum(j_top: float, big_m: float, s: float, f: float, alpha: int, d: int) -> float:
    """Eq. (10): sz(0)^2 + (1 - J/M) sz(J/S)^2 + 2 sum_{j=1}^{J-1} (1 - j/M) sz(j/S)^2, over sz(0)^2 M."""
    j = np.arange(1, int(j_top), dtype=float)
    z0 = float(_gh_sz(np.array([0.0]), f, alpha, d)[0])
    zj = float(_gh_sz(np.array([float(j_top) / s]), f, alpha, d)[0])
    mid = float(np.sum(2.0 * (1.0 - j / big_m) * _gh_sz(j / s, f, alpha, d) ** 2))
    return (z0**2 + (1.0 - float(j_top) / big_m) * zj**2 + mid) / (z0**2 * big_m)


def _edf_greenhall(alpha: int, d: int, m: int, n_phase: int, overlapping: bool) -> float:
    """Equivalent degrees of freedom of an unmodified Allan (d = 2) or Hadamard (d = 3) variance.

    C. A. Greenhall and W. J. Riley, "Uncertainty of stability variances based on finite
    differences", PTTI 2003 (NIST SP 1065 section 5.3.3): the exact sum eq. (10) for J <= 100
    lags, the Table 2/3 large-r approximations beyond, cases 2-4 of the paper (F = m; the
    modified variance, case 1, is left to allantools). Same arithmetic as
    allantools.ci.edf_greenhall (a test pins the two to 1e-12) without importing allantools,
    whose import pulls in scipy.stats and scipy.interpolate (~1-3 s). Raises
    NotImplementedError for alpha = +2 with ceil(r) <= d, where the paper gives no formula.
    """
    if not alpha + 2 * d > 1:
        raise ValueError(f"alpha + 2 d must be > 1; got alpha = {alpha}, d = {d}")
    s = float(m) if overlapping else 1.0
    big_m = 1.0 + math.floor(s * (n_phase - (1.0 + m * d)) / m)
    j_top = min(big_m, (d + 1) * s)
    r = big_m / s
    if alpha <= 0:
        if j_top <= _GH_JMAX:
            f = float(m) if m * (d + 1) <= _GH_JMAX else math.inf
            return 1.0 / _gh_basic_sum(j_top, big_m, s, f, alpha, d)
        if r > d + 1:
            a0, a1 = _GH_TABLE2[alpha][d - 1]  # type: ignore[misc]
            return 1.0 / ((1.0 / r) * (a0 - a1 / r))
        return 1.0 / _gh_basic_sum(_GH_JMAX, _GH_JMAX, _GH_JMAX / r, math.inf, alpha, d)
    if alpha == 1:
        b0, b1 = _GH_TABLE3[d - 1]
        if j_top <= _GH_JMAX:
            return 1.0 / _gh_basic_sum(j_top, big_m, s, float(m), 1, d)
        if r > d + 1:
            a0, a1 = _GH_TABLE2[1][d - 1]  # type: ignore[misc]
            return 1.0 / ((1.0 / ((b0 + b1 * math.log(m)) ** 2 * r)) * (a0 - a1 / r))
        mp = _GH_JMAX / r
        z0 = float(_gh_sz(np.array([0.0]), mp, 1, d)[0])
        return 1.0 / (_gh_basic_sum(_GH_JMAX, _GH_JMAX, mp, mp, 1, d) * z0**2 / (b0 + b1 * math.log(m)) ** 2)
    if math.ceil(r) <= d:
        raise NotImplementedError(f"no Greenhall edf for alpha = 2 with r = {r} <= d = {d}")
    a0 = math.comb(4 * d, 2 * d) / math.comb(2 * d, d) ** 2
    return 1.0 / ((1.0 / big_m) * (a0 - (d / 2.0) / r))


def _edf_stein(n_phase: int, m: int, alpha: int) -> float:
    """Stein's approximate edf of the overlapping ADEV (NIST SP 1065 Table 5; N phase points)."""
    n, mm = float(n_phase), float(m)
    if alpha == 2:
        return (n + 1) * (n - 2 * mm) / (2 * (n - mm))
    if alpha == 1:
        prod = math.log((n - 1) / (2 * mm)) * math.log((2 * mm + 1) * (n - 1) / 4)
        return math.exp(math.sqrt(prod)) if prod >= 0 else float("nan")  # nan: no edf (caller falls back)
    if alpha == 0:
        return ((3 * (n - 1) / (2 * mm)) - (2 * (n - 2) / n)) * ((4 * mm**2) / ((4 * mm**2) + 5))
    if alpha == -1:
        return 2 * (n - 2) / (2.3 * n - 4.9) if m == 1 else 5 * n**2 / (4 * mm * (n + (3 * mm)))
    if alpha == -2:
        return (n - 2) / (mm * (n - 3) ** 2) * ((n - 1) ** 2 - 3 * mm * (n - 1) + 4 * mm**2)
    return n - 1


@functools.lru_cache(maxsize=4096)
def _edf_one(kind: str, alpha: int, m: int, n: int) -> float:
    """Equivalent degrees of freedom of one estimate (n rate samples, n + 1 phase points)."""
    p = n + 1
    d = _D[kind]
    if kind in ("total", "modified"):
        from allantools import ci as _atci

    if kind == "total":
        return float(_atci.edf_totdev(n, m, alpha))
    overlapping = kind in ("overlapping", "modified", "overlapping_hadamard")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            if kind == "modified":
                e = float(
                    _atci.edf_greenhall(alpha=int(alpha), d=d, m=int(m), N=p, overlapping=True, modified=True)
                )
            else:
                e = _edf_greenhall(int(alpha), d, int(m), p, overlapping)
    except (NotImplementedError, AssertionError, ZeroDivisionError):  # pragma: no cover - tiny records
        e = float("nan")
    if not (math.isfinite(e) and e > 0):
        # Greenhall has no formula for white PM with fewer than d + 1 terms: fall back to Stein's
        # approximation (NIST SP 1065 Table 5) and, failing that, the term count
        e = _edf_stein(p, m, alpha) if d == 2 else float("nan")
        if not (math.isfinite(e) and e > 0):
            e = float(max(_n_terms(kind, n, np.array([m]))[0], 1))
    return e


def _edf(kind: str, alpha: NDArray[np.int64], ms: NDArray[np.int64], n: int) -> NDArray[np.float64]:
    cache: dict[tuple[int, int], float] = {}
    out = np.empty(ms.size)
    for i, (a, m) in enumerate(zip(alpha, ms)):
        key = (int(a), int(m))
        if key not in cache:
            cache[key] = _edf_one(kind, int(a), int(m), n)
        out[i] = cache[key]
    return out


def _bounds(dev: NDArray[np.float64], edf: NDArray[np.float64], confidence: float):
    """Chi-square bounds (NIST SP 1065 eq. 45; allantools.ci.confidence_interval, vectorised)."""
    from scipy import special  # chi2.ppf(q, nu) = 2 gammaincinv(nu/2, q), as scipy.stats computes it

    p = (1.0 - confidence) / 2.0
    lo = dev * np.sqrt(edf / (2.0 * special.gammaincinv(edf / 2.0, 1.0 - p)))
    hi = dev * np.sqrt(edf / (2.0 * special.gammaincinv(edf / 2.0, p)))
    return lo, hi


def _check_kind(kind: Any) -> None:
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {KINDS}; got {kind!r}")


#: curves with at most this many taus (and records below _THREAD_MIN samples) keep every BLAS
#: product under OpenBLAS's threading thresholds (gemm m n k <= 65536 * 4; dot products are
#: chunked by _DOT), so no thread limit is needed for them
_SMALL_TAUS = 64


def _is_small(args: tuple, kwargs: dict) -> bool:
    """True when a call of allan_deviation/fit_noise makes no BLAS call large enough to thread."""
    first = args[0] if args else kwargs.get("curve_or_rate", kwargs.get("rate"))
    if isinstance(first, AllanCurve):
        return first.tau.size <= _SMALL_TAUS
    taus = kwargs.get("taus", "octave")
    few = (taus in ("octave", "decade")) if isinstance(taus, str) else np.size(taus) <= _SMALL_TAUS
    return few and first is not None and np.size(first) < _THREAD_MIN


def _single_blas(fn: Callable) -> Callable:
    """Run ``fn`` with the BLAS held to one thread unless the call is small (:func:`_is_small`).

    The first multithreaded BLAS call of a process costs ~1-2 s of thread start-up on a busy
    virtual machine (measured: 1.9 s, then 0.05 s; single-threaded 0.02 s), and the
    products here are small (<= 65536 x 44); but setting the limit costs ~10-15 ms on first
    use (threadpoolctl scans every loaded library), a third of a whole analysis of a 2e5
    sample record, so calls whose products stay below the threading thresholds skip it.
    """

    @functools.wraps(fn)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        with contextlib.nullcontext() if _is_small(args, kwargs) else _one_blas_thread():
            return fn(*args, **kwargs)

    return wrapper


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
    _check_kind(kind)
    if isinstance(confidence, bool) or not isinstance(confidence, (int, float, np.floating)):
        raise TypeError(f"confidence must be a real number in (0, 1); got {confidence!r}")
    if not (0.0 < float(confidence) < 1.0):
        raise ValueError(f"confidence must be in (0, 1); got {confidence!r}")
    n = y.size
    if n < 2:
        raise ValueError(f"rate has too few samples: need at least 2; got {n}")
    ms = _resolve_m(taus, fs, n, kind)

    al = None
    if kind == "overlapping" and np.all((ms & (ms - 1)) == 0):  # powers of two: in-place recursion
        dev, al = _octave_overlapping(y, ms, identify=alpha is None)
    else:
        x = _phase(y) if (kind == "overlapping" or alpha is None) else None
        if kind == "overlapping":
            assert x is not None
            dev = _deviation_overlapping(x, ms)
        else:
            dev = _deviation_allantools(kind, y, fs, ms)
        if alpha is None:
            assert x is not None
            al = _identify(x, ms, kind)
        del x
    if alpha is not None:
        al = np.broadcast_to(np.asarray(alpha), ms.shape).astype(np.int64)
        lo = -4 if _D[kind] == 3 else -2
        if np.any((al < lo) | (al > 2)):
            raise ValueError(f"alpha must be integers in [{lo}, 2] for the {kind} deviation; got {alpha!r}")
    assert al is not None  # identified above, or given as alpha
    edf = _edf(kind, al, ms, n)
    low, high = _bounds(dev, edf, float(confidence))
    return AllanCurve(
        tau=ms / fs,
        deviation=dev,
        low=low,
        high=high,
        n_terms=_n_terms(kind, n, ms),
        edf=edf,
        kind=kind,
        confidence=float(confidence),
        fs=fs,
        n_samples=n,
        alpha=np.array(al, dtype=np.int64),
    )


# ---------------------------------------------------------------------------------- public: fit
_NORMAL = NormalDist()
_Z68 = _NORMAL.inv_cdf(0.5 + _ONE_SIGMA / 2.0)  # 1.0
_Z95 = _NORMAL.inv_cdf(0.975)  # 1.96
_Z95_ONE_SIDED = _NORMAL.inv_cdf(0.95)  # 1.645
_FIT_KINDS = ("overlapping", "standard")


def _wnnls(x: NDArray[np.float64], a: NDArray[np.float64], var: NDArray[np.float64]) -> NDArray[np.float64]:
    """argmin_{C >= 0} sum_i (x_i . C - a_i)^2 / var_i, on column-scaled X for conditioning."""
    sw = 1.0 / np.sqrt(var)
    xw = x * sw[:, None]
    scale = np.linalg.norm(xw, axis=0)
    scale[scale == 0] = 1.0
    if x.shape[1] <= _NNLS_ENUM:
        cs = _nnls_enumerate(xw / scale, a * sw)
    else:  # pragma: no cover - the fit has at most five terms
        from scipy import optimize

        cs, _ = optimize.nnls(xw / scale, a * sw, maxiter=50 * x.shape[1])
    return cs / scale


#: up to this many columns NNLS is solved here (Lawson-Hanson), without scipy.optimize
_NNLS_ENUM = 6


def _nnls_enumerate(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """argmin_{c >= 0} ||a c - b|| for a few columns: the Lawson-Hanson active-set algorithm.

    C. L. Lawson and R. J. Hanson, "Solving Least Squares Problems" (1974), ch. 23 (as in
    MATLAB's lsqnonneg and scipy.optimize.nnls): move the column of largest gradient
    a'(b - a c) into the passive set, solve least squares on it, and step back to the
    feasible region while a coefficient goes negative. A gradient within the tolerance
    10 eps ||a||_1 max(shape) counts as zero, so a term that does not help stays exactly 0.
    Same minimiser as scipy.optimize.nnls (to rounding; a test compares them) without
    importing scipy.optimize (~0.3-0.5 s, the largest single cost of a short CLI run).
    """
    rows, k = a.shape
    tol = 10.0 * np.finfo(float).eps * float(np.abs(a).sum(axis=0).max()) * max(rows, k)
    passive = np.zeros(k, dtype=bool)
    x = np.zeros(k)
    w = a.T @ (b - a @ x)
    for _ in range(3 * k + 3):
        if passive.all() or not np.any(w[~passive] > tol):
            break
        j = int(np.argmax(np.where(passive, -np.inf, w)))
        passive[j] = True
        while True:
            z = np.zeros(k)
            z[passive] = np.linalg.lstsq(a[:, passive], b, rcond=None)[0]
            neg = passive & (z <= 0.0)
            if not neg.any():
                break
            step = np.min(x[neg] / (x[neg] - z[neg]))
            x = x + step * (z - x)
            passive &= x > tol
            x[~passive] = 0.0
        x = z
        w = a.T @ (b - a @ x)
    return x


#: correlations are computed exactly (discrete time) up to this m; larger pairs are scaled down
#: keeping their ratio (the correlation of power-law noise depends on m_j/m_i only, for large m)
_RHO_M_CAP = 1024
#: frequency points on (0, 1/2]: 32 per period of sin^4(pi f m_cap). Against 128 per period
#: (65536 points, used before) every correlation moves by <= 8.5e-4 (measured over the 18
#: octaves and the four noise types), far below the model's own accuracy (see fit_noise:
#: modelled 0.40 vs measured 0.33 +- 0.06); the midpoint rule converges slowly only for
#: flicker, whose integrand has a kink at f = 0.
_RHO_GRID = 16 * _RHO_M_CAP


def _rate_psd_shape(alpha: int, f: NDArray[np.float64]) -> NDArray[np.float64]:
    """Shape of the discrete-time rate PSD of each power-law type (f in cycles/sample)."""
    s = np.sin(np.pi * f)
    if alpha == 2:
        return s * s  # differenced white angle (quantization)
    if alpha == 0:
        return np.ones_like(f)  # white rate (ARW)
    if alpha == -1:
        return 1.0 / f  # flicker rate (bias instability)
    return 1.0 / (s * s)  # random-walk rate (RRW; also used for the ramp)


@functools.lru_cache(maxsize=1)
def _rho_grid() -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Midpoint grid f on (0, 1/2] [cycles/sample] and sin(pi f) on it (built on first use)."""
    f = (np.arange(_RHO_GRID) + 0.5) / (2 * _RHO_GRID)
    return f, np.sin(np.pi * f)


def _h(m: int) -> NDArray[np.float64]:
    """|H_m|^2 / 4 = sin^4(pi f m) / sin^2(pi f) on the grid (shared by every noise type)."""
    f, s1 = _rho_grid()
    s = np.sin((np.pi * m) * f)
    s *= s
    s /= s1
    s *= s
    return s


def _scaled(m1: int, m2: int) -> tuple[int, int]:
    """Scale a pair of m down to max <= _RHO_M_CAP keeping their ratio (see :func:`_rho_blocks`)."""
    if max(m1, m2) <= _RHO_M_CAP:
        return m1, m2
    k = max(m1, m2) / _RHO_M_CAP
    return max(1, int(round(m1 / k))), max(1, int(round(m2 / k)))


def _scaled_pairs(ms: NDArray[np.int64]) -> NDArray[np.int64]:
    """:func:`_scaled` of every pair (ms[i], ms[j]), vectorised: shape (n, n, 2)."""
    m1, m2 = np.meshgrid(ms, ms, indexing="ij")
    top = np.maximum(m1, m2)
    k = top / _RHO_M_CAP
    big = top > _RHO_M_CAP
    s1 = np.where(big, np.maximum(1, np.rint(m1 / k)), m1).astype(np.int64)  # rint: half to even, as round
    s2 = np.where(big, np.maximum(1, np.rint(m2 / k)), m2).astype(np.int64)
    return np.stack((s1, s2), axis=-1)


def _rho_blocks(alphas: Sequence[int], ms: NDArray[np.int64]) -> dict[tuple[int, int], NDArray[np.float64]]:
    """rho[(t, s)][i, j]: correlation of term t's noise in A_i with term s's noise in A_j.

    For Gaussian noise with rate PSD S = sum_t S_t, Cov(sum_k D_i[k]^2, sum_l D_j[l]^2)
    = 2 sum_{k,l} E[D_i[k] D_j[l]]^2 -> 2 n int S^2 |H_i|^2 |H_j|^2 df (Parseval, n >> m),
    with |H_m(f)|^2 = 4 sin^4(pi f m) / sin^2(pi f) the response of the second difference
    of the phase to the rate. Expanding S^2 = sum_{t,s} S_t S_s splits the covariance into
    rho_ts(i, j) sd_t(i) sd_s(j) with rho_ts(i, j) = int g_ti g_sj / sqrt(int g_ti^2 int g_sj^2),
    g_ti = S_t |H_i|^2 (S_t the discrete-time shape of each power law: sin^2(pi f) for
    quantization, 1 white, 1/f flicker, 1/sin^2(pi f) random walk). The integrals use the
    midpoint rule on 16384 points of (0, 1/2] (32 per period of the fastest factor).
    For m above 1024 both m of a pair are scaled down keeping their ratio: for power-law
    noise in the continuous-time limit rho depends on m_j/m_i only. This is the n >> m limit:
    the record's ends are added by :func:`_finite_record_delta` in the fit. Octave taus read
    the stored table (:func:`_octave_gram`); the result depends only on the alphas and the m,
    so it is cached (the same taus again, e.g. the other axes of a triad, cost nothing).
    """
    key = (tuple(int(a) for a in alphas), tuple(int(m) for m in ms))
    return {k: v.copy() for k, v in _rho_blocks_cached(*key).items()}


@functools.lru_cache(maxsize=64)
def _rho_blocks_cached(
    alphas: tuple[int, ...], ms: tuple[int, ...]
) -> dict[tuple[int, int], NDArray[np.float64]]:
    n = len(ms)
    pairs = _scaled_pairs(np.asarray(ms, dtype=np.int64))  # (n, n, 2)
    mu = sorted({int(m) for m in np.unique(pairs)})
    ua = sorted(set(alphas))
    gram = _octave_gram(ua, mu)
    if gram is None:  # some m is not a power of two (or the table does not hold it): compute
        gram = _gram_direct(ua, mu)
    lookup = np.zeros(max(mu) + 1, dtype=np.int64)
    lookup[mu] = np.arange(len(mu))
    i1 = lookup[pairs[..., 0]]
    i2 = lookup[pairs[..., 1]]
    diag = np.eye(n, dtype=bool)
    out = {}
    for t, at in enumerate(alphas):
        for s_, as_ in enumerate(alphas):
            r = gram[ua.index(at) * len(mu) + i1, ua.index(as_) * len(mu) + i2]
            if at == as_:
                r[diag] = 1.0
            out[(t, s_)] = r
    return out


def _gram_direct(ua: Sequence[int], mu: Sequence[int]) -> NDArray[np.float64]:
    """Gram matrix of the unit-norm g = S_alpha |H_m|^2 rows, alpha in ``ua`` (outer) by m in ``mu`` (inner).

    Entry [a * len(mu) + i, b * len(mu) + j] = int g_{ua[a], mu[i]} g_{ua[b], mu[j]} df on
    the midpoint grid of :func:`_rho_grid` (see :func:`_rho_blocks`).
    """
    f = _rho_grid()[0]
    h = np.stack([_h(m) for m in mu])  # (len(mu), grid)
    g = np.concatenate([h * _rate_psd_shape(a, f)[None, :] for a in ua])  # (len(ua) len(mu), grid)
    g /= np.linalg.norm(g, axis=1)[:, None]
    rows = g.shape[0]
    chunk = _GEMM_SINGLE // (rows * rows)
    if chunk >= 64:  # k-chunks small enough that OpenBLAS runs each product on one thread
        gram = np.zeros((rows, rows))
        gt = np.ascontiguousarray(g.T)
        for a in range(0, g.shape[1], chunk):
            gram += g[:, a : a + chunk] @ gt[a : a + chunk]
    else:
        with _one_blas_thread():  # a first multithreaded BLAS call costs ~1-2 s of start-up on a busy VM
            gram = g @ g.T
    return gram


#: the noise types and the m of the stored octave table (``_allan_rho_table``)
_TABLE_ALPHAS = (-2, -1, 0, 2)
_TABLE_MS = tuple(1 << k for k in range(_RHO_M_CAP.bit_length()))  # 1, 2, 4, .., 1024


def _octave_gram_direct() -> NDArray[np.float64]:
    """The full octave gram matrix (every alpha of _TABLE_ALPHAS, every m of _TABLE_MS), computed."""
    return _gram_direct(_TABLE_ALPHAS, _TABLE_MS)


@functools.lru_cache(maxsize=1)
def _octave_table() -> NDArray[np.float64] | None:
    """The stored octave gram matrix (44 x 44), or None when it was made for another grid or cap."""
    import binascii  # (base64 itself imports struct and re: ~1 ms)

    from gyrobench.analysis import _allan_rho_table as tab

    if (tab.GRID, tab.M_CAP, tab.ALPHAS, tab.MS) != (_RHO_GRID, _RHO_M_CAP, _TABLE_ALPHAS, _TABLE_MS):
        return None  # pragma: no cover - the table is regenerated whenever these change (a test checks)
    k = len(tab.ALPHAS) * len(tab.MS)
    gram = np.frombuffer(binascii.a2b_base64(tab.GRAM), dtype="<f8").reshape(k, k).astype(float)
    gram.flags.writeable = False
    return gram


def _octave_gram(ua: Sequence[int], mu: Sequence[int]) -> NDArray[np.float64] | None:
    """Rows/columns ``ua`` x ``mu`` of the stored octave table, or None if it does not hold them all.

    The table is :func:`_octave_gram_direct` evaluated once and stored (gyrobench.analysis.
    _allan_rho_table, written by benchmarks/make_rho_table.py): building the 44 g vectors on
    the 16384-point grid and their products cost ~20 ms on first use, the largest fixed cost
    of a fit on an ordinary record; a test checks the table against the direct computation.
    """
    if not (set(ua) <= set(_TABLE_ALPHAS) and set(mu) <= set(_TABLE_MS)):
        return None
    table = _octave_table()
    if table is None:  # pragma: no cover
        return None
    idx = np.array([_TABLE_ALPHAS.index(a) * len(_TABLE_MS) + _TABLE_MS.index(m) for a in ua for m in mu])
    return table[np.ix_(idx, idx)]


#: finite-record correction of rho (overlapping AVAR, :func:`_finite_record_delta`): a pair
#: whose larger m exceeds this is scaled down to it, keeping the ratio m_j/m_i and N/m.
#: 32, not 64: same-type correlations stay within 0.03 of the exact form (0.02 at 64), and
#: the first fit of a 2e5-sample record is ~4 ms faster (it keeps the fit ahead of
#: allantools + NNLS there; coverage is the same at either cap)
_FIN_CAP = 32
#: lags h on a circle of this many points (midpoint frequency grid): more than the 4 _FIN_CAP + 1
#: lags where the kernels' cross-correlations of Q, N and K are non-zero, so those are exact
_FIN_GRID = 8 * _FIN_CAP


def _lag_covariances(
    alphas: Sequence[int], m1: NDArray[np.int64], m2: NDArray[np.int64], grid: int
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """R[p, j, t] = E[d_{m1[p]}[k] d_{m2[p]}[k + h[j]]] for unit noise of type alphas[t]; and h.

    d_m[k] = x[k + 2m] - 2 x[k + m] + x[k] is the second difference of the phase x (cumulative
    sum of the rate samples y), i.e. sum_u w_m[u] y[k + u] with w_m = -1 on u < m, +1 on
    m <= u < 2m, whose transfer function is W_m(f) = -(1 - z^m)^2 / (1 - z), z = exp(-2 pi i f).
    R(h) = int_{-1/2}^{1/2} S(f) W_1(f) conj(W_2(f)) exp(2 pi i f h) df with S the discrete
    rate PSD shape of :func:`_rate_psd_shape` (sin^2(pi f): differenced white phase; 1; 1/|f|;
    1/sin^2(pi f): random walk), evaluated on ``grid`` midpoints by one inverse FFT: exact for
    lags |h| < grid/2 whenever S |W|^2 is a trigonometric polynomial of degree < grid/2 (Q, N,
    K: the kernels have finite support), else aliased (flicker: the error is the tail sum
    sum_p (-1)^p R(h + p grid), R decaying as h^-2).
    """
    f = (np.arange(grid) + 0.5) / grid
    mu, inv = np.unique(np.concatenate([m1, m2]), return_inverse=True)
    z1 = np.exp(-2j * np.pi * f)
    zm = np.exp(-2j * np.pi * np.outer(mu, f))
    w = -((1.0 - zm) ** 2) / (1.0 - z1)
    p = w[inv[: len(m1)]] * np.conj(w[inv[len(m1):]])
    s = np.stack([_rate_psd_shape(int(a), np.minimum(f, 1.0 - f)) for a in alphas], axis=1)
    h = np.arange(grid)
    h = np.where(h < grid // 2, h, h - grid)
    r = np.fft.ifft(p[:, :, None] * s[None, :, :], axis=1) * np.exp(1j * np.pi * h / grid)[:, None]
    return np.ascontiguousarray(r.real), h


def _overlap_counts(
    big_m1: NDArray[np.float64], big_m2: NDArray[np.float64], h: NDArray[np.int64]
) -> NDArray[np.float64]:
    """#{k : 0 <= k < M1, 0 <= k + h < M2}: pairs of terms (d_1[k], d_2[k + h]) of two estimates."""
    m1 = np.asarray(big_m1, dtype=float)[:, None]
    m2 = np.asarray(big_m2, dtype=float)[:, None]
    return np.maximum(0.0, np.minimum(m1, m2 - h[None, :]) - np.maximum(0, -h)[None, :])


def _finite_cov_sums(
    alphas: Sequence[int],
    m1: NDArray[np.int64],
    m2: NDArray[np.int64],
    big_m1: NDArray[np.float64],
    big_m2: NDArray[np.float64],
    grid: int,
) -> NDArray[np.float64]:
    """T[p, t, s] = sum_h R^t_p(h) R^s_p(h) c_p(h), c_p the :func:`_overlap_counts`.

    For Gaussian rate noise with covariance S = sum_t S_t, the overlapping AVAR estimates
    A_i = sum_{k < M_i} d_i[k]^2 / (2 m_i^2 tau_0^2 M_i) are quadratic forms, and
    Cov(A_1, A_2) = 2 sum_{k, l} E[d_1[k] d_2[l]]^2 / norms = 2 sum_{t, s} sum_h R^t(h) R^s(h)
    c(h) / norms: exact for a record of finite length (M_i = n + 1 - 2 m_i terms; the count of
    overlapping term pairs at lag h is where the record ends enter), as the trace
    2 tr(A_1 S A_2 S) (a test checks it against the explicit matrices).
    """
    r, h = _lag_covariances(alphas, m1, m2, grid)
    c = _overlap_counts(big_m1, big_m2, h)
    return np.einsum("pht,phs,ph->pts", r, r, c)


def _finite_record_delta(
    alphas: Sequence[int], ms: NDArray[np.int64], n: int
) -> dict[tuple[int, int], NDArray[np.float64]]:
    """rho_ts(i, j) of a record of n samples minus the same for n -> infinity (overlapping AVAR).

    rho_ts(i, j) = T_ts(i, j) / sqrt(T_tt(i, i) T_ss(j, j)) with T of :func:`_finite_cov_sums`
    (counts for n samples) and with counts replaced by 1 (the n >> m limit that
    :func:`_rho_blocks` models). Pairs with max(m_i, m_j) > _FIN_CAP are evaluated at m scaled
    down to _FIN_CAP with the record scaled alike (M / k): for power-law noise in the
    continuous-time limit the correlation depends on m_j/m_i and M/m only. The difference of
    the two (same kernels, same grid) is added to the stored asymptotic correlations; its
    error against the exact unscaled computation is checked in the tests.
    """
    key = (tuple(int(a) for a in alphas), tuple(int(m) for m in ms), int(n))
    return {k: v.copy() for k, v in _finite_record_delta_cached(*key).items()}


def _count_weighted(
    xt: NDArray[np.float64],
    key: NDArray[np.int64],
    h: NDArray[np.int64],
    big_m1: NDArray[np.float64],
    big_m2: NDArray[np.float64],
) -> NDArray[np.float64]:
    """out[p, q] = sum_h xt[key[p], h, q] c_p(h), c_p the :func:`_overlap_counts` of p.

    One (pairs of that key) x grid x q product per distinct key (BLAS), instead of gathering
    a (pairs, q, grid) copy of xt.
    """
    c = _overlap_counts(big_m1, big_m2, h)
    out = np.empty((key.size, xt.shape[2]))
    order = np.argsort(key, kind="stable")
    ks = key[order]
    cuts = np.flatnonzero(np.diff(ks)) + 1
    for grp in np.split(order, cuts):
        out[grp] = c[grp] @ xt[key[grp[0]]]
    return out


@functools.lru_cache(maxsize=16)
def _finite_record_delta_cached(
    alphas: tuple[int, ...], ms_t: tuple[int, ...], n: int
) -> dict[tuple[int, int], NDArray[np.float64]]:
    ms = np.asarray(ms_t, dtype=np.int64)
    ua = sorted(set(alphas))
    nm = ms.size
    ii, jj = np.triu_indices(nm)
    mi, mj = ms[ii], ms[jj]
    k = np.maximum(np.maximum(mi, mj) / _FIN_CAP, 1.0)
    a = np.maximum(1, np.rint(mi / k)).astype(np.int64)
    b = np.maximum(1, np.rint(mj / k)).astype(np.int64)
    big = _n_terms("overlapping", n, ms).astype(float)
    bi, bj = big[ii] / k, big[jj] / k
    # the distinct kernel pairs (a, b), (a, a), (b, b); their lag covariances once each
    keys = np.concatenate([np.stack([a, b], 1), np.stack([a, a], 1), np.stack([b, b], 1)])
    uk, inv = np.unique(keys, axis=0, return_inverse=True)
    inv = inv.reshape(-1)
    r, h = _lag_covariances(ua, uk[:, 0], uk[:, 1], _FIN_GRID)  # (keys, T, grid)
    p = ii.size
    cross, d1, d2 = inv[:p], inv[p : 2 * p], inv[2 * p :]
    nt = len(ua)
    xt = (r[:, :, :, None] * r[:, :, None, :]).reshape(uk.shape[0], r.shape[1], nt * nt)
    fin = _count_weighted(xt, cross, h, bi, bj).reshape(p, nt, nt)  # xt[u, h, (t, s)] = R^t R^s
    tt = np.arange(nt) * (nt + 1)  # the t = s entries
    xd = r * r
    v1 = _count_weighted(xd, d1, h, bi, bi)
    v2 = _count_weighted(xd, d2, h, bj, bj)
    zf = xt.sum(axis=1).reshape(-1, nt, nt)
    zd = xd.sum(axis=1)
    rho_fin = fin / np.sqrt(v1[:, :, None] * v2[:, None, :])
    rho_inf = zf[cross] / np.sqrt(zd[d1][:, :, None] * zd[d2][:, None, :])
    delta = rho_fin - rho_inf  # (pairs, T, T): t at m_i, s at m_j
    out = {}
    for t, at in enumerate(alphas):
        for s_, as_ in enumerate(alphas):
            x, y = ua.index(at), ua.index(as_)
            blk = np.zeros((nm, nm))
            blk[ii, jj] = delta[:, x, y]
            blk[jj, ii] = delta[:, y, x]
            out[(t, s_)] = blk
    return out


#: excess kurtosis kappa_4 / sigma^4 of angle quantization noise: the error of a uniform
#: quantizer is uniform on [-q/2, q/2) (Widrow & Kollar, Quantization Noise, 2008, ch. 4),
#: mu_4 / sigma^4 = 9/5, so -6/5 (the simulator's ``quantization`` draws exactly this);
#: fit_noise's default ``quantization_kurtosis``
QUANTIZATION_KURTOSIS = -6.0 / 5.0


def _quantization_kurtosis_rho(
    ms: NDArray[np.int64], n: int, kurtosis: float = QUANTIZATION_KURTOSIS
) -> NDArray[np.float64]:
    """Fourth-cumulant part of the quantization term's rho_QQ(i, j) (overlapping AVAR).

    For i.i.d. angle errors e of variance s^2 and excess kurtosis k, a quadratic form
    e'Ae has Cov(e'Ae, e'Be) = 2 s^4 tr(AB) + k s^4 sum_u A_uu B_uu; the Gaussian part is
    :func:`_rho_blocks` (+ :func:`_finite_record_delta`). With d_m[k] = e[k + 2m] - 2 e[k + m]
    + e[k], k < M = n + 1 - 2m, A_uu = a_u = [0 <= u < M] + 4 [m <= u < m + M] + [2m <= u <
    2m + M] and the Gaussian sum T_mm = sum_h R(h)^2 (M - |h|)_+ = 36 M + 32 (M - m)_+
    + 2 (M - 2m)_+, so the part added to rho_QQ(i, j) is k sum_u a_u b_u / (2 sqrt(T_ii T_jj)),
    exact for a finite record; about -0.31 (= -6/5 36/140) for every pair, the diagonal too:
    uniform quantization gives Q-dominated AVAR points 0.69x the Gaussian variance and
    correlations ~0.1 instead of ~0.4 (a test checks both against Monte Carlo).
    """
    m = ms.astype(float)
    big = np.maximum(n + 1 - 2 * m, 0.0)
    t = 36.0 * big + 32.0 * np.maximum(big - m, 0.0) + 2.0 * np.maximum(big - 2.0 * m, 0.0)
    w = np.array([1.0, 4.0, 1.0])
    start = m[:, None] * np.arange(3)[None, :]  # (n_m, 3): the three boxes [start, start + M)
    lo = np.maximum(start[:, None, :, None], start[None, :, None, :])
    end = start + big[:, None]
    hi = np.minimum(end[:, None, :, None], end[None, :, None, :])
    ab = (np.maximum(hi - lo, 0.0) * (w[:, None] * w[None, :])).sum(axis=(2, 3))
    return kurtosis * ab / (2.0 * np.sqrt(np.outer(t, t)))


#: c in Var(ybar_end - ybar_start) = (2 B^2/pi) (ln(L/tau) + c) for flicker rate averaged by the
#: window of each statistic (L >> tau): triangular 2-tau window (overlapping: the sum of m
#: overlapping differences telescopes to m^2-weighted triangles) and tau box (standard);
#: c = 2 Int_0^inf sin^2(lam u) w(u)/u du - ln lam for lam -> inf, w = sinc^4 or sinc^2
#: (evaluated numerically; the box value is 3/2 to 7 digits)
_FLICKER_END_C = {"overlapping": 1.15914, "standard": 1.5}


def _ramp_cross_sd(
    terms: Sequence[str], c: NDArray[np.float64], tau: NDArray[np.float64], ms: NDArray[np.int64], n: int, kind: str
) -> NDArray[np.float64]:
    """sd of the ramp x noise cross term of each AVAR point (0 when R is not fitted or is 0).

    A rate ramp R t is deterministic: each difference of tau-averages is d_r + e_k with
    d_r = R tau exactly, so A = d_r^2/2 + d_r mean(e) + mean(e^2)/2. The first part has no
    variance; the last is the noise's own chi-square part; the middle one has variance
    d_r^2 Var(mean e), uncorrelated with the chi-square part (odd Gaussian moment). The mean
    of the differences telescopes to (tau/L)(ybar_end - ybar_start), the difference of two
    window averages of the rate a lag L apart (L = (n + 1 - 2m)/fs overlapping, with
    triangular 2-tau windows; (floor(n/m) - 1) tau standard, tau boxes). Its variance for
    each noise term (continuous-time, L >> tau) is
    Q: 4 Q^2/(m tau^2) (overlapping) or 4 Q^2/tau^2; N: (4/3) N^2/tau or 2 N^2/tau;
    B: (2 B^2/pi)(ln(L/tau) + c) (``_FLICKER_END_C``); K: K^2 (L - 7 tau/15) or
    K^2 (L - tau/3) (random walk: integral of the squared difference of the two window
    cumulative weights). The cross term is nearly the same random variable (ybar_end -
    ybar_start, dominated by the slow terms) at every tau, so it is given correlation 1
    across tau: a rank-one addition s s' to the point covariance.
    """
    if "R" not in terms:
        return np.zeros(tau.size)
    cd = dict(zip(terms, c))
    if cd["R"] <= 0:
        return np.zeros(tau.size)
    m = ms.astype(float)
    over = kind == "overlapping"
    lag = (n + 1 - 2 * m) * tau / m if over else (np.floor(n / m) - 1.0) * tau
    lag = np.maximum(lag, tau)
    v = np.zeros(tau.size)
    v += cd.get("Q", 0.0) * (4.0 / 3.0) / tau**2 / (m if over else 1.0)
    v += cd.get("N", 0.0) * (4.0 / 3.0 if over else 2.0) / tau
    v += cd.get("B", 0.0) / math.log(2.0) * np.maximum(np.log(lag / tau) + _FLICKER_END_C[kind], 0.0)
    v += 3.0 * cd.get("K", 0.0) * (lag - (7.0 / 15.0 if over else 1.0 / 3.0) * tau)
    d_r = np.sqrt(2.0 * cd["R"]) * tau
    return d_r * (tau / lag) * np.sqrt(np.maximum(v, 0.0))


def _point_covariance(
    x: NDArray[np.float64],
    c: NDArray[np.float64],
    nu: NDArray[np.float64],
    rho: dict[tuple[int, int], NDArray[np.float64]],
    noise: NDArray[np.bool_] | None = None,
    cross: NDArray[np.float64] | None = None,
) -> NDArray[np.float64]:
    """Cov(A_i, A_j) = sum_{t,s} rho_ts(i, j) sd_t(i) sd_s(j) + cross_i cross_j.

    sd_t = C_t tau^p sqrt(2 / nu_t) (Greenhall nu) for the random terms (``noise`` True);
    deterministic terms (the ramp) have no chi-square part, only the rank-one ``cross``
    term of :func:`_ramp_cross_sd`.
    """
    sd = x * c[None, :] * np.sqrt(2.0 / nu)
    if noise is not None:
        sd = sd * noise[None, :]
    k = sd.shape[1]
    if len(rho) == k * k:  # every pair of terms: one contraction over the stacked blocks
        blocks = np.stack([rho[(t, s)] for t in range(k) for s in range(k)]).reshape(k, k, *rho[(0, 0)].shape)
        out = np.einsum("tsij,it,js->ij", blocks, sd, sd)
    else:
        out = np.zeros((x.shape[0], x.shape[0]))
        for (t, s), r in rho.items():
            out += r * np.outer(sd[:, t], sd[:, s])
    if cross is not None:
        out += np.outer(cross, cross)
    return out


@dataclass(frozen=True, slots=True, kw_only=True)
class FitRange:
    """Where the five-power-law model can be fitted, as found by :func:`fit_range`.

    Attributes
    ----------
    tau_min : float or None
        Shortest tau [s] to fit; None when nothing needs excluding.
    excluded : int
        Number of short-tau points below ``tau_min``.
    reason : str
        One line saying what was found (for the report).
    """

    tau_min: float | None
    excluded: int
    reason: str


def fit_range(curve: AllanCurve, *, false_alarm: float = 1e-3, n_terms: int = len(TERMS)) -> FitRange:
    """Find the filter-shaped short-tau region of an Allan deviation curve from the data.

    Parameters
    ----------
    curve : AllanCurve
        The deviation curve (any kind with the IEEE power laws, i.e. an Allan variance).
    false_alarm : float
        Probability that a curve that follows the model anywhere loses a point (Bonferroni
        over the tested triples of points).
    n_terms : int
        Points to keep at least (the fit needs as many as it has terms).

    Returns
    -------
    FitRange

    Notes
    -----
    A sum of power laws with non-negative coefficients, AVAR = sum_n C_n tau^n, is
    log-log convex (its log-log slope never decreases with tau: the slope is the
    C_n tau^n-weighted mean of the exponents n, and its derivative is their weighted
    variance >= 0). The sensor's anti-alias, decimation or on-chip low-pass filter removes
    white noise above its bandwidth, so the first octaves sit below the white-noise line
    and the curve is log-log *concave* there (slope -0.3 flattening into -0.5, e.g. the
    ADIS16405 records). So a significantly concave triple of points on the short-tau side
    (tau up to the ADEV minimum) marks points the model cannot follow; the fit starts at
    the middle point of the last such triple. With l = ln(ADEV), L = ln(tau), the test
    statistic of the triple (k, k+1, k+2) is the change of slope
    d = (l_{k+2} - l_{k+1}) / h2 - (l_{k+1} - l_k) / h1 (h the steps of L), with variance
    v_{k+2}/h2^2 + v_{k+1} (1/h1 + 1/h2)^2 + v_k/h1^2, v = Var(ln ADEV) = 1/(2 edf) (the
    curve's own edf). The correlation of neighbouring points (positive) is ignored: it
    makes this variance an overestimate, so the test is conservative. Concave when
    d < -z sd with z the one-sided normal quantile of ``false_alarm`` / (number of triples).
    """
    if not isinstance(curve, AllanCurve):
        raise TypeError(f"curve must be an AllanCurve; got {type(curve).__name__}")
    if not (0.0 < false_alarm < 1.0):
        raise ValueError(f"false_alarm must be in (0, 1); got {false_alarm!r}")
    tau = np.asarray(curve.tau, dtype=float)
    dev = np.asarray(curve.deviation, dtype=float)
    edf = np.asarray(curve.edf, dtype=float)
    ok = (dev > 0) & (edf > 0)
    if tau.size < 3 or not ok.all():
        return FitRange(tau_min=None, excluded=0, reason="too few or zero points to test the curvature")
    kmin = int(np.argmin(dev))  # short-tau side: up to the ADEV minimum
    n_tri = kmin - 1  # triples (k, k+1, k+2) with k + 2 <= kmin
    last = min(n_tri, tau.size - n_terms - 1)  # keep at least n_terms points
    if last <= 0:
        return FitRange(tau_min=None, excluded=0, reason="no short-tau region to test (ADEV minimum at the start)")
    ll, lt, v = np.log(dev), np.log(tau), 0.5 / edf
    h1, h2 = np.diff(lt)[:-1], np.diff(lt)[1:]
    d = (ll[2:] - ll[1:-1]) / h2 - (ll[1:-1] - ll[:-2]) / h1
    sd = np.sqrt(v[2:] / h2**2 + v[1:-1] * (1 / h1 + 1 / h2) ** 2 + v[:-2] / h1**2)
    z = _NORMAL.inv_cdf(1.0 - false_alarm / max(n_tri, 1))
    concave = np.flatnonzero(d[:last] < -z * sd[:last])
    if concave.size == 0:
        return FitRange(tau_min=None, excluded=0, reason="no filter-shaped (concave) short-tau region")
    j = int(concave[-1]) + 1
    return FitRange(
        tau_min=float(tau[j]),
        excluded=j,
        reason=(
            f"the first {j} point(s) (tau < {tau[j]:.3g} s) are filter-shaped: the log-log curve bends "
            f"down (concave) there, which no sum of the IEEE power laws can do"
        ),
    )


def lowpass_avar_bias(tau: ArrayLike, bandwidth: float, *, fs: float | None = None) -> NDArray[np.float64]:
    """Fractional deficit of the Allan variance of white rate noise behind a first-order low-pass.

    Parameters
    ----------
    tau : array_like
        Cluster times [s], > 0.
    bandwidth : float
        Corner (-3 dB) frequency f_c of the low-pass [Hz], > 0.
    fs : float, optional
        Sample rate [Hz] of the record (0 < f_c < fs/2); None: continuous time (fs -> inf).

    Returns
    -------
    ndarray
        b(tau) = 1 - AVAR(tau) / (N^2 / tau) in [0, 1), with

            b(tau) = (T / (2 tau)) (3 - 4 exp(-tau/T') + exp(-2 tau/T')),  T' = 1 / (2 pi f_c),

        T = T' in continuous time and T = 1 / (fs sinh(2 pi f_c / fs)) <= T' for a record
        sampled at fs; b -> 3 T / (2 tau) for tau >> T'.

    Notes
    -----
    White rate noise N^2 (one-sided PSD) through H(s) = 1/(1 + s T') is a first-order
    Gauss-Markov process with autocorrelation (N^2/(2T')) exp(-|t|/T'); its Allan variance is
    (N^2/tau) (1 - b(tau)) (IEEE Std 952-1997 Annex C, exponentially correlated noise with
    q_c T' = N). Sampled at fs (point samples of that process, or the IIR y_k = a y_(k-1) +
    (1 - a) x_k with a = exp(-2 pi f_c / fs): the same autocorrelation a^|j|), the variance of
    a sum of m samples is D(m) = sigma^2 (m - c (1 - a^m)), c = 2 a / (1 - a^2) =
    1/sinh(2 pi f_c / fs), and AVAR = (4 D(m) - D(2m)) / (2 m^2) gives the expression above
    with T = c / fs (a test checks it against simulation). For any unit-DC-gain filter the
    large-tau deficit is 3 c / (2 tau) with c = (1/pi^2) int_0^inf (1 - |H(f)|^2) / f^2 df:
    1/(2 pi f_c) first order, 1/(2 pi n f_c sin(pi/(2n))) for an n-th order Butterworth
    (0.65x the first-order value at n = 4), 0.148/f_c for a moving average of -3 dB
    frequency f_c (docs/physics.md 1.7).
    """
    tau = _positive_tau(tau)
    bw = _check_bandwidth(bandwidth, fs)
    t_corr = 1.0 / (2.0 * math.pi * bw)
    t = t_corr if fs is None else 1.0 / (float(fs) * math.sinh(2.0 * math.pi * bw / float(fs)))
    x = tau / t_corr
    return (t / (2.0 * tau)) * (3.0 - 4.0 * np.exp(-x) + np.exp(-2.0 * x))


def _check_bandwidth(bandwidth: Any, fs: float | None, name: str = "bandwidth") -> float:
    if isinstance(bandwidth, bool) or not isinstance(bandwidth, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a real number [Hz]; got {bandwidth!r}")
    bw = float(bandwidth)
    if not (math.isfinite(bw) and bw > 0.0):
        raise ValueError(f"{name} must be finite and > 0 Hz; got {bandwidth!r}")
    if fs is not None and not bw < fs / 2.0:
        raise ValueError(
            f"{name} must be < the Nyquist frequency fs/2 = {fs / 2.0:g} Hz (a wider filter cannot shape a record "
            f"sampled at {fs:g} Hz); got {bw:g} Hz"
        )
    return bw


#: default of ``bandwidth_bias``: the filter's bias of an included white-noise point is at most
#: this fraction of the point's standard error (see :func:`bandwidth_range`)
BANDWIDTH_BIAS = 0.1


def bandwidth_range(curve: AllanCurve, bandwidth: float, *, bias: float = BANDWIDTH_BIAS) -> FitRange:
    """Shortest tau at which a stated sensor bandwidth no longer biases the white-noise points.

    Parameters
    ----------
    curve : AllanCurve
        The Allan variance curve (overlapping or standard) to be fitted.
    bandwidth : float
        The sensor's bandwidth f_c [Hz] (-3 dB frequency of its anti-alias / decimation /
        on-chip low-pass), 0 < f_c < fs/2.
    bias : float
        Largest allowed ratio of the filter's bias of a white-noise Allan variance point to
        that point's standard error, > 0 (default :data:`BANDWIDTH_BIAS` = 0.1).

    Returns
    -------
    FitRange
        ``tau_min`` is the first curve tau with b(tau) <= bias * sqrt(2 / nu0(tau)); None when
        that is the first point already.

    Notes
    -----
    Rule: a point tau_i is kept when tau_i >= 1/f_c and the first-order low-pass deficit
    b(tau_i) (:func:`lowpass_avar_bias` at the curve's fs, ~ 3/(4 pi f_c tau)) is at most
    ``bias`` times the relative standard error sqrt(2/nu0_i) of that point for white rate
    noise (nu0 the Greenhall edf of white FM at m_i for this record and statistic; ~ 3 n / (2 m)
    overlapping). b falls and the standard error grows with tau, so every later point passes
    too. For tau >> 1/f_c the rule is tau_min ~ (3 / (4 pi f_c bias))^(2/3) (3 T_rec / 4)^(1/3)
    (overlapping, record length T_rec): longer records, whose points are more precise, start
    later. With the default 0.1 a kept point's bias changes its chi-square contribution by
    about 1 % and moves the fitted N^2 by a fraction of its standard error; ``bias=0.01`` is
    stricter. Why it is conservative: the white-noise standard error is the smallest a point
    can have (other noise only adds variance); and from tau = 1/f_c on, the first-order
    deficit bounds that of Butterworth low-passes of order 2, 4 and 8 (0.5-0.93x of it) and
    of a moving average of the same -3 dB frequency (0.84-0.92x), computed exactly from
    their impulse responses for f_c / fs = 0.01-0.45 (below 1/f_c higher orders can exceed
    it, up to 1.9x; a test checks the 4th order).
    """
    if not isinstance(curve, AllanCurve):
        raise TypeError(f"curve must be an AllanCurve; got {type(curve).__name__}")
    bw = _check_bandwidth(bandwidth, curve.fs)
    if isinstance(bias, bool) or not isinstance(bias, (int, float)) or not (math.isfinite(bias) and bias > 0):
        raise ValueError(f"bandwidth_bias must be finite and > 0; got {bias!r}")
    tau = np.asarray(curve.tau, dtype=float)
    ms = curve.m
    nu0 = _edf(curve.kind if curve.kind in _D else "overlapping", np.zeros(ms.size, dtype=np.int64), ms, curve.n_samples)
    b = lowpass_avar_bias(tau, bw, fs=curve.fs)
    ok = (b <= bias * np.sqrt(2.0 / nu0)) & (tau >= (1.0 - 1e-9) / bw)
    rule = f"a first-order low-pass at the stated bandwidth {bw:g} Hz biases a white-noise point by more than {bias:g} of its standard error"
    if ok[0]:
        return FitRange(tau_min=None, excluded=0, reason=f"no tau excluded by the bandwidth: nowhere does {rule[2:]}")
    if not ok.any():
        # the rule's limit lies beyond the curve: report it, so the fit's refusal can say so
        return FitRange(
            tau_min=float(tau[-1]) * 2.0,
            excluded=int(tau.size),
            reason=f"every point (tau <= {tau[-1]:.3g} s) is excluded: {rule} at every tau of the curve",
        )
    j = int(np.flatnonzero(ok)[0])
    return FitRange(
        tau_min=float(tau[j]),
        excluded=j,
        reason=f"the first {j} point(s) (tau < {tau[j]:.3g} s) are excluded: there {rule}",
    )


@_single_blas
def fit_noise(
    curve_or_rate: AllanCurve | ArrayLike,
    fs: float | None = None,
    *,
    terms: Sequence[str] = TERMS,
    max_iter: int = 20,
    tau_min: float | str | None = None,
    tau_max: float | None = None,
    misfit_p: float = 1e-3,
    bandwidth: float | None = None,
    bandwidth_bias: float = BANDWIDTH_BIAS,
    quantization_kurtosis: float = QUANTIZATION_KURTOSIS,
) -> NoiseFit:
    """Joint weighted non-negative least-squares fit of the IEEE 952 terms to an Allan variance.

    Parameters
    ----------
    curve_or_rate : AllanCurve or array_like
        An overlapping or standard :class:`AllanCurve`, or rate samples [any unit u] (then the
        overlapping deviation at octave taus is computed first).
    fs : float, optional
        Sample rate [Hz]; required with rate samples, ignored with a curve.
    terms : sequence of str
        Subset of ("Q", "N", "B", "K", "R") to fit.
    max_iter : int
        Maximum number of reweighting iterations (stops earlier when the C_n change by less
        than 1e-9 relative).
    tau_min, tau_max : float, optional
        Fit only the points with tau_min <= tau <= tau_max [s] (relative tolerance 1e-9);
        None: no limit. ``tau_min="auto"`` starts above the filter-shaped short-tau region
        that :func:`fit_range` finds in the data (an anti-alias or decimation filter bends
        the first octaves, where no sum of the five power laws can follow).
    misfit_p : float
        Level of the goodness-of-fit test: a fit with p-value below it is a misfit
        (``NoiseFit.misfit``), and its standard errors are multiplied by sqrt(chi2/E[chi2]).
    bandwidth : float, optional
        The sensor's bandwidth [Hz] (0 < bandwidth < fs/2), when known: taus where its
        low-pass still biases the white-noise points are not fitted (:func:`bandwidth_range`,
        with ``bandwidth_bias``). Combined with ``tau_min`` (a number or "auto"): the larger
        tau_min wins, and ``NoiseFit.range_rule`` / ``range_reason`` say which rule set it.
    bandwidth_bias : float
        Ratio of filter bias to a point's standard error that :func:`bandwidth_range` allows.
    quantization_kurtosis : float
        Excess kurtosis (>= -2) of the angle errors behind the Q term, used in the point
        covariance of an overlapping curve: -6/5 (default) for a uniform quantizer's error
        (angle or pulse output), 0 for Gaussian white angle noise (e.g. a Q term that is
        not quantization).

    Returns
    -------
    NoiseFit
        Coefficients in the units implied by u (module docstring), with intervals.

    Notes
    -----
    Model (docs/physics.md 1.5): AVAR(tau) = sum_n C_n tau^n with C_-2 = 3 Q^2, C_-1 = N^2,
    C_0 = (2 ln2/pi) B^2 (the flicker plateau, reached for tau > ~1.6/f_high), C_1 = K^2/3,
    C_2 = R^2/2. Each AVAR point A_i is treated as (sigma_i^2/nu_i) chi2(nu_i) with
    variance 2 sigma_i^2 / nu_i, where sigma_i^2 is the *fitted* curve (not the noisy A_i:
    weighting by the data itself biases the fit low) and nu_i the edf of the estimate for
    the noise type that dominates the fitted curve at tau_i (alpha +2 Q, 0 N, -1 B, -2 K
    and R; Greenhall edf as in :func:`allan_deviation`). The weighted problem
    min || W^1/2 (X C - A) ||, C >= 0, is solved by Lawson-Hanson active-set NNLS
    (:func:`_nnls_enumerate`, equal to scipy.optimize.nnls to rounding) on column-scaled X,
    starting from the weights of the curve's own estimate, and reweighted until stable.

    Uncertainty (the point of the method; checked by benchmarks/coverage_fit.py): the
    AVAR points are strongly correlated across tau (e.g. 0.4-0.5 between any two octaves
    for quantization noise, 0.5 between neighbouring octaves for white rate, 0.9 for RRW),
    and at a crossover two noise types share each point. So the covariance V of the points
    is modelled from the fitted model: V_ij = sum_{t,s} rho_ts(i, j) sd_t(i) sd_s(j), with
    sd_t(i) = C_t tau_i^p_t sqrt(2 / nu_t(i)) (Greenhall edf of term t's noise type at m_i,
    which includes the short-record edge effects) and rho_ts(i, j) the correlation of term
    t's noise in A_i with term s's noise in A_j for Gaussian noise, from the frequency-domain
    form of Cov(A_i, A_j) (see ``_rho_blocks``), for the overlapping kind corrected for the
    finite record (``_finite_record_delta``: the exact lag-sum form of 2 tr(A_i S A_j S) with
    the counts of overlapping term pairs, minus its n >> m limit; it lowers e.g. the RRW
    correlation of the last two octaves of a 4 h record from 0.89 to 0.82) and, for the
    quantization term, by the fourth cumulant of uniform angle quantization
    (``_quantization_kurtosis_rho``: Q-dominated points have 0.69x the Gaussian variance and
    correlations ~0.1, not ~0.4). The weights are 1/V_ii; the covariance of
    the estimate is the sandwich (X'WX)^-1 X'W V W X (X'WX)^-1, over all fitted terms
    (including any the NNLS set to 0, so a bound stays honest). Intervals on C_n are
    C_n +- z sqrt(Cov_nn) (z = 1 and 1.96), clipped at 0 and mapped to the coefficient by the
    monotone C -> sqrt(C / scale), which keeps their coverage.
    Goodness of fit: chi2 = sum_i r_i^2 / V_ii, r = A - X C over the fitted points, each
    residual standardised by its modelled variance; dof = fitted points - terms kept (C_n > 0).
    Its law if the model holds: with H the hat matrix of the weighted fit over the kept terms,
    z = D^-1 (I - H) A (D^2 = diag V) has covariance S = D^-1 (I - H) V (I - H)' D^-1, so chi2
    = sum_k lambda_k chi2_1 (lambda the eigenvalues of S; mean ``chi2_expected`` = trace S, about
    0.45 dof on the five-term model: the residuals are strongly correlated), and p = P(chi2 >=
    observed) is read from the 4-cumulant approximation of Liu, Tang and Zhang (2009).
    Why not r' V^-1 r against chi2(dof), as before: the modelled variances V_ii match the
    scatter of the points over seeds to ~2 %, but the modelled correlations were too high
    (measured over 400 seeds of coverage_fit.py's model at 4 h: neighbouring octaves at
    the long-tau end 0.93 modelled vs 0.88 measured, 0.77 vs 0.65 two octaves apart, 0.40 vs
    0.26 for the first two octaves; the asymptotic n >> m correlation model ignores the
    record's ends, which the Greenhall variances include). V^-1 then amplifies the residuals
    along the near-null directions of V (differences of neighbouring points), and that
    statistic ran at 1.34 dof on average with a variance 6.7x its nominal one: false alarms
    at p < 1e-2 on 10.2 % of records that follow the model and at p < 1e-3 on 4.3 %
    (1000 seeds, 4 h at 10 Hz; 95 % intervals 8.4-12.2 % and 3.1-5.8 %). The AVAR points'
    skewness (chi-square with few edf at long tau) was not the cause: a log-domain
    version of r' V^-1 r was as far off. Standardised by their own variances, the residuals
    depend on the modelled correlations only through the weights lambda, smoothly: measured
    (benchmarks/misfit_false_alarm.py, 1000 seeds each, exact binomial 95 % intervals):
    4 h at 10 Hz p < 1e-2 on 0.90 % (0.41-1.70 %), p < 1e-3 on 0.20 % (0.02-0.72 %), the same
    with ``tau_min="auto"``; 20 h at 10 Hz 0.90 % (0.41-1.70 %) and 0.30 % (0.06-0.87 %);
    1 h at 10 Hz 0.30 % (0.06-0.87 %) and 0/1000 (0-0.37 %), i.e. slightly conservative on
    short records (with the finite-record and quantization corrections of V; before them:
    0.80/0.20 %, 0.80/0.30 %, 0.30/0 %). The former statistic, on the corrected V: 2.8 % and
    1.2 % at 1 h, 5.4 % and 2.8 % at 4 h, 10.0 % and 4.2 % at 20 h (3.7/1.8, 10.2/4.3 and
    17.5/8.7 % on the uncorrected V): V is closer but its near-null directions are still off.
    tests/analysis/test_allan_misfit_calibration.py checks the rate at p < 0.1 and 0.01. The Liu-Tang-Zhang tail is exact for equal lambda
    and within 0.5-11 % of p down to p = 1e-3 for the uneven ones tested (a test checks it
    against Monte Carlo). On a misfit (p < ``misfit_p``) every standard error is
    multiplied by the Birge ratio sqrt(chi2 / chi2_expected) (as the Particle Data Group
    scales errors of inconsistent measurements), so no interval stays tight on data the
    model does not describe; identifiability is then judged on the widened intervals.
    A term is *identifiable* when it is the largest term of the fitted curve at one fitted
    tau at least and its 95 % interval excludes 0; otherwise ``value`` is None and
    ``upper_bound`` = coefficient(C_n + 1.645 sqrt(Cov_nn)) is a one-sided 95 % bound.

    Assumptions: Gaussian noise, except quantization (uniform angle error); independent
    terms; the five power laws only (a
    Gauss-Markov bump or a sinusoid is absorbed into the nearest terms, and an anti-alias
    filter that bends the first octaves biases Q/N); bias instability on its plateau at the
    fitted taus (tau > ~1.6/f_high, i.e. above ~3 samples when the flicker band reaches
    fs/2). The ramp is deterministic: it adds no chi-square variance of its own, only the
    cross term d_r mean(e) with the noise (``_ramp_cross_sd``; a rank-one term of V).
    Before commit 5994ca9 it was given random-walk-rate variance instead, which overstated the
    variance of the longest-tau points up to 2.6x (measured over 200 seeds) and K's
    standard error by 10 % (K 68 % coverage 75.5 %).

    Measured coverage (benchmarks/coverage_fit.py, 200 seeds, 20 h at 10 Hz, each term in
    charge of about a decade of tau; binomial standard error 1.5 % at 95 %, 3.3 % at 68 %):

    ====  ==========  =====  =====
    term  identified  95 %   68 %
    ====  ==========  =====  =====
    Q     200/200     93.5   68.0
    N     200/200     95.0   75.5
    B     200/200     95.0   69.0
    K     200/200     95.5   68.0
    R     108/200     99.1   74.1   (given identified; 93.5 % of all seeds at 95 %)
    ====  ==========  =====  =====

    (Before the finite-record and quantization corrections: Q 96.0/73.0, N 95.5/76.5,
    B 95.0/69.0, K 95.5/69.0, R 99.1/73.8.) Std over the seeds of (C - C_true)/se: Q 1.01
    (0.91 before: the Gaussian model overstated the variance of the quantization points by
    1/0.69), B 1.00, K 1.01 (1.00 and 1.01 before: the finite-record correction moves the
    long-tau correlations, but K's and B's errors were already right), N 0.90 (0.90 before,
    kurtosis 3.8): N's 68 % interval still over-covers and neither correction explains it.
    It comes with the flicker term: the same model without B (fitting Q, N, K, R) gives N
    sd 1.01 and 68 % coverage 68.5 %; without Q (fitting N, B, K, R) sd 0.93 and a mean
    standardised error of +0.47 (200 seeds each). Not resolved: V's B terms use pure 1/f
    noise on its plateau, while the simulated flicker is a sum of first-order poles. R, when
    identified, is biased high (median 1.15x truth): it is identified only on seeds whose
    estimate is high.
    """
    if isinstance(curve_or_rate, AllanCurve):
        curve = curve_or_rate
    else:
        if fs is None:
            raise ValueError("fs [Hz] is required when fit_noise is given rate samples; got None")
        curve = allan_deviation(curve_or_rate, fs)
    if curve.kind not in _FIT_KINDS:
        raise ValueError(f"fit_noise needs an Allan variance curve, kind in {_FIT_KINDS}; got {curve.kind!r}")
    if isinstance(terms, str):
        terms = (terms,)
    terms = tuple(terms)
    bad = [t for t in terms if t not in TERMS]
    if bad or not terms or len(set(terms)) != len(terms):
        raise ValueError(f"terms must be distinct names from {TERMS}; got {terms!r}")
    terms = tuple(t for t in TERMS if t in terms)  # canonical order
    if isinstance(misfit_p, bool) or not isinstance(misfit_p, (int, float)) or not (0.0 <= misfit_p < 1.0):
        raise ValueError(f"misfit_p must be a probability in [0, 1); got {misfit_p!r}")
    qk = quantization_kurtosis
    if isinstance(qk, bool) or not isinstance(qk, (int, float)):
        raise TypeError(f"quantization_kurtosis must be a number; got {qk!r}")
    if not (-2.0 <= qk < math.inf):
        raise ValueError(f"quantization_kurtosis must be >= -2 (an excess kurtosis); got {qk!r}")
    tau_all = np.asarray(curve.tau, dtype=float)
    a_all = np.asarray(curve.variance, dtype=float)
    if not np.any(a_all > 0):
        raise ValueError(
            "rate is constant (zero variance): Allan deviation is 0 at every tau; nothing to fit"
        )
    auto = isinstance(tau_min, str)
    rule, reason = ("user", f"tau_min = {tau_min!r} s given") if tau_min is not None else ("", "")
    if auto:
        if tau_min != "auto":
            raise ValueError(f"tau_min must be a number [s], 'auto' or None; got {tau_min!r}")
        found = fit_range(curve, n_terms=len(terms))
        tau_min, rule, reason = found.tau_min, ("data" if found.tau_min is not None else ""), found.reason
    if bandwidth is not None:
        limit = bandwidth_range(curve, bandwidth, bias=bandwidth_bias)
        current = _check_tau_limit("tau_min", tau_min)
        if limit.tau_min is not None and (current is None or limit.tau_min > current * (1 + 1e-9)):
            tau_min, rule, reason = limit.tau_min, "bandwidth", limit.reason
    lo_t = _check_tau_limit("tau_min", tau_min)
    hi_t = _check_tau_limit("tau_max", tau_max)
    used = np.ones(tau_all.size, dtype=bool)
    if lo_t is not None:
        used &= tau_all >= lo_t * (1 - 1e-9)
    if hi_t is not None:
        used &= tau_all <= hi_t * (1 + 1e-9)
    if lo_t is not None and hi_t is not None and lo_t > hi_t:
        raise ValueError(f"tau_min must be <= tau_max; got tau_min = {lo_t!r} s > tau_max = {hi_t!r} s")
    if int(used.sum()) < len(terms):
        raise ValueError(
            f"the fit range [{lo_t or tau_all[0]:.6g}, {hi_t or tau_all[-1]:.6g}] s holds {int(used.sum())} "
            f"of the curve's tau points, fewer than the {len(terms)} terms to fit ({', '.join(terms)})"
            + (f" (tau_min set by the {rule} rule: {reason})" if rule in ("data", "bandwidth") else "")
        )
    a = a_all[used]
    if not np.all(a > 0):
        i = int(np.flatnonzero(~(a > 0))[0])
        raise ValueError(
            f"curve.deviation must be > 0 at every tau to weight the fit; got 0 at tau = {float(tau_all[used][i])!r} s"
        )

    # per-point model pieces over the whole curve, sliced to the fitted points below
    ms_all = curve.m
    nu_all = np.stack(
        [_edf(curve.kind, np.full(ms_all.size, _ALPHA[t], dtype=np.int64), ms_all, curve.n_samples) for t in terms],
        axis=1,
    )
    rho_all = _rho_blocks([_ALPHA[t] for t in terms], ms_all)
    if curve.kind == "overlapping":  # the record's ends: exact finite-n correction of rho
        delta = _finite_record_delta([_ALPHA[t] for t in terms], ms_all, curve.n_samples)
        rho_all = {k: r + delta[k] for k, r in rho_all.items()}
        if "Q" in terms:  # uniform angle quantization: its fourth cumulant (not Gaussian)
            q = terms.index("Q")
            if qk != 0:
                kq = _quantization_kurtosis_rho(ms_all, curve.n_samples, float(qk))
                rho_all[(q, q)] = rho_all[(q, q)] + kq
    fit, _ = _fit_core(curve, terms, used, nu_all, rho_all, max_iter, misfit_p)
    if auto:
        # past the concave region the filter can still pull the first points off the model: drop
        # the first fitted point while the fit misfits and dropping it lowers chi2 by more than
        # the chi2(1) quantile at the misfit level (the point is an outlier of the model there)
        from scipy import special  # chi2.isf(p, nu) = chdtri(nu, p), as scipy.stats computes it

        gain = float(special.chdtri(1, misfit_p)) if misfit_p > 0 else math.inf
        while fit.misfit and int(used.sum()) > len(terms) + 1:
            trial = used.copy()
            trial[int(np.flatnonzero(used)[0])] = False
            fit2, _ = _fit_core(curve, terms, trial, nu_all, rho_all, max_iter, misfit_p)
            if not (fit.chi2 - fit2.chi2 > gain):
                break
            used, fit = trial, fit2
    return replace(fit, range_rule=rule, range_reason=reason)


def _fit_core(
    curve: AllanCurve,
    terms: tuple[str, ...],
    used: NDArray[np.bool_],
    nu_all: NDArray[np.float64],
    rho_all: dict[tuple[int, int], NDArray[np.float64]],
    max_iter: int,
    misfit_p: float,
) -> tuple[NoiseFit, NDArray[np.float64]]:
    """The weighted NNLS fit of :func:`fit_noise` on the points ``used``; also the standardised residuals."""
    tau = np.asarray(curve.tau, dtype=float)[used]
    a = np.asarray(curve.variance, dtype=float)[used]

    powers = np.array([_POWER[t] for t in terms], dtype=float)
    x = tau[:, None] ** powers[None, :]
    ms = curve.m[used]
    nu = nu_all[used]  # edf of each point for each term's noise type, nu[i, j]
    sel = np.ix_(used, used)
    rho = {k: r[sel] for k, r in rho_all.items()}
    noise = np.array([t != "R" for t in terms])  # the ramp is deterministic (see _ramp_cross_sd)
    var = 2.0 * a**2 / np.asarray(curve.edf, dtype=float)[used]  # first pass: the curve's own edf
    c = np.zeros(len(terms))
    v = np.diag(var)
    it = 0
    for it in range(1, max_iter + 1):
        c_new = _wnnls(x, a, var)
        done = np.allclose(c_new, c, rtol=1e-9, atol=0.0)
        c = c_new
        v_new = _point_covariance(
            x, c, nu, rho, noise, _ramp_cross_sd(terms, c, tau, ms, curve.n_samples, curve.kind)
        )
        var_new = np.diag(v_new)
        if np.all(var_new > 0):
            v, var = v_new, var_new
        else:  # no fitted term at some tau: keep the last weights there
            var = np.where(var_new > 0, var_new, var)
            v = v_new + np.diag(np.where(var_new > 0, 0.0, var))
        if done:
            break

    # sandwich covariance of the weighted LS estimate: (X'WX)^-1 X'W V W X (X'WX)^-1,
    # W = diag(1/var), V the modelled covariance of the AVAR points (correlated across tau)
    xw = x / var[:, None]
    scale = np.sqrt(np.einsum("ij,ij->j", x, xw))
    scale[scale == 0] = 1.0
    bread = np.linalg.pinv((x / scale).T @ (xw / scale), rcond=1e-13)
    meat = (xw / scale).T @ v @ (xw / scale)
    cov = (bread @ meat @ bread) / np.outer(scale, scale)

    resid = (a - x @ c) / np.sqrt(np.diag(v))
    chi2, dof, expected, p_value = _goodness(a - x @ c, v, x, var, c > 0)
    misfit = bool(dof > 0 and p_value < misfit_p)
    inflation = math.sqrt(chi2 / expected) if misfit else 1.0
    cov = cov * inflation**2
    se = np.sqrt(np.clip(np.diag(cov), 0.0, None))

    contrib = x * c[None, :]
    dominant = set(int(j) for j in np.argmax(contrib, axis=1)) if np.any(c > 0) else set()
    coeffs: dict[str, Coefficient] = {}
    for j, name in enumerate(terms):

        def coef(v: float, name: str = name) -> float:
            return avar_to_coefficient(name, v)

        lo95, hi95 = c[j] - _Z95 * se[j], c[j] + _Z95 * se[j]
        ident = bool(c[j] > 0 and lo95 > 0 and j in dominant)
        coeffs[name] = Coefficient(
            name=name,
            value=coef(c[j]) if ident else None,
            ci68=(coef(c[j] - _Z68 * se[j]), coef(c[j] + _Z68 * se[j])),
            ci95=(coef(lo95), coef(hi95)),
            identifiable=ident,
            upper_bound=coef(c[j] + _Z95_ONE_SIDED * se[j]),
            power=_POWER[name],
        )
    return NoiseFit(
        coefficients=coeffs,
        curve=curve,
        avar_coefficients={t: float(v) for t, v in zip(terms, c)},
        covariance=cov,
        iterations=it,
        used=used,
        chi2=chi2,
        dof=dof,
        chi2_expected=expected,
        p_value=p_value,
        misfit=misfit,
        inflation=inflation,
        point_covariance=v,
    ), resid


def _check_tau_limit(name: str, value: Any) -> float | None:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a number [s] or None; got {value!r}")
    if not (math.isfinite(float(value)) and float(value) > 0):
        raise ValueError(f"{name} must be finite and > 0 s; got {value!r}")
    return float(value)


def _goodness(
    r: NDArray[np.float64],
    v: NDArray[np.float64],
    x: NDArray[np.float64],
    var: NDArray[np.float64],
    kept: NDArray[np.bool_],
) -> tuple[float, int, float, float]:
    """chi2 = sum r_i^2 / V_ii, dof, E[chi2] and P(chi2 >= observed) under the model.

    The residuals of the weighted fit (weights 1/var, the kept columns of ``x``; at the NNLS
    solution the kept terms are the unconstrained weighted fit on those columns) are
    r = (I - H) A with H = X_k (X_k' W X_k)^-1 X_k' W, so the standardised residuals z = D^-1 r
    (D^2 = diag V) have covariance S = D^-1 (I - H) V (I - H)' D^-1 and, for Gaussian points,
    chi2 = z'z = sum_k lambda_k chi2_1 with lambda the eigenvalues of S. Its tail is the
    4-cumulant non-central chi-square approximation of H. Liu, Y. Tang and H. H. Zhang,
    "A new chi-square approximation to the distribution of non-negative definite quadratic
    forms in non-central normal variables", Comput. Stat. Data Anal. 53 (2009) 853-856.
    """
    dof = r.size - int(np.count_nonzero(kept))
    if dof <= 0:
        return float("nan"), 0, float("nan"), float("nan")
    from scipy import special  # chi2.sf = chdtrc; ncx2.cdf = chndtr (as scipy.stats computes them)

    d = np.sqrt(np.diag(v))
    z = r / d
    chi2 = float(z @ z)
    xk = x[:, kept] / np.sqrt(var)[:, None]  # W^1/2 X_k
    q, _ = np.linalg.qr(xk)
    sw = np.sqrt(var) / d  # W^-1/2 D^-1 (diagonal; ~1 at convergence, where var = diag V)
    # I - H = W^-1/2 (I - Q Q') W^1/2, so D^-1 (I - H) = diag(sw) (I - Q Q') W^1/2
    m = (np.eye(r.size) - q @ q.T) * (sw[:, None] / np.sqrt(var)[None, :])
    s = m @ v @ m.T
    lam = np.clip(np.linalg.eigvalsh((s + s.T) / 2.0), 0.0, None)
    c1, c2, c3, c4 = (float(np.sum(lam**k)) for k in (1, 2, 3, 4))
    return chi2, dof, c1, _ltz_sf(chi2, c1, c2, c3, c4, special)


def _ltz_sf(q: float, c1: float, c2: float, c3: float, c4: float, special: Any) -> float:
    """P(Q >= q) for Q = sum lambda_k chi2_1 from its cumulant sums c_k = sum lambda^k (Liu-Tang-Zhang 2009)."""
    if c2 <= 0.0:
        return float("nan")
    s1, s2 = c3 / c2**1.5, c4 / c2**2
    if s1 * s1 > s2:
        a = 1.0 / (s1 - math.sqrt(s1 * s1 - s2))
        delta = s1 * a**3 - a * a
        ell = a * a - 2.0 * delta
    else:
        a, delta, ell = 1.0 / s1, 0.0, 1.0 / (s1 * s1)
    t = (q - c1) / math.sqrt(2.0 * c2) * math.sqrt(2.0) * a + ell + delta
    if t <= 0.0:  # below the support of the matched chi-square (a small chi2): no evidence of misfit
        return 1.0
    if delta > 0.0:
        return float(max(1.0 - special.chndtr(t, ell, delta), 0.0))
    return float(special.chdtrc(ell, t))


# ---------------------------------------------------------------------------------- public: read-off
#: tau [s] at which each single-term asymptote equals its coefficient (IEEE 952 C.1):
#: scale tau^power = 1, i.e. sqrt(3), 1, 3, sqrt(2) for Q, N, K, R
_READ_TAU = {t: _SCALE[t] ** (-1.0 / _POWER[t]) for t in TERMS if _POWER[t] != 0}
#: log-log slope of each term's Allan deviation
_SLOPE = {t: _POWER[t] / 2.0 for t in TERMS}


def _normalised(name: str, tau: NDArray[np.float64], dev: NDArray[np.float64]) -> NDArray[np.float64]:
    """Coefficient implied by each point if the single term ``name`` made the whole deviation:
    sqrt(dev^2 tau^-power / scale) (:func:`avar_to_coefficient` per point)."""
    return np.sqrt(dev * dev * tau ** (-float(_POWER[name])) / _SCALE[name])


def slope_readoff(
    curve: AllanCurve | Sequence[AllanCurve],
    *,
    fit_ranges: Mapping[str, tuple[float, float]] | None = None,
    slope_tolerance: float = 0.25,
) -> dict[str, float | None]:
    """IEEE Std 952 graphical read-off of Q, N, B, K, R from an Allan deviation curve.

    Parameters
    ----------
    curve : AllanCurve or sequence of AllanCurve
        The deviation curve(s). Several curves (e.g. the three axes of a triad) are pooled
        in ``fit_ranges`` mode; the graphical mode needs exactly one.
    fit_ranges : mapping of str to (tau_min, tau_max), optional
        Fixed-slope mode: for each named term, the line of that term's slope is fitted by
        least squares in log-log coordinates through all points with tau_min <= tau <=
        tau_max [s] (relative tolerance 1e-9), i.e. the coefficient is the geometric mean of
        the slope-normalised deviations: N = gm(sigma sqrt(tau)), Q = gm(sigma tau)/sqrt(3),
        K = sqrt(3) gm(sigma/sqrt(tau)), R = sqrt(2) gm(sigma/tau), B = gm(sigma)/0.6643.
        This is the "AVLR" computation of the R package avar (Guerrier et al.). Terms not
        named come back None.
    slope_tolerance : float
        Graphical mode: a term is read only if some segment of the curve has a log-log slope
        within this distance of the term's slope (default 0.25, half way to the next term).

    Returns
    -------
    dict of str to float or None
        "Q" [u*s], "N" [u*s^0.5], "B" [u], "K" [u/s^0.5], "R" [u/s]; None when not readable.

    Notes
    -----
    Graphical mode (IEEE 952-1997 C.1; docs/physics.md 1.4; the MathWorks procedure): for the
    slopes -1, -1/2, +1/2, +1 find the segment between adjacent taus whose log-log slope is
    closest to the target, draw the line of exactly that slope through the segment's
    log-midpoint and read it at tau = sqrt(3) s (Q), 1 s (N), 3 s (K), sqrt(2) s (R).
    B = min(sigma) / sqrt(2 ln2 / pi) = min / 0.6643: the IEEE *coefficient*, not the ADEV
    minimum that many datasheets quote as "bias instability" (0.6643 B).
    """
    curves = [curve] if isinstance(curve, AllanCurve) else list(curve)
    if not curves or not all(isinstance(c, AllanCurve) for c in curves):
        raise TypeError(f"curve must be an AllanCurve or a sequence of them; got {curve!r}")
    out: dict[str, float | None] = {t: None for t in TERMS}
    if fit_ranges is not None:
        tau = np.concatenate([np.asarray(c.tau, float) for c in curves])
        dev = np.concatenate([np.asarray(c.deviation, float) for c in curves])
        for name, rng_ in fit_ranges.items():
            if name not in TERMS:
                raise ValueError(f"fit_ranges keys must be in {TERMS}; got {name!r}")
            lo, hi = (float(v) for v in rng_)
            if not (0 < lo <= hi):
                raise ValueError(f"fit_ranges[{name!r}] must satisfy 0 < tau_min <= tau_max [s]; got {rng_!r}")
            sel = (tau >= lo * (1 - 1e-9)) & (tau <= hi * (1 + 1e-9))
            if not np.any(sel):
                raise ValueError(f"fit_ranges[{name!r}] = {rng_!r} s contains no tau of the curve")
            out[name] = float(np.exp(np.mean(np.log(_normalised(name, tau[sel], dev[sel])))))
        return out

    if len(curves) != 1:
        raise ValueError(f"the graphical read-off takes one curve; got {len(curves)} (use fit_ranges to pool)")
    c = curves[0]
    lt, ld = np.log10(np.asarray(c.tau, float)), np.log10(np.asarray(c.deviation, float))
    if lt.size >= 2:
        slope = np.diff(ld) / np.diff(lt)
        mid_t, mid_d = (lt[1:] + lt[:-1]) / 2, (ld[1:] + ld[:-1]) / 2
        for name, tr in _READ_TAU.items():
            p = _SLOPE[name]
            i = int(np.argmin(np.abs(slope - p)))
            if abs(slope[i] - p) <= slope_tolerance:
                out[name] = float(10 ** (mid_d[i] + p * (math.log10(tr) - mid_t[i])))
    out["B"] = float(np.min(c.deviation)) / FLICKER_FLOOR
    return out
