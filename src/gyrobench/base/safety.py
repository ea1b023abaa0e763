"""Output safety: the one rule every gyrobench command applies to what it reads and writes.

Every verb names its inputs and its outputs and calls :func:`check_outputs` before any work
(before simulating, analysing, connecting to a cluster or writing a byte). The rule:

1. **No output is an input.** An output may not resolve to any input of the same command:
   not by name, not through symbolic links or ``..`` (:func:`os.path.realpath`), not as a
   hard link (same device and inode). Two outputs of one command are never the same file
   either, and no input may lie inside a folder an output replaces as a whole. ``--force``
   does not lift this.
2. **Only gyrobench's own files are replaced.** An existing file target is replaced only if
   gyrobench wrote it, recognised by its format's marker (:func:`written_by_gyrobench`):

   ========================= ===================================================================
   format                    marker
   ========================= ===================================================================
   HDF5 (``.h5``, ``.hdf5``) root attribute ``format`` starting ``gyrobench-``
   JSON (``.json``)          first key ``"format"`` with a value starting ``gyrobench-``
   CSV, YAML, TOML           a first line ``# ...`` naming gyrobench (:func:`comment_marker`)
   PNG                       a ``Software`` text chunk starting ``gyrobench`` (:data:`PNG_METADATA`)
   ========================= ===================================================================

   Anything else (a foreign HDF5, a text file named ``.h5``, a user's ``notes.json``, an
   empty file) is replaced only with ``force`` (``--force``).
3. **Suffixes match the verb**: each output names the suffixes it takes (``--save-baseline``
   ``.json``, ``--kalibr`` ``.yaml``, ``-o`` ``.h5`` or ``.csv``, ``--plot`` ``.png``).
4. **Folders**: files are written only into a folder gyrobench made (it holds
   :data:`FOLDER_MARKER`, written by :func:`mark_folder`, or only files gyrobench wrote), an
   empty one or a new one (or any folder with ``force``). A report folder replaced as a whole (``kind="report"``) must
   be new, empty or an earlier report whose manifest (:data:`REPORT_MARKER`) names every
   file it holds unchanged; with ``force`` an earlier report whose files were edited or
   added to may be replaced, a folder without a manifest never.
5. **Databases**: an existing ``--db`` must be an SQLite file gyrobench made (its
   ``application_id`` is :data:`SQLITE_APPLICATION_ID`, or it holds only gyrobench's
   tables); a foreign SQLite file, or a file that is not SQLite, is refused before anything
   is written to it, ``force`` or not.

A refusal is one line naming the paths (an :class:`OutputRefused`, a ``ValueError``: exit 2).
:func:`check_input` refuses an input that is not a regular file (a folder, a FIFO, a device)
in one line, before anything opens it. :func:`escape_controls` makes text from files safe for
a terminal and a report.

This module imports nothing else of gyrobench.
"""

from __future__ import annotations

import os
import re
import secrets
import stat
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

__all__ = [
    "FOLDER_MARKER",
    "PNG_METADATA",
    "REPORT_MARKER",
    "SQLITE_APPLICATION_ID",
    "InputRefused",
    "Output",
    "OutputRefused",
    "check_database",
    "check_input",
    "check_outputs",
    "comment_marker",
    "escape_controls",
    "folder_files",
    "mark_folder",
    "report_manifest",
    "same_file",
    "written_by_gyrobench",
]

#: the file that marks a folder gyrobench made (``simulate SCENARIO --out``)
FOLDER_MARKER = ".gyrobench-folder"
#: the manifest of a report folder (JSON naming each file the report wrote with its SHA-256)
REPORT_MARKER = ".gyrobench-report"
#: SQLite ``PRAGMA application_id`` of gyrobench's databases (the bytes "gyb1")
SQLITE_APPLICATION_ID = 0x67796231
#: ``savefig(metadata=...)`` of every PNG gyrobench writes: the marker :func:`written_by_gyrobench` reads
PNG_METADATA = {"Software": "gyrobench"}

#: bytes read from the top of a file to find its marker
_HEAD_BYTES = 4096
_HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"
_PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
_SQLITE_SIGNATURE = b"SQLite format 3\x00"
_JSON_MARKER = re.compile(rb'\A\s*\{\s*"format"\s*:\s*"gyrobench-')
_SUFFIX_FORMAT = {".h5": "hdf5", ".hdf5": "hdf5", ".csv": "comment", ".yaml": "comment", ".yml": "comment",
                  ".toml": "comment",
                  ".json": "json", ".png": "png"}
