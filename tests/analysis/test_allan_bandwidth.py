"""A stated sensor bandwidth as an input to the fit range (analysis.allan.bandwidth_range).

Closed forms checked against simulation: white rate noise through a first-order low-pass
(discrete AR(1), a = exp(-2 pi f_c / fs)) has the exact Allan variance

    AVAR(m) = (sigma^2 / m) (1 - c (3 - 4 a^m + a^(2m)) / (2 m)),  c = 2 a / (1 - a^2) samples,

(from AVAR = (4 D(m) - D(2m)) / (2 m^2), D(m) = Var of a sum of m samples), the first-order
deficit of :func:`lowpass_avar_bias` with T fs replaced by c = 1/sinh(2 pi f_c / fs) <= T fs.
For any other filter the same D(m) from the autocorrelation of its impulse response gives the
exact curve (here a 4th-order Butterworth). Tolerances: the spread over independent records
(Student t at a family-wise false-alarm rate of 1e-6, Bonferroni over the points).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import signal, stats

from gyrobench.analysis.allan import (
    BANDWIDTH_BIAS,
    _kinds,
    allan_deviation,
    bandwidth_range,
    fit_noise,
    lowpass_avar_bias,
)

FS = 100.0
F_C = 1.0  # Hz
SIGMA = 1.0  # rate noise per sample; N = SIGMA / sqrt(FS)
FALSE_ALARM = 1e-6
RECORDS, N_REC = 16, 1 << 17


def _ar1_exact(m: np.ndarray, a: float) -> np.ndarray:
    """Exact AVAR(m) / (sigma^2 / m) of white noise through y_k = a y_(k-1) + (1 - a) x_k."""
    c = 2.0 * a / (1.0 - a * a)
    return 1.0 - c * (3.0 - 4.0 * a**m + a ** (2 * m)) / (2.0 * m)


def _filter_exact(m: np.ndarray, h: np.ndarray) -> np.ndarray:
    """Exact AVAR(m) / (sigma^2 / m) of white noise (unit variance) through the FIR/IIR impulse response h."""
    h = h / h.sum()  # unit DC gain
    # the IIR tail below 1e-20 of the peak adds nothing in float64, and its products are
    # subnormal numbers that made np.correlate take 10-100 s instead of 0.1 s
    h = h[: int(np.flatnonzero(np.abs(h) > 1e-20 * np.abs(h).max())[-1]) + 1]
    r = np.correlate(h, h, mode="full")[h.size - 1 :]  # R[j], j >= 0

    def d(mm: int) -> float:  # Var(sum of mm samples) = sum_{|j|<mm} (mm - |j|) R[j]
        j = np.arange(min(mm, r.size))
        return float(mm * r[0] + 2.0 * np.sum((mm - j[1:]) * r[j[1:]]))

    return np.array([(4 * d(int(k)) - d(2 * int(k))) / (2.0 * k * k) * k for k in m])


def _ratios(filt, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """AVAR / (sigma^2/m) of each of RECORDS independent filtered records: (m, ratios[record, m])."""
    g = np.random.default_rng(seed)
    out = []
    for _ in range(RECORDS):
        c = allan_deviation(filt(SIGMA * g.standard_normal(N_REC)), FS)
        out.append(c.variance * c.m / SIGMA**2)
    return c.m, np.array(out)


def _t_tolerance(x: np.ndarray) -> np.ndarray:
    k = x.shape[1]
    t = stats.t.isf(FALSE_ALARM / (2 * k), x.shape[0] - 1)
    return t * x.std(axis=0, ddof=1) / math.sqrt(x.shape[0])


def test_first_order_closed_form_against_simulation():
    a = math.exp(-2 * math.pi * F_C / FS)
    m, r = _ratios(lambda x: signal.lfilter([1 - a], [1, -a], x), 20261124)
    want = _ar1_exact(m.astype(float), a)
    assert np.all(np.abs(r.mean(axis=0) - want) <= _t_tolerance(r)), (r.mean(axis=0), want)
    # the test can tell: at m = 8 .. 64 the deficit is 0.96 .. 0.35, far outside the tolerance
    assert np.all(want[3:7] < 0.7)
    # lowpass_avar_bias at the record's fs is this closed form; in continuous time T fs >= c
    np.testing.assert_allclose(lowpass_avar_bias(m / FS, F_C, fs=FS), 1 - want, rtol=1e-12)
    b = lowpass_avar_bias(m / FS, F_C)
    scale = (FS / (2 * math.pi * F_C)) * math.sinh(2 * math.pi * F_C / FS)  # T fs / c
    np.testing.assert_allclose(b, (1 - want) * scale, rtol=1e-12)
    assert np.all(b >= 1 - want)


def test_fourth_order_butterworth_closed_form_and_first_order_bound():
    sos = signal.butter(4, F_C, fs=FS, output="sos")
    m, r = _ratios(lambda x: signal.sosfilt(sos, x), 20261125)
    imp = np.zeros(1 << 14)
    imp[0] = 1.0
    want = _filter_exact(m.astype(float), signal.sosfilt(sos, imp))
    assert np.all(np.abs(r.mean(axis=0) - want) <= _t_tolerance(r)), (r.mean(axis=0), want)
    # large-tau deficit 3 c / (2 tau), c = 1/(2 pi n f_c sin(pi/(2n))) for an n-th order Butterworth
    big = m >= 512
    c_n = 1.0 / (2 * math.pi * 4 * F_C * math.sin(math.pi / 8))
    np.testing.assert_allclose((1 - want[big]) * (m[big] / FS) * 2 / 3, c_n, rtol=0.03)
    # from tau = 1/f_c on, the first-order deficit at the same -3 dB frequency bounds it
    tail = m >= FS / F_C
    assert np.all(1 - want[tail] <= lowpass_avar_bias(m[tail] / FS, F_C, fs=FS))
    assert np.any(1 - want[~tail] > lowpass_avar_bias(m[~tail] / FS, F_C, fs=FS))  # and not before


def _white_se(curve) -> np.ndarray:
    nu0 = _kinds._edf(curve.kind, np.zeros(curve.m.size, dtype=np.int64), curve.m, curve.n_samples)
    return np.sqrt(2.0 / nu0)


def test_rule_starts_at_the_first_tau_whose_bias_is_below_the_stated_fraction():
    g = np.random.default_rng(7)
    a = math.exp(-2 * math.pi * F_C / FS)
    n = 1 << 20
    y = signal.lfilter([1 - a], [1, -a], SIGMA * g.standard_normal(n))
    curve = allan_deviation(y, FS)
    fr = bandwidth_range(curve, F_C)
    j = fr.excluded
    assert fr.tau_min == pytest.approx(curve.tau[j])
    se = _white_se(curve)
    exact = 1 - _ar1_exact(curve.m.astype(float), a)
    # at the start the exact bias is below the fraction of the standard error; one octave earlier it is not
    assert exact[j] <= BANDWIDTH_BIAS * se[j]
    assert exact[j - 1] > BANDWIDTH_BIAS * se[j - 1]
    # the asymptotic solution (3/(4 pi f_c bias))^(2/3) (3 T_rec/4)^(1/3) lies within that octave
    t_rec = n / FS
    approx = (3 / (4 * math.pi * F_C * BANDWIDTH_BIAS)) ** (2 / 3) * (3 * t_rec / 4) ** (1 / 3)
    assert curve.tau[j - 1] < approx <= curve.tau[j]
    # a stricter fraction starts later
    assert bandwidth_range(curve, F_C, bias=0.01).tau_min > fr.tau_min
    # the fit from there recovers N (white level) within its interval at the stated false-alarm rate
    fit = fit_noise(curve, terms=("N",), tau_min=None, bandwidth=F_C)
    assert fit.range_rule == "bandwidth" and fit.tau_used[0] == pytest.approx(fr.tau_min)
    lo, hi = fit.interval("N", 1 - FALSE_ALARM)
    assert lo <= SIGMA / math.sqrt(FS) <= hi
    # without the rule the first octaves pull the white level far down: out of its interval
    fit0 = fit_noise(curve, terms=("N",), tau_min=None)
    lo0, hi0 = fit0.interval("N", 1 - FALSE_ALARM)
    assert hi0 < SIGMA / math.sqrt(FS)


def test_rules_combine_the_larger_tau_min_wins():
    g = np.random.default_rng(8)
    curve = allan_deviation(g.standard_normal(200_000), FS)
    bw = bandwidth_range(curve, 10.0)
    assert bw.tau_min is not None
    f = fit_noise(curve, tau_min=bw.tau_min * 4, bandwidth=10.0)
    assert f.range_rule == "user" and f.tau_used[0] == pytest.approx(bw.tau_min * 4)
    f = fit_noise(curve, tau_min=bw.tau_min / 4, bandwidth=10.0)
    assert f.range_rule == "bandwidth" and f.tau_used[0] == pytest.approx(bw.tau_min)
    assert "stated bandwidth 10 Hz" in f.range_reason
    f = fit_noise(curve, tau_min="auto", bandwidth=10.0)  # white noise: nothing filter-shaped in the data
    assert f.range_rule == "bandwidth"
    f = fit_noise(curve, tau_min="auto")
    assert f.range_rule == "" and f.tau_used[0] == curve.tau[0]
    # any stated bandwidth (< fs/2) excludes at least the taus below 1/f_c
    short = allan_deviation(g.standard_normal(2_000), FS)
    assert bandwidth_range(short, 49.0).tau_min >= 1 / 49.0 > short.tau[0]


@pytest.mark.parametrize(
    ("bw", "exc", "match"),
    [
        (0.0, ValueError, "bandwidth must be finite and > 0 Hz; got 0.0"),
        (-3.0, ValueError, "bandwidth must be finite and > 0 Hz; got -3.0"),
        (50.0, ValueError, "bandwidth must be < the Nyquist frequency fs/2 = 50 Hz"),
        (80.0, ValueError, "got 80 Hz"),
        (math.nan, ValueError, "bandwidth must be finite"),
        ("10", TypeError, "bandwidth must be a real number [Hz]; got '10'"),
        (True, TypeError, "bandwidth must be a real number"),
    ],
)
def test_bad_bandwidth_is_refused_in_one_line(bw, exc, match):
    curve = allan_deviation(np.random.default_rng(1).standard_normal(10_000), FS)
    with pytest.raises(exc) as info:
        fit_noise(curve, bandwidth=bw)
    assert match in str(info.value) and "\n" not in str(info.value)


def test_a_vanishing_bandwidth_gives_the_series_limit_not_inf_times_zero():
    # 3 - 4 e^-x + e^-2x = 2x - 2x^3/3 + O(x^4), so b = 1 - x^2/3 for x = 2 pi f_c tau << 1; at the
    # smallest float T' = 1/(2 pi f_c) overflows to inf, which once made b = inf * 0 = nan
    tau = np.array([0.1, 1.0, 10.0, 100.0])
    x = 2 * np.pi * 1e-9 * tau
    np.testing.assert_allclose(lowpass_avar_bias(tau, 1e-9), 1 - x**2 / 3, rtol=1e-12)
    np.testing.assert_allclose(lowpass_avar_bias(tau, 1e-9, fs=10.0), 1 - x**2 / 3, rtol=1e-12)
    assert np.array_equal(lowpass_avar_bias(tau, 5e-324), np.ones(4))
    assert np.array_equal(lowpass_avar_bias(tau, 5e-324, fs=10.0), np.ones(4))
