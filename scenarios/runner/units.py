"""The shared runner of a paper scenario: simulate N units, judge the claims, build the report.

A paper scenario (see :mod:`gyrobench.scenarios.claims`) defines ``experiment(config,
seed)`` (one unit through the whole pipeline, no formatting), ``CLAIMS``,
``DEVIATIONS`` and ``report(config, units, claims)``. :func:`run_paper` does exactly::

    seeds = range(seed, seed + n_units)
    units = [module.experiment(config, s) for s in seeds]   # on the bench's executor, resumable
    control = [module.experiment(module.control_config(config), s) for s in seeds]  # when it has one
    claims = evaluate(module_claims(module, config), [quantities_of(u) for u in units],
                      [quantities_of(u) for u in control])
    outcome = module.report(config, units, claims)
    outcome.claims, outcome.deviations, outcome.units = claims, list(module.DEVIATIONS), n

Units run where the bench's seeds run (:mod:`gyrobench.scenarios.bench`): a local
process pool (``workers``; ``0`` runs them in this process) or any
:class:`concurrent.futures.Executor`, e.g. ``distributed.Client(addr).get_executor()``.
Every unit runs with the BLAS/OpenMP pools limited to one thread, as the bench's
seeds do, so a unit's result is bit-identical whatever the executor and worker count.

Resumption: each finished unit's result is encoded as JSON with a schema
(:mod:`gyrobench.scenarios.runner.codec`: typed frozen gyrobench dataclasses, tuples, numbers,
strings and numeric arrays; never pickle, so a crafted store runs no code and is refused in one
line), zlib-compressed, and committed to a SQLite file
(one transaction per unit, WAL journal, ``synchronous=FULL``; the bench's
connection), keyed by a run identity (the scenario module's source closure, the
configuration, the gyrobench/numpy/scipy/scikit-learn versions) and the seed. A
reproduction killed at any moment resumes and recomputes no finished unit;
changing the code or the configuration starts afresh rather than mixing units.
Every result, fresh or stored, is the one read back from the file, so a fresh run
and a resumed one hand :func:`evaluate` the same objects.

The store keeps what the claims and the report read (:func:`run_paper`, :func:`slim_result`): a
scenario's ``SLIM_FIELDS`` (data only its figures draw) are kept for the ``REPORT_UNITS`` units its
report draws and emptied in the others; ``keep_units`` keeps every unit whole. A store written by
an older gyrobench (another table layout) is refused in one line.
"""

from __future__ import annotations

import concurrent.futures as cf
import dataclasses
import hashlib
import importlib
import json
import os
import sqlite3
import time
import types
from collections.abc import Callable, Container, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from gyrobench.scenarios.base import Outcome, check_pool
from gyrobench.scenarios.claims import sequential_error, sequential_z
from gyrobench.scenarios.papers.contract import quantities_of

__all__ = [
    "DEFAULT_DB",
    "MAX_SEED",
    "MAX_UNITS",
    "UnitRun",
    "check_run_size",
    "check_unit_memory",
    "concurrent_units",
    "default_db",
    "is_paper_scenario",
    "register_run",
    "run_id",
    "run_ids",
    "run_paper",
    "run_units",
    "slim_result",
]

#: default resume store (in the current directory) when no db is given
DEFAULT_DB = "gyrobench-units.sqlite"

#: the most units one run simulates (``reproduce --units/--max-units/--deviations``, ``n_units``):
#: a claim's pass fraction over 10,000 units has a 95 % interval of at most +-1 percentage point,
#: finer than any claim is stated to; every unit's result is held in memory for the claims and the
#: report, and the fastest paper's unit takes about 0.9 s of CPU (stop 13), so 10,000 units are
#: already hours. Checked in O(1) before any seed list is built (``--units 10000000`` grew without
#: bound before).
MAX_UNITS = 10_000

#: the largest seed a unit may have: seeds are stored as SQLite's signed 64-bit INTEGER
MAX_SEED = 2**63 - 1

