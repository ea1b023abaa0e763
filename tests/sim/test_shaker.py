"""Tests for sim/shaker.py: sweep phase/frequency closed forms, displacement limit, PSD synthesis, bad input."""

from __future__ import annotations

import math
import zlib

import numpy as np
import pytest
from scipy import stats

from gyrobench.base import units
from gyrobench.sim.shaker import (
    FixedSine,
    Phased,
    RandomVibration,
    SineSweep,
    grms,
    psd_from_breakpoints,
    sweep_frequency,
    sweep_phase,
)

G = units.g(1.0)
NAVMAT = [(20.0, 0.01), (80.0, 0.04), (350.0, 0.04), (2000.0, 0.007)]


@pytest.fixture
def rng(request) -> np.random.Generator:
    """The same stream on every run, a different one for every test."""
    key = zlib.crc32(request.node.nodeid.encode())
    return np.random.default_rng([20261121, key])


# ---------------------------------------------------------------- closed form
@pytest.mark.parametrize("spacing", ["log", "linear"])
def test_sweep_phase_derivative_is_two_pi_f(spacing):
    # central difference of the closed-form phase; truncation error h^2 |phi'''|/6 << 1e-6 rel here
    f1, f2, ts = 1.0, 500.0, 600.0
    t = np.linspace(1.0, 599.0, 50)
    h = 1e-4
    dphi = (sweep_phase(t + h, f1, f2, ts, spacing) - sweep_phase(t - h, f1, f2, ts, spacing)) / (2 * h)
    np.testing.assert_allclose(dphi / (2 * np.pi), sweep_frequency(t, f1, f2, ts, spacing), rtol=1e-6)


def test_sweep_end_points_closed_form():
    f1, f2, ts = 2.0, 500.0, 300.0
    r = f2 / f1
    assert sweep_phase(ts, f1, f2, ts, "log") == pytest.approx(2 * np.pi * f1 * ts * (r - 1) / math.log(r), rel=1e-12)
    assert sweep_phase(ts, f1, f2, ts, "linear") == pytest.approx(2 * np.pi * (f1 + f2) * ts / 2, rel=1e-12)
    assert sweep_frequency(ts, f1, f2, ts, "log") == pytest.approx(f2, rel=1e-12)


def test_fixed_sine_samples_closed_form(rng):
    s = FixedSine(frequency=37.0, duration=2.0, acceleration=3 * G, phase=0.3)
    sig = s.sample(1000.0, rng=rng)
    t = np.arange(2000) / 1000.0
    np.testing.assert_allclose(sig.acceleration, 3 * G * np.sin(2 * np.pi * 37.0 * t + 0.3), rtol=0, atol=1e-12 * 3 * G)
    assert np.all(sig.frequency == 37.0) and np.all(sig.on)


def test_displacement_limit_caps_low_frequency_amplitude():
    d_max = 0.0127
    s = SineSweep(f_start=1.0, f_end=500.0, duration=600.0, acceleration=2 * G, max_displacement=d_max)
    fc = math.sqrt(2 * G / d_max) / (2 * math.pi)
    t_low = 600.0 * math.log(fc / 2) / math.log(500.0)  # where f = fc/2
    t_high = 600.0 * math.log(fc * 2) / math.log(500.0)
    f_low = s.frequency(t_low)
    assert s.amplitude(t_low) == pytest.approx(d_max * (2 * np.pi * f_low) ** 2, rel=1e-12)
    assert s.amplitude(t_high) == pytest.approx(2 * G, rel=1e-12)
    # peak displacement never exceeds the stroke
    t = np.linspace(0, 600, 2001)
    assert np.all(s.amplitude(t) / (2 * np.pi * s.frequency(t)) ** 2 <= d_max * (1 + 1e-12))


def test_grms_of_standard_spectra():
    # docs/physics.md 4: NAVMAT P-9492 computes to 6.06 grms; MIL-STD-810G general minimum integrity 7.69
    assert grms(NAVMAT) == pytest.approx(6.06, abs=0.005)
    mil = [(20.0, 0.04), (1000.0, 0.04), (2000.0, 0.01)]
    assert grms(mil) == pytest.approx(7.69, abs=0.005)


def test_psd_slope_in_db_per_octave():
    # +3 dB/oct between 20 and 80 Hz: G(40)/G(20) = 10^(3.0103.../10)... = 2 per octave for the NAVMAT slope
    g = psd_from_breakpoints([(20.0, 0.01), (80.0, 0.04)], [20.0, 40.0, 80.0])
    np.testing.assert_allclose(g, [0.01, 0.02, 0.04], rtol=1e-12)


