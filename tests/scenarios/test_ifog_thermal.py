"""Tests of scenarios.ifog_thermal (paper 003): reduced fast run, closed forms, full reproduction (slow)."""

from __future__ import annotations

import json
import pickle
import time
from dataclasses import replace

import numpy as np
import pytest
from matplotlib.figure import Figure

from gyrobench.scenarios import ifog_thermal as sc
from gyrobench.scenarios import registry
from gyrobench.sim import units

SMALL = sc.Config(
    identification_settle_h=0.5,
    identification_hold_h=0.5,
    validation_soak_h=0.25,
    validation1_runs=2,
    validation2_runs=2,
    fs_hz=0.1,
    seed_summary_count=2,
)


@pytest.fixture(scope="module")
def small_outcome():
    return sc.run(SMALL, 7)


def test_registered():
    assert registry.get("ifog_thermal") is sc


def test_small_run_results_layout(small_outcome):
    r = small_outcome.results
    assert set(r) >= {"txdt_max_deg_h", "validation_zero_rate", "validation_rotated", "windings"}
    assert len(r["validation_zero_rate"]) == 2 and set(r["validation_zero_rate"][0]) == {
        "mse_raw",
        "mse_compensated",
    }
    assert len(r["validation_rotated"]) == 2
    assert set(r["validation_rotated"][0]) == {"mse_raw", "mse_traditional", "mse_improved"}
    assert set(r["windings"]) == {"helical", "dipolar", "quadrupolar", "octupolar"}
    json.dumps(r)  # results.json must serialise
    assert all(isinstance(f.figure, Figure) for f in small_outcome.figures)
    assert [f.name for f in small_outcome.figures] == [
        "fig2_point_heating",
        "fig6_estimated_drift",
        "fig7_validation1",
        "fig8_validation2",
    ]
    assert len(small_outcome.tables) == 9
    assert [d["seed"] for d in r["seed_summary"]] == [7, 8]
    assert all(isinstance(h.holds, bool) for h in small_outcome.headlines[:3])


def test_streaming_compensation_equals_batch(small_outcome):
    assert small_outcome.results["streaming_max_abs_deviation_deg_h"] <= 1e-9


def test_deployment_json_rebuilds_the_network(small_outcome):
    from gyrobench.analysis.compensation.rbf import RBFNetwork

    doc = small_outcome.results["rbf_improved_deployment"]
    net = RBFNetwork.from_json(json.dumps(doc))
    assert net.n_neurons_ == small_outcome.results["rbf_improved"]["n_neurons"]


def test_point_heating_closed_form():
    """T x dT term of a free stretch: n C2 T[degC] Tdot dL (L - 2 z) / (L D), largest at 40 degC."""
    cfg = sc.Config()
    T, shupe, prod, total = sc.point_heating(cfg)
    coil = cfg.coil_spec(defects=False)
    tdot = cfg.point_rate_degC_per_min / 60.0
    exact = (
        coil.index
        * cfg.dn_dT_slope_per_K2
        * 40.0
        * tdot
        * 10.0
        * (1000.0 - 500.0)
        / (1000.0 * coil.diameter)
    )
    assert units.deg_per_h(prod[-1]) == pytest.approx(exact, rel=1e-12)
    np.testing.assert_allclose(total, shupe + prod, rtol=1e-14)
    assert np.max(np.abs(prod)) > 0.2  # the paper's figure 2 statement


def test_winding_table_helical_worst():
    w = sc.winding_comparison(SMALL)
    peaks = {k: v["peak_total"] for k, v in w.items()}
    assert max(peaks, key=peaks.get) == "helical"
    assert peaks["dipolar"] > max(peaks["quadrupolar"], peaks["octupolar"])


