"""The ``gyrobench allan --json`` document from the analysed channels
(:func:`gyrobench.scenarios.reports.allan.analyse`): each fit, curve, channel and log as JSON, in
field units. Formatting only: nothing here computes or decides.

The text report and the figures' names and titles are :mod:`gyrobench.scenarios.reports.allan_text`,
the noise files :mod:`gyrobench.scenarios.reports.allan_yaml`.
"""

from __future__ import annotations

from typing import Any

from gyrobench.scenarios.reports.allan import ChannelResult, _floor, field_unit, field_value

__all__ = ["analysis_json", "channel_json", "curve_json", "fit_json", "log_json"]


def _si_unit(quantity: str) -> str:
    return "m/s^2" if quantity == "accel" else "rad/s"


def _motion_fitted(res: ChannelResult) -> bool:
    """The channel moves and its fit includes the motion (not a fit of its quiet stretches)."""
    return bool(res.nonstationary and _basis(res) != "quiet stretches")


def _basis(res: ChannelResult) -> str:
    ra = res.analysis
    return "whole record" if ra is None else ra.basis



def fit_json(fit, quantity: str = "rate", nonstationary: bool = False) -> dict[str, Any]:
    """A noise fit as JSON: each term's value and intervals in field units, the taus and the misfit.

    The fit: per term value/intervals in field units, the taus used, chi2/dof and p, and
    ``nonstationary`` (motion or steps in what was fitted: the terms describe them too; False for
    a fit of the quiet stretches).

    Parameters
    ----------
    fit : NoiseFit
        The fit.
    quantity : str
        ``"rate"`` or the accelerometer's quantity, for the units.
    nonstationary : bool
        Motion or steps are in what was fitted (the terms describe them too).

    Returns
    -------
    dict of str to object
        The terms, taus used, chi2/dof and p, ``nonstationary``.
    """
    import math

    terms = {}
    for name, c in fit.coefficients.items():
        terms[name] = {
            "value": field_value(name, c.value, quantity) if c.identifiable else None,
            "low": field_value(name, c.ci95[0], quantity) if c.identifiable else 0.0,
            "high": field_value(name, c.ci95[1] if c.identifiable else c.upper_bound, quantity),
            "low68": field_value(name, c.ci68[0], quantity) if c.identifiable else None,
            "high68": field_value(name, c.ci68[1], quantity) if c.identifiable else None,
            "unit": field_unit(name, quantity),
            "identifiable": bool(c.identifiable),
            "bound_note": c.bound_note or None,
        }

    def num(v: float):
        return None if not math.isfinite(v) else float(v)

    return {
        "terms": terms,
        "tau_used": [float(t) for t in fit.tau_used],
        "chi2": num(fit.chi2),
        "dof": int(fit.dof),
        "chi2_expected": num(fit.chi2_expected),
        "chi2_per_dof": num(fit.chi2_per_dof),
        "p_value": num(fit.p_value),
        "misfit": bool(fit.misfit),
        "nonstationary": bool(nonstationary),
        "interval_inflation": float(fit.inflation),
        "tau_min_rule": fit.range_rule or None,
        "tau_min_reason": fit.range_reason or None,
    }


def curve_json(curve, quantity: str = "rate") -> dict[str, Any]:
    """An Allan curve as JSON, in field units.

    Parameters
    ----------
    curve : AllanCurve
        The curve.
    quantity : str
        ``"rate"`` (gyro, deg/h) or the accelerometer's quantity, for the units.

    Returns
    -------
    dict of str to object
        Taus, deviations and their intervals, edf and the statistic.
    """
    return {
        "kind": curve.kind,
        "unit": _si_unit(quantity),
        "confidence": float(curve.confidence),
        "tau": [float(v) for v in curve.tau],
        "deviation": [float(v) for v in curve.deviation],
        "low": [float(v) for v in curve.low],
        "high": [float(v) for v in curve.high],
        "count": [int(v) for v in curve.n_terms],
    }


