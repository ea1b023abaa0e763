"""Paper 003: IFOG temperature drift from coil physics; RBF compensation with a T x dT input.

Cheng, Qi, Zhao (Harbin Engineering University), "Design of a compensation system for
temperature drift errors of interferometric FOGs" (the paper's Chinese text).

What is simulated
-----------------
One FOG unit per seed (quadrupolar 40-layer x 80-turn coil, ~1 km, D = 0.1 m, potted on an
aluminium spool, with drawn winding imperfections, potting properties and sensor position)
in a thermal chamber. Its drift is NOT a formula in T and dT: the chamber drives the
housing, heat flows in (r, z) through spool, anisotropic fibre pack and potting, and the
rate error is the Shupe integral over the fibre turn by turn, with dn/dT, expansion and the
elasto-optic term of the composite-cylinder hoop strain; its T x dT part comes from the
published temperature dependences of silica dn/dT and of the materials' expansion
(``gyrobench.sim.coil2d``). That drift enters the closed-loop FOG shared by every FOG
scenario (``gyrobench.sim.fog_loop.ClosedLoopFOG``, built on the coil by
``gyrobench.sim.fog2d``) as a nonreciprocal phase beside the Sagnac phase; the output is the
loop's, its white noise the optical budget's, its scale factor follows the coil and source
temperatures (``Config``). The test logs what the paper logs: the gyro output and one coil
temperature sensor.

The paper's protocol (the default)
----------------------------------
Identification (Sec. 3, experiment steps 1-5), twice (modelling step 1: one run trains,
the other is the "validation sample"): the record starts at -10 degC (step 2: cool to
-10 degC and record once stable; the 20 -> -10 degC cool-down before it is not in the
record), heat to 40 degC and hold 2 h (step 3), cool to -10 degC and hold 2 h (step 4).

Step 5, "求取升降溫過程中的光纖環(huán)溫度和光纖陀螺儀輸出的平均值" ("obtain the mean values
of the coil temperature and of the gyro output over the heating and cooling process",
which "reduces accidental errors"), is read as the MEAN over the heating-and-cooling
record: it is the mean that modelling step 2 subtracts, Q = output - mean(output), the
networks' training target (the paper cannot know the truth). The alternative reading,
the heating and the cooling records averaged as curves against temperature
(``identification_average="temperature_curves"``), is implemented as a labelled
variant: it averages dT/dt of opposite signs to ~0 and cancels the part of the drift
that is odd in dT/dt, i.e. the Shupe drift the paper's T x dT model is about, so it
cannot be what the paper did (its measured effect is in ``DEVIATIONS``).

Validation 1 (5 runs): -10 degC until stable, heat at 10 degC/h to 40 degC, turntable
pointing north, reference a = 0 deg/h. Validation 2 (5 runs): -10 -> 40 degC at
0.5 degC/min, a = 180 deg/h (eq. 24). The paper records the heating (validation step 2);
the score window ends with the ramp (``score_final_soak`` adds the 1-h 40 degC soak).
Score: the paper's ERR = MSE(d - a) [(deg/h)^2] against the reference a. In this
simulation the reference equals the simulator's true rate (the sense axis points east, so
no Earth rate; a perfect turntable), so ERR is also the MSE against the truth.

Diagnostic (not the paper's protocol, clearly labelled in the report): the same
pipeline with the networks trained on output - truth (the simulator's true rate), which
the paper cannot do; it also removes the constant bias that Q = output - mean(output)
leaves in the compensated output.

Rates: the output and the sensor are logged at 1 Hz; the analysis works on 100-s block
means; features (T [degC], dT/dt [degC/s] by a 15-min Savitzky-Golay derivative, T x dT)
from the logged temperature only (the paper's eq. 13 for dT did not survive extraction).

Compensation
------------
RBF networks grown as MATLAB newrb (``gyrobench.analysis.compensation.rbf``; inputs
min-max scaled to [-1, 1], spread in those units): "improved" on (T, dT, T x dT),
"traditional" on (T, dT). The paper trains "until the network output meets the design
index" and prints neither the index nor the spread; here each network's spread and neuron
count are chosen by leave-one-segment-out cross-validation on the training run alone
(:func:`select_rbf`); no validation run influences the choice.

Also computed per unit: identification run 2 scored (the paper's "validation sample");
streaming compensation equal to batch; the exported a1/a2 network evaluated in single
precision as on the paper's TMS320F28335 (``deployment_float32``); the Table 1 /
figure 2 point-heating T x dT term; peak drift of the four winding patterns.

Shape (issue 13): :func:`experiment` simulates one unit (seed = unit) and computes its
results; :data:`CLAIMS` are judged over the units by the shared runner
(``gyrobench.scenarios.units``); :func:`report` formats tables and figures.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from gyrobench.analysis.compensation.rbf import (
    RADBAS_B,
    RBFNetwork,
    StreamingCompensator,
    batch_compensate,
)
from gyrobench.analysis.features import block_means, thermal_features
from gyrobench.scenarios.base import (
    CompensationTask,
    FigureSpec,
    HeldOutRun,
    Outcome,
    Table,
)
from gyrobench.scenarios.claims import (
    Claim,
    ClaimResult,
    Deviation,
    above,
    finite_median,
    in_range,
    is_true,
    within_factor,
)
from gyrobench.sim import units
from gyrobench.sim.coil import WINDING_PATTERNS
from gyrobench.sim.coil2d import Coil2D, Coil2DSpec, heated_stretch
from gyrobench.sim.environment import PiecewiseLinear, Ramp, Soak, thermal_profile
from gyrobench.sim.fog import TemperatureSensorSpec
from gyrobench.sim.fog2d import FOG2DSpec, FOG2DUnit
from gyrobench.sim.fog_optics import OpticalBudget
from gyrobench.sim.noise import NoiseModel
from gyrobench.sim.recording import Recording

NAME = "ifog_thermal"
TITLE = "IFOG thermal drift from Shupe coil physics; RBF compensation with a T x dT input"
PAPER = "003"

FEATURES_IMPROVED = ("T [degC]", "dT/dt [degC/s]", "T x dT/dt [degC^2/s]")
FEATURES_TRADITIONAL = FEATURES_IMPROVED[:2]

_H = units.HOUR
_MIN = units.MINUTE
_AVERAGES = ("record_mean", "temperature_curves")
_TARGETS = ("paper", "truth")


@dataclass(frozen=True, slots=True, kw_only=True)
class Config:
    """Every parameter of the reproduction, paper setup as default (field units in the name).

    Chamber protocols, FOG build, logging and analysis rates, RBF settings, and the
    conditions of the paper's Table 1 / figure 2 point-heating simulation.

    The coil (``gyrobench.sim.coil2d.Coil2DSpec`` defaults; issue 18): every material
    constant has a cited source or a stated value there; the T x dT term comes from the
    Leviton-Frey dn/dT(T) of silica and the expansion slopes of silica, epoxy and aluminium
    (nothing is set for it). One input is CALIBRATED to the paper: ``lead_difference_rms_m``
    (1.0 m), the spread of a unit's lead A - lead B length, which sets the median
    validation-1 peak drift of drawn units to ~0.15 deg/h (the paper's level for a 10 degC
    change). ``housing_time_constant_min`` sets the chamber-housing conductance
    (C_h / tau_h); ``fibre_length_m`` sets the turns per layer (round(L / (2 pi sum r_j))).

    The FOG (issue 17): the same closed-loop unit as paper 000
    (``gyrobench.sim.fog_loop.ClosedLoopFOG``, built on the drawn coil by
    ``gyrobench.sim.fog2d``), with this paper's parameter set: the loop on the coil's own
    L (~1012 m) and D (~0.099 m) at 1550 nm, loop gain 0.1 (f_3dB ~3.6 kHz), the default
    optical budget (10 mW Er ASE, 30 nm, 20 dB loss; ``sim.fog_optics``) at modulation
    depth ``modulation_depth_pi`` x pi = 3 pi/4 (excess-RIN limited, so a deeper bias
    lowers the noise: cot^2(phi_b/2)), giving ARW 4.0e-4 deg/sqrt(h) (navigation grade;
    a stated choice, not the paper's number: the paper prints none). The IEEE-952 terms the
    optics do not produce are added: bias instability ``bias_instability_deg_h`` and a
    constant ``bias_deg_h`` (assumed). Scale factor vs temperature of the loop,
    (1 + alpha_D dT_coil)^2 / (1 + alpha_lambda dT_housing) about 20 degC: the coil's mean
    pack temperature drives alpha_D, the housing temperature (the source's) drives
    alpha_lambda; ``diameter_tempco_ppm_per_K`` None = the coil's own hoop expansion from its
    composite-cylinder model (``sim.fog2d.coil_diameter_tempco``, ~22 ppm/K on the Al
    spool); ``wavelength_tempco_ppm_per_K`` 4 ppm/K (an unstabilised Er ASE source;
    assumed). The sense axis is horizontal at Harbin (45.8 degN), at azimuth
    ``sense_azimuth_deg`` from north: 90 (east, the default) senses no Earth rate, which is
    the paper's "output 0 deg/h"; 0 (north, the paper's words) senses 10.49 deg/h (see
    ``DEVIATIONS``).

    RBF settings: ``rbf_spread`` / ``rbf_max_neurons`` = None (the default) means
    "choose by leave-one-segment-out cross-validation on identification run 1" (see
    :func:`select_rbf`) over ``rbf_spread_grid`` x ``rbf_neuron_grid``. A number fixes
    that setting, and CV then chooses only the other one (if it is None).

    Protocol switches (module docstring): ``record_cooldown``, ``identification_average``
    (+ ``curve_bin_degC``) and ``score_final_soak``; the defaults are the paper's protocol.
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
    lead_difference_rms_m: float = 1.0
    housing_time_constant_min: float = 20.0
    housing_lag_run_rms: float = 0.1
    modulation_depth_pi: float = 0.75
    bias_instability_deg_h: float = 0.002
    bias_deg_h: float = 0.02
    diameter_tempco_ppm_per_K: float | None = None
    wavelength_tempco_ppm_per_K: float = 4.0
    sense_azimuth_deg: float = 90.0
    sensor_location: str = "outer"
    sensor_noise_K: float = 0.003
    sensor_resolution_K: float = 0.001
    thermal_step_s: float = 20.0
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
    # the paper's identification protocol (module docstring): the record starts at -10 degC
    # (True adds the 20 -> -10 degC cool-down); step 5's averaging ("record_mean": the mean
    # that Q = output - mean(output) subtracts; "temperature_curves": the heating and cooling
    # records averaged as curves against temperature, in bins of curve_bin_degC, a variant)
    record_cooldown: bool = False
    identification_average: str = "record_mean"
    curve_bin_degC: float = 2.5
    # validation runs are scored over the heating (the paper's record); True adds the 40 degC soak
    score_final_soak: bool = False
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
        if self.identification_average not in _AVERAGES:
            raise ValueError(
                f"Config.identification_average must be one of {_AVERAGES}; "
                f"got {self.identification_average!r}"
            )
        for name in ("record_cooldown", "score_final_soak"):
            if not isinstance(getattr(self, name), bool):
                raise TypeError(f"Config.{name} must be a bool; got {getattr(self, name)!r}")
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
            "curve_bin_degC",
        ):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ValueError(f"Config.{name} must be > 0; got {v!r}")
        if not (math.isfinite(self.housing_lag_run_rms) and 0 <= self.housing_lag_run_rms <= 0.5):
            raise ValueError(
                "Config.housing_lag_run_rms must be in [0, 0.5] (relative); "
                f"got {self.housing_lag_run_rms!r}"
            )
        spreads = self.rbf_spread_grid if self.rbf_spread is None else (self.rbf_spread,)
        if not spreads or not all(
            isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and v > 0
            for v in spreads
        ):
            raise ValueError(
                "Config.rbf_spread / rbf_spread_grid must be > 0 (normalized input units); "
                f"got {spreads!r}"
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
                f"Config.analysis_block_s must span at least one sample at fs_hz = {self.fs_hz}; "
                f"got {self.analysis_block_s!r} s"
            )
        v = self.modulation_depth_pi
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not 0 < v < 1:
            raise ValueError(f"Config.modulation_depth_pi must be in (0, 1) (x pi rad); got {v!r}")
        for name, bound in (
            ("diameter_tempco_ppm_per_K", 1000.0),
            ("wavelength_tempco_ppm_per_K", 1000.0),
            ("sense_azimuth_deg", 360.0),
        ):
            v = getattr(self, name)
            if v is None and name == "diameter_tempco_ppm_per_K":
                continue
            if (
                isinstance(v, bool)
                or not isinstance(v, (int, float))
                or not (math.isfinite(v) and abs(v) <= bound)
            ):
                raise ValueError(
                    f"Config.{name} must be finite with |value| <= {bound:g}; got {v!r}"
                )
        self.fog_spec()  # the sim layer validates the build (layers, winding, ...)

    # ----------------------------------------------------------------- builders
    def coil_spec(self, *, winding: str | None = None) -> Coil2DSpec:
        base = Coil2DSpec()
        radii = base.inner_radius + (np.arange(self.layers) + 0.5) * (
            (base.outer_radius - base.inner_radius) / self.layers
        )
        turns = max(2, round(self.fibre_length_m / (2 * math.pi * float(radii.sum()))))
        return replace(
            base,
            layers=self.layers,
            turns_per_layer=turns,
            winding=self.winding if winding is None else winding,
            lead_difference_rms=self.lead_difference_rms_m,
            chamber_conductance=base.housing_heat_capacity
            / (self.housing_time_constant_min * _MIN),
        )

    def fog_spec(self, *, winding: str | None = None) -> FOG2DSpec:
        dtc = self.diameter_tempco_ppm_per_K
        return FOG2DSpec(
            coil=self.coil_spec(winding=winding),
            noise=NoiseModel.from_datasheet(
                bias_instability=self.bias_instability_deg_h,
                bias=self.bias_deg_h,
            ),
            optics=OpticalBudget(),
            bias_phase=self.modulation_depth_pi * math.pi,
            diameter_tempco=None if dtc is None else dtc * 1e-6,
            wavelength_tempco=self.wavelength_tempco_ppm_per_K * 1e-6,
            azimuth=math.radians(self.sense_azimuth_deg),
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


def _unit(config: Config, rng: np.random.Generator) -> FOG2DUnit:
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
        recs.append(
            unit.simulate(
                prof,
                fs=config.fs_hz,
                rng=rng_fog,
                true_rate=rate,
                chamber_scale=1.0 / factor,
                name=name,
                metadata={
                    "scenario": NAME,
                    "seed": seed,
                    "run": name,
                    "housing_time_constant_s": config.housing_time_constant_min * _MIN * factor,
                },
            )
        )
    return recs


def memory_estimate(config: Config) -> float:
    """Peak memory of one unit's :func:`experiment` or :func:`simulate` [bytes], before allocating.

    Per unit (one worker process); the runner multiplies it by the units it runs at once
    (:func:`gyrobench.scenarios.units.check_unit_memory`). With ``N = sum_runs duration fs_hz``
    samples in all the unit's chamber runs (:func:`_runs`), ``m = max_runs duration /
    thermal_step_s`` thermal steps in the longest run and ``g`` thermal nodes of the coil
    grid (``(grid_spool + grid_pack_r + 1)(grid_pack_z + 2) + 1``, 121 by default)::

        bytes = 1.1 x (168 N + 80 g m + 10e6)

    168 B = 21 float64 series per sample: :func:`simulate` returns every run's recording (2
    channels; ~19 truth series: the closed loop's parts -- true, table and Earth rate,
    scale-factor error, nonreciprocal input, loop error, optical and IEEE-952 noise and its
    terms -- and the coil's Shupe and T x dT terms, noise sum and four temperatures) and
    :func:`experiment` holds them all while it block-averages them; 80 B = 10 float64
    (steps x nodes) arrays of the modal thermal solution of one run (~5 measured, doubled for
    the convergence check at dt / 2 when the chamber knots are off the step grid). 10 MB the
    rest; 1.1 the margin. MEASURED (peak RSS increase, one BLAS thread;
    tests/scenarios/test_memory_estimates.py; on the closed-loop FOG, issue 17): 55 MB at the
    default (N = 2.5e5, m = 1470), 419 MB at fs_hz = 10, 132 MB with validation1_runs = 20
    and identification_hold_h = 8 (N = 7.2e5, m = 3630), 117 MB at thermal_step_s = 2
    (m = 14700, on the grid: ~5 arrays), 84 MB at thermal_step_s = 7 (m = 4200, off the
    grid: ~9.3 arrays), simulate and experiment alike; the formula is 1.2-2.1 x these.
    Floats: never an overflow.
    """
    durations = [float(prof.duration) for _, prof, _ in _runs(config)]
    spec = config.coil_spec()
    nodes = (spec.grid_spool + spec.grid_pack_r + 1) * (spec.grid_pack_z + 2) + 1
    n = sum(durations) * float(config.fs_hz)
    m = max(durations) / float(config.thermal_step_s)
    return 1.1 * (168.0 * n + 80.0 * nodes * m + 10e6)


# ======================================================================================
# analysis: one unit through the paper's pipeline
# ======================================================================================


@dataclass(frozen=True, slots=True)
class _Run:
    name: str
    t_h: np.ndarray  # block-centre times from the start of the run [h]
    T: np.ndarray  # logged coil temperature [degC]
    output: np.ndarray  # [deg/h]
    truth: np.ndarray  # simulator's true rate [deg/h] (diagnostics only)
    drift: np.ndarray  # simulator's true coil thermal drift [deg/h] (figures only)
    fs: float  # analysis rate [Hz]
    reference: float  # the turntable reference a [deg/h] the paper scores against
    scored: np.ndarray | None = None  # samples the paper records / scores (record_mask)


def _reference_deg_h(config: Config, name: str) -> float:
    """The paper's reference a [deg/h]: 0 (turntable pointing north), validation 2: eq. (24)."""
    return float(config.validation2_true_rate_deg_h) if name.startswith("val2") else 0.0


def _prepare(rec: Recording, config: Config) -> _Run:
    """Block means of what the test logs (and of the truth) at the analysis rate."""
    b = config.analysis_block_s

    def bm(x):
        return block_means(x, rec.fs, block_s=b)

    n = len(bm(rec["rate"]))
    run = _Run(
        name=rec.name,
        t_h=(np.arange(n) + 0.5) * b / _H,
        T=units.to_celsius(bm(rec["coil_temperature"])),
        output=units.to_deg_per_h(bm(rec["rate"])),
        truth=units.to_deg_per_h(bm(rec["truth/rate"])),
        drift=units.to_deg_per_h(bm(rec["truth/thermal_drift"])),
        fs=1.0 / b,
        reference=_reference_deg_h(config, rec.name),
    )
    return replace(run, scored=record_mask(config, run))


def _features(run: _Run, config: Config, *, product: bool = True) -> np.ndarray:
    return thermal_features(run.T, run.fs, window_s=config.derivative_window_s, product=product)


def score_mse(compensated: np.ndarray, run: HeldOutRun) -> dict[str, float]:
    """MSE [(deg/h)^2] and RMS [deg/h] of compensated output against the true rate (the bench)."""
    err = np.asarray(compensated, dtype=float) - run.truth
    m = float(np.mean(err**2))
    return {"mse": m, "rms": math.sqrt(m)}


def compensation_task(config: Config, seed: int) -> CompensationTask:
    """Training = identification run 1; held out = identification run 2 and every validation run.

    The bench's task (unchanged by issue 13): the whole runs, target output - truth.
    """
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
        spread=spread, goal=config.rbf_goal_deg_h2, max_neurons=max_neurons, normalize="minmax"
    )


