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

from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from gyrobench.io.logs._body import _body_of, _head_lines, _parse_rows, _read_text
from gyrobench.io.logs._body import _parse_plain as _parse_plain  # (tests/analysis/test_allan_fast_paths.py)
from gyrobench.io.logs._kinds import gravity_like, kind_by_name, parse_units
from gyrobench.io.logs._layout import (
    _DELIM_NAMES,
    _check_unique_names,
    _decimal_comma,
    _Header,
    _header_of,
    _index_of,
    _Layout,
    _selected_columns,
    _sniff,
)
from gyrobench.io.logs._names import (
    ACCEL_UNITS,
    GAP_FACTOR,
    MIN_ROWS,
    TIME_UNITS,
    _cells,
    _is_number,
    split_header,
    time_column,
    unit_of,
)
from gyrobench.io.logs._time import (
    GAP_CHOICES,
    UNIFORM_TOLERANCE,
    TimeGrid,
    _check_time_base,
    _fill,
    _iso_times,
    _pieces,
    _segment,
    _time_base,
)

__all__ = [
    "Channel",
    "Log",
    "read_csv_log",
    "ACCEL_UNITS",
    "TIME_UNITS",
    "GAP_FACTOR",
    "MIN_ROWS",
    "GAP_CHOICES",
    "UNIFORM_TOLERANCE",
    "unit_of",
    "split_header",
    "time_column",
]


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
    #: ``--gaps split``: sample ranges [a, b) of the channels' contiguous pieces (None: no gap)
    pieces: tuple[tuple[int, int], ...] | None = None



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
    gaps: str = "refuse",
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
        ``--units``: one unit (a rate unit of gyrobench.base.units.RATE_UNITS or an acceleration
        unit of :data:`ACCEL_UNITS`), applied to the columns of its kind (and to columns of no
        kind, refused if they read gravity), or units per kind, ``gyro=deg/s,accel=g``. A
        column's kind comes from its header unit, name suffix or name (``gyro``, ``omega``,
        ``acc``, ``ax`` ...); it overrides the header's unit of that kind.
    all_axes : bool
        Analyse every gyro (and accelerometer) column the header names, and every column of
        no kind whose name ends in an axis letter (``x``, ``imu.z``): it needs a unit from
        ``--units`` or is refused naming it, never dropped; other columns are listed in a note.
    start, stop : float, optional
        Segment [s from the first sample] to keep.
    temperature : str, optional
        Name of a temperature column [degC] to return alongside.
    decimal : {".", ","}, optional
        Decimal mark of the numbers (``--decimal``); None: detected (a decimal comma when the
        first row of numbers reads as numbers only with "," as the decimal mark, separated
        by ";" or tabs), with a note saying so.
    gaps : {"refuse", "fill", "split"}
        Missing samples in the time column (``--gaps``): refused in one line naming the first
        gap (default); filled by linear interpolation between the neighbouring samples (the
        count in ``notes``); or kept as gaps, ``Log.pieces`` giving the contiguous runs for the
        gap-aware Allan variance (:func:`gyrobench.analysis.allan.allan_deviation_gaps`).
        ``--start/--stop`` count time on the grid, gaps included.

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
    text = _read_text(path)
    head, complete = _head_lines(text)
    comma = _decimal_comma(head, decimal)
    layout = _sniff(path, head, comma) if complete else _sniff_long_head(path, text, head, comma)
    body = _body_of(text, head, layout.first_data)
    del text
    if comma:  # the data rows with decimal points (header lines keep their text)
        body = body.replace(",", ".")
    hdr = _header_of(layout)
    _check_unique_names(path, hdr)
    idxs = _selected_columns(path, hdr, columns, all_axes)
    temp_idx = _index_of(path, hdr, temperature) if temperature is not None else None
    _check_time_base(path, hdr, fs)

    iso = hdr.time_idx is not None and not _is_number(_first_cell(body, layout.delim, hdr.time_idx))
    numeric = (i for i in (hdr.time_idx, temp_idx) if i is not None and not (iso and i == hdr.time_idx))
    usecols = sorted({*idxs, *numeric})
    pos = {c: k for k, c in enumerate(usecols)}
    data = _parse_rows(path, body, layout.first_data, layout.delim, layout.ncols, hdr.names, usecols)
    notes: list[str] = []
    iso_t0 = 0.0
    if iso:  # the time column holds text: ISO-8601 date-times, or refused saying what it holds
        assert hdr.time_idx is not None
        tname = hdr.header[hdr.time_idx] if hdr.header else str(hdr.time_idx)
        t_iso, iso_t0 = _iso_times(path, body, layout.delim, hdr.time_idx, layout.first_data, tname, notes)
        if len(t_iso) != data.shape[0]:  # pragma: no cover - both skip the same blank and comment lines
            raise ValueError(f"{str(path)!r}: {len(t_iso)} times for {data.shape[0]} data rows")
        pos[hdr.time_idx] = data.shape[1]
        data = np.column_stack([data, t_iso])
        hdr = replace(hdr, time_scale=1.0, time_stated=True)
    rows = data.shape[0]
    if rows < MIN_ROWS:
        raise ValueError(
            f"CSV {str(path)!r} has {rows} data row{'s' if rows != 1 else ''}; need at least "
            f"{MIN_ROWS} (and many more for an Allan analysis)"
        )
    if comma and decimal is None:
        notes.append(
            f"decimal comma detected: numbers such as '0,5' separated by {_DELIM_NAMES[layout.delim]} read as 0.5 "
            f"(give --decimal . if the file means otherwise)"
        )
    t0, grid = 0.0, None
    if hdr.time_idx is not None:
        fs, t0, grid = _time_base(path, body, layout, hdr, data[:, pos[hdr.time_idx]], fs, notes, gaps)
    if fs is None:  # pragma: no cover - excluded above (no time column or no time unit without --fs)
        raise ValueError(f"{str(path)!r}: give --fs (sample rate in Hz)")
    data, index = _apply_gaps(data, grid, gaps, notes)
    n_grid = int(index[-1]) + 1
    a, b = _segment(n_grid, float(fs), start, stop)
    if (a, b) != (0, n_grid):
        notes.append(f"segment {a / fs:g} s to {b / fs:g} s of {n_grid / fs:g} s (--start/--stop)")
    keep = slice(*np.searchsorted(index, [a, b]))
    data, index = data[keep], index[keep]
    runs = _pieces(index)
    pieces = runs if len(runs) > 1 else None
    if pieces is not None and temp_idx is not None:
        raise ValueError("--temperature is not available with --gaps split: give --gaps fill, or analyse a segment "
                         "without gaps (--start/--stop)")
    given = parse_units(unit)
    chans = [_channel(hdr, i, given, data[:, pos[i]]) for i in idxs]
    temp = np.array(data[:, pos[temp_idx]]) if temp_idx is not None else None
    t0 += iso_t0
    return Log(
        path=path,
        fs=float(fs),
        channels=chans,
        notes=notes,
        temperature=temp,
        fmt=hdr.fmt,
        t0=t0 + a / fs,
        pieces=pieces,
    )


