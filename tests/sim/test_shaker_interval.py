"""Tests for sim.shaker.interval_mean_acceleration: a shaker profile as one input per output interval."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from gyrobench.base import units
from gyrobench.base.memory import LIMIT_ENV, MemoryLimitError
from gyrobench.sim.shaker import (
    OVERSAMPLING,
    FixedSine,
    Phased,
    RandomVibration,
    interval_mean_acceleration,
)

G = units.g(1.0)
EPS = np.finfo(float).eps


# ---------------------------------------------------------------- closed form
def test_tone_above_the_output_rate_gets_the_moving_average_gain(rng):
    # 137 Hz at a 50 Hz output: m = ceil(4 x 137/50) = 11 shaker samples per output interval. The mean of
    # A sin(2 pi f t + p) over t = (k - k0)/fs + j/(m fs), j = 0..m-1, is A Im(exp(i(2 pi f (k - k0)/fs + p)) H)
    # with H = (1/m) sum_j exp(i 2 pi f j/(m fs)) = exp(i pi f (m-1)/(m fs)) sin(pi f/fs)/(m sin(pi f/(m fs)))
    # (geometric series). The window starts at round(2.013 x 50) = 101 and holds round(4.013 x 50) = 201
    # samples. Tolerance: both sides evaluate phases up to 2 pi f T_v = 3.5e3 rad, each to ~eps relative.
    fs, f, amp, phase = 50.0, 137.0, 2.0 * G, 0.3
    m = math.ceil(OVERSAMPLING * f / fs)
    assert m == 11
    dwell = FixedSine(frequency=f, duration=4.013, acceleration=amp, phase=phase)
    a = interval_mean_acceleration(dwell, duration=10.0, fs=fs, start=2.013, rng=rng)
    assert a.shape == (500,)
    k = np.arange(201)
    gain = np.exp(1j * np.pi * f * (m - 1) / (m * fs)) * math.sin(math.pi * f / fs) / (
        m * math.sin(math.pi * f / (m * fs)))
    expect = amp * np.imag(np.exp(1j * (2 * np.pi * f * k / fs + phase)) * gain)
    np.testing.assert_allclose(a[101:302], expect, rtol=0, atol=16 * EPS * (2 * np.pi * f * 4.02) * amp)
    assert np.all(a[:101] == 0) and np.all(a[302:] == 0)
    # the gain is the attenuation the mean promises: |H| = 0.0940 here (m = 11), far below the full level
    assert np.max(np.abs(a)) <= abs(gain) * amp * (1 + 1e-12)


def test_ramp_spans_the_whole_output_intervals_of_the_window(rng):
    # m = 1 (5 Hz at 100 Hz): a_k = A w(t_k) sin(2 pi f t_k), t_k = (k - k0)/fs, with the raised-cosine
    # taper w of the vibration's duration rounded to whole intervals: 2.004 s -> round(200.4) = 200
    # samples -> 2.0 s, so the taper closes at t = 2.0 s, not 2.004 s.
    fs, f, amp, ramp = 100.0, 5.0, 0.5 * G, 0.25
    dwell = FixedSine(frequency=f, duration=2.004, acceleration=amp, ramp_time=ramp)
    a = interval_mean_acceleration(dwell, duration=3.0, fs=fs, start=0.5, rng=rng)
    t = np.arange(200) / fs
    w = np.ones_like(t)
    w[t < ramp] = 0.5 * (1 - np.cos(np.pi * t[t < ramp] / ramp))
    late = t > 2.0 - ramp
    w[late] = 0.5 * (1 - np.cos(np.pi * (2.0 - t[late]) / ramp))
    np.testing.assert_allclose(a[50:250], amp * w * np.sin(2 * np.pi * f * t), rtol=0, atol=64 * EPS * amp)
    assert np.all(a[:50] == 0) and np.all(a[250:] == 0)


def test_same_stream_same_record_and_the_stream_is_used(rng):
    vib = RandomVibration(breakpoints=((20.0, 0.01), (80.0, 0.04)), duration=5.0)
    seed = int(rng.integers(2**32))
    one = interval_mean_acceleration(vib, duration=6.0, fs=40.0, start=1.0, rng=np.random.default_rng(seed))
    two = interval_mean_acceleration(vib, duration=6.0, fs=40.0, start=1.0, rng=np.random.default_rng(seed))
    other = interval_mean_acceleration(vib, duration=6.0, fs=40.0, start=1.0, rng=np.random.default_rng(seed + 1))
    assert np.array_equal(one, two) and not np.array_equal(one, other)


# ---------------------------------------------------------------- bad input
_SINE = FixedSine(frequency=5.0, duration=4.0, acceleration=G)


@pytest.mark.parametrize(
    ("kwargs", "exc", "needle"),
    [
        ({"vibration": Phased(vibration=_SINE, static_before=1.0)}, TypeError,
         "vibration must be a SineSweep, FixedSine or RandomVibration; got Phased"),
        ({"duration": -1.0}, ValueError, "interval_mean_acceleration.duration must be > 0 s; got -1.0"),
        ({"duration": math.nan}, ValueError, "interval_mean_acceleration.duration must be finite [s]; got nan"),
        ({"fs": 0.0}, ValueError, "fs must be a finite number > 0 Hz; got 0.0"),
        ({"start": -0.5}, ValueError, "interval_mean_acceleration.start must be >= 0 s; got -0.5"),
        ({"start": 7.0}, ValueError, "start + vibration.duration = 11 s must lie inside the record (0, 10] s"),
        ({"duration": 0.001}, ValueError, "hold >= 1 output sample at 100 Hz"),
        ({"rng": 7}, TypeError, "rng must be a numpy.random.Generator; got int"),
    ],
)
def test_bad_input_names_the_parameter(kwargs, exc, needle):
    args = {"vibration": _SINE, "duration": 10.0, "fs": 100.0, "rng": np.random.default_rng(0), **kwargs}
    vibration = args.pop("vibration")
    with pytest.raises(exc, match=re.escape(needle)):
        interval_mean_acceleration(vibration, **args)


def test_memory_is_checked_before_the_oversampled_vibration_is_drawn(monkeypatch):
    # 4 series of round(4 x 100) x 1 samples = 12.8 kB > a 10 kB limit
    monkeypatch.setenv(LIMIT_ENV, "10k")
    with pytest.raises(MemoryLimitError, match="the shaker's vibration sampled at 100 Hz needs about"):
        interval_mean_acceleration(_SINE, duration=10.0, fs=100.0, rng=np.random.default_rng(0))


@pytest.mark.parametrize(
    ("kwargs", "exc", "needle"),
    [
        # duration x fs overflows to inf: once an OverflowError from int(floor(inf))
        ({"duration": 1e200, "fs": 1e200}, MemoryLimitError, "the shaker record of inf output samples needs about"),
        # start x fs overflows: once an OverflowError from round(inf)
        ({"start": 1e308}, ValueError, "must lie inside the record (0, 10] s"),
        # a record of 1e15 output samples: once numpy's MemoryError after the vibration was drawn
        ({"duration": 1e9, "fs": 1e6}, MemoryLimitError, "the shaker record of 1e+15 output samples needs about"),
    ],
)
def test_huge_records_are_refused_in_one_line(kwargs, exc, needle):
    args = {"duration": 10.0, "fs": 100.0, "rng": np.random.default_rng(0), **kwargs}
    with pytest.raises(exc, match=re.escape(needle)):
        interval_mean_acceleration(_SINE, **args)
