"""CSV readers of ``scenarios.logs`` for the logs people have: rostopic echo -p, decimal commas, duplicate names."""

import json

import numpy as np
import pytest

from gyrobench.io.logs import read_csv_log
from tests.scenarios.test_cli import assert_one_line_error, run

FS = 200.0
#: epoch nanoseconds of the first sample (exact steps of 5 ms)
T0_NS = 1_600_000_000_000_000_000


def _rostopic_imu(path, rng, n=2000, frame_id="imu4"):
    """A ``rostopic echo -p /imu`` export of sensor_msgs/Imu: every field, the frame_id as text."""
    cols = (
        ["%time", "field.header.seq", "field.header.stamp", "field.header.frame_id"]
        + [f"field.orientation.{a}" for a in "xyzw"]
        + [f"field.orientation_covariance{i}" for i in range(9)]
        + [f"field.angular_velocity.{a}" for a in "xyz"]
        + [f"field.angular_velocity_covariance{i}" for i in range(9)]
        + [f"field.linear_acceleration.{a}" for a in "xyz"]
        + [f"field.linear_acceleration_covariance{i}" for i in range(9)]
    )
    w = rng.standard_normal((n, 3)) * 1e-3
    acc = rng.standard_normal((n, 3)) * 1e-2 + [0.0, 0.0, 9.81]
    t = T0_NS + np.arange(n, dtype=np.int64) * 5_000_000
    rows = []
    for i in range(n):
        cells = [str(t[i]), str(i), str(t[i] - 123_456), frame_id, "0.0", "0.0", "0.0", "1.0", "-1.0"] + ["0.0"] * 8
        cells += [f"{v:.17g}" for v in w[i]] + ["0.0"] * 9 + [f"{v:.17g}" for v in acc[i]] + ["0.0"] * 9
        rows.append(",".join(cells))
    path.write_text(",".join(cols) + "\n" + "\n".join(rows) + "\n")
    return w, acc


def test_rostopic_echo_csv_with_its_text_frame_id_is_read(tmp_path, rng):
    p = tmp_path / "imu.csv"
    w, acc = _rostopic_imu(p, rng)
    log = read_csv_log(p, None, None, None, all_axes=True)
    assert log.fmt == "ros" and log.fs == pytest.approx(FS, rel=1e-12)
    # the six measured axes; not the orientation, the covariances or the header fields
    assert [c.label for c in log.channels] == [f"field.angular_velocity.{a}" for a in "xyz"] + [
        f"field.linear_acceleration.{a}" for a in "xyz"
    ]
    assert [(c.quantity, c.unit) for c in log.channels] == [("rate", "rad/s")] * 3 + [("accel", "m/s^2")] * 3
    for k in range(3):
        np.testing.assert_array_equal(log.channels[k].data, w[:, k])
        np.testing.assert_array_equal(log.channels[3 + k].data, acc[:, k])
    assert log.t0 == pytest.approx(T0_NS * 1e-9, rel=1e-15)
    one = read_csv_log(p, ["field.angular_velocity.y"], None, None)
    np.testing.assert_array_equal(one.channels[0].data, w[:, 1])


def test_rostopic_text_column_named_for_analysis_is_refused_naming_the_cell(tmp_path, rng):
    p = tmp_path / "imu.csv"
    _rostopic_imu(p, rng, n=50)
    with pytest.raises(ValueError, match=r"line 2, column 'field.header.frame_id': 'imu4' is not a number"):
        read_csv_log(p, ["field.header.frame_id"], None, None)


def test_rostopic_through_the_command_line(tmp_path, capsys, rng):
    p = tmp_path / "imu.csv"
    w, _ = _rostopic_imu(p, rng)
    code, out, err = run(["allan", p, "--column", "field.angular_velocity.z", "--json"], capsys)
    assert code == 0, err
    doc = json.loads(out)
    assert doc["fs"] == pytest.approx(FS, rel=1e-12)


@pytest.mark.parametrize("metadata", ["Sample rate,100\n", "Exported by X,v2\nSample rate,100\n"])
def test_metadata_lines_before_the_header_are_not_data(tmp_path, rng, metadata):
    """A row of text and numbers counts as data only after a header of as many cells, with more numbers than text."""
    rate = rng.standard_normal(300)
    p = tmp_path / "g.csv"
    rows = "\n".join(f"{i / 100!r},{float(v)!r}" for i, v in enumerate(rate))
    p.write_text(metadata + "time [s],gyro [dps]\n" + rows)
    log = read_csv_log(p, None, None, None)
    assert log.channels[0].label == "gyro"
    np.testing.assert_allclose(log.channels[0].data, np.deg2rad(rate), rtol=1e-15)


def _point_and_comma(tmp_path, rng, sep):
    rate = rng.standard_normal(3000) * 0.01
    rows = [f"{i / 100:.2f}{sep}{v:.9f}" for i, v in enumerate(rate)]
    point = tmp_path / "point.csv"
    point.write_text("time [s]" + sep + "gyro [deg/s]\n" + "\n".join(rows) + "\n")
    comma = tmp_path / "comma.csv"
    comma.write_text("time [s]" + sep + "gyro [deg/s]\n" + "\n".join(r.replace(".", ",") for r in rows) + "\n")
    return point, comma


