"""Tests of sim/noise.py: closed forms, generation statistics, chunking, validation.

Statistical tests use fixed seeds and chi-square bands: the overlapping AVAR
estimate A at cluster size m satisfies A ~ A_true chi2(edf)/edf with edf from
allantools' Greenhall algorithm (NIST SP 1065 / Greenhall 2004): the smallest
over the noise types that carry >= 10 % of the AVAR at that tau. Each record is checked at
every octave tau up
to T/10 against a two-sided band at level ALPHA/n_tau (Bonferroni), so the
false-alarm probability of each record test is <= ALPHA = 1e-3.
"""

from __future__ import annotations

import math

import allantools
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import integrate, optimize, stats

from gyrobench.sim import noise as nz
from gyrobench.sim.noise import GaussMarkov, NoiseModel, Sinusoid, ar1_avar, flicker_avar, gm_avar

ALPHA = 1e-3
PLATEAU = 2.0 * math.log(2.0) / math.pi  # flicker AVAR / B^2


# ---------------------------------------------------------------------------- helpers
def _octave_taus(n: int, fs: float, m_min: int = 1) -> np.ndarray:
    m = m_min * 2 ** np.arange(40)
    return m[m <= n / 10] / fs


def _edf(alpha: int, m: int, n_freq: int) -> float:
    return float(
        allantools.edf_greenhall(alpha=alpha, d=2, m=int(m), N=n_freq + 1, overlapping=True)
    )


_ALPHA_OF = {
    "quantization": 2,
    "angle_random_walk": 0,
    "bias_instability": -1,
    "rate_random_walk": -2,
}


def _check_record(model: NoiseModel, y: np.ndarray, fs: float) -> None:
    """Every octave tau up to T/10: estimate inside the chi-square band of the closed form.

    The edf is the smallest Greenhall edf among the noise types contributing >= 10 % of
    the AVAR at that tau (a wider band when types mix; never a narrower one).
    """
    taus = _octave_taus(len(y), fs)
    t, ad, _, _ = allantools.oadev(y, rate=fs, data_type="freq", taus=taus)
    assert np.allclose(t, taus)
    est = ad**2
    terms = model.term_avars(t, fs=fs)
    total = model.theoretical_avar(t, fs=fs)
    p = ALPHA / len(t)
    for i, tau in enumerate(t):
        m = int(round(tau * fs))
        alphas = [
            _ALPHA_OF[k] for k, v in terms.items() if k in _ALPHA_OF and v[i] >= 0.1 * total[i]
        ]
        assert alphas, f"no stochastic term at tau={tau}"
        edf = min(_edf(a, m, len(y)) for a in alphas)
        lo = total[i] * stats.chi2.ppf(p / 2, edf) / edf
        hi = total[i] * stats.chi2.ppf(1 - p / 2, edf) / edf
        assert lo <= est[i] <= hi, (
            f"tau={tau:g} s (m={m}): AVAR {est[i]:.6g} outside [{lo:.6g}, {hi:.6g}] "
            f"(theory {total[i]:.6g}, edf {edf:.1f}, ratio {est[i] / total[i]:.4f})"
        )


#: five-term model (datasheet units) in which every term is the largest one over a range of
#: the octave taus tested on 2**21 samples at 100 Hz (0.01 s .. T/10 = 1311 s): Q up to
#: 0.08 s, N 0.16-2.6 s, B 5-41 s (59-70 % of the AVAR), K 82-164 s, R 328-1311 s (51-83 %).
#: Crossovers chosen in AVAR C_n units: Q/N 0.15 s, N/B 3 s, B/K 80 s, K/R 250 s.
#: The ramp is deterministic: the band is the chi-square band of the total scaled by the
#: edf of the stochastic terms (>= 10 % each, K carries 16 % at 1311 s), wider than the
#: band of the noise part alone, so the false-alarm rate stays <= ALPHA.
FIVE = dict(
    quantization=0.13,
    angle_random_walk=0.0096,
    bias_instability=0.5,
    rate_random_walk=3.9,
    rate_ramp=12.0,
)


# ---------------------------------------------------------------------------- closed forms (1e-12)
def test_white_terms_closed_form():
    m = NoiseModel(quantization=2e-6, angle_random_walk=3e-5)
    tau = np.array([0.01, 0.1, 1.0, 7.3])
    t = m.term_avars(tau, fs=100.0)
    np.testing.assert_allclose(t["quantization"], 3 * 2e-6**2 / tau**2, rtol=1e-12)
    np.testing.assert_allclose(t["angle_random_walk"], 3e-5**2 / tau, rtol=1e-12)


def test_ramp_closed_form():
    tau = np.array([0.5, 3.0, 100.0])
    np.testing.assert_allclose(
        NoiseModel(rate_ramp=2e-9).theoretical_avar(tau, fs=10.0), 2e-9**2 * tau**2 / 2, rtol=1e-12
    )


def test_rrw_discrete_formula_matches_brute_force():
    """K^2 tau/3 (1 + 1/(2m^2)): sum of squared increment weights of a point-sampled random walk."""
    k, fs = 3e-7, 20.0
    for m in (1, 2, 3, 7, 40):
        # weight of increment j (j = 2..2m) in the difference of two consecutive block means
        w = np.array([min(j - 1, 2 * m + 1 - j) for j in range(2, 2 * m + 1)]) / m
        brute = 0.5 * k**2 / fs * np.sum(w**2)
        got = NoiseModel(rate_random_walk=k).theoretical_avar(m / fs, fs=fs)
        np.testing.assert_allclose(got, brute, rtol=1e-12)
        np.testing.assert_allclose(got, k**2 * (m / fs) / 3 * (1 + 0.5 / m**2), rtol=1e-12)


