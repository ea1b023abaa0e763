"""Closed-form checks of the IEEE-952 noise model (:mod:`gyrobench.sim.noise`).

One record per term (Q, N, B, K, R) is generated alone, and its overlapping Allan
variance (allantools, an estimator independent of the model) at one cluster time,
where the estimate has many degrees of freedom, is set beside the term's closed form
(IEEE Std 952-1997, Annex C):

    Q: 3 Q^2 / tau^2        N: N^2 / tau        K: K^2 tau / 3 (1 + 1/(2 m^2))
    B: flicker (PSD B^2/(2 pi f)) over the generated band f_low..fs/2 (brick-wall
       integral, :func:`gyrobench.sim.noise.flicker_avar`); plateau (2 ln 2/pi) B^2
    R: R^2 tau^2 / 2 (deterministic)

Tolerances. The overlapping AVAR estimate A at ``m`` samples per cluster satisfies
A ~ A_true chi2(edf)/edf, edf from Greenhall's algorithm (allantools.edf_greenhall;
NIST SP 1065 sec. 5.3) for the term's power-law type. The tolerance on
|A/A_true - 1| is the wider side of the two-sided chi-square band at a false-alarm
rate of 1e-6 per check. The flicker term is realised as a pole sum whose ADEV ripple
is documented within +-1 % (AVAR +-2 %), so 0.02 is added to its band. The ramp is
deterministic: its tolerance is the float64 cancellation bound of the second
difference of the cumulated phase.
"""

from __future__ import annotations

import math

import numpy as np

from gyrobench.scenarios.checks.core import CLOSED_FORM, Check

__all__ = ["checks", "FALSE_ALARM"]

#: false-alarm rate of each statistical check
FALSE_ALARM = 1e-6
#: where every noise check's closed form and its degrees of freedom come from
_REFERENCE = (
    "IEEE Std 952-1997, Annex C (Allan variance of each noise term); equivalent dof: Greenhall's "
    "algorithm as in W. J. Riley, Handbook of Frequency Stability Analysis, NIST SP 1065 (2008), sec. 5.3"
)
_FS = 100.0
_N = 1 << 18
#: term -> (datasheet keyword, value, samples per cluster m, power-law alpha for the edf, formula)
_TERMS = {
    "Q": ("quantization", 0.5, 1, 2, "AVAR = 3 Q^2 / tau^2 [rad^2/s^2], Q [rad]"),
    "N": ("angle_random_walk", 0.05, 1, 0, "AVAR = N^2 / tau [rad^2/s^2], N [rad/sqrt(s)]"),
    "B": (
        "bias_instability",
        0.5,
        16,
        -1,
        "AVAR = (2 B^2/pi) Int_{f_low}^{fs/2} sin^4(pi f tau)/(pi f tau)^2 df/f "
        "[rad^2/s^2] (plateau (2 ln 2/pi) B^2), B [rad/s]",
    ),
    "K": (
        "rate_random_walk",
        2.0,
        256,
        -2,
        "AVAR = K^2 tau/3 (1 + 1/(2 m^2)) [rad^2/s^2], K [rad/s/sqrt(s)]",
    ),
    "R": ("rate_ramp", 1.0, 256, None, "AVAR = R^2 tau^2 / 2 [rad^2/s^2], R [rad/s^2]"),
}


def _theory(term: str, model, tau: float) -> float:
    from gyrobench.sim.noise import flicker_avar

    m = tau * _FS
    if term == "Q":
        return 3.0 * model.quantization**2 / tau**2
    if term == "N":
        return model.angle_random_walk**2 / tau
    if term == "B":
        lo, hi = model.effective_flicker_band(_FS)
        return float(flicker_avar(np.array([tau]), model.bias_instability, lo, hi)[0])
    if term == "K":
        return model.rate_random_walk**2 * tau / 3.0 * (1.0 + 0.5 / m**2)
    return model.rate_ramp**2 * tau**2 / 2.0


def _tolerance(term: str, m: int, alpha: int | None) -> tuple[float, str]:
    import allantools
    from scipy import stats

    if alpha is None:
        ratio = (_N / m) ** 2
        tol = 10.0 * float(np.finfo(float).eps) * ratio * math.sqrt(_N)
        return tol, (
            f"deterministic: float64 cancellation in the second difference of the cumulated phase, "
            f"10 eps (T/tau)^2 sqrt(n) = {tol:.2g} (T/tau = {_N // m}, n = {_N})"
        )
    edf = float(allantools.edf_greenhall(alpha=alpha, d=2, m=m, N=_N + 1, overlapping=True))
    lo, hi = (float(q) / edf for q in stats.chi2.ppf([FALSE_ALARM / 2, 1 - FALSE_ALARM / 2], edf))
    tol = max(1.0 - lo, hi - 1.0)
    text = (
        f"chi-square band of the overlapping AVAR at false-alarm {FALSE_ALARM:g}: edf {edf:.0f} "
        f"(Greenhall, alpha {alpha}, m {m}, n {_N}) -> [{lo:.4f}, {hi:.4f}], wider side {tol:.4f}"
    )
    if term == "B":
        tol += 0.02
        text += "; + 0.02 for the pole-sum realisation of 1/f (ADEV ripple <= 1 %)"
    return tol, text


def checks(rng: np.random.Generator) -> list[Check]:
    """One AVAR check per IEEE-952 term (2^18 samples at 100 Hz each, ~0.1 s per term)."""
    import allantools

    from gyrobench.sim.noise import NoiseModel

    out = []
    for (term, (key, value, m, alpha, formula)), child in zip(
        _TERMS.items(), rng.spawn(len(_TERMS)), strict=True
    ):
        model = NoiseModel.from_datasheet(**{key: value})
        y = model.generate(_N, _FS, rng=child)
        tau = m / _FS
        t, adev, _, _ = allantools.oadev(y, rate=_FS, data_type="freq", taus=np.array([tau]))
        tol, derivation = _tolerance(term, m, alpha)
        out.append(
            Check(
                id=f"noise.avar_{term}",
                kind=CLOSED_FORM,
                reference=_REFERENCE,
                formula=f"{formula}; tau = {tau:g} s at fs = {_FS:g} Hz",
                expected=_theory(term, model, float(t[0])),
                simulated=float(adev[0]) ** 2,
                tolerance=tol,
                derivation=derivation,
            )
        )
    return out
