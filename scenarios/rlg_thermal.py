"""Paper 004: variable-temperature bias of a dithered RLG compensated by stepwise regression.

Setup (paper 004, Chen, Liu, Chen): the gyro is switched on in the chamber at
-40 degC, then the chamber ramps to +65 degC at 1 degC per 3 min and back; the
output is averaged over 100 s (Chinese military standard practice) and the bias
stability is the standard deviation of these 100-s means. Two temperature sensors
are logged: T1 on the housing, T2 on the cavity. Eleven candidate regressors
(:mod:`gyrobench.analysis.regressors`) enter a stepwise regression (p-enter 0.05, p-remove
0.10); the paper keeps x1, x3, x5, x7, x11 with adjusted R^2 ~ 0.97 and improves
the variable-temperature bias stability of three gyros by about 65 %.

Here three gyros are drawn from one :class:`gyrobench.sim.rlg.RLGSpec` (unit-to-unit
variation), each runs the chamber program twice (two turn-ons: different turn-on
bias, discharge-current balance and noise). Each gyro's model is fitted on its
first run and scored on its second, which it never saw. The simulated output is
pulse counts at ``fs_hz`` from the statistical mode of :mod:`gyrobench.sim.rlg`.

What is not in the paper: the form of x9-x11 (defined in
:mod:`gyrobench.analysis.regressors`), the thermal time constants and the size of each bias
mechanism (tuned as PHYSICS.md 6.4 says; see :class:`gyrobench.sim.rlg.RLGSpec`). The paper's
Table 1 and Table 2 numbers did not survive the text extraction; its text gives
adjusted R^2 ~ 0.97 and ~65 % improvement.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from matplotlib.figure import Figure

from gyrobench.analysis.compensation.stepwise import StepwiseRegression
from gyrobench.analysis.features import block_means
from gyrobench.analysis.metrics import bias_stability, improvement_pct
from gyrobench.analysis.regressors import REGRESSOR_LABELS, REGRESSOR_NAMES, two_sensor_regressors
from gyrobench.scenarios.base import CompensationTask, FigureSpec, Headline, HeldOutRun, Outcome, Table
from gyrobench.sim import units
from gyrobench.sim.environment import PiecewiseLinear, Ramp, Soak, thermal_profile
from gyrobench.sim.recording import Recording
from gyrobench.sim.rlg import (
    CavityGeometry,
    Dither,
    RLGSpec,
    RLGUnit,
    TemperatureSensor,
    ThermalBias,
    TwoNodeThermal,
)

NAME = "rlg_thermal"
TITLE = "RLG variable-temperature bias (-40..+65 degC): stepwise regression on housing/cavity temperatures (paper 004)"

#: the paper's selected terms and its reported figures
PAPER_SELECTED = ("x1", "x3", "x5", "x7", "x11")
PAPER_ADJ_R2 = 0.97
PAPER_IMPROVEMENT_PCT = 65.0


@dataclass(frozen=True, slots=True, kw_only=True)
class Config:
    """The paper's protocol (chamber, averaging, stepwise thresholds) and the simulated gyro budget.

    Field units at this edge: degC, minutes, deg/s, deg/h, arcsec.
    """

    # --- protocol (paper 004)
    n_gyros: int = 3
    start_c: float = -40.0
    high_c: float = 65.0
    ramp_c_per_min: float = 1.0 / 3.0
    power_on_soak_min: float = 30.0
    high_soak_min: float = 60.0
    end_soak_min: float = 30.0
    block_s: float = 100.0
    fs_hz: float = 10.0
    derivative_window_s: float = 500.0
    p_enter: float = 0.05
    p_remove: float = 0.10
    bench_gyro: int = 0
    #: seeds in the seed-dependence table (Table 3), the reported one included (as in ifog_thermal)
    seed_summary_count: int = 11
    # --- gyro budget (not in the paper: typical high-precision dithered RLG, see sim.rlg.RLGSpec)
    triangle_side_m: float = 0.14
    lock_in_deg_s: float = 0.05
    lock_in_spread: float = 0.1
    dither_hz: float = 400.0
    dither_arcsec: float = 150.0
    dither_jitter: float = 0.1
    bias_instability_deg_h: float = 0.002
    bias_repeatability_deg_h: float = 0.01
    flow_repeatability: float = 0.2
    tau_housing_min: float = 10.0
    tau_cavity_min: float = 15.0
    heating_housing_k: float = 4.0
    heating_cavity_k: float = 1.5
    thermal_spread: float = 0.1
    cavity_deg_h_per_k: float = 7.5e-4
    cavity_quadratic_deg_h_per_k2: float = 4e-6
    gradient_deg_h_per_k: float = 6e-3
    flux_deg_h_per_k_per_min: float = 0.095
    flux_quadratic_deg_h_per_k_per_min2: float = 0.19
    gas_coefficient_per_k: float = 0.005
    mechanism_spread: float = 0.15
    sensor_noise_k: float = 0.02
    sensor_resolution_k: float = 0.01
    sensor_offset_spread_k: float = 0.2

    def __post_init__(self) -> None:
        if isinstance(self.n_gyros, bool) or not isinstance(self.n_gyros, int) or self.n_gyros < 1:
            raise ValueError(f"Config.n_gyros must be an integer >= 1; got {self.n_gyros!r}")
        if not (isinstance(self.bench_gyro, int) and 0 <= self.bench_gyro < self.n_gyros):
            raise ValueError(
                f"Config.bench_gyro must be an index in [0, {self.n_gyros}); got {self.bench_gyro!r}"
            )
        if not self.high_c > self.start_c:
            raise ValueError(
                f"Config.high_c must be > start_c [degC]; got {self.high_c!r} <= {self.start_c!r}"
            )
        for name in ("ramp_c_per_min", "block_s", "fs_hz", "derivative_window_s"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and np.isfinite(v) and v > 0):
                raise ValueError(f"Config.{name} must be > 0; got {v!r}")
        if self.fs_hz * self.block_s != round(self.fs_hz * self.block_s):
            raise ValueError(
                f"Config.block_s x fs_hz must be a whole number of samples; got {self.block_s!r} s x {self.fs_hz!r} Hz"
            )
        v = self.seed_summary_count
        if isinstance(v, bool) or not isinstance(v, int) or v < 0:
            raise ValueError(f"Config.seed_summary_count must be an integer >= 0; got {v!r}")
        self.spec()  # validates the gyro budget

    def spec(self) -> RLGSpec:
        """The gyro budget in SI."""
        return RLGSpec(
            geometry=CavityGeometry.triangle(self.triangle_side_m),
            lock_in_rate=units.deg_per_s(self.lock_in_deg_s),
            lock_in_spread=self.lock_in_spread,
            dither=Dither(
                frequency=self.dither_hz,
                amplitude=units.arcsec(self.dither_arcsec),
                amplitude_jitter=self.dither_jitter,
            ),
            thermal=TwoNodeThermal(
                tau_housing=self.tau_housing_min * units.MINUTE,
                tau_cavity=self.tau_cavity_min * units.MINUTE,
                heating_housing=self.heating_housing_k,
                heating_cavity=self.heating_cavity_k,
            ),
            thermal_spread=self.thermal_spread,
            thermal_bias=ThermalBias(
                cavity=units.deg_per_h(self.cavity_deg_h_per_k),
                cavity_quadratic=units.deg_per_h(self.cavity_quadratic_deg_h_per_k2),
                gradient=units.deg_per_h(self.gradient_deg_h_per_k),
                flux=units.deg_per_h(self.flux_deg_h_per_k_per_min) * units.MINUTE,
                flux_quadratic=units.deg_per_h(self.flux_quadratic_deg_h_per_k_per_min2)
                * units.MINUTE**2,
                gas_temperature_coefficient=self.gas_coefficient_per_k,
            ),
            mechanism_spread=self.mechanism_spread,
            bias_instability=units.deg_per_h(self.bias_instability_deg_h),
            bias_repeatability=units.deg_per_h(self.bias_repeatability_deg_h),
            flow_repeatability=self.flow_repeatability,
            sensor=TemperatureSensor(
                noise=self.sensor_noise_k, resolution=self.sensor_resolution_k
            ),
            sensor_offset_spread=self.sensor_offset_spread_k,
        )

    def chamber(self) -> PiecewiseLinear:
        """Chamber program [K]: soak at start (gyro on), ramp up, soak, ramp down, soak."""
        rate = self.ramp_c_per_min / units.MINUTE
        steps = [
            Soak(duration=self.power_on_soak_min * units.MINUTE),
            Ramp(target=units.celsius(self.high_c), rate=rate),
            Soak(duration=self.high_soak_min * units.MINUTE),
            Ramp(target=units.celsius(self.start_c), rate=rate),
            Soak(duration=self.end_soak_min * units.MINUTE),
        ]
        return thermal_profile(units.celsius(self.start_c), steps)


# ----------------------------------------------------------------------------- simulation
def _units_and_streams(
    config: Config, seed: int
) -> tuple[list[RLGUnit], list[list[np.random.Generator]]]:
    r_units, r_runs = np.random.default_rng(seed).spawn(2)
    spec = config.spec()
    gyros = [
        spec.realize(rng=r, label=f"gyro {i + 1}")
        for i, r in enumerate(r_units.spawn(config.n_gyros))
    ]
    runs = [r.spawn(2) for r in r_runs.spawn(config.n_gyros)]
    return gyros, runs


def simulate(config: Config, seed: int) -> list[Recording]:
    """Two chamber runs (fit, held-out) per gyro: pulse-count output, logged T1/T2, truth."""
    gyros, runs = _units_and_streams(config, seed)
    prof = config.chamber()
    recs = []
    for i, (g, rr) in enumerate(zip(gyros, runs, strict=True)):
        for kind, r in zip(("fit", "heldout"), rr, strict=True):
            rec = g.simulate(prof, prof.duration, config.fs_hz, rng=r, name=f"gyro{i + 1}_{kind}")
            meta = dict(rec.metadata)
            meta.update({"scenario": NAME, "seed": seed, "gyro": i + 1, "run": kind})
            recs.append(
                Recording(
                    fs=rec.fs,
                    channels=rec.channels,
                    truth=rec.truth,
                    t0=rec.t0,
                    metadata=meta,
                    name=rec.name,
                )
            )
    return recs


@dataclass(frozen=True)
class _Blocks:
    t_h: np.ndarray  # block centre [h]
    X: np.ndarray  # (n, 11) regressors
    output: np.ndarray  # 100-s mean output [deg/h]
    truth: np.ndarray  # 100-s mean true rate [deg/h]
    thermal: np.ndarray  # 100-s mean true thermal bias [deg/h]
    t1: np.ndarray  # logged housing [degC]
    t2: np.ndarray  # logged cavity [degC]
    chamber: np.ndarray  # [degC]


def _blocks(rec: Recording, config: Config) -> _Blocks:
    fs, b = rec.fs, config.block_s

    def bm(x):
        return block_means(x, fs, block_s=b)

    t1 = bm(units.to_celsius(rec["T1"]))
    t2 = bm(units.to_celsius(rec["T2"]))
    X = two_sensor_regressors(t1, t2, 1.0 / b, window_s=config.derivative_window_s)
    return _Blocks(
        t_h=(np.arange(len(t1)) + 0.5) * b / units.HOUR,
        X=X,
        output=bm(units.to_deg_per_h(rec["rate"])),
        truth=bm(units.to_deg_per_h(rec["truth/true_rate"])),
        thermal=bm(units.to_deg_per_h(rec["truth/thermal_bias"])),
        t1=t1,
        t2=t2,
        chamber=bm(units.to_celsius(rec["truth/chamber"])),
    )


def bias_stability_scores(compensated: np.ndarray, run: HeldOutRun) -> dict[str, float]:
    """Scorer: bias stability (std of the 100-s means, n - 1) before and after compensation [deg/h].

    ``run.output`` and ``compensated`` are already 100-s block means, so each is one block.
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
    """Gyro ``config.bench_gyro``: training = its fitting run, held-out = its second run (100-s blocks).

    Features: the eleven regressors x1..x11 (degC, degC/s); target: the output error
    [deg/h] (output minus true rate), as the paper compensates the bias.
    """
    gyros, runs = _units_and_streams(config, seed)
    i = config.bench_gyro
    prof = config.chamber()
    fit, held = (
        _blocks(gyros[i].simulate(prof, prof.duration, config.fs_hz, rng=r), config)
        for r in runs[i]
    )
    return CompensationTask(
        scenario=NAME,
        feature_names=tuple(
            f"{lab} {nm}" for lab, nm in zip(REGRESSOR_LABELS, REGRESSOR_NAMES, strict=True)
        ),
        X_train=fit.X,
        y_train=fit.output - fit.truth,
        heldout=(
            HeldOutRun(
                label=f"gyro{i + 1}_heldout", X=held.X, output=held.output, truth=held.truth
            ),
        ),
        target="error",
        unit="deg/h",
        scorer=bias_stability_scores,
    )


