"""Paper 000's typed unit result and the rules that turn it into one number per claim.

:class:`UnitResult` is what :func:`~.experiment.experiment` returns for one unit and all
that :mod:`.claims` and :mod:`.report` read. Coefficients are in field units
(:data:`gyrobench.base.units.COEFFICIENT_FIELD_UNITS`), frequencies in Hz, rates in deg/h.

How a unit's quantity tests a claim
-----------------------------------
* "A higher than B" / "B lower than A": the conservative ratio A_low / B_high (A's lower
  95 % bound over B's upper 95 % bound, which is B's interval end or, when B is not
  identifiable, its 95 % upper bound: the coefficient is below it either way). Above 1
  shows A > B at 95 %. When A, the side that must be shown larger, is itself only an upper
  bound, nothing shows it is above anything: the unit cannot test the claim (None), unless
  the data show the reverse (A's bound below B's lower 95 % bound; then A_high / B_low < 1
  is reported, a failure).
* "keeps" (Table 2): the ratio of the two point values, judged within a factor 2 of 1. When
  one side is only a bound the unit decides only if the bound already puts the ratio
  outside that window (then the bounding ratio is reported, a failure); else None.
* "nearly equal" (Table 1, phases 1 and 3): the 95 % intervals overlap (both identified).
* "slightly lower after" (K, R of phase 3 vs 1): the ratio of the point values, both
  identified (else None).
* "as the paper's fit computes it" (the claims on R, which a record of minutes cannot identify,
  and on B of the sweep record, which the swept bias hides): the ratio of the five-term fit's
  point values (``fit_value``), the numbers a table of that fit prints. The paper's tables carry
  no uncertainty, so "much / clearly lower" is read as a ratio above 2, the complement of "keeps"
  (within a factor 2 of 1). Where the non-negative fit prints 0 on both sides the fit found the
  term in neither signal: there is no ratio to read, and the unit cannot test the claim (None;
  reading it as "equal", ratio 1, would pass every "keeps" claim on such a unit whatever the
  signals are). A zero denominator under a positive numerator gives +inf (the table shows a
  term on one side only: 'lower' holds, 'keeps' fails). The control tells whether the analysis
  alone makes such a claim hold (an identity).
* Q "rises in phase 2" (Table 1): phase 2's lower 95 % ADEV bound at tau = 1/fs over the
  larger static upper bound (:func:`~.pipeline.shortest_tau_rise`, whose docstring says why the
  vibration phase's rise is found there and not in a fitted Q).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gyrobench.scenarios.reports.allan import TERMS

from .traces import CompensationTraces, FigureData, ModelTraces, MultiscaleTraces, RecordTraces, SplitTraces

__all__ = [
    "TERMS",
    "BiasModelScores",
    "Coefficient",
    "Coefficients",
    "CompensationTable",
    "CompensationTraces",
    "Decomposition",
    "FigureData",
    "ModelTraces",
    "MultiscaleTraces",
    "Offsets",
    "PhaseTable",
    "RecordTraces",
    "SplitTraces",
    "UnitResult",
    "fit_ratio",
    "keeps_ratio",
    "overlap",
    "shown_ratio",
    "unit_quantities",
    "value_ratio",
]

F32 = NDArray[np.float32]


@dataclass(frozen=True, slots=True, kw_only=True)
class Coefficient:
    """One Allan coefficient [field unit ``unit``]: the value with 95 % and 68 % intervals.

    ``value`` is None when the term is not identifiable from the record; then ``high`` is its
    95 % upper bound, ``low`` 0 and the 68 % ends None. ``tau_min_s`` [s], when set, is the
    shortest cluster time of the fit it comes from (Tables 2 and 3). ``fit_value``, when set
    (Tables 2 and 3), is the five-term least-squares fit's point value whether or not the record
    identifies the term: the number a table of the fit prints, as the paper's tables do (0 where
    the non-negative fit drops the term).

    Attributes
    ----------
    value : float or None
        The coefficient [unit] (None: not identifiable).
    low, high : float
        The 95 % interval [unit].
    low68, high68 : float or None
        The 68 % interval [unit].
    unit : str
        The field unit.
    identifiable : bool
        The record identifies the term.
    tau_min_s : float or None
        Shortest tau of the fit it comes from [s].
    fit_value : float or None
        The fit's point value, even where not identifiable [unit].
    """

    value: float | None
    low: float
    high: float
    low68: float | None
    high68: float | None
    unit: str
    identifiable: bool
    tau_min_s: float | None = None
    fit_value: float | None = None

    @classmethod
    def from_mapping(cls, d: Mapping[str, Any]) -> Coefficient:
        """From :func:`gyrobench.scenarios.reports.allan.coefficients_json`'s entry of one term."""
        return cls(**d)

    def as_dict(self) -> dict[str, Any]:
        """The results.json form (``tau_min_s`` only when set)."""
        out: dict[str, Any] = {
            "value": self.value,
            "low": self.low,
            "high": self.high,
            "low68": self.low68,
            "high68": self.high68,
            "unit": self.unit,
            "identifiable": self.identifiable,
        }
        if self.tau_min_s is not None:
            out["tau_min_s"] = self.tau_min_s
        if self.fit_value is not None:
            out["fit_value"] = self.fit_value
        return out


