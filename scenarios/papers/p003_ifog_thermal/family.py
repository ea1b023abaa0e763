"""Paper 003's device family: the coil defects, materials, sensor and noise the paper does not give.

The paper reports of its gyro the T x dT size of a heated stretch of its 1000-m coil (Table 1)
and, citing its ref. [4], a drift level (0.15 deg/h per 10 degC); it prints no winding, lead,
potting, sensor position or noise figure of the unit it tests. The family sweeps them, each over
a physical range with its source or a stated assumption (:data:`FAMILY`):

============================  ==========================================  ===========================
field (Config)                what                                        range, source
============================  ==========================================  ===========================
lead_difference_rms_m         lead A - lead B length spread (lead         [0.1, 5] m, log: STATED
                              asymmetry)                                  (calibrated 1.198 m inside)
turn_error_probability        a layer's chance of a turn gained (and of   [0, 0.3]: STATED (0.15
                              one lost) at a layer change (winding)       default)
layer_radius_error_pitch_rms  layer radial displacement / pitch (winding  [0, 0.1]: STATED (0.03)
                              tension)
potting_cte_spread            unit-to-unit spread of the potting CTE      [0, 0.3]: STATED (0.15)
epoxy_cte_slope_per_K2        d alpha/dT of the potting epoxy             [0.06e-6, 1.8e-6] /K^2, log:
                                                                          STATED (slope/alpha 1e-3 to
                                                                          3e-2 /K)
silica_cte_slope_per_K2       d alpha/dT of the fibre glass               [0, 5.1e-9] /K^2: the bound
                                                                          of SILICA_CTE_SLOPE_BOUNDS
                                                                          (Souder & Hidnert 1926)
sensor_z_center               logged sensor's mean axial position on the  [-1, 1] of the half height:
                              outer surface (sensor placement)            STATED (not printed)
sensor_noise_K                sensor white noise per sample               [0.0005, 0.03] K, log: STATED
bias_instability_deg_h        FOG flicker floor                           [0.0005, 0.01] deg/h, log:
                                                                          the paper's "+-0.01 deg/h
                                                                          FOG" as the top
============================  ==========================================  ===========================

The constraints are the paper's device claims (:data:`MAP_CONSTRAINTS`: each reads the quantity
and band of its claim in :data:`.claims.CLAIMS`, so the tolerance is the claim's); the claims
mapped are those judged under a precondition (:data:`MAP_CLAIMS`: the four validation claims
and the drift-estimate extension). The paper's contribution, the T x dT input beating (T, dT)
(``003.val2_lowest``), needs a T x dT dependence in the drift the networks learn from: the T x dT
share of the true drift on the training run (:func:`.pipeline.txdt_share`) is reported per point
as a covariate (:data:`MAP_COVARIATES`), so the map shows at which shares the contribution holds.
"""

from __future__ import annotations

from gyrobench.base.ranges import FieldRange
from gyrobench.scenarios.maps.family import Family, Fixed, Parameter
from gyrobench.scenarios.maps.region import Constraint, Covariate
from gyrobench.sim.coil_materials import SILICA_CTE_SLOPE_BOUNDS

from .claims import CLAIMS
from .config import Config

__all__ = ["DEFAULT_POINTS", "DEFAULT_UNITS_PER_POINT", "DESIGN_SEED", "FAMILY", "MAP_CLAIMS", "MAP_CONSTRAINTS",
           "MAP_COVARIATES"]

#: the design's scramble seed (:func:`gyrobench.scenarios.maps.family.design`)
DESIGN_SEED = 2026
#: the default map: 64 Sobol points x 5 units (a unit costs under 1 s of CPU; the contribution's
#: precondition holds on few points, so the map needs more of them than the CLI's default 16)
DEFAULT_POINTS = 64
DEFAULT_UNITS_PER_POINT = 5

