"""Every public function and class of the package has a numpydoc docstring.

The check is ``tools/check_docstrings.py`` (an equivalent of numpydoc's validation: a one-line
summary; a Parameters section naming every parameter with a type; a Returns or Yields section
when something is returned). It is shown to fail on planted bad examples, and to pass on
planted good ones, before it is run over ``gyrobench.base``, ``io``, ``sim``, ``analysis`` and
``scenarios``.

There is no list of exceptions: any public name that fails fails the test, so new code comes
with its docstrings. ``python tools/check_docstrings.py`` lists every failure with what is
missing.
"""

from __future__ import annotations

import importlib
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

sys.path.insert(0, str(ROOT / "tools"))
try:
    import check_docstrings as cd
finally:
    sys.path.pop(0)

PLANTED = '''
"""A planted module."""
from __future__ import annotations
from dataclasses import dataclass

__all__ = ["good", "good_generator", "GoodClass", "GoodData", "no_doc", "two_line_summary",
           "no_parameters", "missing_one", "untyped", "extra", "no_returns", "unannotated_return",
           "no_yields", "BadClass", "ClassNoAttributes", "GoodError"]


def good(x: float, *values: float, scale: float = 1.0, **options: str) -> float:
    """Scale a rate.

    Parameters
    ----------
    x : float
        A rate [rad/s].
    *values : float
        More rates [rad/s].
    scale : float
        Factor [-].
    **options : str
        Ignored.

    Returns
    -------
    float
        x times scale [rad/s].
    """
    return x * scale


def good_generator(n: int, m: int):
    """Count.

    Parameters
    ----------
    n, m : int
        How far.

    Yields
    ------
    int
        0 to n - 1.
    """
    yield from range(n)


class GoodClass:
    """A model.

    Parameters
    ----------
    gain : float
        [-].
    """

    def __init__(self, gain: float) -> None:
        self.gain = gain


@dataclass(frozen=True)
class GoodData:
    """A result.

    Attributes
    ----------
    value : float
        [rad/s].
    """

    value: float


class GoodError(ValueError):
    """A refusal (its constructor is ValueError's)."""


def no_doc(x: float) -> None:
    pass


def two_line_summary(x: float) -> None:
    """A summary that runs
    over two lines.

    Parameters
    ----------
    x : float
        [-].
    """


def no_parameters(x: float) -> None:
    """A summary.

    x is a float.
    """


def missing_one(x: float, y: float) -> None:
    """A summary.

    Parameters
    ----------
    x : float
        [-].
    """


def untyped(x: float) -> None:
    """A summary.

    Parameters
    ----------
    x
        Untyped.
    """


def extra(x: float) -> None:
    """A summary.

    Parameters
    ----------
    x : float
        [-].
    y : float
        Not a parameter.
    """


def no_returns(x: float) -> float:
    """A summary.

    Parameters
    ----------
    x : float
        [-].
    """
    return x


def unannotated_return(x):
    """A summary.

    Parameters
    ----------
    x : float
        [-].
    """
    def inner():
        return None
    return 2 * x


def no_yields(x: float):
    """A summary.

    Parameters
    ----------
    x : float
        [-].
    """
    yield x


class BadClass:
    """A class without Parameters."""

    def __init__(self, gain: float) -> None:
        self.gain = gain


@dataclass(frozen=True)
class ClassNoAttributes:
    """A dataclass whose field is undocumented.

    Attributes
    ----------
    other : float
        [-].
    """

    value: float


def _private(x):
    return x
'''

#: planted name -> a phrase its failure must contain
EXPECTED = {
    "no_doc": "no docstring",
    "two_line_summary": "summary is not one line",
    "no_parameters": "no Parameters section",
    "missing_one": "does not name: y",
    "untyped": "no type for: x",
    "extra": "signature lacks: y",
    "no_returns": "no Returns section",
    "unannotated_return": "no Returns section",
    "no_yields": "no Yields section",
    "BadClass": "no Parameters section",
    "ClassNoAttributes": "Attributes does not name: value",
}


@pytest.fixture(scope="module")
def planted(tmp_path_factory):
    folder = tmp_path_factory.mktemp("planted")
    (folder / "planted_docstrings.py").write_text(textwrap.dedent(PLANTED))
    sys.path.insert(0, str(folder))
    try:
        yield importlib.import_module("planted_docstrings")
    finally:
        sys.path.remove(str(folder))
        sys.modules.pop("planted_docstrings", None)


def test_checker_fails_each_planted_bad_docstring_and_passes_the_good(planted):
    fails = cd.check(["planted_docstrings"])
    by_name: dict[str, list[str]] = {}
    for f in fails:
        by_name.setdefault(f.qualname.rsplit(".", 1)[1], []).append(f.problem)
    assert set(by_name) == set(EXPECTED), sorted(by_name)
    for name, phrase in EXPECTED.items():
        assert any(phrase in p for p in by_name[name]), (name, by_name[name])


def test_public_names_without_all_are_the_unprefixed_ones_defined_here(planted):
    vars(planted).pop("__all__")
    try:
        names = {n for n, _ in cd.public_names(planted)}
    finally:
        planted.__all__ = []
    assert "good" in names and "_private" not in names and "dataclass" not in names


def test_every_public_name_has_a_numpydoc_docstring():
    fails = cd.check()
    assert not fails, "public names without a complete numpydoc docstring:\n" + "\n".join(str(f) for f in fails)


def test_there_is_no_list_of_exempt_names():
    assert not (ROOT / "tests" / "data" / "docstring_debt.txt").exists()
    assert not hasattr(cd, "DEBT")
