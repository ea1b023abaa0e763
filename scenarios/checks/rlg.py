"""Closed-form checks of the ring-laser gyro model (:mod:`gyrobench.sim.rlg`).

- Adler lock-in equation dpsi/dt = 2 pi K (Omega - Omega_L sin psi): above lock-in the
  phase slips at the mean beat frequency f_b = K sqrt(Omega^2 - Omega_L^2) [Hz]
  (Aronowitz, in Laser Applications 1971; docs/physics.md 6.2). The model's RK4
  integration (:func:`gyrobench.sim.rlg.integrate_adler`) over 5 beat periods gives
  the simulated mean beat frequency; near lock-in (Omega = 1.1 Omega_L, the
  frequency is 46 % of the unlocked one) and well above it (2 Omega_L).
- Dither random walk: the angle error left after whole cycles of a randomised
  dither has variance N^2 T with N = Omega_L sqrt((1 + sigma_a^2) / (2 pi K Omega_D))
  [rad/sqrt(s)] (Killpatrick 1967; docs/physics.md 6.3; sigma_a the relative amplitude
  jitter, E[1/a] ~ 1 + sigma_a^2). The sample variance of R = 3000 independent
  realisations (each 3 dither cycles of the Adler equation) is set beside it: the cost is the
  time steps, so 3 x 3000 runs in 60 % of the time of 10 x 1000 with a band half as wide
  (+-0.13 vs +-0.23), which catches a 10 % error in the lock-in rate (21 % in the variance).

Tolerances: the Adler check is numerical (RK4 error per beat cycle
(2 pi K |Omega| dt)^5/120 plus float64 accumulation n_steps eps, times 100); the
dither check is statistical: s^2/sigma^2 ~ chi2(R-1)/(R-1) (the error after 6
crossings is a sum of 6 independent kicks, whose negative excess kurtosis makes the
Gaussian band conservative), two-sided at a false-alarm rate of 1e-6, the wider side.
"""

from __future__ import annotations

import math

import numpy as np

from gyrobench.scenarios.checks.core import CLOSED_FORM, Check, Part, run_parts

__all__ = ["checks", "parts", "FALSE_ALARM"]

FALSE_ALARM = 1e-6
_K = 1e5  # scale factor [counts/rad]
_LOCK_IN_DEG_S = 0.05  # Omega_L [deg/s]
_PERIODS, _STEPS = 5, 4000  # beat periods integrated, RK4 steps per period


def _adler(ratio: float) -> Check:
    from gyrobench.base import units
    from gyrobench.sim import rlg

    wl = units.deg_per_s(_LOCK_IN_DEG_S)
    omega = ratio * wl
    f_b = _K * math.sqrt(omega**2 - wl**2)
    period = 1.0 / f_b
    psi = rlg.integrate_adler(
        lambda t: omega,
        _PERIODS * period,
        scale_factor=_K,
        lock_in_rate=wl,
        dt=period / _STEPS,
        psi0=0.3,
        sample_every=_STEPS,
    )
    simulated = float(psi[-1] - psi[0]) / (2 * math.pi * _PERIODS * period)
    x = 2 * math.pi * _K * abs(omega) * period / _STEPS
    n_steps = _PERIODS * _STEPS
    tol = 100.0 * (x**5 / 120.0 / (2 * math.pi) + n_steps * float(np.finfo(float).eps))
    return Check(
        id=f"rlg.adler_beat_{ratio:g}x_lock_in",
        kind=CLOSED_FORM,
        reference=(
            "R. Adler, 'A study of locking phenomena in oscillators', Proc. IRE 34(6) 351 (1946); F. "
            "Aronowitz, 'The laser gyro', in Laser Applications vol. 1 (Academic Press, 1971)"
        ),
        formula=f"f_b = K sqrt(Omega^2 - Omega_L^2) [Hz]; K = {_K:g} /rad, Omega_L = "
        f"{_LOCK_IN_DEG_S} deg/s, "
        f"Omega = {ratio:g} Omega_L",
        expected=f_b,
        simulated=simulated,
        tolerance=tol,
        derivation=f"RK4, {_STEPS} steps per slip: phase error per cycle (2 pi K Omega dt)^5/120 "
        f"= {x**5 / 120:.2g} rad "
        f"plus float64 accumulation over {n_steps} steps ({n_steps} eps), x 100",
    )


def _dither(rng: np.random.Generator) -> Check:
    from scipy import stats

    from gyrobench.base import units
    from gyrobench.sim import rlg

    r, n_cyc, jitter = 3000, 3, 0.1
    wl = units.deg_per_s(_LOCK_IN_DEG_S)
    dither = rlg.Dither(frequency=400.0, amplitude=20.0 / _K, amplitude_jitter=jitter)
    real = dither.draw(n_cyc, rng=rng, size=r)
    psi0 = rng.uniform(0.0, 2 * math.pi, r)
    duration = n_cyc / dither.frequency
    n = int(math.ceil(duration * 16 * 1.3 * _K * dither.peak_rate))  # >= 16 steps per fastest slip
    psi = rlg.integrate_adler(
        real.rate,
        duration,
        scale_factor=_K,
        lock_in_rate=wl,
        dt=duration / n,
        psi0=psi0,
        sample_every=n,
    )
    err = (psi[-1] - psi[0]) / (2 * math.pi * _K)  # angle error [rad]: the true angle change is 0
    omega_d = 2 * math.pi * dither.frequency * dither.amplitude  # peak dither rate [rad/s]
    n_arw2 = wl**2 * (1 + jitter**2) / (2 * math.pi * _K * omega_d)
    lo, hi = stats.chi2.ppf([FALSE_ALARM / 2, 1 - FALSE_ALARM / 2], r - 1) / (r - 1)
    tol = float(max(1 - lo, hi - 1))
    return Check(
        id="rlg.dither_random_walk",
        kind=CLOSED_FORM,
        reference=(
            "J. E. Killpatrick, 'The laser gyro', IEEE Spectrum 4(10) (1967): random walk of a "
            "randomly dithered ring laser gyro"
        ),
        formula="Var(angle error after T) = N^2 T, N^2 = Omega_L^2 (1 + sigma_a^2) / (2 pi K "
        "Omega_D) [rad^2]; "
        f"400 Hz x 20 counts, sigma_a = {jitter}, T = {duration:g} s",
        expected=n_arw2 * duration,
        simulated=float(err.var(ddof=1)),
        tolerance=tol,
        derivation=f"sample variance of R = {r} realisations: chi2({r - 1})/{r - 1} band at "
        "false-alarm "
        f"{FALSE_ALARM:g} = [{lo:.3f}, {hi:.3f}], wider side",
    )


def parts(rng: np.random.Generator) -> list[Part]:
    """Adler mean beat frequency (two rates) and the dither random walk (``rng``), apart."""
    return [Part("adler_1.1", _adler, (1.1,)), Part("adler_2", _adler, (2.0,)), Part("dither", _dither, (rng,))]


def checks(rng: np.random.Generator) -> list[Check]:
    """Adler mean beat frequency (two rates) and the dither random walk (~3 s)."""
    return run_parts(parts(rng))
