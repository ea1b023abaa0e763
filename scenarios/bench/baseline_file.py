"""Baseline files: a campaign's per-seed scores saved to JSON, read back, and the checks made
before a campaign that its baseline can be written or compared.

:func:`save_baseline` writes a campaign's per-seed scores (and what its seeds can detect,
:func:`~gyrobench.scenarios.bench.gate.power_doc`); :func:`load_baseline` reads one back as a
:class:`~gyrobench.scenarios.bench.campaign.Campaign`. The paired comparison of a new campaign
against a baseline is :func:`gyrobench.scenarios.bench.baseline.compare`.
"""

from __future__ import annotations

import json
import math
import os
import types
from collections.abc import Iterable
from pathlib import Path

from gyrobench.scenarios.bench.campaign import Campaign
from gyrobench.scenarios.bench.compensators import FailedSeedsError
from gyrobench.scenarios.bench.gate import power_doc
from gyrobench.scenarios.bench.power import DEFAULT_MIN_CHANGE
from gyrobench.scenarios.bench.scoring import resolve_scenario
from gyrobench.scenarios.bench.seeds import check_seeds, parse_seeds, seed_text
from gyrobench.scenarios.runner.store import check_output_file

__all__ = [
    "BASELINE_FORMAT",
    "BASELINE_VERSION",
    "check_baseline_matches",
    "check_baseline_path",
    "load_baseline",
    "save_baseline",
]

BASELINE_FORMAT = "gyrobench-baseline"
BASELINE_VERSION = 1


def check_baseline_path(path: str | os.PathLike, *, what: str = "baseline path") -> Path:
    """Check, before a campaign, that :func:`save_baseline` can write ``path``.

    Parameters
    ----------
    path : str or os.PathLike
        The baseline file to be written.
    what : str
        How the messages name it (``"--save-baseline 'b.json'"``).

    Returns
    -------
    pathlib.Path
        ``path`` as a path.

    Raises
    ------
    IsADirectoryError
        If ``path`` is a folder.
    FileNotFoundError
        If its folder does not exist (it is not created).
    PermissionError
        If its folder does not accept new files.
    """
    return check_output_file(path, what=what)


def check_baseline_matches(
    baseline: Campaign,
    scenario: str | types.ModuleType,
    seeds: Iterable[int] | str | None = None,
    *,
    what: str = "baseline",
    seeds_what: str = "seeds",
) -> None:
    """Check, before a campaign, that its result can be compared with ``baseline``.

    :func:`compare` needs the same scenario and at least one common seed; this
    refuses a mismatch before anything is computed. ``what`` and ``seeds_what`` name
    the baseline and the seeds in the messages (``"--baseline 'b.json'"``, ``"--seeds"``).

    Parameters
    ----------
    baseline : Campaign
        The baseline, as :func:`load_baseline` read it.
    scenario : str or module
        The campaign's scenario: a registered name, an importable module path or a module.
    seeds : iterable of int or str, optional
        The campaign's seeds (a list, or text such as ``"0-9"``); None: the baseline's.
    what : str
        How the messages name the baseline.
    seeds_what : str
        How the messages name the seeds.

    Raises
    ------
    ValueError
        If ``baseline`` is of another scenario, or ``seeds`` (when given) share no
        seed with it.
    """
    module = resolve_scenario(scenario)
    name = getattr(module, "NAME", module.__name__)
    if baseline.scenario != name:
        raise ValueError(
            f"{what} is of scenario {baseline.scenario!r}, not {name!r}; "
            "a paired comparison needs the same scenario"
        )
    if seeds is not None:
        seeds = parse_seeds(seeds) if isinstance(seeds, str) else check_seeds(seeds)
        if not set(seeds) & set(baseline.seeds):
            raise ValueError(
                f"{seeds_what} must share seeds with {what} (its seeds: "
                f"{seed_text(baseline.seeds)}); got {seed_text(seeds)} "
                f"(omit {seeds_what} to use the baseline's)"
            )


def _json_float(v: float) -> float | None:
    return v if math.isfinite(v) else None


