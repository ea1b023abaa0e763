"""``gyrobench allan`` on CSV from a real gyro: headers, time columns, gaps, too few rows."""

import json
import math
import warnings

import numpy as np
import pytest

from gyrobench.analysis.allan import allan_deviation, fit_noise
from gyrobench.base import units
from gyrobench.scenarios.cli.allan import read_csv as _read_csv
from tests.scenarios.test_cli import assert_one_line_error, run

# every test runs among planted user files and fails if one changes (tests/conftest.py)
pytestmark = pytest.mark.usefixtures("user_files")


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


# ----------------------------------------------------------------------------- real log formats (issue 14)
FS = 100.0


def _log_rows(rng, n=4000):
    return rng.standard_normal((n, 6)) * np.array([1e-3, 1e-3, 1e-3, 1e-2, 1e-2, 1e-2])


def test_euroc_header_ns_timestamps_and_all_axes(tmp_path, capsys, rng):
    data = _log_rows(rng)
    t = 1403636579758555392 + np.arange(len(data)) * 5_000_000  # EuRoC: epoch ns, 200 Hz
    p = tmp_path / "data.csv"
    head = ("#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
            "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n")
    p.write_text(head + "\n".join(f"{ti}," + ",".join(f"{v:.9g}" for v in row)
                                  for ti, row in zip(t, data, strict=True)) + "\n")
    from gyrobench.io.logs import read_csv_log

    log = read_csv_log(p, None, None, None, all_axes=True)
    assert log.fs == pytest.approx(200.0, rel=1e-12) and log.fmt == "euroc"
    assert [c.label for c in log.channels] == ["w_RS_S_x", "w_RS_S_y", "w_RS_S_z", "a_RS_S_x", "a_RS_S_y", "a_RS_S_z"]
    assert [c.quantity for c in log.channels] == ["rate"] * 3 + ["accel"] * 3
    np.testing.assert_allclose(log.channels[4].data, data[:, 4], rtol=1e-8)
    code, out, err = run(["allan", p, "--all-axes", "--json"], capsys)
    assert code == 0, err
    doc = json.loads(out)
    assert [c["channel"] for c in doc["channels"]] == [c.label for c in log.channels]
    assert doc["channels"][3]["fit"]["terms"]["N"]["unit"] == "m/s/sqrt(h)"


def test_kalibr_and_ros_exports(tmp_path, rng):
    from gyrobench.io.logs import read_csv_log

    data = _log_rows(rng)
    t = 1_600_000_000_000_000_000 + np.arange(len(data)) * 10_000_000
    k = tmp_path / "imu0.csv"
    k.write_text("timestamp,omega_x,omega_y,omega_z,alpha_x,alpha_y,alpha_z\n"
                 + "\n".join(f"{ti}," + ",".join(f"{v:.17g}" for v in row)
                              for ti, row in zip(t, data, strict=True)) + "\n")
    log = read_csv_log(k, ["omega_y", "alpha_z"], None, None)
    assert log.fmt == "kalibr" and log.fs == pytest.approx(FS, rel=1e-12)
    assert [(c.quantity, c.unit) for c in log.channels] == [("rate", "rad/s"), ("accel", "m/s^2")]
    assert any("epoch" in n and "ns" in n for n in log.notes)  # no unit in the header: said how it was read
    np.testing.assert_array_equal(log.channels[0].data, data[:, 1])
    r = tmp_path / "ros.csv"
    cols = ["%time", "field.header.seq", "field.angular_velocity.x", "field.angular_velocity.y",
            "field.angular_velocity.z", "field.linear_acceleration.x"]
    r.write_text(",".join(cols) + "\n" + "\n".join(
        f"{ti},{i}," + ",".join(f"{v:.17g}" for v in row[:4])
        for i, (ti, row) in enumerate(zip(t, data, strict=True))) + "\n")
    log = read_csv_log(r, None, None, None, all_axes=True)
    assert log.fmt == "ros" and log.fs == pytest.approx(FS, rel=1e-12)
    assert [c.label for c in log.channels] == cols[2:]


