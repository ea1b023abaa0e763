"""The claims' tables of a report: each claim's row and status text, the tally of claims by role
and status, the deviations' effects, and the number format every table uses."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

from gyrobench.scenarios.base import Headline, Outcome, Table
from gyrobench.scenarios.reports.reasons import reason

__all__ = ["claim_tally", "fmt", "status_text", "tally_table", "tally_text"]


def fmt(x: Any) -> str:
    """Format a table cell: 4 significant digits for floats, text as is, None as 'n/a'.

    Parameters
    ----------
    x : object
        A cell's value.

    Returns
    -------
    str
        The cell's text.
    """
    if x is None:
        return "n/a"
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, float):
        if math.isnan(x):
            return "n/a"
        if x == 0 or 1e-3 <= abs(x) < 1e5:
            return f"{x:.4g}"
        return f"{x:.3e}"
    return str(x)


def _holds(h: Headline) -> str:
    return {True: "yes", False: "NO", None: "-"}[h.holds]


def _summary_rows(outcomes: Sequence[Outcome]) -> list[list[str]]:
    rows = []
    for o in outcomes:
        for h in o.headlines:
            rows.append([o.scenario, h.quantity, h.reproduced, h.target, _holds(h), h.note])
    return rows


_SUMMARY_COLUMNS = ["scenario", "quantity", "reproduced", "paper / target", "conclusion holds", "note"]

#: the claims table of a paper, in the scenario's section
#: status second: the verdict stays on screen however wide the statement and the numbers are
_CLAIM_COLUMNS = ["claim", "status", "paper's statement", "where", "role", "paper", "criterion",
                  "ours: median [IQR]", "holds / testable", "pass rate [95 % CI]", "control"]


def _paper_heading(outcome: Outcome) -> str:
    """The paper's citation (:func:`gyrobench.scenarios.papers.citation`) for a paper scenario."""
    from gyrobench.scenarios import papers

    keys = sorted({c.claim.paper for c in outcome.claims} | {d.paper for d in outcome.deviations})
    out = []
    for k in keys:
        try:
            out.append(papers.citation(k))
        except KeyError:
            out.append(f"paper {k} (no entry in scenarios.papers)")
    return "; ".join(out)


def _num(x: float | None, unit: str = "") -> str:
    if x is None:
        return "n/a"
    return f"{fmt(float(x))}{' ' + unit if unit else ''}"


def status_text(r: Any) -> str:
    """A judged claim's status for a table, with its measured reason.

    A judged claim's status for a table: upper case, with provisional and, for a claim that failed or
    stays open, its measured reason (:func:`gyrobench.scenarios.reports.reasons.reason`).

    Parameters
    ----------
    r : ClaimResult
        The judged claim.

    Returns
    -------
    str
        Upper case, with "provisional" and, for a claim that failed or stays open, the reason.
    """
    status = r.status
    word = status.upper() if status in ("reproduced", "contradicted", "device matched", "device not matched",
                                        "no different from the control", "below the control") else status
    if r.claim.kind == "calibrated" and r.claim.role == "method" and status == "reproduced":
        word = "CALIBRATED (not counted)"
    notes = []
    if r.provisional:
        notes.append("provisional")
    why = reason(r.as_dict())
    if why:
        notes.append(why)
    if r.claim.same_effect_as:
        notes.append(f"same effect as {r.claim.same_effect_as}: counted once")
    return word + (f" ({'; '.join(notes)})" if notes else "")


def _claim_row(r: Any) -> list[str]:
    """One claims-table row from a :class:`~gyrobench.scenarios.claims.ClaimResult`."""
    c = r.claim
    role = c.role + (" (calibrated)" if c.kind == "calibrated" else "")
    ours = "n/a" if r.median is None else f"{_num(r.median, c.unit)} [{fmt(r.spread[0])}, {fmt(r.spread[1])}]"
    if r.testable:
        lo, hi = r.interval95
        rate = f"{100 * r.pass_rate:.0f} % [{100 * lo:.0f}, {100 * hi:.0f}] %"
    else:
        rate = "n/a"
    counts = f"{r.holds} / {r.testable}" + (f" ({r.precondition_absent} lack the precondition)"
                                            if r.precondition_absent else "")
    control = "-" if r.control is None else f"{r.control.holds} / {r.control.testable}"
    return [c.id, status_text(r), c.statement, c.where, role, _num(c.paper_value, c.unit),
            c.comparator.text(c.unit), ours, counts, rate, control]


def claim_tally(claims: Sequence[Any]) -> Any:
    """The :class:`~gyrobench.scenarios.claims.ClaimTally` of judged claims.

    Parameters
    ----------
    claims : sequence of ClaimResult
        Judged claims.

    Returns
    -------
    ClaimTally
        Their counts.
    """
    from gyrobench.scenarios.claims import tally

    return tally(claims)


def tally_text(n: Any) -> str:
    """One line: device matched, method claims by status, extensions.

    Parameters
    ----------
    n : ClaimTally
        The counts.

    Returns
    -------
    str
        One line.
    """
    dev = f"device matched on {n.device_matched} of {n.device} device claim(s); " if n.device else ""
    ext = f"; extensions (ours): {n.extension_reproduced} of {n.extension} hold" if n.extension else ""
    ext += f"; {n.same_effect} claim(s) counted with the claim showing the same effect" if n.same_effect else ""
    return (
        f"{dev}method claims: {n.reproduced} reproduced, {n.contradicted} CONTRADICTED, "
        f"{n.not_reproducible} not reproducible on this device, {n.identity} no different from (or below) the control, "
        f"{n.undecided} undecided, {n.not_testable} not testable, {n.calibrated} calibrated (not counted){ext}"
    )


