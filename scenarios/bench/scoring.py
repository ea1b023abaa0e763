"""One seed: resolve the scenario, fit the compensator on its training set, score every held-out run.

This is scoring in the calling process; a seed as a campaign's job (its time limit, its
sandboxed compensator, its noise floor) is :mod:`gyrobench.scenarios.bench.jobs`.

A scenario with a compensation stage defines ``compensation_task(config, seed)``
(:mod:`gyrobench.scenarios.base`): a training set and held-out runs whose truth is known.
Scenarios are reached only through :mod:`gyrobench.scenarios.registry` (a registered name)
or an importable module path the user gives; no scenario module is named here.
"""

from __future__ import annotations

import importlib
import math
import types
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gyrobench.base.lazy import attach
from gyrobench.scenarios.bench.compensators import (
    CompensatorError,
    compensator_failed,
    compensator_label,
    fit_compensator,
    resolve_compensator,
)
from gyrobench.scenarios.bench.references import Uncompensated
from gyrobench.scenarios.bench.sandbox_protocol import ChildDied
from gyrobench.scenarios.bench.seeds import check_seeds

__all__ = [
    "bench_scenarios",
    "resolve_scenario",
    "score_or_failure",
    "score_predictions",
    "score_seed",
    "score_task",
]

#: the worker entry points, moved to :mod:`gyrobench.scenarios.bench.jobs`: still reached here
_MOVED = {
    name: "gyrobench.scenarios.bench.jobs"
    for name in (
        "CHILD_DIED", "DEFAULT_SEED_TIMEOUT_S", "MEMORY_FAILURE", "TIMEOUT_FAILURE", "check_seed_timeout",
        "score_job", "score_job_remote", "score_remote", "score_sandboxed",
    )
}
__getattr__, __dir__ = attach(__name__, _MOVED)


def resolve_scenario(scenario: str | types.ModuleType) -> types.ModuleType:
    """The scenario module for a registered name, an importable module path or a module.

    Parameters
    ----------
    scenario : str or module
        A registered scenario name (``"p000_fog_vibration"``), an importable module path, or a
        module object.

    Returns
    -------
    module
        The scenario module; it defines ``compensation_task``.

    Raises
    ------
    TypeError
        If ``scenario`` is neither a string nor a module.
    ValueError
        If the name is unknown or the scenario has no compensation stage.
    """
    from gyrobench.scenarios import registry

    if isinstance(scenario, types.ModuleType):
        module = scenario
    elif isinstance(scenario, str):
        if scenario in registry.table() or "." not in scenario:
            if scenario not in registry.available():
                raise ValueError(
                    "scenario must be one of the scenarios with a compensation stage "
                    f"{bench_scenarios()} or an importable module path; got {scenario!r}"
                )
            module = registry.get(scenario)
        else:
            try:
                module = importlib.import_module(scenario)
            except ModuleNotFoundError as exc:
                raise ValueError(
                    f"scenario must be a registered name {registry.available()} or an importable "
                    f"module; got {scenario!r} ({exc})"
                ) from None
    else:
        raise TypeError(
            f"scenario must be a name or a module; got {type(scenario).__name__} {scenario!r}"
        )
    if not callable(getattr(module, "compensation_task", None)):
        raise ValueError(
            f"scenario {getattr(module, 'NAME', module.__name__)!r} has no compensation stage "
            f"(no compensation_task); scenarios with one: {bench_scenarios()}"
        )
    return module


def bench_scenarios() -> list[str]:
    """The registered scenarios with a compensation stage.

    :func:`gyrobench.scenarios.registry.describe` reads their source: nothing is imported.

    Returns
    -------
    list of str
        Their names, in the registry's order; a scenario whose source cannot be read is left out.
    """
    from gyrobench.scenarios import registry

    out = []
    for name in registry.available():
        try:
            if registry.describe(name).bench:
                out.append(name)
        except (OSError, SyntaxError, ValueError):  # unreadable source: not offered
            continue
    return out


