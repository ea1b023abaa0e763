"""Material data of a fibre coil: fused silica, the acrylate coating, the potting epoxy and an
aluminium spool, each value with its source; silica's dn/dT(T) from the Leviton & Frey (2006)
temperature-dependent Sellmeier fit.

All values in SI (kg/m^3, W/(m K), J/(kg K), Pa, 1/K). The expansion coefficients carry their
temperature slopes (alpha(T) = alpha + slope (T - T_REF)), which set the T x dT term of the
Shupe map (:mod:`gyrobench.sim.coil2d`, docs/physics.md 3.7).

References
----------
D. B. Leviton, B. J. Frey, Proc. SPIE 6273, 62732K (2006); the sources of each material are
stated beside it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.base.validate import number_where as _num

__all__ = [
    "T_REF",
    "Material",
    "SILICA",
    "SILICA_CTE_SLOPE",
    "SILICA_CTE_SLOPE_BOUNDS",
    "ACRYLATE",
    "EPOXY",
    "ALUMINIUM",
    "NIST_6061_EXPANSION",
    "nist_6061_alpha",
    "silica_dn_dT",
]


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
    """alpha(T) [1/K] of 6061-T6 from NIST's cryogenic linear-expansion fit (4-300 K)."""
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
