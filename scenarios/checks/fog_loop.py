"""Closed-form checks of the closed-loop FOG (:mod:`gyrobench.sim.fog_loop`, ``fog_optics``,
``fiber_strain``).

- The optical budget's current-noise terms, each against something outside the code: shot
  noise 2 q i against a photocurrent of Poisson photo-electron counts, excess RIN 2/dnu against
  the measured intensity noise of simulated polarised thermal light (Goodman 1985), the
  feedback resistor's 4 k T/R against a textbook's printed Johnson-noise example.
- ARW of the optical budget, N = sqrt(S_phi/2)/SF (shot + excess RIN + thermal; Lefevre
  sec. 5.3), against the reduced record (1 s angle increments, chi-square with one degree of
  freedom per block) and against the full-rate loop (block sums of M transits whose exact
  variance s^2 v(M) comes from the loop's impulse response, normal bound with the MA(1)
  correlation).
- Loop transfer H(z) = G/(1 + G), G = g z^-d (1 + z^-1)/2/(1 - z^-1): the full nonlinear loop's
  amplitude at 3 kHz and its step response.
- 2 pi resets: the count over a record equals the accumulated ramp phase / 2 pi (within one
  reset), i.e. the angle / angle quantum; the V_2pi loop removes a 2 % modulator gain error
  from the scale factor, blanked reset samples leave -eps/(1 + eps).
- The strain kernel of :mod:`gyrobench.sim.fiber_strain` itself (two-crossing-time integral,
  exact kernel, reduced form against the full loop) is checked in
  :mod:`gyrobench.scenarios.checks.fog_strain`.
- Random (PSD) vibration: the mean square of the strain error samples against
  int |G(f)|^2 S_a(f) df through modes, exact kernel, loop and integrate-and-dump (aliasing
  changes the PSD, not the variance), chi-square band with nu = 2 B_e T.
- Vibration through the reduced chain: the strain tone of a record against
  K kappa W w |H_k(f)| |H(f)| sinc(f/fs) a; the reduced chain against the full loop for a
  500 Hz tone; rectification of the full loop with a loss modulation against
  m phi_res cos(theta)/(2 SF) (docs/physics.md 4.1).

Tolerances are derived where each check is built (docstrings/derivation strings).
"""

from __future__ import annotations

import math

import numpy as np

from gyrobench.scenarios.checks.core import CLOSED_FORM, CONSISTENCY, PRINTED, SECOND_METHOD, Check, Part, run_parts
from gyrobench.sim.sensor import Environment

__all__ = ["checks", "parts", "FALSE_ALARM", "LEFEVRE", "STRAIN"]

#: false-alarm rate of each statistical check
FALSE_ALARM = 1e-6
#: outside references of the checks
LEFEVRE = "H. C. Lefevre, The Fiber-Optic Gyroscope, 2nd ed. (Artech House, 2014)"
ARDITTY = "H. J. Arditty, H. C. Lefevre, 'Sagnac effect in fiber gyroscopes', Opt. Lett. 6(8) 401 (1981)"
STRAIN = (LEFEVRE + ", sec. 3.2 (time-varying perturbations, the (L - 2z) weighting); D. M. Shupe, Appl. Opt. "
          "19(5) 654 (1980); elasto-optic factor: Bertholds & Dandliker, J. Lightwave Technol. 6(1) 17 (1988)")


def _z() -> float:
    from scipy import stats

    return float(stats.norm.isf(FALSE_ALARM / 2))


