"""Tests of scenarios/papers/p004_rlg_thermal (paper 004: one unit = one gyro; claims over units).

The checks every paper shares (a typed frozen result with one float per claim, claims and
deviations well formed, claims judged from the quantities, a report from results alone) are
in tests/scenarios/test_paper_contract.py; these test what paper 004's results mean.
"""

from __future__ import annotations

import json
import math
import pickle

import numpy as np
import pytest

from gyrobench.analysis.compensation.stepwise import StepwiseRegression
from gyrobench.analysis.regressors import REGRESSOR_LABELS
from gyrobench.base import units
from gyrobench.scenarios import registry
from gyrobench.scenarios.base import CompensationTask, Outcome
from gyrobench.scenarios.claims import evaluate
from gyrobench.scenarios.papers import p004_rlg_thermal as sc
from gyrobench.scenarios.papers.p004_rlg_thermal.experiment import has_kinds
from gyrobench.scenarios.papers.p004_rlg_thermal.report import _cross_unit_ratios


@pytest.fixture(scope="module")
def three_units() -> list[sc.UnitResult]:
    return [sc.experiment(sc.Config(), s) for s in range(3)]


@pytest.fixture(scope="module")
def outcome(three_units) -> Outcome:
    claims = evaluate(sc.CLAIMS, [u.quantities for u in three_units])
    return sc.report(sc.Config(), three_units, claims)


def test_registered_and_paper_shape():
    assert registry.get("rlg_thermal") is sc
    assert sc.PAPER == "004" and sc.SOURCE.key == "004"
    assert "seed" not in sc.TITLE.lower()
    assert not hasattr(sc, "run") and not hasattr(sc, "seed_summary")


def test_chamber_program_matches_paper():
    c = sc.Config()
    p = c.chamber()
    # -40 -> +65 at 1 degC / 3 min: 105 K x 180 s per ramp
    ramp_s = 105 * 180.0
    assert p.duration == pytest.approx(30 * 60 + ramp_s + 60 * 60 + ramp_s + 30 * 60, rel=1e-12)
    assert float(units.to_celsius(p(p.times[2]))) == pytest.approx(65.0, abs=1e-9)
    mid = p.times[1] + ramp_s / 2
    assert float(p.derivative(mid)) == pytest.approx(1 / 180.0, rel=1e-12)
    up = sc.Config(return_ramp=False).chamber()
    assert up.duration == pytest.approx(30 * 60 + ramp_s + 60 * 60, rel=1e-12)


# ----------------------------------------------------------------------------- claims
@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_selection_quantities_follow_the_selected_set(three_units):
    """The three selection quantities are the set relations of the selected terms to the paper's."""
    for u in three_units:
        sel, q = set(u.model.selected), u.quantities
        for key in ("keeps_paper_terms", "drops_other_terms", "selects_paper_set"):
            assert q[key] in (0.0, 1.0)  # booleans as 1.0 / 0.0
        assert q["keeps_paper_terms"] == float(set(sc.PAPER_SELECTED) <= sel)
        assert q["drops_other_terms"] == float(not sel & set(sc.PAPER_DROPPED))
        assert q["selects_paper_set"] == q["keeps_paper_terms"] * q["drops_other_terms"]
    assert set(sc.PAPER_SELECTED) | set(sc.PAPER_DROPPED) == set(REGRESSOR_LABELS)


def test_only_the_identified_claims_are_calibrated():
    """Only the device claims the identification sizes (the paper's 0.97) are calibrated; every
    method claim is emergent and judged where the unit shows the thermal effect (issue 28)."""
    calibrated = {c.id for c in sc.CLAIMS if c.kind == "calibrated"}
    assert calibrated == {"004.thermal_effect_large", "004.adj_r2_0_97"}
    roles = {c.id: c.role for c in sc.CLAIMS}
    assert {k for k, r in roles.items() if r == "device"} == calibrated | {"004.multiple_r_high"}
    assert {k for k, r in roles.items() if r == "extension"} == {
        "004.mode_hops_lower_adj_r2", "004.mode_hops_lower_improvement"}
    for c in sc.CLAIMS:
        if c.role != "device":
            assert c.precondition is sc.THERMAL_PRECONDITION, c.id


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_identification_reruns_to_the_stored_constant():
    """identify() on the default Config gives the stored IDENTIFIED, which Config uses."""
    from gyrobench.scenarios.papers.p004_rlg_thermal import identify as ident

    again = ident.identify()
    stored = ident.IDENTIFIED
    assert again.dissipative == stored.dissipative == sc.Config().dissipative
    assert again.seeds == stored.seeds and again.target_share == stored.target_share == sc.PAPER_ADJ_R2
    # the stored k_i are printed to 5 significant digits
    assert again.scale == pytest.approx(stored.scale, rel=1e-4)
    assert ident.CALIBRATED == ("dissipative",)
    with pytest.raises(ValueError, match="target must be a share in"):
        ident.identify(target=1.0)


