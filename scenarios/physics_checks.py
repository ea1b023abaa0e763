"""Closed-form checks of every sensor model, in the report.

Runs :func:`gyrobench.scenarios.checks.core.collect` over the check modules
(:data:`gyrobench.scenarios.checks.core.CHECK_MODULES`: noise AVAR per IEEE-952 term,
Sagnac scale factor, Shupe cancellation, Adler beat frequency, dither random walk,
and whatever the sensor modules add) and reports each check: its formula, the
closed form's value, the model's value, the relative error, and the tolerance with
its derivation, and the kind of its reference (closed form, second method, printed, or
consistency: the code against its own formula, listed but not counted as validation), with the
count of each kind. A failed check is a model bug (or a one-in-a-million false alarm of a
statistical check: each states its false-alarm rate).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from gyrobench.base.ranges import Constraint, FieldChoice, validate
from gyrobench.scenarios.base import Headline, Outcome, Table
from gyrobench.scenarios.checks.core import CHECK_MODULES, KINDS, VALIDATION_KINDS, Check, collect, kind_counts

NAME = "physics_checks"
TITLE = (
    "Physics checks of the sensor models (noise, FOG loop and coil, MEMS resonator, RLG): "
    "simulated beside closed forms, second methods and printed numbers"
)

__all__ = ["NAME", "TITLE", "Config", "simulate", "run_checks", "report", "run"]


@dataclass(frozen=True, slots=True, kw_only=True)
class Config:
    """Which check modules run (default: all of :data:`CHECK_MODULES`, in order).

    Parameters
    ----------
    modules : tuple of str
        The check modules' dotted names.
    """

    modules: tuple[str, ...] = CHECK_MODULES

    #: the declared spec: a config never imports by a name it chose, only the fixed registry
    RANGES: ClassVar[Mapping[str, FieldChoice]] = {
        "modules": FieldChoice(CHECK_MODULES, "the check modules that run"),
    }
    #: the constraints across fields (:class:`~gyrobench.base.ranges.Constraint`)
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "modules is a non-empty tuple",
            lambda c: isinstance(c.modules, tuple) and len(c.modules) > 0,
            lambda c: f"modules must name at least one check module; got {c.modules!r}",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared spec and constraint above

def simulate(config: Config, seed: int) -> list:
    """The checks keep no recordings (each simulates short records internally).

    Parameters
    ----------
    config : Config
        The checks run.
    seed : int
        Unused.

    Returns
    -------
    list
        Empty.
    """
    return []


def run_checks(config: Config, seed: int, *, workers: int = 0, progress: bool = False) -> list[Check]:
    """Every check of ``config.modules``, drawing from ``numpy.random.default_rng(seed)``.

    ``workers`` > 0 runs the modules' parts on that many local processes (the same numbers:
    each module draws from its own child stream, split among its parts as its ``checks``
    splits it). ``progress`` shows a tqdm bar on stderr that moves as each part (a module, or
    one check or group of a module with ``parts``) finishes, with its passed/total.

    Parameters
    ----------
    config : Config
        The checks run.
    seed : int
        Seed of the generator split among the modules.
    workers : int
        Local processes (0: in this one).
    progress : bool
        Show a progress bar.

    Returns
    -------
    list of Check
        Every check.
    """
    rng = np.random.default_rng(seed)
    bar = None
    planned: Callable[[int], None] | None = None
    done: Callable[[str, list[Check]], None] | None = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=len(config.modules), desc=NAME, unit="part", leave=False, mininterval=0)

        def planned(n: int) -> None:
            bar.reset(total=n)

        def done(name: str, checks: list[Check]) -> None:
            bar.set_postfix_str(f"{name}: {sum(c.passed for c in checks)}/{len(checks)} passed")
            bar.update(1)

    try:
        if workers <= 1:  # a pool of one only adds its start-up
            return collect(rng, config.modules, on_plan=planned, on_part_done=done)
        from concurrent.futures import ProcessPoolExecutor

        with ProcessPoolExecutor(max_workers=workers) as pool:
            return collect(rng, config.modules, executor=pool, on_plan=planned, on_part_done=done)
    finally:
        if bar is not None:
            bar.close()


def report(config: Config, seed: int, checks: list[Check], runtime_s: float) -> Outcome:
    """The checks as a table, a headline (passed / all) and ``results["checks"]``.

    Parameters
    ----------
    config : Config
        The checks run.
    seed : int
        Their seed.
    checks : list of Check
        Their results.
    runtime_s : float
        Run time [s].

    Returns
    -------
    Outcome
        The report's outcome.
    """
    rows = [
        [
            c.id,
            c.kind,
            c.formula,
            c.expected,
            c.simulated,
            c.rel_error,
            c.tolerance,
            "yes" if c.passed else "NO",
            c.derivation,
            c.reference,
        ]
        for c in checks
    ]
    failed = [c.id for c in checks if not c.passed]
    n_ok = len(checks) - len(failed)
    counts = kind_counts(checks)
    n_valid = sum(counts[k] for k in VALIDATION_KINDS)
    counts_text = ", ".join(f"{counts[k]} {k}" for k in KINDS)
    kinds_table = Table(
        "Reference kinds: what each check's expected value comes from",
        ["reference kind", "checks", "passed", "counted as validation"],
        [
            [k, counts[k], sum(c.passed for c in checks if c.kind == k), "yes" if k in VALIDATION_KINDS else "no"]
            for k in KINDS
        ],
        note="closed form: an equation derived independently of the model's code; second method: full "
        "integration, exact kinematics or a first-principles simulation; printed: a published number "
        "(source in 'expected value from'); consistency: the code against its own formula reached by "
        "another path, a regression guard and not validation.",
    )
    table = Table(
        "Physics checks: the model's value beside its reference's",
        [
            "check",
            "reference kind",
            "formula",
            "expected",
            "simulated",
            "rel. error",
            "tolerance",
            "passed",
            "tolerance from",
            "expected value from",
        ],
        rows,
        note="rel. error = |simulated - expected| / reference (|expected|, or the stated scale "
        "for a cancellation); "
        "statistical tolerances are chi-square bands at the stated false-alarm rate; "
        "'expected value from' is the outside source of the closed form (book, paper, standard, "
        "datasheet) or the independent second method it is compared with.",
    )
    return Outcome(
        scenario=NAME,
        title=TITLE,
        seed=seed,
        config=config,
        results={"checks": [c.as_dict() for c in checks], "kind_counts": counts},
        tables=[kinds_table, table],
        headlines=[
            Headline(
                "physics checks passed",
                f"{n_ok}/{len(checks)}",
                f"{len(checks)}/{len(checks)}",
                not failed,
                "failed: " + ", ".join(failed) if failed else "every model matches its equations",
            ),
            Headline(
                "checks with an outside reference (validation)",
                f"{n_valid}/{len(checks)}",
                "",
                None,
                counts_text,
            ),
        ],
        conclusion=(
            f"{n_ok} of {len(checks)} checks pass; by reference kind: {counts_text} "
            f"({n_valid} count as validation, the {counts['consistency']} consistency checks do not)."
            + (f" FAILED: {', '.join(failed)}." if failed else "")
        ),
        runtime_s=runtime_s,
    )


def run(config: Config, seed: int, *, progress: bool = False) -> Outcome:
    """Run every check and build the report.

    Parameters
    ----------
    config : Config
        The checks run.
    seed : int
        Their seed.
    progress : bool
        Show a progress bar.

    Returns
    -------
    Outcome
        The report's outcome.
    """
    import os

    t0 = time.perf_counter()
    checks = run_checks(config, seed, workers=len(os.sched_getaffinity(0)), progress=progress)
    return report(config, seed, checks, time.perf_counter() - t0)