_SCHEMA = """
CREATE TABLE IF NOT EXISTS unit_runs (
    run_id TEXT PRIMARY KEY,
    scenario TEXT NOT NULL,
    config TEXT NOT NULL,
    identity TEXT NOT NULL,
    created REAL NOT NULL
);
CREATE TABLE IF NOT EXISTS unit_results (
    run_id TEXT NOT NULL REFERENCES unit_runs(run_id),
    seed INTEGER NOT NULL,
    result BLOB NOT NULL,
    elapsed_s REAL NOT NULL,
    finished REAL NOT NULL,
    full INTEGER NOT NULL,
    PRIMARY KEY (run_id, seed)
);
"""

#: the columns of a unit store this gyrobench writes; a store without them is an older format
_COLUMNS = ("run_id", "seed", "result", "elapsed_s", "finished", "full")


def module_claims(module: types.ModuleType, config: Any) -> tuple[Any, ...]:
    """The claims to judge for ``config``: ``module.claims_for(config)`` where a scenario
    defines it (a config variant that sets an input from a paper number makes that claim
    calibrated), else ``module.CLAIMS``."""
    claims_for = getattr(module, "claims_for", None)
    return tuple(claims_for(config)) if callable(claims_for) else tuple(module.CLAIMS)


def is_paper_scenario(module: types.ModuleType) -> bool:
    """Whether ``module`` has the paper-scenario shape (``experiment`` and ``CLAIMS``).

    Parameters
    ----------
    module : module
        A scenario module.

    Returns
    -------
    bool
        True when it has ``experiment`` and ``CLAIMS``.
    """
    return callable(getattr(module, "experiment", None)) and hasattr(module, "CLAIMS")


@dataclass(frozen=True, slots=True, kw_only=True)
class UnitRun:
    """The units' results in seed order, and how many were computed or read back.

    Parameters
    ----------
    run_id : str
        The run's 16-hex id (:func:`run_id`).
    seeds : tuple of int
        The units' seeds, in order.
    results : tuple of dict
        Each unit's result, in seed order.
    elapsed_s : tuple of float
        Each unit's run time [s].
    computed : int
        Units computed in this run.
    reused : int
        Units read back from the store.
    db : str
        The store's file.
    """

    run_id: str
    seeds: tuple[int, ...]
    results: tuple[dict[str, Any], ...]
    elapsed_s: tuple[float, ...]
    computed: int
    reused: int
    db: str


def run_id(module: types.ModuleType, config: Any) -> tuple[str, str]:
    """(16-hex run id, its JSON identity) of ``module`` with ``config``.

    Parameters
    ----------
    module : module
        The paper scenario.
    config : object
        Its Config.

    Returns
    -------
    tuple of (str, str)
        (16-hex run id, the JSON identity it hashes).
    """
    from gyrobench.scenarios.bench.identity import scenario_identity
    from gyrobench.scenarios.runner.codec import SCHEMA

    ident = dict(scenario_identity(module, config), store_format=SCHEMA)  # old pickled stores never match
    text = json.dumps(ident, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16], text


def run_ids(module: types.ModuleType, configs: Sequence[Any]) -> list[tuple[str, str]]:
    """The :func:`run_id` of ``module`` with each of ``configs``, its source closure hashed once.

    Parameters
    ----------
    module : module
        A paper scenario.
    configs : sequence of the module's Config
        The configurations.

    Returns
    -------
    list of (str, str)
        Each config's (16-hex run id, JSON identity), equal to :func:`run_id`'s.
    """
    from gyrobench.scenarios.bench.identity import canonical, scenario_identity
    from gyrobench.scenarios.runner.codec import SCHEMA

    if not configs:
        return []
    base = dict(scenario_identity(module, configs[0]), store_format=SCHEMA)
    out = []
    for c in configs:
        text = json.dumps(dict(base, config=canonical(c)), sort_keys=True)
        out.append((hashlib.sha256(text.encode()).hexdigest()[:16], text))
    return out


def concurrent_units(n_units: int, workers: int | None) -> int:
    """How many units a local run holds in memory at once.

    How many units a local run holds in memory at once: one per worker process, at most
    ``n_units`` (``workers`` 0: in this process, one at a time; None: the usable CPUs).

    Parameters
    ----------
    n_units : int
        The units of the run.
    workers : int or None
        Worker processes (0: in this process; None: the usable CPUs).

    Returns
    -------
    int
        One per worker, at most ``n_units``.
    """
    from gyrobench.scenarios.runner.executors import default_workers

    if workers == 0:
        return 1
    return max(1, min(int(n_units), workers or default_workers()))


