"""Tests of analysis/compensation/bayes_mlp.py: Jacobian, evidence estimates, reproducibility, contract."""

from __future__ import annotations

import zlib

import numpy as np
import pytest
from scipy import stats
from sklearn.utils.estimator_checks import parametrize_with_checks

from gyrobench.analysis.compensation.bayes_mlp import BayesianRegularizedMLP


@pytest.fixture
def rng(request) -> np.random.Generator:
    """The same stream on every run, a different one for every test."""
    key = zlib.crc32(request.node.nodeid.encode())
    return np.random.default_rng([20261121, key])


@parametrize_with_checks([BayesianRegularizedMLP(hidden_units=3, epochs=30)])
def test_sklearn_contract(estimator, check):
    check(estimator)


def test_jacobian_matches_finite_differences(rng):
    net = BayesianRegularizedMLP(hidden_units=4, epochs=1, random_state=0)
    Z = rng.uniform(-1, 1, (7, 2))
    w = rng.normal(0, 1, 4 * 2 + 4 + 4 + 1)
    A, f = net._forward(w, Z)
    J = net._jacobian(w, Z, A)
    h = 1e-6
    for j in range(w.size):
        dw = np.zeros_like(w)
        dw[j] = h
        num = (net._forward(w + dw, Z)[1] - net._forward(w - dw, Z)[1]) / (2 * h)
        np.testing.assert_allclose(J[:, j], num, rtol=1e-7, atol=1e-9)


def test_nguyen_widrow_initialisation():
    net = BayesianRegularizedMLP(hidden_units=10)
    w = net._init_weights(1, np.random.default_rng(0))
    W1, b1, W2, b2 = net._unpack(w, 1)
    np.testing.assert_allclose(np.abs(W1[:, 0]), 0.7 * 10.0, rtol=1e-12)  # |w_h| = 0.7 H^(1/p)
    np.testing.assert_allclose(b1, 7.0 * np.linspace(-1, 1, 10) * np.sign(W1[:, 0]), rtol=1e-12)
    assert np.all(np.abs(W2) <= 0.5) and b2 == 0.0


def test_noise_variance_from_the_evidence(rng):
    """1/(2 beta) = E_D/(n - gamma) estimates the noise variance: chi-square(n - gamma) bound at 1e-6."""
    n, sigma = 400, 0.05
    x = np.linspace(-1.0, 1.0, n)[:, None]
    y = np.sin(np.pi * x[:, 0]) + sigma * rng.standard_normal(n)
    net = BayesianRegularizedMLP(hidden_units=10, epochs=300, random_state=0).fit(x, y)
    assert 0 < net.gamma_ < 10 * 1 + 10 + 10 + 1
    var_hat = net.y_half_**2 / (2 * net.beta_)  # back to target units
    dof = n - net.gamma_
    lo, hi = stats.chi2.ppf([0.5e-6, 1 - 0.5e-6], dof) / dof
    assert lo < var_hat / sigma**2 < hi


def test_fits_a_saturation_curve():
    x = np.linspace(-3600.0, 3600.0, 21)
    out = np.where(
        np.abs(x) <= 1800, x, np.sign(x) * (1800 + 987.6 * np.tanh((np.abs(x) - 1800) / 987.6))
    )
    net = BayesianRegularizedMLP(random_state=1).fit(out[:, None], x)
    assert np.max(np.abs(net.predict(out[:, None]) - x)) < 0.01 * 3600


def test_same_random_state_same_network():
    x = np.linspace(-1, 1, 30)[:, None]
    y = x[:, 0] ** 3
    a = BayesianRegularizedMLP(hidden_units=4, epochs=50, random_state=3).fit(x, y).predict(x)
    b = BayesianRegularizedMLP(hidden_units=4, epochs=50, random_state=3).fit(x, y).predict(x)
    c = BayesianRegularizedMLP(hidden_units=4, epochs=50, random_state=4).fit(x, y).predict(x)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)


def test_accepts_a_generator_as_random_state():
    x = np.linspace(-1, 1, 30)[:, None]
    a = BayesianRegularizedMLP(hidden_units=3, epochs=5, random_state=np.random.default_rng(7)).fit(
        x, x[:, 0]
    )
    b = BayesianRegularizedMLP(hidden_units=3, epochs=5, random_state=7).fit(x, x[:, 0])
    np.testing.assert_array_equal(a.W1_, b.W1_)


def test_affine_change_of_units_is_invisible():
    """Inputs and targets are min-max scaled: deg/s in, rad/s out gives the same network."""
    x = np.linspace(-3.0, 3.0, 25)[:, None]
    y = np.tanh(x[:, 0])
    a = BayesianRegularizedMLP(hidden_units=3, epochs=20, random_state=0).fit(x, y)
    b = BayesianRegularizedMLP(hidden_units=3, epochs=20, random_state=0).fit(
        1000.0 * x + 5.0, 0.01 * y - 2.0
    )
    np.testing.assert_allclose(
        b.predict(1000.0 * x + 5.0), 0.01 * a.predict(x) - 2.0, rtol=1e-8, atol=1e-10
    )


# ------------------------------------------------------------------ bad input
@pytest.mark.parametrize(
    ("kw", "msg"),
    [
        ({"hidden_units": 0}, "hidden_units must be an integer >= 1; got 0"),
        ({"epochs": 0}, "epochs must be an integer >= 1; got 0"),
        ({"mu": -1.0}, "mu must be a finite number > 0; got -1.0"),
        ({"mu_dec": 1.5}, r"mu_dec must be in \(0, 1\); got 1.5"),
        ({"mu_inc": 0.5}, "mu_inc must be a finite number > 1; got 0.5"),
        ({"mu_max": 1e-3}, "mu_max must be a finite number > mu"),
        ({"min_grad": -1.0}, "min_grad must be a finite number >= 0"),
    ],
)
def test_rejects_bad_parameters(kw, msg):
    with pytest.raises(ValueError, match=msg):
        BayesianRegularizedMLP(**kw).fit([[0.0], [1.0], [2.0]], [0.0, 1.0, 2.0])


def test_rejects_nan_target():
    with pytest.raises(ValueError, match="NaN"):
        BayesianRegularizedMLP().fit([[0.0], [1.0], [2.0]], [0.0, np.nan, 2.0])
