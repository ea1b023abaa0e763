"""One seed: resolve the scenario, fit the compensator on its training set, score every held-out run.

A scenario with a compensation stage defines ``compensation_task(config, seed)``
(:mod:`gyrobench.scenarios.base`): a training set and held-out runs whose truth is known.
Scenarios are reached only through :mod:`gyrobench.scenarios.registry` (a registered name)
or an importable module path the user gives; no scenario module is named here.
"""

from __future__ import annotations

import contextlib
import importlib
import math
import signal
import threading
import time
import types
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gyrobench.scenarios.bench.compensators import (
    CompensatorError,
    compensator_failed,
    compensator_label,
    fit_compensator,
    resolve_compensator,
)
from gyrobench.scenarios.bench.references import Uncompensated
from gyrobench.scenarios.bench.sandbox import ChildDied, MemoryExceeded, RemoteCompensator, Zygote, ZygoteError
from gyrobench.scenarios.bench.seeds import check_seeds

__all__ = [
    "DEFAULT_SEED_TIMEOUT_S",
    "TIMEOUT_FAILURE",
    "bench_scenarios",
    "check_seed_timeout",
    "resolve_scenario",
    "score_job",
    "score_or_failure",
    "score_predictions",
    "score_remote",
    "score_sandboxed",
    "score_job_remote",
    "score_seed",
    "score_task",
]

#: default per-seed time limit [s] of a campaign (``bench --seed-timeout``)
DEFAULT_SEED_TIMEOUT_S = 600.0

#: how a timed-out seed's failure reason starts (such a failure is not stored: a rerun retries it)
TIMEOUT_FAILURE = "exceeded the per-seed time limit"


class _SeedTimeout(BaseException):
    """Raised inside a seed by its time limit (a BaseException: a compensator's ``except
    Exception`` cannot swallow it)."""


def check_seed_timeout(value: Any) -> float | None:
    """``value`` as a per-seed time limit in seconds: a finite number > 0, or None (no limit)."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value <= 0:
        raise ValueError(f"seed_timeout must be a finite number of seconds > 0 (or None); got {value!r}")
    return float(value)


@contextlib.contextmanager
def _time_limit(seconds: float | None) -> Iterator[None]:
    """Raise :class:`_SeedTimeout` in this thread after ``seconds`` (SIGALRM; only in the main
    thread of a process: local pool workers and ``workers=0`` runs. A dask worker's thread runs
    without a limit). Python code is interrupted between bytecodes; a C loop that never returns
    to Python is not."""
    if seconds is None or threading.current_thread() is not threading.main_thread() or not hasattr(
        signal, "setitimer"
    ):
        yield
        return

    def _expired(signum: int, frame: Any) -> None:
        raise _SeedTimeout

    previous = signal.signal(signal.SIGALRM, _expired)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)



def resolve_scenario(scenario: str | types.ModuleType) -> types.ModuleType:
    """The scenario module for a registered name, an importable module path or a module.

    Raises
    ------
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
    """Registered scenarios with a compensation stage (:func:`gyrobench.scenarios.registry.describe`
    reads their source: nothing is imported)."""
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
    """:func:`score_seed`, naming the compensator ``label`` in errors (default: from the object).

    Returns the scores and, for a failed seed, why it failed (a non-finite prediction or
    score); else None. A seed fails at the first held-out run whose prediction or scores are
    not all finite; the runs after it are not scored.
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
    """Fit a resolved ``compensator`` on a built ``task`` (a :class:`~gyrobench.scenarios.base.
    CompensationTask`) and score every held-out run: the scores and why the seed failed, or None
    (:func:`score_or_failure` builds the task and calls this; several compensators can be scored
    on one task this way). ``seed`` seeds the compensator; ``label`` names it in errors."""
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
    """Score every held-out run of ``task`` from ``predict(run.X)`` (None: the raw output), here,
    with this process's numpy: the scores and why the seed failed, or None."""
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


def score_job(
    module_name: str,
    compensator: Any,
    seed: int,
    config: Any,
    label: str | None = None,
    seed_timeout: float | None = None,
) -> tuple[int, dict[str, float], float, str | None]:
    """Worker entry point (module level so it pickles by reference):
    (seed, scores, elapsed [s], failure or None).

    Contained: a compensator (or scenario) that calls ``sys.exit`` or runs past
    ``seed_timeout`` seconds makes the seed failed with that reason instead of ending or
    hanging the campaign (see :func:`_time_limit` for what the limit can interrupt).
    """
    t0 = time.perf_counter()
    try:
        with _time_limit(seed_timeout):
            module = importlib.import_module(module_name)
            scores, failure = _score_with_floor(module, compensator, seed, config, label)
    except SystemExit as exc:
        scores, failure = {}, f"the compensator called sys.exit({exc.code!r}); a compensator must return or raise"
    except _SeedTimeout:
        scores, failure = {}, f"{TIMEOUT_FAILURE} of {seed_timeout:g} s (--seed-timeout)"
    return seed, scores, time.perf_counter() - t0, failure


