"""Conformance of paper 004's stepwise multiple regression on a constructed bias with a known support.

The bias is linear in x1, x3, x5, x7 and x11 of eleven candidate regressors plus white noise
(n = 100 blocks, the length of paper 004's 100-s block records); x2 is correlated with x1
(rho = 0.9), as the temperatures of one block are, so only a test of each candidate *given the
terms already in* (the partial F test) keeps x2 out. Each true coefficient gives a partial t of
about 10: the chance that a true term is missed in one of the trials is below 1e-12.

False selection: once the five true terms are in, each of the six null candidates' partial F
test is exact (F(1, n - 7)), so the first entry of a null term happens with probability
q = 1 - (1 - p_enter)^6 if the six tests were independent (their common residual variance
makes them slightly dependent; Bonferroni bounds q by 6 p_enter above and p_enter below). The
count of trials with a false selection is Binomial(M, q); the test accepts the two-sided
ALPHA = 1e-3 interval of the exact binomial with q in [p_enter, 6 p_enter] and requires the
independent value q0 to lie in the observed count's Clopper-Pearson interval at ALPHA.
"""

from __future__ import annotations

import numpy as np
from scipy.stats import beta, binom

from gyrobench.analysis.compensation import stepwise
from gyrobench.analysis.compensation.stepwise import StepwiseRegression

ALPHA = 1e-3
N_BLOCKS, N_TRIALS, P_ENTER = 100, 120, 0.05
TRUE = (0, 2, 4, 6, 10)  # x1, x3, x5, x7, x11 (0-based)
Q0 = 1.0 - (1.0 - P_ENTER) ** 6


def _trial(rng):
    X = rng.standard_normal((N_BLOCKS, 11))
    X[:, 1] = 0.9 * X[:, 0] + np.sqrt(1 - 0.81) * X[:, 1]
    y = 3.0 + X[:, list(TRUE)].sum(axis=1) + rng.standard_normal(N_BLOCKS)
    return X, y


def _selections(model_factory):
    rng = np.random.default_rng(20261201)
    out = []
    for _ in range(N_TRIALS):
        X, y = _trial(rng)
        out.append(tuple(np.flatnonzero(model_factory().fit(X, y).support_)))
    return out


def _false_count(sel):
    return sum(bool(set(s) - set(TRUE)) for s in sel)


def _conforms(sel) -> bool:
    """No true term missed, the false-selection count inside the derived bounds, the rest exact."""
    if not all(set(TRUE) <= set(s) for s in sel):
        return False
    k = _false_count(sel)
    if not binom.ppf(ALPHA / 2, N_TRIALS, P_ENTER) <= k <= binom.isf(ALPHA / 2, N_TRIALS, 6 * P_ENTER):
        return False
    cp_lo = beta.ppf(ALPHA / 2, k, N_TRIALS - k + 1) if k else 0.0
    cp_hi = beta.isf(ALPHA / 2, k + 1, N_TRIALS - k)
    return bool(cp_lo <= Q0 <= cp_hi) and sum(s == TRUE for s in sel) == N_TRIALS - k


def test_stepwise_selects_the_true_terms_at_the_derived_false_selection_rate():
    assert _conforms(_selections(lambda: StepwiseRegression(p_enter=P_ENTER, p_remove=0.10)))


def test_stepwise_with_marginal_tests_does_not_conform(monkeypatch):
    """Broken variant: each residual sum of squares taken on the last term alone, so every
    candidate is tested on its own rather than given the terms already in."""
    orig = stepwise._rss
    monkeypatch.setattr(stepwise, "_rss", lambda X, y, cols: orig(X, y, cols[-1:]))
    assert not _conforms(_selections(lambda: StepwiseRegression(p_enter=P_ENTER, p_remove=0.10)))


def test_stepwise_with_a_tenfold_entry_threshold_does_not_conform():
    """Broken variant: p_enter applied as 0.5 (the entry test's size ten times the stated one)."""
    assert not _conforms(_selections(lambda: StepwiseRegression(p_enter=0.5, p_remove=0.6)))