@pytest.mark.parametrize(("unit", "scale"), [("s", 1.0), ("ms", 1e3), ("us", 1e6), ("ns", 1e9)])
def test_time_units_from_the_header(tmp_path, rng, unit, scale):
    from gyrobench.io.logs import read_csv_log

    rate = rng.standard_normal(500)
    p = tmp_path / "g.csv"
    t = np.arange(rate.size) * (scale / FS)
    np.savetxt(p, np.column_stack([t, rate]), delimiter=",", header=f"time [{unit}],gyro [deg/s]", comments="")
    assert read_csv_log(p, None, None, None).fs == pytest.approx(FS, rel=1e-9)


def test_epoch_ns_without_unit_is_not_read_as_seconds(tmp_path, capsys, rng):
    rate = rng.standard_normal(4000) * 0.1
    p = tmp_path / "g.csv"
    t = 1_700_000_000_000_000_000 + np.arange(rate.size) * 10_000_000
    p.write_text("timestamp,gyro [deg/s]\n" + "\n".join(f"{ti},{v:.17g}" for ti, v in zip(t, rate, strict=True)) + "\n")
    code, out, err = run(["allan", p], capsys)
    assert code == 0, err
    assert "100 Hz" in out and "Unix epoch times in ns" in out


@pytest.mark.parametrize(
    ("sep", "bom", "quote"),
    [(",", True, False), (";", False, False), ("\t", False, False), (",", False, True), (";", True, True)],
)
def test_bom_quotes_and_separators(tmp_path, rng, sep, bom, quote):
    from gyrobench.io.logs import read_csv_log

    rate = rng.standard_normal(300)
    q = '"' if quote else ""
    text = sep.join([f"{q}time [s]{q}", f"{q}gyro [deg/h]{q}"]) + "\n"
    text += "\n".join(f"{i / FS!r}{sep}{v:.17g}" for i, v in enumerate(rate)) + "\n"
    p = tmp_path / "g.csv"
    p.write_bytes((b"\xef\xbb\xbf" if bom else b"") + text.encode())
    log = read_csv_log(p, None, None, None)
    assert log.channels[0].label == "gyro" and log.fs == pytest.approx(FS, rel=1e-9)
    np.testing.assert_allclose(log.channels[0].data, units.deg_per_h(rate), rtol=1e-15)


def test_extra_column_row_is_refused_naming_the_line(tmp_path, capsys):
    p = tmp_path / "g.csv"
    p.write_text("# note\ntime [s],gyro [deg/s]\n0,1\n0.1,2\n0.2,3,4\n0.3,5\n")
    code, _, err = run(["allan", p], capsys)
    assert_one_line_error(code, err, f"{str(p)!r} line 5: 3 cells where the file has 2; a row with an extra column")


def test_non_number_names_file_line_and_column(tmp_path, capsys):
    p = tmp_path / "g.csv"
    p.write_text("time [s],gyro [deg/s]\n0,1\n0.1,abc\n0.2,3\n")
    code, _, err = run(["allan", p], capsys)
    assert_one_line_error(code, err, f"{str(p)!r} line 3, column 'gyro': 'abc' is not a number")
    assert "could not convert" not in err


def test_truncated_gzip_and_undecodable_bytes(tmp_path, capsys, rate):
    import gzip

    good = tmp_path / "g.csv.gz"
    with gzip.open(good, "wt") as fh:
        fh.write("rate [deg/s]\n" + "\n".join(f"{v:.17g}" for v in rate) + "\n")
    bad = tmp_path / "t.csv.gz"
    bad.write_bytes(good.read_bytes()[:-30])
    code, _, err = run(["allan", bad, "--fs", "10"], capsys)
    assert_one_line_error(code, err, f"{str(bad)!r} is not a complete gzip file")
    raw = tmp_path / "latin.csv"
    raw.write_bytes(b"rate [deg/s]\n0.1\n0.2\n" + b"\xb5\xff\n0.3\n")
    code, _, err = run(["allan", raw, "--fs", "10"], capsys)
    assert_one_line_error(code, err, f"{str(raw)!r} line 4: byte b'\\xb5' is not UTF-8 text")


