"""Columns typed by kind (gyro or accelerometer) from name, unit and magnitude; ``--units`` per kind (issue 30.3)."""

import json

import numpy as np
import pytest

from gyrobench.base import units
from gyrobench.io.logs import read_csv_log
from gyrobench.io.logs._kinds import parse_units
from tests.scenarios.test_cli import assert_one_line_error, run

FS = 100.0
N = 20_000


def _imu_csv(path, rng, names, n=N):
    """Three gyro axes (deg/s, 0.1 deg/s noise) then three accelerometer axes (g, gravity on z), no units."""
    gyro = 0.1 * rng.standard_normal((n, 3))
    acc = 0.003 * rng.standard_normal((n, 3)) + [0.0, 0.0, -1.0156]
    t = np.arange(n) / FS
    np.savetxt(path, np.column_stack([t, gyro, acc]), delimiter=",", header="time [s]," + ",".join(names),
               comments="", fmt="%.9g")
    return gyro, acc


def test_units_per_kind_never_analyse_an_accelerometer_as_a_gyro(tmp_path, capsys, rng):
    """The issue's file: gyro and accel names without units. A bare rate unit reaches only the gyro columns."""
    p = tmp_path / "imu.csv"
    gyro, acc = _imu_csv(p, rng, ["gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"])
    code, _, err = run(["allan", p, "--all-axes", "--units", "deg/s"], capsys)
    assert_one_line_error(code, err, "the unit of column 'accel_x' is unknown")
    log = read_csv_log(p, None, None, "gyro=deg/s,accel=g", all_axes=True)
    assert [(c.label, c.quantity, c.unit) for c in log.channels] == (
        [(f"gyro_{a}", "rate", "deg/s") for a in "xyz"] + [(f"accel_{a}", "accel", "g") for a in "xyz"]
    )
    np.testing.assert_allclose(log.channels[2].data, units.deg_per_s(gyro[:, 2]), rtol=1e-8)
    np.testing.assert_allclose(log.channels[5].data, acc[:, 2] * 9.80665, rtol=1e-8)
    yaml = tmp_path / "imu.yaml"
    code, out, err = run(["allan", p, "--all-axes", "--units", "gyro=deg/s,accel=g", "--kalibr", yaml, "--json",
                          "--accept-nonstationary"], capsys)
    assert code == 0, err
    text = yaml.read_text()
    assert "gyroscope_noise_density" in text and "max over gyro_x, gyro_y, gyro_z" in text
    assert "max over accel_x, accel_y, accel_z" in text
    assert [c["quantity"] for c in json.loads(out)["channels"]] == ["rate"] * 3 + ["accel"] * 3


def test_all_axes_refuses_an_untyped_axis_naming_it_instead_of_dropping_it(tmp_path, capsys, rng):
    p = tmp_path / "imu.csv"
    _imu_csv(p, rng, ["x", "y", "z", "accel_x", "accel_y", "accel_z"])
    code, _, err = run(["allan", p, "--all-axes"], capsys)
    assert_one_line_error(code, err, "the unit of column 'x' is unknown")
    code, _, err = run(["allan", p, "--all-axes", "--units", "gyro=deg/s,accel=g"], capsys)
    assert_one_line_error(code, err, "column 'x' has no kind")
    log = read_csv_log(p, ["x", "y"], None, "gyro=deg/s")  # the user's word gives the kind
    assert [(c.quantity, c.unit) for c in log.channels] == [("rate", "deg/s")] * 2


def test_a_column_reading_gravity_is_not_taken_as_a_gyro_by_a_bare_unit(tmp_path, capsys, rng):
    """Untyped columns with a bare rate unit: the one reading 1 g is refused; gyro= states the kind."""
    p = tmp_path / "imu.csv"
    _imu_csv(p, rng, ["c1", "c2", "c3", "c4", "c5", "c6"])
    code, _, err = run(["allan", p, "--column", "c6", "--units", "deg/s"], capsys)
    assert_one_line_error(code, err, "column 'c6' reads -1.016 on average with little scatter: gravity on an "
                                     "accelerometer axis in g, not a gyro at rest")
    code, _, err = run(["allan", p, "--column", "c1", "--units", "deg/s", "--accept-nonstationary"], capsys)
    assert code == 0, err  # a gyro at rest reads about 0: accepted
    log = read_csv_log(p, ["c6"], None, "gyro=deg/s")  # the user's word: analysed as a gyro
    assert log.channels[0].quantity == "rate"


def test_both_kinds_given_and_a_column_of_no_kind_is_refused(tmp_path, capsys, rng):
    p = tmp_path / "imu.csv"
    _imu_csv(p, rng, ["c1", "c2", "c3", "c4", "c5", "c6"])
    code, _, err = run(["allan", p, "--column", "c1", "--units", "gyro=deg/s,accel=g"], capsys)
    assert_one_line_error(code, err, "column 'c1' has no kind (its name and header say neither gyro nor "
                                     "accelerometer)")


@pytest.mark.parametrize(
    ("text", "match"),
    [("gyro=deg/s,mag=uT", "kinds: gyro|accel"), ("gyro=g", "--units gyro= must be a rate unit"),
     ("accel=deg/s", "--units accel= must be one of"), ("gyro=deg/s,gyro=rad/s", "gives the gyro unit twice"),
     ("gyro=", "kind=unit pairs")],
)
def test_bad_units_are_refused_in_one_line(text, match):
    with pytest.raises(ValueError, match=match):
        parse_units(text)


def test_units_parse():
    assert parse_units("dps") == {"rate": "deg/s", "bare": "1"}
    assert parse_units("g") == {"accel": "g", "bare": "1"}
    assert parse_units(" gyro = rad/s , accel = m/s^2 ") == {"rate": "rad/s", "accel": "m/s^2"}
