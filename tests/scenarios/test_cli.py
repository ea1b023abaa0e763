"""The gyrobench command line: verbs work end to end; bad input gives one line and exit 2."""

import json
from pathlib import Path

import h5py
import numpy as np
import pytest

from analysis.allan import allan_deviation, fit_noise
from scenarios.cli import main
from sim import units
from sim.recording import load_hdf5

VALIDATION = Path(__file__).resolve().parents[2].parent / "shared" / "validation"


def run(argv, capsys):
    try:
        code = main([str(a) for a in argv])
    except SystemExit as exc:  # argparse errors
        code = exc.code
    out, err = capsys.readouterr()
    return code, out, err


def assert_one_line_error(code, err, match):
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("gyrobench: error:")
    assert "Traceback" not in err
    assert match in lines[0], lines[0]


@pytest.fixture
def noise_h5(tmp_path, capsys):
    p = tmp_path / "rec.h5"
    code, out, _ = run(["simulate", "noise", "--N", "0.5", "--B", "2", "--Q", "1", "--fs", "100", "--duration", "20min",
                        "--seed", "4", "-o", p, "-q"], capsys)
    assert code == 0, out
    return p


def test_list(capsys):
    code, out, _ = run(["list"], capsys)
    assert code == 0
    assert out.splitlines()[0].startswith("static_noise")


def test_simulate_noise_hdf5_and_csv_agree(noise_h5, tmp_path, capsys):
    rec = load_hdf5(noise_h5)
    assert rec.fs == 100.0 and rec.n_samples == 120_000 and rec.channels["rate"].unit == "rad/s"
    assert rec.metadata["seed"] == 4
    csv = tmp_path / "rec.csv"
    code, _, _ = run(["simulate", "noise", "--N", "0.5", "--B", "2", "--Q", "1", "--fs", "100", "--duration", "1200s",
                      "--seed", "4", "-o", csv, "-q", "--chunk", "7777"], capsys)
    assert code == 0
    data = np.loadtxt(csv, delimiter=",", comments="#", skiprows=2)
    np.testing.assert_array_equal(data[:, 1], rec["rate"])  # same seed, other chunking, exact


def test_allan_json_on_hdf5(noise_h5, capsys):
    code, out, _ = run(["allan", noise_h5, "--json"], capsys)
    assert code == 0
    doc = json.loads(out)
    assert set(doc) == {"Q", "N", "B", "K", "R"}
    for v in doc.values():
        assert set(v) == {"value", "low", "high", "unit"}
    assert doc["N"]["unit"] == "deg/sqrt(h)" and doc["Q"]["unit"] == "arcsec"
    # plumbing: the CLI prints the library's fit in field units (coverage is tested in tests/analysis)
    rec = load_hdf5(noise_h5)
    fit = fit_noise(allan_deviation(rec["rate"], rec.fs))
    for name, d in doc.items():
        c = fit.coefficients[name]
        if c.identifiable:
            assert d["value"] == pytest.approx(units.coefficient_to_field(name, c.value), rel=1e-12)
            assert d["low"] == pytest.approx(units.coefficient_to_field(name, c.ci95[0]), rel=1e-12)
            assert d["high"] == pytest.approx(units.coefficient_to_field(name, c.ci95[1]), rel=1e-12)
        else:
            assert d["value"] is None
            assert d["high"] == pytest.approx(units.coefficient_to_field(name, c.upper_bound), rel=1e-12)


def test_allan_table_and_plot(noise_h5, tmp_path, capsys):
    png = tmp_path / "adev.png"
    code, out, _ = run(["allan", noise_h5, "--plot", png], capsys)
    assert code == 0
    assert "deg/sqrt(h)" in out and png.stat().st_size > 10_000
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_allan_csv_with_time_column_and_units_from_header(tmp_path, capsys):
    fs = 50.0
    rate = np.random.default_rng([20261121, 9]).standard_normal(20_000) * 0.1  # deg/s
    p = tmp_path / "g.csv"
    np.savetxt(p, np.column_stack([np.arange(len(rate)) / fs, rate]), delimiter=",", header="time [s],gyro [deg/s]", comments="")
    code, out, _ = run(["allan", p, "--json"], capsys)
    assert code == 0
    n = json.loads(out)["N"]
    # fs from the time column and deg/s from the header: the same fit as the library on rad/s at 50 Hz
    c = fit_noise(allan_deviation(units.deg_per_s(rate), fs)).coefficients["N"]
    assert n["value"] == pytest.approx(units.coefficient_to_field("N", c.value), rel=1e-9)


