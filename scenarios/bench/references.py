"""Reference compensators printed beside the user's: the uncompensated output and the papers'
methods as bench compensators.

:data:`UNCOMPENSATED` (``"gyrobench.scenarios.bench.references:Uncompensated"``) scores every
held-out run's raw output against the truth: the bench recognises it and skips the fit and
the task's ``compensate`` step, so it is the uncompensated reference for any target
(``"error"`` or ``"rate"``). A paper's method is named per scenario in
:data:`gyrobench.scenarios.bench.primary.SCENARIO_SCORES`.
"""

from __future__ import annotations

from functools import partial
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "UNCOMPENSATED",
    "FogVibrationBias",
    "IfogSegmentRBF",
    "Uncompensated",
    "fog_vibration_rbf",
    "mems_piecewise",
]

#: the uncompensated reference as a ``"module:attr"`` compensator
UNCOMPENSATED = "gyrobench.scenarios.bench.references:Uncompensated"


class Uncompensated:
    """No compensation: the bench scores the held-out run's output as it is.

    ``fit`` learns nothing. The bench never calls ``predict``: for this class it scores
    ``run.output`` directly (:func:`gyrobench.scenarios.bench.scoring.score_or_failure`),
    because "no compensation" is a zero error prediction for an ``"error"`` target but the
    output itself for a ``"rate"`` target, which a predictor that sees only ``X`` cannot know.
    """

    def get_params(self, deep: bool = True) -> dict[str, Any]:
        return {}

    def set_params(self, **params: Any) -> Uncompensated:
        if params:
            raise ValueError(f"Uncompensated takes no parameters; got {sorted(params)}")
        return self

    def fit(self, X: NDArray[np.float64], y: NDArray[np.float64]) -> Uncompensated:
        return self

    def predict(self, X: NDArray[np.float64]) -> NDArray[np.float64]:
        raise TypeError("Uncompensated does not predict: the bench scores the raw output for it")


def mems_piecewise(X: NDArray[np.float64], y: NDArray[np.float64]):
    """The mems_scale_factor paper's method: the heuristic piecewise polynomial regression with
    the scenario's default settings (``Config().orders``, ``join``, ``join_width``, ``piecewise_alpha``),
    fitted to map the mean outputs [deg/s] to the table rates [deg/s], as the paper's
    reproduction fits it on the pooled fitting runs."""
    from gyrobench.analysis.compensation.polynomial import PiecewisePolynomial
    from gyrobench.scenarios.bench.scoring import resolve_scenario

    c = resolve_scenario("mems_scale_factor").Config()  # through the registry, not the path
    return PiecewisePolynomial(
        orders=tuple(c.orders), join=c.join, join_width=c.join_width, alpha=c.piecewise_alpha
    ).fit(X, y)


class IfogSegmentRBF:
    """The ifog_thermal paper's method: a newrb RBF network on the temperature features
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
        from gyrobench.scenarios.bench.scoring import resolve_scenario

        if groups is None:
            raise ValueError("IfogSegmentRBF.fit needs groups (the training rows' segments) for its CV; got None")
        c = resolve_scenario("ifog_thermal").Config()  # through the registry, not the path
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


class FogVibrationBias:
    """A fitted paper-000 bias model as a bench predictor: ``predict(X)`` with X = [frequency Hz,
    acceleration g] is the model's bias [deg/h] at the frequency clipped to the training range
    [``lo``, ``hi``] Hz while the shaker runs (acceleration > 0), 0 when it is off, as the paper
    compensates (:func:`gyrobench.scenarios.papers.p000_fog_vibration.pipeline.predict_on`)."""

    def __init__(self, model: Any, lo: float, hi: float) -> None:
        self.model, self.lo, self.hi = model, lo, hi

    def predict(self, X: NDArray[np.float64]) -> NDArray[np.float64]:
        X = np.asarray(X, dtype=float)
        out = np.zeros(len(X))
        on = X[:, 1] > 0
        if on.any():
            out[on] = np.asarray(self.model(np.clip(X[on, 0], self.lo, self.hi)), dtype=float).reshape(-1)
        return out


def fog_vibration_rbf(
    X: NDArray[np.float64], y: NDArray[np.float64], random_state: int | None = None
) -> FogVibrationBias:
    """The fog_vibration paper's method: an RBF network with randomly fixed centres of the bias
    [deg/h] against the drive frequency [Hz], fitted to the means of the target in
    ``Config().bin_width_hz`` frequency bins over the rows where the shaker runs (acceleration > 0),
    spread ``rbf_spread_hz``, goal ``rbf_goal_deg_h2``, ``rbf_max_neurons``
    (:class:`gyrobench.analysis.compensation.random_rbf.RandomCentreRBF`; the paper's Fig. 6
    model, :func:`~gyrobench.scenarios.papers.p000_fog_vibration.pipeline.fit_bias_models`).
    Predicts 0 while the shaker is off (:class:`FogVibrationBias`)."""
    from gyrobench.analysis.compensation.random_rbf import RandomCentreRBF
    from gyrobench.analysis.sweep import bin_means
    from gyrobench.scenarios.bench.scoring import resolve_scenario

    c = resolve_scenario("fog_vibration").Config()  # through the registry, not the path
    X = np.asarray(X, dtype=float)
    on = X[:, 1] > 0
    if not on.any():
        raise ValueError("fog_vibration_rbf needs training rows with the shaker on (acceleration > 0); got none")
    lo, hi = min(c.sweep_start_hz, c.sweep_end_hz), max(c.sweep_start_hz, c.sweep_end_hz)
    fb, yb = bin_means(X[on, 0], np.asarray(y, dtype=float)[on], lo=lo, hi=hi, width=c.bin_width_hz)
    net = RandomCentreRBF(
        spread=c.rbf_spread_hz, goal=c.rbf_goal_deg_h2, max_neurons=c.rbf_max_neurons, random_state=random_state
    ).fit(fb[:, None], yb)
    column = partial(_predict_column, net)
    return FogVibrationBias(column, float(fb[0]), float(fb[-1]))


def _predict_column(model: Any, u: NDArray[np.float64]) -> NDArray[np.float64]:
    """A fitted regressor of one input column on the 1-D input ``u``."""
    return np.asarray(model.predict(np.asarray(u, dtype=float).reshape(-1, 1)), dtype=float)
