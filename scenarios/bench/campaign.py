"""Campaigns: score a compensator on a scenario over many seeds, resuming from the store.

:func:`run_campaign` scores many seeds on any :class:`concurrent.futures.Executor` (local
processes by default; ``distributed.Client(address).get_executor()`` for a dask cluster).
Only the calling process writes the database (:mod:`gyrobench.scenarios.runner.store`):
one transaction per finished seed. Running the same campaign again (same
:func:`~gyrobench.scenarios.bench.identity.campaign_id`) reads the seeds already stored and
computes only the others.
"""

from __future__ import annotations

import concurrent.futures as cf
import dataclasses
import math
import os
import sqlite3
import types
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, NoReturn

import numpy as np
from numpy.typing import NDArray

from gyrobench.scenarios.base import check_pool
from gyrobench.scenarios.bench.compensators import (
    CompensatorError,
    CompensatorImportError,
    FailedSeedsError,
    compensator_label,
    resolve_compensator,
)
from gyrobench.scenarios.bench.identity import campaign_id_of, compensator_identity
from gyrobench.scenarios.bench.jobs import (
    DEFAULT_SEED_TIMEOUT_S,
    MEMORY_FAILURE,
    TIMEOUT_FAILURE,
    check_seed_timeout,
    score_job,
    score_job_remote,
)
from gyrobench.scenarios.bench.sandbox import (
    DEFAULT_MEMORY_BYTES,
    Zygote,
    ZygoteError,
    reads_fingerprint,
    shared_zygote,
)
from gyrobench.scenarios.bench.sandboxed import CampaignReads, run_sandboxed
from gyrobench.scenarios.bench.scoring import resolve_scenario
from gyrobench.scenarios.bench.seeds import check_seeds, parse_seeds, seed_text
from gyrobench.scenarios.bench.statistics import ScoreSummary, order_scores, summarize
from gyrobench.scenarios.cli import exits
from gyrobench.scenarios.runner.executors import add_note, check_picklable, contained_map, stop_pool
from gyrobench.scenarios.runner.store import DEFAULT_DB, campaign_generation, connect_db, record_seed, start_session

__all__ = ["Campaign", "run_campaign"]


@dataclass(frozen=True, slots=True, kw_only=True)
class Campaign:
    """Scores of one compensator on one scenario over a set of seeds.

    Attributes
    ----------
    campaign_id : str
        Hash identifying scenario + configuration + code + compensator.
    scenario, compensator, config : str
        Human-readable descriptions.
    scores : mapping
        seed -> {score name: value}, in seed order (a failed seed's scores are those
        computed before it failed, possibly non-finite).
    computed, reused : int
        Seeds computed by this call / read back from the database.
    db : str
        The SQLite file holding the campaign's seeds.
    failed : mapping
        seed -> why it failed (a non-finite prediction or score), for the failed seeds.
        Summaries leave them out; :func:`compare` and :func:`save_baseline` refuse them.
    """

    campaign_id: str
    scenario: str
    compensator: str
    config: str
    scores: Mapping[int, Mapping[str, float]]
    computed: int = 0
    reused: int = 0
    db: str = ""
    failed: Mapping[int, str] = dataclasses.field(default_factory=dict)

    @property
    def seeds(self) -> tuple[int, ...]:
        return tuple(self.scores)

    @property
    def score_names(self) -> list[str]:
        names: set[str] = set()
        for s in self.scores.values():
            names.update(s)
        return order_scores(names)

    @property
    def ok_seeds(self) -> tuple[int, ...]:
        """The seeds that did not fail."""
        return tuple(s for s in self.scores if s not in self.failed)

    def values(self, name: str, seeds: Sequence[int] | None = None) -> NDArray[np.float64]:
        """The score ``name`` for each seed (NaN where a seed lacks it)."""
        seeds = self.seeds if seeds is None else seeds
        return np.array([self.scores[s].get(name, math.nan) for s in seeds], dtype=float)

    def summary(self, level: float = 0.95) -> dict[str, ScoreSummary]:
        """Per score: mean over the seeds that did not fail, with a ``level`` confidence interval.

        Student t for scores of either sign; for scores non-negative by nature a
        lognormal (modified Cox) interval that stays > 0 (see :func:`summarize`).
        """
        ok = self.ok_seeds
        return {n: summarize(n, self.values(n, ok), level) for n in self.score_names}

    def failure_text(self, limit: int = 10) -> str:
        """One line naming the failed seeds and the first reasons ("" when none failed)."""
        if not self.failed:
            return ""
        seeds = sorted(self.failed)
        first = seeds[0]
        return (
            f"compensator {self.compensator} failed on {len(seeds)} of {len(self.scores)} seeds "
            f"of {self.scenario} (seeds {seed_text(seeds, limit)}); seed {first}: "
            f"{self.failed[first]}"
        )


