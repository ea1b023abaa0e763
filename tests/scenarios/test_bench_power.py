"""Power before the run and primary scores.

The smallest attainable p of a distribution-free paired test and the seeds needed are checked
against scipy's exact signed-rank distribution (its all-one-sign extreme, not the formula
retyped); the seed count for a shift is checked by simulating the gate's own test with a
binomial bound at a false-alarm rate of 1e-3.
"""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest
from scipy import stats

from gyrobench.scenarios import bench
from gyrobench.scenarios.bench import power
from gyrobench.scenarios.bench.gate import plan_power
from gyrobench.scenarios.bench.primary import declared_scores
from gyrobench.scenarios.cli import exits
from gyrobench.scenarios.cli.main import main
from tests.scenarios import toy_scenario as toy

#: every bench scenario's declared scores (each paper's BENCH_SCORES, found through the registry)
SCENARIO_SCORES = declared_scores()

TOY = "tests.scenarios.toy_scenario"


def _exact_min_p(n: int) -> float:
    """scipy's exact two-sided signed-rank p of n differences all positive (distinct ranks)."""
    return float(stats.wilcoxon(np.arange(1.0, n + 1), method="exact").pvalue)


@pytest.mark.parametrize("n", [3, 5, 8, 12])
@pytest.mark.parametrize("m", [1, 2, 24])
def test_min_attainable_p_is_scipys_exact_extreme_times_holm(n, m):
    assert power.min_attainable_p(n, m) == pytest.approx(min(1.0, m * _exact_min_p(n)), rel=1e-12)


@pytest.mark.parametrize("alpha", [0.05, 0.01])
@pytest.mark.parametrize("m", [1, 2, 3, 24])
def test_seeds_needed_is_the_fewest_seeds_that_reach_alpha(m, alpha):
    n = power.seeds_needed(m, alpha)
    assert m * _exact_min_p(n) < alpha <= m * _exact_min_p(n - 1)


def test_issue_figures_ifog_with_24_scores_on_8_seeds_is_refused():
    """The issue's figure: 24 scores on 8 seeds reach no lower than 0.188."""
    with pytest.raises(power.UnderpoweredError, match=r"24 x 2/2\^8 = 0.188 >= alpha 0.05.*at least 10 seeds"):
        power.check_power(8, 24, 0.05)
    assert power.check_power(10, 24, 0.05) == ""
    warning = power.check_power(8, 24, 0.05, allow_underpowered=True)
    assert warning.startswith("WARNING: underpowered:") and "\n" not in warning


def test_seeds_for_change_detects_the_shift_with_the_stated_power():
    """Normal per-seed contrasts with a mean shift of 0.6 sigma beyond the margin, one of m = 2
    primary scores: the gate's own test (margin_test, Holm's first step alpha/m) rejects in a
    fraction of 2000 simulated campaigns of the computed size that lies between the power the
    formula gives one seed fewer (< 0.8) and at that size (>= 0.8), each within the binomial's
    3.1 std (false alarm 1e-3; std <= 0.011): the noncentral t is exact for normal contrasts, so
    the count is neither short nor wasteful."""
    from gyrobench.scenarios.bench.margin import margin_test

    m, alpha, delta, margin = 2, 0.05, 0.6, 0.1
    n = power.seeds_for_change(1.0, delta, m, alpha)
    rng = np.random.default_rng(20261127)
    b = np.full(n, 10.0)  # the margin's edge is then 1.0 above b on every seed
    hits = 0
    for _ in range(2000):
        d = margin * b + delta + rng.standard_normal(n)
        p, sign = margin_test(d, b, -1, margin)
        hits += bool(m * p < alpha and sign > 0)
    rate = hits / 2000
    tol = 3.1 * math.sqrt(0.25 / 2000)
    assert power.detection_power(1.0, delta, n - 1, m, alpha) < power.DEFAULT_POWER
    assert power.detection_power(1.0, delta, n - 1, m, alpha) - tol <= rate, (n, rate)
    assert rate <= power.detection_power(1.0, delta, n, m, alpha) + tol, (n, rate)
    assert rate >= power.DEFAULT_POWER - 3.1 * math.sqrt(0.8 * 0.2 / 2000), (n, rate)


