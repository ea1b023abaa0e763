"""Atomic writes: a file or folder appears at its target complete, or not at all.

Data go to a temporary file (or folder) beside the target, which is renamed over the target
only when complete (``os.replace``). The result gets the mode an ordinary ``open(path, "w")``
would give (``0o666`` less the umask). A failed write (disk full, file-size limit, I/O error)
raises :class:`AtomicWriteError`, an ``OSError`` whose message names the target path, never the
temporary file; the temporary file is removed and any previous file at the target is left as it
was. Temporary names carry the writer's process id and start time, so a temporary left by a
killed writer is recognised and removed by :func:`remove_stale_temps`.

This module imports nothing of gyrobench's: every layer may use it.
"""

from __future__ import annotations

import contextlib
import errno
import os
import secrets
import shutil
from collections.abc import Iterator
from pathlib import Path

__all__ = [
    "AtomicWriteError",
    "atomic_path",
    "atomic_folder",
    "remove_stale_temps",
    "temp_name",
    "ensure_free_space",
]

class AtomicWriteError(OSError):
    """Writing a file failed; the message names the target path, not the temporary file.

    Built as ``AtomicWriteError(errno, message, target)``: ``errno`` is the
    underlying error number (``ENOSPC``, ``EFBIG``, ...), ``strerror`` the
    message and ``filename`` the target path.
    """

    def __str__(self) -> str:  # the message alone, not OSError's "[Errno n] strerror: filename"
        return str(self.strerror)


_WRITE_HINTS = {
    errno.ENOSPC: " (the disk is full)",
    errno.EDQUOT: " (disk quota exceeded)",
    errno.EFBIG: " (file-size limit reached: see 'ulimit -f')",
}


def _write_error(path: Path, exc: OSError) -> AtomicWriteError:
    """An AtomicWriteError naming ``path``, with the cause of ``exc`` (not its temp-file name)."""
    if isinstance(exc, AtomicWriteError):
        return exc
    cause = exc.strerror or (str(exc.args[0]) if exc.args else type(exc).__name__)
    hint = _WRITE_HINTS.get(exc.errno or 0, "")
    return AtomicWriteError(exc.errno, f"cannot write {str(path)!r}: {cause}{hint}", str(path))


def _fmt_bytes(n: float) -> str:
    """``28800000`` -> ``"28.8 MB"`` (decimal units, as ``df -H``)."""
    if abs(n) < 1000:
        return f"{n:.0f} B"
    for unit in ("kB", "MB", "GB"):
        n /= 1000
        if abs(n) < 1000:
            return f"{n:.3g} {unit}"
    return f"{n / 1000:.3g} TB"


def ensure_free_space(path: str | os.PathLike, nbytes: int) -> None:
    """Refuse, before writing, a file of about ``nbytes`` that would not fit on ``path``'s disk.

    Parameters
    ----------
    path : path-like
        The file to be written (it and its folder need not exist yet).
    nbytes : int
        Expected size of the file [bytes].

    Raises
    ------
    AtomicWriteError
        With ``errno.ENOSPC`` when ``nbytes`` exceeds the free space of the
        file system that will hold ``path`` (``shutil.disk_usage``).
    """
    p = Path(path).absolute()
    folder = p.parent
    while not folder.exists() and folder != folder.parent:
        folder = folder.parent
    try:
        usage = shutil.disk_usage(folder)
    except OSError:  # cannot tell: let the write itself fail or succeed
        return
    free = usage.free
    if usage.total == 0:  # a pseudo file system (/proc, /sys): sizes mean nothing there
        return
    if nbytes > free:
        raise AtomicWriteError(
            errno.ENOSPC,
            f"cannot write {str(path)!r}: the record needs about {_fmt_bytes(nbytes)} but {str(folder)!r} "
            f"has {_fmt_bytes(free)} free; shorten the record, lower fs or write elsewhere",
            str(path),
        )


def temp_name(path: Path, kind: str = "tmp") -> Path:
    """``.NAME.<pid>.<8 hex>.<kind>`` beside ``path``: the owning process id is in the name, so a
    later run can tell a dead writer's leftovers (:func:`remove_stale_temps`) from a live one's."""
    return path.with_name(f".{path.name}.{os.getpid()}.{secrets.token_hex(4)}.{kind}")


#: kinds of leftovers :func:`remove_stale_temps` removes (a file being written, a folder being
#: filled, a folder swapped out)
_TEMP_KINDS = ("tmp", "tmpdir", "old")


