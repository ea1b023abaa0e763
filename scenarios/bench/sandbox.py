"""The compensator's sandbox: a process that holds only what a real deployment would see.

The user's compensator never runs in a process that holds a task's truth. For every campaign
the bench starts one *zygote*: a fresh interpreter (``python -c``, nothing inherited but the
environment, the working folder and ``sys.path``) that imports the compensator, records what
it reads, and waits. For every seed the zygote forks a *child*; the scoring process (which
built the seed's task) sends the child the training data (``X_train``, ``y_train``, the
training groups, the ``random_state`` integer) and then each held-out run's ``X``, and reads
back the predictions. Scores are computed in the scoring process, with its own numpy, from
the predictions received: a child that patches ``numpy.mean``, walks the stack or the garbage
collector finds no truth, no seed and no configuration to rebuild the task from.

What it cannot stop: a child can still search for its seed (simulate the scenario for seeds
0, 1, ... and match ``X_train``, or invert ``random_state``) and so rebuild the truth. The
noise floor (:func:`gyrobench.scenarios.bench.floor.floor_failure`) is what catches such a
score: it is far below what any compensator can reach from the features.

Wire format. Scoring process -> child: pickled dicts (the child may trust its parent).
Child -> scoring process: never pickled (unpickling runs code): a JSON header
(:func:`recv_json`, at most :data:`MAX_HEADER` bytes) and, for a prediction, the raw
little-endian float64 bytes, checked against the header's shape before
:func:`numpy.frombuffer`.

Containment (the parent keeps it, never the child):

- each child calls ``setsid()``: its own session and process group; the campaign's process
  SIGKILLs the group at the seed's end and at the seed's deadline, so a helper process the
  compensator forked dies too (unless it left the group with its own ``setsid``);
- the zygote and every child write to a pipe the campaign forwards to its stderr, never to
  gyrobench's own stdout/stderr, so a helper left behind cannot hold ``| tee`` open;
- each child's address space is capped (``RLIMIT_AS``, :data:`DEFAULT_MEMORY_BYTES`, ``bench
  --seed-memory``): an allocation past it raises ``MemoryError`` (or kills the child) and
  fails that seed;
- the compensator's import runs in the zygote, under the same time limit as a seed: a
  hanging import, ``sys.exit(7)``, ``KeyboardInterrupt`` or any ``BaseException`` at import
  is reported in one line, never gyrobench's own exit status;
- the zygote and its children die with the campaign's process (``PR_SET_PDEATHSIG``).

Reads. The zygote and its children record, with ``sys.addaudithook``, every file opened for
reading (``open`` events; module sources are covered by the module list), every environment
variable read through ``os.environ`` (``os.getenv`` included) and the modules in
``sys.modules`` after ``fit``/``predict`` that lie outside the standard library; files and
user modules are fingerprinted by content, site-packages modules by path, size and
modification time (:func:`reads_fingerprint`). Network connections and subprocesses are noted
by kind (what they read is not seen); a file opened or a variable read by C code (a C
extension's own ``fopen`` or ``getenv``) is not seen at all.

Reuse. :func:`shared_zygote` keeps the last :data:`SHARED_ZYGOTES` zygotes of this process
(campaigns of one compensator in a test suite start one interpreter, not one each) and
reuses one only while everything it read while importing (modules, files, environment
variables) is unchanged; each child takes the environment and working folder of the
campaign that forks it.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import pickle
import signal
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from gyrobench.scenarios.bench.sandbox_child import MAX_HEADER, _die_with_parent, _zygote_start, reads_fingerprint
from gyrobench.scenarios.bench.sandbox_protocol import (
    ChildDied,
    MemoryExceeded,
    RemoteCompensator,
    RemoteError,
    RemoteExit,
    _str,
    recv_json,
)

__all__ = [
    "DEFAULT_MEMORY_BYTES",
    "MAX_HEADER",
    "ChildDied",
    "ChildStatus",
    "MemoryExceeded",
    "RemoteError",
    "RemoteExit",
    "RemoteCompensator",
    "Zygote",
    "ZygoteError",
    "kill_group",
    "reads_fingerprint",
    "recv_json",
    "shared_zygote",
]

#: default per-seed address-space cap of the compensator's process [bytes] (4 GiB; ``bench
#: --seed-memory``). The zygote with numpy and scikit-learn imported maps about 1 GiB.
DEFAULT_MEMORY_BYTES = 4 * 1024**3


class ZygoteError(Exception):
    """The compensator's process could not be made ready: its import raised, exited or hung.

    ``kind`` is ``"raised"``, ``"exited"``, ``"hung"`` or ``"died"``, or ``"named"`` (the user's
    module raised, the message names it) and ``"bad"`` (not importable or not a compensator: the
    message is :func:`~gyrobench.scenarios.bench.compensators.resolve_compensator`'s);
    ``traceback_text`` holds the import's traceback when it raised.

    Parameters
    ----------
    message : str
        One line saying what happened.
    kind : str
        How the import failed (see above).
    traceback_text : str
        The import's traceback (``""``: none).
    """

    def __init__(self, message: str, *, kind: str, traceback_text: str = "") -> None:
        super().__init__(message)
        self.kind = kind
        self.traceback_text = traceback_text


# ----------------------------------------------------------------------------- campaign side
def _forward(fd: int) -> None:
    """Copy the compensator's output (its prints, warnings) to this process's stderr."""
    try:
        while True:
            block = os.read(fd, 65536)
            if not block:
                break
            with contextlib.suppress(Exception):
                sys.stderr.write(block.decode("utf-8", "replace"))
                sys.stderr.flush()
    except OSError:
        pass
    finally:
        with contextlib.suppress(OSError):
            os.close(fd)


def kill_group(pid: int) -> None:
    """SIGKILL process ``pid`` and its process group (a child is the leader of its own).

    Parameters
    ----------
    pid : int
        The process (and group leader) to kill; one already gone is ignored.
    """
    for kill in (os.killpg, os.kill):
        with contextlib.suppress(ProcessLookupError, PermissionError, OSError):
            kill(pid, signal.SIGKILL)


@dataclass(frozen=True, slots=True)
class ChildStatus:
    """How a child ended: its exit code or the signal that killed it (both None: unknown).

    Attributes
    ----------
    exit : int or None
        The exit code.
    signal : int or None
        The number of the signal that killed it.
    """

    exit: int | None
    signal: int | None

    def reason(self) -> str:
        """How it ended, in words (``"killed by SIGKILL"``).

        Returns
        -------
        str
            The reason, for a seed's failure message.
        """
        if self.signal is not None:
            try:
                name = signal.Signals(self.signal).name
            except ValueError:
                name = f"signal {self.signal}"
            return f"killed by {name}"
        if self.exit is not None:
            return f"exited with code {self.exit} (os._exit or sys.exit outside Python's reach)"
        return "ended without a result"


class Zygote:
    """The campaign's handle on its zygote (see the module docstring).

    ``Zygote(given, memory=..., timeout=...)`` starts it and waits, at most ``timeout`` seconds,
    for the compensator to import: :class:`ZygoteError` if it raised, exited, died or hung.
    ``given`` is a ``"module:attr"`` string (imported only in the zygote) or an object: pickled
    to the zygote when it pickles, else the zygote is forked from this process (it then holds
    this process's memory: the seed list and the configuration, never a task).
    ``identity`` is the compensator's identity as the zygote computed it.

    Parameters
    ----------
    given : str or object
        The compensator: ``"module:attr"``, or an estimator, class or fit function.
    memory : int, optional
        Address-space cap of each child [bytes] (``RLIMIT_AS``); None: none.
    timeout : float, optional
        Longest wait for the compensator's import [s]; None: no limit.

    Raises
    ------
    ZygoteError
        If the import raised, exited, died or hung.
    """

    def __init__(self, given: Any, *, memory: int | None = DEFAULT_MEMORY_BYTES, timeout: float | None = None) -> None:
        self.memory = memory
        self.pid = 0
        self.forked = False
        self.shared = False
        self.import_reads: dict[str, Any] = {}
        self.import_fingerprint: dict[str, str] = {}
        parent, child = socket.socketpair(socket.AF_UNIX, socket.SOCK_SEQPACKET)
        self.ctrl = parent
        self._proc: subprocess.Popen | None = None
        rfd, wfd = os.pipe()
        try:
            pickled = None
            if not isinstance(given, str):
                try:
                    pickled = pickle.dumps(given)
                except Exception:  # noqa: BLE001 - not picklable: fork instead
                    pickled = None
                if pickled is not None and b"__main__" in pickled:  # defined in a script: a fresh
                    pickled = None  # interpreter cannot import it by reference, fork instead
            import tempfile

            fd, self._ready_file = tempfile.mkstemp(prefix="gyrobench-ready-", suffix=".json")
            os.close(fd)
            init = {
                "ready_file": self._ready_file,
                "spec": given if isinstance(given, str) else None,
                "pickled": pickled,
                "sys_path": list(sys.path),
                "cwd": os.getcwd(),
                "memory": memory,
            }
            if isinstance(given, str) or pickled is not None:
                self._start_exec(child, init, wfd)
            else:
                self._start_fork(child, given, wfd)
        finally:
            child.close()
            os.close(wfd)
        threading.Thread(target=_forward, args=(rfd,), daemon=True, name="gyrobench-compensator-output").start()
        self.identity = self._wait_ready(timeout)

    def _start_exec(self, child: socket.socket, init: Mapping[str, Any], wfd: int) -> None:
        code = f"from gyrobench.scenarios.bench.sandbox_child import zygote_main; zygote_main({child.fileno()})"
        self._proc = subprocess.Popen(  # noqa: S603 - this interpreter, a fixed command
            [sys.executable, "-c", code],
            stdin=subprocess.PIPE,
            stdout=wfd,
            stderr=wfd,
            pass_fds=(child.fileno(),),
            start_new_session=True,
            close_fds=True,
        )
        self.pid = self._proc.pid
        assert self._proc.stdin is not None
        try:
            self._proc.stdin.write(pickle.dumps(dict(init)))
            self._proc.stdin.close()
        except OSError:  # the zygote died at once: reported by _wait_ready
            pass

    def _start_fork(self, child: socket.socket, given: Any, wfd: int) -> None:
        self.forked = True
        pid = os.fork()
        if pid == 0:  # the zygote
            code = 0
            try:
                os.setsid()
                _die_with_parent()
                signal.signal(signal.SIGINT, signal.SIG_IGN)
                signal.signal(signal.SIGTERM, signal.SIG_DFL)
                self.ctrl.close()
                os.dup2(wfd, 1)
                os.dup2(wfd, 2)
                _zygote_start(child, {"object": given, "memory": self.memory, "ready_file": self._ready_file})
            except BaseException:  # noqa: BLE001
                code = 1
            finally:
                os._exit(code)
        self.pid = pid

    def _wait_ready(self, timeout: float | None) -> str:
        import select

        ready, _, _ = select.select([self.ctrl], [], [], timeout)
        if not ready:
            self.close()
            with contextlib.suppress(OSError):
                os.unlink(self._ready_file)
            raise ZygoteError(
                f"importing the compensator did not finish within {timeout:g} s; its process was killed",
                kind="hung",
            )
        try:
            raw = self.ctrl.recv(MAX_HEADER)
            head = json.loads(raw.decode("utf-8")) if raw else {}
        except (OSError, ValueError):
            head = {}
        doc: Any = None
        with contextlib.suppress(OSError, ValueError):
            with open(self._ready_file, encoding="utf-8") as f:  # noqa: PTH123
                doc = json.load(f)
        with contextlib.suppress(OSError):
            os.unlink(self._ready_file)
        msg = doc if isinstance(doc, dict) and isinstance(head, dict) and doc.get("kind") == head.get("kind") else {}
        kind = msg.get("kind")
        if kind == "ready" and isinstance(msg.get("identity"), str):
            names = msg.get("reads")
            self.import_reads = names if isinstance(names, dict) else {}
            self.import_fingerprint = reads_fingerprint(self.import_reads)
            return str(msg["identity"])
        self.close()
        if kind in ("import_named", "import_bad"):
            raise ZygoteError(_str(msg, "message"), kind=kind[7:], traceback_text=_str(msg, "traceback"))
        if kind == "import_error":
            raise ZygoteError(
                f"importing it raised {_str(msg, 'type', 200)}: "
                f"{' '.join(_str(msg, 'message').split()) or '(no message)'}",
                kind="raised",
                traceback_text=_str(msg, "traceback"),
            )
        if kind == "import_exit":
            raise ZygoteError(f"importing it called sys.exit({msg.get('code')!r})", kind="exited")
        status = self._status()
        raise ZygoteError(f"its process {status.reason()} while importing it", kind="died")

    def _status(self) -> ChildStatus:
        if self._proc is not None:
            with contextlib.suppress(subprocess.TimeoutExpired):
                rc = self._proc.wait(timeout=5.0)
                return ChildStatus(exit=rc, signal=None) if rc >= 0 else ChildStatus(exit=None, signal=-rc)
            return ChildStatus(None, None)
        with contextlib.suppress(ChildProcessError):
            _, st = os.waitpid(self.pid, 0)
            if os.WIFSIGNALED(st):
                return ChildStatus(exit=None, signal=os.WTERMSIG(st))
            return ChildStatus(exit=os.waitstatus_to_exitcode(st), signal=None)
        return ChildStatus(None, None)

    def fork(self) -> tuple[int, socket.socket]:
        """A new child for one seed.

        Returns
        -------
        pid : int
            The child's process id (the leader of its own process group).
        sock : socket.socket
            The scoring end of its socket.

        Raises
        ------
        ChildDied
            If the zygote did not fork.
        """
        mine, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_STREAM)
        try:
            socket.send_fds(self.ctrl, [b"fork"], [theirs.fileno()])
            raw = self.ctrl.recv(4096)
            pid = int(json.loads(raw.decode())["pid"])
        except (OSError, ValueError, KeyError, TypeError) as exc:
            mine.close()
            raise ChildDied(f"the compensator's process did not fork a child ({type(exc).__name__})") from None
        finally:
            theirs.close()
        return pid, mine

    def end_child(self, pid: int) -> ChildStatus:
        """Kill the child's process group and reap it.

        Parameters
        ----------
        pid : int
            The child, as :meth:`fork` returned it.

        Returns
        -------
        ChildStatus
            How it ended.
        """
        kill_group(pid)
        try:
            self.ctrl.sendall(f"reap {pid}".encode())
            st = json.loads(self.ctrl.recv(4096).decode())
            return ChildStatus(exit=st.get("exit"), signal=st.get("signal"))
        except (OSError, ValueError, AttributeError):
            return ChildStatus(None, None)

    def close(self) -> None:
        """Stop the zygote and its process group."""
        with contextlib.suppress(OSError):
            self.ctrl.sendall(b"quit")
        if self.pid:
            deadline = time.monotonic() + 0.5
            while time.monotonic() < deadline and self._alive():
                time.sleep(0.01)
            kill_group(self.pid)
            self._status()
            self.pid = 0
        with contextlib.suppress(OSError):
            self.ctrl.close()

    def _alive(self) -> bool:
        if self._proc is not None:
            return self._proc.poll() is None
        try:
            pid, _ = os.waitpid(self.pid, os.WNOHANG)
        except ChildProcessError:
            return False
        return not pid

    def __enter__(self) -> Zygote:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


# ----------------------------------------------------------------------------- reuse
#: how many zygotes :func:`shared_zygote` keeps alive in one process
SHARED_ZYGOTES = 2

_SHARED: dict[tuple, Zygote] = {}


def _close_shared() -> None:
    for z in list(_SHARED.values()):
        with contextlib.suppress(Exception):
            z.close()
    _SHARED.clear()


def shared_zygote(given: Any, *, memory: int | None, timeout: float | None) -> Zygote:
    """A zygote for ``given``: a kept one whose import-time reads are unchanged, else a new one.

    A new zygote is kept when it was exec'd; a forked one (for an object that does not pickle,
    or a script's own object) is not kept: close it after use (``zygote.shared`` is False). At
    most :data:`SHARED_ZYGOTES` are kept, the least recently used closed first.

    Parameters
    ----------
    given : str or object
        The compensator, as for :class:`Zygote`.
    memory : int or None
        Address-space cap of each child [bytes]; None: none.
    timeout : float or None
        Longest wait for a new zygote's import [s]; None: no limit.

    Returns
    -------
    Zygote
        A ready zygote.

    Raises
    ------
    ZygoteError
        If a new zygote's import raised, exited, died or hung.
    """
    import atexit

    if isinstance(given, str):
        what: Any = given
    else:
        try:
            raw = pickle.dumps(given)
        except Exception:  # noqa: BLE001 - does not pickle: a forked zygote, never kept
            return Zygote(given, memory=memory, timeout=timeout)
        if b"__main__" in raw:  # a script's own object: forked too, never kept
            return Zygote(given, memory=memory, timeout=timeout)
        what = hashlib.sha256(raw).hexdigest()
    key = (what, tuple(sys.path), os.getcwd(), memory)
    z = _SHARED.pop(key, None)
    if z is not None:
        if z._alive() and reads_fingerprint(z.import_reads) == z.import_fingerprint:
            _SHARED[key] = z  # most recently used last
            return z
        z.close()
    z = Zygote(given, memory=memory, timeout=timeout)
    if not _SHARED:
        atexit.register(_close_shared)
    z.shared = True
    _SHARED[key] = z
    while len(_SHARED) > SHARED_ZYGOTES:
        old = next(iter(_SHARED))
        _SHARED.pop(old).close()
    return z