@dataclass(frozen=True, slots=True, kw_only=True)
class Coefficients:
    """The five coefficients of one signal (one column of Tables 1-3).

    Attributes
    ----------
    Q, N, B, K, R : Coefficient
        The IEEE 952 terms.
    """

    Q: Coefficient
    N: Coefficient
    B: Coefficient
    K: Coefficient
    R: Coefficient

    @classmethod
    def from_mapping(cls, d: Mapping[str, Mapping[str, Any]]) -> Coefficients:
        return cls(**{t: Coefficient.from_mapping(d[t]) for t in TERMS})

    def __getitem__(self, term: str) -> Coefficient:
        if term not in TERMS:
            raise KeyError(f"term must be one of {TERMS}; got {term!r}")
        c: Coefficient = getattr(self, term)
        return c

    def as_dict(self) -> dict[str, Any]:
        return {t: self[t].as_dict() for t in TERMS}


@dataclass(frozen=True, slots=True, kw_only=True)
class PhaseTable:
    """Table 1: the fixed-frequency record's phases (1 static, 2 vibration, 3 static).

    Attributes
    ----------
    phase1, phase2, phase3 : Coefficients
        Static, vibration, static.
    """

    phase1: Coefficients
    phase2: Coefficients
    phase3: Coefficients

    def columns(self) -> dict[str, Coefficients]:
        """``{"1": ..., "2": ..., "3": ...}`` (the results.json keys)."""
        return {"1": self.phase1, "2": self.phase2, "3": self.phase3}


@dataclass(frozen=True, slots=True, kw_only=True)
class Decomposition:
    """Table 2: the sweep record, its a_j bias part and its d1..d_j drift + noise part.

    Attributes
    ----------
    original, bias, drift_noise : Coefficients
        The sweep record, its bias part and its drift + noise part.
    """

    original: Coefficients
    bias: Coefficients
    drift_noise: Coefficients

    def columns(self) -> dict[str, Coefficients]:
        return {"original": self.original, "bias": self.bias, "drift_noise": self.drift_noise}


@dataclass(frozen=True, slots=True, kw_only=True)
class CompensationTable:
    """Table 3: the fixed-frequency record original, denoised, RBF- and LS-compensated.

    Attributes
    ----------
    original, denoised, rbf, ls : Coefficients
        The record at each stage.
    """

    original: Coefficients
    denoised: Coefficients
    rbf: Coefficients
    ls: Coefficients

    def columns(self) -> dict[str, Coefficients]:
        return {"original": self.original, "denoised": self.denoised, "rbf": self.rbf, "ls": self.ls}


