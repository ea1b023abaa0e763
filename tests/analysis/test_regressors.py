"""Tests of analysis/regressors.py: the eleven two-sensor thermal regressors."""

from __future__ import annotations

import numpy as np
import pytest

from gyrobench.analysis.regressors import REGRESSOR_LABELS, REGRESSOR_NAMES, two_sensor_regressors


def test_names_and_labels():
    assert len(REGRESSOR_NAMES) == len(REGRESSOR_LABELS) == 11
    assert REGRESSOR_LABELS[0] == "x1" and REGRESSOR_LABELS[-1] == "x11"


def test_quadratic_temperatures_closed_form():
    """Savitzky-Golay (quadratic) derivatives are exact for quadratic inputs: every column exact."""
    fs = 0.01  # 100-s blocks
    t = np.arange(60) / fs
    t1 = -40.0 + 5e-3 * t + 2e-7 * t**2
    t2 = -41.5 + 4e-3 * t - 1e-7 * t**2
    X = two_sensor_regressors(t1, t2, fs, window_s=500.0)
    d1 = 5e-3 + 4e-7 * t
    d2 = 4e-3 - 2e-7 * t
    g = t1 - t2
    expected = np.column_stack([t1, t2, d1, d2, t1 * d1, t2 * d2, d1**2, d2**2, g, d1 - d2, t1 * g])
    np.testing.assert_allclose(X, expected, rtol=1e-10, atol=1e-14)


def test_gradient_terms_on_ramp():
    fs = 1.0
    t = np.arange(1000.0)
    X = two_sensor_regressors(20 + 0.01 * t, 18 + 0.01 * t, fs, window_s=31.0)
    np.testing.assert_allclose(X[:, 8], 2.0, rtol=1e-12)
    np.testing.assert_allclose(X[:, 9], 0.0, atol=1e-12)
    np.testing.assert_allclose(X[:, 10], 2.0 * (20 + 0.01 * t), rtol=1e-12)


def test_bad_length_mismatch():
    with pytest.raises(ValueError, match="t1 and t2 must have the same length; got 10 and 9"):
        two_sensor_regressors(np.zeros(10), np.zeros(9), 1.0, window_s=5.0)


def test_bad_nan():
    a = np.zeros(20)
    a[3] = np.nan
    with pytest.raises(ValueError, match="t2 must be finite; got a NaN or inf at index 3"):
        two_sensor_regressors(np.zeros(20), a, 1.0, window_s=5.0)


def test_bad_too_short_for_window():
    with pytest.raises(ValueError, match="window_s"):
        two_sensor_regressors(np.arange(4.0), np.arange(4.0), 0.01, window_s=500.0)


def test_bad_fs():
    with pytest.raises(ValueError, match=r"fs must be a finite number > 0 Hz; got 0"):
        two_sensor_regressors(np.arange(10.0), np.arange(10.0), 0, window_s=5.0)
