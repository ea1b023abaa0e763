"""Paper 000's claims and protocol deviations, as data over the typed unit results.

Each :class:`~gyrobench.scenarios.claims.Claim` reads one key of a unit's ``quantities``
(:func:`~.results.unit_quantities`, whose docstring says how a quantity tests a claim); the
shared runner judges them over the units (:func:`gyrobench.scenarios.claims.evaluate`).
"""

from __future__ import annotations

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
from .results import TERMS

__all__ = ["CLAIMS", "DEVIATIONS", "claims_for"]


_STATIONARY_INPUT = (
    "model structure: the closed-loop FOG (sim.fog_loop) has no lasting after-effect of "
    "vibration (no heating, no settling), so phases 1 and 3 share one stationary noise process "
    "by construction; the claim cannot fail for a reason the paper would recognise"
)


def _c(
    key: str,
    where: str,
    statement: str,
    quantity: str,
    comparator: Comparator,
    *,
    unit: str = "x",
    calibrated: str | None = None,
) -> Claim:
    return Claim(
        id=f"000.{key}",
        paper=PAPER,
        where=where,
        statement=statement,
        kind="calibrated" if calibrated else "emergent",
        quantity=quantity,
        comparator=comparator,
        unit=unit,
        calibrated_input=calibrated,
    )


def _table1_claims() -> list[Claim]:
    out = []
    for t in TERMS:
        out.append(
            _c(
                f"t1_{t}_rises",
                "Table 1, conclusion 1",
                f"{t} rises clearly in the vibration phase (phase 2) compared with phases 1 and 3 "
                "(phase 2's lower 95 % bound over the larger static upper bound > 1)",
                f"t1_{t}_phase2_over_static",
                above(1.0),
            )
        )
    for t in ("Q", "N", "B"):
        out.append(
            _c(
                f"t1_{t}_unchanged",
                "Table 1, conclusion 2",
                f"{t} is basically unchanged between phase 1 and phase 3 (95 % intervals overlap)",
                f"t1_{t}_phase1_phase3_overlap",
                is_true(),
                unit="",
                calibrated=_STATIONARY_INPUT,
            )
        )
    for t in ("K", "R"):
        out.append(
            _c(
                f"t1_{t}_lower_after",
                "Table 1, conclusion 2",
                f"{t} is slightly lower in phase 3 than in phase 1 (ratio of the values < 1)",
                f"t1_{t}_phase3_over_phase1",
                below(1.0),
            )
        )
    return out


def _table2_claims() -> list[Claim]:
    out = []
    for t in ("Q", "N", "R"):
        out.append(
            _c(
                f"t2_bias_loses_{t}",
                "Table 2, conclusion 1",
                f"the bias part (a6) has a much lower {t} than the original (original's lower 95 % bound "
                "over the bias part's upper 95 % bound > 1)",
                f"t2_{t}_original_over_bias",
                above(1.0),
            )
        )
    for t in ("B", "K"):
        out.append(
            _c(
                f"t2_bias_keeps_{t}",
                "Table 2, conclusion 1",
                f"the bias part keeps the original's {t} (ratio bias/original within a factor 2 of 1)",
                f"t2_{t}_bias_over_original",
                within_factor(1.0, 2.0),
            )
        )
    for t in ("Q", "N", "R"):
        out.append(
            _c(
                f"t2_drift_noise_keeps_{t}",
                "Table 2, conclusion 2",
                f"the drift + noise part (d1..d6) keeps the original's {t} (ratio within a factor 2 of 1)",
                f"t2_{t}_drift_noise_over_original",
                within_factor(1.0, 2.0),
            )
        )
    for t in ("B", "K"):
        out.append(
            _c(
                f"t2_drift_noise_loses_{t}",
                "Table 2, conclusion 2",
                f"the drift + noise part has a much lower {t} than the original (original's lower 95 % "
                "bound over its upper 95 % bound > 1)",
                f"t2_{t}_original_over_drift_noise",
                above(1.0),
            )
        )
    return out


def _table3_claims() -> list[Claim]:
    out = []
    for t in ("Q", "N"):
        out.append(
            _c(
                f"t3_denoising_lowers_{t}",
                "Table 3",
                f"removing drift + noise (keeping a6) clearly lowers {t} (original's lower 95 % bound over "
                "the denoised upper 95 % bound > 1)",
                f"t3_{t}_original_over_denoised",
                above(1.0),
            )
        )
    for model, label in (("rbf", "RBF"), ("ls", "4th-order LS")):
        for t in ("B", "K", "R"):
            out.append(
                _c(
                    f"t3_{model}_lowers_{t}",
                    "Table 3",
                    f"{label} bias compensation clearly lowers {t} of the denoised record (denoised lower "
                    "95 % bound over the compensated upper 95 % bound > 1)",
                    f"t3_{t}_denoised_over_{model}",
                    above(1.0),
                )
            )
    for t in ("B", "K", "R"):
        out.append(
            _c(
                f"t3_rbf_below_ls_{t}",
                "Table 3",
                f"{t} after RBF compensation is clearly lower than after LS compensation (LS lower 95 % "
                "bound over RBF upper 95 % bound > 1)",
                f"t3_{t}_ls_over_rbf",
                above(1.0),
                )
        )
    return out


