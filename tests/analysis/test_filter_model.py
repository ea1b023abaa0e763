"""analysis.filter_model: process noise from a fit, the Gauss-Markov conversion and the overbound."""

from __future__ import annotations

import numpy as np

from gyrobench.analysis.allan import deviation_bounds, fit_noise
from gyrobench.analysis.filter_model import GM_PEAK_ADEV, GM_PEAK_TAU, filter_model
from gyrobench.sim.noise import GaussMarkov, NoiseModel


def test_gauss_markov_peak_constants_match_a_simulated_gm_curve():
    """Independent check: the sampled GM Allan variance of sim.noise (ar1_avar), not the closed form retyped."""
    gm = GaussMarkov(sigma=1.0, correlation_time=50.0)
    tau = np.linspace(20.0, 300.0, 28001)
    adev = np.sqrt(gm.avar_sampled(tau, 10.0))
    i = int(np.argmax(adev))
    assert abs(tau[i] / 50.0 - GM_PEAK_TAU) < 0.01 and abs(adev[i] - GM_PEAK_ADEV) < 2e-3


def test_overbound_lies_above_the_upper_95_bound_at_every_tau():
    rng = np.random.default_rng(3)
    y = NoiseModel(angle_random_walk=1e-3, bias_instability=1e-4, rate_random_walk=1e-6).generate(50_000, 10.0,
                                                                                                  rng=rng)
    fit = fit_noise(y, 10.0, tau_min="auto")
    plain, over = filter_model(fit), filter_model(fit, overbound=True)
    assert plain.inflation == 1.0 and over.inflation >= 1.0
    _, hi = deviation_bounds(fit.curve.deviation, fit.curve.edf, 0.95)
    model = over.inflation * np.sqrt(fit.avar(fit.curve.tau))
    assert np.all(model >= hi * (1 - 1e-12))
    # the smallest such factor: 1 % less fails somewhere
    assert np.any(0.99 * model < hi)
    assert over.white_density == over.inflation * plain.white_density
    assert np.isclose(plain.white_variance_per_sample, plain.white_density**2 * 10.0)
