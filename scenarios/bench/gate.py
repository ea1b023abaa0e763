"""The gate of the bench: which scores it judges, what its seeds can detect, the check before a
run and ``--seeds auto``.

- :func:`gates_of`: the primary scores a comparison gates (:mod:`~gyrobench.scenarios.bench.primary`);
- :func:`detectable` and :func:`power_doc`: what a baseline's seeds can detect (stored in the
  baseline file);
- :func:`plan_power`: before anything is computed, the seeds a comparison will pair and whether
  they can reach ``alpha`` (:func:`~gyrobench.scenarios.bench.power.check_power`), and the seed
  count of ``--seeds auto`` (:func:`~gyrobench.scenarios.bench.power.auto_seeds`).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from gyrobench.scenarios.bench.campaign import Campaign
from gyrobench.scenarios.bench.compensators import CompensatorError
from gyrobench.scenarios.bench.power import (
    DEFAULT_MIN_CHANGE,
    DEFAULT_POWER,
    SPREAD_CONFIDENCE,
    TEST,
    Detectable,
    auto_seeds,
    check_power,
    detectable_change,
    min_attainable_p,
    partial_spread,
    spread,
    std_upper_bound,
)
from gyrobench.scenarios.bench.primary import PrimaryScore, gated_scores, primary_count, score_unit
from gyrobench.scenarios.bench.statistics import score_direction

__all__ = ["PowerPlan", "detectable", "gates_of", "plan_power", "power_doc", "reference_campaigns"]


def _json_float(v: float) -> float | None:
    return v if math.isfinite(v) else None


def detectable(
    campaign: Campaign, *, alpha: float = 0.05, power: float = DEFAULT_POWER, min_change: float = DEFAULT_MIN_CHANGE
) -> list[Detectable]:
    """What ``campaign``'s seeds, as a baseline, can detect on each of its primary scores.

    For a primary score with mean ``mu`` and seed-to-seed std ``sigma`` over the campaign's
    ``n`` seeds: the shift :func:`~gyrobench.scenarios.bench.power.detectable_change`
    detects with probability ``power`` at ``alpha`` (Holm over the primary scores) in the mean
    score beyond the margin, assuming per-seed contrasts as spread as the baseline's seeds,
    taken at the upper
    confidence bound of ``sigma``
    (:func:`~gyrobench.scenarios.bench.power.std_upper_bound`); ``inf`` when ``n`` seeds cannot
    reach ``alpha`` at all. The spread includes that of the change itself when half the seeds
    carry it (:func:`~gyrobench.scenarios.bench.power.partial_spread`, the spread ``--seeds auto``
    sizes for): ``change`` solves ``change = detectable_change(partial_spread(sigma_U, mu,
    min_change + change / |mu|))`` by fixed-point iteration (``inf`` when it does not settle: the
    seeds are too few for any change).

    Parameters
    ----------
    campaign : Campaign
        The baseline campaign.
    alpha : float
        Family-wise level.
    power : float
        Detection probability.
    min_change : float
        The equivalence margin [-].

    Returns
    -------
    list of Detectable
        One per primary score.
    """
    names = campaign.score_names
    gates = [g for g in gated_scores(campaign.scenario, names) if g.name in names]
    seeds = campaign.ok_seeds
    out = []
    for g in gates:
        values = campaign.values(g.name, seeds)
        mean, std = spread(values)
        upper = std_upper_bound(values)
        n = len(seeds)
        change = _partial_detectable(upper, mean, n, len(gates), alpha, power, min_change)
        out.append(
            Detectable(
                name=g.name,
                unit=g.unit,
                mean=mean,
                std=std,
                std_upper=upper,
                n=n,
                change=change,
                relative=change / abs(mean) if mean and math.isfinite(mean) else math.inf,
            )
        )
    return out


def _partial_detectable(
    upper: float, mean: float, n: int, m: int, alpha: float, power: float, min_change: float
) -> float:
    """The shift beyond the margin detected when half the seeds carry the change (fixed point)."""
    if not (math.isfinite(upper) and math.isfinite(mean)):
        return math.inf
    change = detectable_change(upper, n, m, alpha, power=power)
    for _ in range(200):
        if not math.isfinite(change) or change > 1e6 * max(upper, abs(mean)):
            return math.inf
        total = min_change + (change / abs(mean) if mean else 0.0)
        new = detectable_change(partial_spread(upper, mean, total), n, m, alpha, power=power)
        if abs(new - change) <= 1e-9 * max(new, 1e-300):
            return new
        change = new
    return math.inf


def power_doc(campaign: Campaign, alpha: float, min_change: float = DEFAULT_MIN_CHANGE) -> dict:
    """A baseline file's ``"power"`` section: what its seeds can detect.

    A baseline file's ``"power"`` section: what its seeds can detect (JSON-ready); with the
    equivalence margin ``min_change``, the relative change detected is the margin plus the
    shift beyond it (``"relative_with_margin"``).

    Parameters
    ----------
    campaign : Campaign
        The baseline campaign.
    alpha : float
        Family-wise level.
    min_change : float
        The equivalence margin [-].

    Returns
    -------
    dict
        The section.
    """
    found = detectable(campaign, alpha=alpha, min_change=min_change)
    m = max(1, len(found))
    n = len(campaign.ok_seeds)
    return {
        "test": TEST,
        "statistic": "relative change of the mean score over the paired seeds",
        "correction": f"Holm over the {len(found)} primary score(s)",
        "alpha": alpha,
        "power": DEFAULT_POWER,
        "seeds": n,
        "min_attainable_p": min_attainable_p(n, m),
        "assumption": (
            "per-seed contrasts (c_s - b_s - margin |b_s|) as spread as this baseline's seed-to-seed "
            "values, at the "
            f"one-sided {100 * SPREAD_CONFIDENCE:g} % upper confidence bound of their std (Bonett 2006), "
            "plus the spread of the change itself when a random half of the seeds carry it"
        ),
        "spread_confidence": SPREAD_CONFIDENCE,
        "margin": min_change,
        "detectable": {
            d.name: {
                "unit": d.unit,
                "mean": _json_float(d.mean),
                "std": _json_float(d.std),
                "std_upper": _json_float(d.std_upper),
                "change": _json_float(d.change),  # None: cannot detect any change
                "relative": _json_float(d.relative),
                "relative_with_margin": _json_float(min_change + d.relative),
            }
            for d in found
        },
    }


def gates_of(
    scenario: str,
    names: Sequence[str],
    primary: Sequence[str] | None,
    directions: Mapping[str, int] | None,
    *,
    error: type[Exception] = ValueError,
) -> tuple[PrimaryScore, ...]:
    """The primary scores to gate, all among the compared ``names`` (else ``error``, one line).

    Parameters
    ----------
    scenario : str
        The scenario.
    names : sequence of str
        The compared scores' names.
    primary : sequence of str or None
        The primary scores asked for (None: the scenario's).
    directions : mapping of str to int or None
        Directions declared by name.
    error : type
        The exception raised for an unknown primary score.

    Returns
    -------
    tuple of PrimaryScore
        The gated scores.
    """
    if primary is None:
        gates = gated_scores(scenario, names)
    else:
        if isinstance(primary, str) or not primary:
            raise ValueError(f"primary must be a non-empty sequence of score names; got {primary!r}")
        given = []
        for n in primary:
            d = score_direction(n, directions)
            if d == 0:
                raise ValueError(
                    f"primary score {n!r} has no known direction: give it in directions={{{n!r}: -1 or +1}}"
                )
            given.append(PrimaryScore(name=n, unit=score_unit(scenario, n), direction=d))
        gates = tuple(given)
    absent = [g.name for g in gates if g.name not in names]
    if absent or not gates:
        raise error(
            f"primary score(s) {', '.join(absent) or '(none)'} of {scenario} are not held by both "
            f"campaigns on every compared seed (compared: {', '.join(names[:6])}"
            f"{', ...' if len(names) > 6 else ''}): a regression cannot be judged"
        )
    return gates




@dataclass(frozen=True, slots=True, kw_only=True)
class PowerPlan:
    """The seeds a run will use and what its gate can do, settled before anything is computed.

    ``primary`` is the number of gated scores (None when not known before the run: a scenario
    that declares none, without a baseline); ``warning`` the underpowered warning (only with
    ``allow_underpowered``); ``auto`` the reason line of ``--seeds auto``.

    Attributes
    ----------
    seeds : tuple of int
        The seeds the run uses.
    primary : int or None
        The number of gated scores (None: not known before the run).
    warning : str
        The underpowered warning (only with ``allow_underpowered``).
    auto : str
        The reason line of ``--seeds auto``.
    """

    seeds: tuple[int, ...]
    primary: int | None
    warning: str = ""
    auto: str = ""


def plan_power(
    scenario: str,
    seeds: tuple[int, ...] | str | None,
    *,
    baseline: Campaign | None,
    alpha: float,
    gate: bool,
    allow_underpowered: bool = False,
    min_change: float = DEFAULT_MIN_CHANGE,
    default: Sequence[int] = tuple(range(20)),
    seeds_flag: str = "--seeds",
    allow_flag: str = "--allow-underpowered",
) -> PowerPlan:
    """Settle the seeds of a run and check that its gate can fire with them.

    Settle the seeds of a run (``"auto"``, given, or the baseline's / ``default``) and check
    that the gate can fire with them.

    ``gate``: the run compares with ``baseline`` or writes a baseline, so its seeds must be
    able to reach ``alpha`` with the scenario's primary scores
    (:func:`~gyrobench.scenarios.bench.power.check_power`; the paired seeds are those shared
    with ``baseline``).

    Parameters
    ----------
    scenario : str
        The scenario.
    seeds : tuple of int, str or None
        The seeds given, ``"auto"``, or None (the baseline's, else ``default``).
    baseline : Campaign or None
        The baseline compared with.
    alpha : float
        Family-wise level.
    gate : bool
        The run gates (a baseline comparison).
    allow_underpowered : bool
        Warn instead of refusing an underpowered gate.
    min_change : float
        The equivalence margin [-].
    default : sequence of int
        The seeds when none are given and there is no baseline.
    seeds_flag, allow_flag : str
        The flags named in the messages.

    Returns
    -------
    PowerPlan
        The seeds and what the gate can do.

    Raises
    ------
    UnderpoweredError
        If the gate cannot reach ``alpha`` and ``allow_underpowered`` is false.
    ValueError
        If ``"auto"`` cannot be sized (no primary scores known) or asks for more seeds than the
        baseline holds.
    """
    m = primary_count(scenario, baseline.score_names if baseline is not None else None)
    reason = ""
    if seeds == "auto":
        if m is None:
            raise ValueError(
                f"{seeds_flag} auto: scenario {scenario!r} declares no primary scores and no baseline "
                f"gives its score names; give {seeds_flag} explicitly"
            )
        spreads: dict[str, tuple[float, float, float]] = {}
        units: dict[str, str] = {}
        if baseline is not None:
            for g in gated_scores(scenario, baseline.score_names):
                if g.name in baseline.score_names:
                    values = baseline.values(g.name, baseline.ok_seeds)
                    spreads[g.name] = (*spread(values), std_upper_bound(values))
                    units[g.name] = g.unit
        chosen = auto_seeds(m, alpha, spreads=spreads or None, units=units, min_change=min_change)
        reason = chosen.reason
        if baseline is not None:
            have = sorted(baseline.ok_seeds)
            if chosen.n > len(have):
                raise ValueError(
                    f"{reason}; but the baseline holds only {len(have)} seeds: re-save it on "
                    f"{seeds_flag} 0:{chosen.n}"
                )
            resolved = tuple(have[: chosen.n])
        else:
            resolved = tuple(range(chosen.n))
    elif seeds is None:
        resolved = baseline.seeds if baseline is not None else tuple(default)
    elif isinstance(seeds, str):
        raise ValueError(f"{seeds_flag} must be a seed list or 'auto'; got {seeds!r}")
    else:
        resolved = tuple(seeds)
    warning = ""
    if gate and m is not None:
        n = len(set(resolved) & set(baseline.seeds)) if baseline is not None else len(resolved)
        warning = check_power(
            n, m, alpha, allow_underpowered=allow_underpowered, seeds_flag=seeds_flag, allow_flag=allow_flag
        )
    return PowerPlan(seeds=resolved, primary=m, warning=warning, auto=reason)


def reference_campaigns(
    module: Any, seeds: Sequence[int], *, config: Any = None, executor: Any = None, workers: int | None = None,
    db: Any = None,
) -> dict[str, Campaign]:
    """The reference compensators' campaigns on the given seeds, by label.

    label -> campaign of the reference compensators on ``seeds``: ``"uncompensated"`` (the raw
    output, :data:`~gyrobench.scenarios.bench.references.UNCOMPENSATED`) and the paper's method
    when the scenario names one (its ``BENCH_SCORES``, :func:`~gyrobench.scenarios.bench.primary.scenario_scores`).
    Run into ``db`` like any campaign, so a second run reads them back. A reference whose
    compensator raises on a seed is left out with a warning (it never fails the user's run).

    Parameters
    ----------
    module : module
        The scenario.
    seeds : sequence of int
        The seeds.
    config : object
        The scenario's Config (None: its default).
    executor : concurrent.futures.Executor or None
        Where the seeds run.
    workers : int or None
        Local worker processes.
    db : path-like or None
        The results database (None: none kept).

    Returns
    -------
    dict of str to Campaign
        ``"uncompensated"`` and, when the scenario names one, the paper's method.
    """
    from gyrobench.scenarios.bench.campaign import run_campaign
    from gyrobench.scenarios.bench.primary import scenario_scores
    from gyrobench.scenarios.bench.references import UNCOMPENSATED
    from gyrobench.scenarios.bench.scoring import resolve_scenario

    module = resolve_scenario(module)
    declared = scenario_scores(module)
    refs = {"uncompensated": UNCOMPENSATED}
    if declared is not None and declared.paper:
        refs[declared.paper_label or "paper"] = declared.paper
    kw: dict[str, Any] = {"db": db} if db is not None else {}
    out = {}
    for label, comp in refs.items():
        try:
            out[label] = run_campaign(
                module, comp, seeds, config=config, executor=executor, workers=workers, progress=False,
                sandbox=False, **kw
            )
        except (CompensatorError, TypeError) as exc:  # a reference that cannot run never fails the run
            warnings.warn(f"reference {label} ({comp}) not shown: {exc}", stacklevel=2)
    return out