def channel_json(res: ChannelResult) -> dict[str, Any]:
    """One channel's entry of the ``--json`` document.

    Parameters
    ----------
    res : ChannelResult
        The channel's result.

    Returns
    -------
    dict of str to object
        Its curve, fit (or why none), analysis, warnings and segments, in field units.
    """
    q = res.channel.quantity
    floor, tau = _floor(res.curve)
    out: dict[str, Any] = {
        "channel": res.channel.label,
        "quantity": q,
        "curve": curve_json(res.curve, q),
        "adev_floor": {"value": floor, "unit": _si_unit(q), "tau": tau},
        "fit": None if res.fit is None else fit_json(res.fit, q, _motion_fitted(res)),
        "nonstationary": bool(res.nonstationary),
    }
    if res.no_fit:
        out["no_fit"] = res.no_fit
    out.update(analysis_json(res))
    if res.segments:
        out["segments"] = [
            {"start_s": a, "stop_s": b, "nonstationary": bool(sub.nonstationary),
             "fit": None if sub.fit is None else fit_json(sub.fit, q, sub.nonstationary)}
            for a, b, sub in res.segments
        ]
    if res.pooled is not None:
        out["pooled"] = {"segments": len([s for s in res.segments if s[2].fit is not None]),
                         "n_samples": int(res.pooled.curve.n_samples),
                         "fit": fit_json(res.pooled, q, False)}
    out["warnings"] = list(res.warnings)
    if res.temperature is not None:
        tf = res.temperature
        out["temperature"] = {
            "model": "y = c0 + c_T (T - Tbar) + c_dT dT/dt",
            "c_T": tf.c_temperature,
            "c_T_unit": f"{_si_unit(q)}/degC",
            "c_dT": tf.c_rate,
            "c_dT_unit": f"{_si_unit(q)}/(degC/s)",
            "se_T": tf.se_temperature,
            "se_dT": tf.se_rate,
            "explained": tf.explained,
        }
    return out


def analysis_json(res: ChannelResult) -> dict[str, Any]:
    """What was fitted, as JSON: basis, quiet stretches and the model's extra terms.

    ``basis`` (what was fitted), ``quiet`` (the quiet stretches and what was left out) and ``model``
    (terms beyond Q/N/B/K/R, SI).

    Parameters
    ----------
    res : ChannelResult
        One channel's result.

    Returns
    -------
    dict of str to object
        ``basis``, ``quiet`` (the stretches and what was left out) and ``model`` (SI).
    """
    import math

    ra = res.analysis
    if ra is None:
        return {}
    fs = float(res.curve.fs)
    out: dict[str, Any] = {"basis": ra.basis}
    q = ra.quiet
    if q is not None and ra.basis == "quiet stretches":
        sp = q.spread
        out["quiet"] = {
            "stretches": len(q.stretches),
            "excluded_samples": int(q.n_excluded),
            "excluded_s": [[a / fs, b / fs] for a, b in q.excluded],
            "bridged_from_tau": float(q.curve.tau[q.bridged][0]) if q.bridged.any() else None,
            "spread": [{"tau": float(sp.tau[i]), "stretches": int(sp.n_stretches[i]),
                        "low": None if not math.isfinite(sp.low[i]) else float(sp.low[i]),
                        "high": None if not math.isfinite(sp.high[i]) else float(sp.high[i]),
                        "bartlett_p": None if not math.isfinite(sp.p_value[i]) else float(sp.p_value[i])}
                       for i in range(len(sp.tau))],
        }
    m = ra.model
    if m is not None:
        out["model"] = {
            "criterion": m.criterion,
            "terms": [{"kind": t.kind, "params_si": dict(t.params), "interval95_si": list(t.interval),
                       "chi2_drop": t.drop, "given": t.given} for t in m.extra],
            "first_step_drops": dict(m.drops),
            "threshold": m.threshold,
            "p_value": None if not math.isfinite(m.p_value) else m.p_value,
            "misfit": m.misfit,
        }
    return out


def log_json(log, results: list[ChannelResult]) -> dict[str, Any]:
    """The ``--json`` document: file, rate, notes and one entry per channel.

    For the gyro channels the five coefficients also stand at the top level of each channel
    entry (``"N": {"value", "low", "high", "unit"}``) as before; with one channel the
    document is that channel's entry plus ``file``, ``fs``, ``notes``.

    Parameters
    ----------
    log : ImuLog
        The log analysed.
    results : list of ChannelResult
        Its channels' results.

    Returns
    -------
    dict of str to object
        The document.
    """
    chans = []
    for res in results:
        d = channel_json(res)
        if res.fit is not None:
            for name, t in d["fit"]["terms"].items():
                d[name] = {k: t[k] for k in ("value", "low", "high", "unit")}
        chans.append(d)
    head = {
        "file": str(log.path),
        "fs": float(log.fs),
        "n_samples": int(len(results[0].channel.data)),
        "notes": list(log.notes),
    }
    if len(chans) == 1:
        return {**head, **chans[0]}
    return {**head, "channels": chans}
