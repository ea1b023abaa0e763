"""``gyrobench twin``: a digital twin of a real static gyro record, and whether its Allan deviation matches.

::

    gyrobench twin REAL.csv --column gyro_z [--fs HZ] [--units deg/s] -o twin.h5|twin.csv [--seed S]
                   [--part NAME | --nearest MEMS|FOG|RLG] [--alpha 0.05] [--json] [--plot twin.png]
                   [--save-part FILE.toml [--technology MEMS|FOG|RLG]]

The real record's noise is fitted (:func:`gyrobench.analysis.allan.fit_noise`, the five IEEE
952 terms, ``tau_min="auto"``); the fitted Allan-variance model sum_n C_n tau^n becomes a
:class:`gyrobench.sim.noise.NoiseModel` (each C_n to its coefficient, Q, N, B, K, R), or with
``--part`` / ``--nearest`` a built-in part's model is used instead; a record of the same
length and rate is simulated and the two curves are compared at the fitted taus by
:func:`gyrobench.analysis.twin.compare_twin`: the pass rule is an F test of the two
independent Allan-variance estimates per tau with Sidak's correction, a family-wise
false-alarm rate of ``--alpha`` (a perfect twin fails at most that often). ``--save-part``
writes the fitted model as a part file (:func:`part_fields`) that ``simulate device`` runs. The twin
lives here, not in ``sim`` or ``analysis``: it needs both, which never import each other.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from gyrobench.scenarios.cli.common import (
    MAX_FLAG_VALUE,
    BadInput,
    add_force,
    check_outputs,
    input_file,
    positive_float,
    seed,
)

if TYPE_CHECKING:  # the verb imports numpy, analysis and sim only when it runs (``--help`` stays light)
    import numpy as np
    from numpy.typing import NDArray

    from gyrobench.analysis.allan import NoiseFit
    from gyrobench.analysis.record import RecordAnalysis
    from gyrobench.analysis.twin import SampleComparison, TwinComparison
    from gyrobench.io.recording import Recording
    from gyrobench.sim.noise import NoiseModel
    from gyrobench.sim.parts import Part

__all__ = ["TwinResult", "add_parser", "gauss_markov_term", "make_twin", "nearest_part", "noise_model_from_fit"]

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


def _table(res: TwinResult, label: str) -> list[str]:
    from gyrobench.base import units

    c = res.comparison
    dph = 1.0 / units.deg_per_h(1.0)
    ra = res.analysis
    basis = "" if ra is None or ra.basis == "whole record" else f" (built from the real record's {ra.basis})"
    lines = [f"twin of {label}: model {res.model}{basis}; {res.recording.n_samples} samples at "
             f"{res.recording.fs:g} Hz",
             f"rule: {c.rule}",
             *([f"Gauss-Markov term (the five power laws misfit): sigma {res.coefficients['gm_sigma'] * dph:.4g} "
                f"deg/h, Tc {res.coefficients['gm_correlation_time']:.4g} s"]
               if "gm_sigma" in res.coefficients else []),
             f"{'tau [s]':>10} {'real ADEV':>11} {'real 95% interval':>23} {'twin ADEV':>11} {'twin/real':>9} "
             f"{'band':>15} {'in real95':>9} {'pass':>5}  [deg/h]"]
    for i in range(c.n_taus):
        lines.append(f"{c.tau[i]:>10.4g} {c.real[i] * dph:>11.4g} "
                     f"[{c.real_low95[i] * dph:>10.4g}, {c.real_high95[i] * dph:>10.4g}] {c.twin[i] * dph:>11.4g} "
                     f"{c.ratio[i]:>9.3f} [{c.ratio_low[i]:.3f}, {c.ratio_high[i]:.3f}] "
                     f"{'yes' if c.inside_real95[i] else 'no':>9} {'ok' if c.inside[i] else 'FAIL':>5}")
    sp = res.samples
    if sp is not None:
        lines.append(f"samples [deg/h]: real mean {sp.real_mean * dph:.5g}, sd {sp.real_std * dph:.4g}, range "
                     f"[{sp.real_range[0] * dph:.4g}, {sp.real_range[1] * dph:.4g}]; "
                     f"twin mean {sp.twin_mean * dph:.5g}, "
                     f"sd {sp.twin_std * dph:.4g}, range [{sp.twin_range[0] * dph:.4g}, {sp.twin_range[1] * dph:.4g}]; "
                     f"sd ratio {sp.std_ratio:.3f} in [{sp.band[0]:.3f}, {sp.band[1]:.3f}]: "
                     f"{'ok' if sp.passed else 'FAIL'}")
    verdict = "MATCHES" if res.passed else "DOES NOT MATCH"
    lines.append(f"twin {verdict}: {int(c.inside.sum())}/{c.n_taus} octave taus inside the band"
                 f"{'' if sp is None else ', sample spread ' + ('ok' if sp.passed else 'outside its band')}; "
                 f"{int(c.inside_real95.sum())}/{c.n_taus} inside the real curve's own 95 % interval (informative)")
    return lines


def _json(res: TwinResult, label: str) -> dict:
    c = res.comparison
    sp = res.samples
    samples = None if sp is None else {
        "real_mean": sp.real_mean, "twin_mean": sp.twin_mean, "real_std": sp.real_std, "twin_std": sp.twin_std,
        "real_range": list(sp.real_range), "twin_range": list(sp.twin_range), "std_ratio": sp.std_ratio,
        "band": list(sp.band), "edf": sp.edf, "passed": sp.passed, "unit": "rad/s"}
    return {"source": label, "model": res.model, "fs": res.recording.fs, "n_samples": res.recording.n_samples,
            "basis": None if res.analysis is None else res.analysis.basis,
            "coefficients_si": res.coefficients, "rule": c.rule, "family_alpha": c.family_alpha,
            "per_tau_alpha": c.per_tau_alpha, "passed": res.passed, "adev_passed": c.passed, "samples": samples,
            "taus": [{"tau": float(c.tau[i]), "real": float(c.real[i]), "real_low95": float(c.real_low95[i]),
                      "real_high95": float(c.real_high95[i]), "twin": float(c.twin[i]), "ratio": float(c.ratio[i]),
                      "ratio_low": float(c.ratio_low[i]), "ratio_high": float(c.ratio_high[i]),
                      "edf_real": float(c.edf_real[i]), "edf_twin": float(c.edf_twin[i]),
                      "inside": bool(c.inside[i]), "inside_real95": bool(c.inside_real95[i])}
                     for i in range(c.n_taus)]}


def _plot(res: TwinResult, label: str, target: Path) -> None:
    import matplotlib
    import numpy as np

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from gyrobench.base import units
    from gyrobench.base.atomic import atomic_path
    from gyrobench.base.safety import PNG_METADATA

    c = res.comparison
    dph = 1.0 / units.deg_per_h(1.0)
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.fill_between(c.tau, c.real_low95 * dph, c.real_high95 * dph, alpha=0.25, label="real 95 % interval")
    ax.loglog(c.tau, c.real * dph, "o-", label="real")
    ax.loglog(c.tau, c.twin * dph, "s--", label=f"twin ({res.model})")
    bad = ~c.inside
    if np.any(bad):
        ax.loglog(c.tau[bad], c.twin[bad] * dph, "rx", ms=10, label="outside the F band")
    ax.set_xlabel("tau [s]")
    ax.set_ylabel("Allan deviation [deg/h]")
    ax.set_title(f"twin of {label}: {'matches' if res.passed else 'does not match'} "
                 f"(family-wise alpha {c.family_alpha:g})", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    with atomic_path(target) as tmp:
        fig.savefig(tmp, format="png", dpi=120, bbox_inches="tight", metadata=PNG_METADATA)
    plt.close(fig)


#: the fitted terms a saved part carries: coefficient key -> (Datasheet field, SI -> field unit)
_PART_FIELDS = {"Q": ("quantization", "to_arcsec"), "N": ("arw", "to_deg_per_sqrt_h"),
                "B": ("bias_instability_dph", "to_deg_per_h"), "K": ("rate_random_walk", "to_deg_per_h_per_sqrt_h"),
                "R": ("rate_ramp", "to_deg_per_h2")}


def _grade(b_dph: float) -> str:
    """A fitted part's grade from its bias instability [deg/h] (a labelling convention: < 0.01 navigation,
    < 1 tactical, < 10 industrial, else consumer; the grade selects nothing in the simulation)."""
    return "navigation" if b_dph < 0.01 else "tactical" if b_dph < 1.0 else "industrial" if b_dph < 10.0 else "consumer"


def part_fields(res: TwinResult, fs: float, *, source: str, technology: str, name: str) -> dict[str, object]:
    """The :class:`~gyrobench.sim.parts.Datasheet` fields of a part whose budget is the twin's fitted model.

    Each fitted term becomes its part field in the field's unit (Q arcsec, N deg/sqrt(h), B deg/h as
    the IEEE coefficient itself, K deg/h/sqrt(h), R deg/h^2, the Gauss-Markov sigma and sine amplitude
    deg/h, its correlation time s, the sine's frequency Hz, the constant bias deg/h); a fitted
    low-pass is the part's output filter (corner and order), the record's rate its output rate; the
    part runs on its budget by default (``default_model = "budget"``). The 95 % intervals of the
    IEEE terms are written in ``notes``.
    """
    from gyrobench.base import units

    c = res.coefficients
    f: dict[str, object] = {
        "name": name, "manufacturer": "gyrobench twin", "model": f"fitted to {source}", "technology": technology,
        "source": f"gyrobench twin fit of {source} ({res.recording.n_samples} samples at {fs:g} Hz)",
        "source_kind": "fit", "default_model": "budget", "bias_instability_is_b": True, "output_rate": float(fs),
    }
    for key, (field_name, conv) in _PART_FIELDS.items():
        v = float(c.get(key, 0.0))
        if v > 0:
            f[field_name] = float(getattr(units, conv)(v))
    if c.get("gm_sigma"):
        f["gauss_markov_sigma"] = float(units.to_deg_per_h(c["gm_sigma"]))
        f["gauss_markov_tau"] = float(c["gm_correlation_time"])
    if c.get("sine_amplitude"):
        f["sine_amplitude"] = float(units.to_deg_per_h(c["sine_amplitude"]))
        f["sine_frequency"] = 1.0 / float(c["sine_period"])
    if c.get("lowpass_corner"):
        f["bandwidth"] = float(c["lowpass_corner"])
        f["filter_order"] = int(c["lowpass_order"])
    if c.get("bias"):
        f["bias_offset"] = float(units.to_deg_per_h(c["bias"]))
    b_dph = f.get("bias_instability_dph", 0.0)
    f["grade"] = _grade(b_dph if isinstance(b_dph, float) else 0.0)
    ci = []
    for key, (field_name, conv) in _PART_FIELDS.items():
        co = res.fit.coefficients.get(key)
        if co is not None:
            lo, hi = (float(getattr(units, conv)(x)) for x in co.ci95)
            ci.append(f"{field_name} 95 % interval [{lo:.6g}, {hi:.6g}]" + ("" if co.identifiable else
                                                                             " (not identifiable)"))
    f["notes"] = "; ".join(ci)
    return f


def _toml_value(v: object) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return repr(v)
    return json.dumps(str(v))  # a TOML basic string: JSON's escapes are TOML's


def write_part_toml(path: Path, fields: dict[str, object], what: str) -> None:
    """Write ``fields`` as a part file (top-level keys) with gyrobench's first-line marker, atomically."""
    from gyrobench.base.atomic import atomic_path
    from gyrobench.base.safety import comment_marker

    text = comment_marker(what) + "\n" + "".join(f"{k} = {_toml_value(v)}\n" for k, v in fields.items())
    with atomic_path(path) as tmp:
        Path(tmp).write_text(text, encoding="utf-8")


