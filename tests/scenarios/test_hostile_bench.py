"""Hostile stores and compensators (issue 32): no code from data, identity that follows the code.

A crafted units database (a pickle payload, a type outside gyrobench, a class that is not a
frozen dataclass) must run no code and be refused in one line; every paper's real unit result
must round-trip through the store's codec bit-identically.
"""

from __future__ import annotations

import dataclasses
import json
import pickle
import sqlite3
import zlib

import numpy as np
import pytest

from gyrobench.scenarios import registry
from gyrobench.scenarios.cli.main import main
from gyrobench.scenarios.runner import codec, units
from tests.scenarios import toy_paper as toy

# every test runs among planted user files and fails if one changes (tests/conftest.py)
pytestmark = pytest.mark.usefixtures("user_files")

TOY_CONFIG = toy.Config(n_samples=50)


# ----------------------------------------------------------------------------- codec
def _same(a, b, path="result"):
    """Structural equality, arrays compared bit for bit (dtype, shape, bytes)."""
    assert type(a) is type(b), (path, type(a), type(b))
    if isinstance(a, np.ndarray):
        assert a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes(), path
    elif dataclasses.is_dataclass(a):
        for f in dataclasses.fields(a):
            _same(getattr(a, f.name), getattr(b, f.name), f"{path}.{f.name}")
    elif isinstance(a, (list, tuple)):
        assert len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            _same(x, y, f"{path}[{i}]")
    elif isinstance(a, dict):
        assert list(a) == list(b), path
        for k in a:
            _same(a[k], b[k], f"{path}[{k!r}]")
    elif isinstance(a, float):
        assert np.float64(a).tobytes() == np.float64(b).tobytes(), path  # NaN and -0.0 included
    else:
        assert a == b, path


@pytest.mark.parametrize(
    "value",
    [
        None, True, 0, -(2**70), 1.5, -0.0, float("nan"), float("-inf"), "text", [1, (2, 3.0)],
        {"a": None, 3: "x", (1, 2): [4]},
        np.arange(12, dtype=">i4").reshape(3, 4), np.array([np.nan, 1e-300, -0.0], dtype=np.float32),
        np.zeros((0, 3)), np.array([1 + 2j]), np.float32(2.5), np.int64(7), np.bool_(True),
        np.asfortranarray(np.arange(6.0).reshape(2, 3)),
    ],
)
def test_codec_round_trips_plain_values_exactly(value):
    _same(value, codec.loads(codec.dumps(value)))


PAPERS = [n for n in registry.available() if registry.describe(n).paper is not None]


@pytest.mark.slow
@pytest.mark.parametrize("name", PAPERS)
def test_every_papers_real_unit_result_round_trips(name):
    """A real unit (seed 0, default config) comes back equal, arrays bit-identical, through text."""
    module = registry.get(name)
    unit = module.experiment(module.Config(), 0)
    back = codec.loads(codec.dumps(unit).encode("utf-8"))
    _same(unit, back)


class NotOurs:
    """A plain class (not a dataclass)."""


@dataclasses.dataclass
class Mutable:
    x: int = 0


def test_codec_refuses_values_it_cannot_store():
    for bad in (NotOurs(), Mutable(), {1, 2}, np.array(["a"]), np.array([object()])):
        with pytest.raises(codec.CodecError):
            codec.dumps(bad)


_CLAIM = "gyrobench.scenarios.claims:Claim"


def _doc(value) -> str:
    return json.dumps({"schema": codec.SCHEMA, "value": value})