def test_control_holds_the_chamber_constant_for_the_program_duration():
    c = sc.Config()
    cc = sc.control_config(c)
    ctl = cc.chamber()
    prog = c.chamber()
    # the program's duration after the pre-warm (whole blocks) the record drops
    assert ctl.duration == pytest.approx(prog.duration + cc.prewarm_blocks() * c.block_s, rel=1e-12)
    t = np.linspace(0.0, ctl.duration, 101)
    assert np.all(ctl(t) == pytest.approx(units.celsius(25.0), abs=1e-9))
    with pytest.raises(ValueError, match="constant_c"):
        sc.Config(constant_c=float("nan"))


def test_variants_are_the_deviations_and_refuse_unknown_names():
    named = {d.variant for d in sc.DEVIATIONS if d.variant}
    assert named == set(sc.VARIANTS)
    for d in sc.DEVIATIONS:
        assert d.effect == ""  # measured by the run (reproduce --deviations), never hand-written
    c = sc.Config()
    assert sc.variant_config(c, "up_ramp_only").return_ramp is False
    assert sc.variant_config(c, "langmuir_per_ua").langmuir_deg_h_per_ma == pytest.approx(6.6, rel=1e-12)
    with pytest.raises(ValueError, match="variant_config name must be one of"):
        sc.variant_config(c, "nope")


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_thermal_share_larger_under_the_program_than_under_the_control(three_units):
    """The chamber program drives the thermal bias: each unit's share of the 100-s means' variance
    explained by it falls at constant chamber temperature (same gyro and draws)."""
    ctl = sc.control_config(sc.Config())
    for u in three_units:
        share = u.quantities["thermal_share"]
        assert share is not None and 0.0 < share
        c = sc.experiment(ctl, u.seed).quantities["thermal_share"]
        assert c is not None and c < share


def test_hop_quantities_against_the_counterfactual(three_units):
    """hop_* quantities are the with/without-hops ratios, None when the unit never hops."""
    for u in three_units:
        h, q, s = u.hops, u.quantities, u.stability
        ratio = s.heldout_before_deg_h / s.heldout_after_deg_h
        if h.fit_hops + h.heldout_hops == 0:
            assert q["hop_ratio_cost"] is None and q["hop_adj_r2_cost"] is None
            continue
        assert q["hop_ratio_cost"] == pytest.approx(h.heldout_ratio_nohop / ratio, rel=1e-12)
        if h.fit_hops:
            assert q["hop_adj_r2_cost"] == pytest.approx((1 - u.model.adj_r2) / (1 - h.adj_r2_nohop), rel=1e-12)
        assert len(h.fit_up_degc) + len(h.fit_down_degc) == h.fit_hops
    assert any(u.hops.fit_hops > 0 for u in three_units)


def test_temperature_rate_gradient_kinds():
    """The paper's set carries all three kinds; a set without a gradient carrier does not."""
    assert has_kinds(sc.PAPER_SELECTED)
    assert not has_kinds(["x1", "x3", "x7"])  # no gradient carrier
    assert not has_kinds(["x9", "x3"])  # no temperature carrier
    assert has_kinds(["x2", "x4"])  # dT2/dt = (T1 + H2 - T2)/tau2 carries the gradient


def test_in_sample_identity_ties_adj_r2_to_the_ratio(three_units):
    """Least squares with an intercept: R^2 = 1 - (after/before)^2 on the fitting run."""
    for u in three_units:
        s, m = u.stability, u.model
        assert m.r2 == pytest.approx(1 - (s.fit_after_deg_h / s.fit_before_deg_h) ** 2, rel=1e-12)
        n, p = len(u.fit.t_h), len(m.selected)
        assert m.adj_r2 == pytest.approx(1 - (1 - m.r2) * (n - 1) / (n - p - 1), rel=1e-12)
        q = u.quantities
        assert q["one_minus_adj_r2"] == pytest.approx(1 - m.adj_r2, rel=1e-12)
        assert q["heldout_ratio"] == s.heldout_before_deg_h / s.heldout_after_deg_h


