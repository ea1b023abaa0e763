"""Closed-form check of the FOG's Sagnac scale factor (:mod:`gyrobench.sim.fog2d`, the FOG on the
(r, z) coil that paper 003 runs; its closed loop :mod:`gyrobench.sim.fog_loop`).

- Sagnac scale factor of a unit of the default ``FOG2DSpec``, ``unit.scale_factor``, against a second
  derivation that does not use the model's formula: the transit times of the two beams
  round N = L/(pi D) turns of a loop of radius R = D/2 rotating at Omega, seen in the
  inertial frame (the co-rotating beam chases its moving start point: t_cw = L/(c - R Omega),
  t_ccw = L/(c + R Omega); E. J. Post, Rev. Mod. Phys. 39 (1967) 475), give
  dphi = 2 pi c (t_cw - t_ccw)/lambda; SF = dphi/Omega at Omega = 1e-3 rad/s with
  t_cw - t_ccw = 2 L R Omega/(c^2 - R^2 Omega^2) (no cancellation), c from scipy.constants
  (CODATA 2018: 299 792 458 m/s exactly), not from the model. The two agree to
  (R Omega/c)^2 ~ 3e-26, far below rounding.
- The Shupe checks run on the (r, z) coil paper 003 uses (:mod:`gyrobench.scenarios.checks.coil`,
  ``coil.shupe_radial_*``), not on the 1-D layer model.

The check is exact arithmetic: its tolerance is a float64 rounding bound (stated).
"""

from __future__ import annotations

import math

import numpy as np

from gyrobench.scenarios.checks.core import CLOSED_FORM, Check

__all__ = ["checks"]

_EPS = float(np.finfo(float).eps)


def checks(rng: np.random.Generator) -> list[Check]:
    """Sagnac scale factor of one unit drawn with ``rng`` (its coil's L and D)."""
    from scipy import constants

    from gyrobench.sim.fog2d import FOG2DSpec

    unit = FOG2DSpec().realize(rng=rng)
    c = unit.fog.loop
    omega, radius = 1e-3, c.diameter / 2  # [rad/s], [m]
    dt_transit = 2 * c.length * radius * omega / (constants.c**2 - (radius * omega) ** 2)
    sf = 2 * math.pi * constants.c * dt_transit / c.wavelength / omega
    return [
        Check(
            id="fog.sagnac_scale_factor",
            kind=CLOSED_FORM,
            reference=(
                "E. J. Post, 'Sagnac effect', Rev. Mod. Phys. 39(2) 475 (1967): inertial-frame transit "
                "times; c from CODATA 2018"
            ),
            formula="SF = 2 pi c (t_cw - t_ccw)/(lambda Omega), t_cw,ccw = L/(c -+ R Omega) "
            f"(inertial-frame transit times, Post 1967) [s]; L = {c.length:g} m, "
            f"D = {c.diameter:g} m, lambda = {c.wavelength:g} m, Omega = {omega:g} rad/s",
            expected=sf,
            simulated=unit.scale_factor,
            tolerance=16 * _EPS,
            derivation="float64 rounding: about 10 operations, <= 16 eps; the transit-time form "
            "differs from 2 pi L D/(lambda c) by (R Omega/c)^2 ~ 3e-26 (negligible)",
        ),
    ]