@pytest.mark.parametrize(
    "text, match",
    [
        ("not json", "not valid JSON"),
        (json.dumps({"schema": "other", "value": 1}), "not of schema"),
        (_doc({"$dc": {"type": "os:system", "fields": {}}}), "outside the gyrobench package"),
        (_doc({"$dc": {"type": "subprocess:Popen", "fields": {"args": "true"}}}), "outside the gyrobench"),
        (_doc({"$dc": {"type": "gyrobench.scenarios.cli.main:main", "fields": {}}}), "not a frozen dataclass"),
        (_doc({"$dc": {"type": "gyrobench.scenarios.base:Outcome", "fields": {}}}), "not a frozen dataclass"),
        (_doc({"$dc": {"type": "gyrobench.scenarios.runner.codec:np", "fields": {}}}), "not a frozen dataclass"),
        (_doc({"$dc": {"type": "gyrobench.nothere:X", "fields": {}}}), "no module"),
        (_doc({"$dc": {"type": "gyrobench.scenarios.runner.units:__builtins__", "fields": {}}}), "not a frozen"),
        (_doc({"$dc": {"type": "gyrobench.scenarios.runner.units:UnitRun", "fields": {"x": 1}}}), "has fields"),
        (_doc({"$dc": {"type": "gyrobench.scenarios.runner.units:UnitRun.__init__", "fields": {}}}), "not a frozen"),
        (_doc({"$reduce": ["os.system", ["echo pwned"]]}), "unknown tag"),
        (_doc({"$nd": {"dtype": "|O", "shape": [1], "data": "AAAAAAAAAAA="}}), "not a numeric numpy dtype"),
        (_doc({"$nd": {"dtype": "<f8", "shape": [10**9, 10**9], "data": ""}}), "exceeds the limit"),
        (_doc({"$nd": {"dtype": "<f8", "shape": [2], "data": "AAAA"}}), "does not hold 16 bytes"),
        (_doc({"$float": "1e5"}), r"\$float must be"),
        (_doc({"a": 1, "b": 2}), "one tag key"),
        ('{"schema": "' + codec.SCHEMA + '", "value": NaN}', "non-JSON constant"),
    ],
)
def test_codec_refuses_crafted_documents_in_one_line(text, match):
    with pytest.raises(codec.CodecError, match=match) as info:
        codec.loads(text)
    assert "\n" not in str(info.value)


class _Payload:
    """Unpickling this writes a marker file: proof that code ran."""

    def __init__(self, marker):
        self.marker = marker

    def __reduce__(self):
        return (open, (self.marker, "w"))


def _crafted_units_db(tmp_path, blob):
    """A units database whose row for (toy, seed 0) holds ``blob``, under the real run id."""
    db = tmp_path / "units.sqlite"
    rid, ident = units.run_id(toy, TOY_CONFIG)
    conn = units._open_store(db, rid, toy.NAME, TOY_CONFIG, ident)
    conn.execute("INSERT INTO unit_results VALUES (?, ?, ?, ?, ?, 1)", (rid, 0, blob, 0.1, 0.0))
    conn.close()
    return db


@pytest.mark.parametrize(
    "make",
    [
        lambda marker: pickle.dumps(_Payload(str(marker))),
        lambda marker: _doc({"$dc": {"type": "tests.scenarios.test_hostile_bench:_Payload",
                                     "fields": {"marker": str(marker)}}}).encode(),
        lambda marker: _doc({"$dc": {"type": "builtins:open", "fields": {"file": str(marker)}}}).encode(),
        lambda marker: _doc({"$dc": {"type": "gyrobench.scenarios.base:Outcome", "fields": {}}}).encode(),
    ],
    ids=["pickle-payload", "type-outside-gyrobench", "builtin-callable", "non-dataclass"],
)
def test_crafted_units_db_runs_no_code_and_is_refused_in_one_line(tmp_path, make):
    marker = tmp_path / "pwned"
    db = _crafted_units_db(tmp_path, make(marker))
    with pytest.raises(ValueError, match=r"stored unit \(seed 0\) refused") as info:
        units.run_units(toy, TOY_CONFIG, n_units=1, workers=0, db=db)
    assert "\n" not in str(info.value)
    assert not marker.exists()


