"""docs/physics.md is self-contained and true to the code.

- it has a contents list that is exactly its numbered sections (``tools/physics_toc.py`` writes it);
- it cites no document outside the repository and no issue number;
- every code name it writes in backticks (``sim.noise.NoiseModel``, ``analysis.allan.fit_noise``,
  ``fiber_strain.segment_kernel``) exists, and every physics-check id it names
  (``fog.loop_arw_optical_budget``) is one the check modules define.
"""

from __future__ import annotations

import importlib
import importlib.util
import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "physics.md"
TEXT = DOC.read_text(encoding="utf-8")
PACKAGES = ("base", "io", "sim", "analysis", "scenarios", "scenarios.papers", "scenarios.cli", "scenarios.checks")
#: outside packages the text may name (resolved by import like ours)
EXTERNAL = ("numpy", "scipy", "sklearn", "pywt", "allantools")


def test_contents_list_is_the_sections():
    sys.path.insert(0, str(ROOT / "tools"))
    try:
        import physics_toc
    finally:
        sys.path.pop(0)
    assert "\n## Contents\n" in TEXT, "docs/physics.md has no contents list: run tools/physics_toc.py"
    listed = TEXT.split("\n## Contents\n", 1)[1].split(physics_toc.RULE, 1)[0].strip()
    expected = physics_toc.contents(TEXT).split("\n", 2)[2].strip()
    assert listed == expected, "the contents list is stale: run tools/physics_toc.py"


def test_no_outside_documents_or_issue_numbers():
    bad = re.findall(r"(?i)\bissues? #?\d+|\.\./shared|seeds/", TEXT)
    bad += re.findall(r"PHYSICS(?:-models)?\.md|DESIGN\.md|STYLE\.md", TEXT)  # the shared notes, not this file
    assert not bad, sorted(set(bad))


def _check_id_patterns() -> list[re.Pattern[str]]:
    """Every check id the check modules define, as literal ids or f-string patterns."""
    out = []
    for path in (ROOT / "scenarios" / "checks").glob("*.py"):
        for m in re.finditer(r'\bid=(f?)"([a-z_0-9]+\.(?:[a-z0-9_]|\{[^}]*\})+)"', path.read_text(encoding="utf-8")):
            text = re.escape(m.group(2)) if not m.group(1) else re.sub(
                r"\\\{[^}]*\\\}", "[a-z0-9_.]+", re.escape(m.group(2)))
            out.append(re.compile(text + r"$"))
    return out


def _resolve(dotted: str) -> bool:
    if dotted.split(".")[0] in EXTERNAL:
        dotted_mod, _, attr = dotted.rpartition(".")
        return hasattr(importlib.import_module(dotted_mod), attr)
    parts = dotted.removeprefix("gyrobench.").split(".")
    if parts[0] not in PACKAGES:
        for pkg in PACKAGES:
            if importlib.util.find_spec(f"gyrobench.{pkg}.{parts[0]}") is not None:
                parts = [*pkg.split("."), *parts]
                break
        else:
            return False
    for i in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module("gyrobench." + ".".join(parts[:i]))
        except ImportError:
            continue
        for attr in parts[i:]:
            if not hasattr(obj, attr):
                return False
            obj = getattr(obj, attr)
        return True
    return False


NAMES = sorted(set(re.findall(r"`((?:gyrobench\.)?[a-z_][a-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)+)(?:\(\))?`", TEXT)))
CHECKS = _check_id_patterns()


@pytest.mark.parametrize("name", NAMES)
def test_every_name_exists(name):
    if any(p.match(name) for p in CHECKS) or _resolve(name):
        return
    pytest.fail(f"docs/physics.md names {name!r}: neither a module, function or class nor a physics check")
