"""Paper 003 on ``gyrobench bench``: the scores a regression is judged on and the paper's method
as a bench compensator (the compensation task itself is :func:`.runs.compensation_task`)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from gyrobench.scenarios.bench.primary import PrimaryScore, ScenarioScores

from .config import Config

__all__ = ["BENCH_SCORES", "IfogSegmentRBF"]

#: the primary scores, the score units and the paper's method
BENCH_SCORES = ScenarioScores(
    primary=(
        PrimaryScore(
            name="mean/rms",
            unit="deg/h",
            direction=-1,
            meaning="RMS error of the compensated output, mean over the held-out runs",
        ),
    ),
    units={"mse": "(deg/h)^2", "rms": "deg/h"},
    paper=f"{__name__}:IfogSegmentRBF",
    paper_label="RBF, leave-one-segment-out (paper)",
)


class IfogSegmentRBF:
    """The ifog_thermal paper's method as a bench compensator: a newrb RBF network on (T, dT/dt, T x dT/dt).

    The ifog_thermal paper's method: a newrb RBF network on the temperature features
    (T [degC], dT/dt [degC/s], T x dT/dt [degC^2/s]) predicting the drift [deg/h], its spread and
    neuron count chosen by leave-one-segment-out CV over the identification run's segments.

    ``fit(X, y, groups)`` runs :func:`gyrobench.analysis.compensation.rbf_selection.select_rbf`
    on the scenario's default grids (``Config().rbf_spread_grid`` x ``rbf_neuron_grid``, goal
    ``rbf_goal_deg_h2``, band ``rbf_cv_tolerance``) with ``groups`` as the folds (the task's
    ``groups_train``: settle, heat + hold, cool + hold), then refits
    :class:`~gyrobench.analysis.compensation.rbf.RBFNetwork` (``normalize="minmax"``) on all
    rows with the chosen settings, as the paper's reproduction does on its training set. It
    fits the bench's target (output - true rate), not the paper's Q (output - its mean): the
    bench scores against the truth. No parameters: the settings are the scenario's.
    """

    def get_params(self, deep: bool = True) -> dict[str, Any]:
        return {}

    def set_params(self, **params: Any) -> IfogSegmentRBF:
        if params:
            raise ValueError(f"IfogSegmentRBF takes no parameters; got {sorted(params)}")
        return self

    def fit(
        self, X: NDArray[np.float64], y: NDArray[np.float64], groups: NDArray[np.int_] | None = None
    ) -> IfogSegmentRBF:
        from gyrobench.analysis.compensation.rbf import RBFNetwork
        from gyrobench.analysis.compensation.rbf_selection import select_rbf

        if groups is None:
            raise ValueError("IfogSegmentRBF.fit needs groups (the training rows' segments) for its CV; got None")
        c = Config()
        sel = select_rbf(
            X, y, groups, spreads=c.rbf_spread_grid, neurons=c.rbf_neuron_grid, goal=c.rbf_goal_deg_h2,
            tolerance=c.rbf_cv_tolerance,
        )
        self.selection_ = sel
        self.network_ = RBFNetwork(
            spread=sel.spread, goal=c.rbf_goal_deg_h2, max_neurons=sel.max_neurons, normalize="minmax"
        ).fit(X, y)
        return self

    def predict(self, X: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.asarray(self.network_.predict(X), dtype=float)
