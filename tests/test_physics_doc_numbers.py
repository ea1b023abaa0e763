"""Numbers docs/physics.md quotes, recomputed from the code they describe (a changed model fails here)."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

DOC = (Path(__file__).resolve().parents[1] / "docs" / "physics.md").read_text(encoding="utf-8")


def _quoted(pattern: str) -> float:
    m = re.search(pattern, DOC)
    assert m, f"docs/physics.md no longer has {pattern!r}"
    return float(m.group(1))


def test_beta_1_of_the_free_fibre_and_of_dn_dt_alone_are_the_codes():
    from gyrobench.sim import coil2d

    s = coil2d.Coil2DSpec()
    _, free = s.beta_coefficients(s.inner_radius, bonded=False)
    dn = (coil2d.silica_dn_dT(s.t_hi, s.wavelength) - coil2d.silica_dn_dT(s.t_lo, s.wavelength)) / (s.t_hi - s.t_lo)
    assert _quoted(r"beta_1 = ([0-9.e-]+) /K\^2 for a free fibre") == pytest.approx(float(free), rel=5e-4)
    assert _quoted(r"for a free fibre \(([0-9.e-]+) from dn/dT alone") == pytest.approx(float(dn), rel=5e-4)


def test_interval_mean_gain_quoted_for_the_shaker_check_is_the_codes():
    from gyrobench.sim.shaker import OVERSAMPLING

    f, fs = 137.0, 50.0
    m = math.ceil(OVERSAMPLING * f / fs)
    gain = abs(math.sin(math.pi * f / fs) / (m * math.sin(math.pi * f / (m * fs))))
    sinc = abs(math.sin(math.pi * f / fs) / (math.pi * f / fs))
    assert _quoted(r"m = 11, \|H\| = ([0-9.]+);") == pytest.approx(gain, abs=5e-5)
    assert _quoted(r"gives sinc\(f/fs\) =\s+([0-9.]+)\)") == pytest.approx(sinc, abs=5e-5)
    assert m == 11


def test_source_spectrum_shape_and_arw_quoted_are_the_codes():
    from gyrobench.base import units
    from gyrobench.sim.fog_loop import LoopSpec
    from gyrobench.sim.fog_optics import OpticalBudget

    assert OpticalBudget().width_factor == 1.0  # the docs' "rectangular spectrum (the code's default)"
    assert "rectangular spectrum (the code's default" in DOC
    spec = LoopSpec()
    rect = float(units.to_deg_per_sqrt_h(spec.arw(OpticalBudget())))
    gauss = float(units.to_deg_per_sqrt_h(spec.arw(OpticalBudget(width_factor=1.505))))
    assert _quoted(r"ARW ([0-9.e-]+) instead of") == pytest.approx(gauss, rel=5e-4)
    assert _quoted(r"instead of\s+([0-9.e-]+) deg/sqrt\(h\)") == pytest.approx(rect, rel=5e-4)


def test_part_vibration_numbers_quoted_are_the_codes():
    from gyrobench.sim.coil2d import Coil2D, Coil2DSpec
    from gyrobench.sim.coil_vibration import axial_frequency, inertial_strain, pack_density, shape_weight
    from gyrobench.sim.rlg_vibration import DitherMount

    coil = Coil2D(spec=Coil2DSpec())
    assert _quoted(r"pack density rho_p = ([0-9.]+) kg/m\^3") == pytest.approx(pack_density(coil), abs=0.5)
    assert _quoted(r"epoxy 1300 kg/m\^3 by volume\), kappa = ([0-9.e-]+) per m/s\^2") == pytest.approx(
        inertial_strain(coil), rel=0.03)
    assert _quoted(r"f_1 = sqrt\(E_s A_s/\(rho_s A_s \+ rho_p A_p\)\)/\(4 H\) = ([0-9.]+) kHz") == pytest.approx(
        axial_frequency(coil) / 1e3, rel=0.01)
    assert _quoted(r"the ideal quadrupolar map gives\s+([0-9.]+) m\^2") == pytest.approx(shape_weight(coil), rel=0.05)
    assert _quoted(r"400 Hz dither c = ([0-9.e-]+) rad/\(m/s\^2\)") == pytest.approx(
        DitherMount().coupling(400.0), rel=0.01)
