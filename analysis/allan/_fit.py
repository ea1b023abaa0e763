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
#: (a choice of fit range, stricter than the misfit level :data:`MISFIT_P`)
DROP_P = 1e-3
#: fitted taus a term must dominate to be identifiable, where one is not enough (a one-octave
#: bump at the first fitted tau is not quantization; docs/design-notes.md, "The noise fit")
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
        sqrt(chi2/E[chi2]) (the choice of 0.05 is explained in docs/design-notes.md).
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
    Model (IEEE Std 952-1997 Annex C; docs/physics.md 1.5):

        AVAR(tau) = sum_{n=-2..2} C_n tau^n,
        C_-2 = 3 Q^2, C_-1 = N^2, C_0 = (2 ln 2/pi) B^2, C_1 = K^2/3, C_2 = R^2/2

    (the flicker plateau C_0 holds for tau > ~1.6/f_high). Each point A_i is treated as
    (sigma_i^2/nu_i) chi2(nu_i), with sigma_i^2 the *fitted* curve (weighting by the noisy A_i
    biases the fit low) and nu_i the Greenhall edf of each term's noise type at m_i. The
    problem min || W^1/2 (X C - A) ||, C >= 0, is solved by Lawson-Hanson active-set NNLS on
    column-scaled X, starting from the weights of the curve's own estimate, and reweighted
    until the C_n change by less than 1e-9 relative.

    Point covariance (docs/physics.md 1.6):
    V_ij = sum_{t,s} rho_ts(i, j) sd_t(i) sd_s(j), sd_t(i) = C_t tau_i^p_t sqrt(2 / nu_t(i)),
    with rho_ts the Gaussian correlation of term t's noise in A_i with term s's in A_j from
    the frequency-domain form of Cov(A_i, A_j), corrected on an overlapping curve for the
    finite record and, for Q, for the fourth cumulant of uniform quantization
    (``quantization_kurtosis``). The deterministic ramp adds no chi-square variance of its
    own, only its cross term with the noise (a rank-one term of V). The weights are 1/V_ii;
    the covariance of the estimate is the sandwich (X'WX)^-1 X'W V W X (X'WX)^-1 over all
    fitted terms (including any the NNLS set to 0). Intervals on C_n are
    C_n +- z sqrt(Cov_nn) (z = 1 and 1.96), clipped at 0 and mapped to the coefficient by the
    monotone C -> sqrt(C / scale).

    Goodness of fit: chi2 = sum_i r_i^2 / V_ii over the fitted points (r = A - X C), with
    dof = fitted points - terms kept. With H the hat matrix of the weighted fit over the kept
    terms and D^2 = diag V, z = D^-1 (I - H) A has covariance S = D^-1 (I - H) V (I - H)' D^-1,
    so chi2 = sum_k lambda_k chi2_1 (lambda the eigenvalues of S, mean ``chi2_expected`` =
    trace S), and p = P(chi2 >= observed) is read from the four-cumulant approximation of
    Liu, Tang and Zhang (2009). On a misfit (p < ``misfit_p``) every standard error is
    multiplied by the Birge ratio sqrt(chi2 / chi2_expected).

    A term is *identifiable* when it is the largest term of the fitted curve at one fitted
    tau at least (two for Q) and its 95 % interval excludes 0; otherwise ``value`` is None and
    ``upper_bound`` is the one-sided 95 % bound coefficient(u), u = C_n + 1.645 se_n(u), with
    se_n(u) the standard error when the point covariance is modelled with C_n = u (a test
    inversion). :func:`floor_bounds` further raises it to what a sub-segment of the record
    identifies.

    Assumptions: Gaussian noise except quantization (uniform angle error); independent terms;
    the five power laws only (a Gauss-Markov bump or a sinusoid is absorbed into the nearest
    terms, and a filter that bends the first octaves biases Q and N); bias instability on its
    plateau at the fitted taus.

    Why this statistic and these defaults, and the measured false-alarm rates and interval
    coverage (benchmarks/coverage_fit.py, benchmarks/misfit_false_alarm.py): docs/design-notes.md,
    "The noise fit".

    References
    ----------
    .. [1] IEEE Std 952-1997, Annex C (the five terms and their Allan variance).
    .. [2] C. A. Greenhall and W. J. Riley, "Uncertainty of stability variances based on finite
       differences", Proc. 35th PTTI (2003) (equivalent degrees of freedom).
    .. [3] C. L. Lawson and R. J. Hanson, *Solving Least Squares Problems*, 1974, ch. 23 (NNLS).
    .. [4] H. Liu, Y. Tang and H. H. Zhang, "A new chi-square approximation to the distribution
       of non-negative definite quadratic forms in non-central normal variables",
       Comput. Stat. Data Anal. 53 (2009) 853-856.
    .. [5] Particle Data Group, Review of Particle Physics, Introduction, "Unconstrained
       averaging" (the scale factor S of inconsistent measurements, the Birge ratio).
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
