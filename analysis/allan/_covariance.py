"""The modelled covariance of Allan-variance points: correlations by noise type, finite-record
and quantization corrections, the ramp cross term (the point covariance V of the noise fit).

References
----------
C. A. Greenhall and W. J. Riley, PTTI 2003 (edf); B. Widrow and I. Kollar, "Quantization
Noise" (2008) ch. 4; docs/physics.md 1.5.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from gyrobench.analysis.allan._blas import _GEMM_SINGLE, _one_blas_thread
from gyrobench.analysis.allan._kinds import STATISTICS, _distinct, _n_terms

#: correlations are computed exactly (discrete time) up to this m; larger pairs are scaled down
#: keeping their ratio (the correlation of power-law noise depends on m_j/m_i only, for large m)
_RHO_M_CAP = 1024
#: frequency points on (0, 1/2]: 32 per period of sin^4(pi f m_cap). Against 128 per period
#: (65536 points, used before) every correlation moves by <= 8.5e-4 (measured over the 18
#: octaves and the four noise types), far below the model's own accuracy (see fit_noise:
#: modelled 0.40 vs measured 0.33 +- 0.06); the midpoint rule converges slowly only for
#: flicker, whose integrand has a kink at f = 0.
_RHO_GRID = 16 * _RHO_M_CAP


def _rate_psd_shape(alpha: int, f: NDArray[np.float64]) -> NDArray[np.float64]:
    """Shape of the discrete-time rate PSD of each power-law type (f in cycles/sample)."""
    s = np.sin(np.pi * f)
    if alpha == 2:
        return s * s  # differenced white angle (quantization)
    if alpha == 0:
        return np.ones_like(f)  # white rate (ARW)
    if alpha == -1:
        return 1.0 / f  # flicker rate (bias instability)
    return 1.0 / (s * s)  # random-walk rate (RRW; also used for the ramp)


@functools.lru_cache(maxsize=1)
def _rho_grid() -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Midpoint grid f on (0, 1/2] [cycles/sample] and sin(pi f) on it (built on first use)."""
    f = (np.arange(_RHO_GRID) + 0.5) / (2 * _RHO_GRID)
    return f, np.sin(np.pi * f)


def _h(m: int) -> NDArray[np.float64]:
    """|H_m|^2 / 4 = sin^4(pi f m) / sin^2(pi f) on the grid (shared by every noise type)."""
    f, s1 = _rho_grid()
    s = np.sin((np.pi * m) * f)
    s *= s
    s /= s1
    s *= s
    return s


def _scaled(m1: int, m2: int) -> tuple[int, int]:
    """Scale a pair of m down to max <= _RHO_M_CAP keeping their ratio (see :func:`_rho_blocks`)."""
    if max(m1, m2) <= _RHO_M_CAP:
        return m1, m2
    k = max(m1, m2) / _RHO_M_CAP
    return max(1, int(round(m1 / k))), max(1, int(round(m2 / k)))


def _scaled_pairs(ms: NDArray[np.int64]) -> NDArray[np.int64]:
    """:func:`_scaled` of every pair (ms[i], ms[j]), vectorised: shape (n, n, 2)."""
    m1, m2 = np.meshgrid(ms, ms, indexing="ij")
    top = np.maximum(m1, m2)
    k = top / _RHO_M_CAP
    big = top > _RHO_M_CAP
    s1 = np.where(big, np.maximum(1, np.rint(m1 / k)), m1).astype(np.int64)  # rint: half to even, as round
    s2 = np.where(big, np.maximum(1, np.rint(m2 / k)), m2).astype(np.int64)
    return np.stack((s1, s2), axis=-1)


