"""Plain-text tables of the bench: a campaign's summary and a comparison's verdict."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING

from gyrobench.scenarios.bench.seeds import seed_text

if TYPE_CHECKING:
    from gyrobench.scenarios.bench.baseline import Comparison
    from gyrobench.scenarios.bench.campaign import Campaign

__all__ = ["format_comparison", "format_summary"]


def format_summary(campaign: Campaign, references: Mapping[str, Campaign] | None = None) -> str:
    """Format a campaign's scores as a plain-text table.

    Every score's unit, mean, 95 % CI, how the CI was computed, and n; with ``references``
    (label -> campaign of a reference compensator on the same seeds: the uncompensated
    output, the paper's method), each reference's mean in a column beside.

    The header states the interval methods (see :func:`~gyrobench.scenarios.bench.statistics.summarize`): Student t for
    scores of either sign; for scores non-negative by nature (mse, rms, std,
    stability, ...) the lognormal (modified Cox) interval for the mean, which is
    always > 0 (or the t interval clipped at 0 when a value is exactly 0). Primary
    scores (the gated ones, :mod:`~gyrobench.scenarios.bench.primary`) come first.

    Parameters
    ----------
    campaign : Campaign
        The campaign (:func:`~gyrobench.scenarios.bench.run_campaign`).
    references : mapping of str to Campaign, optional
        Reference campaigns on the same seeds, by label.

    Returns
    -------
    str
        The table, with a header line.
    """
    from gyrobench.scenarios.bench.primary import gated_scores, score_unit

    refs = dict(references or {})
    summary = campaign.summary()
    gated = [g.name for g in gated_scores(campaign.scenario, list(summary)) if g.name in summary]
    order = gated + [n for n in summary if n not in gated]
    rows = [("score", "gate", "unit", "mean", "95% CI", "CI", "n", *refs)]
    ref_means = {label: r.summary() for label, r in refs.items()}
    for name in order:
        s = summary[name]
        ci = "n/a" if math.isnan(s.low) else f"[{s.low:.6g}, {s.high:.6g}]"
        extra = []
        for label in refs:
            r = ref_means[label].get(name)
            extra.append("n/a" if r is None or math.isnan(r.mean) else f"{r.mean:.6g}")
        rows.append(
            (
                s.name,
                "primary" if name in gated else "secondary",
                score_unit(campaign.scenario, name) or "-",
                f"{s.mean:.6g}",
                ci,
                s.method if s.n > 1 else "-",
                str(s.n),
                *extra,
            )
        )
    w = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    head = (
        f"campaign {campaign.campaign_id}: scenario {campaign.scenario}, "
        f"compensator {campaign.compensator}; {len(campaign.scores)} seeds "
        f"({campaign.computed} computed, {campaign.reused} from the database)"
    )
    if campaign.failed:
        head += (
            f"; {len(campaign.failed)} FAILED (non-finite prediction or score: "
            f"seeds {seed_text(sorted(campaign.failed))}), left out of the summary"
        )
    how = [
        "95% CI of the mean over seeds, by CI method: 't' = Student t; 'lognormal' = modified Cox",
        "interval, always > 0, for scores non-negative by nature (mse, rms, std, stability, ...);",
        "'t, clipped at 0' = such a score with a value of exactly 0; only primary scores are gated",
    ]
    if refs:
        how.append("reference columns: mean of the same seeds under " + "; ".join(
            f"{label} ({r.compensator})" for label, r in refs.items()
        ))
    lines = [head, *how] + [
        "  ".join(c.ljust(w[i]) if i in (0, 1, 2, 5) else c.rjust(w[i]) for i, c in enumerate(r))
        for r in rows
    ]
    return "\n".join(lines)


def format_comparison(comparison: Comparison) -> str:
    """Format a baseline comparison as plain text.

    The test and correction, one line per score (primary first, with units and the references'
    means), then the verdict on the primary scores.

    Parameters
    ----------
    comparison : Comparison
        The comparison (:func:`~gyrobench.scenarios.bench.compare`).

    Returns
    -------
    str
        The text, one line per score.
    """
    refs = {r.label: r.means for r in comparison.references}
    n_primary = len(comparison.primary)
    lines = [
        f"comparison with the baseline over {len(comparison.seeds)} matching seeds: {comparison.test}; "
        + (comparison.correction or f"Holm-adjusted over {len(comparison.scores)} scores, alpha {comparison.alpha:g}")
    ]
    if comparison.note:
        lines.append(f"note: {comparison.note}")
    rows = [("score", "gate", "unit", "status", "baseline", "candidate", *refs, "shift", "change", "p (Holm)")]
    for s in comparison.scores:
        rel = "n/a" if not math.isfinite(s.relative) else f"{100 * s.relative:+.3g}%"
        extra = []
        for label in refs:
            v = refs[label].get(s.name)
            extra.append("n/a" if v is None or not math.isfinite(v) else f"{v:.6g}")
        rows.append(
            (
                s.name,
                "primary" if s.primary else "secondary",
                s.unit or "-",
                s.status,
                f"{s.baseline_mean:.6g}",
                f"{s.candidate_mean:.6g}",
                *extra,
                f"{s.effect:+.3g}",
                rel,
                f"{s.p_adjusted:.3g}",
            )
        )
    w = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    lines += [
        "  ".join(c.ljust(w[i]) if i < 4 else c.rjust(w[i]) for i, c in enumerate(r))
        for r in rows
    ]
    if refs:
        lines.append("reference columns: mean over the same seeds of " + ", ".join(refs) + " (not tested)")
    if comparison.missing:
        lines.append(f"not compared (in only one campaign): {', '.join(comparison.missing)}")
    if comparison.unpaired:
        u = comparison.unpaired
        lines.append(
            f"not compared ({len(u)} score(s) not held by every seed, so not paired by seed: "
            f"their names change with the seed): {', '.join(u[:6])}" + (", ..." if len(u) > 6 else "")
        )
    reg, imp, sec = comparison.regressions, comparison.improvements, comparison.secondary_regressions
    if sec:
        lines.append(
            f"secondary scores significantly worse (reported, not gated): {', '.join(s.name for s in sec)}"
        )
    if comparison.failed_seeds:
        lines.append(f"FAILED: {comparison.failure}")
    if reg:
        lines.append(
            f"REGRESSION: {len(reg)} of {n_primary} primary score(s) significantly worse: "
            + ", ".join(s.name for s in reg)
        )
    elif comparison.failed_seeds:
        lines.append(
            f"no significant regression on the {len(comparison.seeds)} seeds compared, but the "
            "comparison FAILS: the compensator failed on the seeds named above"
        )
    else:
        lines.append(
            f"no significant regression of the {n_primary} primary score(s) "
            f"({len(imp)} significantly better)"
        )
    return "\n".join(lines)
