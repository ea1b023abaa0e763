"""Reading real IMU logs (CSV) for ``gyrobench allan``: columns, units, time base, segments.

Formats recognised (see :func:`read_csv_log`):

* plain CSV from any gyro: ``#`` comment lines, an optional header row, ``.gz`` allowed;
  separator ``,``, ``;`` or tab (detected from the header or the first data row); a UTF-8
  byte-order mark (Excel's "CSV UTF-8") and quoted header cells are accepted; decimal
  commas ("0,5;1,2", detected with ``;`` or tab separators, or ``decimal=","``); a header
  that names a column twice is refused;
* EuRoC / ASL (``imu0/data.csv``): header ``#timestamp [ns],w_RS_S_x [rad s^-1],...,
  a_RS_S_x [m s^-2],...`` (the header is a ``#`` line);
* Kalibr IMU CSV: ``timestamp,omega_x,omega_y,omega_z,alpha_x,alpha_y,alpha_z``
  (timestamp in ns, omega in rad/s, alpha = acceleration in m/s^2: Kalibr's naming);
* ROS ``rostopic echo -p`` of sensor_msgs/Imu: ``%time,field.header.seq,field.header.stamp,
  field.header.frame_id,...,field.angular_velocity.x,...,field.linear_acceleration.x,...``
  (times in ns, SI values; text columns such as the frame_id are read only when named, and
  ``all_axes`` skips the orientation and covariance fields).

Time column: its unit comes from the header (``[s]``, ``(ms)``, ``_us``, ``[ns]``) or, when
there is none, from the magnitude: timestamps above 1e8 are taken as Unix epoch times and
their unit is chosen from the order of magnitude of the first one (1e9 s, 1e12 ms,
1e15 us, 1e18 ns around the present), with a note saying so.
Columns without a unit get the unit of their format's convention (Kalibr/ROS/EuRoC: rad/s
and m/s^2) or must be given one (``--units``).

Everything returned is SI: rate in rad/s, acceleration in m/s^2, time in s.
"""

from __future__ import annotations

import csv
import io
import math
import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

__all__ = ["Channel", "Log", "read_csv_log", "ACCEL_UNITS", "unit_of"]

#: a time step larger than this multiple of the median step is a gap in the record
GAP_FACTOR = 1.5
#: fewer data rows than this cannot give any Allan deviation
MIN_ROWS = 2

#: time-column names (case-insensitive, after removing a "[unit]" or "(unit)")
_TIME_NAME = re.compile(
    r"^#?\s*(?:%?time|t|timestamp|times|field\.header\.stamp|stamp)(?:[ _-]?(s|sec|secs|seconds|ms|us|ns))?$",
    re.IGNORECASE,
)
#: time unit name -> seconds
TIME_UNITS = {
    "s": 1.0,
    "sec": 1.0,
    "secs": 1.0,
    "second": 1.0,
    "seconds": 1.0,
    "ms": 1e-3,
    "us": 1e-6,
    "µs": 1e-6,
    "ns": 1e-9,
    "min": 60.0,
    "h": 3600.0,
}
#: acceleration units -> m/s^2 (standard gravity 9.80665 m/s^2, CGPM 1901)
ACCEL_UNITS = {
    "m/s^2": 1.0,
    "m/s2": 1.0,
    "m s^-2": 1.0,
    "g": 9.80665,
    "mg": 9.80665e-3,
    "ug": 9.80665e-6,
}
#: spellings of rate units in real headers -> gyrobench.sim.units.RATE_UNITS names
_RATE_ALIASES = {
    "rad s^-1": "rad/s",
    "rad/sec": "rad/s",
    "rad s-1": "rad/s",
    "dps": "deg/s",
    "deg/sec": "deg/s",
    "°/s": "deg/s",
    "deg s^-1": "deg/s",
    "dph": "deg/h",
    "°/h": "deg/h",
}
#: column-name patterns of gyro (rate) and accelerometer columns, for the all-axes mode
_GYRO_NAME = re.compile(r"(^w_|^omega|gyro|angular_velocity|^g[xyz]$|^w[xyz]$|rate)", re.IGNORECASE)
_ACCEL_NAME = re.compile(r"(^a_|^alpha_|acc|linear_acceleration|^a[xyz]$)", re.IGNORECASE)
#: names that are not a measured axis although they match the patterns above (the covariance
#: fields of ROS sensor_msgs/Imu, e.g. ``field.angular_velocity_covariance0``)
_NOT_AXIS_NAME = re.compile(r"covariance", re.IGNORECASE)
#: name suffixes that carry a unit (``gyro_x_dps``, ``accel_x_g``)
_SUFFIX_UNIT = {
    "dps": "deg/s",
    "degps": "deg/s",
    "radps": "rad/s",
    "rads": "rad/s",
    "dph": "deg/h",
    "g": "g",
    "mg": "mg",
    "mps2": "m/s^2",
    "ms2": "m/s^2",
}
#: formats whose columns have an implied SI unit
_SI_FORMATS = ("euroc", "kalibr", "ros")


