"""Paper 004: variable-temperature bias of a dithered RLG compensated by stepwise regression.

Setup (paper 004, Chen, Liu, Chen): the gyro is switched on, then the chamber runs
between -40 and +65 degC at 1 degC per 3 min; the output is averaged over 100 s
(Chinese military standard practice) and the variable-temperature bias stability is
the standard deviation of these 100-s means. Two temperature sensors are logged: T1
on the housing, T2 on the cavity. Eleven candidate regressors
(:mod:`gyrobench.analysis.regressors`) enter a stepwise regression (MATLAB
``stepwise``: p-enter 0.05, p-remove 0.10); the paper keeps x1, x3, x5, x7, x11
(adjusted R^2 ~0.97, Table 1) and improves the variable-temperature bias stability of
three gyros by about 65 % ("about 2 times" in its conclusion).

One unit = one gyro. Each seed draws one gyro from
:class:`gyrobench.sim.rlg_cavity.CavityRLGSpec` (backscatter amplitudes and phases, the
ZERODUR block's CTE, the PLC's piezo travel, the thermal network's mounts, the discharge's
regulator mismatch, sensor offsets) and runs the chamber program twice (two turn-ons: the
PLC acquires a mode, the leg-current imbalance and gas heating are set anew, new noise). The
gyro's stepwise model is fitted on its first run and scored on its second, which it never
saw. The paper's "three gyros" statements are therefore per-unit statements judged over the
population of units (``gyrobench reproduce --units N``); the first three units stand in for
the paper's gyros 1-3 in the detail tables and figures. The simulated output is pulse counts
at ``fs_hz`` from the statistical mode of :mod:`gyrobench.sim.rlg_cavity`.

Every method claim is emergent: the thermal bias comes from mechanisms (Langmuir flow of the
two discharge legs at their own gas temperatures, the current regulators' drift, the
backscatter null shift whose phases follow the block's expansion and the PLC, mode hops),
evaluated on the nodes of a housing/block thermal network that T1 and T2 read; no term is
written in the form of the paper's regressors. One size is set from a paper-004 number: the
null-shift ratio eta, identified (:mod:`.identify`) so that the thermal bias explains the
paper's 0.97 of the 100-s means' variance on the median unit; the device claims it sizes
(adjusted R^2, the large thermal effect) are calibrated. Method claims are judged on units
that show the thermal effect (:data:`.claims.THERMAL_PRECONDITION`) and on the control
(:func:`.config.control_config`, constant chamber temperature).
Each unit is also run with a PLC of unlimited travel (same draws, no mode hops) to measure
what the hops do to the fit and to the held-out improvement. The in-sample adjusted R^2 and
bias-stability ratio are tied by arithmetic: for least squares with an intercept,
``R^2 = 1 - (after_fit / before_fit)^2`` exactly (see :func:`.experiment.experiment`).

Not in the paper: the form of x9-x11 (defined in :mod:`gyrobench.analysis.regressors`),
the soaks of the chamber program, the derivative estimator, the thermal time
constants and the noise budget (see :data:`.claims.DEVIATIONS` and :class:`.config.Config`). The
paper's Table 1 and Table 2 numbers did not survive the text extraction.

Package layout (the :class:`gyrobench.scenarios.papers.contract.PaperScenario` contract):
:mod:`.config` (the protocol), :mod:`.simulation` (gyros, chamber runs, 100-s blocks),
:mod:`.experiment` (one unit -> :class:`.results.UnitResult`; the bench's
``compensation_task``), :mod:`.claims` (claims and deviations as data), :mod:`.report`
and :mod:`.figures` (from the typed results only). The methods a user applies to real
temperature logs live in :mod:`gyrobench.analysis.thermal_regression`.
"""

from gyrobench.scenarios.papers import Paper

NAME = "rlg_thermal"
TITLE = (
    "RLG variable-temperature bias (-40..+65 degC): stepwise regression on housing and cavity "
    "temperatures"
)
PAPER = "004"

#: the paper itself: gyrobench list and the reports read it with ast (nothing is imported)
SOURCE = Paper(
    key="004",
    authors="Chen Jian, Liu Liying, Chen Junjun",
    authors_zh="陈剑, 刘黎映, 陈军军",
    affiliation="Naval Equipment Department pricing centre; Beijing Institute of "
    "Automatic Control Equipment",
    topic="dithered RLG variable-temperature bias (-40..+65 degC): stepwise multiple "
    "linear regression on housing and cavity temperatures",
    title_en=None,
    title_zh=None,
    journal=None,
    year=None,
    source_note="the seed text starts at the author line",
)

# the constants above come first: the modules below import them from this package
from .bench import BENCH_SCORES  # noqa: E402
from .claims import (  # noqa: E402
    CLAIMS,
    DEVIATIONS,
    PAPER_ADJ_R2,
    PAPER_DROPPED,
    PAPER_IMPROVEMENT_PCT,
    PAPER_SELECTED,
    THERMAL_PRECONDITION,
    claims_for,
)
from .config import VARIANTS, Config, control_config, variant_config  # noqa: E402
from .experiment import bias_stability_scores, compensation_task, experiment  # noqa: E402
from .report import report  # noqa: E402
from .results import UnitResult  # noqa: E402
from .simulation import memory_estimate, simulate  # noqa: E402

__all__ = [
    "BENCH_SCORES",
    "SOURCE",
    "NAME",
    "TITLE",
    "PAPER",
    "CLAIMS",
    "DEVIATIONS",
    "PAPER_ADJ_R2",
    "PAPER_DROPPED",
    "PAPER_IMPROVEMENT_PCT",
    "PAPER_SELECTED",
    "THERMAL_PRECONDITION",
    "Config",
    "VARIANTS",
    "control_config",
    "variant_config",
    "UnitResult",
    "bias_stability_scores",
    "claims_for",
    "compensation_task",
    "experiment",
    "memory_estimate",
    "report",
    "simulate",
]
