"""Reports: each scenario's tables, figures and results.json, and one summary page.

Layout written by :func:`write_report` under ``out_dir``::

    index.html                 self-contained page (figures embedded as base64 PNG)
    report.md                  the same content in Markdown (figures linked)
    <scenario>/results.json    machine-readable results of that scenario
    <scenario>/report.md       that scenario's tables
    <scenario>/<figure>.png    its figures

Every file is written to a temporary name and renamed when complete. Every
report states seed, package version and the full configuration.
"""

from __future__ import annotations

import base64
import dataclasses
import datetime as _dt
import html
import io
import json
import math
import platform
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")

from gyrobench.scenarios.base import Headline, Outcome, Table  # noqa: E402
from gyrobench.sim.recording import atomic_path, package_version  # noqa: E402

__all__ = ["fmt", "write_report", "outcome_json"]


def fmt(x: Any) -> str:
    """Format a table cell: 4 significant digits for floats, text as is, None as 'n/a'."""
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


def _jsonable(o: Any) -> Any:
    import numpy as np

    if dataclasses.is_dataclass(o) and not isinstance(o, type):
        return {f.name: _jsonable(getattr(o, f.name)) for f in dataclasses.fields(o)}
    if isinstance(o, dict):
        return {str(k): _jsonable(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [_jsonable(v) for v in o]
    if isinstance(o, np.ndarray):
        return _jsonable(o.tolist())
    if isinstance(o, np.generic):
        return _jsonable(o.item())
    if isinstance(o, float) and not math.isfinite(o):
        return None
    if isinstance(o, (str, int, float, bool)) or o is None:
        return o
    if isinstance(o, Path):
        return str(o)
    return repr(o)


def outcome_json(outcome: Outcome) -> dict[str, Any]:
    """The results.json document of one outcome: results plus seed, version, config, runtime."""
    doc = {
        "scenario": outcome.scenario,
        "title": outcome.title,
        "seed": outcome.seed,
        "gyrobench_version": package_version(),
        "runtime_s": outcome.runtime_s,
        "config": outcome.config,
        "headlines": [dataclasses.asdict(h) for h in outcome.headlines],
    }
    doc.update(outcome.results)
    return _jsonable(doc)


def _write_text(path: Path, text: str) -> None:
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")


def _png_bytes(fig) -> bytes:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110, bbox_inches="tight")
    return buf.getvalue()


def _md_table(t: Table) -> str:
    lines = [f"**{t.title}**", "", "| " + " | ".join(t.columns) + " |", "|" + "---|" * len(t.columns)]
    lines += ["| " + " | ".join(fmt(c) for c in row) + " |" for row in t.rows]
    if t.note:
        lines += ["", t.note]
    return "\n".join(lines) + "\n"


def _html_table(t: Table) -> str:
    head = "".join(f"<th>{html.escape(c)}</th>" for c in t.columns)
    body = "".join("<tr>" + "".join(f"<td>{html.escape(fmt(c))}</td>" for c in row) + "</tr>" for row in t.rows)
    note = f"<p class='note'>{html.escape(t.note)}</p>" if t.note else ""
    return f"<h3>{html.escape(t.title)}</h3><table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>{note}"


def _holds(h: Headline) -> str:
    return {True: "yes", False: "NO", None: "-"}[h.holds]


def _summary_rows(outcomes: Sequence[Outcome]) -> list[list[str]]:
    rows = []
    for o in outcomes:
        for h in o.headlines:
            rows.append([o.scenario, h.quantity, h.reproduced, h.target, _holds(h), h.note])
    return rows


_SUMMARY_COLUMNS = ["scenario", "quantity", "reproduced", "paper / target", "conclusion holds", "note"]

_CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Helvetica,Arial,sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}
table{border-collapse:collapse;margin:0.5em 0 1em 0;font-size:0.9em}
th,td{border:1px solid #bbb;padding:3px 8px;text-align:right}
th{background:#eef}
td:first-child,th:first-child{text-align:left}
.note{font-size:0.85em;color:#555;max-width:900px}
figure{margin:1em 0}
figure img{max-width:100%;border:1px solid #ddd}
figcaption{font-size:0.85em;color:#444}
.no{color:#b00;font-weight:bold}
.meta{font-size:0.8em;color:#666}
pre{background:#f6f6f6;padding:0.5em;overflow-x:auto;font-size:0.8em}
"""


#: marks on <body> how many figures the browser decoded (read by the report's browser test)
_LOAD_CHECK = (
    "<script>window.addEventListener('load',function(){var im=document.images,ok=0;"
    "for(var i=0;i<im.length;i++){if(im[i].complete&&im[i].naturalWidth>0)ok++;}"
    "document.body.setAttribute('data-figures-loaded',ok);"
    "document.body.setAttribute('data-figures-total',im.length);});</script>"
)


def write_report(outcomes: Sequence[Outcome], out_dir: str | Path, *, command: str = "") -> Path:
    """Write every outcome's files and the summary page; return the path of ``index.html``."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    version = package_version()
    stamp = _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    machine = f"{platform.python_implementation()} {platform.python_version()} on {platform.machine()}"

    md = ["# gyrobench report", "", f"gyrobench {version}; {stamp}; {machine}.", ""]
    if command:
        md += [f"Command: `{command}`", ""]
    h = [
        "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>",
        "<title>gyrobench report</title>",
        f"<style>{_CSS}</style></head><body>",
        "<h1>gyrobench report</h1>",
        f"<p class='meta'>gyrobench {html.escape(version)}; {stamp}; {html.escape(machine)}"
        + (f"; command <code>{html.escape(command)}</code>" if command else "")
        + "</p>",
    ]

    rows = _summary_rows(outcomes)
    summary = Table("Summary: reproduced values beside the papers'", _SUMMARY_COLUMNS, rows)
    md += ["## Summary", "", _md_table(summary)]
    h.append("<h2>Summary</h2>")
    h.append(_html_table(summary).replace("<td>NO</td>", "<td class='no'>NO</td>"))

    for o in outcomes:
        sdir = out / o.scenario
        sdir.mkdir(parents=True, exist_ok=True)
        doc = outcome_json(o)
        _write_text(sdir / "results.json", json.dumps(doc, indent=2, sort_keys=False) + "\n")
        cfg = json.dumps(doc["config"], indent=1)
        meta = f"seed {o.seed}; runtime {fmt(o.runtime_s)} s"
        smd = [f"## {o.title} (`{o.scenario}`)", "", meta, ""]
        if o.conclusion:
            smd += [o.conclusion, ""]
        h.append(f"<h2 id='{html.escape(o.scenario)}'>{html.escape(o.title)} (<code>{html.escape(o.scenario)}</code>)</h2>")
        h.append(f"<p class='meta'>{html.escape(meta)}</p>")
        if o.conclusion:
            h.append(f"<p>{html.escape(o.conclusion)}</p>")
        for t in o.tables:
            smd.append(_md_table(t))
            h.append(_html_table(t))
        for f in o.figures:
            png = _png_bytes(f.figure)
            with atomic_path(sdir / f"{f.name}.png") as tmp:
                tmp.write_bytes(png)
            smd += [f"![{f.caption}]({o.scenario}/{f.name}.png)", "", f"*{f.caption}*", ""]
            b64 = base64.b64encode(png).decode("ascii")
            h.append(
                f"<figure><img alt='{html.escape(f.caption)}' src='data:image/png;base64,{b64}'>"
                f"<figcaption>{html.escape(f.caption)}</figcaption></figure>"
            )
        smd += ["<details><summary>configuration</summary>", "", "```json", cfg, "```", "", "</details>", ""]
        h.append(f"<details><summary>configuration</summary><pre>{html.escape(cfg)}</pre></details>")
        _write_text(sdir / "report.md", "\n".join(smd).replace(f"]({o.scenario}/", "]("))
        md += smd
    h.append(_LOAD_CHECK)
    h.append("</body></html>")
    _write_text(out / "report.md", "\n".join(md))
    index = out / "index.html"
    _write_text(index, "\n".join(h))
    return index