@dataclass(frozen=True)
class Channel:
    """One analysed column: name, quantity ("rate" or "accel"), SI data and where its unit came from."""

    label: str
    quantity: str
    data: NDArray[np.float64]
    unit: str


@dataclass
class Log:
    """Columns read from a log, all sampled at ``fs`` [Hz]; ``notes`` are for the report."""

    path: Path
    fs: float
    channels: list[Channel]
    notes: list[str] = field(default_factory=list)
    temperature: NDArray[np.float64] | None = None
    fmt: str = "csv"
    t0: float = 0.0


# ----------------------------------------------------------------------------- header parsing
def split_header(cell: str) -> tuple[str, str | None]:
    """``"gyro [deg/s]"`` or ``"Time (s)"`` -> (name, unit); the unit may itself hold parentheses."""
    cell = cell.strip()
    close = cell[-1:] if cell[-1:] in ")]" else None
    if close is None:
        return cell, None
    opening = "(" if close == ")" else "["
    depth = 0
    for i in range(len(cell) - 1, -1, -1):
        depth += (cell[i] == close) - (cell[i] == opening)
        if depth == 0:
            return cell[:i].strip(), cell[i + 1 : -1].strip() or None
    return cell, None


def time_column(
    names: list[str], hdr_units: list[str | None]
) -> tuple[int | None, float | None, bool]:
    """Index of the time column, its unit in s (None: not a time unit) and whether the unit was stated."""
    for i, nm in enumerate(names):
        m = _TIME_NAME.match(nm.strip())
        if m:
            unit = hdr_units[i] or m.group(1)
            if unit is None:
                return i, 1.0, False
            return i, TIME_UNITS.get(unit.lower()), True
    return None, None, False


def unit_of(name: str, hdr_unit: str | None, fmt: str) -> tuple[str | None, str | None]:
    """(quantity, unit) of a data column from its header unit, its name suffix or its format."""
    from gyrobench.sim import units

    unit = hdr_unit
    if unit is not None:
        unit = _RATE_ALIASES.get(unit, unit)
        if unit in units.RATE_UNITS:
            return "rate", unit
        if unit in ACCEL_UNITS:
            return "accel", unit
        return None, unit
    suffix = name.rsplit("_", 1)[-1].lower() if "_" in name else ""
    if suffix in _SUFFIX_UNIT:
        u = _SUFFIX_UNIT[suffix]
        return ("accel" if u in ACCEL_UNITS else "rate"), u
    if fmt in _SI_FORMATS:
        if _GYRO_NAME.search(name):
            return "rate", "rad/s"
        if _ACCEL_NAME.search(name):
            return "accel", "m/s^2"
    if _ACCEL_NAME.search(name):
        return "accel", None
    return None, None


def _format_of(names: list[str]) -> str:
    low = [n.lower().lstrip("#").strip() for n in names]
    if any(n.startswith("w_rs_s_") for n in low):
        return "euroc"
    if any(n.startswith("field.angular_velocity") for n in low):
        return "ros"
    if "omega_x" in low and low[:1] == ["timestamp"]:
        return "kalibr"
    return "csv"


def _sniff_delimiter(line: str) -> str:
    """The separator of a header or data row: the most frequent of , ; tab outside quotes (comma on a tie)."""
    counts = {d: 0 for d in (",", ";", "\t")}
    quoted = False
    for ch in line:
        if ch == '"':
            quoted = not quoted
        elif not quoted and ch in counts:
            counts[ch] += 1
    best = max(counts, key=lambda d: (counts[d], d == ","))
    return best if counts[best] else ","


