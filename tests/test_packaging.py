"""The installed package: one import namespace, a plugin that never breaks a user's suite.

A user project that has its own ``sim``, ``analysis`` and ``scenarios`` packages runs its
own pytest with gyrobench installed: its imports get its own packages, its suite is green,
and the ``gyrobench_bench`` fixture works there (with a compensator given as
``"module:attr"`` found from the project's rootdir).
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _env() -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTEST_ADDOPTS")}
    return env


def test_gyrobench_names_are_lazy_and_versioned():
    code = textwrap.dedent(
        """
        import sys, gyrobench
        assert gyrobench.__version__ == "0.6.1", gyrobench.__version__
        heavy = [m for m in ("numpy", "scipy", "sklearn", "matplotlib", "h5py") if m in sys.modules]
        assert not heavy, heavy
        assert callable(gyrobench.fit_noise) and callable(gyrobench.allan_deviation)
        assert callable(gyrobench.run_campaign) and gyrobench.NoiseModel.__name__ == "NoiseModel"
        try:
            gyrobench.no_such_name
        except AttributeError as exc:
            assert "no_such_name" in str(exc)
        else:
            raise AssertionError("unknown attribute did not raise")
        """
    )
    subprocess.run([sys.executable, "-c", code], check=True, env=_env(), cwd="/")


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_user_project_with_sim_analysis_scenarios_packages_runs_its_own_pytest(tmp_path):
    proj = tmp_path / "userproj"
    for pkg in ("sim", "analysis", "scenarios"):
        (proj / pkg).mkdir(parents=True)
        (proj / pkg / "__init__.py").write_text(f"OWNER = 'user {pkg}'\n")
    (proj / "pyproject.toml").write_text("[tool.pytest.ini_options]\npythonpath = ['.']\n")
    # the user's own scenario lives in the user's own 'scenarios' package
    (proj / "scenarios" / "toy.py").write_text((ROOT / "tests" / "scenarios" / "toy_scenario.py").read_text())
    (proj / "mylab").mkdir()
    (proj / "mylab" / "__init__.py").write_text("")
    (proj / "mylab" / "models.py").write_text(
        "from sklearn.linear_model import LinearRegression\nmine = LinearRegression()\n"
    )
    (proj / "tests").mkdir()
    (proj / "tests" / "test_user.py").write_text(
        textwrap.dedent(
            """
            import sim, analysis, scenarios

            def test_own_packages():
                assert sim.OWNER == "user sim"
                assert analysis.OWNER == "user analysis"
                assert scenarios.OWNER == "user scenarios"

            def test_fixture(gyrobench_bench):
                camp = gyrobench_bench.campaign("scenarios.toy", "mylab.models:mine", range(3), workers=0)
                assert camp.seeds == (0, 1, 2)
            """
        )
    )
    r = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "tests"],
        cwd=proj, env=_env(), capture_output=True, text=True, timeout=300,
    )
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    assert "2 passed" in r.stdout


def test_plugin_module_imports_nothing_heavy():
    code = (
        "import sys, gyrobench.scenarios.pytest_plugin\n"
        "heavy = [m for m in ('numpy', 'scipy', 'sklearn', 'matplotlib', 'h5py') if m in sys.modules]\n"
        "assert not heavy, heavy\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True, env=_env(), cwd="/")


@pytest.mark.slow
def test_built_wheel_installs_one_gyrobench_package_and_no_top_level_sim(tmp_path):
    """The wheel holds gyrobench/ only; installed alone, import sim/analysis/scenarios fail."""
    r = subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(tmp_path / "dist"), str(ROOT)],
        capture_output=True, text=True, timeout=600,
    )
    assert r.returncode == 0, r.stderr[-3000:]
    (wheel,) = (tmp_path / "dist").glob("gyrobench-0.6.1-*.whl")
    with zipfile.ZipFile(wheel) as zf:
        tops = {n.split("/")[0] for n in zf.namelist()}
        assert "gyrobench/py.typed" in zf.namelist()
        expected = {
            "gyrobench/sim/noise.py",
            "gyrobench/scenarios/cli/main.py",
            "gyrobench/base/atomic.py",
            "gyrobench/io/logs/__init__.py",
        }
        assert expected <= set(zf.namelist())
        meta = zf.read(next(n for n in zf.namelist() if n.endswith("METADATA"))).decode()
    assert tops == {"gyrobench", "gyrobench-0.6.1.dist-info"}, tops
    assert "License-Expression: MIT" in meta or "License: MIT" in meta
    target = tmp_path / "site"
    subprocess.run(
        [sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--target", str(target), str(wheel)],
        check=True, timeout=600,
    )
    code = textwrap.dedent(
        f"""
        import sys
        sys.path.insert(0, {str(target)!r})
        import gyrobench, gyrobench.sim, gyrobench.analysis, gyrobench.scenarios
        assert gyrobench.__file__.startswith({str(target)!r}), gyrobench.__file__
        for name in ("sim", "analysis", "scenarios"):
            try:
                __import__(name)
            except ModuleNotFoundError:
                pass
            else:
                raise AssertionError(name + " is importable")
        """
    )
    subprocess.run([sys.executable, "-I", "-c", code], check=True, cwd=str(tmp_path), timeout=120)


@pytest.mark.parametrize("argv", [["list"], ["--help"], ["bench", "--help"], ["reproduce", "--help"]])
def test_cli_help_and_list_import_nothing_heavy(argv):
    """'gyrobench list' and every --help stay fast: no numpy, scipy, sklearn, matplotlib, h5py."""
    code = textwrap.dedent(
        f"""
        import contextlib, io, sys
        from gyrobench.scenarios.cli.main import main
        with contextlib.redirect_stdout(io.StringIO()):
            try:
                main({argv!r})
            except SystemExit:
                pass
        heavy = [m for m in ("numpy", "scipy", "sklearn", "matplotlib", "h5py", "dask") if m in sys.modules]
        assert not heavy, heavy
        """
    )
    subprocess.run([sys.executable, "-c", code], check=True, env=_env(), cwd="/")


def test_list_names_every_paper():
    from gyrobench.scenarios import registry
    from gyrobench.scenarios.papers import sources

    papers = {registry.describe(n).paper for n in registry.available()} - {None}
    assert papers and papers <= set(sources())


def test_every_verb_spells_shared_flags_the_same_way():
    """A flag that several verbs take has the same short and long forms on each (-q/--quiet...)."""
    from gyrobench.scenarios.cli.main import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    forms: dict[str, set[tuple[str, ...]]] = {}
    for p in sub.choices.values():
        for action in p._actions:
            longs = [o for o in action.option_strings if o.startswith("--")]
            for lo in longs:
                forms.setdefault(lo, set()).add(tuple(sorted(action.option_strings)))
    mixed = {lo: f for lo, f in forms.items() if len(f) > 1}
    assert not mixed, mixed
    assert forms["--quiet"] == {("--quiet", "-q")}