def run_campaign(
    scenario: str | types.ModuleType,
    compensator: Any,
    seeds: Iterable[int] | str,
    *,
    config: Any = None,
    executor: cf.Executor | None = None,
    workers: int | None = None,
    db: str | os.PathLike = DEFAULT_DB,
    progress: bool = True,
    seed_timeout: float | None = DEFAULT_SEED_TIMEOUT_S,
    seed_memory: int | None = DEFAULT_MEMORY_BYTES,
    sandbox: bool = True,
) -> Campaign:
    """Score ``compensator`` on ``scenario`` for every seed, resuming from ``db``.

    Parameters
    ----------
    scenario : str or module
        Registered name, importable module path or module with ``compensation_task``.
    compensator : estimator, estimator class, fit function or "module:attr"
        See the module docstring. It must pickle (module-level functions and
        classes do; lambdas do not) unless ``workers=0`` (forked, nothing is pickled in).
    seeds : iterable of int or str
        Distinct seeds >= 0, or the text forms of :func:`parse_seeds`.
    config : scenario Config, optional
        Defaults to ``Config()``.
    executor : concurrent.futures.Executor, optional
        Where seeds run, e.g. ``distributed.Client(addr).get_executor()``; it must
        be able to import the scenario module and the compensator's module. Not
        shut down by this function.
    workers : int, optional
        Size of the local process pool when ``executor`` is None (default: the
        usable CPUs). ``0`` runs the seeds one after another, each in its own forked
        process (the compensator need not pickle; its results and exceptions do), so an
        ``os._exit`` or a crash in it fails that seed only.
    db : path
        SQLite file holding every finished seed (created if absent, in an
        existing folder: folders are not created).
    progress : bool
        Show a tqdm progress bar on stderr.
    seed_timeout : float or None
        Per-seed time limit [s] (default :data:`DEFAULT_SEED_TIMEOUT_S`, 600 s; None: none).
        A seed past it, or whose compensator calls ``sys.exit`` or predicts complex values,
        is failed with that reason (a timed-out seed is not stored: a rerun retries it). The
        limit is kept by this process, which kills the compensator's process group; it covers
        the compensator's import too.
    seed_memory : int or None
        Address-space cap [bytes] of the compensator's process per seed (``RLIMIT_AS``, default
        :data:`~gyrobench.scenarios.bench.sandbox.DEFAULT_MEMORY_BYTES`, 4 GiB; None: none). A
        seed past it fails (not stored: a rerun retries it).
    sandbox : bool
        True (the default): the compensator runs in its own process, which receives only the
        training data and the held-out features (:mod:`~gyrobench.scenarios.bench.sandbox`);
        scores are computed outside it and a score below the noise floor fails the seed
        (:mod:`~gyrobench.scenarios.bench.floor`). False runs it in the scoring process: only
        for trusted code (the bench's own references).

    Returns
    -------
    Campaign
        Scores for ``seeds`` in the order given.

    Raises
    ------
    CompensatorError
        If the compensator fails on a seed (see :func:`score_seed`); the message
        adds how many finished seeds are kept in ``db``. Seeds finished before the
        failure are committed; a rerun resumes from them.
    ValueError, TypeError
        Bad scenario, compensator, seeds or db. Any other exception inside a seed
        (a bug in the scenario) is re-raised as is, with a note naming the seed,
        after the seeds already finished are committed.
    """
    module = resolve_scenario(scenario)
    if _is_uncompensated(compensator):
        sandbox = False  # the bench's own raw-output reference: it never predicts, so nothing runs sandboxed
    # a "module:attr" string is imported only in the compensator's own process (the sandbox)
    comp = compensator if sandbox and isinstance(compensator, str) else resolve_compensator(compensator)
    seeds = parse_seeds(seeds) if isinstance(seeds, str) else check_seeds(seeds)
    if config is None:
        config = module.Config()
    check_pool(executor, workers)
    seed_timeout = check_seed_timeout(seed_timeout)
    seed_memory = check_seed_memory(seed_memory)
    zygote = _start_zygote(comp, seed_timeout, seed_memory, seeds) if sandbox else None
    try:
        ident = zygote.identity if zygote is not None else compensator_identity(comp)
        plan = _Plan(
            module=module,
            compensator=comp,
            config=config,
            campaign_id=campaign_id_of(module, config, ident),
            label=compensator_label(comp, compensator),
            short=compensator_label(comp, compensator, short=True),
            name=getattr(module, "NAME", module.__name__),
            db=str(db),
            seed_timeout=seed_timeout,
            seed_memory=seed_memory,
            zygote=zygote,
        )
        return _run_plan(plan, seeds, ident, executor=executor, workers=workers, progress=progress)
    finally:
        if zygote is not None and not zygote.shared:
            zygote.close()


