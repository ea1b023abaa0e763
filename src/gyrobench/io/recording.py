"""A gyro recording: sampled channels with units, the truth behind them, metadata.

A :class:`Recording` is what a test logs (sensor output, internal temperatures,
table rate) plus what only a simulator knows: every error component separately
(``truth``). Channels are stored in SI; the unit string travels with the data.

File forms
----------
HDF5 (h5py): one group per recording under ``/recordings/<name>``, holding four groups of
datasets (the schema, :data:`GROUPS`; written down in docs/recording.md):

- ``channels/``: what a test logs; ``channels/output`` is the gyro's output [rad/s];
- ``truth/``: ``truth/true_rate`` [rad/s] and the error components named in the metadata's
  ``error_components``, nothing else; they sum to ``output - true_rate`` to rounding;
- ``inputs/``: what drives the errors that is not a rate: the environment (chamber and coil
  temperatures, specific force) and the model's physical state (path length, mode index);
- ``detail/``: other rates the model computed: sub-terms of a component, sums of components.

Every dataset has attributes ``unit`` and ``description``; the recording group has the
attributes ``fs`` [Hz], ``t0`` [s], ``n_samples`` and ``metadata`` (JSON text). The root
carries ``format = "gyrobench-recording"`` and ``format_version``. Plain float64 datasets
(optionally gzip- or lzf-compressed) and string attributes, so MATLAB's
``h5read(file, '/recordings/x/channels/output')`` and ``h5readatt`` read them directly.
A file of format version 1 (channel ``rate``, truth ``rate``) is read with ``rate`` as
``output`` and ``truth/rate`` as ``truth/true_rate``.

CSV: a comment line naming gyrobench (:func:`gyrobench.base.safety.comment_marker`, the marker
that lets a later run replace the file), then a header line of ``name [unit]`` columns, first
column ``time [s]``.

Writes are atomic: data go to a temporary file in the destination folder,
which is renamed over the target only when complete (``os.replace``). The
file gets the mode an ordinary ``open(path, "w")`` would give (``0o666`` less
the umask). A failed write (disk full, file-size limit, I/O error) raises
:class:`AtomicWriteError`, an ``OSError`` whose message names the target path,
never the temporary file; the temporary file is removed and any previous file
at the target is left as it was.
"""

from __future__ import annotations

import contextlib
import errno
import json
import math
import os
import re
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from gyrobench.base.atomic import _fmt_bytes, atomic_path, ensure_free_space
from gyrobench.base.ranges import Constraint, FieldRange, as_array, shown, validate
from gyrobench.io.write_rules import RecordingClosureError, check_closes, check_replaceable

__all__ = [
    "Channel",
    "Recording",
    "RecordingFormatError",
    "check_magnitude",
    "check_finite_samples",
    "save_hdf5",
    "load_hdf5",
    "list_hdf5",
    "HDF5StreamWriter",
    "to_csv",
    "load_csv",
    "GROUPS",
    "OUTPUT",
    "closure",
    "schema_problems",
    "RecordingClosureError",
]

FORMAT = "gyrobench-recording"
FORMAT_VERSION = 2
#: the groups of datasets of a recording, in file order
GROUPS = ("channels", "truth", "inputs", "detail")
#: the output channel of a single-axis recording
OUTPUT = "output"
#: the true rate in ``truth/`` of a single-axis recording
TRUE_RATE = "true_rate"
#: compressions :func:`save_hdf5` and :class:`HDF5StreamWriter` apply (h5py's filters; None: none)
COMPRESSIONS = (None, "gzip", "lzf")


class RecordingFormatError(ValueError):
    """A file is not a complete gyrobench recording."""


#: |sample| above ``MAX_MAGNITUDE / sqrt(n)`` is refused by :func:`check_magnitude`
MAX_MAGNITUDE = 1e100


def check_magnitude(
    values: NDArray[np.float64], what: str, *, n_total: int | None = None, hint: str = "check its unit and scale"
) -> None:
    """Refuse samples too large for the sums of squares an analysis forms.

    An Allan variance sums ``n`` squared differences of block averages; with every
    ``|y| <= M`` each term is at most ``4 M**2``, so the sum stays far below the float64
    maximum (1.8e308) when ``M <= 1e100 / sqrt(n)`` (a margin of 1e100). No gyro's rate,
    in any unit, comes near it: larger samples are a wrong unit or corrupt data, and
    would otherwise end in overflow warnings and NaN. Non-finite samples are refused too.

    ``n_total`` is the length of the whole record when ``values`` is one chunk of it.

    Parameters
    ----------
    values : ndarray
        The samples (or one chunk of them).
    what : str
        What they are, for the message (a file and column).
    n_total : int, optional
        Length of the whole record when ``values`` is a chunk.
    hint : str
        What to do, for the message.

    Raises
    ------
    ValueError
        Naming ``what``, the first offending sample and the limit.
    """
    v = np.asarray(values)
    n = max(int(v.size if n_total is None else n_total), 1)
    limit = MAX_MAGNITUDE / math.sqrt(n)
    with np.errstate(invalid="ignore"):
        bad = np.flatnonzero(~(np.abs(v) <= limit))
    if bad.size:
        i = int(bad[0])
        raise ValueError(
            f"{what} has {float(v.flat[i]):.6g} at sample {i} ({bad.size} sample"
            f"{'s' if bad.size > 1 else ''} outside +-{limit:.3g}, the largest magnitude an "
            f"analysis of {n} samples can square without overflow): {hint}"
        )


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

    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "data is 1-D",
            lambda c: isinstance(c.data, np.ndarray) and c.data.ndim == 1,
            lambda c: f"data must be 1-D; got shape {np.shape(c.data)}"
            if isinstance(c.data, np.ndarray) else f"data must be 1-D; got {shown(c.data)}",
        ),
        Constraint(
            "unit is a str",
            lambda c: isinstance(c.unit, str),
            lambda c: f"unit must be a str; got {c.unit!r}",
            TypeError,
        ),
    )

    def __post_init__(self) -> None:
        object.__setattr__(self, "data", as_array(self.data))
        validate(self)  # the declared constraints above


def _as_channels(chans: object) -> object:
    """A mapping as a dict with string keys (never raising: anything else is returned as given)."""
    return {str(k): v for k, v in chans.items()} if isinstance(chans, Mapping) else chans


def _not_channels(rec: Recording, name: str) -> str | None:
    """Why group ``name`` of ``rec`` is not a mapping of name -> Channel, or None when it is."""
    chans = getattr(rec, name)
    if not isinstance(chans, Mapping):
        return f"{name} must be a mapping of name -> Channel; got {type(chans).__name__}"
    bad = next((k for k, v in chans.items() if not isinstance(v, Channel)), None)
    return None if bad is None else f"{name}[{bad!r}] must be a Channel; got {type(chans[bad]).__name__}"


