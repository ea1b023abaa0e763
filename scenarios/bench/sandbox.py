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
noise floor (:func:`gyrobench.scenarios.bench.scoring.floor_failure`) is what catches such a
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
modification time (:func:`reads_fingerprint`). Network connections, subprocesses and
``ctypes`` loads are noted by name (what they read is not seen).
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
]

#: default per-seed address-space cap of the compensator's process [bytes] (4 GiB; ``bench
#: --seed-memory``). The zygote with numpy and scikit-learn imported maps about 1 GiB.
DEFAULT_MEMORY_BYTES = 4 * 1024**3

#: largest JSON header accepted from a child [bytes] (a traceback fits)
MAX_HEADER = 1 << 20

#: prctl option: the signal a process gets when its parent dies (linux/prctl.h)
_PR_SET_PDEATHSIG = 1

#: audit events whose reads the identity cannot see (named in the campaign's warning)
_UNSEEN_EVENTS = {
    "socket.connect": "network connections",
    "subprocess.Popen": "subprocesses",
    "os.system": "subprocesses",
    "os.exec": "subprocesses",
    "os.posix_spawn": "subprocesses",
    "ctypes.dlopen": "ctypes libraries",
    "urllib.Request": "URLs",
}


class ZygoteError(Exception):
    """The compensator's process could not be made ready: its import raised, exited or hung.

    ``kind`` is ``"raised"``, ``"exited"``, ``"hung"`` or ``"died"``; ``traceback_text`` holds
    the import's traceback when it raised.
    """

    def __init__(self, message: str, *, kind: str, traceback_text: str = "") -> None:
        super().__init__(message)
        self.kind = kind
        self.traceback_text = traceback_text


class RemoteError(Exception):
    """The compensator raised in its child; ``remote_type`` is the exception's class name."""

    def __init__(self, message: str, *, remote_type: str, traceback_text: str = "", memory: bool = False) -> None:
        super().__init__(message)
        self.remote_type = remote_type
        self.traceback_text = traceback_text
        self.memory = memory


class RemoteExit(SystemExit):
    """The compensator called ``sys.exit`` in its child (re-raised in the scoring process)."""


class ChildDied(Exception):
    """The child ended (or sent something unreadable) before answering; ``timeout`` [s] is set
    when it was the seed's deadline that passed."""

    def __init__(self, message: str = "", *, timeout: float | None = None) -> None:
        super().__init__(message)
        self.timeout = timeout


class MemoryExceeded(ChildDied):
    """The compensator raised ``MemoryError`` in its child (the per-seed memory cap)."""


# ----------------------------------------------------------------------------- wire format
def recv_json(conn: Any, maxlength: int = MAX_HEADER) -> dict[str, Any]:
    """One JSON object from a child, at most ``maxlength`` bytes (:class:`ChildDied` otherwise)."""
    try:
        raw = conn.recv_bytes(maxlength)
        obj = json.loads(raw.decode("utf-8"))
    except (EOFError, OSError, UnicodeDecodeError, ValueError) as exc:
        raise ChildDied(f"no readable answer ({type(exc).__name__})") from None
    if not isinstance(obj, dict) or not isinstance(obj.get("kind"), str):
        raise ChildDied("an answer that is not a message")
    return obj


def _send_json(conn: Any, obj: Mapping[str, Any]) -> None:
    conn.send_bytes(json.dumps(obj, default=str).encode("utf-8"))


def _str(obj: Mapping[str, Any], key: str, limit: int = 20000) -> str:
    v = obj.get(key, "")
    return (v if isinstance(v, str) else repr(v))[:limit]


