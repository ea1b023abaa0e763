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
from collections.abc import Iterable, Iterator, Sequence
from pathlib import Path
from typing import Any, Literal

from gyrobench.base import safety as _safety

__all__ = ["check_output", "output_lock", "report_manifest", "write_report_as_a_set", "REPORT_MARKER"]

#: the manifest every report folder written by :func:`write_report_as_a_set` holds: JSON naming
#: every file the report wrote with its SHA-256; the next report replaces the folder as a whole
#: only while it holds nothing but those files, unchanged
REPORT_MARKER = _safety.REPORT_MARKER
report_manifest = _safety.report_manifest


def check_output(
    path: str | os.PathLike,
    *,
    what: str,
    kind: Literal["file", "folder", "report"] = "file",
    create_parents: bool = True,
    suffixes: Sequence[str] | None = None,
    inputs: Iterable[tuple[str, str | os.PathLike | None]] = (),
    force: bool | None = None,
) -> Path:
    """Check, before any work, that ``path`` can be written as a ``kind``; return it as a Path.

    One output through the rule of :mod:`gyrobench.base.safety` (:func:`~gyrobench.base.safety.check_outputs`).

    Parameters
    ----------
    path : path-like
        The output.
    what : str
        How the user named it, for the message (``"--out"``, ``"--plot"``, ``"-o"``).
    kind : {"file", "folder", "report"}
        ``"file"``: a file replaced atomically; ``"folder"``: a folder files are written
        into (created if missing; an existing one must be empty or made by gyrobench);
        ``"report"``: a folder replaced as a whole (:func:`write_report_as_a_set`): if it
        exists it must be empty or an earlier gyrobench report, so a mistyped ``--out``
        (``.``, a home folder) can never be swapped away.
    create_parents : bool
        Whether missing parent folders will be created (else they must exist).
    suffixes : sequence of str, optional
        Accepted file suffixes (lower case, with the dot).
    inputs : iterable of (flag, path)
        The command's inputs: the output may not be one of them.
    force : bool, optional
        ``--force`` of a command. None (a library call that writes where it is told): an
        existing file is replaced whoever wrote it; a folder keeps the strict rule.

    Returns
    -------
    Path
        ``path`` as a Path.

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
        (:class:`~gyrobench.base.safety.OutputRefused`) A wrong suffix, an input, an existing
        file gyrobench did not write, or a folder that holds other files.
    """
    out = _safety.Output(Path(path), what, kind, None if suffixes is None else tuple(suffixes), create_parents)
    replace_any = force if force is not None else kind == "file"
    return _safety.check_outputs([out], inputs, force=replace_any)[0]


def write_report_as_a_set(
    outcomes: Sequence[Any], out_dir: str | os.PathLike, *, command: str = "", maps: Any = None
) -> Path:
    """Write a report into a new folder swapped in for ``out_dir`` when complete.

    :func:`gyrobench.scenarios.reports.report.write_report` into a new folder swapped in for
    ``out_dir`` when complete (:func:`gyrobench.base.atomic.atomic_folder`); returns the
    path of ``index.html`` in ``out_dir``. ``maps`` (scenario -> :class:`~.map_section.MapFiles`)
    go into their scenarios' sections.

    A failed or killed report leaves the previous ``out_dir`` as it was; ``out_dir`` never
    mixes two runs' files. Call :func:`check_output` (``kind="report"``) before the work.

    Parameters
    ----------
    outcomes : sequence of Outcome
        The scenarios' outcomes.
    out_dir : path-like
        The report folder.
    command : str
        The command line that made the report, shown in it.
    maps : mapping of str to MapFiles, optional
        Each mapped scenario's map files, shown in its section.

    Returns
    -------
    Path
        ``out_dir / "index.html"``.
    """
    import json

    from gyrobench.base.atomic import atomic_folder
    from gyrobench.scenarios.reports.report import write_report

    out = Path(out_dir)
    with atomic_folder(out) as tmp:
        try:
            index = write_report(outcomes, tmp, command=command, maps=maps)
            doc = {
                "written_by": "gyrobench reproduce; replaced as a whole by the next report while it holds only "
                              "these files",
                "files": report_manifest(tmp),
            }
            (tmp / REPORT_MARKER).write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
        except OSError as exc:  # a full disk: the message names the report's file, not the folder being filled
            raise _in_target(exc, tmp, out) from exc
    return out / Path(index).relative_to(tmp)


def _in_target(exc: OSError, tmp: Path, out: Path) -> OSError:
    """``exc`` with every mention of the temporary folder ``tmp`` replaced by the target ``out``."""
    from gyrobench.base.atomic import AtomicWriteError, _write_error

    name = str(exc.filename).replace(str(tmp), str(out)) if exc.filename else str(out)
    if not isinstance(exc, AtomicWriteError):
        return _write_error(Path(name), exc)
    return AtomicWriteError(exc.errno, str(exc.strerror).replace(str(tmp), str(out)), name)


@contextlib.contextmanager
def output_lock(path: str | os.PathLike, *, what: str) -> Iterator[None]:
    """Hold an exclusive lock on an output for the block.

    Hold an exclusive lock on output ``path`` for the block, so two gyrobench processes never
    write one output at once; the second is refused in one line.

    The lock is ``fcntl.flock`` on ``.<name>.gyrobench-lock`` beside ``path`` (released by
    the kernel when the process ends, however it ends).

    Parameters
    ----------
    path : path-like
        The output.
    what : str
        How the user named it (a flag), for the refusal.

    Yields
    ------
    None
        The block runs holding the lock.

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
