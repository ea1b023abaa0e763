"""Paper 003's coil studies: the Table 1 / figure 2 point heating and the winding comparison.

Both evaluate the (r, z) coil model (:mod:`gyrobench.sim.coil2d`) on the configured build,
without noise or drawn imperfections; they are the same for every unit.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from gyrobench.base import units
from gyrobench.sim.coil2d import Coil2D, heated_stretch
from gyrobench.sim.coil_winding import WINDING_PATTERNS
from gyrobench.sim.fog2d import FOG2DUnit

from .config import Config
from .results import PointHeating, WindingPeak

__all__ = [
    "SWEEP_LENGTHS_M",
    "SWEEP_RATES_DEGC_PER_MIN",
    "free_fibre_beta_slope",
    "point_heating",
    "point_heating_by_reference",
    "point_heating_result",
    "point_heating_sweep",
    "winding_comparison",
]

_MIN = units.MINUTE


#: the heated lengths [m] and rates [degC/min] of the Table 1 sweep (the paper prints neither)
SWEEP_LENGTHS_M = (1.0, 2.0, 5.0, 10.0, 20.0, 50.0)
SWEEP_RATES_DEGC_PER_MIN = (0.5, 1.0, 2.0)


def point_heating(
    config: Config, *, bonded: bool = False, t_ref: float = units.ZERO_CELSIUS
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Paper Table 1 / figure 2: a stretch of fibre at z = 0.25 L0 heated -10 -> 40 degC.

    The stretch (``point_length_m``) ramps at ``point_rate_degC_per_min``; the rest of the
    coil is static (:func:`gyrobench.sim.coil2d.heated_stretch`). Returns T [degC] and the
    components [deg/h]: the Tdot term (beta_T's chord at ``t_ref``), the T x dT term about
    ``t_ref`` [K] (default 0 degC, the reference of the paper's eq. 9 and of its regressor),
    their sum (the same for any ``t_ref``). ``bonded=False``: a free
    fibre (dn/dT + n alpha_f, the paper's model); True: bonded in the pack at the radius
    of the layer that holds 0.25 L0 of an ideal winding.

    Parameters
    ----------
    config : Config
        The configuration.
    bonded : bool
        Bonded in the pack (else a free fibre).
    t_ref : float
        Reference of the T x dT term [K].

    Returns
    -------
    tuple of ndarray
        (T [degC], Tdot term, T x dT term, their sum [deg/h]).
    """
    spec = config.coil_spec()
    L = config.fibre_length_m
    T_c = np.linspace(config.low_degC, config.high_degC, 201)
    radius = None
    if bonded:
        fm = Coil2D(spec=spec).fibre()
        radius = float(fm.r[np.argmin(np.abs(fm.s / fm.length - config.point_z_fraction))])
    sh, prod = heated_stretch(
        spec,
        units.celsius(T_c),
        config.point_rate_degC_per_min / _MIN,
        fibre_length=L,
        diameter=0.1,
        z_center=config.point_z_fraction * L,
        seg_length=config.point_length_m,
        radius=radius,
        t_ref=t_ref,
    )
    d = units.to_deg_per_h
    return T_c, d(sh), d(prod), d(sh + prod)


def free_fibre_beta_slope(config: Config) -> float:
    """d(beta_T)/dT [1/K^2] of a free fibre: the secant of beta_T over the coil spec's range.

    Parameters
    ----------
    config : Config
        The configuration (its coil).

    Returns
    -------
    float
        d(beta_T)/dT [1/K^2].
    """
    cs = config.coil_spec()
    r_any = np.array([cs.inner_radius])
    rise = cs.beta(r_any, cs.t_hi, bonded=False) - cs.beta(r_any, cs.t_lo, bonded=False)
    return float(rise[0] / (cs.t_hi - cs.t_lo))


