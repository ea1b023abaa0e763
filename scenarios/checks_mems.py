"""Closed-form checks of the MEMS resonator gyro (:mod:`gyrobench.sim.mems_resonator`).

``checks(rng) -> list[Check]`` (the contract of :mod:`gyrobench.scenarios.checks`):

* ``mems.brownian_arw``: slow-flow ARW (Brownian only) vs N_B = sqrt(k_B T c_y)/(m w X0);
* ``mems.low_rate_scale_factor``: full integration vs SF = s_trim (w/w0)(G0/G) cos(theta) at a
  temperature away from T0;
* ``mems.quadrature_rejection``: zero-rate output (full integration) vs the quadrature leak
  -Omega_q sin(theta) SF/cos(theta) (+ anisodamping), error relative to Omega_q;
* ``mems.rate_authority``: saturated output (full integration) vs the force-rebalance authority;
* ``mems.drive_amplitude``: the full integration's AGC holds X0;
* ``mems.sense_envelope_saturated``: amplitude and phase of the sense motion beyond the knee,
  full vs slow flow;
* ``mems.slow_flow_vs_full``: largest output difference over the rate set (relative to the
  rate), slow flow vs full integration;
* ``mems.slow_flow_noise_vs_full``: variance of 10-ms output means (one per independent case),
  full vs slow flow;
* ``mems.zero_rate_continuity``: a +-0.1 deg/s pair reads +-0.1 deg/s x SF within the noise;
* ``mems.g_sensitivity``: full integration at +-20 g along the sense axis (inertial force on the
  proof mass, electrostatic cross-stiffness of the forcer plates) vs
  -SF tan(theta) (dk_yx/df)/(2 m w), error relative to the quadrature shift it must reject;
* ``mems.open_loop_scale_factor``: open-loop read-out, full integration vs
  SF = s_trim (w/w0) Re{e^{-j theta} R/R_c} at a temperature away from T0;
* ``mems.open_loop_slow_vs_full``: open loop, slow flow vs full integration (0-6000 deg/s,
  through the pick-off full-scale knee);
* ``mems.open_loop_frequency_response``: open loop, slow flow driven by sinusoidal rates vs the
  closed-form response H(f) (Coriolis + Euler forces through the envelope pole).
* ``mems.open_loop_noise_vs_full``: open loop, output noise PSD over 0-250 Hz (the white level
  inside the bandwidth), full integration with Brownian and pick-off noise vs the slow flow;
* ``mems.open_loop_noise_psd_vs_full``: the same in 250-Hz bands to Nyquist, through the
  sense-mode peak; both against the closed-form ratio rho of the two models' spectra
  (:func:`full_noise_spectrum`, :func:`slow_noise_spectrum`), F-test on the equivalent dof.

Tolerances: numerical ones from RK4 (relative frequency error (w dt)^4/120 per observable
that carries the numerical oscillator's frequency: Coriolis force, AGC amplitude estimate,
demodulation references -> 3 (w dt)^4/120); statistical ones from chi-square quantiles of the
variance estimator (or F quantiles of the ratio of two) at a two-sided false-alarm rate of 1e-6,
plus stated bias bounds.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
from gyrobench.scenarios.checks import Check, Part, run_parts
from gyrobench.sim import units
from gyrobench.sim.mems_resonator import (
    BOLTZMANN,
    MemsResonator,
    brownian_arw,
    electronic_arw,
    g_sensitivity,
    low_rate_scale_factor,
    open_loop_response,
    operating_point,
    quadrature_rate,
    saturated_output,
    simulate,
    simulate_full,
    zero_rate_output,
)
from numpy.typing import NDArray

__all__ = [
    "checks", "parts", "FALSE_ALARM", "STEPS_PER_CYCLE", "rk4_tolerance", "variance_ratio_bounds",
    "f_ratio_bounds", "full_noise_spectrum", "slow_noise_spectrum", "periodogram_band_stats",
    "open_loop_noise_checks",
]

#: two-sided false-alarm rate of every statistical check
FALSE_ALARM = 1e-6
#: RK4 steps per drive period of the full integrations
STEPS_PER_CYCLE = 20
#: full-integration record [s] and the settling part discarded [s]
FULL_DURATION = 0.05
FULL_SETTLE = 0.04
#: rates of the noise-free full integration [deg/s]
FULL_RATES_DPS = (0.0, 100.0, 1000.0, 3000.0, 6000.0)
#: temperature offset of the full-integration unit from T0 [K]
DELTA_T = 20.0
#: specific force of the g-sensitivity cases [m/s^2] (+- 20 g)
G_CASE = 20.0 * 9.80665
#: open-loop full integration: steps per drive period, record and settling [s], rates [deg/s]
OPEN_STEPS_PER_CYCLE = 24
OPEN_DURATION = 0.03
OPEN_SETTLE = 0.01
OPEN_RATES_DPS = (0.0, 500.0, 2000.0, 6000.0)
#: sinusoidal-rate frequencies of the open-loop response check [Hz] and its sample rate [Hz]
RESPONSE_FREQS_HZ = (20.0, 200.0, 500.0, 800.0)
RESPONSE_FS = 1e5


def rk4_tolerance(unit: MemsResonator, steps_per_cycle: int = STEPS_PER_CYCLE) -> float:
    """3 (w dt)^4 / 120: RK4's relative frequency error, carried by three observables."""
    wdt = 2.0 * math.pi / steps_per_cycle
    return 3.0 * wdt**4 / 120.0


