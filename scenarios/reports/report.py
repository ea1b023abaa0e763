"""Reports: each scenario's tables, figures and results.json, and one summary page.

Layout written by :func:`write_report` under ``out_dir``::

    index.html                 self-contained page (figures embedded as base64 PNG)
    report.md                  the same content in Markdown (figures linked)
    <scenario>/results.json    machine-readable results of that scenario
    <scenario>/report.md       that scenario's tables
    <scenario>/<figure>.png    its figures
    <scenario>/map.json        its device-family map, when one is given (with the map's PNGs)

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
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")

from gyrobench.base.atomic import atomic_path
from gyrobench.io.recording import package_version  # noqa: E402
from gyrobench.scenarios.base import Outcome, Table  # noqa: E402
from gyrobench.scenarios.reports.claim_tables import (  # noqa: E402
    _SUMMARY_COLUMNS,
    _claims_table,
    _deviations_table,
    _mark_verdicts,
    _paper_heading,
    _summary_rows,
    claim_tally,
    fmt,
    status_text,
    tally_table,
    tally_text,
)
from gyrobench.scenarios.reports.map_section import FIGURES as MAP_FIGURES  # noqa: E402
from gyrobench.scenarios.reports.map_section import MAP_FILE, MapFiles, map_tables, results_link  # noqa: E402
from gyrobench.scenarios.reports.map_section import RUN_FILE as MAP_RUN_FILE  # noqa: E402
from gyrobench.scenarios.reports.reasons import calibrated_text  # noqa: E402

__all__ = ["claim_tally", "fmt", "outcome_json", "status_text", "tally_table", "tally_text", "write_report"]


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
    if isinstance(o, float) and math.isinf(o):
        return "inf" if o > 0 else "-inf"
    if isinstance(o, float) and not math.isfinite(o):
        return None
    if isinstance(o, (str, int, float, bool)) or o is None:
        return o
    if isinstance(o, Path):
        return str(o)
    return repr(o)


def outcome_json(outcome: Outcome) -> dict[str, Any]:
    """The results.json document of one outcome: results plus seed, version, config, runtime.

    A paper scenario's document also holds ``units`` (how many were simulated),
    ``claims`` (:meth:`~gyrobench.scenarios.claims.ClaimResult.as_dict` each) and
    ``deviations`` (the paper's protocol departures).

    Parameters
    ----------
    outcome : Outcome
        One scenario's outcome.

    Returns
    -------
    dict of str to object
        The document.
    """
    doc: dict[str, Any] = {
        "scenario": outcome.scenario,
        "title": outcome.title,
        "seed": outcome.seed,
        "gyrobench_version": package_version(),
        "runtime_s": outcome.runtime_s,
        "config": outcome.config,
        "headlines": [dataclasses.asdict(h) for h in outcome.headlines],
    }
    if outcome.claims or outcome.deviations:
        doc["units"] = outcome.units
        doc["claims"] = [c.as_dict() for c in outcome.claims]
        doc["deviations"] = [dataclasses.asdict(d) for d in outcome.deviations]
        if outcome.deviation_effects:
            doc["deviation_effects"] = [e.as_dict() for e in outcome.deviation_effects]
    clash = sorted(set(doc) & set(outcome.results))
    if clash:  # a scenario's own numbers must not overwrite the runner's (e.g. the unit count)
        raise ValueError(
            f"scenario {outcome.scenario!r}: results keys {clash} are reserved in results.json"
        )
    doc.update(outcome.results)
    return _jsonable(doc)


def _write_text(path: Path, text: str) -> None:
    """Write a report file; in Markdown and HTML, control characters from configs and files are shown as
    escapes (:func:`gyrobench.base.safety.escape_controls`; JSON escapes them itself)."""
    from gyrobench.base.safety import escape_controls

    if path.suffix in (".md", ".html"):
        text = escape_controls(text)
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


def _td(cell: Any) -> str:
    """A table cell; prose (a string longer than a number or a short word) reads left-aligned."""
    text = fmt(cell)
    cls = " class='txt'" if isinstance(cell, str) and len(text) > 12 else ""
    return f"<td{cls}>{html.escape(text)}</td>"


def _html_table(t: Table) -> str:
    head = "".join(f"<th>{html.escape(c)}</th>" for c in t.columns)
    body = "".join("<tr>" + "".join(_td(c) for c in row) + "</tr>" for row in t.rows)
    note = f"<p class='note'>{html.escape(t.note)}</p>" if t.note else ""
    return f"<h3>{html.escape(t.title)}</h3><table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>{note}"


_CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Helvetica,Arial,sans-serif;max-width:1360px;margin:2em auto;
padding:0 1em;color:#222}
table{border-collapse:collapse;margin:0.5em 0 1em 0;font-size:0.85em;display:block;overflow-x:auto}
th,td{border:1px solid #bbb;padding:3px 8px;text-align:right}
th{background:#eef}
td:first-child,th:first-child{text-align:left}
.note{font-size:0.85em;color:#555;max-width:900px}
figure{margin:0.5em 0.5em 0.5em 0;display:inline-block;vertical-align:top;max-width:100%}
details.fold>summary h3{display:inline}
table.claims{display:table;table-layout:fixed;width:100%;overflow-wrap:anywhere}
table.claims th:nth-child(1){width:9%}table.claims th:nth-child(2){width:13%}
table.claims th:nth-child(3){width:26%}table.claims td:nth-child(2){text-align:left}
table.maptab{display:table;table-layout:fixed;width:100%;overflow-wrap:anywhere}
table.maptab td{text-align:left}
figure img{max-width:100%;border:1px solid #ddd}
nav ol{font-size:0.9em;columns:2}
nav details{display:inline;margin-left:0.5em;font-size:0.9em}
nav details ol{columns:1}
a.top{font-size:0.9em;margin-left:1em}
figcaption{font-size:0.85em;color:#444}
.no{color:#b00;font-weight:bold}
.yes{color:#070;font-weight:bold}
.cal{color:#a60;font-weight:bold;font-style:italic}
td:nth-child(3){text-align:left}
td.txt{text-align:left;min-width:9em}
.meta{font-size:0.8em;color:#666}
pre{background:#f6f6f6;padding:0.5em;overflow-x:auto;font-size:0.8em}
"""


#: marks on <body> what the browser laid out (read by the report's browser test): how many figures it
#: decoded, the page's scroll width, the right edge of the claims tables' status column, the most a claims
#: table and any open table overflow their box, and the smallest ratio of a figure's shown to its natural width
_LOAD_CHECK = (
    "<script>window.addEventListener('load',function(){var im=document.images,ok=0,scale=1,b=document.body;"
    "for(var i=0;i<im.length;i++){if(im[i].complete&&im[i].naturalWidth>0){ok++;"
    "scale=Math.min(scale,im[i].getBoundingClientRect().width/im[i].naturalWidth);}}"
    "var right=0,over=0,cells=document.querySelectorAll('table.claims tr>:nth-child(2)');"
    "for(var j=0;j<cells.length;j++){right=Math.max(right,cells[j].getBoundingClientRect().right+window.scrollX);}"
    "var tabs=document.querySelectorAll('table.claims'),all=document.querySelectorAll('table'),any=0;"
    "for(var k=0;k<tabs.length;k++){over=Math.max(over,tabs[k].scrollWidth-tabs[k].clientWidth);}"
    "for(var n=0;n<all.length;n++){any=Math.max(any,all[n].scrollWidth-all[n].clientWidth);}"
    "b.setAttribute('data-figures-loaded',ok);b.setAttribute('data-figures-total',im.length);"
    "b.setAttribute('data-page-height',document.documentElement.scrollHeight);"
    "b.setAttribute('data-scroll-width',document.scrollingElement.scrollWidth);"
    "b.setAttribute('data-viewport-width',window.innerWidth);"
    "b.setAttribute('data-claims-tables',tabs.length);"
    "b.setAttribute('data-status-right',Math.ceil(right));b.setAttribute('data-claims-overflow',over);"
    "b.setAttribute('data-tables-overflow',any);"
    "b.setAttribute('data-figure-scale',scale.toFixed(3));});</script>"
)


def _anchor(*parts: str) -> str:
    return "-".join(p.replace(" ", "-") for p in parts)


def _scenario_tables(o: Outcome) -> list[tuple[Table, bool]]:
    """(table, is_claims_or_deviations) in the order a scenario's section shows them."""
    own = [(_claims_table(o), True), (_deviations_table(o), True)] if (o.claims or o.deviations) else []
    return [*own, *((t, False) for t in o.tables)]


def _contents(outcomes: Sequence[Outcome], maps: Mapping[str, MapFiles]) -> tuple[list[str], str]:
    """The contents list, as Markdown lines and as an HTML <nav>."""
    md = ["## Contents", "", "- [Summary](#summary)"]
    h = ["<nav id='contents'><h2>Contents</h2><ol>", "<li><a href='#summary'>Summary</a></li>"]
    for o in outcomes:
        md.append(f"- [{o.title}](#{o.scenario})")
        sub = [
            f"<li><a href='#{_anchor(o.scenario, 't', str(i))}'>{html.escape(t.title)}</a></li>"
            for i, (t, _) in enumerate(_scenario_tables(o))
        ]
        if o.figures:
            sub.append(f"<li><a href='#{_anchor(o.scenario, 'figures')}'>Figures ({len(o.figures)})</a></li>")
        if o.scenario in maps:
            sub.append(f"<li><a href='#{_anchor(o.scenario, 'map')}'>Device family map</a></li>")
        h.append(
            f"<li><a href='#{html.escape(o.scenario)}'>{html.escape(o.title)}</a>"
            f"<details><summary>{len(sub)} parts</summary><ol>{''.join(sub)}</ol></details></li>"
        )
    h.append("</ol></nav>")
    return md + [""], "".join(h)


def _summary(outcomes: Sequence[Outcome]) -> tuple[list[str], list[str]]:
    """The summary: the verdict tally and the headline numbers (each paper's tables stay in its section)."""
    md = ["## Summary", ""]
    h = ["<h2 id='summary'>Summary</h2>"]
    tally = tally_table(outcomes)
    claims = [r.as_dict() for o in outcomes for r in o.claims]
    if claims:
        line = calibrated_text(claims)
        md += [f"**{line}**", ""]
        h.append(f"<p class='calibrated'><strong>{html.escape(line)}</strong></p>")
    if tally.rows:
        md += [_md_table(tally)]
        h.append(_link_scenarios(_html_table(tally), outcomes))
    rows = _summary_rows(outcomes)
    if rows:
        summary = Table("Headline numbers beside their targets", _SUMMARY_COLUMNS, rows)
        md += ["", _md_table(summary)]
        h.append(_html_table(summary).replace("<td>NO</td>", "<td class='no'>NO</td>"))
    return md, h


def _link_scenarios(text: str, outcomes: Sequence[Outcome]) -> str:
    """Make each scenario's name in a table's first column a link to its section."""
    for o in outcomes:
        name = html.escape(o.scenario)
        for cell in ("<td>", "<td class='txt'>"):
            text = text.replace(f"{cell}{name}</td>", f"{cell}<a href='#{name}'>{name}</a></td>", 1)
    return text


def _figure_html(caption: str, png: bytes, href: str) -> str:
    """An embedded figure that opens at full size (the PNG file beside the page, ``href``) on click."""
    b64 = base64.b64encode(png).decode("ascii")
    return (
        f"<figure><a href='{html.escape(href)}' target='_blank' title='open at full size'>"
        f"<img alt='{html.escape(caption)}' src='data:image/png;base64,{b64}'></a>"
        f"<figcaption>{html.escape(caption)}</figcaption></figure>"
    )


#: a table with more rows than this is folded under its title (one click opens it)
FOLD_ROWS = 12


def _section_table_html(t: Table, own: bool) -> str:
    """A section's table: claims tables in full; deviations and long tables folded under their title."""
    if own and t.title.startswith("Claims of "):
        return _mark_verdicts(_html_table(t)).replace("<table>", "<table class='claims'>", 1)
    if own or len(t.rows) > FOLD_ROWS:
        body = _html_table(t).split("</h3>", 1)[1]
        return (f"<details class='fold'><summary><h3>{html.escape(t.title)}</h3> ({len(t.rows)} rows)</summary>"
                f"{body}</details>")
    return _html_table(t)


def _map_section(o: Outcome, sdir: Path, m: MapFiles) -> tuple[list[str], list[str]]:
    """A scenario's device-family map (Markdown lines, HTML parts); writes map.json and its PNGs."""
    with atomic_path(sdir / MAP_FILE) as tmp:
        tmp.write_text(json.dumps(m.doc, indent=1, allow_nan=False) + "\n", encoding="utf-8")
    if m.run is not None:
        with atomic_path(sdir / MAP_RUN_FILE) as tmp:
            tmp.write_text(json.dumps(m.run, indent=1) + "\n", encoding="utf-8")
    verdicts = {r.claim.id: status_text(r) for r in o.claims}
    anchor = _anchor(o.scenario, "map")
    smd = ["### Device family map", "", f"Written by: `{m.command}`; "
           f"every point in [{o.scenario}/map.json]({o.scenario}/map.json).", ""]
    h = [f"<h3 id='{anchor}'>Device family map</h3>",
         f"<p class='meta'>Written by <code>{html.escape(m.command)}"
         f"</code>; every point, its parameters, per-point pass rates and region membership in "
         f"<a href='{html.escape(o.scenario)}/map.json'>map.json</a>.</p>"]
    for t in map_tables(m.doc, verdicts):
        smd.append(_md_table(t))
        h.append(_html_table(t).replace("<table>", "<table class='maptab'>", 1))
    h.append("<div class='figs'>")
    for name, caption in MAP_FIGURES:
        png = m.pngs.get(name)
        if png is None:
            continue
        with atomic_path(sdir / name) as tmp:
            tmp.write_bytes(png)
        smd += [f"![{caption}]({o.scenario}/{name})", "", f"*{caption}*", ""]
        h.append(_figure_html(caption, png, f"{o.scenario}/{name}"))
    h.append("</div>")
    return smd, h


def _scenario_section(o: Outcome, sdir: Path, cfg: str, m: MapFiles | None = None) -> tuple[list[str], list[str]]:
    """One scenario's section (Markdown lines, HTML parts); writes its figures' PNG files (and its map's)."""
    seeds = f"seeds {o.seed} to {o.seed + o.units - 1} ({o.units} units)" if o.units > 1 else f"seed {o.seed}"
    meta = f"{seeds}; runtime {fmt(o.runtime_s)} s"
    if o.claims or o.deviations:
        meta = f"{_paper_heading(o)}. {meta}"
    smd = [f"## {o.title} (`{o.scenario}`)", "", meta, ""]
    if o.conclusion:
        smd += [o.conclusion, ""]
    name = html.escape(o.scenario)
    h = [f"<section><h2 id='{name}'>{html.escape(o.title)} (<code>{name}</code>)</h2>",
         f"<p class='meta'>{html.escape(meta)} <a class='top' href='#contents'>contents</a></p>"]
    if o.conclusion:
        h.append(f"<p>{html.escape(o.conclusion)}</p>")
    for i, (t, own) in enumerate(_scenario_tables(o)):
        smd.append(_md_table(t))
        h.append(f"<div id='{_anchor(o.scenario, 't', str(i))}'>{_section_table_html(t, own)}</div>")
    if o.figures:
        h.append(f"<h3 id='{_anchor(o.scenario, 'figures')}'>Figures</h3><div class='figs'>")
    for f in o.figures:
        png = _png_bytes(f.figure)
        with atomic_path(sdir / f"{f.name}.png") as tmp:
            tmp.write_bytes(png)
        smd += [f"![{f.caption}]({o.scenario}/{f.name}.png)", "", f"*{f.caption}*", ""]
        h.append(_figure_html(f.caption, png, f"{o.scenario}/{f.name}.png"))
    if o.figures:
        h.append("</div>")
    if m is not None:
        mmd, mh = _map_section(o, sdir, m)
        smd += mmd
        h += mh
    smd += ["<details><summary>configuration</summary>", "", "```json", cfg, "```", "", "</details>", ""]
    h.append(f"<details><summary>configuration</summary><pre>{html.escape(cfg)}</pre></details></section>")
    return smd, h


def write_report(outcomes: Sequence[Outcome], out_dir: str | Path, *, command: str = "",
                 maps: Mapping[str, MapFiles] | None = None) -> Path:
    """Write every outcome's files and the summary page; return the path of ``index.html``.

    The page reads like a paper's supplement: a contents list with anchors, the tally of
    verdicts and the headline numbers on top, then each scenario once (claims, deviations,
    its tables, its figures side by side, its device-family map when ``maps`` has one, its
    configuration folded). A mapped scenario's results.json links its map.json (``map``).

    Parameters
    ----------
    outcomes : sequence of Outcome
        The scenarios' outcomes.
    out_dir : str or Path
        The report folder.
    command : str
        The command line that made the report, shown in it.
    maps : mapping of str to MapFiles, optional
        Each mapped scenario's map files, shown in its section.

    Returns
    -------
    Path
        ``out_dir / "index.html"``.
    """
    maps = maps or {}
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
    contents_md, contents_html = _contents(outcomes, maps)
    md += contents_md
    h.append(contents_html)
    summary_md, summary_html = _summary(outcomes)
    md += summary_md
    h += summary_html

    for o in outcomes:
        sdir = out / o.scenario
        sdir.mkdir(parents=True, exist_ok=True)
        doc = outcome_json(o)
        m = maps.get(o.scenario)
        if m is not None:
            doc["map"] = results_link(m.doc)
        _write_text(sdir / "results.json", json.dumps(doc, indent=2, sort_keys=False) + "\n")
        smd, sh = _scenario_section(o, sdir, json.dumps(doc["config"], indent=1), m)
        _write_text(sdir / "report.md", "\n".join(smd).replace(f"]({o.scenario}/", "]("))
        md += smd
        h += sh
    h.append(_LOAD_CHECK)
    h.append("</body></html>")
    _write_text(out / "report.md", "\n".join(md))
    index = out / "index.html"
    _write_text(index, "\n".join(h))
    return index
