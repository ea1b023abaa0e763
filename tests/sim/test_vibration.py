"""Tests for sim/vibration.py: aliasing, rectified bias, noise growth, transients, bad input."""

from __future__ import annotations

import math
import zlib

import numpy as np
import pytest
from gyrobench.sim import units
from gyrobench.sim.noise import NoiseModel
from gyrobench.sim.shaker import FixedSine, Phased, SineSweep
from gyrobench.sim.vibration import (
    FogVibrationModel,
    StructuralMode,
    alias_frequency,
    decimate,
    moving_average_gain,
)
from scipy import stats

G = units.g(1.0)


@pytest.fixture
def rng(request) -> np.random.Generator:
    key = zlib.crc32(request.node.nodeid.encode())
    return np.random.default_rng([20261121, key])


def _fit_tone(y, f, fs):
    """Least-squares amplitude of a sinusoid at f [Hz] in y sampled at fs, and the residual."""
    t = np.arange(len(y)) / fs
    a = np.column_stack([np.sin(2 * np.pi * f * t), np.cos(2 * np.pi * f * t)])
    coef, *_ = np.linalg.lstsq(a, y, rcond=None)
    return math.hypot(*coef), y - a @ coef


# ---------------------------------------------------------------- closed form
def test_alias_frequency_formula():
    np.testing.assert_allclose(alias_frequency([500.0, 480.0, 20.0, 170.0], 160.0), [20.0, 0.0, 20.0, 10.0])


@pytest.mark.parametrize("decimation", ["sample", "integrate"])
def test_tone_above_nyquist_appears_at_the_predicted_alias(rng, decimation):
    # one heavily damped mode (settles in ms), tone only, no noise; output 160 Hz, drive 500 Hz
    mode = StructuralMode(frequency=700.0, quality=0.7, tone_gain=units.deg_per_h(10.0) / G)
    model = FogVibrationModel(modes=(mode,), physics_rate=3200.0, output_rate=160.0, decimation=decimation)
    rec = model.simulate(FixedSine(frequency=500.0, duration=4.0, acceleration=2 * G), rng=rng)
    y = rec["rate"][160:]  # skip the first second (ring-up, exp(-pi f t / Q) ~ 1e-1000)
    f_a, amp = model.output_tone(500.0, 2 * G)
    assert f_a == 20.0
    fitted, resid = _fit_tone(y, 20.0, 160.0)
    assert fitted == pytest.approx(float(amp), rel=1e-10)
    assert np.max(np.abs(resid)) < 1e-10 * fitted
    expected = 2 * G * abs(mode.tone_gain * mode.response(500.0, 3200.0))
    if decimation == "integrate":
        expected *= moving_average_gain(500.0, 20, 3200.0)
    assert float(amp) == pytest.approx(float(expected), rel=1e-12)


def test_moving_average_gain_matches_block_mean_of_a_sine():
    fs, m, f = 3200.0, 20, 500.0
    t = np.arange(3200 * 4) / fs
    y = decimate(np.sin(2 * np.pi * f * t + 0.2), m)
    amp, _ = _fit_tone(y, alias_frequency(f, fs / m), fs / m)
    assert amp == pytest.approx(float(moving_average_gain(f, m, fs)), rel=1e-10)


def test_rectified_bias_closed_form(rng):
    # output block = one drive period: the block mean of 2 c x^2 is c a^2 |H|^2 exactly in steady state
    c = units.deg_per_h(0.5) / G**2
    mode = StructuralMode(frequency=150.0, quality=0.8, rectification=c)
    model = FogVibrationModel(modes=(mode,), physics_rate=1000.0, output_rate=100.0, linear_g=0.0)
    rec = model.simulate(FixedSine(frequency=100.0, duration=3.0, acceleration=3 * G), rng=rng)
    expected = float(model.rectified_bias(100.0, 3 * G))
    assert expected == pytest.approx(c * 9 * G**2 * abs(mode.response(100.0, 1000.0)) ** 2, rel=1e-12)
    np.testing.assert_allclose(rec["truth/vibration_bias"][100:], expected, rtol=1e-10)


def test_discrete_mode_resonates_at_its_frequency():
    # bilinear with prewarping: |H_d(f_k)| = Q exactly, as the analog |H(f_k)|
    mode = StructuralMode(frequency=420.0, quality=8.0)
    assert abs(mode.response(420.0, 4000.0)) == pytest.approx(8.0, rel=1e-12)
    assert abs(mode.response(420.0)) == pytest.approx(8.0, rel=1e-12)
    assert abs(mode.response(0.0, 4000.0)) == pytest.approx(1.0, rel=1e-12)


