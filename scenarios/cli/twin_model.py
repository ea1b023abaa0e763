"""The digital twin of a real static gyro record that ``gyrobench twin`` builds and judges.

The record's noise is fitted (:func:`gyrobench.analysis.allan.fit_noise`); the fitted
Allan-variance model sum_n C_n tau^n becomes a :class:`gyrobench.sim.noise.NoiseModel`
(:func:`noise_model_from_fit`; C_n to Q, N, B, K, R, IEEE 952), or a built-in part's model is
used (:func:`nearest_part`); a record of the same length and rate is simulated and the two curves
are compared by :func:`gyrobench.analysis.twin.compare_twin` (:func:`make_twin`). The verb itself
(flags, outputs, the part file) is :mod:`gyrobench.scenarios.cli.twin`. The twin lives in the top
layer: it needs both ``sim`` and ``analysis``, which never import each other.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from gyrobench.scenarios.cli.common import BadInput

if TYPE_CHECKING:  # the verb imports numpy, analysis and sim only when it runs (``--help`` stays light)
    import numpy as np
    from numpy.typing import NDArray

    from gyrobench.analysis.allan import NoiseFit
    from gyrobench.analysis.record import RecordAnalysis
    from gyrobench.analysis.twin import SampleComparison, TwinComparison
    from gyrobench.io.recording import Recording
    from gyrobench.sim.noise import NoiseModel
    from gyrobench.sim.parts import Part

__all__ = [
    "NonStationaryRecord",
    "TwinResult",
    "gauss_markov_term",
    "make_twin",
    "nearest_part",
    "noise_model_from_fit",
]

_FIELDS = {"Q": "quantization", "N": "angle_random_walk", "B": "bias_instability", "K": "rate_random_walk",
           "R": "rate_ramp"}


@dataclass(frozen=True, slots=True, kw_only=True)
class TwinResult:
    """A twin and its comparison with the real record.

    Attributes
    ----------
    fit : NoiseFit
        The real record's noise fit (rad/s in, SI coefficients), from the shared analysis.
    model : str
        "fit" (the fitted model, with any chosen terms named) or the name of the built-in part used.
    coefficients : dict of str to float
        The twin's IEEE coefficients [SI: Q rad, N rad/sqrt(s), B rad/s, K rad/s/sqrt(s), R rad/s^2],
        and the extra terms' parameters (``gm_sigma``, ``gm_correlation_time``, ``sine_amplitude``,
        ``sine_period``, ``lowpass_corner``, ``lowpass_order``, ``lowpass_passes``, ``bias``).
    recording : Recording
        The twin: channel ``output`` [rad/s], truth ``true_rate`` (0) and its noise terms.
    comparison : TwinComparison
        Per-tau test at every tau of the analysed curve.
    samples : SampleComparison or None
        The sample spread, range and mean against the real record's (None for a part's model).
    analysis : RecordAnalysis
        The shared analysis of the real record (verdict, basis, model choice).
    """

    fit: NoiseFit
    model: str
    coefficients: dict[str, float]
    recording: Recording
    comparison: TwinComparison
    samples: SampleComparison | None = None
    analysis: RecordAnalysis | None = None

    @property
    def passed(self) -> bool:
        """The Allan deviation matches at every compared tau and the sample spread matches."""
        return self.comparison.passed and (self.samples is None or self.samples.passed)


class NonStationaryRecord(Exception):
    """The record is not stationary and its quiet stretches hold too few taus to build a twin from."""


def noise_model_from_fit(fit: NoiseFit) -> NoiseModel:
    """The :class:`NoiseModel` whose Allan variance is the fit's model sum_n C_n tau^n (C_n -> Q, N, B, K, R).

    Parameters
    ----------
    fit : NoiseFit
        A noise fit.

    Returns
    -------
    NoiseModel
        Its IEEE 952 model (a term the fit set to 0 is 0).
    """
    from gyrobench.analysis.allan import avar_to_coefficient
    from gyrobench.sim.noise import NoiseModel

    c = {k: avar_to_coefficient(k, fit.avar_coefficients.get(k, 0.0)) for k in _FIELDS}
    return NoiseModel(quantization=c["Q"], angle_random_walk=c["N"], bias_instability=c["B"],
                      rate_random_walk=c["K"], rate_ramp=c["R"])


def gauss_markov_term(fit: NoiseFit, *, level: float = 0.05) -> tuple[NDArray[np.float64], float, float] | None:
    """A first-order Gauss-Markov term added to the fitted model where the curve needs one, or None.

    Only for a misfit (``fit.misfit``: the five power laws do not follow the fitted points).
    The model A(tau) = sum_n C_n tau^n + sigma^2 g(tau/Tc)/(tau/Tc)^2
    (:func:`gyrobench.sim.noise.gm_avar`, docs/physics.md 1.2) is fitted to the fitted points
    by non-negative least squares in (C_n, sigma^2) for each Tc on a log grid over the fitted
    taus, each point weighted by its chi-square standard error A_fit sqrt(2/edf) (diagonal:
    the points' correlation is ignored, so the test below is approximate). The term is kept
    when the weighted residual sum drops by more than the chi2(2) quantile at 1 - ``level``
    (two added parameters). Returns (C_n in the order Q, N, B, K, R, sigma [rad/s], Tc [s]).

    Parameters
    ----------
    fit : NoiseFit
        The record's noise fit.
    level : float
        False-alarm rate of the test that keeps the term.

    Returns
    -------
    tuple of (ndarray, float, float) or None
        (the power-law coefficients C_n refitted with it, sigma^2, Tc [s]); None when the fit
        needs no Gauss-Markov term.
    """
    import numpy as np
    from scipy.optimize import nnls
    from scipy.stats import chi2

    from gyrobench.sim.noise import gm_avar

    if not fit.misfit:
        return None
    used = fit.used
    tau = np.asarray(fit.curve.tau, dtype=float)[used]
    a = np.asarray(fit.curve.deviation, dtype=float)[used] ** 2
    nu = np.asarray(fit.curve.edf, dtype=float)[used]
    if len(tau) < 8:
        return None
    powers = {"Q": -2, "N": -1, "B": 0, "K": 1, "R": 2}
    w = 1.0 / (np.maximum(fit.avar(tau), 1e-300) * np.sqrt(2.0 / nu))
    base = np.column_stack([tau ** p for p in powers.values()])
    _, r0 = nnls(base * w[:, None], a * w)
    best: tuple[float, NDArray[np.float64], float] | None = None
    for tc in np.geomspace(tau[0], tau[-1], 48):
        x = np.column_stack([base, gm_avar(tau, 1.0, float(tc))])
        coef, r = nnls(x * w[:, None], a * w)
        if coef[-1] > 0 and (best is None or r < best[0]):
            best = (float(r), coef, float(tc))
    if best is None or r0**2 - best[0] ** 2 <= chi2.ppf(1 - level, 2):
        return None
    _, coef, tc = best
    return coef[:5], float(np.sqrt(coef[5])), tc


def nearest_part(fit: NoiseFit, technology: str) -> Part:
    """The built-in part of ``technology`` whose (N, B) are nearest the fit's in log distance.

    The distance is sqrt(ln(N_part/N_fit)^2 + ln(B_part/B_fit)^2) with the fit's model
    coefficients (a term the fit set to 0 is taken at its 95 % upper bound).

    Parameters
    ----------
    fit : NoiseFit
        The record's noise fit.
    technology : str
        The technology of the built-in parts considered.

    Returns
    -------
    Part
        The nearest part.
    """
    from gyrobench.analysis.allan import avar_to_coefficient
    from gyrobench.sim import parts

    def level(key: str) -> float:
        v = avar_to_coefficient(key, fit.avar_coefficients.get(key, 0.0))
        return v if v > 0 else max(fit.coefficients[key].upper_bound, 1e-300)

    n_fit, b_fit = level("N"), level("B")
    # a part without a bias-instability figure has B = 0: no log distance, not a candidate
    cands = [d for d in parts.datasheets() if d.technology == technology and d.bias_instability_dph is not None]
    if not cands:
        raise BadInput(f"--nearest must be one of {parts.TECHNOLOGIES}; got {technology!r}")
    best = min(cands, key=lambda d: math.hypot(math.log(d.angle_random_walk() / n_fit),
                                               math.log(d.bias_instability() / b_fit)))
    return parts.get(best.name)


def _fit_recording(model, n: int, fs: float, rng, *, source: str, fit_meta: dict):
    import numpy as np

    from gyrobench.io.recording import Channel, Recording

    comps = model.components(n, fs, rng=rng)
    out = np.sum(list(comps.values()), axis=0) if comps else np.zeros(n)
    truth = {"true_rate": Channel(np.zeros(n), "rad/s", "input rate (static record)")}
    truth.update({k: Channel(v, "rad/s", f"IEEE 952 term {k}") for k, v in comps.items()})
    return Recording(fs=fs, channels={"output": Channel(out, "rad/s", "twin output")}, truth=truth, t0=0.5 / fs,
                     metadata={"model": "gyrobench twin (fitted NoiseModel)", "source": source,
                               "noise_model": model.to_datasheet(), "fit": fit_meta,
                               "error_components": list(comps), "ignored_inputs": []},
                     name="twin")


def _fitted_model(ra: RecordAnalysis, rate: NDArray[np.float64], gauss_markov: bool):
    """The twin's NoiseModel, its low-pass (order, corner, passes) or None, its label and coefficients.

    From the shared analysis: the IEEE terms of the chosen model, its Gauss-Markov and sinusoid
    terms, its low-pass (white noise N through it; N from the fit over the bent taus), and the
    fitted samples' mean as the constant bias.
    """
    import numpy as np

    from gyrobench.analysis.allan import avar_to_coefficient
    from gyrobench.sim.noise import GaussMarkov, NoiseModel, Sinusoid

    fit = ra.fit
    assert fit is not None  # make_twin refuses a record without a fit
    m = ra.model
    cn = dict(fit.avar_coefficients) if m is None or not m.extra else {**fit.avar_coefficients, **m.avar_coefficients}
    c = {k: avar_to_coefficient(k, float(cn.get(k, 0.0))) for k in _FIELDS}
    spans = ra.fitted_stretches
    bias = float(np.mean(rate if spans is None else np.concatenate([rate[a:b] for a, b in spans])))
    gm: tuple[GaussMarkov, ...] = ()
    sines: tuple[Sinusoid, ...] = ()
    lowpass: tuple[int, float, int] | None = None
    names: list[str] = []
    coeffs = dict(c)
    if m is not None:
        amp: dict[str, float] = {}
        g = m.term("gauss_markov") if gauss_markov else None
        if g is not None:
            sig = amp.get("amp_gauss_markov", g.params["sigma"])  # refitted with the low-pass over the bent taus
            gm = (GaussMarkov(sigma=sig, correlation_time=g.params["tc"]),)
            coeffs.update(gm_sigma=sig, gm_correlation_time=g.params["tc"])
            names.append("Gauss-Markov")
        sn = m.term("sinusoid")
        if sn is not None:
            amp_s = amp.get("amp_sinusoid", sn.params["amplitude"])
            sines = (Sinusoid(amplitude=amp_s, frequency=1.0 / sn.params["period"]),)
            coeffs.update(sine_amplitude=amp_s, sine_period=sn.params["period"])
            names.append("sinusoid")
        lp = m.term("lowpass")
        if lp is not None:
            lowpass = (int(lp.params["order"]), float(lp.params["corner"]), int(lp.params["passes"]))
            c["N"] = coeffs["N"] = float(lp.params["N"])
            if "C_Q" in lp.params:  # quantization after the filter, fitted with it over the bent taus
                c["Q"] = coeffs["Q"] = avar_to_coefficient("Q", float(lp.params["C_Q"]))
            coeffs.update(lowpass_order=lowpass[0], lowpass_corner=lowpass[1], lowpass_passes=lowpass[2])
            names.append("low-pass")
    coeffs["bias"] = bias
    model = NoiseModel(quantization=c["Q"], angle_random_walk=0.0 if lowpass else c["N"], bias_instability=c["B"],
                       rate_random_walk=c["K"], rate_ramp=c["R"], gauss_markov=gm, sinusoids=sines, bias=bias)
    label = "fit" + "".join(f" + {n}" for n in names)
    return model, lowpass, label, coeffs, c["N"]


def _lowpassed_white(n: int, fs: float, n_coef: float, lowpass: tuple[int, float, int], rng) -> NDArray[np.float64]:
    """White rate noise of N [rad/sqrt(s)] through the Butterworth (order, corner [Hz], passes)."""
    import numpy as np
    from scipy.signal import butter, sosfilt, sosfiltfilt

    order, corner, passes = lowpass
    sos = butter(order, corner / (fs / 2.0), output="sos")
    pad = min(n, int(20 * fs / corner) + 1)  # settle the filter on a run-in, then drop it
    w = rng.standard_normal(n + 2 * pad) * n_coef * math.sqrt(fs)
    y = sosfiltfilt(sos, w) if passes == 2 else sosfilt(sos, w)
    return np.asarray(y[pad : pad + n])


def make_twin(rate: NDArray[np.float64], fs: float, *, rng: np.random.Generator, source: str = "",
              part: str | None = None, nearest: str | None = None, family_alpha: float = 0.05,
              gauss_markov: bool = True, analysis: RecordAnalysis | None = None) -> TwinResult:
    """Analyse ``rate`` [rad/s] at ``fs`` [Hz] as ``allan`` does, simulate its twin from ``rng`` and compare.

    The analysis is :func:`gyrobench.analysis.record.analyse_record` (the verdict, the quiet
    stretches of a non-stationary record, the fit range and the chosen terms), or ``analysis``
    when given. The twin carries the chosen model: the IEEE terms, any Gauss-Markov, sinusoid and
    low-pass terms and the constant bias. It is judged at every tau of the analysed curve (the
    quiet stretches' curve, computed on the twin with the same windows left out, for a
    non-stationary record), and its sample spread is compared too (:func:`compare_samples`).
    ``part`` (a built-in name or .toml) or ``nearest`` (a technology) replaces the fitted model
    by a part's datasheet model.

    Parameters
    ----------
    rate : ndarray
        The real record [rad/s].
    fs : float
        Its sample rate [Hz].
    rng : numpy.random.Generator
        The twin's stream.
    source : str
        The record's name, for the result.
    part : str or None
        A built-in part to compare with (its noise model simulated too).
    nearest : str or None
        A technology: compare with its built-in part nearest the fit (:func:`nearest_part`).
    family_alpha : float
        Family-wise false-alarm rate of the comparison.
    gauss_markov : bool
        Add a Gauss-Markov term where the fit needs one (:func:`gauss_markov_term`).
    analysis : RecordAnalysis or None
        The record's analysis, when already made.

    Returns
    -------
    TwinResult
        The analysis, the twin's model, its record and the comparisons.

    Raises
    ------
    NonStationaryRecord
        The record is not stationary and its quiet stretches could not be analysed.
    """
    import numpy as np

    from gyrobench.analysis.allan import allan_deviation
    from gyrobench.analysis.quiet import quiet_curve
    from gyrobench.analysis.record import analyse_record, octave_subset
    from gyrobench.analysis.twin import compare_samples, compare_twin, sample_variance_edf
    from gyrobench.sim import parts as parts_mod
    from gyrobench.sim.sensor import Environment

    rate = np.asarray(rate, dtype=float)
    n = len(rate)
    ra = analysis if analysis is not None else analyse_record(rate, fs)
    if ra.nonstationary and ra.basis != "quiet stretches":
        raise NonStationaryRecord(
            "the record is not stationary (motion or steps) and its quiet stretches hold too few taus for a fit: "
            "no twin is built (analyse a quiet stretch with gyrobench allan --start/--stop)")
    fit = ra.fit
    if fit is None:
        raise ValueError(f"no noise fit for this record: {ra.no_fit}")
    fit_meta = {k: {"value": c.value, "ci95": list(c.ci95), "identifiable": c.identifiable}
                for k, c in fit.coefficients.items()}
    samples = None
    if part is not None or nearest is not None:
        p = parts_mod.get(part) if part is not None else nearest_part(fit, str(nearest))
        rec = p.simulate(Environment(n / fs), fs=fs, rng=rng)
        nm = p.datasheet.noise_model()
        coeffs = {k: float(getattr(nm, f)) for k, f in _FIELDS.items()}
        label = p.name
        out = np.asarray(rec["output"], dtype=float)
    else:
        model, lowpass, label, coeffs, n_coef = _fitted_model(ra, rate, gauss_markov)
        comps = model.components(n, fs, rng=rng)
        if lowpass is not None:
            comps["angle_random_walk"] = _lowpassed_white(n, fs, n_coef, lowpass, rng)
        if model.bias:
            comps.setdefault("bias", np.full(n, model.bias))
        rec = _twin_recording(comps, n, fs, source=source, fit_meta=fit_meta, datasheet=model.to_datasheet())
        out = np.asarray(rec["output"], dtype=float)
    if ra.basis == "quiet stretches" and ra.stationarity is not None and ra.quiet is not None:
        qt = quiet_curve(out, fs, ra.stationarity)
        twin_curve = qt.curve if qt is not None else None
        real_samples = np.concatenate([rate[a:b] for a, b in ra.quiet.stretches])
        twin_samples = np.concatenate([out[a:b] for a, b in ra.quiet.stretches])
    else:
        twin_curve = allan_deviation(out, fs, kind=fit.curve.kind, taus="octave")
        twin_curve = octave_subset(twin_curve)
        real_samples, twin_samples = rate, out
    real_curve = ra.fit_curve
    if twin_curve is None or twin_curve.tau.shape != real_curve.tau.shape:
        raise NonStationaryRecord("the twin's quiet-stretch curve does not hold the real curve's taus")
    cmp = compare_twin(real_curve, twin_curve, family_alpha=family_alpha, extra_tests=1)
    if part is None and nearest is None:
        samples = compare_samples(real_samples, twin_samples, edf=sample_variance_edf(real_curve),
                                  level=cmp.per_tau_alpha)
    return TwinResult(fit=fit, model=label, coefficients=coeffs, recording=rec, comparison=cmp, samples=samples,
                      analysis=ra)


def _twin_recording(comps: dict, n: int, fs: float, *, source: str, fit_meta: dict, datasheet: dict):
    import numpy as np

    from gyrobench.io.recording import Channel, Recording

    out = np.sum(list(comps.values()), axis=0) if comps else np.zeros(n)
    truth = {"true_rate": Channel(np.zeros(n), "rad/s", "input rate (static record)")}
    truth.update({k: Channel(np.asarray(v, dtype=float), "rad/s", f"twin term {k}") for k, v in comps.items()})
    return Recording(fs=fs, channels={"output": Channel(out, "rad/s", "twin output")}, truth=truth, t0=0.5 / fs,
                     metadata={"model": "gyrobench twin (fitted model)", "source": source,
                               "noise_model": datasheet, "fit": fit_meta,
                               "error_components": list(comps), "ignored_inputs": []},
                     name="twin")
