"""Tests of scenarios/claims.py: Wilson interval (pinned to a published table), comparators,
verdicts, and evaluation over units with untestable (None / NaN) quantities."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gyrobench.scenarios import claims as cl
from gyrobench.scenarios.claims import (
    Claim,
    Precondition,
    above,
    below,
    evaluate,
    in_range,
    is_true,
    tally,
    within_factor,
)


# ----------------------------------------------------------------------------- Wilson interval
@pytest.mark.parametrize(
    "k, n, lo, hi",
    [
        # Newcombe, Stat. Med. 17, 857 (1998), Table I, method 3 (score, no continuity
        # correction), printed to 4 decimals
        (81, 263, 0.2553, 0.3662),
        (15, 148, 0.0624, 0.1605),
        (0, 20, 0.0, 0.1611),
        (1, 29, 0.0061, 0.1718),
    ],
)
def test_wilson_interval_matches_newcombe_table_1(k, n, lo, hi):
    got = cl.wilson_interval(k, n)
    assert got == pytest.approx((lo, hi), abs=0.5e-4)  # the table's rounding


def test_wilson_interval_closed_form_and_symmetry():
    # k/n = 1/2: centred on 1/2, half-width z sqrt(1/4n + z^2/4n^2) / (1 + z^2/n)
    z, n = 1.959963984540054, 20
    lo, hi = cl.wilson_interval(10, n)
    half = z * math.sqrt(0.25 / n + z * z / (4 * n * n)) / (1 + z * z / n)
    assert (lo, hi) == pytest.approx((0.5 - half, 0.5 + half), rel=1e-14)
    # k <-> n - k mirrors the interval about 1/2
    for k in range(n + 1):
        a, b = cl.wilson_interval(k, n)
        c, d = cl.wilson_interval(n - k, n)
        assert (a, b) == pytest.approx((1 - d, 1 - c), abs=1e-15)


@pytest.mark.parametrize("n", range(1, 60))
def test_wilson_interval_ends_are_exact_at_zero_and_all(n):
    assert cl.wilson_interval(0, n)[0] == 0.0
    assert cl.wilson_interval(n, n)[1] == 1.0
    if n > 1:
        lo, hi = cl.wilson_interval(n // 2, n)
        assert 0.0 < lo < hi < 1.0


@pytest.mark.parametrize(
    "k, n, match",
    [
        (0, 0, "n must be an integer > 0"),
        (3, 2, r"k must be an integer in \[0, n=2\]"),
        (-1, 5, "k must be"),
        (1.0, 5, "k must be"),
        (True, 5, "k must be"),
        (1, True, "n must be"),
    ],
)
def test_wilson_interval_refuses_bad_counts(k, n, match):
    with pytest.raises(ValueError, match=match):
        cl.wilson_interval(k, n)


# ----------------------------------------------------------------------------- verdicts
def test_verdict_thresholds_at_20_units():
    # lower Wilson end crosses 50 % between 14/20 (0.481) and 15/20 (0.531)
    assert cl.wilson_interval(14, 20)[0] < 0.5 < cl.wilson_interval(15, 20)[0]
    assert cl.verdict(15, 20) == "holds for most units"
    assert cl.verdict(14, 20) == "undecided"
    assert cl.verdict(10, 20) == "undecided"
    # upper end crosses 50 % between 5/20 (0.469) and 6/20 (0.519)
    assert cl.verdict(6, 20) == "undecided"
    assert cl.verdict(5, 20) == "fails for most units"
    assert cl.verdict(0, 0) == "not testable"


def test_few_units_never_decide():
    # one unit's yes/no is never a verdict (1/1: [0.21, 1]); all of n units hold needs n >= 4
    assert cl.verdict(1, 1) == "undecided" and cl.verdict(0, 1) == "undecided"
    assert cl.verdict(3, 3) == "undecided"  # lower end 0.439
    assert cl.verdict(4, 4) == "holds for most units"  # lower end 0.510
    assert cl.verdict(0, 4) == "fails for most units"


# ----------------------------------------------------------------------------- comparators
def test_within_factor_is_two_sided_and_inclusive():
    c = within_factor(15.71, 2)
    assert (c.lo, c.hi) == (15.71 / 2, 15.71 * 2)
    assert c.holds(15.71 / 2) and c.holds(15.71 * 2) and c.holds(15.71)
    assert not c.holds(np.nextafter(15.71 / 2, 0)) and not c.holds(np.nextafter(31.42, 99))
    assert c.text("%") == "within 2x of 15.71 % (7.855 to 31.42)"


def test_in_range_above_below_is_true():
    r = in_range(3, 30)
    assert r.holds(3) and r.holds(30) and not r.holds(2.999) and not r.holds(30.01)
    a, b = above(0.2), below(0.2)
    assert a.holds(0.2001) and not a.holds(0.2)  # strict: "more than 0.2"
    assert b.holds(0.1999) and not b.holds(0.2)
    assert a.text("deg/h") == "> 0.2 deg/h" and b.text() == "< 0.2"
    t = is_true()
    assert t.holds(1.0) and not t.holds(0.0)
    assert r.text() == "between 3 and 30"


@pytest.mark.parametrize(
    "make, match",
    [
        (lambda: within_factor(0.0), "within_factor value must be finite and > 0; got 0.0"),
        (lambda: within_factor(-1.0), "value must be finite and > 0"),
        (lambda: within_factor(math.nan), "value must be finite and > 0"),
        (lambda: within_factor(1.0, 1.0), "factor must be finite and > 1; got 1.0"),
        (lambda: in_range(30, 3), "in_range needs lo < hi; got lo=30, hi=3"),
    ],
)
def test_comparators_refuse_bad_bounds(make, match):
    with pytest.raises(ValueError, match=match):
        make()


def _claim(**kw) -> Claim:
    base = dict(
        id="x.q",
        paper="001",
        where="Table 1",
        statement="q is about 2.",
        kind="emergent",
        quantity="q",
        comparator=within_factor(2.0),
        paper_value=2.0,
    )
    base.update(kw)
    return Claim(**base)


def test_claim_kind_and_calibrated_input_go_together():
    with pytest.raises(ValueError, match=r"Claim.kind must be one of \['calibrated', 'emergent'\]; got 'tuned'"):
        _claim(kind="tuned")
    with pytest.raises(ValueError, match="calibrated_input must be given exactly when"):
        _claim(kind="calibrated")
    with pytest.raises(ValueError, match="calibrated_input must be given exactly when"):
        _claim(calibrated_input="Config.x set from Table 1")
    assert _claim(kind="calibrated", calibrated_input="Config.x from Table 1").kind == "calibrated"


# ----------------------------------------------------------------------------- evaluate
def test_evaluate_counts_testable_units_and_skips_none_nan_missing():
    c = _claim()
    units = [
        {"q": 2.0},
        {"q": None},
        {"q": math.nan},
        {},
        {"q": 5.0},
        {"q": np.float64(1.0)},
        {"q": math.inf},
        {"q": 3.9},
    ]
    (r,) = evaluate([c], units)
    # inf is a value (a ratio over a zero denominator: the quantity is there on one side only), so it
    # is judged (and fails "< 4" here); None, NaN and a missing key cannot test the claim
    assert (r.units, r.testable, r.holds) == (8, 5, 3)  # 2.0, 1.0, 3.9 hold; 5.0 and inf fail
    assert r.pass_rate == 0.6
    assert r.interval95 == cl.wilson_interval(3, 5)
    assert r.median == pytest.approx(np.median([2.0, 5.0, 1.0, 3.9, math.inf]))
    assert r.spread == pytest.approx((np.percentile([2, 5, 1, 3.9, 1e300], 25), 5.0))
    assert r.verdict == "undecided"


def test_evaluate_booleans_and_untestable_claim():
    t = _claim(id="x.t", quantity="t", comparator=is_true(), paper_value=None)
    u = _claim(id="x.u", quantity="u")
    units = [{"t": True, "u": None}, {"t": 1.0, "u": math.nan}, {"t": np.bool_(False)}, {"t": 1}]
    rt, ru = evaluate([t, u], units)
    assert (rt.testable, rt.holds) == (4, 3)
    assert (ru.testable, ru.holds, ru.pass_rate, ru.interval95, ru.median, ru.spread) == (
        0,
        0,
        None,
        None,
        None,
        None,
    )
    assert ru.verdict == "not testable"
    d = ru.as_dict()
    assert d["interval95"] is None and d["pass_rate"] is None and d["verdict"] == "not testable"


def test_evaluate_refuses_a_quantity_that_is_not_a_number():
    with pytest.raises(
        TypeError, match="claim 'x.q': a unit's quantity must be a number, None or NaN; got str"
    ):
        evaluate([_claim()], [{"q": 1.0}, {"q": "1.0"}])


def test_as_dict_has_the_results_json_keys():
    c = _claim(kind="calibrated", calibrated_input="Config.x from Table 1", unit="%")
    (r,) = evaluate([c], [{"q": v} for v in (1.5, 2.5, 3.0, 9.0)])
    d = r.as_dict()
    need = {
        "id",
        "paper",
        "where",
        "statement",
        "kind",
        "calibrated_input",
        "paper_value",
        "comparator",
        "units",
        "testable",
        "holds",
        "pass_rate",
        "interval95",
        "median",
        "spread",
    }
    assert need <= set(d)
    assert d["comparator"] == "within 2x of 2 % (1 to 4)"
    assert (d["units"], d["testable"], d["holds"]) == (4, 4, 3)
    assert d["interval95"] == list(cl.wilson_interval(3, 4))
    assert d["spread"] == [r.spread[0], r.spread[1]]


def test_finite_median_skips_untestable_units():
    import math

    from gyrobench.scenarios.claims import finite_median

    assert finite_median([3.0, None, float("nan"), 1.0, float("inf"), 2.0]) == 2.0
    assert math.isnan(finite_median([None, float("nan")]))


# ---------------------------------------------------------------------------- roles, preconditions, control
def _units(values, key="q"):
    return [{key: float(v)} for v in values]


def test_precondition_absent_units_are_not_fails():
    pre = Precondition(text="the unit shows the effect", quantity="effect", comparator=above(3.0))
    c = Claim(id="x.m", paper="001", where="s", statement="t", kind="emergent", quantity="q",
              comparator=above(1.0), precondition=pre)
    units = [{"q": 2.0, "effect": 5.0}, {"q": 0.0, "effect": 5.0}, {"q": 0.0, "effect": 1.0},
             {"q": 2.0, "effect": None}]
    (r,) = evaluate([c], units)
    assert (r.units, r.testable, r.holds, r.precondition_absent) == (4, 2, 1, 2)
    assert not r.precondition_mostly_absent  # 2 of 4 is not most
    (r,) = evaluate([c], units + [{"q": 2.0, "effect": 0.0}])
    assert r.precondition_mostly_absent and r.status == "not reproducible on this device"


def test_control_overlap_makes_an_identity_and_separation_a_finding():
    c = Claim(id="x.i", paper="001", where="s", statement="t", kind="emergent", quantity="q", comparator=is_true())
    units = _units([1.0] * 20)
    (same,) = evaluate([c], units, _units([1.0] * 17 + [0.0] * 3))
    # 20/20 vs 17/20: Fisher's exact two-sided p = 0.23 (hypergeometric, margins 37 / 3)
    assert same.verdict == "holds for most units" and same.identity and same.status == "no different from the control"
    assert same.control_p_value == pytest.approx(0.2307692307, rel=1e-6)
    (apart,) = evaluate([c], units, _units([0.0] * 20))
    assert not apart.identity and apart.status == "reproduced"
    # without a control nothing is flagged
    (alone,) = evaluate([c], units)
    assert alone.control is None and alone.status == "reproduced"


def test_the_identity_rule_is_two_sided():
    """An undecided claim the control holds about as often, and any claim the control holds
    significantly more often, is flagged; a claim failing on both stays contradicted."""
    c = Claim(id="x.t", paper="001", where="s", statement="t", kind="emergent", quantity="q", comparator=is_true())
    (fails_alike,) = evaluate([c], _units([0.0] * 18 + [1.0] * 2), _units([0.0] * 17 + [1.0] * 3))
    assert fails_alike.verdict == "fails for most units" and fails_alike.status == "contradicted"
    (undecided_alike,) = evaluate([c], _units([0.0] * 10 + [1.0] * 10), _units([0.0] * 9 + [1.0] * 11))
    assert undecided_alike.status == "no different from the control"
    (below,) = evaluate([c], _units([0.0] * 12 + [1.0] * 8), _units([1.0] * 20))
    assert below.verdict == "undecided" and below.status == "below the control"
    (fails_apart,) = evaluate([c], _units([0.0] * 20), _units([1.0] * 20))
    assert fails_apart.status == "below the control"
    # a claim that holds on 15/20 units and on 3/20 controls (p = 1.4e-4) is a finding
    (found,) = evaluate([c], _units([1.0] * 15 + [0.0] * 5), _units([1.0] * 3 + [0.0] * 17))
    assert found.control_p_value < 1e-3 and found.status == "reproduced"


def test_the_control_ignores_the_precondition():
    pre = Precondition(text="effect", quantity="e", comparator=above(0.5))
    c = Claim(id="x.p", paper="001", where="s", statement="t", kind="emergent", quantity="q",
              comparator=is_true(), precondition=pre)
    (r,) = evaluate([c], [{"q": 1.0, "e": 1.0}] * 10, [{"q": 1.0, "e": 0.0}] * 10)
    assert r.control.testable == 10 and r.control.holds == 10 and r.identity


def test_provisional_verdicts_end_within_five_points_of_half():
    c = _claim()
    for k, n, provisional in ((15, 20, True), (17, 20, False), (2, 20, False), (5, 20, True)):
        (r,) = evaluate([c], _units([2.0] * k + [0.0] * (n - k)))
        lo, hi = r.interval95
        assert r.provisional is provisional, (k, n, lo, hi)
        assert r.verdict != "undecided"


def test_misses_say_which_way():
    c = Claim(id="x.f", paper="001", where="s", statement="t", kind="emergent", quantity="q",
              comparator=within_factor(10.0, 2.0))
    (r,) = evaluate([c], _units([1.0, 2.0, 30.0, 10.0]))
    assert (r.misses_below, r.misses_above, r.miss_direction) == (2, 1, "both")
    (r,) = evaluate([c], _units([1.0, 2.0, 3.0, 30.0]))
    assert r.miss_direction == "below"
    assert above(1.0).miss(1.0) == "below" and below(1.0).miss(1.0) == "above" and is_true().miss(0.0) == "false"


def test_device_claims_are_matched_not_reproduced_and_take_no_precondition():
    c = Claim(id="x.d", paper="001", where="s", statement="t", kind="calibrated", calibrated_input="set",
              quantity="q", comparator=above(0.0), role="device")
    (r,) = evaluate([c], _units([1.0] * 10))
    assert r.status == "device matched"
    n = tally([r])
    assert (n.device, n.device_matched, n.method, n.reproduced) == (1, 1, 0, 0)
    with pytest.raises(
        ValueError, match=r"Claim.precondition must be None for a device claim \(it states what the device shows\); got"
    ):
        Claim(id="x.d", paper="001", where="s", statement="t", kind="emergent", quantity="q", comparator=is_true(),
              role="device", precondition=Precondition(text="p", quantity="q", comparator=is_true()))
    with pytest.raises(ValueError, match="role must be one of"):
        Claim(id="x.d", paper="001", where="s", statement="t", kind="emergent", quantity="q", comparator=is_true(),
              role="finding")  # type: ignore[arg-type]


def test_tally_counts_each_status_once():
    mk = lambda i, role="method", kind="emergent": Claim(  # noqa: E731
        id=f"x.{i}", paper="001", where="s", statement="t", kind=kind, quantity="q", comparator=above(0.0),
        role=role, calibrated_input="set" if kind == "calibrated" else None)
    claims = [mk(0), mk(1, kind="calibrated"), mk(2, role="extension"), mk(3)]
    units = _units([1.0] * 10)
    res = evaluate(claims[:3], units) + evaluate(claims[3:], _units([-1.0] * 10))
    n = tally(res)
    assert (n.method, n.reproduced, n.calibrated, n.contradicted, n.extension, n.extension_reproduced) == (
        3, 1, 1, 1, 1, 1)
    assert tally(res) + tally(res) == tally(res + res)


def test_spread_keeps_infinite_ends_where_numpy_gives_nan():
    # np.percentile interpolates inf - inf = NaN; a quartile at or next to an infinite value is that value
    assert cl._percentile(np.array([1.0, 2.0, 3.0, math.inf]), 75) == math.inf
    assert cl._percentile(np.array([-math.inf, 1.0, 2.0]), 25) == -math.inf
    assert cl._percentile(np.array([1.0, 2.0, math.inf, math.inf]), 75) == math.inf
    assert cl._percentile(np.array([1.0, 2.0, 3.0, 4.0, math.inf]), 25) == pytest.approx(2.0)
    v = np.array([3.0, 1.0, 4.0, 1.5, 9.0])
    assert cl._percentile(v, 25) == pytest.approx(np.percentile(v, 25))


def test_an_infinite_median_survives_results_json_into_the_readme_table():
    # report._jsonable writes +-inf as the strings "inf"/"-inf" (JSON has no infinity); readme_table
    # reads the claims back from results.json and must print them as inf, not fail or show n/a
    import json

    from gyrobench.scenarios.reports import readme_table, report

    (r,) = evaluate([_claim(comparator=above(1.0))], [{"q": math.inf}, {"q": math.inf}, {"q": 3.0}])
    doc = json.loads(json.dumps(report._jsonable(r.as_dict()), allow_nan=False))
    assert doc["median"] == "inf" and doc["spread"] == ["inf", "inf"]  # 3 + 0.5 (inf - 3) at the 25th
    row = readme_table._row(doc)
    assert "inf [inf, inf]" in row and "3/3" in row


def test_a_precondition_with_also_needs_every_condition():
    pre = Precondition(text="share", quantity="s", comparator=above(0.5),
                       also=(Precondition(text="r2", quantity="r", comparator=above(0.9)),))
    c = Claim(id="x.a", paper="004", where="s", statement="t", kind="emergent", quantity="q", comparator=is_true(),
              precondition=pre)
    units = [{"q": 1.0, "s": 0.9, "r": 0.95}, {"q": 1.0, "s": 0.9, "r": 0.5}, {"q": 1.0, "s": 0.1, "r": 0.99},
             {"q": 1.0, "s": 0.9, "r": None}]
    (r,) = evaluate([c], units)
    assert (r.testable, r.precondition_absent) == (1, 3)
    assert r.as_dict()["precondition"]["also"][0]["quantity"] == "r"


def test_claims_sharing_one_effect_are_counted_once():
    lead = Claim(id="x.lead", paper="000", where="s", statement="t", kind="emergent", quantity="q",
                 comparator=is_true())
    again = Claim(id="x.again", paper="000", where="s", statement="t", kind="emergent", quantity="q",
                  comparator=is_true(), same_effect_as="x.lead")
    res = evaluate([lead, again], _units([1.0] * 20))
    assert [r.status for r in res] == ["reproduced", "reproduced"]
    n = tally(res)
    assert (n.method, n.reproduced, n.same_effect) == (1, 1, 1)
    with pytest.raises(ValueError, match=r"Claim.same_effect_as must name another claim; got its own id 'x.self'"):
        Claim(id="x.self", paper="000", where="s", statement="t", kind="emergent", quantity="q",
              comparator=is_true(), same_effect_as="x.self")


def test_a_deviation_that_moves_a_median_is_a_change_at_the_same_pass_count():
    from gyrobench.scenarios.claims import deviation_effect

    c = Claim(id="x.d", paper="001", where="s", statement="t", kind="emergent", quantity="q", comparator=below(1.0))
    ours = evaluate([c], _units([2.0] * 10))
    theirs = evaluate([c], _units([60.0] * 10))  # still failing 0/10, the median 30x higher
    e = deviation_effect("v", ours, theirs)
    assert [x[0] for x in e.changed] == ["x.d"] and "median 2 -> 60" in e.text()
    assert e.as_dict()["changes"][0]["median_variant"] == 60.0
    same = deviation_effect("v", ours, evaluate([c], _units([3.0] * 10)))  # 1.5x: not a change
    assert not same.changed and "no claim's pass count changes" in same.text()
