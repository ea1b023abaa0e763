"""A fitted noise model as a navigation filter's process noise, optionally overbounding the data.

:func:`filter_model` turns an IEEE 952 fit (rate in rad/s or m/s^2) into the continuous-time
densities a Kalman filter takes, and states every conversion:

* white noise density sigma_w = N [u/sqrt(Hz)] (angle or velocity random walk), and its
  discrete per-sample variance at the sample rate, sigma_d^2 = N^2 fs [u^2] (the ROS
  ``sensor_msgs/Imu`` covariance diagonal);
* random-walk density sigma_rw = K [u/s/sqrt(Hz)] (rate or acceleration random walk);
* bias instability B, which no finite-state filter models exactly, as either
  - a first-order Gauss-Markov state whose Allan deviation peaks at the B plateau: the
    Gauss-Markov ADEV has its maximum 0.6174 sigma at tau = 1.8926 Tc (IEEE Std 952-1997
    Annex C, exponentially correlated noise), so sigma_GM = 0.664 B / 0.6174 and
    Tc = tau_B / 1.8926, tau_B the tau of the fitted ADEV minimum, or
  - a random walk whose ADEV reaches the plateau 0.664 B at tau_B:
    K_eq = 0.664 B sqrt(3 / tau_B) [u/s/sqrt(Hz)] (conservative beyond tau_B, none below).

Overbounding (the peers' folk advice is to inflate the Allan values 10-20x): with
``overbound=True`` the model's AVAR is scaled by the smallest factor k^2 that puts its ADEV at
or above the data's upper 95 % bound at every tau of the curve (k^2 = max_i high95_i^2 /
A_model(tau_i)); all densities scale by k. This is the smallest overbound within the fitted
model's shape (not over all models).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from gyrobench.analysis.allan import NoiseFit, deviation_bounds

__all__ = ["FilterModel", "filter_model", "GM_PEAK_TAU", "GM_PEAK_ADEV"]

#: tau / Tc at the peak of a first-order Gauss-Markov Allan deviation, and the peak ADEV / sigma
#: (maximum of sqrt(g(r)) / r, g(r) = 2 r - 3 + 4 e^-r - e^-2r; IEEE Std 952-1997 Annex C)
GM_PEAK_TAU = 1.8926
GM_PEAK_ADEV = 0.6174
#: ADEV plateau of bias instability over B: sqrt(2 ln 2 / pi)
B_PLATEAU = math.sqrt(2.0 * math.log(2.0) / math.pi)


@dataclass(frozen=True, slots=True, kw_only=True)
class FilterModel:
    """Process-noise parameters of one axis, SI (u the rate unit: rad/s or m/s^2).

    Attributes
    ----------
    white_density : float
        N [u/sqrt(Hz)].
    white_variance_per_sample : float
        N^2 fs [u^2], the discrete white-noise variance at the sample rate.
    random_walk_density : float
        K [u/s/sqrt(Hz)] (its 95 % upper bound when not identifiable).
    gm_sigma, gm_tc : float
        Gauss-Markov equivalent of B: stationary sigma [u] and correlation time [s] (0 without B).
    rw_equivalent_density : float
        Random-walk equivalent of B [u/s/sqrt(Hz)] (0 without B).
    tau_b : float
        The tau of the fitted ADEV minimum used by the B conversions [s].
    inflation : float
        k, the factor all densities carry (1 without overbounding).
    fs : float
        Sample rate [Hz].
    bounds : tuple of str
        Terms given at their 95 % upper bound (not identifiable).
    """

    white_density: float
    white_variance_per_sample: float
    random_walk_density: float
    gm_sigma: float
    gm_tc: float
    rw_equivalent_density: float
    tau_b: float
    inflation: float
    fs: float
    bounds: tuple[str, ...]


def _value(fit: NoiseFit, name: str) -> tuple[float, bool]:
    c = fit.coefficients.get(name)
    if c is None:
        return 0.0, False
    if c.identifiable and c.value is not None:
        return float(c.value), False
    return float(c.upper_bound), True


def overbound_factor(fit: NoiseFit, confidence: float = 0.95) -> float:
    """k >= 1 so that k^2 times the model AVAR lies on or above the data's upper ``confidence`` bound at every tau."""
    curve = fit.curve
    tau = np.asarray(curve.tau, dtype=float)
    _, hi = deviation_bounds(np.asarray(curve.deviation, dtype=float), np.asarray(curve.edf, dtype=float), confidence)
    model = fit.avar(tau)
    ok = model > 0
    if not ok.any():
        return 1.0
    return max(1.0, float(np.sqrt(np.max(hi[ok] ** 2 / model[ok]))))


def filter_model(fit: NoiseFit, *, overbound: bool = False) -> FilterModel:
    """The fit as process noise (module docstring); ``overbound`` scales it to overbound the data's 95 % bound.

    Parameters
    ----------
    fit : NoiseFit
        An Allan-variance noise fit (:func:`gyrobench.analysis.allan.fit_noise`).
    overbound : bool
        Scale every density by :func:`overbound_factor` so the model's Allan deviation
        overbounds the data's 95 % bound at every tau.

    Returns
    -------
    FilterModel
        White-noise density and per-sample variance, random-walk density, the Gauss-Markov
        equivalent of the bias instability and its random-walk bound, in the fit's rate unit.
    """
    fs = float(fit.curve.fs)
    n, n_b = _value(fit, "N")
    k, k_b = _value(fit, "K")
    b, b_b = _value(fit, "B")
    tau = np.asarray(fit.curve.tau, dtype=float)
    adev = np.sqrt(np.maximum(fit.avar(tau), 0.0))
    tau_b = float(tau[int(np.argmin(adev))]) if adev.size else 1.0
    scale = overbound_factor(fit) if overbound else 1.0
    plateau = B_PLATEAU * b
    return FilterModel(
        white_density=scale * n,
        white_variance_per_sample=(scale * n) ** 2 * fs,
        random_walk_density=scale * k,
        gm_sigma=scale * plateau / GM_PEAK_ADEV,
        gm_tc=tau_b / GM_PEAK_TAU if b > 0 else 0.0,
        rw_equivalent_density=scale * plateau * math.sqrt(3.0 / tau_b) if b > 0 else 0.0,
        tau_b=tau_b,
        inflation=scale,
        fs=fs,
        bounds=tuple(name for name, bound in (("N", n_b), ("K", k_b), ("B", b_b)) if bound),
    )
