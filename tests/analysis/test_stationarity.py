"""analysis.stationarity: motion and step flags on static records; temperature regression."""

from __future__ import annotations

import math
from statistics import NormalDist

import numpy as np
import pytest

from gyrobench.analysis.allan import allan_deviation
from gyrobench.analysis.stationarity import remove_temperature, stationarity_check

FS = 100.0


def _record(rng, n=200_000):
    return 1e-3 * math.sqrt(FS) * rng.standard_normal(n) + np.cumsum(
        2e-6 / math.sqrt(FS) * rng.standard_normal(n)
    )


def _check(y):
    c = allan_deviation(y, FS, taus=[1.28])
    return stationarity_check(y, FS, float(c.deviation[0]), window=1.28)


def test_stationary_record_is_not_flagged():
    rep = _check(_record(np.random.default_rng(31)))
    assert rep.stationary, (rep.motion[:3], rep.steps[:3])


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_false_alarm_rate_of_white_noise_within_its_binomial_bound():
    """White noise, 400 records of 64 windows: the any-flag rate at false_alarm = 0.05 (the
    documented probability of any flag, Bonferroni over the motion and step tests) stays
    within its binomial bound at 1e-6."""
    from scipy.stats import binom

    rng = np.random.default_rng(41)
    w, k, n_rec, fa = 32, 64, 400, 0.05
    flags = 0
    for _ in range(n_rec):
        y = rng.standard_normal(w * k)
        adev = math.sqrt(1.0 / w)  # white rate, unit variance: AVAR(tau_w) = 1/w
        rep = stationarity_check(y, 1.0, adev, window=float(w), false_alarm=fa)
        flags += not rep.stationary
    assert flags <= binom.isf(1e-6, n_rec, fa)


def test_too_short_record_is_not_called_stationary():
    rep = stationarity_check(np.zeros(20), 10.0, 1.0, window=1.0)
    assert not rep.tested and not rep.stationary
    assert "too short" in rep.warnings("gyro")[0]


def test_motion_burst_is_flagged():
    y = _record(np.random.default_rng(32))
    y[50_000:50_300] += 0.05 * np.random.default_rng(33).standard_normal(300)  # 3 s of handling
    rep = _check(y)
    assert rep.motion and all(480 <= a <= 505 for a, _, _ in rep.motion), rep.motion
    assert "motion or vibration" in rep.warnings("gx")[0]


def test_step_is_flagged_at_its_time():
    y = _record(np.random.default_rng(34))
    y[120_000:] += 0.02  # a 0.02 rad/s step at t = 1200 s (20x the 1.28 s ADEV)
    rep = _check(y)
    assert any(abs(t - 1200) <= 1.28 for t, _ in rep.steps), rep.steps
    assert "not stationary" in rep.warnings("gx")[-1]


def test_temperature_coefficients_are_recovered():
    rng = np.random.default_rng(35)
    n = 200_000
    t = np.arange(n) / FS
    temp = 25 + 10 * np.sin(2 * np.pi * t / 1000.0)  # 10 degC swing, period 1000 s
    dtdt = 10 * 2 * np.pi / 1000.0 * np.cos(2 * np.pi * t / 1000.0)
    c_t, c_dt = 3e-4, 5e-3  # [rad/s/degC], [rad/s/(degC/s)]
    noise = 1e-3 * math.sqrt(FS) * rng.standard_normal(n)
    y = noise + c_t * (temp - temp.mean()) + c_dt * dtdt
    clean, fit = remove_temperature(y, temp, FS)
    z = NormalDist().inv_cdf(
        1 - 1e-6 / 4
    )  # white residuals: the OLS errors hold; 1e-6 over two checks
    assert abs(fit.c_temperature - c_t) <= z * fit.se_temperature
    assert abs(fit.c_rate - c_dt) <= z * fit.se_rate
    # the explained share R^2 = drift variance / total; its large-n sampling sd is
    # 2 R (1 - R^2) / sqrt(n) (delta method, fixed regressors); z as above
    drift = np.var(c_t * (temp - temp.mean()) + c_dt * dtdt)
    r2 = drift / (np.var(noise) + drift)  # 0.043: noise variance 1e-4 (sd 0.01)
    assert abs(fit.explained - r2) <= z * 2 * math.sqrt(r2) * (1 - r2) / math.sqrt(n)
    # what is left is the white noise (up to its mean): the drift is gone to within the coefficients' errors
    left = np.std(clean - noise)
    assert left <= z * (fit.se_temperature * np.std(temp) + fit.se_rate * np.std(dtdt)), left