def check_unit_memory(
    module: types.ModuleType, config: Any, *, concurrent: int, source: str = "its configuration"
) -> None:
    """Refuse, before any unit starts, a local run whose units do not fit in memory together.

    A scenario's ``memory_estimate(config)`` is the peak of ONE unit (one ``experiment`` in
    one worker process). This is the one place that multiplies it by the units running at
    once on this machine (:func:`concurrent_units`); a remote executor's workers hold their
    units in their own memory, so its callers do not call this.
    :func:`gyrobench.scenarios.registry.load_config` has already checked one unit.

    Parameters
    ----------
    module : module
        The paper scenario (its ``memory_estimate``).
    config : object
        The scenario's Config.
    concurrent : int
        Units running at once (:func:`concurrent_units`).
    source : str
        Where the configuration came from, for the message.

    Raises
    ------
    gyrobench.base.memory.MemoryLimitError
        One line: the scenario, ``source`` (e.g. ``"config file 'big.toml'"``), the units at
        once, the estimate and the limit.
    """
    from gyrobench.base import memory

    est = memory.scenario_bytes(module, config)
    if est is None:
        return
    name = getattr(module, "NAME", module.__name__)
    memory.check_memory(
        est * concurrent,
        f"scenario {name} with {source} ({concurrent} unit(s) at once, one per worker process, "
        f"about {memory.format_bytes(est)} each)",
        hint="lower --workers, or shorten the records or lower the sample rate in --config",
    )


def slim_result(module: types.ModuleType, result: Any) -> Any:
    """A unit's result with the report-only arrays emptied.

    ``result`` with every array of the fields ``module.SLIM_FIELDS`` names emptied (same dtype and
    number of dimensions, no elements): what a unit the report does not draw is stored as.

    A scenario lists there the fields only its report's figures read, and in ``REPORT_UNITS`` how many
    leading units of a run the report draws; the claims read ``quantities``, which is never slimmed.
    A scenario without ``SLIM_FIELDS`` stores every unit whole.

    Parameters
    ----------
    module : module
        The paper scenario (its ``SLIM_FIELDS``).
    result : object
        One unit's result.

    Returns
    -------
    object
        ``result`` with those fields' arrays emptied (same dtype and dimensions).
    """
    names = tuple(getattr(module, "SLIM_FIELDS", ()))
    if not names:
        return result
    if isinstance(result, Mapping):
        return {**result, **{k: _emptied(result[k]) for k in names}}
    return dataclasses.replace(result, **{k: _emptied(getattr(result, k)) for k in names})


def _emptied(value: Any) -> Any:
    """``value`` with each numpy array inside it (through frozen dataclasses, tuples, lists and dicts)
    replaced by an empty array of its dtype and number of dimensions."""
    if isinstance(value, np.ndarray):
        return np.empty((0,) * value.ndim, dtype=value.dtype)
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return dataclasses.replace(value, **{f.name: _emptied(getattr(value, f.name))
                                             for f in dataclasses.fields(value) if f.init})
    if isinstance(value, (list, tuple)):
        return type(value)(_emptied(v) for v in value)
    if isinstance(value, dict):
        return {k: _emptied(v) for k, v in value.items()}
    return value


#: glibc mallopt parameters (malloc.h): M_TRIM_THRESHOLD, M_MMAP_THRESHOLD
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3
_MALLOC_TUNED = False


def keep_freed_memory() -> bool:
    """Let this process's C allocator reuse the memory of freed large arrays instead of returning it to
    the system (glibc: arrays up to 1 GB from the heap, which is trimmed only above 2 GB free).

    A unit allocates and frees arrays of tens of MB over and over (paper 000: about 0.7 GB of fresh
    pages a unit); each fresh page is a page fault, which on this project's virtual machines cost as
    much CPU as the arithmetic (paper 000: 180,000 faults and 0.6-1.0 s of system time a unit, 38,000
    and 0.1-0.3 s with the memory kept; the peak RSS rises by 2-5 %). Values are unchanged: only
    where the allocator takes memory from. Called once per process, by units run in this process or
    a local process pool (not on a cluster's workers); True when the allocator took the setting
    (glibc), False elsewhere.
    """
    global _MALLOC_TUNED
    if _MALLOC_TUNED:
        return True
    try:
        import ctypes

        libc = ctypes.CDLL("libc.so.6")
        ok = bool(libc.mallopt(_M_MMAP_THRESHOLD, 1 << 30)) and bool(libc.mallopt(_M_TRIM_THRESHOLD, 1 << 31))
    except (OSError, AttributeError):
        return False
    _MALLOC_TUNED = ok
    return ok


