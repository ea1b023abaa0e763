"""One analysis of a static rate record: stationarity verdict, what is fitted, the fit range and the model.

:func:`analyse_record` is the single path that ``gyrobench allan``, ``gyrobench twin``, the
Kalibr export and the Python API share. It decides, in this order:

1. the Allan deviation of the record (:func:`gyrobench.analysis.allan.allan_deviation`);
2. the stationarity verdict (:func:`stationarity_verdict`: motion and steps on windows of the
   curve's tau nearest 1 s);
3. what is fitted: the whole record when it is stationary; otherwise its quiet stretches,
   pooled per tau and bridged where harmless (:func:`gyrobench.analysis.quiet.quiet_curve`),
   or, when they hold too few taus, the whole record with its short taus kept (the motion's
   misfit then shows);
4. the fit range and the IEEE 952 fit (:func:`gyrobench.analysis.allan.fit_noise`), with the
   open terms' bounds floored by the record's sub-segments on a whole stationary record
   (:func:`gyrobench.analysis.allan.floor_bounds`);
5. the model terms beyond Q/N/B/K/R that the data ask for (a Gauss-Markov process, a
   sinusoid, the sensor's own low-pass), chosen by :func:`gyrobench.analysis.model_select.select_model`.

The result is a frozen :class:`RecordAnalysis`; the command-line exit statuses follow from
:attr:`RecordAnalysis.nonstationary` alone.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.analysis.allan import TERMS, AllanCurve, FitRange, NoiseFit
from gyrobench.analysis.quiet import QuietCurve
from gyrobench.analysis.stationarity import StationarityReport

if TYPE_CHECKING:
    from gyrobench.analysis.model_select import ModelChoice

__all__ = ["FIT_KINDS", "RecordAnalysis", "analyse_record", "octave_subset", "stationarity_verdict"]

#: statistics with the IEEE 952 term coefficients (the Allan variances)
FIT_KINDS = ("overlapping", "standard")
#: stationarity windows: at least this many, of at least 8 samples
MIN_STATIONARITY_WINDOWS = 32


@dataclass(frozen=True, slots=True, kw_only=True)
class RecordAnalysis:
    """Result of :func:`analyse_record`.

    Attributes
    ----------
    curve : AllanCurve
        Allan deviation of the whole record.
    stationarity : StationarityReport or None
        The motion/step check (None when no tau of the curve gives 32 windows of 8 samples).
    nonstationary : bool
        Motion or steps were found.
    basis : str
        What was fitted: "whole record", "quiet stretches", or "whole record (motion kept)" for
        a non-stationary record whose quiet stretches hold too few taus (or with ``quiet=False``).
    quiet : QuietCurve or None
        The quiet-stretch curve, when the record is non-stationary and one could be built.
    fit_curve : AllanCurve
        The curve that was fitted (the whole record's octave taus, or the quiet curve).
    fit : NoiseFit or None
        The IEEE 952 fit; None for a kind without one (``no_fit`` says why).
    fit_range : FitRange or None
        What ``tau_min="auto"`` found on ``fit_curve`` (None otherwise).
    bandwidth_range : FitRange or None
        What a stated ``bandwidth`` excludes (None without one).
    model : ModelChoice or None
        The extra terms the data chose (None without a fit or with ``select=False``).
    no_fit : str
        Why there is no fit ("" when there is one).
    warnings : tuple of str
        The stationarity findings, one line each.
    """

    curve: AllanCurve
    stationarity: StationarityReport | None
    nonstationary: bool
    basis: str
    quiet: QuietCurve | None
    fit_curve: AllanCurve
    fit: NoiseFit | None
    fit_range: FitRange | None
    bandwidth_range: FitRange | None
    model: ModelChoice | None
    no_fit: str
    warnings: tuple[str, ...]

    @property
    def fitted_stretches(self) -> tuple[tuple[int, int], ...] | None:
        """Sample ranges the fit describes: None for the whole record, else the quiet stretches."""
        return self.quiet.stretches if self.basis == "quiet stretches" and self.quiet is not None else None


def stationarity_verdict(rate: ArrayLike, fs: float, curve: AllanCurve, label: str) -> StationarityReport | None:
    """The motion/step check on windows of the curve's tau nearest 1 s with >= 32 windows of >= 8 samples.

    None when no tau of the curve qualifies (the record is too short to test).

    Parameters
    ----------
    rate : array_like
        The rate record [any unit].
    fs : float
        Sample rate [Hz].
    curve : AllanCurve
        Its Allan curve (the window length is one of its taus).
    label : str
        The channel's name, for the warning lines.

    Returns
    -------
    StationarityReport or None
        The check's verdict; None when the record is too short to test.
    """
    from gyrobench.analysis.stationarity import stationarity_check

    y = np.asarray(rate, dtype=float)
    ok = (curve.m >= 8) & (y.size // np.maximum(curve.m, 1) >= MIN_STATIONARITY_WINDOWS)
    if not np.any(ok):
        return None
    i = int(np.flatnonzero(ok)[np.argmin(np.abs(np.log(curve.tau[ok])))])
    return stationarity_check(y, fs, float(curve.deviation[i]), window=float(curve.tau[i]))


def octave_subset(curve: AllanCurve) -> AllanCurve:
    """The points of ``curve`` at m = 2^k (the fit's point covariance grows as the square of the taus).

    Parameters
    ----------
    curve : AllanCurve
        An Allan curve.

    Returns
    -------
    AllanCurve
        Its points at m = 2^k (``curve`` itself when they are all of that kind).
    """
    m = curve.m
    keep = (m & (m - 1)) == 0
    if keep.all():
        return curve
    return AllanCurve(tau=curve.tau[keep], deviation=curve.deviation[keep], low=curve.low[keep],
                      high=curve.high[keep], n_terms=curve.n_terms[keep], edf=curve.edf[keep], kind=curve.kind,
                      confidence=curve.confidence, fs=curve.fs, n_samples=curve.n_samples,
                      alpha=None if curve.alpha is None else curve.alpha[keep])


def analyse_record(
    rate: ArrayLike,
    fs: float,
    *,
    label: str = "rate",
    taus: str = "octave",
    kind: str = "overlapping",
    terms: tuple[str, ...] = TERMS,
    tau_min: float | str | None = "auto",
    tau_max: float | None = None,
    bandwidth: float | None = None,
    bandwidth_bias: float = 0.1,
    quiet: bool = True,
    floor: bool = True,
    select: bool = True,
    select_options: dict[str, Any] | None = None,
) -> RecordAnalysis:
    """Analyse a static rate record (module docstring): verdict, fitted curve, fit and model terms.

    Parameters
    ----------
    rate : array_like
        Rate samples [any unit u], one every 1/fs, finite.
    fs : float
        Sample rate [Hz].
    label : str
        The channel's name, for the warning lines.
    taus : {"octave", "decade", "all"}
        Tau list of the curve (the fit uses the octave taus of "all").
    kind : str
        Statistic of the curve; only "overlapping" and "standard" are fitted.
    terms : tuple of str
        The IEEE 952 terms fitted (``"Q"``, ``"N"``, ``"B"``, ``"K"``, ``"R"``), as in
        :func:`gyrobench.analysis.allan.fit_noise`.
    tau_min : float, "auto" or None
        Shortest tau fitted [s] (as in ``fit_noise``).
    tau_max : float or None
        Longest tau fitted [s] (None: the curve's last).
    bandwidth : float or None
        The sensor's output bandwidth [Hz] (None: unknown; taus it biases are kept).
    bandwidth_bias : float
        Largest relative Allan-variance bias of the output filter a fitted tau may carry.
    quiet : bool
        On a non-stationary record fit its quiet stretches (default); False fits the whole
        record with its short taus kept.
    floor : bool
        Floor the open terms' bounds of a whole-record fit by its halves, quarters and eighths.
    select : bool
        Choose extra model terms (:func:`gyrobench.analysis.model_select.select_model`).
    select_options : dict, optional
        Keyword options of ``select_model`` (e.g. ``criterion``, ``filter_order``).

    Returns
    -------
    RecordAnalysis
        The curve, the stationarity verdict, the fit (None for a statistic that is not fitted)
        and the selected model terms.
    """
    from gyrobench.analysis.allan import allan_deviation, bandwidth_range, fit_noise, fit_range, floor_bounds
    from gyrobench.analysis.quiet import quiet_curve

    y = np.asarray(rate, dtype=float)
    curve = allan_deviation(y, fs, taus=taus, kind=kind)
    stat = stationarity_verdict(y, fs, curve, label)
    moving = bool(stat is not None and stat.tested and not stat.stationary)
    warnings = tuple(stat.warnings(label)) if stat is not None else ()
    if kind not in FIT_KINDS:
        return RecordAnalysis(curve=curve, stationarity=stat, nonstationary=moving, basis="whole record", quiet=None,
                              fit_curve=curve, fit=None, fit_range=None, bandwidth_range=None, model=None,
                              no_fit=(f"no noise fit for the {kind} deviation: the IEEE 952 term coefficients (3 Q^2/"
                                      f"tau^2, N^2/tau, ...) are those of the Allan variance; the curve is exported"),
                              warnings=warnings)
    whole = octave_subset(curve) if taus == "all" else curve
    if len(whole.tau) < len(terms):
        raise ValueError(
            f"{label}: {y.size} samples at {fs:g} Hz give {len(whole.tau)} {curve.kind} Allan deviation point(s) at "
            f"taus={taus!r} (up to {whole.tau[-1]:.3g} s); the {'/'.join(terms)} fit needs at least {len(terms)}: "
            "use a longer record or fewer --terms")
    qc = None
    fit_curve, basis, fit_nonstationary = whole, "whole record", False
    if moving:
        fit_curve, basis, fit_nonstationary = whole, "whole record (motion kept)", True
        if quiet and stat is not None and kind == "overlapping":
            qc = quiet_curve(y, fs, stat, taus="decade" if taus == "decade" else "octave")
            if qc is not None and len(qc.curve.tau) >= len(terms) + 2:
                fit_curve, basis, fit_nonstationary = qc.curve, "quiet stretches", False
    options: dict[str, Any] = {"terms": terms, "tau_min": tau_min, "tau_max": tau_max, "bandwidth": bandwidth}
    fr = fit_range(fit_curve, n_terms=len(terms), nonstationary=fit_nonstationary) if tau_min == "auto" else None
    bw = bandwidth_range(fit_curve, bandwidth, bias=bandwidth_bias) if bandwidth is not None else None
    fit = fit_noise(fit_curve, bandwidth_bias=bandwidth_bias, nonstationary=fit_nonstationary, **options)
    if floor and basis == "whole record":
        fit = floor_bounds(fit, y, fs, bandwidth_bias=bandwidth_bias, **options)
    model = None
    if select:
        from gyrobench.analysis.model_select import select_model

        model = select_model(fit, **(select_options or {}))
    return RecordAnalysis(curve=curve, stationarity=stat, nonstationary=moving, basis=basis, quiet=qc,
                          fit_curve=fit_curve, fit=fit, fit_range=fr, bandwidth_range=bw, model=model, no_fit="",
                          warnings=warnings)


def stretch_samples(analysis: RecordAnalysis, rate: ArrayLike) -> list[NDArray[np.float64]]:
    """The samples the analysis fitted: the whole record, or each quiet stretch."""
    y = np.asarray(rate, dtype=float)
    spans = analysis.fitted_stretches
    return [y] if spans is None else [y[a:b] for a, b in spans]
