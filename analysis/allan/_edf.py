"""Equivalent degrees of freedom of the Allan and Hadamard variances (Greenhall-Riley, Stein).

References
----------
C. A. Greenhall and W. J. Riley, "Uncertainty of stability variances based on finite
differences", PTTI 2003 (NIST SP 1065 section 5.3.3); NIST SP 1065 Table 5 (Stein).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

#: Greenhall & Riley (2003) Table 2: (a0, a1) of 1/edf ~ (a0 - a1/r)/r for unmodified variances
#: at large r, by alpha (+2 .. -4) and d (1, 2, 3); None where alpha + 2d <= 1
_GH_TABLE2: dict[int, tuple[tuple[float, float] | None, ...]] = {
    2: ((3.0 / 2.0, 1.0 / 2.0), (35.0 / 18.0, 1.0), (231.0 / 100.0, 3.0 / 2.0)),
    1: ((78.6, 25.2), (790.0, 410.0), (9950.0, 6520.0)),
    0: ((2.0 / 3.0, 1.0 / 6.0), (2.0 / 3.0, 1.0 / 3.0), (7.0 / 9.0, 1.0 / 2.0)),
    -1: (None, (0.852, 0.375), (0.997, 0.617)),
    -2: (None, (1.079, 0.368), (1.033, 0.607)),
    -3: (None, None, (1.053, 0.553)),
    -4: (None, None, (1.302, 0.535)),
}
#: Greenhall & Riley (2003) Table 3: (b0, b1) of the alpha = +1 (flicker PM) case, by d
_GH_TABLE3 = ((6.0, 4.0), (15.23, 12.0), (47.8, 40.0))
_GH_JMAX = 100


def _gh_sw(t: NDArray[np.float64], alpha: int) -> NDArray[np.float64]:
    """Greenhall & Riley eq. (7): the generalised autocovariance kernel s_w(t) of S_x ~ f^(alpha - 2)."""
    a = np.abs(t)
    if alpha % 2 == 0:  # alpha = 2, 0, -2, -4: -|t|, |t|^3, |t|^5, |t|^7
        return -a if alpha == 2 else a ** (3 - alpha)
    # alpha = 1, -1, -3: t^(3 - alpha) ln|t|, 0 at t = 0
    return t ** (3 - alpha) * np.log(a, out=np.zeros_like(a), where=a > 0.0)


def _gh_lags(m: int, n_phase: int, d: int, overlapping: bool) -> tuple[float, float, float, float]:
    """Greenhall & Riley's (S, M, J, r = M/S) for averaging factor m over n_phase phase points.

    PTTI 2003, eq. (10)'s sum limits: S = m (overlapped) or 1, M = 1 + floor(S (N - (1 + m d)) / m),
    J = min(M, (d + 1) S).
    """
    s = float(m) if overlapping else 1.0
    big_m = 1.0 + math.floor(s * (n_phase - (1.0 + m * d)) / m)
    return s, big_m, min(big_m, (d + 1) * s), big_m / s


def _edf_greenhall(alpha: int, d: int, m: int, n_phase: int, overlapping: bool) -> float:
    """Equivalent degrees of freedom of an unmodified Allan (d = 2) or Hadamard (d = 3) variance.

    C. A. Greenhall and W. J. Riley, "Uncertainty of stability variances based on finite
    differences", PTTI 2003 (NIST SP 1065 section 5.3.3): the exact sum eq. (10) for J <= 100
    lags, the Table 2/3 large-r approximations beyond, cases 2-4 of the paper (F = m; the
    modified variance, case 1, is left to allantools). Same arithmetic as
    allantools.ci.edf_greenhall (a test pins the two to 1e-12) without importing allantools,
    whose import pulls in scipy.stats and scipy.interpolate (~1-3 s). Raises
    NotImplementedError for alpha = +2 with ceil(r) <= d, where the paper gives no formula.
    """
    if not alpha + 2 * d > 1:
        raise ValueError(f"alpha + 2 d must be > 1; got alpha = {alpha}, d = {d}")
    if alpha != 1:  # one case logic for one m and many (:func:`_edf_greenhall_many`)
        with np.errstate(divide="ignore", invalid="ignore"):  # a record too short for m: nan, as allantools
            v = float(_edf_greenhall_many(alpha, d, np.array([m], dtype=np.int64), n_phase, overlapping)[0])
        if math.isnan(v):
            r = _gh_lags(m, n_phase, d, overlapping)[3]
            if alpha == 2 and math.ceil(r) <= d:
                raise NotImplementedError(f"no Greenhall edf for alpha = 2 with r = {r} <= d = {d}")
            raise ZeroDivisionError(f"no Greenhall edf: {n_phase} phase points are too few for m = {m}")
        return v
    with np.errstate(divide="ignore", invalid="ignore"):
        v = _edf_flicker_pm(d, m, n_phase, overlapping)
    if not math.isfinite(v):
        raise ZeroDivisionError(f"no Greenhall edf: {n_phase} phase points are too few for m = {m}")
    return v


def _edf_flicker_pm(d: int, m: int, n_phase: int, overlapping: bool) -> float:
    """The alpha = +1 (flicker PM) case of :func:`_edf_greenhall`: Table 3's (b0, b1) normalisation."""
    s, big_m, j_top, r = _gh_lags(m, n_phase, d, overlapping)
    b0, b1 = _GH_TABLE3[d - 1]
    if j_top <= _GH_JMAX:
        return 1.0 / _gh_basic_sum(j_top, big_m, s, float(m), 1, d)
    if r > d + 1:
        a0, a1 = _GH_TABLE2[1][d - 1]  # type: ignore[misc]
        return 1.0 / ((1.0 / ((b0 + b1 * math.log(m)) ** 2 * r)) * (a0 - a1 / r))
    mp = _GH_JMAX / r
    z0 = float(_gh_sz_many(np.array([0.0]), np.array([mp]), 1, d, False)[0])
    return 1.0 / (_gh_basic_sum(_GH_JMAX, _GH_JMAX, mp, mp, 1, d) * z0**2 / (b0 + b1 * math.log(m)) ** 2)


