"""The contract every paper scenario package meets: :class:`PaperScenario`.

A paper is a package ``gyrobench.scenarios.papers.p<key>_<scenario>`` (one folder, discovered
by :func:`gyrobench.scenarios.papers.discover`; nothing is registered elsewhere) with four
modules:

``config.py``
    ``Config``: a frozen dataclass whose defaults are the paper's stated protocol (field
    units allowed here, at the edge, with the unit in the field name or docstring).
``experiment.py``
    ``experiment(config, seed) -> <Result>``: ONE simulated unit (each seed is another
    unit) through the whole pipeline, returned as a typed frozen dataclass that satisfies
    :class:`UnitResult` (its ``quantities`` hold one number per claim, ``None`` where the
    unit cannot test it). No formatting. ``simulate(config, seed)`` gives the unit's
    recordings with truth; ``memory_estimate(config)`` the peak bytes of one unit.
``claims.py``
    ``CLAIMS`` and ``DEVIATIONS`` as data (:mod:`gyrobench.scenarios.claims`), and
    ``claims_for(config)``: the claims judged for that config (a variant may mark more of
    them calibrated).
``report.py``
    ``report(config, units, claims) -> Outcome``: tables and figures from the units'
    typed results and the judged claims only. It imports nothing from
    :mod:`gyrobench.sim`; it never re-runs a simulation.

The package's ``__init__`` states ``NAME``, ``TITLE`` and ``PAPER`` as literals and ``SOURCE``
(a :class:`gyrobench.scenarios.papers.Paper`), and re-exports ``Config`` and the functions
above (and, when the paper has a compensation stage for ``gyrobench bench``,
``compensation_task`` and ``BENCH_SCORES``, a
:class:`gyrobench.scenarios.bench.primary.ScenarioScores`), so the package itself is a
:class:`PaperScenario`. The contract test (``tests/scenarios/test_paper_contract.py``) runs
over every discovered paper.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any, Protocol, runtime_checkable

from gyrobench.scenarios.base import Outcome
from gyrobench.scenarios.claims import Claim, ClaimResult, Deviation

__all__ = ["PaperScenario", "UnitResult", "PACKAGE_MODULES", "quantities_of"]

#: the modules every paper package has
PACKAGE_MODULES = ("config", "experiment", "claims", "report")


@runtime_checkable
class UnitResult(Protocol):
    """One unit's result: a frozen dataclass with its seed and one number per claim."""

    @property
    def seed(self) -> int: ...

    @property
    def quantities(self) -> Mapping[str, float | None]: ...


@runtime_checkable
class PaperScenario(Protocol):
    """What a paper package exports (a module satisfies this Protocol structurally)."""

    NAME: str
    TITLE: str
    PAPER: str
    CLAIMS: tuple[Claim, ...]
    DEVIATIONS: tuple[Deviation, ...]

    @property
    def Config(self) -> type: ...  # noqa: N802 - the config class the package exports

    def experiment(self, config: Any, seed: int) -> UnitResult: ...

    def claims_for(self, config: Any) -> tuple[Claim, ...]: ...

    def report(self, config: Any, units: Sequence[Any], claims: Sequence[ClaimResult]) -> Outcome: ...

    def simulate(self, config: Any, seed: int) -> list[Any]: ...

    def memory_estimate(self, config: Any) -> float: ...


def quantities_of(unit: Any) -> Mapping[str, float | None]:
    """The per-claim quantities of a unit's result (typed result, or a legacy mapping).

    Parameters
    ----------
    unit : object
        A unit's result.

    Returns
    -------
    mapping of str to float or None
        Claim quantity -> number.

    Raises
    ------
    TypeError
        If ``unit`` has neither a ``quantities`` attribute nor a ``"quantities"`` key
        holding a mapping.
    """
    q = getattr(unit, "quantities", None)
    if q is None and isinstance(unit, Mapping):
        q = unit.get("quantities")
    if not isinstance(q, Mapping):
        raise TypeError(
            f"a unit's result must carry a 'quantities' mapping (UnitResult); got {type(unit).__name__}"
        )
    return q
