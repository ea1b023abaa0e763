"""The MEMS open-loop noise-spectrum checks of :mod:`gyrobench.scenarios.checks.mems`
(``mems.open_loop_noise_vs_full`` and ``mems.open_loop_noise_psd_vs_full``): the full
integration's output PSD with Brownian and pick-off noise against the slow flow's, both against
the closed-form ratio of the two models' spectra (:func:`full_noise_spectrum`,
:func:`slow_noise_spectrum`), F-test on the equivalent degrees of freedom. Kept apart from the
other MEMS checks for size; they run as one part of ``checks_mems.parts``."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from gyrobench.base import units
from gyrobench.scenarios.checks.core import SECOND_METHOD, Check
from gyrobench.scenarios.checks.mems import FALSE_ALARM, open_loop_unit
from gyrobench.sim.mems_full import simulate_full
from gyrobench.sim.mems_resonator import BOLTZMANN, MemsResonator, low_rate_scale_factor, operating_point
from gyrobench.sim.mems_slow_flow import slow_flow

__all__ = ["f_ratio_bounds", "full_noise_spectrum", "open_loop_noise_checks", "periodogram_band_stats",
           "slow_noise_spectrum"]


# ----------------------------------------------------------------------------- noise PSD
#: open-loop noise PSD, full vs slow flow: cases, output rate [Hz], settling and analysed
#: record per case [s], slow-flow columns and record per column [s] (100 segments of
#: NOISE_RECORD after one of settling), band width [Hz]
NOISE_CASES = 1250
NOISE_FS = 3000.0
NOISE_SETTLE = 0.006
NOISE_RECORD = 0.024
NOISE_SLOW_COLS = 64
NOISE_SLOW_DURATION = 2.4
NOISE_BAND = 250.0
#: RK4 steps per drive period of the noise integration (its held force is in
#: :func:`full_noise_spectrum`; the common relative frequency error (w dt)^4/120 moves the mode
#: split by that fraction of 500 Hz, 0.1 Hz at 16 steps)
NOISE_STEPS_PER_CYCLE = 16
#: frequency grid of the autocovariance (points over one fs period) and alias terms summed.
#: The inverse FFT of the spectrum sampled on the grid is the autocovariance aliased in lag by
#: _PSD_GRID / fs = 1.37 s; the slowest decay of either spectrum is the sense envelope's
#: c_y/(2m) ~ 490 /s, so the aliased lags carry e^-660 of the variance (nothing in float64).
_PSD_GRID = 2**12
_PSD_ALIASES = 200
#: outside references of the two noise-spectrum checks
_REFERENCE = (
    "second method: fixed-step RK4 of the full equations with the carrier against the slow flow, each "
    "against its closed-form spectrum; Brownian force 4 k_B T c: R. P. Leland, IEEE Sensors J. 5(3) 493 "
    "(2005); periodogram statistics: D. B. Percival, A. T. Walden, Spectral Analysis for Physical "
    "Applications (Cambridge Univ. Press, 1993); equivalent dof: F. E. Satterthwaite, Biometrics Bull. "
    "2(6) 110 (1946)"
)


def _dirichlet(x: NDArray, n_dec: int, dt: float) -> NDArray:
    """(1/N) sum_{i=1..N} e^{j 2 pi x i dt}: the interval mean of N samples at x [Hz].

    Closed form e^{j th (N+1)/2} sin(N th/2) / (N sin(th/2)), th = 2 pi x dt (-> phase only
    where sin(th/2) = 0).
    """
    th = 2.0 * np.pi * np.asarray(x) * dt
    den = n_dec * np.sin(th / 2.0)
    small = np.abs(den) < 1e-12
    amp = np.where(small, np.cos(th / 2.0) ** (n_dec - 1),
                   np.sin(n_dec * th / 2.0) / np.where(small, 1.0, den))
    return np.exp(0.5j * th * (n_dec + 1)) * amp


def slow_noise_spectrum(unit: MemsResonator, f: NDArray, fs: float) -> NDArray:
    """Two-sided PSD of the slow flow's sampled open-loop output [(rad/s)^2/Hz] at f [Hz].

    The interval mean and the sampling at fs alias the continuous
    :func:`~gyrobench.sim.mems_resonator.open_loop_noise_psd`:
    sum_k S_B(f + k fs) sinc^2((f + k fs)/fs) (Brownian) plus the white pick-off part, which
    stays white at its level (sum_k sinc^2 = 1). Halved: two-sided.

    Parameters
    ----------
    unit : MemsResonator
        The open-loop unit.
    f : ndarray
        Frequencies [Hz].
    fs : float
        Output rate [Hz].

    Returns
    -------
    ndarray
        The two-sided PSD [(rad/s)^2/Hz].
    """
    from gyrobench.sim.mems_resonator import _open_loop_noise_parts

    op = operating_point(unit)
    k = np.arange(-_PSD_ALIASES, _PSD_ALIASES + 1)
    fk = np.add.outer(f, k * fs)
    brown, white = _open_loop_noise_parts(unit, op, fk)
    return (np.sum(brown * np.sinc(fk / fs) ** 2, axis=-1) + white) / 2.0


def full_noise_spectrum(
    unit: MemsResonator, f: NDArray, fs: float, steps_per_cycle: int
) -> NDArray:
    """Two-sided PSD of :func:`simulate_full`'s sampled open-loop output [(rad/s)^2/Hz] at f.

    The full integration reads out Re{a w_c <2 (y + n) e^{-jwt}>} (a = k_out (1 + e_on)),
    the mean of N = f_x/(fs dt) RK4 samples of y times the real carrier 2 Re{a e^{-jwt}}.
    A sense-displacement component e^{j 2 pi nu t} lands at nu - f_x and nu + f_x, both
    f (mod fs) when f_x/fs is an integer, so it reaches the output through
    H(nu) = a D(nu - f_x) + conj(a) D(nu + f_x) (D the N-sample mean, :func:`_dirichlet`):
    the carrier's 2w image leaks through the interval mean and adds coherently. The
    Brownian y has the exact second-order PSD 2 k_B T c_y |R(nu)|^2 sinc^2(nu dt) (force held
    over each RK4 step, R(nu) = 1/(m (w_y^2 - (2 pi nu)^2) + j c_y 2 pi nu)); so

        S(f) = sum_k 2 k_B T c_y |R(nu_k)|^2 sinc^2(nu_k dt) |H(nu_k)|^2 + white/2,
        nu_k = f + f_x + k fs   [DERIVED]

    with the pick-off part white at the slow flow's level (RK4 samples of white noise, N per
    interval, the same variance S_n fs per output sample). Drive-mode noise, the anisoelastic
    and electrostatic couplings are left out (their noise is below 1e-6 of the sense mode's).
    Exact at T0 (the drive at f_x); requires f_x/fs to be an integer.

    Parameters
    ----------
    unit : MemsResonator
        The open-loop unit.
    f : ndarray
        Frequencies [Hz].
    fs : float
        Output rate [Hz].
    steps_per_cycle : int
        RK4 steps per drive period.

    Returns
    -------
    ndarray
        The two-sided PSD [(rad/s)^2/Hz].
    """
    from gyrobench.sim.mems_resonator import _open_loop_noise_parts, _readout_weight

    op = operating_point(unit)
    fx = op.wx / (2.0 * math.pi)
    ratio = fx / fs
    if abs(ratio - round(ratio)) > 1e-9:
        raise ValueError(f"f_x/fs must be an integer; got {ratio!r}")
    n_dec = max(1, int(round(fx * steps_per_cycle / fs)))
    dt = 1.0 / (fs * n_dec)
    a = op.k_out * (1.0 + unit.turn_on_scale_factor) * _readout_weight(op)
    k = np.arange(-_PSD_ALIASES, _PSD_ALIASES + 1)
    # D(x) depends on x dt mod 1 only and fs dt = 1/n_dec: D(f + k fs) repeats with period
    # n_dec in k, so the n_dec distinct kernels are computed once (nu - f_x = f + k fs,
    # nu + f_x = f + (k + 2 f_x/fs) fs)
    kernels = np.stack([_dirichlet(f + j * fs, n_dec, dt) for j in range(n_dec)])
    shift = 2 * int(round(ratio))
    total = np.zeros(np.shape(f))
    for kk in k:  # one alias at a time: bounded temporaries
        nu = f + fx + kk * fs
        w = 2.0 * math.pi * nu
        r2 = 1.0 / np.abs(op.ky - op.m * w**2 + 1j * op.cy * w) ** 2
        h = a * kernels[kk % n_dec] + np.conj(a) * kernels[(kk + shift) % n_dec]
        total += 2.0 * BOLTZMANN * op.temperature * op.cy * r2 * np.sinc(nu * dt) ** 2 * (
            np.abs(h) ** 2)
    _, white = _open_loop_noise_parts(unit, op, np.zeros(1))
    return total + white / 2.0


def periodogram_band_stats(
    spectrum: NDArray, fs: float, n: int, bands: list[NDArray]
) -> tuple[NDArray, NDArray]:
    """Expected band means of the one-sided periodogram of n samples and their equivalent dof.

    ``spectrum``: the two-sided PSD of the sampled process on ``np.fft.fftfreq(_PSD_GRID,
    1/fs)``; its autocovariance r(tau) = fs ifft(S) gives the n x n covariance Sigma of one
    segment; the DFT X = F x has E[X X^H] = F Sigma F^H and E[X X^T] = F Sigma F^T, so for a
    Gaussian process P_j = 2 |X_j|^2/(fs n) has mean 2 A_jj/(fs n) and
    cov(P_j, P_l) = (2/(fs n))^2 (|A_jl|^2 + |B_jl|^2). A band mean of one segment then has
    the equivalent degrees of freedom nu = 2 mean^2/var (Satterthwaite); ``bands`` lists the
    bin indices of each band. Exact for the rectangular window, leakage and correlated bins
    included.

    Parameters
    ----------
    spectrum : ndarray
        Two-sided PSD of the sampled process on the module's grid.
    fs : float
        Sample rate [Hz].
    n : int
        Samples per segment.
    bands : list of ndarray
        The periodogram bins of each band.

    Returns
    -------
    tuple of ndarray
        (expected band means, equivalent dof).
    """
    from scipy.linalg import toeplitz

    r = (fs * np.fft.ifft(spectrum)).real[:n]
    sigma = toeplitz(r)
    t = np.arange(n)
    means, dofs = [], []
    for b in bands:
        fm = np.exp(-2j * np.pi * np.outer(b, t) / n)
        a = fm @ sigma @ fm.conj().T
        bb = fm @ sigma @ fm.T
        c = (2.0 / (fs * n)) ** 2 * (np.abs(a) ** 2 + np.abs(bb) ** 2)
        mu = float(np.mean(2.0 * a.diagonal().real / (fs * n)))
        var = float(c.sum()) / len(b) ** 2
        means.append(mu)
        dofs.append(2.0 * mu * mu / var)
    return np.array(means), np.array(dofs)


def _band_periodogram(x: NDArray, fs: float, bands: list[NDArray]) -> NDArray:
    """Band means of the one-sided periodogram of each column of x (n, cases), per column."""
    n = x.shape[0]
    p = 2.0 * np.abs(np.fft.rfft(x - x.mean(axis=0), axis=0)) ** 2 / (fs * n)
    return np.stack([p[b].mean(axis=0) for b in bands])


def f_ratio_bounds(dof_1: float, dof_2: float, false_alarm: float) -> tuple[float, float]:
    """Two-sided bounds of (s_1^2/sigma_1^2)/(s_2^2/sigma_2^2) ~ F(dof_1, dof_2).

    Parameters
    ----------
    dof_1, dof_2 : float
        Degrees of freedom of the two estimates.
    false_alarm : float
        Two-sided false-alarm rate.

    Returns
    -------
    tuple of float
        (low, high).
    """
    from scipy import stats

    return (float(stats.f.ppf(false_alarm / 2, dof_1, dof_2)),
            float(stats.f.ppf(1 - false_alarm / 2, dof_1, dof_2)))


def open_loop_noise_checks(rng: np.random.Generator) -> list[Check]:
    """Open-loop output noise PSD: the full integration against the slow flow, band by band.

    Open-loop output noise PSD: full integration (Brownian forces on both modes, pick-off
    noise) vs the slow flow, band by band, against the closed-form ratio of their spectra.

    The full integration runs NOISE_CASES independent cases for NOISE_SETTLE + NOISE_RECORD
    at NOISE_FS with NOISE_STEPS_PER_CYCLE RK4 steps per drive period. A band of NOISE_BAND
    holds NOISE_BAND x NOISE_RECORD = 6 periodogram bins. The record is sized for what the
    check must catch, a 10 % error in the noise PSD of either model: 1250 full cases against
    6400 slow-flow segments give an F band of +-0.065 on the level (0.046 with the 2112 cases x
    20 steps x 34 ms of an earlier design, at 2.3 times the RK4 work), so a 10 % error sits 2.4
    standard deviations outside the band (tests/scenarios/test_checks_catch_errors.py perturbs
    the full model's noise by +-10 % and sees both checks fail). The split between the two
    sides minimises the cost at that band: the band's variance goes as 1/N_full + 1/N_slow
    (each segment carries about the same dof), a full case costs ~28 slow-flow segments, so the
    cheapest split has N_slow/N_full = sqrt(28) ~ 5; 1250 + 6400 gives the band of the 1100 +
    21312 used before (1/N_full + 1/N_slow 9.56e-4 both) in three quarters of the time. The
    settling NOISE_SETTLE = 6 ms is 2.9 time constants of the sense envelope (c_y/(2m) ~
    490 /s): the variance still missing, e^{-2 c_y t/(2m)} <= 0.003, is added to both
    tolerances. The slow flow runs
    NOISE_SLOW_COLS columns of NOISE_SLOW_DURATION cut into segments of the same length. Each
    side's band-mean periodogram has its exact expectation and equivalent dof
    (:func:`periodogram_band_stats`); the full's expectation differs from the slow flow's by
    rho = E_full/E_slow (:func:`full_noise_spectrum` vs :func:`slow_noise_spectrum`: the slow
    flow's first-order envelope and ideal demodulator, the full's held noise force), and
    (P_full/P_slow)/rho ~ F(nu_full, nu_slow).

    Parameters
    ----------
    rng : numpy.random.Generator
        The cases' streams.

    Returns
    -------
    list of Check
        One check per band.
    """
    unit = open_loop_unit()
    fs = NOISE_FS
    r_full, r_slow = rng.spawn(2)
    n_set, n = int(round(NOISE_SETTLE * fs)), int(round(NOISE_RECORD * fs))
    full = simulate_full(unit, np.zeros(NOISE_CASES), duration=NOISE_SETTLE + NOISE_RECORD,
                         fs=fs, rng=r_full, steps_per_cycle=NOISE_STEPS_PER_CYCLE, adc=False)
    x_full = full.output[n_set:n_set + n]
    n_seg = int(round(NOISE_SLOW_DURATION * fs)) // n
    slow = slow_flow(unit, np.zeros(((n_seg + 1) * n, NOISE_SLOW_COLS)), fs=fs, rng=r_slow,
                    adc=False, flicker=False)
    # the first segment of each column is settling (envelope time constant 2 ms << 30 ms)
    x_slow = (slow.output[n:].reshape(n_seg, n, NOISE_SLOW_COLS).transpose(1, 0, 2)
              .reshape(n, n_seg * NOISE_SLOW_COLS))
    freqs = np.fft.rfftfreq(n, 1.0 / fs)
    edges = np.arange(0.0, fs / 2.0, NOISE_BAND)
    bands = [np.flatnonzero((freqs > lo) & (freqs <= lo + NOISE_BAND) & (freqs < fs / 2))
             for lo in edges]
    grid = np.fft.fftfreq(_PSD_GRID, 1.0 / fs)
    e_full, nu_full = periodogram_band_stats(
        full_noise_spectrum(unit, grid, fs, NOISE_STEPS_PER_CYCLE), fs, n, bands)
    e_slow, nu_slow = periodogram_band_stats(slow_noise_spectrum(unit, grid, fs), fs, n, bands)
    rho = e_full / e_slow
    p_full = _band_periodogram(x_full, fs, bands).mean(axis=1)
    p_slow = _band_periodogram(x_slow, fs, bands).mean(axis=1)
    dof_f, dof_s = nu_full * NOISE_CASES, nu_slow * n_seg * NOISE_SLOW_COLS
    # variance the full cases still miss after the settling (the sense envelope's decay)
    op = operating_point(unit)
    settle = math.exp(-2.0 * op.cy / (2.0 * op.m) * NOISE_SETTLE)
    # the level: the first band (42-250 Hz, inside the ~790 Hz open-loop bandwidth)
    lo0, hi0 = f_ratio_bounds(dof_f[0], dof_s[0], FALSE_ALARM)
    tol0 = max(1 - lo0, hi0 - 1) + settle
    # the shape: every other band up to Nyquist, Bonferroni over them
    m = len(bands) - 1
    worst = (-1.0, 1, 0.0, 1.0)  # (error / tol, band, error, tol)
    for i in range(1, len(bands)):
        lo, hi = f_ratio_bounds(dof_f[i], dof_s[i], FALSE_ALARM / m)
        tol = max(1 - lo, hi - 1) + settle
        e = abs(p_full[i] / (rho[i] * p_slow[i]) - 1)
        if e / tol > worst[0]:
            worst = (e / tol, i, e, tol)
    _, iw, _, tol_w = worst
    sf = low_rate_scale_factor(unit)
    arw = math.sqrt(p_slow[0] * rho[0] / 2.0) / sf
    rec = (f"{NOISE_CASES} full-integration cases x {NOISE_RECORD * 1e3:g} ms at "
           f"{fs:g} Hz ({NOISE_STEPS_PER_CYCLE} RK4 steps per period; {NOISE_SETTLE * 1e3:g} ms "
           f"settling dropped) vs {n_seg * NOISE_SLOW_COLS} slow-flow segments of the same "
           "length; rectangular-window periodograms")
    band = f"{edges[iw]:g}-{edges[iw] + NOISE_BAND:g} Hz"
    return [
        Check(
            id="mems.open_loop_noise_vs_full",
            kind=SECOND_METHOD,
            reference=_REFERENCE,
            formula=(
                f"open loop, Brownian + pick-off noise: output PSD over 0-{NOISE_BAND:g} Hz, "
                "full integration vs slow flow x rho [(rad/s)^2/Hz] "
                f"(input-referred ARW sqrt(S/2)/SF = {units.to_deg_per_sqrt_h(arw):.3g} "
                "deg/sqrt(h))"
            ),
            expected=float(rho[0] * p_slow[0]),
            simulated=float(p_full[0]),
            tolerance=tol0,
            derivation=(
                f"F({dof_f[0]:.0f}, {dof_s[0]:.0f}) bounds at {FALSE_ALARM:g} two-sided "
                f"(equivalent dof of the two band means from the closed-form spectra), plus the "
                f"settling deficit e^(-c_y t/m) = {settle:.1g}; {rec}; "
                f"rho = E_full/E_slow = {rho[0]:.4f} (closed forms)"
            ),
        ),
        Check(
            id="mems.open_loop_noise_psd_vs_full",
            kind=SECOND_METHOD,
            reference=_REFERENCE,
            formula=(
                f"open loop: output PSD in {m} bands of {NOISE_BAND:g} Hz from {NOISE_BAND:g} Hz to "
                "Nyquist (through the sense-mode peak near the mode split), full vs slow flow "
                "x rho; worst band relative to its tolerance [(rad/s)^2/Hz]"
            ),
            expected=float(rho[iw] * p_slow[iw]),
            simulated=float(p_full[iw]),
            tolerance=float(tol_w),
            derivation=(
                f"worst band {band}: F(nu_full, nu_slow) bounds at {FALSE_ALARM:g}/{m} "
                f"two-sided (Bonferroni over the bands) plus the settling deficit {settle:.1g}; {rec}; "
                f"rho = E_full/E_slow "
                f"{rho[1:].min():.4f}-{rho[1:].max():.4f} over the bands: the slow flow's "
                "first-order envelope and ideal demodulator overstate the full equations' "
                "noise by up to that much near and above the mode split"
            ),
        ),
    ]
