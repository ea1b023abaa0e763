"""The example paper on ``gyrobench bench``: its compensation task and the scores it is judged on.

The task: learn the gyro's bias from one static record and remove it from another. The one
feature is a constant (the bias does not depend on anything); the paper's method is least squares
(scikit-learn's ``LinearRegression``), whose intercept is the record mean. The held-out record's
truth is a zero rate, so its compensated RMS is the white noise's per-sample standard deviation
60 N sqrt(fs) deg/h when the bias is removed (module docstring of the package).
"""

from __future__ import annotations

import numpy as np

from gyrobench.scenarios.base import CompensationTask, HeldOutRun
from gyrobench.scenarios.bench.primary import PrimaryScore, ScenarioScores

from . import NAME
from .config import Config
from .experiment import _rate_deg_h

__all__ = ["BENCH_SCORES", "compensation_task"]

#: the primary score, the score units and the paper's method
BENCH_SCORES = ScenarioScores(
    primary=(
        PrimaryScore(name="mean/rms", unit="deg/h", direction=-1, meaning="RMS of the compensated held-out record"),
    ),
    units={"rms": "deg/h", "mse": "deg^2/h^2"},
    paper="sklearn.linear_model:LinearRegression",
    paper_label="least squares (the record mean)",
)


def compensation_task(config: Config, seed: int) -> CompensationTask:
    """A training record (seed ``2 seed``) and a held-out one (seed ``2 seed + 1``) of the unit [deg/h].

    Parameters
    ----------
    config : Config
        The paper's configuration.
    seed : int
        The unit's seed (>= 0).

    Returns
    -------
    CompensationTask
        One constant feature; the target is the error (output - a zero true rate) [deg/h].
    """
    train, held = _rate_deg_h(config, 2 * seed), _rate_deg_h(config, 2 * seed + 1)
    ones = np.ones((config.n_samples, 1))
    run = HeldOutRun(label="static", X=ones, output=held, truth=np.zeros_like(held))
    return CompensationTask(
        scenario=NAME, feature_names=("one",), X_train=ones, y_train=train, heldout=(run,), unit="deg/h",
    )
