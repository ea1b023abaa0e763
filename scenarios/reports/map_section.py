"""A paper's device-family map in its report section: the region table, the claims over the region
beside the nominal device, the map's figures, and the link from results.json.

A map is what ``gyrobench reproduce NAME --map`` wrote (``map.json`` and its PNGs,
:mod:`gyrobench.scenarios.maps`). :func:`load_maps` reads the maps a report folder already holds
(so the next ``reproduce`` into that folder keeps them); :func:`map_tables` turns one into the
section's tables, reading only ``map.json`` and the report's own claim verdicts;
:func:`results_link` is what results.json says about it.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from gyrobench.scenarios.base import Table

__all__ = ["FIGURES", "MAP_FILE", "RUN_FILE", "MapFiles", "load_map", "load_maps", "map_tables", "results_link"]

#: map.json's name in a scenario's folder
MAP_FILE = "map.json"
#: map_run.json's (:data:`gyrobench.scenarios.maps.build.RUN_FILE`)
RUN_FILE = "map_run.json"
#: the map's PNGs and their captions, in the order the section shows them
FIGURES = (
    ("phase_diagrams.png", "Method claims over the device family: each claim's pass rate over its two most "
                           "sensitive parameters (|Spearman rho|); region points ringed red, the nominal device a "
                           "black star, the region's medoid a red diamond, refined-stage points black dots."),
    ("specification_curves.png", "Specification curves: every region point's median of each claim's quantity, "
                                 "sorted; the claim's band shaded, the paper's value dashed."),
    ("constraints.png", "The paper's reported device facts over the family: each fact's point medians over its "
                        "two most sensitive parameters; points satisfying it ringed green, region points red."),
    ("covariates.png", "The claims against the quantities they rest on (covariates): each point's pass rate "
                       "over the point's median of the covariate."),
)


@dataclass(frozen=True, slots=True, kw_only=True)
class MapFiles:
    """One map as a report carries it: map.json's content and its PNGs' bytes.

    Attributes
    ----------
    doc : dict
        map.json.
    pngs : dict
        File name -> PNG bytes, for the names of :data:`FIGURES` present.
    run : dict or None
        map_run.json (the command, the units computed and reused), when present.
    """

    doc: dict[str, Any]
    pngs: dict[str, bytes]
    run: dict[str, Any] | None = None

    @property
    def command(self) -> str:
        """The command that wrote the map (``"gyrobench reproduce --map"`` when not recorded)."""
        cmd = (self.run or {}).get("command")
        return cmd if isinstance(cmd, str) and cmd else "gyrobench reproduce --map"


def load_map(folder: Path) -> MapFiles | None:
    """The map in a folder: map.json with gyrobench's map format, its PNGs and map_run.json.

    Parameters
    ----------
    folder : Path
        A scenario's folder of a report (or of a ``reproduce --map`` output).

    Returns
    -------
    MapFiles or None
        The map, or None when the folder holds no readable map.json of the map format.
    """
    from gyrobench.scenarios.maps.region import MAP_FORMAT

    path = folder / MAP_FILE
    if not path.is_file():
        return None
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if not isinstance(doc, dict) or doc.get("format") != MAP_FORMAT:
        return None
    pngs = {name: (folder / name).read_bytes() for name, _ in FIGURES if (folder / name).is_file()}
    run = None
    try:
        run = json.loads((folder / RUN_FILE).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        pass
    return MapFiles(doc=doc, pngs=pngs, run=run if isinstance(run, dict) else None)


def load_maps(out_dir: str | Path, scenarios: Sequence[str]) -> dict[str, MapFiles]:
    """The maps a report folder holds for ``scenarios`` (``out_dir/<scenario>/map.json``).

    Parameters
    ----------
    out_dir : path
        A report folder (absent: no maps).
    scenarios : sequence of str
        The scenarios being reported.

    Returns
    -------
    dict
        Scenario -> its map, for those that have one.
    """
    out = Path(out_dir)
    found = {}
    for name in scenarios:
        m = load_map(out / name)
        if m is not None:
            found[name] = m
    return found


def _pct(ci: Sequence[float] | None) -> str:
    return "-" if not ci else f"[{100 * ci[0]:.0f} %, {100 * ci[1]:.0f} %]"


def _num(x: Any) -> str:
    if x is None:
        return "-"
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, (int, float)) and math.isfinite(x):
        return f"{x:.4g}"
    return str(x)


def _top(sensitivity: Sequence[Mapping[str, Any]], k: int = 2) -> str:
    ranked = [s for s in sensitivity if s.get("rho") is not None][:k]
    return ", ".join(f"{s['field']} ({s['rho']:+.2f})" for s in ranked) or "-"


def map_tables(doc: Mapping[str, Any], verdicts: Mapping[str, str]) -> list[Table]:
    """The section's tables from map.json: the region, and each claim over it beside the nominal device.

    Parameters
    ----------
    doc : mapping
        map.json.
    verdicts : mapping
        Claim id -> this report's verdict on the nominal device (its units), where the report has it.

    Returns
    -------
    list of Table
        The reported facts over the family (the region table) and the method claims over the region.
    """
    pts = doc["points"]
    n = len(pts)
    design = doc["design"]
    nominal = doc.get("nominal")
    counts = doc["constraint_counts"]
    stages = doc.get("stages") or {}
    rows = []
    for c in doc["constraints"]:
        nom = "-" if nominal is None else (f"{_num(nominal['constraint_medians'][c['id']])} "
                                           f"({'holds' if nominal['constraints_satisfied'][c['id']] else 'misses'})")
        cell = f"{counts[c['id']]} of {n}"
        if "2" in stages:  # refined: the two stages' counts beside the total
            cell += " (" + " + ".join(f"{st['constraint_counts'][c['id']]} of {st['points']}"
                                      for _, st in sorted(stages.items())) + ")"
        rows.append([c["id"], c["source"], c["comparator"], cell, nom, _top(c.get("sensitivity", []))])
    conflicts = "; ".join(f"{a} and {b}" for a, b in doc["conflicts"]) or "none"
    region_note = (
        f"{doc['finding']} {doc.get('nominal_text', '')} Conflicting pairs (each holds somewhere, never together): "
        f"{conflicts}. Design: {design['points']} {design['method']} points x {design['units_per_point']} units "
        f"(seed {design['seed']}); a point satisfies a fact when the median over its units does. "
        f"{_refinement_note(doc)}The nominal "
        "device is the default reproduction's configuration, run as one more point with its own "
        f"{len(nominal['seeds']) if nominal else 0} units."
    )
    region = Table(
        "Device family: which reported facts hold together (the region)",
        ["fact", "where", "tolerance", "points satisfying", "nominal device (median)", "most sensitive (rho)"],
        rows, note=region_note,
    )
    crow = []
    for c in doc["claims"]:
        nom = c.get("nominal")
        nom_text = "-" if nom is None else (f"{nom['verdict']} ({nom['holds']} of {nom['testable']} testable units)")
        crow.append([c["id"], c["verdict"], f"{c['family_holds']} of {c['family_testable']}", nom_text,
                     verdicts.get(c["id"], "not in this report"), _top(c.get("sensitivity", []))])
    claims = Table(
        "Method claims over the region beside the nominal device",
        ["claim", "over the region (k of n points, exact 95 %)", "whole family (points)",
         "nominal device in the map", "nominal device in this report", "most sensitive (rho)"],
        crow,
        note="A point holds a claim when more than half of its testable units pass; the region verdict counts "
        "region points that could test the claim, with the Clopper-Pearson interval and which way the failing "
        "points miss. 'whole family' counts every point, region or not (what the claim does where the paper's "
        "facts do not hold). 'nominal device in this report' is the verdict of this report's units (the default "
        "configuration); 'in the map' is the same device over the map's few units.",
    )
    return [region, claims]


def _refinement_note(doc: Mapping[str, Any]) -> str:
    """The second stage in a sentence or two (:mod:`gyrobench.scenarios.maps.refine`): why it ran or not, and
    the region per stage."""
    ref = doc.get("refinement")
    if not ref:
        return ""
    text = f"Refinement: {ref['reason']}"
    stages = doc.get("stages") or {}
    if "2" in stages:
        text += (f"; region points by stage: {stages['1']['region']} of {stages['1']['points']} (space-filling), "
                 f"{stages['2']['region']} of {stages['2']['points']} (refined; not space-filling, so the "
                 "'whole family' counts mix the two)")
    return text + ". "


def results_link(doc: Mapping[str, Any]) -> dict[str, Any]:
    """What results.json says about the map: the file, the region and each claim's region count.

    The points themselves (parameters, per-point pass rates, region membership) are in map.json
    beside results.json (``file``).

    Parameters
    ----------
    doc : mapping
        map.json.

    Returns
    -------
    dict
        ``file``, ``format``, ``points``, ``region``, ``finding``, ``medoid``, ``nominal_in_region``,
        ``nominal_missed`` (the facts the nominal device misses), ``nominal_device`` (what it is),
        ``refinement`` (the second stage: ran or not, the region per stage) and per claim
        ``region_holds`` / ``region_testable``.
    """
    nominal = doc.get("nominal")
    ref = doc.get("refinement")
    return {
        "file": MAP_FILE,
        "format": doc["format"],
        "points": len(doc["points"]),
        "region": list(doc["region"]),
        "finding": doc["finding"],
        "medoid": doc.get("medoid"),
        "nominal_in_region": None if nominal is None else nominal["in_region"],
        "nominal_missed": None if nominal is None else [k for k, ok in nominal["constraints_satisfied"].items()
                                                        if not ok],
        "nominal_device": doc.get("family", {}).get("nominal_device", ""),
        "refinement": None if not ref else {"triggered": ref["triggered"], "reason": ref["reason"],
                                            "stages": doc.get("stages")},
        "claims": {c["id"]: {"region_holds": c["region_holds"], "region_testable": c["region_testable"]}
                   for c in doc["claims"]},
    }
