"""Exact strain kernel, random-PSD vibration variance, ClosedLoopFOG's nonreciprocal input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from gyrobench.base import units
from gyrobench.sim.fiber_strain import (
    StrainMode,
    linear_kernel,
    segment_kernel,
    segment_weight,
)
from gyrobench.sim.fog_loop import ClosedLoopFOG, LoopSpec, gain_error_scale_factor
from gyrobench.sim.fog_optics import SPEED_OF_LIGHT, OpticalBudget
from gyrobench.sim.sensor import Environment

L, NG = 1000.0, 1.468


def _numeric_kernel(psi, f):
    # e^{-jw tau/2} (1/a) int psi sin(a (L - 2z)) dz by adaptive quadrature
    a = math.pi * f * NG / SPEED_OF_LIGHT
    w = quad(lambda z: psi(z) * math.sin(a * (L - 2 * z)), 0.0, L, limit=400, epsabs=0)[0] / a
    return w * np.exp(-1j * a * L)


@pytest.mark.parametrize("f", [1.0, 500.0, 5e4, 3e5])
def test_linear_kernel_matches_the_integral(f):
    got = complex(linear_kernel(L, f, NG))
    want = _numeric_kernel(lambda z: z / L, f)
    assert abs(got - want) < 1e-9 * L**2 / 6


@pytest.mark.parametrize("f", [500.0, 5e4, 3e5])
@pytest.mark.parametrize("z0,ln", [(0.0, 0.5), (100.0, 300.0), (400.0, 600.0)])
def test_segment_kernel_matches_the_integral(f, z0, ln):
    got = complex(segment_kernel(z0, ln, L, f, NG))
    a = math.pi * f * NG / SPEED_OF_LIGHT
    inner = quad(lambda z: math.sin(a * (L - 2 * z)), z0, z0 + ln, limit=400, epsabs=0)[0] / a
    want = inner * np.exp(-1j * a * L)
    assert abs(got - want) < 1e-9 * ln * L


def test_kernels_tend_to_the_small_tau_weights():
    assert complex(segment_kernel(100.0, 300.0, L, 0.0, NG)) == segment_weight(100.0, 300.0, L)
    assert complex(linear_kernel(L, 0.0, NG)) == pytest.approx(-(L**2) / 6, rel=1e-15)
    # series and closed form meet at x = 0.1 (the switch point)
    a = 0.1 / L
    f = a * SPEED_OF_LIGHT / (math.pi * NG)
    lo, hi = linear_kernel(L, f * (1 - 1e-9), NG), linear_kernel(L, f * (1 + 1e-9), NG)
    assert abs(complex(lo) - complex(hi)) < 1e-10 * L**2


def test_small_tau_amplitude_error_is_within_its_bound():
    # |W(w) - W| <= (a L)^2/6 int |psi| |L - 2z| dz; for psi = z/L: int = L^2/4
    for f in (500.0, 1200.0, 5e4):
        a = math.pi * f * NG / SPEED_OF_LIGHT
        w = complex(linear_kernel(L, f, NG)) * np.exp(1j * a * L)
        assert abs(w.imag) < 1e-9 * L**2
        assert abs(w.real + L**2 / 6) <= (a * L) ** 2 / 6 * L**2 / 4


def test_segment_mode_weight_must_fit_the_coil():
    seg = StrainMode(frequency=300.0, quality=30.0, strain=1e-12, weight=499.75, segment=(0.0, 0.5))
    ClosedLoopFOG(modes=(seg,))
    with pytest.raises(ValueError, match="weight"):
        ClosedLoopFOG(loop=LoopSpec(length=800.0), modes=(seg,))
    with pytest.raises(ValueError, match="segment"):
        StrainMode(frequency=300.0, quality=30.0, segment=(-1.0, 0.5))
    with pytest.raises(TypeError, match="segment"):
        StrainMode(frequency=300.0, quality=30.0, segment=[0.0, 0.5])


def test_random_vibration_psd_integrates_to_the_variance():
    unit = ClosedLoopFOG()
    g0 = units.g(1.0)

    def psd(f):
        return np.where((f >= 20) & (f <= 2000), 0.04 * g0**2, 0.0)

    for term in ("strain", "loop_error", "rocking"):
        var = unit.vibration_error_variance(psd, 100.0, 2000.0, term=term)
        fo, sy = unit.vibration_error_psd(psd, 100.0, 2000.0, term=term, n=20001)
        assert var > 0
        assert np.trapezoid(sy, fo) == pytest.approx(var, rel=2e-3)
    with pytest.raises(ValueError, match="term"):
        unit.vibration_transfer([1.0], 100.0, term="bogus")


def test_nonreciprocal_input_passes_the_loop_unscaled(rng):
    unit = ClosedLoopFOG(modes=(), optics=OpticalBudget(source_power=1e3))

    def nr(t):
        return 1e-6 * np.sin(2 * np.pi * t / 50.0)

    rec = unit._record(100.0, 10.0, rng=rng, true_rate=1e-3, coil_temperature=313.15, nonreciprocal_rate=nr
    )
    t = rec.time + 0.05
    np.testing.assert_allclose(rec["truth/nonreciprocal"], nr(t), rtol=0, atol=1e-20)
    slow = 1e-3 + unit.earth_rate
    r_t = unit.scale_factor_ratio(313.15, unit.reference_temperature)
    want = slow * r_t + nr(t)
    got = rec["output"] - rec["truth/optical_noise"] - rec["truth/ieee_noise"]
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-18)


def test_nonreciprocal_input_shares_the_gain_error_ratio(rng):
    eps = 0.02
    unit = ClosedLoopFOG(
        modes=(), loop=LoopSpec(gain_loop=False, modulator_gain_error=eps, reset_blanking=True)
    )
    rec = unit._record(10.0, 10.0, rng=rng, nonreciprocal_rate=1e-5)
    r_g = float(gain_error_scale_factor(0.0, eps, reset_blanking=True)[()])
    slow = unit.earth_rate
    got = rec["output"] - rec["truth/optical_noise"] - rec["truth/ieee_noise"]
    np.testing.assert_allclose(got, (slow + 1e-5) * r_g, rtol=1e-12)


@pytest.mark.parametrize("f", [500.0, 5e4, 3e5])
def test_uniform_strain_rate_cancels_exactly(f):
    # psi = 1 over the whole fibre: W(w) = 0 at every frequency, not only as w tau -> 0
    assert abs(complex(segment_kernel(0.0, L, L, f, NG))) < 1e-12 * L**2


@pytest.mark.parametrize(
    "term,channel", [("loop_error", "loop_error"), ("strain", "strain_nonreciprocity")]
)
def test_random_vibration_record_variance_matches_the_closed_form(rng, term, channel):
    # a second configuration besides the physics check: output 400 Hz (little aliasing),
    # 30 s of a flat 20-1500 Hz PSD; chi-square band with nu = 2 B_e T at 1e-6 two-sided
    from scipy import stats

    from gyrobench.sim.shaker import RandomVibration

    unit = ClosedLoopFOG()
    rv = RandomVibration(breakpoints=((20.0, 0.02), (1500.0, 0.02)), duration=30.0)
    g0 = units.g(1.0)

    def psd(f):
        return rv.shaped_psd(f) * g0**2

    fs = 400.0
    var = unit.vibration_error_variance(psd, fs, 1500.0, term=term)
    fo, sy = unit.vibration_error_psd(psd, fs, 1500.0, term=term)
    nu = 2.0 * 30.0 * np.trapezoid(sy, fo) ** 2 / np.trapezoid(sy**2, fo)
    sh = rv.sample(8 * fs, rng=rng)
    y = unit.simulate(Environment(30.0, vibration=sh), fs=fs, rng=rng)[f"truth/{channel}"]
    ratio = float(np.mean(y**2)) / var
    lo, hi = stats.chi2.ppf(5e-7, nu) / nu, stats.chi2.isf(5e-7, nu) / nu
    assert lo < ratio < hi
