"""Paper 001 on ``gyrobench bench``: the scores a regression is judged on and the paper's method
as a bench compensator (the compensation task itself is :func:`.experiment.compensation_task`)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from gyrobench.scenarios.bench.primary import PrimaryScore, ScenarioScores

from .config import Config

__all__ = ["BENCH_SCORES", "mems_piecewise"]

#: the primary scores, the score units and the paper's method
BENCH_SCORES = ScenarioScores(
    primary=(
        PrimaryScore(
            name="mean/nonlinearity_pct",
            unit="%",
            direction=-1,
            meaning="scale-factor nonlinearity K_n of the compensated rate table",
        ),
        PrimaryScore(
            name="mean/rms_dps",
            unit="deg/s",
            direction=-1,
            meaning="RMS error of the compensated rate table",
        ),
    ),
    units={"nonlinearity_pct": "%", "rms_dps": "deg/s"},
    paper=f"{__name__}:mems_piecewise",
    paper_label="piecewise polynomial (paper)",
)


def mems_piecewise(X: NDArray[np.float64], y: NDArray[np.float64]) -> Any:
    """The paper's method as a bench compensator: the heuristic piecewise polynomial regression.

    The mems_scale_factor paper's method: the heuristic piecewise polynomial regression with
    the scenario's default settings (``Config().orders``, ``join``, ``join_width``, ``piecewise_alpha``),
    fitted to map the mean outputs [deg/s] to the table rates [deg/s], as the paper's
    reproduction fits it on the pooled fitting runs.

    Parameters
    ----------
    X : ndarray
        Mean outputs [deg/s], one column.
    y : ndarray
        Table rates [deg/s].

    Returns
    -------
    PiecewisePolynomial
        The fitted regression.
    """
    from gyrobench.analysis.compensation.polynomial import PiecewisePolynomial

    c = Config()
    return PiecewisePolynomial(
        orders=tuple(c.orders), join=c.join, join_width=c.join_width, alpha=c.piecewise_alpha
    ).fit(X, y)