def _channel_group(name: str) -> Constraint:
    """The declared constraint that group ``name`` is a mapping of name -> Channel (a TypeError)."""
    return Constraint(
        f"{name} is a mapping of name -> Channel",
        lambda c: _not_channels(c, name) is None,
        lambda c: str(_not_channels(c, name)),
        TypeError,
    )


def _lengths(rec: Recording) -> dict[str, int]:
    """Each channel's length, named ``group/name`` (``name`` for ``channels``)."""
    return {
        f"{g}/{k}" if g != "channels" else k: len(c.data)
        for g in GROUPS for k, c in getattr(rec, g).items()
    }


def _collision(rec: Recording) -> str | None:
    """A truth channel that is not an error component and whose target group holds that name, or None."""
    keep = truth_names(rec.metadata)
    if keep is None:
        return None
    for k, c in rec.truth.items():
        target = rec.detail if c.unit in ("rad/s", "rad") else rec.inputs
        if k not in keep and k in target:
            return k
    return None


def _json_error(metadata: Mapping[str, Any]) -> str | None:
    """Why ``metadata`` does not serialise to JSON, or None when it does."""
    try:
        json.dumps(dict(metadata), default=_json_default)
    except (TypeError, ValueError) as exc:
        return " ".join(str(exc).split())
    return None


def truth_names(metadata: Mapping[str, Any]) -> set[str] | None:
    """The names ``truth/`` holds by the metadata's ``error_components``, or None when it names none.

    A list names the components of ``output``; the true rate is ``true_rate``. A mapping (a
    triad) names each output channel's components; channel ``c``'s true value is ``c.true``.

    Parameters
    ----------
    metadata : mapping
        A recording's metadata.

    Returns
    -------
    set of str or None
        The truth channels' names.
    """
    comps = metadata.get("error_components")
    if isinstance(comps, (list, tuple)):
        return {TRUE_RATE, *map(str, comps)}
    if isinstance(comps, Mapping):
        return {n for ch, names in comps.items() for n in (f"{ch}.true", *map(str, names))}
    return None


def _sorted_groups(
    truth: dict[str, Channel], inputs: dict[str, Channel], detail: dict[str, Channel], metadata: Mapping[str, Any]
) -> tuple[dict[str, Channel], dict[str, Channel], dict[str, Channel]]:
    """Truth reduced to the true rate and the named components; the rest to inputs (not a rate) or detail."""
    keep = truth_names(metadata)
    if keep is None:
        return truth, inputs, detail
    truth_out = {}
    for k, c in truth.items():
        if k in keep:
            truth_out[k] = c
        else:  # to its group: Recording's constraints refused a name that group holds already
            (detail if c.unit in ("rad/s", "rad") else inputs)[k] = c
    return truth_out, inputs, detail


@dataclass(frozen=True, slots=True)
class Recording:
    """Sampled output of one run of one gyro, with its truth (the schema: docs/recording.md).

    Parameters
    ----------
    fs : float
        Sample rate [Hz], > 0.
    channels : mapping str -> Channel
        What a real test logs: ``output`` (the gyro's output [rad/s]), logged temperatures,
        the table rate.
    truth : mapping str -> Channel
        What only the simulator knows: ``true_rate`` and each error component. When the
        metadata names the components (``error_components``), every other channel given here
        is moved to ``inputs`` (a unit other than rad/s) or ``detail`` (rad/s), so ``truth``
        holds exactly the true rate and the components.
    t0 : float
        Time of the first sample [s].
    metadata : mapping
        JSON-serialisable: spec, environment config, seed, package version, and
        ``error_components`` (the truth channels summing to ``output - true_rate``).
    name : str
        Identifier, used as the HDF5 group name.
    inputs : mapping str -> Channel
        What drives the errors that is not a rate: the environment (temperatures, specific
        force) and the model's physical state (lengths, mode index).
    detail : mapping str -> Channel
        Other rates the model computed: sub-terms of a component, sums of components.
    """

    fs: float
    channels: Mapping[str, Channel]
    truth: Mapping[str, Channel] = field(default_factory=dict)
    t0: float = 0.0
    metadata: Mapping[str, Any] = field(default_factory=dict)
    name: str = "recording"
    inputs: Mapping[str, Channel] = field(default_factory=dict)
    detail: Mapping[str, Channel] = field(default_factory=dict)

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "fs": FieldRange(0, math.inf, "Hz", "output sample rate", low_open=True),
    }
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        *(_channel_group(g) for g in GROUPS),
        Constraint(
            "channels holds at least one channel",
            lambda c: len(c.channels) > 0,
            lambda c: "channels must hold at least one channel; got none",
        ),
        Constraint(
            "metadata is a mapping",
            lambda c: isinstance(c.metadata, Mapping),
            lambda c: f"metadata must be a mapping; got {type(c.metadata).__name__}",
            TypeError,
        ),
        Constraint(
            "every channel has the same length",
            lambda c: len(set(_lengths(c).values())) <= 1,
            lambda c: f"channels must all have the same length; got {_lengths(c)}",
        ),
        Constraint(
            "name non-empty, without '/'",
            lambda c: isinstance(c.name, str) and bool(c.name) and "/" not in c.name,
            lambda c: f"name must be non-empty without '/'; got {c.name!r}",
        ),
        Constraint(
            "a truth channel moved out of truth does not collide",
            lambda c: _collision(c) is None,
            lambda c: f"truth[{_collision(c)!r}] is not an error component and its group already holds a channel "
            f"{_collision(c)!r}",
        ),
        Constraint(
            "metadata is JSON-serialisable",
            lambda c: _json_error(c.metadata) is None,
            lambda c: f"metadata must be JSON-serialisable; {_json_error(c.metadata)}",
            TypeError,
        ),
    )

    def __post_init__(self) -> None:
        object.__setattr__(self, "channels", _as_channels(self.channels))
        object.__setattr__(self, "truth", _as_channels(self.truth))
        object.__setattr__(self, "inputs", _as_channels(self.inputs))
        object.__setattr__(self, "detail", _as_channels(self.detail))
        validate(self)  # the declared specs and constraints above
        truth, inputs, detail = _sorted_groups(dict(self.truth), dict(self.inputs), dict(self.detail), self.metadata)
        object.__setattr__(self, "truth", truth)
        object.__setattr__(self, "inputs", inputs)
        object.__setattr__(self, "detail", detail)
        object.__setattr__(self, "fs", float(self.fs))

    def groups(self) -> dict[str, Mapping[str, Channel]]:
        """The four groups of datasets, in file order (:data:`GROUPS`)."""
        return {g: getattr(self, g) for g in GROUPS}

    @property
    def n_samples(self) -> int:
        return len(next(iter(self.channels.values())).data)

    @property
    def nbytes(self) -> int:
        """Bytes of sample data in every group (about the size of its HDF5 file) [bytes]."""
        return sum(c.data.nbytes for chs in self.groups().values() for c in chs.values())

    @property
    def time(self) -> NDArray[np.float64]:
        """Sample times [s]."""
        return self.t0 + np.arange(self.n_samples) / self.fs

    def channel(self, key: str) -> Channel:
        """The channel ``key``: a logged channel's name, or ``truth/``, ``inputs/`` or ``detail/`` and a name.

        Parameters
        ----------
        key : str
            The name, as in the HDF5 file below the recording's group (without ``channels/``).

        Returns
        -------
        Channel
            The channel.

        Raises
        ------
        KeyError
            Naming the recording and listing what it holds.
        """
        if key in self.channels:
            return self.channels[key]
        group, _, name = key.partition("/")
        if group in GROUPS[1:] and name in getattr(self, group):
            return getattr(self, group)[name]
        held = [*sorted(self.channels), *(f"{g}/{k}" for g in GROUPS[1:] for k in sorted(getattr(self, g)))]
        raise KeyError(f"recording {self.name!r} has no channel {key!r}; it holds {held}")

    def __getitem__(self, key: str) -> NDArray[np.float64]:
        return self.channel(key).data

    def columns(self) -> dict[str, Channel]:
        """Every dataset by its column name: the logged channels' own names, the others ``group/name``."""
        cols = dict(self.channels)
        for g in GROUPS[1:]:
            cols.update({f"{g}/{k}": c for k, c in getattr(self, g).items()})
        return cols

    def to_dataframe(self) -> Any:
        """The recording as a pandas DataFrame: one column per dataset, indexed by time [s].

        Columns are named as :meth:`columns` names them (``output``, ``truth/true_rate``,
        ``inputs/temperature``, ...), in SI; ``df.attrs`` holds ``fs``, ``name``, the units
        (``units``: column -> unit) and the metadata. pandas is not a dependency of gyrobench:
        it is imported here, and its absence is one line.

        Returns
        -------
        pandas.DataFrame
            The samples.

        Raises
        ------
        ImportError
            pandas is not installed.
        """
        import importlib

        try:
            pd = importlib.import_module("pandas")  # not a dependency: imported only here
        except ImportError:
            raise ImportError("Recording.to_dataframe needs pandas, which gyrobench does not depend on: "
                              "pip install pandas") from None
        cols = self.columns()
        df = pd.DataFrame({k: c.data for k, c in cols.items()}, index=pd.Index(self.time, name="time [s]"))
        df.attrs.update({"fs": self.fs, "name": self.name, "units": {k: c.unit for k, c in cols.items()},
                         "metadata": json.loads(metadata_json(self.metadata))})
        return df


