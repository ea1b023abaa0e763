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

The shared tolerances, units and references are :mod:`gyrobench.scenarios.checks.mems_shared`;
the noise checks :mod:`gyrobench.scenarios.checks.mems_noise`, the open-loop ones
:mod:`gyrobench.scenarios.checks.mems_open_loop` and :mod:`gyrobench.scenarios.checks.mems_psd`;
:func:`parts` runs them all.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from gyrobench.base import units
from gyrobench.scenarios.checks.core import CLOSED_FORM, SECOND_METHOD, Check, Part, run_parts
from gyrobench.scenarios.checks.mems_noise import _continuity, _low_rate_noise, _noise_vs_full
from gyrobench.scenarios.checks.mems_open_loop import _open_loop_checks, _open_loop_response_check
from gyrobench.scenarios.checks.mems_shared import (
    DELTA_T,
    FALSE_ALARM,
    FULL_DURATION,
    FULL_RATES_DPS,
    FULL_SETTLE,
    G_CASE,
    KAAJAKARI,
    LELAND,
    SAUKOSKI,
    SECOND_FULL,
    STEPS_PER_CYCLE,
    _slow_noise_free,
    check_unit,
    open_loop_unit,
    rk4_tolerance,
    variance_ratio_bounds,
)
from gyrobench.sim.mems_full import simulate_full
from gyrobench.sim.mems_resonator import (
    MemsResonator,
    brownian_arw,
    g_sensitivity,
    low_rate_scale_factor,
    operating_point,
    quadrature_rate,
    saturated_output,
    zero_rate_output,
)
from gyrobench.sim.mems_slow_flow import slow_flow

__all__ = ["checks", "parts", "FALSE_ALARM", "STEPS_PER_CYCLE", "rk4_tolerance", "variance_ratio_bounds",
           "open_loop_unit"]


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