def _gh_basic_sum(j_top: float, big_m: float, s: float, f: float, alpha: int, d: int) -> float:
    """Eq. (10) for one (J, M, S, F): :func:`_gh_basic_sums` of one request."""
    jt, bm, ss, ff = (np.array([float(v)]) for v in (j_top, big_m, s, f))
    return float(_gh_basic_sums(jt, bm, ss, ff, alpha, d)[0])


def _gh_basic_sums(
    j_top: NDArray[np.float64],
    big_m: NDArray[np.float64],
    s: NDArray[np.float64],
    f: NDArray[np.float64],
    alpha: int,
    d: int,
) -> NDArray[np.float64]:
    """Eq. (10), sz(0)^2 + (1 - J/M) sz(J/S)^2 + 2 sum_{j=1}^{J-1} (1 - j/M) sz(j/S)^2 over sz(0)^2 M,
    for several (J, M, S, F) at one (alpha, d), in one evaluation of the kernel.

    The kernel values sz(0), sz(J/S) and sz(j/S), j < J, of every request are evaluated in one
    array (grouped by whether F is infinite) and the sums over j are segment sums.
    """
    out = np.empty(j_top.size)
    for inf_group in (False, True):
        sel = np.flatnonzero(np.isinf(f) == inf_group)
        if not sel.size:
            continue
        jt = j_top[sel].astype(np.int64)
        counts = np.maximum(jt - 1, 0)  # j = 1 .. J - 1
        owner = np.repeat(np.arange(sel.size), counts)
        starts = np.concatenate(([0], np.cumsum(counts)[:-1]))
        j = (np.arange(owner.size) - starts[owner] + 1).astype(float)
        ss = s[sel]
        t = np.concatenate((np.zeros(sel.size), jt / ss, j / ss[owner]))
        ff = np.concatenate((f[sel], f[sel], f[sel][owner]))
        sz = _gh_sz_many(t, ff, alpha, d, inf_group)
        z0, zj, zmid = sz[: sel.size], sz[sel.size : 2 * sel.size], sz[2 * sel.size :]
        bm = big_m[sel]
        terms = 2.0 * (1.0 - j / bm[owner]) * zmid**2
        mid = np.bincount(owner, weights=terms, minlength=sel.size)
        out[sel] = (z0**2 + (1.0 - jt / bm) * zj**2 + mid) / (z0**2 * bm)
    return out


