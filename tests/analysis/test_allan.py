"""Tests of analysis.allan: estimators pinned to allantools, closed forms, bad input, the fit."""

from __future__ import annotations

import math
import warnings

import allantools
import numpy as np
import pytest
from allantools import ci as atci
from scipy import stats

from gyrobench.analysis import allan
from gyrobench.analysis.allan import (
    KINDS,
    TERMS,
    AllanCurve,
    _blas,
    _covariance,
    _kinds,
    _terms,
    allan_deviation,
    coefficient_to_avar,
    fit_noise,
    identify_noise,
    slope_readoff,
)
from gyrobench.sim.noise import NoiseModel

ALLANTOOLS = {
    "overlapping": allantools.oadev,
    "standard": allantools.adev,
    "modified": allantools.mdev,
    "hadamard": allantools.hdev,
    "overlapping_hadamard": allantools.ohdev,
    "total": allantools.totdev,
}


@pytest.fixture
def mixed(rng) -> np.ndarray:
    """White + random-walk rate on a large offset (tests the mean removal), 6000 samples."""
    return 1e3 + rng.standard_normal(6000) + 0.02 * np.cumsum(rng.standard_normal(6000))


# ------------------------------------------------------------------------------------ estimators
@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("taus", ["octave", "decade"])
def test_deviation_matches_allantools(mixed, kind, taus):
    fs = 12.5
    c = allan_deviation(mixed, fs, taus=taus, kind=kind)
    t, d, _, ns = ALLANTOOLS[kind](mixed, rate=fs, data_type="freq", taus=c.tau)
    np.testing.assert_allclose(t, c.tau, rtol=1e-12)
    np.testing.assert_allclose(c.deviation, d, rtol=1e-9, atol=0)
    np.testing.assert_array_equal(c.n_terms, np.asarray(ns, dtype=int))


def test_overlapping_matches_allantools_at_every_tau(mixed):
    """The blockwise estimator (several blocks at small m) against allantools.oadev for every m."""
    y = np.tile(mixed, 4)  # 24000 samples: 3 blocks of 8192
    m = np.r_[1:40, 100, 1000, 4095, 4096, 4097, 8191, 8192, 8193, 11999]
    c = allan_deviation(y, 1.0, taus=m.astype(float), alpha=0)
    _, d, _, ns = allantools.oadev(y, rate=1.0, data_type="freq", taus=c.tau)
    np.testing.assert_array_equal(c.m, m)
    np.testing.assert_allclose(c.deviation, d, rtol=1e-9, atol=0)
    np.testing.assert_array_equal(c.n_terms, ns.astype(int))


@pytest.mark.parametrize("threads", [2, 3])
def test_threaded_passes_match_allantools(mixed, monkeypatch, threads):
    """Splitting each pass across threads (each range keeps the m values after it) changes nothing."""
    monkeypatch.setattr(_blas, "_THREADS", threads)
    monkeypatch.setattr(_blas, "_THREAD_MIN", 100)
    y = np.tile(mixed, 3)
    for taus in ("octave", np.r_[1:12, 100, 1000, 4499].astype(float)):
        c = allan_deviation(y, 1.0, taus=taus, alpha=0)
        _, d, _, _ = allantools.oadev(y, rate=1.0, data_type="freq", taus=c.tau)
        np.testing.assert_allclose(c.deviation, d, rtol=1e-9, atol=0)


def test_octave_list_stops_at_quarter_record():
    c = allan_deviation(np.arange(1000.0) % 7, 1.0)
    assert c.m.tolist() == [1, 2, 4, 8, 16, 32, 64, 128]  # m <= N/4 = 250


@pytest.mark.parametrize("kind", KINDS)
def test_max_m_closed_form_matches_term_counts(kind):
    for n in range(2, 80):
        m = np.arange(1, n + 1)
        counts = _kinds._n_terms(kind, n, m)
        brute = n // 2 if kind == "total" else int(m[counts >= 2].max(initial=0))
        assert _kinds._max_m(kind, n) == brute, (kind, n)


def test_ramp_closed_form():
    """Noise-free ramp y = R t: ADEV = R tau / sqrt(2) exactly (docs/physics.md 1.2)."""
    fs, r = 50.0, 3.0e-3
    y = r * np.arange(20000) / fs
    for kind in ("overlapping", "standard"):
        c = allan_deviation(y, fs, kind=kind, alpha=-2)
        np.testing.assert_allclose(c.deviation, r * c.tau / math.sqrt(2), rtol=1e-9)


