"""Tests for analysis/wavelet.py: perfect reconstruction, level consistency, bands, CWT, spectrum, bad input."""

from __future__ import annotations

import zlib

import numpy as np
import pytest

from gyrobench.analysis.wavelet import amplitude_spectrum, cwt_map, decompose, max_level


@pytest.fixture
def rng(request) -> np.random.Generator:
    key = zlib.crc32(request.node.nodeid.encode())
    return np.random.default_rng([20261121, key])


def test_branches_sum_back_to_the_signal(rng):
    x = np.cumsum(rng.standard_normal(20000)) + rng.standard_normal(20000)
    dec = decompose(x, 200.0, level=10)
    assert dec.level == 10 and len(dec.details) == 10
    scale = np.max(np.abs(x))
    np.testing.assert_allclose(dec.reconstruct(), x, rtol=0, atol=1e-12 * scale)
    for j in range(11):
        np.testing.assert_allclose(dec.approx(j) + dec.detail_sum(j), x, rtol=0, atol=1e-12 * scale)


def test_approximation_independent_of_depth(rng):
    # A6 from a 10-level decomposition (A10 + D10..D7) equals A6 from a 6-level one (docs/physics.md 7.1)
    x = rng.standard_normal(16384)
    a10 = decompose(x, 100.0, level=10).approx(6)
    a6 = decompose(x, 100.0, level=6).approx(6)
    np.testing.assert_allclose(a10, a6, rtol=0, atol=1e-12 * np.max(np.abs(x)))


def test_constant_has_no_details():
    # db4 has 4 vanishing moments and the symmetric extension of a constant is constant
    x = np.full(8192, 3.5)
    dec = decompose(x, 100.0, level=8)
    assert max(np.max(np.abs(d)) for d in dec.details) < 1e-12 * 3.5
    np.testing.assert_allclose(dec.approximation, 3.5, rtol=1e-12)


def test_sine_lands_in_its_band():
    fs = 1000.0
    t = np.arange(32768) / fs
    f0 = 0.75 * fs / 2**3  # centre of D3 nominal band [fs/16, fs/8]
    dec = decompose(np.sin(2 * np.pi * f0 * t), fs, level=6)
    lo, hi = dec.band(3)
    assert lo < f0 < hi
    energy = np.array([np.sum(d**2) for d in dec.details])
    # db4 is not a brick-wall filter: most, not all, of the energy is in D3
    assert np.argmax(energy) == 2 and energy[2] / energy.sum() > 0.8


def test_level_too_deep_for_the_record_is_an_error(rng):
    x = rng.standard_normal(5000)
    assert max_level(5000) == 9
    with pytest.raises(ValueError, match=r"level must be in \[1, 9\] for 5000 samples and db4.*>= 7168 samples"):
        decompose(x, 100.0, level=10)


def test_level_max_uses_the_deepest_usable_level(rng):
    dec = decompose(rng.standard_normal(5000), 100.0, level="max")
    assert dec.level == 9


def test_record_too_short_for_one_level():
    with pytest.raises(ValueError, match="too few for one level"):
        decompose(np.ones(5), 100.0, level=1)


def test_unknown_wavelet_lists_where_to_look(rng):
    with pytest.raises(ValueError, match=r"pywt.wavelist\(kind='discrete'\)"):
        decompose(rng.standard_normal(1000), 100.0, wavelet="db99x", level=2)


def test_nonfinite_input_rejected():
    x = np.ones(1000)
    x[10] = np.nan
    with pytest.raises(ValueError, match="x must be finite; got nan at index 10"):
        decompose(x, 100.0, level=2)


def test_branch_index_checked(rng):
    dec = decompose(rng.standard_normal(4096), 100.0, level=4)
    with pytest.raises(ValueError, match=r"level j must be an integer in \[1, 4\]; got 5"):
        dec.detail(5)


def test_amplitude_spectrum_reads_a_bin_centred_sine():
    fs, n = 400.0, 4000
    t = np.arange(n) / fs
    x = 0.7 * np.sin(2 * np.pi * 20.0 * t) + 2.0
    f, a = amplitude_spectrum(x, fs)
    k = int(np.argmax(a))
    assert f[k] == 20.0 and a[k] == pytest.approx(0.7, rel=1e-12)
    assert a[0] < 1e-12


def test_cwt_map_peaks_at_the_tone_and_only_while_it_is_on():
    fs = 200.0
    t = np.arange(12000) / fs
    x = np.where((t > 20) & (t < 40), np.sin(2 * np.pi * 25.0 * t), 0.0)
    m = cwt_map(x, fs, frequencies=np.geomspace(2.0, 100.0, 30), time_block=100)
    assert m.magnitude.shape == (30, 120)
    i = int(np.argmax(m.magnitude.max(axis=1)))
    assert abs(np.log(m.frequency[i] / 25.0)) < np.log(100 / 2.0) / 29  # within one grid step
    row = m.magnitude[i]
    assert row[(m.time > 25) & (m.time < 35)].min() > 20 * row[(m.time < 15) | (m.time > 45)].max()
