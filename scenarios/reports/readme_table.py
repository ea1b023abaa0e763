"""The reproduced-results table (docs/results.md) and its summary (README.md), generated from a
report's results.json files.

::

    python -m gyrobench.scenarios.reports.readme_table gyrobench-report            # print the table
    python -m gyrobench.scenarios.reports.readme_table gyrobench-report --splice docs/results.md --summary README.md

The table is built from the same ``claims`` lists the report's summary shows (see
:func:`gyrobench.scenarios.claims.ClaimResult.as_dict`), one row per claim, so the docs and
the report can never disagree; the summary is the table's first part (one tally row per
paper and the physics checks' count). ``--splice FILE`` writes the full table and
``--summary FILE`` the summary, each replacing only the text between the lines
``<!-- reproduced-results:begin -->`` and ``<!-- reproduced-results:end -->`` of FILE
(refused when the markers are missing); nothing else of the file is touched.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from gyrobench.scenarios.reports.reasons import calibrated_text, findings, reason

__all__ = [
    "BEGIN", "END", "format_summary", "format_table", "load_report", "main", "splice", "stability_text",
]

BEGIN = "<!-- reproduced-results:begin -->"
END = "<!-- reproduced-results:end -->"


def load_report(folder: str | Path) -> list[dict[str, Any]]:
    """Read every ``<scenario>/results.json`` of a report folder.

    Parameters
    ----------
    folder : str or Path
        A report folder written by ``gyrobench reproduce``.

    Returns
    -------
    list of dict
        The results documents, in the registry's order.

    Raises
    ------
    FileNotFoundError
        If ``folder`` holds no results.json.
    """
    from gyrobench.scenarios import registry

    root = Path(folder)
    docs = [json.loads(p.read_text()) for p in sorted(root.glob("*/results.json"))]
    if not docs:
        raise FileNotFoundError(
            f"report folder {str(root)!r} holds no <scenario>/results.json; "
            "run 'gyrobench reproduce --all --out DIR' first"
        )
    order = {n: i for i, n in enumerate(registry.table())}
    return sorted(
        docs, key=lambda d: (order.get(d.get("scenario"), len(order)), d.get("scenario", ""))
    )


def _fmt(x: float | None) -> str:
    from gyrobench.scenarios.reports.claim_tables import fmt

    return "n/a" if x is None else fmt(float(x))


def _paper(key: str) -> str:
    from gyrobench.scenarios import papers

    try:
        return f"{key} {papers.citation(key, short=True)}"
    except KeyError:
        return key


def _row(c: dict[str, Any]) -> str:
    unit = f" {c['unit']}" if c.get("unit") else ""
    paper_value = "-" if c["paper_value"] is None else f"{_fmt(c['paper_value'])}{unit}"
    ours = (
        "n/a"
        if c["median"] is None
        else f"{_fmt(c['median'])}{unit} [{_fmt(c['spread'][0])}, {_fmt(c['spread'][1])}]"
    )
    if c["testable"]:
        lo, hi = c["interval95"]
        holds = f"{c['holds']}/{c['testable']} ({100 * lo:.0f}-{100 * hi:.0f} %)"
    else:
        holds = f"0/0 of {c['units']}"
    status = c.get("status", c["verdict"])
    if c["kind"] == "calibrated" and c.get("role", "method") == "method" and status == "reproduced":
        status = "*calibrated, not counted*"
    elif status in ("reproduced", "contradicted", "device matched", "device not matched",
                    "no different from the control", "below the control"):
        status = f"**{status}**"
    notes = []
    if c.get("provisional"):
        notes.append("provisional")
    why = reason(c)
    if why:
        notes.append(why)
    if c.get("precondition_absent") and c.get("status") != "not reproducible on this device":
        notes.append(f"{c['precondition_absent']} unit(s) lack the precondition")
    control = c.get("control")
    if control and c.get("status") not in ("no different from the control", "below the control"):
        notes.append(f"control {control['holds']}/{control['testable']}")
    if c.get("same_effect_as"):
        notes.append(f"same effect as {c['same_effect_as']}: counted once")
    if notes:
        status += f" ({'; '.join(notes)})"
    role = c.get("role", "method") + (" (calibrated)" if c["kind"] == "calibrated" else "")
    cells = [
        _paper(c["paper"]),
        c["where"],
        c["statement"],
        role,
        paper_value,
        c["comparator"],
        ours,
        holds,
        status,
    ]
    return "| " + " | ".join(s.replace("|", "\\|") for s in cells) + " |"


def _tally_row(doc: dict[str, Any]) -> str:
    """One paper's claims counted by role and status (from its results.json claims)."""
    claims = doc["claims"]

    def count(role: str, *statuses: str, kind: str | None = None) -> int:
        return sum(
            c.get("role", "method") == role and c.get("status") in statuses and (kind is None or c["kind"] == kind)
            and not c.get("same_effect_as")
            for c in claims
        )

    device = sum(c.get("role") == "device" for c in claims)
    ext = sum(c.get("role") == "extension" for c in claims)
    cells = [
        _paper(doc["claims"][0]["paper"]) if claims else doc.get("scenario", ""),
        str(doc.get("units", "")),
        f"{count('device', 'device matched')} / {device}",
        f"{sum(c.get('role') == 'device' and c['kind'] == 'calibrated' for c in claims)} / {device}",
        str(count("method", "reproduced", kind="emergent")),
        str(count("method", "contradicted")),
        str(count("method", "not reproducible on this device")),
        str(count("method", "no different from the control", "below the control")),
        str(count("method", "undecided")),
        str(count("method", "not testable")),
        str(count("method", "reproduced", kind="calibrated")),
        f"{count('extension', 'reproduced')} / {ext}",
    ]
    return "| " + " | ".join(cells) + " |"