IDENTIFICATION_SEGMENTS = ("settle", "heat + hold", "cool + hold")


def identification_segments(config: Config, t_h: np.ndarray) -> np.ndarray:
    """Segment (0 settle, 1 heat + hold, 2 cool + hold) of each time ``t_h`` [h] of an ident. run.

    The boundaries are knots of the chamber program (``Config.identification_profile``),
    known before any data are seen: the end of the -10 degC settle and the end of the
    40 degC hold.
    """
    knots_h = np.asarray(config.identification_profile().times, dtype=float) / _H
    knots_h = knots_h - knots_h[0]
    return np.digitize(np.asarray(t_h, dtype=float), [knots_h[2], knots_h[4]])


def record_mask(config: Config, run: _Run) -> np.ndarray:
    """Samples of ``run`` the paper records (identification) or scores (validation).

    Identification: from the chamber reaching -10 degC (experiment step 2), unless
    ``record_cooldown``. Validation: until the end of the heating ramp (validation step 2
    records the heating), unless ``score_final_soak``.
    """
    if run.name.startswith("ident"):
        knots = config.identification_profile().times
        start_h = (knots[1] - knots[0]) / _H
        return np.ones(len(run.t_h), bool) if config.record_cooldown else run.t_h >= start_h
    if config.score_final_soak:
        return np.ones(len(run.t_h), bool)
    rate = (
        config.validation1_rate_degC_per_h / _H
        if run.name.startswith("val1")
        else config.validation2_rate_degC_per_min / _MIN
    )
    knots = config.validation_profile(rate).times
    return run.t_h <= (knots[2] - knots[0]) / _H


