"""Tests of analysis.compensation.rbf_selection: newrb spread and size by leave-one-segment-out CV."""

from __future__ import annotations

import numpy as np
import pytest

from gyrobench.analysis.compensation.rbf import RBFNetwork
from gyrobench.analysis.compensation.rbf_selection import prefix_predictions, select_rbf


def _segmented_data(rng):
    """Three contiguous segments of a smooth 2-D surface plus small noise."""
    x = np.linspace(-1.0, 1.0, 150)
    X = np.column_stack([x, np.sin(3 * x)])
    y = 0.5 * x**2 + 0.2 * X[:, 1] + 0.01 * rng.standard_normal(len(x))
    return X, y, np.repeat([0, 1, 2], 50)


def test_select_rbf_follows_the_stated_rule(rng):
    """Fewest neurons among cells within 10 % of the best CV MSE; ties to the largest spread;
    the CV MSE of a cell is the mean of its held-out segment MSEs, recomputed here by hand
    with a separate newrb fit of exactly that neuron count (the selection reads it off one
    longer fit). The two solve the same least-squares problem by different factorizations,
    so they agree to rounding times the design's condition number: rel 1e-9."""
    X, y, seg = _segmented_data(rng)
    spreads, neurons = (0.5, 2.0, 8.0), (2, 4, 8)
    sel = select_rbf(X, y, seg, spreads=spreads, neurons=neurons, tolerance=0.10)
    assert set(sel.cv_mse) == {(s, n) for s in spreads for n in neurons}
    for s, n in ((2.0, 4), (0.5, 8), (8.0, 2)):
        by_hand = np.mean(
            [
                np.mean(
                    (
                        RBFNetwork(spread=s, max_neurons=n, normalize="minmax")
                        .fit(X[seg != f], y[seg != f])
                        .predict(X[seg == f])
                        - y[seg == f]
                    )
                    ** 2
                )
                for f in (0, 1, 2)
            ]
        )
        assert sel.cv_mse[(s, n)] == pytest.approx(by_hand, rel=1e-9)
    best = min(sel.cv_mse.values())
    assert sel.cv_mse[sel.best] == best
    band = [k for k, v in sel.cv_mse.items() if v <= 1.1 * best]
    assert sel.chosen in band
    assert sel.max_neurons == min(k[1] for k in band)
    assert sel.spread == max(k[0] for k in band if k[1] == sel.max_neurons)


def test_select_rbf_zero_tolerance_is_the_cv_minimum(rng):
    X, y, seg = _segmented_data(rng)
    sel = select_rbf(X, y, seg, spreads=(0.5, 4.0), neurons=(3, 6), tolerance=0.0)
    assert sel.chosen == sel.best


def test_select_rbf_needs_two_segments(rng):
    X, y, _ = _segmented_data(rng)
    with pytest.raises(
        ValueError, match=r"segments must hold at least 2 distinct labels .*got labels \[0\]"
    ):
        select_rbf(X, y, np.zeros(len(y), dtype=int), spreads=(1.0,), neurons=(3,))


def test_prefix_predictions_equal_a_fit_of_that_size(rng):
    """The k-neuron network read off a longer newrb fit predicts as a fresh k-neuron fit (newrb
    picks neurons greedily, independent of max_neurons); same least-squares problem, different
    factorizations: rel 1e-9."""
    X, y, _ = _segmented_data(rng)
    long = RBFNetwork(spread=2.0, max_neurons=8, normalize="minmax").fit(X, y)
    pred = prefix_predictions(long, X, y, X[::7], (3, 8))
    for k in (3, 8):
        fresh = RBFNetwork(spread=2.0, max_neurons=k, normalize="minmax").fit(X, y).predict(X[::7])
        np.testing.assert_allclose(pred[k], fresh, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"spreads": ()}, r"spreads and neurons must be non-empty"),
        ({"neurons": ()}, r"spreads and neurons must be non-empty"),
        ({"tolerance": -0.1}, r"tolerance must be >= 0 \(relative\); got -0.1"),
    ],
)
def test_select_rbf_bad_grid(rng, kwargs, match):
    X, y, seg = _segmented_data(rng)
    args = {"spreads": (1.0,), "neurons": (3,), **kwargs}
    with pytest.raises(ValueError, match=match):
        select_rbf(X, y, seg, **args)


def test_select_rbf_bad_shapes(rng):
    X, y, seg = _segmented_data(rng)
    with pytest.raises(ValueError, match=r"X must have shape \(n, k\) and y, segments shape \(n,\)"):
        select_rbf(X, y, seg[:-1], spreads=(1.0,), neurons=(3,))
