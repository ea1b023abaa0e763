"""The ``bench`` verb of the ``gyrobench`` command line.

::

    gyrobench bench SCENARIO --compensator module:attr --seeds 0:100
    gyrobench bench --part FILE.toml|NAME [--model physics|budget] --compensator module:attr ...
        [--workers N | --scheduler ADDRESS] [--db FILE] [--config FILE.toml]
        [--save-baseline FILE.json] [--baseline FILE.json] [--alpha 0.05] [--quiet]
        [--seeds auto] [--min-change 0.05] [--allow-underpowered] [--no-references]
        [--seed-timeout SECONDS] [--seed-memory GIB]

Exit status of :func:`run` (see :mod:`gyrobench.scenarios.cli.exits`): 0 on success, 1 when
the campaign is significantly worse than ``--baseline`` on some primary score by more than the
equivalence margin ``--min-change``. The compensator runs in its own processes
(:mod:`gyrobench.scenarios.bench.sandbox`): its module is never imported here, and nothing it
does (an exit, a signal, ``KeyboardInterrupt`` at import) becomes this process's status. Bad
input raises
``ValueError``, ``TypeError`` or ``FileNotFoundError`` with a one-line message (the
command line wrapper prints it and exits 2). So does a compensator that raises on a
seed (:class:`gyrobench.scenarios.bench.CompensatorError`, a ``ValueError``): exit 2 means
"could not score", never "got worse". A compensator whose prediction or scores are not
finite (NaN, inf) or complex on some seeds, that calls ``sys.exit`` or ``os._exit``, crashes
(a segfault), or runs past ``--seed-timeout`` (default 600 s) makes those seeds *failed*
(without ``--scheduler`` each seed runs in its own forked process, also with ``--workers 0``,
which runs them one at a time):
they are recorded in the
database, left out of the summary, and :class:`~gyrobench.scenarios.bench.FailedSeedsError`
is raised after the summary (and the comparison) are printed, naming the seeds: exit 3,
whatever the comparison says, and no baseline is written. A comparison that cannot be made
once the campaign has run (no seed or no score can be paired:
:class:`~gyrobench.scenarios.bench.ComparisonError`) also exits 3. A timed-out seed is not
stored (a rerun retries it). A worker process killed by SIGKILL (the OOM killer),
or another run of the same campaign on the same database that got other scores, raises
:class:`~gyrobench.scenarios.cli.exits.InternalError`: exit 4. With ``GYROBENCH_TRACEBACK=1``
in the environment the traceback is printed on stderr first.

Everything that can be checked without computing is checked before the campaign
starts, including the gate's power (:func:`gyrobench.scenarios.bench.gate.plan_power`: a
comparison, or a baseline written, whose seeds cannot reach ``--alpha`` with the scenario's
primary scores is refused in one line naming the seeds needed, exit 2, unless
``--allow-underpowered``, which prints a WARNING as the first line): the scenario,
configuration, compensator, seeds, the ``--baseline`` file
(readable, of the same scenario, sharing seeds with ``--seeds``) and the
``--save-baseline`` path (not a folder; its folder exists: it is never created).
"""

from __future__ import annotations

import argparse
import os
from typing import Any

from gyrobench.scenarios.cli import exits
from gyrobench.scenarios.cli.common import MAX_WORKERS, input_file, ranged