def variance_ratio_bounds(dof: float, false_alarm: float = FALSE_ALARM) -> tuple[float, float]:
    """Two-sided chi-square bounds of s^2/sigma^2 with ``dof`` degrees of freedom."""
    from scipy import stats

    return (
        float(stats.chi2.ppf(false_alarm / 2, dof) / dof),
        float(stats.chi2.ppf(1 - false_alarm / 2, dof) / dof),
    )


def check_unit() -> MemsResonator:
    """The default resonator with quadrature, a phase error and anisodamping (no trim, no ADC), and a
    quiet front end (pick-off noise 1e-13 m/sqrt(Hz), no 1/f term): the default's high-range-part
    front end (``DEFAULT_PICKOFF_NOISE``) would bury the Brownian noise these checks compare with
    its closed form, and the 1/f term is not part of the resonator's physics being checked."""
    return MemsResonator(
        quadrature_coupling=1e-4, phase_error=0.02, damping_coupling=5e-4, output_bits=None,
        pickoff_noise=1e-13, bias_instability=0.0,
    )


def _full_noise_free(unit: MemsResonator, temperature: float, rng: np.random.Generator):
    """The rate cases, then two zero-rate cases at +-G_CASE along the sense axis."""
    rates = units.deg_per_s(np.array(FULL_RATES_DPS))
    k = rates.size
    res = simulate_full(
        unit, np.concatenate([rates, [0.0, 0.0]]), duration=FULL_DURATION, fs=1000.0, rng=rng,
        temperature=temperature, steps_per_cycle=STEPS_PER_CYCLE, noise=False, adc=False,
        specific_force=np.concatenate([np.zeros(k), [G_CASE, -G_CASE]]),
    )
    keep = int(round(FULL_SETTLE * 1000.0))
    out = res.output[keep:].mean(axis=0)
    return (rates, out[:k], res.sense_envelope[-1, :k], res.drive_amplitude[keep:, :k],
            out[k:])


def _slow_noise_free(unit: MemsResonator, rates, temperature: float, rng: np.random.Generator):
    res = simulate(unit, np.tile(rates, (40, 1)), fs=1000.0, rng=rng, temperature=temperature,
                   noise=False, adc=False, flicker=False)
    return res.output[-1], res.sense_envelope[-1]


