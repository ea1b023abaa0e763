"""``gyrobench simulate imu``: a triad on a motion definition, written as HDF5, EuRoC and Kalibr files."""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy.stats import norm

from gyrobench.base import units
from gyrobench.io.recording import load_hdf5
from gyrobench.scenarios.cli.main import main
from gyrobench.sim import parts

from .test_cli import run

# every test runs among planted user files and fails if one changes (tests/conftest.py)
pytestmark = pytest.mark.usefixtures("user_files")

TRAJECTORY = """
[site]
latitude_deg = 45.0

[[motion]]
duration_s = {static}

[[motion]]
duration_s = 9.0
rate_dps = [0, 0, 10]

[accelerometer]
vrw_m_s_sqrt_h = 0.05
"""


def _write(tmp_path, static=10.0):
    p = tmp_path / "motion.toml"
    p.write_text(TRAJECTORY.format(static=static))
    return p


def test_simulate_imu_writes_hdf5_euroc_and_kalibr(tmp_path, capsys):
    traj = _write(tmp_path)
    h5, euroc, yaml = tmp_path / "imu.h5", tmp_path / "data.csv", tmp_path / "imu.yaml"
    code, out, err = run(["simulate", "imu", "adxrs646", "--trajectory", traj, "-o", h5, "--euroc", euroc,
                          "--kalibr", yaml, "--misalignment", "1", "--seed", "3"], capsys)
    assert code == 0, err
    rec = load_hdf5(h5)
    assert sorted(rec.channels) == ["accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z"]
    # the 90 deg turn is in the z gyro: its samples sum to pi/2 (x fs) up to the part's errors
    turn = np.sum(rec["truth/gyro_z.true"]) / rec.fs
    assert turn == pytest.approx(np.pi / 2 + 19.0 * rec["truth/gyro_z.true"][0], rel=1e-9)
    rows = euroc.read_text().splitlines()
    assert rows[0].startswith("#timestamp [ns],w_RS_S_x [rad s^-1]") and len(rows) == 1 + rec.n_samples
    np.testing.assert_allclose(np.array(rows[1].split(","), dtype=float)[1:4], [rec[f"gyro_{a}"][0] for a in "xyz"],
                               rtol=1e-15)
    # stamped at the record's own sample times (interval centres, as the ROS bag is), to the ns
    stamps = [int(r.split(",")[0]) for r in rows[1:3]]
    assert stamps == [round((rec.t0 + k / rec.fs) * 1e9) for k in range(2)] and rec.t0 > 0
    assert yaml.read_text().startswith("# written by gyrobench\n")


def test_the_increments_option_writes_increments(tmp_path, capsys):
    traj = _write(tmp_path)
    code, _, err = run(["simulate", "imu", "adxrs646", "--trajectory", traj, "-o", tmp_path / "d.h5",
                        "--increments"], capsys)
    assert code == 0, err
    rec = load_hdf5(tmp_path / "d.h5")
    assert rec.channels["dtheta_z"].unit == "rad" and rec.channels["dv_z"].unit == "m/s"


@pytest.mark.slow
def test_allan_all_axes_reads_a_static_euroc_file_and_recovers_each_gyros_n(tmp_path, capsys):
    """A static 2700 s record at 20 Hz (300 crossover times of the part): 'allan --all-axes' on the
    EuRoC file fits each gyro's N within Z standard errors of the sheet's (1 % over 3 axes)."""
    p = tmp_path / "static.toml"
    p.write_text("[[motion]]\nduration_s = 2700.0\n[accelerometer]\nvrw_m_s_sqrt_h = 0.05\n")
    euroc = tmp_path / "data.csv"
    code, _, err = run(["simulate", "imu", "adxrs646", "--trajectory", p, "-o", tmp_path / "s.h5", "--euroc", euroc,
                        "--fs", "20"], capsys)
    assert code == 0, err
    code, out, err = run(["allan", euroc, "--all-axes", "--json"], capsys)
    assert code == 0, err
    doc = json.loads(out)
    z = float(norm.ppf(1 - 0.01 / (2 * 3)))
    n_true = units.to_deg_per_sqrt_h(parts.get("adxrs646").datasheet.angle_random_walk())
    gyros = [c for c in doc["channels"] if c["channel"].startswith("w_RS_S")]
    assert len(gyros) == 3
    for c in gyros:
        n = c["fit"]["terms"]["N"]
        assert n["unit"] == "deg/sqrt(h)"
        se = (n["high"] - n["low"]) / (2 * 1.96)
        assert abs(n["value"] - n_true) <= z * se, (c["channel"], n, n_true)


@pytest.mark.parametrize(
    ("extra", "match"),
    [
        ([], r"simulate imu needs --trajectory FILE.toml"),
        (["--trajectory", "{traj}", "-o", "{tmp}/x.txt"], r"-o must end in .h5, .hdf5 or .csv"),
        (["--trajectory", "{traj}", "-o", "{tmp}/x.h5", "--euroc", "{tmp}/x.txt"], r"--euroc must end in .csv"),
        (["--trajectory", "{traj}", "-o", "{traj}"], r"-o must end in .h5|must be four different files"),
        (["--trajectory", "{tmp}/bad.toml", "-o", "{tmp}/x.h5"], r"bad.toml: unknown tables \['spin'\]"),
        (["--trajectory", "{traj}", "-o", "{tmp}/x.h5", "--Q", "1"], r"simulate imu: --Q do not apply"),
    ],
)
def test_bad_imu_input_is_one_line_exit_2(tmp_path, capsys, extra, match):
    traj = _write(tmp_path)
    (tmp_path / "bad.toml").write_text("[spin]\nx = 1\n")
    argv = ["simulate", "imu", "adxrs646", *[a.format(traj=traj, tmp=tmp_path) for a in extra]]
    code, out, err = run(argv, capsys)
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    import re

    assert re.search(match, err), err
    assert not (tmp_path / "x.h5").exists()


