"""ROS bags of an IMU record: written by gyrobench, read back with rosbags (the reader ROS users use)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from rosbags.highlevel import AnyReader

from gyrobench.io import rosbag as rb
from gyrobench.io.recording import load_hdf5
from gyrobench.sim import parts

from ..scenarios.test_cli import run

pytestmark = pytest.mark.usefixtures("user_files")

STATIC = ("[site]\nlatitude_deg = 45.0\n\n[[motion]]\nduration_s = 2.0\n\n"
          "[[motion]]\nduration_s = 1.0\nrate_dps = [0, 0, 30]\n")


def _read(path: Path):
    with AnyReader([path]) as reader:
        conns = [(c.topic, c.msgtype, c.msgcount) for c in reader.connections]
        msgs = [(t, reader.deserialize(raw, c.msgtype)) for c, t, raw in reader.messages()]
    return conns, msgs


@pytest.mark.parametrize("name", ["imu.bag", "imu_ros2"])
def test_a_bag_reads_back_with_its_topic_count_stamps_and_si_values(tmp_path, capsys, name):
    traj = tmp_path / "m.toml"
    traj.write_text(STATIC)
    bag = tmp_path / name
    code, out, err = run(["simulate", "imu", "stim300", "--trajectory", traj, "-o", tmp_path / "r.h5",
                          "--rosbag", bag, "--seed", "4"], capsys)
    assert code == 0, err
    assert ("ROS 1 bag" if name.endswith(".bag") else "ROS 2 bag folder") in out
    assert bag.is_file() == name.endswith(".bag")
    rec = load_hdf5(tmp_path / "r.h5")
    conns, msgs = _read(bag)
    assert conns == [("/imu0", "sensor_msgs/msg/Imu", rec.n_samples)] and len(msgs) == rec.n_samples == 300
    stamps = np.array([m.header.stamp.sec * 10**9 + m.header.stamp.nanosec for _, m in msgs])
    expected = np.round((0.5 / 100.0 + np.arange(300) / 100.0) * 1e9).astype(np.int64)  # the sample centres
    np.testing.assert_array_equal(stamps, expected)
    np.testing.assert_array_equal([t for t, _ in msgs], expected)
    for a in "xyz":
        np.testing.assert_array_equal([getattr(m.angular_velocity, a) for _, m in msgs], rec[f"gyro_{a}"])
        np.testing.assert_array_equal([getattr(m.linear_acceleration, a) for _, m in msgs], rec[f"accel_{a}"])
    # the 30 deg/s turn about z is in rad/s; the static block reads gravity up, about +9.8 m/s^2 in m/s^2
    assert msgs[-1][1].angular_velocity.z == pytest.approx(math.radians(30.0), abs=0.01)
    assert abs(np.mean([m.linear_acceleration.z for _, m in msgs[:200]])) == pytest.approx(9.8, abs=0.05)
    m = msgs[0][1]
    assert m.orientation_covariance[0] == -1.0  # no orientation produced (the message's convention)
    n = parts.get("stim300").datasheet.angle_random_walk()
    vrw = parts.get("stim300").accelerometer().velocity_random_walk
    np.testing.assert_allclose(m.angular_velocity_covariance, np.diag([n * n * 100.0] * 3).ravel(), rtol=1e-12)
    np.testing.assert_allclose(m.linear_acceleration_covariance, np.diag([vrw * vrw * 100.0] * 3).ravel(), rtol=1e-12)


def test_increments_are_written_as_rates_and_ideal_accelerometers_as_unknown_covariance(tmp_path, capsys):
    traj = tmp_path / "m.toml"
    traj.write_text(STATIC)
    code, _, err = run(["simulate", "imu", "adxrs646", "--trajectory", traj, "-o", tmp_path / "d.h5", "--increments",
                        "--rosbag", tmp_path / "d.bag"], capsys)
    assert code == 0, err
    rec = load_hdf5(tmp_path / "d.h5")
    _, msgs = _read(tmp_path / "d.bag")
    np.testing.assert_allclose([m.angular_velocity.z for _, m in msgs], rec["dtheta_z"] * 100.0, rtol=1e-15)
    np.testing.assert_allclose([m.linear_acceleration.x for _, m in msgs], rec["dv_x"] * 100.0, rtol=1e-15)
    np.testing.assert_array_equal(msgs[0][1].linear_acceleration_covariance, np.zeros(9))


def test_bag_outputs_are_refused_in_one_line(tmp_path, capsys, monkeypatch):
    traj = tmp_path / "m.toml"
    traj.write_text(STATIC)
    (tmp_path / "old.bag").write_bytes(b"user's bag")
    for bag, match in ((tmp_path / "old.bag", "exists: a bag is written only to a new path"),
                       (tmp_path / "x.db3", "takes NAME.bag")):
        code, _, err = run(["simulate", "imu", "stim300", "--trajectory", traj, "-o", tmp_path / "x.h5",
                            "--rosbag", bag], capsys)
        assert code == 2 and match in err and len(err.strip().splitlines()) == 1, err
    assert (tmp_path / "old.bag").read_bytes() == b"user's bag" and not (tmp_path / "x.h5").exists()
    monkeypatch.setattr(rb, "rosbags_available", lambda: False)
    code, _, err = run(["simulate", "imu", "stim300", "--trajectory", traj, "-o", tmp_path / "x.h5",
                        "--rosbag", tmp_path / "n.bag"], capsys)
    assert code == 2 and "pip install 'gyrobench[ros]'" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "x.h5").exists()


def test_the_writer_without_rosbags_says_how_to_install_it(tmp_path, monkeypatch):
    import sys

    out = tmp_path / "w"
    out.mkdir()
    monkeypatch.setitem(sys.modules, "rosbags.typesys", None)  # an import of it now raises ImportError
    with pytest.raises(rb.RosbagsMissing, match=r"pip install 'gyrobench\[ros\]'"):
        rb.write_imu_bag(out / "a.bag", np.zeros((2, 3)), np.zeros((2, 3)), stamps=[0.0, 0.01])
    assert not rb.rosbags_available()
    assert list(out.iterdir()) == []


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"stamps": [0.01, 0.01]}, "strictly increasing"),
        ({"stamps": [-1.0, 0.0]}, ">= 0 s"),
        ({"gyro_variance": -1.0}, "gyro_variance must be a finite variance"),
        ({"topic": "imu"}, "topic must be a ROS name"),
    ],
)
def test_bad_writer_input_is_refused_before_anything_is_written(tmp_path, kw, match):
    out = tmp_path / "w"
    out.mkdir()
    args = {"stamps": [0.0, 0.01], **kw}
    with pytest.raises(ValueError, match=match):
        rb.write_imu_bag(out / "a.bag", np.zeros((2, 3)), np.zeros((2, 3)), **args)
    assert list(out.iterdir()) == []
