"""Fit range and goodness of fit of analysis.allan.fit_noise: where the model holds, chi2, misfit.

Synthetic records with known truth: the five-term model (which the fit must leave whole
and not flag at the stated level), and white + random-walk rate noise passed through a
low-pass filter (what a sensor's anti-alias / decimation filter does to its first octaves),
whose filter-shaped region must be found and excluded.
"""

from __future__ import annotations

import math
from statistics import NormalDist

import numpy as np
import pytest

from gyrobench.analysis.allan import (
    FitRange,
    allan_deviation,
    avar_to_coefficient,
    fit_noise,
    fit_range,
)

FS = 100.0
N_TRUE = 1e-3  # rad/s/sqrt(Hz) = rad/sqrt(s)
K_TRUE = 2e-6  # rad/s/sqrt(s)
#: false-alarm rate of every interval check below (two-sided, per coefficient)
FALSE_ALARM = 1e-6


def filtered_record(rng: np.random.Generator, n: int = 400_000, cutoff: float = 5.0) -> np.ndarray:
    """White rate (N_TRUE) + random-walk rate (K_TRUE), low-passed by a 4th-order Butterworth at ``cutoff`` Hz.

    The filter has unit gain at DC, so the ADEV for tau >> 1/cutoff is the unfiltered
    N^2/tau + K^2 tau/3; the first octaves (tau = 0.01 .. ~0.1 s) lie below it.
    """
    from scipy import signal

    white = N_TRUE * math.sqrt(FS) * rng.standard_normal(n)
    walk = np.cumsum(K_TRUE / math.sqrt(FS) * rng.standard_normal(n))
    sos = signal.butter(4, cutoff, fs=FS, output="sos")
    return signal.sosfilt(sos, white) + walk


@pytest.fixture(scope="module")
def filtered_curve():
    return allan_deviation(filtered_record(np.random.default_rng(20261123)), FS)


def test_fit_range_finds_the_filter_shaped_octaves(filtered_curve):
    fr = fit_range(filtered_curve)
    assert isinstance(fr, FitRange)
    # a 5 Hz 4th-order low-pass bends the octaves below ~0.1 s; they must be excluded
    assert fr.tau_min is not None and fr.tau_min >= 0.04, fr
    assert fr.excluded == int(np.sum(filtered_curve.tau < fr.tau_min))
    assert "filter-shaped" in fr.reason


def test_unrestricted_fit_of_a_filtered_record_is_a_misfit_and_widened(filtered_curve):
    fit = fit_noise(filtered_curve)
    assert fit.misfit and fit.p_value < 1e-3
    assert fit.inflation == pytest.approx(math.sqrt(fit.chi2 / fit.chi2_expected), rel=1e-12)
    assert fit.chi2_per_dof == pytest.approx(fit.chi2 / fit.chi2_expected, rel=1e-12)
    plain = fit_noise(filtered_curve, misfit_p=0.0)  # the test switched off: no widening
    assert not plain.misfit and plain.inflation == 1.0
    j = list(fit.avar_coefficients).index("N")
    assert fit.covariance[j, j] == pytest.approx(
        plain.covariance[j, j] * fit.inflation**2, rel=1e-9
    )


def test_auto_range_fit_recovers_the_truth(filtered_curve):
    fit = fit_noise(filtered_curve, tau_min="auto", terms=("Q", "N", "B", "K"))
    assert fit.tau_used[0] >= fit_range(filtered_curve).tau_min
    assert not fit.misfit, (fit.chi2, fit.dof, fit.p_value)
    level = 1.0 - FALSE_ALARM
    lo, hi = fit.interval("N", level)
    assert lo <= N_TRUE <= hi, (lo, hi)
    lo, hi = fit.interval("K", level)
    assert lo <= K_TRUE <= hi, (lo, hi)


def test_model_conformant_record_keeps_every_point():
    """The five-term model is log-log convex: nothing is cut and the fit is not flagged."""
    from gyrobench.sim.noise import NoiseModel

    model = NoiseModel(
        quantization=2e-5, angle_random_walk=N_TRUE, bias_instability=1e-4, rate_random_walk=K_TRUE
    )
    y = model.generate(400_000, FS, rng=np.random.default_rng(20261124))
    curve = allan_deviation(y, FS)
    assert fit_range(curve).tau_min is None
    fit = fit_noise(curve, tau_min="auto")
    assert fit.used.all()
    assert not fit.misfit, (fit.chi2, fit.dof, fit.p_value)
    assert 0.0 <= fit.p_value <= 1.0 and fit.dof == fit.used.sum() - sum(
        1 for v in fit.avar_coefficients.values() if v > 0
    )


