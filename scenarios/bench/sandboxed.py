"""Sandboxed seeds on local processes, and what a campaign's compensator read.

:func:`run_sandboxed` runs a campaign's seeds, each in a scoring process forked from the
campaign's, talking to its own child of the compensator's zygote
(:mod:`~gyrobench.scenarios.bench.sandbox`); :class:`CampaignReads` merges what the children
read and stores it with its fingerprints (:func:`~gyrobench.scenarios.runner.store.record_reads`).
"""

from __future__ import annotations

import contextlib
import os
import signal
import sqlite3
import warnings
from collections.abc import Callable, Mapping, Sequence
from typing import Any

from gyrobench.scenarios.bench.jobs import CHILD_DIED, TIMEOUT_FAILURE, score_sandboxed
from gyrobench.scenarios.bench.sandbox import ChildStatus, kill_group, reads_fingerprint
from gyrobench.scenarios.cli import exits
from gyrobench.scenarios.runner.executors import default_workers
from gyrobench.scenarios.runner.store import record_reads

__all__ = ["CampaignReads", "run_sandboxed"]


class CampaignReads:
    """What a campaign's compensator read, stored with its fingerprints as seeds add names.

    What a campaign's compensator read (module, file and environment names, merged over its
    seeds), stored with its fingerprints (:func:`~gyrobench.scenarios.runner.store.record_reads`)
    whenever a seed adds a name, so a rerun finds the campaign only while they are unchanged.

    Parameters
    ----------
    conn : sqlite3.Connection
        The results database.
    campaign_id : str
        The campaign.
    static_id : str
        Its static id.
    names : mapping of str to object
        The reads already recorded.
    """

    def __init__(self, conn: sqlite3.Connection, campaign_id: str, static_id: str, names: Mapping[str, Any]) -> None:
        self.conn, self.campaign_id, self.static_id = conn, campaign_id, static_id
        self.names: dict[str, Any] = {"modules": {}, "files": [], "env": [], "env_all": False, "unseen": []}
        self.dirty = True
        self.add(names)
        self.dirty = not names

    def add(self, names: Mapping[str, Any] | None) -> None:
        """Merge one seed's (or the import's) reads."""
        if not names:
            return
        n = self.names
        modules = {**n["modules"], **{str(k): str(v) for k, v in dict(names.get("modules") or {}).items()}}
        files = sorted(set(n["files"]) | {str(f) for f in names.get("files") or ()})
        env = sorted(set(n["env"]) | {str(e) for e in names.get("env") or ()})
        unseen = sorted(set(n["unseen"]) | {str(u) for u in names.get("unseen") or ()})
        env_all = bool(n["env_all"] or names.get("env_all"))
        new = {"modules": modules, "files": files, "env": env, "env_all": env_all, "unseen": unseen}
        if new != n:
            self.names, self.dirty = new, True

    def save(self) -> None:
        """Store the names and their fingerprints, if a seed added any."""
        if self.dirty:
            record_reads(self.conn, self.campaign_id, self.static_id, self.names, reads_fingerprint(self.names))
            self.dirty = False

    def warn_unseen(self, label: str) -> None:
        """One warning line naming what the identity cannot see, when the compensator used it."""
        if self.names["unseen"]:
            warnings.warn(
                f"compensator {label} used {', '.join(self.names['unseen'])}: what it read through them is not "
                "part of the campaign's identity (a change there does not start a new campaign)",
                RuntimeWarning,
                stacklevel=3,
            )


