"""What the MEMS resonator checks share: the false-alarm rate, the RK4 and F-ratio tolerances, the
check units (closed loop and open loop), the noise-free integrations and the outside references.

The checks themselves are :mod:`gyrobench.scenarios.checks.mems` (closed loop),
:mod:`gyrobench.scenarios.checks.mems_noise` (noise, continuity, low output rate),
:mod:`gyrobench.scenarios.checks.mems_open_loop` and :mod:`gyrobench.scenarios.checks.mems_psd`.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from gyrobench.sim.mems_resonator import (
    MemsResonator,
)
from gyrobench.sim.mems_slow_flow import slow_flow

__all__ = ["FALSE_ALARM", "STEPS_PER_CYCLE", "check_unit", "open_loop_unit", "rk4_tolerance", "variance_ratio_bounds"]

#: two-sided false-alarm rate of every statistical check
FALSE_ALARM = 1e-6
#: RK4 steps per drive period of the noise-free closed-loop integration (the least
#: simulate_full takes): its tolerance 3 (w dt)^4/120 = 6.0e-4 (2.4e-4 at the 20 used before,
#: for a quarter more time); every error it bounds but the slow flow's own moved with it as
#: h^4, the largest staying at 0.57 of it, and a 10 % model error is still 170 tolerances out
STEPS_PER_CYCLE = 16
#: full-integration record [s] and the settling part discarded [s]: noise-free, so the 2 ms kept
#: (two output samples) need no length for averaging (the 10 ms kept before changed no check by
#: more than a tenth of its tolerance)
FULL_DURATION = 0.042
FULL_SETTLE = 0.04
#: rates of the noise-free full integration [deg/s]
FULL_RATES_DPS = (0.0, 100.0, 1000.0, 3000.0, 6000.0)
#: temperature offset of the full-integration unit from T0 [K]
DELTA_T = 20.0
#: specific force of the g-sensitivity cases [m/s^2] (+- 20 g)
G_CASE = 20.0 * 9.80665

#: outside references of the checks (docstring of :mod:`gyrobench.sim.mems_resonator`)
LELAND = "R. P. Leland, 'Mechanical-thermal noise in MEMS gyroscopes', IEEE Sensors J. 5(3) 493 (2005)"
ACAR_SHKEL = "C. Acar, A. Shkel, MEMS Vibratory Gyroscopes (Springer, 2009), ch. 2"
SAUKOSKI = ("M. Saukoski, System and circuit design for a capacitive MEMS gyroscope, Helsinki Univ. of "
            "Technology doctoral thesis (2008), ch. 2-3")
KAAJAKARI = "V. Kaajakari, Practical MEMS (Small Gear Publishing, 2009), ch. 6-7"
SECOND_FULL = ("second method: fixed-step RK4 of the full rotating-frame equations of motion with the "
               "carrier (" + ACAR_SHKEL + ")")


def rk4_tolerance(unit: MemsResonator, steps_per_cycle: int = STEPS_PER_CYCLE) -> float:
    """3 (w dt)^4 / 120: RK4's relative frequency error, carried by three observables.

    An error model with a safety factor, not a strict bound: RK4's phase error per step of a
    harmonic oscillator is (w dt)^5/120, i.e. a relative frequency error (w dt)^4/120, and an
    observable that compounds it through up to three factors (frequency, amplitude read-out,
    demodulation) is allowed three times that. Measured at 16, 20 and 32 steps per period the
    RK4-dominated checks stay at a fixed fraction of it (scale factor 0.40, drive amplitude
    0.57-0.61, slow flow vs full 0.40), i.e. their error scales as h^4 as the model says; the
    g-sensitivity and rate-authority checks also carry a step-independent part (3.9e-5 and
    1.5e-5 of their value at 48 steps) the model does not contain, 0.16 and 0.04 of this at 16
    steps. RK4's amplitude loss (w dt)^6/144 per step is outside it: the AGC's start value
    pre-compensates it and the loop absorbs it.

    Parameters
    ----------
    unit : MemsResonator
        The unit integrated.
    steps_per_cycle : int
        RK4 steps per drive period.

    Returns
    -------
    float
        The relative tolerance [-].
    """
    wdt = 2.0 * math.pi / steps_per_cycle
    return 3.0 * wdt**4 / 120.0


def variance_ratio_bounds(dof: float, false_alarm: float = FALSE_ALARM) -> tuple[float, float]:
    """Two-sided chi-square bounds of s^2/sigma^2 with ``dof`` degrees of freedom.

    Parameters
    ----------
    dof : float
        Degrees of freedom.
    false_alarm : float
        Two-sided false-alarm rate.

    Returns
    -------
    tuple of float
        (low, high) of s^2/sigma^2.
    """
    from scipy import stats

    return (
        float(stats.chi2.ppf(false_alarm / 2, dof) / dof),
        float(stats.chi2.ppf(1 - false_alarm / 2, dof) / dof),
    )


def check_unit() -> MemsResonator:
    """The resonator every MEMS check runs: the default with its errors and a quiet front end.

    The default resonator with quadrature, a phase error and anisodamping (no trim, no ADC), and a
    quiet front end (pick-off noise 1e-13 m/sqrt(Hz), no 1/f term): the default's high-range-part
    front end (``DEFAULT_PICKOFF_NOISE``) would bury the Brownian noise these checks compare with
    its closed form, and the 1/f term is not part of the resonator's physics being checked.

    Returns
    -------
    MemsResonator
        Quadrature coupling 1e-4, phase error 0.02 rad, anisodamping 5e-4, no output quantizer,
        pick-off noise 1e-13 m/sqrt(Hz), no bias instability.
    """
    return MemsResonator(
        quadrature_coupling=1e-4, phase_error=0.02, damping_coupling=5e-4, output_bits=None,
        pickoff_noise=1e-13, bias_instability=0.0,
    )


def _slow_noise_free(unit: MemsResonator, rates, temperature: float, rng: np.random.Generator):
    res = slow_flow(unit, np.tile(rates, (40, 1)), fs=1000.0, rng=rng, temperature=temperature,
                   noise=False, adc=False, flicker=False)
    return res.output[-1], res.sense_envelope[-1]


def open_loop_unit() -> MemsResonator:
    """:func:`check_unit` read out open loop.

    Returns
    -------
    MemsResonator
        The check unit with readout ``"open_loop"``.
    """
    return replace(check_unit(), readout="open_loop")
