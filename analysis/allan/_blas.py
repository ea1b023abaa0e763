"""BLAS threading of the Allan code: chunked dot products, worker threads, one-thread BLAS limits.

OpenBLAS threads a ddot above 10000 elements and a gemm above m n k = 65536 * 4, which on a
busy machine costs far more than it gains for the products here; these helpers keep the
products below those thresholds or hold the BLAS to one thread (threadpoolctl, a
scikit-learn dependency) while the Allan code runs its own worker threads.
"""

from __future__ import annotations

import contextlib
import functools
import os
import threading
from collections.abc import Callable, Iterator
from concurrent.futures import ThreadPoolExecutor
from typing import Any, ParamSpec, TypeVar

import numpy as np
from numpy.typing import NDArray

from gyrobench.analysis.allan._results import AllanCurve

#: the chunk of each dot product: OpenBLAS threads ddot above 10000 elements, which costs far
#: more than it gains here
_DOT = 8192
#: OpenBLAS runs a gemm on one thread when m n k <= 65536 * GEMM_MULTITHREAD_THRESHOLD (4)
_GEMM_SINGLE = 65536 * 4
#: worker threads of the overlapping estimator (numpy ufuncs and BLAS release the GIL) and
#: the number of terms below which one thread is used
_THREADS = max(1, min(2, os.cpu_count() or 1))
_THREAD_MIN = 1 << 21

_P = ParamSpec("_P")
_R = TypeVar("_R")


def _sumsq(w: NDArray[np.float64]) -> float:
    """sum(w**2) by single-threaded BLAS dot products on chunks of _DOT elements."""
    return float(sum(np.dot(w[c : c + _DOT], w[c : c + _DOT]) for c in range(0, w.size, _DOT)))


def _dot(a: NDArray[np.float64], b: NDArray[np.float64]) -> float:
    """a . b by BLAS dot products on chunks of _DOT elements (OpenBLAS never threads those)."""
    if a.size <= _DOT:
        return float(np.dot(a, b))
    return float(sum(np.dot(a[c : c + _DOT], b[c : c + _DOT]) for c in range(0, a.size, _DOT)))


def _dot_self(w: NDArray[np.float64]) -> float:
    """sum(w**2) in one BLAS call (worker-thread blocks, with the BLAS held to one thread)."""
    return float(np.dot(w, w))


_BLAS_LOCK = threading.Lock()
_blas_users = 0
_blas_limit: Any = None


@functools.lru_cache(maxsize=1)
def _blas_controller() -> Any:
    """One threadpoolctl controller per process: it scans the loaded libraries once (~9 ms)."""
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController()


@contextlib.contextmanager
def _one_blas_thread() -> Iterator[None]:
    """Hold the BLAS to one thread while any caller is inside (reference-counted).

    threadpool_limits is process-wide and restores what it saw on entry, so two overlapping
    plain ``with threadpool_limits(...)`` blocks on different threads can restore in the
    wrong order and leave the BLAS at one thread for good; here the first caller in sets
    the limit and the last one out restores it.
    """
    global _blas_users, _blas_limit
    with _BLAS_LOCK:
        if _blas_users == 0:
            _blas_limit = _blas_controller().limit(limits=1, user_api="blas")
        _blas_users += 1
    try:
        yield
    finally:
        with _BLAS_LOCK:
            _blas_users -= 1
            if _blas_users == 0:
                _blas_limit.restore_original_limits()
                _blas_limit = None


def _segments(n: int) -> list[tuple[int, int]]:
    """Split [0, n) into one contiguous range per worker thread (one range for short records)."""
    k = _THREADS if n >= _THREAD_MIN else 1
    edges = [(n * i) // k for i in range(k + 1)]
    return [(edges[i], edges[i + 1]) for i in range(k) if edges[i + 1] > edges[i]]


def _map(fn, jobs: list) -> list:
    """Run fn over jobs, on threads when there is more than one (numpy releases the GIL)."""
    if len(jobs) == 1:
        return [fn(jobs[0])]
    with ThreadPoolExecutor(len(jobs)) as ex:
        return list(ex.map(fn, jobs))


#: curves with at most this many taus (and records below _THREAD_MIN samples) keep every BLAS
#: product under OpenBLAS's threading thresholds (gemm m n k <= 65536 * 4; dot products are
#: chunked by _DOT), so no thread limit is needed for them
_SMALL_TAUS = 64


def _is_small(args: tuple, kwargs: dict) -> bool:
    """True when a call of allan_deviation/fit_noise makes no BLAS call large enough to thread."""
    first = args[0] if args else kwargs.get("curve_or_rate", kwargs.get("rate"))
    if isinstance(first, AllanCurve):
        return first.tau.size <= _SMALL_TAUS
    taus = kwargs.get("taus", "octave")
    few = (taus in ("octave", "decade")) if isinstance(taus, str) else np.size(taus) <= _SMALL_TAUS
    return few and first is not None and np.size(first) < _THREAD_MIN


def _single_blas(fn: Callable[_P, _R]) -> Callable[_P, _R]:
    """Run ``fn`` with the BLAS held to one thread unless the call is small (:func:`_is_small`).

    The first multithreaded BLAS call of a process costs ~1-2 s of thread start-up on a busy
    virtual machine (measured: 1.9 s, then 0.05 s; single-threaded 0.02 s), and the
    products here are small (<= 65536 x 44); but setting the limit costs ~10-15 ms on first
    use (threadpoolctl scans every loaded library), a third of a whole analysis of a 2e5
    sample record, so calls whose products stay below the threading thresholds skip it.
    The wrapper has the signature of ``fn`` (ParamSpec; functools.wraps), so type checkers
    and IDEs see the wrapped function's parameters and return type (a test runs mypy on it).
    """

    @functools.wraps(fn)
    def wrapper(*args: _P.args, **kwargs: _P.kwargs) -> _R:
        with contextlib.nullcontext() if _is_small(args, kwargs) else _one_blas_thread():
            return fn(*args, **kwargs)

    return wrapper

