"""A map's units on the shared runner: every (point, unit) pair, resumable, on the existing executors.

Point ``i`` is the paper's ``Config`` at the design's i-th values; its unit ``j`` is
``module.experiment(config_i, unit_seed(seed, i, j))`` with

    unit_seed(seed, i, j) = seed + MAP_SEED_OFFSET + i * UNITS_PER_POINT_MAX + j

so a unit's seed depends on its point and unit index only (never on the order units finish in, the
worker count or the executor), and no map seed is one of the report's seeds (0 ...) or an
identification's (900 ...). The family's nominal device runs as point ``NOMINAL_POINT`` (past the
last design point a map may have), so its seeds do not depend on the design's size. Each unit runs
through the runner's worker entry point (``_unit_job`` of :mod:`gyrobench.scenarios.runner.units`:
BLAS pools limited to one thread, the result encoded by the codec; the store's private helpers are
used as they are, so a map's units are stored exactly as
:func:`~gyrobench.scenarios.runner.units.run_units` stores them), so a local pool (``workers``),
this process (``workers=0``) or a Dask executor give the same bits. Each finished unit is committed
to the unit store under its point's run id (the scenario's source closure and that point's
``Config``), the store :func:`gyrobench.scenarios.runner.units.run_units` uses: a map killed at any
moment resumes and recomputes no finished unit. (A point's run id is the one ``reproduce`` gives the
same config, but map seeds start at ``MAP_SEED_OFFSET``, so a map does not reuse a reproduction's
units.) Units are stored slim (:func:`~gyrobench.scenarios.runner.units.slim_result`): the map reads
only their ``quantities``.
"""

from __future__ import annotations

import concurrent.futures as cf
import os
import types
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from gyrobench.scenarios.papers.contract import quantities_of
from gyrobench.scenarios.runner import units as runner

from .family import MAX_POINTS

__all__ = ["MAP_SEED_OFFSET", "NOMINAL_POINT", "UNITS_PER_POINT_MAX", "MapUnits", "run_map", "unit_seed"]

#: added to every map unit's seed: apart from the report's seeds (0, 1, ...) and identifications'
MAP_SEED_OFFSET = 10_000_000
#: the most units one point may have (the stride of point indices in :func:`unit_seed`)
UNITS_PER_POINT_MAX = 1000
#: the point index the nominal device's units run under (no design point has it)
NOMINAL_POINT = MAX_POINTS


def unit_seed(seed: int, point: int, unit: int) -> int:
    """The seed of one unit of one point of a map (see the module).

    Parameters
    ----------
    seed : int
        The map's first seed (``reproduce --seed``).
    point : int
        The point's index (>= 0).
    unit : int
        The unit's index at the point, in ``[0, UNITS_PER_POINT_MAX)``.

    Returns
    -------
    int
        ``seed + MAP_SEED_OFFSET + point * UNITS_PER_POINT_MAX + unit``.
    """
    if not 0 <= unit < UNITS_PER_POINT_MAX:
        raise ValueError(f"units per point must be in [1, {UNITS_PER_POINT_MAX}]; got unit index {unit!r}")
    if point < 0:
        raise ValueError(f"point index must be >= 0; got {point!r}")
    return seed + MAP_SEED_OFFSET + point * UNITS_PER_POINT_MAX + unit


@dataclass(frozen=True, slots=True, kw_only=True)
class MapUnits:
    """Every point's units: seeds and claim quantities, in point then unit order.

    Attributes
    ----------
    run_ids : tuple of str
        Each point's run id in the unit store.
    seeds : tuple of tuple of int
        Each point's unit seeds.
    quantities : tuple of tuple of dict
        Each point's units' ``quantities`` mappings.
    computed, reused : int
        Units computed now and read back from the store.
    run_s : float
        Sum of the units' wall-clock run times [s], each measured in its worker (not CPU time).
    """

    run_ids: tuple[str, ...]
    seeds: tuple[tuple[int, ...], ...]
    quantities: tuple[tuple[dict[str, Any], ...], ...]
    computed: int
    reused: int
    run_s: float