def _unit_job(
    module_name: str, config: Any, seed: int, full: bool = True, own_worker: bool = False
) -> tuple[int, bytes, float, bool]:
    """Worker entry point: one unit's ``experiment`` result, encoded by the codec and compressed
    (:func:`slim_result` unless ``full``). Module level: it pickles to the worker; the result comes back
    as the stored bytes, never as a pickle of our own. ``own_worker``: this process or one of a local
    process pool (:func:`keep_freed_memory` applies)."""
    from threadpoolctl import threadpool_limits

    if own_worker:
        keep_freed_memory()

    t0 = time.perf_counter()
    module = importlib.import_module(module_name)
    with threadpool_limits(limits=1):
        result = module.experiment(config, seed)
    try:
        quantities_of(result)
    except TypeError:
        raise TypeError(
            f"{module_name}.experiment must return a UnitResult (a typed result with a 'quantities' "
            f"mapping); got {type(result).__name__} for seed {seed}"
        ) from None
    from gyrobench.scenarios.runner import codec

    stored = result if full else slim_result(module, result)
    return seed, codec.dumps_compressed(stored), time.perf_counter() - t0, full or stored is result


def _decode(blob: bytes, seed: int, db: str | os.PathLike) -> Any:
    """A stored unit result, decoded without running code (a one-line ValueError naming the db
    and the seed if the row is not a result the codec wrote)."""
    from gyrobench.scenarios.runner import codec

    try:
        return codec.loads(blob)
    except codec.CodecError as exc:
        raise ValueError(f"db {str(db)!r}: stored unit (seed {seed}) refused: {exc}") from None


def check_run_size(n_units: Any, seed: Any = 0, *, what: str = "n_units", seed_name: str = "seed") -> None:
    """Refuse, in O(1) and one line, a run size or first seed out of range.

    Refuse, in O(1) and in one line, a run of ``n_units`` units from ``seed`` that is not an
    integer in ``[1, MAX_UNITS]`` or whose seeds pass :data:`MAX_SEED` (``what`` and ``seed_name``
    name them in the message, e.g. ``"--units"``).

    Parameters
    ----------
    n_units : object
        The number of units, an integer in [1, MAX_UNITS].
    seed : object
        The first seed; the last, seed + n_units - 1, must be <= :data:`MAX_SEED`.
    what : str
        How the message names ``n_units`` (e.g. ``"--units"``).
    seed_name : str
        How the message names ``seed``.
    """
    if isinstance(n_units, bool) or not isinstance(n_units, int) or n_units < 1:
        raise ValueError(f"{what} must be an integer >= 1; got {n_units!r}")
    if n_units > MAX_UNITS:
        shown = f"an integer of {len(str(n_units))} digits" if n_units > 10**30 else str(n_units)
        raise ValueError(
            f"{what} must be at most {MAX_UNITS} units (a claim's interval is then within +-1 point; "
            f"every unit's result is held in memory); got {shown}"
        )
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ValueError(f"{seed_name} must be an integer >= 0; got {seed!r}")
    if seed > MAX_SEED - n_units + 1:
        shown = f"an integer of {len(str(seed))} digits" if seed > 10**30 else str(seed)
        raise ValueError(f"{seed_name} + units - 1 must be at most {MAX_SEED} (a 64-bit seed); got {shown}")


def _check_args(n_units: Any, seed: Any, workers: Any, executor: Any) -> None:
    check_run_size(n_units, seed)
    check_pool(executor, workers)


