"""What ``gyrobench allan`` prints and writes from the analysed channels
(:func:`gyrobench.scenarios.reports.allan.analyse`): the text report, the ``--json`` document,
plot file names and titles, and the Kalibr IMU noise file. Formatting only: nothing here
computes or decides."""

from __future__ import annotations

from typing import Any

from gyrobench.base import units
from gyrobench.scenarios.reports.allan import ChannelResult, _floor, field_unit, field_value

__all__ = ["analysis_json", "channel_json", "curve_json", "deviation_lines", "filter_yaml", "fit_json", "kalibr_yaml",
           "log_json", "log_text", "model_lines", "nonstationary_line", "plot_paths", "plot_title"]


def _si_unit(quantity: str) -> str:
    return "m/s^2" if quantity == "accel" else "rad/s"


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


def _temp_units(quantity: str) -> tuple[float, str]:
    """Factor from SI and unit of a temperature coefficient's numerator: deg/h (gyro) or ug (accelerometer)."""
    if quantity == "accel":
        return 1.0 / 9.80665e-6, "ug"
    return float(units.to_deg_per_h(1.0)), "deg/h"


def plot_paths(plot, results: list[ChannelResult]) -> list[tuple[Any, ChannelResult]]:
    """The figure file of each channel: ``plot`` itself for one channel, else ``<stem>_<channel><suffix>``.

    Parameters
    ----------
    plot : Path
        The ``--plot`` file.
    results : list of ChannelResult
        The channels' results.

    Returns
    -------
    list of (Path, ChannelResult)
        Each channel's figure file.
    """
    import re

    if len(results) == 1:
        return [(plot, results[0])]
    out = []
    for res in results:
        safe = re.sub(r"[^A-Za-z0-9._-]+", "_", res.channel.label).strip("_") or "channel"
        out.append((plot.with_name(f"{plot.stem}_{safe}{plot.suffix}"), res))
    return out


#: longest warning line in a figure's title block [characters]
_TITLE_WIDTH = 110


def _motion_fitted(res: ChannelResult) -> bool:
    """The channel moves and its fit includes the motion (not a fit of its quiet stretches)."""
    return bool(res.nonstationary and _basis(res) != "quiet stretches")


def plot_title(log, res: ChannelResult) -> str:
    """The figure's title block: the record, then what the report warns of (non-stationary, misfit, warnings).

    Parameters
    ----------
    log : ImuLog
        The log analysed.
    res : ChannelResult
        The channel's result.

    Returns
    -------
    str
        The title text.
    """
    n = len(res.channel.data)
    lines = [f"{log.path.name}: {res.channel.label}, {log.fs:g} Hz, {n / log.fs / 3600:.3g} h ({n} samples)"]
    if res.nonstationary:
        lines.append("NOT STATIONARY (motion or steps): " + ("the fit is of the quiet stretches"
                                                             if not _motion_fitted(res) else
                                                             "the terms describe them too"))
    f = res.fit
    if f is not None and f.misfit:
        lines.append(
            f"MISFIT: chi2/dof = {f.chi2_per_dof:.3g}, p = {f.p_value:.2g}; intervals widened x{f.inflation:.3g}"
        )
    for w in res.warnings:
        lines.append(w if len(w) <= _TITLE_WIDTH else w[: _TITLE_WIDTH - 3] + "...")
    return "\n".join(lines)


def _basis(res: ChannelResult) -> str:
    ra = res.analysis
    return "whole record" if ra is None else ra.basis


def nonstationary_line(res: ChannelResult) -> str:
    """The report's first line for a channel with motion or steps.

    Parameters
    ----------
    res : ChannelResult
        One channel's result.

    Returns
    -------
    str
        The line.
    """
    if _basis(res) == "quiet stretches":
        return (
            f"NONSTATIONARY {res.channel.label}: motion or steps in the record (WARNING lines below); the fit is of "
            f"its quiet stretches (QUIET line below)"
        )
    return (
        f"NONSTATIONARY {res.channel.label}: motion or steps in the record (WARNING lines below); the fitted "
        f"terms describe them as noise: analyse a quiet stretch (--start/--stop)"
    )


