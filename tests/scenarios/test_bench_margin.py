"""The gate's equivalence margin (``--min-change``) is in the test itself.

A change within the margin is "no regression" even when every seed shows it (the plain test
calls it significant); a change well beyond it is a regression at the README's 12 seeds; the
detectable change is printed, and an underpowered comparison says so on its first line.
The end-to-end check on the README's scenario (ifog_thermal, the README's Ridge pipeline with
its prediction shrunk toward zero by a known fraction) is in the slow tier.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from gyrobench.scenarios import bench
from gyrobench.scenarios.cli import exits
from tests.scenarios import toy_scenario as toy

ROOT = Path(__file__).resolve().parents[2]
README_SEEDS = 12


@pytest.fixture(scope="module")
def base(tmp_path_factory):
    d = tmp_path_factory.mktemp("margin")
    return bench.run_campaign(toy, toy.good, range(README_SEEDS), workers=2, db=d / "b.db", progress=False)


def _scaled(camp, factor, jitter=0.0, seed=1):
    """``camp`` with every score multiplied by ``factor`` (times 1 + jitter * N(0, 1) per seed)."""
    rng = np.random.default_rng(seed)
    scores = {}
    for s, sc in camp.scores.items():
        f = factor * (1 + jitter * rng.standard_normal())
        scores[s] = {k: v * f for k, v in sc.items()}
    return bench.Campaign(campaign_id="c", scenario=camp.scenario, compensator="c", config=camp.config, scores=scores)


def test_a_change_within_the_margin_is_no_regression_even_when_significant(base):
    worse = _scaled(base, 1.002, jitter=0.0005)  # 0.2 % worse on every seed
    plain = bench.compare(base, worse, min_change=0.0)
    assert plain.regressions  # the plain test: significant on 12 of 12 seeds
    assert not bench.compare(base, worse, min_change=0.01).regressions  # within the 1 % margin


def test_a_change_beyond_the_margin_is_a_regression(base):
    worse = _scaled(base, 1.10, jitter=0.02)
    res = bench.compare(base, worse, min_change=0.01)
    assert {s.name for s in res.regressions} == {s.name for s in res.primary}
    better = _scaled(base, 0.90, jitter=0.02)
    res = bench.compare(base, better, min_change=0.01)
    assert not res.regressions and len(res.improvements) == len(res.primary)


def test_a_change_of_exactly_the_margin_is_a_coin_toss_not_a_certainty(base):
    """At a change equal to the margin the edge test is centred on zero: it calls a regression
    at most alpha of the time (a worse-side rejection of a two-sided test at 0.05: at most 2.5 %),
    never every time. Of 20 jittered draws at most 4 may be called (binomial chance of 5 or more
    at a true rate of 5 %: 0.3 %)."""
    calls = sum(bool(bench.compare(base, _scaled(base, 1.05, jitter=0.02, seed=k), min_change=0.05).regressions)
                for k in range(20))
    assert calls <= 4


def test_the_detectable_change_is_given_and_a_weak_comparison_warns_first(base):
    tight = bench.compare(base, _scaled(base, 1.0, jitter=0.002), min_change=0.05)
    assert tight.power_line.startswith("detectable change at 12 seeds")
    noisy = bench.compare(base, _scaled(base, 1.0, jitter=0.3), min_change=0.05)
    assert noisy.power_line.startswith("WARNING: underpowered: detectable change at 12 seeds")
    assert "seeds detect a change of 10 %" in noisy.power_line
    assert all(d.change > 0.10 for d in noisy.detectable)


def test_min_change_zero_is_the_plain_test(base):
    worse = _scaled(base, 1.0001, jitter=0.00001)
    a = bench.compare(base, worse, min_change=0.0)
    assert a.regressions and a.test == "two-sided Wilcoxon signed-rank on paired per-seed scores"


# ----------------------------------------------------------------------------- the README's case
def _project(folder: Path) -> None:
    (folder / "mylab").mkdir()
    (folder / "mylab" / "__init__.py").write_text("")
    (folder / "mylab" / "models.py").write_text(textwrap.dedent("""
        from sklearn.linear_model import Ridge
        from sklearn.pipeline import make_pipeline
        from sklearn.preprocessing import PolynomialFeatures, StandardScaler

        mine = make_pipeline(StandardScaler(), PolynomialFeatures(2), Ridge(alpha=1e-3))


        class Shrunk:
            '''The README's pipeline, its prediction shrunk toward 0 by ``lam`` (a known regression).'''

            def __init__(self, lam=0.0):
                self.lam = lam

            def fit(self, X, y):
                from sklearn.base import clone

                self.model = clone(mine).fit(X, y)
                return self

            def predict(self, X):
                return (1 - self.lam) * self.model.predict(X)


        tiny = Shrunk(0.006)    # about +0.2 % on mean/rms (measured below)
        tenth = Shrunk(0.083)   # about +10 %
    """))


def _cli(folder: Path, *argv: str):
    env = {**os.environ, "PYTHONPATH": f"{ROOT}{os.pathsep}{os.environ.get('PYTHONPATH', '')}"}
    cmd = [sys.executable, "-c", "import sys; from gyrobench.scenarios.cli.main import main; sys.exit(main())",
           "bench", "ifog_thermal", "--db", str(folder / "b.db"), "--no-references", "-q", *argv]
    r = subprocess.run(cmd, cwd=folder, env=env, capture_output=True, text=True, timeout=1800)
    return r.returncode, r.stdout, r.stderr


@pytest.mark.slow  # three 12-seed campaigns of ifog_thermal (about a minute on 2 cores)
def test_readme_case_a_0_2_percent_change_exits_0_and_10_percent_exits_1(tmp_path):
    _project(tmp_path)
    code, out, err = _cli(tmp_path, "--compensator", "mylab.models:mine", "--seeds", f"0:{README_SEEDS}",
                          "--save-baseline", str(tmp_path / "good.json"))
    assert code == exits.OK, err
    assert "detectable change at 12 seeds" in out
    base = {int(s): v["mean/rms"] for s, v in json.loads((tmp_path / "good.json").read_text())["scores"].items()}
    for comp, low, high, want in (("tiny", 0.001, 0.004, exits.OK), ("tenth", 0.07, 0.13, exits.REGRESSION)):
        argv = ["--compensator", f"mylab.models:{comp}", "--baseline", str(tmp_path / "good.json"),
                "--min-change", "0.01", "--save-baseline", str(tmp_path / f"{comp}.json")]
        code, out, err = _cli(tmp_path, *argv[:-2])
        assert code == want, (comp, out, err)
        assert out.splitlines()[0].startswith(("detectable change at 12 seeds", "WARNING: underpowered"))
        # the change really is what it is named: measured on the same seeds
        code2, _, err2 = _cli(tmp_path, *argv[:2], "--seeds", f"0:{README_SEEDS}", "--save-baseline",
                              str(tmp_path / f"{comp}.json"))
        assert code2 == exits.OK, err2
        cand = json.loads((tmp_path / f"{comp}.json").read_text())["scores"]
        change = float(np.mean([cand[str(s)]["mean/rms"] / base[s] - 1 for s in base]))
        assert low < change < high, (comp, change)
