"""Every paper reaches its device through the one interface, ``unit.simulate(environment, fs=, rng=)``.

A static scan (AST) of every module of every paper package under ``scenarios/papers/``:

* no private name of ``gyrobench.sim`` is imported or read: no ``from gyrobench.sim.x import _y``,
  no ``alias._y`` on a name bound to a ``gyrobench.sim`` module, no import of a private sim
  module (``gyrobench.sim._x``, ``gyrobench.sim.parts._x``);
* no paper runs a model through one of the sim's other runners (:data:`RUNNERS`: the slow flow,
  the full integration, the FOG loop, the Adler integration), by import or attribute;
* every paper package calls ``.simulate(...)`` with the keywords ``fs`` and ``rng`` at least once.

The scan sees the source, not the run: a paper that reached a runner through ``getattr`` with a
computed name would pass it. :data:`RUNNERS` is the list of the sim's public functions that run a
device model besides its ``simulate``; a test checks each still exists where it is listed, so a
rename cannot empty the list without failing here.
"""

from __future__ import annotations

import ast
import importlib
from pathlib import Path

import pytest

import gyrobench.scenarios.papers as papers_pkg

PAPERS_DIR = Path(papers_pkg.__file__).parent

#: the sim's public functions that run a device model other than through its ``simulate``
RUNNERS = {
    "gyrobench.sim.mems_slow_flow": ("slow_flow", "rate_table"),
    "gyrobench.sim.mems_full": ("simulate_full",),
    "gyrobench.sim.fog_loop": ("run_loop",),
    "gyrobench.sim.rlg": ("integrate_adler",),
}

PAPER_PACKAGES = sorted(p for p in PAPERS_DIR.iterdir() if p.is_dir() and (p / "__init__.py").exists())


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def _is_sim(module: str) -> bool:
    return module == "gyrobench.sim" or module.startswith("gyrobench.sim.")


def violations(source: str, filename: str = "<source>") -> list[str]:
    """Private sim names and sim runners a module's source imports or reads, one line each."""
    tree = ast.parse(source, filename)
    found: list[str] = []
    bound: dict[str, str] = {}  # local name -> the gyrobench.sim module it is bound to
    runner_names = {(m, f) for m, fs in RUNNERS.items() for f in fs}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.split(".")[0] == "gyrobench":
            for a in node.names:
                full = f"{node.module}.{a.name}"
                if not (_is_sim(node.module) or _is_sim(full)):
                    continue
                if any(_private(part) for part in full.split(".")):
                    found.append(f"{filename}:{node.lineno}: from {node.module} import {a.name}")
                elif (node.module, a.name) in runner_names:
                    found.append(f"{filename}:{node.lineno}: imports the runner {full}")
                else:
                    bound[a.asname or a.name] = full
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name.split(".")[0] != "gyrobench":
                    continue
                if _is_sim(a.name) and any(_private(part) for part in a.name.split(".")):
                    found.append(f"{filename}:{node.lineno}: imports the private module {a.name}")
                # ``import a.b.c as d`` binds ``d`` to a.b.c; ``import a.b.c`` binds ``a``
                bound[a.asname or "gyrobench"] = a.name if a.asname else "gyrobench"
    for node in ast.walk(tree):
        if not isinstance(node, ast.Attribute):
            continue
        chain = [node.attr]
        v = node.value
        while isinstance(v, ast.Attribute):
            chain.append(v.attr)
            v = v.value
        if not (isinstance(v, ast.Name) and v.id in bound):
            continue
        # the dotted path from the sim name to this attribute, e.g. gyrobench.sim.mems_resonator._f_ext
        path = ".".join([bound[v.id], *reversed(chain)])
        module, _, attr = path.rpartition(".")
        if _private(attr) and _is_sim(module):
            found.append(f"{filename}:{node.lineno}: reads the private {path}")
        elif (module, attr) in runner_names:
            found.append(f"{filename}:{node.lineno}: reads the runner {path}")
    return sorted(set(found))


def _simulate_calls(source: str) -> int:
    """Calls ``x.simulate(...)`` with the keywords ``fs`` and ``rng``."""
    n = 0
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "simulate":
            if {"fs", "rng"} <= {k.arg for k in node.keywords}:
                n += 1
    return n


def test_there_are_papers_to_scan():
    assert len(PAPER_PACKAGES) >= 4, PAPER_PACKAGES


@pytest.mark.parametrize("package", PAPER_PACKAGES, ids=lambda p: p.name)
def test_no_paper_module_uses_a_private_sim_name_or_a_runner(package):
    found = [v for f in sorted(package.rglob("*.py")) for v in violations(f.read_text(), str(f))]
    assert found == [], "\n".join(found)


@pytest.mark.parametrize("package", PAPER_PACKAGES, ids=lambda p: p.name)
def test_every_paper_simulates_through_the_interface(package):
    calls = sum(_simulate_calls(f.read_text()) for f in package.rglob("*.py"))
    assert calls >= 1, f"{package.name}: no unit.simulate(environment, fs=, rng=) call"


def test_every_listed_runner_exists():
    for module, names in RUNNERS.items():
        mod = importlib.import_module(module)
        for name in names:
            assert callable(getattr(mod, name, None)), f"{module}.{name}"


@pytest.mark.parametrize(
    "source",
    [
        "from gyrobench.sim.mems_resonator import _f_ext\n",
        "from gyrobench.sim import mems_resonator as mr\nmr._static_channels(op, w, a)\n",
        "import gyrobench.sim.mems_resonator\ngyrobench.sim.mems_resonator._output_map(u, op, c)\n",
        "from gyrobench.sim import mems_slow_flow\nmems_slow_flow.slow_flow(u, w, fs=1.0, rng=g)\n",
        "from gyrobench.sim.mems_slow_flow import slow_flow\n",
        "from gyrobench.sim.parts._device import simulate_part\n",
        "from gyrobench import sim\nsim.mems_resonator._f_ext(op, w, a)\n",
    ],
)
def test_the_scan_finds_each_kind_of_bypass(source):
    assert len(violations(source)) == 1, violations(source)


def test_the_scan_passes_public_use():
    source = (
        "from dataclasses import replace\n"
        "from gyrobench.sim import mems_resonator as mr\n"
        "from gyrobench.sim.sensor import Environment\n"
        "unit = replace(mr.MemsResonator(), idealization='noise_free')\n"
        "rec = unit.simulate(Environment(1.0), fs=100.0, rng=g)\n"
        "out = mr.static_rate_output(unit, w)\n"
        "x = unit.__class__\n"
    )
    assert violations(source) == []
    assert _simulate_calls(source) == 1
