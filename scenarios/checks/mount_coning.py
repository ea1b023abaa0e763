"""Checks of the mount-coning rectification (:mod:`gyrobench.sim.mount_coning`): exact kinematics and a closed form.

- **Rectified bias against the exact rotation kinematics.** Each mount mode is a base-excited
  single-degree-of-freedom oscillator whose amplitude and lag at frequency ratio r = f/f_k and
  damping zeta = 1/(2 Q) are the textbook ones (Thomson & Dahleh, Theory of Vibration with
  Applications, 5th ed., 1998, eqs. 3.1-3 and 3.1-4):

      a_k = c_k A / sqrt((1 - r^2)^2 + (2 zeta r)^2),   tan(psi_k) = 2 zeta r / (1 - r^2).

  The attitude C(t) = exp([theta(t) x]), theta = (a_x cos(w t - psi_x), a_y cos(w t - psi_y), 0),
  is built as rotation matrices (:class:`scipy.spatial.transform.Rotation`) on N points of one
  period; the body-frame rotation over each step is C_k^T C_{k+1}, and the sum of their
  rotation vectors' z components over the period, divided by the period, is the exact mean
  body rate about the sense axis (no small-angle expansion, no commutation formula). The
  model's *time-domain* rate (:meth:`MountConing.rate`, body frame: the modes' responses and
  derivatives on the record's Fourier transform, then the commutation product) is averaged
  over whole cycles of a sampled sine and compared with it at the lower mode, between the
  modes, at the upper mode and far below and above both (where the rectified bias is orders of
  magnitude smaller, yet must still match). A model in the space frame fails by a relative
  error of 2. (The classical value (1/2) w a_x a_y sin(psi_y - psi_x) of Goodman & Robinson,
  J. Appl. Mech. 25, 210 (1958), is the space-frame limit, reported in the formula text.)
- **Q from the half-power width.** The half-power frequencies of one mode's response
  |theta/a|^2 are found numerically on the model (root finding, no formula of the model
  retyped); for the displacement response of a damped oscillator they satisfy exactly
  (f_2^2 - f_1^2) / f_0^2 = 4 zeta sqrt(1 - zeta^2) (Thomson & Dahleh, sec. 3.2), which gives
  Q back; the usual f_0 / (f_2 - f_1) is reported in the formula text beside it (it is biased
  by O(1/Q^2)).

Every check is deterministic (no noise): its tolerance is derived from the truncations (the
step of the kinematics, the neglected fourth order of the commutation formula) and rounding.
"""

from __future__ import annotations

import math

import numpy as np

from gyrobench.scenarios.checks.core import CLOSED_FORM, SECOND_METHOD, Check

__all__ = ["checks", "exact_body_rate"]

#: the mount the checks use: paper 000's identified band (400 and 460 Hz, Q 10) at unit-order
#: compliance; the checks are relative so the compliance only scales every value
_F_X, _F_Y, _Q, _C = 400.0, 460.0, 10.0, 1e-6
#: table amplitude [m/s^2] (2 g)
_A = 2.0 * 9.80665
#: sampling rate [Hz] and record length [s] of the time-domain check (whole cycles of every test frequency)
_FS, _T = 12800.0, 1.0


#: points per period of the exact kinematics
_N_KIN = 20000


def _amp_lag(f: float, f0: float, a: float) -> tuple[float, float]:
    """Textbook amplitude [rad] and lag [rad] of a base-excited mode (Thomson & Dahleh eqs. 3.1-3, 3.1-4)."""
    r, z = f / f0, 1.0 / (2.0 * _Q)
    return _C * a / math.hypot(1.0 - r * r, 2.0 * z * r), math.atan2(2.0 * z * r, 1.0 - r * r)


def exact_body_rate(f: float, a: float, n: int = _N_KIN) -> float:
    """Mean body-frame rate about z [rad/s] of the coning attitude, from rotation matrices.

    C_k = exp([theta(t_k) x]) on ``n`` steps of one period; the mean is
    sum_k rotvec(C_k^T C_{k+1})_z / T. Exact kinematics but for the step: the rotation vector
    of each step is its body-rate integral to O(h^3), so the mean carries (w h)^2/6 relative.

    Parameters
    ----------
    f : float
        Coning frequency [Hz].
    a : float
        Half-angle amplitude [rad].
    n : int
        Steps per period.

    Returns
    -------
    float
        The mean body rate about z [rad/s].
    """
    from scipy.spatial.transform import Rotation

    ax, px = _amp_lag(f, _F_X, a)
    ay, py = _amp_lag(f, _F_Y, a)
    w = 2.0 * math.pi * f
    t = np.arange(n + 1) / (n * f)
    rot = Rotation.from_rotvec(np.column_stack([ax * np.cos(w * t - px), ay * np.cos(w * t - py), np.zeros_like(t)]))
    step = (rot[:-1].inv() * rot[1:]).as_rotvec()
    return float(np.sum(step[:, 2]) * f)