def heat_cool_average(
    X: np.ndarray, y: np.ndarray, segments: np.ndarray, *, bin_degC: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The heating (segment 1) and cooling (segment 2) records averaged as curves against T.

    Rows are binned by temperature (``X[:, 0]``, bins of ``bin_degC`` from the lowest
    logged T); in every bin both records reach, each record's mean of every feature and of
    ``y`` is taken, and the two means are averaged. Returns (X, y, fold labels), one row
    per bin in rising T, folds = the lower, middle and upper third of the bins.
    """
    heat, cool = segments == 1, segments == 2
    lo = float(np.min(X[:, 0]))
    b = np.floor((X[:, 0] - lo) / bin_degC).astype(int)
    common = np.intersect1d(np.unique(b[heat]), np.unique(b[cool]))
    if len(common) < 3:
        raise ValueError(
            f"heat_cool_average: the heating and cooling records share {len(common)} "
            f"temperature bins of {bin_degC} degC; need >= 3"
        )
    Z = np.column_stack([X, y])
    rows = [
        0.5 * (Z[heat & (b == k)].mean(axis=0) + Z[cool & (b == k)].mean(axis=0)) for k in common
    ]
    A = np.asarray(rows)
    folds = np.concatenate([np.full(len(p), i) for i, p in enumerate(np.array_split(A[:, 0], 3))])
    return A[:, :-1], A[:, -1], folds


@dataclass(frozen=True, slots=True)
class TrainingSet:
    """What the networks are trained on: features (T, dT/dt, T x dT/dt), target, CV folds."""

    X: np.ndarray
    y: np.ndarray
    segments: np.ndarray
    mean_output_deg_h: float  # the mean subtracted to form Q (paper), 0 for the truth target
    mean_T_degC: float  # step 5's other mean (not a model input)


def training_set(config: Config, run: _Run, *, target: str = "paper") -> TrainingSet:
    """The training data of identification run ``run``.

    ``target="paper"``: Q = output - mean(output) over the record (modelling step 2; the
    paper cannot know the truth). ``target="truth"`` (diagnostic): output - the
    simulator's true rate. Features are computed on the whole run (the derivative needs
    the history), then cut to the record (:func:`record_mask`) and, for
    ``identification_average="temperature_curves"``, averaged (:func:`heat_cool_average`).
    """
    if target not in _TARGETS:
        raise ValueError(f"target must be one of {_TARGETS}; got {target!r}")
    keep = record_mask(config, run)
    X = _features(run, config)[keep]
    y = (run.output - run.truth if target == "truth" else run.output)[keep]
    seg = identification_segments(config, run.t_h)[keep]
    if config.identification_average == "temperature_curves":
        X, y, seg = heat_cool_average(X, y, seg, bin_degC=config.curve_bin_degC)
    mean = float(np.mean(y)) if target == "paper" else 0.0
    return TrainingSet(
        X=X, y=y - mean, segments=seg, mean_output_deg_h=mean, mean_T_degC=float(np.mean(X[:, 0]))
    )


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


def _prefix_predictions(net: RBFNetwork, X_fit, y_fit, X_new, counts) -> dict[int, np.ndarray]:
    """Predictions on ``X_new`` of the newrb networks made of the first k neurons of ``net``.

    newrb adds one neuron per iteration and the choice of the next neuron does not
    depend on ``max_neurons``, so the k-neuron network has the first k centres of a
    longer fit; its output layer [b2, LW] is the least-squares solution on those centres.
    """
    Z = (np.asarray(X_fit, float) - net.x_offset_) * net.x_gain_
    Zn = (np.asarray(X_new, float) - net.x_offset_) * net.x_gain_
    b = RADBAS_B / float(net.spread)
    out = {}
    for k in counts:
        c = net.centers_[: min(int(k), net.n_neurons_)]
        G = np.column_stack([np.ones(len(Z)), np.exp(-((_cdist(Z, c) * b) ** 2))])
        sol, *_ = np.linalg.lstsq(G, y_fit, rcond=None)
        out[int(k)] = sol[0] + np.exp(-((_cdist(Zn, c) * b) ** 2)) @ sol[1:]
    return out


def _cdist(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.sqrt(np.maximum(np.sum((a[:, None, :] - b[None, :, :]) ** 2, axis=2), 0.0))


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
    noisy, so among nearly equal models the simplest is preferred. The traditional and
    the improved model are each chosen by this same rule on their own inputs. No
    validation run takes part. One newrb fit per (spread, fold) with the largest neuron
    count gives every smaller count (:func:`_prefix_predictions`).

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
    counts = sorted({int(n) for n in neurons})
    errs: dict[tuple[float, int], list[float]] = {}
    for spread in spreads:
        for f in labels:
            held = segments == f
            net = RBFNetwork(spread=spread, goal=goal, max_neurons=counts[-1], normalize="minmax")
            net.fit(X[~held], y[~held])
            pred = _prefix_predictions(net, X[~held], y[~held], X[held], counts)
            for mn in counts:
                errs.setdefault((float(spread), mn), []).append(
                    float(np.mean((pred[mn] - y[held]) ** 2))
                )
    cv = {k: float(np.mean(v)) for k, v in errs.items()}
    best = min(cv, key=cv.__getitem__)
    band = [k for k, v in cv.items() if v <= (1.0 + tolerance) * cv[best]]
    chosen = min(band, key=lambda k: (k[1], -k[0]))
    return RBFSelection(spread=chosen[0], max_neurons=chosen[1], cv_mse=cv, best=best)


def _select(config: Config, X: np.ndarray, y: np.ndarray, segments: np.ndarray) -> RBFSelection:
    """:func:`select_rbf` over the Config grid (a fixed spread or neuron count pins that axis)."""
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


def err(d: np.ndarray, run: _Run) -> float:
    """The paper's ERR = MSE(d - a) [(deg/h)^2] over the scored samples (eq. 19, a = reference)."""
    m = np.ones(len(run.t_h), bool) if run.scored is None else run.scored
    return float(np.mean((np.asarray(d, float)[m] - run.reference) ** 2))