#: the shortest time limit [s] on importing the compensator (the per-seed limit, but never less:
#: a fresh interpreter importing numpy and scikit-learn takes seconds on a loaded machine)
IMPORT_TIMEOUT_FLOOR_S = 30.0


def _is_uncompensated(compensator: object) -> bool:
    """True for the bench's raw-output reference, by object or by its ``module:attr`` name."""
    from gyrobench.scenarios.bench.references import Uncompensated

    if isinstance(compensator, str):
        return compensator.replace(" ", "") == "gyrobench.scenarios.bench.references:Uncompensated"
    return compensator is Uncompensated or isinstance(compensator, Uncompensated)


def _start_zygote(comp: Any, seed_timeout: float | None, seed_memory: int | None, seeds: Sequence[int]) -> Zygote:
    """The compensator's process (:class:`~gyrobench.scenarios.bench.sandbox.Zygote`); its import
    failing, exiting or hanging is one error naming it."""
    label = comp if isinstance(comp, str) else compensator_label(comp, comp, short=True)
    timeout = None if seed_timeout is None else max(seed_timeout, IMPORT_TIMEOUT_FLOOR_S)
    try:
        return shared_zygote(comp, memory=seed_memory, timeout=timeout)
    except ZygoteError as exc:
        if exc.kind == "bad":
            raise ValueError(str(exc)) from None
        if exc.kind == "named":
            raise CompensatorImportError(str(exc), traceback_text=exc.traceback_text) from None
        if exc.kind in ("raised", "exited"):
            raise CompensatorImportError(f"compensator {label}: {exc}", traceback_text=exc.traceback_text) from None
        limit = f" (the per-seed time limit, --seed-timeout, and at least {IMPORT_TIMEOUT_FLOOR_S:g} s)"
        raise FailedSeedsError(
            f"compensator {label} failed on all {len(seeds)} seeds (seeds {seed_text(list(seeds))}): {exc}"
            + (limit if exc.kind == "hung" else ""),
            seeds=list(seeds),
        ) from None


def check_seed_memory(value: Any) -> int | None:
    """``value`` as a per-seed memory cap in bytes: an integer >= 256 MiB, or None (no cap)."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value < 2**28:
        raise ValueError(f"seed_memory must be a number of bytes >= 268435456 (256 MiB), or None; got {value!r}")
    return int(value)


def _run_plan(
    plan: _Plan, seeds: Sequence[int], ident: str, *, executor: cf.Executor | None, workers: int | None,
    progress: bool,
) -> Campaign:
    """Open the store, read back the finished seeds, compute the others."""
    config, db = plan.config, plan.db
    conn = connect_db(db)
    try:
        reads = None
        if plan.zygote is not None:  # what the compensator read is part of the campaign's identity
            cid, names = campaign_generation(conn, plan.campaign_id, reads_fingerprint)
            reads = CampaignReads(conn, cid, plan.campaign_id, names)
            reads.add(plan.zygote.import_reads)
            plan = dataclasses.replace(plan, campaign_id=cid)
        session = start_session(
            conn,
            plan.campaign_id,
            seeds,
            scenario=plan.name,
            compensator=plan.label,
            config=repr(config),
            identity=ident,
        )
        recorder = _Recorder(conn, plan, session.session_id, session.done, session.failed, reads)
        todo = [s for s in seeds if s not in session.done]
        if todo:
            _compute(plan, todo, recorder, total=len(seeds), executor=executor, workers=workers, progress=progress)
        if reads is not None:
            reads.save()
            reads.warn_unseen(plan.short)
        return Campaign(
            campaign_id=plan.campaign_id,
            scenario=plan.name,
            compensator=plan.label,
            config=repr(config),
            scores={s: recorder.done[s] for s in seeds},
            computed=len(todo),
            reused=len(session.done),
            db=plan.db,
            failed={s: recorder.failed[s] for s in seeds if s in recorder.failed},
        )
    finally:
        conn.close()


@dataclass(frozen=True, slots=True, kw_only=True)
class _Plan:
    """What every step of one campaign needs: the resolved scenario, compensator and
    configuration, the campaign id, the compensator's labels (full, and short for errors),
    the scenario's name and the database path."""

    module: types.ModuleType
    compensator: Any
    config: Any
    campaign_id: str
    label: str
    short: str
    name: str
    db: str
    seed_timeout: float | None = None
    seed_memory: int | None = None
    zygote: Zygote | None = None


