"""Closed-form checks of the mount-coning rectification (:mod:`gyrobench.sim.mount_coning`).

- **Rectified bias against the classical coning drift.** Two angular oscillations
  theta_x = a_x cos(w t), theta_y = a_y cos(w t - phi) about axes perpendicular to the sense
  axis turn the body about it at the mean rate

      Omega_z = (1/2) w a_x a_y sin(phi)                                       [rad/s]

  (Goodman & Robinson, J. Appl. Mech. 25, 210 (1958); Savage, J. Guid. Control Dyn. 21(1),
  19 (1998), eq. 49). Each mount mode is a base-excited single-degree-of-freedom oscillator
  whose amplitude and lag at frequency ratio r = f/f_k and damping zeta = 1/(2 Q) are the
  textbook ones (Thomson & Dahleh, Theory of Vibration with Applications, 5th ed., 1998,
  eqs. 3.1-3 and 3.1-4):

      a_k = c_k A / sqrt((1 - r^2)^2 + (2 zeta r)^2),   tan(psi_k) = 2 zeta r / (1 - r^2),

  so phi = psi_y - psi_x. The model's *time-domain* rate (:meth:`MountConing.rate`: both modes'
  responses and derivatives on the record's Fourier transform, then the commutation product)
  is averaged over whole cycles of a sampled sine and compared with that value at the lower
  mode, between the modes, at the upper mode and far below and above both (where the rectified
  bias is orders of magnitude smaller, yet must still match).
- **Q from the half-power width.** The half-power frequencies of one mode's response
  |theta/a|^2 are found numerically on the model (root finding, no formula of the model
  retyped); for the displacement response of a damped oscillator they satisfy exactly
  (f_2^2 - f_1^2) / f_0^2 = 4 zeta sqrt(1 - zeta^2) (Thomson & Dahleh, sec. 3.2), which gives
  Q back; the usual f_0 / (f_2 - f_1) is reported in the formula text beside it (it is biased
  by O(1/Q^2)).

Every check is deterministic (no noise): its tolerance is the rounding of the computation.
"""

from __future__ import annotations

import math

import numpy as np

from gyrobench.scenarios.checks.core import Check

__all__ = ["checks"]

#: the mount the checks use: paper 000's identified band (400 and 460 Hz, Q 10) at unit-order
#: compliance; the checks are relative so the compliance only scales every value
_F_X, _F_Y, _Q, _C = 400.0, 460.0, 10.0, 1e-6
#: table amplitude [m/s^2] (2 g)
_A = 2.0 * 9.80665
#: sampling rate [Hz] and record length [s] of the time-domain check (whole cycles of every test frequency)
_FS, _T = 12800.0, 1.0


def _classical(f: float, a: float) -> float:
    """(1/2) w a_x a_y sin(psi_y - psi_x) from the textbook amplitude and lag of each mode [rad/s]."""

    def amp_lag(f0: float) -> tuple[float, float]:
        r, z = f / f0, 1.0 / (2.0 * _Q)
        return _C * a / math.hypot(1.0 - r * r, 2.0 * z * r), math.atan2(2.0 * z * r, 1.0 - r * r)

    ax, px = amp_lag(_F_X)
    ay, py = amp_lag(_F_Y)
    return 0.5 * (2.0 * math.pi * f) * ax * ay * math.sin(py - px)


def _rectified(f: float) -> Check:
    from gyrobench.sim.mount_coning import MountConing, RockingMode

    mount = MountConing(
        x=RockingMode(frequency=_F_X, quality=_Q, compliance=_C),
        y=RockingMode(frequency=_F_Y, quality=_Q, compliance=_C),
    )
    n = int(round(_FS * _T))
    t = np.arange(n) / _FS
    rate = mount.rate(_A * np.cos(2.0 * math.pi * f * t), _FS)
    expected = _classical(f, _A)
    # rounding: the FFT's relative error grows as eps log2(n) on the largest components; the
    # mean of a product of two such signals carries it relative to |a_x a_y w|, which exceeds
    # |expected| by 1/|sin(phi)| (large far from resonance, where phi -> 0 or pi)
    ax = abs(complex(mount.x.response(f))) * _A
    ay = abs(complex(mount.y.response(f))) * _A
    scale = 0.5 * 2.0 * math.pi * f * ax * ay
    tol = 1e3 * np.finfo(float).eps * math.log2(n) * scale / abs(expected)
    return Check(
        id=f"mount_coning.rectified_bias_{f:g}hz",
        reference=(
            "R. E. Goodman, A. R. Robinson, J. Appl. Mech. 25, 210 (1958); P. G. Savage, J. Guid. "
            "Control Dyn. 21(1) 19 (1998), eq. 49; W. T. Thomson, M. D. Dahleh, Theory of Vibration "
            "with Applications, 5th ed. (1998), eqs. 3.1-3, 3.1-4"
        ),
        formula=f"mean Omega_z = (1/2) w a_x a_y sin(psi_y - psi_x), a_k, psi_k of a base-excited "
        f"oscillator (modes {_F_X:g}/{_F_Y:g} Hz, Q {_Q:g}); time-domain rate of a {f:g} Hz, 2 g sine, "
        f"{_T:g} s at {_FS:g} Hz [rad/s]",
        expected=expected,
        simulated=float(np.mean(rate)),
        tolerance=float(tol),
        derivation=f"deterministic: FFT rounding eps log2(n) (n = {n}) on the product's scale "
        f"(1/2) w a_x a_y = {scale:.3g} rad/s, x 1000 margin, relative to |expected|",
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
    """The rectified bias at and off resonance and Q from the half-power width (deterministic;
    ``rng`` is unused, the collector's contract)."""
    return [*(_rectified(f) for f in (50.0, _F_X, 430.0, _F_Y, 2000.0)), _q_half_power()]