#: a sandboxed seed whose compensator's process ended without answering (the campaign's
#: process, which reaps it, replaces this with how it ended)
CHILD_DIED = "the compensator's process ended without a result"

#: how a seed failed by the per-seed memory cap starts (not stored: a rerun with a larger
#: ``--seed-memory`` retries it)
MEMORY_FAILURE = "exceeded the per-seed memory cap"


def _score_with_floor(
    module: types.ModuleType, compensator: Any, seed: int, config: Any, label: str | None
) -> tuple[dict[str, float], str | None]:
    """:func:`score_or_failure` on one task, then its noise-floor verdict
    (:func:`~gyrobench.scenarios.bench.floor.floor_failure`; not for the uncompensated output)."""
    from threadpoolctl import threadpool_limits

    from gyrobench.scenarios.bench.floor import floor_failure

    comp = resolve_compensator(compensator)
    (seed,) = check_seeds([seed])
    config = module.Config() if config is None else config
    label = compensator_label(comp, compensator, short=True) if label is None else label
    with threadpool_limits(limits=1):
        task = module.compensation_task(config, seed)
        scores, failure = score_task(task, comp, seed, label)
        if failure is None and not (comp is Uncompensated or isinstance(comp, Uncompensated)):
            failure = floor_failure(getattr(module, "NAME", module.__name__), task, scores)
    return scores, failure


def score_remote(task: Any, remote: RemoteCompensator, seed: int, label: str) -> tuple[dict[str, float], str | None]:
    """Fit the compensator in its own process (``remote``) on ``task``'s training data only and
    score its predictions here (:func:`score_predictions`)."""
    from gyrobench.scenarios.bench.compensators import seed_int

    groups = getattr(task, "groups_train", None)
    try:
        remote.fit(task.X_train, task.y_train, groups, seed_int(seed))
    except ChildDied:
        raise
    except Exception as exc:
        raise compensator_failed(label, seed, "fit", exc) from None
    return score_predictions(task, remote.predict, seed, label)


def score_sandboxed(
    module_name: str, seed: int, config: Any, label: str, fd: int, memory: int | None = None,
    deadline: float | None = None, seed_timeout: float | None = None,
) -> tuple[int, dict[str, float], float, str | None, dict[str, Any]]:
    """Scoring process of one sandboxed seed: build the task, talk to the compensator's child on
    socket ``fd`` (:class:`~gyrobench.scenarios.bench.sandbox.RemoteCompensator`), score, check
    the noise floor. Returns (seed, scores, elapsed [s], failure or None, the child's reads)."""
    from multiprocessing.connection import Connection

    from threadpoolctl import threadpool_limits

    from gyrobench.scenarios.bench.floor import floor_failure

    t0 = time.perf_counter()
    module = importlib.import_module(module_name)
    remote = RemoteCompensator(Connection(fd), deadline=deadline, timeout=seed_timeout)
    reads: dict[str, Any] = {}
    try:
        with threadpool_limits(limits=1):
            task = module.compensation_task(config, seed)
            scores, failure = score_remote(task, remote, seed, label)
            if failure is None:
                failure = floor_failure(getattr(module, "NAME", module.__name__), task, scores)
        reads = remote.finish()
    except SystemExit as exc:
        scores, failure = {}, f"the compensator called sys.exit({exc.code!r}); a compensator must return or raise"
    except MemoryExceeded:
        cap = "" if memory is None else f" of {memory / 1024**3:g} GiB"
        scores, failure = {}, f"{MEMORY_FAILURE}{cap} (--seed-memory): it raised MemoryError"
    except ChildDied as exc:
        timed_out = f"{TIMEOUT_FAILURE} of {exc.timeout:g} s (--seed-timeout)" if exc.timeout else None
        scores, failure = {}, timed_out or CHILD_DIED
    return seed, scores, time.perf_counter() - t0, failure, reads


def score_job_remote(
    module_name: str, compensator: Any, seed: int, config: Any, label: str,
    seed_timeout: float | None = None, memory: int | None = None,
) -> tuple[int, dict[str, float], float, str | None, dict[str, Any]]:
    """Worker entry point of a sandboxed seed on any executor (a dask worker): its own zygote
    (:class:`~gyrobench.scenarios.bench.sandbox.Zygote`) and child, the deadline kept here."""
    t0 = time.perf_counter()
    deadline = None if seed_timeout is None else time.monotonic() + seed_timeout
    try:
        zygote = Zygote(compensator, memory=memory, timeout=seed_timeout)
    except ZygoteError as exc:
        return seed, {}, time.perf_counter() - t0, f"the compensator could not be loaded: {exc}", {}
    try:
        pid, sock = zygote.fork()
        try:
            result = score_sandboxed(module_name, seed, config, label, sock.detach(), memory, deadline, seed_timeout)
        finally:
            status = zygote.end_child(pid)
    finally:
        zygote.close()
    if result[3] == CHILD_DIED:
        result = (*result[:3], f"the compensator's process {status.reason()}", result[4])
    return result