def _cells(line: str, delim: str) -> list[str]:
    return [
        c.strip()
        for c in next(csv.reader([line], delimiter=delim, quotechar='"', skipinitialspace=True))
    ]


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


# ----------------------------------------------------------------------------- file access
def _read_text(path: Path) -> str:
    """The whole file as text (gzip when named .gz); one readable line on any read failure."""
    import gzip
    import zlib

    try:
        if path.suffix.lower() == ".gz":
            with gzip.open(path, "rb") as fh:
                raw = fh.read()
        else:
            raw = path.read_bytes()
    except (EOFError, gzip.BadGzipFile, zlib.error) as exc:
        raise ValueError(
            f"{str(path)!r} is not a complete gzip file ({exc}); re-export or re-download it"
        ) from None
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        raise ValueError(
            f"{str(path)!r} line {line}: byte {raw[exc.start : exc.start + 1]!r} is not UTF-8 text; "
            f"save the CSV as UTF-8"
        ) from None


# ----------------------------------------------------------------------------- the reader
def read_csv_log(
    path: Path,
    columns: list[str] | None = None,
    fs: float | None = None,
    unit: str | None = None,
    *,
    all_axes: bool = False,
    start: float | None = None,
    stop: float | None = None,
    temperature: str | None = None,
    decimal: str | None = None,
) -> Log:
    """Read rate/acceleration columns of a CSV IMU log.

    Parameters
    ----------
    path : Path
        .csv or .csv.gz.
    columns : list of str, optional
        Column names or 0-based indices (``--column``, repeatable). None: the only data
        column, or with ``all_axes`` every gyro and accelerometer column.
    fs : float, optional
        Sample rate [Hz]; required without a time column; with one, it must agree.
    unit : str, optional
        Unit of the named columns when the header has none (a rate unit of
        gyrobench.sim.units.RATE_UNITS or an acceleration unit of :data:`ACCEL_UNITS`).
    all_axes : bool
        Analyse every gyro (and accelerometer) column the header names.
    start, stop : float, optional
        Segment [s from the first sample] to keep.
    temperature : str, optional
        Name of a temperature column [degC] to return alongside.
    decimal : {".", ","}, optional
        Decimal mark of the numbers (``--decimal``); None: detected (a decimal comma when the
        first row of numbers reads as numbers only with "," as the decimal mark, separated
        by ";" or tabs), with a note saying so.

    Raises
    ------
    ValueError
        One line naming the file (and line and column where it applies).

    Notes
    -----
    The steps, each a function: the layout (:func:`_sniff`: first data row, separator,
    header), the columns (:func:`_header_of`, :func:`_selected_columns`), the time base
    check (:func:`_check_time_base`), the parsing (:func:`_parse_rows`), the time column
    (:func:`_time_base`: unit, uniform steps, fs) and the channels (:func:`_channel`).
    """
    lines = _read_text(path).splitlines()
    comma = _decimal_comma(lines, decimal)
    layout = _sniff(path, lines, comma)
    if comma:  # the data rows with decimal points (header lines keep their text)
        lines = lines[: layout.first_data] + [ln.replace(",", ".") for ln in lines[layout.first_data :]]
    hdr = _header_of(layout)
    _check_unique_names(path, hdr)
    idxs = _selected_columns(path, hdr, columns, all_axes)
    temp_idx = _index_of(path, hdr, temperature) if temperature is not None else None
    _check_time_base(path, hdr, fs)

    usecols = sorted({*idxs, *(i for i in (hdr.time_idx, temp_idx) if i is not None)})
    pos = {c: k for k, c in enumerate(usecols)}
    data = _parse_rows(path, lines, layout.first_data, layout.delim, layout.ncols, hdr.names, usecols)
    rows = data.shape[0]
    if rows < MIN_ROWS:
        raise ValueError(
            f"CSV {str(path)!r} has {rows} data row{'s' if rows != 1 else ''}; need at least "
            f"{MIN_ROWS} (and many more for an Allan analysis)"
        )
    notes: list[str] = []
    if comma and decimal is None:
        notes.append(
            f"decimal comma detected: numbers such as '0,5' separated by {_DELIM_NAMES[layout.delim]} read as 0.5 "
            f"(give --decimal . if the file means otherwise)"
        )
    t0 = 0.0
    if hdr.time_idx is not None:
        fs, t0 = _time_base(path, lines, layout, hdr, data[:, pos[hdr.time_idx]], fs, notes)
    if fs is None:  # pragma: no cover - excluded above (no time column or no time unit without --fs)
        raise ValueError(f"{str(path)!r}: give --fs (sample rate in Hz)")
    a, b = _segment(rows, float(fs), start, stop)
    if (a, b) != (0, rows):
        notes.append(f"segment {a / fs:g} s to {b / fs:g} s of {rows / fs:g} s (--start/--stop)")
    chans = [_channel(hdr, i, unit, data[a:b, pos[i]]) for i in idxs]
    temp = np.array(data[a:b, pos[temp_idx]]) if temp_idx is not None else None
    return Log(
        path=path,
        fs=float(fs),
        channels=chans,
        notes=notes,
        temperature=temp,
        fmt=hdr.fmt,
        t0=t0 + a / fs,
    )