def point_heating(config: Config, *, bonded: bool = False):
    """Paper Table 1 / figure 2: a stretch of fibre at z = 0.25 L0 heated -10 -> 40 degC.

    The stretch (``point_length_m``) ramps at ``point_rate_degC_per_min``; the rest of the
    coil is static (:func:`gyrobench.sim.coil2d.heated_stretch`). Returns T [degC] and the
    components [deg/h]: beta_T at 0 degC, the T x dT term from the material temperature
    dependences (T in degC, as the paper's regressor), their sum. ``bonded=False``: a free
    fibre (dn/dT + n alpha_f, the paper's model); True: bonded in the pack at the radius
    of the layer that holds 0.25 L0 of an ideal winding.
    """
    spec = config.coil_spec()
    L = config.fibre_length_m
    T_c = np.linspace(config.low_degC, config.high_degC, 201)
    radius = None
    if bonded:
        fm = Coil2D(spec=spec).fibre()
        radius = float(fm.r[np.argmin(np.abs(fm.s / fm.length - config.point_z_fraction))])
    sh, prod = heated_stretch(
        spec,
        units.celsius(T_c),
        config.point_rate_degC_per_min / _MIN,
        fibre_length=L,
        diameter=0.1,
        z_center=config.point_z_fraction * L,
        seg_length=config.point_length_m,
        radius=radius,
    )
    d = units.to_deg_per_h
    return T_c, d(sh), d(prod), d(sh + prod)


def winding_comparison(config: Config) -> dict[str, dict[str, Any]]:
    """Peak coil drift [deg/h] of the identification run per ideal winding (no noise or defects)."""
    out: dict[str, dict[str, Any]] = {}
    prof = config.identification_profile()
    d = units.to_deg_per_h
    for pattern in WINDING_PATTERNS:
        try:
            spec = config.fog_spec(winding=pattern)
        except ValueError as exc:  # layer count not a multiple of the pattern's period
            out[pattern] = {"error": str(exc)}
            continue
        run = FOG2DUnit(spec=spec, coil=Coil2D(spec=spec.coil)).thermal_response(prof)
        out[pattern] = {
            "peak_total": float(np.max(np.abs(d(run.total)))),
            "peak_shupe": float(np.max(np.abs(d(run.shupe)))),
            "peak_product": float(np.max(np.abs(d(run.product)))),
        }
    return out


def _comp(config: Config, model, r: _Run, product: bool) -> np.ndarray:
    """Compensated output d = output - model(T, dT[, T x dT]) over the whole run [deg/h]."""
    return batch_compensate(
        model, r.output, r.T, r.fs, window_s=config.derivative_window_s, product=product
    )


def fit_models(config: Config, train: TrainingSet):
    """(selection improved, selection traditional, improved, traditional) from one training set.

    Each model's spread and neuron count come from :func:`select_rbf` on ``train`` alone;
    the networks are then refitted on the whole training set with the chosen settings.
    """
    X_imp, X_trad, y = train.X, train.X[:, :2], train.y
    sel_imp = _select(config, X_imp, y, train.segments)
    sel_trad = _select(config, X_trad, y, train.segments)
    improved = _rbf(config, *sel_imp.chosen).fit(X_imp, y)
    traditional = _rbf(config, *sel_trad.chosen).fit(X_trad, y)
    return sel_imp, sel_trad, improved, traditional


@dataclass(frozen=True, slots=True)
class _Fitted:
    """One protocol's result: training set, selections, networks, compensated outputs."""

    train: TrainingSet
    sel_imp: RBFSelection
    sel_trad: RBFSelection
    improved: RBFNetwork
    traditional: RBFNetwork
    comp_imp: dict[str, np.ndarray]  # run name -> d with the improved network
    comp_trad: dict[str, np.ndarray]


def _fit_protocol(config: Config, runs: Mapping[str, _Run], target: str) -> _Fitted:
    train = training_set(config, runs["ident_1"], target=target)
    sel_imp, sel_trad, improved, traditional = fit_models(config, train)
    held = [r for name, r in runs.items() if name != "ident_1"]
    return _Fitted(
        train,
        sel_imp,
        sel_trad,
        improved,
        traditional,
        {r.name: _comp(config, improved, r, True) for r in held},
        {r.name: _comp(config, traditional, r, False) for r in held},
    )


def _scores(runs: Mapping[str, _Run], comp_imp, comp_trad) -> dict[str, Any]:
    """ERR [(deg/h)^2] of every held-out run: raw, traditional, improved (eqs. 19, 22-24)."""

    def row(r: _Run) -> dict[str, float]:
        return {
            "raw": err(r.output, r),
            "traditional": err(comp_trad[r.name], r),
            "improved": err(comp_imp[r.name], r),
        }

    return {
        "ident_2": row(runs["ident_2"]),
        "val1": [row(r) for n, r in runs.items() if n.startswith("val1")],
        "val2": [row(r) for n, r in runs.items() if n.startswith("val2")],
    }


def claim_quantities(scores: Mapping[str, Any]) -> dict[str, float]:
    """The validation claims' quantities of one unit from its ERR scores (:func:`_scores`)."""
    v1, v2 = scores["val1"], scores["val2"]
    raw1 = float(np.mean([d["raw"] for d in v1]))
    raw2 = float(np.mean([d["raw"] for d in v2]))
    return {
        "val1_ratio": raw1 / float(np.mean([d["improved"] for d in v1])),
        "val1_every_run_lower": float(all(d["improved"] < d["raw"] for d in v1)),
        "val2_improved_lowest": float(
            all(d["improved"] < min(d["raw"], d["traditional"]) for d in v2)
        ),
        "val2_ratio": raw2 / float(np.mean([d["improved"] for d in v2])),
    }


def _float32_check(config: Config, runs: Mapping[str, _Run], fit: _Fitted) -> dict[str, Any]:
    """The exported networks in single precision (the DSP) against float64, every held-out run."""
    docs = {p: json.loads(m.to_json()) for p, m in ((True, fit.improved), (False, fit.traditional))}
    c32: dict[bool, dict[str, np.ndarray]] = {True: {}, False: {}}
    for name, r in runs.items():
        if name == "ident_1":
            continue
        for p in (True, False):
            y32 = deployment_float32(docs[p], _features(r, config, product=p)).astype(float)
            c32[p][name] = r.output - y32
    diffs = [np.max(np.abs(c32[True][n] - fit.comp_imp[n])) for n in c32[True]]
    rel = [
        abs(err(c32[True][n], runs[n]) - err(fit.comp_imp[n], runs[n]))
        / err(fit.comp_imp[n], runs[n])
        for n in c32[True]
    ]
    q32 = claim_quantities(_scores(runs, c32[True], c32[False]))
    return {
        "max_abs_output_weight": float(np.max(np.abs(docs[True]["LW"]))),
        "max_abs_compensation_difference_deg_h": float(max(diffs)),
        "max_relative_err_change": float(max(rel)),
        "quantities": q32,
    }


