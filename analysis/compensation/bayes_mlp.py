"""Bayesian-regularized MLP trained as MATLAB ``trainbr`` (Levenberg-Marquardt + MacKay evidence).

Network: inputs scaled to [-1, 1] (``mapminmax``), one hidden layer of tanh
units, one linear output, target scaled to [-1, 1]. Weights w (N_p of them).

Objective (MacKay 1992; Foresee & Hagan 1997; docs/physics.md 7.3)::

    F(w) = beta E_D + alpha E_W,   E_D = sum_i e_i^2,  e = t - f(w),   E_W = sum_j w_j^2

Each epoch, with J = d f / d w (n x N_p, Gauss-Newton):

    repeat:  dw = (beta J'J + (alpha + mu) I)^-1 (beta J'e - alpha w)
             if F(w + dw) < F(w): accept, mu *= mu_dec; else mu *= mu_inc  (stop if mu > mu_max)
    gamma = N_p - alpha tr[(beta J'J + alpha I)^-1]        (effective number of parameters)
    alpha = gamma / (2 E_W),   beta = (n - gamma) / (2 E_D)

(the factor 2 of the gradient and Hessian cancels in dw; gamma is MacKay's
N_p - 2 alpha tr[A^-1] with A = 2 beta J'J + 2 alpha I). Start: gamma = N_p,
beta = (n - gamma)/(2 E_D) (1 if not positive), alpha = gamma/(2 E_W).
Stops after ``epochs``, when mu > mu_max, or when |gradient| < min_grad.
Nguyen-Widrow initialisation of the hidden layer as MATLAB ``initnw``:
w_h = 0.7 H^(1/p) r_h/|r_h| (r_h uniform in [-1, 1]^p),
b = 0.7 H^(1/p) linspace(-1, 1, H) sign(w_h1); output weights uniform in
[-0.5, 0.5], output bias 0.

References
----------
D. J. C. MacKay, "Bayesian interpolation", Neural Computation 4(3), 1992;
F. D. Foresee, M. T. Hagan, "Gauss-Newton approximation to Bayesian learning",
ICNN 1997; MATLAB trainbr documentation (defaults epochs 1000, mu 0.005,
mu_dec 0.1, mu_inc 10, mu_max 1e10, min_grad 1e-7); R package brnn (R/brnn.R);
D. Nguyen, B. Widrow, IJCNN 1990.
"""

from __future__ import annotations

import math
from numbers import Integral, Real

import numpy as np
from numpy.typing import ArrayLike, NDArray
from sklearn.base import BaseEstimator, RegressorMixin
from sklearn.utils.validation import check_is_fitted, validate_data

__all__ = ["BayesianRegularizedMLP"]

_TINY = 1e-300


