"""Strain along the fibre (sim/fiber_strain.py): weights and the nonreciprocity kernel."""

import math

import numpy as np
import pytest

from gyrobench.sim.fiber_strain import (
    ELASTO_OPTIC_FACTOR,
    StrainMode,
    elasto_optic_factor,
    exact_strain_phase,
    segment_weight,
    shape_weight,
    strain_rate_coefficient,
)
from gyrobench.sim.fog_optics import SPEED_OF_LIGHT

L = 1000.0


def test_weights_closed_forms():
    assert abs(shape_weight(lambda z: np.ones_like(z), L)) < 1e-9 * L**2
    assert abs(shape_weight(lambda z: z / L, L) / (-(L**2) / 6) - 1) < 1e-12
    assert segment_weight(0.0, 1.0, L) == 999.0
    assert segment_weight(L / 2 - 5, 10.0, L) == 0.0  # centred on the midpoint
    # a segment's weight equals the shape integral of its indicator (Simpson, smooth edges aside)
    w = shape_weight(lambda z: ((z >= 100) & (z <= 150)).astype(float), L, n=2_000_001)
    assert abs(w / segment_weight(100.0, 50.0, L) - 1) < 1e-4


def test_elasto_optic_factor_values():
    # docs/physics.md 4.1 quotes 0.795 for SMF-28 (0.125, 0.258, 0.161): that is n = 1.444
    # (fused silica at 1550 nm); 0.788 for (0.121, 0.270, 0.17) at the same n (the default)
    assert round(elasto_optic_factor(1.444, 0.125, 0.258, 0.161), 3) == 0.795
    assert (
        abs(
            elasto_optic_factor(1.46, 0.125, 0.258, 0.161)
            - (1 - 1.46**2 / 2 * (0.258 - 0.161 * 0.383))
        )
        < 1e-15
    )
    assert round(ELASTO_OPTIC_FACTOR, 3) == 0.788


@pytest.mark.parametrize("f", [500.0, 5000.0])
def test_exact_kernel_vs_small_tau_and_harmonic_form(f):
    lam, ng, n, eps0 = 1550e-9, 1.468, 1.46, 1e-6
    w = 2 * np.pi * f
    v = SPEED_OF_LIGHT / ng
    k0 = 2 * np.pi / lam
    t = np.linspace(0, 1 / f, 32, endpoint=False)
    y = exact_strain_phase(
        lambda z, tt: eps0 * (z / L) * np.cos(w * tt),
        t,
        length=L,
        wavelength=lam,
        group_index=ng,
        index=n,
    )
    # harmonic form: dphi = Re{2j e^{-jw tau/2} e^{jwt} k0 n xi eps0 int psi sin(w (L-2z)/(2v)) dz}
    # (orientation: wave entered at L minus wave entered at 0, the sign of the small-tau form)
    z = np.linspace(0, L, 200001)
    from scipy.integrate import simpson

    integral = simpson((z / L) * np.sin(w * (L - 2 * z) / (2 * v)), x=z)
    tau = L / v
    harm = np.real(
        2j
        * np.exp(-1j * w * tau / 2)
        * np.exp(1j * w * t)
        * k0
        * n
        * ELASTO_OPTIC_FACTOR
        * eps0
        * integral
    )
    np.testing.assert_allclose(y, harm, rtol=0, atol=1e-7 * np.max(np.abs(harm)))
    # small-tau closed form amplitude: (k0 n xi / v) w eps0 L^2/6, to (w tau/2)^2/6
    amp = math.hypot(
        *np.linalg.lstsq(np.column_stack([np.sin(w * t), np.cos(w * t)]), y, rcond=None)[0]
    )
    cf = k0 * n * ELASTO_OPTIC_FACTOR / v * w * eps0 * L**2 / 6
    assert abs(amp / cf - 1) < (w * tau / 2) ** 2 / 6 + 1e-7
    # rate form: phase / SF = K int eps_dot (L - 2z) dz
    sf = 2 * np.pi * L * 0.1 / (lam * SPEED_OF_LIGHT)
    k = strain_rate_coefficient(L, 0.1, ng, n)
    assert abs(cf / sf / (k * w * eps0 * L**2 / 6) - 1) < 1e-12


def test_mode_validation():
    with pytest.raises(ValueError, match="quality must be > 0.5"):
        StrainMode(frequency=100.0, quality=0.4)
    with pytest.raises(ValueError, match="segment"):
        segment_weight(999.0, 5.0, L)