def _streaming_deviation(config: Config, model: RBFNetwork, r: _Run, batch: np.ndarray) -> float:
    """Largest |streaming - batch| [deg/h]: the compensator fed 7-sample pieces, as a DSP would."""
    sc = StreamingCompensator(model, r.fs, window_s=config.derivative_window_s, product=True)
    pieces = [sc.push(r.output[i : i + 7], r.T[i : i + 7]) for i in range(0, len(r.output), 7)]
    return float(np.max(np.abs(np.concatenate(pieces + [sc.flush()]) - batch)))


def _traces(config: Config, runs: Mapping[str, _Run], fit: _Fitted) -> dict[str, Any]:
    """Downsampled (100-s blocks) traces of the unit for the report's figures [h, degC, deg/h]."""
    r = runs["ident_2"]
    f32 = np.float32
    ident = {
        "t_h": r.t_h.astype(f32),
        "T": r.T.astype(f32),
        "measured": (r.output - r.reference).astype(f32),
        "true_drift_plus_bias": (r.drift + config.bias_deg_h).astype(f32),
        "estimate_improved": (r.output - fit.comp_imp[r.name]).astype(f32),
        "estimate_traditional": (r.output - fit.comp_trad[r.name]).astype(f32),
    }
    val1 = [
        {
            "t_h": v.t_h.astype(f32),
            "raw": v.output.astype(f32),
            "improved": fit.comp_imp[n].astype(f32),
        }
        for n, v in runs.items()
        if n.startswith("val1")
    ]
    v = runs["val2_run1"]
    val2 = {
        "t_h": v.t_h.astype(f32),
        "raw": v.output.astype(f32),
        "traditional": fit.comp_trad[v.name].astype(f32),
        "improved": fit.comp_imp[v.name].astype(f32),
        "reference": v.reference,
    }
    return {"ident_2": ident, "val1": val1, "val2": val2}


def _drift_peak_val1(runs: Mapping[str, _Run]) -> float:
    """Median over the validation-1 runs of the peak |true coil drift| while scored [deg/h]."""
    peaks = [
        float(np.max(np.abs(r.drift[r.scored]))) for n, r in runs.items() if n.startswith("val1")
    ]
    return float(np.median(peaks))


def _protocol_summary(fit: _Fitted, scores: Mapping[str, Any]) -> dict[str, Any]:
    return {
        "selection": {"improved": fit.sel_imp.as_dict(), "traditional": fit.sel_trad.as_dict()},
        "n_neurons": {
            "improved": fit.improved.n_neurons_,
            "traditional": fit.traditional.n_neurons_,
        },
        "training_mean_output_deg_h": fit.train.mean_output_deg_h,
        "training_rows": int(len(fit.train.y)),
        "scores": scores,
        "quantities": claim_quantities(scores),
    }


def experiment(config: Config, seed: int) -> dict[str, Any]:
    """One unit (seed) through the paper's pipeline: simulate, train on Q, select, score ERR.

    Returns ``quantities`` (one number per claim of :data:`CLAIMS`), the paper protocol's
    details (``paper``), the labelled diagnostic with the truth target
    (``diagnostic_truth_target``), the float32 deployment check, the streaming check,
    the point-heating curve, the winding comparison and downsampled traces for figures.
    """
    runs = {r.name: _prepare(r, config) for r in simulate(config, seed)}
    paper = _fit_protocol(config, runs, "paper")
    truth = _fit_protocol(config, runs, "truth")
    s_paper = _scores(runs, paper.comp_imp, paper.comp_trad)
    s_truth = _scores(runs, truth.comp_imp, truth.comp_trad)
    T_pt, sh_pt, prod_pt, tot_pt = point_heating(config)
    txdt = float(np.max(np.abs(prod_pt)))
    bonded_max = float(np.max(np.abs(point_heating(config, bonded=True)[2])))
    cs = config.coil_spec()
    r_any = np.array([cs.inner_radius])
    b_free = float(
        (cs.beta(r_any, cs.t_hi, bonded=False) - cs.beta(r_any, cs.t_lo, bonded=False))[0]
        / (cs.t_hi - cs.t_lo)
    )
    drift_peak = _drift_peak_val1(runs)
    r0 = runs["val1_run1"]
    return {
        "seed": int(seed),
        "quantities": {
            "txdt_point_max_deg_h": txdt,
            "drift_peak_val1_deg_h": drift_peak,
            **claim_quantities(s_paper),
        },
        "paper": _protocol_summary(paper, s_paper),
        "diagnostic_truth_target": _protocol_summary(truth, s_truth),
        "deployment": json.loads(paper.improved.to_json()),
        "float32": _float32_check(config, runs, paper),
        "streaming_max_abs_deviation_deg_h": _streaming_deviation(
            config, paper.improved, r0, paper.comp_imp[r0.name]
        ),
        "point_heating": {
            "T_degC": T_pt,
            "shupe": sh_pt,
            "product": prod_pt,
            "total": tot_pt,
            "bonded_max": bonded_max,
            "b_free": b_free,
        },
        "windings": winding_comparison(config),
        "traces": _traces(config, runs, paper),
    }


# ======================================================================================
# the paper's claims
# ======================================================================================

_CAL_LEADS = (
    "Config.lead_difference_rms_m = 1.0 m (Coil2DSpec.lead_difference_rms), the spread of a "
    "unit's lead A - lead B fibre length, set so that the median over 20 drawn units of this "
    "quantity is ~0.15 deg/h (0.137 measured on the coil alone); it is the dominant drift "
    "source of a drawn quadrupolar unit (0.20 deg/h per m of asymmetry in this program)"
)

#: the drift the compensators remove is set mostly by the calibrated lead asymmetry, so every
#: validation claim (a ratio or ordering of that drift against the residual) is fed by it
_CAL_FED = (
    "fed by the drift level, which is CALIBRATED: " + _CAL_LEADS
)

CLAIMS: tuple[Claim, ...] = (
    Claim(
        id="003.txdt_point",
        paper=PAPER,
        where="Sec. 2, Table 1 / Fig. 2",
        statement="A stretch of the 1000-m coil at 0.25 L0 heated from -10 to 40 degC: the "
        "nonreciprocity caused by the T x dT term alone exceeds 0.2 deg/h at its maximum "
        "(here: a free fibre, 10 m heated at 1 degC/min; the paper prints neither, and the "
        "term scales linearly with both, so the verdict rests on that assumed case, which was "
        "fixed before the coil model and not changed for it; the T x dT coefficient from "
        "Leviton-Frey dn/dT(T) and the silica expansion slope).",
        kind="emergent",
        quantity="txdt_point_max_deg_h",
        comparator=above(0.2),
        paper_value=0.2,
        unit="deg/h",
    ),
    Claim(
        id="003.drift_level",
        paper=PAPER,
        where="Sec. 0 (introduction, citing its ref. [4])",
        statement="For a +-0.01 deg/h FOG a 10 degC change of the coil temperature gives a "
        "0.15 deg/h temperature drift (here: median over the validation-1 runs, coil warming "
        "10 degC per hour, of the peak true coil drift).",
        kind="calibrated",
        calibrated_input=_CAL_LEADS,
        quantity="drift_peak_val1_deg_h",
        comparator=within_factor(0.15, 2.0),
        paper_value=0.15,
        unit="deg/h",
    ),
    Claim(
        id="003.val1_every_run",
        paper=PAPER,
        where="Sec. 5, Table 2",
        statement="Validation 1 (10 degC/h, a = 0): in every run the MSE after compensation "
        "is clearly smaller than before.",
        kind="calibrated",
        calibrated_input=_CAL_FED,
        quantity="val1_every_run_lower",
        comparator=is_true(),
    ),
    Claim(
        id="003.val1_order",
        paper=PAPER,
        where="Sec. 5, Table 2; abstract; Sec. 6",
        statement="Validation 1: compensation improves the output by about an order of "
        "magnitude (mean ERR raw / compensated over the five runs).",
        kind="calibrated",
        calibrated_input=_CAL_FED,
        quantity="val1_ratio",
        comparator=in_range(3.0, 30.0),
        paper_value=10.0,
        unit="x",
    ),
    Claim(
        id="003.val2_lowest",
        paper=PAPER,
        where="Sec. 5, Table 3",
        statement="Validation 2 (0.5 degC/min, a = 180 deg/h): the improved (T, dT, T x dT) "
        "compensation has a lower MSE than the raw output and than the traditional (T, dT) "
        "compensation in every run.",
        kind="calibrated",
        calibrated_input=_CAL_FED,
        quantity="val2_improved_lowest",
        comparator=is_true(),
    ),
    Claim(
        id="003.val2_order",
        paper=PAPER,
        where="Sec. 5, Table 3",
        statement="Validation 2: the improved compensation raises the accuracy by about an "
        "order of magnitude (mean ERR raw / improved over the five runs).",
        kind="calibrated",
        calibrated_input=_CAL_FED,
        quantity="val2_ratio",
        comparator=in_range(3.0, 30.0),
        paper_value=10.0,
        unit="x",
    ),
)

