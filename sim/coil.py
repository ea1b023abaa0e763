"""Fibre coil of an interferometric FOG: geometry, winding, radial heat diffusion, Shupe integral.

All parameters in SI (m, K, s, W, J). The chain is

    chamber T_c(t) --(housing lag)--> housing T_h --> coil outer surface
                                             \\--> spool (lumped) --> coil inner surface
    radial heat diffusion through the M layers  ->  T_j(t), Tdot_j(t) per layer
    winding pattern  ->  fibre segment [z0_j, z1_j] of each layer  ->  weight w_j
    Shupe integral with strain term and T-dependent dn/dT  ->  rate error Omega_E(t)

Non-reciprocal rate error (docs/physics.md 3.2, 3.5; DERIVED there, Shupe 1980, Mohr 1996):

    Omega_E = (n / (L D)) Int_0^L [ (dn/dT(T) + n alpha_f) Tdot + n xi eps_dot ] (L - 2 z) dz     [rad/s]

with D the mean coil diameter, dn/dT(T) = C1 + C2 (T - T0), xi = 1 - (n^2/2)[p12 - nu (p11 + p12)]
and the fibre's mechanical strain rate eps_dot = (alpha_c(r, T) - alpha_f) Tdot, where the
constraining (spool / potting) expansion alpha_c varies linearly with radius from
``constraint_cte_inner`` to ``constraint_cte_outer`` and with temperature by the factor
(1 + ``constraint_cte_tempco`` (T - T0)). In a radial (1-D) model the temperature is
uniform over a layer, so the integral is a sum over layers with weights

    w_j = Int_{layer j} (L - 2 z) dz = l_j (L - z0_j - z1_j)                        [m^2]

Both C2 and the temperature dependence of alpha_c make terms in T x Tdot: that is where the
product regressor of paper 003 comes from physically; nothing here is a formula in the
logged temperature.

Sign convention: z = 0 at port A; heating the half z < L/2 gives a positive rate error
(docs/physics.md 3.2: +135.6 deg/h for the defaults at 1 K/min).

References
----------
D. M. Shupe, Appl. Opt. 19(5) 654 (1980); F. Mohr, J. Lightwave Technol. 14(1) 27 (1996);
docs/physics.md 3.2-3.5 (derivations, default constants, Li et al. COL 13(9) 090603 (2015) materials).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from numbers import Integral

import numpy as np
from gyrobench.sim import units
from gyrobench.sim._validate import number_where as _num
from gyrobench.sim.coil2d import WINDING_PATTERNS, winding_sequence  # their home: the (r, z) coil
from gyrobench.sim.fiber_strain import elasto_optic_factor  # its home: the strain kernels
from numpy.typing import ArrayLike, NDArray
from scipy import linalg

__all__ = [
    "WINDING_PATTERNS",
    "CoilSpec",
    "Winding",
    "ThermalNetwork",
    "CoilThermalModel",
    "ShupeTerms",
    "winding_sequence",
    "elasto_optic_factor",
    "shupe_terms",
    "segment_weight",
]





@dataclass(frozen=True, slots=True, kw_only=True)
class CoilSpec:
    """Fibre coil: geometry, optics, winding, thermal and strain parameters (SI).

    Parameters
    ----------
    length : float
        Fibre length L [m].
    inner_radius, outer_radius : float
        Radii of the wound fibre pack [m]; the mean diameter D = inner + outer radius is
        the Sagnac/Shupe diameter (defaults give D = 0.1 m, docs/physics.md 3.1).
    height : float
        Axial height of the pack [m].
    layers : int
        Number of fibre layers M (one diffusion cell per layer).
    winding : str
        ``"helical"``, ``"dipolar"``, ``"quadrupolar"`` or ``"octupolar"``.
    winding_defect_rms : float
        Relative rms error of each layer's fibre length (crossovers, miscounted turns) [-];
        0 gives the ideal mapping. Drawn by :meth:`realize_winding` with an explicit ``rng``.
    wavelength : float
        Source mean wavelength [m].
    index : float
        Effective refractive index n [-].
    dn_dT : float
        C1, dn/dT at ``dn_dT_ref`` [1/K].
    dn_dT_slope : float
        C2 = d(dn/dT)/dT [1/K^2]. Default 3e-8 /K^2: was calibrated so paper 003's
        point-heating case showed a T x dT term above 0.2 deg/h (docs/physics.md 3.5; about 1.5x the Leviton-Frey
        slope of fused silica, 2.07e-8 over -10..40 degC). Paper 003 now runs on
        :mod:`gyrobench.sim.coil2d`, where this slope comes from material data.
    dn_dT_ref : float
        T0 [K] of the dn/dT expansion and of the strain tempco (273.15 K = 0 degC, so the
        product term is literally C2 T[degC] Tdot).
    fibre_cte : float
        alpha_f [1/K].
    p11, p12, poisson : float
        Photo-elastic constants and Poisson ratio of silica.
    constraint_cte_inner, constraint_cte_outer : float
        Expansion coefficient [1/K] imposed on the fibre at the inner (spool side) and the
        outer layer (potting side); linear in radius in between (unverified, tune).
    constraint_decay_length : float
        lambda_c [m]: alpha_c goes from the inner to the outer value as
        (1 - exp(-(r - r_in)/lambda_c)) / (1 - exp(-(r_out - r_in)/lambda_c)) (the spool's
        grip fades with distance); ``inf`` gives a profile linear in radius.
    constraint_cte_tempco : float
        Relative temperature coefficient of the constraining expansion [1/K]
        (adhesive CTE rises with temperature; unverified).
    conductivity : float
        Effective radial conductivity of the potted pack k [W/m/K].
    volumetric_heat_capacity : float
        rho c of the potted pack [J/m^3/K].
    """

    length: float = 1000.0
    inner_radius: float = 0.0472
    outer_radius: float = 0.0528
    height: float = 0.013
    layers: int = 40
    winding: str = "quadrupolar"
    winding_defect_rms: float = 0.0
    wavelength: float = 1550e-9
    index: float = 1.46
    dn_dT: float = 1.0e-5
    dn_dT_slope: float = 3.0e-8
    dn_dT_ref: float = units.ZERO_CELSIUS
    fibre_cte: float = 5.5e-7
    p11: float = 0.121
    p12: float = 0.270
    poisson: float = 0.17
    constraint_cte_inner: float = 1.2e-5
    constraint_cte_outer: float = 4.0e-6
    constraint_cte_tempco: float = 0.01
    constraint_decay_length: float = math.inf
    conductivity: float = 0.25
    volumetric_heat_capacity: float = 1.6e6

    def __post_init__(self) -> None:
        o = "CoilSpec"
        _num(o, "length", self.length, "> 0", "m", lambda v: v > 0)
        _num(o, "inner_radius", self.inner_radius, "> 0", "m", lambda v: v > 0)
        _num(
            o,
            "outer_radius",
            self.outer_radius,
            f"> inner_radius ({self.inner_radius!r})",
            "m",
            lambda v: v > self.inner_radius,
        )
        _num(o, "height", self.height, "> 0", "m", lambda v: v > 0)
        winding_sequence(self.winding, self.layers)  # validates layers and pattern
        _num(
            o,
            "winding_defect_rms",
            self.winding_defect_rms,
            "in [0, 0.2]",
            "(relative)",
            lambda v: 0 <= v <= 0.2,
        )
        _num(o, "wavelength", self.wavelength, "> 0", "m", lambda v: v > 0)
        _num(o, "index", self.index, ">= 1", "", lambda v: v >= 1)
        for name in (
            "dn_dT",
            "dn_dT_slope",
            "fibre_cte",
            "p11",
            "p12",
            "constraint_cte_inner",
            "constraint_cte_outer",
            "constraint_cte_tempco",
        ):
            _num(o, name, getattr(self, name), "finite", "", lambda v: True)
        if self.constraint_decay_length != math.inf:
            _num(
                o,
                "constraint_decay_length",
                self.constraint_decay_length,
                "> 0 (or inf)",
                "m",
                lambda v: v > 0,
            )
        _num(o, "dn_dT_ref", self.dn_dT_ref, "> 0", "K", lambda v: v > 0)
        _num(o, "poisson", self.poisson, "in [0, 0.5)", "", lambda v: 0 <= v < 0.5)
        _num(o, "conductivity", self.conductivity, "> 0", "W/m/K", lambda v: v > 0)
        _num(
            o,
            "volumetric_heat_capacity",
            self.volumetric_heat_capacity,
            "> 0",
            "J/m^3/K",
            lambda v: v > 0,
        )

    # ------------------------------------------------------------------ geometry
    @property
    def diameter(self) -> float:
        """Mean coil diameter D = r_in + r_out [m]."""
        return self.inner_radius + self.outer_radius

    @property
    def layer_pitch(self) -> float:
        """Radial thickness of one layer [m]."""
        return (self.outer_radius - self.inner_radius) / self.layers

    @property
    def layer_radii(self) -> NDArray[np.float64]:
        """Radius of each layer's centre (inner -> outer) [m]."""
        return np.asarray(self.inner_radius + (np.arange(self.layers) + 0.5) * self.layer_pitch, dtype=np.float64)

    @property
    def diffusivity(self) -> float:
        """a = k / (rho c) [m^2/s]."""
        return self.conductivity / self.volumetric_heat_capacity

    @property
    def xi(self) -> float:
        """Elasto-optic factor xi [-] (0.78 for the defaults)."""
        return elasto_optic_factor(self.index, self.p11, self.p12, self.poisson)

    @property
    def shupe_coefficient(self) -> float:
        """n (dn/dT + n alpha_f) / (L D) at T0 [1/(K m^2)]: Omega_E = this * sum_j w_j Tdot_j."""
        return (
            self.index * (self.dn_dT + self.index * self.fibre_cte) / (self.length * self.diameter)
        )

    def constraint_cte(self) -> NDArray[np.float64]:
        """alpha_c of each layer at T0 [1/K] (inner -> outer; see ``constraint_decay_length``)."""
        lam = self.constraint_decay_length
        s = self.layer_radii - self.inner_radius
        if math.isinf(lam):
            frac = s / (self.outer_radius - self.inner_radius)
        else:
            frac = -np.expm1(-s / lam) / -math.expm1(-(self.outer_radius - self.inner_radius) / lam)
        return (
            self.constraint_cte_inner
            + (self.constraint_cte_outer - self.constraint_cte_inner) * frac
        )

    def realize_winding(self, *, rng: np.random.Generator | None = None) -> Winding:
        """The layer -> fibre mapping of this coil; with ``winding_defect_rms`` > 0 one drawn unit (needs ``rng``)."""
        if self.winding_defect_rms > 0:
            if rng is None:
                raise ValueError(
                    f"CoilSpec.winding_defect_rms = {self.winding_defect_rms!r} > 0 needs an rng to draw the defects"
                )
            return Winding.with_defects(
                self.winding, self.layers, self.length, rms=self.winding_defect_rms, rng=rng
            )
        return Winding.ideal(self.winding, self.layers, self.length)


