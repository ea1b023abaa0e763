"""Contracts shared by every scenario, the report writer and the bench.

A scenario is a module (registered in :mod:`gyrobench.scenarios.registry`) that defines

``NAME`` : str
    registry key, e.g. ``"mems_scale_factor"``.
``TITLE`` : str
    one line for ``gyrobench list`` and the report.
``Config`` : frozen dataclass
    every parameter with the paper's setup as default (field units allowed here,
    at the edge, with the unit in the field name or docstring).
``simulate(config, seed) -> list[Recording]``
    every recording the experiment produces, with truth (``gyrobench simulate``).

A **paper scenario** also sets ``PAPER`` (a key of :mod:`gyrobench.scenarios.papers`) and
defines, instead of ``run``:

``experiment(config, seed) -> dict``
    one simulated unit (each seed is another unit) through the whole pipeline; its
    ``"quantities"`` hold one number per claim (None where the unit cannot test it).
``CLAIMS`` : tuple of :class:`gyrobench.scenarios.claims.Claim`
    every checkable statement of the paper, calibrated or emergent, with its comparator.
``DEVIATIONS`` : tuple of :class:`gyrobench.scenarios.claims.Deviation`
    departures from the paper's stated protocol, with reason and measured effect.
``report(config, units, claims) -> Outcome``
    tables and figures from the units' results (formatting only).

:func:`gyrobench.scenarios.runner.units.run_paper` runs the units (resumable, on local processes
or a dask.distributed cluster), judges the claims over them and calls ``report``. Other
scenarios (``static_noise``, ``physics_checks``) define

``run(config, seed, *, progress=False) -> Outcome``
    simulate, analyse, and return tables, figures and headline numbers.

and, when it has a compensation stage (for ``gyrobench bench``),

``compensation_task(config, seed) -> CompensationTask``
    features and targets of the training run and the held-out runs.

Figures are matplotlib figures drawn with the Agg backend; the report writer
saves them as PNG and embeds them in a self-contained HTML page.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from gyrobench.base.ranges import Constraint, FieldChoice, FieldRange, check_ranges, field_range, range_error, validate

__all__ = [
    "Table",
    "FigureSpec",
    "Headline",
    "Outcome",
    "HeldOutRun",
    "CompensationTask",
    "FieldRange",
    "check_ranges",
    "field_range",
    "range_error",
    "mse_scores",
]


def _short_rows(table: Table) -> list[int]:
    """The indices of the rows whose cell count is not the column count."""
    return [i for i, r in enumerate(table.rows) if len(r) != len(table.columns)]


def _labels_ok(task: CompensationTask) -> bool:
    """Whether the task's training groups are None or one integer label per training row."""
    g = task.groups_train
    return g is None or (
        np.ndim(g) == 1 and len(g) == len(task.X_train) and np.issubdtype(np.asarray(g).dtype, np.integer)
    )


@dataclass(frozen=True)
class Table:
    """A report table. Cells are numbers or strings; numbers are formatted by the writer.

    Parameters
    ----------
    title : str
        E.g. ``"Table 1. Allan coefficients of the three phases"``.
    columns : sequence of str
        Header cells, units in brackets: ``"N [deg/sqrt(h)]"``.
    rows : sequence of sequence
        Body cells.
    note : str
        Text printed under the table (targets, caveats).
    """

    title: str
    columns: Sequence[str]
    rows: Sequence[Sequence[Any]]
    note: str = ""

    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "every row has one cell per column",
            lambda c: not _short_rows(c),
            lambda c: f"rows must each have {len(c.columns)} cells (one per column); rows {_short_rows(c)} of "
            f"table {c.title!r} do not",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared constraint above


@dataclass(frozen=True)
class FigureSpec:
    """A figure of the report: ``name`` (file stem), caption, and the matplotlib Figure.

    Attributes
    ----------
    name : str
        File stem of the figure in the report.
    caption : str
        Its caption.
    figure : matplotlib.figure.Figure
        The figure.
    """

    name: str
    caption: str
    figure: Any  # matplotlib.figure.Figure


