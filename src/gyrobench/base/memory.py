"""Memory estimates, checked before allocating: the one place gyrobench decides "too big".

Every path that builds a large array (a scenario's recordings, an HDF5 channel read
back, an Allan analysis, a campaign's seeds) estimates its peak memory with the
functions here and calls :func:`check_memory` first, so a request that cannot fit is
refused in one line (the estimate and the limit) instead of ending in a
``MemoryError`` traceback or the OOM killer.

The limit
---------
``limit = MARGIN x available``, where *available* is the kernel's estimate of memory
that can be allocated without swapping (``MemAvailable`` in ``/proc/meminfo``), further
capped by the cgroup (container) limit ``memory.max - memory.current`` when one is set,
and by the environment variable ``GYROBENCH_MEMORY_LIMIT`` (bytes, or with a suffix
k, M, G: a cap for shared machines, and how the tests make the limit small).
``MARGIN`` = 0.8 leaves room for the interpreter, the libraries and other processes.

The estimates are of the float64 arrays each path holds at its peak (8 bytes per
sample per array); the array counts are stated with each function. They are
estimates, not bounds: allocator overhead and page rounding add a few percent.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

__all__ = [
    "MARGIN",
    "LIMIT_ENV",
    "MemoryLimitError",
    "available_memory",
    "memory_limit",
    "check_memory",
    "format_bytes",
    "series_bytes",
    "allan_bytes",
    "csv_read_bytes",
    "scenario_bytes",
    "check_scenario",
]

#: fraction of the available memory a run may plan to use
MARGIN = 0.8
#: environment variable capping the limit [bytes; suffix k, M, G allowed]
LIMIT_ENV = "GYROBENCH_MEMORY_LIMIT"
#: bytes of one float64 sample
SAMPLE_BYTES = 8


class MemoryLimitError(ValueError):
    """The estimated memory of a run exceeds the limit (:func:`memory_limit`); bad input, exit 2."""


def format_bytes(n: float) -> str:
    """``5.76e9`` -> ``"5.76 GB"`` (decimal units, as ``free -h --si``); inf -> ``"inf B"``."""
    if not math.isfinite(n):
        return f"{n} B"
    if abs(n) < 1000:
        return f"{n:.0f} B"
    for unit in ("kB", "MB", "GB", "TB", "PB"):
        n /= 1000
        if abs(n) < 1000:
            return f"{n:.3g} {unit}"
    return f"{n / 1000:.3g} EB"


def _meminfo_available() -> int | None:
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:  # not Linux: free physical pages
        return int(os.sysconf("SC_AVPHYS_PAGES")) * int(os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return None


def _cgroup_available() -> int | None:
    """``memory.max - memory.current`` of this process's cgroup (v2), or None if unlimited."""
    try:
        rel = ""
        with open("/proc/self/cgroup") as fh:
            for line in fh:
                if line.startswith("0::"):
                    rel = line[3:].strip()
        base = Path("/sys/fs/cgroup") / rel.lstrip("/")
        limit = (base / "memory.max").read_text().strip()
        if limit == "max":
            return None
        return max(0, int(limit) - int((base / "memory.current").read_text().strip()))
    except (OSError, ValueError):
        return None


def _parse_size(text: str) -> int:
    t = text.strip().upper().removesuffix("B")
    factor = {"K": 1e3, "M": 1e6, "G": 1e9, "T": 1e12}.get(t[-1:], 1)
    if factor != 1:
        t = t[:-1]
    try:
        v = float(t) * factor
    except ValueError:
        raise ValueError(
            f"{LIMIT_ENV} must be a size in bytes, with an optional suffix k, M, G (e.g. 2G); "
            f"got {text!r}"
        ) from None
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{LIMIT_ENV} must be > 0 bytes; got {text!r}")
    return int(v)


def available_memory() -> int | None:
    """Bytes that can be allocated without swapping (MemAvailable, capped by the cgroup);
    None if it cannot be told."""
    values = [v for v in (_meminfo_available(), _cgroup_available()) if v is not None]
    return min(values) if values else None


