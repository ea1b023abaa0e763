"""The import-free replacements on the CLI path agree with what they replace.

gyrobench's own Greenhall edf (instead of allantools.ci, whose import pulls in scipy.stats),
the chi-square quantiles of analysis/allan/_chi2.py (instead of scipy.stats and scipy.special), the enumerated NNLS
(instead of scipy.optimize.nnls) and the C parse of plain CSV rows (instead of numpy.loadtxt).
"""

from __future__ import annotations

import subprocess
import sys
import warnings

import numpy as np
import pytest
from allantools import ci as atci
from scipy import optimize, stats

from gyrobench.analysis import allan
from gyrobench.analysis.allan import _covariance, _curve, _edf, _kinds, _nnls, _octave
from gyrobench.io import logs

N_PHASE = [50, 101, 1000, 4097, 100_001, 1_000_001, 100_000_001]


def _ms(n: int) -> list[int]:
    return sorted({1, 2, 3, 5, 8, 16, 25, 33, 64, 100, 128, 1000, 4096, n // 5, n // 4, n // 3, (n - 1) // 2} - {0})


@pytest.mark.parametrize(("d", "overlapping"), [(2, True), (2, False), (3, True), (3, False)])
def test_edf_greenhall_matches_allantools(d, overlapping):
    """Cases 2-4 of Greenhall & Riley over N, m and alpha, including the J > 100 and r <= d + 1 branches."""
    checked = 0
    for alpha in range(-4 if d == 3 else -2, 3):
        for n in N_PHASE:
            for m in _ms(n):
                try:
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore")
                        want = atci.edf_greenhall(alpha=alpha, d=d, m=m, N=n, overlapping=overlapping)
                except (NotImplementedError, AssertionError, ZeroDivisionError) as exc:
                    want = exc
                if isinstance(want, AssertionError) and alpha == -4:
                    # allantools' Table 2 lookup refuses alpha = -4 although the table has the row
                    assert _edf._edf_greenhall(alpha, d, m, n, overlapping) > 0
                    continue
                if isinstance(want, Exception):
                    with pytest.raises(type(want)):
                        _edf._edf_greenhall(alpha, d, m, n, overlapping)
                    continue
                got = _edf._edf_greenhall(alpha, d, m, n, overlapping)
                if np.isfinite(want):
                    assert got == pytest.approx(want, rel=1e-12), (alpha, n, m)
                    checked += 1
    assert checked > 200


@pytest.mark.parametrize(("d", "overlapping"), [(2, True), (2, False), (3, True), (3, False)])
def test_edf_greenhall_many_matches_allantools(d, overlapping):
    """The batched edf (all m of one alpha at once, which the scalar form calls with one m) against
    allantools; nan exactly where allantools has no value, and for alpha = +1 (left to the scalar form).
    allantools evaluates the same kernel terms in another order: 1e-12 relative."""
    checked = 0
    for alpha in range(-4 if d == 3 else -2, 3):
        for n in N_PHASE:
            ms = np.array(_ms(n), dtype=np.int64)
            with np.errstate(all="ignore"):
                got = _edf._edf_greenhall_many(alpha, d, ms, n, overlapping)
            for m, g in zip(ms, got, strict=True):
                if alpha == 1:
                    assert np.isnan(g)
                    continue
                try:
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore")
                        want = atci.edf_greenhall(alpha=alpha, d=d, m=int(m), N=n, overlapping=overlapping)
                except (NotImplementedError, AssertionError, ZeroDivisionError) as exc:
                    want = exc
                if isinstance(want, AssertionError) and alpha == -4:  # allantools' Table 2 lookup refuses -4
                    assert g > 0
                    continue
                if isinstance(want, Exception) or not np.isfinite(want):
                    assert not (np.isfinite(g) and g > 0), (alpha, n, int(m), g, want)
                    continue
                assert g == pytest.approx(want, rel=1e-12), (alpha, n, int(m))
                checked += 1
    assert checked > 300


@pytest.mark.parametrize("alpha", [2, 1, 0, -1, -2])
def test_edf_stein_matches_allantools(alpha):
    for n in (10, 1001, 100_001):
        for m in (1, 2, 7, n // 4):
            with np.errstate(invalid="ignore"):
                want = atci.edf_simple(n, m, alpha)
            assert _edf._edf_stein(n, m, alpha) == pytest.approx(want, rel=1e-14, nan_ok=True)


def test_bounds_match_scipy_stats(rng):
    dev = rng.uniform(0.5, 2.0, 50)
    edf = np.concatenate([rng.uniform(0.3, 10.0, 25), rng.uniform(10.0, 1e6, 25)])
    for conf in (0.683, 0.95):
        lo, hi = _curve.deviation_bounds(dev, edf, conf)
        p = (1.0 - conf) / 2.0
        # 1e-12: the quantiles' stated accuracy (both are iterative solutions, not the same arithmetic)
        np.testing.assert_allclose(lo, dev * np.sqrt(edf / stats.chi2.isf(p, edf)), rtol=1e-12)
        np.testing.assert_allclose(hi, dev * np.sqrt(edf / stats.chi2.ppf(p, edf)), rtol=1e-12)


def _nnls_problem(g: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """A random NNLS problem: 6-39 rows, 1-5 unit-norm columns of scales spread over e^+-3."""
    rows, k = int(g.integers(6, 40)), int(g.integers(1, 6))
    a = g.standard_normal((rows, k)) * np.exp(g.uniform(-3, 3, k))
    a /= np.linalg.norm(a, axis=0)
    return a, g.standard_normal(rows)


@pytest.mark.parametrize("seed", range(40))
def test_enumerated_nnls_matches_scipy(seed):
    g = np.random.default_rng(seed)
    a, b = _nnls_problem(g)
    got = _nnls._nnls_enumerate(a, b)
    want, _ = optimize.nnls(a, b)
    assert np.all(got >= 0)
    assert np.array_equal(got == 0, want == 0)
    np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("seed", range(40))
def test_nnls_passive_guess_gives_the_same_minimiser(seed):
    """A guessed positive set (right, wrong, empty or full) never changes the NNLS answer, only its cost."""
    g = np.random.default_rng(seed)
    a, b = _nnls_problem(g)
    cold = _nnls._nnls_enumerate(a, b)
    k = a.shape[1]
    for guess in (cold > 0, g.random(k) < 0.5, np.zeros(k, dtype=bool), np.ones(k, dtype=bool)):
        got = _nnls._nnls_enumerate(a, b, guess)
        assert np.array_equal(got == 0, cold == 0)
        np.testing.assert_allclose(got, cold, rtol=1e-12, atol=1e-15)


def test_plain_rows_parse_like_loadtxt(rng):
    x = rng.standard_normal((500, 3)) * np.array([1e-9, 1.0, 1e6])
    body = "\n".join(",".join(f"{v:.17g}" for v in row) for row in x)
    got = logs._parse_plain(body, ",", 500, 3)
    assert got is not None and np.array_equal(got, x)
    semi = body.replace(",", ";")
    assert np.array_equal(logs._parse_plain(semi, ";", 500, 3), x)


@pytest.mark.parametrize(
    "body",
    [
        "1,2\n3,", "1,2\n3,x", "1,,2\n3,4", "1,2\n\n3,4", "1 2,3\n4,5", "1,2\n3,4e",
        # a cell split by whitespace and an empty cell elsewhere: the token count would add up
        "1 2,3\n,5", "1\t2,3\n4,", ",1\n2 3", "1,2\n3,4 5\n,6",
    ],
)
def test_plain_rows_refuse_what_loadtxt_would_refuse(body):
    n_rows = body.count("\n") + 1
    assert logs._parse_plain(body, ",", n_rows, 2) is None


@pytest.mark.parametrize(
    "ms", [2 ** np.arange(27), np.array([1, 3, 5, 100, 1000, 1025, 1536, 3000, 5000, 99_999, 2**20 + 1])]
)
def test_scaled_pairs_is_scaled_of_every_pair(ms):
    want = np.array([[_covariance._scaled(int(a), int(b)) for b in ms] for a in ms])
    assert np.array_equal(_covariance._scaled_pairs(ms), want)


@pytest.mark.parametrize("n", [20_000, 4096 * 300, 1_060_001])
def test_streamed_later_octaves_match_in_place(monkeypatch, n):
    """The residue-group path of long records (no n-float work array) against the in-place one.

    Forced on here by a zero work-array budget; a drifting record with an offset, of a length
    that is not a multiple of the 4096-sample block, so the partly valid last rows are exercised.
    """
    g = np.random.default_rng(n)
    y = g.standard_normal(n) + 1e-2 * np.cumsum(g.standard_normal(n)) + 1e-6 * np.arange(n) + 5.0
    ref = allan.allan_deviation(y, 100.0)
    assert ref.m.max() >= 4096  # octaves past the first pass exist
    calls = []
    real = _octave._later_streamed
    monkeypatch.setattr(_octave, "_later_streamed", lambda *a: calls.append(1) or real(*a))
    monkeypatch.setattr(_octave, "_WORK_BYTES", 0)
    got = allan.allan_deviation(y, 100.0)
    assert calls
    np.testing.assert_allclose(got.deviation, ref.deviation, rtol=1e-12, atol=0)
    assert np.array_equal(got.alpha, ref.alpha)
    np.testing.assert_array_equal(got.edf, ref.edf)


@pytest.mark.parametrize("rows", [1, 7, 64, 2048])
def test_residue_sums_do_not_depend_on_their_chunks(rows):
    """The streamed path's moving sums reuse their buffers chunk after chunk: any chunk of rows gives
    the same bits as the whole group at once in fresh arrays (a partly filled last block and the
    zero padding past the end included), and they are the moving sums S_B to rounding."""
    n, b, w, i0 = 4096 * 37 + 1234, 4096, 64, 128
    g = np.random.default_rng(rows)
    y = g.standard_normal(n) + 3.0
    mean = float(y.mean())
    nj = (n - b - i0) // b + 1
    nb = -(-n // b) + 1
    blocks = _octave._rows_of(y, mean, b, 0, nb, 0, b)  # (nb, b), zero past the end
    gs = blocks.reshape(nb, b // w, w).sum(axis=2)
    grp = i0 // w
    start = gs[:-1, grp:].sum(axis=1) + gs[1:, :grp].sum(axis=1)  # S_B at column i0 of each block
    whole = _octave._residue_sums(y, b, i0, w, nj, start, rows=nj)
    chunked = _octave._residue_sums(y, b, i0, w, nj, start, rows=rows)
    assert np.array_equal(chunked, whole)
    k = np.arange(nj)[:, None] * b + i0 + np.arange(w)[None, :]
    x = np.concatenate(([0.0], np.cumsum(y - mean)))
    valid = k + b <= n
    direct = x[np.minimum(k + b, n)] - x[k]
    # worst-case rounding of the reference: a cumulative sum of n terms errs by up to n eps max|x|
    # at each of its two ends (the block sums of b terms err far less)
    bound = 2.0 * n * np.finfo(float).eps * float(np.max(np.abs(x)) + np.max(np.abs(y - mean)))
    np.testing.assert_allclose(whole[valid], direct[valid], rtol=0, atol=bound)


@pytest.mark.parametrize("seed", range(5))
def test_distinct_is_numpy_unique(seed):
    g = np.random.default_rng(seed)
    a = g.integers(-3, 3000, size=(g.integers(0, 40), 3))
    assert np.array_equal(_kinds._distinct(a), np.unique(a))


def test_a_first_curve_and_fit_do_not_import_numpy_ma():
    """numpy 2's plain unique() imports numpy.ma (~10 ms) on a process's first call."""
    code = (
        "import sys, numpy as np\n"
        "from gyrobench.analysis.allan import allan_deviation, fit_noise\n"
        "y = np.random.default_rng(1).standard_normal(20000)\n"
        "fit_noise(allan_deviation(y, 100.0))\n"
        "print('numpy.ma' in sys.modules)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