def score_seed(
    scenario: str | types.ModuleType, compensator: Any, seed: int, config: Any = None
) -> dict[str, float]:
    """Fit ``compensator`` on the scenario's training run for ``seed`` and score every held-out run.

    Parameters
    ----------
    scenario : str or module
        Registered scenario name, importable module path, or module object.
    compensator : estimator, estimator class, fit function or "module:attr"
        See the module docstring.
    seed : int
        Seed of the scenario's simulation (>= 0); also seeds the compensator.
    config : scenario Config, optional
        Defaults to the scenario's ``Config()`` (the paper's setup).

    Returns
    -------
    dict
        ``"<run label>/<score>"`` for every held-out run and ``"mean/<score>"``, the
        mean over the runs that report that score; keys sorted.

    Raises
    ------
    CompensatorError
        If the compensator's fit or predict raises (the message names the
        compensator, the seed, the stage and the original exception; the original
        is chained as ``__cause__``), its prediction has the wrong size, or its
        prediction or a score is not finite (NaN or inf: in a campaign such a seed
        is recorded as failed instead, see :func:`run_campaign`).
    TypeError
        If a fit function returns something that cannot predict.
    """
    comp = resolve_compensator(compensator)
    label = compensator_label(comp, compensator, short=True)
    scores, failure = score_or_failure(scenario, comp, seed, config, label)
    if failure is not None:
        raise CompensatorError(
            f"compensator {label} failed on seed {seed}: {failure}",
            compensator=label,
            seed=seed,
            stage="score",
        )
    return scores


def score_or_failure(
    scenario: str | types.ModuleType,
    compensator: Any,
    seed: int,
    config: Any = None,
    label: str | None = None,
) -> tuple[dict[str, float], str | None]:
    """:func:`score_seed`, returning a failed seed's reason instead of raising.

    A seed fails at the first held-out run whose prediction or scores are not all finite; the
    runs after it are not scored.

    Parameters
    ----------
    scenario : str or module
        As for :func:`resolve_scenario`.
    compensator : estimator, estimator class, fit function or "module:attr"
        As for :func:`score_seed`.
    seed : int
        Seed of the scenario's simulation (>= 0); also seeds the compensator.
    config : scenario Config, optional
        Defaults to the scenario's ``Config()``.
    label : str, optional
        How errors name the compensator (default: from the object).

    Returns
    -------
    scores : dict of str to float
        As for :func:`score_seed` (only the runs scored before a failure).
    failure : str or None
        Why the seed failed (a non-finite prediction or score), or None.

    Raises
    ------
    CompensatorError
        If the compensator's fit or predict raises, or its prediction has the wrong size.
    """
    from threadpoolctl import threadpool_limits

    module = resolve_scenario(scenario)
    comp = resolve_compensator(compensator)
    (seed,) = check_seeds([seed])
    if config is None:
        config = module.Config()
    if label is None:
        label = compensator_label(comp, compensator, short=True)
    with threadpool_limits(limits=1):
        return score_task(module.compensation_task(config, seed), comp, seed, label)


def score_task(task: Any, compensator: Any, seed: int, label: str) -> tuple[dict[str, float], str | None]:
    """Fit a resolved compensator on a built task and score every held-out run.

    :func:`score_or_failure` builds the task and calls this; several compensators can be scored
    on one task this way.

    Parameters
    ----------
    task : CompensationTask
        A scenario's task (:class:`~gyrobench.scenarios.base.CompensationTask`).
    compensator : object
        A compensator as :func:`~gyrobench.scenarios.bench.compensators.resolve_compensator`
        returns it; :class:`~gyrobench.scenarios.bench.references.Uncompensated` scores the raw
        output.
    seed : int
        Seeds the compensator.
    label : str
        How errors name the compensator.

    Returns
    -------
    scores : dict of str to float
        As for :func:`score_predictions`.
    failure : str or None
        Why the seed failed, or None.
    """
    # the uncompensated reference scores the raw output: nothing to fit or predict
    raw = compensator is Uncompensated or isinstance(compensator, Uncompensated)
    groups = getattr(task, "groups_train", None)
    predict = (
        None if raw else fit_compensator(compensator, task.X_train, task.y_train, seed, label=label, groups=groups)
    )
    return score_predictions(task, predict, seed, label)