def test_tau_limits_select_points(filtered_curve):
    fit = fit_noise(filtered_curve, tau_min=0.16, tau_max=100.0)
    tau = filtered_curve.tau
    np.testing.assert_array_equal(
        fit.used, (tau >= 0.16 * (1 - 1e-9)) & (tau <= 100.0 * (1 + 1e-9))
    )
    np.testing.assert_array_equal(fit.tau_used, tau[fit.used])
    assert fit.point_covariance.shape == (fit.used.sum(),) * 2


@pytest.mark.parametrize(
    ("kwargs", "exc", "match"),
    [
        ({"tau_min": 10.0, "tau_max": 1.0}, ValueError, "tau_min must be <= tau_max"),
        ({"tau_min": -1.0}, ValueError, "tau_min must be finite and > 0 s; got -1.0"),
        ({"tau_max": float("nan")}, ValueError, "tau_max must be finite and > 0 s"),
        ({"tau_min": "automatic"}, ValueError, "tau_min must be a number"),
        ({"tau_min": [1.0]}, TypeError, "tau_min must be a number"),
        (
            {"tau_min": 500.0},
            ValueError,
            "holds 1 of the curve's tau points, fewer than the 5 terms",
        ),
        ({"misfit_p": 1.5}, ValueError, "misfit_p must be a probability"),
    ],
)
def test_bad_fit_limits_are_refused(filtered_curve, kwargs, exc, match):
    with pytest.raises(exc, match=match):
        fit_noise(filtered_curve, **kwargs)


def test_chi2_is_the_standardised_residual_norm_with_its_exact_law(filtered_curve):
    """chi2 = sum r_i^2 / V_ii; its law: sum lambda_k chi2_1, lambda = eig of the residuals' correlation."""
    fit = fit_noise(filtered_curve, tau_min=0.32, misfit_p=0.0)
    a = filtered_curve.variance[fit.used]
    r = a - fit.avar(fit.tau_used)
    v = fit.point_covariance
    d = np.sqrt(np.diag(v))
    assert fit.chi2 == pytest.approx(float(np.sum((r / d) ** 2)), rel=1e-9)
    # the residuals of the weighted fit over the kept terms: r = (I - H) A, H = X (X'WX)^-1 X'W
    names = [k for k, c in fit.avar_coefficients.items() if c > 0]
    x = np.stack([fit.term_avar(k, fit.tau_used) / fit.avar_coefficients[k] for k in names], axis=1)
    w = np.diag(1.0 / np.diag(v))
    h = x @ np.linalg.solve(x.T @ w @ x, x.T @ w)
    s = np.diag(1 / d) @ (np.eye(a.size) - h) @ v @ (np.eye(a.size) - h).T @ np.diag(1 / d)
    assert fit.dof == a.size - len(names)
    assert fit.chi2_expected == pytest.approx(np.trace(s), rel=1e-6)
    # the p-value against a Monte Carlo of the quadratic form (binomial tolerance at 1e-6)
    lam = np.clip(np.linalg.eigvalsh(s), 0, None)
    draws = (np.random.default_rng(11).standard_normal((400_000, lam.size)) ** 2) @ lam
    p_mc = float(np.mean(draws >= fit.chi2))
    tol = NormalDist().inv_cdf(1 - 1e-6 / 2) * math.sqrt(p_mc * (1 - p_mc) / draws.size) + 0.02 * p_mc
    assert abs(fit.p_value - p_mc) <= tol, (fit.p_value, p_mc)


@pytest.mark.parametrize("lam", [[1.0] * 7, [3.0, 1.0, 0.5, 0.2, 0.1, 0.05], [0.9, 0.8, 0.1, 0.05, 0.01]])
def test_quadratic_form_tail(lam):
    """The Liu-Tang-Zhang tail: exact for equal weights (chi2_k); elsewhere measured within 0.5-11 % of p
    down to p = 1e-3 (one dominant weight is the hardest case), checked to 15 % + the Monte Carlo error."""
    from scipy import stats

    from gyrobench.analysis.allan import _goodness

    lam = np.array(lam)
    c = [float(np.sum(lam**k)) for k in (1, 2, 3, 4)]
    draws = (np.random.default_rng(12).standard_normal((1_000_000, lam.size)) ** 2) @ lam
    for p in (0.5, 0.1, 1e-2, 1e-3):
        q = float(np.quantile(draws, 1 - p))
        got = _goodness._ltz_sf(q, *c)
        if np.all(lam == lam[0]):
            assert got == pytest.approx(stats.chi2.sf(q / lam[0], lam.size), rel=1e-9)
        se = math.sqrt(p * (1 - p) / draws.size)
        assert abs(got - p) <= NormalDist().inv_cdf(1 - 1e-6 / 2) * se + 0.15 * p, (p, got)


def test_identifiability_uses_the_widened_interval(filtered_curve):
    fit = fit_noise(filtered_curve)
    z = NormalDist().inv_cdf(0.975)
    for j, (name, c) in enumerate(fit.avar_coefficients.items()):
        se = math.sqrt(max(fit.covariance[j, j], 0.0))
        assert fit.coefficients[name].ci95[1] == pytest.approx(
            avar_to_coefficient(name, c + z * se), rel=1e-9
        )


