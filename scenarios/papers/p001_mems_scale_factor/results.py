"""The typed result of one paper-001 unit: :class:`UnitResult` and its parts (frozen dataclasses).

What :func:`~.experiment.experiment` returns and :func:`~.report.report` reads; NumPy arrays
are fields, numbers are Python floats. Rates and outputs in [deg/s], K_n in [%] unless the
field says otherwise. Nothing here imports :mod:`gyrobench.sim`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from gyrobench.analysis.scale_factor import SearchStep

__all__ = ["DeviceSummary", "Join", "MethodScore", "MlpFit", "RawAnalysis", "Trace", "UnitResult"]


@dataclass(frozen=True, slots=True, kw_only=True)
class RawAnalysis:
    """The uncompensated table of the fitting runs: the paper's Table 1, K_n and Table 2.

    Attributes
    ----------
    table1_dps : ndarray, shape (m,)
        Per-rate mean over the fitting runs of the dwell means [deg/s] (the paper's Table 1).
    run_std_dps : ndarray, shape (m,)
        Per-rate standard deviation over the fitting runs (ddof 1; zeros for one run) [deg/s].
    pointwise_pct : ndarray, shape (m,)
        Pointwise nonlinearity a_j of Table 1 [%].
    scale_factor, bias_dps : float
        LS scale factor [-] and bias [deg/s] of Table 1.
    raw_kn_pct_per_run : tuple of float
        K_n of each fitting run [%].
    raw_kn_pct : float
        Their mean [%] (the paper's 15.71 %).
    raw_kn_pct_heldout : float
        Mean K_n of the held-out runs [%].
    low_rate_kn : float
        K_n between the breakpoints found [-] (NaN without both, or with fewer than 3 rates).
    low_rate_kn_paper : float
        K_n on the paper's low-rate segment, |rate| <= 1800 deg/s (between the paper's
        breakpoints) [-]: a property of the device, whatever our heuristic finds (NaN with
        fewer than 3 rates there).
    breakpoints_dps : tuple of float
        The breakpoints the heuristic search found, ascending [deg/s].
    search_trace : tuple of SearchStep
        The search's trace (the paper's Table 2).
    """

    table1_dps: NDArray[np.float64]
    run_std_dps: NDArray[np.float64]
    pointwise_pct: NDArray[np.float64]
    scale_factor: float
    bias_dps: float
    raw_kn_pct_per_run: tuple[float, ...]
    raw_kn_pct: float
    raw_kn_pct_heldout: float
    low_rate_kn: float
    low_rate_kn_paper: float
    breakpoints_dps: tuple[float, ...]
    search_trace: tuple[SearchStep, ...]

    def trace_array(self) -> NDArray[np.float64]:
        """The trace as an (n, 7) float array: side, end rate, points, K_n, |dK_n|, dd, counter."""
        rows = [
            (s.side, s.end_rate, s.n_points, s.nonlinearity, s.abs_diff, s.diff2, s.counter)
            for s in self.search_trace
        ]
        return np.array(rows, dtype=float).reshape(-1, 7)


@dataclass(frozen=True, slots=True, kw_only=True)
class MethodScore:
    """One compensator scored on one unit (all NaN when it could not be fitted).

    Attributes
    ----------
    kn_fit_pct : float
        Mean K_n of the compensated fitting runs (in-sample, the paper's scoring) [%].
    kn_heldout_pct : float
        Mean K_n of the compensated held-out runs at the table rates [%].
    rms_heldout_pct : float
        Mean RMS of the held-out pointwise nonlinearity a_j [%].
    kn_dense_pct : float
        Mean K_n of the compensated dense noise-free sweeps of the held-out power-ons [%].
    compensated_heldout_dps : ndarray, shape (m,)
        Held-out run 0 compensated [deg/s].
    pointwise_heldout_pct : ndarray, shape (m,)
        Its pointwise nonlinearity a_j [%].
    dense_error_dps : ndarray, shape (n_dense,)
        Compensated minus true rate on held-out power-on 0's dense sweep [deg/s].
    """

    kn_fit_pct: float
    kn_heldout_pct: float
    rms_heldout_pct: float
    kn_dense_pct: float
    compensated_heldout_dps: NDArray[np.float64]
    pointwise_heldout_pct: NDArray[np.float64]
    dense_error_dps: NDArray[np.float64]


@dataclass(frozen=True, slots=True, kw_only=True)
class Join:
    """The piecewise fit around one breakpoint, with and without its Hermite join (paper Fig. 4).

    ``x`` is the gyro output [deg/s]; ``left``, ``right`` and ``joined`` the compensated rate of
    the two segments alone and of the joined model [deg/s]; ``data_x``, ``data_y`` the fitting
    points within 4 half-joins of the breakpoint (output, rate) [deg/s].

    Attributes
    ----------
    breakpoint : float
        The breakpoint, in gyro output [deg/s].
    rate_dps : float
        The table rate there [deg/s].
    half_join : float
        Half-width of the join [deg/s of output].
    x : ndarray
        Gyro outputs [deg/s].
    left, right, joined : ndarray
        The compensated rate of each segment alone and of the joined model [deg/s].
    data_x, data_y : ndarray
        The fitting points within 4 half-joins (output, rate) [deg/s].
    """

    breakpoint: float
    rate_dps: float
    half_join: float
    x: NDArray[np.float64]
    left: NDArray[np.float64]
    right: NDArray[np.float64]
    joined: NDArray[np.float64]
    data_x: NDArray[np.float64]
    data_y: NDArray[np.float64]


@dataclass(frozen=True, slots=True, kw_only=True)
class MlpFit:
    """The Bayes-regularized network's effective number of parameters and epochs run.

    Attributes
    ----------
    gamma : float
        Effective number of parameters.
    epochs_run : int
        Training epochs run.
    """

    gamma: float
    epochs_run: int


@dataclass(frozen=True, slots=True, kw_only=True)
class Trace:
    """A 1 Hz trace of fitting run 0, dwells in table order (paper Fig. 2): time [s], rates [deg/s].

    Attributes
    ----------
    time_s : ndarray
        Time [s].
    table_dps : ndarray
        Table rate [deg/s].
    output_dps : ndarray
        Gyro output [deg/s].
    """

    time_s: NDArray[np.float64]
    table_dps: NDArray[np.float64]
    output_dps: NDArray[np.float64]


@dataclass(frozen=True, slots=True, kw_only=True)
class DeviceSummary:
    """What the report says of the device: v_max [V], turn-on SF repeatability [ppm], knee [deg/s].

    Attributes
    ----------
    dac_full_scale_v : float
        v_max [V].
    scale_factor_repeatability_ppm : float
        Turn-on scale-factor repeatability [ppm].
    rate_authority_dps : float
        The knee [deg/s].
    """

    dac_full_scale_v: float
    scale_factor_repeatability_ppm: float
    rate_authority_dps: float


@dataclass(frozen=True, slots=True, kw_only=True)
class UnitResult:
    """One unit through the whole pipeline (satisfies ``papers.contract.UnitResult``).

    Deterministic in (config, seed) except ``timing_ms`` and ``fit_time_ms`` (wall times).

    Attributes
    ----------
    seed : int
        The unit.
    variant : str
        ``Config.variant``.
    quantities : mapping of str to float or None
        One number per claim quantity (see ``claims.CLAIMS``); rankings as 1.0 / 0.0, None
        where the unit cannot test the claim.
    rates_dps : ndarray, shape (m,)
        Table rates [deg/s].
    fit_means_dps, held_means_dps : ndarray, shape (n_runs, m)
        Dwell means of the fitting and held-out runs [deg/s].
    raw : RawAnalysis
        The uncompensated table.
    raw_kn_dense_pct : float
        Mean K_n of the held-out power-ons' dense noise-free sweeps, uncompensated [%].
    dense_rates_dps : ndarray
        Rates of the dense sweep [deg/s].
    methods : mapping of str to MethodScore
        Per method key (``config.METHOD_LABELS``).
    floor_pct, floor_fit_pct : float
        Repeatability floor: mean K_n of the held-out (fitting) runs compensated by
        interpolation through the fit-run means [%] (NaN on a saturated plateau).
    device : DeviceSummary
        The unit's device numbers the report quotes.
    piecewise_orders : tuple of int
        Orders of the fitted piecewise segments (empty when it could not be fitted).
    continuity : tuple of Join
        One per breakpoint of the piecewise fit.
    mlp : MlpFit or None
        None when the network could not be fitted.
    fit_errors : mapping of str to str
        Method key -> the ValueError that refused its fit.
    trace : Trace
        1 Hz trace of fitting run 0.
    timing_ms, fit_time_ms : mapping of str to float
        Median evaluation time on the 21-point table and fit time per method [ms].
    """

    seed: int
    variant: str
    quantities: Mapping[str, float | None]
    rates_dps: NDArray[np.float64]
    fit_means_dps: NDArray[np.float64]
    held_means_dps: NDArray[np.float64]
    raw: RawAnalysis
    raw_kn_dense_pct: float
    dense_rates_dps: NDArray[np.float64]
    methods: Mapping[str, MethodScore]
    floor_pct: float
    floor_fit_pct: float
    device: DeviceSummary
    piecewise_orders: tuple[int, ...]
    continuity: tuple[Join, ...]
    mlp: MlpFit | None
    fit_errors: Mapping[str, str]
    trace: Trace
    timing_ms: Mapping[str, float]
    fit_time_ms: Mapping[str, float]

    @property
    def rate_authority_dps(self) -> float:
        """The unit's rate authority (knee) [deg/s]."""
        return self.device.rate_authority_dps
