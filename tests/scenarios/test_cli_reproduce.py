"""``gyrobench reproduce`` with a paper scenario (the toy paper, registered for the test):
--units, --workers, --db resumption, old-shape scenarios beside it, bad input."""

from __future__ import annotations

import json
from collections import Counter

import pytest

from gyrobench.scenarios import registry
from tests.scenarios.test_cli import assert_one_line_error, run

# every test runs among planted user files and fails if one changes (tests/conftest.py)
pytestmark = pytest.mark.usefixtures("user_files")


@pytest.fixture
def toy_registered(monkeypatch):
    monkeypatch.setitem(registry.SCENARIOS, "toy_paper", "tests.scenarios.toy_paper")


def _claims(path):
    doc = json.loads(path.read_text())
    return doc, [
        (c["id"], c["testable"], c["holds"], c["median"], c["interval95"]) for c in doc["claims"]
    ]


def test_reproduce_paper_scenario_over_units(toy_registered, tmp_path, capsys):
    code, out, err = run(
        [
            "reproduce",
            "toy_paper",
            "--out",
            tmp_path / "a",
            "--units",
            "8",
            "--seed",
            "5",
            "--workers",
            "0",
            "-q",
        ],
        capsys,
    )
    assert code == 0, err
    doc, claims = _claims(tmp_path / "a" / "toy_paper" / "results.json")
    assert doc["units"] == 8 and doc["seed"] == 5 and doc["unit_run"]["seeds"] == list(range(5, 13))
    assert [c[0] for c in claims] == ["toy.gain", "toy.residual", "toy.sane", "toy.even"]
    assert claims[2][1:3] == (8, 8)  # toy.sane holds on every unit
    assert (tmp_path / "a.units.sqlite").is_file()  # the default resume store, beside the report
    assert "8 unit(s); method claims:" in out and "CONTRADICTED" in out
    md = (tmp_path / "a" / "report.md").read_text()
    assert "method (calibrated)" in md and "Deviations from the paper's protocol" in md
    # two workers: the same claims, bit for bit
    code, _, err = run(
        [
            "reproduce",
            "toy_paper",
            "--out",
            tmp_path / "b",
            "--units",
            "8",
            "--seed",
            "5",
            "--workers",
            "2",
            "-q",
        ],
        capsys,
    )
    assert code == 0, err
    assert _claims(tmp_path / "b" / "toy_paper" / "results.json")[1] == claims


def test_reproduce_resumes_from_the_db(toy_registered, tmp_path, capsys, monkeypatch):
    log = tmp_path / "calls.log"
    monkeypatch.setenv("GYROBENCH_TOY_CALL_LOG", str(log))
    db = tmp_path / "store.sqlite"
    argv = ["reproduce", "toy_paper", "--units", "4", "--workers", "0", "--db", db, "-q"]
    assert run([*argv, "--out", tmp_path / "a"], capsys)[0] == 0
    twice = 2  # each seed runs as a unit and as its control
    assert Counter(map(int, log.read_text().split())) == Counter(list(range(4)) * twice)
    assert run([*argv[:3], "6", *argv[4:], "--out", tmp_path / "b"], capsys)[0] == 0
    assert Counter(map(int, log.read_text().split())) == Counter(
        list(range(6)) * twice
    )  # only units 4 and 5 (and their controls) added
    assert not (tmp_path / "a" / "units.sqlite").exists()


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_reproduce_old_and_new_shapes_together(toy_registered, tmp_path, capsys):
    cfg_free = ["--units", "2", "--workers", "0", "-q"]
    code, out, err = run(
        ["reproduce", "toy_paper", "static_noise", "--out", tmp_path / "rep", *cfg_free], capsys
    )
    # static_noise at its default length takes a few seconds; it keeps its own run()
    assert code == 0, err
    assert "testable headline conclusions hold" in out and "2 unit(s)" in out
    assert "claims" not in json.loads((tmp_path / "rep" / "static_noise" / "results.json").read_text())


