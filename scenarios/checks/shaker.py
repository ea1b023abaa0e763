"""Closed-form check of the shaker input a sensor sees (:func:`gyrobench.sim.shaker.interval_mean_acceleration`).

- **Interval-mean gain of a tone above the output rate.** The model samples the profile at m fs
  (m = ceil(4 f_max / fs)) and averages each output interval. For a tone A sin(2 pi f t + p)
  that mean is A |H(f)| sin(2 pi f k/fs + p + arg H(f)) with the moving-average response

      H(f) = (1/m) sum_j exp(i 2 pi f j/(m fs)) = exp(i pi f (m - 1)/(m fs)) sin(pi f/fs) / (m sin(pi f/(m fs)))

  (a geometric series; Oppenheim & Schafer, Discrete-Time Signal Processing, 3rd ed. (2010),
  sec. 2.6, the moving-average system). The check fits the output's amplitude at f (least
  squares on sin and cos of 2 pi f k/fs over the whole dwell, no formula of the model retyped)
  and compares it with A |H(f)| for a 137 Hz tone at a 50 Hz output (m = 11), where the output
  folds the tone to 13 Hz at |H| = 0.0940 of its level: a point sampler would keep it at 1, a
  true integrate-and-dump output (m -> inf) at |sinc(f/fs)| = 0.0847.

Deterministic: the tolerance is the rounding of phases up to 2 pi f T.
"""

from __future__ import annotations

import math

import numpy as np

from gyrobench.scenarios.checks.core import CLOSED_FORM, Check

__all__ = ["checks"]

#: output rate [Hz], tone [Hz] and its level [m/s^2], the dwell [s] inside a record [s]
_FS, _F, _A = 50.0, 137.0, 2.0 * 9.80665
_DWELL, _RECORD = 40.0, 44.0


def _interval_gain(rng: np.random.Generator) -> Check:
    from gyrobench.sim.shaker import OVERSAMPLING, FixedSine, interval_mean_acceleration

    m = math.ceil(OVERSAMPLING * _F / _FS)
    a = interval_mean_acceleration(FixedSine(frequency=_F, duration=_DWELL, acceleration=_A, phase=0.3),
                                   duration=_RECORD, fs=_FS, start=2.0, rng=rng)
    k0, n = int(round(2.0 * _FS)), int(round(_DWELL * _FS))
    k = np.arange(n)
    basis = np.column_stack([np.sin(2 * np.pi * _F * k / _FS), np.cos(2 * np.pi * _F * k / _FS)])
    coef, *_ = np.linalg.lstsq(basis, a[k0:k0 + n], rcond=None)
    gain = abs(math.sin(math.pi * _F / _FS) / (m * math.sin(math.pi * _F / (m * _FS))))
    phase_span = 2 * np.pi * _F * _DWELL
    return Check(
        id="shaker.interval_mean_gain",
        kind=CLOSED_FORM,
        reference="A. V. Oppenheim, R. W. Schafer, Discrete-Time Signal Processing, 3rd ed. (2010), sec. 2.6 "
        "(the moving-average system's frequency response, a geometric series)",
        formula=f"fitted output amplitude of a {_F:g} Hz tone at a {_FS:g} Hz output = A |H(f)|, "
        f"|H| = |sin(pi f/fs) / (m sin(pi f/(m fs)))| = {gain:.4f}, m = {m} (|sinc(f/fs)| = "
        f"{abs(np.sinc(_F / _FS)):.4f} for m -> inf) [m/s^2]",
        expected=_A * gain,
        simulated=float(math.hypot(*coef)),
        tolerance=1e-9,
        derivation=f"deterministic: both sides evaluate phases up to 2 pi f T = {phase_span:.2g} rad to ~eps "
        "relative each (~1e-12 of the amplitude), and the least-squares fit of a pure tone over "
        f"{n} samples adds rounding only; 1e-9 covers both",
    )


def checks(rng: np.random.Generator) -> list[Check]:
    """The interval-mean gain of a tone above the output rate (``rng``: the shaker's stream)."""
    return [_interval_gain(rng)]
