"""Report writer: files, formats, atomicity, and rendering in a real browser."""

import json
import re
import shutil
import subprocess
from dataclasses import dataclass

import numpy as np
import pytest
from matplotlib.figure import Figure

from gyrobench.scenarios.base import FigureSpec, Headline, Outcome, Table
from gyrobench.scenarios.claims import Claim, Deviation, Precondition, above, evaluate, is_true, within_factor
from gyrobench.scenarios.reports.report import claim_tally, fmt, write_report


@dataclass(frozen=True)
class _Cfg:
    fs_hz: float = 100.0
    rates: tuple = (1.0, 2.0)


def _figure(color):
    fig = Figure(figsize=(4, 3))
    ax = fig.add_subplot()
    x = np.linspace(0, 10, 100)
    ax.plot(x, np.sin(x), color=color, lw=3)
    return fig


def _outcome(name="toy", holds=True):
    return Outcome(
        scenario=name,
        title=f"{name} title",
        seed=3,
        config=_Cfg(),
        results={"value_pct": 0.14, "array": np.arange(3), "nan": float("nan")},
        tables=[Table("Table 1. <things>", ["a", "b [deg/h]"], [["x", 1.234567], ["y", None]], note="target 1.2")],
        figures=[FigureSpec("fig_a", "first figure", _figure("tab:red")),
                 FigureSpec("fig_b", "second", _figure("tab:blue"))],
        headlines=[Headline("K_n [%]", "0.14", "0.14", holds, "held-out run")],
        conclusion="It holds.",
        runtime_s=1.5,
    )


def test_fmt():
    assert fmt(1.234567) == "1.235" and fmt(None) == "n/a" and fmt(float("nan")) == "n/a"
    assert fmt(1.5e-7) == "1.500e-07" and fmt(True) == "yes" and fmt("x") == "x" and fmt(3) == "3"


def test_files_and_results_json(tmp_path):
    index = write_report([_outcome("alpha"), _outcome("beta", holds=False)], tmp_path,
                         command="gyrobench reproduce --all")
    assert index == tmp_path / "index.html"
    for name in ("alpha", "beta"):
        doc = json.loads((tmp_path / name / "results.json").read_text())
        assert doc["scenario"] == name and doc["seed"] == 3 and doc["config"] == {"fs_hz": 100.0, "rates": [1.0, 2.0]}
        assert doc["value_pct"] == 0.14 and doc["array"] == [0, 1, 2] and doc["nan"] is None
        assert "gyrobench_version" in doc and doc["runtime_s"] == 1.5
        assert (tmp_path / name / "fig_a.png").read_bytes()[:4] == b"\x89PNG"
        assert "**Table 1. <things>**" in (tmp_path / name / "report.md").read_text()
    html = index.read_text()
    assert "Table 1. &lt;things&gt;" in html  # escaped
    assert html.count("data:image/png;base64,") == 4  # self-contained
    assert "<td class='no'>NO</td>" in html  # a failed conclusion stands out
    assert "gyrobench reproduce --all" in html
    md = (tmp_path / "report.md").read_text()
    assert md.startswith("# gyrobench report") and "| alpha | K_n [%] | 0.14 | 0.14 | yes |" in md
    assert not list(tmp_path.rglob("*.tmp"))


def _chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        exe = shutil.which(name)
        if exe:
            return exe
    return None


_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
          "--disable-background-networking", "--disable-component-update", "--disable-sync", "--hide-scrollbars"]


@pytest.mark.skipif(_chromium() is None, reason="Chromium not installed (.ci/run installs Debian's chromium)")
@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_report_renders_in_a_browser(tmp_path):
    index = write_report([_outcome("alpha"), _outcome("beta")], tmp_path / "rep")
    exe = _chromium()
    profile = tmp_path / "profile"
    dom = subprocess.run(
        [exe, *_FLAGS, f"--user-data-dir={profile}", "--virtual-time-budget=10000", "--dump-dom", index.as_uri()],
        capture_output=True, text=True, timeout=120,
    )
    assert dom.returncode == 0, dom.stderr[-2000:]
    m = re.search(r'data-figures-loaded="(\d+)"\s+data-figures-total="(\d+)"', dom.stdout)
    assert m, "load check did not run: " + dom.stdout[:500]
    assert m.group(1) == m.group(2) == "4"  # every embedded figure decoded
    assert "Summary" in dom.stdout
    shot = tmp_path / "shot.png"
    r = subprocess.run(
        [exe, *_FLAGS, f"--user-data-dir={profile}", "--window-size=1200,2400", f"--screenshot={shot}", index.as_uri()],
        capture_output=True, text=True, timeout=120,
    )
    assert r.returncode == 0 and shot.is_file(), r.stderr[-2000:]
    from matplotlib.image import imread

    img = imread(shot)[..., :3]
    # the red and blue curves of the figures are on screen, not only text
    red = (img[..., 0] > 0.7) & (img[..., 1] < 0.3) & (img[..., 2] < 0.3)
    blue = (img[..., 2] > 0.6) & (img[..., 0] < 0.3)
    assert red.sum() > 200 and blue.sum() > 200