@dataclass(frozen=True, slots=True, kw_only=True)
class BiasModelScores:
    """The bias models' MSE [(deg/h)^2] against their a7 targets and the true bias, and the bins.

    Attributes
    ----------
    rbf_vs_target, ls_vs_target : float
        Each model's MSE against its training targets [(deg/h)^2].
    rbf_vs_truth, ls_vs_truth : float
        Each model's MSE against the true bias [(deg/h)^2].
    target_vs_truth : float
        The targets' MSE against the true bias [(deg/h)^2].
    rbf_neurons : int
        The RBF network's size.
    n_bins : int
        Training bins.
    training_range_hz : tuple of float
        The training frequency range [Hz].
    peak_bias_frequency_hz : float
        Where the targets peak [Hz].
    true_peak_bias_frequency_hz : float
        Where the true bias peaks [Hz].
    """

    rbf_vs_target: float
    ls_vs_target: float
    rbf_vs_truth: float
    ls_vs_truth: float
    target_vs_truth: float
    rbf_neurons: int
    n_bins: int
    training_range_hz: tuple[float, float]
    peak_bias_frequency_hz: float
    true_peak_bias_frequency_hz: float

    def as_dict(self) -> dict[str, Any]:
        return {
            "rbf_vs_target": self.rbf_vs_target,
            "ls_vs_target": self.ls_vs_target,
            "rbf_vs_truth": self.rbf_vs_truth,
            "ls_vs_truth": self.ls_vs_truth,
            "target_vs_truth": self.target_vs_truth,
            "rbf_neurons": self.rbf_neurons,
            "n_bins": self.n_bins,
            "training_range_hz": list(self.training_range_hz),
            "peak_bias_frequency_hz": self.peak_bias_frequency_hz,
            "true_peak_bias_frequency_hz": self.true_peak_bias_frequency_hz,
            "unit": "(deg/h)^2",
        }


@dataclass(frozen=True, slots=True, kw_only=True)
class Offsets:
    """Figures 7-8 in numbers [deg/h] (spike ratio dimensionless); NaN where not measurable.

    Attributes
    ----------
    offset_denoised, offset_rbf, offset_ls : float
        Mean offset during vibration of each signal [deg/h].
    static_scatter : float
        Std of the static phase's block means [deg/h].
    edge_spike_ratio : float
        Edge spikes over the steady reference [-].
    residual_vs_truth_rbf, residual_vs_truth_ls : float
        Each compensation's residual against the true bias [deg/h].
    true_bias_steady : float
        The true steady bias of the dwell [deg/h].
    """

    offset_denoised: float
    offset_rbf: float
    offset_ls: float
    static_scatter: float
    edge_spike_ratio: float
    residual_vs_truth_rbf: float
    residual_vs_truth_ls: float
    true_bias_steady: float

    def as_dict(self) -> dict[str, float]:
        return {
            "offset_denoised": self.offset_denoised,
            "offset_rbf": self.offset_rbf,
            "offset_ls": self.offset_ls,
            "static_scatter": self.static_scatter,
            "edge_spike_ratio": self.edge_spike_ratio,
            "residual_vs_truth_rbf": self.residual_vs_truth_rbf,
            "residual_vs_truth_ls": self.residual_vs_truth_ls,
            "true_bias_steady": self.true_bias_steady,
        }


# ------------------------------------------------------------------------------ figure traces (float32)
@dataclass(frozen=True, slots=True, kw_only=True)
class UnitResult:
    """One simulated unit through paper 000's analysis.

    One simulated unit through paper 000's analysis (satisfies
    :class:`gyrobench.scenarios.papers.contract.UnitResult`).

    Attributes
    ----------
    seed : int
        The unit's seed.
    quantities : mapping of str to float or None
        One number per claim quantity (None: this unit cannot test it).
    phases : PhaseTable
        Table 1.
    decomposition : Decomposition
        Table 2.
    compensation : CompensationTable
        Table 3.
    bias_models : BiasModelScores
        The bias models' scores.
    offsets : Offsets
        Figures 7-8 in numbers.
    figures : FigureData
        What the figures draw.
    """

    seed: int
    quantities: Mapping[str, float | None]
    phases: PhaseTable
    decomposition: Decomposition
    compensation: CompensationTable
    bias_models: BiasModelScores
    offsets: Offsets
    figures: FigureData


# ------------------------------------------------------------------------------ quantity rules
def zero_safe_ratio(num: float, den: float) -> float:
    """num / den of two non-negative numbers: +inf when only den is 0, 0 when both are."""
    if den > 0:
        return float(num / den)
    return math.inf if num > 0 else 0.0


