"""Tests of scenarios/mems_scale_factor.py: the paper-001 reproduction on the default seed, contract, bad config."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from gyrobench.analysis.compensation.polynomial import PiecewisePolynomial
from gyrobench.scenarios import mems_scale_factor as ms
from gyrobench.scenarios.base import Outcome

SMALL = ms.Config(
    rates_dps=(360.0, 0.0, -360.0),
    dwell_s=5.0,
    settle_s=1.0,
    warmup_s=0.0,
    lead_in_s=1.0,
    fs_hz=50.0,
    n_fit_runs=1,
    n_heldout_runs=1,
)


@pytest.fixture(scope="module")
def outcome() -> Outcome:
    """The default experiment on the CLI's default seed (0)."""
    return ms.run(ms.Config(), 0)


# ------------------------------------------------------------------ paper targets (issue 3)
def test_raw_nonlinearity_matches_paper(outcome):
    assert abs(outcome.results["raw_nonlinearity_pct"] - 15.71) <= 1.0


def test_low_rates_nearly_linear(outcome):
    assert 1e-4 <= outcome.results["low_rate_nonlinearity"] < 1e-2  # paper: order 1e-3


def test_breakpoints_at_1800(outcome):
    assert outcome.results["breakpoints_dps"] == [-1800.0, 1800.0]
    assert outcome.results["piecewise_breakpoint_rates_dps"] == [-1800.0, 1800.0]
    assert outcome.results["methods"]["piecewise"]["orders"] == [9, 1, 9]


def test_piecewise_heldout_at_most_0p2_pct(outcome):
    assert outcome.results["methods"]["piecewise"]["heldout_nonlinearity_pct"] <= 0.2


def test_two_stage_within_factor_two_of_paper(outcome):
    kn = outcome.results["methods"]["two_stage_poly"]["heldout_nonlinearity_pct"]
    assert 0.59 / 2 <= kn <= 0.59 * 2


def test_bayes_bp_no_worse_than_twice_the_paper(outcome):
    assert outcome.results["methods"]["bayes_bp"]["heldout_nonlinearity_pct"] <= 0.45 * 2


@pytest.mark.xfail(
    strict=True,
    reason=(
        "honest simulation: the trainbr-style network fits the simulated gyro far better (about 0.02 %) than the "
        "paper's 0.45 %; the outcome reports it and the method order; the data are not tuned to match"
    ),
)
def test_bayes_bp_within_factor_two_of_paper(outcome):
    assert (
        0.45 / 2 <= outcome.results["methods"]["bayes_bp"]["heldout_nonlinearity_pct"] <= 0.45 * 2
    )


def test_heldout_improvement_at_least_20x_for_all_and_100x_for_piecewise_and_mlp(outcome):
    """The paper says "about two orders of magnitude"; its own ratios are 112x, 35x and 27x.

    On the default seed the piecewise and BR-MLP models exceed 100x, the two-stage
    polynomial does not (about 27x, as in the paper): >= 20x is what holds for all three.
    """
    raw = outcome.results["raw_nonlinearity_pct"]
    ratio = {k: raw / m["heldout_nonlinearity_pct"] for k, m in outcome.results["methods"].items()}
    assert all(v >= 20 for v in ratio.values()), ratio
    assert ratio["piecewise"] >= 100 and ratio["bayes_bp"] >= 100, ratio
    assert ratio["two_stage_poly"] < 100, ratio  # so the test name does not overstate it


# ------------------------------------------------------------------ outcome contract
def test_results_json_has_the_issue_keys(outcome):
    r = json.loads(json.dumps(outcome.results))
    assert isinstance(r["raw_nonlinearity_pct"], float)
    assert isinstance(r["breakpoints_dps"], list)
    for key in ("piecewise", "two_stage_poly", "bayes_bp"):
        for field in ("nonlinearity_pct", "heldout_nonlinearity_pct", "eval_time_ms"):
            assert np.isfinite(r["methods"][key][field]), (key, field)


def test_tables_figures_headlines(outcome):
    t1, t2, t3, t4 = outcome.tables
    assert len(t1.rows) == 21 and len(t2.rows) == 20 and len(t3.rows) == 5
    assert len(t4.rows) == len(ms.Config().sf_repeatability_sweep_ppm)
    assert t3.rows[-1][0].startswith("interpolation through the fit-run means")
    assert [f.name for f in outcome.figures] == [
        "fig2_raw_output",
        "fig3_input_output",
        "fig4_continuity",
        "fig5_compensated",
        "fig6_nonlinearity",
    ]
    order = [h for h in outcome.headlines if h.quantity.startswith("method order")][0]
    assert order.holds == outcome.results["method_order_matches_paper"]
    raw = outcome.headlines[0]
    assert raw.holds is True and raw.target == "15.71"


