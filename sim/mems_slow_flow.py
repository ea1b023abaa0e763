"""The MEMS gyro's demodulated slow flow at the output rate: exact steps, DAC clamp, rate tables.

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
from gyrobench.sim.mems_full import _as_cases
from gyrobench.sim.mems_resonator import (
    FLICKER_BAND_HZ,
    MemsResonator,
    OperatingPoint,
    _adc,
    _clamp,
    _equilibrium_command,
    _f_ext,
    _front_end,
    _output_map,
    _readout_weight,
    operating_point,
)
from gyrobench.sim.noise import NoiseModel

__all__ = [
    "SlowFlowResult",
    "slow_flow",
    "rate_table",
]


def _cmat(c: complex) -> NDArray:
    """Real 2x2 matrix of multiplication by the complex number c."""
    return np.array([[c.real, -c.imag], [c.imag, c.real]])


@dataclass(frozen=True, slots=True)
class _Discrete:
    phi: NDArray  # (5, 5) state transition over h
    gam: NDArray  # (5, 2) input (F_ext envelope, ZOH)
    chol: NDArray  # (5, 5) noise factor
    h: float


def _slow_matrices(
    op: OperatingPoint, unit: MemsResonator, h: float, noise: bool, *, saturated: bool = False
) -> _Discrete:
    """Exact discretisation of the slow flow over h (matrix exponential, Van Loan noise).

    State [B_r, B_i, u_I, u_Q, J], J' = u_I (J: integral of u_I, for the exact output mean).
    ``saturated``: the rate integrator is clamped (u_I' = 0, u_I held over the step).
    """
    p, r = op.pole, op.receptance
    gz = 1j * op.gain * np.exp(1j * op.theta)
    a = np.zeros((5, 5))
    a[0:2, 0:2] = _cmat(p)
    a[0:2, 2:4] = _cmat(-p * r * gz)
    a[2:4, 0:2] = _cmat(op.kappa_c)
    a[4, 2] = 1.0
    bd = np.zeros((5, 2))
    bd[0:2, :] = _cmat(-p * r)
    bw = np.zeros((5, 4))  # noise inputs: f_r, f_i (force envelope), n_r, n_i (pick-off)
    bw[0:2, 0:2] = _cmat(-p * r)
    bw[2:4, 2:4] = _cmat(op.kappa_c)
    if saturated:
        a[2, :] = 0.0
        bw[2, :] = 0.0
    # two-sided intensities: each envelope component has one-sided PSD 2 S -> intensity S
    s_f = 4.0 * BOLTZMANN * op.temperature * op.cy if noise else 0.0
    s_n = unit.pickoff_noise**2 if noise else 0.0
    qc = np.diag([s_f, s_f, s_n, s_n])
    return _discretize(a, bd, bw, qc, h)


def _discretize(a: NDArray, bd: NDArray, bw: NDArray, qc: NDArray, h: float) -> _Discrete:
    """Zero-order-hold (Phi, Gamma) of dx = A x + B_d u and the noise factor of B_w w.

    Van Loan (IEEE Trans. Autom. Control 23(3) 395, 1978): the discrete noise covariance is
    Q_d = F22^T F12 with F = expm([[-A, B_w Q_c B_w^T], [0, A^T]] h); returned as a
    square-root factor L (L L^T = Q_d, via its eigen-decomposition, clipped at 0).

    F holds expm(-A h), which grows as exp(-Re(lambda) h) for the stable poles and cancels in
    the product (relative error ~ eps exp(-2 Re(lambda) h)): at -Re(lambda) h ~ 60 (the default
    unit at fs = 8 Hz) Q_d is lost to rounding. When -Re(lambda)_min h > 4 (error > ~1e-12),
    Van Loan's formula is applied over h / 2^k with -Re(lambda) h / 2^k <= 1 and the step
    doubled k times, Q_d(2 h) = Phi(h) Q_d(h) Phi(h)^T + Q_d(h) (the covariance of two
    consecutive steps' noise; exact).
    """
    from scipy.linalg import expm

    n, m = a.shape[0], bd.shape[1]
    aug = np.zeros((n + m, n + m))
    aug[:n, :n] = a
    aug[:n, n:] = bd
    e = expm(aug * h)
    decay = float(np.max(-np.linalg.eigvals(a).real, initial=0.0)) * h
    k = math.ceil(math.log2(decay)) if decay > 4.0 else 0
    hs = h / 2**k
    vl = np.zeros((2 * n, 2 * n))
    vl[:n, :n] = -a
    vl[:n, n:] = bw @ qc @ bw.T
    vl[n:, n:] = a.T
    ev = expm(vl * hs)
    qd = ev[n:, n:].T @ ev[:n, n:]
    phi_s = ev[n:, n:].T  # expm(A hs)
    for _ in range(k):
        qd = phi_s @ qd @ phi_s.T + qd
        phi_s = phi_s @ phi_s
    qd = 0.5 * (qd + qd.T)
    w, v = np.linalg.eigh(qd)
    return _Discrete(e[:n, :n], e[:n, n:], v * np.sqrt(np.clip(w, 0.0, None)), h)


def _fext(
    op: OperatingPoint, rate: NDArray, accel: NDArray, force: NDArray | float = 0.0
) -> NDArray:
    """F_ext envelope (Coriolis, anisodamping, quadrature incl. its specific-force part,
    angular acceleration) as [re, im] (:func:`_f_ext`)."""
    z = _f_ext(op, rate, accel, force)
    return np.stack([np.real(z), np.imag(z)], axis=-1)


def _open_loop_matrices(
    op: OperatingPoint, unit: MemsResonator, h: float, noise: bool
) -> _Discrete:
    """Exact discretisation of the open-loop slow flow over h (no rebalance).

    State [B_r, B_i, J_r, J_i] with J' = B + n~ (the integral of the pick-off envelope, for its
    exact interval mean); inputs the F_ext envelope [re, im] (ZOH); noise f~ (force) and n~
    (pick-off), two-sided intensities S_F = 4 k_B T c_y and S_n per component.
    """
    p, r = op.pole, op.receptance
    a = np.zeros((4, 4))
    a[0:2, 0:2] = _cmat(p)
    a[2:4, 0:2] = np.eye(2)
    bd = np.zeros((4, 2))
    bd[0:2, :] = _cmat(-p * r)
    bw = np.zeros((4, 4))
    bw[0:2, 0:2] = _cmat(-p * r)
    bw[2:4, 2:4] = np.eye(2)
    s_f = 4.0 * BOLTZMANN * op.temperature * op.cy if noise else 0.0
    s_n = unit.pickoff_noise**2 if noise else 0.0
    qc = np.diag([s_f, s_f, s_n, s_n])
    return _discretize(a, bd, bw, qc, h)


def _run_open_loop(
    b0: NDArray, d: NDArray, z: NDArray | None, disc: _Discrete
) -> tuple[NDArray, NDArray]:
    """Open-loop slow flow for all steps at once: per-step mean pick-off envelope and end B.

    ``b0`` (k,) complex start envelope, ``d`` (n, k, 2), ``z`` (n, k, >= 4) standard normals.
    """
    e = d @ disc.gam.T
    if z is not None:
        e = e + z[..., :4] @ disc.chol.T
    y0 = np.stack([b0.real, b0.imag], axis=-1)
    x = _modal_filter(disc.phi[:2, :2], y0, e[..., :2])
    if x is None:  # pragma: no cover - a 2x2 complex-pole block is always diagonalisable
        raise RuntimeError("open-loop transition matrix not diagonalisable")
    x_start = np.concatenate([y0[None], x[:-1]], axis=0)
    j = x_start @ disc.phi[2:4, :2].T + e[..., 2:4]
    mean_b = (j[..., 0] + 1j * j[..., 1]) / disc.h
    return mean_b, x[..., 0] + 1j * x[..., 1]


#: steps per noise draw of the slow flow (the stream is the same whatever the path taken)
_NOISE_CHUNK_VALUES = 2**20


def _draw_noise(rng: np.random.Generator, n: int, k: int) -> NDArray[np.float64]:
    """(n, k, 5) standard normals, drawn in chunks of steps (bounded temporaries)."""
    chunk = max(1, _NOISE_CHUNK_VALUES // (5 * k))
    out = np.empty((n, k, 5))
    for i in range(0, n, chunk):
        out[i:i + chunk] = rng.standard_normal((min(chunk, n - i), k, 5))
    return out


def _run_linear(
    s0: NDArray, d: NDArray, z: NDArray | None, disc: _Discrete, v_max: float
) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """The unclamped slow flow for all steps at once, in the eigenbasis of Phi (lfilter per mode).

    J (the integral of u_I) never feeds back and is reset each step, so the recursion is the
    4-state x_{i+1} = Phi4 x_i + e_i; with Phi4 = V Lambda V^-1 each mode is a scalar
    first-order filter. Returns the per-step mean u_I, end-of-step u_Q and B, and a mask of
    the columns where the DAC limit is crossed (those must be rerun with the clamp).
    """
    from scipy.signal import lfilter

    n, k = d.shape[0], d.shape[1]
    phi, gam, chol = disc.phi, disc.gam, disc.chol
    e = d @ gam.T  # (n, k, 5)
    if z is not None:
        e = e + z @ chol.T
    lam, vec = np.linalg.eig(phi[:4, :4])
    bad = np.ones(k, dtype=bool)
    if np.linalg.cond(vec) > 1e8:  # not safely diagonalisable: let the clamped loop do it
        return np.empty((n, k)), np.empty((n, k)), np.empty((n, k), complex), bad
    vinv = np.linalg.inv(vec)
    f = e[:, :, :4] @ vinv.T  # (n, k, 4) modal inputs
    q0 = s0[:, :4] @ vinv.T  # (k, 4)
    q = np.empty((n, k, 4), complex)
    for j in range(4):
        zi = (lam[j] * q0[:, j])[None, :]  # lfilter state for r_i = f_i + lam r_{i-1}
        q[:, :, j], _ = lfilter([1.0], [1.0, -lam[j]], f[:, :, j], axis=0, zi=zi)
    x_end = (q @ vec.T).real  # state at the end of each step (n, k, 4)
    x_start = np.concatenate([s0[None, :, :4], x_end[:-1]], axis=0)
    mean_u = (x_start @ phi[4, :4] + e[:, :, 4]) / disc.h
    _, _, hit = _clamp(x_end[:, :, 2], x_end[:, :, 3], v_max)
    bad = np.any(hit, axis=0)
    return mean_u, x_end[:, :, 3], x_end[:, :, 0] + 1j * x_end[:, :, 1], bad


def _modal_filter(m: NDArray, y0: NDArray, f: NDArray) -> NDArray | None:
    """y_{i+1} = M y_i + f_i for all i at once (eigenbasis of M, one lfilter per mode).

    ``y0`` (..., q), ``f`` (n, ..., q); returns the end-of-step states (n, ..., q), or None when
    M is not safely diagonalisable (eigenvector condition number > 1e8).
    """
    from scipy.signal import lfilter

    lam, vec = np.linalg.eig(m)
    if np.linalg.cond(vec) > 1e8:
        return None
    vinv = np.linalg.inv(vec)
    g = f @ vinv.T
    q0 = y0 @ vinv.T
    out = np.empty(g.shape, complex)
    for j in range(lam.size):
        zi = (lam[j] * q0[..., j])[None, ...]
        out[..., j], _ = lfilter([1.0], [1.0, -lam[j]], g[..., j], axis=0, zi=zi)
    return (out @ vec.T).real


@dataclass(frozen=True, slots=True)
class _Segment:
    """``length`` steps of one column of the clamped slow flow: per-step mean u_I, end-of-step
    u_Q and B, and the (clamped, J = 0) state after the last of them."""

    length: int
    mean_u: NDArray
    u_q: NDArray
    b: NDArray
    end: NDArray


def _linear_segment(
    x0: NDArray, e_lin: NDArray, disc: _Discrete, v: float
) -> _Segment | None:
    """Steps from state ``x0`` (5,) while the unclamped step stays inside the DAC limit.

    ``e_lin`` (n, 5): the step inputs d gam^T + z chol^T. The segment ends before the first
    step whose end state would cross the limit (that step is a saturated one).
    """
    x = _modal_filter(disc.phi[:4, :4], x0[:4], e_lin[:, :4])
    if x is None:
        return None
    _, _, hit = _clamp(x[:, 2], x[:, 3], v)
    n_ok = int(np.argmax(hit)) if np.any(hit) else x.shape[0]
    x_start = np.concatenate([x0[None, :4], x[:-1]], axis=0)[:n_ok]
    mean_u = (x_start @ disc.phi[4, :4] + e_lin[:n_ok, 4]) / disc.h
    end = x0.copy() if n_ok == 0 else np.append(x[n_ok - 1], 0.0)
    return _Segment(n_ok, mean_u, x[:n_ok, 3], x[:n_ok, 0] + 1j * x[:n_ok, 1], end)


#: iterations and tolerance [x v_max] of the saturated-segment fixed point
_SAT_ITER = 40
_SAT_TOL = 1e-13


def _saturated_batch(
    x0: NDArray, e_lin: NDArray, e_sat: NDArray, disc: _Discrete, sat: _Discrete, v: float
) -> tuple[NDArray, NDArray, NDArray, NDArray, NDArray] | None:
    """Saturated steps of k columns from their clamped states ``x0`` (k, 5), all at once.

    Each saturated step holds u_I = sgn sqrt(v^2 - u_Q^2) (u_Q at the step start), so the
    recursion of y = [B_r, B_i, u_Q] is y_{i+1} = A y_i + g a(u_Q,i) + e_i with a nonlinear
    only through the square root. Linearised, a = alpha + beta u_Q + r (beta common to the
    columns: the median slope at their start values; alpha per column so a is exact at the
    start), the linear part runs as modal filters (:func:`_modal_filter`) and the residual r
    is iterated to a fixed point (a chord iteration: r is second order in u_Q - u_Q0 plus the
    columns' slope spread). A column's segment ends before the first step the step-by-step
    loop would not take as saturated with its sign (the unclamped candidate inside the limit,
    or of the other sign), after a step whose u_Q must be clipped at the DAC limit, or where
    the iteration has not converged. ``e_lin``, ``e_sat`` (n, k, 5): step inputs of the free
    and the saturated discretisation.

    Returns (n_ok (k,), mean u_I (n, k), end-of-step u_Q (n, k), B (n, k), the clamped end
    states (n, k, 5)), or None if the transition matrix cannot be diagonalised.
    """
    n, k = e_lin.shape[0], e_lin.shape[1]
    cand0 = x0 @ disc.phi.T + e_lin[0]
    sgn = np.where(cand0[:, 2] >= 0, 1.0, -1.0)
    uq0 = x0[:, 3]
    s0 = np.sqrt(np.maximum(v * v - uq0 * uq0, 0.0))
    ok0 = s0 > 1e-6 * v
    slope = np.where(ok0, -sgn * uq0 / np.where(ok0, s0, 1.0), 0.0)
    beta = float(np.median(slope))
    alpha = sgn * s0 - beta * uq0
    idx = [0, 1, 3]
    g = sat.phi[idx, 2]
    m = sat.phi[np.ix_(idx, idx)].copy()
    m[:, 2] += g * beta
    y0 = x0[:, idx]
    es = e_sat[:, :, idx]
    r = np.zeros((n, k))
    y_start = np.empty((n, k, 3))
    converged = np.zeros((n, k), dtype=bool)
    for _ in range(_SAT_ITER):
        y = _modal_filter(m, y0, es + (alpha + r)[:, :, None] * g)
        if y is None:
            return None
        y_start[0], y_start[1:] = y0, y[:-1]
        uq = y_start[:, :, 2]
        r_new = sgn * np.sqrt(np.maximum(v * v - uq * uq, 0.0)) - (alpha + beta * uq)
        converged = np.abs(r_new - r) <= _SAT_TOL * v
        r = r_new
        if np.all(converged):
            break
    # the steps exactly as the loop takes them, from the converged start states
    uq_s = y_start[:, :, 2]
    sh = np.zeros((n, k, 5))
    sh[..., 0], sh[..., 1], sh[..., 3] = y_start[..., 0], y_start[..., 1], uq_s
    sh[..., 2] = sgn * np.sqrt(np.maximum(v * v - uq_s * uq_s, 0.0))
    s_new = sh @ sat.phi.T + e_sat
    mean_u = s_new[..., 4] / sat.h
    ui_e, uq_e, _ = _clamp(s_new[..., 2], s_new[..., 3], v)
    ends = np.stack([s_new[..., 0], s_new[..., 1], ui_e, uq_e, np.zeros((n, k))], axis=-1)
    # start states as the loop has them (clamped ends), and its candidate test
    st = np.concatenate([x0[None], ends[:-1]], axis=0)
    cand = st @ disc.phi.T + e_lin
    _, _, hit = _clamp(cand[..., 2], cand[..., 3], v)
    take = hit & (np.sign(cand[..., 2]) == sgn) & converged & ok0
    # a step whose u_Q is clipped changes the next start state: the segment ends after it
    take[1:] &= np.abs(s_new[:-1, :, 3]) <= v
    n_ok = np.where(np.all(take, axis=0), n, np.argmin(take, axis=0))
    return n_ok, mean_u, uq_e, s_new[..., 0] + 1j * s_new[..., 1], ends


def _saturated_segment(
    x0: NDArray, e_lin: NDArray, e_sat: NDArray, disc: _Discrete, sat: _Discrete, v: float
) -> _Segment | None:
    """One column's saturated segment from the clamped state ``x0`` (5,) (see
    :func:`_saturated_batch`); None if it cannot start here."""
    out = _saturated_batch(x0[None], e_lin[:, None], e_sat[:, None], disc, sat, v)
    if out is None or out[0][0] == 0:
        return None
    n_ok = int(out[0][0])
    mean_u, uq, b, ends = (a[:n_ok, 0] for a in out[1:])
    return _Segment(n_ok, mean_u, uq, b, ends[-1])


#: segments per column before the segmented solver steps the rest of it
_MAX_SEGMENTS = 16


def _run_segmented(
    s: NDArray, d: NDArray, z: NDArray | None, disc: _Discrete, sat: _Discrete, v: float
) -> tuple[NDArray, NDArray, NDArray]:
    """The clamped slow flow, column by column, as alternating free and saturated segments.

    Takes the same steps as :func:`_run_clamped` (the reference; equal to rounding, test):
    a free segment runs until the first step whose unclamped end crosses the DAC limit
    (:func:`_linear_segment`), a saturated one until the loop would leave saturation
    (:func:`_saturated_segment`); each is solved for all its steps at once. A column that
    switches more than ``_MAX_SEGMENTS`` times (a rate dithering on the knee), or whose
    segment cannot be solved, is stepped from there by :func:`_run_clamped`.
    """
    n, k = d.shape[0], d.shape[1]
    out_u = np.empty((n, k))
    out_q = np.empty((n, k))
    out_b = np.empty((n, k), complex)
    todo = np.ones(k, dtype=bool)
    # columns saturated from the first step (a dwell beyond the knee): one batch; those it
    # carries to the end are done, the others go column by column below
    cand0 = s @ disc.phi.T + d[0] @ disc.gam.T + (0.0 if z is None else z[0] @ disc.chol.T)
    _, _, hit0 = _clamp(cand0[:, 2], cand0[:, 3], v)
    if np.any(hit0):
        cols = np.flatnonzero(hit0)
        e_lin = d[:, cols] @ disc.gam.T
        e_sat = d[:, cols] @ sat.gam.T
        if z is not None:
            e_lin = e_lin + z[:, cols] @ disc.chol.T
            e_sat = e_sat + z[:, cols] @ sat.chol.T
        batch = _saturated_batch(s[cols], e_lin, e_sat, disc, sat, v)
        if batch is not None:
            full = batch[0] == n
            done = cols[full]
            out_u[:, done], out_q[:, done], out_b[:, done] = (a[:, full] for a in batch[1:4])
            todo[done] = False
    for c in np.flatnonzero(todo):
        zc = None if z is None else z[:, c]
        e_lin = d[:, c] @ disc.gam.T
        e_sat = d[:, c] @ sat.gam.T
        if zc is not None:
            e_lin = e_lin + zc @ disc.chol.T
            e_sat = e_sat + zc @ sat.chol.T
        x = s[c].copy()
        i, saturated, segments = 0, False, 0
        while i < n:
            seg: _Segment | None = None
            if segments < _MAX_SEGMENTS:
                seg = (_saturated_segment(x, e_lin[i:], e_sat[i:], disc, sat, v) if saturated
                       else _linear_segment(x, e_lin[i:], disc, v))
            if seg is None or (saturated and seg.length == 0):
                zr = None if zc is None else zc[i:, None, :]
                u_c, q_c, b_c = _run_clamped(x[None], d[i:, c:c + 1], zr, disc, sat, v)
                out_u[i:, c], out_q[i:, c], out_b[i:, c] = u_c[:, 0], q_c[:, 0], b_c[:, 0]
                break
            j = i + seg.length
            out_u[i:j, c], out_q[i:j, c], out_b[i:j, c] = seg.mean_u, seg.u_q, seg.b
            i, x, saturated, segments = j, seg.end, not saturated, segments + 1
    return out_u, out_q, out_b


def _run_clamped(
    s: NDArray, d: NDArray, z: NDArray | None, disc: _Discrete, sat: _Discrete, v: float
) -> tuple[NDArray, NDArray, NDArray]:
    """The slow flow step by step with the rebalance DAC clamp (see :func:`slow_flow`).

    The reference of :func:`_run_segmented` (which :func:`slow_flow` uses).
    """
    n, k = d.shape[0], d.shape[1]
    phi_t, gam_t, chol_t = disc.phi.T, disc.gam.T, disc.chol.T
    zero = np.zeros((k, 5))
    out_u = np.empty((n, k))
    out_q = np.empty((n, k))
    out_b = np.empty((n, k), complex)
    h = disc.h
    s = s.copy()
    for i in range(n):
        zi = zero if z is None else z[i]
        s_new = s @ phi_t + d[i] @ gam_t + zi @ chol_t
        _, _, hit = _clamp(s_new[:, 2], s_new[:, 3], v)
        if np.any(hit):
            # redo the step of the saturated columns with u_I held at the DAC limit
            sh = s[hit].copy()
            uq0 = np.clip(sh[:, 3], -v, v)
            sh[:, 2] = np.sign(s_new[hit, 2]) * np.sqrt(np.maximum(v * v - uq0 * uq0, 0.0))
            s_new[hit] = sh @ sat.phi.T + d[i][hit] @ sat.gam.T + zi[hit] @ sat.chol.T
        mean_u = s_new[:, 4] / h
        ui, uq, _ = _clamp(s_new[:, 2], s_new[:, 3], v)
        s_new[:, 2], s_new[:, 3], s_new[:, 4] = ui, uq, 0.0
        s = s_new
        out_u[i], out_q[i] = mean_u, uq
        out_b[i] = s[:, 0] + 1j * s[:, 1]
    return out_u, out_q, out_b



@dataclass(frozen=True, slots=True)
class SlowFlowResult:
    """Output of :func:`slow_flow`; arrays of the rate's shape.

    ``output`` [rad/s] the gyro output (after ADC when requested), ``u_i``, ``u_q`` [V] the
    interval-mean rebalance commands (u_q: end-of-interval value; open loop: the rate and
    quadrature channels Re, Im{w_c sat(mean B_m)} [N]), ``sense_envelope`` [m] the complex
    sense envelope at the end of each interval.

    Attributes
    ----------
    fs : float
        Output rate [Hz].
    output : ndarray
        Gyro output [rad/s] (after the ADC when requested).
    u_i, u_q : ndarray
        Interval-mean rebalance commands [V] (u_q: end-of-interval value); open loop: the rate
        and quadrature channels Re, Im{w_c sat(mean B_m)} [N].
    sense_envelope : ndarray of complex
        Complex sense envelope at the end of each interval [m].
    """

    fs: float
    output: NDArray[np.float64]
    u_i: NDArray[np.float64]
    u_q: NDArray[np.float64]
    sense_envelope: NDArray[np.complex128]


def slow_flow(
    unit: MemsResonator,
    rate: ArrayLike,
    *,
    fs: float,
    rng: np.random.Generator,
    temperature: float | None = None,
    noise: bool = True,
    adc: bool = True,
    flicker: bool = True,
    specific_force: ArrayLike | None = None,
    drive_specific_force: float = 0.0,
) -> SlowFlowResult:
    """Slow-flow (demodulated) simulation at the output rate; one sample per 1/fs.

    Parameters
    ----------
    unit : MemsResonator
    rate : array_like, shape (n,) or (n, k)
        True rate [rad/s], held over each output interval (ZOH); k independent columns share
        the unit (e.g. the dwells of a rate table). Omega' = central difference x fs.
    fs : float
        Output sample rate [Hz], > 0.
    rng : numpy.random.Generator
        Two child streams are spawned: envelope noise, 1/f term.
    temperature : float, optional
        Die temperature [K] (default T0).
    noise, adc, flicker : bool
        Brownian + pick-off noise; output range and quantization; the 1/f term.
    specific_force : array_like, optional
        Specific force along the sense axis [m/s^2] (+1 g at rest with the sense axis up),
        broadcast to the rate's shape, held over each interval (ZOH); default 0. It adds the
        quadrature stiffness (dk_yx/df) f (:func:`electrostatic_cross_stiffness`).
    drive_specific_force : float
        Specific force along the drive axis [m/s^2], constant over the record (like the
        temperature): the sense stiffness it changes (:func:`operating_point`,
        :func:`drive_axis_sensitivity`); default 0.

    Returns
    -------
    SlowFlowResult

    Notes
    -----
    Each column starts at the noise-free equilibrium of its first rate (clamped). Exact for
    the linear part for any fs: the output is the exact mean of u_I over the interval. When
    the rate command would leave the DAC range within an interval, that interval is redone
    with u_I held at the limit (the exact discretisation with u_I' = 0), then u_Q is clipped:
    exact in the saturated steady state, approximate only in the interval where the loop
    enters or leaves saturation. Columns that never reach the limit run as modal filters over
    all steps; the others as alternating free and saturated segments, each solved for all its
    steps at once (:func:`_run_segmented`; the step-by-step loop :func:`_run_clamped` is its
    reference, equal to rounding in a test).
    """
    _check_rng(rng)
    fs = real_field("slow_flow", "fs", fs)
    if not fs > 0:
        raise ValueError(f"fs must be > 0 Hz; got {fs!r}")
    w = np.asarray(rate, dtype=float)
    if w.ndim not in (1, 2) or w.shape[0] == 0 or not np.all(np.isfinite(w)):
        raise ValueError(f"rate must be a finite (n,) or (n, k) array [rad/s]; got shape {w.shape}")
    squeeze = w.ndim == 1
    w2 = w[:, None] if squeeze else w
    n, k = w2.shape
    op = operating_point(unit, temperature, drive_specific_force=drive_specific_force)
    acc = np.gradient(w2, axis=0) * fs if n > 1 else np.zeros_like(w2)
    if specific_force is None:
        fy = np.zeros_like(w2)
    else:
        f_in = np.asarray(specific_force, dtype=float)
        if not np.all(np.isfinite(f_in)):
            raise ValueError("specific_force must be finite [m/s^2]")
        try:
            fy = np.broadcast_to(f_in[:, None] if squeeze and f_in.ndim == 1 else f_in,
                                 w2.shape)
        except ValueError:
            raise ValueError(
                f"specific_force must broadcast to the rate's shape {w.shape}; "
                f"got shape {f_in.shape}"
            ) from None
    d = _fext(op, w2, acc, fy)  # (n, k, 2)
    r_noise, r_flick = rng.spawn(2)
    if op.open_loop:
        ol = _open_loop_matrices(op, unit, 1.0 / fs, noise)
        b0 = op.receptance * (d[0, :, 0] + 1j * d[0, :, 1])
        z = _draw_noise(r_noise, n, k) if noise else None
        mean_b, out_b = _run_open_loop(b0, d, z, ol)
        ch = _readout_weight(op) * _front_end(op, mean_b)
        return _finish(unit, op, ch.real, ch.imag, out_b, fs, r_flick, flicker, adc, squeeze)
    disc = _slow_matrices(op, unit, 1.0 / fs, noise)
    # initial state: equilibrium at the first rate
    u = _equilibrium_command(op, w2[0], acc[0], fy[0])
    ui, uq, _ = _clamp(u.real, u.imag, op.v_max)
    gz = 1j * op.gain * np.exp(1j * op.theta)
    b = op.receptance * ((d[0, :, 0] + 1j * d[0, :, 1]) + gz * (ui + 1j * uq))
    s = np.stack([b.real, b.imag, ui, uq, np.zeros(k)], axis=1)  # (k, 5)
    z = _draw_noise(r_noise, n, k) if noise else None
    out_u, out_q, out_b, bad = _run_linear(s, d, z, disc, op.v_max)
    if np.any(bad):  # columns whose rebalance saturates: step by step with the clamp
        sat = _slow_matrices(op, unit, 1.0 / fs, noise, saturated=True)
        cols = np.flatnonzero(bad)
        zc = None if z is None else z[:, cols]
        u_c, q_c, b_c = _run_segmented(s[cols], d[:, cols], zc, disc, sat, op.v_max)
        out_u[:, cols], out_q[:, cols], out_b[:, cols] = u_c, q_c, b_c
    return _finish(unit, op, out_u, out_q, out_b, fs, r_flick, flicker, adc, squeeze)


def _finish(
    unit: MemsResonator, op: OperatingPoint, out_u: NDArray, out_q: NDArray, out_b: NDArray,
    fs: float, r_flick: np.random.Generator, flicker: bool, adc: bool, squeeze: bool,
) -> SlowFlowResult:
    """Output map, turn-on bias and trim, the 1/f and rate-random-walk terms and the ADC.

    The two low-frequency terms (``flicker``) are one :class:`~gyrobench.sim.noise.NoiseModel`
    (its own child stream per term), run continuously through the columns in order.
    """
    n, k = out_u.shape
    y = _output_map(unit, op, out_u) + unit.turn_on_bias - unit.bias_trim
    if flicker and (unit.bias_instability > 0 or unit.rate_random_walk > 0):
        nm = NoiseModel(bias_instability=unit.bias_instability,
                        rate_random_walk=unit.rate_random_walk, flicker_band=FLICKER_BAND_HZ)
        y = y + nm.generate(n * k, fs, rng=r_flick).reshape(k, n).T
    if adc:
        y = _adc(unit, y)
    if squeeze:
        return SlowFlowResult(fs, y[:, 0], out_u[:, 0], out_q[:, 0], out_b[:, 0])
    return SlowFlowResult(fs, y, out_u, out_q, out_b)


def rate_table(
    unit: MemsResonator,
    rates: ArrayLike,
    *,
    rng: np.random.Generator,
    fs: float = 200.0,
    average_s: float = 90.0,
    settle_s: float = 0.5,
    temperature: float | None = None,
) -> NDArray[np.float64]:
    """Mean output per table rate [rad/s]: each dwell settles, then is averaged.

    ``settle_s`` [s] is discarded, ``average_s`` [s] averaged, at ``fs`` [Hz].

    One power-on (the unit as given) for the whole table; the dwells run as independent
    columns of one slow-flow call (the rebalance loop settles in ms, so a dwell's mean does not
    depend on the previous rate). The 1/f term runs continuously through the dwells in table
    order.

    Parameters
    ----------
    unit : MemsResonator
        The unit, powered on as given.
    rates : array_like
        Table rates [rad/s], in table order.
    rng : numpy.random.Generator
        The run's streams.
    fs : float
        Output rate [Hz].
    average_s : float
        Averaged part of each dwell [s].
    settle_s : float
        Discarded start of each dwell [s].
    temperature : float or None
        Die temperature [K]; None: the unit's T0.

    Returns
    -------
    ndarray
        Mean output per table rate [rad/s].
    """
    w = _as_cases("rates", rates)
    n_settle = int(round(settle_s * fs))
    n_avg = int(round(average_s * fs))
    if n_avg < 1 or n_settle < 0:
        raise ValueError(
            "average_s must cover >= 1 sample and settle_s must be >= 0 s; "
            f"got {average_s!r}, {settle_s!r}"
        )
    col = np.broadcast_to(w, (n_settle + n_avg, w.size))
    res = slow_flow(unit, col, fs=fs, rng=rng, temperature=temperature)
    return res.output[n_settle:].mean(axis=0)
