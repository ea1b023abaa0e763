"""Rate-table scale-factor analysis: LS fit, nonlinearity (IEEE), asymmetry, breakpoint search.

Works on plain arrays: the commanded table rates and the gyro's mean output at
each rate, in any one consistent rate unit (the nonlinearity is a ratio; the
scale factor is output unit per input unit; breakpoints come back in the unit
of ``rates``).

Definitions (docs/physics.md section 5; IEEE Std 1431 / GJB 2426A; seed paper 001, eq. 1-6)::

    F_j   = K W_j + F0 + v_j                        (model; K, F0 by least squares)
    K     = (m S(WF) - S(W) S(F)) / (m S(W^2) - S(W)^2),  F0 = (S(F) - K S(W)) / m
    a_j   = (F_j - (K W_j + F0)) / F_m              (pointwise nonlinearity)
    K_n   = max_j |a_j|                             (scale-factor nonlinearity)

F_m is the one-sided full-scale output amplitude, max_j |F_j| unless given.
Asymmetry: K+ fitted on W >= 0, K- on W <= 0, K_a = |K+ - K-| / ((K+ + K-)/2).

:func:`dwell_means` turns a continuous rate-table record into the table's outputs (the
mean over each settled dwell). Two helpers for several runs of one table: :func:`range_nonlinearity` (K_n of the rates
inside a band, e.g. between the breakpoints found) and :func:`repeatability_floor` (the
compensation with no model error at the table rates, whose held-out K_n is the run-to-run
repeatability floor).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "ScaleFactorFit",
    "fit_scale_factor",
    "asymmetry",
    "SearchStep",
    "BreakpointSearch",
    "breakpoint_search",
    "heuristic_split",
    "check_rate_table",
    "dwell_means",
    "range_nonlinearity",
    "repeatability_floor",
]


def check_rate_table(
    rates: ArrayLike, outputs: ArrayLike, *, min_points: int = 3
) -> tuple[NDArray, NDArray]:
    """Validate a rate table: 1-D, equal length, >= ``min_points``, finite, strictly monotonic rates.

    Parameters
    ----------
    rates : array_like
        Table rates.
    outputs : array_like
        Mean output at each rate.
    min_points : int
        Fewest points accepted.

    Returns
    -------
    rates, outputs : ndarray
        The two arrays as float64.

    Raises
    ------
    ValueError
        Naming the first offending element.
    """
    w = np.asarray(rates, dtype=float)
    f = np.asarray(outputs, dtype=float)
    if w.ndim != 1 or f.ndim != 1:
        raise ValueError(f"rates and outputs must be 1-D; got shapes {w.shape} and {f.shape}")
    if w.shape != f.shape:
        raise ValueError(f"rates and outputs must have the same length; got {w.size} and {f.size}")
    if w.size < min_points:
        raise ValueError(f"a rate table needs at least {min_points} rates; got {w.size}")
    if not np.all(np.isfinite(w)):
        i = int(np.flatnonzero(~np.isfinite(w))[0])
        raise ValueError(f"rates must be finite; got {float(w[i])!r} at index {i}")
    if not np.all(np.isfinite(f)):
        i = int(np.flatnonzero(~np.isfinite(f))[0])
        raise ValueError(
            f"outputs must be finite; got {float(f[i])!r} at index {i} (rate {float(w[i])!r})"
        )
    d = np.diff(w)
    if not (np.all(d > 0) or np.all(d < 0)):
        if np.any(d == 0):
            i = int(np.flatnonzero(d == 0)[0])
            raise ValueError(
                f"rates must be distinct; got the duplicate rate {float(w[i])!r} at indices {i} and {i + 1}"
            )
        i = int(np.flatnonzero(np.sign(d) != np.sign(d[0]))[0])
        raise ValueError(
            "rates must be strictly monotonic (a rate-table sequence); "
            f"got {float(w[i])!r} -> {float(w[i + 1])!r} at index {i + 1}"
        )
    return w, f


@dataclass(frozen=True, slots=True)
class ScaleFactorFit:
    """Least-squares scale-factor fit of a rate table.

    Attributes
    ----------
    scale_factor : float
        K [output unit / rate unit].
    bias : float
        F0 [output unit].
    full_scale : float
        F_m [output unit].
    residuals : ndarray
        F_j - (K W_j + F0) [output unit].
    pointwise : ndarray
        a_j = residuals / F_m [-].
    nonlinearity : float
        K_n = max |a_j| [-].
    """

    scale_factor: float
    bias: float
    full_scale: float
    residuals: NDArray[np.float64]
    pointwise: NDArray[np.float64]
    nonlinearity: float

    @property
    def nonlinearity_pct(self) -> float:
        """K_n [%]."""
        return 100.0 * self.nonlinearity

    @property
    def nonlinearity_ppm(self) -> float:
        """K_n [ppm]."""
        return 1e6 * self.nonlinearity


def _ls_line(w: NDArray, f: NDArray) -> tuple[float, float]:
    """K and F0 by the closed-form normal equations (eq. 2-3), on centred data for accuracy."""
    wm, fm = w.mean(), f.mean()
    dw = w - wm
    k = float(np.dot(dw, f - fm) / np.dot(dw, dw))
    return k, float(fm - k * wm)


def fit_scale_factor(
    rates: ArrayLike, outputs: ArrayLike, *, full_scale: float | None = None
) -> ScaleFactorFit:
    """Least-squares scale factor, bias and IEEE nonlinearity of a rate table.

    Parameters
    ----------
    rates : array_like
        Commanded rates W_j (strictly monotonic, >= 3) [any rate unit].
    outputs : array_like
        Mean gyro output F_j at each rate [output unit].
    full_scale : float, optional
        F_m [output unit], > 0; default max |F_j|.

    Returns
    -------
    ScaleFactorFit

    Examples
    --------
    >>> fit = fit_scale_factor([-2.0, -1.0, 0.0, 1.0, 2.0], [-1.9, -1.0, 0.0, 1.0, 1.9])
    >>> round(fit.scale_factor, 6), round(fit.nonlinearity_pct, 4)
    (0.96, 2.1053)
    """
    w, f = check_rate_table(rates, outputs)
    k, f0 = _ls_line(w, f)
    fm = float(np.max(np.abs(f))) if full_scale is None else full_scale
    if isinstance(fm, bool) or not (isinstance(fm, (int, float)) and math.isfinite(fm) and fm > 0):
        raise ValueError(f"full_scale must be a finite number > 0 [output unit]; got {fm!r}")
    res = f - (k * w + f0)
    a = res / fm
    return ScaleFactorFit(k, f0, float(fm), res, a, float(np.max(np.abs(a))))


def asymmetry(rates: ArrayLike, outputs: ArrayLike) -> float:
    """Scale-factor asymmetry K_a = |K+ - K-| / ((K+ + K-)/2) [-].

    K+ is the LS scale factor over W >= 0 and K- over W <= 0 (each needs >= 2 rates).

    Parameters
    ----------
    rates : array_like
        Table rates W (any rate unit).
    outputs : array_like
        Mean gyro output at each rate.

    Returns
    -------
    float
        K_a [-].
    """
    w, f = check_rate_table(rates, outputs)
    pos, neg = w >= 0, w <= 0
    if pos.sum() < 2 or neg.sum() < 2:
        raise ValueError(
            f"asymmetry needs at least 2 rates >= 0 and 2 rates <= 0; got {int(pos.sum())} and {int(neg.sum())}"
        )
    kp, _ = _ls_line(w[pos], f[pos])
    kn, _ = _ls_line(w[neg], f[neg])
    return abs(kp - kn) / (0.5 * (kp + kn))


@dataclass(frozen=True, slots=True)
class SearchStep:
    """One row of the breakpoint-search trace (the paper's Table 2).

    ``end_rate`` closes the interval [0, end_rate]; ``nonlinearity`` is that
    interval's K_n [-]; ``abs_diff`` = |K_n(k) - K_n(k-1)|; ``diff2`` =
    abs_diff(k) - abs_diff(k-1); ``counter`` the run of positive ``diff2`` (NaN
    where not yet defined).

    Attributes
    ----------
    side : int
        +1 for the positive rates, -1 for the negative.
    end_rate : float
        End of the interval [0, end_rate] (the table's rate unit).
    n_points : int
        Table points in the interval.
    nonlinearity : float
        K_n of the interval [-].
    abs_diff : float
        |K_n(k) - K_n(k-1)| [-].
    diff2 : float
        abs_diff(k) - abs_diff(k-1) [-].
    counter : int
        Run of positive ``diff2``.
    """

    side: int
    end_rate: float
    n_points: int
    nonlinearity: float
    abs_diff: float
    diff2: float
    counter: int


@dataclass(frozen=True, slots=True)
class BreakpointSearch:
    """Result of :func:`breakpoint_search`: breakpoints (None where none was found) and the trace.

    Attributes
    ----------
    negative, positive : float or None
        Breakpoint rate on each side (None where none was found).
    trace : tuple of SearchStep
        Every step of the search.
    """

    negative: float | None
    positive: float | None
    trace: tuple[SearchStep, ...]

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """The breakpoints found, ascending."""
        return tuple(b for b in (self.negative, self.positive) if b is not None)


def _interval_kn(w: NDArray, f: NDArray) -> float:
    if w.size < 3:
        return 0.0  # a line through two points: no nonlinearity
    k, f0 = _ls_line(w, f)
    return float(np.max(np.abs(f - (k * w + f0))) / np.max(np.abs(f)))


def heuristic_split(
    interval_nonlinearity: ArrayLike, *, run_length: int = 3
) -> tuple[int | None, NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]:
    """The paper's split rule applied to the nonlinearities K_n(0), K_n(1), ... of growing intervals.

    d(k) = |K_n(k) - K_n(k-1)| (k >= 1), dd(k) = d(k) - d(k-1) (k >= 2); the
    counter grows by one on each dd(k) > 0 and resets to 0 otherwise. When it
    reaches ``run_length`` at k, the run began at k0 = k - run_length + 1 and the
    split index is k0 - 1: the last interval before the step that started the run.

    Parameters
    ----------
    interval_nonlinearity : array_like
        K_n of the intervals in growing order [-] (any consistent unit).
    run_length : int
        Consecutive positive dd needed, >= 1.

    Returns
    -------
    split : int or None
        Index into ``interval_nonlinearity`` of the last interval of the linear
        range, or None.
    abs_diff, diff2 : ndarray
        d and dd per interval (NaN where undefined).
    counter : ndarray of int
        The counter after each interval (frozen after the split).

    Examples
    --------
    >>> split, d, dd, c = heuristic_split([0.0, 1.0, 3.0, 6.0, 10.0])
    >>> split, c.tolist()
    (1, [0, 0, 1, 2, 3])
    """
    if (
        isinstance(run_length, bool)
        or not isinstance(run_length, (int, np.integer))
        or run_length < 1
    ):
        raise ValueError(f"run_length must be an integer >= 1; got {run_length!r}")
    kn = np.asarray(interval_nonlinearity, dtype=float)
    if kn.ndim != 1 or not np.all(np.isfinite(kn)):
        raise ValueError(
            f"interval_nonlinearity must be a 1-D array of finite values; got {interval_nonlinearity!r}"
        )
    d = np.full(kn.size, math.nan)
    d[1:] = np.abs(np.diff(kn))
    dd = np.full(kn.size, math.nan)
    dd[2:] = np.diff(d[1:])
    counter = np.zeros(kn.size, dtype=np.int64)
    split, c = None, 0
    for k in range(kn.size):
        if split is None:
            c = c + 1 if dd[k] > 0 else 0
            if c >= run_length:
                split = k - run_length
        counter[k] = c
    return split, d, dd, counter


def breakpoint_search(
    rates: ArrayLike, outputs: ArrayLike, *, run_length: int = 3
) -> BreakpointSearch:
    """The heuristic breakpoint search of seed paper 001 (section 2.2.1), with its trace.

    For each direction (positive, then negative rates):

    1. grow the interval from zero, [0, r_1], [0, r_2], ... (r_k the k-th rate
       away from zero, the zero rate or the smallest |rate| as start) and compute
       each interval's scale-factor nonlinearity K_n(k) (LS line over its points);
    2. d(k) = |K_n(k) - K_n(k-1)|, then dd(k) = d(k) - d(k-1); a positive dd(k)
       increments a counter, any other value resets it to 0;
    3. when the counter reaches ``run_length`` (3 in the paper), the run began at
       dd(k0) and the interval is split "at the first point": the breakpoint is
       r_(k0-1), the last rate before the step whose nonlinearity change started
       the run (the end of the last interval that still belonged to the linear
       range). The search stops at the first split in each direction (the paper's
       three regions: negative high rates, low rates, positive high rates).

    The convention of step 3 (which rate is "the first point") is our reading
    of the paper; with it a knee at 1800 deg/s yields 1800 deg/s. Steps 2-3 are
    :func:`heuristic_split`.

    Parameters
    ----------
    rates, outputs : array_like
        The rate table (strictly monotonic rates, >= 3 points, finite outputs).
    run_length : int
        Consecutive positive second differences needed to split, >= 1.

    Returns
    -------
    BreakpointSearch
    """
    if (
        isinstance(run_length, bool)
        or not isinstance(run_length, (int, np.integer))
        or run_length < 1
    ):
        raise ValueError(f"run_length must be an integer >= 1; got {run_length!r}")
    w, f = check_rate_table(rates, outputs)
    found: dict[int, float | None] = {1: None, -1: None}
    trace: list[SearchStep] = []
    for side in (1, -1):
        sel = np.flatnonzero(side * w >= 0)
        order = sel[np.argsort(side * w[sel])]
        if order.size < 2:
            continue
        kns = [_interval_kn(w[order[: k + 1]], f[order[: k + 1]]) for k in range(1, order.size)]
        split, d, dd, counter = heuristic_split(kns, run_length=run_length)
        if split is not None:
            found[side] = float(w[order[split + 1]])
        for j, kn in enumerate(kns):
            trace.append(
                SearchStep(
                    side,
                    float(w[order[j + 1]]),
                    j + 2,
                    kn,
                    float(d[j]),
                    float(dd[j]),
                    int(counter[j]),
                )
            )
    return BreakpointSearch(found[-1], found[1], tuple(trace))


def range_nonlinearity(rates: ArrayLike, outputs: ArrayLike, lo: float, hi: float) -> float:
    """K_n [-] of the part of a rate table with ``lo <= rate <= hi``; NaN with fewer than 3 rates.

    The LS line and F_m = max |F_j| are those of the selected points only
    (:func:`fit_scale_factor` on them), e.g. the low-rate segment between the breakpoints
    of :func:`breakpoint_search`.

    Parameters
    ----------
    rates, outputs : array_like
        The rate table (strictly monotonic rates, finite outputs).
    lo, hi : float
        Band of rates kept [rate unit], inclusive.

    Returns
    -------
    float
        K_n of the band [-], or NaN when it holds fewer than 3 rates.

    Examples
    --------
    >>> w = [-2.0, -1.0, 0.0, 1.0, 2.0]
    >>> range_nonlinearity(w, [-1.5, -1.0, 0.0, 1.0, 1.5], -1.0, 1.0)
    0.0
    """
    w, f = check_rate_table(rates, outputs, min_points=1)
    if not (isinstance(lo, (int, float)) and isinstance(hi, (int, float)) and lo <= hi):
        raise ValueError(f"range_nonlinearity needs numbers lo <= hi [rate unit]; got lo={lo!r}, hi={hi!r}")
    sel = (w >= lo) & (w <= hi)
    if sel.sum() < 3:
        return math.nan
    return fit_scale_factor(w[sel], f[sel]).nonlinearity


def repeatability_floor(
    rates: ArrayLike, fit_means: ArrayLike, outputs: ArrayLike
) -> NDArray[np.float64]:
    """Compensate ``outputs`` with a curve through the fitting runs' per-rate mean outputs.

    The curve maps output -> rate by piecewise-linear interpolation through the
    points (mean over the fitting runs of the output at rate j, rate j), extended
    linearly beyond the end rates by the end chords. It has no model error at the
    table rates, so the K_n left on a held-out run is its run-to-run
    difference from the fitting runs (divided by the local slope): the
    repeatability floor of a compensation fitted to these runs when the runs differ
    by bias, temperature and noise. It is one run's value, not a bound: a smoother
    curve can land below it, and does when the runs' scale factors differ.

    Parameters
    ----------
    rates : array_like, shape (m,)
        Table rates [rate unit].
    fit_means : array_like, shape (n_runs, m)
        Per-rate mean outputs of the fitting runs [output unit].
    outputs : array_like, shape (m,)
        The outputs to compensate [output unit].

    Returns
    -------
    ndarray, shape (m,)
        Compensated rates [rate unit].

    Raises
    ------
    ValueError
        If the mean outputs do not increase strictly with rate (a saturated plateau: no
        curve through them can be inverted).

    Examples
    --------
    >>> repeatability_floor([-1.0, 0.0, 1.0], [[-2.0, 0.0, 2.0]], [1.0, 3.0]).tolist()
    [0.5, 1.5]
    """
    xm = np.asarray(fit_means, dtype=float).mean(axis=0)
    order = np.argsort(xm)
    x, r = xm[order], np.asarray(rates, dtype=float)[order]
    if np.any(np.diff(x) <= 0):
        raise ValueError(
            "repeatability_floor needs mean outputs that increase strictly with rate; "
            f"got {xm.tolist()!r}"
        )
    o = np.asarray(outputs, dtype=float)
    out = np.interp(o, x, r)
    lo, hi = o < x[0], o > x[-1]
    out[lo] = r[0] + (o[lo] - x[0]) * (r[1] - r[0]) / (x[1] - x[0])
    out[hi] = r[-1] + (o[hi] - x[-1]) * (r[-1] - r[-2]) / (x[-1] - x[-2])
    return out


def dwell_means(output: ArrayLike, windows: ArrayLike) -> NDArray[np.float64]:
    """Mean of a continuous rate-table record over each settled dwell: the table's outputs F_j.

    Parameters
    ----------
    output : array_like, shape (n,)
        The gyro output sampled through the whole table program [output unit].
    windows : array_like of int, shape (m, 2)
        Per table rate, the [start, stop) sample indices of its settled dwell (settling
        time already cut), 0 <= start < stop <= n.

    Returns
    -------
    ndarray, shape (m,)
        Mean output over each window [output unit].

    Raises
    ------
    ValueError
        If ``output`` is not 1-D, or a window is not an integer pair with
        0 <= start < stop <= n.

    Examples
    --------
    >>> dwell_means([9.0, 1.0, 2.0, 9.0, 5.0, 7.0], [[1, 3], [4, 6]]).tolist()
    [1.5, 6.0]
    """
    y = np.asarray(output, dtype=float)
    if y.ndim != 1:
        raise ValueError(f"output must be a 1-D record; got shape {y.shape}")
    w = np.asarray(windows)
    if w.ndim != 2 or w.shape[1] != 2 or w.shape[0] < 1 or not np.issubdtype(w.dtype, np.integer):
        raise ValueError(f"windows must be integer [start, stop) pairs, shape (m, 2); got {windows!r}")
    bad = (w[:, 0] < 0) | (w[:, 0] >= w[:, 1]) | (w[:, 1] > y.size)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(
            f"windows must satisfy 0 <= start < stop <= {y.size} (record length); "
            f"got {w[i].tolist()!r} at index {i}"
        )
    return np.array([float(np.mean(y[a:b])) for a, b in w])
