"""Upper bounds that the record's own sub-segments cannot contradict (issue 30, item 2).

A term the whole record cannot identify gets a one-sided 95 % bound. On real records that
bound sat below what a part of the same record identifies (ADIS16405 accelerometers at 100 Hz:
the velocity random walk "< 0.186 m/s/sqrt(h)" on the whole record, 0.303 on its first
2000 s): the long record's fit range starts later (its points are more precise, so the
short-tau filter bend is found further out) and its terms trade off differently. Data that
identify a value over a stretch do not support a bound below it, so :func:`floor_bounds` fits
the halves and quarters of the record with the same options and raises each non-identifiable
term's bound to the largest value a sub-segment identifies, saying so in
``Coefficient.bound_note``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np
from gyrobench.analysis.allan._curve import allan_deviation
from gyrobench.analysis.allan._results import NoiseFit
from numpy.typing import ArrayLike

#: the sub-segments fitted by default: the halves and the quarters of the record
PARTS = (2, 4)


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
    """
    from gyrobench.analysis.allan._fit import fit_noise

    y = np.asarray(rate, dtype=float)
    open_terms = [t for t, c in fit.coefficients.items() if not c.identifiable]
    bad = [k for k in parts if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or k < 2]
    if bad:
        raise ValueError(f"parts must be integers >= 2 (segments per split); got {list(parts)!r}")
    if not open_terms:
        return fit
    best: dict[str, tuple[float, str]] = {}
    for k in parts:
        edges = np.linspace(0, y.size, k + 1).astype(int)
        for i in range(k):
            seg = y[edges[i] : edges[i + 1]]
            try:
                sub = fit_noise(allan_deviation(seg, fs, kind=fit.curve.kind), **fit_options)
            except ValueError:  # too short for the fit: no evidence either way
                continue
            for t in open_terms:
                c = sub.coefficients.get(t)
                if c is not None and c.identifiable and c.value is not None and c.value > best.get(t, (0.0, ""))[0]:
                    where = f"samples {edges[i]}-{edges[i + 1]} ({i + 1} of {k})"
                    best[t] = (c.value, where)
    coefficients = dict(fit.coefficients)
    for t, (value, where) in best.items():
        c = coefficients[t]
        if value > c.upper_bound:
            note = f"bound raised {value / c.upper_bound:.3g}x to the value identified over {where}"
            coefficients[t] = replace(c, upper_bound=value, bound_note=note)
    return replace(fit, coefficients=coefficients)
