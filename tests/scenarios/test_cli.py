"""The gyrobench command line: verbs work end to end; bad input gives one line and exit 2."""

import json
from pathlib import Path

import h5py
import numpy as np
import pytest

from gyrobench.analysis.allan import allan_deviation, fit_noise
from gyrobench.base import units
from gyrobench.io.recording import load_hdf5
from gyrobench.scenarios.cli.main import main
from gyrobench.scenarios.reports.allan import TERMS
from gyrobench.scenarios.static_noise import MIN_SAMPLES

# every test runs among planted user files and fails if one changes (tests/conftest.py)
pytestmark = pytest.mark.usefixtures("user_files")

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
    assert rec.fs == 100.0 and rec.n_samples == 120_000 and rec.channels["output"].unit == "rad/s"
    assert rec.metadata["seed"] == 4
    csv = tmp_path / "rec.csv"
    code, _, _ = run(["simulate", "noise", "--N", "0.5", "--B", "2", "--Q", "1", "--fs", "100", "--duration", "1200s",
                      "--seed", "4", "-o", csv, "-q", "--chunk", "7777"], capsys)
    assert code == 0
    data = np.loadtxt(csv, delimiter=",", comments="#", skiprows=2)
    np.testing.assert_array_equal(data[:, 1], rec["output"])  # same seed, other chunking, exact


def test_allan_json_on_hdf5(noise_h5, capsys):
    code, out, _ = run(["allan", noise_h5, "--json"], capsys)
    assert code == 0
    doc = json.loads(out)
    assert {"curve", "fit", "adev_floor"} <= set(doc)  # issue 14: the curve and the fit's statistics too
    doc = {name: doc[name] for name in ("Q", "N", "B", "K", "R")}
    for v in doc.values():
        assert set(v) == {"value", "low", "high", "unit"}
    assert doc["N"]["unit"] == "deg/sqrt(h)" and doc["Q"]["unit"] == "arcsec"
    # plumbing: the CLI prints the library's fit in field units (coverage is tested in tests/analysis)
    rec = load_hdf5(noise_h5)
    fit = fit_noise(allan_deviation(rec["output"], rec.fs))
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
    np.savetxt(p, np.column_stack([np.arange(len(rate)) / fs, rate]), delimiter=",",
               header="time [s],gyro [deg/s]", comments="")
    code, out, _ = run(["allan", p, "--json"], capsys)
    assert code == 0
    n = json.loads(out)["N"]
    # fs from the time column and deg/s from the header: the same fit as the library on rad/s at 50 Hz
    c = fit_noise(allan_deviation(units.deg_per_s(rate), fs)).coefficients["N"]
    assert n["value"] == pytest.approx(units.coefficient_to_field("N", c.value), rel=1e-9)


def test_csv_reader_keeps_every_row(tmp_path):
    from gyrobench.scenarios.cli.allan import read_csv as _read_csv

    rate = np.arange(1.0, 101.0)
    for header, comments in (("# a comment\n# another\nrate [deg/h]\n", 2), ("", 0)):
        p = tmp_path / f"c{comments}.csv"
        p.write_text(header + "\n".join(map(str, rate)) + "\n")
        got, fs, _ = _read_csv(p, None if header else "0", 10.0, None if header else "deg/h")
        np.testing.assert_array_equal(got, units.deg_per_h(rate))
        assert fs == 10.0


def test_allan_reads_the_shipped_real_gyro_excerpt(capsys):
    """A real gzip CSV from tests/data (any clone): the CLI reports the library's own fit of it."""
    import gzip


    p = Path(__file__).resolve().parents[1] / "data" / "adis16405_1hz" / "adis16405_imu1_1Hz.csv.gz"
    code, out, err = run(["allan", p, "--column", "gyro_x_dps", "--fs", "1", "--units", "deg/s", "--json"], capsys)
    assert code == 0, err
    doc = json.loads(out)
    with gzip.open(p, "rt") as fh:
        x = np.loadtxt((ln for ln in fh if ln[:1] not in ("#", "g")), delimiter=",", usecols=0)
    fit = fit_noise(allan_deviation(units.deg_per_s(x), 1.0), tau_min="auto")
    assert doc["N"]["value"] == pytest.approx(fit.coefficients["N"].value / units.deg_per_sqrt_h(1.0), rel=1e-12)


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
    assert_one_line_error(code, err, "rate contains nan at sample 500")  # not np.float64(nan)


