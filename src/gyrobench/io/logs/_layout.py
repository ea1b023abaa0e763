"""Layout of a CSV log: the first data row, the separator, decimal commas, the header and the selected columns."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from gyrobench.io.logs._names import (
    _ISO,
    _NOT_AXIS_NAME,
    MIN_ROWS,
    _cells,
    _format_of,
    _is_number,
    _sniff_delimiter,
    not_a_number_cause,
    space_separated,
    split_header,
    time_column,
    unit_of,
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
        _refuse_text_times(path, lines)
        _refuse_lookalike_numbers(path, lines)
        raise ValueError(f"CSV {str(path)!r} has 0 data rows; need at least {MIN_ROWS}")
    first = _decimal_point(lines[first_data].strip(), comma)
    delim = _sniff_delimiter(first)
    ncols = len(_cells(first, delim))
    header = _header_row(candidates, delim, ncols)
    _check_names(path, header, first_data)
    if header is not None and len(header) != ncols:
        raise ValueError(
            f"{str(path)!r} line {first_data + 1}: {ncols} cells, but the header names {len(header)}"
        )
    return _Layout(first_data=first_data, delim=delim, ncols=ncols, header=header)


#: longest header cell (column name) [characters]: real logs name columns in tens of characters
MAX_NAME_CHARS = 1000


def _refuse_lookalike_numbers(path: Path, lines: list[str]) -> None:
    """A file with no data row whose rows hold numbers in a form not read (space-separated columns, a
    Unicode minus, hex floats, thousand separators): say which, naming the line and the cell."""
    for i, raw in enumerate(lines[:_DECIMAL_SNIFF_LINES]):
        s = raw.strip()
        if not s or s.startswith("#"):
            continue
        if space_separated(s):
            raise ValueError(
                f"{str(path)!r} line {i + 1}: the columns are separated by spaces ({s[:40]!r}); gyrobench reads "
                "',', ';' or tab separated columns: convert the spaces (e.g. tr -s ' ' ',' < in > out.csv)"
            )
        for delim in dict.fromkeys((_sniff_delimiter(s), ";", "\t", ",")):  # "1,234.5;2" splits on ';'
            for cell in _cells(s, delim):
                why = not_a_number_cause(cell)
                if why:
                    raise ValueError(f"{str(path)!r} line {i + 1}: {cell[:40]!r} is not a number: {why}")


def _check_names(path: Path, header: list[str] | None, line: int) -> None:
    """Refuse a header cell longer than :data:`MAX_NAME_CHARS`, in one line."""
    for k, cell in enumerate(header or []):
        if len(cell) > MAX_NAME_CHARS:
            raise ValueError(
                f"{str(path)!r} line {line}: the name of column {k} has {len(cell)} characters (at most "
                f"{MAX_NAME_CHARS}): not a log's header"
            )


def _refuse_text_times(path: Path, lines: list[str]) -> None:
    """A file with no data row whose time column holds text after its header: say so, naming the cell."""
    rows = [(i, ln.strip()) for i, ln in enumerate(lines[:_DECIMAL_SNIFF_LINES]) if ln.strip()]
    for (_, head), (j, row) in zip(rows, rows[1:], strict=False):
        delim = _sniff_delimiter(head)
        names = [split_header(c)[0] for c in _cells(head.lstrip("#"), delim)]
        idx = time_column(names, [None] * len(names))[0]
        cells = _cells(row, delim)
        cell = cells[idx] if idx is not None and len(cells) == len(names) else "0"
        if not (_is_number(cell) or _is_number(cell.replace(",", ".")) or _ISO.match(cell)):
            why = not_a_number_cause(cell)
            raise ValueError(
                f"time column {names[idx or 0]!r} of {str(path)!r} line {j + 1}: {cell[:40]!r} is "
                + (f"not a number: {why}" if why else "neither a number nor an ISO-8601 date-time "
                   "(YYYY-MM-DDThh:mm:ss[.fff][Z]); convert the times to seconds or to ISO-8601")
            )


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
        numbers = sum(1 for c in cells if c != "" and (_is_number(c) or _ISO.match(c) is not None))
        texts = sum(1 for c in cells if c != "" and not (_is_number(c) or _ISO.match(c) is not None))
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


def _schema_outputs(names: list[str]) -> list[str]:
    """The outputs of a CSV written by gyrobench (docs/recording.md): ``output`` beside ``truth/true_rate``, or
    each ``c`` beside ``truth/c.true`` (a triad); empty for any other header."""
    if "output" in names and "truth/true_rate" in names:
        return ["output"]
    return [n for n in names if f"truth/{n}.true" in names]


def _selected_columns(path: Path, hdr: _Header, columns: list[str] | None, all_axes: bool) -> list[int]:
    """Indices of the columns to analyse: the named ones, every gyro/accelerometer column, a gyrobench
    recording's outputs, or the only one."""
    names, time_idx = hdr.names, hdr.time_idx
    if columns:
        idxs = [_index_of(path, hdr, c) for c in columns]
        dup = sorted({i for i in idxs if idxs.count(i) > 1})
        if dup:
            raise ValueError(f"--column names column {dup[0]} of {str(path)!r} twice")
    elif all_axes:
        from gyrobench.io.logs._kinds import axis_like, kind_by_name

        idxs = [
            i
            for i, nm in enumerate(names)
            if i != time_idx
            and not _NOT_AXIS_NAME.search(nm)
            and (unit_of(nm, hdr.units[i], hdr.fmt)[0] is not None or kind_by_name(nm) is not None
                 or (hdr.fmt == "csv" and axis_like(nm)))
        ]
        if not idxs:
            raise ValueError(
                f"--all-axes found no gyro or accelerometer column in {str(path)!r} (columns: {hdr.listing}); "
                f"name them with --column"
            )
    elif outputs := _schema_outputs(names):
        idxs = [names.index(n) for n in outputs]
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
