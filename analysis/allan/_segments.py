"""Upper bounds that the record's own sub-segments cannot contradict (issue 30, item 2).

A term the whole record cannot identify gets a one-sided 95 % bound. On real records that
bound sat below what a part of the same record identifies (ADIS16405 accelerometers at 100 Hz:
the velocity random walk "< 0.186 m/s/sqrt(h)" on the whole record, 0.303 on its first
2000 s): the long record's fit range starts later (its points are more precise, so the
short-tau filter bend is found further out) and its terms trade off differently. Data that
identify a value over a stretch do not support a bound below it, so :func:`floor_bounds` fits
the halves, quarters and eighths of the record with the same options and raises each
non-identifiable term's bound to the largest value a sub-segment identifies, saying so in
``Coefficient.bound_note``. Eighths are needed: on the ADIS16405 imu2 1 Hz record an eighth
identifies R = 2.9e-6 [1.3e-6, 3.9e-6] rad/s^2 where the whole record's bound was < 3.5e-7
and no half or quarter identifies R.

:func:`pool_curves` pools the curves of separate stretches of one record (the quiet stretches
between handling, issue 30 item 1) into one EDF-weighted curve for one fit.

:func:`halves_agreement` asks the converse of a real record: do the 95 % intervals of its two
halves overlap, term by term (the coverage check of issue 30 on real data)?
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from gyrobench.analysis.allan._curve import allan_deviation
from gyrobench.analysis.allan._fit import fit_noise
from gyrobench.analysis.allan._kinds import STATISTICS, _edf
from gyrobench.analysis.allan._results import AllanCurve, Coefficient, NoiseFit

#: the sub-segments fitted by default: the halves, quarters and eighths of the record. Over the
#: 18 axes of the six ADIS16405 1 Hz excerpts (tests/data) sixteenths raise no bound beyond what
#: eighths give; 32nds raise one (imu2 x, Q 2.0x, from a 312-sample stretch) at 2.2x the cost
PARTS = (2, 4, 8)


def floor_bounds(
    fit: NoiseFit, rate: ArrayLike, fs: float, *, parts: Sequence[int] = PARTS, **fit_options: Any
) -> NoiseFit:
    """``fit`` with each non-identifiable term's upper bound raised to what a sub-segment identifies.

    Parameters
    ----------
    fit : NoiseFit
        The fit of the whole record ``rate`` (from :func:`fit_noise`).
    rate : array_like
        The rate samples the fit's curve was computed from [unit u].
    fs : float
        Sample rate [Hz].
    parts : sequence of int
        Split the record into k equal consecutive segments for each k (>= 2) and fit each.
    **fit_options
        Options of :func:`fit_noise` for the segments (the whole record's ``terms``,
        ``tau_min``, ... should be passed: the segments are fitted alike).

    Returns
    -------
    NoiseFit
        The same fit; a term not identifiable on the whole record has ``upper_bound`` =
        max(its bound, the largest value a segment identifies) and a ``bound_note``. A
        segment too short for the fit (fewer points than terms) is skipped.

    Notes
    -----
    The k segments of a split all have n // k samples (the last n mod k samples are left out
    of that split): equal lengths share one point model (edf and correlations, cached by
    length), so a split costs its curves and its NNLS iterations, not k point models.
    """
    from gyrobench.analysis.allan._fit import fit_noise

    y = np.asarray(rate, dtype=float)
    open_terms = [t for t, c in fit.coefficients.items() if not c.identifiable]
    bad = [k for k in parts if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or k < 2]
    if bad:
        raise ValueError(f"parts must be integers >= 2 (segments per split); got {list(parts)!r}")
    if not open_terms:
        return fit
    coefficients = dict(fit.coefficients)
    own = {t: coefficients[t].upper_bound for t in open_terms}  # the whole record's bounds
    for k in dict.fromkeys(int(k) for k in parts):
        _floor_split(coefficients, own, y, fs, k, fit.curve.kind, fit_noise, fit_options)
    return replace(fit, coefficients=coefficients)


def _floor_split(
    coefficients: dict[str, Any],
    own: dict[str, float],
    y: np.ndarray,
    fs: float,
    k: int,
    kind: str,
    fit_noise: Any,
    fit_options: dict[str, Any],
) -> None:
    """Fit the k segments of n // k samples; raise the open bounds in ``coefficients`` in place.

    ``own``: the whole record's bounds of the open terms (the note states the raise against them).
    """
    size = y.size // k
    for i in range(k):
        a, b = i * size, (i + 1) * size
        try:
            sub = fit_noise(allan_deviation(y[a:b], fs, kind=kind), **fit_options)
        except ValueError:  # too short for the fit: no evidence either way
            continue
        for t in own:
            c = sub.coefficients.get(t)
            if c is None or not c.identifiable or c.value is None:
                continue
            cur = coefficients[t]
            if c.value > cur.upper_bound:
                note = (
                    f"bound raised {c.value / own[t]:.3g}x to the value identified over samples {a}-{b} "
                    f"({i + 1} of {k})"
                )
                coefficients[t] = replace(cur, upper_bound=c.value, bound_note=note)


def pool_curves(curves: Sequence[AllanCurve]) -> AllanCurve:
    """One Allan variance curve from the curves of separate stretches of a record: EDF-weighted.

    Parameters
    ----------
    curves : sequence of AllanCurve
        Curves of the same kind, sample rate and confidence, each from a stretch of the same
        sensor (e.g. the quiet stretches between handling): at least one.

    Returns
    -------
    AllanCurve
        At the taus every curve holds (the shortest stretch's: a tau only the long stretches
        reach would describe them alone), AVAR = sum_s w_s AVAR_s / sum_s w_s with
        w_s the stretch's white-noise edf, edf nu = (sum_s w_s)^2 / sum_s (w_s^2 / nu_s)
        (nu_s the curve's own edf), bounds from chi-square with nu (NIST SP 1065 eq. 45),
        ``n_terms`` summed and ``n_samples`` the stretches' total.

    Notes
    -----
    Each stretch's estimate has Var(AVAR_s) = 2 sigma^4 / nu_s (nu_s its edf) and the
    stretches are independent, so the weighted mean has variance 2 sigma^4 sum_s w_s^2 / nu_s
    / (sum_s w_s)^2, i.e. the edf above (Satterthwaite). Weights proportional to nu_s give the
    smallest variance, but a curve's edf depends on the noise type it identifies from the
    data at each tau: weighting by it biased the pooled AVAR at long taus (-9 % at m =
    n_shortest / 4 on white noise, 68 % intervals covering 46 %). The white-noise edf
    depends on m and the stretch's length only, so the weights are the EDF weighting made
    data-free (the same up to the noise type's common factor when the stretches share it).
    :func:`fit_noise` models the pooled curve as one record of the total length: exact for
    the edf at short taus (nu ~ n / m for each stretch, so the sum is that of the total), an
    overestimate where m approaches a stretch's length (a few % at m = n_shortest / 8), and
    the correlation between taus is that of one record (the stretches' end effects differ).
    """
    from gyrobench.analysis.allan._curve import deviation_bounds

    curves = list(curves)
    if not curves or not all(isinstance(c, AllanCurve) for c in curves):
        raise TypeError(f"curves must be a non-empty sequence of AllanCurve; got {curves!r}")
    first = curves[0]
    for name in ("kind", "fs", "confidence"):
        got = {getattr(c, name) for c in curves}
        if len(got) > 1:
            raise ValueError(f"curves must share one {name}; got {sorted(got, key=str)}")
    common = set(int(m) for m in first.m)
    for c in curves[1:]:
        common &= set(int(m) for m in c.m)
    ms = np.array(sorted(common), dtype=np.int64)
    if ms.size == 0:
        raise ValueError("curves must share at least one tau; got none in common")
    kind = first.kind if first.kind in STATISTICS else "overlapping"
    wtot = np.zeros(ms.size)
    vsum = np.zeros(ms.size)
    wsum = np.zeros(ms.size)
    n_terms = np.zeros(ms.size, dtype=np.int64)
    for c in curves:
        idx = np.searchsorted(c.m, ms)
        w = _edf(kind, np.zeros(ms.size, dtype=np.int64), ms, c.n_samples)  # white-noise edf: data-free
        wtot += w
        wsum += w * c.variance[idx]
        vsum += w**2 / c.edf[idx]
        n_terms += c.n_terms[idx]
    dev = np.sqrt(wsum / wtot)
    edf = wtot**2 / vsum
    lo, hi = deviation_bounds(dev, edf, first.confidence)
    return AllanCurve(
        tau=ms / first.fs,
        deviation=dev,
        low=lo,
        high=hi,
        n_terms=n_terms,
        edf=edf,
        kind=first.kind,
        confidence=first.confidence,
        fs=first.fs,
        n_samples=int(sum(c.n_samples for c in curves)),
        alpha=None,
    )


@dataclass(frozen=True, slots=True, kw_only=True)
class HalvesPair:
    """One term of the two halves of a record (:func:`halves_agreement`).

    ``first`` and ``second``: each half's 95 % interval of the coefficient, or [0, its one-sided
    95 % bound] where that half leaves the term open (coefficient units). ``overlap``: the two
    intervals share a point.
    """

    term: str
    first: tuple[float, float]
    second: tuple[float, float]
    overlap: bool


def _interval_or_bound(c: Coefficient) -> tuple[float, float]:
    return (float(c.ci95[0]), float(c.ci95[1])) if c.identifiable else (0.0, float(c.upper_bound))


def halves_agreement(rate: ArrayLike, fs: float, *, floor: bool = False, **fit_options: Any) -> list[HalvesPair]:
    """Each term that either half of ``rate`` identifies, with both halves' 95 % intervals.

    The record is split at n // 2 and each half fitted with :func:`fit_noise` (``fit_options``,
    e.g. ``tau_min="auto"`` as ``gyrobench allan`` does), then, when ``floor``, with
    :func:`floor_bounds` on that half as the CLI applies it. Consistent 95 % intervals of two
    independent halves overlap far more often than 95 % of the time, so a share of pairs
    that do not overlap well above 5 % says the intervals are too narrow for the record.

    Parameters
    ----------
    rate : array_like, shape (n,)
        Rate samples [any unit], one every 1/fs.
    fs : float
        Sample rate [Hz], > 0.
    floor : bool
        Apply :func:`floor_bounds` to each half's fit.

    Returns
    -------
    list of HalvesPair
        In the fit's term order; terms open in both halves are left out.
    """
    y = np.asarray(rate, dtype=float)
    h = y.size // 2
    fits = []
    for part in (y[:h], y[h:]):
        fit = fit_noise(allan_deviation(part, fs), **fit_options)
        fits.append(floor_bounds(fit, part, fs, **fit_options) if floor else fit)
    out = []
    for name, a in fits[0].coefficients.items():
        b = fits[1].coefficients[name]
        if not (a.identifiable or b.identifiable):
            continue
        (lo_a, hi_a), (lo_b, hi_b) = _interval_or_bound(a), _interval_or_bound(b)
        out.append(HalvesPair(term=name, first=(lo_a, hi_a), second=(lo_b, hi_b),
                              overlap=lo_a <= hi_b and lo_b <= hi_a))
    return out
