"""Nothing lost, on every verb: no output is an input or a user's file (gyrobench.base.safety).

One test per row of the table of commands that used to exit 0 over their input; then the
markers by which gyrobench recognises its own files, --force, folders, databases, inputs that
are not regular files. Every test runs under the ``user_files`` fixture: planted user files
(and every input the test makes) must be byte-identical when it ends.
"""

from __future__ import annotations

import os
import sqlite3

import numpy as np
import pytest

from gyrobench.base import safety
from gyrobench.scenarios import bench
from gyrobench.scenarios.cli.main import main
from gyrobench.scenarios.runner import store
from tests.scenarios import toy_scenario as toy
from tests.scenarios.test_cli import assert_one_line_error, run

pytestmark = pytest.mark.usefixtures("user_files")

TOY = "tests.scenarios.toy_scenario"


def _real_csv(path, n=3000, seed=1):
    """A user's static record: time [s] and a gyro column [deg/s] at 100 Hz."""
    rng = np.random.default_rng(seed)
    rows = "\n".join(f"{i / 100:.2f},{v:.6f}" for i, v in enumerate(0.01 * rng.standard_normal(n)))
    path.write_text("time [s],gyro_z [deg/s]\n" + rows + "\n")
    return path


def _noise(path, capsys, *extra):
    return run(["simulate", "noise", "--N", "0.1", "--fs", "100", "--duration", "30s", "-q", "-o", path, *extra],
               capsys)


@pytest.fixture(scope="module")
def shared_db(tmp_path_factory):
    """A results database holding the stored seeds of two campaigns (two compensators of the toy)."""
    d = tmp_path_factory.mktemp("shared")
    db = d / "shared.db"
    bench.run_campaign(toy, toy.good, range(2), workers=0, db=db, progress=False)
    bench.run_campaign(toy, toy.fit_least_squares, range(2), workers=0, db=db, progress=False)
    return db


# ----------------------------------------------------------------------------- the table, row by row
def test_row1_bench_db_given_as_save_baseline_is_refused(shared_db, tmp_path, capsys, user_files):
    db = tmp_path / "shared.db"
    db.write_bytes(shared_db.read_bytes())
    user_files.keep(db)
    code, _, err = run(["bench", TOY, "--compensator", f"{TOY}:good", "--seeds", "0:8", "--workers", "0", "-q",
                        "--allow-underpowered", "--db", db, "--save-baseline", db], capsys)
    assert_one_line_error(code, err, "--save-baseline")
    assert str(db) in err and "--db" in err


def test_row2_bench_save_baseline_over_the_compensators_source_is_refused(tmp_path, capsys, monkeypatch,
                                                                         user_files):
    src = user_files.plant(tmp_path / "hc.py", "from tests.scenarios.toy_scenario import good\n")
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    code, _, err = run(["bench", TOY, "--compensator", "hc:good", "--seeds", "0:8", "--workers", "0", "-q",
                        "--allow-underpowered", "--db", tmp_path / "b.db", "--save-baseline", src], capsys)
    assert_one_line_error(code, err, "hc.py")
    assert not (tmp_path / "b.db").exists()  # refused before anything was written


@pytest.mark.parametrize("suffix", [".csv", ".h5"])
def test_row3_twin_output_over_its_real_record_is_refused(suffix, tmp_path, capsys, user_files):
    real = tmp_path / f"real{suffix}"
    if suffix == ".csv":
        _real_csv(real)
    else:  # a gyrobench file: replaced only as an output, never as the command's own input
        assert _noise(real, capsys)[0] == 0
    user_files.keep(real)
    code, _, err = run(["twin", real, "--column", "gyro_z" if suffix == ".csv" else "rate", "-o", real], capsys)
    assert_one_line_error(code, err, "is the input")
    assert err.count(str(real)) == 2  # both paths named


def test_row4_allan_kalibr_over_the_record_is_refused(tmp_path, capsys, user_files):
    real = _real_csv(tmp_path / "real.csv")
    user_files.keep(real)
    code, _, err = run(["allan", real, "--column", "gyro_z", "--kalibr", real], capsys)
    assert_one_line_error(code, err, "is the input")


