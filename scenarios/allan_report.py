"""Allan fits in field units: the coefficient table and the ``--json`` document.

:mod:`gyrobench.analysis.allan` returns coefficients in the units of the rate it was given
(rad/s here, so Q [rad], N [rad/sqrt(s)], ...); this edge module converts them to
the IEEE-952 field units of :data:`gyrobench.sim.units.COEFFICIENT_FIELD_UNITS`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from gyrobench.scenarios.base import Table
from gyrobench.sim import units

__all__ = [
    "coefficients_json",
    "coefficient_table",
    "TERMS",
    "analyse",
    "log_json",
    "log_text",
    "ChannelResult",
]

TERMS = ("Q", "N", "B", "K", "R")


def _field(name: str, v: float | None) -> float | None:
    f = units.coefficient_to_field(name, v)
    return None if f is None else float(f)


def coefficients_json(fit) -> dict[str, dict[str, Any]]:
    """``{"Q": {"value", "low", "high", "unit", ...}, ...}`` in field units.

    ``low``/``high`` are the 95 % interval; ``low68``/``high68`` the 68 % one.
    ``value`` is None when the term is not identifiable from the record; then
    ``high`` holds the 95 % upper bound and ``low`` is 0.
    """
    out = {}
    for name in TERMS:
        c = fit.coefficients.get(name)
        unit = units.COEFFICIENT_FIELD_UNITS[name][0]
        if c is None:
            continue
        if c.identifiable and c.value is not None:
            out[name] = {
                "value": _field(name, c.value),
                "low": _field(name, c.ci95[0]),
                "high": _field(name, c.ci95[1]),
                "low68": _field(name, c.ci68[0]),
                "high68": _field(name, c.ci68[1]),
                "unit": unit,
                "identifiable": True,
            }
        else:
            out[name] = {
                "value": None,
                "low": 0.0,
                "high": _field(name, c.upper_bound),
                "low68": None,
                "high68": None,
                "unit": unit,
                "identifiable": False,
            }
    return out


def _interval_text(d: dict[str, Any]) -> tuple[str, str]:
    if d["value"] is None:
        return "not identifiable", f"< {d['high']:.3g}"
    return f"{d['value']:.4g}", f"[{d['low']:.3g}, {d['high']:.3g}]"


def coefficient_table(fit, *, title: str, truth: dict[str, float] | None = None) -> Table:
    """A report table of the fitted coefficients (and the true values, when known)."""
    js = coefficients_json(fit)
    cols = ["term", "unit", "fitted", "95 % interval"] + (["true", "true inside"] if truth else [])
    rows = []
    for name, d in js.items():
        v, ci = _interval_text(d)
        row = [name, d["unit"], v, ci]
        if truth is not None:
            t = truth.get(name, 0.0)
            inside = (d["low"] <= t <= d["high"]) if d["value"] is not None else t <= d["high"]
            row += [t, inside]
        rows.append(row)
    return Table(title, cols, rows)


# ----------------------------------------------------------------------------- CLI analysis of a log
#: accelerometer coefficients: the same IEEE terms on m/s^2 (IEEE Std 1293-1998 names):
#: name, field unit, factor from SI (N [m/s/sqrt(s)] x sqrt(3600) = m/s/sqrt(h); B [m/s^2] /
#: (1e-6 g0) = ug; K [m/s^2/sqrt(s)] x sqrt(3600) = m/s^2/sqrt(h))
ACCEL_FIELD_UNITS = {
    "Q": ("velocity quantization", "m/s", 1.0),
    "N": ("velocity random walk", "m/s/sqrt(h)", units.HOUR**0.5),
    "B": ("bias instability", "ug", 1.0 / (1e-6 * units.G0)),
    "K": ("acceleration random walk", "m/s^2/sqrt(h)", units.HOUR**0.5),
    "R": ("acceleration ramp", "m/s^3", 1.0),
}
#: fitted kinds (the IEEE 952 term coefficients hold for the Allan variance); the same as
#: gyrobench.analysis.allan's, repeated so the CLI need not import the analysis (a test pins it)
FIT_KINDS = ("overlapping", "standard")


def field_value(name: str, v, quantity: str = "rate"):
    """A coefficient in SI -> its field unit (gyro: IEEE 952 units; accelerometer: ACCEL_FIELD_UNITS)."""
    if v is None:
        return None
    if quantity == "accel":
        return float(v) * ACCEL_FIELD_UNITS[name][2]
    return float(units.coefficient_to_field(name, v))


def field_unit(name: str, quantity: str = "rate") -> str:
    return (
        ACCEL_FIELD_UNITS[name][1]
        if quantity == "accel"
        else units.COEFFICIENT_FIELD_UNITS[name][0]
    )


@dataclass
class ChannelResult:
    """Curve and fit (None for kinds without a fit) of one channel, with why there is no fit."""

    channel: Any
    curve: Any
    fit: Any = None
    no_fit: str | None = None
    fit_range: Any = None
    bandwidth_range: Any = None
    warnings: list = field(default_factory=list)
    temperature: Any = None
    nonstationary: bool = False
    segments: list = field(default_factory=list)  # (start_s, stop_s, ChannelResult) of --segments auto
    pooled: Any = None  # --segments auto: one NoiseFit over the quiet stretches' pooled curve (pool_curves)


def _stationarity(data, fs: float, curve, label: str) -> tuple[list[str], bool, Any]:
    """Motion/step warnings on windows of the curve's tau nearest 1 s with >= 32 windows,
    whether motion or steps were found (the record is then flagged non-stationary) and the
    :class:`StationarityReport` (None when no tau qualifies)."""
    import numpy as np
    from gyrobench.analysis.stationarity import stationarity_check

    n = len(data)
    ok = (curve.m >= 8) & (n // np.maximum(curve.m, 1) >= 32)
    if not np.any(ok):
        return [], False, None
    i = int(np.flatnonzero(ok)[np.argmin(np.abs(np.log(curve.tau[ok])))])
    rep = stationarity_check(data, fs, float(curve.deviation[i]), window=float(curve.tau[i]))
    return rep.warnings(label), bool(rep.tested and not rep.stationary), rep


def check_finite(channel: Any) -> None:
    """Refuse a channel with NaN or inf samples, naming the first one."""
    import numpy as np

    bad = np.flatnonzero(~np.isfinite(channel.data))
    if len(bad):
        # float(): print nan / inf, not np.float64(nan)
        raise ValueError(
            f"{channel.label} contains {float(channel.data[bad[0]])} at sample {bad[0]} ({len(bad)} "
            f"non-finite sample{'s' if len(bad) > 1 else ''}): the data must be finite"
        )


def analyse(
    channel,
    fs: float,
    *,
    taus: str = "octave",
    kind: str = "overlapping",
    terms: tuple[str, ...] = TERMS,
    tau_min="auto",
    tau_max: float | None = None,
    temperature=None,
    bandwidth: float | None = None,
    bandwidth_bias: float = 0.1,
    segments: str | None = None,
) -> ChannelResult:
    """Allan deviation of one channel (SI) and, for the Allan variance kinds, the noise fit.

    With ``taus="all"`` the fit uses the octave taus among them (the fit's point covariance
    grows as the square of the number of taus, and neighbouring m carry no new information).
    """
    from gyrobench.analysis.allan import (
        AllanCurve,
        allan_deviation,
        bandwidth_range,
        fit_noise,
        fit_range,
        floor_bounds,
    )

    check_finite(channel)
    data, tfit = channel.data, None
    if temperature is not None:
        from gyrobench.analysis.stationarity import remove_temperature

        data, tfit = remove_temperature(channel.data, temperature, fs)
    curve = allan_deviation(data, fs, taus=taus, kind=kind)
    warn, moving, stat = _stationarity(data, fs, curve, channel.label)
    if kind not in FIT_KINDS:
        return ChannelResult(
            channel,
            curve,
            warnings=warn,
            temperature=tfit,
            nonstationary=moving,
            no_fit=(
                f"no noise fit for the {kind} deviation: the IEEE 952 term coefficients (3 Q^2/tau^2, N^2/tau, ...) "
                f"are those of the Allan variance; the curve is exported"
            ),
        )
    fit_curve = curve
    if taus == "all":
        m = curve.m
        keep = (m & (m - 1)) == 0
        fit_curve = AllanCurve(
            tau=curve.tau[keep],
            deviation=curve.deviation[keep],
            low=curve.low[keep],
            high=curve.high[keep],
            n_terms=curve.n_terms[keep],
            edf=curve.edf[keep],
            kind=curve.kind,
            confidence=curve.confidence,
            fs=curve.fs,
            n_samples=curve.n_samples,
            alpha=None if curve.alpha is None else curve.alpha[keep],
        )
    if len(fit_curve.tau) < len(terms):
        raise ValueError(
            f"{channel.label}: {len(channel.data)} samples at {fs:g} Hz give {len(fit_curve.tau)} {curve.kind} Allan "
            f"deviation point(s) at taus={taus!r} (up to {fit_curve.tau[-1]:.3g} s); the "
            f"{'/'.join(terms)} fit needs at least {len(terms)}: use a longer record or fewer --terms"
        )
    fr = fit_range(fit_curve, n_terms=len(terms), nonstationary=moving) if tau_min == "auto" else None
    bw = bandwidth_range(fit_curve, bandwidth, bias=bandwidth_bias) if bandwidth is not None else None
    options = {"terms": terms, "tau_min": tau_min, "tau_max": tau_max, "bandwidth": bandwidth}
    fit = fit_noise(fit_curve, bandwidth_bias=bandwidth_bias, nonstationary=moving, **options)
    # an open term's bound never below what a half or a quarter of the record identifies (issue 30)
    fit = floor_bounds(fit, data, fs, bandwidth_bias=bandwidth_bias, **options)
    result = ChannelResult(
        channel, curve, fit=fit, fit_range=fr, bandwidth_range=bw, warnings=warn, temperature=tfit,
        nonstationary=moving,
    )
    if segments == "auto" and moving:
        result.segments = _segment_fits(channel, data, fs, stat, taus=taus, kind=kind, terms=terms,
                                        tau_min=tau_min, tau_max=tau_max, bandwidth=bandwidth,
                                        bandwidth_bias=bandwidth_bias)
        result.pooled = _pooled_fit(result.segments, bandwidth_bias=bandwidth_bias, **options)
    return result


def _pooled_fit(segments: list, **fit_options):
    """``--segments auto``: one fit over the quiet stretches' EDF-weighted pooled Allan variance
    (:func:`pool_curves`), None with fewer than two fitted stretches or no common taus to fit.

    An open term's bound is raised to the largest value a stretch identifies (as
    :func:`floor_bounds` does with a record's halves and quarters), saying so in its note.
    """
    from dataclasses import replace as _replace

    from gyrobench.analysis.allan import fit_noise, pool_curves

    fitted = [sub for _, _, sub in segments if sub.fit is not None]
    if len(fitted) < 2:
        return None
    try:
        pooled = fit_noise(pool_curves([sub.fit.curve for sub in fitted]), **fit_options)
    except ValueError:  # too few common taus for the terms
        return None
    coefficients = dict(pooled.coefficients)
    for name, c in pooled.coefficients.items():
        if c.identifiable:
            continue
        best = max((sub.fit.coefficients[name].value for sub in fitted if name in sub.fit.coefficients
                    and sub.fit.coefficients[name].identifiable), default=None)
        if best is not None and best > c.upper_bound:
            coefficients[name] = _replace(c, upper_bound=best, bound_note=(
                f"bound raised {best / c.upper_bound:.3g}x to the value identified over a quiet stretch"))
    return _replace(pooled, coefficients=coefficients)


def _segment_fits(channel, data, fs: float, stat, **options) -> list:
    """``--segments auto``: the fit of each quiet stretch (:func:`quiet_stretches`) long enough to fit.

    Each stretch is analysed as a record of its own (its own stationarity check and fit range);
    a stretch too short for the fit is left out.
    """
    from dataclasses import replace as _replace

    from gyrobench.analysis.stationarity import quiet_stretches

    out = []
    for a, b in quiet_stretches(stat, len(data), fs):
        part = _replace(channel, data=data[a:b]) if hasattr(channel, "__dataclass_fields__") else None
        if part is None:
            continue
        try:
            res = analyse(part, fs, **options)
        except ValueError:  # too short for the fit
            continue
        out.append((a / fs, b / fs, res))
    return out


def _floor(curve) -> tuple[float, float]:
    import numpy as np

    i = int(np.argmin(curve.deviation))
    return float(curve.deviation[i]), float(curve.tau[i])


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
