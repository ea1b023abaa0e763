"""Closed-form checks of the FOG model (:mod:`gyrobench.sim.fog`, :mod:`gyrobench.sim.coil`).

- Sagnac scale factor of the default unit, ``FOGSpec().scale_factor``, against
  SF = 2 pi L D / (lambda c) [s] (Lefevre, The Fiber-Optic Gyroscope, eq. 2.10)
  with c from scipy.constants (CODATA), not from the model.
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
    sf = 2 * math.pi * c.length * c.diameter / (c.wavelength * constants.c)
    helical, helical_cf = _shupe("helical")
    quad, quad_cf = _shupe("quadrupolar")
    sum_tol = 4 * _LAYERS * _EPS  # 40-term sum and 4 products, each <= 1 ulp of the largest term
    return [
        Check(
            id="fog.sagnac_scale_factor",
            formula=f"SF = 2 pi L D / (lambda c) [s]; L = {c.length:g} m, D = {c.diameter:g} m, "
            f"lambda = {c.wavelength:g} m",
            expected=sf,
            simulated=spec.scale_factor,
            tolerance=10 * _EPS,
            derivation="exact expression: 5 float64 roundings, <= 10 eps",
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