@dataclass(frozen=True)
class Headline:
    """One headline number for the summary table: the reproduced value beside the paper's.

    ``holds`` says whether the paper's conclusion holds in the simulation (None when
    the number has no pass/fail meaning).

    Attributes
    ----------
    quantity : str
        What is compared.
    reproduced : str
        Our value, formatted with its unit.
    target : str
        The paper's value, formatted.
    holds : bool or None
        Whether the paper's conclusion holds here.
    note : str
        A remark for the table.
    """

    quantity: str
    reproduced: str
    target: str
    holds: bool | None = None
    note: str = ""


@dataclass
class Outcome:
    """What ``run`` returns: machine-readable results, tables, figures, headline numbers.

    Attributes
    ----------
    scenario : str
        The scenario's registry name.
    title : str
        Its one-line title.
    seed : int
        The seed (of the first unit, for a paper).
    config : object
        The configuration run.
    results : dict
        Machine-readable results (written to results.json).
    tables : list of Table
        The report's tables.
    figures : list of FigureSpec
        The report's figures.
    headlines : list of Headline
        The summary's headline numbers.
    conclusion : str
        One paragraph for the report.
    runtime_s : float
        Wall time of the run [s].
    claims : list of ClaimResult
        The paper's judged claims (papers only).
    deviations : list of Deviation
        Its protocol deviations (papers only).
    units : int
        Units the claims were judged over.
    deviation_effects : list of DeviationEffect
        Measured effects of the deviations (``reproduce --deviations``).
    """

    scenario: str
    title: str
    seed: int
    config: Any
    results: dict[str, Any]
    tables: list[Table] = field(default_factory=list)
    figures: list[FigureSpec] = field(default_factory=list)
    headlines: list[Headline] = field(default_factory=list)
    conclusion: str = ""
    runtime_s: float = math.nan
    #: paper scenarios: the claims judged over units (scenarios.claims.ClaimResult), the
    #: protocol deviations (scenarios.claims.Deviation) and how many units were simulated
    claims: list[Any] = field(default_factory=list)
    deviations: list[Any] = field(default_factory=list)
    units: int = 1
    #: paper scenarios run with ``reproduce --deviations``: each deviation's measured effect
    #: (scenarios.claims.DeviationEffect); empty when the effects were not measured in this run
    deviation_effects: list[Any] = field(default_factory=list)


@dataclass(frozen=True)
class HeldOutRun:
    """One run the compensator never saw during fitting.

    Parameters
    ----------
    label : str
        Short name used in score keys (``"val1_run3"``).
    X : ndarray, shape (n, n_features)
        Features computed from what the test logs.
    output : ndarray, shape (n,)
        What the gyro reported, in the scenario's report unit.
    truth : ndarray, shape (n,)
        The true quantity the compensated output should equal (same unit).
    """

    label: str
    X: NDArray[np.float64]
    output: NDArray[np.float64]
    truth: NDArray[np.float64]


def mse_scores(compensated: NDArray[np.float64], run: HeldOutRun) -> dict[str, float]:
    """Default scorer: mean squared and RMS error of the compensated output against truth.

    Parameters
    ----------
    compensated : ndarray
        The compensated output of one held-out run (the run's unit).
    run : HeldOutRun
        The run, with its truth.

    Returns
    -------
    dict of str to float
        ``{"mse": ..., "rms": ...}`` in the run's unit squared and the run's unit.
    """
    err = np.asarray(compensated, float) - run.truth
    mse = float(np.mean(err**2))
    return {"mse": mse, "rms": math.sqrt(mse)}


