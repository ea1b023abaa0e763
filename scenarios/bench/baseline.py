"""The paired comparison of a new campaign against a baseline, seed by seed.

:func:`compare` tests a candidate campaign against a baseline (see its Notes for the test and
the multiple-comparison correction; the statistics are in
:mod:`gyrobench.scenarios.bench.statistics`, the equivalence margin in
:mod:`gyrobench.scenarios.bench.margin`). The baseline files themselves (:func:`save_baseline`,
:func:`load_baseline` and the checks made before a campaign) are in
:mod:`gyrobench.scenarios.bench.baseline_file` and re-exported here.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np

from gyrobench.scenarios.bench.baseline_file import (
    BASELINE_FORMAT,
    BASELINE_VERSION,
    check_baseline_matches,
    check_baseline_path,
    load_baseline,
    save_baseline,
)
from gyrobench.scenarios.bench.campaign import Campaign
from gyrobench.scenarios.bench.gate import gates_of
from gyrobench.scenarios.bench.margin import DetectableChange, comparison_note, margin_test, observed_detectable
from gyrobench.scenarios.bench.margin import power_line as _power_line
from gyrobench.scenarios.bench.power import DEFAULT_MIN_CHANGE, TEST
from gyrobench.scenarios.bench.primary import directions_of, score_unit
from gyrobench.scenarios.bench.seeds import seed_text
from gyrobench.scenarios.bench.statistics import hodges_lehmann, holm, order_scores, score_direction

__all__ = [
    "BASELINE_FORMAT",
    "BASELINE_VERSION",
    "Comparison",
    "ComparisonError",
    "DetectableChange",
    "ReferenceMeans",
    "ScoreComparison",
    "check_baseline_matches",
    "check_baseline_path",
    "compare",
    "load_baseline",
    "save_baseline",
]


class ComparisonError(ValueError):
    """A campaign that cannot be compared with the baseline.

    No seed or no score can be paired, or the baseline has no finite score on the shared seeds.
    Raised by :func:`compare` once the campaign has run; the command line exits
    :data:`gyrobench.scenarios.cli.exits.FAILED_SEEDS` (3), never 0: a gate that cannot compare
    does not pass. (What can be checked before the campaign, a baseline of another scenario or
    sharing no seed with ``--seeds``, is refused first as bad input, exit 2.)
    """


@dataclass(frozen=True, slots=True, kw_only=True)
class ScoreComparison:
    """One score of a candidate campaign against the baseline, over the matching seeds.

    Attributes
    ----------
    name : str
        The score's name (``"mean/rms_residual"``).
    direction : int
        +1 higher is better, -1 lower is better, 0 unknown (:func:`score_direction`).
    n : int
        Number of paired seeds compared.
    baseline_mean, candidate_mean : float
        Mean of the score over those seeds [the score's unit].
    effect : float
        Hodges-Lehmann estimate of the paired shift, candidate - baseline [the score's unit].
    relative : float
        (mean candidate - mean baseline) / |mean baseline| [-]; NaN when the baseline's mean is
        0 or not finite.
    p_value : float
        The gate's p-value [-] (:func:`~gyrobench.scenarios.bench.margin.margin_test`: the paired t test
        of the mean change), against the margin when there is one.
    p_adjusted : float
        ``p_value`` after Holm's correction within its group (primary or secondary) [-].
    status : str
        "improved", "regressed", "changed" (significant, direction unknown) or "unchanged".
    primary : bool
        Whether the score is gated.
    unit : str
        The score's unit (``""``: none declared).
    """

    name: str
    direction: int
    n: int
    baseline_mean: float
    candidate_mean: float
    effect: float
    relative: float
    p_value: float
    p_adjusted: float
    status: str
    primary: bool = True
    unit: str = ""


@dataclass(frozen=True, slots=True, kw_only=True)
class ReferenceMeans:
    """A reference compensator's mean of every compared score over the compared seeds.

    Printed beside the user's, never tested.

    Attributes
    ----------
    label : str
        ``"uncompensated"`` or the paper's method.
    compensator : str
        The reference compensator's label.
    means : mapping of str to float
        Score name -> its mean over the compared seeds [the score's unit].
    """

    label: str
    compensator: str
    means: Mapping[str, float]


@dataclass(frozen=True, slots=True, kw_only=True)
class Comparison:
    """All scores compared; ``regressions`` non-empty means a significant regression.

    ``failed_seeds`` non-empty means the candidate failed on those seeds (a non-finite
    prediction or score): the comparison then fails whatever the scores say (``passed`` is
    False; the command line exits :data:`gyrobench.scenarios.cli.exits.FAILED_SEEDS`), and
    ``failure`` says so in one line. The paired test runs on the other seeds.

    ``missing`` names the scores held by only one campaign, ``unpaired`` those that some
    compared seed lacks (a name that changes with the seed): neither is tested.

    Only the *primary* scores (:mod:`~gyrobench.scenarios.bench.primary`) are gated:
    ``regressions`` holds the primary scores significantly worse (Holm over the primary
    scores); ``secondary_regressions`` the secondary ones (Holm among the secondary scores),
    reported, never failing the comparison. ``correction`` states the correction;
    ``references`` holds each reference compensator's (the uncompensated output, the paper's
    method) mean of every score over the compared seeds (:class:`ReferenceMeans`).

    Attributes
    ----------
    scores : tuple of ScoreComparison
        Every compared score, the primary ones first.
    seeds : tuple of int
        The seeds of the paired test (shared, and finite in both campaigns).
    alpha : float
        Family-wise error rate [-].
    test : str
        The test, in words.
    missing : tuple of str
        Scores held by only one campaign (not tested).
    unpaired : tuple of str
        Scores that some compared seed lacks (not tested).
    note : str
        What the reader should know about the result (too few seeds, dropped baseline seeds).
    failed_seeds : tuple of int
        The candidate's failed seeds.
    failure : str
        One line on the failed seeds (``""``: none).
    correction : str
        The multiple-comparison correction, in words.
    references : tuple of ReferenceMeans
        The reference compensators' means.
    min_change : float
        Equivalence margin [-], a fraction of the baseline's per-seed score.
    detectable : tuple of DetectableChange
        Per primary score, the relative change these seeds detect with power 0.8.
    """

    scores: tuple[ScoreComparison, ...]
    seeds: tuple[int, ...]
    alpha: float
    test: str
    missing: tuple[str, ...] = ()
    unpaired: tuple[str, ...] = ()
    note: str = ""
    failed_seeds: tuple[int, ...] = ()
    failure: str = ""
    correction: str = ""
    references: tuple[ReferenceMeans, ...] = ()
    min_change: float = 0.0
    detectable: tuple[DetectableChange, ...] = ()

    @property
    def power_line(self) -> str:
        """What these seeds detect, in one line (:func:`~gyrobench.scenarios.bench.margin.power_line`)."""
        return _power_line(self.detectable, self.alpha, self.min_change)

    @property
    def passed(self) -> bool:
        """No failed seed and no significant regression of a primary score."""
        return not self.failed_seeds and not self.regressions

    @property
    def primary(self) -> tuple[ScoreComparison, ...]:
        """The gated scores."""
        return tuple(s for s in self.scores if s.primary)

    @property
    def regressions(self) -> tuple[ScoreComparison, ...]:
        """Primary scores significantly worse: these fail the comparison."""
        return tuple(s for s in self.scores if s.primary and s.status == "regressed")

    @property
    def secondary_regressions(self) -> tuple[ScoreComparison, ...]:
        """Secondary scores significantly worse: reported, not gated."""
        return tuple(s for s in self.scores if not s.primary and s.status == "regressed")

    @property
    def improvements(self) -> tuple[ScoreComparison, ...]:
        """Primary scores significantly better."""
        return tuple(s for s in self.scores if s.primary and s.status == "improved")

    def format(self) -> str:
        """Plain text: one line per score, then the verdict
        (:func:`~gyrobench.scenarios.bench.formatting.format_comparison`)."""
        from gyrobench.scenarios.bench.formatting import format_comparison

        return format_comparison(self)


def compare(
    baseline: Campaign | str | os.PathLike,
    campaign: Campaign | str | os.PathLike,
    *,
    alpha: float = 0.05,
    directions: Mapping[str, int] | None = None,
    primary: Sequence[str] | None = None,
    references: Mapping[str, Campaign] | None = None,
    min_change: float = DEFAULT_MIN_CHANGE,
) -> Comparison:
    """Compare a candidate campaign with a baseline, seed by seed.

    Parameters
    ----------
    baseline, campaign : Campaign or path to a baseline JSON
    alpha : float
        Family-wise error rate over all compared scores.
    directions : mapping, optional
        Overrides for :func:`score_direction`.
    primary : sequence of str, optional
        The scores to gate; default: the scenario's primary scores
        (:func:`~gyrobench.scenarios.bench.primary.gated_scores`).
    references : mapping, optional
        Label -> campaign of a reference compensator on the same seeds (the uncompensated
        output, the paper's method): its means are reported beside the user's, never tested.
    min_change : float
        Equivalence margin, relative to the baseline's per-seed score (default
        :data:`~gyrobench.scenarios.bench.power.DEFAULT_MIN_CHANGE`, 5 %): a change within it is
        "unchanged" however significant; a change is "regressed" (or "improved") only when the
        test finds it beyond the margin (see Notes). 0: the plain test of any change.

    Returns
    -------
    Comparison

    Raises
    ------
    ComparisonError
        If no seed or score can be paired, or a primary score is not held by both campaigns
        on every compared seed.

    Notes
    -----
    Both campaigns ran the same seeds, so seed ``s`` gives both compensators the
    same simulated data: the comparison is paired, on the per-seed differences
    ``d_s = candidate_s - baseline_s`` over the seeds both hold (seeds where either
    score is NaN are dropped). Pairs are made by seed, never by a run's name: a score is
    compared only if every compared seed holds it in both campaigns; one whose name changes
    with the seed (``"unit7_heldout/mse"``) is listed in ``unpaired`` and not tested (its
    ``mean/`` counterpart is).

    The test is the gate's test of the mean change (:data:`~gyrobench.scenarios.bench.power.TEST`,
    :func:`~gyrobench.scenarios.bench.margin.margin_test`): a paired t test of the contrast
    ``c_s - b_s -+ margin |b_s|``, whose mean is ``mean|b| (R -+ margin)`` with ``R`` the relative
    change of the mean score, one-sided at ``alpha / 2`` on each side, its p floored at ``2 / 2^n``
    (the smallest p any test whose level holds for every symmetric spread of the contrast can give).
    It judges the mean, as ``--seeds auto`` sizes for it, so a regression carried by a few seeds is
    caught; its level under skewed, heavy-tailed scores was measured by simulation (docs/bench.md).
    A score whose differences are all exactly zero (the same compensator: scores
    are deterministic) is "unchanged" with p = 1.

    A candidate seed that failed (listed in ``campaign.failed``, or with a non-finite
    score: a campaign read from JSON) is never dropped silently: it is named in
    ``failed_seeds`` and the comparison does not pass, whatever the other seeds say. A
    baseline seed with a non-finite score is left out of the paired test (with a note);
    if no seed is left, the comparison is refused.

    Only the primary scores are gated. Their p-values are adjusted by Holm's step-down
    method over the primary scores alone, which keeps the probability of any false
    "regressed" or "improved" among them at most ``alpha``; the secondary scores (each
    held-out run, the other means) are Holm-adjusted among themselves and reported,
    never gated. A significant score is "improved" or "regressed" by the sign of the signed-rank
    statistic (``W+ - W-``) and the score's direction; the reported effect is the Hodges-Lehmann
    shift. With n nonzero differences the smallest attainable
    two-sided p is 2 / 2**n, times the number of primary scores under Holm (a note
    says when n is too small to ever reach significance; the command line refuses such a
    run before computing, :func:`~gyrobench.scenarios.bench.power.check_power`).

    The margin enters the test itself: for a score whose shift is worse, the signed-rank test
    runs on ``d_s + direction * min_change * |b_s|`` (lower-is-better: ``c_s - (1 + min_change) b_s``),
    centred on zero when the candidate is worse by exactly the margin; "regressed" needs that test
    significant, with the shift beyond the margin (one-sided at alpha/2: "worse by more than the
    margin"). A better shift is tested the same way against ``1 - min_change``. A change of 0.2 %
    with a 1 % margin is "unchanged" even on every seed. ``detectable`` holds, per primary score,
    the relative change the compared seeds detect with power 0.8 from the spread of the observed
    relative differences (:func:`~gyrobench.scenarios.bench.margin.observed_detectable`).
    """
    if not (isinstance(min_change, (int, float)) and 0 <= min_change < 10):
        raise ValueError(f"min_change must be in [0, 10) (a fraction of the baseline's score); got {min_change!r}")
    if not (isinstance(alpha, (int, float)) and 0 < alpha < 1):
        raise ValueError(f"alpha must be in (0, 1); got {alpha!r}")
    base = baseline if isinstance(baseline, Campaign) else load_baseline(baseline)
    cand = campaign if isinstance(campaign, Campaign) else load_baseline(campaign)
    common = _common_seeds(base, cand)
    names, missing, unpaired = _score_names(base, cand, common)
    cand_failed, base_failed = _failed_seeds(base, cand, common, names)
    failed_seeds = tuple(sorted(s for s in cand_failed if s in cand.scores))
    seeds = tuple(s for s in common if s not in cand_failed and s not in base_failed)
    if not seeds and not failed_seeds:
        raise ComparisonError(
            f"the baseline has no finite scores on the seeds it shares with the campaign "
            f"({seed_text(common)}): re-save it from a compensator that works"
        )
    gates = gates_of(cand.scenario, names, primary, directions, error=ComparisonError)
    dirs = {**directions_of(gates), **(directions or {})}
    gated = {g.name for g in gates}
    paired = [
        _paired(name, base, cand, seeds, dirs, primary=name in gated, unit=score_unit(cand.scenario, name),
                margin=float(min_change))
        for name in names
    ]
    adjusted = np.empty(len(paired))
    for group in (True, False):  # Holm over the primary scores; the secondary among themselves
        idx = [i for i, (p, _) in enumerate(paired) if p.primary == group]
        if idx:
            adjusted[idx] = holm(np.array([paired[i][0].p_value for i in idx]))
    out = tuple(
        _judged(p, sign, float(pa), alpha) for (p, sign), pa in zip(paired, adjusted, strict=True)
    )
    out = tuple(sorted(out, key=lambda s: not s.primary))
    refs = tuple(
        ReferenceMeans(
            label=label,
            compensator=r.compensator,
            means={n: float(np.mean(r.values(n, seeds))) for n in names if r.values(n, seeds).size},
        )
        for label, r in (references or {}).items()
    )
    dropped = sorted(s for s in base_failed if s in common and s not in cand_failed)
    failure = ""
    if failed_seeds:
        first = failed_seeds[0]
        failure = (
            f"compensator {cand.compensator} failed on {len(failed_seeds)} of {len(common)} "
            f"compared seeds (seeds {seed_text(failed_seeds)}; seed {first}: "
            f"{cand_failed[first]}): a campaign with a failed seed never passes the comparison"
        )
    detect = observed_detectable(base, cand, seeds, [g.name for g in gates], alpha, float(min_change))
    return Comparison(
        scores=out,
        seeds=seeds,
        alpha=float(alpha),
        test=(
            TEST + (f", against an equivalence margin of {100 * min_change:g} % of the baseline" if min_change else "")
        ),
        min_change=float(min_change),
        detectable=detect,
        missing=missing,
        unpaired=unpaired,
        note=comparison_note(out, dropped, same_config=base.config == cand.config, alpha=alpha),
        failed_seeds=failed_seeds,
        failure=failure,
        correction=(
            f"Holm over the {len(gates)} primary score(s) at family-wise alpha {alpha:g} (gated); "
            f"the {len(out) - len(gates)} secondary score(s) Holm-adjusted among themselves "
            "(reported, not gated)"
        ),
        references=refs,
    )


def _common_seeds(base: Campaign, cand: Campaign) -> tuple[int, ...]:
    """The candidate's seeds the baseline holds too (refusing another scenario or no overlap)."""
    if base.scenario != cand.scenario:
        raise ValueError(
            f"baseline is of scenario {base.scenario!r}, campaign of {cand.scenario!r}; "
            "a paired comparison needs the same scenario"
        )
    common = tuple(s for s in cand.seeds if s in base.scores)
    if not common:
        raise ComparisonError(
            f"baseline and campaign share no seed (baseline seeds {seed_text(base.seeds)}, "
            f"campaign seeds {seed_text(cand.seeds)}); run the campaign on the baseline's seeds"
        )
    return common


def _score_names(
    base: Campaign, cand: Campaign, common: Sequence[int]
) -> tuple[list[str], tuple[str, ...], tuple[str, ...]]:
    """(the scores to compare, the scores in only one campaign, the scores not in every seed).

    Pairs are made by seed: a score is compared only if every common seed that did not fail
    holds it in both campaigns. A name that changes with the seed (``"unit7_heldout/mse"``)
    cannot be paired and is listed apart, never taken for a failure. A candidate that failed on
    every common seed before any score is compared on all the baseline's scores.
    """
    bnames, cnames = set(base.score_names), set(cand.score_names)
    names = order_scores(bnames & cnames)
    if not names and set(cand.failed) >= set(common):  # failed before any score: compare all
        names, cnames = order_scores(bnames), bnames
    missing = tuple(order_scores(bnames ^ cnames))
    if not names:
        raise ComparisonError(
            "baseline and campaign have no score in common; were they run on the same scenario?"
        )
    ok = [s for s in common if s not in base.failed and s not in cand.failed]
    held = [set(c.scores[s]) for c in (base, cand) for s in ok]
    unpaired = tuple(n for n in names if any(n not in h for h in held))
    names = [n for n in names if n not in unpaired]
    if not names:
        raise ComparisonError(
            f"no score is held by every seed compared ({len(unpaired)} scores, e.g. "
            f"{', '.join(unpaired[:3])}, are not): a score name that changes with the seed "
            "cannot be paired by seed"
        )
    return names, missing, unpaired


def _failed_seeds(
    base: Campaign, cand: Campaign, common: Sequence[int], names: Sequence[str]
) -> tuple[dict[int, str], set[int]]:
    """(candidate seeds that failed -> why, baseline seeds with a non-finite score): the
    candidate's recorded failures plus any common seed with a non-finite compared score."""
    cand_failed = dict(cand.failed)
    base_failed = set(base.failed)
    for s in common:
        if s not in cand_failed:
            bad = [n for n in names if not math.isfinite(cand.scores[s].get(n, math.nan))]
            if bad:
                cand_failed[s] = f"score {bad[0]} is {cand.scores[s].get(bad[0], math.nan)!r}"
        if any(not math.isfinite(base.scores[s].get(n, math.nan)) for n in names):
            base_failed.add(s)
    return cand_failed, base_failed


def _paired(
    name: str,
    base: Campaign,
    cand: Campaign,
    seeds: Sequence[int],
    directions: Mapping[str, int] | None,
    *,
    primary: bool,
    unit: str,
    margin: float = 0.0,
) -> tuple[ScoreComparison, float]:
    """The signed-rank test, means and Hodges-Lehmann shift of score ``name`` over ``seeds``, as a
    comparison not yet corrected for multiplicity (``p_adjusted`` = ``p_value``, status
    "unchanged"), and the sign of ``W+ - W-``."""
    b, c = base.values(name, seeds), cand.values(name, seeds)
    d = c - b
    direction = score_direction(name, directions)
    p, sign = margin_test(d, b, direction, margin)
    bm = float(np.mean(b)) if b.size else math.nan
    cm = float(np.mean(c)) if c.size else math.nan
    comparison = ScoreComparison(
        name=name,
        direction=direction,
        n=int(d.size),
        baseline_mean=bm,
        candidate_mean=cm,
        effect=hodges_lehmann(d) if d.size else math.nan,
        relative=(cm - bm) / abs(bm) if bm != 0 and math.isfinite(bm) else math.nan,
        p_value=p,
        p_adjusted=p,
        status="unchanged",
        primary=primary,
        unit=unit,
    )
    return comparison, sign


def _judged(s: ScoreComparison, sign: float, p_adjusted: float, alpha: float) -> ScoreComparison:
    """The score's status at ``alpha`` after Holm's correction: "improved" or "regressed" by the
    sign of the shift and the score's direction, "changed" when the direction is unknown."""
    if p_adjusted < alpha and sign != 0:
        if s.direction == 0:
            status = "changed"
        else:
            status = "improved" if sign * s.direction > 0 else "regressed"
    else:
        status = "unchanged"
    return replace(s, p_adjusted=p_adjusted, status=status)