def test_repeated_column_gives_one_table(tmp_path, capsys, rng):
    data = rng.standard_normal((4000, 2))
    p = tmp_path / "g.csv"
    np.savetxt(p, data, delimiter=",", header="gx [deg/s],gy [deg/s]", comments="")
    code, out, err = run(["allan", p, "--fs", "50", "--column", "gx", "--column", "gy"], capsys)
    assert code == 0, err
    rows = [ln for ln in out.splitlines() if ln.startswith(("gx ", "gy "))]
    assert len(rows) == 10  # five terms of each channel, one table
    code, _, err = run(["allan", p, "--fs", "50", "--column", "gx", "--column", "0"], capsys)
    assert_one_line_error(code, err, "--column names column 0 of")


def test_start_stop_segment(tmp_path, rng):
    from gyrobench.io.logs import read_csv_log

    rate = rng.standard_normal(1000)
    p = tmp_path / "g.csv"
    np.savetxt(p, rate, header="gyro [deg/s]", comments="")
    log = read_csv_log(p, None, 10.0, None, start=10.0, stop=50.0)
    np.testing.assert_array_equal(log.channels[0].data, units.deg_per_s(rate[100:500]))
    assert any("segment 10 s to 50 s" in n for n in log.notes)
    with pytest.raises(ValueError, match="--start/--stop keep 0 samples"):
        read_csv_log(p, None, 10.0, None, start=200.0)


def test_misfit_is_said_first_and_fit_options(tmp_path, capsys, rng):
    from scipy import signal

    y = signal.sosfilt(signal.butter(4, 5.0, fs=FS, output="sos"), rng.standard_normal(200_000))
    p = tmp_path / "g.csv"
    np.savetxt(p, y, header="gyro [deg/s]", comments="", fmt="%.9g")
    code, out, err = run(["allan", p, "--fs", "100", "--tau-min", "0.01"], capsys)  # the whole curve
    assert code == 0, err
    assert out.splitlines()[0].startswith("MISFIT gyro: ")
    code, out, err = run(["allan", p, "--fs", "100", "--json", "--terms", "N,K", "--tau-max", "100"], capsys)
    assert code == 0, err
    fit = json.loads(out)["fit"]
    assert set(fit["terms"]) == {"N", "K"} and fit["tau_used"][0] > 0.01 and fit["tau_used"][-1] <= 100
    assert {"chi2", "dof", "p_value", "misfit", "chi2_per_dof"} <= set(fit)
    code, _, err = run(["allan", p, "--fs", "100", "--terms", "N,X"], capsys)
    assert code == 2 and "--terms must be distinct names from Q,N,B,K,R" in err


def test_other_kinds_export_the_curve_without_a_fit(tmp_path, capsys, rate):
    p = tmp_path / "g.csv"
    np.savetxt(p, rate, header="gyro [deg/s]", comments="")
    code, out, err = run(["allan", p, "--fs", "10", "--kind", "modified", "--json"], capsys)
    assert code == 0, err
    doc = json.loads(out)
    assert doc["fit"] is None and "no noise fit for the modified deviation" in doc["no_fit"]
    c = allan_deviation(units.deg_per_s(rate), 10.0, kind="modified")
    np.testing.assert_allclose(doc["curve"]["deviation"], c.deviation, rtol=1e-12)
    assert doc["adev_floor"]["value"] == pytest.approx(float(c.deviation.min()), rel=1e-12)


def test_all_taus_too_large_is_one_line(tmp_path, capsys):
    p = tmp_path / "g.csv"
    p.write_text("gyro [deg/s]\n" + "0.1\n0.2\n" * 200_001)
    code, _, err = run(["allan", p, "--fs", "100", "--taus", "all"], capsys)
    assert_one_line_error(code, err, "taus='all' on 400002 samples means 100000 taus")


