"""gyrobench allan on filtered and moving records: the exit status says motion, not a filter (issue 30 item 1)."""

from __future__ import annotations

import json

import numpy as np

from tests.scenarios.test_cli import run

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