_FORMAT_NAME = {"hdf5": "HDF5 root attribute format='gyrobench-...'", "comment": "first line '# ... gyrobench ...'",
                "json": "JSON key \"format\": \"gyrobench-...\"", "png": "PNG text chunk Software='gyrobench'"}


class OutputRefused(ValueError):
    """An output that is an input, or would replace a file gyrobench did not write: one line, exit 2."""


class InputRefused(ValueError):
    """An input that is not a regular file (a folder, a FIFO, a device, a socket): one line, exit 2."""


@dataclass(frozen=True, slots=True)
class Output:
    """One output of a command.

    Attributes
    ----------
    path : Path
        The output as given.
    flag : str
        How the user named it, for messages (``"-o"``, ``"--plot"``, ``"--db"``).
    kind : {"file", "folder", "report", "database"}
        A file replaced atomically; a folder files are written into; a folder replaced as a
        whole; an SQLite database written in place.
    suffixes : tuple of str, optional
        The suffixes it may end in (lower case, with the dot); None: any.
    create_parents : bool
        Whether missing parent folders will be created (else they must exist).
    """

    path: Path
    flag: str
    kind: Literal["file", "folder", "report", "database"] = "file"
    suffixes: tuple[str, ...] | None = None
    create_parents: bool = True


# ----------------------------------------------------------------------------- text
_CONTROL = re.compile("[\x00-\x08\x0b-\x1f\x7f-\x9f\u202a-\u202e\u2066-\u2069]")


def escape_controls(text: str) -> str:
    """``text`` with control characters shown as escapes (ESC as ``\\x1b``, BEL as ``\\x07``).

    Newlines and tabs are kept; every other C0 and C1 control character, DEL and the Unicode
    bidirectional overrides are replaced, so text from a file (a column name, a config label)
    can never move the cursor, ring the bell, retitle a terminal or reorder a report's text.

    Examples
    --------
    >>> escape_controls("gyro\\x1b[2Jz\\x07")
    'gyro\\\\x1b[2Jz\\\\x07'
    """
    def esc(m: re.Match[str]) -> str:
        c = ord(m.group())
        return f"\\x{c:02x}" if c < 0x100 else f"\\u{c:04x}"

    return _CONTROL.sub(esc, text)


def comment_marker(what: str) -> str:
    """The first line gyrobench writes into a CSV, YAML or TOML file: ``# written by gyrobench <what>``."""
    return f"# written by gyrobench {escape_controls(what).replace(chr(10), ' ')}".rstrip()


# ----------------------------------------------------------------------------- inputs
def _kind_of(mode: int) -> str:
    if stat.S_ISREG(mode):
        return "a regular file"
    if stat.S_ISDIR(mode):
        return "a folder"
    if stat.S_ISFIFO(mode):
        return "a FIFO (named pipe)"
    if stat.S_ISCHR(mode):
        return "a character device"
    if stat.S_ISBLK(mode):
        return "a block device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def check_input(path: str | os.PathLike, what: str) -> Path:
    """``path`` as a Path if it is a readable regular file (symbolic links followed), else one line.

    Checked before anything opens it: a FIFO would block the read forever, ``/dev/zero``
    never ends, a folder is not a file.

    Parameters
    ----------
    path : path-like
        The input.
    what : str
        How the user named it (``"recording file"``, ``"--profile"``).

    Raises
    ------
    FileNotFoundError
        ``"<what> not found: '<path>' does not exist"`` (a broken link says so).
    InputRefused
        A folder, FIFO, device or socket, named as such.
    PermissionError
        A file that cannot be read.
    """
    p = Path(path)
    try:
        st = os.stat(p)
    except FileNotFoundError:
        if os.path.islink(p):
            raise FileNotFoundError(f"{what} not found: {str(p)!r} is a symbolic link to "
                                    f"{os.readlink(p)!r}, which does not exist") from None
        raise FileNotFoundError(f"{what} not found: {str(p)!r} does not exist") from None
    except NotADirectoryError:
        raise FileNotFoundError(f"{what} not found: {str(p)!r} does not exist (a part of the path is a file)") from None
    except OSError as exc:
        raise InputRefused(f"{what} {str(p)!r} cannot be read ({exc.strerror or exc})") from None
    if not stat.S_ISREG(st.st_mode):
        raise InputRefused(f"{what} {str(p)!r} is {_kind_of(st.st_mode)}, not a regular file: give a file")
    if not os.access(p, os.R_OK):
        raise PermissionError(f"{what} {str(p)!r} cannot be read (permission denied)")
    return p


