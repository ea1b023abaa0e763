"""The finite-record covariance of overlapping Allan-variance points (_covariance._finite_cov_sums).

Each overlapping AVAR estimate is a quadratic form in the Gaussian rate samples, so the
covariance of two of them is 2 tr(A_1 S A_2 S); ``_finite_cov_sums`` evaluates it as a sum
over lags of products of the second-difference kernels' cross-covariances, weighted by the
number of overlapping term pairs (where the record length enters). Checked here against the
explicit matrices, against Monte Carlo, and the scaled correction ``_finite_record_delta``
used by fit_noise against the unscaled exact computation.
"""

from __future__ import annotations

import numpy as np
import pytest

from gyrobench.analysis import allan
from gyrobench.analysis.allan import _covariance

#: the rate covariance matrices of the brute-force check and the factor of each type's shape:
#: Q y = diff of white phase (PSD 4 sin^2), N white, K random walk from 0 (PSD 1/(4 sin^2))
_SCALE = {2: 4.0, 0: 1.0, -2: 0.25}


def _rate_cov(alpha: int, n: int) -> np.ndarray:
    u = np.arange(n)
    if alpha == 0:
        return np.eye(n)
    if alpha == 2:
        return 2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    return np.minimum.outer(u, u) + 1.0  # random walk e_0 + .. + e_u (non-stationary rate)


def _second_differences(m: int, n: int) -> np.ndarray:
    """Rows d_m[k] = x[k + 2m] - 2 x[k + m] + x[k] as weights on the n rate samples."""
    big = n + 1 - 2 * m
    d = np.zeros((big, n))
    for k in range(big):
        d[k, k : k + m] = -1.0
        d[k, k + m : k + 2 * m] = 1.0
    return d


@pytest.mark.parametrize(("m1", "m2"), [(1, 1), (1, 4), (3, 5), (8, 8), (2, 9), (9, 2)])
def test_cov_sums_equal_the_trace(m1, m2):
    n = 40
    alphas = [2, 0, -2]
    got = _covariance._finite_cov_sums(
        alphas, np.array([m1]), np.array([m2]), np.array([n + 1.0 - 2 * m1]),
        np.array([n + 1 - 2 * m2]), 256,
    )[0]
    d1, d2 = _second_differences(m1, n), _second_differences(m2, n)
    a1, a2 = d1.T @ d1, d2.T @ d2
    for ti, t in enumerate(alphas):
        for si, s in enumerate(alphas):
            want = np.trace(a1 @ _rate_cov(t, n) @ a2 @ _rate_cov(s, n))
            assert got[ti, si] * _SCALE[t] * _SCALE[s] == pytest.approx(want, rel=1e-12)


def _d2(x: np.ndarray, m: int, n: int) -> np.ndarray:
    """Second differences x[k + 2m] - 2 x[k + m] + x[k] of each row of the (reps, n + 1) phases."""
    return x[:, 2 * m :] - 2 * x[:, m : n + 1 - m] + x[:, : n + 1 - 2 * m]


def _exact_rho(alphas, mi, mj, n, grid):
    """Unscaled rho_ts(i, j) of a record of n samples and of n -> infinity (single pair)."""
    big = lambda m: float(n + 1 - 2 * m)  # noqa: E731
    m1, m2 = np.array([mi, mj, mi]), np.array([mi, mj, mj])

    def rho(b1, b2):
        t = _covariance._finite_cov_sums(alphas, m1, m2, b1, b2, grid)
        return t[2] / np.sqrt(np.outer(np.diagonal(t[0]), np.diagonal(t[1])))

    fin = rho(np.array([big(mi), big(mj), big(mi)]), np.array([big(mi), big(mj), big(mj)]))
    inf = rho(np.full(3, 1e18), np.full(3, 1e18))
    return fin, inf


@pytest.mark.slow  # exact finite-record correlations over many pairs (tens of seconds): slow tier
def test_scaled_correction_against_the_exact_one():
    """The correction fit_noise adds (pairs scaled to m <= 64) against the unscaled exact one.

    The stated accuracy of the scaled approximation (docs/physics.md 1.6), at _FIN_CAP = 32:
    same-type terms (the ones that carry a point's variance) <= 0.03 (measured 0.028, K; the
    correction itself reaches 0.2; 0.020 at a cap of 64, which cost ~4 ms per first fit and
    the 2e5-sample speed target); cross-type terms with quantization at a large m <= 0.1
    (measured 0.096; Q is not scale-free, but its share of a point there is ~(m_Q/m)^2,
    negligible). Pairs with both m <= _FIN_CAP are unscaled and exact (Q, N, K) to rounding.
    """
    n = 20000
    ms = 2 ** np.arange(13)  # up to 4096 < n/4
    ua = [2, 0, -1, -2]
    delta = _covariance._finite_record_delta(ua, ms, n)
    worst_same = worst_cross = 0.0
    for i in range(ms.size):
        for j in range(i, ms.size):
            grid = max(1 << 14, int(2 ** np.ceil(np.log2(16 * (ms[i] + ms[j])))))
            fin, inf = _exact_rho(ua, ms[i], ms[j], n, grid)
            got = np.array([[delta[(t, s)][i, j] for s in range(4)] for t in range(4)])
            err = np.abs(got - (fin - inf))
            if ms[j] <= _covariance._FIN_CAP:  # unscaled: Q, N, K exact; flicker aliased on the grid
                qnk = np.ix_([0, 1, 3], [0, 1, 3])
                np.testing.assert_allclose(got[qnk], (fin - inf)[qnk], atol=1e-12)
            worst_same = max(worst_same, float(np.diagonal(err).max()))
            worst_cross = max(worst_cross, float((err - np.diag(np.diagonal(err))).max()))
    assert worst_same <= 0.03
    assert worst_cross <= 0.1


