"""Fibre coil in (r, z): axisymmetric heat flow, winding map, thermo-elastic strain, Shupe map.

All parameters in SI (m, K, s, W, J, Pa). The chain is

    chamber T_c(t) --(convection h_ch A_h)--> housing (lumped, C_h)
        --(gas gap h_gap on the outer and end faces; contact h_c under the spool)-->
    finite-volume (r, z) grid: spool | fibre pack (anisotropic k_r, k_z) | potting skin
        -> node temperatures T(t) and exact rates Tdot(t) (first-order-hold matrix exponential)
    winding map: every turn of fibre -> (r, z, s along the fibre, ds)
    composite-cylinder strain -> beta_T(r, T) of each turn
    Shupe functional as a LINEAR map on node rates plus one bilinear T x Tdot form:

        Omega_E(t) = (n/(L D)) [ Tdot(t) . W0  +  (T(t) - T0) . Q Tdot(t) ]            [rad/s]

    (beta_T as its chord over [t_lo, t_hi] written about T0 = ``t_ref``: the sum is the same
    for any T0, temperature unit or origin; only the split between the two terms moves)

        W0 = P^T (w * beta_0),   Q = P^T diag(w * beta_1) P,   w_i = ds_i (L - 2 s_i)  [m^2]

with P the bilinear interpolation from the cell centres to the turns (exact for a field
linear in r and z), beta_T(r, T) = beta_0(r) + beta_1(r) (T - T0) the phase coefficient of a
fibre bonded into the pack (docs/physics.md 3.7):

    beta_T = dn/dT(T) + n alpha_f(T) + n xi (d eps_theta/dT (r, T) - alpha_f(T))            [1/K]

dn/dT(T) from the Leviton & Frey (2006) temperature-dependent Sellmeier fit of fused silica;
the expansion coefficients from :data:`SILICA`, :data:`ALUMINIUM`, :data:`EPOXY` (values
and their temperature slopes with sources there); d eps_theta/dT from the plane-stress
composite cylinder (isotropic spool + cylindrically orthotropic pack, Lekhnitskii) with the
CTEs evaluated at T. beta_1 is the secant slope of beta_T over [``t_lo``, ``t_hi``]:
NOTHING in the T x Tdot term is a free constant.

Stated simplifications: axisymmetric (the in-layer crossover sector and the lead routing
are smeared over the circumference; for the Shupe integral this is exact, since in an
axisymmetric temperature field a fibre element's temperature does not depend on its azimuth,
but heat paths that break the symmetry, e.g. a bolt pattern or a cable exit, are not
represented); the strain follows the local temperature with the
uniform-temperature coefficient d eps_theta/dT (quasi-static, no stress from gradients);
plane stress in the pack (free end faces), no potting skin or housing in the elastic model;
moduli independent of temperature; no flanges.

References
----------
D. M. Shupe, Appl. Opt. 19(5) 654 (1980); F. Mohr, J. Lightwave Technol. 14(1) 27 (1996);
D. B. Leviton, B. J. Frey, Proc. SPIE 6273, 62732K (2006); S. G. Lekhnitskii, Anisotropic
Plates (1968), cylindrically anisotropic disc; R. A. Schapery, J. Compos. Mater. 2, 380
(1968) (composite CTEs); J. C. Halpin, J. L. Kardos, Polym. Eng. Sci. 16, 344 (1976);
J. C. Maxwell (1873) / L. N. McCartney, composite conductivity; S. Timoshenko,
J. N. Goodier, Theory of Elasticity (1951), compound cylinders; docs/physics.md 3.7.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from numbers import Integral

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import linalg

from gyrobench.base import units
from gyrobench.base.validate import number_where as _num
from gyrobench.sim.fiber_strain import elasto_optic_factor

__all__ = [
    "WINDING_PATTERNS",
    "winding_sequence",
    "Material",
    "SILICA",
    "SILICA_CTE_SLOPE_BOUNDS",
    "ACRYLATE",
    "EPOXY",
    "ALUMINIUM",
    "nist_6061_alpha",
    "silica_dn_dT",
    "maxwell_conductivity",
    "PackProperties",
    "pack_properties",
    "composite_cylinder_strain",
    "Grid",
    "Coil2DSpec",
    "Imperfections",
    "FibreMap",
    "fibre_map",
    "Coil2D",
    "ThermalRun",
    "fv_grid",
    "first_order_hold",
    "heated_stretch",
]





#: winding name -> the repeating A/B layer sequence (inner -> outer); helical has none.
WINDING_PATTERNS: dict[str, str | None] = {
    "helical": None,
    "dipolar": "AB",
    "quadrupolar": "ABBA",
    "octupolar": "ABBABAAB",
}


def winding_sequence(pattern: str, layers: int) -> str | None:
    """The A/B sequence of ``layers`` layers (inner -> outer), or None for helical.

    Parameters
    ----------
    pattern : str
        A key of :data:`WINDING_PATTERNS` (``"helical"``, ``"dipolar"``, ``"quadrupolar"``,
        ``"octupolar"``).
    layers : int
        Number of layers.

    Returns
    -------
    str or None
        One letter per layer, ``"A"`` or ``"B"`` (the half of the fibre it belongs to); None for
        a helical winding.

    Raises
    ------
    ValueError
        Unknown pattern, or a layer count that is not a multiple of the pattern's period
        (dipolar 2, quadrupolar 4, octupolar 8).
    """
    if pattern not in WINDING_PATTERNS:
        raise ValueError(
            f"winding pattern must be one of {sorted(WINDING_PATTERNS)}; got {pattern!r}"
        )
    if isinstance(layers, bool) or not isinstance(layers, Integral) or layers < 1:
        raise ValueError(f"coil layers must be an integer >= 1; got {layers!r}")
    period = WINDING_PATTERNS[pattern]
    if period is None:
        return None
    if layers % len(period):
        raise ValueError(
            f"{pattern} winding needs a layer count that is a multiple of {len(period)} "
            f"(pattern {period}); got {layers} layers"
        )
    return period * (layers // len(period))


# ======================================================================================
# materials
# ======================================================================================

#: reference temperature of the material tables [K]
T_REF = 293.15


@dataclass(frozen=True, slots=True, kw_only=True)
class Material:
    """An isotropic material near room temperature (SI).

    Parameters
    ----------
    name : str
    conductivity : float
        k [W/(m K)].
    volumetric_heat_capacity : float
        rho c_p [J/(m^3 K)].
    youngs_modulus : float
        E [Pa].
    poisson : float
        nu [-].
    cte : float
        Linear expansion coefficient alpha at ``T_REF`` = 293.15 K [1/K].
    cte_slope : float
        d alpha/dT near ``T_REF`` [1/K^2] (alpha(T) = cte + cte_slope (T - T_REF)).
    source : str
        Where the numbers come from.
    """

    name: str
    conductivity: float
    volumetric_heat_capacity: float
    youngs_modulus: float
    poisson: float
    cte: float
    cte_slope: float
    source: str = ""

    def alpha(self, T: ArrayLike) -> NDArray[np.float64] | float:
        """alpha(T) = cte + cte_slope (T - 293.15 K) [1/K]."""
        return self.cte + self.cte_slope * (np.asarray(T, dtype=float) - T_REF)


#: Fused silica (every value cited; docs/physics.md 3.7 "Material data"): rho 2203 kg/m^3,
#: k 1.38 W/(m K), E 73.1 GPa, nu 0.17, alpha 0.55e-6 /K at 300 K (Crystran Ltd., The Crystran
#: Handbook of Infra-red and Ultra-violet Optical Materials, 5th ed. (2023), fused silica, as
#: tabulated in the refractiveindex.info database); c_p 703 J/(kg K) (Crystran fused silica
#: data sheet). alpha at T_REF = alpha(300 K) - slope x 6.85 K. Slope 2.4e-9 /K^2 (Hahn &
#: Kirby, AIP Conf. Proc. 3, 13 (1972), SRM 739 table; this transcription is not re-verified)
#: is bounded by verified facts: fused silica has its minimum length near -80 degC (Souder &
#: Hidnert, NBS Sci. Paper 524 (1926)), so alpha rises from 0 at ~193 K to 0.55e-6 at 300 K
#: and, rising ever more slowly, its slope at 293 K lies in [0, 0.55e-6 / 107 K = 5.1e-9]
#: (``SILICA_CTE_SLOPE_BOUNDS``). Over that bound the free-fibre T x dT term of paper 003
#: moves by -13 % / +6 % (docs/physics.md 3.7).
SILICA_CTE_SLOPE = 2.4e-9
SILICA_CTE_SLOPE_BOUNDS = (0.0, 0.55e-6 / (300.0 - 193.15))
SILICA = Material(
    name="fused silica",
    conductivity=1.38,
    volumetric_heat_capacity=2203.0 * 703.0,
    youngs_modulus=73.1e9,
    poisson=0.17,
    cte=0.55e-6 - SILICA_CTE_SLOPE * (300.0 - T_REF),
    cte_slope=SILICA_CTE_SLOPE,
    source="Crystran handbook 5th ed. (2023); slope Hahn & Kirby 1972 within the bound "
    "from Souder & Hidnert 1926",
)
#: UV-cured acrylate fibre coating. Only k 0.20 W/(m K) and rho c 1.2e3 x 1.5e3 J/(m^3 K)
#: enter the model (the coating's share of the pack conductivity and heat capacity); both are
#: ASSUMED (no published value was read for this project) and halving or doubling either
#: moves paper 003's drift and T x dT by < 0.5 % (docs/physics.md 9,
#: ``benchmarks/coil_sensitivity.py``). The elastic model lumps the soft coating into the
#: matrix (:func:`pack_properties`), so E, nu, alpha and its slope below are placeholders that
#: no result depends on (``test_coating_elastic_values_do_not_enter``).
ACRYLATE = Material(
    name="acrylate coating",
    conductivity=0.20,
    volumetric_heat_capacity=1.8e6,
    youngs_modulus=0.7e9,
    poisson=0.40,
    cte=1.0e-4,
    cte_slope=3.0e-7,
    source="ASSUMED k and rho c (effect < 0.5 %); elastic values unused",
)
#: Potting epoxy below its glass transition: rho 1300 kg/m^3, E 4 GPa, alpha 60e-6 /K
#: (Budinski & Budinski, Engineering Materials, Prentice Hall (1999), as quoted in Princeton
#: MAE 324's materials glossary); k 0.20 W/(m K), c_p 1500 J/(kg K), nu 0.40 (MakeItFrom.com,
#: "Epoxy"; polymers 0.1-0.2 W/(m K), Windberger et al., Proceedings 69, 18 (2021)). Slope
#: 0.18e-6 /K^2 ASSUMED (the same slope/alpha ratio, 3e-3 /K, as the acrylate; no published
#: alpha(T) read for a potting epoxy); its effect is measured (docs/physics.md 9).
EPOXY = Material(
    name="potting epoxy",
    conductivity=0.20,
    volumetric_heat_capacity=1300.0 * 1500.0,
    youngs_modulus=4.0e9,
    poisson=0.40,
    cte=60e-6,
    cte_slope=0.18e-6,
    source="Budinski & Budinski 1999; MakeItFrom 'Epoxy'; slope ASSUMED",
)
#: Aluminium alloy 6061-T6 spool: rho 2700 kg/m^3, E 68.9 GPa, nu 0.33, k 167 W/(m K) at
#: 25 degC, c_p 896 J/(kg K), mean alpha 23.6e-6 /K over 20-100 degC (Aluminum Association
#: typical values as listed on 6061-T6 material data sheets, e.g. Glemco's). alpha(T_REF)
#: from NIST's cryogenic fit for 6061-T6 (trc.nist.gov/cryogenics/materials, linear
#: expansion (L - L293)/L293 x 1e5 = a + bT + cT^2 + dT^3, 4-300 K, 4 % fit error):
#: d/dT at 293.15 K = 22.64e-6 /K (``nist_6061_alpha``); slope = (23.6e-6 - alpha(293.15 K))
#: / (333.15 K - 293.15 K) = 0.024e-6 /K^2, the AA mean taken at its range's midpoint.
NIST_6061_EXPANSION = (-4.1277e2, -3.0389e-1, 8.7696e-3, -9.9821e-6)


def nist_6061_alpha(T: float) -> float:
    """alpha(T) [1/K] of 6061-T6 from NIST's cryogenic linear-expansion fit (4-300 K).

    Parameters
    ----------
    T : float
        Temperature [K], 4-300 K (the fit's range).

    Returns
    -------
    float
        alpha(T) [1/K].
    """
    _, b, c, d = NIST_6061_EXPANSION
    return (b + 2.0 * c * T + 3.0 * d * T * T) * 1e-5


_AL_ALPHA_REF = nist_6061_alpha(T_REF)
ALUMINIUM = Material(
    name="aluminium 6061-T6",
    conductivity=167.0,
    volumetric_heat_capacity=2700.0 * 896.0,
    youngs_modulus=68.9e9,
    poisson=0.33,
    cte=_AL_ALPHA_REF,
    cte_slope=(23.6e-6 - _AL_ALPHA_REF) / (333.15 - T_REF),
    source="Aluminum Association typical 6061-T6; NIST cryogenic 6061-T6 expansion fit",
)

# Leviton & Frey (2006) temperature-dependent Sellmeier of Corning 7980 (valid 30-310 K):
# n^2 - 1 = sum_i S_i(T) lam^2 / (lam^2 - lam_i(T)^2), lam in um, S_i, lam_i quartic in T [K].
# Coefficients as transcribed in public code citing doi:10.1117/12.672853 (Leviton & Frey, Proc. SPIE 6273 (2006));
# they reproduce dn/dT = 8.16e-6 /K at 293 K, 1.55 um (S1).
_LF_S = np.array(
    [
        [1.10127, -4.94251e-5, 5.27414e-7, -1.59700e-9, 1.75949e-12],
        [1.78752e-5, 4.76391e-5, -4.49019e-7, 1.44546e-9, -1.57223e-12],
        [7.93552e-1, -1.27815e-3, 1.84595e-5, -9.20275e-8, 1.48829e-10],
    ]
)
_LF_L = np.array(
    [
        [-8.906e-2, 9.0873e-6, -6.53638e-8, 7.77072e-11, 6.84605e-14],
        [2.97562e-1, -8.59578e-4, 6.59069e-6, -1.09482e-8, 7.85145e-13],
        [9.34454, -7.09788e-3, 1.01968e-4, -5.07660e-7, 8.21348e-10],
    ]
)


def _silica_index(T: NDArray[np.float64], wavelength: float) -> NDArray[np.float64]:
    lam2 = (wavelength * 1e6) ** 2
    p = T[..., None] ** np.arange(5)
    S = p @ _LF_S.T
    lam_i = p @ _LF_L.T
    return np.sqrt(1.0 + np.sum(S * lam2 / (lam2 - lam_i**2), axis=-1))


def silica_dn_dT(T: ArrayLike, wavelength: float = 1550e-9) -> NDArray[np.float64]:
    """dn/dT of fused silica [1/K] at temperature T [K] (Leviton & Frey 2006 Sellmeier).

    Central difference (h = 0.05 K) of the temperature-dependent Sellmeier index; the fit
    holds for 30-310 K. Accepted to 330 K (the coil spec's t_hi limit); paper 003's programs
    reach 313.15 K, a 3 K extrapolation (stated).

    >>> round(float(silica_dn_dT(293.15)) * 1e6, 2)
    8.16

    Parameters
    ----------
    T : array_like
        Temperature [K], 30-330 K.
    wavelength : float
        Vacuum wavelength [m].

    Returns
    -------
    ndarray
        dn/dT [1/K].
    """
    T = np.asarray(T, dtype=float)
    _num(
        "silica_dn_dT",
        "wavelength",
        wavelength,
        "in (0.2e-6, 3e-6)",
        "m",
        lambda v: 2e-7 < v < 3e-6,
    )
    if np.any((T < 30.0) | (T > 330.0)):
        raise ValueError(
            f"temperature must be within 30-330 K (the Leviton-Frey fit holds to 310 K; beyond, "
            f"a stated extrapolation); got {T!r}"
        )
    h = 0.05
    return (_silica_index(T + h, wavelength) - _silica_index(T - h, wavelength)) / (2 * h)


def maxwell_conductivity(k_f: float, k_m: float, phi: float) -> float:
    """Transverse conductivity of parallel cylinders (k_f, fraction phi) in a matrix k_m [W/(m K)].

    k_T = k_m [(k_f + k_m) + phi (k_f - k_m)] / [(k_f + k_m) - phi (k_f - k_m)]
    (Maxwell's dilute-cylinder form, as applied by McCartney; docs/physics.md 3.7).

    Parameters
    ----------
    k_f : float
        Conductivity of the cylinders (fibres) [W/(m K)].
    k_m : float
        Conductivity of the matrix [W/(m K)].
    phi : float
        Volume fraction of the cylinders [-].

    Returns
    -------
    float
        k_T [W/(m K)].
    """
    _num("maxwell_conductivity", "phi", phi, "in [0, 1)", "", lambda v: 0 <= v < 1)
    return k_m * ((k_f + k_m) + phi * (k_f - k_m)) / ((k_f + k_m) - phi * (k_f - k_m))


@dataclass(frozen=True, slots=True)
class PackProperties:
    """Effective properties of the potted fibre pack (r radial, t hoop = fibre direction, z axial).

    ``k_r``, ``k_z`` [W/(m K)], ``rho_c`` [J/(m^3 K)], ``E_t``, ``E_r`` [Pa], ``nu_tr`` (strain
    in r per strain in t under hoop stress) [-], ``alpha_t``, ``alpha_r`` [1/K] (at the
    temperature the properties were evaluated at).

    Attributes
    ----------
    k_r, k_z : float
        Radial and axial conductivity [W/(m K)].
    rho_c : float
        Volumetric heat capacity [J/(m^3 K)].
    E_t, E_r : float
        Hoop (fibre direction) and radial Young's modulus [Pa].
    nu_tr : float
        Strain in r per strain in t under hoop stress [-].
    alpha_t, alpha_r : float
        Hoop and radial expansion coefficients [1/K].
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
    T : float
        Temperature at which the constituents' properties are taken [K].
    glass, coating, matrix : Material
        The fibre's glass and coating and the potting matrix.

    Returns
    -------
    PackProperties
        The effective properties at ``T``.

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

    Parameters
    ----------
    r : array_like
        Radii in the pack where the hoop strain is wanted [m].
    bore : float
        Inner radius of the spool [m].
    inner : float
        Outer radius of the spool = inner radius of the pack [m].
    outer : float
        Outer radius of the pack [m].
    spool_E : float
        Young's modulus of the spool [Pa].
    spool_nu : float
        Poisson's ratio of the spool [-].
    spool_alpha : float
        Expansion coefficient of the spool [1/K].
    pack : PackProperties
        The pack's effective properties.

    Returns
    -------
    eps_theta : ndarray
        d eps_theta/dT at ``r`` [1/K].
    pressure : float
        Interface pressure per kelvin [Pa/K] (positive = compression).
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


@dataclass(frozen=True, slots=True)
class Grid:
    """Axisymmetric finite-volume grid: conductance matrix, capacities and boundary conductances.

    ``r_faces`` (nr + 1,), ``z_faces`` (nz + 1,) [m]; cell (i, j) is node i * nz + j;
    ``K`` (m, m) conductance matrix [W/K] of the interior links; ``cap`` (m,) [J/K];
    ``g_face`` dict side -> (m,) conductance from each cell centre to that outer face [W/K]
    (zero for cells not on the side; "inner" is zero when the grid starts at r = 0).

    Attributes
    ----------
    r_faces : ndarray, shape (nr + 1,)
        Radial cell faces [m].
    z_faces : ndarray, shape (nz + 1,)
        Axial cell faces [m].
    K : ndarray, shape (m, m)
        Conductance matrix of the interior links [W/K].
    cap : ndarray, shape (m,)
        Heat capacity of each cell [J/K].
    g_face : dict of str to ndarray
        Side -> conductance from each cell centre to that outer face [W/K].
    """

    r_faces: NDArray[np.float64]
    z_faces: NDArray[np.float64]
    K: NDArray[np.float64]
    cap: NDArray[np.float64]
    g_face: dict[str, NDArray[np.float64]]

    @property
    def r_centres(self) -> NDArray[np.float64]:
        f = self.r_faces
        return 0.5 * (f[:-1] + f[1:])

    @property
    def z_centres(self) -> NDArray[np.float64]:
        f = self.z_faces
        return 0.5 * (f[:-1] + f[1:])

    @property
    def shape(self) -> tuple[int, int]:
        return len(self.r_faces) - 1, len(self.z_faces) - 1

    def interpolation(self, r: ArrayLike, z: ArrayLike) -> NDArray[np.float64]:
        """P (n_points, m): bilinear interpolation on the cell centres, linear beyond the edges.

        Exact for any field linear in r and z (so the axial-gradient check is exact).
        """
        r = np.asarray(r, dtype=float)
        z = np.asarray(z, dtype=float)
        rc, zc = self.r_centres, self.z_centres
        nr, nz = self.shape
        i = np.clip(np.searchsorted(rc, r) - 1, 0, nr - 2)
        j = np.clip(np.searchsorted(zc, z) - 1, 0, nz - 2)
        tr = (r - rc[i]) / (rc[i + 1] - rc[i])
        tz = (z - zc[j]) / (zc[j + 1] - zc[j])
        P = np.zeros((len(r), nr * nz))
        rows = np.arange(len(r))
        for di, wr in ((0, 1 - tr), (1, tr)):
            for dj, wz in ((0, 1 - tz), (1, tz)):
                np.add.at(P, (rows, (i + di) * nz + j + dj), wr * wz)
        return P


def fv_grid(
    r_faces: ArrayLike,
    z_faces: ArrayLike,
    k_r: ArrayLike,
    k_z: ArrayLike,
    rho_c: ArrayLike,
) -> Grid:
    """Finite-volume conduction on an (r, z) tensor grid with per-cell properties (shape (nr, nz)).

    Discretises rho c dT/dt = (1/r) d/dr(k_r r dT/dr) + d/dz(k_z dT/dz) (docs/physics.md 3.7):
    radial half-cell resistance ln(r_face / r_c) / (2 pi k_r dz), axial (dz/2) / (k_z pi
    (r2^2 - r1^2)), links in series (harmonic mean across a material interface). Second order
    in space for smooth fields.

    Parameters
    ----------
    r_faces : array_like, shape (nr + 1,)
        Radial cell faces [m].
    z_faces : array_like, shape (nz + 1,)
        Axial cell faces [m].
    k_r, k_z : array_like, shape (nr, nz)
        Radial and axial conductivity of each cell [W/(m K)].
    rho_c : array_like, shape (nr, nz)
        Volumetric heat capacity of each cell [J/(m^3 K)].

    Returns
    -------
    Grid
        The conductances and capacities.
    """
    rf = np.asarray(r_faces, dtype=float)
    zf = np.asarray(z_faces, dtype=float)
    if rf.ndim != 1 or len(rf) < 3 or np.any(np.diff(rf) <= 0) or rf[0] < 0:
        raise ValueError(f"r_faces must be >= 3 increasing radii >= 0 m; got {rf!r}")
    if zf.ndim != 1 or len(zf) < 3 or np.any(np.diff(zf) <= 0):
        raise ValueError(f"z_faces must be >= 3 increasing positions [m]; got {zf!r}")
    nr, nz = len(rf) - 1, len(zf) - 1
    kr = np.broadcast_to(np.asarray(k_r, float), (nr, nz))
    kz = np.broadcast_to(np.asarray(k_z, float), (nr, nz))
    rc_ = np.broadcast_to(np.asarray(rho_c, float), (nr, nz))
    if np.any(kr <= 0) or np.any(kz <= 0) or np.any(rc_ <= 0):
        raise ValueError("k_r, k_z and rho_c must be > 0 in every cell")
    rc = 0.5 * (rf[:-1] + rf[1:])
    dz = np.diff(zf)[None, :]
    area = (math.pi * np.diff(rf**2))[:, None]  # annulus area of each ring [m^2]
    # half-cell resistances [K/W]
    R_out = np.log(rf[1:] / rc)[:, None] / (2 * math.pi * kr * dz)
    with np.errstate(divide="ignore"):
        R_in = np.log(rc / np.where(rf[:-1] > 0, rf[:-1], np.nan))[:, None] / (
            2 * math.pi * kr * dz
        )
    R_z = 0.5 * dz / (kz * area)
    m = nr * nz
    idx = np.arange(m).reshape(nr, nz)
    K = np.zeros((m, m))

    def link(a, b, g):  # a, b: index arrays without repeats, so fancy += is exact
        K[a, a] += g
        K[b, b] += g
        K[a, b] -= g
        K[b, a] -= g

    g_r = 1.0 / (R_out[:-1, :] + R_in[1:, :])
    link(idx[:-1, :].ravel(), idx[1:, :].ravel(), g_r.ravel())
    g_zl = 1.0 / (R_z[:, :-1] + R_z[:, 1:])
    link(idx[:, :-1].ravel(), idx[:, 1:].ravel(), g_zl.ravel())
    cap = (rc_ * area * dz).ravel()
    g_face = {s: np.zeros(m) for s in ("inner", "outer", "bottom", "top")}
    if rf[0] > 0:
        g_face["inner"][idx[0, :]] = 1.0 / R_in[0, :]
    g_face["outer"][idx[-1, :]] = 1.0 / R_out[-1, :]
    g_face["bottom"][idx[:, 0]] = 1.0 / R_z[:, 0]
    g_face["top"][idx[:, -1]] = 1.0 / R_z[:, -1]
    return Grid(r_faces=rf, z_faces=zf, K=K, cap=cap, g_face=g_face)


def first_order_hold(A: NDArray[np.float64], b: NDArray[np.float64], dt: float):
    """(Phi, q0, q1): x_{k+1} = Phi x_k + q0 u_k + q1 u_{k+1}, exact for u linear over each step.

    From expm of the augmented matrix [[A dt, b dt, 0], [0, 0, 1], [0, 0, 0]] (Van Loan
    1978): Phi = E11, Gamma0 = E12, Gamma1 = E13; u(t_k + tau) = u_k + (u_{k+1} - u_k) tau/dt
    gives q0 = Gamma0 - Gamma1, q1 = Gamma1.

    Parameters
    ----------
    A : ndarray, shape (m, m)
        System matrix of dx/dt = A x + b u [1/s].
    b : ndarray, shape (m,)
        Input vector [unit of x per unit of u per s].
    dt : float
        Step [s].

    Returns
    -------
    Phi : ndarray, shape (m, m)
        State transition matrix.
    q0, q1 : ndarray, shape (m,)
        Input weights of u_k and u_{k+1}.
    """
    m = len(b)
    M = np.zeros((m + 2, m + 2))
    M[:m, :m] = A * dt
    M[:m, m] = b * dt
    M[m, m + 1] = 1.0
    E = linalg.expm(M)
    return E[:m, :m], E[:m, m] - E[:m, m + 1], E[:m, m + 1]


# ======================================================================================
# coil specification, drawn imperfections, winding map
# ======================================================================================


@dataclass(frozen=True, slots=True, kw_only=True)
class Coil2DSpec:
    """A potted fibre coil on an aluminium spool in a housing (SI); defaults: a 1 km nav-grade coil.

    Parameters
    ----------
    inner_radius, outer_radius, height : float
        Fibre pack r_i, r_o and axial height H [m] (D ~ 0.1 m, as sim/coil.py).
    layers, turns_per_layer : int
        M layers of N turns: layer j holds N 2 pi r_j of fibre (length proportional to its
        radius); L = N 2 pi sum r_j (+ crossovers and leads) = 1005 m for the defaults.
    winding : str
        ``"helical"``, ``"dipolar"``, ``"quadrupolar"``, ``"octupolar"``.
    bore_radius : float
        Spool bore [m]; the spool is the annulus bore..r_i over the full height.
    skin : float
        Potting skin over the outer and end faces of the pack [m] (stated: 0.5 mm).
    packing, glass_fraction, interlayer_fraction : float
        Coated-fibre volume fraction phi (0.80, stated: quadrupolar packs ~0.8-0.9),
        (80 um / 135 um)^2 = 0.351 (reduced-cladding PM fibre), resin interlayer t_l/p (0.1,
        stated).
    spool, matrix, coating, glass : Material
    index : float
        Effective index n of the guided mode (1.46 as sim/coil.py).
    p11, p12 : float
        Photo-elastic constants of silica (0.121, 0.270; docs/physics.md 3.5).
    wavelength : float
        [m].
    crossover_turns : float
        Fibre length of each layer-to-layer crossover, in turns of its radius (0.5, stated).
    lead_length : float
        Fibre lead from each end of the pack to the coupler [m] (0.5, stated), in the skin
        at the top outer corner.
    lead_difference_rms : float
        rms of a drawn unit's lead A - lead B length (fibre-midpoint error plus pigtail
        routing) [m]. CALIBRATED: 1.0 m sets the median peak drift of drawn units under
        paper 003's validation-1 program (10 degC/h, -10 -> 40 degC) to ~0.15 deg/h, the
        level the paper quotes for a 10 degC change; it is the dominant drift source of a
        drawn quadrupolar unit (0.20 deg/h per m of asymmetry in that program).
    housing_heat_capacity : float
        C_h [J/K] (0.5 kg of aluminium: 450 J/K, stated).
    chamber_conductance : float
        h_ch A_h between chamber air and housing [W/K] (0.375: 12.5 W/(m^2 K) over 0.03 m^2,
        the top of Cengel's free-convection range for gases, 2-25 W/(m^2 K), a slow chamber
        fan; tau_h = C_h/G = 1200 s as sim/coil.py; ASSUMED, effect measured in
        docs/physics.md 9).
    gap_coefficient : float
        h_gap [W/(m^2 K)] of the gas gap between the coil's outer/end/bore faces and the
        housing (10 = k_air/delta for a still-air gap delta = 2.6 mm, k_air 0.026 W/(m K),
        radiation neglected; ASSUMED gap, effect measured in docs/physics.md 9).
    mount_coefficient : float
        h_c [W/(m^2 K)] of the bolted spool-to-housing contact under the spool (bottom face of
        the spool only: the asymmetric mount makes axial gradients) (1000; ASSUMED bolted
        Al-Al joint, effect measured in docs/physics.md 9: none within 0.1 %).
    t_ref, t_lo, t_hi : float
        T0 of the expansion beta_T = beta_0 + beta_1 (T - T0) and the secant range of beta_1
        [K] (15 degC; -10 and 40 degC, paper 003's range). beta_T is the chord over
        [t_lo, t_hi], so T0 moves only the split between the Tdot and T x Tdot terms, never
        their sum (any T0 >= 0 K is accepted: 0 K is the kelvin origin).
    grid_spool, grid_pack_r, grid_pack_z : int
        Cells across the spool, the pack radially and the pack axially (one skin cell each).
    """

    inner_radius: float = 0.0472
    outer_radius: float = 0.0528
    height: float = 0.013
    layers: int = 40
    turns_per_layer: int = 80
    winding: str = "quadrupolar"
    bore_radius: float = 0.035
    skin: float = 0.5e-3
    packing: float = 0.80
    glass_fraction: float = (80.0 / 135.0) ** 2
    interlayer_fraction: float = 0.1
    spool: Material = ALUMINIUM
    matrix: Material = EPOXY
    coating: Material = ACRYLATE
    glass: Material = SILICA
    index: float = 1.46
    p11: float = 0.121
    p12: float = 0.270
    wavelength: float = 1550e-9
    crossover_turns: float = 0.5
    lead_length: float = 0.5
    lead_difference_rms: float = 1.0
    housing_heat_capacity: float = 450.0
    chamber_conductance: float = 0.375
    gap_coefficient: float = 10.0
    mount_coefficient: float = 1000.0
    t_ref: float = units.ZERO_CELSIUS + 15.0
    t_lo: float = units.ZERO_CELSIUS - 10.0
    t_hi: float = units.ZERO_CELSIUS + 40.0
    grid_spool: int = 3
    grid_pack_r: int = 8
    grid_pack_z: int = 8

    def __post_init__(self) -> None:
        o = "Coil2DSpec"
        _num(o, "bore_radius", self.bore_radius, "> 0", "m", lambda v: v > 0)
        _num(
            o,
            "inner_radius",
            self.inner_radius,
            f"> bore_radius ({self.bore_radius!r})",
            "m",
            lambda v: v > self.bore_radius,
        )
        _num(
            o,
            "outer_radius",
            self.outer_radius,
            f"> inner_radius ({self.inner_radius!r})",
            "m",
            lambda v: v > self.inner_radius,
        )
        _num(o, "height", self.height, "> 0", "m", lambda v: v > 0)
        _num(o, "skin", self.skin, "> 0", "m", lambda v: v > 0)
        winding_sequence(self.winding, self.layers)
        for name in ("turns_per_layer", "grid_spool", "grid_pack_r", "grid_pack_z"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, Integral) or v < 2:
                raise ValueError(f"{o}.{name} must be an integer >= 2; got {v!r}")
        for name in ("spool", "matrix", "coating", "glass"):
            if not isinstance(getattr(self, name), Material):
                raise TypeError(
                    f"{o}.{name} must be a Material; got {type(getattr(self, name)).__name__}"
                )
        for name in ("index",):
            _num(o, name, getattr(self, name), ">= 1", "", lambda v: v >= 1)
        for name in ("crossover_turns", "lead_length", "lead_difference_rms"):
            _num(o, name, getattr(self, name), ">= 0", "", lambda v: v >= 0)
        for name in (
            "housing_heat_capacity",
            "chamber_conductance",
            "gap_coefficient",
            "mount_coefficient",
            "wavelength",
        ):
            _num(o, name, getattr(self, name), "> 0", "(SI)", lambda v: v > 0)
        _num(o, "t_lo", self.t_lo, f"< t_hi ({self.t_hi!r})", "K", lambda v: 30 < v < self.t_hi)
        _num(o, "t_hi", self.t_hi, "<= 330", "K", lambda v: v <= 330)
        _num(o, "t_ref", self.t_ref, "in [0, 1000]", "K", lambda v: 0 <= v <= 1000)
        pack_properties(
            packing=self.packing,
            glass_fraction=self.glass_fraction,
            interlayer_fraction=self.interlayer_fraction,
        )

    @property
    def layer_pitch(self) -> float:
        """Radial pitch p_r = (r_o - r_i)/M [m]."""
        return (self.outer_radius - self.inner_radius) / self.layers

    @property
    def xi(self) -> float:
        """Elasto-optic factor xi = 1 - (n^2/2)[p12 - nu (p11 + p12)] [-]."""
        return elasto_optic_factor(self.index, self.p11, self.p12, self.glass.poisson)

    def pack(self, T: float = T_REF) -> PackProperties:
        """Effective pack properties at temperature T [K] (:func:`pack_properties`)."""
        return pack_properties(
            packing=self.packing,
            glass_fraction=self.glass_fraction,
            interlayer_fraction=self.interlayer_fraction,
            T=T,
            glass=self.glass,
            coating=self.coating,
            matrix=self.matrix,
        )

    def hoop_strain_rate(self, r: ArrayLike, T: float) -> NDArray[np.float64]:
        """d eps_theta/dT [1/K] of the pack at radii r with all CTEs taken at T [K]."""
        eps, _ = composite_cylinder_strain(
            r,
            bore=self.bore_radius,
            inner=self.inner_radius,
            outer=self.outer_radius,
            spool_E=self.spool.youngs_modulus,
            spool_nu=self.spool.poisson,
            spool_alpha=float(self.spool.alpha(T)),
            pack=self.pack(T),
        )
        return eps

    def beta(
        self, r: ArrayLike, T: float, *, bonded: ArrayLike | bool = True
    ) -> NDArray[np.float64]:
        """beta_T(r, T) = dn/dT + n alpha_f + n xi (d eps_theta/dT - alpha_f) [1/K].

        Where not ``bonded`` (leads): the free fibre, dn/dT + n alpha_f.
        """
        r = np.asarray(r, dtype=float)
        a_f = float(self.glass.alpha(T))
        n = self.index
        free = float(silica_dn_dT(T, self.wavelength)) + n * a_f
        bonded = np.broadcast_to(np.asarray(bonded, bool), r.shape)
        rr = np.clip(r, self.inner_radius, self.outer_radius)
        mech = n * self.xi * (self.hoop_strain_rate(rr, T) - a_f)
        return free + np.where(bonded, mech, 0.0)

    def beta_coefficients(self, r: ArrayLike, bonded: ArrayLike | bool = True, *, t_ref: float | None = None):
        """(beta_0, beta_1) of the chord of beta_T over [t_lo, t_hi], split about ``t_ref``.

        beta_T(T) is represented by its chord (secant) over the material data's range,
        beta_T(T) ~ beta_T(t_lo) + beta_1 (T - t_lo), beta_1 the secant slope [1/K^2]; written
        about a reference T_ref it is beta_0 + beta_1 (T - T_ref) with beta_0 = the chord at
        T_ref [1/K] (``t_ref`` None: the spec's ``t_ref``). The drift (n/(L D)) [Tdot . W0 +
        (T - T_ref) . Q Tdot] is then the same for every T_ref, in any temperature unit or
        origin; only its split between the Tdot and the T x Tdot terms moves with T_ref
        (the Tdot term by beta_1 (T_ref' - T_ref) . Tdot). beta_0 is the chord, not beta_T at
        t_ref itself: that is 0.2-0.9 % above the chord at 15 degC (the chord's curvature
        error) and would make the sum depend on T_ref at that order.
        """
        t0 = self.t_ref if t_ref is None else float(t_ref)
        lo = self.beta(r, self.t_lo, bonded=bonded)
        b1 = (self.beta(r, self.t_hi, bonded=bonded) - lo) / (self.t_hi - self.t_lo)
        return lo + b1 * (t0 - self.t_lo), b1

    def realize(self, *, rng: np.random.Generator) -> Coil2D:
        """One drawn unit: potting properties and winding imperfections (:class:`Imperfections`).

        Potting spreads (stated, typical batch-to-batch and cure variation; none from a paper):
        matrix CTE x (1 + 0.15 N(0, 1)), matrix modulus x exp(0.3 N(0, 1)), matrix
        conductivity x (1 + 0.1 N(0, 1)), packing + 0.03 N(0, 1) clipped to [0.6, 0.9],
        interlayer fraction uniform in [0.05, 0.2].
        """
        import dataclasses

        if not isinstance(rng, np.random.Generator):
            raise TypeError(f"rng must be a numpy.random.Generator; got {type(rng).__name__}")
        m = self.matrix
        matrix = dataclasses.replace(
            m,
            cte=m.cte * (1 + 0.15 * rng.standard_normal()),
            youngs_modulus=m.youngs_modulus * math.exp(0.3 * rng.standard_normal()),
            conductivity=m.conductivity * (1 + 0.1 * rng.standard_normal()),
        )
        spec = dataclasses.replace(
            self,
            matrix=matrix,
            packing=float(np.clip(self.packing + 0.03 * rng.standard_normal(), 0.6, 0.9)),
            interlayer_fraction=float(rng.uniform(0.05, 0.2)),
        )
        return Coil2D(spec=spec, imperfections=Imperfections.draw(self, rng=rng))


@dataclass(frozen=True, slots=True, kw_only=True)
class Imperfections:
    """Drawn departures of one wound coil from its drawing (all stated, none from a paper).

    Parameters
    ----------
    turn_errors : ndarray of int, shape (M,)
        Extra (+1) or missing (-1) turns per layer; each layer +-1 with probability 0.15
        each (a turn gained or lost at the flange at a layer change; stated).
    radius_errors : ndarray, shape (M,)
        Radial displacement of each layer [m]; N(0, (0.03 p_r)^2) (tension variation; stated).
    lead_difference : float
        Lead A minus lead B length [m]; N(0, ``Coil2DSpec.lead_difference_rms``^2) (CALIBRATED
        rms, see there).
    sensor_z : float
        Axial position of the logged temperature sensor on the outer potting surface,
        as a fraction of the half height in [-1, 1] (uniform; stated).
    """

    turn_errors: NDArray[np.int64]
    radius_errors: NDArray[np.float64]
    lead_difference: float = 0.0
    sensor_z: float = 0.0

    @classmethod
    def none(cls, layers: int) -> Imperfections:
        return cls(turn_errors=np.zeros(layers, dtype=np.int64), radius_errors=np.zeros(layers))

    @classmethod
    def draw(cls, spec: Coil2DSpec, *, rng: np.random.Generator) -> Imperfections:
        M = spec.layers
        te = rng.choice(np.array([-1, 0, 1]), size=M, p=[0.15, 0.7, 0.15])
        return cls(
            turn_errors=te.astype(np.int64),
            radius_errors=0.03 * spec.layer_pitch * rng.standard_normal(M),
            lead_difference=float(spec.lead_difference_rms * rng.standard_normal()),
            sensor_z=float(rng.uniform(-1.0, 1.0)),
        )


@dataclass(frozen=True, slots=True)
class FibreMap:
    """The fibre as pieces: radius r, axial z, fibre coordinate s (from port A), length ds [m].

    ``bonded`` is False for the leads (free fibre); ``layer`` is -1 for leads and
    crossovers. ``length`` L = sum ds; ``diameter`` D = sum_{turns} ds 2 r / L (Sagnac:
    L D = sum of 2 x enclosed area over the turns).

    Attributes
    ----------
    r, z : ndarray
        Radius and axial position of each piece [m].
    s : ndarray
        Fibre coordinate of each piece from port A [m].
    ds : ndarray
        Length of each piece [m].
    bonded : ndarray of bool
        False for the leads (free fibre).
    layer : ndarray of int
        Layer of each piece; -1 for leads and crossovers.
    length : float
        L [m].
    diameter : float
        D [m].
    """

    r: NDArray[np.float64]
    z: NDArray[np.float64]
    s: NDArray[np.float64]
    ds: NDArray[np.float64]
    bonded: NDArray[np.bool_]
    layer: NDArray[np.int64]
    length: float
    diameter: float

    @property
    def weights(self) -> NDArray[np.float64]:
        """w_i = ds_i (L - 2 s_i) [m^2] (exact Int (L - 2z) dz over each piece)."""
        return self.ds * (self.length - 2.0 * self.s)


def _layer_pieces(spec: Coil2DSpec, j: int, up: bool, imp: Imperfections):
    N = spec.turns_per_layer + int(imp.turn_errors[j])
    r = spec.inner_radius + (j + 0.5) * spec.layer_pitch + float(imp.radius_errors[j])
    p = spec.height / N
    u = (np.arange(N) + 0.5) * p - 0.5 * spec.height
    z = u if up else -u
    return np.full(N, r), z, np.full(N, 2 * math.pi * r)


def fibre_map(spec: Coil2DSpec, imperfections: Imperfections | None = None) -> FibreMap:
    """Map every turn (and crossover, lead) of the winding to (r, z, s, ds).

    Symmetric patterns (:data:`WINDING_PATTERNS`): both halves start at
    the fibre midpoint on the spool at the bottom flange; each half reverses its traverse
    direction at every one of its own layers (so a half's next layer starts where its last
    ended); a crossover of ``crossover_turns`` turns joins successive layers of a half at
    the flange, at the mean radius of the two layers. Half A runs from the midpoint toward
    port A (s decreasing), half B toward port B. Helical: one fibre, layer after layer,
    alternating direction. Leads: at the top outer corner, in the skin.

    Parameters
    ----------
    spec : Coil2DSpec
        The coil's drawing.
    imperfections : Imperfections, optional
        Drawn departures from it; None: the ideal winding.

    Returns
    -------
    FibreMap
        The fibre's pieces.
    """
    imp = Imperfections.none(spec.layers) if imperfections is None else imperfections
    if len(imp.turn_errors) != spec.layers or len(imp.radius_errors) != spec.layers:
        raise ValueError(f"imperfections must have one entry per layer ({spec.layers})")
    seq = winding_sequence(spec.winding, spec.layers)
    halves = ["A"] * spec.layers if seq is None else list(seq)
    pieces: dict[str, list[tuple]] = {"A": [], "B": []}
    count = {"A": 0, "B": 0}
    last: dict[str, float | None] = {"A": None, "B": None}
    r_start = spec.inner_radius + 0.5 * spec.layer_pitch
    for j, h in enumerate(halves):
        up = count[h] % 2 == 0 if seq is not None else j % 2 == 0
        r, z, ds = _layer_pieces(spec, j, up, imp)
        prev_r = last[h] if last[h] is not None else (None if h == "A" else r_start)
        if prev_r is not None and spec.crossover_turns > 0:
            rx = 0.5 * (prev_r + r[0])
            zx = -0.5 * spec.height if up else 0.5 * spec.height
            pieces[h].append(
                (
                    np.array([rx]),
                    np.array([zx]),
                    np.array([spec.crossover_turns * 2 * math.pi * rx]),
                    np.array([-1]),
                )
            )
        pieces[h].append((r, z, ds, np.full(len(r), j)))
        count[h] += 1
        last[h] = float(r[0])

    def cat(h):
        if not pieces[h]:
            return (np.zeros(0),) * 3 + (np.zeros(0, dtype=np.int64),)
        return tuple(np.concatenate([p[k] for p in pieces[h]]) for k in range(4))

    rA, zA, dA, lA = cat("A")
    rB, zB, dB, lB = cat("B")
    lead_r = spec.outer_radius + 0.5 * spec.skin
    lead_z = 0.5 * spec.height + 0.5 * spec.skin
    lead_a = max(spec.lead_length + 0.5 * imp.lead_difference, 0.0)
    lead_b = max(spec.lead_length - 0.5 * imp.lead_difference, 0.0)
    if seq is None:  # helical: port A at the first turn; the A list is in s order
        s_A = lead_a + np.cumsum(dA) - 0.5 * dA
        s_mid = lead_a + dA.sum()
        s_B = np.zeros(0)
    else:  # A from the midpoint toward port A, B toward port B
        s_mid = lead_a + dA.sum()
        s_A = s_mid - (np.cumsum(dA) - 0.5 * dA)
        s_B = s_mid + np.cumsum(dB) - 0.5 * dB
    L = s_mid + dB.sum() + lead_b
    r = np.concatenate([[lead_r], rA, rB, [lead_r]])
    z = np.concatenate([[lead_z], zA, zB, [lead_z]])
    s = np.concatenate([[0.5 * lead_a], s_A, s_B, [L - 0.5 * lead_b]])
    ds = np.concatenate([[lead_a], dA, dB, [lead_b]])
    layer = np.concatenate([[-1], lA, lB, [-1]]).astype(np.int64)
    bonded = np.ones(len(r), bool)
    bonded[0] = bonded[-1] = False
    turns = layer >= 0
    D = float(np.sum(ds[turns] * 2 * r[turns]) / L)
    keep = ds > 0
    return FibreMap(
        r=r[keep],
        z=z[keep],
        s=s[keep],
        ds=ds[keep],
        bonded=bonded[keep],
        layer=layer[keep],
        length=float(L),
        diameter=D,
    )


# ======================================================================================
# the coil in its housing: thermal network, Shupe map, runs
# ======================================================================================


@dataclass(frozen=True, slots=True)
class ThermalRun:
    """One chamber program on the coarse thermal step (SI).

    ``t`` (n,) [s]; ``chamber``, ``housing``, ``sensor``, ``coil_mean`` (n,) [K];
    ``shupe`` (n,) [rad/s]: (n/(L D)) Tdot . W0 (beta_T at T0, all of dn/dT, expansion and the
    elasto-optic strain term); ``product`` (n,) [rad/s]: (n/(L D)) (T - T0) . Q Tdot (the
    T x dT term from the material temperature dependences); ``dt`` [s] the step used and
    ``convergence`` the max |Omega(dt) - Omega(dt/2)| / max |Omega(dt/2)| of the check (0 when
    every chamber knot lies on the step grid: the first-order hold is then exact at the samples).

    Attributes
    ----------
    t : ndarray, shape (n,)
        Times [s].
    chamber, housing, sensor, coil_mean : ndarray, shape (n,)
        Chamber, housing, logged-sensor and mean coil temperature [K].
    shupe : ndarray, shape (n,)
        The Tdot rate error [rad/s].
    product : ndarray, shape (n,)
        The T x dT rate error [rad/s].
    dt : float
        Thermal step used [s].
    convergence : float
        Step-halving check [-].
    """

    t: NDArray[np.float64]
    chamber: NDArray[np.float64]
    housing: NDArray[np.float64]
    sensor: NDArray[np.float64]
    coil_mean: NDArray[np.float64]
    shupe: NDArray[np.float64]
    product: NDArray[np.float64]
    dt: float
    convergence: float

    @property
    def total(self) -> NDArray[np.float64]:
        """Non-reciprocal rate error [rad/s]."""
        return self.shupe + self.product


@dataclass(frozen=True, kw_only=True)
class Coil2D:
    """One coil unit: its (r, z) thermal network and the precomputed Shupe map.

    State x = [T of each grid cell (spool | pack | skin columns x skin | pack | skin rows),
    T_housing] [K]:  C dx/dt = -K x + e_h G_ch T_chamber. Boundary links (series with the
    half cell): outer, top and bore faces and the bottom of pack/skin through the gas gap
    h_gap; the spool's bottom face through the mount contact h_c; housing to chamber G_ch.

    Parameters
    ----------
    spec : Coil2DSpec
        The coil's drawing and materials.
    imperfections : Imperfections, optional
        The unit's drawn departures from the drawing; None: the ideal coil.
    """

    spec: Coil2DSpec = field(default_factory=Coil2DSpec)
    imperfections: Imperfections | None = None

    # ---------------------------------------------------------------- geometry
    def grid(self) -> Grid:
        """The FV grid with the materials of spool, pack and skin."""
        c = self.spec
        r_faces = np.concatenate(
            [
                np.linspace(c.bore_radius, c.inner_radius, c.grid_spool + 1),
                np.linspace(c.inner_radius, c.outer_radius, c.grid_pack_r + 1)[1:],
                [c.outer_radius + c.skin],
            ]
        )
        h2 = 0.5 * c.height
        z_faces = np.concatenate(
            [[-h2 - c.skin], np.linspace(-h2, h2, c.grid_pack_z + 1), [h2 + c.skin]]
        )
        nr, nz = len(r_faces) - 1, len(z_faces) - 1
        pack = c.pack(T_REF)
        m = c.matrix
        kr = np.full((nr, nz), m.conductivity)
        kz = kr.copy()
        rc = np.full((nr, nz), m.volumetric_heat_capacity)
        sp = slice(0, c.grid_spool)
        kr[sp, :] = kz[sp, :] = c.spool.conductivity
        rc[sp, :] = c.spool.volumetric_heat_capacity
        pr = slice(c.grid_spool, c.grid_spool + c.grid_pack_r)
        pz = slice(1, 1 + c.grid_pack_z)
        kr[pr, pz], kz[pr, pz], rc[pr, pz] = pack.k_r, pack.k_z, pack.rho_c
        return fv_grid(r_faces, z_faces, kr, kz, rc)

    def network(
        self, chamber_scale: float = 1.0
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], Grid]:
        """(K, cap, g_in, grid): cap dx/dt = -K x + g_in T_chamber; K symmetric [W/K], cap [J/K].

        ``chamber_scale`` multiplies the chamber-housing conductance G_ch (run-to-run airflow).
        """
        _num("Coil2D.network", "chamber_scale", chamber_scale, "> 0", "", lambda v: v > 0)
        c = self.spec
        g_ch = c.chamber_conductance * chamber_scale
        g = self._grid
        nr, nz = g.shape
        m = nr * nz
        rf, zf = g.r_faces, g.z_faces
        dz = np.diff(zf)
        ring = math.pi * np.diff(rf**2)

        def series(g_half, h, area):
            return 1.0 / (1.0 / g_half + 1.0 / (h * area))

        gb = np.zeros(m)
        idx = np.arange(m).reshape(nr, nz)
        outer = idx[-1, :]
        gb[outer] += series(g.g_face["outer"][outer], c.gap_coefficient, 2 * math.pi * rf[-1] * dz)
        inner = idx[0, :]
        gb[inner] += series(g.g_face["inner"][inner], c.gap_coefficient, 2 * math.pi * rf[0] * dz)
        top = idx[:, -1]
        gb[top] += series(g.g_face["top"][top], c.gap_coefficient, ring)
        bot = idx[:, 0]
        h_bot = np.where(np.arange(nr) < c.grid_spool, c.mount_coefficient, c.gap_coefficient)
        gb[bot] += series(g.g_face["bottom"][bot], h_bot, ring)
        K = np.zeros((m + 1, m + 1))
        K[:m, :m] = g.K
        K[:m, :m] += np.diag(gb)
        K[:m, m] = -gb
        K[m, :m] = -gb
        K[m, m] = gb.sum() + g_ch
        cap = np.concatenate([g.cap, [c.housing_heat_capacity]])
        g_in = np.zeros(m + 1)
        g_in[m] = g_ch
        return K, cap, g_in, g

    @cached_property
    def _grid(self) -> Grid:
        return self.grid()

    @cached_property
    def _modes(self):
        return self.modes(1.0)

    def modes(self, chamber_scale: float = 1.0):
        """Modal form x = Tm z, dz/dt = -mu z + beta u (S = C^-1/2 K C^-1/2 = V mu V^T)."""
        K, cap, g_in, _ = self.network(chamber_scale)
        ci = 1.0 / np.sqrt(cap)
        mu, V = np.linalg.eigh(ci[:, None] * K * ci[None, :])
        if np.any(mu <= 0):
            raise ValueError(
                "thermal network is not strictly stable (a node without a path to the chamber)"
            )
        return mu, ci[:, None] * V, V.T @ (ci * g_in)

    def fibre(self) -> FibreMap:
        """This unit's fibre map (:func:`fibre_map`; built once per unit)."""
        return self._fibre

    @cached_property
    def _fibre(self) -> FibreMap:
        return fibre_map(self.spec, self.imperfections)

    @cached_property
    def shupe_map(self) -> tuple[NDArray[np.float64], NDArray[np.float64], float]:
        """(W0 (m+1,) [m^2/K... x beta], Q (m+1, m+1), prefactor n/(L D) [1/m^2]).

        Omega = pre [Tdot . W0 + (T - T0) . Q Tdot]; the housing node has zero weight.
        """
        g = self._grid
        fm = self.fibre()
        P = g.interpolation(fm.r, fm.z)
        b0, b1 = self.spec.beta_coefficients(fm.r, bonded=fm.bonded)
        w = fm.weights
        m = P.shape[1]
        W0 = np.zeros(m + 1)
        W0[:m] = P.T @ (w * b0)
        Q = np.zeros((m + 1, m + 1))
        Q[:m, :m] = P.T @ ((w * b1)[:, None] * P)
        return W0, Q, self.spec.index / (fm.length * fm.diameter)

    @cached_property
    def sensor_row(self) -> NDArray[np.float64]:
        """Interpolation row of the logged sensor on the outer potting surface (m+1,)."""
        c = self.spec
        zs = 0.0 if self.imperfections is None else self.imperfections.sensor_z
        row = self._grid.interpolation([c.outer_radius + c.skin], [zs * 0.5 * c.height])[0]
        return np.concatenate([row, [0.0]])

    # ---------------------------------------------------------------- runs
    def run(
        self,
        chamber_times: ArrayLike,
        chamber_values: ArrayLike,
        *,
        dt: float = 20.0,
        tol: float = 2e-3,
        max_halvings: int = 4,
        chamber_scale: float = 1.0,
    ) -> ThermalRun:
        """Solve the network once for a piecewise-linear chamber program; check convergence.

        Parameters
        ----------
        chamber_times, chamber_values : array_like
            Knots of the chamber temperature program [s], [K] (linear between knots, held
            after the last). The run covers [times[0], times[-1]].
        dt : float
            Coarse thermal step [s]. Stepping is first-order-hold exact (matrix exponential),
            so the only time error is the input's departure from linear within a step (knots
            off the step grid).
        tol : float
            Convergence check: the run is repeated at dt/2 and accepted when
            max |Omega(dt) - Omega(dt/2)| <= tol max |Omega(dt/2)| (else dt is halved, at
            most ``max_halvings`` times, then ValueError).
        chamber_scale : float
            Factor on the chamber-housing conductance for this run (the Shupe map is reused).
        """
        tk = np.asarray(chamber_times, float)
        vk = np.asarray(chamber_values, float)
        if tk.ndim != 1 or tk.shape != vk.shape or len(tk) < 2 or np.any(np.diff(tk) <= 0):
            raise ValueError(
                "chamber_times must be >= 2 increasing knots [s] matching chamber_values [K]"
            )
        _num("Coil2D.run", "dt", dt, "> 0", "s", lambda v: v > 0)
        modes = self._modes if chamber_scale == 1.0 else self.modes(chamber_scale)
        on_grid = np.allclose((tk - tk[0]) / dt, np.round((tk - tk[0]) / dt), atol=1e-9, rtol=0)
        # FOH is exact at the samples for knots on the step grid, and for a constant program wherever
        # its knots fall (it is linear within every step): nothing to check. A constant program's
        # drift is rounding noise, whose relative convergence the check below could never reach.
        if on_grid or np.all(vk == vk[0]):
            return self._solve(tk, vk, dt, modes)
        conv = float("nan")
        for _ in range(max_halvings + 1):
            coarse = self._solve(tk, vk, dt, modes)
            fine = self._solve(tk, vk, dt / 2, modes)
            tot_f = np.interp(coarse.t, fine.t, fine.total)  # every coarse time is a fine one
            scale = max(float(np.max(np.abs(tot_f))), 1e-30)
            conv = float(np.max(np.abs(coarse.total - tot_f))) / scale
            if conv <= tol:
                return _with(coarse, conv)
            dt /= 2
        raise ValueError(
            f"thermal run did not converge to {tol:g} (last {conv:.3g}) down to dt = {dt:g} s"
        )

    def node_temperatures(
        self, chamber_times: ArrayLike, chamber_values: ArrayLike, *, dt: float = 20.0
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(t, x): every node's temperature [K] on the step grid (cells, then housing)."""
        tk = np.asarray(chamber_times, float)
        vk = np.asarray(chamber_values, float)
        _num("Coil2D.node_temperatures", "dt", dt, "> 0", "s", lambda v: v > 0)
        t, _, z = _modal_states(tk, vk, dt, self._modes)
        return t, z @ self._modes[1].T

    @cached_property
    def _pack_mask(self) -> NDArray[np.float64]:
        c = self.spec
        nr, nz = c.grid_spool + c.grid_pack_r + 1, c.grid_pack_z + 2
        mask = np.zeros((nr, nz))
        mask[c.grid_spool : c.grid_spool + c.grid_pack_r, 1 : 1 + c.grid_pack_z] = 1.0
        w = mask.ravel() * self._grid.cap
        return np.concatenate([w / w.sum(), [0.0]])

    def _solve(self, tk, vk, dt, modes) -> ThermalRun:
        """Modal first-order-hold recursion, exact for u linear over each step (mode by mode):

        z_{k+1} = phi z_k + beta [(G0 - G1) u_k + G1 u_{k+1}],  phi = exp(-mu dt),
        G0 = (1 - phi)/mu,  G1 = (mu dt - 1 + phi)/(mu^2 dt).
        """
        mu, Tm, beta = modes
        W0, Q, pre = self.shupe_map
        t, u, z = _modal_states(tk, vk, dt, modes)
        x = z @ Tm.T
        xdot = (np.outer(u, beta) - mu * z) @ Tm.T
        dT = x - self.spec.t_ref
        return ThermalRun(
            t=t,
            chamber=u,
            housing=x[:, -1],
            sensor=x @ self.sensor_row,
            coil_mean=x @ self._pack_mask,
            shupe=pre * (xdot @ W0),
            product=pre * np.einsum("ti,ti->t", dT @ Q, xdot),
            dt=dt,
            convergence=0.0,
        )


def _foh_step(mu, beta, dt):
    """(phi, q0, q1) of one first-order-hold step of length ``dt`` [s] (:meth:`Coil2D._solve`)."""
    h = mu * dt
    phi = np.exp(-h)
    G0 = -np.expm1(-h) / mu
    G1 = np.where(
        h > 1e-6, (h + np.expm1(-h)) / (mu * np.maximum(h, 1e-300)), 0.5 * dt * (1 - h / 3)
    )
    return phi, beta * (G0 - G1), beta * G1


def _modal_states(tk, vk, dt, modes):
    """(t, u, z): sample times [s], chamber input [K] and modal states on the step grid, plus the
    program's end when it falls between grid points (one shorter last step, equally exact)."""
    mu, _, beta = modes
    n = int(math.floor((tk[-1] - tk[0]) / dt + 1e-9)) + 1
    t = tk[0] + dt * np.arange(n)
    last = float(tk[-1] - t[-1])
    partial = last > 1e-9 * dt
    if partial:
        t = np.append(t, tk[-1])
    u = np.interp(t, tk, vk)
    phi, q0, q1 = _foh_step(mu, beta, dt)
    z = np.empty((len(t), len(mu)))
    z[0] = beta * u[0] / mu
    f = np.outer(u[: n - 1], q0) + np.outer(u[1:n], q1)
    for k in range(n - 1):
        z[k + 1] = phi * z[k] + f[k]
    if partial:
        phi_l, q0_l, q1_l = _foh_step(mu, beta, last)
        z[n] = phi_l * z[n - 1] + q0_l * u[n - 1] + q1_l * u[n]
    return t, u, z


def _with(run: ThermalRun, conv: float) -> ThermalRun:
    import dataclasses

    return dataclasses.replace(run, convergence=conv)


def heated_stretch(
    spec: Coil2DSpec,
    T: ArrayLike,
    rate: float,
    *,
    fibre_length: float,
    diameter: float,
    z_center: float,
    seg_length: float,
    radius: float | None = None,
    t_ref: float = units.ZERO_CELSIUS,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Tdot and T x dT rate errors [rad/s] of one heated stretch (paper 003, Table 1 / Fig. 2).

    A stretch of ``seg_length`` [m] centred at ``z_center`` [m] along a fibre of
    ``fibre_length`` L, at temperature T [K] rising at ``rate`` [K/s], the rest static:

        Omega_Tdot = (n/(L D)) beta_0 Tdot w,   Omega_TxdT = (n/(L D)) beta_1 (T - T_ref) Tdot w,
        w = l (L - 2 z_c),  beta_T(T) ~ beta_0 + beta_1 (T - T_ref)

    with beta_T represented by its chord over [t_lo, t_hi] (material data;
    :meth:`Coil2DSpec.beta_coefficients`), so the sum does not depend on ``t_ref`` [K] or on
    the temperature scale; the split does. Default T_ref = 0 degC: the paper's eq. (9),
    dz = alpha_T L0 T with T in degC, puts the reference length at 0 degC, and its T x dT
    regressor has T in degC. ``radius`` None: free fibre (dn/dT + n alpha_f); a radius: fibre
    bonded in the pack at that radius.

    Parameters
    ----------
    spec : Coil2DSpec
        The coil's materials.
    T : array_like
        Temperature of the stretch [K].
    rate : float
        Its heating rate Tdot [K/s].
    fibre_length : float
        Fibre length L [m].
    diameter : float
        Mean coil diameter D [m].
    z_center : float
        Centre z_c of the stretch along the fibre [m].
    seg_length : float
        Length l of the stretch [m].
    radius : float, optional
        Radius at which the fibre is bonded in the pack [m]; None: free fibre.
    t_ref : float
        Reference temperature T_ref [K].

    Returns
    -------
    Omega_Tdot, Omega_TxdT : ndarray
        The two rate errors [rad/s].
    """
    T = np.asarray(T, dtype=float)
    r = np.array([spec.inner_radius if radius is None else radius])
    b0, b1 = (float(v[0]) for v in spec.beta_coefficients(r, bonded=radius is not None, t_ref=t_ref))
    w = seg_length * (fibre_length - 2.0 * z_center)
    pre = spec.index / (fibre_length * diameter)
    return np.full(T.shape, pre * b0 * rate * w), pre * b1 * (T - t_ref) * rate * w
