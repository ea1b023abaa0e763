"""Paper 001: a +-3600 deg/s MEMS gyro on a rate table, scale-factor nonlinearity, compensation.

Scenario ``mems_scale_factor``. The device (:mod:`gyrobench.sim.mems_resonator`): a lumped
2-DOF Coriolis vibratory gyro with force rebalance whose high-range knee is the rebalance
DAC's authority, Omega_max = sqrt(F_max^2 - F_q^2) / (2 m w X0), flat beyond it
(docs/physics.md 5.1). Each unit (:func:`experiment`, one seed) is one unit drawn from a
:class:`~gyrobench.sim.mems_resonator.MemsResonatorSpec` population, with its own power-ons
(turn-on bias and scale-factor error, ambient temperature, noise).

Three devices (``Config.variant``):

* ``"identified"`` (default): the design below read out through a smooth front-end
  compression (:mod:`gyrobench.sim.mems_nonlinear`, Rapp) whose two parameters are
  identified from what the paper reports about its prototype (``identify``: raw K_n 15.71 %,
  low-rate K_n 1e-3; CALIBRATED). The control population (:func:`control_config`) is the
  same units under ``"design"`` (linear scale factor).
* ``"design"``: the spec as given, by default the plausible +-3600 deg/s design
  (v_max = 0.7 V, authority about 1.1-1.4x the range). The default because it is
  a plausible design not solved for the paper's number: nothing in it is set from paper
  001, so every claim is emergent. Its knee lies
  beyond the table, so its raw K_n is the noise of the dwell means (ppm), not the paper's 15.71 %: a finding, reported.
* ``"calibrated"``: the same population with the rebalance DAC full scale v_max set to
  :data:`CALIBRATED_V_MAX_V`, CALIBRATED (:func:`calibrated_v_max`) so that the median
  noise-free raw K_n of units 0-19 is the paper's 15.71 %. Under it every claim is
  calibrated (:func:`claims_for`); the knee then lies at about 2300-3200 deg/s.

Modules: ``config`` (the protocol and the paper's printed values), ``device`` (the unit
population, noise-free static output, the v_max calibration), ``rate_table`` (the runs,
records, memory estimate), ``results`` (the typed unit result), ``experiment`` (one unit,
``compensation_task`` for ``gyrobench bench``), ``claims`` (claims and deviations as data),
``effects`` (re-measuring the deviations' effects), ``report``. Methods a user applies to
real rate-table data live in :mod:`gyrobench.analysis.scale_factor` and
:mod:`gyrobench.analysis.compensation`.
"""

from __future__ import annotations

NAME = "mems_scale_factor"
TITLE = "High-range MEMS gyro: scale-factor nonlinearity and heuristic piecewise compensation"
PAPER = "001"

from .claims import CALIBRATED_INPUT, CLAIMS, DEVIATIONS, IDENTIFIED_INPUT, claims_for  # noqa: E402
from .config import (  # noqa: E402
    CALIBRATED_V_MAX_V,
    METHOD_LABELS,
    PAPER_KN_PCT,
    PAPER_ORDER,
    PAPER_RAW_KN,
    PAPER_TIME_MS,
    VARIANTS,
    Config,
)
from .device import calibrated_v_max, device_spec, draw_unit, rate_transfer, static_output  # noqa: E402
from .effects import control_config, deviation_effects, variant_config  # noqa: E402
from .experiment import compensation_task, experiment, nonlinearity_scorer  # noqa: E402
from .identify import IDENTIFIED, Identification, identify_p001_device  # noqa: E402
from .rate_table import memory_estimate, rate_means, simulate  # noqa: E402
from .report import report  # noqa: E402
from .results import UnitResult  # noqa: E402

#: the paper contract (gyrobench.scenarios.papers.contract); the other names imported here are
#: public in their modules
__all__ = [
    "NAME",
    "TITLE",
    "PAPER",
    "Config",
    "CLAIMS",
    "DEVIATIONS",
    "UnitResult",
    "VARIANTS",
    "experiment",
    "claims_for",
    "report",
    "simulate",
    "memory_estimate",
    "compensation_task",
    "control_config",
    "variant_config",
]
