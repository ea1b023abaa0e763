"""The default MEMS noise of sim/mems_resonator.py: cited levels, the output word, a record's Allan fit.

The defaults are one cited part's, the ADXRS646's: its printed angle random walk and its printed
bias drift (read as the ADEV floor), no rate random walk (its front page prints none), a 20-bit
word (a design choice) whose LSB is below the sample noise at every output rate >= 1 Hz,
turn-on bias and scale-factor repeatability as cited in
:class:`~gyrobench.sim.mems_resonator.MemsResonator`.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from gyrobench.base import units
from gyrobench.sim import mems_resonator as mr
from gyrobench.sim import mems_slow_flow
from gyrobench.sim.mems_population import MemsResonatorSpec
from gyrobench.sim.mems_resonator import NOISE_FIGURES, MemsResonator

Z_1E6 = 4.8916  # two-sided standard-normal quantile at a false-alarm rate of 1e-6


def _n_total(unit: MemsResonator) -> float:
    """Input-referred white rate noise N [rad/sqrt(s)] (Brownian and pick-off)."""
    return math.hypot(mr.brownian_arw(unit), mr.electronic_arw(unit))


# ------------------------------------------------------------------ the printed figures
def test_cited_figures_are_one_parts_printed_values_with_their_units():
    assert set(NOISE_FIGURES) == {"angle_random_walk", "bias_drift"}
    assert (NOISE_FIGURES["angle_random_walk"].value, NOISE_FIGURES["angle_random_walk"].unit) == (
        0.01, "deg/sqrt(s)")
    assert (NOISE_FIGURES["bias_drift"].value, NOISE_FIGURES["bias_drift"].unit) == (12.0, "deg/h")
    assert all("ADXRS646" in f.source for f in NOISE_FIGURES.values())  # one part for every figure
    # ADEV minimum of a flicker term over B: sqrt(2 ln2/pi), printed as 0.664 in IEEE 952
    assert mr.ADEV_MIN_PER_B == pytest.approx(0.6643, abs=5e-5)


def test_default_white_noise_is_the_adxrs646_arw():
    """N = 0.01 deg/sqrt(s) to the 5 digits stored."""
    n = units.to_deg_per_s(_n_total(MemsResonator()))
    # DEFAULT_PICKOFF_NOISE is stored to 5 digits: half a unit in the 5th is 2.2e-5 of it
    assert n == pytest.approx(0.01, rel=0.5e-4 / 2.2658)
    assert units.to_deg_per_sqrt_h(_n_total(MemsResonator())) == pytest.approx(0.6, rel=1e-4)


def test_default_bias_instability_is_the_adxrs646_floor():
    b = MemsResonator().bias_instability
    assert units.to_deg_per_h(b) == pytest.approx(12.0 / mr.ADEV_MIN_PER_B, rel=1e-12)
    assert units.to_deg_per_h(mr.ADEV_MIN_PER_B * b) == pytest.approx(12.0, rel=1e-12)  # the ADEV floor
    assert MemsResonator().rate_random_walk == 0.0  # no sheet read prints one
    assert mr.FLICKER_BAND_HZ == (1e-6, math.inf)


def test_default_turn_on_errors_are_the_cited_values():
    """Turn-on bias 0.1 deg/s and SF repeatability 1000 ppm, 1 sigma (MemsResonator docstring)."""
    u = MemsResonator()
    assert units.to_deg_per_s(u.bias_repeatability) == pytest.approx(0.1, rel=1e-12)
    assert units.to_ppm(u.scale_factor_repeatability) == pytest.approx(1000.0, rel=1e-12)


def test_output_lsb_is_below_the_noise_at_every_output_rate():
    """q = 2 R / 2^20 = 0.0076 deg/s, below the per-sample noise N sqrt(fs) down to fs = 1 Hz."""
    u = MemsResonator()
    q = units.to_deg_per_s(u.resolution)
    assert q == pytest.approx(8000.0 / 2**20, rel=1e-12)
    n = units.to_deg_per_s(_n_total(u)) * mr.low_rate_scale_factor(u)
    assert q < n * math.sqrt(1.0)


def test_datasheet_constructor_passes_rate_random_walk_and_the_word():
    spec = MemsResonatorSpec.from_datasheet(noise_density_convention="two-sided",
                                            bias_instability_dph=37.6, rate_random_walk_dph_rth=3.0)
    assert units.to_deg_per_h_per_sqrt_h(spec.nominal.rate_random_walk) == pytest.approx(3.0, rel=1e-12)
    assert spec.nominal.output_bits == 20


def test_rate_random_walk_reaches_the_output(rng):
    """A K-only output (noise=False: no Brownian or pick-off noise; no 1/f, no ADC): half the
    mean square of the difference of two consecutive 100-s block means is the AVAR at 100 s,
    K^2 tau/3 (1 + 1/(2 m^2)) (the sampled form, docs/physics.md 2). Each column's difference
    depends only on the walk's increments inside it, so the 64 columns are independent:
    chi-square(64) bounds at 1e-6 two-sided."""
    from scipy import stats

    k = units.deg_per_h_per_sqrt_h(100.0)
    unit = replace(MemsResonator(), bias_instability=0.0, rate_random_walk=k, output_bits=None)
    fs, tau, cols = 10.0, 100.0, 64
    m = int(tau * fs)
    res = mems_slow_flow.slow_flow(unit, np.zeros((2 * m, cols)), fs=fs, rng=rng, noise=False, adc=False)
    means = res.output.reshape(2, m, cols).mean(axis=1)
    avar = 0.5 * np.mean((means[1] - means[0]) ** 2)
    theory = k**2 * tau / 3.0 * (1.0 + 0.5 / m**2)
    lo, hi = stats.chi2.ppf([5e-7, 1 - 5e-7], cols) / cols
    assert lo <= avar / theory <= hi


# ------------------------------------------------------------------ a small rate at 10 Hz
def _paired_half_difference(unit: MemsResonator, rate: float, fs: float, dur: float, seed: int) -> float:
    """(mean out(+rate) - mean out(-rate)) / 2 from two runs with the same noise (same seed)."""
    n = int(round(dur * fs))
    up = mems_slow_flow.slow_flow(unit, np.full(n, rate), fs=fs, rng=np.random.default_rng(seed)).output
    down = mems_slow_flow.slow_flow(unit, np.full(n, -rate), fs=fs, rng=np.random.default_rng(seed)).output
    return float(up.mean() - down.mean()) / 2.0


def test_plus_minus_five_hundredths_deg_per_s_reads_within_10_percent_at_10_hz():
    """+-0.05 deg/s at 10 Hz reads SF x 0.05 deg/s: the quantizer does not bend small rates.

    The slow flow is linear and its noise additive, so two runs with the same seed differ only
    by the input and by the ADC's rounding: a paired half-difference isolates the response
    (the sensor's own noise, 0.01 deg/sqrt(s) with a 12 deg/h floor, would take a long record
    to average below 10 % of 0.05 deg/s, on any output word). The noise dithers the 20-bit
    quantizer (sample noise 0.032 deg/s = 4.1 q): each rounding error is uniform on +-q/2 and
    independent, so the half-difference's error has sd q / sqrt(24 n); bound Z(1e-6) sd plus
    the dithered quantizer's bias bound (q/pi) exp(-2 pi^2 sigma^2/q^2). The bound is itself
    below 10 % of the input (asserted). The old default (16-bit word, pick-off noise 1e-13
    m/sqrt(Hz), no 1/f) fails the same reading: its sample noise is below the LSB.
    """
    fs, dur, seed = 10.0, 60.0, 20261127
    w = units.deg_per_s(0.05)
    unit = MemsResonator()
    sf = mr.low_rate_scale_factor(unit)
    q = unit.resolution
    n = int(round(dur * fs))
    sigma = sf * _n_total(unit) * math.sqrt(fs)
    bound = Z_1E6 * q / math.sqrt(24.0 * n) + q / math.pi * math.exp(-2 * math.pi**2 * sigma**2 / q**2)
    assert bound < 0.1 * sf * w
    got = _paired_half_difference(unit, w, fs, dur, seed)
    assert abs(got - sf * w) <= bound
    old = replace(unit, output_bits=16, pickoff_noise=1e-13, bias_instability=0.0)
    got_old = _paired_half_difference(old, w, fs, dur, seed)
    assert abs(got_old - sf * w) > 0.1 * sf * w


# ------------------------------------------------------------------ a static record's Allan fit
@pytest.mark.slow  # about 10 s: 2e5 s of 10-Hz slow flow (2e6 samples) and its Allan fit
def test_default_static_record_at_10_hz_fits_n_and_shows_the_bias_instability_floor():
    """A drawn default unit, 55.6 h at rest at 10 Hz (20-bit ADC, 1/f term on): the joint Allan fit
    (tau_min "auto": the rebalance loop bends the first octave; tau_max 14000 s, where the pole
    sum's 1/f band keeps the ADEV flat within 1 %) finds N and identifies B, each within
    Z(1e-6) of its 68 % half-width of the model's value (N x SF; B added after the scale factor)."""
    from gyrobench.analysis.allan import fit_noise

    r_unit, r_sim = np.random.default_rng(20261127).spawn(2)
    unit = MemsResonatorSpec().realize(rng=r_unit)
    fs, dur = 10.0, 2e5
    res = mems_slow_flow.slow_flow(unit, np.zeros(int(dur * fs)), fs=fs, rng=r_sim)
    fit = fit_noise(units.to_deg_per_s(res.output), fs, tau_min="auto", tau_max=14000.0)
    n_model = units.to_deg_per_s(_n_total(unit) * mr.low_rate_scale_factor(unit))
    b_model = units.to_deg_per_s(unit.bias_instability)
    for name, model in (("N", n_model), ("B", b_model)):
        c = fit.coefficients[name]
        assert c.identifiable, name
        half = (c.ci68[1] - c.ci68[0]) / 2.0
        assert abs(c.value - model) <= Z_1E6 * half, (name, c.value, model, half)
    assert not fit.misfit
