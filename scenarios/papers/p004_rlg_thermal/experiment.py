"""One unit of paper 004 (one gyro): stepwise model on its first turn-on, scored on its second.

:func:`experiment` returns a typed :class:`~.results.UnitResult` (no formatting);
:func:`compensation_task` hands the same runs to ``gyrobench bench``.

On the fitting run the least-squares residual has zero mean, so
``R^2 = 1 - (after_fit / before_fit)^2`` exactly: adjusted R^2 and the in-sample
bias-stability ratio are one number seen twice.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from gyrobench.analysis.compensation.stepwise import StepwiseRegression
from gyrobench.analysis.metrics import bias_stability, improvement_pct
from gyrobench.analysis.regressors import REGRESSOR_LABELS, REGRESSOR_NAMES
from gyrobench.analysis.thermal_regression import StepwiseTable, block_bias_stability, stepwise_table
from gyrobench.scenarios.base import CompensationTask, HeldOutRun

from . import NAME
from .claims import PAPER_DROPPED, PAPER_SELECTED
from .config import Config
from .results import FitTraces, GyroDraw, HeldoutTraces, HopEffect, Stability, UnitResult
from .simulation import Blocks, memory_estimate, runs, simulate

__all__ = [
    "experiment",
    "compensation_task",
    "bias_stability_scores",
    "has_kinds",
    "thermal_share",
    "truth_r2",
    "simulate",
    "memory_estimate",
]


def has_kinds(selected: Sequence[str]) -> bool:
    """Whether a selection uses temperature, rate and gradient information.

    Temperature: x1, x2 or a product with a temperature (x5, x6, x11). Rate: any
    rate term. Gradient: x9-x11, or the cavity rate terms, since the cavity node's
    rate is driven by the housing-cavity difference, C_b dT2/dt = g_a (T1 - T2) + ...
    (sim.rlg_cavity.CavityThermal; x4, x6, x8 carry the gradient).

    Parameters
    ----------
    selected : sequence of str
        The selected regressors' names.

    Returns
    -------
    bool
        True when temperature, rate and gradient information are all used.
    """
    s = set(selected)
    temp = bool(s & {"x1", "x2", "x5", "x6", "x11"})
    rate = bool(s & {"x3", "x4", "x5", "x6", "x7", "x8", "x10"})
    grad = bool(s & {"x4", "x6", "x8", "x9", "x10", "x11"})
    return temp and rate and grad


def thermal_share(fit: Blocks) -> float | None:
    """Share of the fitting run's 100-s means' variance the true thermal bias explains.

    var(thermal) / var(output - true rate), both over the run's 100-s means (n - 1); None
    when the output error does not vary.

    Parameters
    ----------
    fit : Blocks
        The fitting run.

    Returns
    -------
    float or None
        The share [-]; None when the output error does not vary.
    """
    err = np.var(fit.output - fit.truth, ddof=1)
    return float(np.var(fit.thermal, ddof=1) / err) if err > 0 else None


def truth_r2(fit: Blocks) -> float | None:
    """R^2 of the candidate regressors on the fitting run's true thermal bias.

    R^2 of the eleven candidate regressors x1..x11 regressed (least squares, with intercept) on the
    fitting run's *true* thermal bias (100-s means) [-]: how much of the effect the paper's model
    can represent at all. None when the true thermal bias does not vary.

    Parameters
    ----------
    fit : Blocks
        The fitting run.

    Returns
    -------
    float or None
        R^2 [-]; None when the true thermal bias does not vary.
    """
    y = fit.thermal - fit.thermal.mean()
    tss = float(y @ y)
    if not tss > 0:
        return None
    A = np.column_stack([np.ones(len(y)), fit.X])
    beta, *_ = np.linalg.lstsq(A, fit.thermal, rcond=None)
    r = fit.thermal - A @ beta
    return float(1.0 - (r @ r) / tss)


def _quantities(
    config: Config, model: StepwiseTable, stab: Stability, hops: HopEffect, share: float | None,
    r2_truth: float | None = None,
) -> dict[str, float | None]:
    """One number per claim quantity (booleans as 1.0 / 0.0)."""
    sel = set(model.selected)
    before, after = (
        (stab.fit_before_deg_h, stab.fit_after_deg_h)
        if config.score_in_sample
        else (stab.heldout_before_deg_h, stab.heldout_after_deg_h)
    )
    return {
        "thermal_share": share,
        "truth_r2": r2_truth,
        "keeps_paper_terms": float(set(PAPER_SELECTED) <= sel),
        "drops_other_terms": float(not (sel & set(PAPER_DROPPED))),
        "selects_paper_set": float(sel == set(PAPER_SELECTED)),
        "temperature_rate_gradient": float(has_kinds(model.selected)),
        "multiple_r": model.multiple_r,
        "one_minus_adj_r2": 1.0 - model.adj_r2,
        "rmse_deg_h": model.rmse,
        "significance_f": model.significance_f,
        "heldout_ratio": before / after if after > 0 else None,
        "hop_adj_r2_cost": hops.adj_r2_cost,
        "hop_ratio_cost": hops.ratio_cost,
    }


def _fit_and_score(
    config: Config, fit: Blocks, held: Blocks
) -> tuple[StepwiseTable, Stability, NDArray[np.float64]]:
    """Stepwise model on the fitting run; bias stabilities before/after on both runs [deg/h]."""
    m = StepwiseRegression(p_enter=config.p_enter, p_remove=config.p_remove).fit(fit.X, fit.output - fit.truth)
    comp_fit, comp_held = fit.output - m.predict(fit.X), held.output - m.predict(held.X)
    stab = Stability(
        fit_before_deg_h=block_bias_stability(fit.output, fit.truth),
        fit_after_deg_h=block_bias_stability(comp_fit, fit.truth),
        heldout_before_deg_h=block_bias_stability(held.output, held.truth),
        heldout_after_deg_h=block_bias_stability(comp_held, held.truth),
        heldout_floor_deg_h=block_bias_stability(held.output - held.thermal, held.truth),
    )
    return stepwise_table(m, REGRESSOR_LABELS), stab, comp_held


def _hop_effect(
    fit: Blocks,
    held: Blocks,
    model: StepwiseTable,
    stab: Stability,
    model_nh: StepwiseTable,
    stab_nh: Stability,
) -> HopEffect:
    """Hop counts and temperatures, and the hop run's results against the no-hop counterfactual."""
    n_fit = len(fit.hops_up) + len(fit.hops_down)
    n_held = len(held.hops_up) + len(held.hops_down)
    hopped = n_fit + n_held > 0
    return HopEffect(
        fit_hops=n_fit,
        heldout_hops=n_held,
        fit_up_degc=tuple(fit.hops_up.tolist()),
        fit_down_degc=tuple(fit.hops_down.tolist()),
        heldout_up_degc=tuple(held.hops_up.tolist()),
        heldout_down_degc=tuple(held.hops_down.tolist()),
        adj_r2_nohop=model_nh.adj_r2,
        heldout_ratio_nohop=stab_nh.heldout_ratio,
        selected_nohop=model_nh.selected,
        adj_r2_cost=(1.0 - model.adj_r2) / (1.0 - model_nh.adj_r2) if n_fit else None,
        ratio_cost=stab_nh.heldout_ratio / stab.heldout_ratio if hopped else None,
    )