def _check_layout(db: str | os.PathLike) -> None:
    """Refuse, in one line and before anything is written, an existing unit store whose table has
    another layout than :data:`_COLUMNS` (a store of an older gyrobench)."""
    p = Path(db)
    if not p.is_file() or p.stat().st_size == 0:
        return
    try:
        conn = sqlite3.connect(f"{p.resolve().as_uri()}?mode=ro", uri=True)
    except sqlite3.Error:
        return  # connect_db names what is wrong with the file
    try:
        have = tuple(r[1] for r in conn.execute("PRAGMA table_info(unit_results)"))
    except sqlite3.DatabaseError:
        return
    finally:
        conn.close()
    if have and have != _COLUMNS:
        raise ValueError(
            f"db {str(db)!r} is a unit store of an older gyrobench (columns {', '.join(have)}); "
            "delete it (its units are recomputed) or give another --db"
        )


def _open_store(
    db: str | os.PathLike, rid: str, name: str, config: Any, identity: str
) -> sqlite3.Connection:
    from gyrobench.scenarios.runner.store import connect_db

    _check_layout(db)
    conn = connect_db(db, _SCHEMA)  # WAL, synchronous=FULL, checks the folder exists
    try:
        register_run(conn, rid, name, config, identity)
    except BaseException:
        conn.close()
        raise
    return conn


def register_run(conn: sqlite3.Connection, rid: str, name: str, config: Any, identity: str) -> None:
    """Record a run in an open unit store, once (a second call for the same run id does nothing).

    Parameters
    ----------
    conn : sqlite3.Connection
        The unit store (:func:`gyrobench.scenarios.runner.store.connect_db`).
    rid : str
        The run id (:func:`run_id`).
    name : str
        The scenario's name.
    config : Any
        The run's configuration (stored as its repr).
    identity : str
        The run's JSON identity (:func:`run_id`).
    """
    conn.execute("BEGIN IMMEDIATE")
    conn.execute(
        "INSERT OR IGNORE INTO unit_runs VALUES (?, ?, ?, ?, ?)",
        (rid, name, repr(config), identity, time.time()),
    )
    conn.execute("COMMIT")


def _store(conn: sqlite3.Connection, rid: str, seed: int, blob: bytes, elapsed: float, full: bool) -> bytes:
    """Commit one unit; return the stored blob (another process may have stored it first; a whole
    result replaces a slim one, never the other way)."""
    conn.execute("BEGIN IMMEDIATE")
    try:
        conn.execute(
            "INSERT INTO unit_results VALUES (?, ?, ?, ?, ?, ?) ON CONFLICT (run_id, seed) DO UPDATE SET "
            "result = excluded.result, elapsed_s = excluded.elapsed_s, finished = excluded.finished, "
            "full = excluded.full WHERE excluded.full > unit_results.full",
            (rid, seed, blob, elapsed, time.time(), int(full)),
        )
        (stored,) = conn.execute(
            "SELECT result FROM unit_results WHERE run_id = ? AND seed = ?", (rid, seed)
        ).fetchone()
    except BaseException:
        conn.execute("ROLLBACK")
        raise
    conn.execute("COMMIT")
    return bytes(stored)


def _execute(
    module_name: str,
    config: Any,
    todo: Sequence[int],
    record: Callable[[int, bytes, float, bool], None],
    *,
    full: Container[int],
    executor: cf.Executor | None,
    workers: int | None,
) -> None:
    """Run ``_unit_job`` for every seed of ``todo`` and ``record`` each as it finishes."""
    from gyrobench.scenarios.runner.executors import add_note, check_picklable, local_pool, stop_pool

    if executor is None and workers == 0:
        for s in todo:
            record(*_unit_job(module_name, config, s, s in full, True))
        return
    check_picklable(None, config)
    own = executor is None
    ex: cf.Executor = local_pool(workers) if executor is None else executor
    local = isinstance(ex, cf.ProcessPoolExecutor)  # this machine's processes (not a cluster's workers)
    futures: dict[cf.Future, int] = {}
    ok = False
    try:
        futures = {ex.submit(_unit_job, module_name, config, s, s in full, local): s for s in todo}
        for fut in cf.as_completed(futures):
            try:
                record(*fut.result())
            except Exception as exc:
                add_note(exc, f"while computing unit (seed) {futures[fut]} of {module_name}")
                raise
        ok = True
    finally:
        for f in futures:
            f.cancel()
        if own:
            stop_pool(ex, kill=not ok)  # Ctrl-C, SIGTERM or an error: running units are killed