__all__ = ["add_parser", "run", "scheduler_executor"]


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Add the ``bench`` sub-command to ``subparsers``; its ``func`` default is :func:`run`.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``gyrobench`` command's subparsers.

    Returns
    -------
    argparse.ArgumentParser
        The ``bench`` parser.
    """
    p = subparsers.add_parser(
        "bench",
        help="score a compensator on a scenario over many seeds; compare with a baseline",
        description=(
            "Fit and score a compensator on every seed of a scenario's compensation task; "
            "print each "
            "score's mean with a 95 % confidence interval. Finished seeds are kept in --db, so an "
            "interrupted campaign resumes where it stopped. With --baseline, exit 1 when a "
            "score is "
            "significantly worse by more than --min-change on a primary score's mean (paired t test of the mean "
            "change against the margin, Holm-adjusted "
            "over the scenario's primary scores; the others are reported, not gated). A comparison whose seeds "
            "cannot reach --alpha is refused before computing (exit 2) unless --allow-underpowered."
        ),
    )
    p.add_argument(
        "scenario",
        nargs="?",
        help="scenario name with a compensation stage (see 'gyrobench list', marked [bench]); with --part: "
        "'part' or omitted",
    )
    p.add_argument(
        "--part",
        metavar="FILE.toml|NAME",
        help="your own part: a part file (twin --save-part writes one) or a built-in part ('gyrobench parts'); "
        "the compensator is calibrated in one chamber program and scored in another (docs/bench.md)",
    )
    p.add_argument(
        "--model",
        choices=("physics", "budget"),
        help="with --part: run the part on its physics model or its datasheet budget (default: the part's own "
        "default_model, as 'simulate device' does: physics for a built-in part, budget for a twin's part file)",
    )
    p.add_argument(
        "--compensator",
        required=True,
        metavar="MODULE:ATTR",
        help="a scikit-learn estimator (instance or class) or a fit function f(X, y) -> predict, "
        "as 'package.module:attr'",
    )
    p.add_argument(
        "--seeds",
        default=None,
        help="'START:STOP' (half-open), '1,5,9', or 'auto': the count that detects a --min-change "
        "of the primary scores (from the --baseline's spread) (default: the --baseline's seeds, else 0:20)",
    )
    p.add_argument(
        "--min-change",
        type=ranged("--min-change", 0.0, 10.0, low_open=True, unit="(fraction of the mean)"),
        default=None,
        metavar="FRACTION",
        help="equivalence margin of the gate, as a fraction of the baseline's score: a change within it is "
        "never a regression, however significant; --seeds auto sizes the run to detect twice it with power "
        "0.8 (default 0.05 = 5 %%)",
    )
    p.add_argument(
        "--allow-underpowered",
        action="store_true",
        help="run a comparison whose seeds cannot reach --alpha (refused otherwise, exit 2); "
        "a WARNING line comes first",
    )
    p.add_argument(
        "--no-references",
        action="store_true",
        help="do not score the uncompensated output and the paper's method beside the compensator",
    )
    p.add_argument(
        "--workers",
        type=ranged("--workers", 0, MAX_WORKERS, integer=True, unit="processes"),
        default=None,
        help="local worker processes (default: usable CPUs; 0 = one seed at a time, each in its own forked "
        "process: the compensator need not pickle)",
    )
    p.add_argument(
        "--seed-timeout",
        type=ranged("--seed-timeout", 0.0, 1e6, low_open=True, unit="s"),
        default=None,
        metavar="SECONDS",
        help="per-seed time limit; a seed past it is failed (exit 3) and retried by a rerun (default 600)",
    )
    p.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="dask.distributed scheduler address (e.g. tcp://host:8786); seeds run on that cluster",
    )
    p.add_argument(
        "--db",
        default=None,
        help="SQLite file keeping every finished seed (default gyrobench-bench.sqlite)",
    )
    p.add_argument("--config", metavar="FILE.toml", help="override the scenario's configuration")
    p.add_argument(
        "--save-baseline",
        metavar="FILE.json",
        help="write this campaign's per-seed scores as a baseline",
    )
    p.add_argument(
        "--baseline",
        metavar="FILE.json",
        help="compare with a stored baseline; exit 1 on a significant regression",
    )
    p.add_argument(
        "--alpha",
        type=ranged("--alpha", 0.0, 1.0, low_open=True, high_open=True),
        default=0.05,
        help="family-wise significance level of the comparison (default 0.05)",
    )
    _add_trust_flags(p)
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    p.add_argument("--force", action="store_true",
                   help="replace an existing --save-baseline file that gyrobench did not write (default: refused); "
                        "never the --baseline or another input, never a foreign --db")
    p.set_defaults(func=run)
    return p


def check_bench_outputs(args: argparse.Namespace, db: str) -> None:
    """--save-baseline and --db through the output rule (:mod:`gyrobench.base.safety`): never the
    --baseline, the --config or the compensator's source; a .json baseline; a database gyrobench
    did not make refused before anything is written to it; folders are never created."""
    import sys
    from pathlib import Path

    from gyrobench.base.safety import Output
    from gyrobench.scenarios.cli.common import check_outputs

    outs = []
    if args.save_baseline:
        outs.append(Output(Path(args.save_baseline), "--save-baseline", suffixes=(".json",), create_parents=False))
    outs.append(Output(Path(db), "--db" if args.db is not None else "--db (default)", kind="database",
                       create_parents=False))
    module = sys.modules.get(str(args.compensator).partition(":")[0])
    source = getattr(module, "__file__", None)
    part = args.part if args.part is not None and args.part.lower().endswith(".toml") else None
    check_outputs(args, outs, [("--baseline", args.baseline), ("--config", args.config), ("--compensator", source),
                               ("--part", part)])


def scheduler_executor(args: argparse.Namespace) -> tuple[Any, Any]:
    """The executor for ``--scheduler`` and the call that closes it.

    (executor, closer) for ``args.scheduler`` (a dask.distributed address); (None, None) for the
    local process pool. Shared by ``gyrobench bench`` and ``gyrobench reproduce``.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed arguments with ``scheduler`` (a dask.distributed address or None).

    Returns
    -------
    tuple
        (executor, closer); (None, None) for the local process pool.
    """
    if not args.scheduler:
        return None, None
    if args.workers is not None:
        raise ValueError("give either --workers or --scheduler, not both")
    try:
        from distributed import Client
    except ImportError:
        raise ValueError(
            "--scheduler needs dask.distributed: pip install 'gyrobench[distributed]'"
        ) from None
    try:
        client = Client(args.scheduler, timeout="10s")
    except (OSError, TimeoutError) as exc:
        raise ValueError(f"--scheduler: cannot connect to {args.scheduler!r}: {exc}") from None
    return client.get_executor(), client.close


def run(args: argparse.Namespace) -> int:
    """Run the campaign described by ``args``; return the exit status (0 ok, 1 regression).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed ``bench`` arguments.

    Returns
    -------
    int
        The exit status: 0 ok, 1 a significant regression.
    """
    from gyrobench.scenarios import bench, registry

    # 'mylab.models:mine' is found from the current folder first, as 'python -m' would
    # (worker processes inherit sys.path)
    bench.prepend_import_path(os.getcwd())

    auto = args.seeds is not None and args.seeds.strip().lower() == "auto"
    seeds = "auto" if auto else bench.parse_seeds(args.seeds) if args.seeds is not None else None
    if args.workers is not None and args.workers < 0:
        raise ValueError(f"--workers must be >= 0; got {args.workers}")
    seed_timeout = bench.check_seed_timeout(
        bench.DEFAULT_SEED_TIMEOUT_S if args.seed_timeout is None else args.seed_timeout
    )
    if not 0 < args.alpha < 1:
        raise ValueError(f"--alpha must be in (0, 1); got {args.alpha}")
    module = bench.resolve_scenario(_scenario_name(args))
    for flag, given in (("--config", args.config), ("baseline file", args.baseline)):  # a FIFO or device never ends
        if given:
            input_file(given, flag)
    config = registry.load_config(module, args.config) if args.config else module.Config()
    if args.part is not None or args.model is not None:
        from gyrobench.scenarios.cli.bench_part import part_config

        config = part_config(args, config)
    _check_compensator_spec(args.compensator)  # imported only in the compensator's own process
    # read and check the baseline first: a bad or mismatched file fails before any computing
    baseline = bench.load_baseline(args.baseline) if args.baseline else None
    if baseline is not None:
        bench.check_baseline_matches(
            baseline, module, None if auto else seeds, what=f"--baseline {args.baseline!r}", seeds_what="--seeds"
        )
        if getattr(module, "NAME", None) == "part":
            from gyrobench.scenarios.cli.bench_part import check_same_part

            check_same_part(baseline, config, args.baseline)
    # power before the run: a gate that can never fire is refused here, before any computing
    plan = bench.plan_power(
        getattr(module, "NAME", module.__name__),
        seeds,
        baseline=baseline,
        alpha=args.alpha,
        gate=baseline is not None or bool(args.save_baseline),
        allow_underpowered=args.allow_underpowered,
        min_change=_min_change(args),
    )
    seeds = plan.seeds
    db = args.db if args.db is not None else bench.DEFAULT_DB
    check_bench_outputs(args, db)  # before connecting to a cluster or computing
    for line in (plan.warning, plan.auto):
        if line:
            print(line, flush=True)
    if getattr(module, "NAME", None) == "part":
        from gyrobench.scenarios.cli.bench_part import part_line

        print(part_line(config, args.part), flush=True)
    executor, close = scheduler_executor(args)
    try:
        campaign = bench.run_campaign(
            module,
            args.compensator,
            seeds,
            config=config,
            executor=executor,
            workers=args.workers,
            db=db,
            progress=not args.quiet,
            seed_timeout=seed_timeout,
            seed_memory=_seed_memory(args),
        )
        references = (
            {}
            if args.no_references
            else bench.reference_campaigns(module, seeds, config=config, executor=executor, workers=args.workers, db=db)
        )
    except bench.CompensatorError as exc:
        if exits.traceback_wanted():
            raise  # the command line prints exc.traceback_text (the worker's traceback)
        raise exc.with_context(f"set {bench.TRACEBACK_ENV}=1 for its traceback") from exc
    finally:
        if close is not None:
            close()
    summary = bench.format_summary(campaign, references)
    result = (
        bench.compare(baseline, campaign, alpha=args.alpha, references=references, min_change=_min_change(args))
        if baseline is not None
        else None
    )
    if result is not None and result.power_line:  # first, before the tables: a weak gate says so
        print(result.power_line)
    print(summary)
    if result is not None:
        print(result.format())
    # the comparison may find failed seeds the campaign did not record (a non-finite score read
    # back); either way "FAILED" is never followed by exit 0
    if campaign.failed:
        failure, failed = campaign.failure_text(), sorted(campaign.failed)
    elif result is not None and result.failed_seeds:
        failure, failed = result.failure, list(result.failed_seeds)
    else:
        failure, failed = "", []
    if failure:
        what = []
        if args.save_baseline:
            what.append(f"--save-baseline {args.save_baseline!r} not written")
        if result is not None:
            what.append(f"the comparison with --baseline {args.baseline!r} fails")
        raise bench.FailedSeedsError(failure + "".join(f"; {w}" for w in what), seeds=failed)
    if args.save_baseline:
        path = bench.save_baseline(args.save_baseline, campaign, alpha=args.alpha, min_change=_min_change(args))
        print(f"baseline written to {path}")
        print(_baseline_power_line(campaign, args.alpha, _min_change(args)))
    if result is not None:
        return exits.REGRESSION if result.regressions else exits.OK
    return exits.OK



# ----------------------------------------------------------------------------- trust flags
#: default of ``--seed-memory`` [GiB]: the compensator's address-space cap per seed
DEFAULT_SEED_MEMORY_GIB = 4.0


def _add_trust_flags(p: argparse.ArgumentParser) -> None:
    """The flags of the compensator's sandbox (:mod:`gyrobench.scenarios.bench.sandbox`)."""
    p.add_argument(
        "--seed-memory",
        type=ranged("--seed-memory", 0.25, 1e6, unit="GiB"),
        default=DEFAULT_SEED_MEMORY_GIB,
        metavar="GIB",
        help="address-space cap (RLIMIT_AS) of the compensator's process per seed; a seed past it fails "
        "(exit 3) and is retried by a rerun (default 4)",
    )


