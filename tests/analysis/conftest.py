"""Fixtures for the analysis tests: the shared validation data (``rng`` is in tests/conftest.py)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

#: ../shared/validation relative to the repository root (never copied into the project);
#: GYROBENCH_VALIDATION names it explicitly (a git worktree sits at another depth)
VALIDATION = Path(
    os.environ.get("GYROBENCH_VALIDATION") or Path(__file__).resolve().parents[2].parent / "shared" / "validation"
)


@pytest.fixture
def validation() -> Path:
    """The shared reference-data folder; the test is skipped when it is absent."""
    if not VALIDATION.is_dir():
        pytest.skip(f"reference data folder {VALIDATION} not found")
    return VALIDATION
