"""gyrobench allan on filtered and moving records: the exit status says motion, not a filter (issue 30 item 1)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from tests.scenarios.test_cli import run

# every test runs among planted user files and fails if one changes (tests/conftest.py)
pytestmark = pytest.mark.usefixtures("user_files")

FS = 100.0


def _write(path, y):
    np.savetxt(path, np.column_stack([np.arange(y.size) / FS, y]), delimiter=",", header="time [s],gyro [deg/s]",
               comments="", fmt="%.9g")


def test_filtered_record_is_stationary_and_handled_one_is_not(tmp_path, capsys):
    """A 16-sample moving average of white noise (a sensor's decimation filter) exits 0 with
    nonstationary false; the same record with 3 s of handling (5x the noise) exits 5 and says so
    on its first line. The stationarity test's false-alarm rate on filtered noise is checked in
    tests/analysis/test_stationarity.py; this is the CLI's wiring of it."""
    rng = np.random.default_rng(46)
    x = 0.01 * rng.standard_normal(200_015)
    p = tmp_path / "g.csv"
    _write(p, np.convolve(x, np.ones(16) / 16, mode="valid"))
    code, out, err = run(["allan", p, "--json"], capsys)
    assert code == 0, err
    assert json.loads(out)["nonstationary"] is False
    x[50_000:50_300] *= 5.0
    _write(p, np.convolve(x, np.ones(16) / 16, mode="valid"))
    code, out, err = run(["allan", p], capsys)
    assert code == 5, err
    assert out.splitlines()[0].startswith("NONSTATIONARY gyro: "), out


def test_segments_auto_pools_the_quiet_stretches_into_one_fit(tmp_path, capsys):
    """--segments auto: a 0.05 deg/s step at 600 s of a 1000 s white-noise record; the pooled fit
    over the two stretches holds N within z se of the truth 0.06 deg/sqrt(h) (z two-sided at 1e-6,
    se half the 68 % interval) and its interval is narrower than either stretch's (it holds all
    their samples); JSON 'pooled' and a POOLED text line."""
    from statistics import NormalDist

    rng = np.random.default_rng(47)
    n = 100_000
    y = 0.01 * rng.standard_normal(n)
    y[60_000:] += 0.05
    p = tmp_path / "g.csv"
    _write(p, y)
    code, out, err = run(["allan", p, "--segments", "auto", "--json", "--terms", "N,B"], capsys)
    assert code == 5, err
    doc = json.loads(out)
    pooled, segs = doc["pooled"], doc["segments"]
    assert pooled["segments"] == len(segs) == 2
    t = pooled["fit"]["terms"]["N"]
    se = (t["high68"] - t["low68"]) / 2.0
    n_true = 0.01 / np.sqrt(FS) * 60.0
    assert abs(t["value"] - n_true) <= NormalDist().inv_cdf(1.0 - 0.5e-6) * se, (t, n_true)
    for s in segs:
        u = s["fit"]["terms"]["N"]
        assert t["high"] - t["low"] < u["high"] - u["low"], (t, u)
    code, out, err = run(["allan", p, "--segments", "auto", "--terms", "N,B"], capsys)
    assert any(ln.startswith("POOLED gyro: one fit over") and " N " in ln for ln in out.splitlines()), out
