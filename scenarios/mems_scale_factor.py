"""Seed paper 001: a +-3600 deg/s MEMS gyro on a rate table, scale-factor nonlinearity and its compensation.

Protocol (paper section 3): the gyro is powered and warmed up (20-30 min), then
the table steps through 21 rates, +3600 -> -3600 deg/s in 360 deg/s steps; the
output is sampled at 200 Hz and averaged over 1-2 min of each settled dwell.
Several runs are made; Table 1 is the per-rate mean over runs, the raw
nonlinearity is the mean of the runs' K_n (paper: 15.71 %).

Methods (paper section 4): the heuristic breakpoint search (Table 2), the
piecewise 9-1-9 polynomial with cubic Hermite joins, the two-stage 9th-order
polynomial and a Bayesian-regularized BP network with 10 hidden units (Table 3:
0.14 %, 0.59 %, 0.45 %; 0.247, 0.755, 37.8 ms).

Here every compensator is fitted on the per-rate means of the ``n_fit_runs``
runs (pooled, as the paper fits "several groups of data") and scored by the IEEE
K_n of the compensated table both on those runs and on ``n_heldout_runs``
further runs of the same gyro that the fit never saw (different turn-on bias,
ambient temperature and noise). The compensated rate is scored against the
table rate (the truth).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
from matplotlib.figure import Figure
from numpy.typing import NDArray

from analysis.compensation.bayes_mlp import BayesianRegularizedMLP
from analysis.compensation.polynomial import PiecewisePolynomial, TwoStagePolynomial
from analysis.scale_factor import asymmetry, breakpoint_search, fit_scale_factor
from scenarios.base import CompensationTask, FigureSpec, Headline, HeldOutRun, Outcome, Table
from sim import units
from sim.environment import rate_steps
from sim.mems import MemsSpec, die_temperature, simulate_output
from sim.recording import Channel, Recording, package_version

NAME = "mems_scale_factor"
TITLE = "High-range MEMS gyro: scale-factor nonlinearity and heuristic piecewise compensation (paper 001)"

#: the paper's numbers (Table 3 and text)
PAPER = {
    "raw_nonlinearity_pct": 15.71,
    "breakpoints_dps": [-1800.0, 1800.0],
    "orders": [9, 1, 9],
    "methods": {
        "piecewise": {"nonlinearity_pct": 0.14, "eval_time_ms": 0.247},
        "two_stage_poly": {"nonlinearity_pct": 0.59, "eval_time_ms": 0.755},
        "bayes_bp": {"nonlinearity_pct": 0.45, "eval_time_ms": 37.8},
    },
}
#: run-to-run scale-factor changes of the sensitivity table (Table 4) [-]
SF_CHANGES = (0.0, 1e-4, 3e-4, 1e-3)
METHOD_LABELS = {
    "piecewise": "Heuristic piecewise 9-1-9 + Hermite",
    "two_stage_poly": "Two-stage 9th-order polynomial",
    "bayes_bp": "Bayes-regularized BP (10 hidden)",
}


def _default_rates() -> tuple[float, ...]:
    return tuple(float(r) for r in np.arange(3600.0, -3600.0 - 1.0, -360.0))


@dataclass(frozen=True, slots=True, kw_only=True)
class Config:
    """The paper's rate-table test and methods (field units at this edge).

    Parameters
    ----------
    gyro : MemsSpec
        The unit under test (SI; defaults calibrated to K_n = 15.71 %, see sim.mems).
    rates_dps : tuple of float
        Table rates in test order [deg/s], strictly monotonic.
    dwell_s, settle_s : float
        Time at each rate and the part discarded before averaging [s] (90 s averaged).
    acceleration_dps2 : float
        Table acceleration between rates [deg/s^2].
    lead_in_s : float
        Zero-rate time at the start of the record [s].
    warmup_s : float
        Power-on time before the record starts [s] (paper: 20-30 min).
    fs_hz : float
        Sample rate [Hz].
    ambient_c, ambient_spread_c : float
        Mean lab temperature and its run-to-run standard deviation [degC].
    n_fit_runs, n_heldout_runs : int
        Runs used for Table 1 and the fits; runs kept for scoring only.
    orders : tuple of int
        Piecewise orders (negative high, low, positive high rates).
    join_width : float
        Hermite join width as a fraction of the output span.
    piecewise_alpha : float
        Curvature penalty of the piecewise segments (scaled units).
    poly_degree : int
        Degree of both stages of the two-stage polynomial.
    hidden_units, mlp_epochs : int
        Bayesian-regularized network size and trainbr epochs.
    timing_repeats : int
        Repeats of each method's compensation of the 21-point table (median reported).
    """

    gyro: MemsSpec = field(default_factory=MemsSpec)
    rates_dps: tuple[float, ...] = field(default_factory=_default_rates)
    dwell_s: float = 100.0
    settle_s: float = 10.0
    acceleration_dps2: float = 100.0
    lead_in_s: float = 10.0
    warmup_s: float = 1500.0
    fs_hz: float = 200.0
    ambient_c: float = 25.0
    ambient_spread_c: float = 0.5
    n_fit_runs: int = 3
    n_heldout_runs: int = 1
    orders: tuple[int, int, int] = (9, 1, 9)
    join_width: float = 0.05
    piecewise_alpha: float = 1e-6
    poly_degree: int = 9
    hidden_units: int = 10
    mlp_epochs: int = 1000
    timing_repeats: int = 200

    def __post_init__(self) -> None:
        if not isinstance(self.gyro, MemsSpec):
            raise TypeError(f"Config.gyro must be a MemsSpec; got {type(self.gyro).__name__}")
        r = np.asarray(self.rates_dps, dtype=float)
        if r.ndim != 1 or r.size < 3 or not np.all(np.isfinite(r)):
            raise ValueError(
                f"Config.rates_dps must hold at least 3 finite rates [deg/s]; got {self.rates_dps!r}"
            )
        d = np.diff(r)
        if not (np.all(d > 0) or np.all(d < 0)):
            raise ValueError(
                f"Config.rates_dps must be strictly monotonic without duplicates [deg/s]; got {self.rates_dps!r}"
            )
        for name, unit in (("dwell_s", "s"), ("acceleration_dps2", "deg/s^2"), ("fs_hz", "Hz")):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ValueError(f"Config.{name} must be > 0 {unit}; got {v!r}")
        for name in ("settle_s", "lead_in_s", "warmup_s", "ambient_spread_c", "piecewise_alpha"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0):
                raise ValueError(f"Config.{name} must be finite and >= 0; got {v!r}")
        if not self.settle_s < self.dwell_s:
            raise ValueError(
                f"Config.settle_s must be < dwell_s = {self.dwell_s} s; got {self.settle_s!r}"
            )
        for name, lo in (
            ("n_fit_runs", 1),
            ("n_heldout_runs", 1),
            ("poly_degree", 0),
            ("hidden_units", 1),
            ("mlp_epochs", 1),
            ("timing_repeats", 1),
        ):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int) or v < lo:
                raise ValueError(f"Config.{name} must be an integer >= {lo}; got {v!r}")
        if len(self.orders) != 3 or any(
            isinstance(o, bool) or not isinstance(o, int) or o < 0 for o in self.orders
        ):
            raise ValueError(f"Config.orders must be three integers >= 0; got {self.orders!r}")
        if not 0 < self.join_width < 0.5:
            raise ValueError(f"Config.join_width must be in (0, 0.5); got {self.join_width!r}")


# ------------------------------------------------------------------ simulation
def _program(config: Config):
    return rate_steps(
        units.deg_per_s(np.asarray(config.rates_dps, dtype=float)),
        dwell=config.dwell_s,
        settle=config.settle_s,
        acceleration=units.deg_per_s(config.acceleration_dps2),
        lead_in=config.lead_in_s,
    )


def _simulate_run(
    config: Config, program, rng: np.random.Generator, *, index: int, role: str, seed: int
) -> Recording:
    r_amb, r_gyro = rng.spawn(2)
    fs = config.fs_hz
    n = int(math.floor(program.profile.duration * fs)) + 1
    t = np.arange(n) / fs
    rate = program.profile(t)
    ambient = units.celsius(config.ambient_c + config.ambient_spread_c * r_amb.standard_normal())
    temp = die_temperature(config.gyro, ambient, t + config.warmup_s)
    out = simulate_output(
        config.gyro, rate, fs=fs, temperature=temp, acceleration=units.G0, rng=r_gyro
    )
    truth = {"true_rate": Channel(rate, "rad/s", "table rate (truth)")}
    truth.update({k: Channel(v, "rad/s", f"{k} error") for k, v in out.components.items()})
    return Recording(
        fs=fs,
        channels={
            "rate": Channel(out.output, "rad/s", "gyro output"),
            "table_rate": Channel(rate, "rad/s", "rate-table rate"),
            "temperature": Channel(temp, "K", "die temperature"),
        },
        truth=truth,
        metadata={
            "scenario": NAME,
            "seed": seed,
            "run": index,
            "role": role,
            "rates_dps": list(config.rates_dps),
            "windows_s": program.windows.tolist(),
            "ambient_c": float(units.to_celsius(ambient)),
            "turn_on_bias_dps": float(units.to_deg_per_s(out.turn_on_bias)),
            "version": package_version(),
        },
        name=f"{role}_run{index}",
    )


def simulate(config: Config, seed: int) -> list[Recording]:
    """The ``n_fit_runs`` fitting runs then the ``n_heldout_runs`` held-out runs, one child stream each."""
    program = _program(config)
    n_runs = config.n_fit_runs + config.n_heldout_runs
    children = np.random.default_rng(seed).spawn(n_runs)
    return [
        _simulate_run(
            config,
            program,
            rng,
            index=i,
            role="fit" if i < config.n_fit_runs else "heldout",
            seed=seed,
        )
        for i, rng in enumerate(children)
    ]


def rate_means(rec: Recording) -> NDArray[np.float64]:
    """Mean output over each settled window [deg/s] (the paper's per-rate measured output)."""
    t = rec.time
    y = units.to_deg_per_s(rec["rate"])
    out = []
    for a, b in rec.metadata["windows_s"]:
        m = (t >= a) & (t < b)
        out.append(float(np.mean(y[m])))
    return np.array(out)


# ------------------------------------------------------------------ scoring
def nonlinearity_scorer(compensated: NDArray[np.float64], run: HeldOutRun) -> dict[str, float]:
    """K_n [%] of the compensated table against the table rates (IEEE definition), and the RMS error."""
    fit = fit_scale_factor(run.truth, np.asarray(compensated, dtype=float))
    err = np.asarray(compensated, dtype=float) - run.truth
    return {"nonlinearity_pct": fit.nonlinearity_pct, "rms_dps": float(np.sqrt(np.mean(err**2)))}


def _estimators(config: Config, seed: int) -> dict:
    return {
        "piecewise": PiecewisePolynomial(
            orders=tuple(config.orders), join_width=config.join_width, alpha=config.piecewise_alpha
        ),
        "two_stage_poly": TwoStagePolynomial(
            degree=config.poly_degree, second_degree=config.poly_degree
        ),
        "bayes_bp": BayesianRegularizedMLP(
            hidden_units=config.hidden_units, epochs=config.mlp_epochs, random_state=seed
        ),
    }


def compensation_task(config: Config, seed: int) -> CompensationTask:
    """Features = per-rate mean outputs [deg/s] of the fitting runs, target = table rate [deg/s]."""
    recs = simulate(config, seed)
    rates = np.asarray(config.rates_dps, dtype=float)
    means = [rate_means(r) for r in recs]
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


def _median_time_ms(fn, repeats: int) -> float:
    fn()  # warm caches
    ts = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t0)
    return 1e3 * float(np.median(ts))