def _process_start(pid: int) -> float | None:
    """Start time of process ``pid`` [s since the epoch] (Linux /proc), None if unknown."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
        ticks = int(stat.rpartition(")")[2].split()[19])  # field 22, after the command name
        for line in Path("/proc/stat").read_text().splitlines():
            if line.startswith("btime "):
                return int(line.split()[1]) + ticks / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError):
        pass
    return None


def _owner_alive(pid: int, since: float) -> bool:
    """Whether process ``pid`` exists and could own a file last modified at ``since``: a
    process that started after it is another process that got the pid again."""
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process: alive
        pass
    except OSError:
        return True
    start = _process_start(pid)
    return start is None or start <= since + 1.0  # 1 s: the clock-tick rounding of btime


def remove_stale_temps(path: str | os.PathLike) -> list[Path]:
    """Remove the temporary files and folders that dead processes left for target ``path``.

    Leftovers are named ``.NAME.<pid>.<hex>.tmp`` (a file being written),
    ``.NAME.<pid>.<hex>.tmpdir`` (a folder being filled) and ``.NAME.<pid>.<hex>.old`` (a
    folder being replaced, :func:`atomic_folder`); those whose process is gone (or whose pid
    now belongs to a process started after them) are removed. A live writer's files are
    left alone. If a ``.old`` folder is left and the target is missing (a kill between the
    two renames of a folder swap), it is renamed back instead of removed.

    Returns the paths removed (or restored).
    """
    import re

    p = Path(path)
    pattern = re.compile(rf"^\.{re.escape(p.name)}\.(\d+)\.[0-9a-f]{{8}}\.({'|'.join(_TEMP_KINDS)})$")
    done: list[Path] = []
    try:
        entries = list(os.scandir(p.parent))
    except OSError:
        return done
    for e in entries:
        m = pattern.match(e.name)
        if not m:
            continue
        try:
            mtime = e.stat(follow_symlinks=False).st_mtime
        except OSError:
            continue
        if _owner_alive(int(m.group(1)), mtime):
            continue
        stale = Path(e.path)
        try:
            if m.group(2) == "old" and not p.exists() and not p.is_symlink():
                os.replace(stale, p)
            elif e.is_dir(follow_symlinks=False):
                shutil.rmtree(stale)
            else:
                stale.unlink()
        except OSError:  # another process cleaned it first, or no permission: not ours to fix
            continue
        done.append(stale)
    return done


def _create_temp(path: Path) -> Path:
    """Create an empty, new temporary file beside ``path`` with mode ``0o666 & ~umask``.

    ``tempfile.mkstemp`` would give 0600 whatever the umask, and the final file
    would keep it; ``os.open`` with 0666 lets the kernel apply the umask (and any
    default ACL) exactly as for an ordinary ``open(path, "w")``. The name carries the
    process id (:func:`temp_name`); leftovers of dead processes for the same target are
    removed first (:func:`remove_stale_temps`).
    """
    remove_stale_temps(path)
    for _ in range(100):
        tmp = temp_name(path)
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0), 0o666)
        except FileExistsError:
            continue
        os.close(fd)
        return tmp
    raise FileExistsError(errno.EEXIST, "no free temporary name", str(path))  # pragma: no cover


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; rename it onto ``path`` only on success.

    An exception (or a kill) inside the block leaves ``path`` untouched and the
    temporary file removed (or, after a kill, a ``.NAME.<pid>.<hex>.tmp`` file that
    never looks like the result, and that the next write to ``path`` removes once that
    process is gone). The result has mode ``0o666 & ~umask``, as any new file.

    Raises
    ------
    AtomicWriteError
        For an ``OSError`` while creating, writing (inside the block) or
        renaming; the message names ``path``, not the temporary file.
    """
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp_path = _create_temp(path)
    except OSError as exc:
        raise _write_error(path, exc) from exc
    try:
        yield tmp_path
        os.replace(tmp_path, path)
    except OSError as exc:
        raise _write_error(path, exc) from exc
    finally:
        with contextlib.suppress(FileNotFoundError):
            tmp_path.unlink()


@contextlib.contextmanager
def atomic_folder(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a new, empty folder beside ``path``; on success it replaces ``path`` as a whole.

    The files of a run are written into ``.NAME.<pid>.<hex>.tmpdir``; only when the block
    finishes is that folder renamed to ``path`` (a previous ``path`` is first renamed to
    ``.NAME.<pid>.<hex>.old``, then removed). So ``path`` holds one run's files or the
    previous run's, never a mix. An exception in the block removes the new folder and
    leaves ``path`` as it was. After a kill, the next call removes the dead run's folders
    (:func:`remove_stale_temps`; an ``.old`` folder whose target went missing between the
    two renames is renamed back).

    Raises
    ------
    AtomicWriteError
        For an ``OSError`` while creating or swapping; the message names ``path``.
    NotADirectoryError
        If ``path`` exists and is not a folder.
    """
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise NotADirectoryError(errno.ENOTDIR, f"{str(path)!r} exists and is not a folder", str(path))
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        remove_stale_temps(path)
        tmp = temp_name(path, "tmpdir")
        tmp.mkdir(mode=0o777)
    except OSError as exc:
        raise _write_error(path, exc) from exc
    try:
        yield tmp
        old = None
        if path.exists():
            old = temp_name(path, "old")
            os.replace(path, old)
        try:
            os.replace(tmp, path)
        except OSError:
            if old is not None:
                os.replace(old, path)
            raise
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
    except OSError as exc:
        raise _write_error(path, exc) from exc
    finally:
        if tmp.exists():
            shutil.rmtree(tmp, ignore_errors=True)