def test_finite_record_covariance_against_monte_carlo(rng):
    """White rate noise, n = 256, m = 32 and 64 (T/4): the record ends lower the correlation.

    Cov(A_32, A_64) is estimated from 20000 records in 100 batches; the batch means' t test
    at false alarm 1e-6 accepts the exact finite-record value and rejects the n >> m model.
    """
    from scipy import stats

    n, reps, batches = 256, 20000, 100
    m = np.array([32, 64])
    big = n + 1 - 2 * m
    bf = big.astype(float)
    exact = _covariance._finite_cov_sums([0], m[[0]], m[[1]], bf[[0]], bf[[1]], 1024)[0, 0, 0]
    var = _covariance._finite_cov_sums([0], m, m, big.astype(float), big.astype(float), 1024)[:, 0, 0]
    norm = 2.0 * m.astype(float) ** 2 * big
    cov_exact = 2.0 * exact / (norm[0] * norm[1])
    # the n >> m model: the same correlation with every count equal (_covariance._rho_blocks)
    rho_inf = _covariance._rho_blocks([0], m)[(0, 0)][0, 1]
    cov_inf = rho_inf * 2.0 * np.sqrt(var[0] * var[1]) / (norm[0] * norm[1])
    y = rng.standard_normal((reps, n))
    x = np.concatenate([np.zeros((reps, 1)), np.cumsum(y, axis=1)], axis=1)
    a = np.stack([(_d2(x, k, n) ** 2).sum(1) for k in m], 1) / norm
    a = a.reshape(batches, reps // batches, 2)
    a = a - a.mean(1, keepdims=True)
    c = (a[..., 0] * a[..., 1]).sum(1)
    c /= reps // batches - 1
    se = c.std(ddof=1) / np.sqrt(batches)
    tol = stats.t.isf(0.5e-6, batches - 1) * se
    assert abs(c.mean() - cov_exact) <= tol
    assert abs(c.mean() - cov_inf) > tol


def _phase_second_differences(m: int, n: int) -> np.ndarray:
    """Rows d_m[k] = e[k + 2m] - 2 e[k + m] + e[k] as weights on the n + 1 phase errors e."""
    big = n + 1 - 2 * m
    d = np.zeros((big, n + 1))
    for k in range(big):
        d[k, k] += 1.0
        d[k, k + m] -= 2.0
        d[k, k + 2 * m] += 1.0
    return d


def test_quantization_kurtosis_rho_equals_the_matrix_form():
    """k sum_u A_uu B_uu / (2 sqrt(tr(AA) tr(BB))) with the explicit matrices (n = 40)."""
    n = 40
    ms = np.array([1, 2, 3, 5, 8, 10])
    got = _covariance._quantization_kurtosis_rho(ms, n)
    a = [(lambda d: d.T @ d)(_phase_second_differences(int(m), n)) for m in ms]
    k = allan.QUANTIZATION_KURTOSIS
    for i in range(ms.size):
        for j in range(ms.size):
            tr = np.sqrt(np.trace(a[i] @ a[i]) * np.trace(a[j] @ a[j]))
            want = k * np.sum(np.diag(a[i]) * np.diag(a[j])) / (2 * tr)
            assert got[i, j] == pytest.approx(want, rel=1e-12)


def test_uniform_quantization_covariance_against_monte_carlo(rng):
    """Uniform angle errors, n = 512, m = 1, 2, 8, 64: variances and covariances of the AVAR.

    Model: Cov = s_i s_j (rho_Gauss + rho_kurtosis), with the Gaussian sums of
    _finite_cov_sums. 20000 records in 100 batches; each of the 4 variances and 6
    covariances passes the batch-means t test at a family-wise false alarm of 1e-6
    (Bonferroni over the 10), and the Gaussian model (rho_kurtosis = 0) fails it.
    """
    from scipy import stats

    n, reps, batches = 512, 20000, 100
    ms = np.array([1, 2, 8, 64])
    big = (n + 1 - 2 * ms).astype(float)
    i1, i2 = np.meshgrid(np.arange(4), np.arange(4), indexing="ij")
    i1, i2 = i1.ravel(), i2.ravel()
    t = _covariance._finite_cov_sums([2], ms[i1], ms[i2], big[i1], big[i2], 2048)
    gauss = 2.0 * 16.0 * t[:, 0, 0].reshape(4, 4)  # shape sin^2; differenced phase: 4 sin^2
    sd = np.sqrt(np.diag(gauss))
    kurt = _covariance._quantization_kurtosis_rho(ms, n) * np.outer(sd, sd)
    norm = 2.0 * ms.astype(float) ** 2 * big
    want, gauss_only = (gauss + kurt) / np.outer(norm, norm), gauss / np.outer(norm, norm)
    e = (rng.random((reps, n + 1)) - 0.5) * np.sqrt(12.0)
    a = np.stack([(_d2(e, m, n) ** 2).sum(1) for m in ms], 1) / norm
    a = a.reshape(batches, reps // batches, 4)
    a = a - a.mean(1, keepdims=True)
    c = np.einsum("bri,brj->bij", a, a) / (reps // batches - 1)
    se = c.std(axis=0, ddof=1) / np.sqrt(batches)
    q = stats.t.isf(0.5e-6 / 10, batches - 1)
    iu = np.triu_indices(4)
    assert np.all(np.abs(c.mean(0) - want)[iu] <= q * se[iu])
    assert np.any(np.abs(c.mean(0) - gauss_only)[iu] > q * se[iu])


def test_gaussian_quantization_kurtosis_gives_the_gaussian_fit(rng):
    """quantization_kurtosis=0 drops the fourth-cumulant term; bad values are refused."""
    y = np.diff(rng.random(20_001)) * 3.0 + rng.standard_normal(20_000)
    curve = allan.allan_deviation(y, 10.0)
    gauss = allan.fit_noise(curve, quantization_kurtosis=0.0)
    uniform = allan.fit_noise(curve)
    q = list(uniform.avar_coefficients).index("Q")
    assert uniform.covariance[q, q] < gauss.covariance[q, q]  # uniform error: smaller variance
    with pytest.raises(ValueError, match="quantization_kurtosis must be >= -2"):
        allan.fit_noise(curve, quantization_kurtosis=-3.0)
    with pytest.raises(TypeError, match="quantization_kurtosis must be a number"):
        allan.fit_noise(curve, quantization_kurtosis="uniform")


def test_count_weighted_sums_by_pieces_equal_the_counts_written_out():
    # the fit sums c_p(h) R_t R_s over the lag grid as M_1 S_1 + M_2 S_2 + S_3 with one S per (key, D)
    # (the counts are piecewise linear in h once both records are >= grid/2 long); here against the
    # counts of _overlap_counts summed term by term, for records around that length, either sign of
    # D = M_2 - M_1, integer and fractional M (scaled pairs), several pairs per key
    rng = np.random.default_rng(7)
    grid = 64
    h = np.arange(grid)
    h = np.where(h < grid // 2, h, h - grid)
    r = rng.standard_normal((5, grid, 3))
    key = rng.integers(0, 5, 400)
    b1 = rng.choice([rng.uniform(1, 40), 31.0, 32.0, 32.5, 1e6], 400) + rng.integers(0, 3, 400) * 7.5
    b2 = np.maximum(b1 + rng.choice([-40.0, -3.0, -0.5, 0.0, 2.0, 2.25, 40.0], 400), 1.0)
    got = _covariance._count_weighted(r, key, h, b1, b2)
    c = _covariance._overlap_counts(b1, b2, h)
    want = np.einsum("ph,pht,phs->pts", c, r[key], r[key])
    assert np.any(np.minimum(b1, b2) < grid // 2) and np.any(np.minimum(b1, b2) >= grid // 2)
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12 * np.abs(want).max())


def test_the_precomputed_point_covariance_equals_the_term_by_term_one():
    # the fit evaluates V(C) ~30 times through PointCovarianceModel (one product with C C');
    # here against _point_covariance + _ramp_cross_sd evaluated from scratch, with and without R
    # and with a zero C_R (no ramp cross term)
    from gyrobench.analysis.allan._fit import _ALPHA, _POWER

    rng = np.random.default_rng(3)
    ms = 2 ** np.arange(12)
    tau = ms / 100.0
    n = 200_000
    for terms in (("Q", "N", "B", "K", "R"), ("N", "B", "K")):
        alphas = [_ALPHA[t] for t in terms]
        rho = _covariance._rho_blocks(alphas, ms)
        x = tau[:, None] ** np.array([_POWER[t] for t in terms])[None, :]
        nu = rng.uniform(2.0, 50.0, x.shape)
        noise = np.array([t != "R" for t in terms])
        ramp = (*_covariance._ramp_basis(terms, tau, ms, n, "overlapping"), terms.index("R")) if "R" in terms else None
        model = _covariance.PointCovarianceModel(x, nu, rho, noise, ramp)
        for c in (rng.uniform(0.0, 1.0, len(terms)), np.r_[rng.uniform(0.0, 1.0, len(terms) - 1), 0.0]):
            want = _covariance._point_covariance(
                x, c, nu, rho, noise, _covariance._ramp_cross_sd(terms, c, tau, ms, n, "overlapping")
            )
            np.testing.assert_allclose(model(c), want, rtol=1e-12, atol=1e-14 * np.abs(want).max())
