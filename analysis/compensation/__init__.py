"""The papers' compensation models as scikit-learn estimators.

Every estimator follows scikit-learn's contract (``__init__`` stores parameters, ``fit``
validates and returns ``self``, learned state ends in ``_``), so they plug into pipelines and
grid searches, and any scikit-learn regressor plugs into the bench in their place.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from gyrobench.base.lazy import attach

#: public name -> the submodule that defines it (imported on first access, so importing
#: this package costs nothing until a name is used)
_LAZY: dict[str, str] = {
    "PolynomialRegressor": "gyrobench.analysis.compensation.polynomial",
    "TwoStagePolynomial": "gyrobench.analysis.compensation.polynomial",
    "PiecewisePolynomial": "gyrobench.analysis.compensation.polynomial",
    "RBFNetwork": "gyrobench.analysis.compensation.rbf",
    "StreamingCompensator": "gyrobench.analysis.compensation.rbf",
    "batch_compensate": "gyrobench.analysis.compensation.rbf",
    "RandomCentreRBF": "gyrobench.analysis.compensation.random_rbf",
    "RBFSelection": "gyrobench.analysis.compensation.rbf_selection",
    "select_rbf": "gyrobench.analysis.compensation.rbf_selection",
    "BayesianRegularizedMLP": "gyrobench.analysis.compensation.bayes_mlp",
    "StepwiseRegression": "gyrobench.analysis.compensation.stepwise",
}

__all__ = [
    "PolynomialRegressor",
    "TwoStagePolynomial",
    "PiecewisePolynomial",
    "RBFNetwork",
    "StreamingCompensator",
    "batch_compensate",
    "RandomCentreRBF",
    "RBFSelection",
    "select_rbf",
    "BayesianRegularizedMLP",
    "StepwiseRegression",
]

if TYPE_CHECKING:  # pragma: no cover - for type checkers and IDEs only
    from gyrobench.analysis.compensation.bayes_mlp import BayesianRegularizedMLP as BayesianRegularizedMLP
    from gyrobench.analysis.compensation.polynomial import PiecewisePolynomial as PiecewisePolynomial
    from gyrobench.analysis.compensation.polynomial import PolynomialRegressor as PolynomialRegressor
    from gyrobench.analysis.compensation.polynomial import TwoStagePolynomial as TwoStagePolynomial
    from gyrobench.analysis.compensation.random_rbf import RandomCentreRBF as RandomCentreRBF
    from gyrobench.analysis.compensation.rbf import RBFNetwork as RBFNetwork
    from gyrobench.analysis.compensation.rbf import StreamingCompensator as StreamingCompensator
    from gyrobench.analysis.compensation.rbf import batch_compensate as batch_compensate
    from gyrobench.analysis.compensation.rbf_selection import RBFSelection as RBFSelection
    from gyrobench.analysis.compensation.rbf_selection import select_rbf as select_rbf
    from gyrobench.analysis.compensation.stepwise import StepwiseRegression as StepwiseRegression


__getattr__, __dir__ = attach(__name__, _LAZY)
