"""Paper 003's typed results: what one unit's ``experiment`` returns, nested frozen dataclasses.

Everything the claims and the report read is here, so the report needs no simulator.
Numbers are Python floats (field units in the names: deg/h, degC, (deg/h)^2 for an ERR);
traces are float32 arrays of 100-s block means (the report's figures).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gyrobench.analysis.compensation.rbf_selection import RBFSelection

__all__ = [
    "Float32Check",
    "IdentTrace",
    "PointHeating",
    "ProtocolResult",
    "RunErr",
    "Scores",
    "Traces",
    "UnitResult",
    "Val1Trace",
    "Val2Trace",
    "ValidationQuantities",
    "WindingPeak",
]


@dataclass(frozen=True, kw_only=True)
class RunErr:
    """The paper's ERR = MSE(d - a) [(deg/h)^2] of one held-out run (eqs. 19, 22-24).

    Attributes
    ----------
    raw, traditional, improved : float
        ERR of the raw and each compensated output [(deg/h)^2].
    """

    raw: float
    traditional: float
    improved: float

    @property
    def improved_lowest(self) -> bool:
        """Whether the improved compensation beats both the raw output and the traditional one."""
        return self.improved < min(self.raw, self.traditional)

    def as_dict(self) -> dict[str, float]:
        return {"raw": self.raw, "traditional": self.traditional, "improved": self.improved}


@dataclass(frozen=True, kw_only=True)
class Scores:
    """ERR of every held-out run: identification run 2, validation 1 and 2 runs in order.

    Attributes
    ----------
    ident_2 : RunErr
        Identification run 2.
    val1 : tuple of RunErr
        The validation-1 runs.
    val2 : tuple of RunErr
        The validation-2 runs.
    """

    ident_2: RunErr
    val1: tuple[RunErr, ...]
    val2: tuple[RunErr, ...]

    def as_dict(self) -> dict[str, Any]:
        return {
            "ident_2": self.ident_2.as_dict(),
            "val1": [d.as_dict() for d in self.val1],
            "val2": [d.as_dict() for d in self.val2],
        }


@dataclass(frozen=True, kw_only=True)
class ValidationQuantities:
    """The validation claims' quantities of one unit, from its ERR scores.

    ``val1_ratio`` / ``val2_ratio``: mean raw ERR over mean improved ERR [x];
    ``val1_every_run_lower``: 1.0 when the improved ERR is below the raw one in every
    validation-1 run, else 0.0; ``val2_improved_lowest``: 1.0 when the improved ERR is the
    lowest of the three in every validation-2 run.

    Attributes
    ----------
    val1_ratio, val2_ratio : float
        Mean raw ERR over mean improved ERR [-].
    val1_every_run_lower : float
        1.0 when the improved ERR is below the raw one in every validation-1 run.
    val2_improved_lowest : float
        1.0 when the improved ERR is the lowest in every validation-2 run.
    """

    val1_ratio: float
    val1_every_run_lower: float
    val2_improved_lowest: float
    val2_ratio: float

    @classmethod
    def from_scores(cls, scores: Scores) -> ValidationQuantities:
        v1, v2 = scores.val1, scores.val2
        raw1 = float(np.mean([d.raw for d in v1]))
        raw2 = float(np.mean([d.raw for d in v2]))
        return cls(
            val1_ratio=raw1 / float(np.mean([d.improved for d in v1])),
            val1_every_run_lower=float(all(d.improved < d.raw for d in v1)),
            val2_improved_lowest=float(all(d.improved_lowest for d in v2)),
            val2_ratio=raw2 / float(np.mean([d.improved for d in v2])),
        )

    def as_dict(self) -> dict[str, float]:
        return {
            "val1_ratio": self.val1_ratio,
            "val1_every_run_lower": self.val1_every_run_lower,
            "val2_improved_lowest": self.val2_improved_lowest,
            "val2_ratio": self.val2_ratio,
        }


@dataclass(frozen=True, kw_only=True)
class ProtocolResult:
    """One training protocol (the paper's target Q, or the truth-target diagnostic) of a unit.

    Attributes
    ----------
    selection_improved, selection_traditional : RBFSelection
        Each model's selection.
    n_neurons_improved, n_neurons_traditional : int
        Each network's size.
    training_mean_output_deg_h : float
        The mean subtracted to form Q [deg/h] (0 for the truth target).
    training_rows : int
        Training rows.
    scores : Scores
        ERR of every held-out run.
    quantities : ValidationQuantities
        The validation quantities.
    """

    selection_improved: RBFSelection
    selection_traditional: RBFSelection
    n_neurons_improved: int
    n_neurons_traditional: int
    training_mean_output_deg_h: float  # the mean subtracted to form Q; 0 for the truth target
    training_rows: int
    scores: Scores
    quantities: ValidationQuantities


@dataclass(frozen=True, kw_only=True)
class Float32Check:
    """The exported networks evaluated in single precision (the paper's DSP) against float64.

    Attributes
    ----------
    max_abs_output_weight : float
        Largest |LW| of the improved network.
    max_abs_compensation_difference_deg_h : float
        Largest |float32 - float64| compensation [deg/h].
    max_relative_err_change : float
        Largest |ERR32 - ERR64| / ERR64 over the held-out runs [-].
    quantities : ValidationQuantities
        The validation quantities re-scored in float32.
    """

    max_abs_output_weight: float  # largest |LW| of the improved network
    max_abs_compensation_difference_deg_h: float
    max_relative_err_change: float  # largest |ERR32 - ERR64| / ERR64 over the held-out runs
    quantities: ValidationQuantities  # the validation quantities re-scored in float32

    def as_dict(self) -> dict[str, Any]:
        return {
            "max_abs_output_weight": self.max_abs_output_weight,
            "max_abs_compensation_difference_deg_h": self.max_abs_compensation_difference_deg_h,
            "max_relative_err_change": self.max_relative_err_change,
            "quantities": self.quantities.as_dict(),
        }


@dataclass(frozen=True, kw_only=True)
class PointHeating:
    """Table 1 / figure 2: a heated fibre stretch, -10 -> 40 degC, and the coil constants printed.

    Attributes
    ----------
    T_degC : ndarray
        Stretch temperature [degC].
    shupe : ndarray
        The Tdot term, free fibre [deg/h].
    product : ndarray
        The T x dT term about 0 degC, free fibre [deg/h].
    total : ndarray
        Their sum [deg/h].
    bonded_max : float
        Max |T x dT term| of the stretch bonded in the pack [deg/h].
    b_free : float
        d(beta_T)/dT of a free fibre [1/K^2].
    fibre_cte_per_K : float
        The fibre glass's expansion coefficient at 20 degC [1/K].
    wavelength_m : float
        Source wavelength [m].
    sweep : tuple of (float, float, float)
        (heated length [m], rate [degC/min], max |T x dT| [deg/h]) over the sweep.
    by_reference : tuple of (str, float, float)
        (reference, max |T x dT|, max |Tdot term|) [deg/h] at 0 degC, t_ref, 0 K.
    """

    T_degC: NDArray[np.float64]  # temperature of the heated stretch
    shupe: NDArray[np.float64]  # Tdot term, beta_T's chord at 0 degC [deg/h]
    product: NDArray[np.float64]  # T x dT term about 0 degC, free fibre [deg/h]
    total: NDArray[np.float64]  # their sum [deg/h]
    bonded_max: float  # max |T x dT term| of the stretch bonded in the pack [deg/h]
    b_free: float  # d(beta_T)/dT of a free fibre [1/K^2]
    fibre_cte_per_K: float  # the fibre glass's expansion coefficient at 20 degC [1/K]
    wavelength_m: float  # source wavelength [m]
    # (heated length [m], rate [degC/min], max |T x dT| [deg/h]): the claim against what Table 1 leaves out
    sweep: tuple[tuple[float, float, float], ...] = ()
    # (reference, max |T x dT| [deg/h], max |Tdot term| [deg/h]): the split at 0 degC, t_ref, 0 K
    by_reference: tuple[tuple[str, float, float], ...] = ()


@dataclass(frozen=True, kw_only=True)
class WindingPeak:
    """Peak coil drift [deg/h] of the identification run for one ideal winding, or why none.

    Attributes
    ----------
    winding : str
        The winding pattern.
    peak_total, peak_shupe, peak_product : float or None
        Peak total, Tdot and T x dT drift [deg/h].
    error : str or None
        Why none (the layer count does not fit the pattern).
    """

    winding: str
    peak_total: float | None = None
    peak_shupe: float | None = None
    peak_product: float | None = None
    error: str | None = None  # the layer count does not fit the pattern

    def as_dict(self) -> dict[str, Any]:
        if self.error is not None:
            return {"error": self.error}
        return {"peak_total": self.peak_total, "peak_shupe": self.peak_shupe, "peak_product": self.peak_product}


@dataclass(frozen=True, kw_only=True)
class IdentTrace:
    """Identification run 2 for figure 6 [h, degC, deg/h], float32.

    Attributes
    ----------
    t_h : ndarray
        Time [h].
    T : ndarray
        Logged temperature [degC].
    measured : ndarray
        Output [deg/h].
    true_drift_plus_bias : ndarray
        True drift plus bias [deg/h].
    estimate_improved, estimate_traditional : ndarray
        Each network's drift estimate [deg/h].
    """

    t_h: NDArray[np.float32]
    T: NDArray[np.float32]
    measured: NDArray[np.float32]  # output - a
    true_drift_plus_bias: NDArray[np.float32]
    estimate_improved: NDArray[np.float32]
    estimate_traditional: NDArray[np.float32]


@dataclass(frozen=True, kw_only=True)
class Val1Trace:
    """One validation-1 run for figure 7 [h, deg/h], float32.

    Attributes
    ----------
    t_h : ndarray
        Time [h].
    raw, improved : ndarray
        Raw and compensated output [deg/h].
    """

    t_h: NDArray[np.float32]
    raw: NDArray[np.float32]
    improved: NDArray[np.float32]


@dataclass(frozen=True, kw_only=True)
class Val2Trace:
    """Validation-2 run 1 for figure 8 [h, deg/h], float32; ``reference`` a [deg/h].

    Attributes
    ----------
    t_h : ndarray
        Time [h].
    raw, traditional, improved : ndarray
        Raw and compensated outputs [deg/h].
    reference : float
        The reference a [deg/h].
    """

    t_h: NDArray[np.float32]
    raw: NDArray[np.float32]
    traditional: NDArray[np.float32]
    improved: NDArray[np.float32]
    reference: float


@dataclass(frozen=True, kw_only=True)
class Traces:
    """Downsampled traces of the unit for the report's figures.

    Attributes
    ----------
    ident_2 : IdentTrace
        Figure 6.
    val1 : tuple of Val1Trace
        Figure 7.
    val2 : Val2Trace
        Figure 8.
    """

    ident_2: IdentTrace
    val1: tuple[Val1Trace, ...]
    val2: Val2Trace


@dataclass(frozen=True, kw_only=True)
class UnitResult:
    """One unit (seed) through paper 003's pipeline (satisfies ``papers.contract.UnitResult``).

    ``paper``: the paper's protocol (target Q = output - mean(output)); ``diagnostic_truth_target``:
    the same networks trained on output - truth (not possible for the paper);
    ``deployment_json``: the improved network exported (``RBFNetwork.to_json``).

    Attributes
    ----------
    seed : int
        The unit's seed.
    txdt_point_max_deg_h : float
        Max |T x dT term| of the point-heating case [deg/h].
    drift_peak_val1_deg_h : float
        Median peak |true coil drift| of the validation-1 runs [deg/h].
    val1_drift_to_noise : float
        std(true drift) / std(the rest of the error) over validation 1 [-].
    paper : ProtocolResult
        The paper's protocol (target Q = output - mean(output)).
    diagnostic_truth_target : ProtocolResult
        The same networks trained on output - truth (a labelled diagnostic).
    deployment_json : str
        The improved network exported (``RBFNetwork.to_json``).
    float32 : Float32Check
        The exported networks in single precision.
    streaming_max_abs_deviation_deg_h : float
        Largest |streaming - batch| compensation [deg/h].
    point_heating : PointHeating
        Table 1 / figure 2.
    windings : tuple of WindingPeak
        Peak coil drift per ideal winding.
    traces : Traces
        The figures' traces.
    val1_drift_estimate_error : float
        rms(estimated - true drift) / std(true drift), median over validation 1 [-].
    txdt_share : float
        The T x dT share of the training drift: R^2(1, T, dT, T dT) - R^2(1, T, dT) of the true
        drift on identification run 1 (``pipeline.txdt_share``) [-].
    """

    seed: int
    txdt_point_max_deg_h: float
    drift_peak_val1_deg_h: float
    val1_drift_to_noise: float  # std(true drift) / std(the rest of the error), validation 1 [x]
    paper: ProtocolResult
    diagnostic_truth_target: ProtocolResult
    deployment_json: str
    float32: Float32Check
    streaming_max_abs_deviation_deg_h: float
    point_heating: PointHeating
    windings: tuple[WindingPeak, ...]
    traces: Traces
    #: rms(estimated - true drift) / std(true drift), median over the validation-1 runs [-]
    val1_drift_estimate_error: float = math.nan
    #: the true drift's variance on identification run 1 only a T x dT input explains
    #: (``pipeline.txdt_share``) [-]
    txdt_share: float = math.nan

    @property
    def quantities(self) -> dict[str, float | None]:
        """One number per claim of ``CLAIMS`` (the claims module names which)."""
        return {
            "txdt_point_max_deg_h": self.txdt_point_max_deg_h,
            "drift_peak_val1_deg_h": self.drift_peak_val1_deg_h,
            "val1_drift_to_noise": self.val1_drift_to_noise,
            "txdt_unabsorbed": self.txdt_unabsorbed,
            "val1_drift_estimate_error": self.val1_drift_estimate_error,
            "txdt_share": self.txdt_share,
            **self.paper.quantities.as_dict(),
        }

    @property
    def txdt_unabsorbed(self) -> float:
        """The part of the true drift the (T, dT) model cannot absorb, on validation 2 [-]: with both
        networks trained on the true drift (``diagnostic_truth_target``), the traditional (T, dT)
        network's mean ERR over the improved (T, dT, T x dT) network's, minus 1."""
        v2 = self.diagnostic_truth_target.scores.val2
        return float(np.mean([d.traditional for d in v2]) / np.mean([d.improved for d in v2]) - 1.0)

