"""Every docstring example in gyrobench.sim and gyrobench.analysis runs as written (STYLE: a
small seeded Example that runs as a doctest)."""

from __future__ import annotations

import doctest
import importlib
import pkgutil

import pytest

import gyrobench.analysis
import gyrobench.sim


def _modules() -> list[str]:
    out = []
    for pkg in (gyrobench.sim, gyrobench.analysis):
        for info in pkgutil.walk_packages(pkg.__path__, prefix=pkg.__name__ + "."):
            out.append(info.name)
    return sorted(out)


@pytest.mark.parametrize("name", _modules())
def test_docstring_examples_run(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples failed in {name}"
