"""Paper 004's claims and protocol deviations, as data over :class:`~.results.UnitResult`.

Roles: the large thermal effect, Multiple R and adjusted R^2 are ``device`` claims (the
large effect and adjusted R^2 sized by the identification, :mod:`.identify`, and so
``calibrated``, as they say); selection, RMSE, significance F and improvement are ``method`` claims judged where
the unit shows the thermal effect (:data:`THERMAL_PRECONDITION`); the mode-hop questions are
``extension`` claims (ours). The thermal bias comes from mechanisms (Langmuir flow, regulator
drift, backscatter null shift following the block and the PLC, mode hops) on a housing/block
thermal network; no term is written in the form of the paper's regressors.
Each claim reads one key of the unit's ``quantities`` (built by
:func:`.experiment.experiment`); the paper's "three gyros" statements are per-unit
statements judged over the population of units (the 65 % also over triples of units,
:mod:`.triples`).
"""

from __future__ import annotations

from typing import Any

from gyrobench.scenarios.claims import (
    Claim,
    Comparator,
    Deviation,
    Precondition,
    above,
    below,
    in_range,
    is_true,
    within_factor,
)

from . import PAPER
from .config import Config

__all__ = [
    "CLAIMS",
    "THERMAL_PRECONDITION",
    "DEVIATIONS",
    "PAPER_ADJ_R2",
    "PAPER_DROPPED",
    "PAPER_IMPROVEMENT_PCT",
    "PAPER_SELECTED",
    "claims_for",
]

#: the paper's selected terms, the terms it reports as not significant, and its figures
PAPER_SELECTED = ("x1", "x3", "x5", "x7", "x11")
PAPER_DROPPED = ("x2", "x4", "x6", "x8", "x9", "x10")
PAPER_ADJ_R2 = 0.97
PAPER_IMPROVEMENT_PCT = 65.0

_IDENTIFIED_ETA = (
    "Config.dissipative (backscatter null-shift ratio eta), identified so that the median "
    "identification unit's thermal bias explains 97 % of its 100-s means' variance (identify.py)"
)

#: the method claims' precondition: the unit's temperature field has a large effect on its output
TRUTH_R2_MIN = 0.9
THERMAL_PRECONDITION = Precondition(
    text="the true thermal bias explains at least half the variance of the fitting run's 100-s means "
    "(var(thermal) / var(output - true rate)), and the eleven candidate regressors, regressed on that true "
    f"thermal bias, explain more than {TRUTH_R2_MIN:g} of it (R^2)",
    quantity="thermal_share",
    comparator=above(0.5),
    also=(
        Precondition(
            text=f"the candidates regressed on the true thermal bias: R^2 > {TRUTH_R2_MIN:g}",
            quantity="truth_r2",
            comparator=above(TRUTH_R2_MIN),
        ),
    ),
)


def _claim(cid: str, where: str, statement: str, quantity: str, comparator: Comparator, **kw: Any) -> Claim:
    return Claim(
        id=f"004.{cid}",
        paper=PAPER,
        where=where,
        statement=statement,
        quantity=quantity,
        comparator=comparator,
        **kw,
    )