# ----------------------------------------------------------------------------- layout and header
@dataclass(frozen=True)
class _Layout:
    """Where the data start, their separator and cell count, and the header row's cells (None: no header)."""

    first_data: int
    delim: str
    ncols: int
    header: list[str] | None


def _sniff(path: Path, lines: list[str], comma: bool = False) -> _Layout:
    """The first data row, the separator and the header of a CSV's lines.

    The header is the last non-empty line before the first data row (see
    :func:`_first_data_row`); a "#" line counts when it splits into as many cells as the first
    data row (EuRoC). With ``comma`` the numbers have decimal commas.
    """
    first_data, candidates = _first_data_row(lines, comma)
    if first_data is None:
        raise ValueError(f"CSV {str(path)!r} has 0 data rows; need at least {MIN_ROWS}")
    first = _decimal_point(lines[first_data].strip(), comma)
    delim = _sniff_delimiter(first)
    ncols = len(_cells(first, delim))
    header = _header_row(candidates, delim, ncols)
    if header is not None and len(header) != ncols:
        raise ValueError(
            f"{str(path)!r} line {first_data + 1}: {ncols} cells, but the header names {len(header)}"
        )
    return _Layout(first_data=first_data, delim=delim, ncols=ncols, header=header)


def _first_data_row(lines: list[str], comma: bool = False) -> tuple[int | None, list[str]]:
    """Index of the first data row (None: there is none) and the non-empty lines before it.

    A data row is a row of numbers, or a row that follows a header of as many cells and holds
    more numbers than text, at least two (a ``rostopic echo -p`` row with its text frame_id;
    text in an analysed column is refused when the rows are parsed). The lines before it come
    stripped, "#" lines as "#" + their text without the leading "#"s.
    """
    candidates: list[str] = []
    header: list[str] | None = None  # cells of the previous line when it reads as a header
    for i, raw in enumerate(lines):
        s = raw.strip()
        if not s:
            continue
        if s.startswith("#"):
            candidates.append("#" + s.lstrip("#").strip())
            header = None
            continue
        line = _decimal_point(s, comma)
        cells = _cells(line, _sniff_delimiter(line))
        numbers = sum(1 for c in cells if c != "" and _is_number(c))
        texts = sum(1 for c in cells if c != "" and not _is_number(c))
        if numbers and not texts:
            return i, candidates
        if header is not None and len(header) == len(cells) > 1 and numbers > texts and numbers >= 2:
            return i, candidates
        candidates.append(s)
        header = cells if numbers == 0 else None
    return None, candidates


def _decimal_point(line: str, comma: bool) -> str:
    """The line with decimal points for decimal commas (``comma``), else as it is."""
    return line.replace(",", ".") if comma else line


#: separators by name, for messages
_DELIM_NAMES = {",": "','", ";": "';'", "\t": "tabs"}
#: lines of a file looked at to detect a decimal comma
_DECIMAL_SNIFF_LINES = 200


