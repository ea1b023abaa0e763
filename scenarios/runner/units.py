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

This module schedules the units (which seeds, resumption, the control, the claims); one unit's
execution (the worker entry point, the executor, the memory check, the slim results) is
:mod:`gyrobench.scenarios.runner.unit_jobs`, and the store's tables, run identity, reads and
writes are :mod:`gyrobench.scenarios.runner.unit_store`. Their public names are re-exported here.
"""

from __future__ import annotations

import concurrent.futures as cf
import os
import time
import types
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from gyrobench.scenarios.base import Outcome, check_pool
from gyrobench.scenarios.claims import sequential_error, sequential_z
from gyrobench.scenarios.papers.contract import quantities_of
from gyrobench.scenarios.runner.unit_jobs import (
    _execute,
    _unit_job,  # noqa: F401  (the maps' runner and the benchmarks reach it here)
    check_unit_memory,
    concurrent_units,
    keep_freed_memory,  # noqa: F401  (the benchmarks reach it here)
    slim_result,
)
from gyrobench.scenarios.runner.unit_store import (
    DEFAULT_DB,
    _decode,
    _open_store,
    _store,
    default_db,
    register_run,
    run_id,
    run_ids,
)

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

#: the most units one run simulates (``reproduce --units/--max-units/--deviations``, ``n_units``):
#: a claim's pass fraction over 10,000 units has a 95 % interval of at most +-1 percentage point,
#: finer than any claim is stated to; every unit's result is held in memory for the claims and the
#: report, and the fastest paper's unit takes about 0.9 s of CPU (stop 13), so 10,000 units are
#: already hours. Checked in O(1) before any seed list is built (``--units 10000000`` grew without
#: bound before).
MAX_UNITS = 10_000

#: the largest seed a unit may have: seeds are stored as SQLite's signed 64-bit INTEGER
MAX_SEED = 2**63 - 1

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