def test_components_sum_to_output(rng):
    noise = NoiseModel.from_datasheet(quantization=0.1, angle_random_walk=0.01, bias_instability=0.05)
    mode = StructuralMode(frequency=200.0, quality=10.0, rectification=1e-8, tone_gain=1e-6, noise_weight=1.0)
    model = FogVibrationModel(noise=noise, modes=(mode,), heating_gain=1e-9, transient_gain=1e-8, physics_rate=2000.0,
                              output_rate=200.0)
    prof = Phased(vibration=SineSweep(f_start=10.0, f_end=400.0, duration=5.0, acceleration=G), static_before=2.0,
                  static_after=2.0)
    rec = model.simulate(prof, rng=rng)
    total = sum(c.data for k, c in rec.truth.items() if k != "true_rate")
    np.testing.assert_allclose(rec["rate"], total, rtol=0, atol=1e-12 * np.max(np.abs(rec["rate"])))
    assert rec.n_samples == 1800
    on = rec["shaker_on"]
    assert on[:400].sum() == 0 and on[400:1400].all() and on[1400:].sum() == 0
    # nothing vibration-related before switch-on
    for k in ("vibration_bias", "vibration_tone", "vibration_noise", "vibration_transient", "vibration_heating"):
        assert np.all(rec[f"truth/{k}"][:400] == 0.0)


def test_same_seed_same_record():
    mode = StructuralMode(frequency=200.0, quality=10.0, rectification=1e-8, noise_weight=1.0)
    model = FogVibrationModel(noise=NoiseModel.from_datasheet(angle_random_walk=0.01), modes=(mode,),
                              physics_rate=2000.0, output_rate=200.0)
    prof = FixedSine(frequency=50.0, duration=2.0, acceleration=G, control_error=0.02)
    a = model.simulate(prof, rng=np.random.default_rng(5))["rate"]
    b = model.simulate(prof, rng=np.random.default_rng(5))["rate"]
    np.testing.assert_array_equal(a, b)


def test_transients_spike_at_on_and_off_and_decay(rng):
    mode = StructuralMode(frequency=300.0, quality=0.7)
    kappa = units.deg_per_h(1.0) / G**2
    model = FogVibrationModel(modes=(mode,), transient_gain=kappa, transient_time=0.5, physics_rate=2000.0,
                              output_rate=100.0)
    prof = Phased(vibration=FixedSine(frequency=100.0, duration=10.0, acceleration=G), static_before=5.0,
                  static_after=10.0)
    tr = model.simulate(prof, rng=rng)["truth/vibration_transient"]
    s = G**2  # table acceleration power a^2 of the sine
    on, off = 500, 1500
    # first-order high-pass of a step: kappa S phi^(k+1), phi = exp(-1/(fs T)); the first block is only
    # partly rung up (~3 % short), which shifts later samples by < 3 % x (1 - phi) = 6e-4 relative
    phi = math.exp(-1 / 50.0)
    assert tr[on + 5] == pytest.approx(kappa * s * phi**6, rel=1e-3)
    assert tr[on] > 0.9 * kappa * s
    assert tr[off] < -0.9 * kappa * s
    # decays as exp(-t/T_tr): after 5 T_tr below 1 % of the spike
    assert abs(tr[on + 250]) < 0.01 * tr[on] and abs(tr[off + 250]) < 0.01 * abs(tr[off])


def test_heating_settles_to_gain_times_energy(rng):
    mode = StructuralMode(frequency=300.0, quality=0.7)
    h = units.deg_per_h(0.1) / G**2
    model = FogVibrationModel(modes=(mode,), heating_gain=h, heating_time=2.0, physics_rate=2000.0, output_rate=100.0)
    rec = model.simulate(FixedSine(frequency=100.0, duration=40.0, acceleration=G), rng=rng)
    s = float(model.modal_energy(100.0, G).sum())
    assert rec["truth/vibration_heating"][-1] == pytest.approx(h * s, rel=1e-6)


