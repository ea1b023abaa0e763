"""Tests of analysis.compensation.rbf (RBF network as MATLAB newrb, deployment form, streaming)."""

from __future__ import annotations

import json
import zlib

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from sklearn.utils.estimator_checks import parametrize_with_checks

from gyrobench.analysis.compensation.rbf import RADBAS_B, RBFNetwork, StreamingCompensator, batch_compensate


@pytest.fixture
def rng(request) -> np.random.Generator:
    key = zlib.crc32(request.node.nodeid.encode())
    return np.random.default_rng([20261121, key])


@parametrize_with_checks([RBFNetwork(), RBFNetwork(spread=2.0, normalize="minmax", max_neurons=10)])
def test_sklearn_contract(estimator, check):
    check(estimator)


def _newrb_reference(p, t, goal, spread, mn):
    """Literal transcription of MATLAB designrb (newrb.m), column-deleting version, one output."""
    q = p.shape[0]
    b = np.sqrt(-np.log(0.5)) / spread
    dist = np.sqrt(((p[:, None, :] - p[None, :, :]) ** 2).sum(-1))
    P = np.exp(-((dist * b) ** 2))
    d = t.reshape(-1, 1)
    dd = float((d.T @ d)[0, 0])
    left = list(range(q))
    used = []
    W = []
    mses = []
    for k in range(mn):
        if k > 0:
            wj = W[-1]
            a = wj @ P / (wj @ wj)
            P = P - np.outer(wj, a)
        PP = (P * P).sum(0)
        e = ((P.T @ d)[:, 0] ** 2) / (dd * PP)
        e[np.isnan(e)] = 0
        pick = int(np.argmax(e**2))
        W.append(P[:, pick].copy())
        P = np.delete(P, pick, axis=1)
        used.append(left.pop(pick))
        c = p[used]
        a1 = np.exp(-((np.sqrt(((c[:, None, :] - p[None, :, :]) ** 2).sum(-1)) * b) ** 2))
        G = np.vstack([a1, np.ones(q)])
        x = np.linalg.lstsq(G.T, t, rcond=None)[0]
        mse = float(np.mean((t - x @ G) ** 2))
        mses.append(mse)
        if mse < goal:
            break
    return used, np.array(mses)


def test_selection_matches_designrb_transcription(rng):
    X = rng.uniform(-2, 2, size=(60, 2))
    y = np.sin(X[:, 0]) * np.cos(2 * X[:, 1]) + 0.05 * rng.standard_normal(60)
    net = RBFNetwork(spread=0.8, goal=1e-3, max_neurons=25).fit(X, y)
    used, mses = _newrb_reference(X, y, 1e-3, 0.8, 25)
    assert net.selected_.tolist() == used
    np.testing.assert_allclose(net.mse_history_, mses, rtol=1e-9)


def test_radbas_is_half_at_spread():
    """A one-neuron network's basis function is 0.5 at distance = spread (closed form)."""
    X = np.array([[0.0], [1.0]])
    net = RBFNetwork(spread=1.7, max_neurons=1).fit(X, np.array([1.0, 0.0]))
    c = net.centers_[0, 0]
    a1 = np.exp(-((1.7 * net.b1_[0]) ** 2))
    assert abs(a1 - 0.5) < 1e-15
    assert net.b1_[0] == pytest.approx(RADBAS_B / 1.7, rel=1e-15)
    # prediction at the centre = LW + b2 (radbas(0) = 1)
    assert net.predict([[c]])[0] == pytest.approx(net.weights_[0, 0] + net.bias_[0], rel=1e-12)


def test_stops_at_goal_and_max_neurons(rng):
    X = rng.uniform(-1, 1, size=(80, 1))
    y = np.sin(4 * X[:, 0])
    net = RBFNetwork(spread=0.3, goal=1e-4).fit(X, y)
    assert net.mse_history_[-1] < 1e-4
    assert np.all(net.mse_history_[:-1] >= 1e-4)
    assert net.n_neurons_ == len(net.mse_history_) == net.centers_.shape[0]
    net5 = RBFNetwork(spread=0.3, max_neurons=5).fit(X, y)
    assert net5.n_neurons_ == 5


def test_interpolates_with_all_neurons(rng):
    """newrb with MN = Q and goal 0 interpolates distinct points (like newrbe)."""
    X = np.linspace(0, 1, 12)[:, None]
    y = rng.standard_normal(12)
    net = RBFNetwork(spread=0.2).fit(X, y)
    np.testing.assert_allclose(net.predict(X), y, atol=1e-7)


def test_duplicate_inputs_stop_growth():
    X = np.array([[0.0], [0.0], [1.0], [1.0]])
    y = np.array([1.0, 1.0, 2.0, 2.0])
    net = RBFNetwork(spread=0.5).fit(X, y)
    assert net.n_neurons_ == 2


def test_minmax_normalization_is_scale_invariant(rng):
    X = rng.uniform(-1, 1, size=(50, 2))
    y = X[:, 0] ** 2 - X[:, 1]
    a = RBFNetwork(spread=0.7, normalize="minmax", max_neurons=15).fit(X, y)
    b = RBFNetwork(spread=0.7, normalize="minmax", max_neurons=15).fit(X * [1e3, 1e-4] + [5, -2], y)
    np.testing.assert_array_equal(a.selected_, b.selected_)
    np.testing.assert_allclose(
        a.predict(X), b.predict(X * [1e3, 1e-4] + [5, -2]), rtol=1e-9, atol=1e-12
    )