def test_csv_reader_keeps_every_row(tmp_path):
    from scenarios.cli import _read_csv

    rate = np.arange(1.0, 101.0)
    for header, comments in (("# a comment\n# another\nrate [deg/h]\n", 2), ("", 0)):
        p = tmp_path / f"c{comments}.csv"
        p.write_text(header + "\n".join(map(str, rate)) + "\n")
        got, fs, _ = _read_csv(p, None if header else "0", 10.0, None if header else "deg/h")
        np.testing.assert_array_equal(got, units.deg_per_h(rate))
        assert fs == 10.0


@pytest.mark.skipif(not (VALIDATION / "smac_imudata_adis16405").is_dir(), reason="shared/validation absent")
def test_allan_reads_a_real_gyro_csv(capsys):
    p = VALIDATION / "smac_imudata_adis16405" / "adis16405_imu1_100Hz.csv.gz"
    code, out, err = run(["allan", p, "--column", "gyro_x_dps", "--fs", "100", "--units", "deg/s", "--json"], capsys)
    assert code == 0, err
    doc = json.loads(out)
    # datasheet noise density 0.05 deg/s/sqrt(Hz) -> N = 3 deg/sqrt(h); the fit must be of that order
    assert 0.5 < doc["N"]["value"] < 10


def test_simulate_scenario_writes_recordings(tmp_path, capsys):
    cfg = tmp_path / "c.toml"
    cfg.write_text("[fog]\nduration_h = 0.05\n[mems]\nduration_h = 0.05\n")
    code, out, err = run(["simulate", "static_noise", "--seed", "2", "--out", tmp_path, "--config", cfg], capsys)
    assert code == 0, err
    files = sorted((tmp_path / "static_noise").glob("*.h5"))
    assert [f.name for f in files] == ["static_fog.h5", "static_mems.h5"]
    rec = load_hdf5(files[0])
    assert "true_rate" in rec.truth and rec.n_samples == 18_000


def test_reproduce_static_noise(tmp_path, capsys):
    cfg = tmp_path / "c.toml"
    cfg.write_text("[fog]\nduration_h = 0.5\n[mems]\nduration_h = 0.5\n")
    code, out, err = run(["reproduce", "static_noise", "--out", tmp_path / "rep", "--config", cfg, "-q"], capsys)
    assert code == 0, err
    res = json.loads((tmp_path / "rep" / "static_noise" / "results.json").read_text())
    assert res["seed"] == 0 and res["config"]["fog"]["duration_h"] == 0.5
    assert set(res["grades"]) == {"fog", "mems"}
    html = (tmp_path / "rep" / "index.html").read_text()
    assert html.count("data:image/png;base64,") == 2
    assert (tmp_path / "rep" / "report.md").is_file()


# ----------------------------------------------------------------------------- bad input, one case each
def test_bad_nan_in_csv(tmp_path, capsys):
    p = tmp_path / "g.csv"
    p.write_text("rate [deg/s]\n" + "\n".join(["0.1"] * 500 + ["nan"] + ["0.2"] * 500) + "\n")
    code, _, err = run(["allan", p, "--fs", "10"], capsys)
    assert_one_line_error(code, err, "nan")


def test_bad_inf_in_csv(tmp_path, capsys):
    p = tmp_path / "g.csv"
    p.write_text("rate [deg/s]\n" + "\n".join(["0.1"] * 500 + ["inf"]) + "\n")
    code, _, err = run(["allan", p, "--fs", "10"], capsys)
    assert_one_line_error(code, err, "inf")


def test_bad_too_few_samples(tmp_path, capsys):
    p = tmp_path / "g.csv"
    p.write_text("rate [deg/s]\n0.1\n0.2\n")
    code, _, err = run(["allan", p, "--fs", "10"], capsys)
    assert_one_line_error(code, err, "")


