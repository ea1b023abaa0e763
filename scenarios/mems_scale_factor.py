"""Paper 001: a +-3600 deg/s MEMS gyro on a rate table, scale-factor nonlinearity, compensation.

The device (:mod:`gyrobench.sim.mems_resonator`): a lumped 2-DOF Coriolis vibratory gyro with
force rebalance whose high-range knee is the rebalance DAC's authority,
Omega_max = sqrt(F_max^2 - F_q^2) / (2 m w X0), flat beyond it (docs/physics.md 5.1). Each
unit (:func:`experiment`, one seed) is one unit drawn from a
:class:`~gyrobench.sim.mems_resonator.MemsResonatorSpec` population, with its own power-ons
(turn-on bias and scale-factor error, ambient temperature, noise).

Two devices (``Config.variant``):

* ``"design"`` (default): the spec as given, by default the module's plausible +-3600 deg/s
  design (v_max = 0.7 V, authority about 1.1-1.4x the range). The default because issue 16
  asks for a plausible design not solved for the paper's number: nothing in it is set from
  paper 001, so every claim is emergent. Its knee lies beyond the table, so its raw K_n is
  the noise of the dwell means (ppm), not the paper's 15.71 %: a finding, reported.
* ``"calibrated"``: the same population with the rebalance DAC full scale v_max set to
  :data:`CALIBRATED_V_MAX_V`, CALIBRATED (:func:`calibrated_v_max`) so that the median
  noise-free raw K_n of units 0-19 is the paper's 15.71 %. Under it the raw-K_n claim is
  calibrated (the report says so); the knee then lies at about 2300-3200 deg/s.

Protocol (paper section 3): after warm-up the table steps through 21 rates, +3600 -> -3600
deg/s in 360 deg/s steps; the output is sampled at 200 Hz and averaged over 1-2 min of each
settled dwell (here 60 s after 0.5 s settling). Several runs are made; Table 1 is the
per-rate mean over runs, the raw nonlinearity the mean of the runs' K_n (paper: 15.71 %).

Methods (paper section 4): the heuristic breakpoint search (Table 2, run unchanged:
:func:`gyrobench.analysis.scale_factor.breakpoint_search`; where it splits is a result), the
piecewise 9-1-9 polynomial with cubic Hermite joins, the two-stage 9th-order polynomial and a
Bayesian-regularized BP network with 10 hidden units (Table 3: 0.14 %, 0.59 %, 0.45 %).

One unit is ``n_fit_runs`` rate-table runs the compensators are fitted on (per-rate means
pooled) and ``n_heldout_runs`` further power-ons they never saw. Each method is scored by the
IEEE K_n of the compensated table against the table rates

* at the 21 table rates of the held-out run(s) (claims), and of the fitting runs (in-sample,
  the paper's own scoring, reported);
* on a dense held-out sweep: the noise-free static output of each held-out power-on (its
  turn-on errors at its die temperature, no quantization) every ``dense_step_dps`` over the
  table's range (claims), so K_n also sees the model error between the table rates.

The claims (:data:`CLAIMS`) are judged over units by
:func:`gyrobench.scenarios.claims.evaluate`; :func:`report` builds tables and figures.
The older curve model :mod:`gyrobench.sim.mems` (knee placed at the paper's breakpoint, width
solved for 15.71 %, a sign step) is no longer used here.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

import numpy as np
from gyrobench.analysis.scale_factor import breakpoint_search, fit_scale_factor
from gyrobench.scenarios.base import CompensationTask, FigureSpec, HeldOutRun, Outcome, Table
from gyrobench.scenarios.claims import (
    Claim,
    ClaimResult,
    Deviation,
    finite_median,
    in_range,
    is_true,
    within_factor,
)
from gyrobench.sim import mems_resonator as mr
from gyrobench.sim import units
from gyrobench.sim.mems_resonator import MemsResonator, MemsResonatorSpec
from gyrobench.sim.recording import Channel, Recording, package_version
from numpy.typing import NDArray

if TYPE_CHECKING:
    from matplotlib.figure import Figure

NAME = "mems_scale_factor"
TITLE = "High-range MEMS gyro: scale-factor nonlinearity and heuristic piecewise compensation"
PAPER = "001"

#: the three compensation methods, in the order of the paper's Table 3
METHOD_LABELS = {
    "piecewise": "Heuristic piecewise 9-1-9 + Hermite",
    "two_stage_poly": "Two-stage 9th-order polynomial",
    "bayes_bp": "Bayes-regularized BP (10 hidden)",
}
#: the paper's Table 3: K_n after compensation [%] and evaluation time [ms] (MATLAB)
PAPER_KN_PCT = {"piecewise": 0.14, "two_stage_poly": 0.59, "bayes_bp": 0.45}
PAPER_TIME_MS = {"piecewise": 0.247, "two_stage_poly": 0.755, "bayes_bp": 37.8}
#: the paper's order of the methods, best first (Table 3 and its text)
PAPER_ORDER = ("piecewise", "bayes_bp", "two_stage_poly")
#: the paper's raw K_n (section 3) [-]
PAPER_RAW_KN = 0.1571
#: the devices Config.variant selects
VARIANTS = ("design", "calibrated")
#: rebalance DAC full scale v_max [V] of the "calibrated" variant: CALIBRATED by
#: :func:`calibrated_v_max` (default spec, units 0-19) so that the median noise-free raw K_n on
#: the paper's 21 rates is 15.71 %. The design value is 0.7 V.
CALIBRATED_V_MAX_V = 0.44017


def _default_rates() -> tuple[float, ...]:
    return tuple(float(r) for r in np.arange(3600.0, -3600.0 - 1.0, -360.0))


@dataclass(frozen=True, slots=True, kw_only=True)
class Config:
    """The paper's rate-table test and methods (field units at this edge).

    Parameters
    ----------
    gyro : MemsResonatorSpec
        The population the units are drawn from (SI; default the plausible design).
    variant : {"design", "calibrated"}
        "design": ``gyro`` as given; "calibrated": ``gyro`` with its nominal rebalance DAC
        full scale set to :data:`CALIBRATED_V_MAX_V` (CALIBRATED to the paper's 15.71 %).
    rates_dps : tuple of float
        Table rates in test order [deg/s], strictly monotonic.
    average_s, settle_s : float
        Averaged and discarded (settling) time of each dwell [s].
    fs_hz : float
        Output sample rate [Hz].
    ambient_c, ambient_spread_c : float
        Mean die temperature during the runs and its run-to-run standard deviation [degC]
        (the units are factory-trimmed at 25 degC).
    n_fit_runs, n_heldout_runs : int
        Power-ons the compensators are fitted on; power-ons kept for scoring only (per unit).
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
    dense_step_dps : float
        Rate step of the dense held-out sweep [deg/s], > 0.
    """

    gyro: MemsResonatorSpec = field(default_factory=MemsResonatorSpec)
    variant: str = "design"
    rates_dps: tuple[float, ...] = field(default_factory=_default_rates)
    average_s: float = 60.0
    settle_s: float = 0.5
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
    timing_repeats: int = 50
    dense_step_dps: float = 10.0

    def __post_init__(self) -> None:
        if not isinstance(self.gyro, MemsResonatorSpec):
            raise TypeError(
                f"Config.gyro must be a MemsResonatorSpec; got {type(self.gyro).__name__}"
            )
        if self.variant not in VARIANTS:
            raise ValueError(f"Config.variant must be one of {VARIANTS}; got {self.variant!r}")
        r = np.asarray(self.rates_dps, dtype=float)
        if r.ndim != 1 or r.size < 3 or not np.all(np.isfinite(r)):
            raise ValueError(
                "Config.rates_dps must hold at least 3 finite rates [deg/s]; "
                f"got {self.rates_dps!r}"
            )
        d = np.diff(r)
        if not (np.all(d > 0) or np.all(d < 0)):
            raise ValueError(
                "Config.rates_dps must be strictly monotonic without duplicates [deg/s]; "
                f"got {self.rates_dps!r}"
            )
        for name, unit in (("average_s", "s"), ("fs_hz", "Hz"), ("dense_step_dps", "deg/s")):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ValueError(f"Config.{name} must be > 0 {unit}; got {v!r}")
        for name in ("settle_s", "ambient_spread_c", "piecewise_alpha"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0):
                raise ValueError(f"Config.{name} must be finite and >= 0; got {v!r}")
        if not (isinstance(self.ambient_c, (int, float)) and math.isfinite(self.ambient_c)):
            raise ValueError(f"Config.ambient_c must be finite [degC]; got {self.ambient_c!r}")
        if int(round(self.average_s * self.fs_hz)) < 1:
            raise ValueError(
                "Config.average_s must cover at least one sample at fs_hz; "
                f"got {self.average_s!r} s at {self.fs_hz!r} Hz"
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


# ------------------------------------------------------------------ the device
def device_spec(config: Config) -> MemsResonatorSpec:
    """The population of ``config.variant`` (the calibrated one has v_max = CALIBRATED_V_MAX_V)."""
    if config.variant == "calibrated":
        nom = replace(config.gyro.nominal, dac_full_scale=CALIBRATED_V_MAX_V)
        return replace(config.gyro, nominal=nom)
    return config.gyro


def draw_unit(spec: MemsResonatorSpec, seed: int) -> MemsResonator:
    """Unit ``seed`` of the population: realized from the first child of default_rng(seed)."""
    r_unit, _ = np.random.default_rng(seed).spawn(2)
    return spec.realize(rng=r_unit)


def static_output(
    unit: MemsResonator, rates_dps: NDArray[np.float64], temperature: float
) -> NDArray[np.float64]:
    """Noise-free settled output [deg/s] of one power-on at constant rates and temperature [K].

    The slow flow without noise, 1/f term and ADC, run for 1 s at 200 Hz from each rate's
    (clamped) equilibrium; the mean of the last 0.1 s. Linear columns start at their
    equilibrium; saturated ones settle within the loop's time constants (tens of ms). Equals
    SF Omega + ZRO below the authority and ``mems_resonator.saturated_output`` beyond it (test).
    """
    w = units.deg_per_s(np.asarray(rates_dps, dtype=float))
    col = np.broadcast_to(w, (200, w.size))
    res = mr.simulate(
        unit, col, fs=200.0, rng=np.random.default_rng(0), temperature=temperature,
        noise=False, adc=False, flicker=False,
    )
    return units.to_deg_per_s(res.output[-20:].mean(axis=0))


def calibrated_v_max(
    spec: MemsResonatorSpec | None = None,
    seeds: Sequence[int] = tuple(range(20)),
    rates_dps: Sequence[float] | None = None,
) -> float:
    """v_max [V] such that the median noise-free raw K_n of the units ``seeds`` is 15.71 %.

    The units are those :func:`experiment` draws (:func:`draw_unit`), trimmed, at T0, without
    turn-on errors; K_n (IEEE, F_m = max |F|) of the noise-free table (:func:`static_output`)
    on the paper's 21 rates. The draws do not depend on v_max, so the same units are
    evaluated at each trial value (scipy brentq between 0.3 and 1 x the nominal v_max).
    This is the CALIBRATION behind :data:`CALIBRATED_V_MAX_V`.
    """
    from scipy.optimize import brentq

    base = MemsResonatorSpec() if spec is None else spec
    rates = np.asarray(_default_rates() if rates_dps is None else rates_dps, dtype=float)
    drawn = [draw_unit(base, s) for s in seeds]
    t0 = base.nominal.reference_temperature

    def excess(v: float) -> float:
        kns = [
            fit_scale_factor(rates, static_output(replace(u, dac_full_scale=v), rates, t0))
            .nonlinearity
            for u in drawn
        ]
        return float(np.median(kns)) - PAPER_RAW_KN

    v0 = base.nominal.dac_full_scale
    return float(brentq(excess, 0.3 * v0, v0, xtol=1e-5))


# ------------------------------------------------------------------ simulation
@dataclass(frozen=True, slots=True)
class _Run:
    """One rate-table run: the power-on, its die temperature [K], the output (n, k) [rad/s]."""

    unit: MemsResonator
    temperature: float
    output: NDArray[np.float64]


def _runs(config: Config, seed: int) -> list[_Run]:
    """Unit ``seed``'s runs: realize the unit, then per run its ambient, power-on and noise.

    Each run's dwells are independent columns of one slow-flow call (the rebalance loop
    settles in ms, so a dwell's mean does not depend on the previous rate).
    """
    unit = draw_unit(device_spec(config), seed)
    _, r_runs = np.random.default_rng(seed).spawn(2)
    w = units.deg_per_s(np.asarray(config.rates_dps, dtype=float))
    n = int(round(config.settle_s * config.fs_hz)) + int(round(config.average_s * config.fs_hz))
    col = np.broadcast_to(w, (n, w.size))
    out = []
    for rr in r_runs.spawn(config.n_fit_runs + config.n_heldout_runs):
        r_amb, r_on, r_sim = rr.spawn(3)
        temp = units.celsius(config.ambient_c + config.ambient_spread_c * r_amb.standard_normal())
        on = unit.power_on(rng=r_on)
        res = mr.simulate(on, col, fs=config.fs_hz, rng=r_sim, temperature=temp)
        out.append(_Run(on, float(temp), res.output))
    return out


def _means(config: Config, run: _Run) -> NDArray[np.float64]:
    """Mean output over each settled dwell [deg/s] (the paper's per-rate measured output)."""
    n_settle = int(round(config.settle_s * config.fs_hz))
    return units.to_deg_per_s(run.output[n_settle:].mean(axis=0))


def _recording(config: Config, run: _Run, *, index: int, role: str, seed: int) -> Recording:
    """A run as a record: the dwells one after another in table order."""
    n, k = run.output.shape
    rate = np.repeat(units.deg_per_s(np.asarray(config.rates_dps, dtype=float)), n)
    n_settle = int(round(config.settle_s * config.fs_hz))
    windows = [[j * n + n_settle, (j + 1) * n] for j in range(k)]
    return Recording(
        fs=config.fs_hz,
        channels={
            "rate": Channel(run.output.T.reshape(-1), "rad/s", "gyro output"),
            "table_rate": Channel(rate, "rad/s", "rate-table rate"),
            "temperature": Channel(np.full(n * k, run.temperature), "K", "die temperature"),
        },
        truth={"true_rate": Channel(rate.copy(), "rad/s", "table rate (truth)")},
        metadata={
            "scenario": NAME,
            "seed": seed,
            "run": index,
            "role": role,
            "variant": config.variant,
            "rates_dps": list(config.rates_dps),
            "windows_samples": windows,
            "die_temperature_c": float(units.to_celsius(run.temperature)),
            "turn_on_bias_dps": float(units.to_deg_per_s(run.unit.turn_on_bias)),
            "scale_factor_error_ppm": float(units.to_ppm(run.unit.turn_on_scale_factor)),
            "rate_authority_dps": float(units.to_deg_per_s(mr.rate_authority(run.unit))),
            "version": package_version(),
        },
        name=f"{role}_run{index}",
    )


def simulate(config: Config, seed: int) -> list[Recording]:
    """Unit ``seed``'s runs: the ``n_fit_runs`` fitting runs then the held-out runs.

    The unit is drawn from the first child stream of ``numpy.random.default_rng(seed)``; each
    run has its own child of the second (ambient temperature, power-on, noise).
    """
    return [
        _recording(
            config, run, index=i, role="fit" if i < config.n_fit_runs else "heldout", seed=seed
        )
        for i, run in enumerate(_runs(config, seed))
    ]


def memory_estimate(config: Config) -> float:
    """Peak memory of one unit's :func:`experiment` or :func:`simulate` [bytes], before allocating.

    Per unit (one worker process); the runner multiplies it by the units it runs at once
    (:func:`gyrobench.scenarios.units.check_unit_memory`). With ``n_run = (settle_s +
    average_s) fs_hz len(rates_dps)`` samples in one run (one slow-flow call of
    ``sim.mems_resonator.simulate``), ``N = n_run (n_fit_runs + n_heldout_runs)`` in all, and
    ``n_dense = 200 (span(rates_dps) / dense_step_dps + 1)`` in one dense-sweep call
    (:func:`static_output`, 200 samples per rate)::

        bytes = 1.1 x (48 N + 376 max(n_run, n_dense) + 40e6)

    48 B = 6 float64 series held per sample of every run (outputs, recordings' channels),
    376 B = 47 float64 working series of the slow-flow call running, 40 MB the rest (fits,
    figure data); 1.1 is the margin. MEASURED (peak RSS increase, one BLAS thread;
    tests/scenarios/test_memory_estimates.py): 160 MB at the default (N = 1.0e6), 514 MB at
    average_s = 240 (N = 4.0e6), 314 MB at fs_hz = 400 with n_fit_runs = 6 (N = 3.6e6),
    1.0 GB at dense_step_dps = 0.5 (n_dense = 2.9e6); the formula is 1.2-1.4 x these.
    Floats: an absurd record gives a huge (or infinite) estimate, never an overflow.
    """
    n_run = (float(config.settle_s) + float(config.average_s)) * config.fs_hz
    n_run *= len(config.rates_dps)
    span = float(max(config.rates_dps)) - float(min(config.rates_dps))
    n_dense = 200.0 * (span / config.dense_step_dps + 1.0)
    n_all = n_run * (config.n_fit_runs + config.n_heldout_runs)
    return 1.1 * (48.0 * n_all + 376.0 * max(n_run, n_dense) + 40e6)


def rate_means(rec: Recording) -> NDArray[np.float64]:
    """Mean output over each settled window of a record [deg/s]."""
    y = units.to_deg_per_s(rec["rate"])
    return np.array([float(np.mean(y[a:b])) for a, b in rec.metadata["windows_samples"]])


# ------------------------------------------------------------------ scoring
def nonlinearity_scorer(compensated: NDArray[np.float64], run: HeldOutRun) -> dict[str, float]:
    """K_n [%] of the compensated table against the table rates (IEEE), and the RMS error."""
    fit = fit_scale_factor(run.truth, np.asarray(compensated, dtype=float))
    err = np.asarray(compensated, dtype=float) - run.truth
    return {"nonlinearity_pct": fit.nonlinearity_pct, "rms_dps": float(np.sqrt(np.mean(err**2)))}


def _estimators(config: Config, seed: int) -> dict[str, Any]:
    from gyrobench.analysis.compensation.bayes_mlp import BayesianRegularizedMLP
    from gyrobench.analysis.compensation.polynomial import PiecewisePolynomial, TwoStagePolynomial

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
    rates = np.asarray(config.rates_dps, dtype=float)
    means = [_means(config, run) for run in _runs(config, seed)]
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


def repeatability_floor(
    rates: NDArray[np.float64], fit_means: NDArray[np.float64], outputs: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Compensate ``outputs`` with a curve through the fitting runs' per-rate mean outputs [deg/s].

    The curve maps output -> rate by piecewise-linear interpolation through the
    points (mean over the fitting runs of the output at rate j, rate j), extended
    linearly beyond the end rates by the end chords. It has no model error at the
    table rates, so the K_n left on a held-out run is its run-to-run
    difference from the fitting runs (divided by the local slope): the
    repeatability floor of a compensation fitted to these runs when the runs differ
    by bias, temperature and noise. It is one run's value, not a bound: a smoother
    curve can land below it, and does when the runs' scale factors differ.

    Parameters
    ----------
    rates : ndarray, shape (m,)
        Table rates [deg/s].
    fit_means : ndarray, shape (n_runs, m)
        Per-rate mean outputs of the fitting runs [deg/s].
    outputs : ndarray, shape (m,)
        The outputs to compensate [deg/s].

    Returns
    -------
    ndarray, shape (m,)
        Compensated rates [deg/s].
    """
    xm = np.asarray(fit_means, dtype=float).mean(axis=0)
    order = np.argsort(xm)
    x, r = xm[order], np.asarray(rates, dtype=float)[order]
    if np.any(np.diff(x) <= 0):
        raise ValueError(
            "repeatability_floor needs mean outputs that increase strictly with rate; "
            f"got {xm.tolist()!r}"
        )
    o = np.asarray(outputs, dtype=float)
    out = np.interp(o, x, r)
    lo, hi = o < x[0], o > x[-1]
    out[lo] = r[0] + (o[lo] - x[0]) * (r[1] - r[0]) / (x[1] - x[0])
    out[hi] = r[-1] + (o[hi] - x[-1]) * (r[-1] - r[-2]) / (x[-1] - x[-2])
    return out


def _mean_kn(rates: NDArray, tables) -> float:
    """Mean K_n [%] of compensated rate tables against the table rates."""
    return float(np.mean([fit_scale_factor(rates, c).nonlinearity_pct for c in tables]))


def _floor_kn(rates: NDArray, fit_means: NDArray, outputs: NDArray) -> float:
    """Mean K_n [%] of ``outputs`` (one table per row) compensated by repeatability_floor.

    NaN when the fitting runs' mean outputs do not increase strictly with rate (a saturated
    device's flat plateau): no curve through them can be inverted there.
    """
    xm = np.asarray(fit_means, dtype=float).mean(axis=0)
    if np.any(np.diff(xm[np.argsort(rates)]) <= 0):
        return math.nan
    return _mean_kn(rates, [repeatability_floor(rates, fit_means, o) for o in outputs])


# ------------------------------------------------------------------ experiment (one unit)
def _dense_rates(config: Config) -> NDArray[np.float64]:
    """The dense sweep's rates [deg/s]: every ``dense_step_dps`` across the table's span."""
    lo, hi = min(config.rates_dps), max(config.rates_dps)
    return np.arange(lo, hi + 0.5 * config.dense_step_dps, config.dense_step_dps)


def _raw_analysis(
    rates: NDArray[np.float64], fit_means: NDArray[np.float64], held_means: NDArray[np.float64]
) -> dict[str, Any]:
    """Table 1 (mean of the fitting runs), raw K_n, the heuristic search (Table 2), low-rate K_n."""
    table1 = fit_means.mean(axis=0)
    fit1 = fit_scale_factor(rates, table1)
    search = breakpoint_search(rates, table1)
    low_kn = math.nan
    if search.negative is not None and search.positive is not None:
        low = (rates >= search.negative) & (rates <= search.positive)
        if low.sum() >= 3:
            low_kn = fit_scale_factor(rates[low], table1[low]).nonlinearity
    per_run = [fit_scale_factor(rates, m).nonlinearity_pct for m in fit_means]
    trace = [
        (s.side, s.end_rate, s.n_points, s.nonlinearity, s.abs_diff, s.diff2, s.counter)
        for s in search.trace
    ]
    std = fit_means.std(axis=0, ddof=1) if len(fit_means) > 1 else np.zeros_like(rates)
    return {
        "table1_dps": table1,
        "run_std_dps": std,
        "pointwise_pct": 100.0 * fit1.pointwise,
        "scale_factor": fit1.scale_factor,
        "bias_dps": fit1.bias,
        "raw_kn_pct_per_run": per_run,
        "raw_kn_pct": float(np.mean(per_run)),
        "raw_kn_pct_heldout": _mean_kn(rates, held_means),
        "low_rate_kn": low_kn,
        "breakpoints_dps": list(search.breakpoints),
        "search_trace": np.array(trace, dtype=float).reshape(-1, 7),
    }


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


def _score_method(
    est: Any,
    rates: NDArray[np.float64],
    fit_means: NDArray[np.float64],
    held_means: NDArray[np.float64],
    dense_rates: NDArray[np.float64],
    dense_outputs: NDArray[np.float64],
) -> dict[str, Any]:
    """K_n [%] of one fitted compensator: in-sample, held-out table rates, dense held-out sweep.

    ``est`` None (the method could not be fitted): every number NaN (untestable).
    """
    if est is None:
        nan = math.nan
        return {
            "kn_fit_pct": nan, "kn_heldout_pct": nan, "rms_heldout_pct": nan, "kn_dense_pct": nan,
            "compensated_heldout_dps": np.full(rates.size, nan),
            "pointwise_heldout_pct": np.full(rates.size, nan),
            "dense_error_dps": np.full(dense_rates.size, nan),
        }
    held = [est.predict(m[:, None]) for m in held_means]
    hfits = [fit_scale_factor(rates, c) for c in held]
    dense = [est.predict(d[:, None]) for d in dense_outputs]
    return {
        "kn_fit_pct": _mean_kn(rates, [est.predict(m[:, None]) for m in fit_means]),
        "kn_heldout_pct": float(np.mean([f.nonlinearity_pct for f in hfits])),
        "rms_heldout_pct": float(np.mean([100 * np.sqrt(np.mean(f.pointwise**2)) for f in hfits])),
        "kn_dense_pct": _mean_kn(dense_rates, dense),
        "compensated_heldout_dps": held[0],
        "pointwise_heldout_pct": 100.0 * hfits[0].pointwise,
        "dense_error_dps": dense[0] - dense_rates,
    }


def _continuity(model: Any, fit_means: NDArray[np.float64], rates: NDArray[np.float64]) -> list:
    """Curves of the piecewise fit around each breakpoint, with and without the Hermite join."""
    X, y = fit_means.reshape(-1), np.tile(rates, len(fit_means))
    out = []
    for k, (b, br) in enumerate(zip(model.breakpoints_, model.breakpoint_rates_, strict=True)):
        h = model.half_join_
        xs = np.linspace(b - 4 * h, b + 4 * h, 200)
        m = np.abs(X - b) < 4 * h
        out.append(
            {
                "breakpoint": float(b),
                "rate_dps": float(br),
                "half_join": float(h),
                "x": xs,
                "left": model.segments_[k].predict(xs[:, None]),
                "right": model.segments_[k + 1].predict(xs[:, None]),
                "joined": model.predict(xs[:, None]),
                "data_x": X[m],
                "data_y": y[m],
            }
        )
    return out


def _eval_times_ms(models: Mapping[str, Any], x: NDArray[np.float64], repeats: int) -> dict:
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


def _quantities(raw: Mapping[str, Any], methods: Mapping[str, Mapping]) -> dict[str, float | None]:
    """One number per claim quantity (see CLAIMS); booleans as 1.0 / 0.0."""
    held = {k: m["kn_heldout_pct"] for k, m in methods.items()}
    dense = {k: m["kn_dense_pct"] for k, m in methods.items()}
    rms = {k: m["rms_heldout_pct"] for k, m in methods.items()}
    others = [k for k in methods if k != "piecewise"]
    q: dict[str, float | None] = {
        "raw_kn_pct": raw["raw_kn_pct"],
        "breakpoints_at_1800": float(raw["breakpoints_dps"] == [-1800.0, 1800.0]),
        "low_rate_kn": raw["low_rate_kn"],
    }
    for key in methods:
        q[f"kn_heldout_pct.{key}"] = held[key]
        q[f"improvement.{key}"] = raw["raw_kn_pct_heldout"] / held[key]
    q["order_as_paper"] = _flag(held, _before(PAPER_ORDER, held))
    q["piecewise_best"] = _flag(held, all(held["piecewise"] < held[k] for k in others))
    q["bayes_bp_beats_two_stage"] = _flag(held, held["bayes_bp"] < held["two_stage_poly"])
    q["piecewise_smallest_rms"] = _flag(rms, all(rms["piecewise"] < rms[k] for k in others))
    for key in methods:
        q[f"kn_dense_pct.{key}"] = dense[key]
    q["order_as_paper_dense"] = _flag(dense, _before(PAPER_ORDER, dense))
    return q


def _flag(values: Mapping[str, float], holds: bool) -> float | None:
    """A ranking as 1.0 / 0.0, or None (untestable) when a method has no value (not fitted)."""
    if any(not math.isfinite(v) for v in values.values()):
        return None
    return float(holds)


def _trace(config: Config, run: _Run) -> dict[str, NDArray[np.float64]]:
    """A 1 Hz trace of a run (dwells in table order) for the figure."""
    n, k = run.output.shape
    step = max(1, int(round(config.fs_hz)))
    y = run.output.T.reshape(-1)[::step]
    table = np.repeat(np.asarray(config.rates_dps, dtype=float), n)[::step]
    return {
        "time_s": np.arange(y.size) * step / config.fs_hz,
        "table_dps": table,
        "output_dps": units.to_deg_per_s(y),
    }


def experiment(config: Config, seed: int) -> dict[str, Any]:
    """One unit: its rate-table runs, raw K_n and breakpoints, the three methods fitted and scored.

    Returns the unit's ``quantities`` (one number per claim, see :data:`CLAIMS`) and
    what :func:`report` draws: Table 1 and the breakpoint search of the fitting runs,
    per method the in-sample, held-out and dense-sweep K_n [%] and curves, the
    repeatability floor, the unit's rate authority, a 1 Hz trace of fitting run 0.
    Deterministic in (config, seed) except ``timing_ms`` and ``fit_time_ms`` (wall times).
    """
    runs = _runs(config, seed)
    rates = np.asarray(config.rates_dps, dtype=float)
    nf = config.n_fit_runs
    means = np.array([_means(config, run) for run in runs])
    fit_means, held_means = means[:nf], means[nf:]
    raw = _raw_analysis(rates, fit_means, held_means)
    dense_rates = _dense_rates(config)
    dense_out = np.array([static_output(r.unit, dense_rates, r.temperature) for r in runs[nf:]])
    models, fit_ms, fit_errors = _fit_methods(config, seed, rates, fit_means)
    pw, bp = models["piecewise"], models["bayes_bp"]
    methods = {
        k: _score_method(est, rates, fit_means, held_means, dense_rates, dense_out)
        for k, est in models.items()
    }
    return {
        "seed": seed,
        "variant": config.variant,
        "quantities": _quantities(raw, methods),
        "rates_dps": rates,
        "fit_means_dps": fit_means,
        "held_means_dps": held_means,
        "raw": raw,
        "raw_kn_dense_pct": _mean_kn(dense_rates, dense_out),
        "dense_rates_dps": dense_rates,
        "methods": methods,
        "floor_pct": _floor_kn(rates, fit_means, held_means),
        "floor_fit_pct": _floor_kn(rates, fit_means, fit_means),
        "rate_authority_dps": float(units.to_deg_per_s(mr.rate_authority(runs[0].unit))),
        "piecewise_orders": [] if pw is None else list(pw.orders_),
        "continuity": [] if pw is None else _continuity(pw, fit_means, rates),
        "mlp": {} if bp is None else {"gamma": bp.gamma_, "epochs_run": bp.n_iter_},
        "fit_errors": fit_errors,
        "trace": _trace(config, runs[0]),
        "timing_ms": _eval_times_ms(models, held_means[0][:, None], config.timing_repeats),
        "fit_time_ms": fit_ms,
    }


# ------------------------------------------------------------------ claims
#: what the "calibrated" variant sets from the paper (named by the raw-K_n claim's report note)
CALIBRATED_INPUT = (
    "sim.mems_resonator MemsResonator.dac_full_scale (rebalance DAC full scale v_max) = "
    f"{CALIBRATED_V_MAX_V} V, solved with scipy brentq (calibrated_v_max) so that the median "
    "noise-free raw K_n of units 0-19 on the paper's 21 rates is 15.71 % (design value 0.7 V); "
    "only with Config.variant = 'calibrated'"
)
_TEXT3 = "Sec. 3, text and Table 3"


def _method_claims(key: str) -> tuple[Claim, ...]:
    label, kn = METHOD_LABELS[key], PAPER_KN_PCT[key]
    return (
        Claim(
            id=f"001.kn_heldout.{key}",
            paper=PAPER,
            where="Table 3",
            statement=(
                f"{label} compensation brings K_n to {kn} % (scored here on a held-out run at the "
                "21 table rates)."
            ),
            kind="emergent",
            quantity=f"kn_heldout_pct.{key}",
            comparator=within_factor(kn),
            paper_value=kn,
            unit="%",
        ),
        Claim(
            id=f"001.improvement.{key}",
            paper=PAPER,
            where=_TEXT3,
            statement=(
                f"{label} compensation improves K_n by about two orders of magnitude (raw / "
                "compensated K_n of the held-out run, read as 30x to 300x; the paper's own "
                "Table 3 gives 112x, 27x and 35x)."
            ),
            kind="emergent",
            quantity=f"improvement.{key}",
            comparator=in_range(30.0, 300.0),
            unit="x",
        ),
    )


def _dense_claim(key: str) -> Claim:
    label, kn = METHOD_LABELS[key], PAPER_KN_PCT[key]
    return Claim(
        id=f"001.kn_dense.{key}",
        paper=PAPER,
        where="Table 3 (extension: between the table rates)",
        statement=(
            f"{label}: the paper's K_n = {kn} % (scored at the 21 table rates) holds between them "
            f"too (our extension: noise-free held-out sweep every 10 deg/s)."
        ),
        kind="emergent",
        quantity=f"kn_dense_pct.{key}",
        comparator=within_factor(kn),
        paper_value=kn,
        unit="%",
    )


def _order_claim(id_: str, where: str, statement: str, quantity: str) -> Claim:
    return Claim(
        id=id_,
        paper=PAPER,
        where=where,
        statement=statement,
        kind="emergent",
        quantity=quantity,
        comparator=is_true(),
    )


CLAIMS: tuple[Claim, ...] = (
    Claim(
        id="001.raw_kn",
        paper=PAPER,
        where="Sec. 3, after Table 1",
        statement=(
            "The raw scale-factor nonlinearity K_n, averaged over the runs, is 15.71 % "
            "(emergent on the default design; calibrated under Config.variant = 'calibrated', "
            "which sets v_max for it)."
        ),
        kind="emergent",
        quantity="raw_kn_pct",
        comparator=within_factor(15.71),
        paper_value=15.71,
        unit="%",
    ),
    Claim(
        id="001.breakpoints",
        paper=PAPER,
        where="Table 2",
        statement=(
            "The heuristic breakpoint search splits the range at -1800 and +1800 deg/s "
            "(negative high-rate, low-rate and positive high-rate segments; the heuristic "
            "runs unchanged on the simulated Table 1)."
        ),
        kind="emergent",
        quantity="breakpoints_at_1800",
        comparator=is_true(),
    ),
    Claim(
        id="001.low_rate_kn",
        paper=PAPER,
        where="Sec. 3, after Table 2",
        statement=(
            "In the low-rate segment (between the breakpoints found) K_n is of order 1e-3 "
            "(read as within a factor sqrt(10) of 1e-3; untestable on a unit where the "
            "heuristic does not find both breakpoints)."
        ),
        kind="emergent",
        quantity="low_rate_kn",
        comparator=within_factor(1e-3, math.sqrt(10.0)),
        paper_value=1e-3,
        unit="-",
    ),
    *(c for key in METHOD_LABELS for c in _method_claims(key)),
    _order_claim(
        "001.order",
        _TEXT3,
        "Ranking by K_n: the heuristic piecewise fit best, Bayes-BP second, the two-stage "
        "polynomial worst (held-out run, table rates).",
        "order_as_paper",
    ),
    _order_claim(
        "001.piecewise_best",
        _TEXT3,
        "The heuristic piecewise fit compensates best (lowest held-out K_n of the three).",
        "piecewise_best",
    ),
    _order_claim(
        "001.bayes_bp_beats_two_stage",
        _TEXT3,
        "The Bayes-BP network compensates better than the two-stage 9th-order polynomial.",
        "bayes_bp_beats_two_stage",
    ),
    _order_claim(
        "001.piecewise_smallest_error",
        "Fig. 6",
        "The piecewise fit has the smallest overall error (RMS of the held-out pointwise "
        "nonlinearity a_j).",
        "piecewise_smallest_rms",
    ),
    *(_dense_claim(key) for key in METHOD_LABELS),
    _order_claim(
        "001.order_dense",
        "Table 3 (extension: between the table rates)",
        "The paper's ranking (piecewise < Bayes-BP < two-stage) also holds on the dense held-out "
        "sweep (our extension).",
        "order_as_paper_dense",
    ),
)


#: where the effects below come from (re-measure with :func:`deviation_effects`)
_MEASURED = (
    "medians over units (seeds) 0-19, default Config (design device), held-out K_n at the "
    "table rates"
)

DEVIATIONS: tuple[Deviation, ...] = (
    Deviation(
        paper=PAPER,
        what="the device under test",
        paper_says=(
            "a +-3600 deg/s MEMS prototype whose output bends beyond about 1800 deg/s "
            "(raw K_n 15.71 %)"
        ),
        we_do=(
            "units drawn from sim.mems_resonator's plausible +-3600 deg/s force-rebalance design "
            "(v_max = 0.7 V: knee at the rebalance authority, 1.1-1.4x the range); "
            "Config.variant = 'calibrated' sets v_max = 0.44017 V (CALIBRATED to 15.71 %)"
        ),
        reason=(
            "the knee must follow from a physical limit of the device, not a curve placed at "
            "the paper's breakpoint (issue 16); the paper does not describe its device's design"
        ),
        effect=(
            f"{_MEASURED}: design: knee 4057-5226 deg/s, raw K_n 5.1e-5 % (noise of the dwell "
            "means), breakpoints on 1/20 units, every K_n and ranking claim but two fails "
            "(compensation cannot improve a linear table). Calibrated variant: knee 2510-3283 "
            "deg/s, raw K_n 15.7 % (19/20 within 2x, calibrated), flat output beyond the knee, "
            "so compensated K_n 15.3 % (piecewise), 9.8 % (two-stage), 11.4 % (BR-MLP), "
            "improvement 1.0-1.6x, breakpoints at +-1800 on 0/20; 0.76 s per unit "
            "(design 0.58 s; reproduce --workers 1 on a shared 2-core machine)"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="scoring on a held-out run",
        paper_says=(
            "fits the several groups of data and computes K_n of the compensated output by eqs. "
            "(5)-(6) (Table 3); no run kept out of the fit is mentioned"
        ),
        we_do=(
            "the claims score each method on a power-on it never saw (own turn-on bias and "
            "scale-factor error, temperature and noise); the in-sample K_n is reported beside it"
        ),
        reason="a compensation is used on later power-ons; in-sample K_n flatters a flexible model",
        effect=(
            f"{_MEASURED}: in-sample piecewise 5.2e-5 %, two-stage 1.41e-3 %, BR-MLP 3.8e-3 % "
            "against held-out 5.4e-5 %, 1.39e-3 %, 3.8e-3 %; the paper's order on 0/20 units "
            "either way; no claim's verdict changes"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="number of runs",
        paper_says="'several groups' of data (number not given); Table 1 is their mean",
        we_do=(
            "3 fitting power-ons pooled for the fits (Table 1 their mean) and 1 held-out "
            "power-on per unit; a 9th-order segment on the rates of one side needs >= 10 "
            "distinct outputs, so >= 2 runs must be pooled"
        ),
        reason="the paper does not give the number; 3 is the smallest that leaves margin",
        effect=(
            f"{_MEASURED}: with 5 fitting runs piecewise 5.2e-5 %, two-stage 2.0e-3 %, BR-MLP "
            "3.7e-3 % (3 runs: 5.4e-5, 1.39e-3, 3.8e-3 %); the paper's order on 0/20 units "
            "either way; no verdict changes"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="dwells, settling and warm-up",
        paper_says=(
            "warm-up 20-30 min, then the table steps through the rates; 200 Hz, 1-2 min "
            "averaged per settled rate"
        ),
        we_do=(
            "each dwell an independent column of the slow flow started at its equilibrium, "
            "0.5 s settling, 60 s averaged; die temperature constant per run (25 degC, 0.5 K "
            "run-to-run), no table acceleration and no warm-up drift"
        ),
        reason=(
            "the rebalance loop settles in ms and the resonator model takes a temperature per "
            "call; 60 s (the paper's lower end) keeps a unit near the runtime budget"
        ),
        effect=(
            f"{_MEASURED}: with 120 s averaged raw K_n 3.9e-5 %, piecewise 4.1e-5 %, two-stage "
            "1.37e-3 %, BR-MLP 3.8e-3 %, a split on 5/20 units (60 s: 5.1e-5, 5.4e-5, 1.39e-3, "
            "3.8e-3 %, 1/20); +-1800 on 0/20 either way; no verdict changes"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="piecewise segments: curvature penalty",
        paper_says="each segment an ordinary least-squares polynomial (eqs. 7-9), orders 9-1-9",
        we_do=(
            "least squares with a curvature penalty alpha = 1e-6 (scaled units) on each segment "
            "(PiecewisePolynomial.alpha)"
        ),
        reason=(
            "on six distinct rates a plain 9th-order fit is not determined between them and "
            "oscillates between them"
        ),
        effect=(
            f"{_MEASURED}: alpha = 0 gives the same medians (piecewise 5.4e-5 %): the heuristic "
            "splits on 1/20 design units, so the piecewise fit is almost always one linear "
            "segment; no verdict changes"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="continuity at the breakpoints",
        paper_says=(
            "weighted refit f2 of the next segment from x_(n-4), then a cubic Hermite curve "
            "between (x_(n-3), y_(n-3)) and (x_4, y_4) over the overlap of the two fits"
        ),
        we_do=(
            "a cubic Hermite curve over a join of fixed width (5 % of the output span, centred "
            "on the breakpoint), end values and slopes from the two segment fits; no weighted "
            "refit"
        ),
        reason="the paper's weights and index conventions are not given completely",
        effect=(
            f"{_MEASURED}: join width 2 % and 10 % give the same medians as 5 % (piecewise "
            "5.4e-5 %; no breakpoint on 19/20 design units); no verdict changes"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="Bayes-BP network training",
        paper_says="Bayes-BP network with 10 hidden nodes trained on the learning set (MATLAB)",
        we_do=(
            "numpy re-implementation of MATLAB trainbr (Levenberg-Marquardt + MacKay evidence), "
            "tanh hidden layer, linear output, mapminmax scaling, Nguyen-Widrow start seeded "
            "per unit, up to 1000 epochs, every fitting point used for training, one training"
        ),
        reason="the paper gives no training details; trainbr's defaults are the MATLAB ones",
        effect=(
            f"{_MEASURED}: BR-MLP 3.8e-3 % with 1000 epochs, 4.3e-3 % with 200; the paper's "
            "order on 0/20 units either way; no verdict changes"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="evaluation times",
        paper_says=(
            "0.247 ms (piecewise), 0.755 ms (two-stage), 37.8 ms (Bayes-BP); piecewise tens of "
            "times faster than the network and more than 2x faster than the two-stage polynomial"
        ),
        we_do="time each compensation of the 21-point table (numpy, one thread) but judge no claim",
        reason=(
            "a time measures an implementation and a machine (MATLAB, the paper's computer), "
            "not the method"
        ),
        effect=(
            f"{_MEASURED}: piecewise 0.11 ms, two-stage 0.17 ms, BR-MLP 0.08 ms: the network "
            "is fastest here (a 10-unit tanh layer on 21 points is a few numpy operations)"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="run-to-run repeatability of the device",
        paper_says=(
            "a real prototype; its repeatability is not given ('the nonlinear curves of the "
            "same prototype are similar')"
        ),
        we_do=(
            "each power-on draws a turn-on scale-factor error (1000 ppm, 1 sigma) and bias "
            "(0.1 deg/s), sim.mems_resonator defaults (rate grade, cited in docs/physics.md 5.1)"
        ),
        reason="no number for this device; the resonator model's population defaults",
        effect=(
            f"{_MEASURED}: with 0 ppm: piecewise 5.3e-5 %, two-stage 5.6e-5 %, BR-MLP 2.2e-4 % "
            "(1000 ppm: 5.4e-5, 1.39e-3, 3.8e-3 %): the 9th-order fits chase the runs' slope "
            "scatter; the paper's order on 0/20 units either way"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="breakpoint heuristic: where to split",
        paper_says="when the count reaches 3, split 'from the first point' (从第1个点处)",
        we_do=(
            "split at the end of the last interval before the run of positive signs "
            "(analysis.scale_factor.heuristic_split)"
        ),
        reason="the text does not say which point is 'the first'",
        effect=(
            "the other reading (the end of the first interval of the run) moves each split one "
            "table rate outward; over units 0-19 neither reading gives +-1800 on any unit, "
            "design or calibrated device (design: a split on 1/20 units; calibrated: 11/20, "
            "at 1080-2520 deg/s, on noise below the knee)"
        ),
    ),
)


def _variants(config: Config) -> dict[str, Config]:
    """The configurations :func:`deviation_effects` compares (name -> Config)."""
    nom = config.gyro.nominal
    return {
        "default": config,
        "calibrated": replace(config, variant="calibrated"),
        "fit_runs_5": replace(config, n_fit_runs=5),
        "sf_repeatability_0": replace(
            config,
            gyro=replace(config.gyro, nominal=replace(nom, scale_factor_repeatability=0.0)),
        ),
        "piecewise_alpha_0": replace(config, piecewise_alpha=0.0),
        "join_width_0.02": replace(config, join_width=0.02),
        "join_width_0.10": replace(config, join_width=0.10),
        "mlp_epochs_200": replace(config, mlp_epochs=200),
        "average_120s": replace(config, average_s=120.0),
    }


def _effect_row(us: Sequence[Mapping[str, Any]]) -> dict[str, float]:
    """Medians over units of the numbers the DEVIATIONS quote."""

    def med(f: Any) -> float:
        return finite_median(f(u) for u in us)

    row = {
        f"{what}.{k}": med(lambda u, k=k, w=what: u["methods"][k][w])
        for k in METHOD_LABELS
        for what in ("kn_fit_pct", "kn_heldout_pct", "kn_dense_pct")
    }
    row |= {f"eval_ms.{k}": med(lambda u, k=k: u["timing_ms"][k]) for k in METHOD_LABELS}
    row["raw_kn_pct"] = med(lambda u: u["raw"]["raw_kn_pct"])
    row["floor_pct"] = med(lambda u: u["floor_pct"])
    row["units_in_paper_order"] = float(sum(u["quantities"]["order_as_paper"] or 0.0 for u in us))
    row["units_with_a_breakpoint"] = float(sum(bool(u["raw"]["breakpoints_dps"]) for u in us))
    row["units_split_at_1800"] = float(sum(u["quantities"]["breakpoints_at_1800"] for u in us))
    return row


def deviation_effects(
    config: Config | None = None,
    seeds: Sequence[int] = tuple(range(20)),
    names: Sequence[str] | None = None,
) -> dict[str, dict[str, float]]:
    """Re-measure the effects quoted in :data:`DEVIATIONS` (slow: one experiment per variant/seed).

    For each variant of :func:`_variants` (or those in ``names``): the median over ``seeds``
    of each method's in-sample, held-out and dense-sweep K_n [%], the raw K_n, the
    repeatability floor [%], the evaluation times [ms], and counts of units in the paper's
    order, with any breakpoint, split at +-1800. The quoted numbers were measured with
    ``deviation_effects()`` (seeds 0-19).
    """
    base = Config() if config is None else config
    variants = _variants(base)
    keep = list(variants) if names is None else list(names)
    return {n: _effect_row([experiment(variants[n], s) for s in seeds]) for n in keep}


def claims_for(config: Config) -> tuple[Claim, ...]:
    """:data:`CLAIMS`, every one marked calibrated when ``config.variant`` sets v_max.

    v_max places the knee of the device, so it feeds the raw table every claim is computed
    from (raw K_n, the breakpoints, and each compensator's training data and improvement
    ratio): under the calibrated variant no paper-001 claim is reproduced. The shared
    runner judges these (:func:`gyrobench.scenarios.units.module_claims`).
    """
    if config.variant != "calibrated":
        return CLAIMS
    return tuple(replace(c, kind="calibrated", calibrated_input=CALIBRATED_INPUT) for c in CLAIMS)


# ------------------------------------------------------------------ report: tables
def _pct(values: Sequence[float], fmt: str = ".3g") -> str:
    """``"median [25th, 75th percentile]"`` of the units' values."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if v.size == 0:
        return "n/a"
    q1, q2, q3 = np.percentile(v, [25, 50, 75])
    return f"{q2:{fmt}} [{q1:{fmt}}, {q3:{fmt}}]"


def _table1(u: Mapping[str, Any]) -> Table:
    raw, rates = u["raw"], u["rates_dps"]
    rows = [
        [r, r, m, s, a]
        for r, m, s, a in zip(
            rates, raw["table1_dps"], raw["run_std_dps"], raw["pointwise_pct"], strict=True
        )
    ]
    return Table(
        f"Table 1. Ideal and measured output per table rate (unit seed {u['seed']}, mean of "
        f"{len(u['fit_means_dps'])} fitting runs)",
        ["rate [deg/s]", "ideal [deg/s]", "measured mean [deg/s]", "run std [deg/s]", "a_j [%]"],
        rows,
        note=(
            f"Raw K_n = {raw['raw_kn_pct']:.3g} % (mean over the runs; paper 15.71 %; device "
            f"'{u['variant']}', rate authority {u['rate_authority_dps']:.0f} deg/s); low-rate "
            f"K_n = {raw['low_rate_kn']:.1e} (paper: order 1e-3; n/a without both breakpoints). "
            "The paper's Table 1 values did not survive text extraction."
        ),
    )


def _table2(u: Mapping[str, Any]) -> Table:
    rows = []
    for side, end, npts, kn, d, dd, counter in u["raw"]["search_trace"]:
        rows.append(
            [
                "+" if side > 0 else "-",
                f"[0, {end:+.0f}]",
                int(npts),
                100 * kn,
                "" if math.isnan(d) else 100 * d,
                "" if math.isnan(dd) else 100 * dd,
                "" if math.isnan(dd) else ("+" if dd > 0 else "-"),
                "" if math.isnan(counter) else int(counter),
            ]
        )
    bps = u["raw"]["breakpoints_dps"]
    return Table(
        f"Table 2. Heuristic breakpoint search on Table 1 (unit seed {u['seed']})",
        ["side", "interval [deg/s]", "points", "K_n [%]", "abs diff [%]", "diff of abs diff [%]"]
        + ["sign", "counter"],
        rows,
        note=(
            f"Breakpoints found: {', '.join(f'{b:+.0f}' for b in bps) or 'none'} deg/s (paper: "
            "-1800 and +1800; the heuristic runs unchanged, where it splits is a result). "
            "Split after 3 consecutive positive "
            "signs, at the end of the last interval before the run (our reading of 'from the "
            "first point'). The paper's Table 2 numbers did not survive extraction."
        ),
    )


def _table3(units_: Sequence[Mapping[str, Any]]) -> Table:
    def col(f):
        return [f(u) for u in units_]

    rows: list[list[Any]] = [
        [
            "raw (no compensation)",
            _pct(col(lambda u: u["raw"]["raw_kn_pct_heldout"])),
            _pct(col(lambda u: u["raw_kn_dense_pct"])),
            _pct(col(lambda u: u["raw"]["raw_kn_pct"])),
            15.71,
            "",
            "",
        ]
    ]
    for key, label in METHOD_LABELS.items():
        rows.append(
            [
                label,
                _pct(col(lambda u, k=key: u["methods"][k]["kn_heldout_pct"])),
                _pct(col(lambda u, k=key: u["methods"][k]["kn_dense_pct"])),
                _pct(col(lambda u, k=key: u["methods"][k]["kn_fit_pct"])),
                PAPER_KN_PCT[key],
                _pct(col(lambda u, k=key: u["timing_ms"][k])),
                PAPER_TIME_MS[key],
            ]
        )
    rows.append(
        [
            "interpolation through the fit-run means (repeatability floor)",
            _pct(col(lambda u: u["floor_pct"])),
            "",
            _pct(col(lambda u: u["floor_fit_pct"])),
            "",
            "",
            "",
        ]
    )
    return Table(
        f"Table 3. K_n after compensation over {len(units_)} unit(s): median [interquartile range]",
        [
            "method",
            "K_n held-out, table rates [%]",
            "K_n held-out, dense sweep [%]",
            "K_n fitting runs (in-sample) [%]",
            "paper K_n [%]",
            "eval time, numpy [ms]",
            "paper time, MATLAB [ms]",
        ],
        rows,
        note=(
            "Held-out: runs the fit never saw, scored at the 21 table rates (the claims) and on "
            "the noise-free static curve of the held-out power-on every 10 deg/s (dense sweep, "
            "our extension; K_n depends on the grid through the LS line: the raw curve's is "
            "larger on the dense grid than at the 21 rates). In-sample is the paper's own scoring"
            " (its Table 3 is computed on the data it fitted). Eval time: median wall time of "
            "compensating the 21-point table on this machine (numpy), not comparable with the "
            "paper's MATLAB times. Last row: the run-to-run repeatability floor of these runs "
            "(n/a where the mean outputs do not increase strictly: a saturated plateau)."
        ),
    )


def _counts(labels: Sequence[str]) -> list[tuple[str, int]]:
    keys = sorted(set(labels), key=lambda k: (-labels.count(k), k))
    return [(k, labels.count(k)) for k in keys]


def _order_label(kn: Mapping[str, float]) -> str:
    ok = {k: v for k, v in kn.items() if math.isfinite(v)}
    missing = "".join(f" ({k} not fitted)" for k in kn if k not in ok)
    return " < ".join(sorted(ok, key=ok.__getitem__)) + missing


def _table4(units_: Sequence[Mapping[str, Any]]) -> Table:
    n = len(units_)
    bps = [", ".join(f"{b:+.0f}" for b in u["raw"]["breakpoints_dps"]) or "none" for u in units_]
    held = [_order_label({k: m["kn_heldout_pct"] for k, m in u["methods"].items()}) for u in units_]
    dense = [_order_label({k: m["kn_dense_pct"] for k, m in u["methods"].items()}) for u in units_]
    rows = [["breakpoints found [deg/s]", v, c] for v, c in _counts(bps)]
    rows += [["method order, held-out table rates (best first)", v, c] for v, c in _counts(held)]
    rows += [["method order, dense sweep (best first)", v, c] for v, c in _counts(dense)]
    for key in METHOD_LABELS:
        failed = sum(key in u["fit_errors"] for u in units_)
        if failed:
            rows.append([f"{METHOD_LABELS[key]}: could not be fitted", "ValueError", failed])
    return Table(
        f"Table 4. What the heuristic and the ranking give over {n} unit(s)",
        ["outcome", "value", f"units (of {n})"],
        rows,
        note="Paper: breakpoints -1800, +1800; order piecewise < bayes_bp < two_stage_poly.",
    )


# ------------------------------------------------------------------ report: figures
def _fig_raw(u: Mapping[str, Any]) -> Figure:
    from matplotlib.figure import Figure

    tr = u["trace"]
    fig = Figure(figsize=(8.0, 4.2))
    ax = fig.add_subplot()
    t = tr["time_s"] / 60.0
    ax.plot(t, tr["table_dps"], color="0.6", lw=1.0, label="table rate")
    ax.plot(t, tr["output_dps"], lw=0.8, label="gyro output")
    ax.set_xlabel("time [min]")
    ax.set_ylabel("rate [deg/s]")
    ax.set_title(f"Raw MEMS output at the 21 table rates (unit seed {u['seed']}, fit run 0, 1 Hz)")
    ax.grid(True, alpha=0.3)
    ax.legend()
    return fig


def _fig_io(u: Mapping[str, Any]) -> Figure:
    from matplotlib.figure import Figure

    rates, raw = u["rates_dps"], u["raw"]
    fig = Figure(figsize=(6.4, 4.8))
    ax = fig.add_subplot()
    ax.plot(rates, rates, color="0.6", lw=1.0, label="ideal output")
    line = raw["scale_factor"] * rates + raw["bias_dps"]
    ax.plot(rates, line, "--", color="C1", lw=1.0, label="LS line")
    ax.plot(rates, raw["table1_dps"], "o", color="C0", label="measured (mean of runs)")
    ax.set_xlabel("table rate [deg/s]")
    ax.set_ylabel("gyro output [deg/s]")
    kn = np.max(np.abs(raw["pointwise_pct"]))
    ax.set_title(f"Input vs output: K_n of the mean table = {kn:.2f} %")
    ax.grid(True, alpha=0.3)
    ax.legend()
    return fig


def _fig_continuity(u: Mapping[str, Any]) -> Figure:
    from matplotlib.figure import Figure

    joins = u["continuity"]
    fig = Figure(figsize=(9.0, 4.2))
    for k, c in enumerate(joins):
        ax = fig.add_subplot(1, len(joins), k + 1)
        ax.plot(c["x"], c["left"], "--", lw=1.0, label="left segment")
        ax.plot(c["x"], c["right"], "--", lw=1.0, label="right segment")
        ax.plot(c["x"], c["joined"], "k", lw=1.6, label="with Hermite join")
        pad = 0.1 * (c["joined"].max() - c["joined"].min())
        ax.set_ylim(c["joined"].min() - pad, c["joined"].max() + pad)  # bare segments diverge
        b, h = c["breakpoint"], c["half_join"]
        ax.axvspan(b - h, b + h, color="0.9")
        ax.plot(c["data_x"], c["data_y"], "o", color="C3", ms=4, label="data")
        ax.set_title(f"breakpoint {c['rate_dps']:+.0f} deg/s")
        ax.set_xlabel("gyro output [deg/s]")
        ax.set_ylabel("compensated rate [deg/s]")
        ax.grid(True, alpha=0.3)
        if k == 0:
            ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def _fig_compensated(u: Mapping[str, Any]) -> Figure:
    from matplotlib.figure import Figure

    rates = u["rates_dps"]
    fig = Figure(figsize=(6.4, 4.8))
    ax = fig.add_subplot()
    ax.plot(rates, rates, color="0.6", lw=1.0, label="ideal")
    ax.plot(rates, u["held_means_dps"][0], "o-", ms=3, lw=0.8, label="raw")
    for i, (key, m) in enumerate(u["methods"].items()):
        mark, label = "s^v"[i % 3], METHOD_LABELS[key]
        ax.plot(rates, m["compensated_heldout_dps"], mark, ms=4, mfc="none", label=label)
    ax.set_xlabel("table rate [deg/s]")
    ax.set_ylabel("output [deg/s]")
    ax.set_title(f"Held-out run before and after compensation (unit seed {u['seed']})")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    return fig


def _fig_nonlinearity(u: Mapping[str, Any]) -> Figure:
    from matplotlib.figure import Figure

    rates = u["rates_dps"]
    raw = fit_scale_factor(rates, u["held_means_dps"][0])
    fig = Figure(figsize=(9.0, 4.2))
    ax1 = fig.add_subplot(1, 2, 1)
    ax1.plot(rates, 100 * raw.pointwise, "o-", ms=3)
    ax1.set_title("before compensation")
    ax1.set_ylabel("pointwise nonlinearity a_j [%]")
    ax2 = fig.add_subplot(1, 2, 2)
    for key, m in u["methods"].items():
        a = m["pointwise_heldout_pct"]
        label = f"{METHOD_LABELS[key]} ({np.max(np.abs(a)):.3f} %)"
        ax2.plot(rates, a, "o-", ms=3, lw=0.8, label=label)
    ax2.set_title("after compensation (held-out run)")
    ax2.legend(fontsize=7)
    for ax in (ax1, ax2):
        ax.set_xlabel("table rate [deg/s]")
        ax.grid(True, alpha=0.3)
    fig.tight_layout()
    return fig


def _fig_dense(u: Mapping[str, Any]) -> Figure:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.0, 4.4))
    ax = fig.add_subplot()
    for key, m in u["methods"].items():
        ax.plot(u["dense_rates_dps"], m["dense_error_dps"], lw=0.9, label=METHOD_LABELS[key])
    for r in u["rates_dps"]:
        ax.axvline(r, color="0.85", lw=0.6, zorder=0)
    ax.set_xlabel("true rate [deg/s] (grey: the 21 table rates the models were fitted at)")
    ax.set_ylabel("compensated - true [deg/s]")
    ax.set_title(f"Dense held-out sweep, noise-free, every 10 deg/s (unit seed {u['seed']})")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    return fig


def _fig_population(units_: Sequence[Mapping[str, Any]]) -> Figure:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.0, 4.4))
    ax = fig.add_subplot()
    for i, key in enumerate(METHOD_LABELS):
        for j, (what, mark) in enumerate((("kn_heldout_pct", "o"), ("kn_dense_pct", "x"))):
            v = [u["methods"][key][what] for u in units_]
            x = i + 0.2 * (j - 0.5) + 0.04 * np.linspace(-1, 1, len(v))
            label = ("held-out, table rates", "held-out, dense sweep")[j] if i == 0 else None
            ax.plot(x, v, mark, color=f"C{j}", ms=4, label=label)
        ax.plot(
            [i - 0.3, i + 0.3],
            [PAPER_KN_PCT[key]] * 2,
            "k-",
            lw=1.5,
            label="paper" if i == 0 else None,
        )
    ax.set_xticks(range(len(METHOD_LABELS)), list(METHOD_LABELS.values()), fontsize=8)
    ax.set_yscale("log")
    ax.set_ylabel("K_n after compensation [%]")
    ax.set_title(f"K_n per unit ({len(units_)} units) beside the paper's Table 3")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    return fig