def _sequential_note(o: Outcome) -> str:
    """With ``--units auto``: the looks and the group-sequential z every verdict was judged at."""
    seq = o.results.get("sequential") if isinstance(o.results, dict) else None
    if not seq:
        return ""
    return (f" Units were added until claims were decided (looks at {', '.join(map(str, seq['looks']))} units); "
            f"every verdict uses the Wilson interval at z = {seq['z']:.3f} instead of 1.96, so that a claim whose "
            f"true pass rate is 50 % is decided with probability {100 * seq['error_at_50_percent']:.1f} % (<= 5 %).")


def _claims_table(o: Outcome) -> Table:
    if o.units > 1:
        over = (f"Judged over {o.units} units (seeds {o.seed} to {o.seed + o.units - 1}; each unit has its own "
                "noise and drawn parameters).")
    else:
        over = f"One unit (seed {o.seed}): a quick look; no verdict can be reached on one unit."
    note = (
        f"{over} {tally_text(claim_tally(o.claims))}.{_sequential_note(o)} A verdict needs the 95 % Wilson "
        "interval of the pass rate "
        "entirely above (holds) or below (fails) 50 %; it is provisional when the interval ends within 5 points "
        "of 50 %. Device claims are what the simulated device was matched to; method claims are the paper's "
        "results on it, judged only on units that show the effect (the precondition); 'control' is the same "
        "claim on the same seeds with the paper's effect switched off, and a claim whose pass rate there is not "
        "distinguishable from the units' (Fisher's exact test, two-sided, 5 %) is no different from the "
        "control (unless it fails on both: contradicted), and one passing significantly less often on the "
        "units is below the control: neither is a finding. A calibrated claim (an input was set from the "
        "paper's number) is not counted as reproduced."
    )
    return Table(f"Claims of {_paper_heading(o)}", _CLAIM_COLUMNS, [_claim_row(r) for r in o.claims], note=note)


def deviation_effect_text(d: Any, effects: Sequence[Any]) -> str:
    """The measured-effect cell of a deviation: this run's measurement, or why there is none."""
    by_variant = {e.variant: e for e in effects}
    variant = getattr(d, "variant", None)
    if variant and variant in by_variant:
        return f"variant '{variant}' {by_variant[variant].text()}"
    legacy = f" An earlier run's note: {d.effect}" if d.effect else ""
    if not variant:
        return "no config variant: not measurable by a run." + legacy
    return f"not measured in this run (gyrobench reproduce --deviations runs variant '{variant}')." + legacy


def _deviations_table(o: Outcome) -> Table:
    rows = [[d.what, d.paper_says, d.we_do, d.reason, deviation_effect_text(d, o.deviation_effects)]
            for d in o.deviations]
    return Table(
        "Deviations from the paper's protocol",
        ["what", "the paper", "this simulation", "why", "measured effect on the claims"],
        rows,
        note="" if rows else "No departure from a protocol the paper states.",
    )


def _mark_verdicts(text: str) -> str:
    """Colour the status cells of an HTML claims table (failures as prominent as successes)."""
    import re

    for word, cls in (("REPRODUCED", "yes"), ("DEVICE MATCHED", "yes"), ("CONTRADICTED", "no"),
                      ("DEVICE NOT MATCHED", "no"), ("NO DIFFERENT FROM THE CONTROL", "cal"),
                      ("BELOW THE CONTROL", "cal"), ("CALIBRATED (not counted)", "cal")):
        text = re.sub(rf"<td(?: class='txt')?>({re.escape(word)}(?: \([^<]*\))?)</td>", rf"<td class='{cls}'>\1</td>",
                      text)
    return text


def tally_table(outcomes: Sequence[Outcome]) -> Table:
    """The status of every paper's claims in one table (the report's first screen).

    Parameters
    ----------
    outcomes : sequence of Outcome
        The scenarios' outcomes.

    Returns
    -------
    Table
        One row per paper.
    """
    cols = ["scenario", "paper", "units", "device matched", "device calibrated", "method: reproduced",
            "CONTRADICTED", "not reproducible on this device", "no different from / below the control", "undecided",
            "not testable", "method calibrated (not counted)", "extensions: hold / all"]
    rows: list[list[Any]] = []
    for o in outcomes:
        if not (o.claims or o.deviations):
            continue
        n = claim_tally(o.claims)
        papers = ", ".join(sorted({c.claim.paper for c in o.claims})) or "-"
        rows.append([o.scenario, papers, o.units, f"{n.device_matched} / {n.device}",
                     f"{n.device_calibrated} / {n.device}", n.reproduced, n.contradicted,
                     n.not_reproducible, n.identity, n.undecided, n.not_testable, n.calibrated,
                     f"{n.extension_reproduced} / {n.extension}"])
    return Table(
        "Claims at a glance", cols, rows,
        note="Per paper: how many device claims the simulated device matches and how many of them are "
        "calibrated (an input of the device was set from them: matched by construction), and the paper's method "
        "claims by status. Each paper's section gives every claim with its interval, precondition and control.",
    )