def run_sandboxed(
    plan: Any, todo: Sequence[int], recorder: Any, bar: Any, *, workers: int | None, on_error: Callable
) -> None:
    """Score the seeds of a campaign's plan in sandboxed processes.

    Score each seed of ``plan`` (a campaign's plan) in a forked scoring process of this one,
    talking to a child of the compensator's zygote (:mod:`~gyrobench.scenarios.bench.sandbox`), at
    most ``workers`` seeds at once. This process keeps every deadline: at a seed's end, and at its deadline, it SIGKILLs
    the child's process group (and, at the deadline, the scoring process). ``recorder`` records a
    seed's outcome and its reads; ``on_error(exc, seed, plan, recorder)`` raises what a seed's
    scoring process raised.

    Parameters
    ----------
    plan : CampaignPlan
        The campaign's plan.
    todo : sequence of int
        The seeds to score.
    recorder : callable
        Stores each finished seed.
    bar : tqdm.tqdm or None
        The progress bar.
    workers : int or None
        Seeds at once.
    on_error : callable
        Called with each seed's failure.
    """
    import multiprocessing as mp
    import time
    from multiprocessing.connection import wait

    from gyrobench.scenarios.runner.executors import _contained_child, _relink, death_reason

    assert plan.zygote is not None
    zygote = plan.zygote
    ctx = mp.get_context("fork")
    pending = list(reversed(todo))
    limit = max(1, workers or default_workers())
    running: dict[Any, tuple[int, Any, int, float]] = {}  # result pipe -> (seed, scorer, child pid, start)
    try:
        while pending or running:
            while pending and len(running) < limit:
                seed = pending.pop()
                pid, sock = zygote.fork()
                recv, send = ctx.Pipe(duplex=False)
                args = (plan.module.__name__, seed, plan.config, plan.short, sock.fileno(), plan.seed_memory)
                job = (send, os.getpid(), score_sandboxed, args)
                proc = ctx.Process(target=_contained_child, args=job, daemon=True)
                proc.start()
                send.close()
                sock.close()
                running[recv] = (seed, proc, pid, time.monotonic())
            timeout = None
            if plan.seed_timeout is not None:
                oldest = min(start for *_, start in running.values())
                timeout = max(0.0, oldest + plan.seed_timeout - time.monotonic())
            ready = wait(list(running), timeout=timeout)
            now = time.monotonic()
            for recv in list(running):
                seed, proc, pid, start = running[recv]
                if recv in ready:
                    try:
                        kind, value = recv.recv()
                        if kind == "err":
                            value = _relink(value)
                    except (EOFError, OSError):
                        proc.join(timeout=5.0)
                        kind, value = "died", death_reason(proc.exitcode)
                elif plan.seed_timeout is not None and now - start >= plan.seed_timeout:
                    proc.kill()
                    kind, value = "timeout", None
                else:
                    continue
                del running[recv]
                recv.close()
                status = zygote.end_child(pid)  # the child's whole process group, also on success
                proc.join(timeout=5.0)
                _record(plan, recorder, seed, kind, value, status, on_error)
                bar.update(1)
    finally:
        for _seed, proc, pid, _start in running.values():
            kill_group(pid)
            with contextlib.suppress(Exception):
                proc.kill()
        for recv, (_seed, proc, pid, _start) in running.items():
            with contextlib.suppress(Exception):
                proc.join(timeout=2.0)
                recv.close()
            with contextlib.suppress(Exception):
                zygote.end_child(pid)


def _record(
    plan: Any, recorder: Any, seed: int, kind: str, value: Any, status: ChildStatus, on_error: Callable
) -> None:
    """Record one seed's outcome (or raise what the compensator's failure means)."""
    if kind == "ok":
        seed_, scores, elapsed, failure, reads = value
        if failure == CHILD_DIED and status.signal == signal.SIGKILL:  # the OOM killer, as for a worker
            raise exits.InternalError(
                f"a worker process died while scoring seed {seed} of {plan.name} (the compensator's process was "
                f"killed by SIGKILL: killed, or out of memory: see 'dmesg'); {recorder.kept()}"
            )
        if failure == CHILD_DIED:
            failure = f"the compensator's process {status.reason()}"
        recorder.add_reads(reads)
        recorder(seed_, scores, elapsed, failure)
    elif kind == "err":
        on_error(value, seed, plan, recorder)
    elif kind == "timeout":
        recorder(seed, {}, 0.0, f"{TIMEOUT_FAILURE} of {plan.seed_timeout:g} s (--seed-timeout; the compensator's "
                                "process group was killed)")
    else:
        raise exits.InternalError(
            f"the scoring process of seed {seed} of {plan.name} {value} (killed, or out of memory: see 'dmesg'); "
            f"{recorder.kept()}"
        )


