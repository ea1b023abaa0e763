"""Stepwise multiple linear regression with partial-F entry and removal (as MATLAB ``stepwisefit``).

Start from the constant model. At each step, for every excluded term compute the
partial F statistic of adding it,

    F_j = (RSS_S - RSS_{S+j}) / (RSS_{S+j} / (n - |S| - 2)) ~ F(1, n - |S| - 2),

and add the term with the smallest p-value if it is below ``p_enter``; if no term
can enter, compute for every included term the partial F of removing it,

    F_j = (RSS_{S-j} - RSS_S) / (RSS_S / (n - |S| - 1)) ~ F(1, n - |S| - 1),

and remove the term with the largest p-value if it exceeds ``p_remove``. Stop when
nothing enters or leaves (or after ``max_iter`` steps).

References
----------
MathWorks, ``stepwisefit`` documentation (defaults PEnter = 0.05, PRemove = 0.10,
empty initial model); Draper & Smith, *Applied Regression Analysis*, 3rd ed.,
ch. 15 (stepwise procedure); docs/physics.md 7.4.
"""

from __future__ import annotations

import math
import numbers
import warnings

import numpy as np
from numpy.typing import NDArray
from scipy import stats
from sklearn.base import BaseEstimator, RegressorMixin
from sklearn.exceptions import ConvergenceWarning
from sklearn.utils.validation import check_is_fitted, validate_data

__all__ = ["StepwiseRegression"]


def _rss(X: NDArray[np.float64], y: NDArray[np.float64], cols: list[int]) -> float:
    """Residual sum of squares of y on [1, X[:, cols]] by least squares (centred for conditioning)."""
    yc = y - y.mean()
    if not cols:
        return float(yc @ yc)
    Xc = X[:, cols] - X[:, cols].mean(axis=0)
    beta, *_ = np.linalg.lstsq(Xc, yc, rcond=None)
    r = yc - Xc @ beta
    return float(r @ r)


def _partial_p(rss_small: float, rss_big: float, df: int) -> float:
    """p-value of the partial F test of one extra term (df = residual dof of the bigger model)."""
    if df <= 0:
        return 1.0
    if rss_big <= 1e-14 * max(rss_small, 1e-300):
        return 0.0 if rss_small > rss_big else 1.0
    f = max(rss_small - rss_big, 0.0) / (rss_big / df)
    return float(stats.f.sf(f, 1, df))