def _rate_scale(quantity: str) -> tuple[float, str]:
    """SI per field unit of a rate-like value: deg/h for a gyro, ug for an accelerometer."""
    if quantity == "accel":
        return 9.80665e-6, "ug"
    return float(units.deg_per_h(1.0)), "deg/h"


def model_lines(res: ChannelResult) -> list[str]:
    """The QUIET line (what was left out) and the MODEL lines (terms chosen beyond Q/N/B/K/R).

    Parameters
    ----------
    res : ChannelResult
        One channel's result.

    Returns
    -------
    list of str
        The QUIET and MODEL lines (empty when neither applies).
    """
    ra = res.analysis
    if ra is None:
        return []
    out = []
    label = res.channel.label
    if ra.basis == "quiet stretches" and ra.quiet is not None:
        out.append(f"QUIET {label}: {ra.quiet.describe(res.curve.fs)}")
    m = ra.model
    if m is None:
        return out
    k, unit = _rate_scale(res.channel.quantity)
    for term in m.extra:
        line = f"MODEL {label}: {term.describe(k, unit)}"
        if term.kind == "lowpass":
            n = term.params.get("N", 0.0)
            nf = field_value("N", n, res.channel.quantity)
            lo, hi = (field_value("N", v, res.channel.quantity) for v in term.interval)
            line += (f" ({'given' if term.given else 'identified'}; the bent short taus fitted with it: N "
                     f"{nf:.4g} [{lo:.4g}, {hi:.4g}] {field_unit('N', res.channel.quantity)})")
        else:
            line += f" (chosen: chi2 drop {term.drop:.3g} > {m.threshold:.3g})"
        out.append(line)
    if not any(t.kind != "lowpass" for t in m.extra):
        best = max(m.drops.items(), key=lambda kv: kv[1], default=None)
        if best is not None:
            out.append(f"MODEL {label}: no Gauss-Markov or sinusoid term needed (largest chi2 drop {best[1]:.3g} "
                       f"for {best[0].replace('_', '-')}, < {m.threshold:.3g})")
    if m.misfit:
        out.append(f"MISFIT {label}: the chosen model still misfits the fitted Allan variance (GLS p = "
                   f"{m.p_value:.2g}): a term of another kind (or motion) is in the record")
    return out


def deviation_lines(res: ChannelResult) -> list[str]:
    """The Allan deviation at each tau, with its confidence interval, in field units.

    Parameters
    ----------
    res : ChannelResult
        One channel's result.

    Returns
    -------
    list of str
        One line per tau.
    """
    c = res.curve
    k, unit = _rate_scale(res.channel.quantity)
    conf = f"{c.confidence:.1%}".replace(".0%", "%")
    out = [f"{res.channel.label}: {c.kind} deviation [{unit}] (tau [s]: value [{conf} interval])"]
    row = []
    for i in range(len(c.tau)):
        row.append(f"{c.tau[i]:.4g}: {c.deviation[i] / k:.4g} [{c.low[i] / k:.3g}, {c.high[i] / k:.3g}]")
    for j in range(0, len(row), 4):
        out.append("  " + ";  ".join(row[j : j + 4]))
    return out


def _excluded_text(res: ChannelResult, excl: int) -> str:
    """Why the first ``excl`` taus of a channel's fit were left out: the rule that set tau_min, then misfit."""
    f = res.fit
    if f.range_rule == "bandwidth" and res.bandwidth_range is not None:
        n = res.bandwidth_range.excluded
        what = "by --bandwidth: " + res.bandwidth_range.reason.split(": there ")[-1]
    elif f.range_rule == "data" and res.fit_range is not None:
        n, what = res.fit_range.excluded, "filter-shaped: the log-log curve bends down there, which no sum of the "
        what += "IEEE power laws can do"
    elif f.range_rule == "user":
        n, what = excl, "below --tau-min"
    else:
        n, what = 0, ""
    n = min(n, excl)
    parts = [f"{n} {what}"] if n else []
    if excl > n:
        parts.append(f"{excl - n} {'more ' if n else ''}misfitting the model")
    return f" ({'; '.join(parts)})"