def test_sweep_replicate_0_at_zero_repeatability_is_the_main_experiment(outcome):
    r = outcome.results
    sweep = r["heldout_nonlinearity_pct_vs_sf_repeatability"]
    assert sweep["sigma_ppm"] == [0.0, 100.0, 300.0, 1000.0] and sweep["replicates"] == 3
    cell = sweep["per_replicate"]["0"][0]
    for key, m in r["methods"].items():
        assert cell[key] == m["heldout_nonlinearity_pct"]
    assert cell["floor"] == r["repeatability_floor_pct"]
    assert all(len(v) == 3 for v in sweep["per_replicate"].values())


def test_sweep_grows_with_the_scale_factor_repeatability(outcome):
    """Common random numbers within a replicate: larger turn-on errors, larger held-out K_n."""
    med = outcome.results["heldout_nonlinearity_pct_vs_sf_repeatability"]["median"]
    for key in ("piecewise", "bayes_bp", "floor"):
        vals = [med[s][key] for s in ("0", "100", "300", "1000")]
        assert np.all(np.diff(vals) > 0), (key, vals)


def test_conclusion_states_what_table_4_shows(outcome):
    """Every number in the conclusion's Table 4 sentence comes from the table's medians."""
    med = outcome.results["heldout_nonlinearity_pct_vs_sf_repeatability"]["median"]
    for sig, cell in med.items():
        assert (
            f"at {float(sig):g} ppm piecewise {cell['piecewise']:.3f} %, two-stage "
            f"{cell['two_stage_poly']:.3f} %, BR-MLP {cell['bayes_bp']:.3f} %"
        ) in outcome.conclusion
    paper = outcome.results["method_order_paper"]
    in_order = [s for s, c in med.items() if sorted(paper, key=c.get) == paper]
    listed = ", ".join(f"{float(s):g}" for s in in_order)
    if not in_order:
        where = "none of these values."
    elif len(in_order) < len(med):
        where = f"{listed} ppm only."
    else:
        where = "every value."
    assert f"The medians are in the paper's order at {where}" in outcome.conclusion
    assert "few hundred ppm" not in outcome.conclusion  # the old, unmeasured claim


def test_repeatability_floor_is_reported_beside_the_methods(outcome):
    """Default seed: the floor lies below every method, BR-MLP within 2x of it (the reason it beats 0.45 %)."""
    r = outcome.results
    floor = r["repeatability_floor_pct"]
    assert 0 < floor < min(m["heldout_nonlinearity_pct"] for m in r["methods"].values())
    assert r["methods"]["bayes_bp"]["heldout_nonlinearity_pct"] < 2 * floor
    assert f"{floor:.3f} %" in outcome.conclusion


def test_repeatability_floor_closed_form():
    """Outputs equal to the fit-run means map to the rates exactly; beyond the ends, linear extension."""
    rates = np.array([-2.0, -1.0, 0.0, 1.0, 2.0])
    fit = np.array([[-1.5, -0.9, 0.1, 1.1, 1.4], [-1.7, -1.1, -0.1, 0.9, 1.6]])  # mean: tanh-like
    xm = fit.mean(axis=0)
    np.testing.assert_allclose(ms.repeatability_floor(rates, fit, xm), rates, rtol=1e-15)
    got = ms.repeatability_floor(
        rates, fit, np.array([xm[0] - 0.1, 0.5 * (xm[1] + xm[2]), xm[-1] + 0.1])
    )
    np.testing.assert_allclose(got, [-2.0 - 0.1 / 0.6, -0.5, 2.0 + 0.1 / 0.5], rtol=1e-12)


def test_repeatability_floor_rejects_non_increasing_means():
    with pytest.raises(ValueError, match="increase strictly with rate; got"):
        ms.repeatability_floor(np.arange(3.0), np.array([[0.0, 1.0, 1.0]]), np.zeros(3))


def test_method_order_is_reported_not_forced(outcome):
    r = outcome.results
    order = sorted(r["methods"], key=lambda k: r["methods"][k]["heldout_nonlinearity_pct"])
    assert r["method_order_heldout"] == order
    assert r["method_order_paper"] == ["piecewise", "bayes_bp", "two_stage_poly"]
    if order != r["method_order_paper"]:
        assert "differs from the paper" in outcome.conclusion


# ------------------------------------------------------------------ simulation and task
def test_simulate_records_truth_that_sums_to_the_output():
    recs = ms.simulate(SMALL, 5)
    assert [r.metadata["role"] for r in recs] == ["fit", "heldout"]
    for rec in recs:
        total = rec["truth/true_rate"] + sum(
            c.data for k, c in rec.truth.items() if k != "true_rate"
        )
        np.testing.assert_allclose(total, rec["rate"], rtol=1e-12, atol=1e-15)
        np.testing.assert_array_equal(rec["table_rate"], rec["truth/true_rate"])
    m = ms.rate_means(recs[0])
    # linear range: output = rate + bias + sign offset + g-sensitivity + noise, a few deg/s at most
    assert m.shape == (3,) and np.all(np.abs(m - np.array([360.0, 0.0, -360.0])) < 5.0)
    windows = np.array(recs[0].metadata["windows_s"])
    assert np.all(windows[:, 1] <= recs[0].time[-1])