def test_constant_rate_has_zero_deviation():
    c = allan_deviation(np.full(512, 7.0), 1.0, alpha=0)
    np.testing.assert_array_equal(c.deviation, 0.0)


def test_sinusoid_closed_form():
    """A sampled sine: overlapping AVAR = A^2 (sin^2(pi f0 tau)/(pi f0 tau))^2 up to end effects."""
    fs, f0, a = 100.0, 0.37, 2.0
    y = a * np.sin(2 * np.pi * f0 * np.arange(2_000_00) / fs)
    c = allan_deviation(y, fs, taus=np.array([0.1, 0.5, 1.0]), alpha=0)
    # discrete-time exact form: average of m samples of a sine at f0/fs
    w = np.pi * f0 / fs
    m = c.m
    avar = a**2 * (np.sin(w * m) ** 2 / (m * np.sin(w))) ** 2
    # The differences d_k of consecutive m-averages are an exact sinusoid of amplitude D, so
    # sum_k d_k^2 = n_t D^2/2 + (D^2/2) sum_k cos(4 pi f0 k/fs + phi) and |sum_k cos(k t + phi)|
    # <= 1/|sin(t/2)|: the relative end effect is at most 1/(n_t sin(2 pi f0/fs)) (2.2e-4 here)
    bound = 1.0 / (c.n_terms * np.sin(2 * np.pi * f0 / fs))
    assert np.all(np.abs(c.variance / avar - 1.0) <= bound * (1 + 1e-9) + 1e-12)


# ------------------------------------------------------------------------------------ bounds, edf, noise id
def test_bounds_match_allantools_confidence_interval(mixed):
    c = allan_deviation(mixed, 1.0, alpha=0, confidence=0.9)
    for d, e, lo, hi in zip(c.deviation, c.edf, c.low, c.high, strict=True):
        alo, ahi = atci.confidence_interval(d, e, ci=0.9)
        assert lo == pytest.approx(alo, rel=1e-12) and hi == pytest.approx(ahi, rel=1e-12)


@pytest.mark.parametrize(
    ("kind", "d", "overlapping", "modified"),
    [
        ("overlapping", 2, True, False),
        ("standard", 2, False, False),
        ("modified", 2, True, True),
        ("hadamard", 3, False, False),
        ("overlapping_hadamard", 3, True, False),
    ],
)
@pytest.mark.parametrize("alpha", [2, 0, -1, -2])
def test_edf_is_greenhall(mixed, kind, d, overlapping, modified, alpha):
    c = allan_deviation(mixed, 1.0, kind=kind, alpha=alpha)
    want = [atci.edf_greenhall(alpha=alpha, d=d, m=int(m), N=mixed.size + 1, overlapping=overlapping,
                               modified=modified) for m in c.m[:6]]
    np.testing.assert_allclose(c.edf[:6], want, rtol=1e-12)


@pytest.mark.parametrize(("alpha", "make"), [
    (0, lambda g, n: g.standard_normal(n)),
    (-2, lambda g, n: np.cumsum(g.standard_normal(n))),
    (2, lambda g, n: np.diff(g.standard_normal(n + 1))),
])
def test_noise_id_matches_allantools(rng, alpha, make):
    y = make(rng, 3000)
    tau, got = identify_noise(y, 1.0, taus=np.array([1.0, 2.0, 4.0, 8.0]))
    want = [atci.autocorr_noise_id(y, int(m), data_type="freq", dmin=0, dmax=2)[0] for m in tau]
    assert got.tolist() == [int(np.clip(w, -2, 2)) for w in want]
    assert got[0] == alpha


def test_octave_path_identifies_like_the_general_path(rng):
    """allan_deviation's in-place octave recursion reads the same block means as identify_noise."""
    y = np.cumsum(rng.standard_normal(40000)) * 0.01 + rng.standard_normal(40000)
    c = allan_deviation(y, 2.0)
    _, alpha = identify_noise(y, 2.0)
    assert c.alpha.tolist() == alpha.tolist()
    assert len(set(alpha.tolist())) > 1  # the test sees a change of noise type


