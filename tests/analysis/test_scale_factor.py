"""Tests of analysis/scale_factor.py: LS fit, K_n, asymmetry, the heuristic breakpoint search."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gyrobench.analysis.scale_factor import (
    asymmetry,
    breakpoint_search,
    dwell_means,
    fit_scale_factor,
    heuristic_split,
    range_nonlinearity,
    repeatability_floor,
)

GRID = np.arange(3600.0, -3601.0, -360.0)


def _knee(w, ok=1800.0, ws=987.61):
    a = np.abs(w)
    return np.where(a <= ok, w, np.sign(w) * (ok + ws * np.tanh((a - ok) / ws)))


# ------------------------------------------------------------------ closed form
def test_noise_free_linear_gyro():
    f = 0.8 * GRID + 3.0
    fit = fit_scale_factor(GRID, f)
    assert fit.scale_factor == pytest.approx(0.8, rel=1e-12)
    assert fit.bias == pytest.approx(3.0, rel=1e-12)
    assert fit.nonlinearity < 1e-14
    assert fit.full_scale == pytest.approx(0.8 * 3600 + 3.0, rel=1e-12)


def test_known_cubic_by_hand():
    """F = W + c W^3 on W = -2..2: K = 1 + 3.4c, F0 = 0, max residual 2.4c at |W| = 1, F_m = 2 + 8c."""
    c = 0.01
    w = np.array([-2.0, -1.0, 0.0, 1.0, 2.0])
    fit = fit_scale_factor(w, w + c * w**3)
    assert fit.scale_factor == pytest.approx(1 + 3.4 * c, rel=1e-12)
    assert abs(fit.bias) < 1e-15
    assert fit.nonlinearity == pytest.approx(2.4 * c / (2 + 8 * c), rel=1e-12)
    assert fit.nonlinearity_pct == pytest.approx(100 * 2.4 * c / (2 + 8 * c), rel=1e-12)
    assert fit.nonlinearity_ppm == pytest.approx(1e6 * 2.4 * c / (2 + 8 * c), rel=1e-12)
    np.testing.assert_allclose(fit.pointwise * fit.full_scale, fit.residuals, rtol=1e-12)


def test_full_scale_override():
    w = np.array([-2.0, -1.0, 0.0, 1.0, 2.0])
    fit = fit_scale_factor(w, w + 0.01 * w**3, full_scale=4.0)
    assert fit.nonlinearity == pytest.approx(0.024 / 4.0, rel=1e-12)


def test_decreasing_and_increasing_rates_agree():
    f = GRID + 1e-8 * GRID**3
    a, b = fit_scale_factor(GRID, f), fit_scale_factor(GRID[::-1], f[::-1])
    assert a.nonlinearity == pytest.approx(b.nonlinearity, rel=1e-12)


def test_asymmetry_closed_form():
    w = np.array([-2.0, -1.0, 0.0, 1.0, 2.0])
    f = np.where(w >= 0, 1.1 * w, 0.9 * w)
    assert asymmetry(w, f) == pytest.approx(0.2, rel=1e-12)


# ------------------------------------------------------------------ breakpoint search
def test_split_rule_by_hand():
    split, d, dd, counter = heuristic_split([0.0, 1.0, 3.0, 6.0, 10.0])
    assert split == 1
    np.testing.assert_array_equal(counter, [0, 0, 1, 2, 3])
    np.testing.assert_allclose(d[1:], [1.0, 2.0, 3.0, 4.0], rtol=1e-12)
    np.testing.assert_allclose(dd[2:], [1.0, 1.0, 1.0], rtol=1e-12)


def test_split_rule_resets_on_a_negative_sign():
    # d = 1, 2, 1, 2, 3, 4: dd = +, -, +, +, + -> run starts at index 4, split at 3
    kn = np.cumsum([0.0, 1.0, 2.0, 1.0, 2.0, 3.0, 4.0])
    split, _, _, counter = heuristic_split(kn)
    assert split == 3
    np.testing.assert_array_equal(counter, [0, 0, 1, 0, 1, 2, 3])


def test_table2_style_sequence():
    """A Table-2-like sequence (interval K_n [%] for [0, 360] ... [0, 3600]): small and falling, then rising fast."""
    kn_pct = [0.0, 0.094, 0.075, 0.059, 0.059, 0.41, 2.36, 5.64, 9.36, 12.84]
    ends = np.arange(360.0, 3601.0, 360.0)
    split, _, _, counter = heuristic_split(kn_pct)
    assert ends[split] == 1800.0
    assert counter.tolist() == [0, 0, 0, 0, 0, 1, 2, 3, 3, 3]


def test_breakpoint_search_on_a_closed_form_knee():
    """F = W for |W| <= 1800, F = W - sign(W) c (|W| - 1800)^2 beyond (c = 1e-3 s/deg): splits at +-1800.

    The low range is exactly linear in binary floating point (K_n = 0 exactly). The first
    interval past the knee, [0, 2160] (7 points j = 0..6, only the last one low by
    d = c 360^2), has residuals d ((3j - 5)/28 - [j = 6]), so K_n = 15 d / (28 (2160 - d)).
    The counter then runs 1, 2, 3 and the search splits at the end of the last linear interval.
    """
    c = 1e-3
    a = np.abs(GRID)
    f = GRID - np.sign(GRID) * np.where(a > 1800.0, c * (a - 1800.0) ** 2, 0.0)
    res = breakpoint_search(GRID, f)
    assert (res.negative, res.positive) == (-1800.0, 1800.0)
    d = c * 360.0**2
    for side in (1, -1):
        steps = [st for st in res.trace if st.side == side]
        assert [st.end_rate for st in steps] == list(side * np.arange(360.0, 3601.0, 360.0))
        assert [st.nonlinearity for st in steps[:5]] == [0.0] * 5
        assert steps[5].nonlinearity == pytest.approx(15 * d / (28 * (2160.0 - d)), rel=1e-12)
        assert [st.counter for st in steps] == [0, 0, 0, 0, 0, 1, 2, 3, 3, 3]
        assert all(st.diff2 > 0 for st in steps[5:8])


def test_no_split_on_a_linear_table():
    res = breakpoint_search(GRID, 2.0 * GRID + 1.0)
    assert res.breakpoints == ()
    assert len(res.trace) == 20


def test_search_finds_the_knee():
    """Knee at 1800 deg/s (docs/physics.md 5) plus a 2 deg/s sign-dependent offset: breakpoints +-1800."""
    f = _knee(GRID) + 2.0 * np.sign(GRID)
    res = breakpoint_search(GRID, f)
    assert (res.negative, res.positive) == (-1800.0, 1800.0)
    pos = [s for s in res.trace if s.side > 0]
    assert [s.end_rate for s in pos] == list(np.arange(360.0, 3601.0, 360.0))
    assert [s.n_points for s in pos] == list(range(2, 12))


def test_search_trace_matches_direct_interval_fits():
    f = _knee(GRID) + 2.0 * np.sign(GRID)
    res = breakpoint_search(GRID, f)
    for s in res.trace:
        m = (np.sign(GRID) * s.side >= 0) & (np.abs(GRID) <= abs(s.end_rate))
        expect = 0.0 if m.sum() < 3 else fit_scale_factor(GRID[m], f[m]).nonlinearity
        assert s.nonlinearity == pytest.approx(expect, rel=1e-12, abs=1e-15)


# ------------------------------------------------------------------ bad input
def test_rejects_fewer_than_three_rates():
    with pytest.raises(ValueError, match="at least 3 rates; got 2"):
        fit_scale_factor([0.0, 1.0], [0.0, 1.0])


def test_rejects_non_monotonic_rates():
    with pytest.raises(ValueError, match="strictly monotonic"):
        fit_scale_factor([0.0, 2.0, 1.0], [0.0, 2.0, 1.0])


def test_rejects_duplicate_rates():
    with pytest.raises(ValueError, match="duplicate rate 1.0"):
        fit_scale_factor([0.0, 1.0, 1.0, 2.0], [0.0, 1.0, 1.0, 2.0])


def test_rejects_nan_output():
    with pytest.raises(ValueError, match=r"outputs must be finite; got nan at index 1"):
        fit_scale_factor([0.0, 1.0, 2.0], [0.0, np.nan, 2.0])


def test_rejects_length_mismatch():
    with pytest.raises(ValueError, match="same length"):
        fit_scale_factor([0.0, 1.0, 2.0], [0.0, 1.0])


def test_rejects_nonpositive_full_scale():
    with pytest.raises(ValueError, match="full_scale must be a finite number > 0"):
        fit_scale_factor([0.0, 1.0, 2.0], [0.0, 1.0, 2.0], full_scale=0.0)


def test_search_rejects_non_monotonic_rates():
    with pytest.raises(ValueError, match="strictly monotonic"):
        breakpoint_search([0.0, 2.0, 1.0, 3.0], [0.0, 2.0, 1.0, 3.0])


def test_search_rejects_nan_output():
    with pytest.raises(ValueError, match="outputs must be finite"):
        breakpoint_search(GRID, np.where(GRID == 0, np.nan, GRID))


def test_search_rejects_bad_run_length():
    with pytest.raises(ValueError, match="run_length must be an integer >= 1; got 0"):
        breakpoint_search(GRID, GRID, run_length=0)


def test_asymmetry_needs_two_rates_per_side():
    with pytest.raises(ValueError, match="at least 2 rates >= 0 and 2 rates <= 0"):
        asymmetry([0.0, 1.0, 2.0], [0.0, 1.0, 2.0])


# ------------------------------------------------------------------ properties
@settings(max_examples=50, deadline=None)
@given(
    a=st.floats(1e-3, 1e3),
    c=st.floats(1e-3, 1e3),
    cubic=st.floats(-1e-8, 1e-8),
)
def test_nonlinearity_is_unit_free(a, c, cubic):
    """K_n does not change when rates are rescaled (deg/s -> rad/s) or outputs rescaled (volts -> counts)."""
    f = GRID + cubic * GRID**3 + 0.3
    ref = fit_scale_factor(GRID, f)
    got = fit_scale_factor(c * GRID, a * f)
    assert got.nonlinearity == pytest.approx(ref.nonlinearity, rel=1e-9, abs=1e-15)
    assert got.scale_factor == pytest.approx(ref.scale_factor * a / c, rel=1e-9)


@settings(max_examples=30, deadline=None)
@given(a=st.floats(1e-2, 1e2), c=st.floats(1e-2, 1e2))
def test_breakpoints_scale_with_the_rate_unit(a, c):
    f = _knee(GRID) + 2.0 * np.sign(GRID)
    res = breakpoint_search(c * GRID, a * f)
    assert res.negative == pytest.approx(-1800.0 * c, rel=1e-12)
    assert res.positive == pytest.approx(1800.0 * c, rel=1e-12)


# ------------------------------------------------------------------ several runs of one table
def test_range_nonlinearity_closed_form():
    """F = W + c W^2 on W = -2..2, band [0, 2]: LS line slope 1 + 2c, intercept -c/3, max residual
    2c/3 at W = 1, F_m = 2 + 4c, so K_n = (2c/3) / (2 + 4c); the points outside do not enter."""
    c = 0.01
    w = np.array([-2.0, -1.0, 0.0, 1.0, 2.0])
    f = w + c * w**2
    f[0] = -50.0  # far off, outside the band
    assert range_nonlinearity(w, f, 0.0, 2.0) == pytest.approx((2 * c / 3) / (2 + 4 * c), rel=1e-12)


def test_range_nonlinearity_needs_three_rates_in_the_band():
    w = np.array([-2.0, -1.0, 0.0, 1.0, 2.0])
    assert np.isnan(range_nonlinearity(w, w**3, 0.5, 2.0))  # only 1 and 2 inside
    assert range_nonlinearity(w, 2 * w + 1, -1.0, 1.0) < 1e-15  # a line: no nonlinearity


def test_range_nonlinearity_rejects_an_empty_band():
    with pytest.raises(ValueError, match="lo <= hi"):
        range_nonlinearity([0.0, 1.0, 2.0], [0.0, 1.0, 2.0], 2.0, 1.0)


def test_repeatability_floor_closed_form():
    """Outputs equal to the fit-run means map to the rates exactly; linear beyond the ends."""
    rates = np.array([-2.0, -1.0, 0.0, 1.0, 2.0])
    fit = np.array([[-1.5, -0.9, 0.1, 1.1, 1.4], [-1.7, -1.1, -0.1, 0.9, 1.6]])  # mean: tanh-like
    xm = fit.mean(axis=0)
    np.testing.assert_allclose(repeatability_floor(rates, fit, xm), rates, rtol=1e-15)
    got = repeatability_floor(rates, fit, np.array([xm[0] - 0.1, 0.5 * (xm[1] + xm[2]), xm[-1] + 0.1]))
    np.testing.assert_allclose(got, [-2.0 - 0.1 / 0.6, -0.5, 2.0 + 0.1 / 0.5], rtol=1e-12)


def test_repeatability_floor_rate_order_does_not_matter():
    """A table taken from +rate to -rate (the paper's order) gives the same compensation."""
    rates = np.array([-2.0, -1.0, 0.0, 1.0, 2.0])
    fit = np.array([[-1.5, -0.9, 0.1, 1.1, 1.4]])
    out = np.array([-1.0, 0.3, 1.5])
    np.testing.assert_array_equal(
        repeatability_floor(rates[::-1], fit[:, ::-1], out), repeatability_floor(rates, fit, out)
    )


def test_repeatability_floor_rejects_non_increasing_means():
    with pytest.raises(ValueError, match="increase strictly with rate; got"):
        repeatability_floor(np.arange(3.0), np.array([[0.0, 1.0, 1.0]]), np.zeros(3))


def test_dwell_means_by_hand():
    """Each window's mean; the settling samples outside the windows do not enter."""
    y = np.array([100.0, 1.0, 2.0, 3.0, -100.0, 10.0, 20.0])
    np.testing.assert_array_equal(dwell_means(y, [[1, 4], [5, 7]]), [2.0, 15.0])


@pytest.mark.parametrize(
    ("windows", "msg"),
    [
        ([[0, 3], [3, 3]], r"0 <= start < stop <= 5 \(record length\); got \[3, 3\] at index 1"),
        ([[-1, 2]], "got \\[-1, 2\\] at index 0"),
        ([[0, 6]], "got \\[0, 6\\] at index 0"),
        ([[0.0, 2.0]], "integer"),
        ([0, 2], "shape \\(m, 2\\)"),
    ],
)
def test_dwell_means_rejects_bad_windows(windows, msg):
    with pytest.raises(ValueError, match=msg):
        dwell_means(np.zeros(5), windows)


def test_dwell_means_rejects_a_2d_record():
    with pytest.raises(ValueError, match="output must be a 1-D record; got shape"):
        dwell_means(np.zeros((5, 2)), [[0, 2]])
