"""Seed lists of a bench campaign: parsing ``"0:100"``-style text, checking counts and values.

A campaign's seeds are distinct integers in ``[0, 2**63)`` (the database stores them as
SQLite INTEGER), at most :data:`MAX_SEEDS` of them, and the calling process must be able to
hold one future and one row of scores per seed (:data:`BYTES_PER_SEED`).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np

__all__ = ["BYTES_PER_SEED", "MAX_SEED", "MAX_SEEDS", "check_seeds", "parse_seeds", "seed_text"]


def parse_seeds(text: str) -> tuple[int, ...]:
    """Parse a seed list: a range, a stepped range, a comma list or one seed.

    Parse a seed list: ``"0:100"`` (half-open range, like Python), ``"0:100:5"``,
    ``"1,5,9"`` (a comma list) or ``"7"``.

    Parameters
    ----------
    text : str
        ``"0:100"`` (half-open), ``"0:100:5"``, ``"1,5,9"`` or ``"7"``.

    Returns
    -------
    tuple of int
        The seeds.

    Raises
    ------
    ValueError
        If the text is not of these forms, a seed is negative, the list is empty or
        holds a seed twice.
    """
    if not isinstance(text, str):
        raise TypeError(f"seeds must be a string like '0:100' or '1,5,9'; got {text!r}")
    s = text.strip()
    usage = (
        "seeds must be 'START:STOP' (half-open range), 'START:STOP:STEP' or a comma list "
        f"like '1,5,9' of integers >= 0; got {text!r}"
    )
    try:
        if ":" in s:
            parts = [int(p) for p in s.split(":")]
            if len(parts) not in (2, 3):
                raise ValueError
            if len(parts) == 3 and parts[2] <= 0:
                raise ValueError
            span = range(*parts)
            _check_count(len(span), what=text)  # before building a tuple of 10**12 ints
            seeds = tuple(span)
        else:
            seeds = tuple(int(p) for p in s.split(","))
    except ValueError as exc:
        if str(exc).startswith("seeds must"):
            raise
        raise ValueError(usage) from None
    return check_seeds(seeds, what=text)


#: most seeds one campaign may hold. The bound is what the calling process holds at once:
#: every seed is a submitted future (~1 kB) and a row of scores read back (~1-2 kB for the
#: scenarios' 10-40 scores), so 10**6 seeds take about 2-3 GB, checked against the memory
#: limit too (gyrobench.base.memory); at ~0.5 s per seed it is also ~6 CPU-days of work.
MAX_SEEDS = 10**6
#: largest seed: the database stores seeds as SQLite INTEGER (signed 64-bit)
MAX_SEED = 2**63 - 1
#: bytes one seed costs the calling process (a future and its scores), for the memory check
BYTES_PER_SEED = 3000


def _check_count(n: int, *, what: Any) -> None:
    if n > MAX_SEEDS:
        raise ValueError(
            f"seeds must number at most {MAX_SEEDS} per campaign (each is a future and a row of "
            f"scores held by this process); got {n} in {what!r}: split the campaign"
        )
    from gyrobench.base import memory

    memory.check_memory(
        n * BYTES_PER_SEED, f"a campaign of {n} seeds", hint="use fewer seeds per campaign"
    )


def check_seeds(seeds: Iterable[int], *, what: Any = None) -> tuple[int, ...]:
    """Check a seed list and return it as Python ints.

    ``seeds`` as a tuple of Python ints, checked: integers in [0, MAX_SEED], distinct, at
    least one and at most MAX_SEEDS (and their memory); ``what`` names them in errors.

    Parameters
    ----------
    seeds : iterable of int
        The seeds.
    what : object
        How the messages name them.

    Returns
    -------
    tuple of int
        The seeds as Python ints.
    """
    seeds = tuple(seeds)
    what = seeds if what is None else what
    _check_count(len(seeds), what=what if len(seeds) < 20 else f"{len(seeds)} seeds")
    for s in seeds:
        if isinstance(s, (bool, np.bool_)) or not isinstance(s, (int, np.integer)):
            raise TypeError(f"seeds must be integers >= 0; got {s!r} in {what!r}")
        if s < 0:
            raise ValueError(f"seeds must be integers >= 0; got {int(s)} in {what!r}")
        if s > MAX_SEED:
            raise ValueError(
                f"seeds must be <= 2**63 - 1 = {MAX_SEED} (the database stores them as 64-bit "
                f"integers); got {int(s)} in {what!r}"
            )
    if not seeds:
        raise ValueError(f"seeds must hold at least one seed; got {what!r}")
    seeds = tuple(int(s) for s in seeds)
    if len(set(seeds)) != len(seeds):
        dup = sorted({s for s in seeds if seeds.count(s) > 1})
        raise ValueError(f"seeds must be distinct; got {dup} more than once in {what!r}")
    return seeds


def seed_text(seeds: Sequence[int], limit: int = 10) -> str:
    """``"3:9"`` for a run of consecutive seeds, else a comma list of at most ``limit`` seeds.

    Parameters
    ----------
    seeds : sequence of int
        The seeds.
    limit : int
        The most listed.

    Returns
    -------
    str
        The text.
    """
    s = list(seeds)
    if len(s) > 1 and s == list(range(s[0], s[-1] + 1)):
        return f"{s[0]}:{s[-1] + 1}"
    return ",".join(map(str, s[:limit])) + (f",... ({len(s)} seeds)" if len(s) > limit else "")
