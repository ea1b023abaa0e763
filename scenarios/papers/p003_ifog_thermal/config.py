"""Paper 003's configuration: the chamber protocols, the FOG build, the analysis settings.

:class:`Config` holds every parameter of the reproduction with the paper's protocol as
default (field units in the field names); its builders turn it into the simulator's specs
(:class:`gyrobench.sim.fog2d.FOG2DSpec`) and chamber programs. See the package docstring
for the protocol it encodes.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import ClassVar

import numpy as np

from gyrobench.base import units
from gyrobench.base.ranges import Constraint, FieldChoice, FieldRange, ordered, validate
from gyrobench.sim.coil2d import Coil2DSpec
from gyrobench.sim.coil_materials import EPOXY, SILICA, SILICA_CTE_SLOPE, T_REF, Material
from gyrobench.sim.environment import PiecewiseLinear, Ramp, Soak, thermal_profile
from gyrobench.sim.fog2d import FOG2DSpec, TemperatureSensorSpec
from gyrobench.sim.fog_optics import OpticalBudget
from gyrobench.sim.noise import NoiseModel

__all__ = [
    "AVERAGES",
    "ESTIMATORS",
    "Config",
    "FEATURES_IMPROVED",
    "FEATURES_TRADITIONAL",
    "NAME",
    "PAPER",
    "TARGETS",
    "TITLE",
]

# the package's identity, for its modules (the package __init__ repeats them as literals,
# which the registry reads with ast)
NAME = "ifog_thermal"
TITLE = "IFOG thermal drift from Shupe coil physics; RBF compensation with a T x dT input"
PAPER = "003"

FEATURES_IMPROVED = ("T [degC]", "dT/dt [degC/s]", "T x dT/dt [degC^2/s]")
FEATURES_TRADITIONAL = FEATURES_IMPROVED[:2]

_H = units.HOUR
_MIN = units.MINUTE
#: step 5's averaging: the record mean (the paper's protocol) or heating and cooling as curves
AVERAGES = ("record_mean", "temperature_curves")
#: the dT/dt estimator of the features: a Savitzky-Golay derivative over ``derivative_window_s``
#: (ours) or the central difference of the analysis-rate samples (a variant; the paper's eq. 13
#: did not survive extraction)
ESTIMATORS = ("savgol", "central_difference")
#: the networks' training target: Q = output - mean(output) (the paper) or output - truth
TARGETS = ("paper", "truth")


@dataclass(frozen=True, slots=True, kw_only=True)
class Config:
    """Every parameter of the reproduction, paper setup as default (field units in the name).

    Chamber protocols, FOG build, logging and analysis rates, RBF settings, and the
    conditions of the paper's Table 1 / figure 2 point-heating simulation.

    The coil (``gyrobench.sim.coil2d.Coil2DSpec`` defaults): every material
    constant has a cited source or a stated value there; the T x dT term comes from the
    Leviton-Frey dn/dT(T) of silica and the expansion slopes of silica, epoxy and aluminium
    (nothing is set for it). One input is CALIBRATED to the paper: ``lead_difference_rms_m``
    (1.198 m), the spread of a unit's lead A - lead B length, identified by
    :func:`.identify.identify_lead_asymmetry` (frozen in ``identify.IDENTIFIED``) so that the
    median validation-1 peak coil drift of 60 drawn coils (identification seeds) is 0.15 deg/h
    (the paper's level for a 10 degC change). ``housing_time_constant_min`` sets the chamber-housing conductance
    (C_h / tau_h); ``fibre_length_m`` sets the turns per layer (round(L / (2 pi sum r_j))).

    The FOG: the same closed-loop unit as paper 000
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
    :func:`gyrobench.analysis.compensation.rbf_selection.select_rbf`) over ``rbf_spread_grid``
    x ``rbf_neuron_grid``. A number fixes
    that setting, and CV then chooses only the other one (if it is None).

    Protocol switches (package docstring): ``record_cooldown``, ``identification_average``
    (+ ``curve_bin_degC``) and ``score_final_soak``; the defaults are the paper's protocol.
    ``derivative_estimator`` (``ESTIMATORS``): how dT/dt is taken from the logged temperature.
    ``thermal_program`` False is the control population (``control_config``): no thermal
    program, the chamber holds ``start_degC`` for each run's duration.

    Coil defects and materials a device family sweeps (defaults: the ``Coil2DSpec`` and
    ``sim.coil_materials`` values, all stated there): ``turn_error_probability`` (a layer's
    chance of one turn gained, and of one lost), ``layer_radius_error_pitch_rms`` (layer radial
    displacement rms / pitch), ``potting_cte_spread`` (unit-to-unit relative spread of the
    potting's CTE), ``epoxy_cte_slope_per_K2`` and ``silica_cte_slope_per_K2`` (d alpha/dT of
    the potting and of the fibre glass [1/K^2]; the glass keeps alpha(300 K) = 0.55e-6 /K),
    ``sensor_z_center`` (the logged sensor's mean axial position on the outer surface, a
    fraction of the half height).

    Attributes
    ----------
    start_degC : float
        Chamber temperature at the start of every run [degC].
    low_degC, high_degC : float
        The identification program's low and high temperatures [degC].
    identification_rate_degC_per_min : float
        Identification ramp rate [degC/min].
    identification_settle_h : float
        Settle at the low temperature before the heating ramp [h].
    identification_hold_h : float
        Hold after each ramp [h].
    validation_soak_h : float
        Validation runs' soak [h].
    validation1_runs : int
        Validation-1 runs.
    validation1_rate_degC_per_h : float
        Validation-1 ramp rate [degC/h].
    validation2_runs : int
        Validation-2 runs.
    validation2_rate_degC_per_min : float
        Validation-2 ramp rate [degC/min].
    validation2_true_rate_deg_h : float
        The turntable rate of validation 2 [deg/h].
    winding : str
        The coil's winding pattern (``sim.coil_winding.WINDING_PATTERNS``).
    layers : int
        The coil's layers.
    fibre_length_m : float
        Fibre length [m] (sets the turns per layer).
    lead_difference_rms_m : float
        Spread of a unit's lead A - lead B length [m] (CALIBRATED).
    housing_time_constant_min : float
        Chamber-housing thermal time constant [min].
    housing_lag_run_rms : float
        Relative run-to-run spread of the housing's conductance [-].
    modulation_depth_pi : float
        Biasing modulation depth [pi rad].
    bias_instability_deg_h : float
        Added bias instability B [deg/h].
    bias_deg_h : float
        Added constant bias [deg/h].
    diameter_tempco_ppm_per_K : float or None
        Coil diameter tempco [ppm/K] (None: the coil's own hoop expansion).
    wavelength_tempco_ppm_per_K : float
        Source wavelength tempco [ppm/K].
    sense_azimuth_deg : float
        Sense-axis azimuth from north [deg].
    sensor_location : str
        Where the temperature sensor sits on the coil (``sim.fog2d.TemperatureSensorSpec``).
    sensor_noise_K : float
        The temperature sensor's white noise [K].
    sensor_resolution_K : float
        Its resolution [K].
    thermal_step_s : float
        The coil's thermal solver step [s].
    fs_hz : float
        FOG logging rate [Hz].
    analysis_block_s : float
        Averaging block of the analysis [s].
    derivative_window_s : float
        Window of the dT/dt estimate [s].
    derivative_estimator : {"savgol", "central_difference"}
        How dT/dt is taken from the logged temperature.
    thermal_program : bool
        Run the thermal programs (False: the control, the chamber holds ``start_degC``).
    rbf_spread : float or None
        RBF spread in normalized input units (None: chosen by cross-validation).
    rbf_goal_deg_h2 : float
        newrb's goal [(deg/h)^2].
    rbf_max_neurons : int or None
        Network size (None: chosen by cross-validation).
    rbf_spread_grid : tuple of float
        The spreads cross-validation tries.
    rbf_neuron_grid : tuple of int
        The sizes cross-validation tries.
    rbf_cv_tolerance : float
        Relative CV tolerance of the simplest-model rule [-].
    record_cooldown : bool
        Record the identification run from its start (else from reaching the low temperature).
    identification_average : {"record_mean", "temperature_curves"}
        How step 5 averages the identification records.
    curve_bin_degC : float
        Temperature bin of the "temperature_curves" average [degC].
    score_final_soak : bool
        Score the validation runs' final soak too.
    point_z_fraction : float
        Position of the heated stretch along the fibre [fraction of L].
    point_length_m : float
        Length of the heated stretch [m].
    point_rate_degC_per_min : float
        Its heating rate [degC/min].
    turn_error_probability : float
        A layer's chance of one turn gained, and of one lost [-].
    layer_radius_error_pitch_rms : float
        Layer radial displacement rms over the pitch [-].
    potting_cte_spread : float
        Unit-to-unit relative spread of the potting's CTE [-].
    epoxy_cte_slope_per_K2 : float
        d alpha/dT of the potting [1/K^2].
    silica_cte_slope_per_K2 : float
        d alpha/dT of the fibre glass [1/K^2].
    sensor_z_center : float
        The logged sensor's mean axial position on the outer surface [fraction of the half height].
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
    lead_difference_rms_m: float = 1.198  # CALIBRATED: identify.IDENTIFIED
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
    # coil defects and materials (Coil2DSpec, sim.coil_materials defaults)
    turn_error_probability: float = 0.15
    layer_radius_error_pitch_rms: float = 0.03
    potting_cte_spread: float = 0.15
    epoxy_cte_slope_per_K2: float = EPOXY.cte_slope
    silica_cte_slope_per_K2: float = SILICA_CTE_SLOPE
    sensor_z_center: float = 0.0
    # logging and analysis
    fs_hz: float = 1.0
    analysis_block_s: float = 100.0
    derivative_window_s: float = 900.0
    derivative_estimator: str = "savgol"
    # False: the control population (no thermal program): every run keeps its duration and
    # record windows but the chamber holds start_degC throughout
    thermal_program: bool = True
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

    #: every numeric field's documented range, in its field unit (:class:`~gyrobench.scenarios.base.FieldRange`;
    #: refused in one line outside it). Chamber: a climatic chamber's span and ramp rates; durations: what one
    #: unit's records can hold (the memory estimate refuses a long run at a high rate first); the build: a
    #: navigation FOG's coil and source; counts: what one unit runs in minutes, not weeks.
    RANGES: ClassVar[Mapping[str, FieldRange | FieldChoice]] = {
        "start_degC": FieldRange(-70.0, 150.0, "degC", "climatic chamber span"),
        "low_degC": FieldRange(-70.0, 150.0, "degC", "climatic chamber span"),
        "high_degC": FieldRange(-70.0, 150.0, "degC", "climatic chamber span"),
        "identification_rate_degC_per_min": FieldRange(0.0, 20.0, "degC/min", "chamber ramp rate", low_open=True),
        "identification_settle_h": FieldRange(0.0, 1000.0, "h", "one unit's record", low_open=True),
        "identification_hold_h": FieldRange(0.0, 1000.0, "h", "one unit's record", low_open=True),
        "validation_soak_h": FieldRange(0.0, 1000.0, "h", "one unit's record", low_open=True),
        "validation1_runs": FieldRange(1, 1000, "runs", "runs one unit holds", integer=True),
        "validation1_rate_degC_per_h": FieldRange(0.0, 1200.0, "degC/h", "chamber ramp rate", low_open=True),
        "validation2_runs": FieldRange(1, 1000, "runs", "runs one unit holds", integer=True),
        "validation2_rate_degC_per_min": FieldRange(0.0, 20.0, "degC/min", "chamber ramp rate", low_open=True),
        "validation2_true_rate_deg_h": FieldRange(-3.6e6, 3.6e6, "deg/h", "a rate table's +-1000 deg/s"),
        "layers": FieldRange(1, 1000, "layers", "a wound coil's layer count", integer=True),
        "fibre_length_m": FieldRange(0.0, 2e4, "m", "a FOG coil's fibre (km class)", low_open=True),
        "lead_difference_rms_m": FieldRange(0.0, 100.0, "m", "lead asymmetry, well under the coil length"),
        "housing_time_constant_min": FieldRange(0.0, 1e4, "min", "thermal lag of a housing", low_open=True),
        "housing_lag_run_rms": FieldRange(0.0, 0.5, "1", "relative run-to-run spread"),
        "modulation_depth_pi": FieldRange(0.0, 1.0, "pi rad", "biasing modulation depth", low_open=True,
                                          high_open=True),
        "bias_instability_deg_h": FieldRange(0.0, 1000.0, "deg/h", "any gyro grade"),
        "bias_deg_h": FieldRange(-1e4, 1e4, "deg/h", "any gyro grade"),
        "diameter_tempco_ppm_per_K": FieldRange(-1000.0, 1000.0, "ppm/K", "any spool material"),
        "wavelength_tempco_ppm_per_K": FieldRange(-1000.0, 1000.0, "ppm/K", "any broadband source"),
        "sense_azimuth_deg": FieldRange(-360.0, 360.0, "deg", "one turn either way"),
        "sensor_noise_K": FieldRange(0.0, 10.0, "K", "a temperature sensor"),
        "sensor_resolution_K": FieldRange(0.0, 10.0, "K", "a temperature sensor"),
        "thermal_step_s": FieldRange(0.01, 3600.0, "s", "thermal solver step"),
        "turn_error_probability": FieldRange(0.0, 0.5, "1", "chance per layer of a turn gained (and lost)"),
        "layer_radius_error_pitch_rms": FieldRange(0.0, 1.0, "1", "layer radial error rms / layer pitch"),
        "potting_cte_spread": FieldRange(0.0, 0.5, "1", "relative unit-to-unit spread of the potting CTE"),
        "epoxy_cte_slope_per_K2": FieldRange(-1e-5, 1e-5, "1/K^2", "d alpha/dT of a potting polymer"),
        "silica_cte_slope_per_K2": FieldRange(-1e-7, 1e-7, "1/K^2", "d alpha/dT of a fibre glass"),
        "sensor_z_center": FieldRange(-1.0, 1.0, "1", "fraction of the coil's half height"),
        "fs_hz": FieldRange(1e-3, 1e4, "Hz", "FOG logging rate"),
        "analysis_block_s": FieldRange(0.0, 1e5, "s", "averaging block", low_open=True),
        "derivative_window_s": FieldRange(0.0, 1e5, "s", "dT/dt window", low_open=True),
        "rbf_spread": FieldRange(0.0, 1e6, "1", "RBF spread, normalized input units", low_open=True),
        "rbf_goal_deg_h2": FieldRange(0.0, 1e6, "(deg/h)^2", "newrb goal"),
        "rbf_max_neurons": FieldRange(1, 10000, "neurons", "newrb network size", integer=True),
        "rbf_spread_grid": FieldRange(0.0, 1e6, "1", "RBF spread, normalized input units", low_open=True),
        "rbf_neuron_grid": FieldRange(1, 10000, "neurons", "newrb network size", integer=True),
        "rbf_cv_tolerance": FieldRange(0.0, 10.0, "1", "relative CV tolerance"),
        "identification_average": FieldChoice(AVERAGES, "step 5's averaging"),
        "derivative_estimator": FieldChoice(ESTIMATORS, "the dT/dt estimator of the features"),
        "curve_bin_degC": FieldRange(0.0, 100.0, "degC", "temperature bin", low_open=True),
        "point_z_fraction": FieldRange(0.0, 1.0, "1", "fraction of the coil length"),
        "point_length_m": FieldRange(0.0, 2e4, "m", "heated stretch, within a coil", low_open=True),
        "point_rate_degC_per_min": FieldRange(0.0, 20.0, "degC/min", "heating rate", low_open=True),
    }

    #: the constraints across fields (:class:`~gyrobench.base.ranges.Constraint`)
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        ordered("low_degC", "high_degC"),
        Constraint(
            "rbf_spread is not None or rbf_spread_grid",
            lambda c: c.rbf_spread is not None or len(c.rbf_spread_grid) > 0,
            lambda c: "rbf_spread_grid must hold at least one spread > 0 (normalized input units) when "
            f"rbf_spread is None; got {c.rbf_spread_grid!r}",
        ),
        Constraint(
            "rbf_max_neurons is not None or rbf_neuron_grid",
            lambda c: c.rbf_max_neurons is not None or len(c.rbf_neuron_grid) > 0,
            lambda c: "rbf_neuron_grid must hold at least one integer >= 1 when rbf_max_neurons is None; "
            f"got {c.rbf_neuron_grid!r}",
        ),
        Constraint(
            "analysis_block_s x fs_hz >= 1",
            lambda c: c.analysis_block_s * c.fs_hz >= 1,
            lambda c: f"analysis_block_s must span at least one sample at fs_hz = {c.fs_hz} Hz; "
            f"got {c.analysis_block_s!r} s",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above
        self.fog_spec()  # the sim layer validates the build (layers, winding, ...)

    # ----------------------------------------------------------------- builders
    def coil_spec(self, *, winding: str | None = None) -> Coil2DSpec:
        """The coil: ``Coil2DSpec`` defaults with this build (``winding`` overrides the pattern)."""
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
            turn_error_probability=self.turn_error_probability,
            radius_error_rms=self.layer_radius_error_pitch_rms,
            matrix_cte_spread=self.potting_cte_spread,
            sensor_z_center=self.sensor_z_center,
            matrix=self._epoxy(),
            glass=self._silica(),
        )

    def _epoxy(self) -> Material:
        """The potting epoxy with this build's expansion slope (the material itself at its own slope)."""
        if self.epoxy_cte_slope_per_K2 == EPOXY.cte_slope:
            return EPOXY
        return replace(EPOXY, cte_slope=self.epoxy_cte_slope_per_K2)

    def _silica(self) -> Material:
        """Fused silica with this build's expansion slope, alpha(300 K) = 0.55e-6 /K kept (the
        material itself at its own slope)."""
        b = self.silica_cte_slope_per_K2
        if b == SILICA.cte_slope:
            return SILICA
        return replace(SILICA, cte=0.55e-6 - b * (300.0 - T_REF), cte_slope=b)

    def fog_spec(self, *, winding: str | None = None) -> FOG2DSpec:
        """The closed-loop FOG on :meth:`coil_spec`, with this build's noise, optics and sensor."""
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
        """Chamber program of an identification run [K over s], from ``start_degC``."""
        r = self.identification_rate_degC_per_min / _MIN
        C = units.celsius
        return self._held(thermal_profile(
            C(self.start_degC),
            [
                Ramp(target=C(self.low_degC), rate=r),
                Soak(duration=self.identification_settle_h * _H),
                Ramp(target=C(self.high_degC), rate=r),
                Soak(duration=self.identification_hold_h * _H),
                Ramp(target=C(self.low_degC), rate=r),
                Soak(duration=self.identification_hold_h * _H),
            ],
        ))

    def validation_profile(self, rate_K_per_s: float) -> PiecewiseLinear:
        """Chamber program of a validation run: soak at ``low_degC``, ramp, soak at ``high_degC``."""
        C = units.celsius
        soak = Soak(duration=self.validation_soak_h * _H)
        return self._held(
            thermal_profile(C(self.low_degC), [soak, Ramp(target=C(self.high_degC), rate=rate_K_per_s), soak])
        )

    def _held(self, program: PiecewiseLinear) -> PiecewiseLinear:
        """``program`` itself, or (``thermal_program`` False, the control) the same knot times at a
        constant ``start_degC``: the runs' durations, segments and record windows are unchanged."""
        if self.thermal_program:
            return program
        times = np.asarray(program.times, dtype=float)
        return PiecewiseLinear(times=times, values=np.full(times.shape, units.celsius(self.start_degC)))
