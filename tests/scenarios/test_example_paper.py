"""A paper is one folder: the example paper in ``example_paper/p999_example`` becomes a paper of
gyrobench when its folder is on the papers package path, and by nothing else.

The test adds the folder's parent to ``gyrobench.scenarios.papers.__path__`` (where a new paper's
folder would sit in the source tree) and changes nothing else: no registry line, no table, no
packaging entry. The paper is then listed by ``gyrobench list`` with its source, reproduced by
``gyrobench reproduce``, checked by the paper contract test's checks and, by its ``bench.py``, a
``gyrobench bench`` scenario with its declared scores; without the folder it is none of these (so
the test can fail).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

from gyrobench.scenarios import papers, registry
from gyrobench.scenarios.claims import evaluate
from tests.scenarios import test_paper_contract as contract
from tests.scenarios.test_cli import run

#: the folder that holds the example paper's folder (not a package itself)
EXAMPLE_ROOT = Path(__file__).parent / "example_paper"
NAME = "example_bias"


@pytest.fixture
def example_on_path(monkeypatch):
    """The example paper's folder added to the papers package path; nothing else changes."""
    monkeypatch.setattr(papers, "__path__", [*papers.__path__, str(EXAMPLE_ROOT)])
    yield
    sys.modules.pop(f"{papers.__name__}.p999_example", None)
    for key in [k for k in sys.modules if k.startswith(f"{papers.__name__}.p999_example.")]:
        sys.modules.pop(key)


def test_without_its_folder_the_example_is_not_a_paper(capsys):
    assert NAME not in registry.available()
    code, out, _ = run(["list"], capsys)
    assert code == 0 and NAME not in out


def test_the_folder_alone_makes_it_listed_with_its_source(example_on_path, capsys):
    assert NAME in registry.available()
    assert registry.table()[NAME] == f"{papers.__name__}.p999_example"
    assert papers.sources()["999"].authors == "A. Example, B. Example"
    code, out, _ = run(["list"], capsys)
    assert code == 0
    assert f"{NAME:<20} Example paper" in out
    assert "paper 999: A. Example, B. Example (the gyrobench test suite)" in out


def test_the_folder_alone_makes_it_reproducible(example_on_path, tmp_path, capsys):
    code, _, err = run(["reproduce", NAME, "--out", tmp_path / "r", "--units", "4", "--workers", "0", "-q"], capsys)
    assert code == 0, err
    doc = json.loads((tmp_path / "r" / NAME / "results.json").read_text())
    assert doc["units"] == 4 and [c["id"] for c in doc["claims"]] == ["999.bias"]
    assert "A. Example" in (tmp_path / "r" / NAME / "report.md").read_text()


def test_the_contract_test_checks_it(example_on_path):
    """Every check of tests/scenarios/test_paper_contract.py, on the example paper's unit."""
    module = registry.get(NAME)
    config = module.Config()
    paper = (module, config, module.experiment(config, 0))
    checks = [getattr(contract, n) for n in dir(contract) if n.startswith("test_") and n != (
        "test_every_paper_of_the_registry_is_a_discovered_paper_package")]
    assert len(checks) >= 8
    for check in checks:
        check(paper)
    # and the unit's claim is judged from its quantities by the shared evaluator
    (res,) = evaluate(module.claims_for(config), [paper[2].quantities])
    assert res.testable == 1


def test_without_its_folder_the_example_is_no_bench_scenario():
    from gyrobench.scenarios.bench.scoring import bench_scenarios

    assert NAME not in bench_scenarios()


def test_the_folder_alone_makes_it_a_bench_scenario_with_its_scores(example_on_path):
    """Its bench.py is all it takes: listed for ``gyrobench bench``, its declared primary score gated,
    and the paper's method scored on a seed. With the bias removed, the held-out record's mean
    squared error is the white noise's: n mse / (sigma^2 (1 + 1/n)) follows chi-square with n degrees
    of freedom (sigma = 60 N sqrt(fs) deg/h; the 1/n is the training mean's variance, whose one
    shared draw the bound neglects), checked two-sided at a false-alarm rate of 1e-6."""
    from scipy.stats import chi2

    from gyrobench.scenarios.bench import score_seed
    from gyrobench.scenarios.bench.primary import gated_scores, scenario_scores
    from gyrobench.scenarios.bench.scoring import bench_scenarios

    module = registry.get(NAME)
    assert NAME in bench_scenarios()
    assert scenario_scores(NAME) is module.BENCH_SCORES
    assert [g.name for g in gated_scores(NAME, ["mean/rms", "mean/mse"])] == ["mean/rms"]
    config = module.Config(bias_deg_h=100.0)
    scores = score_seed(NAME, module.BENCH_SCORES.paper, 3, config)
    assert set(scores) == {"mean/mse", "mean/rms", "static/mse", "static/rms"}
    n = config.n_samples
    sigma2 = (60.0 * config.arw_deg_sqrt_h) ** 2 * config.fs_hz
    stat = n * scores["static/mse"] / (sigma2 * (1 + 1 / n))
    assert chi2.ppf(5e-7, n) <= stat <= chi2.ppf(1 - 5e-7, n), stat
