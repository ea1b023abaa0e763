"""Forged or broken HDF5 input refused before it is read (issue 32.4), ``--start/--stop`` on HDF5, and
recordings checked finite before they are written. Every refusal: one line, exit 2."""

from __future__ import annotations

import json
import math

import h5py
import numpy as np
import pytest

from gyrobench.io.recording import Channel, HDF5StreamWriter, Recording, load_hdf5, save_hdf5, to_csv
from tests.scenarios.test_cli import assert_one_line_error, run

# every test runs among planted user files and fails if one changes (tests/conftest.py)
pytestmark = pytest.mark.usefixtures("user_files")

N = 4000


def _file(path, build, *, n=N):
    """A gyrobench HDF5 file with recording 'r' (fs 10 Hz, n samples, empty truth) completed by build(h5, group)."""
    with h5py.File(path, "w") as f:
        f.attrs["format"] = "gyrobench-recording"
        f.attrs["format_version"] = 1
        g = f.create_group("recordings/r")
        g.attrs.update({"fs": 10.0, "t0": 0.0, "n_samples": n, "metadata": "{}"})
        g.create_group("truth")
        build(f, g)
    return path


def _rate(g, **kw):
    d = g.require_group("channels").create_dataset("rate", **kw)
    d.attrs["unit"] = "rad/s"
    return d


def _plain(f, g):
    _rate(g, data=np.random.default_rng(1).standard_normal(N))


def _recordings_external(f, g):
    _file(f.filename.replace("x.h5", "other.h5"), _plain)
    del f["recordings"]
    f["recordings"] = h5py.ExternalLink("other.h5", "/recordings")


def _recording_external(f, g):
    _file(f.filename.replace("x.h5", "other.h5"), _plain)
    del f["recordings/r"]
    f["recordings/r"] = h5py.ExternalLink("other.h5", "/recordings/r")


def _recording_soft(f, g):
    _plain(f, g)
    f.move("recordings/r", "stash")
    f["recordings/r"] = h5py.SoftLink("/stash")


def _hard_duplicate(f, g):
    _plain(f, g)
    g["truth/rate"] = g["channels/rate"]  # a second hard link to the same dataset


def _external_storage(f, g):
    np.random.default_rng(2).standard_normal(N).tofile(f.filename.replace("x.h5", "raw.bin"))
    _rate(g, shape=(N,), dtype="f8", external=[("raw.bin", 0, N * 8)])


