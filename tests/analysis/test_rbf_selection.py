"""select_rbf (analysis.compensation.rbf_selection) and deployment_float32 (analysis.deployment):
RBF selection by leave-one-segment-out cross-validation, and single-precision deployment of an
exported network, methods a user applies to a real gyro's thermal-chamber logs."""

from __future__ import annotations

import json

import numpy as np
import pytest
from gyrobench.analysis.compensation.rbf_selection import select_rbf
from gyrobench.analysis.deployment import deployment_float32

# ------------------------------------------------------------------ RBF selection (CV)


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
    from gyrobench.analysis.compensation.rbf import RBFNetwork

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



# --------------------------------------------------------------- float32 deployment


def test_float32_deployment_error_within_rounding_bound(rng):
    """float32 a1/a2 vs float64: each output is a sum of k terms LW_i a1_i, each a1_i carries a
    few ulp of float32 (the inputs, the distance, exp), so
    |a2_32 - a2_64| <= c eps32 (sum |LW_i| + |b2|), with c = 16 covering ~5 roundings per term."""
    from gyrobench.analysis.compensation.rbf import RBFNetwork

    X, y, _ = _segmented_data(rng)
    for spread in (0.5, 32.0):  # well conditioned, and large cancelling weights
        net = RBFNetwork(spread=spread, max_neurons=8, normalize="minmax").fit(X, y)
        doc = json.loads(net.to_json())
        y32 = deployment_float32(doc, X)
        assert y32.dtype == np.float32
        bound = 16 * np.finfo(np.float32).eps * (np.sum(np.abs(doc["LW"])) + abs(doc["b2"][0]))
        assert np.max(np.abs(y32 - net.predict(X))) <= bound


