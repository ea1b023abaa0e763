"""Choosing a newrb RBF network's spread and neuron count by leave-one-segment-out CV.

A temperature-drift record (a chamber program) falls into contiguous thermal regimes
(settle, heat + hold, cool + hold). :func:`select_rbf` holds out one regime at a time,
fits :class:`gyrobench.analysis.compensation.rbf.RBFNetwork` on the others and scores the
held-out regime; of the grid cells whose mean held-out MSE lies within a relative band of
the best, it takes the one with the fewest neurons (ties: the largest spread). It needs
only the training record, so it applies to a real test's log as it is.

References: the "one-standard-error"-style parsimony rule (Breiman, Friedman, Olshen and
Stone, *Classification and Regression Trees*, 1984, sec. 3.4.3; Hastie, Tibshirani and
Friedman, *The Elements of Statistical Learning*, 2nd ed., 2009, sec. 7.10).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.analysis.compensation.rbf import RADBAS_B, RBFNetwork

__all__ = ["RBFSelection", "prefix_predictions", "select_rbf"]


@dataclass(frozen=True, slots=True)
class RBFSelection:
    """Result of :func:`select_rbf`: the chosen newrb settings and the CV table they came from.

    Attributes
    ----------
    spread : float
        Chosen spread [normalized input units].
    max_neurons : int
        Chosen neuron count.
    cv_mse : dict
        ``(spread, max_neurons) -> mean held-out-segment MSE`` [target unit squared], in
        grid order (spreads as given, neuron counts rising).
    best : tuple of (float, int)
        The grid cell with the lowest CV MSE.
    """

    spread: float
    max_neurons: int
    cv_mse: dict[tuple[float, int], float]
    best: tuple[float, int]

    @property
    def chosen(self) -> tuple[float, int]:
        """``(spread, max_neurons)`` of the choice."""
        return (self.spread, self.max_neurons)

    def as_dict(self) -> dict[str, Any]:
        """JSON-able form: the choice, the best cell and every grid cell's CV MSE."""
        return {
            "spread": self.spread,
            "max_neurons": self.max_neurons,
            "cv_mse_chosen": self.cv_mse[self.chosen],
            "best": {"spread": self.best[0], "max_neurons": self.best[1]},
            "cv_mse_best": self.cv_mse[self.best],
            "grid": [{"spread": k[0], "max_neurons": k[1], "cv_mse": v} for k, v in self.cv_mse.items()],
        }