def test_compensation_task_contract():
    task = sc.compensation_task(SMALL, 3)
    assert task.target == "error" and task.X_train.shape[1] == 3
    assert len(task.heldout) == 1 + SMALL.validation1_runs + SMALL.validation2_runs
    assert [h.label for h in task.heldout][:2] == ["ident_2", "val1_run1"]
    pickle.dumps(task.scorer)
    h = task.heldout[-1]
    s = task.scorer(h.truth + 0.1, h)
    assert s["mse"] == pytest.approx(0.01, rel=1e-12)
    assert np.allclose(h.truth, SMALL.validation2_true_rate_deg_h)


def test_simulate_is_deterministic():
    a = sc.simulate(replace(SMALL, validation1_runs=1, validation2_runs=1), 11)
    b = sc.simulate(replace(SMALL, validation1_runs=1, validation2_runs=1), 11)
    assert [r.name for r in a] == ["ident_1", "ident_2", "val1_run1", "val2_run1"]
    for x, y in zip(a, b, strict=True):
        np.testing.assert_array_equal(x["rate"], y["rate"])


def test_bad_layer_count_for_winding():
    with pytest.raises(
        ValueError, match=r"quadrupolar winding needs a layer count that is a multiple of 4"
    ):
        sc.Config(layers=42)


def test_bad_ramp_the_diffusion_step_cannot_resolve():
    cfg = replace(SMALL, identification_rate_degC_per_min=30.0)
    with pytest.raises(ValueError, match=r"chamber rate 30 K/min .* per diffusion step"):
        sc.simulate(cfg, 0)


def test_bad_runs():
    with pytest.raises(ValueError, match=r"validation1_runs must be an integer >= 1"):
        sc.Config(validation1_runs=0)


# ------------------------------------------------------------------ RBF selection (CV)


def _segmented_data(rng):
    """Three contiguous segments of a smooth 2-D surface plus small noise."""
    x = np.linspace(-1.0, 1.0, 150)
    X = np.column_stack([x, np.sin(3 * x)])
    y = 0.5 * x**2 + 0.2 * X[:, 1] + 0.01 * rng.standard_normal(len(x))
    return X, y, np.repeat([0, 1, 2], 50)


@pytest.fixture
def rng(request) -> np.random.Generator:
    import zlib

    return np.random.default_rng([20261121, zlib.crc32(request.node.nodeid.encode())])


def test_select_rbf_follows_the_stated_rule(rng):
    """Fewest neurons among cells within 10 % of the best CV MSE; ties to the largest spread;
    the CV MSE of a cell is the mean of its held-out segment MSEs, recomputed here by hand."""
    from gyrobench.analysis.compensation.rbf import RBFNetwork

    X, y, seg = _segmented_data(rng)
    spreads, neurons = (0.5, 2.0, 8.0), (2, 4, 8)
    sel = sc.select_rbf(X, y, seg, spreads=spreads, neurons=neurons, tolerance=0.10)
    assert set(sel.cv_mse) == {(s, n) for s in spreads for n in neurons}
    s, n = 2.0, 4
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
    assert sel.cv_mse[(s, n)] == pytest.approx(by_hand, rel=1e-12)
    best = min(sel.cv_mse.values())
    assert sel.cv_mse[sel.best] == best
    band = [k for k, v in sel.cv_mse.items() if v <= 1.1 * best]
    assert sel.chosen in band
    assert sel.max_neurons == min(k[1] for k in band)
    assert sel.spread == max(k[0] for k in band if k[1] == sel.max_neurons)


def test_select_rbf_zero_tolerance_is_the_cv_minimum(rng):
    X, y, seg = _segmented_data(rng)
    sel = sc.select_rbf(X, y, seg, spreads=(0.5, 4.0), neurons=(3, 6), tolerance=0.0)
    assert sel.chosen == sel.best


def test_select_rbf_needs_two_segments(rng):
    X, y, _ = _segmented_data(rng)
    with pytest.raises(
        ValueError, match=r"segments must hold at least 2 distinct labels .*got labels \[0\]"
    ):
        sc.select_rbf(X, y, np.zeros(len(y), dtype=int), spreads=(1.0,), neurons=(3,))