def _seed_memory(args: argparse.Namespace) -> int:
    return int(args.seed_memory * 1024**3)


def _scenario_name(args: argparse.Namespace) -> str:
    """The scenario: the positional, or ``part`` with ``--part`` (the only scenario it goes with)."""
    if args.part is not None:
        if args.scenario not in (None, "part"):
            raise ValueError(f"--part runs the scenario 'part'; got scenario {args.scenario!r} (omit it)")
        return "part"
    if args.scenario is None:
        raise ValueError("bench needs a SCENARIO (see 'gyrobench list', marked [bench]) or --part FILE.toml|NAME")
    return str(args.scenario)


def _check_compensator_spec(spec: str) -> None:
    """``spec`` reads as ``package.module:attr`` (its module is imported only in the compensator's
    own process, so an exit or a hang at import never becomes this process's)."""
    if spec.count(":") != 1 or not all(spec.split(":")):
        raise ValueError(f"compensator must be 'package.module:attr'; got {spec!r}")


def _min_change(args: argparse.Namespace) -> float:
    from gyrobench.scenarios.bench.power import DEFAULT_MIN_CHANGE

    return DEFAULT_MIN_CHANGE if args.min_change is None else float(args.min_change)


def _baseline_power_line(campaign: Any, alpha: float, margin: float) -> str:
    """What a baseline's seeds detect, in one line (from the upper confidence bound of its
    seed-to-seed spread: conservative)."""
    from gyrobench.scenarios.bench import gate

    parts = []
    for d in gate.detectable(campaign, alpha=alpha, min_change=margin):
        rel = margin + d.relative
        parts.append(f"{d.name} {100 * rel:.3g} %" if rel != float("inf") else f"{d.name} (none: too few seeds)")
    return (
        f"detectable change at {len(campaign.ok_seeds)} seeds (power 0.8, alpha {alpha:g}, margin {100 * margin:g} %, "
        f"mean change, assuming per-seed contrasts as spread as the baseline's own scores at the upper bound of "
        f"their spread plus that of a change carried by half the seeds; a comparison prints the figure from its "
        f"observed differences): "
        f"{', '.join(parts) or '(no primary score)'}"
    )
