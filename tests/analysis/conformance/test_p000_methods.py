"""Conformance of paper 000's methods on constructed records: the db4 split and the two bias fits.

db4 split. A record = slow bias b(t) (a sine of period 400 samples, far inside the band of the
level-6 approximation, below fs / 2^7) + white noise N(0, sigma^2). The db4 wavelet is
orthogonal, so the level-6 approximation of white noise keeps on average 2^-6 of its variance
(the other 1 - 2^-6 goes to d1..d6); the approximation's error against b is that share of the
noise plus the bias's own leakage into the details (negligible at this period). The mean of
(a6 - b)^2 over the record is then sigma^2 2^-6 times a chi^2-like ratio whose effective degrees
of freedom are about n 2^-6; its ALPHA upper quantile with that many degrees of freedom is the
bound. A broken variant (the level-2 approximation) keeps 2^-2 of the noise and fails it.

Bias fits (against vibration frequency, 1-500 Hz bins). LS 4th order on a bias that is a
4th-order polynomial: the fit's error against the truth is the projection of the bins' noise
on a 5-dimensional space, so its sum of squares over sigma_b^2 is chi^2_5 exactly; the bound is
its ALPHA upper quantile over the n bins. The random-centre RBF (spread 12 Hz, the half width
of the resonance; goal twice the bins' noise variance) on a bias with a resonance a 4th-order
polynomial cannot follow: the RBF meets its goal with fewer centres than bins and its error
against the truth is below the goal, while the LS fit's error is above its noise floor.
"""

from __future__ import annotations

import numpy as np
from scipy.stats import chi2

from gyrobench.analysis.compensation.random_rbf import RandomCentreRBF
from gyrobench.analysis.wavelet import decompose

ALPHA = 1e-3
SIGMA = 1.0
N_REC = 2**14


def _record(seed):
    rng = np.random.default_rng([20261201, seed])
    t = np.arange(N_REC)
    bias = 3.0 * np.sin(2 * np.pi * t / 400.0) + 1.0
    return bias, bias + SIGMA * rng.standard_normal(N_REC)


def _approx_error_bound(level):
    dof = N_REC / 2**level
    return SIGMA**2 / 2**level * chi2.isf(ALPHA, dof) / dof


def test_db4_level6_approximation_recovers_the_bias_to_the_derived_noise_share():
    bias, x = _record(0)
    dec = decompose(x, fs=1.0, level=10)
    err = float(np.mean((dec.approx(6) - bias) ** 2))
    assert err < _approx_error_bound(6)


def test_the_level2_approximation_keeps_too_much_noise():
    """Broken variant: the split taken at level 2."""
    bias, x = _record(0)
    dec = decompose(x, fs=1.0, level=10)
    assert float(np.mean((dec.approx(2) - bias) ** 2)) > _approx_error_bound(6)


F = np.arange(1.0, 501.0, 5.0)  # bin centres [Hz]
SIGMA_B = 0.01  # scatter of a bin mean [deg/h]


def _bins(curve, seed):
    rng = np.random.default_rng([20261201, 100 + seed])
    return curve(F), curve(F) + SIGMA_B * rng.standard_normal(F.size)


def quartic(f):
    u = f / 250.0 - 1.0
    return 0.5 + 0.3 * u - 0.2 * u**2 + 0.4 * u**3 + 0.1 * u**4


def resonant(f):
    return quartic(f) + 2.0 / (1.0 + ((f - 180.0) / 12.0) ** 2)


LS_BOUND = SIGMA_B**2 * chi2.isf(ALPHA, 5) / F.size


def test_ls_4th_order_reaches_the_noise_floor_on_a_quartic_bias():
    truth, y = _bins(quartic, 0)
    fit = np.polynomial.Polynomial.fit(F, y, 4)
    assert float(np.mean((fit(F) - truth) ** 2)) < LS_BOUND


def test_ls_2nd_order_does_not():
    """Broken variant: the LS order set to 2."""
    truth, y = _bins(quartic, 0)
    fit = np.polynomial.Polynomial.fit(F, y, 2)
    assert float(np.mean((fit(F) - truth) ** 2)) > LS_BOUND


def test_rbf_follows_a_resonance_the_ls_fit_cannot():
    truth, y = _bins(resonant, 1)
    goal = 2 * SIGMA_B**2
    net = RandomCentreRBF(spread=12.0, goal=goal, random_state=0).fit(F[:, None], y)
    assert net.mse_ < goal and net.n_neurons_ < F.size - 1
    rbf_err = float(np.mean((net.predict(F[:, None]) - truth) ** 2))
    ls = np.polynomial.Polynomial.fit(F, y, 4)
    ls_err = float(np.mean((ls(F) - truth) ** 2))
    assert rbf_err < goal and ls_err > LS_BOUND
