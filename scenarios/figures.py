"""Figures shared by several scenarios and the CLI (matplotlib, Agg, no pyplot state)."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from gyrobench.sim import units

__all__ = ["allan_figure"]

_TERM_STYLE = {"Q": "tab:purple", "N": "tab:blue", "B": "tab:green", "K": "tab:orange", "R": "tab:red"}


def allan_figure(curve, fit=None, *, title: str = "", true_avar=None, quantity: str = "rate") -> Figure:
    """ADEV in deg/h against tau with its confidence band, the fitted model and each term's asymptote.

    Parameters
    ----------
    curve : analysis.allan.AllanCurve
        Computed from a rate in rad/s.
    fit : analysis.allan.NoiseFit, optional
        Joint fit; its total and identifiable terms are drawn.
    true_avar : callable tau -> AVAR [rad^2/s^2], optional
        The closed-form curve of the simulated model, drawn dashed.
    """
    k, yunit = (1.0 / 9.80665e-6, "ug") if quantity == "accel" else (units.to_deg_per_h(1.0), "deg/h")
    fig = Figure(figsize=(7.0, 4.8))
    ax = fig.add_subplot()
    tau = np.asarray(curve.tau)
    ax.fill_between(tau, curve.low * k, curve.high * k, color="0.85", label=f"{curve.confidence:.0%} confidence")
    ax.loglog(tau, curve.deviation * k, "k.-", lw=1, label=f"{curve.kind} ADEV")
    tt = np.geomspace(tau[0], tau[-1], 200)
    if true_avar is not None:
        ax.loglog(tt, np.sqrt(true_avar(tt)) * k, "k--", lw=0.8, label="true model")
    if fit is not None:
        ax.loglog(tt, np.sqrt(fit.avar(tt)) * k, color="tab:gray", lw=2, alpha=0.7, label="fitted model")
        for name, c in fit.coefficients.items():
            if c.identifiable and c.value:
                v, unit = units.coefficient_to_field(name, c.value), units.COEFFICIENT_FIELD_UNITS[name][0]
                ax.loglog(tt, np.sqrt(fit.term_avar(name, tt)) * k, ":", color=_TERM_STYLE[name], lw=1.3,
                          label=f"{name} = {v:.3g} {unit}")
        lo, hi = (curve.low * k).min(), (curve.high * k).max()
        ax.set_ylim(lo / 3, hi * 3)
    ax.set_xlabel("cluster time tau [s]")
    ax.set_ylabel(f"Allan deviation [{yunit}]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    if title:
        ax.set_title(title, fontsize=10)
    return fig