def closure(rec: Recording, output: str = OUTPUT) -> tuple[float, float]:
    """How far the error components miss ``output - true value``: (max |residual|, scale) [channel unit].

    The residual is ``output - true - sum(components)`` over the samples, with the components
    and the true value named by the metadata's ``error_components`` (:func:`truth_names`);
    the scale is the largest magnitude among the summed channels, for a rounding bound
    (``k (m + 2) eps scale`` for ``m`` components).

    Parameters
    ----------
    rec : Recording
        A recording whose metadata names its components.
    output : str
        The output channel (``output``; a triad's ``gyro_x``, ...).

    Returns
    -------
    tuple of float
        (max |residual|, scale).

    Raises
    ------
    ValueError
        The metadata names no components for ``output``.
    """
    comps = rec.metadata.get("error_components")
    if isinstance(comps, Mapping):
        names, true = list(comps.get(output, [])), f"{output}.true"
    else:
        names, true = list(comps or []), TRUE_RATE
    if comps is None or (isinstance(comps, Mapping) and output not in comps):
        raise ValueError(f"recording {rec.name!r}: the metadata names no error components of {output!r}")
    terms = [rec.truth[k].data for k in names]
    out, tr = rec[output], rec.truth[true].data
    resid = out - tr - (np.sum(terms, axis=0) if terms else 0.0)
    scale = max(float(np.max(np.abs(x), initial=0.0)) for x in (out, tr, *terms))
    return float(np.max(np.abs(resid), initial=0.0)), scale


def schema_problems(rec: Recording) -> list[str]:
    """What a recording lacks of the schema (docs/recording.md); empty when it follows it.

    Checked: an ``output`` channel in rad/s (or, for a triad, the outputs the metadata's
    ``error_components`` maps), ``truth/true_rate`` (``truth/<output>.true``), the component
    list in the metadata, every listed component under ``truth/`` and nothing else there.
    The closure itself is :func:`closure`.

    Parameters
    ----------
    rec : Recording
        The recording.

    Returns
    -------
    list of str
        One line per problem.
    """
    problems = []
    comps = rec.metadata.get("error_components")
    outputs = list(comps) if isinstance(comps, Mapping) else [OUTPUT]
    for ch in outputs:
        if ch not in rec.channels:
            problems.append(f"no output channel {ch!r}")
        elif rec.channels[ch].unit not in ("rad/s", "m/s^2", "rad", "m/s"):
            problems.append(f"channel {ch!r} is in {rec.channels[ch].unit!r}, not an SI rate")
    names = truth_names(rec.metadata)
    if names is None:
        problems.append("the metadata names no error_components")
    else:
        if missing := sorted(names - set(rec.truth)):
            problems.append(f"truth lacks {missing}")
        if extra := sorted(set(rec.truth) - names):
            problems.append(f"truth holds {extra}, which are not error components")
    return problems


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


class _GuardedFile:
    """The binary file h5py's ``fileobj`` driver writes to; a failed write never reaches HDF5.

    With h5py's default driver a failed write (disk full, ``ulimit -f``) leaves
    dirty HDF5 caches that every later flush tries to write again: closing the
    file fails, the file stays open, and HDF5's clean-up at interpreter exit
    crashes the process (segfault, exit 139). An exception raised inside this
    driver's callbacks is no better (h5py may meet it while freeing an object,
    then crashes too). So the first ``OSError`` is only remembered in
    :attr:`error`; from then on writes are accepted and dropped, HDF5 sees
    success and closes cleanly, and the caller raises :attr:`error` at its next
    check (:meth:`check`: after each block of writes and after closing).
    """

    def __init__(self, raw) -> None:
        self._raw = raw
        self.error: OSError | None = None
        self._discard = False

    def discard(self) -> None:
        """Drop every later write (the file is going to be removed)."""
        self._discard = True

    def check(self) -> None:
        """Raise the first write error, if any."""
        if self.error is not None:
            raise self.error

    def _failed(self, exc: OSError) -> None:
        self.error = self.error or exc
        self._discard = True

    def read(self, n: int = -1) -> bytes:
        return self._raw.read(n)

    def readinto(self, b) -> int:
        return self._raw.readinto(b)

    def seek(self, pos: int, whence: int = 0) -> int:
        return self._raw.seek(pos, whence)

    def tell(self) -> int:
        return self._raw.tell()

    def write(self, b) -> int:
        view = memoryview(b).cast("B")
        if not self._discard:
            try:
                done = 0
                while done < len(view):  # an unbuffered write may be partial (e.g. just below ulimit -f)
                    k = self._raw.write(view[done:])
                    if not k:
                        raise OSError(errno.EIO, "write returned no progress")
                    done += k
            except OSError as exc:
                self._failed(exc)
        return len(view)

    def truncate(self, size: int | None = None) -> int:
        if not self._discard:
            try:
                return self._raw.truncate(size)
            except OSError as exc:
                self._failed(exc)
        return self.tell() if size is None else size

    def flush(self) -> None:
        pass  # unbuffered: nothing to flush; durability comes from sync()

    def sync(self) -> None:
        """Push the data to the disk (before the rename makes the file visible)."""
        if not self._discard:
            try:
                os.fsync(self._raw.fileno())
            except OSError as exc:
                self._failed(exc)
        self.check()


