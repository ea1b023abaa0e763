"""Polynomial compensators: plain, two-stage, and heuristic piecewise with cubic Hermite joins.

All three are scikit-learn regressors. Each fits in scaled variables: every input
feature is mapped to u in [-1, 1] by its training min/max and the target to
[-1, 1] the same way, and the polynomial is expressed in the Legendre basis of u.
That is the same polynomial as the power series but well conditioned (raw 9th
powers of 3600 deg/s are not; docs/physics.md 7.5).

With several input features a polynomial is additive (a sum of one polynomial
per feature, no cross terms); with one feature, the usual case of a gyro's output
against the table rate, it is the ordinary polynomial of the given degree.

References
----------
Seed paper 001 (Du, Su, Liu, Li), sections 2.1-2.2 and 3; docs/physics.md 7.5.
"""

from __future__ import annotations

import math
import warnings
from numbers import Integral, Real

import numpy as np
from numpy.polynomial import legendre as L
from numpy.typing import ArrayLike, NDArray
from sklearn.base import BaseEstimator, RegressorMixin
from sklearn.utils.validation import check_is_fitted, validate_data

from gyrobench.analysis.scale_factor import BreakpointSearch, breakpoint_search

__all__ = ["PolynomialRegressor", "TwoStagePolynomial", "PiecewisePolynomial"]


def _check_degree(owner: str, name: str, d) -> int:
    if isinstance(d, bool) or not isinstance(d, Integral) or d < 0:
        raise ValueError(f"{owner}.{name} must be an integer >= 0; got {d!r}")
    return int(d)


def _check_alpha(owner: str, a) -> float:
    if isinstance(a, bool) or not isinstance(a, Real) or not (math.isfinite(float(a)) and float(a) >= 0):
        raise ValueError(
            f"{owner}.alpha must be a finite number >= 0 (curvature-penalty weight, scaled units); got {a!r}"
        )
    return float(a)


