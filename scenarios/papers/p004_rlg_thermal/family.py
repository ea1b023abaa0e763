"""Paper 004's device family: the gyro sizes the paper does not give, its device facts, its method claims.

The paper reports of its gyro only what the temperature regressors do with its output (a large
thermal effect, Multiple R high, adjusted R^2 ~0.97, Table 1); every mechanism size of the
simulated gyro is open. The family sweeps the ones the thermal bias depends on, each over a
physical range with its source or a stated assumption (:data:`FAMILY`):

==========================  ==========================================  ===========================
field (Config)              what                                        range, source
==========================  ==========================================  ===========================
dissipative                 backscatter null shift per unit lock-in eta [1e-6, 3e-2], log: STATED
                                                                        (CAVITY_RLG_FAMILY; no
                                                                        printed source; the default
                                                                        1.26e-3 is identified)
langmuir_deg_h_per_ma       Langmuir flow coefficient                   [0.0066, 6.6] deg/h/mA, log:
                                                                        the value Aronowitz & Lim
                                                                        print and its per-uA reading
imbalance_repeatability_ua  leg-current imbalance at turn-on (Langmuir  [0, 10] uA: STATED
                            drive)                                      (CAVITY_RLG_FAMILY)
mount_asymmetry             block-mount conductance spread (gradient    [0, 0.5]: STATED
                            coupling)                                   (CAVITY_RLG_FAMILY)
backscatter_sigma           mirror backscatter amplitude scale          [8e-8, 8e-7], log: STATED
                                                                        (rms lock-in ~0.01-0.1 deg/s)
sensor_noise_k              temperature sensors' white noise per sample [0.002, 0.1] K: STATED
                            (sensor coupling)
==========================  ==========================================  ===========================

The sensors read the housing and block-A nodes directly (:class:`gyrobench.sim.rlg_cavity.CavityRLG`):
how a sensor couples to its node is no Config field, so the "sensor coupling" swept is the
sensors' noise, which the derivative regressors x3-x8 read. The fixed sizes are listed with their
sources in :data:`FAMILY` (``fixed``). The constraints are the paper's device claims
(:data:`MAP_CONSTRAINTS`: each reads the quantity and band of its claim in :data:`.claims.CLAIMS`,
so the tolerance is the claim's); the method claims mapped are those judged under
:data:`.claims.THERMAL_PRECONDITION` (:data:`MAP_CLAIMS`).
"""

from __future__ import annotations

from gyrobench.base.ranges import FieldRange
from gyrobench.scenarios.maps.family import Family, Fixed, Parameter
from gyrobench.scenarios.maps.region import Constraint
from gyrobench.sim.rlg_cavity import CAVITY_RLG_FAMILY

from .claims import CLAIMS, THERMAL_PRECONDITION
from .config import Config

__all__ = ["DESIGN_SEED", "FAMILY", "MAP_CLAIMS", "MAP_CONSTRAINTS"]

#: the design's scramble seed (:func:`gyrobench.scenarios.maps.family.design`)
DESIGN_SEED = 2026

_FAM = CAVITY_RLG_FAMILY