# ----------------------------------------------------------------------------- figures
def _fig_output_vs_temperature(blocks: list[_Blocks]) -> Figure:
    fig = Figure(figsize=(10.0, 4.2), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2)
    b = blocks[0]
    ax1.plot(b.t_h, b.output, "k.-", lw=0.8, ms=3, label="gyro 1 output (100-s mean)")
    ax1.set_xlabel("time [h]")
    ax1.set_ylabel("output bias [deg/h]")
    axt = ax1.twinx()
    axt.plot(b.t_h, b.chamber, color="0.6", lw=1, label="chamber")
    axt.plot(b.t_h, b.t1, color="tab:red", lw=1, label="T1 housing")
    axt.plot(b.t_h, b.t2, color="tab:blue", lw=1, label="T2 cavity")
    axt.set_ylabel("temperature [degC]")
    axt.legend(loc="lower center", fontsize=8)
    ax1.legend(loc="upper left", fontsize=8)
    ax1.set_title("(a) output and temperatures, fitting run")
    for k, bb in enumerate(blocks):
        ax2.plot(bb.t1, bb.output - np.mean(bb.output), ".-", lw=0.6, ms=3, label=f"gyro {k + 1}")
    ax2.set_xlabel("housing temperature T1 [degC]")
    ax2.set_ylabel("output bias - mean [deg/h]")
    ax2.set_title("(b) output vs temperature (up and down ramps)")
    ax2.legend(fontsize=8)
    return fig


