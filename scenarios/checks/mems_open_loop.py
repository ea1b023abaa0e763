"""The MEMS open-loop checks of :mod:`gyrobench.scenarios.checks.mems`: the open-loop scale factor
(full integration vs the receptance closed form), open loop slow flow vs full integration, and the
slow flow's frequency response to sinusoidal rates vs the closed-form H(f). They run as two parts
of ``mems.parts``; the tolerances are those of :mod:`gyrobench.scenarios.checks.mems_shared`.
"""

from __future__ import annotations

import numpy as np

from gyrobench.base import units
from gyrobench.scenarios.checks.core import CONSISTENCY, SECOND_METHOD, Check
from gyrobench.scenarios.checks.mems_shared import (
    ACAR_SHKEL,
    DELTA_T,
    SECOND_FULL,
    _slow_noise_free,
    open_loop_unit,
    rk4_tolerance,
)
from gyrobench.sim.mems_full import simulate_full
from gyrobench.sim.mems_resonator import (
    low_rate_scale_factor,
    open_loop_response,
    operating_point,
    zero_rate_output,
)
from gyrobench.sim.mems_slow_flow import slow_flow

__all__: list[str] = []

#: open-loop full integration: steps per drive period, record and settling [s], rates [deg/s]
OPEN_STEPS_PER_CYCLE = 24
OPEN_DURATION = 0.03
OPEN_SETTLE = 0.01
OPEN_RATES_DPS = (0.0, 500.0, 2000.0, 6000.0)
#: sinusoidal-rate frequencies of the open-loop response check [Hz] and its sample rate [Hz]
RESPONSE_FREQS_HZ = (20.0, 200.0, 500.0, 800.0)
RESPONSE_FS = 1e5


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