def _rho_blocks(alphas: Sequence[int], ms: NDArray[np.int64]) -> dict[tuple[int, int], NDArray[np.float64]]:
    """rho[(t, s)][i, j]: correlation of term t's noise in A_i with term s's noise in A_j.

    For Gaussian noise with rate PSD S = sum_t S_t, Cov(sum_k D_i[k]^2, sum_l D_j[l]^2)
    = 2 sum_{k,l} E[D_i[k] D_j[l]]^2 -> 2 n int S^2 |H_i|^2 |H_j|^2 df (Parseval, n >> m),
    with |H_m(f)|^2 = 4 sin^4(pi f m) / sin^2(pi f) the response of the second difference
    of the phase to the rate. Expanding S^2 = sum_{t,s} S_t S_s splits the covariance into
    rho_ts(i, j) sd_t(i) sd_s(j) with rho_ts(i, j) = int g_ti g_sj / sqrt(int g_ti^2 int g_sj^2),
    g_ti = S_t |H_i|^2 (S_t the discrete-time shape of each power law: sin^2(pi f) for
    quantization, 1 white, 1/f flicker, 1/sin^2(pi f) random walk). The integrals use the
    midpoint rule on 16384 points of (0, 1/2] (32 per period of the fastest factor).
    For m above 1024 both m of a pair are scaled down keeping their ratio: for power-law
    noise in the continuous-time limit rho depends on m_j/m_i only. This is the n >> m limit:
    the record's ends are added by :func:`_finite_record_delta` in the fit. Octave taus read
    the stored table (:func:`_octave_gram`); the result depends only on the alphas and the m,
    so it is cached (the same taus again, e.g. the other axes of a triad, cost nothing).
    """
    key = (tuple(int(a) for a in alphas), tuple(int(m) for m in ms))
    return {k: v.copy() for k, v in _rho_blocks_cached(*key).items()}


@functools.lru_cache(maxsize=64)
def _rho_blocks_cached(
    alphas: tuple[int, ...], ms: tuple[int, ...]
) -> dict[tuple[int, int], NDArray[np.float64]]:
    n = len(ms)
    pairs = _scaled_pairs(np.asarray(ms, dtype=np.int64))  # (n, n, 2)
    mu = [int(m) for m in _distinct(pairs)]
    ua = sorted(set(alphas))
    gram = _octave_gram(ua, mu)
    if gram is None:  # some m is not a power of two (or the table does not hold it): compute
        gram = _gram_direct(ua, mu)
    lookup = np.zeros(max(mu) + 1, dtype=np.int64)
    lookup[mu] = np.arange(len(mu))
    i1 = lookup[pairs[..., 0]]
    i2 = lookup[pairs[..., 1]]
    diag = np.eye(n, dtype=bool)
    out = {}
    for t, at in enumerate(alphas):
        for s_, as_ in enumerate(alphas):
            r = gram[ua.index(at) * len(mu) + i1, ua.index(as_) * len(mu) + i2]
            if at == as_:
                r[diag] = 1.0
            out[(t, s_)] = r
    return out


def _gram_direct(ua: Sequence[int], mu: Sequence[int]) -> NDArray[np.float64]:
    """Gram matrix of the unit-norm g = S_alpha |H_m|^2 rows, alpha in ``ua`` (outer) by m in ``mu`` (inner).

    Entry [a * len(mu) + i, b * len(mu) + j] = int g_{ua[a], mu[i]} g_{ua[b], mu[j]} df on
    the midpoint grid of :func:`_rho_grid` (see :func:`_rho_blocks`).
    """
    f = _rho_grid()[0]
    h = np.stack([_h(m) for m in mu])  # (len(mu), grid)
    g = np.concatenate([h * _rate_psd_shape(a, f)[None, :] for a in ua])  # (len(ua) len(mu), grid)
    g /= np.linalg.norm(g, axis=1)[:, None]
    rows = g.shape[0]
    chunk = _GEMM_SINGLE // (rows * rows)
    if chunk >= 64:  # k-chunks small enough that OpenBLAS runs each product on one thread
        gram = np.zeros((rows, rows))
        gt = np.ascontiguousarray(g.T)
        for a in range(0, g.shape[1], chunk):
            gram += g[:, a : a + chunk] @ gt[a : a + chunk]
    else:
        with _one_blas_thread():  # a first multithreaded BLAS call costs ~1-2 s of start-up on a busy VM
            gram = g @ g.T
    return gram