def _check_twin_outputs(args, path: Path) -> None:
    """-o and --plot through the output rule (gyrobench.base.safety): never the record or the --part file."""
    from gyrobench.base.safety import Output

    part = args.part if args.part is not None and args.part.lower().endswith(".toml") else None
    if args.part is not None:  # read once here: a missing, foreign or too deeply nested part fails before the fit
        from gyrobench.scenarios.cli.simulate import load_part

        load_part(args.part, "--part")
    outs = [Output(Path(args.output), "-o", suffixes=(".h5", ".hdf5", ".csv"), create_parents=False)]
    if args.plot:
        outs.append(Output(Path(args.plot), "--plot", suffixes=(".png",), create_parents=False))
    if args.save_part:
        outs.append(Output(Path(args.save_part), "--save-part", suffixes=(".toml",), create_parents=False))
    check_outputs(args, outs, [("FILE", path), ("--part", part)])


def _cmd_twin(args) -> int:
    import numpy as np

    from gyrobench.io.recording import save_hdf5
    from gyrobench.scenarios.cli.allan import _check_allan_input, _read_hdf5

    path = input_file(args.file, "recording file")  # not found, a folder, a FIFO, a device: one line
    if args.part is not None and args.nearest is not None:
        raise BadInput("give --part NAME or --nearest TECHNOLOGY, not both")
    if args.save_part is not None and (args.part is not None or args.nearest is not None):
        raise BadInput("--save-part saves the fitted model; with --part or --nearest the twin is a built-in part's")
    if args.technology is not None and args.save_part is None:
        raise BadInput("--technology names the technology of the --save-part file; give --save-part FILE.toml")
    if Path(args.output).suffix.lower() not in (".h5", ".hdf5", ".csv"):
        raise BadInput(f"-o must end in .h5, .hdf5 or .csv; got {args.output!r}")
    _check_twin_outputs(args, path)  # before any work
    columns = [args.column] if args.column is not None else None
    if path.suffix.lower() in (".h5", ".hdf5"):
        if args.fs is not None or args.units is not None:
            raise BadInput("--fs and --units apply to CSV input; an HDF5 recording carries its own")
        log = _read_hdf5(path, None, columns)
    else:
        from gyrobench.io.logs import read_csv_log

        log = read_csv_log(path, columns, args.fs, args.units)
    # without --column, a triad's first gyro (its outputs come in name order, accelerometers first)
    ch = log.channels[0] if columns else next((c for c in log.channels if c.quantity == "rate"), log.channels[0])
    if ch.quantity != "rate":
        raise BadInput(f"--column must name a rate column; {ch.label!r} is {ch.quantity}")
    rate = np.asarray(ch.data, dtype=float)
    if not np.all(np.isfinite(rate)):
        raise BadInput(f"{ch.label!r} holds non-finite samples; the twin needs a complete record")
    _check_allan_input(rate, log.fs, ch.label, "overlapping")
    from gyrobench.scenarios.cli import exits

    try:
        res = make_twin(rate, log.fs, rng=np.random.default_rng(args.seed), source=f"{path.name}:{ch.label}",
                        part=args.part, nearest=args.nearest, family_alpha=args.alpha)
    except NonStationaryRecord as exc:
        print(f"NONSTATIONARY {path.name}:{ch.label}: {exc}")
        return exits.NONSTATIONARY
    if Path(args.output).suffix.lower() == ".csv":
        from gyrobench.io.recording import to_csv

        to_csv(Path(args.output), res.recording, overwrite=args.force)
    else:
        save_hdf5(Path(args.output), res.recording, overwrite=args.force)
    label = f"{path.name}:{ch.label}"
    if args.save_part:
        import re

        stem = re.sub(r"[^a-z0-9_.-]+", "-", Path(args.save_part).stem.lower()).strip("-") or "twin"
        fields = part_fields(res, log.fs, source=label, technology=args.technology or "MEMS", name=stem)
        from gyrobench.sim.parts import Datasheet

        Datasheet(**fields)  # type: ignore[arg-type]  # the part file simulate device reads back, checked first
        write_part_toml(Path(args.save_part), fields, f"twin {label}: a part fitted to the record")
    if args.plot:
        _plot(res, label, Path(args.plot))
    if args.json:
        print(json.dumps(_json(res, label)))
    else:
        lines = _table(res, label)
        if res.analysis is not None and res.analysis.nonstationary:
            lines.insert(0, f"NONSTATIONARY {label}: motion or steps in the record; the twin is of its quiet "
                            "stretches, as gyrobench allan analyses them")
        print("\n".join(lines))
        print(f"wrote {args.output}" + (f" and {args.plot}" if args.plot else "")
              + (f" and the part file {args.save_part} (simulate device {args.save_part})" if args.save_part else ""))
    if res.analysis is not None and res.analysis.nonstationary and not args.accept_nonstationary:
        return exits.NONSTATIONARY
    return 0 if res.passed else 1