def _rectified(f: float) -> Check:
    from gyrobench.sim.mount_coning import MountConing, RockingMode

    mount = MountConing(
        x=RockingMode(frequency=_F_X, quality=_Q, compliance=_C),
        y=RockingMode(frequency=_F_Y, quality=_Q, compliance=_C),
    )
    n = int(round(_FS * _T))
    t = np.arange(n) / _FS
    rate = mount.rate(_A * np.cos(2.0 * math.pi * f * t), _FS)
    expected = exact_body_rate(f, _A)
    ax, px = _amp_lag(f, _F_X, _A)
    ay, py = _amp_lag(f, _F_Y, _A)
    classical = 0.5 * (2.0 * math.pi * f) * ax * ay * math.sin(py - px)
    # truncations relative to the mean: the kinematics' step (w h)^2/6, h = 1/(n f); the
    # commutation formula's neglected order, theta_max^2 (both vanish with sin(psi_y - psi_x), as
    # the rate does: in-phase modes rotate about a fixed axis, zero about z at every order).
    # rounding: the FFT's relative error eps log2(n) on the largest components, carried by the
    # mean of a product relative to (1/2) w a_x a_y, which exceeds |expected| by 1/|sin(phi)|.
    step = (2.0 * math.pi / _N_KIN) ** 2 / 6.0
    order = max(ax, ay) ** 2
    scale = 0.5 * 2.0 * math.pi * f * ax * ay
    rnd = 1e3 * np.finfo(float).eps * math.log2(n) * scale / abs(expected)
    tol = 2.0 * (step + order) + rnd
    return Check(
        id=f"mount_coning.rectified_bias_{f:g}hz",
        kind=SECOND_METHOD,
        reference=(
            "second method: exact rotation kinematics, products of rotation matrices C_k^T C_{k+1} of "
            "C = exp([theta x]) (M. D. Shuster, 'A survey of attitude representations', J. Astronaut. Sci. "
            "41(4) 439 (1993)); mode amplitude and lag: W. T. Thomson, M. D. Dahleh, Theory of Vibration "
            "with Applications, 5th ed. (1998), eqs. 3.1-3, 3.1-4"
        ),
        formula=f"mean body-frame Omega_z of C(t) = exp([theta x]), theta = (a_x cos(wt - psi_x), a_y cos(wt - "
        f"psi_y), 0) (modes {_F_X:g}/{_F_Y:g} Hz, Q {_Q:g}), {_N_KIN} steps per period; model: time-domain "
        f"rate of a {f:g} Hz, 2 g sine, {_T:g} s at {_FS:g} Hz [rad/s]; space-frame classical value "
        f"(1/2) w a_x a_y sin(psi_y - psi_x) = {classical:.6g}",
        expected=expected,
        simulated=float(np.mean(rate)),
        tolerance=float(tol),
        derivation=f"deterministic: kinematics step (2 pi/{_N_KIN})^2/6 = {step:.2g} and the fourth order "
        f"theta_max^2 = {order:.2g}, each x2; FFT rounding eps log2(n) (n = {n}) on the product's scale "
        f"{scale:.3g} rad/s, x 1000 margin, relative to |expected|: {rnd:.2g}",
    )


def _q_half_power() -> Check:
    from scipy.optimize import brentq, minimize_scalar

    from gyrobench.sim.mount_coning import RockingMode

    mode = RockingMode(frequency=_F_X, quality=_Q, compliance=_C)

    def p(f: float) -> float:
        return float(abs(complex(mode.response(f))) ** 2)

    peak = minimize_scalar(lambda f: -p(f), bounds=(0.5 * _F_X, 1.5 * _F_X), method="bounded",
                           options={"xatol": 1e-10})
    f_pk, p_pk = float(peak.x), p(float(peak.x))
    f1 = brentq(lambda f: p(f) - p_pk / 2, 0.5 * _F_X, f_pk, xtol=1e-12, rtol=1e-15)
    f2 = brentq(lambda f: p(f) - p_pk / 2, f_pk, 1.5 * _F_X, xtol=1e-12, rtol=1e-15)
    # (f2^2 - f1^2)/f0^2 = 4 z sqrt(1 - z^2) =: w, i.e. 16 z^4 - 16 z^2 + w^2 = 0: z^2 = (1 - sqrt(1 - w^2/4)) / 2
    w = (f2 * f2 - f1 * f1) / _F_X**2
    zeta = math.sqrt((1.0 - math.sqrt(1.0 - w * w / 4.0)) / 2.0)
    # the peak's location is found to ~sqrt(eps) relative (flat maximum), its value to eps;
    # the half-power roots to 1e-12 Hz: both far inside 1e-8
    return Check(
        id="mount_coning.q_half_power_width",
        kind=CLOSED_FORM,
        reference=(
            "W. T. Thomson, M. D. Dahleh, Theory of Vibration with Applications, 5th ed. (1998), sec. "
            "3.2 (half-power points)"
        ),
        formula=f"Q = 1/(2 zeta), (f2^2 - f1^2)/f0^2 = 4 zeta sqrt(1 - zeta^2) at the half-power points of "
        f"|theta/a|^2 (mode {_F_X:g} Hz; f0/(f2 - f1) = {_F_X / (f2 - f1):.4f}, O(1/Q^2) biased)",
        expected=_Q,
        simulated=1.0 / (2.0 * zeta),
        tolerance=1e-8,
        derivation="deterministic: peak value to machine precision (the bounded search's error in f "
        "enters the peak's value to second order), roots to 1e-12 Hz; 1e-8 relative covers both",
    )


def checks(rng: np.random.Generator) -> list[Check]:
    """Check the rectified bias at and off resonance and Q from the half-power width.

    Deterministic: ``rng`` is unused (the collector's contract).

    Parameters
    ----------
    rng : numpy.random.Generator
        The module's stream (the collector's contract; a deterministic module does not draw from it).

    Returns
    -------
    list of Check
        The module's checks.
    """
    return [*(_rectified(f) for f in (50.0, _F_X, 430.0, _F_Y, 2000.0)), _q_half_power()]
