"""The compensator's side of the sandbox (:mod:`gyrobench.scenarios.bench.sandbox`): what its
processes record of their reads, the zygote's loop and each seed's child.

Everything here runs in the compensator's own processes, except :func:`reads_fingerprint`,
which the campaign's process also calls to fingerprint the recorded reads again. It imports
only the standard library at module level (the zygote's interpreter starts from it).
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import pickle
import signal
import socket
import sys
from collections.abc import Mapping
from typing import Any

__all__ = ["MAX_HEADER", "reads_fingerprint", "reads_names", "zygote_main"]

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
    "urllib.Request": "URLs",
}


def _send_json(conn: Any, obj: Mapping[str, Any]) -> None:
    conn.send_bytes(json.dumps(obj, default=str).encode("utf-8"))


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
            code = p.endswith((".py", ".pyc", ".so", ".pth", ".pyd"))  # module sources: in the module list
            if not code and not p.startswith(("/proc/", "/sys/", "/dev/")):
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


_STDLIB_ROOTS: tuple[str, ...] | None = None


def _is_stdlib(path: str) -> bool:
    global _STDLIB_ROOTS
    if _STDLIB_ROOTS is None:
        import sysconfig

        paths = sysconfig.get_paths()
        _STDLIB_ROOTS = tuple({paths[k].rstrip("/") + "/" for k in ("stdlib", "platstdlib") if paths.get(k)})
    return path.startswith(_STDLIB_ROOTS) and "site-packages" not in path


#: the modules loaded when the zygote said it was ready (a child reports only the others)
_BASE_MODULES: set[str] = set()


def _module_files(skip: set[str] | frozenset[str] = frozenset()) -> dict[str, str]:
    """module name -> file of every loaded module outside the standard library (but ``skip``)."""
    out = {}
    for name, mod in list(sys.modules.items()):
        if name in skip:
            continue
        path = getattr(mod, "__file__", None)
        if isinstance(path, str) and path and not _is_stdlib(path):
            out[name] = path
    return out


def reads_names(*, since_ready: bool = False) -> dict[str, Any]:
    """This process's reads, by name.

    This process's reads, by name (the fingerprints are taken by :func:`reads_fingerprint`);
    ``since_ready``: only the modules loaded after the zygote was ready (the campaign has the rest).

    Parameters
    ----------
    since_ready : bool
        Only the modules loaded after the zygote was ready.

    Returns
    -------
    dict of str to object
        The reads, by name.
    """
    return {
        "modules": _module_files(_BASE_MODULES if since_ready else frozenset()),
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
    """The fingerprint of every read named, taken now.

    ``"kind:name" -> fingerprint`` of every read named in ``names`` (:func:`reads_names`),
    taken now: user modules and files by the SHA-256 of their content, site-packages modules by
    path, size and modification time, environment variables by the SHA-256 of their value
    (``"unset"``), and the whole environment when it was iterated.

    Parameters
    ----------
    names : mapping of str to object
        The reads, by name (:func:`reads_names`).
    environ : mapping of str to str or None
        The environment (None: ``os.environ``).

    Returns
    -------
    dict of str to str
        ``"kind:name"`` -> fingerprint.
    """
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
        digest = None if v is None else hashlib.sha256(v.encode("utf-8", "surrogateescape")).hexdigest()[:16]
        out[f"env:{key}"] = "unset" if digest is None else digest
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
    return {
        "kind": "error", "stage": stage, "type": type(exc).__name__, "message": message, "traceback": text,
        "memory": isinstance(exc, MemoryError),
    }


def _adopt(environ: Any, cwd: Any) -> None:
    """Take the scoring process's environment and working folder (a zygote serves several
    campaigns: each child sees the environment its campaign runs in, as a fresh process would)."""
    if isinstance(environ, dict):
        _READS.active = False
        try:
            for key in [k for k in os.environ if k not in environ]:
                del os.environ[key]
            os.environ.update({str(k): str(v) for k, v in environ.items()})
        finally:
            _READS.active = True
    if isinstance(cwd, str):
        with contextlib.suppress(OSError):
            os.chdir(cwd)


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
            _adopt(msg.get("environ"), msg.get("cwd"))
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
            _send_json(conn, {"kind": "reads", "reads": reads_names(since_ready=True)})
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


def _ready(ctrl: socket.socket, compensator: Any, ready_file: str) -> None:
    """Say ready on the control socket; the compensator's identity and the import's reads (too
    long for one datagram) go to ``ready_file``, which the campaign made for it."""
    from gyrobench.scenarios.bench.identity import compensator_identity

    ident = compensator_identity(compensator)
    _READS.active = False  # the bench's own reading of the modules is not the compensator's
    names = reads_names()
    _BASE_MODULES.update(names["modules"])
    _report(ctrl, ready_file, {"kind": "ready", "identity": ident, "reads": names})
    _READS.active = True


def _report(ctrl: socket.socket, ready_file: str, doc: Mapping[str, Any]) -> None:
    """The zygote's answer to its start: ``doc`` in ``ready_file`` (a traceback or the module list
    can exceed one datagram), its kind on the control socket."""
    with contextlib.suppress(OSError):
        with open(ready_file, "w", encoding="utf-8") as f:  # noqa: PTH123
            json.dump(doc, f, default=str)
        ctrl.sendall(json.dumps({"kind": doc["kind"]}).encode())


def _zygote_start(ctrl: socket.socket, init: Mapping[str, Any]) -> None:
    """The zygote: import the compensator (recording its reads), say ready, serve."""
    from gyrobench.scenarios.bench.compensators import CompensatorImportError, resolve_compensator

    try:
        from threadpoolctl import threadpool_limits

        threadpool_limits(limits=1)  # the same summation order on every executor (see the package doc)
        _install_recorders()
        if "object" in init:
            given = init["object"]
        else:
            given = init["spec"] if init.get("spec") is not None else pickle.loads(init["pickled"])
        compensator = resolve_compensator(given)
        _ready(ctrl, compensator, init["ready_file"])
    except CompensatorImportError as exc:  # the user's module raised while importing: named by resolve
        doc = {"kind": "import_named", "message": str(exc), "traceback": exc.traceback_text}
        _report(ctrl, init["ready_file"], doc)
        return
    except (ValueError, TypeError) as exc:  # not importable, no such attribute, not a compensator
        _report(ctrl, init["ready_file"], {"kind": "import_bad", "message": str(exc)})
        return
    except BaseException as exc:  # noqa: BLE001 - the import's failure, in one message
        msg = _error_message(exc, "import")
        msg["kind"] = "import_" + msg["kind"]
        _report(ctrl, init["ready_file"], msg)
        return
    _zygote_loop(ctrl, compensator, init.get("memory"))


def zygote_main(fd: int) -> None:
    """Entry point of the exec'd zygote (``python -c``): the init message is on stdin.

    Parameters
    ----------
    fd : int
        The socket's file descriptor.
    """
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