def test_temperature_column_and_step_warning(tmp_path, capsys, rng):
    n = 100_000
    t = np.arange(n) / FS
    temp = 25 + 10 * np.sin(2 * np.pi * t / 500.0)
    y = 0.01 * rng.standard_normal(n) + 0.002 * (temp - 25)  # deg/s
    p = tmp_path / "g.csv"
    np.savetxt(p, np.column_stack([t, y, temp]), delimiter=",", header="time [s],gyro [deg/s],temp [degC]",
               comments="", fmt="%.9g")
    code, out, err = run(["allan", p, "--column", "gyro", "--temperature", "temp", "--json"], capsys)
    assert code == 0, err
    tc = json.loads(out)["temperature"]
    # white residuals here, so se_T is the estimate's standard error: z at two-sided 1e-6
    from scipy.stats import norm

    assert abs(tc["c_T"] - units.deg_per_s(0.002)) <= norm.isf(0.5e-6) * tc["se_T"]
    assert tc["c_T_unit"] == "rad/s/degC"
    y[60_000:] += 0.05  # a step at 600 s
    np.savetxt(p, np.column_stack([t, y]), delimiter=",", header="time [s],gyro [deg/s]", comments="", fmt="%.9g")
    code, out, err = run(["allan", p], capsys)
    assert code == 5, err  # exits.NONSTATIONARY: the step is its own diagnosis (issue 30)
    lines = out.splitlines()
    assert lines[0].startswith("NONSTATIONARY gyro: "), out
    assert any(ln.startswith("WARNING gyro: ") and "step(s)" in ln for ln in lines[:4]), out
    kalibr = tmp_path / "imu.yaml"
    code, out, err = run(["allan", p, "--json", "--accept-nonstationary", "--kalibr", kalibr], capsys)
    assert code == 0, err
    doc = json.loads(out)
    # the record has a step; the fit is of the quiet stretches either side, which do not
    assert doc["nonstationary"] is True and doc["fit"]["nonstationary"] is False and doc["basis"] == "quiet stretches"
    assert "# not stationary as a whole; fitted from the quiet stretches: gyro" in kalibr.read_text()


def test_quiet_record_is_not_flagged_nonstationary(tmp_path, capsys, rng):
    """White noise only: no motion or step flag, exit 0, nonstationary false in the fit."""
    n = 100_000
    p = tmp_path / "g.csv"
    np.savetxt(p, np.column_stack([np.arange(n) / FS, 0.01 * rng.standard_normal(n)]), delimiter=",",
               header="time [s],gyro [deg/s]", comments="", fmt="%.9g")
    code, out, err = run(["allan", p, "--json"], capsys)
    assert code == 0, err
    doc = json.loads(out)
    assert doc["nonstationary"] is False and doc["fit"]["nonstationary"] is False


def test_kalibr_yaml_holds_n_and_k_in_si(tmp_path, capsys, rng):
    n = 200_000
    data = np.column_stack([np.arange(n) * 10_000_000,  # ns
                            1e-3 * 10 * rng.standard_normal((n, 2)),  # gyro N = 1e-3 rad/sqrt(s) at 100 Hz
                            2e-2 * 10 * rng.standard_normal((n, 1))])  # accel N = 2e-2 m/s/sqrt(s)
    p = tmp_path / "imu0.csv"
    np.savetxt(p, data, delimiter=",", header="timestamp,omega_x,omega_y,alpha_x", comments="",
               fmt=["%d", "%.9g", "%.9g", "%.9g"])
    out_yaml = tmp_path / "imu.yaml"
    code, out, err = run(["allan", p, "--all-axes", "--kalibr", out_yaml, "--json"], capsys)
    assert code == 0, err
    doc = json.loads(out)
    got = dict(ln.split(":", 1) for ln in out_yaml.read_text().splitlines() if ln and not ln.startswith("#"))
    val = {k: float(v.split("#")[0]) for k, v in got.items()}
    assert val["update_rate"] == 100.0
    gyro_n = max(units.deg_per_sqrt_h(c["fit"]["terms"]["N"]["value"]) for c in doc["channels"][:2])
    assert val["gyroscope_noise_density"] == pytest.approx(gyro_n, rel=1e-5)  # 6 printed digits
    assert val["accelerometer_noise_density"] == pytest.approx(doc["channels"][2]["fit"]["terms"]["N"]["value"] / 60,
                                                                rel=1e-5)
    assert {"gyroscope_random_walk", "accelerometer_random_walk"} <= set(val)
    code, _, err = run(["allan", p, "--all-axes", "--kalibr", tmp_path / "nope" / "imu.yaml"], capsys)
    assert_one_line_error(code, err, "--kalibr must be in an existing folder")


