"""Where the five-power-law model can be fitted: the filter-shaped short-tau region found in the
data (:func:`fit_range`) or implied by a stated sensor bandwidth (:func:`bandwidth_range`)."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.analysis.allan._checks import _check_bandwidth, _positive_tau
from gyrobench.analysis.allan._kinds import STATISTICS, _edf
from gyrobench.analysis.allan._results import _NORMAL, AllanCurve, FitRange
from gyrobench.analysis.allan._terms import TERMS


def fit_range(
    curve: AllanCurve, *, false_alarm: float = 1e-3, n_terms: int = len(TERMS), nonstationary: bool = False
) -> FitRange:
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
    nonstationary : bool
        The record was flagged non-stationary (motion or steps, :mod:`gyrobench.analysis.stationarity`).
        Motion bends the curve too, so the concave region is then not excluded (Notes) and the
        reason says so.

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

    On a non-stationary record the concave region may be the motion's (issue 30: a 1 Hz tag
    record with handling lost its 1-64 s octaves, where no filter acts), and its shape does not
    tell the two apart: a low-pass makes a bump under the white-noise line (the ADEV of a
    smooth output rises as tau^+1 into the filter's time scale), motion a bump of the same
    shape above it, whose falling edge (tau^-1, bounded bursts) the Q term then extrapolates
    over it. A rule on the first octave's slope (> -1/2, a roll-off toward Nyquist) was
    tried and kept the drop on a simulated 1 Hz handling record (slope +0.16: the motion
    dominates from 1 s). So on a non-stationary record nothing is excluded here: the short
    taus are fitted and the misfit shows; a known filter is excluded with ``bandwidth`` or
    ``tau_min`` given as a number.
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
    if nonstationary:
        return FitRange(
            tau_min=None,
            excluded=0,
            reason=(
                f"short taus kept (non-stationary record): the curve bends down below tau = {tau[j]:.3g} s, which "
                f"a filter or the record's motion/steps can make; not taken as a filter's here, so those points "
                f"are fitted and a misfit shows (give --bandwidth or --tau-min for a known filter)"
            ),
        )
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
    # written as (T / T') (3 - 4 e^-x + e^-2x) / (2 x), x = tau / T', with expm1 so that a corner
    # frequency near the smallest float (T' overflowing to inf) gives the limit b -> 1, not inf * 0
    w = 2.0 * math.pi * bw
    u = 0.0 if fs is None else w / float(fs)
    ratio = 1.0 if u < 1e-8 else u / math.sinh(u)  # T / T' = u / sinh(u), 1 - u^2/6 below 1e-8
    x = tau * w
    with np.errstate(invalid="ignore", divide="ignore"):
        g = (-4.0 * np.expm1(-x) + np.expm1(-2.0 * x)) / (2.0 * x)
    return ratio * np.where(x > 0.0, g, 1.0)


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
    kind = curve.kind if curve.kind in STATISTICS else "overlapping"
    nu0 = _edf(kind, np.zeros(ms.size, dtype=np.int64), ms, curve.n_samples)
    b = lowpass_avar_bias(tau, bw, fs=curve.fs)
    ok = (b <= bias * np.sqrt(2.0 / nu0)) & (tau >= (1.0 - 1e-9) / bw)
    rule = (
        f"a first-order low-pass at the stated bandwidth {bw:g} Hz biases a white-noise point by more than "
        f"{bias:g} of its standard error"
    )
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
