"""Paper 003: IFOG temperature drift from coil physics; RBF compensation with the T x dT term.

Cheng, Qi, Zhao (Harbin Engineering University), "Design of a temperature-drift error
compensation system for interferometric FOGs" (seed 003, summary in shared/seeds/README.md).

What is simulated
-----------------
One FOG unit (quadrupolar 40-layer coil, 1000 m, D = 0.1 m, with drawn winding defects)
sits in a thermal chamber. Its drift is NOT a formula in T and dT: the chamber drives a
lagging housing, heat diffuses radially through the potted fibre pack (implicit steps of
5 s), and the rate error is the Shupe integral over the fibre with the elasto-optic strain
term and a temperature-dependent dn/dT (``gyrobench.sim.coil``, ``gyrobench.sim.fog``). The test logs what the
paper logs: the gyro output and one coil temperature sensor (noise 3 mK, 1 mK steps).

Protocols (paper defaults)
--------------------------
- identification (x2; run 1 trains and selects, run 2 checks the identification): from
  20 degC cool to -10 degC and settle 2 h; heat to 40 degC and hold 2 h; cool to -10 degC
  and hold 2 h; ramps at 1 degC/min (the paper does not print its rate); true rate 0.
- validation 1: 5 runs, 1 h at -10 degC, -10 -> 40 degC at 10 degC/h, 1 h at 40 degC; true rate 0.
- validation 2: 5 runs, same at 0.5 degC/min; constant true rate 180 deg/h (the turntable).

Rates: the output and the sensor are logged at 1 Hz; the analysis works on 100-s block
means (``analysis_block_s``; the paper's data are slow), features (T [degC], dT/dt
[degC/s] by a 15-min Savitzky-Golay derivative, T x dT) from the logged temperature only.

Compensation
------------
RBF networks grown as MATLAB newrb (``gyrobench.analysis.compensation.rbf``; inputs min-max
scaled to [-1, 1], spread in those units) fitted to the drift output - truth of
identification run 1: "improved" on (T, dT, T x dT), "traditional" on (T, dT). The paper
fits Q = output - mean(output); with the turntable's known rate we fit output - truth, which
also removes the constant bias (stated, not hidden). MSE against the true rate in (deg/h)^2.
The paper prints neither spread nor goal (goal 0 here). Each network's spread and neuron
count are chosen by leave-one-segment-out cross-validation on identification run 1 alone
(``select_rbf``: folds settle / heat + hold / cool + hold; the fewest neurons within 10 %
of the best CV MSE, ties to the largest spread; the same rule for both models). No
validation run influences the choice. The report also carries a table of how both
conclusions change over spread 1-16 and 5-20 neurons. That table is scored on the
validation runs and is labelled as such; it is a diagnostic and is not used for selection.

Further checks in the report: identification run 2 scored with both networks (its own
table; it takes no part in training or selection); streaming compensation equal to batch;
and the deployment form (the exported a1/a2 network, ``deployment_float32``) evaluated in
single precision as on the paper's DSP, against float64. Its acceptance criterion, no
held-out run's MSE changed by more than 1 %, is ours: the paper states none.

Run-to-run realism: the housing lag differs by ``housing_lag_run_rms`` (10 %) between
chamber runs, and the noise of every run is a fresh stream; the unit (its winding
defects) is the same for all runs of a seed. How large the drift is, and therefore the
raw/compensated ratio, depends strongly on the drawn unit (the seed). The report therefore
runs the whole pipeline for ``seed_summary_count`` (8) seeds. With the CV rule, the
paper's two conclusions hold for some units and not for others.
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import dataclass, replace

import numpy as np
from matplotlib.figure import Figure

from gyrobench.analysis.compensation.rbf import RBFNetwork, StreamingCompensator, batch_compensate
from gyrobench.analysis.features import block_means, thermal_features
from gyrobench.scenarios.base import CompensationTask, FigureSpec, Headline, HeldOutRun, Outcome, Table
from gyrobench.sim import units
from gyrobench.sim.coil import (
    WINDING_PATTERNS,
    CoilSpec,
    CoilThermalModel,
    Winding,
    segment_weight,
    shupe_terms,
)
from gyrobench.sim.environment import PiecewiseLinear, Ramp, Soak, thermal_profile
from gyrobench.sim.fog import FOGSpec, FOGUnit, TemperatureSensorSpec
from gyrobench.sim.noise import NoiseModel
from gyrobench.sim.recording import Recording

NAME = "ifog_thermal"
TITLE = (
    "IFOG thermal drift from Shupe coil physics; RBF compensation with the T x dT term (paper 003)"
)

FEATURES_IMPROVED = ("T [degC]", "dT/dt [degC/s]", "T x dT/dt [degC^2/s]")
FEATURES_TRADITIONAL = FEATURES_IMPROVED[:2]

_H = units.HOUR
_MIN = units.MINUTE


@dataclass(frozen=True, slots=True, kw_only=True)
class Config:
    """Every parameter of the reproduction, paper setup as default (field units, named in the field).

    Chamber protocols, FOG build, logging and analysis rates, RBF settings, and the
    conditions of the paper's Table 1 / figure 2 point-heating simulation.

    Strain constants (``constraint_cte_inner_per_K`` 2.3e-5 /K, ``constraint_cte_outer_per_K``
    3e-6 /K, ``constraint_decay_length_mm`` 1 mm, ``constraint_cte_tempco_per_K`` 0.01 /K) and
    ``dn_dT_slope_per_K2`` (C2): these are NOT measured values and no source fixes them.
    PHYSICS.md 3.5 calls the strain model and C2 unverified defaults to be tuned. They
    differ from the ``CoilSpec`` defaults (1.2e-5 / 4e-6 /K, linear in radius), and the
    commit that set them (6a37791) records no reason. What they are based on: 2.3e-5 /K
    is the CTE of the aluminium spool alloy (PHYSICS.md 3.4, Li et al. COL 2015 Table 2),
    which acts on the inner layers. 3e-6 /K is a nearly free fibre in the outer potting
    (a few times the fibre's 5.5e-7 /K). A 1 mm decay length means the spool's grip
    fades within the inner ~7 of the 40 layers (pitch 0.14 mm). What they do
    (measured with ``thermal_response``, identification profile): an ideal
    quadrupolar coil then has almost no drift (peak 0.014 deg/h, against 0.14 deg/h
    with the CoilSpec defaults). So a drawn unit's drift is set by its 2 % winding
    defects, and the strain term dominates it: the peak is 0.25-0.8 deg/h over seeds 0-3,
    and ~20 % of it is the T x dT part coming from ``constraint_cte_tempco_per_K``. That
    is the paper's order (0.15 deg/h for a 10 degC change, seed-003 introduction). It
    also means the raw MSE, and with it every raw/compensated ratio, depends strongly
    on the seed. C2 is calibrated so that the Table-1 point-heating case gives a
    T x dT term above 0.2 deg/h (PHYSICS.md 3.5).

    RBF settings: ``rbf_spread`` / ``rbf_max_neurons`` = None (the default) means
    "choose by leave-one-segment-out cross-validation on identification run 1" (see
    :func:`select_rbf`) over ``rbf_spread_grid`` x ``rbf_neuron_grid``. A number fixes
    that setting, and CV then chooses only the other one (if it is None).
    """

    # chamber protocols
    start_degC: float = 20.0
    low_degC: float = -10.0
    high_degC: float = 40.0
    identification_rate_degC_per_min: float = 1.0
    identification_settle_h: float = 2.0
    identification_hold_h: float = 2.0
    validation_soak_h: float = 1.0
    validation1_runs: int = 5
    validation1_rate_degC_per_h: float = 10.0
    validation2_runs: int = 5
    validation2_rate_degC_per_min: float = 0.5
    validation2_true_rate_deg_h: float = 180.0
    # FOG build
    winding: str = "quadrupolar"
    layers: int = 40
    fibre_length_m: float = 1000.0
    winding_defect_rms: float = 0.02
    constraint_cte_inner_per_K: float = 2.3e-5
    constraint_cte_outer_per_K: float = 3.0e-6
    constraint_decay_length_mm: float = 1.0
    constraint_cte_tempco_per_K: float = 0.01
    dn_dT_slope_per_K2: float = 3.0e-8
    housing_time_constant_min: float = 20.0
    housing_lag_run_rms: float = 0.1
    arw_deg_sqrt_h: float = 0.0005
    bias_instability_deg_h: float = 0.002
    bias_deg_h: float = 0.02
    sensor_location: str = "outer"
    sensor_noise_K: float = 0.003
    sensor_resolution_K: float = 0.001
    thermal_step_s: float = 5.0
    # logging and analysis
    fs_hz: float = 1.0
    analysis_block_s: float = 100.0
    derivative_window_s: float = 900.0
    # RBF (newrb) settings; spread in min-max normalized input units; None = select by CV
    rbf_spread: float | None = None
    rbf_goal_deg_h2: float = 0.0
    rbf_max_neurons: int | None = None
    rbf_spread_grid: tuple[float, ...] = (0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0)
    rbf_neuron_grid: tuple[int, ...] = (3, 5, 10, 20, 40)
    rbf_cv_tolerance: float = 0.10
    # seed dependence: the whole pipeline for seeds seed .. seed + n - 1 (0 or 1: this seed only)
    seed_summary_count: int = 8
    # Table 1 / figure 2: a heated stretch of fibre at 0.25 L0
    point_z_fraction: float = 0.25
    point_length_m: float = 10.0
    point_rate_degC_per_min: float = 1.0

    def __post_init__(self) -> None:
        if not self.low_degC < self.high_degC:
            raise ValueError(
                f"Config.low_degC must be < high_degC; got {self.low_degC!r} and {self.high_degC!r}"
            )
        for name in ("validation1_runs", "validation2_runs"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int) or v < 1:
                raise ValueError(f"Config.{name} must be an integer >= 1; got {v!r}")
        v = self.seed_summary_count
        if isinstance(v, bool) or not isinstance(v, int) or v < 0:
            raise ValueError(f"Config.seed_summary_count must be an integer >= 0; got {v!r}")
        for name in (
            "identification_rate_degC_per_min",
            "validation1_rate_degC_per_h",
            "validation2_rate_degC_per_min",
            "identification_settle_h",
            "identification_hold_h",
            "validation_soak_h",
            "fs_hz",
            "analysis_block_s",
            "derivative_window_s",
            "point_length_m",
            "point_rate_degC_per_min",
        ):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ValueError(f"Config.{name} must be > 0; got {v!r}")
        if not (math.isfinite(self.housing_lag_run_rms) and 0 <= self.housing_lag_run_rms <= 0.5):
            raise ValueError(
                f"Config.housing_lag_run_rms must be in [0, 0.5] (relative); got {self.housing_lag_run_rms!r}"
            )
        spreads = self.rbf_spread_grid if self.rbf_spread is None else (self.rbf_spread,)
        if not spreads or not all(
            isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and v > 0
            for v in spreads
        ):
            raise ValueError(
                f"Config.rbf_spread / rbf_spread_grid must be > 0 (normalized input units); got {spreads!r}"
            )
        neurons = self.rbf_neuron_grid if self.rbf_max_neurons is None else (self.rbf_max_neurons,)
        if not neurons or not all(
            isinstance(v, int) and not isinstance(v, bool) and v >= 1 for v in neurons
        ):
            raise ValueError(
                f"Config.rbf_max_neurons / rbf_neuron_grid must be integers >= 1; got {neurons!r}"
            )
        if not (math.isfinite(self.rbf_cv_tolerance) and self.rbf_cv_tolerance >= 0):
            raise ValueError(
                f"Config.rbf_cv_tolerance must be >= 0 (relative); got {self.rbf_cv_tolerance!r}"
            )
        if not 0 <= self.point_z_fraction <= 1:
            raise ValueError(
                f"Config.point_z_fraction must be in [0, 1] (of L0); got {self.point_z_fraction!r}"
            )
        if self.analysis_block_s * self.fs_hz < 1:
            raise ValueError(
                f"Config.analysis_block_s must span at least one sample at fs_hz = {self.fs_hz}; got {self.analysis_block_s!r} s"
            )
        self.fog_spec()  # the sim layer validates the build (layers, winding, ...)

    # ----------------------------------------------------------------- builders
    def coil_spec(self, *, winding: str | None = None, defects: bool = True) -> CoilSpec:
        return CoilSpec(
            length=self.fibre_length_m,
            layers=self.layers,
            winding=self.winding if winding is None else winding,
            winding_defect_rms=self.winding_defect_rms if defects else 0.0,
            constraint_cte_inner=self.constraint_cte_inner_per_K,
            constraint_cte_outer=self.constraint_cte_outer_per_K,
            constraint_decay_length=self.constraint_decay_length_mm * 1e-3,
            constraint_cte_tempco=self.constraint_cte_tempco_per_K,
            dn_dT_slope=self.dn_dT_slope_per_K2,
        )

    def fog_spec(self, *, winding: str | None = None, defects: bool = True) -> FOGSpec:
        return FOGSpec(
            thermal=CoilThermalModel(
                coil=self.coil_spec(winding=winding, defects=defects),
                housing_time_constant=self.housing_time_constant_min * _MIN,
            ),
            noise=NoiseModel.from_datasheet(
                angle_random_walk=self.arw_deg_sqrt_h,
                bias_instability=self.bias_instability_deg_h,
                bias=self.bias_deg_h,
            ),
            sensor=TemperatureSensorSpec(
                location=self.sensor_location,
                noise=self.sensor_noise_K,
                resolution=self.sensor_resolution_K,
            ),
            thermal_step=self.thermal_step_s,
        )

    def identification_profile(self) -> PiecewiseLinear:
        r = self.identification_rate_degC_per_min / _MIN
        C = units.celsius
        return thermal_profile(
            C(self.start_degC),
            [
                Ramp(target=C(self.low_degC), rate=r),
                Soak(duration=self.identification_settle_h * _H),
                Ramp(target=C(self.high_degC), rate=r),
                Soak(duration=self.identification_hold_h * _H),
                Ramp(target=C(self.low_degC), rate=r),
                Soak(duration=self.identification_hold_h * _H),
            ],
        )

    def validation_profile(self, rate_K_per_s: float) -> PiecewiseLinear:
        C = units.celsius
        soak = Soak(duration=self.validation_soak_h * _H)
        return thermal_profile(
            C(self.low_degC), [soak, Ramp(target=C(self.high_degC), rate=rate_K_per_s), soak]
        )


def _runs(config: Config):
    """(name, chamber profile, true rate [rad/s]) of every run, in order."""
    ident = config.identification_profile()
    v1 = config.validation_profile(config.validation1_rate_degC_per_h / _H)
    v2 = config.validation_profile(config.validation2_rate_degC_per_min / _MIN)
    a = units.deg_per_h(config.validation2_true_rate_deg_h)
    out = [("ident_1", ident, 0.0), ("ident_2", ident, 0.0)]
    out += [(f"val1_run{i + 1}", v1, 0.0) for i in range(config.validation1_runs)]
    out += [(f"val2_run{i + 1}", v2, a) for i in range(config.validation2_runs)]
    return out


def _unit(config: Config, rng: np.random.Generator) -> FOGUnit:
    return config.fog_spec().realize(rng=rng)


def simulate(config: Config, seed: int) -> list[Recording]:
    """All runs of the experiment with one FOG unit: 2 identification, validation 1 and 2 runs."""
    root = np.random.default_rng(seed)
    rng_unit, rng_runs = root.spawn(2)
    unit = _unit(config, rng_unit)
    runs = _runs(config)
    recs = []
    for (name, prof, rate), rng in zip(runs, rng_runs.spawn(len(runs)), strict=True):
        rng_setup, rng_fog = rng.spawn(2)
        # run-to-run mounting/airflow: the housing lag differs a little between chamber runs
        factor = max(0.5, 1.0 + config.housing_lag_run_rms * rng_setup.standard_normal())
        thermal = replace(
            unit.spec.thermal,
            housing_time_constant=unit.spec.thermal.housing_time_constant * factor,
        )
        run_unit = FOGUnit(spec=replace(unit.spec, thermal=thermal), winding=unit.winding)
        recs.append(
            run_unit.simulate(
                prof,
                fs=config.fs_hz,
                rng=rng_fog,
                true_rate=rate,
                name=name,
                metadata={
                    "scenario": NAME,
                    "seed": seed,
                    "run": name,
                    "housing_time_constant_s": thermal.housing_time_constant,
                },
            )
        )
    return recs


# ======================================================================================
# analysis
# ======================================================================================


@dataclass(frozen=True, slots=True)
class _Run:
    name: str
    t_h: np.ndarray  # block-centre times [h]
    T: np.ndarray  # logged coil temperature [degC]
    output: np.ndarray  # [deg/h]
    truth: np.ndarray  # true rate [deg/h]
    drift: np.ndarray  # true thermal drift (coil) [deg/h]
    fs: float  # analysis rate [Hz]


def _prepare(rec: Recording, config: Config) -> _Run:
    """Block means of what the test logs (and of the truth) at the analysis rate."""
    b = config.analysis_block_s

    def bm(x):
        return block_means(x, rec.fs, block_s=b)

    n = len(bm(rec["rate"]))
    t = rec.t0 + (np.arange(n) + 0.5) * b
    return _Run(
        name=rec.name,
        t_h=(t - rec.t0) / _H,
        T=units.to_celsius(bm(rec["coil_temperature"])),
        output=units.to_deg_per_h(bm(rec["rate"])),
        truth=units.to_deg_per_h(bm(rec["truth/rate"])),
        drift=units.to_deg_per_h(bm(rec["truth/thermal_drift"])),
        fs=1.0 / b,
    )


def _features(run: _Run, config: Config, *, product: bool = True) -> np.ndarray:
    return thermal_features(run.T, run.fs, window_s=config.derivative_window_s, product=product)


def score_mse(compensated: np.ndarray, run: HeldOutRun) -> dict[str, float]:
    """MSE [(deg/h)^2] and RMS [deg/h] of compensated output against the true rate (paper: ERR = MSE(d - a))."""
    err = np.asarray(compensated, dtype=float) - run.truth
    m = float(np.mean(err**2))
    return {"mse": m, "rms": math.sqrt(m)}


def compensation_task(config: Config, seed: int) -> CompensationTask:
    """Training = identification run 1; held out = identification run 2 and every validation run."""
    runs = [_prepare(r, config) for r in simulate(config, seed)]
    train = runs[0]
    held = tuple(
        HeldOutRun(label=r.name, X=_features(r, config), output=r.output, truth=r.truth)
        for r in runs[1:]
    )
    return CompensationTask(
        scenario=NAME,
        feature_names=FEATURES_IMPROVED,
        X_train=_features(train, config),
        y_train=train.output - train.truth,
        heldout=held,
        target="error",
        unit="deg/h",
        scorer=score_mse,
    )


def _rbf(config: Config, spread: float, max_neurons: int) -> RBFNetwork:
    return RBFNetwork(
        spread=spread,
        goal=config.rbf_goal_deg_h2,
        max_neurons=max_neurons,
        normalize="minmax",
    )


IDENTIFICATION_SEGMENTS = ("settle", "heat + hold", "cool + hold")


def identification_segments(config: Config, t_h: np.ndarray) -> np.ndarray:
    """Segment index (0 settle, 1 heat + hold, 2 cool + hold) of each time ``t_h`` [h] of an identification run.

    The boundaries are knots of the chamber program (``Config.identification_profile``),
    known before any data are seen: the end of the -10 degC settle and the end of the
    40 degC hold.
    """
    knots_h = np.asarray(config.identification_profile().times, dtype=float) / _H
    knots_h = knots_h - knots_h[0]
    return np.digitize(np.asarray(t_h, dtype=float), [knots_h[2], knots_h[4]])


@dataclass(frozen=True, slots=True)
class RBFSelection:
    """Result of :func:`select_rbf`: the chosen newrb settings and the CV table they came from."""

    spread: float
    max_neurons: int
    # (spread, max_neurons) -> mean held-out-segment MSE [(deg/h)^2]
    cv_mse: dict[tuple[float, int], float]
    best: tuple[float, int]  # grid cell with the lowest CV MSE

    @property
    def chosen(self) -> tuple[float, int]:
        return (self.spread, self.max_neurons)

    def as_dict(self) -> dict:
        return {
            "spread": self.spread,
            "max_neurons": self.max_neurons,
            "cv_mse_chosen": self.cv_mse[self.chosen],
            "best": {"spread": self.best[0], "max_neurons": self.best[1]},
            "cv_mse_best": self.cv_mse[self.best],
            "grid": [
                {"spread": k[0], "max_neurons": k[1], "cv_mse": v} for k, v in self.cv_mse.items()
            ],
        }


def select_rbf(
    X: np.ndarray,
    y: np.ndarray,
    segments: np.ndarray,
    *,
    spreads,
    neurons,
    goal: float = 0.0,
    tolerance: float = 0.10,
) -> RBFSelection:
    """Choose newrb spread and neuron count by leave-one-segment-out CV on the training run only.

    Rule: for every (spread, max_neurons) of the grid, fit on all segments but one and
    predict the held-out segment. The CV MSE is the mean of the held-out segment MSEs,
    so each thermal regime counts equally. Of the cells whose CV MSE is within
    ``tolerance`` (10 %) of the best, take the one with the fewest neurons. Ties go
    to the largest spread, i.e. the smoothest surface.

    Why this rule: the segments of the identification run (settle, heat + hold,
    cool + hold) are contiguous blocks. Random K-fold on 100-s blocks of a slow
    thermal record would leak neighbouring, strongly correlated samples into the test
    fold and favour interpolating networks. Holding out a whole segment asks what the
    scenario needs: does the model carry over to a thermal history it has not seen?
    The 10 % band is a "one-standard-error"-style parsimony rule (Breiman et al. 1984;
    Hastie, Tibshirani, Friedman, ESL 7.10). With only three folds the CV minimum is
    noisy, so among nearly equal models the simplest is preferred. Fewer neurons and a
    wider spread both mean a smoother surface. The traditional and the improved model are
    each chosen by this same rule on their own inputs. No validation run takes part.

    Parameters
    ----------
    X : ndarray, shape (n, k)
        Features of the training run.
    y : ndarray, shape (n,)
        Drift target [deg/h].
    segments : ndarray of int, shape (n,)
        Fold label of every sample (:func:`identification_segments`).
    spreads, neurons : sequence
        Grid of spread [normalized input units] and max_neurons.
    goal : float
        newrb goal [(deg/h)^2].
    tolerance : float
        Relative CV-MSE band [-].

    Raises
    ------
    ValueError
        If ``segments`` has fewer than two distinct labels.
    """
    labels = np.unique(segments)
    if len(labels) < 2:
        raise ValueError(
            "select_rbf: segments must hold at least 2 distinct labels (one cross-validation "
            f"fold each); got labels {labels.tolist()}"
        )
    cv: dict[tuple[float, int], float] = {}
    for spread in spreads:
        for mn in neurons:
            errs = []
            for f in labels:
                held = segments == f
                net = RBFNetwork(spread=spread, goal=goal, max_neurons=mn, normalize="minmax")
                net.fit(X[~held], y[~held])
                errs.append(float(np.mean((net.predict(X[held]) - y[held]) ** 2)))
            cv[(float(spread), int(mn))] = float(np.mean(errs))
    best = min(cv, key=cv.__getitem__)
    band = [k for k, v in cv.items() if v <= (1.0 + tolerance) * cv[best]]
    chosen = min(band, key=lambda k: (k[1], -k[0]))
    return RBFSelection(spread=chosen[0], max_neurons=chosen[1], cv_mse=cv, best=best)


def _select(config: Config, X: np.ndarray, y: np.ndarray, segments: np.ndarray) -> RBFSelection:
    """:func:`select_rbf` over the Config grid (a fixed ``rbf_spread`` / ``rbf_max_neurons`` pins that axis)."""
    spreads = config.rbf_spread_grid if config.rbf_spread is None else (config.rbf_spread,)
    neurons = (
        config.rbf_neuron_grid if config.rbf_max_neurons is None else (config.rbf_max_neurons,)
    )
    return select_rbf(
        X,
        y,
        segments,
        spreads=spreads,
        neurons=neurons,
        goal=config.rbf_goal_deg_h2,
        tolerance=config.rbf_cv_tolerance,
    )


def deployment_float32(doc: dict, X: np.ndarray) -> np.ndarray:
    """Evaluate an exported network (``RBFNetwork.to_json`` document) entirely in float32.

    p = (x - x_offset) .* x_gain; a1 = radbas(||IW - p|| .* b1); a2 = LW a1 + b2, every
    array and every operation in IEEE single precision (the paper's TMS320F28335 DSP
    has a single-precision FPU). The inputs are rounded to float32 first.
    """
    f = np.float32
    x = np.asarray(X, dtype=f)
    p = (x - np.asarray(doc["x_offset"], dtype=f)) * np.asarray(doc["x_gain"], dtype=f)
    iw = np.asarray(doc["IW"], dtype=f).reshape(-1, x.shape[1])
    dist = np.sqrt(np.sum((p[:, None, :] - iw[None, :, :]) ** 2, axis=2, dtype=f), dtype=f)
    n = dist * np.asarray(doc["b1"], dtype=f)[None, :]
    a1 = np.exp(-(n * n), dtype=f)
    lw = np.asarray(doc["LW"], dtype=f).reshape(-1, iw.shape[0])
    a2 = a1 @ lw.T + np.asarray(doc["b2"], dtype=f)[None, :]
    return a2[:, 0]


def _mse(x, truth) -> float:
    return float(np.mean((np.asarray(x) - np.asarray(truth)) ** 2))


def point_heating(config: Config):
    """Paper Table 1 / figure 2: a stretch of free fibre at z = 0.25 L0 heated -10 -> 40 degC.

    The stretch (``point_length_m``) ramps at ``point_rate_degC_per_min``; the rest of the
    coil is static. Returns T [degC] and the Shupe components [deg/h]: constant-dn/dT
    term, the T x dT term from dn/dT(T), and their sum (no strain: a free fibre).
    """
    coil = config.coil_spec(defects=False)
    L = coil.length
    w = np.array([segment_weight(L, config.point_z_fraction * L, config.point_length_m)])
    T_c = np.linspace(config.low_degC, config.high_degC, 201)
    Tdot = np.full((len(T_c), 1), config.point_rate_degC_per_min / _MIN)
    terms = shupe_terms(coil, w, units.celsius(T_c)[:, None], Tdot, constraint_cte=np.zeros(1))
    d = units.to_deg_per_h
    return T_c, d(terms.shupe), d(terms.dndT_product), d(terms.shupe + terms.dndT_product)


def winding_comparison(config: Config) -> dict[str, dict[str, float]]:
    """Peak coil drift [deg/h] of the identification chamber run for each ideal winding (no defects, no noise)."""
    out = {}
    prof = config.identification_profile()
    for pattern in WINDING_PATTERNS:
        try:
            spec = config.fog_spec(winding=pattern, defects=False)
        except ValueError as exc:  # layer count not a multiple of the pattern's period
            out[pattern] = {"error": str(exc)}
            continue
        unit = FOGUnit(
            spec=spec, winding=Winding.ideal(pattern, spec.coil.layers, spec.coil.length)
        )
        _, _, _, terms = unit.thermal_response(prof)
        d = units.to_deg_per_h
        out[pattern] = {
            "peak_total": float(np.max(np.abs(d(terms.total)))),
            "peak_shupe": float(np.max(np.abs(d(terms.shupe + terms.dndT_product)))),
            "peak_strain": float(np.max(np.abs(d(terms.strain)))),
        }
    return out


def _comp(config: Config, model, r: _Run, product: bool) -> np.ndarray:
    return batch_compensate(
        model, r.output, r.T, r.fs, window_s=config.derivative_window_s, product=product
    )


def fit_models(config: Config, train: _Run):
    """(selection improved, selection traditional, improved net, traditional net) from one identification run.

    Each model's spread and neuron count come from :func:`select_rbf` on ``train`` alone;
    the networks are then refitted on the whole run with the chosen settings.
    """
    y = train.output - train.truth
    X_imp, X_trad = _features(train, config), _features(train, config, product=False)
    segments = identification_segments(config, train.t_h)
    sel_imp = _select(config, X_imp, y, segments)
    sel_trad = _select(config, X_trad, y, segments)
    improved = _rbf(config, *sel_imp.chosen).fit(X_imp, y)
    traditional = _rbf(config, *sel_trad.chosen).fit(X_trad, y)
    return sel_imp, sel_trad, improved, traditional


def _validation_scores(config: Config, improved, traditional, v1, v2):
    val1 = [
        {
            "mse_raw": _mse(r.output, r.truth),
            "mse_compensated": _mse(_comp(config, improved, r, True), r.truth),
        }
        for r in v1
    ]
    val2 = [
        {
            "mse_raw": _mse(r.output, r.truth),
            "mse_traditional": _mse(_comp(config, traditional, r, False), r.truth),
            "mse_improved": _mse(_comp(config, improved, r, True), r.truth),
        }
        for r in v2
    ]
    return val1, val2


@dataclass(frozen=True, slots=True)
class _Pipeline:
    """One seed through the whole pipeline: simulate, CV-select, fit, score the validation runs."""

    recs: list[Recording]
    runs: dict[str, _Run]
    sel_imp: RBFSelection
    sel_trad: RBFSelection
    improved: RBFNetwork
    traditional: RBFNetwork
    v1: list[_Run]
    v2: list[_Run]
    val1: list[dict]
    val2: list[dict]


def _pipeline(config: Config, seed: int) -> _Pipeline:
    """What :func:`run` reports for ``seed`` and :func:`seed_summary` repeats for the other seeds."""
    recs = simulate(config, seed)
    runs = {r.name: _prepare(r, config) for r in recs}
    sel_imp, sel_trad, improved, traditional = fit_models(config, runs["ident_1"])
    v1 = [runs[f"val1_run{i + 1}"] for i in range(config.validation1_runs)]
    v2 = [runs[f"val2_run{i + 1}"] for i in range(config.validation2_runs)]
    val1, val2 = _validation_scores(config, improved, traditional, v1, v2)
    return _Pipeline(recs, runs, sel_imp, sel_trad, improved, traditional, v1, v2, val1, val2)


def seed_summary(config: Config, seeds) -> list[dict]:
    """The whole pipeline (simulate, CV-select, fit, score) for each seed: how much the result depends on the unit drawn.

    Returns one dict per seed: ``seed``, the CV choices, ``validation1_ratio`` (mean raw /
    mean compensated MSE) and ``validation2_wins`` (runs with improved < traditional).
    """
    return [_summary_row(s, _pipeline(config, s)) for s in seeds]


def _summary_row(seed, p: _Pipeline) -> dict:
    return {
        "seed": int(seed),
        "improved": {"spread": p.sel_imp.spread, "max_neurons": p.sel_imp.max_neurons},
        "traditional": {"spread": p.sel_trad.spread, "max_neurons": p.sel_trad.max_neurons},
        "validation1_ratio": float(np.mean([d["mse_raw"] for d in p.val1]))
        / float(np.mean([d["mse_compensated"] for d in p.val1])),
        "validation2_wins": int(sum(d["mse_improved"] < d["mse_traditional"] for d in p.val2)),
    }


def run(config: Config, seed: int, *, progress: bool = False) -> Outcome:
    """Simulate every run, fit both RBF models on identification run 1, score, and draw the paper's figures."""
    t_start = time.perf_counter()
    p = _pipeline(config, seed)
    recs, runs, train = p.recs, p.runs, p.runs["ident_1"]
    sel_imp, sel_trad, improved, traditional = p.sel_imp, p.sel_trad, p.improved, p.traditional
    v1, v2, val1, val2 = p.v1, p.v2, p.val1, p.val2

    def comp(model, r: _Run, product: bool):
        return _comp(config, model, r, product)

    id2 = runs["ident_2"]
    ident2 = {
        "mse_raw": _mse(id2.output, id2.truth),
        "mse_traditional": _mse(comp(traditional, id2, False), id2.truth),
        "mse_improved": _mse(comp(improved, id2, True), id2.truth),
    }

    # deployment check: streaming compensation of validation-1 run 1 in 7-sample blocks equals batch
    r0 = v1[0]
    sc = StreamingCompensator(improved, r0.fs, window_s=config.derivative_window_s, product=True)
    pieces = [sc.push(r0.output[i : i + 7], r0.T[i : i + 7]) for i in range(0, len(r0.output), 7)]
    streamed = np.concatenate(pieces + [sc.flush()])
    batch = comp(improved, r0, True)
    stream_dev = float(np.max(np.abs(streamed - batch)))

    # deployment in single precision: the exported a1/a2 form evaluated in float32 (the DSP)
    # on every held-out run, against the float64 network; and the two conclusions in float32
    doc = json.loads(improved.to_json())
    doc_trad = json.loads(traditional.to_json())

    def comp32(d, r: _Run, product: bool):
        return r.output - deployment_float32(d, _features(r, config, product=product)).astype(float)

    held = [id2, *v1, *v2]
    c32 = {r.name: comp32(doc, r, True) for r in held}
    f32_dev, f32_rel = 0.0, []
    for r in held:
        c64 = comp(improved, r, True)
        f32_dev = max(f32_dev, float(np.max(np.abs(c32[r.name] - c64))))
        m64 = _mse(c64, r.truth)
        f32_rel.append(abs(_mse(c32[r.name], r.truth) - m64) / m64)
    mean_raw1 = float(np.mean([d["mse_raw"] for d in val1]))
    mean_comp1 = float(np.mean([d["mse_compensated"] for d in val1]))
    ratio1 = mean_raw1 / mean_comp1
    ratio1_f32 = mean_raw1 / float(np.mean([_mse(c32[r.name], r.truth) for r in v1]))
    wins_f32 = sum(
        _mse(c32[r.name], r.truth) < _mse(comp32(doc_trad, r, False), r.truth) for r in v2
    )
    float32 = {
        "max_abs_output_weight": float(np.max(np.abs(doc["LW"]))),
        "max_abs_compensation_difference_deg_h": f32_dev,
        "max_relative_mse_change": float(max(f32_rel)),
        "validation_zero_rate_mean_ratio": ratio1_f32,
        "validation_rotated_wins": int(wins_f32),
    }

    sensitivity = _sensitivity(config, train, v1, v2, comp)
    summary = [_summary_row(seed, p)]
    summary += seed_summary(config, range(seed + 1, seed + config.seed_summary_count))
    n_ratio_ok = sum(d["validation1_ratio"] >= 10.0 for d in summary)
    n_wins_ok = sum(d["validation2_wins"] == len(v2) for d in summary)
    n_both_ok = sum(
        d["validation1_ratio"] >= 10.0 and d["validation2_wins"] == len(v2) for d in summary
    )
    # the CV choice scored like a sensitivity row: these are the reported models, no refit needed
    chosen_row = {
        "spread": sel_imp.spread,
        "max_neurons": sel_imp.max_neurons,
        "traditional_spread": sel_trad.spread,
        "traditional_max_neurons": sel_trad.max_neurons,
        "validation1_ratio": summary[0]["validation1_ratio"],
        "validation2_wins": summary[0]["validation2_wins"],
    }
    T_pt, sh_pt, prod_pt, tot_pt = point_heating(config)
    txdt_max = float(np.max(np.abs(prod_pt)))
    windings = winding_comparison(config)

    imp_lt_trad = [d["mse_improved"] < d["mse_traditional"] for d in val2]
    ranking = sorted(
        (k for k in windings if "peak_total" in windings[k]),
        key=lambda k: windings[k]["peak_total"],
    )

    results = {
        "txdt_max_deg_h": txdt_max,
        "validation_zero_rate": val1,
        "validation_rotated": val2,
        "windings": {k: v.get("peak_total") for k, v in windings.items()},
        "windings_detail": windings,
        "identification_2": ident2,
        "validation_zero_rate_mean_ratio": ratio1,
        "rbf_improved": {
            "spread": improved.spread,
            "n_neurons": improved.n_neurons_,
            "training_mse": float(improved.mse_history_[-1]),
        },
        "rbf_traditional": {
            "spread": traditional.spread,
            "n_neurons": traditional.n_neurons_,
            "training_mse": float(traditional.mse_history_[-1]),
        },
        "rbf_selection": {
            "rule": _SELECTION_RULE,
            "segments": list(IDENTIFICATION_SEGMENTS),
            "improved": sel_imp.as_dict(),
            "traditional": sel_trad.as_dict(),
        },
        "rbf_improved_deployment": doc,
        "rbf_deployment_float32": float32,
        "rbf_sensitivity": sensitivity,
        "rbf_sensitivity_note": "scored on validation data, NOT used for selection",
        "rbf_cv_choice_scored": chosen_row,
        "seed_summary": summary,
        "streaming_max_abs_deviation_deg_h": stream_dev,
        "rates": {
            "logged_hz": config.fs_hz,
            "analysis_block_s": config.analysis_block_s,
            "thermal_step_s": config.thermal_step_s,
            "derivative_window_s": config.derivative_window_s,
        },
        "winding_z0_m": recs[0].metadata["winding_z0_m"],
    }

    tables = [
        Table(
            "Table 1. Point-heating simulation conditions (paper) and the reproduced T x dT term",
            ["quantity", "paper", "reproduced"],
            [
                ["fibre CTE alpha_T [1/degC]", "5.5e-7", f"{config.coil_spec().fibre_cte:.3g}"],
                ["coil length L0 [m]", "1000", f"{config.fibre_length_m:g}"],
                ["wavelength [nm]", "1550", f"{config.coil_spec().wavelength * 1e9:g}"],
                [
                    "reference point",
                    "0.25 L0",
                    f"{config.point_z_fraction:g} L0, {config.point_length_m:g} m heated",
                ],
                [
                    "temperature sweep [degC]",
                    "-10 -> 40",
                    f"{config.low_degC:g} -> {config.high_degC:g} "
                    f"at {config.point_rate_degC_per_min:g} degC/min",
                ],
                ["d(dn/dT)/dT [1/K^2]", "(not printed)", f"{config.dn_dT_slope_per_K2:.3g}"],
                ["max T x dT term [deg/h]", "> 0.2", f"{txdt_max:.3f}"],
            ],
            note="The paper's Table 1 did not survive extraction beyond alpha_T, L0, lambda, 0.25 L0 and the sweep; "
            "the heated length, rate and C2 are ours (C2 calibrated, PHYSICS.md 3.5).",
        ),
        Table(
            "Identification run 2 (the paper's check of the identification; not used for training "
            "or selection): MSE [(deg/h)^2]",
            ["raw", "traditional (T, dT)", "improved (T, dT, T x dT)", "raw / improved"],
            [
                [
                    ident2["mse_raw"],
                    ident2["mse_traditional"],
                    ident2["mse_improved"],
                    ident2["mse_raw"] / ident2["mse_improved"],
                ]
            ],
            note="Same chamber program as the training run, a fresh noise stream and its own housing lag.",
        ),
        Table(
            "Table 2. Validation 1 (-10 -> 40 degC at 10 degC/h, true rate 0): MSE before/after [(deg/h)^2]",
            ["run", "MSE raw", "MSE compensated (T, dT, T x dT)", "ratio"],
            [
                [i + 1, d["mse_raw"], d["mse_compensated"], d["mse_raw"] / d["mse_compensated"]]
                for i, d in enumerate(val1)
            ]
            + [["mean", mean_raw1, mean_comp1, ratio1]],
            note="Paper: about one order of magnitude lower after compensation.",
        ),
        Table(
            "Table 3. Validation 2 (0.5 degC/min, true rate 180 deg/h): MSE [(deg/h)^2]",
            [
                "run",
                "raw",
                "traditional (T, dT)",
                "improved (T, dT, T x dT)",
                "improved < traditional",
            ],
            [
                [
                    i + 1,
                    d["mse_raw"],
                    d["mse_traditional"],
                    d["mse_improved"],
                    "yes" if ok else "no",
                ]
                for i, (d, ok) in enumerate(zip(val2, imp_lt_trad, strict=True))
            ],
            note="Paper: improved is lowest in every run, about an order of magnitude better than raw.",
        ),
        _cv_table(sel_imp, sel_trad, config),
        Table(
            "RBF settings scored on validation data, NOT used for selection: how the two "
            "conclusions depend on spread and neuron count (same runs)",
            [
                "spread [normalized]",
                "max neurons",
                "validation 1 raw/compensated",
                "validation 2 improved < traditional",
            ],
            [
                [
                    d["spread"],
                    d["max_neurons"],
                    d["validation1_ratio"],
                    f"{d['validation2_wins']}/{len(v2)}",
                ]
                for d in sensitivity
            ]
            + [
                [
                    f"CV choice: improved {chosen_row['spread']:g}, "
                    f"traditional {chosen_row['traditional_spread']:g}",
                    f"{chosen_row['max_neurons']} / {chosen_row['traditional_max_neurons']}",
                    chosen_row["validation1_ratio"],
                    f"{chosen_row['validation2_wins']}/{len(v2)}",
                ]
            ],
            note="Diagnostic only: every row is scored on the validation runs, so picking a row from this "
            "table would be selection on test data. The models in Tables 2 and 3 use the last row, which "
            "leave-one-segment-out CV on identification run 1 chose (table above). In the grid rows both "
            "models share the settings. Small spreads (near-interpolating Gaussians) follow the training "
            "trajectory and generalize poorly to other ramp rates. The paper does not print its spread.",
        ),
        Table(
            "Deployment form in single precision (DSP): exported a1/a2 network of the improved model "
            "evaluated in float32 vs float64, all held-out runs",
            ["quantity", "value"],
            [
                ["largest output weight, abs(LW)", float32["max_abs_output_weight"]],
                [
                    "largest abs(compensated output float32 - float64) [deg/h]",
                    float32["max_abs_compensation_difference_deg_h"],
                ],
                ["largest relative change of a run's MSE", float32["max_relative_mse_change"]],
                [
                    "validation 1 raw/compensated, float32 (float64 in Table 2)",
                    float32["validation_zero_rate_mean_ratio"],
                ],
                [
                    "validation 2 improved < traditional, both float32",
                    f"{float32['validation_rotated_wins']}/{len(v2)}",
                ],
            ],
            note=_float32_note(float32),
        ),
        Table(
            f"Seed dependence: the whole pipeline (simulate, CV selection, fit, score) for "
            f"{len(summary)} drawn units",
            [
                "seed",
                "improved spread / neurons",
                "traditional spread / neurons",
                "validation 1 raw/compensated",
                "validation 2 improved < traditional",
            ],
            [
                [
                    d["seed"],
                    f"{d['improved']['spread']:g} / {d['improved']['max_neurons']}",
                    f"{d['traditional']['spread']:g} / {d['traditional']['max_neurons']}",
                    d["validation1_ratio"],
                    f"{d['validation2_wins']}/{len(v2)}",
                ]
                for d in summary
            ],
            note=f"Validation 1 >= 10x in {n_ratio_ok}/{len(summary)} seeds; improved < traditional in every "
            f"validation-2 run in {n_wins_ok}/{len(summary)}; both in {n_both_ok}/{len(summary)}. Each seed "
            "is a different unit (winding defects) and different noise. The headlines are for seed "
            f"{seed} only.",
        ),
        Table(
            "Winding patterns: peak coil drift of the identification chamber run (ideal windings, no noise) [deg/h]",
            ["winding", "peak total", "peak Shupe (dn/dT)", "peak strain"],
            [
                [
                    k,
                    v.get("peak_total", "n/a"),
                    v.get("peak_shupe", "n/a"),
                    v.get("peak_strain", v.get("error", "")),
                ]
                for k, v in windings.items()
            ],
            note="Not in the paper. Same chamber program and coil; only the layer order changes.",
        ),
    ]

    figures = _figures(
        config, T_pt, sh_pt, prod_pt, tot_pt, runs, improved, traditional, comp, v1, v2
    )
    headlines = [
        Headline(
            "max T x dT term, point at 0.25 L0 [deg/h]", f"{txdt_max:.3f}", "> 0.2", txdt_max > 0.2
        ),
        Headline(
            "validation 1: mean MSE raw / compensated",
            f"{ratio1:.1f}x",
            "~10x (>= 10x)",
            ratio1 >= 10.0,
            f"seed {seed}; the ratio is set by the drawn unit's drift over the noise floor and varies "
            f"strongly with the seed: >= 10x in {n_ratio_ok}/{len(summary)} seeds (seed-dependence table)",
        ),
        Headline(
            "validation 2: improved < traditional",
            f"{sum(imp_lt_trad)}/{len(imp_lt_trad)} runs",
            "every run",
            all(imp_lt_trad),
            f"seed {seed}; RBF settings chosen by CV on identification run 1 (improved spread "
            f"{sel_imp.spread:g} / {sel_imp.max_neurons} neurons, traditional {sel_trad.spread:g} / "
            f"{sel_trad.max_neurons}); every run in {n_wins_ok}/{len(summary)} seeds",
        ),
        Headline(
            "winding ranking (lowest peak drift first)",
            " < ".join(ranking),
            "no paper value; PHYSICS.md 3.2 (linear radial profile): octupolar < quadrupolar < dipolar < helical",
            None,
            "the spool's strain profile is not linear in radius, so the ranking is the physics' verdict",
        ),
    ]
    conclusion = (
        f"The coil physics gives a T x dT term of {txdt_max:.3f} deg/h for the paper's point-heating case. "
        f"The improved RBF lowers the validation-1 mean MSE {ratio1:.1f}x; it beats the traditional (T, dT) "
        f"network in {sum(imp_lt_trad)} of {len(imp_lt_trad)} validation-2 runs (seed {seed}; spread and "
        f"neuron count of each network chosen by leave-one-segment-out CV on identification run 1). "
        f"Over {len(summary)} seeds the validation-1 target (>= 10x) holds in {n_ratio_ok} and "
        f"'improved < traditional in every validation-2 run' in {n_wins_ok}: the paper's conclusions "
        "hold for some drawn units, not for all."
    )
    return Outcome(
        scenario=NAME,
        title=TITLE,
        seed=seed,
        config=config,
        results=results,
        tables=tables,
        figures=figures,
        headlines=headlines,
        conclusion=conclusion,
        runtime_s=time.perf_counter() - t_start,
    )


_SELECTION_RULE = (
    "leave-one-segment-out CV on identification run 1 (segments: settle, heat + hold, cool + hold); "
    "CV MSE = mean of held-out segment MSEs; among grid cells within rbf_cv_tolerance of the best CV MSE "
    "take the fewest neurons, ties to the largest spread; each model (traditional, improved) by this same rule"
)

# Our acceptance criterion for the float32 deployment form (the paper states none): no held-out
# run's MSE may change by more than 1 %. A strict choice: the compensated MSE of the five
# validation-1 runs differs between runs by tens of %, so 1 % is a change no table would show.
_FLOAT32_MSE_TOLERANCE = 0.01


def _float32_note(f32: dict) -> str:
    ok = f32["max_relative_mse_change"] <= _FLOAT32_MSE_TOLERANCE
    verdict = (
        "ACCEPTABLE by this criterion."
        if ok
        else "NOT ACCEPTABLE by this criterion. The cancelling output weights lose digits in single "
        "precision (a relative rounding of ~6e-8 in a1, times weights of this size), and what is lost "
        "is not small next to the compensated residual. A single-precision DSP should then evaluate "
        "the output layer in double precision, or export a better-conditioned network (fewer or "
        "narrower neurons, or output weights on an orthogonalised basis)."
    )
    return (
        "The paper's TMS320F28335 has a single-precision FPU. Here the inputs, weights and every "
        "operation are rounded to float32. Wide Gaussians are nearly collinear, so the output "
        "weights are large, of opposite signs, and cancel. Criterion (our choice; the paper states "
        "none): the float32 network must not change any held-out run's MSE by more than "
        f"{_FLOAT32_MSE_TOLERANCE:.0%}. {verdict} The last two rows "
        "show whether the paper's two conclusions still hold in float32."
    )


def _cv_table(sel_imp: RBFSelection, sel_trad: RBFSelection, config: Config) -> Table:
    neurons = sorted({k[1] for k in sel_imp.cv_mse})
    spreads = sorted({k[0] for k in sel_imp.cv_mse})
    rows = []
    for model, sel in (("improved", sel_imp), ("traditional", sel_trad)):
        for sp in spreads:
            cells = []
            for mn in neurons:
                v = sel.cv_mse[(sp, mn)]
                mark = "*" if (sp, mn) == sel.chosen else ("(best)" if (sp, mn) == sel.best else "")
                cells.append(f"{v:.4g}{mark}")
            rows.append([model, sp, *cells])
    return Table(
        "RBF selection by leave-one-segment-out cross-validation on identification run 1: "
        "CV MSE [(deg/h)^2] by spread (rows) and max neurons (columns)",
        ["model", "spread [normalized]", *[f"{mn} neurons" for mn in neurons]],
        rows,
        note=f"* = chosen: improved spread {sel_imp.spread:g} with {sel_imp.max_neurons} neurons, "
        f"traditional spread {sel_trad.spread:g} with {sel_trad.max_neurons} neurons. "
        f"Rule: the fewest neurons within {config.rbf_cv_tolerance:.0%} of the best CV MSE, ties to "
        "the largest spread; folds are the settle, heat + hold and cool + hold segments. Only the "
        "training run takes part. (best) marks the unpenalised CV minimum when it differs.",
    )


def _sensitivity(config: Config, train: _Run, v1, v2, comp) -> list[dict]:
    """Validation-1 ratio and validation-2 wins over a small grid of newrb spread / neuron counts.

    Both networks share the settings of a row. Scored on the validation runs: a diagnostic
    of how much the conclusions depend on the settings. It is NOT used to choose them
    (that is :func:`select_rbf`, on identification run 1 only).
    """
    y = train.output - train.truth
    X_imp, X_trad = _features(train, config), _features(train, config, product=False)
    raw1 = float(np.mean([_mse(r.output, r.truth) for r in v1]))
    out = []
    for spread in (1.0, 4.0, 16.0):
        for mn in (5, 10, 20):
            imp = _rbf(config, spread, mn).fit(X_imp, y)
            trad = _rbf(config, spread, mn).fit(X_trad, y)
            ratio = raw1 / float(np.mean([_mse(comp(imp, r, True), r.truth) for r in v1]))
            wins = sum(
                _mse(comp(imp, r, True), r.truth) < _mse(comp(trad, r, False), r.truth) for r in v2
            )
            out.append(
                {
                    "spread": spread,
                    "max_neurons": mn,
                    "validation1_ratio": ratio,
                    "validation2_wins": int(wins),
                }
            )
    return out


def _figures(config, T_pt, sh_pt, prod_pt, tot_pt, runs, improved, traditional, comp, v1, v2):
    figs = []
    f = Figure(figsize=(7, 4))
    ax = f.add_subplot()
    ax.plot(T_pt, prod_pt, label="T x dT term (dn/dT(T))")
    ax.plot(T_pt, sh_pt, label="constant dn/dT term")
    ax.plot(T_pt, tot_pt, "--", label="total")
    ax.axhline(0.2, color="grey", lw=0.8, ls=":")
    ax.set_xlabel("temperature of the heated stretch [degC]")
    ax.set_ylabel("rate error [deg/h]")
    ax.set_title(
        f"Shupe error of {config.point_length_m:g} m at {config.point_z_fraction:g} L0, "
        f"{config.point_rate_degC_per_min:g} degC/min"
    )
    ax.legend()
    f.tight_layout()
    figs.append(
        FigureSpec(
            "fig2_point_heating",
            "Figure 2: thermally induced non-reciprocity of a heated fibre "
            "stretch at 0.25 L0 (-10 -> 40 degC); the T x dT term alone.",
            f,
        )
    )

    r = runs["ident_2"]
    f = Figure(figsize=(8, 5))
    ax = f.add_subplot(211)
    ax.plot(r.t_h, r.output - r.truth, lw=0.6, color="0.6", label="measured drift (output - truth)")
    ax.plot(r.t_h, r.drift + config.bias_deg_h, lw=1.0, label="true coil drift + bias")
    ax.plot(
        r.t_h, improved.predict(_features(r, config)), lw=1.0, label="RBF estimate (T, dT, T x dT)"
    )
    ax.plot(
        r.t_h,
        traditional.predict(_features(r, config, product=False)),
        lw=1.0,
        ls="--",
        label="RBF estimate (T, dT)",
    )
    ax.set_ylabel("drift [deg/h]")
    ax.legend(fontsize=7)
    ax.set_title("Identification run 2 (not used for training)")
    ax2 = f.add_subplot(212, sharex=ax)
    ax2.plot(r.t_h, r.T)
    ax2.set_xlabel("time [h]")
    ax2.set_ylabel("logged coil T [degC]")
    f.tight_layout()
    figs.append(
        FigureSpec(
            "fig6_estimated_drift",
            "Figure 6: drift estimated by the RBF networks on the second "
            "identification run, beside the true drift.",
            f,
        )
    )

    f = Figure(figsize=(8, 4))
    ax = f.add_subplot()
    for i, rr in enumerate(v1):
        ax.plot(rr.t_h, rr.output, lw=0.5, color="C0", alpha=0.6, label="raw" if i == 0 else None)
        ax.plot(
            rr.t_h,
            comp(improved, rr, True),
            lw=0.5,
            color="C1",
            alpha=0.8,
            label="compensated" if i == 0 else None,
        )
    ax.set_xlabel("time [h]")
    ax.set_ylabel("output [deg/h] (true rate 0)")
    ax.set_title("Validation 1: five runs at 10 degC/h")
    ax.legend()
    f.tight_layout()
    figs.append(
        FigureSpec(
            "fig7_validation1",
            "Figure 7: validation 1, raw and compensated output of the five runs.",
            f,
        )
    )

    f = Figure(figsize=(8, 4))
    ax = f.add_subplot()
    rr = v2[0]
    ax.plot(rr.t_h, rr.output, lw=0.6, label="raw")
    ax.plot(rr.t_h, comp(traditional, rr, False), lw=0.6, label="traditional (T, dT)")
    ax.plot(rr.t_h, comp(improved, rr, True), lw=0.6, label="improved (T, dT, T x dT)")
    ax.axhline(config.validation2_true_rate_deg_h, color="k", lw=0.8, ls=":", label="true rate")
    ax.set_xlabel("time [h]")
    ax.set_ylabel("output [deg/h]")
    ax.set_title("Validation 2, run 1: 0.5 degC/min, 180 deg/h")
    ax.legend(fontsize=8)
    f.tight_layout()
    figs.append(
        FigureSpec(
            "fig8_validation2",
            "Figure 8: validation 2, raw, traditional and improved compensation.",
            f,
        )
    )
    return figs
