"""Tests of scenarios.ifog_thermal (paper 003): reduced fast run, closed forms, full reproduction (slow)."""

from __future__ import annotations

import json
import pickle
import time
from dataclasses import replace

import numpy as np
import pytest
from matplotlib.figure import Figure

from scenarios import ifog_thermal as sc
from scenarios import registry
from sim import units

SMALL = sc.Config(
    identification_settle_h=0.5,
    identification_hold_h=0.5,
    validation_soak_h=0.25,
    validation1_runs=2,
    validation2_runs=2,
    fs_hz=0.1,
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
    assert len(small_outcome.tables) == 5
    assert all(isinstance(h.holds, bool) for h in small_outcome.headlines[:3])


def test_streaming_compensation_equals_batch(small_outcome):
    assert small_outcome.results["streaming_max_abs_deviation_deg_h"] <= 1e-9


def test_deployment_json_rebuilds_the_network(small_outcome):
    from analysis.compensation.rbf import RBFNetwork

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


@pytest.mark.slow
def test_full_reproduction_targets_and_runtime():
    """Default config, seed 0: the paper's three conclusions and the 2-minute budget."""
    t0 = time.perf_counter()
    out = sc.run(sc.Config(), 0)
    elapsed = time.perf_counter() - t0
    assert elapsed < 120.0
    r = out.results
    assert r["txdt_max_deg_h"] > 0.2
    raw = np.mean([d["mse_raw"] for d in r["validation_zero_rate"]])
    comp = np.mean([d["mse_compensated"] for d in r["validation_zero_rate"]])
    assert raw / comp >= 10.0
    assert all(d["mse_improved"] < d["mse_traditional"] for d in r["validation_rotated"])
    assert len(r["validation_zero_rate"]) == 5 and len(r["validation_rotated"]) == 5
