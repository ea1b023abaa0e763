"""The bench as a package (scenarios/bench/): its public names, its boundaries with the rest of
gyrobench, and its size."""

from __future__ import annotations

import ast
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import gyrobench.scenarios.bench as bench
from gyrobench.scenarios import registry

SCENARIOS = Path(bench.__file__).resolve().parents[1]
BENCH = SCENARIOS / "bench"

#: the public names of the single-module bench (v0.2.0), which the package must keep
NAMES_OF_THE_MODULE = {
    "DEFAULT_DB", "CompensatorError", "FailedSeedsError", "Campaign", "ScoreSummary",
    "ScoreComparison", "Comparison", "parse_seeds", "resolve_scenario", "resolve_compensator",
    "compensator_identity", "score_seed", "campaign_id", "run_campaign", "score_direction",
    "score_is_nonnegative", "check_baseline_path", "check_baseline_matches", "save_baseline",
    "load_baseline", "compare", "format_summary",
    # public by name though not in the module's __all__
    "BASELINE_FORMAT", "BASELINE_VERSION", "LOWER_IS_BETTER_TOKENS", "HIGHER_IS_BETTER_TOKENS",
    "NONNEGATIVE_TOKENS", "MAX_SEEDS", "MAX_SEED", "BYTES_PER_SEED", "prepend_import_path",
    "CompensatorImportError", "TRACEBACK_ENV", "connect_db",
}


def _tree(path: Path) -> ast.Module:
    return ast.parse(path.read_text(), filename=str(path))


def test_every_public_name_of_the_module_is_importable_from_the_package():
    assert set(bench.__all__) >= NAMES_OF_THE_MODULE, NAMES_OF_THE_MODULE - set(bench.__all__)
    for name in bench.__all__:
        obj = getattr(bench, name)
        home = getattr(obj, "__module__", None)
        homes = ("gyrobench.scenarios.bench.", "gyrobench.scenarios.runner.")
        assert home is None or home.startswith(homes), (name, home)
    with pytest.raises(AttributeError, match="no_such_name"):
        bench.no_such_name  # noqa: B018


def test_every_bench_module_declares_all_and_stays_under_600_lines():
    for path in sorted(BENCH.glob("*.py")):
        n = len(path.read_text().splitlines())
        assert n <= 600, f"{path.name} has {n} lines"
        names = {
            t.id
            for node in _tree(path).body
            if isinstance(node, (ast.Assign, ast.AnnAssign))
            for t in (node.targets if isinstance(node, ast.Assign) else [node.target])
            if isinstance(t, ast.Name)
        }
        assert "__all__" in names, f"{path.name} has no __all__"


def test_no_module_outside_the_bench_uses_a_private_name_of_it():
    """units.py shares the store, identity and pools through public names only."""
    found = []
    for path in sorted(SCENARIOS.rglob("*.py")):
        if BENCH in path.parents:
            continue
        for node in ast.walk(_tree(path)):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("gyrobench.scenarios.bench"):
                found += [f"{path.name}: {node.module}.{a.name}" for a in node.names if a.name.startswith("_")]
            elif isinstance(node, ast.Attribute) and node.attr.startswith("_") and not node.attr.startswith("__"):
                if isinstance(node.value, ast.Name) and node.value.id in ("bench", "bench_cli"):
                    found.append(f"{path.name}: {node.value.id}.{node.attr}")
    assert not found, found


def test_the_bench_reaches_scenarios_only_through_the_registry():
    """No bench module imports a scenario module by its path, so moving a paper's module (and
    changing its registry line) cannot break the bench."""
    scenario_modules = set(registry.SCENARIOS.values())
    for path in sorted(BENCH.glob("*.py")):
        for node in ast.walk(_tree(path)):
            mods = []
            if isinstance(node, ast.ImportFrom) and node.module:
                mods = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
            elif isinstance(node, ast.Import):
                mods = [a.name for a in node.names]
            bad = [m for m in mods if m in scenario_modules or m.startswith("gyrobench.scenarios.papers")]
            assert not bad, f"{path.name} imports {bad}"


def test_importing_the_bench_command_line_imports_nothing_heavy():
    code = textwrap.dedent(
        """
        import sys
        import gyrobench.scenarios.bench
        from gyrobench.scenarios.cli import bench as cli
        heavy = [m for m in ("numpy", "scipy", "sklearn", "matplotlib") if m in sys.modules]
        assert not heavy, heavy
        """
    )
    subprocess.run([sys.executable, "-c", code], check=True, cwd="/")