def format_table(docs: Sequence[dict[str, Any]], *, stability: str | None = None) -> str:
    """The full markdown table of a report: the tally, every claim's row, the physics checks.

    Parameters
    ----------
    docs : sequence of dict
        The report's results.json documents (:func:`load_report`).
    stability : str, optional
        The stability line (:func:`stability_text`), when already computed; computed otherwise.

    Returns
    -------
    str
        Markdown: a paragraph on how claims are judged, one tally row per paper, one row per
        claim, and a line on the closed-form physics checks.

    Raises
    ------
    ValueError
        If the report holds no paper claims and no physics checks.
    """
    return _markdown(docs, rows=True, stability=stability)


def format_summary(docs: Sequence[dict[str, Any]], *, stability: str | None = None) -> str:
    """The summary of a report for the README: the tally per paper and the physics checks.

    Parameters
    ----------
    docs : sequence of dict
        The report's results.json documents (:func:`load_report`).
    stability : str, optional
        The stability line (:func:`stability_text`), when already computed; computed otherwise.

    Returns
    -------
    str
        Markdown: a line on how many units, one tally row per paper (as in :func:`format_table`),
        how many claims are calibrated, the stability line, one bullet per paper on its default
        device and its map, the line on the physics checks and a link to the findings; not the
        one-row-per-claim table nor the findings bullets
        (:func:`gyrobench.scenarios.reports.reasons.findings`), which :func:`format_table` writes.

    Raises
    ------
    ValueError
        If the report holds no paper claims and no physics checks.
    """
    return _markdown(docs, rows=False, stability=stability)


