"""The joint weighted NNLS fit of the IEEE 952 terms to an Allan variance, with honest intervals.

:func:`fit_noise` is a pipeline of small steps: the curve and the options are checked, the fit
window is set (:func:`_lower_limit`, :func:`_used_points`), the point model (edf and
correlations of every point for every term, :func:`_point_model`) is built once, the weighted
NNLS is iterated (:func:`_reweight`), its covariance (:func:`_sandwich`) and goodness of fit
(:mod:`._goodness`) give the intervals (:func:`_coefficients`), and with ``tau_min="auto"``
misfitting first points are dropped (:func:`_drop_misfitting_first_points`).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.analysis.allan._blas import _single_blas
from gyrobench.analysis.allan._checks import _check_tau_limit
from gyrobench.analysis.allan._covariance import (
    QUANTIZATION_KURTOSIS,
    PointCovarianceModel,
    _finite_record_delta,
    _quantization_kurtosis_rho,
    _ramp_basis,
    _rho_blocks,
    _stack_rho,
)
from gyrobench.analysis.allan._curve import allan_deviation
from gyrobench.analysis.allan._goodness import _goodness
from gyrobench.analysis.allan._kinds import _FIT_KINDS, STATISTICS, _edf
from gyrobench.analysis.allan._nnls import _wnnls
from gyrobench.analysis.allan._results import _NORMAL, AllanCurve, Coefficient, NoiseFit
from gyrobench.analysis.allan._terms import _ALPHA, _POWER, TERM, TERMS, avar_to_coefficient
from gyrobench.analysis.allan._window import BANDWIDTH_BIAS, bandwidth_range, fit_range

_ONE_SIGMA = math.erf(1.0 / math.sqrt(2.0))  # 0.682689...
_Z68 = _NORMAL.inv_cdf(0.5 + _ONE_SIGMA / 2.0)  # 1.0
_Z95 = _NORMAL.inv_cdf(0.975)  # 1.96
_Z95_ONE_SIDED = _NORMAL.inv_cdf(0.95)  # 1.645

#: default level of the misfit test: below it the fit is a misfit and its intervals are widened
MISFIT_P = 0.05
#: level of the chi2(1) test that drops a misfitting first point with ``tau_min="auto"``
#: (a choice of fit range, kept as strict as before the misfit level moved to 0.05)
DROP_P = 1e-3
#: fitted taus a term must dominate to be identifiable, where one is not enough (issue 30: on a
#: 100 Hz ADIS16405 accelerometer a Q term "identified" from a bump at the first fitted tau
#: pushed the velocity random walk's bound below its value on a sub-segment of the same record)
_MIN_DOMINANT = {"Q": 2}


@_single_blas
def fit_noise(
    curve_or_rate: AllanCurve | ArrayLike,
    fs: float | None = None,
    *,
    terms: Sequence[str] = TERMS,
    max_iter: int = 20,
    tau_min: float | str | None = None,
    tau_max: float | None = None,
    misfit_p: float = MISFIT_P,
    bandwidth: float | None = None,
    bandwidth_bias: float = BANDWIDTH_BIAS,
    quantization_kurtosis: float = QUANTIZATION_KURTOSIS,
    nonstationary: bool = False,
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
        Level of the goodness-of-fit test (default :data:`MISFIT_P` = 0.05): a fit with p-value
        below it is a misfit (``NoiseFit.misfit``), and its standard errors are multiplied by
        sqrt(chi2/E[chi2]). (Until issue 30 the default was 1e-3: on real records fits at
        p = 0.003-0.03 kept intervals that the halves of the same record contradicted.)
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
    nonstationary : bool
        The record was flagged non-stationary (motion or steps). With ``tau_min="auto"`` the
        concave short-tau region is then not excluded (:func:`fit_range`: motion makes the
        same shape as a filter) and misfitting first points are not dropped: the motion's
        points stay in the fit so that its misfit shows.

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
    tests/analysis/test_allan_misfit_calibration.py checks the rate at p < 0.1 and 0.01. The
    Liu-Tang-Zhang tail is exact for equal lambda and within 0.5-11 % of p down to p = 1e-3
    for the uneven ones tested (a test checks it against Monte Carlo). On a misfit (p <
    ``misfit_p``) every standard error is multiplied by the Birge ratio sqrt(chi2 /
    chi2_expected) (as the Particle Data Group scales errors of inconsistent measurements), so
    no interval stays tight on data the model does not describe; identifiability is then judged
    on the widened intervals.
    A term is *identifiable* when it is the largest term of the fitted curve at one fitted
    tau at least (two for Q: a one-octave bump at the first fitted tau is not quantization)
    and its 95 % interval excludes 0; otherwise ``value`` is None and ``upper_bound`` is a
    one-sided 95 % bound coefficient(u), u = C_n + 1.645 se_n(u) with se_n(u) the standard
    error when the point covariance is modelled with C_n = u (``_bound_se``, a test
    inversion; the plain C_n + 1.645 sqrt(Cov_nn) models none of the term's own noise when
    the NNLS set C_n near 0: with it, the 95 % intervals of the ADIS16405 records' halves
    missed each other on 10 of 90 term pairs at misfit level 0.05, with the inversion on 5).
    :func:`floor_bounds` further raises it to what a sub-segment of the record identifies.

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
    curve = _curve_of(curve_or_rate, fs)
    terms = _check_terms(terms)
    _check_misfit_p(misfit_p)
    qk = _check_quantization_kurtosis(quantization_kurtosis)
    if not np.any(np.asarray(curve.variance, dtype=float) > 0):
        raise ValueError(
            "rate is constant (zero variance): Allan deviation is 0 at every tau; nothing to fit"
        )
    limit = _lower_limit(curve, tau_min, len(terms), bandwidth, bandwidth_bias, nonstationary)
    used = _used_points(curve, limit, tau_max, terms)
    nu_all, rho_all = _point_model(curve, terms, qk)
    fit, _ = _fit_core(curve, terms, used, nu_all, rho_all, max_iter, misfit_p)
    if isinstance(tau_min, str) and not nonstationary:  # "auto" (on motion, dropping would hide the misfit)
        fit = _drop_misfitting_first_points(fit, curve, terms, nu_all, rho_all, max_iter, misfit_p)
    return replace(fit, range_rule=limit.rule, range_reason=limit.reason)


# ---------------------------------------------------------------------------------- checks
def _curve_of(curve_or_rate: AllanCurve | ArrayLike, fs: float | None) -> AllanCurve:
    """The curve to fit: the one given, or the overlapping octave curve of the rate samples."""
    if isinstance(curve_or_rate, AllanCurve):
        curve = curve_or_rate
    else:
        if fs is None:
            raise ValueError("fs [Hz] is required when fit_noise is given rate samples; got None")
        curve = allan_deviation(curve_or_rate, fs)
    if curve.kind not in _FIT_KINDS:
        raise ValueError(f"fit_noise needs an Allan variance curve, kind in {_FIT_KINDS}; got {curve.kind!r}")
    return curve


def _check_terms(terms: Sequence[str]) -> tuple[str, ...]:
    """The terms to fit, distinct names of TERMS, in canonical order."""
    if isinstance(terms, str):
        terms = (terms,)
    terms = tuple(terms)
    bad = [t for t in terms if t not in TERMS]
    if bad or not terms or len(set(terms)) != len(terms):
        raise ValueError(f"terms must be distinct names from {TERMS}; got {terms!r}")
    return tuple(t for t in TERMS if t in terms)  # canonical order


def _check_misfit_p(misfit_p: Any) -> None:
    if isinstance(misfit_p, bool) or not isinstance(misfit_p, (int, float)) or not (0.0 <= misfit_p < 1.0):
        raise ValueError(f"misfit_p must be a probability in [0, 1); got {misfit_p!r}")


def _check_quantization_kurtosis(qk: Any) -> float:
    if isinstance(qk, bool) or not isinstance(qk, (int, float)):
        raise TypeError(f"quantization_kurtosis must be a number; got {qk!r}")
    if not (-2.0 <= qk < math.inf):
        raise ValueError(f"quantization_kurtosis must be >= -2 (an excess kurtosis); got {qk!r}")
    return qk


# ---------------------------------------------------------------------------------- fit window
@dataclass(frozen=True, slots=True)
class _LowerLimit:
    """The shortest tau to fit (as given or found; checked later), the rule that set it and why."""

    tau_min: Any
    rule: str
    reason: str


def _lower_limit(
    curve: AllanCurve,
    tau_min: Any,
    n_terms: int,
    bandwidth: float | None,
    bandwidth_bias: float,
    nonstationary: bool = False,
) -> _LowerLimit:
    """tau_min of the fit: the user's number, the data's (``"auto"``, :func:`fit_range`) or the bandwidth's.

    When several apply the largest wins (:func:`bandwidth_range` replaces a smaller one).
    """
    rule, reason = ("user", f"tau_min = {tau_min!r} s given") if tau_min is not None else ("", "")
    if isinstance(tau_min, str):
        if tau_min != "auto":
            raise ValueError(f"tau_min must be a number [s], 'auto' or None; got {tau_min!r}")
        found = fit_range(curve, n_terms=n_terms, nonstationary=nonstationary)
        rule = "data" if found.tau_min is not None else ""
        if nonstationary and found.reason.startswith("short taus kept"):
            rule = "nonstationary"  # the concave region was found and kept: the motion's, not a filter's
        tau_min, reason = found.tau_min, found.reason
    if bandwidth is not None:
        limit = bandwidth_range(curve, bandwidth, bias=bandwidth_bias)
        current = _check_tau_limit("tau_min", tau_min)
        if limit.tau_min is not None and (current is None or limit.tau_min > current * (1 + 1e-9)):
            tau_min, rule, reason = limit.tau_min, "bandwidth", limit.reason
    return _LowerLimit(tau_min, rule, reason)


def _used_points(
    curve: AllanCurve, limit: _LowerLimit, tau_max: Any, terms: tuple[str, ...]
) -> NDArray[np.bool_]:
    """The curve points with tau_min <= tau <= tau_max (relative tolerance 1e-9), enough and all > 0."""
    tau_all = np.asarray(curve.tau, dtype=float)
    lo_t = _check_tau_limit("tau_min", limit.tau_min)
    hi_t = _check_tau_limit("tau_max", tau_max)
    used = np.ones(tau_all.size, dtype=bool)
    if lo_t is not None:
        used &= tau_all >= lo_t * (1 - 1e-9)
    if hi_t is not None:
        used &= tau_all <= hi_t * (1 + 1e-9)
    if lo_t is not None and hi_t is not None and lo_t > hi_t:
        raise ValueError(f"tau_min must be <= tau_max; got tau_min = {lo_t!r} s > tau_max = {hi_t!r} s")
    if int(used.sum()) < len(terms):
        rule, reason = limit.rule, limit.reason
        raise ValueError(
            f"the fit range [{lo_t or tau_all[0]:.6g}, {hi_t or tau_all[-1]:.6g}] s holds {int(used.sum())} "
            f"of the curve's tau points, fewer than the {len(terms)} terms to fit ({', '.join(terms)})"
            + (f" (tau_min set by the {rule} rule: {reason})" if rule in ("data", "bandwidth") else "")
        )
    a = np.asarray(curve.variance, dtype=float)[used]
    if not np.all(a > 0):
        i = int(np.flatnonzero(~(a > 0))[0])
        raise ValueError(
            f"curve.deviation must be > 0 at every tau to weight the fit; got 0 at tau = {float(tau_all[used][i])!r} s"
        )
    return used


# ---------------------------------------------------------------------------------- point model
def _point_model(
    curve: AllanCurve, terms: tuple[str, ...], qk: float
) -> tuple[NDArray[np.float64], dict[tuple[int, int], NDArray[np.float64]]]:
    """Edf nu[i, t] and correlations rho[(t, s)][i, j] of every curve point for every term's noise.

    Over the whole curve (the fit slices them to its points). A curve pooled over pieces
    (``AllanCurve.edf_scale``) has each term's one-record edf scaled by the pieces' share at
    that tau; its correlations are modelled as those of one record (an approximation: the pieces'
    ends add independence). For a statistic with
    ``FitConstants.finite_record`` (the overlapping AVAR) the correlations get the exact
    finite-record correction and, for the Q term, the fourth cumulant of quantization ``qk``.
    """
    ms_all = curve.m
    nu_all = np.stack(
        [_edf(curve.kind, np.full(ms_all.size, _ALPHA[t], dtype=np.int64), ms_all, curve.n_samples) for t in terms],
        axis=1,
    )
    if curve.edf_scale is not None:  # pooled pieces: each tau holds only the pieces long enough for it
        nu_all = nu_all * np.asarray(curve.edf_scale, dtype=float)[:, None]
    rho_all = _rho_blocks([_ALPHA[t] for t in terms], ms_all)
    fc = STATISTICS[curve.kind].fit
    if fc is not None and fc.finite_record:  # the record's ends: exact finite-n correction of rho
        delta = _finite_record_delta([_ALPHA[t] for t in terms], ms_all, curve.n_samples)
        rho_all = {k: r + delta[k] for k, r in rho_all.items()}
        if "Q" in terms:  # uniform angle quantization: its fourth cumulant (not Gaussian)
            q = terms.index("Q")
            if qk != 0:
                kq = _quantization_kurtosis_rho(ms_all, curve.n_samples, float(qk))
                rho_all[(q, q)] = rho_all[(q, q)] + kq
    return nu_all, rho_all


# ---------------------------------------------------------------------------------- the fit
def _drop_misfitting_first_points(
    fit: NoiseFit,
    curve: AllanCurve,
    terms: tuple[str, ...],
    nu_all: NDArray[np.float64],
    rho_all: dict[tuple[int, int], NDArray[np.float64]],
    max_iter: int,
    misfit_p: float,
) -> NoiseFit:
    """``tau_min="auto"``: drop the first fitted point while the fit misfits and that helps significantly.

    Past the concave region the filter can still pull the first points off the model: the
    first fitted point is dropped while the fit misfits and dropping it lowers chi2 by more
    than the chi2(1) quantile at the smaller of the misfit level and :data:`DROP_P` (the point is
    an outlier of the model there).
    """
    level = min(misfit_p, DROP_P)
    gain = _chi2_1_isf(level) if level > 0 else math.inf
    used = fit.used
    while fit.misfit and int(used.sum()) > len(terms) + 1:
        trial = used.copy()
        trial[int(np.flatnonzero(used)[0])] = False
        fit2, _ = _fit_core(curve, terms, trial, nu_all, rho_all, max_iter, misfit_p)
        if not (fit.chi2 - fit2.chi2 > gain):
            break
        used, fit = trial, fit2
    return fit


@functools.lru_cache(maxsize=8)
def _chi2_1_isf(level: float) -> float:
    """The chi2(1) quantile exceeded with probability ``level`` (once per level and process: ~3 ms each)."""
    from gyrobench.analysis.allan._chi2 import chi2_isf  # numpy only: no scipy.special import

    return float(chi2_isf(level, 1.0))


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
    rho_sel = {k: r[sel] for k, r in rho_all.items()}
    stacked = _stack_rho(rho_sel, len(terms))
    rho = rho_sel if stacked is None else stacked
    noise = np.array([TERM[t].random for t in terms])  # the ramp is deterministic (see _ramp_cross_sd)

    ramp = (*_ramp_basis(terms, tau, ms, curve.n_samples, curve.kind), terms.index("R")) if "R" in terms else None
    point_covariance = PointCovarianceModel(x, nu, rho, noise, ramp)

    var0 = 2.0 * a**2 / np.asarray(curve.edf, dtype=float)[used]  # first pass: the curve's own edf
    c, v, var, it = _reweight(x, a, var0, max_iter, point_covariance)
    bread = _sandwich_bread(x, var)
    cov = _sandwich(x, var, v, bread)

    resid = (a - x @ c) / np.sqrt(np.diag(v))
    chi2, dof, expected, p_value = _goodness(a - x @ c, v, x, var, c > 0)
    misfit = bool(dof > 0 and p_value < misfit_p)
    inflation = math.sqrt(chi2 / expected) if misfit else 1.0
    cov = cov * inflation**2
    se = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    coefficients = _coefficients(terms, x, c, se)
    for j, name in enumerate(terms):
        if not coefficients[name].identifiable and TERM[name].random:
            se_u = _bound_se(j, c, se[j], x, var, point_covariance, inflation, bread)
            bound = avar_to_coefficient(name, c[j] + _Z95_ONE_SIDED * se_u)
            coefficients[name] = replace(coefficients[name], upper_bound=max(bound, coefficients[name].upper_bound))
    return NoiseFit(
        coefficients=coefficients,
        curve=curve,
        avar_coefficients={t: float(v) for t, v in zip(terms, c, strict=True)},
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


def _reweight(
    x: NDArray[np.float64],
    a: NDArray[np.float64],
    var: NDArray[np.float64],
    max_iter: int,
    point_covariance: Callable[[NDArray[np.float64]], NDArray[np.float64]],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], int]:
    """Iterate the weighted NNLS with weights 1/V_ii of the fitted model until the C_n settle.

    Starts from the weights ``var``; returns C, the modelled point covariance V, the weights'
    variances and the iterations done (stops when C changes by less than 1e-9 relative).
    """
    c = np.zeros(x.shape[1])
    v = np.diag(var)
    it = 0
    for it in range(1, max_iter + 1):  # noqa: B007 - the count is returned
        c_new = _wnnls(x, a, var, passive=c > 0 if it > 1 else None)
        done = np.allclose(c_new, c, rtol=1e-9, atol=0.0)
        c = c_new
        v_new = point_covariance(c)
        var_new = np.diag(v_new)
        if np.all(var_new > 0):
            v, var = v_new, var_new
        else:  # no fitted term at some tau: keep the last weights there
            var = np.where(var_new > 0, var_new, var)
            v = v_new + np.diag(np.where(var_new > 0, 0.0, var))
        if done:
            break
    return c, v, var, it


def _bound_se(
    j: int,
    c: NDArray[np.float64],
    se_j: float,
    x: NDArray[np.float64],
    var: NDArray[np.float64],
    point_covariance: Callable[[NDArray[np.float64]], NDArray[np.float64]],
    inflation: float,
    bread: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]] | None = None,
) -> float:
    """Standard error of C_j if the truth were its one-sided 95 % upper bound u (test inversion).

    The covariance of the fit is modelled at the fitted C; for a term the NNLS set near 0 that
    model holds none of the term's own noise, so C_j + 1.645 se_j sat below values the same
    data show (on real records, below the estimate of a half of the record). The bound is the
    u with u = C_j + 1.645 se_j(u), se_j(u) the sandwich standard error of the same estimator
    (weights unchanged) when the points' covariance is modelled with C_j = u; solved by
    fixed-point iteration from the plain bound (se_j(u) grows with u; at most 30 steps, and
    stopped when u changes by < 1e-6 relative or would exceed 1e3 times its start, where the
    data bound the term only weakly and the last se is kept).
    """
    u = c[j] + _Z95_ONE_SIDED * se_j
    se_u = se_j
    if not (u > 0):
        return se_j
    start = u
    for _ in range(30):
        c_h = c.copy()
        c_h[j] = max(c[j], u)
        cov_h = _sandwich(x, var, point_covariance(c_h), bread)
        se_new = math.sqrt(max(float(cov_h[j, j]), 0.0)) * inflation
        u_new = c[j] + _Z95_ONE_SIDED * max(se_new, se_j)
        if u_new > 1e3 * start:
            break
        se_u = max(se_new, se_j)
        done = abs(u_new - u) <= 1e-6 * u
        u = u_new
        if done:
            break
    return se_u


def _sandwich(
    x: NDArray[np.float64],
    var: NDArray[np.float64],
    v: NDArray[np.float64],
    bread: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]] | None = None,
) -> NDArray[np.float64]:
    """Covariance of the weighted LS estimate: (X'WX)^-1 X'W V W X (X'WX)^-1.

    W = diag(1/var), V the modelled covariance of the AVAR points (correlated across tau);
    computed on column-scaled X for conditioning. ``bread``: :func:`_sandwich_bread` of the
    same ``x`` and ``var``, when several V share them (the same numbers, computed once).
    """
    xs, b, scale = _sandwich_bread(x, var) if bread is None else bread
    meat = xs.T @ v @ xs
    return (b @ meat @ b) / np.outer(scale, scale)


def _sandwich_bread(
    x: NDArray[np.float64], var: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """The V-free parts of :func:`_sandwich`: W X / scale, (X'WX / scale scale')^+ and the column scale."""
    xw = x / var[:, None]
    scale = np.sqrt(np.einsum("ij,ij->j", x, xw))
    scale[scale == 0] = 1.0
    bread = np.linalg.pinv((x / scale).T @ (xw / scale), rcond=1e-13)
    return xw / scale, bread, scale


def _coefficients(
    terms: tuple[str, ...], x: NDArray[np.float64], c: NDArray[np.float64], se: NDArray[np.float64]
) -> dict[str, Coefficient]:
    """Each term's value, 68/95 % intervals and upper bound; identifiable when it dominates somewhere
    and its 95 % interval excludes 0."""
    contrib = x * c[None, :]
    wins = np.bincount(np.argmax(contrib, axis=1), minlength=len(terms)) if np.any(c > 0) else np.zeros(len(terms))
    dominant = {j for j, name in enumerate(terms) if wins[j] >= _MIN_DOMINANT.get(name, 1)}
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
    return coeffs
