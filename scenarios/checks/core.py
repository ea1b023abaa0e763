"""Physics checks of the sensor models: the record type and the collector.

Every physical model in :mod:`gyrobench.sim` has at least one check with a reference outside
its code: a quantity the model simulates beside the value an independently derived closed
form, a second method (full integration, exact kinematics) or a printed number gives for it.
Each check declares its reference's kind (:data:`KINDS`); a check that compares the code with
its own formula is kind ``"consistency"`` and is not counted as validation. Each check
module listed in :data:`CHECK_MODULES` defines

``checks(rng) -> list[Check]``
    run the module's checks (short records, full equations where the model has a
    fast form), drawing every random number from ``rng`` (a
    :class:`numpy.random.Generator`).

and may define

``parts(rng) -> list[Part]``
    the same checks as independent pieces with their streams already drawn from ``rng``
    (``checks(rng)`` is then :func:`run_parts` of them): :func:`collect` runs the pieces one
    by one, or side by side on an executor, and reports each as it finishes.

The ``physics_checks`` scenario runs them all and reports each check's id, formula,
expected and simulated values, relative error and tolerance with its derivation.
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Callable, Sequence
from concurrent.futures import Executor
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from gyrobench.base.ranges import Constraint, validate

__all__ = [
    "CHECK_MODULES",
    "CLOSED_FORM",
    "CONSISTENCY",
    "KINDS",
    "PRINTED",
    "SECOND_METHOD",
    "VALIDATION_KINDS",
    "Check",
    "Part",
    "collect",
    "kind_counts",
    "run_parts",
]

#: reference kind: ``expected`` is a closed form derived independently of the model's code
#: (a textbook or paper equation evaluated in the check, not the model's function)
CLOSED_FORM = "closed form"
#: reference kind: ``expected`` comes from a second, independent method (full integration of the
#: equations the model reduces, exact kinematics, a process simulated from first principles)
SECOND_METHOD = "second method"
#: reference kind: ``expected`` is a published number, with its source in ``reference``
PRINTED = "printed"
#: reference kind: the check compares the code with its own formula (the same equations reached
#: by another path of this package): a regression guard, NOT counted as validation
CONSISTENCY = "consistency"
#: every reference kind, in report order
KINDS: tuple[str, ...] = (CLOSED_FORM, SECOND_METHOD, PRINTED, CONSISTENCY)
#: the kinds that count as validation (an outside reference)
VALIDATION_KINDS: tuple[str, ...] = (CLOSED_FORM, SECOND_METHOD, PRINTED)

#: modules defining ``checks(rng) -> list[Check]``, in report order (append new ones at the
#: end: :func:`collect` gives each module its own child stream in this order, so an added
#: module changes no earlier module's numbers)
CHECK_MODULES: tuple[str, ...] = (
    "gyrobench.scenarios.checks.noise",
    "gyrobench.scenarios.checks.fog",
    "gyrobench.scenarios.checks.rlg",
    "gyrobench.scenarios.checks.mems",
    "gyrobench.scenarios.checks.rlg_cavity",
    "gyrobench.scenarios.checks.fog_loop",
    "gyrobench.scenarios.checks.coil",
    "gyrobench.scenarios.checks.mems_nonlinear",
    "gyrobench.scenarios.checks.mount_coning",
    "gyrobench.scenarios.checks.fog_strain",
    "gyrobench.scenarios.checks.shaker",
    "gyrobench.scenarios.checks.trajectory",
)


def _magnitude(check: Check) -> float:
    """The check's reference magnitude: ``|scale|``, or ``|expected|`` without a scale."""
    return abs(check.expected) if check.scale is None else abs(check.scale)


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
    reference : str
        Where ``expected`` comes from outside the code: a book, paper, standard or datasheet
        (with the chapter, section or equation where one is printed), or, for a check whose
        point is that two methods agree, ``"second method: ..."`` naming the independent
        method and its source. Never only a module of this package.
    kind : str
        The reference's kind, one of :data:`KINDS`: ``"closed form"`` (derived independently
        of the model's code), ``"second method"`` (full integration, exact kinematics, a
        first-principles simulation), ``"printed"`` (a published number, its source in
        ``reference``) or ``"consistency"`` (the code against its own formula reached by another
        path: a regression guard, not validation; :data:`VALIDATION_KINDS` are the others).
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
    reference: str
    kind: str
    scale: float | None = None

    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "kind is one of KINDS",
            lambda c: c.kind in KINDS,
            lambda c: f"kind must be one of {KINDS}; got {c.kind!r} (check {c.id!r})",
        ),
        Constraint(
            "reference is a non-empty string",
            lambda c: isinstance(c.reference, str) and bool(c.reference.strip()),
            lambda c: f"reference must be a non-empty string; got {c.reference!r} (check {c.id!r})",
        ),
        Constraint(
            "tolerance finite and > 0",
            lambda c: math.isfinite(c.tolerance) and c.tolerance > 0,
            lambda c: f"tolerance must be finite and > 0; got {c.tolerance!r} (check {c.id!r})",
        ),
        Constraint(
            "a finite non-zero reference magnitude",
            lambda c: math.isfinite(_magnitude(c)) and _magnitude(c) > 0,
            lambda c: "expected or scale must give a finite non-zero reference magnitude; "
            f"got expected={c.expected!r}, scale={c.scale!r} (check {c.id!r})",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared constraints above

    @property
    def rel_error(self) -> float:
        """``|simulated - expected| / reference`` (reference: ``scale`` or ``|expected|``)."""
        return abs(self.simulated - self.expected) / _magnitude(self)

    @property
    def validates(self) -> bool:
        """True when the reference is outside the code (kind in :data:`VALIDATION_KINDS`)."""
        return self.kind in VALIDATION_KINDS

    @property
    def passed(self) -> bool:
        """True when the relative error is within the tolerance (a NaN never passes)."""
        return bool(self.rel_error <= self.tolerance)

    def as_dict(self) -> dict[str, object]:
        """The results.json form: id, kind, formula, expected, simulated, rel_error, tolerance,
        its derivation, reference, passed."""
        return {
            "id": self.id,
            "kind": self.kind,
            "formula": self.formula,
            "expected": self.expected,
            "simulated": self.simulated,
            "rel_error": self.rel_error,
            "tolerance": self.tolerance,
            "tolerance_derivation": self.derivation,
            "reference": self.reference,
            "passed": self.passed,
        }


@dataclass(frozen=True, slots=True)
class Part:
    """One independent piece of a check module: ``func(*args)`` returns a Check or a list.

    ``func`` is a module-level function and ``args`` picklable (a part may run on a worker
    process); ``label`` names it in the progress bar.

    Attributes
    ----------
    label : str
        The part's name in the progress bar.
    func : callable
        A module-level function returning a Check or a list of them.
    args : tuple
        Its (picklable) arguments.
    """

    label: str
    func: Callable[..., Any]
    args: tuple[Any, ...] = ()

    def run(self) -> list[Check]:
        """The part's checks, as a list."""
        out = self.func(*self.args)
        return [out] if isinstance(out, Check) else list(out)


def kind_counts(checks: Sequence[Check]) -> dict[str, int]:
    """The number of checks of each reference kind, every kind of :data:`KINDS` in order.

    Parameters
    ----------
    checks : sequence of Check
        Checks.

    Returns
    -------
    dict of str to int
        Kind -> count.
    """
    return {k: sum(c.kind == k for c in checks) for k in KINDS}


def run_parts(parts: Sequence[Part]) -> list[Check]:
    """Every part's checks, in order (what a module's ``checks(rng)`` returns).

    Parameters
    ----------
    parts : sequence of Part
        A module's parts.

    Returns
    -------
    list of Check
        Their checks.
    """
    return [c for p in parts for c in p.run()]


def _run_part(part: Part) -> list[Check]:
    """Module level, so it pickles to a worker process."""
    return part.run()


def _module_checks(name: str, rng: np.random.Generator) -> list[Check]:
    """One module's checks (module level, so it pickles to a worker process)."""
    return list(importlib.import_module(name).checks(rng))


def _plan(rng: np.random.Generator, modules: tuple[str, ...]) -> list[tuple[str, Part]]:
    """(module, part) in report order: one child stream per module, split by its ``parts``."""
    out: list[tuple[str, Part]] = []
    for name, child in zip(modules, rng.spawn(len(modules)), strict=True):
        mod = importlib.import_module(name)
        if hasattr(mod, "parts"):
            out.extend((name, p) for p in mod.parts(child))
        else:
            out.append((name, Part(name.rsplit(".", 1)[-1], _module_checks, (name, child))))
    return out


def collect(
    rng: np.random.Generator,
    modules: tuple[str, ...] = CHECK_MODULES,
    *,
    executor: Executor | None = None,
    on_plan: Callable[[int], None] | None = None,
    on_part_done: Callable[[str, list[Check]], None] | None = None,
) -> list[Check]:
    """Run every check module's checks with its own child stream of ``rng``.

    Each module gets one spawned child generator, in the order of ``modules``, so adding a
    module at the end changes no earlier module's numbers, and the results are the same
    whether the modules run here or on ``executor`` (e.g. a process pool), in any order. A
    module with ``parts`` is run part by part (its parts draw from its child stream exactly as
    its ``checks`` does). ``on_plan(n)`` is called first with the number of parts;
    ``on_part_done(label, checks)`` as each part finishes (in completion order on an
    executor), e.g. to move a progress bar; the label is the module's short name, with the
    part's after a dot for a module with parts.

    Parameters
    ----------
    rng : numpy.random.Generator
        The stream split among the modules.
    modules : tuple of str
        The check modules, in order.
    executor : concurrent.futures.Executor or None
        Where the parts run (None: here).
    on_plan : callable or None
        Called with the number of parts before any runs.
    on_part_done : callable or None
        Called with (part name, its checks) as each part finishes.

    Returns
    -------
    list of Check
        Every check, in module order.
    """
    plan = _plan(rng, modules)
    if on_plan is not None:
        on_plan(len(plan))

    def label(name: str, part: Part) -> str:
        short = name.rsplit(".", 1)[-1]
        return short if part.label == short else f"{short}.{part.label}"

    if executor is None:
        per_part = []
        for n, p in plan:
            per_part.append(p.run())
            if on_part_done is not None:
                on_part_done(label(n, p), per_part[-1])
    else:
        from concurrent.futures import as_completed

        futures = {executor.submit(_run_part, p): label(n, p) for n, p in plan}
        if on_part_done is not None:
            for f in as_completed(futures):
                on_part_done(futures[f], f.result())
        per_part = [f.result() for f in futures]
    out: list[Check] = [c for checks in per_part for c in checks]
    ids = [c.id for c in out]
    dup = sorted({i for i in ids if ids.count(i) > 1})
    if dup:
        raise ValueError(f"check ids must be unique; repeated: {dup}")
    return out
