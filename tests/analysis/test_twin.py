"""Tests of analysis/twin.py: the twin pass rule's behaviour, its power and its false-alarm rate."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import binom

from gyrobench.analysis.allan import allan_deviation, fit_noise
from gyrobench.analysis.twin import FAMILY_ALPHA, compare_twin
from gyrobench.sim.noise import NoiseModel


def _white(seed, n=4096, scale=1.0):
    return allan_deviation(scale * np.random.default_rng(seed).standard_normal(n), 1.0)


def test_a_curve_is_its_own_perfect_twin():
    c = _white(0)
    res = compare_twin(c, c)
    assert res.passed and np.all(res.ratio == 1.0)
    # the band holds 1 and widens as the edf falls (longer taus)
    assert np.all(res.ratio_low < 1) and np.all(res.ratio_high > 1)
    assert np.all(np.diff(res.ratio_high - res.ratio_low) > 0)
    assert res.n_taus == len(c.tau) and "family-wise" in res.rule


def test_a_twin_twice_too_noisy_fails_and_only_where_compared():
    real, twin = _white(1), _white(2, scale=2.0)
    res = compare_twin(real, twin)
    assert not res.passed
    # at the shortest tau (edf in the thousands) a factor 2 is far outside
    assert not res.inside[0] and res.ratio[0] == pytest.approx(2.0, rel=0.1)
    # comparing only the last tau (edf ~ 2) cannot see it: the band there is wider than x2
    last = compare_twin(real, twin, taus=real.tau[-1:])
    assert last.passed and last.ratio_high[0] > 2.0


def test_the_simultaneous_band_is_wider_than_the_per_tau_band():
    c = _white(3)
    one = compare_twin(c, c, taus=c.tau[:1])
    all_ = compare_twin(c, c)
    assert one.per_tau_alpha == pytest.approx(FAMILY_ALPHA, rel=1e-12)
    assert all_.per_tau_alpha < FAMILY_ALPHA / len(c.tau) * 1.05  # Sidak ~ Bonferroni for small alpha
    assert all_.ratio_high[0] > one.ratio_high[0]


def test_bad_input_is_one_line():
    c = _white(4)
    with pytest.raises(TypeError, match="real must be an AllanCurve"):
        compare_twin(np.ones(3), c)
    with pytest.raises(ValueError, match="twin must have the real curve's taus"):
        compare_twin(c, _white(5, n=2048))
    with pytest.raises(ValueError, match=r"family_alpha must be in \(0, 1\)"):
        compare_twin(c, c, family_alpha=1.0)
    with pytest.raises(ValueError, match="is not a tau of the curves"):
        compare_twin(c, c, taus=[3.3])
    with pytest.raises(ValueError, match="at least one"):
        compare_twin(c, c, taus=[])
    with pytest.raises(ValueError, match="kind must be 'overlapping' or 'standard'"):
        compare_twin(allan_deviation(np.random.default_rng(0).standard_normal(512), 1.0, kind="modified"), c)


# The false-alarm rate of the rule, over S seeds of a synthetic static record (N, B and K all
# visible in 2e4 samples at 1 Hz), for a perfect twin (the true model simulated independently):
# the failure count may exceed the binomial(S, FAMILY_ALPHA) quantile at 1 - 1e-3 only with
# probability 1e-3 if the rule holds its rate. The fitted twin that `gyrobench twin` builds is
# checked the same way in tests/scenarios/test_cli_twin.py.
#
# S = 100 (was 200; ~0.35 s a seed): the bound is binom.isf(1e-3, 100, 0.05) = 13, exceeded with
# probability 4.6e-4 <= 1e-3 at the nominal rate. The defect this guards is a band too narrow for
# the m = 13 compared taus, e.g. the Sidak correction lost (each tau at 0.05): measured on these
# seeds 45/100 fail that way, and P(Binomial(100, 0.45) <= 13) < 1e-10, so it cannot pass. Power
# against a smaller excess: 0.95 at a true rate 0.20 (4x), 0.65 at 0.15. Measured: 7/100 (bound 13).
S = 100


@pytest.mark.slow
def test_false_alarm_rate_of_the_pass_rule_over_seeds():
    truth = NoiseModel(angle_random_walk=1e-3, bias_instability=1e-4, rate_random_walk=2e-6)
    n, fs = 20_000, 1.0
    fails = 0
    for s in range(S):
        rng = np.random.default_rng([7, s])
        real = truth.generate(n, fs, rng=rng)
        fit = fit_noise(real, fs)
        twin = allan_deviation(truth.generate(n, fs, rng=rng), fs)
        fails += not compare_twin(fit.curve, twin, taus=fit.tau_used).passed
    assert fails <= binom.isf(1e-3, S, FAMILY_ALPHA), fails
