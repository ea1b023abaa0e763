"""The fused octave passes of analysis.allan (the overlapping fast path) against references.

Two references: the one-octave-per-pass moving-sum recursion written out plainly below
(the implementation before the passes were fused: every S_m is the same floating-point
sum, only the order of adding the D_m^2 differs, so 1e-12 relative), and allantools.oadev
(1e-9 relative, the package-wide rule). The records cross many blocks, the thread split
and both ways of splitting the later passes across threads; the lengths are odd, prime,
or exact multiples of the block.
"""

from __future__ import annotations

import math

import allantools
import numpy as np
import pytest
from threadpoolctl import threadpool_info

from gyrobench.analysis import allan
from gyrobench.analysis.allan import _blas, _noise_id, _octave, _taus, allan_deviation
from gyrobench.sim.noise import NoiseModel

#: white + quantization + flicker + random-walk rate, each in charge of some octaves
MODEL = NoiseModel(
    quantization=2e-3, angle_random_walk=1e-2, bias_instability=2e-3, rate_random_walk=1e-4
)


def _record(rng: np.random.Generator, n: int, offset: float = 1e3) -> np.ndarray:
    """The four-term model at 100 Hz on a large offset (checks the mean removal)."""
    return offset + MODEL.generate(n, 100.0, rng=rng)