def test_row5_simulate_device_output_over_its_rate_csv_is_refused(tmp_path, capsys, user_files):
    rates = user_files.plant(tmp_path / "r.csv", "time [s],rate [deg/s]\n0,0\n10,1\n20,1\n")
    code, _, err = run(["simulate", "device", "stim300", "--rate-csv", rates, "-o", rates], capsys)
    assert_one_line_error(code, err, "is the input --rate-csv")


def test_row6_simulate_scenario_into_a_users_folder_is_refused(tmp_path, capsys, monkeypatch, user_files):
    mine = user_files.plant(tmp_path / "static_noise" / "static_mems.h5", kind="hdf5")
    monkeypatch.chdir(tmp_path)
    code, _, err = run(["simulate", "static_noise", "--out", "."], capsys)
    assert_one_line_error(code, err, "is a folder gyrobench did not make")
    assert mine.exists()


# ----------------------------------------------------------------------------- the rest of the family
def test_baseline_given_as_save_baseline_is_refused(tmp_path, capsys, user_files):
    base = tmp_path / "x.json"
    camp = bench.run_campaign(toy, toy.good, range(2), workers=0, db=tmp_path / "a.db", progress=False)
    bench.save_baseline(base, camp)
    user_files.keep(base)
    code, _, err = run(["bench", TOY, "--compensator", f"{TOY}:good", "--workers", "0", "-q", "--allow-underpowered",
                        "--db", tmp_path / "b.db", "--baseline", base, "--save-baseline", base], capsys)
    assert_one_line_error(code, err, "is the input --baseline")


@pytest.mark.parametrize("name", ["foreign.h5", "notes.h5", "notes.csv"])
def test_an_existing_output_gyrobench_did_not_write_is_refused_and_force_replaces_it(name, tmp_path, capsys,
                                                                                     user_files):
    target = tmp_path / name
    if name == "foreign.h5":
        user_files.plant(target, kind="hdf5")
    else:
        user_files.plant(target, "my notes\n")
    code, _, err = _noise(target, capsys)
    assert_one_line_error(code, err, "gyrobench did not write it")
    user_files.verify()
    user_files._kept.pop(target)  # --force replaces it on purpose
    assert _noise(target, capsys, "--force")[0] == 0
    assert safety.written_by_gyrobench(target)


@pytest.mark.parametrize("suffix", [".h5", ".csv"])
def test_gyrobench_replaces_its_own_record(suffix, tmp_path, capsys):
    target = tmp_path / f"rec{suffix}"
    assert _noise(target, capsys)[0] == 0
    assert safety.written_by_gyrobench(target)
    assert _noise(target, capsys)[0] == 0


def test_plot_and_kalibr_over_foreign_files_are_refused_before_the_analysis(tmp_path, capsys, user_files):
    real = _real_csv(tmp_path / "real.csv")
    user_files.keep(real)
    png = user_files.plant(tmp_path / "fig.png", b"\x89PNG\r\n\x1a\nmine")
    code, _, err = run(["allan", real, "--column", "gyro_z", "--plot", png], capsys)
    assert_one_line_error(code, err, "gyrobench did not write it")
    code, _, err = run(["allan", real, "--column", "gyro_z", "--plot", tmp_path / "fig.svg"], capsys)
    assert_one_line_error(code, err, "--plot must end in .png")
    yaml = user_files.plant(tmp_path / "imu.yaml", "mine: 1\n")
    code, _, err = run(["allan", real, "--column", "gyro_z", "--kalibr", yaml], capsys)
    assert_one_line_error(code, err, "gyrobench did not write it")


def test_allan_writes_marked_files_it_may_replace(tmp_path, capsys):
    rec = tmp_path / "rec.h5"
    assert _noise(rec, capsys)[0] == 0
    png, yaml = tmp_path / "a.png", tmp_path / "imu.yaml"
    for _ in range(2):  # the second run replaces the first run's files
        code, out, err = run(["allan", rec, "--plot", png, "--kalibr", yaml, "--accept-nonstationary"], capsys)
        assert code == 0, err
    assert safety.written_by_gyrobench(png) and safety.written_by_gyrobench(yaml)


