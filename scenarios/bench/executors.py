"""Where seeds and units run: the local pool size, the pickling check before a pool, notes on
errors. Shared by the bench's campaigns and the units runner (:mod:`gyrobench.scenarios.units`).
"""

from __future__ import annotations

import os
import pickle
from typing import Any

__all__ = ["add_note", "check_picklable", "default_workers"]


def default_workers() -> int:
    """The usable CPUs of this process (its affinity mask), at least 1: the default size of a
    local process pool."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def add_note(exc: BaseException, text: str) -> None:
    """Add ``text`` to ``exc``'s notes (shown under its traceback; Python >= 3.11, else nothing)."""
    if hasattr(exc, "add_note"):  # Python >= 3.11
        exc.add_note(text)


def check_picklable(compensator: Any, config: Any) -> None:
    """Check the compensator and the configuration pickle, before they are sent to workers.

    Raises
    ------
    TypeError
        Naming which does not pickle and what to use instead.
    """
    for what, obj in (("compensator", compensator), ("config", config)):
        try:
            pickle.dumps(obj)
        except Exception as exc:  # noqa: BLE001 - pickling raises many kinds
            raise TypeError(
                f"{what} must pickle to run in worker processes (use a module-level function "
                "or class, "
                f"not a lambda or closure, or workers=0); got {obj!r}: {exc}"
            ) from None