def _gh_sz_many(
    t: NDArray[np.float64], f: NDArray[np.float64], alpha: int, d: int, f_infinite: bool
) -> NDArray[np.float64]:
    """Eqs. (8)-(9): the kernel after the F-sample averaging (F = inf: s_w at alpha + 2) and the d-th
    difference, sum_k (-1)^k C(2d, d+k) s_x(t + k), with one F per t (all infinite when ``f_infinite``)."""
    tk = t[None, :] + np.arange(-d, d + 1, dtype=float)[:, None]  # row d + k: t + k
    if f_infinite:
        sx = _gh_sw(tk, alpha + 2)
    else:
        fr = f[None, :]
        w = _gh_sw(np.stack((tk, tk - 1.0 / fr, tk + 1.0 / fr)), alpha)
        sx = fr**2 * (2.0 * w[0] - w[1] - w[2])
    out = math.comb(2 * d, d) * sx[d]
    for k in range(1, d + 1):
        out = out + (-1) ** k * math.comb(2 * d, d + k) * (sx[d - k] + sx[d + k])
    return out


def _edf_greenhall_many(
    alpha: int, d: int, ms: NDArray[np.int64], n_phase: int, overlapping: bool
) -> NDArray[np.float64]:
    """:func:`_edf_greenhall` at every m of ``ms`` (one alpha), with the exact sums evaluated together.

    The case logic of :func:`_edf_greenhall` for alpha != +1 (which calls this with one m); nan
    where the paper gives no value (alpha = +2 with ceil(r) <= d, or alpha + 2 d <= 1), and
    alpha = +1 (flicker PM) is left to the scalar function (nan here too), so that the caller
    falls back. A test checks both against allantools.ci.edf_greenhall to 1e-12.
    """
    out = np.full(ms.size, np.nan)
    if not alpha + 2 * d > 1 or alpha == 1:
        return out
    req: list[tuple[int, float, float, float, float]] = []  # (index, J, M, S, F)
    for i, m_ in enumerate(ms):
        m = int(m_)
        s, big_m, j_top, r = _gh_lags(m, n_phase, d, overlapping)
        if alpha <= 0:
            if j_top <= _GH_JMAX:
                req.append((i, j_top, big_m, s, float(m) if m * (d + 1) <= _GH_JMAX else math.inf))
            elif r > d + 1:
                a0, a1 = _GH_TABLE2[alpha][d - 1]  # type: ignore[misc]
                out[i] = 1.0 / ((1.0 / r) * (a0 - a1 / r))
            else:
                req.append((i, _GH_JMAX, _GH_JMAX, _GH_JMAX / r, math.inf))
        elif math.ceil(r) > d:  # alpha = +2
            a0 = math.comb(4 * d, 2 * d) / math.comb(2 * d, d) ** 2
            out[i] = 1.0 / ((1.0 / big_m) * (a0 - (d / 2.0) / r))
    if req:
        idx, jt, bm, ss, ff = (np.array(v) for v in zip(*req, strict=True))
        out[idx.astype(np.int64)] = 1.0 / _gh_basic_sums(jt, bm, ss, ff, alpha, d)
    return out


def _edf_stein(n_phase: int, m: int, alpha: int) -> float:
    """Stein's approximate edf of the overlapping ADEV (NIST SP 1065 Table 5; N phase points)."""
    n, mm = float(n_phase), float(m)
    if alpha == 2:
        return (n + 1) * (n - 2 * mm) / (2 * (n - mm))
    if alpha == 1:
        prod = math.log((n - 1) / (2 * mm)) * math.log((2 * mm + 1) * (n - 1) / 4)
        return math.exp(math.sqrt(prod)) if prod >= 0 else float("nan")  # nan: no edf (caller falls back)
    if alpha == 0:
        return ((3 * (n - 1) / (2 * mm)) - (2 * (n - 2) / n)) * ((4 * mm**2) / ((4 * mm**2) + 5))
    if alpha == -1:
        return 2 * (n - 2) / (2.3 * n - 4.9) if m == 1 else 5 * n**2 / (4 * mm * (n + (3 * mm)))
    if alpha == -2:
        return (n - 2) / (mm * (n - 3) ** 2) * ((n - 1) ** 2 - 3 * mm * (n - 1) + 4 * mm**2)
    return n - 1
