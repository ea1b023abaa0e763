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

# every test runs among planted user files and fails if one changes (tests/conftest.py)
pytestmark = pytest.mark.usefixtures("user_files")

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
    assert c.n_taus >= 8 and np.allclose(c.tau, res.fit.curve.tau)  # every octave tau, not only the fitted
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


def test_twin_of_a_moving_record_is_built_from_its_quiet_stretches_and_exits_5(tmp_path, capsys):
    """A 1 Hz record with handling over a tenth: allan and twin share the verdict (exit 5); the twin is of
    the quiet stretches (the same windows left out of both curves) and says so."""
    from tests.analysis.record_classes import motion_record

    y, fs, _ = motion_record(np.random.default_rng(2))
    p = tmp_path / "m.csv"
    np.savetxt(p, np.column_stack([np.arange(y.size) / fs, np.degrees(y)]), delimiter=",",
               header="time [s],gyro [deg/s]", comments="", fmt="%.10g")
    code, out, err = run(["allan", p], capsys)
    assert code == 5, err
    code, out, err = run(["twin", p, "-o", tmp_path / "t.h5"], capsys)
    assert code == 5, err
    assert out.splitlines()[0].startswith("NONSTATIONARY") and "quiet stretches" in out
    code, out, err = run(["twin", p, "-o", tmp_path / "t2.h5", "--accept-nonstationary", "--json"], capsys)
    doc = json.loads(out)
    assert code in (0, 1) and doc["basis"] == "quiet stretches"


def test_phone_class_twin_needs_its_filter_and_its_n():
    """The filtered, bumped phone record: the chosen model's twin (quiet stretches, low-pass term) matches
    at every octave tau and in its sample spread; without its low-pass, or with N x 2, it fails at the
    short taus."""
    from gyrobench.analysis.quiet import quiet_curve
    from gyrobench.analysis.twin import compare_twin
    from tests.analysis.record_classes import phone_record

    y, fs, _ = phone_record(np.random.default_rng(1))
    res = make_twin(y, fs, rng=np.random.default_rng(5))
    assert res.model.endswith("low-pass") and res.samples.passed
    assert res.comparison.passed, (res.comparison.tau[~res.comparison.inside], res.comparison.ratio)
    ra = res.analysis
    lp = ra.model.term("lowpass")
    n_coef = lp.params["N"]
    rng = np.random.default_rng(6)
    base = res.recording["output"] - res.recording["truth/angle_random_walk"]
    for white in (rng.standard_normal(y.size) * n_coef * np.sqrt(fs),  # no filter
                  2.0 * res.recording["truth/angle_random_walk"]):  # N x 2
        twin = quiet_curve(base + white, fs, ra.stationarity).curve
        c = compare_twin(ra.fit_curve, twin)
        assert not c.passed and not c.inside[0]


def test_a_tenfold_adev_difference_never_matches():
    """At the last taus (1-2 edf) the F band is wider than 10x; the 10x rule still fails such a twin."""
    from gyrobench.analysis.twin import compare_twin

    rng = np.random.default_rng(0)
    real = allan_deviation(rng.standard_normal(64), 1.0)
    real = dataclasses.replace(real, edf=np.ones(real.tau.size))  # one degree of freedom: sqrt F band ~ 25x
    twin = dataclasses.replace(real, deviation=real.deviation * 11.0)
    c = compare_twin(real, twin, taus=real.tau[-1:], max_ratio=1e9)
    assert c.passed  # the F band alone allows it
    assert not compare_twin(real, twin, taus=real.tau[-1:]).passed


def test_allan_filter_model_file_has_units_in_every_key(tmp_path, capsys):
    out = tmp_path / "noise.yaml"
    code, text, err = run(["allan", RECORDS[0], "--column", "gyro_z_dps", "--fs", "1", "--filter-model", out,
                           "--overbound"], capsys)
    assert code == 0, err
    body = out.read_text()
    for line in body.splitlines():
        if line.startswith("#") or line.endswith(":"):
            continue
        key = line.split(":")[0].strip()
        assert "[" in line or key.endswith(("_hz", "_s", "_squared", "_1", "_rad_per_s", "identified")), line
    assert "kalibr:" in body and "openvins:" in body and "angular_velocity_covariance" in body
    # the deviation values are in the text output
    assert "overlapping deviation [deg/h]" in text


@pytest.mark.parametrize("axis", [0, 1])
def test_twin_of_a_real_100hz_record_with_a_filter_bend_matches_at_every_octave_tau(axis):
    """ADIS16405 imu1 at 100 Hz (SMAC-Group/imudata, ../shared/validation): its first octaves bend under the
    sensor's low-pass. The chosen model carries a low-pass term; its twin matches at all 18 octave taus and
    in its sample spread (family-wise false-alarm rate 0.05; the z axis, with a 20 Hz tone the model has no
    term for, is left out). The same twin with N x 2, or without its filter, fails."""
    from gyrobench.analysis.record import octave_subset
    from tests.analysis.conftest import VALIDATION

    path = VALIDATION / "smac_imudata_adis16405" / "adis16405_imu1_100Hz.csv.gz"
    if not path.is_file():
        pytest.skip(f"reference record {path} not found (set GYROBENCH_VALIDATION)")
    y = np.radians(np.loadtxt(path, delimiter=",", skiprows=2, usecols=(axis,)))
    res = make_twin(y, 100.0, rng=np.random.default_rng(axis))
    c = res.comparison
    assert res.model.endswith("low-pass") and c.n_taus == len(res.fit.curve.tau) >= 16
    assert c.passed and res.samples.passed, (c.tau[~c.inside], c.ratio[~c.inside], res.samples)
    rec = res.recording
    white = rec["truth/angle_random_walk"]
    rest = rec["output"] - white
    lp = res.analysis.model.term("lowpass")
    unfiltered = np.random.default_rng(9).standard_normal(y.size) * lp.params["N"] * 10.0  # N sqrt(fs)
    for wrong in (rest + 2.0 * white, rest + unfiltered):
        twin = octave_subset(allan_deviation(wrong, 100.0))
        assert not compare_twin(res.fit.curve, twin).passed
