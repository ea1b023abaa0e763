"""The numpy-only chi-square laws of analysis/allan/_chi2.py against scipy.special, an independent implementation.

scipy.special (cephes igam/igami, Temme's asymptotic series at large a) is a different algorithm
from the series + continued fraction + Newton of _chi2, so agreement to 1e-12 relative is evidence
for both. Where scipy is itself inaccurate (the lower tail at a >~ 5e5, measured 7e-7 relative on
the quantile at nu = 1e7 and 8e-6 at 1e8) the check is the Wilson-Hilferty cube-normal quantile,
whose own error falls like |z|^3 nu^-3/2 (8.6e-9 at nu = 1e6, 8.6e-12 at 1e8, z = -7).
"""

from __future__ import annotations

import math
from statistics import NormalDist

import numpy as np
import pytest
from scipy import special

from gyrobench.analysis.allan import _chi2

#: probabilities the callers use (0.025, 0.5, 1e-3 ... 1e-6 levels) and the extreme tails
PROBS = np.array([1e-300, 1e-100, 1e-12, 1e-6, 1e-3, 0.025, 0.1587, 0.3, 0.5, 0.7, 0.975, 1 - 1e-6, 1 - 1e-12])
#: dof from below the smallest edf the curve produces (0.3) to a 1e5-sample record's
NU_SCIPY = [0.3, 0.5, 1.0, 1.5, 2.0, 3.0, 7.0, 12.3, 50.0, 127.0, 1e3, 1e4, 1e5, 3e5]
REL = 1e-12


@pytest.mark.parametrize("nu", NU_SCIPY)
def test_quantiles_match_scipy(nu):
    with np.errstate(under="ignore"):
        want_ppf = 2.0 * special.gammaincinv(nu / 2.0, PROBS)
        want_isf = special.chdtri(nu, PROBS)
    ok = want_ppf > 0.0  # scipy underflows to 0 where the quantile is below ~1e-308
    np.testing.assert_allclose(_chi2.chi2_ppf(PROBS, nu)[ok], want_ppf[ok], rtol=REL)
    ok = want_isf > 0.0
    np.testing.assert_allclose(_chi2.chi2_isf(PROBS, nu)[ok], want_isf[ok], rtol=REL)


@pytest.mark.parametrize("nu", [1e6, 1e7, 1e8])
def test_quantiles_at_huge_dof(nu):
    """Upper tail against scipy; lower tail against Wilson-Hilferty (scipy's lower tail is off here)."""
    upper = PROBS[PROBS >= 0.025]
    np.testing.assert_allclose(_chi2.chi2_ppf(upper, nu), 2.0 * special.gammaincinv(nu / 2.0, upper), rtol=REL)
    lower = np.array([1e-12, 1e-6, 1e-3])
    z = np.array([NormalDist().inv_cdf(p) for p in lower])
    c = 2.0 / (9.0 * nu)
    wh = nu * (1.0 - c + z * math.sqrt(c)) ** 3
    # WH's own error falls like |z|^3 nu^-3/2 (measured 8.6e-9 at nu = 1e6 and 8.6e-12 at 1e8, z = -7, where
    # scipy and _chi2 agree to 6e-15 at 1e6): 0.1 |z|^3 nu^-3/2 is 4x that, and 600x below scipy's 7e-7 at 1e7
    np.testing.assert_allclose(_chi2.chi2_ppf(lower, nu), wh, rtol=0.1 * float(np.max(np.abs(z) ** 3)) * nu**-1.5)


@pytest.mark.parametrize("nu", NU_SCIPY + [1e6, 1e7])
def test_sf_matches_scipy(nu):
    x = nu * np.array([1e-6, 0.01, 0.3, 0.9, 1.0, 1.1, 2.0, 5.0]) + np.array([0, 0, 0, 0, 0, 0, 0, 3.0])
    want = special.chdtrc(nu, x)
    ok = want > 1e-290
    np.testing.assert_allclose(_chi2.chi2_sf(x, nu)[ok], want[ok], rtol=1e-12)


@pytest.mark.parametrize(("x", "nu", "lam"), [(10.0, 3.0, 2.0), (50.0, 5.5, 20.0), (200.0, 30.0, 100.0),
                                              (3.0, 0.7, 0.3), (1e3, 12.0, 900.0), (40.0, 2.0, 0.0)])
def test_noncentral_sf_matches_scipy(x, nu, lam):
    want = 1.0 - special.chndtr(x, nu, lam)
    # scipy returns the cdf: its 1 - cdf carries an absolute error ~1e-16
    assert _chi2.ncx2_sf(x, nu, lam) == pytest.approx(want, rel=1e-12, abs=1e-15)


def test_round_trip_and_monotone():
    nu = np.geomspace(0.3, 1e7, 60)
    x = _chi2.chi2_isf(1e-3, nu)
    np.testing.assert_allclose(_chi2.chi2_sf(x, nu), 1e-3, rtol=1e-12)
    assert np.all(np.diff(x) > 0)


def test_nan_propagates_and_bad_values_are_refused():
    assert np.isnan(_chi2.chi2_ppf(0.025, np.nan))
    assert np.isnan(_chi2.chi2_sf(np.nan, 3.0))
    with pytest.raises(ValueError, match="a > 0"):
        _chi2.gammainc_pq(-1.0, 1.0)
    with pytest.raises(ValueError, match="0 <= prob <= 1"):
        _chi2.gammaincinv_pq(2.0, 1.5, upper=False)
