"""One unit's execution for the paper-unit runner: where units run, how much memory they may take
together, and the worker entry point that runs one ``experiment`` and encodes its result.

:func:`_unit_job` runs in a worker process (or this one) with the BLAS/OpenMP pools limited to one
thread, so a unit's result is bit-identical whatever the executor and worker count;
:func:`_execute` hands the seeds to the executor and records each unit as it finishes.
:func:`slim_result` empties the report-only arrays of a unit the report does not draw. The
scheduling (which seeds, resumption, the claims) is :mod:`gyrobench.scenarios.runner.units`.
"""

from __future__ import annotations

import concurrent.futures as cf
import dataclasses
import importlib
import time
import types
from collections.abc import Callable, Container, Mapping, Sequence
from typing import Any

import numpy as np

from gyrobench.scenarios.papers.contract import quantities_of

__all__ = ["check_unit_memory", "concurrent_units", "slim_result"]

def concurrent_units(n_units: int, workers: int | None) -> int:
    """How many units a local run holds in memory at once.

    How many units a local run holds in memory at once: one per worker process, at most
    ``n_units`` (``workers`` 0: in this process, one at a time; None: the usable CPUs).

    Parameters
    ----------
    n_units : int
        The units of the run.
    workers : int or None
        Worker processes (0: in this process; None: the usable CPUs).

    Returns
    -------
    int
        One per worker, at most ``n_units``.
    """
    from gyrobench.scenarios.runner.executors import default_workers

    if workers == 0:
        return 1
    return max(1, min(int(n_units), workers or default_workers()))


def check_unit_memory(
    module: types.ModuleType, config: Any, *, concurrent: int, source: str = "its configuration"
) -> None:
    """Refuse, before any unit starts, a local run whose units do not fit in memory together.

    A scenario's ``memory_estimate(config)`` is the peak of ONE unit (one ``experiment`` in
    one worker process). This is the one place that multiplies it by the units running at
    once on this machine (:func:`concurrent_units`); a remote executor's workers hold their
    units in their own memory, so its callers do not call this.
    :func:`gyrobench.scenarios.registry.load_config` has already checked one unit.

    Parameters
    ----------
    module : module
        The paper scenario (its ``memory_estimate``).
    config : object
        The scenario's Config.
    concurrent : int
        Units running at once (:func:`concurrent_units`).
    source : str
        Where the configuration came from, for the message.

    Raises
    ------
    gyrobench.base.memory.MemoryLimitError
        One line: the scenario, ``source`` (e.g. ``"config file 'big.toml'"``), the units at
        once, the estimate and the limit.
    """
    from gyrobench.base import memory

    est = memory.scenario_bytes(module, config)
    if est is None:
        return
    name = getattr(module, "NAME", module.__name__)
    memory.check_memory(
        est * concurrent,
        f"scenario {name} with {source} ({concurrent} unit(s) at once, one per worker process, "
        f"about {memory.format_bytes(est)} each)",
        hint="lower --workers, or shorten the records or lower the sample rate in --config",
    )


def slim_result(module: types.ModuleType, result: Any) -> Any:
    """A unit's result with the report-only arrays emptied.

    ``result`` with every array of the fields ``module.SLIM_FIELDS`` names emptied (same dtype and
    number of dimensions, no elements): what a unit the report does not draw is stored as.

    A scenario lists there the fields only its report's figures read, and in ``REPORT_UNITS`` how many
    leading units of a run the report draws; the claims read ``quantities``, which is never slimmed.
    A scenario without ``SLIM_FIELDS`` stores every unit whole.

    Parameters
    ----------
    module : module
        The paper scenario (its ``SLIM_FIELDS``).
    result : object
        One unit's result.

    Returns
    -------
    object
        ``result`` with those fields' arrays emptied (same dtype and dimensions).
    """
    names = tuple(getattr(module, "SLIM_FIELDS", ()))
    if not names:
        return result
    if isinstance(result, Mapping):
        return {**result, **{k: _emptied(result[k]) for k in names}}
    return dataclasses.replace(result, **{k: _emptied(getattr(result, k)) for k in names})


