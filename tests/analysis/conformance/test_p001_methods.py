"""Conformance of paper 001's methods on constructed rate tables whose outcome is known by construction.

Each device maps the table rate w to a noise-free output x(w) by inverting a chosen
compensation curve G (rate = G(output)); every run adds independent N(0, sigma^2) to each
per-rate mean output. A method that implements its model correctly on a device its model
contains reaches the noise floor on a held-out run:

    compensated error at table rate j:  e_j = G'(x_j) (n_j - m_j) + O(sigma^2),

n_j the held-out run's noise and m_j the fit's error at x_j. Both have covariance <= sigma^2 I
in output units (a least-squares or penalized fit is a linear smoother whose hat matrix has
eigenvalues <= 1), so every residual of the IEEE straight line through the e_j (a projection)
has standard deviation <= s = sqrt(2) max G' sigma. With the union bound over the 21 table
rates, P(max_j |r_j| > z s) <= 42 Phi(-z); z = Phi^-1(1 - ALPHA / 42) gives the K_n bound
z s / F_m at the false-alarm rate ALPHA, F_m >= 3600 - 1 deg/s the full-scale compensated output.
A deliberately broken variant of each method must exceed its bound (or miss the breakpoints).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.stats import norm

from gyrobench.analysis import scale_factor
from gyrobench.analysis.compensation.bayes_mlp import BayesianRegularizedMLP
from gyrobench.analysis.compensation.polynomial import PiecewisePolynomial, TwoStagePolynomial
from gyrobench.analysis.scale_factor import breakpoint_search, fit_scale_factor

GRID = np.arange(3600.0, -3601.0, -360.0)
ALPHA = 1e-3  # false-alarm rate of every bound below
SIGMA = 0.005  # per-run noise of a per-rate mean output [deg/s]
B = 1800.0  # the constructed breakpoints [deg/s]
A9 = 3.0  # weight of the 9th-order term beyond the breakpoints
Z = float(norm.isf(ALPHA / (2 * GRID.size)))
FULL_SCALE = 3600.0 - 1.0


def g_919(x):
    """Rate [deg/s] from output [deg/s]: linear inside +-B, 9th-order polynomial beyond (C2 at +-B)."""
    x = np.asarray(x, dtype=float)
    u = np.clip((np.abs(x) - B) / B, 0.0, None)
    return x + np.sign(x) * B * (u**3 + A9 * u**9)


def g_919_slope(x):
    u = np.clip((np.abs(np.asarray(x, dtype=float)) - B) / B, 0.0, None)
    return 1.0 + 3 * u**2 + 9 * A9 * u**8


def g_poly9(x):
    """Rate from output: one global monotone 9th-order polynomial (the two-stage model's own)."""
    v = np.asarray(x, dtype=float) / 3000.0
    return 3000.0 * (v + 0.05 * v**3 + 0.02 * v**9)


def g_poly9_slope(x):
    v = np.asarray(x, dtype=float) / 3000.0
    return 1.0 + 0.15 * v**2 + 0.18 * v**8


X0_TANH = 2500.0


def g_tanh(x):
    """Rate from output: one tanh unit (a 10-hidden tanh network contains it)."""
    return 4000.0 * np.tanh(np.asarray(x, dtype=float) / X0_TANH)


def g_tanh_slope(x):
    return 4000.0 / X0_TANH / np.cosh(np.asarray(x, dtype=float) / X0_TANH) ** 2


def table(g, seed, n_runs=4):
    """Per-rate mean outputs of ``n_runs`` runs [deg/s], shape (n_runs, 21)."""
    x0 = np.array([brentq(lambda x, w=w: float(g(x)) - w, -20000.0, 20000.0) for w in GRID])
    rng = np.random.default_rng([20261201, seed])
    return x0 + SIGMA * rng.standard_normal((n_runs, GRID.size))


def kn_bound_pct(slope, runs):
    s = math.sqrt(2.0) * float(np.max(slope(runs))) * SIGMA
    return 100.0 * Z * s / FULL_SCALE


def heldout_kn_pct(model, runs):
    X, y = runs[:3].reshape(-1)[:, None], np.tile(GRID, 3)
    model.fit(X, y)
    return fit_scale_factor(GRID, model.predict(runs[3][:, None])).nonlinearity_pct


# ------------------------------------------------------------------ heuristic breakpoints
def test_heuristic_search_finds_the_constructed_breakpoints():
    runs = table(g_919, 0)
    assert breakpoint_search(GRID, runs[:3].mean(axis=0)).breakpoints == (-B, B)


def test_a_split_at_the_end_of_the_run_misses_the_breakpoints(monkeypatch):
    """Broken variant: the split taken at the run's last interval, not before its first."""
    orig = scale_factor.heuristic_split

    def late(kn, *, run_length=3):
        split, d, dd, c = orig(kn, run_length=run_length)
        return (None if split is None else split + run_length), d, dd, c

    monkeypatch.setattr(scale_factor, "heuristic_split", late)
    runs = table(g_919, 0)
    assert breakpoint_search(GRID, runs[:3].mean(axis=0)).breakpoints != (-B, B)


# ------------------------------------------------------------------ piecewise 9-1-9 + Hermite
def test_piecewise_reaches_the_noise_floor_on_a_919_device():
    runs = table(g_919, 1)
    model = PiecewisePolynomial()
    kn = heldout_kn_pct(model, runs)
    assert model.breakpoint_rates_ == (-B, B) and model.orders_ == (9, 1, 9)
    assert kn < kn_bound_pct(g_919_slope, runs)


def test_the_paper_join_spans_only_the_overlap_of_the_fits():
    """Sec. 2.2.2: the join lies inside the range of the breakpoint rate's own samples."""
    runs = table(g_919, 1)
    model = PiecewisePolynomial().fit(runs[:3].reshape(-1)[:, None], np.tile(GRID, 3))
    for (x0, x1), r in zip(model.joins_, model.breakpoint_rates_, strict=True):
        at = runs[:3, GRID == r].ravel()
        assert (x0, x1) == (at.min(), at.max())


def test_a_centred_join_of_5_percent_exceeds_the_noise_floor():
    """Broken variant: the join centred on the breakpoint over 5 % of the output span takes its
    ends from the outer segment between table points."""
    runs = table(g_919, 1)
    assert heldout_kn_pct(PiecewisePolynomial(join="centred"), runs) > kn_bound_pct(g_919_slope, runs)


# ------------------------------------------------------------------ two-stage polynomial
class _TwoStageSkippingStage1(TwoStagePolynomial):
    """Broken variant: stage 2 evaluated on the raw input instead of on stage 1's output."""

    def predict(self, X):
        X = np.asarray(X, dtype=float)
        return self.stage2_.predict(X)


def test_two_stage_reaches_the_noise_floor_on_a_global_9th_order_device():
    runs = table(g_poly9, 2)
    assert heldout_kn_pct(TwoStagePolynomial(), runs) < kn_bound_pct(g_poly9_slope, runs)


def test_two_stage_without_its_first_stage_exceeds_the_noise_floor():
    runs = table(g_poly9, 2)
    assert heldout_kn_pct(_TwoStageSkippingStage1(), runs) > kn_bound_pct(g_poly9_slope, runs)


# ------------------------------------------------------------------ Bayes-BP
def test_bayes_bp_reaches_the_noise_floor_on_a_tanh_device():
    runs = table(g_tanh, 3)
    net = BayesianRegularizedMLP(hidden_units=10, random_state=0)
    assert heldout_kn_pct(net, runs) < kn_bound_pct(g_tanh_slope, runs)


def test_bayes_bp_stopped_after_three_epochs_exceeds_the_noise_floor():
    """Broken variant: training stopped long before the Levenberg-Marquardt iteration converges."""
    runs = table(g_tanh, 3)
    net = BayesianRegularizedMLP(hidden_units=10, epochs=3, random_state=0)
    assert heldout_kn_pct(net, runs) > kn_bound_pct(g_tanh_slope, runs)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_the_bounds_are_not_vacuous(seed):
    """The noise bound is a small fraction of the raw K_n: a method that does nothing fails it."""
    for g, slope in ((g_919, g_919_slope), (g_poly9, g_poly9_slope), (g_tanh, g_tanh_slope)):
        runs = table(g, seed)
        raw = fit_scale_factor(GRID, runs[3]).nonlinearity_pct
        assert raw > 100 * kn_bound_pct(slope, runs)