@pytest.mark.parametrize(
    "argv, match",
    [
        (["--units", "0"], "--units (or 'auto') must be an integer > 0; got '0'"),
        (["--workers", "-1"], "--workers must be an integer in [0, 1024] processes; got '-1'"),
        (
            ["--workers", "1", "--scheduler", "tcp://127.0.0.1:1"],
            "give either --workers or --scheduler, not both",
        ),
    ],
)
def test_reproduce_bad_options(toy_registered, tmp_path, capsys, argv, match):
    code, _, err = run(["reproduce", "toy_paper", "--out", tmp_path / "o", *argv], capsys)
    assert_one_line_error(code, err, match)


def test_reproduce_db_in_missing_folder(toy_registered, tmp_path, capsys):
    code, _, err = run(
        [
            "reproduce",
            "toy_paper",
            "--out",
            tmp_path / "o",
            "--units",
            "1",
            "--workers",
            "0",
            "--db",
            tmp_path / "missing" / "u.sqlite",
            "-q",
        ],
        capsys,
    )
    assert_one_line_error(code, err, "does not exist")


def test_reproduce_measures_the_deviations(toy_registered, tmp_path, capsys):
    """--deviations runs each deviation's variant over the first N units; without it nothing is claimed."""
    code, _, err = run(["reproduce", "toy_paper", "--units", "4", "--workers", "0", "--out", tmp_path / "a", "-q"],
                       capsys)
    assert code == 0, err
    doc = json.loads((tmp_path / "a" / "toy_paper" / "results.json").read_text())
    assert "deviation_effects" not in doc
    assert "not measured in this run" in (tmp_path / "a" / "report.md").read_text()
    code, _, err = run(["reproduce", "toy_paper", "--units", "4", "--workers", "0", "--deviations", "3",
                        "--out", tmp_path / "b", "-q"], capsys)
    assert code == 0, err
    doc = json.loads((tmp_path / "b" / "toy_paper" / "results.json").read_text())
    effects = {e["variant"]: e for e in doc["deviation_effects"]}
    assert set(effects) == {"paper_length", "paper_noise"} and {e["units"] for e in effects.values()} == {3}
    # the residual claim (below 0.05) cannot hold with 10x the noise: the measured change shows it
    res = next(c for c in effects["paper_noise"]["changes"] if c["claim"] == "toy.residual")
    assert res["holds_variant"] == 0 and res["testable_variant"] == 3
    md = (tmp_path / "b" / "report.md").read_text()
    assert "variant 'paper_noise' over 3 unit(s): " in md and "toy.residual" in md


def test_units_auto_adds_units_only_for_open_claims(toy_registered, tmp_path, capsys):
    """--units auto: 20 units, then batches of 10 while a claim's interval straddles 50 %, up to --max-units."""
    from tests.scenarios import toy_paper as toy

    code, _, err = run(["reproduce", "toy_paper", "--units", "auto", "--max-units", "40", "--workers", "0",
                        "--out", tmp_path / "a", "-q"], capsys)
    assert code == 0, err
    doc = json.loads((tmp_path / "a" / "toy_paper" / "results.json").read_text())
    used = {c["id"]: c["units"] for c in doc["claims"]}
    assert doc["units"] == max(used.values()) and set(used.values()) <= {20, 30, 40}
    # recompute from the units themselves: each claim stops at the first batch that decides it, judged at
    # the group-sequential z of the looks 20, 30, 40
    from gyrobench.scenarios.claims import evaluate, sequential_z

    z = sequential_z((20, 30, 40))
    assert doc["sequential"]["looks"] == [20, 30, 40] and doc["sequential"]["z"] == z
    assert doc["sequential"]["error_at_50_percent"] <= 0.05 and z > 1.96
    qs = [toy.experiment(toy.Config(), s)["quantities"] for s in range(40)]
    for claim in toy.CLAIMS:
        verdicts = {n: evaluate([claim], qs[:n], z=z)[0].verdict for n in (20, 30, 40)}
        first = next((n for n in (20, 30) if verdicts[n] != "undecided"), 40)
        assert used[claim.id] == first, (claim.id, verdicts)
    assert run(["reproduce", "toy_paper", "--units", "5", "--max-units", "9", "--out", tmp_path / "b", "-q"],
               capsys)[0] == 2
