"""Tests of analysis.sweep (frequency-bin means of a swept-sine record)."""

from __future__ import annotations

import numpy as np
import pytest

from gyrobench.analysis.sweep import bin_means


def test_full_bins_are_the_plain_means_of_their_samples(rng):
    """Every full bin's pair equals the mean of the samples inside its edges (computed with masks)."""
    f = rng.uniform(1.0, 11.0, 5000)
    y = rng.standard_normal(5000)
    fm, ym = bin_means(f, y, lo=1.0, hi=11.0, width=1.0)
    assert fm.size == 10
    for k in range(10):
        inside = (f >= 1.0 + k) & (f < 2.0 + k)
        assert fm[k] == pytest.approx(f[inside].mean(), rel=1e-12)
        assert ym[k] == pytest.approx(y[inside].mean(), rel=1e-12, abs=1e-15)


def test_a_linear_signal_stays_on_its_line(rng):
    """Means are linear: y = 3 f - 2 gives y_mean = 3 f_mean - 2 in every bin (closed form)."""
    f = np.sort(rng.uniform(0.0, 50.0, 2000))
    fm, ym = bin_means(f, 3.0 * f - 2.0, lo=0.0, hi=50.0, width=2.5)
    np.testing.assert_allclose(ym, 3.0 * fm - 2.0, rtol=0, atol=1e-12 * 150)


def test_a_partial_last_bin_is_merged_into_its_neighbour():
    """Ten samples a bin over [0, 4) and two in [4, 5): the two join bin [3, 4); empty bins vanish."""
    f = np.concatenate([np.linspace(k + 0.05, k + 0.95, 10) for k in range(4)] + [np.array([4.1, 4.2])])
    y = np.arange(f.size, dtype=float)
    fm, ym = bin_means(f, y, lo=0.0, hi=8.0, width=1.0)
    assert fm.size == 4
    last = f >= 3.0
    assert fm[-1] == pytest.approx(f[last].mean()) and ym[-1] == pytest.approx(y[last].mean())


def test_bad_input_named():
    with pytest.raises(ValueError, match=r"f and y must be 1-D of the same length; got shapes \(3,\) and \(4,\)"):
        bin_means(np.zeros(3), np.zeros(4), lo=0.0, hi=1.0, width=0.1)
    with pytest.raises(ValueError, match=r"lo and hi must be finite with lo < hi; got lo=2.0, hi=1.0"):
        bin_means(np.zeros(3), np.zeros(3), lo=2.0, hi=1.0, width=0.1)
    with pytest.raises(ValueError, match=r"width must be finite and > 0; got 0.0"):
        bin_means(np.zeros(3), np.zeros(3), lo=0.0, hi=1.0, width=0.0)
