"""Lazy package attributes (gyrobench.base.lazy.attach)."""

from __future__ import annotations

import sys

import pytest

from gyrobench.base.lazy import attach


def test_a_name_loads_from_its_module_and_an_unknown_one_is_named():
    get, names = attach("gyrobench.base", {"FieldRange": "gyrobench.base.ranges"})
    from gyrobench.base.ranges import FieldRange

    assert get("FieldRange") is FieldRange
    assert "FieldRange" in names()
    with pytest.raises(AttributeError, match="module 'gyrobench.base' has no attribute 'nope'"):
        get("nope")


def test_a_reimported_module_gives_its_new_objects_never_a_stale_one(monkeypatch):
    """What pytester does between inline runs: the submodule is dropped and imported again."""
    get, _ = attach("gyrobench.base", {"FieldRange": "gyrobench.base.ranges"})
    old = get("FieldRange")
    monkeypatch.delitem(sys.modules, "gyrobench.base.ranges")
    new = get("FieldRange")
    assert new is not old and new is sys.modules["gyrobench.base.ranges"].FieldRange
