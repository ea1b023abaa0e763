"""Where seeds and units run: the local pool (its size, workers that die with their parent,
stopping it at once on Ctrl-C or SIGTERM), the pickling check before a pool, notes on errors.
Shared by the bench's campaigns and the units runner (:mod:`gyrobench.scenarios.runner.units`).
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import os
import pickle
import signal
import sys
from typing import Any

__all__ = ["add_note", "check_picklable", "contained_map", "death_reason", "default_workers", "local_pool", "stop_pool"]

#: prctl option: the signal a process gets when its parent dies (linux/prctl.h)
_PR_SET_PDEATHSIG = 1


def _die_with_parent(parent_pid: int) -> None:
    """Worker initializer: SIGKILL this worker when its parent dies (``prctl(PR_SET_PDEATHSIG)``
    on Linux; elsewhere nothing), exit at once if the parent is already gone, and ignore SIGINT
    (a Ctrl-C reaches the whole process group: the parent alone stops the pool, so a worker
    prints no traceback)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if sys.platform.startswith("linux"):
        import ctypes

        with contextlib.suppress(OSError, AttributeError):
            ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)
    if os.getppid() != parent_pid:  # the parent died before the death signal was set
        os._exit(1)


def local_pool(workers: int | None) -> cf.ProcessPoolExecutor:
    """A local process pool of ``workers`` (default :func:`default_workers`) whose workers die
    with this process (:func:`_die_with_parent`), even when it is SIGKILLed."""
    return cf.ProcessPoolExecutor(
        max_workers=workers or default_workers(), initializer=_die_with_parent, initargs=(os.getpid(),)
    )


def stop_pool(ex: cf.Executor, *, kill: bool) -> None:
    """Shut a local pool down: wait for its workers, or with ``kill`` (Ctrl-C, SIGTERM, an
    error) SIGKILL them first, so a stuck compensator cannot hold the campaign."""
    if kill:
        procs = list((getattr(ex, "_processes", None) or {}).values())
        for p in procs:
            with contextlib.suppress(Exception):
                p.kill()
        ex.shutdown(wait=False, cancel_futures=True)
        for p in procs:
            with contextlib.suppress(Exception):
                p.join(timeout=2.0)
        return
    ex.shutdown(wait=True, cancel_futures=True)


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


def _contained_child(conn: Any, parent_pid: int, fn: Any, args: tuple) -> None:
    """A contained job's process: its result or exception sent back, then ``os._exit(0)`` (a
    thread the job left behind, or an atexit hook, cannot hold it)."""
    _die_with_parent(parent_pid)
    try:
        try:
            msg: tuple[str, Any] = ("ok", fn(*args))
        except BaseException as exc:  # noqa: BLE001 - sent to the parent, which re-raises it
            msg = ("err", _cause_chain(exc))
        try:
            conn.send(msg)
        except Exception as exc:  # noqa: BLE001 - an exception that does not pickle
            first = msg[1][0] if msg[0] == "err" else msg[1]
            conn.send(("err", [RuntimeError(f"{type(first).__name__}: {first} ({exc})")]))
        conn.close()
    finally:
        os._exit(0)


def _cause_chain(exc: BaseException) -> list[BaseException]:
    """``exc`` and its ``__cause__`` chain as a list (pickling an exception drops its cause; the
    parent links them again, :func:`_relink`), each one that does not pickle cut off."""
    chain: list[BaseException] = []
    seen: set[int] = set()
    e: BaseException | None = exc
    while e is not None and id(e) not in seen and len(chain) < 16:
        seen.add(id(e))
        try:
            pickle.dumps(e)
        except Exception as why:  # noqa: BLE001 - an exception that does not pickle ends the chain
            if not chain:
                chain.append(RuntimeError(f"{type(e).__name__}: {e} (it does not pickle: {why})"))
            break
        chain.append(e)
        e = e.__cause__
    return chain


def _relink(chain: list[BaseException]) -> BaseException:
    """The first exception of ``chain`` with each next one as its ``__cause__`` again."""
    for outer, inner in zip(chain[:-1], chain[1:], strict=True):
        outer.__cause__ = inner
    return chain[0]


def death_reason(exitcode: int | None) -> str:
    """Why a job's process ended without a result, in words (``exitcode`` as multiprocessing gives it)."""
    if exitcode is not None and exitcode < 0:
        try:
            name = signal.Signals(-exitcode).name
        except ValueError:
            name = f"signal {-exitcode}"
        return f"killed by {name}"
    return f"exited with code {exitcode} (os._exit or sys.exit outside Python's reach)"


def contained_map(
    fn: Any, jobs: Any, *, workers: int | None, hard_timeout: float | None = None
) -> Any:
    """Run ``fn(*args)`` for each ``(key, args)`` of ``jobs``, each in its own forked process, at
    most ``workers`` at once; yield ``(key, kind, value)`` as each ends: ``"ok"`` and the result,
    ``"err"`` and the exception it raised, or ``"died"`` and why its process ended without one
    (:func:`death_reason`; ``"timed out after N s"`` past ``hard_timeout``, the process killed).

    A job that calls ``os._exit``, segfaults or hangs in C code ends only its own process. Every
    process dies with this one (:func:`_die_with_parent`); leaving the generator early (an error,
    Ctrl-C, SIGTERM) SIGKILLs the running ones.
    """
    import multiprocessing as mp
    import time
    from multiprocessing.connection import wait

    ctx = mp.get_context("fork")
    pending = list(jobs)
    pending.reverse()
    limit = max(1, workers or default_workers())
    running: dict[Any, tuple[Any, Any, float]] = {}  # receiving end -> (key, process, start)
    try:
        while pending or running:
            while pending and len(running) < limit:
                key, args = pending.pop()
                recv, send = ctx.Pipe(duplex=False)
                proc = ctx.Process(target=_contained_child, args=(send, os.getpid(), fn, args), daemon=True)
                proc.start()
                send.close()
                running[recv] = (key, proc, time.monotonic())
            timeout = None
            if hard_timeout is not None:
                oldest = min(start for _, _, start in running.values())
                timeout = max(0.0, oldest + hard_timeout - time.monotonic())
            ready = wait(list(running), timeout=timeout)
            now = time.monotonic()
            for recv in list(running):
                key, proc, start = running[recv]
                if recv in ready:
                    try:
                        kind, value = recv.recv()
                        if kind == "err":
                            value = _relink(value)
                    except (EOFError, OSError):
                        proc.join(timeout=5.0)
                        kind, value = "died", death_reason(proc.exitcode)
                elif hard_timeout is not None and now - start >= hard_timeout:
                    proc.kill()
                    kind, value = "died", f"timed out after {hard_timeout:g} s (killed)"
                else:
                    continue
                del running[recv]
                recv.close()
                proc.join(timeout=5.0)
                yield key, kind, value
    finally:
        for _key, proc, _start in running.values():
            with contextlib.suppress(Exception):
                proc.kill()
        for recv, (_key, proc, _start) in running.items():
            with contextlib.suppress(Exception):
                proc.join(timeout=2.0)
                recv.close()
