"""Checks of the IMU's ideal increments (:mod:`gyrobench.sim.trajectory`): closed forms and a second method.

- **Coning increments.** For classical coning, the rotation vector a(t) = beta [cos w t, sin w t, 0]
  of C_nb(t), the body rate has the closed form (P. G. Savage, Strapdown Analytics, 2000,
  sec. 7.1.1.1)

      omega(t) = w sin(beta) [-sin w t, cos w t, 0] - w (1 - cos beta) [0, 0, 1],

  whose integral over each sample interval [t0, t1] is sin(beta) [cos w t1 - cos w t0,
  sin w t1 - sin w t0, 0] - w (1 - cos beta) (t1 - t0) z. The model's increments (8-node
  Gauss-Legendre on each interval) are compared with it, component by component (largest
  error), and through the coning drift (the z increments' sum, -w (1 - cos beta) T).
- **Attitude from the rate, a second method.** The closed-form rate, integrated as the
  direction-cosine kinematics dC/dt = C [omega x] by an adaptive Runge-Kutta solver
  (scipy.integrate.solve_ivp, DOP853), reaches the attitude exp([a(t) x]) the motion defines.
- **The two-sample coning residual.** The two-sample rotation vector phi = d1 + d2 + (2/3) d1 x d2
  (Miller 1983) leaves, per 2T interval on classical coning, the residual
  w beta^2 h (w h)^4 / 960 about the coning axis (h = 2T; J. E. Bortz, IEEE Trans. AES 7(1), 1971,
  for the exact rotation vector; M. B. Ignagni, J. Guid. Control Dyn. 13(2) 363 (1990), table 1),
  measured here against the exact rotation vector between the interval's edge attitudes.
- **Rocking gravity (Bessel).** A block rocking about x, angle A sin(w t), senses gravity rotating in
  its y-z plane; over one whole period the velocity increment is [0, 0, -g T J0(A)]
  (Abramowitz & Stegun 9.1.18: J0(A) = (1/pi) int_0^pi cos(A sin t) dt).

Every check is deterministic: its tolerance is derived from the quadrature's order, the solver's
tolerance or rounding (stated per check).
"""

from __future__ import annotations

import math

import numpy as np

from gyrobench.scenarios.checks.core import CLOSED_FORM, SECOND_METHOD, Check, Part, run_parts

__all__ = ["checks", "parts"]

_EPS = float(np.finfo(float).eps)
#: the coning checks' motion: half angle [rad], frequency [Hz], length [s], sample rate [Hz]
_BETA, _F, _T, _FS = 0.01, 10.0, 1.0, 200.0
_SAVAGE = "P. G. Savage, Strapdown Analytics (Strapdown Associates, 2000), sec. 7.1.1.1 (classical coning)"


def _no_earth():
    from gyrobench.sim.earth import Site

    return Site(earth_rotation=False)


