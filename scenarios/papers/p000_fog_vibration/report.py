"""Paper 000's report: tables, conclusion and figures from the units' typed results and judged claims.

Formatting only: nothing here simulates (no import from :mod:`gyrobench.sim`); the figures are
drawn by :mod:`.figures` from each unit's :class:`~.results.FigureData`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from gyrobench.scenarios.base import FigureSpec, Outcome, Table
from gyrobench.scenarios.claims import ClaimResult, finite_median

from . import NAME, TITLE
from .config import Config, split_level_m
from .figures import fig_compensation, fig_models, fig_multiscale, fig_records, fig_spectrum_cwt, fig_split
from .results import TERMS, Coefficient, Coefficients, UnitResult

__all__ = ["report"]


def _text(d: Coefficient) -> str:
    if d.value is None:
        return f"< {d.high:.3g}"
    return f"{d.value:.3g} [{d.low:.3g}, {d.high:.3g}]"


def _coef_table(title: str, cols: dict[str, Coefficients], note: str = "") -> Table:
    rows = []
    for t in TERMS:
        unit = next(iter(cols.values()))[t].unit
        rows.append([t, unit] + [_text(cols[n][t]) for n in cols])
    return Table(title, ["term", "unit"] + list(cols), rows, note)


def _detail_tables(u: UnitResult, config: Config) -> list[Table]:
    """Tables 1-3 of one unit (the first), with 95 % intervals."""
    j, m = config.bias_level, split_level_m(config)
    fs = config.fog.output_rate_hz
    band = (
        f"Q, N from the full tau range; B, K, R from tau >= 2^{j + 1}/fs = {m / fs:.3g} s for every column "
        f"(a{j} is smooth below ~2^{j} samples by construction; its ADEV there would read as a spurious R). "
    )
    return [
        _coef_table(
            f"Table 1 (unit seed {u.seed}). Allan coefficients of the three phases of the "
            f"{config.fixed_hz:g} Hz record (95 % intervals)",
            {f"phase {k}": v for k, v in u.phases.columns().items()},
            note=(
                f"Phase 1 static, 2 vibration, 3 static; {config.guard_s:g} s guard after each edge. "
                "'< x' = not identifiable, 95 % upper bound. Paper: every coefficient rises clearly in "
                "phase 2; Q, N, B unchanged from phase 1 to 3, K and R slightly lower after."
            ),
        ),
        _coef_table(
            f"Table 2 (unit seed {u.seed}). Sweep record: original vs bias (a{j}) vs drift + noise "
            f"(d1..d{j})",
            u.decomposition.columns(),
            note=band
            + "Paper: the bias part loses most of Q, N and R and keeps B and K; drift + noise "
            "keeps Q, N, R and loses B, K.",
        ),
        _coef_table(
            f"Table 3 (unit seed {u.seed}). {config.fixed_hz:g} Hz record: original, denoised "
            f"(a{j}), RBF- and LS-compensated",
            u.compensation.columns(),
            note=band
            + "Paper: denoising lowers Q and N; RBF and LS compensation lower B, K, R; RBF "
            "lower than LS.",
        ),
    ]


def _median_text(ds: list[Coefficient]) -> str:
    vals = [d.value for d in ds if d.value is not None]
    if not vals:
        return f"bound only (median < {np.median([d.high for d in ds]):.3g})"
    return f"{np.median(vals):.3g} ({len(vals)}/{len(ds)})"


def _table_columns(u: UnitResult, key: str) -> dict[str, Coefficients]:
    """The columns of Table 1 (``"phases"``), 2 (``"decomposition"``) or 3 (``"compensation"``)."""
    if key == "phases":
        return u.phases.columns()
    if key == "decomposition":
        return u.decomposition.columns()
    return u.compensation.columns()


def _population_table(units_: Sequence[UnitResult]) -> Table:
    """Median of each identified coefficient over the units, per table column."""
    groups = [("Table 1", "phases", k) for k in ("1", "2", "3")]
    groups += [("Table 2", "decomposition", k) for k in ("original", "bias", "drift_noise")]
    groups += [("Table 3", "compensation", k) for k in ("original", "denoised", "rbf", "ls")]
    rows = []
    for tab, key, col in groups:
        rows.append(
            [tab, col if key != "phases" else f"phase {col}"]
            + [_median_text([_table_columns(u, key)[col][t] for u in units_]) for t in TERMS]
        )
    unit_row = units_[0].phases.phase1
    cols = ["table", "column"] + [f"{t} [{unit_row[t].unit}]" for t in TERMS]
    return Table(
        f"Tables 1-3 over {len(units_)} units: median of the identified values (units where identified)",
        cols,
        rows,
        note="A term not identifiable in a unit's record (a 95 % upper bound only) is left out "
        "of the median; 'bound only' = identified in no unit.",
    )


def _model_table(units_: Sequence[UnitResult], config: Config) -> Table:
    keys = [
        ("rbf_vs_target", "RBF vs a7 target"),
        ("ls_vs_target", "LS vs a7 target"),
        ("rbf_vs_truth", "RBF vs true bias"),
        ("ls_vs_truth", "LS vs true bias"),
        ("target_vs_truth", "a7 target vs true bias"),
        ("peak_bias_frequency_hz", "frequency of the largest a7 bias bin [Hz]"),
        ("true_peak_bias_frequency_hz", "frequency of the largest true bias [Hz]"),
    ]
    rows = []
    for k, label in keys:
        v = np.array([getattr(u.bias_models, k) for u in units_])
        rows.append(
            [
                label,
                float(getattr(units_[0].bias_models, k)),
                float(np.median(v)),
                f"{np.percentile(v, 25):.3g} - {np.percentile(v, 75):.3g}",
            ]
        )
    for k, label in (
        ("offset_denoised", "vibration offset, denoised [deg/h]"),
        ("offset_rbf", "vibration offset, RBF-compensated [deg/h]"),
        ("offset_ls", "vibration offset, LS-compensated [deg/h]"),
        ("true_bias_steady", "true vibration bias [deg/h]"),
        ("residual_vs_truth_rbf", "RBF model - true bias [deg/h]"),
        ("residual_vs_truth_ls", "LS model - true bias [deg/h]"),
    ):
        v = np.array([getattr(u.offsets, k) for u in units_])
        rows.append(
            [
                label,
                float(getattr(units_[0].offsets, k)),
                float(np.nanmedian(v)),
                f"{np.nanpercentile(v, 25):.3g} - {np.nanpercentile(v, 75):.3g}",
            ]
        )
    n0 = units_[0].bias_models.rbf_neurons
    return Table(
        f"Bias models (MSE [(deg/h)^2], peak frequencies [Hz]) and the {config.fixed_hz:g} Hz "
        "vibration offsets",
        ["quantity", "first unit", f"median of {len(units_)}", "interquartile range"],
        rows,
        note=(
            f"RBF: {config.rbf_centres} centres, spread {config.rbf_spread_hz:g} Hz, goal "
            f"{config.rbf_goal_deg_h2:g} (deg/h)^2 ({n0} neurons in the first unit), trained with LS "
            f"(order {config.ls_order}) on 1 Hz bin means of a{config.train_level}. Offsets: steady "
            "vibration phase minus steady phase 1."
        ),
    )


def _table_dict(columns: dict[str, Coefficients]) -> dict[str, Any]:
    return {k: c.as_dict() for k, c in columns.items()}


def _results(config: Config, units_: Sequence[UnitResult]) -> dict[str, Any]:
    u0 = units_[0]
    return {
        "first_unit": {
            "seed": u0.seed,
            "phases": _table_dict(u0.phases.columns()),
            "decomposition": _table_dict(u0.decomposition.columns()),
            "compensation": _table_dict(u0.compensation.columns()),
            "bias_models": u0.bias_models.as_dict(),
            "offsets": u0.offsets.as_dict(),
        },
        "quantities_by_unit": [{"seed": u.seed, **u.quantities} for u in units_],
        "protocol": {
            "bias_level": config.bias_level,
            "train_level": config.train_level,
            "rbf_centres": config.rbf_centres,
            "rbf_spread_hz": config.rbf_spread_hz,
            "rbf_goal_deg_h2": config.rbf_goal_deg_h2,
            "ls_order": config.ls_order,
            "tau_min_s_for_B_K_R": split_level_m(config) / config.fog.output_rate_hz,
            "phase_durations_s": [
                config.static_before_s,
                config.vibration_s,
                config.static_after_s,
            ],
            "guard_s": config.guard_s,
        },
    }


def _rise_text(units_: Sequence[UnitResult]) -> str:
    """Median phase-2/phase-1 ratio of each Allan term over the units where both are identified."""
    parts = []
    for t in TERMS:
        r = [
            v2 / v1
            for u in units_
            if (v2 := u.phases.phase2[t].value) is not None and (v1 := u.phases.phase1[t].value)
        ]
        parts.append(f"{t} {np.median(r):.3g} ({len(r)} units)" if r else f"{t} not identified")
    return ", ".join(parts)


def _conclusion(claims: Sequence[ClaimResult], units_: Sequence[UnitResult]) -> str:
    """The claims' verdicts by kind, and the numbers behind the failing compensation claims."""

    def ids(kind: str | None, verdict: str) -> str:
        sel = [c for c in claims if (kind is None or c.claim.kind == kind) and c.verdict == verdict]
        return ", ".join(c.claim.id.removeprefix("000.") for c in sel) or "none"

    def med(group: str, key: str) -> float:
        return finite_median(getattr(getattr(u, group), key) for u in units_)

    def cm(key: str) -> str:
        c = next(c for c in claims if c.claim.id == f"000.{key}")
        return "not testable" if c.median is None else f"{c.median:.3g} ({c.testable} units)"

    n_cal = sum(c.claim.kind == "calibrated" for c in claims)
    return (
        f"Over {len(units_)} units. Emergent claims holding for most units: "
        f"{ids('emergent', 'holds for most units')}. Emergent claims FAILING for most units: "
        f"{ids('emergent', 'fails for most units')}. Undecided: {ids(None, 'undecided')}. "
        "Not testable (a coefficient the claim needs is only a 95 % bound in every unit; K and R "
        "need records of days; the method claims on R and on the sweep record's B are judged on the fit's "
        "point values instead, and are not testable on a unit whose fit prints 0 on both sides): "
        f"{ids(None, 'not testable')}. {n_cal} claims are calibrated (true "
        "by the model's structure: no after-effect of vibration) and are not counted as "
        f"reproduced; of these, FAILING for most units: {ids('calibrated', 'fails for most units')}. "
        f"Phase 2 over phase 1 (median of identified point values): {_rise_text(units_)}. "
        f"Medians over units: vibration offset {med('offsets', 'offset_denoised'):.3g} deg/h denoised, "
        f"{med('offsets', 'offset_rbf'):.3g} after RBF and {med('offsets', 'offset_ls'):.3g} after LS "
        f"compensation (true bias {med('offsets', 'true_bias_steady'):.3g}); K denoised/LS "
        f"{cm('t3_ls_lowers_K')}, denoised/RBF {cm('t3_rbf_lowers_K')}; R (the fit's point values) original/bias part "
        f"{cm('t2_bias_loses_R')}, drift + noise/original {cm('t2_drift_noise_keeps_R')}. RBF "
        f"network: {med('bias_models', 'rbf_neurons'):.0f} neurons for "
        f"{med('bias_models', 'n_bins'):.0f} training pairs, MSE against the true bias "
        f"{med('bias_models', 'rbf_vs_truth'):.3g} (deg/h)^2, against its targets "
        f"{med('bias_models', 'rbf_vs_target'):.3g}; LS {med('bias_models', 'ls_vs_truth'):.3g} "
        "against the true bias. The largest a7 bias bin lies at "
        f"{med('bias_models', 'peak_bias_frequency_hz'):.0f} Hz, the largest true rectified bias "
        f"at {med('bias_models', 'true_peak_bias_frequency_hz'):.0f} Hz (medians): where the "
        "a7 bin means peak is set by noise when the true bias is far below their scatter."
    )


