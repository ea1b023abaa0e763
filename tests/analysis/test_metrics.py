"""Tests of analysis.metrics: per-segment IEEE 952 fits (closed form, statistics, bad input)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from gyrobench.analysis.allan import allan_deviation, fit_noise
from gyrobench.analysis.metrics import SegmentFit, segment_noise_fits

#: two-sided false-alarm rate of the statistical bounds
ALARM = 1e-6


def test_each_segment_is_fitted_on_its_own_samples_only():
    # closed form: the segment fit is exactly the fit of the slice, whatever the neighbours hold
    rng = np.random.default_rng(7)
    fs = 50.0
    y = np.concatenate([rng.normal(0, 1.0, 3000), 1e3 + rng.normal(0, 50.0, 2000)])
    fits = segment_noise_fits(y, fs, {"quiet": (0.0, 60.0), "loud": (60.0, 100.0)})
    assert list(fits) == ["quiet", "loud"] and isinstance(fits["quiet"], SegmentFit)
    assert (fits["quiet"].start, fits["quiet"].stop, fits["loud"].start, fits["loud"].stop) == (
        0,
        3000,
        3000,
        5000,
    )
    assert fits["loud"].duration == 40.0
    ms = 2 ** np.arange(int(math.log2(3000 // 4)) + 1)
    direct = fit_noise(allan_deviation(y[:3000], fs, taus=ms / fs))
    for t, c in direct.coefficients.items():
        got = fits["quiet"].fit.coefficients[t]
        assert got.identifiable == c.identifiable
        np.testing.assert_allclose(got.ci95, c.ci95, rtol=1e-12, atol=0)


def test_white_noise_segments_give_their_own_N_within_chi_square_bounds():
    """Three segments of white rate noise, N = sigma/sqrt(fs): each fit returns its own N.

    Bound: with N alone, the converged weighted fit is C = N^2 estimated as
    sum_i nu_i (tau_i A_i) / sum_i nu_i, a fixed convex combination of the AVAR points,
    each tau_i A_i ~ C chi2(nu_i)/nu_i (sd C sqrt(2/nu_i), nu_i = the points' edf).
    Whatever their correlation, sd(C_hat) <= C sqrt(2) sum sqrt(nu_i) / sum nu_i
    (the sd of a sum is at most the sum of the sds); the test allows z(1e-6) = 4.89 of
    that, i.e. a false alarm below 1e-6 per segment in the normal approximation.
    """
    rng = np.random.default_rng(20261121)
    fs, n = 100.0, 30000
    sigmas = (1.0, 2.0, 4.0)
    y = np.concatenate([rng.normal(0.0, s, n) for s in sigmas])
    mask = np.zeros(y.size, dtype=bool)
    mask[n : 2 * n] = True  # one segment as a mask, the others as times
    fits = segment_noise_fits(y, fs, [(0.0, n / fs), mask, (2 * n / fs, 3 * n / fs)], terms=("N",))
    z = stats.norm.isf(ALARM / 2)
    for (key, f), s in zip(fits.items(), sigmas, strict=True):
        nu = np.asarray(f.fit.curve.edf, dtype=float)
        rel_sd = math.sqrt(2.0) * np.sum(np.sqrt(nu)) / np.sum(nu)
        n_true = s / math.sqrt(fs)
        n_hat = f.fit.coefficients["N"].value
        assert n_hat is not None, key
        lo, hi = n_true * math.sqrt(1 - z * rel_sd), n_true * math.sqrt(1 + z * rel_sd)
        assert lo <= n_hat <= hi, (key, n_hat, lo, hi)
        # the bound is tight enough to tell the segments apart (a factor 2 in N)
        assert hi < 2 * lo


def test_too_short_segment_is_a_clear_error():
    y = np.random.default_rng(3).normal(size=1000)
    with pytest.raises(
        ValueError,
        match=r"segment '2' holds 40 samples \(4 s\); fitting 5 terms .* needs >= 64 samples",
    ):
        segment_noise_fits(y, 10.0, [(0.0, 50.0), (50.0, 54.0)])
    # a larger smallest cluster needs a longer segment
    with pytest.raises(ValueError, match=r"segment 'a' holds 500 samples .* needs >= 512 samples"):
        segment_noise_fits(y, 10.0, {"a": (0.0, 50.0)}, min_m=8)


def test_bad_segments_rejected():
    y = np.zeros(1000) + np.random.default_rng(4).normal(size=1000)
    gap = np.zeros(1000, dtype=bool)
    gap[:100] = gap[200:300] = True
    with pytest.raises(ValueError, match=r"segment 'g': the mask must select one contiguous run"):
        segment_noise_fits(y, 10.0, {"g": gap})
    with pytest.raises(
        ValueError, match=r"segment '1' ends at 200.0 s, after the record's end at 100.0 s"
    ):
        segment_noise_fits(y, 10.0, [(0.0, 200.0)])
    with pytest.raises(ValueError, match=r"segment '1' must satisfy 0 <= start < end"):
        segment_noise_fits(y, 10.0, [(50.0, 10.0)])
    with pytest.raises(
        TypeError, match=r"segment 'x' must be \(start_s, end_s\) or a boolean mask"
    ):
        segment_noise_fits(y, 10.0, {"x": (1.0, 2.0, 3.0)})
    with pytest.raises(ValueError, match=r"fs must be a finite number > 0 Hz; got 0"):
        segment_noise_fits(y, 0, [(0.0, 10.0)])
