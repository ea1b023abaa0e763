"""Closed-form checks of the sensor models: the record type and the collector.

Every physical model in :mod:`gyrobench.sim` has at least one closed-form check: a
quantity the model simulates beside the value an equation gives for it. Each check
module listed in :data:`CHECK_MODULES` defines

``checks(rng) -> list[Check]``
    run the module's checks (short records, full equations where the model has a
    fast form), drawing every random number from ``rng`` (a
    :class:`numpy.random.Generator`).

The ``physics_checks`` scenario runs them all and reports each check's id, formula,
expected and simulated values, relative error and tolerance with its derivation.
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Callable
from concurrent.futures import Executor
from dataclasses import dataclass

import numpy as np

__all__ = ["CHECK_MODULES", "Check", "collect"]

#: modules defining ``checks(rng) -> list[Check]``, in report order (append new ones at the
#: end: :func:`collect` gives each module its own child stream in this order, so an added
#: module changes no earlier module's numbers)
CHECK_MODULES: tuple[str, ...] = (
    "gyrobench.scenarios.checks_noise",
    "gyrobench.scenarios.checks_fog",
    "gyrobench.scenarios.checks_rlg",
    "gyrobench.scenarios.checks_mems",
    "gyrobench.scenarios.checks_rlg_cavity",
    "gyrobench.scenarios.checks_fog_loop",
    "gyrobench.scenarios.checks_coil",
    "gyrobench.scenarios.checks_mount_coning",
)


@dataclass(frozen=True, slots=True, kw_only=True)
class Check:
    """One closed-form check: a simulated quantity beside the value its equation gives.

    Parameters
    ----------
    id : str
        Short stable identifier, ``"<model>.<quantity>"``, e.g. ``"fog.sagnac_scale_factor"``.
    formula : str
        The closed form, plain text with units, e.g. ``"S = 2 pi L D / (lambda c) [s]"``.
    expected : float
        The closed form's value (SI).
    simulated : float
        The model's value for the same quantity (SI).
    tolerance : float
        Largest acceptable relative error (``rel_error``), > 0.
    derivation : str
        Where the tolerance comes from: the estimator's degrees of freedom and the
        false-alarm rate for a statistical check, the discretisation order for a
        numerical one, rounding for an exact one.
    scale : float, optional
        The magnitude the error is measured against when ``expected`` is 0 (or when
        the natural reference is another quantity, e.g. the uncancelled term for a
        cancellation check); default ``abs(expected)``.
    """

    id: str
    formula: str
    expected: float
    simulated: float
    tolerance: float
    derivation: str
    scale: float | None = None

    def __post_init__(self) -> None:
        if not (math.isfinite(self.tolerance) and self.tolerance > 0):
            raise ValueError(f"check {self.id!r}: tolerance must be finite and > 0; got {self.tolerance!r}")
        reference = abs(self.expected) if self.scale is None else abs(self.scale)
        if not (math.isfinite(reference) and reference > 0):
            raise ValueError(
                f"check {self.id!r}: needs a finite non-zero reference magnitude (expected or scale); "
                f"got expected={self.expected!r}, scale={self.scale!r}"
            )

    @property
    def rel_error(self) -> float:
        """``|simulated - expected| / reference`` (reference: ``scale`` or ``|expected|``)."""
        reference = abs(self.expected) if self.scale is None else abs(self.scale)
        return abs(self.simulated - self.expected) / reference

    @property
    def passed(self) -> bool:
        """True when the relative error is within the tolerance (a NaN never passes)."""
        return bool(self.rel_error <= self.tolerance)

    def as_dict(self) -> dict[str, object]:
        """The results.json form: id, formula, expected, simulated, rel_error, tolerance, passed."""
        return {
            "id": self.id,
            "formula": self.formula,
            "expected": self.expected,
            "simulated": self.simulated,
            "rel_error": self.rel_error,
            "tolerance": self.tolerance,
            "tolerance_derivation": self.derivation,
            "passed": self.passed,
        }


def _module_checks(name: str, rng: np.random.Generator) -> list[Check]:
    """One module's checks (module level, so it pickles to a worker process)."""
    return list(importlib.import_module(name).checks(rng))


def collect(
    rng: np.random.Generator,
    modules: tuple[str, ...] = CHECK_MODULES,
    *,
    executor: Executor | None = None,
    on_module_done: Callable[[str, list[Check]], None] | None = None,
) -> list[Check]:
    """Run every check module's ``checks`` with its own child stream of ``rng``.

    Each module gets one spawned child generator, in the order of ``modules``, so adding a
    module at the end changes no earlier module's numbers, and the results are the same
    whether the modules run here or on ``executor`` (e.g. a process pool), in any order.
    ``on_module_done(name, checks)`` is called as each module finishes (in completion order
    on an executor), e.g. to move a progress bar.
    """
    children = rng.spawn(len(modules))
    if executor is None:
        per_module = []
        for n, c in zip(modules, children, strict=True):
            per_module.append(_module_checks(n, c))
            if on_module_done is not None:
                on_module_done(n, per_module[-1])
    else:
        from concurrent.futures import as_completed

        futures = {executor.submit(_module_checks, n, c): n for n, c in zip(modules, children, strict=True)}
        if on_module_done is not None:
            for f in as_completed(futures):
                on_module_done(futures[f], f.result())
        per_module = [f.result() for f in futures]
    out: list[Check] = [c for checks in per_module for c in checks]
    ids = [c.id for c in out]
    dup = sorted({i for i in ids if ids.count(i) > 1})
    if dup:
        raise ValueError(f"check ids must be unique; repeated: {dup}")
    return out