class BayesianRegularizedMLP(RegressorMixin, BaseEstimator):
    """One-hidden-layer tanh network trained with Bayesian regularization (MATLAB trainbr).

    Parameters
    ----------
    hidden_units : int
        Number of tanh hidden units, >= 1 (10 in seed paper 001).
    epochs : int
        Maximum Levenberg-Marquardt epochs, >= 1.
    mu, mu_dec, mu_inc, mu_max : float
        Marquardt damping: start, decrease factor (0, 1), increase factor > 1, limit.
    min_grad : float
        Stop when the gradient norm of F falls below this, >= 0.
    random_state : int, numpy.random.Generator or None
        Seed of the Nguyen-Widrow initialisation.

    Attributes
    ----------
    W1_, b1_, W2_, b2_ : ndarray / float
        Weights in scaled units.
    alpha_, beta_, gamma_ : float
        Final hyper-parameters and effective number of parameters.
    n_iter_ : int
        Epochs run.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.linspace(-1.0, 1.0, 41)[:, None]
    >>> net = BayesianRegularizedMLP(hidden_units=5, random_state=0).fit(x, np.tanh(2 * x[:, 0]))
    >>> bool(np.max(np.abs(net.predict(x) - np.tanh(2 * x[:, 0]))) < 1e-3)
    True
    """

    def __init__(
        self,
        hidden_units=10,
        epochs=1000,
        mu=0.005,
        mu_dec=0.1,
        mu_inc=10.0,
        mu_max=1e10,
        min_grad=1e-7,
        random_state=None,
    ):
        self.hidden_units = hidden_units
        self.epochs = epochs
        self.mu = mu
        self.mu_dec = mu_dec
        self.mu_inc = mu_inc
        self.mu_max = mu_max
        self.min_grad = min_grad
        self.random_state = random_state

    def _check_params(self) -> None:
        owner = type(self).__name__
        for name in ("hidden_units", "epochs"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, Integral) or v < 1:
                raise ValueError(f"{owner}.{name} must be an integer >= 1; got {v!r}")

        def real(name, ok, what):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, Real) or not math.isfinite(v) or not ok(v):
                raise ValueError(f"{owner}.{name} must be {what}; got {v!r}")

        real("mu", lambda v: v > 0, "a finite number > 0")
        real("mu_dec", lambda v: 0 < v < 1, "in (0, 1)")
        real("mu_inc", lambda v: v > 1, "a finite number > 1")
        real("mu_max", lambda v: v > self.mu, f"a finite number > mu = {self.mu!r}")
        real("min_grad", lambda v: v >= 0, "a finite number >= 0")

    # ------------------------------------------------------------------ network
    def _unpack(self, w: NDArray[np.float64], p: int):
        h = int(self.hidden_units)
        W1 = w[: h * p].reshape(h, p)
        b1 = w[h * p : h * p + h]
        W2 = w[h * p + h : h * p + 2 * h]
        return W1, b1, W2, w[-1]

    def _forward(self, w, Z):
        W1, b1, W2, b2 = self._unpack(w, Z.shape[1])
        A = np.tanh(Z @ W1.T + b1)
        return A, A @ W2 + b2

    def _jacobian(self, w, Z, A):
        """d f / d w, shape (n, N_p), same order as w: W1 (row-major), b1, W2, b2."""
        _, _, W2, _ = self._unpack(w, Z.shape[1])
        D = (1.0 - A**2) * W2  # d f / d (pre-activation)
        n, p = Z.shape
        JW1 = (D[:, :, None] * Z[:, None, :]).reshape(n, -1)
        return np.hstack([JW1, D, A, np.ones((n, 1))])

    def _init_weights(self, p: int, rng: np.random.Generator) -> NDArray[np.float64]:
        h = int(self.hidden_units)
        mag = 0.7 * h ** (1.0 / p)
        R = rng.uniform(-1.0, 1.0, (h, p))
        norms = np.linalg.norm(R, axis=1, keepdims=True)
        W1 = mag * R / np.where(norms > 0, norms, 1.0)
        b1 = np.zeros(h) if h == 1 else mag * np.linspace(-1.0, 1.0, h) * np.sign(W1[:, 0])
        W2 = rng.uniform(-0.5, 0.5, h)
        return np.concatenate([W1.ravel(), b1, W2, [0.0]])

    # --------------------------------------------------------------------- fit
    def fit(self, X: ArrayLike, y: ArrayLike) -> BayesianRegularizedMLP:
        """Train on (X, y) with Bayesian-regularized Levenberg-Marquardt.

        Parameters
        ----------
        X : array_like, shape (n_samples, n_features)
        y : array_like, shape (n_samples,)

        Returns
        -------
        self
        """
        self._check_params()
        X, y = validate_data(self, X, y, y_numeric=True)
        X = np.asarray(X, dtype=float)
        y = np.asarray(y, dtype=float)
        n, p = X.shape
        lo, hi = X.min(axis=0), X.max(axis=0)
        span = hi - lo
        self.x_center_ = 0.5 * (lo + hi)
        self.x_gain_ = np.where(span > 0, 2.0 / np.where(span > 0, span, 1.0), 0.0)
        ylo, yhi = float(y.min()), float(y.max())
        self.y_center_ = 0.5 * (ylo + yhi)
        self.y_half_ = 0.5 * (yhi - ylo) if yhi > ylo else 1.0
        Z = (X - self.x_center_) * self.x_gain_
        t = (y - self.y_center_) / self.y_half_

        rng = (
            self.random_state
            if isinstance(self.random_state, np.random.Generator)
            else np.random.default_rng(self.random_state)
        )
        w = self._init_weights(p, rng)
        n_p = w.size
        eye = np.eye(n_p)
        A, f = self._forward(w, Z)
        e = t - f
        ed, ew = float(e @ e), float(w @ w)
        gamma = float(n_p)
        beta = (n - gamma) / (2.0 * max(ed, _TINY)) if n > gamma else 1.0
        alpha = gamma / (2.0 * max(ew, _TINY))
        mu = float(self.mu)
        perf = beta * ed + alpha * ew
        n_iter = 0
        for epoch in range(1, int(self.epochs) + 1):
            n_iter = epoch
            J = self._jacobian(w, Z, A)
            H = J.T @ J
            g = beta * (J.T @ e) - alpha * w  # = -grad(F)/2
            if 2.0 * np.linalg.norm(g) < self.min_grad:
                break
            accepted = False
            while mu <= self.mu_max:
                try:
                    dw = np.linalg.solve(beta * H + (alpha + mu) * eye, g)
                except np.linalg.LinAlgError:
                    mu *= self.mu_inc
                    continue
                w2 = w + dw
                A2, f2 = self._forward(w2, Z)
                e2 = t - f2
                ed2, ew2 = float(e2 @ e2), float(w2 @ w2)
                perf2 = beta * ed2 + alpha * ew2
                if np.isfinite(perf2) and perf2 < perf:
                    w, A, e, ed, ew = w2, A2, e2, ed2, ew2
                    mu *= self.mu_dec
                    accepted = True
                    break
                mu *= self.mu_inc
            if not accepted:
                break
            # MacKay evidence update with the Gauss-Newton Hessian at the new weights
            J = self._jacobian(w, Z, A)
            try:
                trace = float(np.trace(np.linalg.inv(beta * (J.T @ J) + alpha * eye)))
            except np.linalg.LinAlgError:
                trace = 0.0
            gamma = float(np.clip(n_p - alpha * trace, 0.0, n_p))
            alpha = gamma / (2.0 * max(ew, _TINY)) if gamma > 0 else alpha
            beta = (n - gamma) / (2.0 * max(ed, _TINY)) if n > gamma else beta
            perf = beta * ed + alpha * ew
        W1, b1, W2, b2 = (np.array(v) for v in self._unpack(w, p))
        self.W1_, self.b1_, self.W2_, self.b2_ = W1, b1, W2, float(b2)
        self.alpha_, self.beta_, self.gamma_ = float(alpha), float(beta), float(gamma)
        self.n_iter_ = n_iter
        return self

    def predict(self, X: ArrayLike) -> NDArray[np.float64]:
        """Network output in target units, shape (n_samples,)."""
        check_is_fitted(self, "W1_")
        X = np.asarray(validate_data(self, X, reset=False), dtype=float)
        Z = (X - self.x_center_) * self.x_gain_
        return self.y_center_ + self.y_half_ * (
            np.tanh(Z @ self.W1_.T + self.b1_) @ self.W2_ + self.b2_
        )
