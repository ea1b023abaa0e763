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
(``select_rbf``); no validation run influences the choice.

Also computed per unit: identification run 2 scored (the paper's "validation sample");
streaming compensation equal to batch; the exported a1/a2 network evaluated in single
precision as on the paper's TMS320F28335 (``deployment_float32``); the Table 1 /
figure 2 point-heating T x dT term; peak drift of the four winding patterns.

Claims, control and identification (issues 24, 27)
--------------------------------------------------
The drift level (0.15 deg/h per 10 degC) is a ``device`` claim: the one calibrated
parameter, the lead-asymmetry spread, is identified from it (:mod:`.identify`, frozen in
``IDENTIFIED``). The Table 1 T x dT term is a device claim from material data, reported
against the heated length and rate the paper leaves out and split about 0 degC (its eq. 9;
the coil's drift itself does not depend on the reference, ``sim.coil2d``). The validation
claims are ``method`` claims with a per-unit precondition (validation-1 drift above 3x the
noise) and a control population (``control_config``: no thermal program). Every measurable
deviation names a variant (``variant_config``), among them ERR on the logged rate (no 100-s
averaging) and the central-difference dT/dt.

Package layout (the paper contract, ``gyrobench.scenarios.papers.contract``)
---------------------------------------------------------------------------
``config``: :class:`Config`, the paper's protocol as defaults. ``runs``: the chamber runs
simulated (:func:`simulate`), prepared and handed to the bench
(:func:`compensation_task`). ``pipeline``: training set, RBF selection and fit, ERR,
float32 and streaming checks. ``coil``: the point-heating and winding studies.
``experiment``: one unit -> :class:`UnitResult` (``results``: the typed result
dataclasses). ``claims``: :data:`CLAIMS`, :data:`DEVIATIONS`, :func:`claims_for`.
``report``: tables and figures from the results only. The methods a user applies to
real data live in ``gyrobench.analysis``: ``compensation.rbf`` (the newrb network),
``compensation.rbf_selection`` (:func:`select_rbf`) and ``deployment``
(:func:`deployment_float32`).
"""

from __future__ import annotations

from gyrobench.analysis.compensation.rbf_selection import RBFSelection, select_rbf
from gyrobench.analysis.deployment import deployment_float32
from gyrobench.scenarios.papers import Paper

from .bench import BENCH_SCORES, IfogSegmentRBF
from .claims import CLAIMS, DEVIATIONS, claims_for
from .coil import point_heating, winding_comparison
from .config import FEATURES_IMPROVED, FEATURES_TRADITIONAL, Config
from .experiment import experiment
from .identify import IDENTIFIED, identify_lead_asymmetry
from .pipeline import TrainingSet, err, fit_models, heat_cool_average, training_set
from .report import report
from .results import UnitResult
from .runs import (
    IDENTIFICATION_SEGMENTS,
    Run,
    compensation_task,
    identification_segments,
    memory_estimate,
    prepare,
    record_mask,
    score_mse,
    simulate,
)
from .variants import VARIANTS, control_config, variant_config

# literals: the registry reads them with ast (config.NAME, TITLE, PAPER are the same)
NAME = "ifog_thermal"
TITLE = "IFOG thermal drift from Shupe coil physics; RBF compensation with a T x dT input"
PAPER = "003"

#: the paper itself: gyrobench list and the reports read it with ast (nothing is imported)
SOURCE = Paper(
    key="003",
    authors="Cheng Jianhua, Qi Bing, Zhao Lin",
    authors_zh="程建华, 齐兵, 赵琳",
    affiliation="College of Automation, Harbin Engineering University, Harbin",
    topic="IFOG temperature drift: RBF network with a T x dT product term, real-time "
    "compensation on a DSP",
    title_en="Design of compensation system for temperature drift errors of "
    "interferometric fiber optical gyroscopes",
    title_zh="干涉式光纤陀螺仪温漂误差补偿系统的设计",
    journal="Systems Engineering and Electronics (系统工程与电子技术)",
    year=2016,
    volume_issue="38(6)",
    doi="10.3969/j.issn.1001-506X.2016.06.25",
    source_note="journal from the ISSN 1001-506X in the DOI the text prints; received "
    "2015-04-20, online 2016-02-15",
)

__all__ = [
    "IfogSegmentRBF",
    "BENCH_SCORES",
    "SOURCE",
    "CLAIMS",
    "DEVIATIONS",
    "FEATURES_IMPROVED",
    "FEATURES_TRADITIONAL",
    "IDENTIFIED",
    "IDENTIFICATION_SEGMENTS",
    "NAME",
    "PAPER",
    "RBFSelection",
    "Run",
    "TITLE",
    "TrainingSet",
    "UnitResult",
    "VARIANTS",
    "Config",
    "claims_for",
    "compensation_task",
    "control_config",
    "deployment_float32",
    "err",
    "experiment",
    "fit_models",
    "heat_cool_average",
    "identification_segments",
    "identify_lead_asymmetry",
    "memory_estimate",
    "point_heating",
    "prepare",
    "record_mask",
    "report",
    "score_mse",
    "select_rbf",
    "simulate",
    "training_set",
    "variant_config",
    "winding_comparison",
]