def _coning_increments() -> list[Check]:
    from gyrobench.sim.trajectory import ConingMotion, increments

    inc = increments(ConingMotion(half_angle=_BETA, frequency=_F, duration=_T), _FS, site=_no_earth())
    w, n = 2.0 * math.pi * _F, len(inc.dtheta)
    t0 = np.arange(n) / _FS
    t1 = t0 + 1.0 / _FS
    want = np.stack(
        [math.sin(_BETA) * (np.cos(w * t1) - np.cos(w * t0)), math.sin(_BETA) * (np.sin(w * t1) - np.sin(w * t0)),
         np.full(n, -w * (1.0 - math.cos(_BETA)) / _FS)], axis=-1)
    step = math.sin(_BETA) * w / _FS  # the size of one interval's x/y increment [rad]
    drift = -w * (1.0 - math.cos(_BETA)) * _T
    return [
        Check(
            id="trajectory.coning_increments",
            kind=CLOSED_FORM,
            reference=_SAVAGE,
            formula=f"max |dtheta_model - dtheta_closed| over {n} intervals, dtheta_closed = sin(b) [cos w t1 - cos "
            f"w t0, sin w t1 - sin w t0, 0] - w (1 - cos b) T z (b {_BETA:g} rad, {_F:g} Hz, {_FS:g} Hz) [rad], "
            "relative to one interval's sin(b) w T",
            expected=0.0,
            simulated=float(np.max(np.abs(inc.dtheta - want))),
            scale=step,
            tolerance=8.0 * _EPS * w * _T * math.sin(_BETA) / step,
            derivation="rounding: the phases w t (up to w x the record) carry eps w t each, so both sides' sines "
            "and cosines are good to ~eps w t; times sin(b), x8 for the two sides' operations, relative to the "
            "interval's increment (the 8-node quadrature's error, (w T)^16 / 16!, is far below)",
        ),
        Check(
            id="trajectory.coning_drift",
            kind=CLOSED_FORM,
            reference=_SAVAGE,
            formula=f"sum of the z increments over {_T:g} s = -w (1 - cos b) t (b {_BETA:g} rad, {_F:g} Hz) [rad]",
            expected=drift,
            simulated=float(np.sum(inc.dtheta[:, 2])),
            tolerance=8.0 * n * _EPS,
            derivation=f"rounding: {n} summed increments, each good to a few eps of itself (x8)",
        ),
    ]


def _coning_attitude() -> Check:
    from scipy.integrate import solve_ivp

    from gyrobench.sim.trajectory import ConingMotion

    beta, f = 0.3, 2.0
    m = ConingMotion(half_angle=beta, frequency=f, duration=1.0)

    def rhs(t: float, c_flat: np.ndarray) -> np.ndarray:
        c = c_flat.reshape(3, 3)
        _, w, _, _ = m.state(np.array([t]))
        wx = np.array([[0.0, -w[0, 2], w[0, 1]], [w[0, 2], 0.0, -w[0, 0]], [-w[0, 1], w[0, 0], 0.0]])
        return (c @ wx).ravel()

    c0 = m.state(np.array([0.0]))[0][0]
    times = [0.25, 0.5, 1.0]
    sol = solve_ivp(rhs, (0.0, 1.0), c0.ravel(), method="DOP853", rtol=1e-12, atol=1e-13, t_eval=times)
    err = max(float(np.max(np.abs(sol.y[:, k].reshape(3, 3) - m.state(np.array([t]))[0][0])))
              for k, t in enumerate(sol.t))
    return Check(
        id="trajectory.coning_attitude_ode",
        kind=SECOND_METHOD,
        reference="second method: dC/dt = C [omega x] integrated by an adaptive 8th-order Runge-Kutta (Dormand-"
        "Prince DOP853, E. Hairer, S. P. Norsett, G. Wanner, Solving ODEs I, 2nd ed., 1993, sec. II.10) from the "
        f"closed-form rate ({_SAVAGE})",
        formula=f"max |C_ode(t) - exp([a(t) x])| at t = 0.25, 0.5, 1 s (b {beta:g} rad, {f:g} Hz) [-], elements of "
        "a rotation matrix (scale 1)",
        expected=0.0,
        simulated=err,
        scale=1.0,
        tolerance=1e-9,
        derivation="the solver's local tolerance 1e-12 (rtol) accumulated over ~1e3 steps of a rotation of "
        "w t ~ 13 rad: global error ~1e-10, x10",
    )


