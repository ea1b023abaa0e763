"""Allan fits in field units: the coefficient table, and the analysis of a log's channels that
``gyrobench allan`` prints (its text, ``--json`` document and Kalibr file are formatted in
:mod:`gyrobench.scenarios.reports.allan_text`).

:mod:`gyrobench.analysis.allan` returns coefficients in the units of the rate it was given
(rad/s here, so Q [rad], N [rad/sqrt(s)], ...); this edge module converts them to
the IEEE-952 field units of :data:`gyrobench.base.units.COEFFICIENT_FIELD_UNITS`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from gyrobench.base import units
from gyrobench.scenarios.base import Table

__all__ = [
    "coefficients_json",
    "coefficient_table",
    "TERMS",
    "analyse",
    "stationarity",
    "ChannelResult",
]

TERMS = ("Q", "N", "B", "K", "R")


def _field(name: str, v: float | None) -> float | None:
    f = units.coefficient_to_field(name, v)
    return None if f is None else float(f)


def coefficients_json(fit) -> dict[str, dict[str, Any]]:
    """The fitted IEEE 952 coefficients as a JSON mapping, in field units.

    ``{"Q": {"value", "low", "high", "unit", ...}, ...}`` in field units.

    ``low``/``high`` are the 95 % interval; ``low68``/``high68`` the 68 % one.
    ``value`` is None when the term is not identifiable from the record; then
    ``high`` holds the 95 % upper bound and ``low`` is 0.

    Parameters
    ----------
    fit : NoiseFit
        The noise fit.

    Returns
    -------
    dict of str to dict
        ``{"Q": {"value", "low", "high", "low68", "high68", "unit", ...}, ...}``.
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
    """A report table of the fitted coefficients (and the true values, when known).

    Parameters
    ----------
    fit : NoiseFit
        The noise fit.
    title : str
        The table's title.
    truth : dict of str to float or None
        True coefficients (SI) of a simulated record, shown beside the fit.

    Returns
    -------
    Table
        One row per term.
    """
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
    """Curve and fit (None for kinds without a fit) of one channel, with why there is no fit.

    Attributes
    ----------
    channel : LogChannel
        The channel analysed.
    curve : AllanCurve
        Its deviation curve.
    fit : NoiseFit or None
        The noise fit (None for a kind without one).
    no_fit : str or None
        Why there is no fit.
    fit_range : object
        The fitted tau range and why.
    bandwidth_range : object
        The taus the output filter biases.
    warnings : list of str
        Warning lines.
    temperature : object
        The temperature channel's summary (None: none in the log).
    nonstationary : bool
        Motion or steps were found.
    segments : list
        ``(start_s, stop_s, ChannelResult)`` per segment of ``--segments auto``.
    pooled : object
        The fit over the pooled quiet stretches (``--segments auto``).
    analysis : RecordAnalysis or None
        The analysis behind the fit.
    segments_asked : bool
        ``--segments auto`` was given.
    """

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
    pooled: Any = None  # --segments auto: the fit over the quiet stretches pooled per tau
    analysis: Any = None  # the RecordAnalysis (gyrobench.analysis.record) behind the fit
    segments_asked: bool = False  # --segments auto was given