@dataclass(frozen=True, slots=True, kw_only=True)
class Winding:
    """Which stretch of fibre [z0_j, z1_j] (z from port A) lies in layer j (inner -> outer).

    Symmetric windings (docs/physics.md 3.3) start at the split point z_c (the fibre midpoint
    when ideal): the i-th "A" layer takes the next stretch toward port A,
    [z_c - (a_0 + ... + a_i), z_c - (a_0 + ... + a_{i-1})], the i-th "B" layer the next
    stretch toward port B. Helical: layer j holds [l_0 + ... + l_{j-1}, l_0 + ... + l_j].
    The stretches always tile [0, L], so sum_j w_j = Int_0^L (L - 2z) dz = 0 exactly and a
    uniform Tdot gives no Shupe error whatever the defects.
    """

    pattern: str
    length: float
    z0: NDArray[np.float64]
    z1: NDArray[np.float64]

    @classmethod
    def from_layer_lengths(cls, pattern: str, lengths: ArrayLike) -> Winding:
        """Mapping for given per-layer fibre lengths [m] (their sum is the fibre length)."""
        lengths = np.asarray(lengths, dtype=float)
        if lengths.ndim != 1 or not np.all(np.isfinite(lengths)) or np.any(lengths <= 0):
            raise ValueError(
                f"layer lengths must be a 1-D array of finite values > 0 m; got {lengths!r}"
            )
        seq = winding_sequence(pattern, len(lengths))
        L = float(lengths.sum())
        z0 = np.empty_like(lengths)
        if seq is None:
            z0[:] = np.concatenate([[0.0], np.cumsum(lengths)[:-1]])
        else:
            is_a = np.array([c == "A" for c in seq])
            zc = float(lengths[is_a].sum())
            a_cum = np.cumsum(
                np.where(is_a, lengths, 0.0)
            )  # A fibre used up to and including layer j
            b_cum = np.cumsum(np.where(is_a, 0.0, lengths))
            z0[:] = np.where(is_a, zc - a_cum, zc + b_cum - lengths)
        return cls(pattern=pattern, length=L, z0=z0, z1=z0 + lengths)

    @classmethod
    def ideal(cls, pattern: str, layers: int, length: float) -> Winding:
        """Equal fibre length L / M per layer."""
        winding_sequence(pattern, layers)
        _num("Winding", "length", length, "> 0", "m", lambda v: v > 0)
        return cls.from_layer_lengths(pattern, np.full(layers, length / layers))

    @classmethod
    def with_defects(
        cls, pattern: str, layers: int, length: float, *, rms: float, rng: np.random.Generator
    ) -> Winding:
        """Layer lengths L/M (1 + e_j), e_j ~ N(0, rms^2), rescaled to total L.

        Models miscounted turns and crossovers: the A and B halves no longer meet at L/2
        and symmetric layer pairs no longer mirror each other (the "effective asymmetric
        length" of docs/physics.md 3.3).
        """
        winding_sequence(pattern, layers)
        _num("Winding", "rms", rms, "in [0, 0.2]", "(relative)", lambda v: 0 <= v <= 0.2)
        if not isinstance(rng, np.random.Generator):
            raise TypeError(f"rng must be a numpy.random.Generator; got {type(rng).__name__}")
        e = np.clip(rms * rng.standard_normal(layers), -0.5, 0.5)
        lengths = (length / layers) * (1.0 + e)
        return cls.from_layer_lengths(pattern, lengths * (length / lengths.sum()))

    @property
    def layers(self) -> int:
        return len(self.z0)

    @property
    def weights(self) -> NDArray[np.float64]:
        """w_j = Int_{z0_j}^{z1_j} (L - 2z) dz = (z1 - z0)(L - z0 - z1) [m^2]."""
        return (self.z1 - self.z0) * (self.length - self.z0 - self.z1)