@contextlib.contextmanager
def _h5_create(tmp: Path) -> Iterator[tuple[Any, _GuardedFile]]:
    """An h5py File writing into the (existing, empty) file ``tmp``, and its guard; closed on exit.

    The caller calls ``guard.check()`` after each block of writes; on leaving,
    the file is closed (writes discarded if anything failed, so HDF5 has
    nothing left to flush at exit) and the first write error is raised
    (``atomic_path`` then names the target path and removes ``tmp``).
    """
    import h5py

    raw = open(tmp, "r+b", buffering=0)  # noqa: SIM115 (closed in finally, after the HDF5 file)
    guard = _GuardedFile(raw)
    try:
        h5 = h5py.File(guard, "w")
        try:
            yield h5, guard
            guard.check()
            h5.close()
            guard.sync()
        except BaseException as exc:
            guard.discard()
            with contextlib.suppress(Exception):
                h5.close()
            if guard.error is not None and exc is not guard.error and isinstance(exc, Exception):
                raise guard.error from None  # e.g. h5py reading back a dropped block: the cause is the write error
            raise
    finally:
        raw.close()


def _check_compression(compression: object) -> str | None:
    if compression not in COMPRESSIONS:
        raise ValueError(f"compression must be one of {list(COMPRESSIONS)}; got {compression!r}")
    return compression if compression is None else str(compression)


def _write_group(h5, rec: Recording, *, compression: str | None = None) -> None:
    grp = h5.require_group("recordings").create_group(rec.name)
    grp.attrs["fs"] = rec.fs
    grp.attrs["t0"] = rec.t0
    grp.attrs["n_samples"] = rec.n_samples
    grp.attrs["metadata"] = metadata_json(rec.metadata)
    for sub, chans in rec.groups().items():
        g = grp.create_group(sub)
        for k, c in chans.items():
            chunks = True if len(c.data) > 1 << 16 or (compression and len(c.data)) else None
            ds = g.create_dataset(k, data=c.data, chunks=chunks, compression=compression if chunks else None)
            ds.attrs["unit"] = c.unit
            ds.attrs["description"] = c.description


def _mark_root(h5) -> None:
    h5.attrs["format"] = FORMAT
    h5.attrs["format_version"] = FORMAT_VERSION
    h5.attrs["gyrobench_version"] = package_version()


def check_finite_samples(data: NDArray, what: str, *, offset: int = 0) -> None:
    """Refuse non-finite samples before they are written (a file ``allan`` would refuse), in one line.

    ``offset`` is the record's index of ``data[0]`` when ``data`` is one chunk of it.

    Parameters
    ----------
    data : ndarray
        The samples (or one chunk of them).
    what : str
        What they are, for the message.
    offset : int
        Record index of ``data[0]``.

    Raises
    ------
    ValueError
        Naming ``what``, the first non-finite sample, its index and how many there are.
    """
    v = np.asarray(data)
    if v.dtype.kind not in "fc":
        return
    step = 1 << 20  # blockwise: no record-sized boolean temporary
    for a in range(0, v.size, step):
        finite = np.isfinite(v[a : a + step])
        if not finite.all():
            i = a + int(np.flatnonzero(~finite)[0])
            total = int(v.size - np.count_nonzero(np.isfinite(v)))
            many = "s" if total > 1 else ""
            raise ValueError(
                f"{what} has {v[i].item()!r} at sample {offset + i} ({total} non-finite sample{many}"
                f"{' in this block' if offset else ''}); "
                "a recording is written only with finite samples: check the configuration's values and units"
            )


def _check_recording_finite(rec: Recording) -> None:
    for sub, chans in rec.groups().items():
        for k, c in chans.items():
            check_finite_samples(c.data, f"recording {rec.name!r}: {sub}/{k}")


def save_hdf5(
    path: str | os.PathLike,
    recordings: Recording | list[Recording],
    *,
    compression: str | None = None,
    overwrite: bool = False,
) -> Path:
    """Write one or several recordings to an HDF5 file, atomically.

    Before a byte is written each recording that names its error components must close
    (:func:`gyrobench.io.write_rules.check_closes`), and an existing ``path`` must be a file
    gyrobench wrote unless ``overwrite`` (:func:`gyrobench.io.write_rules.check_replaceable`).

    Parameters
    ----------
    path : str or os.PathLike
        The HDF5 file (an existing one is replaced only if gyrobench wrote it, or with ``overwrite``).
    recordings : Recording or list of Recording
        The recordings, each stored under ``/recordings/<name>``.
    compression : {None, "gzip", "lzf"}
        h5py's filter on every dataset (chunked): ``"gzip"`` (deflate, level 4, readable by
        MATLAB and any HDF5 build), ``"lzf"`` (faster, h5py's own filter: other tools need
        the lzf plugin), None: uncompressed. A simulated gyro's noise is nearly incompressible
        (float64 mantissas of noise); constant and step-wise channels shrink much.
    overwrite : bool
        Replace an existing file gyrobench did not write (default: refused).

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    ValueError
        If two recordings share a name, or a sample is not finite (nothing is written).
    RecordingClosureError
        If a recording's components do not sum to ``output - true_rate`` (nothing is written).
    OutputRefused
        If ``path`` exists, gyrobench did not write it and not ``overwrite``.
    AtomicWriteError
        If the data would not fit on the disk (checked before writing) or the
        write fails; ``path`` is then left as it was.
    """
    compression = _check_compression(compression)
    recs = [recordings] if isinstance(recordings, Recording) else list(recordings)
    names = [r.name for r in recs]
    if len(set(names)) != len(names):
        raise ValueError(f"recording names must be unique within a file; got {names}")
    for r in recs:
        _check_recording_finite(r)
        check_closes(r, path)
    check_replaceable(path, overwrite=overwrite)
    ensure_free_space(path, sum(r.nbytes for r in recs))
    with atomic_path(path) as tmp, _h5_create(tmp) as (h5, guard):
        _mark_root(h5)
        for r in recs:
            _write_group(h5, r, compression=compression)
            guard.check()
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
        fmt = fmt.decode(errors="replace")
    if not isinstance(fmt, str):
        fmt = _short_repr(fmt)
    link = h5.get("recordings", getlink=True) if fmt == FORMAT else None
    if fmt != FORMAT or link is None:
        h5.close()
        raise RecordingFormatError(
            f"{str(p)!r} is an HDF5 file but not a gyrobench recording (root attribute format={fmt!r})"
        )
    if not isinstance(link, h5py.HardLink):
        h5.close()
        raise RecordingFormatError(_link_message(f"{str(p)!r}: /recordings", link))
    return h5