def memory_limit() -> tuple[float, str]:
    """(limit [bytes], how it was set): ``MARGIN`` x available, capped by ``LIMIT_ENV``."""
    avail = available_memory()
    limit, how = math.inf, "memory available: unknown"
    if avail is not None:
        limit, how = MARGIN * avail, f"{MARGIN:.0%} of the {format_bytes(avail)} available"
    env = os.environ.get(LIMIT_ENV, "").strip()
    if env:
        cap = _parse_size(env)
        if cap < limit:
            limit, how = float(cap), f"{LIMIT_ENV}={env}"
    return limit, how


def check_memory(nbytes: float, what: str, *, hint: str = "") -> float:
    """Refuse, before allocating, a run whose estimated peak memory exceeds :func:`memory_limit`.

    Parameters
    ----------
    nbytes : float
        Estimated peak memory of the run [bytes] (inf or NaN: refused).
    what : str
        What needs it, named in the message (``"simulate static_noise (2 recordings of
        7.2e8 samples)"``).
    hint : str
        What to do instead (default: shorten the record or lower the sample rate).

    Returns
    -------
    float
        ``nbytes``.

    Raises
    ------
    MemoryLimitError
        One line: the estimate, the limit and how the limit was set.
    """
    limit, how = memory_limit()
    if not (nbytes <= limit):  # NaN and inf are refused too
        hint = hint or "shorten the record or lower the sample rate"
        raise MemoryLimitError(
            f"{what} needs about {format_bytes(nbytes)} of memory, more than the limit of "
            f"{format_bytes(limit)} ({how}): {hint}"
        )
    return nbytes


def series_bytes(n_samples: float, n_series: float = 1) -> float:
    """Bytes of ``n_series`` float64 series of ``n_samples`` samples each (a float: never
    overflows)."""
    return float(n_samples) * float(n_series) * SAMPLE_BYTES


#: float64 working arrays of n samples an Allan analysis holds besides its input: the
#: overlapping and standard kinds (analysis.allan: phase x (n + 1) and one block-sum array
#: s (n), plus blocks) ~2; the allantools kinds (modified, hadamard, total: phase,
#: extended or differenced copies) ~4. Rounded up, as an estimate.
ALLAN_WORK_ARRAYS = {"overlapping": 3, "standard": 3, "modified": 5, "hadamard": 5, "total": 6}


def allan_bytes(n_samples: float, kind: str = "overlapping") -> float:
    """Estimated peak bytes of an Allan analysis of ``n_samples`` samples, input included."""
    return series_bytes(n_samples, 1 + ALLAN_WORK_ARRAYS.get(kind, 6))


#: copies of a CSV's text a read holds at its peak (gyrobench.io.logs: the bytes read, the
#: decoded text, the data rows' text, and their lines or their one-line copy for the parser), and the
#: float64 arrays per parsed cell (the result and numpy.loadtxt's growing buffer). Measured on a 93 MB,
#: 1e6-row, 7-column CSV: 354 MB peak (tracemalloc) against the 482 MB this estimates.
CSV_TEXT_COPIES = 4
CSV_CELL_ARRAYS = 2


def csv_read_bytes(n_bytes: float, cells_per_byte: float) -> float:
    """Estimated peak bytes of reading a CSV of ``n_bytes`` bytes of text holding ``cells_per_byte``
    cells per byte (separators and line ends per byte of a sample of it):
    ``CSV_TEXT_COPIES n_bytes + CSV_CELL_ARRAYS 8 cells_per_byte n_bytes``."""
    return float(n_bytes) * (CSV_TEXT_COPIES + CSV_CELL_ARRAYS * SAMPLE_BYTES * float(cells_per_byte))


def scenario_bytes(module, config) -> float | None:
    """Estimated peak memory of a scenario's ``simulate`` / ``run`` for ``config`` [bytes].

    A scenario module states its own estimate as a module-level function
    ``memory_estimate(config) -> float`` (its recordings and their analysis); None when
    it does not define one (the run is then not checked).
    """
    fn = getattr(module, "memory_estimate", None)
    return float(fn(config)) if callable(fn) else None


def check_scenario(module, config, what: str) -> None:
    """:func:`check_memory` for a scenario's run, when it states an estimate
    (:func:`scenario_bytes`)."""
    est = scenario_bytes(module, config)
    if est is not None:
        check_memory(est, what, hint="shorten the records or lower the sample rate in --config")