def _ar1_brute(m: int, u: float) -> float:
    phi = math.exp(-u)
    j = np.arange(-(m - 1), m)
    var_mean = np.sum((m - np.abs(j)) * phi ** np.abs(j)) / m**2
    cov_next = np.sum((m - np.abs(j)) * phi ** np.abs(m + j)) / m**2
    return var_mean - cov_next


@pytest.mark.parametrize("u", [1e-6, 1e-3, 0.05, 0.7, 3.0, 20.0])
def test_ar1_avar_matches_brute_force(u):
    ms = np.array([1, 2, 3, 5, 16, 100])
    brute = np.array([_ar1_brute(int(m), u) for m in ms])
    # brute force loses ~u^-1 digits to cancellation; the closed form is the accurate one
    np.testing.assert_allclose(ar1_avar(ms, u), brute, rtol=max(1e-12, 1e-15 / u**2), atol=0)


def test_ar1_avar_tends_to_continuous_gm():
    tc, sigma = 2.0, 1.3
    tau = np.array([0.1, 1.0, 3.78, 20.0])
    fs = 1e6
    np.testing.assert_allclose(
        GaussMarkov(sigma=sigma, correlation_time=tc).avar_sampled(tau, fs),
        gm_avar(tau, sigma, tc),
        rtol=1e-6,
    )


def test_gm_continuous_matches_physics_formula_and_peak():
    tc, sigma = 5.0, 2.0
    qc = math.sqrt(2 * sigma**2 / tc)
    tau = np.array([0.3, 5.0, 9.46, 80.0])
    r = tau / tc
    phys = (qc * tc) ** 2 / tau * (1 - tc / (2 * tau) * (3 - 4 * np.exp(-r) + np.exp(-2 * r)))
    np.testing.assert_allclose(gm_avar(tau, sigma, tc), phys, rtol=1e-12)
    # ADEV peak at tau = 1.893 Tc with value 0.4365 qc sqrt(Tc) (docs/physics.md 1.2)
    res = optimize.minimize_scalar(
        lambda x: -gm_avar(x * tc, sigma, tc),
        bounds=(0.5, 5),
        method="bounded",
        options={"xatol": 1e-10},
    )
    assert res.x == pytest.approx(1.8926, abs=5e-4)
    assert math.sqrt(-res.fun) / (qc * math.sqrt(tc)) == pytest.approx(0.4365, abs=5e-5)


def test_gm_small_tau_is_rate_random_walk_without_cancellation():
    tc, sigma = 1e5, 1.0
    tau = 1e-3
    qc2 = 2 * sigma**2 / tc
    np.testing.assert_allclose(
        gm_avar(tau, sigma, tc), qc2 * tau / 3 * (1 - 3 * tau / (4 * tc)), rtol=1e-9
    )


def test_sinusoid_zeros_at_multiples_of_period():
    s = Sinusoid(amplitude=2.0, frequency=0.25)
    tau = np.array([4.0, 8.0, 12.0])
    assert np.all(s.avar(tau) < 1e-28)
    assert np.all(s.avar_sampled(tau, fs=100.0) < 1e-28)