def test_crafted_units_db_through_reproduce_exits_2_with_one_line(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(registry.SCENARIOS, "toy_paper", "tests.scenarios.toy_paper")
    marker = tmp_path / "pwned"
    module = registry.get("toy_paper")
    config = module.Config()
    db = tmp_path / "units.sqlite"
    rid, ident = units.run_id(module, config)
    conn = units._open_store(db, rid, module.NAME, config, ident)
    conn.execute("INSERT INTO unit_results VALUES (?, ?, ?, ?, ?, 1)",
                 (rid, 0, pickle.dumps(_Payload(str(marker))), 0.1, 0.0))
    conn.close()
    argv = ["reproduce", "toy_paper", "--units", "2", "--workers", "0", "--db", str(db),
            "--out", str(tmp_path / "rep"), "-q"]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "never unpickled" in err[0], err
    assert not marker.exists()


def test_units_store_holds_json_and_resumes_identically(tmp_path):
    db = tmp_path / "u.sqlite"
    first = units.run_units(toy, TOY_CONFIG, n_units=3, workers=0, db=db)
    again = units.run_units(toy, TOY_CONFIG, n_units=3, workers=0, db=db)
    assert again.reused == 3 and again.computed == 0
    _same(list(first.results), list(again.results))
    with sqlite3.connect(db) as conn:
        blobs = [bytes(b) for (b,) in conn.execute("SELECT result FROM unit_results")]
    assert blobs and all(b.startswith(codec.COMPRESSED_MAGIC) for b in blobs)
    assert all(json.loads(zlib.decompress(b[len(codec.COMPRESSED_MAGIC):]))["schema"] == codec.SCHEMA for b in blobs)


# ----------------------------------------------------------------------------- configs
def test_physics_checks_config_imports_nothing_outside_its_registry(tmp_path, capsys, monkeypatch):
    """``modules = ["this"]`` would print the Zen of Python if imported: refused in one line listing
    the valid modules, before anything is imported."""
    import sys

    from gyrobench.scenarios import physics_checks
    from gyrobench.scenarios.checks.core import CHECK_MODULES

    monkeypatch.delitem(sys.modules, "this", raising=False)
    with pytest.raises(ValueError, match=r"Config.modules\[0\] must be one of \(.*; got .this.$") as info:
        physics_checks.Config(modules=("this",))
    assert all(m in str(info.value) for m in CHECK_MODULES) and "\n" not in str(info.value)
    cfg = tmp_path / "c.toml"
    cfg.write_text('modules = ["this"]\n')
    code = main(["reproduce", "physics_checks", "--config", str(cfg), "--out", str(tmp_path / "rep"), "-q"])
    captured = capsys.readouterr()
    assert code == 2 and "this" not in sys.modules
    err = captured.err.strip().splitlines()
    assert len(err) == 1 and "check modules" in err[0], err
    assert "Beautiful is better" not in captured.out


# ----------------------------------------------------------------------------- identity
from gyrobench.scenarios import bench  # noqa: E402
from gyrobench.scenarios.bench import identity  # noqa: E402
from tests.scenarios import toy_scenario  # noqa: E402

FAST = toy_scenario.Config(n_samples=60)

_COMP = '''
import numpy as np
import {helper}


class Poly:
    """A polynomial fit without get_params: its state is its attributes."""

    def __init__(self, degree):
        self.degree = degree

    def __call__(self, X, y):
        coef = np.polyfit(X[:, 0], y, self.degree) * {helper}.SCALE
        return lambda Z: np.polyval(coef, Z[:, 0])


POLY = Poly({degree})
'''


def _user_compensator(tmp_path, monkeypatch, name, degree=1, scale="1.0"):
    """A compensator file ``<name>.py`` importing a helper module beside it (both top-level,
    outside any package), imported afresh."""
    import importlib
    import sys

    helper = f"{name}_helper"
    (tmp_path / f"{helper}.py").write_text(f"SCALE = {scale}\n")
    (tmp_path / f"{name}.py").write_text(_COMP.format(helper=helper, degree=degree))
    monkeypatch.syspath_prepend(str(tmp_path))
    for m in (name, helper):
        sys.modules.pop(m, None)
    importlib.invalidate_caches()
    return importlib.import_module(name)


def test_editing_a_helper_module_beside_the_compensator_changes_the_campaign_id(tmp_path, monkeypatch):
    mod = _user_compensator(tmp_path, monkeypatch, "gb_comp_a")
    before = identity.campaign_id(toy_scenario, mod.POLY, FAST)
    assert identity.campaign_id(toy_scenario, mod.POLY, FAST) == before  # stable while nothing changes
    mod = _user_compensator(tmp_path, monkeypatch, "gb_comp_a", scale="1600.0")
    assert identity.campaign_id(toy_scenario, mod.POLY, FAST) != before


def test_a_constructor_argument_without_get_params_changes_the_campaign_id(tmp_path, monkeypatch):
    mod = _user_compensator(tmp_path, monkeypatch, "gb_comp_b")
    assert identity.campaign_id(toy_scenario, mod.Poly(1), FAST) != identity.campaign_id(
        toy_scenario, mod.Poly(3), FAST
    )
    assert identity.campaign_id(toy_scenario, mod.Poly(3), FAST) == identity.campaign_id(
        toy_scenario, mod.Poly(3), FAST
    )


def test_changed_helper_recomputes_instead_of_serving_old_scores(tmp_path, monkeypatch):
    db = tmp_path / "c.db"
    mod = _user_compensator(tmp_path, monkeypatch, "gb_comp_c")
    first = bench.run_campaign(toy_scenario, mod.POLY, range(2), config=FAST, workers=0, db=db, progress=False)
    mod = _user_compensator(tmp_path, monkeypatch, "gb_comp_c", scale="1600.0")
    second = bench.run_campaign(toy_scenario, mod.POLY, range(2), config=FAST, workers=0, db=db, progress=False)
    assert (second.reused, second.computed) == (0, 2)
    assert second.scores != first.scores


def test_a_score_edited_in_the_db_is_recomputed_with_a_warning_never_dropped(tmp_path):
    from sklearn.linear_model import LinearRegression

    db = tmp_path / "c.db"
    kw = dict(config=FAST, workers=0, db=db, progress=False)
    first = bench.run_campaign(toy_scenario, LinearRegression(), range(3), **kw)
    with sqlite3.connect(db) as conn:
        (text,) = conn.execute("SELECT scores FROM seed_scores WHERE seed = 1").fetchone()
        doc = json.loads(text)
        doc[sorted(doc)[0]] = "nan"
        conn.execute("UPDATE seed_scores SET scores = ? WHERE seed = 1", (json.dumps(doc, sort_keys=True),))
    with pytest.warns(RuntimeWarning, match=r"seed\(s\) 1 do not match their checksum"):
        again = bench.run_campaign(toy_scenario, LinearRegression(), range(3), **kw)
    assert (again.reused, again.computed) == (2, 1)
    assert again.scores == first.scores and not again.failed
    third = bench.run_campaign(toy_scenario, LinearRegression(), range(3), **kw)  # now verified: reused
    assert (third.reused, third.computed) == (3, 0)


def test_a_row_without_a_checksum_is_recomputed(tmp_path):
    from sklearn.linear_model import LinearRegression

    db = tmp_path / "c.db"
    kw = dict(config=FAST, workers=0, db=db, progress=False)
    bench.run_campaign(toy_scenario, LinearRegression(), range(2), **kw)
    with sqlite3.connect(db) as conn:
        conn.execute("DELETE FROM seed_checksums WHERE seed = 0")
    with pytest.warns(RuntimeWarning, match="checksum"):
        again = bench.run_campaign(toy_scenario, LinearRegression(), range(2), **kw)
    assert (again.reused, again.computed) == (1, 1)


# ----------------------------------------------------------------------------- containment
# module level, so worker processes import them as "module:attr"
def exits_in_fit(X, y):
    """Calls sys.exit(7) in fit."""
    import sys

    sys.exit(7)


def exits_in_predict(X, y):
    """Fits; calls sys.exit(0) on predict."""
    import sys

    return lambda Z: sys.exit(0)


def complex_pred(X, y):
    """Predicts complex values."""
    return lambda Z: np.zeros(len(Z)) + 1j


def hangs_in_fit(X, y):
    """Never returns (swallowing every Exception on the way)."""
    import time

    while True:
        try:
            time.sleep(0.05)
        except Exception:  # noqa: BLE001, S110 - a hostile compensator
            pass


@pytest.mark.parametrize(
    "comp, reason",
    [
        (exits_in_fit, "the compensator called sys.exit(7)"),
        (exits_in_predict, "the compensator called sys.exit(0)"),
        (complex_pred, "the prediction on run run1 is complex (complex128)"),
    ],
    ids=["sys-exit-in-fit", "sys-exit-in-predict", "complex"],
)
@pytest.mark.parametrize("workers", [0, 1])
def test_misbehaving_compensator_makes_the_seed_failed_with_its_reason(tmp_path, comp, reason, workers):
    camp = bench.run_campaign(toy_scenario, comp, range(2), config=FAST, workers=workers, db=tmp_path / "c.db",
                              progress=False)
    assert sorted(camp.failed) == [0, 1]
    assert all(r.startswith(reason) for r in camp.failed.values()), camp.failed


@pytest.mark.parametrize("workers", [0, 1])
def test_a_hanging_compensator_is_failed_at_the_seed_timeout_and_retried_by_a_rerun(tmp_path, workers):
    import time

    t0 = time.monotonic()
    camp = bench.run_campaign(toy_scenario, hangs_in_fit, [3], config=FAST, workers=workers, db=tmp_path / "c.db",
                              progress=False, seed_timeout=0.5)
    assert time.monotonic() - t0 < 30
    assert camp.failed[3].startswith("exceeded the per-seed time limit of 0.5 s")
    with sqlite3.connect(tmp_path / "c.db") as conn:
        assert conn.execute("SELECT COUNT(*) FROM seed_scores").fetchone() == (0,)  # not stored


@pytest.mark.parametrize(
    "comp, words",
    [
        ("exits_in_fit", "seed 0: the compensator called sys.exit(7)"),
        ("complex_pred", "is complex"),
    ],
)
def test_cli_misbehaving_compensator_exits_3_naming_seed_and_reason(tmp_path, capsys, monkeypatch, comp, words):
    _assert_failed_seed_exit_3(tmp_path, capsys, monkeypatch, comp, words, workers="0")


def test_cli_seed_timeout_is_checked(tmp_path, capsys):
    for bad in ("0", "-1", "nan", "inf"):
        argv = ["bench", "tests.scenarios.toy_scenario", "--compensator", f"{__name__}:complex_pred",
                "--seed-timeout", bad, "-q"]
        with pytest.raises(SystemExit) as info:  # refused by the flag's parser, naming it
            main(argv)
        assert info.value.code == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "--seed-timeout must be a finite number in (0, 1e+06] s" in err[0], err


# ----------------------------------------------------------------------------- process hygiene
def _children(pid: int) -> set[int]:
    """Live processes whose parent is ``pid`` (Linux /proc)."""
    import os

    out = set()
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as fh:
                    fields = fh.read().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[1]) == pid and fields[0] != "Z":
                out.add(int(entry))
    return out


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def _default_sigint() -> None:
    """In a child before exec: SIGINT back to its default disposition."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _stuck_campaign(tmp_path, workers: int):
    """A `gyrobench bench` process whose compensator never returns, once its workers run."""
    import subprocess
    import sys
    import time
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    argv = [sys.executable, "-c", "import sys; from gyrobench.scenarios.cli.main import main; sys.exit(main())",
            "bench", "tests.scenarios.toy_scenario", "--compensator", f"{__name__}:hangs_in_fit",
            "--seeds", "0:4", "--workers", str(workers), "--no-references", "--db", str(tmp_path / "c.db"), "-q"]
    # SIGINT at its default in the child whatever this process inherited: a background job (a CI
    # script started with `&`) ignores SIGINT, and Python then installs no KeyboardInterrupt handler
    proc = subprocess.Popen(argv, cwd=root, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=_default_sigint)
    deadline = time.monotonic() + 60
    kids: set[int] = set()
    while time.monotonic() < deadline and len(kids) < max(workers, 1):
        time.sleep(0.2)
        kids = _children(proc.pid) if workers else {proc.pid}
    time.sleep(2.0)  # the seeds are in fit (the toy task takes well under a second)
    assert proc.poll() is None, proc.communicate()
    return proc, _children(proc.pid)


@pytest.mark.slow
def test_workers_die_within_seconds_of_a_sigkilled_parent(tmp_path):
    import os
    import signal
    import time

    proc, kids = _stuck_campaign(tmp_path, workers=2)
    assert kids
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    deadline = time.monotonic() + 5
    while time.monotonic() < deadline and any(_alive(k) for k in kids):
        time.sleep(0.1)
    assert not [k for k in kids if _alive(k)]


@pytest.mark.slow
@pytest.mark.parametrize("sig, code, line", [("SIGTERM", 143, "gyrobench: error: terminated (SIGTERM)"),
                                             ("SIGINT", 130, "gyrobench: interrupted")])
@pytest.mark.parametrize("workers", [0, 2])
def test_one_signal_stops_a_stuck_campaign_within_seconds_with_one_line(tmp_path, sig, code, line, workers):
    import signal
    import time

    proc, kids = _stuck_campaign(tmp_path, workers=workers)
    t0 = time.monotonic()
    proc.send_signal(getattr(signal, sig))
    # a campaign the signal did not stop would wait for the hanging fit until the seed's deadline
    # (--seed-timeout, 600 s): 60 s separates the two on a loaded machine too (the stop takes
    # well under a second idle; 10 s was exceeded at load 6)
    _, err = proc.communicate(timeout=60)
    assert time.monotonic() - t0 < 60
    assert proc.returncode == code
    assert err.strip().splitlines() == [line]
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline and any(_alive(k) for k in kids):
        time.sleep(0.1)
    assert not [k for k in kids if _alive(k)]


def os_exit_in_fit(X, y):
    """Ends its process with status 0 in fit, bypassing every Python handler."""
    import os

    os._exit(0)


def segfault_in_predict(X, y):
    """Fits; reads address 0 on predict (SIGSEGV)."""
    import ctypes

    return lambda Z: ctypes.string_at(0)


@pytest.mark.parametrize(
    "comp, words",
    [
        ("os_exit_in_fit", "seed 0: the compensator's process exited with code 0"),
        ("segfault_in_predict", "seed 0: the compensator's process killed by SIGSEGV"),
    ],
)
@pytest.mark.parametrize("workers", ["0", "1"])
def test_cli_a_compensator_that_ends_its_process_fails_the_seed_exit_3(tmp_path, capsys, monkeypatch, comp, words,
                                                                       workers):
    """Also with ``--workers 0``: every seed runs in its own forked process, so neither the
    compensator's ``os._exit`` nor its segfault can end the campaign."""
    _assert_failed_seed_exit_3(tmp_path, capsys, monkeypatch, comp, words, workers=workers)