def test_bad_inf_in_csv(tmp_path, capsys):
    p = tmp_path / "g.csv"
    p.write_text("rate [deg/s]\n" + "\n".join(["0.1"] * 500 + ["inf"]) + "\n")
    code, _, err = run(["allan", p, "--fs", "10"], capsys)
    assert_one_line_error(code, err, "rate contains inf at sample 500")


@pytest.mark.parametrize(
    ("rows", "match"),
    [
        (2, "rate has too few samples for the"),  # analysis.allan: fewer than the first octave tau needs
        (20, "rate: 20 samples at 10 Hz give 3 overlapping Allan deviation point(s) at taus='octave' "
             "(up to 0.4 s); the Q/N/B/K/R fit needs at least 5"),
    ],
)
def test_bad_too_few_samples(tmp_path, capsys, rows, match):
    p = tmp_path / "g.csv"
    p.write_text("rate [deg/s]\n" + "\n".join(f"0.{i}" for i in range(rows)) + "\n")
    code, _, err = run(["allan", p, "--fs", "10"], capsys)
    assert_one_line_error(code, err, match)


def test_bad_nonpositive_fs(capsys, tmp_path):
    code, _, err = run(["simulate", "noise", "--N", "1", "--fs", "0", "--duration", "1s", "-o", tmp_path / "x.h5"],
                       capsys)
    assert_one_line_error(code, err, "--fs must be a finite number > 0; got '0'")
    assert not (tmp_path / "x.h5").exists()


def test_bad_negative_coefficient(capsys, tmp_path, user_files):
    code, _, err = run(["simulate", "noise", "--K", "-0.1", "--duration", "1s", "-o", tmp_path / "x.h5"], capsys)
    assert_one_line_error(code, err, "--K must be a finite number >= 0; got '-0.1'")
    assert user_files.written(tmp_path) == []  # nothing written, not even a temporary file
    # a value argparse would not take for a number ("-1e-3"): refused by the same check, not "expected one argument"
    code, _, err = run(["simulate", "noise", "--N", "-1e-3", "--duration", "1s", "-o", tmp_path / "x.h5"], capsys)
    assert_one_line_error(code, err, "--N must be a finite number >= 0; got '-1e-3'")
    assert user_files.written(tmp_path) == []


def test_bad_allan_fs_zero(tmp_path, capsys):
    p = tmp_path / "g.csv"
    p.write_text("rate [deg/s]\n" + "\n".join(["0.1"] * 100) + "\n")
    code, _, err = run(["allan", p, "--fs", "0"], capsys)
    assert_one_line_error(code, err, "--fs must be a finite number > 0; got '0'")
    code, _, err = run(["allan", p, "--fs", "-5"], capsys)
    assert_one_line_error(code, err, "--fs must be a finite number > 0; got '-5'")


def test_bad_hdf5_with_fs_zero(noise_h5, capsys):
    with h5py.File(noise_h5, "r+") as h5:
        h5["recordings/noise"].attrs["fs"] = 0.0
    code, _, err = run(["allan", noise_h5], capsys)
    assert_one_line_error(code, err, f"{str(noise_h5)!r}: recording 'noise': attribute 'fs' "
                                     "must be in [1e-09, 1e+15] Hz (no gyro samples outside it); got 0.0")


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


def test_bad_unknown_scenario(tmp_path, capsys, user_files):
    code, _, err = run(["reproduce", "nope", "--out", tmp_path], capsys)
    assert_one_line_error(code, err, "scenario must be one of")
    assert user_files.written(tmp_path) == []


def test_bad_config_key(tmp_path, capsys):
    cfg = tmp_path / "c.toml"
    cfg.write_text("nonsense = 3\n")
    code, _, err = run(["simulate", "static_noise", "--out", tmp_path / "o", "--config", cfg], capsys)
    assert_one_line_error(code, err, "has no parameter(s) ['nonsense']")
    assert not (tmp_path / "o").exists()


def test_bad_duration(tmp_path, capsys):
    code, _, err = run(["simulate", "noise", "--N", "1", "--duration", "3 parsecs", "-o", tmp_path / "x.h5"], capsys)
    assert_one_line_error(code, err, "duration must be")