# ----------------------------------------------------------------------------- identity
def _stat(p: Path) -> os.stat_result | None:
    try:
        return os.stat(p)
    except OSError:
        return None


def same_file(a: str | os.PathLike, b: str | os.PathLike) -> str | None:
    """How ``a`` and ``b`` are the same file, or None if they are not.

    Returns ``"the same path"``, ``"through a symbolic link or '..'"`` (equal real paths)
    or ``"a hard link of it"`` (the same device and inode under another name).
    """
    pa, pb = Path(a), Path(b)
    if os.path.abspath(pa) == os.path.abspath(pb):
        return "the same path"
    if os.path.realpath(pa) == os.path.realpath(pb):
        return "the same file, through a symbolic link or '..'"
    sa, sb = _stat(pa), _stat(pb)
    if sa is not None and sb is not None and (sa.st_dev, sa.st_ino) == (sb.st_dev, sb.st_ino):
        return "a hard link of it" if stat.S_ISREG(sa.st_mode) else "the same file"
    return None


def _inside(folder: Path, p: Path) -> bool:
    real, f = os.path.realpath(p), os.path.realpath(folder)
    return real == f or real.startswith(f.rstrip(os.sep) + os.sep)


# ----------------------------------------------------------------------------- markers
def _head(p: Path, n: int = _HEAD_BYTES) -> bytes:
    try:
        with open(p, "rb") as fh:
            return fh.read(n)
    except OSError:
        return b""


def _hdf5_marked(p: Path) -> bool:
    if not _head(p, len(_HDF5_SIGNATURE)) == _HDF5_SIGNATURE:
        return False
    try:
        import h5py

        with h5py.File(p, "r") as h5:
            fmt = h5.attrs.get("format")
    except Exception:  # any unreadable HDF5 file is not recognisably gyrobench's
        return False
    if isinstance(fmt, bytes):
        fmt = fmt.decode("utf-8", "replace")
    return isinstance(fmt, str) and fmt.startswith("gyrobench-")


def _comment_marked(p: Path) -> bool:
    first = _head(p).split(b"\n", 1)[0].lstrip(b"\xef\xbb\xbf")
    return first.startswith(b"#") and b"gyrobench" in first


def _png_marked(p: Path) -> bool:
    try:
        with open(p, "rb") as fh:
            if fh.read(8) != _PNG_SIGNATURE:
                return False
            for _ in range(64):  # text chunks come before the image data
                head = fh.read(8)
                if len(head) < 8:
                    return False
                size, kind = int.from_bytes(head[:4], "big"), head[4:]
                if kind in (b"IDAT", b"IEND") or size > 1 << 20:
                    return False
                data = fh.read(size)
                fh.read(4)  # CRC
                if kind in (b"tEXt", b"iTXt"):
                    key, _, text = data.partition(b"\x00")
                    if key == b"Software" and text.lstrip(b"\x00").startswith(b"gyrobench"):
                        return True
    except OSError:
        return False
    return False


def written_by_gyrobench(path: str | os.PathLike) -> bool:
    """Whether the file at ``path`` carries gyrobench's marker for its suffix (module docstring).

    A file of another suffix, an unreadable one or an empty one is not gyrobench's.
    """
    p = Path(path)
    fmt = _SUFFIX_FORMAT.get(p.suffix.lower())
    if fmt == "hdf5":
        return _hdf5_marked(p)
    if fmt == "comment":
        return _comment_marked(p)
    if fmt == "json":
        return bool(_JSON_MARKER.match(_head(p)))
    if fmt == "png":
        return _png_marked(p)
    return False


