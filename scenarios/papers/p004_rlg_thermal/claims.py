"""Paper 004's claims and protocol deviations, as data over :class:`~.results.UnitResult`.

Every claim is emergent: the thermal bias comes from mechanisms (Langmuir flow of the two
discharge legs at their own gas temperatures, the current regulators' drift, the
backscatter null shift whose phases follow the block's expansion and the PLC, mode hops),
evaluated on the nodes of a housing/block thermal network that T1 and T2 read; no term is
written in the form of the paper's regressors and no size was set from a paper-004 number.
Each claim reads one key of the unit's ``quantities`` (built by
:func:`.experiment.experiment`); the paper's "three gyros" statements are per-unit
statements judged over the population of units.
"""

from __future__ import annotations

from typing import Any

from gyrobench.scenarios.claims import (
    Claim,
    Comparator,
    Deviation,
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
        "keeps_x1_x3_x5_x7_x11",
        "Sec. 3 (stepwise), Table 1",
        "Stepwise regression (MATLAB stepwise over x1..x11) keeps x1, x3, x5, x7 and x11 (per "
        "unit: all five selected).",
        "keeps_paper_terms",
        is_true(),
        kind="emergent",
    ),
    _claim(
        "drops_x2_x4_x6_x8_x9_x10",
        "Sec. 3 (stepwise)",
        "x2, x4, x6, x8, x9 and x10 are not significant and are left out (per unit: none of them "
        "selected).",
        "drops_other_terms",
        is_true(),
        kind="emergent",
    ),
    _claim(
        "selection_stability",
        "Sec. 3, Eq. (3) applied to three gyros",
        "One term set, x1, x3, x5, x7, x11, serves every gyro (selection stability: the pass rate "
        "is the fraction of units whose stepwise selection is exactly the paper's set).",
        "selects_paper_set",
        is_true(),
        kind="emergent",
    ),
    _claim(
        "bias_depends_on_t_rate_gradient",
        "Sec. 3 and conclusion",
        "The output bias depends on the internal temperature, the temperature rate and the "
        "temperature gradient (per unit: the selection carries all three kinds of term).",
        "temperature_rate_gradient",
        is_true(),
        kind="emergent",
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
    ),
    _claim(
        "adj_r2_0_97",
        "Table 1 (text)",
        "Adjusted R^2 ~0.97: the regressors explain 97 % of the bias (compared as 1 - adjusted "
        "R^2 within a factor 2 of 0.03, since a factor 2 on a number near 1 means nothing).",
        "one_minus_adj_r2",
        within_factor(1.0 - PAPER_ADJ_R2, 2.0),
        paper_value=1.0 - PAPER_ADJ_R2,
        kind="emergent",
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
    ),
    _claim(
        "significance_f",
        "Table 1 (text)",
        "The regression is significant (significance F below the 0.05 level).",
        "significance_f",
        below(0.05),
        paper_value=0.05,
        kind="emergent",
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
    ),
    _claim(
        "mode_hops_lower_adj_r2",
        "not in the paper (bench question, issue 19): Sec. 3 fit under PLC mode hops",
        "Mode hops make the stepwise fit worse: per unit whose fitting run hops, 1 - adjusted "
        "R^2 with hops exceeds that of the same gyro and draws with a PLC of unlimited travel "
        "(ratio > 1). The paper does not mention mode hops.",
        "hop_adj_r2_cost",
        above(1.0),
        unit="x",
        kind="emergent",
    ),
    _claim(
        "mode_hops_lower_improvement",
        "not in the paper (bench question, issue 19): Sec. 4 improvement under PLC mode hops",
        "Mode hops cost held-out improvement: per unit whose runs hop, the held-out before/after "
        "ratio without hops (PLC of unlimited travel, same draws) over the ratio with hops "
        "exceeds 1. The paper does not mention mode hops.",
        "hop_ratio_cost",
        above(1.0),
        unit="x",
        kind="emergent",
    ),
)