def _alpha_arg(text: str) -> float:
    import argparse

    v = positive_float("--alpha")(text)
    if not v < 1:
        raise argparse.ArgumentTypeError(f"--alpha must be in (0, 1); got {text!r}")
    return v


def add_parser(sub) -> None:
    """Add ``twin`` to the subparsers ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The ``gyrobench`` command's subparsers.
    """
    s = sub.add_parser("twin", help="digital twin of a real static record: fit, simulate, compare Allan deviations",
                       epilog="exit status: 0 the twin matches; 1 it does not (some octave tau outside the band, "
                              "or the sample spread); 2 bad input; 5 the record is not stationary (the twin is of "
                              "its quiet stretches, or none is built; --accept-nonstationary exits 0/1)")
    s.add_argument("file", help="real static record: CSV (.csv, .csv.gz) or gyrobench HDF5")
    s.add_argument("--column", help="the rate column (CSV name or index; HDF5 channel, default 'rate')")
    s.add_argument("--fs", type=positive_float("--fs", MAX_FLAG_VALUE),
                   help="CSV without a time column: sample rate [Hz]")
    s.add_argument("--units", help="CSV: unit of the column, e.g. deg/s, deg/h, rad/s (default: from the header)")
    s.add_argument("-o", "--output", required=True, help="write the twin recording here (.h5 HDF5 or .csv, with its "
                                                      "truth columns)")
    s.add_argument("--seed", type=seed, default=0, help="seed of the twin's noise (default 0)")
    s.add_argument("--part", help="use this built-in part's (or .toml part's) datasheet model instead of the fit")
    s.add_argument("--nearest", choices=("MEMS", "FOG", "RLG"),
                   help="use the built-in part of this technology nearest the fit in (N, B)")
    s.add_argument("--alpha", type=_alpha_arg, default=0.05,
                   help="family-wise false-alarm rate of the pass rule: a perfect twin fails at most this often "
                        "(default 0.05)")
    s.add_argument("--accept-nonstationary", action="store_true",
                   help="exit 0/1 by the match also when the record has motion or steps (the twin is then of its "
                        "quiet stretches; default: exit status 5, as allan)")
    s.add_argument("--save-part", help="also write the fitted model as a part file (.toml) that 'simulate device' "
                                       "reads (its budget: the fitted Q, N, B, K, R, Gauss-Markov, sine and filter "
                                       "terms)")
    s.add_argument("--technology", choices=("MEMS", "FOG", "RLG"),
                   help="the technology the --save-part file names (default MEMS; the saved part runs on its "
                        "budget unless simulate device --model physics)")
    s.add_argument("--json", action="store_true", help="print the per-tau comparison as JSON")
    s.add_argument("--plot", help="write the overlaid ADEV figure (PNG)")
    add_force(s)
    s.set_defaults(func=_cmd_twin)
