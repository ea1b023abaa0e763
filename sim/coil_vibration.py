"""The (r, z) coil's own vibration modes: inertial strain of the spool under axial acceleration, on the winding map.

All SI: acceleration [m/s^2], strain [-], lengths [m], density [kg/m^3], modulus [Pa].

The strain-rate nonreciprocity of :mod:`gyrobench.sim.fiber_strain` (docs/physics.md 4.1),

    Omega_eps(t) = (n_g n xi / (L D)) int_0^L eps_dot(s, t) (L - 2s) ds                [rad/s]

needs the strain along the fibre. Under an acceleration a along the coil axis (the sense axis)
the spool of :class:`gyrobench.sim.coil2d.Coil2DSpec` (an aluminium annulus, bore radius r_b to
the pack's inner radius r_i, over the pack's height H, bolted at its bottom face) carries the
inertia of itself and of the pack bonded to it. With the pack's load entering the spool at the
height where it sits (a thin pack: shear lag neglected, ASSUMED), the axial stress at height z
(z from -H/2 to H/2, the mount at -H/2) is

    sigma_z(z) = -(rho_s A_s + rho_p A_p) a (H/2 - z) / A_s,   A_s = pi (r_i^2 - r_b^2), A_p = pi (r_o^2 - r_i^2)

and, the spool's radial face free (uniaxial stress), its hoop strain is -nu_s sigma_z / E_s. The
bonded pack follows the spool's hoop strain (thin pack vs radius, 5.6 mm vs 50 mm: ASSUMED
uniform through the layers), so the fibre's axial strain is

    eps(s, t) = kappa psi(z(s)) x(t),   kappa = nu_s (rho_s A_s + rho_p A_p) H / (E_s A_s),
    psi(z) = (H/2 - z)/H                                                          (bonded fibre)

(0 on the free leads) with x = H_1 a the modal acceleration of the spool's first axial
(quarter-wave, fixed-free bar) mode f_1 = sqrt(E_s A_s / (rho_s A_s + rho_p A_p)) / (4 H): 85 kHz
for the default coil, so the response is quasi-static at every shaker frequency (Q_1 = 15, the
same ASSUMED damping as the loop's default coil mode). The weight of the shape along the fibre
is a sum over the winding map's pieces (:class:`~gyrobench.sim.coil_winding.FibreMap`, w_i = ds_i
(L - 2 s_i)):

    W = sum_i w_i psi(z_i)                                                              [m^2]

A symmetric winding cancels most of it, the drawn unit's turn and radius errors leave the rest:
for the default quadrupolar coil the ideal map gives W = 12 m^2 (7e-5 of the linear-ramp
weight L^2/6; a dipolar map 0.08 m^2, an octupolar 0.04 m^2: the quadrupole cancels radial, not axial,
gradients best), drawn units -850 to +90 m^2 (seeds 1-5). A uniform strain (psi = 1) gives
W = sum w_i = 0 to rounding, so a pure translation that strains every turn alike gives no
error; a static acceleration (eps_dot = 0) gives none either: the FOG has no first-order
g-sensitivity.

Densities: silica 2203 kg/m^3 (Crystran, :data:`~gyrobench.sim.coil_materials.SILICA`'s source),
epoxy 1300 and aluminium 6061-T6 2700 kg/m^3 (the sources of
:data:`~gyrobench.sim.coil_materials.EPOXY` and :data:`~gyrobench.sim.coil_materials.ALUMINIUM`),
acrylate 1200 kg/m^3 (ASSUMED, the rho of the coating's assumed rho c = 1.2e3 x 1.5e3 J/(m^3 K));
the pack's density is their volume-weighted mean (glass phi g, coating phi (1 - g), matrix
1 - phi). Default coil: rho_p = 1502 kg/m^3, kappa = 2.2e-10 per m/s^2.

:func:`coil_modes` is the mode set a FOG on this coil vibrates with: this inertial mode, and the
loop's default pigtail (0.5 m of lead at the coil end: 300 Hz, Q 30, 3e-12 per m/s^2 and the
microbending loss 1e-6 per m/s^2 whose correlation with the loop residual rectifies) and fixture
rocking (900 Hz, Q 10, 1e-8 rad per m/s^2 about the sense axis: true rate) of
:class:`gyrobench.sim.fog_loop.ClosedLoopFOG`, ASSUMED there. The loop's default coil mode (an
ASSUMED strain 2e-12 per m/s^2 with W = 1e-3 L^2/6) is replaced by the inertial mode, not added
to it: one coil strain, counted once.

References
----------
docs/physics.md 4.1 and 4.3; Timoshenko & Goodier, Theory of Elasticity, 3rd ed. (1970), sec. 1-5
(a bar under its own weight); Lefevre, The Fiber-Optic Gyroscope, 2nd ed. (2014), sec. 3.2
(time-varying non-reciprocity, the (L - 2z) weighting shared with the Shupe effect).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from gyrobench.sim.coil2d import Coil2D
from gyrobench.sim.fiber_strain import StrainMode, segment_weight

__all__ = [
    "SILICA_DENSITY",
    "ACRYLATE_DENSITY",
    "EPOXY_DENSITY",
    "ALUMINIUM_DENSITY",
    "COIL_MODE_QUALITY",
    "pack_density",
    "inertial_strain",
    "axial_frequency",
    "shape_weight",
    "inertial_mode",
    "coil_modes",
]

SILICA_DENSITY = 2203.0
"""Fused silica [kg/m^3] (Crystran handbook, 5th ed. (2023), as :data:`~gyrobench.sim.coil_materials.SILICA`)."""
ACRYLATE_DENSITY = 1200.0
"""Acrylate coating [kg/m^3]: ASSUMED (the coating's rho c = 1.2e3 x 1.5e3 J/(m^3 K) of coil_materials)."""
EPOXY_DENSITY = 1300.0
"""Potting epoxy [kg/m^3] (Budinski & Budinski (1999), as :data:`~gyrobench.sim.coil_materials.EPOXY`)."""
ALUMINIUM_DENSITY = 2700.0
"""Aluminium 6061-T6 [kg/m^3] (Aluminum Association typical, as :data:`~gyrobench.sim.coil_materials.ALUMINIUM`)."""
COIL_MODE_QUALITY = 15.0
"""Q of the spool's axial mode [-]: ASSUMED, the loop's default coil mode's (a potted coil)."""


def pack_density(coil: Coil2D) -> float:
    """rho_p = phi g rho_glass + phi (1 - g) rho_coating + (1 - phi) rho_matrix [kg/m^3] (module docstring).

    Parameters
    ----------
    coil : Coil2D
        The (drawn) coil.

    Returns
    -------
    float
        rho_p [kg/m^3].
    """
    s = coil.spec
    phi, g = s.packing, s.glass_fraction
    return phi * g * SILICA_DENSITY + phi * (1.0 - g) * ACRYLATE_DENSITY + (1.0 - phi) * EPOXY_DENSITY


def _areas(coil: Coil2D) -> tuple[float, float]:
    s = coil.spec
    return math.pi * (s.inner_radius**2 - s.bore_radius**2), math.pi * (s.outer_radius**2 - s.inner_radius**2)


def inertial_strain(coil: Coil2D) -> float:
    """kappa = nu_s (rho_s A_s + rho_p A_p) H / (E_s A_s): fibre strain at the mount per m/s^2 [1/(m/s^2)].

    Parameters
    ----------
    coil : Coil2D
        The (drawn) coil.

    Returns
    -------
    float
        kappa [1/(m/s^2)].
    """
    s = coil.spec
    a_s, a_p = _areas(coil)
    load = ALUMINIUM_DENSITY * a_s + pack_density(coil) * a_p
    return s.spool.poisson * load * s.height / (s.spool.youngs_modulus * a_s)


def axial_frequency(coil: Coil2D) -> float:
    """f_1 = sqrt(E_s A_s / (rho_s A_s + rho_p A_p)) / (4 H): the spool's quarter-wave axial mode [Hz].

    Parameters
    ----------
    coil : Coil2D
        The (drawn) coil.

    Returns
    -------
    float
        f_1 [Hz].
    """
    s = coil.spec
    a_s, a_p = _areas(coil)
    load = ALUMINIUM_DENSITY * a_s + pack_density(coil) * a_p
    return math.sqrt(s.spool.youngs_modulus * a_s / load) / (4.0 * s.height)


def shape_weight(coil: Coil2D, shape: Callable[[NDArray[np.float64]], NDArray[np.float64]] | None = None) -> float:
    """W = sum_i ds_i (L - 2 s_i) psi(z_i) over the bonded pieces of the coil's fibre map [m^2].

    Parameters
    ----------
    coil : Coil2D
        The (drawn) coil.
    shape : callable, optional
        psi(z) [-] of the axial position z [m] (mid-plane 0); default (H/2 - z)/H, the inertial
        shape (module docstring).

    Returns
    -------
    float
        W [m^2].
    """
    fm = coil.fibre()
    h = coil.spec.height
    z = np.asarray(fm.z, dtype=float)
    psi = (0.5 * h - z) / h if shape is None else np.asarray(shape(z), dtype=float) * np.ones_like(z)
    return float(np.sum(np.where(fm.bonded, fm.weights * psi, 0.0)))


def inertial_mode(coil: Coil2D) -> StrainMode:
    """The spool's axial mode as a :class:`StrainMode`: f_1, COIL_MODE_QUALITY, kappa, W (module docstring).

    Parameters
    ----------
    coil : Coil2D
        The (drawn) coil.

    Returns
    -------
    StrainMode
        The mode (no segment: the kernel is W e^{-jw tau/2}).
    """
    return StrainMode(frequency=axial_frequency(coil), quality=COIL_MODE_QUALITY,
                      strain=inertial_strain(coil), weight=shape_weight(coil))


def coil_modes(coil: Coil2D) -> tuple[StrainMode, ...]:
    """The modes a FOG on ``coil`` vibrates with: the inertial mode, the pigtail and the fixture (module docstring).

    Parameters
    ----------
    coil : Coil2D
        The (drawn) coil.

    Returns
    -------
    tuple of StrainMode
        (inertial spool mode, 0.5 m pigtail at the coil end, fixture rocking).
    """
    length = coil.fibre().length
    lead = min(0.5, 0.5 * length)
    return (
        inertial_mode(coil),
        StrainMode(frequency=300.0, quality=30.0, strain=3e-12, weight=segment_weight(0.0, lead, length),
                   loss=1e-6, segment=(0.0, lead)),
        StrainMode(frequency=900.0, quality=10.0, rocking=1e-8),
    )