@pytest.mark.parametrize("text", ["-5s", "-5", "-0.5h"])
def test_bad_negative_duration(tmp_path, capsys, text, user_files):
    # before: argparse took "-5s" for an option and said "expected one argument"
    code, _, err = run(["simulate", "noise", "--N", "1", "--duration", text, "-o", tmp_path / "x.h5"], capsys)
    assert_one_line_error(code, err, f"--duration must be > 0 s; got '{text}'")
    code, _, err = run(["simulate", "noise", "--N", "1", f"--duration={text}", "-o", tmp_path / "x.h5"], capsys)
    assert_one_line_error(code, err, f"--duration must be > 0 s; got '{text}'")
    assert user_files.written(tmp_path) == []


def test_bad_too_short_noise_record(tmp_path, capsys, user_files):
    code, _, err = run(["simulate", "noise", "--N", "1", "--duration", "0.1s", "-o", tmp_path / "x.h5"], capsys)
    assert_one_line_error(code, err, "--duration x --fs = 0.1 s x 100 Hz gives 10 samples; a record needs at least 64")
    assert user_files.written(tmp_path) == []


def test_min_samples_is_the_fewest_the_default_fit_takes(tmp_path, capsys):
    # before: the minimum was 33 (2 x 16 + 1), but the default octave taus stop at T/4, so a
    # 33..63-sample record was written and then refused by 'gyrobench allan' (4 taus, not 5)
    rate = np.random.default_rng([20261121, 64]).standard_normal(MIN_SAMPLES)
    assert allan_deviation(rate, 1.0).tau.size == len(TERMS)
    assert allan_deviation(rate[:-1], 1.0).tau.size == len(TERMS) - 1
    p = tmp_path / "x.h5"
    code, _, err = run(["simulate", "noise", "--N", "1", "--duration", f"{MIN_SAMPLES / 100}s", "-o", p, "-q"], capsys)
    assert code == 0, err
    code, _, err = run(["allan", p], capsys)
    assert code == 0, err


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
    r = subprocess.run([str(exe), "simulate", "noise", "--N", "nan", "-o", str(tmp_path / "x.h5")],
                       capture_output=True, text=True)
    assert r.returncode == 2
    assert len(r.stderr.strip().splitlines()) == 1 and "Traceback" not in r.stderr


# ----------------------------------------------------------------------------- flags that belong to the other form
def test_bad_scenario_flags_for_noise(tmp_path, capsys, user_files):
    cfg = tmp_path / "c.toml"
    cfg.write_text("[fog]\nduration_h = 0.05\n")
    code, _, err = run(["simulate", "noise", "--N", "1", "--duration", "60s", "-o", tmp_path / "x.h5",
                        "--config", cfg, "--out", tmp_path / "D"], capsys)
    assert_one_line_error(code, err, "simulate noise: --out, --config apply to 'simulate SCENARIO'")
    assert sorted(p.name for p in user_files.written(tmp_path)) == ["c.toml"]


def test_bad_noise_flags_for_scenario(tmp_path, capsys, user_files):
    code, _, err = run(["simulate", "static_noise", "--fs", "10", "--N", "5", "--out", tmp_path / "D"], capsys)
    assert_one_line_error(code, err, "simulate static_noise: --N, --fs apply to 'simulate noise' only")
    assert user_files.written(tmp_path) == []


# ----------------------------------------------------------------------------- config holes
def test_bad_config_giving_an_empty_record(tmp_path, capsys):
    cfg = tmp_path / "c.toml"
    cfg.write_text("[fog]\nduration_h = 1e-9\n[mems]\nduration_h = 0.05\n")
    code, _, err = run(["simulate", "static_noise", "--out", tmp_path / "o", "--config", cfg], capsys)
    assert_one_line_error(code, err, "GradeSpec.duration_h x fs_hz must give >= 64 samples")
    assert not (tmp_path / "o").exists()  # checked before any file is written


def test_bad_config_negative_coefficient_names_the_config_field(tmp_path, capsys):
    cfg = tmp_path / "c.toml"
    cfg.write_text("[fog]\nN_deg_sqrt_h = -1.0\n")
    code, _, err = run(["simulate", "static_noise", "--out", tmp_path / "o", "--config", cfg], capsys)
    assert_one_line_error(code, err, "Config.fog.N_deg_sqrt_h must be [0, 10000] deg/sqrt(h); got -1.0")
    assert not (tmp_path / "o").exists()


