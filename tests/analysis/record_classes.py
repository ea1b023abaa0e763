"""Synthetic analogues, with known truth, of the real-record classes the analysis must handle.

Each generator returns (rate [rad/s], fs [Hz], truth) with the truth in SI. They stand for
records that peers analyse and that a naive IEEE 952 fit gets wrong:

* :func:`phone_record`: a phone IMU left on a desk, 100 Hz white + flicker noise, low-passed
  forward and backward (zero phase, ``scipy.signal.filtfilt``) and decimated to 10 Hz, with a
  constant bias and sparse desk bumps (a small share of 0.8 s windows disturbed);
* :func:`hvac_record`: 1 h at 100 Hz of N, B, K noise plus a sinusoid of period 1200 s (an air
  conditioning cycle);
* :func:`motion_record`: a 1 Hz record with handling motion over a tenth of its length.

The noise terms are generated with :class:`gyrobench.sim.noise.NoiseModel` (its generators are
checked against their closed-form Allan variances in tests/sim).
"""

from __future__ import annotations

import math

import numpy as np

from gyrobench.base import units
from gyrobench.sim.noise import NoiseModel

DEG_H = units.deg_per_h(1.0)  # rad/s per deg/h
DEG_SQRT_H = math.radians(1.0) / 60.0  # rad/sqrt(s) per deg/sqrt(h)


def phone_record(
    rng: np.random.Generator,
    *,
    hours: float = 6.0,
    n_dsh: float = 3.0,
    b_dph: float = 25.0,
    bias_dph: float = -2752.0,
    corner_hz: float = 2.0,
    order: int = 4,
    bump_share: float = 0.005,
    bump_dps: float = 3.0,
    filtered: bool = True,
) -> tuple[np.ndarray, float, dict[str, float]]:
    """6 h static at 10 Hz, decimated from 100 Hz through a zero-phase Butterworth, with desk bumps.

    The 100 Hz white rate noise (N) is low-passed by ``scipy.signal.filtfilt`` with a Butterworth
    of ``order`` at ``corner_hz`` (forward and backward: |H|^2 applied twice, zero phase) and kept
    every 10th sample; the flicker (B) is generated at 10 Hz (it lives far below the corner).
    ``bump_share`` of the 0.8 s windows get a damped 8 Hz-ish oscillation of ``bump_dps`` deg/s
    peak (a desk knock). Truth: N [rad/sqrt(s)], B [rad/s], bias [rad/s], the filter's corner
    [Hz] and order, and the number of bumped windows.
    """
    from scipy.signal import butter, filtfilt

    fs_hi, dec = 100.0, 10
    fs = fs_hi / dec
    n = int(round(hours * 3600.0 * fs))
    white = rng.standard_normal(n * dec) * (n_dsh * DEG_SQRT_H) * math.sqrt(fs_hi)
    if filtered:
        b, a = butter(order, corner_hz / (fs_hi / 2.0))
        white = filtfilt(b, a, white)
    y = white[::dec].copy()
    y += NoiseModel(bias_instability=b_dph * DEG_H).generate(n, fs=fs, rng=rng)
    y += bias_dph * DEG_H
    w = 8  # 0.8 s windows
    k = n // w
    n_bumps = int(round(bump_share * k))
    hit = rng.choice(k, size=n_bumps, replace=False)
    t = np.arange(w) / fs
    for i in hit:
        phase = rng.uniform(0, 2 * math.pi)
        y[i * w : (i + 1) * w] += math.radians(bump_dps) * np.exp(-t / 0.3) * np.cos(2 * math.pi * 3.7 * t + phase)
    truth = {"N": n_dsh * DEG_SQRT_H, "B": b_dph * DEG_H, "bias": bias_dph * DEG_H, "corner_hz": corner_hz,
             "order": float(order), "bumps": float(n_bumps)}
    return y, fs, truth


def hvac_record(
    rng: np.random.Generator,
    *,
    hours: float = 1.0,
    fs: float = 100.0,
    n_dsh: float = 0.3,
    b_dph: float = 3.0,
    k_dph_sqrt_h: float = 3.0,
    sine_dph: float = 20.0,
    period_s: float = 1200.0,
) -> tuple[np.ndarray, float, dict[str, float]]:
    """1 h at 100 Hz: N 0.3 deg/sqrt(h), B 3 deg/h, K 3 deg/h/sqrt(h) plus a 20 deg/h sine of period 1200 s."""
    n = int(round(hours * 3600.0 * fs))
    model = NoiseModel(angle_random_walk=n_dsh * DEG_SQRT_H, bias_instability=b_dph * DEG_H,
                       rate_random_walk=k_dph_sqrt_h * DEG_H / 60.0)
    y = model.generate(n, fs=fs, rng=rng)
    t = np.arange(n) / fs
    y += sine_dph * DEG_H * np.sin(2 * math.pi * t / period_s + rng.uniform(0, 2 * math.pi))
    truth = {"N": model.angle_random_walk, "B": model.bias_instability, "K": model.rate_random_walk,
             "sine_amplitude": sine_dph * DEG_H, "sine_period": period_s}
    return y, fs, truth


def motion_record(rng: np.random.Generator, *, hours: float = 2.0) -> tuple[np.ndarray, float, dict[str, float]]:
    """1 Hz, N 0.5 deg/sqrt(h) and B 5 deg/h, with handling motion (a 0.2 deg/s random swing) over a tenth."""
    fs = 1.0
    n = int(round(hours * 3600.0 * fs))
    model = NoiseModel(angle_random_walk=0.5 * DEG_SQRT_H, bias_instability=5.0 * DEG_H)
    y = model.generate(n, fs=fs, rng=rng)
    a = n // 3
    span = n // 10
    y[a : a + span] += math.radians(0.2) * np.cumsum(rng.standard_normal(span)) / math.sqrt(span) * 5
    return y, fs, {"N": model.angle_random_walk, "B": model.bias_instability, "motion": (a / fs, (a + span) / fs)}
