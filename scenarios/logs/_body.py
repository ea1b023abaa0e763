"""The body of a CSV log: the file's text (gzip too) and its data rows parsed as numbers."""

from __future__ import annotations

import io
import warnings
from pathlib import Path

import numpy as np
from gyrobench.scenarios.logs._names import _cells, _is_number
from numpy.typing import NDArray


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
