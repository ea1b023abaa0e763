"""Paper 001's claims and protocol deviations as data, judged over the units' typed results.

:data:`CLAIMS` states every checkable claim of the paper once (see
:mod:`gyrobench.scenarios.claims`); each reads one key of a unit's
``UnitResult.quantities``. :data:`DEVIATIONS` lists the departures from the paper's stated
protocol with their measured effects (re-measure with
:func:`~.effects.deviation_effects`). :func:`claims_for` marks every claim calibrated under
``Config.variant = "calibrated"``.
"""

from __future__ import annotations

import math
from dataclasses import replace

from gyrobench.scenarios.claims import Claim, Deviation, in_range, is_true, within_factor

from . import PAPER
from .config import CALIBRATED_V_MAX_V, METHOD_LABELS, PAPER_KN_PCT, Config

__all__ = ["CALIBRATED_INPUT", "CLAIMS", "DEVIATIONS", "claims_for"]

#: what the "calibrated" variant sets from the paper (named by the raw-K_n claim's report note)
CALIBRATED_INPUT = (
    "sim.mems_resonator MemsResonator.dac_full_scale (rebalance DAC full scale v_max) = "
    f"{CALIBRATED_V_MAX_V} V, solved with scipy brentq (calibrated_v_max) so that the median "
    "noise-free raw K_n of units 0-19 on the paper's 21 rates is 15.71 % (design value 0.7 V); "
    "only with Config.variant = 'calibrated'"
)
_TEXT3 = "Sec. 3, text and Table 3"


def _method_claims(key: str) -> tuple[Claim, ...]:
    label, kn = METHOD_LABELS[key], PAPER_KN_PCT[key]
    return (
        Claim(
            id=f"001.kn_heldout.{key}",
            paper=PAPER,
            where="Table 3",
            statement=(
                f"{label} compensation brings K_n to {kn} % (scored here on a held-out run at the "
                "21 table rates)."
            ),
            kind="emergent",
            quantity=f"kn_heldout_pct.{key}",
            comparator=within_factor(kn),
            paper_value=kn,
            unit="%",
        ),
        Claim(
            id=f"001.improvement.{key}",
            paper=PAPER,
            where=_TEXT3,
            statement=(
                f"{label} compensation improves K_n by about two orders of magnitude (raw / "
                "compensated K_n of the held-out run, read as 30x to 300x; the paper's own "
                "Table 3 gives 112x, 27x and 35x)."
            ),
            kind="emergent",
            quantity=f"improvement.{key}",
            comparator=in_range(30.0, 300.0),
            unit="x",
        ),
    )


def _dense_claim(key: str) -> Claim:
    label, kn = METHOD_LABELS[key], PAPER_KN_PCT[key]
    return Claim(
        id=f"001.kn_dense.{key}",
        paper=PAPER,
        where="Table 3 (extension: between the table rates)",
        statement=(
            f"{label}: the paper's K_n = {kn} % (scored at the 21 table rates) holds between them "
            f"too (our extension: noise-free held-out sweep every 10 deg/s)."
        ),
        kind="emergent",
        quantity=f"kn_dense_pct.{key}",
        comparator=within_factor(kn),
        paper_value=kn,
        unit="%",
    )


def _order_claim(id_: str, where: str, statement: str, quantity: str) -> Claim:
    return Claim(
        id=id_,
        paper=PAPER,
        where=where,
        statement=statement,
        kind="emergent",
        quantity=quantity,
        comparator=is_true(),
    )