def report(config: Config, units: Sequence[UnitResult], claims: Sequence[ClaimResult]) -> Outcome:
    """Tables (first unit in detail, all units as medians) and figures (first unit); formats only.

    Parameters
    ----------
    config : Config
        The configuration run.
    units : sequence of UnitResult
        The units' results.
    claims : sequence of ClaimResult
        The judged claims.

    Returns
    -------
    Outcome
        Tables, figures and results.
    """
    if not units:
        raise ValueError("report needs at least one unit; got 0")
    u0 = units[0]
    fd = u0.figures
    figures = [
        FigureSpec(
            "fig1_records",
            "Fig. 1: the two records (block means), static -> vibration -> static",
            fig_records(fd.records, config),
        ),
        FigureSpec(
            "fig2_spectrum_cwt",
            "Fig. 2: FFT spectrum vs continuous-wavelet time-frequency map, 500 Hz record of the first "
            "unit. The paper's EMD panel is not drawn (no EMD package among the dependencies).",
            fig_spectrum_cwt(fd.fixed_rate, fd.fs),
        ),
        FigureSpec(
            "fig3_multiscale",
            f"Fig. 3: multiscale view of the sweep record (db4, {config.level} levels)",
            fig_multiscale(fd.multiscale, config),
        ),
        FigureSpec(
            "fig4_split",
            f"Fig. 4: a{config.train_level}, a{config.bias_level} (bias), "
            f"d{config.bias_level}, d1 and the reconstructed drift + noise",
            fig_split(fd.split, config),
        ),
        FigureSpec(
            "fig6_bias_models",
            "Fig. 6: RBF vs 4th-order LS bias model against vibration frequency",
            fig_models(fd.models, u0.bias_models.rbf_neurons, config),
        ),
        FigureSpec(
            "fig7_8_compensation",
            "Figs. 7-8: denoising and bias compensation of the 500 Hz record",
            fig_compensation(fd.compensation, config),
        ),
    ]
    return Outcome(
        scenario=NAME,
        title=TITLE,
        seed=int(u0.seed),
        config=config,
        results=_results(config, units),
        tables=_detail_tables(u0, config) + [_population_table(units), _model_table(units, config)],
        figures=figures,
        conclusion=_conclusion(claims, units),
    )