def run_units(
    module: types.ModuleType,
    config: Any,
    *,
    seed: int = 0,
    n_units: int = 20,
    executor: cf.Executor | None = None,
    workers: int | None = None,
    db: str | os.PathLike = DEFAULT_DB,
    progress: bool = False,
    whole: int | None = None,
) -> UnitRun:
    """``module.experiment(config, s)`` for ``s`` in ``range(seed, seed + n_units)``, resuming.

    Parameters
    ----------
    module : module
        A paper scenario (:func:`is_paper_scenario`), importable by name in the workers.
    config : the module's Config
    seed : int
        The first unit's seed (>= 0).
    n_units : int
        How many units (>= 1).
    executor : concurrent.futures.Executor, optional
        Where units run (not shut down here). Excludes ``workers``.
    workers : int, optional
        Local process pool size (default: the usable CPUs); ``0`` runs in this process.
    db : path
        SQLite resume store (created if absent, in an existing folder).
    progress : bool
        A tqdm bar on stderr.
    whole : int, optional
        How many leading units are stored whole; the others as :func:`slim_result` (default: all
        whole). A slim stored unit asked for whole is recomputed.

    Returns
    -------
    UnitRun
        The units' results in seed order, with how many were computed or read back.

    Raises
    ------
    ValueError, TypeError
        Bad arguments, or a module without the paper-scenario shape. An exception in a
        unit is re-raised with a note naming the seed, after the finished units are committed.
    """
    _check_args(n_units, seed, workers, executor)
    if not is_paper_scenario(module):
        raise ValueError(
            f"scenario {getattr(module, 'NAME', module.__name__)!r} is not a paper scenario "
            "(it must define experiment and CLAIMS)"
        )
    seeds = tuple(range(seed, seed + n_units))
    rid, identity = run_id(module, config)
    name = getattr(module, "NAME", module.__name__)
    conn = _open_store(db, rid, name, config, identity)
    try:
        blobs: dict[int, bytes] = {}
        elapsed: dict[int, float] = {}
        full = set(seeds if whole is None else seeds[:whole])
        for s, blob, el, is_full in conn.execute(
            "SELECT seed, result, elapsed_s, full FROM unit_results WHERE run_id = ?", (rid,)
        ):
            if s in seeds and (is_full or s not in full):
                blobs[s], elapsed[s] = bytes(blob), float(el)
        reused = len(blobs)
        todo = [s for s in seeds if s not in blobs]
        if executor is None and todo:  # our own local pool: its units share this machine
            check_unit_memory(module, config, concurrent=concurrent_units(len(todo), workers))
        from tqdm import tqdm

        bar = tqdm(
            total=n_units,
            initial=reused,
            disable=not progress or not todo,
            desc=f"{name} units",
            unit="unit",
            dynamic_ncols=True,
        )

        def record(s: int, blob: bytes, el: float, is_full: bool) -> None:
            blobs[s], elapsed[s] = _store(conn, rid, s, blob, el, is_full), el
            bar.update(1)

        try:
            _execute(module.__name__, config, todo, record, executor=executor, workers=workers, full=full)
        finally:
            bar.close()
        return UnitRun(
            run_id=rid,
            seeds=seeds,
            results=tuple(_decode(blobs[s], s, db) for s in seeds),
            elapsed_s=tuple(elapsed[s] for s in seeds),
            computed=len(todo),
            reused=reused,
            db=str(db),
        )
    finally:
        conn.close()