def list_hdf5(path: str | os.PathLike) -> list[str]:
    """Names of the recordings in a gyrobench HDF5 file.

    Parameters
    ----------
    path : str or os.PathLike
        A gyrobench HDF5 file.

    Returns
    -------
    list of str
        The recordings' names.
    """
    with _open_checked(path) as h5:
        return list(h5["recordings"].keys())


#: sample rates a recording read from a file may have [Hz]: one sample per ~32 years to
#: 1 PHz, beyond any gyro's data rate. The Allan fit itself was checked finite over
#: 1e-12..1e40 Hz (its tau**-2 .. tau**2 terms overflow float64 near 1e83 Hz).
FS_RANGE_HZ = (1e-9, 1e15)


class _NameError(KeyError):
    """No recording of that name (or several and none named): a KeyError with a plain message."""

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else ""


class _ChoiceError(ValueError):
    """Several recordings in the file and none named."""


class _RangeError(ValueError):
    """``start``/``stop`` out of range: the caller's values, not the file's fault."""


def _attr(grp, key: str, kind: type, where: str):
    """Group attribute ``key`` as a finite float or an int, else RecordingFormatError naming it."""
    if key not in grp.attrs:
        raise RecordingFormatError(f"{where} has no attribute {key!r}: incomplete file?")
    raw = grp.attrs[key]
    arr = np.asarray(raw)
    if arr.size != 1 or arr.dtype.kind not in ("f", "i", "u") or arr.dtype == bool:
        raise RecordingFormatError(
            f"{where}: attribute {key!r} must be a real number; got {_short_repr(raw)}"
        )
    v = float(arr.reshape(()))
    if not math.isfinite(v) or (kind is int and v != int(v)):
        raise RecordingFormatError(
            f"{where}: attribute {key!r} must be a finite {'integer' if kind is int else 'number'}; "
            f"got {_short_repr(raw)}"
        )
    return int(v) if kind is int else v


def _short_repr(v: Any) -> str:
    text = " ".join(repr(v).split())
    return text if len(text) <= 80 else text[:77] + "..."


def _text_attr(attrs, key: str, where: str, default: str | None = None) -> str:
    if key not in attrs:
        if default is not None:
            return default
        raise RecordingFormatError(f"{where} has no attribute {key!r}: incomplete file?")
    v = attrs[key]
    if isinstance(v, bytes):
        try:
            return v.decode()
        except UnicodeDecodeError:
            raise RecordingFormatError(f"{where}: attribute {key!r} is not UTF-8 text") from None
    if not isinstance(v, str):
        raise RecordingFormatError(f"{where}: attribute {key!r} must be text; got {_short_repr(v)}")
    return v


def _free_text(v: Any) -> str:
    """A free-text attribute (a description) as text, whatever another tool stored in it."""
    if isinstance(v, bytes):
        return v.decode(errors="replace")
    return v if isinstance(v, str) else _short_repr(v)


def _datasets(h5, grp, sub: str, where: str) -> dict[str, Any]:
    """The datasets of ``grp[sub]``, refusing links that leave the file or do not resolve.

    HDF5 external links would make a recording read another file without a word, and soft
    links can loop: both are refused (gyrobench writes neither).
    """
    import h5py

    link = grp.get(sub, getlink=True)
    if link is None:
        raise RecordingFormatError(f"{where} has no {sub!r} group: incomplete file?")
    if isinstance(link, (h5py.ExternalLink, h5py.SoftLink)):
        raise RecordingFormatError(_link_message(f"{where}: {sub}", link))
    out = {}
    g = grp[sub]
    if not isinstance(g, h5py.Group):
        raise RecordingFormatError(f"{where}/{sub} must be a group; got a {type(g).__name__}")
    _check_stored_once(g, f"{where}: {sub}")
    for k in g:
        lk = g.get(k, getlink=True)
        if isinstance(lk, (h5py.ExternalLink, h5py.SoftLink)):
            raise RecordingFormatError(_link_message(f"{where}: {sub}/{k}", lk))
        ds = g[k]
        if not isinstance(ds, h5py.Dataset):
            raise RecordingFormatError(f"{where}/{sub}/{k} must be a dataset; got a group")
        _check_stored_once(ds, f"{where}: {sub}/{k}")
        _check_storage(ds, f"{where}: {sub}/{k}")
        out[k] = ds
    return out


def _check_stored_once(obj: Any, name: str) -> None:
    """Refuse an object reachable under several names (HDF5 hard links): one array read as two channels."""
    import h5py

    rc = h5py.h5o.get_info(obj.id).rc
    if rc != 1:
        raise RecordingFormatError(
            f"{name} is stored under {rc} names in the file (HDF5 hard links); each group and dataset of a "
            "recording must be stored once"
        )