def log_text(log, results: list[ChannelResult]) -> list[str]:
    """The printed report: misfits first, then the record, the notes and one table of every channel.

    Parameters
    ----------
    log : ImuLog
        The log analysed.
    results : list of ChannelResult
        Its channels' results.

    Returns
    -------
    list of str
        The report's lines.
    """
    import numpy as np

    out = [nonstationary_line(res) for res in results if res.nonstationary]
    for res in results:
        f = res.fit
        if f is not None and f.misfit:
            out.append(
                f"MISFIT {res.channel.label}: the Q/N/B/K/R model does not describe the Allan variance over the "
                f"fitted taus {f.tau_used[0]:.3g}-{f.tau_used[-1]:.3g} s (chi2/dof = {f.chi2_per_dof:.3g}, "
                f"p = {f.p_value:.2g}); intervals widened x{f.inflation:.3g}"
            )
    for res in results:
        out += [f"WARNING {w}" for w in res.warnings]
    first = results[0]
    n = len(first.channel.data)
    out.append(
        f"{log.path}: {n} samples at {log.fs:g} Hz ({n / log.fs / 3600:.3g} h); {first.curve.kind} "
        f"deviation, {len(first.curve.tau)} taus from {first.curve.tau[0]:.3g} to {first.curve.tau[-1]:.3g} s"
    )
    out += [f"note: {t}" for t in log.notes]
    for res in results:
        if res.temperature is not None:
            tf, k, u = res.temperature, *_temp_units(res.channel.quantity)
            out.append(
                f"{res.channel.label}: removed the temperature-explained part y = c_T (T - Tbar) + c_dT dT/dt "
                f"(least squares, {tf.explained:.1%} of the variance): c_T = {tf.c_temperature * k:.4g} "
                f"+- {tf.se_temperature * k:.2g} {u}/degC, c_dT = {tf.c_rate * k / 60:.4g} "
                f"+- {tf.se_rate * k / 60:.2g} {u}/(degC/min) (white-residual standard errors)"
            )
        if res.no_fit:
            out.append(f"{res.channel.label}: {res.no_fit}")
            continue
        f = res.fit
        tau_f = f.curve.tau
        excl = int(np.sum(tau_f < f.tau_used[0]))
        why = ""
        if excl:
            why = _excluded_text(res, excl)
        p = "n/a" if f.dof == 0 else f"{f.p_value:.2g}"
        out.append(
            f"{res.channel.label}: fit over {int(f.used.sum())} taus {f.tau_used[0]:.3g}-{f.tau_used[-1]:.3g} s"
            f"{f'; {excl} short tau(s) excluded' + why if excl else ''}; chi2/dof = {f.chi2_per_dof:.3g}, "
            f"p = {p}"
        )
        if res.nonstationary and res.fit_range is not None and res.fit_range.reason.startswith("short taus kept"):
            out.append(f"{res.channel.label}: {res.fit_range.reason}")  # which --tau-min auto rule applied
    if all(res.fit is None for res in results):
        return out
    multi = len(results) > 1
    width = max(18, *(len(r.channel.label) + 1 for r in results))  # full names: ROS axes differ only at the end
    head = (
        f"{'channel':<{width}}" if multi else ""
    ) + f"{'term':<5}{'value':>14}  {'95 % interval':<28}unit"
    out.append(head)
    for res in results:
        if res.fit is None:
            continue
        q = res.channel.quantity
        for name, c in res.fit.coefficients.items():
            pre = f"{res.channel.label:<{width}}" if multi else ""
            unit = field_unit(name, q)
            if not c.identifiable:
                hi = field_value(name, c.upper_bound, q)
                why = "not identifiable from this record" + ("; bound from a sub-segment" if c.bound_note else "")
                out.append(pre + f"{name:<5}{'n/i':>14}  {'< ' + format(hi, '.3g'):<28}{unit}   ({why})")
            else:
                v, lo, hi = (field_value(name, x, q) for x in (c.value, *c.ci95))
                out.append(
                    pre
                    + f"{name:<5}{v:>14.4g}  [{lo:.4g}, {hi:.4g}]".ljust(49 - (0 if multi else 0))
                    + unit
                )
    for res in results:
        out += model_lines(res)
    for res in results:
        out += _segment_lines(res)
    for res in results:
        out += deviation_lines(res)
    return out