def _decimal_comma(lines: list[str], decimal: str | None) -> bool:
    """Whether the numbers have decimal commas: ``decimal`` (``--decimal``), or detected.

    Detected from the first row that reads as numbers: with points ("0.5,1.2" or "0,1" as
    two columns) it is False; it is True when that row reads as numbers only with "," as
    the decimal mark, its cells separated by ";" or tabs ("0,5;1,2"). A single column of
    "0,5" is read as two columns unless ``decimal=","``.
    """
    if decimal is not None:
        if decimal not in (".", ","):
            raise ValueError(f"--decimal must be '.' or ','; got {decimal!r}")
        return decimal == ","
    for raw in lines[:_DECIMAL_SNIFF_LINES]:
        s = raw.strip()
        if not s or s.startswith("#"):
            continue
        if _all_numbers(s):
            return False
        if "," in s and ("\t" in s or ";" in s) and _all_numbers(s.replace(",", ".")):
            return True
    return False


def _all_numbers(line: str) -> bool:
    """Every non-empty cell of the line (its own separator) is a number, and one is at least."""
    cells = _cells(line, _sniff_delimiter(line))
    return all(_is_number(c) for c in cells if c != "") and any(c != "" for c in cells)


def _header_row(candidates: list[str], delim: str, ncols: int) -> list[str] | None:
    """The header cells: the last line before the data, or None (a "#" line that is not a header)."""
    if not candidates:
        return None
    s = candidates[-1]
    if s.startswith("#"):
        cells = _cells(s[1:], delim)
        return cells if len(cells) == ncols and len(cells) > 1 else None
    return _cells(s, delim)


@dataclass(frozen=True)
class _Header:
    """The columns of a log: raw header cells, names and units, format and the time column."""

    header: list[str] | None
    ncols: int
    names: list[str]
    units: list[str | None]
    fmt: str
    time_idx: int | None
    time_scale: float | None
    time_stated: bool

    @property
    def listing(self) -> list[str] | str:
        """The column names for a message (or how to name unnamed columns)."""
        return (
            self.names
            if self.names
            else f"{self.ncols} unnamed columns, no header: give an index 0..{self.ncols - 1}"
        )


def _header_of(layout: _Layout) -> _Header:
    """Names and units of the header cells, the log's format and its time column."""
    header, ncols = layout.header, layout.ncols
    names, hdr_units = (
        (list(t) for t in zip(*(split_header(h) for h in header), strict=True))
        if header
        else ([], [None] * ncols)
    )
    names = [n.lstrip("#").strip() if k == 0 else n for k, n in enumerate(names)]
    time_idx, time_scale, time_stated = (
        time_column(names, hdr_units) if names else (None, None, False)
    )
    return _Header(
        header=header,
        ncols=ncols,
        names=names,
        units=hdr_units,
        fmt=_format_of(names) if names else "csv",
        time_idx=time_idx,
        time_scale=time_scale,
        time_stated=time_stated,
    )


def _check_unique_names(path: Path, hdr: _Header) -> None:
    """Refuse a header that names a column twice (a name would choose only the first), in one line."""
    seen: dict[str, list[int]] = {}
    for i, nm in enumerate(hdr.names):
        if nm:
            seen.setdefault(nm, []).append(i)
    dups = [(nm, idx) for nm, idx in seen.items() if len(idx) > 1]
    if dups:
        which = "; ".join(f"{nm!r} (columns {', '.join(str(i) for i in idx)})" for nm, idx in dups)
        raise ValueError(
            f"the header of {str(path)!r} names {which} more than once: rename the duplicates so that each "
            f"column has its own name"
        )


# ----------------------------------------------------------------------------- column selection
def _index_of(path: Path, hdr: _Header, col: str) -> int:
    """Index of a ``--column`` (or ``--temperature``) given by name, header cell, unique
    case-insensitive name, or 0-based index."""
    names = hdr.names
    if col in names:
        return names.index(col)
    if hdr.header and col in hdr.header:
        return hdr.header.index(col)
    low = [nm.lower() for nm in names]
    if low.count(col.lower()) == 1:
        return low.index(col.lower())
    try:
        idx = int(col)
    except ValueError:
        raise ValueError(
            f"--column {col!r} is not in {str(path)!r}; columns: {hdr.listing}"
        ) from None
    if not 0 <= idx < hdr.ncols:
        raise ValueError(
            f"--column {idx} is out of range for {str(path)!r}: it has {hdr.ncols} columns (0..{hdr.ncols - 1})"
        )
    return idx


