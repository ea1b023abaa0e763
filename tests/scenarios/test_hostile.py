"""Hostile input: every case of issue 15 gives one line and a documented exit status.

Exit statuses (gyrobench.scenarios.exits): 0 ok, 1 regression, 2 bad input, 3 failed seeds,
4 internal failure. "One line" means stderr holds exactly one line, starting
``gyrobench: error:``, and no traceback (unless GYROBENCH_TRACEBACK=1).
"""

from __future__ import annotations

import math
import sqlite3
from pathlib import Path

import numpy as np
import pytest
from sklearn.linear_model import LinearRegression

from gyrobench.scenarios import bench, exits
from gyrobench.scenarios.cli import main
from gyrobench.scenarios.pytest_plugin import GyrobenchBench
from tests.scenarios import toy_scenario as toy

TOY = "tests.scenarios.toy_scenario"
HERE = __name__
FAST = toy.Config(n_samples=60)


# ----------------------------------------------------------------------------- compensators
# module level, so worker processes and the command line import them as "module:attr"
def nan_pred(X, y):
    """Fits nothing; predicts NaN everywhere."""
    return lambda Z: np.full(len(Z), math.nan)


def inf_pred(X, y):
    """Predicts +inf everywhere."""
    return lambda Z: np.full(len(Z), math.inf)