#: the noise types and the m of the stored octave table (``_rho_table``)
_TABLE_ALPHAS = (-2, -1, 0, 2)
_TABLE_MS = tuple(1 << k for k in range(_RHO_M_CAP.bit_length()))  # 1, 2, 4, .., 1024


def _octave_gram_direct() -> NDArray[np.float64]:
    """The full octave gram matrix (every alpha of _TABLE_ALPHAS, every m of _TABLE_MS), computed."""
    return _gram_direct(_TABLE_ALPHAS, _TABLE_MS)


@functools.lru_cache(maxsize=1)
def _octave_table() -> NDArray[np.float64] | None:
    """The stored octave gram matrix (44 x 44), or None when it was made for another grid or cap."""
    import binascii  # (base64 itself imports struct and re: ~1 ms)

    from gyrobench.analysis.allan import _rho_table as tab

    if (tab.GRID, tab.M_CAP, tab.ALPHAS, tab.MS) != (_RHO_GRID, _RHO_M_CAP, _TABLE_ALPHAS, _TABLE_MS):
        return None  # pragma: no cover - the table is regenerated whenever these change (a test checks)
    k = len(tab.ALPHAS) * len(tab.MS)
    gram = np.frombuffer(binascii.a2b_base64(tab.GRAM), dtype="<f8").reshape(k, k).astype(float)
    gram.flags.writeable = False
    return gram


def _octave_gram(ua: Sequence[int], mu: Sequence[int]) -> NDArray[np.float64] | None:
    """Rows/columns ``ua`` x ``mu`` of the stored octave table, or None if it does not hold them all.

    The table is :func:`_octave_gram_direct` evaluated once and stored (gyrobench.analysis.
    _rho_table, written by benchmarks/make_rho_table.py): building the 44 g vectors on
    the 16384-point grid and their products cost ~20 ms on first use, the largest fixed cost
    of a fit on an ordinary record; a test checks the table against the direct computation.
    """
    if not (set(ua) <= set(_TABLE_ALPHAS) and set(mu) <= set(_TABLE_MS)):
        return None
    table = _octave_table()
    if table is None:  # pragma: no cover
        return None
    idx = np.array([_TABLE_ALPHAS.index(a) * len(_TABLE_MS) + _TABLE_MS.index(m) for a in ua for m in mu])
    return table[np.ix_(idx, idx)]


#: finite-record correction of rho (overlapping AVAR, :func:`_finite_record_delta`): a pair
#: whose larger m exceeds this is scaled down to it, keeping the ratio m_j/m_i and N/m.
#: 32, not 64: same-type correlations stay within 0.03 of the exact form (0.02 at 64), and
#: the first fit of a 2e5-sample record is ~4 ms faster (it keeps the fit ahead of
#: allantools + NNLS there; coverage is the same at either cap)
_FIN_CAP = 32
#: lags h on a circle of this many points (midpoint frequency grid): more than the 4 _FIN_CAP + 1
#: lags where the kernels' cross-correlations of Q, N and K are non-zero, so those are exact
_FIN_GRID = 8 * _FIN_CAP


