"""The Allan variance of a record's quiet stretches: pooled per tau, bridged where that is harmless.

A static record with sparse disturbances (a desk bump now and then, a door slammed) is not
stationary as a whole, but nearly all of it is. :func:`quiet_curve` analyses what is left
when the windows that :func:`gyrobench.analysis.stationarity.stationarity_check` flags are
taken out:

* at short taus, the gap-aware overlapping Allan variance over the quiet stretches
  (:func:`gyrobench.analysis.allan.allan_deviation_gaps`): every stretch long enough for a
  tau (2m + 1 samples) contributes to it, so the curve is not capped at the shortest stretch;
* at long taus, where few stretches reach, the whole record with each flagged window
  replaced by the mean of its neighbouring quiet windows (bridged), but only at the taus where
  what the bridge can change (Notes) stays below a tenth of the point's standard error and
  the record has no flagged step (a bridge cannot undo a step).

The spread between the stretches at each tau is tested (Bartlett's homogeneity test of
their Allan variances, :class:`StretchSpread`) and the left-out samples are listed.

References: NIST SP 1065 (Riley 2008) sec. 5.2.10 (gaps: analyse over the contiguous
segments) and eq. 11; M. S. Bartlett, "Properties of sufficiency and statistical tests",
Proc. R. Soc. A 160 (1937) 268-282 (homogeneity of variances).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.analysis.allan import AllanCurve, allan_deviation, allan_deviation_gaps, deviation_bounds
from gyrobench.analysis.stationarity import StationarityReport, quiet_stretches

__all__ = ["BRIDGE_BIAS", "QuietCurve", "StretchSpread", "quiet_curve"]

#: largest allowed bound of the bridge's bias at a tau, as a fraction of that point's
#: white-noise standard error (the rule of :func:`gyrobench.analysis.allan.bandwidth_range`)
BRIDGE_BIAS = 0.1
#: shortest quiet stretch used, in stationarity windows (the smallest quiet_stretches allows)
MIN_WINDOWS = 4


@dataclass(frozen=True, slots=True, kw_only=True)
class StretchSpread:
    """How much the quiet stretches' Allan deviations differ at each tau (Bartlett's test).

    Attributes
    ----------
    tau : ndarray
        Cluster times [s] of the pooled curve.
    n_stretches : ndarray of int
        Stretches long enough to hold the tau (2m + 1 samples or more).
    low, high : ndarray
        Smallest and largest Allan deviation over those stretches [rate unit] (nan where
        fewer than 2).
    p_value : ndarray
        Bartlett's test that the stretches share one Allan variance (nan where fewer than 2):
        a small p says the stretches differ by more than their scatter (the record changes
        between stretches).
    """

    tau: NDArray[np.float64]
    n_stretches: NDArray[np.int64]
    low: NDArray[np.float64]
    high: NDArray[np.float64]
    p_value: NDArray[np.float64]

    def worst(self) -> tuple[float, float] | None:
        """(tau, p) of the smallest homogeneity p-value, or None when no tau has 2 stretches."""
        ok = np.isfinite(self.p_value)
        if not ok.any():
            return None
        i = int(np.flatnonzero(ok)[np.argmin(self.p_value[ok])])
        return float(self.tau[i]), float(self.p_value[i])


@dataclass(frozen=True, slots=True, kw_only=True)
class QuietCurve:
    """Result of :func:`quiet_curve`.

    Attributes
    ----------
    curve : AllanCurve
        Overlapping Allan deviation of the quiet part of the record, ``edf_scale`` set for the fit.
    stretches : tuple of (start, stop)
        Half-open sample ranges of the quiet stretches used.
    excluded : tuple of (start, stop)
        Half-open sample ranges left out (flagged windows, stretches shorter than
        :data:`MIN_WINDOWS` windows, the samples after the last whole window).
    n_excluded : int
        Samples left out.
    bridged : ndarray of bool
        Per tau of ``curve``: from the bridged whole record (True) or the stretches (False).
    spread : StretchSpread
        The spread between the stretches at each tau.
    """

    curve: AllanCurve
    stretches: tuple[tuple[int, int], ...]
    excluded: tuple[tuple[int, int], ...]
    n_excluded: int
    bridged: NDArray[np.bool_]
    spread: StretchSpread

    def describe(self, fs: float) -> str:
        """One line: what was left out and where the curve comes from."""
        n = self.curve.n_samples
        worst = self.spread.worst()
        spread = ("" if worst is None
                  else f"; stretches' spread: smallest Bartlett p = {worst[1]:.2g} at {worst[0]:.3g} s")
        tb = self.curve.tau[self.bridged]
        bridge = f"; taus >= {tb[0]:.3g} s from the record with those samples bridged" if tb.size else ""
        return (f"quiet stretches: {len(self.stretches)} pooled per tau, {self.n_excluded} of {n} samples "
                f"({self.n_excluded / n:.2%}) left out in {len(self.excluded)} range(s){bridge}{spread}")


def _complement(ranges: list[tuple[int, int]], n: int) -> list[tuple[int, int]]:
    out, pos = [], 0
    for a, b in ranges:
        if a > pos:
            out.append((pos, a))
        pos = b
    if pos < n:
        out.append((pos, n))
    return out


def _bridge(y: NDArray[np.float64], excluded: list[tuple[int, int]], w: int) -> NDArray[np.float64]:
    """``y`` with each excluded range replaced by the mean of the ``w`` samples either side of it."""
    out = y.copy()
    for a, b in excluded:
        left = y[max(a - w, 0) : a]
        right = y[b : min(b + w, y.size)]
        both = np.concatenate([left, right])
        out[a:b] = float(both.mean()) if both.size else 0.0
    return out


def _white_edf(ms: NDArray[np.int64], n: int) -> NDArray[np.float64]:
    from gyrobench.analysis.allan._kinds import _edf

    return _edf("overlapping", np.zeros(ms.size, dtype=np.int64), ms, n)


def _spread(pieces: list[NDArray[np.float64]], curve: AllanCurve) -> StretchSpread:
    """Per-tau Bartlett homogeneity test of the pieces' overlapping Allan variances.

    Each piece j holding m gives A_j with white-noise edf nu_j (taken as A_j ~ sigma^2
    chi2(nu_j)/nu_j); with nu = sum nu_j and A_p = sum nu_j A_j / nu, Bartlett's statistic
    M = nu ln A_p - sum nu_j ln A_j over C = 1 + (sum 1/nu_j - 1/nu) / (3 (k - 1)) is
    chi2(k - 1) when the pieces share sigma^2.
    """
    from gyrobench.analysis.allan._chi2 import chi2_sf  # numpy only: no scipy.stats import
    from gyrobench.analysis.allan._gaps import _second_difference_sum
    from gyrobench.analysis.allan._octave import _phase

    ms = curve.m
    k_tau = ms.size
    vals: list[list[float]] = [[] for _ in range(k_tau)]
    nus: list[list[float]] = [[] for _ in range(k_tau)]
    for y in pieces:
        ok = np.flatnonzero(ms <= (y.size - 1) // 2)
        if ok.size == 0:
            continue
        x = _phase(y)
        nu = _white_edf(ms[ok], y.size)
        for i, v in zip(ok.tolist(), nu.tolist(), strict=True):
            mi = int(ms[i])
            est = _second_difference_sum(x, mi) / (2.0 * mi**2 * (y.size + 1 - 2 * mi))
            if est > 0:
                vals[i].append(est)
                nus[i].append(float(v))
    count = np.array([len(v) for v in vals], dtype=np.int64)
    lo = np.full(k_tau, np.nan)
    hi = np.full(k_tau, np.nan)
    p = np.full(k_tau, np.nan)
    for i in range(k_tau):
        if count[i] < 2:
            continue
        av, nv = np.asarray(vals[i]), np.asarray(nus[i])
        lo[i], hi[i] = math.sqrt(float(av.min())), math.sqrt(float(av.max()))
        nt = float(nv.sum())
        ap = float(nv @ av) / nt
        m_stat = nt * math.log(ap) - float(nv @ np.log(av))
        c = 1.0 + (float(np.sum(1.0 / nv)) - 1.0 / nt) / (3.0 * (count[i] - 1))
        p[i] = float(chi2_sf(max(m_stat / c, 0.0), float(count[i] - 1)))
    return StretchSpread(tau=np.asarray(curve.tau, dtype=float), n_stretches=count, low=lo, high=hi, p_value=p)


def quiet_curve(
    rate: ArrayLike,
    fs: float,
    report: StationarityReport,
    *,
    taus: str = "octave",
    bridge_bias: float = BRIDGE_BIAS,
) -> QuietCurve | None:
    """The overlapping Allan deviation of the quiet stretches of a record (module docstring).

    Parameters
    ----------
    rate : array_like
        Rate samples [any unit u], one every 1/fs.
    fs : float
        Sample rate [Hz].
    report : StationarityReport
        The record's :func:`stationarity_check` (its flagged windows and steps).
    taus : {"octave", "decade"}
        Tau list, resolved for the whole record's length.
    bridge_bias : float
        Largest allowed bound of the bridge's relative bias, as a fraction of the point's
        white-noise standard error (default :data:`BRIDGE_BIAS`).

    Returns
    -------
    QuietCurve or None
        None when the record was not tested or no quiet stretch holds two Allan terms.

    Notes
    -----
    The bridge: each left-out range is replaced by the mean of the window-length runs either
    side of it. Over the share f of the record that is bridged the samples' fast noise is
    replaced by one mean (a bump's excess is removed with them); a cluster mean of m >= w
    samples then loses at most the share of its variance that those samples carried, so
    the Allan variance at any tau is biased by at most about 2 f relative (both clusters of a
    difference). A tau is taken from the bridged record when 2 f <= ``bridge_bias`` x
    sqrt(2 / nu0(tau)) (nu0 the white-noise edf of the whole record at m), i.e. where
    the bias bound is a tenth of the point's standard error, and only without steps.
    Below that the pooled stretches are used (unbiased for stationary noise).
    """
    y = np.asarray(rate, dtype=float)
    n = y.size
    if not report.tested:
        return None
    stretches = quiet_stretches(report, n, fs, min_windows=MIN_WINDOWS)
    pieces = [y[a:b] for a, b in stretches]
    if not pieces or max(p.size for p in pieces) < 3:
        return None
    excluded = _complement(stretches, n)
    n_excl = int(sum(b - a for a, b in excluded))
    try:
        pooled = allan_deviation_gaps(pieces, fs, taus=taus)
    except ValueError:
        return None
    # the gaps curve resolves its taus for the pieces' total; the long taus come from the bridged record
    w = max(int(round(report.window * fs)), 1)
    full = allan_deviation(_bridge(y, excluded, w), fs, taus=taus)
    ms_full = full.m
    f = n_excl / n
    nu0 = _white_edf(ms_full, n)
    can_bridge = (not report.steps) and f < 1.0
    bridged_ok = can_bridge & (2.0 * f <= bridge_bias * np.sqrt(2.0 / nu0))
    # from the first bridged tau on, every tau is bridged (the rule is monotone in m)
    first = int(np.argmax(bridged_ok)) if bridged_ok.any() else ms_full.size
    pooled_ms = set(int(m) for m in pooled.m)
    rows_m, src = [], []
    for i, m in enumerate(ms_full):
        if i >= first:
            rows_m.append(int(m))
            src.append(True)
        elif int(m) in pooled_ms:
            rows_m.append(int(m))
            src.append(False)
    ms = np.asarray(rows_m, dtype=np.int64)
    bridged = np.asarray(src, dtype=bool)
    dev = np.empty(ms.size)
    edf = np.empty(ms.size)
    n_terms = np.empty(ms.size, dtype=np.int64)
    alpha = np.zeros(ms.size, dtype=np.int64)
    scale = np.ones(ms.size)
    white_n = _white_edf(ms, n)
    for j, m in enumerate(ms):
        if bridged[j]:
            i = int(np.flatnonzero(ms_full == m)[0])
            dev[j], edf[j], n_terms[j] = full.deviation[i], full.edf[i], full.n_terms[i]
            alpha[j] = 0 if full.alpha is None else int(full.alpha[i])
        else:
            i = int(np.flatnonzero(pooled.m == m)[0])
            dev[j], edf[j], n_terms[j] = pooled.deviation[i], pooled.edf[i], pooled.n_terms[i]
            alpha[j] = 0 if pooled.alpha is None else int(pooled.alpha[i])
            lens = [p.size for p in pieces if m <= (p.size - 1) // 2]
            held = float(sum(_white_edf(np.array([m]), L)[0] for L in lens))
            scale[j] = min(held / white_n[j], 1.0)
    lo, hi = deviation_bounds(dev, edf, full.confidence)
    curve = AllanCurve(tau=ms / fs, deviation=dev, low=lo, high=hi, n_terms=n_terms, edf=edf, kind="overlapping",
                       confidence=full.confidence, fs=float(fs), n_samples=n, alpha=alpha, edf_scale=scale)
    return QuietCurve(curve=curve, stretches=tuple(stretches), excluded=tuple(excluded), n_excluded=n_excl,
                      bridged=bridged, spread=_spread(pieces, curve))
