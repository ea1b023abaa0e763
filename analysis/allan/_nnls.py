"""Weighted non-negative least squares of the noise fit (Lawson-Hanson, without scipy.optimize)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def _wnnls(
    x: NDArray[np.float64],
    a: NDArray[np.float64],
    var: NDArray[np.float64],
    passive: NDArray[np.bool_] | None = None,
) -> NDArray[np.float64]:
    """argmin_{C >= 0} sum_i (x_i . C - a_i)^2 / var_i, on column-scaled X for conditioning.

    ``passive``: the terms expected to be > 0 (the last iteration's), tried first
    (:func:`_nnls_enumerate`).
    """
    sw = 1.0 / np.sqrt(var)
    xw = x * sw[:, None]
    scale = np.linalg.norm(xw, axis=0)
    scale[scale == 0] = 1.0
    if x.shape[1] <= _NNLS_ENUM:
        cs = _nnls_enumerate(xw / scale, a * sw, passive)
    else:  # pragma: no cover - the fit has at most five terms
        from scipy import optimize

        cs, _ = optimize.nnls(xw / scale, a * sw, maxiter=50 * x.shape[1])
    return cs / scale


#: up to this many columns NNLS is solved here (Lawson-Hanson), without scipy.optimize
_NNLS_ENUM = 6


def _nnls_enumerate(
    a: NDArray[np.float64], b: NDArray[np.float64], passive0: NDArray[np.bool_] | None = None
) -> NDArray[np.float64]:
    """argmin_{c >= 0} ||a c - b|| for a few columns: the Lawson-Hanson active-set algorithm.

    C. L. Lawson and R. J. Hanson, "Solving Least Squares Problems" (1974), ch. 23 (as in
    MATLAB's lsqnonneg and scipy.optimize.nnls): move the column of largest gradient
    a'(b - a c) into the passive set, solve least squares on it, and step back to the
    feasible region while a coefficient goes negative. A gradient within the tolerance
    10 eps ||a||_1 max(shape) counts as zero, so a term that does not help stays exactly 0.
    Same minimiser as scipy.optimize.nnls (to rounding; a test compares them) without
    importing scipy.optimize (~0.3-0.5 s, the largest single cost of a short CLI run).

    ``passive0`` (a guess of the positive set, e.g. the previous reweighting iteration's): the
    least-squares solution on it is returned when it satisfies the optimality (KKT) conditions
    of the algorithm's own exit, all its coefficients > 0 and no gradient of the others above
    the tolerance, which is then the NNLS minimiser; otherwise the algorithm runs from the start.
    One lstsq instead of ~4 per reweighting iteration of the fit.
    """
    rows, k = a.shape
    tol = 10.0 * np.finfo(float).eps * float(np.abs(a).sum(axis=0).max()) * max(rows, k)
    if passive0 is not None and passive0.any():
        z = np.zeros(k)
        z[passive0] = np.linalg.lstsq(a[:, passive0], b, rcond=None)[0]
        if np.all(z[passive0] > tol):
            w = a.T @ (b - a @ z)
            if not np.any(w[~passive0] > tol):
                return z
    passive = np.zeros(k, dtype=bool)
    x = np.zeros(k)
    w = a.T @ (b - a @ x)
    for _ in range(3 * k + 3):
        if passive.all() or not np.any(w[~passive] > tol):
            break
        j = int(np.argmax(np.where(passive, -np.inf, w)))
        passive[j] = True
        while True:
            z = np.zeros(k)
            z[passive] = np.linalg.lstsq(a[:, passive], b, rcond=None)[0]
            neg = passive & (z <= 0.0)
            if not neg.any():
                break
            step = np.min(x[neg] / (x[neg] - z[neg]))
            x = x + step * (z - x)
            passive &= x > tol
            x[~passive] = 0.0
        x = z
        w = a.T @ (b - a @ x)
    return x