def test_std_upper_bound_covers_a_normal_spread_at_its_confidence():
    """Normal samples of 16: the one-sided 95 % bound is at or above the true std in >= 95 % of
    1000 samples, within the binomial's 3.1 std (false alarm 1e-3: 0.021); it is above the
    sample std, and relatively wider for a sample with a far outlier than without it."""
    rng = np.random.default_rng(20261202)
    x = rng.standard_normal((1000, 16))
    bounds = np.array([power.std_upper_bound(row) for row in x])
    rate = float(np.mean(bounds >= 1.0))
    assert rate >= power.SPREAD_CONFIDENCE - 3.1 * math.sqrt(0.95 * 0.05 / 1000), rate
    assert np.all(bounds > x.std(axis=1, ddof=1))
    calm = x[0].copy()
    wild = calm.copy()
    wild[0] = calm.mean() + 6 * calm.std(ddof=1)
    assert power.std_upper_bound(wild) / np.std(wild, ddof=1) > power.std_upper_bound(calm) / np.std(calm, ddof=1)
    assert power.std_upper_bound([1.0]) != power.std_upper_bound([1.0])  # NaN: one value has no spread
    assert power.std_upper_bound([2.0, 2.0, 2.0]) == 0.0


def _auto_power(rng, sizing, runs, min_change):
    """Fraction of ``runs`` campaigns that detect a change of twice ``min_change`` when each is
    sized by --seeds auto from its own 16-seed baseline of a lognormal score (shape 1: kurtosis
    114, the seed-to-seed spread of a score with rare bad seeds). ``sizing(values)`` gives the
    spread the sizing uses. Each campaign: baseline b_s and candidate
    c_s = (1 + m) b_s + m mu + sigma e_s (e normal), whose per-seed differences beyond the margin
    are as spread as the score's seeds (sigma, mu: the lognormal's std and mean), the sizing's
    assumption; the gate's own test (margin_test) decides."""
    from gyrobench.scenarios.bench.margin import margin_test

    mu, sigma = math.exp(0.5), math.sqrt((math.e - 1) * math.e)
    hits = 0
    for _ in range(runs):
        base = rng.lognormal(0.0, 1.0, 16)
        spreads = {"mean/rms": (float(base.mean()), float(base.std(ddof=1)), sizing(base))}
        n = power.auto_seeds(1, 0.05, spreads=spreads, min_change=min_change).n
        b = rng.lognormal(0.0, 1.0, n)
        c = (1 + min_change) * b + min_change * mu + sigma * rng.standard_normal(n)
        p, sign = margin_test(c - b, b, -1, min_change)
        hits += bool(p < 0.05 and sign > 0)
    return hits / runs


def test_seeds_auto_from_a_small_heavy_tailed_baseline_reaches_the_nominal_power():
    """--seeds auto sized from 16 seeds of a heavy-tailed score (see _auto_power) detects twice the
    margin (a 40 % change at a 20 % margin, so that the campaigns stay short) in >= 80 % of 400
    campaigns, within the binomial's 3.1 std at power 0.8 (false alarm 1e-3: 0.062; measured
    0.905). Sized from the sample std instead it falls short by more than that (measured 0.64:
    the simulation tells a rule that underestimates the spread)."""
    rng = np.random.default_rng(20261203)
    tol = 3.1 * math.sqrt(0.8 * 0.2 / 400)
    bound = _auto_power(rng, power.std_upper_bound, 400, 0.2)
    sample = _auto_power(rng, lambda v: float(np.std(v, ddof=1)), 400, 0.2)
    assert bound >= power.DEFAULT_POWER - tol, (bound, sample)
    assert sample < power.DEFAULT_POWER - tol, (bound, sample)


def test_hodges_lehmann_of_a_long_campaign_is_the_median_of_its_walsh_averages():
    """Beyond 3000 seeds the shift is found without forming the averages: the same value as the
    formed averages' median, also when most differences are exactly zero (a compensator worse
    on some seeds only), where the plain median is 0."""
    from gyrobench.scenarios.bench.statistics import hodges_lehmann

    rng = np.random.default_rng(20261204)
    d = np.where(rng.random(3001) < 0.55, 0.0, rng.lognormal(0.0, 1.0, 3001))
    i, j = np.triu_indices(d.size)
    assert np.median(d) == 0.0
    assert hodges_lehmann(d) == pytest.approx(float(np.median((d[i] + d[j]) / 2)), rel=1e-12, abs=1e-15)
    assert hodges_lehmann(d) > 0