def test_identification_segments_split_at_the_chamber_knots():
    """Settle ends, and the 40 degC hold ends, at knots 2 and 4 of the chamber program."""
    knots_h = SMALL.identification_profile().times / 3600.0
    t = np.array([0.0, knots_h[2] - 1e-6, knots_h[2] + 1e-6, knots_h[4] - 1e-6, knots_h[4] + 1e-6])
    np.testing.assert_array_equal(sc.identification_segments(SMALL, t), [0, 0, 1, 1, 2])


def test_selection_sees_only_identification_run_1(small_outcome):
    """The reported choice is reproduced from identification run 1 alone, and a different
    validation protocol (other ramp rates, other run counts) does not change it."""
    r = small_outcome.results["rbf_selection"]
    other = replace(
        SMALL, validation1_runs=1, validation2_runs=3, validation2_rate_degC_per_min=0.25
    )
    for cfg in (SMALL, other):
        train = sc._prepare(sc.simulate(cfg, 7)[0], cfg)
        assert train.name == "ident_1"
        sel_imp, sel_trad, imp, trad = sc.fit_models(cfg, train)
        assert [sel_imp.spread, sel_imp.max_neurons] == [
            r["improved"]["spread"],
            r["improved"]["max_neurons"],
        ]
        assert [sel_trad.spread, sel_trad.max_neurons] == [
            r["traditional"]["spread"],
            r["traditional"]["max_neurons"],
        ]


def test_fixed_rbf_settings_bypass_the_search():
    cfg = replace(SMALL, rbf_spread=16.0, rbf_max_neurons=5)
    train = sc._prepare(sc.simulate(cfg, 7)[0], cfg)
    sel_imp, sel_trad, imp, _ = sc.fit_models(cfg, train)
    assert sel_imp.chosen == sel_trad.chosen == (16.0, 5)
    assert list(sel_imp.cv_mse) == [(16.0, 5)]
    assert imp.spread == 16.0 and imp.max_neurons == 5


def test_fixed_spread_searches_the_neuron_count_only():
    cfg = replace(SMALL, rbf_spread=8.0)
    train = sc._prepare(sc.simulate(cfg, 7)[0], cfg)
    sel_imp, *_ = sc.fit_models(cfg, train)
    assert {k[0] for k in sel_imp.cv_mse} == {8.0}
    assert {k[1] for k in sel_imp.cv_mse} == set(cfg.rbf_neuron_grid)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"rbf_spread": 0.0}, r"rbf_spread / rbf_spread_grid must be > 0"),
        ({"rbf_spread_grid": ()}, r"rbf_spread / rbf_spread_grid must be > 0"),
        ({"rbf_max_neurons": 0}, r"rbf_max_neurons / rbf_neuron_grid must be integers >= 1"),
        ({"rbf_cv_tolerance": -0.1}, r"rbf_cv_tolerance must be >= 0"),
        ({"seed_summary_count": -1}, r"seed_summary_count must be an integer >= 0"),
    ],
)
def test_bad_rbf_settings(kwargs, match):
    with pytest.raises(ValueError, match=match):
        sc.Config(**kwargs)


def test_sensitivity_table_is_labelled_as_not_used_for_selection(small_outcome):
    t = next(t for t in small_outcome.tables if "sensitivity" in t.title or "NOT used" in t.title)
    assert "scored on validation data, NOT used for selection" in t.title
    assert str(t.rows[-1][0]).startswith("CV choice")
    r = small_outcome.results
    row, sel = r["rbf_cv_choice_scored"], r["rbf_selection"]
    assert (row["spread"], row["max_neurons"]) == (
        sel["improved"]["spread"],
        sel["improved"]["max_neurons"],
    )
    assert (row["traditional_spread"], row["traditional_max_neurons"]) == (
        sel["traditional"]["spread"],
        sel["traditional"]["max_neurons"],
    )
    # the CV row is the reported models' score, the same numbers as Tables 2 and 3
    v1, v2 = r["validation_zero_rate"], r["validation_rotated"]
    assert row["validation1_ratio"] == r["validation_zero_rate_mean_ratio"]
    assert row["validation1_ratio"] == pytest.approx(
        np.mean([d["mse_raw"] for d in v1]) / np.mean([d["mse_compensated"] for d in v1]),
        rel=1e-12,
    )
    assert row["validation2_wins"] == sum(d["mse_improved"] < d["mse_traditional"] for d in v2)


