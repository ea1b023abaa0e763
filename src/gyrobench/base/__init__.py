"""The base layer: what every layer of gyrobench may use, importing none of them.

Modules
-------
validate
    one-line checks of scalar arguments (finite, positive, a Generator, a sample rate).
ranges
    declarative field specs (:class:`~gyrobench.base.ranges.FieldRange`) and the refusal of a
    value outside them.
memory
    memory estimates, checked before allocating.
atomic
    atomic writes of files and folders.
units
    named conversions between field units and SI.
safety
    the output rule every command applies: no output is an input, only gyrobench's own files are
    replaced (or with --force), foreign folders and databases refused; inputs must be regular files.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from gyrobench.base.lazy import attach

#: public name -> the submodule that defines it (imported on first access, so importing
#: this package costs nothing until a name is used)
_LAZY: dict[str, str] = {
    "check_rng": "gyrobench.base.validate",
    "check_fs": "gyrobench.base.validate",
    "real_number": "gyrobench.base.validate",
    "positive_number": "gyrobench.base.validate",
    "FieldRange": "gyrobench.base.ranges",
    "check_ranges": "gyrobench.base.ranges",
    "field_range": "gyrobench.base.ranges",
    "range_error": "gyrobench.base.ranges",
    "MemoryLimitError": "gyrobench.base.memory",
    "available_memory": "gyrobench.base.memory",
    "memory_limit": "gyrobench.base.memory",
    "check_memory": "gyrobench.base.memory",
    "AtomicWriteError": "gyrobench.base.atomic",
    "atomic_path": "gyrobench.base.atomic",
    "atomic_folder": "gyrobench.base.atomic",
    "ensure_free_space": "gyrobench.base.atomic",
}

__all__ = [
    "check_rng",
    "check_fs",
    "real_number",
    "positive_number",
    "FieldRange",
    "check_ranges",
    "field_range",
    "range_error",
    "MemoryLimitError",
    "available_memory",
    "memory_limit",
    "check_memory",
    "AtomicWriteError",
    "atomic_path",
    "atomic_folder",
    "ensure_free_space",
]

if TYPE_CHECKING:  # pragma: no cover - for type checkers and IDEs only
    from gyrobench.base.atomic import AtomicWriteError as AtomicWriteError
    from gyrobench.base.atomic import atomic_folder as atomic_folder
    from gyrobench.base.atomic import atomic_path as atomic_path
    from gyrobench.base.atomic import ensure_free_space as ensure_free_space
    from gyrobench.base.memory import MemoryLimitError as MemoryLimitError
    from gyrobench.base.memory import available_memory as available_memory
    from gyrobench.base.memory import check_memory as check_memory
    from gyrobench.base.memory import memory_limit as memory_limit
    from gyrobench.base.ranges import FieldRange as FieldRange
    from gyrobench.base.ranges import check_ranges as check_ranges
    from gyrobench.base.ranges import field_range as field_range
    from gyrobench.base.ranges import range_error as range_error
    from gyrobench.base.validate import check_fs as check_fs
    from gyrobench.base.validate import check_rng as check_rng
    from gyrobench.base.validate import positive_number as positive_number
    from gyrobench.base.validate import real_number as real_number


__getattr__, __dir__ = attach(__name__, _LAZY)
