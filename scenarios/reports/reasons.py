"""Measured reasons and findings, written from a report's claim documents.

Every phrase here is built from the fields of a judged claim as results.json stores it
(:meth:`gyrobench.scenarios.claims.ClaimResult.as_dict`): the median of the units' quantity,
the paper's value, the pass count, the units lacking the precondition, the control's pass
count and Fisher's p-value. No text of a finding is written by hand, so a referee can recount
every figure from the per-unit quantities beside it (``unit_quantities`` and
``control_quantities`` in the same results.json).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

__all__ = ["calibrated_count", "calibrated_text", "findings", "measured", "reason", "short_statement"]

#: statuses that are a failure or leave the claim open: each gets its measured reason
FAILED = ("contradicted", "device not matched", "undecided", "not testable", "not reproducible on this device",
          "no different from the control", "below the control")


def _fmt(x: Any) -> str:
    from gyrobench.scenarios.reports.claim_tables import fmt

    return fmt(float(x)) if isinstance(x, (int, float)) and not isinstance(x, bool) else fmt(x)


def _with_unit(x: Any, unit: str) -> str:
    return _fmt(x) + (f" {unit}" if unit and unit != "-" else "")  # "-": a pure number


def measured(c: Mapping[str, Any]) -> str:
    """The claim's measurement in one phrase: ``"median 16.9 % vs the paper's 0.4 %; 3 of 20 units pass"``.

    Parameters
    ----------
    c : mapping
        A claim document (results.json ``claims`` entry).

    Returns
    -------
    str
        The median (with the paper's value when it gives one, else the criterion) and the pass
        count; for a yes/no claim only the pass count.
    """
    unit = c.get("unit") or ""
    passes = f"{c['holds']} of {c['testable']} units pass"
    if c.get("median") is None:
        return f"no unit gave a value ({c['units']} simulated)"
    if c.get("comparator") == "true for the unit":
        return passes
    paper = (f" vs the paper's {_with_unit(c['paper_value'], unit)}" if c.get("paper_value") is not None
             else f", criterion {c['comparator']}")
    return f"median {_with_unit(c['median'], unit)}{paper}; {passes}"


def reason(c: Mapping[str, Any]) -> str:
    """Why a claim failed or could not be decided, from its measurements; ``""`` for a claim that holds.

    Parameters
    ----------
    c : mapping
        A claim document (results.json ``claims`` entry).

    Returns
    -------
    str
        ``"precondition absent on 17 of 20 units: <the precondition>"`` (not reproducible),
        ``"units 20/20 pass, control 17/20; Fisher p = 0.23"`` (no different from or below the
        control), ``"no unit could test it ..."`` (not testable), else :func:`measured` with the
        side most misses fall on.
    """
    status = c.get("status", "")
    if status not in FAILED:
        return ""
    if status == "not reproducible on this device":
        pre = c.get("precondition") or {}
        return (f"precondition absent on {c['precondition_absent']} of {c['units']} units: "
                f"{pre.get('text', 'the precondition')}")
    if status in ("no different from the control", "below the control"):
        ctrl, test = c.get("control") or {}, c.get("control_test") or {}
        p = test.get("p_value")
        return (f"units {c['holds']}/{c['testable']} pass, control {ctrl.get('holds')}/{ctrl.get('testable')}"
                + ("" if p is None else f"; Fisher p = {p:.2g}"))
    if status == "not testable":
        absent = c.get("precondition_absent") or 0
        why = f"; precondition absent on {absent}" if absent else ""
        return f"no unit could test it (0 of {c['units']} units gave a value{why})"
    text = measured(c)
    direction = (c.get("misses") or {}).get("direction")
    if direction in ("below", "above") and c.get("comparator") != "true for the unit":
        text += f", most misses {direction} the band"
    return text


def calibrated_count(claims: Sequence[Mapping[str, Any]]) -> tuple[int, int, dict[str, int]]:
    """How many claims are calibrated (an input was set from them by an identification).

    Parameters
    ----------
    claims : sequence of mapping
        Claim documents (results.json ``claims`` entries), of one paper or of all.

    Returns
    -------
    tuple of (int, int, dict)
        The calibrated claims, all claims, and the calibrated claims per role.
    """
    cal = [c for c in claims if c.get("kind") == "calibrated"]
    roles: dict[str, int] = {}
    for c in cal:
        roles[c.get("role", "method")] = roles.get(c.get("role", "method"), 0) + 1
    return len(cal), len(claims), roles


def calibrated_text(claims: Sequence[Mapping[str, Any]]) -> str:
    """One sentence: how many claims are calibrated (set by an identification), by role; not evidence.

    Parameters
    ----------
    claims : sequence of mapping
        Claim documents (results.json ``claims`` entries).

    Returns
    -------
    str
        E.g. ``"7 of 40 claims are calibrated (device 5, method 2): ..."``.
    """
    n, total, roles = calibrated_count(claims)
    by_role = ", ".join(f"{k} {v}" for k, v in sorted(roles.items()))
    return (f"{n} of {total} claims are calibrated" + (f" ({by_role})" if by_role else "")
            + ": an input of the simulation was set from them by an identification, so they hold by "
            "construction and are not evidence.")


#: a parenthesis of a claim's statement longer than this (a scoring note) is left out of a finding
ASIDE_CHARS = 40


def short_statement(statement: str) -> str:
    """A claim's statement without its long parentheses (how it is scored, kept in the claims table).

    Parameters
    ----------
    statement : str
        The claim's statement.

    Returns
    -------
    str
        ``statement`` without the parentheses longer than :data:`ASIDE_CHARS` and its final full stop.
    """
    out, depth, start = [], 0, 0
    spans: list[tuple[int, int]] = []
    for i, ch in enumerate(statement):
        if ch == "(":
            if depth == 0:
                start = i
            depth += 1
        elif ch == ")" and depth:
            depth -= 1
            if depth == 0 and i - start > ASIDE_CHARS:
                spans.append((start, i + 1))
    last = 0
    for a, b in spans:
        out.append(statement[last:a].rstrip())
        last = b
    out.append(statement[last:])
    return "".join(out).strip().rstrip(".")


def _quoted(c: Mapping[str, Any]) -> str:
    return f"{c['where']}, \"{short_statement(c['statement'])}\""


def _brief(c: Mapping[str, Any]) -> str:
    """A finding's measurement: ``"median 0.385 % vs the paper's 0.59 %, 16/19 units, control 0/20"``."""
    ctrl = c.get("control")
    counts = f"{c['holds']}/{c['testable']} units" + (f", control {ctrl['holds']}/{ctrl['testable']}" if ctrl else "")
    if c.get("median") is None or c.get("comparator") == "true for the unit":
        return counts
    unit = c.get("unit") or ""
    ref = (f"the paper's {_with_unit(c['paper_value'], unit)}" if c.get("paper_value") is not None
           else c["comparator"])
    return f"median {_with_unit(c['median'], unit)} vs {ref}, {counts}"


def findings(doc: Mapping[str, Any], name: str) -> str:
    """One paper's findings as a Markdown bullet, every figure from its results.json document.

    Parameters
    ----------
    doc : mapping
        A paper's results.json document (with ``claims``).
    name : str
        How the bullet names the paper (e.g. ``"001 Du et al."``).

    Returns
    -------
    str
        ``"- **name:** ..."``: the counted method claims reproduced and contradicted, each with
        its median against the paper's value (or criterion) and its pass counts on the units and the
        control, those not reproducible on this device
        grouped by their reason, and the count of the others by status.
    """
    method = [c for c in doc["claims"] if c.get("role", "method") == "method" and not c.get("same_effect_as")]
    held = [c for c in method if c["status"] == "reproduced" and c["kind"] == "emergent"]
    failed = [c for c in method if c["status"] == "contradicted"]
    parts = []
    if held:
        parts.append("reproduced: " + "; ".join(f"{_quoted(c)} ({_brief(c)})" for c in held))
    if failed:
        parts.append("contradicted: " + "; ".join(f"{_quoted(c)} ({_brief(c)})" for c in failed))
    absent = [c for c in method if c["status"] == "not reproducible on this device"]
    if absent:
        by_reason: dict[str, list[str]] = {}
        for c in absent:
            by_reason.setdefault(reason(c), []).append(c["where"])
        parts.append("not reproducible on this device: " + "; ".join(
            f"{', '.join(dict.fromkeys(where))} ({why})" for why, where in by_reason.items()))
    others: dict[str, int] = {}
    for c in method:
        if c not in held and c not in failed and c not in absent:
            key = "calibrated" if c["status"] == "reproduced" else c["status"]
            others[key] = others.get(key, 0) + 1
    if others:
        parts.append("the other method claims: " + ", ".join(f"{v} {k}" for k, v in others.items()))
    body = ". ".join(p[0].upper() + p[1:] for p in parts) if parts else "No method claim"
    return f"- **{name}** ({len(method)} method claims over {doc['units']} units): {body}."
