"""Tests of sim.coil: winding mapping, Shupe integral closed forms, heat diffusion vs analytic solutions."""

from __future__ import annotations

import math
import zlib
from fractions import Fraction

import numpy as np
import pytest
from gyrobench.sim import units
from gyrobench.sim.coil import (
    WINDING_PATTERNS,
    CoilSpec,
    CoilThermalModel,
    Winding,
    elasto_optic_factor,
    segment_weight,
    shupe_terms,
    slab_network,
    winding_sequence,
)
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import integrate, optimize, special


@pytest.fixture
def rng(request) -> np.random.Generator:
    key = zlib.crc32(request.node.nodeid.encode())
    return np.random.default_rng([20261121, key])


T0 = units.ZERO_CELSIUS
FREE = np.zeros(40)  # no strain: the Shupe term alone


# ----------------------------------------------------------------------------- winding


def test_quadrupolar_mapping_follows_physics_3_3():
    """First layers of ABBA: A0 = [L/2 - l, L/2], B0 = [L/2, L/2 + l], B1 = [L/2 + l, L/2 + 2l],
    A1 = [L/2 - 2l, L/2 - l]."""
    w = Winding.ideal("quadrupolar", 8, 800.0)
    lay, h = 100.0, 400.0
    np.testing.assert_array_equal(w.z0[:4], [h - lay, h, h + lay, h - 2 * lay])
    np.testing.assert_array_equal(w.z1[:4], [h, h + lay, h + 2 * lay, h - lay])
    assert winding_sequence("octupolar", 8) == "ABBABAAB"


@settings(max_examples=40, deadline=None)
@given(
    pattern=st.sampled_from(sorted(WINDING_PATTERNS)),
    groups=st.integers(1, 6),
    seed=st.integers(0, 2**32 - 1),
    rms=st.floats(0.0, 0.1),
)
def test_layers_tile_the_fibre_and_weights_sum_to_zero(pattern, groups, seed, rms):
    """Any winding, with or without defects, covers [0, L] exactly once: sum w_j = Int (L - 2z) dz = 0."""
    period = len(WINDING_PATTERNS[pattern] or "A")
    layers = period * groups * (2 if pattern == "helical" else 1)
    w = Winding.with_defects(pattern, layers, 1000.0, rms=rms, rng=np.random.default_rng(seed))
    order = np.argsort(w.z0)
    np.testing.assert_allclose(w.z0[order][1:], w.z1[order][:-1], rtol=0, atol=1e-9)
    assert w.z0[order][0] == pytest.approx(0.0, abs=1e-9) and w.z1[order][-1] == pytest.approx(
        1000.0, rel=1e-12
    )
    assert abs(w.weights.sum()) <= 1e-9 * 1000.0**2


# ------------------------------------------------------------------------------ Shupe


@pytest.mark.parametrize("pattern", sorted(WINDING_PATTERNS))
def test_uniform_heating_gives_zero(pattern, rng):
    """A uniform Tdot (and a uniform constraint) gives no rate error for any winding, ideal or defective."""
    coil = CoilSpec(winding=pattern, constraint_cte_inner=7e-6, constraint_cte_outer=7e-6)
    T = np.full(40, units.celsius(35.0))
    for w in (
        Winding.ideal(pattern, 40, 1000.0),
        Winding.with_defects(pattern, 40, 1000.0, rms=0.05, rng=rng),
    ):
        t = shupe_terms(coil, w.weights, T, np.full(40, 1.0 / 60.0))
        scale = coil.shupe_coefficient * 1000.0**2 / 4 / 60.0  # the half-heated value
        for part in (t.shupe, t.dndT_product, t.strain, t.strain_product, t.total):
            assert abs(part) <= 1e-12 * scale


def test_half_fibre_at_1K_per_min_gives_135_6_deg_h():
    """z < L/2 at +1 K/min: Omega = n (dn/dT + n alpha_f) Tdot L / (4 D) (docs/physics.md 3.2)."""
    coil = CoilSpec(winding="helical")
    w = Winding.ideal("helical", 40, 1000.0)
    tdot = np.where(np.arange(40) < 20, 1.0 / 60.0, 0.0)
    t = shupe_terms(coil, w.weights, np.full(40, T0), tdot, constraint_cte=FREE)
    exact = 1.46 * (1.0e-5 + 1.46 * 5.5e-7) * (1.0 / 60.0) * 1000.0 / (4 * 0.1)
    assert t.shupe == pytest.approx(exact, rel=1e-12)
    assert units.to_deg_per_h(t.shupe) == pytest.approx(135.6, abs=0.05)  # printed precision