def test_experiment_is_deterministic_and_small(three_units):
    again = sc.experiment(sc.Config(), 1)
    blob = pickle.dumps(again)
    assert blob == pickle.dumps(three_units[1])
    assert len(blob) < 2_000_000
    assert three_units[0].quantities != three_units[1].quantities  # another unit


def test_experiment_matches_its_own_traces(three_units):
    """The held-out 'after' stability is the std of the stored compensated trace minus truth."""
    u = three_units[0]
    h = u.heldout
    assert u.stability.heldout_after_deg_h == pytest.approx(np.std(h.compensated - h.truth, ddof=1), rel=1e-12)
    # the stored compensation is the stored model applied to the stored regressors
    assert np.allclose(h.compensated, h.output - u.model.predict(h.X), rtol=0, atol=1e-12)


# ----------------------------------------------------------------------------- report
def test_report_runs(outcome, three_units):
    assert outcome.scenario == sc.NAME and outcome.seed == 0 and outcome.title == sc.TITLE
    json.dumps(outcome.results, allow_nan=True)
    assert [t.title.split(".")[0] for t in outcome.tables] == [
        "Table 1",
        "Table 1b",
        "Table 2",
        "Table 3 (not in the paper)",
        "Table 4 (not in the paper)",
        "Table 5 (not in the paper)",
    ]
    assert {f.name for f in outcome.figures} == {
        "fig1_output_vs_temperature",
        "fig2_rate_and_gradient",
        "fig4_before_after",
        "fig5_population",
        "fig6_mode_hops",
    }
    rows = outcome.results["unit_rows"]
    assert [r["seed"] for r in rows] == [0, 1, 2]
    freq = outcome.results["selection_frequency"]
    for lab in REGRESSOR_LABELS:
        assert freq[lab] == sum(lab in u.model.selected for u in three_units) / 3
    assert "0/3" in outcome.conclusion or "1/3" in outcome.conclusion or "3/3" in outcome.conclusion


def test_report_one_unit_and_refuses_none():
    u = sc.experiment(sc.Config(), 5)
    o = sc.report(sc.Config(), [u], evaluate(sc.CLAIMS, [u.quantities]))
    assert o.seed == 5 and o.results["unit_rows"][0]["cross_unit_ratio"] is None
    with pytest.raises(ValueError, match="units must hold at least one experiment result"):
        sc.report(sc.Config(), [], [])


def test_cross_unit_ratio_with_own_model_is_own_ratio(three_units):
    """Applying a unit's own model (the list [u, u]) gives exactly its held-out ratio."""
    u = three_units[2]
    r = _cross_unit_ratios([u, u])
    assert r[0] == pytest.approx(u.quantities["heldout_ratio"], rel=1e-12)
    assert all(isinstance(v, float) for v in _cross_unit_ratios(three_units))


# ----------------------------------------------------------------------------- bench, simulate
def test_compensation_task_reproduces_experiment(three_units):
    task = sc.compensation_task(sc.Config(), 0)
    assert isinstance(task, CompensationTask)
    assert task.X_train.shape[1] == 11 and task.target == "error"
    m = StepwiseRegression().fit(task.X_train, task.y_train)
    run = task.heldout[0]
    assert run.label == "heldout"  # the same name for every seed: the bench's scores pair across seeds
    scores = task.scorer(task.compensate(m.predict(run.X), run), run)
    s = three_units[0].stability
    assert scores["bias_stability_deg_h"] == pytest.approx(s.heldout_after_deg_h, rel=1e-12)
    assert scores["before_deg_h"] == pytest.approx(s.heldout_before_deg_h, rel=1e-12)


def test_simulate_recordings():
    recs = sc.simulate(sc.Config(), 3)
    assert [r.name for r in recs] == ["unit3_fit", "unit3_heldout"]
    for r in recs:
        assert {"output", "counts", "T1", "T2"} <= set(r.channels)
        assert "thermal_bias" in r.truth
        assert r.metadata["unit"] == 3
        # T1 and T2 are readings of the network's housing and block-A nodes: reading error =
        # turn-on offset N(0, spread^2) + white noise + quantization (resolution^2/12); bounds
        # at z(1e-6) on the offset and on the sample sd (relative sd 1/sqrt(2 n))
        from scipy.stats import norm

        cfg, z = sc.Config(), norm.isf(0.5e-6)
        sd = math.hypot(cfg.sensor_noise_k, cfg.sensor_resolution_k / math.sqrt(12.0))
        for ch in ("T1", "T2"):
            d = np.asarray(r[ch]) - np.asarray(r[f"inputs/{ch}"])
            assert abs(np.std(d) / sd - 1.0) <= z / math.sqrt(2 * len(d))
            assert abs(np.mean(d)) <= z * cfg.sensor_offset_spread_k
    assert not np.array_equal(recs[0]["output"], recs[1]["output"])


