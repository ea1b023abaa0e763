"""Paper 003's claims and protocol deviations, as data over the units' typed results.

Each :class:`~gyrobench.scenarios.claims.Claim` reads one key of
:attr:`.results.UnitResult.quantities`; the shared runner judges them over the units
(:func:`gyrobench.scenarios.claims.evaluate`). :data:`DEVIATIONS` state where the
reproduction departs from the paper's protocol, with the measured effect.
"""

from __future__ import annotations

from gyrobench.scenarios.claims import Claim, Deviation, above, in_range, is_true, within_factor

from .config import PAPER, Config

__all__ = ["CLAIMS", "DEVIATIONS", "claims_for"]

_CAL_LEADS = (
    "Config.lead_difference_rms_m = 1.0 m (Coil2DSpec.lead_difference_rms), the spread of a "
    "unit's lead A - lead B fibre length, set so that the median over 20 drawn units of this "
    "quantity is ~0.15 deg/h (0.137 measured on the coil alone); it is the dominant drift "
    "source of a drawn quadrupolar unit (0.20 deg/h per m of asymmetry in this program)"
)

#: the drift the compensators remove is set mostly by the calibrated lead asymmetry, so every
#: validation claim (a ratio or ordering of that drift against the residual) is fed by it
_CAL_FED = (
    "fed by the drift level, which is CALIBRATED: " + _CAL_LEADS
)

CLAIMS: tuple[Claim, ...] = (
    Claim(
        id="003.txdt_point",
        paper=PAPER,
        where="Sec. 2, Table 1 / Fig. 2",
        statement="A stretch of the 1000-m coil at 0.25 L0 heated from -10 to 40 degC: the "
        "nonreciprocity caused by the T x dT term alone exceeds 0.2 deg/h at its maximum "
        "(here: a free fibre, 10 m heated at 1 degC/min; the paper prints neither, and the "
        "term scales linearly with both, so the verdict rests on that assumed case, which was "
        "fixed before the coil model and not changed for it; the T x dT coefficient from "
        "Leviton-Frey dn/dT(T) and the silica expansion slope).",
        kind="emergent",
        quantity="txdt_point_max_deg_h",
        comparator=above(0.2),
        paper_value=0.2,
        unit="deg/h",
    ),
    Claim(
        id="003.drift_level",
        paper=PAPER,
        where="Sec. 0 (introduction, citing its ref. [4])",
        statement="For a +-0.01 deg/h FOG a 10 degC change of the coil temperature gives a "
        "0.15 deg/h temperature drift (here: median over the validation-1 runs, coil warming "
        "10 degC per hour, of the peak true coil drift).",
        kind="calibrated",
        calibrated_input=_CAL_LEADS,
        quantity="drift_peak_val1_deg_h",
        comparator=within_factor(0.15, 2.0),
        paper_value=0.15,
        unit="deg/h",
    ),
    Claim(
        id="003.val1_every_run",
        paper=PAPER,
        where="Sec. 5, Table 2",
        statement="Validation 1 (10 degC/h, a = 0): in every run the MSE after compensation "
        "is clearly smaller than before.",
        kind="calibrated",
        calibrated_input=_CAL_FED,
        quantity="val1_every_run_lower",
        comparator=is_true(),
    ),
    Claim(
        id="003.val1_order",
        paper=PAPER,
        where="Sec. 5, Table 2; abstract; Sec. 6",
        statement="Validation 1: compensation improves the output by about an order of "
        "magnitude (mean ERR raw / compensated over the five runs).",
        kind="calibrated",
        calibrated_input=_CAL_FED,
        quantity="val1_ratio",
        comparator=in_range(3.0, 30.0),
        paper_value=10.0,
        unit="x",
    ),
    Claim(
        id="003.val2_lowest",
        paper=PAPER,
        where="Sec. 5, Table 3",
        statement="Validation 2 (0.5 degC/min, a = 180 deg/h): the improved (T, dT, T x dT) "
        "compensation has a lower MSE than the raw output and than the traditional (T, dT) "
        "compensation in every run.",
        kind="calibrated",
        calibrated_input=_CAL_FED,
        quantity="val2_improved_lowest",
        comparator=is_true(),
    ),
    Claim(
        id="003.val2_order",
        paper=PAPER,
        where="Sec. 5, Table 3",
        statement="Validation 2: the improved compensation raises the accuracy by about an "
        "order of magnitude (mean ERR raw / improved over the five runs).",
        kind="calibrated",
        calibrated_input=_CAL_FED,
        quantity="val2_ratio",
        comparator=in_range(3.0, 30.0),
        paper_value=10.0,
        unit="x",
    ),
)