def segment_weight(length: float, z_center: float, seg_length: float) -> float:
    """Shupe weight Int (L - 2z) dz of a fibre stretch of ``seg_length`` centred at ``z_center`` [m^2]."""
    return seg_length * (length - 2.0 * z_center)


# ======================================================================================
# Heat diffusion
# ======================================================================================


@dataclass(frozen=True)
class ThermalNetwork:
    """Linear lumped/finite-volume thermal model dx/dt = A x + b u(t) and its time stepping.

    Parameters
    ----------
    A : ndarray, shape (m, m)
        System matrix [1/s].
    b : ndarray, shape (m,)
        Input vector [1/s] for the scalar driving temperature u [K].

    Notes
    -----
    Implicit (backward Euler, L-stable, first order):
        (I - dt A) x_{k+1} = x_k + dt b u_{k+1}
    Crank-Nicolson (A-stable, second order; may ring for dt >> cell time constants):
        (I - dt/2 A) x_{k+1} = (I + dt/2 A) x_k + dt/2 b (u_k + u_{k+1})
    The left matrix is LU-factorized once (``scipy.linalg.lu_factor``) and the one-step
    propagator x_{k+1} = P x_k + q0 u_k + q1 u_{k+1} is precomputed, so a step is one
    small matrix-vector product. Both schemes reproduce the quasi-steady ramp solution
    exactly (a linear ramp has no truncation error in the difference quotient).
    """

    A: NDArray[np.float64]
    b: NDArray[np.float64]

    def propagator(self, dt: float, scheme: str = "implicit"):
        """(P, q0, q1) of one step of ``dt`` [s] for ``scheme`` in {"implicit", "crank-nicolson"}."""
        _num("ThermalNetwork", "dt", dt, "> 0", "s", lambda v: v > 0)
        m = len(self.b)
        eye = np.eye(m)
        if scheme == "implicit":
            lu = linalg.lu_factor(eye - dt * self.A)
            P = linalg.lu_solve(lu, eye)
            return P, np.zeros(m), linalg.lu_solve(lu, dt * self.b)
        if scheme == "crank-nicolson":
            lu = linalg.lu_factor(eye - 0.5 * dt * self.A)
            P = linalg.lu_solve(lu, eye + 0.5 * dt * self.A)
            q = linalg.lu_solve(lu, 0.5 * dt * self.b)
            return P, q, q.copy()
        raise ValueError(f"scheme must be 'implicit' or 'crank-nicolson'; got {scheme!r}")

    def steady_state(self, u: float) -> NDArray[np.float64]:
        """x with A x + b u = 0 [K]."""
        return np.asarray(np.linalg.solve(self.A, -self.b * u), dtype=np.float64)

    def simulate(
        self, u: ArrayLike, dt: float, *, x0: ArrayLike | None = None, scheme: str = "implicit"
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """States and their time derivatives at the samples of ``u`` (spacing ``dt``).

        Parameters
        ----------
        u : array_like, shape (n,)
            Driving temperature at t_k = k dt [K].
        dt : float
            Step [s].
        x0 : array_like, optional
            Initial state [K]; default the steady state for u[0].
        scheme : {"implicit", "crank-nicolson"}

        Returns
        -------
        x : ndarray, shape (n, m)
            Temperatures [K].
        xdot : ndarray, shape (n, m)
            dx/dt = A x + b u at each sample [K/s].
        """
        u = np.asarray(u, dtype=float)
        if u.ndim != 1 or len(u) < 1 or not np.all(np.isfinite(u)):
            raise ValueError(
                f"u must be a finite 1-D array with at least one sample; got shape {u.shape}"
            )
        P, q0, q1 = self.propagator(dt, scheme)
        x = np.empty((len(u), len(self.b)))
        x[0] = self.steady_state(u[0]) if x0 is None else np.asarray(x0, dtype=float)
        # Affine step x_{k+1} = P x_k + q0 u_k + q1 u_{k+1}; forcing precomputed in one go.
        forcing = np.outer(u[:-1], q0) + np.outer(u[1:], q1)
        for k in range(len(u) - 1):
            x[k + 1] = P @ x[k] + forcing[k]
        xdot = x @ self.A.T + np.outer(u, self.b)
        return x, xdot


def slab_network(
    n_cells: int,
    thickness: float,
    diffusivity: float,
    *,
    geometry: str = "slab",
    inner_radius: float = 1.0,
) -> ThermalNetwork:
    """Finite-volume conduction through ``n_cells`` cells, both faces tied to the input u (Dirichlet).

    For tests against analytic solutions: ``geometry="slab"`` (plane wall of ``thickness``
    [m]) or ``"cylinder"`` (annulus from ``inner_radius`` to ``inner_radius + thickness``).
    Conductances between cell centres are exact for the geometry (k A / dx, or
    2 pi k / ln(r2/r1) per unit height); a face is half a cell away from its cell centre.
    """
    if isinstance(n_cells, bool) or not isinstance(n_cells, Integral) or n_cells < 1:
        raise ValueError(f"n_cells must be an integer >= 1; got {n_cells!r}")
    faces = inner_radius + np.linspace(0.0, thickness, n_cells + 1)
    centres = 0.5 * (faces[:-1] + faces[1:])
    return _chain(faces, centres, diffusivity, geometry)


def _chain(faces, centres, a, geometry):
    """A, b of a cell chain whose two faces are held at u; unit conductivity, capacity 1/a."""
    m = len(centres)
    if geometry == "slab":
        cap = np.diff(faces) / a
        g_int = 1.0 / np.diff(centres)
        g_in, g_out = 1.0 / (centres[0] - faces[0]), 1.0 / (faces[-1] - centres[-1])
    elif geometry == "cylinder":
        cap = 0.5 * np.diff(faces**2) / a
        g_int = 1.0 / np.log(centres[1:] / centres[:-1])
        g_in, g_out = 1.0 / np.log(centres[0] / faces[0]), 1.0 / np.log(faces[-1] / centres[-1])
    else:
        raise ValueError(f"geometry must be 'slab' or 'cylinder'; got {geometry!r}")
    K = np.zeros((m, m))
    for j, g in enumerate(g_int):
        K[j, j] += g
        K[j + 1, j + 1] += g
        K[j, j + 1] -= g
        K[j + 1, j] -= g
    K[0, 0] += g_in
    K[-1, -1] += g_out
    bvec = np.zeros(m)
    bvec[0] += g_in
    bvec[-1] += g_out
    return ThermalNetwork(A=-K / cap[:, None], b=bvec / cap)


@dataclass(frozen=True, slots=True, kw_only=True)
class CoilThermalModel:
    """Thermal network of the coil in its housing, driven by the chamber temperature.

    State x = [T_housing, T_spool, T_layer_0 (inner) ... T_layer_{M-1} (outer)] [K].

    - Housing (lumped, first order; unaffected by the coil):
      tau_h dT_h/dt = T_chamber - T_h.
    - Spool (lumped aluminium, heat capacity C_s): C_s dT_s/dt = G_sh (T_h - T_s) + G_in (T_0 - T_s).
    - Layers: cylindrical finite volumes of the potted pack (conductivity k, rho c), one
      per fibre layer; the inner face is in contact with the spool, the outer face
      exchanges heat with the housing through a film coefficient h_out:
      rho c dT/dt = k (d2T/dr2 + (1/r) dT/dr) (docs/physics.md 3.4).

    Parameters
    ----------
    housing_time_constant : float
        tau_h [s] (docs/physics.md 3.4: 10-30 min, unverified).
    spool_heat_capacity : float
        C_s [J/K] (an aluminium hub of ~25 g: 2740 * 896 * 1e-5 m^3 ~ 25 J/K).
    spool_housing_conductance : float
        G_sh [W/K] through the mounting flange.
    outer_film_coefficient : float
        h_out [W/m^2/K] between the outer surface and the housing.
    """

    coil: CoilSpec = field(default_factory=CoilSpec)
    housing_time_constant: float = 1200.0
    spool_heat_capacity: float = 25.0
    spool_housing_conductance: float = 0.05
    outer_film_coefficient: float = 10.0

    def __post_init__(self) -> None:
        o = "CoilThermalModel"
        if not isinstance(self.coil, CoilSpec):
            raise TypeError(f"{o}.coil must be a CoilSpec; got {type(self.coil).__name__}")
        _num(o, "housing_time_constant", self.housing_time_constant, "> 0", "s", lambda v: v > 0)
        _num(o, "spool_heat_capacity", self.spool_heat_capacity, "> 0", "J/K", lambda v: v > 0)
        _num(
            o,
            "spool_housing_conductance",
            self.spool_housing_conductance,
            "> 0",
            "W/K",
            lambda v: v > 0,
        )
        _num(
            o,
            "outer_film_coefficient",
            self.outer_film_coefficient,
            "> 0",
            "W/m^2/K",
            lambda v: v > 0,
        )

    def network(self) -> ThermalNetwork:
        """The linear system dx/dt = A x + b T_chamber."""
        c = self.coil
        M = c.layers
        H, k = c.height, c.conductivity
        faces = c.inner_radius + np.arange(M + 1) * c.layer_pitch
        r = c.layer_radii
        cap_layers = c.volumetric_heat_capacity * math.pi * np.diff(faces**2) * H  # [J/K]
        g_int = 2 * math.pi * k * H / np.log(r[1:] / r[:-1])  # [W/K]
        g_in = 2 * math.pi * k * H / math.log(r[0] / c.inner_radius)
        g_half_out = 2 * math.pi * k * H / math.log(c.outer_radius / r[-1])
        g_film = self.outer_film_coefficient * 2 * math.pi * c.outer_radius * H
        g_out = 1.0 / (1.0 / g_half_out + 1.0 / g_film)

        m = M + 2
        K = np.zeros((m, m))  # conductance matrix (rows: heat balance of each node) [W/K]

        def link(i, j, g):
            K[i, i] += g
            K[j, j] += g
            K[i, j] -= g
            K[j, i] -= g

        link(1, 0, self.spool_housing_conductance)
        link(1, 2, g_in)
        for j, g in enumerate(g_int):
            link(2 + j, 3 + j, g)
        link(2 + M - 1, 0, g_out)
        cap = np.concatenate([[1.0], [self.spool_heat_capacity], cap_layers])
        A = -K / cap[:, None]
        # the housing is a large body: its temperature follows the chamber only
        A[0, :] = 0.0
        A[0, 0] = -1.0 / self.housing_time_constant
        b = np.zeros(m)
        b[0] = 1.0 / self.housing_time_constant
        return ThermalNetwork(A=A, b=b)

    def check_step(
        self, dt: float, chamber_rate_max: float, *, max_step_temperature: float = 0.5
    ) -> None:
        """Refuse a step the diffusion model cannot resolve.

        Raises
        ------
        ValueError
            If dt > tau_h / 10 (the housing lag, the fastest external dynamics, would be
            stepped over), or if the chamber changes by more than ``max_step_temperature``
            [K] within one step (|rate| dt).
        """
        _num("CoilThermalModel", "dt", dt, "> 0", "s", lambda v: v > 0)
        if dt > self.housing_time_constant / 10:
            raise ValueError(
                f"thermal step dt = {dt!r} s cannot resolve the housing time constant "
                f"{self.housing_time_constant!r} s; need dt <= tau_h / 10 = {self.housing_time_constant / 10:g} s"
            )
        step = abs(chamber_rate_max) * dt
        if step > max_step_temperature:
            raise ValueError(
                f"chamber rate {abs(chamber_rate_max) * 60:g} K/min changes the temperature by {step:g} K per "
                f"diffusion step of {dt:g} s; at most {max_step_temperature:g} K per step is resolved: "
                f"use dt <= {max_step_temperature / abs(chamber_rate_max):.3g} s or a slower ramp"
            )


# ======================================================================================
# Shupe integral
# ======================================================================================


@dataclass(frozen=True, slots=True)
class ShupeTerms:
    """Rate-error components [rad/s] of the non-reciprocal phase, one value per time sample.

    ``shupe``: (n/(L D)) sum_j w_j (C1 + n alpha_f) Tdot_j  (classic Shupe, constant dn/dT);
    ``dndT_product``: (n/(L D)) sum_j w_j C2 (T_j - T0) Tdot_j  (T x dT from dn/dT(T));
    ``strain``: (n/(L D)) sum_j w_j n xi (alpha_c_j (1 + kappa (T_j - T0)) - alpha_f) Tdot_j;
    ``strain_product``: the part of ``strain`` proportional to kappa (T x dT from alpha_c(T)).
    """

    shupe: NDArray[np.float64]
    dndT_product: NDArray[np.float64]
    strain: NDArray[np.float64]
    strain_product: NDArray[np.float64]

    @property
    def total(self) -> NDArray[np.float64]:
        """Sum of all non-reciprocal terms [rad/s] (``strain_product`` is inside ``strain``)."""
        return self.shupe + self.dndT_product + self.strain

    @property
    def product(self) -> NDArray[np.float64]:
        """Everything proportional to T x Tdot [rad/s]."""
        return self.dndT_product + self.strain_product


def shupe_terms(
    coil: CoilSpec,
    weights: ArrayLike,
    T: ArrayLike,
    Tdot: ArrayLike,
    *,
    constraint_cte: ArrayLike | None = None,
) -> ShupeTerms:
    """Non-reciprocal rate error of fibre stretches with weights w_j, temperatures T_j, rates Tdot_j.

    Parameters
    ----------
    coil : CoilSpec
        Optical, thermo-optic and strain constants (L, D, n, C1, C2, T0, alpha_f, xi, kappa).
    weights : array_like, shape (m,)
        w_j = Int_j (L - 2z) dz [m^2] (:attr:`Winding.weights`, :func:`segment_weight`).
    T, Tdot : array_like, shape (n, m) or (m,)
        Temperature [K] and its rate [K/s] of each stretch at each time.
    constraint_cte : array_like, shape (m,), optional
        alpha_c of each stretch at T0 [1/K]; default :meth:`CoilSpec.constraint_cte`
        (requires m = layers). Pass zeros for a free (unstrained) fibre.

    Returns
    -------
    ShupeTerms
        Components [rad/s], shape (n,) (or scalars for 1-D input).

    Notes
    -----
    Omega_E = (n/(L D)) sum_j w_j [(C1 + C2 (T_j - T0) + n alpha_f) Tdot_j
    + n xi (alpha_c_j (1 + kappa (T_j - T0)) - alpha_f) Tdot_j]  (docs/physics.md 3.2, 3.5).
    """
    w = np.asarray(weights, dtype=float)
    T = np.asarray(T, dtype=float)
    Tdot = np.asarray(Tdot, dtype=float)
    if T.shape != Tdot.shape or T.shape[-1] != len(w):
        raise ValueError(
            f"T {T.shape} and Tdot {Tdot.shape} must both end in the number of weights {len(w)}"
        )
    if constraint_cte is None:
        if len(w) != coil.layers:
            raise ValueError(
                f"constraint_cte must be given for {len(w)} stretches (the default is per layer, {coil.layers})"
            )
        ac = coil.constraint_cte()
    else:
        ac = np.asarray(constraint_cte, dtype=float).reshape(len(w))
    n = coil.index
    pre = n / (coil.length * coil.diameter)
    dT0 = T - coil.dn_dT_ref
    wt = Tdot * w
    shupe = pre * (coil.dn_dT + n * coil.fibre_cte) * wt.sum(axis=-1)
    prod = pre * coil.dn_dT_slope * (dT0 * wt).sum(axis=-1)
    nxi = n * coil.xi
    strain = (
        pre
        * nxi
        * (wt * (ac * (1.0 + coil.constraint_cte_tempco * dT0) - coil.fibre_cte)).sum(axis=-1)
    )
    strain_prod = pre * nxi * coil.constraint_cte_tempco * (wt * ac * dT0).sum(axis=-1)
    return ShupeTerms(shupe=shupe, dndT_product=prod, strain=strain, strain_product=strain_prod)
