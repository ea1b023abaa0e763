"""Output locations, checked before any work; a report folder written as a set.

Every verb that writes calls :func:`check_output` on each of its output paths first,
before simulating or analysing anything, so a wrong ``--out``, ``-o``, ``--plot``,
``--save-baseline`` or ``--db`` fails in one line in a fraction of a second instead of
after the work. :func:`write_report_as_a_set` writes a report folder so that it holds
one run's files or the previous run's, never a mix.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any, Literal

__all__ = ["check_output", "output_lock", "report_manifest", "write_report_as_a_set", "REPORT_MARKER"]

#: the manifest every report folder written by :func:`write_report_as_a_set` holds: JSON naming
#: every file the report wrote with its SHA-256; the next report replaces the folder as a whole
#: only while it holds nothing but those files, unchanged
REPORT_MARKER = ".gyrobench-report"


def _existing_ancestor(p: Path) -> Path:
    a = p
    while not a.exists() and not a.is_symlink() and a != a.parent:
        a = a.parent
    return a


def _probe_writable(folder: Path, what: str, target: Path) -> None:
    """Create and remove a file in ``folder``: the one test that answers "can I write here"
    for root, read-only mounts, /proc and ACLs alike."""
    from gyrobench.base.atomic import temp_name

    probe = temp_name(folder / ".gyrobench-probe")
    try:
        fd = os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    except OSError as exc:
        raise PermissionError(
            f"cannot write {str(target)!r} ({what}): the folder {str(folder)!r} does not "
            f"accept new files ({exc.strerror or exc})"
        ) from None
    os.close(fd)
    os.unlink(probe)


def _sha256(path: Path) -> str:
    import hashlib

    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _files(folder: Path) -> dict[str, Path]:
    """Every entry below ``folder`` that is not a folder (links included), by relative POSIX path."""
    out = {}
    for root, dirs, names in os.walk(folder, followlinks=False):
        for name in names + [d for d in dirs if os.path.islink(os.path.join(root, d))]:
            full = Path(root) / name
            out[full.relative_to(folder).as_posix()] = full
    return out


def report_manifest(folder: str | os.PathLike) -> dict[str, str]:
    """``{relative path: sha256}`` of every regular file below ``folder`` (the manifest it writes)."""
    return {rel: _sha256(p) for rel, p in sorted(_files(Path(folder)).items()) if rel != REPORT_MARKER}


def _foreign_files(p: Path) -> list[str] | None:
    """The files of folder ``p`` a gyrobench report did not write (None: ``p`` is not readable).

    A folder may be replaced when it is empty, or when its manifest names every file it holds
    with the same SHA-256: a file the user added or edited, a link, or a folder without a
    manifest (anything else), is foreign.
    """
    import json

    try:
        files = _files(p)
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


def check_output(
    path: str | os.PathLike,
    *,
    what: str,
    kind: Literal["file", "folder", "report"] = "file",
    create_parents: bool = True,
    suffixes: Sequence[str] | None = None,
) -> Path:
    """Check, before any work, that ``path`` can be written as a ``kind``; return it as a Path.

    Parameters
    ----------
    path : path-like
        The output.
    what : str
        How the user named it, for the message (``"--out"``, ``"--plot"``, ``"-o"``).
    kind : {"file", "folder", "report"}
        ``"file"``: a file (an existing file is replaced; a folder is refused).
        ``"folder"``: a folder files are written into (created if missing).
        ``"report"``: a folder replaced as a whole (:func:`write_report_as_a_set`): if it
        exists it must be empty or an earlier gyrobench report, so a mistyped ``--out``
        (``.``, a home folder) can never be swapped away.
    create_parents : bool
        Whether missing parent folders will be created (else they must exist).
    suffixes : sequence of str, optional
        Accepted file suffixes (lower case, with the dot).

    Raises
    ------
    IsADirectoryError
        A file output that is an existing folder.
    NotADirectoryError
        A folder output that is an existing file, or a path through a file.
    FileNotFoundError
        A missing parent folder when ``create_parents`` is False.
    PermissionError
        The folder that would receive the output does not accept new files.
    ValueError
        A wrong suffix, or a report folder that holds other files.
    """
    p = Path(path)
    text = str(p)
    if not text or text.strip() != text:
        raise ValueError(f"{what} must be a path without surrounding spaces; got {text!r}")
    if kind == "file":
        if p.is_dir():
            raise IsADirectoryError(f"{what} must be a file name; got the folder {text!r}")
        if suffixes is not None and p.suffix.lower() not in suffixes:
            raise ValueError(f"{what} must end in {', '.join(suffixes)}; got {text!r}")
        if p.exists() and not p.is_file():
            raise ValueError(f"{what} must be a regular file; got {text!r}")
    else:
        if p.exists() and not p.is_dir():
            raise NotADirectoryError(f"{what} must be a folder; {text!r} is an existing file")
        if p.is_symlink():
            raise ValueError(f"{what} must not be a symbolic link (it would be replaced by a folder); got {text!r}")
        foreign = _foreign_files(p) if kind == "report" and p.is_dir() else []
        if foreign is None or foreign:
            listed = foreign or []
            shown = ", ".join(listed[:3]) + (f" and {len(listed) - 3} more" if len(listed) > 3 else "")
            raise ValueError(
                f"{what} {text!r} exists and is not a gyrobench report folder (a report replaces "
                f"its folder as a whole, and this one holds files no report wrote: {shown or 'unreadable'}): "
                "give a new folder or an earlier report's"
            )
    # the folder that receives the output (for "report": its parent, where the swap happens)
    receiver = p.parent if kind in ("file", "report") or not p.exists() else p
    base = _existing_ancestor(receiver)
    if not base.is_dir():
        raise NotADirectoryError(
            f"cannot write {text!r} ({what}): {str(base)!r} is a file, not a folder"
        )
    if base != receiver and not create_parents:
        raise FileNotFoundError(
            f"{what} must be in an existing folder; the folder {str(receiver)!r} does not exist "
            f"(create it first); got {text!r}"
        )
    _probe_writable(base, what, p)
    return p


def write_report_as_a_set(
    outcomes: Sequence[Any], out_dir: str | os.PathLike, *, command: str = ""
) -> Path:
    """:func:`gyrobench.scenarios.reports.report.write_report` into a new folder swapped in for
    ``out_dir`` when complete (:func:`gyrobench.base.atomic.atomic_folder`); returns the
    path of ``index.html`` in ``out_dir``.

    A failed or killed report leaves the previous ``out_dir`` as it was; ``out_dir`` never
    mixes two runs' files. Call :func:`check_output` (``kind="report"``) before the work.
    """
    import json

    from gyrobench.base.atomic import atomic_folder
    from gyrobench.scenarios.reports.report import write_report

    out = Path(out_dir)
    with atomic_folder(out) as tmp:
        index = write_report(outcomes, tmp, command=command)
        doc = {
            "written_by": "gyrobench reproduce; replaced as a whole by the next report while it holds only these files",
            "files": report_manifest(tmp),
        }
        (tmp / REPORT_MARKER).write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
    return out / Path(index).relative_to(tmp)


@contextlib.contextmanager
def output_lock(path: str | os.PathLike, *, what: str) -> Iterator[None]:
    """Hold an exclusive lock on output ``path`` for the block, so two gyrobench processes never
    write one output at once; the second is refused in one line.

    The lock is ``fcntl.flock`` on ``.<name>.gyrobench-lock`` beside ``path`` (released by
    the kernel when the process ends, however it ends).

    Raises
    ------
    BlockingIOError
        Another process holds the lock.
    """
    import fcntl

    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    lock = p.parent / f".{p.name}.gyrobench-lock"
    fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise BlockingIOError(
                f"{what} {str(p)!r} is being written by another gyrobench process (lock {str(lock)!r}): "
                "wait for it to finish or choose another output"
            ) from None
        yield
    finally:
        os.close(fd)
