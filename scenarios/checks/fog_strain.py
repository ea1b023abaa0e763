"""Closed-form checks of the fibre-strain nonreciprocity kernel (:mod:`gyrobench.sim.fiber_strain`)
that the closed-loop FOG (:mod:`gyrobench.sim.fog_loop`) carries its vibration error through.

- The two-crossing-time integral of a harmonic strain along the fibre (no small-tau
  approximation) against the closed form (k0 n xi n_g / c) w eps0 int psi (L - 2z) dz: 0 for
  uniform strain, -L^2/6 for psi = z/L.
- The exact kernel e^{-jw tau/2} W(w) (phasor, amplitude and phase) against the same integral;
  the reduced form with that kernel against the full loop driven by the exact strain phase (the
  small-tau kernel's error is reported beside it).

Every check is deterministic (``rng`` is accepted for the collector's contract). Split from
:mod:`gyrobench.scenarios.checks.fog_loop` (the loop, its optical budget and the vibration
chain through it), whose statistical checks keep their streams; the values here are the same
as there. Tolerances are derived where each check is built.
"""

from __future__ import annotations

import math

import numpy as np

from gyrobench.scenarios.checks.core import CLOSED_FORM, SECOND_METHOD, Check, Part, run_parts
from gyrobench.scenarios.checks.fog_loop import LEFEVRE, STRAIN

__all__ = ["checks", "parts"]


def _strain_kernel() -> list[Check]:
    from gyrobench.sim.fiber_strain import ELASTO_OPTIC_FACTOR, exact_strain_phase
    from gyrobench.sim.fog_optics import SPEED_OF_LIGHT

    length, lam, ng, n = 1000.0, 1550e-9, 1.468, 1.46
    f, eps0 = 500.0, 1e-6
    w = 2 * np.pi * f
    k0 = 2 * np.pi / lam
    pre = k0 * n * ELASTO_OPTIC_FACTOR * ng / SPEED_OF_LIGHT * w * eps0
    t = np.linspace(0, 1 / f, 64, endpoint=False)

    def amp(psi):
        y = exact_strain_phase(
            lambda z, tt: eps0 * psi(z) * np.cos(w * tt),
            t,
            length=length,
            wavelength=lam,
            group_index=ng,
            index=n,
        )
        basis = np.column_stack([np.sin(w * t), np.cos(w * t)])
        c, *_ = np.linalg.lstsq(basis, y, rcond=None)
        return math.hypot(*c)

    tau = ng * length / SPEED_OF_LIGHT
    small_tau = (w * tau / 2) ** 2 / 6  # sin x = x (1 - x^2/6), |x| <= w tau/2
    uncancelled = pre * length**2 / 2  # int |L - 2z| dz: every contribution with one sign
    return [
        Check(
            id="fog.strain_uniform_zero",
            kind=CLOSED_FORM,
            reference=STRAIN,
            formula="dphi = (k0 n xi n_g/c) w eps0 int_0^L (L - 2z) dz = 0 for uniform strain; "
            "exact two-crossing-time integral, 500 Hz, L = 1 km; relative to the "
            "uncancelled integral of |L - 2z|",
            expected=0.0,
            simulated=amp(lambda z: np.ones_like(z)),
            tolerance=1e-9,
            scale=uncancelled,
            derivation="Simpson on 4001 points integrates the odd kernel to rounding; 1e-9 "
            "covers float64 cancellation of terms of size k0 n xi eps0 L",
        ),
        Check(
            id="fog.strain_mode_linear",
            kind=CLOSED_FORM,
            reference=STRAIN,
            formula="dphi amplitude = (k0 n xi n_g/c) w eps0 W, W = int (z/L)(L - 2z) dz = "
            "-L^2/6 (psi = z/L), 500 Hz",
            expected=pre * length**2 / 6,
            simulated=amp(lambda z: z / length),
            tolerance=small_tau + 1e-8,
            derivation=f"small-tau kernel error (w tau/2)^2/6 = {small_tau:.2g} plus Simpson "
            "(h^4 error on a smooth integrand) and fit rounding 1e-8",
        ),
    ]


