"""The reference compensator printed beside the user's in every scenario: the uncompensated output.

:data:`UNCOMPENSATED` (``"gyrobench.scenarios.bench.references:Uncompensated"``) scores every
held-out run's raw output against the truth: the bench recognises it and skips the fit and
the task's ``compensate`` step, so it is the uncompensated reference for any target
(``"error"`` or ``"rate"``). A paper's method, the other reference, lives in the paper's package
and is named by its ``BENCH_SCORES`` (:class:`gyrobench.scenarios.bench.primary.ScenarioScores`).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "UNCOMPENSATED",
    "Uncompensated",
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