# Effects measured with `gyrobench reproduce ifog_thermal --units 20 --config FILE` over seeds
# 0-19 (default Config; each variant = one Config switch); the numbers are pass counts "k/20"
# of the claims named, on the (r, z) coil (sim.coil2d, issue 18) in the closed-loop FOG
# (sim.fog_loop via sim.fog2d, issue 17).
DEVIATIONS: tuple[Deviation, ...] = (
    Deviation(
        paper=PAPER,
        what="Earth rate",
        paper_says="turntable pointing exactly north, 'the FOG output is then 0 deg/h'; a = 0",
        we_do="the sense axis is horizontal and points east at Harbin (sense_azimuth_deg = 90), "
        "where the Earth-rate component is 0, so the input is 0 in identification and "
        "validation 1 and the reference a equals the simulator's truth",
        reason="a horizontal north-pointing axis at Harbin (45.8 degN) senses 15.041 "
        "cos(45.8 deg) = 10.48 deg/h, which contradicts the paper's 'output 0 deg/h'; east is "
        "the orientation that gives the zero input the paper states",
        effect="measured over seeds 0-19 with the axis pointing north (sense_azimuth_deg = 0: "
        "the loop adds 10.48 deg/h) and a kept at the paper's value: validation-1 "
        "raw/compensated median 1.01x (default 16.0x), validation-2 1.02x (3.6x); "
        "003.val1_order 0/20 (12/20 east), 003.val2_order 0/20 (8/20), 003.val2_lowest 5/20 "
        "(7/20), 003.val1_every_run 12/20 (19/20): Q removes the constant from the training "
        "target, so a constant the reference does not contain stays in d",
    ),
    Deviation(
        paper=PAPER,
        what="Validation-2 input",
        paper_says="turntable 'rotated 180 deg'; eq. (24) uses a = 180 deg/h",
        we_do="a constant 180 deg/h input rate (the reference of eq. 24); the loop's thermal "
        "scale-factor error at that rate is simulated",
        reason="the text's only number for the reference is 180 deg/h",
        effect="the scale-factor error at 180 deg/h spans -0.22 to +0.14 deg/h (unit 0, run 1) "
        "beside a coil drift of 0.43 deg/h (next row); measured over seeds 0-19 with a zero "
        "validation-2 rate (a = 0, no scale-factor error) instead: 003.val2_lowest 7/20 "
        "(7/20 at 180 deg/h), 003.val2_order 7/20 (8/20), median raw/improved 84x (3.6x)",
    ),
    Deviation(
        paper=PAPER,
        what="Scale factor vs temperature",
        paper_says="not discussed: the paper compensates the bias only; whether its gyro's "
        "scale factor was temperature-compensated is not said",
        we_do="the closed loop's SF(T)/SF0 = (1 + alpha_D dT_coil)^2/(1 + alpha_lambda "
        "dT_housing) about 20 degC, uncompensated; alpha_D = the coil's own hoop expansion on "
        "its aluminium spool (22.7 ppm/K for unit 0, from the composite-cylinder model), "
        "alpha_lambda = 4 ppm/K (assumed): 41 ppm/K",
        reason="one FOG model for every scenario (issue 17); alpha_D from the same coil "
        "mechanics that makes the Shupe drift, nothing chosen for the claims",
        effect="measured over seeds 0-19 with diameter_tempco_ppm_per_K = 2.76 (the net "
        "1.5 ppm/K of the earlier FOG2D product form): validation-2 median raw/improved 73x "
        "(default 3.6x), 003.val2_order 4/20 (8/20), 003.val2_lowest 8/20 (7/20), "
        "validation-1 unchanged (rate 0; val1_order 12/20): at 180 deg/h the scale-factor "
        "error follows T, not dT/dt, and the networks trained at rate 0 cannot see it, so it "
        "stays in d and sets the default's validation-2 ratio",
    ),
    Deviation(
        paper=PAPER,
        what="Deployment precision",
        paper_says="the network runs on a TMS320F28335 (single-precision FPU)",
        we_do="claims are scored with the float64 network; the exported a1/a2 form is also "
        "evaluated in float32 and re-scored (report table)",
        reason="float64 is the reference implementation; the float32 form is the check",
        effect="measured over seeds 0-19: in float32 every claim's pass count is unchanged "
        "(val1_every_run 19, val1_order 12, val2_lowest 7, val2_order 8 of 20); the largest "
        "relative change of a run's ERR is 0.06 % (median over units), 2.1 % at most; 17 of "
        "20 units stay within our 1 % criterion",
    ),
    Deviation(
        paper=PAPER,
        what="Network size and spread",
        paper_says="newrb trained 'until the output meets the design index' (index, spread "
        "and input scaling not printed)",
        we_do="inputs min-max scaled; spread and neuron count by leave-one-segment-out CV on "
        "the training run (goal 0)",
        reason="the paper's settings are not printed; CV uses the training run only",
        effect="not measurable against the paper (its settings are unknown); the CV choice "
        "per unit is in the population table",
    ),
    Deviation(
        paper=PAPER,
        what="Identification record",
        paper_says="step 2: record at -10 degC once the coil temperature and the output are "
        "stable; the heating and cooling rates are not printed",
        we_do="the record starts when the chamber reaches -10 degC, so the 2-h settle includes "
        "the coil's approach (housing lag 20 min); ramps at 1 degC/min",
        reason="'stable' has no stated criterion; the rate is not printed",
        effect="nearest measured (seeds 0-19): also recording the 20 -> -10 degC cool-down before "
        "it (record_cooldown=True) gives val1_every_run 19/20 (19/20), val1_order 12/20 "
        "(12/20), val2_lowest 9/20 (7/20), val2_order 6/20 (8/20)",
    ),
    Deviation(
        paper=PAPER,
        what="Step 5 averaging (interpretation)",
        paper_says="step 5: 'obtain the mean values of the coil temperature and of the gyro "
        "output over the heating and cooling process'",
        we_do="the mean over the heating-and-cooling record, subtracted to form Q (modelling "
        "step 2); variant identification_average='temperature_curves' averages the heating and "
        "cooling records as curves against temperature",
        reason="averaging the two records against T sets dT/dt to ~0 and cancels the drift "
        "that is odd in dT/dt, the very dependence the paper models",
        effect="measured over seeds 0-19 with the temperature_curves variant: validation-1 "
        "raw/compensated median 20.0x (default 16.0x), validation-2 2.5x (default 3.6x); "
        "003.val1_every_run 19/20 (19/20), 003.val1_order 10/20 (12/20), 003.val2_lowest 3/20 "
        "(7/20), 003.val2_order 10/20 (8/20)",
    ),
)


# ======================================================================================
# report: tables and figures from the units' results (formatting only)
# ======================================================================================


def _med(units: Sequence[Mapping[str, Any]], get) -> float:
    return finite_median(get(u) for u in units)


def _population_table(units: Sequence[Mapping[str, Any]]) -> Table:
    rows = []
    for u in units:
        p, d = u["paper"], u["diagnostic_truth_target"]
        si, st = p["selection"]["improved"], p["selection"]["traditional"]
        wins = sum(x["improved"] < min(x["raw"], x["traditional"]) for x in p["scores"]["val2"])
        rows.append(
            [
                u["seed"],
                f"{si['spread']:g} / {si['max_neurons']}",
                f"{st['spread']:g} / {st['max_neurons']}",
                u["quantities"]["drift_peak_val1_deg_h"],
                p["quantities"]["val1_ratio"],
                f"{wins}/{len(p['scores']['val2'])}",
                p["quantities"]["val2_ratio"],
                d["quantities"]["val1_ratio"],
                d["quantities"]["val2_ratio"],
                u["float32"]["max_relative_err_change"],
            ]
        )
    return Table(
        f"Population: the paper's pipeline for each of {len(units)} drawn units (seed = unit)",
        [
            "seed",
            "improved spread / neurons",
            "traditional spread / neurons",
            "peak drift val. 1 [deg/h]",
            "val. 1 raw/comp.",
            "val. 2 improved lowest",
            "val. 2 raw/improved",
            "DIAGNOSTIC truth target: val. 1 raw/comp.",
            "DIAGNOSTIC truth target: val. 2 raw/improved",
            "float32: max rel. ERR change",
        ],
        rows,
        note="Paper protocol: target Q = output - mean(output) over the identification record, "
        "ERR = "
        "MSE(d - a). The two DIAGNOSTIC columns train the same networks on output - the "
        "simulator's truth (not possible for the paper; it also removes the constant bias Q "
        "leaves in the output). Claims are judged by the shared evaluation over these units.",
    )


