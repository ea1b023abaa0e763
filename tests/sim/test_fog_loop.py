"""Full-rate closed-loop IFOG (sim/fog_loop.py) against its closed forms."""

import math

import numpy as np
import pytest
from scipy import signal

from gyrobench.base import units
from gyrobench.sim.fog_loop import LoopSpec, gain_error_scale_factor, run_loop
from gyrobench.sim.fog_optics import OpticalBudget
from gyrobench.sim.sensor import Environment

EPS = float(np.finfo(float).eps)


def test_coil_numbers():
    # docs/physics.md 3.8 / 1.3 (1 km, 0.1 m, 1550 nm, n_g 1.468)
    s = LoopSpec()
    assert round(s.scale_factor, 4) == 1.3522
    assert round(s.transit_time * 1e6, 3) == 4.897
    assert round(s.proper_frequency / 1e3, 2) == 102.11
    assert round(units.to_arcsec(s.angle_quantum), 2) == 4.69
    # angle quantum = n_g lambda / D exactly
    assert (
        abs(s.angle_quantum - s.group_index * s.wavelength / s.diameter) < 8 * EPS * s.angle_quantum
    )


def test_transfer_function_values():
    s = LoopSpec()
    assert abs(s.transfer(0.0) - 1.0) < 1e-14
    assert abs(abs(s.transfer(3000.0)) - 0.771) < 0.005  # docs/physics.md 3.8 check
    # small-g bandwidth g/(2 pi tau) within the O(g) correction
    small = LoopSpec(loop_gain=0.01)
    f0 = 0.01 / (2 * math.pi * small.transit_time)
    assert abs(small.bandwidth() / f0 - 1) < 0.03
    assert abs(abs(s.transfer(s.bandwidth())) - 1 / math.sqrt(2)) < 1e-9


def test_unstable_gain_rejected():
    with pytest.raises(ValueError, match=r"loop_gain must give a stable loop \(delay 2: below ~1\); got 1.5"):
        LoopSpec(loop_gain=1.5, delay=2)
    with pytest.raises(ValueError, match=r"LoopSpec.loop_gain must be \(0, 2\) 1; got 2.5"):
        LoopSpec(loop_gain=2.5)
    with pytest.raises(ValueError, match=r"delay must be an integer in \[1, 2\] transits; got 3"):
        LoopSpec(delay=3)


def test_noise_free_constant_rate_is_exact():
    s = LoopSpec(gain_loop=False)
    om = 0.01
    r = run_loop(s, np.full(512 * 100, s.scale_factor * om), samples_per_output=512)
    np.testing.assert_allclose(r.rate[5:], om, rtol=1e-12)
    # ramp resets: one per 2 pi of accumulated phase
    expected = s.scale_factor * om * len(r.delta) / (2 * math.pi)
    assert abs(abs(int(r.resets.sum())) - expected) <= 1


@pytest.mark.parametrize("d", [1, 2])
def test_step_and_frequency_response_match_transfer(d):
    # the rate loop alone (a V_2pi update during the transient would change G)
    s = LoopSpec(delay=d, loop_gain=0.1 if d == 1 else 0.08, gain_loop=False)
    n = 4096
    step = np.full(n, 1e-3)
    r = run_loop(s, step, samples_per_output=1)
    b, a = s._poly()
    lin = signal.lfilter(b, a, step)
    # sin x = x - x^3/6: |x| <= 1e-3 -> relative nonlinearity <= 2e-7
    np.testing.assert_allclose(-r.delta, lin, rtol=0, atol=2e-7 * 1e-3 * 10)
    for f in (500.0, 3000.0, 8000.0):
        k = np.arange(1 << 15)
        w = 2 * np.pi * f * s.transit_time
        x = 1e-3 * np.sin(w * k)
        y = -run_loop(s, x, samples_per_output=1).delta
        sl = slice(2000, None)
        basis = np.column_stack([np.sin(w * k[sl]), np.cos(w * k[sl])])
        c, *_ = np.linalg.lstsq(basis, y[sl], rcond=None)
        # y = Im(H e^{j w k}) = Re(H) sin(w k) + Im(H) cos(w k)
        h_sim = (c[0] + 1j * c[1]) / 1e-3
        h = complex(s.transfer(f))
        assert abs(h_sim - h) < 1e-5, (f, h_sim, h)  # nonlinearity x^2/6 <= 2e-7 + fit leakage


