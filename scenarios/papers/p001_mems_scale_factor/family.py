"""Paper 001's device family: the read-out sizes, the noise and the repeatability the paper does not give.

The paper reports of its +-3600 deg/s prototype only what its rate table shows (section 3,
Table 2): raw K_n 15.71 %, the low rates nearly linear (K_n of order 1e-3), the heuristic's
breakpoints at -1800 and +1800 deg/s, similar curves run to run and "several significant local
features". Its design, read-out, noise and repeatability are not given. The default
(``variant="identified"``) device reads the resonator out open loop through the sense chain of
:mod:`gyrobench.sim.mems_readout`; the family sweeps that chain's nonlinearity sizes, the noise
and the run-to-run repeatability (:data:`FAMILY`), each over a physical range with its source or a
stated assumption:

===================================  =========================================  ==============================
field (Config path)                  what                                       range, source
===================================  =========================================  ==============================
readout.nominal.rail                 front-end rail V_rail: where the read-out  [1, 3] V, log: STATED (a 3.3-5 V
                                     clips (with the identified C_f)            supply's output swing)
readout.nominal.sense_bias           sense-electrode bias V_s: electrostatic    [0, 15] V: STATED (pull-in
                                     softening (expansive)                      margin, see Parameter)
readout.nominal.k3                   flexure cubic stiffness (hardening)        [0, 7.5e11] N/m^3: STATED
readout.nominal.gap                  pick-off gap g: the 1/(g - y) expansion    [1.8, 2.5] um: STATED (etch)
gyro.quadrature_spread               unit-to-unit quadrature (shares the rail)  [0, 6e-4]: STATED (0-3x default)
gyro.nominal.pickoff_noise           front-end noise (the ARW)                  [2.27e-14, 2.27e-11] m/sqrt(Hz),
                                                                                log: 0.1x-100x the cited part's
gyro.nominal.scale_factor_           turn-on scale-factor error (1 sigma)       [0, 1e-2]: the rate grade's
repeatability                                                                   0.1-1 % (Norouzpour-Shirazi 2013)
ambient_spread_c                     run-to-run die temperature (1 sigma)       [0, 3] degC: STATED
===================================  =========================================  ==============================

The feedback capacitor stays the identified one (``variant="identified"``: C_f from raw K_n
15.71 % on the nominal chain, :data:`.identify.IDENTIFIED`); the rail moves where the chain clips
for that C_f (the clip displacement solves V_c dC(y_c) / C_f = V_rail), so the raw K_n is a
constraint here, not a calibration. The nominal point (:meth:`Family.nominal
<gyrobench.scenarios.maps.family.Family.nominal>`) is the default ``Config()``, the device
``gyrobench reproduce mems_scale_factor`` runs.

The constraints (:data:`MAP_CONSTRAINTS`) are the paper's device facts: its four device claims
(quantity and band of each claim in :data:`.claims.CLAIMS`, so the tolerance is the claim's) and
the heuristic's breakpoints, one constraint per side: the median over a point's units of how far
from -1800 or +1800 deg/s the heuristic split that side (``breakpoint_negative_miss_dps``,
``breakpoint_positive_miss_dps``) below a quarter table step (90 deg/s). The search returns table
rates only, so a unit's miss is 0, 360, 720, ... deg/s, and the band holds a median of 0 and no
other: the median of an even count of units (a unit that did not split that side gives no value)
averages two misses, 180 deg/s or more unless both are 0 (a distance, not the position, so that
1440 and 2160 do not average to 1800). No unit splitting that side gives a NaN median.

The method claims mapped (:data:`MAP_CLAIMS`) are those judged where the unit shows the effect
(:data:`.claims.SHOWS_THE_EFFECT`). The breakpoint claim is among them: over
the region, whose points already split at +-1800 by the median of their units, it holds nearly by
construction, so its whole-family count is the informative one.

:func:`noise_free_breakpoints` runs the heuristic on the noise-free table of each point's nominal
unit over a large design (milliseconds a point): where the family's read-out splits without noise,
and whether those points give the paper's raw and low-rate K_n, the mechanism behind the map's
breakpoint counts.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np

from gyrobench.base.ranges import FieldRange
from gyrobench.scenarios.claims import below
from gyrobench.scenarios.maps.family import Family, Fixed, Parameter
from gyrobench.scenarios.maps.region import Constraint
from gyrobench.sim.mems_resonator import DEFAULT_PICKOFF_NOISE

from .claims import CLAIMS, SHOWS_THE_EFFECT
from .config import Config

__all__ = [
    "BREAKPOINT_TOLERANCE_DPS",
    "BreakpointScan",
    "DEFAULT_POINTS",
    "DEFAULT_UNITS_PER_POINT",
    "DESIGN_SEED",
    "FAMILY",
    "MAP_CLAIMS",
    "MAP_CONSTRAINTS",
    "noise_free_breakpoints",
    "noise_free_table",
]

#: the design's scramble seed (:func:`gyrobench.scenarios.maps.family.design`)
DESIGN_SEED = 2001
#: the default map: 32 Sobol points x 3 units (a unit costs about 3-4 s of CPU)
DEFAULT_POINTS = 32
DEFAULT_UNITS_PER_POINT = 3
#: tolerance of the breakpoint facts: a quarter of the table's 360 deg/s step [deg/s] (module docstring)
BREAKPOINT_TOLERANCE_DPS = 90.0
#: the paper's breakpoints (Table 2) [deg/s]
_PAPER_BREAKPOINT_DPS = 1800.0

FAMILY = Family(
    paper="001",
    nominal_device=(
        "the default Config(): the read-out chain identified from the raw and low-rate K_n "
        "(identify.IDENTIFIED; rail 1.5 V, sense bias 5 V, no cubic stiffness, 2 um gap)"
    ),
    base=Config(),
    parameters=(
        Parameter(
            field="readout.nominal.rail",
            range=FieldRange(1.0, 3.0, "V"),
            scale="log",
            source="STATED ASSUMPTION: the output swing of a charge amplifier on a 3.3-5 V supply less its "
            "headroom (SenseChain's default 1.5 V; SenseChain.RANGES allows 0.1-10 V); with the identified C_f "
            "it places the clip from about 1500 deg/s (1 V) to beyond the table's 3600 deg/s (3 V)",
            label="front-end rail V_rail",
        ),
        Parameter(
            field="readout.nominal.sense_bias",
            range=FieldRange(0.0, 15.0, "V"),
            scale="linear",
            source="STATED ASSUMPTION: MEMS sense-electrode bias, volts to tens of V (Kaajakari, Practical MEMS, "
            "2009, ch. 6; SenseChain.RANGES 0-30 V), kept below 15 V so that no drawn unit (gap 3 sigma small, "
            "quadrature 3 sigma large) reaches the harmonic balance's pull-in on the 1.8 um gap",
            label="sense bias V_s (softening)",
        ),
        Parameter(
            field="readout.nominal.k3",
            range=FieldRange(0.0, 7.5e11, "N/m^3"),
            scale="linear",
            source="STATED ASSUMPTION: from folded flexures (0, the default) to a stretching flexure whose "
            "hardening (3/4) k3 a^2 at the full-scale envelope (~1e-7 m) is ~3x the default electrostatic "
            "softening; 7.5e11 keeps a unit drawn +3 sigma (k3_spread 10 %) inside SenseChain.RANGES (<= 1e12)",
            label="cubic stiffness k3 (hardening)",
        ),
        Parameter(
            field="readout.nominal.gap",
            range=FieldRange(1.8e-6, 2.5e-6, "m"),
            scale="linear",
            source="STATED ASSUMPTION: the 2 um design gap -10 %/+25 % (deep-reactive-ion etch bias; "
            "SenseChain.RANGES 0.5-10 um, Kaajakari 2009 ch. 6); below 1.8 um a drawn unit can reach pull-in "
            "at 15 V",
            label="pick-off gap g",
        ),
        Parameter(
            field="gyro.quadrature_spread",
            range=FieldRange(0.0, 6e-4, "1"),
            scale="linear",
            source="STATED ASSUMPTION: unit-to-unit 1-sigma of k_yx/k_x from a trimmed quadrature (0) to 3x "
            "MemsResonatorSpec's default 2e-4 (Omega_q ~ 540 deg/s, an untrimmed quadrature of hundreds of "
            "deg/s); the quadrature shares the front end's rail with the rate",
            label="quadrature spread (1 sigma)",
        ),
        Parameter(
            field="gyro.nominal.pickoff_noise",
            range=FieldRange(DEFAULT_PICKOFF_NOISE / 10.0, DEFAULT_PICKOFF_NOISE * 100.0, "m/sqrt(Hz)"),
            scale="log",
            source="0.1x to 100x the default (ARW 0.01 deg/sqrt(s), the ADXRS646 data sheet's); the upper end "
            "(about 1 deg/s/sqrt(Hz)) is a STATED ASSUMPTION beyond the data sheets read (ADXRS646 0.01, "
            "ADXRS150 0.05 deg/s/sqrt(Hz)): a prototype's read-out, kept so that the map shows what the "
            "breakpoints do when noise reaches the low rates' curvature",
            label="pick-off noise density",
        ),
        Parameter(
            field="gyro.nominal.scale_factor_repeatability",
            range=FieldRange(0.0, 1e-2, "1"),
            scale="linear",
            source="the rate-grade scale-factor accuracy 0.1-1 % of the grade table in A. Norouzpour-Shirazi, "
            "'Interface circuits and systems for inertial sensors', IEEE Sensors 2013 tutorial, read as a "
            "1 sigma up to 1 % (the default 1000 ppm is its lower end, docs/physics.md 5.1)",
            label="turn-on scale-factor error (1 sigma)",
        ),
        Parameter(
            field="ambient_spread_c",
            range=FieldRange(0.0, 3.0, "degC"),
            scale="linear",
            source="STATED ASSUMPTION: run-to-run 1-sigma of the die temperature after the paper's 20-30 min "
            "warm-up, from a temperature-controlled table (0) to a lab without control (3 degC; the default "
            "0.5 degC)",
            label="run-to-run die temperature (1 sigma)",
        ),
    ),
    fixed=(
        Fixed(field="variant", source="'identified': the open-loop sense chain with C_f identified from raw K_n "
              "15.71 % on the nominal chain (identify.IDENTIFIED, 1.866 fF; CALIBRATED)"),
        Fixed(field="readout.nominal.carrier", source="STATED (SenseChain: 1 V pick-off carrier)"),
        Fixed(field="readout.nominal.sense_area", source="the default resonator's electrodes "
              "(MemsResonator: 1e-8 m^2)"),
        Fixed(field="readout.gap_spread", source="mems_readout.TOLERANCE_SOURCES['gap_spread'] (STATED)"),
        Fixed(field="readout.feedback_capacitance_spread",
              source="mems_readout.TOLERANCE_SOURCES['feedback_capacitance_spread'] (STATED)"),
        Fixed(field="readout.rail_spread", source="mems_readout.TOLERANCE_SOURCES['rail_spread'] (STATED)"),
        Fixed(field="readout.k3_spread", source="mems_readout.TOLERANCE_SOURCES['k3_spread'] (STATED)"),
        Fixed(field="gyro.nominal.mode_split", source="STATED (MemsResonator: +500 Hz, docs/physics.md 5.1)"),
        Fixed(field="gyro.nominal.drive_amplitude", source="STATED (MemsResonator: 5 um, docs/physics.md 5.1)"),
        Fixed(field="gyro.nominal.bias_instability", source="the ADXRS646 data sheet's 12 deg/h bias drift read "
              "as the ADEV floor (MemsResonator.NOISE_FIGURES)"),
        Fixed(field="gyro.nominal.bias_repeatability", source="0.1 deg/s, inside the rate-grade range "
              "(Norouzpour-Shirazi 2013; docs/physics.md 5.1); a turn-on bias is linear and leaves K_n alone"),
        Fixed(field="ambient_c", source="STATED: the units are factory-trimmed at 25 degC and run there"),
    ),
)


def _breakpoint(side: str, sign: float) -> Constraint:
    target = sign * _PAPER_BREAKPOINT_DPS
    tol = BREAKPOINT_TOLERANCE_DPS
    return Constraint(
        id=f"001.breakpoint_{side}",
        fact=f"the heuristic breakpoint search splits the {side} rates at {target:+.0f} deg/s (the median over "
        f"the point's units of |breakpoint - ({target:+.0f})| below {tol:.0f} deg/s, a quarter table step, so "
        "exactly that table rate; a unit that does not split the side gives no value)",
        source="Table 2",
        quantity=f"breakpoint_{side}_miss_dps",
        comparator=below(tol),
    )


#: the paper's device facts as constraints: its device claims' quantities and bands, and the breakpoints
MAP_CONSTRAINTS: tuple[Constraint, ...] = (
    *(
        Constraint(id=c.id, fact=c.statement, source=c.where, quantity=c.quantity, comparator=c.comparator)
        for c in CLAIMS
        if c.role == "device"
    ),
    _breakpoint("negative", -1.0),
    _breakpoint("positive", 1.0),
)

#: the method (and extension) claims, judged where the unit shows the effect
MAP_CLAIMS = tuple(c for c in CLAIMS if c.precondition is SHOWS_THE_EFFECT)


@dataclass(frozen=True, slots=True, kw_only=True)
class BreakpointScan:
    """Where the heuristic splits the noise-free table of each point's nominal unit.

    Attributes
    ----------
    points : int
        Design points scanned.
    splits : dict
        ``"(negative, positive)"`` [deg/s] (``None`` where a side did not split) -> points.
    at_1800 : int
        Points split at both -1800 and +1800 deg/s.
    one_side_1800 : int
        Points split at exactly one of -1800 and +1800 deg/s.
    k_n_facts : int
        Points whose noise-free raw K_n and low-rate K_n satisfy the paper's facts
        (:data:`MAP_CONSTRAINTS`' bands).
    k_n_facts_splits : dict
        The splits of those points, as ``splits``.
    """

    points: int
    splits: dict[str, int]
    at_1800: int
    one_side_1800: int
    k_n_facts: int
    k_n_facts_splits: dict[str, int]


def noise_free_table(config: Config) -> np.ndarray:
    """The noise-free Table 1 [deg/s] of ``config``'s nominal unit on its table rates.

    The point's nominal resonator (no unit-to-unit spread, so no quadrature) read out open loop
    through its nominal chain (the identified C_f), factory-trimmed at T0, at T0: the static
    output of :func:`gyrobench.sim.mems_resonator.static_rate_output` (B = R F_ext through the chain), as
    :mod:`.identify` solves C_f on. Noise, turn-on errors and the output word are left out.

    Parameters
    ----------
    config : Config
        An open-loop variant (``"identified"`` or ``"readout_design"``).

    Returns
    -------
    ndarray
        The output at each of ``config.rates_dps`` [deg/s].
    """
    from gyrobench.base import units
    from gyrobench.sim import mems_resonator as mr

    from .device import device_spec
    from .identify import nominal_open_loop_unit

    spec = device_spec(config)
    if spec.chain is None:
        raise ValueError(f"noise_free_table needs an open-loop variant (identified, readout_design); "
                         f"got {config.variant!r}")
    unit = nominal_open_loop_unit(spec.chain.nominal, spec.nominal)
    rates = np.asarray(config.rates_dps, dtype=float)
    return np.asarray(units.to_deg_per_s(mr.static_rate_output(unit, units.deg_per_s(rates))), dtype=float)


def noise_free_breakpoints(points: int = 1024, seed: int = DESIGN_SEED + 1) -> BreakpointScan:
    """Where the heuristic splits the noise-free tables of ``points`` design points of :data:`FAMILY`.

    :func:`gyrobench.analysis.scale_factor.breakpoint_search` on :func:`noise_free_table`.

    Parameters
    ----------
    points : int
        Design points (:func:`gyrobench.scenarios.maps.family.design`; a power of two: Sobol).
    seed : int
        The design's seed (default: not the map's, so the scan is a second, larger sample).

    Returns
    -------
    BreakpointScan
        The splits, how many sit at +-1800 deg/s, and the splits of the points whose noise-free
        raw and low-rate K_n satisfy the paper's facts.
    """
    from gyrobench.analysis.scale_factor import breakpoint_search, fit_scale_factor, range_nonlinearity
    from gyrobench.scenarios.maps.family import design

    from .identify import LOW_RATE_LIMIT_DPS

    facts = {c.quantity: c for c in MAP_CONSTRAINTS}
    splits: Counter[str] = Counter()
    fitting: Counter[str] = Counter()
    both = one = 0
    for values in design(FAMILY, points, seed).values:
        config = FAMILY.config(values)
        rates = np.asarray(config.rates_dps, dtype=float)
        table = noise_free_table(config)
        found = breakpoint_search(rates, table)
        key = f"({found.negative}, {found.positive})"
        splits[key] += 1
        hits = (found.negative == -_PAPER_BREAKPOINT_DPS) + (found.positive == _PAPER_BREAKPOINT_DPS)
        both += hits == 2
        one += hits == 1
        raw = 100.0 * fit_scale_factor(rates, table).nonlinearity
        low = range_nonlinearity(rates, table, -LOW_RATE_LIMIT_DPS, LOW_RATE_LIMIT_DPS)
        if facts["raw_kn_pct"].holds(raw) and facts["low_rate_kn"].holds(low):
            fitting[key] += 1
    return BreakpointScan(
        points=points, splits=dict(splits.most_common()), at_1800=int(both), one_side_1800=int(one),
        k_n_facts=sum(fitting.values()), k_n_facts_splits=dict(fitting.most_common()),
    )
