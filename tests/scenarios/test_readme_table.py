"""The README's reproduced-results table is generated from the report's claims."""

from __future__ import annotations

import pytest

from gyrobench.scenarios import registry
from gyrobench.scenarios.cli.main import main
from gyrobench.scenarios.reports import readme_table


@pytest.fixture
def report(tmp_path, monkeypatch):
    monkeypatch.setitem(registry.SCENARIOS, "toy_paper", "tests.scenarios.toy_paper")
    out = tmp_path / "rep"
    assert (
        main(["reproduce", "toy_paper", "--units", "6", "--workers", "0", "--out", str(out), "-q"])
        == 0
    )
    return out


def test_table_rows_are_the_claims(report, capsys):
    assert readme_table.main([str(report)]) == 0
    text = capsys.readouterr().out
    import json

    claims = json.loads((report / "toy_paper" / "results.json").read_text())["claims"]
    tally, *rows = [r for r in text.splitlines() if r.startswith("| toy |")]
    assert len(rows) == 4  # one per claim, after the paper's tally row
    for row, c in zip(rows, claims, strict=True):
        assert c["statement"] in row and f"{c['holds']}/{c['testable']}" in row and c["status"] in row.lower()
    assert "| method (calibrated) |" in rows[1]
    assert f"| {claims[3]['holds']}/3 (" in rows[3]  # the even-only claim: 3 of 6 units test it
    def n(status, kind=None):
        return sum(c["status"] == status and kind in (None, c["kind"]) for c in claims)

    assert tally == (f"| toy | 6 | 0 / 0 | 0 / 0 | {n('reproduced', 'emergent')} | {n('contradicted')} | 0 "
                     f"| {n('no different from the control') + n('below the control')} "
                     f"| {n('undecided')} | 0 | {n('reproduced', 'calibrated')} | 0 / 0 |")


def test_splice_replaces_only_the_marked_section(report, tmp_path):
    readme = tmp_path / "README.md"
    readme.write_text(
        "# x\n\n## Reproduced "
        f"results\n\nkept\n{readme_table.BEGIN}\nold\n{readme_table.END}\nafter\n"
    )
    assert readme_table.main([str(report), "--splice", str(readme)]) == 0
    text = readme.read_text()
    assert text.startswith("# x\n\n## Reproduced results\n\nkept\n") and text.endswith(
        f"{readme_table.END}\nafter\n"
    )
    assert "\nold\n" not in text and "| toy | Table 1 | The gain is about 1. |" in text


def test_refusals(tmp_path, capsys):
    assert readme_table.main([str(tmp_path)]) == 2
    assert "holds no <scenario>/results.json" in capsys.readouterr().err
    with pytest.raises(ValueError, match="marker lines"):
        readme_table.splice("no markers", "t")


def test_summary_is_the_tally_without_the_claim_rows(report, tmp_path):
    docs = readme_table.load_report(report)
    table, summary = readme_table.format_table(docs), readme_table.format_summary(docs)
    (tally,) = [r for r in summary.splitlines() if r.startswith("| toy |")]
    assert tally in table and "| claim |" not in summary and "| claim |" in table
    readme, results = tmp_path / "README.md", tmp_path / "results.md"
    for f in (readme, results):
        f.write_text(f"head\n{readme_table.BEGIN}\nold\n{readme_table.END}\ntail\n")
    assert readme_table.main([str(report), "--splice", str(results), "--summary", str(readme)]) == 0
    assert readme.read_text() == f"head\n{readme_table.BEGIN}\n{summary}{readme_table.END}\ntail\n"
    assert results.read_text() == f"head\n{readme_table.BEGIN}\n{table}{readme_table.END}\ntail\n"


def test_a_file_without_markers_leaves_both_files_untouched(report, tmp_path):
    readme, results = tmp_path / "README.md", tmp_path / "results.md"
    results.write_text(f"{readme_table.BEGIN}\nold\n{readme_table.END}\n")
    readme.write_text("no markers\n")
    assert readme_table.main([str(report), "--splice", str(results), "--summary", str(readme)]) == 2
    assert results.read_text() == f"{readme_table.BEGIN}\nold\n{readme_table.END}\n"


def test_readme_summary_and_docs_results_come_from_the_same_report():
    """README.md holds the summary, docs/results.md the full table, both generated from one report:
    the README's tally rows are the docs' tally rows, and only the docs hold the claim rows."""
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]

    def marked(path):
        text = path.read_text(encoding="utf-8")
        assert text.count(readme_table.BEGIN) == 1 and text.count(readme_table.END) == 1, path
        return text.split(readme_table.BEGIN, 1)[1].split(readme_table.END, 1)[0]

    summary, table = marked(root / "README.md"), marked(root / "docs" / "results.md")
    assert "| claim |" not in summary and "| claim |" in table
    tally = [r for r in summary.splitlines() if r.startswith("| ") and not r.startswith("| paper |")]
    assert tally and all(r in table.splitlines() for r in tally)
    checks = [r for r in summary.splitlines() if r.startswith("Closed-form checks")]
    assert checks and checks[0] in table


def test_each_paper_names_its_default_device_and_whether_it_lies_in_the_region(report):
    docs = readme_table.load_report(report)
    (line,) = [r for r in readme_table.format_summary(docs).splitlines() if r.startswith("- toy (toy_paper): ")]
    assert "the default run uses the default Config()" in line and "holds no map" in line  # no family, no map
    finding = "No point of the family satisfies every reported device fact (4 points). Never satisfied: toy.f."
    empty = {"points": 4, "region": [], "finding": finding, "medoid": None, "nominal_in_region": False,
             "nominal_missed": ["toy.f"], "nominal_device": "the identified toy device", "refinement": {
                 "triggered": True, "reason": "r", "stages": {"1": {"points": 2, "region": 0},
                                                              "2": {"points": 2, "region": 0}}}}
    paper = next(d for d in docs if d.get("claims"))
    mapped = [dict(paper, map=empty) if d is paper else d for d in docs]
    (line,) = [r for r in readme_table.format_table(mapped).splitlines() if r.startswith("- toy (toy_paper): ")]
    assert "uses the identified toy device" in line and "0 of 4 family points" in line
    assert "(0 of 2 space-filling points, 0 of 2 refined ones)" in line
    assert "lies outside it (misses toy.f)" in line  # why the region is empty: the finding's facts
    assert line.endswith("the region is empty, so no paper-consistent device can be named: Never satisfied: toy.f.")