def _markdown(docs: Sequence[dict[str, Any]], *, rows: bool, stability: str | None) -> str:
    papers = [d for d in docs if d.get("claims")]
    lines = []
    if papers:
        n = sorted({d["units"] for d in papers})
        if not rows:
            lines += [
                f"The claims of each paper by role and status, judged over {', '.join(map(str, n))} simulated "
                "unit(s) per paper and a control (the same seeds with the effect switched off); calibrated "
                "claims are shown but not counted.",
                "",
            ]
        lines += [] if not rows else [
            f"Every claim of the papers, judged over {', '.join(map(str, n))} simulated unit(s) per paper "
            "(each unit its own noise and drawn parameters). Device claims are what the simulated device "
            "was matched to; method claims are what the paper's method achieves on it, judged only on units "
            "that show the effect, and against a control (the same seeds with the effect switched off): a claim "
            "whose pass rate there is not distinguishable from the units' (Fisher's exact test, two-sided, 5 %) "
            "is no different from the control (below it when the units pass significantly less often; a claim "
            "failing on both stays contradicted), not a finding. \"holds on\" is k/n "
            "with the 95 % Wilson interval of the pass rate; a verdict needs that interval entirely above or below "
            "50 %, and is provisional within 5 points of it. Calibrated claims are shown but not counted.",
            "",
        ]
        lines += [
            "| paper | units | device matched | device calibrated | method: reproduced | contradicted | not "
            "reproducible on this device | no different from / below the control | undecided | not testable | method "
            "calibrated | extensions: hold / all |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|",
        ]
        lines += [_tally_row(d) for d in papers]
        calibrated = calibrated_text([c for d in papers for c in d["claims"]])
        lines += ["", calibrated, "", stability or stability_text(papers)]
        if rows:
            lines += [
                "",
                "| paper | where | claim | role | paper | criterion | ours: median [IQR] | holds on | status |",
                "|---|---|---|---|---|---|---|---|---|",
            ]
            lines += [_row(c) for d in papers for c in d["claims"]]
    lines += _map_lines(papers, brief=not rows)
    checks = [c for d in docs for c in d.get("checks", [])]
    if checks:
        failed = [c["id"] for c in checks if not c["passed"]]
        lines += [
            "",
            "Closed-form checks of the sensor models (`physics_checks`): "
            f"{len(checks) - len(failed)} of "
            f"{len(checks)} pass" + (f"; FAILED: {', '.join(failed)}." if failed else "."),
        ]
    if papers and rows:
        lines += ["", "In short (generated from each paper's results.json; the reasons claim by claim are in the "
                  "table above):", ""]
        lines += [findings(d, _paper(d["claims"][0]["paper"])) for d in papers]
    elif papers:
        lines += ["", "What each paper's method claims gave, claim by claim, with the measured reasons: "
                  "[docs/results.md](docs/results.md)."]
    if not lines:
        raise ValueError(
            "the report holds no paper claims and no physics checks: nothing to tabulate"
        )
    return "\n".join(lines) + "\n"


def _family_device(scenario: str) -> str:
    """What a paper's default device is, from its family module (:attr:`~gyrobench.scenarios.maps.family.Family.
    nominal_device`); "" when the paper has no family or does not say."""
    from gyrobench.scenarios import registry
    from gyrobench.scenarios.maps.build import family_module

    try:
        fam = family_module(registry.get(scenario))
    except (KeyError, ValueError, ImportError):
        return ""
    return "" if fam is None else str(getattr(fam.FAMILY, "nominal_device", ""))


def _map_lines(papers: Sequence[dict[str, Any]], *, brief: bool = False) -> list[str]:
    """One bullet per paper: the device its default run (the table's units) uses and whether that device lies
    in the paper-consistent region of its map (or that the region is empty, and why, or that the report holds
    no map); with a map, the region's size and its medoid (the device to name when the nominal lies outside),
    whose parameters ``brief`` leaves to map.json."""
    out = []
    for d in papers:
        m = d.get("map")
        key = _paper(d["claims"][0]["paper"])
        device = (m or {}).get("nominal_device") or _family_device(d["scenario"]) or "the default Config()"
        head = f"- {key} ({d['scenario']}): the default run uses {device}"
        if not m:
            out.append(head + "; this report holds no map of its family, so whether it lies in the "
                       "paper-consistent region is not shown (`reproduce NAME --map` into the same folder).")
            continue
        n, reg = m["points"], len(m["region"])
        if m.get("nominal_in_region") is None:
            nominal = "the nominal device is no point of the family"
        elif m["nominal_in_region"]:
            nominal = "the nominal device (these units) lies in it"
        else:
            missed = ", ".join(m.get("nominal_missed") or [])
            nominal = "the nominal device (these units) lies outside it" + (f" (misses {missed})" if missed else "")
        med = m.get("medoid")
        if med is None:
            why = re.sub(r"^No point of the family[^.(]*\([^)]*\)\.\s*", "", m["finding"]) or m["finding"]
            where = f"the region is empty, so no paper-consistent device can be named: {why}"
        else:
            params = ("parameters in map.json" if brief
                      else ", ".join(f"{k} = {v:.4g}" for k, v in med["parameters"].items()))
            where = f"its medoid is point {med['index']} ({params})."
        ref = (m.get("refinement") or {}).get("stages") or {}
        refined = ""
        if "2" in ref:
            refined = (f" ({ref['1']['region']} of {ref['1']['points']} space-filling points, {ref['2']['region']} of "
                       f"{ref['2']['points']} refined ones)")
        out.append(f"{head}. Map ({d['scenario']}/map.json): {reg} of {n} family points satisfy every reported "
                   f"device fact{refined}; {nominal}; {where}")
    return (["", "The device each paper's default run uses, and its device-family map (`reproduce NAME --map`):",
             "", *out]) if out else []