def test_bounds_cover_the_truth_at_the_stated_rate(rng):
    """White rate noise, N = 1: the 68.3 % band at tau = m holds sigma_true = 1/sqrt(tau) with
    probability 0.683. The AVAR points of one curve are correlated across octaves (0.5 for
    neighbours), so the misses of one curve are not binomial: each check uses its own
    independent record (11 octaves m = 1..1024 x 40 records of 2**14 samples), and the count
    of misses of the 440 independent checks is binomial(440, 0.317). Two-sided bound at a
    false-alarm rate of 1e-6."""
    ms, reps, n = 2 ** np.arange(11), 40, 1 << 14
    misses = 0
    for m in ms:
        for _ in range(reps):
            c = allan_deviation(rng.standard_normal(n), 1.0, taus=[float(m)], alpha=0)
            truth = 1.0 / math.sqrt(float(m))
            misses += int(truth < c.low[0] or truth > c.high[0])
    k = ms.size * reps
    lo, hi = stats.binom.ppf(0.5e-6, k, 1 - 0.683), stats.binom.isf(0.5e-6, k, 1 - 0.683)
    assert lo <= misses <= hi, (misses, lo, hi)


def test_edf_total_is_nist_table(mixed):
    """Total deviation edf: NIST SP 1065 Table 7 (allantools.ci.edf_totdev) for each alpha."""
    for alpha in (0, -1, -2):
        c = allan_deviation(mixed, 1.0, kind="total", alpha=alpha)
        want = [atci.edf_totdev(mixed.size, int(m), alpha) for m in c.m]
        np.testing.assert_allclose(c.edf, want, rtol=1e-12)


