"""Checks of the MEMS sense-channel nonlinearity: the stiffening equation and the open-loop read-out chain.

``checks(rng) -> list[Check]`` (the contract of :mod:`gyrobench.scenarios.checks.core`):

* ``mems.sense_stiffening_full_ode`` (second method): the harmonic-balance amplitude of the
  Duffing sense mode (:meth:`gyrobench.sim.mems_nonlinear.DuffingSense.amplitude`) against a
  full RK4 integration of m y'' + c y' + k_y y + k3 y^3 = F cos(w t) to its steady state, the
  fundamental read by projection over whole cycles, at 0.5, 1 and 2 times the critical rate
  (through the bend).
* ``mems.readout_slow_vs_full_bend`` (second method): paper 001's identified open-loop device
  (:mod:`gyrobench.sim.mems_readout`: stiffening of the biased sense electrodes, the
  differential pick-off's 1/(g - y), the charge amplifier's rail) with a one-sigma quadrature:
  the slow flow's noise-free rate channel (harmonic balance and the describing function on the
  envelope, :func:`gyrobench.sim.mems_slow_flow.slow_flow`'s path) against the full sense
  equation integrated with the carrier, m y'' + c y' + k_y y - (F_e(y) - k_e y) = Re{F_ext
  e^{jwt}}, the pick-off and rail applied to y(t) sample by sample and synchronously
  demodulated, at 1800, 2880 and 3600 deg/s (below, in and past the bend).
* ``mems.readout_pickoff_small_amplitude`` (closed form): the pick-off's describing gain at
  a = 0.05 g against the series of its fundamental, 2 eps0 A_s y/(g^2 - y^2) = (2 eps0 A_s/g^2)
  (y + y^3/g^2 + y^5/g^4 + ...), whose cos-coefficients give 1 + (3/4) u^2 + (5/8) u^4 + (35/64)
  u^6, u = a/g (no rail: the amplitude below the clip).
* ``mems.nonlinear_cubic_coefficient`` (consistency): the first-order perturbation of the same
  harmonic-balance equation the model solves, a3 = -(3/4) k3 (2 m w X0)^2 / dk^3: a regression
  guard of the Duffing transfer's small-rate end, not validation.

Each full integration starts from the LINEAR steady state (y = Re{R F e^{jwt}}, not the harmonic
balance's answer) and runs long enough for the nonlinear correction's transient to decay;
the check units' sense Q is lowered (stated per check) so that takes tens, not hundreds, of
cycles. Tolerances are derived per check (truncations stated); about 1.5 s in all.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from gyrobench.base import units
from gyrobench.scenarios.checks.core import CLOSED_FORM, CONSISTENCY, SECOND_METHOD, Check
from gyrobench.sim import mems_population
from gyrobench.sim import mems_resonator as mr
from gyrobench.sim.mems_nonlinear import DuffingSense, RateTransfer

__all__ = ["checks", "duffing_check_sense", "integrate_sense", "readout_check_unit"]

_EPS = float(np.finfo(float).eps)
#: cubic stiffness of the check's Duffing sense beam [N/m^3]: puts its critical rate near
#: 3000 deg/s for the default resonator (a check value, not a default of any device)
_K3 = 1.6e9
#: the check units' sense quality factor (the transient of the nonlinear correction decays
#: in 2 Q/w_y: about 3 drive cycles)
_Q_CHECK = 10.0
#: RK4 steps per drive cycle, and Hermite sub-samples per step for the demodulation
_STEPS, _SUB = 96, 16
_NAYFEH = "A. H. Nayfeh, D. T. Mook, Nonlinear Oscillations (Wiley, 1979), ch. 4"
_RK4 = ("second method: fixed-step RK4 of the full sense equation with the carrier, from the linear "
        "steady state, fundamental by projection over whole cycles (E. Hairer, S. P. Norsett, G. Wanner, "
        "Solving Ordinary Differential Equations I, 2nd ed. (Springer, 1993), sec. II.1)")


def duffing_check_sense(sense_q: float | None = None) -> DuffingSense:
    """A Duffing sense mode built from the default resonator with a stiff cubic term.

    A Duffing sense mode with the default resonator's m, w, w_y, X0, k3 = 1.6e9 N/m^3 and Q_y
    ``sense_q`` (default: the resonator's).

    Parameters
    ----------
    sense_q : float or None
        Q_y [-] (None: the resonator's).

    Returns
    -------
    DuffingSense
        m, w, w_y and X0 of the default resonator, k3 = 1.6e9 N/m^3.
    """
    op = mr.operating_point(mr.MemsResonator())
    return DuffingSense(
        mass=op.m, drive_omega=op.wx, sense_omega=op.wy,
        sense_q=mr.MemsResonator().sense_q if sense_q is None else sense_q,
        k3=_K3, drive_amplitude=op.x0,
    )


def integrate_sense(
    *, m: float, c: float, k: float, w: float, force: np.ndarray, restoring, linear: np.ndarray,
    cycles: int, demod_cycles: int, readout=None,
) -> np.ndarray:
    """The fundamental (complex, e^{jwt} convention) of ``readout(y)`` (default y) at steady state.

    m y'' + c y' + k y + restoring(y) = Re{F e^{jwt}}, vectorised over the forces ``force``
    (complex, one per case), from y = Re{B e^{jwt}} with B = ``linear`` (one per case), fixed-step
    RK4 with :data:`_STEPS` steps per cycle for ``cycles`` cycles; the last ``demod_cycles``
    are projected, readout(y) sampled at :data:`_SUB` points per step on the cubic Hermite
    interpolant of (y, y') (O(h^4)), trapezoid rule over whole cycles.

    Parameters
    ----------
    m : float
        Mass [kg].
    c : float
        Damping [kg/s].
    k : float
        Linear stiffness [N/m].
    w : float
        Drive frequency [rad/s].
    force : ndarray of complex
        Force phasors F, one per case [N].
    restoring : callable
        ``restoring(y)``, the nonlinear restoring force [N].
    linear : ndarray of complex
        Starting phasors B, one per case [m].
    cycles : int
        Drive cycles integrated.
    demod_cycles : int
        The last cycles demodulated.
    readout : callable or None
        ``readout(y)`` demodulated (None: y).

    Returns
    -------
    ndarray of complex
        The fundamental of each case.
    """
    h = 2.0 * math.pi / w / _STEPS
    y = linear.real.astype(float).copy()
    v = -w * linear.imag.astype(float)  # d/dt Re{B e^{jwt}} at t = 0: Re{j w B}
    fr, fi = force.real, force.imag

    def acc(t: float, yy: np.ndarray, vv: np.ndarray) -> np.ndarray:
        f = fr * math.cos(w * t) - fi * math.sin(w * t)
        return (f - c * vv - k * yy - restoring(yy)) / m

    read = (lambda x: x) if readout is None else readout
    n_total = cycles * _STEPS
    n_demod = demod_cycles * _STEPS
    s = (np.arange(_SUB) / _SUB)[:, None]
    h00, h10 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s
    h01, h11 = -2 * s**3 + 3 * s**2, s**3 - s**2
    acc_sum = np.zeros(linear.shape, dtype=complex)
    for i in range(n_total):
        t = i * h
        k1y, k1v = v, acc(t, y, v)
        k2y, k2v = v + 0.5 * h * k1v, acc(t + 0.5 * h, y + 0.5 * h * k1y, v + 0.5 * h * k1v)
        k3y, k3v = v + 0.5 * h * k2v, acc(t + 0.5 * h, y + 0.5 * h * k2y, v + 0.5 * h * k2v)
        k4y, k4v = v + h * k3v, acc(t + h, y + h * k3y, v + h * k3v)
        y1 = y + h / 6.0 * (k1y + 2 * k2y + 2 * k3y + k4y)
        v1 = v + h / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v)
        if i >= n_total - n_demod:
            ys = h00 * y + h10 * h * v + h01 * y1 + h11 * h * v1  # (_SUB, cases)
            ts = t + s[:, 0] * h
            acc_sum += np.sum(read(ys) * np.exp(-1j * w * ts)[:, None], axis=0)
        y, v = y1, v1
    return 2.0 * acc_sum / (n_demod * _SUB)


def _third_harmonic_error(k3: float, a: float, m: float, w: float, ky: float, dk_slope: float) -> float:
    """|dA/A| of first harmonic balance from the neglected third harmonic (module docstring).

    A3 ~ -(k3 A^3/4)/(k_y - 9 m w^2); its feedback (3/4) k3 A^2 A3 on the fundamental's equation,
    over the slope d/dA of that equation (dk + (9/4) k3 A^2): (3/16) (k3 A^2)^2 / (|k_y - 9 m w^2| dk').
    """
    return 3.0 / 16.0 * (k3 * a * a) ** 2 / (abs(ky - 9.0 * m * w * w) * dk_slope)


def _stiffening_ode() -> Check:
    sense = duffing_check_sense(_Q_CHECK)
    m, w, wy = sense.mass, sense.drive_omega, sense.sense_omega
    c, ky = sense.damping, m * wy * wy
    rates = np.array([0.5, 1.0, 2.0]) * sense.critical_rate
    force = -1j * sense.coriolis_force(rates)  # Re{-j F e^{jwt}} = F sin(wt): the Coriolis force's phase
    r_lin = 1.0 / (ky - m * w * w + 1j * c * w)
    tau_cycles = 2.0 * m / c * w / (2.0 * math.pi)
    cycles = int(math.ceil(16.0 * tau_cycles)) + 4
    got = integrate_sense(m=m, c=c, k=ky, w=w, force=force, restoring=lambda y: sense.k3 * y**3,
                          linear=r_lin * force, cycles=cycles, demod_cycles=4)
    full = np.abs(got)
    hb = np.abs(sense.amplitude(rates))
    err = np.abs(hb - full) / full
    worst = int(np.argmax(err))
    a = float(full[worst])
    dk = sense.detuning_stiffness
    third = _third_harmonic_error(sense.k3, a, m, w, ky, dk + 2.25 * sense.k3 * a * a)
    settle = math.exp(-(cycles - 4) / tau_cycles)  # the start's relative error is below 1
    rk4 = (2.0 * math.pi / _STEPS) ** 4
    tol = 3.0 * third + settle + 2.0 * rk4 + 1e-12
    return Check(
        id="mems.sense_stiffening_full_ode",
        kind=SECOND_METHOD,
        reference=_RK4 + "; harmonic balance: " + _NAYFEH,
        formula=(
            "first-harmonic amplitude of m y'' + c y' + k_y y + k3 y^3 = F sin(wt), F = 2 m w X0 Omega: harmonic "
            "balance A^2[(dk + 3/4 k3 A^2)^2 + (c w)^2] = F^2 (model) vs full RK4 [m]; Omega = 0.5, 1, 2 x "
            f"Omega_d = {units.to_deg_per_s(sense.critical_rate):.0f} deg/s, k3 = {_K3:g} N/m^3, Q_y = {_Q_CHECK:g}"
        ),
        expected=a,
        simulated=float(hb[worst]),
        tolerance=tol,
        derivation=(
            f"worst of the three rates ({rates[worst] / sense.critical_rate:g} Omega_d): the neglected third "
            f"harmonic (3/16)(k3 A^2)^2/(|k_y - 9 m w^2| dk') = {third:.2g} (x3), the transient from the "
            f"linear start e^(-t/tau) = {settle:.1g} after {cycles - 4} cycles (tau = {tau_cycles:.2f} cycles), "
            f"RK4's steady-state amplitude error <= (w h)^4 = {rk4:.1g} (x2; {_STEPS} steps per cycle)"
        ),
    )


def readout_check_unit() -> mr.MemsResonator:
    """Paper 001's identified open-loop nominal unit with a one-sigma quadrature and Q_y = 10.

    The lower Q shrinks the receptance |R|; the feedback capacitor is scaled by the same ratio
    |R(Q_y = 10)| / |R(Q_y)| so that the rail is reached at about the same rates as on the
    identified unit (the check runs through the bend, not below it).

    Returns
    -------
    MemsResonator
        The unit.
    """
    from gyrobench.scenarios.papers.p001_mems_scale_factor.identify import IDENTIFIED, nominal_open_loop_unit
    from gyrobench.sim.mems_readout import SenseChain

    nominal = mr.MemsResonator()
    base = replace(nominal, sense_q=_Q_CHECK, quadrature_coupling=mems_population.MemsResonatorSpec().quadrature_spread)
    ratio = abs(mr.operating_point(base).receptance) / abs(mr.operating_point(nominal).receptance)
    chain = replace(SenseChain(), feedback_capacitance=IDENTIFIED.feedback_capacitance_f * ratio)
    return nominal_open_loop_unit(chain, base)


def _readout_bend() -> Check:
    unit = readout_check_unit()
    chain = unit.sense_chain
    assert chain is not None
    op = mr.operating_point(unit)
    dps = np.array([1800.0, 2880.0, 3600.0])
    rates = units.deg_per_s(dps)
    zeros = np.zeros(rates.size)
    slow = mr.static_rate_output(unit, rates)
    force = mr.external_force(op, rates, zeros)
    r = op.receptance
    ke = chain.electrostatic_stiffness
    tau_cycles = 2.0 * op.m / op.cy * op.wx / (2.0 * math.pi)
    cycles = int(math.ceil(16.0 * tau_cycles)) + 4
    v1 = integrate_sense(
        m=op.m, c=op.cy, k=op.ky, w=op.wx, force=force,
        restoring=lambda y: chain.k3 * y**3 - (chain.electrode_force(y) - ke * y),
        linear=r * force, cycles=cycles, demod_cycles=4, readout=chain.frontend_output,
    )
    envelope = v1 / chain.small_signal_gain
    full = mr._output_map(unit, op, (mr._readout_weight(op) * envelope).real)
    err = np.abs(slow - full) / np.abs(full)
    worst = int(np.argmax(err))
    kink = (math.pi / (_STEPS * _SUB)) ** 2
    settle = math.exp(-(cycles - 4) / tau_cycles)
    b = np.abs(chain.stiffened_envelope(r * force, r))
    # the third harmonic's feedback, as for the Duffing beam with k3 a^2 -> (4/3) |dk(a)|, over |1/R|
    k_nl = float(np.max(np.abs(chain.stiffness_change(b)))) * 4.0 / 3.0
    third = 3.0 / 16.0 * k_nl**2 / (abs(op.ky - 9.0 * op.m * op.wx**2) * abs(1.0 / r))
    rk4 = (2.0 * math.pi / _STEPS) ** 4
    tol = 10.0 * kink + settle + 3.0 * third + 2.0 * rk4 + 1e-9
    clip = b / chain.clip_displacement  # > 1: the front end at its rail for part of each cycle
    return Check(
        id="mems.readout_slow_vs_full_bend",
        kind=SECOND_METHOD,
        reference=(_RK4 + "; pick-off and electrode force: V. Kaajakari, Practical MEMS (2009), ch. 6; "
                   "describing function: A. Gelb, W. E. Vander Velde, Multiple-Input Describing Functions "
                   "(McGraw-Hill, 1968), ch. 2"),
        formula=(
            "open-loop rate channel of paper 001's identified unit (quadrature 1 sigma, Q_y 10): slow flow (harmonic "
            "balance + describing function of clip(V_c dC(y)/C_f)) vs the full sense equation with the carrier, "
            "the pick-off and rail on y(t), synchronous demodulation; 1800, 2880, 3600 deg/s [rad/s]"
        ),
        expected=float(full[worst]),
        simulated=float(slow[worst]),
        tolerance=tol,
        derivation=(
            f"worst at {dps[worst]:g} deg/s (|B|/y_c = {', '.join(f'{x:.2f}' for x in clip)}: the rail is "
            f"reached at the upper two rates); the rail's kinks on the trapezoid demodulation ({_STEPS} x {_SUB} "
            f"samples per cycle, Hermite interpolant O(h^4)): (pi/M)^2 x 10 = {10 * kink:.1g}; the transient from "
            f"the linear start e^(-t/tau) = {settle:.1g}; the neglected harmonics of the stiffening, "
            f"(3/16)((4/3)|dk|)^2/(|k_y - 9 m w^2| |1/R|) x 3 = {3 * third:.1g}; RK4 (w h)^4 x 2 = "
            f"{2 * rk4:.1g}; 1e-9 rounding"
        ),
    )


def _pickoff_small() -> Check:
    from gyrobench.sim.mems_readout import SenseChain

    chain = SenseChain(feedback_capacitance=1e-12)  # a large C_f: the rail is far (no clipping)
    u = 0.05
    a = u * chain.gap
    assert a < chain.clip_displacement
    series = 1.0 + 0.75 * u**2 + 0.625 * u**4
    nxt = 35.0 / 64.0 * u**6
    return Check(
        id="mems.readout_pickoff_small_amplitude",
        kind=CLOSED_FORM,
        reference="V. Kaajakari, Practical MEMS (2009), ch. 6 (differential parallel-plate capacitance); series of "
        "y/(g^2 - y^2) with the cos^3, cos^5 Fourier coefficients 3/4, 5/8 (I. S. Gradshteyn, I. M. Ryzhik, Table "
        "of Integrals, 7th ed. (2007), 1.320)",
        formula="describing gain of dC(y) = 2 eps0 A_s y/(g^2 - y^2) at a = 0.05 g: 1 + (3/4) u^2 + (5/8) u^4 [-]",
        expected=series,
        simulated=float(chain.describing_gain(a)),
        tolerance=2.0 * nxt / series + 64.0 * _EPS,
        derivation=f"the next term (35/64) u^6 = {nxt:.1g} (x2), plus 64 eps of the 32-node quadrature's rounding",
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
        kind=CONSISTENCY,
        reference=_NAYFEH + " (harmonic balance, first-order perturbation of the equation the model solves)",
        formula="a3 = -(3/4) k3 (2 m w X0)^2 / (m (w_y^2 - w^2))^3 [s^2/rad^2] (harmonic balance, 1st order)",
        expected=a3,
        simulated=simulated,
        tolerance=2.0 * trunc + rnd,
        derivation=(
            f"Richardson extrapolation of (y - x)/x^3 at u = {u1:g}, {u1 / 2:g} of Omega_d: the u^4 "
            f"remainder 3 u^4 = {trunc:.1e} (x2), plus 5 eps of rounding of y - x over x^3 |a3| = {rnd:.1e}"
        ),
    )


def checks(rng: np.random.Generator) -> list[Check]:
    """The four checks (deterministic: ``rng`` is not drawn from).

    Parameters
    ----------
    rng : numpy.random.Generator
        Unused (the module's stream, by the check modules' contract).

    Returns
    -------
    list of Check
        The checks.
    """
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator; got {type(rng).__name__}")
    return [_stiffening_ode(), _readout_bend(), _pickoff_small(), _cubic()]