def save_baseline(
    path: str | os.PathLike, campaign: Campaign, *, alpha: float = 0.05, min_change: float = DEFAULT_MIN_CHANGE
) -> Path:
    """Write ``campaign``'s per-seed scores to a JSON baseline (atomically).

    The file also stores, under ``"power"``, what its seeds can detect on each primary score
    at ``alpha`` with the equivalence margin ``min_change``
    (:func:`~gyrobench.scenarios.bench.gate.detectable`).

    Parameters
    ----------
    path : str or os.PathLike
        The JSON file to write (its folder must exist; an existing file is replaced atomically).
    campaign : Campaign
        A finished campaign with no failed seed.
    alpha : float
        Family-wise error rate [-] at which the stored power is computed, in (0, 1).
    min_change : float
        Equivalence margin [-], a fraction of the baseline's per-seed score.

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    TypeError
        If ``campaign`` is not a :class:`Campaign`.
    FailedSeedsError
        If the campaign failed on a seed (a baseline never holds a failed seed).
    IsADirectoryError, FileNotFoundError
        If ``path`` is a folder or its folder does not exist (folders are never
        created).
    """
    from gyrobench.base.atomic import atomic_path
    from gyrobench.io.recording import package_version

    if not isinstance(campaign, Campaign):
        raise TypeError(f"campaign must be a Campaign; got {type(campaign).__name__}")
    path = check_baseline_path(path)
    if campaign.failed:
        raise FailedSeedsError(
            f"not saving baseline {str(path)!r}: {campaign.failure_text()}",
            seeds=sorted(campaign.failed),
        )
    doc = {
        "format": BASELINE_FORMAT,
        "format_version": BASELINE_VERSION,
        "gyrobench_version": package_version(),
        "campaign_id": campaign.campaign_id,
        "scenario": campaign.scenario,
        "compensator": campaign.compensator,
        "config": campaign.config,
        "seeds": list(campaign.seeds),
        "scores": {
            str(s): {k: (v if math.isfinite(v) else None) for k, v in sc.items()}
            for s, sc in campaign.scores.items()
        },
        "summary": {
            n: {
                "mean": _json_float(s.mean),
                "low": _json_float(s.low),  # None: no interval (one seed)
                "high": _json_float(s.high),
                "n": s.n,
                "interval": s.method,
            }
            for n, s in campaign.summary().items()
        },
        "power": power_doc(campaign, alpha, min_change),
    }
    text = json.dumps(doc, indent=1, allow_nan=False, default=lambda o: None) + "\n"
    with atomic_path(path) as tmp:
        tmp.write_text(text)
    return path


def load_baseline(path: str | os.PathLike) -> Campaign:
    """Read a baseline written by :func:`save_baseline`.

    Parameters
    ----------
    path : str or os.PathLike
        The baseline's JSON file.

    Returns
    -------
    Campaign
        Its per-seed scores (a ``null`` score read as NaN), with ``db`` set to the file's path.

    Raises
    ------
    FileNotFoundError
        If the file does not exist.
    ValueError
        If it is not a gyrobench baseline.
    """
    p = Path(path)
    if not p.is_file():
        raise FileNotFoundError(f"baseline file not found: {str(p)!r}")
    try:
        doc = json.loads(p.read_text())
        if doc.get("format") != BASELINE_FORMAT:
            raise ValueError(f"format is {doc.get('format')!r}, not {BASELINE_FORMAT!r}")
        if int(doc.get("format_version", 1)) > BASELINE_VERSION:
            raise ValueError(
                f"format_version must be <= {BASELINE_VERSION} (written by a newer gyrobench?); "
                f"got {doc.get('format_version')!r}"
            )
        scores = {
            int(s): {k: (math.nan if v is None else float(v)) for k, v in sc.items()}
            for s, sc in doc["scores"].items()
        }
        return Campaign(
            campaign_id=str(doc["campaign_id"]),
            scenario=str(doc["scenario"]),
            compensator=str(doc["compensator"]),
            config=str(doc["config"]),
            scores=dict(sorted(scores.items())),
            db=str(p),
        )
    except RecursionError:  # JSON nested thousands deep (a baseline is a flat table of scores)
        raise ValueError(f"baseline {str(p)!r} is not a gyrobench baseline file: it nests values too deeply") from None
    except (ValueError, KeyError, TypeError, AttributeError) as exc:
        raise ValueError(f"baseline {str(p)!r} is not a gyrobench baseline file: {exc}") from None