def _reference(y: np.ndarray, ms: np.ndarray) -> tuple[np.ndarray, dict[int, np.ndarray]]:
    """One octave per pass: S_1 = y - mean, D_m = S_m[k+m] - S_m[k], S_2m = S_m[k] + S_m[k+m].

    Returns the deviation at each m and the noise-identification block means S_m[j m] / m.
    """
    n = y.size
    s = y - y.mean()
    dev, blocks = {}, {}
    m = 1
    while m <= ms.max():
        nt = n + 1 - 2 * m
        nb = min(n // m, _noise_id._NOISE_ID_MAX)
        if nb >= _noise_id._NOISE_ID_MIN:
            blocks[m] = s[: nb * m : m] / m
        d = s[m : m + nt] - s[:nt]
        dev[m] = math.sqrt(float(np.dot(d, d)) / (2.0 * nt)) / m
        s = s[:nt] + s[m : m + nt]
        m *= 2
    return np.array([dev[int(m)] for m in ms]), {int(m): blocks[int(m)] for m in ms if m in blocks}


def _fast(y: np.ndarray, ms: np.ndarray) -> tuple[np.ndarray, np.ndarray, dict[int, np.ndarray]]:
    """The fast path's deviation, alpha and the block means it hands to _noise_id_blocks."""
    seen: list[np.ndarray] = []
    real = _octave._noise_id_blocks

    def spy(z, dmax, **kw):
        seen.append(np.array(z))
        return real(z, dmax, **kw)

    _octave._noise_id_blocks = spy
    try:
        dev, alpha = _octave._octave_overlapping(y, ms, identify=True)
    finally:
        _octave._noise_id_blocks = real
    n = y.size
    with_blocks = [int(m) for m in ms if min(n // m, _noise_id._NOISE_ID_MAX) >= _noise_id._NOISE_ID_MIN]
    assert len(seen) == len(with_blocks)
    return dev, alpha, dict(zip(with_blocks, seen, strict=True))


def _allantools(y: np.ndarray, ms: np.ndarray) -> np.ndarray:
    taus, d, _, _ = allantools.oadev(y, rate=1.0, data_type="freq", taus=ms.astype(float))
    np.testing.assert_array_equal(np.rint(taus).astype(np.int64), ms)
    return np.asarray(d)


CONFIGS = {
    # name: (n, threads, block, first, later, residue_min)
    "default, one thread": (1_000_003, 1, None, None, None, None),
    "default, two threads": (1_000_003, 2, None, None, None, None),
    "block multiple, two threads": (1 << 19, 2, None, None, None, None),
    "small blocks, 3 threads, residues": (300_007, 3, 4096, 5, 3, 1 << 10),
    "small blocks, 2 threads, odd": (262_145, 2, 1 << 13, 8, 2, 1 << 12),
    "one octave per later pass": (300_001, 2, 1 << 14, 3, 1, 1 << 11),
}


@pytest.mark.parametrize("name", list(CONFIGS))
def test_fused_passes_match_one_octave_recursion_and_allantools(rng, monkeypatch, name):
    n, threads, block, first, later, residue_min = CONFIGS[name]
    monkeypatch.setattr(_blas, "_THREADS", threads)
    monkeypatch.setattr(_blas, "_THREAD_MIN", 100 if threads > 1 else 1 << 40)
    for attr, value in (
        ("_FUSE_BLOCK", block),
        ("_FUSE_FIRST", first),
        ("_FUSE_LATER", later),
        ("_RESIDUE_MIN", residue_min),
    ):
        if value is not None:
            monkeypatch.setattr(_octave, attr, value)
    y = _record(rng, n)
    ms = _taus._resolve_m("octave", 1.0, n, "overlapping")
    assert ms[-1] >= 1 << 15  # the later passes run, several of them on big m
    dev, alpha, blocks = _fast(y, ms)
    ref, ref_blocks = _reference(y, ms)
    np.testing.assert_allclose(dev, ref, rtol=1e-12, atol=0)
    np.testing.assert_allclose(dev, _allantools(y, ms), rtol=1e-9, atol=0)
    # noise identification sees the same block means, bit for bit
    assert blocks.keys() == ref_blocks.keys()
    for m, z in ref_blocks.items():
        np.testing.assert_array_equal(blocks[m], z, err_msg=f"m = {m}")
    _, alpha_general = allan.identify_noise(y, 1.0)
    np.testing.assert_array_equal(alpha, alpha_general)
    assert len(set(alpha.tolist())) > 1  # the record shows more than one noise type


@pytest.mark.parametrize("n", [4, 5, 7, 9, 31, 64, 100, 1001, 4095, 4096, 4097, 8193])
def test_short_records_match_the_reference(rng, n):
    """Records shorter than a block, with and without a later pass (n = 4: m = 1 only)."""
    y = _record(rng, n)
    ms = _taus._resolve_m("octave", 1.0, n, "overlapping")
    dev, alpha, blocks = _fast(y, ms)
    ref, ref_blocks = _reference(y, ms)
    np.testing.assert_allclose(dev, ref, rtol=1e-12, atol=0)
    np.testing.assert_allclose(dev, _allantools(y, ms), rtol=1e-9, atol=0)
    for m, z in ref_blocks.items():
        np.testing.assert_array_equal(blocks[m], z)


def test_some_octaves_only(rng, monkeypatch):
    """A tau list of some powers of two: the passes still run through every octave below."""
    monkeypatch.setattr(_blas, "_THREAD_MIN", 100)
    monkeypatch.setattr(_octave, "_FUSE_BLOCK", 1 << 13)
    monkeypatch.setattr(_octave, "_FUSE_FIRST", 4)
    y = _record(rng, 200_003)
    m = np.array([2, 8, 16, 256, 2048, 4096, 32768], dtype=np.int64)
    c = allan_deviation(y, 4.0, taus=m / 4.0)
    np.testing.assert_array_equal(c.m, m)
    ref, _ = _reference(y, m)
    np.testing.assert_allclose(c.deviation, ref, rtol=1e-12, atol=0)
    np.testing.assert_allclose(c.deviation, _allantools(y, m), rtol=1e-9, atol=0)
    _, alpha = allan.identify_noise(y, 4.0, taus=m / 4.0)
    np.testing.assert_array_equal(c.alpha, alpha)


def test_drifting_record_keeps_its_precision(rng, monkeypatch):
    """Random-walk rate on an offset of 1e6: every S_m is the reference's, so 1e-12 still holds."""
    monkeypatch.setattr(_blas, "_THREAD_MIN", 100)
    n = 400_001
    y = 1e6 + np.cumsum(rng.standard_normal(n)) + 1e-3 * rng.standard_normal(n)
    ms = _taus._resolve_m("octave", 1.0, n, "overlapping")
    dev, _, _ = _fast(y, ms)
    ref, _ = _reference(y, ms)
    np.testing.assert_allclose(dev, ref, rtol=1e-12, atol=0)


#: lengths of a later pass's k range, from m and the thread count k
NT = {
    "odd": lambda m, k: 100_001,
    "power of two": lambda m, k: 1 << 17,
    "3 blocks + 7": lambda m, k: 3 * (1 << 15) + 7,
    "last run of the last thread is one k": lambda m, k: 9 * m + (m * (k - 1)) // k + 1,
}


@pytest.mark.parametrize("threads", [1, 2, 3])
@pytest.mark.parametrize("m", [1 << 10, 1 << 12, 1 << 15])
@pytest.mark.parametrize("shape", list(NT))
def test_later_jobs_cover_every_k_once(monkeypatch, threads, m, shape):
    """Jobs of a later pass: ranges (with tails) or residue classes, disjoint and complete."""
    monkeypatch.setattr(_blas, "_THREADS", threads)
    monkeypatch.setattr(_blas, "_THREAD_MIN", 100)
    monkeypatch.setattr(_octave, "_RESIDUE_MIN", 1 << 12)
    nt = NT[shape](m, threads)
    g = 2
    s = np.arange(nt + 4 * m, dtype=float)
    jobs = _octave._later_jobs(s, m, g, nt)
    hits = np.zeros(nt, dtype=np.int64)
    owner = np.zeros(m, dtype=np.int64)  # jobs touching each residue k mod m
    for runs, hi, tail in jobs:
        mine = np.zeros(m, dtype=bool)
        for a, b in runs:
            assert 0 <= a < b <= nt
            hits[a:b] += 1
            mine[np.arange(a, b) % m] = True
        owner += mine
        if tail is not None:  # the values after the range, as they were before the pass
            np.testing.assert_array_equal(tail, s[hi : hi + (2**g - 1) * m])
    np.testing.assert_array_equal(hits, 1)
    residue = threads > 1 and m >= _octave._RESIDUE_MIN
    assert all(tail is None for _, _, tail in jobs) == (residue or threads == 1)
    if residue:  # each thread reads and writes only its own residues: nothing shared
        np.testing.assert_array_equal(owner, 1)


def test_blas_thread_count_is_restored(rng, monkeypatch):
    """The fast path holds the BLAS to one thread while its own threads run, then restores it."""
    monkeypatch.setattr(_blas, "_THREAD_MIN", 100)
    before = [p["num_threads"] for p in threadpool_info()]
    allan_deviation(_record(rng, 50_000), 10.0)
    assert [p["num_threads"] for p in threadpool_info()] == before


def test_overlapping_blas_limits_restore_in_any_order():
    """Two callers on different threads leave in the opposite order: the BLAS stays at one
    thread while either is inside and is restored when the last one leaves (a plain
    ``with threadpool_limits`` per caller would restore too early, then to 1 for good)."""

    def blas() -> list[int]:
        return [p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"]

    before = blas()
    a, b = _blas._one_blas_thread(), _blas._one_blas_thread()
    a.__enter__()
    b.__enter__()
    assert set(blas()) <= {1}
    a.__exit__(None, None, None)  # the first in leaves first
    assert set(blas()) <= {1}
    b.__exit__(None, None, None)
    assert blas() == before
