"""What ``gyrobench allan`` prints from the analysed channels
(:func:`gyrobench.scenarios.reports.allan.analyse`): the text report, the plot file names and
titles. Formatting only: nothing here computes or decides.

The ``--json`` document is :mod:`gyrobench.scenarios.reports.allan_json` and the Kalibr IMU noise
file and the filter's noise model are :mod:`gyrobench.scenarios.reports.allan_yaml`; their names
are importable from here too.
"""

from __future__ import annotations

from typing import Any

from gyrobench.base import units
from gyrobench.scenarios.reports.allan import ChannelResult, field_unit, field_value
from gyrobench.scenarios.reports.allan_json import (
    _basis,
    _motion_fitted,
    analysis_json,
    channel_json,
    curve_json,
    fit_json,
    log_json,
)
from gyrobench.scenarios.reports.allan_yaml import filter_yaml, kalibr_yaml

__all__ = ["analysis_json", "channel_json", "curve_json", "deviation_lines", "filter_yaml", "fit_json", "kalibr_yaml",
           "log_json", "log_text", "model_lines", "nonstationary_line", "plot_paths", "plot_title"]


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