@pytest.mark.parametrize("n", [6, 10, 40])
def test_detectable_change_is_the_inverse_of_seeds_for_change(n):
    change = power.detectable_change(2.0, n, 1, 0.05)
    assert power.seeds_for_change(2.0, change * 1.000001, 1, 0.05) <= n
    assert power.seeds_for_change(2.0, change * 0.9, 1, 0.05) > n or n == power.seeds_needed(1, 0.05)
    assert power.detectable_change(2.0, 3, 1, 0.05) == math.inf  # 2/2^3 >= 0.05: nothing


def test_every_declared_primary_score_is_a_mean_score_with_a_unit():
    for name, declared in SCENARIO_SCORES.items():
        assert 1 <= len(declared.primary) <= 2, name
        for p in declared.primary:
            assert p.name.startswith("mean/") and p.unit and p.direction in (-1, 1), (name, p)


@pytest.mark.parametrize("scenario", ["ifog_thermal", "rlg_thermal", "mems_scale_factor"])
def test_declared_primary_scores_are_what_the_scenario_scores(scenario):
    """Robust to the held-out runs' names (rlg_thermal's 'unit7_heldout' or 'heldout'): the
    primary scores are the means, held by every seed."""
    scores = bench.score_seed(scenario, bench.Uncompensated(), 0)
    for p in SCENARIO_SCORES[scenario].primary:
        assert math.isfinite(scores[p.name]), p.name


@pytest.mark.slow
def test_fog_vibration_primary_scores_are_what_it_scores(shared_tasks):
    scores = bench.score_seed("fog_vibration", bench.Uncompensated(), 0)
    assert all(math.isfinite(scores[p.name]) for p in SCENARIO_SCORES["fog_vibration"].primary)


def test_uncompensated_scores_the_raw_output_for_error_and_rate_targets():
    """The reference is the task's scorer on each held-out run's output as it is."""
    task = toy.compensation_task(toy.Config(), 3)
    want = [toy.scorer(run.output, run) for run in task.heldout]
    got = bench.score_seed(toy, bench.UNCOMPENSATED, 3)
    for run, w in zip(task.heldout, want, strict=True):
        assert all(got[f"{run.label}/{k}"] == v for k, v in w.items())
    module = bench.resolve_scenario("mems_scale_factor")  # target "rate": compensated = output
    task = module.compensation_task(module.Config(), 0)
    got = bench.score_seed(module, bench.Uncompensated, 0)
    rms = [math.sqrt(np.mean((run.output - run.truth) ** 2)) for run in task.heldout]
    assert got["mean/rms_dps"] == pytest.approx(np.mean(rms), rel=1e-12)


def _campaign(scenario, values):
    return bench.Campaign(campaign_id="x", scenario=scenario, compensator="c", config="", scores=values)


def test_only_primary_scores_are_gated():
    """rlg_thermal: a secondary score worse on all 12 seeds is reported, not gated; the primary
    worse on all 12 fails the comparison."""
    base = {s: {"mean/bias_stability_deg_h": 1.0 + s, "mean/improvement_pct": 20.0 + s} for s in range(12)}
    sec = {s: {"mean/bias_stability_deg_h": 1.0 + s, "mean/improvement_pct": 10.0 + s} for s in range(12)}
    r = bench.compare(_campaign("rlg_thermal", base), _campaign("rlg_thermal", sec))
    assert r.passed and not r.regressions and [s.name for s in r.secondary_regressions] == ["mean/improvement_pct"]
    assert "Holm over the 1 primary score(s)" in r.format() and "reported, not gated" in r.format()
    prim = {s: {"mean/bias_stability_deg_h": 2.0 + s, "mean/improvement_pct": 20.0 + s} for s in range(12)}
    r = bench.compare(_campaign("rlg_thermal", base), _campaign("rlg_thermal", prim))
    assert not r.passed and [s.name for s in r.regressions] == ["mean/bias_stability_deg_h"]
    assert r.regressions[0].unit == "deg/h" and r.regressions[0].p_adjusted == pytest.approx(_exact_min_p(12))


def test_a_missing_primary_score_cannot_be_judged():
    base = {s: {"mean/improvement_pct": 20.0 + s} for s in range(12)}
    with pytest.raises(bench.ComparisonError, match="primary score.*mean/bias_stability_deg_h.*cannot be judged"):
        bench.compare(_campaign("rlg_thermal", base), _campaign("rlg_thermal", base))