def test_save_baseline_over_a_users_json_is_refused(tmp_path, capsys, user_files):
    notes = user_files.plant(tmp_path / "notes.json", '{"mine": true}\n')
    code, _, err = run(["bench", TOY, "--compensator", f"{TOY}:good", "--seeds", "0:8", "--workers", "0", "-q",
                        "--allow-underpowered", "--db", tmp_path / "b.db", "--save-baseline", notes], capsys)
    assert_one_line_error(code, err, "gyrobench did not write it")


def test_a_foreign_sqlite_db_is_refused_before_anything_is_written_to_it(tmp_path, capsys, user_files):
    db = user_files.plant(tmp_path / "mine.sqlite", kind="sqlite")
    code, _, err = run(["bench", TOY, "--compensator", f"{TOY}:good", "--seeds", "0:8", "--workers", "0", "-q",
                        "--allow-underpowered", "--db", db], capsys)
    assert_one_line_error(code, err, "an SQLite database gyrobench did not make (tables notes)")
    with pytest.raises(ValueError, match="gyrobench did not make"):  # the library refuses it too
        bench.connect_db(db)
    code, _, err = run(["reproduce", "static_noise", "--out", tmp_path / "rep", "--db", db, "--units", "1"], capsys)
    assert_one_line_error(code, err, "gyrobench did not make")
    assert not (tmp_path / "rep").exists()


def test_a_gyrobench_db_is_marked_and_reused(tmp_path, shared_db):
    assert sqlite3.connect(shared_db).execute("PRAGMA application_id").fetchone()[0] == safety.SQLITE_APPLICATION_ID
    old = tmp_path / "old.db"  # a gyrobench database made before the mark: recognised by its tables
    conn = sqlite3.connect(old)
    conn.executescript(store.SCHEMA)
    conn.close()
    bench.connect_db(old).close()


def test_reproduce_refuses_an_input_inside_the_report_folder(tmp_path, capsys, user_files):
    cfg = user_files.plant(tmp_path / "rep" / "cfg.toml", "")
    code, _, err = run(["reproduce", "static_noise", "--out", tmp_path / "rep", "--config", cfg], capsys)
    assert code == 2 and str(cfg) in err


@pytest.mark.parametrize("kind", ["fifo", "folder", "device"])
def test_an_input_that_is_not_a_regular_file_is_named(kind, tmp_path, capsys):
    if kind == "fifo":
        path, says = tmp_path / "x.csv", "is a FIFO (named pipe)"
        os.mkfifo(path)
    elif kind == "folder":
        path, says = tmp_path / "x.csv", "is a folder"
        path.mkdir()
    else:
        path, says = "/dev/zero", "is a character device"
    for argv in (["allan", path], ["twin", path, "-o", tmp_path / "t.h5"],
                 ["simulate", "device", "stim300", "--profile", path, "-o", tmp_path / "d.h5"],
                 ["simulate", "device", "stim300", "--rate-csv", path, "-o", tmp_path / "d.h5"]):
        code, _, err = run(argv, capsys)
        assert_one_line_error(code, err, says)
    assert not (tmp_path / "t.h5").exists() and not (tmp_path / "d.h5").exists()


def test_a_missing_input_is_not_found(tmp_path, capsys):
    code, _, err = run(["allan", tmp_path / "nope.csv"], capsys)
    assert_one_line_error(code, err, "recording file not found")