def test_identification_2_table(small_outcome):
    t = next(t for t in small_outcome.tables if t.title.startswith("Identification run 2"))
    d = small_outcome.results["identification_2"]
    assert t.rows[0][:3] == [d["mse_raw"], d["mse_traditional"], d["mse_improved"]]


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
        y32 = sc.deployment_float32(doc, X)
        assert y32.dtype == np.float32
        bound = 16 * np.finfo(np.float32).eps * (np.sum(np.abs(doc["LW"])) + abs(doc["b2"][0]))
        assert np.max(np.abs(y32 - net.predict(X))) <= bound


def test_float32_result_is_reported_with_its_verdict(small_outcome):
    f = small_outcome.results["rbf_deployment_float32"]
    assert set(f) >= {
        "max_abs_compensation_difference_deg_h",
        "max_relative_mse_change",
        "validation_zero_rate_mean_ratio",
        "validation_rotated_wins",
    }
    t = next(t for t in small_outcome.tables if "single precision" in t.title)
    ok = f["max_relative_mse_change"] <= sc._FLOAT32_MSE_TOLERANCE
    assert ("NOT ACCEPTABLE" not in t.note) == ok
    assert "Criterion (our choice; the paper states none)" in t.note


@pytest.mark.slow
def test_full_reproduction_reports_honestly_and_runtime():
    """Default config, seed 0, in the 2-minute budget.

    The targets (validation 1 >= 10x; improved < traditional in every validation-2 run)
    are NOT asserted: with the RBF settings chosen by CV on identification run 1 they
    hold for some drawn units and not for others (seed-dependence table). What is
    asserted is that the report states the outcome as computed: the headlines' verdicts
    and the conclusion follow the numbers in results.json, and the seed summary's row for
    seed 0 is the reported run.
    """
    t0 = time.perf_counter()
    out = sc.run(sc.Config(), 0)
    elapsed = time.perf_counter() - t0
    assert elapsed < 120.0
    r = out.results
    assert r["txdt_max_deg_h"] > 0.2  # a physics closed form, not a fitted result
    assert len(r["validation_zero_rate"]) == 5 and len(r["validation_rotated"]) == 5
    raw = np.mean([d["mse_raw"] for d in r["validation_zero_rate"]])
    comp = np.mean([d["mse_compensated"] for d in r["validation_zero_rate"]])
    ratio = raw / comp
    wins = sum(d["mse_improved"] < d["mse_traditional"] for d in r["validation_rotated"])
    h = {x.quantity: x for x in out.headlines}
    assert h["validation 1: mean MSE raw / compensated"].holds == (ratio >= 10.0)
    assert h["validation 1: mean MSE raw / compensated"].reproduced == f"{ratio:.1f}x"
    assert h["validation 2: improved < traditional"].holds == (wins == 5)
    assert h["validation 2: improved < traditional"].reproduced == f"{wins}/5 runs"
    assert (
        f"{ratio:.1f}x" in out.conclusion and f"in {wins} of 5 validation-2 runs" in out.conclusion
    )
    summary = r["seed_summary"]
    assert [d["seed"] for d in summary] == list(range(8))
    assert summary[0]["validation1_ratio"] == pytest.approx(ratio, rel=1e-12)
    assert summary[0]["validation2_wins"] == wins
    n_ok = sum(d["validation1_ratio"] >= 10.0 for d in summary)
    assert f">= 10x in {n_ok}/8 seeds" in h["validation 1: mean MSE raw / compensated"].note
    sel = r["rbf_selection"]["improved"]
    assert (sel["spread"], sel["max_neurons"]) == (
        summary[0]["improved"]["spread"],
        summary[0]["improved"]["max_neurons"],
    )
