"""The overlapping Allan variance core: blockwise per-tau passes and the fused octave recursion.

With the phase x_k = sum_{i<k} (y_i - ybar) and S_m[k] = x_{k+m} - x_k the moving sum of m
rates, the overlapping AVAR at m is sum_k D_m[k]^2 / (2 m^2 (n + 1 - 2m)) with D_m[k] =
S_m[k+m] - S_m[k] = x_{k+2m} - 2 x_{k+m} + x_k (NIST SP 1065 eq. 11); at octave m the moving
sums follow S_2m[k] = S_m[k] + S_m[k+m] (see :func:`_octave_overlapping`).
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Callable
from functools import partial

import numpy as np
from numpy.typing import NDArray

from gyrobench.analysis.allan import _blas
from gyrobench.analysis.allan._blas import _dot_self, _map, _one_blas_thread, _segments, _sumsq
from gyrobench.analysis.allan._noise_id import _NOISE_ID_MAX, _NOISE_ID_MIN, _noise_id_blocks

#: block size of the overlapping estimator (fits in L2 cache)
_BLOCK = 1 << 16
#: fused octave passes (see :func:`_octave_overlapping`): octaves of the first pass, octaves
#: per later pass, values of k per block, and the m from which later passes split k by
#: residue class mod m across threads instead of by range (no tail copies)
_FUSE_FIRST = 12
_FUSE_LATER = 2
_FUSE_BLOCK = 1 << 17
_RESIDUE_MIN = 1 << 18


def _fuse_block(n: int) -> int:
    """Values of k per block of the fused passes for n samples: about n/16, from 2^15 to _FUSE_BLOCK.

    The block buffers are fresh memory on every call, and on a virtual machine each page's first
    touch costs ~1-3 us: two 1 MB buffers (the 2^17 block) were ~500 page faults, more than the
    halo's recomputation saves on a short record (a 2e5-sample curve measured 4000 faults and
    ~16 ms CPU with 2^17-value blocks, ~930 faults and ~11 ms with 2^15, on a fresh process;
    1e6 samples ran best at 2^16). Long records keep 2^17 (halo overhead 3 %).
    """
    top = 1 << max(n - 1, 1).bit_length()  # the power of two >= n
    return min(_FUSE_BLOCK, max(1 << 15, top >> 4))


def _phase(y: NDArray[np.float64]) -> NDArray[np.float64]:
    """Integrated rate x_k = sum_{i<k} (y_i - mean y), x_0 = 0, in units of rate*sample (N + 1 points).

    Same sequence of roundings as allantools.frequency2phase (mean removed before the
    cumulative sum, which keeps precision on a large offset), without its 1/fs factor.
    """
    x = np.empty(y.size + 1)
    x[0] = 0.0
    np.subtract(y, y.mean(), out=x[1:])
    np.cumsum(x, out=x)
    return x



def _ssq_range(x: NDArray[np.float64], m: int, lo: int, hi: int) -> float:
    """Sum over k in [lo, hi) of (x[k+2m] - 2 x[k+m] + x[k])^2, blockwise (two block buffers)."""
    u = np.empty(min(_BLOCK, hi - lo))
    v = np.empty_like(u)
    s = 0.0
    for a in range(lo, hi, _BLOCK):
        b = min(hi, a + _BLOCK)
        w, z = u[: b - a], v[: b - a]
        np.subtract(x[a + 2 * m : b + 2 * m], x[a + m : b + m], out=w)
        np.subtract(x[a + m : b + m], x[a:b], out=z)
        np.subtract(w, z, out=w)
        s += _sumsq(w)
    return s


def _overlapping_ssq(x: NDArray[np.float64], m: int) -> tuple[float, int]:
    """Sum of squared second differences (x[k+2m] - 2 x[k+m] + x[k]) over all k.

    Blockwise, one pass over ``x`` (split across threads): no O(N) temporaries.
    """
    n = x.size - 2 * m
    return sum(_map(lambda r: _ssq_range(x, m, *r), _segments(n))), n


def _deviation_overlapping(x: NDArray[np.float64], ms: NDArray[np.int64]) -> NDArray[np.float64]:
    dev = np.empty(ms.size)
    for i, m in enumerate(ms):
        s, n = _overlapping_ssq(x, int(m))
        dev[i] = math.sqrt(s / (2.0 * n)) / m
    return dev


def _first_pass(
    y: NDArray[np.float64],
    mean: float,
    out: NDArray[np.float64] | None,
    levels: list[int],
    sums: list[bool],
    ids: dict[int, NDArray[np.float64]],
    lo: int,
    hi: int,
    ssq: Callable[[NDArray[np.float64]], float],
) -> list[float]:
    """The first octaves m = 1, 2, .., M/2 (``levels``) for k in [lo, hi), in one pass over ``y``.

    Block by block (:func:`_fuse_block` values of k plus a halo of M - 1 samples, in cache):
    S_1 = y - mean, then per level sum D_m[k]^2 (where ``sums``), the block means
    ``ids[m][j] = S_m[j m]`` that fall in the block, and S_2m[k] = S_m[k] + S_m[k+m] into
    the other buffer. Every S_m value is the same sum, in the same order, as the one-octave
    recursion. Writes S_M[k] to ``out`` (None when no octave follows). Reads only ``y``, so
    ranges of k can run on threads without sharing anything but disjoint slices of ``out``.
    """
    n = y.size
    big = 2 * levels[-1]  # M
    halo = big - 1  # S_M[k] and every D_m[k], m <= M/2, read y[k .. k + M - 1]
    blk = _fuse_block(n)
    cur = np.empty(min(blk, hi - lo) + halo)
    nxt = np.empty_like(cur)
    acc = [0.0] * len(levels)
    for a in range(lo, hi, blk):
        b = min(hi, a + blk)
        size = min(n, b + halo) - a  # u[i] = S_m[a + i] for i < size
        u, v = cur, nxt
        np.subtract(y[a : a + size], mean, out=u[:size])
        for i, m in enumerate(levels):
            z = ids.get(m)
            if z is not None:
                j0, j1 = -(-a // m), min(-(-b // m), z.size)
                if j1 > j0:
                    z[j0:j1] = u[j0 * m - a : (j1 - 1) * m - a + 1 : m]
            c = min(b, n + 1 - 2 * m) - a  # D_m terms with k in the block
            if sums[i] and c > 0:
                np.subtract(u[m : m + c], u[:c], out=v[:c])
                acc[i] += ssq(v[:c])
            size -= m
            if size <= 0 or (out is None and i == len(levels) - 1):  # no S_2m at k >= a, or not needed
                break
            np.add(u[:size], u[m : m + size], out=v[:size])
            u, v = v, u
        if out is not None:
            c = min(b, n + 1 - big) - a  # valid S_M
            if c > 0:
                out[a : a + c] = u[:c]
    return acc


def _later_pass(
    s_arr: NDArray[np.float64],
    m: int,
    g: int,
    sums: list[bool],
    write: bool,
    ssq: Callable[[NDArray[np.float64]], float],
    job: tuple[list[tuple[int, int]], int, NDArray[np.float64] | None],
) -> list[float]:
    """Octaves m, 2m, .., 2^(g-1) m in one in-place pass over S_m, for k in the runs of ``job``.

    With T_0[j] = S_m[k + j m] (j < 2^g, views of ``s_arr``), T_{l+1}[i] = T_l[2i] +
    T_l[2i+1] = S_{2^(l+1) m}[k + i 2^(l+1) m]: the same sums in the same order as g
    one-octave steps. D at level l is T_l[1] - T_l[0]; T_g[0] = S_{2^g m}[k] is written
    over S_m[k] when ``write``. Returns sum D^2 per level (0 where ``sums`` is False).

    ``job`` = (runs, hi, tail). Each run [a, b) of k is processed in ascending k, so every
    read of S_m[k + j m] precedes the write at that index. A range of k ending at ``hi``
    reads the values from ``hi`` on, which the next thread's range overwrites, from
    ``tail`` (s_arr[hi : hi + (2^g - 1) m] copied before the pass). With one block of
    residues mod m per thread (runs [q m + r0, q m + r1)) every read stays in the thread's
    own indices and ``tail`` is None.
    """
    runs, hi, tail = job
    n = s_arr.size
    acc = [0.0] * g
    blk = _fuse_block(n)
    width = min(blk, max(b - a for a, b in runs))
    d = np.empty(width)
    tree = [[np.empty(width) for _ in range(1 << (g - lv))] for lv in range(1, g)]

    def view(p: int, c: int) -> NDArray[np.float64]:  # S_m[p : p + c] as it was before the pass
        if tail is None or p + c <= hi:
            return s_arr[p : p + c]
        if p >= hi:
            return tail[p - hi : p - hi + c]
        return np.concatenate((s_arr[p:hi], tail[: p + c - hi]))

    for r0, r1 in runs:
        for a in range(r0, r1, blk):
            b = min(r1, a + blk)
            ends = [min(b, n + 1 - 2 * (m << lv)) - a for lv in range(g)]  # D terms per level
            # T_l[i] is needed for k < a + ends[l + bit_length(i) - 1] (i = 0 like i = 1)
            need = [
                [ends[min(lv + max(i.bit_length() - 1, 0), g - 1)] for i in range(1 << (g - lv))]
                for lv in range(g)
            ]
            t = [view(a + j * m, c) for j, c in enumerate(need[0]) if c > 0]
            for lv in range(g):
                c = ends[lv]
                if c <= 0:
                    break
                if sums[lv]:
                    np.subtract(t[1][:c], t[0][:c], out=d[:c])
                    acc[lv] += ssq(d[:c])
                if lv == g - 1:
                    if write:
                        np.add(t[0][:c], t[1][:c], out=s_arr[a : a + c])
                    break
                t = [
                    np.add(t[2 * i][:c2], t[2 * i + 1][:c2], out=tree[lv][i][:c2])
                    for i, c2 in enumerate(need[lv + 1])
                    if c2 > 0
                ]
    return acc


def _later_jobs(
    s_arr: NDArray[np.float64], m: int, g: int, nt: int
) -> list[tuple[list[tuple[int, int]], int, NDArray[np.float64] | None]]:
    """Thread jobs of one :func:`_later_pass` over k in [0, nt): ranges with tails, or residues."""
    segs = _segments(nt)
    k = len(segs)
    if k > 1 and m >= _RESIDUE_MIN:  # thread i: k mod m in [m i / k, m (i + 1) / k)
        edges = [(m * i) // k for i in range(k + 1)]
        return [
            ([(q + lo, min(q + hi, nt)) for q in range(0, nt - lo, m)], 0, None)
            for lo, hi in zip(edges[:-1], edges[1:], strict=True)
        ]
    span = ((1 << g) - 1) * m
    jobs = [([(lo, hi)], hi, s_arr[hi : hi + span].copy()) for lo, hi in segs[:-1]]
    return jobs + [([segs[-1]], 0, None)]


#: above this many bytes of work array (n float64 moving sums) the octaves from 2^_FUSE_FIRST on
#: are computed group by group of residues (see :func:`_later_streamed`) instead of in place
_WORK_BYTES = 256 << 20
#: residue groups of the streamed later octaves, and rows per chunk of their passes
#: (64 groups: a group's moving sums, n/64 floats, stay in the L3 cache through all of its
#: octaves on 1e8 samples; 16 groups ran 3x slower, memory-bound)
_GROUPS = 64
_STREAM_ROWS = 2048


def _rows_of(y: NDArray[np.float64], mean: float, b: int, r0: int, r1: int, c0: int, c1: int,
             buf: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
    """Columns c0 .. c1-1 of blocks r0 .. r1-1 (``b`` samples a block) of y - mean, zero past the end.

    Shape (r1 - r0, c1 - c0); written into ``buf[: r1 - r0]`` when given (a buffer reused from
    call to call instead of fresh memory for every chunk).
    """
    n = y.size
    a0 = r0 * b
    full = min(r1 - r0, max(0, (n - a0) // b))  # rows wholly inside the record
    out = np.empty((r1 - r0, c1 - c0)) if buf is None else buf[: r1 - r0]
    if full == r1 - r0:
        return np.subtract(y[a0 : r1 * b].reshape(r1 - r0, b)[:, c0:c1], mean, out=out)
    out[full:] = 0.0  # (only these columns: a full-width pad was 60 MB)
    if full:
        np.subtract(y[a0 : a0 + full * b].reshape(full, b)[:, c0:c1], mean, out=out[:full])
    start = a0 + full * b  # the partial row
    if start + c0 < n:
        seg = y[start + c0 : min(start + c1, n)]
        np.subtract(seg, mean, out=out[full, : seg.size])
    return out


def _residue_sums(y: NDArray[np.float64], b: int, i0: int, w: int, nj: int,
                  start: NDArray[np.float64], rows: int | None = None) -> NDArray[np.float64]:
    """Z[j, c] = S_B[j B + i0 + c] (B = ``b``) for j < ``nj``, c < ``w``: one residue group's moving sums.

    Moving the window by one sample adds y[(j + 1) B + i] and drops y[j B + i], so
    S_B[j B + i0 + c] = S_B[j B + i0] + sum_{c' < c} (y[(j + 1) B + i0 + c'] - y[j B + i0 + c']):
    column 0 is ``start[j]`` (built from the block sums of the column groups, see
    :func:`_later_streamed`) and the others are one difference of two rows of the record and a
    cumulative sum along the row, written straight into Z (the mean cancels in the
    differences). Chunks of ``rows`` blocks (default _STREAM_ROWS); every element is the same
    expression whatever the chunk, so the result does not depend on ``rows``. Entries with
    j B + i0 + c + B > n read the zero padding past the end and are not moving sums.
    """
    rows = _STREAM_ROWS if rows is None else rows
    z = np.empty((nj, w))
    cap = min(nj, rows)
    blk_buf = np.empty((cap + 1, w - 1))
    for r0 in range(0, nj, rows):
        r1 = min(nj, r0 + rows)
        if (r1 + 1) * b <= y.size:  # inside the record: the rows as a view of it, no copy
            blk = y[r0 * b : (r1 + 1) * b].reshape(r1 + 1 - r0, b)[:, i0 : i0 + w - 1]
        else:
            blk = _rows_of(y, 0.0, b, r0, r1 + 1, i0, i0 + w - 1, blk_buf)
        out = z[r0:r1]
        np.subtract(blk[1:], blk[:-1], out=out[:, 1:])
        out[:, 0] = start[r0:r1]
        for c in range(1, w):  # = np.cumsum(out, axis=1) bit for bit, but a column at a time (faster)
            np.add(out[:, c - 1], out[:, c], out=out[:, c])
    return z


def _later_streamed(
    y: NDArray[np.float64],
    mean: float,
    big: int,
    top: int,
    want: set[int],
    identify: bool,
    ssq: Callable[[NDArray[np.float64]], float],
) -> tuple[dict[int, float], dict[int, NDArray[np.float64] | None]]:
    """Octaves m = big, 2 big, .., top without an n-float work array: by residue groups mod ``big``.

    With B = big, write k = j B + i (0 <= i < B). For every m that is a multiple of B,
    S_m[j B + i] = sum_{l < m/B} S_B[(j + l) B + i] and D_m[j B + i] = S_m[(j + q) B + i] -
    S_m[j B + i] (q = m/B): for a fixed residue i the recursion S_2m = S_m + S_m(+m) runs on
    the decimated sequence Z_i[j] = S_B[j B + i] alone. The residues are split into
    _GROUPS groups of B/_GROUPS columns; a group's Z (n/_GROUPS floats) is built from the
    data and carried through every later octave, then dropped, so the work memory is
    n/_GROUPS floats per thread instead of n (and in cache while it is worked on).
    S_B[j B + i] is built from its value at the group's first column (block sums of the column
    groups) plus the cumulative sum of the samples that enter and leave the window (see
    :func:`_residue_sums`), so it differs from the tree sum of the in-place path by rounding
    only (relative ~w eps of the moving sums' scale);
    every later S_m is the same tree as in :func:`_later_pass`. Invalid entries (k + m > n) are
    NaN and never summed.
    Returns sum D_m^2 per wanted m and, for the noise identification, the block means'
    sums S_m[j m] (j < min(n/m, _NOISE_ID_MAX)) of each wanted m (None below _NOISE_ID_MIN).
    """
    n = y.size
    b = big
    w = b // _GROUPS
    nb_all = -(-n // b) + 1  # blocks, plus one of padding
    octs = []
    mm = b
    while mm <= top:
        octs.append(mm)
        mm <<= 1

    # block sums of each column group: gs[j, g] = sum of y - mean over block j, columns of group g
    gs = np.zeros((nb_all, _GROUPS))
    rows_buf = np.empty((min(nb_all, 512), b))
    for r0 in range(0, nb_all, 512):
        r1 = min(nb_all, r0 + 512)
        _rows_of(y, mean, b, r0, r1, 0, b, rows_buf).reshape(r1 - r0, _GROUPS, w).sum(axis=2, out=gs[r0:r1])
    del rows_buf
    # start[j, g] = S_B at block j, first column of group g: groups >= g of block j + groups < g of j + 1
    start = np.cumsum(gs[:-1, ::-1], axis=1)[:, ::-1]
    start[:, 1:] += np.cumsum(gs[1:, :-1], axis=1)

    def one_group(g: int) -> tuple[dict[int, float], dict[int, NDArray[np.float64] | None]]:
        i0 = g * w
        nj = (n - b - i0) // b + 1  # rows with a valid first column: j B + i0 + B <= n
        z = _residue_sums(y, b, i0, w, nj, start[:, g])
        k_last = (nj - 1) * b + i0 + np.arange(w)  # the last row's k: valid while k + B <= n
        z[nj - 1, k_last + b > n] = np.nan
        acc: dict[int, float] = {}
        ids: dict[int, NDArray[np.float64] | None] = {}
        buf = np.empty((_STREAM_ROWS, w))
        rows = nj
        for mm in octs:
            q = mm // b
            if identify and g == 0 and mm in want:
                nbk = min(n // mm, _NOISE_ID_MAX)
                ids[mm] = z[: nbk * q : q, 0].copy() if nbk >= _NOISE_ID_MIN else None
            full = rows - q - 1  # D rows j with row j + q fully valid
            s_ = 0.0
            nxt = (mm << 1) <= top
            for r0 in range(0, max(full, 0), _STREAM_ROWS):
                r1 = min(full, r0 + _STREAM_ROWS)
                if mm in want:
                    d = np.subtract(z[r0 + q : r1 + q], z[r0:r1], out=buf[: r1 - r0])
                    s_ += ssq(d.ravel())
                if nxt:
                    z[r0:r1] += z[r0 + q : r1 + q]
            if rows - q - 1 >= 0:  # the last D row: row j + q is the partly valid last row
                j = rows - q - 1
                d = z[j + q] - z[j]
                ok = np.isfinite(d)
                if mm in want:
                    s_ += float(np.dot(d[ok], d[ok]))
                if nxt:
                    z[j] += z[j + q]
            if mm in want:
                acc[mm] = s_
            rows = rows - q  # rows past this are not S_2m
        return acc, ids

    accs: dict[int, float] = {mm: 0.0 for mm in octs if mm in want}
    ids_late: dict[int, NDArray[np.float64] | None] = {}
    gs_all = list(range(_GROUPS))
    jobs = [gs_all[t::_blas._THREADS] for t in range(min(_blas._THREADS, _GROUPS))]
    for part in _map(lambda grp: [one_group(g) for g in grp], jobs):
        for acc, ids in part:
            for k_, v in acc.items():
                accs[k_] += v
            ids_late.update(ids)
    return accs, ids_late


def _octave_overlapping(
    y: NDArray[np.float64], ms: NDArray[np.int64], identify: bool
) -> tuple[NDArray[np.float64], NDArray[np.int64] | None]:
    """Overlapping ADEV at power-of-two m by the moving-sum recursion (fast path).

    S_1[k] = y_k - mean(y); D_m[k] = S_m[k+m] - S_m[k] (= x_{k+2m} - 2 x_{k+m} + x_k);
    S_2m[k] = S_m[k] + S_m[k+m]. The octaves are computed in fused passes: the first
    _FUSE_FIRST in one pass over ``y``, block by block in cache (:func:`_first_pass`), which
    writes S_M (M = 2^_FUSE_FIRST) into the one n-float work array; then _FUSE_LATER octaves
    per in-place pass over that array (:func:`_later_pass`). Every S_m is the same
    floating-point sum as in the one-octave-per-pass recursion (so the noise identification
    block means S_m[j m] / m are bit for bit the same); only the order in which the D_m^2
    are added differs (~1e-16 relative).
    Threads split k by range (first pass, small m) or by residue mod m (m >= _RESIDUE_MIN);
    meanwhile the BLAS is held to one thread (threadpoolctl, a scikit-learn dependency: it
    is process-wide, so :func:`_one_blas_thread` counts concurrent callers), so the
    per-block dot products run in parallel on these threads.
    """
    n = y.size
    want = {int(m) for m in ms}
    top = int(ms.max())
    mean = y.mean()
    segs = _segments(n)
    threaded = len(segs) > 1
    ssq = _dot_self if threaded else _sumsq
    dev: dict[int, float] = {}
    alpha: dict[int, int | None] = {}

    def nb_of(m: int) -> int:
        return min(n // m, _NOISE_ID_MAX)

    def finish(levels: list[int], accs: list[list[float]]) -> None:
        for i, m in enumerate(levels):
            if m in want:
                dev[m] = math.sqrt(sum(a[i] for a in accs) / (2.0 * (n + 1 - 2 * m))) / m

    with _one_blas_thread() if threaded else contextlib.nullcontext():
        levels = [1 << i for i in range(_FUSE_FIRST) if (1 << i) <= top]
        m = 2 * levels[-1]  # the first octave after the first pass
        streamed = m <= top and n * 8 > _WORK_BYTES
        s_arr = np.empty(n) if (m <= top and not streamed) else None
        ids = {
            k: np.empty(nb_of(k))
            for k in levels
            if identify and k in want and nb_of(k) >= _NOISE_ID_MIN
        }
        fn = partial(_first_pass, y, mean, s_arr, levels, [k in want for k in levels], ids, ssq=ssq)
        finish(levels, _map(lambda r: fn(*r), segs))
        for k in levels:
            if identify and k in want:
                if k in ids:
                    ids[k] /= k  # the block means (in place: ids is ours, and n-sized temporaries fault)
                    alpha[k] = _noise_id_blocks(ids[k], 2, overwrite=True)
                else:
                    alpha[k] = None

        if streamed:
            accs, ids_late = _later_streamed(y, mean, m, top, want, identify, ssq)
            later = sorted(accs)
            finish(later, [[accs[k] for k in later]])
            for k, z in ids_late.items():
                alpha[k] = _noise_id_blocks(z / k, 2, overwrite=True) if z is not None else None
            m = 2 * top  # done
        while m <= top:
            assert s_arr is not None  # allocated by the first pass whenever m <= top
            g = 1
            while g < _FUSE_LATER and (m << g) <= top:
                g += 1
            levels = [m << lv for lv in range(g)]
            for lv, mm in enumerate(levels):
                if identify and mm in want:
                    nb = nb_of(mm)
                    if nb < _NOISE_ID_MIN:
                        alpha[mm] = None
                        continue
                    z = s_arr[: nb * mm : m].reshape(nb, 1 << lv)  # S_m[j mm + i m]
                    while z.shape[1] > 1:  # the pass's sum tree: S_mm[j mm], bit for bit
                        z = z[:, 0::2] + z[:, 1::2]
                    alpha[mm] = _noise_id_blocks(z[:, 0] / mm, 2, overwrite=True)
            sums = [mm in want for mm in levels]
            fn = partial(_later_pass, s_arr, m, g, sums, (m << g) <= top, ssq)
            finish(levels, _map(fn, _later_jobs(s_arr, m, g, n + 1 - 2 * m)))
            m <<= g
    del s_arr
    devs = np.array([dev[int(m)] for m in ms])
    if not identify:
        return devs, None
    out = np.zeros(ms.size, dtype=np.int64)
    last = 0
    for i, m in enumerate(ms):
        a_ = alpha[int(m)]
        if a_ is not None:
            last = int(np.clip(a_, -2, 2))
        out[i] = last
    return devs, out

