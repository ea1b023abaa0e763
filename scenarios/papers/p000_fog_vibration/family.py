"""Paper 000's device family: the mount, the record and the noise grade the paper does not give.

The paper reports of its FOG and its shaker set-up only what the Allan tables and figures show
(Table 1's rise of the terms in the vibration phase and phases 1 and 3 alike, fig. 3's bias
offset at about 300-500 Hz, fig. 7's offset standing clear after denoising); the mount, the phase
lengths and the gyro's grade are not given. The default device's vibration bias is the coning of
two rocking modes of its mount (:mod:`gyrobench.sim.mount_coning`, identified in :mod:`.identify`).
The family sweeps the mount's modes, the record's phases and the bias instability
(:data:`FAMILY`), each over a physical range with its source or a stated assumption:

===========================  =========================================  ===================================
field (Config path)          what                                       range, source
===========================  =========================================  ===================================
fog.mount.x.frequency        rocking mode about x                       [250, 650] Hz: STATED (fixture modes)
fog.mount.y.frequency        rocking mode about y                       [250, 650] Hz: STATED
fog.mount.x.quality          its quality factor                         [3, 50], log: STATED (bolted joints)
fog.mount.y.quality          its quality factor                         [3, 50], log: STATED
fog.mount.x.compliance       its tilt per acceleration                  [1.42e-7, 1.42e-5] rad/(m/s^2), log:
                                                                        0.1x-10x the identified one
fog.mount.y.compliance       its tilt per acceleration                  as x
static_before_s              static phase 1                             [300, 900] s: STATED
vibration_s                  vibration phase 2                          [150, 900] s: STATED
static_after_s               static phase 3                             [300, 900] s: STATED
fog.B_deg_h                  bias instability (noise grade)             [0.01, 0.5] deg/h, log: STATED
===========================  =========================================  ===================================

The nominal point (:meth:`Family.nominal <gyrobench.scenarios.maps.family.Family.nominal>`) is
the default ``Config()``, the device ``gyrobench reproduce fog_vibration`` runs. The acceleration
stays 2 g: the coning bias scales as a^2 c_x c_y, so the compliances' range covers other levels.

**Constraints** (:data:`MAP_CONSTRAINTS`): the paper's device facts, each with the quantity and
band of its device claim in :data:`.claims.CLAIMS` (the tolerance is the claim's), except
:data:`KEPT_OUT`: Table 1's K and R facts (rise in phase 2, lower after) need records of about
37,000 h (K) and 4,700 h (R) per phase at the default B, 1,500 h and 940 h at the family's lowest
B (:func:`.identify.required_record_s`), out of reach of every record of the family (<= 900 s a
phase), so they would empty the region for a reason of ours, not the paper's; and N's rise,
which the fit of the vibration phase leaves open on this device (its vibration adds tones and a
bias, no white noise: the claim's statement); and B's rise, which gives no finite value on any
point of the default map: the vibration phase's fit never identifies B, though its longest phase
at the family's highest B is long enough by the record rule (measured: :data:`KEPT_OUT`). Those six are
mapped as claims instead (:data:`MAP_CLAIMS`), so the map shows on how many points each could be
tested. Q, N and B "unchanged between phases 1 and 3" hold by the model's structure (the claims'
calibrated input: phases 1 and 3 share one stationary noise process); they stay in as facts.

**Claims mapped** (:data:`MAP_CLAIMS`): every method and extension claim (the method claims
under :data:`.claims.VIBRATION_BIAS_SHOWS`), then the kept-out device facts.
"""

from __future__ import annotations

import dataclasses

from gyrobench.base.ranges import FieldRange
from gyrobench.scenarios.maps.family import Family, Fixed, Parameter
from gyrobench.scenarios.maps.region import Constraint

from .claims import CLAIMS
from .config import Config
from .identify import IDENTIFIED, INPUTS, required_record_s

__all__ = [
    "DEFAULT_POINTS",
    "DEFAULT_UNITS_PER_POINT",
    "DESIGN_SEED",
    "FAMILY",
    "KEPT_OUT",
    "MAP_CLAIMS",
    "MAP_CONSTRAINTS",
]

#: the design's scramble seed (:func:`gyrobench.scenarios.maps.family.design`)
DESIGN_SEED = 2000
#: the default map: 32 Sobol points x 3 units (a unit costs about 3 s of CPU and 0.5 GB)
DEFAULT_POINTS = 32
DEFAULT_UNITS_PER_POINT = 3

_C = IDENTIFIED.compliance_rad_per_m_s2

_MODE_HZ = ("STATED ASSUMPTION: a bolted gyro fixture's rocking modes, hundreds of Hz (the identification "
            "places them at 400 and 460 Hz, in fig. 3's band); the range reaches 50 Hz beyond the band's "
            "ends on both sides, so fig. 3's fact selects where the bias offset sits")
_MODE_Q = ("STATED ASSUMPTION: a bolted joint's damping ratio of 1-17 % (Q 3-50; the identification's "
           "Q 10 is a damping ratio of 5 %)")
_MODE_C = ("0.1x-10x the identified compliance (identify.IDENTIFIED, CALIBRATED to fig. 7's offset at 10 x "
           "the scatter on the median unit): the coning bias scales as c_x c_y, so the range spans biases "
           "from 1/100 to 100 times the identified one")
_PHASE = ("STATED ASSUMPTION: the paper gives no durations; the default phases (300 s vibration, 600 s "
          "static) from half to 900 s in whole seconds (on every sample grid), a range across the record B needs "
          "to be identified in a phase "
          f"({required_record_s('B', INPUTS) / 60.0:.1f} min, identify.required_record_s)")