def test_allan_figure_has_band_model_bounds_shading_and_residuals(rng):
    from gyrobench.analysis.allan import fit_noise as fit_
    from gyrobench.scenarios.reports.figures import allan_figure

    c = allan_deviation(units.deg_per_s(0.01 * rng.standard_normal(100_000)), 100.0)
    fit = fit_(c, tau_min=0.04)
    fig = allan_figure(c, fit, title="f.csv: gyro, 100 Hz, 0.278 h")
    ax, axr = fig.axes
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "95% confidence" in labels and any(t.startswith("fitted model") for t in labels)
    assert any(t.startswith("N = ") for t in labels) and any(" < " in t and "(95 %)" in t for t in labels)
    assert len(ax.patches) >= 1  # the not-fitted taus (0.01, 0.02 s) shaded
    assert axr.get_ylabel() == "(AVAR - fit) / sd" and ax.get_title().startswith("f.csv: gyro")


def test_plot_writes_every_channel_with_its_warnings(tmp_path, capsys, rng):
    """--plot with several channels: one figure per channel (issue 30 item 6), warnings in the title."""
    n = 20_000
    y = 0.01 * rng.standard_normal((n, 2))
    y[12_000:, 1] += 0.05  # a step in the second channel only
    p = tmp_path / "g.csv"
    np.savetxt(p, np.column_stack([np.arange(n) / FS, y]), delimiter=",",
               header="time [s],gx [deg/s],gy [deg/s]", comments="", fmt="%.9g")
    png = tmp_path / "adev.png"
    code, out, err = run(["allan", p, "--column", "gx", "--column", "gy", "--plot", png], capsys)
    assert code == 5, err  # the step: exits.NONSTATIONARY
    for name in ("adev_gx.png", "adev_gy.png"):
        assert (tmp_path / name).stat().st_size > 0 and f"wrote {tmp_path / name}" in out
    assert not png.exists()
    from gyrobench.io.logs import read_csv_log
    from gyrobench.scenarios.reports import allan as rep
    from gyrobench.scenarios.reports import allan_text as txt

    log = read_csv_log(p, ["gy"], None, None)
    res = rep.analyse(log.channels[0], log.fs)
    title = txt.plot_title(log, res)
    assert "NOT STATIONARY" in title and "step(s)" in title, title


def test_segments_auto_fits_the_quiet_stretches_around_a_step(tmp_path, capsys, rng):
    """--segments auto: a step at 600 s of a 1000 s white-noise record; the two stretches are fitted alone.

    Each stretch is white noise of N = 0.01 deg/s / sqrt(100 Hz) = 1e-3 deg/sqrt(s) (0.06 deg/sqrt(h)):
    its N must lie within z se of it, se half the 68 % interval, z for two-sided false alarm
    1e-6 over the two stretches. The check fails if a stretch spans the step (the step would
    enter as a random walk and bias N) or if none is fitted.
    """
    from statistics import NormalDist

    n = 100_000
    y = 0.01 * rng.standard_normal(n)
    y[60_000:] += 0.05
    p = tmp_path / "g.csv"
    np.savetxt(p, np.column_stack([np.arange(n) / FS, y]), delimiter=",", header="time [s],gyro [deg/s]",
               comments="", fmt="%.9g")
    code, out, err = run(["allan", p, "--segments", "auto", "--json", "--terms", "N,B"], capsys)
    assert code == 5, err
    segs = json.loads(out)["segments"]
    assert len(segs) == 2 and segs[0]["stop_s"] <= 600.0 <= segs[1]["start_s"], segs
    n_true = 0.01 / math.sqrt(FS) * 60.0  # deg/sqrt(h)
    z = NormalDist().inv_cdf(1.0 - 1e-6 / 2.0 / len(segs))
    for s in segs:
        t = s["fit"]["terms"]["N"]
        se = (t["high68"] - t["low68"]) / 2.0
        assert abs(t["value"] - n_true) <= z * se, (s, n_true)
    code, out, err = run(["allan", p, "--segments", "auto", "--terms", "N,B"], capsys)
    assert any(ln.startswith("SEGMENTS gyro: 2 quiet stretch(es)") for ln in out.splitlines()), out


