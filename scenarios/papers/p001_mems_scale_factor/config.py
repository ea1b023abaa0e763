"""Paper 001's rate-table test and methods as a frozen :class:`Config`, and the paper's printed values.

Defaults are the paper's protocol (section 3): 21 table rates, +3600 -> -3600 deg/s in
360 deg/s steps, 200 Hz output averaged over 60 s of each settled dwell, several runs; the
methods of section 4 (piecewise 9-1-9 with Hermite joins, two-stage 9th-order polynomial,
Bayes-regularized BP network with 10 hidden units). Field units at this edge, in the field
names; the device population is SI (:class:`gyrobench.sim.mems_population.MemsResonatorSpec`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from gyrobench.base.ranges import Constraint, FieldChoice, FieldRange, validate
from gyrobench.sim.mems_population import MemsResonatorSpec
from gyrobench.sim.mems_readout import SenseChainSpec

__all__ = [
    "CALIBRATED_V_MAX_V",
    "Config",
    "METHOD_LABELS",
    "PAPER_KN_PCT",
    "PAPER_ORDER",
    "PAPER_RAW_KN",
    "PAPER_TIME_MS",
    "OPEN_LOOP_VARIANTS",
    "VARIANTS",
    "default_rates",
]

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
#: the devices Config.variant selects ("identified": the paper's prototype, identify.py;
#: "rapp": the phenomenological fitted curve, labelled)
VARIANTS = ("identified", "design", "calibrated", "readout_design", "rapp")
#: the variants read out open loop through the physical sense chain (device.py)
OPEN_LOOP_VARIANTS = ("identified", "readout_design")
#: rebalance DAC full scale v_max [V] of the "calibrated" variant: CALIBRATED by
#: :func:`~gyrobench.scenarios.papers.p001_mems_scale_factor.device.calibrated_v_max`
#: (default spec, units 0-19) so that the median noise-free raw K_n on the paper's 21 rates
#: is 15.71 %. The design value is 0.7 V.
CALIBRATED_V_MAX_V = 0.44017


def default_rates() -> tuple[float, ...]:
    """The paper's 21 table rates, +3600 -> -3600 deg/s in 360 deg/s steps [deg/s].

    Returns
    -------
    tuple of float
        The rates [deg/s].
    """
    return tuple(float(r) for r in np.arange(3600.0, -3600.0 - 1.0, -360.0))


@dataclass(frozen=True, slots=True, kw_only=True)
class Config:
    """The paper's rate-table test and methods (field units at this edge).

    Parameters
    ----------
    gyro : MemsResonatorSpec
        The population the units are drawn from (SI; default the plausible design).
    readout : SenseChainSpec
        The open-loop sense chains the units are read out through (SI; the device family of
        the open-loop variants: nominal chain, manufacturing tolerances and each field's range,
        :mod:`gyrobench.sim.mems_readout`).
    variant : {"identified", "design", "calibrated", "readout_design", "rapp"}
        "identified" (default): ``gyro`` read out open loop through ``readout`` with the
        feedback capacitor identified from the paper's raw K_n (``identify.IDENTIFIED``,
        CALIBRATED); "readout_design": the same chain at its design values (nothing from the
        paper); "design": ``gyro`` as given (force rebalance, linear through the table);
        "calibrated": ``gyro`` with its nominal rebalance DAC full scale set to
        :data:`CALIBRATED_V_MAX_V` (CALIBRATED to the paper's 15.71 %); "rapp": the rebalanced
        ``gyro`` through a fitted amplifier curve (PHENOMENOLOGICAL, ``identify.RAPP_IDENTIFIED``).
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
    join : {"overlap", "centred"}
        The piecewise fit's Hermite join (:class:`~gyrobench.analysis.compensation.polynomial.
        PiecewisePolynomial`): "overlap" (the paper's: over the overlap of the two fits' data at
        the breakpoint rate) or "centred" (``join_width`` of the output span centred on it).
    join_width : float
        Width of a "centred" join as a fraction of the output span.
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
    readout: SenseChainSpec = field(default_factory=SenseChainSpec)
    variant: str = "identified"
    rates_dps: tuple[float, ...] = field(default_factory=default_rates)
    average_s: float = 60.0
    settle_s: float = 0.5
    fs_hz: float = 200.0
    ambient_c: float = 25.0
    ambient_spread_c: float = 0.5
    n_fit_runs: int = 3
    n_heldout_runs: int = 1
    orders: tuple[int, int, int] = (9, 1, 9)
    join: str = "overlap"
    join_width: float = 0.05
    piecewise_alpha: float = 1e-6
    poly_degree: int = 9
    hidden_units: int = 10
    mlp_epochs: int = 1000
    timing_repeats: int = 50
    dense_step_dps: float = 10.0

    #: documented ranges; the device population states its own in
    #: :class:`~gyrobench.sim.mems_population.MemsResonatorSpec` (SI)
    RANGES: ClassVar[Mapping[str, FieldRange | FieldChoice]] = {
        "rates_dps": FieldRange(-36000, 36000, "deg/s", "table rates; 10x the paper's +-3600 deg/s"),
        "average_s": FieldRange(0, 3.6e7, "s", "<= 1e4 h; the memory estimate refuses long runs", low_open=True),
        "settle_s": FieldRange(0, 3600, "s", "discarded settling part of a dwell"),
        "fs_hz": FieldRange(0, 1e5, "Hz", "output sample rate", low_open=True),
        "ambient_c": FieldRange(-55, 125, "degC", "die temperature, the military operating range"),
        "ambient_spread_c": FieldRange(0, 50, "degC", "run-to-run 1-sigma of the die temperature"),
        "n_fit_runs": FieldRange(1, 1000, "runs", "power-ons fitted on, per unit", integer=True),
        "n_heldout_runs": FieldRange(1, 1000, "runs", "power-ons scored only, per unit", integer=True),
        "orders": FieldRange(0, 20, "1", "piecewise polynomial orders", integer=True),
        "join_width": FieldRange(0, 0.5, "1", "Hermite join width / output span (__post_init__)", True, True),
        "piecewise_alpha": FieldRange(0, 1e6, "1", "curvature penalty on scaled units, >= 0"),
        "poly_degree": FieldRange(0, 20, "1", "degree of both polynomial stages (21 table points)", integer=True),
        "hidden_units": FieldRange(1, 1000, "units", "hidden units of the network", integer=True),
        "mlp_epochs": FieldRange(1, 1e6, "epochs", "trainbr epochs", integer=True),
        "timing_repeats": FieldRange(1, 1e5, "repeats", "repeats of the timing (median reported)", integer=True),
        "dense_step_dps": FieldRange(0, 7200, "deg/s", "step of the dense held-out sweep", low_open=True),
        "variant": FieldChoice(VARIANTS, "the device variant"),
        "join": FieldChoice(("overlap", "centred"), "the piecewise fit's Hermite join"),
    }

    #: the constraints across fields (:class:`~gyrobench.base.ranges.Constraint`)
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "len(rates_dps) >= 3",
            lambda c: len(c.rates_dps) >= 3,
            lambda c: f"rates_dps must hold at least 3 finite rates [deg/s]; got {c.rates_dps!r}",
        ),
        Constraint(
            "rates_dps strictly monotonic",
            lambda c: bool(np.all(np.diff(c.rates_dps) > 0) or np.all(np.diff(c.rates_dps) < 0)),
            lambda c: f"rates_dps must be strictly monotonic without duplicates [deg/s]; got {c.rates_dps!r}",
        ),
        Constraint(
            "average_s x fs_hz >= 1",
            lambda c: int(round(c.average_s * c.fs_hz)) >= 1,
            lambda c: f"average_s must cover at least one sample at fs_hz; got {c.average_s!r} s at "
            f"{c.fs_hz!r} Hz",
        ),
        Constraint(
            "len(orders) == 3",
            lambda c: len(c.orders) == 3,
            lambda c: f"orders must be three integers >= 0; got {c.orders!r}",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above
