"""Tests of analysis/thermal_regression.py: block regressors, block bias stability, stepwise tables."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats
from sklearn.exceptions import NotFittedError

from gyrobench.analysis.compensation.stepwise import StepwiseRegression
from gyrobench.analysis.metrics import bias_stability
from gyrobench.analysis.thermal_regression import (
    StepwiseTable,
    block_bias_stability,
    selection_frequency,
    stepwise_table,
    two_sensor_blocks,
)


# ----------------------------------------------------------------------------- two_sensor_blocks
def test_blocks_of_two_ramps_closed_form():
    """Linear ramps at 1 Hz: a block mean is the ramp at the block's mean sample time, the rates
    are the slope, the gradient the offset; the 50-sample tail is dropped."""
    fs, block_s, slope = 1.0, 100.0, 1.0 / 180.0  # 1 degC per 3 min
    t = np.arange(2050) / fs
    b = two_sensor_blocks(-40.0 + slope * t, -41.5 + slope * t, fs, block_s=block_s, window_s=500.0)
    assert b.X.shape == (20, 11) and b.t1.shape == b.t2.shape == (20,)
    centre = np.arange(20) * block_s + 49.5  # mean of samples k*100 .. k*100 + 99
    t1 = -40.0 + slope * centre
    np.testing.assert_allclose(b.t1, t1, rtol=1e-12)
    np.testing.assert_allclose(b.t2, -41.5 + slope * centre, rtol=1e-12)
    cols = {
        0: t1,  # x1 = T1
        2: np.full(20, slope),  # x3 = dT1/dt
        3: np.full(20, slope),  # x4 = dT2/dt
        4: t1 * slope,  # x5 = T1 dT1/dt
        6: np.full(20, slope**2),  # x7
        8: np.full(20, 1.5),  # x9 = T1 - T2
        10: t1 * 1.5,  # x11 = T1 (T1 - T2)
    }
    for j, expected in cols.items():
        np.testing.assert_allclose(b.X[:, j], expected, rtol=1e-9, atol=1e-14, err_msg=f"x{j + 1}")
    np.testing.assert_allclose(b.X[:, 9], 0.0, atol=1e-14)  # x10: the gradient does not change


def test_blocks_refuse_short_logs():
    with pytest.raises(ValueError, match="shorter than one block"):
        two_sensor_blocks(np.zeros(50), np.zeros(50), 1.0, block_s=100.0, window_s=500.0)
    with pytest.raises(ValueError, match=r"window_s = 500.0 s spans 5 samples but x has only 3"):
        two_sensor_blocks(np.zeros(300), np.zeros(300), 1.0, block_s=100.0, window_s=500.0)
    with pytest.raises(ValueError, match="x must be finite"):
        two_sensor_blocks([np.nan] * 300, np.zeros(300), 1.0, block_s=100.0, window_s=500.0)


# ----------------------------------------------------------------------------- block_bias_stability
def test_block_bias_stability_is_the_gjb_metric_of_the_block_means():
    """On 100-s block means it equals metrics.bias_stability of the raw record (GJB 100-s means)."""
    rng = np.random.default_rng(20261127)
    fs, n = 10.0, 30_000
    raw = 0.01 * rng.standard_normal(n) + 0.002 * np.sin(np.arange(n) / 3000.0)
    means = raw.reshape(-1, 1000).mean(axis=1)
    got = block_bias_stability(means, np.zeros_like(means))
    assert got == pytest.approx(bias_stability(raw, fs, block_s=100.0), rel=1e-12)
    # a reference common to both shifts nothing: it is subtracted sample by sample
    ref = np.linspace(-1.0, 1.0, len(means))
    assert block_bias_stability(means + ref, ref) == pytest.approx(got, rel=1e-12)


def test_block_bias_stability_of_white_blocks_within_chi_square_bounds():
    """n white block means of sd sigma: (n - 1) s^2 / sigma^2 ~ chi2(n - 1); bounds at 1e-6."""
    rng = np.random.default_rng(4)
    n, sigma = 400, 0.03
    s = block_bias_stability(sigma * rng.standard_normal(n), np.zeros(n))
    lo, hi = stats.chi2.ppf([0.5e-6, 1 - 0.5e-6], n - 1)
    assert math.sqrt(lo / (n - 1)) * sigma <= s <= math.sqrt(hi / (n - 1)) * sigma


def test_block_bias_stability_bad_input():
    with pytest.raises(ValueError, match=r"same length; got shapes \(3,\) and \(2,\)"):
        block_bias_stability([1.0, 2.0, 3.0], [0.0, 0.0])
    with pytest.raises(ValueError, match="at least 2 blocks; got 1"):
        block_bias_stability([1.0], [0.0])


# ----------------------------------------------------------------------------- stepwise_table
@pytest.fixture(scope="module")
def fitted() -> tuple[StepwiseRegression, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(7)
    X = rng.standard_normal((300, 4))
    y = 1.0 + 2.0 * X[:, 0] - 3.0 * X[:, 2] + 0.1 * rng.standard_normal(300)
    return StepwiseRegression().fit(X, y), X, y


def test_stepwise_table_names_the_model(fitted):
    m, X, y = fitted
    t = stepwise_table(m, ["a", "b", "c", "d"])
    assert isinstance(t, StepwiseTable)
    assert t.selected == ("a", "c")  # the two terms the response depends on
    assert {s[1] for s in t.steps if s[0] == "enter"} >= {"a", "c"}
    assert all(isinstance(v, float) for v in (t.multiple_r, t.r2, t.adj_r2, t.rmse, t.intercept))
    assert t.coef[1] == 0.0 and math.isnan(t.coef_stderr[1])  # excluded term
    # the value object applies the same model as the estimator
    np.testing.assert_allclose(t.predict(X), m.predict(X), rtol=1e-12)
    # the table's statistics are those of the final least-squares fit: R^2 = 1 - RSS/TSS
    y_hat = t.predict(X)
    r2 = 1.0 - np.sum((y - y_hat) ** 2) / np.sum((y - y.mean()) ** 2)
    assert t.r2 == pytest.approx(r2, rel=1e-12)


def test_stepwise_table_bad_input(fitted):
    m, X, _ = fitted
    with pytest.raises(ValueError, match="labels must name each of the 4 columns; got 3 labels"):
        stepwise_table(m, ["a", "b", "c"])
    with pytest.raises(NotFittedError):
        stepwise_table(StepwiseRegression(), ["a"])
    t = stepwise_table(m, ["a", "b", "c", "d"])
    with pytest.raises(ValueError, match=r"X must have shape \(n, 4\); got \(300, 3\)"):
        t.predict(X[:, :3])


# ----------------------------------------------------------------------------- selection_frequency
def test_selection_frequency_counts_models():
    got = selection_frequency([("x1", "x3"), ("x3",), ()], ["x1", "x2", "x3"])
    assert got == {"x1": 1 / 3, "x2": 0.0, "x3": 2 / 3}
    assert list(got) == ["x1", "x2", "x3"]


def test_selection_frequency_bad_input():
    with pytest.raises(ValueError, match="at least one model's selection"):
        selection_frequency([], ["x1"])
    with pytest.raises(ValueError, match=r"not in labels: \['x9'\]"):
        selection_frequency([("x9",)], ["x1"])