FAMILY = Family(
    paper="003",
    nominal_device=(
        "the default Config(): lead asymmetry identified from the drift level (identify.IDENTIFIED; 1.198 m "
        "rms), the stated winding, potting and sensor defaults"
    ),
    base=Config(),
    parameters=(
        Parameter(
            field="lead_difference_rms_m",
            range=FieldRange(0.1, 5.0, "m"),
            scale="log",
            source="STATED ASSUMPTION: the spread of lead A - lead B fibre length of a wound coil (fibre-midpoint "
            "error plus pigtail routing), from a coil wound from a marked midpoint with trimmed pigtails "
            "(0.1 m) to hand-routed leads (5 m); the calibrated 1.198 m (identify.IDENTIFIED) lies inside",
            label="lead asymmetry (rms)",
        ),
        Parameter(
            field="turn_error_probability",
            range=FieldRange(0.0, 0.3, "1"),
            scale="linear",
            source="STATED ASSUMPTION: a turn gained or lost at a flange at a layer change, from a perfect "
            "winding machine (0) to twice the stated default 0.15 (sim.coil_winding.Imperfections)",
            label="turn error probability per layer",
        ),
        Parameter(
            field="layer_radius_error_pitch_rms",
            range=FieldRange(0.0, 0.1, "1"),
            scale="linear",
            source="STATED ASSUMPTION: winding-tension variation of the layer radius, 0 to 10 % of the layer "
            "pitch (default 3 %, sim.coil_winding.Imperfections)",
            label="layer radius error / pitch",
        ),
        Parameter(
            field="potting_cte_spread",
            range=FieldRange(0.0, 0.3, "1"),
            scale="linear",
            source="STATED ASSUMPTION: batch-to-batch and cure variation of the potting's expansion, 0 to "
            "30 % (default 15 %, Coil2DSpec.realize)",
            label="potting CTE spread (rel. 1 sigma)",
        ),
        Parameter(
            field="epoxy_cte_slope_per_K2",
            range=FieldRange(0.06e-6, 1.8e-6, "1/K^2"),
            scale="log",
            source="STATED ASSUMPTION: no published alpha(T) of a potting epoxy was read; slope/alpha of "
            "1e-3 to 3e-2 /K on alpha = 60e-6 /K, the top as the CTE rises towards a glass transition above the "
            "chamber's 40 degC (the default 0.18e-6 is 3e-3 /K, sim.coil_materials.EPOXY)",
            label="potting d alpha/dT",
        ),
        Parameter(
            field="silica_cte_slope_per_K2",
            range=FieldRange(SILICA_CTE_SLOPE_BOUNDS[0], SILICA_CTE_SLOPE_BOUNDS[1], "1/K^2"),
            scale="linear",
            source="sim.coil_materials.SILICA_CTE_SLOPE_BOUNDS: fused silica's minimum length near -80 degC "
            "(Souder & Hidnert, NBS Sci. Paper 524 (1926)) bounds d alpha/dT at 293 K to [0, 5.1e-9] /K^2; "
            "Hahn & Kirby (1972)'s 2.4e-9 lies inside",
            label="fibre glass d alpha/dT",
        ),
        Parameter(
            field="sensor_z_center",
            range=FieldRange(-1.0, 1.0, "1"),
            scale="linear",
            source="STATED ASSUMPTION: the paper logs one PT1000 on the coil and prints no position; the mean "
            "axial position on the outer potting surface over its whole height (each unit's sensor within "
            "1 - |centre| of it)",
            label="sensor axial position (of half height)",
        ),
        Parameter(
            field="sensor_noise_K",
            range=FieldRange(0.0005, 0.03, "K"),
            scale="log",
            source="STATED ASSUMPTION: white noise per 1-Hz sample of the logged sensor, from the paper's "
            "PT1000 on an 18-bit ADC (about 0.4 mK resolution) to a noisy read-out (30 mK)",
            label="temperature sensor noise",
        ),
        Parameter(
            field="bias_instability_deg_h",
            range=FieldRange(0.0005, 0.01, "deg/h"),
            scale="log",
            source="the paper's introduction speaks of a +-0.01 deg/h FOG: the top of the range; the bottom "
            "(0.0005 deg/h) a STATED navigation-grade floor",
            label="bias instability",
        ),
    ),
    fixed=(
        Fixed(field="fibre_length_m", source="the paper's Table 1: L0 = 1000 m"),
        Fixed(field="layers", source="STATED (Config): a 40-layer quadrupolar pack on a 0.1 m coil"),
        Fixed(field="winding", source="STATED (Config): quadrupolar, the usual navigation-FOG winding "
              "(the paper prints none)"),
        Fixed(field="sensor_location", source="the paper logs the coil (fibre-ring) temperature: the outer "
              "potting surface"),
        Fixed(field="sensor_resolution_K", source="STATED (Config): 1 mK (the paper's 18-bit ADC, ~0.4 mK)"),
        Fixed(field="housing_time_constant_min", source="STATED (Coil2DSpec.chamber_conductance: 12.5 W/(m^2 K) "
              "free convection, Cengel; tau_h 20 min)"),
        Fixed(field="housing_lag_run_rms", source="STATED (Config): run-to-run mounting and airflow spread"),
        Fixed(field="modulation_depth_pi", source="STATED (Config): 3 pi/4 bias, ARW 4e-4 deg/sqrt(h)"),
        Fixed(field="bias_deg_h", source="STATED (Config): a constant bias (removed by Q = output - mean)"),
        Fixed(field="wavelength_tempco_ppm_per_K", source="STATED (Config): an unstabilised Er ASE source"),
        Fixed(field="point_length_m", source="ASSUMED (docs/physics.md 9): Table 1's heated length is not printed"),
        Fixed(field="point_rate_degC_per_min", source="ASSUMED (docs/physics.md 9): Table 1's rate is not printed"),
    ),
)

#: the paper's device facts as constraints: each of its device claims' quantity and band
MAP_CONSTRAINTS: tuple[Constraint, ...] = tuple(
    Constraint(id=c.id, fact=c.statement, source=c.where, quantity=c.quantity, comparator=c.comparator)
    for c in CLAIMS
    if c.role == "device"
)

#: the method (and extension) claims, each judged on units that show its effect
MAP_CLAIMS = tuple(c for c in CLAIMS if c.precondition is not None)

#: what the contribution claim (003.val2_lowest) rests on, reported per point
MAP_COVARIATES: tuple[Covariate, ...] = (
    Covariate(
        quantity="txdt_share",
        label="T x dT share of the training drift [-]",
        definition="R^2(1, T, dT, T x dT) - R^2(1, T, dT) of the true coil drift on identification run 1 "
        "against the logged features (pipeline.txdt_share): the drift variance only a T x dT input explains, "
        "what the improved network can gain over the traditional one",
    ),
    Covariate(
        quantity="txdt_unabsorbed",
        label="(T, dT) network's excess validation-2 ERR, truth-trained [-]",
        definition="the precondition of 003.val2_lowest: with both networks trained on the true drift, the "
        "(T, dT) network's mean validation-2 ERR over the (T, dT, T x dT) network's, minus 1",
    ),
)