def _exact_linear_radial_sum(pattern: str, M: int) -> Fraction:
    """sum_j (w_j / l^2) * j/(M-1) with exact rationals, from the A/B sequence (independent of sim.coil)."""
    seq = WINDING_PATTERNS[pattern]
    total = Fraction(0)
    if seq is None:
        for j in range(M):
            total += Fraction(M - 2 * j - 1) * Fraction(j, M - 1)  # w_j = l^2 (M - 2j - 1)
        return total
    seq = seq * (M // len(seq))
    a = b = 0
    for j, c in enumerate(seq):
        if c == "A":  # [L/2 - (a+1) l, L/2 - a l]: w = l (L - 2 z_mid) = l^2 (2a + 1)
            w = Fraction(2 * a + 1)
            a += 1
        else:
            w = -Fraction(2 * b + 1)
            b += 1
        total += w * Fraction(j, M - 1)
    return total


@pytest.mark.parametrize(
    "pattern, printed, digits",
    [
        ("helical", -0.93, 0.005),
        ("dipolar", -0.035, 0.0005),
        ("quadrupolar", 0.0017, 0.00005),
        ("octupolar", 0.0, 1e-15),
    ],
)
def test_linear_radial_tdot_gives_physics_3_2_table(pattern, printed, digits):
    """0.01 K/min outer-inner Tdot difference, linear in radius, M = 40: exact sum and the printed table."""
    coil = CoilSpec(winding=pattern)
    w = Winding.ideal(pattern, 40, 1000.0)
    d = 0.01 / 60.0
    tdot = d * np.arange(40) / 39.0
    got = shupe_terms(coil, w.weights, np.full(40, T0), tdot, constraint_cte=FREE).shupe
    exact = coil.shupe_coefficient * 25.0**2 * d * float(_exact_linear_radial_sum(pattern, 40))
    assert got == pytest.approx(
        exact, rel=1e-12, abs=1e-14 * abs(coil.shupe_coefficient * 625 * d * 10660 / 39)
    )
    assert units.to_deg_per_h(got) == pytest.approx(printed, abs=digits)


def test_ratios_relative_to_helical():
    """docs/physics.md 3.3: dipole 1/27 of helical, quadrupole ~1/500, octupole exactly 0 for a linear profile."""
    h = float(_exact_linear_radial_sum("helical", 40))
    assert float(_exact_linear_radial_sum("dipolar", 40)) / h == pytest.approx(1 / 26.65, rel=0.01)
    assert abs(h / float(_exact_linear_radial_sum("quadrupolar", 40))) == pytest.approx(
        533.0, rel=0.01
    )
    assert _exact_linear_radial_sum("octupolar", 40) == 0


def test_product_term_closed_form():
    """One stretch at uniform T, Tdot: dndT_product = n C2 (T - T0) Tdot w / (L D) exactly."""
    coil = CoilSpec()
    w = np.array([segment_weight(1000.0, 250.0, 10.0)])
    T, tdot = units.celsius(40.0), 1.0 / 60.0
    t = shupe_terms(coil, w, np.array([T]), np.array([tdot]), constraint_cte=np.zeros(1))
    pre = coil.index / (coil.length * coil.diameter)
    assert t.dndT_product == pytest.approx(pre * coil.dn_dT_slope * 40.0 * tdot * 5000.0, rel=1e-12)
    assert t.shupe == pytest.approx(
        pre * (coil.dn_dT + coil.index * coil.fibre_cte) * tdot * 5000.0, rel=1e-12
    )


def test_strain_term_closed_form():
    """A stretch with constraint alpha_c: strain = n/(LD) n xi (alpha_c (1 + kappa (T - T0)) - alpha_f) Tdot w."""
    coil = CoilSpec(constraint_cte_tempco=0.02)
    w = np.array([segment_weight(1000.0, 100.0, 5.0)])
    T, tdot, ac = units.celsius(-10.0), -0.3 / 60.0, 1.5e-5
    t = shupe_terms(coil, w, np.array([T]), np.array([tdot]), constraint_cte=np.array([ac]))
    pre = coil.index / (coil.length * coil.diameter)
    nxi = coil.index * coil.xi
    assert t.strain == pytest.approx(
        pre * nxi * (ac * (1 - 0.2) - coil.fibre_cte) * tdot * w[0], rel=1e-12
    )
    assert t.strain_product == pytest.approx(
        pre * nxi * ac * 0.02 * (-10.0) * tdot * w[0], rel=1e-12
    )


def test_elasto_optic_factor_is_0_78():
    assert elasto_optic_factor(1.46, 0.121, 0.270, 0.17) == pytest.approx(0.783, abs=0.0005)


# --------------------------------------------------------------------------- diffusion


def _slab_analytic(x, t, h, a, terms=400):
    k = 2 * np.arange(terms) + 1
    s = (
        (4 / (np.pi * k))[None, :]
        * np.sin(np.pi * k[None, :] * x[:, None] / h)
        * np.exp(-(k**2) * np.pi**2 * a * t / h**2)
    )
    return 1.0 - s.sum(axis=1)


@pytest.mark.parametrize("scheme", ["implicit", "crank-nicolson"])
def test_slab_step_response_converges_to_analytic(scheme):
    """Both faces stepped 0 -> 1 K: error vs the Fourier series shrinks at the scheme's order.

    Second order in space; backward Euler first order in time, so dt ~ dx^2 keeps the
    whole error O(dx^2): halving dx must divide the error by ~4 (>= 3 asserted).
    (Crank-Nicolson with dt >> dx^2/a rings on this discontinuous start: it is only
    A-stable, the documented reason the coil model defaults to backward Euler.)
    """
    errs = []
    for n in (20, 40):
        dx = 1.0 / n
        dt = 0.5 * dx**2
        net = slab_network(n, 1.0, 1.0)
        steps = int(round(0.05 / dt))
        x, _ = net.simulate(np.ones(steps + 1), dt, x0=np.zeros(n), scheme=scheme)
        centres = (np.arange(n) + 0.5) * dx
        errs.append(np.max(np.abs(x[-1] - _slab_analytic(centres, steps * dt, 1.0, 1.0))))
    assert errs[1] < 5e-3
    assert errs[0] / errs[1] > 3.0


def test_cylinder_slowest_mode_matches_bessel_root():
    """Annulus r in [1, 2] with both faces held: slowest decay rate a lambda_1^2, with
    J0(l r1) Y0(l r2) - J0(l r2) Y0(l r1) = 0; FV error O(dr^2) ~ 1e-4 relative at 200 cells."""
    f = lambda lam: special.j0(lam) * special.y0(2 * lam) - special.j0(2 * lam) * special.y0(lam)  # noqa: E731
    lam1 = optimize.brentq(f, 2.0, 4.0)
    net = slab_network(200, 1.0, 1.0, geometry="cylinder", inner_radius=1.0)
    slowest = np.min(-np.linalg.eigvals(net.A).real)
    assert slowest == pytest.approx(lam1**2, rel=3e-4)


def _annulus_step(r, t, r1, r2, a, terms=40):
    """Annulus r1 < r < r2 at 0, both faces stepped to 1 at t = 0 (Carslaw & Jaeger 13.3):
    T = 1 - sum_n c_n U(l_n r) exp(-a l_n^2 t), U(l r) = J0(l r) Y0(l r1) - J0(l r1) Y0(l r),
    U(l_n r2) = 0, c_n = Int r U dr / Int r U^2 dr (eigenfunction expansion of the initial 1)."""

    def U(lam, x):
        return special.j0(lam * x) * special.y0(lam * r1) - special.j0(lam * r1) * special.y0(
            lam * x
        )

    grid = np.linspace(1.0, (terms + 2) * np.pi / (r2 - r1), 20000)
    v = U(grid, r2)
    brackets = np.nonzero(np.sign(v[:-1]) != np.sign(v[1:]))[0][:terms]
    out = np.ones((len(t), len(r)))
    for i in brackets:
        lam = optimize.brentq(lambda x: U(x, r2), grid[i], grid[i + 1])
        num = integrate.quad(lambda x, lam=lam: x * U(lam, x), r1, r2, limit=200)[0]
        den = integrate.quad(lambda x, lam=lam: x * U(lam, x) ** 2, r1, r2, limit=200)[0]
        out -= (num / den) * U(lam, r)[None, :] * np.exp(-a * lam**2 * np.asarray(t))[:, None]
    return out


def test_coil_network_step_response_matches_annulus_series():
    """The coil's own network (``CoilThermalModel.network``), in the limit where its pack is a
    plain annulus with both faces held: a spool of huge heat capacity, almost decoupled from
    the housing (inner face stays at the spool's initial 1 K), and a huge outer film
    coefficient (outer face at the housing, held at 1 K by a constant chamber). The pack starts
    at 0 K. Cell-centred finite volumes are second order in dr; backward Euler is first order
    in dt, so dt ~ dr^2 keeps the whole error O(dr^2): doubling the layer count must divide the
    error by ~4 (>= 3 asserted). At 40 layers (dr = 0.14 mm, h = 5.6 mm) the leading term
    ~ (dr/h)^2 ~ 6e-4 K for a 1 K step, so 1e-3 K is asserted. The 40-term series is exact to
    far below that after 20 s (exp(-a l_41^2 t) ~ exp(-1600))."""
    times = np.array([20.0, 50.0, 100.0])
    errs = []
    for M in (20, 40):
        coil = CoilSpec(layers=M, winding="helical")
        net = CoilThermalModel(
            coil=coil,
            spool_heat_capacity=1e12,
            spool_housing_conductance=1e-12,
            outer_film_coefficient=1e9,
        ).network()
        dt = 0.02 * (40 / M) ** 2
        n = int(round(times[-1] / dt))
        x0 = np.zeros(M + 2)
        x0[:2] = 1.0  # housing and spool at 1 K, the pack at 0 K
        x, _ = net.simulate(np.ones(n + 1), dt, x0=x0)
        exact = _annulus_step(
            coil.layer_radii, times, coil.inner_radius, coil.outer_radius, coil.diffusivity
        )
        errs.append(np.max(np.abs(x[np.round(times / dt).astype(int), 2:] - exact)))
    assert errs[1] < 1e-3
    assert errs[0] / errs[1] > 3.0


def test_coil_network_housing_is_first_order_lag():
    """Chamber step 0 -> 1 K: backward Euler on tau_h dT_h/dt = u - T_h gives exactly
    T_h[k] = 1 - (1 + dt/tau_h)^-k (closed form of the recursion, 1e-12)."""
    m = CoilThermalModel(housing_time_constant=1200.0)
    dt, n = 5.0, 2000
    u = np.ones(n + 1)
    x, _ = m.network().simulate(u, dt, x0=np.zeros(m.coil.layers + 2))
    k = np.arange(n + 1)
    np.testing.assert_allclose(x[:, 0], 1.0 - (1.0 + dt / 1200.0) ** -k, rtol=0, atol=1e-12)


def test_quasi_steady_ramp_all_layers_at_chamber_rate():
    """Long chamber ramp: every layer, the spool and the housing heat at the chamber rate."""
    m = CoilThermalModel()
    rate = 0.5 / 60.0
    t = np.arange(0, 6 * 3600.0, 5.0)
    x, xdot = m.network().simulate(250.0 + rate * t, 5.0)
    np.testing.assert_allclose(xdot[-1], rate, rtol=1e-6)


def test_steady_state_is_uniform():
    x = CoilThermalModel().network().steady_state(300.0)
    np.testing.assert_allclose(x, 300.0, rtol=1e-13)


# ----------------------------------------------------------------------------- bad input


def test_zero_layers_is_an_error():
    with pytest.raises(ValueError, match=r"coil layers must be an integer >= 1; got 0"):
        CoilSpec(layers=0)


def test_quadrupolar_needs_multiple_of_four_layers():
    with pytest.raises(
        ValueError, match=r"quadrupolar winding needs a layer count that is a multiple of 4.*got 42"
    ):
        CoilSpec(layers=42, winding="quadrupolar")


def test_octupolar_needs_multiple_of_eight_layers():
    with pytest.raises(
        ValueError, match=r"octupolar winding needs a layer count that is a multiple of 8.*got 36"
    ):
        Winding.ideal("octupolar", 36, 1000.0)


def test_unknown_winding_is_an_error():
    with pytest.raises(ValueError, match=r"winding pattern must be one of"):
        CoilSpec(winding="toroidal")


def test_unresolvable_chamber_rate_is_an_error():
    with pytest.raises(
        ValueError, match=r"chamber rate 60 K/min changes the temperature by 5 K per diffusion step"
    ):
        CoilThermalModel().check_step(5.0, 1.0)


def test_step_longer_than_housing_lag_is_an_error():
    with pytest.raises(ValueError, match=r"cannot resolve the housing time constant"):
        CoilThermalModel(housing_time_constant=60.0).check_step(10.0, 1e-4)


def test_defects_need_an_rng():
    with pytest.raises(ValueError, match=r"needs an rng"):
        CoilSpec(winding_defect_rms=0.01).realize_winding()


def test_outer_radius_must_exceed_inner():
    with pytest.raises(ValueError, match=r"outer_radius must be > inner_radius"):
        CoilSpec(inner_radius=0.05, outer_radius=0.04)


def test_default_geometry():
    c = CoilSpec()
    assert c.diameter == pytest.approx(0.1, rel=1e-12)
    assert c.layer_pitch == pytest.approx(0.14e-3, rel=1e-9)
    assert math.isclose(c.diffusivity, 1.5625e-7, rel_tol=1e-12)