# ----------------------------------------------------------------------------- bad input
def test_bad_config_temperatures():
    with pytest.raises(ValueError, match=r"Config.start_c must be < high_c \[degC\]; got -40.0 and -50.0"):
        sc.Config(high_c=-50.0)


def test_bad_config_dither_below_lock_in():
    with pytest.raises(ValueError, match="dither amplitude too small for lock-in"):
        sc.Config(backscatter_sigma=1e-4)


def test_bad_config_block_not_whole_samples():
    with pytest.raises(ValueError, match="whole number of samples"):
        sc.Config(block_s=100.05)


def test_bad_config_return_ramp_kind():
    with pytest.raises(TypeError, match=r"Config.return_ramp must be a bool; got 1"):
        sc.Config(return_ramp=1)


def test_bad_program_fewer_blocks_than_regressors():
    """A chamber program shorter than 13 blocks of 100 s cannot fit 11 candidates: a clear error."""
    c = sc.Config(high_c=-38.0, power_on_soak_min=1.0, high_soak_min=1.0, end_soak_min=1.0)
    with pytest.raises(
        ValueError, match=r"more observations than regressors.*n_samples = 9, n_features = 11"
    ):
        sc.experiment(c, 0)


# ----------------------------------------------------------------------------- population (slow)
@pytest.mark.slow
def test_twenty_units_every_claim_testable():
    """20 units (seeds 0-19, ~3 s each): every paper claim is testable on every unit with the thermal
    effect (significance F where stepwise selects a term), and a rerun
    of the evaluation from the same units gives the same counts."""
    us = [sc.experiment(sc.Config(), s) for s in range(20)]
    res = evaluate(sc.CLAIMS, [u.quantities for u in us])
    hop_ids = {"004.mode_hops_lower_adj_r2", "004.mode_hops_lower_improvement"}
    present = [u for u in us if sc.THERMAL_PRECONDITION.present_in(u.quantities)]  # both conditions
    empty = sum(not u.model.selected for u in present)  # significance F needs a selected term
    for r in res:
        if r.claim.id in hop_ids:
            continue
        untestable = empty if r.claim.id == "004.significance_f" else 0
        assert r.testable + r.precondition_absent + untestable == 20, r.claim.id
    # units that never hop cannot test the hop claims
    again = evaluate(sc.CLAIMS, [u.quantities for u in us])
    assert [r.holds for r in res] == [r.holds for r in again]
    o = sc.report(sc.Config(), us, res)
    assert len(o.results["unit_rows"]) == 20
    assert all(math.isfinite(r["cross_unit_ratio"]) for r in o.results["unit_rows"])


def test_triples_group_consecutive_units_and_judge_the_mean_improvement(three_units):
    """Three units make one triple; its ratio is 1 / (1 - mean improvement); four units still one."""
    from gyrobench.scenarios.papers.p004_rlg_thermal.triples import judge_triples

    t = judge_triples(three_units)
    assert t.seeds == (0,)
    present = all(sc.THERMAL_PRECONDITION.present_in(u.quantities) for u in three_units)
    assert (t.testable, t.precondition_absent) == ((1, 0) if present else (0, 1))
    if present:
        gains = [1.0 - 1.0 / u.quantities["heldout_ratio"] for u in three_units]
        assert t.ratios[0] == pytest.approx(1.0 / (1.0 - sum(gains) / 3.0), rel=1e-12)
        assert min(u.quantities["heldout_ratio"] for u in three_units) <= t.ratios[0]
        assert t.ratios[0] <= max(u.quantities["heldout_ratio"] for u in three_units)
    assert judge_triples(three_units[:2]).seeds == ()
    assert judge_triples([*three_units, three_units[0]]).seeds == (0,)


def test_report_gives_the_triples(outcome):
    t = outcome.results["triples_65pct"]
    assert t["claim"] == "004.improvement_65pct" and t["triples"] == 1
    assert "triples of units" in outcome.conclusion
