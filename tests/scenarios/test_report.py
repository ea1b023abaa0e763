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
from gyrobench.scenarios.report import fmt, write_report


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
        figures=[FigureSpec("fig_a", "first figure", _figure("tab:red")), FigureSpec("fig_b", "second", _figure("tab:blue"))],
        headlines=[Headline("K_n [%]", "0.14", "0.14", holds, "held-out run")],
        conclusion="It holds.",
        runtime_s=1.5,
    )


def test_fmt():
    assert fmt(1.234567) == "1.235" and fmt(None) == "n/a" and fmt(float("nan")) == "n/a"
    assert fmt(1.5e-7) == "1.500e-07" and fmt(True) == "yes" and fmt("x") == "x" and fmt(3) == "3"


def test_files_and_results_json(tmp_path):
    index = write_report([_outcome("alpha"), _outcome("beta", holds=False)], tmp_path, command="gyrobench reproduce --all")
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
    """The report of two real scenarios (the fastest, ~8 s), not a synthetic one, in Chromium."""
    from gyrobench.scenarios.cli import main

    out = tmp_path / "rep"
    assert main(["reproduce", "mems_scale_factor", "rlg_thermal", "--out", str(out)]) == 0
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
    summary = re.search(r"<h2>Summary</h2>\s*<h3>[^<]*</h3>\s*<table>(.*?)</table>", dom.stdout, re.S)
    assert summary, "summary table missing: " + dom.stdout[:1000]
    rows = re.findall(r"<tr>(.*?)</tr>", summary.group(1), re.S)
    scen = {re.match(r"<td>([^<]*)</td>", r).group(1) for r in rows[1:]}
    assert scen == {"mems_scale_factor", "rlg_thermal"}  # a headline row for each scenario