def _point_table(config: Config, u0: Mapping[str, Any]) -> Table:
    txdt = u0["quantities"]["txdt_point_max_deg_h"]
    coil = config.coil_spec()
    return Table(
        "Table 1. Point-heating simulation conditions (paper) and the reproduced T x dT term",
        ["quantity", "paper", "reproduced"],
        [
            ["fibre CTE alpha_T [1/degC]", "5.5e-7", f"{coil.glass.cte:.3g} (silica, 20 degC)"],
            ["coil length L0 [m]", "1000", f"{config.fibre_length_m:g}"],
            ["wavelength [nm]", "1550", f"{coil.wavelength * 1e9:g}"],
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
            [
                "d(beta_T)/dT [1/K^2], free fibre",
                "(not printed)",
                f"{u0['point_heating']['b_free']:.3g} (Leviton-Frey dn/dT(T) + n d(alpha)/dT)",
            ],
            ["max T x dT term [deg/h], free fibre", "> 0.2", f"{txdt:.3f}"],
            [
                "max T x dT term [deg/h], bonded in the pack",
                "(not in the paper)",
                f"{u0['point_heating']['bonded_max']:.3f}",
            ],
        ],
        note="EMERGENT: the T x dT coefficient comes from material data (sim/coil2d.py), nothing "
        "was set for it. The heated length and rate are ours (Table 1 did not survive "
        "extraction); the term scales linearly with both.",
    )


def _score_tables(u0: Mapping[str, Any]) -> list[Table]:
    s = u0["paper"]["scores"]
    i2, v1, v2 = s["ident_2"], s["val1"], s["val2"]
    seed = u0["seed"]
    m_raw, m_imp = np.mean([d["raw"] for d in v1]), np.mean([d["improved"] for d in v1])
    return [
        Table(
            f"Identification run 2 (the paper's 'validation sample'), unit {seed}: ERR [(deg/h)^2]",
            ["raw", "traditional (T, dT)", "improved (T, dT, T x dT)", "raw / improved"],
            [[i2["raw"], i2["traditional"], i2["improved"], i2["raw"] / i2["improved"]]],
            note="Same chamber program as the training run; fresh noise and its own housing lag.",
        ),
        Table(
            f"Table 2. Validation 1 (-10 -> 40 degC at 10 degC/h, a = 0), unit {seed}: "
            "ERR [(deg/h)^2]",
            ["run", "ERR raw", "ERR compensated (T, dT, T x dT)", "ratio"],
            [[i + 1, d["raw"], d["improved"], d["raw"] / d["improved"]] for i, d in enumerate(v1)]
            + [["mean", m_raw, m_imp, m_raw / m_imp]],
            note="Paper: clearly lower after compensation, about one order of magnitude.",
        ),
        Table(
            f"Table 3. Validation 2 (0.5 degC/min, a = 180 deg/h), unit {seed}: ERR [(deg/h)^2]",
            ["run", "raw", "traditional (T, dT)", "improved (T, dT, T x dT)", "improved lowest"],
            [
                [
                    i + 1,
                    d["raw"],
                    d["traditional"],
                    d["improved"],
                    "yes" if d["improved"] < min(d["raw"], d["traditional"]) else "no",
                ]
                for i, d in enumerate(v2)
            ],
            note="Paper: improved is lowest in every run, about an order of magnitude better "
            "than raw.",
        ),
    ]


def _cv_table(config: Config, u0: Mapping[str, Any]) -> Table:
    sel = u0["paper"]["selection"]
    neurons = sorted({g["max_neurons"] for g in sel["improved"]["grid"]})
    rows = []
    for model in ("improved", "traditional"):
        s = sel[model]
        grid = {(g["spread"], g["max_neurons"]): g["cv_mse"] for g in s["grid"]}
        for sp in sorted({k[0] for k in grid}):
            cells = []
            for mn in neurons:
                mark = "*" if (sp, mn) == (s["spread"], s["max_neurons"]) else ""
                if (sp, mn) == (s["best"]["spread"], s["best"]["max_neurons"]) and not mark:
                    mark = "(best)"
                cells.append(f"{grid[(sp, mn)]:.4g}{mark}")
            rows.append([model, sp, *cells])
    return Table(
        f"RBF selection, unit {u0['seed']}: leave-one-segment-out CV MSE [(deg/h)^2] on the "
        "training "
        "run, by spread (rows) and max neurons (columns)",
        ["model", "spread [normalized]", *[f"{mn} neurons" for mn in neurons]],
        rows,
        note=f"* = chosen: the fewest neurons within {config.rbf_cv_tolerance:.0%} of the best CV "
        "MSE, ties to the largest spread; folds are the settle, heat + hold and cool + hold "
        "segments (temperature thirds for the temperature_curves variant). Only the training run "
        "takes part. (best) marks the unpenalised CV minimum when it differs.",
    )


# Our acceptance criterion for the float32 deployment form (the paper states none): no held-out
# run's ERR may change by more than 1 %.
_FLOAT32_TOLERANCE = 0.01


def _float32_table(units: Sequence[Mapping[str, Any]]) -> Table:
    f = [u["float32"] for u in units]
    n_ok = sum(x["max_relative_err_change"] <= _FLOAT32_TOLERANCE for x in f)
    flips = sum(
        x["quantities"][k] != u["paper"]["quantities"][k]
        for x, u in zip(f, units, strict=True)
        for k in ("val1_every_run_lower", "val2_improved_lowest")
    )
    return Table(
        "Deployment form in single precision (the paper's DSP): exported a1/a2 networks in float32 "
        "vs float64, every held-out run, over the units",
        ["quantity", "median over units", "largest"],
        [
            [
                "largest output weight abs(LW)",
                _med(f, lambda x: x["max_abs_output_weight"]),
                max(x["max_abs_output_weight"] for x in f),
            ],
            [
                "largest abs(d float32 - d float64) [deg/h]",
                _med(f, lambda x: x["max_abs_compensation_difference_deg_h"]),
                max(x["max_abs_compensation_difference_deg_h"] for x in f),
            ],
            [
                "largest relative change of a run's ERR",
                _med(f, lambda x: x["max_relative_err_change"]),
                max(x["max_relative_err_change"] for x in f),
            ],
        ],
        note=f"Criterion (ours; the paper states none): no run's ERR changes by more than "
        f"{_FLOAT32_TOLERANCE:.0%}. Met by {n_ok} of {len(f)} units. Yes/no claim quantities that "
        f"differ between float32 and float64: {flips} (of {2 * len(f)}: units x 2 claims).",
    )


def _winding_table(u0: Mapping[str, Any]) -> Table:
    w = u0["windings"]
    return Table(
        "Winding patterns: peak coil drift of the identification chamber run "
        "(ideal windings, no noise) [deg/h]",
        ["winding", "peak total", "peak Shupe (beta_T at T0)", "peak T x dT"],
        [
            [
                k,
                v.get("peak_total", "n/a"),
                v.get("peak_shupe", "n/a"),
                v.get("peak_product", v.get("error", "")),
            ]
            for k, v in w.items()
        ],
        note="Not in the paper. Same chamber program and coil; only the layer order changes.",
    )


def _fig_point(config: Config, u0: Mapping[str, Any]) -> FigureSpec:
    from matplotlib.figure import Figure

    p = u0["point_heating"]
    f = Figure(figsize=(7, 4))
    ax = f.add_subplot()
    ax.plot(p["T_degC"], p["product"], label="T x dT term (material data)")
    ax.plot(p["T_degC"], p["shupe"], label="beta_T(0 degC) term")
    ax.plot(p["T_degC"], p["total"], "--", label="total")
    ax.axhline(0.2, color="grey", lw=0.8, ls=":")
    ax.set_xlabel("temperature of the heated stretch [degC]")
    ax.set_ylabel("rate error [deg/h]")
    ax.set_title(
        f"Shupe error of {config.point_length_m:g} m at {config.point_z_fraction:g} L0, "
        f"{config.point_rate_degC_per_min:g} degC/min"
    )
    ax.legend()
    f.tight_layout()
    return FigureSpec(
        "fig2_point_heating",
        "Figure 2: nonreciprocity of a heated fibre stretch at 0.25 L0 (-10 -> 40 degC); "
        "the T x dT "
        "term alone (from material data: Leviton-Frey dn/dT(T), silica expansion).",
        f,
    )


