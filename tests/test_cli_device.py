"""The 'gyrobench parts' and 'gyrobench simulate device' verbs: files with the one truth layout, one-line errors."""

from __future__ import annotations

import math

import h5py
import numpy as np
import pytest
from gyrobench.scenarios.cli import main
from gyrobench.sim import parts
from gyrobench.sim.recording import load_hdf5

EPS = np.finfo(float).eps


def test_parts_lists_every_part_with_its_source(capsys):
    assert main(["parts"]) == 0
    text = capsys.readouterr().out
    for d in parts.datasheets():
        assert f"{d.name}: {d.manufacturer} {d.model}" in text
        assert d.source in text


def _sum_residual(rec) -> tuple[float, float]:
    out, true = rec["output"], rec["truth/true_rate"]
    comps = [rec["truth/" + k] for k in rec.metadata["error_components"]]
    scale = max(np.max(np.abs(a)) for a in (out, true, *comps))
    return float(np.max(np.abs(out - true - np.sum(comps, axis=0)))), 16 * (len(comps) + 2) * EPS * scale


def test_simulate_device_from_csv_profiles_to_hdf5(tmp_path, capsys):
    (tmp_path / "rate.csv").write_text("time [s],rate [deg/s]\n0,0\n50,10\n100,-10\n")
    (tmp_path / "temp.csv").write_text("time [s],temperature [degC]\n0,20\n100,40\n")
    out = tmp_path / "stim.h5"
    rc = main(["simulate", "device", "stim300", "--rate-csv", str(tmp_path / "rate.csv"), "--temperature-csv",
               str(tmp_path / "temp.csv"), "--fs", "10", "--seed", "3", "-o", str(out), "-q"])
    assert rc == 0
    rec = load_hdf5(out)
    assert rec.n_samples == 1000 and rec.fs == 10.0
    # the rate CSV reaches the truth: linear between the rows, at the sample centres
    t = rec.time
    expect = np.radians(np.interp(t, [0, 50, 100], [0, 10, -10]))
    assert np.allclose(rec["truth/true_rate"], expect, rtol=0, atol=1e-12)
    assert np.allclose(rec["truth/temperature"], np.interp(t, [0, 100], [293.15, 313.15]), atol=1e-9)
    resid, tol = _sum_residual(rec)
    assert resid <= tol
    with h5py.File(out) as f:  # units as attributes, readable without gyrobench
        grp = f["recordings"][rec.name]
        assert grp["channels/output"].attrs["unit"] == "rad/s"
        for k in ("true_rate", *parts.ERROR_COMPONENTS):
            assert grp["truth"][k].attrs["unit"] == "rad/s"
            assert np.array_equal(grp["truth"][k][()], rec["truth/" + k])


def test_simulate_device_profile_toml_to_csv(tmp_path):
    (tmp_path / "p.toml").write_text(
        "duration_s = 60\nrate_dps = [[0, 0], [30, 5], [60, 5]]\ntemperature_c = 30\nspecific_force_g = 1\n")
    out = tmp_path / "m.csv"
    assert main(["simulate", "device", "mti-1", "--profile", str(tmp_path / "p.toml"), "--fs", "50",
                 "-o", str(out), "-q"]) == 0
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    header = out.read_text().splitlines()[0].split(",")
    col = {h.split(" [")[0]: i for i, h in enumerate(header)}
    err = data[:, col["output"]] - data[:, col["truth/true_rate"]]
    comps = sum(data[:, col["truth/" + k]] for k in parts.ERROR_COMPONENTS)
    # CSV holds %.17g: the identity survives to float64 rounding
    assert np.max(np.abs(err - comps)) <= 64 * EPS * np.max(np.abs(data[:, 1:10]))
    assert np.allclose(data[:, col["truth/specific_force"]], 9.80665)
    g = parts.get("mti-1").datasheet.g_sensitivity
    assert g is None and np.all(data[:, col["truth/g_sensitivity"]] == 0)  # the sheet gives none
    assert math.isclose(data[-1, col["truth/true_rate"]], math.radians(5.0), rel_tol=1e-12)


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["simulate", "device", "nope", "--duration", "10s", "-o", "x.h5"], "unknown part 'nope'"),
        (["simulate", "device", "stim300", "-o", "x.h5"], "needs --duration"),
        (["simulate", "device", "stim300", "--duration", "10s", "-o", "x.txt"], "-o must end in"),
        (["simulate", "device", "stim300", "--duration", "10s", "--N", "1", "-o", "x.h5"], "--N apply to"),
        (["simulate", "noise", "extra", "--duration", "10s", "-o", "x.h5"], "second positional"),
        (["simulate", "noise", "--profile", "p.toml", "--duration", "10s", "-o", "x.h5"], "--profile apply to"),
        (["simulate", "device", "stim300", "--rate-csv", "missing.csv", "-o", "x.h5"], "does not exist"),
    ],
)
def test_simulate_device_bad_input_is_one_line_exit_2(argv, needle, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert needle in err and "\n" not in err, err


def test_parts_names_each_part_s_physics_solve_or_why_not(capsys):
    # one 'physics model:' line per part: the solved parameters (every built-in part maps)
    assert main(["parts"]) == 0
    lines = [ln for ln in capsys.readouterr().out.splitlines() if ln.strip().startswith("physics model:")]
    assert len(lines) == len(parts.names())
    text = "\n".join(lines)
    assert "fog_spec: source power" in text and "mems_spec: pick-off noise" in text and "rlg_spec: lock-in" in text
    assert "fog_spec: coil L" in text and "mems_spec: proof mass" in text and "not mapped" not in text
