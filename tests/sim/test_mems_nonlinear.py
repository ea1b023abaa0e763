"""Tests of sim.mems_nonlinear: the smooth, compressive scale-factor nonlinearity.

Closed forms (small-signal scale factor 1, leading cubic coefficient, monotonicity, the
inverse) and the harmonic-balance amplitude of the Duffing sense mode against a full
integration of its equation of motion through the bend.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from gyrobench.sim.mems_nonlinear import DuffingSense, RateTransfer, duffing_normalized, rapp, rapp_inverse

DEG = math.pi / 180.0


def test_cardano_root_solves_the_cubic_and_is_odd():
    u = np.concatenate([-np.logspace(-8, 3, 40), [0.0], np.logspace(-8, 3, 40)])
    v = duffing_normalized(u)
    # v + v^3 = u to rounding (relative to the larger term)
    assert np.all(np.abs(v + v**3 - u) <= 1e-13 * np.maximum(np.abs(u), 1e-300) + 1e-300)
    assert np.array_equal(duffing_normalized(-u), -v)


def test_small_signal_scale_factor_is_one():
    """d out / d rate at 0 is 1 (both mechanisms' series start with the rate itself)."""
    t = RateTransfer(duffing_rate=2000 * DEG, rail_rate=3000 * DEG, rail_order=1.5)
    h = 1e-4 * DEG
    slope = (t(h) - t(-h)) / (2 * h)
    assert abs(slope - 1.0) < 1e-9


@pytest.mark.parametrize(
    ("transfer", "a3"),
    [
        (RateTransfer(duffing_rate=2000 * DEG), -1.0 / (2000 * DEG) ** 2),
        (RateTransfer(rail_rate=3000 * DEG, rail_order=1.0), -0.5 / (3000 * DEG) ** 2),
        (RateTransfer(duffing_rate=2000 * DEG, rail_rate=3000 * DEG, rail_order=3.0), -1.0 / (2000 * DEG) ** 2),
    ],
)
def test_leading_cubic_coefficient(transfer, a3):
    """(out - rate) / rate^3 -> a3 at small rates: -1/Omega_d^2 (Duffing, v = u - u^3 + 3u^5),
    -1/(2 Omega_s^2) (Rapp p = 1: (1 + r^2)^(-1/2) = 1 - r^2/2); Rapp p > 1 starts at order 2p+1."""
    w = np.array([20.0, 40.0, 80.0]) * DEG
    ratio = (transfer(w) - w) / w**3
    # the next term is O(w^2) relative: extrapolate the three points to w = 0 (quadratic in w^2)
    c = np.polyfit(w**2, ratio, 2)
    assert abs(c[-1] / a3 - 1.0) < 1e-4
    assert transfer.cubic_coefficient == pytest.approx(a3, rel=1e-12)


@pytest.mark.parametrize("order", [1.0, 2.0, 4.62, 10.0])
def test_transfer_is_monotone_compressive_and_never_clips(order):
    t = RateTransfer(duffing_rate=5000 * DEG, rail_rate=2774 * DEG, rail_order=order)
    w = np.linspace(-3600, 3600, 72001) * DEG
    y = t(w)
    assert np.all(np.diff(y) > 0)  # strictly increasing: invertible
    assert np.all(np.abs(y[w != 0]) < np.abs(w[w != 0]))  # compressive
    assert np.max(np.abs(y)) < t.rail_rate  # below the rail: no clip
    assert np.allclose(t.inverse(y), w, rtol=1e-9, atol=1e-12)


def test_rapp_inverse_and_errors():
    x = np.linspace(-5.0, 5.0, 101)
    assert np.allclose(rapp_inverse(rapp(x, 2.0, 3.0), 2.0, 3.0), x, rtol=1e-10)
    with pytest.raises(ValueError, match="rapp_inverse y must satisfy"):
        rapp_inverse([2.5], 2.0, 3.0)
    with pytest.raises(ValueError, match="rapp order must be finite and >= 1"):
        rapp(x, 2.0, 0.5)
    with pytest.raises(ValueError, match="RateTransfer.rail_rate must be > 0"):
        RateTransfer(rail_rate=-1.0)
    with pytest.raises(ValueError, match="DuffingSense.sense_omega must exceed drive_omega"):
        DuffingSense(mass=1e-9, drive_omega=1e5, sense_omega=9e4, sense_q=100, k3=1.0, drive_amplitude=1e-6)


def _sense(q: float) -> DuffingSense:
    w = 2 * math.pi * 15e3
    return DuffingSense(mass=2e-9, drive_omega=w, sense_omega=1.02 * w, sense_q=q, k3=3e9, drive_amplitude=5e-6)


def test_undamped_limit_is_the_closed_form():
    """At high Q the damped harmonic balance tends to Omega_d v(Omega/Omega_d), read at the
    small-signal scale factor; the damping's correction is O((c w / dk)^2)."""
    s = _sense(1e7)
    od = s.critical_rate
    rates = np.array([0.1, 0.5, 1.0, 2.5]) * od
    a = s.amplitude(rates)
    small = s.coriolis_force(1.0) / s.detuning_stiffness  # A per rad/s at small rates
    assert np.allclose(a / small, od * duffing_normalized(rates / od), rtol=1e-9)


@pytest.mark.slow
def test_harmonic_balance_against_full_integration_through_the_bend():
    """The first-harmonic amplitude of the integrated equation of motion equals the harmonic
    balance's at u = Omega/Omega_d = 0.3, 1 and 2.5 (linear, the bend, compressed).

    Truncation: the third harmonic, A3/A ~ (k3 A^2/4)/(9 m w^2 - k_y) ~ v^2 (w_y^2/w^2 - 1)/24,
    feeds back on the first at relative order (3/4 k3 A^2 / dk) A3/A = v^2 A3/A; the tolerance is
    three times that bound at the largest v (the integration itself is at rtol 1e-9)."""
    from scipy.integrate import solve_ivp

    s = _sense(200.0)
    m, w = s.mass, s.drive_omega
    u = np.array([0.3, 1.0, 2.5])
    rates = u * s.critical_rate
    f = s.coriolis_force(rates)
    a_hb = s.amplitude(rates)
    scale = float(np.max(a_hb))
    # dimensionless time tau = w t, z = y / scale: z'' + g z' + kk z + k3n z^3 = fn cos(tau)
    g = s.damping / (m * w)
    kk = (s.sense_omega / w) ** 2
    k3n = s.k3 * scale**2 / (m * w**2)
    fn = f / (m * w**2 * scale)

    def rhs(tau, state):
        z, dz = state[:3], state[3:]
        return np.concatenate([dz, fn * np.cos(tau) - g * dz - kk * z - k3n * z**3])

    cycles, last = 800, 20  # decay time 2Q/w_y: 800 cycles are about 25 time constants
    t_end = 2 * math.pi * cycles
    t_eval = np.linspace(t_end - 2 * math.pi * last, t_end, 64 * last, endpoint=False)
    sol = solve_ivp(rhs, (0.0, t_end), np.zeros(6), method="DOP853", rtol=1e-9, atol=1e-12, t_eval=t_eval)
    assert sol.success
    first = 2.0 * np.abs(np.mean(sol.y[:3] * np.exp(-1j * sol.t), axis=1)) * scale
    v = np.abs(a_hb) * math.sqrt(0.75 * s.k3 / s.detuning_stiffness)
    bound = float(np.max(v**4)) * ((s.sense_omega / w) ** 2 - 1.0) / 24.0
    assert np.all(np.abs(first / np.abs(a_hb) - 1.0) < 3.0 * bound), (first / np.abs(a_hb) - 1.0, bound)
