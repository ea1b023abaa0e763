"""Exit codes that mean what they say (issue 31 item 4): a comparison that cannot be made once
the campaign has run exits 3 with its line, never 0; "FAILED" never comes with exit 0."""

from __future__ import annotations

import json
import math

import pytest

from gyrobench.scenarios import bench
from gyrobench.scenarios.cli import exits
from gyrobench.scenarios.cli.main import main
from gyrobench.scenarios.pytest_plugin import GyrobenchBench
from tests.scenarios import toy_scenario as toy

# every test runs among planted user files and fails if one changes (tests/conftest.py)
pytestmark = pytest.mark.usefixtures("user_files")

TOY = "tests.scenarios.toy_scenario"


@pytest.fixture(scope="module")
def good_baseline(tmp_path_factory):
    d = tmp_path_factory.mktemp("base")
    camp = bench.run_campaign(toy, toy.good, range(12), workers=0, db=d / "b.db", progress=False)
    return bench.save_baseline(d / "good.json", camp)


def _renamed_baseline(good_baseline, tmp_path):
    """The good baseline with every score renamed: same scenario and seeds, no score in common."""
    doc = json.loads(good_baseline.read_text())
    doc["scores"] = {s: {f"{k}_renamed": v for k, v in sc.items()} for s, sc in doc["scores"].items()}
    path = tmp_path / "renamed.json"
    path.write_text(json.dumps(doc))
    return path


def _bench(argv, capsys):
    code = main(["bench", TOY, "--workers", "0", "--quiet", *argv])
    cap = capsys.readouterr()
    return code, cap.out, cap.err.splitlines()


def test_a_comparison_without_a_common_score_exits_3_in_one_line(tmp_path, capsys, good_baseline):
    base = _renamed_baseline(good_baseline, tmp_path)
    argv = ["--compensator", f"{TOY}:good", "--baseline", str(base), "--db", str(tmp_path / "c.db")]
    code, out, err = _bench(argv, capsys)
    assert code == exits.FAILED_SEEDS, err
    assert len(err) == 1 and err[0].startswith("gyrobench: error: baseline and campaign have no score in common")


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_failed_seeds_found_by_the_comparison_alone_exit_3(tmp_path, capsys, good_baseline, monkeypatch):
    """A comparison whose candidate has a non-finite score the campaign did not record as failed
    (a campaign read back from an older file): the table says FAILED, so the exit is 3."""
    real_compare = bench.compare

    def compare_with_a_nan_seed(baseline, campaign, **kw):
        scores = {s: dict(v) for s, v in campaign.scores.items()}
        scores[4] = {k: math.nan for k in scores[4]}
        old = bench.Campaign(
            campaign_id="x", scenario=campaign.scenario, compensator="old", config=campaign.config, scores=scores
        )
        return real_compare(baseline, old, **kw)

    monkeypatch.setattr(bench, "compare", compare_with_a_nan_seed)
    argv = ["--compensator", f"{TOY}:good", "--baseline", str(good_baseline), "--db", str(tmp_path / "c.db")]
    code, out, err = _bench(argv, capsys)
    assert "FAILED" in out
    assert code == exits.FAILED_SEEDS, err
    assert len(err) == 1 and "failed on 1 of 12 compared seeds (seeds 4;" in err[0]
    assert err[0].endswith("fails")


@pytest.mark.parametrize("comp", ["good", "degraded"])
@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_failed_never_comes_with_exit_0(tmp_path, capsys, good_baseline, comp):
    argv = ["--compensator", f"{TOY}:{comp}", "--baseline", str(good_baseline), "--db", str(tmp_path / "c.db")]
    code, out, err = _bench(argv, capsys)
    assert code == (exits.OK if comp == "good" else exits.REGRESSION), err
    assert "FAILED" not in out and not err


def test_plugin_fails_in_one_line_when_the_comparison_cannot_be_made(tmp_path, good_baseline):
    base = _renamed_baseline(good_baseline, tmp_path)
    fixture = GyrobenchBench(root=tmp_path, db=tmp_path / "p.db", save=False, workers=0)
    with pytest.raises(pytest.fail.Exception, match="against renamed.json: baseline and campaign have no score"):
        fixture.assert_no_regression(toy, toy.good, baseline=base)