def test_json_round_trip_predicts_identically(rng):
    X = rng.uniform(-3, 3, size=(70, 3))
    y = np.tanh(X[:, 0] * X[:, 2]) + X[:, 1]
    net = RBFNetwork(spread=1.5, goal=1e-3, normalize="minmax").fit(X, y)
    text = net.to_json()
    doc = json.loads(text)
    assert set(["IW", "b1", "LW", "b2", "x_offset", "x_gain"]) <= set(doc)
    back = RBFNetwork.from_json(text)
    Xt = rng.uniform(-3, 3, size=(40, 3))
    np.testing.assert_array_equal(back.predict(Xt), net.predict(Xt))
    # the documented DSP form computed by hand
    p = (Xt - np.array(doc["x_offset"])) * np.array(doc["x_gain"])
    IW, b1, LW, b2 = (np.array(doc[k]) for k in ("IW", "b1", "LW", "b2"))
    a1 = np.exp(-((np.linalg.norm(IW[None, :, :] - p[:, None, :], axis=2) * b1) ** 2))
    np.testing.assert_allclose(a1 @ LW.T + b2, net.predict(Xt)[:, None], rtol=1e-12, atol=1e-12)


def test_from_json_rejects_other_documents():
    with pytest.raises(ValueError, match="format"):
        RBFNetwork.from_json('{"format": "something/2"}')


@pytest.mark.parametrize(
    "kw, match",
    [
        ({"spread": 0.0}, "spread must be"),
        ({"spread": float("nan")}, "spread must be"),
        ({"goal": -1.0}, "goal must be"),
        ({"max_neurons": 0}, "max_neurons must be"),
        ({"max_neurons": 2.5}, "max_neurons must be"),
        ({"normalize": "zscore"}, "normalize must be one of"),
    ],
)
def test_bad_params(kw, match):
    with pytest.raises(ValueError, match=match):
        RBFNetwork(**kw).fit(np.zeros((3, 1)), np.zeros(3))


def _thermal_record(rng, n=900, fs=1.0):
    t = np.arange(n) / fs
    T = -10 + 50 * (t / t[-1]) + 0.01 * rng.standard_normal(n)
    drift = 0.02 * T + 3.0 * np.gradient(T, t) * (1 + 0.01 * T)
    out = drift + 0.01 * rng.standard_normal(n)
    return out, T


def test_streaming_equals_batch_for_any_blocks(rng):
    out, T = _thermal_record(rng)
    from gyrobench.analysis.features import thermal_features

    X = thermal_features(T, 1.0, window_s=61.0)
    net = RBFNetwork(spread=1.0, normalize="minmax", max_neurons=20).fit(X[::5], out[::5])
    ref = batch_compensate(net, out, T, 1.0, window_s=61.0)
    for sizes in ([900], [1] * 900, [7, 100, 3, 250, 540], [61, 61, 1, 777]):
        comp = StreamingCompensator(net, 1.0, window_s=61.0)
        pieces, i = [], 0
        for s in sizes:
            pieces.append(comp.push(out[i : i + s], T[i : i + s]))
            i += s
        pieces.append(comp.flush())
        got = np.concatenate(pieces)
        # identical up to floating-point rounding (summation order of the filter and BLAS)
        np.testing.assert_allclose(got, ref, rtol=1e-12, atol=1e-12 * np.max(np.abs(ref)))
    assert comp.latency_samples == 30


def test_streaming_short_record_is_an_error(rng):
    comp = StreamingCompensator(RBFNetwork(), 1.0, window_s=61.0)
    comp.push(np.zeros(10), np.zeros(10))
    with pytest.raises(ValueError, match="shorter than the derivative window"):
        comp.flush()


@settings(max_examples=25, deadline=None)
@given(cuts=st.lists(st.integers(1, 899), max_size=12, unique=True))
@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_streaming_equals_batch_for_random_partitions(cuts):
    """Property: any block partition of the record gives the batch result (to rounding)."""
    rng = np.random.default_rng(5)
    out, T = _thermal_record(rng, n=900)
    net = _STREAM_NET
    ref = batch_compensate(net, out, T, 1.0, window_s=61.0)
    comp = StreamingCompensator(net, 1.0, window_s=61.0)
    edges = [0, *sorted(cuts), 900]
    got = np.concatenate(
        [comp.push(out[a:b], T[a:b]) for a, b in zip(edges[:-1], edges[1:], strict=True)] + [comp.flush()]
    )
    np.testing.assert_allclose(got, ref, rtol=1e-12, atol=1e-12 * np.max(np.abs(ref)))


def _stream_net():
    from gyrobench.analysis.features import thermal_features

    out, T = _thermal_record(np.random.default_rng(6), n=900)
    X = thermal_features(T, 1.0, window_s=61.0)
    return RBFNetwork(spread=1.0, normalize="minmax", max_neurons=15).fit(X[::5], out[::5])


_STREAM_NET = _stream_net()