def _arw_reduced(rng: np.random.Generator) -> Check:
    from scipy import stats

    from gyrobench.sim.fog_loop import ClosedLoopFOG

    unit = ClosedLoopFOG(modes=())
    rec = unit.simulate(Environment(600.0), fs=400.0, rng=rng)
    noise = rec["output"] - rec["truth/true_rate"]
    ang = noise.reshape(-1, 400).sum(axis=1) / 400.0
    n = len(ang)
    n2 = float(np.mean(ang**2))
    hi = stats.chi2.isf(FALSE_ALARM / 2, n) / n
    lo = stats.chi2.ppf(FALSE_ALARM / 2, n) / n
    # N_hat/N = sqrt(chi2/n): relative band on N
    tol = max(math.sqrt(hi) - 1, 1 - math.sqrt(lo))
    return Check(
        id="fog.loop_arw_optical_budget",
        kind=CONSISTENCY,
        reference=LEFEVRE + ", sec. 5.3 (shot, excess-RIN and thermal noise of the detected signal)",
        formula="N = sqrt(S_phi/2)/SF, S_phi = 2q/(i0 sin^2(phi_b/2)) + cot^2(phi_b/2)/dnu "
        "+ S_th/((i0/2)^2 sin^2 phi_b) [rad/sqrt(s)]; reduced record 600 s at 400 Hz",
        expected=unit.arw,
        simulated=math.sqrt(n2),
        tolerance=tol,
        derivation=f"{n} zero-mean 1 s angle increments: N_hat^2/N^2 ~ chi2({n})/{n}; "
        f"two-sided band at {FALSE_ALARM:g} on N (the loop's block correction c/(400 M) "
        "~ 4e-5 is far inside)",
    )


def _arw_full(rng: np.random.Generator) -> Check:
    from scipy import stats

    from gyrobench.sim.fog_loop import LoopSpec, run_loop
    from gyrobench.sim.fog_optics import OpticalBudget

    spec = LoopSpec(gain_loop=False)
    optics = OpticalBudget()
    m, n_out = 64, 6000
    run = run_loop(spec, np.zeros(m * n_out), samples_per_output=m, optics=optics, rng=rng)
    tau = spec.transit_time
    v, cv = spec.block_noise_moments(m)
    # N^2 from block sums: var(angle) = s^2 v(M), s^2 = S_phi/(2 tau) (tau/SF)^2 = N^2 tau
    ang = run.rate[10:] / run.fs
    n2_hat = float(np.mean(ang**2)) / (tau * v)
    rho = cv / v
    dof = len(ang) / (1 + 2 * rho**2)  # equivalent dof of the mean square of an MA(1)
    lo = stats.chi2.ppf(FALSE_ALARM / 2, dof) / dof
    hi = stats.chi2.isf(FALSE_ALARM / 2, dof) / dof
    return Check(
        id="fog.loop_full_arw_optical_budget",
        kind=SECOND_METHOD,
        reference=LEFEVRE + ", sec. 5.3; second method: the full-rate loop's block sums against the reduced record",
        formula="var(block angle of M transits) = N^2 tau v(M), v(M) = sum_{|l|<M} (M-|l|) "
        "r_h(l); full-rate loop, M = 64, detector noise from the budget",
        expected=spec.arw(optics),
        simulated=math.sqrt(n2_hat),
        tolerance=max(math.sqrt(hi) - 1, 1 - math.sqrt(lo)),
        derivation=f"{len(ang)} block sums with MA(1) correlation rho = {rho:.3f}: equivalent "
        f"dof n/(1 + 2 rho^2) = {dof:.0f}; two-sided chi-square band at {FALSE_ALARM:g} on N",
    )


