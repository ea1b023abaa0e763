"""What ``gyrobench allan`` prints for the smaller cases: full channel names, the segment message, filled
gaps, the temperature hint, the deviation values and the quiet-stretch lines."""

from __future__ import annotations

import json

import numpy as np

from tests.scenarios.test_cli import run

FS = 100.0


def test_ros_all_axes_table_keeps_full_channel_names(tmp_path, capsys, rng):
    n = 20_000
    t = np.arange(n) / FS
    cols = ["%time", "field.header.seq", "field.angular_velocity.x", "field.angular_velocity.y",
            "field.angular_velocity.z"]
    data = 0.01 * rng.standard_normal((n, 3))
    p = tmp_path / "ros.csv"
    p.write_text(",".join(cols) + "\n" + "\n".join(
        f"{int(ti * 1e9)},{i}," + ",".join(f"{v:.9g}" for v in row) for i, (ti, row) in enumerate(zip(t, data,
                                                                                                      strict=True)))
        + "\n")
    code, out, err = run(["allan", p, "--all-axes", "--terms", "N,B"], capsys)
    assert code in (0, 5), err
    rows = [ln for ln in out.splitlines() if ln.startswith("field.angular_velocity.") and " N " in f" {ln} "]
    assert {r.split()[0] for r in rows} == set(cols[2:]), out


def test_no_segment_message_without_segments_and_quiet_lines(tmp_path, capsys, rng):
    n = 100_000
    y = 0.01 * rng.standard_normal(n)
    y[60_000:] += 0.05  # a step at 600 s
    p = tmp_path / "g.csv"
    np.savetxt(p, np.column_stack([np.arange(n) / FS, y]), delimiter=",", header="time [s],gyro [deg/s]",
               comments="", fmt="%.9g")
    code, out, err = run(["allan", p, "--terms", "N,B"], capsys)
    assert code == 5, err
    assert "SEGMENTS" not in out and "no quiet stretch" not in out
    assert any(ln.startswith("QUIET gyro: quiet stretches:") and "left out" in ln for ln in out.splitlines()), out
    assert "overlapping deviation [deg/h]" in out  # the deviation values
    code, out, err = run(["allan", p, "--terms", "N,B", "--json"], capsys)
    doc = json.loads(out)
    assert doc["basis"] == "quiet stretches" and doc["quiet"]["stretches"] == 2


def test_filled_gaps_are_warned_of(tmp_path, capsys, rng):
    n = 50_000
    t = np.arange(n) / FS
    keep = (t < 200.0) | (t >= 210.0)  # a 10 s gap
    y = 0.01 * rng.standard_normal(n)
    p = tmp_path / "g.csv"
    np.savetxt(p, np.column_stack([t[keep], y[keep]]), delimiter=",", header="time [s],gyro [deg/s]", comments="",
               fmt="%.9g")
    code, out, err = run(["allan", p, "--gaps", "fill", "--terms", "N,B", "--accept-nonstationary"], capsys)
    assert code == 0, err
    assert any(ln.startswith("WARNING gyro: the filled samples are interpolated") for ln in out.splitlines()), out


def test_identified_ramp_with_a_temperature_column_points_at_temperature(tmp_path, capsys, rng):
    n = 200_000
    t = np.arange(n) / FS
    temp = 25 + 0.01 * t  # a 20 degC ramp over 2000 s
    y = 0.01 * rng.standard_normal(n) + 0.002 * (temp - 25)
    p = tmp_path / "g.csv"
    np.savetxt(p, np.column_stack([t, y, temp]), delimiter=",", header="time [s],gyro [deg/s],temp [degC]",
               comments="", fmt="%.9g")
    code, out, err = run(["allan", p, "--column", "gyro", "--accept-nonstationary"], capsys)
    assert code == 0, err
    assert any("--temperature 'temp'" in ln for ln in out.splitlines()), out
    code, out, err = run(["allan", p, "--column", "gyro", "--temperature", "temp", "--accept-nonstationary"], capsys)
    assert "--temperature 'temp'" not in out