@pytest.mark.slow
@pytest.mark.skipif(_chromium() is None, reason="Chromium not installed (.ci/run installs Debian's chromium)")
def test_real_report_renders_in_a_browser(tmp_path):
    """The report of two real scenarios (the fastest), not a synthetic one, in Chromium. Three units
    each: the report has the same sections, tables and figures as with the default 20 (which took
    ~160 s of the slow tier here); what 20 units add is claims' statistics, not rendering, and
    the CI's main job writes that full report anyway."""
    from gyrobench.scenarios.cli.main import main

    out = tmp_path / "rep"
    assert main(["reproduce", "mems_scale_factor", "rlg_thermal", "--units", "3", "-q", "--out", str(out)]) == 0
    index = out / "index.html"
    n_img = index.read_text().count("<img ")
    assert n_img >= 2  # both scenarios have figures
    dom = subprocess.run(
        [_chromium(), *_FLAGS, f"--user-data-dir={tmp_path / 'profile'}", "--virtual-time-budget=10000",
         "--dump-dom", index.as_uri()],
        capture_output=True, text=True, timeout=120,
    )
    assert dom.returncode == 0, dom.stderr[-2000:]
    m = re.search(r'data-figures-loaded="(\d+)"\s+data-figures-total="(\d+)"', dom.stdout)
    assert m, "load check did not run: " + dom.stdout[:500]
    # every <img> decoded (complete and naturalWidth > 0), and the browser saw all of them
    assert int(m.group(1)) == int(m.group(2)) == n_img
    summary = re.search(r"<h2[^>]*>Summary</h2>(.*?)<h2", dom.stdout, re.S)
    assert summary, "summary missing: " + dom.stdout[:1000]
    for name in ("mems_scale_factor", "rlg_thermal"):  # each scenario's claims (or headlines) are there
        assert f">{name}<" in summary.group(1)


def _paper_outcome():
    claims = (
        Claim(id="p.a", paper="001", where="Table 2", statement="K_n is about 15.71 %.", kind="calibrated",
              calibrated_input="knee width solved for 15.71 %", quantity="a", comparator=within_factor(15.71),
              paper_value=15.71, unit="%", role="device"),
        Claim(id="p.b", paper="001", where="Sec. 4", statement="The residual drops by more than 10x.",
              kind="emergent", quantity="b", comparator=above(10.0), paper_value=10.0, unit="x"),
        Claim(id="p.c", paper="001", where="Sec. 5", statement="The fit converges in every run.",
              kind="emergent", quantity="c", comparator=is_true()),
        Claim(id="p.d", paper="001", where="Sec. 5", statement="The method finds the knee.",
              kind="emergent", quantity="c", comparator=is_true(),
              precondition=Precondition(text="the unit has a knee", quantity="knee", comparator=above(0.5))),
        Claim(id="p.e", paper="001", where="Sec. 6", statement="The split keeps Q.", kind="emergent",
              quantity="c", comparator=is_true()),
    )
    units = [{"a": 15.0 + i, "b": 2.0 + i % 3, "c": 1.0, "knee": float(i < 3)} for i in range(20)]
    control = [{"a": 1.0, "b": 1.0, "c": float(i % 7 != 0), "knee": 0.0} for i in range(20)]
    o = _outcome("paper")
    o.headlines = []
    o.claims = evaluate(claims, units, control)
    o.deviations = [Deviation(paper="001", what="target", paper_says="output - mean", we_do="output - truth",
                              reason="none", effect="ratio 426x -> 18x on unit 0")]
    o.units = 20
    return o