def test_quiet_stretches_split_at_motion_and_steps():
    from gyrobench.analysis.stationarity import StationarityReport, quiet_stretches

    rep = StationarityReport(window=1.0, motion=[(40.0, 41.0, 9.0)], steps=[(100.0, 7.0)])
    # windows 0-39 | 40 moving | 41-99 | step before 100 | 100-149 (150 windows of 10 samples)
    assert quiet_stretches(rep, 1505, 10.0) == [(0, 400), (410, 1000), (1000, 1500)]
    assert quiet_stretches(rep, 1505, 10.0, min_windows=55) == [(410, 1000)]
    with pytest.raises(ValueError, match=r"min_windows must be an integer >= 4; got 2"):
        quiet_stretches(rep, 1505, 10.0, min_windows=2)


def _handled_1hz_record(seed: int) -> np.ndarray:
    """27.8 h at 1 Hz: white noise 0.01 rad/s and, every 7000 s, 60-400 s of handling (a 20-sample moving
    average of 2 rad/s white noise, dominating the curve from 1 s) followed by a re-mounting bias step."""
    rng = np.random.default_rng(seed)
    n = 100_000
    y = 0.01 * rng.standard_normal(n)
    for start in range(3000, n - 2000, 7000):
        length = int(rng.integers(60, 400))
        y[start : start + length] += 2.0 * np.convolve(rng.standard_normal(length + 19), np.ones(20) / 20, "valid")
        y[start + length :] += rng.normal(0.0, 0.02)
    return y


def test_short_taus_of_a_moving_record_are_fitted_not_dropped_as_filter_shaped(rng):
    """Issue 30 item 1: a 1 Hz record with handling bends down at short tau like a filtered one; flagged
    non-stationary, its short taus stay in the fit (whose misfit then shows, p < 1e-6) and the report says
    which rule applied. A filtered quiet record still has its first octaves dropped as filter-shaped."""
    from gyrobench.analysis.allan import allan_deviation, fit_range
    from gyrobench.io.logs import Channel
    from gyrobench.scenarios.reports import allan as rep
    from gyrobench.scenarios.reports import allan_text as txt

    n = 200_000
    y = 0.01 * np.convolve(rng.standard_normal(n + 15), np.ones(16) / 16, mode="valid")  # a 16-sample filter
    res = rep.analyse(Channel(label="gyro", quantity="rate", data=y, unit="rad/s"), 100.0)
    assert not res.nonstationary
    assert res.fit.range_rule == "data" and res.fit_range.excluded > 0
    assert "filter-shaped" in txt._excluded_text(res, res.fit_range.excluded)

    y = _handled_1hz_record(48)
    assert fit_range(allan_deviation(y, 1.0)).excluded >= 3  # the unflagged rule drops the motion's octaves
    res = rep.analyse(Channel(label="gyro", quantity="rate", data=y, unit="rad/s"), 1.0)
    # by default the quiet stretches are fitted: without the handling nothing is filter-shaped
    assert res.nonstationary and res.analysis.basis == "quiet stretches"
    assert res.fit_range.excluded == 0 and res.fit.tau_used[0] == res.fit.curve.tau[0]
    res = rep.analyse(Channel(label="gyro", quantity="rate", data=y, unit="rad/s"), 1.0, quiet=False)
    assert res.nonstationary and res.analysis.basis == "whole record (motion kept)"
    assert res.fit_range.excluded == 0 and res.fit.range_rule == "nonstationary"
    assert res.fit.tau_used[0] == res.fit.curve.tau[0]
    assert res.fit.misfit and res.fit.p_value < 1e-6
    assert res.fit.range_reason.startswith("short taus kept (non-stationary record)")
    text = txt.log_text(type("Log", (), {"path": "r.csv", "fs": 1.0, "notes": []})(), [res])
    assert any(ln.startswith("gyro: short taus kept (non-stationary record)") for ln in text), text
