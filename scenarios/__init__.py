"""The papers' experiments, the closed-form physics checks, the runner, the ``gyrobench`` command
line, the reports and the bench.

This package exports its contract only: what a scenario returns (:class:`Outcome` with its
tables, figures and headline numbers; :class:`CompensationTask` for the bench), what a paper
states (:class:`Claim`, :class:`Deviation`, judged by :func:`evaluate` into
:class:`ClaimResult`), what a paper package is (:class:`PaperScenario`), and the bench's two
entry points (:func:`run_campaign`, :func:`format_summary`). Names load on first use.

Subpackages
-----------
papers
    one package per paper (config, device, experiment, claims, report), each exporting the
    :class:`PaperScenario` contract.
checks
    the closed-form physics checks of the sensor models (``physics_checks``).
runner
    executors, the unit store and the paper-unit runner.
bench
    scoring a compensator over many seeds, the regression gate.
cli
    one module per ``gyrobench`` verb.
reports
    the paper reports, the Allan report, the README summary and docs/results.md table.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from gyrobench.base.lazy import attach

#: public name -> the submodule that defines it (imported on first access, so importing
#: this package costs nothing until a name is used)
_LAZY: dict[str, str] = {
    "Outcome": "gyrobench.scenarios.base",
    "Table": "gyrobench.scenarios.base",
    "FigureSpec": "gyrobench.scenarios.base",
    "Headline": "gyrobench.scenarios.base",
    "CompensationTask": "gyrobench.scenarios.base",
    "HeldOutRun": "gyrobench.scenarios.base",
    "Claim": "gyrobench.scenarios.claims",
    "Deviation": "gyrobench.scenarios.claims",
    "Comparator": "gyrobench.scenarios.claims",
    "Precondition": "gyrobench.scenarios.claims",
    "ClaimResult": "gyrobench.scenarios.claims",
    "evaluate": "gyrobench.scenarios.claims",
    "PaperScenario": "gyrobench.scenarios.papers.contract",
    "run_campaign": "gyrobench.scenarios.bench",
    "format_summary": "gyrobench.scenarios.bench",
}

__all__ = [
    "Outcome",
    "Table",
    "FigureSpec",
    "Headline",
    "CompensationTask",
    "HeldOutRun",
    "Claim",
    "Deviation",
    "Comparator",
    "Precondition",
    "ClaimResult",
    "evaluate",
    "PaperScenario",
    "run_campaign",
    "format_summary",
]

if TYPE_CHECKING:  # pragma: no cover - for type checkers and IDEs only
    from gyrobench.scenarios.base import CompensationTask as CompensationTask
    from gyrobench.scenarios.base import FigureSpec as FigureSpec
    from gyrobench.scenarios.base import Headline as Headline
    from gyrobench.scenarios.base import HeldOutRun as HeldOutRun
    from gyrobench.scenarios.base import Outcome as Outcome
    from gyrobench.scenarios.base import Table as Table
    from gyrobench.scenarios.bench import format_summary as format_summary
    from gyrobench.scenarios.bench import run_campaign as run_campaign
    from gyrobench.scenarios.claims import Claim as Claim
    from gyrobench.scenarios.claims import ClaimResult as ClaimResult
    from gyrobench.scenarios.claims import Comparator as Comparator
    from gyrobench.scenarios.claims import Deviation as Deviation
    from gyrobench.scenarios.claims import Precondition as Precondition
    from gyrobench.scenarios.claims import evaluate as evaluate
    from gyrobench.scenarios.papers.contract import PaperScenario as PaperScenario


__getattr__, __dir__ = attach(__name__, _LAZY)