def _loop_response() -> list[Check]:
    from scipy import signal

    from gyrobench.sim.fog_loop import LoopSpec, run_loop

    spec = LoopSpec(gain_loop=False)
    f = 3000.0
    k = np.arange(1 << 15)
    w = 2 * np.pi * f * spec.transit_time
    amp = 1e-3
    y = -run_loop(spec, amp * np.sin(w * k), samples_per_output=1).delta
    sl = slice(2000, None)
    basis = np.column_stack([np.sin(w * k[sl]), np.cos(w * k[sl])])
    c, *_ = np.linalg.lstsq(basis, y[sl], rcond=None)
    h = complex(spec.transfer(f))
    step = np.full(4096, amp)
    b, a = spec._poly()
    lin = signal.lfilter(b, a, step)
    ys = -run_loop(spec, step, samples_per_output=1).delta
    nl = amp**2 / 6  # sin x = x - x^3/6: relative error of the slope <= x^2/6 at |x| <= amp
    return [
        Check(
            id="fog.loop_frequency_response",
            kind=CONSISTENCY,
            reference=LEFEVRE + ", ch. 6 (closed loop, digital phase ramp)",
            formula="|H(e^{j w tau})|, H = G/(1+G), G = g z^-1 (1+z^-1)/2/(1-z^-1); g = 0.1, "
            "f = 3 kHz",
            expected=abs(h),
            simulated=math.hypot(*c) / amp,
            tolerance=10 * nl + 1e-6,
            derivation="loop nonlinearity sin x vs x: <= x^2/6 relative at |x| <= 1e-3 rad (x10 "
            "for its accumulation over the loop's memory) + 1e-6 for the least-squares fit of "
            "30 000 samples after the start transient",
        ),
        Check(
            id="fog.loop_step_response",
            kind=CONSISTENCY,
            reference=LEFEVRE + ", ch. 6 (closed loop, digital phase ramp)",
            formula="-delta_k = (h * phi)_k for a phase step phi = 1e-3 rad; largest deviation "
            "of the full loop from the linear H over 4096 transits, relative to the step",
            expected=amp,
            simulated=amp + float(np.max(np.abs(ys - lin))),
            tolerance=10 * nl,
            derivation="nonlinearity x^2/6 of the error signal during the transient, x10 for "
            "its accumulation",
        ),
    ]


def _resets(rng: np.random.Generator) -> list[Check]:
    from gyrobench.sim.fog_loop import LoopSpec, run_loop
    from gyrobench.sim.fog_optics import OpticalBudget

    spec = LoopSpec(gain_loop=False)
    om = 0.0123  # rad/s
    m, n_out = 512, 400
    run = run_loop(
        spec,
        np.full(m * n_out, spec.scale_factor * om),
        samples_per_output=m,
        optics=OpticalBudget(),
        rng=rng,
    )
    count = float(-run.resets.sum())
    accumulated = float(-run.delta.sum()) / (2 * math.pi)
    expected_rate = om * len(run.delta) * spec.transit_time / spec.angle_quantum
    eps = 0.02
    # noise-free scale-factor records: the V_2pi loop takes the 2 % gain error to < 1e-7 by
    # output 80 and to rounding (1e-15) by output 150 (about one e-fold per 10 outputs); the
    # blanked loop is linear after 5 outputs. 400 outputs (1200 before) leave the averaged
    # last 200 (from output 200) past both transients, at a third of the cost.
    n_sf = 400
    sv = LoopSpec(modulator_gain_error=eps, gain_loop=True)
    rv = run_loop(sv, np.full(m * n_sf, sv.scale_factor * om), samples_per_output=m)
    sb = LoopSpec(modulator_gain_error=eps, gain_loop=False, reset_blanking=True)
    rb = run_loop(sb, np.full(m * n_sf, sb.scale_factor * om), samples_per_output=m)
    return [
        Check(
            id="fog.loop_reset_count",
            kind=CONSISTENCY,
            reference=LEFEVRE + ", ch. 6 (digital phase ramp and its 2 pi resets)",
            formula="number of 2 pi resets = accumulated ramp phase / (2 pi) (+-1); noisy record, "
            f"Omega = {om} rad/s, {len(run.delta)} transits",
            expected=accumulated,
            simulated=count,
            tolerance=1.0 / accumulated,
            derivation="the ramp register stays in [0, 2 pi): count and accumulated phase / 2 pi "
            "differ by less than one reset",
        ),
        Check(
            id="fog.loop_reset_rate",
            kind=CLOSED_FORM,
            reference=LEFEVRE + ", ch. 6 (one reset per angle quantum n_g lambda / D); " + ARDITTY,
            formula="resets = Omega T / (angle quantum), quantum = 2 pi tau/SF = n_g lambda/D",
            expected=expected_rate,
            simulated=count,
            tolerance=(
                1.0
                + _z()
                * spec.arw(OpticalBudget())
                * math.sqrt(len(run.delta) * spec.transit_time)
                / spec.angle_quantum
            )
            / expected_rate,
            derivation="one reset of register quantisation plus z(1e-6) x the ARW angle noise "
            "N sqrt(T) in quanta",
        ),
        Check(
            id="fog.loop_v2pi_scale_factor",
            kind=CLOSED_FORM,
            reference=LEFEVRE + ", ch. 6 (V_2pi control by the reset error)",
            formula="SF ratio with the V_2pi loop on and a 2 % modulator gain error = 1",
            expected=1.0,
            simulated=float(rv.rate[-200:].mean() / om),
            tolerance=1e-6,
            derivation="the gain loop drives G - 1 to < 1e-7 (integral control); 1 ppm allows "
            "the reset ripple in a 200-sample mean",
        ),
        Check(
            id="fog.loop_blanked_reset_scale_factor",
            kind=CLOSED_FORM,
            reference=LEFEVRE + ", ch. 6 (V_2pi control by the reset error)",
            formula="SF ratio with reset samples blanked = 1/(1 + eps), eps = 0.02",
            expected=1.0 / (1.0 + eps),
            simulated=float(rb.rate[200:].mean() / om),
            tolerance=1e-9,
            derivation="noise-free, linear after lock: float64 rounding of the block sums",
        ),
    ]