def run_paper(
    module: types.ModuleType,
    config: Any,
    *,
    seed: int = 0,
    n_units: int = 20,
    executor: cf.Executor | None = None,
    workers: int | None = None,
    db: str | os.PathLike = DEFAULT_DB,
    progress: bool = False,
    deviation_units: int = 0,
    max_units: int | None = None,
    keep_units: bool = False,
) -> Outcome:
    """Run the units (:func:`run_units`), judge :func:`module_claims` over them, build the report.

    With ``deviation_units`` > 0, each deviation's config variant also runs over the first
    that many units (:func:`measure_deviations`) and ``outcome.deviation_effects`` holds the
    measured change of every claim's pass count.

    With ``max_units`` (``reproduce --units auto``), units are added in batches of
    :data:`AUTO_BATCH` while any claim's interval still straddles 50 %, up to ``max_units``;
    each claim is judged over the units it needed (its ``units`` field): a claim keeps the units
    that decided it, an open one gets every batch. Every look judges by the Wilson interval at
    the group-sequential z of :func:`gyrobench.scenarios.claims.sequential_z` for the planned looks
    (n_units, n_units + AUTO_BATCH, ..., max_units), so that a claim whose true pass rate is 50 %
    is decided at some look with probability at most 5 % (a Pocock-type boundary on the exact
    binomial crossing probability; 1.96 at every look would decide it 12 % of the time over 20,
    30, ..., 60 units). ``results["sequential"]`` records the looks and z.

    Returns the module's :class:`~gyrobench.scenarios.base.Outcome` with ``claims``,
    ``deviations``, ``units`` and ``runtime_s`` filled, and ``results["unit_run"]`` (seeds,
    per-unit runtimes, how many were computed and read back) set. The report writer
    puts the claims (:meth:`~gyrobench.scenarios.claims.ClaimResult.as_dict`) and the
    deviations into results.json.

    The store keeps what the claims and the report read: the first ``module.REPORT_UNITS`` units
    whole, the others, the control's and the deviations' as :func:`slim_result`; ``keep_units``
    stores every unit whole.

    Parameters
    ----------
    module : module
        A paper scenario (:func:`is_paper_scenario`).
    config : object
        Its Config.
    seed : int
        The first unit's seed.
    n_units : int
        Units to run (the first look with ``max_units``).
    executor : concurrent.futures.Executor, optional
        Where the units run (a dask client's, for instance); None: local processes.
    workers : int or None
        Local worker processes (0: in this process; None: the usable CPUs).
    db : path-like
        The resume store.
    progress : bool
        Show a progress bar.
    deviation_units : int
        Units each deviation's variant runs over (0: none).
    max_units : int or None
        Add batches while a claim is undecided, up to this many units (None: one look).
    keep_units : bool
        Store every unit's whole result (else the slimmed ones, :func:`slim_result`).

    Returns
    -------
    Outcome
        The claims judged and the report built from the units.
    """
    t0 = time.perf_counter()
    kw: dict[str, Any] = dict(seed=seed, executor=executor, workers=workers, db=db, progress=progress)
    claim_list = module_claims(module, config)
    used = dict.fromkeys((c.id for c in claim_list), n_units)
    looks = auto_looks(n_units, max_units) if max_units is not None else (n_units,)
    z = sequential_z(looks) if max_units is not None else None
    report_units = None if keep_units else getattr(module, "REPORT_UNITS", None)
    others = None if keep_units else 0
    while True:
        run = run_units(module, config, n_units=n_units, whole=report_units, **kw)
        control = _run_control(module, config, n_units=n_units, whole=others, **kw)
        claims = _judge(claim_list, used, run, control, z)
        open_ids = [r.claim.id for r in claims if r.verdict == "undecided"]
        if max_units is None or not open_ids or n_units >= max_units:
            break
        n_units = min(n_units + AUTO_BATCH, max_units)
        used.update(dict.fromkeys(open_ids, n_units))  # decided claims keep the units that decided them
    outcome = module.report(config, list(run.results), claims)
    if not isinstance(outcome, Outcome):
        raise TypeError(
            f"{module.__name__}.report must return an Outcome; got {type(outcome).__name__}"
        )
    outcome.seed = seed
    outcome.claims = list(claims)
    outcome.deviations = list(getattr(module, "DEVIATIONS", ()))
    outcome.units = n_units
    outcome.runtime_s = time.perf_counter() - t0
    if deviation_units:
        outcome.deviation_effects = measure_deviations(
            module, config, run.results[:deviation_units], seed=seed, executor=executor, workers=workers, db=db,
            progress=progress, whole=others,
        )
    if z is not None:
        outcome.results["sequential"] = {
            "looks": list(looks), "z": z, "alpha": 0.05, "error_at_50_percent": sequential_error(looks, z),
            "rule": "Wilson interval at a constant z over the planned looks (Pocock-type), z chosen from the exact "
                    "binomial crossing probability at a true pass rate of 50 %",
        }
    outcome.results["unit_quantities"] = _per_unit(run)
    if control is not None:
        outcome.results["control_quantities"] = _per_unit(control)
    outcome.results["unit_run"] = {
        "n": n_units,
        "seeds": list(run.seeds),
        "computed": run.computed,
        "reused": run.reused,
        "unit_runtime_s": list(run.elapsed_s),
        "run_id": run.run_id,
    }
    if control is not None:
        outcome.results["control_run"] = {
            "n": n_units,
            "seeds": list(control.seeds),
            "computed": control.computed,
            "reused": control.reused,
            "unit_runtime_s": list(control.elapsed_s),
            "run_id": control.run_id,
        }
    return outcome