def nan_on_odd_seeds(X, y, random_state=None):
    """A least-squares fit that predicts NaN at one sample for odd seeds (random_state is
    derived from the seed; its parity is not the seed's, so decide from the data)."""
    model = LinearRegression().fit(X, y)
    odd = int(round(abs(float(X[0, 0])) * 1e6)) % 2 == 1

    def predict(Z):
        p = model.predict(Z)
        if odd:
            p[len(p) // 2] = math.nan
        return p

    return predict


def huge_pred(X, y):
    """Finite predictions so large that the squared error overflows to inf (a score is inf)."""
    return lambda Z: np.full(len(Z), 1e200)


def _run(argv, capsys):
    code = main(argv)
    cap = capsys.readouterr()
    return code, cap.out, cap.err.splitlines()


def _one_line(err, code, expected_code):
    assert code == expected_code, err
    assert len(err) == 1, err
    assert err[0].startswith("gyrobench: error: "), err
    assert "Traceback" not in err[0]


# ----------------------------------------------------------------------------- 1. failed seeds
@pytest.mark.parametrize("comp", [nan_pred, inf_pred, huge_pred], ids=["nan", "inf", "overflow"])
def test_nonfinite_prediction_or_score_makes_the_seed_failed_and_recorded(tmp_path, comp):
    db = tmp_path / "c.db"
    camp = bench.run_campaign(toy, comp, range(3), config=FAST, workers=0, db=db, progress=False)
    assert sorted(camp.failed) == [0, 1, 2]
    assert camp.ok_seeds == ()
    reason = camp.failed[0]
    if comp is huge_pred:
        assert reason.startswith("score run1/mse is inf")
    else:
        assert reason.startswith("the prediction on run run1 has 60 non-finite values of 60 (")
    with sqlite3.connect(db) as conn:
        rows = conn.execute("SELECT seed, reason FROM seed_failures ORDER BY seed").fetchall()
    assert rows == [(s, camp.failed[s]) for s in range(3)]
    again = bench.run_campaign(toy, comp, range(3), config=FAST, workers=0, db=db, progress=False)
    assert (again.reused, again.failed) == (3, camp.failed)  # read back as failed
    summary = bench.format_summary(camp)
    assert "3 FAILED" in summary and "seeds 0:3" in summary


def test_failed_seeds_are_left_out_of_the_summary(tmp_path):
    camp = bench.run_campaign(
        toy, nan_on_odd_seeds, range(8), config=FAST, workers=0, db=tmp_path / "c.db", progress=False
    )
    assert camp.failed and camp.ok_seeds  # both kinds among 8 seeds
    n_ok = len(camp.ok_seeds)
    assert {s.n for s in camp.summary().values()} == {n_ok}


def test_score_seed_raises_for_a_nonfinite_prediction():
    with pytest.raises(bench.CompensatorError, match=r"failed on seed 3: the prediction on run run1 "
                       r"has 60 non-finite values of 60 \(nan at sample 0\)"):
        bench.score_seed(toy, nan_pred, 3, FAST)


@pytest.fixture(scope="module")
def good_baseline(tmp_path_factory):
    d = tmp_path_factory.mktemp("base")
    camp = bench.run_campaign(toy, toy.good, range(12), workers=0, db=d / "b.db", progress=False)
    return bench.save_baseline(d / "good.json", camp)


@pytest.mark.parametrize("comp", ["nan_pred", "inf_pred"])
def test_cli_baseline_with_failed_seeds_exits_3_naming_the_seeds(tmp_path, capsys, good_baseline, comp):
    argv = ["bench", TOY, "--compensator", f"{HERE}:{comp}", "--baseline", str(good_baseline),
            "--workers", "0", "--quiet", "--db", str(tmp_path / "c.db")]
    code, out, err = _run(argv, capsys)
    _one_line(err, code, exits.FAILED_SEEDS)
    assert code not in (exits.OK, exits.REGRESSION, exits.BAD_INPUT)
    assert f"compensator {HERE}:{comp} failed on 12 of 12 seeds of toy (seeds 0:12)" in err[0]
    assert "the comparison with --baseline" in err[0] and err[0].endswith("fails")
    assert "FAILED: compensator" in out  # the comparison table says so too


def test_cli_some_failed_seeds_fail_the_gate_and_name_them(tmp_path, capsys, good_baseline):
    argv = ["bench", TOY, "--compensator", f"{HERE}:nan_on_odd_seeds", "--baseline",
            str(good_baseline), "--workers", "0", "--quiet", "--db", str(tmp_path / "c.db")]
    code, out, err = _run(argv, capsys)
    _one_line(err, code, exits.FAILED_SEEDS)
    camp = bench.run_campaign(toy, nan_on_odd_seeds, range(12), workers=0, db=tmp_path / "c.db",
                              progress=False)
    assert f"(seeds {','.join(map(str, sorted(camp.failed)))})" in err[0]


def test_cli_save_baseline_of_failed_seeds_is_refused(tmp_path, capsys):
    base = tmp_path / "b.json"
    argv = ["bench", TOY, "--compensator", f"{HERE}:inf_pred", "--seeds", "0:2", "--save-baseline",
            str(base), "--workers", "0", "--quiet", "--db", str(tmp_path / "c.db")]
    code, _, err = _run(argv, capsys)
    _one_line(err, code, exits.FAILED_SEEDS)
    assert "--save-baseline" in err[0] and "not written" in err[0]
    assert not base.exists()


def test_failed_seeds_in_a_worker_process(tmp_path):
    camp = bench.run_campaign(toy, f"{HERE}:nan_pred", [0, 1], config=FAST, workers=2,
                              db=tmp_path / "c.db", progress=False)
    assert sorted(camp.failed) == [0, 1]


def test_compare_with_a_baseline_read_from_json_with_nan_never_passes(tmp_path, good_baseline):
    """A campaign saved by an older gyrobench with NaN scores: the NaN seeds are failures."""
    good = bench.load_baseline(good_baseline)
    scores = {s: dict(v) for s, v in good.scores.items()}
    scores[4] = {k: math.nan for k in scores[4]}
    cand = bench.Campaign(campaign_id="x", scenario="toy", compensator="old", config=good.config,
                          scores=scores)
    res = bench.compare(good, cand)
    assert res.failed_seeds == (4,) and not res.passed
    assert "seed 4: score mean/bias_stability is nan" in res.failure


def test_compare_refuses_a_baseline_without_finite_scores(good_baseline):
    good = bench.load_baseline(good_baseline)
    nan = {s: {k: math.nan for k in v} for s, v in good.scores.items()}
    broken = bench.Campaign(campaign_id="x", scenario="toy", compensator="b", config="", scores=nan)
    with pytest.raises(ValueError, match="baseline has no finite scores on the seeds"):
        bench.compare(broken, good)


def test_plugin_assert_no_regression_fails_on_failed_seeds(tmp_path, good_baseline):
    fixture = GyrobenchBench(root=tmp_path, db=tmp_path / "p.db", save=False, workers=0)
    with pytest.raises(pytest.fail.Exception, match=r"failed on 12 of 12 compared seeds "
                       r"\(seeds 0:12; seed 0: the prediction on run run1 has 300 non-finite"):
        fixture.assert_no_regression(toy, nan_pred, baseline=good_baseline)
    saving = GyrobenchBench(root=tmp_path, db=tmp_path / "p.db", save=True, workers=0)
    with pytest.raises(pytest.fail.Exception, match="not written: compensator .* failed on 2 of 2"):
        saving.assert_no_regression(toy, inf_pred, baseline=tmp_path / "new.json", seeds=[0, 1])
    assert not (tmp_path / "new.json").exists()
