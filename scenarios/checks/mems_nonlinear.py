"""Closed-form checks of the smooth scale-factor nonlinearity (:mod:`gyrobench.sim.mems_nonlinear`).

``checks(rng) -> list[Check]`` (the contract of :mod:`gyrobench.scenarios.checks.core`), on paper
001's default device (the resonator population of
:mod:`gyrobench.scenarios.papers.p001_mems_scale_factor` read out through the identified Rapp
front end, :data:`~gyrobench.scenarios.papers.p001_mems_scale_factor.identify.IDENTIFIED`) and
on a Duffing sense mode built from the default resonator's physical constants:

* ``mems.nonlinear_small_signal_scale_factor``: central-difference slope of the composed
  transfer (Duffing sense beam, then the identified Rapp front end) at zero rate vs 1: both
  series start with the rate itself (Nayfeh & Mook, *Nonlinear Oscillations*, Wiley 1979,
  ch. 4: the Duffing response to first order is the linear one; Rapp 1991, as eq. 4.45 of
  Ghannouchi, Hammi & Helaoui, *Behavioral Modeling and Predistortion of Wideband Wireless
  Transmitters*, Wiley 2015: unit small-signal gain).
* ``mems.nonlinear_cubic_coefficient``: the leading cubic coefficient of the Duffing sense
  transfer, Richardson-extrapolated from (y - x)/x^3 at two small rates, vs the first-order
  perturbation of the harmonic-balance equation dk A + (3/4) k3 A^3 = F (Nayfeh & Mook ch. 4),
  read out at the small-signal scale factor: a3 = -(3/4) k3 (2 m w X0)^2 / dk^3 [s^2/rad^2].
* ``mems.nonlinear_monotone_3600``: the smallest secant slope of the identified transfer on a
  0.1 deg/s grid over +-3600 deg/s vs the closed-form derivative of the Rapp characteristic at
  the end rate, dy/dx = (1 + |x/Omega_s|^(2p))^(-1 - 1/(2p)) (> 0: strictly increasing; the
  derivative falls with |x|, so its minimum over the range is at the ends).
* ``mems.nonlinear_no_clip_3600``: the unit of the default 001 population (20 units drawn as
  the experiment draws them) with the lowest force-rebalance authority, noise-free slow flow
  at +-3600 deg/s with the 20-bit ADC, read through the identified transfer, vs the unclipped
  closed form transfer(SF Omega + ZRO): a rebalance clamp (Saukoski 2008 ch. 2-3: the
  feedback force range bounds the input range) or the ADC range inside +-3600 deg/s would
  flatten it by far more than the tolerance.

Tolerances: rounding and the truncation of the finite differences, derived per check.
Fast (closed forms and one short noise-free slow-flow call): about 0.1 s.
"""

from __future__ import annotations

import numpy as np

from gyrobench.base import units
from gyrobench.scenarios.checks.core import Check
from gyrobench.sim import mems_resonator as mr
from gyrobench.sim.mems_nonlinear import DuffingSense, RateTransfer

__all__ = ["checks", "duffing_check_sense"]

_EPS = float(np.finfo(float).eps)
#: cubic stiffness of the check's Duffing sense beam [N/m^3]: puts its critical rate near
#: 3000 deg/s for the default resonator (a check value, not a default of any device)
_K3 = 1.6e9
#: outside references of the checks
_NAYFEH = "A. H. Nayfeh, D. T. Mook, Nonlinear Oscillations (Wiley, 1979), ch. 4"
_RAPP = ("C. Rapp (1991), as eq. 4.45 of F. M. Ghannouchi, O. Hammi, M. Helaoui, Behavioral Modeling and "
         "Predistortion of Wideband Wireless Transmitters (Wiley, 2015)")


def duffing_check_sense() -> DuffingSense:
    """A Duffing sense mode with the default resonator's m, w, w_y, Q_y, X0 and k3 = 1.6e9 N/m^3."""
    op = mr.operating_point(mr.MemsResonator())
    return DuffingSense(
        mass=op.m, drive_omega=op.wx, sense_omega=op.wy, sense_q=mr.MemsResonator().sense_q,
        k3=_K3, drive_amplitude=op.x0,
    )


def _identified() -> RateTransfer:
    from gyrobench.scenarios.papers.p001_mems_scale_factor.identify import IDENTIFIED, transfer_of

    return transfer_of(IDENTIFIED)


def _small_signal() -> Check:
    rail = _identified()
    sense = duffing_check_sense()
    t = RateTransfer(duffing_rate=sense.critical_rate, rail_rate=rail.rail_rate, rail_order=rail.rail_order)
    h = 1e-5 * t.duffing_rate
    slope = float((t(h) - t(-h))[()] / (2.0 * h))
    # truncation: the odd series y = x - x^3/Omega_d^2 + ...: central slope 1 - (h/Omega_d)^2 + ...
    trunc = (h / t.duffing_rate) ** 2
    tol = 2.0 * trunc + 8.0 * _EPS
    return Check(
        id="mems.nonlinear_small_signal_scale_factor",
        reference=_NAYFEH + "; " + _RAPP,
        formula="d/dOmega rapp(Omega_d v(Omega/Omega_d)) at 0 = 1 [-]",
        expected=1.0,
        simulated=slope,
        tolerance=tol,
        derivation=(
            f"central difference at h = 1e-5 Omega_d: truncation (h/Omega_d)^2 = {trunc:.1e} of the "
            "cubic term (x2 for the next ones), plus 8 eps of rounding"
        ),
    )