def _fig_rate_gradient(b: _Blocks) -> Figure:
    fig = Figure(figsize=(8.0, 4.2), layout="constrained")
    ax = fig.subplots()
    ax.plot(b.t_h, b.X[:, 2] * units.MINUTE, color="tab:red", label="dT1/dt housing")
    ax.plot(b.t_h, b.X[:, 3] * units.MINUTE, color="tab:blue", label="dT2/dt cavity")
    ax.set_xlabel("time [h]")
    ax.set_ylabel("temperature rate [degC/min]")
    axg = ax.twinx()
    axg.plot(b.t_h, b.X[:, 8], "k--", label="gradient T1 - T2")
    axg.set_ylabel("gradient T1 - T2 [degC]")
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = axg.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, fontsize=8, loc="lower left")
    ax.set_title("Temperature rate and gradient during the chamber cycle (gyro 1, fitting run)")
    return fig


def _fig_before_after(held: list[_Blocks], comps: list[np.ndarray], stats: list[dict]) -> Figure:
    n = len(held)
    fig = Figure(figsize=(8.0, 2.6 * n), layout="constrained")
    axes = np.atleast_1d(fig.subplots(n, 1, sharex=True))
    for k, (ax, b, c, s) in enumerate(zip(axes, held, comps, stats, strict=True)):
        ax.plot(
            b.t_h,
            b.output - b.output.mean(),
            color="tab:red",
            lw=1,
            label=f"before: {s['bias_stability_before_deg_h']:.4f} deg/h",
        )
        ax.plot(
            b.t_h,
            c - c.mean(),
            color="tab:blue",
            lw=1,
            label=f"after: {s['bias_stability_after_deg_h']:.4f} deg/h",
        )
        ax.set_ylabel("bias - mean [deg/h]")
        ax.set_title(
            f"({'abc'[k] if k < 3 else k}) gyro {k + 1}, held-out run: {s['improvement_pct']:.1f} % better"
        )
        ax.legend(fontsize=8, loc="upper right")
    axes[-1].set_xlabel("time [h]")
    return fig