def test_simulate_is_reproducible_and_runs_differ():
    a, b = ms.simulate(SMALL, 11), ms.simulate(SMALL, 11)
    np.testing.assert_array_equal(a[0]["rate"], b[0]["rate"])
    assert a[0].metadata["turn_on_bias_dps"] != a[1].metadata["turn_on_bias_dps"]
    assert a[0].metadata["scale_factor_error_ppm"] == 0.0  # default gyro: no turn-on SF scatter


def test_replicates_are_independent_and_share_draws_across_repeatability():
    """Replicate r > 0 is another set of runs; the same replicate at another sigma differs only by e_on."""
    a = ms.simulate(SMALL, 11, replicate=1)
    assert (
        a[0].metadata["turn_on_bias_dps"] != ms.simulate(SMALL, 11)[0].metadata["turn_on_bias_dps"]
    )
    cfg = dataclasses.replace(
        SMALL, gyro=dataclasses.replace(SMALL.gyro, scale_factor_repeatability=1e-3)
    )
    b = ms.simulate(cfg, 11, replicate=1)
    assert b[0].metadata["turn_on_bias_dps"] == a[0].metadata["turn_on_bias_dps"]
    e = [r.metadata["scale_factor_error_ppm"] for r in b]
    assert all(v != 0.0 for v in e) and e[0] != e[1]
    np.testing.assert_array_equal(b[0]["truth/noise"], a[0]["truth/noise"])


def test_simulate_rejects_negative_replicate():
    with pytest.raises(ValueError, match="replicate must be an integer >= 0; got -1"):
        ms.simulate(SMALL, 0, replicate=-1)


def test_compensation_task():
    cfg = dataclasses.replace(ms.Config(), dwell_s=20.0, settle_s=5.0, warmup_s=600.0)
    task = ms.compensation_task(cfg, 3)
    assert task.X_train.shape == (63, 1) and task.y_train.shape == (63,)
    assert task.target == "rate" and task.unit == "deg/s" and len(task.heldout) == 1
    run = task.heldout[0]
    assert task.scorer(run.truth, run)["nonlinearity_pct"] == 0.0
    assert abs(task.scorer(run.output, run)["nonlinearity_pct"] - 15.71) < 1.0
    model = PiecewisePolynomial().fit(task.X_train, task.y_train)
    assert task.scorer(task.compensate(model.predict(run.X), run), run)["nonlinearity_pct"] < 0.2


def test_one_fit_run_is_too_few_for_order_9():
    cfg = dataclasses.replace(ms.Config(), dwell_s=12.0, settle_s=2.0, warmup_s=0.0, n_fit_runs=1)
    with pytest.raises(ValueError, match="order 9 needs at least 10 distinct inputs; got 6"):
        ms.run(cfg, 0)


# ------------------------------------------------------------------ bad config
@pytest.mark.parametrize(
    ("kw", "msg"),
    [
        ({"rates_dps": (1.0, 0.0)}, "at least 3 finite rates"),
        ({"rates_dps": (0.0, 2.0, 1.0)}, "strictly monotonic"),
        ({"rates_dps": (2.0, 1.0, 1.0, 0.0)}, "strictly monotonic without duplicates"),
        ({"rates_dps": (2.0, float("nan"), 0.0)}, "finite rates"),
        ({"settle_s": 100.0}, "settle_s must be < dwell_s"),
        ({"fs_hz": 0.0}, "fs_hz must be > 0 Hz"),
        ({"n_fit_runs": 0}, "n_fit_runs must be an integer >= 1"),
        ({"orders": (9, 1)}, "orders must be three integers"),
        ({"join_width": 0.7}, r"join_width must be in \(0, 0.5\)"),
        ({"sf_repeatability_sweep_ppm": ()}, r"sf_repeatability_sweep_ppm must be .* got \(\)"),
        ({"sf_repeatability_sweep_ppm": (-1.0,)}, r"in \[0, 1e5\) ppm; got \(-1.0,\)"),
        ({"sweep_replicates": 0}, "sweep_replicates must be an integer >= 1; got 0"),
    ],
)
def test_config_rejects(kw, msg):
    with pytest.raises(ValueError, match=msg):
        ms.Config(**kw)


def test_config_rejects_wrong_gyro_type():
    with pytest.raises(TypeError, match="Config.gyro must be a MemsSpec"):
        ms.Config(gyro={"knee_rate": 1.0})


@pytest.mark.slow
@pytest.mark.parametrize("seed", [1, 2, 3, 4, 5])
def test_targets_hold_on_other_seeds(seed):
    """Not a default-seed accident: the issue's targets hold on five more seeds."""
    cfg = dataclasses.replace(ms.Config(), sf_repeatability_sweep_ppm=(0.0,), sweep_replicates=1)
    r = ms.run(cfg, seed).results
    assert abs(r["raw_nonlinearity_pct"] - 15.71) <= 1.0
    assert r["breakpoints_dps"] == [-1800.0, 1800.0]
    assert r["methods"]["piecewise"]["heldout_nonlinearity_pct"] <= 0.2
    assert 0.295 <= r["methods"]["two_stage_poly"]["heldout_nonlinearity_pct"] <= 1.18