def stability_text(docs: Sequence[dict[str, Any]], *, draws: int = 2000, seed: int = 0) -> str:
    """The line on how many status words another seed set is expected to change.

    Parameters
    ----------
    docs : sequence of dict
        The report's results.json documents that hold claims.
    draws : int, default 2000
        Posterior samples per claim (:func:`gyrobench.scenarios.reports.stability.expected_flips`).
    seed : int, default 0
        Seed of the posterior sampling, so the generated text is reproducible.

    Returns
    -------
    str
        One markdown paragraph: the expected number of claims whose status changes on another
        seed set of the report's size and of twice its size, with its standard deviation.
    """
    from gyrobench.scenarios.reports.stability import expected_flips

    n = sorted({int(d["units"]) for d in docs})
    parts = []
    for units in (None, 2 * n[-1]):
        p = np.array([f.probability for f in
                      expected_flips(docs, units=units, draws=draws, rng=np.random.default_rng(seed))])
        parts.append((float(p.sum()), float(np.sqrt(np.sum(p * (1 - p)))), p.size))
    (e, sd, total), (e2, sd2, _) = parts
    return (
        f"Stability: on another seed set of {', '.join(map(str, n))} units the status of {e:.1f} "
        f"+- {sd:.1f} of these {total} claims is expected to change ({100 * e / total:.0f} %), and "
        f"of {e2:.1f} +- {sd2:.1f} at {2 * n[-1]} units: the posterior predictive of each claim's "
        "counts (`gyrobench.scenarios.reports.stability`); `benchmarks/status_flips.py` measures it "
        "between two seed sets (docs/stability.md)."
    )


def splice(text: str, table: str) -> str:
    """Replace the marked section of a text.

    Parameters
    ----------
    text : str
        A file's text holding the lines :data:`BEGIN` and :data:`END`, once each, in that order.
    table : str
        The new text between them.

    Returns
    -------
    str
        ``text`` with the lines between :data:`BEGIN` and :data:`END` replaced by ``table``.

    Raises
    ------
    ValueError
        If the markers are missing, repeated or out of order.
    """
    if text.count(BEGIN) != 1 or text.count(END) != 1 or text.index(BEGIN) > text.index(END):
        raise ValueError(f"the file must hold the marker lines {BEGIN!r} then {END!r}, once each")
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    return f"{head}{BEGIN}\n{table}{END}{tail}"


def main(argv: Sequence[str] | None = None) -> int:
    """Print the table of a report, or splice it and its summary into files.

    Parameters
    ----------
    argv : sequence of str, optional
        Command-line arguments (``sys.argv[1:]`` when None).

    Returns
    -------
    int
        0 on success, 2 when the report or a file's markers are missing.
    """
    p = argparse.ArgumentParser(
        prog="python -m gyrobench.scenarios.reports.readme_table", description=__doc__.split("\n")[0]
    )
    p.add_argument("report", help="report folder written by 'gyrobench reproduce'")
    p.add_argument(
        "--splice", metavar="FILE", help="write the full table into the marked section of FILE (docs/results.md)"
    )
    p.add_argument(
        "--summary", metavar="FILE", help="write the summary into the marked section of FILE (README.md)"
    )
    args = p.parse_args(argv)
    try:
        docs = load_report(args.report)
        papers = [d for d in docs if d.get("claims")]
        stability = stability_text(papers) if papers else None  # the costly part, once for both files
        table = format_table(docs, stability=stability)
        writes = [(args.splice, table),
                  (args.summary, format_summary(docs, stability=stability) if args.summary else "")]
        updates = []
        for name, text in writes:
            if name:
                path = Path(name)
                updates.append((path, splice(path.read_text(encoding="utf-8"), text)))
        for path, text in updates:  # both files checked before either is written
            path.write_text(text, encoding="utf-8")
            print(f"updated {path}")
        if not updates:
            sys.stdout.write(table)
    except (ValueError, FileNotFoundError) as exc:
        print(f"readme_table: error: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
