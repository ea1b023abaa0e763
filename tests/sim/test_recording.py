"""Recording: HDF5/CSV round trips, atomic writes, and what loading refuses."""

import json
import os

import h5py
import numpy as np
import pytest

from gyrobench.base.atomic import AtomicWriteError, atomic_path
from gyrobench.io.recording import (
    Channel,
    HDF5StreamWriter,
    Recording,
    RecordingFormatError,
    list_hdf5,
    load_hdf5,
    save_hdf5,
    to_csv,
)


def _rec(n=1000, name="run1"):
    rng = np.random.default_rng([20261121, 1])
    return Recording(
        fs=200.0,
        t0=12.5,
        channels={
            "rate": Channel(rng.standard_normal(n), "rad/s", "gyro output"), "temp": Channel(np.full(n, 300.0), "K")
        },
        truth={"true_rate": Channel(np.zeros(n), "rad/s"), "arw": Channel(rng.standard_normal(n), "rad/s")},
        metadata={"seed": 7, "spec": {"N": 1e-4}, "tags": [1, 2]},
        name=name,
    )


def test_hdf5_round_trip_is_exact(tmp_path):
    rec = _rec()
    save_hdf5(tmp_path / "r.h5", rec)
    back = load_hdf5(tmp_path / "r.h5")
    assert back.fs == rec.fs and back.t0 == rec.t0 and back.name == rec.name
    assert dict(back.metadata) == dict(rec.metadata)
    for k in rec.channels:
        np.testing.assert_array_equal(back[k], rec[k])
        assert back.channels[k].unit == rec.channels[k].unit
    for k in rec.truth:
        np.testing.assert_array_equal(back[f"truth/{k}"], rec[f"truth/{k}"])


def test_hdf5_layout_is_plain_for_matlab(tmp_path):
    # h5read(file, '/recordings/run1/channels/rate') and h5readatt need plain float64 datasets and string attributes
    save_hdf5(tmp_path / "r.h5", _rec())
    with h5py.File(tmp_path / "r.h5", "r") as h5:
        ds = h5["/recordings/run1/channels/rate"]
        assert ds.dtype == np.float64 and ds.ndim == 1
        assert ds.attrs["unit"] == "rad/s"
        assert h5["/recordings/run1"].attrs["fs"] == 200.0
        json.loads(h5["/recordings/run1"].attrs["metadata"])


def test_several_recordings_in_one_file(tmp_path):
    save_hdf5(tmp_path / "r.h5", [_rec(name="a"), _rec(name="b")])
    assert list_hdf5(tmp_path / "r.h5") == ["a", "b"]
    assert load_hdf5(tmp_path / "r.h5", "b").name == "b"
    with pytest.raises(ValueError, match="holds 2 recordings"):
        load_hdf5(tmp_path / "r.h5")
    with pytest.raises(KeyError, match="has no recording 'c'"):
        load_hdf5(tmp_path / "r.h5", "c")
    with pytest.raises(ValueError, match="names must be unique"):
        save_hdf5(tmp_path / "s.h5", [_rec(name="a"), _rec(name="a")])


def test_stream_writer_equals_one_shot(tmp_path):
    rec = _rec(n=10_000)
    with HDF5StreamWriter(tmp_path / "s.h5", name="run1", fs=rec.fs, t0=rec.t0, channels={"rate": "rad/s"},
                          truth={"arw": "rad/s"}, chunk=1000) as w:
        for i in range(0, 10_000, 3333):
            w.append(rate=rec["rate"][i : i + 3333], truth={"arw": rec["truth/arw"][i : i + 3333]})
    back = load_hdf5(tmp_path / "s.h5")
    np.testing.assert_array_equal(back["rate"], rec["rate"])
    np.testing.assert_array_equal(back["truth/arw"], rec["truth/arw"])


def test_interrupted_stream_leaves_no_file(tmp_path):
    target = tmp_path / "s.h5"
    with pytest.raises(RuntimeError, match="boom"):
        with HDF5StreamWriter(target, name="x", fs=1.0, channels={"rate": "rad/s"}) as w:
            w.append(rate=np.zeros(10))
            raise RuntimeError("boom")
    assert not target.exists()
    assert list(tmp_path.iterdir()) == []