def test_paper_claims_in_their_section_and_results_json(tmp_path, monkeypatch):
    from gyrobench.scenarios import papers

    monkeypatch.setattr(papers, "sources", dict)  # a paper without an entry is named by its key
    o = _paper_outcome()
    n = claim_tally(o.claims)
    # p.a device matched; p.b fails on the units and on the control alike (0/20, 0/20): contradicted;
    # p.c, p.e hold on the control about as often (17/20 vs 20/20, Fisher p = 0.23): no different from
    # the control; p.d lacks its precondition on 17 of 20 units
    assert (n.device, n.device_matched, n.device_calibrated, n.method, n.reproduced, n.contradicted, n.identity,
            n.not_reproducible) == (1, 1, 1, 4, 0, 1, 2, 1)
    index = write_report([o, _outcome("beta")], tmp_path)
    doc = json.loads((tmp_path / "paper" / "results.json").read_text())
    assert doc["units"] == 20 and [c["id"] for c in doc["claims"]] == ["p.a", "p.b", "p.c", "p.d", "p.e"]
    need = {"id", "paper", "where", "statement", "kind", "calibrated_input", "paper_value", "comparator",
            "units", "testable", "holds", "pass_rate", "interval95", "median", "spread", "role", "status",
            "precondition", "precondition_absent", "control", "misses", "provisional", "identity"}
    assert all(need <= set(c) for c in doc["claims"])
    b = doc["claims"][1]
    assert b["holds"] == 0 and b["interval95"][1] < 0.5 and b["status"] == "contradicted"
    assert b["misses"] == {"below": 20, "above": 0, "direction": "below"}
    assert doc["claims"][2]["control"]["holds"] == 17 and doc["claims"][2]["status"] == "no different from the control"
    assert doc["claims"][3]["precondition_absent"] == 17
    assert doc["claims"][3]["precondition"]["text"] == "the unit has a knee"
    assert doc["deviations"][0]["effect"] == "ratio 426x -> 18x on unit 0"
    beta = json.loads((tmp_path / "beta" / "results.json").read_text())
    assert "claims" not in beta  # a scenario without claims keeps its old document
    md = (tmp_path / "report.md").read_text()
    summary = md.split("## Summary", 1)[1].split("\n## paper title", 1)[0]
    # the summary tallies the claims; the claims table stands once, in the paper's own section
    assert "**Claims at a glance**" in summary
    assert "| paper | 001 | 20 | 1 / 1 | 1 / 1 | 0 | 1 | 1 | 2 | 0 | 0 | 0 | 0 / 0 |" in summary
    assert "| p.a |" not in summary
    section = md.split("\n## paper title", 1)[1]
    assert "| p.a | DEVICE MATCHED | K_n is about 15.71 %. | Table 2 | device (calibrated) | 15.71 % |" in section
    assert "| p.b |" in section and "| 0 / 20 |" in section
    assert "CONTRADICTED (median 3 x vs the paper's 10 x; 0 of 20 units pass, most misses below the band)" in section
    assert ("| p.c | NO DIFFERENT FROM THE CONTROL (units 20/20 pass, control 17/20; Fisher p = 0.23) |" in section
            and "| 20 / 20 | 100 % [84, 100] % | 17 / 20 |" in section)
    assert "| 3 / 3 (17 lack the precondition) |" in section
    assert "not reproducible on this device (precondition absent on 17 of 20 units: the unit has a knee)" in section
    assert "Deviations from the paper's protocol" in section and "ratio 426x -> 18x on unit 0" in section
    assert "paper 001 (no entry in scenarios.papers)" in section
    assert md.count("| p.a | DEVICE MATCHED |") == 1
    assert "seeds 3 to 22 (20 units)" in md
    html = index.read_text()
    assert ("<td class='no'>CONTRADICTED (median 3 x vs the paper&#x27;s 10 x; 0 of 20 units pass, most misses "
            "below the band)</td>") in html
    assert "<td class='yes'>DEVICE MATCHED</td>" in html
    assert ("<td class='cal'>NO DIFFERENT FROM THE CONTROL (units 20/20 pass, control 17/20; Fisher p = 0.23)"
            "</td>") in html
    assert "| beta | K_n [%] | 0.14 | 0.14 | yes |" in md  # headline scenarios still summarised
    # the figures open at full size: each embedded image links to its PNG file beside the page
    assert html.count("target='_blank' title='open at full size'>") == html.count("<figure>") >= 2


def test_contents_links_resolve_and_the_tally_comes_first(tmp_path):
    index = write_report([_paper_outcome(), _outcome("beta")], tmp_path)
    page = index.read_text()
    nav = page[page.index("<nav id='contents'>"):page.index("</nav>")]
    links = re.findall(r"href='#([^']+)'", nav)
    ids = set(re.findall(r"id='([^']+)'", page))
    assert links and set(links) <= ids, set(links) - ids
    assert {"summary", "paper", "beta"} <= set(links)
    tally = page[page.index("Claims at a glance"):page.index("Headline numbers")]
    assert "<a href='#paper'>paper</a>" in tally
    # the tally precedes every scenario section, and the page holds each claims table once
    assert page.index("Claims at a glance") < page.index("<h2 id='paper'>")
    assert page.count("<h3>Claims of ") == 1


