"""Pairing by seed, not by a run's name (issue 31 item 3).

A scenario whose held-out runs are named after the unit or the seed (rlg_thermal:
``unit7_heldout/...``) gives score names that no two seeds share. Those names cannot be
paired; the comparison must pair the scores every seed holds (``mean/...``) and list the
others apart, never call the seeds "failed".
"""

from __future__ import annotations

import argparse
import re
import textwrap

import pytest

from gyrobench.scenarios import bench
from gyrobench.scenarios.cli import bench as bench_cli

TOY = "tests.scenarios.toy_scenario"

#: the toy scenario, with each held-out run named after the seed's unit, as rlg_thermal does
_UNIT_LABELS = textwrap.dedent(
    """
    import dataclasses

    from tests.scenarios import toy_scenario as toy

    NAME = "toy_unit_labels"
    Config = toy.Config
    good, degraded = toy.good, toy.degraded


    def compensation_task(config, seed):
        task = toy.compensation_task(config, seed)
        runs = tuple(dataclasses.replace(r, label=f"unit{seed}_{r.label}") for r in task.heldout)
        return dataclasses.replace(task, heldout=runs)
    """
)


@pytest.fixture
def unit_labels(tmp_path, monkeypatch) -> str:
    pkg = tmp_path / "mylab_pairing"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "unit_labels.py").write_text(_UNIT_LABELS)
    monkeypatch.syspath_prepend(str(tmp_path))
    return "mylab_pairing.unit_labels"


def _cli(argv: list[str]) -> int:
    p = argparse.ArgumentParser()
    bench_cli.add_parser(p.add_subparsers(dest="verb"))
    args = p.parse_args(["bench", *argv])
    return args.func(args)


def test_names_that_change_with_the_seed_are_left_out_and_the_means_are_paired(unit_labels, tmp_path):
    good = bench.run_campaign(unit_labels, f"{unit_labels}:good", range(12), workers=0, db=tmp_path / "a.db",
                              progress=False)
    again = bench.run_campaign(unit_labels, f"{unit_labels}:good", range(12), workers=0, db=tmp_path / "b.db",
                               progress=False)
    result = bench.compare(good, again)
    assert result.passed and not result.failed_seeds and "FAILED" not in result.format()
    assert result.seeds == tuple(range(12))
    assert {s.name for s in result.scores} == {n for n in good.score_names if n.startswith("mean/")}
    assert set(result.unpaired) == {n for n in good.score_names if not n.startswith("mean/")}
    assert all(s.status == "unchanged" and s.n == 12 for s in result.scores)
    assert "not held by every seed" in result.format()


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_cli_with_unit_named_runs_exits_0_unchanged_and_1_on_a_regression(unit_labels, tmp_path, capsys):
    base = str(tmp_path / "good.json")
    common = ["--seeds", "0:12", "--workers", "0", "--quiet"]
    db = ["--db", str(tmp_path / "c.db")]
    assert _cli([unit_labels, "--compensator", f"{unit_labels}:good", *common, *db, "--save-baseline", base]) == 0
    capsys.readouterr()
    db2 = ["--db", str(tmp_path / "d.db")]  # recomputed, not read back
    assert _cli([unit_labels, "--compensator", f"{unit_labels}:good", *common, *db2, "--baseline", base]) == 0
    out = capsys.readouterr().out
    assert "over 12 matching seeds" in out and "no significant regression" in out and "FAILED" not in out
    assert _cli([unit_labels, "--compensator", f"{unit_labels}:degraded", *common, *db2, "--baseline", base]) == 1
    out = capsys.readouterr().out
    assert "REGRESSION" in out and "FAILED" not in out


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_rlg_thermal_unchanged_compensator_passes_against_its_own_baseline(tmp_path, capsys):
    """rlg_thermal names its held-out run after the unit: 3 seeds, the same compensator, exit 0.

    3 seeds cannot reach alpha (2/2^3 = 0.25 on the one primary score), so the run needs
    --allow-underpowered and says so on its first line."""
    base = str(tmp_path / "b.json")
    common = ["--compensator", "sklearn.linear_model:LinearRegression", "--seeds", "0:3", "--workers", "0", "-q"]
    common += ["--allow-underpowered", "--no-references"]
    assert _cli(["rlg_thermal", *common, "--db", str(tmp_path / "a.db"), "--save-baseline", base]) == 0
    capsys.readouterr()
    assert _cli(["rlg_thermal", *common, "--db", str(tmp_path / "b.db"), "--baseline", base]) == 0
    out = capsys.readouterr().out
    assert out.splitlines()[0].startswith("WARNING: underpowered:") and "at least 6 seeds" in out.splitlines()[0]
    assert "over 3 matching seeds" in out and "FAILED" not in out
    assert re.search(r"mean/bias_stability_deg_h\s+primary\s+deg/h\s+unchanged", out)


@pytest.mark.slow
def test_rlg_thermal_regression_exits_1(tmp_path, capsys, shared_tasks):
    """No thermal compensation (DummyRegressor) against LinearRegression on 8 seeds: the held-out
    improvement falls from ~24 % to 0 on every seed, i.e. the primary score (held-out bias
    stability) rises on every seed. With the one primary score the smallest attainable p is
    2 / 2**8 = 0.0078 < 0.05, so 8 seeds can show it."""
    shared_tasks("rlg_thermal", range(8))  # two runs and the references over these seeds (conftest)
    base = str(tmp_path / "b.json")
    common = ["--seeds", "0:8", "--workers", "0", "-q"]
    good = ["--compensator", "sklearn.linear_model:LinearRegression"]
    assert _cli(["rlg_thermal", *good, *common, "--db", str(tmp_path / "a.db"), "--save-baseline", base]) == 0
    capsys.readouterr()
    worse = ["--compensator", "sklearn.dummy:DummyRegressor"]
    assert _cli(["rlg_thermal", *worse, *common, "--db", str(tmp_path / "b.db"), "--baseline", base]) == 1
    out = capsys.readouterr().out
    assert "REGRESSION: 1 of 1 primary score(s) significantly worse: mean/bias_stability_deg_h" in out
    assert "mean/improvement_pct" in out and "FAILED" not in out
