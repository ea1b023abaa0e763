"""Allan-family deviations of rate data, their confidence bounds, and the IEEE 952 noise fit.

Everything here works on plain arrays of rate samples in any unit ``u`` (deg/s, rad/s,
fractional frequency, ...) taken at ``fs`` [Hz]; results come out in the units implied by
the input. With tau in seconds the fitted IEEE Std 952 coefficients are

====  ==========================  ========  =====================
name  term                        unit      AVAR term
====  ==========================  ========  =====================
Q     quantization                u*s       3 Q^2 / tau^2
N     angle random walk           u*s^0.5   N^2 / tau
B     bias instability            u         (2 ln2/pi) B^2
K     rate random walk            u/s^0.5   K^2 tau / 3
R     rate ramp                   u/s       R^2 tau^2 / 2
====  ==========================  ========  =====================

(so rate in rad/s gives Q in rad, N in rad/sqrt(s), B in rad/s, K in rad/s/sqrt(s),
R in rad/s^2; conversion to field units happens at the edges, see :mod:`gyrobench.base.units`).

Three layers:

* :func:`allan_deviation` -> :class:`AllanCurve`: overlapping (default), standard
  (non-overlapping), modified, Hadamard, overlapping Hadamard and total deviation with
  confidence bounds from the equivalent degrees of freedom (edf).
* :func:`fit_noise` -> :class:`NoiseFit`: joint weighted non-negative least squares of the
  five IEEE terms on the Allan variance, each coefficient with 68 % and 95 % intervals or
  "not identifiable from this record" with a 95 % upper bound.
* :func:`slope_readoff`: the IEEE 952 graphical method (and the fixed-slope line fits used
  in the literature), for comparison with published numbers.

The package's modules (private; everything public is imported from here):

* ``_terms``: one record per IEEE term (power of tau, AVAR scale, noise type);
* ``_kinds``: one record per statistic (:data:`KINDS`): its estimator, term count, tau
  limits, edf and, for the Allan variances, the fit's constants;
* ``_octave``, ``_noise_id``, ``_edf``, ``_taus``, ``_curve``: the curve (octave core,
  noise identification, degrees of freedom, tau lists, :func:`allan_deviation`);
* ``_covariance``, ``_window``, ``_nnls``, ``_goodness``, ``_fit``: the fit (point
  covariance, fit range, NNLS, goodness of fit, :func:`fit_noise`);
* ``_readoff``: :func:`slope_readoff`; ``_results``: the result dataclasses; ``_blas``:
  BLAS threading; ``_checks``: input checks; ``_rho_table``: the stored correlation table.

References
----------
IEEE Std 952-1997, Annex C. W. J. Riley, "Handbook of Frequency Stability Analysis",
NIST SP 1065 (2008). C. A. Greenhall and W. J. Riley, "Uncertainty of stability variances
based on finite differences", PTTI 2003. W. J. Riley and C. A. Greenhall, "Power law noise
identification using the lag 1 autocorrelation", EFTF 2004. A. Wallin et al., allantools.
docs/physics.md section 1.
"""

from __future__ import annotations

from gyrobench.analysis.allan._covariance import QUANTIZATION_KURTOSIS
from gyrobench.analysis.allan._curve import allan_deviation, deviation_bounds, identify_noise
from gyrobench.analysis.allan._fit import MISFIT_P, fit_noise
from gyrobench.analysis.allan._gaps import allan_deviation_gaps as allan_deviation_gaps  # records with gaps
from gyrobench.analysis.allan._kinds import _FIT_KINDS as _FIT_KINDS  # (allan_report pins its copy to it)
from gyrobench.analysis.allan._kinds import KINDS
from gyrobench.analysis.allan._readoff import slope_readoff
from gyrobench.analysis.allan._results import AllanCurve, Coefficient, FitRange, NoiseFit
from gyrobench.analysis.allan._segments import HalvesPair, floor_bounds, halves_agreement, pool_curves
from gyrobench.analysis.allan._taus import TAU_CHOICES
from gyrobench.analysis.allan._terms import _POWER as _POWER  # (read by tests/analysis/test_validation.py)
from gyrobench.analysis.allan._terms import FLICKER_FLOOR as FLICKER_FLOOR
from gyrobench.analysis.allan._terms import TERMS, avar_to_coefficient, coefficient_to_avar
from gyrobench.analysis.allan._window import BANDWIDTH_BIAS, bandwidth_range, fit_range, lowpass_avar_bias

# allantools, scipy and threadpoolctl are imported where they are used: importing this package
# (and so ``gyrobench allan --help`` or ``gyrobench list``) costs numpy only

__all__ = [
    "KINDS",
    "TAU_CHOICES",
    "TERMS",
    "AllanCurve",
    "Coefficient",
    "FitRange",
    "HalvesPair",
    "NoiseFit",
    "fit_range",
    "bandwidth_range",
    "BANDWIDTH_BIAS",
    "QUANTIZATION_KURTOSIS",
    "lowpass_avar_bias",
    "allan_deviation",
    "fit_noise",
    "MISFIT_P",
    "floor_bounds",
    "halves_agreement",
    "deviation_bounds",
    "pool_curves",
    "identify_noise",
    "slope_readoff",
    "avar_to_coefficient",
    "coefficient_to_avar",
]
