"""Gaps and uniformity of a CSV log's time column: ``--gaps refuse|fill|split`` and every step checked."""

import json

import numpy as np
import pytest

from gyrobench.analysis.allan import allan_deviation
from gyrobench.io.logs import UNIFORM_TOLERANCE, read_csv_log
from tests.scenarios.test_cli import assert_one_line_error, run

FS = 100.0
N = 200_000
DROP = 123_456


@pytest.fixture(scope="module")
def dropped(tmp_path_factory):
    """A 2e5-sample record (white plus random-walk rate) with sample DROP missing from its CSV."""
    rng = np.random.default_rng([20261127, 30])
    y = rng.standard_normal(N) + np.cumsum(rng.standard_normal(N)) * 2e-3
    t = np.arange(N) / FS
    keep = np.ones(N, dtype=bool)
    keep[DROP] = False
    p = tmp_path_factory.mktemp("gaps") / "g.csv"
    np.savetxt(p, np.column_stack([t[keep], y[keep]]), delimiter=",", header="time [s],gyro [rad/s]",
               comments="", fmt="%.17g")
    return p, y


def test_a_gap_is_refused_by_default_naming_it_and_the_flag(dropped, capsys):
    p, _ = dropped
    code, _, err = run(["allan", p], capsys)
    assert_one_line_error(code, err, f"has a gap before data row {DROP + 1}: step 0.02")
    assert "give --gaps fill (linear interpolation) or --gaps split" in err


@pytest.mark.parametrize("gaps", ["fill", "split"])
def test_one_dropped_sample_in_2e5_matches_the_unbroken_record(dropped, gaps):
    """fill and split: every ADEV point inside the unbroken curve's interval at false-alarm 1e-6."""
    p, y = dropped
    log = read_csv_log(p, None, None, None, gaps=gaps)
    assert log.fs == pytest.approx(FS, rel=1e-12)
    full = allan_deviation(y, FS, confidence=1 - 1e-6)
    if gaps == "fill":
        assert log.pieces is None and len(log.channels[0].data) == N
        assert any("1 missing sample in 1 gap" in n and "linear interpolation" in n for n in log.notes)
        x = log.channels[0].data
        assert x[DROP] == pytest.approx((y[DROP - 1] + y[DROP + 1]) / 2, rel=1e-12)
        got = allan_deviation(x, FS)
    else:
        from gyrobench.analysis.allan import allan_deviation_gaps

        assert log.pieces == ((0, DROP), (DROP, N - 1))
        x = log.channels[0].data
        got = allan_deviation_gaps([x[a:b] for a, b in log.pieces], FS)
    np.testing.assert_array_equal(got.tau, full.tau)
    assert np.all((full.low <= got.deviation) & (got.deviation <= full.high))


@pytest.mark.parametrize("gaps", ["fill", "split"])
def test_gaps_through_the_command_line(dropped, capsys, gaps):
    p, _ = dropped
    code, out, err = run(["allan", p, "--gaps", gaps, "--json", "--accept-nonstationary"], capsys)
    assert code == 0, err
    doc = json.loads(out)
    assert doc["fs"] == pytest.approx(FS, rel=1e-12)
    assert any(f"--gaps {gaps}" in n for n in doc["notes"]), doc["notes"]


def test_every_third_step_a_tenth_is_refused(tmp_path, capsys):
    """The median step is 1 ms, so no step is a gap; the times leave the uniform grid."""
    steps = np.tile([1e-3, 1e-3, 1e-4], 1000)
    t = np.concatenate([[0.0], np.cumsum(steps)])
    p = tmp_path / "t.csv"
    np.savetxt(p, np.column_stack([t, np.zeros_like(t)]), delimiter=",", header="time [s],gyro [rad/s]",
               comments="")
    code, _, err = run(["allan", p], capsys)
    assert_one_line_error(code, err, "is not uniform: data row")
    assert f"(the tolerance is {UNIFORM_TOLERANCE:g} step" in err


def test_jitter_within_the_tolerance_passes_and_the_rate_is_the_grid_step(tmp_path, rng):
    """Time stamps off the grid by up to 0.2 step (so no step exceeds the gap factor 1.5) are read; fs is 1 / the
    grid step."""
    n = 5000
    t = np.arange(n) / FS + rng.uniform(-0.2, 0.2, n) / FS
    t[0], t[-1] = 0.0, (n - 1) / FS
    p = tmp_path / "j.csv"
    np.savetxt(p, np.column_stack([t, rng.standard_normal(n)]), delimiter=",", header="time [s],gyro [rad/s]",
               comments="", fmt="%.17g")
    assert read_csv_log(p, None, None, None).fs == pytest.approx(FS, rel=1e-12)


def test_split_start_stop_count_time_on_the_grid(dropped):
    p, _ = dropped
    log = read_csv_log(p, None, None, None, gaps="split", start=1000.0, stop=1500.0)
    assert log.pieces == ((0, DROP - 100_000), (DROP - 100_000, 49_999))
    assert log.t0 == pytest.approx(1000.0)
    whole = read_csv_log(p, None, None, None, gaps="split", stop=1000.0)
    assert whole.pieces is None and len(whole.channels[0].data) == 100_000


@pytest.mark.parametrize(
    ("extra", "match"),
    [(["--kind", "modified"], "--gaps split computes the overlapping Allan deviation"),
     (["--segments", "auto"], "--segments auto is not available with --gaps split")],
)
def test_split_refuses_what_it_does_not_compute(dropped, capsys, extra, match):
    p, _ = dropped
    code, _, err = run(["allan", p, "--gaps", "split", *extra], capsys)
    assert_one_line_error(code, err, match)
