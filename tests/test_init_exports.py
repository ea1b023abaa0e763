"""The curated ``__init__``s: each layer exports its public names, lazily, and honestly.

- every name in the ``__all__`` of ``gyrobench.base``, ``io``, ``sim``, ``analysis``,
  ``analysis.compensation`` and ``scenarios`` resolves, and is public where it is defined
  (listed in its own module's ``__all__``), so a package never exports a private helper;
- importing those packages imports nothing heavy (numpy, scipy, scikit-learn, matplotlib, h5py):
  names load on first use;
- a paper package's ``__all__`` is the paper contract (what the runner, the report and the bench
  read from it), nothing more.
"""

from __future__ import annotations

import importlib
import os
import subprocess
import sys

import pytest

PACKAGES = (
    "gyrobench.base",
    "gyrobench.io",
    "gyrobench.sim",
    "gyrobench.analysis",
    "gyrobench.analysis.compensation",
    "gyrobench.scenarios",
)
HEAVY = ("numpy", "scipy", "sklearn", "matplotlib", "h5py")
#: what a paper package may export: the PaperScenario protocol, the bench's task and the
#: runner's optional hooks (control population, protocol variants) and the unit's result type
PAPER_CONTRACT = {
    "NAME", "TITLE", "PAPER", "Config", "CLAIMS", "DEVIATIONS", "UnitResult", "experiment", "claims_for",
    "report", "simulate", "memory_estimate", "compensation_task", "control_config", "variant_config", "VARIANTS",
    # the paper's source record and bench scores (one folder), and what its unit store keeps whole
    "SOURCE", "BENCH_SCORES", "REPORT_UNITS", "SLIM_FIELDS",
}


@pytest.mark.parametrize("package", PACKAGES)
def test_every_exported_name_resolves_and_is_public_where_defined(package):
    pkg = importlib.import_module(package)
    assert pkg.__all__ and len(set(pkg.__all__)) == len(pkg.__all__)
    for name in pkg.__all__:
        obj = getattr(pkg, name)
        home = importlib.import_module(pkg._LAZY[name])
        assert getattr(home, name) is obj
        assert name in getattr(home, "__all__", ()), f"{package}.{name} is not in {home.__name__}.__all__"
    assert set(pkg.__all__) <= set(dir(pkg))
    with pytest.raises(AttributeError, match="no_such_name"):
        pkg.no_such_name  # noqa: B018


def test_importing_the_packages_imports_nothing_heavy():
    code = (
        "import sys\n"
        + "".join(f"import {p}\n" for p in PACKAGES)
        + f"heavy = [m for m in {HEAVY!r} if m in sys.modules]\n"
        + "assert not heavy, heavy\n"
    )
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTEST_ADDOPTS")}
    subprocess.run([sys.executable, "-c", code], check=True, env=env, cwd="/")


def _papers() -> list[str]:
    import pkgutil

    import gyrobench.scenarios.papers as papers

    return sorted(f"{papers.__name__}.{m.name}" for m in pkgutil.iter_modules(papers.__path__) if m.ispkg)


@pytest.mark.parametrize("name", _papers())
def test_paper_packages_export_only_their_contract(name):
    module = importlib.import_module(name)
    extra = set(module.__all__) - PAPER_CONTRACT
    assert not extra, f"{module.__name__}.__all__ exports more than the paper contract: {sorted(extra)}"
    for attr in module.__all__:
        assert hasattr(module, attr), attr