class RemoteCompensator:
    """The scoring process's handle on one child: ``fit`` then ``predict`` per held-out run.

    Every answer is parsed strictly (:func:`recv_json`, raw float64 bytes of the announced
    shape). A child error is raised as :class:`RemoteError` (``MemoryError`` flagged), a
    ``sys.exit`` as :class:`RemoteExit`, a dead or garbled child as :class:`ChildDied`.
    """

    def __init__(self, conn: Any, *, deadline: float | None = None, timeout: float | None = None) -> None:
        self.conn = conn
        self.deadline = deadline  # time.monotonic() past which no answer is awaited
        self.timeout = timeout

    def _request(self, msg: Mapping[str, Any]) -> dict[str, Any]:
        try:
            self.conn.send(dict(msg))
        except (OSError, EOFError, ValueError) as exc:
            raise ChildDied(f"the request could not be sent ({type(exc).__name__})") from None
        return self._answer()

    def _answer(self) -> dict[str, Any]:
        if self.deadline is not None:
            left = self.deadline - time.monotonic()
            if left <= 0 or not self.conn.poll(left):
                raise ChildDied("the seed's deadline passed", timeout=self.timeout or 0.0)
        ans = recv_json(self.conn)
        kind = ans["kind"]
        if kind == "error" and _str(ans, "type", 200) == "MemoryError":
            raise MemoryExceeded(_str(ans, "message"))
        if kind == "error":
            raise RemoteError(
                _str(ans, "message"), remote_type=_str(ans, "type", 200), traceback_text=_str(ans, "traceback"),
                memory=_str(ans, "type", 200) == "MemoryError",
            )
        if kind == "exit":
            raise RemoteExit(ans.get("code") if isinstance(ans.get("code"), (int, str, type(None))) else None)
        return ans

    def fit(self, X: Any, y: Any, groups: Any, random_state: int) -> None:
        """Send the training data; return when the child has fitted."""
        ans = self._request({"op": "fit", "X": X, "y": y, "groups": groups, "random_state": int(random_state)})
        if ans["kind"] != "fitted":
            raise ChildDied(f"an unexpected answer {ans['kind'][:40]!r} to fit")

    def predict(self, X: Any) -> Any:
        """The child's prediction on ``X``: a float64 array, or an empty complex array of the
        child's dtype when it predicted complex values."""
        import numpy as np

        ans = self._request({"op": "predict", "X": X})
        if ans["kind"] == "complex":
            dtype = _str(ans, "dtype", 40)
            return np.zeros(0, dtype=dtype if dtype in ("complex64", "complex128", "complex256") else complex)
        shape = ans.get("shape")
        if ans["kind"] != "pred" or not isinstance(shape, list) or not all(
            isinstance(s, int) and not isinstance(s, bool) and 0 <= s < 2**40 for s in shape
        ) or len(shape) > 8:
            raise ChildDied("a prediction header that is not valid")
        count = 1
        for s in shape:
            count *= s
        nbytes = 8 * count
        try:
            raw = self.conn.recv_bytes(max(1, nbytes))
        except (EOFError, OSError) as exc:
            raise ChildDied(f"the prediction did not arrive ({type(exc).__name__})") from None
        if len(raw) != nbytes:
            raise ChildDied(f"a prediction of {len(raw)} bytes where its header announced {nbytes}")
        return np.frombuffer(raw, dtype="<f8").reshape(shape).astype(float)

    def finish(self) -> dict[str, Any]:
        """Ask for the child's reads (its manifest) and let it exit; ``{}`` if it cannot answer."""
        try:
            ans = self._request({"op": "end"})
        except (ChildDied, RemoteError, RemoteExit):
            return {}
        reads = ans.get("reads")
        return reads if ans["kind"] == "reads" and isinstance(reads, dict) else {}


# ----------------------------------------------------------------------------- reads
class _Reads:
    """What this process read: files opened for reading, environment variables, unseen kinds."""

    def __init__(self) -> None:
        self.files: set[str] = set()
        self.env: set[str] = set()
        self.env_all = False
        self.unseen: set[str] = set()
        self.active = True


_READS = _Reads()


def _audit(event: str, args: tuple) -> None:
    if not _READS.active:
        return
    if event == "open":
        try:
            path, mode, flags = args[0], args[1], args[2]
        except (IndexError, TypeError):
            return
        if isinstance(path, int) or path is None:
            return
        if isinstance(mode, str):
            reading = not any(c in mode for c in "wax+")
        else:
            reading = isinstance(flags, int) and (flags & os.O_ACCMODE) == os.O_RDONLY
        if reading:
            p = os.fsdecode(path)
            if not p.endswith((".py", ".pyc", ".so", ".pth", ".pyd")) and not p.startswith(("/proc/", "/sys/", "/dev/")):
                _READS.files.add(os.path.abspath(p))
    elif event in _UNSEEN_EVENTS:
        _READS.unseen.add(_UNSEEN_EVENTS[event])