def _figure_claims() -> list[Claim]:
    return [
        _c(
            "fig3_bias_band",
            "Sec. 3, fig. 3",
            "the low-frequency part shows a bias offset in the vibration phase at high vibration frequencies, "
            "about 300-500 Hz (frequency of the largest a7 bias bin)",
            "fig3_peak_bias_frequency",
            in_range(300.0, 500.0),
            unit="Hz",
        ),
        _c(
            "fig6_rbf_far_better_target",
            "Sec. 4, fig. 6",
            "the RBF network approximates the bias curve far more accurately than the 4th-order LS fit "
            "(MSE against the a7 bias curve, the paper's blue line: LS/RBF > 3, 'far' taken as the lower end of "
            "an order of magnitude)",
            "fig6_mse_ls_over_rbf_target",
            above(3.0),
        ),
        _c(
            "fig6_rbf_far_better_truth",
            "Sec. 4, fig. 6",
            "as above, scored against the simulator's true rectified bias, which the paper cannot know "
            "(LS/RBF MSE > 3)",
            "fig6_mse_ls_over_rbf_truth",
            above(3.0),
        ),
        _c(
            "fig7_offset_remains",
            "Sec. 4, fig. 7",
            "after removing drift + noise the vibration phase still shows a bias offset (|offset| over the "
            "scatter of 10 s means of static phase 1 > 3)",
            "fig7_offset_over_scatter",
            above(3.0),
        ),
        _c(
            "fig8_edge_spikes",
            "Sec. 4, fig. 8",
            "after RBF compensation larger fluctuations remain at the vibration on/off edges (at each edge, the "
            "largest deviation within 3 s over the 95th percentile of the largest deviations of 6 s windows of "
            "the steady vibration phase > 1)",
            "fig8_edge_spike_ratio",
            above(1.0),
        ),
        _c(
            "fig8_rbf_compensates_offset",
            "Sec. 4, fig. 8",
            "RBF compensation removes the vibration-phase bias offset (|offset after| / |offset before| < 1)",
            "fig8_rbf_offset_over_denoised",
            below(1.0),
        ),
    ]


#: every checkable statement of paper 000's tables, figures and conclusions
CLAIMS: tuple[Claim, ...] = tuple(
    _table1_claims() + _table2_claims() + _table3_claims() + _figure_claims()
)


