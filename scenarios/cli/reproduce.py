"""``gyrobench reproduce``: the papers' claims over simulated units and their controls, and one report."""

from __future__ import annotations

import shlex
import time
from pathlib import Path

from gyrobench.scenarios.cli.common import (
    MAX_WORKERS,
    BadInput,
    check_outputs,
    closing,
    input_file,
    positive_int,
    ranged,
    seed,
    units_or_auto,
)

__all__ = ["AUTO_START_UNITS", "DEVIATION_UNITS", "MAX_UNITS", "add_parser"]

#: units each deviation's variant runs over with a bare ``reproduce --deviations``
DEVIATION_UNITS = 5
#: ``--units auto``: the first batch, and the default ceiling (``--max-units``)
AUTO_START_UNITS = 20
MAX_UNITS = 60


def _cmd_reproduce(args) -> int:
    """Run the scenarios; a paper scenario (``experiment`` + ``CLAIMS``) over ``--units`` units
    through the shared runner (:mod:`gyrobench.scenarios.runner.units`), any other by its ``run``."""
    from gyrobench.scenarios import registry
    from gyrobench.scenarios.reports.outputs import output_lock

    if args.map:
        from gyrobench.scenarios.cli.reproduce_map import cmd_map

        return cmd_map(args)
    if args.points is not None or args.units_per_point is not None:
        raise BadInput("--points and --units-per-point go with --map")
    names = registry.available() if args.all else list(args.scenarios)
    if not names:
        raise BadInput("name at least one scenario or give --all (see 'gyrobench list')")
    if args.all and args.scenarios:
        raise BadInput("give either --all or scenario names, not both")
    if args.config and len(names) != 1:
        raise BadInput("--config applies to one scenario; name exactly one")
    if args.workers is not None and args.workers < 0:
        raise BadInput(f"--workers must be an integer >= 0; got {args.workers}")
    if args.units == "auto":
        start_units, max_units = min(AUTO_START_UNITS, args.max_units), args.max_units
    elif args.max_units != MAX_UNITS:
        raise BadInput(f"--max-units goes with --units auto; got --units {args.units}")
    else:
        start_units, max_units = args.units, None
    from gyrobench.scenarios.runner.units import check_run_size

    try:  # O(1), before any seed list exists
        check_run_size(max_units or start_units, args.seed, what="--max-units" if max_units else "--units",
                       seed_name="--seed")
        if args.deviations:
            check_run_size(args.deviations, args.seed, what="--deviations", seed_name="--seed")
    except ValueError as exc:
        raise BadInput(str(exc)) from None
    mods = [registry.get(n) for n in names]  # fails fast on an unknown name
    if args.config is not None:
        input_file(args.config, "--config")
    configs = [registry.load_config(m, args.config) for m in mods]
    _check_reproduce_outputs(args)  # before any work
    with output_lock(args.out, what="--out"):  # a second reproduce into the same --out is refused
        return _reproduce(args, mods, configs, start_units, max_units)


def _check_reproduce_outputs(args) -> None:
    """--out (a report folder, replaced as a whole) and --db (or its default beside --out) through the
    output rule (gyrobench.base.safety): never the --config, a foreign folder or a foreign database."""
    from gyrobench.base.safety import Output
    from gyrobench.scenarios.runner import units

    db = Path(args.db) if args.db else units.default_db(Path(args.out))
    check_outputs(args, [Output(Path(args.out), "--out", kind="report"),
                         Output(db, "--db" if args.db else "--db (default)", kind="database")],
                  [("--config", args.config)])


