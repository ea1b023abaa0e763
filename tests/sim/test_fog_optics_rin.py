"""The excess-RIN coefficient of sim.fog_optics measured on simulated thermal light (issue 26).

Thermal (broadband, Gaussian) light: the field is a circular complex Gaussian process; its
intensity I = |E|^2 fluctuates. For polarised light with a rectangular spectrum of width dnu the
one-sided relative intensity-noise PSD at low frequency is 2/dnu (Goodman, Statistical Optics,
1985, sec. 9.2-9.3: count variance <K> + <K>^2 tau_c / T, tau_c = 1/dnu); two independent
polarisations (depolarised light) halve it. The test simulates the field, measures the variance
of block means of I (a white one-sided PSD S1 gives var = S1 / (2T)), and compares with what
:class:`~gyrobench.sim.fog_optics.OpticalBudget` uses: the two hypotheses 1/dnu and 2/dnu differ
by 2x, far outside the estimate's statistical error.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from gyrobench.base.units import SPEED_OF_LIGHT
from gyrobench.sim.fog_optics import OpticalBudget


def _thermal_intensity(rng: np.random.Generator, n: int, dnu: float, modes: int) -> np.ndarray:
    """Intensity of ``modes`` independent polarisation modes of thermal light, rectangular spectrum of
    width ``dnu`` (in units of the sampling rate), sampled at rate 1."""
    f = np.fft.fftfreq(n)
    band = np.abs(f) < dnu / 2
    out = np.zeros(n)
    for _ in range(modes):
        spec = np.where(band, rng.standard_normal(n) + 1j * rng.standard_normal(n), 0.0)
        out += np.abs(np.fft.ifft(spec)) ** 2
    return out


def _measured_rin_times_dnu(rng: np.random.Generator, modes: int) -> tuple[float, float]:
    """One-sided RIN x dnu from block means, and its standard error (chi-square, K - 1 dof)."""
    n, dnu, t = 2**21, 0.05, 1000  # T dnu = 50 coherence times per block, 2097 blocks
    i = _thermal_intensity(rng, n, dnu, modes)
    blocks = i[: n // t * t].reshape(-1, t).mean(axis=1)
    k = blocks.size
    est = 2.0 * t * blocks.var(ddof=1) / i.mean() ** 2 * dnu
    return est, est * math.sqrt(2.0 / (k - 1))


@pytest.mark.parametrize("polarized, modes", [(True, 1), (False, 2)])
def test_budget_rin_equals_the_measured_intensity_noise_of_thermal_light(polarized, modes):
    """The budget's one-sided RIN (2/dnu_eff polarised, 1/dnu_eff depolarised) agrees with the
    simulated light within 4 standard errors (false alarm 6e-5 per case); the block length adds a
    bias of order 1/(T dnu) = 2 %, inside that band (4 sigma ~ 12 %)."""
    est, se = _measured_rin_times_dnu(np.random.default_rng(26 + modes), modes)
    ob = OpticalBudget(polarized=polarized)  # rectangular spectrum: width_factor 1
    lam = 1550e-9
    dnu_eff = ob.effective_bandwidth(lam)
    ib = ob.bias_current(math.pi / 2)
    rin_times_dnu = ob.current_psd(math.pi / 2, lam)["rin"] / ib**2 * dnu_eff  # dimensionless
    assert abs(est - rin_times_dnu) < 4 * se + 0.02 * rin_times_dnu, (est, se, rin_times_dnu)
    # the other convention (a factor 2 away) is rejected by the same measurement
    assert abs(est - rin_times_dnu / 2) > 4 * se + 0.02 * rin_times_dnu


def test_default_budget_rin_in_db_per_hz():
    """The defaults (30 nm at 1550 nm, rectangular): dnu_eff = c dlambda/lambda^2 = 3.745 THz;
    polarised RIN 2/dnu_eff = 5.34e-13 /Hz = -122.7 dB/Hz (the depolarised -125.7 dB/Hz is the
    lambda^2/(c dlambda) printed for FOG sources, Lefevre sec. 5.3)."""
    ob = OpticalBudget()
    lam = 1550e-9
    dnu = SPEED_OF_LIGHT * 30e-9 / lam**2
    assert ob.effective_bandwidth(lam) == pytest.approx(3.745e12, rel=1e-3)
    ib = ob.bias_current(math.pi / 2)
    rin = ob.current_psd(math.pi / 2, lam)["rin"] / ib**2  # [1/Hz]
    assert 10 * math.log10(rin) == pytest.approx(-122.7, abs=0.05)
    assert 10 * math.log10(1.0 / dnu) == pytest.approx(-125.7, abs=0.05)
