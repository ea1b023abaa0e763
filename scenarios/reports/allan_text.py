"""What ``gyrobench allan`` prints and writes from the analysed channels
(:func:`gyrobench.scenarios.reports.allan.analyse`): the text report, the ``--json`` document,
plot file names and titles, and the Kalibr IMU noise file. Formatting only: nothing here
computes or decides."""

from __future__ import annotations

from typing import Any

from gyrobench.base import units
from gyrobench.scenarios.reports.allan import ChannelResult, _floor, field_unit, field_value

__all__ = ["channel_json", "curve_json", "fit_json", "kalibr_yaml", "log_json", "log_text", "nonstationary_line",
           "plot_paths", "plot_title"]


def _si_unit(quantity: str) -> str:
    return "m/s^2" if quantity == "accel" else "rad/s"


def fit_json(fit, quantity: str = "rate", nonstationary: bool = False) -> dict[str, Any]:
    """The fit: per term value/intervals in field units, the taus used, chi2/dof and p, and
    ``nonstationary`` (motion or steps in the record: the terms describe them too)."""
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
    q = res.channel.quantity
    floor, tau = _floor(res.curve)
    out: dict[str, Any] = {
        "channel": res.channel.label,
        "quantity": q,
        "curve": curve_json(res.curve, q),
        "adev_floor": {"value": floor, "unit": _si_unit(q), "tau": tau},
        "fit": None if res.fit is None else fit_json(res.fit, q, res.nonstationary),
        "nonstationary": bool(res.nonstationary),
    }
    if res.no_fit:
        out["no_fit"] = res.no_fit
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


def log_json(log, results: list[ChannelResult]) -> dict[str, Any]:
    """The ``--json`` document: file, rate, notes and one entry per channel.

    For the gyro channels the five coefficients also stand at the top level of each channel
    entry (``"N": {"value", "low", "high", "unit"}``) as before; with one channel the
    document is that channel's entry plus ``file``, ``fs``, ``notes``.
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
    """The figure file of each channel: ``plot`` itself for one channel, else ``<stem>_<channel><suffix>``."""
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


def plot_title(log, res: ChannelResult) -> str:
    """The figure's title block: the record, then what the report warns of (non-stationary, misfit, warnings)."""
    n = len(res.channel.data)
    lines = [f"{log.path.name}: {res.channel.label}, {log.fs:g} Hz, {n / log.fs / 3600:.3g} h ({n} samples)"]
    if res.nonstationary:
        lines.append("NOT STATIONARY (motion or steps): the terms describe them too")
    f = res.fit
    if f is not None and f.misfit:
        lines.append(
            f"MISFIT: chi2/dof = {f.chi2_per_dof:.3g}, p = {f.p_value:.2g}; intervals widened x{f.inflation:.3g}"
        )
    for w in res.warnings:
        lines.append(w if len(w) <= _TITLE_WIDTH else w[: _TITLE_WIDTH - 3] + "...")
    return "\n".join(lines)


def nonstationary_line(res: ChannelResult) -> str:
    """The report's first line for a channel with motion or steps."""
    return (
        f"NONSTATIONARY {res.channel.label}: motion or steps in the record (WARNING lines below); the fitted "
        f"terms describe them as noise: analyse a quiet stretch (--start/--stop)"
    )


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
    """The printed report: misfits first, then the record, the notes and one table of every channel."""
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
    head = (
        f"{'channel':<18}" if multi else ""
    ) + f"{'term':<5}{'value':>14}  {'95 % interval':<28}unit"
    out.append(head)
    for res in results:
        if res.fit is None:
            continue
        q = res.channel.quantity
        for name, c in res.fit.coefficients.items():
            pre = f"{res.channel.label[:17]:<18}" if multi else ""
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
        out += _segment_lines(res)
    return out


def _segment_lines(res: ChannelResult) -> list[str]:
    """``--segments auto``: one line per quiet stretch of a non-stationary channel (its terms, in field units)."""
    if not res.nonstationary or not res.segments:
        return [f"SEGMENTS {res.channel.label}: no quiet stretch long enough to fit"] if res.nonstationary else []
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
            f"POOLED {res.channel.label}: one fit over the stretches' EDF-weighted Allan variance "
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
    """
    lines = [
        "# Kalibr IMU noise parameters written by gyrobench allan",
        f"# from {log.path.name}: {len(results[0].channel.data)} samples at {log.fs:g} Hz",
        "# densities are the IEEE 952 N and K of each axis (largest over the axes), continuous time",
    ]
    moving = [r.channel.label for r in results if r.nonstationary]
    if moving:
        lines.append(f"# WARNING not stationary (motion or steps; the values describe them too): {', '.join(moving)}")
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