def _cdist(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """Euclidean distances between the rows of ``a`` (n, k) and of ``b`` (m, k): (n, m)."""
    return np.sqrt(np.maximum(np.sum((a[:, None, :] - b[None, :, :]) ** 2, axis=2), 0.0))


def prefix_predictions(
    net: RBFNetwork, X_fit: ArrayLike, y_fit: ArrayLike, X_new: ArrayLike, counts: Iterable[int]
) -> dict[int, NDArray[np.float64]]:
    """Predictions on ``X_new`` of the newrb networks made of the first k neurons of ``net``.

    newrb adds one neuron per iteration and the choice of the next neuron does not
    depend on ``max_neurons``, so the k-neuron network has the first k centres of a
    longer fit; its output layer [b2, LW] is the least-squares solution on those centres,
    ``min || [1, radbas(||z - c_j|| b)] w - y_fit ||``, ``b = sqrt(-ln 0.5) / spread``
    (MATLAB newrb's radbas bias). ``net`` must be fitted (one output).
    """
    y_arr = np.asarray(y_fit, dtype=float)
    Z = (np.asarray(X_fit, float) - net.x_offset_) * net.x_gain_
    Zn = (np.asarray(X_new, float) - net.x_offset_) * net.x_gain_
    b = RADBAS_B / float(net.spread)
    out = {}
    for k in counts:
        c = net.centers_[: min(int(k), net.n_neurons_)]
        G = np.column_stack([np.ones(len(Z)), np.exp(-((_cdist(Z, c) * b) ** 2))])
        sol, *_ = np.linalg.lstsq(G, y_arr, rcond=None)
        out[int(k)] = sol[0] + np.exp(-((_cdist(Zn, c) * b) ** 2)) @ sol[1:]
    return out


def select_rbf(
    X: ArrayLike,
    y: ArrayLike,
    segments: ArrayLike,
    *,
    spreads: Iterable[float],
    neurons: Iterable[int],
    goal: float = 0.0,
    tolerance: float = 0.10,
) -> RBFSelection:
    """Choose newrb spread and neuron count by leave-one-segment-out CV on the training run only.

    Rule: for every (spread, max_neurons) of the grid, fit on all segments but one and
    predict the held-out segment. The CV MSE is the mean of the held-out segment MSEs,
    so each thermal regime counts equally. Of the cells whose CV MSE is within
    ``tolerance`` (10 %) of the best, take the one with the fewest neurons. Ties go
    to the largest spread, i.e. the smoothest surface.

    Why this rule: the segments of a chamber record (settle, heat + hold, cool + hold)
    are contiguous blocks. Random K-fold on 100-s blocks of a slow thermal record would
    leak neighbouring, strongly correlated samples into the test fold and favour
    interpolating networks. Holding out a whole segment asks what a compensation needs:
    does the model carry over to a thermal history it has not seen? The band is a
    "one-standard-error"-style parsimony rule (module docstring). With only three folds
    the CV minimum is noisy, so among nearly equal models the simplest is preferred. One
    newrb fit per (spread, fold) with the largest neuron count gives every smaller count
    (:func:`prefix_predictions`).

    Parameters
    ----------
    X : array_like, shape (n, k)
        Features of the training run.
    y : array_like, shape (n,)
        Target (e.g. drift [deg/h]).
    segments : array_like of int, shape (n,)
        Fold label of every sample.
    spreads : iterable of float
        Grid of spread [normalized input units], each > 0.
    neurons : iterable of int
        Grid of max_neurons, each >= 1.
    goal : float
        newrb goal [target unit squared].
    tolerance : float
        Relative CV-MSE band [-], >= 0.

    Returns
    -------
    RBFSelection

    Raises
    ------
    ValueError
        If ``segments`` has fewer than two distinct labels, its length differs from
        ``y``'s, a grid is empty, or ``tolerance`` is negative.
    """
    X = np.asarray(X, dtype=float)
    y = np.asarray(y, dtype=float)
    segments = np.asarray(segments)
    if segments.shape != y.shape or X.ndim != 2 or len(X) != len(y):
        raise ValueError(
            f"select_rbf: X must have shape (n, k) and y, segments shape (n,); got X {X.shape}, "
            f"y {y.shape}, segments {segments.shape}"
        )
    labels = np.unique(segments)
    if len(labels) < 2:
        raise ValueError(
            "select_rbf: segments must hold at least 2 distinct labels (one cross-validation "
            f"fold each); got labels {labels.tolist()}"
        )
    spreads = tuple(spreads)
    counts = sorted({int(n) for n in neurons})
    if not spreads or not counts:
        raise ValueError(f"select_rbf: spreads and neurons must be non-empty; got {spreads!r}, {counts!r}")
    if not tolerance >= 0:
        raise ValueError(f"select_rbf: tolerance must be >= 0 (relative); got {tolerance!r}")
    errs: dict[tuple[float, int], list[float]] = {}
    for spread in spreads:
        for f in labels:
            held = segments == f
            net = RBFNetwork(spread=spread, goal=goal, max_neurons=counts[-1], normalize="minmax")
            net.fit(X[~held], y[~held])
            pred = prefix_predictions(net, X[~held], y[~held], X[held], counts)
            for mn in counts:
                errs.setdefault((float(spread), mn), []).append(float(np.mean((pred[mn] - y[held]) ** 2)))
    cv = {k: float(np.mean(v)) for k, v in errs.items()}
    best = min(cv, key=cv.__getitem__)
    band = [k for k, v in cv.items() if v <= (1.0 + tolerance) * cv[best]]
    chosen = min(band, key=lambda k: (k[1], -k[0]))
    return RBFSelection(spread=chosen[0], max_neurons=chosen[1], cv_mse=cv, best=best)