def experiment(config: Config, seed: int) -> UnitResult:
    """One unit (one gyro): fit stepwise on its first turn-on, score on its second.

    Parameters
    ----------
    config : Config
    seed : int
        The unit (each seed is another gyro with its own two turn-ons).

    Returns
    -------
    UnitResult
        ``quantities`` (one per claim of :data:`.claims.CLAIMS`), ``model`` (Table-1
        statistics, coefficients, p-values, steps), ``stability`` (bias stability [deg/h]
        before and after on both runs, and the held-out noise floor), ``hops`` (mode hops and
        the same unit's results with a PLC of unlimited travel, same draws), ``gyro`` (the
        drawn parameters) and the ``fit`` and ``heldout`` traces (100-s blocks) the figures and
        the cross-unit table use.

    Raises
    ------
    ValueError
        If the chamber program gives fewer 100-s blocks than the stepwise fit needs.
    """
    gyro, fit, held = runs(config, seed)
    model, stab, comp_held = _fit_and_score(config, fit, held)
    _, fit_nh, held_nh = runs(config, seed, mode_hops=False)
    model_nh, stab_nh, _ = _fit_and_score(config, fit_nh, held_nh)
    hops = _hop_effect(fit, held, model, stab, model_nh, stab_nh)
    return UnitResult(
        seed=int(seed),
        quantities=_quantities(config, model, stab, hops, thermal_share(fit), truth_r2(fit)),
        model=model,
        stability=stab,
        hops=hops,
        gyro=GyroDraw(
            cte_ppm_per_k=float(gyro.cte * 1e6),
            hop_spacing_k=float(gyro.hop_spacing),
            hysteresis_k=float(gyro.hysteresis),
            lock_in_min_deg_s=float(np.min(fit.lock_in)),
            lock_in_max_deg_s=float(np.max(fit.lock_in)),
            thermal_bias_std_deg_h=float(np.std(fit.thermal, ddof=1)),
        ),
        fit=FitTraces(
            t_h=fit.t_h,
            output=fit.output,
            t1=fit.t1,
            t2=fit.t2,
            chamber=fit.chamber,
            mode=fit.mode,
            dt1=fit.X[:, 2],
            dt2=fit.X[:, 3],
            gradient=fit.X[:, 8],
        ),
        heldout=HeldoutTraces(
            t_h=held.t_h, X=held.X, output=held.output, truth=held.truth, compensated=comp_held
        ),
    )