def test_plan_power_without_baseline_says_what_it_assumed():
    plan = plan_power("ifog_thermal", "auto", baseline=None, alpha=0.05, gate=True)
    assert plan.seeds == tuple(range(power.seeds_needed(1, 0.05))) == tuple(range(6))
    assert "assumed a change larger than the seed-to-seed spread" in plan.auto
    plan = plan_power("mems_scale_factor", "auto", baseline=None, alpha=0.05, gate=True)
    assert len(plan.seeds) == power.seeds_needed(2, 0.05) == 7


def test_plan_power_refuses_before_computing_and_names_the_seeds():
    with pytest.raises(power.UnderpoweredError, match=r"at least 7 seeds \(--seeds 0:7\)"):
        plan_power("mems_scale_factor", tuple(range(5)), baseline=None, alpha=0.05, gate=True)
    plan = plan_power("mems_scale_factor", tuple(range(5)), baseline=None, alpha=0.05, gate=False)
    assert plan.warning == "" and plan.seeds == tuple(range(5))  # a summary alone is not a gate


@pytest.fixture(scope="module")
def toy_baseline(tmp_path_factory):
    d = tmp_path_factory.mktemp("power")
    camp = bench.run_campaign(toy, toy.good, range(16), workers=0, db=d / "b.db", progress=False)
    return bench.save_baseline(d / "good.json", camp)


def _bench(argv, capsys):
    code = main(["bench", TOY, "--workers", "0", "--quiet", *argv])
    cap = capsys.readouterr()
    return code, cap.out, cap.err.splitlines()


def test_cli_refuses_an_underpowered_comparison_in_one_line(tmp_path, capsys, toy_baseline):
    """The toy gates 3 mean scores: 5 seeds reach 3 x 2/2^5 = 0.19; refused, nothing computed."""
    db = tmp_path / "c.db"
    argv = ["--compensator", f"{TOY}:degraded", "--baseline", str(toy_baseline), "--seeds", "0:5", "--db", str(db)]
    code, out, err = _bench(argv, capsys)
    assert code == exits.BAD_INPUT and out == "" and not db.exists()
    assert len(err) == 1 and "3 x 2/2^5 = 0.188 >= alpha 0.05" in err[0] and "at least 7 seeds" in err[0]
    code, out, err = _bench([*argv, "--allow-underpowered"], capsys)
    assert code == exits.OK, err  # the degraded compensator passes: this gate cannot fail
    assert out.splitlines()[0].startswith("WARNING: underpowered:") and "cannot fail" in out.splitlines()[0]


@pytest.mark.slow
def test_cli_seeds_auto_from_the_baseline_catches_the_degraded_compensator(tmp_path, capsys):
    """--seeds auto sizes the run to detect twice the --min-change margin from the baseline's
    seed-to-seed spread plus that of a change carried by half the seeds (which alone asks for
    about 45 seeds whatever the margin): a 100 % margin (a 200 % change; the degraded compensator
    is 15-420 times worse) needs fewer seeds than a 64-seed baseline holds and the run catches the
    degraded compensator; a 10 % margin asks for more: refused in one line naming them, nothing
    simulated."""
    camp = bench.run_campaign(toy, toy.good, range(64), workers=0, db=tmp_path / "g.db", progress=False)
    baseline = bench.save_baseline(tmp_path / "good.json", camp)

    def auto(min_change, db):
        argv = ["--compensator", f"{TOY}:degraded", "--baseline", str(baseline), "--seeds", "auto"]
        return _bench([*argv, "--min-change", min_change, "--db", str(tmp_path / db)], capsys)

    code, out, err = auto("1.0", "a.db")
    first = out.splitlines()[0] if out else ""
    sized = re.match(r"--seeds auto: (\d+) seeds detect a 200 % change \(twice the 100 % margin\) of mean/", first)
    assert sized and "seed-to-seed std" in first and "95 % upper bound" in first, (first, err)
    n = int(sized.group(1))
    assert power.seeds_needed(3, 0.05) <= n <= 64
    assert code == exits.REGRESSION and f"over {n} matching seeds" in out
    code, out, err = auto("0.1", "b.db")
    assert code == exits.BAD_INPUT and len(err) == 1, err
    assert re.search(r"--seeds auto: (\d+) seeds detect a 20 % change .*the baseline holds only 64 seeds: "
                     r"re-save it on --seeds 0:\1$", err[0]), err
    assert not (tmp_path / "b.db").exists()  # refused before simulating


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_cli_prints_units_and_the_uncompensated_reference(tmp_path, capsys, toy_baseline):
    argv = ["--compensator", f"{TOY}:good", "--baseline", str(toy_baseline), "--db", str(tmp_path / "c.db")]
    code, out, err = _bench(argv, capsys)
    assert code == exits.OK, err
    head = next(line for line in out.splitlines() if line.startswith("score ") and "status" in line)
    assert head.split()[:4] == ["score", "gate", "unit", "status"] and "uncompensated" in head
    row = next(line for line in out.splitlines() if line.startswith("mean/mse ") and "unchanged" in line)
    uncompensated = bench.run_campaign(toy, bench.UNCOMPENSATED, range(16), workers=0, db=tmp_path / "c.db",
                                       progress=False)
    assert f"{np.mean(uncompensated.values('mean/mse')):.6g}" in row.split()
    assert "Holm over the 3 primary score(s)" in out and "not gated" in out


