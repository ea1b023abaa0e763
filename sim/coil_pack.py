"""The fibre pack as a composite: effective conductivities and expansion (Maxwell, Schapery,
Halpin-Tsai) and the plane-stress composite cylinder (isotropic spool + cylindrically
orthotropic pack) that gives each turn's hoop strain per kelvin.

References
----------
R. A. Schapery, J. Compos. Mater. 2, 380 (1968); J. C. Halpin, J. L. Kardos, Polym. Eng. Sci.
16, 344 (1976); J. C. Maxwell (1873) / L. N. McCartney, composite conductivity; S. G.
Lekhnitskii, Anisotropic Plates (1968); S. Timoshenko, J. N. Goodier, Theory of Elasticity
(1951), compound cylinders; docs/physics.md 3.7.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.base.validate import number_where as _num
from gyrobench.sim.coil_materials import ACRYLATE, EPOXY, SILICA, T_REF, Material

__all__ = [
    "maxwell_conductivity",
    "PackProperties",
    "pack_properties",
    "composite_cylinder_strain",
]


def maxwell_conductivity(k_f: float, k_m: float, phi: float) -> float:
    """Transverse conductivity of parallel cylinders (k_f, fraction phi) in a matrix k_m [W/(m K)].

    k_T = k_m [(k_f + k_m) + phi (k_f - k_m)] / [(k_f + k_m) - phi (k_f - k_m)]
    (Maxwell's dilute-cylinder form, as applied by McCartney; docs/physics.md 3.7).
    """
    _num("maxwell_conductivity", "phi", phi, "in [0, 1)", "", lambda v: 0 <= v < 1)
    return k_m * ((k_f + k_m) + phi * (k_f - k_m)) / ((k_f + k_m) - phi * (k_f - k_m))


@dataclass(frozen=True, slots=True)
class PackProperties:
    """Effective properties of the potted fibre pack (r radial, t hoop = fibre direction, z axial).

    ``k_r``, ``k_z`` [W/(m K)], ``rho_c`` [J/(m^3 K)], ``E_t``, ``E_r`` [Pa], ``nu_tr`` (strain
    in r per strain in t under hoop stress) [-], ``alpha_t``, ``alpha_r`` [1/K] (at the
    temperature the properties were evaluated at).
    """

    k_r: float
    k_z: float
    rho_c: float
    E_t: float
    E_r: float
    nu_tr: float
    alpha_t: float
    alpha_r: float


def pack_properties(
    *,
    packing: float,
    glass_fraction: float,
    interlayer_fraction: float,
    T: float = T_REF,
    glass: Material = SILICA,
    coating: Material = ACRYLATE,
    matrix: Material = EPOXY,
) -> PackProperties:
    """Effective pack properties from its constituents at temperature T [K].

    Parameters
    ----------
    packing : float
        Volume fraction of coated fibre in the pack phi [-].
    glass_fraction : float
        (cladding diameter / coated diameter)^2 [-].
    interlayer_fraction : float
        Resin-rich interlayer thickness over the layer pitch t_l/p [-] (radial only).

    Notes
    -----
    Conduction: Maxwell twice (glass in coating, coated fibre in matrix) for k_T; radial
    series with the interlayer: 1/k_r = (1 - f)/k_T + f/k_m; k_z = k_T (docs/physics.md 3.7).
    Elasticity (glass volume fraction v_g = phi glass_fraction; the soft coating is lumped
    into the matrix): E_t = v_g E_g + (1 - v_g) E_m (Voigt); E_r Halpin-Tsai with xi = 2;
    nu_tr = v_g nu_g + (1 - v_g) nu_m (rule of mixtures). Expansion (Schapery 1968):
    alpha_t = (v_g E_g a_g + (1 - v_g) E_m a_m) / E_t,
    alpha_r = (1 + nu_g) v_g a_g + (1 + nu_m)(1 - v_g) a_m - alpha_t nu_tr.
    """
    o = "pack_properties"
    _num(o, "packing", packing, "in (0, 0.91)", "", lambda v: 0 < v < 0.91)
    _num(o, "glass_fraction", glass_fraction, "in (0, 1)", "", lambda v: 0 < v < 1)
    _num(o, "interlayer_fraction", interlayer_fraction, "in [0, 0.5)", "", lambda v: 0 <= v < 0.5)
    k_fibre = maxwell_conductivity(glass.conductivity, coating.conductivity, glass_fraction)
    k_T = maxwell_conductivity(k_fibre, matrix.conductivity, packing)
    f = interlayer_fraction
    k_r = 1.0 / ((1 - f) / k_T + f / matrix.conductivity)
    vg = packing * glass_fraction
    vc = packing * (1 - glass_fraction)
    rho_c = (
        vg * glass.volumetric_heat_capacity
        + vc * coating.volumetric_heat_capacity
        + (1 - packing) * matrix.volumetric_heat_capacity
    )
    Eg, Em = glass.youngs_modulus, matrix.youngs_modulus
    ag, am = float(glass.alpha(T)), float(matrix.alpha(T))
    E_t = vg * Eg + (1 - vg) * Em
    eta = (Eg / Em - 1) / (Eg / Em + 2.0)
    E_r = Em * (1 + 2.0 * eta * vg) / (1 - eta * vg)
    nu_tr = vg * glass.poisson + (1 - vg) * matrix.poisson
    alpha_t = (vg * Eg * ag + (1 - vg) * Em * am) / E_t
    alpha_r = (1 + glass.poisson) * vg * ag + (1 + matrix.poisson) * (1 - vg) * am - alpha_t * nu_tr
    return PackProperties(k_r, k_T, rho_c, E_t, E_r, nu_tr, alpha_t, alpha_r)


def composite_cylinder_strain(
    r: ArrayLike,
    *,
    bore: float,
    inner: float,
    outer: float,
    spool_E: float,
    spool_nu: float,
    spool_alpha: float,
    pack: PackProperties,
) -> tuple[NDArray[np.float64], float]:
    """Hoop strain per kelvin d eps_theta/dT(r) [1/K] in the pack and interface pressure [Pa/K].

    Plane stress, uniform temperature change. Spool: isotropic annulus bore..inner,
    u = A_s r + B_s / r with the stress-free part alpha_s r. Pack (cylindrically orthotropic,
    stiffness C from the compliance [[1/E_r, -nu_tr/E_t], [-nu_tr/E_t, 1/E_t]]):

        u(r) = A r^k + B r^-k + Gamma r,   k = sqrt(C_tt/C_rr)
        Gamma = [(C_rr - C_rt) alpha_r - (C_tt - C_rt) alpha_t] / (C_rr - C_tt)

    (Lekhnitskii; docs/physics.md 3.7) with Gamma = alpha for an isotropic pack. Four
    conditions: sigma_r(bore) = 0, sigma_r(outer) = 0, u and sigma_r continuous at inner.
    Returns eps_theta = u/r at ``r`` and p = -sigma_r(inner) (positive = compression).
    """
    r = np.asarray(r, dtype=float)
    if not (0 < bore < inner < outer):
        raise ValueError(
            f"need 0 < bore < inner < outer radius; got {bore!r}, {inner!r}, {outer!r}"
        )
    S = np.array([[1 / pack.E_r, -pack.nu_tr / pack.E_t], [-pack.nu_tr / pack.E_t, 1 / pack.E_t]])
    C = np.linalg.inv(S)
    Crr, Crt, Ctt = C[0, 0], C[0, 1], C[1, 1]
    k = math.sqrt(Ctt / Crr)
    beta_r = Crr * pack.alpha_r + Crt * pack.alpha_t
    if abs(Crr - Ctt) <= 1e-9 * Crr:
        if abs(pack.alpha_r - pack.alpha_t) > 1e-12:
            raise ValueError("an isotropic pack needs alpha_r == alpha_t")
        gamma = pack.alpha_r
    else:
        gamma = ((Crr - Crt) * pack.alpha_r - (Ctt - Crt) * pack.alpha_t) / (Crr - Ctt)
    Es = spool_E / (1 - spool_nu**2)

    def spool_sr(rr):  # sigma_r coefficients of (A_s, B_s) and constant, per K
        return np.array([Es * (1 + spool_nu), -Es * (1 - spool_nu) / rr**2]), -Es * (
            1 + spool_nu
        ) * spool_alpha

    def pack_sr(rr):  # sigma_r = Crr u' + Crt u/r - beta_r
        cA = (Crr * k + Crt) * rr ** (k - 1)
        cB = (-Crr * k + Crt) * rr ** (-k - 1)
        return np.array([cA, cB]), (Crr + Crt) * gamma - beta_r

    M = np.zeros((4, 4))
    rhs = np.zeros(4)
    c, d = spool_sr(bore)
    M[0, :2], rhs[0] = c, -d
    c, d = pack_sr(outer)
    M[1, 2:], rhs[1] = c, -d
    # u continuity: A_s a + B_s / a = A a^k + B a^-k + Gamma a
    M[2, :2] = [inner, 1 / inner]
    M[2, 2:] = [-(inner**k), -(inner**-k)]
    rhs[2] = gamma * inner
    cs, ds = spool_sr(inner)
    cp, dp = pack_sr(inner)
    M[3, :2], M[3, 2:], rhs[3] = cs, -cp, dp - ds
    A_s, B_s, A, B = np.linalg.solve(M, rhs)
    eps = A * r ** (k - 1) + B * r ** (-k - 1) + gamma
    cs, ds = spool_sr(inner)
    p = -float(cs @ [A_s, B_s] + ds)
    return eps, p


# ======================================================================================
# finite-volume grid
# ======================================================================================
