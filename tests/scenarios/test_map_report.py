"""A paper's device-family map in its report: the section's tables, results.json's link, the map's
numbers recounted from the JSON alone; a map killed by SIGKILL and resumed gives the same map.json."""

from __future__ import annotations

import json
import os
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pytest

from gyrobench.scenarios import registry
from tests.scenarios.test_cli import run
from tests.scenarios.test_maps import _recount, _recount_nominal

pytestmark = pytest.mark.usefixtures("user_files")

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def toy_registered(monkeypatch):
    monkeypatch.setitem(registry.SCENARIOS, "toy_map_paper", "tests.scenarios.toy_map_paper")


def test_report_section_and_results_json_give_the_map_recounted_from_the_json(toy_registered, tmp_path, capsys):
    out = tmp_path / "r"
    code, _, err = run(["reproduce", "toy_map_paper", "--map", "--points", "8", "--units-per-point", "3",
                        "--workers", "0", "-q", "--out", out], capsys)
    assert code == 0, err
    code, stdout, err = run(["reproduce", "toy_map_paper", "--units", "3", "--workers", "0", "-q", "--out", out],
                            capsys)
    assert code == 0, err
    assert "its device-family map" in stdout
    res = json.loads((out / "toy_map_paper" / "results.json").read_text())
    link = res["map"]
    doc = json.loads((out / "toy_map_paper" / link["file"]).read_text())
    reg, counts, verdicts = _recount(doc)  # independent code: the comparators and Clopper-Pearson redone
    assert link["region"] == reg and link["points"] == 8
    for cid, got in link["claims"].items():
        assert (got["region_holds"], got["region_testable"]) == verdicts[cid][:2]
    assert link["nominal_in_region"] is True  # the toy's nominal (x 0.5, y 0.1) is inside by construction
    assert _recount_nominal(doc) == (True, link["medoid"]["index"])
    md = (out / "toy_map_paper" / "report.md").read_text()
    for cid, n in counts.items():  # the region table's "points satisfying" cells
        assert f"| {cid} |" in md and f"| {n} of 8 |" in md
    for c in doc["claims"]:  # the claims table: the region verdict beside this report's own verdict
        k, n = verdicts[c["id"]][:2]
        line = next(ln for ln in md.splitlines() if ln.startswith(f"| {c['id']} | holds on")
                    or ln.startswith(f"| {c['id']} | no region"))
        assert (f"holds on {k} of {n} region points" in line) or n == 0
        status = next(x for x in res["claims"] if x["id"] == c["id"])["status"]
        assert status.upper() in line.upper()  # this report's own verdict on the nominal device, beside
    from gyrobench.scenarios.reports.readme_table import format_summary, format_table, load_report

    readme = format_summary(load_report(out))  # the README's block names the nominal device and the medoid
    results = format_table(load_report(out))  # docs/results.md gives the medoid's parameters too
    med = link["medoid"]["index"]
    head = (f"{len(reg)} of 8 family points satisfy every reported device fact; the nominal device (these units) "
            f"lies in it; its medoid is point {med} (")
    assert head + "parameters in map.json)" in readme and head + "x = " in results
    page = (out / "index.html").read_text()
    assert "id='toy_map_paper-map'" in page and "Method claims over the region beside the nominal device" in page
    assert page.count("toy_map_paper/phase_diagrams.png") >= 1
    for name in ("map.json", "map_run.json", "phase_diagrams.png", "specification_curves.png", "constraints.png"):
        assert (out / "toy_map_paper" / name).is_file(), name


def _toy_cli(args, env=None, name="toy_map_paper", module="tests.scenarios.toy_map_paper"):
    """``gyrobench`` with a toy paper registered (default the toy map paper), in a child process."""
    boot = ("import sys; from gyrobench.scenarios import registry; "
            f"registry.SCENARIOS[{name!r}] = {module!r}; "
            "from gyrobench.scenarios.cli.main import main; sys.exit(main(sys.argv[1:]))")
    return subprocess.Popen([sys.executable, "-c", boot, *args], cwd=ROOT, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)


def _stored(db: Path) -> int:
    if not db.exists():
        return 0
    try:
        with sqlite3.connect(db, timeout=5) as conn:
            return int(conn.execute("SELECT count(*) FROM unit_results").fetchone()[0])
    except sqlite3.OperationalError:  # the store's tables not created yet
        return 0


@pytest.mark.slow  # three child processes (imports ~3 s each) and a 0.2-s unit delay
def test_a_map_killed_by_sigkill_resumes_to_the_uninterrupted_map_json(tmp_path):
    args = ["reproduce", "toy_map_paper", "--map", "--points", "8", "--units-per-point", "2", "--workers", "0", "-q"]
    env = dict(os.environ, TOY_MAP_UNIT_DELAY_S="0.2")
    db = tmp_path / "k.db"
    child = _toy_cli([*args, "--db", str(db), "--out", str(tmp_path / "k")], env)
    t0 = time.monotonic()
    while _stored(db) < 5 and child.poll() is None and time.monotonic() - t0 < 120:
        time.sleep(0.05)
    assert child.poll() is None, child.communicate()  # still running: killed mid-run
    child.send_signal(signal.SIGKILL)
    child.wait(timeout=60)
    done = _stored(db)
    assert 5 <= done < 18 and not (tmp_path / "k").exists()  # 8 x 2 + the nominal's 2 = 18 units
    resumed = _toy_cli([*args, "--db", str(db), "--out", str(tmp_path / "k")])
    out, err = resumed.communicate(timeout=300)
    assert resumed.returncode == 0, err
    assert f"{18 - done} computed, {done} reused" in out.decode()
    whole = _toy_cli([*args, "--db", str(tmp_path / "w.db"), "--out", str(tmp_path / "w")])
    out, err = whole.communicate(timeout=300)
    assert whole.returncode == 0, err
    a = (tmp_path / "k" / "toy_map_paper" / "map.json").read_bytes()
    assert a == (tmp_path / "w" / "toy_map_paper" / "map.json").read_bytes()
