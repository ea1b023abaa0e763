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

__all__ = ["TwinComparison", "compare_twin", "FAMILY_ALPHA"]

FAMILY_ALPHA = 0.05
"""Default family-wise false-alarm rate of the pass rule (a perfect twin fails at most this often)."""


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
    passed : bool
        ``inside`` at every compared tau.
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

    @property
    def passed(self) -> bool:
        """The pass rule: the ratio lies in its band at every compared tau."""
        return bool(np.all(self.inside))

    @property
    def n_taus(self) -> int:
        """Number of compared taus m."""
        return int(len(self.tau))

    @property
    def rule(self) -> str:
        """The pass rule in one line."""
        return (f"pass when twin/real ADEV lies in its F(edf_twin, edf_real) band at all {self.n_taus} fitted taus; "
                f"Sidak per-tau level {self.per_tau_alpha:.4g}, family-wise false-alarm rate "
                f"<= {self.family_alpha:g} for a perfect twin")


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
    a = 1.0 - (1.0 - float(family_alpha)) ** (1.0 / m)
    nu_r = np.asarray(real.edf, dtype=float)[i]
    nu_t = np.asarray(twin.edf, dtype=float)[i]
    r_dev = np.asarray(real.deviation, dtype=float)[i]
    t_dev = np.asarray(twin.deviation, dtype=float)[i]
    lo = np.sqrt(f.ppf(a / 2, nu_t, nu_r))
    hi = np.sqrt(f.ppf(1 - a / 2, nu_t, nu_r))
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(r_dev > 0, t_dev / r_dev, math.inf)
    real_lo, real_hi = deviation_bounds(r_dev, nu_r, 0.95)
    inside = (ratio >= lo) & (ratio <= hi)
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
    )