def _two_sample_residual() -> Check:
    from scipy.spatial.transform import Rotation

    from gyrobench.sim.trajectory import ConingMotion, increments

    inc = increments(ConingMotion(half_angle=_BETA, frequency=_F, duration=_T), _FS, site=_no_earth())
    d1, d2 = inc.dtheta[0::2], inc.dtheta[1::2]
    phi = d1 + d2 + (2.0 / 3.0) * np.cross(d1, d2)
    c = inc.attitude
    # the exact rotation vector between each 2T interval's edge attitudes (C_k^T C_{k+2})
    exact = Rotation.from_matrix(np.swapaxes(c[0:-1:2], 1, 2) @ c[2::2]).as_rotvec()
    w, h = 2.0 * math.pi * _F, 2.0 / _FS
    return Check(
        id="trajectory.two_sample_coning_residual",
        kind=CLOSED_FORM,
        reference="M. B. Ignagni, 'Optimal strapdown attitude integration algorithms', J. Guid. Control Dyn. "
        "13(2) 363 (1990), table 1 (two-sample algorithm, coefficient 2/3; residual w b^2 h (w h)^4 / 960)",
        formula=f"mean |phi - phi_exact|_z per 2T interval, phi = d1 + d2 + (2/3) d1 x d2 (b {_BETA:g} rad, "
        f"{_F:g} Hz, T = 1/{_FS:g} s) against w b^2 h (w h)^4 / 960 [rad]",
        expected=w * _BETA**2 * h * (w * h) ** 4 / 960.0,
        simulated=float(np.mean(np.abs(phi - exact)[:, 2])),
        tolerance=0.05,
        derivation=f"truncation: the published residual is the leading term of a series in (w h)^2 (w h = "
        f"{w * h:.2f}); the next term's coefficient is not printed there, so 5 % is an ASSUMPTION about its size "
        "(uncorrected, the error is ~200x larger: the check cannot pass without the 2/3 correction)",
    )


def _rocking_bessel() -> Check:
    from scipy.special import j0

    from gyrobench.sim.trajectory import RockingMotion, increments

    amp, f = 0.4, 5.0
    site = _no_earth()
    inc = increments(RockingMotion(amplitude=amp, frequency=f, duration=2.0), 8 * f, site=site)
    period = 1.0 / f
    dv = inc.dv.reshape(-1, 8, 3).sum(axis=1)
    expected = -site.gravity * period * float(j0(amp))
    return Check(
        id="trajectory.rocking_gravity_bessel",
        kind=CLOSED_FORM,
        reference="M. Abramowitz, I. A. Stegun, Handbook of Mathematical Functions (1964), 9.1.18: "
        "J0(A) = (1/pi) int_0^pi cos(A sin t) dt",
        formula=f"velocity increment along z over each whole period of a rocking A sin(w t) about x (A {amp:g} rad, "
        f"{f:g} Hz, 8 samples a period) = -g T J0(A) [m/s] (worst period)",
        expected=expected,
        simulated=float(dv[np.argmax(np.abs(dv[:, 2] - expected)), 2]),
        tolerance=1e-13,
        derivation="quadrature: 8 Gauss-Legendre nodes per sample interval at w T = pi/4 integrate cos(A sin) to "
        "~1e-16 (the error term's (w T)^16 / 16!); rounding of 64 summed terms, ~1e-14, x10",
    )


def parts(rng: np.random.Generator) -> list[Part]:
    """The four deterministic groups (``rng`` unused but required by the collector).

    Parameters
    ----------
    rng : numpy.random.Generator
        The module's stream (the collector's contract; a deterministic module does not draw from it).

    Returns
    -------
    list of Part
        Independent parts, each with its own arguments.
    """
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator; got {type(rng).__name__}")
    return [
        Part("coning_increments", _coning_increments),
        Part("coning_attitude", _coning_attitude),
        Part("two_sample_residual", _two_sample_residual),
        Part("rocking_bessel", _rocking_bessel),
    ]


def checks(rng: np.random.Generator) -> list[Check]:
    """The trajectory checks (deterministic).

    Parameters
    ----------
    rng : numpy.random.Generator
        The module's stream (the collector's contract; a deterministic module does not draw from it).

    Returns
    -------
    list of Check
        The module's checks.
    """
    return run_parts(parts(rng))