# ----------------------------------------------------------------------------- writing: failures, names, modes, space
_FSIZE_MAIN = r"""
import resource, sys
from gyrobench.scenarios.reports.allan import TERMS
from gyrobench.scenarios.cli.main import main
from gyrobench.scenarios.static_noise import MIN_SAMPLES
resource.setrlimit(resource.RLIMIT_FSIZE, (200_000, 200_000))
sys.exit(main(sys.argv[1:]))
"""


def _visible_lines(err: str) -> list[str]:
    """What a terminal shows, less the progress bar: for each line, the text after the last carriage
    return (tqdm redraws in place), without the bar's own lines (tqdm writes those on a pipe too)."""
    lines = [ln.split("\r")[-1] for ln in err.split("\n")]
    return [ln for ln in lines if ln.strip() and not ln.startswith("simulate:")]


def _assert_error_is_last(err: str, message: str) -> None:
    assert "Traceback" not in err
    assert _visible_lines(err) == [message], err
    assert err.rstrip().splitlines()[-1].split("\r")[-1] == message, err  # nothing redrawn after it


@pytest.mark.parametrize("target", ["noise.h5", "noise.csv", "static_noise"])
@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_failed_write_is_one_line_and_exit_2(tmp_path, target):
    # before: "gyrobench: error: ... '.a.h5.xxxx.tmp' ..." then a segfault (exit 139), or a traceback then 139
    import subprocess
    import sys

    out = tmp_path / "out"
    if target == "static_noise":
        cfg = tmp_path / "c.toml"
        cfg.write_text("[fog]\nduration_h = 0.05\n[mems]\nduration_h = 0.05\n")
        argv = ["simulate", "static_noise", "--out", out, "--config", cfg]
        named = out / "static_noise" / "static_fog.h5"
    else:  # 60 000 samples: 480 kB of HDF5, 2 MB of CSV; progress bar on (no -q, small chunks)
        argv = ["simulate", "noise", "--N", "1", "--fs", "1000", "--duration", "60s", "--chunk", "4096",
                "-o", out / target]
        named = out / target
    r = subprocess.run([sys.executable, "-c", _FSIZE_MAIN, *map(str, argv)], capture_output=True, text=True,
                       timeout=300)
    assert r.returncode == 2, (r.returncode, r.stderr)
    _assert_error_is_last(
        r.stderr,
        f"gyrobench: error: cannot write {str(named)!r}: File too large (file-size limit reached: see 'ulimit -f')",
    )
    # no temporary file left, no half-written output (the folder mark gyrobench writes first is not an output)
    assert [p for p in out.rglob("*") if p.is_file() and p.name != ".gyrobench-folder"] == []


def test_progress_bar_is_closed_on_error(tmp_path, capsys, monkeypatch, user_files):
    # before: the bar stayed open and redrew itself after the error line
    from gyrobench.io.recording import HDF5StreamWriter

    calls = []

    def failing_append(self, **kw):
        calls.append(1)
        if len(calls) == 3:
            raise ValueError("injected failure while streaming")

    monkeypatch.setattr(HDF5StreamWriter, "append", failing_append)
    code, _, err = run(["simulate", "noise", "--N", "1", "--duration", "100s", "--chunk", "1000",
                        "-o", tmp_path / "x.h5"], capsys)
    assert code == 2 and len(calls) == 3
    assert "simulate:" in err  # the bar was on
    _assert_error_is_last(err, "gyrobench: error: injected failure while streaming")
    assert user_files.written(tmp_path) == []


def test_unwritable_output_names_the_output_not_a_temp_file(tmp_path, capsys):
    (tmp_path / "afile").write_text("")
    target = tmp_path / "afile" / "x.h5"  # its folder is a file, as /proc/x.h5 is not writable
    code, _, err = run(["simulate", "noise", "--N", "1", "--duration", "10s", "-o", target], capsys)
    assert_one_line_error(code, err, f"cannot write {str(target)!r}")
    assert ".tmp" not in err


def test_output_mode_follows_umask(tmp_path, capsys):
    import os

    old = os.umask(0o022)
    try:
        code, _, _ = run(["simulate", "noise", "--N", "1", "--duration", "10s", "-o", tmp_path / "x.h5", "-q"], capsys)
    finally:
        os.umask(old)
    assert code == 0
    assert (tmp_path / "x.h5").stat().st_mode & 0o777 == 0o644  # before: 0600 whatever the umask