class StepwiseRegression(RegressorMixin, BaseEstimator):
    """Linear regression whose terms enter and leave by partial F-tests (MATLAB ``stepwisefit``).

    Parameters
    ----------
    p_enter : float, default 0.05
        A term enters if the p-value of its partial F test is below this.
    p_remove : float, default 0.10
        An included term leaves if its p-value exceeds this. Must be >= ``p_enter``
        (otherwise a term could enter and leave forever).
    max_iter : int, default 100
        Maximum number of entry/removal steps.

    Attributes
    ----------
    support_ : ndarray of bool, shape (n_features,)
        Selected terms.
    coef_ : ndarray, shape (n_features,)
        Coefficients of the final model (0 for excluded terms).
    intercept_ : float
    pvalues_ : ndarray, shape (n_features,)
        For included terms the p-value of removing them, for excluded terms the
        p-value of adding them (MATLAB's PVAL).
    coef_stderr_ : ndarray, shape (n_features,)
        Standard errors of the included coefficients (NaN for excluded).
    multiple_r_, r2_, adj_r2_, rmse_, f_statistic_, significance_f_ : float
        Table statistics of the final model: R = sqrt(R^2); R^2 = 1 - RSS/TSS;
        adjusted R^2 = 1 - (1 - R^2)(n - 1)/(n - p - 1); RMSE = sqrt(RSS/(n - p - 1));
        F = ((TSS - RSS)/p) / (RSS/(n - p - 1)) with significance F = P(F(p, n-p-1) > F).
        With no term selected: R = R^2 = 0 and F, significance F are NaN.
    n_selected_ : int
    history_ : list of tuple
        ``("enter" | "remove", feature index, p-value)`` per step.
    n_iter_ : int
    n_features_in_ : int

    Raises
    ------
    ValueError (in ``fit``)
        If p_enter/p_remove are not in (0, 1) or p_enter > p_remove; if
        n_samples <= n_features + 1 (too few observations, e.g. fewer 100-s blocks
        than regressors); if a column has zero variance.

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> X = rng.standard_normal((200, 4))
    >>> y = 1.0 + 2.0 * X[:, 0] - 3.0 * X[:, 2] + 0.1 * rng.standard_normal(200)
    >>> m = StepwiseRegression().fit(X, y)
    >>> m.support_.tolist(), np.round(m.coef_[[0, 2]], 1).tolist()
    ([True, False, True, False], [2.0, -3.0])
    """

    def __init__(self, p_enter: float = 0.05, p_remove: float = 0.10, max_iter: int = 100):
        self.p_enter = p_enter
        self.p_remove = p_remove
        self.max_iter = max_iter

    def _check_params(self) -> None:
        for name in ("p_enter", "p_remove"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, numbers.Real) or not (0.0 < float(v) < 1.0):
                raise ValueError(
                    f"StepwiseRegression.{name} must be a probability in (0, 1); got {v!r}"
                )
        if self.p_enter > self.p_remove:
            raise ValueError(
                "StepwiseRegression.p_enter must be <= p_remove; "
                f"got p_enter={self.p_enter!r} > p_remove={self.p_remove!r}"
            )
        if (
            isinstance(self.max_iter, bool)
            or not isinstance(self.max_iter, numbers.Integral)
            or self.max_iter < 1
        ):
            raise ValueError(
                f"StepwiseRegression.max_iter must be an integer >= 1; got {self.max_iter!r}"
            )

    def fit(self, X, y):
        """Select terms by stepwise partial F-tests and fit the final model.

        Parameters
        ----------
        X : array_like, shape (n_samples, n_features)
            Candidate regressors (e.g. x1..x11 on 100-s blocks).
        y : array_like, shape (n_samples,)
            Response (e.g. 100-s mean gyro output).

        Returns
        -------
        self
        """
        self._check_params()
        X, y = validate_data(self, X, y, y_numeric=True, dtype=np.float64)
        n, p = X.shape
        if n <= p + 1:
            raise ValueError(
                f"StepwiseRegression needs more observations than regressors + 1: n_samples = {n}, "
                f"n_features = {p}; give at least {p + 2} samples (e.g. 100-s blocks)"
            )
        sd = X.std(axis=0)
        flat = np.flatnonzero(~(sd > 1e-12 * np.maximum(1.0, np.abs(X).max(axis=0))))
        if flat.size:
            raise ValueError(
                f"StepwiseRegression: regressor column(s) {flat.tolist()} have zero variance "
                "(constant over the record; the intercept already models a constant); drop them"
            )
        y = np.asarray(y, dtype=np.float64)
        included: list[int] = []
        history: list[tuple[str, int, float]] = []
        n_iter = 0
        converged = False
        while n_iter < self.max_iter:
            rss_s = _rss(X, y, included)
            excluded = [j for j in range(p) if j not in included]
            enter = [
                (_partial_p(rss_s, _rss(X, y, included + [j]), n - len(included) - 2), j)
                for j in excluded
            ]
            if enter:
                pv, j = min(enter)
                if pv < self.p_enter:
                    included.append(j)
                    history.append(("enter", j, pv))
                    n_iter += 1
                    continue
            df = n - len(included) - 1
            remove = [
                (_partial_p(_rss(X, y, [k for k in included if k != j]), rss_s, df), j)
                for j in included
            ]
            if remove:
                pv, j = max(remove)
                if pv > self.p_remove:
                    included.remove(j)
                    history.append(("remove", j, pv))
                    n_iter += 1
                    continue
            converged = True
            break
        if not converged:
            warnings.warn(
                f"StepwiseRegression did not settle within max_iter={self.max_iter} steps",
                ConvergenceWarning,
                stacklevel=2,
            )
        self._finish(X, y, sorted(included))
        self.history_ = history
        self.n_iter_ = n_iter
        return self

    def _finish(self, X: NDArray[np.float64], y: NDArray[np.float64], cols: list[int]) -> None:
        n, p_all = X.shape
        p = len(cols)
        ybar = float(y.mean())
        tss = float(((y - ybar) ** 2).sum())
        coef = np.zeros(p_all)
        stderr = np.full(p_all, np.nan)
        if cols:
            A = np.column_stack([np.ones(n), X[:, cols]])
            beta, *_ = np.linalg.lstsq(A, y, rcond=None)
            r = y - A @ beta
            rss = float(r @ r)
            coef[cols] = beta[1:]
            intercept = float(beta[0])
            dof = n - p - 1
            s2 = rss / dof
            cov = s2 * np.linalg.pinv(A.T @ A)
            stderr[cols] = np.sqrt(np.maximum(np.diag(cov)[1:], 0.0))
        else:
            rss = tss
            intercept = ybar
        dof = n - p - 1
        r2 = 1.0 - rss / tss if tss > 0 else 0.0
        self.coef_ = coef
        self.intercept_ = intercept
        self.support_ = np.zeros(p_all, dtype=bool)
        self.support_[cols] = True
        self.n_selected_ = p
        self.coef_stderr_ = stderr
        self.r2_ = float(r2)
        self.multiple_r_ = float(math.sqrt(max(r2, 0.0)))
        self.adj_r2_ = float(1.0 - (1.0 - r2) * (n - 1) / dof)
        self.rmse_ = float(math.sqrt(rss / dof))
        if p and rss > 0:
            f = ((tss - rss) / p) / (rss / dof)
            self.f_statistic_ = float(f)
            self.significance_f_ = float(stats.f.sf(f, p, dof))
        elif p:
            self.f_statistic_, self.significance_f_ = math.inf, 0.0
        else:
            self.f_statistic_, self.significance_f_ = math.nan, math.nan
        # MATLAB PVAL: removal p for included terms, entry p for excluded ones
        pv = np.empty(p_all)
        for j in range(p_all):
            if j in cols:
                pv[j] = _partial_p(_rss(X, y, [k for k in cols if k != j]), rss, dof)
            else:
                pv[j] = _partial_p(rss, _rss(X, y, cols + [j]), dof - 1)
        self.pvalues_ = pv

    def predict(self, X):
        """Predicted response ``intercept_ + X @ coef_``."""
        check_is_fitted(self, "coef_")
        X = validate_data(self, X, reset=False, dtype=np.float64)
        return self.intercept_ + X @ self.coef_

    def summary(self) -> dict[str, float | int | list]:
        """The regression table statistics (Multiple R, R^2, adjusted R^2, RMSE, F, significance F)."""
        check_is_fitted(self, "coef_")
        return {
            "multiple_r": self.multiple_r_,
            "r2": self.r2_,
            "adj_r2": self.adj_r2_,
            "rmse": self.rmse_,
            "f_statistic": self.f_statistic_,
            "significance_f": self.significance_f_,
            "selected": np.flatnonzero(self.support_).tolist(),
        }
