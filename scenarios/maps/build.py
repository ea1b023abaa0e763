"""A paper's map end to end: its family module's design, the units, the region and claims, the files.

A paper that can be mapped has a ``family`` module beside its scenario module (or the scenario
module itself) defining ``FAMILY`` (:class:`~.family.Family`), ``MAP_CONSTRAINTS`` (:class:`~.region.Constraint`),
``MAP_CLAIMS`` (the claims to map) and ``DESIGN_SEED``, and optionally ``MAP_COVARIATES``
(:class:`~.region.Covariate`: quantities a claim rests on, reported per point). The family's
nominal device (:attr:`~.family.Family.nominal`, when its base configuration is a point of the
family) runs as one more point (:data:`~.run.NOMINAL_POINT`). :func:`map_paper` runs the map and
:func:`write_map` writes ``map.json`` (the map), ``map_run.json`` (how the run went),
``phase_diagrams.png``, ``specification_curves.png``, ``constraints.png`` and (with covariates)
``covariates.png`` into a folder.
"""

from __future__ import annotations

import concurrent.futures as cf
import importlib
import json
import os
import types
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from gyrobench.scenarios.runner import units as runner

from .family import design
from .refine import joined, plan_refinement
from .region import MapResult, _medians, analyse
from .run import NOMINAL_POINT, MapUnits, run_map

__all__ = ["RUN_FILE", "Mapped", "family_module", "map_paper", "write_map"]

#: how one map run went (command, units computed and reused), beside map.json
RUN_FILE = "map_run.json"


@dataclass(frozen=True, slots=True, kw_only=True)
class Mapped:
    """A map's result and how its units ran.

    Parameters
    ----------
    result : MapResult
        The region and the claims over the family.
    units : MapUnits
        The units' seeds, quantities and counts.
    """

    result: MapResult
    units: MapUnits


def family_module(module: types.ModuleType) -> types.ModuleType | None:
    """The module defining a paper's family.

    Parameters
    ----------
    module : module
        A paper scenario.

    Returns
    -------
    module or None
        ``module`` itself when it defines ``FAMILY``, else its ``family`` submodule; None when the
        paper defines no family to map.
    """
    if hasattr(module, "FAMILY"):
        return module
    name = module.__name__ + ".family"
    try:
        return importlib.import_module(name)
    except ModuleNotFoundError as exc:
        if exc.name == name:
            return None
        raise


def map_paper(
    module: types.ModuleType,
    *,
    points: int,
    units_per_point: int,
    seed: int = 0,
    executor: cf.Executor | None = None,
    workers: int | None = None,
    db: str | os.PathLike = runner.DEFAULT_DB,
    progress: bool = False,
    family: types.ModuleType | None = None,
    refine: bool = True,
) -> Mapped:
    """Map a paper over design points of its family, refined where the region is small (:mod:`.refine`).

    The first stage's units (and the nominal device's) run first; the second stage's points follow
    from their constraint medians, and take the point indices after the first stage's.

    Parameters
    ----------
    module : module
        A paper scenario.
    points : int
        Design points (:func:`~.family.design`).
    units_per_point : int
        Units at each point.
    seed : int
        The map's first seed (:func:`~.run.unit_seed`).
    executor : concurrent.futures.Executor, optional
        Where units run (see :func:`~.run.run_map`).
    workers : int, optional
        Local process pool size; ``0`` runs in this process.
    db : path
        SQLite unit store.
    progress : bool
        A tqdm bar on stderr.
    family : module, optional
        Defines ``FAMILY``, ``MAP_CONSTRAINTS``, ``MAP_CLAIMS``, ``DESIGN_SEED`` and optionally
        ``MAP_COVARIATES`` (default :func:`family_module`).
    refine : bool
        Run the second stage where the first stage's region is small (:mod:`.refine`).

    Returns
    -------
    Mapped
        The map and how its units ran.
    """
    fam = family or family_module(module)
    if fam is None:
        raise ValueError(f"scenario {getattr(module, 'NAME', module.__name__)!r} defines no device family to map")
    first = design(fam.FAMILY, points, fam.DESIGN_SEED)
    configs = [fam.FAMILY.config(v) for v in first.values]
    index = list(range(len(configs)))
    nominal = fam.FAMILY.nominal
    if nominal is not None:
        configs.append(fam.FAMILY.config(nominal))
        index.append(NOMINAL_POINT)

    def units_of(cfgs: list, idx: Sequence[int]) -> MapUnits:
        return run_map(module, cfgs, units_per_point=units_per_point, seed=seed, executor=executor, workers=workers,
                       db=db, progress=progress, point_indices=idx)

    run = units_of(configs, index)
    n = len(first)
    plan = None
    if refine:  # the second stage, from the first stage's constraint medians alone (refine.py)
        med = [_medians(fam.MAP_CONSTRAINTS, u) for u in run.quantities[:n]]
        sat = [[c.holds(m) for c, m in zip(fam.MAP_CONSTRAINTS, row, strict=True)] for row in med]
        plan = plan_refinement(fam.FAMILY, first, [c.comparator for c in fam.MAP_CONSTRAINTS], med, sat)
    second = plan.design if plan is not None else None
    if second is not None:
        more = units_of([fam.FAMILY.config(v) for v in second.values], range(n, n + len(second)))
        run = MapUnits(run_ids=run.run_ids[:n] + more.run_ids + run.run_ids[n:], seeds=run.seeds[:n] + more.seeds
                       + run.seeds[n:], quantities=run.quantities[:n] + more.quantities + run.quantities[n:],
                       computed=run.computed + more.computed, reused=run.reused + more.reused,
                       run_s=run.run_s + more.run_s)
    d = joined(first, second)
    m = len(d)
    result = analyse(fam.FAMILY, d, run.seeds[:m], run.quantities[:m], fam.MAP_CONSTRAINTS, fam.MAP_CLAIMS,
                     covariates=getattr(fam, "MAP_COVARIATES", ()),
                     nominal_seeds=run.seeds[m] if nominal is not None else (),
                     nominal_units=run.quantities[m] if nominal is not None else None, refinement=plan)
    return Mapped(result=result, units=run)


def write_map(mapped: Mapped, folder: Path, *, command: str = "") -> Path:
    """Write ``map.json``, ``map_run.json`` and the PNGs into a folder.

    ``map.json`` is a function of the family, the design and the units' results only (the same map
    gives the same bytes however its units ran, resumed or not); how this run went (the command, the
    units computed and reused, their summed run time) is in ``map_run.json`` beside it.

    Parameters
    ----------
    mapped : Mapped
        A map.
    folder : Path
        Created if absent.
    command : str
        The command line, recorded in map_run.json.

    Returns
    -------
    Path
        map.json's path.
    """
    from .figures import constraint_maps, covariate_maps, phase_diagrams, specification_curves

    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "map.json"
    path.write_text(json.dumps(mapped.result.as_dict(), indent=1, allow_nan=False) + "\n", encoding="utf-8")
    run = {"command": command, "computed": mapped.units.computed, "reused": mapped.units.reused,
           "unit_wall_s_summed": mapped.units.run_s, "run_ids": list(mapped.units.run_ids)}
    (folder / RUN_FILE).write_text(json.dumps(run, indent=1) + "\n", encoding="utf-8")
    phase_diagrams(mapped.result, folder / "phase_diagrams.png")
    specification_curves(mapped.result, folder / "specification_curves.png")
    constraint_maps(mapped.result, folder / "constraints.png")
    covariate_maps(mapped.result, folder / "covariates.png")
    return path