@dataclass(frozen=True)
class CompensationTask:
    """What a scenario hands the bench: a training set and held-out runs with truth.

    ``target`` says how a fitted regressor's prediction is used:

    ``"error"``
        the regressor predicts the output's error; compensated = output - prediction.
    ``"rate"``
        the regressor predicts the true quantity directly; compensated = prediction.

    ``scorer(compensated, run) -> dict`` must be a module-level function (so it
    pickles to worker processes); scores are named ``"<run.label>/<key>"`` by the
    bench, and averaged over runs as ``"mean/<key>"``.

    ``groups_train`` (optional, shape ``(n,)``, integers): a group label per training row,
    e.g. the thermal segment of the chamber program a row was logged in, for methods that
    select their settings by leave-one-group-out cross-validation. The bench passes it the
    scikit-learn way, as ``fit(X, y, groups=groups_train)``, only to a compensator whose
    ``fit`` (or fit function) names a ``groups`` parameter, or to a scikit-learn search
    (``GridSearchCV`` and the like, which route it to their ``cv`` splitter); every other
    compensator gets ``fit(X, y)``. None: the task has no groups.

    Attributes
    ----------
    scenario : str
        The scenario's registry name.
    feature_names : tuple of str
        Names of the columns of ``X_train`` (and of each held-out run's features).
    X_train : ndarray, shape (n, n_features)
        Training features.
    y_train : ndarray, shape (n,)
        Training target (in ``unit``).
    heldout : tuple of HeldOutRun
        The held-out runs, with truth.
    target : {"error", "rate"}
        How a prediction is used (above).
    unit : str
        Unit of the target and of the compensated output.
    scorer : callable
        ``scorer(compensated, run) -> dict`` of scores (module-level, so it pickles).
    groups_train : ndarray of int, optional
        Group label per training row (above).
    """

    scenario: str
    feature_names: tuple[str, ...]
    X_train: NDArray[np.float64]
    y_train: NDArray[np.float64]
    heldout: tuple[HeldOutRun, ...]
    target: str = "error"
    unit: str = ""
    scorer: Callable[[NDArray[np.float64], HeldOutRun], Mapping[str, float]] = mse_scores
    groups_train: NDArray[np.int_] | None = None

    RANGES: ClassVar[Mapping[str, FieldChoice]] = {
        "target": FieldChoice(("error", "rate"), "what the regressor predicts"),
    }
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "X_train is (n, number of features)",
            lambda c: np.ndim(c.X_train) == 2 and np.shape(c.X_train)[1] == len(c.feature_names),
            lambda c: f"X_train must have shape (n, {len(c.feature_names)}); got {np.shape(c.X_train)}",
        ),
        Constraint(
            "groups_train: None or one integer label per training row",
            _labels_ok,
            lambda c: f"groups_train must be None or {len(c.X_train)} integer labels (one per training row); "
            f"got shape {np.shape(c.groups_train)}, dtype {np.asarray(c.groups_train).dtype}",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above

    def compensate(self, prediction: NDArray[np.float64], run: HeldOutRun) -> NDArray[np.float64]:
        """Turn a regressor's prediction on ``run.X`` into the compensated output."""
        prediction = np.asarray(prediction, float).reshape(-1)
        return run.output - prediction if self.target == "error" else prediction


def check_pool(executor: Any, workers: Any) -> None:
    """Refuse a bad ``workers``/``executor`` pair of a unit or seed runner in one line.

    ``workers``: None or an integer >= 0 (0: in-process); ``executor``: None or a
    :class:`concurrent.futures.Executor`; not both.
    """
    import concurrent.futures as cf

    if workers is not None and (
        isinstance(workers, bool) or not isinstance(workers, int) or workers < 0
    ):
        raise ValueError(f"workers must be an integer >= 0; got {workers!r}")
    if executor is not None and not isinstance(executor, cf.Executor):
        raise TypeError(
            f"executor must be a concurrent.futures.Executor; got {type(executor).__name__}"
        )
    if executor is not None and workers is not None:
        raise ValueError("give either executor or workers, not both")