def _segment_lines(res: ChannelResult) -> list[str]:
    """``--segments auto``: one line per quiet stretch of a non-stationary channel (its terms, in field units)."""
    if not res.nonstationary or not res.segments:
        asked = res.nonstationary and res.segments_asked
        return [f"SEGMENTS {res.channel.label}: no quiet stretch long enough to fit on its own"] if asked else []
    out = [f"SEGMENTS {res.channel.label}: {len(res.segments)} quiet stretch(es) fitted on their own"]
    for a, b, sub in res.segments:
        q = sub.channel.quantity
        parts = []
        for name, c in (sub.fit.coefficients.items() if sub.fit is not None else ()):
            if c.identifiable:
                v, lo, hi = (field_value(name, x, q) for x in (c.value, *c.ci95))
                parts.append(f"{name} {v:.4g} [{lo:.4g}, {hi:.4g}] {field_unit(name, q)}")
        flag = "; itself not stationary" if sub.nonstationary else ""
        out.append(f"  {a:g}-{b:g} s: " + ("; ".join(parts) or "no identifiable term") + flag)
    f = res.pooled
    if f is not None:
        q = res.channel.quantity
        parts = []
        for name, c in f.coefficients.items():
            if c.identifiable:
                v, lo, hi = (field_value(name, x, q) for x in (c.value, *c.ci95))
                parts.append(f"{name} {v:.4g} [{lo:.4g}, {hi:.4g}] {field_unit(name, q)}")
            else:
                parts.append(f"{name} < {field_value(name, c.upper_bound, q):.3g} {field_unit(name, q)} (n/i)")
        p = "n/a" if f.dof == 0 else f"{f.p_value:.2g}"
        out.append(
            f"POOLED {res.channel.label}: one fit over the stretches' Allan variance pooled per tau "
            f"({f.curve.n_samples} samples, taus {f.tau_used[0]:.3g}-{f.tau_used[-1]:.3g} s, "
            f"chi2/dof = {f.chi2_per_dof:.3g}, p = {p}): " + "; ".join(parts)
        )
    return out


