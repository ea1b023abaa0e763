"""Goodness of fit of the noise fit: chi2 of the standardised residuals and its exact-law tail.

References
----------
H. Liu, Y. Tang and H. H. Zhang, "A new chi-square approximation to the distribution of
non-negative definite quadratic forms in non-central normal variables", Comput. Stat. Data
Anal. 53 (2009) 853-856.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from gyrobench.analysis.allan._chi2 import chi2_sf, ncx2_sf


def _goodness(
    r: NDArray[np.float64],
    v: NDArray[np.float64],
    x: NDArray[np.float64],
    var: NDArray[np.float64],
    kept: NDArray[np.bool_],
) -> tuple[float, int, float, float]:
    """chi2 = sum r_i^2 / V_ii, dof, E[chi2] and P(chi2 >= observed) under the model.

    The residuals of the weighted fit (weights 1/var, the kept columns of ``x``; at the NNLS
    solution the kept terms are the unconstrained weighted fit on those columns) are
    r = (I - H) A with H = X_k (X_k' W X_k)^-1 X_k' W, so the standardised residuals z = D^-1 r
    (D^2 = diag V) have covariance S = D^-1 (I - H) V (I - H)' D^-1 and, for Gaussian points,
    chi2 = z'z = sum_k lambda_k chi2_1 with lambda the eigenvalues of S. Its tail is the
    4-cumulant non-central chi-square approximation of H. Liu, Y. Tang and H. H. Zhang,
    "A new chi-square approximation to the distribution of non-negative definite quadratic
    forms in non-central normal variables", Comput. Stat. Data Anal. 53 (2009) 853-856.
    """
    dof = r.size - int(np.count_nonzero(kept))
    if dof <= 0:
        return float("nan"), 0, float("nan"), float("nan")
    d = np.sqrt(np.diag(v))
    z = r / d
    chi2 = float(z @ z)
    xk = x[:, kept] / np.sqrt(var)[:, None]  # W^1/2 X_k
    q, _ = np.linalg.qr(xk)
    sw = np.sqrt(var) / d  # W^-1/2 D^-1 (diagonal; ~1 at convergence, where var = diag V)
    # I - H = W^-1/2 (I - Q Q') W^1/2, so D^-1 (I - H) = diag(sw) (I - Q Q') W^1/2
    m = (np.eye(r.size) - q @ q.T) * (sw[:, None] / np.sqrt(var)[None, :])
    s = m @ v @ m.T
    lam = np.clip(np.linalg.eigvalsh((s + s.T) / 2.0), 0.0, None)
    c1, c2, c3, c4 = (float(np.sum(lam**k)) for k in (1, 2, 3, 4))
    return chi2, dof, c1, _ltz_sf(chi2, c1, c2, c3, c4)


def _ltz_sf(q: float, c1: float, c2: float, c3: float, c4: float) -> float:
    """P(Q >= q) for Q = sum lambda_k chi2_1 from its cumulant sums c_k = sum lambda^k (Liu-Tang-Zhang 2009)."""
    if c2 <= 0.0:
        return float("nan")
    s1, s2 = c3 / c2**1.5, c4 / c2**2
    if s1 * s1 > s2:
        a = 1.0 / (s1 - math.sqrt(s1 * s1 - s2))
        delta = s1 * a**3 - a * a
        ell = a * a - 2.0 * delta
    else:
        a, delta, ell = 1.0 / s1, 0.0, 1.0 / (s1 * s1)
    t = (q - c1) / math.sqrt(2.0 * c2) * math.sqrt(2.0) * a + ell + delta
    if t <= 0.0:  # below the support of the matched chi-square (a small chi2): no evidence of misfit
        return 1.0
    if delta > 0.0:
        return ncx2_sf(t, ell, delta)
    return float(chi2_sf(t, ell))

