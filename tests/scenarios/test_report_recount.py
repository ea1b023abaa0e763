"""A referee can recount the report: every claim's pass count and median from the per-unit quantities
results.json carries, every reason and finding generated from those numbers, the README's block
generated, not written by hand."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from gyrobench.scenarios import registry
from gyrobench.scenarios.base import Outcome
from gyrobench.scenarios.claims import Claim, Precondition, above, evaluate, in_range, is_true, within_factor
from gyrobench.scenarios.cli.main import main
from gyrobench.scenarios.reports import readme_table
from gyrobench.scenarios.reports.reasons import calibrated_count, findings, measured, reason, short_statement
from gyrobench.scenarios.reports.report import fmt, write_report

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def toy_report(tmp_path_factory):
    """The toy paper run through the real runner (6 units and their control)."""
    mp = pytest.MonkeyPatch()
    mp.setitem(registry.SCENARIOS, "toy_paper", "tests.scenarios.toy_paper")
    out = tmp_path_factory.mktemp("recount") / "rep"
    try:
        assert main(["reproduce", "toy_paper", "--units", "6", "--workers", "0", "--out", str(out), "-q"]) == 0
    finally:
        mp.undo()
    return out


def _value(v):
    return float(v) if isinstance(v, str) else v  # results.json spells +-inf as "inf" / "-inf"


def _passes(criterion, q):
    """A pass as results.json's ``criterion`` states it (the referee's reading of the document)."""
    lo, hi = _value(criterion["lo"]), _value(criterion["hi"])
    return {"is_true": q == 1.0, "above": q > lo, "below": q < hi}.get(criterion["kind"], lo <= q <= hi)


def _present(pre, unit):
    if pre is None:
        return True
    q = unit.get(pre["quantity"])
    ok = q is not None and not (isinstance(q, float) and math.isnan(q)) and _passes(pre["criterion"], _value(q))
    return ok and all(_present(p, unit) for p in pre["also"])


def _recount(claim, units, *, precondition=True):
    values = []
    for u in units:
        if precondition and not _present(claim["precondition"], u):
            continue
        q = u.get(claim["quantity"])
        if q is not None:
            values.append(_value(q))
    holds = sum(_passes(claim["criterion"], q) for q in values)
    return holds, len(values), (float(np.median(values)) if values else None)


def test_results_json_lets_a_referee_recount_every_claim(toy_report):
    """Each claim names its quantity and criterion; the units' and the control's per-unit values are
    there, keyed by seed, and recounting them gives the stored pass counts, medians and control."""
    doc = json.loads((toy_report / "toy_paper" / "results.json").read_text())
    units, control = doc["unit_quantities"], doc["control_quantities"]
    assert [u["seed"] for u in units] == doc["unit_run"]["seeds"] and len(units) == doc["units"] == 6
    assert [u["seed"] for u in control] == doc["control_run"]["seeds"]
    for c in doc["claims"]:
        assert all(c["quantity"] in u for u in units), c["id"]
        holds, testable, median = _recount(c, units)
        assert (holds, testable) == (c["holds"], c["testable"]), c["id"]
        assert median == pytest.approx(c["median"], rel=1e-12), c["id"]
        ch, ct, _ = _recount(c, control, precondition=False)  # the control is judged without the precondition
        assert (ch, ct) == (c["control"]["holds"], c["control"]["testable"]), c["id"]


def _doc(**kw):
    base = {"id": "x", "paper": "009", "where": "Table 2", "statement": "K_n is 0.4 %.", "kind": "emergent",
            "role": "method", "unit": "%", "paper_value": 0.4, "comparator": "within 2x of 0.4 % (0.2 to 0.8)",
            "units": 20, "testable": 20, "holds": 3, "median": 16.9, "precondition": None,
            "precondition_absent": 0, "misses": {"below": 0, "above": 17, "direction": "above"},
            "control": {"holds": 0, "testable": 20}, "control_test": None, "status": "contradicted"}
    return {**base, **kw}


def test_a_failed_claim_gives_its_measured_reason():
    assert reason(_doc()) == "median 16.9 % vs the paper's 0.4 %; 3 of 20 units pass, most misses above the band"
    pre = {"text": "truth R^2 at least 0.9", "quantity": "r2", "comparator": "> 0.9"}
    assert reason(_doc(status="not reproducible on this device", precondition=pre, precondition_absent=17,
                       testable=3)) == "precondition absent on 17 of 20 units: truth R^2 at least 0.9"
    assert reason(_doc(status="no different from the control", holds=20, control={"holds": 17, "testable": 20},
                       control_test={"p_value": 0.2308})) == "units 20/20 pass, control 17/20; Fisher p = 0.23"
    assert reason(_doc(status="not testable", testable=0, holds=0, median=None)) == (
        "no unit could test it (0 of 20 units gave a value)")
    assert reason(_doc(status="undecided", holds=11, comparator="true for the unit", median=1.0)) == (
        "11 of 20 units pass")
    assert reason(_doc(status="reproduced", holds=20)) == ""  # a claim that holds needs no reason
    assert measured(_doc(paper_value=None, comparator="> 10 x", unit="x", median=2.5)) == (
        "median 2.5 x, criterion > 10 x; 3 of 20 units pass")
    assert short_statement("The bias part (a6) has a lower R (judged on the fit's point values, as the paper's "
                           "table prints them).") == "The bias part (a6) has a lower R"


def _mixed_outcome() -> Outcome:
    """A paper with a claim of every status a finding names, over 20 units drawn with a fixed seed."""
    rng = np.random.default_rng(7)
    claims = (
        Claim(id="d.a", paper="009", where="Table 1", statement="The raw K_n is 15.7 %.", kind="calibrated",
              calibrated_input="knee set from Table 1", quantity="raw", comparator=within_factor(15.7),
              paper_value=15.7, unit="%", role="device"),
        Claim(id="m.gain", paper="009", where="Table 2", statement="Compensation gains 10x.", kind="emergent",
              quantity="gain", comparator=in_range(3.0, 30.0), paper_value=10.0, unit="x"),
        Claim(id="m.kn", paper="009", where="Table 3", statement="The compensated K_n is 0.4 %.",
              kind="emergent", quantity="kn", comparator=within_factor(0.4), paper_value=0.4, unit="%"),
        Claim(id="m.sel", paper="009", where="Sec. 4", statement="Stepwise selects the paper's set.",
              kind="emergent", quantity="sel", comparator=is_true(),
              precondition=Precondition(text="truth R^2 at least 0.9", quantity="r2", comparator=above(0.9))),
    )
    units = [{"raw": float(rng.normal(15.7, 1.0)), "gain": float(rng.lognormal(np.log(12.0), 0.3)),
              "kn": float(rng.normal(16.9, 2.0)), "sel": 1.0, "r2": float(i < 3)} for i in range(20)]
    control = [{"raw": 1.0, "gain": 1.0, "kn": 16.0, "sel": 0.0, "r2": 0.0} for _ in range(20)]
    results = evaluate(claims, units, control)
    return Outcome(scenario="p009", title="p009", seed=1, config={}, units=20, claims=results,
                   results={"unit_quantities": [{"seed": 1 + i, **u} for i, u in enumerate(units)],
                            "control_quantities": [{"seed": 1 + i, **u} for i, u in enumerate(control)]})


_MEASURED = re.compile(r'(?P<where>[^";]+), "(?P<statement>[^"]+)" \(median (?P<median>\S+) (?P<unit>\S+) vs the '
                       r"paper's (?P<paper>\S+) \S+, (?P<holds>\d+)/(?P<testable>\d+) units, control "
                       r"(?P<ch>\d+)/(?P<ct>\d+)\)")


def test_every_figure_of_the_findings_recounts_from_results_json(tmp_path, monkeypatch):
    from gyrobench.scenarios import papers

    monkeypatch.setattr(papers, "sources", dict)
    write_report([_mixed_outcome()], tmp_path)
    (doc,) = readme_table.load_report(tmp_path)
    by_statement = {c["statement"].rstrip("."): c for c in doc["claims"]}
    status = {c["id"]: c["status"] for c in doc["claims"]}
    assert (status["m.gain"], status["m.kn"], status["m.sel"]) == (
        "reproduced", "contradicted", "not reproducible on this device")
    bullet = findings(doc, "009")
    found = list(_MEASURED.finditer(bullet))
    assert {m["statement"] for m in found} == {"Compensation gains 10x", "The compensated K_n is 0.4 %"}
    for m in found:
        c = by_statement[m["statement"]]
        holds, testable, median = _recount(c, doc["unit_quantities"])
        assert (int(m["holds"]), int(m["testable"])) == (holds, testable)
        assert (int(m["ch"]), int(m["ct"])) == _recount(c, doc["control_quantities"], precondition=False)[:2]
        assert m["median"] == fmt(median) and m["paper"] == fmt(c["paper_value"]) and m["unit"] == c["unit"]
    absent = "Not reproducible on this device: Sec. 4 (precondition absent on 17 of 20 units: truth R^2 at least 0.9)"
    assert absent in bullet
    summary, table = readme_table.format_summary([doc]), readme_table.format_table([doc])
    assert bullet in table and bullet not in summary  # the findings go to docs/results.md
    assert "1 of 4 claims are calibrated (device 1)" in summary
    assert calibrated_count(doc["claims"])[:2] == (1, 4)
    # the first screen of the HTML page counts the calibrated claims too
    page = (tmp_path / "index.html").read_text()
    assert page.index("1 of 4 claims are calibrated") < page.index("Claims at a glance")


def _shape(block: str) -> list[str]:
    """A spliced block's fixed lines, every figure replaced: what the generator writes whatever the report
    (the devices block, one bullet per paper whose text depends on the maps the report holds, aside)."""
    devices = "The device each paper's default run uses"
    lines = block.splitlines()
    if any(ln.startswith(devices) for ln in lines):
        start = next(i for i, ln in enumerate(lines) if ln.startswith(devices))
        end = next((i for i in range(start + 2, len(lines)) if not lines[i].startswith("- ")), len(lines))
        lines = lines[:start - 1 if start and not lines[start - 1] else start] + lines[end:]
    keep = [ln for ln in lines if not ln.startswith(("| ", "- **", "|---"))]
    shape = [re.sub(r"\d+(\.\d+)?", "#", ln) for ln in keep]
    return [re.sub(r"calibrated \([a-z #,]+\):", "calibrated (by role):", ln) for ln in shape]


def _marked(text: str) -> str:
    return text.split(readme_table.BEGIN + "\n", 1)[1].split(readme_table.END, 1)[0]


def test_readme_results_are_generated_not_written(toy_report):
    """The README's spliced block has the generator's form (its fixed lines, figures aside, are what the
    generator writes from a report; every paper has its tally row and its default device's bullet), and the
    README's Results section holds no figure outside it. Fails until the README is regenerated with
    ``python -m gyrobench.scenarios.reports.readme_table <report> --splice docs/results.md --summary README.md``."""
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    block = _marked(readme)
    checks = {"scenario": "physics_checks", "checks": [{"id": "c1", "passed": True}]}
    generated = readme_table.format_summary([*readme_table.load_report(toy_report), checks])
    assert _shape(block) == _shape(generated)
    tally = [ln for ln in block.splitlines() if ln.startswith("| ") and not ln.startswith("| paper |")]
    bullets = [ln for ln in block.splitlines() if ln.startswith("- ") and " the default run uses " in ln]
    assert len(tally) == len(bullets) >= 1  # each paper: its tally row and its default device's bullet
    for row, bullet in zip(tally, bullets, strict=True):
        assert bullet.startswith(f"- {row.split(' | ')[0][2:]} (")
    section = readme.split("\n## Results\n", 1)[1].split("\n## ", 1)[0]
    outside = section.replace(block, "").replace(readme_table.BEGIN, "").replace(readme_table.END, "")
    prose = [ln for ln in outside.splitlines() if "readme_table" not in ln]
    assert not [ln for ln in prose if re.search(r"\d", ln)], "hand-written figures beside the generated block"