# ----------------------------------------------------------------------------- run
def _terms(support: np.ndarray) -> list[str]:
    return [REGRESSOR_LABELS[j] for j in np.flatnonzero(support)]


def _stability(x: np.ndarray, b: _Blocks) -> float:
    """Bias stability [deg/h] of 100-s block values ``x`` against the blocks' true rate.

    The blocks are already the GJB 100-s means, so this is
    :func:`gyrobench.analysis.metrics.bias_stability` (1 sigma, n - 1) of the error ``x - truth``.
    """
    return float(np.std(np.asarray(x) - b.truth, ddof=1))


def _fit_gyro(config: Config, g, streams, prof, i: int) -> tuple[_Blocks, _Blocks, StepwiseRegression]:
    """Simulate gyro ``i``'s fitting and held-out runs, block them, fit stepwise on the first."""
    rf = g.simulate(prof, prof.duration, config.fs_hz, rng=streams[0], name=f"gyro{i + 1}_fit")
    rh = g.simulate(prof, prof.duration, config.fs_hz, rng=streams[1], name=f"gyro{i + 1}_heldout")
    bf, bh = _blocks(rf, config), _blocks(rh, config)
    m = StepwiseRegression(p_enter=config.p_enter, p_remove=config.p_remove).fit(
        bf.X, bf.output - bf.truth
    )
    return bf, bh, m


