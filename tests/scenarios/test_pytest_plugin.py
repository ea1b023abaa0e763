"""The gyrobench pytest plugin, exercised in inner pytest runs (pytester) on the toy scenario."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import scipy.stats  # noqa: F401
import threadpoolctl  # noqa: F401
import tqdm  # noqa: F401

# Inner runs are in-process: pytester drops modules first imported inside them, and numpy's
# extension modules cannot load twice in a process, so import what the inner tests use here.
import gyrobench.scenarios.bench  # noqa: F401
from tests.scenarios import toy_scenario  # noqa: F401

pytest_plugins = ["pytester"]

ROOT = Path(__file__).resolve().parents[2]

USER_TESTS = """
from tests.scenarios import toy_scenario as toy

CFG = toy.Config(n_samples=120)

def test_good(gyrobench_bench):
    gyrobench_bench.assert_no_regression(
        toy, toy.good, baseline="baselines/toy.json", seeds=range(12), config=CFG
    )

def test_same_by_name(gyrobench_bench):
    res = gyrobench_bench.assert_no_regression(
        "tests.scenarios.toy_scenario",
        "tests.scenarios.toy_scenario:good",
        baseline="baselines/toy.json",
        config=CFG,
    )
    assert res is None or (len(res.seeds) == 12 and res.regressions == ())

def test_degraded(gyrobench_bench):
    gyrobench_bench.assert_no_regression(
        toy, toy.degraded, baseline="baselines/toy.json", seeds=range(12), config=CFG
    )
"""


#: inner runs skip plugins they do not need (hypothesis's summary hook alone costs ~2 s per run)
FAST = ("-p", "no:hypothesispytest", "-p", "no:cacheprovider")


@pytest.fixture
def user_suite(pytester: pytest.Pytester) -> pytest.Pytester:
    pytester.syspathinsert(ROOT)
    pytester.makepyfile(test_user=USER_TESTS)
    return pytester


def test_plugin_is_registered_by_the_entry_point(pytester: pytest.Pytester):
    result = pytester.runpytest("--help")
    result.stdout.fnmatch_lines(["*--gyrobench-save-baselines*", "*--gyrobench-workers*"])


def test_missing_baseline_fails_with_instructions(user_suite: pytest.Pytester):
    result = user_suite.runpytest(*FAST, "-k", "test_good")
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines(["*baselines/toy.json* does not exist*--gyrobench-save-baselines*"])


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_save_then_assert_no_regression(user_suite: pytest.Pytester):
    saved = user_suite.runpytest(*FAST, "-k", "test_good", "--gyrobench-save-baselines")
    saved.assert_outcomes(passed=1)
    base = user_suite.path / "baselines" / "toy.json"
    assert json.loads(base.read_text())["seeds"] == list(range(12))

    result = user_suite.runpytest(*FAST)
    result.assert_outcomes(passed=2, failed=1)
    result.stdout.fnmatch_lines(
        ["*test_degraded*", "*regressed against toy.json*", "*REGRESSION*mean/mse*"]
    )
    assert "test_good FAILED" not in result.stdout.str()


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_workers_option_runs_in_processes(user_suite: pytest.Pytester):
    user_suite.runpytest(*FAST, "-k", "test_good", "--gyrobench-save-baselines").assert_outcomes(
        passed=1
    )
    user_suite.runpytest(
        *FAST, "-k", "test_good or test_same_by_name", "--gyrobench-workers", "2"
    ).assert_outcomes(passed=2)


def test_baseline_of_another_scenario_fails_before_computing(
    user_suite: pytest.Pytester, monkeypatch: pytest.MonkeyPatch
):
    (user_suite.path / "baselines").mkdir()
    gyrobench.scenarios.bench.save_baseline(
        user_suite.path / "baselines" / "toy.json",
        gyrobench.scenarios.bench.Campaign(
            campaign_id="x",
            scenario="ifog_thermal",
            compensator="c",
            config="",
            scores={s: {"mean/mse": 1.0} for s in range(12)},
        ),
    )
    log = user_suite.path / "calls.log"
    monkeypatch.setenv("GYROBENCH_TOY_CALL_LOG", str(log))
    result = user_suite.runpytest(*FAST, "-k", "test_good")
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines(["*baselines/toy.json* is of scenario 'ifog_thermal', not 'toy'*"])
    assert not log.exists()  # no seed was simulated


UNDERPOWERED_TESTS = """
from tests.scenarios import toy_scenario as toy

CFG = toy.Config(n_samples=120)

def test_save(gyrobench_bench):
    gyrobench_bench.assert_no_regression(
        toy, toy.good, baseline="baselines/toy.json", seeds=range(64), config=CFG
    )

def test_few_seeds(gyrobench_bench):
    gyrobench_bench.assert_no_regression(
        toy, toy.degraded, baseline="baselines/toy.json", seeds=range(5), config=CFG
    )

def test_few_seeds_allowed(gyrobench_bench):
    gyrobench_bench.assert_no_regression(
        toy, toy.degraded, baseline="baselines/toy.json", seeds=range(5), config=CFG,
        allow_underpowered=True,
    )

def test_auto(gyrobench_bench):
    gyrobench_bench.assert_no_regression(
        toy, toy.degraded, baseline="baselines/toy.json", seeds="auto", config=CFG
    )

def test_auto_wide_margin(gyrobench_bench):
    gyrobench_bench.assert_no_regression(
        toy, toy.degraded, baseline="baselines/toy.json", seeds="auto", config=CFG, min_change=0.4
    )
"""


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_underpowered_fails_before_computing_or_warns_in_the_report(
    pytester: pytest.Pytester, monkeypatch: pytest.MonkeyPatch
):
    """5 seeds on the toy's 3 gated scores reach 3 x 2/2^5 = 0.19: the test fails naming 7
    seeds, nothing simulated; allowed, it passes (it cannot fail) with one warning in the
    report's warnings summary. seeds="auto" sizes the run from the 64-seed baseline: at the default
    5 % margin it fails naming the seeds to re-save it on, nothing simulated; at a 40 % margin the
    baseline's seeds suffice (sized from the spread's 95 % upper bound: 18 seeds at 25 %) and it
    catches the degraded compensator."""
    pytester.syspathinsert(ROOT)
    pytester.makepyfile(test_user=UNDERPOWERED_TESTS)
    pytester.runpytest(*FAST, "-k", "test_save", "--gyrobench-save-baselines").assert_outcomes(passed=1)
    log = pytester.path / "calls.log"
    monkeypatch.setenv("GYROBENCH_TOY_CALL_LOG", str(log))
    result = pytester.runpytest(*FAST, "-k", "test_few_seeds and not allowed")
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines(["*toy.json: seeds: *3 x 2/2^5 = 0.188 >= alpha 0.05*at least 7 seeds*"])
    assert not log.exists()
    result = pytester.runpytest(*FAST, "-k", "test_few_seeds_allowed", "-rA")
    result.assert_outcomes(passed=1, warnings=1)
    result.stdout.fnmatch_lines(["*warnings summary*", "*UnderpoweredWarning: toy.json: WARNING: underpowered:*"])
    log.unlink(missing_ok=True)
    result = pytester.runpytest(*FAST, "-k", "test_auto and not wide")  # the default 5 % margin
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines(["*toy.json: --seeds auto: * the baseline holds only 64 seeds: re-save it on*"])
    assert not log.exists()  # refused before simulating
    result = pytester.runpytest(*FAST, "-k", "test_auto_wide_margin")
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines(["*regressed against toy.json*", "*uncompensated*", "*REGRESSION*primary*"])