def _figures(units_: Sequence[Mapping[str, Any]]) -> list[FigureSpec]:
    u = units_[0]
    specs = [
        (
            "fig2_raw_output",
            "Raw gyro output over the rate-table program (cf. paper Fig. 2)",
            _fig_raw,
        ),
        (
            "fig3_input_output",
            "Table rate vs mean output with the LS line (cf. paper Fig. 3)",
            _fig_io,
        ),
        (
            "fig4_continuity",
            "Piecewise fit near the breakpoints, with and without the Hermite join (cf. Fig. 4)",
            _fig_continuity,
        ),
        (
            "fig5_compensated",
            "Held-out run before and after compensation (cf. paper Fig. 5)",
            _fig_compensated,
        ),
        (
            "fig6_nonlinearity",
            "Pointwise nonlinearity before and after compensation, held-out run (cf. paper Fig. 6)",
            _fig_nonlinearity,
        ),
        (
            "fig7_dense_sweep",
            "Compensation error between the table rates (not in the paper)",
            _fig_dense,
        ),
    ]
    figs = [
        FigureSpec(n, c, f(u)) for n, c, f in specs if n != "fig4_continuity" or u["continuity"]
    ]
    figs.append(
        FigureSpec(
            "fig8_population",
            "Held-out K_n of every unit beside the paper's values (not in the paper)",
            _fig_population(units_),
        )
    )
    return figs


