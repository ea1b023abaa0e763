"""The typed results of the Allan code: a deviation curve, a noise fit and its coefficients, a fit range."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from statistics import NormalDist
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.analysis.allan._checks import _positive_tau
from gyrobench.analysis.allan._kinds import KINDS
from gyrobench.analysis.allan._terms import _POWER, avar_to_coefficient
from gyrobench.base.ranges import Constraint, FieldChoice, FieldRange, validate

__all__ = ["AllanCurve", "Coefficient", "FitRange", "NoiseFit"]

_NORMAL = NormalDist()


def _shape_of_tau(name: str, *, optional: bool) -> Constraint:
    """The declared constraint that field ``name`` has the shape of ``tau`` (or is None, if optional)."""

    def holds(c: AllanCurve) -> bool:
        v = getattr(c, name)
        return (optional and v is None) or np.shape(v) == np.shape(c.tau)

    def message(c: AllanCurve) -> str:
        return f"{name} must have the shape of tau {np.shape(c.tau)}; got {np.shape(getattr(c, name))}"

    return Constraint(f"{name} has the shape of tau", holds, message)


@dataclass(frozen=True, slots=True, kw_only=True)
class AllanCurve:
    """An Allan-family deviation curve with its confidence band.

    Attributes
    ----------
    tau : ndarray
        Cluster times [s], tau = m / fs.
    deviation : ndarray
        Deviation [rate unit].
    low, high : ndarray
        Confidence bounds of the deviation at ``confidence`` [rate unit]
        (chi-square with ``edf`` degrees of freedom, NIST SP 1065 eq. 45).
    n_terms : ndarray
        Number of terms (differences) averaged in each estimate, as allantools/Stable32 count them.
    edf : ndarray
        Equivalent degrees of freedom used for the bounds.
    kind : str
        One of :data:`KINDS`.
    confidence : float
        Two-sided confidence level of ``low``/``high`` (e.g. 0.683).
    fs : float
        Sample rate [Hz].
    n_samples : int
        Number of rate samples the curve was computed from.
    alpha : ndarray or None
        Power-law noise exponent alpha (S_y ~ f^alpha) assumed at each tau for the edf.
    edf_scale : ndarray or None
        For a curve pooled over separate pieces of a record (gaps, or the quiet stretches
        between motion): at each tau, the white-noise edf of the pieces that hold that tau over
        the white-noise edf of one record of ``n_samples`` (<= 1). :func:`fit_noise` multiplies
        each term's one-record edf by it, so a tau that only the long pieces reach is weighted
        by what they hold. None: one contiguous record (a factor of 1).
    """

    tau: NDArray[np.float64]
    deviation: NDArray[np.float64]
    low: NDArray[np.float64]
    high: NDArray[np.float64]
    n_terms: NDArray[np.int64]
    edf: NDArray[np.float64]
    kind: str
    confidence: float
    fs: float
    n_samples: int
    alpha: NDArray[np.int64] | None = None
    edf_scale: NDArray[np.float64] | None = None

    RANGES: ClassVar[Mapping[str, FieldRange | FieldChoice]] = {
        "kind": FieldChoice(tuple(KINDS), "the deviation"),
        "confidence": FieldRange(0, 1, "1", "two-sided confidence level", low_open=True, high_open=True),
        "fs": FieldRange(0, math.inf, "Hz", "sample rate", low_open=True),
    }
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = tuple(
        _shape_of_tau(name, optional=name == "edf_scale")
        for name in ("deviation", "low", "high", "n_terms", "edf", "edf_scale")
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above

    @property
    def variance(self) -> NDArray[np.float64]:
        """The variance, ``deviation**2`` [rate unit^2]."""
        return self.deviation**2

    @property
    def m(self) -> NDArray[np.int64]:
        """Averaging factors m = tau * fs [samples]."""
        return np.rint(self.tau * self.fs).astype(np.int64)


@dataclass(frozen=True, slots=True, kw_only=True)
class Coefficient:
    """One fitted IEEE 952 coefficient.

    Attributes
    ----------
    name : str
        "Q", "N", "B", "K" or "R".
    value : float or None
        Point estimate [unit implied by the rate unit, see module docstring]; None when the
        record cannot show this term (``identifiable`` False).
    ci68, ci95 : tuple of float
        Two-sided 68.27 % and 95 % confidence intervals (always computed, also for
        non-identifiable terms, where the lower end is usually 0).
    identifiable : bool
        True when the term dominates the fitted curve at one tau at least and its 95 %
        interval excludes 0.
    upper_bound : float
        One-sided 95 % upper bound (for a non-identifiable term never below the value a
        sub-segment of the record identifies, when :func:`floor_bounds` was applied).
    power : int
        The AVAR term is C tau**power: Q -2, N -1, B 0, K 1, R 2.
    bound_note : str
        Empty, or why ``upper_bound`` was raised (the sub-segment and its value).
    """

    name: str
    value: float | None
    ci68: tuple[float, float]
    ci95: tuple[float, float]
    identifiable: bool
    upper_bound: float
    power: int
    bound_note: str = ""


@dataclass(frozen=True, slots=True, kw_only=True)
class NoiseFit:
    """Result of :func:`fit_noise`.

    Attributes
    ----------
    coefficients : dict of str to Coefficient
        The fitted terms, keyed by name.
    curve : AllanCurve
        The curve that was fitted.
    avar_coefficients : dict of str to float
        Fitted C_n of AVAR = sum_n C_n tau^n (non-negative; 0 for terms the NNLS dropped).
    covariance : ndarray
        Covariance matrix of the C_n, in the order of ``avar_coefficients``.
    iterations : int
        Reweighting iterations performed.
    used : ndarray of bool
        Which points of ``curve`` were fitted (``tau_min <= tau <= tau_max``).
    chi2 : float
        Goodness of fit sum_i r_i^2 / V_ii of the residuals r = A - X C of the fitted points,
        each against its modelled variance V_ii (the V of the intervals); nan without degrees
        of freedom. (Before: r' V^-1 r, which ran 1.3x its nominal law; see :func:`fit_noise`.)
    dof : int
        Degrees of freedom: fitted points minus the terms the fit kept (C_n > 0).
    chi2_expected : float
        E[chi2] if the model holds: the trace of the residuals' modelled correlation
        D^-1 (I - H) V (I - H)' D^-1 (H the fit's hat matrix, D^2 = diag V); the effective
        number of degrees of freedom (nan when dof = 0).
    p_value : float
        P(chi2 >= observed) under the model, from the exact law of chi2 (a Gaussian quadratic
        form sum_k lambda_k chi2_1, lambda the eigenvalues of that correlation) in the
        Liu-Tang-Zhang approximation: small means the five-power-law model does not describe
        the fitted points within their scatter (nan when dof = 0).
    misfit : bool
        ``p_value < misfit_p`` (the level :func:`fit_noise` was given).
    inflation : float
        Factor the standard errors were multiplied by: sqrt(chi2 / chi2_expected) on a misfit
        (the Birge ratio), else 1.
    point_covariance : ndarray
        Modelled covariance V of the fitted AVAR points [rate unit^4] (not inflated).
    range_rule : str
        What set the shortest fitted tau: "user" (a number given as ``tau_min``), "data"
        (the filter-shaped region :func:`fit_range` found, ``tau_min="auto"``), "bandwidth"
        (the stated sensor bandwidth, :func:`bandwidth_range`), "nonstationary" (``tau_min="auto"``
        on a record flagged non-stationary: the concave short-tau region is kept, as motion makes
        it too), or "" (no lower limit). When
        several apply the largest tau_min wins and is named here. ``tau_min="auto"`` may then
        drop further misfitting first points (see :func:`fit_noise`).
    range_reason : str
        One line saying why the fit starts where it does ("" without a lower limit).
    """

    coefficients: dict[str, Coefficient]
    curve: AllanCurve
    avar_coefficients: dict[str, float] = field(default_factory=dict)
    covariance: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 0)))
    iterations: int = 0
    used: NDArray[np.bool_] = field(default_factory=lambda: np.zeros(0, dtype=bool))
    chi2: float = float("nan")
    dof: int = 0
    chi2_expected: float = float("nan")
    p_value: float = float("nan")
    misfit: bool = False
    inflation: float = 1.0
    point_covariance: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 0)))
    range_rule: str = ""
    range_reason: str = ""

    @property
    def tau_used(self) -> NDArray[np.float64]:
        """The cluster times [s] that were fitted."""
        return np.asarray(self.curve.tau)[self.used]

    @property
    def chi2_per_dof(self) -> float:
        """chi2 per effective degree of freedom, chi2 / chi2_expected (~1 when the model holds; nan without dof)."""
        return self.chi2 / self.chi2_expected if self.dof > 0 else float("nan")

    def avar(self, tau: ArrayLike) -> NDArray[np.float64]:
        """Fitted model Allan variance sum_n C_n tau^n at ``tau`` [s] [rate unit^2]."""
        tau = _positive_tau(tau)
        out = np.zeros_like(tau)
        for name in self.avar_coefficients:
            out = out + self.term_avar(name, tau)
        return out

    def interval(self, name: str, level: float) -> tuple[float, float]:
        """Two-sided interval of coefficient ``name`` at confidence ``level`` in (0, 1).

        C_n +- z sqrt(Cov_nn) with z = Phi^-1((1 + level)/2), clipped at 0 and mapped by
        C -> sqrt(C / scale) (the same construction as ``ci68``/``ci95``), e.g. for a test
        at a stated false-alarm rate: ``fit.interval("N", 1 - 1e-6 / 5)``.
        """
        if name not in self.avar_coefficients:
            raise ValueError(f"name must be one of the fitted terms {tuple(self.avar_coefficients)}; got {name!r}")
        if isinstance(level, bool) or not isinstance(level, (int, float, np.floating)):
            raise TypeError(f"level must be a real number in (0, 1); got {level!r}")
        if not (0.0 < level < 1.0):
            raise ValueError(f"level must be a real number in (0, 1); got {level!r}")
        j = list(self.avar_coefficients).index(name)
        z = _NORMAL.inv_cdf(0.5 + float(level) / 2.0)
        c, se = self.avar_coefficients[name], math.sqrt(max(float(self.covariance[j, j]), 0.0))
        return avar_to_coefficient(name, c - z * se), avar_to_coefficient(name, c + z * se)

    def term_avar(self, name: str, tau: ArrayLike) -> NDArray[np.float64]:
        """One term's AVAR asymptote C_n tau^n at ``tau`` [s] (uses the point estimate C_n)."""
        if name not in self.avar_coefficients:
            raise ValueError(f"name must be one of the fitted terms {tuple(self.avar_coefficients)}; got {name!r}")
        tau = _positive_tau(tau)
        return self.avar_coefficients[name] * tau ** float(_POWER[name])


@dataclass(frozen=True, slots=True, kw_only=True)
class FitRange:
    """Where the five-power-law model can be fitted, as found by :func:`fit_range`.

    Attributes
    ----------
    tau_min : float or None
        Shortest tau [s] to fit; None when nothing needs excluding.
    excluded : int
        Number of short-tau points below ``tau_min``.
    reason : str
        One line saying what was found (for the report).
    """

    tau_min: float | None
    excluded: int
    reason: str