#: measured over units 0-19 (seeds 0-19) with the default Config (cavity model) unless stated
DEVIATIONS: tuple[Deviation, ...] = (
    Deviation(
        paper=PAPER,
        what="gyro and the sizes of its thermal mechanisms",
        paper_says="three real dithered RLGs (type, lock-in, discharge and block data not given)",
        we_do="cavity-model gyros (sim.rlg_cavity): every mechanism size cited or a stated "
        "assumption (Langmuir 0.0066 deg/h per uA, leg imbalance 1 uA per turn-on, backscatter "
        "null shift eta 1e-4, ZERODUR class-2 CTE, mount asymmetry 30 %), none set from a "
        "paper-004 number",
        reason="issue 19: the thermal bias must come from mechanisms, so what stepwise selects "
        "and how well it fits are results",
        effect=(
            "Langmuir coefficient x10 (0.066 deg/h per uA): adj. R^2 median 0.98 (default 0.44), "
            "held-out ratio 4.89x (1.33x), in-sample 7.29x; adj. R^2 claim 6/20 (0/20), 65 % "
            "10/20 (9/20), x4 selected by 20/20 units, exact set 0/20. "
            "Null shift eta x10 (1e-3): adj. R^2 0.52, held-out 1.45x while a perfect thermal "
            "model would reach 7.6x (the backscatter bias oscillates with temperature and steps "
            "at hops: no polynomial regressor follows it); hops then cost fit on 13/19 and "
            "improvement on 13/19 units (median 1 - adj. R^2 ratio 1.35). With the Langmuir "
            "coefficient as Aronowitz & Lim print it (0.0066 deg/h per mA, 1000x smaller than "
            "the default's reading per uA) the thermal bias is the null shift alone: adj. R^2 "
            "median 0.12, held-out 1.05x, 65 % 1/20"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="chamber program",
        paper_says="gyro powered and started, then the chamber runs over -40..+65 degC at 1 "
        "degC/3 min (soaks and direction not given)",
        we_do="gyro on at -40 degC (30-min soak), ramp to +65, 60-min soak, ramp back to -40, "
        "30-min soak (12.5 h; Config.return_ramp)",
        reason="the paper gives range and rate only; a full cycle exercises both signs of the "
        "rate and of the housing-cavity gradient",
        effect=(
            "with one up-ramp only (return_ramp=False): held-out ratio median 1.12x (full cycle "
            "1.33x), adj. R^2 median 0.22 (0.44), Multiple R 0.48 (0.67); 'temperature, rate and "
            "gradient' 10/20 (13/20), 'drops x2, x4, ...' 5/20 (2/20), 65 % 2/20 (9/20); 3 units "
            "select nothing (significance F then untestable); exact selection 0/20 either way"
        ),
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
        effect=(
            "in-sample ratio median 1.34x vs held-out 1.33x; the 65 % claim holds 9/20 either "
            "way. A perfect thermal model would reach 1.66x held out "
            "(noise floor): the simulated thermal bias (median std 0.019 deg/h of 100-s means) is "
            "near the floor (~0.015 deg/h)"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="one model per gyro",
        paper_says="'this compensation model applied to three gyros' (Eq. 3; could be one "
        "coefficient set)",
        we_do="each unit (gyro) fits its own stepwise model; applying unit s's model to unit s+1 "
        "is a labelled diagnostic (Table 4)",
        reason="the paper's text does not say whether the coefficients are refitted per gyro",
        effect=(
            "with the neighbouring unit's model the held-out ratio median is 0.74x (IQR "
            "0.37-1.01: worse than uncompensated) against 1.33x with its own; the 65 % claim would "
            "hold on 0/20. The mechanisms' signs differ between units (CTE, "
            "mount asymmetry, regulator mismatch), so one coefficient set does not transfer"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="gradient candidates x9-x11",
        paper_says="'temperature gradient etc.' (the form of x9-x11 is not given)",
        we_do="x9 = T1 - T2, x10 = d(T1 - T2)/dt, x11 = T1 (T1 - T2) (analysis.regressors)",
        reason="the text names only x1-x8 explicitly",
        effect=(
            "selected by x9 6/20, x10 3/20, x11 11/20 units; the 'keeps x1, x3, x5, x7, x11' claim "
            "fails on every unit, mostly because x1 (5/20), x5 (4/20) and x7 (4/20) are rarely "
            "selected; other forms were not tried"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="temperature-rate estimator",
        paper_says="not given",
        we_do="Savitzky-Golay derivative of the 100-s means over 500 s (5 blocks)",
        reason="a smoothed derivative of the logged temperatures; 500 s is the shortest 5-block "
        "window",
        effect=(
            "with 1000 s: exact selection 0/20 (0/20), 'keeps' 0/20 (0/20), 'drops' 2/20 (2/20); "
            "adj. R^2 median 0.45 (0.44), ratio median 1.33x (1.33x), 65 % 9/20 (9/20)"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="samples of the regression",
        paper_says="raw data averaged over 100 s (GJB) to compute the gyro's precision; the "
        "regression's sampling is not stated",
        we_do="the regression is fitted on the same 100-s means",
        reason="the paper's metric and its Table 1 are most naturally on the 100-s means",
        effect=(
            "on 10-s means (block_s=10; stability then also of 10-s means) noise dominates: "
            "Multiple R 0.21, 1 - adj. R^2 0.96, RMSE 0.080 deg/h, ratio 1.02x; the Multiple R, "
            "RMSE and 65 % claims fail 20/20"
        ),
    ),
)



def claims_for(config: Config) -> tuple[Claim, ...]:
    """The claims judged for ``config``: every variant judges all of :data:`CLAIMS` (none is calibrated)."""
    return CLAIMS