CLAIMS: tuple[Claim, ...] = (
    Claim(
        id="001.raw_kn",
        paper=PAPER,
        where="Sec. 3, after Table 1",
        statement=(
            "The raw scale-factor nonlinearity K_n, averaged over the runs, is 15.71 % "
            "(emergent on the default design; calibrated under Config.variant = 'calibrated', "
            "which sets v_max for it)."
        ),
        kind="emergent",
        quantity="raw_kn_pct",
        comparator=within_factor(15.71),
        paper_value=15.71,
        unit="%",
    ),
    Claim(
        id="001.breakpoints",
        paper=PAPER,
        where="Table 2",
        statement=(
            "The heuristic breakpoint search splits the range at -1800 and +1800 deg/s "
            "(negative high-rate, low-rate and positive high-rate segments; the heuristic "
            "runs unchanged on the simulated Table 1)."
        ),
        kind="emergent",
        quantity="breakpoints_at_1800",
        comparator=is_true(),
    ),
    Claim(
        id="001.low_rate_kn",
        paper=PAPER,
        where="Sec. 3, after Table 2",
        statement=(
            "In the low-rate segment (between the breakpoints found) K_n is of order 1e-3 "
            "(read as within a factor sqrt(10) of 1e-3; untestable on a unit where the "
            "heuristic does not find both breakpoints)."
        ),
        kind="emergent",
        quantity="low_rate_kn",
        comparator=within_factor(1e-3, math.sqrt(10.0)),
        paper_value=1e-3,
        unit="-",
    ),
    *(c for key in METHOD_LABELS for c in _method_claims(key)),
    _order_claim(
        "001.order",
        _TEXT3,
        "Ranking by K_n: the heuristic piecewise fit best, Bayes-BP second, the two-stage "
        "polynomial worst (held-out run, table rates).",
        "order_as_paper",
    ),
    _order_claim(
        "001.piecewise_best",
        _TEXT3,
        "The heuristic piecewise fit compensates best (lowest held-out K_n of the three).",
        "piecewise_best",
    ),
    _order_claim(
        "001.bayes_bp_beats_two_stage",
        _TEXT3,
        "The Bayes-BP network compensates better than the two-stage 9th-order polynomial.",
        "bayes_bp_beats_two_stage",
    ),
    _order_claim(
        "001.piecewise_smallest_error",
        "Fig. 6",
        "The piecewise fit has the smallest overall error (RMS of the held-out pointwise "
        "nonlinearity a_j).",
        "piecewise_smallest_rms",
    ),
    *(_dense_claim(key) for key in METHOD_LABELS),
    _order_claim(
        "001.order_dense",
        "Table 3 (extension: between the table rates)",
        "The paper's ranking (piecewise < Bayes-BP < two-stage) also holds on the dense held-out "
        "sweep (our extension).",
        "order_as_paper_dense",
    ),
)


#: where the effects below come from (re-measure with :func:`~.effects.deviation_effects`)
_MEASURED = (
    "medians over units (seeds) 0-19, default Config (design device), held-out K_n at the "
    "table rates"
)