def _cubic() -> Check:
    sense = duffing_check_sense()
    t = RateTransfer(duffing_rate=sense.critical_rate)
    dk = sense.detuning_stiffness
    g = 2.0 * sense.mass * sense.drive_omega * sense.drive_amplitude  # Coriolis force per rad/s
    a3 = -0.75 * sense.k3 * g**2 / dk**3
    x1 = 0.02 * t.duffing_rate
    x2 = 0.5 * x1

    def ratio(x: float) -> float:
        return float((t(x) - x)[()] / x**3)

    simulated = (4.0 * ratio(x2) - ratio(x1)) / 3.0
    # v = u - u^3 + 3 u^5 - 12 u^7: (y - x)/x^3 = a3 (1 - 3 u^2 + 12 u^4 ...); Richardson removes
    # u^2, leaving 12 u^4 (4 (1/16) - 1)/3 = -3 u1^4 relative; rounding of y - x: eps x / (x^3 |a3|)
    u1 = x1 / t.duffing_rate
    trunc = 3.0 * u1**4
    rnd = 5.0 * _EPS / (x2**2 * abs(a3))
    return Check(
        id="mems.nonlinear_cubic_coefficient",
        reference=_NAYFEH + " (harmonic balance, first-order perturbation)",
        formula="a3 = -(3/4) k3 (2 m w X0)^2 / (m (w_y^2 - w^2))^3 [s^2/rad^2] (harmonic balance, 1st order)",
        expected=a3,
        simulated=simulated,
        tolerance=2.0 * trunc + rnd,
        derivation=(
            f"Richardson extrapolation of (y - x)/x^3 at u = {u1:g}, {u1 / 2:g} of Omega_d: the u^4 "
            f"remainder 3 u^4 = {trunc:.1e} (x2), plus 5 eps of rounding of y - x over x^3 |a3| = {rnd:.1e}"
        ),
    )


def _monotone() -> Check:
    t = _identified()
    top = units.deg_per_s(3600.0)
    step = units.deg_per_s(0.1)
    x = np.linspace(-top, top, int(round(2 * top / step)) + 1)
    y = t(x)
    slopes = np.diff(y) / np.diff(x)
    s, p = t.rail_rate, t.rail_order

    def deriv(w: float) -> float:
        return (1.0 + abs(w / s) ** (2.0 * p)) ** (-1.0 - 1.0 / (2.0 * p))

    expected = deriv(top)
    # the smallest secant lies between y'(top) and y'(top - h) (y' falls with |x|)
    h = float(x[1] - x[0])
    tol = (deriv(top - h) - expected) / expected + 8.0 * _EPS * top / (h * expected)
    return Check(
        id="mems.nonlinear_monotone_3600",
        reference=_RAPP,
        formula="min secant slope over +-3600 deg/s = (1 + |x/Omega_s|^(2p))^(-1-1/(2p)) at 3600 deg/s > 0",
        expected=expected,
        simulated=float(np.min(slopes)),
        tolerance=tol,
        derivation=(
            f"the end secant over h = 0.1 deg/s lies between y'(3600) and y'(3600 - h): "
            f"{(deriv(top - h) - expected) / expected:.1e}, plus 8 eps of rounding of y over h"
        ),
    )


def _no_clip() -> Check:
    from gyrobench.scenarios.papers.p001_mems_scale_factor.config import Config
    from gyrobench.scenarios.papers.p001_mems_scale_factor.device import device_spec, draw_unit

    spec = device_spec(Config())
    drawn = [draw_unit(spec, seed) for seed in range(20)]
    unit = min(drawn, key=mr.rate_authority)
    top = units.deg_per_s(3600.0)
    rates = np.array([top, -top])
    res = mr.slow_flow(unit, np.tile(rates, (20, 1)), fs=200.0, rng=np.random.default_rng(0),
                      noise=False, flicker=False, adc=True)
    t = _identified()
    got = t(res.output[-1])
    linear = mr.low_rate_scale_factor(unit) * rates + mr.zero_rate_output(unit)
    expected = t(linear)
    err = np.abs(got - expected)
    worst = int(np.argmax(err))
    # the ADC rounds to q/2; the transfer's slope at 3600 deg/s (< 1) only shrinks it
    q = unit.resolution
    tol = (0.5 * q + 64.0 * _EPS * top) / abs(float(expected[worst]))
    auth = units.to_deg_per_s(mr.rate_authority(unit))
    return Check(
        id="mems.nonlinear_no_clip_3600",
        reference=(
            "M. Saukoski, System and circuit design for a capacitive MEMS gyroscope, Helsinki Univ. of "
            "Technology doctoral thesis (2008), ch. 2-3 (the feedback force range bounds the input " "range); " +
            _RAPP
        ),
        formula="Omega_out(+-3600 deg/s) = rapp(SF Omega + ZRO) (no rebalance clamp, no ADC clip) [rad/s]",
        expected=float(expected[worst]),
        simulated=float(got[worst]),
        tolerance=tol,
        derivation=(
            f"the unit of the 20 drawn with the lowest rebalance authority ({auth:.0f} deg/s), noise-free: "
            f"ADC rounding q/2 (q = {units.to_deg_per_s(q):.2g} deg/s) plus 64 eps of the slow flow's "
            "arithmetic, relative to the output at 3600 deg/s"
        ),
    )


def checks(rng: np.random.Generator) -> list[Check]:
    """The four nonlinear-mechanism checks (deterministic: ``rng`` is not drawn from)."""
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator; got {type(rng).__name__}")
    return [_small_signal(), _cubic(), _monotone(), _no_clip()]
