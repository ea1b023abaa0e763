"""The README's "Reproduced results" table, generated from a report's results.json files.

::

    python -m gyrobench.scenarios.readme_table gyrobench-report            # print the markdown
    python -m gyrobench.scenarios.readme_table gyrobench-report --splice README.md

The table is built from the same ``claims`` lists the report's summary shows (see
:func:`gyrobench.scenarios.claims.ClaimResult.as_dict`), one row per claim, so the README
and the report can never disagree. ``--splice FILE`` replaces only the text between
the lines ``<!-- reproduced-results:begin -->`` and ``<!-- reproduced-results:end -->``
of FILE (refused when the markers are missing); nothing else of the file is touched.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

__all__ = ["BEGIN", "END", "format_table", "load_report", "main", "splice"]

BEGIN = "<!-- reproduced-results:begin -->"
END = "<!-- reproduced-results:end -->"


def load_report(folder: str | Path) -> list[dict[str, Any]]:
    """Every ``<scenario>/results.json`` under ``folder``, in the registry's order.

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
    order = {n: i for i, n in enumerate(registry.SCENARIOS)}
    return sorted(
        docs, key=lambda d: (order.get(d.get("scenario"), len(order)), d.get("scenario", ""))
    )


def _fmt(x: float | None) -> str:
    from gyrobench.scenarios.report import fmt

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
    verdict = c["verdict"]
    if c["kind"] == "calibrated":
        kind, verdict = "*calibrated*", f"*{verdict}* (calibrated, not counted)"
    else:
        kind = "emergent"
        verdict = (
            f"**{verdict}**"
            if verdict in ("holds for most units", "fails for most units")
            else verdict
        )
    cells = [
        _paper(c["paper"]),
        c["where"],
        c["statement"],
        kind,
        paper_value,
        c["comparator"],
        ours,
        holds,
        verdict,
    ]
    return "| " + " | ".join(s.replace("|", "\\|") for s in cells) + " |"


def format_table(docs: Sequence[dict[str, Any]]) -> str:
    """The markdown: a line on the units, the claims table, the tally, the physics checks."""
    papers = [d for d in docs if d.get("claims")]
    lines = []
    if papers:
        n = sorted({d["units"] for d in papers})
        lines += [
            f"Every claim of the papers, judged over {', '.join(map(str, n))} simulated unit(s) "
            "per paper "
            '(each unit its own noise and drawn parameters). "holds on" is k/n with the 95 % '
            "Wilson "
            "interval of the pass rate; a verdict needs that interval entirely above (holds) or "
            "below "
            "(fails) 50 %. Calibrated claims (an input was set from the paper's number, or the "
            "claim holds by the model's construction) are shown but "
            "not counted as reproduced.",
            "",
            "| paper | where | claim | kind | paper | criterion | ours: median [IQR] | holds on "
            "| verdict |",
            "|---|---|---|---|---|---|---|---|---|",
        ]
        claims = [c for d in papers for c in d["claims"]]
        lines += [_row(c) for c in claims]
        emergent = [c for c in claims if c["kind"] == "emergent"]
        tally = {
            v: sum(c["verdict"] == v for c in emergent)
            for v in ("holds for most units", "fails for most units", "undecided", "not testable")
        }
        lines += [
            "",
            f"Emergent claims: {tally['holds for most units']} hold for most units, "
            f"{tally['fails for most units']} fail for most units, {tally['undecided']} undecided, "
            f"{tally['not testable']} not testable; {len(claims) - len(emergent)} calibrated.",
        ]
    checks = [c for d in docs for c in d.get("checks", [])]
    if checks:
        failed = [c["id"] for c in checks if not c["passed"]]
        lines += [
            "",
            "Closed-form checks of the sensor models (`physics_checks`): "
            f"{len(checks) - len(failed)} of "
            f"{len(checks)} pass" + (f"; FAILED: {', '.join(failed)}." if failed else "."),
        ]
    if not lines:
        raise ValueError(
            "the report holds no paper claims and no physics checks: nothing to tabulate"
        )
    return "\n".join(lines) + "\n"


def splice(text: str, table: str) -> str:
    """``text`` with the lines between :data:`BEGIN` and :data:`END` replaced by ``table``."""
    if text.count(BEGIN) != 1 or text.count(END) != 1 or text.index(BEGIN) > text.index(END):
        raise ValueError(f"the file must hold the marker lines {BEGIN!r} then {END!r}, once each")
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    return f"{head}{BEGIN}\n{table}{END}{tail}"


def main(argv: Sequence[str] | None = None) -> int:
    p = argparse.ArgumentParser(
        prog="python -m gyrobench.scenarios.readme_table", description=__doc__.split("\n")[0]
    )
    p.add_argument("report", help="report folder written by 'gyrobench reproduce'")
    p.add_argument(
        "--splice", metavar="FILE", help="replace the marked section of FILE (e.g. README.md)"
    )
    args = p.parse_args(argv)
    try:
        table = format_table(load_report(args.report))
        if args.splice:
            path = Path(args.splice)
            path.write_text(splice(path.read_text(encoding="utf-8"), table), encoding="utf-8")
            print(f"updated {path}")
        else:
            sys.stdout.write(table)
    except (ValueError, FileNotFoundError) as exc:
        print(f"readme_table: error: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
