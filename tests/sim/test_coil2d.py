"""Tests of sim.coil2d: materials, FV conduction, winding map, strain, Shupe map, runs."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from gyrobench.base import units
from gyrobench.scenarios.checks import coil as checks_coil
from gyrobench.sim import coil_materials, coil_pack
from gyrobench.sim.coil2d import Coil2D, Coil2DSpec
from gyrobench.sim.coil_winding import Imperfections, fibre_map


def test_silica_dn_dT_matches_published_value():
    # Leviton-Frey Sellmeier at 293 K, 1.55 um: 8.16e-6 /K (Corning 7980)
    assert float(coil_materials.silica_dn_dT(293.0)) == pytest.approx(8.16e-6, abs=0.01e-6)
    # its slope over -10..40 degC is ~2e-8 /K^2 (docs/physics.md 3.7: 2.0-2.3e-8)
    s = (coil_materials.silica_dn_dT(313.15) - coil_materials.silica_dn_dT(263.15)) / 50.0
    assert 1.8e-8 < float(s) < 2.4e-8
    with pytest.raises(ValueError, match="temperature"):
        coil_materials.silica_dn_dT(400.0)


def test_maxwell_limits():
    assert coil_pack.maxwell_conductivity(1.38, 0.2, 0.0) == pytest.approx(0.2)
    assert coil_pack.maxwell_conductivity(0.2, 0.2, 0.7) == pytest.approx(0.2)
    with pytest.raises(ValueError, match="phi"):
        coil_pack.maxwell_conductivity(1.0, 0.2, 1.0)


def test_fibre_length_per_layer_proportional_to_radius():
    spec = Coil2DSpec(crossover_turns=0.0, lead_length=0.0)
    fm = fibre_map(spec)
    per_layer = np.array([fm.ds[fm.layer == j].sum() for j in range(spec.layers)])
    radii = spec.inner_radius + (np.arange(spec.layers) + 0.5) * spec.layer_pitch
    np.testing.assert_allclose(per_layer / radii, 2 * math.pi * spec.turns_per_layer, rtol=1e-12)
    assert fm.length == pytest.approx(per_layer.sum())
    # ideal symmetric winding: midpoint at L/2 within the A/B length difference of the layers
    assert fm.diameter == pytest.approx(2 * np.sum(radii**2) / np.sum(radii), rel=1e-12)


@pytest.mark.parametrize("pattern", ["helical", "dipolar", "quadrupolar", "octupolar"])
def test_pieces_tile_the_fibre(pattern):
    spec = Coil2DSpec(winding=pattern)
    imp = Imperfections.draw(spec, rng=np.random.default_rng(3))
    fm = fibre_map(spec, imp)
    order = np.argsort(fm.s)
    edges_lo = fm.s[order] - 0.5 * fm.ds[order]
    edges_hi = fm.s[order] + 0.5 * fm.ds[order]
    np.testing.assert_allclose(edges_lo[1:], edges_hi[:-1], atol=1e-9)
    assert edges_lo[0] == pytest.approx(0.0, abs=1e-9)
    assert edges_hi[-1] == pytest.approx(fm.length, rel=1e-12)
    assert abs(fm.weights.sum()) < 1e-12 * np.abs(fm.weights).sum()


def test_quadrupole_cancels_radial_gradient_better_than_helical():
    # docs/physics.md 3.7: radial-gradient ratio helical / quadrupole > 100
    out = {}
    for pattern in ("helical", "quadrupolar"):
        spec = Coil2DSpec(winding=pattern, crossover_turns=0.0, lead_length=0.0)
        fm = fibre_map(spec)
        out[pattern] = abs(np.sum(fm.weights * (fm.r - spec.inner_radius)))
    assert out["helical"] / out["quadrupolar"] > 100


def test_composite_cylinder_equal_properties_is_free_expansion():
    a = 23e-6
    pack = coil_pack.PackProperties(1, 1, 1, E_t=70e9, E_r=70e9, nu_tr=0.33, alpha_t=a, alpha_r=a)
    eps, p = coil_pack.composite_cylinder_strain(
        np.array([0.048, 0.052]),
        bore=0.035,
        inner=0.0472,
        outer=0.0528,
        spool_E=70e9,
        spool_nu=0.33,
        spool_alpha=a,
        pack=pack,
    )
    np.testing.assert_allclose(eps, a, rtol=1e-10)
    assert abs(p) < 1e-6


def test_all_coil_checks_pass():
    out = checks_coil.checks(np.random.default_rng(0))
    assert {c.id for c in out} >= {
        "coil.conduction_finite_cylinder",
        "coil.quadrupole_axial_gradient",
        "coil.potted_cylinder_strain",
        "coil.zero_uniform",
        "coil.modal_vs_expm",
    }
    bad = [(c.id, c.rel_error, c.tolerance) for c in out if not c.passed]
    assert not bad


def test_conduction_converges_second_order():
    p = dict(a=0.010, h=0.005, k_r=0.27, k_z=0.40, rho_c=1.7e6)
    errs = []
    for n, i in ((6, 1), (18, 4)):
        v, r, z = checks_coil.finite_cylinder_fv(n, n + 1, 30.0, i, **p)
        errs.append(abs(v - checks_coil.finite_cylinder_analytic(r, z, 30.0, **p)))
    assert errs[0] / errs[1] > 3**1.5  # at least 1.5th order observed on 3x refinement


def test_run_is_exact_on_grid_and_checked_off_grid():
    unit = Coil2D(spec=Coil2DSpec(grid_pack_r=4, grid_pack_z=4))
    tk = np.array([0.0, 1200.0, 4200.0, 7200.0])
    vk = np.array([263.15, 263.15, 313.15, 313.15])
    a = unit.run(tk, vk, dt=60.0)
    b = unit.run(tk, vk, dt=30.0)
    np.testing.assert_allclose(a.total, b.total[::2], rtol=0, atol=1e-9 * np.abs(b.total).max())
    c = unit.run(tk + np.array([0, 7.0, 7.0, 0]), vk, dt=60.0)  # knots off the step grid
    assert 0 < c.convergence <= 2e-3


def test_uniform_temperature_has_no_drift_and_steady_state_is_chamber():
    unit = Coil2D(spec=Coil2DSpec(grid_pack_r=4, grid_pack_z=4))
    r = unit.run(np.array([0.0, 3600.0]), np.array([300.0, 300.0]), dt=60.0)
    # rounding of the modal transform (stiff network: aluminium vs epoxy cells): 1e-10 relative
    np.testing.assert_allclose(r.coil_mean, 300.0, rtol=1e-10)
    assert np.max(np.abs(units.to_deg_per_h(r.total))) < 1e-6


def test_realize_is_deterministic_and_draws_units():
    spec = Coil2DSpec()
    a = spec.realize(rng=np.random.default_rng(5))
    b = spec.realize(rng=np.random.default_rng(5))
    c = spec.realize(rng=np.random.default_rng(6))
    np.testing.assert_array_equal(a.imperfections.turn_errors, b.imperfections.turn_errors)
    assert a.spec == b.spec and a.spec != c.spec
    with pytest.raises(TypeError, match="rng"):
        spec.realize(rng=5)


@pytest.mark.parametrize(
    "kw, match",
    [
        (dict(outer_radius=0.04), "outer_radius"),
        (dict(layers=6), "multiple of 4"),
        (dict(turns_per_layer=1), "turns_per_layer"),
        (dict(gap_coefficient=0.0), "gap_coefficient"),
        (dict(t_lo=320.0), "t_lo"),
        (dict(packing=0.95), "packing"),
    ],
)
def test_bad_spec_refused(kw, match):
    with pytest.raises(ValueError, match=match):
        Coil2DSpec(**kw)


def test_txdt_uses_material_slopes_not_a_constant():
    spec = Coil2DSpec()
    r = np.array([0.05])
    _, b1 = spec.beta_coefficients(r)
    # no material temperature dependence: beta_1 is only the silica dn/dT slope
    flat = dataclasses.replace(
        spec,
        spool=dataclasses.replace(spec.spool, cte_slope=0.0),
        matrix=dataclasses.replace(spec.matrix, cte_slope=0.0),
        glass=dataclasses.replace(spec.glass, cte_slope=0.0),
        coating=dataclasses.replace(spec.coating, cte_slope=0.0),
    )
    _, b1_flat = flat.beta_coefficients(r)
    dn = (coil_materials.silica_dn_dT(spec.t_hi) - coil_materials.silica_dn_dT(spec.t_lo)) / (spec.t_hi - spec.t_lo)
    assert float(b1_flat[0]) == pytest.approx(float(dn), rel=1e-9)
    assert float(b1[0]) > float(b1_flat[0])
    assert units.ZERO_CELSIUS < spec.t_ref


def test_the_mount_makes_an_axial_gradient():
    """The spool bolted at its bottom face heats the pack's bottom first: an axial gradient
    during a ramp, which vanishes when the mount is no better than the gas gap elsewhere
    (the grid is then symmetric about z = 0)."""

    def top_minus_bottom(spec):
        unit = Coil2D(spec=spec)
        t, x = unit.node_temperatures([0.0, 600.0, 3600.0], [263.15, 263.15, 313.15], dt=60.0)
        g = unit._grid
        rows = g.interpolation([0.05, 0.05], [0.45 * spec.height, -0.45 * spec.height])
        top, bottom = x[-1, :-1] @ rows.T
        return float(top - bottom)

    asym = top_minus_bottom(Coil2DSpec())
    sym = top_minus_bottom(Coil2DSpec(mount_coefficient=10.0))
    assert asym < -1e-3  # bottom warmer by more than a millikelvin while heating
    assert abs(sym) < 1e-9 * abs(asym) * 1e3


def test_default_grid_is_converged_for_the_drift():
    """docs/physics.md 3.7 states the default 8 x 8 pack grid gives the peak drift of a drawn
    unit under a 1 K/min ramp within 1 % of a 16 x 16 grid."""
    imp = Imperfections.draw(Coil2DSpec(), rng=np.random.default_rng(3))
    tk = np.array([0.0, 1800.0, 4800.0, 8400.0])
    vk = np.array([263.15, 263.15, 313.15, 313.15])
    peaks = []
    for n in (8, 16):
        spec = Coil2DSpec(grid_spool=3 * n // 8, grid_pack_r=n, grid_pack_z=n)
        peaks.append(np.max(np.abs(Coil2D(spec=spec, imperfections=imp).run(tk, vk).total)))
    assert abs(peaks[0] - peaks[1]) < 0.01 * peaks[1]


def test_orthotropic_composite_cylinder_satisfies_its_equations():
    """The default (orthotropic) pack: check equilibrium, free outer face, interface pressure and
    displacement continuity with the spool's Lame solution, from eps_theta(r) alone (u = eps r,
    u' by a 4th-order central difference), independently of the solver's constants."""
    spec = Coil2DSpec()
    pack = spec.pack(293.15)
    a, b, c = spec.bore_radius, spec.inner_radius, spec.outer_radius
    Es, nus, als = spec.spool.youngs_modulus, spec.spool.poisson, float(spec.spool.alpha(293.15))

    def u(r):
        eps, _ = coil_pack.composite_cylinder_strain(
            np.atleast_1d(r),
            bore=a,
            inner=b,
            outer=c,
            spool_E=Es,
            spool_nu=nus,
            spool_alpha=als,
            pack=pack,
        )
        return eps * np.atleast_1d(r)

    S = np.array([[1 / pack.E_r, -pack.nu_tr / pack.E_t], [-pack.nu_tr / pack.E_t, 1 / pack.E_t]])
    C = np.linalg.inv(S)

    def sigma(r):
        h = 1e-6
        du = (-u(r + 2 * h) + 8 * u(r + h) - 8 * u(r - h) + u(r - 2 * h)) / (12 * h)
        er, et = du - pack.alpha_r, u(r) / r - pack.alpha_t
        return C[0, 0] * er + C[0, 1] * et, C[0, 1] * er + C[1, 1] * et

    _, p = coil_pack.composite_cylinder_strain(
        np.array([b]),
        bore=a,
        inner=b,
        outer=c,
        spool_E=Es,
        spool_nu=nus,
        spool_alpha=als,
        pack=pack,
    )
    scale = p if abs(p) > 0 else 1.0
    sr_out, _ = sigma(np.array([c - 2.1e-6]))
    assert abs(sr_out[0]) < 1e-3 * abs(scale) + 1.0  # free outer face (evaluated just inside)
    sr_in, _ = sigma(np.array([b + 2.1e-6]))
    assert sr_in[0] == pytest.approx(-p, rel=1e-3)
    # equilibrium d(r sigma_r)/dr = sigma_theta in the pack
    r = np.linspace(b + 1e-4, c - 1e-4, 5)
    h = 1e-5
    d_rsr = ((r + h) * sigma(r + h)[0] - (r - h) * sigma(r - h)[0]) / (2 * h)
    np.testing.assert_allclose(d_rsr, sigma(r)[1], rtol=1e-4, atol=1e-3 * abs(scale))
    # the spool (Lame, free bore, pressure p at b) meets the pack without a gap
    u_spool = als * b - p * b / Es * ((b * b + a * a) / (b * b - a * a) - nus)
    assert u(b)[0] == pytest.approx(u_spool, rel=1e-9)


def test_aluminium_expansion_follows_its_two_cited_sources():
    """ALUMINIUM's alpha(T_REF) is the derivative of NIST's 6061-T6 expansion fit (checked here
    by a central difference of the fit itself), and its slope carries it to the Aluminum
    Association's mean 23.6e-6 /K over 20-100 degC at that range's midpoint (60 degC)."""
    a, b, c, d = coil_materials.NIST_6061_EXPANSION

    def strain(T):
        return (a + b * T + c * T**2 + d * T**3) * 1e-5

    h = 0.01
    fd = (strain(293.15 + h) - strain(293.15 - h)) / (2 * h)
    # central-difference truncation of a cubic: d 1e-5 h^2 exactly; rounding ~1e-17
    assert abs(coil_materials.ALUMINIUM.cte - fd) < abs(d) * 1e-5 * h * h + 1e-16
    assert abs(float(coil_materials.ALUMINIUM.alpha(333.15)) - 23.6e-6) < 1e-15


def test_silica_expansion_slope_lies_within_its_verified_bound():
    """alpha(300 K) is Crystran's 0.55e-6 /K, and the (unverified) Hahn & Kirby slope lies
    between 0 and the secant from the minimum-length temperature (~193 K, Souder & Hidnert)."""
    lo, hi = coil_materials.SILICA_CTE_SLOPE_BOUNDS
    assert lo <= coil_materials.SILICA.cte_slope <= hi
    assert abs(float(coil_materials.SILICA.alpha(300.0)) - 0.55e-6) < 1e-18
    assert abs(hi - 0.55e-6 / (300.0 - 193.15)) < 1e-18


def test_coating_elastic_values_do_not_enter():
    """The coating's E, nu, alpha and slope are documented as unused (the elastic model lumps
    the soft coating into the matrix): changing them must leave beta_T unchanged, while its
    conductivity does change the pack."""
    import dataclasses

    spec = Coil2DSpec()
    odd = dataclasses.replace(
        spec.coating, youngs_modulus=7e9, poisson=0.2, cte=3e-4, cte_slope=1e-6
    )
    other = dataclasses.replace(spec, coating=odd)
    r = np.linspace(spec.inner_radius, spec.outer_radius, 5)
    for T in (263.15, 293.15, 313.15):
        assert np.array_equal(spec.beta(r, T), other.beta(r, T))
    hot = dataclasses.replace(spec, coating=dataclasses.replace(spec.coating, conductivity=0.4))
    assert hot.pack().k_r != spec.pack().k_r


def test_a_program_ending_between_grid_points_is_run_to_its_end():
    """A chamber program ending off the step grid (7210 s at dt = 60 s) is run to its end by one
    shorter last step, exact like the others under the first-order hold: its end state equals a
    run whose grid holds the end (dt = 10 s) to rounding, for a program linear between knots on
    both grids."""
    unit = Coil2D(spec=Coil2DSpec(grid_pack_r=4, grid_pack_z=4))
    tk = np.array([0.0, 1200.0, 4200.0, 7210.0])
    vk = np.array([263.15, 263.15, 313.15, 313.15])
    a = unit.run(tk, vk, dt=60.0)
    b = unit.run(tk, vk, dt=10.0)
    assert a.t[-1] == 7210.0 and b.t[-1] == 7210.0
    np.testing.assert_allclose(a.total[-1], b.total[-1], rtol=0, atol=1e-9 * np.abs(b.total).max())
    np.testing.assert_allclose(a.total[:-1], b.total[:-1:6], rtol=0, atol=1e-9 * np.abs(b.total).max())
