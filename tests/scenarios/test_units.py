"""Tests of scenarios/runner/units.py (the shared runner of paper scenarios) on a toy paper scenario."""

from __future__ import annotations

import json
import os
import pickle
import signal
import sqlite3
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

from gyrobench.scenarios.claims import evaluate
from gyrobench.scenarios.runner import units
from tests.scenarios import toy_paper as toy
from tests.scenarios import toy_scenario

ROOT = Path(__file__).resolve().parents[2]

_KILL_SCRIPT = """
import sys
sys.path.insert(0, {root!r})
from gyrobench.scenarios.runner import units
from tests.scenarios import toy_paper as toy
units.run_units(toy, toy.Config(sleep_s=0.05), n_units={n}, workers=2, db={db!r})
"""


def _rows(db: Path) -> int:
    try:
        with sqlite3.connect(f"file:{db}?mode=ro", uri=True, timeout=5) as conn:  # never creates the file
            return conn.execute("SELECT COUNT(*) FROM unit_results").fetchone()[0]
    except sqlite3.OperationalError:  # not created yet
        return 0


@pytest.mark.slow  # end to end: SIGKILLs a running reproduction and resumes it: slow tier
def test_killed_with_sigkill_resumes_with_nothing_lost_or_recomputed(tmp_path, monkeypatch):
    n = 80
    db = tmp_path / "kill.db"
    log1, log2 = tmp_path / "calls1.log", tmp_path / "calls2.log"
    proc = subprocess.Popen(
        [sys.executable, "-c", _KILL_SCRIPT.format(root=str(ROOT), n=n, db=str(db))],
        env=dict(os.environ, GYROBENCH_TOY_CALL_LOG=str(log1)),
        start_new_session=True,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    try:
        deadline = time.monotonic() + 120
        while _rows(db) < 6:
            if proc.poll() is not None:
                pytest.fail(
                    f"run exited early ({proc.returncode}): " + proc.stderr.read().decode()[-2000:]
                )
            if time.monotonic() > deadline:
                pytest.fail("the run did not commit 6 units within 120 s")
            time.sleep(0.02)
        os.killpg(proc.pid, signal.SIGKILL)  # the runner and its worker processes
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
    with sqlite3.connect(db) as conn:
        assert conn.execute("PRAGMA integrity_check").fetchone()[0] == "ok"
        committed = {s for (s,) in conn.execute("SELECT seed FROM unit_results")}
    assert 6 <= len(committed) < n, "the kill must land mid-run"
    assert committed <= set(_calls(log1))
    monkeypatch.setenv("GYROBENCH_TOY_CALL_LOG", str(log2))
    run = units.run_units(toy, toy.Config(sleep_s=0.05), n_units=n, workers=2, db=db)
    assert _calls(log2) == Counter(set(range(n)) - committed)  # nothing committed is recomputed
    assert (run.computed, run.reused) == (n - len(committed), len(committed))
    for s in (min(committed), max(set(range(n)) - committed)):  # nothing lost or altered
        assert pickle.dumps(run.results[s]["quantities"]) == pickle.dumps(
            toy.experiment(toy.Config(sleep_s=0.05), s)["quantities"]
        )


def _calls(path) -> Counter:
    return Counter(map(int, path.read_text().split())) if path.exists() else Counter()


def test_run_units_in_seed_order_and_as_experiment_gives(tmp_path):
    run = units.run_units(toy, toy.Config(), seed=3, n_units=4, workers=0, db=tmp_path / "u.db")
    assert run.seeds == (3, 4, 5, 6)
    assert (run.computed, run.reused) == (4, 0)
    for s, r in zip(run.seeds, run.results, strict=True):
        direct = toy.experiment(toy.Config(), s)
        assert r["quantities"] == direct["quantities"]
        np.testing.assert_array_equal(r["trace"], direct["trace"])


def test_resumes_and_recomputes_nothing(tmp_path, monkeypatch):
    db = tmp_path / "u.db"
    log = tmp_path / "calls.log"
    monkeypatch.setenv("GYROBENCH_TOY_CALL_LOG", str(log))
    monkeypatch.setenv("GYROBENCH_TOY_FAIL_SEED", "4")
    with pytest.raises(RuntimeError, match="seed 4"):
        units.run_units(toy, toy.Config(), seed=0, n_units=8, workers=0, db=db)
    assert _calls(log) == Counter(range(5))  # 0..3 finished and committed, 4 failed
    with sqlite3.connect(db) as conn:
        assert sorted(s for (s,) in conn.execute("SELECT seed FROM unit_results")) == [0, 1, 2, 3]
    monkeypatch.delenv("GYROBENCH_TOY_FAIL_SEED")
    log.unlink()
    run = units.run_units(toy, toy.Config(), seed=0, n_units=8, workers=0, db=db)
    assert _calls(log) == Counter(range(4, 8))  # only the unfinished units, each once
    assert (run.computed, run.reused) == (4, 4)
    log.unlink()
    again = units.run_units(toy, toy.Config(), seed=0, n_units=8, workers=0, db=db)
    assert not log.exists() and (again.computed, again.reused) == (0, 8)
    assert pickle.dumps(again.results) == pickle.dumps(run.results)


def test_another_config_is_another_run(tmp_path, monkeypatch):
    db = tmp_path / "u.db"
    log = tmp_path / "calls.log"
    monkeypatch.setenv("GYROBENCH_TOY_CALL_LOG", str(log))
    a = units.run_units(toy, toy.Config(), n_units=2, workers=0, db=db)
    b = units.run_units(toy, toy.Config(noise=0.2), n_units=2, workers=0, db=db)
    assert a.run_id != b.run_id and b.computed == 2
    assert _calls(log) == Counter({0: 2, 1: 2})
    assert a.results[0]["quantities"]["residual"] != b.results[0]["quantities"]["residual"]


def test_bit_identical_for_any_worker_count(tmp_path):
    out = {}
    for w in (0, 1, 2):
        o = units.run_paper(
            toy, toy.Config(), seed=10, n_units=6, workers=w, db=tmp_path / f"w{w}.db"
        )
        timing = o.results.pop("unit_run")  # per-unit runtimes differ from run to run
        o.results.pop("control_run")
        assert timing["seeds"] == list(range(10, 16)) and timing["computed"] == 6
        out[w] = pickle.dumps(([c.as_dict() for c in o.claims], o.results, o.tables))
    assert out[0] == out[1] == out[2]


def test_run_paper_fills_the_outcome(tmp_path):
    o = units.run_paper(toy, toy.Config(), seed=2, n_units=6, workers=0, db=tmp_path / "u.db")
    assert (o.seed, o.units) == (2, 6)
    assert o.deviations == list(toy.DEVIATIONS)
    assert [c.claim.id for c in o.claims] == [c.id for c in toy.CLAIMS]
    assert o.runtime_s > 0 and o.results["unit_run"]["seeds"] == list(range(2, 8))
    # the claims are exactly evaluate() over the units' quantities
    qs = [toy.experiment(toy.Config(), s)["quantities"] for s in range(2, 8)]
    # the control: the same seeds under control_config, judged beside the units
    cqs = [toy.experiment(toy.control_config(toy.Config()), s)["quantities"] for s in range(2, 8)]
    assert [c.as_dict() for c in o.claims] == [c.as_dict() for c in evaluate(toy.CLAIMS, qs, cqs)]
    assert o.results["control_run"]["seeds"] == list(range(2, 8))
    assert o.results["control_run"]["run_id"] != o.results["unit_run"]["run_id"]
    by = {c.claim.id: c for c in o.claims}
    assert by["toy.even"].testable == 3  # seeds 2, 4, 6: None on odd seeds
    assert by["toy.sane"].holds == 6
    gains = sorted(q["gain"] for q in qs)
    assert by["toy.gain"].median == pytest.approx((gains[2] + gains[3]) / 2, rel=1e-15)
    assert by["toy.gain"].holds == sum(0.5 <= g <= 2.0 for g in gains)


def test_refuses_bad_arguments(tmp_path):
    db = tmp_path / "u.db"
    with pytest.raises(ValueError, match="n_units must be an integer >= 1; got 0"):
        units.run_units(toy, toy.Config(), n_units=0, db=db)
    with pytest.raises(ValueError, match="seed must be an integer >= 0; got -1"):
        units.run_units(toy, toy.Config(), seed=-1, db=db)
    with pytest.raises(ValueError, match="workers must be an integer >= 0"):
        units.run_units(toy, toy.Config(), workers=-2, db=db)
    with pytest.raises(ValueError, match="not a paper scenario"):
        units.run_units(toy_scenario, toy_scenario.Config(), db=db)
    with pytest.raises(FileNotFoundError, match="does not exist"):
        units.run_units(toy, toy.Config(), db=tmp_path / "nope" / "u.db")


def test_is_paper_scenario():
    assert units.is_paper_scenario(toy)
    assert not units.is_paper_scenario(toy_scenario)


@pytest.mark.slow
def test_dask_localcluster_equals_local(tmp_path, monkeypatch):
    """Units on a dask.distributed cluster (the --scheduler path) give the local run's results."""
    pytest.importorskip("distributed")
    from distributed import Client, LocalCluster

    from gyrobench.scenarios import registry
    from gyrobench.scenarios.cli.main import main

    ref = units.run_paper(toy, toy.Config(), n_units=6, workers=0, db=tmp_path / "ref.db")
    monkeypatch.setitem(registry.SCENARIOS, "toy_paper", "tests.scenarios.toy_paper")
    with (
        LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster,
        Client(cluster) as client,
    ):
        o = units.run_paper(
            toy, toy.Config(), n_units=6, executor=client.get_executor(), db=tmp_path / "d.db"
        )
        argv = ["reproduce", "toy_paper", "--units", "6", "--out", str(tmp_path / "rep"), "-q"]
        assert main([*argv, "--scheduler", cluster.scheduler_address]) == 0
    assert [c.as_dict() for c in o.claims] == [c.as_dict() for c in ref.claims]
    doc = json.loads((tmp_path / "rep" / "toy_paper" / "results.json").read_text())
    assert [c["holds"] for c in doc["claims"]] == [c.holds for c in ref.claims]
    assert [c["median"] for c in doc["claims"]] == [c.median for c in ref.claims]


def test_a_config_variant_can_mark_a_claim_calibrated():
    """The runner judges claims_for(config) when a scenario defines it (paper 001's v_max variant)."""
    from gyrobench.scenarios.papers import p001_mems_scale_factor as ms
    from gyrobench.scenarios.runner.units import module_claims

    default = {c.id: c.kind for c in module_claims(ms, ms.Config(variant="design"))}
    variant = {c.id: c.kind for c in module_claims(ms, ms.Config(variant="calibrated"))}
    assert default["001.raw_kn"] == "emergent" and variant["001.raw_kn"] == "calibrated"
    assert {k for k in default if default[k] != variant[k]} == set(default)  # every claim


# ------------------------------------------------------------------ a small store
def _stored(db) -> dict[tuple[str, int], tuple[bytes, int]]:
    with sqlite3.connect(db) as conn:
        rows = conn.execute("SELECT run_id, seed, result, full FROM unit_results")
        return {(r, s): (bytes(b), f) for r, s, b, f in rows}


def test_store_keeps_the_report_units_whole_and_the_rest_slim(tmp_path, monkeypatch):
    """With SLIM_FIELDS and REPORT_UNITS = 1 the first unit of the main run is stored whole, the
    others and every control unit with the slimmed field emptied; the claims are those of a run
    that keeps every unit whole, and a run asking for whole units recomputes the slim ones."""
    monkeypatch.setattr(toy, "SLIM_FIELDS", ("trace",), raising=False)
    monkeypatch.setattr(toy, "REPORT_UNITS", 1, raising=False)
    slim_db, whole_db = tmp_path / "slim.db", tmp_path / "whole.db"
    o = units.run_paper(toy, toy.Config(), seed=3, n_units=4, workers=0, db=slim_db)
    k = units.run_paper(toy, toy.Config(), seed=3, n_units=4, workers=0, db=whole_db, keep_units=True)
    assert [c.as_dict() for c in o.claims] == [c.as_dict() for c in k.claims]
    rid = o.results["unit_run"]["run_id"]
    rows = _stored(slim_db)
    assert {s: f for (r, s), (_, f) in rows.items() if r == rid} == {3: 1, 4: 0, 5: 0, 6: 0}
    assert {f for (r, _), (_, f) in rows.items() if r != rid} == {0}  # the control's units
    assert all(f == 1 for _, f in _stored(whole_db).values())
    run = units.run_units(toy, toy.Config(), seed=3, n_units=4, workers=0, db=slim_db)
    assert run.computed == 3 and run.reused == 1
    assert all(r["trace"].shape == (20,) for r in run.results)
    again = units.run_units(toy, toy.Config(), seed=3, n_units=4, workers=0, db=slim_db, whole=1)
    assert again.computed == 0 and again.reused == 4  # a whole unit serves a slim request


def test_slim_result_empties_arrays_and_keeps_the_quantities():
    """The emptied field keeps its dtype and number of dimensions; nothing else changes."""
    import types

    mod = types.SimpleNamespace(SLIM_FIELDS=("trace",))
    r = toy.experiment(toy.Config(), 1)
    r["trace"] = {"a": np.ones((3, 4), np.float32), "b": (np.arange(5), 2.0)}
    s = units.slim_result(mod, r)
    assert s["quantities"] == r["quantities"]
    assert s["trace"]["a"].shape == (0, 0) and s["trace"]["a"].dtype == np.float32
    assert s["trace"]["b"][0].size == 0 and s["trace"]["b"][1] == 2.0
    assert r["trace"]["a"].shape == (3, 4)  # the original is untouched


def test_a_store_of_the_previous_format_is_refused_in_one_line(tmp_path, capsys, monkeypatch):
    """A unit store whose table has the previous layout (no ``full`` column) is refused, by the
    runner and by ``reproduce`` (exit 2, one line naming the file), and left as it was."""
    db = tmp_path / "old.sqlite"
    with sqlite3.connect(db) as conn:
        conn.execute("CREATE TABLE unit_results (run_id TEXT NOT NULL, seed INTEGER NOT NULL, result BLOB NOT NULL, "
                     "elapsed_s REAL NOT NULL, finished REAL NOT NULL, PRIMARY KEY (run_id, seed))")
        conn.execute("INSERT INTO unit_results VALUES ('x', 0, x'00', 1.0, 0.0)")
    before = db.read_bytes()
    with pytest.raises(ValueError, match="older gyrobench") as info:
        units.run_units(toy, toy.Config(), n_units=1, workers=0, db=db)
    assert "\n" not in str(info.value) and str(db) in str(info.value)
    from gyrobench.scenarios import registry
    from gyrobench.scenarios.cli.main import main

    monkeypatch.setitem(registry.SCENARIOS, "toy_paper", "tests.scenarios.toy_paper")
    assert main(["reproduce", "toy_paper", "--units", "1", "--workers", "0", "--db", str(db),
                 "--out", str(tmp_path / "rep"), "-q"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "older gyrobench" in err[0], err
    assert db.read_bytes() == before


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="glibc's mallopt")
def test_keep_freed_memory_takes_on_glibc_and_changes_no_value(tmp_path):
    """The allocator setting is accepted (glibc) and idempotent; units computed in a process that has
    it equal, bit for bit, those of a process where it is never applied (another store)."""
    code = (
        "import pickle, sys\n"
        "from gyrobench.scenarios.runner import units\n"
        "from tests.scenarios import toy_paper as toy\n"
        "if sys.argv[1] == 'off':\n"
        "    ok, units.keep_freed_memory = False, lambda: False\n"
        "else:\n"
        "    ok = units.keep_freed_memory() and units.keep_freed_memory()\n"
        "r = units.run_units(toy, toy.Config(), n_units=3, workers=0, db=sys.argv[2])\n"
        "sys.stdout.buffer.write(pickle.dumps((ok, [x['trace'].tobytes() for x in r.results])))\n"
    )
    out = {}
    for mode in ("on", "off"):
        env = dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parents[2]))
        res = subprocess.run([sys.executable, "-c", code, mode, str(tmp_path / f"{mode}.db")], capture_output=True,
                             env=env, check=True)
        out[mode] = pickle.loads(res.stdout)
    assert out["on"][0] is True
    assert out["on"][1] == out["off"][1]