def _selected_columns(path: Path, hdr: _Header, columns: list[str] | None, all_axes: bool) -> list[int]:
    """Indices of the columns to analyse: the named ones, every gyro/accelerometer column, or the only one."""
    names, time_idx = hdr.names, hdr.time_idx
    if columns:
        idxs = [_index_of(path, hdr, c) for c in columns]
        dup = sorted({i for i in idxs if idxs.count(i) > 1})
        if dup:
            raise ValueError(f"--column names column {dup[0]} of {str(path)!r} twice")
    elif all_axes:
        idxs = [
            i
            for i, nm in enumerate(names)
            if i != time_idx
            and not _NOT_AXIS_NAME.search(nm)
            and unit_of(nm, hdr.units[i], hdr.fmt)[0] is not None
            and (_GYRO_NAME.search(nm) or _ACCEL_NAME.search(nm) or hdr.units[i])
        ]
        if not idxs:
            raise ValueError(
                f"--all-axes found no gyro or accelerometer column in {str(path)!r} (columns: {hdr.listing}); "
                f"name them with --column"
            )
    else:
        cand = [i for i in range(hdr.ncols) if i != time_idx]
        if len(cand) != 1:
            raise ValueError(
                f"{str(path)!r} has {len(cand)} data columns: name the rate column with --column "
                f"(columns: {hdr.listing}), or use --all-axes"
            )
        idxs = cand
    for i in idxs:
        if i == time_idx:
            raise ValueError(
                f"--column {names[i]!r} is the time column of {str(path)!r}; name the rate column"
            )
    return idxs


# ----------------------------------------------------------------------------- time column
def _check_time_base(path: Path, hdr: _Header, fs: float | None) -> None:
    """Without --fs the log needs a time column with a time unit."""
    if fs is None and hdr.time_idx is None:
        raise ValueError(
            f"{str(path)!r} has no time column (a header such as 'time [s]'): give --fs (sample rate in Hz)"
        )
    if fs is None and hdr.time_scale is None:
        raise ValueError(
            f"the time column {(hdr.header or hdr.names)[hdr.time_idx or 0]!r} of {str(path)!r} has no time unit "
            f"({'|'.join(TIME_UNITS)}): give --fs (sample rate in Hz)"
        )


def _time_unit(
    t_first: float, raw_step: float, tname: str, hdr: _Header
) -> tuple[float | None, str | None]:
    """Seconds per unit of the time column and a note on how it was chosen (None: stated in the header)."""
    time_scale = hdr.time_scale
    if hdr.time_stated or time_scale is None:
        return time_scale, None
    time_scale, note = _time_scale_from_magnitude(t_first, tname)
    if note is None and hdr.fmt in _SI_FORMATS:  # Kalibr, ROS and EuRoC write nanoseconds
        time_scale, note = (
            1e-9,
            f"time column {tname!r} read in ns (the {hdr.fmt} format's unit)",
        )
    elif note is None and raw_step >= 1.0:
        note = (
            f"time column {tname!r} has no unit and steps of {raw_step:.6g}: read as "
            f"seconds; give the unit in the header (e.g. 'time [ns]') if it is not"
        )
    return time_scale, note


def _time_base(
    path: Path,
    lines: list[str],
    layout: _Layout,
    hdr: _Header,
    t: NDArray[np.float64],
    fs: float | None,
    notes: list[str],
) -> tuple[float | None, float]:
    """The sample rate [Hz] and the first time [s] from the time column ``t`` (checked uniform).

    The rate is 1 / the median step; a given ``fs`` must agree with it to 1 %. How the time
    unit was chosen, when the header does not state it, is appended to ``notes``.
    """
    assert hdr.time_idx is not None
    t_first = float(t[0])
    if abs(t_first) > 2.0**53:  # integer epoch ns (ROS, Kalibr, EuRoC): float64 keeps 256 ns steps only
        t = _exact_time(lines, layout.first_data, layout.delim, hdr.time_idx, t)
    tname = hdr.header[hdr.time_idx] if hdr.header else str(hdr.time_idx)
    raw_step = float(np.median(np.diff(t)))  # in the column's own unit
    time_scale, note = _time_unit(t_first, raw_step, tname, hdr)
    if note:
        notes.append(note)
    _check_uniform(path, t, tname)
    step = raw_step * (time_scale or 1.0)
    if fs is None:
        fs = 1.0 / step
    elif time_scale is not None and abs(fs * step - 1.0) > 0.01:
        raise ValueError(
            f"--fs {fs:g} Hz disagrees with the time column {tname!r} of {str(path)!r}, whose median "
            f"step gives {1.0 / step:.6g} Hz; drop --fs or fix the time unit"
        )
    return fs, t_first * (time_scale or 1.0)


