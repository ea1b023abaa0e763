"""Axisymmetric heat conduction on an (r, z) finite-volume grid and its exact discretisation.

rho c dT/dt = (1/r) d/dr(k_r r dT/dr) + d/dz(k_z dT/dz), discretised on a tensor grid of cells
(:func:`fv_grid`), stepped with the first-order-hold matrix exponential (:func:`first_order_hold`,
exact for an input linear over each step; Van Loan 1978) or on its modes.

References
----------
C. F. Van Loan, IEEE Trans. Autom. Control 23(3) 395 (1978); docs/physics.md 3.7.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import linalg

__all__ = [
    "Grid",
    "fv_grid",
    "first_order_hold",
]


@dataclass(frozen=True, slots=True)
class Grid:
    """Axisymmetric finite-volume grid: conductance matrix, capacities and boundary conductances.

    ``r_faces`` (nr + 1,), ``z_faces`` (nz + 1,) [m]; cell (i, j) is node i * nz + j;
    ``K`` (m, m) conductance matrix [W/K] of the interior links; ``cap`` (m,) [J/K];
    ``g_face`` dict side -> (m,) conductance from each cell centre to that outer face [W/K]
    (zero for cells not on the side; "inner" is zero when the grid starts at r = 0).
    """

    r_faces: NDArray[np.float64]
    z_faces: NDArray[np.float64]
    K: NDArray[np.float64]
    cap: NDArray[np.float64]
    g_face: dict[str, NDArray[np.float64]]

    @property
    def r_centres(self) -> NDArray[np.float64]:
        f = self.r_faces
        return 0.5 * (f[:-1] + f[1:])

    @property
    def z_centres(self) -> NDArray[np.float64]:
        f = self.z_faces
        return 0.5 * (f[:-1] + f[1:])

    @property
    def shape(self) -> tuple[int, int]:
        return len(self.r_faces) - 1, len(self.z_faces) - 1

    def interpolation(self, r: ArrayLike, z: ArrayLike) -> NDArray[np.float64]:
        """P (n_points, m): bilinear interpolation on the cell centres, linear beyond the edges.

        Exact for any field linear in r and z (so the axial-gradient check is exact).
        """
        r = np.asarray(r, dtype=float)
        z = np.asarray(z, dtype=float)
        rc, zc = self.r_centres, self.z_centres
        nr, nz = self.shape
        i = np.clip(np.searchsorted(rc, r) - 1, 0, nr - 2)
        j = np.clip(np.searchsorted(zc, z) - 1, 0, nz - 2)
        tr = (r - rc[i]) / (rc[i + 1] - rc[i])
        tz = (z - zc[j]) / (zc[j + 1] - zc[j])
        P = np.zeros((len(r), nr * nz))
        rows = np.arange(len(r))
        for di, wr in ((0, 1 - tr), (1, tr)):
            for dj, wz in ((0, 1 - tz), (1, tz)):
                np.add.at(P, (rows, (i + di) * nz + j + dj), wr * wz)
        return P


def fv_grid(
    r_faces: ArrayLike,
    z_faces: ArrayLike,
    k_r: ArrayLike,
    k_z: ArrayLike,
    rho_c: ArrayLike,
) -> Grid:
    """Finite-volume conduction on an (r, z) tensor grid with per-cell properties (shape (nr, nz)).

    Discretises rho c dT/dt = (1/r) d/dr(k_r r dT/dr) + d/dz(k_z dT/dz) (docs/physics.md 3.7):
    radial half-cell resistance ln(r_face / r_c) / (2 pi k_r dz), axial (dz/2) / (k_z pi
    (r2^2 - r1^2)), links in series (harmonic mean across a material interface). Second order
    in space for smooth fields.
    """
    rf = np.asarray(r_faces, dtype=float)
    zf = np.asarray(z_faces, dtype=float)
    if rf.ndim != 1 or len(rf) < 3 or np.any(np.diff(rf) <= 0) or rf[0] < 0:
        raise ValueError(f"r_faces must be >= 3 increasing radii >= 0 m; got {rf!r}")
    if zf.ndim != 1 or len(zf) < 3 or np.any(np.diff(zf) <= 0):
        raise ValueError(f"z_faces must be >= 3 increasing positions [m]; got {zf!r}")
    nr, nz = len(rf) - 1, len(zf) - 1
    kr = np.broadcast_to(np.asarray(k_r, float), (nr, nz))
    kz = np.broadcast_to(np.asarray(k_z, float), (nr, nz))
    rc_ = np.broadcast_to(np.asarray(rho_c, float), (nr, nz))
    if np.any(kr <= 0) or np.any(kz <= 0) or np.any(rc_ <= 0):
        raise ValueError("k_r, k_z and rho_c must be > 0 in every cell")
    rc = 0.5 * (rf[:-1] + rf[1:])
    dz = np.diff(zf)[None, :]
    area = (math.pi * np.diff(rf**2))[:, None]  # annulus area of each ring [m^2]
    # half-cell resistances [K/W]
    R_out = np.log(rf[1:] / rc)[:, None] / (2 * math.pi * kr * dz)
    with np.errstate(divide="ignore"):
        R_in = np.log(rc / np.where(rf[:-1] > 0, rf[:-1], np.nan))[:, None] / (
            2 * math.pi * kr * dz
        )
    R_z = 0.5 * dz / (kz * area)
    m = nr * nz
    idx = np.arange(m).reshape(nr, nz)
    K = np.zeros((m, m))

    def link(a, b, g):  # a, b: index arrays without repeats, so fancy += is exact
        K[a, a] += g
        K[b, b] += g
        K[a, b] -= g
        K[b, a] -= g

    g_r = 1.0 / (R_out[:-1, :] + R_in[1:, :])
    link(idx[:-1, :].ravel(), idx[1:, :].ravel(), g_r.ravel())
    g_zl = 1.0 / (R_z[:, :-1] + R_z[:, 1:])
    link(idx[:, :-1].ravel(), idx[:, 1:].ravel(), g_zl.ravel())
    cap = (rc_ * area * dz).ravel()
    g_face = {s: np.zeros(m) for s in ("inner", "outer", "bottom", "top")}
    if rf[0] > 0:
        g_face["inner"][idx[0, :]] = 1.0 / R_in[0, :]
    g_face["outer"][idx[-1, :]] = 1.0 / R_out[-1, :]
    g_face["bottom"][idx[:, 0]] = 1.0 / R_z[:, 0]
    g_face["top"][idx[:, -1]] = 1.0 / R_z[:, -1]
    return Grid(r_faces=rf, z_faces=zf, K=K, cap=cap, g_face=g_face)


def first_order_hold(A: NDArray[np.float64], b: NDArray[np.float64], dt: float):
    """(Phi, q0, q1): x_{k+1} = Phi x_k + q0 u_k + q1 u_{k+1}, exact for u linear over each step.

    From expm of the augmented matrix [[A dt, b dt, 0], [0, 0, 1], [0, 0, 0]] (Van Loan
    1978): Phi = E11, Gamma0 = E12, Gamma1 = E13; u(t_k + tau) = u_k + (u_{k+1} - u_k) tau/dt
    gives q0 = Gamma0 - Gamma1, q1 = Gamma1.
    """
    m = len(b)
    M = np.zeros((m + 2, m + 2))
    M[:m, :m] = A * dt
    M[:m, m] = b * dt
    M[m, m + 1] = 1.0
    E = linalg.expm(M)
    return E[:m, :m], E[:m, m] - E[:m, m + 1], E[:m, m + 1]


# ======================================================================================
# coil specification, drawn imperfections, winding map
# ======================================================================================




def _foh_step(mu, beta, dt):
    """(phi, q0, q1) of one first-order-hold step of length ``dt`` [s] (:meth:`Coil2D._solve`)."""
    h = mu * dt
    phi = np.exp(-h)
    G0 = -np.expm1(-h) / mu
    G1 = np.where(
        h > 1e-6, (h + np.expm1(-h)) / (mu * np.maximum(h, 1e-300)), 0.5 * dt * (1 - h / 3)
    )
    return phi, beta * (G0 - G1), beta * G1


def _modal_states(tk, vk, dt, modes):
    """(t, u, z): sample times [s], chamber input [K] and modal states on the step grid, plus the
    program's end when it falls between grid points (one shorter last step, equally exact)."""
    mu, _, beta = modes
    n = int(math.floor((tk[-1] - tk[0]) / dt + 1e-9)) + 1
    t = tk[0] + dt * np.arange(n)
    last = float(tk[-1] - t[-1])
    partial = last > 1e-9 * dt
    if partial:
        t = np.append(t, tk[-1])
    u = np.interp(t, tk, vk)
    phi, q0, q1 = _foh_step(mu, beta, dt)
    z = np.empty((len(t), len(mu)))
    z[0] = beta * u[0] / mu
    f = np.outer(u[: n - 1], q0) + np.outer(u[1:n], q1)
    for k in range(n - 1):
        z[k + 1] = phi * z[k] + f[k]
    if partial:
        phi_l, q0_l, q1_l = _foh_step(mu, beta, last)
        z[n] = phi_l * z[n - 1] + q0_l * u[n - 1] + q1_l * u[n]
    return t, u, z
