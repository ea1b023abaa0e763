"""A paper's map end to end: its family module's design, the units, the region and claims, the files.

A paper that can be mapped has a ``family`` module beside its scenario module (or the scenario
module itself) defining ``FAMILY`` (:class:`~.family.Family`), ``MAP_CONSTRAINTS`` (:class:`~.region.Constraint`),
``MAP_CLAIMS`` (the claims to map) and ``DESIGN_SEED``. :func:`map_paper` runs the map and
:func:`write_map` writes ``map.json``, ``phase_diagrams.png``, ``specification_curves.png`` and
``constraints.png``
into a folder.
"""

from __future__ import annotations

import concurrent.futures as cf
import importlib
import json
import os
import types
from dataclasses import dataclass
from pathlib import Path

from gyrobench.scenarios.runner import units as runner

from .family import design
from .region import MapResult, analyse
from .run import MapUnits, run_map

__all__ = ["Mapped", "family_module", "map_paper", "write_map"]


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
) -> Mapped:
    """Map a paper over design points of its family.

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
        Defines ``FAMILY``, ``MAP_CONSTRAINTS``, ``MAP_CLAIMS``, ``DESIGN_SEED`` (default
        :func:`family_module`).

    Returns
    -------
    Mapped
        The map and how its units ran.
    """
    fam = family or family_module(module)
    if fam is None:
        raise ValueError(f"scenario {getattr(module, 'NAME', module.__name__)!r} defines no device family to map")
    d = design(fam.FAMILY, points, fam.DESIGN_SEED)
    configs = [fam.FAMILY.config(v) for v in d.values]
    run = run_map(module, configs, units_per_point=units_per_point, seed=seed, executor=executor,
                  workers=workers, db=db, progress=progress)
    result = analyse(fam.FAMILY, d, run.seeds, run.quantities, fam.MAP_CONSTRAINTS, fam.MAP_CLAIMS)
    return Mapped(result=result, units=run)


def write_map(mapped: Mapped, folder: Path, *, command: str = "") -> Path:
    """Write ``map.json`` and the three PNGs into a folder.

    Parameters
    ----------
    mapped : Mapped
        A map.
    folder : Path
        Created if absent.
    command : str
        The command line, recorded in map.json.

    Returns
    -------
    Path
        map.json's path.
    """
    from .figures import constraint_maps, phase_diagrams, specification_curves

    folder.mkdir(parents=True, exist_ok=True)
    doc = mapped.result.as_dict()
    doc["command"] = command
    doc["unit_run"] = {"computed": mapped.units.computed, "reused": mapped.units.reused,
                       "unit_wall_s_summed": mapped.units.run_s, "run_ids": list(mapped.units.run_ids)}
    path = folder / "map.json"
    path.write_text(json.dumps(doc, indent=1, allow_nan=False) + "\n", encoding="utf-8")
    phase_diagrams(mapped.result, folder / "phase_diagrams.png")
    specification_curves(mapped.result, folder / "specification_curves.png")
    constraint_maps(mapped.result, folder / "constraints.png")
    return path