def test_constant_rate_fit_is_refused():
    """ADEV of a constant is 0 (no warning, alpha 0); fitting it names the problem."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        c = allan_deviation(np.zeros(4096), 1.0)
    np.testing.assert_array_equal(c.deviation, 0.0)
    with pytest.raises(ValueError, match=r"rate is constant \(zero variance\): Allan deviation is 0 at every tau"):
        fit_noise(np.full(4096, 3.0), 1.0)


# ------------------------------------------------------------------------------------ bad input
def test_nan_names_the_index():
    y = np.ones(100)
    y[37] = np.nan
    with pytest.raises(ValueError, match=r"rate must be finite.*index 37"):
        allan_deviation(y, 1.0)


def test_inf_names_the_index():
    y = np.ones(100)
    y[5] = -np.inf
    with pytest.raises(ValueError, match=r"-inf at index 5"):
        allan_deviation(y, 1.0)


def test_too_few_samples_for_tau():
    with pytest.raises(ValueError, match=r"too few samples for tau = 60.0 s"):
        allan_deviation(np.ones(100), 1.0, taus=[1.0, 60.0])


def test_too_few_samples_for_automatic_taus():
    with pytest.raises(ValueError, match=r"too few samples"):
        allan_deviation(np.ones(3), 1.0)


@pytest.mark.parametrize("fs", [0.0, -10.0, math.inf, math.nan])
def test_non_positive_fs(fs):
    with pytest.raises(ValueError, match=r"fs must be finite and > 0 Hz; got"):
        allan_deviation(np.ones(100), fs)


def test_unknown_kind_lists_choices():
    with pytest.raises(ValueError, match=r"kind must be one of \('overlapping', 'standard'.*got 'allan'"):
        allan_deviation(np.ones(100), 1.0, kind="allan")


def test_unknown_taus_string_lists_choices():
    with pytest.raises(ValueError, match=r"taus must be one of \('octave', 'decade', 'all'\).*got 'log10'"):
        allan_deviation(np.ones(100), 1.0, taus="log10")


def test_tau_not_multiple_of_sample_period():
    with pytest.raises(ValueError, match=r"multiples of 1/fs = 0.1 s; got tau = 0.25 s"):
        allan_deviation(np.ones(100), 10.0, taus=[0.25])


def test_two_dimensional_rate():
    with pytest.raises(ValueError, match=r"1-D array.*shape \(10, 2\)"):
        allan_deviation(np.ones((10, 2)), 1.0)


def test_confidence_out_of_range():
    with pytest.raises(ValueError, match=r"confidence must be in \(0, 1\); got 1.5"):
        allan_deviation(np.ones(100), 1.0, confidence=1.5)


def test_fit_needs_fs_with_rate():
    with pytest.raises(ValueError, match=r"fs \[Hz\] is required"):
        fit_noise(np.ones(100))


def test_fit_rejects_unknown_terms():
    c = allan_deviation(np.random.default_rng(0).standard_normal(1000), 1.0)
    with pytest.raises(ValueError, match=r"terms must be distinct names from \('Q', 'N', 'B', 'K', 'R'\)"):
        fit_noise(c, terms=("N", "X"))


def test_fit_rejects_non_allan_curve():
    c = allan_deviation(np.random.default_rng(0).standard_normal(1000), 1.0, kind="hadamard")
    with pytest.raises(ValueError, match=r"kind in \('overlapping', 'standard'\); got 'hadamard'"):
        fit_noise(c)


# ------------------------------------------------------------------------------------ fit: closed form
def exact_curve(c: dict[str, float], *, fs: float = 10.0, n: int = 10_000_000) -> AllanCurve:
    """A noise-free AllanCurve sigma^2 = sum C_n tau^n at octave taus (edf for white rate)."""
    m = 2 ** np.arange(int(math.log2(n // 4)) + 1)
    tau = m / fs
    var = sum(v * tau ** float(_terms._POWER[k]) for k, v in c.items())
    edf = _kinds._edf("overlapping", np.zeros(m.size, dtype=np.int64), m, n)
    return AllanCurve(tau=tau, deviation=np.sqrt(var), low=np.sqrt(var), high=np.sqrt(var),
                      n_terms=n + 1 - 2 * m, edf=edf, kind="overlapping", confidence=0.683, fs=fs, n_samples=n)


def test_fit_recovers_exact_curve():
    truth = {"Q": 5e-3, "N": 1e-2, "B": 3e-3, "K": 1e-4, "R": 1e-6}
    c = {k: coefficient_to_avar(k, v) for k, v in truth.items()}
    fit = fit_noise(exact_curve(c))
    for k, v in truth.items():
        assert fit.coefficients[k].identifiable, k
        assert fit.coefficients[k].value == pytest.approx(v, rel=1e-8), k
    tau = np.logspace(-1, 5, 7)
    np.testing.assert_allclose(fit.avar(tau), sum(fit.term_avar(k, tau) for k in TERMS), rtol=1e-14)


def test_coefficient_conversions_are_ieee():
    """C_-2 = 3 Q^2, C_-1 = N^2, C_0 = (2 ln2/pi) B^2, C_1 = K^2/3, C_2 = R^2/2 (docs/physics.md 1.5)."""
    got = [coefficient_to_avar(k, 2.0) for k in TERMS]
    assert got == pytest.approx([12.0, 4.0, 4 * 2 * math.log(2) / math.pi, 4.0 / 3.0, 2.0], rel=1e-15)


# ------------------------------------------------------------------------------------ slope read-off
@pytest.mark.parametrize(("name", "sigma"), [
    ("Q", lambda t: math.sqrt(3) * 0.7 / t),
    ("N", lambda t: 0.7 / np.sqrt(t)),
    ("K", lambda t: 0.7 * np.sqrt(t / 3)),
    ("R", lambda t: 0.7 * t / math.sqrt(2)),
])
def test_slope_readoff_single_term(name, sigma):
    c = exact_curve({"N": 1.0})
    c = AllanCurve(tau=c.tau, deviation=sigma(c.tau), low=c.low, high=c.high, n_terms=c.n_terms, edf=c.edf,
                   kind="overlapping", confidence=0.683, fs=c.fs, n_samples=c.n_samples)
    assert slope_readoff(c)[name] == pytest.approx(0.7, rel=1e-12)
    lo, hi = float(c.tau[2]), float(c.tau[5])
    assert slope_readoff(c, fit_ranges={name: (lo, hi)})[name] == pytest.approx(0.7, rel=1e-12)


def test_slope_readoff_bias_instability_is_min_over_0_6643():
    c = exact_curve({"N": 1e-2, "B": coefficient_to_avar("B", 5e-3), "K": 1e-8})
    got = slope_readoff(c)
    assert got["B"] == pytest.approx(np.min(c.deviation) / math.sqrt(2 * math.log(2) / math.pi), rel=1e-12)
    assert got["R"] is None  # no +1 slope anywhere on this curve


# ------------------------------------------------------------------------------------ fit: statistics
#: Q [u s], N [u s^0.5], B [u], K [u s^-0.5], R [u s^-1]: each term in charge of about a decade
FIVE = {"Q": math.sqrt(0.5 / 3.0), "N": 1.0, "B": math.sqrt(0.05 / (2 * math.log(2) / math.pi)),
        "K": math.sqrt(7.5e-4), "R": 5e-4}


def five_term_model() -> NoiseModel:
    return NoiseModel(quantization=FIVE["Q"], angle_random_walk=FIVE["N"], bias_instability=FIVE["B"],
                      rate_random_walk=FIVE["K"], rate_ramp=FIVE["R"])


#: overall false-alarm rate of each statistical fit test, split (Bonferroni) over its checks
FALSE_ALARM = 1e-6


def test_five_term_fit_intervals_cover_truth(rng):
    """20 h at 10 Hz: Q, N, B, K identifiable; each of the five intervals covers the truth.

    Each interval is built at level 1 - 1e-6/5 (z = 5.03), so with calibrated intervals
    P(any miss) <= 1e-6 (measured calibration: fit_noise docstring, benchmarks/coverage_fit.py).
    Identifiability needs the 95 % lower bound > 0: at the truth C/se = 6.6 for K (the
    weakest of the four), so a miss needs a 4.7-sigma low estimate (P ~ 1e-6); Q, N, B have
    C/se > 24.
    """
    fs = 10.0
    y = five_term_model().generate(int(20 * 3600 * fs), fs, rng=rng)
    fit = fit_noise(y, fs)
    level = 1.0 - FALSE_ALARM / len(FIVE)
    for k, v in FIVE.items():
        lo, hi = fit.interval(k, level)
        assert lo <= v <= hi, (k, v, (lo, hi))
    for k in ("Q", "N", "B", "K"):
        assert fit.coefficients[k].identifiable, k


def test_interval_levels_are_normal_quantiles_on_the_avar_scale(rng):
    """ci68, ci95, upper_bound and interval(level) are C_n +- z se mapped by sqrt(C/scale).

    Except the upper bound of a non-identifiable term, which is computed with the term's own
    noise in the point covariance (``_bound_se``) and so is never below C_n + 1.645 se.
    """
    fs = 10.0
    fit = fit_noise(five_term_model().generate(int(2 * 3600 * fs), fs, rng=rng), fs)
    for j, (k, c) in enumerate(fit.coefficients.items()):
        cn, se = fit.avar_coefficients[k], math.sqrt(fit.covariance[j, j])
        for level, got in ((0.6826894921370859, c.ci68), (0.95, c.ci95), (0.9, (0.0, c.upper_bound))):
            z = stats.norm.ppf(0.5 + level / 2)
            want = [allan.avar_to_coefficient(k, cn - z * se), allan.avar_to_coefficient(k, cn + z * se)]
            np.testing.assert_allclose(fit.interval(k, level), want, rtol=1e-12, atol=0)
            if level == 0.9 and not c.identifiable:  # the bound of an open term: by test inversion, not lower
                assert got[1] >= want[1] * (1 - 1e-12), (k, got[1], want[1])
                continue
            np.testing.assert_allclose(got[1], want[1], rtol=1e-12, atol=0)
            if level != 0.9:
                np.testing.assert_allclose(got[0], want[0], rtol=1e-12, atol=0)
    with pytest.raises(ValueError, match=r"level must be a real number in \(0, 1\); got 1.0"):
        fit.interval("N", 1.0)
    with pytest.raises(TypeError, match=r"level must be a real number in \(0, 1\); got '0.9'"):
        fit.interval("N", "0.9")
    with pytest.raises(ValueError, match=r"name must be one of the fitted terms .*; got 'X'"):
        fit.interval("X", 0.9)


def _mean_difference_weights(kind: str, n: int, m: int) -> np.ndarray:
    """w with mean_k(ybar_{k+m} - ybar_k) = w . y: the telescoped end-minus-start windows."""
    w = np.zeros(n)
    if kind == "overlapping":  # triangles of 2m - 1 samples, total weight m, over n_t m
        tri = np.convolve(np.ones(m), np.ones(m)) / (m * (n + 1 - 2 * m))
        w[n + 1 - 2 * m : n] += tri
        w[: 2 * m - 1] -= tri
    else:  # first and last of the M = n // m boxes, over (M - 1) m
        big = n // m
        w[(big - 1) * m : big * m] += 1.0 / (m * (big - 1))
        w[:m] -= 1.0 / (m * (big - 1))
    return w


@pytest.mark.parametrize("kind", ["overlapping", "standard"])
@pytest.mark.parametrize("m", [16, 64, 256])
def test_ramp_cross_term_is_the_exact_discrete_variance(rng, kind, m):
    """_ramp_cross_sd = d_r sd(mean of the differences) against the exact discrete variance.

    The mean of the differences is w . y (checked on a random record, so the telescoping is
    pinned too); white rate (N = 1, fs = 1) gives Var = |w|^2, random-walk rate (K = 1)
    gives Var = sum_j (sum_{i >= j} w_i)^2. The docstring's continuous-time forms differ
    from these sums by the discretisation of the windows: exactly 1/(2 m^2) relative for
    white rate in the triangles (sum of squares m(2 m^2 + 1)/3 vs 2 m^3/3), 0 for the
    boxes, and O(tau/(m^2 L)) for the random walk; 1/m^2 bounds all of them.
    """
    n, r = 20_001, 1e-3
    w = _mean_difference_weights(kind, n, m)
    y = rng.standard_normal(n)
    if kind == "overlapping":
        s = np.convolve(y, np.ones(m), "valid") / m
        direct = np.mean(s[m:] - s[:-m])
    else:
        direct = np.mean(np.diff(y[: (n // m) * m].reshape(-1, m).mean(axis=1)))
    np.testing.assert_allclose(w @ y, direct, rtol=1e-9)
    tau, ms = np.array([float(m)]), np.array([m], dtype=np.int64)
    exact = {"N": w @ w, "K": float(np.sum(np.cumsum(w[::-1])[::-1] ** 2))}
    for name, c in (("N", 1.0), ("K", 1.0 / 3.0)):  # N = 1, K = 1 in AVAR coefficients
        sd = _covariance._ramp_cross_sd((name, "R"), np.array([c, r**2 / 2]), tau, ms, n, kind)[0]
        var = (sd / (r * m)) ** 2  # d_r = R tau
        assert abs(var / exact[name] - 1.0) <= 1.0 / m**2, (name, var / exact[name] - 1.0)


def test_flicker_end_constants_are_the_window_integrals():
    """FitConstants.flicker_end_c: c = 2 Int_0^inf sin^2(lam u) w(u)/u du - ln lam (lam -> inf)
    = gamma + ln 2 + Int_0^1 (w - 1)/u du + Int_1^inf w/u du, w = sinc^4 (triangle) or
    sinc^2 (box); to the 6 digits printed in the module (5e-6)."""
    from scipy import integrate

    for kind, p in (("overlapping", 4), ("standard", 2)):

        def w(u, p=p):
            return (np.sin(u) / u) ** p

        head = integrate.quad(lambda u: (w(u) - 1.0) / u, 0.0, 1.0)[0]
        tail = sum(integrate.quad(lambda u: w(u) / u, k, k + 1.0)[0] for k in range(1, 2000))
        tail += (1.0 / 4.0 if p == 2 else 3.0 / 32.0) / 2000.0**p  # mean sin^p over the rest
        c = np.euler_gamma + math.log(2.0) + head + tail
        assert abs(_kinds.STATISTICS[kind].fit.flicker_end_c - c) <= 5e-6, (kind, c)


def test_short_record_rate_random_walk_and_ramp_not_identifiable(rng):
    """30 min at 10 Hz: K and R dominate only beyond the longest tau (T/4 = 450 s).

    Their upper bounds must hold the truth: one-sided, each at 1e-6/2 (the upper end of the
    two-sided interval at level 1 - 1e-6), so 1e-6 overall.
    """
    fs = 10.0
    y = five_term_model().generate(int(0.5 * 3600 * fs), fs, rng=rng)
    fit = fit_noise(y, fs)
    for k in ("K", "R"):
        c = fit.coefficients[k]
        assert not c.identifiable and c.value is None, k
        assert fit.interval(k, 1.0 - FALSE_ALARM)[1] > FIVE[k], (k, fit.interval(k, 1.0 - FALSE_ALARM))
    for k in ("Q", "N"):
        assert fit.coefficients[k].identifiable
