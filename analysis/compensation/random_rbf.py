"""RBF network with randomly fixed centres, grown until its training error meets a goal.

The network (Haykin's "fixed centres selected at random"; the 随机固定法 of seed paper 000)
is MATLAB ``newrb``'s radial-basis layer with a linear output layer:

    y(x) = b2 + sum_i w_i exp(-(b ||x - c_i||)^2),   b = sqrt(-ln 0.5) / spread

so a basis function falls to 0.5 at a distance ``spread`` from its centre (inputs are not
scaled, as in ``newrb``: ``spread`` is in the units of the inputs). The centres are the
distinct training inputs taken in a random order (a repeated input, e.g. the many samples of
a static phase, would only repeat a column); with the first k of them the output layer
[b2, w] is the least-squares solution of [1, Phi_k] [b2; w] = y, and k is the smallest
count whose training MSE is below ``goal`` (``newrb``'s stopping rule), else
``max_neurons``. MATLAB ``newrb``'s orthogonal-least-squares choice of centres is
:class:`gyrobench.analysis.compensation.rbf.RBFNetwork`.

References
----------
S. Haykin, *Neural Networks: A Comprehensive Foundation*, 2nd ed., Prentice Hall, 1999,
Sec. 5.13 "fixed centers selected at random".
MathWorks, ``newrb`` documentation (radbas basis, b = 0.8326 / spread, GOAL and MN).
"""

from __future__ import annotations

import math
from numbers import Integral, Real

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import qr, solve_triangular
from sklearn.base import BaseEstimator, RegressorMixin
from sklearn.utils.validation import check_is_fitted, validate_data

__all__ = ["RandomCentreRBF", "RADBAS_B"]

#: sqrt(-ln 0.5) = 0.8326: radbas(RADBAS_B) = 0.5, so b = RADBAS_B / spread (MATLAB newrb)
RADBAS_B = math.sqrt(-math.log(0.5))


def _basis(X: NDArray[np.float64], centres: NDArray[np.float64], b: float) -> NDArray[np.float64]:
    """radbas(b ||x - c||) = exp(-sum_j (b (x_j - c_j))^2) for every row of X and every centre."""
    z = b * (X[:, None, :] - centres[None, :, :])
    return np.exp(-np.sum(z**2, axis=2))


