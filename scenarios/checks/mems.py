"""Closed-form checks of the MEMS resonator gyro (:mod:`gyrobench.sim.mems_resonator`).

``checks(rng) -> list[Check]`` (the contract of :mod:`gyrobench.scenarios.checks.core`):

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
* ``mems.low_output_rate_noise``: the slow flow's output variance at 4 Hz, far below the loop
  (the exact discretisation's sub-step doubling), vs (SF N)^2 fs, chi-square bounds.

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

from gyrobench.base import units
from gyrobench.scenarios.checks.core import CLOSED_FORM, CONSISTENCY, SECOND_METHOD, Check, Part, run_parts
from gyrobench.sim.mems_full import simulate_full
from gyrobench.sim.mems_resonator import (
    MemsResonator,
    brownian_arw,
    electronic_arw,
    g_sensitivity,
    low_rate_scale_factor,
    open_loop_response,
    operating_point,
    quadrature_rate,
    saturated_output,
    zero_rate_output,
)
from gyrobench.sim.mems_slow_flow import slow_flow

__all__ = ["checks", "parts", "FALSE_ALARM", "STEPS_PER_CYCLE", "rk4_tolerance", "variance_ratio_bounds",
           "open_loop_unit"]

#: two-sided false-alarm rate of every statistical check
FALSE_ALARM = 1e-6
#: RK4 steps per drive period of the noise-free closed-loop integration (the least
#: simulate_full takes): its tolerance 3 (w dt)^4/120 = 6.0e-4 (2.4e-4 at the 20 used before,
#: for a quarter more time); every error it bounds but the slow flow's own moved with it as
#: h^4, the largest staying at 0.57 of it, and a 10 % model error is still 170 tolerances out
STEPS_PER_CYCLE = 16
#: full-integration record [s] and the settling part discarded [s]: noise-free, so the 2 ms kept
#: (two output samples) need no length for averaging (the 10 ms kept before changed no check by
#: more than a tenth of its tolerance)
FULL_DURATION = 0.042
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

#: outside references of the checks (docstring of :mod:`gyrobench.sim.mems_resonator`)
LELAND = "R. P. Leland, 'Mechanical-thermal noise in MEMS gyroscopes', IEEE Sensors J. 5(3) 493 (2005)"
ACAR_SHKEL = "C. Acar, A. Shkel, MEMS Vibratory Gyroscopes (Springer, 2009), ch. 2"
SAUKOSKI = ("M. Saukoski, System and circuit design for a capacitive MEMS gyroscope, Helsinki Univ. of "
            "Technology doctoral thesis (2008), ch. 2-3")
KAAJAKARI = "V. Kaajakari, Practical MEMS (Small Gear Publishing, 2009), ch. 6-7"
SECOND_FULL = ("second method: fixed-step RK4 of the full rotating-frame equations of motion with the "
               "carrier (" + ACAR_SHKEL + ")")


def rk4_tolerance(unit: MemsResonator, steps_per_cycle: int = STEPS_PER_CYCLE) -> float:
    """3 (w dt)^4 / 120: RK4's relative frequency error, carried by three observables.

    An error model with a safety factor, not a strict bound: RK4's phase error per step of a
    harmonic oscillator is (w dt)^5/120, i.e. a relative frequency error (w dt)^4/120, and an
    observable that compounds it through up to three factors (frequency, amplitude read-out,
    demodulation) is allowed three times that. Measured at 16, 20 and 32 steps per period the
    RK4-dominated checks stay at a fixed fraction of it (scale factor 0.40, drive amplitude
    0.57-0.61, slow flow vs full 0.40), i.e. their error scales as h^4 as the model says; the
    g-sensitivity and rate-authority checks also carry a step-independent part (3.9e-5 and
    1.5e-5 of their value at 48 steps) the model does not contain, 0.16 and 0.04 of this at 16
    steps. RK4's amplitude loss (w dt)^6/144 per step is outside it: the AGC's start value
    pre-compensates it and the loop absorbs it.

    Parameters
    ----------
    unit : MemsResonator
        The unit integrated.
    steps_per_cycle : int
        RK4 steps per drive period.

    Returns
    -------
    float
        The relative tolerance [-].
    """
    wdt = 2.0 * math.pi / steps_per_cycle
    return 3.0 * wdt**4 / 120.0


def variance_ratio_bounds(dof: float, false_alarm: float = FALSE_ALARM) -> tuple[float, float]:
    """Two-sided chi-square bounds of s^2/sigma^2 with ``dof`` degrees of freedom.

    Parameters
    ----------
    dof : float
        Degrees of freedom.
    false_alarm : float
        Two-sided false-alarm rate.

    Returns
    -------
    tuple of float
        (low, high) of s^2/sigma^2.
    """
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
    res = slow_flow(unit, np.tile(rates, (40, 1)), fs=1000.0, rng=rng, temperature=temperature,
                   noise=False, adc=False, flicker=False)
    return res.output[-1], res.sense_envelope[-1]


def _arw_check(rng: np.random.Generator) -> Check:
    unit = replace(check_unit(), pickoff_noise=0.0)
    # each output sample is the exact interval mean of the rate command (the slow flow carries its
    # integral J), so a 1-s block mean is the same at any fs: 20 Hz costs a tenth of 200 Hz
    fs, cols, dur, block = 20.0, 32, 250.0, 1.0
    n = int(dur * fs)
    res = slow_flow(unit, np.zeros((n, cols)), fs=fs, rng=rng, adc=False, flicker=False)
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
        kind=CLOSED_FORM,
        reference=LELAND,
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
            kind=SECOND_METHOD,
            reference=SECOND_FULL + "; closed form (force rebalance, demodulation phase): " + SAUKOSKI,
            formula="SF = s_trim (w/w0) (G0/G) cos(theta) [-] (full integration, 0 and 1000 deg/s)",
            expected=sf_closed,
            simulated=float(sf_full),
            tolerance=tol,
            derivation=der,
        ),
        Check(
            id="mems.quadrature_rejection",
            kind=SECOND_METHOD,
            reference=SECOND_FULL + "; closed form (quadrature through the demodulation phase error): " + SAUKOSKI,
            formula="Omega_hat(0) = SF (c_yx/(2m) - Omega_q tan(theta)) [rad/s]; error / Omega_q",
            expected=zro,
            simulated=float(full[0]),
            tolerance=tol,
            derivation=der + "; measured against the quadrature rate Omega_q it must reject",
            scale=wq,
        ),
        Check(
            id="mems.rate_authority",
            kind=SECOND_METHOD,
            reference=SECOND_FULL + "; closed form (the feedback force range bounds the input range): " + SAUKOSKI,
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
            kind=SECOND_METHOD,
            reference=SECOND_FULL + "; drive amplitude control: " + SAUKOSKI,
            formula="AGC holds the drive amplitude: mean X_hat = X0 [m] (last 2 ms, all rates)",
            expected=unit.drive_amplitude,
            simulated=float(np.mean(x_full)),
            tolerance=tol,
            derivation=der,
        ),
        Check(
            id="mems.sense_envelope_saturated",
            kind=SECOND_METHOD,
            reference=SECOND_FULL + " against the averaged slow flow",
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
            kind=SECOND_METHOD,
            reference=SECOND_FULL + "; closed form (parallel-plate electrostatic spring): " + KAAJAKARI,
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
            kind=SECOND_METHOD,
            reference=SECOND_FULL + " against the averaged slow flow",
            formula="max over rates |Omega_slow - Omega_full| / max(|Omega|, 100 deg/s) [-]",
            expected=float(slow[i]),
            simulated=float(full[i]),
            tolerance=tol,
            derivation=der + f"; worst rate {units.to_deg_per_s(rates[i]):g} deg/s",
            scale=float(max(abs(rates[i]), units.deg_per_s(100.0))),
        ),
    ]


#: closed-loop noise check: settling dropped [s], the averaging block [s] and blocks per case,
#: RK4 steps per drive period, full-integration cases, slow-flow cases
NVF_SETTLE = 0.01
NVF_BLOCK = 0.002
NVF_BLOCKS = 8
NVF_STEPS_PER_CYCLE = 16
NVF_FULL_CASES = 960
NVF_SLOW_CASES = 8192


def _block_covariance(b: np.ndarray) -> np.ndarray:
    """Covariance of the block means b (blocks, cases) about their known zero mean."""
    return (b @ b.T) / b.shape[1]


def _noise_vs_full(rng: np.random.Generator) -> Check:
    """Mean square of NVF_BLOCKS consecutive 2-ms output means per independent case, full
    integration vs slow flow, F-test on Satterthwaite's equivalent degrees of freedom.

    Every case starts at the noise-free equilibrium and is settled for NVF_SETTLE = 10 ms
    (2.4 time constants of the slowest loop pole, variance deficit e^{-2 |Re s|min t} < 0.009,
    added to the tolerance), then NVF_BLOCKS block means are taken. The blocks of one case are
    correlated by the loop; their covariance C (NVF_BLOCKS x NVF_BLOCKS) is measured on the
    slow flow's NVF_SLOW_CASES independent cases (under the null hypothesis that the models
    agree it is the full integration's too), and the mean square over the blocks of one case
    has the equivalent dof (tr C)^2 / sum C_jl^2 (Gaussian: var of a quadratic form
    2 tr(C^2)). Eight 2-ms blocks give about 3.7 dof per 26-ms case, against 1 dof per 25-ms
    case of an earlier design (one 10-ms mean per case): 960 cases at 16 RK4 steps per
    period bound the variance ratio to +-0.13 (was +-0.23 with 1200 cases at 20 steps, 1.6
    times the RK4 work), so a 10 % error in the noise amplitude (21 % in variance) is caught
    (tests/scenarios/test_checks_catch_errors.py). A full case costs ~55 slow-flow cases and
    the band's variance goes as 1/N_full + 1/N_slow, so the cheapest split has N_slow/N_full
    ~ sqrt(55) ~ 7: 960 + 8192 give a slightly narrower band than the 900 + 16384 used before
    (1/N_full + 1/N_slow 1.164e-3 vs 1.172e-3) at less cost. The 2-ms block's sinc^2 null at
    500 Hz sits on the mode split, where the slow flow's first-order envelope departs from the
    full equations (mems.open_loop_noise_psd_vs_full).
    """
    from scipy import stats

    unit = check_unit()
    r_full, r_slow = rng.spawn(2)
    fs = 1000.0
    n_set, m = int(round(NVF_SETTLE * fs)), int(round(NVF_BLOCK * fs))
    n_rec = m * NVF_BLOCKS
    mu = zero_rate_output(unit)
    full = simulate_full(unit, np.zeros(NVF_FULL_CASES), duration=(n_set + n_rec) / fs, fs=fs,
                         rng=r_full, steps_per_cycle=NVF_STEPS_PER_CYCLE, adc=False)
    bf = full.output[n_set:n_set + n_rec].reshape(NVF_BLOCKS, m, -1).mean(axis=1) - mu
    slow = slow_flow(unit, np.zeros((n_set + n_rec, NVF_SLOW_CASES)), fs=fs, rng=r_slow, adc=False,
                    flicker=False)
    bs = slow.output[n_set:].reshape(NVF_BLOCKS, m, -1).mean(axis=1) - mu
    var_full, var_slow = float(np.mean(bf**2)), float(np.mean(bs**2))
    c = _block_covariance(bs)
    per_case = float(np.trace(c) ** 2 / np.sum(c**2))
    dof_f, dof_s = per_case * NVF_FULL_CASES, per_case * NVF_SLOW_CASES
    lo, hi = (float(q) for q in stats.f.ppf([FALSE_ALARM / 2, 1 - FALSE_ALARM / 2], dof_f, dof_s))
    # variance still missing after the settling: at most e^{-2 |Re s|min t_settle}
    settle = math.exp(-2.0 * float(np.min(-operating_point(unit).loop_poles.real)) * NVF_SETTLE)
    tol = max(1 - lo, hi - 1) + settle
    return Check(
        id="mems.slow_flow_noise_vs_full",
        kind=SECOND_METHOD,
        reference=(
            SECOND_FULL + " against the slow flow; Satterthwaite, Biometrics Bull. 2(6) 110 (1946) for the "
            "equivalent dof"
        ),
        formula=(
            f"mean square of {NVF_BLOCKS} consecutive {NVF_BLOCK * 1e3:g}-ms output means per "
            f"independent case after {NVF_SETTLE * 1e3:g} ms, Brownian + pick-off noise, closed "
            "loop, full vs slow flow [(rad/s)^2]"
        ),
        expected=var_slow,
        simulated=var_full,
        tolerance=tol,
        derivation=(
            f"F({dof_f:.0f}, {dof_s:.0f}) bounds at {FALSE_ALARM:g} two-sided: {NVF_FULL_CASES} "
            f"full-integration cases ({NVF_STEPS_PER_CYCLE} RK4 steps per period) and "
            f"{NVF_SLOW_CASES} slow-flow cases, {per_case:.2f} equivalent dof per case "
            "(tr C)^2/sum C^2 from the slow flow's block covariance C; plus the settling deficit "
            f"bound e^(-2 |Re s|min t) = {settle:.1g}"
        ),
    )


def _continuity(rng: np.random.Generator) -> Check:
    unit = replace(check_unit(), output_bits=16)
    fs, dur = 200.0, 20.0
    w = units.deg_per_s(0.1)
    n = int(dur * fs)
    res = slow_flow(unit, np.tile([w, -w], (n, 1)), fs=fs, rng=rng, flicker=False)
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
        kind=CONSISTENCY,
        reference=(
            "B. Widrow, I. Kollar, Quantization Noise (Cambridge Univ. Press, 2008): mean of a "
            "quantizer with Gaussian dither; " + LELAND
        ),
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
    """:func:`check_unit` read out open loop.

    Returns
    -------
    MemsResonator
        The check unit with readout ``"open_loop"``.
    """
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
            kind=SECOND_METHOD,
            reference=SECOND_FULL + "; closed form (open-loop sense response through the receptance): " + ACAR_SHKEL,
            formula="SF_ol = s_trim (w/w0) Re{e^{-j theta} R(T)/R_c} [-] (full integration, "
                    "0 and 500 deg/s)",
            expected=low_rate_scale_factor(unit, temp),
            simulated=float((full[1] - full[0]) / rates[1]),
            tolerance=tol,
            derivation=der,
        ),
        Check(
            id="mems.open_loop_slow_vs_full",
            kind=SECOND_METHOD,
            reference=SECOND_FULL + " against the averaged slow flow, open loop",
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
        res = slow_flow(unit, amp * np.cos(2 * np.pi * f * t), fs=fs, rng=rng, noise=False,
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
        kind=CONSISTENCY,
        reference=(
            "second method: the exact-discretised slow flow (C. F. Van Loan, IEEE Trans. Autom. "
            "Control 23(3) 395 (1978)) driven by sinusoidal rates against the closed-form response; " + ACAR_SHKEL
        ),
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


#: low-output-rate noise check: output rate [Hz] (-Re(pole)/fs ~ 60-120 for the check unit,
#: where the exact discretisation needs the Van Loan sub-steps and doubling), columns, samples
LOW_FS = 4.0
LOW_COLS, LOW_SAMPLES = 256, 250


def _low_rate_noise(rng: np.random.Generator) -> Check:
    """Output noise of the slow flow at LOW_FS (far below the loop) vs the closed form N^2 fs.

    Each output sample is the interval mean of the rate-equivalent white noise, one-sided PSD
    2 N^2 with N = hypot(N_B, N_e) input-referred, so its variance is (SF N)^2 fs. Known mean
    (the zero-rate output): the mean square of the LOW_COLS x LOW_SAMPLES samples has
    chi-square bounds on that many dof (adjacent interval means are correlated only through the
    loop's settling, O(fs/|Re s|)); the loop's finite bandwidth takes at most 2 fs/|Re s|min of
    the variance (a deficit), added to the tolerance. The exact discretisation at -Re(s) h ~ 60
    lost Q_d to rounding before the sub-step doubling (48x the closed form at 8 Hz).
    """
    from scipy import stats

    unit = check_unit()
    fs = LOW_FS
    res = slow_flow(unit, np.zeros((LOW_SAMPLES, LOW_COLS)), fs=fs, rng=rng, adc=False, flicker=False)
    x = res.output - zero_rate_output(unit)
    sf = low_rate_scale_factor(unit)
    n_tot = math.hypot(brownian_arw(unit), electronic_arw(unit))
    dof = x.size
    lo, hi = (float(q) / dof for q in stats.chi2.ppf([FALSE_ALARM / 2, 1 - FALSE_ALARM / 2], dof))
    pole = float(np.min(-operating_point(unit).loop_poles.real))
    bias = 2.0 * fs / pole
    return Check(
        id="mems.low_output_rate_noise",
        kind=CLOSED_FORM,
        reference=(
            LELAND + " (N_B); IEEE Std 952-1997, Annex C (angle random walk: the tau-mean of white rate "
            "noise has variance N^2/tau); exact discretisation: C. F. Van Loan, IEEE Trans. Autom. "
            "Control 23(3) 395 (1978)"
        ),
        formula=(
            f"variance of the output samples at fs = {fs:g} Hz (closed loop, Brownian + pick-off noise) "
            "= (SF N)^2 fs, N = hypot(N_B, N_e) [(rad/s)^2]"
        ),
        expected=(sf * n_tot) ** 2 * fs,
        simulated=float(np.mean(x**2)),
        tolerance=max(1.0 - lo, hi - 1.0) + bias,
        derivation=(
            f"mean square of {dof} samples about the known zero-rate output: chi-square({dof}) bounds at "
            f"{FALSE_ALARM:g} two-sided, the wider side, plus the loop-bandwidth deficit bound "
            f"2 fs/|Re s|min = {bias:.2g} (|Re s|min/fs = {pole / fs:.0f})"
        ),
    )


def parts(rng: np.random.Generator) -> list[Part]:
    """Split the MEMS checks into eight independent parts.

    Each part has its own child of ``rng`` (the eighth added last: the first seven children are
    those of ``rng.spawn(7)``).

    Parameters
    ----------
    rng : numpy.random.Generator
        The module's stream (the collector's contract; a deterministic module does not draw from it).

    Returns
    -------
    list of Part
        Independent parts, each with its own arguments (children of ``rng`` where it draws).
    """
    from gyrobench.scenarios.checks.mems_psd import open_loop_noise_checks  # it imports this module

    r = rng.spawn(8)
    funcs = (_arw_check, _full_checks, _noise_vs_full, _continuity, _open_loop_checks,
             _open_loop_response_check, open_loop_noise_checks, _low_rate_noise)
    return [Part(f.__name__.strip("_"), f, (ri,)) for f, ri in zip(funcs, r, strict=True)]


def checks(rng: np.random.Generator) -> list[Check]:
    """Run the MEMS resonator checks (tens of seconds; four short full integrations).

    Parameters
    ----------
    rng : numpy.random.Generator
        The module's stream (the collector's contract; a deterministic module does not draw from it).

    Returns
    -------
    list of Check
        The module's checks.
    """
    return run_parts(parts(rng))
