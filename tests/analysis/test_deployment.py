"""Tests of analysis.deployment: an exported RBF network evaluated in single precision."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gyrobench.analysis.compensation.rbf import RBFNetwork
from gyrobench.analysis.deployment import deployment_float32


def _segmented_data(rng):
    """A smooth 2-D surface plus small noise (the data of the RBF selection tests)."""
    x = np.linspace(-1.0, 1.0, 150)
    X = np.column_stack([x, np.sin(3 * x)])
    y = 0.5 * x**2 + 0.2 * X[:, 1] + 0.01 * rng.standard_normal(len(x))
    return X, y, np.repeat([0, 1, 2], 50)


def test_float32_deployment_error_within_rounding_bound(rng):
    """float32 a1/a2 vs float64: each output is a sum of k terms LW_i a1_i, each a1_i carries a
    few ulp of float32 (the inputs, the distance, exp), so
    |a2_32 - a2_64| <= c eps32 (sum |LW_i| + |b2|), with c = 16 covering ~5 roundings per term."""
    X, y, _ = _segmented_data(rng)
    for spread in (0.5, 32.0):  # well conditioned, and large cancelling weights
        net = RBFNetwork(spread=spread, max_neurons=8, normalize="minmax").fit(X, y)
        doc = json.loads(net.to_json())
        y32 = deployment_float32(doc, X)
        assert y32.dtype == np.float32
        bound = 16 * np.finfo(np.float32).eps * (np.sum(np.abs(doc["LW"])) + abs(doc["b2"][0]))
        assert np.max(np.abs(y32 - net.predict(X))) <= bound


def test_float32_accepts_the_json_text(rng):
    X, y, _ = _segmented_data(rng)
    text = RBFNetwork(spread=2.0, max_neurons=4, normalize="minmax").fit(X, y).to_json()
    np.testing.assert_array_equal(deployment_float32(text, X), deployment_float32(json.loads(text), X))


def test_float32_bad_input(rng):
    X, y, _ = _segmented_data(rng)
    doc = json.loads(RBFNetwork(spread=2.0, max_neurons=4, normalize="minmax").fit(X, y).to_json())
    with pytest.raises(ValueError, match=r"doc must hold .* missing \['LW'\]"):
        deployment_float32({k: v for k, v in doc.items() if k != "LW"}, X)
    with pytest.raises(ValueError, match=r"X must have shape \(n, k\); got \(150,\)"):
        deployment_float32(doc, X[:, 0])
