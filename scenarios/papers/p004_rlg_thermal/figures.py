"""Paper 004's figures, drawn from the units' typed results only (matplotlib, Agg)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from .claims import PAPER_ADJ_R2, PAPER_IMPROVEMENT_PCT
from .results import UnitResult

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["output_vs_temperature", "rate_and_gradient", "before_after", "population", "mode_hops"]

_MINUTE_S = 60.0  # the rates are drawn per minute


def output_vs_temperature(units: Sequence[UnitResult]) -> Figure:
    """Output and temperatures over the first unit's fitting run; output vs T1 for three units.

    Parameters
    ----------
    units : sequence of UnitResult
        The units' results.

    Returns
    -------
    Figure
        The figure.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10.0, 4.2), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2)
    f = units[0].fit
    ax1.plot(f.t_h, f.output, "k.-", lw=0.8, ms=3, label=f"unit {units[0].seed} output (100-s mean)")
    ax1.set_xlabel("time [h]")
    ax1.set_ylabel("output bias [deg/h]")
    axt = ax1.twinx()
    axt.plot(f.t_h, f.chamber, color="0.6", lw=1, label="chamber")
    axt.plot(f.t_h, f.t1, color="tab:red", lw=1, label="T1 housing")
    axt.plot(f.t_h, f.t2, color="tab:blue", lw=1, label="T2 cavity")
    axt.set_ylabel("temperature [degC]")
    axt.legend(loc="lower center", fontsize=8)
    ax1.legend(loc="upper left", fontsize=8)
    ax1.set_title("(a) output and temperatures, fitting run")
    for u in units[:3]:
        g = u.fit
        ax2.plot(g.t1, g.output - np.mean(g.output), ".-", lw=0.6, ms=3, label=f"unit {u.seed}")
    ax2.set_xlabel("housing temperature T1 [degC]")
    ax2.set_ylabel("output bias - mean [deg/h]")
    ax2.set_title("(b) output vs temperature (up and down ramps)")
    ax2.legend(fontsize=8)
    return fig


def rate_and_gradient(u: UnitResult) -> Figure:
    """Housing and cavity temperature rates and the housing-cavity gradient of a fitting run.

    Parameters
    ----------
    u : UnitResult
        A unit's result.

    Returns
    -------
    Figure
        The figure.
    """
    from matplotlib.figure import Figure

    f = u.fit
    fig = Figure(figsize=(8.0, 4.2), layout="constrained")
    ax = fig.subplots()
    ax.plot(f.t_h, f.dt1 * _MINUTE_S, color="tab:red", label="dT1/dt housing")
    ax.plot(f.t_h, f.dt2 * _MINUTE_S, color="tab:blue", label="dT2/dt cavity")
    ax.set_xlabel("time [h]")
    ax.set_ylabel("temperature rate [degC/min]")
    axg = ax.twinx()
    axg.plot(f.t_h, f.gradient, "k--", label="gradient T1 - T2")
    axg.set_ylabel("gradient T1 - T2 [degC]")
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = axg.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, fontsize=8, loc="lower left")
    ax.set_title(f"Temperature rate and gradient during the chamber cycle (unit {u.seed}, fitting run)")
    return fig


def before_after(units: Sequence[UnitResult]) -> Figure:
    """Held-out bias before and after compensation, first three units.

    Parameters
    ----------
    units : sequence of UnitResult
        The units' results.

    Returns
    -------
    Figure
        The figure.
    """
    from matplotlib.figure import Figure

    shown = units[:3]
    fig = Figure(figsize=(8.0, 2.6 * len(shown)), layout="constrained")
    axes = np.atleast_1d(fig.subplots(len(shown), 1, sharex=True))
    for k, (ax, u) in enumerate(zip(axes, shown, strict=True)):
        h, s = u.heldout, u.stability
        before, comp = h.output - h.truth, h.compensated - h.truth
        label_before = f"before: {s.heldout_before_deg_h:.4f} deg/h"
        ax.plot(h.t_h, before - before.mean(), color="tab:red", lw=1, label=label_before)
        ax.plot(h.t_h, comp - comp.mean(), color="tab:blue", lw=1, label=f"after: {s.heldout_after_deg_h:.4f} deg/h")
        ax.set_ylabel("bias - mean [deg/h]")
        ax.set_title(f"({'abc'[k]}) unit {u.seed}, held-out run: {s.heldout_ratio:.2f}x better")
        ax.legend(fontsize=8, loc="upper right")
    axes[-1].set_xlabel("time [h]")
    return fig


def population(rows: Sequence[Mapping[str, Any]]) -> Figure:
    """Every unit's 1 - R^2 against its before/after ratios, with the in-sample identity and the paper.

    Parameters
    ----------
    rows : sequence of mapping
        One row per unit (its R^2 and ratios).

    Returns
    -------
    Figure
        The figure.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.0, 4.6), layout="constrained")
    ax = fig.subplots()
    x = np.array([1.0 - r["r2"] for r in rows])
    ax.loglog(x, [r["fit_ratio"] for r in rows], "o", mfc="none", color="tab:gray", label="fitting run (in-sample)")
    ax.loglog(x, [r["heldout_ratio"] for r in rows], "o", color="tab:blue", label="held-out run")
    grid = np.geomspace(min(0.01, x.min() / 2), max(0.5, x.max() * 2), 100)
    ax.loglog(grid, 1.0 / np.sqrt(grid), "k-", lw=0.8, label="in-sample identity: ratio = 1/sqrt(1 - R^2)")
    paper_ratio = 1.0 / (1.0 - PAPER_IMPROVEMENT_PCT / 100.0)
    ax.loglog([1.0 - PAPER_ADJ_R2], [paper_ratio], "r*", ms=14, label="paper: adj. R^2 0.97, 65 %")
    ax.set_xlabel("1 - R^2 on the fitting run")
    ax.set_ylabel("bias stability before / after")
    ax.set_title("Units: fit quality vs improvement (one point per unit)")
    ax.legend(fontsize=8)
    return fig


def mode_hops(units: Sequence[UnitResult]) -> Figure:
    """PLC mode index against the logged cavity temperature, first three units.

    Parameters
    ----------
    units : sequence of UnitResult
        The units' results.

    Returns
    -------
    Figure
        The figure.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.0, 4.2), layout="constrained")
    ax = fig.subplots()
    for u in units[:3]:
        f = u.fit
        ax.plot(f.t2, f.mode - f.mode[0], ".-", lw=0.6, ms=2, label=f"unit {u.seed}")
    ax.set_xlabel("cavity temperature T2 (logged) [degC]")
    ax.set_ylabel("PLC mode index - initial")
    ax.set_title("Mode hops over the chamber cycle (fitting run): heating and cooling differ")
    ax.legend(fontsize=8)
    return fig