# ----------------------------------------------------------------------------- Kalibr export
def kalibr_yaml(log, results: list[ChannelResult]) -> str:
    """The Kalibr IMU noise file (imu.yaml) from the fits of a log's gyro and accelerometer axes.

    Conversions (Kalibr wiki "IMU Noise Model"; continuous-time densities equal the IEEE 952
    coefficients in SI):

    * gyroscope_noise_density [rad/s/sqrt(Hz)] = N [rad/sqrt(s)] (angle random walk);
    * gyroscope_random_walk [rad/s^2/sqrt(Hz)] = K [rad/s/sqrt(s)] (rate random walk);
    * accelerometer_noise_density [m/s^2/sqrt(Hz)] = N [m/s/sqrt(s)] (velocity random walk);
    * accelerometer_random_walk [m/s^3/sqrt(Hz)] = K [m/s^2/sqrt(s)] (acceleration random walk);
    * update_rate [Hz] = the sample rate.

    Kalibr takes one value per sensor: the largest over the axes (conservative). A term not
    identifiable on an axis contributes its 95 % upper bound, and the file says so in a
    comment. Bias instability has no place in Kalibr's model and is given as a comment.

    Parameters
    ----------
    log : ImuLog
        The log analysed.
    results : list of ChannelResult
        Its channels' results.

    Returns
    -------
    str
        The imu.yaml text.
    """
    lines = [
        "# Kalibr IMU noise parameters written by gyrobench allan",
        f"# from {log.path.name}: {len(results[0].channel.data)} samples at {log.fs:g} Hz",
        "# densities are the IEEE 952 N and K of each axis (largest over the axes), continuous time",
    ]
    moving = [r.channel.label for r in results if _motion_fitted(r)]
    if moving:
        lines.append(f"# WARNING not stationary (motion or steps; the values describe them too): {', '.join(moving)}")
    quiet = [r.channel.label for r in results if r.nonstationary and not _motion_fitted(r)]
    if quiet:
        lines.append(f"# not stationary as a whole; fitted from the quiet stretches: {', '.join(quiet)}")
    keys = {
        ("rate", "N"): ("gyroscope_noise_density", "rad/s/sqrt(Hz)"),
        ("rate", "K"): ("gyroscope_random_walk", "rad/s^2/sqrt(Hz)"),
        ("accel", "N"): ("accelerometer_noise_density", "m/s^2/sqrt(Hz)"),
        ("accel", "K"): ("accelerometer_random_walk", "m/s^3/sqrt(Hz)"),
    }
    body = []
    for (q, term), (key, unit) in keys.items():
        fits = [
            r
            for r in results
            if r.fit is not None and r.channel.quantity == q and term in r.fit.coefficients
        ]
        if not fits:
            continue
        vals, bounds = [], []
        for r in fits:
            c = r.fit.coefficients[term]
            vals.append(c.value if c.identifiable else c.upper_bound)
            if not c.identifiable:
                bounds.append(r.channel.label)
        floored = [r.channel.label for r in fits if r.fit.coefficients[term].bound_note]
        note = f"  # 95 % upper bound on {', '.join(bounds)} (not identifiable)" if bounds else ""
        note += f"; bound from a sub-segment on {', '.join(floored)}" if floored else ""
        body.append(
            f"{key}: {max(vals):.6e}  # [{unit}] max over {', '.join(r.channel.label for r in fits)}{note}"
        )
        if term == "N":
            bis = [r.fit.coefficients["B"] for r in fits if "B" in r.fit.coefficients]
            bi = [c.value for c in bis if c.identifiable]
            if bi:
                lines.append(
                    f"# {'gyroscope' if q == 'rate' else 'accelerometer'} bias instability B (not used by "
                    f"Kalibr): {max(bi):.4e} [{_si_unit(q)}]"
                )
    if not body:
        raise ValueError(
            "--kalibr needs a fitted gyro or accelerometer channel (N and K terms); none was fitted"
        )
    return "\n".join(lines + body + [f"update_rate: {log.fs:g}  # [Hz]", ""])