def _vibration_chain(rng: np.random.Generator) -> list[Check]:
    from gyrobench.base import units
    from gyrobench.sim.fiber_strain import StrainMode
    from gyrobench.sim.fog_loop import ClosedLoopFOG, LoopSpec, loop_average, run_loop
    from gyrobench.sim.shaker import FixedSine

    mode = StrainMode(frequency=300.0, quality=30.0, strain=3e-12, weight=500.0)
    unit = ClosedLoopFOG(modes=(mode,))
    fs, f, a0 = 400.0, 150.0, units.g(2.0)
    sh = FixedSine(frequency=f, duration=10.0, acceleration=a0).sample(8 * fs, rng=rng)
    rec = unit.simulate(Environment(10.0, vibration=sh), fs=fs, rng=rng)
    y = rec["truth/strain_nonreciprocity"]
    t = rec.time + 0.5 / fs
    basis = np.column_stack([np.sin(2 * np.pi * f * t), np.cos(2 * np.pi * f * t)])
    c, *_ = np.linalg.lstsq(basis, y, rcond=None)
    cf = (
        unit.strain_coefficient()
        * mode.strain
        * mode.weight
        * 2
        * np.pi
        * f
        * a0
        * abs(mode.response(f)[()])
        * abs(unit.loop.transfer(f))
        * abs(np.sinc(f / fs))
    )
    spec = LoopSpec(gain_loop=False)
    m, n_out, kp = 512, 100, 16
    fo = 1 / (m * spec.transit_time)
    fv = round(500.0 * n_out / fo) * fo / n_out
    amp = 1e-3
    x = amp * np.sin(2 * np.pi * fv * np.arange(n_out * kp) / (kp * fo))
    red = loop_average(np.fft.rfft(x), len(x), kp * fo, fo, spec)
    k = np.arange(n_out * m)
    ph = spec.scale_factor * amp * np.sin(2 * np.pi * fv * (k + 0.5) * spec.transit_time)
    full = run_loop(spec, ph, samples_per_output=m).rate
    mid = (2 * np.pi * fv * spec.transit_time) ** 2 / 24
    return [
        Check(
            id="fog.vibration_strain_tone",
            kind=CONSISTENCY,
            reference=STRAIN,
            formula="tone = K kappa W w a |H_k(f)| |H(f)| sinc(f/fs), K = n_g n xi/(L D); "
            "150 Hz, 2 g, mode 300 Hz Q 30; reduced record at 400 Hz",
            expected=float(cf),
            simulated=math.hypot(*c),
            tolerance=1e-9,
            derivation="the frequency-domain chain is exact for a whole number of cycles; "
            "1e-9 for FFT and least-squares rounding",
        ),
        Check(
            id="fog.vibration_reduced_vs_full_loop",
            kind=SECOND_METHOD,
            reference=(
                "second method: the full-rate loop, transit by transit (" + LEFEVRE +
                ", ch. 6), against the reduced form"
            ),
            formula="reduced form (H, integrate-and-dump sinc, block centres) vs the full-rate "
            "loop for a 500 Hz rate tone of 1e-3 rad/s; largest output difference / amplitude",
            expected=amp,
            simulated=amp + float(np.max(np.abs(full[2:] - red[2:]))),
            tolerance=2 * mid + 1e-6,
            derivation=f"midpoint-rule error of the transit sum (w tau)^2/24 = {mid:.2g}, twice, "
            "+ 1e-6 for the loop's start transient and rounding",
        ),
    ]