def test_record_larger_than_free_space_is_refused(tmp_path, capsys, monkeypatch, user_files):
    import shutil

    monkeypatch.setattr(shutil, "disk_usage", lambda p: shutil._ntuple_diskusage(10**12, 10**12 - 10**6, 10**6))
    code, _, err = run(["simulate", "noise", "--N", "1", "--fs", "1000", "--duration", "1h",
                        "-o", tmp_path / "x.h5"], capsys)
    assert_one_line_error(code, err, "the record needs about 86.4 MB but")
    assert "has 1 MB free" in err
    assert user_files.written(tmp_path) == []


def test_noise_record_states_its_truth(noise_h5):
    rec = load_hdf5(noise_h5)
    terms = rec.metadata["error_components"]
    assert terms == ["quantization", "angle_random_walk", "bias_instability"]  # those of the flags given
    assert sorted(rec.truth) == sorted(["true_rate", *terms])
    assert not np.any(rec["truth/true_rate"])  # a static record
    total = np.zeros(rec.n_samples)
    for k in terms:  # summed in the generator's order: the output's own bits
        total += rec[f"truth/{k}"]
    np.testing.assert_array_equal(total, rec["output"])
    si = rec.metadata["noise_model_si"]
    assert si["angle_random_walk_rad_per_sqrt_s"] == pytest.approx(units.deg_per_sqrt_h(0.5), rel=1e-15)
    assert si["bias_instability_rad_per_s"] == pytest.approx(units.deg_per_h(2.0), rel=1e-15)
    assert si["quantization_rad"] == pytest.approx(units.arcsec(1.0), rel=1e-15)
    assert si["rate_random_walk_rad_per_s_sqrt_s"] == 0.0 and si["rate_ramp_rad_per_s2"] == 0.0


# ----------------------------------------------------------------------------- constant data
def test_bad_constant_data(tmp_path, capsys):
    p = tmp_path / "g.csv"
    p.write_text("rate [deg/s]\n" + "\n".join(["0.1"] * 1000) + "\n")
    code, _, err = run(["allan", p, "--fs", "10"], capsys)
    assert_one_line_error(code, err, "rate is constant (zero variance): Allan deviation is 0 at every tau")


# ----------------------------------------------------------------------------- allan --bandwidth
@pytest.fixture
def lowpassed_csv(tmp_path):
    """20 min at 100 Hz of white rate noise behind a first-order 2 Hz low-pass (no time column)."""
    from scipy import signal

    a = np.exp(-2 * np.pi * 2.0 / 100.0)
    y = signal.lfilter([1 - a], [1, -a], 0.01 * np.random.default_rng(5).standard_normal(120_000))
    p = tmp_path / "lp.csv"
    p.write_text("rate [rad/s]\n" + "\n".join(f"{v:.9e}" for v in y) + "\n")
    return p


def test_allan_bandwidth_sets_the_fit_range_and_says_so(lowpassed_csv, capsys):
    from gyrobench.analysis.allan import bandwidth_range

    # (20 min: the rule keeps tau >= 20 s, 4 octaves, so fit the white level alone)
    args = ["allan", lowpassed_csv, "--fs", "100", "--terms", "N", "--bandwidth", "2"]
    code, out, _ = run([*args, "--json"], capsys)
    assert code == 0
    d = json.loads(out)
    assert d["fit"]["tau_min_rule"] == "bandwidth"
    assert "stated bandwidth 2 Hz" in d["fit"]["tau_min_reason"]
    rate = np.loadtxt(lowpassed_csv, skiprows=1)
    want = bandwidth_range(allan_deviation(rate, 100.0), 2.0).tau_min
    assert d["fit"]["tau_used"][0] == pytest.approx(want)
    code, out, _ = run(args, capsys)
    assert code == 0
    assert "11 short tau(s) excluded (11 by --bandwidth: a first-order low-pass at the stated bandwidth 2 Hz" in out
    # a --tau-min above the bandwidth's limit wins, and the output says the user's limit set it
    code, out, _ = run([*args, "--tau-min", str(4 * want), "--json"], capsys)
    assert code == 0 and json.loads(out)["fit"]["tau_min_rule"] == "user"
    # a looser fraction starts earlier
    code, out, _ = run([*args, "--bandwidth-bias", "0.5", "--json"], capsys)
    assert code == 0 and json.loads(out)["fit"]["tau_used"][0] < want


