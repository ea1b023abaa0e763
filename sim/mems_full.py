"""Full integration of the MEMS gyro's equations of motion (RK4), the slow flow's reference.

Equations, units and references: :mod:`gyrobench.sim.mems_resonator` and docs/physics.md 5.1.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.base.units import BOLTZMANN  # exact SI, re-exported
from gyrobench.base.validate import check_rng as _check_rng
from gyrobench.base.validate import real_field
from gyrobench.sim.mems_resonator import (
    MemsResonator,
    _adc,
    _clamp,
    _equilibrium_command,
    _limit,
    _output_map,
    _readout_weight,
    operating_point,
)

__all__ = [
    "FullResult",
    "simulate_full",
]


@dataclass(frozen=True, slots=True)
class FullResult:
    """Output of :func:`simulate_full`, sampled at ``fs`` (boxcar averages over each interval).

    Arrays have shape (n_out, n_cases). ``output`` [rad/s] is the gyro output (before the
    ADC when ``adc=False``); ``u_i``, ``u_q`` [V] the rebalance commands; ``drive_amplitude``
    [m] the AGC's amplitude estimate; ``sense_envelope`` [m] the complex sense envelope
    <2 y e^{-j w t}> (demodulated without noise).

    Attributes
    ----------
    fs : float
        Output rate [Hz].
    output : ndarray
        Gyro output [rad/s], shape (n_out, n_cases) (before the ADC when ``adc=False``).
    u_i, u_q : ndarray
        In-phase and quadrature rebalance commands [V].
    drive_amplitude : ndarray
        The AGC's drive amplitude estimate [m].
    sense_envelope : ndarray of complex
        Complex sense envelope <2 y e^{-j w t}> [m], demodulated without noise.
    """

    fs: float
    output: NDArray[np.float64]
    u_i: NDArray[np.float64]
    u_q: NDArray[np.float64]
    drive_amplitude: NDArray[np.float64]
    sense_envelope: NDArray[np.complex128]


def _as_cases(name: str, v: ArrayLike) -> NDArray[np.float64]:
    a = np.atleast_1d(np.asarray(v, dtype=float))
    if a.ndim != 1 or not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be a finite scalar or 1-D array [SI]; got shape {a.shape}")
    return a


def simulate_full(
    unit: MemsResonator,
    rate: ArrayLike,
    *,
    duration: float,
    rng: np.random.Generator,
    fs: float = 1000.0,
    rate_acceleration: ArrayLike = 0.0,
    specific_force: ArrayLike = 0.0,
    drive_specific_force: ArrayLike = 0.0,
    temperature: float | None = None,
    steps_per_cycle: int = 24,
    noise: bool = True,
    adc: bool = True,
    initial: str = "equilibrium",
) -> FullResult:
    """Integrate the full rotating-frame equations with the carrier (fixed-step RK4, vectorised).

    Parameters
    ----------
    unit : MemsResonator
    rate : array_like, shape (k,) or scalar
        Omega(0) of each independent case [rad/s].
    duration : float
        Record length [s], > 0.
    rng : numpy.random.Generator
        Noise stream (Brownian forces on both modes, pick-off noise), one draw set per step.
    fs : float
        Output sample rate [Hz]; the output is the boxcar mean of the RK4 samples over 1/fs.
    rate_acceleration : array_like
        Omega' of each case [rad/s^2]: Omega(t) = Omega(0) + Omega' t.
    specific_force : array_like
        f of each case [m/s^2], constant: specific force along the sense axis (+1 g at rest
        with the sense axis up). Enters as the inertial force -m f on the proof mass and, through
        the displaced mass, the forcer's electrostatic cross-stiffness k_e eps_A x y
        (:func:`electrostatic_cross_stiffness`; its reciprocal k_e eps_A y^2/2 on the drive).
    drive_specific_force : array_like
        f_d of each case [m/s^2], constant: specific force along the drive axis, the inertial
        force -m f_d on the drive; the drive oscillates about x_s = -m f_d/k_x (the start
        state includes it) and the same k_e eps_A x y term changes the sense stiffness.
    temperature : float, optional
        Die temperature [K] (default T0).
    steps_per_cycle : int
        RK4 steps per drive period (>= 16); the RK4 amplitude error per step is (w dt)^6/144.
    noise : bool
        Draw the Brownian and pick-off noises.
    adc : bool
        Apply output range and quantization.
    initial : {"equilibrium", "rest"}
        Start at the slow-flow equilibrium (drive at X0, sense nulled, commands at their
        steady values) or with the drive at X0 and the rebalance commands at 0.

    Returns
    -------
    FullResult

    Notes
    -----
    Each step holds the noise forces constant: variance S/(2 dt) per step for a one-sided PSD S
    (band-limited white noise of the same level up to 1/(2 dt)). The drive reference is the
    AGC's own estimate (ideal phase tracking): X_hat = sqrt(x^2 + (x'/w_x)^2),
    cos wt = x/X_hat, sin wt = -x'/(w_x X_hat).
    """
    _check_rng(rng)
    if unit.sense_chain is not None:
        raise ValueError(
            "simulate_full integrates the linear sense mode; a unit with a sense_chain is integrated "
            "through its chain in gyrobench.scenarios.checks.mems_nonlinear (full sense equation with the "
            "carrier); use simulate, or replace(unit, sense_chain=None)"
        )
    op = operating_point(unit, temperature)
    w0 = _as_cases("rate", rate)
    al = np.broadcast_to(_as_cases("rate_acceleration", rate_acceleration), w0.shape).copy()
    sf_y = np.broadcast_to(_as_cases("specific_force", specific_force), w0.shape).copy()
    f_d = _as_cases("drive_specific_force", drive_specific_force)
    if f_d.size not in (1, w0.size):
        raise ValueError(
            f"drive_specific_force must be a scalar or one value per case ({w0.size}); "
            f"got shape {f_d.shape}"
        )
    f_d = np.broadcast_to(f_d, w0.shape).copy()
    if not (isinstance(steps_per_cycle, (int, np.integer)) and steps_per_cycle >= 16):
        raise ValueError(f"steps_per_cycle must be an integer >= 16; got {steps_per_cycle!r}")
    duration = real_field("simulate_full", "duration", duration)
    fs = real_field("simulate_full", "fs", fs)
    if not (duration > 0 and fs > 0):
        raise ValueError(f"duration and fs must be > 0; got {duration!r} s and {fs!r} Hz")
    if initial not in ("equilibrium", "rest"):
        raise ValueError(f"initial must be 'equilibrium' or 'rest'; got {initial!r}")
    k = w0.size
    period = 2.0 * math.pi / op.wx
    n_dec = max(1, int(round(1.0 / (fs * period * (1.0 / steps_per_cycle)))))
    dt = 1.0 / (fs * n_dec)  # exactly n_dec steps per output sample
    n_out = int(round(duration * fs))
    if n_out < 1:
        raise ValueError(f"duration must cover at least one output sample; got {duration!r} s")

    m, wx, x0 = op.m, op.wx, op.x0
    cx, cy, kx, ky, kyx, cyx = op.cx, op.cy, op.kx, op.ky, op.kyx, op.cyx
    gz = 1j * op.gain * np.exp(1j * op.theta)
    kc = op.kappa_c
    # AGC: c_a = c_x + Kp e + I,  I' = Ki e,  e = X0 - X_hat; envelope X' = (c_a - c_x) X / (2m)
    wa = 2.0 * math.pi * unit.agc_bandwidth
    kp_a = 2.0 * m * wa / x0
    ki_a = kp_a * wa / 4.0
    sig_fx = math.sqrt(2.0 * BOLTZMANN * op.temperature * cx / dt) if noise else 0.0
    sig_fy = math.sqrt(2.0 * BOLTZMANN * op.temperature * cy / dt) if noise else 0.0
    sig_n = unit.pickoff_noise / math.sqrt(2.0 * dt) if noise else 0.0

    # electrostatic cross-stiffness k_e eps_A of the forcer plates [N/m per m]
    ke_eps = op.kyx_g * ky / m
    y_static = -m * sf_y / ky
    x_static = -m * f_d / kx
    if op.open_loop:  # no rebalance: the sense mass moves, B = R F_ext at equilibrium
        f_ext = (-1j * op.coriolis_gain * w0 - 1j * wx * cyx * x0
                 - (kyx + op.kyx_g * sf_y + m * al) * x0)
        ui, uq = np.zeros(k), np.zeros(k)
        # receptance with the sense stiffness the displaced drive gives (operating_point)
        r_d = 1.0 / (ky - ke_eps * x_static - m * wx**2 + 1j * cy * wx)
        b = r_d * f_ext if initial == "equilibrium" else np.zeros(k, complex)
    elif initial == "equilibrium":
        u = _equilibrium_command(op, w0, al, sf_y)
        ui, uq, _ = _clamp(u.real, u.imag, op.v_max)
        f_ext = (-1j * op.coriolis_gain * w0 - 1j * wx * cyx * x0
                 - (kyx + op.kyx_g * sf_y + m * al) * x0)
        b = op.receptance * (f_ext + gz * (ui + 1j * uq))
    else:
        ui, uq, b = np.zeros(k), np.zeros(k), np.zeros(k, complex)
    # state rows: x, y, vx, vy, I_agc, u_i, u_q (positions, then velocities: the two modes'
    # equations are evaluated side by side on the (2, k) blocks, one array operation for both)
    s = np.empty((7, k))
    s[0], s[2] = x0 + x_static, 0.0
    s[1], s[3] = b.real + y_static, (1j * wx * b).real
    # I_agc at the discrete equilibrium: c_x plus the RK4 amplitude decay of the harmonic
    # oscillator, |R| = 1 - (w dt)^6/144 per step, which the AGC must make up
    s[4] = cx + 2.0 * m * (wx * dt) ** 6 / (144.0 * dt)
    s[5], s[6] = ui, uq

    gzr, gzi = gz.real, gz.imag
    kcr, kci = (0.0, 0.0) if op.open_loop else (2.0 * kc.real, 2.0 * kc.imag)
    inv_wx = 1.0 / wx
    two_m = 2.0 * m
    ma = m * al
    mf = m * sf_y
    mfd = m * f_d
    half_ke = 0.5 * ke_eps
    # Terms that are identically zero (no angular acceleration, specific force or noise; no
    # rebalance in open loop) are skipped: adding or subtracting an exact 0.0 changes no bit,
    # so the result is the same as evaluating the full expressions, in fewer array operations.
    # With no angular acceleration Omega(t) = w0 + al t is w0 + al 0 for every t (al t = +-0).
    has_al, has_f, has_fd = bool(np.any(al)), bool(np.any(mf)), bool(np.any(mfd))
    closed = not op.open_loop
    # Both modes at once: rows (x, y) of a (2, k) block, the other mode's state as the reversed
    # view. Subtracting b is adding -b and (-c) b = -(c b) exactly in IEEE arithmetic, so a
    # coefficient column with a sign per row ([c, -c]) gives bit for bit the two scalar
    # expressions below, evaluated in the same order. Every coefficient is a full array of the
    # operand's shape: numpy multiplies two equal-shape arrays with less overhead than a Python
    # float or a broadcast column, and the products are the same (one rounding each).
    def full(*rows: float) -> NDArray:
        return np.repeat(np.array(rows, dtype=float)[:, None], k, axis=1)

    sign = full(1.0, -1.0)
    k_own = full(kx, ky)
    k_nl = full(half_ke, ke_eps)  # k_e eps_A y^2/2 on the drive, k_e eps_A x y on the sense
    k_yx, c_yx, m2 = full(kyx, kyx), full(cyx, cyx), full(m, m)
    gz_r, gz_cross = full(gzr, gzr), full(-gzi, gzi)
    kc_r, kc_cross = full(kcr, kcr), full(-kci, kci)
    kp_a1, cx1, cy1, x01, ki_a1, inv_wx1 = (full(v)[0] for v in (kp_a, cx, cy, x0, ki_a, inv_wx))
    if has_al:
        ma2 = ma * sign
    else:
        om_c = w0 + al * 0.0
        cen_c = np.broadcast_to(m * om_c * om_c, (2, k)).copy()
        tmo_c = (two_m * om_c) * sign
    xv = np.empty((2, k))  # x, x'/w_x
    sq = np.empty((2, k))
    xh = np.empty(k)
    e = np.empty(k)
    tmp_buf = np.empty((2, k))
    z_buf = np.empty((2, k))
    r = np.empty((2, k))
    p = np.empty((2, k))

    def deriv(t: float, s: NDArray, f2: NDArray, n: NDArray) -> NDArray:
        x, y, vx, vy, ia = s[0], s[1], s[2], s[3], s[4]
        pos, pos_r, vel_r, u = s[0:2], s[1::-1], s[3:1:-1], s[5:7]
        z, tmp = z_buf, tmp_buf  # scratch (local names: updated in place below)
        if has_al:
            om = w0 + al * t
            cen = m * om * om
            tmo = (two_m * om) * sign
        else:
            cen, tmo = cen_c, tmo_c
        xv[0] = x
        np.multiply(vx, inv_wx1, out=xv[1])  # x'/w_x
        np.multiply(xv, xv, out=sq)
        np.add(sq[0], sq[1], out=xh)
        np.sqrt(xh, out=xh)
        np.subtract(x01, xh, out=e)
        out = np.empty_like(s)
        acc = out[2:4]
        # a_x = ((I_agc + Kp e - c_x) x' - k_x x - k_yx y - c_yx y' + 2 m Omega y' + m Omega^2 x
        #        + m Omega' y + k_e eps_A y^2/2 - m f_d + f_x) / m
        # a_y = (F_fb - c_y y' - k_y y - k_yx x - c_yx x' - 2 m Omega x' + m Omega^2 y - m Omega' x
        #        - m f + k_e eps_A x y + f_y) / m, each in that order (row 0 and row 1 of acc)
        ax = np.multiply(kp_a1, e, out=acc[0])
        ax += ia
        ax -= cx1
        ax *= vx
        ay = np.multiply(cy1, vy, out=acc[1])
        if closed:
            # reference [cos wt, sin wt] = [x, -v_n]/X_hat; r holds [cos wt, -sin wt]
            np.divide(xv, xh, out=r)
            # F_fb = Re{z e^{jwt}} = z_r cos - z_i sin, z = gz u
            np.multiply(gz_r, u, out=z)
            z += np.multiply(gz_cross, u[::-1], out=tmp)
            z *= r
            np.subtract(np.add(z[0], z[1], out=xh), ay, out=ay)
        else:
            np.negative(ay, out=ay)  # 0 - a_y: no rebalance force
        acc -= np.multiply(k_own, pos, out=tmp)
        acc -= np.multiply(k_yx, pos_r, out=tmp)
        acc -= np.multiply(c_yx, vel_r, out=tmp)
        acc += np.multiply(tmo, vel_r, out=tmp)
        acc += np.multiply(cen, pos, out=tmp)
        if has_al:
            acc += np.multiply(ma2, pos_r, out=tmp)
        if has_f:
            ay -= mf
        np.multiply(k_nl, pos_r, out=tmp)
        tmp *= y
        acc += tmp
        if has_fd:
            ax -= mfd
        if noise:
            acc += f2
        acc /= m2
        out[0:2] = s[2:4]
        np.multiply(ki_a1, e, out=out[4])
        if closed:
            # u' = kappa_c 2 (y + n) (c_ref - j s_ref)
            np.multiply(np.add(y, n, out=e) if noise else y, r, out=p)  # [pr, pi]
            du = np.multiply(kc_r, p, out=out[5:7])
            du += np.multiply(kc_cross, p[::-1], out=tmp)
        else:  # no rebalance: the commands stay 0
            out[5:] = 0.0
        return out

    v_max = op.v_max
    lim = np.empty(k)

    def clamp(s: NDArray) -> None:
        """:func:`_clamp` of rows u_i, u_q of s in place, without the mask (min/max: the same
        values as np.clip, less overhead)."""
        u_i, u_q = s[5], s[6]
        np.maximum(u_q, -v_max, out=u_q)
        np.minimum(u_q, v_max, out=u_q)
        np.multiply(u_q, u_q, out=lim)
        np.subtract(v_max * v_max, lim, out=lim)
        np.maximum(lim, 0.0, out=lim)
        np.sqrt(lim, out=lim)
        np.maximum(u_i, -lim, out=u_i)
        np.minimum(u_i, lim, out=u_i)

    out_ui = np.empty((n_out, k))
    out_uq = np.empty((n_out, k))
    out_xa = np.empty((n_out, k))
    out_b = np.empty((n_out, k), complex)
    out_bm = np.empty((n_out, k), complex)
    t = 0.0
    zero = np.zeros((3, k))
    sig3 = np.array([sig_fx, sig_fy, sig_n])[:, None]
    # the states after each step of (a chunk of) one output interval; the read-outs are computed
    # from them at once and summed in step order (the same sums, term by term, as accumulating
    # per step). Chunks of at most 2^18 / k steps bound the two buffers to ~30 MB at any k.
    chunk = max(1, min(n_dec, 2**18 // k))
    hist = np.empty((chunk, 7, k))
    terms = np.empty((chunk, 7, k))  # u_i, u_q, X_hat, 2 y e^{-jwt} (re, im), with pick-off noise (re, im)
    n_terms = 5 if closed else 7
    for j in range(n_out):
        if noise:  # scaled once per output sample (the same products as scaling each step)
            z3 = rng.standard_normal((n_dec, 3, k)) * sig3
        acc = np.zeros((n_terms, k))
        for c0 in range(0, n_dec, chunk):
            nc = min(chunk, n_dec - c0)
            for i in range(nc):
                zi = z3[c0 + i] if noise else zero
                f2, nn = zi[0:2], zi[2]
                k1 = deriv(t, s, f2, nn)
                k2 = deriv(t + dt / 2, s + (dt / 2) * k1, f2, nn)
                k3 = deriv(t + dt / 2, s + (dt / 2) * k2, f2, nn)
                k4 = deriv(t + dt, s + dt * k3, f2, nn)
                s = s + (dt / 6) * (k1 + 2 * k2 + 2 * k3 + k4)
                t += dt
                if closed:
                    clamp(s)
                hist[i] = s
            h, tm = hist[:nc], terms[:nc]
            tm[:, 0:2] = h[:, 5:7]
            xa = np.sqrt(h[:, 0] ** 2 + (h[:, 2] / wx) ** 2, out=tm[:, 2])
            # e^{-jwt} = x/X_hat + j x'/(w X_hat), a real times a complex exact part by part;
            # j x'/(w X_hat) as numpy divides a complex by a real: times the reciprocal
            ref_r, ref_i = h[:, 0] / xa, h[:, 2] * (1.0 / (wx * xa))
            c2 = 2.0 * h[:, 1]
            np.multiply(c2, ref_r, out=tm[:, 3])
            np.multiply(c2, ref_i, out=tm[:, 4])
            if not closed:  # the pick-off, with its noise
                cm = 2.0 * (h[:, 1] + z3[c0:c0 + nc, 2]) if noise else c2
                np.multiply(cm, ref_r, out=tm[:, 5])
                np.multiply(cm, ref_i, out=tm[:, 6])
            for i in range(nc):
                acc += tm[i, :n_terms]
        out_ui[j], out_uq[j] = acc[0] / n_dec, acc[1] / n_dec
        out_xa[j] = acc[2] / n_dec
        out_b[j].real, out_b[j].imag = acc[3:5]
        out_b[j] /= n_dec
        if closed:
            out_bm[j] = 0.0
        else:
            out_bm[j].real, out_bm[j].imag = acc[5:7]
            out_bm[j] /= n_dec
    if op.open_loop:  # read-out: the demodulated pick-off, limited by the front end
        ch = _readout_weight(op) * _limit(out_bm, op.y_fs)
        out_ui, out_uq = ch.real, ch.imag
    y_out = _output_map(unit, op, out_ui) + unit.turn_on_bias - unit.bias_trim
    if adc:
        y_out = _adc(unit, y_out)
    return FullResult(fs, y_out, out_ui, out_uq, out_xa, out_b)