# ------------------------------------------------------------------ report
def _jsonable(v: Any) -> Any:
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, np.generic):
        return v.item()
    if isinstance(v, Mapping):
        return {str(k): _jsonable(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_jsonable(x) for x in v]
    return v


def _results(units_: Sequence[Mapping[str, Any]]) -> dict[str, Any]:
    """The numbers behind the tables: unit 0's detail, every unit's quantities and K_n."""
    u = units_[0]
    keys = ("kn_fit_pct", "kn_heldout_pct", "kn_dense_pct", "rms_heldout_pct")
    unit0 = {
        "seed": u["seed"],
        "rates_dps": u["rates_dps"],
        "fit_means_dps": u["fit_means_dps"],
        "held_means_dps": u["held_means_dps"],
        "raw": {k: v for k, v in u["raw"].items()},
        "methods": {k: {f: m[f] for f in keys} for k, m in u["methods"].items()},
        "piecewise_orders": u["piecewise_orders"],
        "mlp": u["mlp"],
        "floor_pct": u["floor_pct"],
    }
    population = {
        "seeds": [x["seed"] for x in units_],
        "quantities": {k: [x["quantities"][k] for x in units_] for k in u["quantities"]},
        "methods": {
            k: {f: [x["methods"][k][f] for x in units_] for f in keys} for k in METHOD_LABELS
        },
        "raw_kn_dense_pct": [x["raw_kn_dense_pct"] for x in units_],
        "floor_pct": [x["floor_pct"] for x in units_],
        "breakpoints_dps": [x["raw"]["breakpoints_dps"] for x in units_],
        "rate_authority_dps": [x["rate_authority_dps"] for x in units_],
        "fit_errors": [x["fit_errors"] for x in units_],
        "eval_time_ms": {k: [x["timing_ms"][k] for x in units_] for k in METHOD_LABELS},
        "fit_time_ms": {k: [x["fit_time_ms"][k] for x in units_] for k in METHOD_LABELS},
    }
    return _jsonable(
        {
            "paper_kn_pct": PAPER_KN_PCT,
            "paper_eval_time_ms": PAPER_TIME_MS,
            "paper_order": list(PAPER_ORDER),
            "variant": units_[0]["variant"],
            "unit0": unit0,
            "population": population,
        }
    )


def _conclusion(
    config: Config, units_: Sequence[Mapping[str, Any]], claims: Sequence[ClaimResult]
) -> str:
    """Prose from the judged claims and the units' medians (no verdict is decided here)."""
    by: dict[str, list[ClaimResult]] = {"calibrated": [], "holds": [], "fails": [], "other": []}
    for c in claims:
        if c.claim.kind == "calibrated":
            by["calibrated"].append(c)
        else:
            v = c.verdict
            word = v.split()[0] if v.startswith(("holds", "fails")) else "other"
            by[word].append(c)

    def ids(cs):
        return ", ".join(f"{c.claim.id} ({c.holds}/{c.testable})" for c in cs) or "none"

    def med(f):
        return finite_median(f(u) for u in units_)

    def kn(k: str, what: str) -> float:
        return med(lambda u: u["methods"][k][what])

    kns = ", ".join(
        f"{METHOD_LABELS[k]} {kn(k, 'kn_heldout_pct'):.3g} % (paper {PAPER_KN_PCT[k]} %, dense "
        f"sweep {kn(k, 'kn_dense_pct'):.3g} %)"
        for k in METHOD_LABELS
    )
    floor = med(lambda u: u["floor_pct"])
    nom = device_spec(config).nominal
    sf_ppm = units.to_ppm(nom.scale_factor_repeatability)
    auth = [u["rate_authority_dps"] for u in units_]
    device = (
        f"Device: '{config.variant}' variant of the resonator population (rebalance DAC full "
        f"scale v_max = {nom.dac_full_scale:g} V"
        + (", CALIBRATED so the median noise-free raw K_n of units 0-19 is 15.71 %: it feeds "
           "the raw table every claim is computed from, so every claim is calibrated under this "
           "variant, none reproduced" if
           config.variant == "calibrated" else ", the plausible design: nothing set from the "
           "paper, every claim emergent")
        + f"); rate authority (knee) {min(auth):.0f}-{max(auth):.0f} deg/s over the units, "
        f"turn-on scale-factor repeatability {sf_ppm:g} ppm (1 sigma). "
    )
    return (
        f"Over {len(units_)} unit(s). {device}Calibrated (set from the paper, not reproduced): "
        f"{ids(by['calibrated'])}. Emergent claims that hold for most units: {ids(by['holds'])}. "
        f"Emergent claims that fail for most units: {ids(by['fails'])}. Undecided: "
        f"{ids(by['other'])}. Median held-out K_n after compensation: {kns}. Median raw K_n "
        f"{med(lambda u: u['raw']['raw_kn_pct']):.3g} % (paper 15.71 %). The run-to-run "
        f"repeatability floor of the simulated runs is {floor:.3g} % (median over the units "
        "where it is defined: not where a saturated plateau repeats an output). Beyond the "
        "knee the output is flat, so no compensator can recover the rate there. The dense "
        "sweep scores each fit between the "
        "21 rates it was fitted at, which the paper's table does not."
    )


def report(
    config: Config, units: Sequence[Mapping[str, Any]], claims: Sequence[ClaimResult]
) -> Outcome:
    """Tables and figures from the units' results (detail from the first unit); no verdicts."""
    if not units:
        raise ValueError("report needs at least one unit's experiment result; got none")
    return Outcome(
        scenario=NAME,
        title=TITLE,
        seed=int(units[0]["seed"]),
        config=config,
        results=_results(units),
        tables=[_table1(units[0]), _table2(units[0]), _table3(units), _table4(units)],
        figures=_figures(units),
        conclusion=_conclusion(config, units, claims),
    )
