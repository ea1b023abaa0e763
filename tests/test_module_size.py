"""No module under ``scenarios/`` is over 600 lines (the bench's limit, CONTRIBUTING.md).

A module that grows past the limit is split along a seam of responsibility (records vs.
evaluation vs. formatting, scheduling vs. execution, schema vs. reads and writes) with its
public names re-exported from the old path; the test names every module over the limit with
its length.

Only ``scenarios/`` is bound so far. The ``sim/`` and ``io/`` modules are not yet bound (several
physics models and ``io/recording.py`` are over 1,000 lines), nor is ``base/safety.py``; they
get the same test when they are split.
"""

from __future__ import annotations

from pathlib import Path

import gyrobench

#: the bench's limit [lines per module]
LIMIT = 600

#: modules allowed over the limit: none (an entry needs a reason in its comment, and
#: test_every_allowance_is_still_needed fails once an entry is no longer over the limit)
ALLOWED: frozenset[str] = frozenset()

#: the package folder (not resolved: ``scenarios`` is a link to the top-level folder)
PACKAGE = Path(gyrobench.__file__).parent


def line_counts(root: Path) -> dict[str, int]:
    """Lines of every ``.py`` file under ``root / "scenarios"``, keyed by its path from ``root``."""
    return {
        path.relative_to(root).as_posix(): len(path.read_text(encoding="utf-8").splitlines())
        for path in sorted((root / "scenarios").rglob("*.py"))
    }


def oversized(counts: dict[str, int], limit: int = LIMIT, allowed: set[str] | frozenset[str] = frozenset()
              ) -> list[str]:
    """Each module over ``limit`` lines and not in ``allowed``, as ``"path: N lines"``."""
    return [f"{p}: {n} lines" for p, n in counts.items() if n > limit and p not in allowed]


def test_no_scenarios_module_is_over_the_limit():
    counts = line_counts(PACKAGE)
    assert len(counts) > 100  # the walk found the package (a wrong root would pass vacuously)
    bad = oversized(counts, LIMIT, ALLOWED)
    assert not bad, f"modules over {LIMIT} lines (split them along a seam):\n" + "\n".join(bad)


def test_every_allowance_is_still_needed():
    """An allowed module exists and is still over the limit; once split, its entry goes."""
    counts = line_counts(PACKAGE)
    stale = [f"{p}: {'missing' if p not in counts else f'{counts[p]} lines'}" for p in sorted(ALLOWED)
             if counts.get(p, 0) <= LIMIT]
    assert not stale, "remove these from ALLOWED in tests/test_module_size.py:\n" + "\n".join(stale)


def test_the_check_sees_a_module_over_the_limit(tmp_path):
    """The walk and the count can fail: a planted 601-line module is named, a 600-line one and an
    allowed one are not."""
    (tmp_path / "scenarios" / "sub").mkdir(parents=True)
    (tmp_path / "scenarios" / "sub" / "big.py").write_text("x = 1\n" * (LIMIT + 1))
    (tmp_path / "scenarios" / "edge.py").write_text("x = 1\n" * LIMIT)
    (tmp_path / "scenarios" / "allowed.py").write_text("x = 1\n" * (LIMIT + 50))
    counts = line_counts(tmp_path)
    assert counts["scenarios/sub/big.py"] == LIMIT + 1 and counts["scenarios/edge.py"] == LIMIT
    assert oversized(counts, LIMIT, {"scenarios/allowed.py"}) == [f"scenarios/sub/big.py: {LIMIT + 1} lines"]
