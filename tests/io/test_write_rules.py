"""The rules every recording writer applies before it writes (gyrobench.io.write_rules): a record that
names its components closes, and an existing file is replaced only if gyrobench wrote it."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import h5py
import numpy as np
import pytest

from gyrobench.base.safety import OutputRefused
from gyrobench.io.recording import (
    Channel,
    HDF5StreamWriter,
    Recording,
    RecordingClosureError,
    load_hdf5,
    save_hdf5,
    to_csv,
)
from gyrobench.io.write_rules import closure_tolerance
from gyrobench.scenarios.cli.main import main

EPS = np.finfo(float).eps


def _record(miss: float = 0.0, n: int = 1000) -> Recording:
    """A record of two components whose output misses their sum by ``miss`` rad/s on one sample."""
    rng = np.random.default_rng(20261203)
    true = np.full(n, 0.5)
    a, b = 1e-5 * rng.standard_normal(n), np.full(n, 2e-6)
    out = true + a + b
    out[n // 2] += miss
    return Recording(fs=100.0, name="hand", channels={"output": Channel(out, "rad/s")},
                     truth={"true_rate": Channel(true, "rad/s"), "arw": Channel(a, "rad/s"),
                            "bias": Channel(b, "rad/s")},
                     metadata={"error_components": ["arw", "bias"]})


def _stream(path: Path, rec: Recording, **kw) -> None:
    with HDF5StreamWriter(path, name=rec.name, fs=rec.fs, channels={"output": "rad/s"},
                          truth={k: "rad/s" for k in rec.truth}, metadata=dict(rec.metadata), **kw) as w:
        for lo in range(0, rec.n_samples, 300):  # the bad sample lands in the second chunk
            w.append(output=rec["output"][lo:lo + 300], truth={k: c.data[lo:lo + 300] for k, c in rec.truth.items()})


WRITERS = {
    "save_hdf5": lambda p, r, **kw: save_hdf5(p, r, **kw),
    "save_hdf5_gzip": lambda p, r, **kw: save_hdf5(p, r, compression="gzip", **kw),
    "to_csv": lambda p, r, **kw: to_csv(p, r, **kw),
    "stream": _stream,
}


def _suffix(name: str) -> str:
    return ".csv" if name == "to_csv" else ".h5"


@pytest.mark.parametrize("writer", WRITERS)
def test_a_record_that_does_not_close_is_refused_and_nothing_is_written(tmp_path, writer):
    rec = _record(miss=1e-9)  # 1e-9 rad/s (0.2 deg/h): ~5 orders above the rounding of a 0.5 rad/s sum
    path = tmp_path / f"bad{_suffix(writer)}"
    with pytest.raises(RecordingClosureError) as err:
        WRITERS[writer](path, rec)
    msg = str(err.value)
    assert "\n" not in msg and str(path) in msg and "1e-09" in msg and "tolerance" in msg, msg
    assert not path.exists() and list(tmp_path.iterdir()) == []  # no temporary file left either


@pytest.mark.parametrize("writer", WRITERS)
def test_a_record_that_closes_to_rounding_is_written(tmp_path, writer):
    rec = _record()
    path = tmp_path / f"good{_suffix(writer)}"
    WRITERS[writer](path, rec)
    assert path.exists()


def test_the_tolerance_is_the_rounding_bound_of_the_sum():
    """A miss of a few ulps of the largest term passes; ten times the bound does not."""
    rec = _record()
    tol = closure_tolerance(rec, "output", 0.5)
    assert tol == pytest.approx(16 * 4 * EPS * 0.5, rel=1e-12)
    save_hdf5_ok = _record(miss=tol / 4)
    from gyrobench.io.write_rules import check_closes

    check_closes(save_hdf5_ok, "x.h5")
    with pytest.raises(RecordingClosureError):
        check_closes(_record(miss=10 * tol), "x.h5")


def test_a_record_naming_a_component_its_truth_lacks_is_refused(tmp_path):
    rec = _record()
    rec = dataclasses.replace(rec, metadata={"error_components": ["arw", "bias", "shupe"]})
    with pytest.raises(RecordingClosureError, match="shupe"):
        save_hdf5(tmp_path / "x.h5", rec)
    assert not (tmp_path / "x.h5").exists()


def test_a_record_without_a_component_list_is_written_as_it_is(tmp_path):
    """A real log names no components and promises no closure."""
    log = Recording(fs=10.0, channels={"output": Channel(np.arange(100.0), "rad/s")})
    assert load_hdf5(save_hdf5(tmp_path / "log.h5", log)).n_samples == 100


def test_the_command_line_refuses_a_record_that_does_not_close_in_one_line(tmp_path, capsys, monkeypatch):
    from gyrobench.sim import parts

    real = parts.simulate_part

    def broken(*a, **kw):
        rec = real(*a, **kw)
        out = rec.channels["output"]
        return dataclasses.replace(rec, channels={**rec.channels, "output": Channel(out.data + 1e-6, out.unit)})

    monkeypatch.setattr(parts, "simulate_part", broken)
    out = tmp_path / "d.h5"
    code = main(["simulate", "device", "stim300", "--duration", "20s", "--fs", "100", "-o", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "\n" not in err and "does not close" in err and str(out) in err, err
    assert not out.exists()


# ----------------------------------------------------------------------------- replacing files
@pytest.mark.parametrize("writer", WRITERS)
def test_a_foreign_file_is_not_replaced_without_overwrite(tmp_path, writer):
    path = tmp_path / f"mine{_suffix(writer)}"
    if path.suffix == ".h5":
        with h5py.File(path, "w") as h5:
            h5["lab"] = np.arange(3.0)
    else:
        path.write_text("time,rate\n0,1\n")
    before = path.read_bytes()
    with pytest.raises(OutputRefused, match="gyrobench did not write it"):
        WRITERS[writer](path, _record())
    assert path.read_bytes() == before
    WRITERS[writer](path, _record(), overwrite=True)
    assert path.read_bytes() != before


@pytest.mark.parametrize("writer", WRITERS)
def test_a_file_gyrobench_wrote_is_replaced(tmp_path, writer):
    path = tmp_path / f"ours{_suffix(writer)}"
    WRITERS[writer](path, _record())
    first = path.read_bytes()
    rec = _record()
    WRITERS[writer](path, dataclasses.replace(rec, fs=200.0))
    assert path.read_bytes() != first


def test_a_folder_is_never_replaced(tmp_path):
    (tmp_path / "d.h5").mkdir()
    with pytest.raises(OutputRefused, match="folder"):
        save_hdf5(tmp_path / "d.h5", _record(), overwrite=True)
