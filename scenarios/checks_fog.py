"""Closed-form checks of the FOG model (:mod:`gyrobench.sim.fog`, :mod:`gyrobench.sim.coil`).

- Sagnac scale factor of the default unit, ``FOGSpec().scale_factor``, against a second
  derivation that does not use the model's formula: the transit times of the two beams
  round N = L/(pi D) turns of a loop of radius R = D/2 rotating at Omega, seen in the
  inertial frame (the co-rotating beam chases its moving start point: t_cw = L/(c - R Omega),
  t_ccw = L/(c + R Omega); E. J. Post, Rev. Mod. Phys. 39 (1967) 475), give
  dphi = 2 pi c (t_cw - t_ccw)/lambda; SF = dphi/Omega at Omega = 1e-3 rad/s with
  t_cw - t_ccw = 2 L R Omega/(c^2 - R^2 Omega^2) (no cancellation), c from scipy.constants
  (CODATA 2018: 299 792 458 m/s exactly), not from the model. The two agree to
  (R Omega/c)^2 ~ 3e-26, far below rounding.
- Shupe rate error of a helical and a quadrupolar winding (40 layers, L = 1000 m) under
  a heating rate linear in radius (inner layer 0, outer layer 0.01 K/min more) against
  the closed form Omega_E = n (dn/dT + n alpha_f)/(L D) * l^2 * d * S, where
  S = sum_j (w_j/l^2) j/(M-1) is summed in exact rationals from the A/B layer sequence
  (a fibre stretch [z0, z0+l] has weight w = l (L - 2 z_mid); docs/physics.md 3.2, 3.3),
  independent of :mod:`gyrobench.sim.coil`'s own weights. The quadrupolar error is
  measured against the uncancelled (helical) term, and the cancellation ratio
  helical/quadrupolar against the exact rational ratio.

Every check is exact arithmetic: tolerances are float64 rounding bounds (stated).
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
from gyrobench.scenarios.checks import Check

__all__ = ["checks"]

_LAYERS = 40
_LENGTH = 1000.0  # [m]
_DT_RATE = 0.01 / 60.0  # outer - inner heating-rate difference [K/s]
_EPS = float(np.finfo(float).eps)


def _exact_linear_radial_sum(pattern: str, layers: int) -> Fraction:
    """sum_j (w_j / l^2) j/(M-1), exact, from the winding's A/B layer sequence."""
    from gyrobench.sim.coil import WINDING_PATTERNS

    seq = WINDING_PATTERNS[pattern]
    total = Fraction(0)
    if seq is None:  # helical: layer j holds fibre [j l, (j+1) l], w_j = l^2 (M - 2j - 1)
        return sum(
            (Fraction(layers - 2 * j - 1) * Fraction(j, layers - 1) for j in range(layers)),
            Fraction(0),
        )
    seq = seq * (layers // len(seq))
    a = b = 0
    for j, c in enumerate(seq):
        if c == "A":  # A half, outward from the middle: w = l^2 (2a + 1)
            w = Fraction(2 * a + 1)
            a += 1
        else:  # B half: w = -l^2 (2b + 1)
            w = -Fraction(2 * b + 1)
            b += 1
        total += w * Fraction(j, layers - 1)
    return total


def _shupe(pattern: str) -> tuple[float, float]:
    """(model, closed form) Shupe rate error [rad/s] for the linear radial heating rate."""
    from gyrobench.sim import units
    from gyrobench.sim.coil import CoilSpec, Winding, shupe_terms

    coil = CoilSpec(winding=pattern, layers=_LAYERS, length=_LENGTH)
    w = Winding.ideal(pattern, _LAYERS, _LENGTH)
    tdot = _DT_RATE * np.arange(_LAYERS) / (_LAYERS - 1)
    model = float(
        shupe_terms(
            coil,
            w.weights,
            np.full(_LAYERS, units.ZERO_CELSIUS),
            tdot,
            constraint_cte=np.zeros(_LAYERS),
        ).shupe
    )
    n = coil.index
    pre = n * (coil.dn_dT + n * coil.fibre_cte) / (coil.length * coil.diameter)
    seg = _LENGTH / _LAYERS
    return model, pre * seg**2 * _DT_RATE * float(_exact_linear_radial_sum(pattern, _LAYERS))


def checks(rng: np.random.Generator) -> list[Check]:
    """Sagnac scale factor and Shupe cancellation (deterministic; ``rng`` unused)."""
    from gyrobench.sim.fog import FOGSpec
    from scipy import constants

    spec = FOGSpec()
    c = spec.coil
    omega, radius = 1e-3, c.diameter / 2  # [rad/s], [m]
    dt_transit = 2 * c.length * radius * omega / (constants.c**2 - (radius * omega) ** 2)
    sf = 2 * math.pi * constants.c * dt_transit / c.wavelength / omega
    helical, helical_cf = _shupe("helical")
    quad, quad_cf = _shupe("quadrupolar")
    sum_tol = 4 * _LAYERS * _EPS  # 40-term sum and 4 products, each <= 1 ulp of the largest term
    return [
        Check(
            id="fog.sagnac_scale_factor",
            formula="SF = 2 pi c (t_cw - t_ccw)/(lambda Omega), t_cw,ccw = L/(c -+ R Omega) "
            f"(inertial-frame transit times, Post 1967) [s]; L = {c.length:g} m, "
            f"D = {c.diameter:g} m, lambda = {c.wavelength:g} m, Omega = {omega:g} rad/s",
            expected=sf,
            simulated=spec.scale_factor,
            tolerance=16 * _EPS,
            derivation="float64 rounding: about 10 operations, <= 16 eps; the transit-time form "
            "differs from 2 pi L D/(lambda c) by (R Omega/c)^2 ~ 3e-26 (negligible)",
        ),
        Check(
            id="fog.shupe_helical",
            formula="Omega_E = n (dn/dT + n alpha_f)/(L D) l^2 dTdot S_helical [rad/s]; "
            f"M = {_LAYERS} layers, Tdot linear in radius, 0 -> 0.01 K/min",
            expected=helical_cf,
            simulated=helical,
            tolerance=sum_tol,
            derivation=f"exact rational sum vs float64 sum of {_LAYERS} terms: <= 4 M eps = "
            f"{sum_tol:.2g}",
        ),
        Check(
            id="fog.shupe_quadrupolar",
            formula="Omega_E as fog.shupe_helical with the ABBA sequence; error relative to the "
            "helical term",
            expected=quad_cf,
            simulated=quad,
            tolerance=sum_tol,
            scale=helical_cf,
            derivation="rounding of the 40-term sum is relative to its largest terms, those of the "
            f"uncancelled (helical) sum: <= 4 M eps = {sum_tol:.2g} of it",
        ),
        Check(
            id="fog.shupe_cancellation_ratio",
            formula="Omega_helical / Omega_quadrupolar = S_helical / S_quadrupolar (exact "
            "rationals)",
            expected=float(
                _exact_linear_radial_sum("helical", _LAYERS)
                / _exact_linear_radial_sum("quadrupolar", _LAYERS)
            ),
            simulated=helical / quad,
            tolerance=2 * sum_tol * abs(helical_cf / quad_cf),
            derivation="the quadrupolar error (<= 4 M eps of the helical term) relative to the "
            "quadrupolar "
            "value is amplified by the ratio; twice that",
        ),
    ]