# ----------------------------------------------------------------------------- folders
def _sha256(path: Path) -> str:
    import hashlib

    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def folder_files(folder: str | os.PathLike) -> dict[str, Path]:
    """Every entry below ``folder`` that is not a folder (links included), by relative POSIX path."""
    folder = Path(folder)
    out = {}
    for root, dirs, names in os.walk(folder, followlinks=False):
        for name in names + [d for d in dirs if os.path.islink(os.path.join(root, d))]:
            full = Path(root) / name
            out[full.relative_to(folder).as_posix()] = full
    return out


def report_manifest(folder: str | os.PathLike) -> dict[str, str]:
    """``{relative path: sha256}`` of every regular file below ``folder`` (the manifest a report writes)."""
    return {rel: _sha256(p) for rel, p in sorted(folder_files(folder).items()) if rel != REPORT_MARKER}


def _foreign_report_files(p: Path) -> list[str] | None:
    """The files of folder ``p`` a gyrobench report did not write (None: ``p`` is not readable).

    Empty, or a manifest naming every file it holds with the same SHA-256: nothing is
    foreign. A file the user added or edited, a link, or any file of a folder without a
    manifest is foreign.
    """
    import json

    try:
        files = folder_files(p)
    except OSError:
        return None
    if not files:
        return []
    try:
        manifest = json.loads((p / REPORT_MARKER).read_text(encoding="utf-8"))["files"]
        if not isinstance(manifest, dict):
            raise TypeError
    except (OSError, ValueError, KeyError, TypeError, RecursionError):  # unreadable: nothing counts as ours
        manifest = {}
    foreign = []
    for rel, full in sorted(files.items()):
        if rel == REPORT_MARKER and manifest:
            continue
        if full.is_symlink() or not full.is_file() or manifest.get(rel) != _sha256(full):
            foreign.append(rel)
    return foreign


def _listed(names: list[str]) -> str:
    return ", ".join(names[:3]) + (f" and {len(names) - 3} more" if len(names) > 3 else "")


def mark_folder(path: str | os.PathLike) -> Path:
    """Create folder ``path`` (and its parents) if missing and put :data:`FOLDER_MARKER` in it; return it."""
    p = Path(path)
    p.mkdir(parents=True, exist_ok=True)
    marker = p / FOLDER_MARKER
    if not marker.exists():
        marker.write_text("made by gyrobench: the next run of the same command may replace the files it wrote "
                          "here; it never replaces a file gyrobench did not write\n", encoding="utf-8")
    return p


# ----------------------------------------------------------------------------- databases
def _sqlite_tables(p: Path) -> tuple[int, list[str]]:
    """(application_id, table names) of an SQLite file, opened read-only."""
    import sqlite3
    import urllib.parse

    conn = sqlite3.connect(f"file:{urllib.parse.quote(str(p.absolute()))}?mode=ro", uri=True, timeout=10.0)
    try:
        app = int(conn.execute("PRAGMA application_id").fetchone()[0])
        tables = [r[0] for r in conn.execute("SELECT name FROM sqlite_master WHERE type = 'table'")]
    finally:
        conn.close()
    return app, tables


def check_database(path: str | os.PathLike, flag: str, tables: Iterable[str], *, force: bool = False) -> Path:
    """Refuse, before anything is written, a database ``path`` gyrobench did not make.

    A missing file is fine (it will be created). An existing one must be an SQLite file
    whose ``application_id`` is :data:`SQLITE_APPLICATION_ID`, or whose tables are all among
    ``tables`` (gyrobench's schema; SQLite's own ``sqlite_*`` tables aside). An empty file
    is replaced only with ``force``; a foreign SQLite file, or a file that is not SQLite, never.

    Raises
    ------
    OutputRefused
        Naming the file and what it holds.
    """
    p = Path(path)
    st = _stat(p)
    if st is None:
        return p
    if not stat.S_ISREG(st.st_mode):
        raise OutputRefused(f"{flag} {str(p)!r} is {_kind_of(st.st_mode)}, not a database file")
    if st.st_size == 0:
        if force:
            return p
        raise OutputRefused(f"{flag} {str(p)!r} is an empty file gyrobench did not make: it is not used as a "
                            "database; give a new path, or --force to use it")
    if _head(p, len(_SQLITE_SIGNATURE)) != _SQLITE_SIGNATURE:
        raise OutputRefused(f"{flag} {str(p)!r} exists and is not an SQLite database: nothing is written to it; "
                            "give a new path")
    import sqlite3

    try:
        app, names = _sqlite_tables(p)
    except sqlite3.Error as exc:
        raise OutputRefused(f"{flag} {str(p)!r} cannot be read to check that gyrobench made it ({exc}): nothing is "
                            "written to it") from None
    known = set(tables)
    own = [n for n in names if not n.startswith("sqlite_")]
    if app == SQLITE_APPLICATION_ID or (own and set(own) <= known):
        return p
    what = f"tables {_listed(sorted(own))}" if own else "no tables"
    raise OutputRefused(f"{flag} {str(p)!r} is an SQLite database gyrobench did not make ({what}): nothing is "
                        "written to it; give a new path")


