"""The cluster times of a curve: automatic lists (octave, decade, all) or the user's taus, checked."""

from __future__ import annotations

import math
import os
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gyrobench.analysis.allan._kinds import STATISTICS, _distinct
from gyrobench.analysis.allan._octave import _BLOCK

#: automatic tau lists
TAU_CHOICES = ("octave", "decade", "all")


#: taus="all": largest number of (sample, tau) pairs computed, ~1-2 min at the measured
#: 2.8e8 pairs/s of the blockwise per-tau pass (2 shared cores)
_ALL_TAUS_MAX_WORK = 2e10
#: bytes per tau of the curve and its work (tau, m, deviation, bounds, terms, edf, alpha)
_BYTES_PER_TAU = 8 * 10


def _available_memory() -> float:
    """Available physical memory [bytes] (sysconf; inf where the platform does not say)."""
    try:
        return float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):  # pragma: no cover - non-POSIX
        return math.inf


def _check_all_taus(n: int, n_tau: int) -> None:
    """Refuse taus='all' that would not fit in memory or would run for hours, in one line."""
    mem = 8.0 * (n + 1) + _BYTES_PER_TAU * n_tau + 16 * _BLOCK * 8
    avail = _available_memory()
    if mem > 0.8 * avail:
        raise ValueError(
            f"taus='all' on {n} samples means {n_tau} taus and about {mem / 2**30:.3g} GiB, more than 80 % of the "
            f"{avail / 2**30:.3g} GiB available: use taus='octave' or 'decade', or a shorter segment"
        )
    work = float(n) * n_tau
    if work > _ALL_TAUS_MAX_WORK:
        raise ValueError(
            f"taus='all' on {n} samples means {n_tau} taus, {work:.3g} sample-tau pairs (about "
            f"{work / 2.8e8 / 60:.3g} min here; the limit is {_ALL_TAUS_MAX_WORK:.0e}, ~1-2 min): use taus='octave' "
            f"or 'decade', or a shorter segment (n <= {int(math.sqrt(4 * _ALL_TAUS_MAX_WORK))} samples)"
        )


def _resolve_m(taus: Any, fs: float, n: int, kind: str) -> NDArray[np.int64]:
    """The averaging factors m of ``taus`` for n samples of the ``kind`` statistic, checked."""
    stat = STATISTICS[kind]
    if isinstance(taus, str):
        if taus not in TAU_CHOICES:
            raise ValueError(f"taus must be one of {TAU_CHOICES} or an array of tau [s]; got {taus!r}")
        m_max = min(n // stat.stop_ratio, stat.max_m(n))
        if m_max < 1:
            raise ValueError(
                f"rate has too few samples for the {kind} deviation: need at least "
                f"{stat.stop_ratio} samples for taus={taus!r}; got {n}"
            )
        if taus == "octave":
            m = 2 ** np.arange(int(math.floor(math.log2(m_max))) + 1)
        elif taus == "decade":
            k = int(math.floor(math.log10(m_max)))
            m = np.array([f * 10**j for j in range(k + 1) for f in (1, 2, 4)])
        else:
            _check_all_taus(n, m_max)
            m = np.arange(1, m_max + 1)
        m = m[m <= m_max]
        return m.astype(np.int64)
    t = np.asarray(taus, dtype=float)
    if t.ndim == 0:
        t = t[None]
    if t.ndim != 1 or t.size == 0:
        raise ValueError(f"taus must be one of {TAU_CHOICES} or a non-empty 1-D array of tau [s]; got {taus!r}")
    if not np.all(np.isfinite(t) & (t > 0)):
        raise ValueError(f"taus must be finite and > 0 s; got {t!r}")
    mf = t * fs
    m = np.rint(mf)
    bad = np.abs(mf - m) > 1e-6 * np.maximum(m, 1.0)
    if np.any(bad) or np.any(m < 1):
        i = int(np.flatnonzero(bad | (m < 1))[0])
        raise ValueError(f"taus must be multiples of 1/fs = {1 / fs!r} s; got tau = {float(t[i])!r} s")
    m = _distinct(m.astype(np.int64))
    m_max = stat.max_m(n)
    if m[-1] > m_max:
        need = stat.samples_needed(int(m[-1]))
        raise ValueError(
            f"rate has too few samples for tau = {float(m[-1] / fs)!r} s (m = {int(m[-1])}) in the {kind} deviation: "
            f"the largest tau with at least 2 terms is {float(m_max / fs)!r} s for {n} samples "
            f"(need about {need} samples)"
        )
    return m