def seed_summary(config: Config, seeds) -> list[dict]:
    """Adjusted R^2 (fitting run) and held-out improvement [%] of every gyro, for each seed.

    The whole pipeline of :func:`run` (draw the units, simulate both turn-ons, fit,
    score) without tables or figures; it shows how much the two targets depend on the
    draw, which one seed cannot.
    """
    prof = config.chamber()
    out = []
    for s in seeds:
        gyros, runs = _units_and_streams(config, int(s))
        adj, imp = [], []
        for i in range(config.n_gyros):
            bf, bh, m = _fit_gyro(config, gyros[i], runs[i], prof, i)
            before = _stability(bh.output, bh)
            after = _stability(bh.output - m.predict(bh.X), bh)
            adj.append(float(m.adj_r2_))
            imp.append(improvement_pct(before, after))
        out.append({"seed": int(s), "adj_r2": adj, "improvement_pct": imp})
    return out


def run(config: Config, seed: int, *, progress: bool = False) -> Outcome:
    """Simulate the three gyros, fit each on its first run, score on its second, build tables and figures."""
    from tqdm import tqdm

    t_start = time.perf_counter()
    gyros, runs = _units_and_streams(config, seed)
    prof = config.chamber()
    fits, helds, models, comps, gyro_results = [], [], [], [], []
    for i in tqdm(range(config.n_gyros), desc=NAME, unit="gyro", disable=not progress):
        g = gyros[i]
        bf, bh, m = _fit_gyro(config, g, runs[i], prof, i)
        comp_h = bh.output - m.predict(bh.X)
        comp_f = bf.output - m.predict(bf.X)
        before, after = _stability(bh.output, bh), _stability(comp_h, bh)
        fb, fa = _stability(bf.output, bf), _stability(comp_f, bf)
        # the best any model of the logged temperatures could do: output minus the true thermal bias
        floor = _stability(bh.output - bh.thermal, bh)
        sel = _terms(m.support_)
        gyro_results.append(
            {
                "label": g.label,
                "selected": sel,
                "selected_names": [REGRESSOR_NAMES[int(s[1:]) - 1] for s in sel],
                "multiple_r": m.multiple_r_,
                "r2": m.r2_,
                "adj_r2": m.adj_r2_,
                "rmse_deg_h": m.rmse_,
                "f_statistic": m.f_statistic_,
                "significance_f": m.significance_f_,
                "intercept_deg_h": m.intercept_,
                "coefficients": {
                    REGRESSOR_LABELS[j]: float(m.coef_[j]) for j in np.flatnonzero(m.support_)
                },
                "pvalues": {
                    REGRESSOR_LABELS[j]: float(m.pvalues_[j]) for j in range(len(REGRESSOR_LABELS))
                },
                "steps": [[a, REGRESSOR_LABELS[j], float(p)] for a, j, p in m.history_],
                "bias_stability_before_deg_h": before,
                "bias_stability_after_deg_h": after,
                "improvement_pct": improvement_pct(before, after),
                "fit_run": {
                    "bias_stability_before_deg_h": fb,
                    "bias_stability_after_deg_h": fa,
                    "improvement_pct": improvement_pct(fb, fa),
                },
                "heldout_noise_floor_deg_h": floor,
                "n_blocks_fit": int(len(bf.output)),
                "unit": {
                    "lock_in_deg_s": float(units.to_deg_per_s(g.lock_in_rate)),
                    "arw_deg_sqrt_h": float(units.to_deg_per_sqrt_h(g.angle_random_walk)),
                    "pulse_weight_arcsec": float(units.to_arcsec(g.pulse_weight)),
                    "tau_housing_min": g.thermal.tau_housing / units.MINUTE,
                    "tau_cavity_min": g.thermal.tau_cavity / units.MINUTE,
                    "thermal_bias_std_deg_h": float(np.std(bf.thermal, ddof=1)),
                },
            }
        )
        fits.append(bf)
        helds.append(bh)
        models.append(m)
        comps.append(comp_h)

    # one model for every unit: gyro 1's fitted model applied to each gyro's held-out run
    # (a reading of the paper's "this compensation model applied to three gyros")
    for r, bh in zip(gyro_results, helds, strict=True):
        comp = bh.output - models[0].predict(bh.X)
        after = _stability(comp, bh)
        r["gyro1_model"] = {
            "bias_stability_after_deg_h": after,
            "improvement_pct": improvement_pct(r["bias_stability_before_deg_h"], after),
        }

    # ---------------------------------------------------------------- tables
    t1_rows = [
        [
            r["label"],
            ", ".join(r["selected"]) or "(none)",
            r["multiple_r"],
            r["r2"],
            r["adj_r2"],
            r["rmse_deg_h"],
            r["f_statistic"],
            r["significance_f"],
        ]
        for r in gyro_results
    ]
    t1_rows.append(
        [
            "paper 004",
            ", ".join(PAPER_SELECTED),
            "n/a",
            "n/a",
            f"~{PAPER_ADJ_R2}",
            "n/a",
            "n/a",
            "n/a",
        ]
    )
    table1 = Table(
        title="Table 1. Multiple linear regression on the fitting run (100-s blocks): selected terms and statistics",
        columns=[
            "gyro",
            "selected terms",
            "Multiple R",
            "R^2",
            "adjusted R^2",
            "RMSE [deg/h]",
            "F",
            "significance F",
        ],
        rows=t1_rows,
        note=(
            "Candidates x1..x11: "
            + "; ".join(
                f"{a} = {b}" for a, b in zip(REGRESSOR_LABELS, REGRESSOR_NAMES, strict=True)
            )
            + " (temperatures in degC, rates in degC/s; x9-x11 defined in analysis.regressors, the paper does not give "
            "their form). Stepwise p-enter 0.05, p-remove 0.10. The paper's table values were lost in extraction; its "
            "text gives adjusted R^2 ~0.97 and the terms x1, x3, x5, x7, x11. The candidates are strongly collinear "
            "(T1 ~ T2, dT1/dt ~ dT2/dt ~ gradient during ramps), so different but equivalent term sets can be selected."
        ),
    )
    g0 = gyro_results[0]
    coef_rows = [
        [
            lab,
            REGRESSOR_NAMES[j],
            g0["coefficients"][lab] if lab in g0["coefficients"] else "excluded",
            float(models[0].coef_stderr_[j]) if lab in g0["coefficients"] else "",
            g0["pvalues"][lab],
        ]
        for j, lab in enumerate(REGRESSOR_LABELS)
    ]
    table1b = Table(
        title="Table 1b. Gyro 1 model: coefficients (deg/h per unit of the term) and stepwise p-values",
        columns=[
            "term",
            "definition",
            "coefficient",
            "std. error",
            "p-value (remove if in, enter if out)",
        ],
        rows=[["x0", "intercept", g0["intercept_deg_h"], "", ""]] + coef_rows,
    )
    table2 = Table(
        title="Table 2. Variable-temperature bias stability (1 sigma of 100-s means) before and after compensation",
        columns=[
            "gyro",
            "before [deg/h]",
            "after [deg/h]",
            "improvement [%]",
            "fitting run improvement [%]",
            "with gyro 1's model [%]",
            "noise floor [deg/h]",
            "paper improvement [%]",
        ],
        rows=[
            [
                r["label"],
                r["bias_stability_before_deg_h"],
                r["bias_stability_after_deg_h"],
                r["improvement_pct"],
                r["fit_run"]["improvement_pct"],
                r["gyro1_model"]["improvement_pct"],
                r["heldout_noise_floor_deg_h"],
                f"~{PAPER_IMPROVEMENT_PCT:.0f}",
            ]
            for r in gyro_results
        ],
        note=(
            "Before/after from the held-out run (second turn-on, never used for fitting), each gyro with its own "
            "model. 'With gyro 1's model': the held-out run compensated by gyro 1's fitted model instead (the paper's "
            "text can be read as one model applied to three gyros). Noise floor: the held-out output minus the true "
            "thermal bias, i.e. what a perfect thermal model would leave (dither random walk, count quantization, "
            "flicker)."
        ),
    )

    # ---------------------------------------------------------------- seed dependence
    adj = [r["adj_r2"] for r in gyro_results]
    imp = [r["improvement_pct"] for r in gyro_results]
    summary = [{"seed": seed, "adj_r2": adj, "improvement_pct": imp}]
    summary += seed_summary(config, range(seed + 1, seed + config.seed_summary_count))
    for row in summary:
        row["adj_r2_target_holds"] = bool(all(a >= 0.9 for a in row["adj_r2"]))
        row["improvement_target_holds"] = bool(all(50.0 <= v <= 80.0 for v in row["improvement_pct"]))
    n_adj = sum(r["adj_r2_target_holds"] for r in summary)
    n_imp = sum(r["improvement_target_holds"] for r in summary)
    n_both = sum(r["adj_r2_target_holds"] and r["improvement_target_holds"] for r in summary)
    table3 = Table(
        title=f"Table 3 (not in the paper). Seed dependence: the whole pipeline on seeds {seed}-{seed + len(summary) - 1}",
        columns=["seed", "adjusted R^2 (3 gyros)", "held-out improvement [%] (3 gyros)",
                 "adj. R^2 >= 0.9 (all)", "improvement 50-80 % (all)"],
        rows=[
            [r["seed"], ", ".join(f"{a:.3f}" for a in r["adj_r2"]),
             ", ".join(f"{v:.1f}" for v in r["improvement_pct"]),
             "yes" if r["adj_r2_target_holds"] else "NO",
             "yes" if r["improvement_target_holds"] else "NO"]
            for r in summary
        ],
        note=(
            f"Each seed draws three new units and their two turn-ons. Adjusted R^2 >= 0.9 for every gyro on "
            f"{n_adj}/{len(summary)} seeds, held-out improvement 50-80 % for every gyro on {n_imp}/{len(summary)}, "
            f"both on {n_both}/{len(summary)}. The first row is the run reported above. The paper reports one set of three "
            "gyros; these rows show how far another draw of three units moves the two numbers."
        ),
    )

    # ---------------------------------------------------------------- figures
    stats = gyro_results
    figures = [
        FigureSpec(
            "fig1_output_vs_temperature",
            "Figure 1. Gyro output (100-s means) and temperatures over the chamber cycle; output vs housing temperature for the three gyros.",
            _fig_output_vs_temperature(fits),
        ),
        FigureSpec(
            "fig2_rate_and_gradient",
            "Figure 2. Temperature rates of housing and cavity and the housing-cavity gradient during the cycle.",
            _fig_rate_gradient(fits[0]),
        ),
        FigureSpec(
            "fig4_before_after",
            "Figure 4. Held-out runs: bias before and after stepwise-regression compensation, three gyros.",
            _fig_before_after(helds, comps, stats),
        ),
    ]

    # ---------------------------------------------------------------- headlines
    headlines = [
        Headline(
            "adjusted R^2 on the fitting run",
            ", ".join(f"{a:.3f}" for a in adj),
            f"~{PAPER_ADJ_R2} (target >= 0.9)",
            summary[0]["adj_r2_target_holds"],
            f"holds on {n_adj} of {len(summary)} seeds (Table 3)",
        ),
        Headline(
            "held-out bias-stability improvement [%]",
            ", ".join(f"{v:.1f}" for v in imp),
            f"~{PAPER_IMPROVEMENT_PCT:.0f} (target 50-80 each)",
            summary[0]["improvement_target_holds"],
            f"holds on {n_imp} of {len(summary)} seeds (Table 3)",
        ),
        Headline(
            "selected terms",
            "; ".join(f"{r['label']}: {', '.join(r['selected'])}" for r in gyro_results),
            ", ".join(PAPER_SELECTED),
            None,
            "the candidates are collinear: the selected set differs from unit to unit; compare R^2 and improvement",
        ),
        Headline(
            "bias depends on temperature, its rate and the gradient",
            "every gyro keeps a temperature, a rate and a gradient-carrying term"
            if all(_has_kinds(r["selected"]) for r in gyro_results)
            else "not every gyro keeps all three kinds",
            "x1 (T), x3/x5/x7 (rate), x11 (gradient)",
            bool(all(_has_kinds(r["selected"]) for r in gyro_results)),
            "temperature-carrying: x1, x2 or a product with T (x5, x6, x11); gradient-carrying: x9-x11, or the "
            "cavity rate x4/x6/x8, since in the two-node model dT2/dt = (T1 + H2 - T2)/tau2 is the gradient "
            "(plus the self-heating offset)",
        ),
    ]
    results = {
        "gyros": gyro_results,
        "seed_summary": summary,
        "regressors": dict(zip(REGRESSOR_LABELS, REGRESSOR_NAMES, strict=True)),
        "paper": {
            "selected": list(PAPER_SELECTED),
            "adj_r2": PAPER_ADJ_R2,
            "improvement_pct": PAPER_IMPROVEMENT_PCT,
        },
        "protocol": {
            "chamber_duration_h": prof.duration / units.HOUR,
            "block_s": config.block_s,
            "fs_hz": config.fs_hz,
        },
    }
    mean_imp = float(np.mean(imp))
    cross_txt = (
        ", ".join(f"{r['gyro1_model']['improvement_pct']:.0f}" for r in gyro_results[1:]) or "n/a"
    )
    return Outcome(
        scenario=NAME,
        title=TITLE,
        seed=seed,
        config=config,
        results=results,
        tables=[table1, table1b, table2, table3],
        figures=figures,
        headlines=headlines,
        conclusion=(
            f"Stepwise regression on the housing and cavity temperatures, their rates, products and gradient terms "
            f"fits each gyro's variable-temperature bias with adjusted R^2 {min(adj):.2f}-{max(adj):.2f} and improves "
            f"the held-out bias stability by {min(imp):.0f}-{max(imp):.0f} % (mean {mean_imp:.0f} %; paper ~65 %, "
            "'about 2x'). What remains after compensation is close to the noise floor set by the dither random walk "
            "and pulse quantization over 100 s, plus turn-on changes of the discharge balance the model cannot know. "
            f"Applying gyro 1's model to the other gyros gives {cross_txt} %. The selected terms differ from unit to "
            "unit and from the paper's x1, x3, x5, x7, x11: the candidates are nearly collinear, so several term sets "
            f"fit equally well. Over seeds {seed}-{seed + len(summary) - 1} (Table 3) the adjusted-R^2 target holds for "
            f"all three gyros on {n_adj} and the improvement target on {n_imp} of {len(summary)} seeds."
        ),
        runtime_s=time.perf_counter() - t_start,
    )


def _has_kinds(selected: list[str]) -> bool:
    """Whether a selection uses temperature, rate and gradient information.

    Temperature: x1, x2 or a product with a temperature (x5, x6, x11). Rate: any
    rate term. Gradient: x9-x11, or the cavity rate terms, since in the two-node
    model dT2/dt = (T1 + H2 - T2)/tau2 (x4, x6, x8 carry the gradient).
    """
    s = set(selected)
    temp = bool(s & {"x1", "x2", "x5", "x6", "x11"})
    rate = bool(s & {"x3", "x4", "x5", "x6", "x7", "x8", "x10"})
    grad = bool(s & {"x4", "x6", "x8", "x9", "x10", "x11"})
    return temp and rate and grad
