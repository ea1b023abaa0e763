"""Closed-form checks of every sensor model, in the report.

Runs :func:`gyrobench.scenarios.checks.core.collect` over the check modules
(:data:`gyrobench.scenarios.checks.core.CHECK_MODULES`: noise AVAR per IEEE-952 term,
Sagnac scale factor, Shupe cancellation, Adler beat frequency, dither random walk,
and whatever the sensor modules add) and reports each check: its formula, the
closed form's value, the model's value, the relative error, and the tolerance with
its derivation. A failed check is a model bug (or a one-in-a-million false alarm of
a statistical check: each states its false-alarm rate).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from gyrobench.scenarios.base import Headline, Outcome, Table
from gyrobench.scenarios.checks.core import CHECK_MODULES, Check, collect

NAME = "physics_checks"
TITLE = (
    "Closed-form checks of the sensor models (noise, FOG loop and coil, MEMS resonator, RLG): "
    "simulated beside the equations"
)

__all__ = ["NAME", "TITLE", "Config", "simulate", "run_checks", "report", "run"]


@dataclass(frozen=True, slots=True, kw_only=True)
class Config:
    """Which check modules run (default: all of :data:`CHECK_MODULES`, in order)."""

    modules: tuple[str, ...] = CHECK_MODULES

    def __post_init__(self) -> None:
        if not isinstance(self.modules, tuple) or not all(isinstance(m, str) for m in self.modules):
            raise TypeError(f"Config.modules must be a tuple of module names; got {self.modules!r}")
        if not self.modules:
            raise ValueError("Config.modules must name at least one check module; got ()")
        unknown = [m for m in self.modules if m not in CHECK_MODULES]
        if unknown:  # a config never imports by a name it chose: only the fixed registry (issue 32)
            raise ValueError(
                f"Config.modules must be among the check modules {', '.join(CHECK_MODULES)}; got {unknown[0]!r}"
            )


def simulate(config: Config, seed: int) -> list:
    """The checks keep no recordings (each simulates short records internally)."""
    return []


def run_checks(config: Config, seed: int, *, workers: int = 0, progress: bool = False) -> list[Check]:
    """Every check of ``config.modules``, drawing from ``numpy.random.default_rng(seed)``.

    ``workers`` > 0 runs the modules' parts on that many local processes (the same numbers:
    each module draws from its own child stream, split among its parts as its ``checks``
    splits it). ``progress`` shows a tqdm bar on stderr that moves as each part (a module, or
    one check or group of a module with ``parts``) finishes, with its passed/total.
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
    """The checks as a table, a headline (passed / all) and ``results["checks"]``."""
    rows = [
        [
            c.id,
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
    table = Table(
        "Closed-form checks: the model's value beside the equation's",
        [
            "check",
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
        results={"checks": [c.as_dict() for c in checks]},
        tables=[table],
        headlines=[
            Headline(
                "closed-form checks passed",
                f"{n_ok}/{len(checks)}",
                f"{len(checks)}/{len(checks)}",
                not failed,
                "failed: " + ", ".join(failed) if failed else "every model matches its equations",
            )
        ],
        conclusion=(
            f"{n_ok} of {len(checks)} closed-form checks pass."
            + (f" FAILED: {', '.join(failed)}." if failed else "")
        ),
        runtime_s=runtime_s,
    )


def run(config: Config, seed: int, *, progress: bool = False) -> Outcome:
    """Run every check and build the report."""
    import os

    t0 = time.perf_counter()
    checks = run_checks(config, seed, workers=len(os.sched_getaffinity(0)), progress=progress)
    return report(config, seed, checks, time.perf_counter() - t0)