def test_imu_flags_are_refused_by_the_other_targets(tmp_path, capsys):
    code, _, err = run(["simulate", "noise", "--N", "0.1", "--duration", "10s", "-o", tmp_path / "n.h5",
                        "--trajectory", "x.toml"], capsys)
    assert code == 2 and "--trajectory apply to 'simulate imu' only" in err
    assert main is not None


def test_a_csv_trajectory_of_quaternions_and_velocities(tmp_path, capsys):
    """A 90 deg turn sampled at 100 Hz as quaternions: the record's true z rate integrates to the
    turn plus the Earth's rate about the down axis over the record (-Omega sin(phi) t)."""
    from scipy.spatial.transform import Rotation

    from gyrobench.sim.earth import EARTH_RATE

    t = np.arange(0.0, 20.0 + 1e-9, 0.01)
    yaw = np.radians(10.0) * np.clip(t - 5.0, 0.0, 9.0)
    q = Rotation.from_euler("z", yaw[:, None]).as_quat()[:, [3, 0, 1, 2]]
    p = tmp_path / "traj.csv"
    rows = ["time_s,qw,qx,qy,qz,vn_mps,ve_mps,vd_mps"]
    rows += [",".join(f"{x:.17g}" for x in r) for r in np.column_stack([t, q, np.zeros((len(t), 3))])]
    p.write_text("\n".join(rows) + "\n")
    code, _, err = run(["simulate", "imu", "adxrs646", "--trajectory", p, "-o", tmp_path / "c.h5",
                        "--latitude", "45"], capsys)
    assert code == 0, err
    rec = load_hdf5(tmp_path / "c.h5")
    turn = np.sum(rec["truth/gyro_z.true"]) / rec.fs
    earth = -EARTH_RATE * np.sin(np.radians(45.0)) * 20.0
    # the spline smooths the two kinks of the sampled yaw, each within one sample interval: the
    # turn it integrates is the sampled one up to (rate step x h^2), 1.7e-5 rad x 2
    assert turn == pytest.approx(np.pi / 2 + earth, abs=4e-5)
    code, _, err = run(["simulate", "imu", "adxrs646", "--trajectory", p, "-o", tmp_path / "d.h5",
                        "--latitude", "95"], capsys)
    assert code == 2


STATIC = "[site]\nlatitude_deg = 30.0\n\n[[motion]]\nduration_s = 5.0\n"


def _static(tmp_path, extra=""):
    p = tmp_path / "static.toml"
    p.write_text(STATIC + extra)
    return p


def test_a_part_with_accelerometer_figures_uses_them_and_says_so(tmp_path, capsys):
    code, out, err = run(["simulate", "imu", "stim300", "--trajectory", _static(tmp_path), "-o", tmp_path / "s.h5",
                          "--seed", "2"], capsys)
    assert code == 0, err
    rec = load_hdf5(tmp_path / "s.h5")
    assert rec.metadata["accelerometer_from"].startswith("the part's datasheet (stim300: ")
    assert "accelerometers: the part's datasheet" in out
    assert rec.metadata["accelerometer"] == parts.get("stim300").accelerometer().to_metadata()
    noise = rec["truth/accel_z.noise"]
    # white noise of the sheet's VRW at 100 Hz: per-sample sd N sqrt(fs) = 0.01 m/s^2 (the flicker adds little)
    assert 0.005 < float(np.std(noise)) < 0.02


def test_a_gyro_only_part_keeps_ideal_accelerometers(tmp_path, capsys):
    code, _, err = run(["simulate", "imu", "adxrs646", "--trajectory", _static(tmp_path), "-o", tmp_path / "a.h5",
                        "--misalignment", "1"], capsys)
    assert code == 0, err
    rec = load_hdf5(tmp_path / "a.h5")
    assert rec.metadata["accelerometer_from"].startswith("ideal (the adxrs646 sheet gives no accelerometer figures")
    for a in "xyz":  # ideal: the output is the true specific force after the triad's misalignment, no other term
        ideal = rec[f"truth/accel_{a}.true"] + rec[f"truth/accel_{a}.misalignment"]
        np.testing.assert_array_equal(rec[f"accel_{a}"], ideal)


def test_the_trajectorys_accelerometer_table_replaces_the_parts(tmp_path, capsys):
    traj = _static(tmp_path, "\n[accelerometer]\nvrw_m_s_sqrt_h = 0.5\n")
    code, _, err = run(["simulate", "imu", "stim300", "--trajectory", traj, "-o", tmp_path / "t.h5"], capsys)
    assert code == 0, err
    rec = load_hdf5(tmp_path / "t.h5")
    assert rec.metadata["accelerometer_from"] == "the trajectory's [accelerometer] table"
    assert rec.metadata["accelerometer"]["velocity_random_walk"] == pytest.approx(0.5 / 60)
    assert rec.metadata["accelerometer"]["bias_instability"] == 0.0