class RandomCentreRBF(RegressorMixin, BaseEstimator):
    """RBF network with randomly fixed centres, grown until the training MSE is below ``goal``.

    Parameters
    ----------
    spread : float, default 1.0
        Distance [input units] at which a basis function has fallen to 0.5 (``newrb``
        SPREAD). Must be finite and > 0.
    goal : float, default 0.0
        Mean-squared-error goal [target units^2]: the network stops growing at the first
        size whose training MSE is below it. Must be finite and >= 0.
    max_neurons : int or None, default None
        Largest number of centres. The network never has more than m - 1 (m distinct
        training inputs: with the constant column, m - 1 centres already interpolate them;
        0 centres when every input is the same); None means that many. Must be None or an
        integer >= 1.
    random_state : None, int or numpy.random.Generator, default None
        The random order of the centres: a Generator is used as given (its stream
        advances), an int seeds ``numpy.random.default_rng``, None draws fresh entropy.

    Attributes
    ----------
    centers_ : ndarray, shape (n_neurons, n_features)
        The centres: distinct training inputs (rows of ``numpy.unique(X, axis=0)``) in the
        drawn order.
    b_ : float
        Basis width parameter RADBAS_B / spread [1 / input units].
    weights_ : ndarray, shape (n_neurons,)
        Output-layer weights [target units].
    intercept_ : float
        Output-layer bias b2 [target units].
    mse_ : float
        Training MSE at the chosen size [target units^2].
    n_neurons_ : int
        Number of centres kept.
    n_features_in_ : int
        Number of input columns.

    Notes
    -----
    One QR of the n x (k_max + 1) design [1, Phi_{k_max}] (the columns in the drawn order)
    gives every size's residual: ||y||^2 - sum_{i <= k} (Q' y)_i^2, so the smallest k below
    the goal is found without refitting; the output layer is then R_k^{-1} (Q' y)_k.
    Cost: memory 8 n k_max bytes for the design.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.linspace(0.0, 10.0, 101)[:, None]
    >>> net = RandomCentreRBF(spread=1.0, goal=1e-4, random_state=0).fit(x, np.sin(x[:, 0]))
    >>> bool(net.mse_ < 1e-4)
    True
    """

    def __init__(self, spread=1.0, goal=0.0, max_neurons=None, random_state=None):
        self.spread = spread
        self.goal = goal
        self.max_neurons = max_neurons
        self.random_state = random_state

    def _check_params(self) -> None:
        s = self.spread
        if isinstance(s, bool) or not isinstance(s, Real) or not (math.isfinite(float(s)) and float(s) > 0):
            raise ValueError(f"RandomCentreRBF.spread must be a finite number > 0 (input units); got {s!r}")
        g = self.goal
        if isinstance(g, bool) or not isinstance(g, Real) or not (math.isfinite(float(g)) and float(g) >= 0):
            raise ValueError(f"RandomCentreRBF.goal must be a finite number >= 0 (target units^2); got {g!r}")
        m = self.max_neurons
        if m is not None and (isinstance(m, bool) or not isinstance(m, Integral) or m < 1):
            raise ValueError(f"RandomCentreRBF.max_neurons must be None or an integer >= 1; got {m!r}")
        r = self.random_state
        is_int = isinstance(r, Integral) and not isinstance(r, bool)
        if not (r is None or is_int or isinstance(r, np.random.Generator)):
            raise TypeError(
                f"RandomCentreRBF.random_state must be None, an int or a numpy.random.Generator; got {r!r}"
            )

    def _rng(self) -> np.random.Generator:
        r = self.random_state
        return r if isinstance(r, np.random.Generator) else np.random.default_rng(r)

    def fit(self, X: ArrayLike, y: ArrayLike) -> RandomCentreRBF:
        """Draw the centres' order and grow the network on (X, y) until the goal is met.

        Parameters
        ----------
        X : array_like, shape (n_samples, n_features)
            Inputs (n_samples >= 2).
        y : array_like, shape (n_samples,)
            Targets.

        Returns
        -------
        self : RandomCentreRBF

        Raises
        ------
        ValueError
            On a bad parameter, or fewer than 2 samples.
        """
        self._check_params()
        X, y = validate_data(self, X, y, y_numeric=True)
        X = np.asarray(X, dtype=float)
        y = np.asarray(y, dtype=float).reshape(-1)
        n = X.shape[0]
        if n < 2:
            raise ValueError(f"RandomCentreRBF needs at least 2 samples; got n_samples = {n}")
        distinct = np.unique(X, axis=0)  # a repeated input would give a repeated (dependent) column
        k_cap = len(distinct) - 1  # with the constant column, m - 1 centres interpolate m distinct inputs
        k_max = k_cap if self.max_neurons is None else min(int(self.max_neurons), k_cap)
        b = RADBAS_B / float(self.spread)
        centres = distinct[self._rng().permutation(len(distinct))[:k_max]]
        design = np.column_stack([np.ones(n), _basis(X, centres, b)])
        q, r = qr(design, mode="economic")
        qy = q.T @ y
        resid = np.maximum(float(y @ y) - np.cumsum(qy**2), 0.0)  # after 1 + k columns, k = 0..k_max
        mse = resid / n
        below_goal = np.flatnonzero(mse[1:] < self.goal)
        k = int(below_goal[0]) + 1 if below_goal.size else k_max
        if np.all(np.diag(r)[: k + 1] != 0.0):
            sol = solve_triangular(r[: k + 1, : k + 1], qy[: k + 1])
        else:  # exactly dependent columns (e.g. the constant in the span): minimum-norm least squares
            sol = np.linalg.lstsq(design[:, : k + 1], y, rcond=None)[0]
        self.centers_ = centres[:k].copy()
        self.b_ = b
        self.weights_ = np.asarray(sol[1:], dtype=float)
        self.intercept_ = float(sol[0])
        self.mse_ = float(mse[k])
        self.n_neurons_ = k
        return self

    def predict(self, X: ArrayLike) -> NDArray[np.float64]:
        """Network output b2 + Phi(X) w for the rows of X.

        Returns
        -------
        ndarray, shape (n_samples,)
        """
        check_is_fitted(self, "centers_")
        X = validate_data(self, X, reset=False)
        return self.intercept_ + _basis(np.asarray(X, dtype=float), self.centers_, self.b_) @ self.weights_