def test_random_vibration_variance_is_sum_of_psd_lines(rng):
    # Parseval: deterministic line amplitudes, random phases -> the sample variance is exact
    rv = RandomVibration(breakpoints=tuple(NAVMAT), duration=4.0)
    fs = 8192.0
    sig = rv.sample(fs, rng=rng)
    n = len(sig.acceleration)
    fk = np.fft.rfftfreq(n, 1 / fs)
    expected = np.sum(rv.shaped_psd(fk[1:]) * fs / n) * G**2
    assert np.mean(sig.acceleration**2) == pytest.approx(expected, rel=1e-12)
    assert abs(np.mean(sig.acceleration)) < 1e-12 * math.sqrt(expected)


def test_random_vibration_displacement_shaping_meets_the_stroke():
    rv = RandomVibration(breakpoints=((5.0, 0.04), (2000.0, 0.04)), duration=1.0, max_displacement=0.002)
    fc = rv.displacement_corner()
    assert fc > 5.0
    f = np.geomspace(5.0, 2000.0, 4000)
    sd = math.sqrt(np.trapezoid(rv.shaped_psd(f) * G**2 / (2 * np.pi * f) ** 4, f))
    assert 3 * sd == pytest.approx(0.002, rel=1e-6)


def test_phased_bounds_and_mask(rng):
    p = Phased(vibration=FixedSine(frequency=10.0, duration=3.0, acceleration=G), static_before=2.0, static_after=1.0)
    assert p.phase_bounds == ((0.0, 2.0), (2.0, 5.0), (5.0, 6.0))
    sig = p.sample(100.0, rng=rng)
    assert len(sig.acceleration) == 600
    assert not sig.on[:200].any() and sig.on[200:500].all() and not sig.on[500:].any()
    assert np.all(sig.acceleration[:200] == 0) and np.all(np.isnan(sig.frequency[500:]))


# ---------------------------------------------------------------- statistical
def test_controller_error_has_the_requested_rms(rng):
    # GM of std s, Tc = 0.5 s over T = 2000 s: the variance estimate has about T/Tc = 4000
    # equivalent degrees of freedom (2 x T/(2 Tc)); 1e-6 two-sided chi-square bound.
    s = FixedSine(frequency=5.0, duration=2000.0, acceleration=G, control_error=0.03, control_time=0.5)
    sig = s.sample(50.0, rng=rng)
    e = sig.amplitude / G - 1.0
    nu = 2000.0 / 0.5
    lo, hi = stats.chi2.ppf([0.5e-6, 1 - 0.5e-6], nu) / nu
    assert lo < np.var(e) / 0.03**2 < hi


# ---------------------------------------------------------------- bad input
def test_negative_acceleration_rejected():
    with pytest.raises(ValueError, match=r"SineSweep.acceleration must be >= 0 m/s\^2; got -1.0"):
        SineSweep(f_start=1.0, f_end=500.0, duration=10.0, acceleration=-1.0)


def test_negative_acceleration_rejected_fixed_sine():
    with pytest.raises(ValueError, match=r"FixedSine.acceleration must be >= 0"):
        FixedSine(frequency=500.0, duration=10.0, acceleration=-2.0)


def test_sweep_beyond_nyquist_rejected(rng):
    s = SineSweep(f_start=1.0, f_end=500.0, duration=1.0, acceleration=G)
    with pytest.raises(ValueError, match=r"needs fs > 1000.0 Hz \(Nyquist\); got fs=800.0 Hz"):
        s.sample(800.0, rng=rng)


def test_bad_spacing_rejected():
    with pytest.raises(ValueError, match=r"spacing must be one of \['log', 'linear'\]"):
        SineSweep(f_start=1.0, f_end=5.0, duration=1.0, acceleration=G, spacing="cubic")


def test_zero_frequency_rejected():
    with pytest.raises(ValueError, match=r"SineSweep.f_start must be > 0 Hz"):
        SineSweep(f_start=0.0, f_end=5.0, duration=1.0, acceleration=G)


def test_psd_breakpoints_must_increase():
    with pytest.raises(ValueError, match="strictly increasing"):
        psd_from_breakpoints([(100.0, 0.01), (50.0, 0.02)], [60.0])


def test_sample_requires_generator():
    with pytest.raises(TypeError, match="rng must be a numpy.random.Generator"):
        FixedSine(frequency=5.0, duration=1.0, acceleration=G).sample(100.0, rng=1)


def test_moving_span_is_the_first_and_last_nonzero_sample():
    from gyrobench.sim.shaker import moving_span

    rng = np.random.default_rng(5)
    for _ in range(20):
        a = np.where(rng.random(500) < 0.05, rng.standard_normal(500), 0.0)
        nz = np.flatnonzero(a)
        assert moving_span(a) == ((int(nz[0]), int(nz[-1])) if nz.size else None)
    assert moving_span(np.zeros(7)) is None and moving_span(np.zeros(0)) is None
    assert moving_span(np.array([0.0, -2.0])) == (1, 1)