def test_gain_error_scale_factor_three_cases():
    eps, om = 0.02, 0.0123
    n = 512 * 1200
    base = dict(modulator_gain_error=eps)
    # reset samples blanked: SF ratio 1/(1 + eps) exactly, for either loop delay
    for d, g in ((1, 0.1), (2, 0.08)):
        s = LoopSpec(gain_loop=False, reset_blanking=True, delay=d, loop_gain=g, **base)
        r = run_loop(s, np.full(n, s.scale_factor * om), samples_per_output=512)
        assert abs(r.rate[200:].mean() / om - 1 / (1 + eps)) < 1e-9
    # resets in the loop: -(2/3) pi^2 eps^3 (-52 ppm) within the parity-term bound
    s = LoopSpec(gain_loop=False, **base)
    ratio = float(gain_error_scale_factor(s.scale_factor * om, eps))
    assert abs((ratio - 1) + 2 / 3 * math.pi**2 * eps**3) < 1e-6
    r = run_loop(s, np.full(n, s.scale_factor * om), samples_per_output=512)
    g = 1 + eps
    bound = (
        abs(math.cos(g * s.bias_phase))
        * (1 - math.cos(2 * math.pi * eps))
        / (2 * math.pi * math.sin(s.bias_phase))
    )
    assert abs(r.rate[200:].mean() / om - ratio) < bound
    assert abs(r.rate[200:].mean() / om - 1) < 1e-4  # far below the blanked -2 %
    # the V_2pi loop: DAC gain settles at 1/(1 + eps), SF error < 1 ppm
    s = LoopSpec(gain_loop=True, **base)
    r = run_loop(s, np.full(n, s.scale_factor * om), samples_per_output=512)
    assert abs(r.dac_gain[-1] * (1 + eps) - 1) < 1e-7
    assert abs(r.rate[-200:].mean() / om - 1) < 1e-6


def test_scale_factor_nonlinearity_of_gain_error_matches_full_loop():
    # -52 ppm at low rate falls to ~-24 ppm at 1 rad/s (second order in the reset fraction)
    eps = 0.02
    s = LoopSpec(modulator_gain_error=eps, gain_loop=False)
    bound = (
        abs(math.cos((1 + eps) * s.bias_phase))
        * (1 - math.cos(2 * math.pi * eps))
        / (2 * math.pi * math.sin(s.bias_phase))
    )
    ratios = []
    for om in (0.0123, 0.2, 1.0):
        r = run_loop(s, np.full(512 * 1200, s.scale_factor * om), samples_per_output=512)
        th = float(gain_error_scale_factor(s.scale_factor * om, eps))
        assert abs(r.rate[200:].mean() / om - th) < bound
        ratios.append(th)
    assert ratios[2] - ratios[0] > 2.5e-5  # the formula is not flat: 29 ppm from 0.0123 to 1 rad/s


def test_reduced_unit_uses_the_gain_error_scale_factor(rng):
    from gyrobench.sim.fog_loop import ClosedLoopFOG

    loop = LoopSpec(modulator_gain_error=0.02, gain_loop=False)
    unit = ClosedLoopFOG(loop=loop, modes=(), optics=OpticalBudget(source_power=1e3))
    om = 1.0
    rec = unit.simulate(Environment(1.0, true_rate=om), fs=400.0, rng=rng)
    true = om + unit.earth_rate
    expected = true * (gain_error_scale_factor(loop.scale_factor * true, 0.02) - 1)
    np.testing.assert_allclose(rec["truth/scale_factor_error"], expected, rtol=1e-12)


def test_vibration_span_is_widened_to_a_5_smooth_transform_length():
    """The vibration span is padded to a block count whose sample count factors into 2, 3, 5 (a
    prime-sized FFT is ~10x slower); it never shrinks and never exceeds the record."""
    from scipy.fft import next_fast_len

    from gyrobench.sim.fog_loop import _smooth_blocks

    k = _smooth_blocks(120766, 8, 600000)
    assert k >= 120766 and next_fast_len(k * 8, real=True) == k * 8
    assert _smooth_blocks(120766, 8, 120766) == 120766  # the record is the limit


def test_default_budget_arw_is_the_documented_worked_example():
    """docs/physics.md 3.8's worked example, N = sqrt(S_phi/2)/SF with S_phi from the budget
    (its terms checked in checks_fog_loop: fog.optical_budget_*), is 1.323e-3 deg/sqrt(h) at
    phi_b = pi/2, RIN-limited with RIN/shot = 75.0 (one-sided polarised RIN 2/dnu_eff, issue 26)."""
    from gyrobench.scenarios.checks.fog_loop import _optical_budget
    from gyrobench.sim.fog_loop import ClosedLoopFOG

    for c in _optical_budget(np.random.default_rng(0)):
        assert abs(c.simulated / c.expected - 1) <= c.tolerance, c.id
    unit = ClosedLoopFOG(modes=())
    assert units.to_deg_per_sqrt_h(unit.arw) == pytest.approx(1.323e-3, abs=0.0005e-3)
    psd = unit.optics.phase_psd(math.pi / 2, unit.loop.wavelength)
    assert psd["rin"] / psd["shot"] == pytest.approx(75.03, abs=0.005)
