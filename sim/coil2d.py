"""Fibre coil in (r, z): axisymmetric heat flow, winding map, thermo-elastic strain, Shupe map.

All parameters in SI (m, K, s, W, J, Pa). The chain is

    chamber T_c(t) --(convection h_ch A_h)--> housing (lumped, C_h)
        --(gas gap h_gap on the outer and end faces; contact h_c under the spool)-->
    finite-volume (r, z) grid: spool | fibre pack (anisotropic k_r, k_z) | potting skin
        -> node temperatures T(t) and exact rates Tdot(t) (first-order-hold matrix exponential)
    winding map: every turn of fibre -> (r, z, s along the fibre, ds)
    composite-cylinder strain -> beta_T(r, T) of each turn
    Shupe functional as a LINEAR map on node rates plus one bilinear T x Tdot form:

        Omega_E(t) = (n/(L D)) [ Tdot(t) . W0  +  (T(t) - T0) . Q Tdot(t) ]            [rad/s]

    (beta_T as its chord over [t_lo, t_hi] written about T0 = ``t_ref``: the sum is the same
    for any T0, temperature unit or origin; only the split between the two terms moves)

        W0 = P^T (w * beta_0),   Q = P^T diag(w * beta_1) P,   w_i = ds_i (L - 2 s_i)  [m^2]

with P the bilinear interpolation from the cell centres to the turns (exact for a field
linear in r and z), beta_T(r, T) = beta_0(r) + beta_1(r) (T - T0) the phase coefficient of a
fibre bonded into the pack (docs/physics.md 3.7):

    beta_T = dn/dT(T) + n alpha_f(T) + n xi (d eps_theta/dT (r, T) - alpha_f(T))            [1/K]

dn/dT(T) from the Leviton & Frey (2006) temperature-dependent Sellmeier fit of fused silica;
the expansion coefficients from :data:`SILICA`, :data:`ALUMINIUM`, :data:`EPOXY` (values
and their temperature slopes with sources there); d eps_theta/dT from the plane-stress
composite cylinder (isotropic spool + cylindrically orthotropic pack, Lekhnitskii) with the
CTEs evaluated at T. beta_1 is the secant slope of beta_T over [``t_lo``, ``t_hi``]:
NOTHING in the T x Tdot term is a free constant.

Stated simplifications: axisymmetric (the in-layer crossover sector and the lead routing
are smeared over the circumference; for the Shupe integral this is exact, since in an
axisymmetric temperature field a fibre element's temperature does not depend on its azimuth,
but heat paths that break the symmetry, e.g. a bolt pattern or a cable exit, are not
represented); the strain follows the local temperature with the
uniform-temperature coefficient d eps_theta/dT (quasi-static, no stress from gradients);
plane stress in the pack (free end faces), no potting skin or housing in the elastic model;
moduli independent of temperature; no flanges.

References
----------
D. M. Shupe, Appl. Opt. 19(5) 654 (1980); F. Mohr, J. Lightwave Technol. 14(1) 27 (1996);
D. B. Leviton, B. J. Frey, Proc. SPIE 6273, 62732K (2006); S. G. Lekhnitskii, Anisotropic
Plates (1968), cylindrically anisotropic disc; R. A. Schapery, J. Compos. Mater. 2, 380
(1968) (composite CTEs); J. C. Halpin, J. L. Kardos, Polym. Eng. Sci. 16, 344 (1976);
J. C. Maxwell (1873) / L. N. McCartney, composite conductivity; S. Timoshenko,
J. N. Goodier, Theory of Elasticity (1951), compound cylinders; docs/physics.md 3.7.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.base import units
from gyrobench.base.ranges import Constraint, FieldChoice, FieldRange, ordered, validate
from gyrobench.base.validate import number_where as _num
from gyrobench.sim.coil_heat import Grid, _modal_states, fv_grid
from gyrobench.sim.coil_materials import ACRYLATE, ALUMINIUM, EPOXY, SILICA, T_REF, Material, silica_dn_dT
from gyrobench.sim.coil_pack import PackProperties, composite_cylinder_strain, pack_properties
from gyrobench.sim.coil_winding import WINDING_PATTERNS, FibreMap, Imperfections, fibre_map, winding_sequence
from gyrobench.sim.fiber_strain import elasto_optic_factor

__all__ = [
    "Coil2DSpec",
    "Coil2D",
    "ThermalRun",
    "heated_stretch",
]


@dataclass(frozen=True, slots=True, kw_only=True)
class Coil2DSpec:
    """A potted fibre coil on an aluminium spool in a housing (SI); defaults: a 1 km nav-grade coil.

    Parameters
    ----------
    inner_radius, outer_radius, height : float
        Fibre pack r_i, r_o and axial height H [m] (D ~ 0.1 m, as sim/coil.py).
    layers, turns_per_layer : int
        M layers of N turns: layer j holds N 2 pi r_j of fibre (length proportional to its
        radius); L = N 2 pi sum r_j (+ crossovers and leads) = 1005 m for the defaults.
    winding : str
        ``"helical"``, ``"dipolar"``, ``"quadrupolar"``, ``"octupolar"``.
    bore_radius : float
        Spool bore [m]; the spool is the annulus bore..r_i over the full height.
    skin : float
        Potting skin over the outer and end faces of the pack [m] (stated: 0.5 mm).
    packing, glass_fraction, interlayer_fraction : float
        Coated-fibre volume fraction phi (0.80, stated: quadrupolar packs ~0.8-0.9),
        (80 um / 135 um)^2 = 0.351 (reduced-cladding PM fibre), resin interlayer t_l/p (0.1,
        stated).
    spool, matrix, coating, glass : Material
    index : float
        Effective index n of the guided mode (1.46 as sim/coil.py).
    p11, p12 : float
        Photo-elastic constants of silica (0.121, 0.270; docs/physics.md 3.5).
    wavelength : float
        [m].
    crossover_turns : float
        Fibre length of each layer-to-layer crossover, in turns of its radius (0.5, stated).
    lead_length : float
        Fibre lead from each end of the pack to the coupler [m] (0.5, stated), in the skin
        at the top outer corner.
    lead_difference_rms : float
        rms of a drawn unit's lead A - lead B length (fibre-midpoint error plus pigtail
        routing) [m]. CALIBRATED: 1.0 m sets the median peak drift of drawn units under
        paper 003's validation-1 program (10 degC/h, -10 -> 40 degC) to ~0.15 deg/h, the
        level the paper quotes for a 10 degC change; it is the dominant drift source of a
        drawn quadrupolar unit (0.20 deg/h per m of asymmetry in that program).
    housing_heat_capacity : float
        C_h [J/K] (0.5 kg of aluminium: 450 J/K, stated).
    chamber_conductance : float
        h_ch A_h between chamber air and housing [W/K] (0.375: 12.5 W/(m^2 K) over 0.03 m^2,
        the top of Cengel's free-convection range for gases, 2-25 W/(m^2 K), a slow chamber
        fan; tau_h = C_h/G = 1200 s as sim/coil.py; ASSUMED, effect measured in
        docs/physics.md 9).
    gap_coefficient : float
        h_gap [W/(m^2 K)] of the gas gap between the coil's outer/end/bore faces and the
        housing (10 = k_air/delta for a still-air gap delta = 2.6 mm, k_air 0.026 W/(m K),
        radiation neglected; ASSUMED gap, effect measured in docs/physics.md 9).
    mount_coefficient : float
        h_c [W/(m^2 K)] of the bolted spool-to-housing contact under the spool (bottom face of
        the spool only: the asymmetric mount makes axial gradients) (1000; ASSUMED bolted
        Al-Al joint, effect measured in docs/physics.md 9: none within 0.1 %).
    t_ref, t_lo, t_hi : float
        T0 of the expansion beta_T = beta_0 + beta_1 (T - T0) and the secant range of beta_1
        [K] (15 degC; -10 and 40 degC, paper 003's range). beta_T is the chord over
        [t_lo, t_hi], so T0 moves only the split between the Tdot and T x Tdot terms, never
        their sum (any T0 >= 0 K is accepted: 0 K is the kelvin origin).
    grid_spool, grid_pack_r, grid_pack_z : int
        Cells across the spool, the pack radially and the pack axially (one skin cell each).
    turn_error_probability : float
        Probability that a layer gains one turn, and again that it loses one, at a layer change
        (:class:`Imperfections`; 0.15 stated, in [0, 0.5]).
    radius_error_rms : float
        rms radial displacement of a layer as a fraction of the layer pitch (0.03 stated: tension
        variation).
    matrix_cte_spread : float
        Relative 1-sigma unit-to-unit spread of the potting matrix's expansion coefficient
        (:meth:`realize`; 0.15 stated).
    sensor_z_center : float
        Centre of the logged sensor's axial position on the outer potting surface, as a fraction
        of the half height in [-1, 1]; a unit's sensor is drawn uniformly within
        ``1 - |sensor_z_center|`` of it, so it stays on the surface (0: uniform over the whole
        height, stated).
    """

    inner_radius: float = 0.0472
    outer_radius: float = 0.0528
    height: float = 0.013
    layers: int = 40
    turns_per_layer: int = 80
    winding: str = "quadrupolar"
    bore_radius: float = 0.035
    skin: float = 0.5e-3
    packing: float = 0.80
    glass_fraction: float = (80.0 / 135.0) ** 2
    interlayer_fraction: float = 0.1
    spool: Material = ALUMINIUM
    matrix: Material = EPOXY
    coating: Material = ACRYLATE
    glass: Material = SILICA
    index: float = 1.46
    p11: float = 0.121
    p12: float = 0.270
    wavelength: float = 1550e-9
    crossover_turns: float = 0.5
    lead_length: float = 0.5
    lead_difference_rms: float = 1.0
    housing_heat_capacity: float = 450.0
    chamber_conductance: float = 0.375
    gap_coefficient: float = 10.0
    mount_coefficient: float = 1000.0
    t_ref: float = units.ZERO_CELSIUS + 15.0
    t_lo: float = units.ZERO_CELSIUS - 10.0
    t_hi: float = units.ZERO_CELSIUS + 40.0
    grid_spool: int = 3
    grid_pack_r: int = 8
    grid_pack_z: int = 8
    turn_error_probability: float = 0.15
    radius_error_rms: float = 0.03
    matrix_cte_spread: float = 0.15
    sensor_z_center: float = 0.0

    RANGES: ClassVar[Mapping[str, FieldRange | FieldChoice]] = {
        "inner_radius": FieldRange(0, math.inf, "m", "inner radius of the fibre pack (> bore_radius)", low_open=True),
        "outer_radius": FieldRange(0, math.inf, "m", "outer radius of the fibre pack (> inner_radius)", low_open=True),
        "height": FieldRange(0, math.inf, "m", "axial height of the pack", low_open=True),
        "layers": FieldRange(1, math.inf, "layers", "a multiple of the winding's period", integer=True),
        "turns_per_layer": FieldRange(2, math.inf, "turns", "turns across one layer (>= 2 cells)", integer=True),
        "winding": FieldChoice(tuple(WINDING_PATTERNS), "the layer pattern of the two fibre halves"),
        "bore_radius": FieldRange(0, math.inf, "m", "radius of the spool's bore", low_open=True),
        "skin": FieldRange(0, math.inf, "m", "thickness of the pack's skin cell", low_open=True),
        "packing": FieldRange(0, 1, "1", "fibre packing fraction (coil_pack.pack_properties bounds it)"),
        "glass_fraction": FieldRange(0, 1, "1", "glass share of a coated fibre's section"),
        "interlayer_fraction": FieldRange(0, 1, "1", "interlayer share of the pack"),
        "index": FieldRange(1, math.inf, "1", "fibre group index, >= 1"),
        "p11": FieldRange(-math.inf, math.inf, "1", "Pockels elasto-optic coefficient p11 of silica"),
        "p12": FieldRange(-math.inf, math.inf, "1", "Pockels elasto-optic coefficient p12 of silica"),
        "wavelength": FieldRange(0, math.inf, "m", "source wavelength", low_open=True),
        "crossover_turns": FieldRange(0, math.inf, "turns", "turns of each layer crossover, >= 0"),
        "lead_length": FieldRange(0, math.inf, "m", "fibre lead length, >= 0"),
        "lead_difference_rms": FieldRange(0, math.inf, "m", "rms length difference of the two leads, >= 0"),
        "turn_error_probability": FieldRange(0, 0.5, "1", "a layer's chance of one turn gained (and of one lost)"),
        "radius_error_rms": FieldRange(0, math.inf, "1", "layer radial displacement rms, a fraction of the pitch"),
        "matrix_cte_spread": FieldRange(0, math.inf, "1", "unit-to-unit relative spread of the potting's CTE"),
        "sensor_z_center": FieldRange(-1, 1, "1", "the sensor's mean axial position, a fraction of the half height"),
        "housing_heat_capacity": FieldRange(0, math.inf, "J/K", "housing heat capacity", low_open=True),
        "chamber_conductance": FieldRange(0, math.inf, "W/K", "chamber-housing conductance", low_open=True),
        "gap_coefficient": FieldRange(0, math.inf, "W/(m^2 K)", "spool-pack gap heat transfer", low_open=True),
        "mount_coefficient": FieldRange(0, math.inf, "W/(m^2 K)", "spool mount heat transfer", low_open=True),
        "t_ref": FieldRange(0, 1000, "K", "T0 of the expansion beta_T (0 K is the kelvin origin)"),
        "t_lo": FieldRange(30, 330, "K", "low end of beta_1's secant range (< t_hi)", low_open=True),
        "t_hi": FieldRange(30, 330, "K", "high end of beta_1's secant range (silica dn/dT fit)", low_open=True),
        "grid_spool": FieldRange(2, math.inf, "cells", "cells across the spool", integer=True),
        "grid_pack_r": FieldRange(2, math.inf, "cells", "cells across the pack radially", integer=True),
        "grid_pack_z": FieldRange(2, math.inf, "cells", "cells across the pack axially", integer=True),
    }
    #: the radii nest and the secant range is ordered
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        ordered("bore_radius", "inner_radius", unit="m"),
        ordered("inner_radius", "outer_radius", unit="m"),
        ordered("t_lo", "t_hi", unit="K"),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above (and the four Materials' types)
        winding_sequence(self.winding, self.layers)  # the layer count is a multiple of the pattern's period
        pack_properties(  # the pack's fractions give a physical composite
            packing=self.packing,
            glass_fraction=self.glass_fraction,
            interlayer_fraction=self.interlayer_fraction,
        )

    @property
    def layer_pitch(self) -> float:
        """Radial pitch p_r = (r_o - r_i)/M [m]."""
        return (self.outer_radius - self.inner_radius) / self.layers

    @property
    def xi(self) -> float:
        """Elasto-optic factor xi = 1 - (n^2/2)[p12 - nu (p11 + p12)] [-]."""
        return elasto_optic_factor(self.index, self.p11, self.p12, self.glass.poisson)

    def pack(self, T: float = T_REF) -> PackProperties:
        """Effective pack properties at temperature T [K] (:func:`pack_properties`)."""
        return pack_properties(
            packing=self.packing,
            glass_fraction=self.glass_fraction,
            interlayer_fraction=self.interlayer_fraction,
            T=T,
            glass=self.glass,
            coating=self.coating,
            matrix=self.matrix,
        )

    def hoop_strain_rate(self, r: ArrayLike, T: float) -> NDArray[np.float64]:
        """d eps_theta/dT [1/K] of the pack at radii r with all CTEs taken at T [K]."""
        eps, _ = composite_cylinder_strain(
            r,
            bore=self.bore_radius,
            inner=self.inner_radius,
            outer=self.outer_radius,
            spool_E=self.spool.youngs_modulus,
            spool_nu=self.spool.poisson,
            spool_alpha=float(self.spool.alpha(T)),
            pack=self.pack(T),
        )
        return eps

    def beta(
        self, r: ArrayLike, T: float, *, bonded: ArrayLike | bool = True
    ) -> NDArray[np.float64]:
        """beta_T(r, T) = dn/dT + n alpha_f + n xi (d eps_theta/dT - alpha_f) [1/K].

        Where not ``bonded`` (leads): the free fibre, dn/dT + n alpha_f.
        """
        r = np.asarray(r, dtype=float)
        a_f = float(self.glass.alpha(T))
        n = self.index
        free = float(silica_dn_dT(T, self.wavelength)) + n * a_f
        bonded = np.broadcast_to(np.asarray(bonded, bool), r.shape)
        rr = np.clip(r, self.inner_radius, self.outer_radius)
        mech = n * self.xi * (self.hoop_strain_rate(rr, T) - a_f)
        return free + np.where(bonded, mech, 0.0)

    def beta_coefficients(self, r: ArrayLike, bonded: ArrayLike | bool = True, *, t_ref: float | None = None):
        """(beta_0, beta_1) of the chord of beta_T over [t_lo, t_hi], split about ``t_ref``.

        beta_T(T) is represented by its chord (secant) over the material data's range,
        beta_T(T) ~ beta_T(t_lo) + beta_1 (T - t_lo), beta_1 the secant slope [1/K^2]; written
        about a reference T_ref it is beta_0 + beta_1 (T - T_ref) with beta_0 = the chord at
        T_ref [1/K] (``t_ref`` None: the spec's ``t_ref``). The drift (n/(L D)) [Tdot . W0 +
        (T - T_ref) . Q Tdot] is then the same for every T_ref, in any temperature unit or
        origin; only its split between the Tdot and the T x Tdot terms moves with T_ref
        (the Tdot term by beta_1 (T_ref' - T_ref) . Tdot). beta_0 is the chord, not beta_T at
        t_ref itself: that is 0.2-0.9 % above the chord at 15 degC (the chord's curvature
        error) and would make the sum depend on T_ref at that order.
        """
        t0 = self.t_ref if t_ref is None else float(t_ref)
        lo = self.beta(r, self.t_lo, bonded=bonded)
        b1 = (self.beta(r, self.t_hi, bonded=bonded) - lo) / (self.t_hi - self.t_lo)
        return lo + b1 * (t0 - self.t_lo), b1

    def realize(self, *, rng: np.random.Generator) -> Coil2D:
        """One drawn unit: potting properties and winding imperfections (:class:`Imperfections`).

        Potting spreads (stated, typical batch-to-batch and cure variation; none from a paper):
        matrix CTE x (1 + ``matrix_cte_spread`` N(0, 1)) (0.15 by default), matrix modulus x exp(0.3 N(0, 1)), matrix
        conductivity x (1 + 0.1 N(0, 1)), packing + 0.03 N(0, 1) clipped to [0.6, 0.9],
        interlayer fraction uniform in [0.05, 0.2].
        """
        import dataclasses

        if not isinstance(rng, np.random.Generator):
            raise TypeError(f"rng must be a numpy.random.Generator; got {type(rng).__name__}")
        m = self.matrix
        matrix = dataclasses.replace(
            m,
            cte=m.cte * (1 + self.matrix_cte_spread * rng.standard_normal()),
            youngs_modulus=m.youngs_modulus * math.exp(0.3 * rng.standard_normal()),
            conductivity=m.conductivity * (1 + 0.1 * rng.standard_normal()),
        )
        spec = dataclasses.replace(
            self,
            matrix=matrix,
            packing=float(np.clip(self.packing + 0.03 * rng.standard_normal(), 0.6, 0.9)),
            interlayer_fraction=float(rng.uniform(0.05, 0.2)),
        )
        return Coil2D(spec=spec, imperfections=Imperfections.draw(self, rng=rng))



@dataclass(frozen=True, slots=True)
class ThermalRun:
    """One chamber program on the coarse thermal step (SI).

    ``t`` (n,) [s]; ``chamber``, ``housing``, ``sensor``, ``coil_mean`` (n,) [K];
    ``shupe`` (n,) [rad/s]: (n/(L D)) Tdot . W0 (beta_T at T0, all of dn/dT, expansion and the
    elasto-optic strain term); ``product`` (n,) [rad/s]: (n/(L D)) (T - T0) . Q Tdot (the
    T x dT term from the material temperature dependences); ``dt`` [s] the step used and
    ``convergence`` the max |Omega(dt) - Omega(dt/2)| / max |Omega(dt/2)| of the check (0 when
    every chamber knot lies on the step grid: the first-order hold is then exact at the samples).

    Attributes
    ----------
    t : ndarray, shape (n,)
        Times [s].
    chamber, housing, sensor, coil_mean : ndarray, shape (n,)
        Chamber, housing, logged-sensor and mean coil temperature [K].
    shupe : ndarray, shape (n,)
        The Tdot rate error [rad/s].
    product : ndarray, shape (n,)
        The T x dT rate error [rad/s].
    dt : float
        Thermal step used [s].
    convergence : float
        Step-halving check [-].
    """

    t: NDArray[np.float64]
    chamber: NDArray[np.float64]
    housing: NDArray[np.float64]
    sensor: NDArray[np.float64]
    coil_mean: NDArray[np.float64]
    shupe: NDArray[np.float64]
    product: NDArray[np.float64]
    dt: float
    convergence: float

    @property
    def total(self) -> NDArray[np.float64]:
        """Non-reciprocal rate error [rad/s]."""
        return self.shupe + self.product


@dataclass(frozen=True, kw_only=True)
class Coil2D:
    """One coil unit: its (r, z) thermal network and the precomputed Shupe map.

    State x = [T of each grid cell (spool | pack | skin columns x skin | pack | skin rows),
    T_housing] [K]:  C dx/dt = -K x + e_h G_ch T_chamber. Boundary links (series with the
    half cell): outer, top and bore faces and the bottom of pack/skin through the gas gap
    h_gap; the spool's bottom face through the mount contact h_c; housing to chamber G_ch.

    Parameters
    ----------
    spec : Coil2DSpec
        The coil's drawing and materials.
    imperfections : Imperfections, optional
        The unit's drawn departures from the drawing; None: the ideal coil.
    """

    spec: Coil2DSpec = field(default_factory=Coil2DSpec)
    imperfections: Imperfections | None = None

    # ---------------------------------------------------------------- geometry
    def grid(self) -> Grid:
        """The FV grid with the materials of spool, pack and skin."""
        c = self.spec
        r_faces = np.concatenate(
            [
                np.linspace(c.bore_radius, c.inner_radius, c.grid_spool + 1),
                np.linspace(c.inner_radius, c.outer_radius, c.grid_pack_r + 1)[1:],
                [c.outer_radius + c.skin],
            ]
        )
        h2 = 0.5 * c.height
        z_faces = np.concatenate(
            [[-h2 - c.skin], np.linspace(-h2, h2, c.grid_pack_z + 1), [h2 + c.skin]]
        )
        nr, nz = len(r_faces) - 1, len(z_faces) - 1
        pack = c.pack(T_REF)
        m = c.matrix
        kr = np.full((nr, nz), m.conductivity)
        kz = kr.copy()
        rc = np.full((nr, nz), m.volumetric_heat_capacity)
        sp = slice(0, c.grid_spool)
        kr[sp, :] = kz[sp, :] = c.spool.conductivity
        rc[sp, :] = c.spool.volumetric_heat_capacity
        pr = slice(c.grid_spool, c.grid_spool + c.grid_pack_r)
        pz = slice(1, 1 + c.grid_pack_z)
        kr[pr, pz], kz[pr, pz], rc[pr, pz] = pack.k_r, pack.k_z, pack.rho_c
        return fv_grid(r_faces, z_faces, kr, kz, rc)

    def network(
        self, chamber_scale: float = 1.0
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], Grid]:
        """(K, cap, g_in, grid): cap dx/dt = -K x + g_in T_chamber; K symmetric [W/K], cap [J/K].

        ``chamber_scale`` multiplies the chamber-housing conductance G_ch (run-to-run airflow).
        """
        _num("Coil2D.network", "chamber_scale", chamber_scale, "> 0", "", lambda v: v > 0)
        c = self.spec
        g_ch = c.chamber_conductance * chamber_scale
        g = self._grid
        nr, nz = g.shape
        m = nr * nz
        rf, zf = g.r_faces, g.z_faces
        dz = np.diff(zf)
        ring = math.pi * np.diff(rf**2)

        def series(g_half, h, area):
            return 1.0 / (1.0 / g_half + 1.0 / (h * area))

        gb = np.zeros(m)
        idx = np.arange(m).reshape(nr, nz)
        outer = idx[-1, :]
        gb[outer] += series(g.g_face["outer"][outer], c.gap_coefficient, 2 * math.pi * rf[-1] * dz)
        inner = idx[0, :]
        gb[inner] += series(g.g_face["inner"][inner], c.gap_coefficient, 2 * math.pi * rf[0] * dz)
        top = idx[:, -1]
        gb[top] += series(g.g_face["top"][top], c.gap_coefficient, ring)
        bot = idx[:, 0]
        h_bot = np.where(np.arange(nr) < c.grid_spool, c.mount_coefficient, c.gap_coefficient)
        gb[bot] += series(g.g_face["bottom"][bot], h_bot, ring)
        K = np.zeros((m + 1, m + 1))
        K[:m, :m] = g.K
        K[:m, :m] += np.diag(gb)
        K[:m, m] = -gb
        K[m, :m] = -gb
        K[m, m] = gb.sum() + g_ch
        cap = np.concatenate([g.cap, [c.housing_heat_capacity]])
        g_in = np.zeros(m + 1)
        g_in[m] = g_ch
        return K, cap, g_in, g

    @cached_property
    def _grid(self) -> Grid:
        return self.grid()

    @cached_property
    def _modes(self):
        return self.modes(1.0)

    def modes(self, chamber_scale: float = 1.0):
        """Modal form x = Tm z, dz/dt = -mu z + beta u (S = C^-1/2 K C^-1/2 = V mu V^T)."""
        K, cap, g_in, _ = self.network(chamber_scale)
        ci = 1.0 / np.sqrt(cap)
        mu, V = np.linalg.eigh(ci[:, None] * K * ci[None, :])
        if np.any(mu <= 0):
            raise ValueError(
                "thermal network is not strictly stable (a node without a path to the chamber)"
            )
        return mu, ci[:, None] * V, V.T @ (ci * g_in)

    def fibre(self) -> FibreMap:
        """This unit's fibre map (:func:`fibre_map`; built once per unit)."""
        return self._fibre

    @cached_property
    def _fibre(self) -> FibreMap:
        return fibre_map(self.spec, self.imperfections)

    @cached_property
    def shupe_map(self) -> tuple[NDArray[np.float64], NDArray[np.float64], float]:
        """(W0 (m+1,) [m^2/K... x beta], Q (m+1, m+1), prefactor n/(L D) [1/m^2]).

        Omega = pre [Tdot . W0 + (T - T0) . Q Tdot]; the housing node has zero weight.
        """
        g = self._grid
        fm = self.fibre()
        P = g.interpolation(fm.r, fm.z)
        b0, b1 = self.spec.beta_coefficients(fm.r, bonded=fm.bonded)
        w = fm.weights
        m = P.shape[1]
        W0 = np.zeros(m + 1)
        W0[:m] = P.T @ (w * b0)
        Q = np.zeros((m + 1, m + 1))
        Q[:m, :m] = P.T @ ((w * b1)[:, None] * P)
        return W0, Q, self.spec.index / (fm.length * fm.diameter)

    @cached_property
    def sensor_row(self) -> NDArray[np.float64]:
        """Interpolation row of the logged sensor on the outer potting surface (m+1,)."""
        c = self.spec
        zs = 0.0 if self.imperfections is None else self.imperfections.sensor_z
        row = self._grid.interpolation([c.outer_radius + c.skin], [zs * 0.5 * c.height])[0]
        return np.concatenate([row, [0.0]])

    # ---------------------------------------------------------------- runs
    def run(
        self,
        chamber_times: ArrayLike,
        chamber_values: ArrayLike,
        *,
        dt: float = 20.0,
        tol: float = 2e-3,
        max_halvings: int = 4,
        chamber_scale: float = 1.0,
    ) -> ThermalRun:
        """Solve the network once for a piecewise-linear chamber program; check convergence.

        Parameters
        ----------
        chamber_times, chamber_values : array_like
            Knots of the chamber temperature program [s], [K] (linear between knots, held
            after the last). The run covers [times[0], times[-1]].
        dt : float
            Coarse thermal step [s]. Stepping is first-order-hold exact (matrix exponential),
            so the only time error is the input's departure from linear within a step (knots
            off the step grid).
        tol : float
            Convergence check: the run is repeated at dt/2 and accepted when
            max |Omega(dt) - Omega(dt/2)| <= tol max |Omega(dt/2)| (else dt is halved, at
            most ``max_halvings`` times, then ValueError).
        chamber_scale : float
            Factor on the chamber-housing conductance for this run (the Shupe map is reused).
        """
        tk = np.asarray(chamber_times, float)
        vk = np.asarray(chamber_values, float)
        if tk.ndim != 1 or tk.shape != vk.shape or len(tk) < 2 or np.any(np.diff(tk) <= 0):
            raise ValueError(
                "chamber_times must be >= 2 increasing knots [s] matching chamber_values [K]"
            )
        _num("Coil2D.run", "dt", dt, "> 0", "s", lambda v: v > 0)
        modes = self._modes if chamber_scale == 1.0 else self.modes(chamber_scale)
        on_grid = np.allclose((tk - tk[0]) / dt, np.round((tk - tk[0]) / dt), atol=1e-9, rtol=0)
        # FOH is exact at the samples for knots on the step grid, and for a constant program wherever
        # its knots fall (it is linear within every step): nothing to check. A constant program's
        # drift is rounding noise, whose relative convergence the check below could never reach.
        if on_grid or np.all(vk == vk[0]):
            return self._solve(tk, vk, dt, modes)
        conv = float("nan")
        for _ in range(max_halvings + 1):
            coarse = self._solve(tk, vk, dt, modes)
            fine = self._solve(tk, vk, dt / 2, modes)
            tot_f = np.interp(coarse.t, fine.t, fine.total)  # every coarse time is a fine one
            scale = max(float(np.max(np.abs(tot_f))), 1e-30)
            conv = float(np.max(np.abs(coarse.total - tot_f))) / scale
            if conv <= tol:
                return _with(coarse, conv)
            dt /= 2
        raise ValueError(
            f"thermal run did not converge to {tol:g} (last {conv:.3g}) down to dt = {dt:g} s"
        )

    def node_temperatures(
        self, chamber_times: ArrayLike, chamber_values: ArrayLike, *, dt: float = 20.0
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(t, x): every node's temperature [K] on the step grid (cells, then housing)."""
        tk = np.asarray(chamber_times, float)
        vk = np.asarray(chamber_values, float)
        _num("Coil2D.node_temperatures", "dt", dt, "> 0", "s", lambda v: v > 0)
        t, _, z = _modal_states(tk, vk, dt, self._modes)
        return t, z @ self._modes[1].T

    @cached_property
    def _pack_mask(self) -> NDArray[np.float64]:
        c = self.spec
        nr, nz = c.grid_spool + c.grid_pack_r + 1, c.grid_pack_z + 2
        mask = np.zeros((nr, nz))
        mask[c.grid_spool : c.grid_spool + c.grid_pack_r, 1 : 1 + c.grid_pack_z] = 1.0
        w = mask.ravel() * self._grid.cap
        return np.concatenate([w / w.sum(), [0.0]])

    def _solve(self, tk, vk, dt, modes) -> ThermalRun:
        """Modal first-order-hold recursion, exact for u linear over each step (mode by mode):

        z_{k+1} = phi z_k + beta [(G0 - G1) u_k + G1 u_{k+1}],  phi = exp(-mu dt),
        G0 = (1 - phi)/mu,  G1 = (mu dt - 1 + phi)/(mu^2 dt).
        """
        mu, Tm, beta = modes
        W0, Q, pre = self.shupe_map
        t, u, z = _modal_states(tk, vk, dt, modes)
        x = z @ Tm.T
        xdot = (np.outer(u, beta) - mu * z) @ Tm.T
        dT = x - self.spec.t_ref
        return ThermalRun(
            t=t,
            chamber=u,
            housing=x[:, -1],
            sensor=x @ self.sensor_row,
            coil_mean=x @ self._pack_mask,
            shupe=pre * (xdot @ W0),
            product=pre * np.einsum("ti,ti->t", dT @ Q, xdot),
            dt=dt,
            convergence=0.0,
        )



def _with(run: ThermalRun, conv: float) -> ThermalRun:
    import dataclasses

    return dataclasses.replace(run, convergence=conv)


def heated_stretch(
    spec: Coil2DSpec,
    T: ArrayLike,
    rate: float,
    *,
    fibre_length: float,
    diameter: float,
    z_center: float,
    seg_length: float,
    radius: float | None = None,
    t_ref: float = units.ZERO_CELSIUS,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Tdot and T x dT rate errors [rad/s] of one heated stretch (paper 003, Table 1 / Fig. 2).

    A stretch of ``seg_length`` [m] centred at ``z_center`` [m] along a fibre of
    ``fibre_length`` L, at temperature T [K] rising at ``rate`` [K/s], the rest static:

        Omega_Tdot = (n/(L D)) beta_0 Tdot w,   Omega_TxdT = (n/(L D)) beta_1 (T - T_ref) Tdot w,
        w = l (L - 2 z_c),  beta_T(T) ~ beta_0 + beta_1 (T - T_ref)

    with beta_T represented by its chord over [t_lo, t_hi] (material data;
    :meth:`Coil2DSpec.beta_coefficients`), so the sum does not depend on ``t_ref`` [K] or on
    the temperature scale; the split does. Default T_ref = 0 degC: the paper's eq. (9),
    dz = alpha_T L0 T with T in degC, puts the reference length at 0 degC, and its T x dT
    regressor has T in degC. ``radius`` None: free fibre (dn/dT + n alpha_f); a radius: fibre
    bonded in the pack at that radius.

    Parameters
    ----------
    spec : Coil2DSpec
        The coil's materials.
    T : array_like
        Temperature of the stretch [K].
    rate : float
        Its heating rate Tdot [K/s].
    fibre_length : float
        Fibre length L [m].
    diameter : float
        Mean coil diameter D [m].
    z_center : float
        Centre z_c of the stretch along the fibre [m].
    seg_length : float
        Length l of the stretch [m].
    radius : float, optional
        Radius at which the fibre is bonded in the pack [m]; None: free fibre.
    t_ref : float
        Reference temperature T_ref [K].

    Returns
    -------
    Omega_Tdot, Omega_TxdT : ndarray
        The two rate errors [rad/s].
    """
    T = np.asarray(T, dtype=float)
    r = np.array([spec.inner_radius if radius is None else radius])
    b0, b1 = (float(v[0]) for v in spec.beta_coefficients(r, bonded=radius is not None, t_ref=t_ref))
    w = seg_length * (fibre_length - 2.0 * z_center)
    pre = spec.index / (fibre_length * diameter)
    return np.full(T.shape, pre * b0 * rate * w), pre * b1 * (T - t_ref) * rate * w