def shown_ratio(big: Coefficient, small: Coefficient) -> float | None:
    """Evidence that ``big`` > ``small`` (module docstring).

    big identified: big's lower 95 % bound over small's upper 95 % bound (> 1 shows big > small).
    big only a bound: the unit decides only when the data show the reverse (big's bound below
    small's lower 95 % bound: big.high / small.low < 1), else None.

    Parameters
    ----------
    big, small : Coefficient
        The coefficients.

    Returns
    -------
    float or None
        The evidence ratio (> 1 shows big > small), or None when the unit cannot decide.
    """
    if big.value is not None:
        return zero_safe_ratio(big.low, small.high)
    if small.value is not None and big.high < small.low:
        return float(big.high / small.low)
    return None


def keeps_ratio(num: Coefficient, den: Coefficient, factor: float = 2.0) -> float | None:
    """num / den for a "keeps" claim (judged within ``factor`` of 1).

    Both identified: the ratio of the values. One side only a bound: the unit decides only
    when the bound already puts the ratio outside the window (num.high / den.low < 1/factor,
    or num.low / den.high > factor; that bounding ratio is returned), else None.

    Parameters
    ----------
    num, den : Coefficient
        The coefficients.
    factor : float
        The "keeps" window's factor.

    Returns
    -------
    float or None
        The ratio, or None when the unit cannot decide.
    """
    if num.value is not None and den.value is not None:
        return float(num.value / den.value) if den.value > 0 else None
    if num.value is None and den.value is not None and num.high < den.low / factor:
        return float(num.high / den.low)
    if den.value is None and num.value is not None and num.low > factor * den.high:
        return zero_safe_ratio(num.low, den.high)
    return None


def value_ratio(num: Coefficient, den: Coefficient) -> float | None:
    """num / den of the point values; None unless both are identified.

    Parameters
    ----------
    num, den : Coefficient
        The coefficients.

    Returns
    -------
    float or None
        num / den.
    """
    if num.value is None or den.value is None or den.value <= 0:
        return None
    return float(num.value / den.value)


def fit_ratio(num: Coefficient, den: Coefficient) -> float | None:
    """The ratio of two coefficients' fit values, as a table of the fit reads.

    num / den of the fit's point values (``fit_value``; module docstring), as a table of the fit
    reads: +inf when only den is 0; None when either is not set or both are 0 (the fit
    finds the term in neither signal: no ratio, so the unit cannot test a "keeps" or a "lower"
    claim). Judged > 2 for "higher" and within a factor 2 of 1 for "keeps".

    Parameters
    ----------
    num, den : Coefficient
        The coefficients.

    Returns
    -------
    float or None
        num / den; +inf when only den is 0; None when either is unset or both are 0.
    """
    if num.fit_value is None or den.fit_value is None:
        return None
    if num.fit_value <= 0 and den.fit_value <= 0:
        return None
    return zero_safe_ratio(num.fit_value, den.fit_value)


def overlap(a: Coefficient, b: Coefficient) -> float | None:
    """1.0 when the 95 % intervals of two identified coefficients overlap, 0.0 when not, None if a bound.

    Parameters
    ----------
    a, b : Coefficient
        The coefficients.

    Returns
    -------
    float or None
        1.0, 0.0, or None when either is only a bound.
    """
    if a.value is None or b.value is None:
        return None
    return 1.0 if (a.low <= b.high and b.low <= a.high) else 0.0