class _Recorder:
    """Commits finished seeds to the open database and keeps what is stored (``done``,
    ``failed``), so an error can say how many seeds a rerun will resume from."""

    def __init__(
        self,
        conn: sqlite3.Connection,
        plan: _Plan,
        session_id: int,
        done: Mapping[int, Mapping[str, float]],
        failed: Mapping[int, str],
        reads: CampaignReads | None = None,
    ) -> None:
        self.conn, self.plan, self.session_id = conn, plan, session_id
        self.done: dict[int, Mapping[str, float]] = dict(done)
        self.failed: dict[int, str] = dict(failed)
        self.reads = reads

    def add_reads(self, names: Mapping[str, Any] | None) -> None:
        """A seed's reads, stored at once when they add a name (a kill loses none)."""
        if self.reads is not None:
            self.reads.add(names)
            self.reads.save()

    def __call__(self, seed: int, scores: dict[str, float], elapsed: float, failure: str | None) -> None:
        if failure is not None and failure.startswith((TIMEOUT_FAILURE, MEMORY_FAILURE)):  # a rerun retries it
            self.done[seed], self.failed[seed] = dict(scores), failure
            return
        stored, failure = record_seed(
            self.conn, self.plan.campaign_id, self.session_id, seed, scores, elapsed, failure, db=self.plan.db
        )
        self.done[seed] = stored  # exactly what a resume reads back
        if failure is not None:
            self.failed[seed] = failure

    def kept(self) -> str:
        """What is left in the database for a rerun, in words."""
        n = len(self.done)
        if n == 0:
            return f"no seed had finished (nothing stored in {self.plan.db!r})"
        return (
            f"the {n} finished seed{'s are' if n != 1 else ' is'} kept in {self.plan.db!r} "
            "(a rerun resumes from them)"
        )


def _compute(
    plan: _Plan,
    todo: Sequence[int],
    recorder: _Recorder,
    *,
    total: int,
    executor: cf.Executor | None,
    workers: int | None,
    progress: bool,
) -> None:
    """Score the seeds of ``todo`` one at a time (``workers=0``) or on a pool, recording each,
    with a progress bar over all ``total`` seeds. Without an ``executor`` every seed runs in its
    own forked process (:func:`_run_contained`), also with ``workers=0``: an ``os._exit`` or a
    segfault in the compensator ends that process only, never the campaign."""
    from tqdm import tqdm

    bar = tqdm(
        total=total,
        initial=total - len(todo),
        disable=not progress,
        desc=f"{plan.name} seeds",
        unit="seed",
        dynamic_ncols=True,
    )
    try:
        if plan.zygote is not None and executor is None:  # the compensator in its own process per seed
            _check_memory(plan, todo, workers)
            run_sandboxed(plan, todo, recorder, bar, workers=1 if workers == 0 else workers, on_error=_raise_seed_error)
        elif executor is None and workers == 0:  # one seed at a time, each in its own forked process
            _run_contained(plan, todo, recorder, bar, workers=1)
        else:
            _run_on_pool(plan, todo, recorder, bar, executor=executor, workers=workers)
    finally:
        bar.close()