def _random_vibration(rng: np.random.Generator) -> Check:
    from scipy import stats

    from gyrobench.base import units
    from gyrobench.sim.fog_loop import ClosedLoopFOG
    from gyrobench.sim.shaker import RandomVibration

    unit = ClosedLoopFOG()  # default modes: pigtail 300 Hz, coil 1.2 kHz, fixture 900 Hz
    bp = ((20.0, 0.01), (80.0, 0.04), (350.0, 0.04), (2000.0, 0.007))  # NAVMAT P-9492
    fs, m, dur = 100.0, 42, 60.0
    rv = RandomVibration(breakpoints=bp, duration=dur)
    g0 = units.g(1.0)

    def psd(f):
        return rv.shaped_psd(f) * g0**2

    var = unit.vibration_error_variance(psd, fs, bp[-1][0])
    fo, sy = unit.vibration_error_psd(psd, fs, bp[-1][0])
    b_e = float(np.trapezoid(sy, fo) ** 2 / np.trapezoid(sy**2, fo))
    nu = 2.0 * b_e * dur
    lo = stats.chi2.ppf(FALSE_ALARM / 2, nu) / nu
    hi = stats.chi2.isf(FALSE_ALARM / 2, nu) / nu
    sh = rv.sample(fs * m, rng=rng)
    rec = unit.simulate(Environment(dur, vibration=sh), fs=fs, rng=rng)
    y = rec["truth/strain_nonreciprocity"]
    return Check(
        id="fog.vibration_random_psd_variance",
        kind=CONSISTENCY,
        reference=(
            "J. S. Bendat, A. G. Piersol, Random Data: Analysis and Measurement Procedures (Wiley): "
            "mean-square estimate of a Gaussian process, nu = 2 B_e T; NAVMAT P-9492 (1979) spectrum; " + STRAIN
        ),
        formula="var(strain error samples) = int |G(f)|^2 S_a(f) df, G = K kappa jw H_k(f) "
        "e^{-jw tau/2} W(w) H(e^{jw tau}) sinc(f/fs) summed over modes; NAVMAT P-9492 "
        f"random vibration ({rv.grms:.2f} grms, 20-2000 Hz), 60 s at fs = 100 Hz (aliased)",
        expected=var,
        simulated=float(np.mean(y**2)),
        tolerance=max(hi - 1.0, 1.0 - lo),
        derivation=f"mean square of {len(y)} samples of a zero-mean Gaussian process: "
        f"chi2(nu)/nu with nu = 2 B_e T = {nu:.0f} (B_e = (int S_y)^2/int S_y^2 = "
        f"{b_e:.1f} Hz of the folded output PSD S_y, T = 60 s; Bendat & Piersol); two-sided "
        f"at {FALSE_ALARM:g}. The shaker's random-phase synthesis has fixed amplitudes, so the "
        "spread is at most the Gaussian one (conservative)",
    )