# ----------------------------------------------------------------------------- the fixture itself
def test_the_fixture_fails_a_command_that_replaces_its_input(tmp_path, monkeypatch, user_files):
    """With the rule broken (no output is ever an input, every file is taken for gyrobench's) a command
    writes over its input through a link to its folder; the fixture's check at the command's end fails
    the test."""
    rates = tmp_path / "data" / "r.csv"
    rates.parent.mkdir()
    rates.write_text("time [s],rate [deg/s]\n0,0\n10,1\n20,1\n")
    (tmp_path / "alias").symlink_to(rates.parent, target_is_directory=True)
    monkeypatch.setattr(safety, "same_file", lambda a, b: None)
    monkeypatch.setattr(safety, "written_by_gyrobench", lambda p: True)
    with pytest.raises(pytest.fail.Exception, match=r"a user's file changed: .*r\.csv has other bytes"):
        main(["simulate", "device", "stim300", "--rate-csv", str(rates), "-o", str(tmp_path / "alias" / "r.csv"),
              "-q"])


def test_the_fixture_fails_a_test_whose_planted_file_changed(tmp_path, user_files):
    planted = user_files.plant(tmp_path / "mine.txt", "mine\n")
    planted.write_text("changed\n")
    with pytest.raises(pytest.fail.Exception, match="mine.txt has other bytes"):
        user_files.verify()
    planted.write_text("mine\n")  # put back, so the fixture's own check at the end passes


# ----------------------------------------------------------------------------- the rule's parts
def _recording(path):
    from gyrobench.io.recording import Channel, Recording, save_hdf5

    rec = Recording(fs=10.0, channels={"rate": Channel(np.zeros(100), "rad/s")}, name="r")
    return save_hdf5(path, rec)


def test_markers_are_recognised_per_format(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, _ = plt.subplots()
    fig.savefig(tmp_path / "ours.png", metadata=safety.PNG_METADATA)
    fig.savefig(tmp_path / "theirs.png")  # matplotlib's own Software chunk
    plt.close(fig)
    _recording(tmp_path / "ours.h5")
    (tmp_path / "ours.csv").write_text(safety.comment_marker("recording 'r'") + "\ntime [s],rate [rad/s]\n")
    (tmp_path / "ours.yaml").write_text("# Kalibr IMU noise parameters written by gyrobench allan\n")
    (tmp_path / "ours.json").write_text('{\n "format": "gyrobench-baseline"}\n')
    (tmp_path / "theirs.json").write_text('{"notes": 1, "format": "gyrobench-baseline"}\n')  # not the first key
    (tmp_path / "theirs.csv").write_text("time,rate\n# gyrobench\n")
    (tmp_path / "theirs.h5").write_text("text named .h5\n")
    (tmp_path / "empty.h5").write_bytes(b"")
    for name in ("ours.png", "ours.h5", "ours.csv", "ours.yaml", "ours.json"):
        assert safety.written_by_gyrobench(tmp_path / name), name
    for name in ("theirs.png", "theirs.json", "theirs.csv", "theirs.h5", "empty.h5"):
        assert not safety.written_by_gyrobench(tmp_path / name), name


def test_same_file_names_how(tmp_path):
    a = tmp_path / "a.csv"
    a.write_text("x\n")
    (tmp_path / "s").mkdir()
    (tmp_path / "l.csv").symlink_to(a)
    os.link(a, tmp_path / "h.csv")
    assert safety.same_file(a, tmp_path / "s" / ".." / "a.csv") == "the same path"
    assert "symbolic link" in safety.same_file(tmp_path / "l.csv", a)
    assert safety.same_file(tmp_path / "h.csv", a) == "a hard link of it"
    assert safety.same_file(tmp_path / "b.csv", a) is None


def test_a_folder_of_gyrobench_files_without_a_marker_is_written_into(tmp_path):
    """A folder filled before folders were marked holds only gyrobench's files: it may be written into;
    one user file among them makes it foreign."""
    folder = tmp_path / "sim" / "static_noise"
    folder.mkdir(parents=True)
    _recording(folder / "static_mems.h5")
    out = safety.Output(folder, "--out", kind="folder")
    safety.check_outputs([out])
    (folder / "notes.txt").write_text("mine\n")
    with pytest.raises(safety.OutputRefused, match="is a folder gyrobench did not make"):
        safety.check_outputs([out])
    safety.check_outputs([out], force=True)