# ----------------------------------------------------------------------------- channels
def _channel(hdr: _Header, i: int, unit: str | None, x: NDArray[np.float64]) -> Channel:
    """Column ``i`` as a Channel in SI, its unit from ``--units``, the header, the name or the format."""
    label = hdr.names[i] if hdr.names else f"column {i}"
    q, u = unit_of(hdr.names[i], hdr.units[i], hdr.fmt) if hdr.names else (None, None)
    if unit is not None:
        u = _RATE_ALIASES.get(unit, unit)
        q = "accel" if u in ACCEL_UNITS else "rate"
    if u is None:
        from gyrobench.sim import units

        raise ValueError(
            f"the unit of column {label!r} is unknown: give --units "
            f"({'|'.join(list(units.RATE_UNITS) + list(ACCEL_UNITS))})"
        )
    return Channel(label=label, quantity=q or "rate", data=_to_si(x, q or "rate", u), unit=u)


def _to_si(x: NDArray[np.float64], quantity: str, unit: str) -> NDArray[np.float64]:
    if quantity == "accel":
        if unit not in ACCEL_UNITS:
            raise ValueError(
                f"acceleration unit must be one of {sorted(ACCEL_UNITS)}; got {unit!r}"
            )
        return x * ACCEL_UNITS[unit]
    from gyrobench.sim import units

    return np.asarray(units.rate_to_si(np.ascontiguousarray(x), unit), dtype=float)


def _parse_plain(body: str, delim: str, n_rows: int, ncols: int) -> NDArray | None:
    """Rows of plain numbers (no quotes, comments or blank lines) parsed in C; None if any cell is not.

    numpy.fromstring with a separator reads every cell with the same correctly rounded
    string-to-double conversion as numpy.loadtxt, about 10x faster; it stops (and warns) at the
    first cell that is not a number or is empty, and the count check catches a short or blank
    row, so any such file returns None and goes through loadtxt and its error messages. Only
    for "," and ";": numpy's separator matching would let a tab also match spaces in a cell.
    """
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            flat = np.fromstring(body.replace("\n", delim), dtype=float, sep=delim)
        except (ValueError, DeprecationWarning):
            return None
    if flat.size != n_rows * ncols:
        return None
    return flat.reshape(n_rows, ncols)


def _parse_rows(
    path: Path,
    lines: list[str],
    first: int,
    delim: str,
    ncols: int,
    names: list[str],
    usecols: list[int],
) -> NDArray:
    """The data rows' columns ``usecols`` as floats.

    Every row must have ``ncols`` cells: when the separators in the body do not add up to
    that, the rows are scanned and the first bad one is refused naming its line; a cell that
    is not a number is refused naming its line and column.
    """
    body = "\n".join(lines[first:])
    n_rows = len(lines) - first
    if body.count(delim) != n_rows * (
        ncols - 1
    ):  # some row (or a comment, blank or quoted cell) differs
        _check_row_lengths(path, lines, first, delim, ncols)
    elif delim in ",;" and '"' not in body and "#" not in body:  # (a tab separator would match any whitespace)
        fast = _parse_plain(body, delim, n_rows, ncols)
        if fast is not None:
            return fast[:, usecols]
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            return np.loadtxt(
                io.StringIO(body),
                delimiter=delim,
                comments="#",
                ndmin=2,
                quotechar='"',
                dtype=float,
                usecols=usecols,
            )
    except ValueError:
        pass
    _refuse_first_bad_cell(path, lines, first, delim, names, usecols)
    raise ValueError(f"{str(path)!r}: the data rows cannot be read as numbers")  # pragma: no cover


