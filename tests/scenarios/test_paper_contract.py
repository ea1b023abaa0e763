"""The paper-scenario contract (gyrobench.scenarios.papers.contract), over every discovered paper.

One unit of each paper is run once (module-scoped fixture, seed 0, the paper's default
config) and checked for what every paper must do: a typed frozen result with one quantity
per claim, claims judged by the shared evaluator, a report built from results alone, and a
package laid out as config / experiment / claims / report with a report that imports
nothing from ``gyrobench.sim``.
"""

from __future__ import annotations

import ast
import dataclasses
import importlib
import math
from pathlib import Path

import pytest

from gyrobench.scenarios import papers, registry
from gyrobench.scenarios.base import Outcome
from gyrobench.scenarios.claims import Claim, Deviation, evaluate
from gyrobench.scenarios.papers.contract import PACKAGE_MODULES, PaperScenario, UnitResult

PAPER_SCENARIOS = [n for n in registry.available() if registry.describe(n).paper is not None]

#: no module of a paper package is longer than this (the house issue's limit)
MAX_MODULE_LINES = 600


def test_every_paper_of_the_registry_is_a_discovered_paper_package():
    found = papers.discover()
    assert [p.name for p in found] == PAPER_SCENARIOS
    assert len(papers.sources()) == len(found)  # each states its source paper
    for name in PAPER_SCENARIOS:
        assert registry.table()[name].startswith("gyrobench.scenarios.papers.p"), name


@pytest.fixture(scope="module", params=PAPER_SCENARIOS)
def paper(request):
    module = registry.get(request.param)
    config = module.Config()
    unit = module.experiment(config, 0)
    return module, config, unit


def _package_dir(module) -> Path:
    return Path(module.__file__).parent


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_package_satisfies_the_protocol(paper):
    module, config, _ = paper
    assert isinstance(module, PaperScenario)
    assert dataclasses.is_dataclass(config) and type(config).__dataclass_params__.frozen
    assert all(isinstance(c, Claim) for c in module.CLAIMS)
    assert all(isinstance(d, Deviation) for d in module.DEVIATIONS)
    assert {c.paper for c in module.CLAIMS} == {module.PAPER}


def test_package_layout_and_module_sizes(paper):
    module, _, _ = paper
    root = _package_dir(module)
    for name in PACKAGE_MODULES:
        assert (root / f"{name}.py").is_file(), f"{root} lacks {name}.py"
    for path in root.glob("*.py"):
        n = len(path.read_text(encoding="utf-8").splitlines())
        assert n <= MAX_MODULE_LINES, f"{path} has {n} lines"


def test_report_imports_nothing_from_sim(paper):
    module, _, _ = paper
    tree = ast.parse((_package_dir(module) / "report.py").read_text(encoding="utf-8"))
    imported = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module:
            imported.append(node.module)
        elif isinstance(node, ast.Import):
            imported.extend(a.name for a in node.names)
    assert not [m for m in imported if m.startswith("gyrobench.sim")], imported


def test_unit_result_is_typed_frozen_with_a_quantity_per_claim(paper):
    module, config, unit = paper
    assert isinstance(unit, UnitResult)
    assert dataclasses.is_dataclass(unit) and type(unit).__dataclass_params__.frozen
    assert unit.seed == 0
    claims = module.claims_for(config)
    missing = {c.quantity for c in claims} - set(unit.quantities)
    assert not missing, f"claims read quantities the unit does not give: {sorted(missing)}"
    for key, q in unit.quantities.items():
        assert q is None or isinstance(q, float), (key, q)


def test_claims_judged_from_the_units_quantities(paper):
    """The shared evaluator reproduces, claim by claim, the comparator on the unit's value."""
    module, config, unit = paper
    claims = module.claims_for(config)
    results = evaluate(claims, [unit.quantities])
    for claim, res in zip(claims, results, strict=True):
        q = unit.quantities[claim.quantity]
        pre = claim.precondition
        shows = pre is None or pre.present(unit.quantities.get(pre.quantity))
        testable = q is not None and math.isfinite(q) and shows
        assert res.testable == int(testable), claim.id
        assert res.holds == int(testable and claim.comparator.holds(q)), claim.id


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_report_builds_from_results_alone(paper):
    module, config, unit = paper
    claims = evaluate(module.claims_for(config), [unit.quantities])
    outcome = module.report(config, [unit], claims)
    assert isinstance(outcome, Outcome)
    assert outcome.scenario == module.NAME
    assert outcome.tables


def test_package_exports_what_it_defines(paper):
    module, _, _ = paper
    assert set(PaperScenario.__protocol_attrs__ if hasattr(PaperScenario, "__protocol_attrs__") else ()) <= set(
        dir(module)
    )
    for name in PACKAGE_MODULES:
        sub = importlib.import_module(f"{module.__name__}.{name}")
        assert hasattr(sub, "__all__"), f"{sub.__name__} has no __all__"


def test_deviations_are_variants_with_no_hand_written_number(paper):
    """A deviation names the config variant that runs the paper's protocol; its measured effect is
    computed by ``reproduce --deviations``, so its effect cell holds no number the run did not compute."""
    import re

    module, config, _ = paper
    assert module.DEVIATIONS, "a paper states at least one departure (or choice) as a deviation"
    for d in module.DEVIATIONS:
        assert not re.search(r"\d", d.effect), (d.what, d.effect)
        if d.variant:  # a departure no config can undo (a figure not drawn) is listed without one
            variant = module.variant_config(config, d.variant)
            assert type(variant) is type(config) and variant != config, d.variant
    assert any(d.variant for d in module.DEVIATIONS), "no deviation of this paper can be measured"


def test_control_switches_the_effect_off(paper):
    """Every paper defines its control population: the same units with the paper's effect off."""
    module, config, _ = paper
    control = module.control_config(config)
    assert type(control) is type(config) and control != config