def _check_storage(ds: Any, name: str) -> None:
    """Refuse a dataset whose samples are not all in the file: external raw storage, a virtual dataset, or
    chunks never written (they would read as the fill value)."""
    plist = ds.id.get_create_plist()
    if plist.get_external_count() > 0:
        ext = plist.get_external(0)[0]
        raise RecordingFormatError(
            f"{name} keeps its samples in the external file {ext.decode(errors='replace')!r} (HDF5 external "
            "storage); a recording must hold its own data: copy the data into the file"
        )
    if ds.is_virtual:
        raise RecordingFormatError(
            f"{name} is an HDF5 virtual dataset (its samples live in other datasets or files); a recording "
            "must hold its own data: copy the data into the file"
        )
    if ds.chunks is not None and ds.size and plist.get_nfilters() > 0:  # unfiltered: the storage size tells
        expected = math.prod(-(-n // c) for n, c in zip(ds.shape, ds.chunks, strict=True))
        written = ds.id.get_num_chunks()
        if written < expected:
            raise RecordingFormatError(
                f"{name} claims {ds.size} samples in {expected} chunks but {written} of them are written (the "
                "rest would read as the fill value): truncated or forged file"
            )


def _link_message(name: str, lk: Any) -> str:
    import h5py

    if isinstance(lk, h5py.ExternalLink):
        return (f"{name} is an HDF5 external link to {lk.filename!r}:{lk.path}; external links are "
                "refused (a recording must hold its own data): copy the data into the file")
    return f"{name} is an HDF5 soft link to {lk.path!r}; links are refused in a recording"


def load_hdf5(
    path: str | os.PathLike, name: str | None = None, *, start: float | None = None, stop: float | None = None
) -> Recording:
    """Read one recording (``name``, or the only one) and check it is complete.

    Everything is checked before any sample is read: the attributes ``fs``, ``t0``
    (finite real numbers), ``n_samples`` (an integer) and ``metadata`` (JSON text);
    every channel must be a real (float or integer) 1-D dataset of ``n_samples``
    values, stored in the file itself (external, soft and duplicate hard links at every
    level, external raw storage, virtual datasets and unwritten chunks are refused), and all
    of them together must fit in memory (:func:`gyrobench.base.memory.check_memory`: the
    samples read, their float64 copies and the largest chunk decompressed).

    ``start`` and ``stop`` [s after the first sample] read only the samples in between
    (``t0`` moves to the first one read).

    Parameters
    ----------
    path : str or os.PathLike
        A gyrobench HDF5 file.
    name : str, optional
        The recording (None: the file must hold exactly one).
    start, stop : float, optional
        Read only the samples from ``start`` to ``stop`` [s after the first sample].

    Returns
    -------
    Recording
        The recording (float64 channels, SI).

    Raises
    ------
    RecordingFormatError
        For a foreign, truncated or malformed file (the message names the file and
        the item), complex data, or links.
    gyrobench.base.memory.MemoryLimitError
        If the channels would not fit in memory.
    KeyError
        If ``name`` is not in the file.
    """
    import h5py

    from gyrobench.base import memory

    with _open_checked(path) as h5:
        try:
            raw_version = h5.attrs.get("format_version", 1)
            try:
                version = int(raw_version)
            except (TypeError, ValueError):  # not a number: read as the first version
                version = 1
            recs = h5["recordings"]
            if name is None:
                if len(recs) != 1:
                    raise _ChoiceError(f"{str(path)!r} holds {len(recs)} recordings {list(recs)}; name one")
                name = next(iter(recs))
            if name not in recs:
                raise _NameError(f"{str(path)!r} has no recording {name!r}; it has {list(recs)}")
            where = f"{str(path)!r}: recording {name!r}"
            _check_stored_once(recs, f"{str(path)!r}: /recordings")
            link = recs.get(name, getlink=True)
            if not isinstance(link, h5py.HardLink):
                raise RecordingFormatError(_link_message(where, link))
            grp = recs[name]
            if not isinstance(grp, h5py.Group):
                raise RecordingFormatError(f"{where} must be a group; got a {type(grp).__name__}")
            _check_stored_once(grp, where)
            _check_attribute_memory(path, recs, where)  # before any attribute's text is read
            fs = _attr(grp, "fs", float, where)
            if not FS_RANGE_HZ[0] <= fs <= FS_RANGE_HZ[1]:
                raise RecordingFormatError(
                    f"{where}: attribute 'fs' must be in [{FS_RANGE_HZ[0]:g}, {FS_RANGE_HZ[1]:g}] Hz "
                    f"(no gyro samples outside it); got {fs!r}"
                )
            t0 = _attr(grp, "t0", float, where)
            n = _attr(grp, "n_samples", int, where)
            meta_text = _text_attr(grp.attrs, "metadata", where)
            try:
                meta = json.loads(meta_text)
            except (json.JSONDecodeError, RecursionError) as exc:
                raise RecordingFormatError(f"{where}: attribute 'metadata' is not JSON ({exc})") from None
            if not isinstance(meta, dict):
                raise RecordingFormatError(
                    f"{where}: attribute 'metadata' must be a JSON object; got {_short_repr(meta)}"
                )
            # inputs/ and detail/ came with format version 2: a version-1 file has neither
            sets = {sub: _datasets(h5, grp, sub, where) for sub in GROUPS if sub in GROUPS[:2] or sub in grp}
            for sub, dss in sets.items():
                for k, ds in dss.items():
                    if ds.dtype.kind not in ("f", "i", "u"):
                        kind = "complex" if ds.dtype.kind == "c" else str(ds.dtype)
                        raise RecordingFormatError(
                            f"{where}: {sub}/{k} holds {kind} data; a channel must be real "
                            "(float or integer), it is never cast"
                        )
                    if ds.shape != (n,):
                        raise RecordingFormatError(
                            f"{where}: {sub}/{k} has shape {ds.shape}, expected ({n},) "
                            "(attribute n_samples): truncated file?"
                        )
                    stored = ds.id.get_storage_size()
                    if ds.id.get_create_plist().get_nfilters() == 0 and stored < ds.nbytes:
                        # unfiltered data take their full size on disk: less means unwritten chunks
                        raise RecordingFormatError(
                            f"{where}: {sub}/{k} claims {n} samples ({_fmt_bytes(ds.nbytes)}) but "
                            f"the file stores {_fmt_bytes(stored)} of them: truncated or forged file"
                        )
            a, b = _sample_range(n, fs, start, stop, where)
            n_series = sum(len(d) for d in sets.values())
            memory.check_memory(
                _read_bytes([ds for d in sets.values() for ds in d.values()], b - a),
                f"reading {where} ({n_series} channels of {b - a} samples)",
                hint="read fewer samples (--start/--stop, or split the file) or use a machine with more memory",
            )
            out: dict[str, dict[str, Channel]] = {}
            for sub, dss in sets.items():
                out[sub] = {}
                for k, ds in dss.items():
                    data = ds[a:b].astype(float, copy=False)
                    out[sub][k] = Channel(
                        data,
                        _text_attr(ds.attrs, "unit", f"{where}: {sub}/{k}"),
                        _free_text(ds.attrs.get("description", "")),
                    )
        except (RecordingFormatError, memory.MemoryLimitError, _NameError, _ChoiceError, _RangeError):
            raise
        except (KeyError, ValueError) as exc:
            raise RecordingFormatError(f"{str(path)!r}: recording {name!r} is incomplete ({exc})") from None
        except (OSError, RuntimeError, TypeError, RecursionError) as exc:  # h5py: link loops, bad objects
            raise RecordingFormatError(
                f"{str(path)!r}: recording {name!r} cannot be read ({' '.join(str(exc).split())})"
            ) from None
        if version < 2:
            _read_version_1(out)
        try:
            return Recording(fs=fs, channels=out["channels"], truth=out["truth"], t0=t0 + a / fs, metadata=meta,
                             name=name, inputs=out.get("inputs", {}), detail=out.get("detail", {}))
        except (ValueError, TypeError) as exc:  # e.g. fs = 0 written by another tool: name the file
            raise RecordingFormatError(f"{str(path)!r}: recording {name!r} is invalid: {exc}") from None


def _read_version_1(groups: dict[str, dict[str, Channel]]) -> None:
    """Rename, in place, what format version 1 named otherwise: channel ``rate`` -> ``output``, truth
    ``rate`` -> ``true_rate`` (each only where the new name is absent; a duplicate ``truth/rate`` beside
    ``truth/true_rate`` is dropped)."""
    chans, truth = groups["channels"], groups["truth"]
    if OUTPUT not in chans and "rate" in chans:
        groups["channels"] = {(OUTPUT if k == "rate" else k): c for k, c in chans.items()}
    if "rate" in truth:
        rate = truth.pop("rate")
        truth.setdefault(TRUE_RATE, rate)


#: peak bytes of reading a text attribute per byte stored: HDF5's copy, the bytes, the str and the
#: JSON objects parsed from it (a 60 MB metadata attribute peaked at 371 MB: about 6)
ATTRIBUTE_COPIES = 6
#: attributes of at most this many bytes in all are read without a memory check
_SMALL_ATTRIBUTES = 1 << 20


def _check_attribute_memory(path: str | os.PathLike, recs: Any, where: str) -> None:
    """Count the recording's attributes against the memory limit before any is read.

    A variable-length string attribute's size is not stored where it can be asked for, but it
    lives in the file: the file's bytes outside the recordings' datasets bound everything the
    attributes can hold. Reading them costs about :data:`ATTRIBUTE_COPIES` times that
    (:func:`gyrobench.base.memory.check_memory`); a bound under 1 MB is not checked.
    """
    import h5py

    from gyrobench.base import memory

    def hard(group: Any, key: str) -> Any:  # the object a hard link names, else None (links are refused later)
        return group[key] if isinstance(group.get(key, getlink=True), h5py.HardLink) else None

    data = 0
    try:
        for name in recs:
            rec = hard(recs, name)
            for sub in GROUPS if isinstance(rec, h5py.Group) else ():
                g = hard(rec, sub)
                for k in g if isinstance(g, h5py.Group) else ():
                    ds = hard(g, k)
                    data += int(ds.id.get_storage_size()) if isinstance(ds, h5py.Dataset) else 0
    except Exception:  # a malformed file: the whole file bounds its attributes (its faults are named later)
        data = 0
    bound = max(os.path.getsize(path) - data, 0)
    if bound > _SMALL_ATTRIBUTES:
        memory.check_memory(
            ATTRIBUTE_COPIES * bound,
            f"reading the attributes of {where} (up to {_fmt_bytes(bound)} of the file is not sample data)",
            hint="the file holds far more than a recording's metadata: rewrite it without the extra attributes",
        )


def _sample_range(n: int, fs: float, start: float | None, stop: float | None, where: str) -> tuple[int, int]:
    """Samples [a, b) between ``start`` and ``stop`` [s after the first sample]; at least 2 of them."""
    for flag, v in (("--start", start), ("--stop", stop)):
        if v is not None and not (math.isfinite(v) and v >= 0):
            raise _RangeError(f"{flag} must be a finite time >= 0 s; got {v!r}")
    a = 0 if start is None else min(n, int(math.ceil(start * fs - 1e-9)))
    b = n if stop is None else min(n, int(math.floor(stop * fs + 1e-9)))
    if (start is not None or stop is not None) and b - a < 2:
        raise _RangeError(
            f"--start/--stop keep {max(b - a, 0)} samples of the {n / fs:g} s of {where}; need at least 2"
        )
    return a, max(a, b)


def _read_bytes(datasets: list[Any], n: int) -> float:
    """Peak bytes of reading ``n`` samples of each dataset as float64: the samples as stored, their float64
    copy when stored otherwise, and the largest chunk decompressed at once."""
    from gyrobench.base import memory

    total = memory.series_bytes(n, len(datasets))
    chunk = 0.0
    for ds in datasets:
        if ds.dtype != np.float64:
            total += float(n) * ds.dtype.itemsize
        if ds.chunks is not None:
            chunk = max(chunk, float(math.prod(ds.chunks)) * ds.dtype.itemsize)
    return total + chunk


class HDF5StreamWriter:
    """Write a recording chunk by chunk, so a long record never sits in memory.

    Use as a context manager; the file appears at ``path`` only after a clean
    exit (atomic rename). Channels are declared up front. Given
    ``expected_samples``, a record that would not fit on the disk is refused
    on entry, before anything is written (:func:`ensure_free_space`); a write
    that fails later raises :class:`AtomicWriteError` and leaves no file.

    Parameters
    ----------
    path : str or os.PathLike
        The HDF5 file.
    name : str
        The recording's name.
    fs : float
        Sample rate [Hz].
    channels : mapping of str to str
        Channel name -> unit.
    truth : mapping of str to str, optional
        Truth channel name -> unit.
    t0 : float
        Time of the first sample [s].
    metadata : mapping, optional
        JSON-serialisable metadata.
    chunk : int
        HDF5 chunk length [samples].
    expected_samples : int, optional
        Samples to be written, for the free-space check on entry.
    compression : {None, "gzip", "lzf"}
        h5py's filter on every dataset (:func:`save_hdf5`).
    overwrite : bool
        Replace an existing file gyrobench did not write (default: refused, on entry).

    Notes
    -----
    When the metadata names the error components, every chunk must close
    (:func:`gyrobench.io.write_rules.check_closes`) before it is appended; a chunk that does not
    raises, and the file is never committed.

    Examples
    --------
    >>> import numpy as np, tempfile, os
    >>> p = os.path.join(tempfile.mkdtemp(), "x.h5")
    >>> with HDF5StreamWriter(p, name="r", fs=10.0, channels={"output": "rad/s"}) as w:
    ...     w.append(output=np.zeros(5)); w.append(output=np.ones(5))
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
        expected_samples: int | None = None,
        compression: str | None = None,
        overwrite: bool = False,
    ) -> None:
        if not (math.isfinite(fs) and fs > 0):
            raise ValueError(f"fs must be a finite number > 0 Hz; got {fs!r}")
        if not (isinstance(chunk, int) and chunk > 0):
            raise ValueError(f"chunk must be an integer > 0 samples; got {chunk!r}")
        self._compression = _check_compression(compression)
        self.path = Path(path)
        self.name, self.fs, self.t0 = name, float(fs), float(t0)
        self._units = {"channels": dict(channels), "truth": dict(truth or {}), "inputs": {}, "detail": {}}
        self._meta = dict(metadata or {})
        self._chunk = chunk
        self._expected = expected_samples
        self._n = 0
        self._stack: contextlib.ExitStack | None = None
        self._overwrite = bool(overwrite)

    def __enter__(self) -> HDF5StreamWriter:
        check_replaceable(self.path, overwrite=self._overwrite)
        if self._expected is not None:
            n_ds = len(self._units["channels"]) + len(self._units["truth"])
            ensure_free_space(self.path, 8 * self._expected * n_ds)
        with contextlib.ExitStack() as stack:  # a failure below closes and removes what was opened
            tmp = stack.enter_context(atomic_path(self.path))
            h5, self._guard = stack.enter_context(_h5_create(tmp))
            _mark_root(h5)
            grp = h5.require_group("recordings").create_group(self.name)
            grp.attrs["fs"] = self.fs
            grp.attrs["t0"] = self.t0
            grp.attrs["metadata"] = metadata_json(self._meta)
            self._ds = {}
            for sub, units_ in self._units.items():
                g = grp.create_group(sub)
                for k, u in units_.items():
                    ds = g.create_dataset(k, shape=(0,), maxshape=(None,), dtype="f8", chunks=(self._chunk,),
                                          compression=self._compression)
                    ds.attrs["unit"] = u
                    ds.attrs["description"] = ""
                    self._ds[(sub, k)] = ds
            self._grp = grp
            self._stack = stack.pop_all()  # success: kept open until __exit__
        return self

    def append(self, *, truth: Mapping[str, NDArray] | None = None, **channels: NDArray) -> None:
        """Append the next samples of every declared channel (and truth component)."""
        given = {("channels", k): v for k, v in channels.items()}
        given.update({("truth", k): v for k, v in (truth or {}).items()})
        if set(given) != set(self._ds):
            raise ValueError(
                f"append must give every declared channel {sorted(k for _, k in self._ds)}; "
                f"got {sorted(k for _, k in given)}"
            )
        lengths = {len(v) for v in given.values()}
        if len(lengths) != 1:
            raise ValueError(f"append: all channels must have the same length; got {lengths}")
        for (sub, k), v in given.items():
            check_finite_samples(v, f"recording {self.name!r}: {sub}/{k}", offset=self._n)
        if truth_names(self._meta) is not None:  # the chunk closes, or nothing of it is appended
            check_closes(Recording(fs=self.fs, name=self.name, metadata=self._meta,
                                   channels={k: Channel(v, self._units["channels"][k]) for k, v in channels.items()},
                                   truth={k: Channel(v, self._units["truth"][k]) for k, v in (truth or {}).items()}),
                         self.path)
        m = lengths.pop()
        for key, v in given.items():
            ds = self._ds[key]
            ds.resize((self._n + m,))
            ds[self._n :] = v
        self._n += m
        self._guard.check()

    def __exit__(self, exc_type, exc, tb) -> bool:
        # the HDF5 file is closed (writes discarded on error) before atomic_path removes or renames it
        stack, self._stack = self._stack, None
        assert stack is not None  # set by __enter__; __exit__ runs once
        self._ds = {}
        if exc_type is not None:
            return bool(stack.__exit__(exc_type, exc, tb))  # the file is removed, the target left as it was
        with stack:  # an error setting the attribute reaches the contexts like one from the block
            self._grp.attrs["n_samples"] = self._n
        return False


def to_csv(path: str | os.PathLike, rec: Recording, *, include_truth: bool = True, overwrite: bool = False) -> Path:
    """Export a recording to CSV, atomically.

    The first line is gyrobench's marker, with the recording's name, rate and metadata (JSON,
    with the component list); the second the header. The columns are ``time [s]``, then
    ``name [unit]`` for each logged channel, then (with
    ``include_truth``) ``group/name [unit]`` for every dataset of ``truth``, ``inputs`` and
    ``detail`` (:meth:`Recording.columns`).

    Parameters
    ----------
    path : str or os.PathLike
        The CSV file (an existing one is replaced only if gyrobench wrote it, or with ``overwrite``).
    rec : Recording
        The recording; if it names its error components it must close (:func:`save_hdf5`).
    include_truth : bool
        Also write the truth, inputs and detail (``truth/<name> [unit]``, ...).
    overwrite : bool
        Replace an existing file gyrobench did not write (default: refused).

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    ValueError
        If a sample is not finite (nothing is written).
    RecordingClosureError
        If its components do not sum to ``output - true_rate`` (nothing is written).
    OutputRefused
        If ``path`` exists, gyrobench did not write it and not ``overwrite``.
    """
    _check_recording_finite(rec)
    check_closes(rec, path)
    check_replaceable(path, overwrite=overwrite)
    cols = [("time", "s", rec.time)]
    cols += [(k, c.unit, c.data) for k, c in (rec.columns() if include_truth else rec.channels).items()]
    from gyrobench.base.safety import comment_marker

    # the first line is gyrobench's marker (gyrobench.base.safety): a later run may replace this file
    # the metadata (with the component list) rides on the marker line: the header stays the second line
    marker = comment_marker(f"recording {rec.name!r}; fs {rec.fs!r} Hz; metadata {metadata_json(rec.metadata)}")
    header = marker + "\n" + ",".join(f"{k} [{u}]" for k, u, _ in cols)
    ensure_free_space(path, 25 * len(cols) * rec.n_samples)  # "%.17g," is at most 25 characters
    data = np.column_stack([c for _, _, c in cols])
    with atomic_path(path) as tmp:
        np.savetxt(tmp, data, delimiter=",", header=header, comments="", fmt="%.17g")
    return Path(path)


_CSV_MARKER = re.compile(
    r"^# written by gyrobench recording '(?P<name>[^']*)'; fs (?P<fs>\S+) Hz; metadata (?P<meta>\{.*\})$"
)
_CSV_COLUMN = re.compile(r"^(?P<name>.+) \[(?P<unit>[^\]]*)\]$")


def load_csv(path: str | os.PathLike) -> Recording:
    """Read back a recording that :func:`to_csv` (or ``gyrobench simulate``) wrote as CSV.

    The marker line gives the name, rate and metadata; the header's ``group/name [unit]``
    columns the groups (a name without a group is a logged channel).

    Parameters
    ----------
    path : str or os.PathLike
        The CSV file.

    Returns
    -------
    Recording
        The recording (%.17g columns round-trip float64 exactly).

    Raises
    ------
    RecordingFormatError
        The file is not a gyrobench recording CSV (its first line is not the marker with the
        metadata, or a header cell is not ``name [unit]``).
    """
    p = Path(path)
    with open(p, encoding="utf-8") as fh:
        first, header = fh.readline().rstrip("\n"), fh.readline().rstrip("\n")
    m = _CSV_MARKER.match(first)
    if m is None:
        raise RecordingFormatError(f"{str(p)!r} is not a gyrobench recording CSV (its first line is not "
                                   "gyrobench's marker with the metadata)")
    try:
        meta = json.loads(m["meta"])
        fs = float(m["fs"])
    except (ValueError, json.JSONDecodeError) as exc:
        raise RecordingFormatError(f"{str(p)!r}: the marker line's rate or metadata is unreadable ({exc})") from None
    cells = [_CSV_COLUMN.match(c) for c in header.split(",")]
    if not cells or any(c is None for c in cells) or cells[0]["name"] != "time":  # type: ignore[index]
        raise RecordingFormatError(f"{str(p)!r}: the header must be 'time [s]' then 'name [unit]' cells; got "
                                   f"{_short_repr(header)}")
    data = np.loadtxt(p, delimiter=",", skiprows=2, ndmin=2)
    groups: dict[str, dict[str, Channel]] = {g: {} for g in GROUPS}
    for j, c in enumerate(cells[1:], start=1):
        assert c is not None
        group, _, name = c["name"].partition("/")
        if not name or group not in GROUPS[1:]:
            group, name = "channels", c["name"]
        groups[group][name] = Channel(data[:, j], c["unit"])
    t0 = float(data[0, 0]) if len(data) else 0.0
    return Recording(fs=fs, t0=t0, metadata=meta, name=m["name"], **groups)
