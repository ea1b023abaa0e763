"""Tests of sim/mems_resonator.py: closed forms, slow-flow equilibrium, continuity, population.

The full-integration checks (slow flow vs RK4, noise level, authority) run in
tests/scenarios/test_checks_mems.py through scenarios.checks_mems.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from gyrobench.base import units
from gyrobench.sim import mems_slow_flow
from gyrobench.sim.mems_full import simulate_full
from gyrobench.sim.mems_population import MemsResonatorSpec, factory_trim
from gyrobench.sim.mems_resonator import (
    BOLTZMANN,
    MemsResonator,
    brownian_arw,
    electronic_arw,
    low_rate_scale_factor,
    operating_point,
    quadrature_rate,
    rate_authority,
    saturated_output,
    zero_rate_output,
)
from gyrobench.sim.mems_slow_flow import rate_table, slow_flow

Z = 4.89  # two-sided normal quantile at a 1e-6 false-alarm rate


def _quiet(**kw) -> MemsResonator:
    """Default design without noise sources in the output stage (no ADC, no 1/f)."""
    base = dict(output_bits=None, bias_instability=0.0)
    base.update(kw)
    return MemsResonator(**base)


def _settled(unit, rates, temperature=None):
    res = slow_flow(unit, np.tile(rates, (40, 1)), fs=1000.0, rng=np.random.default_rng(0),
                   temperature=temperature, noise=False, adc=False, flicker=False)
    return res.output[-1]


# ------------------------------------------------------------------ closed forms
def test_brownian_arw_matches_the_physics_notes_example():
    # docs/physics.md 5.1: m = 2e-9 kg, 20 kHz, Q_y = 1e4, X = 5 um, 300 K, matched -> 8.12e-6
    unit = _quiet(drive_frequency=20e3, mode_split=0.0, sense_q=1e4, loop_bandwidth=0.2,
                  reference_temperature=300.0)
    n_b = brownian_arw(unit)
    w = 2 * math.pi * 20e3
    assert n_b == pytest.approx(math.sqrt(BOLTZMANN * 300.0 / (2e-9 * 1e4 * 25e-12 * w)), rel=1e-12)
    assert n_b == pytest.approx(8.12e-6, rel=5e-4)  # the notes print 3 figures


def test_quadrature_rate_matches_the_physics_notes_example():
    # docs/physics.md 5.1: m = 2 ug, 20 kHz, k_yx = 1e-4 k -> Omega_q = 6.283 rad/s
    unit = _quiet(drive_frequency=20e3, quadrature_coupling=1e-4)
    assert quadrature_rate(unit) == pytest.approx(1e-4 * 2 * math.pi * 20e3 / 2, rel=1e-12)
    assert quadrature_rate(unit) == pytest.approx(6.283, rel=1e-4)


def test_electronic_arw_is_pickoff_noise_over_open_loop_sensitivity():
    unit = _quiet(pickoff_noise=2e-13)
    op = operating_point(unit)
    dy_dw = 2 * op.m * op.wx * op.x0 / abs(op.ky - op.m * op.wx**2 + 1j * op.cy * op.wx)
    assert electronic_arw(unit) == pytest.approx(2e-13 / dy_dw, rel=1e-12)


def test_authority_without_quadrature_is_f_max_over_coriolis_gain():
    unit = _quiet()
    op = operating_point(unit)
    expected = op.gain * unit.dac_full_scale / op.coriolis_gain
    assert rate_authority(unit) == pytest.approx(expected, rel=1e-12)
    # with quadrature (theta = 0): sqrt(F_max^2 - F_q^2) / (2 m w X0)
    uq = _quiet(quadrature_coupling=3e-4)
    opq = operating_point(uq)
    fq = opq.kyx * opq.x0
    fmax = opq.gain * uq.dac_full_scale
    expected_q = math.sqrt(fmax**2 - fq**2) / opq.coriolis_gain
    assert rate_authority(uq) == pytest.approx(expected_q, rel=1e-12)


# ------------------------------------------------------------------ slow-flow equilibrium
@pytest.mark.parametrize("theta", [0.0, 0.01, -0.03])
def test_slow_flow_settles_on_the_closed_form_output(theta):
    unit = _quiet(quadrature_coupling=2e-4, damping_coupling=1e-3, phase_error=theta)
    t = unit.reference_temperature + 15.0
    w = units.deg_per_s(np.array([-1000.0, 0.0, 500.0, 3000.0]))
    out = _settled(unit, w, t)
    sf = low_rate_scale_factor(unit, t)
    np.testing.assert_allclose(out, sf * w + zero_rate_output(unit, t), rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("theta", [0.0, 0.005, 0.02, -0.02])
def test_quadrature_leaks_as_omega_q_sin_theta(theta):
    unit = _quiet(quadrature_coupling=2e-4, phase_error=theta)
    out = _settled(unit, np.zeros(1))[0]
    # untrimmed: K_out = G0/(2 m w0 X0), so Omega_hat(0) = -Omega_q sin(theta) exactly
    assert out == pytest.approx(-quadrature_rate(unit) * math.sin(theta), abs=1e-12)


def test_scale_factor_tempco_follows_frequency_and_gain_tempcos():
    unit = _quiet(frequency_tc=-30e-6, gain_tc=50e-6, phase_tc=0.0)
    t0 = unit.reference_temperature
    sf = low_rate_scale_factor(unit, t0 + 10.0)
    assert sf == pytest.approx((1 - 30e-6 * 10) / (1 + 50e-6 * 10), rel=1e-12)
    w = units.deg_per_s(np.array([0.0, 1000.0]))
    out = _settled(unit, w, t0 + 10.0)
    assert (out[1] - out[0]) / w[1] == pytest.approx(sf, rel=1e-9)


def test_bias_tempco_through_the_damping_tempco():
    # theta = 0: Omega_hat(0, T) = SF(T) eps_c w_y(T) (1 + b_Q dT) / (2 Q_y0)   [c_yx / (2m)]
    unit = _quiet(damping_coupling=1e-3, phase_tc=0.0, q_tc=3e-3, frequency_tc=-30e-6)
    for dt in (-20.0, 0.0, 30.0):
        t = unit.reference_temperature + dt
        wy = 2 * math.pi * (unit.drive_frequency + unit.mode_split) * (1 - 30e-6 * dt)
        expected = low_rate_scale_factor(unit, t) * 1e-3 * wy * (1 + 3e-3 * dt) / (2 * unit.sense_q)
        assert zero_rate_output(unit, t) == pytest.approx(expected, rel=1e-12)
        assert _settled(unit, np.zeros(1), t)[0] == pytest.approx(expected, rel=1e-9)


def test_output_saturates_beyond_the_authority():
    unit = _quiet(quadrature_coupling=1e-4, phase_error=0.01)
    auth = rate_authority(unit)
    w = np.array([1.05, 1.5, 3.0, -2.0]) * auth
    out = _settled(unit, w)
    expected = [saturated_output(unit, x) for x in w]
    # u_I is held over each saturated step while u_Q still converges: 1e-6, not rounding
    np.testing.assert_allclose(out, expected, rtol=1e-6)
    sf, zro = low_rate_scale_factor(unit), zero_rate_output(unit)
    # flat: from 1.05x to 3x the authority the plateau moves by < 2e-4 of the onset value
    # SF Omega_max + Omega_hat(0) (it drifts as the uncancelled force rotates B)
    np.testing.assert_allclose(out[:3], sf * auth + zro, rtol=2e-4)
    below = _settled(unit, np.array([0.99 * auth]))
    assert below[0] == pytest.approx(sf * 0.99 * auth + zro, rel=1e-9)


def test_linear_fast_path_equals_the_clamped_loop():
    """The all-steps eigenbasis recursion and the step-by-step loop agree below the DAC limit."""

    unit = _quiet(quadrature_coupling=1e-4, phase_error=0.01)
    op = operating_point(unit)
    n, k = 2000, 3
    w = np.tile(units.deg_per_s(np.array([-3000.0, 0.0, 2000.0])), (n, 1))
    w[n // 2:] *= 0.5  # a rate step inside the record
    d = mems_slow_flow._fext(op, w, np.zeros_like(w))
    disc = mems_slow_flow._slow_matrices(op, unit, 1 / 200.0, True)
    sat = mems_slow_flow._slow_matrices(op, unit, 1 / 200.0, True, saturated=True)
    z = mems_slow_flow._draw_noise(np.random.default_rng(2), n, k)
    s0 = np.zeros((k, 5))
    u1, q1, b1, bad = mems_slow_flow._run_linear(s0, d, z, disc, op.v_max)
    u2, q2, b2 = mems_slow_flow._run_clamped(s0, d, z, disc, sat, op.v_max)
    assert not np.any(bad)
    np.testing.assert_allclose(u1, u2, rtol=0, atol=1e-9 * op.v_max)
    np.testing.assert_allclose(q1, q2, rtol=0, atol=1e-9 * op.v_max)
    np.testing.assert_allclose(b1, b2, rtol=0, atol=1e-9 * np.max(np.abs(b2)))


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_segmented_solver_equals_the_step_loop():
    """The saturated-segment solver takes the loop's steps: equal to rounding.

    Columns: deep saturation of both signs, a rate stepping out of and back into saturation,
    one stepping in, and two within 1e-5 of the knee (noise dithers them across it, so they
    exercise the switch limit and the step-by-step fallback). 1e-9 of v_max (of max |B|) is
    rounding of a 12000-step recursion solved in a different order, not a model tolerance.
    """
    from gyrobench.sim import mems_resonator as mr

    unit = _quiet(quadrature_coupling=2e-4, phase_error=0.02, damping_coupling=5e-4,
                  dac_full_scale=0.44)
    op = operating_point(unit)
    auth = rate_authority(unit)
    fs, n = 200.0, 12000
    w = np.tile(np.array([3.0, 1.2, -1.5, 1.00001, 0.99999, 0.5]) * auth, (n, 1))
    w[n // 3:2 * n // 3, 1] = 0.5 * auth
    w[n // 2:, 5] = 2.0 * auth
    acc = np.gradient(w, axis=0) * fs
    d = mems_slow_flow._fext(op, w, acc)
    disc = mems_slow_flow._slow_matrices(op, unit, 1 / fs, True)
    sat = mems_slow_flow._slow_matrices(op, unit, 1 / fs, True, saturated=True)
    z = mems_slow_flow._draw_noise(np.random.default_rng(3), n, w.shape[1])
    u = mr._equilibrium_command(op, w[0], acc[0])
    ui, uq, _ = mr._clamp(u.real, u.imag, op.v_max)
    b = op.receptance * ((d[0, :, 0] + 1j * d[0, :, 1]) + 1j * op.gain
                         * np.exp(1j * op.theta) * (ui + 1j * uq))
    s0 = np.stack([b.real, b.imag, ui, uq, np.zeros(w.shape[1])], axis=1)
    u1, q1, b1 = mems_slow_flow._run_clamped(s0, d, z, disc, sat, op.v_max)
    u2, q2, b2 = mems_slow_flow._run_segmented(s0, d, z, disc, sat, op.v_max)
    assert np.all(np.abs(u1[n // 2:, 0]) > 0.9 * op.v_max)  # really saturated
    np.testing.assert_allclose(u2, u1, rtol=0, atol=1e-9 * op.v_max)
    np.testing.assert_allclose(q2, q1, rtol=0, atol=1e-9 * op.v_max)
    np.testing.assert_allclose(b2, b1, rtol=0, atol=1e-9 * np.max(np.abs(b1)))


# ------------------------------------------------------------------ full integration (short)
@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_full_integration_agrees_with_the_slow_flow():
    """RK4 with the carrier (16 steps per period) vs the slow flow, below and beyond the knee.

    Tolerance: RK4's relative frequency error (w dt)^4/120, carried by the Coriolis force, the
    AGC amplitude estimate and the demodulation references: 3 (w dt)^4/120 (relative to the
    rate, floor 100 deg/s).
    """
    unit = _quiet(quadrature_coupling=1e-4, phase_error=0.01)
    w = units.deg_per_s(np.array([0.0, 1000.0, 6000.0]))
    full = simulate_full(unit, w, duration=0.045, fs=1000.0, rng=np.random.default_rng(0),
                         steps_per_cycle=16, noise=False, adc=False)
    got = full.output[-5:].mean(axis=0)
    slow = _settled(unit, w)
    tol = 3 * (2 * math.pi / 16) ** 4 / 120
    scale = np.maximum(np.abs(w), units.deg_per_s(100.0))
    assert np.all(np.abs(got - slow) / scale <= tol)


# ------------------------------------------------------------------ continuity through zero
def test_no_step_at_zero_rate_noise_free():
    unit = _quiet(quadrature_coupling=1e-4, phase_error=0.01, damping_coupling=1e-3)
    w = units.deg_per_s(np.array([-0.3, -0.2, -0.1, 0.0, 0.1, 0.2, 0.3]))
    out = _settled(unit, w)
    sf = low_rate_scale_factor(unit)
    np.testing.assert_allclose(np.diff(out), sf * np.diff(w), rtol=1e-9)


def test_plus_minus_tenth_deg_per_s_reads_within_the_noise(rng):
    # with noise and a 16-bit ADC; the earlier quiet front end and no 1/f term, so the bound
    # (white noise of the means plus the dither bias) stays tight and complete
    unit = MemsResonator(quadrature_coupling=1e-4, phase_error=0.01, output_bits=16,
                         pickoff_noise=1e-13, bias_instability=0.0)
    fs, dur = 200.0, 20.0
    w = units.deg_per_s(0.1)
    res = slow_flow(unit, np.tile([w, -w, 0.0], (int(dur * fs), 1)), fs=fs, rng=rng)
    zro = zero_rate_output(unit)
    sf = low_rate_scale_factor(unit)
    n = math.hypot(brownian_arw(unit), electronic_arw(unit)) * sf
    sd = n / math.sqrt(dur)
    q = unit.resolution
    dither = q / math.pi * math.exp(-2 * math.pi**2 * (n * math.sqrt(fs)) ** 2 / q**2)
    got = res.output.mean(axis=0) - zro
    np.testing.assert_allclose(got, [sf * w, -sf * w, 0.0], atol=Z * sd + dither, rtol=0)


# ------------------------------------------------------------------ noise level (slow flow)
def test_slow_flow_noise_level_matches_the_closed_form(rng):
    unit = _quiet(quadrature_coupling=1e-4)
    fs, cols, dur, block = 200.0, 16, 100.0, 1.0
    n = int(dur * fs)
    res = slow_flow(unit, np.zeros((n, cols)), fs=fs, rng=rng, adc=False, flicker=False)
    m = int(block * fs)
    means = res.output.reshape(n // m, m, cols).mean(axis=1) - zero_rate_output(unit)
    n_hat = math.sqrt(np.mean(means**2) * block)
    n_cf = math.hypot(brownian_arw(unit), electronic_arw(unit))
    from scipy import stats

    dof = means.size
    lo = math.sqrt(stats.chi2.ppf(5e-7, dof) / dof)
    hi = math.sqrt(stats.chi2.ppf(1 - 5e-7, dof) / dof)
    bias = 2.0 / (block * float(np.min(-operating_point(unit).loop_poles.real)))
    assert lo * (1 - bias) <= n_hat / n_cf <= hi


@pytest.mark.parametrize("fs", [1.0, 4.0, 8.0])
def test_noise_level_holds_at_output_rates_far_below_the_loop(fs, rng):
    """At fs where -Re(pole)/fs >> 1 (the default unit: 60 at 8 Hz, 490 at 1 Hz) the exact
    discretisation's noise covariance must not cancel away: each sample is the interval mean of
    the rate-equivalent white noise, variance N^2 fs (up to the loop's settling, ``bias``). The
    Van Loan product alone gave 48x (8 Hz) to ~9000x (2 Hz) the closed form."""
    unit = _quiet(quadrature_coupling=1e-4)
    cols, n = 16, 1000
    res = slow_flow(unit, np.zeros((n, cols)), fs=fs, rng=rng, adc=False, flicker=False)
    means = res.output - zero_rate_output(unit)
    n_hat = math.sqrt(np.mean(means**2) / fs)
    n_cf = math.hypot(brownian_arw(unit), electronic_arw(unit))
    from scipy import stats

    dof = means.size
    lo = math.sqrt(stats.chi2.ppf(5e-7, dof) / dof)
    hi = math.sqrt(stats.chi2.ppf(1 - 5e-7, dof) / dof)
    bias = 2.0 * fs / float(np.min(-operating_point(unit).loop_poles.real))
    assert lo * (1 - bias) <= n_hat / n_cf <= hi


@pytest.mark.parametrize(
    "kw",
    [
        dict(mass=4e-9),
        dict(sense_q=60.0),
        dict(reference_temperature=350.0),
        dict(drive_amplitude=2.5e-6),
        dict(drive_frequency=10e3, mode_split=300.0),
    ],
)
def test_brownian_arw_scales_with_mass_q_temperature_amplitude_frequency(kw, rng):
    """N_B = sqrt(k_B T w_y/(m Q_y))/(w X0) across the parameters it names (Brownian only)."""
    unit = _quiet(pickoff_noise=0.0, **kw)
    fs, cols, dur, block = 200.0, 16, 100.0, 1.0
    n = int(dur * fs)
    res = slow_flow(unit, np.zeros((n, cols)), fs=fs, rng=rng, adc=False, flicker=False)
    m = int(block * fs)
    means = res.output.reshape(n // m, m, cols).mean(axis=1) - zero_rate_output(unit)
    n_hat = math.sqrt(np.mean(means**2) * block) / low_rate_scale_factor(unit)
    op = operating_point(unit)
    n_cf = math.sqrt(BOLTZMANN * op.temperature * op.wy / (op.m * unit.sense_q)) / (op.wx * op.x0)
    assert brownian_arw(unit) == pytest.approx(n_cf, rel=1e-12)
    from scipy import stats

    dof = means.size
    lo = math.sqrt(stats.chi2.ppf(5e-7, dof) / dof)
    hi = math.sqrt(stats.chi2.ppf(1 - 5e-7, dof) / dof)
    bias = 2.0 / (block * float(np.min(-op.loop_poles.real)))
    assert lo * (1 - bias) <= n_hat / n_cf <= hi


def test_quantization_and_range(rng):
    unit = MemsResonator(pickoff_noise=0.0)
    res = slow_flow(unit, np.full(50, 2.0 * unit.output_range), fs=200.0, rng=rng)
    q = unit.resolution
    assert np.all(np.abs(res.output) <= unit.output_range)
    np.testing.assert_allclose(res.output / q, np.round(res.output / q), atol=1e-9)


# ------------------------------------------------------------------ determinism and shapes
def test_seed_gives_bit_identical_output():
    unit = MemsResonator(bias_instability=units.deg_per_h(20.0))
    w = np.linspace(0, 1, 300)
    a = slow_flow(unit, w, fs=200.0, rng=np.random.default_rng(7)).output
    b = slow_flow(unit, w, fs=200.0, rng=np.random.default_rng(7)).output
    assert np.array_equal(a, b) and a.shape == (300,)


def test_full_integration_seed_is_bit_identical():
    unit = _quiet()
    kw = dict(duration=0.002, fs=1000.0, steps_per_cycle=16)
    a = simulate_full(unit, [0.0, 1.0], rng=np.random.default_rng(3), **kw).output
    b = simulate_full(unit, [0.0, 1.0], rng=np.random.default_rng(3), **kw).output
    assert np.array_equal(a, b) and a.shape == (2, 2)


def test_full_integration_cases_do_not_depend_on_their_companions():
    """Noise-free cases are integrated column by column (elementwise operations only), so a case
    gives the same bits alone or among 3000 others, whose read-outs are summed in chunks of
    steps (2^18 / k = 87 of the 300 per output sample) instead of in one block."""
    unit = _quiet(quadrature_coupling=1e-4)
    kw = dict(duration=0.002, fs=1000.0, steps_per_cycle=20, noise=False, adc=False)
    rates = np.linspace(-1.0, 1.0, 3000)
    many = simulate_full(unit, rates, rng=np.random.default_rng(0), **kw)
    few = simulate_full(unit, rates[[0, 1234, 2999]], rng=np.random.default_rng(0), **kw)
    for name in ("output", "drive_amplitude", "sense_envelope"):
        assert np.array_equal(getattr(many, name)[:, [0, 1234, 2999]], getattr(few, name))


def test_rate_table_means_follow_the_scale_factor(rng):
    unit = _quiet(quadrature_coupling=1e-4)
    w = units.deg_per_s(np.array([-3600.0, 0.0, 3600.0]))
    means = rate_table(unit, w, rng=rng, average_s=10.0)
    sf = low_rate_scale_factor(unit)
    n = math.hypot(brownian_arw(unit), electronic_arw(unit)) * sf
    np.testing.assert_allclose(means, sf * w + zero_rate_output(unit), atol=Z * n / math.sqrt(10.0))


# ------------------------------------------------------------------ population
def test_realize_is_deterministic_and_trimmed():
    spec = MemsResonatorSpec(nominal=_quiet())
    a = spec.realize(rng=np.random.default_rng(5))
    b = spec.realize(rng=np.random.default_rng(5))
    assert a == b
    assert low_rate_scale_factor(a) == pytest.approx(1.0, rel=1e-12)
    assert zero_rate_output(a) == pytest.approx(0.0, abs=1e-12)
    assert a.mass != spec.nominal.mass and a.quadrature_coupling != 0.0


def test_zero_spread_population_is_the_nominal_unit():
    nominal = _quiet(quadrature_coupling=1e-4)
    spec = MemsResonatorSpec(
        nominal=nominal, mass_spread=0, frequency_spread=0, split_spread=0, q_spread=0,
        gap_spread=0, quadrature_spread=0, damping_coupling_spread=0, phase_error_spread=0,
        phase_tc_spread=0,
    )
    assert spec.realize(rng=np.random.default_rng(1)) == factory_trim(nominal)


def test_power_on_draws_turn_on_errors():
    unit = _quiet(bias_repeatability=1e-3, scale_factor_repeatability=1e-3)
    draws = [unit.power_on(rng=np.random.default_rng(i)) for i in range(400)]
    b = np.array([d.turn_on_bias for d in draws])
    e = np.array([d.turn_on_scale_factor for d in draws])
    from scipy import stats

    lo, hi = stats.chi2.ppf([5e-7, 1 - 5e-7], 400) / 400
    assert lo <= np.mean(b**2) / 1e-6 <= hi and lo <= np.mean(e**2) / 1e-6 <= hi
    d0 = draws[0]
    assert low_rate_scale_factor(d0) == pytest.approx(1 + d0.turn_on_scale_factor, rel=1e-12)


def test_datasheet_noise_convention_is_explicit():
    two = MemsResonatorSpec.from_datasheet(noise_density_dps_rthz=0.01,
                                           noise_density_convention="two-sided")
    one = MemsResonatorSpec.from_datasheet(noise_density_dps_rthz=0.01,
                                           noise_density_convention="one-sided")
    n2 = math.hypot(brownian_arw(two.nominal), electronic_arw(two.nominal))
    n1 = math.hypot(brownian_arw(one.nominal), electronic_arw(one.nominal))
    assert n2 == pytest.approx(units.deg_per_s(0.01), rel=1e-9)
    assert n1 == pytest.approx(units.deg_per_s(0.01) / math.sqrt(2), rel=1e-9)
    with pytest.raises(ValueError, match="noise_density_convention"):
        MemsResonatorSpec.from_datasheet(noise_density_convention="psd")
    with pytest.raises(ValueError, match="Brownian floor"):
        MemsResonatorSpec.from_datasheet(noise_density_dps_rthz=1e-5,
                                         noise_density_convention="two-sided")


def test_datasheet_range_sets_the_authority():
    spec = MemsResonatorSpec.from_datasheet(range_dps=3600.0, range_margin=1.25,
                                            noise_density_convention="two-sided")
    assert rate_authority(spec.nominal) == pytest.approx(units.deg_per_s(4500.0), rel=1e-9)


def test_datasheet_range_sets_the_open_loop_knee():
    spec = MemsResonatorSpec.from_datasheet(range_dps=3600.0, range_margin=1.25,
                                            noise_density_convention="two-sided",
                                            nominal=MemsResonator(readout="open_loop"))
    assert rate_authority(spec.nominal) == pytest.approx(units.deg_per_s(4500.0), rel=1e-9)


def test_datasheet_nonlinearity_sets_the_cubic():
    spec = MemsResonatorSpec.from_datasheet(nonlinearity_pct_fs=0.1,
                                            noise_density_convention="two-sided", output_bits=None)
    w = units.deg_per_s(np.linspace(-3600, 3600, 21))
    out = _settled(spec.nominal, w)
    k, f0 = np.polyfit(w, out, 1)
    kn = np.max(np.abs(out - (k * w + f0))) / np.max(np.abs(out))
    assert kn == pytest.approx(1e-3, rel=0.01)  # first order in a3: a3 K_n^2 ~ 1e-3 relative


# ------------------------------------------------------------------ bad input
@pytest.mark.parametrize(
    ("kw", "match"),
    [
        (dict(mass=0.0), r"mass must be \(0, 0.001\] kg; got 0.0"),
        (dict(sense_q=-1.0), r"sense_q must be \(0, 1e\+07\] 1; got -1.0"),
        (dict(pickoff_noise=-1e-12), r"pickoff_noise must be \[0, 1e-06\] m/sqrt\(Hz\); got -1e-12"),
        (dict(output_bits=1), r"output_bits must be an integer in \[2, 64\] bits; got 1"),
        (dict(phase_error=2.0), r"phase_error must be \(-1.5708, 1.5708\) rad; got 2.0"),
        (dict(mode_split=-2e4), "mode_split must keep"),
    ],
)
def test_bad_parameters_name_themselves(kw, match):
    with pytest.raises(ValueError, match=match):
        MemsResonator(**kw)


def test_wrong_kinds_raise_type_error():
    with pytest.raises(TypeError, match="mass must be a real number"):
        MemsResonator(mass="2e-9")
    with pytest.raises(TypeError, match="rng must be a numpy.random.Generator"):
        slow_flow(MemsResonator(), [0.0], fs=200.0, rng=1)
    with pytest.raises(TypeError, match="nominal must be a MemsResonator"):
        MemsResonatorSpec(nominal=1)


def test_unstable_loop_is_refused():
    with pytest.raises(ValueError, match="rebalance loop unstable"):
        operating_point(MemsResonator(sense_q=5000.0))


def test_bad_rate_input():
    with pytest.raises(ValueError, match="rate must be a finite"):
        slow_flow(MemsResonator(), [0.0, np.nan], fs=200.0, rng=np.random.default_rng(0))
    with pytest.raises(ValueError, match="fs must be > 0"):
        slow_flow(MemsResonator(), [0.0], fs=0.0, rng=np.random.default_rng(0))
    with pytest.raises(ValueError, match="steps_per_cycle"):
        simulate_full(MemsResonator(), [0.0], duration=0.01, rng=np.random.default_rng(0),
                      steps_per_cycle=4)


def test_frozen():
    with pytest.raises(dataclasses.FrozenInstanceError):
        MemsResonator().mass = 1.0  # type: ignore[misc]


# ------------------------------------------------------------------ g-sensitivity
G0 = 9.80665  # standard gravity [m/s^2]


def test_electrostatic_cross_stiffness_is_the_parallel_plate_term():
    """dk_yx/df = k_e eps_A m / k_y with k_e = 2 eps0 A V_b^2 / g^3 (independent arithmetic)."""
    from gyrobench.sim.mems_resonator import EPSILON_0, electrostatic_cross_stiffness

    unit = _quiet(forcer_area_gradient=3e4)
    k_e = 2 * EPSILON_0 * unit.electrode_area * unit.bias_voltage**2 / unit.electrode_gap**3
    k_y = unit.mass * (2 * math.pi * (unit.drive_frequency + unit.mode_split)) ** 2
    expected = k_e * 3e4 * unit.mass / k_y
    assert electrostatic_cross_stiffness(unit) == pytest.approx(expected, rel=1e-12)
    assert electrostatic_cross_stiffness(_quiet(forcer_area_gradient=0.0)) == 0.0


@pytest.mark.parametrize("theta", [0.0, 0.005, -0.02])
def test_g_sensitivity_is_the_quadrature_leak_of_the_cross_stiffness(theta):
    from gyrobench.sim.mems_resonator import electrostatic_cross_stiffness, g_sensitivity

    unit = _quiet(quadrature_coupling=1e-4, damping_coupling=5e-4, phase_error=theta)
    op = operating_point(unit)
    sf = low_rate_scale_factor(unit)
    expected = -sf * math.tan(theta) * electrostatic_cross_stiffness(unit) / (2 * op.m * op.wx)
    gs = g_sensitivity(unit)
    assert gs == pytest.approx(expected, rel=1e-9, abs=1e-18)
    # the slow flow with a specific-force profile: +-5 g and 0 at zero rate
    f = np.array([5 * G0, -5 * G0, 0.0])
    res = slow_flow(unit, np.zeros((40, 3)), fs=1000.0, rng=np.random.default_rng(0),
                   noise=False, adc=False, flicker=False, specific_force=np.tile(f, (40, 1)))
    zro = zero_rate_output(unit)
    np.testing.assert_allclose(res.output[-1], zro + gs * f, rtol=0,
                               atol=1e-9 * abs(quadrature_rate(unit)))


def test_default_population_g_sensitivity_size():
    """With theta_e ~ N(0, 5 mrad) the rms g-sensitivity is 5 mrad x the quadrature shift per g.

    Closed form over 400 drawn units (no simulation): rms |dOmega/df| g vs sigma_theta x
    (dk_yx/df) g / (2 m w); the chi-square bounds of an rms of 400 draws at 1e-6 (the other
    drawn parameters move m, w, k_y by a few % -> 10 % allowance).
    """
    from scipy import stats

    from gyrobench.sim.mems_resonator import electrostatic_cross_stiffness, g_sensitivity

    spec = MemsResonatorSpec(nominal=_quiet())
    rng = np.random.default_rng(11)
    gs = np.array([g_sensitivity(spec.realize(rng=rng)) for _ in range(400)]) * G0
    op = operating_point(spec.nominal)
    expected = 5e-3 * electrostatic_cross_stiffness(spec.nominal) * G0 / (2 * op.m * op.wx)
    lo, hi = np.sqrt(stats.chi2.ppf([5e-7, 1 - 5e-7], 400) / 400)
    rms = float(np.sqrt(np.mean(gs**2)))
    assert lo * 0.9 <= rms / expected <= hi * 1.1
    # the size the docs quote: 39 deg/h/g rms (datasheets: STIM 10-18, ADXRS453 36 deg/h/g)
    assert units.to_deg_per_h(expected) == pytest.approx(39.1, abs=0.5)


def test_bad_specific_force_shape():
    with pytest.raises(ValueError, match="specific_force must broadcast"):
        slow_flow(MemsResonator(), np.zeros((10, 2)), fs=200.0, rng=np.random.default_rng(0),
                 specific_force=np.zeros(3))


# ------------------------------------------------------------------ open-loop read-out
def _open(**kw) -> MemsResonator:
    return _quiet(readout="open_loop", **kw)


@pytest.mark.parametrize("dt", [0.0, -30.0, 40.0])
def test_open_loop_scale_factor_follows_the_receptance(dt):
    """SF_ol = s_trim (w/w0) Re{e^{-j theta} R(T)/R_c}; the settled slow flow reads it."""
    unit = _open(quadrature_coupling=1e-4, damping_coupling=5e-4, phase_error=0.01,
                 q_tc=3e-3, frequency_tc=-30e-6)
    t = unit.reference_temperature + dt
    m, q = unit.mass, unit.sense_q
    wx0, wy0 = 2 * math.pi * unit.drive_frequency, 2 * math.pi * (unit.drive_frequency + 500.0)
    s = 1 - 30e-6 * dt
    wx, wy = wx0 * s, wy0 * s
    r = 1 / (m * (wy**2 - wx**2) + 1j * m * wy / q * (1 + 3e-3 * dt) * wx)
    rc = 1 / (m * (wy0**2 - wx0**2) + 1j * m * wy0 / q * wx0)
    th = 0.01 + unit.phase_tc * dt
    expected = s * (np.exp(-1j * th) * r / rc).real
    assert low_rate_scale_factor(unit, t) == pytest.approx(expected, rel=1e-12)
    w = units.deg_per_s(np.array([-1000.0, 0.0, 2000.0]))
    out = _settled(unit, w, t)
    np.testing.assert_allclose(out, expected * w + zero_rate_output(unit, t), rtol=1e-9)


def test_open_loop_scale_factor_depends_on_the_mode_split_unlike_force_rebalance():
    """A 5 % split error (R_c designed for 500 Hz, the part at 475 Hz) moves SF_ol by ~5 %."""
    unit = _open()
    op = operating_point(unit)
    shifted = dataclasses.replace(unit, mode_split=475.0)
    # keep the design receptance: compare the raw demodulated outputs through R/R_c
    r_new = operating_point(shifted).receptance
    ratio = (r_new / op.receptance).real
    assert ratio == pytest.approx(500.0 * (2 * 15e3 + 500.0) / (475.0 * (2 * 15e3 + 475.0)),
                                  rel=2e-2)  # |R| ~ 1/(w_y^2 - w^2) (Q = 100: 1-2 % from c_y)
    assert abs(ratio - 1) > 0.04


def test_open_loop_frequency_response_closed_form():
    """Sinusoidal rate through the slow flow at 100 kHz vs H(f) x sinc^2(f/fs).

    ZOH input and interval-mean output each contribute sinc(f/fs) (their h/2 delays cancel);
    the central-difference Omega' of the Euler force errs by (W h)^2/6 relative, on a term
    W/(2 w) of the Coriolis force: tolerance 2x that bound, plus 1e-9.
    """
    from gyrobench.sim.mems_resonator import open_loop_response

    unit = _open()
    op = operating_point(unit)
    fs = 1e5
    h = 1 / fs
    sf = low_rate_scale_factor(unit)
    amp = units.deg_per_s(100.0)
    p = op.pole
    for f in (20.0, 200.0, 500.0, 800.0):
        per = int(round(fs / f))
        nset, nrec = int(0.05 * fs), per * max(1, int(round(0.05 * f)))
        t = np.arange(nset + nrec) * h
        res = slow_flow(unit, amp * np.cos(2 * np.pi * f * t), fs=fs, rng=np.random.default_rng(0),
                       noise=False, adc=False, flicker=False)
        y, tt = res.output[nset:] - zero_rate_output(unit), t[nset:]
        a = np.stack([np.cos(2 * np.pi * f * tt), -np.sin(2 * np.pi * f * tt)], axis=1)
        c = np.linalg.lstsq(a, y, rcond=None)[0]
        h_sim = (c[0] + 1j * c[1]) / (amp * sf)
        h_cf = open_loop_response(unit, f) * np.sinc(f * h) ** 2
        w = 2 * np.pi * f
        gmax = max(abs(-p / (1j * w - p)), abs(-p / (-1j * w - p)))
        tol = 2 * (w * h) ** 2 / 6 * w / (2 * op.wx) * gmax / abs(h_cf) + 1e-9
        assert abs(h_sim - h_cf) / abs(h_cf) <= tol, (f, h_sim, h_cf, tol)
    # the response peaks near the mode split and falls beyond it
    mag = np.abs(open_loop_response(unit, [0.0, 250.0, 500.0, 2000.0]))
    assert mag[2] > mag[1] > mag[0] == pytest.approx(1.0) and mag[3] < 0.1


def test_open_loop_saturates_at_the_pickoff_full_scale():
    unit = _open(quadrature_coupling=1e-4, phase_error=0.01)
    auth = rate_authority(unit)
    op = operating_point(unit)
    # at the knee the settled envelope |R F_ext| equals Y_fs
    f_ext = -1j * op.coriolis_gain * auth - op.kyx * op.x0
    assert abs(op.receptance * f_ext) == pytest.approx(unit.pickoff_full_scale, rel=1e-9)
    w = np.array([0.99, 1.5, 3.0, -2.0]) * auth
    out = _settled(unit, w)
    np.testing.assert_allclose(out[1:], [saturated_output(unit, x) for x in w[1:]], rtol=1e-9)
    sf, zro = low_rate_scale_factor(unit), zero_rate_output(unit)
    assert out[0] == pytest.approx(sf * w[0] + zro, rel=1e-9)
    # beyond the knee the output keeps bending (phase kept, amplitude limited) but stays bounded
    assert abs(out[2]) < abs(sf * w[2])


def test_open_loop_noise_level_matches_the_force_rebalance_closed_form(rng):
    """Input-referred white noise is the same N = sqrt(N_B^2 + N_e^2) in both read-outs."""
    from scipy import stats

    unit = _open(quadrature_coupling=1e-4)
    fs, cols, dur, block = 200.0, 16, 100.0, 1.0
    n = int(dur * fs)
    res = slow_flow(unit, np.zeros((n, cols)), fs=fs, rng=rng, adc=False, flicker=False)
    m = int(block * fs)
    means = res.output.reshape(n // m, m, cols).mean(axis=1) - zero_rate_output(unit)
    n_hat = math.sqrt(np.mean(means**2) * block) / low_rate_scale_factor(unit)
    n_cf = math.hypot(brownian_arw(unit), electronic_arw(unit))
    dof = means.size
    lo = math.sqrt(stats.chi2.ppf(5e-7, dof) / dof)
    hi = math.sqrt(stats.chi2.ppf(1 - 5e-7, dof) / dof)
    tau = 1.0 / abs(operating_point(unit).pole.real)  # envelope time constant
    assert lo * (1 - 2 * tau / block) <= n_hat / n_cf <= hi


def test_open_loop_trim_and_bad_readout():
    spec = MemsResonatorSpec(nominal=_open())
    u = spec.realize(rng=np.random.default_rng(4))
    assert low_rate_scale_factor(u) == pytest.approx(1.0, rel=1e-12)
    assert zero_rate_output(u) == pytest.approx(0.0, abs=1e-12)
    with pytest.raises(ValueError, match="readout must be one of"):
        MemsResonator(readout="closed")


def test_datasheet_repeatability_limit_is_read_as_three_sigma():
    from gyrobench.sim.mems_resonator import LIMIT_SIGMAS

    kw = dict(noise_density_convention="two-sided", bias_repeatability_dps=0.3,
              scale_factor_repeatability_ppm=2000.0)
    one = MemsResonatorSpec.from_datasheet(**kw).nominal
    lim = MemsResonatorSpec.from_datasheet(repeatability_convention="limit", **kw).nominal
    assert LIMIT_SIGMAS == 3.0
    assert one.scale_factor_repeatability == pytest.approx(2e-3, rel=1e-12)
    assert lim.scale_factor_repeatability == pytest.approx(2e-3 / 3, rel=1e-12)
    assert lim.bias_repeatability == pytest.approx(units.deg_per_s(0.1), rel=1e-12)
    with pytest.raises(ValueError, match="repeatability_convention"):
        MemsResonatorSpec.from_datasheet(repeatability_convention="max", **kw)


# ------------------------------------------------------------------ open-loop noise PSD
def test_open_loop_noise_psd_closed_form_at_zero_frequency_and_its_peak():
    """S(0) = 2 SF^2 (N_B^2 + N_e^2) (theta = 0, T0); the Brownian part peaks near the split."""
    from gyrobench.sim.mems_resonator import open_loop_noise_psd

    # a quiet front end (the default's pick-off noise, sized for a high-range part's 0.25
    # deg/sqrt(s), is 45x the Brownian floor and would bury the peak this test looks at)
    unit = _open(pickoff_noise=1e-13)
    sf = low_rate_scale_factor(unit)
    n2 = brownian_arw(unit) ** 2 + electronic_arw(unit) ** 2
    assert open_loop_noise_psd(unit, 0.0) == pytest.approx(2 * sf**2 * n2, rel=1e-12)
    f = np.array([0.0, 250.0, 490.0, 1000.0, 5000.0])
    s = open_loop_noise_psd(unit, f)
    white = 2 * sf**2 * electronic_arw(unit) ** 2
    assert s[2] > s[1] > s[0] and s[2] > 10 * s[0]
    assert s[4] == pytest.approx(white, rel=0.05)  # far above the split: pick-off only
    with pytest.raises(ValueError, match="open_loop"):
        open_loop_noise_psd(_quiet(), 0.0)


def test_slow_flow_open_loop_noise_psd_matches_its_closed_form(rng):
    """Band-mean periodograms of the slow flow (open loop) vs the exact expectation of the
    closed form sampled at fs (aliasing, interval mean, rectangular-window leakage), band by
    band from 17 Hz to Nyquist; chi-square bounds with the closed-form equivalent dof at
    1e-6 two-sided, Bonferroni over the 15 bands."""
    from scipy import stats

    from gyrobench.scenarios.checks.mems_psd import _PSD_GRID, periodogram_band_stats, slow_noise_spectrum

    # a quiet front end, so the Brownian peak this test resolves stands out (the default
    # pick-off noise is sized for a high-range part and is white)
    unit = _open(quadrature_coupling=1e-4, phase_error=0.02, pickoff_noise=1e-13)
    fs, n, cols, n_seg = 3000.0, 180, 32, 200
    res = slow_flow(unit, np.zeros(((n_seg + 1) * n, cols)), fs=fs, rng=rng, adc=False,
                   flicker=False)
    x = res.output[n:].reshape(n_seg, n, cols).transpose(1, 0, 2).reshape(n, n_seg * cols)
    p = 2 * np.abs(np.fft.rfft(x - x.mean(axis=0), axis=0)) ** 2 / (fs * n)
    f = np.fft.rfftfreq(n, 1 / fs)
    bands = [np.flatnonzero((f > lo) & (f <= lo + 100) & (f < fs / 2))
             for lo in np.arange(0.0, fs / 2, 100.0)]
    grid = np.fft.fftfreq(_PSD_GRID, 1 / fs)
    mean, dof = periodogram_band_stats(slow_noise_spectrum(unit, grid, fs), fs, n, bands)
    alpha = 1e-6 / len(bands)
    for b, mu, nu in zip(bands, mean, dof * n_seg * cols, strict=True):
        got = p[b].mean() / mu
        lo, hi = stats.chi2.ppf([alpha / 2, 1 - alpha / 2], nu) / nu
        assert lo <= got <= hi, (f[b][0], got, lo, hi)
    # the peak near the mode split is resolved (9x the low-frequency level in 100-Hz bands)
    assert mean.max() > 5 * mean[0]


@pytest.mark.slow  # about 10 s CPU: 2112 RK4 cases of 34 ms
def test_open_loop_noise_psd_full_integration_agrees_with_the_slow_flow():
    """The physics check: full-integration output noise PSD vs the slow flow's, band by band
    (0-250 Hz level; 5 bands to Nyquist through the sense-mode peak), F bounds at 1e-6."""
    from gyrobench.scenarios.checks.mems_psd import open_loop_noise_checks

    out = open_loop_noise_checks(np.random.default_rng(16))
    assert [c.id for c in out] == ["mems.open_loop_noise_vs_full",
                                   "mems.open_loop_noise_psd_vs_full"]
    assert all(c.passed for c in out), [(c.id, c.rel_error, c.tolerance) for c in out]


def test_full_and_slow_noise_spectra_differ_by_the_first_order_envelope():
    """Closed forms: E_full/E_slow -> sinc^2(f_y dt) (the held noise force) at low frequency
    and falls by O(f/f_x) toward the mode split (first-order envelope, 2w image)."""
    from gyrobench.scenarios.checks.mems_psd import full_noise_spectrum, slow_noise_spectrum

    unit = dataclasses.replace(_open(), pickoff_noise=0.0)
    fs, spc = 3000.0, 20
    f = np.array([1.0, 250.0, 500.0, 1000.0])
    rho = full_noise_spectrum(unit, f, fs, spc) / slow_noise_spectrum(unit, f, fs)
    dt = 1 / (15e3 * spc)
    assert rho[0] == pytest.approx(np.sinc(15.5e3 * dt) ** 2, abs=2e-3)
    # two O(f/f_x) terms, each at most f/f_x in power, below the held-force factor
    assert rho[0] > rho[1] > rho[2] > rho[3] > rho[0] - 2 * f[3] / 15e3
    # the pick-off noise is white and identical in both
    w = dataclasses.replace(_open(), reference_temperature=1e-9)
    assert full_noise_spectrum(w, f, fs, spc) == pytest.approx(
        slow_noise_spectrum(w, f, fs), rel=1e-9)


# ------------------------------------------------------------------ drive-axis specific force
def test_drive_axis_sensitivity_is_the_receptance_change_of_the_displaced_drive():
    """d ln SF/d f_d = -(k_e eps_A m/k_x) Re{e^{-j theta} R^2/R_c}/Re{e^{-j theta} R/R_c}."""
    from gyrobench.sim.mems_resonator import EPSILON_0, drive_axis_sensitivity

    unit = _open(phase_error=0.01)
    op = operating_point(unit)
    k_e = 2 * EPSILON_0 * unit.electrode_area * unit.bias_voltage**2 / unit.electrode_gap**3
    dk = k_e * unit.forcer_area_gradient * op.m / op.kx  # [N/m per m/s^2]
    r = op.receptance
    e = np.exp(-1j * op.theta) / op.r_design
    expected = -dk * (e * r * r).real / (e * r).real
    assert drive_axis_sensitivity(unit) == pytest.approx(expected, rel=1e-5)
    # size: about -12 ppm/g for the default design (Q_y = 100 moves it a few % from the
    # undamped -(k_e eps_A / w_x^2)/(m (w_y^2 - w_x^2)))
    ppm_per_g = drive_axis_sensitivity(unit) * 9.80665 * 1e6
    undamped = -(k_e * unit.forcer_area_gradient / op.wx**2) / (op.m * (op.wy**2 - op.wx**2))
    assert -14.0 < ppm_per_g < -11.0
    assert drive_axis_sensitivity(unit) == pytest.approx(undamped, rel=0.05)
    # force rebalance nulls the sense motion: no scale-factor change
    assert drive_axis_sensitivity(_quiet(phase_error=0.01)) == 0.0
    # a double-ended forcer (eps_A = 0) has none either
    assert drive_axis_sensitivity(_open(forcer_area_gradient=0.0)) == 0.0


@pytest.mark.parametrize("g_d", [-20.0, 20.0])
def test_slow_flow_settles_on_the_drive_axis_scale_factor(g_d):
    unit = _open(quadrature_coupling=1e-4, phase_error=0.01)
    f_d = g_d * 9.80665
    w = units.deg_per_s(np.array([0.0, 500.0]))
    res = slow_flow(unit, np.tile(w, (40, 1)), fs=1000.0, rng=np.random.default_rng(0),
                   noise=False, adc=False, flicker=False, drive_specific_force=f_d)
    sf = (res.output[-1, 1] - res.output[-1, 0]) / w[1]
    assert sf == pytest.approx(low_rate_scale_factor(unit, drive_specific_force=f_d), rel=1e-9)
    from gyrobench.sim.mems_resonator import drive_axis_sensitivity

    assert sf / low_rate_scale_factor(unit) - 1 == pytest.approx(
        drive_axis_sensitivity(unit) * f_d, rel=1e-3)  # linear to (dSF/SF)^2


def test_bad_drive_specific_force():
    with pytest.raises(ValueError, match="drive_specific_force"):
        operating_point(_open(), drive_specific_force=float("nan"))
    with pytest.raises(ValueError, match="drive_specific_force"):
        operating_point(_open(), drive_specific_force=-1e12)
    with pytest.raises(ValueError, match="drive_specific_force"):
        simulate_full(_open(), np.zeros(2), duration=0.001, rng=np.random.default_rng(0),
                      drive_specific_force=np.zeros(3))


# ------------------------------------------------------------------ error split of a record
@pytest.mark.parametrize("shape", ["one", "columns", "temperature_blocks"])
def test_total_error_split_keeps_the_output_and_closes(shape):
    """error_split="total" skips the noise-free run: the same output bits, one component closing it."""
    from gyrobench.io.recording import schema_problems
    from gyrobench.sim.sensor import Environment

    fs = 200.0
    if shape == "columns":
        env = Environment(0.5, true_rate=np.tile(units.deg_per_s(np.array([-100.0, 0.0, 250.0])), (100, 1)),
                          temperature=units.celsius(30.0))
    elif shape == "temperature_blocks":
        n = 400
        env = Environment(n / fs, true_rate=np.full(n, 0.3), temperature=units.celsius(np.linspace(20.0, 40.0, n)))
    else:
        env = Environment(1.0, true_rate=np.linspace(-1.0, 1.0, 200))
    unit = MemsResonator()
    parts = unit.simulate(env, fs=fs, rng=np.random.default_rng(11))
    total = dataclasses.replace(unit, error_split="total").simulate(env, fs=fs, rng=np.random.default_rng(11))
    assert np.array_equal(total["output"], parts["output"])
    assert np.array_equal(total["truth/true_rate"], parts["truth/true_rate"])
    assert parts.metadata["error_components"] == ["deterministic_error", "noise"]
    assert total.metadata["error_components"] == ["total_error"]
    assert set(total.truth) == {"true_rate", "total_error"}
    assert schema_problems(total) == [] and schema_problems(parts) == []
    # the two components and the total describe the same error (to the rounding of their sum)
    split = parts["truth/deterministic_error"] + parts["truth/noise"]
    np.testing.assert_allclose(total["truth/total_error"], split, rtol=0, atol=4 * np.spacing(np.max(np.abs(
        parts["output"]))))


def test_error_split_is_a_declared_choice():
    with pytest.raises(ValueError, match="error_split"):
        MemsResonator(error_split="none")
