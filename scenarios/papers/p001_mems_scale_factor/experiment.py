"""One paper-001 unit through the whole pipeline: :func:`experiment` -> :class:`~.results.UnitResult`.

Methods (paper section 4): the heuristic breakpoint search (Table 2, run unchanged:
:func:`gyrobench.analysis.scale_factor.breakpoint_search`; where it splits is a result), the
piecewise 9-1-9 polynomial with cubic Hermite joins, the two-stage 9th-order polynomial and a
Bayesian-regularized BP network with 10 hidden units (Table 3: 0.14 %, 0.59 %, 0.45 %).

Each method is fitted on the pooled per-rate means of the unit's ``n_fit_runs`` runs and
scored by the IEEE K_n of the compensated table against the table rates

* at the 21 table rates of the held-out run(s) (claims), and of the fitting runs (in-sample,
  the paper's own scoring, reported);
* on a dense held-out sweep: the noise-free static output of each held-out power-on (its
  turn-on errors at its die temperature, no quantization) every ``dense_step_dps`` over the
  table's range (claims), so K_n also sees the model error between the table rates.

:func:`compensation_task` hands the same runs to ``gyrobench bench``. No formatting here.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gyrobench.analysis.scale_factor import (
    breakpoint_search,
    fit_scale_factor,
    range_nonlinearity,
    repeatability_floor,
)
from gyrobench.base import units
from gyrobench.scenarios.base import CompensationTask, HeldOutRun

from . import NAME
from .config import PAPER_ORDER, PAPER_RAW_KN, Config
from .device import device_spec, rate_authority_dps, rate_transfer, static_output
from .identify import LOW_RATE_LIMIT_DPS
from .rate_table import dense_rates, run_means, simulate_runs, trace
from .results import DeviceSummary, Join, MethodScore, MlpFit, RawAnalysis, UnitResult

__all__ = [
    "compensation_task",
    "experiment",
    "hermite_error_ratio",
    "local_features_ratio",
    "nonlinearity_scorer",
    "quantities",
    "raw_analysis",
    "score_method",
]


def nonlinearity_scorer(compensated: NDArray[np.float64], run: HeldOutRun) -> dict[str, float]:
    """K_n [%] of the compensated table against the table rates (IEEE), and the RMS error.

    Parameters
    ----------
    compensated : ndarray
        The compensated rates of a held-out run [deg/s].
    run : HeldOutRun
        The run (its table rates).

    Returns
    -------
    dict of str to float
        ``"nonlinearity_pct"`` (K_n [%]) and ``"rms_dps"`` [deg/s].
    """
    fit = fit_scale_factor(run.truth, np.asarray(compensated, dtype=float))
    err = np.asarray(compensated, dtype=float) - run.truth
    return {"nonlinearity_pct": fit.nonlinearity_pct, "rms_dps": float(np.sqrt(np.mean(err**2)))}


def _estimators(config: Config, seed: int) -> dict[str, Any]:
    from gyrobench.analysis.compensation.bayes_mlp import BayesianRegularizedMLP
    from gyrobench.analysis.compensation.polynomial import PiecewisePolynomial, TwoStagePolynomial

    return {
        "piecewise": PiecewisePolynomial(
            orders=tuple(config.orders),
            join=config.join,
            join_width=config.join_width,
            alpha=config.piecewise_alpha,
        ),
        "two_stage_poly": TwoStagePolynomial(
            degree=config.poly_degree, second_degree=config.poly_degree
        ),
        "bayes_bp": BayesianRegularizedMLP(
            hidden_units=config.hidden_units, epochs=config.mlp_epochs, random_state=seed
        ),
    }


def compensation_task(config: Config, seed: int) -> CompensationTask:
    """Features = per-rate mean outputs [deg/s] of the fitting runs, target = table rate [deg/s].

    Parameters
    ----------
    config : Config
        The configuration.
    seed : int
        The unit's seed.

    Returns
    -------
    CompensationTask
        The fitting runs' features and targets, and the held-out runs.
    """
    rates = np.asarray(config.rates_dps, dtype=float)
    means = [run_means(config, run) for run in simulate_runs(config, seed)]
    fit = means[: config.n_fit_runs]
    held = tuple(
        HeldOutRun(label=f"heldout{i}", X=m[:, None], output=m, truth=rates.copy())
        for i, m in enumerate(means[config.n_fit_runs :])
    )
    return CompensationTask(
        scenario=NAME,
        feature_names=("output_dps",),
        X_train=np.concatenate(fit)[:, None],
        y_train=np.tile(rates, len(fit)),
        heldout=held,
        target="rate",
        unit="deg/s",
        scorer=nonlinearity_scorer,
    )


def _mean_kn(rates: NDArray[np.float64], tables: Any) -> float:
    """Mean K_n [%] of compensated rate tables against the table rates."""
    return float(np.mean([fit_scale_factor(rates, c).nonlinearity_pct for c in tables]))


def _floor_kn(rates: NDArray[np.float64], fit_means: NDArray[np.float64], outputs: NDArray[np.float64]) -> float:
    """Mean K_n [%] of ``outputs`` (one table per row) compensated by repeatability_floor.

    NaN when the fitting runs' mean outputs do not increase strictly with rate (a saturated
    device's flat plateau): no curve through them can be inverted there.
    """
    xm = np.asarray(fit_means, dtype=float).mean(axis=0)
    if np.any(np.diff(xm[np.argsort(rates)]) <= 0):
        return math.nan
    return _mean_kn(rates, [repeatability_floor(rates, fit_means, o) for o in outputs])


def raw_analysis(
    rates: NDArray[np.float64], fit_means: NDArray[np.float64], held_means: NDArray[np.float64]
) -> RawAnalysis:
    """Table 1 (mean of the fitting runs), raw K_n, the heuristic search (Table 2), low-rate K_n.

    Parameters
    ----------
    rates : ndarray
        Table rates [deg/s].
    fit_means : ndarray
        The fitting runs' mean outputs [deg/s], one row per run.
    held_means : ndarray
        The held-out runs' [deg/s].

    Returns
    -------
    RawAnalysis
        Table 1, raw K_n, Table 2's search and the low-rate K_n.
    """
    table1 = fit_means.mean(axis=0)
    fit1 = fit_scale_factor(rates, table1)
    search = breakpoint_search(rates, table1)
    low_kn = math.nan
    if search.negative is not None and search.positive is not None:
        low_kn = range_nonlinearity(rates, table1, search.negative, search.positive)
    per_run = tuple(fit_scale_factor(rates, m).nonlinearity_pct for m in fit_means)
    std = fit_means.std(axis=0, ddof=1) if len(fit_means) > 1 else np.zeros_like(rates)
    return RawAnalysis(
        table1_dps=table1,
        run_std_dps=std,
        pointwise_pct=100.0 * fit1.pointwise,
        scale_factor=fit1.scale_factor,
        bias_dps=fit1.bias,
        raw_kn_pct_per_run=per_run,
        raw_kn_pct=float(np.mean(per_run)),
        raw_kn_pct_heldout=_mean_kn(rates, held_means),
        low_rate_kn=low_kn,
        low_rate_kn_paper=range_nonlinearity(rates, table1, -LOW_RATE_LIMIT_DPS, LOW_RATE_LIMIT_DPS),
        breakpoints_dps=tuple(search.breakpoints),
        search_trace=search.trace,
    )


def _fit_methods(
    config: Config, seed: int, rates: NDArray[np.float64], fit_means: NDArray[np.float64]
) -> tuple[dict[str, Any], dict[str, float], dict[str, str]]:
    """The three compensators fitted on the pooled fitting runs, and their fit times [ms].

    A method that cannot be fitted on this unit's data (ValueError: e.g. a 9th-order piecewise
    segment beyond a breakpoint where the saturated plateau leaves fewer than 10 distinct
    outputs) is None, its error message in the third item.
    """
    X, y = fit_means.reshape(-1)[:, None], np.tile(rates, len(fit_means))
    models: dict[str, Any] = _estimators(config, seed)
    fit_ms: dict[str, float] = {}
    errors: dict[str, str] = {}
    for key, est in models.items():
        t0 = time.perf_counter()
        try:
            est.fit(X, y)
        except ValueError as exc:
            models[key], errors[key] = None, str(exc)
        fit_ms[key] = 1e3 * (time.perf_counter() - t0)
    return models, fit_ms, errors


def score_method(
    est: Any,
    rates: NDArray[np.float64],
    fit_means: NDArray[np.float64],
    held_means: NDArray[np.float64],
    dense_rates_dps: NDArray[np.float64],
    dense_outputs: NDArray[np.float64],
) -> MethodScore:
    """K_n [%] of one fitted compensator: in-sample, held-out table rates, dense held-out sweep.

    ``est`` None (the method could not be fitted): every number NaN (untestable).

    Parameters
    ----------
    est : estimator or None
        The fitted compensator (None: it could not be fitted).
    rates : ndarray
        Table rates [deg/s].
    fit_means : ndarray
        The fitting runs' mean outputs [deg/s].
    held_means : ndarray
        The held-out runs' [deg/s].
    dense_rates_dps : ndarray
        The dense sweep's rates [deg/s].
    dense_outputs : ndarray
        The held-out power-ons' noise-free outputs there [deg/s].

    Returns
    -------
    MethodScore
        The K_n figures [%].
    """
    if est is None:
        nan = math.nan
        return MethodScore(
            kn_fit_pct=nan, kn_heldout_pct=nan, rms_heldout_pct=nan, kn_dense_pct=nan,
            compensated_heldout_dps=np.full(rates.size, nan),
            pointwise_heldout_pct=np.full(rates.size, nan),
            dense_error_dps=np.full(dense_rates_dps.size, nan),
        )
    held = [est.predict(m[:, None]) for m in held_means]
    hfits = [fit_scale_factor(rates, c) for c in held]
    dense = [est.predict(d[:, None]) for d in dense_outputs]
    return MethodScore(
        kn_fit_pct=_mean_kn(rates, [est.predict(m[:, None]) for m in fit_means]),
        kn_heldout_pct=float(np.mean([f.nonlinearity_pct for f in hfits])),
        rms_heldout_pct=float(np.mean([100 * np.sqrt(np.mean(f.pointwise**2)) for f in hfits])),
        kn_dense_pct=_mean_kn(dense_rates_dps, dense),
        compensated_heldout_dps=held[0],
        pointwise_heldout_pct=100.0 * hfits[0].pointwise,
        dense_error_dps=dense[0] - dense_rates_dps,
    )


def _continuity(model: Any, fit_means: NDArray[np.float64], rates: NDArray[np.float64]) -> tuple[Join, ...]:
    """Curves of the piecewise fit around each breakpoint, with and without the Hermite join."""
    X, y = fit_means.reshape(-1), np.tile(rates, len(fit_means))
    out = []
    step = float(np.median(np.abs(np.diff(fit_means.mean(axis=0)))))  # output spacing of the rates
    for k, (b, br) in enumerate(zip(model.breakpoints_, model.breakpoint_rates_, strict=True)):
        x0, x1 = model.joins_[k]
        h = 0.5 * (x1 - x0)
        half = max(4 * h, 0.5 * step)
        xs = np.linspace(b - half, b + half, 200)
        m = np.abs(X - b) < half
        out.append(
            Join(
                breakpoint=float(0.5 * (x0 + x1)),
                rate_dps=float(br),
                half_join=float(h),
                x=xs,
                left=model.segments_[k].predict(xs[:, None]),
                right=model.segments_[k + 1].predict(xs[:, None]),
                joined=model.predict(xs[:, None]),
                data_x=X[m],
                data_y=y[m],
            )
        )
    return tuple(out)


#: half width of the band of table rates around a breakpoint swept for the join's error [deg/s]
#: (one table step) and the rate step of that sweep [deg/s]
JOIN_SWEEP_DPS, JOIN_SWEEP_STEP_DPS = 360.0, 0.25


def hermite_error_ratio(model: Any, held: Sequence[Any], config: Config) -> float:
    """The Hermite join's effect near the breakpoints (paper fig. 4) on the held-out power-ons.

    On each held-out power-on's noise-free static output, swept every
    :data:`JOIN_SWEEP_STEP_DPS` over +-:data:`JOIN_SWEEP_DPS` around each breakpoint rate, the
    largest |compensated - true rate| of the joined curve over the outputs inside the joins,
    divided by the same for the segments alone (switching at the breakpoints,
    ``PiecewisePolynomial.predict_unjoined``) [-]: <= 1 when the continuity processing does
    not increase the error near the breakpoints. NaN without a fitted model, a join of
    non-zero width or a swept output inside one.

    Parameters
    ----------
    model : PiecewisePolynomial or None
        The fitted piecewise model.
    held : sequence of HeldOutRun
        The held-out power-ons.
    config : Config
        The configuration.

    Returns
    -------
    float
        The joined curve's largest error near the breakpoints over the segments' alone [-]; NaN
        when untestable.
    """
    if model is None or not any(x1 > x0 for x0, x1 in model.joins_):
        return math.nan
    lo, hi = min(config.rates_dps), max(config.rates_dps)
    offsets = np.arange(-JOIN_SWEEP_DPS, JOIN_SWEEP_DPS + 0.5 * JOIN_SWEEP_STEP_DPS, JOIN_SWEEP_STEP_DPS)
    rates = np.concatenate([np.clip(br + offsets, lo, hi) for br in model.breakpoint_rates_])
    inside = np.zeros(0, dtype=bool)
    joined, bare = [], []
    for r in held:
        out = static_output(r.unit, rates, r.temperature, rate_transfer(config))
        inside = np.zeros(out.size, dtype=bool)
        for x0, x1 in model.joins_:
            inside |= (out >= x0) & (out <= x1) & (x1 > x0)
        if inside.any():
            xs = out[inside][:, None]
            joined.append(np.max(np.abs(model.predict(xs) - rates[inside])))
            bare.append(np.max(np.abs(model.predict_unjoined(xs) - rates[inside])))
    if not bare or max(bare) == 0:
        return math.nan
    return float(max(joined) / max(bare))


def local_features_ratio(
    config: Config, rates: NDArray[np.float64], fit_means: NDArray[np.float64], piecewise: MethodScore
) -> float:
    """The paper's premise that one fitting function describes the data poorly, as a ratio.

    The paper's premise that the data have several significant local features, which one fitting
    function describes poorly [-]: the in-sample K_n of one ``poly_degree`` polynomial fitted to the
    pooled fitting runs, over the piecewise fit's in-sample K_n. NaN when either cannot be fitted.

    Parameters
    ----------
    config : Config
        The configuration (its ``poly_degree``).
    rates : ndarray
        Table rates [deg/s].
    fit_means : ndarray
        The fitting runs' mean outputs [deg/s].
    piecewise : MethodScore
        The piecewise fit's scores.

    Returns
    -------
    float
        One polynomial's in-sample K_n over the piecewise fit's [-]; NaN when either cannot be fitted.
    """
    from gyrobench.analysis.compensation.polynomial import PolynomialRegressor

    X, y = fit_means.reshape(-1)[:, None], np.tile(rates, len(fit_means))
    try:
        one = PolynomialRegressor(degree=config.poly_degree).fit(X, y)
    except ValueError:
        return math.nan
    kn_one = _mean_kn(rates, [one.predict(m[:, None]) for m in fit_means])
    kn_pw = piecewise.kn_fit_pct
    return kn_one / kn_pw if math.isfinite(kn_pw) and kn_pw > 0 else math.nan


def _none_if_nan(x: float) -> float | None:
    return x if math.isfinite(x) else None


def _eval_times_ms(models: Mapping[str, Any], x: NDArray[np.float64], repeats: int) -> dict[str, float]:
    """Median wall time [ms] of each model compensating the 21-point table ``x`` (this machine)."""
    out = {}
    for key, est in models.items():
        if est is None:
            out[key] = math.nan
            continue
        est.predict(x)  # warm caches
        ts = []
        for _ in range(repeats):
            t0 = time.perf_counter()
            est.predict(x)
            ts.append(time.perf_counter() - t0)
        out[key] = 1e3 * float(np.median(ts))
    return out


def _before(order: Sequence[str], kn: Mapping[str, float]) -> bool:
    """Whether the K_n values are strictly increasing in ``order`` (best first)."""
    return all(kn[a] < kn[b] for a, b in zip(order[:-1], order[1:], strict=True))


def _flag(values: Mapping[str, float], holds: bool) -> float | None:
    """A ranking as 1.0 / 0.0, or None (untestable) when a method has no value (not fitted)."""
    if any(not math.isfinite(v) for v in values.values()):
        return None
    return float(holds)


def _run_spread_ratio(raw: RawAnalysis) -> float:
    """Largest run-to-run standard deviation of the output at a table rate, over the amplitude
    of the nonlinearity (K_n F_m, F_m = max |Table 1|) [-]: small when the runs' curves are alike;
    inf when only the amplitude is 0 (judged: the runs differ by more than a nonlinearity there is
    not), NaN when both are 0 (no nonlinearity to compare the runs with: the unit cannot test the
    claim; inf there would fail it on identical runs)."""
    amplitude = raw.raw_kn_pct / 100.0 * float(np.max(np.abs(raw.table1_dps)))
    spread = float(np.max(raw.run_std_dps))
    if amplitude > 0:
        return spread / amplitude
    return math.inf if spread > 0 else math.nan


def _miss(breakpoints: Sequence[float], side: float) -> float | None:
    """|b - side x LOW_RATE_LIMIT_DPS| [deg/s] of the breakpoint on ``side`` (+1 or -1); None without one."""
    b = next((b for b in breakpoints if side * b > 0), None)
    return None if b is None else abs(b - side * LOW_RATE_LIMIT_DPS)


def quantities(
    raw: RawAnalysis, methods: Mapping[str, MethodScore], hermite_ratio: float = math.nan
) -> dict[str, float | None]:
    """One number per claim quantity (see ``claims.CLAIMS``); booleans as 1.0 / 0.0.

    Beside them, for the device family's constraints (:mod:`.family`), how far from the paper's
    breakpoint the heuristic split each side: ``breakpoint_positive_miss_dps`` and
    ``breakpoint_negative_miss_dps`` = |b - (+-1800)| [deg/s] (None where it did not split that side).

    ``hermite_ratio``: :func:`hermite_error_ratio` of the piecewise fit (NaN: untestable).

    Parameters
    ----------
    raw : RawAnalysis
        Table 1, raw K_n and the breakpoint search.
    methods : mapping of str to MethodScore
        Each method's scores.
    hermite_ratio : float
        :func:`hermite_error_ratio` of the piecewise fit (NaN: untestable).

    Returns
    -------
    dict of str to float or None
        Claim quantity -> the unit's number.
    """
    held = {k: m.kn_heldout_pct for k, m in methods.items()}
    dense = {k: m.kn_dense_pct for k, m in methods.items()}
    rms = {k: m.rms_heldout_pct for k, m in methods.items()}
    others = [k for k in methods if k != "piecewise"]
    q: dict[str, float | None] = {
        "raw_kn_pct": raw.raw_kn_pct,
        "raw_kn_ratio": raw.raw_kn_pct / (100.0 * PAPER_RAW_KN),
        "run_spread_ratio": _run_spread_ratio(raw),
        "breakpoints_at_1800": float(raw.breakpoints_dps == (-1800.0, 1800.0)),
        "breakpoint_positive_miss_dps": _miss(raw.breakpoints_dps, 1.0),
        "breakpoint_negative_miss_dps": _miss(raw.breakpoints_dps, -1.0),
        "low_rate_kn": raw.low_rate_kn_paper,
    }
    for key in methods:
        q[f"kn_heldout_pct.{key}"] = held[key]
        q[f"improvement.{key}"] = raw.raw_kn_pct_heldout / held[key]
    q["order_as_paper"] = _flag(held, _before(PAPER_ORDER, held))
    q["piecewise_best"] = _flag(held, all(held["piecewise"] < held[k] for k in others))
    q["bayes_bp_beats_two_stage"] = _flag(held, held["bayes_bp"] < held["two_stage_poly"])
    q["piecewise_smallest_rms"] = _flag(rms, all(rms["piecewise"] < rms[k] for k in others))
    for key in methods:
        q[f"kn_dense_pct.{key}"] = dense[key]
    q["order_as_paper_dense"] = _flag(dense, _before(PAPER_ORDER, dense))
    q["hermite_error_ratio"] = hermite_ratio if math.isfinite(hermite_ratio) else None
    return q


def experiment(config: Config, seed: int) -> UnitResult:
    """One unit: its rate-table runs, raw K_n and breakpoints, the three methods fitted and scored.

    Returns the unit's ``quantities`` (one number per claim, see ``claims.CLAIMS``) and
    what the report draws: Table 1 and the breakpoint search of the fitting runs,
    per method the in-sample, held-out and dense-sweep K_n [%] and curves, the
    repeatability floor, the unit's rate authority, a 1 Hz trace of fitting run 0.
    Deterministic in (config, seed) except ``timing_ms`` and ``fit_time_ms`` (wall times).

    Parameters
    ----------
    config : Config
        The configuration.
    seed : int
        The unit's seed.

    Returns
    -------
    UnitResult
        The unit's quantities and what the report draws.
    """
    runs = simulate_runs(config, seed)
    rates = np.asarray(config.rates_dps, dtype=float)
    nf = config.n_fit_runs
    means = np.array([run_means(config, run) for run in runs])
    fit_means, held_means = means[:nf], means[nf:]
    raw = raw_analysis(rates, fit_means, held_means)
    dense = dense_rates(config)
    dense_out = np.array([static_output(r.unit, dense, r.temperature, rate_transfer(config)) for r in runs[nf:]])
    models, fit_ms, fit_errors = _fit_methods(config, seed, rates, fit_means)
    pw, bp = models["piecewise"], models["bayes_bp"]
    methods = {
        k: score_method(est, rates, fit_means, held_means, dense, dense_out)
        for k, est in models.items()
    }
    nom = device_spec(config).nominal
    return UnitResult(
        seed=seed,
        variant=config.variant,
        quantities={
            **quantities(raw, methods, hermite_error_ratio(pw, runs[nf:], config)),
            "local_features_ratio": _none_if_nan(local_features_ratio(config, rates, fit_means, methods["piecewise"])),
        },
        rates_dps=rates,
        fit_means_dps=fit_means,
        held_means_dps=held_means,
        raw=raw,
        raw_kn_dense_pct=_mean_kn(dense, dense_out),
        dense_rates_dps=dense,
        methods=methods,
        floor_pct=_floor_kn(rates, fit_means, held_means),
        floor_fit_pct=_floor_kn(rates, fit_means, fit_means),
        device=DeviceSummary(
            dac_full_scale_v=float(nom.dac_full_scale),
            scale_factor_repeatability_ppm=float(units.to_ppm(nom.scale_factor_repeatability)),
            rate_authority_dps=rate_authority_dps(runs[0].unit),
        ),
        piecewise_orders=() if pw is None else tuple(pw.orders_),
        continuity=() if pw is None else _continuity(pw, fit_means, rates),
        mlp=None if bp is None else MlpFit(gamma=bp.gamma_, epochs_run=bp.n_iter_),
        fit_errors=fit_errors,
        trace=trace(config, runs[0]),
        timing_ms=_eval_times_ms(models, held_means[0][:, None], config.timing_repeats),
        fit_time_ms=fit_ms,
    )