def test_sinusoid_sampled_factor_and_brute_force():
    s = Sinusoid(amplitude=1.5, frequency=3.0, phase=0.3)
    fs = 10.0
    x = math.pi * s.frequency / fs
    tau = np.array([0.1, 0.3, 0.7, 1.1])
    np.testing.assert_allclose(
        s.avar_sampled(tau, fs), s.avar(tau) * (x / math.sin(x)) ** 2, rtol=1e-12
    )
    # brute force: phase-averaged overlapping AVAR of the sampled sine
    # (exact over full periods of 10 samples)
    n = 10 * 2000
    y = s.amplitude * np.sin(2 * np.pi * s.frequency * np.arange(n) / fs + s.phase)
    for m in (1, 3, 7, 11):
        th = np.concatenate([[0.0], np.cumsum(y)]) / fs
        d = th[2 * m :] - 2 * th[m:-m] + th[: -2 * m]
        d = d[: (len(d) // 10) * 10]
        est = np.mean(d**2) / (2 * (m / fs) ** 2)
        np.testing.assert_allclose(est, s.avar_sampled(m / fs, fs), rtol=1e-9)


def test_sinusoid_peak_location():
    s = Sinusoid(amplitude=1.0, frequency=1.0)
    res = optimize.minimize_scalar(
        lambda t: -s.avar(t), bounds=(0.1, 0.9), method="bounded", options={"xatol": 1e-10}
    )
    assert res.x == pytest.approx(0.3710, abs=2e-4)
    assert math.sqrt(-res.fun) == pytest.approx(0.7246, abs=2e-4)


def test_flicker_avar_plateau_limit():
    b = 3e-6
    np.testing.assert_allclose(flicker_avar([1e3, 1e4], b, 1e-12, 1e6), PLATEAU * b**2, rtol=1e-9)


def test_flicker_avar_small_tau_limit():
    b, f0 = 2e-6, 10.0
    tau = np.array([1e-6, 1e-5])
    np.testing.assert_allclose(
        flicker_avar(tau, b, 1e-9, f0), math.pi * b**2 * f0**2 * tau**2, rtol=1e-6
    )


def test_flicker_avar_matches_quadrature():
    b, lo, hi = 1.0, 0.01, 5.0
    for tau in (0.05, 0.4, 3.0, 40.0):
        val, _ = integrate.quad(
            lambda f, tau=tau: (
                4 * b**2 / (2 * np.pi * f) * np.sin(np.pi * f * tau) ** 4 / (np.pi * f * tau) ** 2
            ),
            lo,
            hi,
            limit=2000,
            epsabs=0,
            epsrel=1e-12,
        )
        np.testing.assert_allclose(flicker_avar(tau, b, lo, hi), val, rtol=1e-9)


def test_flicker_avar_physics_table():
    # sigma/B = 0.270 (x=0.5), 0.480 (1), 0.647 (2), 0.661 (5), 0.664 (>=20), f_low -> 0
    # (docs/physics.md 1.3);
    # printed with 3 digits, apparently truncated (0.2707 -> 0.270): one unit of the last digit
    x = np.array([0.5, 1.0, 2.0, 5.0, 20.0])
    got = np.sqrt(flicker_avar(x / np.pi, 1.0, 1e-15, 1.0))
    np.testing.assert_allclose(got, [0.270, 0.480, 0.647, 0.661, 0.664], atol=1e-3)


# ---------------------------------------------------------------------------- the flicker pole sum
def test_pole_sum_weights_and_spacing():
    b, fs = 2e-6, 100.0
    tc, sig = NoiseModel(bias_instability=b).flicker_poles(fs)
    np.testing.assert_allclose(tc[1:] / tc[:-1], math.sqrt(10.0), rtol=1e-12)
    np.testing.assert_allclose(sig**2, b**2 * math.log(math.sqrt(10.0)) / math.pi, rtol=1e-12)
    assert tc[0] == pytest.approx(10**0.25 / (2 * math.pi * fs / 2), rel=1e-12)
    assert tc[-1] >= 1 / (2 * math.pi * 1e-6)


def test_pole_sum_plateau_ripple():
    """The documented flatness: ADEV within +-1 % of 0.6643 B for 3.5/fs <= tau <= 0.014/f_low."""
    fs = 100.0
    m = NoiseModel(bias_instability=1.0)
    tau = np.logspace(np.log10(3.5 / fs), np.log10(0.014 / 1e-6), 400)
    ratio = np.sqrt(m.theoretical_avar(tau, fs=fs) / PLATEAU)
    assert np.all(np.abs(ratio - 1) <= 0.01), (ratio.min(), ratio.max())
    assert math.log10(tau[-1] / tau[0]) > 5.5


def test_pole_sum_psd_within_documented_band():
    """PSD within +-0.15 dB of B^2/(2 pi f) from 9 f_low to fs/3 (sampled pole sum)."""
    fs, b = 100.0, 1.0
    tc, sig = NoiseModel(bias_instability=b).flicker_poles(fs)
    f = np.logspace(np.log10(9e-6), np.log10(fs / 3), 2000)
    phi = np.exp(-1 / (fs * tc))
    s = (
        np.sum(
            sig**2 * (1 - phi**2) / np.abs(1 - phi * np.exp(-2j * np.pi * f[:, None] / fs)) ** 2,
            axis=1,
        )
        / fs
    )
    db = 10 * np.log10(s / (b**2 / (2 * np.pi * f)))
    assert np.max(np.abs(db)) <= 0.15


def test_pole_sum_tracks_brick_wall_inside_band():
    fs = 100.0
    m = NoiseModel(bias_instability=1.0)
    tau = np.logspace(-1, 3, 50)
    np.testing.assert_allclose(
        m.theoretical_avar(tau, fs=fs), flicker_avar(tau, 1.0, 1e-6, fs / 2), rtol=0.02
    )


def test_arma_spectral_factor_has_pole_sum_autocovariance():
    """One-input ARMA == sum of independent AR(1): autocovariances agree (lag 0..5000)."""
    u = np.array([3.0, 0.9, 0.3, 0.1, 0.03, 0.01, 0.003, 0.001])
    var = np.full(len(u), 0.7)
    b, a, rho, phi, us, zeta, g = nz._sum_of_ar1_as_arma(u, var)
    lags = np.array([0, 1, 2, 5, 30, 300, 5000])
    want = np.sum(np.sort(var)[None, :] * np.exp(-np.outer(lags, us)), axis=1)
    cross = np.outer(rho, rho) / -np.expm1(-(us[:, None] + us[None, :]))
    got = np.array([np.sum(cross * phi[None, :] ** lag) for lag in lags])
    np.testing.assert_allclose(got, want, rtol=1e-9)


def test_sos_realisation_matches_partial_fractions():
    """The second-order sections realise the factor's impulse response to 1e-9 (u = 3 .. 1e-3)."""
    from scipy import signal

    for u in (
        np.array([3.0, 0.9, 0.3, 0.1, 0.03, 0.01, 0.003, 0.001]),
        np.array([1.7, 0.5, 0.17, 0.05, 0.017, 0.005, 0.0017]),
    ):
        _, _, rho, phi, _, zeta, g = nz._sum_of_ar1_as_arma(u, np.full(len(u), 0.7))
        sos = nz._sos_from_roots(zeta, phi, g)
        imp = signal.sosfilt(sos, np.r_[1.0, np.zeros(9999)])
        want = np.sum(rho[None, :] * phi[None, :] ** np.arange(10000)[:, None], axis=1)
        np.testing.assert_allclose(imp, want, rtol=1e-9)


@pytest.mark.parametrize(
    "u",
    [
        np.array([0.004, 0.0013]),
        np.array([3.0, 0.9, 0.3, 0.1, 0.03, 0.01, 0.003, 0.001]),
        np.array([0.5]),
    ],
)
def test_sos_stationary_state_has_pole_sum_variance(u):
    """Output variance from the drawn initial state's covariance = sum of pole variances (1e-9)."""
    var = np.linspace(0.5, 1.0, len(u))
    _, _, _, phi, _, zeta, g = nz._sum_of_ar1_as_arma(u, var)
    sos = nz._sos_from_roots(zeta, phi, g)
    a_mat, b_vec = nz._sos_state_space(sos)
    from scipy import linalg

    cov = linalg.solve_discrete_lyapunov(a_mat, np.outer(b_vec, b_vec))
    # output y = C z + D eps with C, D read from the state-space rows of the last section's y
    n = a_mat.shape[0]
    x = np.zeros(n + 1)
    x[n] = 1.0
    for s in range(sos.shape[0]):
        z0 = np.zeros(n + 1)
        z0[2 * s] = 1.0
        x = sos[s, 0] * x + z0
    c, d = x[:n], x[n]
    # the Lyapunov solution carries ~cond * eps ~ eps/u_min^2 relative error (1e-8 at u = 1.3e-3)
    np.testing.assert_allclose(c @ cov @ c + d**2, np.sum(var), rtol=1e-7)
    # lag-1 covariance too: E[y_{k+1} y_k] = C A Sigma C^T + C B D
    np.testing.assert_allclose(
        c @ a_mat @ cov @ c + (c @ b_vec) * d, np.sum(var * np.exp(-u)), rtol=1e-7
    )


def _interp_avar(c: float, ratio: int, ms: np.ndarray) -> np.ndarray:
    """Exact phase-averaged AVAR of a unit-variance AR(1) (T = c h) sampled every h = ratio
    fine steps and linearly interpolated, at fine cluster sizes ms."""
    phi = math.exp(-1.0 / c)
    lag = np.arange(2 * int(ms.max()) + 2)
    rbar = np.zeros(len(lag))
    for r in range(ratio):
        k2 = r + lag
        j2, r2 = k2 // ratio, k2 % ratio
        w1a, w1b, w2a, w2b = 1 - r / ratio, r / ratio, 1 - r2 / ratio, r2 / ratio
        cov = lambda d: phi ** np.abs(d)  # noqa: E731
        rbar += (
            w1a * w2a * cov(j2)
            + w1a * w2b * cov(j2 + 1)
            + w1b * w2a * cov(j2 - 1)
            + w1b * w2b * cov(j2)
        )
    rbar /= ratio

    def dsum(n):
        ll = np.arange(1, n)
        return n * rbar[0] + 2 * np.sum((n - ll) * rbar[1:n])

    return np.array([(4 * dsum(m) - dsum(2 * m)) / (2 * m * m) for m in ms])


@pytest.mark.parametrize("fs", [1000.0, 10.0])
def test_decimation_error_bound(fs):
    """The documented decimation error (default band): < 0.1 % of the flicker AVAR at every tau.

    Upper bound: every pole of levels 1 and 2 counted with its full interpolation deficit
    (the bridges the generator adds between coarse levels only make the real deficit smaller),
    exact phase-averaged, relative to the pole sum's AVAR, for tau up to 60 knot spacings of
    level 2 (coarser levels act at longer tau the same way). The default band gets no
    full-rate bridge: the fast poles dominate the short-tau AVAR.
    """
    model = NoiseModel(bias_instability=1.0)
    tc, sig = model.flicker_poles(fs)
    fl = nz._Flicker(tc, sig**2, 1.0 / fs, np.random.default_rng(0))
    assert fl.fine is not None and fl.fine_bridge is None
    ms = np.unique(np.round(np.logspace(0, math.log10(60 * nz._LEVEL_RATIO**2), 40)).astype(int))
    deficit = np.zeros(len(ms))
    n_checked = 0
    for t, s in zip(tc, sig, strict=True):
        h = _level_step(t * fs)
        if h in (nz._LEVEL_RATIO, nz._LEVEL_RATIO**2):
            deficit += (ar1_avar(ms, 1.0 / (t * fs)) - _interp_avar(t * fs / h, h, ms)) * s**2
            n_checked += 1
    assert n_checked >= 3
    total = model.theoretical_avar(ms / fs, fs=fs)
    assert np.all(deficit >= -1e-12 * total)
    assert np.max(deficit / total) < 1e-3, np.max(deficit / total)


def _level_step(t_over_dt: float) -> int:
    """Knot spacing (in samples) the generator uses for a pole (mirrors _Flicker's rule)."""
    if t_over_dt < nz._DECIM_MARGIN * nz._LEVEL_RATIO:
        return 1
    lv = int(math.floor(math.log(t_over_dt / nz._DECIM_MARGIN) / math.log(nz._LEVEL_RATIO) + 1e-12))
    return nz._LEVEL_RATIO**lv


def _bridge_avar(v: float, ratio: int, ms: np.ndarray) -> np.ndarray:
    """Exact phase-averaged AVAR of consecutive independent discrete Brownian bridges
    (step variance v, zero at knots every ``ratio`` samples)."""
    lag = np.arange(2 * int(ms.max()) + 2)
    rbar = np.zeros(len(lag))
    for ll in range(ratio):
        r = np.arange(0, ratio - ll)
        rbar[ll] = v / ratio * np.sum(r - r * (r + ll) / ratio)

    def dsum(n):
        k = np.arange(1, n)
        return n * rbar[0] + 2 * np.sum((n - k) * rbar[1:n])

    return np.array([(4 * dsum(m) - dsum(2 * m)) / (2 * m * m) for m in ms])


@pytest.mark.parametrize("c", [256.0, 809.5, 2560.0])
def test_bridge_restores_decimated_pole(c):
    """Interpolated knots + Brownian bridge of rate 2 sigma^2/T == the full-rate pole.

    Measured 2.5e-6 (256 h/T)^2 relative.

    (Without the bridge the deficit is up to ~100 % of the pole's AVAR at tau << h.)
    """
    ratio = nz._LEVEL_RATIO
    ms = np.unique(np.round(np.logspace(0, math.log10(60 * ratio), 30)).astype(int))
    full = ar1_avar(ms, 1.0 / (c * ratio))
    interp = _interp_avar(c, ratio, ms)
    bridged = interp + _bridge_avar(2.0 / (c * ratio), ratio, ms)
    assert np.max(np.abs(full - bridged) / full) < 1e-5 * (256.0 / c) ** 2
    assert np.max((full - interp) / full) > 0.5


# ---------------------------------------------------------------------------- generation statistics
FS = 100.0
N_REC = 1 << 20


@pytest.mark.parametrize(
    "name, kwargs, seed",
    [
        ("quantization", dict(quantization=0.5), 11),
        ("angle_random_walk", dict(angle_random_walk=0.05), 12),
        ("bias_instability", dict(bias_instability=0.5), 13),
        ("rate_random_walk", dict(rate_random_walk=2.0), 14),
    ],
)
def test_each_term_adev_within_chi2_band(name, kwargs, seed):
    model = NoiseModel.from_datasheet(**kwargs)
    y = model.generate(N_REC, FS, rng=np.random.default_rng(seed))
    _check_record(model, y, FS)


def test_rate_ramp_adev_is_deterministic():
    model = NoiseModel.from_datasheet(rate_ramp=1.0)
    y = model.generate(N_REC, FS, rng=np.random.default_rng(15))
    taus = _octave_taus(N_REC, FS)
    t, ad, _, _ = allantools.oadev(y, rate=FS, data_type="freq", taus=taus)
    np.testing.assert_allclose(ad**2, model.theoretical_avar(t, fs=FS), rtol=1e-6)


def test_five_terms_adev_within_chi2_band():
    model = NoiseModel.from_datasheet(**FIVE)
    tau = _octave_taus(1 << 21, FS)
    terms = model.term_avars(tau, fs=FS)
    largest = [max(terms, key=lambda k: terms[k][i]) for i in range(tau.size)]
    for name in ("bias_instability", "rate_random_walk", "rate_ramp"):
        assert largest.count(name) >= 2, (name, largest)  # each term shows on the tested curve
    y = model.generate(1 << 21, FS, rng=np.random.default_rng(16))
    _check_record(model, y, FS)


def test_gauss_markov_term_adev_within_chi2_band():
    gm = GaussMarkov(sigma=1e-4, correlation_time=2.0)
    model = NoiseModel(gauss_markov=(gm,))
    y = model.generate(N_REC, FS, rng=np.random.default_rng(17))
    taus = _octave_taus(N_REC, FS)
    t, ad, _, _ = allantools.oadev(y, rate=FS, data_type="freq", taus=taus)
    th = model.theoretical_avar(t, fs=FS)
    p = ALPHA / len(t)
    for i, tau in enumerate(t):
        m = int(round(tau * FS))
        edf = min(_edf(a, m, N_REC) for a in (0, -2))  # GM is RRW-like below Tc, white above
        assert (
            th[i] * stats.chi2.ppf(p / 2, edf) / edf
            <= ad[i] ** 2
            <= th[i] * stats.chi2.ppf(1 - p / 2, edf) / edf
        )


def test_flicker_starts_stationary():
    """Var of the first sample over independent starts = sum of pole variances (chi2, 1e-3)."""
    model = NoiseModel(bias_instability=1.0)
    fs = 100.0
    k = 200
    first = np.array(
        [model.generate(1, fs, rng=np.random.default_rng([99, i]))[0] for i in range(k)]
    )
    var_true = np.sum(model.flicker_poles(fs)[1] ** 2)
    stat = np.sum(first**2) / var_true  # chi2(k) under H0 (zero mean)
    assert stats.chi2.ppf(ALPHA / 2, k) <= stat <= stats.chi2.ppf(1 - ALPHA / 2, k)


def _streaming_oavar(model, fs, n, ms, seed, chunk=1 << 22):
    """Overlapping AVAR at cluster sizes ms of an n-sample record, reduced chunk by chunk."""
    stream = model.stream(fs, rng=np.random.default_rng(seed))
    mmax = int(max(ms))
    tail = np.zeros(0)  # last 2*mmax angle samples carried over
    acc = np.zeros(len(ms))
    count = np.zeros(len(ms))
    theta_last = 0.0
    for y in stream.chunks(n, chunk):
        th = np.cumsum(y) / fs + theta_last
        theta_last = th[-1]
        th = np.concatenate([tail, th]) if len(tail) else np.concatenate([[0.0], th])
        start = len(tail) if len(tail) else 0
        for i, m in enumerate(ms):
            # second differences whose last index lies in this chunk's new samples
            lo = max(2 * m, start)
            d = th[lo:] - 2 * th[lo - m : len(th) - m] + th[lo - 2 * m : len(th) - 2 * m]
            acc[i] += np.dot(d, d)
            count[i] += len(d)
        tail = th[-2 * mmax :]
    taus = np.asarray(ms) / fs
    return acc / count / (2 * taus**2)


@pytest.mark.slow
def test_flicker_plateau_flat_over_four_decades():
    """ADEV within +-5 % of 0.6643 B for tau = 3..30000 samples (4 decades).

    n = 2^28 samples. Before asserting, the test checks that at every tau the
    (1 - ALPHA/n_tau) chi-square band of the estimate around the pole-sum theory lies
    inside +-5 % of the plateau, so a correct generator fails with probability <= ALPHA.
    """
    fs = 1.0
    model = NoiseModel(bias_instability=1.0, flicker_band=(1e-9, math.inf))
    n = 1 << 28
    ms = np.array([3 * 2**k for k in range(14)] + [30000])
    theory = model.theoretical_avar(ms / fs, fs=fs)
    p = ALPHA / len(ms)
    for m, th in zip(ms, theory, strict=True):
        edf = _edf(-1, m, n)
        lo = math.sqrt(th * stats.chi2.ppf(p / 2, edf) / edf / PLATEAU)
        hi = math.sqrt(th * stats.chi2.ppf(1 - p / 2, edf) / edf / PLATEAU)
        assert 0.95 <= lo and hi <= 1.05, (m, lo, hi)
    est = _streaming_oavar(model, fs, n, ms, seed=2026)
    ratio = np.sqrt(est / PLATEAU)
    assert np.all(np.abs(ratio - 1) <= 0.05), dict(
        zip(ms.tolist(), np.round(ratio, 4).tolist(), strict=True)
    )


def test_streaming_oavar_helper_matches_allantools():
    model = NoiseModel.from_datasheet(angle_random_walk=0.05, bias_instability=0.5)
    ms = np.array([1, 4, 64])
    est = _streaming_oavar(model, FS, 50_000, ms, seed=3, chunk=7_777)
    y = model.generate(50_000, FS, rng=np.random.default_rng(3))
    _, ad, _, _ = allantools.oadev(y, rate=FS, data_type="freq", taus=ms / FS)
    np.testing.assert_allclose(est, ad**2, rtol=1e-9)


# ------------------------------------------------------------------------ chunking and components
ALL_TERMS = NoiseModel(
    quantization=1e-6,
    angle_random_walk=2e-5,
    bias_instability=3e-6,
    rate_random_walk=1e-7,
    rate_ramp=1e-9,
    gauss_markov=(GaussMarkov(sigma=1e-5, correlation_time=0.3),),
    sinusoids=(Sinusoid(amplitude=1e-5, frequency=1.7, phase=0.2),),
    bias=1e-4,
)


@settings(max_examples=40, deadline=None)
@given(
    cuts=st.lists(st.integers(min_value=0, max_value=3000), min_size=1, max_size=8),
    seed=st.integers(min_value=0, max_value=2**32 - 1),
    fs=st.sampled_from([1.0, 100.0, 1000.0]),
)
def test_chunked_equals_one_shot(cuts, seed, fs):
    n = sum(cuts)
    one = ALL_TERMS.generate(n, fs, rng=np.random.default_rng(seed))
    s = ALL_TERMS.stream(fs, rng=np.random.default_rng(seed))
    parts = [s.take(c) for c in cuts]
    assert np.array_equal(np.concatenate(parts), one)


@settings(max_examples=15, deadline=None)
@given(cuts=st.lists(st.integers(min_value=1, max_value=70_000), min_size=1, max_size=4))
def test_chunked_equals_one_shot_across_internal_blocks(cuts):
    """Chunks larger than the internal block and misaligned with the flicker levels."""
    n = sum(cuts)
    one = ALL_TERMS.generate(n, 1000.0, rng=np.random.default_rng(7))
    s = ALL_TERMS.stream(1000.0, rng=np.random.default_rng(7))
    assert np.array_equal(np.concatenate([s.take(c) for c in cuts]), one)


def test_chunks_iterator_equals_one_shot():
    one = ALL_TERMS.generate(10_007, 100.0, rng=np.random.default_rng(8))
    s = ALL_TERMS.stream(100.0, rng=np.random.default_rng(8))
    assert np.array_equal(np.concatenate(list(s.chunks(10_007, 999))), one)


def test_components_sum_to_generate():
    comps = ALL_TERMS.components(5000, 100.0, rng=np.random.default_rng(9))
    total = np.zeros(5000)
    for v in comps.values():
        total += v
    assert np.array_equal(total, ALL_TERMS.generate(5000, 100.0, rng=np.random.default_rng(9)))
    assert set(comps) == {
        "quantization",
        "angle_random_walk",
        "bias_instability",
        "rate_random_walk",
        "rate_ramp",
        "gauss_markov_0",
        "sinusoid_0",
        "bias",
    }


def test_adding_a_term_leaves_others_unchanged():
    small = NoiseModel(angle_random_walk=2e-5, bias_instability=3e-6)
    big = NoiseModel(
        quantization=1e-6,
        angle_random_walk=2e-5,
        bias_instability=3e-6,
        rate_random_walk=1e-7,
        gauss_markov=(GaussMarkov(sigma=1e-5, correlation_time=0.3),),
    )
    a = small.components(4000, 100.0, rng=np.random.default_rng(10))
    b = big.components(4000, 100.0, rng=np.random.default_rng(10))
    for k in a:
        assert np.array_equal(a[k], b[k]), k


def test_deterministic_components_values():
    m = NoiseModel(
        rate_ramp=2e-9, sinusoids=(Sinusoid(amplitude=1e-5, frequency=0.5, phase=0.1),), bias=3e-4
    )
    c = m.components(1000, 10.0, rng=np.random.default_rng(0), t0=5.0)
    t = 5.0 + np.arange(1000) / 10.0
    np.testing.assert_allclose(c["rate_ramp"], 2e-9 * t, rtol=1e-12)
    np.testing.assert_allclose(
        c["sinusoid_0"], 1e-5 * np.sin(2 * np.pi * 0.5 * t + 0.1), rtol=1e-9, atol=1e-20
    )
    assert np.all(c["bias"] == 3e-4)


def test_quantization_angle_error_is_uniform_with_std_q():
    q = 1e-6
    y = NoiseModel(quantization=q).generate(200_000, 1.0, rng=np.random.default_rng(4))
    e = np.cumsum(y)  # e_k - e_{-1}
    half = math.sqrt(12) * q / 2
    assert np.ptp(e) <= 2 * half * (1 + 1e-12)


def test_zero_samples():
    assert ALL_TERMS.generate(0, 100.0, rng=np.random.default_rng(0)).shape == (0,)
    assert all(
        v.shape == (0,)
        for v in ALL_TERMS.components(0, 100.0, rng=np.random.default_rng(0)).values()
    )


# ---------------------------------------------------------------------------- datasheet round trip
def test_datasheet_round_trip():
    ds = dict(
        quantization=0.7,
        angle_random_walk=0.013,
        bias_instability=0.21,
        rate_random_walk=0.034,
        rate_ramp=0.05,
    )
    back = NoiseModel.from_datasheet(**ds).to_datasheet()
    for key, name in zip("QNBKR", ds, strict=True):
        assert back[key] == pytest.approx(ds[name], rel=1e-12)


def test_from_datasheet_unknown_keyword():
    with pytest.raises(TypeError, match="unknown keyword"):
        NoiseModel.from_datasheet(arw=0.1)


# ---------------------------------------------------------------------------- validation
@pytest.mark.parametrize(
    "name",
    ["quantization", "angle_random_walk", "bias_instability", "rate_random_walk", "rate_ramp"],
)
def test_negative_coefficient_rejected(name):
    with pytest.raises(ValueError, match=rf"NoiseModel\.{name} must be \[0, 1e\+100\] \S+; got -1"):
        NoiseModel(**{name: -1.0})


@pytest.mark.parametrize(
    "name",
    ["quantization", "angle_random_walk", "bias_instability", "rate_random_walk", "rate_ramp"],
)
def test_nan_coefficient_rejected(name):
    with pytest.raises(ValueError, match=rf"NoiseModel\.{name} must be \[0, 1e\+100\].*; got nan"):
        NoiseModel(**{name: float("nan")})


def test_inf_coefficient_rejected():
    with pytest.raises(ValueError, match=r"angle_random_walk must be \[0, 1e\+100\] rad/sqrt\(s\); got inf"):
        NoiseModel(angle_random_walk=math.inf)


def test_string_coefficient_rejected():
    with pytest.raises(
        TypeError, match=r"NoiseModel\.bias_instability must be a real number \[rad/s\]; got '0.1'"
    ):
        NoiseModel(bias_instability="0.1")


def test_bool_coefficient_rejected():
    with pytest.raises(
        TypeError, match=r"NoiseModel\.quantization must be a real number \[rad\]; got True"
    ):
        NoiseModel(quantization=True)


def test_datasheet_negative_rejected():
    with pytest.raises(
        ValueError, match=r"from_datasheet\.rate_random_walk must be finite and >= 0; got -0.1"
    ):
        NoiseModel.from_datasheet(rate_random_walk=-0.1)


def test_flicker_band_inverted_rejected():
    with pytest.raises(
        ValueError, match=r"flicker_band must satisfy 0 < f_low < f_high \[Hz\]; got \(1.0, 0.5\)"
    ):
        NoiseModel(flicker_band=(1.0, 0.5))


def test_flicker_band_zero_low_rejected():
    with pytest.raises(ValueError, match=r"flicker_band\[0\] must be > 0 Hz or inf; got 0.0"):
        NoiseModel(flicker_band=(0.0, 1.0))


def test_flicker_band_nan_rejected():
    with pytest.raises(ValueError, match=r"flicker_band\[0\] must be > 0 Hz or inf; got nan"):
        NoiseModel(flicker_band=(float("nan"), 1.0))


def test_flicker_band_wrong_type_rejected():
    with pytest.raises(TypeError, match=r"flicker_band must be a tuple; got list"):
        NoiseModel(flicker_band=[1e-6, 1.0])


def test_flicker_band_string_rejected():
    with pytest.raises(TypeError, match=r"flicker_band\[0\] must be a real number \[Hz\]; got '1e-6'"):
        NoiseModel(flicker_band=("1e-6", 1.0))


def test_bias_nan_rejected():
    with pytest.raises(ValueError, match=r"NoiseModel\.bias must be a finite number \[rad/s\]; got nan"):
        NoiseModel(bias=float("nan"))


def test_gauss_markov_wrong_type_rejected():
    with pytest.raises(TypeError, match=r"gauss_markov must be a tuple of GaussMarkov"):
        NoiseModel(gauss_markov=[GaussMarkov(sigma=1.0, correlation_time=1.0)])


def test_gauss_markov_zero_time_rejected():
    with pytest.raises(ValueError, match=r"GaussMarkov\.correlation_time must be \(0, 1e\+100\] s; got 0"):
        GaussMarkov(sigma=1.0, correlation_time=0.0)


def test_gauss_markov_negative_sigma_rejected():
    with pytest.raises(ValueError, match=r"GaussMarkov\.sigma must be \[0, 1e\+100\] rad/s; got -1"):
        GaussMarkov(sigma=-1.0, correlation_time=1.0)


def test_sinusoid_zero_frequency_rejected():
    with pytest.raises(ValueError, match=r"Sinusoid\.frequency must be \(0, 1e\+100\] Hz; got 0"):
        Sinusoid(amplitude=1.0, frequency=0.0)


def test_sinusoid_nan_phase_rejected():
    with pytest.raises(ValueError, match=r"Sinusoid\.phase must be a finite number \[rad\]; got nan"):
        Sinusoid(amplitude=1.0, frequency=1.0, phase=float("nan"))


def test_fs_zero_rejected():
    with pytest.raises(ValueError, match=r"fs must be a finite number > 0 Hz; got 0"):
        NoiseModel(angle_random_walk=1e-5).generate(10, 0.0, rng=np.random.default_rng(0))


def test_fs_nan_rejected_in_theory():
    with pytest.raises(ValueError, match=r"fs must be a finite number > 0 Hz; got nan"):
        NoiseModel(angle_random_walk=1e-5).theoretical_avar([1.0], fs=float("nan"))


def test_fs_string_rejected():
    with pytest.raises(TypeError, match=r"fs must be a real number \[Hz\]; got '100'"):
        NoiseModel(angle_random_walk=1e-5).generate(10, "100", rng=np.random.default_rng(0))


def test_rng_wrong_type_rejected():
    with pytest.raises(TypeError, match=r"rng must be a numpy.random.Generator; got int"):
        NoiseModel(angle_random_walk=1e-5).generate(10, 100.0, rng=0)


def test_negative_n_rejected():
    with pytest.raises(ValueError, match=r"n must be >= 0 samples; got -1"):
        NoiseModel(angle_random_walk=1e-5).generate(-1, 100.0, rng=np.random.default_rng(0))


def test_float_n_rejected():
    with pytest.raises(TypeError, match=r"n must be an integer number of samples; got 10.0"):
        NoiseModel(angle_random_walk=1e-5).generate(10.0, 100.0, rng=np.random.default_rng(0))


def test_nonpositive_tau_rejected():
    with pytest.raises(ValueError, match=r"tau must be > 0 s everywhere"):
        NoiseModel(angle_random_walk=1e-5).theoretical_avar([1.0, 0.0], fs=10.0)


def test_bad_chunk_rejected():
    s = NoiseModel(angle_random_walk=1e-5).stream(10.0, rng=np.random.default_rng(0))
    with pytest.raises(ValueError, match=r"chunk must be an integer > 0 samples; got 0"):
        list(s.chunks(10, 0))


def test_prefetch_thread_does_not_change_values(monkeypatch):
    """Drawing the next block in the worker thread gives the same samples as drawing inline."""
    n = 3 * nz._BLOCK + 123
    monkeypatch.setattr(nz, "_PREFETCH", True)
    with_thread = ALL_TERMS.generate(n, 100.0, rng=np.random.default_rng(21))
    monkeypatch.setattr(nz, "_PREFETCH", False)
    inline = ALL_TERMS.generate(n, 100.0, rng=np.random.default_rng(21))
    assert np.array_equal(with_thread, inline)


SLOW_BAND = NoiseModel(bias_instability=5e-6, flicker_band=(1e-7, 0.05))  # f_high << fs/2 = 500 Hz


def test_slow_band_is_all_decimated_with_bridge():
    """With f_high << fs/2 every pole is decimated and the full-rate Brownian bridge is on."""
    s = SLOW_BAND.stream(1000.0, rng=np.random.default_rng(0))
    assert (
        s._flicker.fine is None
        and s._flicker.coarse is not None
        and s._flicker.fine_bridge is not None
    )


@settings(max_examples=15, deadline=None)
@given(cuts=st.lists(st.integers(min_value=0, max_value=20_000), min_size=1, max_size=6))
def test_chunked_equals_one_shot_slow_band(cuts):
    n = sum(cuts)
    one = SLOW_BAND.generate(n, 1000.0, rng=np.random.default_rng(5))
    s = SLOW_BAND.stream(1000.0, rng=np.random.default_rng(5))
    assert np.array_equal(np.concatenate([s.take(c) for c in cuts]), one)


def test_slow_band_flicker_adev_within_chi2_band():
    fs = 1000.0
    y = SLOW_BAND.generate(1 << 21, fs, rng=np.random.default_rng(18))
    _check_record(SLOW_BAND, y, fs)


def test_forked_child_can_use_the_draw_thread(monkeypatch):
    """After fork the child must not wait on the parent's (absent) worker thread."""
    import multiprocessing as mp

    monkeypatch.setattr(nz, "_PREFETCH", True)
    n = 2 * nz._BLOCK + 5
    want = ALL_TERMS.generate(n, 100.0, rng=np.random.default_rng(33))  # starts the worker here
    ctx = mp.get_context("fork")
    with ctx.Pool(1) as pool:
        got = pool.apply_async(_gen_in_child, (n,)).get(timeout=60)
    assert np.array_equal(got, want)


def _gen_in_child(n):
    nz._PREFETCH = True
    return ALL_TERMS.generate(n, 100.0, rng=np.random.default_rng(33))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_scaled_draws_are_numpys_uniform_and_normal_bit_for_bit(seed):
    """The stream's scaled draws equal Generator.uniform(0, c) and Generator.normal(0, c) exactly."""
    n, c = 10_001, 3.7e-5
    a, b = np.random.default_rng(seed), np.random.default_rng(seed)
    assert nz._scaled(a.random, c, n).tobytes() == b.uniform(0.0, c, n).tobytes()
    assert nz._scaled(a.standard_normal, c, n).tobytes() == b.normal(0.0, c, n).tobytes()
