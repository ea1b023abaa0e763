"""``gyrobench reproduce NAME --map``: one paper's device family mapped (:mod:`gyrobench.scenarios.maps`)."""

from __future__ import annotations

import shlex
import time
from pathlib import Path

from gyrobench.scenarios.cli.common import BadInput

__all__ = ["DEFAULT_POINTS", "DEFAULT_UNITS_PER_POINT", "cmd_map"]

#: ``--map`` defaults: 16 Sobol points x 3 units, unless the family module states its own
#: ``DEFAULT_POINTS`` / ``DEFAULT_UNITS_PER_POINT``
DEFAULT_POINTS = 16
DEFAULT_UNITS_PER_POINT = 3


def cmd_map(args) -> int:
    """Check the inputs, then map the one named paper into ``--out`` (a report folder, written as a set).

    Parameters
    ----------
    args : argparse.Namespace
        ``reproduce``'s parsed arguments with ``--map``.

    Returns
    -------
    int
        The exit status (0).
    """
    from gyrobench.scenarios import registry
    from gyrobench.scenarios.cli.reproduce import _check_reproduce_outputs
    from gyrobench.scenarios.maps.build import family_module
    from gyrobench.scenarios.reports.outputs import output_lock
    from gyrobench.scenarios.runner import units

    if args.all or len(args.scenarios) != 1:
        raise BadInput("--map maps one scenario; name exactly one (not --all)")
    for flag, given in (("--config", args.config), ("--deviations", args.deviations),
                        ("--keep-units", args.keep_units)):
        if given:
            raise BadInput(f"{flag} does not apply to --map")
    if args.units == "auto":
        raise BadInput("--units auto does not apply to --map (give --units-per-point)")
    if args.workers is not None and args.workers < 0:
        raise BadInput(f"--workers must be an integer >= 0; got {args.workers}")
    mod = registry.get(args.scenarios[0])
    if not units.is_paper_scenario(mod) or family_module(mod) is None:
        mappable = [n for n in registry.available()
                    if units.is_paper_scenario(m := registry.get(n)) and family_module(m) is not None]
        raise BadInput(f"scenario {args.scenarios[0]!r} defines no device family to map; --map applies to "
                       f"{', '.join(mappable) or 'no scenario'}")
    fam = family_module(mod)  # a family may state its own default map (what a map of it costs)
    points = args.points or getattr(fam, "DEFAULT_POINTS", DEFAULT_POINTS)
    k = args.units_per_point or getattr(fam, "DEFAULT_UNITS_PER_POINT", DEFAULT_UNITS_PER_POINT)
    from gyrobench.scenarios.maps.run import unit_seed

    try:
        units.check_run_size(1, unit_seed(args.seed, points - 1, k - 1), seed_name="--seed + the map's unit seeds")
    except ValueError as exc:
        raise BadInput(str(exc)) from None
    _check_reproduce_outputs(args)
    with output_lock(args.out, what="--out"):
        return _run(args, mod, points, k)


def _run(args, mod, points: int, k: int) -> int:
    import json

    from gyrobench.base.atomic import atomic_folder
    from gyrobench.scenarios.cli.bench import scheduler_executor
    from gyrobench.scenarios.maps.build import map_paper, write_map
    from gyrobench.scenarios.maps.region import nominal_text, region_finding
    from gyrobench.scenarios.reports.outputs import REPORT_MARKER, report_manifest
    from gyrobench.scenarios.runner import units

    out = Path(args.out)
    db = Path(args.db) if args.db else units.default_db(out)
    executor, close = scheduler_executor(args)
    t0 = time.perf_counter()
    try:
        mapped = map_paper(mod, points=points, units_per_point=k, seed=args.seed, executor=executor,
                           workers=args.workers, db=db, progress=not args.quiet)
    finally:
        if close is not None:
            close()
    command = "gyrobench " + " ".join(shlex.quote(a) for a in args.argv)
    with atomic_folder(out) as tmp:
        path = write_map(mapped, tmp / mod.NAME, command=command)
        kept = keep_other_maps(out, tmp, mod.NAME)
        doc = {"written_by": "gyrobench reproduce --map; replaced as a whole by the next report while it holds "
                             "only these files", "files": report_manifest(tmp)}
        (tmp / REPORT_MARKER).write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
    r = mapped.result
    counts = r.counts()
    print(f"{mod.NAME}: {len(r.design)} points x {k} units in {time.perf_counter() - t0:.1f} s "
          f"({mapped.units.computed} computed, {mapped.units.reused} reused; "
          f"units' run time summed {mapped.units.run_s:.1f} s)")
    print(f"  region: {region_finding(r)}")
    if r.refinement is not None:
        print(f"  refinement: {r.refinement.reason}")
    print(f"  {nominal_text(r)}")
    for c in r.constraints:
        print(f"  {c.id:<36} satisfied on {counts[c.id]} of {len(r.design)} points")
    for m in r.claims:
        print(f"  {m.claim.id:<36} {m.verdict_text()} (whole family: holds on {m.family_k} of "
              f"{m.family_n} points that could test it)")
    print(f"map: {out / path.relative_to(tmp)}")
    if kept:
        print(f"  kept the maps of {', '.join(kept)} already in {out}")
    return 0


def keep_other_maps(out: Path, tmp: Path, name: str) -> list[str]:
    """Copy the maps of the other papers that ``out`` holds into the new folder ``tmp``.

    A map run replaces its report folder as a whole, so without this the maps of several papers
    could not share one folder (and so one report). Only the map's own files are carried over
    (map.json, map_run.json and the map's figures), byte for byte.

    Parameters
    ----------
    out : Path
        The report folder being replaced (absent: nothing to keep).
    tmp : Path
        The new folder that replaces it.
    name : str
        The paper just mapped (its old map is not kept).

    Returns
    -------
    list of str
        The papers whose maps were kept, sorted.
    """
    import shutil

    from gyrobench.scenarios.reports.map_section import FIGURES, MAP_FILE, RUN_FILE

    kept: list[str] = []
    if not out.is_dir():
        return kept
    for old in sorted(d for d in out.iterdir() if d.is_dir() and d.name != name and (d / MAP_FILE).is_file()):
        (tmp / old.name).mkdir(exist_ok=True)
        for file in (MAP_FILE, RUN_FILE, *(f for f, _ in FIGURES)):
            if (old / file).is_file():
                shutil.copyfile(old / file, tmp / old.name / file)
        kept.append(old.name)
    return kept