# ----------------------------------------------------------------------------- outputs
def _probe_writable(folder: Path, what: str, target: Path) -> None:
    """Create and remove a file in ``folder``: the one test that answers "can I write here"
    for root, read-only mounts, /proc and ACLs alike. Its name is that of an atomic write's
    temporary file (``.NAME.<pid>.<hex>.tmp``), so a kill leaves nothing that looks like a result."""
    probe = folder / f"..gyrobench-probe.{os.getpid()}.{secrets.token_hex(4)}.tmp"
    try:
        fd = os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    except OSError as exc:
        raise PermissionError(
            f"cannot write {str(target)!r} ({what}): the folder {str(folder)!r} does not "
            f"accept new files ({exc.strerror or exc})"
        ) from None
    os.close(fd)
    os.unlink(probe)


def _existing_ancestor(p: Path) -> Path:
    a = p
    while not a.exists() and not a.is_symlink() and a != a.parent:
        a = a.parent
    return a


def _check_receiver(o: Output, p: Path, receiver: Path) -> None:
    text = str(p)
    base = _existing_ancestor(receiver)
    if not base.is_dir():
        raise NotADirectoryError(f"cannot write {text!r} ({o.flag}): {str(base)!r} is a file, not a folder")
    if base != receiver and not o.create_parents:
        raise FileNotFoundError(
            f"{o.flag} must be in an existing folder; the folder {str(receiver)!r} does not exist "
            f"(create it first); got {text!r}"
        )
    _probe_writable(base, o.flag, p)


def _check_file(o: Output, p: Path, force: bool) -> None:
    text = str(p)
    if p.is_dir():
        raise IsADirectoryError(f"{o.flag} must be a file name; got the folder {text!r}")
    if o.suffixes is not None and p.suffix.lower() not in o.suffixes:
        raise OutputRefused(f"{o.flag} must end in {', '.join(o.suffixes)}; got {text!r}")
    st = _stat(p)
    if st is not None:
        if not stat.S_ISREG(st.st_mode):
            raise OutputRefused(f"{o.flag} must be a regular file; {text!r} is {_kind_of(st.st_mode)}")
        if not force and not written_by_gyrobench(p):
            fmt = _SUFFIX_FORMAT.get(p.suffix.lower())
            marker = f" (no {_FORMAT_NAME[fmt]})" if fmt else ""
            raise OutputRefused(
                f"{o.flag} {text!r} exists and gyrobench did not write it{marker}: it is never replaced; "
                "give a new path, or --force to replace it"
            )
    _check_receiver(o, p, p.parent)


def _check_folder(o: Output, p: Path, force: bool) -> None:
    text = str(p)
    if p.exists() and not p.is_dir():
        raise NotADirectoryError(f"{o.flag} must be a folder; {text!r} is an existing file")
    if p.is_symlink():
        raise OutputRefused(f"{o.flag} must not be a symbolic link (it would be replaced by a folder); got {text!r}")
    if p.is_dir():
        if o.kind == "report":
            foreign = _foreign_report_files(p)
            report = (p / REPORT_MARKER).is_file()
            if foreign is None or (foreign and not (force and report)):
                shown = _listed(foreign or []) or "unreadable"
                raise OutputRefused(
                    f"{o.flag} {text!r} exists and is not a gyrobench report folder (a report replaces its folder "
                    f"as a whole, and this one holds files no report wrote: {shown}): give a new folder or an "
                    "earlier report's" + (" (--force replaces an earlier report whose files were edited)"
                                          if report else "")
                )
        else:
            try:
                names = sorted(os.listdir(p))
            except OSError as exc:
                raise OutputRefused(f"{o.flag} {text!r} cannot be listed ({exc.strerror or exc})") from None
            if names and FOLDER_MARKER not in names and not force and not _all_ours(p, names):
                raise OutputRefused(
                    f"{o.flag} {text!r} is a folder gyrobench did not make (it holds {_listed(names)} and no "
                    f"{FOLDER_MARKER} file): files are written only into a new or empty folder or one gyrobench "
                    "made; give another folder, or --force to write into it"
                )
    _check_receiver(o, p, p.parent if o.kind == "report" or not p.exists() else p)


