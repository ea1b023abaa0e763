"""Tests of sim.mount_coning: the sampled coning rate against its closed-form mean, and bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gyrobench.sim.mount_coning import MountConing, RockingMode

MOUNT = MountConing(
    x=RockingMode(frequency=400.0, quality=10.0, compliance=1e-6),
    y=RockingMode(frequency=460.0, quality=10.0, compliance=1e-6),
)


@pytest.mark.parametrize("f", [300.0, 430.0, 500.0])
def test_sampled_coning_mean_equals_the_closed_form(f):
    """A sine with a smooth (Hann) on/off over 0.5 s, 4 s steady, on a 6.4 kHz grid: the mean of the
    sampled rate over whole periods of the steady part equals (1/2) A^2 w Im(X conj Y). The signal is
    deterministic; the ring-in has decayed by e^-(pi f0 t/Q) ~ 1e-25 1.5 s into the steady part, so
    what is left is the 2f tone over a window of whole drive periods rounded to the sample grid
    (< 1 sample in 12800): 1e-6 relative."""
    fs, a0 = 6400.0, 19.6
    t = np.arange(int(6.0 * fs)) / fs
    env = np.clip(np.minimum(t - 0.5, 5.5 - t) / 0.5, 0.0, 1.0)
    env = 0.5 - 0.5 * np.cos(np.pi * env)
    acc = a0 * env * np.cos(2 * np.pi * f * t)
    rate = MOUNT.rate(acc, fs)
    k0 = int(2.5 * fs)
    per = fs / f
    n_per = int(2.0 * fs / per)
    k1 = k0 + int(round(n_per * per))
    sim = float(np.mean(rate[k0:k1]))
    closed = float(MOUNT.mean_rate(f, a0))
    assert closed != 0.0
    assert sim == pytest.approx(closed, rel=1e-6)
    assert np.all(rate[: int(0.4 * fs)] == pytest.approx(0.0, abs=1e-12 * abs(closed)))


def test_equal_modes_do_not_cone():
    same = MountConing(x=MOUNT.x, y=MOUNT.x)
    scale = abs(float(MOUNT.mean_rate(430.0, 19.6)))
    assert np.all(np.abs(same.mean_rate(np.array([100.0, 400.0, 700.0]), 19.6)) < 1e-12 * scale)


def test_mean_rate_changes_sign_with_the_mode_order_and_scales_with_a_squared():
    swapped = MountConing(x=MOUNT.y, y=MOUNT.x)
    assert float(swapped.mean_rate(430.0, 10.0)) == pytest.approx(-float(MOUNT.mean_rate(430.0, 10.0)))
    assert float(MOUNT.mean_rate(430.0, 20.0)) == pytest.approx(4 * float(MOUNT.mean_rate(430.0, 10.0)))


def test_bad_input_rejected():
    with pytest.raises(ValueError, match=r"RockingMode.quality must be \(0, 1e\+06\] 1; got 0.0"):
        RockingMode(frequency=400.0, quality=0.0, compliance=1e-6)
    with pytest.raises(TypeError, match=r"RockingMode.frequency must be a real number \[Hz\]; got '4'"):
        RockingMode(frequency="4", quality=1.0, compliance=1e-6)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"acceleration must be a 1-D array; got shape \(2, 2\)"):
        MOUNT.rate(np.zeros((2, 2)), 1000.0)
    with pytest.raises(ValueError, match=r"MountConing.fs must be finite and > 0 Hz; got nan"):
        MOUNT.rate(np.zeros(4), math.nan)


def test_body_frame_is_the_default_and_the_space_frame_is_its_opposite():
    space = MountConing(x=MOUNT.x, y=MOUNT.y, frame="space")
    assert MOUNT.frame == "body"
    f = np.array([300.0, 430.0, 500.0])
    np.testing.assert_array_equal(space.mean_rate(f, 19.6), -MOUNT.mean_rate(f, 19.6))
    with pytest.raises(ValueError, match=r"MountConing.frame must be one of \('body', 'space'\) .*; got 'table'"):
        MountConing(x=MOUNT.x, y=MOUNT.y, frame="table")


def test_exact_kinematics_gives_the_body_frame_sign():
    """Rotation matrices (checks_mount_coning.exact_body_rate) agree with the body-frame model
    and differ from the space-frame one by a relative 2: the kinematics fix the sign."""
    from gyrobench.scenarios.checks.mount_coning import exact_body_rate

    exact = exact_body_rate(430.0, 19.6, n=4000)
    assert float(MOUNT.mean_rate(430.0, 19.6)) == pytest.approx(exact, rel=1e-5)  # (2 pi/4000)^2/6 = 4e-7
    space = MountConing(x=MOUNT.x, y=MOUNT.y, frame="space")
    assert float(space.mean_rate(430.0, 19.6)) == pytest.approx(-exact, rel=1e-5)