def run_map(
    module: types.ModuleType,
    configs: Sequence[Any],
    *,
    units_per_point: int,
    seed: int = 0,
    executor: cf.Executor | None = None,
    workers: int | None = None,
    db: str | os.PathLike = runner.DEFAULT_DB,
    progress: bool = False,
    point_indices: Sequence[int] | None = None,
) -> MapUnits:
    """Run ``units_per_point`` units of ``module`` at each of ``configs``, resuming from ``db``.

    Parameters
    ----------
    module : module
        A paper scenario, importable by name in the workers.
    configs : sequence of the module's Config
        One configuration per point.
    units_per_point : int
        Units at each point, in ``[1, UNITS_PER_POINT_MAX]``.
    seed : int
        The map's first seed (:func:`unit_seed`).
    executor : concurrent.futures.Executor, optional
        Where units run (not shut down here). Excludes ``workers``.
    workers : int, optional
        Local process pool size (default: the usable CPUs); ``0`` runs in this process.
    db : path
        SQLite unit store (created if absent, in an existing folder).
    progress : bool
        A tqdm bar on stderr.
    point_indices : sequence of int, optional
        Each config's point index in :func:`unit_seed` (distinct, >= 0; default 0, 1, ...): the
        nominal device of a map runs under an index no design point has.

    Returns
    -------
    MapUnits
        Every point's seeds and quantities, in point then unit order.

    Raises
    ------
    ValueError
        Bad sizes or a module without the paper-scenario shape. An exception in a unit is
        re-raised with a note naming the point and the seed, after the finished units are committed.
    """
    from tqdm import tqdm

    from gyrobench.scenarios.base import check_pool
    from gyrobench.scenarios.runner.executors import add_note, check_picklable, local_pool, stop_pool

    if not runner.is_paper_scenario(module):
        raise ValueError(f"scenario {getattr(module, 'NAME', module.__name__)!r} is not a paper scenario")
    if isinstance(units_per_point, bool) or not 1 <= units_per_point <= UNITS_PER_POINT_MAX:
        raise ValueError(f"units per point must be an integer in [1, {UNITS_PER_POINT_MAX}]; got {units_per_point!r}")
    if not configs:
        raise ValueError("a map needs at least one point")
    check_pool(executor, workers)
    index = list(range(len(configs))) if point_indices is None else [int(i) for i in point_indices]
    if len(index) != len(configs) or len(set(index)) != len(index):
        raise ValueError(f"point indices must be distinct, one per config; got {point_indices!r}")
    last = unit_seed(seed, max(index), units_per_point - 1)
    runner.check_run_size(1, last, seed_name="the map's last unit seed")
    name = getattr(module, "NAME", module.__name__)
    seeds = tuple(tuple(unit_seed(seed, i, j) for j in range(units_per_point)) for i in index)
    ids = runner.run_ids(module, configs)
    conn = runner._open_store(db, ids[0][0], name, configs[0], ids[0][1])
    try:
        for (rid, ident), c in zip(ids[1:], configs[1:], strict=True):
            runner.register_run(conn, rid, name, c, ident)
        blobs: dict[tuple[int, int], bytes] = {}
        elapsed: dict[tuple[int, int], float] = {}
        for i, (rid, _) in enumerate(ids):
            wanted = set(seeds[i])
            rows = conn.execute("SELECT seed, result, elapsed_s FROM unit_results WHERE run_id = ?", (rid,))
            for s, blob, el in rows:
                if s in wanted:
                    blobs[i, s], elapsed[i, s] = bytes(blob), float(el)
        reused = len(blobs)
        todo = [(i, s) for i in range(len(configs)) for s in seeds[i] if (i, s) not in blobs]
        if executor is None and todo:  # our own local pool: its units share this machine
            at_once = runner.concurrent_units(len(todo), workers)
            for i in sorted({i for i, _ in todo}):
                runner.check_unit_memory(module, configs[i], concurrent=at_once)
        bar = tqdm(total=len(configs) * units_per_point, initial=reused, disable=not progress or not todo,
                   desc=f"{name} map units", unit="unit", dynamic_ncols=True)

        def record(i: int, s: int, blob: bytes, el: float, is_full: bool) -> None:
            blobs[i, s] = runner._store(conn, ids[i][0], s, blob, el, is_full)
            elapsed[i, s] = el
            bar.update(1)

        try:
            if executor is None and workers == 0:
                for i, s in todo:
                    record(i, *runner._unit_job(module.__name__, configs[i], s, False, True))
            elif todo:
                for c in configs:
                    check_picklable(None, c)
                own = executor is None
                ex: cf.Executor = local_pool(workers) if executor is None else executor
                local = isinstance(ex, cf.ProcessPoolExecutor)
                futures: dict[cf.Future, tuple[int, int]] = {}
                ok = False
                try:
                    futures = {ex.submit(runner._unit_job, module.__name__, configs[i], s, False, local): (i, s)
                               for i, s in todo}
                    for fut in cf.as_completed(futures):
                        i, s = futures[fut]
                        try:
                            record(i, *fut.result())
                        except Exception as exc:
                            add_note(exc, f"while computing map point {i}, unit (seed) {s} of {module.__name__}")
                            raise
                    ok = True
                finally:
                    for f in futures:
                        f.cancel()
                    if own:
                        stop_pool(ex, kill=not ok)
        finally:
            bar.close()
        quantities = tuple(
            tuple(dict(quantities_of(runner._decode(blobs[i, s], s, db))) for s in seeds[i])
            for i in range(len(configs))
        )
        return MapUnits(
            run_ids=tuple(r for r, _ in ids),
            seeds=seeds,
            quantities=quantities,
            computed=len(todo),
            reused=reused,
            run_s=float(sum(elapsed.values())),
        )
    finally:
        conn.close()