def _rectification() -> Check:
    from gyrobench.sim.fog_loop import LoopSpec, run_loop

    spec = LoopSpec(gain_loop=False)
    m, n_out = 512, 400
    fs = 1 / (m * spec.transit_time)
    f = round(500 * n_out / fs) * fs / n_out
    om0, m0, th = 0.05, 1e-2, 0.3
    tk = (np.arange(n_out * m) + 0.5) * spec.transit_time
    ph = spec.scale_factor * om0 * np.sin(2 * np.pi * f * tk)
    mk = m0 * np.cos(2 * np.pi * f * tk + th)
    bias = float(
        (
            run_loop(spec, ph, samples_per_output=m, intensity=mk).rate
            - run_loop(spec, ph, samples_per_output=m).rate
        )[2:].mean()
    )
    hf = complex(spec.transfer(f))
    x_res = spec.scale_factor * om0 * abs(1 - hf)
    p_res = spec.scale_factor * om0 * (1 - hf) * -1j  # phasor of the residual (sin -> -j)
    closed = float(np.real(m0 * np.exp(1j * th) * np.conj(p_res))) / (2 * spec.scale_factor)
    return Check(
        id="fog.vibration_rectification_full_loop",
        kind=SECOND_METHOD,
        reference=(
            "second method: the full nonlinear loop (" + LEFEVRE +
            ", ch. 6) with a loss modulation, against the mean of the product of two tones"
        ),
        formula="bias = m phi_res cos(theta)/(2 SF) = Re(M conj(P))/(2 SF), P = SF Omega_v "
        "(1 - H(f)): full nonlinear loop with loss modulation m = 1e-2 at 500 Hz, rate tone "
        "0.05 rad/s",
        expected=closed,
        simulated=bias,
        tolerance=m0 + x_res**2 / 6,
        derivation="orders the closed form neglects: m relative (the loop gain modulated by "
        "1 + m changes phi_res) and the sin curvature x_res^2/6",
    )


#: shot-noise check: photocurrent samples and their rate [Hz]
_SHOT_SAMPLES, _SHOT_FS = 2**20, 1e6
#: excess-RIN check: thermal-light samples, spectral width in units of the sample rate, and the
#: fraction of that width whose periodogram bins are averaged
_RIN_SAMPLES, _RIN_WIDTH, _RIN_LOW = 2**20, 0.05, 0.1


def _shot(ob, lam: float, rng: np.random.Generator) -> Check:
    """Schottky's 2 q i against a photocurrent of Poisson photo-electron counts."""
    from scipy import stats

    from gyrobench.base.units import ELEMENTARY_CHARGE

    phi = math.pi / 2
    ib = ob.bias_current(phi)
    counts = rng.poisson(ib / (ELEMENTARY_CHARGE * _SHOT_FS), _SHOT_SAMPLES)
    current = ELEMENTARY_CHARGE * _SHOT_FS * counts  # [A], the mean current over each sample
    measured = 2.0 * float(current.var(ddof=1)) / _SHOT_FS  # one-sided white PSD [A^2/Hz]
    dof = _SHOT_SAMPLES - 1
    lo, hi = stats.chi2.ppf([FALSE_ALARM / 2, 1 - FALSE_ALARM / 2], dof) / dof
    return Check(
        id="fog.optical_budget_shot",
        kind=SECOND_METHOD,
        reference="W. Schottky, Ann. Phys. 362(23) 541 (1918): shot noise 2 q i; q from CODATA 2018",
        formula="shot-noise current PSD at phi_b = pi/2: the budget's 2 q i_b against a "
        "photocurrent of Poisson photo-electron counts at the rate i_b/q (Schottky 1918; "
        "q from CODATA 2018) [A^2/Hz]",
        expected=ob.current_psd(phi, lam)["shot"],
        simulated=measured,
        tolerance=float(max(1 - lo, hi - 1)),
        derivation=f"sample variance of {_SHOT_SAMPLES} independent {1e6 / _SHOT_FS:g}-us "
        f"current samples: chi2({dof})/{dof} band at {FALSE_ALARM:g} two-sided",
    )