def test_bad_nonpositive_fs(capsys, tmp_path):
    code, _, err = run(["simulate", "noise", "--N", "1", "--fs", "0", "--duration", "1s", "-o", tmp_path / "x.h5"], capsys)
    assert_one_line_error(code, err, "--fs must be a finite number > 0; got '0'")
    assert not (tmp_path / "x.h5").exists()


def test_bad_negative_coefficient(capsys, tmp_path):
    code, _, err = run(["simulate", "noise", "--K", "-0.1", "--duration", "1s", "-o", tmp_path / "x.h5"], capsys)
    assert_one_line_error(code, err, "--K must be a finite number >= 0; got '-0.1'")


def test_bad_unknown_units(tmp_path, capsys):
    p = tmp_path / "g.csv"
    p.write_text("rate\n" + "\n".join(["0.1"] * 100) + "\n")
    code, _, err = run(["allan", p, "--fs", "10", "--units", "furlong/s"], capsys)
    assert_one_line_error(code, err, "rate unit must be one of")


def test_bad_missing_units(tmp_path, capsys):
    p = tmp_path / "g.csv"
    p.write_text("rate\n" + "\n".join(["0.1"] * 100) + "\n")
    code, _, err = run(["allan", p, "--fs", "10"], capsys)
    assert_one_line_error(code, err, "give --units")


def test_bad_truncated_hdf5(noise_h5, tmp_path, capsys):
    data = noise_h5.read_bytes()
    bad = tmp_path / "trunc.h5"
    bad.write_bytes(data[: len(data) // 3])
    code, _, err = run(["allan", bad], capsys)
    assert_one_line_error(code, err, "trunc.h5")


def test_bad_foreign_hdf5(tmp_path, capsys):
    p = tmp_path / "foreign.h5"
    with h5py.File(p, "w") as h5:
        h5["rate"] = np.zeros(100)
    code, _, err = run(["allan", p], capsys)
    assert_one_line_error(code, err, "not a gyrobench recording")


def test_bad_csv_without_named_column(tmp_path, capsys):
    p = tmp_path / "g.csv"
    p.write_text("time [s],gyro_x [deg/s]\n0,1\n0.1,2\n")
    code, _, err = run(["allan", p, "--column", "gyro_z"], capsys)
    assert_one_line_error(code, err, "--column 'gyro_z' is not in")


def test_bad_unknown_scenario(tmp_path, capsys):
    code, _, err = run(["reproduce", "nope", "--out", tmp_path], capsys)
    assert_one_line_error(code, err, "scenario must be one of")
    assert list(tmp_path.iterdir()) == []


def test_bad_config_key(tmp_path, capsys):
    cfg = tmp_path / "c.toml"
    cfg.write_text("nonsense = 3\n")
    code, _, err = run(["simulate", "static_noise", "--out", tmp_path / "o", "--config", cfg], capsys)
    assert_one_line_error(code, err, "has no parameter(s) ['nonsense']")
    assert not (tmp_path / "o").exists()


def test_bad_duration(tmp_path, capsys):
    code, _, err = run(["simulate", "noise", "--N", "1", "--duration", "3 parsecs", "-o", tmp_path / "x.h5"], capsys)
    assert_one_line_error(code, err, "duration must be")


def test_bad_output_suffix(tmp_path, capsys):
    code, _, err = run(["simulate", "noise", "--N", "1", "--duration", "3s", "-o", tmp_path / "x.mat"], capsys)
    assert_one_line_error(code, err, "-o must end in .h5, .hdf5 or .csv")


def test_missing_file(capsys):
    code, _, err = run(["allan", "/nonexistent/x.h5"], capsys)
    assert_one_line_error(code, err, "not found")


def test_console_script_exit_code(tmp_path):
    # the installed entry point, as a user runs it: exit 2, one line, no traceback
    import subprocess
    import sys

    exe = Path(sys.executable).parent / "gyrobench"
    if not exe.exists():
        pytest.skip("gyrobench console script not installed beside this python")
    r = subprocess.run([str(exe), "simulate", "noise", "--N", "nan", "-o", str(tmp_path / "x.h5")], capture_output=True, text=True)
    assert r.returncode == 2
    assert len(r.stderr.strip().splitlines()) == 1 and "Traceback" not in r.stderr