def test_temperature_input_checks():
    with pytest.raises(ValueError, match="temperature must have the rate's length 10; got 9"):
        remove_temperature(np.zeros(10), np.zeros(9), FS)
    with pytest.raises(ValueError, match="temperature column is constant"):
        remove_temperature(np.zeros(10), np.ones(10), FS)


@pytest.mark.parametrize(
    "name",
    ["moving_average_16", "first_order_fs_over_20", "butterworth4_fs_over_40", "butterworth8_near_nyquist"],
)
@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_filtered_white_noise_trips_at_most_the_stated_false_alarm_rate(name):
    """Issue 30: a sensor's low-pass filter is not motion. Filtered white noise, 200 records of
    64 windows of 128 samples, each checked against its own ADEV at the window as the report
    does: the any-flag rate at false_alarm = 0.05 stays within its binomial bound at 1e-6.
    Before the effective degrees of freedom (w - 1 taken for every record), the 16-sample
    moving average tripped the motion test on 10 of 20 200k-sample records at 1e-3."""
    from scipy import signal
    from scipy.stats import binom

    a1 = math.exp(-2.0 * math.pi / 20.0)
    b, a = {
        "moving_average_16": (np.ones(16) / 16, [1.0]),
        "first_order_fs_over_20": ([1.0 - a1], [1.0, -a1]),
        "butterworth4_fs_over_40": signal.butter(4, 2.0 / 40.0),
        "butterworth8_near_nyquist": signal.butter(8, 0.4),
    }[name]
    rng = np.random.default_rng(43)
    w, k, n_rec, fa = 128, 64, 200, 0.05
    flags = 0
    for _ in range(n_rec):
        y = signal.lfilter(b, a, rng.standard_normal(w * k + 500))[500:]  # past the filter's start-up
        c = allan_deviation(y, 1.0, taus=[float(w)])
        rep = stationarity_check(y, 1.0, float(c.deviation[0]), window=float(w), false_alarm=fa)
        flags += not rep.stationary
    assert flags <= binom.isf(1e-6, n_rec, fa), flags


def test_window_variance_dof_of_white_and_moving_average_noise():
    """White noise: nu = w - 1 less the estimation noise (about 3/K of S, here K = 256: within 5 %).
    A 16-sample moving average: nu = tr(M)^2 / tr(M^2) computed exactly from its covariance
    Sigma_il = max(0, 1 - |i - l|/16) with the window mean removed (M = A Sigma A); the estimate
    within 10 % of it (the Toeplitz approximation of M and the 3/K noise are a few % each)."""
    from gyrobench.analysis.stationarity import window_variance_dof

    rng = np.random.default_rng(44)
    w, k = 128, 256
    nu_white = window_variance_dof(rng.standard_normal((k, w)))
    assert 0.95 * (w - 1) <= nu_white <= w - 1
    y = np.convolve(rng.standard_normal(k * w + 15), np.ones(16) / 16, mode="valid")
    lag = np.abs(np.subtract.outer(np.arange(w), np.arange(w)))
    a = np.eye(w) - 1.0 / w
    m = a @ np.maximum(0.0, 1.0 - lag / 16.0) @ a
    nu_exact = np.trace(m) ** 2 / np.sum(m * m)
    assert window_variance_dof(y.reshape(k, w)) == pytest.approx(nu_exact, rel=0.1)


def test_motion_in_a_filtered_record_is_still_flagged():
    """The lower degrees of freedom of filtered noise do not hide handling: 3 s of 5x the rate noise
    (25x the variance) in a 16-sample moving-average record at 100 Hz is flagged at that time, and
    the same record without it is not."""
    rng = np.random.default_rng(45)
    n = 200_000
    x = 0.01 * rng.standard_normal(n + 15)
    assert _check(np.convolve(x, np.ones(16) / 16, mode="valid")).stationary
    x[50_000:50_300] *= 5.0
    rep = _check(np.convolve(x, np.ones(16) / 16, mode="valid"))
    assert rep.motion and all(480 <= a <= 505 for a, _, _ in rep.motion), rep.motion