def _strain_exact_kernel() -> list[Check]:
    from gyrobench.sim.fiber_strain import (
        ELASTO_OPTIC_FACTOR,
        exact_strain_phase,
        linear_kernel,
        strain_rate_coefficient,
    )
    from gyrobench.sim.fog_loop import LoopSpec, loop_average, run_loop
    from gyrobench.sim.fog_optics import SPEED_OF_LIGHT

    spec = LoopSpec(gain_loop=False)
    length, lam, ng, n = spec.length, spec.wavelength, spec.group_index, 1.444
    # (1) closed-form exact kernel vs the numerical two-crossing-time integral, psi = z/L
    f, eps0 = 500.0, 1e-6
    w = 2 * np.pi * f
    t = np.linspace(0, 1 / f, 64, endpoint=False)
    y = exact_strain_phase(
        lambda z, tt: eps0 * (z / length) * np.cos(w * tt),
        t,
        length=length,
        wavelength=lam,
        group_index=ng,
        index=n,
    )
    basis = np.column_stack([np.cos(w * t), -np.sin(w * t)])  # Re(P e^{jwt}) = Re P cos - Im P sin
    c, *_ = np.linalg.lstsq(basis, y, rcond=None)
    k0 = 2 * np.pi / lam
    p_cf = complex(
        k0 * n * ELASTO_OPTIC_FACTOR * 1j * w * ng / SPEED_OF_LIGHT * linear_kernel(length, f, ng)
    ) * eps0
    # (2) reduced form (exact kernel) vs the full loop driven by the exact phase
    m, n_out, kp = 512, 100, 16
    fo = 1 / (m * spec.transit_time)
    fv = round(500.0 * n_out / fo) * fo / n_out
    wv = 2 * np.pi * fv
    kk = strain_rate_coefficient(length, spec.diameter, ng, n)
    amp = 1e-3  # rad/s rate-equivalent
    ph_ex = complex(kk * 1j * wv * linear_kernel(length, fv, ng))
    ph_st = kk * 1j * wv * (-(length**2) / 6)  # small-tau kernel: W, no delay
    e0 = amp / abs(ph_ex)

    def rate(p: complex, tt: np.ndarray) -> np.ndarray:
        return np.real(p * e0 * np.exp(1j * wv * tt))

    tn = np.arange(n_out * kp) / (kp * fo)
    red_ex = loop_average(np.fft.rfft(rate(ph_ex, tn)), len(tn), kp * fo, fo, spec)
    red_st = loop_average(np.fft.rfft(rate(ph_st, tn)), len(tn), kp * fo, fo, spec)
    tk = (np.arange(n_out * m) + 0.5) * spec.transit_time
    full = run_loop(spec, spec.scale_factor * rate(ph_ex, tk), samples_per_output=m).rate
    err_ex = float(np.max(np.abs(full[2:] - red_ex[2:])))
    err_st = float(np.max(np.abs(full[2:] - red_st[2:])))
    mid = (wv * spec.transit_time) ** 2 / 24
    half = wv * spec.transit_time / 2
    return [
        Check(
            id="fog.strain_kernel_exact",
            kind=CLOSED_FORM,
            reference=STRAIN + "; second method: Simpson quadrature of the two-crossing-time integral",
            formula="dphi phasor = k0 n xi (jw/v) e^{-jw tau/2} W(w) eps0, W(w) = "
            "-L^2 (sin x - x cos x)/(2 x^3), x = w tau/2 (psi = z/L), 500 Hz, vs the "
            "two-crossing-time integral; |difference| / |phasor|",
            expected=abs(p_cf),
            simulated=abs(p_cf) + abs(complex(c[0], c[1]) - p_cf),
            tolerance=1e-9,
            derivation="Simpson on 4001 points: the integrand's 4th derivative ~ (w/v)^4 makes "
            "its error < 1e-20; rounding of two O(1) cosines that cancel to O(w tau) = 0.015: "
            "~1e-13; 1e-9 covers both and the fit",
        ),
        Check(
            id="fog.strain_reduced_vs_full_loop",
            kind=SECOND_METHOD,
            reference=STRAIN + "; second method: the full-rate loop (" + LEFEVRE + ", ch. 6)",
            formula="reduced form with the exact strain kernel vs the full-rate loop driven by "
            "the exact strain phase (psi = z/L, 500 Hz, 1e-3 rad/s); largest output "
            "difference / amplitude",
            expected=amp,
            simulated=amp + err_ex,
            tolerance=2 * mid + 1e-6,
            derivation=f"midpoint-rule error (w tau)^2/24 = {mid:.2g}, twice, + 1e-6 for the "
            f"start transient and rounding (as fog.vibration_reduced_vs_full_loop). The "
            f"small-tau kernel (W, no delay) misses by {err_st / amp:.2g} of the amplitude "
            f"(half-transit delay w tau/2 = {half:.2g}, amplitude (w tau/2)^2/10 = "
            f"{half**2 / 10:.2g})",
        ),
    ]


def parts(rng: np.random.Generator) -> list[Part]:
    """The two deterministic groups (``rng`` unused but required by the collector)."""
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator; got {type(rng).__name__}")
    return [Part("strain_kernel", _strain_kernel), Part("strain_exact_kernel", _strain_exact_kernel)]


def checks(rng: np.random.Generator) -> list[Check]:
    """The strain-kernel checks (deterministic)."""
    return run_parts(parts(rng))
