"""Input checks of the Allan code: one clear line naming the parameter, constraint and value."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray


def _positive_tau(tau: ArrayLike) -> NDArray[np.float64]:
    tau = np.asarray(tau, dtype=float)
    if not np.all(np.isfinite(tau) & (tau > 0)):
        raise ValueError(f"tau must be finite and > 0 s; got {tau!r}")
    return tau



# ---------------------------------------------------------------------------------- input checks
def _check_rate(rate: ArrayLike) -> NDArray[np.float64]:
    y = np.asarray(rate)
    if y.ndim != 1:
        raise ValueError(f"rate must be a 1-D array of samples; got shape {y.shape}")
    if not (np.issubdtype(y.dtype, np.floating) or np.issubdtype(y.dtype, np.integer)):
        raise TypeError(f"rate must hold real numbers; got dtype {y.dtype}")
    y = np.asarray(y, dtype=np.float64)
    if math.isfinite(float(np.sum(y))):  # a nan or inf anywhere makes the sum non-finite
        return y
    step = 1 << 20  # blockwise: no N-sized boolean temporaries (and exact where a finite sum overflowed)
    for a in range(0, y.size, step):
        finite = np.isfinite(y[a : a + step])
        if not finite.all():
            bad = a + int(np.flatnonzero(~finite)[0])
            total = int(np.count_nonzero(~np.isfinite(y)))
            raise ValueError(
                f"rate must be finite everywhere; got {float(y[bad])!r} at index {bad} "
                f"({total} non-finite sample(s) in total)"
            )
    return y


def _check_fs(fs: Any) -> float:
    if isinstance(fs, bool) or not isinstance(fs, (int, float, np.integer, np.floating)):
        raise TypeError(f"fs must be a real number [Hz]; got {fs!r}")
    fs = float(fs)
    if not (math.isfinite(fs) and fs > 0.0):
        raise ValueError(f"fs must be finite and > 0 Hz; got {fs!r}")
    return fs



def _check_bandwidth(bandwidth: Any, fs: float | None, name: str = "bandwidth") -> float:
    if isinstance(bandwidth, bool) or not isinstance(bandwidth, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a real number [Hz]; got {bandwidth!r}")
    bw = float(bandwidth)
    if not (math.isfinite(bw) and bw > 0.0):
        raise ValueError(f"{name} must be finite and > 0 Hz; got {bandwidth!r}")
    if fs is not None and not bw < fs / 2.0:
        raise ValueError(
            f"{name} must be < the Nyquist frequency fs/2 = {fs / 2.0:g} Hz (a wider filter cannot shape a record "
            f"sampled at {fs:g} Hz); got {bw:g} Hz"
        )
    return bw




def _check_tau_limit(name: str, value: Any) -> float | None:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a number [s] or None; got {value!r}")
    if not (math.isfinite(float(value)) and float(value) > 0):
        raise ValueError(f"{name} must be finite and > 0 s; got {value!r}")
    return float(value)