def _run_on_pool(
    plan: _Plan,
    todo: Sequence[int],
    recorder: _Recorder,
    bar: Any,
    *,
    executor: cf.Executor | None,
    workers: int | None,
) -> None:
    """Score the seeds on ``executor``, or on a local process pool of ``workers`` (checked to fit
    in memory first), recording each as it finishes."""
    check_picklable(plan.compensator, plan.config)
    own = executor is None
    if own:
        _check_memory(plan, todo, workers)
    if executor is None:
        _run_contained(plan, todo, recorder, bar, workers=workers)
        return
    ex: cf.Executor = executor
    futures: dict[cf.Future, int] = {}
    ok = False
    try:
        if plan.zygote is not None:  # each job starts its own sandbox where it runs
            futures = {
                ex.submit(score_job_remote, plan.module.__name__, plan.compensator, s, plan.config, plan.short,
                          plan.seed_timeout, plan.seed_memory): s
                for s in todo
            }
        else:
            futures = {
                ex.submit(score_job, plan.module.__name__, plan.compensator, s, plan.config, plan.short,
                          plan.seed_timeout): s
                for s in todo
            }
        for fut in cf.as_completed(futures):
            seed = futures[fut]
            try:
                result = fut.result()
            except Exception as exc:
                _raise_seed_error(exc, seed, plan, recorder)
            if len(result) > 4:
                recorder.add_reads(result[4])
            recorder(*result[:4])
            bar.update(1)
        ok = True
    finally:
        for f in futures:
            f.cancel()
        if own:
            stop_pool(ex, kill=not ok)  # Ctrl-C, SIGTERM or an error: stuck workers are killed


def _run_contained(plan: _Plan, todo: Sequence[int], recorder: _Recorder, bar: Any, *, workers: int | None) -> None:
    """Score each seed in its own local process (:func:`~gyrobench.scenarios.runner.executors.contained_map`):
    a compensator that ends its process (``os._exit``, a segfault) or hangs past the seed time
    limit (plus a grace of :data:`_KILL_GRACE_S`, for code the in-process limit cannot interrupt)
    fails that seed with the reason; a process killed by SIGKILL (the OOM killer) is an internal
    failure."""
    hard = None if plan.seed_timeout is None else plan.seed_timeout + _KILL_GRACE_S
    jobs = [
        (s, (plan.module.__name__, plan.compensator, s, plan.config, plan.short, plan.seed_timeout)) for s in todo
    ]
    for seed, kind, value in contained_map(score_job, jobs, workers=workers, hard_timeout=hard):
        if kind == "ok":
            recorder(*value)
        elif kind == "err":
            _raise_seed_error(value, seed, plan, recorder)
        elif value == "killed by SIGKILL":
            raise exits.InternalError(
                f"a worker process died while scoring seed {seed} of {plan.name} (killed, or out of memory: "
                f"see 'dmesg'); {recorder.kept()}"
            )
        elif value.startswith("timed out"):
            recorder(seed, {}, 0.0, f"{TIMEOUT_FAILURE} of {plan.seed_timeout:g} s (--seed-timeout; its process was "
                                    "killed)")
        else:
            recorder(seed, {}, 0.0, f"the compensator's process {value}")
        bar.update(1)


#: seconds past the seed time limit after which a seed's process is killed from outside
_KILL_GRACE_S = 30.0


def _check_memory(plan: _Plan, todo: Sequence[int], workers: int | None) -> None:
    """Every local worker holds one seed's task in memory at once: check it fits."""
    from gyrobench.scenarios.runner import units

    units.check_unit_memory(
        plan.module,
        plan.config,
        concurrent=units.concurrent_units(len(todo), workers or None),
        source="its configuration (bench seeds)",
    )


def _raise_seed_error(exc: Exception, seed: int, plan: _Plan, recorder: _Recorder) -> NoReturn:
    """Re-raise what scoring ``seed`` raised, saying what the database keeps: a compensator's
    failure with that context added, a dead worker as an internal error, anything else (a bug
    in the scenario) as is with a note naming the seed."""
    if isinstance(exc, CompensatorError):
        raise exc.with_context(recorder.kept()) from exc
    if isinstance(exc, cf.BrokenExecutor):
        raise exits.InternalError(
            f"a worker process died while scoring seed {seed} of "
            f"{plan.name} (killed, or out of memory: see 'dmesg'); "
            f"{recorder.kept()}"
        ) from exc
    add_note(exc, f"while scoring seed {seed} of {plan.name} ({recorder.kept()})")
    raise exc