def _minmax(v: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Centre and half-range along axis 0 (half-range 1 where the data are constant)."""
    lo, hi = v.min(axis=0), v.max(axis=0)
    half = 0.5 * (hi - lo)
    return 0.5 * (lo + hi), np.where(half > 0, half, 1.0)


def _curvature_root(d: int) -> NDArray[np.float64]:
    """C with C'C = R, R[j, k] = int_{-1}^{1} P_j''(u) P_k''(u) du (j, k = 1..d).

    Gauss-Legendre quadrature with d nodes is exact (integrand degree <= 2d - 4).
    """
    u, wq = L.leggauss(max(d, 2))
    D2 = np.column_stack([L.legval(u, L.legder(np.eye(d + 1)[k], 2)) for k in range(1, d + 1)])
    R = D2.T @ (wq[:, None] * D2)
    ev, V = np.linalg.eigh(R)
    return (V * np.sqrt(np.clip(ev, 0.0, None))).T


class PolynomialRegressor(RegressorMixin, BaseEstimator):
    """Least-squares polynomial of ``degree`` in scaled inputs (additive over features).

    y = c0 + sum_f sum_{k=1..degree} c_fk P_k(u_f),  u_f = (x_f - centre_f)/half_range_f,
    P_k the Legendre polynomials; fitted by least squares in scaled target units z,
    minimising sum (z - z_hat)^2 + alpha sum_f int_{-1}^{1} (d^2 p_f / du_f^2)^2 du_f
    (a curvature penalty, as in smoothing splines; 0 gives ordinary least squares).
    The penalty keeps a high degree well posed when the inputs come in a few tight
    clusters (repeated runs of a rate table): it leaves the fit through the cluster
    means and removes the oscillation between them.

    Parameters
    ----------
    degree : int
        Polynomial degree, >= 0.
    alpha : float
        Curvature-penalty weight in scaled units, >= 0 (0: ordinary least squares).

    Attributes
    ----------
    coef_ : ndarray, shape (1 + n_features * degree,)
        Legendre coefficients (scaled units), intercept first.
    x_center_, x_half_ : ndarray
        Input scaling.
    y_center_, y_half_ : float
        Target scaling.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.linspace(-3600.0, 3600.0, 21)[:, None]
    >>> m = PolynomialRegressor(degree=3).fit(x, 2.0 + 0.5 * x[:, 0] - 1e-9 * x[:, 0] ** 3)
    >>> float(np.round(m.predict([[1000.0]])[0], 9))
    501.0
    """

    def __init__(self, degree=9, alpha=0.0):
        self.degree = degree
        self.alpha = alpha

    def _design(self, X: NDArray[np.float64]) -> NDArray[np.float64]:
        """Design matrix in the Legendre basis: [1, P_1(u_1) .. P_d(u_1), P_1(u_2) ..]."""
        U = (X - self.x_center_) / self.x_half_
        d = self.degree_
        return np.hstack(
            [np.ones((X.shape[0], 1))] + [L.legvander(U[:, f], d)[:, 1:] for f in range(X.shape[1])]
        )

    def fit(self, X: ArrayLike, y: ArrayLike) -> PolynomialRegressor:
        """Fit the polynomial to (X, y).

        Raises
        ------
        ValueError
            If the degree is larger than the points allow: fewer samples than
            coefficients, or (one feature) fewer than degree + 1 distinct inputs.
        """
        d = _check_degree(type(self).__name__, "degree", self.degree)
        alpha = _check_alpha(type(self).__name__, self.alpha)
        X, y = validate_data(self, X, y, y_numeric=True)
        X = np.asarray(X, dtype=float)
        y = np.asarray(y, dtype=float)
        n, p = X.shape
        n_coef = 1 + p * d
        if n < n_coef:
            raise ValueError(
                f"{type(self).__name__}: degree {d} with {p} feature(s) has {n_coef} coefficients and needs at "
                f"least {n_coef} samples; got {n} sample(s)"
            )
        if p == 1:
            distinct = np.unique(X[:, 0]).size
            if distinct < d + 1:
                raise ValueError(
                    f"{type(self).__name__}: degree {d} needs at least {d + 1} distinct input values; got {distinct}"
                )
        self.degree_ = d
        self.x_center_, self.x_half_ = _minmax(X)
        yc, yh = _minmax(y[:, None])
        self.y_center_, self.y_half_ = float(yc[0]), float(yh[0])
        B = self._design(X)
        z = (y - self.y_center_) / self.y_half_
        if alpha > 0 and d >= 2:
            C = np.zeros((p * d, n_coef))
            root = _curvature_root(d)
            for f in range(p):
                C[f * d : (f + 1) * d, 1 + f * d : 1 + (f + 1) * d] = root
            B = np.vstack([B, math.sqrt(alpha) * C])
            z = np.concatenate([z, np.zeros(p * d)])
        self.coef_, *_ = np.linalg.lstsq(B, z, rcond=None)
        return self

    def predict(self, X: ArrayLike) -> NDArray[np.float64]:
        """Predicted target for X, shape (n_samples,)."""
        check_is_fitted(self, "coef_")
        return self._eval(np.asarray(validate_data(self, X, reset=False), dtype=float))

    def _eval(self, X: NDArray[np.float64]) -> NDArray[np.float64]:
        """Prediction for an already validated float array (no checks; used by the composite models)."""
        return self.y_center_ + self.y_half_ * (self._design(X) @ self.coef_)

    def derivative(self, X: ArrayLike) -> NDArray[np.float64]:
        """d prediction / d feature 0 at X [target unit per input unit]."""
        check_is_fitted(self, "coef_")
        return self._eval_derivative(np.asarray(validate_data(self, X, reset=False), dtype=float))

    def _eval_derivative(self, X: NDArray[np.float64]) -> NDArray[np.float64]:
        """d/dx_0 for an already validated float array."""
        d = self.degree_
        if d == 0:
            return np.zeros(X.shape[0])
        u0 = (X[:, 0] - self.x_center_[0]) / self.x_half_[0]
        c = np.concatenate([[0.0], self.coef_[1 : 1 + d]])
        return (self.y_half_ / self.x_half_[0]) * L.legval(u0, L.legder(c))


class TwoStagePolynomial(RegressorMixin, BaseEstimator):
    """Two-stage polynomial: y ~ P2(P1(x)), each stage a least-squares polynomial.

    Seed paper 001's baseline ("fit the raw output with a 9th-order polynomial,
    then use that fitted output as the input of a second 9th-order fit to the
    ideal output"), read as: stage 1 fits P1: x -> y; stage 2 fits P2: P1(x) -> y.

    Parameters
    ----------
    degree : int
        Degree of stage 1, >= 0.
    second_degree : int
        Degree of stage 2, >= 0.
    alpha : float
        Curvature-penalty weight of both stages (scaled units), >= 0.

    Attributes
    ----------
    stage1_, stage2_ : PolynomialRegressor
    """

    def __init__(self, degree=9, second_degree=9, alpha=0.0):
        self.degree = degree
        self.second_degree = second_degree
        self.alpha = alpha

    def fit(self, X: ArrayLike, y: ArrayLike) -> TwoStagePolynomial:
        """Fit stage 1 on (X, y), then stage 2 on (stage-1 prediction, y)."""
        owner = type(self).__name__
        _check_degree(owner, "degree", self.degree)
        _check_degree(owner, "second_degree", self.second_degree)
        _check_alpha(owner, self.alpha)
        X, y = validate_data(self, X, y, y_numeric=True)
        self.stage1_ = PolynomialRegressor(degree=self.degree, alpha=self.alpha).fit(X, y)
        z = self.stage1_.predict(X)[:, None]
        self.stage2_ = PolynomialRegressor(degree=self.second_degree, alpha=self.alpha).fit(z, y)
        return self

    def predict(self, X: ArrayLike) -> NDArray[np.float64]:
        """P2(P1(X)), shape (n_samples,)."""
        check_is_fitted(self, "stage2_")
        X = np.asarray(validate_data(self, X, reset=False), dtype=float)
        return self.stage2_._eval(self.stage1_._eval(X)[:, None])


class PiecewisePolynomial(RegressorMixin, BaseEstimator):
    """Heuristic piecewise polynomial with C1 cubic Hermite joins (seed paper 001).

    Input x (the gyro output), target y (the table rate). The x axis is split at
    breakpoints b_1 < ... < b_m into segments, each fitted with its own polynomial
    order on the samples with x in [b_left - h, b_right + h] (h = half the join
    width, so neighbouring fits overlap over each join). Over a join [b - h, b + h]
    the prediction is the cubic Hermite curve

        H(x) = h00(t) y0 + h10(t) w m0 + h01(t) y1 + h11(t) w m1,  t = (x - x0)/w, w = 2h,
        y0 = P_L(x0), m0 = P_L'(x0), y1 = P_R(x1), m1 = P_R'(x1),  x0 = b - h, x1 = b + h,

    (h00 = 2t^3 - 3t^2 + 1, h10 = t^3 - 2t^2 + t, h01 = -2t^3 + 3t^2, h11 = t^3 - t^2;
    what ``scipy.interpolate.CubicHermiteSpline([x0, x1], [y0, y1], [m0, m1])``
    evaluates), so the whole curve is C1.

    With more than one input feature, feature 0 is the switching variable: the
    segments and joins are defined on it, each segment is an additive polynomial
    in all features (:class:`PolynomialRegressor`), and y0, m0, y1, m1 are taken
    at x_0 = x0 or x1 with the other features at their sample values (C1 in x_0).

    Parameters
    ----------
    orders : tuple of int
        Polynomial order of each segment, left to right. With
        ``breakpoints="heuristic"`` exactly three (negative high rates, low rates,
        positive high rates; the paper's 9-1-9); a side where no breakpoint is
        found merges into the middle segment.
    breakpoints : "heuristic" or tuple of float
        ``"heuristic"``: :func:`gyrobench.analysis.scale_factor.breakpoint_search` on the
        rate table formed by the distinct target values y (table rates) and the
        mean x at each; the breakpoints in x are the mean outputs at the rates
        found. If the search cannot run (fewer than 3 distinct y) or a breakpoint
        cannot split x (see :meth:`fit`), fewer segments are fitted and a
        ``UserWarning`` says why. A tuple: breakpoints in input (x) units,
        strictly increasing.
    join_width : float
        Width of each Hermite join as a fraction of the input span, in (0, 0.5).
    run_length : int
        Passed to the breakpoint search (3 in the paper).
    alpha : float
        Curvature-penalty weight of the segment fits (scaled units), >= 0. The
        default 1e-6 keeps the paper's 9th-order outer segments well posed on a
        few runs of six rates each (6 clusters of inputs, 10 coefficients);
        alpha = 0 there oscillates by thousands of deg/s between the rates.

    Attributes
    ----------
    breakpoints_ : tuple of float
        Breakpoints in x units.
    breakpoint_rates_ : tuple of float
        Breakpoints in target units (heuristic mode; else empty).
    search_ : BreakpointSearch or None
        The heuristic's result and trace.
    orders_ : tuple of int
        Orders of the segments actually fitted.
    segments_ : list of PolynomialRegressor
    joins_ : list of tuple of float
        (x0, x1) of each Hermite join.
    """

    def __init__(
        self, orders=(9, 1, 9), breakpoints="heuristic", join_width=0.05, run_length=3, alpha=1e-6
    ):
        self.orders = orders
        self.breakpoints = breakpoints
        self.join_width = join_width
        self.run_length = run_length
        self.alpha = alpha

    def _check_params(self) -> tuple[tuple[int, ...], float, float]:
        owner = type(self).__name__
        if not isinstance(self.orders, (tuple, list)) or len(self.orders) < 1:
            raise ValueError(
                f"{owner}.orders must be a non-empty tuple of integers >= 0; got {self.orders!r}"
            )
        orders = tuple(_check_degree(owner, f"orders[{i}]", o) for i, o in enumerate(self.orders))
        if isinstance(self.breakpoints, str):
            if self.breakpoints != "heuristic":
                raise ValueError(
                    f"{owner}.breakpoints must be 'heuristic' or a tuple of floats; got {self.breakpoints!r}"
                )
            if len(orders) != 3:
                raise ValueError(
                    f"{owner}.orders must have 3 entries with breakpoints='heuristic'; got {self.orders!r}"
                )
        else:
            if not isinstance(self.breakpoints, (tuple, list)):
                raise ValueError(
                    f"{owner}.breakpoints must be 'heuristic' or a tuple of floats; got {self.breakpoints!r}"
                )
            b = np.asarray(self.breakpoints, dtype=float)
            if not np.all(np.isfinite(b)) or np.any(np.diff(b) <= 0):
                raise ValueError(
                    f"{owner}.breakpoints must be finite and strictly increasing; got {self.breakpoints!r}"
                )
            if len(orders) != b.size + 1:
                raise ValueError(
                    f"{owner}.orders must have len(breakpoints) + 1 = {b.size + 1} entries; got {len(orders)}"
                )
        w = self.join_width
        if isinstance(w, bool) or not isinstance(w, Real) or not (0 < float(w) < 0.5):
            raise ValueError(
                f"{owner}.join_width must be in (0, 0.5) (fraction of the input span); got {w!r}"
            )
        return orders, float(w), _check_alpha(owner, self.alpha)

    def fit(self, X: ArrayLike, y: ArrayLike) -> PiecewisePolynomial:
        """Find or take the breakpoints, fit each segment, build the Hermite joins.

        Raises
        ------
        ValueError
            For a given breakpoint outside the data (by the half join width) or
            closer than the join width to another, or a segment with fewer
            distinct inputs than its order + 1.

        Warns
        -----
        UserWarning
            Heuristic mode on data that are not a rate table of an increasing
            gyro: fewer than 3 distinct targets, or found breakpoints whose mean
            outputs do not increase, lie within a half join of the data's ends or
            closer than a join; such breakpoints are dropped.
        """
        orders, wfrac, alpha = self._check_params()
        X, y = validate_data(self, X, y, y_numeric=True)
        X = np.asarray(X, dtype=float)
        y = np.asarray(y, dtype=float)
        x = X[:, 0]
        lo, hi = float(x.min()), float(x.max())
        h = 0.5 * wfrac * (hi - lo)
        self.half_join_ = h
        self.search_: BreakpointSearch | None = None
        if isinstance(self.breakpoints, str):
            self._heuristic(x, y, orders, lo, hi, h)
        else:
            self.breakpoints_: tuple[float, ...] = tuple(float(b) for b in self.breakpoints)
            self.breakpoint_rates_: tuple[float, ...] = ()
            self.orders_ = orders
        edges = [-np.inf, *self.breakpoints_, np.inf]
        for i, b in enumerate(self.breakpoints_):
            if not (lo + h < b < hi - h):
                raise ValueError(
                    f"breakpoint {b!r} must lie inside the data ({lo!r}, {hi!r}) by more than the half join width {h!r}"
                )
            if i and b - self.breakpoints_[i - 1] <= 2 * h:
                raise ValueError(
                    f"breakpoints {self.breakpoints_[i - 1]!r} and {b!r} are closer than the join width {2 * h!r}"
                )
        self.segments_ = []
        for i, order in enumerate(self.orders_):
            sel = (x >= edges[i] - h) & (x <= edges[i + 1] + h)
            distinct = np.unique(x[sel]).size
            if distinct < order + 1:
                raise ValueError(
                    f"segment {i} (x from {edges[i]!r} to {edges[i + 1]!r}): order {order} needs at least "
                    f"{order + 1} distinct inputs; got {distinct} sample(s) with distinct inputs"
                )
            self.segments_.append(
                PolynomialRegressor(degree=order, alpha=alpha).fit(X[sel], y[sel])
            )
        self.joins_ = [(b - h, b + h) for b in self.breakpoints_]
        self._join_ends: list[tuple[float, float, float, float]] | None = None
        if X.shape[1] == 1:  # the end values and slopes are constants: evaluate them once
            self._join_ends = [
                self._join_end_values(i, np.zeros((1, 1))) for i in range(len(self.joins_))
            ]
        return self

    def _heuristic(
        self, x: NDArray, y: NDArray, orders: tuple[int, ...], lo: float, hi: float, h: float
    ) -> None:
        """Breakpoints by the paper's search on the table (distinct y, mean x at each).

        Where the search cannot run (fewer than 3 distinct targets) or a breakpoint
        it finds cannot split x (the outputs at the two breakpoints do not increase,
        or one lies within a half join of the data's ends), the data are not a rate
        table of an increasing gyro: the model falls back to fewer segments and
        warns (legal input, degraded model), as for any regression data.
        """
        rates, inv = np.unique(y, return_inverse=True)
        if rates.size < 3:
            warnings.warn(
                f"{type(self).__name__}: the breakpoint search needs at least 3 distinct targets "
                f"(table rates); got {rates.size}: fitting one segment of order {orders[1]}",
                UserWarning,
                stacklevel=3,
            )
            self.breakpoints_, self.breakpoint_rates_, self.orders_ = (), (), (orders[1],)
            return
        xm = np.bincount(inv, weights=x) / np.bincount(inv)
        self.search_ = breakpoint_search(rates, xm, run_length=self.run_length)
        found = []  # (x, rate, side)
        if self.search_.negative is not None:
            found.append((float(xm[rates == self.search_.negative][0]), self.search_.negative, 0))
        if self.search_.positive is not None:
            found.append((float(xm[rates == self.search_.positive][0]), self.search_.positive, 2))
        usable = [f for f in found if lo + h < f[0] < hi - h]
        if len(usable) == 2 and not usable[1][0] - usable[0][0] > 2 * h:
            usable = []  # not increasing in x, or closer than a join
        if len(usable) < len(found):
            warnings.warn(
                f"{type(self).__name__}: breakpoints at x = {[f[0] for f in found]} (rates "
                f"{[f[1] for f in found]}) cannot split the inputs (they must increase, lie inside "
                f"({lo!r}, {hi!r}) by more than {h!r} and be more than {2 * h!r} apart); "
                f"using {[f[0] for f in usable]}",
                UserWarning,
                stacklevel=3,
            )
        self.breakpoints_ = tuple(f[0] for f in usable)
        self.breakpoint_rates_ = tuple(f[1] for f in usable)
        used = [orders[1]]
        for f in usable:
            if f[2] == 0:
                used.insert(0, orders[0])
            else:
                used.append(orders[2])
        self.orders_ = tuple(used)

    def _join_end_values(self, i: int, X: NDArray[np.float64]):
        """y0, m0 (left segment at x0) and y1, m1 (right segment at x1), other features from X."""
        x0, x1 = self.joins_[i]
        left, right = self.segments_[i], self.segments_[i + 1]
        X0, X1 = X.copy(), X.copy()
        X0[:, 0], X1[:, 0] = x0, x1
        return (
            left._eval(X0),
            left._eval_derivative(X0),
            right._eval(X1),
            right._eval_derivative(X1),
        )

    def _hermite(self, i: int, X: NDArray[np.float64], deriv: bool) -> NDArray[np.float64]:
        """Join i at the samples X (feature 0 inside [x0, x1]): value, or d/dx_0 when ``deriv``."""
        x0, x1 = self.joins_[i]
        w = x1 - x0
        ends = (
            self._join_ends[i] if self._join_ends is not None else self._join_end_values(i, X)
        )
        y0, m0, y1, m1 = ends
        t = (X[:, 0] - x0) / w
        if deriv:
            return (
                (6 * t**2 - 6 * t) * (y0 - y1) / w
                + (3 * t**2 - 4 * t + 1) * m0
                + (3 * t**2 - 2 * t) * m1
            )
        t2, t3 = t * t, t * t * t
        return (
            (2 * t3 - 3 * t2 + 1) * y0
            + (t3 - 2 * t2 + t) * w * m0
            + (-2 * t3 + 3 * t2) * y1
            + (t3 - t2) * w * m1
        )

    def _piecewise(self, X: NDArray[np.float64], deriv: bool) -> NDArray[np.float64]:
        x = X[:, 0]
        seg = np.searchsorted(np.asarray(self.breakpoints_, dtype=float), x, side="right")
        out = np.empty(x.size)
        for i, model in enumerate(self.segments_):
            m = seg == i
            if m.any():
                out[m] = model._eval_derivative(X[m]) if deriv else model._eval(X[m])
        for i, (x0, x1) in enumerate(self.joins_):
            m = (x >= x0) & (x <= x1)
            if m.any():
                out[m] = self._hermite(i, X[m], deriv)
        return out

    def predict(self, X: ArrayLike) -> NDArray[np.float64]:
        """Piecewise prediction with Hermite joins, shape (n_samples,)."""
        check_is_fitted(self, "segments_")
        return self._piecewise(
            np.asarray(validate_data(self, X, reset=False), dtype=float), deriv=False
        )

    def derivative(self, X: ArrayLike) -> NDArray[np.float64]:
        """d prediction / d feature 0 at X (analytic, including the Hermite joins)."""
        check_is_fitted(self, "segments_")
        return self._piecewise(
            np.asarray(validate_data(self, X, reset=False), dtype=float), deriv=True
        )
