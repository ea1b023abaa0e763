"""One recording schema for every writer (docs/recording.md), checked on a file of each: the command
line's `simulate noise`, `simulate SCENARIO`, `simulate device`, `simulate imu` and `twin`, and the
Python models saved with `save_hdf5`/`to_csv`. Each file has `output` (a triad: one per axis),
`truth/true_rate`, the components the metadata names and nothing else under `truth/`, and the
components sum to `output - true_rate` to float64 rounding; `allan` and `twin` read it without flags."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path

import h5py
import numpy as np
import pytest

from gyrobench.io.recording import (
    Channel,
    Recording,
    closure,
    list_hdf5,
    load_csv,
    load_hdf5,
    save_hdf5,
    schema_problems,
    to_csv,
)
from gyrobench.scenarios.cli.main import main

EPS = np.finfo(float).eps

pytestmark = pytest.mark.usefixtures("user_files")


def _cli(*argv) -> int:
    try:
        return main([str(a) for a in argv])
    except SystemExit as exc:  # argparse
        return int(exc.code or 0)


def _load(path: Path) -> list[Recording]:
    if path.suffix == ".csv":
        return [load_csv(path)]
    return [load_hdf5(path, name) for name in list_hdf5(path)]


def _outputs(rec: Recording) -> list[str]:
    comps = rec.metadata["error_components"]
    return list(comps) if isinstance(comps, Mapping) else ["output"]


def _assert_closes(rec: Recording, cumulative: bool) -> None:
    """Each output minus its true value equals the sum of its components to rounding.

    The bound: m + 2 terms each rounded at eps relative to the largest magnitude in play, with a
    factor 16 for the models' intermediate operations; a counting output (an RLG's pulses,
    differenced from a cumulative angle) rounds at eps times that angle, at most n max|output|/fs
    times fs."""
    for out in _outputs(rec):
        resid, scale = closure(rec, out)
        comps = rec.metadata["error_components"]
        m = len(comps[out] if isinstance(comps, Mapping) else comps)
        if cumulative:
            scale = max(scale, rec.n_samples * float(np.max(np.abs(rec[out]))) * 2)
        tol = 16 * (m + 2) * EPS * scale
        assert resid <= tol, (rec.name, out, resid, tol)


@dataclass(frozen=True)
class Writer:
    """How to write a file (into a folder) and whether its output counts pulses."""

    name: str
    write: Callable[[Path], list[Path]]
    cumulative: bool = False


def _noise(suffix: str, *extra: str) -> Callable[[Path], list[Path]]:
    def write(tmp: Path) -> list[Path]:
        out = tmp / f"noise{suffix}"
        assert _cli("simulate", "noise", "--Q", "0.5", "--N", "0.01", "--B", "0.05", "--fs", "100",
                    "--duration", "60s", "-o", out, "-q", *extra) == 0
        return [out]

    return write


def _device(suffix: str) -> Callable[[Path], list[Path]]:
    def write(tmp: Path) -> list[Path]:
        prof = tmp / "profile.toml"
        prof.write_text("duration_s = 20.0\nrate_dps = [[0.0, 0.0], [10.0, 0.0], [11.0, 30.0], [20.0, 30.0]]\n"
                        "temperature_c = [[0.0, 20.0], [20.0, 30.0]]\nspecific_force_g = 1.0\n")
        out = tmp / f"device{suffix}"
        assert _cli("simulate", "device", "stim300", "--profile", prof, "--fs", "100", "-o", out) == 0
        return [out]

    return write


def _imu(*extra: str) -> Callable[[Path], list[Path]]:
    def write(tmp: Path) -> list[Path]:
        traj = tmp / "static.toml"
        traj.write_text("[site]\nlatitude_deg = 30.0\n\n[[motion]]\nduration_s = 5.0\n")
        out = tmp / "imu.h5"
        assert _cli("simulate", "imu", "stim300", "--trajectory", traj, "--fs", "100", "-o", out, *extra) == 0
        return [out]

    return write


def _twin(tmp: Path) -> list[Path]:
    (real,) = _noise(".csv")(tmp)
    out = tmp / "twin.h5"
    assert _cli("twin", real, "-o", out, "--seed", "3") in (0, 1)  # match or not, the file is written
    return [out]


def _static_noise(tmp: Path) -> list[Path]:
    cfg = tmp / "short.toml"
    cfg.write_text("[fog]\nduration_h = 0.01\nfs_hz = 50.0\n\n[mems]\nduration_h = 0.01\nfs_hz = 50.0\n")
    assert _cli("simulate", "static_noise", "--config", cfg, "--out", tmp / "out", "-q") == 0
    return sorted((tmp / "out").rglob("*.h5"))


def _model(name: str, draw, fs: float, duration: float, suffix: str = ".h5") -> Callable[[Path], list[Path]]:
    def write(tmp: Path) -> list[Path]:
        from gyrobench.sim.environment import PiecewiseLinear
        from gyrobench.sim.sensor import Environment

        rng = np.random.default_rng(20261202)
        env = Environment(duration, true_rate=PiecewiseLinear(np.array([0.0, duration]), np.array([0.0, 0.02])),
                          temperature=PiecewiseLinear(np.array([0.0, duration]), np.array([293.15, 298.15])),
                          specific_force=9.80665)
        rec = draw(rng).simulate(env, fs=fs, rng=rng)
        out = tmp / f"{name}{suffix}"
        (to_csv if suffix == ".csv" else save_hdf5)(out, rec)
        return [out]

    return write


def _models() -> list[Writer]:
    from gyrobench.sim import mems_population, parts
    from gyrobench.sim.fog2d import FOG2DSpec
    from gyrobench.sim.fog_loop import ClosedLoopFOG
    from gyrobench.sim.rlg import RLGSpec
    from gyrobench.sim.rlg_cavity import CavityRLGSpec

    return [
        Writer("py:fog_loop", _model("fog_loop", lambda rng: ClosedLoopFOG(), 400.0, 1.0)),
        Writer("py:fog2d", _model("fog2d", lambda rng: FOG2DSpec().realize(rng=rng), 10.0, 20.0)),
        Writer("py:mems_resonator", _model("mems", lambda rng: mems_population.MemsResonatorSpec().realize(rng=rng),
                                           200.0, 0.5)),
        Writer("py:mems_resonator_csv", _model("mems", lambda rng: mems_population.MemsResonatorSpec().realize(
            rng=rng), 200.0, 0.5, ".csv")),
        Writer("py:rlg", _model("rlg", lambda rng: RLGSpec().realize(rng=rng), 10.0, 20.0), cumulative=True),
        Writer("py:rlg_cavity", _model("rlg_cavity", lambda rng: CavityRLGSpec().realize(rng=rng), 10.0, 20.0),
               cumulative=True),
        Writer("py:part", _model("part", lambda rng: parts.get("adxrs646").realize(rng=rng), 100.0, 2.0)),
    ]


WRITERS = [
    Writer("simulate noise h5", _noise(".h5")),
    Writer("simulate noise csv", _noise(".csv")),
    Writer("simulate noise --no-terms h5", _noise(".h5", "--no-terms")),
    Writer("simulate noise --no-terms csv", _noise(".csv", "--no-terms")),
    Writer("simulate static_noise", _static_noise),
    Writer("simulate device h5", _device(".h5")),
    Writer("simulate device csv", _device(".csv")),
    Writer("simulate imu", _imu()),
    Writer("simulate imu increments", _imu("--increments")),
    Writer("twin", _twin),
    *_models(),
]
IDS = [w.name for w in WRITERS]


@pytest.mark.parametrize("writer", WRITERS, ids=IDS)
def test_every_writers_file_has_the_schema_and_closes(tmp_path, writer):
    files = writer.write(tmp_path)
    assert files
    for path in files:
        for rec in _load(path):
            assert schema_problems(rec) == [], (path, schema_problems(rec))
            _assert_closes(rec, writer.cumulative)
            for out in _outputs(rec):  # the components explain the error: a record with an error has some
                if np.any(rec[out] != rec[f"truth/{out}.true" if out != "output" else "truth/true_rate"]):
                    assert rec.metadata["error_components"], (path, out)


@pytest.mark.parametrize("suffix", [".h5", ".csv"])
def test_simulate_noise_without_terms_keeps_the_output_and_one_closing_component(tmp_path, suffix):
    """--no-terms stores the same output bits (same seed) and one component, their sum."""
    (tmp_path / "terms").mkdir()
    (tmp_path / "sum").mkdir()
    (a,) = _load(_noise(suffix)(tmp_path / "terms")[0])
    (b,) = _load(_noise(suffix, "--no-terms")(tmp_path / "sum")[0])
    assert np.array_equal(a["output"], b["output"])
    assert b.metadata["error_components"] == ["noise"] and set(b.truth) == {"true_rate", "noise"}
    assert b.metadata["terms_drawn"] == a.metadata["error_components"]
    assert np.array_equal(b["truth/noise"], sum(a.truth[k].data for k in a.metadata["error_components"]))


def test_no_terms_applies_to_simulate_noise_only(tmp_path, capsys):
    code = _cli("simulate", "device", "stim300", "--duration", "20s", "--no-terms", "-o", tmp_path / "d.h5")
    err = capsys.readouterr().err.strip()
    assert code == 2 and "--no-terms" in err and "\n" not in err, err
    assert not (tmp_path / "d.h5").exists()


@pytest.mark.slow
@pytest.mark.parametrize("writer", WRITERS, ids=IDS)
def test_allan_and_twin_read_every_writers_file_without_flags(tmp_path, capsys, writer):
    for path in writer.write(tmp_path):
        capsys.readouterr()
        code = _cli("allan", path)
        out, err = capsys.readouterr()
        assert code in (0, 5), err  # 5: a channel with motion (a rate step) is not stationary
        assert any(k in out for k in ("output", "gyro_x", "dtheta_x")), out
        code = _cli("twin", path, "-o", tmp_path / f"twin_of_{path.stem}.h5", "--accept-nonstationary")
        _, err = capsys.readouterr()
        assert code in (0, 1), err  # the twin matches or not; the file was read


def test_a_version_1_file_reads_rate_as_output(tmp_path):
    """A file of the first layout (channel `rate`, the FOG's `truth/rate`) reads with the new names."""
    n = 64
    rng = np.random.default_rng(5)
    rate, noise = np.full(n, 0.01), rng.standard_normal(n) * 1e-4
    path = tmp_path / "v1.h5"
    with h5py.File(path, "w") as h5:
        h5.attrs["format"] = "gyrobench-recording"
        h5.attrs["format_version"] = 1
        g = h5.create_group("recordings/old")
        g.attrs.update({"fs": 10.0, "t0": 0.0, "n_samples": n,
                        "metadata": '{"error_components": ["optical_noise"]}'})
        for sub, name, data, unit in (("channels", "rate", rate + noise, "rad/s"), ("truth", "rate", rate, "rad/s"),
                                      ("truth", "optical_noise", noise, "rad/s"),
                                      ("truth", "coil_temperature", np.full(n, 300.0), "K")):
            ds = g.require_group(sub).create_dataset(name, data=data)
            ds.attrs["unit"] = unit
    rec = load_hdf5(path)
    assert list(rec.channels) == ["output"]
    np.testing.assert_array_equal(rec["output"], rate + noise)
    np.testing.assert_array_equal(rec["truth/true_rate"], rate)
    np.testing.assert_array_equal(rec["inputs/coil_temperature"], np.full(n, 300.0))
    assert schema_problems(rec) == []


def test_a_version_2_file_keeps_a_channel_named_rate(tmp_path):
    rec = Recording(fs=1.0, channels={"rate": Channel(np.zeros(4), "rad/s")})
    save_hdf5(tmp_path / "r.h5", rec)
    assert list(load_hdf5(tmp_path / "r.h5").channels) == ["rate"]


def test_truth_holds_only_the_true_rate_and_the_named_components():
    n = 8
    ch = {k: Channel(np.zeros(n), u) for k, u in (("true_rate", "rad/s"), ("bias", "rad/s"), ("bias_part", "rad/s"),
                                                  ("temperature", "K"))}
    rec = Recording(fs=1.0, channels={"output": Channel(np.zeros(n), "rad/s")}, truth=ch,
                    metadata={"error_components": ["bias"]})
    assert sorted(rec.truth) == ["bias", "true_rate"]
    assert list(rec.detail) == ["bias_part"] and list(rec.inputs) == ["temperature"]
    bad = Recording(fs=1.0, channels={"output": Channel(np.zeros(n), "rad/s")}, truth={"true_rate": ch["true_rate"]},
                    metadata={"error_components": ["bias"]})
    assert schema_problems(bad) == ["truth lacks ['bias']"]


@pytest.mark.parametrize("compression", ["gzip", "lzf"])
def test_compression_round_trips_and_shrinks_a_constant_channel(tmp_path, compression):
    n = 1 << 14
    rec = Recording(fs=100.0, channels={"output": Channel(np.random.default_rng(1).standard_normal(n), "rad/s")},
                    truth={"true_rate": Channel(np.zeros(n), "rad/s")})
    plain, packed = tmp_path / "plain.h5", tmp_path / "packed.h5"
    save_hdf5(plain, rec)
    save_hdf5(packed, rec, compression=compression)
    back = load_hdf5(packed)
    np.testing.assert_array_equal(back["output"], rec["output"])
    np.testing.assert_array_equal(back["truth/true_rate"], rec["truth/true_rate"])
    with h5py.File(packed) as h5:
        ds = h5["recordings/recording/truth/true_rate"]
        assert ds.compression == compression
        assert ds.id.get_storage_size() < ds.nbytes / 20  # zeros: far below their 8 bytes each
    assert packed.stat().st_size < plain.stat().st_size


def test_compression_refuses_an_unknown_filter(tmp_path):
    rec = Recording(fs=1.0, channels={"output": Channel(np.zeros(4), "rad/s")})
    with pytest.raises(ValueError, match=r"compression must be one of \[None, 'gzip', 'lzf'\]; got 'zstd'"):
        save_hdf5(tmp_path / "x.h5", rec, compression="zstd")
    assert not (tmp_path / "x.h5").exists()


def test_to_dataframe_without_pandas_fails_in_one_line(monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "pandas", None)  # import pandas then raises ImportError
    rec = Recording(fs=1.0, channels={"output": Channel(np.zeros(4), "rad/s")})
    with pytest.raises(ImportError, match=r"^Recording.to_dataframe needs pandas, .*: pip install pandas$"):
        rec.to_dataframe()


def test_to_dataframe_has_a_column_per_dataset():
    pd = pytest.importorskip("pandas")
    n = 5
    rec = Recording(fs=2.0, t0=0.25, channels={"output": Channel(np.arange(n, dtype=float), "rad/s")},
                    truth={"true_rate": Channel(np.zeros(n), "rad/s"), "bias": Channel(np.arange(n, dtype=float),
                                                                                        "rad/s")},
                    inputs={"temperature": Channel(np.full(n, 300.0), "K")}, metadata={"error_components": ["bias"]})
    df = rec.to_dataframe()
    assert isinstance(df, pd.DataFrame)
    assert list(df.columns) == ["output", "truth/true_rate", "truth/bias", "inputs/temperature"]
    np.testing.assert_array_equal(df.index.to_numpy(), 0.25 + np.arange(n) / 2.0)
    assert df.attrs["units"]["inputs/temperature"] == "K"
    assert math.isclose(df.attrs["fs"], 2.0)