# ------------------------------------------------------------------ figures
def _fig_raw(rec: Recording) -> Figure:
    fig = Figure(figsize=(8.0, 4.2))
    ax = fig.add_subplot()
    step = max(1, int(rec.fs // 10))
    t = rec.time[::step] / 60.0
    ax.plot(
        t, units.to_deg_per_s(rec["table_rate"][::step]), color="0.6", lw=1.0, label="table rate"
    )
    ax.plot(t, units.to_deg_per_s(rec["rate"][::step]), lw=0.8, label="gyro output")
    ax.set_xlabel("time [min]")
    ax.set_ylabel("rate [deg/s]")
    ax.set_title("Raw MEMS output at the 21 table rates (fit run 0)")
    ax.grid(True, alpha=0.3)
    ax.legend()
    return fig


def _fig_io(rates, mean, fit) -> Figure:
    fig = Figure(figsize=(6.4, 4.8))
    ax = fig.add_subplot()
    ax.plot(rates, rates, color="0.6", lw=1.0, label="ideal output")
    ax.plot(rates, fit.scale_factor * rates + fit.bias, "--", color="C1", lw=1.0, label="LS line")
    ax.plot(rates, mean, "o", color="C0", label="measured (mean of runs)")
    ax.set_xlabel("table rate [deg/s]")
    ax.set_ylabel("gyro output [deg/s]")
    ax.set_title(f"Input vs output: K_n = {fit.nonlinearity_pct:.2f} %")
    ax.grid(True, alpha=0.3)
    ax.legend()
    return fig


def _fig_continuity(model: PiecewisePolynomial, X: NDArray, y: NDArray) -> Figure:
    fig = Figure(figsize=(9.0, 4.2))
    for k, (b, br) in enumerate(zip(model.breakpoints_, model.breakpoint_rates_, strict=True)):
        ax = fig.add_subplot(1, len(model.breakpoints_), k + 1)
        h = model.half_join_
        xs = np.linspace(b - 4 * h, b + 4 * h, 400)
        left, right = model.segments_[k], model.segments_[k + 1]
        ax.plot(xs, left.predict(xs[:, None]), "--", lw=1.0, label="left segment")
        ax.plot(xs, right.predict(xs[:, None]), "--", lw=1.0, label="right segment")
        joined = model.predict(xs[:, None])
        ax.plot(xs, joined, "k", lw=1.6, label="with Hermite join")
        pad = 0.1 * (joined.max() - joined.min())
        ax.set_ylim(
            joined.min() - pad, joined.max() + pad
        )  # the bare segments diverge outside their data
        ax.axvspan(b - h, b + h, color="0.9")
        m = np.abs(X[:, 0] - b) < 4 * h
        ax.plot(X[m, 0], y[m], "o", color="C3", ms=4, label="data")
        ax.set_title(f"breakpoint {br:+.0f} deg/s")
        ax.set_xlabel("gyro output [deg/s]")
        ax.set_ylabel("compensated rate [deg/s]")
        ax.grid(True, alpha=0.3)
        if k == 0:
            ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def _fig_compensated(rates, raw, comps: dict) -> Figure:
    fig = Figure(figsize=(6.4, 4.8))
    ax = fig.add_subplot()
    ax.plot(rates, rates, color="0.6", lw=1.0, label="ideal")
    ax.plot(rates, raw, "o-", ms=3, lw=0.8, label="raw")
    for i, (key, c) in enumerate(comps.items()):
        ax.plot(rates, c, "s^v"[i], ms=4, mfc="none", label=METHOD_LABELS[key])
    ax.set_xlabel("table rate [deg/s]")
    ax.set_ylabel("output [deg/s]")
    ax.set_title("Held-out run: output before and after compensation")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    return fig


def _fig_nonlinearity(rates, raw_fit, comp_fits: dict) -> Figure:
    fig = Figure(figsize=(9.0, 4.2))
    ax1 = fig.add_subplot(1, 2, 1)
    ax1.plot(rates, 100 * raw_fit.pointwise, "o-", ms=3)
    ax1.set_title("before compensation")
    ax1.set_ylabel("pointwise nonlinearity [%]")
    ax2 = fig.add_subplot(1, 2, 2)
    for key, f in comp_fits.items():
        ax2.plot(
            rates,
            100 * f.pointwise,
            "o-",
            ms=3,
            lw=0.8,
            label=f"{METHOD_LABELS[key]} ({f.nonlinearity_pct:.3f} %)",
        )
    ax2.set_title("after compensation (held-out run)")
    ax2.legend(fontsize=7)
    for ax in (ax1, ax2):
        ax.set_xlabel("table rate [deg/s]")
        ax.grid(True, alpha=0.3)
    fig.tight_layout()
    return fig


# ------------------------------------------------------------------ run
def run(config: Config, seed: int, *, progress: bool = False) -> Outcome:
    """Simulate the runs, analyse the raw table, fit and score the three compensations."""
    t_start = time.perf_counter()
    recs = simulate(config, seed)
    rates = np.asarray(config.rates_dps, dtype=float)
    means = np.array([rate_means(r) for r in recs])
    nf = config.n_fit_runs
    fit_means, held_means = means[:nf], means[nf:]
    table1 = fit_means.mean(axis=0)

    raw_fits = [fit_scale_factor(rates, m) for m in fit_means]
    raw_kn = float(np.mean([f.nonlinearity_pct for f in raw_fits]))
    mean_fit = fit_scale_factor(rates, table1)
    low = np.abs(rates) <= 1800.0
    low_kn = fit_scale_factor(rates[low], table1[low]).nonlinearity if low.sum() >= 3 else math.nan
    asym = (
        asymmetry(rates, table1)
        if (rates >= 0).sum() >= 2 and (rates <= 0).sum() >= 2
        else math.nan
    )
    search = breakpoint_search(rates, table1)
    held_raw_fits = [fit_scale_factor(rates, m) for m in held_means]

    X = fit_means.reshape(-1)[:, None]
    y = np.tile(rates, nf)
    methods, comp_held, comp_held_fits, models = {}, {}, {}, {}
    for key, est in _estimators(config, seed).items():
        t0 = time.perf_counter()
        est.fit(X, y)
        fit_ms = 1e3 * (time.perf_counter() - t0)
        models[key] = est
        kn_fit = float(
            np.mean(
                [
                    fit_scale_factor(rates, est.predict(m[:, None])).nonlinearity_pct
                    for m in fit_means
                ]
            )
        )
        held = [est.predict(m[:, None]) for m in held_means]
        hfits = [fit_scale_factor(rates, c) for c in held]
        x21 = held_means[0][:, None].copy()
        methods[key] = {
            "nonlinearity_pct": kn_fit,
            "heldout_nonlinearity_pct": float(np.mean([f.nonlinearity_pct for f in hfits])),
            "eval_time_ms": _median_time_ms(
                lambda e=est, x=x21: e.predict(x), config.timing_repeats
            ),
            "fit_time_ms": fit_ms,
            "paper_nonlinearity_pct": PAPER["methods"][key]["nonlinearity_pct"],
            "paper_eval_time_ms": PAPER["methods"][key]["eval_time_ms"],
        }
        comp_held[key] = held[0]
        comp_held_fits[key] = hfits[0]
    pw = models["piecewise"]
    methods["piecewise"]["orders"] = list(pw.orders_)
    methods["bayes_bp"]["effective_parameters"] = models["bayes_bp"].gamma_
    methods["bayes_bp"]["epochs_run"] = models["bayes_bp"].n_iter_

    # what-if: the held-out run's scale factor differs by d (run-to-run repeatability, not simulated
    # by default); the saturated range amplifies d by 1/s'(W), about 10 at 3600 deg/s
    sensitivity = {
        f"{d:g}": {
            key: fit_scale_factor(
                rates, est.predict((held_means[0] * (1.0 + d))[:, None])
            ).nonlinearity_pct
            for key, est in models.items()
        }
        for d in SF_CHANGES
    }

    order_sim = sorted(methods, key=lambda k: methods[k]["heldout_nonlinearity_pct"])
    order_paper = sorted(PAPER["methods"], key=lambda k: PAPER["methods"][k]["nonlinearity_pct"])
    bps = [b for b in (search.negative, search.positive) if b is not None]

    results = {
        "raw_nonlinearity_pct": raw_kn,
        "raw_nonlinearity_pct_per_run": [f.nonlinearity_pct for f in raw_fits],
        "raw_nonlinearity_pct_of_mean_table": mean_fit.nonlinearity_pct,
        "raw_nonlinearity_pct_heldout": [f.nonlinearity_pct for f in held_raw_fits],
        "low_rate_nonlinearity": low_kn,
        "scale_factor": mean_fit.scale_factor,
        "bias_dps": mean_fit.bias,
        "asymmetry": asym,
        "breakpoints_dps": bps,
        "piecewise_breakpoint_rates_dps": list(pw.breakpoint_rates_),
        "methods": methods,
        "method_order_heldout": order_sim,
        "method_order_paper": order_paper,
        "method_order_matches_paper": order_sim == order_paper,
        "heldout_nonlinearity_pct_vs_sf_change": sensitivity,
        "table1": {
            "rates_dps": rates.tolist(),
            "mean_output_dps": table1.tolist(),
            "run_outputs_dps": fit_means.tolist(),
            "heldout_outputs_dps": held_means.tolist(),
        },
        "paper": PAPER,
        "n_fit_runs": nf,
        "n_heldout_runs": config.n_heldout_runs,
    }

    # ---------------------------------------------------------------- tables
    t1 = Table(
        "Table 1. Ideal and measured gyro output per table rate (mean of the fitting runs)",
        [
            "rate [deg/s]",
            "ideal output [deg/s]",
            "measured mean [deg/s]",
            "run std [deg/s]",
            "nonlinearity a_j [%]",
        ],
        [
            [r, r, m, s, 100 * a]
            for r, m, s, a in zip(
                rates,
                table1,
                fit_means.std(axis=0, ddof=1) if nf > 1 else np.zeros_like(rates),
                mean_fit.pointwise,
                strict=True,
            )
        ],
        note=(
            f"Raw K_n = {raw_kn:.2f} % (mean over {nf} runs; paper 15.71 %); low-rate (|rate| <= 1800 deg/s) K_n = "
            f"{low_kn:.2e} (paper: order 1e-3). The paper's Table 1 values did not survive text extraction."
        ),
    )
    rows2 = []
    for st in search.trace:
        rows2.append(
            [
                ("+" if st.side > 0 else "-"),
                f"[0, {st.end_rate:+.0f}]",
                st.n_points,
                100 * st.nonlinearity,
                100 * st.abs_diff if not math.isnan(st.abs_diff) else "",
                100 * st.diff2 if not math.isnan(st.diff2) else "",
                ("+" if st.diff2 > 0 else "-") if not math.isnan(st.diff2) else "",
                st.counter,
            ]
        )
    t2 = Table(
        "Table 2. Heuristic breakpoint search (interval nonlinearity, |difference|, its difference, sign, counter)",
        [
            "side",
            "interval [deg/s]",
            "points",
            "K_n [%]",
            "abs diff [%]",
            "diff of abs diff [%]",
            "sign",
            "counter",
        ],
        rows2,
        note=(
            f"Breakpoints found: {bps} deg/s (paper: -1800 and +1800). Split after {3} consecutive positive signs, "
            "at the end of the last interval before the run; the paper's Table 2 numbers did not survive extraction."
        ),
    )
    rows3 = [
        [
            "raw (no compensation)",
            raw_kn,
            float(np.mean([f.nonlinearity_pct for f in held_raw_fits])),
            15.71,
            "",
            "",
            "",
        ]
    ]
    for key, m in methods.items():
        rows3.append(
            [
                METHOD_LABELS[key],
                m["nonlinearity_pct"],
                m["heldout_nonlinearity_pct"],
                m["paper_nonlinearity_pct"],
                m["eval_time_ms"],
                m["paper_eval_time_ms"],
                m["fit_time_ms"],
            ]
        )
    t3 = Table(
        "Table 3. Scale-factor nonlinearity after compensation and time to compensate the 21-point table",
        [
            "method",
            "K_n fit runs [%]",
            "K_n held-out [%]",
            "paper K_n [%]",
            "eval time [ms]",
            "paper time [ms]",
            "fit time [ms]",
        ],
        rows3,
        note=(
            f"Eval time: median of {config.timing_repeats} compensations of the 21-point table on this machine "
            "(the paper's times are from its own machine and software). Held-out order (best first): "
            f"{', '.join(order_sim)}; paper: {', '.join(order_paper)}."
        ),
    )

    t4 = Table(
        "Table 4 (not in the paper). Held-out K_n [%] if the held-out run's scale factor differed by d",
        ["d [ppm]", *(METHOD_LABELS[k] for k in methods), "order (best first)"],
        [
            [
                1e6 * float(d),
                *(v[k] for k in methods),
                " < ".join(sorted(v, key=v.get)),
            ]
            for d, v in sensitivity.items()
        ],
        note=(
            "The default simulation changes the scale factor between runs only through temperature "
            "(about 1e-4 K^-1 x 0.5 K). A run-to-run scale-factor change is amplified about tenfold in the "
            "saturated range, where the compensation curve is steep; the paper's order appears from a few "
            "hundred ppm on. A sensitivity study, not a fit to the paper."
        ),
    )

    # ---------------------------------------------------------------- figures
    figures = [
        FigureSpec(
            "fig2_raw_output",
            "Raw gyro output over the rate-table program (cf. paper Fig. 2)",
            _fig_raw(recs[0]),
        ),
        FigureSpec(
            "fig3_input_output",
            "Table rate vs mean gyro output with the LS line (cf. paper Fig. 3)",
            _fig_io(rates, table1, mean_fit),
        ),
    ]
    if pw.breakpoints_:
        figures.append(
            FigureSpec(
                "fig4_continuity",
                "Piecewise fit near the breakpoints with and without the Hermite join (cf. paper Fig. 4)",
                _fig_continuity(pw, X, y),
            )
        )
    figures += [
        FigureSpec(
            "fig5_compensated",
            "Held-out run before and after each compensation (cf. paper Fig. 5)",
            _fig_compensated(rates, held_means[0], comp_held),
        ),
        FigureSpec(
            "fig6_nonlinearity",
            "Pointwise nonlinearity before and after compensation, held-out run (cf. paper Fig. 6)",
            _fig_nonlinearity(rates, held_raw_fits[0], comp_held_fits),
        ),
    ]

    # ---------------------------------------------------------------- headlines
    hl = [
        Headline(
            "raw scale-factor nonlinearity K_n [%]",
            f"{raw_kn:.2f}",
            "15.71",
            abs(raw_kn - 15.71) <= 1.0,
            "within +-1 %",
        ),
        Headline(
            "low-rate (|rate| <= 1800 deg/s) nonlinearity",
            f"{low_kn:.1e}",
            "order 1e-3",
            1e-4 <= low_kn < 1e-2,
        ),
        Headline(
            "breakpoints [deg/s]",
            ", ".join(f"{b:+.0f}" for b in bps) or "none",
            "-1800, +1800",
            bps == [-1800.0, 1800.0],
        ),
    ]
    for key in ("piecewise", "two_stage_poly", "bayes_bp"):
        m = methods[key]
        p = m["paper_nonlinearity_pct"]
        ok = (
            (m["heldout_nonlinearity_pct"] <= 0.2)
            if key == "piecewise"
            else (p / 2 <= m["heldout_nonlinearity_pct"] <= 2 * p)
        )
        hl.append(
            Headline(
                f"{METHOD_LABELS[key]}: held-out K_n [%]",
                f"{m['heldout_nonlinearity_pct']:.3f}",
                f"{p}",
                ok,
                "target <= 0.2 %"
                if key == "piecewise"
                else "target within a factor 2 of the paper"
                + ("; better than the paper here" if m["heldout_nonlinearity_pct"] < p / 2 else ""),
            )
        )
    hl.append(
        Headline(
            "method order (best first, held-out K_n)",
            " < ".join(order_sim),
            " < ".join(order_paper),
            order_sim == order_paper,
            "not tuned: the simulation's honest order",
        )
    )
    hl.append(
        Headline(
            "fastest compensation",
            min(methods, key=lambda k: methods[k]["eval_time_ms"]),
            "piecewise",
            min(methods, key=lambda k: methods[k]["eval_time_ms"]) == "piecewise",
            "eval time, this machine",
        )
    )

    conclusion = (
        f"The simulated gyro shows K_n = {raw_kn:.2f} % raw (paper 15.71 %) with a nearly linear low-rate range; the "
        f"heuristic search splits at {bps} deg/s. Held-out K_n after compensation: "
        + ", ".join(
            f"{METHOD_LABELS[k]} {methods[k]['heldout_nonlinearity_pct']:.3f} %" for k in methods
        )
        + (
            ". The order of the methods matches the paper."
            if order_sim == order_paper
            else f". The order differs from the paper ({' < '.join(order_paper)}): in this simulation {' < '.join(order_sim)}; "
            "the data were not tuned to force the paper's order (Table 4: the paper's order appears when "
            "the held-out run's scale factor differs by a few hundred ppm)."
        )
    )
    return Outcome(
        scenario=NAME,
        title=TITLE,
        seed=seed,
        config=config,
        results=results,
        tables=[t1, t2, t3, t4],
        figures=figures,
        headlines=hl,
        conclusion=conclusion,
        runtime_s=time.perf_counter() - t_start,
    )