def _install_recorders() -> None:
    """The audit hook (files opened, unseen kinds) and a recording ``os.environ``."""
    sys.addaudithook(_audit)
    base = type(os.environ)

    class _RecordingEnviron(base):  # type: ignore[misc, valid-type]
        def __getitem__(self, key: Any) -> Any:
            if _READS.active:
                _READS.env.add(str(key))
            return super().__getitem__(key)

        def __iter__(self) -> Any:
            if _READS.active:
                _READS.env_all = True
            return super().__iter__()

    os.environ.__class__ = _RecordingEnviron


def _is_stdlib(path: str) -> bool:
    import sysconfig

    for key in ("stdlib", "platstdlib"):
        root = sysconfig.get_paths().get(key)
        if root and path.startswith(root.rstrip("/") + "/") and "site-packages" not in path:
            return True
    return False


def _module_files() -> dict[str, str]:
    """module name -> file of every loaded module outside the standard library."""
    out = {}
    for name, mod in list(sys.modules.items()):
        path = getattr(mod, "__file__", None)
        if isinstance(path, str) and path and not _is_stdlib(path):
            out[name] = path
    return out


def _reads_names() -> dict[str, Any]:
    """This process's reads, by name (the fingerprints are taken by :func:`reads_fingerprint`)."""
    return {
        "modules": _module_files(),
        "files": sorted(_READS.files),
        "env": sorted(_READS.env),
        "env_all": _READS.env_all,
        "unseen": sorted(_READS.unseen),
    }


def _file_fingerprint(path: str, *, content: bool) -> str:
    try:
        if not content:
            st = os.stat(path)
            return f"size {st.st_size} mtime {st.st_mtime_ns}"
        h = hashlib.sha256()
        with open(path, "rb") as f:  # noqa: PTH123 - a raw read of any file
            for block in iter(lambda: f.read(1 << 20), b""):
                h.update(block)
        return h.hexdigest()[:32]
    except OSError:
        return "unreadable"


def reads_fingerprint(names: Mapping[str, Any], environ: Mapping[str, str] | None = None) -> dict[str, str]:
    """``"kind:name" -> fingerprint`` of every read named in ``names`` (:func:`_reads_names`),
    taken now: user modules and files by the SHA-256 of their content, site-packages modules by
    path, size and modification time, environment variables by the SHA-256 of their value
    (``"unset"``), and the whole environment when it was iterated."""
    env = os.environ if environ is None else environ
    out: dict[str, str] = {}
    for name, path in sorted(dict(names.get("modules") or {}).items()):
        third = "site-packages" in path or "dist-packages" in path
        out[f"module:{name}"] = f"{path} " + _file_fingerprint(path, content=not third)
    for path in names.get("files") or ():
        out[f"file:{path}"] = _file_fingerprint(path, content=True)
    keys = sorted(env) if names.get("env_all") else names.get("env") or ()
    for key in keys:
        v = env.get(key)
        out[f"env:{key}"] = "unset" if v is None else hashlib.sha256(v.encode("utf-8", "surrogateescape")).hexdigest()[:16]
    return out


# ----------------------------------------------------------------------------- child side
def _die_with_parent() -> None:
    if sys.platform.startswith("linux"):
        import ctypes

        with contextlib.suppress(OSError, AttributeError):
            ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)


def _error_message(exc: BaseException, stage: str) -> dict[str, Any]:
    import traceback

    if isinstance(exc, SystemExit):
        code = exc.code if isinstance(exc.code, (int, str, type(None))) else repr(exc.code)
        return {"kind": "exit", "stage": stage, "code": code}
    try:
        text = "".join(traceback.format_exception(exc))
    except BaseException:  # noqa: BLE001 - an exception whose formatting raises
        text = ""
    try:
        message = str(exc)
    except BaseException:  # noqa: BLE001
        message = "(its message cannot be shown)"
    return {"kind": "error", "stage": stage, "type": type(exc).__name__, "message": message, "traceback": text}


