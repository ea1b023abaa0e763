"""Paper 001: a +-3600 deg/s MEMS gyro on a rate table, scale-factor nonlinearity, compensation.

Scenario ``mems_scale_factor``. The device (:mod:`gyrobench.sim.mems_resonator`): a lumped
2-DOF Coriolis vibratory gyro; each unit (:func:`experiment`, one seed) is one unit drawn from a
:class:`~gyrobench.sim.mems_population.MemsResonatorSpec` population, with its own power-ons
(turn-on bias and scale-factor error, ambient temperature, noise). The read-out
(``Config.variant``, :mod:`.device`):

* ``"identified"`` (default): OPEN LOOP through the physical sense chain of
  :mod:`gyrobench.sim.mems_readout` (sense-electrode softening, the pick-off's 1/(g - y), the
  charge amplifier's rail, the output word; quadrature and manufacturing tolerances per unit,
  ``Config.readout``), its feedback capacitor identified from the paper's raw K_n 15.71 %
  (``identify``; CALIBRATED, the one number set). The control population
  (:func:`control_config`) is the same units under ``"design"`` (linear scale factor).
* ``"readout_design"``: the same chain at its design values (nothing from the paper).
* ``"design"``: FORCE REBALANCE as given, the plausible +-3600 deg/s design (v_max = 0.7 V,
  authority about 1.1-1.4x the range): linear through the table, raw K_n the noise of the
  dwell means (ppm).
* ``"calibrated"``: force rebalance with the DAC full scale v_max set to
  :data:`CALIBRATED_V_MAX_V` (CALIBRATED: median noise-free raw K_n of units 0-19 = 15.71 %);
  every claim calibrated (:func:`claims_for`).
* ``"rapp"``: the rebalanced units through a fitted amplifier (Rapp) curve, PHENOMENOLOGICAL
  (labelled; no read-out behind it).

Modules: ``config`` (the protocol and the paper's printed values), ``device`` (the unit
population, noise-free static output, the v_max calibration), ``rate_table`` (the runs,
records, memory estimate), ``results`` (the typed unit result), ``experiment`` (one unit,
``compensation_task`` for ``gyrobench bench``), ``claims`` (claims and deviations as data),
``effects`` (re-measuring the deviations' effects), ``report``. Methods a user applies to
real rate-table data live in :mod:`gyrobench.analysis.scale_factor` and
:mod:`gyrobench.analysis.compensation`.
"""

from __future__ import annotations

from gyrobench.scenarios.papers import Paper

NAME = "mems_scale_factor"
TITLE = "High-range MEMS gyro: scale-factor nonlinearity and heuristic piecewise compensation"
PAPER = "001"

#: the paper itself: gyrobench list and the reports read it with ast (nothing is imported)
SOURCE = Paper(
    key="001",
    authors="Du Renjie, Su Zhong, Liu Ning, Li Ling",
    authors_zh="杜仁杰, 苏中, 刘宁, 李羚",
    affiliation="Beijing Information Science and Technology University, "
    "Beijing Key Laboratory of High Dynamic Navigation Technology",
    topic="high-range MEMS gyro: scale-factor nonlinearity and heuristic piecewise "
    "polynomial regression",
    title_en="Research on the compensation of the scale-factor nonlinearity error of MEMS gyros",
    title_zh="MEMS陀螺标度因数非线性误差补偿方法研究",
    journal=None,
    year=None,
    source_note="the seed text has no title; the title is the one a public abstract "
    "listing gives for this abstract (15.71 % -> 0.14 %, 0.247 ms); journal and year not found",
)

from .bench import BENCH_SCORES, mems_piecewise  # noqa: E402
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

__all__ = [
    "BENCH_SCORES",
    "SOURCE",
    "CLAIMS",
    "DEVIATIONS",
    "NAME",
    "PAPER",
    "TITLE",
    "VARIANTS",
    "Config",
    "UnitResult",
    "claims_for",
    "compensation_task",
    "control_config",
    "experiment",
    "memory_estimate",
    "report",
    "simulate",
    "variant_config",
]
