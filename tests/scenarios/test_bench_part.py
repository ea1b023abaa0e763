"""`gyrobench bench --part FILE.toml|NAME`: the fit-your-part loop (simulate -> twin --save-part ->
bench --part), the part file's content in the campaign's identity, and bad part files refused in one
line (exit 2) before anything is written."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from gyrobench.scenarios import part_bench

from .test_cli import assert_one_line_error, run

pytestmark = pytest.mark.usefixtures("user_files")

#: short programs (10 min each at 10 Hz): the loop, not the physics, is under test
SHORT = "train_duration_s = 600.0\ntest_duration_s = 600.0\n"

COMPENSATOR = """\
from sklearn.linear_model import LinearRegression

mine = LinearRegression()
"""


@pytest.fixture
def lab(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A folder with a compensator module, a short-program config and a twin's part file."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "comp_part.py").write_text(COMPENSATOR)
    (tmp_path / "short.toml").write_text(SHORT)
    return tmp_path


def _save_part(lab: Path, capsys) -> Path:
    rec, part = lab / "rec.h5", lab / "mine.toml"
    code, _, err = run(["simulate", "device", "dsp-1760", "--duration", "1200s", "--fs", "10", "-o", rec], capsys)
    assert code == 0, err
    code, out, err = run(["twin", rec, "-o", lab / "twin.h5", "--save-part", part, "--technology", "FOG"], capsys)
    assert code == 0 and part.exists(), err
    return part


def _bench(lab: Path, part: Path | str, capsys, *extra: str) -> tuple[int, str, str]:
    return run(["bench", "--part", part, "--compensator", "comp_part:mine", "--seeds", "0:2", "--workers", "0",
                "-q", "--db", lab / "b.sqlite", "--config", lab / "short.toml", "--no-references", *extra], capsys)


def _campaign(out: str) -> tuple[str, int, int]:
    m = re.search(r"campaign (\w+): scenario part.*?(\d+) computed, (\d+) from the database", out)
    assert m, out
    return m.group(1), int(m.group(2)), int(m.group(3))


@pytest.mark.slow
@pytest.mark.parametrize(("flag", "model"), [(None, "budget"), ("physics", "physics")])
def test_simulate_twin_save_part_bench_part_gives_scores(lab, capsys, flag, model):
    """Without --model the twin's part runs on its own default_model (budget), as simulate device runs it."""
    part = _save_part(lab, capsys)
    code, out, err = _bench(lab, part, capsys, *(("--model", flag) if flag else ()))
    assert code == 0, err
    assert out.startswith(f"part mine from {part}") and f"model {model}:" in out.splitlines()[0], out
    row = next(ln for ln in out.splitlines() if ln.startswith("mean/rms"))
    mean = float(row.split()[3])
    assert np.isfinite(mean) and mean > 0, row


@pytest.mark.slow
def test_a_changed_part_file_starts_a_new_campaign(lab, capsys):
    part = _save_part(lab, capsys)
    code, out, err = _bench(lab, part, capsys, "--model", "budget")
    assert code == 0, err
    first, computed, _ = _campaign(out)
    assert computed == 2
    code, out, err = _bench(lab, part, capsys, "--model", "budget")  # the same file: resumed, nothing computed
    assert code == 0 and _campaign(out) == (first, 0, 2), out
    text = part.read_text()
    arw = re.search(r"^arw = (\S+)$", text, flags=re.M)
    assert arw, text
    part.write_text(text.replace(arw.group(0), f"arw = {2 * float(arw.group(1))!r}"))  # the same path, new content
    code, out, err = _bench(lab, part, capsys, "--model", "budget")
    assert code == 0, err
    second, computed, _ = _campaign(out)
    assert second != first and computed == 2


#: a complete part file: the required keys and one noise figure
GOOD = 'name = "x"\nmanufacturer = "me"\nmodel = "m"\ngrade = "tactical"\nsource = "a test"\ntechnology = "FOG"\n'


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("name = \n", "is not valid TOML"),
        (GOOD + "arw = 0.01\nwobble = 1.0\n", "unknown key(s) ['wobble']"),
        (GOOD + "arw = -1.0\n", "arw"),
        (GOOD.replace('"FOG"', '"TELEPATHY"') + "arw = 0.01\n", "technology"),
        ('name = "x"\ntechnology = "FOG"\narw = 0.01\n', "missing"),
    ],
)
def test_a_bad_part_file_is_refused_in_one_line_before_anything_is_written(lab, capsys, text, match):
    bad = lab / "bad.toml"
    bad.write_text(text)
    code, _, err = _bench(lab, bad, capsys)
    assert_one_line_error(code, err, match)
    assert "bad.toml" in err
    assert not (lab / "b.sqlite").exists()