def _emptied(value: Any) -> Any:
    """``value`` with each numpy array inside it (through frozen dataclasses, tuples, lists and dicts)
    replaced by an empty array of its dtype and number of dimensions."""
    if isinstance(value, np.ndarray):
        return np.empty((0,) * value.ndim, dtype=value.dtype)
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return dataclasses.replace(value, **{f.name: _emptied(getattr(value, f.name))
                                             for f in dataclasses.fields(value) if f.init})
    if isinstance(value, (list, tuple)):
        return type(value)(_emptied(v) for v in value)
    if isinstance(value, dict):
        return {k: _emptied(v) for k, v in value.items()}
    return value


#: glibc mallopt parameters (malloc.h): M_TRIM_THRESHOLD, M_MMAP_THRESHOLD
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3
_MALLOC_TUNED = False


def keep_freed_memory() -> bool:
    """Let this process's C allocator reuse the memory of freed large arrays instead of returning it to
    the system (glibc: arrays up to 1 GB from the heap, which is trimmed only above 2 GB free).

    A unit allocates and frees arrays of tens of MB over and over (paper 000: about 0.7 GB of fresh
    pages a unit); each fresh page is a page fault, which on this project's virtual machines cost as
    much CPU as the arithmetic (paper 000: 180,000 faults and 0.6-1.0 s of system time a unit, 38,000
    and 0.1-0.3 s with the memory kept; the peak RSS rises by 2-5 %). Values are unchanged: only
    where the allocator takes memory from. Called once per process, by units run in this process or
    a local process pool (not on a cluster's workers); True when the allocator took the setting
    (glibc), False elsewhere.
    """
    global _MALLOC_TUNED
    if _MALLOC_TUNED:
        return True
    try:
        import ctypes

        libc = ctypes.CDLL("libc.so.6")
        ok = bool(libc.mallopt(_M_MMAP_THRESHOLD, 1 << 30)) and bool(libc.mallopt(_M_TRIM_THRESHOLD, 1 << 31))
    except (OSError, AttributeError):
        return False
    _MALLOC_TUNED = ok
    return ok


def _unit_job(
    module_name: str, config: Any, seed: int, full: bool = True, own_worker: bool = False
) -> tuple[int, bytes, float, bool]:
    """Worker entry point: one unit's ``experiment`` result, encoded by the codec and compressed
    (:func:`slim_result` unless ``full``). Module level: it pickles to the worker; the result comes back
    as the stored bytes, never as a pickle of our own. ``own_worker``: this process or one of a local
    process pool (:func:`keep_freed_memory` applies)."""
    from threadpoolctl import threadpool_limits

    if own_worker:
        keep_freed_memory()

    t0 = time.perf_counter()
    module = importlib.import_module(module_name)
    with threadpool_limits(limits=1):
        result = module.experiment(config, seed)
    try:
        quantities_of(result)
    except TypeError:
        raise TypeError(
            f"{module_name}.experiment must return a UnitResult (a typed result with a 'quantities' "
            f"mapping); got {type(result).__name__} for seed {seed}"
        ) from None
    from gyrobench.scenarios.runner import codec

    stored = result if full else slim_result(module, result)
    return seed, codec.dumps_compressed(stored), time.perf_counter() - t0, full or stored is result



def _execute(
    module_name: str,
    config: Any,
    todo: Sequence[int],
    record: Callable[[int, bytes, float, bool], None],
    *,
    full: Container[int],
    executor: cf.Executor | None,
    workers: int | None,
) -> None:
    """Run ``_unit_job`` for every seed of ``todo`` and ``record`` each as it finishes."""
    from gyrobench.scenarios.runner.executors import add_note, check_picklable, local_pool, stop_pool

    if executor is None and workers == 0:
        for s in todo:
            record(*_unit_job(module_name, config, s, s in full, True))
        return
    check_picklable(None, config)
    own = executor is None
    ex: cf.Executor = local_pool(workers) if executor is None else executor
    local = isinstance(ex, cf.ProcessPoolExecutor)  # this machine's processes (not a cluster's workers)
    futures: dict[cf.Future, int] = {}
    ok = False
    try:
        futures = {ex.submit(_unit_job, module_name, config, s, s in full, local): s for s in todo}
        for fut in cf.as_completed(futures):
            try:
                record(*fut.result())
            except Exception as exc:
                add_note(exc, f"while computing unit (seed) {futures[fut]} of {module_name}")
                raise
        ok = True
    finally:
        for f in futures:
            f.cancel()
        if own:
            stop_pool(ex, kill=not ok)  # Ctrl-C, SIGTERM or an error: running units are killed
