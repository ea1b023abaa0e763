"""A gyro recording: sampled channels with units, the truth behind them, metadata.

A :class:`Recording` is what a test logs (sensor output, internal temperatures,
table rate) plus what only a simulator knows: every error component separately
(``truth``). Channels are stored in SI; the unit string travels with the data.

File forms
----------
HDF5 (h5py): one group per recording under ``/recordings/<name>``; datasets
``channels/<ch>`` and ``truth/<ch>``, each with attributes ``unit`` and
``description``; group attributes ``fs`` [Hz], ``t0`` [s], ``n_samples`` and
``metadata`` (JSON text). The root carries ``format = "gyrobench-recording"``
and ``format_version``. Plain float64 datasets and string attributes, so
MATLAB's ``h5read(file, '/recordings/x/channels/rate')`` and ``h5readatt``
read them directly.

CSV: a header line of ``name [unit]`` columns, first column ``time [s]``.

Writes are atomic: data go to a temporary file in the destination folder,
which is renamed over the target only when complete (``os.replace``).
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import tempfile
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "Channel",
    "Recording",
    "RecordingFormatError",
    "atomic_path",
    "save_hdf5",
    "load_hdf5",
    "list_hdf5",
    "HDF5StreamWriter",
    "to_csv",
]

FORMAT = "gyrobench-recording"
FORMAT_VERSION = 1


class RecordingFormatError(ValueError):
    """A file is not a complete gyrobench recording."""


def package_version() -> str:
    try:
        from importlib.metadata import version

        return version("gyrobench")
    except Exception:  # not installed (running from a source tree)
        return "0+unknown"


@dataclass(frozen=True, slots=True)
class Channel:
    """One sampled signal.

    Parameters
    ----------
    data : ndarray
        Samples, 1-D float64, in SI.
    unit : str
        SI unit of ``data`` (``"rad/s"``, ``"K"``, ``"m/s^2"``, ...).
    description : str
        Free text.
    """

    data: NDArray[np.float64]
    unit: str
    description: str = ""

    def __post_init__(self) -> None:
        arr = np.asarray(self.data, dtype=float)
        if arr.ndim != 1:
            raise ValueError(f"Channel.data must be 1-D; got shape {arr.shape}")
        object.__setattr__(self, "data", arr)
        if not isinstance(self.unit, str):
            raise TypeError(f"Channel.unit must be a str; got {self.unit!r}")


def _as_channels(name: str, chans: Mapping[str, Channel]) -> dict[str, Channel]:
    if not isinstance(chans, Mapping):
        raise TypeError(f"Recording.{name} must be a mapping of name -> Channel; got {type(chans).__name__}")
    out = {}
    for k, v in chans.items():
        if not isinstance(v, Channel):
            raise TypeError(f"Recording.{name}[{k!r}] must be a Channel; got {type(v).__name__}")
        out[str(k)] = v
    return out


@dataclass(frozen=True, slots=True)
class Recording:
    """Sampled output of one run of one gyro, with its truth.

    Parameters
    ----------
    fs : float
        Sample rate [Hz], > 0.
    channels : mapping str -> Channel
        What a real test logs (sensor output, temperatures, table rate).
    truth : mapping str -> Channel
        What only the simulator knows: the true rate and each error component.
    t0 : float
        Time of the first sample [s].
    metadata : mapping
        JSON-serialisable: spec, environment config, seed, package version.
    name : str
        Identifier, used as the HDF5 group name.
    """

    fs: float
    channels: Mapping[str, Channel]
    truth: Mapping[str, Channel] = field(default_factory=dict)
    t0: float = 0.0
    metadata: Mapping[str, Any] = field(default_factory=dict)
    name: str = "recording"

    def __post_init__(self) -> None:
        if not (isinstance(self.fs, (int, float)) and math.isfinite(self.fs) and self.fs > 0):
            raise ValueError(f"Recording.fs must be a finite number > 0 Hz; got {self.fs!r}")
        chans = _as_channels("channels", self.channels)
        truth = _as_channels("truth", self.truth)
        if not chans:
            raise ValueError("Recording.channels must hold at least one channel; got none")
        lengths = {k: len(c.data) for k, c in {**chans, **{f"truth/{k}": v for k, v in truth.items()}}.items()}
        if len(set(lengths.values())) > 1:
            raise ValueError(f"Recording channels must all have the same length; got {lengths}")
        if not self.name or "/" in self.name:
            raise ValueError(f"Recording.name must be non-empty without '/'; got {self.name!r}")
        object.__setattr__(self, "channels", chans)
        object.__setattr__(self, "truth", truth)
        object.__setattr__(self, "fs", float(self.fs))
        json.dumps(dict(self.metadata), default=_json_default)  # fail early if not serialisable

    @property
    def n_samples(self) -> int:
        return len(next(iter(self.channels.values())).data)

    @property
    def time(self) -> NDArray[np.float64]:
        """Sample times [s]."""
        return self.t0 + np.arange(self.n_samples) / self.fs

    def __getitem__(self, key: str) -> NDArray[np.float64]:
        if key in self.channels:
            return self.channels[key].data
        if key.startswith("truth/") and key[6:] in self.truth:
            return self.truth[key[6:]].data
        raise KeyError(
            f"recording {self.name!r} has no channel {key!r}; channels: {sorted(self.channels)}, "
            f"truth: {sorted('truth/' + k for k in self.truth)}"
        )


def _json_default(o: Any) -> Any:
    import dataclasses

    if dataclasses.is_dataclass(o) and not isinstance(o, type):
        return {f.name: getattr(o, f.name) for f in dataclasses.fields(o)}
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, Path):
        return str(o)
    if isinstance(o, float) and not math.isfinite(o):
        return repr(o)
    raise TypeError(f"metadata value {o!r} of type {type(o).__name__} is not JSON-serialisable")


def metadata_json(metadata: Mapping[str, Any]) -> str:
    """Serialise metadata (dataclasses, numpy scalars, paths allowed) to JSON text."""
    return json.dumps(dict(metadata), default=_json_default, sort_keys=True)


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; rename it onto ``path`` only on success.

    An exception (or a kill) inside the block leaves ``path`` untouched and the
    temporary file removed (or, after a kill, a ``.tmp`` file that never looks
    like the result).
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        yield tmp_path
        os.replace(tmp_path, path)
    finally:
        if tmp_path.exists():
            tmp_path.unlink()


def _write_group(h5, rec: Recording) -> None:
    grp = h5.require_group("recordings").create_group(rec.name)
    grp.attrs["fs"] = rec.fs
    grp.attrs["t0"] = rec.t0
    grp.attrs["n_samples"] = rec.n_samples
    grp.attrs["metadata"] = metadata_json(rec.metadata)
    for sub, chans in (("channels", rec.channels), ("truth", rec.truth)):
        g = grp.create_group(sub)
        for k, c in chans.items():
            ds = g.create_dataset(k, data=c.data, chunks=True if len(c.data) > 1 << 16 else None)
            ds.attrs["unit"] = c.unit
            ds.attrs["description"] = c.description


def _mark_root(h5) -> None:
    h5.attrs["format"] = FORMAT
    h5.attrs["format_version"] = FORMAT_VERSION
    h5.attrs["gyrobench_version"] = package_version()


def save_hdf5(path: str | os.PathLike, recordings: Recording | list[Recording]) -> Path:
    """Write one or several recordings to an HDF5 file, atomically.

    Raises
    ------
    ValueError
        If two recordings share a name.
    """
    import h5py

    recs = [recordings] if isinstance(recordings, Recording) else list(recordings)
    names = [r.name for r in recs]
    if len(set(names)) != len(names):
        raise ValueError(f"recording names must be unique within a file; got {names}")
    with atomic_path(path) as tmp:
        with h5py.File(tmp, "w") as h5:
            _mark_root(h5)
            for r in recs:
                _write_group(h5, r)
    return Path(path)


def _open_checked(path: str | os.PathLike):
    import h5py

    p = Path(path)
    if not p.is_file():
        raise FileNotFoundError(f"recording file not found: {str(p)!r}")
    try:
        h5 = h5py.File(p, "r")
    except OSError as exc:
        raise RecordingFormatError(f"{str(p)!r} is not a readable HDF5 file ({exc})") from None
    fmt = h5.attrs.get("format")
    if isinstance(fmt, bytes):
        fmt = fmt.decode()
    if fmt != FORMAT or "recordings" not in h5:
        h5.close()
        raise RecordingFormatError(
            f"{str(p)!r} is an HDF5 file but not a gyrobench recording (root attribute format={fmt!r})"
        )
    return h5


def list_hdf5(path: str | os.PathLike) -> list[str]:
    """Names of the recordings in a gyrobench HDF5 file."""
    with _open_checked(path) as h5:
        return list(h5["recordings"].keys())


def load_hdf5(path: str | os.PathLike, name: str | None = None) -> Recording:
    """Read one recording (``name``, or the only one) and check it is complete.

    Raises
    ------
    RecordingFormatError
        For a foreign or truncated file, or channel lengths that disagree with
        the stored ``n_samples``.
    KeyError
        If ``name`` is not in the file.
    """
    with _open_checked(path) as h5:
        recs = h5["recordings"]
        if name is None:
            if len(recs) != 1:
                raise ValueError(f"{str(path)!r} holds {len(recs)} recordings {list(recs)}; name one")
            name = next(iter(recs))
        if name not in recs:
            raise KeyError(f"{str(path)!r} has no recording {name!r}; it has {list(recs)}")
        grp = recs[name]
        try:
            fs = float(grp.attrs["fs"])
            t0 = float(grp.attrs["t0"])
            n = int(grp.attrs["n_samples"])
            meta = json.loads(grp.attrs["metadata"])
            out: dict[str, dict[str, Channel]] = {}
            for sub in ("channels", "truth"):
                out[sub] = {}
                for k, ds in grp[sub].items():
                    data = ds[()]
                    if data.shape != (n,):
                        raise RecordingFormatError(
                            f"{str(path)!r}: {name}/{sub}/{k} has shape {data.shape}, expected ({n},): truncated file?"
                        )
                    out[sub][k] = Channel(data, str(ds.attrs["unit"]), str(ds.attrs.get("description", "")))
        except (KeyError, OSError, json.JSONDecodeError) as exc:
            raise RecordingFormatError(f"{str(path)!r}: recording {name!r} is incomplete ({exc})") from None
        return Recording(fs=fs, channels=out["channels"], truth=out["truth"], t0=t0, metadata=meta, name=name)


class HDF5StreamWriter:
    """Write a recording chunk by chunk, so a long record never sits in memory.

    Use as a context manager; the file appears at ``path`` only after a clean
    exit (atomic rename). Channels are declared up front.

    Examples
    --------
    >>> import numpy as np, tempfile, os
    >>> p = os.path.join(tempfile.mkdtemp(), "x.h5")
    >>> with HDF5StreamWriter(p, name="r", fs=10.0, channels={"rate": "rad/s"}) as w:
    ...     w.append(rate=np.zeros(5)); w.append(rate=np.ones(5))
    >>> load_hdf5(p).n_samples
    10
    """

    def __init__(
        self,
        path: str | os.PathLike,
        *,
        name: str,
        fs: float,
        channels: Mapping[str, str],
        truth: Mapping[str, str] | None = None,
        t0: float = 0.0,
        metadata: Mapping[str, Any] | None = None,
        chunk: int = 1 << 18,
    ) -> None:
        if not (math.isfinite(fs) and fs > 0):
            raise ValueError(f"fs must be a finite number > 0 Hz; got {fs!r}")
        self.path = Path(path)
        self.name, self.fs, self.t0 = name, float(fs), float(t0)
        self._units = {"channels": dict(channels), "truth": dict(truth or {})}
        self._meta = dict(metadata or {})
        self._chunk = chunk
        self._n = 0
        self._ctx = None
        self._h5 = None

    def __enter__(self) -> HDF5StreamWriter:
        import h5py

        self._ctx = atomic_path(self.path)
        tmp = self._ctx.__enter__()
        self._h5 = h5py.File(tmp, "w")
        _mark_root(self._h5)
        grp = self._h5.require_group("recordings").create_group(self.name)
        grp.attrs["fs"] = self.fs
        grp.attrs["t0"] = self.t0
        grp.attrs["metadata"] = metadata_json(self._meta)
        self._ds = {}
        for sub, units_ in self._units.items():
            g = grp.create_group(sub)
            for k, u in units_.items():
                ds = g.create_dataset(k, shape=(0,), maxshape=(None,), dtype="f8", chunks=(self._chunk,))
                ds.attrs["unit"] = u
                ds.attrs["description"] = ""
                self._ds[(sub, k)] = ds
        self._grp = grp
        return self

    def append(self, *, truth: Mapping[str, NDArray] | None = None, **channels: NDArray) -> None:
        """Append the next samples of every declared channel (and truth component)."""
        given = {("channels", k): v for k, v in channels.items()}
        given.update({("truth", k): v for k, v in (truth or {}).items()})
        if set(given) != set(self._ds):
            raise ValueError(
                f"append must give every declared channel {sorted(k for _, k in self._ds)}; got {sorted(k for _, k in given)}"
            )
        lengths = {len(v) for v in given.values()}
        if len(lengths) != 1:
            raise ValueError(f"append: all channels must have the same length; got {lengths}")
        m = lengths.pop()
        for key, v in given.items():
            ds = self._ds[key]
            ds.resize((self._n + m,))
            ds[self._n :] = v
        self._n += m

    def __exit__(self, exc_type, exc, tb) -> None:
        try:
            if exc_type is None:
                self._grp.attrs["n_samples"] = self._n
            self._h5.close()
        finally:
            self._ctx.__exit__(exc_type, exc, tb)


def to_csv(path: str | os.PathLike, rec: Recording, *, include_truth: bool = True) -> Path:
    """Export a recording to CSV (``time [s]`` then ``name [unit]`` columns), atomically."""
    cols = [("time", "s", rec.time)]
    cols += [(k, c.unit, c.data) for k, c in rec.channels.items()]
    if include_truth:
        cols += [(f"truth/{k}", c.unit, c.data) for k, c in rec.truth.items()]
    header = ",".join(f"{k} [{u}]" for k, u, _ in cols)
    data = np.column_stack([c for _, _, c in cols])
    with atomic_path(path) as tmp:
        np.savetxt(tmp, data, delimiter=",", header=header, comments="", fmt="%.17g")
    return Path(path)
