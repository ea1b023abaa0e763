"""Does a simulated twin reproduce a real record's Allan deviation? A test with a stated false-alarm rate.

A digital twin of a static gyro record is a simulated record of the same length and rate
from a noise model fitted to the real one. Comparing the twin's Allan deviation with the
real curve's own 95 % interval at each tau is not a usable pass rule: the twin's estimate
scatters too, so even a perfect twin falls outside a per-tau 95 % band of the real curve
about 17 % of the time at each tau, and "inside at every tau" then fails most perfect twins.

The rule here compares two independent estimates of the same variance. At cluster time
tau_i the real and twin Allan variances are, for a perfect twin, sigma_i^2 chi2(nu_r)/nu_r
and sigma_i^2 chi2(nu_t)/nu_t with the equivalent degrees of freedom (edf) of each curve,
so their ratio follows Fisher's F(nu_t, nu_r) (NIST SP 1065 sec. 5.3-5.4: chi-square law of
the Allan variance with its edf). Each fitted tau is tested two-sided at level
alpha' = 1 - (1 - alpha)^(1/m) (Sidak, m fitted taus), so the family-wise false-alarm rate
over the record, "some tau outside although the twin is perfect", is at most alpha when the
taus' tests are independent; the octave taus of one record are positively correlated,
which makes the rule conservative (the rate below alpha), and so does fitting the twin's
model to the real curve (the twin's level follows the real estimate's scatter). The rate
is checked over seeds in ``tests/analysis/test_twin.py``.
Functions of arrays and :class:`AllanCurve` only (``analysis`` imports no ``sim``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.analysis.allan import AllanCurve, deviation_bounds

__all__ = ["TwinComparison", "SampleComparison", "compare_samples", "sample_variance_edf", "compare_twin",
           "FAMILY_ALPHA", "MAX_RATIO"]

FAMILY_ALPHA = 0.05
"""Default family-wise false-alarm rate of the pass rule (a perfect twin fails at most this often)."""
MAX_RATIO = 10.0
"""A twin whose ADEV differs from the real one by this factor or more at any compared tau never
matches, whatever the F band allows there (at the last taus, with 1-2 edf, the band is wider
than 10x; a perfect twin lies beyond 10x with probability ~1 % at 2 edf each, ~6 % at 1)."""


@dataclass(frozen=True, slots=True, kw_only=True)
class TwinComparison:
    """Per-tau comparison of a twin's Allan deviation with a real record's (module docstring).

    Attributes
    ----------
    tau : ndarray
        The compared cluster times [s] (the real fit's taus).
    real, twin : ndarray
        Allan deviations of the real record and of the twin [rate unit].
    real_low95, real_high95 : ndarray
        The real curve's own 95 % interval (chi-square with its edf) [rate unit]; reported, not
        the pass rule.
    edf_real, edf_twin : ndarray
        Equivalent degrees of freedom of each estimate.
    ratio : ndarray
        twin / real Allan deviation.
    ratio_low, ratio_high : ndarray
        The simultaneous band of ``ratio`` for a perfect twin: sqrt of the F(edf_twin, edf_real)
        quantiles at per_tau_alpha/2 and 1 - per_tau_alpha/2.
    inside : ndarray of bool
        ``ratio_low <= ratio <= ratio_high`` at each tau.
    inside_real95 : ndarray of bool
        The twin's deviation inside the real curve's own 95 % interval (informative: a perfect
        twin is inside about 83 % of the time per tau).
    family_alpha : float
        Family-wise false-alarm rate of the rule.
    per_tau_alpha : float
        Sidak level per tau, 1 - (1 - family_alpha)^(1/m).
    max_ratio : float
        A ratio outside [1/max_ratio, max_ratio] fails at any tau.
    passed : bool
        ``inside`` at every compared tau (a property).
    """

    tau: NDArray[np.float64]
    real: NDArray[np.float64]
    real_low95: NDArray[np.float64]
    real_high95: NDArray[np.float64]
    twin: NDArray[np.float64]
    edf_real: NDArray[np.float64]
    edf_twin: NDArray[np.float64]
    ratio: NDArray[np.float64]
    ratio_low: NDArray[np.float64]
    ratio_high: NDArray[np.float64]
    inside: NDArray[np.bool_]
    inside_real95: NDArray[np.bool_]
    family_alpha: float
    per_tau_alpha: float
    max_ratio: float = MAX_RATIO

    @property
    def passed(self) -> bool:
        """The pass rule: the ratio lies in its band (and within ``max_ratio``) at every compared tau."""
        return bool(np.all(self.inside))

    @property
    def n_taus(self) -> int:
        """Number of compared taus m."""
        return int(len(self.tau))

    @property
    def rule(self) -> str:
        """The pass rule in one line."""
        return (f"pass when twin/real ADEV lies in its F(edf_twin, edf_real) band, and within {self.max_ratio:g}x, at "
                f"all {self.n_taus} compared taus; Sidak per-tau level {self.per_tau_alpha:.4g}, family-wise "
                f"false-alarm rate <= {self.family_alpha:g} for a perfect twin")


def _check_curve(name: str, c: object) -> AllanCurve:
    if not isinstance(c, AllanCurve):
        raise TypeError(f"{name} must be an AllanCurve; got {type(c).__name__}")
    if c.kind not in ("overlapping", "standard"):
        raise ValueError(f"{name}.kind must be 'overlapping' or 'standard' (the chi-square edf law); got {c.kind!r}")
    return c


def compare_twin(
    real: AllanCurve,
    twin: AllanCurve,
    *,
    taus: ArrayLike | None = None,
    family_alpha: float = FAMILY_ALPHA,
    max_ratio: float = MAX_RATIO,
    extra_tests: int = 0,
) -> TwinComparison:
    """Test a twin's Allan deviation against a real record's at a family-wise false-alarm rate.

    Parameters
    ----------
    real, twin : AllanCurve
        Overlapping or standard Allan deviations of the real record and of the twin, of the
        same kind, at the same taus (same length and rate).
    taus : array_like, optional
        The cluster times [s] to compare (normally the real noise fit's fitted taus,
        ``NoiseFit.tau_used``); each must be a tau of both curves. Default: every tau.
    family_alpha : float
        Family-wise false-alarm rate in (0, 1): the largest probability that a perfect twin
        fails (default 0.05).
    max_ratio : float
        A ratio outside [1/max_ratio, max_ratio] fails at any tau (default :data:`MAX_RATIO`).
    extra_tests : int
        Further tests sharing the family's level (e.g. :func:`compare_samples`): the Sidak
        level is taken over m + extra_tests.

    Returns
    -------
    TwinComparison

    Raises
    ------
    TypeError, ValueError
        Curves of another type or kind, different taus, an empty tau list, a bad alpha.

    Notes
    -----
    Under a perfect twin A_t/A_r ~ F(nu_t, nu_r) at each tau (A the Allan variance, nu its
    edf); the band on the deviation ratio is [sqrt(F_{a/2}), sqrt(F_{1-a/2})] with
    a = 1 - (1 - family_alpha)^(1/m) (Sidak over m taus). Module docstring for why this
    bounds the family-wise rate. Reference: NIST SP 1065 (Riley 2008) sec. 5.3-5.4.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrobench.analysis.allan import allan_deviation
    >>> rng = np.random.default_rng(0)
    >>> a = allan_deviation(rng.standard_normal(4096), 1.0)
    >>> b = allan_deviation(rng.standard_normal(4096), 1.0)
    >>> compare_twin(a, b).passed
    True
    """
    from scipy.stats import f

    real = _check_curve("real", real)
    twin = _check_curve("twin", twin)
    if real.kind != twin.kind:
        raise ValueError(f"twin.kind must equal real.kind {real.kind!r}; got {twin.kind!r}")
    if isinstance(family_alpha, bool) or not isinstance(family_alpha, (int, float)):
        raise TypeError(f"family_alpha must be a number in (0, 1); got {family_alpha!r}")
    if not 0.0 < float(family_alpha) < 1.0:
        raise ValueError(f"family_alpha must be in (0, 1); got {family_alpha!r}")
    if real.tau.shape != twin.tau.shape or not np.allclose(real.tau, twin.tau, rtol=1e-9, atol=0.0):
        raise ValueError("twin must have the real curve's taus (simulate the same length at the same rate)")
    want = np.asarray(real.tau if taus is None else taus, dtype=float).reshape(-1)
    if want.size == 0:
        raise ValueError("taus must name at least one cluster time [s]; got none")
    idx = []
    for t in want:
        hit = np.flatnonzero(np.isclose(real.tau, t, rtol=1e-9, atol=0.0))
        if hit.size == 0:
            raise ValueError(f"taus: {t!r} s is not a tau of the curves")
        idx.append(int(hit[0]))
    i = np.asarray(idx)
    m = len(i)
    a = 1.0 - (1.0 - float(family_alpha)) ** (1.0 / (m + int(extra_tests)))
    nu_r = np.asarray(real.edf, dtype=float)[i]
    nu_t = np.asarray(twin.edf, dtype=float)[i]
    r_dev = np.asarray(real.deviation, dtype=float)[i]
    t_dev = np.asarray(twin.deviation, dtype=float)[i]
    lo = np.sqrt(f.ppf(a / 2, nu_t, nu_r))
    hi = np.sqrt(f.ppf(1 - a / 2, nu_t, nu_r))
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(r_dev > 0, t_dev / r_dev, math.inf)
    real_lo, real_hi = deviation_bounds(r_dev, nu_r, 0.95)
    inside = (ratio >= lo) & (ratio <= hi) & (ratio >= 1.0 / max_ratio) & (ratio <= max_ratio)
    return TwinComparison(
        tau=np.asarray(real.tau, dtype=float)[i],
        real=r_dev,
        real_low95=real_lo,
        real_high95=real_hi,
        twin=t_dev,
        edf_real=nu_r,
        edf_twin=nu_t,
        ratio=ratio,
        ratio_low=lo,
        ratio_high=hi,
        inside=inside,
        inside_real95=(t_dev >= real_lo) & (t_dev <= real_hi),
        family_alpha=float(family_alpha),
        per_tau_alpha=a,
        max_ratio=float(max_ratio),
    )


@dataclass(frozen=True, slots=True, kw_only=True)
class SampleComparison:
    """The sample distributions of a real record and its twin (:func:`compare_samples`).

    Attributes
    ----------
    real_mean, twin_mean, real_std, twin_std : float
        Sample means and standard deviations [rate unit].
    real_range, twin_range : tuple of float
        (min, max) of the samples [rate unit].
    std_ratio : float
        twin_std / real_std.
    band : tuple of float
        The band of ``std_ratio`` for a perfect twin: sqrt of the F(edf, edf) quantiles at the
        per-test level (two-sided).
    edf : float
        Degrees of freedom assigned to each sample variance.
    passed : bool
        ``std_ratio`` inside ``band``.
    """

    real_mean: float
    twin_mean: float
    real_std: float
    twin_std: float
    real_range: tuple[float, float]
    twin_range: tuple[float, float]
    std_ratio: float
    band: tuple[float, float]
    edf: float
    passed: bool


def compare_samples(real: ArrayLike, twin: ArrayLike, *, edf: float, level: float) -> SampleComparison:
    """Compare the spread of a twin's samples with the real record's: F test of the two sample variances.

    Parameters
    ----------
    real, twin : array_like
        The samples [rate unit] (the same length).
    edf : float
        Degrees of freedom of each sample variance (> 0); the samples are correlated (filter,
        flicker, random walk), so not n - 1: :func:`sample_variance_edf` of the real curve.
    level : float
        Two-sided level of the test in (0, 1) (the twin rule's per-tau level).

    Returns
    -------
    SampleComparison
        Means and ranges are reported, not tested (the twin carries the real mean as its bias).
    """
    from scipy.stats import f

    r = np.asarray(real, dtype=float)
    t = np.asarray(twin, dtype=float)
    if not (edf > 0) or not (0.0 < level < 1.0):
        raise ValueError(f"edf must be > 0 and level in (0, 1); got edf={edf!r}, level={level!r}")
    rs, ts = float(np.std(r)), float(np.std(t))
    ratio = ts / rs if rs > 0 else math.inf
    lo = math.sqrt(float(f.ppf(level / 2, edf, edf)))
    hi = math.sqrt(float(f.ppf(1 - level / 2, edf, edf)))
    return SampleComparison(real_mean=float(np.mean(r)), twin_mean=float(np.mean(t)), real_std=rs, twin_std=ts,
                            real_range=(float(r.min()), float(r.max())), twin_range=(float(t.min()), float(t.max())),
                            std_ratio=ratio, band=(lo, hi), edf=float(edf), passed=bool(lo <= ratio <= hi))


def sample_variance_edf(curve: AllanCurve) -> float:
    """Satterthwaite degrees of freedom of a record's sample variance, from its octave Allan curve.

    The sample variance of 2^J samples is the sum over the octave scales tau_j = 2^(j-1) / fs of
    the Haar wavelet variances, each half the Allan variance at tau_j (the energy decomposition of
    the Haar DWT: D. B. Percival and A. T. Walden, "Wavelet Methods for Time Series Analysis",
    2000, sec. 4.3 and 8.1; AVAR = 2 x Haar wavelet variance). With c_j = AVAR(tau_j) / 2 and
    nu_j the edf of that Allan point, the sum has nu = (sum c_j)^2 / sum (c_j^2 / nu_j)
    (Satterthwaite 1946): long-tau wander (few edf) makes it small, fast noise large.

    Parameters
    ----------
    curve : AllanCurve
        The record's Allan curve (its octave points are used).

    Returns
    -------
    float
        nu, the Satterthwaite edf of the sample variance (1 when no octave point has variance).
    """
    m = curve.m
    octave = (m & (m - 1)) == 0
    c = np.asarray(curve.variance, dtype=float)[octave] / 2.0
    nu = np.maximum(np.asarray(curve.edf, dtype=float)[octave], 1e-9)
    if c.size == 0 or not np.any(c > 0):
        return 1.0
    return float(c.sum() ** 2 / np.sum(c**2 / nu))
