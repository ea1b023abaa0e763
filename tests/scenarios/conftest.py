"""Fixtures of the scenario tests: one shared simulation per (scenario, config, seed).

Several slow bench tests score different compensators on the same seeds of the same scenario
(a baseline, the same compensator again, a worse one, the reference columns), and each bench
run builds every seed's :class:`~gyrobench.scenarios.base.CompensationTask` anew: the same
simulation up to 4 times per seed and test, and again in the next test (fog_vibration ~10-25 s
a seed). A task is a pure function of (config, seed), so :func:`shared_tasks` builds each one
once per session and hands the same object to every test that asks. What the tests check (the
fit, the scores, the store, the gate) still runs in full on each call; only the identical
simulation is not repeated.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterable
from typing import Any

import numpy as np
import pytest

from gyrobench.scenarios.bench.scoring import bench_scenarios, resolve_scenario

#: (scenario module name, config, seed) -> its task, built once per session
_TASKS: dict[tuple[str, Any, int], Any] = {}


def _frozen(task: Any) -> Any:
    """``task`` with every array read-only: a test or compensator that wrote into a shared task
    would change what the next test sees, so it raises instead (numpy's "read-only" ValueError)."""
    arrays = [task.X_train, task.y_train, task.groups_train]
    for run in task.heldout:
        arrays += [getattr(run, f.name) for f in dataclasses.fields(run)]
    for a in arrays:
        if isinstance(a, np.ndarray):
            a.setflags(write=False)
    return task


@pytest.fixture
def shared_tasks(monkeypatch: pytest.MonkeyPatch) -> Callable[[str, Iterable[int]], None]:
    """Memoise every bench scenario's ``compensation_task`` for this test, from the session's store.

    Returns ``prime(scenario, seeds)``, which builds the seeds' tasks in this process. Call it
    before a bench run with ``--workers 0``: that run scores each seed in a forked child, which
    inherits the parent's store but cannot add to it.
    """
    for name in bench_scenarios():
        module = resolve_scenario(name)
        build = module.compensation_task

        def cached(config: Any, seed: int, *, _module: Any = module, _build: Any = build) -> Any:
            key = (_module.__name__, config, int(seed))
            if key not in _TASKS:
                _TASKS[key] = _frozen(_build(config, seed))
            return _TASKS[key]

        monkeypatch.setattr(module, "compensation_task", cached)

    def prime(scenario: str, seeds: Iterable[int]) -> None:
        module = resolve_scenario(scenario)
        for seed in seeds:
            module.compensation_task(module.Config(), seed)

    return prime
