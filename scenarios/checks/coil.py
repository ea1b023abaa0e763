"""Closed-form checks of the (r, z) fibre coil (:mod:`gyrobench.sim.coil2d`).

``checks(rng) -> list[Check]`` (no random numbers are needed: every check is deterministic;
``rng`` is accepted for the collector's contract):

- ``coil.conduction_finite_cylinder``: the FV solver on an anisotropic finite cylinder after
  a step in surface temperature vs the product of the radial Bessel series and the axial
  Fourier series (docs/physics.md 3.7); tolerance from Richardson extrapolation of a 3x grid
  refinement (second-order scheme).
- ``coil.zero_uniform``: a uniform temperature rate gives no Shupe error for any winding
  (sum of the turn weights vs their magnitude; rounding tolerance).
- ``coil.quadrupole_axial_gradient``: the quadrupolar residual under a pure axial gradient
  of the temperature rate, through the precomputed node map, vs its closed form per layer.
- ``coil.shupe_radial_helical`` / ``coil.shupe_radial_quadrupolar`` /
  ``coil.shupe_radial_cancellation_ratio``: the Shupe integral sum_i w_i Tdot_i of the (r, z)
  coil (ideal winding, no crossovers or leads) under a heating rate linear in radius,
  Tdot = G r, through the node map, vs its closed form layer by layer: a layer of N turns at
  radius r_j holds Lambda_j = 2 pi r_j N of fibre; its turns' weights sum to
  Lambda_j (L - 2 s_mid,j) (linear in s), with s_mid,j = C_j + Lambda_j/2 (helical, C_j the
  fibre wound before) or L/2 -+ (C_j + Lambda_j/2) (half A / B of a symmetric winding, C_j the
  half's earlier layers); Shupe, Appl. Opt. 19 (1980) 654 for the weighting (L - 2z).
- ``coil.potted_cylinder_strain`` / ``coil.potted_cylinder_pressure``: the composite-cylinder
  solver with an isotropic pack vs the compound-cylinder (Lame) closed form.
- ``coil.modal_vs_expm``: the modal first-order-hold stepping vs the matrix exponential of
  the augmented system (Van Loan) on a chamber ramp.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from gyrobench.base import units
from gyrobench.scenarios.checks.core import CLOSED_FORM, CONSISTENCY, SECOND_METHOD, Check
from gyrobench.sim import coil2d, coil_heat, coil_pack, coil_winding
from gyrobench.sim.coil_winding import winding_sequence

__all__ = ["checks", "finite_cylinder_analytic", "finite_cylinder_fv"]

#: outside references of the checks
SHUPE = ("D. M. Shupe, 'Thermally induced nonreciprocity in the fiber-optic interferometer', "
         "Appl. Opt. 19(5) 654 (1980)")
MOHR = "F. Mohr, J. Lightwave Technol. 14(1) 27 (1996)"

_EPS = np.finfo(float).eps


def finite_cylinder_analytic(r, z, t, *, a, h, k_r, k_z, rho_c, terms: int = 80) -> float:
    """(T - T_s)/(T0 - T_s) of a solid cylinder (radius a, half height h) after a surface step.

    theta = [sum_n 2/(b_n J1(b_n)) J0(b_n r/a) exp(-b_n^2 Fo_r)]
            x [sum_m 4 (-1)^m/((2m+1) pi) cos((2m+1) pi z/(2h)) exp(-((2m+1) pi/2)^2 Fo_z)],
    Fo_r = k_r t/(rho_c a^2), Fo_z = k_z t/(rho_c h^2) (separation of variables;
    Carslaw & Jaeger, Conduction of Heat in Solids (1959) sec. 7.3 and 3.3).

    Parameters
    ----------
    r, z : float
        Radius and height from the mid-plane of the point [m].
    t : float
        Time after the step [s].
    a : float
        Cylinder radius [m].
    h : float
        Half height [m].
    k_r, k_z : float
        Radial and axial conductivities [W/(m K)].
    rho_c : float
        Volumetric heat capacity [J/(m^3 K)].
    terms : int
        Terms of each series.

    Returns
    -------
    float
        theta [-].
    """
    from scipy import special

    b = special.jn_zeros(0, terms)
    fr = k_r * t / (rho_c * a * a)
    R = np.sum(2 / (b * special.j1(b)) * special.j0(b * r / a) * np.exp(-(b**2) * fr))
    m = np.arange(terms)
    q = (2 * m + 1) * math.pi / 2
    fz = k_z * t / (rho_c * h * h)
    Z = np.sum(4 * (-1.0) ** m / ((2 * m + 1) * math.pi) * np.cos(q * z / h) * np.exp(-(q**2) * fz))
    return float(R * Z)


def finite_cylinder_fv(nr: int, nz: int, t: float, i: int, *, a, h, k_r, k_z, rho_c):
    """FV value and its location (r, z) at radial cell ``i`` of the middle row (nz odd).

    Surfaces (outer, top, bottom) held at 0 through their half cells, initial 1; solved
    exactly in time by the symmetric eigen-decomposition (no time-step error).

    Parameters
    ----------
    nr, nz : int
        Radial and axial cells (nz odd).
    t : float
        Time after the step [s].
    i : int
        The radial cell of the middle row.
    a : float
        Cylinder radius [m].
    h : float
        Half height [m].
    k_r, k_z : float
        Radial and axial conductivities [W/(m K)].
    rho_c : float
        Volumetric heat capacity [J/(m^3 K)].

    Returns
    -------
    tuple of (float, float, float)
        (theta [-], r [m], z [m]).
    """
    g = coil_heat.fv_grid(np.linspace(0, a, nr + 1), np.linspace(-h, h, nz + 1), k_r, k_z, rho_c)
    Kd = g.K + np.diag(g.g_face["outer"] + g.g_face["top"] + g.g_face["bottom"])
    ci = 1 / np.sqrt(g.cap)
    mu, V = np.linalg.eigh(ci[:, None] * Kd * ci[None, :])
    y0 = np.sqrt(g.cap)  # C^(1/2) x0 with x0 = 1
    y = V @ (np.exp(-mu * t) * (V.T @ y0))
    x = ci * y
    j = nz // 2
    return float(x[i * nz + j]), float(g.r_centres[i]), float(g.z_centres[j])


def _conduction_check() -> Check:
    p: dict[str, Any] = dict(a=0.010, h=0.005, k_r=0.27, k_z=0.40, rho_c=1.7e6)
    t = 30.0
    nr, nz = 6, 7
    coarse, r0, z0 = finite_cylinder_fv(nr, nz, t, 0, **p)
    fine, r1, z1 = finite_cylinder_fv(3 * nr, 3 * nz, t, 1, **p)  # same cell centre (a/12, 0)
    if abs(r0 - r1) > 1e-12 or abs(z0 - z1) > 1e-12:
        raise RuntimeError(f"refined cell centre moved: ({r0}, {z0}) -> ({r1}, {z1})")
    expected = finite_cylinder_analytic(r1, z1, t, **p)
    richardson = abs(fine - coarse) / (3**2 - 1)
    return Check(
        id="coil.conduction_finite_cylinder",
        kind=CLOSED_FORM,
        reference=(
            "H. S. Carslaw, J. C. Jaeger, Conduction of Heat in Solids, 2nd ed. (Oxford, 1959): "
            "product of the infinite-cylinder and slab solutions"
        ),
        formula="theta = [sum 2/(b J1(b)) J0(b r/a) e^(-b^2 Fo_r)] x [sum 4(-1)^m/((2m+1)pi) "
        "cos((2m+1)pi z/2h) e^(-((2m+1)pi/2)^2 Fo_z)]; a 10 mm, h 5 mm, k_r 0.27, k_z 0.40 "
        "W/(m K), rho c 1.7e6 J/(m^3 K), t 30 s, at the cell next to the centre",
        expected=expected,
        simulated=fine,
        tolerance=2 * richardson / abs(expected),
        derivation="second-order FV, 3x refinement (18 x 21 vs 6 x 7 cells, same cell centre): "
        "error of the fine grid ~ |fine - coarse| / (3^2 - 1) (Richardson); factor 2 for the "
        "pre-asymptotic range; time exact (eigen-decomposition); 80 series terms (truncation "
        "< 1e-12)",
    )


def _uniform_check() -> Check:
    spec = dataclasses.replace(coil2d.Coil2DSpec(), winding="quadrupolar")
    unit = coil2d.Coil2D(
        spec=spec, imperfections=coil_winding.Imperfections.draw(spec, rng=np.random.default_rng(1))
    )
    w = unit.fibre().weights
    scale = float(np.sum(np.abs(w)))
    return Check(
        id="coil.zero_uniform",
        kind=CLOSED_FORM,
        reference=SHUPE,
        formula="sum_i ds_i (L - 2 s_i) = Int_0^L (L - 2z) dz = 0 [m^2] (uniform Tdot, any "
        "winding)",
        expected=0.0,
        simulated=float(np.sum(w)),
        scale=scale,
        tolerance=len(w) * _EPS * 4,
        derivation="rounding: n_pieces x 4 eps relative to sum |w_i| (summation of n terms)",
    )


def quadrupole_axial_closed_form(spec: coil2d.Coil2DSpec, G: float) -> float:
    """sum_i w_i G z_i [m^3/s... per unit beta] for an ideal winding without crossovers or leads.

    A layer of N turns (pitch p = H/N, turn length l = 2 pi r) traversed in direction
    sigma_z (+1 up) whose fibre coordinate runs sigma_s (-1 toward port A, +1 toward B):
    with centred turn index u, z = sigma_z p u and s = s_mid + sigma_s l u, so
    sum_t l (L - 2 s) G z = -2 sigma_s sigma_z G p l^2 sum u^2
                          = -sigma_s sigma_z G p l^2 N (N^2 - 1)/6.
    Each half reverses its traverse at each of its own layers, starting upward.
    """
    seq = winding_sequence(spec.winding, spec.layers)
    assert seq is not None  # a symmetric winding (helical has no A/B sequence)
    N = spec.turns_per_layer
    p = spec.height / N
    count = {"A": 0, "B": 0}
    total = 0.0
    for j, half in enumerate(seq):
        r = spec.inner_radius + (j + 0.5) * spec.layer_pitch
        sz = 1 if count[half] % 2 == 0 else -1
        ss = -1 if half == "A" else 1
        total += -ss * sz * G * p * (2 * math.pi * r) ** 2 * N * (N * N - 1) / 6
        count[half] += 1
    return total


def _quadrupole_check() -> Check:
    spec = dataclasses.replace(coil2d.Coil2DSpec(), crossover_turns=0.0, lead_length=0.0)
    unit = coil2d.Coil2D(spec=spec)
    fm = unit.fibre()
    g = unit._grid
    P = g.interpolation(fm.r, fm.z)
    G = 1.0  # K/s per m
    zc = np.tile(g.z_centres, g.shape[0])  # node i*nz + j -> z_j
    simulated = float((P.T @ fm.weights) @ (G * zc))
    expected = quadrupole_axial_closed_form(spec, G)
    scale = float(np.sum(np.abs(fm.weights * G * fm.z)))
    return Check(
        id="coil.quadrupole_axial_gradient",
        kind=CLOSED_FORM,
        reference=SHUPE + "; " + MOHR,
        formula="sum_layers -sigma_s sigma_z G p (2 pi r_j)^2 N (N^2 - 1)/6 [m^3 K/s per m], "
        "ideal ABBA, 40 layers x 80 turns, G = 1 K/s/m, through the node map W = P^T w",
        expected=expected,
        simulated=simulated,
        tolerance=64 * len(fm.z) * _EPS * scale / abs(expected),
        derivation="bilinear interpolation is exact for a linear field, so only rounding: "
        "64 n eps x sum |w z| / |expected| (n pieces, the residual is a cancellation)",
    )


def radial_shupe_closed_form(spec: coil2d.Coil2DSpec, G: float) -> float:
    """sum_layers sum_turns l (L - 2 s) G r_j [m^3 K/s] for Tdot = G r, ideal winding, layer by layer."""
    seq = winding_sequence(spec.winding, spec.layers)
    radii = [spec.inner_radius + (j + 0.5) * spec.layer_pitch for j in range(spec.layers)]
    lam = [spec.turns_per_layer * 2 * math.pi * r for r in radii]
    length = sum(lam)
    total = 0.0
    if seq is None:  # helical: one fibre from port A, layer after layer
        wound = 0.0
        for r, lj in zip(radii, lam, strict=True):
            total += G * r * lj * (length - 2 * wound - lj)
            wound += lj
        return total
    wound_half = {"A": 0.0, "B": 0.0}  # each half from the fibre midpoint toward its port
    for r, lj, half in zip(radii, lam, seq, strict=True):
        sign = 1.0 if half == "A" else -1.0
        total += sign * G * r * lj * (2 * wound_half[half] + lj)
        wound_half[half] += lj
    return total


def _radial_shupe_checks() -> list[Check]:
    out: dict[str, tuple[float, float, float, int]] = {}
    for winding in ("helical", "quadrupolar"):
        spec = dataclasses.replace(coil2d.Coil2DSpec(), winding=winding, crossover_turns=0.0, lead_length=0.0)
        unit = coil2d.Coil2D(spec=spec)
        fm = unit.fibre()
        g = unit._grid
        P = g.interpolation(fm.r, fm.z)
        rc = np.repeat(g.r_centres, g.shape[1])  # node i*nz + j -> r_i
        simulated = float((P.T @ fm.weights) @ rc)
        scale = float(np.sum(np.abs(fm.weights * fm.r)))
        out[winding] = (simulated, radial_shupe_closed_form(spec, 1.0), scale, len(fm.r))
    checks = []
    tols = {}
    for winding, (sim, cf, scale, n) in out.items():
        tols[winding] = 64 * n * _EPS * scale / abs(cf)
        checks.append(
            Check(
                id=f"coil.shupe_radial_{winding}",
                kind=CLOSED_FORM,
                reference=SHUPE + "; " + MOHR,
                formula="sum_j (+-) G r_j Lambda_j (L - 2 s_mid,j), Lambda_j = 2 pi r_j N "
                f"[m^3 K/s per (K/s/m)]; {winding}, 40 layers x 80 turns, Tdot = G r, G = 1 K/s/m, "
                "through the node map W = P^T w (Shupe weighting, Appl. Opt. 19 (1980) 654)",
                expected=cf,
                simulated=sim,
                tolerance=tols[winding],
                derivation="bilinear interpolation is exact for a field linear in r, so only "
                f"rounding: 64 n eps x sum |w r| / |expected| (n = {n} pieces)",
            )
        )
    (h, hcf, _, _), (q, qcf, _, _) = out["helical"], out["quadrupolar"]
    checks.append(
        Check(
            id="coil.shupe_radial_cancellation_ratio",
            kind=CLOSED_FORM,
            reference=SHUPE + "; " + MOHR,
            formula="Shupe integral helical / quadrupolar under Tdot = G r, (r, z) coil, closed "
            "forms layer by layer",
            expected=hcf / qcf,
            simulated=h / q,
            tolerance=tols["helical"] + tols["quadrupolar"],
            derivation="relative errors of a ratio add: the two checks' tolerances summed",
        )
    )
    return checks


def _strain_checks() -> list[Check]:
    a, b, c = 0.035, 0.0472, 0.0528
    Es, nus, als = 69e9, 0.33, 23.1e-6
    Ep, nup, alp = 5e9, 0.3, 50e-6
    pack = coil_pack.PackProperties(
        k_r=1, k_z=1, rho_c=1, E_t=Ep, E_r=Ep, nu_tr=nup, alpha_t=alp, alpha_r=alp
    )
    r = np.array([b, 0.5 * (b + c), c])
    eps, p = coil_pack.composite_cylinder_strain(
        r, bore=a, inner=b, outer=c, spool_E=Es, spool_nu=nus, spool_alpha=als, pack=pack
    )
    p_cf = (als - alp) / (
        ((b * b + a * a) / (b * b - a * a) - nus) / Es
        + ((c * c + b * b) / (c * c - b * b) + nup) / Ep
    )
    eps_cf = alp + p_cf * b * b / (Ep * (c * c - b * b)) * ((1 - nup) + (1 + nup) * c * c / r**2)
    der = "4x4 linear solve, condition number < 1e6: 1e6 x eps ~ 2e-10, rounded up to 1e-9"
    common = (
        "plane-stress compound cylinder, Al spool 35-47.2 mm, "
        "isotropic pack 47.2-52.8 mm (5 GPa, 0.3, 50e-6/K)"
    )
    return [
        Check(
            id="coil.potted_cylinder_strain",
            kind=CLOSED_FORM,
            reference=(
                "S. Timoshenko, J. N. Goodier, Theory of Elasticity, 2nd ed. (McGraw-Hill, 1951): "
                "thick-walled and compound cylinders (Lame)"
            ),
            formula="eps_theta(r) = alpha_p + p b^2/(E_p (c^2 - b^2)) [(1 - nu_p) + (1 + nu_p) "
            "c^2/r^2] "
            f"per K at the pack mid-radius ({common}; Timoshenko & Goodier)",
            expected=float(eps_cf[1]),
            simulated=float(eps[1]),
            tolerance=1e-9,
            derivation=der,
        ),
        Check(
            id="coil.potted_cylinder_pressure",
            kind=CLOSED_FORM,
            reference=(
                "S. Timoshenko, J. N. Goodier, Theory of Elasticity, 2nd ed. (McGraw-Hill, 1951): "
                "thick-walled and compound cylinders (Lame)"
            ),
            formula="p = (alpha_s - alpha_p) / ([(b^2 + a^2)/(b^2 - a^2) - nu_s]/E_s + "
            f"[(c^2 + b^2)/(c^2 - b^2) + nu_p]/E_p) per K ({common})",
            expected=float(p_cf),
            simulated=p,
            tolerance=1e-9,
            derivation=der,
        ),
    ]


def _modal_check() -> Check:
    unit = coil2d.Coil2D(spec=coil2d.Coil2DSpec(grid_pack_r=4, grid_pack_z=4))
    tk = np.array([0.0, 600.0, 3600.0])
    vk = np.array([263.15, 263.15, 313.15])
    dt = 60.0
    run = unit.run(tk, vk, dt=dt)
    K, cap, g_in, _ = unit.network()
    A, bvec = -K / cap[:, None], g_in / cap
    Phi, q0, q1 = coil_heat.first_order_hold(A, bvec, dt)
    u = run.chamber
    x = np.linalg.solve(A, -bvec * u[0])
    for k in range(len(u) - 1):
        x = Phi @ x + q0 * u[k] + q1 * u[k + 1]
    return Check(
        id="coil.modal_vs_expm",
        kind=SECOND_METHOD,
        reference=(
            "second method: the matrix exponential of the augmented system (C. F. Van Loan, IEEE "
            "Trans. Autom. Control 23(3) 395 (1978)) against modal first-order-hold stepping"
        ),
        formula="housing temperature after a 50 K chamber ramp: modal FOH recursion vs "
        "expm of the augmented [[A dt, b dt, 0], [0, 0, 1], [0, 0, 0]] (Van Loan 1978) [K]",
        expected=float(x[-1]),
        simulated=float(run.housing[-1]),
        tolerance=1e-9,
        derivation="both exact for a piecewise-linear input; differences are rounding in "
        "expm (scaling and squaring) and the eigen-decomposition: 1e-9 relative",
    )


def _origin_check() -> Check:
    """The coil drift does not depend on the temperature scale's origin (docs/physics.md 3.7).

    A physical drift cannot change with where temperature is measured from: the coil's
    Tdot and T x dT terms are written about ``Coil2DSpec.t_ref``, so moving t_ref from 15 degC
    to 0 K moves the split between them (by ~40 % of the drift here) and leaves their sum
    unchanged but for rounding.
    """
    spec = dataclasses.replace(coil2d.Coil2DSpec(grid_pack_r=4, grid_pack_z=4), lead_difference_rms=1.0)
    imp = coil_winding.Imperfections.draw(spec, rng=np.random.default_rng(3))
    times = np.array([0.0, 3600.0, 7200.0])
    values = units.celsius(np.array([-10.0, 40.0, 40.0]))
    runs = [
        coil2d.Coil2D(spec=dataclasses.replace(spec, t_ref=t_ref), imperfections=imp).run(times, values)
        for t_ref in (units.celsius(15.0), 0.0)
    ]
    return Check(
        id="coil.drift_temperature_origin",
        kind=CONSISTENCY,
        reference=SHUPE + " (the drift depends on temperature rates and differences only, not on the scale's origin)",
        formula="Omega_E(t_ref = 15 degC) - Omega_E(t_ref = 0 K) = 0 [rad/s] (only the Tdot / T x dT split "
        "moves; -10 -> 40 degC in 1 h)",
        expected=0.0,
        simulated=float(np.max(np.abs(runs[1].total - runs[0].total))),
        scale=float(np.max(np.abs(runs[0].total))),
        tolerance=1e-12,
        derivation="rounding: each term is below 10 x the drift and passes ~100 floating-point operations, "
        "10 x 100 x eps = 2.2e-13, so 1e-12",
    )


def checks(rng: np.random.Generator) -> list[Check]:
    """All coil checks (deterministic; ``rng`` unused but required by the collector).

    Parameters
    ----------
    rng : numpy.random.Generator
        The module's stream (the collector's contract; a deterministic module does not draw from it).

    Returns
    -------
    list of Check
        The module's checks.
    """
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator; got {type(rng).__name__}")
    return [
        _conduction_check(),
        _uniform_check(),
        _quadrupole_check(),
        *_radial_shupe_checks(),
        *_strain_checks(),
        _modal_check(),
        _origin_check(),
    ]