def test_all_taus_refused_before_any_work(monkeypatch):
    from gyrobench.analysis.allan import _taus

    y = np.zeros(400_001)  # 100_000 taus x 400_001 samples = 4e10 pairs > the 2e10 limit
    with pytest.raises(
        ValueError, match=r"taus='all' on 400001 samples means 100000 taus, 4e\+10 sample-tau pairs"
    ):
        allan_deviation(y, FS, taus="all")
    monkeypatch.setattr(
        _taus, "_available_memory", lambda: 1e6
    )  # 1 MB left: refuse on memory first
    with pytest.raises(ValueError, match="GiB, more than 80 % of the"):
        allan_deviation(np.zeros(10_000), FS, taus="all")


def test_default_misfit_level_is_005_and_widens_a_real_record():
    """Issue 30: the misfit test rejects at 0.05 by default (was 1e-3), and a rejected fit is widened.

    ADIS16405 imu2 gyro x, 1 Hz excerpt (tests/data): p between 1e-3 and 0.05 with the auto range.
    """
    import gzip
    from pathlib import Path

    from gyrobench.analysis.allan import MISFIT_P

    assert MISFIT_P == 0.05
    path = Path(__file__).resolve().parents[1] / "data" / "adis16405_1hz" / "adis16405_imu2_1Hz.csv.gz"
    with gzip.open(path, "rt") as fh:
        y = np.loadtxt((ln for ln in fh if ln[:1] not in ("#", "g")), delimiter=",", usecols=0)
    fit = fit_noise(y, 1.0, tau_min="auto", terms=("N", "B", "K", "R"))
    assert 1e-3 < fit.p_value < MISFIT_P, fit.p_value
    assert fit.misfit and fit.inflation == pytest.approx(math.sqrt(fit.chi2 / fit.chi2_expected), rel=1e-12)
    strict = fit_noise(y, 1.0, tau_min="auto", terms=("N", "B", "K", "R"), misfit_p=1e-3)
    assert not strict.misfit and strict.inflation == 1.0


def test_quantization_needs_two_dominated_taus():
    """A Q term that dominates a single fitted tau (a one-octave bump) is not identifiable; two are enough."""
    from gyrobench.analysis.allan._fit import _coefficients

    tau = np.array([1.0, 2.0, 4.0, 8.0, 16.0])
    x = tau[:, None] ** np.array([-2.0, -1.0])[None, :]
    se = np.array([1e-6, 1e-6])  # intervals far from 0: only dominance decides
    one = _coefficients(("Q", "N"), x, np.array([1.5, 1.0]), se)  # Q > N at tau = 1 only
    two = _coefficients(("Q", "N"), x, np.array([3.0, 1.0]), se)  # Q > N at tau = 1 and 2
    assert not one["Q"].identifiable and one["N"].identifiable
    assert two["Q"].identifiable and two["N"].identifiable


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_pooled_curve_intervals_cover_at_their_level():
    """pool_curves: three independent white-noise stretches (unit variance, 4096, 2048 and 3000
    samples), 300 times; AVAR(m) = 1/m. At each common tau the pooled 68.3 % interval covers the
    truth at a rate within the binomial bounds at two-sided 1e-6 (Bonferroni over the taus), and
    the pooled curve keeps only the taus all three hold."""
    from scipy.stats import binom

    from gyrobench.analysis.allan import allan_deviation, pool_curves

    rng = np.random.default_rng(48)
    reps = 300
    hits = None
    for _ in range(reps):
        curves = [allan_deviation(rng.standard_normal(n), 1.0) for n in (4096, 2048, 3000)]
        c = pool_curves(curves)
        truth = np.sqrt(1.0 / c.m)
        h = (c.low <= truth) & (truth <= c.high)
        hits = h.astype(int) if hits is None else hits + h
    short = allan_deviation(np.zeros(2048) + rng.standard_normal(2048), 1.0)
    assert np.array_equal(c.m, short.m)
    p = 1e-6 / c.m.size
    lo, hi = binom.ppf(p / 2, reps, c.confidence), binom.isf(p / 2, reps, c.confidence)
    assert np.all((lo <= hits) & (hits <= hi)), (hits, lo, hi)


def test_pool_curves_refuses_mixed_rates():
    from gyrobench.analysis.allan import allan_deviation, pool_curves

    a = allan_deviation(np.random.default_rng(1).standard_normal(512), 1.0)
    b = allan_deviation(np.random.default_rng(2).standard_normal(512), 2.0)
    with pytest.raises(ValueError, match=r"curves must share one fs; got \[1.0, 2.0\]"):
        pool_curves([a, b])
    with pytest.raises(TypeError, match="curves must be a non-empty sequence of AllanCurve"):
        pool_curves([])