def _fig_ident(u0: Mapping[str, Any]) -> FigureSpec:
    from matplotlib.figure import Figure

    r = u0["traces"]["ident_2"]
    f = Figure(figsize=(8, 5))
    ax = f.add_subplot(211)
    ax.plot(r["t_h"], r["measured"], lw=0.6, color="0.6", label="output - a")
    ax.plot(r["t_h"], r["true_drift_plus_bias"], lw=1.0, label="true coil drift + bias")
    ax.plot(r["t_h"], r["estimate_improved"], lw=1.0, label="RBF estimate (T, dT, T x dT)")
    ax.plot(r["t_h"], r["estimate_traditional"], lw=1.0, ls="--", label="RBF estimate (T, dT)")
    ax.set_ylabel("drift [deg/h]")
    ax.legend(fontsize=7)
    ax.set_title(f"Identification run 2, unit {u0['seed']} (not used for training)")
    ax2 = f.add_subplot(212, sharex=ax)
    ax2.plot(r["t_h"], r["T"])
    ax2.set_xlabel("time [h]")
    ax2.set_ylabel("logged coil T [degC]")
    f.tight_layout()
    return FigureSpec(
        "fig6_estimated_drift",
        "Figure 6: drift estimated by the networks (trained on Q = output - mean) on the second "
        "identification run, beside the true drift. Q's networks estimate the drift up to a "
        "constant.",
        f,
    )


def _fig_validation(u0: Mapping[str, Any]) -> list[FigureSpec]:
    from matplotlib.figure import Figure

    f = Figure(figsize=(8, 4))
    ax = f.add_subplot()
    for i, rr in enumerate(u0["traces"]["val1"]):
        ax.plot(
            rr["t_h"], rr["raw"], lw=0.5, color="C0", alpha=0.6, label="raw" if i == 0 else None
        )
        ax.plot(
            rr["t_h"],
            rr["improved"],
            lw=0.5,
            color="C1",
            alpha=0.8,
            label="compensated" if i == 0 else None,
        )
    ax.set_xlabel("time [h]")
    ax.set_ylabel("output [deg/h] (a = 0)")
    ax.set_title(f"Validation 1, unit {u0['seed']}: runs at 10 degC/h")
    ax.legend()
    f.tight_layout()
    g = Figure(figsize=(8, 4))
    bx = g.add_subplot()
    v = u0["traces"]["val2"]
    bx.plot(v["t_h"], v["raw"], lw=0.6, label="raw")
    bx.plot(v["t_h"], v["traditional"], lw=0.6, label="traditional (T, dT)")
    bx.plot(v["t_h"], v["improved"], lw=0.6, label="improved (T, dT, T x dT)")
    bx.axhline(v["reference"], color="k", lw=0.8, ls=":", label="reference a")
    bx.set_xlabel("time [h]")
    bx.set_ylabel("output [deg/h]")
    bx.set_title(f"Validation 2, run 1, unit {u0['seed']}: 0.5 degC/min, a = 180 deg/h")
    bx.legend(fontsize=8)
    g.tight_layout()
    return [
        FigureSpec("fig7_validation1", "Figure 7: validation 1, raw and compensated output.", f),
        FigureSpec("fig8_validation2", "Figure 8: validation 2, raw, traditional and improved.", g),
    ]


def _fig_population(units: Sequence[Mapping[str, Any]]) -> FigureSpec:
    from matplotlib.figure import Figure

    f = Figure(figsize=(8, 4))
    ax = f.add_subplot()
    seeds = [u["seed"] for u in units]
    for key, mk, lab in (
        ("val1_ratio", "o", "val. 1 raw/comp."),
        ("val2_ratio", "s", "val. 2 raw/improved"),
    ):
        ax.plot(
            seeds,
            [u["paper"]["quantities"][key] for u in units],
            mk,
            label=f"{lab} (paper protocol)",
        )
        ax.plot(
            seeds,
            [u["diagnostic_truth_target"]["quantities"][key] for u in units],
            mk,
            mfc="none",
            label=f"{lab} (DIAGNOSTIC truth target)",
        )
    ax.axhspan(3.0, 30.0, color="0.9", label="'about an order of magnitude' (3-30x)")
    ax.set_yscale("log")
    ax.set_xlabel("unit (seed)")
    ax.set_ylabel("ERR raw / compensated")
    ax.legend(fontsize=7)
    f.tight_layout()
    return FigureSpec(
        "population_ratios",
        "Improvement ratios of every unit with the paper's protocol and, hollow, the "
        "truth-target diagnostic.",
        f,
    )


def _results(units: Sequence[Mapping[str, Any]]) -> dict[str, Any]:
    """JSON-able numbers behind the tables: per-unit summaries and unit 0's detail."""
    u0 = units[0]

    def summary(u):
        return {
            "seed": u["seed"],
            "quantities": u["quantities"],
            "selection": {
                k: {"spread": v["spread"], "max_neurons": v["max_neurons"]}
                for k, v in u["paper"]["selection"].items()
            },
            "training_mean_output_deg_h": u["paper"]["training_mean_output_deg_h"],
            "diagnostic_truth_target_quantities": u["diagnostic_truth_target"]["quantities"],
            "float32": u["float32"],
            "streaming_max_abs_deviation_deg_h": u["streaming_max_abs_deviation_deg_h"],
        }

    return {
        "unit_rows": [summary(u) for u in units],
        "detail_unit": {
            "seed": u0["seed"],
            "paper": u0["paper"],
            "diagnostic_truth_target": u0["diagnostic_truth_target"],
            "deployment": u0["deployment"],
        },
        "txdt_max_deg_h": u0["quantities"]["txdt_point_max_deg_h"],
        "windings": u0["windings"],
        "float32_tolerance": _FLOAT32_TOLERANCE,
    }


def _bands(units: Sequence[Mapping[str, Any]], key: str) -> str:
    """How many units' ratio ``key`` lie below, inside and above its claim's band (3-30x)."""
    cmp = next(c.comparator for c in CLAIMS if c.quantity == key)
    a, b = cmp.lo, cmp.hi
    q = [v for u in units if (v := u["quantities"][key]) is not None and math.isfinite(v)]
    lo, hi = sum(v < a for v in q), sum(v > b for v in q)
    return f"{lo} below {a:g}x, {len(q) - lo - hi} in {a:g}-{b:g}x, {hi} above {b:g}x"


def _conclusion(claims: Sequence[ClaimResult], units: Sequence[Mapping[str, Any]]) -> str:
    parts = []
    for c in claims:
        rate = "not testable" if c.pass_rate is None else f"{c.holds}/{c.testable}"
        mark = " [CALIBRATED, not a reproduction]" if c.claim.kind == "calibrated" else ""
        parts.append(f"{c.claim.id}: {c.verdict} ({rate}){mark}")
    d1 = _med(units, lambda u: u["diagnostic_truth_target"]["quantities"]["val1_ratio"])
    p1 = _med(units, lambda u: u["paper"]["quantities"]["val1_ratio"])
    return (
        f"Over {len(units)} units with the paper's protocol (target Q = output - mean, ERR against "
        f"the reference): "
        + "; ".join(parts)
        + f". Validation-1 ratio: {_bands(units, 'val1_ratio')}"
        f" (median {p1:.3g}x); validation-2 ratio: {_bands(units, 'val2_ratio')}. The ratio is set "
        "by the drawn unit's drift over the constant that Q leaves in the output; in validation 2 "
        "(180 deg/h) also by the loop's uncompensated scale-factor error, which follows T and "
        "which networks trained at rate 0 cannot remove (deviation 'Scale factor vs "
        "temperature'). DIAGNOSTIC with "
        f"the simulator's truth as target (not possible for the paper): median validation-1 ratio "
        f"{d1:.3g}x."
    )


def report(
    config: Config, units: Sequence[Mapping[str, Any]], claims: Sequence[ClaimResult]
) -> Outcome:
    """Tables and figures from the units' results (population from all, detail from the first)."""
    if not units:
        raise ValueError("report needs at least one unit's results; got none")
    u0 = units[0]
    tables = [
        _population_table(units),
        _point_table(config, u0),
        *_score_tables(u0),
        _cv_table(config, u0),
        _float32_table(units),
        _winding_table(u0),
    ]
    figures = [_fig_point(config, u0), _fig_ident(u0), *_fig_validation(u0), _fig_population(units)]
    return Outcome(
        scenario=NAME,
        title=TITLE,
        seed=int(u0["seed"]),
        config=config,
        results=_results(units),
        tables=tables,
        figures=figures,
        conclusion=_conclusion(claims, units),
    )
