"""Paper 004 on ``gyrobench bench``: the scores a regression is judged on and the paper's method
(least squares, scikit-learn's ``LinearRegression``; the compensation task itself is
:func:`.experiment.compensation_task`)."""

from __future__ import annotations

from gyrobench.scenarios.bench.primary import PrimaryScore, ScenarioScores

__all__ = ["BENCH_SCORES"]

#: the primary scores, the score units and the paper's method
BENCH_SCORES = ScenarioScores(
    primary=(
        PrimaryScore(
            name="mean/bias_stability_deg_h",
            unit="deg/h",
            direction=-1,
            meaning="bias stability (100-s blocks) of the compensated held-out run",
        ),
    ),
    units={"bias_stability_deg_h": "deg/h", "before_deg_h": "deg/h", "improvement_pct": "%"},
    paper="sklearn.linear_model:LinearRegression",
    paper_label="least squares on x1..x11 (paper)",
)