def test_paper_heading_cites_the_paper(monkeypatch, tmp_path):
    from gyrobench.scenarios import papers

    monkeypatch.setattr(papers, "citation", lambda key, short=False: f"CITATION OF {key}")
    write_report([_paper_outcome()], tmp_path)
    md = (tmp_path / "report.md").read_text()
    assert "**Claims of CITATION OF 001**" in md
    assert "CITATION OF 001. seeds 3 to 22 (20 units)" in md  # the scenario section's header line


def test_results_keys_may_not_overwrite_the_runners_fields():
    from gyrobench.scenarios.base import Outcome
    from gyrobench.scenarios.claims import Deviation
    from gyrobench.scenarios.reports.report import outcome_json

    o = Outcome(scenario="x", title="t", seed=0, config=None, results={"units": [1, 2]})
    o.claims, o.units = [], 3
    o.deviations = [  # any deviation makes the runner's fields appear
        Deviation(paper="000", what="w", paper_says="p", we_do="d", reason="r", effect="e")
    ]
    with pytest.raises(ValueError, match=r"scenario 'x': results keys \['units'\] are reserved"):
        outcome_json(o)


_PAPERS = ("fog_vibration", "mems_scale_factor", "ifog_thermal", "rlg_thermal")


def _layout(index, tmp_path, width=1400):
    """The page's layout marks (see the report's load check) in Chromium at a ``width``-px window."""
    dom = subprocess.run(
        [_chromium(), *_FLAGS, f"--user-data-dir={tmp_path / 'profile'}", f"--window-size={width},900",
         "--virtual-time-budget=20000", "--dump-dom", index.as_uri()],
        capture_output=True, text=True, timeout=300,
    )
    assert dom.returncode == 0, dom.stderr[-2000:]
    body = re.search(r"<body([^>]*)>", dom.stdout)
    assert body, dom.stdout[:500]
    return dict(re.findall(r'data-([a-z-]+)="([^"]*)"', body.group(1)))


@pytest.mark.slow
@pytest.mark.skipif(_chromium() is None, reason="Chromium not installed (.ci/run installs Debian's chromium)")
def test_claims_tables_fit_a_1400_px_screen_and_figures_open_at_full_size(tmp_path):
    """All four papers' report (two units each: the tables have every claim and the figures are the
    default report's; rlg_thermal's section with a two-point device-family map) at a 1400-px
    window: the page does not scroll sideways, no claims table overflows
    its box, the status column's right edge is on screen; figures are shown at their natural width
    (or the page's, when wider) and each links to its own PNG beside the page. The same report's
    results.json files let every claim's pass counts be recounted from their per-unit quantities."""
    import base64

    from gyrobench.scenarios.cli.main import main

    out = tmp_path / "rep"
    # a tiny device-family map first: the report carries it into rlg_thermal's section
    assert main(["reproduce", "rlg_thermal", "--map", "--points", "2", "--units-per-point", "1", "--workers", "0",
                 "-q", "--out", str(out)]) == 0
    assert main(["reproduce", *_PAPERS, "--units", "2", "-q", "--out", str(out)]) == 0
    index = out / "index.html"
    assert "id='rlg_thermal-map'" in index.read_text()
    marks = _layout(index, tmp_path)
    assert marks["viewport-width"] == "1400"
    assert int(marks["claims-tables"]) == len(_PAPERS)
    assert int(marks["scroll-width"]) <= 1400, marks
    assert int(marks["claims-overflow"]) == 0, marks
    assert int(marks["tables-overflow"]) == 0, marks  # nor the first screen's tally (open tables)
    assert 0 < int(marks["status-right"]) <= 1400, marks
    assert marks["figures-loaded"] == marks["figures-total"] != "0"
    assert float(marks["figure-scale"]) >= 0.9, marks  # no figure shrunk to a fraction of its size
    page = index.read_text()
    figures = re.findall(r"<figure><a href='([^']+)'[^>]*><img alt='[^']*' src='data:image/png;base64,([^']+)'>",
                         page)
    assert len(figures) == page.count("<figure>") == int(marks["figures-total"])
    for href, b64 in figures:  # the click target is the same figure, full size
        assert (out / href).read_bytes() == base64.b64decode(b64), href
    from tests.scenarios.test_report_recount import _recount

    for name in _PAPERS:  # every paper's claims recount from the per-unit quantities its results.json carries
        doc = json.loads((out / name / "results.json").read_text())
        for c in doc["claims"]:
            assert _recount(c, doc["unit_quantities"])[:2] == (c["holds"], c["testable"]), (name, c["id"])
            control = _recount(c, doc["control_quantities"], precondition=False)[:2]
            assert control == (c["control"]["holds"], c["control"]["testable"]), (name, c["id"])
