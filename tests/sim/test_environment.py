"""Environment profiles: closed-form shapes and validation."""

import numpy as np
import pytest

from gyrobench.base import units
from gyrobench.sim.environment import PiecewiseLinear, Ramp, Soak, rate_steps, thermal_profile


def test_thermal_profile_ramp_rate_and_soak():
    start, top = units.celsius(-10.0), units.celsius(40.0)
    rate = 10.0 / 3600.0  # 10 degC/h
    p = thermal_profile(start, [Soak(duration=1800.0), Ramp(target=top, rate=rate), Soak(duration=7200.0)])
    assert p.duration == pytest.approx(1800.0 + 5 * 3600.0 + 7200.0, rel=1e-12)
    t = np.array([0.0, 1800.0, 1800.0 + 2.5 * 3600.0, p.times[-1]])
    np.testing.assert_allclose(p(t), [start, start, units.celsius(15.0), top], rtol=1e-12)
    np.testing.assert_allclose(p.derivative(np.array([100.0, 5000.0, p.times[-1] - 1])), [0.0, rate, 0.0], atol=1e-15)


def test_ramp_by_duration_and_direction():
    p = thermal_profile(300.0, [Ramp(target=290.0, duration=100.0)])
    assert p.derivative(np.array([50.0]))[0] == pytest.approx(-0.1, rel=1e-12)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [({"target": 300.0}, "exactly one of rate"),
     ({"target": 300.0, "rate": 1.0, "duration": 2.0}, "exactly one of rate"),
     ({"target": 300.0, "rate": 0.0}, "Ramp.rate must be > 0"),
     ({"target": float("nan"), "rate": 1.0}, "Ramp.target must be a finite")],
)
def test_ramp_rejects(kwargs, match):
    with pytest.raises(ValueError, match=match):
        Ramp(**kwargs)


def test_soak_rejects_nonpositive():
    with pytest.raises(ValueError, match=r"Soak.duration must be > 0 s; got -1"):
        Soak(duration=-1)


def test_from_segments_rejects_gap_overlap_jump():
    with pytest.raises(ValueError, match="a gap in the profile"):
        PiecewiseLinear.from_segments([(0, 10, 1, 2), (11, 20, 2, 3)])
    with pytest.raises(ValueError, match="an overlap in the profile"):
        PiecewiseLinear.from_segments([(0, 10, 1, 2), (9, 20, 2, 3)])
    with pytest.raises(ValueError, match="a jump in the profile"):
        PiecewiseLinear.from_segments([(0, 10, 1, 2), (10, 20, 2.5, 3)])
    p = PiecewiseLinear.from_segments([(0, 10, 1, 2), (10, 20, 2, 3)])
    assert p(15.0) == pytest.approx(2.5, rel=1e-12)


def test_times_must_increase():
    with pytest.raises(ValueError, match="strictly increasing"):
        PiecewiseLinear(np.array([0.0, 1.0, 1.0]), np.zeros(3))


def test_rate_steps_windows_and_acceleration():
    rates = units.deg_per_s(np.arange(3600.0, -3601.0, -360.0))
    acc = units.deg_per_s(100.0)
    r = rate_steps(rates, dwell=90.0, settle=30.0, acceleration=acc, lead_in=60.0)
    assert r.windows.shape == (21, 2)
    # the table sits exactly at the commanded rate inside every settled window
    mid = r.windows.mean(axis=1)
    np.testing.assert_allclose(r.profile(mid), rates, rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.diff(r.windows, axis=1)[:, 0], 60.0, rtol=1e-12)
    # transitions never exceed the acceleration; starts and ends at rest
    slopes = np.abs(np.diff(r.profile.values) / np.diff(r.profile.times))
    assert slopes.max() == pytest.approx(acc, rel=1e-12)
    assert r.profile.values[0] == 0.0 and r.profile.values[-1] == 0.0
    # first transition 0 -> 3600 deg/s at 100 deg/s^2 takes 36 s after the 60 s lead-in
    assert r.windows[0, 0] == pytest.approx(60.0 + 36.0 + 30.0, rel=1e-12)


def test_rate_steps_rejects():
    with pytest.raises(ValueError, match="settle must satisfy"):
        rate_steps([1.0], dwell=10.0, settle=10.0, acceleration=1.0)
    with pytest.raises(ValueError, match="acceleration must be > 0 rad/s"):
        rate_steps([1.0], dwell=10.0, settle=1.0, acceleration=0.0)
    with pytest.raises(ValueError, match="rates must be a 1-D array"):
        rate_steps([1.0, float("nan")], dwell=10.0, settle=1.0, acceleration=1.0)
