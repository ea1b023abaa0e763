"""The body of a CSV log: the file's text (gzip too) and its data rows parsed as numbers."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from gyrobench.io.logs._names import _cells, _is_number, not_a_number_cause

# ----------------------------------------------------------------------------- file access
#: bytes decompressed at a time from a .gz file, its size counted against the memory limit after each
_GZIP_BLOCK = 1 << 20
#: bytes at the top of a file sampled for its cells per byte (the memory estimate)
_SAMPLE_BYTES = 1 << 16
#: lines split off the top of the text to find the header and the first data row (the rest stays one string)
HEAD_LINES = 1000


def _read_text(path: Path) -> str:
    """The whole file as text (gzip when named .gz), line ends made "\\n"; one readable line on any read failure.

    The memory the read will take (:func:`gyrobench.base.memory.csv_read_bytes`) is checked
    before the file is read, from its size, or for a .gz file after every block decompressed:
    a gzip bomb is refused when its decompressed size so far would not fit, never allocated whole.
    """
    import gzip
    import zlib

    try:
        raw = _read_gzip(path) if path.suffix.lower() == ".gz" else _read_plain(path)
    except (EOFError, gzip.BadGzipFile, zlib.error) as exc:
        raise ValueError(
            f"{str(path)!r} is not a complete gzip file ({exc}); re-export or re-download it"
        ) from None
    _check_line_length(path, raw)  # before the text and its lines are made
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        raise ValueError(
            f"{str(path)!r} line {line}: byte {raw[exc.start : exc.start + 1]!r} is not UTF-8 text; "
            f"save the CSV as UTF-8"
        ) from None
    del raw
    if "\r" in text:
        text = text.replace("\r\n", "\n").replace("\r", "\n")
    return text


#: longest line of a log [bytes]: thousands of columns fit; every cell stays below csv's field limit (131072)
MAX_LINE_BYTES = 100_000
#: bytes scanned at a time for line ends (:func:`_check_line_length`)
_SCAN_BLOCK = 1 << 24


def _longest_line(raw: bytes | bytearray) -> tuple[int, int]:
    """(length [bytes], 1-based number) of the longest line of ``raw``, scanned in blocks (no list of lines)."""
    a = np.frombuffer(raw, dtype=np.uint8)
    best, best_line, prev, seen = 0, 1, -1, 0
    for s in range(0, len(a), _SCAN_BLOCK):
        nl = np.flatnonzero(a[s : s + _SCAN_BLOCK] == 10) + s
        if nl.size:
            lengths = np.diff(nl, prepend=prev) - 1
            k = int(np.argmax(lengths))
            if lengths[k] > best:
                best, best_line = int(lengths[k]), seen + k + 1
            seen += nl.size
            prev = int(nl[-1])
    if len(a) - prev - 1 > best:
        best, best_line = len(a) - prev - 1, seen + 1
    return best, best_line


def _check_line_length(path: Path, raw: bytes | bytearray) -> None:
    """Refuse a file with a line longer than :data:`MAX_LINE_BYTES`, in one line naming it."""
    n, line = _longest_line(raw)
    if n > MAX_LINE_BYTES:
        raise ValueError(
            f"{str(path)!r} line {line} has {n} bytes (a log's line has at most {MAX_LINE_BYTES}): not a CSV log "
            "(a binary file, or line ends missing?)"
        )


def _cells_per_byte(sample: bytes) -> float:
    """Cells per byte of a sample of CSV text: its separators and line ends per byte."""
    n = sum(sample.count(c) for c in (b",", b";", b"\t", b"\n")) + 1
    return n / max(len(sample), 1)


def _check_read_memory(path: Path, n_bytes: int, sample: bytes, *, so_far: bool = False) -> None:
    from gyrobench.base import memory

    memory.check_memory(
        memory.csv_read_bytes(n_bytes, _cells_per_byte(sample)),
        f"reading {str(path)!r} ({'more than ' if so_far else ''}{memory.format_bytes(n_bytes)} of text)",
        hint="split the file (or raise GYROBENCH_MEMORY_LIMIT if the machine has the memory)",
    )


def _read_plain(path: Path) -> bytes:
    with path.open("rb") as fh:
        _check_read_memory(path, path.stat().st_size, fh.read(_SAMPLE_BYTES))
        fh.seek(0)
        return fh.read()


def _read_gzip(path: Path) -> bytearray:
    """The decompressed bytes, counted block by block against the memory limit."""
    import gzip

    out = bytearray()
    with gzip.open(path, "rb") as fh:
        while block := fh.read(_GZIP_BLOCK):
            out += block
            _check_read_memory(path, len(out), bytes(out[:_SAMPLE_BYTES]), so_far=True)
    return out


def _head_lines(text: str) -> tuple[list[str], bool]:
    """The first :data:`HEAD_LINES` lines of ``text`` and whether they are all of it.

    As ``text.split("\n", HEAD_LINES)`` without making its last part, the rest of the text
    (a copy of the whole body: ~30 ms on a 28 MB file, as much again in fresh pages).
    """
    pos = -1
    for _ in range(HEAD_LINES):
        pos = text.find("\n", pos + 1)
        if pos < 0:
            return text.split("\n"), True
    return text[:pos].split("\n"), False


def _body_of(text: str, head: list[str], first: int) -> str:
    """The text from line ``first`` (0-based, within ``head``) on, without its trailing line ends.

    One slice: the trailing "\n" are left out of it rather than stripped from a copy.
    """
    start = sum(len(ln) + 1 for ln in head[:first])
    end = len(text)
    while end > start and text[end - 1] == "\n":
        end -= 1
    return text[start:end]


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
    body: str,
    first: int,
    delim: str,
    ncols: int,
    names: list[str],
    usecols: list[int],
) -> NDArray:
    """The data rows' columns ``usecols`` as floats; ``body`` is the text from the first data row (line ``first``).

    Every row must have ``ncols`` cells: when the separators in the body do not add up to
    that, the rows are scanned and the first bad one is refused naming its line; a cell that
    is not a number is refused naming its line and column. Plain rows of numbers are parsed
    in C: by numpy.fromstring when every column is wanted, by numpy.loadtxt (which converts
    only ``usecols``, from a list of the lines) otherwise; both use the correctly rounded
    string-to-double conversion.
    """
    body = body.rstrip("\n")
    n_rows = body.count("\n") + 1
    plain = False
    if body.count(delim) != n_rows * (ncols - 1):  # some row (or a comment, blank or quoted cell) differs
        _check_row_lengths(path, body.split("\n"), first, delim, ncols)
    elif delim in ",;" and '"' not in body and "#" not in body:  # (a tab separator would match any whitespace)
        plain = True
        if len(usecols) == ncols:
            fast = _parse_plain(body, delim, n_rows, ncols)
            if fast is not None:
                return fast[:, usecols]
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            return np.loadtxt(  # a list of lines: numpy iterates it in C (a StringIO is 3-4x slower and larger)
                body.split("\n"),
                delimiter=delim,
                comments=None if plain else "#",  # (numpy strips comments line by line in Python)
                ndmin=2,
                quotechar='"',
                dtype=float,
                usecols=usecols,
            )
    except ValueError:
        pass
    _refuse_first_bad_cell(path, body.split("\n"), first, delim, names, usecols)
    raise ValueError(f"{str(path)!r}: the data rows cannot be read as numbers")  # pragma: no cover


def _check_row_lengths(path: Path, rows: list[str], first: int, delim: str, ncols: int) -> None:
    """Refuse the first data row (``rows`` start at line ``first``) without ``ncols`` cells, naming its line."""
    for j, ln in enumerate(rows):
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
    path: Path, rows: list[str], first: int, delim: str, names: list[str], usecols: list[int]
) -> None:
    """Refuse the first cell of ``usecols`` that is not a number (``rows`` start at line ``first``)."""
    for j, ln in enumerate(rows):
        s = ln.strip()
        if not s or s.startswith("#"):
            continue
        cells = _cells(s, delim)
        for k in usecols:
            if k < len(cells) and not _is_number(cells[k]):
                col = names[k] if k < len(names) else str(k)
                why = not_a_number_cause(cells[k])
                raise ValueError(
                    f"{str(path)!r} line {first + j + 1}, column {col!r}: {cells[k][:40]!r} is not a number"
                    + (f": {why}" if why else "")
                )
