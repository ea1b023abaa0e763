"""Fixtures shared by every test package."""

import zlib

import numpy as np
import pytest


@pytest.fixture
def rng(request) -> np.random.Generator:
    """The same stream on every run, a different one for every test."""
    key = zlib.crc32(request.node.nodeid.encode())
    return np.random.default_rng([20261121, key])

# Property tests draw the same examples on every run (the equivalent of a fixed seed), so a
# CI result never depends on which examples Hypothesis happened to try.
from hypothesis import settings as _hypothesis_settings  # noqa: E402

_hypothesis_settings.register_profile("gyrobench", derandomize=True, database=None)
_hypothesis_settings.load_profile("gyrobench")