@pytest.mark.parametrize("sep", [";", "\t"])
def test_decimal_comma_is_detected(tmp_path, rng, sep):
    point, comma = _point_and_comma(tmp_path, rng, sep)
    ref = read_csv_log(point, None, None, None)
    got = read_csv_log(comma, None, None, None)
    assert got.fs == ref.fs
    np.testing.assert_array_equal(got.channels[0].data, ref.channels[0].data)
    assert any(n.startswith("decimal comma detected") for n in got.notes)
    assert not any("decimal" in n for n in ref.notes)
    forced = read_csv_log(comma, None, None, None, decimal=",")
    np.testing.assert_array_equal(forced.channels[0].data, ref.channels[0].data)
    assert not any("decimal" in n for n in forced.notes)  # given, not guessed: nothing to say


def test_decimal_comma_of_a_single_column_needs_the_flag(tmp_path, rng):
    rate = rng.standard_normal(500)
    p = tmp_path / "g.csv"
    p.write_text("\n".join(f"{v:.9f}".replace(".", ",") for v in rate) + "\n")
    with pytest.raises(ValueError, match="has 2 data columns"):  # "0,5" alone reads as two columns
        read_csv_log(p, None, 100.0, "deg/s")
    log = read_csv_log(p, None, 100.0, "deg/s", decimal=",")
    np.testing.assert_allclose(log.channels[0].data, np.deg2rad(np.round(rate, 9)), rtol=1e-15)


def test_decimal_flag_is_checked(tmp_path, rng):
    point, _ = _point_and_comma(tmp_path, rng, ";")
    with pytest.raises(ValueError, match=r"^--decimal must be '\.' or ','; got ';'$"):
        read_csv_log(point, None, None, None, decimal=";")


def test_decimal_comma_through_the_command_line(tmp_path, capsys, rng):
    point, comma = _point_and_comma(tmp_path, rng, ";")
    code, ref, err = run(["allan", point, "--json"], capsys)
    assert code == 0, err
    for extra in ([], ["--decimal", ","]):
        code, out, err = run(["allan", comma, "--json", *extra], capsys)
        assert code == 0, err
        a, b = json.loads(ref), json.loads(out)
        assert a["N"] == b["N"] and a["fs"] == b["fs"]
    code, _, err = run(["allan", comma, "--decimal", "."], capsys)  # forced point: no row of numbers
    assert_one_line_error(code, err, "has 0 data rows")


@pytest.mark.parametrize(
    ("header", "named"),
    [
        ("time [s],gyro [dps],gyro [deg/h]", "'gyro' (columns 1, 2)"),
        ("time [s],gx,gy,gx,gy", "'gx' (columns 1, 3); 'gy' (columns 2, 4)"),
    ],
)
def test_duplicate_header_names_are_refused_naming_them(tmp_path, capsys, rng, header, named):
    ncols = header.count(",") + 1
    data = np.column_stack([np.arange(200) / 100.0, rng.standard_normal((200, ncols - 1))])
    p = tmp_path / "g.csv"
    np.savetxt(p, data, delimiter=",", header=header, comments="")
    with pytest.raises(ValueError, match="names " + named.replace("(", r"\(").replace(")", r"\)") + " more than once"):
        read_csv_log(p, ["1"], None, "deg/s")
    code, _, err = run(["allan", p, "--column", "1", "--units", "deg/s"], capsys)
    assert_one_line_error(code, err, f"names {named} more than once: rename the duplicates")


# ----------------------------------------------------------------------------- ISO-8601 time columns
def _iso_csv(path, rng, fmt, n=3000):
    t = np.datetime64("2024-03-01T10:00:00.000", "ns") + np.arange(n) * np.timedelta64(5, "ms")
    rate = rng.standard_normal(n)
    rows = (fmt(str(ti)[:23]) + f",{float(v)!r}" for ti, v in zip(t, rate, strict=True))
    path.write_text("time,gyro [deg/s]\n" + "\n".join(rows))
    return rate


@pytest.mark.parametrize("fmt", [lambda s: s + "Z", lambda s: s, lambda s: s.replace("T", " ")])
def test_iso_8601_time_column_is_read_in_utc(tmp_path, rng, fmt):
    p = tmp_path / "iso.csv"
    rate = _iso_csv(p, rng, fmt)
    log = read_csv_log(p, None, None, None)
    assert log.fs == pytest.approx(FS, rel=1e-12)
    assert log.t0 == pytest.approx(1_709_287_200.0, abs=1e-6)  # 2024-03-01T10:00:00Z
    np.testing.assert_allclose(log.channels[0].data, np.deg2rad(rate), rtol=1e-14)
    assert any("ISO-8601 UTC" in n for n in log.notes)


@pytest.mark.parametrize(
    ("fmt", "match"),
    [(lambda s: s + "+01:00", "has a UTC offset; ISO-8601 times are read only in UTC"),
     (lambda s: s[8:10] + "/" + s[5:7] + "/" + s[:4] + " " + s[11:], "is neither a number nor an ISO-8601 date-time")],
)
def test_other_text_times_are_refused_saying_which(tmp_path, capsys, rng, fmt, match):
    p = tmp_path / "t.csv"
    _iso_csv(p, rng, fmt)
    code, _, err = run(["allan", p], capsys)
    assert_one_line_error(code, err, match)
    assert "line 2" in err
