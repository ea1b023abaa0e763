"""pytest plugin (entry point ``pytest11``): assert "no regression" of a compensator in your tests.

Installing gyrobench registers this plugin; its fixture ``gyrobench_bench`` scores
a compensator on a scenario over many seeds and compares the per-seed scores with
a stored baseline (paired t test of the mean change against the margin, Holm-adjusted over the
scenario's primary scores; see :func:`gyrobench.scenarios.bench.compare`). Seeds that
cannot reach ``alpha`` fail the test before anything is computed, naming the seeds needed
(``allow_underpowered=True`` turns that into a warning)::

    from mylab.models import my_regressor

    def test_my_compensator_does_not_regress(gyrobench_bench):
        gyrobench_bench.assert_no_regression(
            "ifog_thermal", my_regressor, baseline="baselines/ifog_ridge.json", seeds=range(20)
        )

``baseline`` is relative to the test file's folder. A ``"module:attr"`` compensator is
imported from the pytest rootdir first (the folder of your ``pyproject.toml``,
``pytest.ini`` or ``setup.cfg``), then from the folder pytest was started in, before
anything installed, whatever your own packages are called. Create or refresh the
baselines with ``pytest --gyrobench-save-baselines`` (the asserting tests then
write the file instead of comparing). Seeds run in the test process by default;
``--gyrobench-workers N`` (or ``workers=N``) uses N local processes. Campaign
results are kept in a database in pytest's temporary folder for the session, so
two tests asking for the same campaign compute it once.

Options
-------
``--gyrobench-save-baselines``
    write the baselines named by ``assert_no_regression`` instead of comparing.
``--gyrobench-workers N``
    local worker processes for the campaigns (default 0: in the test process).
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import pytest

#: seeds used when neither the test nor an existing baseline names them
DEFAULT_SEEDS = tuple(range(20))


def pytest_addoption(parser: pytest.Parser) -> None:
    """Register the plugin's command-line options with pytest.

    Parameters
    ----------
    parser : pytest.Parser
        pytest's option parser; the options go to the group ``gyrobench``.
    """
    group = parser.getgroup("gyrobench", "gyrobench compensator regression tests")
    group.addoption(
        "--gyrobench-save-baselines",
        action="store_true",
        default=False,
        help="write the baselines named by gyrobench_bench.assert_no_regression, do not compare",
    )
    group.addoption(
        "--gyrobench-workers",
        type=int,
        default=0,
        metavar="N",
        help="local worker processes for gyrobench campaigns (default 0: in the test process)",
    )


class GyrobenchBench:
    """What the ``gyrobench_bench`` fixture gives a test.

    Parameters
    ----------
    root : Path
        Folder that relative baseline paths are read from (the test file's folder).
    db : Path
        SQLite file of the campaigns' finished seeds.
    save : bool
        Write the baselines instead of comparing (``--gyrobench-save-baselines``).
    workers : int
        Worker processes for the seeds.
    """

    def __init__(self, *, root: Path, db: Path, save: bool, workers: int) -> None:
        self.root = root
        self.db = db
        self.save = save
        self.workers = workers

    def campaign(
        self,
        scenario: Any,
        compensator: Any,
        seeds: Iterable[int] | str = DEFAULT_SEEDS,
        *,
        config: Any = None,
        workers: int | None = None,
    ):
        """Run (or read back) a campaign: see :func:`gyrobench.scenarios.bench.run_campaign`."""
        from gyrobench.scenarios import bench

        return bench.run_campaign(
            scenario,
            compensator,
            seeds,
            config=config,
            workers=self.workers if workers is None else workers,
            db=self.db,
            progress=False,
        )

    def assert_no_regression(
        self,
        scenario: Any,
        compensator: Any,
        *,
        baseline: str | os.PathLike,
        seeds: Iterable[int] | str | None = None,
        config: Any = None,
        alpha: float = 0.05,
        workers: int | None = None,
        directions: Mapping[str, int] | None = None,
        allow_underpowered: bool = False,
        min_change: float | None = None,
    ):
        """Fail the test if ``compensator`` is significantly worse than ``baseline`` on a primary
        score (:mod:`gyrobench.scenarios.bench.primary`; the others are reported, not gated), or
        if it failed on any seed (a non-finite prediction or score; the message names the
        seeds).

        Before computing anything, the seeds must be able to reach ``alpha`` with the scenario's
        primary scores (:func:`gyrobench.scenarios.bench.gate.plan_power`): else the test fails in
        one line naming the seeds needed, unless ``allow_underpowered=True``, which emits an
        :class:`~gyrobench.scenarios.bench.power.UnderpoweredWarning` (in pytest's warnings
        summary) instead. A failing comparison's message shows the uncompensated output and the
        paper's method beside the compensator.

        Parameters
        ----------
        scenario, compensator, config
            As for :func:`gyrobench.scenarios.bench.run_campaign`.
        baseline : path
            Baseline JSON (:func:`gyrobench.scenarios.bench.save_baseline`), relative to the
            test file's folder unless absolute.
        seeds : optional
            Default: the baseline's seeds (or :data:`DEFAULT_SEEDS` when writing a new one).
            ``"auto"``: the count that detects a ``min_change`` of every primary score (from
            the baseline's spread; see :func:`gyrobench.scenarios.bench.power.auto_seeds`).
        alpha : float
            Family-wise significance level over the primary scores.
        directions : mapping, optional
            Overrides for :func:`gyrobench.scenarios.bench.score_direction`.
        allow_underpowered : bool
            Run a comparison whose seeds cannot reach ``alpha`` (with a warning).
        min_change : float, optional
            The gate's equivalence margin, relative to the baseline's score (default
            :data:`gyrobench.scenarios.bench.power.DEFAULT_MIN_CHANGE`, 5 %): a change within it
            never fails the test; ``seeds="auto"`` sizes the run to detect twice it (power 0.8).
            An underpowered comparison (its seeds detect more than twice the margin, from the
            observed per-seed differences) warns with
            :class:`~gyrobench.scenarios.bench.power.UnderpoweredWarning`.

        Returns
        -------
        scenarios.bench.Comparison or None
            None when the baseline was (re)written (``--gyrobench-save-baselines``).
        """
        __tracebackhide__ = True
        from gyrobench.scenarios import bench
        from gyrobench.scenarios.bench.power import DEFAULT_MIN_CHANGE

        min_change = DEFAULT_MIN_CHANGE if min_change is None else min_change

        path = Path(baseline)
        relative = not path.is_absolute()
        if relative:
            path = self.root / path
        stored = bench.load_baseline(path) if path.is_file() else None
        if stored is not None:
            try:  # before computing anything; a rewrite (save) may change the seeds
                bench.check_baseline_matches(
                    stored,
                    scenario,
                    None if self.save or (isinstance(seeds, str) and seeds.strip().lower() == "auto") else seeds,
                    what=f"gyrobench baseline {str(path)!r}",
                )
            except ValueError as exc:
                pytest.fail(str(exc), pytrace=False)
        if self.save and not relative:  # a missing folder fails now, not after the campaign
            bench.check_baseline_path(path)
        if stored is None and not self.save:
            pytest.fail(
                f"gyrobench baseline {str(path)!r} does not exist; create it with "
                "'pytest --gyrobench-save-baselines' from the compensator you trust",
                pytrace=False,
            )
        module = bench.resolve_scenario(scenario)
        auto = isinstance(seeds, str) and seeds.strip().lower() == "auto"
        try:  # power before the run: a gate that can never fire fails here, before computing
            plan = bench.plan_power(
                getattr(module, "NAME", module.__name__),
                "auto" if auto else None if seeds is None else _seed_tuple(seeds),
                baseline=None if self.save else stored,
                alpha=alpha,
                gate=True,
                allow_underpowered=allow_underpowered,
                min_change=min_change,
                default=stored.seeds if stored is not None else DEFAULT_SEEDS,
                seeds_flag="seeds",
                allow_flag="allow_underpowered=True",
            )
        except ValueError as exc:
            pytest.fail(f"{path.name}: {exc}", pytrace=False)
        if plan.warning:
            warnings.warn(bench.UnderpoweredWarning(f"{path.name}: {plan.warning}"), stacklevel=2)
        campaign = self.campaign(module, compensator, plan.seeds, config=config, workers=workers)
        if self.save:
            if campaign.failed:  # a baseline from a compensator that fails is never written
                pytest.fail(
                    f"gyrobench baseline {str(path)!r} not written: {campaign.failure_text()}",
                    pytrace=False,
                )
            if relative:  # a baseline folder beside the tests is created; absolute paths are not
                path.parent.mkdir(parents=True, exist_ok=True)
            bench.save_baseline(path, campaign)
            return None
        assert stored is not None  # a missing baseline failed above unless saving
        try:
            result = bench.compare(stored, campaign, alpha=alpha, directions=directions, min_change=min_change)
        except bench.ComparisonError as exc:  # a gate that cannot compare does not pass
            pytest.fail(
                f"{campaign.compensator} on {campaign.scenario} against {path.name}: {exc}",
                pytrace=False,
            )
        if result.failed_seeds:  # fails whatever the other seeds say (exit 3 on the command line)
            pytest.fail(
                f"{campaign.compensator} on {campaign.scenario} against {path.name}: "
                f"{result.failure}",
                pytrace=False,
            )
        if result.regressions:
            refs = bench.reference_campaigns(
                module, plan.seeds, config=config, workers=self.workers if workers is None else workers, db=self.db
            )
            result = bench.compare(
                stored, campaign, alpha=alpha, directions=directions, references=refs, min_change=min_change
            )
            pytest.fail(
                (f"{plan.warning}\n" if plan.warning else "")
                + f"{campaign.compensator} on {campaign.scenario} regressed against {path.name}:\n"
                + result.format(),
                pytrace=False,
            )
        if result.power_line.startswith("WARNING") and not plan.warning:  # one warning per gate
            warnings.warn(bench.UnderpoweredWarning(f"{path.name}: {result.power_line}"), stacklevel=2)
        return result


def _seed_tuple(seeds: Iterable[int] | str) -> tuple[int, ...]:
    """``seeds`` (a list or ``"0:20"``-style text) as a checked tuple."""
    from gyrobench.scenarios.bench.seeds import check_seeds, parse_seeds

    return parse_seeds(seeds) if isinstance(seeds, str) else check_seeds(seeds)


@pytest.fixture(scope="session")
def _gyrobench_db(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("gyrobench") / "bench.sqlite"


@pytest.fixture
def gyrobench_bench(request: pytest.FixtureRequest, _gyrobench_db: Path) -> GyrobenchBench:
    """Score compensators over seeds and assert no regression against a stored baseline.

    See :class:`GyrobenchBench` (``campaign``, ``assert_no_regression``).
    """
    from gyrobench.scenarios.bench import prepend_import_path

    cfg = request.config
    # "mylab.models:mine" is found from the project first: rootdir, then the invocation folder
    prepend_import_path(cfg.invocation_params.dir)
    prepend_import_path(cfg.rootpath)
    workers = cfg.getoption("--gyrobench-workers")
    if workers < 0:
        raise pytest.UsageError(f"--gyrobench-workers must be >= 0; got {workers}")
    return GyrobenchBench(
        root=Path(request.path).parent,
        db=_gyrobench_db,
        save=bool(cfg.getoption("--gyrobench-save-baselines")),
        workers=workers,
    )