def _reproduce(args, mods, configs, start_units: int, max_units: int | None) -> int:
    """The work of ``reproduce`` once its inputs are checked and its output is locked."""
    from tqdm import tqdm

    from gyrobench.scenarios.cli.bench import scheduler_executor
    from gyrobench.scenarios.reports.outputs import write_report_as_a_set
    from gyrobench.scenarios.reports.report import claim_tally, tally_text
    from gyrobench.scenarios.runner import units

    if not args.scheduler:  # local units share this machine's memory: one per worker at once
        source = f"config file {args.config!r}" if args.config else "its default configuration"
        for m, cfg in zip(mods, configs, strict=True):
            if units.is_paper_scenario(m):
                n_at_once = units.concurrent_units(start_units, args.workers)
                units.check_unit_memory(m, cfg, concurrent=n_at_once, source=source)
    out = Path(args.out)
    db = Path(args.db) if args.db else units.default_db(out)
    executor, close = scheduler_executor(args)
    workers = args.workers
    from gyrobench.scenarios.runner.executors import local_pool, stop_pool

    pool = None
    if executor is None and workers != 0 and any(units.is_paper_scenario(m) for m in mods):
        # one local pool for every paper scenario (workers start and import once, not per scenario);
        # its workers die with this process, and are killed on Ctrl-C, SIGTERM or an error
        pool = local_pool(workers)
        executor, workers = pool, None
    outcomes = []
    t0 = time.perf_counter()
    ok = False
    try:
        bar = tqdm(list(zip(mods, configs, strict=True)), desc="reproduce", unit="scenario", disable=args.quiet)
        with closing(bar):
            for mod, cfg in bar:
                bar.set_postfix_str(mod.NAME)
                if units.is_paper_scenario(mod):
                    outcomes.append(units.run_paper(mod, cfg, seed=args.seed, n_units=start_units, executor=executor,
                                                    workers=workers, db=db, progress=not args.quiet,
                                                    deviation_units=args.deviations or 0, max_units=max_units,
                                                    keep_units=args.keep_units))
                else:
                    outcomes.append(mod.run(cfg, args.seed, progress=not args.quiet))
        ok = True
    finally:
        if pool is not None:
            stop_pool(pool, kill=not ok)
        elif close is not None:
            close()
    from gyrobench.scenarios.reports.map_section import load_maps

    # a map the folder holds (reproduce NAME --map) goes into its scenario's section of the new report
    maps = load_maps(out, [o.scenario for o in outcomes])
    index = write_report_as_a_set(outcomes, out, command="gyrobench " + " ".join(shlex.quote(a) for a in args.argv),
                                  maps=maps)
    print(f"{len(outcomes)} scenario(s) in {time.perf_counter() - t0:.1f} s")
    for name in maps:
        print(f"  {name}: its device-family map ({out / name / 'map.json'}) is in the report")
    for o in outcomes:
        if o.claims:
            what = f"{o.units} unit(s); {tally_text(claim_tally(o.claims))}"
        else:
            held = sum(1 for h in o.headlines if h.holds is True)
            what = f"{held}/{sum(1 for h in o.headlines if h.holds is not None)} testable headline conclusions hold"
        print(f"  {o.scenario:<20} {o.runtime_s:7.1f} s   {what}")
    print(f"report: {index}")
    return 0


def add_parser(sub) -> None:
    """Add ``reproduce`` to the subparsers ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The ``gyrobench`` command's subparsers.
    """
    s = sub.add_parser("reproduce", help="run scenarios and write the report (Markdown, HTML, PNG, results.json)")
    s.add_argument("scenarios", nargs="*", help="scenario names (see 'gyrobench list')")
    s.add_argument("--all", action="store_true", help="every registered scenario")
    s.add_argument("--out", default="gyrobench-report", help="output folder (default gyrobench-report)")
    s.add_argument("--seed", type=seed, default=0, help="seed of the first unit (default 0)")
    s.add_argument("--max-units", type=positive_int("--max-units"), default=MAX_UNITS,
                   help=f"with --units auto: the most units a claim may use (default {MAX_UNITS})")
    s.add_argument("--units", type=units_or_auto, default=20,
                   help="paper scenarios: units simulated, seeds SEED..SEED+N-1 (default 20; 1 = quick look; "
                   "'auto': 20, then batches of 10 while a claim's interval straddles 50 %%, up to --max-units, every "
                   "look judged at a group-sequential z that keeps the chance of deciding a 50 %% claim at 5 %%)")
    s.add_argument("--workers", type=ranged("--workers", 0, MAX_WORKERS, integer=True, unit="processes"), default=None,
                   help="local worker processes for the units (default: usable CPUs; 0 = in this process)")
    s.add_argument("--scheduler", metavar="ADDRESS", help="dask.distributed scheduler address; units run there")
    s.add_argument("--db", help="SQLite file keeping every finished unit, so a rerun resumes "
                                "(default OUT/units.sqlite)")
    s.add_argument("--config", help="TOML file overriding one scenario's parameters")
    s.add_argument("--deviations", nargs="?", const=DEVIATION_UNITS, type=positive_int("--deviations"),
                   metavar="N", help="also run each deviation's config variant (the paper's protocol) over the "
                   f"first N units (default {DEVIATION_UNITS}) and report every claim's measured change")
    s.add_argument("--keep-units", action="store_true",
                   help="store every unit's whole result in --db (default: what the claims and the report read, "
                   "the figures' data of the units the report draws only)")
    s.add_argument("--map", action="store_true",
                   help="one paper: map its device family (the paper-consistent region and every method claim "
                        "over it) into OUT/NAME/map.json and PNGs")
    s.add_argument("--points", type=ranged("--points", 2, 4096, integer=True, unit="points"), default=None,
                   help="with --map: design points (a power of two gives a Sobol design; default 16)")
    s.add_argument("--units-per-point", type=ranged("--units-per-point", 1, 1000, integer=True, unit="units"),
                   default=None, help="with --map: units at each point (default 3)")
    s.add_argument("-q", "--quiet", action="store_true", help="no progress bars")
    s.add_argument("--force", action="store_true",
                   help="replace an earlier report in --out whose files were edited or added to (default: refused); "
                        "never a folder that is not a gyrobench report, never a foreign --db")
    s.set_defaults(func=_cmd_reproduce)