def test_interrupted_save_keeps_previous_file(tmp_path, monkeypatch):
    target = tmp_path / "r.h5"
    save_hdf5(target, _rec(name="old"))
    import gyrobench.io.recording as recording

    def broken(h5, rec, **_):
        raise OSError("disk full")

    monkeypatch.setattr(recording, "_write_group", broken)
    with pytest.raises(OSError, match="disk full"):
        save_hdf5(target, _rec(name="new"))
    assert list_hdf5(target) == ["old"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.h5"]


def test_atomic_path_renames_only_on_success(tmp_path):
    target = tmp_path / "x.txt"
    with atomic_path(target) as tmp:
        tmp.write_text("ok")
        assert not target.exists()
    assert target.read_text() == "ok"


def test_truncated_file_is_refused(tmp_path):
    save_hdf5(tmp_path / "r.h5", _rec(n=100_000))
    data = (tmp_path / "r.h5").read_bytes()
    (tmp_path / "t.h5").write_bytes(data[: len(data) // 2])
    with pytest.raises(RecordingFormatError, match="not a readable HDF5 file|incomplete|truncated"):
        load_hdf5(tmp_path / "t.h5")


def test_foreign_hdf5_is_refused(tmp_path):
    with h5py.File(tmp_path / "f.h5", "w") as h5:
        h5["x"] = np.arange(3.0)
    with pytest.raises(RecordingFormatError, match="not a gyrobench recording"):
        load_hdf5(tmp_path / "f.h5")


def test_not_hdf5_is_refused(tmp_path):
    (tmp_path / "n.h5").write_text("time,rate\n0,1\n")
    with pytest.raises(RecordingFormatError, match="not a readable HDF5 file"):
        load_hdf5(tmp_path / "n.h5")


def test_length_mismatch_in_file_is_refused(tmp_path):
    save_hdf5(tmp_path / "r.h5", _rec())
    with h5py.File(tmp_path / "r.h5", "r+") as h5:
        del h5["/recordings/run1/channels/temp"]
        h5["/recordings/run1/channels/temp"] = np.zeros(10)
        h5["/recordings/run1/channels/temp"].attrs["unit"] = "K"
    with pytest.raises(RecordingFormatError, match=r"has shape \(10,\), expected \(1000,\)"):
        load_hdf5(tmp_path / "r.h5")


def test_missing_file():
    with pytest.raises(FileNotFoundError, match="recording file not found"):
        load_hdf5("/nonexistent/x.h5")


def test_csv_export(tmp_path):
    rec = _rec(n=50)
    to_csv(tmp_path / "r.csv", rec)
    lines = (tmp_path / "r.csv").read_text().splitlines()
    assert lines[0].startswith("# written by gyrobench recording")  # the marker a later run may replace it by
    assert lines[1] == "time [s],rate [rad/s],temp [K],truth/true_rate [rad/s],truth/arw [rad/s]"
    data = np.loadtxt(tmp_path / "r.csv", delimiter=",", skiprows=2)
    np.testing.assert_array_equal(data[:, 1], rec["rate"])  # %.17g round-trips float64 exactly
    np.testing.assert_allclose(data[:, 0], rec.time, rtol=1e-15)


@pytest.mark.parametrize(
    ("kwargs", "exc", "match"),
    [
        ({"fs": 0.0}, ValueError, r"^Recording.fs must be > 0 Hz; got 0.0$"),
        ({"fs": float("nan")}, ValueError, r"^Recording.fs must be > 0 Hz; got nan$"),
        ({"channels": {}}, ValueError, "at least one channel"),
        ({"channels": {"rate": np.zeros(3)}}, TypeError, r"channels\['rate'\] must be a Channel"),
        ({"name": "a/b"}, ValueError, "without '/'"),
        ({"metadata": {"x": object()}}, TypeError, "not JSON-serialisable"),
    ],
)
def test_recording_rejects(kwargs, exc, match):
    base = {"fs": 1.0, "channels": {"rate": Channel(np.zeros(3), "rad/s")}}
    base.update(kwargs)
    with pytest.raises(exc, match=match):
        Recording(**base)


def test_unequal_channel_lengths_rejected():
    with pytest.raises(ValueError, match="same length"):
        Recording(fs=1.0, channels={"a": Channel(np.zeros(3), "K"), "b": Channel(np.zeros(4), "K")})


def test_channel_must_be_1d():
    with pytest.raises(ValueError, match="Channel.data must be 1-D"):
        Channel(np.zeros((2, 2)), "K")


# ----------------------------------------------------------------------------- failed writes, permissions, free space
_FSIZE_SCRIPT = r"""
import resource, sys
import numpy as np
from gyrobench.base.atomic import AtomicWriteError
from gyrobench.io.recording import HDF5StreamWriter, Recording, Channel, save_hdf5

resource.setrlimit(resource.RLIMIT_FSIZE, (1_000_000, 1_000_000))
target = sys.argv[1]
try:
    if sys.argv[2] == "stream":
        with HDF5StreamWriter(target, name="x", fs=1.0, channels={"rate": "rad/s"}, chunk=1 << 14) as w:
            for _ in range(20):
                w.append(rate=np.ones(1 << 14))  # 128 kB per call: the limit is hit in append
    else:
        save_hdf5(target, Recording(fs=1.0, channels={"rate": Channel(np.ones(1 << 18), "rad/s")}))
except AtomicWriteError as exc:
    print(f"{exc.errno} {exc}")
"""


@pytest.mark.parametrize("how", ["stream", "save"])
def test_failed_write_is_an_error_naming_the_target_not_a_crash(tmp_path, how):
    # before: the HDF5 file stayed open after the failed flush and the interpreter segfaulted at exit (139)
    import errno
    import subprocess
    import sys

    target = tmp_path / "out" / "big.h5"
    r = subprocess.run([sys.executable, "-c", _FSIZE_SCRIPT, str(target), how], capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 0, (r.returncode, r.stderr)
    assert r.stderr == ""
    assert r.stdout.startswith(f"{errno.EFBIG} cannot write {str(target)!r}: File too large (file-size limit reached")
    assert ".tmp" not in r.stdout
    assert list((tmp_path / "out").iterdir()) == []  # no temporary file, no half-written target


@pytest.mark.parametrize("umask", [0o022, 0o027, 0o077])
def test_written_files_get_the_umask_mode(tmp_path, umask):
    # before: tempfile.mkstemp made every output 0600 whatever the umask
    old = os.umask(umask)
    try:
        save_hdf5(tmp_path / "r.h5", _rec(n=10))
        to_csv(tmp_path / "r.csv", _rec(n=10))
        with HDF5StreamWriter(tmp_path / "s.h5", name="x", fs=1.0, channels={"rate": "rad/s"}) as w:
            w.append(rate=np.zeros(3))
    finally:
        os.umask(old)
    for name in ("r.h5", "r.csv", "s.h5"):
        assert (tmp_path / name).stat().st_mode & 0o777 == 0o666 & ~umask, name


def test_unwritable_target_is_named_not_the_temp_file(tmp_path):
    (tmp_path / "afile").write_text("x")
    target = tmp_path / "afile" / "r.h5"  # a folder that is a file
    with pytest.raises(AtomicWriteError, match=r"cannot write '.*afile/r\.h5'") as info:
        save_hdf5(target, _rec(n=10))
    assert ".tmp" not in str(info.value)


def test_write_error_in_block_names_the_target(tmp_path):
    import errno

    target = tmp_path / "x.txt"
    msg = r"cannot write '.*x\.txt': No space left on device \(the disk is full\)"
    with pytest.raises(AtomicWriteError, match=msg) as info:
        with atomic_path(target) as tmp:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(tmp))
    assert info.value.errno == errno.ENOSPC and ".tmp" not in str(info.value)
    assert list(tmp_path.iterdir()) == []


def test_record_larger_than_free_space_is_refused_before_writing(tmp_path, monkeypatch):
    import shutil

    import gyrobench.base.atomic as atomic

    monkeypatch.setattr(atomic.shutil, "disk_usage", lambda p: shutil._ntuple_diskusage(10**9, 10**9 - 4000, 4000))
    assert _rec(n=1000).nbytes == 4 * 1000 * 8
    with pytest.raises(AtomicWriteError, match=r"needs about 32 kB but .* has 4 kB free"):
        save_hdf5(tmp_path / "r.h5", _rec(n=1000))  # (2 channels + 2 truth) x 1000 x 8 B
    with pytest.raises(AtomicWriteError, match=r"needs about 8 MB but .* has 4 kB free"):
        with HDF5StreamWriter(tmp_path / "s.h5", name="x", fs=1.0, channels={"rate": "rad/s"}, expected_samples=10**6):
            raise AssertionError("the check must come before the file is opened")
    with pytest.raises(AtomicWriteError, match="free"):
        to_csv(tmp_path / "r.csv", _rec(n=1000))
    assert list(tmp_path.iterdir()) == []


def test_stream_writer_rejects_bad_chunk(tmp_path):
    with pytest.raises(ValueError, match="chunk must be an integer > 0 samples; got 0"):
        HDF5StreamWriter(tmp_path / "s.h5", name="x", fs=1.0, channels={"rate": "rad/s"}, chunk=0)


def test_free_space_of_a_pseudo_file_system_is_not_a_limit(tmp_path, monkeypatch):
    import shutil

    from gyrobench.base.atomic import ensure_free_space

    monkeypatch.setattr(shutil, "disk_usage", lambda p: shutil._ntuple_diskusage(0, 0, 0))  # as /proc reports
    ensure_free_space(tmp_path / "x.h5", 10**6)  # no refusal: the write itself will say what is wrong


def test_invalid_stored_fs_names_the_file(tmp_path):
    save_hdf5(tmp_path / "r.h5", _rec(n=10))
    with h5py.File(tmp_path / "r.h5", "r+") as h5:
        h5["/recordings/run1"].attrs["fs"] = 0.0
    msg = r"r\.h5': recording 'run1': attribute 'fs' must be in \[1e-09, 1e\+15\] Hz .*got 0\.0"
    with pytest.raises(RecordingFormatError, match=msg):
        load_hdf5(tmp_path / "r.h5")