def test_a_missing_part_file_and_an_unknown_part_are_refused_in_one_line(lab, capsys):
    code, _, err = _bench(lab, lab / "none.toml", capsys)
    assert_one_line_error(code, err, "none.toml")
    code, _, err = _bench(lab, "no-such-part", capsys)
    assert_one_line_error(code, err, "--part: unknown part 'no-such-part'")
    code, _, err = run(["bench", "ifog_thermal", "--part", "stim300", "--compensator", "comp_part:mine"], capsys)
    assert_one_line_error(code, err, "--part runs the scenario 'part'")
    code, _, err = run(["bench", "ifog_thermal", "--model", "budget", "--compensator", "comp_part:mine"], capsys)
    assert_one_line_error(code, err, "--model goes with --part")
    assert not (lab / "b.sqlite").exists()


def test_the_part_file_rides_in_the_config_and_the_campaign_id(lab):
    """The campaign id hashes the configuration, which holds the file's text: a changed text, a new id."""
    from gyrobench.scenarios.bench import campaign_id

    text = 'name = "x"\ntechnology = "FOG"\narw = 0.01\n'
    a = part_bench.Config(part="file", part_toml=text, model="budget")
    b = part_bench.Config(part="file", part_toml=text.replace("0.01", "0.02"), model="budget")
    assert campaign_id(part_bench, "comp_part:mine", a) != campaign_id(part_bench, "comp_part:mine", b)
    assert campaign_id(part_bench, "comp_part:mine", a) == campaign_id(
        part_bench, "comp_part:mine", part_bench.Config(part="file", part_toml=text, model="budget"))
    with pytest.raises(ValueError, match="part_toml must be given exactly when part is 'file'"):
        part_bench.Config(part="file")


def test_calibration_and_test_are_one_unit():
    """Both runs of a seed share the unit's draw (its turn-on bias, from the BMI088's bias repeatability);
    another seed is another unit."""
    cfg = part_bench.Config(part="bmi088", model="budget", train_duration_s=600.0, test_duration_s=600.0)
    (train, test), (train2, _) = part_bench.simulate(cfg, 5), part_bench.simulate(cfg, 6)
    assert train["truth/turn_on_bias"][0] == test["truth/turn_on_bias"][0]
    assert train["truth/turn_on_bias"][0] != train2["truth/turn_on_bias"][0]


def test_a_linear_compensator_removes_the_parts_linear_thermal_error():
    """BMI088 on its budget: a bias tempco and g-sensitivity from its sheet, linear in T and g, so a
    linear regression on the features must beat the uncompensated output on the held-out program
    (fails if a feature is misaligned with the record or in the wrong unit)."""
    from sklearn.linear_model import LinearRegression

    from gyrobench.scenarios.bench import score_seed

    cfg = part_bench.Config(part="bmi088", model="budget", train_duration_s=900.0, test_duration_s=900.0)
    task = part_bench.compensation_task(cfg, 3)
    held = task.heldout[0]
    raw = float(np.sqrt(np.mean((held.output - held.truth) ** 2)))
    scores = score_seed(part_bench, LinearRegression(), 3, config=cfg)
    assert scores["mean/rms"] < raw, (scores, raw)
    # the features are what the test logs: the chamber temperature inside the programme's span
    assert task.X_train[:, 0].min() >= min(cfg.train_temperatures_c) - 1e-9
    assert task.X_train[:, 0].max() <= max(cfg.train_temperatures_c) + 1e-9


@pytest.mark.slow
def test_a_baseline_of_another_part_is_refused_before_the_campaign(lab, capsys):
    base = lab / "base.json"
    code, out, err = run(["bench", "--part", "stim300", "--model", "budget", "--compensator", "comp_part:mine",
                          "--seeds", "0:2", "--workers", "0", "-q", "--db", lab / "b.sqlite", "--config",
                          lab / "short.toml", "--no-references", "--save-baseline", base, "--allow-underpowered"],
                         capsys)
    assert code == 0 and base.exists(), err
    compare = ["--compensator", "comp_part:mine", "--workers", "0", "-q", "--db", lab / "b.sqlite", "--config",
               lab / "short.toml", "--no-references", "--baseline", base, "--allow-underpowered"]
    code, out, err = run(["bench", "--part", "stim300", "--model", "budget", *compare], capsys)
    assert code == 0, (out, err)  # the same part and model: compared
    code, _, err = run(["bench", "--part", "hg9900", "--model", "budget", *compare], capsys)
    assert_one_line_error(code, err, "was run on another part or model")
    code, _, err = run(["bench", "--part", "stim300", *compare], capsys)  # stim300's own model is physics
    assert_one_line_error(code, err, "was run on another part or model")
