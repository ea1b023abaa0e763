"""The gap-aware overlapping Allan deviation (``allan_deviation_gaps``): pieces pooled per tau."""

import numpy as np
import pytest

from gyrobench.analysis.allan import allan_deviation, allan_deviation_gaps

FS = 50.0


def test_one_piece_is_the_overlapping_deviation(rng):
    """Closed form: with no gap the pooled sums are eq. 11 itself (the octave recursion computes it another way)."""
    y = rng.standard_normal(20_000) + 3.0
    c = allan_deviation(y, FS)
    g = allan_deviation_gaps([y], FS)
    np.testing.assert_array_equal(g.tau, c.tau)
    np.testing.assert_allclose(g.deviation, c.deviation, rtol=1e-12)
    np.testing.assert_allclose(g.edf, c.edf, rtol=1e-12)
    np.testing.assert_array_equal(g.n_terms, c.n_terms)
    np.testing.assert_array_equal(g.alpha, c.alpha)


def test_two_pieces_pool_their_sums_weighted_by_their_term_counts(rng):
    """Each piece's AVAR from allan_deviation (given taus), weighted by its n + 1 - 2m terms, is the pooled AVAR."""
    y1, y2 = rng.standard_normal(6_000), rng.standard_normal(9_001)
    g = allan_deviation_gaps([y1, y2], FS)
    num = np.zeros(g.tau.size)
    for y in (y1, y2):
        ok = g.tau * FS <= (y.size - 1) // 2
        c = allan_deviation(y, FS, taus=g.tau[ok])
        num[ok] += c.deviation**2 * c.n_terms
    np.testing.assert_allclose(g.deviation**2, num / g.n_terms, rtol=1e-12)
    assert g.n_samples == 15_001


def test_a_step_across_a_gap_does_not_reach_the_curve(rng):
    """No second difference spans a gap: an offset between the pieces changes nothing (joined, it dominates)."""
    y = rng.standard_normal(40_000)
    a, b = y[:17_000], y[17_001:]
    g = allan_deviation_gaps([a, b], FS)
    g_step = allan_deviation_gaps([a, b + 1e3], FS)
    np.testing.assert_allclose(g_step.deviation, g.deviation, rtol=1e-9)
    joined = allan_deviation(np.concatenate([a, b + 1e3]), FS)
    assert np.all(joined.deviation[-4:] > 100 * g.deviation[-4:])


def test_one_dropped_sample_matches_the_unbroken_record_within_its_statistics(rng):
    """Every point of the split record lies inside the unbroken curve's interval at false-alarm 1e-6."""
    n = 200_000
    y = rng.standard_normal(n) + np.cumsum(rng.standard_normal(n)) * 2e-3  # white and random-walk rate
    full = allan_deviation(y, FS, confidence=1 - 1e-6)
    g = allan_deviation_gaps([y[:123_456], y[123_457:]], FS)
    np.testing.assert_array_equal(g.tau, full.tau)
    assert np.all((full.low <= g.deviation) & (g.deviation <= full.high))


@pytest.mark.parametrize(
    ("pieces", "match"),
    [([], "at least one contiguous run"), ([np.ones(1)] * 8, "no tau with 2 terms"),
     ([np.ones(100), np.array([1.0, np.nan])], "must be finite")],
)
def test_bad_pieces_are_refused_in_one_line(pieces, match):
    with pytest.raises(ValueError, match=match):
        allan_deviation_gaps(pieces, FS)
