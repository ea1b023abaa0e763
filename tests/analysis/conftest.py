"""Fixtures for the analysis tests: a per-test seeded Generator and the shared validation data."""

from __future__ import annotations

import zlib
from pathlib import Path

import numpy as np
import pytest

#: ../shared/validation relative to the repository root (never copied into the project)
VALIDATION = Path(__file__).resolve().parents[2].parent / "shared" / "validation"


@pytest.fixture
def rng(request) -> np.random.Generator:
    """The same stream on every run, a different one for every test."""
    key = zlib.crc32(request.node.nodeid.encode())
    return np.random.default_rng([20261121, key])


@pytest.fixture
def validation() -> Path:
    """The shared reference-data folder; the test is skipped when it is absent."""
    if not VALIDATION.is_dir():
        pytest.skip(f"reference data folder {VALIDATION} not found")
    return VALIDATION