def _unwritten_chunks(f, g):
    d = _rate(g, shape=(N,), dtype="f8", chunks=(N // 20,), compression="gzip")
    d[: N // 20] = 1.0  # 1 chunk of 20 written


def _virtual(f, g):
    src = f.create_dataset("hidden", data=np.random.default_rng(3).standard_normal(N))
    layout = h5py.VirtualLayout(shape=(N,), dtype="f8")
    layout[:] = h5py.VirtualSource(src)
    g.require_group("channels").create_virtual_dataset("rate", layout).attrs["unit"] = "rad/s"


CASES = {
    "recordings-external-link": (_recordings_external, "/recordings is an HDF5 external link to 'other.h5'"),
    "recording-external-link": (_recording_external, "recording 'r' is an HDF5 external link to 'other.h5'"),
    "recording-soft-link": (_recording_soft, "recording 'r' is an HDF5 soft link to '/stash'"),
    "hard-duplicate": (_hard_duplicate, "channels/rate is stored under 2 names in the file (HDF5 hard links)"),
    "external-storage": (_external_storage, "channels/rate keeps its samples in the external file 'raw.bin'"),
    "unwritten-chunks": (_unwritten_chunks, "channels/rate claims 4000 samples in 20 chunks but 1 of them are written"),
    "virtual-dataset": (_virtual, "channels/rate is an HDF5 virtual dataset"),
}


@pytest.mark.parametrize("case", list(CASES))
def test_forged_hdf5_is_refused_in_one_line(tmp_path, capsys, case):
    build, message = CASES[case]
    p = _file(tmp_path / "x.h5", build)
    code, _, err = run(["allan", p], capsys)
    assert_one_line_error(code, err, message)


def test_the_plain_file_of_those_cases_is_read(tmp_path, capsys):
    """The control: the same file without the forgery analyses (exit 0), so the refusals are the forgeries'."""
    p = _file(tmp_path / "x.h5", _plain)
    code, _, err = run(["allan", p, "--terms", "N", "--accept-nonstationary"], capsys)
    assert code == 0, err


def test_compressed_read_counts_its_largest_chunk_against_the_memory_limit(tmp_path, capsys, monkeypatch):
    """2e6 zeros in one gzip chunk: 16 MB of samples plus 16 MB decompressed at once; 24 MB is refused, 40 MB not."""
    n = 2_000_000

    def build(f, g):
        _rate(g, data=np.zeros(n), chunks=(n,), compression="gzip")

    p = _file(tmp_path / "x.h5", build, n=n)
    assert p.stat().st_size < 1e6  # the declared size is all the reader can know before decompressing
    monkeypatch.setenv("GYROBENCH_MEMORY_LIMIT", "24M")
    with pytest.raises(ValueError, match=r"reading .* \(1 channels of 2000000 samples\) needs about 32 MB"):
        load_hdf5(p)
    monkeypatch.setenv("GYROBENCH_MEMORY_LIMIT", "40M")
    assert load_hdf5(p).n_samples == n


def test_start_stop_read_only_the_segment_of_an_hdf5_recording(tmp_path, capsys):
    y = np.random.default_rng(4).standard_normal(N)
    p = save_hdf5(tmp_path / "r.h5", Recording(fs=10.0, t0=5.0, channels={"rate": Channel(y, "rad/s")}, name="r"))
    rec = load_hdf5(p, start=100.0, stop=250.0)
    np.testing.assert_array_equal(rec["rate"], y[1000:2500])
    assert rec.t0 == pytest.approx(105.0)
    code, out, err = run(["allan", p, "--start", "100", "--stop", "250", "--json", "--terms", "N",
                          "--accept-nonstationary"], capsys)
    assert code == 0, err
    doc = json.loads(out)
    assert doc["n_samples"] == 1500 and any("segment 100 s to 250 s" in n for n in doc["notes"])
    code, _, err = run(["allan", p, "--start", "399.85"], capsys)
    assert_one_line_error(code, err, "--start/--stop keep 1 samples of the 400 s of")


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_recordings_are_checked_finite_before_they_are_written(tmp_path, bad):
    y = np.zeros(100)
    y[37] = bad
    rec = Recording(fs=10.0, channels={"rate": Channel(np.zeros(100), "rad/s")}, truth={"bias": Channel(y, "rad/s")})
    for write in (lambda p: save_hdf5(p, rec), lambda p: to_csv(p, rec)):
        with pytest.raises(ValueError, match=rf"recording 'recording': truth/bias has {bad!r} at sample 37 \(1 "):
            write(tmp_path / "r.out")
        assert not (tmp_path / "r.out").exists()
    with pytest.raises(ValueError, match=r"channels/rate has .* at sample 137 \(1 non-finite sample in this block"):
        with HDF5StreamWriter(tmp_path / "s.h5", name="s", fs=10.0, channels={"rate": "rad/s"}) as w:
            w.append(rate=np.zeros(100))
            w.append(rate=y)
    assert not (tmp_path / "s.h5").exists()


# ----------------------------------------------------------------------------- CSV and gzip memory
def test_csv_over_the_memory_limit_is_refused_before_it_is_read(tmp_path, capsys, monkeypatch):
    """A 12 MB CSV with a 20 MB limit: the estimate (text copies and parsed cells) is refused in one line."""
    p = tmp_path / "big.csv"
    rows = "0.001,0.002\n" * 1_000_000
    p.write_text("time [s],gyro [rad/s]\n" + rows)
    monkeypatch.setenv("GYROBENCH_MEMORY_LIMIT", "20M")
    code, _, err = run(["allan", p], capsys)
    assert_one_line_error(code, err, f"reading {str(p)!r} (12 MB of text) needs about")
    assert "GYROBENCH_MEMORY_LIMIT=20M" in err


def test_gzip_bomb_is_refused_while_it_is_decompressed(tmp_path, capsys, monkeypatch):
    """200 MB of text in a ~0.2 MB .gz: refused after decompressing a few MB, never holding more than the limit."""
    import gzip
    import tracemalloc

    p = tmp_path / "bomb.csv.gz"
    block = ("0,0\n" * 250_000).encode()  # 1 MB
    with gzip.open(p, "wb", compresslevel=9) as fh:
        fh.write(b"time [s],gyro [rad/s]\n")
        for _ in range(200):
            fh.write(block)
    assert p.stat().st_size < 1e6
    monkeypatch.setenv("GYROBENCH_MEMORY_LIMIT", "50M")
    tracemalloc.start()
    try:
        code, _, err = run(["allan", p], capsys)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert_one_line_error(code, err, f"reading {str(p)!r} (more than ")
    assert peak < 50e6