def _lag_covariances(
    alphas: Sequence[int], m1: NDArray[np.int64], m2: NDArray[np.int64], grid: int
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """R[p, j, t] = E[d_{m1[p]}[k] d_{m2[p]}[k + h[j]]] for unit noise of type alphas[t]; and h.

    d_m[k] = x[k + 2m] - 2 x[k + m] + x[k] is the second difference of the phase x (cumulative
    sum of the rate samples y), i.e. sum_u w_m[u] y[k + u] with w_m = -1 on u < m, +1 on
    m <= u < 2m, whose transfer function is W_m(f) = -(1 - z^m)^2 / (1 - z), z = exp(-2 pi i f).
    R(h) = int_{-1/2}^{1/2} S(f) W_1(f) conj(W_2(f)) exp(2 pi i f h) df with S the discrete
    rate PSD shape of :func:`_rate_psd_shape` (sin^2(pi f): differenced white phase; 1; 1/|f|;
    1/sin^2(pi f): random walk), evaluated on ``grid`` midpoints by one inverse FFT: exact for
    lags |h| < grid/2 whenever S |W|^2 is a trigonometric polynomial of degree < grid/2 (Q, N,
    K: the kernels have finite support), else aliased (flicker: the error is the tail sum
    sum_p (-1)^p R(h + p grid), R decaying as h^-2).
    """
    f = (np.arange(grid) + 0.5) / grid
    mu, inv = np.unique(np.concatenate([m1, m2]), return_inverse=True)
    z1 = np.exp(-2j * np.pi * f)
    zm = np.exp(-2j * np.pi * np.outer(mu, f))
    w = -((1.0 - zm) ** 2) / (1.0 - z1)
    p = w[inv[: len(m1)]] * np.conj(w[inv[len(m1):]])
    h = np.arange(grid)
    h = np.where(h < grid // 2, h, h - grid)
    shift = np.exp(1j * np.pi * h / grid)
    fold = np.minimum(f, 1.0 - f)
    r = np.empty((p.shape[0], grid, len(alphas)))
    for t, a in enumerate(alphas):  # one noise type at a time: (pairs, grid) arrays stay in cache
        r[:, :, t] = (np.fft.ifft(p * _rate_psd_shape(int(a), fold), axis=1) * shift).real
    return r, h


def _overlap_counts(
    big_m1: NDArray[np.float64], big_m2: NDArray[np.float64], h: NDArray[np.int64]
) -> NDArray[np.float64]:
    """#{k : 0 <= k < M1, 0 <= k + h < M2}: pairs of terms (d_1[k], d_2[k + h]) of two estimates."""
    m1 = np.asarray(big_m1, dtype=float)[:, None]
    m2 = np.asarray(big_m2, dtype=float)[:, None]
    return np.maximum(0.0, np.minimum(m1, m2 - h[None, :]) - np.maximum(0, -h)[None, :])


def _finite_cov_sums(
    alphas: Sequence[int],
    m1: NDArray[np.int64],
    m2: NDArray[np.int64],
    big_m1: NDArray[np.float64],
    big_m2: NDArray[np.float64],
    grid: int,
) -> NDArray[np.float64]:
    """T[p, t, s] = sum_h R^t_p(h) R^s_p(h) c_p(h), c_p the :func:`_overlap_counts`.

    For Gaussian rate noise with covariance S = sum_t S_t, the overlapping AVAR estimates
    A_i = sum_{k < M_i} d_i[k]^2 / (2 m_i^2 tau_0^2 M_i) are quadratic forms, and
    Cov(A_1, A_2) = 2 sum_{k, l} E[d_1[k] d_2[l]]^2 / norms = 2 sum_{t, s} sum_h R^t(h) R^s(h)
    c(h) / norms: exact for a record of finite length (M_i = n + 1 - 2 m_i terms; the count of
    overlapping term pairs at lag h is where the record ends enter), as the trace
    2 tr(A_1 S A_2 S) (a test checks it against the explicit matrices).
    """
    r, h = _lag_covariances(alphas, m1, m2, grid)
    c = _overlap_counts(big_m1, big_m2, h)
    return np.einsum("pht,phs,ph->pts", r, r, c)


def _finite_record_delta(
    alphas: Sequence[int], ms: NDArray[np.int64], n: int
) -> dict[tuple[int, int], NDArray[np.float64]]:
    """rho_ts(i, j) of a record of n samples minus the same for n -> infinity (overlapping AVAR).

    rho_ts(i, j) = T_ts(i, j) / sqrt(T_tt(i, i) T_ss(j, j)) with T of :func:`_finite_cov_sums`
    (counts for n samples) and with counts replaced by 1 (the n >> m limit that
    :func:`_rho_blocks` models). Pairs with max(m_i, m_j) > _FIN_CAP are evaluated at m scaled
    down to _FIN_CAP with the record scaled alike (M / k): for power-law noise in the
    continuous-time limit the correlation depends on m_j/m_i and M/m only. The difference of
    the two (same kernels, same grid) is added to the stored asymptotic correlations; its
    error against the exact unscaled computation is checked in the tests.
    """
    key = (tuple(int(a) for a in alphas), tuple(int(m) for m in ms), int(n))
    return {k: v.copy() for k, v in _finite_record_delta_cached(*key).items()}


def _count_weighted(
    r: NDArray[np.float64],
    key: NDArray[np.int64],
    h: NDArray[np.int64],
    big_m1: NDArray[np.float64],
    big_m2: NDArray[np.float64],
) -> NDArray[np.float64]:
    """out[p, t, s] = sum_h c_p(h) R[key[p], h, t] R[key[p], h, s], c_p the :func:`_overlap_counts` of p.

    Where both records are at least half the lag grid long (M_1, M_2 >= grid/2: no count is
    clipped at 0), c(h) = min(M_1, M_2 - h) - max(0, -h) is piecewise linear in h with one
    break at D = M_2 - M_1:

        c(h) = M_1 [h <= D] + M_2 [h > D] - h [h > D] + h [h < 0],

    so the sum is M_1 S_1 + M_2 S_2 + S_3 with S_w = sum_h w(h) R_t R_s evaluated once per
    distinct (key, floor(D)), not per pair: octave taus have one D per key, so the many pairs
    cost a few (T x grid) @ (grid x T) products. Shorter records (a pair's last octaves scaled
    down) take the counts written out. A test checks both against the explicit sum.
    """
    big_m1 = np.asarray(big_m1, dtype=float)
    big_m2 = np.asarray(big_m2, dtype=float)
    out = np.empty((key.size, r.shape[2], r.shape[2]))
    long = np.minimum(big_m1, big_m2) >= h.size // 2
    if np.any(long):
        d = np.floor(big_m2[long] - big_m1[long]).astype(np.int64)
        lo = int(d.min())
        span = int(d.max()) - lo + 1
        codes, back = np.unique(key[long] * span + (d - lo), return_inverse=True)  # (key, D) as one integer
        hs = h[None, :]
        after = hs > (codes % span + lo)[:, None]  # (combos, grid)
        weights = np.stack([~after, after, np.where(after, -hs, 0) + np.where(hs < 0, hs, 0)]).astype(float)
        rk = r[codes // span]  # (combos, grid, T)
        sums = np.matmul((rk[None] * weights[:, :, :, None]).transpose(0, 1, 3, 2), rk[None])  # (3, combos, T, T)
        back = back.reshape(-1)
        out[long] = (
            big_m1[long, None, None] * sums[0][back] + big_m2[long, None, None] * sums[1][back] + sums[2][back]
        )
    short = np.flatnonzero(~long)
    if short.size:
        rs = r[key[short]]
        counts = _overlap_counts(big_m1[short], big_m2[short], h)
        out[short] = np.matmul((rs * counts[:, :, None]).transpose(0, 2, 1), rs)
    return out


@functools.lru_cache(maxsize=16)
def _finite_record_delta_cached(
    alphas: tuple[int, ...], ms_t: tuple[int, ...], n: int
) -> dict[tuple[int, int], NDArray[np.float64]]:
    ms = np.asarray(ms_t, dtype=np.int64)
    ua = sorted(set(alphas))
    nm = ms.size
    ii, jj = np.triu_indices(nm)
    mi, mj = ms[ii], ms[jj]
    k = np.maximum(np.maximum(mi, mj) / _FIN_CAP, 1.0)
    a = np.maximum(1, np.rint(mi / k)).astype(np.int64)
    b = np.maximum(1, np.rint(mj / k)).astype(np.int64)
    big = _n_terms("overlapping", n, ms).astype(float)
    bi, bj = big[ii] / k, big[jj] / k
    # the distinct kernel pairs (a, b), (a, a), (b, b); their lag covariances once each
    # (a pair (a, b) encoded as a * base + b: np.unique over rows (axis=0) cost ~0.5 ms here)
    base = int(max(int(a.max()), int(b.max()))) + 1
    codes = np.concatenate([a * base + b, a * base + a, b * base + b])
    uc, inv = np.unique(codes, return_inverse=True)
    uk = np.stack([uc // base, uc % base], axis=1)
    inv = inv.reshape(-1)
    r, h = _lag_covariances(ua, uk[:, 0], uk[:, 1], _FIN_GRID)  # (keys, grid, T)
    p = ii.size
    cross, d1, d2 = inv[:p], inv[p : 2 * p], inv[2 * p :]
    fin = _count_weighted(r, cross, h, bi, bj)  # (pairs, T, T): t at m_i, s at m_j
    v1 = np.diagonal(_count_weighted(r, d1, h, bi, bi), axis1=1, axis2=2)
    v2 = np.diagonal(_count_weighted(r, d2, h, bj, bj), axis1=1, axis2=2)
    zf = np.matmul(r.transpose(0, 2, 1), r)  # the n -> infinity limit: every count 1
    zd = np.diagonal(zf, axis1=1, axis2=2)
    rho_fin = fin / np.sqrt(v1[:, :, None] * v2[:, None, :])
    rho_inf = zf[cross] / np.sqrt(zd[d1][:, :, None] * zd[d2][:, None, :])
    delta = rho_fin - rho_inf  # (pairs, T, T): t at m_i, s at m_j
    out = {}
    for t, at in enumerate(alphas):
        for s_, as_ in enumerate(alphas):
            x, y = ua.index(at), ua.index(as_)
            blk = np.zeros((nm, nm))
            blk[ii, jj] = delta[:, x, y]
            blk[jj, ii] = delta[:, y, x]
            out[(t, s_)] = blk
    return out


#: excess kurtosis kappa_4 / sigma^4 of angle quantization noise: the error of a uniform
#: quantizer is uniform on [-q/2, q/2) (Widrow & Kollar, Quantization Noise, 2008, ch. 4),
#: mu_4 / sigma^4 = 9/5, so -6/5 (the simulator's ``quantization`` draws exactly this);
#: fit_noise's default ``quantization_kurtosis``
QUANTIZATION_KURTOSIS = -6.0 / 5.0


def _quantization_kurtosis_rho(
    ms: NDArray[np.int64], n: int, kurtosis: float = QUANTIZATION_KURTOSIS
) -> NDArray[np.float64]:
    """Fourth-cumulant part of the quantization term's rho_QQ(i, j) (overlapping AVAR).

    For i.i.d. angle errors e of variance s^2 and excess kurtosis k, a quadratic form
    e'Ae has Cov(e'Ae, e'Be) = 2 s^4 tr(AB) + k s^4 sum_u A_uu B_uu; the Gaussian part is
    :func:`_rho_blocks` (+ :func:`_finite_record_delta`). With d_m[k] = e[k + 2m] - 2 e[k + m]
    + e[k], k < M = n + 1 - 2m, A_uu = a_u = [0 <= u < M] + 4 [m <= u < m + M] + [2m <= u <
    2m + M] and the Gaussian sum T_mm = sum_h R(h)^2 (M - |h|)_+ = 36 M + 32 (M - m)_+
    + 2 (M - 2m)_+, so the part added to rho_QQ(i, j) is k sum_u a_u b_u / (2 sqrt(T_ii T_jj)),
    exact for a finite record; about -0.31 (= -6/5 36/140) for every pair, the diagonal too:
    uniform quantization gives Q-dominated AVAR points 0.69x the Gaussian variance and
    correlations ~0.1 instead of ~0.4 (a test checks both against Monte Carlo).
    """
    m = ms.astype(float)
    big = np.maximum(n + 1 - 2 * m, 0.0)
    t = 36.0 * big + 32.0 * np.maximum(big - m, 0.0) + 2.0 * np.maximum(big - 2.0 * m, 0.0)
    w = np.array([1.0, 4.0, 1.0])
    start = m[:, None] * np.arange(3)[None, :]  # (n_m, 3): the three boxes [start, start + M)
    lo = np.maximum(start[:, None, :, None], start[None, :, None, :])
    end = start + big[:, None]
    hi = np.minimum(end[:, None, :, None], end[None, :, None, :])
    ab = (np.maximum(hi - lo, 0.0) * (w[:, None] * w[None, :])).sum(axis=(2, 3))
    return kurtosis * ab / (2.0 * np.sqrt(np.outer(t, t)))


def _ramp_cross_sd(
    terms: Sequence[str], c: NDArray[np.float64], tau: NDArray[np.float64], ms: NDArray[np.int64], n: int, kind: str
) -> NDArray[np.float64]:
    """sd of the ramp x noise cross term of each AVAR point (0 when R is not fitted or is 0).

    A rate ramp R t is deterministic: each difference of tau-averages is d_r + e_k with
    d_r = R tau exactly, so A = d_r^2/2 + d_r mean(e) + mean(e^2)/2. The first part has no
    variance; the last is the noise's own chi-square part; the middle one has variance
    d_r^2 Var(mean e), uncorrelated with the chi-square part (odd Gaussian moment). The mean
    of the differences telescopes to (tau/L)(ybar_end - ybar_start), the difference of two
    window averages of the rate a lag L apart (L = (n + 1 - 2m)/fs overlapping, with
    triangular 2-tau windows; (floor(n/m) - 1) tau standard, tau boxes). Its variance for
    each noise term (continuous-time, L >> tau) is
    Q: 4 Q^2/(m tau^2) (overlapping) or 4 Q^2/tau^2; N: (4/3) N^2/tau or 2 N^2/tau;
    B: (2 B^2/pi)(ln(L/tau) + c); K: K^2 (L - 7 tau/15) or K^2 (L - tau/3) (random walk:
    integral of the squared difference of the two window cumulative weights); these
    constants are the statistic's ``FitConstants`` (:mod:`._kinds`). The cross term is nearly
    the same random variable (ybar_end - ybar_start, dominated by the slow terms) at every
    tau, so it is given correlation 1 across tau: a rank-one addition s s' to the point
    covariance.
    """
    if "R" not in terms:
        return np.zeros(tau.size)
    basis, scale = _ramp_basis(terms, tau, ms, n, kind)
    return _ramp_from_basis(basis, scale, c, terms.index("R"))


def _ramp_basis(
    terms: Sequence[str], tau: NDArray[np.float64], ms: NDArray[np.int64], n: int, kind: str
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The parts of :func:`_ramp_cross_sd` that do not depend on C: sd = sqrt(C_R) scale sqrt(basis @ C).

    basis[i, t]: the variance of the window-average difference per unit C_t (0 for R and
    for terms not fitted); scale = sqrt(2) tau (tau / L), from d_r = sqrt(2 C_R) tau.
    """
    fc = STATISTICS[kind].fit
    if fc is None:
        raise ValueError(f"kind must be a statistic the noise fit accepts; got {kind!r}")
    m = ms.astype(float)
    lag = np.maximum(fc.lag(n, m, tau), tau)
    per_term = {
        "Q": (4.0 / 3.0) / tau**2 / (m if fc.q_per_m else 1.0),
        "N": fc.n_factor / tau,
        "B": np.maximum(np.log(lag / tau) + fc.flicker_end_c, 0.0) / math.log(2.0),
        "K": 3.0 * (lag - fc.k_offset * tau),
    }
    basis = np.zeros((tau.size, len(terms)))
    for j, t in enumerate(terms):
        if t in per_term:
            basis[:, j] = per_term[t]
    return basis, math.sqrt(2.0) * tau * (tau / lag)


def _ramp_from_basis(
    basis: NDArray[np.float64], scale: NDArray[np.float64], c: NDArray[np.float64], r_index: int
) -> NDArray[np.float64]:
    """:func:`_ramp_cross_sd` from its :func:`_ramp_basis` (0 where C_R <= 0)."""
    if not c[r_index] > 0:
        return np.zeros(scale.size)
    return math.sqrt(c[r_index]) * scale * np.sqrt(np.maximum(basis @ c, 0.0))


class PointCovarianceModel:
    """V(C) of :func:`_point_covariance` with everything that does not depend on C computed once.

    V(C) = sum_{t,s} C_t C_s G_ts + s(C) s(C)', G_ts(i, j) = rho_ts(i, j) u_t(i) u_s(j) with u_t =
    tau^p_t sqrt(2 / nu_t) for the random terms (0 for the ramp) and s the ramp cross term of
    :func:`_ramp_cross_sd` (``ramp`` = its :func:`_ramp_basis` and the index of R, or None).
    The fit evaluates V some 30 times per record on the same points; each call is then one
    (k^2) x (n^2) product. A test checks it against :func:`_point_covariance`.
    """

    def __init__(
        self,
        x: NDArray[np.float64],
        nu: NDArray[np.float64],
        rho: dict[tuple[int, int], NDArray[np.float64]] | NDArray[np.float64],
        noise: NDArray[np.bool_],
        ramp: tuple[NDArray[np.float64], NDArray[np.float64], int] | None,
    ) -> None:
        n, k = x.shape
        u = x * np.sqrt(2.0 / nu) * noise[None, :]
        if isinstance(rho, np.ndarray):
            blocks = rho
        else:
            blocks = np.zeros((k, k, n, n))
            for (t, s), r in rho.items():
                blocks[t, s] = r
        self._gram = (blocks * u.T[:, None, :, None] * u.T[None, :, None, :]).reshape(k * k, n * n)
        self._n = n
        self._ramp = ramp

    def __call__(self, c: NDArray[np.float64]) -> NDArray[np.float64]:
        out = (np.outer(c, c).reshape(-1) @ self._gram).reshape(self._n, self._n)
        if self._ramp is not None:
            cross = _ramp_from_basis(*self._ramp[:2], c, self._ramp[2])
            out += np.outer(cross, cross)
        return out


def _point_covariance(
    x: NDArray[np.float64],
    c: NDArray[np.float64],
    nu: NDArray[np.float64],
    rho: dict[tuple[int, int], NDArray[np.float64]] | NDArray[np.float64],
    noise: NDArray[np.bool_] | None = None,
    cross: NDArray[np.float64] | None = None,
) -> NDArray[np.float64]:
    """Cov(A_i, A_j) = sum_{t,s} rho_ts(i, j) sd_t(i) sd_s(j) + cross_i cross_j.

    sd_t = C_t tau^p sqrt(2 / nu_t) (Greenhall nu) for the random terms (``noise`` True);
    deterministic terms (the ramp) have no chi-square part, only the rank-one ``cross``
    term of :func:`_ramp_cross_sd`. ``rho``: the blocks by (t, s), or :func:`_stack_rho` of
    them (the fit evaluates V ~30 times on the same blocks: stacked once, not on every call).
    """
    sd = x * c[None, :] * np.sqrt(2.0 / nu)
    if noise is not None:
        sd = sd * noise[None, :]
    k = sd.shape[1]
    blocks = rho if isinstance(rho, np.ndarray) else _stack_rho(rho, k)
    if blocks is not None:  # every pair of terms: one contraction over the stacked blocks
        out = np.einsum("tsij,it,js->ij", blocks, sd, sd)
    else:
        assert isinstance(rho, dict)
        out = np.zeros((x.shape[0], x.shape[0]))
        for (t, s), r in rho.items():
            out += r * np.outer(sd[:, t], sd[:, s])
    if cross is not None:
        out += np.outer(cross, cross)
    return out


def _stack_rho(rho: dict[tuple[int, int], NDArray[np.float64]], k: int) -> NDArray[np.float64] | None:
    """The blocks rho[(t, s)] of k terms as one (k, k, n, n) array; None unless every pair is there."""
    if len(rho) != k * k:
        return None
    first = rho[(0, 0)]
    return np.stack([rho[(t, s)] for t in range(k) for s in range(k)]).reshape(k, k, *first.shape)