# ----------------------------------------------------------------------------- filter process noise
def filter_yaml(log, results: list[ChannelResult], *, overbound: bool = False) -> str:
    """The fitted model as a navigation filter's process noise (:func:`gyrobench.analysis.filter_model.filter_model`).

    Sections: ``gyrobench`` (every key carries its unit: each axis's white and random-walk
    densities, B as a Gauss-Markov state and as a random-walk equivalent, the inflation),
    ``kalibr`` (imu.yaml) and ``openvins`` (kalibr_imu_chain.yaml ``imu0``), whose key names
    the tools fix, with the unit in a comment on every line, and ``ros`` (the diagonal of
    ``sensor_msgs/Imu`` covariances: the per-sample white-noise variance N^2 fs). Kalibr,
    OpenVINS and ROS take one value per sensor: the largest over the axes.

    Parameters
    ----------
    log : ImuLog
        The log analysed.
    results : list of ChannelResult
        Its channels' results.
    overbound : bool
        Scale the model to overbound the data's 95 % bound.

    Returns
    -------
    str
        The YAML text.
    """
    from gyrobench.analysis.filter_model import filter_model

    lines = [f"# gyrobench filter process noise from {log.path.name} ({log.fs:g} Hz)",
             "# conversions: white density = N; random-walk density = K; B as Gauss-Markov sigma = 0.664 B / 0.6174,",
             "# Tc = tau_B / 1.8926 (its ADEV peaks at the B plateau at tau_B),",
             "# or as random walk 0.664 B sqrt(3 / tau_B)"]
    if overbound:
        lines.append("# overbounded: every density scaled by the smallest k putting the model ADEV on or above the "
                     "data's upper 95 % bound at every tau")
    moving = [r.channel.label for r in results if r.nonstationary]
    if moving:
        lines.append("# not stationary as a whole (fitted from the quiet stretches where possible): "
                     + ", ".join(moving))
    per: dict[str, list] = {"rate": [], "accel": []}
    lines.append("gyrobench:")
    for r in results:
        if r.fit is None:
            continue
        fm = filter_model(r.fit, overbound=overbound)
        q = r.channel.quantity
        per[q].append(fm)
        u = "m_per_s2" if q == "accel" else "rad_per_s"
        u2 = "m_per_s3" if q == "accel" else "rad_per_s2"
        key = "".join(ch if ch.isalnum() else "_" for ch in r.channel.label).strip("_")
        lines += [f"  {key}:",
                  f"    white_density_{u}_per_sqrt_hz: {fm.white_density:.6e}",
                  f"    white_variance_per_sample_{u}_squared: {fm.white_variance_per_sample:.6e}",
                  f"    random_walk_density_{u2}_per_sqrt_hz: {fm.random_walk_density:.6e}",
                  f"    bias_gauss_markov_sigma_{u}: {fm.gm_sigma:.6e}",
                  f"    bias_gauss_markov_time_constant_s: {fm.gm_tc:.6g}",
                  f"    bias_random_walk_equivalent_{u2}_per_sqrt_hz: {fm.rw_equivalent_density:.6e}",
                  f"    bias_tau_s: {fm.tau_b:.6g}",
                  f"    inflation_factor_1: {fm.inflation:.4g}",
                  f"    upper_bounds_not_identified: [{', '.join(fm.bounds)}]"]
    if not per["rate"] and not per["accel"]:
        raise ValueError("--filter-model needs a fitted gyro or accelerometer channel; none was fitted")
    tool = []
    for q, pre, unit_w, unit_rw in (("rate", "gyroscope", "rad/s/sqrt(Hz)", "rad/s^2/sqrt(Hz)"),
                                    ("accel", "accelerometer", "m/s^2/sqrt(Hz)", "m/s^3/sqrt(Hz)")):
        if per[q]:
            w = max(f.white_density for f in per[q])
            rw = max(max(f.random_walk_density, f.rw_equivalent_density) for f in per[q])
            tool += [f"  {pre}_noise_density: {w:.6e}  # [{unit_w}]",
                     f"  {pre}_random_walk: {rw:.6e}  # [{unit_rw}] max of K and B's random-walk equivalent"]
    lines += ["kalibr:", *tool, f"  update_rate: {log.fs:g}  # [Hz]"]
    lines += ["openvins:", *tool, f"  update_rate: {log.fs:g}  # [Hz]"]
    lines.append("ros:")
    for q, name, unit in (("rate", "angular_velocity_covariance", "rad^2/s^2"),
                          ("accel", "linear_acceleration_covariance", "m^2/s^4")):
        if per[q]:
            d = max(f.white_variance_per_sample for f in per[q])
            lines.append(f"  {name}: [{d:.6e}, 0.0, 0.0, 0.0, {d:.6e}, 0.0, 0.0, 0.0, {d:.6e}]  # [{unit}] row-major")
    return "\n".join(lines) + "\n"
