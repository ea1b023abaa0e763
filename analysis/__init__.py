"""Methods for any recording, simulated or real: plain arrays and a sample rate in, typed
results out. It never imports :mod:`gyrobench.sim`.

This package exports the names a user reaches for first (loaded on first use); everything else
is public in its module.

Modules
-------
allan
    Allan deviations (overlapping, standard, modified, Hadamard, total) with their bounds, the
    joint Q/N/B/K/R fit with intervals, the slope read-off, fit ranges.
stationarity
    whether a record is stationary, its quiet stretches, the temperature part removed.
wavelet
    wavelet multiscale decomposition and time-frequency maps (PyWavelets).
twin
    the comparison of a real record's Allan deviation with a simulated twin's.
scale_factor, thermal_regression, features, metrics, sweep, regressors, deployment
    scale-factor fits and breakpoint search; two-sensor thermal regression tables; features
    of temperature logs; scores against truth; rate-bin means; float32 deployment checks.
compensation
    the papers' compensation models as scikit-learn estimators.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from gyrobench.base.lazy import attach

#: public name -> the submodule that defines it (imported on first access, so importing
#: this package costs nothing until a name is used)
_LAZY: dict[str, str] = {
    "AllanCurve": "gyrobench.analysis.allan",
    "NoiseFit": "gyrobench.analysis.allan",
    "Coefficient": "gyrobench.analysis.allan",
    "allan_deviation": "gyrobench.analysis.allan",
    "fit_noise": "gyrobench.analysis.allan",
    "floor_bounds": "gyrobench.analysis.allan",
    "pool_curves": "gyrobench.analysis.allan",
    "halves_agreement": "gyrobench.analysis.allan",
    "slope_readoff": "gyrobench.analysis.allan",
    "identify_noise": "gyrobench.analysis.allan",
    "fit_range": "gyrobench.analysis.allan",
    "StationarityReport": "gyrobench.analysis.stationarity",
    "stationarity_check": "gyrobench.analysis.stationarity",
    "quiet_stretches": "gyrobench.analysis.stationarity",
    "remove_temperature": "gyrobench.analysis.stationarity",
    "MultiscaleDecomposition": "gyrobench.analysis.wavelet",
    "decompose": "gyrobench.analysis.wavelet",
    "cwt_map": "gyrobench.analysis.wavelet",
    "TwinComparison": "gyrobench.analysis.twin",
    "compare_twin": "gyrobench.analysis.twin",
    "ScaleFactorFit": "gyrobench.analysis.scale_factor",
    "fit_scale_factor": "gyrobench.analysis.scale_factor",
    "mse": "gyrobench.analysis.metrics",
    "rms": "gyrobench.analysis.metrics",
    "bias_stability": "gyrobench.analysis.metrics",
    "improvement_pct": "gyrobench.analysis.metrics",
}

__all__ = [
    "AllanCurve",
    "NoiseFit",
    "Coefficient",
    "allan_deviation",
    "fit_noise",
    "floor_bounds",
    "pool_curves",
    "halves_agreement",
    "slope_readoff",
    "identify_noise",
    "fit_range",
    "StationarityReport",
    "stationarity_check",
    "quiet_stretches",
    "remove_temperature",
    "MultiscaleDecomposition",
    "decompose",
    "cwt_map",
    "TwinComparison",
    "compare_twin",
    "ScaleFactorFit",
    "fit_scale_factor",
    "mse",
    "rms",
    "bias_stability",
    "improvement_pct",
]

if TYPE_CHECKING:  # pragma: no cover - for type checkers and IDEs only
    from gyrobench.analysis.allan import AllanCurve as AllanCurve
    from gyrobench.analysis.allan import Coefficient as Coefficient
    from gyrobench.analysis.allan import NoiseFit as NoiseFit
    from gyrobench.analysis.allan import allan_deviation as allan_deviation
    from gyrobench.analysis.allan import fit_noise as fit_noise
    from gyrobench.analysis.allan import fit_range as fit_range
    from gyrobench.analysis.allan import floor_bounds as floor_bounds
    from gyrobench.analysis.allan import halves_agreement as halves_agreement
    from gyrobench.analysis.allan import identify_noise as identify_noise
    from gyrobench.analysis.allan import pool_curves as pool_curves
    from gyrobench.analysis.allan import slope_readoff as slope_readoff
    from gyrobench.analysis.metrics import bias_stability as bias_stability
    from gyrobench.analysis.metrics import improvement_pct as improvement_pct
    from gyrobench.analysis.metrics import mse as mse
    from gyrobench.analysis.metrics import rms as rms
    from gyrobench.analysis.scale_factor import ScaleFactorFit as ScaleFactorFit
    from gyrobench.analysis.scale_factor import fit_scale_factor as fit_scale_factor
    from gyrobench.analysis.stationarity import StationarityReport as StationarityReport
    from gyrobench.analysis.stationarity import quiet_stretches as quiet_stretches
    from gyrobench.analysis.stationarity import remove_temperature as remove_temperature
    from gyrobench.analysis.stationarity import stationarity_check as stationarity_check
    from gyrobench.analysis.twin import TwinComparison as TwinComparison
    from gyrobench.analysis.twin import compare_twin as compare_twin
    from gyrobench.analysis.wavelet import MultiscaleDecomposition as MultiscaleDecomposition
    from gyrobench.analysis.wavelet import cwt_map as cwt_map
    from gyrobench.analysis.wavelet import decompose as decompose


__getattr__, __dir__ = attach(__name__, _LAZY)