@pytest.mark.parametrize(
    ("value", "match"),
    [
        ("0", "--bandwidth must be a finite number > 0; got '0'"),
        ("-2", "--bandwidth must be a finite number > 0; got '-2'"),
        ("50", "--bandwidth must be < the Nyquist frequency fs/2 = 50 Hz of lp.csv (sampled at 100 Hz); got 50 Hz"),
        ("75", "--bandwidth must be < the Nyquist frequency fs/2 = 50 Hz"),
    ],
)
def test_bad_allan_bandwidth(lowpassed_csv, capsys, value, match):
    code, _, err = run(["allan", lowpassed_csv, "--fs", "100", "--bandwidth", value], capsys)
    assert_one_line_error(code, err, match)


def test_bad_allan_bandwidth_bias_without_bandwidth(lowpassed_csv, capsys):
    code, _, err = run(["allan", lowpassed_csv, "--fs", "100", "--bandwidth-bias", "0.2"], capsys)
    assert_one_line_error(code, err, "--bandwidth-bias applies with --bandwidth HZ")
    code, _, err = run(["allan", lowpassed_csv, "--fs", "100", "--bandwidth", "2", "--bandwidth-bias", "0"], capsys)
    assert_one_line_error(code, err, "--bandwidth-bias must be a finite number > 0; got '0'")


def test_cli_edge_copies_of_analysis_constants_agree():
    """The CLI-side copies (kept so parsing imports no analysis) equal the analysis values."""
    import inspect

    from gyrobench.analysis import allan
    from gyrobench.base import units
    from gyrobench.io import logs
    from gyrobench.scenarios.cli.main import build_parser
    from gyrobench.scenarios.reports import allan as allan_report

    assert allan_report.FIT_KINDS == allan._FIT_KINDS
    assert inspect.signature(allan_report.analyse).parameters["bandwidth_bias"].default == (
        allan.BANDWIDTH_BIAS
    )
    sub = next(a for a in build_parser()._actions if a.__class__.__name__ == "_SubParsersAction")
    bw = next(a for a in sub.choices["allan"]._actions if "--bandwidth-bias" in a.option_strings)
    assert bw.default == allan.BANDWIDTH_BIAS
    assert logs.ACCEL_UNITS["g"] == units.G0 and logs.TIME_UNITS["h"] == units.HOUR


@pytest.mark.parametrize("suffix", [".h5", ".csv"])
def test_simulate_noise_too_big_for_the_disk_is_one_line_before_any_progress(tmp_path, capsys, suffix, user_files):
    """Found by the random flag fuzzer: an HDF5 record larger than the free disk was refused by the
    stream writer after the progress bar had drawn (three lines on stderr); the disk is now checked
    first, for both formats."""
    import shutil

    free = shutil.disk_usage(tmp_path).free
    seconds = 2 * free / 8 / 10  # at 10 Hz, twice the free bytes at 8 bytes a sample
    code = main(["simulate", "noise", "--N", "0.1", "--fs", "10", "--duration", f"{seconds:.0f}s",
                 "-o", str(tmp_path / f"o{suffix}")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "free" in err[0], err
    assert user_files.written(tmp_path) == []


def test_a_closed_output_pipe_ends_quietly_with_141(monkeypatch, capsys):
    """``gyrobench parts | head -1``: the reader leaves, the next write raises BrokenPipeError; the verb
    stops with 141 (128 + SIGPIPE, as a shell reports it) and prints nothing (it printed
    'gyrobench: error: [Errno 32] Broken pipe' and exited 2)."""
    import io

    class ClosedPipe(io.StringIO):
        def write(self, text):
            raise BrokenPipeError(32, "Broken pipe")

    monkeypatch.setattr("sys.stdout", ClosedPipe())
    assert main(["parts"]) == 141
    assert capsys.readouterr().err == ""


def test_help_lists_every_exit_status():
    # the epilog is built from gyrobench.scenarios.exits: a new code shows up in --help (5, allan's
    # non-stationary verdict, was missing from the hand-written list)
    from gyrobench.scenarios.cli import exits
    from gyrobench.scenarios.cli.main import build_parser

    epilog = " ".join(build_parser().epilog.split())
    codes = [getattr(exits, n) for n in exits.__all__ if isinstance(getattr(exits, n), int)]
    assert len(codes) >= 9
    for code in codes:
        assert f" {code} " in f" {epilog} ", code