FAMILY = Family(
    paper="000",
    nominal_device=(
        "the default Config(): the coning mount identified from fig. 7 (identify.IDENTIFIED; rocking modes "
        "400 and 460 Hz, Q 10), phases 600/300/600 s, B 0.05 deg/h"
    ),
    base=Config(),
    parameters=(
        Parameter(field="fog.mount.x.frequency", range=FieldRange(250.0, 650.0, "Hz"), scale="linear",
                  source=_MODE_HZ, label="mount mode x frequency"),
        Parameter(field="fog.mount.y.frequency", range=FieldRange(250.0, 650.0, "Hz"), scale="linear",
                  source=_MODE_HZ, label="mount mode y frequency"),
        Parameter(field="fog.mount.x.quality", range=FieldRange(3.0, 50.0, "1"), scale="log",
                  source=_MODE_Q, label="mount mode x Q"),
        Parameter(field="fog.mount.y.quality", range=FieldRange(3.0, 50.0, "1"), scale="log",
                  source=_MODE_Q, label="mount mode y Q"),
        Parameter(field="fog.mount.x.compliance", range=FieldRange(_C / 10.0, _C * 10.0, "rad/(m/s^2)"),
                  scale="log", source=_MODE_C, label="mount mode x compliance"),
        Parameter(field="fog.mount.y.compliance", range=FieldRange(_C / 10.0, _C * 10.0, "rad/(m/s^2)"),
                  scale="log", source=_MODE_C, label="mount mode y compliance"),
        Parameter(field="static_before_s", range=FieldRange(300.0, 900.0, "s"), scale="linear",
                  source=_PHASE, label="static phase 1", step=1.0),
        Parameter(field="vibration_s", range=FieldRange(150.0, 900.0, "s"), scale="linear",
                  source=_PHASE, label="vibration phase 2", step=1.0),
        Parameter(field="static_after_s", range=FieldRange(300.0, 900.0, "s"), scale="linear",
                  source=_PHASE, label="static phase 3", step=1.0),
        Parameter(field="fog.B_deg_h", range=FieldRange(0.01, 0.5, "deg/h"), scale="log",
                  source="STATED ASSUMPTION: a FOG's bias instability from a navigation-grade 0.01 deg/h to a "
                  "tactical 0.5 deg/h (the default 0.05 deg/h is chosen so the static phases identify B, "
                  "identify.py)", label="bias instability B"),
    ),
    fixed=(
        Fixed(field="acceleration_g", source="STATED (the paper gives no level); degenerate with the compliances "
              "(the coning bias scales as a^2 c_x c_y)"),
        Fixed(field="fixed_hz", source="the paper's fixed-frequency record (b): 500 Hz"),
        Fixed(field="sweep_end_hz", source="the paper's sweep (a): 1-500 Hz"),
        Fixed(field="fog.Q_arcsec", source="STATED (identify.INPUTS: 0.01 arcsec)"),
        Fixed(field="fog.K_deg_h_sqrt_h", source="STATED (identify.INPUTS: 0.003 deg/h/sqrt(h))"),
        Fixed(field="fog.R_deg_h2", source="STATED (identify.INPUTS: 0.001 deg/h^2)"),
        Fixed(field="fog.mode_frequency_spread", source="STATED, no source (identify.INPUTS: 5 %)"),
        Fixed(field="fog.coupling_spread", source="STATED, no source (identify.INPUTS: 0.3 in the log)"),
        Fixed(field="fog.latitude_deg", source="the paper's lab, Southeast University, Nanjing (sim.earth)"),
    ),
)

def _out_of_reach(t: str) -> str:
    """Why ``t`` (K or R) is out of reach: the record it needs at the default B and at the family's lowest B."""
    low_b = dataclasses.replace(INPUTS, B_deg_h=FAMILY.parameters[-1].range.low)
    need, least = (required_record_s(t, i) / 3600.0 for i in (INPUTS, low_b))
    return (f"{t} needs about {need:,.0f} h of record a phase at the default B ({least:,.0f} h at the family's "
            "lowest B; identify.required_record_s); the family's phases are <= 900 s")


#: the device facts kept out of the region, with the reason (module docstring)
KEPT_OUT: dict[str, str] = {
    "000.t1_N_rises": "the vibration phase's fit leaves N open on this device (the vibration adds tones and a "
    "bias, no white noise)",
    "000.t1_B_rises": "no finite value on any point of the default map (32 points x 3 units; vibration phases up "
    "to 900 s, B up to 0.5 deg/h): the phase-2 fit never identifies B, so its bound decides nothing. At the "
    "family's most favourable corner (every phase 900 s, B 0.5 deg/h; two units) phases 1 and 3 identify B "
    "(0.49-0.50 deg/h, +-2 %) while phase 2's fit gives only a 95 % upper bound of 31 and 54 deg/h: the "
    "vibration's tones and bias, not the record's length (identify.required_record_s: about 6 s at that B), "
    "keep B open in the vibration phase",
    **{f"000.t1_{t}_rises": _out_of_reach(t) for t in ("K", "R")},
    **{f"000.t1_{t}_lower_after": _out_of_reach(t) for t in ("K", "R")},
}

#: the paper's device facts as constraints: its device claims' quantities and bands, less KEPT_OUT
MAP_CONSTRAINTS: tuple[Constraint, ...] = tuple(
    Constraint(id=c.id, fact=c.statement, source=c.where, quantity=c.quantity, comparator=c.comparator)
    for c in CLAIMS
    if c.role == "device" and c.id not in KEPT_OUT
)

#: every method and extension claim, then the device facts kept out of the region
MAP_CLAIMS = (
    *(c for c in CLAIMS if c.role != "device"),
    *(c for c in CLAIMS if c.id in KEPT_OUT),
)