def test_workers_0_runs_an_unpicklable_closure_and_survives_os_exit_on_every_seed(tmp_path):
    """``workers=0`` forks (nothing pickled in): a closure compensator still runs, and a seed
    whose compensator ends its process is failed while the other seeds score."""
    import os

    end_process = [False]

    def fit(X, y):  # a closure: it does not pickle
        if end_process[0]:
            os._exit(5)
        return lambda Z: np.zeros(len(Z))

    camp = bench.run_campaign(toy_scenario, fit, range(2), config=FAST, workers=0, db=tmp_path / "c.db",
                              progress=False)
    assert camp.failed == {} and len(camp.ok_seeds) == 2
    end_process[0] = True
    camp = bench.run_campaign(toy_scenario, fit, [5, 6], config=FAST, workers=0, db=tmp_path / "d.db",
                              progress=False)
    assert sorted(camp.failed) == [5, 6]
    assert all("exited with code 5" in r for r in camp.failed.values()), camp.failed


@pytest.mark.slow
def test_reproduce_workers_die_within_seconds_of_a_sigkilled_parent(tmp_path):
    """The units runner's local pool: its workers die with a SIGKILLed `reproduce`."""
    import os
    import signal
    import subprocess
    import sys
    import time

    argv = [sys.executable, "-c", "import sys; from gyrobench.scenarios.cli.main import main; sys.exit(main())",
            "reproduce", "rlg_thermal", "--units", "8", "--workers", "2", "--out", str(tmp_path / "rep"), "-q"]
    proc = subprocess.Popen(argv, cwd=tmp_path, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 60
    kids: set[int] = set()
    while time.monotonic() < deadline and len(kids) < 2 and proc.poll() is None:
        time.sleep(0.2)
        kids = _children(proc.pid)
    assert kids and proc.poll() is None
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    deadline = time.monotonic() + 5
    while time.monotonic() < deadline and any(_alive(k) for k in kids):
        time.sleep(0.1)
    assert not [k for k in kids if _alive(k)]


def _assert_failed_seed_exit_3(tmp_path, capsys, monkeypatch, comp, words, *, workers):
    """``gyrobench bench`` with compensator ``comp`` on the toy exits 3 in one line containing ``words``."""
    monkeypatch.chdir(tmp_path)
    argv = ["bench", "tests.scenarios.toy_scenario", "--compensator", f"{__name__}:{comp}", "--seeds", "0:2",
            "--workers", workers, "--no-references", "--db", str(tmp_path / "c.db"), "-q"]
    assert main(argv) == 3
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("gyrobench: error:") and words in err[0], err


def test_compressed_rows_round_trip_and_a_truncated_or_inflating_one_is_refused(monkeypatch):
    value = {"x": np.arange(1000, dtype=np.float32), "q": (1.5, None)}
    blob = codec.dumps_compressed(value)
    assert blob.startswith(codec.COMPRESSED_MAGIC) and len(blob) < len(codec.dumps(value))
    back = codec.loads(blob)
    assert back["q"] == (1.5, None) and back["x"].tobytes() == value["x"].tobytes()
    for bad, why in ((blob[:-10], "truncated"), (codec.COMPRESSED_MAGIC + b"not zlib", "not a valid compressed")):
        with pytest.raises(codec.CodecError, match=why) as info:
            codec.loads(bad)
        assert "\n" not in str(info.value)
    monkeypatch.setattr(codec, "MAX_DOCUMENT_BYTES", 1000)
    with pytest.raises(codec.CodecError, match="inflates beyond 1000 bytes"):
        codec.loads(codec.COMPRESSED_MAGIC + zlib.compress(b" " * 100_000))
