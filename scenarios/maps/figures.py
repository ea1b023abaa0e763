"""A map's figures: each claim's phase diagram over its two most sensitive parameters, and the
specification curve (every region point's result sorted, the paper's value marked).

Axes are in the family's field units (log where the parameter is swept on a log scale). Each PNG
carries gyrobench's ``Software`` text chunk (:data:`gyrobench.base.safety.PNG_METADATA`).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from numpy.typing import NDArray  # noqa: E402

from gyrobench.base.safety import PNG_METADATA  # noqa: E402

from .region import ClaimMap, MapResult, Sensitivity  # noqa: E402

__all__ = ["constraint_maps", "covariate_maps", "phase_diagrams", "specification_curves"]


def _panels(n: int, height: float) -> tuple[Any, Any]:
    """A figure of ``n`` panels, three to a row, each 4.8 in wide and ``height`` in high (three panels at
    90 dpi: 1296 px, inside the report's 1400-px page at full size)."""
    cols = min(n, 3)
    rows = math.ceil(n / cols)
    return plt.subplots(rows, cols, figsize=(4.8 * cols, height * rows), squeeze=False, layout="constrained")


def _save(fig: Any, axes: Any, used: int, path: Path) -> Path:
    """Hide the panels past ``used``, write the PNG with gyrobench's marker, close the figure."""
    for ax in list(axes.flat)[used:]:
        ax.set_visible(False)
    fig.savefig(path, dpi=90, metadata=PNG_METADATA)
    plt.close(fig)
    return path


def _parameter_axes(ax: Any, result: MapResult, a: int, b: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Every design point's values of parameters ``a`` (x) and ``b`` (y), the axes labelled and
    logarithmic where the parameter is swept on a log scale."""
    params = result.family.parameters
    x = np.array([v[params[a].field] for v in result.design.values])
    y = np.array([v[params[b].field] for v in result.design.values])
    for j, axis in ((a, "x"), (b, "y")):
        if params[j].scale == "log":
            (ax.set_xscale if axis == "x" else ax.set_yscale)("log")
    ax.set_xlabel(params[a].axis_label())
    ax.set_ylabel(params[b].axis_label())
    return x, y


def _mark_nominal(ax: Any, result: MapResult, a: int, b: int) -> None:
    """The nominal device (the default reproduce's) as a black star, the region's medoid as a red
    diamond and the refined stage's points as black dots, on parameters ``a`` (x) and ``b`` (y)."""
    params = result.family.parameters
    second = [v for i, v in enumerate(result.design.values) if result.design.stage_of(i) == 2]
    if second:  # the refined stage's points (refine.py), dotted
        ax.scatter([v[params[a].field] for v in second], [v[params[b].field] for v in second], marker=".", s=14,
                   color="k", label="refined stage", zorder=3)
    if result.nominal is not None:
        v = result.nominal.values
        ax.scatter([v[params[a].field]], [v[params[b].field]], marker="*", s=260, color="k",
                   label="nominal device" + (" (in the region)" if result.nominal.in_region else ""), zorder=4)
    med = result.medoid
    if med is not None:
        v = result.design.values[med]
        ax.scatter([v[params[a].field]], [v[params[b].field]], marker="D", s=70, facecolors="none",
                   edgecolors="darkred", linewidths=1.8, label="region medoid", zorder=4)


def _short(text: str, width: int = 58) -> str:
    """``text`` cut to ``width`` characters (an ellipsis marks the cut)."""
    return text if len(text) <= width else text[: width - 3] + "..."


def _axes_of(result: MapResult, m: ClaimMap) -> tuple[int, int]:
    """Indices of the claim's two most sensitive parameters (the first two in family order when no
    parameter's rank correlation could be computed)."""
    return _top_two(result, m.sensitivity)


def _top_two(result: MapResult, sensitivity: tuple[Sensitivity, ...]) -> tuple[int, int]:
    names = result.family.names
    ranked = [names.index(s.field) for s in sensitivity if s.rho is not None]
    rest = [j for j in range(len(names)) if j not in ranked]
    order = ranked + rest
    return order[0], order[1] if len(order) > 1 else order[0]


def phase_diagrams(result: MapResult, path: Path) -> Path:
    """Each claim's pass rate over its two most sensitive parameters, one PNG.

    One PNG: per claim, every point's pass rate over its two most sensitive parameters; region
    points ringed in red, points that could not test the claim as grey crosses.

    Parameters
    ----------
    result : MapResult
        A map.
    path : Path
        The PNG to write.

    Returns
    -------
    Path
        ``path``.
    """
    claims = result.claims
    fig, axes = _panels(len(claims), 4.6)
    region = set(result.region)
    params = result.family.parameters
    sc = None
    for ax, m in zip(axes.flat, claims, strict=False):
        a, b = _axes_of(result, m)
        x, y = _parameter_axes(ax, result, a, b)
        rate = np.array(m.pass_rates())
        ok = np.isfinite(rate)
        sc = ax.scatter(x[ok], y[ok], c=rate[ok], cmap="viridis", vmin=0.0, vmax=1.0, s=70, edgecolors="none")
        ax.scatter(x[~ok], y[~ok], marker="x", color="0.6", s=40, label="not testable")
        inr = np.array([i in region for i in range(len(x))], bool)
        ax.scatter(x[inr], y[inr], facecolors="none", edgecolors="red", s=170, linewidths=1.6, label="region")
        _mark_nominal(ax, result, a, b)
        rho = {s.field: s.rho for s in m.sensitivity}
        ra, rb = rho.get(params[a].field), rho.get(params[b].field)
        tag = ", ".join(f"rho={r:+.2f}" if r is not None else "rho n/a" for r in (ra, rb))
        ax.set_title(f"{m.claim.id}\n{_short(m.verdict_text())}\n(Spearman {tag})", fontsize=8.5)
        ax.grid(True, which="both", alpha=0.25)
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncols=2, fontsize=9)
    if sc is not None:
        fig.colorbar(sc, ax=axes, shrink=0.6, label="pass rate over the point's units")
    fig.suptitle(f"paper {result.family.paper}: method claims over the device family "
                 f"({len(result.design)} points, {len(region)} in the region)")
    return _save(fig, axes, len(claims), path)


def specification_curves(result: MapResult, path: Path) -> Path:
    """Each claim's specification curve over the region points, one PNG.

    One PNG: per claim, the region points' median quantities sorted (every point when the region is
    empty, said in the title), the claim's band shaded and the paper's value as a dashed line.

    Parameters
    ----------
    result : MapResult
        A map.
    path : Path
        The PNG to write.

    Returns
    -------
    Path
        ``path``.
    """
    claims = result.claims
    fig, axes = _panels(len(claims), 3.9)
    region = list(result.region)
    which = region or list(range(len(result.design)))
    for ax, m in zip(axes.flat, claims, strict=False):
        yes_no = m.claim.comparator.kind == "is_true"
        vals = [(m.pass_rates()[i] if yes_no else m.medians[i], m.point_verdicts[i]) for i in which]
        vals = sorted((v for v in vals if math.isfinite(v[0])), key=lambda t: t[0])
        ys = np.array([v for v, _ in vals])
        colours = ["tab:green" if verdict == "holds" else "tab:red" for _, verdict in vals]
        ax.scatter(np.arange(len(ys)), ys, c=colours, s=30, zorder=3)
        c = m.claim.comparator
        if yes_no:
            ax.axhline(0.5, color="k", lw=0.8, ls=":", label="half the units")
            ax.set_ylabel("pass rate over the point's units")
            ax.set_ylim(-0.05, 1.05)
        else:
            lo = c.lo if math.isfinite(c.lo) else (float(ys.min()) if len(ys) else 0.0)
            hi = c.hi if math.isfinite(c.hi) else (float(ys.max()) if len(ys) else 1.0)
            ax.axhspan(min(lo, hi), max(lo, hi), color="tab:green", alpha=0.12, label="claim's band")
            if m.claim.paper_value is not None:
                ax.axhline(m.claim.paper_value, color="k", ls="--", lw=1.0, label="paper's value")
            pos = len(ys) and bool(np.all(ys > 0))
            if pos and ys.max() / ys.min() > 30:
                ax.set_yscale("log")
            unit = f" [{m.claim.unit}]" if m.claim.unit else ""
            ax.set_ylabel(f"median {m.claim.quantity}{unit}")
        ax.set_xlabel("points, sorted")
        where = "region points" if region else "all points (region empty)"
        ax.set_title(f"{m.claim.id}: {where}", fontsize=8.5)
        ax.legend(fontsize=7, loc="best")
        ax.grid(True, alpha=0.25)
    fig.suptitle(f"paper {result.family.paper}: specification curves (green: the point holds the claim)")
    return _save(fig, axes, len(claims), path)


def constraint_maps(result: MapResult, path: Path) -> Path:
    """Each reported device fact over its two most sensitive parameters, one PNG.

    One PNG: per reported device fact, every point's median quantity over the fact's two most
    sensitive parameters; points satisfying the fact ringed in green, region points in red.

    Parameters
    ----------
    result : MapResult
        A map.
    path : Path
        The PNG to write.

    Returns
    -------
    Path
        ``path``.
    """
    cons = result.constraints
    fig, axes = _panels(len(cons), 4.6)
    region = set(result.region)
    counts = result.counts()
    for j, (ax, c) in enumerate(zip(axes.flat, cons, strict=False)):
        sens = result.constraint_sensitivity(j)
        a, b = _top_two(result, sens)
        x, y = _parameter_axes(ax, result, a, b)
        med = np.array([row[j] for row in result.constraint_medians])
        ok = np.isfinite(med)
        sc = ax.scatter(x[ok], y[ok], c=med[ok], cmap="plasma", s=70, edgecolors="none")
        fig.colorbar(sc, ax=ax, label=f"median {c.quantity}")
        sat = np.array([result.satisfied[i][j] for i in range(len(x))], bool)
        ax.scatter(x[sat], y[sat], facecolors="none", edgecolors="green", s=150, linewidths=1.5, label="fact holds")
        inr = np.array([i in region for i in range(len(x))], bool)
        ax.scatter(x[inr], y[inr], facecolors="none", edgecolors="red", s=230, linewidths=1.5, label="region")
        ax.set_title(f"{c.id}: needs {c.comparator.text()}\nholds on {counts[c.id]} of {len(x)} points",
                     fontsize=8.5)
        ax.grid(True, which="both", alpha=0.25)
        ax.legend(fontsize=7, loc="best")
    fig.suptitle(f"paper {result.family.paper}: the reported device facts over the family")
    return _save(fig, axes, len(cons), path)


def covariate_maps(result: MapResult, path: Path) -> Path | None:
    """Each claim's pass rate against each covariate's point median, one PNG (None: no covariate).

    One panel per claim and covariate: every point's pass rate over the point's median of the
    covariate, region points ringed in red, the nominal device as a black star, Spearman's rho in
    the title.

    Parameters
    ----------
    result : MapResult
        A map.
    path : Path
        The PNG to write.

    Returns
    -------
    Path or None
        ``path``, or None when the family names no covariate (nothing written).
    """
    if not result.covariates:
        return None
    pairs = [(k, j) for j in range(len(result.covariates)) for k in range(len(result.claims))]
    fig, axes = _panels(len(pairs), 4.2)
    region = set(result.region)
    for ax, (k, j) in zip(axes.flat, pairs, strict=False):
        m, v = result.claims[k], result.covariates[j]
        x = np.array([row[j] for row in result.covariate_medians])
        rate = np.array(m.pass_rates())
        ok = np.isfinite(x) & np.isfinite(rate)
        inr = np.array([i in region for i in range(len(x))], bool)
        ax.scatter(x[ok], rate[ok], s=40, color="tab:blue", label="family point")
        ax.scatter(x[ok & inr], rate[ok & inr], facecolors="none", edgecolors="red", s=130, linewidths=1.5,
                   label="region")
        n = result.nominal
        if n is not None and math.isfinite(n.covariate_medians[j]) and n.testable[k]:
            ax.scatter([n.covariate_medians[j]], [n.holds[k] / n.testable[k]], marker="*", s=260, color="k",
                       label="nominal device", zorder=4)
        if ok.any() and np.all(x[ok] > 0) and x[ok].max() / x[ok].min() > 30:
            ax.set_xscale("log")
        rho, _, pts = result.covariate_sensitivity(k, j)
        tag = f"Spearman rho={rho:+.2f} over {pts} points" if rho is not None else f"rho n/a ({pts} points)"
        ax.set_title(f"{m.claim.id}\n{tag}", fontsize=8.5)
        ax.set_xlabel(f"point median: {v.label}")
        ax.set_ylabel("pass rate over the point's units")
        ax.set_ylim(-0.05, 1.05)
        ax.axhline(0.5, color="k", lw=0.8, ls=":")
        ax.grid(True, which="both", alpha=0.25)
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncols=3, fontsize=9)
    fig.suptitle(f"paper {result.family.paper}: the claims against the quantities they rest on")
    return _save(fig, axes, len(pairs), path)
