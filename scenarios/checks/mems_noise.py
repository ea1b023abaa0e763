"""The MEMS noise checks of :mod:`gyrobench.scenarios.checks.mems`: the closed loop's output noise,
slow flow vs full integration (F test on Satterthwaite's dof), the zero-rate continuity through
the quantizer, and the slow flow's noise at a low output rate (chi-square bounds). They run as
three parts of ``mems.parts``; the tolerances are those of
:mod:`gyrobench.scenarios.checks.mems_shared`.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from gyrobench.base import units
from gyrobench.scenarios.checks.core import CLOSED_FORM, CONSISTENCY, SECOND_METHOD, Check
from gyrobench.scenarios.checks.mems_shared import (
    FALSE_ALARM,
    LELAND,
    SECOND_FULL,
    check_unit,
)
from gyrobench.sim.mems_full import simulate_full
from gyrobench.sim.mems_resonator import (
    brownian_arw,
    electronic_arw,
    low_rate_scale_factor,
    operating_point,
    zero_rate_output,
)
from gyrobench.sim.mems_slow_flow import slow_flow

__all__: list[str] = []

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