def _serve_seed(conn: Any, compensator: Any) -> None:
    """One child: fit, predict on request, report the reads, exit."""
    import numpy as np
    from gyrobench.scenarios.bench.compensators import fit_user_code, predictor_of

    predict = None
    while True:
        try:
            msg = conn.recv()
        except (EOFError, OSError):
            return
        op = msg.get("op") if isinstance(msg, dict) else None
        if op == "fit":
            try:
                predict = predictor_of(
                    compensator, fit_user_code(compensator, msg["X"], msg["y"], msg["random_state"], msg["groups"])
                )
                reply: dict[str, Any] = {"kind": "fitted"}
            except BaseException as exc:  # noqa: BLE001 - everything the user's code raises is reported
                reply = _error_message(exc, "fit")
            _send_json(conn, reply)
        elif op == "predict" and predict is not None:
            try:
                raw = predict(msg["X"])
                if np.iscomplexobj(raw):
                    _send_json(conn, {"kind": "complex", "dtype": str(np.asarray(raw).dtype)})
                    continue
                pred = np.ascontiguousarray(np.asarray(raw, dtype=float), dtype="<f8")
            except BaseException as exc:  # noqa: BLE001
                _send_json(conn, _error_message(exc, "predict"))
                continue
            _send_json(conn, {"kind": "pred", "shape": list(pred.shape)})
            conn.send_bytes(pred.tobytes())
        elif op == "end":
            _READS.active = False
            _send_json(conn, {"kind": "reads", "reads": _reads_names()})
            return
        else:
            return


def _child_main(sock: socket.socket, compensator: Any, memory: int | None) -> None:
    """A forked child of the zygote: own session, memory cap, serve one seed, ``os._exit``."""
    from multiprocessing.connection import Connection

    code = 0
    try:
        os.setsid()
        _die_with_parent()
        if memory is not None:
            import resource

            resource.setrlimit(resource.RLIMIT_AS, (int(memory), int(memory)))
        _serve_seed(Connection(sock.detach()), compensator)
    except BaseException:  # noqa: BLE001 - nothing the user's code raises leaves this process
        code = 1
    finally:
        with contextlib.suppress(BaseException):
            sys.stdout.flush()
            sys.stderr.flush()
        os._exit(code)


def _recv_ctrl(ctrl: socket.socket) -> tuple[bytes, list[int]]:
    msg, fds, _flags, _addr = socket.recv_fds(ctrl, 4096, 4)
    return msg, list(fds)


def _zygote_loop(ctrl: socket.socket, compensator: Any, memory: int | None) -> None:
    """Serve the campaign's requests: ``fork`` (with one socket), ``reap PID``, ``quit``."""
    while True:
        try:
            msg, fds = _recv_ctrl(ctrl)
        except OSError:
            return
        if not msg or msg == b"quit":
            return
        if msg == b"fork" and len(fds) == 1:
            sock = socket.socket(fileno=fds[0])
            pid = os.fork()
            if pid == 0:
                ctrl.close()
                _child_main(sock, compensator, memory)
            sock.close()
            ctrl.sendall(json.dumps({"pid": pid}).encode())
        elif msg.startswith(b"reap "):
            for fd in fds:
                os.close(fd)
            status: dict[str, Any] = {"exit": None, "signal": None}
            try:
                _, st = os.waitpid(int(msg[5:]), 0)
                if os.WIFSIGNALED(st):
                    status["signal"] = os.WTERMSIG(st)
                else:
                    status["exit"] = os.waitstatus_to_exitcode(st)
            except (ChildProcessError, ValueError):
                pass
            ctrl.sendall(json.dumps(status).encode())
        else:
            for fd in fds:
                os.close(fd)


def _ready(ctrl: socket.socket, compensator: Any, given: Any) -> None:
    from gyrobench.scenarios.bench.identity import compensator_identity

    ctrl.sendall(json.dumps({"kind": "ready", "identity": compensator_identity(compensator)}).encode())
    del given


