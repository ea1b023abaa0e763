"""Tests of ``gyrobench twin`` (scenarios/cli/twin.py): real ADIS16405 records, a wrong twin, the CLI."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from gyrobench.analysis.allan import allan_deviation, fit_noise
from gyrobench.analysis.twin import compare_twin
from gyrobench.io.recording import load_hdf5
from gyrobench.scenarios.cli.main import main
from gyrobench.scenarios.cli.twin import make_twin, noise_model_from_fit
from gyrobench.sim import parts

DATA = Path(__file__).resolve().parents[1] / "data" / "adis16405_1hz"
RECORDS = sorted(DATA.glob("adis16405_imu*_1Hz.csv.gz"))
AXES = ("gyro_x_dps", "gyro_y_dps", "gyro_z_dps")


def _rate(path: Path, axis: str) -> np.ndarray:
    arr = np.loadtxt(path, delimiter=",", skiprows=2)
    return np.radians(arr[:, AXES.index(axis)])


def run(argv, capsys):
    try:
        code = main([str(a) for a in argv])
    except SystemExit as exc:  # argparse errors
        code = exc.code
    out, err = capsys.readouterr()
    return code, out, err


def test_the_excerpt_is_there():
    assert len(RECORDS) == 6


# Each record's twin is judged at family-wise false-alarm rate 0.05 (analysis/twin.py); the
# fitted twin fails at most that often (test_fitted_twin_false_alarm_rate_over_seeds, slow), so
# 18 records expect ~0.2 chance fails; a fail here points at a mismatch. Fixed seed per axis.
@pytest.mark.parametrize("axis", AXES)
@pytest.mark.parametrize("path", RECORDS, ids=lambda p: p.name.split("_")[1])
def test_twin_of_a_real_adis16405_record_matches_at_every_fitted_tau(path, axis):
    res = make_twin(_rate(path, axis), 1.0, rng=np.random.default_rng(AXES.index(axis)))
    c = res.comparison
    assert c.n_taus >= 8 and np.allclose(c.tau, res.fit.tau_used)
    assert c.passed, (c.tau[~c.inside], c.ratio[~c.inside])
    # the twin's truth terms sum to its output (the one truth layout), true rate 0
    rec = res.recording
    comps = [rec["truth/" + k] for k in rec.metadata["error_components"]]
    assert np.max(np.abs(rec["output"] - np.sum(comps, axis=0))) <= 1e-15 * np.max(np.abs(rec["output"])) * 8


@pytest.mark.parametrize("path", RECORDS[:2], ids=lambda p: p.name.split("_")[1])
def test_a_wrong_twin_with_twice_the_angle_random_walk_fails(path):
    rate = _rate(path, "gyro_z_dps")
    fit = fit_noise(rate, 1.0, tau_min="auto")
    good = noise_model_from_fit(fit)
    wrong = dataclasses.replace(good, angle_random_walk=2 * good.angle_random_walk)
    twin = allan_deviation(wrong.generate(len(rate), 1.0, rng=np.random.default_rng(0)), 1.0)
    c = compare_twin(fit.curve, twin, taus=fit.tau_used)
    assert not c.passed and not c.inside[0] and c.ratio[0] > 1.5


def test_a_navigation_fog_is_not_a_twin_of_a_mems_record():
    rate = _rate(RECORDS[0], "gyro_x_dps")
    res = make_twin(rate, 1.0, rng=np.random.default_rng(0), part="astrix-120")
    assert res.model == "astrix-120" and not res.comparison.passed


def test_a_record_with_a_gauss_markov_bump_gets_the_term():
    # white noise plus a strong first-order Gauss-Markov term (sigma 3e-4 rad/s, Tc 100 s): the
    # five power laws misfit, the twin gains a Gauss-Markov term near the truth and matches
    from gyrobench.sim.noise import GaussMarkov, NoiseModel

    truth = NoiseModel(angle_random_walk=1e-3, gauss_markov=(GaussMarkov(sigma=3e-4, correlation_time=100.0),))
    for s in range(3):
        y = truth.generate(20_000, 1.0, rng=np.random.default_rng([9, s]))
        res = make_twin(y, 1.0, rng=np.random.default_rng(1))
        assert res.fit.misfit and res.model == "fit + Gauss-Markov" and res.comparison.passed
        # measured 3.0e-4 and 83-100 s on these seeds: the term is the bump, not a stray pole
        assert 1.5e-4 < res.coefficients["gm_sigma"] < 6e-4 and 25 < res.coefficients["gm_correlation_time"] < 400


def test_nearest_part_of_a_technology():
    rate = _rate(RECORDS[0], "gyro_x_dps")
    res = make_twin(rate, 1.0, rng=np.random.default_rng(0), nearest="MEMS")
    assert parts.get(res.model).datasheet.technology == "MEMS"
    # the ADIS16405 (ARW ~ 2 deg/sqrt(h)) is nearest the high-noise MEMS parts, not the tactical ones
    assert res.model not in ("stim300", "adis16495-1", "sch16t-k01")


def test_cli_twin_writes_the_twin_table_json_and_plot(tmp_path, capsys):
    out, png = tmp_path / "twin.h5", tmp_path / "twin.png"
    code, text, err = run(["twin", RECORDS[0], "--column", "gyro_z_dps", "--fs", "1", "-o", out, "--plot", png,
                           "--seed", "3"], capsys)
    assert code == 0, err
    assert "twin MATCHES" in text and "family-wise false-alarm rate <= 0.05" in text
    assert png.stat().st_size > 1000
    rec = load_hdf5(out)
    assert rec.n_samples == 10_000 and rec.fs == 1.0 and np.all(rec["truth/true_rate"] == 0)
    code, text, err = run(["twin", RECORDS[0], "--column", "gyro_z_dps", "--fs", "1", "-o", out, "--json",
                           "--alpha", "0.01"], capsys)
    doc = json.loads(text)
    assert code == 0 and doc["passed"] and doc["family_alpha"] == 0.01 and len(doc["taus"]) >= 8
    assert all(t["inside"] for t in doc["taus"])
    csv = tmp_path / "twin.csv"
    code, _, err = run(["twin", RECORDS[0], "--column", "gyro_z_dps", "--fs", "1", "-o", csv], capsys)
    assert code == 0, err
    assert csv.read_text().count("\n") > 10_000


def test_cli_twin_exit_1_when_the_twin_does_not_match(tmp_path, capsys):
    code, text, _ = run(["twin", RECORDS[0], "--column", "gyro_x_dps", "--fs", "1", "-o", tmp_path / "t.h5",
                         "--part", "hg9900"], capsys)
    assert code == 1 and "DOES NOT MATCH" in text


@pytest.mark.parametrize("extra, match", [
    (["--part", "stim300", "--nearest", "MEMS"], "not both"),
    (["--alpha", "1.5"], r"--alpha must be in \(0, 1\)"),
    (["--part", "nope"], "unknown part 'nope'"),
    (["-o", "twin.txt"], "-o must end in .h5, .hdf5 or .csv"),
])
def test_cli_twin_bad_input_is_one_line(tmp_path, capsys, extra, match):
    code, _, err = run(["twin", RECORDS[0], "--column", "gyro_x_dps", "--fs", "1", "-o", tmp_path / "t.h5", *extra],
                       capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1
    import re

    assert re.search(match, err), err


# make_twin's own false-alarm rate (fit, optional Gauss-Markov term, simulate, compare) over S
# synthetic records of a known model: the count may exceed the binomial(S, 0.05) quantile at
# 1 - 1e-3 only with probability 1e-3 if a fitted twin fails at most 5 % of the time. Measured:
# 1/200 fail (bound 21; one record got a Gauss-Markov term): fitting makes the rule conservative.
S = 200


@pytest.mark.slow
def test_fitted_twin_false_alarm_rate_over_seeds():
    from scipy.stats import binom

    from gyrobench.sim.noise import NoiseModel

    truth = NoiseModel(angle_random_walk=1e-3, bias_instability=1e-4, rate_random_walk=2e-6)
    fails = 0
    for s in range(S):
        rng = np.random.default_rng([8, s])
        res = make_twin(truth.generate(20_000, 1.0, rng=rng), 1.0, rng=rng)
        fails += not res.comparison.passed
    assert fails <= binom.isf(1e-3, S, 0.05), fails