DEVIATIONS: tuple[Deviation, ...] = (
    Deviation(
        paper=PAPER,
        what="the device under test",
        paper_says=(
            "a +-3600 deg/s MEMS prototype whose output bends beyond about 1800 deg/s "
            "(raw K_n 15.71 %)"
        ),
        we_do=(
            "units drawn from sim.mems_resonator's plausible +-3600 deg/s force-rebalance design "
            "(v_max = 0.7 V: knee at the rebalance authority, 1.1-1.4x the range); "
            "Config.variant = 'calibrated' sets v_max = 0.44017 V (CALIBRATED to 15.71 %)"
        ),
        reason=(
            "the knee must follow from a physical limit of the device, not a curve placed at "
            "the paper's breakpoint (issue 16); the paper does not describe its device's design"
        ),
        effect=(
            f"{_MEASURED}: design: knee 4057-5226 deg/s, raw K_n 5.1e-5 % (noise of the dwell "
            "means), breakpoints on 1/20 units, every K_n and ranking claim but two fails "
            "(compensation cannot improve a linear table). Calibrated variant: knee 2510-3283 "
            "deg/s, raw K_n 15.7 % (19/20 within 2x, calibrated), flat output beyond the knee, "
            "so compensated K_n 15.3 % (piecewise), 9.8 % (two-stage), 11.4 % (BR-MLP), "
            "improvement 1.0-1.6x, breakpoints at +-1800 on 0/20; 0.76 s per unit "
            "(design 0.58 s; reproduce --workers 1 on a shared 2-core machine)"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="scoring on a held-out run",
        paper_says=(
            "fits the several groups of data and computes K_n of the compensated output by eqs. "
            "(5)-(6) (Table 3); no run kept out of the fit is mentioned"
        ),
        we_do=(
            "the claims score each method on a power-on it never saw (own turn-on bias and "
            "scale-factor error, temperature and noise); the in-sample K_n is reported beside it"
        ),
        reason="a compensation is used on later power-ons; in-sample K_n flatters a flexible model",
        effect=(
            f"{_MEASURED}: in-sample piecewise 5.2e-5 %, two-stage 1.41e-3 %, BR-MLP 3.8e-3 % "
            "against held-out 5.4e-5 %, 1.39e-3 %, 3.8e-3 %; the paper's order on 0/20 units "
            "either way; no claim's verdict changes"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="number of runs",
        paper_says="'several groups' of data (number not given); Table 1 is their mean",
        we_do=(
            "3 fitting power-ons pooled for the fits (Table 1 their mean) and 1 held-out "
            "power-on per unit; a 9th-order segment on the rates of one side needs >= 10 "
            "distinct outputs, so >= 2 runs must be pooled"
        ),
        reason="the paper does not give the number; 3 is the smallest that leaves margin",
        effect=(
            f"{_MEASURED}: with 5 fitting runs piecewise 5.2e-5 %, two-stage 2.0e-3 %, BR-MLP "
            "3.7e-3 % (3 runs: 5.4e-5, 1.39e-3, 3.8e-3 %); the paper's order on 0/20 units "
            "either way; no verdict changes"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="dwells, settling and warm-up",
        paper_says=(
            "warm-up 20-30 min, then the table steps through the rates; 200 Hz, 1-2 min "
            "averaged per settled rate"
        ),
        we_do=(
            "each dwell an independent column of the slow flow started at its equilibrium, "
            "0.5 s settling, 60 s averaged; die temperature constant per run (25 degC, 0.5 K "
            "run-to-run), no table acceleration and no warm-up drift"
        ),
        reason=(
            "the rebalance loop settles in ms and the resonator model takes a temperature per "
            "call; 60 s (the paper's lower end) keeps a unit near the runtime budget"
        ),
        effect=(
            f"{_MEASURED}: with 120 s averaged raw K_n 3.9e-5 %, piecewise 4.1e-5 %, two-stage "
            "1.37e-3 %, BR-MLP 3.8e-3 %, a split on 5/20 units (60 s: 5.1e-5, 5.4e-5, 1.39e-3, "
            "3.8e-3 %, 1/20); +-1800 on 0/20 either way; no verdict changes"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="piecewise segments: curvature penalty",
        paper_says="each segment an ordinary least-squares polynomial (eqs. 7-9), orders 9-1-9",
        we_do=(
            "least squares with a curvature penalty alpha = 1e-6 (scaled units) on each segment "
            "(PiecewisePolynomial.alpha)"
        ),
        reason=(
            "on six distinct rates a plain 9th-order fit is not determined between them and "
            "oscillates between them"
        ),
        effect=(
            f"{_MEASURED}: alpha = 0 gives the same medians (piecewise 5.4e-5 %): the heuristic "
            "splits on 1/20 design units, so the piecewise fit is almost always one linear "
            "segment; no verdict changes"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="continuity at the breakpoints",
        paper_says=(
            "weighted refit f2 of the next segment from x_(n-4), then a cubic Hermite curve "
            "between (x_(n-3), y_(n-3)) and (x_4, y_4) over the overlap of the two fits"
        ),
        we_do=(
            "a cubic Hermite curve over a join of fixed width (5 % of the output span, centred "
            "on the breakpoint), end values and slopes from the two segment fits; no weighted "
            "refit"
        ),
        reason="the paper's weights and index conventions are not given completely",
        effect=(
            f"{_MEASURED}: join width 2 % and 10 % give the same medians as 5 % (piecewise "
            "5.4e-5 %; no breakpoint on 19/20 design units); no verdict changes"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="Bayes-BP network training",
        paper_says="Bayes-BP network with 10 hidden nodes trained on the learning set (MATLAB)",
        we_do=(
            "numpy re-implementation of MATLAB trainbr (Levenberg-Marquardt + MacKay evidence), "
            "tanh hidden layer, linear output, mapminmax scaling, Nguyen-Widrow start seeded "
            "per unit, up to 1000 epochs, every fitting point used for training, one training"
        ),
        reason="the paper gives no training details; trainbr's defaults are the MATLAB ones",
        effect=(
            f"{_MEASURED}: BR-MLP 3.8e-3 % with 1000 epochs, 4.3e-3 % with 200; the paper's "
            "order on 0/20 units either way; no verdict changes"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="evaluation times",
        paper_says=(
            "0.247 ms (piecewise), 0.755 ms (two-stage), 37.8 ms (Bayes-BP); piecewise tens of "
            "times faster than the network and more than 2x faster than the two-stage polynomial"
        ),
        we_do="time each compensation of the 21-point table (numpy, one thread) but judge no claim",
        reason=(
            "a time measures an implementation and a machine (MATLAB, the paper's computer), "
            "not the method"
        ),
        effect=(
            f"{_MEASURED}: piecewise 0.11 ms, two-stage 0.17 ms, BR-MLP 0.08 ms: the network "
            "is fastest here (a 10-unit tanh layer on 21 points is a few numpy operations)"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="run-to-run repeatability of the device",
        paper_says=(
            "a real prototype; its repeatability is not given ('the nonlinear curves of the "
            "same prototype are similar')"
        ),
        we_do=(
            "each power-on draws a turn-on scale-factor error (1000 ppm, 1 sigma) and bias "
            "(0.1 deg/s), sim.mems_resonator defaults (rate grade, cited in docs/physics.md 5.1)"
        ),
        reason="no number for this device; the resonator model's population defaults",
        effect=(
            f"{_MEASURED}: with 0 ppm: piecewise 5.3e-5 %, two-stage 5.6e-5 %, BR-MLP 2.2e-4 % "
            "(1000 ppm: 5.4e-5, 1.39e-3, 3.8e-3 %): the 9th-order fits chase the runs' slope "
            "scatter; the paper's order on 0/20 units either way"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="breakpoint heuristic: where to split",
        paper_says="when the count reaches 3, split 'from the first point' (从第1个点处)",
        we_do=(
            "split at the end of the last interval before the run of positive signs "
            "(analysis.scale_factor.heuristic_split)"
        ),
        reason="the text does not say which point is 'the first'",
        effect=(
            "the other reading (the end of the first interval of the run) moves each split one "
            "table rate outward; over units 0-19 neither reading gives +-1800 on any unit, "
            "design or calibrated device (design: a split on 1/20 units; calibrated: 11/20, "
            "at 1080-2520 deg/s, on noise below the knee)"
        ),
    ),
)


def claims_for(config: Config) -> tuple[Claim, ...]:
    """:data:`CLAIMS`, every one marked calibrated when ``config.variant`` sets v_max.

    v_max places the knee of the device, so it feeds the raw table every claim is computed
    from (raw K_n, the breakpoints, and each compensator's training data and improvement
    ratio): under the calibrated variant no paper-001 claim is reproduced. The shared
    runner judges these (:func:`gyrobench.scenarios.units.module_claims`).
    """
    if config.variant != "calibrated":
        return CLAIMS
    return tuple(replace(c, kind="calibrated", calibrated_input=CALIBRATED_INPUT) for c in CLAIMS)