def _check_row_lengths(path: Path, lines: list[str], first: int, delim: str, ncols: int) -> None:
    """Refuse the first data row without ``ncols`` cells, naming its line."""
    for j, ln in enumerate(lines[first:]):
        s = ln.strip()
        if not s or s.startswith("#") or ln.count(delim) == ncols - 1:
            continue
        n = len(_cells(s, delim))
        if n != ncols:
            raise ValueError(
                f"{str(path)!r} line {first + j + 1}: {n} cells where the file has {ncols}; "
                f"a row with {'an extra' if n > ncols else 'a missing'} column is refused"
            )


def _refuse_first_bad_cell(
    path: Path, lines: list[str], first: int, delim: str, names: list[str], usecols: list[int]
) -> None:
    """Refuse the first cell of ``usecols`` that is not a number, naming its line and column."""
    for j, ln in enumerate(lines[first:]):
        s = ln.strip()
        if not s or s.startswith("#"):
            continue
        cells = _cells(s, delim)
        for k in usecols:
            if k < len(cells) and not _is_number(cells[k]):
                col = names[k] if k < len(names) else str(k)
                raise ValueError(
                    f"{str(path)!r} line {first + j + 1}, column {col!r}: {cells[k]!r} is not a number"
                )


def _exact_time(
    lines: list[str], first: int, delim: str, idx: int, t: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Integer timestamps re-read as int64, relative to the first (exact steps); ``t - t[0]`` otherwise."""
    try:
        ti = np.loadtxt(
            io.StringIO("\n".join(lines[first:])),
            delimiter=delim,
            comments="#",
            usecols=[idx],
            dtype=np.int64,
            quotechar='"',
            ndmin=1,
        )
    except (ValueError, OverflowError):
        return t - t[0]
    return (ti - ti[0]).astype(np.float64)


def _time_scale_from_magnitude(first: float, name: str) -> tuple[float, str | None]:
    """Unit of a time column without one: Unix epoch times by the magnitude of the first, else seconds."""
    t0 = abs(first)
    if t0 < 1e8:
        return 1.0, None
    # 1e8 s = 1973; the present is ~1.7e9 s, ~1.7e12 ms, ~1.7e15 us, ~1.7e18 ns
    for scale, unit in ((1e-9, "ns"), (1e-6, "us"), (1e-3, "ms"), (1.0, "s")):
        if 1e8 <= t0 * scale < 1e11:
            return scale, (
                f"time column {name!r} has no unit; its values ({t0:.4g}) are Unix epoch times in "
                f"{unit} by their magnitude"
            )
    return 1.0, None


def _check_uniform(path: Path, t: NDArray[np.float64], tname: str) -> None:
    dt = np.diff(t)
    bad = np.flatnonzero(~(dt > 0))
    if len(bad):
        i = int(bad[0])
        raise ValueError(
            f"time column {tname!r} of {str(path)!r} must increase strictly: data row {i + 2} "
            f"has {t[i + 1]:.12g} after {t[i]:.12g} in row {i + 1}"
        )
    step = float(np.median(dt))
    gaps = np.flatnonzero(dt > GAP_FACTOR * step)
    if len(gaps):
        i = int(gaps[0])
        raise ValueError(
            f"time column {tname!r} of {str(path)!r} has a gap before data row {i + 2}: step {dt[i]:.6g} "
            f"({t[i]:.12g} -> {t[i + 1]:.12g}) is {dt[i] / step:.3g} x the median step {step:.6g} "
            f"({len(gaps)} such gap{'s' if len(gaps) > 1 else ''}); Allan analysis needs uniform sampling: "
            f"analyse the segments separately"
        )


def _segment(rows: int, fs: float, start: float | None, stop: float | None) -> tuple[int, int]:
    """Sample range of the --start/--stop segment [s from the first sample]."""
    for name, v in (("--start", start), ("--stop", stop)):
        if v is not None and not (math.isfinite(v) and v >= 0):
            raise ValueError(f"{name} must be a finite time >= 0 s; got {v!r}")
    a = 0 if start is None else int(math.ceil(start * fs - 1e-9))
    b = rows if stop is None else min(rows, int(math.floor(stop * fs + 1e-9)))
    if b - a < MIN_ROWS:
        raise ValueError(
            f"--start/--stop keep {max(b - a, 0)} samples of the {rows / fs:g} s record; need at least {MIN_ROWS}"
        )
    return a, b