def _zygote_start(ctrl: socket.socket, init: Mapping[str, Any]) -> None:
    """The zygote: import the compensator (recording its reads), say ready, serve."""
    from gyrobench.scenarios.bench.compensators import resolve_compensator

    _install_recorders()
    try:
        from threadpoolctl import threadpool_limits

        threadpool_limits(limits=1)  # the same summation order on every executor (see the package doc)
        if "object" in init:
            given = init["object"]
        else:
            given = init["spec"] if init.get("spec") is not None else pickle.loads(init["pickled"])
        compensator = resolve_compensator(given)
        _ready(ctrl, compensator, given)
    except BaseException as exc:  # noqa: BLE001 - the import's failure, in one message
        msg = _error_message(exc, "import")
        msg["kind"] = "import_" + msg["kind"]
        with contextlib.suppress(OSError):
            ctrl.sendall(json.dumps(msg, default=str).encode())
        return
    _zygote_loop(ctrl, compensator, init.get("memory"))


def zygote_main(fd: int) -> None:
    """Entry point of the exec'd zygote (``python -c``): the init message is on stdin."""
    code = 0
    try:
        _die_with_parent()
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        init = pickle.loads(sys.stdin.buffer.read())
        sys.path[:] = list(init["sys_path"])
        os.chdir(init["cwd"])
        _zygote_start(socket.socket(fileno=fd), init)
    except BaseException:  # noqa: BLE001
        code = 1
    finally:
        with contextlib.suppress(BaseException):
            sys.stdout.flush()
            sys.stderr.flush()
        os._exit(code)


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
    """SIGKILL process ``pid`` and its process group (a child is the leader of its own)."""
    for kill in (os.killpg, os.kill):
        with contextlib.suppress(ProcessLookupError, PermissionError, OSError):
            kill(pid, signal.SIGKILL)


@dataclass(frozen=True, slots=True)
class ChildStatus:
    """How a child ended: its exit code or the signal that killed it (both None: unknown)."""

    exit: int | None
    signal: int | None

    def reason(self) -> str:
        if self.signal is not None:
            try:
                name = signal.Signals(self.signal).name
            except ValueError:
                name = f"signal {self.signal}"
            return f"was killed by {name}"
        if self.exit is not None:
            return f"exited with code {self.exit} (os._exit, or an exit outside Python's reach)"
        return "ended without a result"


class Zygote:
    """The campaign's handle on its zygote (see the module docstring).

    ``Zygote(given, memory=..., timeout=...)`` starts it and waits, at most ``timeout`` seconds,
    for the compensator to import: :class:`ZygoteError` if it raised, exited, died or hung.
    ``given`` is a ``"module:attr"`` string (imported only in the zygote) or an object: pickled
    to the zygote when it pickles, else the zygote is forked from this process (it then holds
    this process's memory: the seed list and the configuration, never a task).
    ``identity`` is the compensator's identity as the zygote computed it.
    """

    def __init__(self, given: Any, *, memory: int | None = DEFAULT_MEMORY_BYTES, timeout: float | None = None) -> None:
        self.memory = memory
        self.pid = 0
        self.forked = False
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
            init = {
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
        code = f"from gyrobench.scenarios.bench.sandbox import zygote_main; zygote_main({child.fileno()})"
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
                _zygote_start(child, {"object": given, "memory": self.memory})
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
            raise ZygoteError(
                f"importing the compensator did not finish within {timeout:g} s (the per-seed time limit, "
                "--seed-timeout); its process was killed",
                kind="hung",
            )
        try:
            raw = self.ctrl.recv(MAX_HEADER)
            msg = json.loads(raw.decode("utf-8")) if raw else {}
        except (OSError, ValueError):
            msg = {}
        kind = msg.get("kind") if isinstance(msg, dict) else None
        if kind == "ready" and isinstance(msg.get("identity"), str):
            return str(msg["identity"])
        self.close()
        if kind == "import_error":
            raise ZygoteError(
                f"importing it raised {_str(msg, 'type', 200)}: {' '.join(_str(msg, 'message').split()) or '(no message)'}",
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
        """A new child for one seed: (its pid, the scoring end of its socket)."""
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
        """Kill the child's process group and reap it: how it ended."""
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
