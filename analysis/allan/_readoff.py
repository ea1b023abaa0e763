"""The IEEE Std 952 graphical read-off of the noise terms (and the fixed-slope line fits).

References
----------
IEEE Std 952-1997 C.1; docs/physics.md 1.4; S. Guerrier et al., R package avar (AVLR).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

from gyrobench.analysis.allan._results import AllanCurve
from gyrobench.analysis.allan._terms import _POWER, _SCALE, FLICKER_FLOOR, TERMS

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
