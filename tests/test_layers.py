"""The layers of the package and the one direction imports may point.

``gyrobench.base`` (validation, field specs, memory estimates, atomic writes, units) imports
nothing of ours; ``gyrobench.io`` (recordings, readers of real logs) imports only ``base``;
``gyrobench.sim`` (physics) and ``gyrobench.analysis`` (methods for any recording) import ``base``
and ``io`` and never each other; ``gyrobench.scenarios`` (papers, checks, runner, CLI, reports)
may import everything. Every import counts: at module level, inside functions and under
``TYPE_CHECKING``. The picture is in docs/layers.md.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import gyrobench

ROOT = Path(gyrobench.__file__).resolve().parent
PACKAGE = Path(gyrobench.__file__).parent  # not resolved: sim, analysis, scenarios are links

#: layer -> the layers it may import (besides itself)
ALLOWED = {
    "base": set(),
    "io": {"base"},
    "sim": {"base", "io"},
    "analysis": {"base", "io"},
    "scenarios": {"base", "io", "sim", "analysis"},
}


def _modules() -> list[tuple[str, Path]]:
    out = []
    for layer in ALLOWED:
        folder = PACKAGE / layer
        for path in sorted(folder.rglob("*.py")):
            rel = path.relative_to(PACKAGE).with_suffix("")
            parts = list(rel.parts)
            if parts[-1] == "__init__":
                parts = parts[:-1]
            out.append(("gyrobench." + ".".join(parts), path))
    return out


def _imports(module: str, path: Path) -> list[tuple[int, str]]:
    tree = ast.parse(path.read_text(), filename=str(path))
    package = module if path.name == "__init__.py" else module.rsplit(".", 1)[0]
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [(node.lineno, a.name) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            found.append((node.lineno, target))
    return [(line, t) for line, t in found if t == "gyrobench" or t.startswith("gyrobench.")]


MODULES = _modules()


def test_every_layer_has_modules():
    layers = {m.split(".")[1] for m, _ in MODULES}
    assert layers == set(ALLOWED)


@pytest.mark.parametrize("layer", list(ALLOWED))
def test_imports_point_one_way(layer):
    bad = []
    for module, path in MODULES:
        if module.split(".")[1] != layer:
            continue
        for line, target in _imports(module, path):
            parts = target.split(".")
            if len(parts) < 2:
                if layer == "scenarios":  # the version, for --version and the reports
                    continue
                bad.append(f"{path.relative_to(ROOT.parent)}:{line} imports the top-level gyrobench")
                continue
            other = parts[1]
            if other != layer and other not in ALLOWED[layer]:
                bad.append(f"{path.name}:{line} ({module}) imports {target}")
    assert not bad, "\n".join(bad)


def test_the_checker_sees_a_forbidden_import(tmp_path):
    """The walk above finds imports inside functions and relative ones (so it can fail)."""
    src = "def f():\n    from gyrobench.analysis import allan\n\nfrom ..analysis import twin\n"
    path = tmp_path / "x.py"
    path.write_text(src)
    found = [t for _, t in _imports("gyrobench.sim.x", path)]
    assert sorted(found) == ["gyrobench.analysis", "gyrobench.analysis"]