def test_baseline_file_stores_what_it_can_detect(toy_baseline):
    doc = json.loads(toy_baseline.read_text())["power"]
    assert doc["seeds"] == 16 and set(doc["detectable"]) == {"mean/mse", "mean/rms", "mean/bias_stability"}
    camp = bench.load_baseline(toy_baseline)
    assert doc["spread_confidence"] == power.SPREAD_CONFIDENCE
    for name, d in doc["detectable"].items():
        mean, std = power.spread(camp.values(name))
        assert d["std"] == pytest.approx(std) and d["std_upper"] > std
        assert d["std_upper"] == pytest.approx(power.std_upper_bound(camp.values(name)))
        # the change half the seeds carry adds its own spread (power.partial_spread): a fixed point
        total = doc["margin"] + d["change"] / mean
        spread = power.partial_spread(d["std_upper"], mean, total)
        assert d["change"] == pytest.approx(power.detectable_change(spread, 16, 3, 0.05), rel=1e-6)
        assert d["change"] > power.detectable_change(d["std_upper"], 16, 3, 0.05)
        assert d["relative"] == pytest.approx(d["change"] / mean)


def five_percent_scale_error(X, y):
    """A compensator for a "rate" target (mems_scale_factor: X = the output) that returns the
    output 5 % too small: the identified device compresses high rates, so this moves every
    reading further from the truth, clearly worse than no compensation on the RMS rate error
    (5 % too large would partly undo the compression and score better)."""
    return lambda Xn: 0.95 * np.asarray(Xn, dtype=float)[:, 0]


def a_200_deg_h_offset(X, y):
    """A compensator that predicts a constant 200 deg/h error: on the part scenario (dsp-1760 on its
    physics, held-out error rms about 50 deg/h, mean near zero) it leaves about 200 deg/h on every
    seed, clearly worse than no compensation."""
    return lambda Xn: np.full(len(Xn), 200.0)


LS = "sklearn.linear_model:LinearRegression"
SCALED = "tests.scenarios.test_bench_power:five_percent_scale_error"
OFFSET = "tests.scenarios.test_bench_power:a_200_deg_h_offset"

#: scenario -> (the compensator of the baseline, a clearly worse one, --min-change, baseline seeds).
#: On mems_scale_factor least squares is not reliably better than no compensation (the held-out
#: runs' scale factor differs from the fitting runs'): there the uncompensated output is the
#: baseline. On fog_vibration a straight line in (frequency, acceleration) cannot follow the
#: resonant vibration bias (worse than none on 9 of seeds 0-9): the baseline is the paper's RBF
#: on frequency bins, 3.8x-20x better than no compensation on each of seeds 0-9.
GATE_CASES = {
    "ifog_thermal": (LS, bench.UNCOMPENSATED, 0.2, 16),
    "rlg_thermal": (LS, bench.UNCOMPENSATED, 0.2, 16),
    "mems_scale_factor": (bench.UNCOMPENSATED, SCALED, 2.0, 16),
    "fog_vibration": (SCENARIO_SCORES["fog_vibration"].paper, bench.UNCOMPENSATED, 1.0, 10),
    # your own part (the default dsp-1760 on its physics): a linear fit in (T, dT, rate, g) is worse
    # than none on its held-out program (111 against 53 deg/h), so no compensation is the baseline
    "part": (bench.UNCOMPENSATED, OFFSET, 1.0, 10),
}