CLAIMS: tuple[Claim, ...] = (
    _claim(
        "thermal_effect_large",
        "Sec. 1-2 (the temperature field has a large effect on the output)",
        "The temperature field has a large effect on the gyro's output over -40..+65 degC (per "
        "unit: the true thermal bias explains more than half the variance of the fitting run's "
        "100-s means).",
        "thermal_share",
        above(0.5),
        kind="calibrated",
        calibrated_input=_IDENTIFIED_ETA,
        role="device",
    ),
    _claim(
        "keeps_x1_x3_x5_x7_x11",
        "Sec. 3 (stepwise), Table 1",
        "Stepwise regression (MATLAB stepwise over x1..x11) keeps x1, x3, x5, x7 and x11 (per "
        "unit: all five selected).",
        "keeps_paper_terms",
        is_true(),
        kind="emergent",
        role="method",
        precondition=THERMAL_PRECONDITION,
    ),
    _claim(
        "drops_x2_x4_x6_x8_x9_x10",
        "Sec. 3 (stepwise)",
        "x2, x4, x6, x8, x9 and x10 are not significant and are left out (per unit: none of them "
        "selected).",
        "drops_other_terms",
        is_true(),
        kind="emergent",
        role="method",
        precondition=THERMAL_PRECONDITION,
    ),
    _claim(
        "selection_stability",
        "Sec. 3, Eq. (3) applied to three gyros",
        "One term set, x1, x3, x5, x7, x11, serves every gyro (selection stability: the pass rate "
        "is the fraction of units whose stepwise selection is exactly the paper's set).",
        "selects_paper_set",
        is_true(),
        kind="emergent",
        role="method",
        precondition=THERMAL_PRECONDITION,
    ),
    _claim(
        "bias_depends_on_t_rate_gradient",
        "Sec. 3 and conclusion",
        "The output bias depends on the internal temperature, the temperature rate and the "
        "temperature gradient (per unit: the selection carries all three kinds of term).",
        "temperature_rate_gradient",
        is_true(),
        kind="emergent",
        role="method",
        precondition=THERMAL_PRECONDITION,
    ),
    _claim(
        "multiple_r_high",
        "Table 1 (text)",
        "Multiple R shows a high positive correlation between x1, x3, x5, x7, x11 and the bias "
        "(taken as Multiple R > 0.8, the usual threshold of 'high'; R^2 = Multiple R^2 is not a "
        "separate claim).",
        "multiple_r",
        above(0.8),
        kind="emergent",
        role="device",
    ),
    _claim(
        "adj_r2_0_97",
        "Table 1 (text)",
        "Adjusted R^2 ~0.97: the regressors explain 97 % of the bias (compared as 1 - adjusted "
        "R^2 within a factor 2 of 0.03, since a factor 2 on a number near 1 means nothing).",
        "one_minus_adj_r2",
        within_factor(1.0 - PAPER_ADJ_R2, 2.0),
        paper_value=1.0 - PAPER_ADJ_R2,
        kind="calibrated",
        calibrated_input=_IDENTIFIED_ETA,
        role="device",
    ),
    _claim(
        "rmse_below_0_05",
        "Table 1 (text)",
        "The RMSE is below 0.05 (the paper's words: 'less than the significance level 0.05'; read "
        "as 0.05 deg/h on the 100-s means).",
        "rmse_deg_h",
        below(0.05),
        paper_value=0.05,
        unit="deg/h",
        kind="emergent",
        role="method",
        precondition=THERMAL_PRECONDITION,
    ),
    _claim(
        "significance_f",
        "Table 1 (text)",
        "The regression is significant (significance F below the 0.05 level).",
        "significance_f",
        below(0.05),
        paper_value=0.05,
        kind="emergent",
        role="method",
        precondition=THERMAL_PRECONDITION,
    ),
    _claim(
        "improvement_65pct",
        "Sec. 4, Table 2, Fig. 4",
        "Compensation improves each gyro's variable-temperature bias stability by about 65 % "
        "(compared as the held-out before/after ratio within a factor 2 of 1/(1 - 0.65) = 2.86).",
        "heldout_ratio",
        within_factor(1.0 / (1.0 - PAPER_IMPROVEMENT_PCT / 100.0), 2.0),
        paper_value=1.0 / (1.0 - PAPER_IMPROVEMENT_PCT / 100.0),
        unit="x",
        kind="emergent",
        role="method",
        precondition=THERMAL_PRECONDITION,
    ),
    _claim(
        "improvement_about_2x",
        "Conclusion",
        "The model improves the variable-temperature bias stability 'by about 2 times' (held-out "
        "before/after ratio; the factor 2 is applied to the gain over no compensation, ratio - 1, "
        "so 1.5x to 3x: a factor 2 on the ratio itself would pass 1.0x, no improvement).",
        "heldout_ratio",
        in_range(1.5, 3.0),
        paper_value=2.0,
        unit="x",
        kind="emergent",
        role="method",
        precondition=THERMAL_PRECONDITION,
    ),
    _claim(
        "mode_hops_lower_adj_r2",
        "not in the paper (bench question): Sec. 3 fit under PLC mode hops",
        "Mode hops make the stepwise fit worse: per unit whose fitting run hops, 1 - adjusted "
        "R^2 with hops exceeds that of the same gyro and draws with a PLC of unlimited travel "
        "(ratio > 1). The paper does not mention mode hops.",
        "hop_adj_r2_cost",
        above(1.0),
        unit="x",
        kind="emergent",
        role="extension",
        precondition=THERMAL_PRECONDITION,
    ),
    _claim(
        "mode_hops_lower_improvement",
        "not in the paper (bench question): Sec. 4 improvement under PLC mode hops",
        "Mode hops cost held-out improvement: per unit whose runs hop, the held-out before/after "
        "ratio without hops (PLC of unlimited travel, same draws) over the ratio with hops "
        "exceeds 1. The paper does not mention mode hops.",
        "hop_ratio_cost",
        above(1.0),
        unit="x",
        kind="emergent",
        role="extension",
        precondition=THERMAL_PRECONDITION,
    ),
)


