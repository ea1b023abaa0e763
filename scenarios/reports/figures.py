"""Figures shared by several scenarios and the CLI (matplotlib, Agg, no pyplot state)."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from gyrobench.base import units

__all__ = ["allan_figure"]

_TERM_STYLE = {
    "Q": "tab:purple",
    "N": "tab:blue",
    "B": "tab:green",
    "K": "tab:orange",
    "R": "tab:red",
}
#: confidence of the drawn band: the level of the coefficient table's intervals
BAND_LEVEL = 0.95


def _band(curve, level: float):
    """Chi-square bounds of the deviation at ``level`` from the curve's edf (NIST SP 1065 eq. 45)."""
    from scipy import stats

    edf = np.asarray(curve.edf, dtype=float)
    p = (1.0 - level) / 2.0
    dev = np.asarray(curve.deviation, dtype=float)
    with np.errstate(invalid="ignore", divide="ignore"):
        return dev * np.sqrt(edf / stats.chi2.ppf(1.0 - p, edf)), dev * np.sqrt(
            edf / stats.chi2.ppf(p, edf)
        )


def allan_figure(
    curve, fit=None, *, title: str = "", true_avar=None, quantity: str = "rate"
) -> Figure:
    """ADEV against tau with its 95 % band, the fitted model, each term's asymptote and the residuals.

    Parameters
    ----------
    curve : analysis.allan.AllanCurve
        Computed from a rate in rad/s (``quantity="rate"``, drawn in deg/h) or an
        acceleration in m/s^2 (``"accel"``, drawn in ug).
    fit : analysis.allan.NoiseFit, optional
        Joint fit: the model is drawn as a thick line over the fitted taus (dashed where it
        is extrapolated over the taus left out), identifiable terms as dotted asymptotes
        labelled with their values and with what the line plots (e.g. "line 0.664 B": the
        bias-instability floor sits at 0.664 B), non-identifiable terms as their 95 % upper
        bound (thin dash-dot, "<"), the taus left out of the fit shaded, and a lower panel
        shows the normalised residuals (data - model) / sd of each point (sd from the fit's
        point covariance; excluded points use the curve's own edf).
    true_avar : callable tau -> AVAR [SI^2], optional
        The closed-form curve of a simulated model, drawn dashed.
    """
    k, yunit = (
        (1.0 / 9.80665e-6, "ug") if quantity == "accel" else (units.to_deg_per_h(1.0), "deg/h")
    )
    fig = Figure(figsize=(7.2, 6.0) if fit is not None else (7.0, 4.8))
    if fit is not None:
        ax, axr = fig.subplots(
            2, 1, sharex=True, gridspec_kw={"height_ratios": [3.2, 1.0], "hspace": 0.06}
        )
    else:
        ax, axr = fig.add_subplot(), None
    tau = np.asarray(curve.tau)
    dev = np.asarray(curve.deviation)
    lo, hi = _band(curve, BAND_LEVEL)
    ax.fill_between(tau, lo * k, hi * k, color="0.85", label=f"{BAND_LEVEL:.0%} confidence")
    ax.loglog(tau, dev * k, "k.-", lw=1, ms=4, label=f"{curve.kind} deviation")
    tt = np.geomspace(tau[0], tau[-1], 200)
    if true_avar is not None:
        ax.loglog(tt, np.sqrt(true_avar(tt)) * k, "k--", lw=0.8, label="true model")
    if fit is not None:
        used = (
            np.asarray(fit.used, dtype=bool)
            if np.size(fit.used) == np.size(fit.curve.tau)
            else None
        )
        fit_tau = np.asarray(fit.curve.tau)
        if used is not None and not used.all():
            t_lo, t_hi = fit_tau[used][0], fit_tau[used][-1]
            for a_, b_, cut in (
                (tau[0] / 1.5, t_lo / 1.2, t_lo > tau[0]),
                (t_hi * 1.2, tau[-1] * 1.5, t_hi < tau[-1]),
            ):
                if cut:
                    for axis in (ax, axr):
                        axis.axvspan(a_, b_, color="tab:red", alpha=0.07, lw=0)
            ax.text(
                0.01,
                0.02,
                "shaded: not fitted",
                transform=ax.transAxes,
                fontsize=7,
                color="tab:red",
            )
        # the model over the fitted taus; dashed where it is extrapolated (taus left out of the fit)
        f_lo, f_hi = (fit_tau[used][0], fit_tau[used][-1]) if used is not None else (tau[0], tau[-1])
        inner = (tt >= f_lo * (1 - 1e-9)) & (tt <= f_hi * (1 + 1e-9))
        t_in = np.concatenate([[f_lo], tt[inner], [f_hi]])
        ax.loglog(
            t_in,
            np.sqrt(fit.avar(t_in)) * k,
            color="tab:cyan",
            lw=2.4,
            alpha=0.85,
            label="fitted model"
            + (f" (MISFIT, chi2/dof {fit.chi2_per_dof:.3g})" if fit.misfit else ""),
        )
        for side in (tt[tt < f_lo], tt[tt > f_hi]):
            if side.size:
                edge = f_lo if side[0] < f_lo else f_hi
                t_out = np.sort(np.concatenate([side, [edge]]))
                ax.loglog(t_out, np.sqrt(fit.avar(t_out)) * k, "--", color="tab:cyan", lw=1.2, alpha=0.85)
        for name, c in fit.coefficients.items():
            what = _asymptote_text(name, float(c.power))
            if c.identifiable and c.value:
                v, unit = _field(name, c.value, quantity)
                ax.loglog(
                    tt,
                    np.sqrt(fit.term_avar(name, tt)) * k,
                    ":",
                    color=_TERM_STYLE[name],
                    lw=1.4,
                    label=f"{name} = {v:.3g} {unit}; line {what}",
                )
            else:
                from gyrobench.analysis.allan import coefficient_to_avar

                ub = coefficient_to_avar(name, c.upper_bound) * tt ** float(c.power)
                v, unit = _field(name, c.upper_bound, quantity)
                ax.loglog(
                    tt,
                    np.sqrt(ub) * k,
                    "-.",
                    color=_TERM_STYLE[name],
                    lw=0.7,
                    alpha=0.6,
                    label=f"{name} < {v:.3g} {unit} (95 %); line {what}",
                )
        ax.set_ylim((lo * k).min() / 3, (hi * k).max() * 3)
        # residual panel: (A - model) / sd_A
        model = fit.avar(fit_tau)
        sd = np.sqrt(2.0 * model**2 / np.asarray(fit.curve.edf, dtype=float))
        if used is not None and np.asarray(fit.point_covariance).shape == (used.sum(), used.sum()):
            sd[used] = np.sqrt(np.diag(fit.point_covariance))
        r = (np.asarray(fit.curve.deviation) ** 2 - model) / sd
        inside = used if used is not None else np.ones(r.size, dtype=bool)
        axr.axhline(0.0, color="0.5", lw=0.8)
        axr.axhspan(-2, 2, color="0.9")
        good = r[inside & np.isfinite(r)]
        lim = max(float(np.max(np.abs(good))) * 1.3, 3.0) if good.size else 3.0
        axr.scatter(fit_tau[inside], r[inside], c="k", s=12, zorder=3, label="fitted")
        out_r = np.clip(r[~inside], -lim * 0.95, lim * 0.95)
        axr.scatter(
            fit_tau[~inside],
            out_r,
            c="tab:red",
            marker="x",
            s=14,
            zorder=3,
            label="not fitted (clipped)",
        )
        axr.set_xscale("log")
        axr.set_ylabel("(AVAR - fit) / sd", fontsize=8)
        axr.set_ylim(-lim, lim)
        axr.grid(True, which="both", alpha=0.3)
        axr.set_xlabel("cluster time tau [s]")
    else:
        ax.set_xlabel("cluster time tau [s]")
    ax.set_ylabel(f"Allan deviation [{yunit}]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6.5, loc="best")
    if title:
        ax.set_title(title, fontsize=9)
    return fig


def _asymptote_text(name: str, power: float) -> str:
    """What a term's line plots: its ADEV sqrt(C(1) tau^p) for the coefficient 1, e.g. "0.664 B" for
    bias instability (AVAR = (2 ln 2 / pi) B^2) or "N tau^-0.5" (IEEE Std 952-1997 Annex C)."""
    from gyrobench.analysis.allan import coefficient_to_avar

    fac = float(np.sqrt(coefficient_to_avar(name, 1.0)))
    head = name if abs(fac - 1.0) < 5e-4 else f"{fac:.3g} {name}"
    half = power / 2.0
    return head if half == 0 else f"{head} tau^{half:g}"


def _field(name: str, value: float, quantity: str) -> tuple[float, str]:
    if quantity == "accel":
        from gyrobench.scenarios.reports.allan import ACCEL_FIELD_UNITS

        _, unit, f = ACCEL_FIELD_UNITS[name]
        return value * f, unit
    return float(units.coefficient_to_field(name, value)), units.COEFFICIENT_FIELD_UNITS[name][0]