def stationarity(data, fs: float, curve, label: str) -> tuple[list[str], bool, Any]:
    """The motion and step check of a channel and its warnings.

    Motion/step warnings (:func:`gyrobench.analysis.record.stationarity_verdict`), whether motion or
    steps were found (the record is then flagged non-stationary) and the :class:`StationarityReport`
    (None when no tau qualifies).

    Parameters
    ----------
    data : array_like
        The channel's samples.
    fs : float
        Sample rate [Hz].
    curve : AllanCurve
        Its Allan curve.
    label : str
        The channel's name, for the warnings.

    Returns
    -------
    tuple of (list of str, bool, StationarityReport or None)
        The warnings, whether motion or steps were found, and the report (None: too short to test).
    """
    from gyrobench.analysis.record import stationarity_verdict

    rep = stationarity_verdict(data, fs, curve, label)
    if rep is None:
        return [], False, None
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
    quiet: bool = True,
    select: bool = True,
) -> ChannelResult:
    """Allan deviation of one channel (SI) and, for the Allan variance kinds, the noise fit.

    The analysis is :func:`gyrobench.analysis.record.analyse_record` (the path ``twin`` and the
    Python API share): on a non-stationary channel the quiet stretches are fitted (``quiet``).
    With ``taus="all"`` the fit uses the octave taus among them.

    Parameters
    ----------
    channel : LogChannel
        The channel (samples in SI).
    fs : float
        Sample rate [Hz].
    taus : {"octave", "decade", "all"}
        Tau list of the curve.
    kind : str
        The deviation (only the Allan variance kinds are fitted).
    terms : tuple of str
        The IEEE 952 terms fitted.
    tau_min : float, "auto" or None
        Shortest tau fitted [s].
    tau_max : float or None
        Longest tau fitted [s].
    temperature : LogChannel or None
        The log's temperature channel, reported beside the fit.
    bandwidth : float or None
        The sensor's output bandwidth [Hz].
    bandwidth_bias : float
        Largest relative Allan-variance bias of the output filter a fitted tau may carry.
    segments : str or None
        ``"auto"``: also fit each stationary segment (``--segments auto``).
    quiet : bool
        On a non-stationary channel fit its quiet stretches.
    select : bool
        Choose extra model terms.

    Returns
    -------
    ChannelResult
        The curve, the fit (None for a kind without one) and the warnings.
    """
    from gyrobench.analysis.record import analyse_record

    check_finite(channel)
    data, tfit = channel.data, None
    if temperature is not None:
        from gyrobench.analysis.stationarity import remove_temperature

        data, tfit = remove_temperature(channel.data, temperature, fs)
    ra = analyse_record(data, fs, label=channel.label, taus=taus, kind=kind, terms=terms, tau_min=tau_min,
                        tau_max=tau_max, bandwidth=bandwidth, bandwidth_bias=bandwidth_bias, quiet=quiet,
                        select=select)
    result = ChannelResult(
        channel, ra.curve, fit=ra.fit, no_fit=ra.no_fit or None, fit_range=ra.fit_range,
        bandwidth_range=ra.bandwidth_range, warnings=list(ra.warnings), temperature=tfit,
        nonstationary=ra.nonstationary, analysis=ra, segments_asked=segments == "auto",
    )
    if segments == "auto" and ra.nonstationary and ra.fit is not None:
        options = {"terms": terms, "tau_min": tau_min, "tau_max": tau_max, "bandwidth": bandwidth}
        result.segments = _segment_fits(channel, data, fs, ra.stationarity, taus=taus, kind=kind, terms=terms,
                                        tau_min=tau_min, tau_max=tau_max, bandwidth=bandwidth,
                                        bandwidth_bias=bandwidth_bias)
        result.pooled = ra.fit if ra.basis == "quiet stretches" else _pooled_fit(
            result.segments, bandwidth_bias=bandwidth_bias, **options)
    return result


def _pooled_fit(segments: list, **fit_options):
    """``--segments auto``: one fit over the quiet stretches' EDF-weighted pooled Allan variance
    (:func:`pool_curves`), None with fewer than two fitted stretches or no common taus to fit.

    An open term's bound is raised to the largest value a stretch identifies (as
    :func:`floor_bounds` does with a record's halves, quarters and eighths), saying so in its note.
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
            res = analyse(part, fs, quiet=False, select=False, **options)
        except ValueError:  # too short for the fit
            continue
        out.append((a / fs, b / fs, res))
    return out


def _floor(curve) -> tuple[float, float]:
    import numpy as np

    i = int(np.argmin(curve.deviation))
    return float(curve.deviation[i]), float(curve.tau[i])
