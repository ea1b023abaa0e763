"""A seed as a job: the worker entry points of a campaign, with the seed's containment.

:func:`score_job` scores one seed in a worker process (the compensator in that process);
:func:`score_job_remote` and :func:`score_sandboxed` score it with the compensator in its own
child (:mod:`gyrobench.scenarios.bench.sandbox`), the truth kept in the scoring process. Both
contain the seed: a compensator that calls ``sys.exit``, runs past the per-seed time limit or
exceeds the per-seed memory cap makes the seed failed with that reason, and every score is
checked against the scenario's noise floor (:func:`~gyrobench.scenarios.bench.floor.floor_failure`).
Scoring one task is :mod:`gyrobench.scenarios.bench.scoring`.
"""

from __future__ import annotations

import contextlib
import importlib
import math
import signal
import threading
import time
import types
from collections.abc import Iterator
from typing import Any

from gyrobench.scenarios.bench.compensators import compensator_failed, compensator_label, resolve_compensator
from gyrobench.scenarios.bench.references import Uncompensated
from gyrobench.scenarios.bench.sandbox import ChildDied, MemoryExceeded, RemoteCompensator, Zygote, ZygoteError
from gyrobench.scenarios.bench.scoring import score_predictions, score_task
from gyrobench.scenarios.bench.seeds import check_seeds

__all__ = [
    "CHILD_DIED",
    "DEFAULT_SEED_TIMEOUT_S",
    "MEMORY_FAILURE",
    "TIMEOUT_FAILURE",
    "check_seed_timeout",
    "score_job",
    "score_job_remote",
    "score_remote",
    "score_sandboxed",
]

#: default per-seed time limit [s] of a campaign (``bench --seed-timeout``)
DEFAULT_SEED_TIMEOUT_S = 600.0

#: how a timed-out seed's failure reason starts (such a failure is not stored: a rerun retries it)
TIMEOUT_FAILURE = "exceeded the per-seed time limit"


class _SeedTimeout(BaseException):
    """Raised inside a seed by its time limit (a BaseException: a compensator's ``except
    Exception`` cannot swallow it)."""


def check_seed_timeout(value: Any) -> float | None:
    """Check a per-seed time limit.

    Parameters
    ----------
    value : float or None
        The limit [s]: a finite number > 0, or None (no limit).

    Returns
    -------
    float or None
        ``value`` as a float, or None.

    Raises
    ------
    ValueError
        If ``value`` is not a finite number > 0 (a bool is refused) nor None.
    """
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


def score_job(
    module_name: str,
    compensator: Any,
    seed: int,
    config: Any,
    label: str | None = None,
    seed_timeout: float | None = None,
) -> tuple[int, dict[str, float], float, str | None]:
    """Score one seed in a worker process, contained (module level: it pickles by reference).

    A compensator (or scenario) that calls ``sys.exit`` or runs past ``seed_timeout`` seconds
    makes the seed failed with that reason instead of ending or hanging the campaign (see
    :func:`_time_limit` for what the limit can interrupt); a score below the scenario's noise
    floor fails it too.

    Parameters
    ----------
    module_name : str
        The scenario's module.
    compensator : object
        The compensator, as for :func:`~gyrobench.scenarios.bench.scoring.score_seed`.
    seed : int
        The seed.
    config : scenario Config or None
        None: the scenario's ``Config()``.
    label : str, optional
        How errors name the compensator.
    seed_timeout : float, optional
        Per-seed time limit [s]; None: none.

    Returns
    -------
    seed : int
        The seed.
    scores : dict of str to float
        Its scores (empty when it failed before any).
    elapsed : float
        Wall time [s].
    failure : str or None
        Why the seed failed, or None.
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
    """Fit the compensator in its own process on the task's training data only; score here.

    Parameters
    ----------
    task : CompensationTask
        The seed's task (it never leaves this process).
    remote : RemoteCompensator
        The handle on the compensator's child.
    seed : int
        The seed; the child receives only its ``random_state`` integer.
    label : str
        How errors name the compensator.

    Returns
    -------
    scores : dict of str to float
        As for :func:`~gyrobench.scenarios.bench.scoring.score_predictions`.
    failure : str or None
        Why the seed failed, or None.

    Raises
    ------
    CompensatorError
        If the compensator's fit or predict raised in its child.
    ChildDied
        If the child ended before answering.
    """
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
    """The scoring process of one sandboxed seed: build the task, score the child's predictions.

    It talks to the compensator's child on socket ``fd``
    (:class:`~gyrobench.scenarios.bench.sandbox.RemoteCompensator`), scores, and checks the
    noise floor. A ``sys.exit``, a ``MemoryError`` or a dead child fails the seed.

    Parameters
    ----------
    module_name : str
        The scenario's module.
    seed : int
        The seed.
    config : scenario Config
        The scenario's configuration.
    label : str
        How errors name the compensator.
    fd : int
        File descriptor of the scoring end of the child's socket (taken over and closed).
    memory : int, optional
        The child's address-space cap [bytes], named in a memory failure.
    deadline : float, optional
        ``time.monotonic()`` value [s] past which the child's answers are not awaited.
    seed_timeout : float, optional
        The per-seed time limit [s], named in a timeout failure.

    Returns
    -------
    seed : int
        The seed.
    scores : dict of str to float
        Its scores (empty when it failed before any).
    elapsed : float
        Wall time [s].
    failure : str or None
        Why the seed failed, or None.
    reads : dict
        What the child read (its manifest; ``{}`` when it failed).
    """
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
    """Score one sandboxed seed on any executor (a dask worker), with its own zygote and child.

    The zygote (:class:`~gyrobench.scenarios.bench.sandbox.Zygote`) is started and closed here,
    and the deadline kept here; a compensator that cannot be loaded fails the seed.

    Parameters
    ----------
    module_name : str
        The scenario's module.
    compensator : object
        The compensator, as for :class:`~gyrobench.scenarios.bench.sandbox.Zygote`.
    seed : int
        The seed.
    config : scenario Config
        The scenario's configuration.
    label : str
        How errors name the compensator.
    seed_timeout : float, optional
        Per-seed time limit [s], the compensator's import included; None: none.
    memory : int, optional
        The child's address-space cap [bytes]; None: none.

    Returns
    -------
    tuple
        (seed, scores, elapsed [s], failure or None, the child's reads), as for
        :func:`score_sandboxed`; a dead child's failure says how it ended.
    """
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