#: our departures from the paper's protocol; ``variant`` names the :func:`.config.variant_config`
#: that runs the paper's protocol (or the alternative reading), measured by ``reproduce --deviations``
DEVIATIONS: tuple[Deviation, ...] = (
    Deviation(
        paper=PAPER,
        what="gyro and the sizes of its thermal mechanisms",
        paper_says="three real dithered RLGs (type, lock-in, discharge and block data not given)",
        we_do="cavity-model gyros (sim.rlg_cavity): every mechanism size cited or a stated "
        "assumption, none set from a paper-004 number but the identified sizes of identify.py",
        reason="the thermal bias must come from mechanisms, so what stepwise selects "
        "and how well it fits are results; the variant reads the Langmuir coefficient per uA "
        "instead of per mA as printed",
        variant="langmuir_per_ua",
    ),
    Deviation(
        paper=PAPER,
        what="chamber program",
        paper_says="gyro powered and started, then the chamber runs over the range at the stated "
        "rate (soaks and direction not given)",
        we_do="gyro on at the low end (soak), ramp to the high end, soak, ramp back, soak "
        "(Config.return_ramp)",
        reason="the paper gives range and rate only; a full cycle exercises both signs of the "
        "rate and of the housing-cavity gradient",
        variant="up_ramp_only",
    ),
    Deviation(
        paper=PAPER,
        what="data the stability claims are scored on",
        paper_says="the model is applied to the high/low-temperature test data of three gyros "
        "(not said whether those data were used for the fit)",
        we_do="each gyro's model is fitted on its first turn-on and the before/after stability is "
        "scored on its second turn-on (held out)",
        reason="a compensation model is used on later runs; in-sample scoring equals adjusted R^2 "
        "by arithmetic (R^2 = 1 - (after/before)^2)",
        variant="in_sample_scoring",
    ),
    Deviation(
        paper=PAPER,
        what="one model per gyro",
        paper_says="'this compensation model applied to three gyros' (Eq. 3; could be one "
        "coefficient set)",
        we_do="each unit (gyro) fits its own stepwise model; applying unit s's model to unit s+1 "
        "is a labelled diagnostic (Table 4, measured there)",
        reason="the paper's text does not say whether the coefficients are refitted per gyro",
    ),
    Deviation(
        paper=PAPER,
        what="gradient candidates x9-x11",
        paper_says="'temperature gradient etc.' (the form of x9-x11 is not given)",
        we_do="x9 = T1 - T2, x10 = d(T1 - T2)/dt, x11 = T1 (T1 - T2) (analysis.regressors)",
        reason="the text names only x1-x8 explicitly; other forms were not tried",
    ),
    Deviation(
        paper=PAPER,
        what="temperature-rate estimator",
        paper_says="not given",
        we_do="Savitzky-Golay derivative of the 100-s means over five blocks (Config.derivative_window_s)",
        reason="a smoothed derivative of the logged temperatures; five blocks is the shortest "
        "window of the estimator",
        variant="derivative_window_doubled",
    ),
    Deviation(
        paper=PAPER,
        what="samples of the regression",
        paper_says="raw data averaged over 100 s (GJB) to compute the gyro's precision; the "
        "regression's sampling is not stated",
        we_do="the regression is fitted on the same 100-s means",
        reason="the paper's metric and its Table 1 are most naturally on the 100-s means; the "
        "variant fits and scores on 10-s means",
        variant="blocks_10s",
    ),
)


def claims_for(config: Config) -> tuple[Claim, ...]:
    """The claims judged for ``config``: every variant judges all of :data:`CLAIMS` (none is calibrated).

    Parameters
    ----------
    config : Config
        The configuration.

    Returns
    -------
    tuple of Claim
        :data:`CLAIMS`.
    """
    return CLAIMS