def _all_ours(folder: Path, names: list[str]) -> bool:
    """Whether every entry of ``folder`` is a regular file gyrobench wrote (a folder it filled before it
    marked its folders)."""
    return all((folder / n).is_file() and not (folder / n).is_symlink() and written_by_gyrobench(folder / n)
               for n in names)


def _check_text(o: Output) -> Path:
    text = str(o.path)
    if not text or text.strip() != text:
        raise OutputRefused(f"{o.flag} must be a path without surrounding spaces; got {text!r}")
    return Path(o.path)


def check_outputs(
    outputs: Sequence[Output],
    inputs: Iterable[tuple[str, str | os.PathLike | None]] = (),
    *,
    force: bool = False,
    tables: Iterable[str] = (),
) -> list[Path]:
    """Apply the output rule (module docstring) to a command's ``outputs``; return their paths.

    Parameters
    ----------
    outputs : sequence of Output
        Every output of the command (a ``"database"`` output is also read).
    inputs : iterable of (flag, path)
        Every file the command reads, named as the user named it (None entries are skipped).
    force : bool
        ``--force``: replace existing files gyrobench did not write (never an input, never a
        foreign database, never a folder without a report manifest).
    tables : iterable of str
        The table names of gyrobench's databases (for ``"database"`` outputs).

    Raises
    ------
    OutputRefused
        An output that is an input or another output, a wrong suffix, an existing target
        gyrobench did not write (without ``force``), a foreign folder or database. One line
        naming both paths where two are involved.
    IsADirectoryError, NotADirectoryError, FileNotFoundError, PermissionError
        A path of the wrong type, a missing parent folder (when not created), a folder that
        does not accept new files.
    """
    ins = [(flag, Path(p)) for flag, p in inputs if p is not None]
    paths = [_check_text(o) for o in outputs]
    tables = tuple(tables)
    for o, p in zip(outputs, paths, strict=True):
        for flag, q in ins:
            how = same_file(p, q)
            if how is not None:
                raise OutputRefused(f"{o.flag} {str(p)!r} is the input {flag} {str(q)!r} ({how}): an output never "
                                    "replaces an input; give another path")
            if o.kind == "report" and _inside(p, q):
                raise OutputRefused(f"the input {flag} {str(q)!r} is inside {o.flag} {str(p)!r}, which a report "
                                    "replaces as a whole: move it out, or give another folder")
    for i, (a, pa) in enumerate(zip(outputs, paths, strict=True)):
        for b, pb in zip(outputs[i + 1:], paths[i + 1:], strict=True):
            how = same_file(pa, pb)
            if how is not None:
                raise OutputRefused(f"{a.flag} {str(pa)!r} and {b.flag} {str(pb)!r} are one file ({how}): give each "
                                    "output its own path")
            for x, px, y, py in ((a, pa, b, pb), (b, pb, a, pa)):
                if x.kind == "report" and _inside(px, py):
                    raise OutputRefused(f"{y.flag} {str(py)!r} is inside {x.flag} {str(px)!r}, which a report "
                                        "replaces as a whole: give it a path outside")
    for o, p in zip(outputs, paths, strict=True):
        if o.kind == "file":
            _check_file(o, p, force)
        elif o.kind == "database":
            if p.is_dir():
                raise IsADirectoryError(f"{o.flag} must be a file name; got the folder {str(p)!r}")
            if o.suffixes is not None and p.suffix.lower() not in o.suffixes:
                raise OutputRefused(f"{o.flag} must end in {', '.join(o.suffixes)}; got {str(p)!r}")
            check_database(p, o.flag, tables, force=force)
            _check_receiver(o, p, p.parent)
        else:
            _check_folder(o, p, force)
    return paths
