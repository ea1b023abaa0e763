"""Tests of analysis/compensation/stepwise.py (MATLAB stepwisefit semantics)."""

from __future__ import annotations

import zlib

import numpy as np
import pytest
from scipy import stats
from sklearn.utils.estimator_checks import parametrize_with_checks

from gyrobench.analysis.compensation.stepwise import StepwiseRegression


@pytest.fixture
def rng(request) -> np.random.Generator:
    key = zlib.crc32(request.node.nodeid.encode())
    return np.random.default_rng([20261121, key])


@parametrize_with_checks([StepwiseRegression()])
def test_sklearn_compatible(estimator, check):
    check(estimator)


def test_recovers_true_terms_and_coefficients(rng):
    """y = 1 + 2 x0 - 1.5 x3 + 0.8 x5 + noise among 8 candidates: exactly {0, 3, 5} kept.

    Coefficients within z * stderr of the truth, z at a two-sided false-alarm rate of 1e-6.
    """
    n, p = 300, 8
    X = rng.standard_normal((n, p))
    beta = np.zeros(p)
    beta[[0, 3, 5]] = [2.0, -1.5, 0.8]
    y = 1.0 + X @ beta + 0.3 * rng.standard_normal(n)
    m = StepwiseRegression().fit(X, y)
    # the true terms are in; a noise term may also enter (rate tested below)
    assert set(np.flatnonzero(m.support_)) >= {0, 3, 5}
    z = stats.norm.ppf(1 - 5e-7)
    sel = m.support_
    assert np.all(np.abs(m.coef_[sel] - beta[sel]) <= z * m.coef_stderr_[sel])
    assert np.all(m.coef_[~sel] == 0.0)
    # entries happen strongest first
    assert [h[1] for h in m.history_[:3]] == [0, 3, 5]


def test_recovers_exactly_the_true_set_when_others_are_orthogonal():
    """Candidates exactly orthogonal to the response and to the true terms have F = 0 and never enter."""
    n = 64
    t = np.arange(n)
    cols = [np.cos(2 * np.pi * k * t / n) for k in (1, 2, 3, 4, 5)]
    X = np.column_stack(cols)
    y = 3.0 * X[:, 1] + 2.0 * X[:, 2] - 1.0 * X[:, 4] + 0.01 * np.sin(2 * np.pi * 7 * t / n)
    m = StepwiseRegression().fit(X, y)
    assert m.support_.tolist() == [False, True, True, False, True]
    np.testing.assert_allclose(m.coef_, [0.0, 3.0, 2.0, 0.0, -1.0], rtol=0, atol=1e-12)


@pytest.mark.slow  # statistical calibration over many fits (tens of seconds): slow tier
def test_noise_regressor_enters_at_the_stated_rate(rng):
    """Two real terms and one pure-noise candidate: the noise term's partial F (given the real
    terms) is exactly F(1, n - 4) under the null, so it enters with probability p_enter = 0.05.

    2000 trials; the count must lie in the binomial(2000, 0.05) interval at a two-sided
    false-alarm rate of 1e-6.
    """
    trials, n = 2000, 40
    hits = 0
    for _ in range(trials):
        X = rng.standard_normal((n, 3))
        y = 3.0 * X[:, 0] - 2.0 * X[:, 1] + rng.standard_normal(n)
        m = StepwiseRegression().fit(X, y)
        assert m.support_[0] and m.support_[1]
        hits += bool(m.support_[2])
    lo, hi = stats.binom.ppf([5e-7, 1 - 5e-7], trials, 0.05)
    assert lo <= hits <= hi, (hits, lo, hi)


def test_pure_noise_model_selects_nothing_at_rate(rng):
    """One pure-noise candidate and y pure noise: the term enters with probability 0.05 (exact F test)."""
    trials, n = 2000, 25
    hits = 0
    for _ in range(trials):
        X = rng.standard_normal((n, 1))
        y = rng.standard_normal(n)
        hits += bool(StepwiseRegression().fit(X, y).support_[0])
    lo, hi = stats.binom.ppf([5e-7, 1 - 5e-7], trials, 0.05)
    assert lo <= hits <= hi, (hits, lo, hi)


