"""``gyrobench allan`` on CSV from a real gyro: headers, time columns, gaps, too few rows."""

import json
import warnings

import numpy as np
import pytest

from gyrobench.analysis.allan import allan_deviation, fit_noise
from gyrobench.scenarios.cli import _read_csv
from gyrobench.sim import units
from tests.scenarios.test_cli import assert_one_line_error, run


@pytest.fixture
def rate(rng):
    return rng.standard_normal(3000)


def test_headerless_single_column_needs_no_column(tmp_path, capsys, rate):
    p = tmp_path / "g.csv"
    np.savetxt(p, rate)
    code, out, err = run(["allan", p, "--fs", "50", "--units", "deg/h", "--json"], capsys)
    assert code == 0, err
    c = fit_noise(allan_deviation(units.deg_per_h(rate), 50.0)).coefficients["N"]
    assert json.loads(out)["N"]["value"] == pytest.approx(units.coefficient_to_field("N", c.value), rel=1e-12)


def test_headerless_without_fs_says_give_fs(tmp_path, capsys, rate):
    p = tmp_path / "g.csv"
    np.savetxt(p, rate)
    code, _, err = run(["allan", p, "--units", "deg/h"], capsys)
    assert_one_line_error(code, err, "has no time column (a header such as 'time [s]'): give --fs")


def test_headerless_several_columns_need_column(tmp_path, capsys, rate):
    p = tmp_path / "g.csv"
    np.savetxt(p, np.column_stack([rate, rate]), delimiter=",")
    code, _, err = run(["allan", p, "--fs", "50", "--units", "deg/h"], capsys)
    assert_one_line_error(code, err, "has 2 data columns: name the rate column with --column "
                                     "(columns: 2 unnamed columns, no header: give an index 0..1)")
    code, _, err = run(["allan", p, "--fs", "50", "--units", "deg/h", "--column", "2"], capsys)
    assert_one_line_error(code, err, "--column 2 is out of range")


@pytest.mark.parametrize(
    ("time_header", "scale"),
    [("time [s]", 1.0), ("Time (s)", 1.0), ("TIME [ms]", 1e3), ("t_s", 1.0), ("timestamp", 1.0),
     ("Timestamp (ms)", 1e3), ("t", 1.0), ("time_ms", 1e3)],
)
def test_time_headers_are_recognised(tmp_path, rate, time_header, scale):
    p = tmp_path / "g.csv"
    t = np.arange(len(rate)) / 50.0 * scale
    np.savetxt(p, np.column_stack([t, rate]), delimiter=",", header=f"{time_header},gyro (deg/h)", comments="")
    got, fs, label = _read_csv(p, None, None, None)  # no --column, no --fs, no --units
    assert fs == pytest.approx(50.0, rel=1e-9)
    assert label == "gyro"
    np.testing.assert_allclose(got, units.deg_per_h(rate), rtol=1e-15)


def test_time_gap_is_refused_naming_the_row(tmp_path, capsys, rate):
    p = tmp_path / "g.csv"
    t = np.arange(len(rate)) / 50.0
    t[1000:] += 0.5  # a 0.52 s step among 0.02 s ones: 26 samples missing
    np.savetxt(p, np.column_stack([t, rate]), delimiter=",", header="time [s],gyro [deg/h]", comments="")
    code, _, err = run(["allan", p], capsys)
    assert_one_line_error(code, err, "time column 'time [s]' of")
    assert "has a gap before data row 1001: step 0.52 (19.98 -> 20.5) is 26 x the median step 0.02" in err
    assert "Allan analysis needs uniform sampling" in err
    # also when --fs is given: the data are still not uniformly sampled
    code, _, err = run(["allan", p, "--fs", "50"], capsys)
    assert_one_line_error(code, err, "has a gap before data row 1001")


def test_small_jitter_is_not_a_gap(tmp_path, rate):
    p = tmp_path / "g.csv"
    t = np.arange(len(rate)) / 50.0 + np.random.default_rng([20261121, 5]).uniform(-0.004, 0.004, len(rate))
    np.savetxt(p, np.column_stack([t, rate]), delimiter=",", header="time [s],gyro [deg/h]", comments="")
    _, fs, _ = _read_csv(p, None, None, None)
    assert fs == pytest.approx(50.0, rel=0.01)


def test_time_not_increasing_is_refused_naming_the_row(tmp_path, capsys):
    p = tmp_path / "g.csv"
    p.write_text("time [s],gyro [deg/h]\n0,1\n0.1,2\n0.1,3\n0.3,4\n")
    code, _, err = run(["allan", p], capsys)
    assert_one_line_error(code, err, "must increase strictly: data row 3 has 0.1 after 0.1 in row 2")


@pytest.mark.parametrize(("body", "rows"), [("", 0), ("0.1\n", 1)])
def test_empty_or_one_row_csv(tmp_path, capsys, body, rows):
    # before: numpy's "input contained no data" warning, then an Allan error about samples
    p = tmp_path / "g.csv"
    p.write_text("rate [deg/s]\n" + body)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        code, _, err = run(["allan", p, "--fs", "10"], capsys)
    assert_one_line_error(code, err, f"CSV {str(p)!r} has {rows} data row{'s' if rows != 1 else ''}; need at least 2")


def test_csv_with_no_lines_at_all(tmp_path, capsys):
    p = tmp_path / "g.csv"
    p.write_text("# only a comment\n")
    code, _, err = run(["allan", p, "--fs", "10"], capsys)
    assert_one_line_error(code, err, "has 0 data rows; need at least 2")


def test_time_column_without_time_unit_needs_fs(tmp_path, capsys, rate):
    p = tmp_path / "g.csv"
    np.savetxt(p, np.column_stack([np.arange(len(rate)), rate]), delimiter=",", header="time [UTC],gyro [deg/h]",
               comments="")
    code, _, err = run(["allan", p], capsys)
    assert_one_line_error(code, err, "the time column 'time [UTC]' of")
    assert "has no time unit" in err and "give --fs" in err