def _thermal_light_intensity(rng: np.random.Generator, n: int, width: float) -> np.ndarray:
    """Intensity |E|^2 of polarised thermal light: a circular complex Gaussian field with a
    rectangular spectrum of ``width`` (in units of the sample rate), n samples at rate 1."""
    f = np.fft.fftfreq(n)
    spec = np.where(np.abs(f) < width / 2, rng.standard_normal(n) + 1j * rng.standard_normal(n), 0)
    return np.abs(np.fft.ifft(spec)) ** 2


def _rin(ob, lam: float, rng: np.random.Generator) -> Check:
    """The budget's excess RIN against the measured intensity noise of simulated thermal light.

    Polarised thermal light (Goodman, Statistical Optics, 1985, sec. 9.2-9.3) has intensity
    autocovariance <I>^2 |g(tau)|^2: for a rectangular optical spectrum of width dnu the
    intensity PSD is the spectrum's autoconvolution, a triangle, one-sided
    S_I(f) = 2 <I>^2 (1 - f/dnu)/dnu for f < dnu. The measured RIN x dnu is the mean over
    the periodogram bins below dnu/10 of 2 |X_k|^2 / (n <I>^2) / (1 - f_k/dnu), each bin an
    exponential variable (2 dof); the budget's dimensionless RIN x dnu_eff (rectangular:
    width_factor 1) is then set beside it, in the budget's units through its own dnu_eff.
    """
    from scipy import stats

    if ob.width_factor != 1.0 or not ob.polarized:
        raise ValueError("the RIN check simulates polarised light with a rectangular spectrum")
    phi = math.pi / 2
    n = _RIN_SAMPLES
    i = _thermal_light_intensity(rng, n, _RIN_WIDTH)
    k = np.arange(1, int(n * _RIN_WIDTH * _RIN_LOW) + 1)
    f = k / n
    p = 2.0 * np.abs(np.fft.rfft(i - i.mean())[k]) ** 2 / (n * i.mean() ** 2)
    measured_times_width = float(np.mean(p / (1.0 - f / _RIN_WIDTH))) * _RIN_WIDTH
    dnu = ob.effective_bandwidth(lam)
    ib = ob.bias_current(phi)
    expected = ob.current_psd(phi, lam)["rin"]
    dof = 2 * k.size
    lo, hi = stats.chi2.ppf([FALSE_ALARM / 2, 1 - FALSE_ALARM / 2], dof) / dof
    # <I> estimated from the record itself: relative error ~ sqrt(1/(n width)), squared twice
    mean_err = 2 * _z() / math.sqrt(n * _RIN_WIDTH)
    return Check(
        id="fog.optical_budget_rin",
        kind=SECOND_METHOD,
        reference=(
            "J. W. Goodman, Statistical Optics (Wiley, 1985), sec. 9.2-9.3: intensity fluctuations of "
            "polarized thermal light"
        ),
        formula="excess-RIN current PSD at phi_b = pi/2: the budget's i_b^2 x 2/dnu_eff against "
        "i_b^2 x (measured RIN x dnu of simulated polarised thermal light) / dnu_eff, "
        f"dnu_eff = c dlambda/lambda^2 = {dnu:.4g} Hz (Goodman 1985, sec. 9.2) [A^2/Hz]",
        expected=expected,
        simulated=ib**2 * measured_times_width / dnu,
        tolerance=float(max(1 - lo, hi - 1)) + mean_err,
        derivation=f"mean of {k.size} periodogram bins below dnu/10 (each 2 dof, divided by the "
        f"triangle 1 - f/dnu): chi2({dof})/{dof} band at {FALSE_ALARM:g} two-sided, plus "
        f"2 z/sqrt(n dnu) = {mean_err:.2g} for <I> estimated from the same {n} samples; the "
        "other convention (1/dnu) is 50 % away",
    )


