"""The stored octave correlation table of the noise fit equals the direct computation.

``fit_noise`` models the covariance of the Allan-variance points with correlations rho that
are integrals over a 16384-point frequency grid; for power-of-two m they are read from a
table (gyrobench.analysis.allan._rho_table) instead, and every other m is computed. Both
must give the same rho to rounding, and so the same fit.
"""

from __future__ import annotations

import numpy as np
import pytest

from gyrobench.analysis import allan
from gyrobench.analysis.allan import _covariance
from gyrobench.analysis.allan import _rho_table as tab


def _direct(monkeypatch, alphas, ms):
    """_rho_blocks without the table (and without the cache)."""
    monkeypatch.setattr(_covariance, "_octave_gram", lambda ua, mu: None)
    return _covariance._rho_blocks_cached.__wrapped__(tuple(alphas), tuple(int(m) for m in ms))


def test_table_is_the_direct_gram():
    assert (tab.GRID, tab.M_CAP) == (_covariance._RHO_GRID, _covariance._RHO_M_CAP)
    table = _covariance._octave_table()
    assert table is not None
    direct = _covariance._octave_gram_direct()
    assert table.shape == direct.shape == (44, 44)
    np.testing.assert_allclose(table, table.T, rtol=0, atol=1e-15)  # a Gram matrix, to rounding
    # the same sums of products, to rounding (entries are correlations in [0, 1])
    np.testing.assert_allclose(table, direct, rtol=0, atol=1e-14)


@pytest.mark.parametrize(
    ("alphas", "ms"),
    [
        ((2, 0, -1, -2, -2), 2 ** np.arange(18)),  # the five-term fit of a 1e6-sample record
        ((0, -2), 2 ** np.arange(5, 27)),  # two terms, octaves far above the 1024 cap
        ((2, 0, -1), 2 ** np.arange(3)),
    ],
)
def test_octave_rho_from_the_table_equals_direct(monkeypatch, alphas, ms):
    _covariance._rho_blocks_cached.cache_clear()
    got = _covariance._rho_blocks(list(alphas), np.asarray(ms))
    want = _direct(monkeypatch, alphas, ms)
    assert got.keys() == want.keys()
    for k in got:
        np.testing.assert_allclose(got[k], want[k], rtol=0, atol=1e-14)
    _covariance._rho_blocks_cached.cache_clear()


def test_non_octave_taus_are_computed(monkeypatch):
    calls = []
    real = _covariance._gram_direct
    monkeypatch.setattr(_covariance, "_gram_direct", lambda ua, mu: calls.append(tuple(mu)) or real(ua, mu))
    _covariance._rho_blocks_cached.cache_clear()
    _covariance._rho_blocks([0, -2], np.array([1, 3, 10, 100, 3000]))
    assert calls and 3 in calls[0]  # m = 3 is in no table: computed
    calls.clear()
    _covariance._rho_blocks([0, -2], 2 ** np.arange(12))
    assert not calls  # octaves: read from the table
    _covariance._rho_blocks_cached.cache_clear()


def test_fit_with_the_table_equals_the_direct_fit(monkeypatch, rng):
    y = rng.standard_normal(50_000) + np.cumsum(1e-3 * rng.standard_normal(50_000))
    curve = allan.allan_deviation(y, 100.0)
    _covariance._rho_blocks_cached.cache_clear()
    fit = allan.fit_noise(curve)
    _covariance._rho_blocks_cached.cache_clear()
    monkeypatch.setattr(_covariance, "_octave_gram", lambda ua, mu: None)
    ref = allan.fit_noise(curve)
    _covariance._rho_blocks_cached.cache_clear()
    for k in ref.avar_coefficients:
        assert fit.avar_coefficients[k] == pytest.approx(ref.avar_coefficients[k], rel=1e-9, abs=1e-300)
    np.testing.assert_allclose(fit.covariance, ref.covariance, rtol=1e-9, atol=1e-30)
    assert fit.chi2 == pytest.approx(ref.chi2, rel=1e-9)