def point_heating_sweep(config: Config) -> tuple[tuple[float, float, float], ...]:
    """(heated length [m], rate [degC/min], max |T x dT term| [deg/h]) over the sweep grid.

    The quantities the paper's Table 1 leaves out (``SWEEP_LENGTHS_M`` x
    ``SWEEP_RATES_DEGC_PER_MIN``), each case run through :func:`point_heating` (free fibre,
    T_ref = 0 degC): the claim's value as a function of them, not one assumed case.

    Parameters
    ----------
    config : Config
        The configuration.

    Returns
    -------
    tuple of (float, float, float)
        (heated length [m], rate [degC/min], max |T x dT term| [deg/h]) per case.
    """
    out = []
    for length in SWEEP_LENGTHS_M:
        for rate in SWEEP_RATES_DEGC_PER_MIN:
            c = replace(config, point_length_m=length, point_rate_degC_per_min=rate)
            out.append((length, rate, float(np.max(np.abs(point_heating(c)[2])))))
    return tuple(out)


def point_heating_by_reference(config: Config) -> tuple[tuple[str, float, float], ...]:
    """The point-heating terms of the default case split at three temperature references.

    (reference, max |T x dT term|, max |Tdot term|) [deg/h] of the default case, split at
    0 degC (the paper's eq. 9), at the coil model's t_ref and at 0 K: the sum is the same, the
    split is not.

    Parameters
    ----------
    config : Config
        The configuration.

    Returns
    -------
    tuple of (str, float, float)
        (reference, max |T x dT term|, max |Tdot term|) [deg/h] at 0 degC, the coil's t_ref and 0 K.
    """
    refs = (
        ("0 degC (eq. 9)", units.ZERO_CELSIUS),
        (f"{units.to_celsius(config.coil_spec().t_ref):g} degC (coil t_ref)", config.coil_spec().t_ref),
        ("0 K", 0.0),
    )
    out = []
    for label, t_ref in refs:
        _, sh, prod, _ = point_heating(config, t_ref=t_ref)
        out.append((label, float(np.max(np.abs(prod))), float(np.max(np.abs(sh)))))
    return tuple(out)


def point_heating_result(config: Config) -> PointHeating:
    """Table 1 / figure 2's point heating, free and bonded, with the sweep and the split.

    :func:`point_heating` free and bonded, with the coil constants Table 1 prints, the sweep
    over the quantities it leaves out and the split at three references.

    Parameters
    ----------
    config : Config
        The configuration.

    Returns
    -------
    PointHeating
        The result.
    """
    T_pt, sh_pt, prod_pt, tot_pt = point_heating(config)
    coil = config.coil_spec()
    return PointHeating(
        sweep=point_heating_sweep(config),
        by_reference=point_heating_by_reference(config),
        T_degC=T_pt,
        shupe=sh_pt,
        product=prod_pt,
        total=tot_pt,
        bonded_max=float(np.max(np.abs(point_heating(config, bonded=True)[2]))),
        b_free=free_fibre_beta_slope(config),
        fibre_cte_per_K=float(coil.glass.cte),
        wavelength_m=float(coil.wavelength),
    )


def winding_comparison(config: Config) -> tuple[WindingPeak, ...]:
    """Peak coil drift [deg/h] of the identification run per ideal winding (no noise or defects).

    Parameters
    ----------
    config : Config
        The configuration.

    Returns
    -------
    tuple of WindingPeak
        One per winding.
    """
    out = []
    prof = config.identification_profile()
    d = units.to_deg_per_h
    for pattern in WINDING_PATTERNS:
        try:
            spec = config.fog_spec(winding=pattern)
        except ValueError as exc:  # layer count not a multiple of the pattern's period
            out.append(WindingPeak(winding=pattern, error=str(exc)))
            continue
        run = FOG2DUnit(spec=spec, coil=Coil2D(spec=spec.coil)).thermal_response(prof)
        out.append(
            WindingPeak(
                winding=pattern,
                peak_total=float(np.max(np.abs(d(run.total)))),
                peak_shupe=float(np.max(np.abs(d(run.shupe)))),
                peak_product=float(np.max(np.abs(d(run.product)))),
            )
        )
    return tuple(out)