def bias_stability_scores(compensated: NDArray[np.float64], run: HeldOutRun) -> dict[str, float]:
    """Scorer: bias stability (std of the 100-s means, n - 1) before and after compensation [deg/h].

    ``run.output`` and ``compensated`` are already 100-s block means, so each is one block.

    Parameters
    ----------
    compensated : ndarray
        Compensated 100-s means of a held-out run [deg/h].
    run : HeldOutRun
        The run.

    Returns
    -------
    dict of str to float
        Bias stability before and after [deg/h].
    """
    comp = np.asarray(compensated, float) - run.truth
    before = bias_stability(run.output - run.truth, 1.0, block_s=1.0)
    after = bias_stability(comp, 1.0, block_s=1.0)
    return {
        "bias_stability_deg_h": after,
        "before_deg_h": before,
        "improvement_pct": improvement_pct(before, after),
    }


def compensation_task(config: Config, seed: int) -> CompensationTask:
    """Unit ``seed``: training = its fitting run, held-out = its second run (100-s blocks).

    The held-out run is labelled ``"heldout"`` whatever the seed, so the bench's score names
    pair across seeds.

    Features: the eleven regressors x1..x11 (degC, degC/s); target: the output error
    [deg/h] (output minus true rate), as the paper compensates the bias.

    Parameters
    ----------
    config : Config
        The configuration.
    seed : int
        The unit's seed.

    Returns
    -------
    CompensationTask
        The fitting run and the held-out run, as 100-s blocks.
    """
    _, fit, held = runs(config, seed)
    return CompensationTask(
        scenario=NAME,
        feature_names=tuple(f"{lab} {nm}" for lab, nm in zip(REGRESSOR_LABELS, REGRESSOR_NAMES, strict=True)),
        X_train=fit.X,
        y_train=fit.output - fit.truth,
        heldout=(HeldOutRun(label="heldout", X=held.X, output=held.output, truth=held.truth),),
        target="error",
        unit="deg/h",
        scorer=bias_stability_scores,
    )