def score_predictions(
    task: Any, predict: Callable | None, seed: int, label: str
) -> tuple[dict[str, float], str | None]:
    """Score every held-out run of ``task`` from its predictions, with this process's numpy.

    Parameters
    ----------
    task : CompensationTask
        The seed's task.
    predict : callable or None
        ``predict(run.X)`` -> the predicted error, one value per sample [the task's unit];
        None scores the raw output (the uncompensated reference).
    seed : int
        The seed, named in errors.
    label : str
        How errors name the compensator.

    Returns
    -------
    scores : dict of str to float
        ``"<run label>/<score>"`` per held-out run and ``"mean/<score>"``, keys sorted.
    failure : str or None
        Why the seed failed (the first run with a non-finite prediction or score), or None.

    Raises
    ------
    CompensatorError
        If ``predict`` raises or returns the wrong number of values.
    """
    scores: dict[str, float] = {}
    per_key: dict[str, list[float]] = {}
    for run in task.heldout:
        run_scores, failure = _score_run(task, run, predict, seed, label)
        for k, v in run_scores.items():
            scores[f"{run.label}/{k}"] = v
            per_key.setdefault(k, []).append(v)
        if failure is not None:
            return dict(sorted(scores.items())), failure
    for k, vals in per_key.items():
        scores[f"mean/{k}"] = math.fsum(vals) / len(vals)
    return dict(sorted(scores.items())), None


def _score_run(
    task: Any, run: Any, predict: Callable | None, seed: int, label: str
) -> tuple[dict[str, float], str | None]:
    """One held-out run's scores (empty if the prediction is not finite) and why it failed, or
    None. ``predict`` None scores the raw output (the uncompensated reference)."""
    if run.label == "mean" or "/" in run.label:
        raise ValueError(
            f"held-out run labels must not be 'mean' or contain '/'; got {run.label!r}"
        )
    if predict is None:
        return _scored(task, run, np.asarray(run.output, dtype=float))
    stage = f"predict on run {run.label}"
    try:
        raw = predict(run.X)
        if np.iscomplexobj(raw):  # never truncated to its real part
            return {}, (f"the prediction on run {run.label} is complex ({np.asarray(raw).dtype}); "
                        "a compensator must predict real values")
        pred = np.asarray(raw, dtype=float)
    except ChildDied:  # the compensator's process ended: a failed seed, not a raising compensator
        raise
    except Exception as exc:
        raise compensator_failed(label, seed, stage, exc) from exc
    if pred.size != len(run.output):
        raise CompensatorError(
            f"compensator {label} failed on seed {seed} ({stage}): the prediction must "
            f"have {len(run.output)} values (one per sample of X); got shape {pred.shape}",
            compensator=label,
            seed=seed,
            stage=stage,
        )
    failure = _nonfinite(f"the prediction on run {run.label}", pred)
    if failure is not None:
        return {}, failure
    return _scored(task, run, task.compensate(pred, run))


def _scored(task: Any, run: Any, compensated: NDArray[np.float64]) -> tuple[dict[str, float], str | None]:
    """The task's scores of ``compensated`` on ``run`` and why the seed failed (a non-finite
    score), or None."""
    failure = None
    with np.errstate(all="ignore"):  # an overflow is reported as a failed seed
        run_scores = {k: float(v) for k, v in task.scorer(compensated, run).items()}
    bad = [k for k, v in run_scores.items() if not math.isfinite(v)]
    if bad:
        failure = f"score {run.label}/{bad[0]} is {run_scores[bad[0]]!r}" + (
            f" ({len(bad)} non-finite scores)" if len(bad) > 1 else ""
        )
    return run_scores, failure


def _nonfinite(what: str, values: NDArray[np.float64]) -> str | None:
    """``"<what> has 3 non-finite values of 300 (nan at sample 0)"``, or None if all are finite."""
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size == 0:
        return None
    i = int(bad[0])
    return (
        f"{what} has {bad.size} non-finite value{'s' if bad.size > 1 else ''} of {values.size} "
        f"({float(values.flat[i])!r} at sample {i})"
    )