def _arw_check(rng: np.random.Generator) -> Check:
    unit = replace(check_unit(), pickoff_noise=0.0)
    fs, cols, dur, block = 200.0, 32, 250.0, 1.0
    n = int(dur * fs)
    res = simulate(unit, np.zeros((n, cols)), fs=fs, rng=rng, adc=False, flicker=False)
    m = int(block * fs)
    means = res.output.reshape(n // m, m, cols).mean(axis=1)
    sf = low_rate_scale_factor(unit)
    mu = zero_rate_output(unit)
    var = float(np.mean((means - mu) ** 2))  # known mean: dof = number of blocks
    dof = means.size
    n_hat = math.sqrt(var * block) / sf
    lo, hi = variance_ratio_bounds(dof)
    poles = operating_point(unit).loop_poles
    bias = 2.0 / (block * float(np.min(-poles.real)))  # finite-block correction bound
    tol = max(1 - math.sqrt(lo), math.sqrt(hi) - 1) + bias
    return Check(
        id="mems.brownian_arw",
        formula="N_B = sqrt(k_B T c_y) / (m w X0) = sqrt(k_B T w_y/(m Q_y)) / (w X0) [rad/sqrt(s)]",
        expected=brownian_arw(unit),
        simulated=n_hat,
        tolerance=tol,
        derivation=(
            f"variance of {dof} independent {block:g}-s means (known mean): chi-square bounds at "
            f"{FALSE_ALARM:g} two-sided, square-rooted, plus the finite-block bias bound "
            f"2/(T |Re s|min) = {bias:.2g} of the loop poles"
        ),
    )


def _full_checks(rng: np.random.Generator) -> list[Check]:
    unit = check_unit()
    temp = unit.reference_temperature + DELTA_T
    r_full, r_slow = rng.spawn(2)
    rates, full, b_full, x_full, g_full = _full_noise_free(unit, temp, r_full)
    slow, b_slow = _slow_noise_free(unit, rates, temp, r_slow)
    tol = rk4_tolerance(unit)
    op = operating_point(unit, temp)
    # the sense envelope in saturation is the open-loop response R F: its sensitivity to a
    # common relative frequency error is d ln R / d ln w = 2 w^2 / (w_y^2 - w^2)
    tol_b = tol * 2 * op.wx**2 / (op.wy**2 - op.wx**2)
    sf_closed = low_rate_scale_factor(unit, temp)
    sf_full = (full[2] - full[0]) / rates[2]
    zro = zero_rate_output(unit, temp)
    wq = quadrature_rate(unit, temp)
    sat_expected = saturated_output(unit, float(rates[-1]), temp)
    diff = np.abs(full - slow) / np.maximum(np.abs(rates), units.deg_per_s(100.0))
    i = int(np.argmax(diff))
    # the quadrature shift per unit specific force the g-sensitivity check must reject
    wq_g = abs(op.kyx_g / (2.0 * op.m * op.wx)) * low_rate_scale_factor(unit, temp)
    der = (f"RK4 with {STEPS_PER_CYCLE} steps per drive period: 3 (w dt)^4/120 = {tol:.2g} "
           "(relative frequency error in the Coriolis force, AGC amplitude estimate and "
           "demodulation references)")
    return [
        Check(
            id="mems.low_rate_scale_factor",
            formula="SF = s_trim (w/w0) (G0/G) cos(theta) [-] (full integration, 0 and 1000 deg/s)",
            expected=sf_closed,
            simulated=float(sf_full),
            tolerance=tol,
            derivation=der,
        ),
        Check(
            id="mems.quadrature_rejection",
            formula="Omega_hat(0) = SF (c_yx/(2m) - Omega_q tan(theta)) [rad/s]; error / Omega_q",
            expected=zro,
            simulated=float(full[0]),
            tolerance=tol,
            derivation=der + "; measured against the quadrature rate Omega_q it must reject",
            scale=wq,
        ),
        Check(
            id="mems.rate_authority",
            formula=(
                "saturated output at 6000 deg/s: |u| = v_max, Im{kappa_c B} = 0 "
                "(onset SF Omega_max + Omega_hat(0)) [rad/s]"
            ),
            expected=sat_expected,
            simulated=float(full[-1]),
            tolerance=tol,
            derivation=der,
        ),
        Check(
            id="mems.drive_amplitude",
            formula="AGC holds the drive amplitude: mean X_hat = X0 [m] (last 10 ms, all rates)",
            expected=unit.drive_amplitude,
            simulated=float(np.mean(x_full)),
            tolerance=tol,
            derivation=der,
        ),
        Check(
            id="mems.sense_envelope_saturated",
            formula=(
                "complex sense envelope B at 6000 deg/s (rebalance saturated), "
                "|B_full - B_slow| / |B_slow| [m]"
            ),
            expected=0.0,
            simulated=float(abs(b_full[-1] - b_slow[-1])),
            tolerance=tol_b,
            derivation=der + f" x d ln R / d ln w = 2 w^2/(w_y^2 - w^2) = {tol_b / tol:.3g} "
                             "(amplitude and phase of the open-loop sense motion)",
            scale=float(abs(b_slow[-1])),
        ),
        Check(
            id="mems.g_sensitivity",
            formula=(
                "dOmega_hat/df = -SF tan(theta) k_e eps_A (m/k_y) / (2 m w), "
                "k_e = 2 eps0 A V_b^2/g^3 "
                "[rad/s per m/s^2]; (Omega(+20 g) - Omega(-20 g))/(40 g), error / quadrature shift"
            ),
            expected=g_sensitivity(unit, temp),
            simulated=float((g_full[0] - g_full[1]) / (2.0 * G_CASE)),
            tolerance=tol,
            derivation=der + "; measured against the quadrature shift per m/s^2 "
                             "SF (dk_yx/df)/(2 m w) it must reject",
            scale=wq_g,
        ),
        Check(
            id="mems.slow_flow_vs_full",
            formula="max over rates |Omega_slow - Omega_full| / max(|Omega|, 100 deg/s) [-]",
            expected=float(slow[i]),
            simulated=float(full[i]),
            tolerance=tol,
            derivation=der + f"; worst rate {units.to_deg_per_s(rates[i]):g} deg/s",
            scale=float(max(abs(rates[i]), units.deg_per_s(100.0))),
        ),
    ]


#: closed-loop noise check: independent cases of each model, settling dropped [s], the
#: averaging block [s], full-integration cases, slow-flow cases
NVF_SETTLE = 0.015
NVF_BLOCK = 0.01
NVF_FULL_CASES = 1200
NVF_SLOW_CASES = 65536


def _noise_vs_full(rng: np.random.Generator) -> Check:
    """Variance of one 10-ms output mean per independent case, full integration vs slow flow.

    Every case starts at the noise-free equilibrium and is settled for NVF_SETTLE = 15 ms
    (3.5 time constants of the slowest loop pole), then one NVF_BLOCK mean is taken: the block
    means are independent across cases, so the variance about the known mean has exactly
    ``cases`` degrees of freedom (consecutive blocks of one long record are correlated by the
    loop). 1200 x 25 ms of full integration gives tighter bounds than 256 x 4 correlated
    20-ms blocks of 100 ms did, in a third of the RK4 steps.
    """
    unit = check_unit()
    r_full, r_slow = rng.spawn(2)
    fs = 1000.0
    n_set, m = int(round(NVF_SETTLE * fs)), int(round(NVF_BLOCK * fs))
    mu = zero_rate_output(unit)
    full = simulate_full(unit, np.zeros(NVF_FULL_CASES), duration=NVF_SETTLE + NVF_BLOCK, fs=fs,
                         rng=r_full, steps_per_cycle=STEPS_PER_CYCLE, adc=False)
    bf = full.output[n_set:n_set + m].mean(axis=0) - mu
    slow = simulate(unit, np.zeros((n_set + m, NVF_SLOW_CASES)), fs=fs, rng=r_slow, adc=False,
                    flicker=False)
    bs = slow.output[n_set:].mean(axis=0) - mu
    var_full, var_slow = float(np.mean(bf**2)), float(np.mean(bs**2))
    lo, hi = variance_ratio_bounds(bf.size)
    z = 4.89  # two-sided standard-normal quantile at FALSE_ALARM
    sd_slow = math.sqrt(2.0 / bs.size)
    # variance still missing after the settling: at most e^{-2 |Re s|min t_settle}
    settle = math.exp(-2.0 * float(np.min(-operating_point(unit).loop_poles.real)) * NVF_SETTLE)
    tol = max(1 - lo, hi - 1) + z * sd_slow + settle
    return Check(
        id="mems.slow_flow_noise_vs_full",
        formula=(
            f"var of one {NVF_BLOCK * 1e3:g}-ms output mean per independent case after "
            f"{NVF_SETTLE * 1e3:g} ms, Brownian + pick-off noise, full vs slow flow [(rad/s)^2]"
        ),
        expected=var_slow,
        simulated=var_full,
        tolerance=tol,
        derivation=(
            f"chi-square bounds of the full integration's {bf.size} independent block means at "
            f"{FALSE_ALARM:g} two-sided, plus {z} sqrt(2/{bs.size}) for the slow-flow reference, "
            f"plus the settling deficit bound e^(-2 |Re s|min t) = {settle:.1g}"
        ),
    )


def _continuity(rng: np.random.Generator) -> Check:
    unit = replace(check_unit(), output_bits=16)
    fs, dur = 200.0, 20.0
    w = units.deg_per_s(0.1)
    n = int(dur * fs)
    res = simulate(unit, np.tile([w, -w], (n, 1)), fs=fs, rng=rng, flicker=False)
    half = float(res.output[:, 0].mean() - res.output[:, 1].mean()) / 2.0
    sf = low_rate_scale_factor(unit)
    n_tot = math.hypot(brownian_arw(unit), electronic_arw(unit))
    sd = sf * n_tot / math.sqrt(dur) / math.sqrt(2.0)  # half-difference of two independent means
    q = unit.resolution
    sigma_sample = sf * n_tot * math.sqrt(fs)
    dither_bias = q / math.pi * math.exp(-2 * math.pi**2 * sigma_sample**2 / q**2)
    z = 4.89  # two-sided normal quantile at 1e-6
    tol = (z * sd + dither_bias) / (sf * w)
    return Check(
        id="mems.zero_rate_continuity",
        formula="(Omega_hat(+0.1 deg/s) - Omega_hat(-0.1 deg/s))/2 = SF x 0.1 deg/s [rad/s]",
        expected=sf * w,
        simulated=half,
        tolerance=tol,
        derivation=(
            f"{z} sigma of the half-difference of two {dur:g}-s means "
            f"(N = {n_tot:.3g} rad/sqrt(s)), "
            f"plus the dithered-quantizer bias bound (q/pi) exp(-2 pi^2 sigma^2/q^2)"
        ),
    )


def open_loop_unit() -> MemsResonator:
    """:func:`check_unit` read out open loop."""
    return replace(check_unit(), readout="open_loop")


def _open_loop_checks(rng: np.random.Generator) -> list[Check]:
    unit = open_loop_unit()
    temp = unit.reference_temperature + DELTA_T
    rates = units.deg_per_s(np.array(OPEN_RATES_DPS))
    r_full, r_slow = rng.spawn(2)
    res = simulate_full(unit, rates, duration=OPEN_DURATION, fs=1000.0, rng=r_full,
                        temperature=temp, steps_per_cycle=OPEN_STEPS_PER_CYCLE, noise=False,
                        adc=False)
    full = res.output[int(round(OPEN_SETTLE * 1000.0)):].mean(axis=0)
    slow, _ = _slow_noise_free(unit, rates, temp, r_slow)
    op = operating_point(unit, temp)
    sens = 2 * op.wx**2 / (op.wy**2 - op.wx**2)
    tol = rk4_tolerance(unit, OPEN_STEPS_PER_CYCLE) * sens
    der = (f"RK4 with {OPEN_STEPS_PER_CYCLE} steps per drive period: 3 (w dt)^4/120 times the "
           f"receptance's sensitivity to a common frequency error 2 w^2/(w_y^2 - w^2) = {sens:.3g}"
           " (the open-loop output is R F)")
    floor = units.deg_per_s(100.0)
    diff = np.abs(full - slow) / np.maximum(np.abs(rates), floor)
    i = int(np.argmax(diff))
    return [
        Check(
            id="mems.open_loop_scale_factor",
            formula="SF_ol = s_trim (w/w0) Re{e^{-j theta} R(T)/R_c} [-] (full integration, "
                    "0 and 500 deg/s)",
            expected=low_rate_scale_factor(unit, temp),
            simulated=float((full[1] - full[0]) / rates[1]),
            tolerance=tol,
            derivation=der,
        ),
        Check(
            id="mems.open_loop_slow_vs_full",
            formula="open loop: max over rates |Omega_slow - Omega_full| / max(|Omega|, 100 deg/s)"
                    " [-] (0-6000 deg/s, through the pick-off full-scale knee)",
            expected=float(slow[i]),
            simulated=float(full[i]),
            tolerance=tol,
            derivation=der + f"; worst rate {units.to_deg_per_s(rates[i]):g} deg/s",
            scale=float(max(abs(rates[i]), floor)),
        ),
    ]


def _open_loop_response_check(rng: np.random.Generator) -> Check:
    """Slow flow (open loop) driven by sinusoidal rates vs H(f) sinc^2(f/fs) (ZOH in, mean out)."""
    unit = open_loop_unit()
    op = operating_point(unit)
    fs, h = RESPONSE_FS, 1.0 / RESPONSE_FS
    amp = units.deg_per_s(100.0)
    sf, zro, p = low_rate_scale_factor(unit), zero_rate_output(unit), op.pole
    worst = (-1.0, 0.0, 0.0, 1.0, 0.0)  # (rel error / tol, f, |err|, tol, |H|)
    for f in RESPONSE_FREQS_HZ:
        per = int(round(fs / f))
        nset, nrec = int(0.05 * fs), per * max(1, int(round(0.05 * f)))
        t = np.arange(nset + nrec) * h
        res = simulate(unit, amp * np.cos(2 * np.pi * f * t), fs=fs, rng=rng, noise=False,
                       adc=False, flicker=False)
        y, tt = res.output[nset:] - zro, t[nset:]
        a = np.stack([np.cos(2 * np.pi * f * tt), -np.sin(2 * np.pi * f * tt)], axis=1)
        c = np.linalg.lstsq(a, y, rcond=None)[0]
        h_sim = complex(c[0], c[1]) / (amp * sf)
        h_cf = complex(open_loop_response(unit, f)) * float(np.sinc(f * h)) ** 2
        w = 2 * np.pi * f
        gmax = max(abs(-p / (1j * w - p)), abs(-p / (-1j * w - p)))
        t_f = 2 * (w * h) ** 2 / 6 * w / (2 * op.wx) * gmax / abs(h_cf) + 1e-9
        e = abs(h_sim - h_cf) / abs(h_cf)
        if e / t_f > worst[0]:
            worst = (e / t_f, f, e, t_f, abs(h_cf))
    _, f_w, e_w, t_w, _ = worst
    return Check(
        id="mems.open_loop_frequency_response",
        formula=("H(f) = [c_+ G(jW) + conj(c_- G(-jW))]/2 / Re c_0, G(s) = -p/(s - p), "
                 "c_+- ~ -j m X0 (2 w +- W) w_c R; worst of "
                 f"{', '.join(f'{x:g}' for x in RESPONSE_FREQS_HZ)} Hz, |H_sim - H| / |H| [-]"),
        expected=0.0,
        simulated=float(e_w),
        tolerance=float(t_w),
        derivation=(f"at {f_w:g} Hz (worst relative to its tolerance): twice the bound of the "
                    "central-difference Omega' error (W h)^2/6 on the Euler term W/(2 w), times "
                    "max |G(+-jW)| / |H|, plus 1e-9; the ZOH input and interval-mean output are "
                    "in the closed form as sinc^2(f/fs)"),
        scale=1.0,
    )


# ----------------------------------------------------------------------------- noise PSD
#: open-loop noise PSD, full vs slow flow: cases, output rate [Hz], settling and analysed
#: record per case [s], slow-flow columns and record per column [s], band width [Hz]
NOISE_CASES = 2112
NOISE_FS = 3000.0
NOISE_SETTLE = 0.01
NOISE_RECORD = 0.024
NOISE_SLOW_COLS = 64
NOISE_SLOW_DURATION = 20.0
NOISE_BAND = 250.0
#: frequency grid of the autocovariance (points over one fs period) and alias terms summed.
#: The inverse FFT of the spectrum sampled on the grid is the autocovariance aliased in lag by
#: _PSD_GRID / fs = 1.37 s; the slowest decay of either spectrum is the sense envelope's
#: c_y/(2m) ~ 490 /s, so the aliased lags carry e^-660 of the variance (nothing in float64).
_PSD_GRID = 2**12
_PSD_ALIASES = 200


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
    """Two-sided bounds of (s_1^2/sigma_1^2)/(s_2^2/sigma_2^2) ~ F(dof_1, dof_2)."""
    from scipy import stats

    return (float(stats.f.ppf(false_alarm / 2, dof_1, dof_2)),
            float(stats.f.ppf(1 - false_alarm / 2, dof_1, dof_2)))


def open_loop_noise_checks(rng: np.random.Generator) -> list[Check]:
    """Open-loop output noise PSD: full integration (Brownian forces on both modes, pick-off
    noise) vs the slow flow, band by band, against the closed-form ratio of their spectra.

    The full integration runs NOISE_CASES independent cases for NOISE_SETTLE + NOISE_RECORD
    at NOISE_FS. A band of NOISE_BAND holds NOISE_BAND x NOISE_RECORD = 6 periodogram bins,
    so 250-Hz bands of 24-ms records carry the dof per band per case of 100-Hz bands of
    60-ms records at half the RK4 steps (34 ms per case instead of 70; the bands are 2.5 times
    as wide and end at Nyquist); 2112 cases (3 % more than the 2048 of the 60-ms design) make
    up the leakage of the shorter window, so the tolerances are no wider than before (seed 0:
    level 0.046 vs 0.047, worst band 0.050 vs 0.054). The slow flow runs
    NOISE_SLOW_COLS columns of NOISE_SLOW_DURATION cut into segments of the same length. Each
    side's band-mean periodogram has its exact expectation and equivalent dof
    (:func:`periodogram_band_stats`); the full's expectation differs from the slow flow's by
    rho = E_full/E_slow (:func:`full_noise_spectrum` vs :func:`slow_noise_spectrum`: the slow
    flow's first-order envelope and ideal demodulator, the full's held noise force), and
    (P_full/P_slow)/rho ~ F(nu_full, nu_slow).
    """
    unit = open_loop_unit()
    fs = NOISE_FS
    r_full, r_slow = rng.spawn(2)
    n_set, n = int(round(NOISE_SETTLE * fs)), int(round(NOISE_RECORD * fs))
    full = simulate_full(unit, np.zeros(NOISE_CASES), duration=NOISE_SETTLE + NOISE_RECORD,
                         fs=fs, rng=r_full, steps_per_cycle=STEPS_PER_CYCLE, adc=False)
    x_full = full.output[n_set:n_set + n]
    n_seg = int(round(NOISE_SLOW_DURATION * fs)) // n
    slow = simulate(unit, np.zeros(((n_seg + 1) * n, NOISE_SLOW_COLS)), fs=fs, rng=r_slow,
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
        full_noise_spectrum(unit, grid, fs, STEPS_PER_CYCLE), fs, n, bands)
    e_slow, nu_slow = periodogram_band_stats(slow_noise_spectrum(unit, grid, fs), fs, n, bands)
    rho = e_full / e_slow
    p_full = _band_periodogram(x_full, fs, bands).mean(axis=1)
    p_slow = _band_periodogram(x_slow, fs, bands).mean(axis=1)
    dof_f, dof_s = nu_full * NOISE_CASES, nu_slow * n_seg * NOISE_SLOW_COLS
    # the level: the first band (42-250 Hz, inside the ~790 Hz open-loop bandwidth)
    lo0, hi0 = f_ratio_bounds(dof_f[0], dof_s[0], FALSE_ALARM)
    tol0 = max(1 - lo0, hi0 - 1)
    # the shape: every other band up to Nyquist, Bonferroni over them
    m = len(bands) - 1
    worst = (-1.0, 1, 0.0, 1.0)  # (error / tol, band, error, tol)
    for i in range(1, len(bands)):
        lo, hi = f_ratio_bounds(dof_f[i], dof_s[i], FALSE_ALARM / m)
        tol = max(1 - lo, hi - 1)
        e = abs(p_full[i] / (rho[i] * p_slow[i]) - 1)
        if e / tol > worst[0]:
            worst = (e / tol, i, e, tol)
    _, iw, _, tol_w = worst
    sf = low_rate_scale_factor(unit)
    arw = math.sqrt(p_slow[0] * rho[0] / 2.0) / sf
    rec = (f"{NOISE_CASES} full-integration cases x {NOISE_RECORD * 1e3:g} ms at "
           f"{fs:g} Hz ({STEPS_PER_CYCLE} RK4 steps per period; {NOISE_SETTLE * 1e3:g} ms "
           f"settling dropped) vs {n_seg * NOISE_SLOW_COLS} slow-flow segments of the same "
           "length; rectangular-window periodograms")
    band = f"{edges[iw]:g}-{edges[iw] + NOISE_BAND:g} Hz"
    return [
        Check(
            id="mems.open_loop_noise_vs_full",
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
                f"(equivalent dof of the two band means from the closed-form spectra); {rec}; "
                f"rho = E_full/E_slow = {rho[0]:.4f} (closed forms)"
            ),
        ),
        Check(
            id="mems.open_loop_noise_psd_vs_full",
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
                f"two-sided (Bonferroni over the bands); {rec}; rho = E_full/E_slow "
                f"{rho[1:].min():.4f}-{rho[1:].max():.4f} over the bands: the slow flow's "
                "first-order envelope and ideal demodulator overstate the full equations' "
                "noise by up to that much near and above the mode split"
            ),
        ),
    ]


def parts(rng: np.random.Generator) -> list[Part]:
    """The checks in seven independent parts, each with its own child of ``rng``."""
    r = rng.spawn(7)
    funcs = (_arw_check, _full_checks, _noise_vs_full, _continuity, _open_loop_checks,
             _open_loop_response_check, open_loop_noise_checks)
    return [Part(f.__name__.strip("_"), f, (ri,)) for f, ri in zip(funcs, r, strict=True)]


def checks(rng: np.random.Generator) -> list[Check]:
    """Run the MEMS resonator checks (tens of seconds; four short full integrations)."""
    return run_parts(parts(rng))
