"""Primary scores: the few scores of each bench scenario a regression is judged on.

A scenario's compensation task reports many scores (every held-out run's and their
``mean/``); testing all of them under a multiple-comparison correction asks for more seeds
than a user can afford (with ``m`` scores the smallest attainable Holm-adjusted p of the
signed-rank test on ``n`` seeds is ``m * 2 / 2**n``). So each bench scenario declares here,
on the bench side, a small set of *primary* scores with their unit and direction: the gate
(:func:`~gyrobench.scenarios.bench.compare`'s verdict, the exit status) reads only those;
the others are *secondary*: tested and reported, never gated.

Primary scores are ``mean/`` scores (the mean over the held-out runs), so they are held by
every seed whatever the runs are called (rlg_thermal's run is named after the unit).

A scenario declares them as ``BENCH_SCORES`` (a :class:`ScenarioScores`) in its own module: a
paper in its package (``papers/p<key>_<scenario>/bench.py``). A scenario that declares none (a
user's own, or the tests' toy scenario) gates on every ``mean/`` score whose direction
:func:`score_direction` knows.

The declaration also names the *paper's method* as a bench compensator (``"module:attr"``,
defined in the paper's package), printed beside the user's compensator with the uncompensated
output (:mod:`gyrobench.scenarios.bench.references`).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from types import ModuleType
from typing import ClassVar

from gyrobench.base.ranges import Constraint, validate
from gyrobench.scenarios.bench.statistics import score_direction

__all__ = [
    "PrimaryScore",
    "ScenarioScores",
    "declared_scores",
    "directions_of",
    "gated_scores",
    "primary_count",
    "scenario_scores",
    "score_unit",
]


@dataclass(frozen=True, slots=True, kw_only=True)
class PrimaryScore:
    """One gated score: its name in the campaign, unit and which way is better.

    ``direction`` is -1 (lower is better) or +1 (higher is better).

    Attributes
    ----------
    name : str
        Its name in the campaign.
    unit : str
        Its unit.
    direction : int
        -1 (lower is better) or +1 (higher is better).
    meaning : str
        What it measures.
    """

    name: str
    unit: str
    direction: int
    meaning: str = ""

    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "direction is -1 or +1",
            lambda c: c.direction in (-1, 1) and not isinstance(c.direction, bool),
            lambda c: f"direction must be -1 or +1; got {c.direction!r}",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared constraint above


@dataclass(frozen=True, slots=True, kw_only=True)
class ScenarioScores:
    """What the bench knows of one scenario's scores.

    ``units`` maps a score's last path component (``"mse"``) to its unit; ``paper`` is the
    paper's method as a ``"module:attr"`` compensator and ``paper_label`` its short name.

    Attributes
    ----------
    primary : tuple of PrimaryScore
        The gated scores.
    units : mapping of str to str
        A score's last path component -> its unit.
    paper : str
        The paper's method (``"module:attr"``).
    paper_label : str
        Its label.
    """

    primary: tuple[PrimaryScore, ...]
    units: Mapping[str, str]
    paper: str = ""
    paper_label: str = ""


def scenario_scores(scenario: str | ModuleType) -> ScenarioScores | None:
    """The declared scores of a scenario.

    The declared scores of ``scenario`` (a name, a module path or a module): its module's
    ``BENCH_SCORES``, or None if it declares none or has no compensation stage.

    Parameters
    ----------
    scenario : str or module
        The scenario.

    Returns
    -------
    ScenarioScores or None
        Its ``BENCH_SCORES``.
    """
    from gyrobench.scenarios.bench.scoring import resolve_scenario

    try:
        module = resolve_scenario(scenario)
    except ValueError:
        return None
    declared = getattr(module, "BENCH_SCORES", None)
    return declared if isinstance(declared, ScenarioScores) else None


def declared_scores() -> dict[str, ScenarioScores]:
    """name -> declared scores of every scenario with a compensation stage that declares them.

    Returns
    -------
    dict of str to ScenarioScores
        Scenario name -> its declared scores.
    """
    from gyrobench.scenarios.bench.scoring import bench_scenarios

    out = {}
    for name in bench_scenarios():
        declared = scenario_scores(name)
        if declared is not None:
            out[name] = declared
    return out


def primary_count(scenario: str | ModuleType, names: Iterable[str] | None = None) -> int | None:
    """How many scores the gate tests for a scenario.

    How many scores the gate tests for ``scenario``: its declared primary scores, else the
    directional ``mean/`` scores among ``names``; None if neither is known (no names given).

    Parameters
    ----------
    scenario : str or module
        The scenario.
    names : iterable of str or None
        The scores' names.

    Returns
    -------
    int or None
        The count (None: not known).
    """
    declared = scenario_scores(scenario)
    if declared is not None:
        return len(declared.primary)
    if names is None:
        return None
    return len(gated_scores(scenario, names))


def gated_scores(scenario: str | ModuleType, names: Iterable[str]) -> tuple[PrimaryScore, ...]:
    """The primary scores of a scenario, declared or inferred from the score names.

    The primary scores of ``scenario`` (declared, or every ``mean/`` score of ``names`` with
    a known direction when the scenario declares none).

    Parameters
    ----------
    scenario : str or module
        The scenario.
    names : iterable of str
        The compared scores' names.

    Returns
    -------
    tuple of PrimaryScore
        The declared ones, or every ``mean/`` score with a known direction.
    """
    declared = scenario_scores(scenario)
    if declared is not None:
        return declared.primary
    out = []
    for n in sorted(names):
        d = score_direction(n)
        if n.startswith("mean/") and d != 0:
            out.append(PrimaryScore(name=n, unit=score_unit(scenario, n), direction=d))
    return tuple(out)


def score_unit(scenario: str | ModuleType, name: str) -> str:
    """The unit of score ``name`` of ``scenario`` (``""`` when not known).

    Declared units first (by the name's last path component), then the suffix of the name:
    ``_pct`` is %, ``_deg_h`` deg/h, ``_dps`` deg/s.

    Parameters
    ----------
    scenario : str or module
        The scenario.
    name : str
        The score's name.

    Returns
    -------
    str
        Its unit (``""`` when not known).
    """
    key = name.rsplit("/", 1)[-1]
    declared = scenario_scores(scenario)
    if declared is not None and key in declared.units:
        return declared.units[key]
    for suffix, unit in (("_pct", "%"), ("_deg_h", "deg/h"), ("_dps", "deg/s")):
        if key.endswith(suffix):
            return unit
    return ""


def directions_of(primary: Iterable[PrimaryScore]) -> Mapping[str, int]:
    """``{name: direction}`` of the primary scores (the overrides :func:`compare` applies).

    Parameters
    ----------
    primary : iterable of PrimaryScore
        The primary scores.

    Returns
    -------
    mapping of str to int
        Name -> direction.
    """
    return {p.name: p.direction for p in primary}
