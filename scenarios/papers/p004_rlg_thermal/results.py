"""The typed result of one unit (one gyro) of paper 004: :class:`UnitResult` and its parts.

Everything the claims, the tables and the figures read is here, so the report never
re-runs a simulation. Field units are in the names (deg/h, degC, K, ppm/K, h) and,
for the traces, in the comments; the traces are 100-s block means (``Config.block_s``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from gyrobench.analysis.thermal_regression import StepwiseTable

__all__ = ["Stability", "HopEffect", "GyroDraw", "FitTraces", "HeldoutTraces", "UnitResult"]


@dataclass(frozen=True, slots=True, kw_only=True)
class Stability:
    """Bias stability [deg/h] (1 sigma of the block means, n - 1) before and after compensation.

    ``heldout_floor_deg_h``: the held-out output minus the true thermal bias, what a perfect
    thermal model would leave (dither random walk, count quantization, flicker).

    Attributes
    ----------
    fit_before_deg_h, fit_after_deg_h : float
        The fitting run's bias stability before and after [deg/h].
    heldout_before_deg_h, heldout_after_deg_h : float
        The held-out run's [deg/h].
    heldout_floor_deg_h : float
        What a perfect thermal model would leave [deg/h].
    """

    fit_before_deg_h: float
    fit_after_deg_h: float
    heldout_before_deg_h: float
    heldout_after_deg_h: float
    heldout_floor_deg_h: float

    @property
    def heldout_ratio(self) -> float:
        """Held-out before / after [x]."""
        return self.heldout_before_deg_h / self.heldout_after_deg_h

    @property
    def fit_ratio(self) -> float:
        """Fitting-run (in-sample) before / after [x]."""
        return self.fit_before_deg_h / self.fit_after_deg_h

    @property
    def floor_ratio(self) -> float:
        """Held-out before / what a perfect thermal model would leave [x]."""
        return self.heldout_before_deg_h / self.heldout_floor_deg_h


@dataclass(frozen=True, slots=True, kw_only=True)
class HopEffect:
    """PLC mode hops of the unit's runs and its results without them (same draws, unlimited travel).

    ``adj_r2_cost`` = (1 - adj. R^2 with hops) / (1 - adj. R^2 without), None when the
    fitting run does not hop; ``ratio_cost`` = held-out before/after without hops over with
    hops (> 1: the hops cost improvement), None when neither run hops.

    Attributes
    ----------
    fit_hops, heldout_hops : int
        Mode hops of each run.
    fit_up_degc, fit_down_degc : tuple of float
        Block temperature at the fitting run's heating and cooling hops [degC].
    heldout_up_degc, heldout_down_degc : tuple of float
        The held-out run's [degC].
    adj_r2_nohop : float
        Adjusted R^2 without hops.
    heldout_ratio_nohop : float
        Held-out before/after ratio without hops.
    selected_nohop : tuple of str
        The regressors selected without hops.
    adj_r2_cost : float or None
        (1 - adj. R^2 with hops) / (1 - adj. R^2 without).
    ratio_cost : float or None
        Held-out ratio without hops over with.
    """

    fit_hops: int
    heldout_hops: int
    fit_up_degc: tuple[float, ...]  # block temperature at heating hops [degC]
    fit_down_degc: tuple[float, ...]  # ... at cooling hops
    heldout_up_degc: tuple[float, ...]
    heldout_down_degc: tuple[float, ...]
    adj_r2_nohop: float
    heldout_ratio_nohop: float
    selected_nohop: tuple[str, ...]
    adj_r2_cost: float | None
    ratio_cost: float | None


@dataclass(frozen=True, slots=True, kw_only=True)
class GyroDraw:
    """What the unit drew from the population, and its fitting run's lock-in and thermal bias.

    Attributes
    ----------
    cte_ppm_per_k : float
        The block's expansion [ppm/K].
    hop_spacing_k : float
        Temperature between mode hops [K].
    hysteresis_k : float
        Up/down hop hysteresis [K].
    lock_in_min_deg_s, lock_in_max_deg_s : float
        The fitting run's lock-in range [deg/s].
    thermal_bias_std_deg_h : float
        Std of the 100-s means of the true thermal bias [deg/h].
    """

    cte_ppm_per_k: float
    hop_spacing_k: float
    hysteresis_k: float
    lock_in_min_deg_s: float
    lock_in_max_deg_s: float
    thermal_bias_std_deg_h: float  # std of the 100-s means of the true thermal bias


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class FitTraces:
    """The fitting run's block means the figures draw.

    Attributes
    ----------
    t_h : ndarray
        Block centres [h].
    output : ndarray
        Output [deg/h].
    t1, t2 : ndarray
        Logged housing and cavity temperatures [degC].
    chamber : ndarray
        Chamber [degC].
    mode : ndarray
        PLC mode index at each block's end.
    dt1, dt2 : ndarray
        x3 = dT1/dt and x4 = dT2/dt [degC/s].
    gradient : ndarray
        x9 = T1 - T2 [degC].
    """

    t_h: NDArray[np.float64]  # block centre [h]
    output: NDArray[np.float64]  # output [deg/h]
    t1: NDArray[np.float64]  # logged housing temperature [degC]
    t2: NDArray[np.float64]  # logged cavity temperature [degC]
    chamber: NDArray[np.float64]  # chamber [degC]
    mode: NDArray[np.float64]  # PLC mode index at the end of each block
    dt1: NDArray[np.float64]  # x3 = dT1/dt [degC/s]
    dt2: NDArray[np.float64]  # x4 = dT2/dt [degC/s]
    gradient: NDArray[np.float64]  # x9 = T1 - T2 [degC]


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class HeldoutTraces:
    """The held-out run's block means: regressors, output, truth and the compensated output.

    Attributes
    ----------
    t_h : ndarray
        Block centres [h].
    X : ndarray
        Regressors x1..x11.
    output : ndarray
        Output [deg/h].
    truth : ndarray
        True rate [deg/h].
    compensated : ndarray
        Compensated output [deg/h].
    """

    t_h: NDArray[np.float64]  # block centre [h]
    X: NDArray[np.float64]  # (n, 11) regressors x1..x11 [degC, degC/s]
    output: NDArray[np.float64]  # [deg/h]
    truth: NDArray[np.float64]  # true rate [deg/h]
    compensated: NDArray[np.float64]  # output - the unit's model [deg/h]


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class UnitResult:
    """One unit's result (:class:`gyrobench.scenarios.papers.contract.UnitResult`).

    Attributes
    ----------
    seed : int
        The unit.
    quantities : dict
        One number per claim quantity (booleans as 1.0 / 0.0; None where untestable).
    model : StepwiseTable
        The stepwise model fitted on the first run (deg/h per unit of each term).
    stability : Stability
    hops : HopEffect
    gyro : GyroDraw
    fit : FitTraces
    heldout : HeldoutTraces
    """

    seed: int
    quantities: dict[str, float | None]
    model: StepwiseTable
    stability: Stability
    hops: HopEffect
    gyro: GyroDraw
    fit: FitTraces
    heldout: HeldoutTraces
