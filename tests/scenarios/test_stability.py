"""The expected status changes between seed sets, against exact enumeration of the counts."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from scipy.stats import multinomial

from gyrobench.scenarios.claims import Claim, ClaimResult, ControlResult, Precondition, above
from gyrobench.scenarios.reports.stability import claim_from_row, flip_probability, status_changes

N = 20
DRAWS = 4000
Z_FALSE_ALARM = 3.29  # two-sided 0.1 % per case


def _claim(precondition: bool) -> Claim:
    return Claim(
        id="t.c", paper="t", where="Sec. 1", statement="s", kind="emergent", quantity="q",
        comparator=above(1.0), role="method",
        precondition=Precondition(text="p", quantity="pq", comparator=above(0.0)) if precondition else None,
    )


def _row(claim: Claim, units: tuple[int, int, int], control: tuple[int, int] | None) -> dict:
    """A results.json entry with (holds, fails, precondition absent) units and (holds, fails) control."""
    h, f, a = units
    control_result = None if control is None else ControlResult(
        units=sum(control), testable=sum(control), holds=control[0])
    return ClaimResult(claim=claim, units=h + f + a, testable=h + f, holds=h, median=None, spread=None,
                       precondition_absent=a, control=control_result).as_dict()


def _compositions(n: int, k: int):
    for cuts in itertools.combinations(range(n + k - 1), k - 1):
        parts = np.diff((-1, *cuts, n + k - 1)) - 1
        yield tuple(int(x) for x in parts)


def _exact_flip(claim: Claim, p_units, p_control) -> float:
    """1 - sum_s P(s)^2 over every count the n units (and n control units) can give."""
    prob: dict[str, float] = {}
    controls = [None] if p_control is None else list(_compositions(N, 2))
    for u in _compositions(N, len(p_units)):
        pu = multinomial.pmf(u, N, p_units)
        h, f, a = (*u, 0)[:3]
        for c in controls:
            pc = 1.0 if c is None else multinomial.pmf(c, N, p_control)
            ctrl = None if c is None else ControlResult(units=N, testable=N, holds=c[0])
            s = ClaimResult(claim=claim, units=N, testable=h + f, holds=h, median=None, spread=None,
                            precondition_absent=a, control=ctrl).status
            prob[s] = prob.get(s, 0.0) + pu * pc
    assert math.isclose(sum(prob.values()), 1.0, rel_tol=1e-9)
    return 1.0 - sum(v * v for v in prob.values())


# The posterior is made sharp (a million units of evidence: its spread moves the flip probability
# by far less than the Monte-Carlo error), so the predictive flip probability must equal the exact
# one at the true category probabilities.
CASES = {
    "pass rate near the verdict's edge": (False, (0.62, 0.38), None),
    "precondition absent on about half": (True, (0.40, 0.12, 0.48), None),
    "control close to the units": (False, (0.80, 0.20), (0.45, 0.55)),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_flip_probability_matches_exact_enumeration(case):
    precondition, p_units, p_control = CASES[case]
    claim = _claim(precondition)
    big = 1_000_000
    units = tuple(round(big * p) for p in p_units) + ((0,) if len(p_units) == 2 else ())
    control = None if p_control is None else tuple(round(big * p) for p in p_control)
    row = _row(claim, units, control)
    got = flip_probability(row, units=N, draws=DRAWS, rng=np.random.default_rng(7)).probability
    exact = _exact_flip(claim, p_units, p_control)
    se = math.sqrt(exact * (1 - exact) / DRAWS)
    assert 0.05 < exact < 0.95  # each case sits where the status can change
    assert abs(got - exact) < Z_FALSE_ALARM * se, (got, exact, se)


def test_an_untestable_claim_stays_untestable():
    claim = _claim(False)
    row = ClaimResult(claim=claim, units=20, testable=0, holds=0, median=None, spread=None).as_dict()
    f = flip_probability(row, draws=500, rng=np.random.default_rng(1))
    assert (f.status, f.probability, f.units) == ("not testable", 0.0, 20)


def test_the_claim_is_rebuilt_from_its_results_json_entry():
    claim = _claim(True)
    back = claim_from_row(_row(claim, (3, 2, 1), (1, 4)))
    assert back == claim


def test_status_changes_lists_the_claims_whose_word_differs():
    a = [{"claims": [{"id": "x", "status": "reproduced"}, {"id": "y", "status": "undecided"}]}]
    b = [{"claims": [{"id": "x", "status": "undecided"}, {"id": "y", "status": "undecided"}]}]
    (change,) = status_changes(a, b)
    assert (change.claim_id, change.before, change.after) == ("x", "reproduced", "undecided")
    with pytest.raises(ValueError, match="different claims"):
        status_changes(a, [{"claims": [{"id": "x", "status": "undecided"}]}])


def test_bad_unit_counts_are_refused():
    row = _row(_claim(False), (3, 2, 0), None)
    with pytest.raises(ValueError, match="units must be an integer >= 1; got 0"):
        flip_probability(row, units=0, rng=np.random.default_rng(0))
    with pytest.raises(ValueError, match="inconsistent counts"):
        flip_probability({**row, "holds": 9}, rng=np.random.default_rng(0))