def _johnson(ob) -> Check:
    """The budget's thermal term against a textbook's printed Johnson-noise example."""
    # Horowitz & Hill, The Art of Electronics, 3rd ed. (2015), sec. 8.1.1: "a 10k resistor at
    # room temperature has an rms open-circuit noise voltage of 1.3 uV, measured with a
    # bandwidth of 10 kHz": 4 k T = v^2/(R B) [J]
    v, r, b = 1.3e-6, 1e4, 1e4
    printed = v**2 / (r * b) / ob.feedback_resistance  # 4 k T / R_f [A^2/Hz]
    model = ob.current_psd(math.pi / 2, 1550e-9)["thermal"] - ob.amplifier_current_noise**2
    # the printed 1.3 is rounded (+-0.05: +-7.7 % squared); "room temperature" 290-300 K
    # against the budget's temperature (up to 300/290 - 1 = 3.4 %)
    tol = (1.35 / 1.3) ** 2 - 1 + abs(ob.temperature / 295.0 - 1) + 295.0 / 290.0 - 1
    return Check(
        id="fog.optical_budget_johnson",
        kind=PRINTED,
        reference=(
            "P. Horowitz, W. Hill, The Art of Electronics, 3rd ed. (Cambridge Univ. Press, 2015), sec. "
            "8.1.1: Johnson noise of 10 kOhm"
        ),
        formula="feedback-resistor current noise 4 k_B T/R_f against Horowitz & Hill's printed "
        "1.3 uV rms for 10 kOhm in 10 kHz at room temperature, scaled to R_f "
        f"= {ob.feedback_resistance:g} Ohm [A^2/Hz]",
        expected=printed,
        simulated=model,
        tolerance=tol,
        derivation=f"the printed value's rounding (1.3 +- 0.05, squared: {(1.35 / 1.3) ** 2 - 1:.1%}) "
        f"plus room temperature 290-300 K against the budget's {ob.temperature:g} K",
    )


def _optical_budget(rng: np.random.Generator) -> list[Check]:
    """The budget's three current-noise terms against a simulation or a printed value each."""
    from gyrobench.sim.fog_loop import ClosedLoopFOG

    unit = ClosedLoopFOG(modes=())
    ob, lam = unit.optics, unit.loop.wavelength
    r_shot, r_rin = rng.spawn(2)
    return [_shot(ob, lam, r_shot), _rin(ob, lam, r_rin), _johnson(ob)]


def parts(rng: np.random.Generator) -> list[Part]:
    """The checks in eight independent parts (statistical ones draw from children of ``rng``).

    Parameters
    ----------
    rng : numpy.random.Generator
        The module's stream (the collector's contract; a deterministic module does not draw from it).

    Returns
    -------
    list of Part
        Independent parts, each with its own arguments (children of ``rng`` where it draws).
    """
    r = rng.spawn(6)  # the budget's stream last: the other checks keep their streams
    return [
        Part("optical_budget", _optical_budget, (r[5],)),
        Part("arw_reduced", _arw_reduced, (r[0],)),
        Part("arw_full", _arw_full, (r[1],)),
        Part("loop_response", _loop_response),
        Part("resets", _resets, (r[2],)),
        Part("vibration_chain", _vibration_chain, (r[3],)),
        Part("random_vibration", _random_vibration, (r[4],)),
        Part("rectification", _rectification),
    ]


def checks(rng: np.random.Generator) -> list[Check]:
    """Closed-loop FOG checks (statistical ones draw from children of ``rng``).

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