def unit_quantities(
    phases: PhaseTable,
    decomposition: Decomposition,
    compensation: CompensationTable,
    scores: BiasModelScores,
    offsets: Offsets,
    *,
    shortest_tau_rise: float | None = None,
) -> dict[str, float | None]:
    """One number per claim quantity (module docstring: how a unit's quantity tests a claim).

    ``shortest_tau_rise``: Table 1's rise at tau = 1/fs
    (:func:`~.pipeline.shortest_tau_rise`; None: not measured).

    Parameters
    ----------
    phases : PhaseTable
        Table 1.
    decomposition : Decomposition
        Table 2.
    compensation : CompensationTable
        Table 3.
    scores : BiasModelScores
        The bias models' scores.
    offsets : Offsets
        The offsets.
    shortest_tau_rise : float or None
        Table 1's rise at tau = 1/fs (None: not measured).

    Returns
    -------
    dict of str to float or None
        Claim quantity -> the unit's number.
    """
    p1, p2, p3 = phases.phase1, phases.phase2, phases.phase3
    o, b, dn = decomposition.original, decomposition.bias, decomposition.drift_noise
    co, cd, cr, cl = compensation.original, compensation.denoised, compensation.rbf, compensation.ls
    q: dict[str, float | None] = {}
    for t in ("N", "B", "K", "R"):  # "higher than phases 1 and 3": the weaker of the two comparisons
        # (Q's rise is read off the ADEV at tau = 1/fs: ``shortest_tau_rise``)
        vs = [r for r in (shown_ratio(p2[t], p1[t]), shown_ratio(p2[t], p3[t])) if r is not None]
        q[f"t1_{t}_phase2_over_static"] = min(vs) if vs else None
    q["t1_adev_shortest_phase2_over_static"] = shortest_tau_rise
    for t in ("Q", "N", "B"):
        q[f"t1_{t}_phase1_phase3_overlap"] = overlap(p1[t], p3[t])
    for t in ("K", "R"):
        q[f"t1_{t}_phase3_over_phase1"] = value_ratio(p3[t], p1[t])
    for t in ("Q", "N"):  # R of Table 2 and B of the sweep record: as the paper's fit prints them (below)
        q[f"t2_{t}_original_over_bias"] = shown_ratio(o[t], b[t])
        q[f"t2_{t}_drift_noise_over_original"] = keeps_ratio(dn[t], o[t])
    q["t2_K_bias_over_original"] = keeps_ratio(b["K"], o["K"])
    q["t2_K_original_over_drift_noise"] = shown_ratio(o["K"], dn["K"])
    # as the paper's five-term fit computes them (module docstring): B of the sweep record (hidden by the
    # swept bias), R (needs thousands of hours)
    q["t2_R_original_over_bias_fit"] = fit_ratio(o["R"], b["R"])
    q["t2_R_drift_noise_over_original_fit"] = fit_ratio(dn["R"], o["R"])
    q["t2_B_bias_over_original_fit"] = fit_ratio(b["B"], o["B"])
    q["t2_B_original_over_drift_noise_fit"] = fit_ratio(o["B"], dn["B"])
    q["t3_R_denoised_over_rbf_fit"] = fit_ratio(cd["R"], cr["R"])
    q["t3_R_denoised_over_ls_fit"] = fit_ratio(cd["R"], cl["R"])
    q["t3_R_ls_over_rbf_fit"] = fit_ratio(cl["R"], cr["R"])
    for t in ("Q", "N"):
        q[f"t3_{t}_original_over_denoised"] = shown_ratio(co[t], cd[t])
    for t in ("B", "K"):  # R of Table 3: as the paper's fit prints it (above)
        q[f"t3_{t}_denoised_over_rbf"] = shown_ratio(cd[t], cr[t])
        q[f"t3_{t}_denoised_over_ls"] = shown_ratio(cd[t], cl[t])
        q[f"t3_{t}_ls_over_rbf"] = shown_ratio(cl[t], cr[t])
    q["fig3_peak_bias_frequency"] = scores.peak_bias_frequency_hz
    q["fig6_mse_ls_over_rbf_target"] = zero_safe_ratio(scores.ls_vs_target, scores.rbf_vs_target)
    q["fig6_mse_ls_over_rbf_truth"] = zero_safe_ratio(scores.ls_vs_truth, scores.rbf_vs_truth)
    q["fig7_offset_over_scatter"] = abs(offsets.offset_denoised) / offsets.static_scatter
    q["fig8_edge_spike_ratio"] = offsets.edge_spike_ratio
    q["fig8_rbf_offset_over_denoised"] = zero_safe_ratio(abs(offsets.offset_rbf), abs(offsets.offset_denoised))
    # the method claims' precondition: the simulator's true vibration bias over the 10-s scatter
    q["pre_vibration_bias_over_scatter"] = abs(offsets.true_bias_steady) / offsets.static_scatter
    return {k: (float(v) if v is not None and not math.isnan(v) else None) for k, v in q.items()}
