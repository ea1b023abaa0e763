"""The noise floor: a score no compensator can reach from the features, computed from the truth.

A held-out run's uncompensated error ``e = output - truth`` holds the sensor's white noise
``w`` (angle random walk, read-out noise), which no function of the logged features can
predict: for any prediction ``f(X)`` independent of ``w``, the compensated error's mean square
is at least ``var(w)`` up to a sampling term of order ``1/sqrt(n)``. The bench estimates the
white-noise standard deviation of ``e`` per run and per seed from its second differences
(robustly, a drift of the run's own time scale and steps barely enter it),

    sigma_w = 1.4826 median(|e[k+1] - 2 e[k] + e[k-1]|) / sqrt(6)

(for white noise the second difference has variance ``6 sigma_w**2``; 1.4826 turns the median
absolute value of a normal variable into its standard deviation), and scores, with the
scenario's own scorer, a compensated output whose error is :data:`FLOOR_FRACTION` of that white
noise: ``truth + FLOOR_FRACTION * sigma_w * z`` with ``z`` a fixed standard-normal draw. A
lower-is-better primary score below that is *implausible*: the compensator's residual would be
a quarter of the noise it cannot see, which happens only if the truth reached it. The seed
fails (exit 3).

A run shorter than :data:`MIN_SERIES` samples (a rate table, a few block means) has too few
differences for the estimate; its floor is the score of a residual of :data:`SHORT_FRACTION`
(one millionth) of the uncompensated error: a near-perfect score.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

__all__ = ["FLOOR_FRACTION", "MIN_SERIES", "SHORT_FRACTION", "floor_failure", "noise_floor", "white_noise_std"]

#: the floor's residual, as a fraction of the estimated white noise
FLOOR_FRACTION = 0.25
#: runs with fewer samples get the relative floor :data:`SHORT_FRACTION`
MIN_SERIES = 64
#: the floor's residual of a short run, as a fraction of its uncompensated error
SHORT_FRACTION = 1e-6
#: seed of the fixed standard-normal draw ``z`` (any fixed value; stated so the floor is reproducible)
_Z_SEED = 0x6E6F6973


def white_noise_std(e: np.ndarray) -> float:
    """Robust white-noise standard deviation of ``e`` from its second differences (module doc).

    Parameters
    ----------
    e : ndarray
        A residual.

    Returns
    -------
    float
        The white-noise standard deviation.
    """
    d2 = np.diff(np.asarray(e, dtype=float), 2)
    return 1.4826 * float(np.median(np.abs(d2))) / math.sqrt(6.0)


def _floor_run(task: Any, run: Any) -> dict[str, float]:
    truth = np.asarray(run.truth, dtype=float)
    e = np.asarray(run.output, dtype=float) - truth
    if e.size >= MIN_SERIES:
        z = np.random.default_rng(_Z_SEED).standard_normal(e.size)
        residual = FLOOR_FRACTION * white_noise_std(e) * z
    else:
        residual = SHORT_FRACTION * e
    with np.errstate(all="ignore"):
        return {k: float(v) for k, v in task.scorer(truth + residual, run).items()}


def noise_floor(task: Any) -> dict[str, float]:
    """Every score's floor on ``task``: per run (``"<label>/<score>"``) and ``"mean/<score>"``.

    Parameters
    ----------
    task : CompensationTask
        The seed's task.

    Returns
    -------
    dict of str to float
        Score name -> its floor.
    """
    out: dict[str, float] = {}
    per_key: dict[str, list[float]] = {}
    for run in task.heldout:
        for k, v in _floor_run(task, run).items():
            out[f"{run.label}/{k}"] = v
            per_key.setdefault(k, []).append(v)
    for k, vals in per_key.items():
        out[f"mean/{k}"] = math.fsum(vals) / len(vals)
    return out


def floor_failure(scenario: str, task: Any, scores: Mapping[str, float]) -> str | None:
    """Why a seed's scores are implausible against the noise floor, or None.

    Why the seed's scores are implausible (a lower-is-better primary score below the noise
    floor, :func:`noise_floor`), or None.

    Parameters
    ----------
    scenario : str
        The scenario.
    task : CompensationTask
        The seed's task.
    scores : mapping of str to float
        The seed's scores.

    Returns
    -------
    str or None
        Why the scores are implausible, or None.
    """
    from gyrobench.scenarios.bench.primary import gated_scores

    gates = [g for g in gated_scores(scenario, list(scores)) if g.direction < 0 and g.name in scores]
    if not gates:
        return None
    floor = noise_floor(task)
    for g in gates:
        value, low = scores[g.name], floor.get(g.name, math.nan)
        if math.isfinite(value) and math.isfinite(low) and value < low:
            unit = f" {g.unit}" if g.unit else ""
            return (
                f"implausible score: {g.name} = {value:.4g}{unit} is below the scenario's noise floor {low:.4g}{unit} "
                "(the score of an error a quarter of the white noise in the uncompensated output, from the truth): "
                "no compensator reaches it from the features; did the truth reach the compensator?"
            )
    return None