def measure_deviations(
    module: types.ModuleType,
    config: Any,
    units: Sequence[Any],
    *,
    seed: int,
    executor: cf.Executor | None,
    workers: int | None,
    db: str | os.PathLike,
    progress: bool,
    whole: int | None = None,
) -> list[Any]:
    """Each deviation's effect: its config variant (``module.variant_config(config, name)``) run over
    the seeds of ``units`` (our protocol's first units, already run), claims judged on both.

    Deviations without a variant, or a scenario without ``variant_config``, measure nothing.
    """
    from gyrobench.scenarios.claims import deviation_effect, evaluate

    make = getattr(module, "variant_config", None)
    if not callable(make) or not units:
        return []
    claims = module_claims(module, config)
    ours = evaluate(claims, [quantities_of(u) for u in units])
    effects = []
    for d in getattr(module, "DEVIATIONS", ()):
        if not getattr(d, "variant", None):
            continue
        vrun = run_units(module, make(config, d.variant), seed=seed, n_units=len(units), executor=executor,
                         workers=workers, db=db, progress=progress, whole=whole)
        theirs = evaluate(claims, [quantities_of(u) for u in vrun.results])
        effects.append(deviation_effect(d.variant, ours, theirs))
    return effects


#: units added per batch by ``reproduce --units auto``
AUTO_BATCH = 10


def _per_unit(run: UnitRun) -> list[dict[str, Any]]:
    """Every unit's claim quantities with its seed (what results.json lets a referee recount from)."""
    return [{"seed": int(s), **quantities_of(u)} for s, u in zip(run.seeds, run.results, strict=True)]


def auto_looks(start: int, max_units: int) -> tuple[int, ...]:
    """The unit counts ``--units auto`` may judge at: start, start + AUTO_BATCH, ..., max_units."""
    looks = list(range(start, max_units, AUTO_BATCH)) + [max_units]
    return tuple(sorted(set(looks)))


def _judge(
    claims: Sequence[Any], used: Mapping[str, int], run: UnitRun, control: UnitRun | None, z: float | None = None
) -> list[Any]:
    """Each claim judged over its first ``used[claim.id]`` units (and as many control units); ``z`` of the
    verdict's Wilson interval (None: the fixed-count 1.96)."""
    from gyrobench.scenarios.claims import evaluate

    units = [quantities_of(u) for u in run.results]
    ctrl = None if control is None else [quantities_of(u) for u in control.results]
    out = []
    for c in claims:
        n = used[c.id]
        extra = {} if z is None else {"z": z}
        out += evaluate([c], units[:n], None if ctrl is None else ctrl[:n], **extra)
    return out


def _run_control(module: types.ModuleType, config: Any, **kw: Any) -> UnitRun | None:
    """The control population: the same seeds under ``module.control_config(config)`` (the paper's
    effect switched off), on the same executor and store; None for a scenario without a control."""
    make = getattr(module, "control_config", None)
    if not callable(make):
        return None
    return run_units(module, make(config), **kw)


def default_db(out_dir: str | os.PathLike) -> Path:
    """The resume store beside a report folder: ``<out_dir>.units.sqlite``.

    Beside, not inside: the report folder is replaced as a whole by each new report
    (:func:`gyrobench.scenarios.reports.outputs.write_report_as_a_set`), the store must survive it.

    Parameters
    ----------
    out_dir : path-like
        The report folder.

    Returns
    -------
    Path
        ``<out_dir>.units.sqlite``.
    """
    out = Path(out_dir)
    return out.with_name(out.name + ".units.sqlite")
