"""Tests of gyrobench.io.imu_formats: EuRoC CSV and Kalibr imu.yaml as navigation tools read them."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from gyrobench.io.imu_formats import EUROC_HEADER, FORMAT_MARKER, kalibr_imu_yaml, write_euroc
from gyrobench.io.logs import read_csv_log


def test_a_euroc_file_reads_back_with_gyrobenchs_reader_and_a_plain_csv_reader(tmp_path):
    rng = np.random.default_rng(0)
    g, a = 0.01 * rng.standard_normal((500, 3)), 9.8 + 0.1 * rng.standard_normal((500, 3))
    path = write_euroc(tmp_path / "data.csv", g, a, fs=200.0)
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    assert ",".join(rows[0]) == EUROC_HEADER
    assert int(rows[2][0]) - int(rows[1][0]) == 5_000_000  # 200 Hz in ns
    np.testing.assert_array_equal(np.array(rows[1:], dtype=float)[:, 1:], np.column_stack([g, a]))
    log = read_csv_log(path, all_axes=True)
    assert log.fs == pytest.approx(200.0)
    assert [ch.quantity for ch in log.channels] == ["rate"] * 3 + ["accel"] * 3
    for ch, col in zip(log.channels, np.column_stack([g, a]).T, strict=True):
        np.testing.assert_allclose(ch.data, col, rtol=1e-15)
    assert log.channels[0].unit == "rad/s" and log.channels[3].unit == "m s^-2"  # as the header states


def test_kalibr_yaml_states_every_unit():
    text = kalibr_imu_yaml(gyro_noise_density=1.7e-4, gyro_random_walk=2e-5, accel_noise_density=2e-3,
                           accel_random_walk=3e-3, update_rate=200.0)
    lines = text.splitlines()
    assert lines[0] == FORMAT_MARKER
    assert "gyroscope_noise_density: 0.00017  # [rad/s/sqrt(Hz)]" in lines
    assert all("[" in line for line in lines[2:])


def test_bad_inputs_are_refused(tmp_path):
    with pytest.raises(ValueError, match=r"gyro and accel must both have shape \(n, 3\)"):
        write_euroc(tmp_path / "x.csv", np.zeros((3, 2)), np.zeros((3, 2)), fs=1.0)
    with pytest.raises(ValueError, match=r"must be finite"):
        write_euroc(tmp_path / "x.csv", np.full((3, 3), np.nan), np.zeros((3, 3)), fs=1.0)
    assert not (tmp_path / "x.csv").exists()
    with pytest.raises(ValueError, match=r"update_rate must be a finite number >= 0"):
        kalibr_imu_yaml(gyro_noise_density=0, gyro_random_walk=0, accel_noise_density=0, accel_random_walk=0,
                        update_rate=float("nan"))