# Effects measured with `gyrobench reproduce ifog_thermal --units 20 --config FILE` over seeds
# 0-19 (default Config; each variant = one Config switch); the numbers are pass counts "k/20"
# of the claims named, on the (r, z) coil (sim.coil2d, issue 18) in the closed-loop FOG
# (sim.fog_loop via sim.fog2d, issue 17).
DEVIATIONS: tuple[Deviation, ...] = (
    Deviation(
        paper=PAPER,
        what="Earth rate",
        paper_says="turntable pointing exactly north, 'the FOG output is then 0 deg/h'; a = 0",
        we_do="the sense axis is horizontal and points east at Harbin (sense_azimuth_deg = 90), "
        "where the Earth-rate component is 0, so the input is 0 in identification and "
        "validation 1 and the reference a equals the simulator's truth",
        reason="a horizontal north-pointing axis at Harbin (45.8 degN) senses 15.041 "
        "cos(45.8 deg) = 10.48 deg/h, which contradicts the paper's 'output 0 deg/h'; east is "
        "the orientation that gives the zero input the paper states",
        effect="measured over seeds 0-19 with the axis pointing north (sense_azimuth_deg = 0: "
        "the loop adds 10.48 deg/h) and a kept at the paper's value: validation-1 "
        "raw/compensated median 1.01x (default 16.0x), validation-2 1.02x (3.6x); "
        "003.val1_order 0/20 (12/20 east), 003.val2_order 0/20 (8/20), 003.val2_lowest 5/20 "
        "(7/20), 003.val1_every_run 12/20 (19/20): Q removes the constant from the training "
        "target, so a constant the reference does not contain stays in d",
    ),
    Deviation(
        paper=PAPER,
        what="Validation-2 input",
        paper_says="turntable 'rotated 180 deg'; eq. (24) uses a = 180 deg/h",
        we_do="a constant 180 deg/h input rate (the reference of eq. 24); the loop's thermal "
        "scale-factor error at that rate is simulated",
        reason="the text's only number for the reference is 180 deg/h",
        effect="the scale-factor error at 180 deg/h spans -0.22 to +0.14 deg/h (unit 0, run 1) "
        "beside a coil drift of 0.43 deg/h (next row); measured over seeds 0-19 with a zero "
        "validation-2 rate (a = 0, no scale-factor error) instead: 003.val2_lowest 7/20 "
        "(7/20 at 180 deg/h), 003.val2_order 7/20 (8/20), median raw/improved 84x (3.6x)",
    ),
    Deviation(
        paper=PAPER,
        what="Scale factor vs temperature",
        paper_says="not discussed: the paper compensates the bias only; whether its gyro's "
        "scale factor was temperature-compensated is not said",
        we_do="the closed loop's SF(T)/SF0 = (1 + alpha_D dT_coil)^2/(1 + alpha_lambda "
        "dT_housing) about 20 degC, uncompensated; alpha_D = the coil's own hoop expansion on "
        "its aluminium spool (22.7 ppm/K for unit 0, from the composite-cylinder model), "
        "alpha_lambda = 4 ppm/K (assumed): 41 ppm/K",
        reason="one FOG model for every scenario (issue 17); alpha_D from the same coil "
        "mechanics that makes the Shupe drift, nothing chosen for the claims",
        effect="measured over seeds 0-19 with diameter_tempco_ppm_per_K = 2.76 (the net "
        "1.5 ppm/K of the earlier FOG2D product form): validation-2 median raw/improved 73x "
        "(default 3.6x), 003.val2_order 4/20 (8/20), 003.val2_lowest 8/20 (7/20), "
        "validation-1 unchanged (rate 0; val1_order 12/20): at 180 deg/h the scale-factor "
        "error follows T, not dT/dt, and the networks trained at rate 0 cannot see it, so it "
        "stays in d and sets the default's validation-2 ratio",
    ),
    Deviation(
        paper=PAPER,
        what="Deployment precision",
        paper_says="the network runs on a TMS320F28335 (single-precision FPU)",
        we_do="claims are scored with the float64 network; the exported a1/a2 form is also "
        "evaluated in float32 and re-scored (report table)",
        reason="float64 is the reference implementation; the float32 form is the check",
        effect="measured over seeds 0-19: in float32 every claim's pass count is unchanged "
        "(val1_every_run 19, val1_order 12, val2_lowest 7, val2_order 8 of 20); the largest "
        "relative change of a run's ERR is 0.06 % (median over units), 2.1 % at most; 17 of "
        "20 units stay within our 1 % criterion",
    ),
    Deviation(
        paper=PAPER,
        what="Network size and spread",
        paper_says="newrb trained 'until the output meets the design index' (index, spread "
        "and input scaling not printed)",
        we_do="inputs min-max scaled; spread and neuron count by leave-one-segment-out CV on "
        "the training run (goal 0)",
        reason="the paper's settings are not printed; CV uses the training run only",
        effect="not measurable against the paper (its settings are unknown); the CV choice "
        "per unit is in the population table",
    ),
    Deviation(
        paper=PAPER,
        what="Identification record",
        paper_says="step 2: record at -10 degC once the coil temperature and the output are "
        "stable; the heating and cooling rates are not printed",
        we_do="the record starts when the chamber reaches -10 degC, so the 2-h settle includes "
        "the coil's approach (housing lag 20 min); ramps at 1 degC/min",
        reason="'stable' has no stated criterion; the rate is not printed",
        effect="nearest measured (seeds 0-19): also recording the 20 -> -10 degC cool-down before "
        "it (record_cooldown=True) gives val1_every_run 19/20 (19/20), val1_order 12/20 "
        "(12/20), val2_lowest 9/20 (7/20), val2_order 6/20 (8/20)",
    ),
    Deviation(
        paper=PAPER,
        what="Step 5 averaging (interpretation)",
        paper_says="step 5: 'obtain the mean values of the coil temperature and of the gyro "
        "output over the heating and cooling process'",
        we_do="the mean over the heating-and-cooling record, subtracted to form Q (modelling "
        "step 2); variant identification_average='temperature_curves' averages the heating and "
        "cooling records as curves against temperature",
        reason="averaging the two records against T sets dT/dt to ~0 and cancels the drift "
        "that is odd in dT/dt, the very dependence the paper models",
        effect="measured over seeds 0-19 with the temperature_curves variant: validation-1 "
        "raw/compensated median 20.0x (default 16.0x), validation-2 2.5x (default 3.6x); "
        "003.val1_every_run 19/20 (19/20), 003.val1_order 10/20 (12/20), 003.val2_lowest 3/20 "
        "(7/20), 003.val2_order 10/20 (8/20)",
    ),
)


def claims_for(config: Config) -> tuple[Claim, ...]:
    """The claims judged for ``config``: :data:`CLAIMS` (no variant calibrates another claim)."""
    return CLAIMS
