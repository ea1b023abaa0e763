"""Paper 003's coil identified from the paper's device-level report.

The paper (Sec. 0, citing its ref. [4]) reports the device level: "for a +-0.01 deg/h FOG a
10 degC change of the coil temperature gives a 0.15 deg/h temperature drift". The (r, z) coil
(:mod:`gyrobench.sim.coil2d`) takes every material constant from data; what is not known is
the size of a unit's winding imperfections, and the one that dominates a drawn quadrupolar
coil's drift is the lead asymmetry (lead A - lead B fibre length, drawn N(0, s^2) per unit).
Its spread s (``Config.lead_difference_rms_m``) is the one CALIBRATED parameter, identified
here:

    find s such that  median_{i=1..N} max_{t in ramp} |Omega_E,i(t; s)| = 0.15 deg/h

with Omega_E,i the coil drift [deg/h] of drawn coil i (``Coil2DSpec.realize`` with the
identification seeds, not the evaluation's) under the validation-1 chamber program (soak at
-10 degC, 10 degC/h to 40 degC: the coil warms 10 degC in each hour), the maximum taken over
the soak and the ramp (what validation 1 scores), solved by bisection on s to ``XTOL_M``.
N = 60: the median of N drawn peaks has a sampling spread of roughly 1.25/sqrt(N) relative
(the peaks are near half-normal in s); 20 coils gave 1.44 m, 60 give 1.198 m. The
"+-0.01 deg/h" class is read as the noise level and is not identified (the noise budget is a
stated choice in ``Config``). The result is frozen in :data:`IDENTIFIED` with its inputs;
``Config.lead_difference_rms_m`` defaults to it and the tests re-run the identification's
defining equation on it.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from gyrobench.base import units

from .config import Config

__all__ = ["IDENTIFIED", "XTOL_M", "Identification", "identify_lead_asymmetry", "median_peak_drift"]

#: the bisection's tolerance on the lead-asymmetry spread [m]
XTOL_M = 0.01


@dataclass(frozen=True, slots=True, kw_only=True)
class Identification:
    """The identified lead-asymmetry spread with the inputs that determine it.

    Attributes
    ----------
    target_deg_h : float
        The median peak drift aimed at [deg/h].
    units : int
        Coils drawn.
    first_seed : int
        Their first seed.
    bracket_m : tuple of float
        The bisection's bracket [m].
    xtol_m : float
        Its tolerance [m].
    lead_difference_rms_m : float
        The identified spread [m].
    median_peak_deg_h : float
        The median peak drift there [deg/h].
    """

    target_deg_h: float  # the paper's drift level for a 10 degC change
    units: int  # drawn coils of the identification population
    first_seed: int  # their seeds: first_seed, first_seed + 1, ...
    bracket_m: tuple[float, float]  # the bisection's starting interval [m]
    xtol_m: float
    lead_difference_rms_m: float  # the identified spread (CALIBRATED) [m]
    median_peak_deg_h: float  # the median peak drift at that spread [deg/h]


def median_peak_drift(config: Config, lead_rms_m: float, *, n_units: int, first_seed: int) -> float:
    """Median peak coil drift [deg/h] of the validation-1 program over drawn coils.

    Median over drawn coils of the peak |coil drift| [deg/h] of the validation-1 program while
    scored (soak and ramp), at lead-asymmetry spread ``lead_rms_m`` [m] (the coil alone: no loop,
    no noise).

    Parameters
    ----------
    config : Config
        The configuration.
    lead_rms_m : float
        The lead-asymmetry spread [m].
    n_units : int
        Coils drawn.
    first_seed : int
        Their first seed.

    Returns
    -------
    float
        The median of each coil's peak |drift| while scored [deg/h].
    """
    if not (np.isfinite(lead_rms_m) and lead_rms_m >= 0):
        raise ValueError(f"lead_rms_m must be finite and >= 0 (m); got {lead_rms_m!r}")
    if isinstance(n_units, bool) or not isinstance(n_units, int) or n_units < 1:
        raise ValueError(f"n_units must be an integer >= 1; got {n_units!r}")
    spec = replace(config, lead_difference_rms_m=float(lead_rms_m)).coil_spec()
    rate = config.validation1_rate_degC_per_h / units.HOUR
    prof = config.validation_profile(rate)
    end_ramp = float(prof.times[2])
    peaks = []
    for seed in range(first_seed, first_seed + n_units):
        run = spec.realize(rng=np.random.default_rng(seed)).run(prof.times, prof.values)
        keep = run.t <= end_ramp
        peaks.append(float(np.max(np.abs(units.to_deg_per_h(run.total[keep])))))
    return float(np.median(peaks))


def identify_lead_asymmetry(
    config: Config,
    *,
    target_deg_h: float = 0.15,
    n_units: int = 60,
    first_seed: int = 10_000,
    bracket_m: tuple[float, float] = (0.25, 4.0),
    xtol_m: float = XTOL_M,
) -> Identification:
    """Bisect the lead-asymmetry spread until the median peak drift meets ``target_deg_h``.

    The median peak grows with the spread (each coil's lead term scales with it); the bracket
    must contain the target (else ValueError naming it).

    Parameters
    ----------
    config : Config
        The configuration.
    target_deg_h : float
        The median peak drift aimed at [deg/h].
    n_units : int
        Coils drawn.
    first_seed : int
        Their first seed.
    bracket_m : tuple of float
        The bracket of the spread [m].
    xtol_m : float
        The bisection's tolerance [m].

    Returns
    -------
    Identification
        The identified spread and its inputs.
    """
    lo, hi = bracket_m

    def f(s: float) -> float:
        return median_peak_drift(config, s, n_units=n_units, first_seed=first_seed) - target_deg_h

    f_lo, f_hi = f(lo), f(hi)
    if not f_lo < 0 < f_hi:
        raise ValueError(
            f"bracket_m must bracket the target {target_deg_h} deg/h; got {bracket_m!r} "
            f"(median peaks {f_lo + target_deg_h:.4g} and {f_hi + target_deg_h:.4g} deg/h)"
        )
    while hi - lo > xtol_m:
        mid = 0.5 * (lo + hi)
        if f(mid) < 0:
            lo = mid
        else:
            hi = mid
    s = round(0.5 * (lo + hi), 3)
    return Identification(
        target_deg_h=target_deg_h,
        units=n_units,
        first_seed=first_seed,
        bracket_m=bracket_m,
        xtol_m=xtol_m,
        lead_difference_rms_m=s,
        median_peak_deg_h=median_peak_drift(config, s, n_units=n_units, first_seed=first_seed),
    )


#: :func:`identify_lead_asymmetry` (default arguments) on ``Config()`` with the spread set aside
#: (frozen; re-run in tests/scenarios/test_ifog_thermal.py)
IDENTIFIED = Identification(
    target_deg_h=0.15,
    units=60,
    first_seed=10_000,
    bracket_m=(0.25, 4.0),
    xtol_m=XTOL_M,
    lead_difference_rms_m=1.198,
    median_peak_deg_h=0.15027451089459892,
)
