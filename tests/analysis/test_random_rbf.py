"""Tests of analysis.compensation.random_rbf (RBF network with randomly fixed centres)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from sklearn.utils.estimator_checks import parametrize_with_checks

from gyrobench.analysis.compensation.random_rbf import RADBAS_B, RandomCentreRBF


@parametrize_with_checks([RandomCentreRBF(random_state=0), RandomCentreRBF(spread=3.0, goal=0.01, random_state=1)])
def test_sklearn_contract(estimator, check):
    check(estimator)


def _resonant_bias(f):
    """A resonant bias curve (two Lorentzian peaks, tens of deg/h) to exercise the goal."""
    f = np.asarray(f, dtype=float)
    return 4.0 / (1 + ((f - 180.0) / 6.0) ** 2) + 40.0 / (1 + ((f - 460.0) / 23.0) ** 2)


def test_meets_its_goal_and_generalizes(rng):
    """Noise-free samples 1 Hz apart, spread 1.2 Hz, goal 1e-4: training MSE below the goal (the
    stopping rule) and held-out RMS at the midpoints <= 2 sqrt(goal).

    The bound: the error at a midpoint is the mean of the two neighbouring node errors (MSE <= goal
    by convexity) plus the network's curvature between the nodes; requiring that term to stay within
    the same rms gives 2 sqrt(goal). It can fail: a too-narrow spread (0.3 Hz) leaves dips between
    the centres (checked below)."""
    goal = 1e-4
    f_train = np.arange(1.5, 499.0, 1.0)
    f_held = f_train[:-1] + 0.5
    net = RandomCentreRBF(spread=1.2, goal=goal, random_state=rng).fit(f_train[:, None], _resonant_bias(f_train))
    assert net.mse_ < goal
    train = net.predict(f_train[:, None])
    assert np.mean((train - _resonant_bias(f_train)) ** 2) == pytest.approx(net.mse_, rel=1e-6, abs=1e-12)
    held = net.predict(f_held[:, None])
    assert np.sqrt(np.mean((held - _resonant_bias(f_held)) ** 2)) <= 2.0 * math.sqrt(goal)
    narrow = RandomCentreRBF(spread=0.3, goal=goal, random_state=rng).fit(f_train[:, None], _resonant_bias(f_train))
    assert np.sqrt(np.mean((narrow.predict(f_held[:, None]) - _resonant_bias(f_held)) ** 2)) > 2.0 * math.sqrt(goal)


def test_is_least_squares_on_its_centres_and_minimal(rng):
    """The QR shortcut equals a direct least-squares solve on the chosen centres, and one centre fewer
    (the same random order) would not have met the goal."""
    x = np.sort(rng.uniform(0.0, 50.0, 80))
    y = np.sin(x / 4.0) + 0.1 * rng.standard_normal(80)
    goal, spread = 0.02, 3.0
    net = RandomCentreRBF(spread=spread, goal=goal, random_state=7).fit(x[:, None], y)
    perm = np.random.default_rng(7).permutation(80)
    assert 1 <= net.n_neurons_ < 79
    np.testing.assert_array_equal(net.centers_[:, 0], x[perm[: net.n_neurons_]])

    def lstsq_mse(k):
        g = np.column_stack([np.ones(80), np.exp(-((net.b_ * (x[:, None] - x[perm[:k]][None, :])) ** 2))])
        sol, *_ = np.linalg.lstsq(g, y, rcond=None)
        return sol, float(np.mean((g @ sol - y) ** 2))

    sol, mse = lstsq_mse(net.n_neurons_)
    np.testing.assert_allclose(np.r_[net.intercept_, net.weights_], sol, rtol=1e-6, atol=1e-8)
    assert mse == pytest.approx(net.mse_, rel=1e-8) and mse < goal
    assert lstsq_mse(net.n_neurons_ - 1)[1] >= goal
    assert net.b_ == pytest.approx(math.sqrt(math.log(2.0)) / spread)
    assert RADBAS_B == pytest.approx(0.8326, abs=5e-5)  # newrb's printed constant


def test_two_features_use_the_euclidean_distance(rng):
    """With 2 input columns a basis function is radbas(b ||x - c||): a network with one centre and
    the goal unreachable predicts b2 + w exp(-b^2 (dx^2 + dy^2)) at a new point."""
    X = rng.uniform(-1.0, 1.0, (30, 2))
    y = rng.standard_normal(30)
    net = RandomCentreRBF(spread=0.7, max_neurons=1, random_state=3).fit(X, y)
    p = np.array([[0.2, -0.4]])
    d2 = float(np.sum((p[0] - net.centers_[0]) ** 2))
    expected = net.intercept_ + net.weights_[0] * math.exp(-(net.b_**2) * d2)
    assert net.predict(p)[0] == pytest.approx(expected, rel=1e-12)


def test_bad_input_named():
    x = np.arange(5.0)[:, None]
    with pytest.raises(ValueError, match=r"RandomCentreRBF.spread must be a finite number > 0 \(input units\); got 0"):
        RandomCentreRBF(spread=0).fit(x, x[:, 0])
    with pytest.raises(ValueError, match=r"RandomCentreRBF.goal must be a finite number >= 0"):
        RandomCentreRBF(goal=-1.0).fit(x, x[:, 0])
    with pytest.raises(ValueError, match=r"RandomCentreRBF.max_neurons must be None or an integer >= 1; got 0"):
        RandomCentreRBF(max_neurons=0).fit(x, x[:, 0])
    with pytest.raises(TypeError, match=r"RandomCentreRBF.random_state must be None, an int or"):
        RandomCentreRBF(random_state="seed").fit(x, x[:, 0])
    with pytest.raises(ValueError, match=r"needs at least 2 samples; got n_samples = 1"):
        RandomCentreRBF().fit(x[:1], x[:1, 0])


def test_repeated_inputs_fit_the_mean_of_each_input(rng):
    """Five distinct inputs, each repeated ten times (as the static samples of a record): the centres are
    distinct, and with goal 0 the m - 1 = 4 centres and the constant interpolate the five group means
    (least squares on repeated rows), so the training MSE is the within-group mean square (closed form)."""
    levels = np.arange(5.0)
    x = np.repeat(levels, 10)
    y = np.sin(x) + 0.1 * rng.standard_normal(x.size)
    net = RandomCentreRBF(spread=1.0, random_state=rng).fit(x[:, None], y)
    assert net.n_neurons_ == 4 and np.unique(net.centers_[:, 0]).size == 4
    means = np.array([y[x == v].mean() for v in levels])
    np.testing.assert_allclose(net.predict(levels[:, None]), means, rtol=0, atol=1e-9)
    within = float(np.mean((y - np.repeat(means, 10)) ** 2))
    assert net.mse_ == pytest.approx(within, rel=1e-9)
    flat = RandomCentreRBF(random_state=0).fit(np.ones((6, 2)), np.arange(6.0))  # one distinct input
    assert flat.n_neurons_ == 0 and flat.predict(np.zeros((2, 2))) == pytest.approx([2.5, 2.5])