def _first_cell(body: str, delim: str, idx: int) -> str:
    """Cell ``idx`` of the first data row (the first line of ``body``)."""
    cells = _cells(body[: body.find("\n")] if "\n" in body else body, delim)
    return cells[idx] if idx < len(cells) else ""


def _sniff_long_head(path: Path, text: str, head: list[str], comma: bool) -> _Layout:
    """:func:`_sniff` on the first lines, or on all of them when no data row is among the first."""
    try:
        return _sniff(path, head, comma)
    except ValueError:
        return _sniff(path, text.split("\n"), comma)


def _apply_gaps(
    data: NDArray[np.float64], grid: TimeGrid | None, gaps: str, notes: list[str]
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """The rows with the gaps filled (``fill``) or kept (``split``), and each row's sample number on the grid."""
    if grid is None or not len(grid.gaps):
        return data, np.arange(data.shape[0], dtype=np.int64)
    n_miss, n_gaps = int(grid.missing.sum()), len(grid.gaps)
    where = f"{n_gaps} gap{'s' if n_gaps > 1 else ''}, the first after data row {int(grid.gaps[0]) + 1}"
    if gaps == "fill":
        notes.append(f"--gaps fill: {n_miss} missing sample{'s' if n_miss > 1 else ''} in {where} filled by linear "
                     f"interpolation ({n_miss / grid.n_grid:.3g} of the record)")
        return _fill(data, grid), np.arange(grid.n_grid, dtype=np.int64)
    notes.append(f"--gaps split: {n_miss} missing sample{'s' if n_miss > 1 else ''} in {where}; the Allan variance "
                 f"pools the {n_gaps + 1} contiguous pieces")
    return data, grid.index



# ----------------------------------------------------------------------------- channels
def _channel(hdr: _Header, i: int, given: dict[str, str], x: NDArray[np.float64]) -> Channel:
    """Column ``i`` as a Channel in SI: its kind (gyro "rate" or "accel") from its header unit, its name
    suffix, its name or its format, else from ``--units``; its unit from ``--units`` for that kind, the
    header, the name suffix or the format.

    A column whose kind only a bare ``--units`` rate unit gives is refused when it reads gravity
    (:func:`gravity_like`): an accelerometer axis is never analysed as a gyro.
    """
    from gyrobench.base import units

    label = hdr.names[i] if hdr.names else f"column {i}"
    name = hdr.names[i] if hdr.names else ""
    q, u = unit_of(name, hdr.units[i], hdr.fmt) if hdr.names else (None, None)
    q = q or kind_by_name(name)
    kinds = [k for k in ("rate", "accel") if k in given]
    if q is None and len(kinds) == 2:
        raise ValueError(
            f"column {label!r} has no kind (its name and header say neither gyro nor accelerometer), so --units "
            f"gyro=...,accel=... cannot tell which applies: give its unit in the header (e.g. '{label} [deg/s]') "
            f"or analyse it alone with one unit"
        )
    typed_by_units = q is None and len(kinds) == 1
    q = q or (kinds[0] if kinds else None)
    if q in given:
        u = given[q]
    if u is None:
        raise ValueError(
            f"the unit of column {label!r} is unknown: give --units "
            f"({'|'.join(list(units.RATE_UNITS) + list(ACCEL_UNITS))}, or gyro=UNIT,accel=UNIT)"
        )
    if typed_by_units and q == "rate" and "bare" in given and (g := gravity_like(x)) is not None:
        raise ValueError(
            f"column {label!r} reads {float(np.mean(x)):.4g} on average with little scatter: gravity on an "
            f"accelerometer axis in {g}, not a gyro at rest; give the kinds (e.g. --units gyro={u},accel={g}, "
            f"with kinds in the column names), or --units gyro={u} if it is a gyro"
        )
    return Channel(label=label, quantity=q or "rate", data=_to_si(x, q or "rate", u), unit=u)


def _to_si(x: NDArray[np.float64], quantity: str, unit: str) -> NDArray[np.float64]:
    if quantity == "accel":
        if unit not in ACCEL_UNITS:
            raise ValueError(
                f"acceleration unit must be one of {sorted(ACCEL_UNITS)}; got {unit!r}"
            )
        return x * ACCEL_UNITS[unit]
    from gyrobench.base import units

    return np.asarray(units.rate_to_si(np.ascontiguousarray(x), unit), dtype=float)
