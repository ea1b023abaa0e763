"""Documented ranges of numeric configuration fields: :class:`FieldRange` and the one-line
refusal of a value outside them, re-exported from :mod:`gyrobench.sim.ranges`.

They live in ``sim`` so the simulator's own dataclasses (nested in the scenarios' configs) can
state their ``RANGES`` without ``sim`` importing ``scenarios`` (DESIGN: imports point one way);
kept free of numpy so the command line's flag types can use them (``gyrobench --help`` imports
only the standard library)."""

from __future__ import annotations

from gyrobench.sim.ranges import FieldRange, check_ranges, field_range, range_error

__all__ = ["FieldRange", "check_ranges", "field_range", "range_error"]