FAMILY = Family(
    paper="004",
    nominal_device=(
        "the default Config(): the null shift identified from the bias swing (identify.IDENTIFIED; ratio "
        "1.26e-3), Langmuir 0.0066 deg/h/mA"
    ),
    base=Config(),
    parameters=(
        Parameter(
            field="dissipative",
            range=FieldRange(_FAM.dissipative.low, _FAM.dissipative.high, "1"),
            scale="log",
            source="STATED ASSUMPTION: no printed source of a null shift per unit lock-in; "
            "sim.rlg_cavity.CAVITY_RLG_FAMILY.dissipative, from variable-temperature biases of 0.001-1 deg/h "
            "over lock-in rates of 0.01-0.1 deg/s (identified to 1.26e-3 for the nominal device, identify.py)",
            label="null-shift ratio eta",
        ),
        Parameter(
            field="langmuir_deg_h_per_ma",
            range=FieldRange(0.0066, 6.6, "deg/h/mA"),
            scale="log",
            source="Aronowitz & Lim, Opt. Eng. 18(4) 376 (1979) print 0.0066 deg/h per mA of leg imbalance; "
            "the upper end reads the printed unit per uA (1000x, the deviation variant langmuir_per_ua): "
            "the range spans the two readings",
            label="Langmuir coefficient",
        ),
        Parameter(
            field="imbalance_repeatability_ua",
            range=FieldRange(0.0, _FAM.imbalance_repeatability.high * 1e6, "uA"),
            scale="linear",
            source="STATED ASSUMPTION: sim.rlg_cavity.CAVITY_RLG_FAMILY.imbalance_repeatability "
            "(up to 1.7 % of a 0.6 mA leg current)",
            label="leg imbalance at turn-on (std)",
        ),
        Parameter(
            field="mount_asymmetry",
            range=FieldRange(_FAM.mount_asymmetry.low, _FAM.mount_asymmetry.high, "1"),
            scale="linear",
            source="STATED ASSUMPTION: sim.rlg_cavity.CAVITY_RLG_FAMILY.mount_asymmetry (machined mounts of "
            "one design): the housing-to-block gradient coupling",
            label="mount asymmetry (gradient coupling)",
        ),
        Parameter(
            field="backscatter_sigma",
            range=FieldRange(8e-8, 8e-7, "1"),
            scale="log",
            source="STATED ASSUMPTION: the default 4e-7 gives an rms lock-in of ~0.05 deg/s on the 0.14 m "
            "triangle (docs/physics.md 6.6) and the lock-in scales with it; the range spans lock-in rates "
            "of ~0.01-0.1 deg/s, the span CAVITY_RLG_FAMILY.dissipative is stated over",
            label="backscatter amplitude",
        ),
        Parameter(
            field="sensor_noise_k",
            range=FieldRange(0.002, 0.1, "K"),
            scale="linear",
            source="STATED ASSUMPTION: white noise per 10-Hz sample of a logged RTD/thermistor channel, "
            "from a 0.01 K-resolution read-out's own noise (0.002 K) to a noisy one (0.1 K)",
            label="temperature sensor noise",
        ),
    ),
    fixed=(
        Fixed(field="cte_bound_ppm_per_k", source="SCHOTT, Technical Details of ZERODUR: expansion class 2"),
        Fixed(field="gas_rise_k", source="STATED, inside CAVITY_RLG_FAMILY.gas_rise [10, 100] K"),
        Fixed(field="tcr_mismatch_ppm_per_k", source="STATED, inside CAVITY_RLG_FAMILY.tcr_mismatch_std "
              "[0, 25] ppm/K (metal-film resistor TCR classes)"),
        Fixed(field="walk_phase_std_rad", source="STATED, inside CAVITY_RLG_FAMILY.walk_phase_std [0, 3] rad"),
        Fixed(field="leg_current_ma", source="STATED (docs/physics.md 6.6: I_0 = 0.6 mA)"),
        Fixed(field="triangle_side_m", source="STATED: a 0.42 m path triangle (docs/physics.md 6.6)"),
        Fixed(field="plc_travel_min_wavelengths", source="STATED (docs/physics.md 6.6: travel 1.2-1.8 lambda)"),
        Fixed(field="plc_travel_max_wavelengths", source="STATED (docs/physics.md 6.6: travel 1.2-1.8 lambda)"),
        Fixed(field="bias_instability_deg_h", source="STATED (Config): a navigation-grade RLG's flicker floor"),
        Fixed(field="bias_repeatability_deg_h", source="STATED (Config): turn-on to turn-on bias spread"),
    ),
)

#: the paper's device facts as constraints: each of its device claims' quantity and band
MAP_CONSTRAINTS: tuple[Constraint, ...] = tuple(
    Constraint(id=c.id, fact=c.statement, source=c.where, quantity=c.quantity, comparator=c.comparator)
    for c in CLAIMS
    if c.role == "device"
)

#: the method (and extension) claims judged where the unit shows the thermal effect
MAP_CLAIMS = tuple(c for c in CLAIMS if c.precondition is THERMAL_PRECONDITION)
