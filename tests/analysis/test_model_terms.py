"""Independent checks of the model-term shapes (analysis.model_select) and the quiet-stretch curve (analysis.quiet)."""

from __future__ import annotations

import math

import numpy as np
from scipy.signal import butter, sosfilt, sosfiltfilt
from scipy.stats import norm

from gyrobench.analysis.allan import allan_deviation, fit_noise
from gyrobench.analysis.model_select import filter_shape, gm_shape, sine_shape
from gyrobench.analysis.quiet import quiet_curve
from gyrobench.analysis.stationarity import StationarityReport
from gyrobench.sim.noise import GaussMarkov, Sinusoid


def test_filter_shape_matches_simulated_filtered_white_noise():
    """The closed-form (autocovariance) AVAR of white noise through a Butterworth against 4e6 simulated samples,
    once and forward-backward; tolerance: z at two-sided 1e-6 over the 2 x 8 points of the curve's own 68 % bounds
    (half-widths as standard errors)."""
    rng = np.random.default_rng(46)
    fs, n = 10.0, 4_000_000
    z = norm.isf(1e-6 / 2 / 16)
    for passes in (1, 2):
        sos = butter(4, 2.0 / (fs / 2.0), output="sos")
        w = rng.standard_normal(n)
        y = sosfiltfilt(sos, w) if passes == 2 else sosfilt(sos, w)
        c = allan_deviation(y[1000:-1000], fs)
        m = c.m[:8]
        expect = filter_shape(m, 4, 2.0, fs, passes) / m  # sigma = 1
        se = (c.high[:8] ** 2 - c.low[:8] ** 2) / 2.0
        assert np.all(np.abs(c.variance[:8] - expect) <= z * se), (passes, c.variance[:8] / expect)


def test_filter_shape_tends_to_white_noise_and_its_large_tau_deficit():
    """g_f -> 1 - 3 c / (2 m) with c = 1 / (fs sinh(2 pi f_c / fs)) fs for a first-order filter: the sampled
    first-order deficit of analysis.allan.lowpass_avar_bias, an independent derivation."""
    from gyrobench.analysis.allan import lowpass_avar_bias

    fs, fc = 100.0, 5.0
    m = np.array([256, 1024, 4096])
    g = filter_shape(m, 1, fc, fs, 1)
    b = lowpass_avar_bias(m / fs, fc, fs=fs)
    # a digital Butterworth (bilinear) is not the sampled RC filter: the large-tau deficits agree to 15 %
    assert np.all(np.abs((1 - g) / b - 1) < 0.15), (1 - g) / b


def test_sine_and_gauss_markov_shapes_against_sim_noise():
    fs = 10.0
    tau = np.array([0.4, 1.6, 6.4, 25.6, 102.4])
    s = Sinusoid(amplitude=1.0, frequency=1.0 / 37.0)
    assert np.allclose(sine_shape(tau, 37.0, fs), s.avar_sampled(tau, fs), rtol=1e-12)
    # the selector uses the continuous law; the sampled one (ar1_avar, exact) differs by 3 % at m = 4 and
    # by < 0.3 % from m = 16 on, where the fit's points start on a filtered record
    gm = GaussMarkov(sigma=1.0, correlation_time=500.0)
    assert np.allclose(gm_shape(tau[1:], 500.0), gm.avar_sampled(tau[1:], fs), rtol=3e-3)


def test_quiet_curve_of_a_stationary_record_with_flagged_windows_is_unbiased():
    """White noise, 40 windows flagged at random: the quiet curve's N interval holds the truth, and the bridged
    taus lie within their own 99.9 % bounds of N^2 / tau."""
    rng = np.random.default_rng(7)
    fs, n = 10.0, 400_000
    y = rng.standard_normal(n)
    win = 0.8
    k = int(n / (win * fs))
    bad = rng.choice(k, size=40, replace=False)
    rep = StationarityReport(window=win, motion=[(i * win, (i + 1) * win, 10.0) for i in sorted(bad)], steps=[])
    q = quiet_curve(y, fs, rep)
    assert q is not None and q.n_excluded >= 40 * 8
    fit = fit_noise(q.curve, terms=("N", "B", "K"))
    c = fit.coefficients["N"]
    truth = 1.0 / math.sqrt(fs)
    assert c.ci95[0] <= truth <= c.ci95[1], (c.ci95, truth)
    tb = q.curve.tau[q.bridged]
    if tb.size:
        from gyrobench.analysis.allan import deviation_bounds

        dev = q.curve.deviation[q.bridged]
        lo, hi = deviation_bounds(dev, q.curve.edf[q.bridged], 0.999)
        expect = np.sqrt(truth**2 / tb)
        assert np.all((lo <= expect) & (expect <= hi))