# ---------------------------------------------------------------- statistical
def test_noise_grows_by_the_predicted_factor(rng):
    # white output noise during a steady sine: sample variance vs N0^2 fs gain^2 at a 1e-6 two-sided chi-square bound
    n0 = units.deg_per_sqrt_h(0.02)
    mode = StructuralMode(frequency=150.0, quality=0.8, noise_weight=3.0)
    model = FogVibrationModel(noise=NoiseModel(angle_random_walk=n0), modes=(mode,), physics_rate=1000.0,
                              output_rate=100.0)
    rec = model.simulate(FixedSine(frequency=100.0, duration=100.0, acceleration=2 * G), rng=rng)
    y = rec["rate"][100:]
    gain = float(model.noise_gain(100.0, 2 * G))
    assert gain > 2.0
    nu = len(y)
    ratio = np.sum(y**2) / nu / (n0**2 * 100.0 * gain**2)
    lo, hi = stats.chi2.ppf([0.5e-6, 1 - 0.5e-6], nu) / nu
    assert lo < ratio < hi


# ---------------------------------------------------------------- bad input
def test_sweep_beyond_physics_resolution_rejected(rng):
    model = FogVibrationModel(physics_rate=1600.0, output_rate=160.0)
    with pytest.raises(ValueError, match=r"vibration up to 500.0 Hz needs physics_rate >= 2000.0 Hz"):
        model.simulate(SineSweep(f_start=1.0, f_end=500.0, duration=1.0, acceleration=G), rng=rng)


def test_negative_acceleration_rejected_by_model():
    model = FogVibrationModel(modes=(StructuralMode(frequency=100.0, quality=5.0, rectification=1.0),))
    with pytest.raises(ValueError, match=r"acceleration amplitude must be finite and >= 0 m/s\^2"):
        model.rectified_bias(100.0, -1.0)


def test_non_integer_rate_ratio_rejected():
    with pytest.raises(ValueError, match=r"physics_rate must be an integer multiple of output_rate = 300.0 Hz"):
        FogVibrationModel(physics_rate=1000.0, output_rate=300.0)


def test_mode_above_physics_nyquist_rejected():
    with pytest.raises(ValueError, match=r"modes\[0\].frequency = 3000.0 Hz must be below physics_rate/2"):
        FogVibrationModel(modes=(StructuralMode(frequency=3000.0, quality=5.0),), physics_rate=4000.0)


def test_overdamped_mode_rejected():
    with pytest.raises(ValueError, match=r"StructuralMode.quality must be > 0.5"):
        StructuralMode(frequency=100.0, quality=0.4)


def test_bad_decimation_rejected():
    with pytest.raises(ValueError, match=r"decimation must be one of \['integrate', 'sample'\]"):
        FogVibrationModel(decimation="cic")


def test_random_vibration_rectified_bias_matches_the_spectrum(rng):
    # Parseval: lines of fixed amplitude A_l (random phases) give <2 x_k^2> = sum_l A_l^2 |H_k(f_l)|^2 over the
    # record period; the filter's start from rest (decay time Q/(pi f_k) = 0.5 ms) costs < 1e-3 of it here
    from gyrobench.sim.shaker import RandomVibration

    c = units.deg_per_h(0.2) / G**2
    mode = StructuralMode(frequency=300.0, quality=0.7, rectification=c)
    model = FogVibrationModel(modes=(mode,), physics_rate=8000.0, output_rate=400.0)
    rv = RandomVibration(breakpoints=((20.0, 0.01), (80.0, 0.04), (350.0, 0.04), (1000.0, 0.0114)), duration=2.0)
    rec = model.simulate(rv, rng=rng)
    n = 16000
    fk = np.fft.rfftfreq(n, 1 / 8000.0)
    a2 = 2.0 * rv.shaped_psd(fk) * (8000.0 / n) * G**2
    a2[0] = 0.0
    expected = c * np.sum(a2 * np.abs(mode.response(fk, 8000.0)) ** 2)
    assert np.mean(rec["truth/vibration_bias"]) == pytest.approx(expected, rel=1e-3)
    assert np.all(rec["shaker_frequency"] == 0.0)  # no drive frequency is defined for random vibration


def test_random_vibration_needs_physics_rate_for_its_band(rng):
    from gyrobench.sim.shaker import RandomVibration

    rv = RandomVibration(breakpoints=((20.0, 0.01), (2000.0, 0.01)), duration=1.0)
    with pytest.raises(ValueError, match=r"vibration up to 2000.0 Hz needs physics_rate >= 8000.0 Hz"):
        FogVibrationModel().simulate(rv, rng=rng)