def test_table_statistics_closed_form(rng):
    """R, R^2, adjusted R^2, RMSE, F, significance F and coefficient stderr against direct formulas."""
    n = 50
    X = rng.standard_normal((n, 3))
    y = 0.5 + X @ np.array([1.0, -2.0, 0.7]) + 0.5 * rng.standard_normal(n)
    m = StepwiseRegression().fit(X, y)
    assert m.support_.all()
    A = np.column_stack([np.ones(n), X])
    beta, *_ = np.linalg.lstsq(A, y, rcond=None)
    r = y - A @ beta
    rss, tss, p = r @ r, ((y - y.mean()) ** 2).sum(), 3
    r2 = 1 - rss / tss
    f = ((tss - rss) / p) / (rss / (n - p - 1))
    np.testing.assert_allclose(m.coef_, beta[1:], rtol=1e-10)
    assert m.intercept_ == pytest.approx(beta[0], rel=1e-10)
    assert m.r2_ == pytest.approx(r2, rel=1e-12)
    assert m.multiple_r_ == pytest.approx(np.sqrt(r2), rel=1e-12)
    assert m.adj_r2_ == pytest.approx(1 - (1 - r2) * (n - 1) / (n - p - 1), rel=1e-12)
    assert m.rmse_ == pytest.approx(np.sqrt(rss / (n - p - 1)), rel=1e-12)
    assert m.f_statistic_ == pytest.approx(f, rel=1e-10)
    assert m.significance_f_ == pytest.approx(stats.f.sf(f, p, n - p - 1), rel=1e-8)
    cov = rss / (n - p - 1) * np.linalg.inv(A.T @ A)
    np.testing.assert_allclose(m.coef_stderr_, np.sqrt(np.diag(cov))[1:], rtol=1e-8)
    # p-value of removing a term equals the t-test p-value of its coefficient
    t = beta[1:] / np.sqrt(np.diag(cov))[1:]
    np.testing.assert_allclose(m.pvalues_, 2 * stats.t.sf(np.abs(t), n - p - 1), rtol=1e-6)
    np.testing.assert_allclose(m.predict(X), A @ beta, rtol=1e-10)


def test_term_entered_early_is_removed_later(rng):
    """Classic removal: x0 ~ x1 + x2 enters first; once x1 and x2 are in, x0 is redundant and leaves."""
    n = 200
    x1, x2 = rng.standard_normal(n), rng.standard_normal(n)
    x0 = x1 + x2 + 0.3 * rng.standard_normal(n)
    y = x1 + x2 + 0.05 * rng.standard_normal(n)
    m = StepwiseRegression().fit(np.column_stack([x0, x1, x2]), y)
    assert m.history_[0][:2] == ("enter", 0)
    assert ("remove", 0) in [h[:2] for h in m.history_]
    assert m.support_.tolist() == [False, True, True]


def test_empty_model_statistics():
    """A candidate exactly uncorrelated with y (F = 0, p = 1) never enters: constant model."""
    x = np.tile([1.0, 1.0, -1.0, -1.0], 10)
    y = 5.0 + np.tile([1.0, -1.0, 1.0, -1.0], 10)
    m = StepwiseRegression().fit(x[:, None], y)
    assert not m.support_.any() and m.history_ == []
    assert m.r2_ == 0.0 and m.multiple_r_ == 0.0
    assert np.isnan(m.f_statistic_) and np.isnan(m.significance_f_)
    assert m.intercept_ == pytest.approx(5.0, rel=1e-12)
    assert m.pvalues_[0] == pytest.approx(1.0)
    np.testing.assert_allclose(m.predict(x[:, None]), 5.0, rtol=1e-12)


# ------------------------------------------------------------------ bad input
def test_bad_fewer_samples_than_regressors(rng):
    with pytest.raises(
        ValueError, match=r"more observations than regressors.*n_samples = 10, n_features = 11"
    ):
        StepwiseRegression().fit(rng.standard_normal((10, 11)), rng.standard_normal(10))


def test_bad_zero_variance_regressor(rng):
    X = rng.standard_normal((50, 4))
    X[:, 2] = 25.0
    with pytest.raises(ValueError, match=r"column\(s\) \[2\] have zero variance"):
        StepwiseRegression().fit(X, rng.standard_normal(50))


def test_bad_p_enter_above_p_remove(rng):
    with pytest.raises(
        ValueError, match=r"p_enter must be <= p_remove; got p_enter=0.2 > p_remove=0.1"
    ):
        StepwiseRegression(p_enter=0.2, p_remove=0.1).fit(
            rng.standard_normal((20, 2)), rng.standard_normal(20)
        )


def test_bad_probability(rng):
    with pytest.raises(ValueError, match=r"p_enter must be a probability in \(0, 1\); got 0"):
        StepwiseRegression(p_enter=0).fit(rng.standard_normal((20, 2)), rng.standard_normal(20))