@pytest.mark.slow
@pytest.mark.parametrize("scenario", sorted(SCENARIO_SCORES))
def test_every_scenario_unchanged_passes_and_a_worse_one_fails(scenario, tmp_path, capsys, shared_tasks):
    """Over every bench scenario: a compensator against its own baseline exits 0 on 3 seeds
    (allowed underpowered, with the warning first); a clearly worse one exits 1 on the baseline's
    seeds. (On the identified devices --seeds auto asks more seeds than these baselines hold for
    a 20 % change, e.g. 101 on rlg_thermal, and refuses in one line; its choice is tested on the toy.)"""
    good, worse, _min_change, n_base = GATE_CASES[scenario]
    shared_tasks(scenario, range(n_base))  # three runs over these seeds: one simulation each (conftest)
    base, db = str(tmp_path / "b.json"), str(tmp_path / "c.db")
    common = ["--workers", "0", "-q", "--db", db, "--no-references"]
    argv = ["bench", scenario, "--compensator", good, *common, "--seeds", f"0:{n_base}", "--save-baseline", base]
    assert main(argv) == 0
    capsys.readouterr()
    code = main(["bench", scenario, "--compensator", good, *common, "--seeds", "0:3", "--baseline", base,
                 "--allow-underpowered"])
    out = capsys.readouterr().out
    assert code == exits.OK and out.startswith("WARNING: underpowered:") and "FAILED" not in out
    code = main(["bench", scenario, "--compensator", worse, *common, "--seeds", f"0:{n_base}", "--baseline", base])
    cap = capsys.readouterr()
    assert code == exits.REGRESSION, cap.out + cap.err
    assert "REGRESSION" in cap.out and "FAILED" not in cap.out


def test_a_paper_reference_that_fails_is_left_out_with_a_warning(tmp_path, monkeypatch):
    """The reference columns never fail the user's run: a paper method that raises is skipped."""
    from gyrobench.scenarios.bench.primary import PrimaryScore, ScenarioScores

    declared = ScenarioScores(
        primary=(PrimaryScore(name="mean/rms", unit="deg/h", direction=-1),),
        units={"rms": "deg/h"},
        paper=f"{TOY}:fit_returning_nonsense",
        paper_label="broken paper",
    )
    monkeypatch.setattr(toy, "BENCH_SCORES", declared, raising=False)
    with pytest.warns(UserWarning, match="reference broken paper .* not shown"):
        refs = bench.reference_campaigns(toy, range(2), workers=0, db=tmp_path / "r.db")
    assert list(refs) == ["uncompensated"]


def _t1_only():
    from sklearn.compose import ColumnTransformer
    from sklearn.linear_model import LinearRegression
    from sklearn.pipeline import make_pipeline

    return make_pipeline(ColumnTransformer([("T1", "passthrough", [0])]), LinearRegression())


#: rlg_thermal's least squares on the first regressor only (x1) instead of all eleven: a partial
#: regression, not "no compensation". Over seeds 0-15 the held-out improvement falls from 28.0 %
#: to 7.0 % (the issue's "28.4 % -> 7.0 %"), the bias stability rises on 16 of 16 seeds.
rlg_x1_only = _t1_only()


@pytest.mark.slow
def test_rlg_thermal_partial_regression_exits_1(tmp_path, capsys, shared_tasks):
    shared_tasks("rlg_thermal", range(16))  # two runs and the references over these seeds (conftest)
    base, db = str(tmp_path / "b.json"), str(tmp_path / "c.db")
    common = ["--workers", "0", "-q", "--db", db]
    assert main(["bench", "rlg_thermal", "--compensator", LS, *common, "--seeds", "0:16", "--save-baseline", base]) == 0
    capsys.readouterr()
    worse = f"{__name__}:rlg_x1_only"
    code = main(["bench", "rlg_thermal", "--compensator", worse, *common, "--seeds", "0:16", "--baseline", base])
    out = capsys.readouterr().out
    assert code == exits.REGRESSION, out
    assert "REGRESSION: 1 of 1 primary score(s) significantly worse: mean/bias_stability_deg_h" in out
    assert "least squares on x1..x11 (paper)" in out and "uncompensated" in out