#: every remaining departure from what the paper states or shows, with its measured effect
DEVIATIONS: tuple[Deviation, ...] = (
    Deviation(
        paper=PAPER,
        what="the gyro and its vibration response",
        paper_says="one FOG of unstated type on a shaker; its records show a bias offset at "
        "300-500 Hz (fig. 3) and Allan coefficients that all rise during vibration (Table 1)",
        we_do="the closed-loop FOG of sim.fog_loop (one drawn unit per seed), vibration from "
        "mechanics: strain along the fibre through the (L - 2z) kernel, fixture rocking, loss "
        "modulation times the loop residual; mode sizes are sim.fog_loop's assumed defaults, no "
        "paper number used (the earlier phenomenological sim.vibration sizes, placed for the "
        "paper's figures, are no longer used)",
        reason="issue 17: the vibration error must follow from the device's physics",
        effect=(
            "measured on seeds 0-19: true rectified bias at 500 Hz and 2 g 1.9e-4 deg/h (median; "
            "closed form (A^2/2) Re[L conj((1 - H)(S + Rk))]) against a 0.21 deg/h scatter of 10 s "
            "means; strain tone a few deg/h rms aliased to 100 Hz under 56 deg/h rms output "
            "noise (mostly Q). So "
            "t1_Q_rises 0/20 (median phase-2/phase-1 Q 1.05), fig7_offset_remains 0/20, "
            "fig8_rbf_compensates_offset 3/20 (RBF adds the noise it learned: |offset| x2.98), "
            "t3 B claims 0/20 (ratio 0.84), fig6_rbf_far_better_truth 0/20; fig3_bias_band 15/20 "
            "reads where the a7 noise peaks (10/20 with 200 s static phases), not a bias band. "
            "With "
            "the sim.vibration sizes these claims held and were marked calibrated"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="Earth rate and sense-axis azimuth",
        paper_says="sense axis horizontal; model w = wn + b0 + br + noise (wn the true rate); "
        "azimuth and site latitude not stated",
        we_do="Nanjing (32.06 N, the paper's affiliation), axis horizontal pointing north "
        "(assumed): wn = Omega_e cos(lat) = 12.7 deg/h, constant",
        reason="the paper's model includes the true rate; the azimuth is not given",
        effect="none on any claim: a constant rate is removed by the phase-1 mean and has no "
        "Allan variance (the scale factor is constant at the reference temperature)",
    ),
    Deviation(
        paper=PAPER,
        what="phase durations",
        paper_says="not stated (figure 1 shows three phases of unstated length)",
        we_do="600 s static, 300 s vibration, 600 s static",
        reason="B of the static phases must be identifiable for 'B rises in phase 2' to be testable",
        effect=(
            "measured on seeds 0-19 with 200 s static phases (vibration 300 s): fig3_bias_band "
            "15/20 -> 10/20, fig8_edge_spikes 0/20 -> 1/20, fig8_rbf_compensates_offset 3/20 -> "
            "6/20; every other pass count and testable count unchanged (B of phases 1 and 3 "
            "identifiable in 20/20 either way on this device)"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="RBF centre selection",
        paper_says="randomly fixed centres (隨機(jī)固定法)",
        we_do="default as the paper; variant rbf_centres='ols' (MATLAB newrb orthogonal least "
        "squares) was the previous default",
        reason="the paper's protocol is the default; the variant shows what the choice changes",
        effect=(
            "measured on seeds 0-19 (same units): no claim's pass count changes; OLS stops at a "
            "median of 465 neurons, random centres at 493 (of 497 bin means: both nearly "
            "interpolate the noisy targets); RBF-compensated 500 Hz offsets differ by at most "
            "0.029 deg/h"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="approximation the bias models are trained on",
        paper_says="Sec. 3: a6 is the bias (Table 2, denoising); Sec. 4 and fig. 4: the RBF is "
        "trained on a7",
        we_do="default as the text (Table 2/3 on a6, models trained on a7); variant "
        "train_level=6 was the previous default",
        reason="the paper's text is the default; the variant shows what the choice changes",
        effect=(
            "measured on seeds 0-19 (same units): no claim's pass count changes; RBF MSE against "
            "the true bias 0.092 instead of 0.091 (deg/h)^2, RBF-compensated offset -0.194 "
            "instead of -0.183 deg/h (medians; largest per-unit difference 0.053 deg/h)"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="Allan fit range of wavelet-processed signals",
        paper_says="Allan analysis of each reconstructed signal (range not stated)",
        we_do="B, K, R from tau >= 2^(j+1)/fs = 0.32 s for every column of Tables 2 and 3",
        reason="below that an approximation a_j is smooth by construction; its ADEV (slope +1) "
        "would be read as a large spurious rate ramp R",
        effect=(
            "measured on seeds 0-19 with B, K, R of every column read from the full tau range: "
            "t2_bias_keeps_B, t3_rbf_lowers_B, t3_ls_lowers_B and t3_rbf_below_ls_B become not "
            "testable (0 of 20 units; B of a6 is then not identifiable); other pass counts "
            "unchanged"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="Table 1 guard",
        paper_says="the three phases, cut at the switching edges",
        we_do="a 5 s guard after each switching edge is left out of the phase it starts",
        reason="the on/off transients belong to neither steady state",
        effect=(
            "measured on seeds 0-19 with no guard: every Table 1 pass and testable count "
            "unchanged (t1_Q_rises 0/20, Q and B of phases 1 and 3 overlap 20/20; N, K, R never "
            "identifiable); median t1_Q ratio 0.881 either way"
        ),
    ),
    Deviation(
        paper=PAPER,
        what="figure 2 EMD panel",
        paper_says="FFT, EMD and CWT panels",
        we_do="FFT and CWT only",
        reason="no EMD implementation among the allowed dependencies; the panel's role is "
        "negative (EMD fails to separate the phases)",
        effect="none on any claim (figure only; no claim is made about EMD)",
    ),
    Deviation(
        paper=PAPER,
        what="acceleration level, output rate, bin means as training pairs",
        paper_says="'fixed acceleration', rate and training-pair construction not stated",
        we_do="2 g peak; 400 Hz integrate-and-dump output; 1 Hz bin means of the sweep's a7 as "
        "RBF/LS training pairs; models evaluated inside the training range (500 Hz read at "
        "~499 Hz)",
        reason="values the paper leaves open",
        effect="not varied (no paper value to compare with)",
    ),
)


def claims_for(config: Config) -> tuple[Claim, ...]:
    """The claims judged for ``config``: :data:`CLAIMS` for every configuration (no variant of
    this paper sets an input from a paper number, so none marks more claims calibrated)."""
    return CLAIMS
