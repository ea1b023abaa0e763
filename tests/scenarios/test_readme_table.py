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

    assert tally == (f"| toy | 6 | 0 / 0 | {n('reproduced', 'emergent')} | {n('contradicted')} | 0 "
                     f"| {n('identity of the analysis')} "
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
