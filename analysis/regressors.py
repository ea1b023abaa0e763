"""Candidate regressors for two-sensor thermal bias models (housing T1, cavity T2).

Eleven candidates, numbered x1..x11 as in stepwise thermal-compensation practice
for ring laser gyros with a housing and a cavity sensor:

====  ==================  ==========================================================
x1    T1                  housing temperature
x2    T2                  cavity temperature
x3    dT1/dt              housing temperature rate
x4    dT2/dt              cavity temperature rate
x5    T1 dT1/dt           housing temperature x its rate
x6    T2 dT2/dt           cavity temperature x its rate
x7    (dT1/dt)^2          square of the housing rate
x8    (dT2/dt)^2          square of the cavity rate
x9    T1 - T2             gradient: housing minus cavity (heat flowing into the block)
x10   d(T1 - T2)/dt       rate of change of the gradient
x11   T1 (T1 - T2)        housing temperature x gradient (temperature-dependent
                          gradient sensitivity, e.g. gas viscosity in the discharge)
====  ==================  ==========================================================

The three gradient terms x9-x11 are this module's definition: the source practice
names "temperature gradient terms" without giving their form. x9 is the
gradient itself, x10 its rate, and x11 lets the gradient's effect scale with the
housing temperature, the same way x5 lets the rate's effect scale.

Units: temperatures in whatever the caller logs (degC is usual; products then
depend on that choice of origin, so state it), rates in that unit per second.
Derivatives are Savitzky-Golay smoothed (:func:`gyrobench.analysis.features.smoothed_derivative`).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.analysis.features import smoothed_derivative

__all__ = ["REGRESSOR_NAMES", "REGRESSOR_LABELS", "two_sensor_regressors"]

#: short names of x1..x11
REGRESSOR_NAMES: tuple[str, ...] = (
    "T1",
    "T2",
    "dT1/dt",
    "dT2/dt",
    "T1*dT1/dt",
    "T2*dT2/dt",
    "(dT1/dt)^2",
    "(dT2/dt)^2",
    "T1-T2",
    "d(T1-T2)/dt",
    "T1*(T1-T2)",
)
#: "x1".."x11"
REGRESSOR_LABELS: tuple[str, ...] = tuple(f"x{i + 1}" for i in range(len(REGRESSOR_NAMES)))


def _series(name: str, x: ArrayLike) -> NDArray[np.float64]:
    a = np.asarray(x, dtype=float)
    if a.ndim != 1:
        raise ValueError(f"{name} must be 1-D; got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(
            f"{name} must be finite; got a NaN or inf at index {int(np.flatnonzero(~np.isfinite(a))[0])}"
        )
    return a


def two_sensor_regressors(
    t1: ArrayLike, t2: ArrayLike, fs: float, *, window_s: float
) -> NDArray[np.float64]:
    """The eleven candidate regressors x1..x11 from housing and cavity temperatures.

    Parameters
    ----------
    t1, t2 : array_like, shape (n,)
        Housing and cavity temperatures, same unit (e.g. degC), sampled at ``fs``.
        Block means (e.g. 100-s) are fine: pass ``fs = 1/block_s``.
    fs : float
        Sample rate [Hz].
    window_s : float
        Smoothing window of the derivatives [s] (at least 5 samples are used).

    Returns
    -------
    ndarray, shape (n, 11)
        Columns in the order of :data:`REGRESSOR_NAMES`.

    Raises
    ------
    ValueError
        If the series differ in length, are not finite, or are shorter than the window.

    Examples
    --------
    >>> t = np.arange(20) * 100.0
    >>> X = two_sensor_regressors(20 + 0.005 * t, 18 + 0.005 * t, 0.01, window_s=500.0)
    >>> X.shape, float(round(X[3, 2], 12)), float(X[3, 8])
    ((20, 11), 0.005, 2.0)
    """
    a1 = _series("t1", t1)
    a2 = _series("t2", t2)
    if a1.shape != a2.shape:
        raise ValueError(f"t1 and t2 must have the same length; got {len(a1)} and {len(a2)}")
    if (
        isinstance(fs, bool)
        or not isinstance(fs, (int, float))
        or not (math.isfinite(fs) and fs > 0)
    ):
        raise ValueError(f"fs must be a finite number > 0 Hz; got {fs!r}")
    d1 = smoothed_derivative(a1, fs, window_s=window_s)
    d2 = smoothed_derivative(a2, fs, window_s=window_s)
    g = a1 - a2
    dg = d1 - d2
    return np.column_stack([a1, a2, d1, d2, a1 * d1, a2 * d2, d1 * d1, d2 * d2, g, dg, a1 * g])
