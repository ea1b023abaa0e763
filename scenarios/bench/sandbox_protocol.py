"""The scoring process's side of the sandbox protocol: reading a child's answers and the
errors that say how a child's work ended (:mod:`gyrobench.scenarios.bench.sandbox` starts the
processes; :mod:`gyrobench.scenarios.bench.sandbox_child` is the compensator's side).

Scoring process -> child: pickled dicts (the child may trust its parent). Child -> scoring
process: never pickled (unpickling runs code): a JSON header (:func:`recv_json`, at most
:data:`~gyrobench.scenarios.bench.sandbox_child.MAX_HEADER` bytes) and, for a prediction, the
raw little-endian float64 bytes, checked against the header's shape before
:func:`numpy.frombuffer`.
"""

from __future__ import annotations

import json
import os
import time
from collections.abc import Mapping
from typing import Any

from gyrobench.scenarios.bench.sandbox_child import MAX_HEADER

__all__ = [
    "ChildDied",
    "MemoryExceeded",
    "RemoteCompensator",
    "RemoteError",
    "RemoteExit",
    "recv_json",
]


class RemoteError(Exception):
    """The compensator raised in its child.

    Parameters
    ----------
    message : str
        The child's exception message.
    remote_type : str
        The exception's class name.
    traceback_text : str
        The child's traceback (``""``: none sent).
    """

    def __init__(self, message: str, *, remote_type: str, traceback_text: str = "") -> None:
        super().__init__(message)
        self.remote_type = remote_type
        self.traceback_text = traceback_text

    def __reduce__(self):  # keyword-only fields: rebuilt by name when it crosses a process boundary
        return (_remote_error, (str(self), self.remote_type, self.traceback_text))


def _remote_error(message: str, remote_type: str, traceback_text: str) -> RemoteError:
    return RemoteError(message, remote_type=remote_type, traceback_text=traceback_text)


class RemoteExit(SystemExit):
    """The compensator called ``sys.exit`` in its child (re-raised in the scoring process)."""


class ChildDied(Exception):
    """The child ended (or sent something unreadable) before answering.

    Parameters
    ----------
    message : str
        What was seen.
    timeout : float, optional
        The seed's time limit [s], set when it was the seed's deadline that passed.
    """

    def __init__(self, message: str = "", *, timeout: float | None = None) -> None:
        super().__init__(message)
        self.timeout = timeout


class MemoryExceeded(ChildDied):
    """The compensator raised ``MemoryError`` in its child (the per-seed memory cap).

    Parameters
    ----------
    message : str
        The child's message.
    timeout : float, optional
        Unused (None): a memory failure is not a deadline.
    """


def recv_json(conn: Any, maxlength: int = MAX_HEADER) -> dict[str, Any]:
    """One JSON message from a child, read strictly.

    Parameters
    ----------
    conn : multiprocessing.connection.Connection
        The scoring end of the child's socket.
    maxlength : int
        Largest message accepted [bytes].

    Returns
    -------
    dict
        The message: a JSON object with a string ``"kind"``.

    Raises
    ------
    ChildDied
        If nothing readable arrives, the message is longer than ``maxlength``, not UTF-8 JSON,
        or not an object with a ``"kind"``.
    """
    try:
        raw = conn.recv_bytes(maxlength)
        obj = json.loads(raw.decode("utf-8"))
    except (EOFError, OSError, UnicodeDecodeError, ValueError) as exc:
        raise ChildDied(f"no readable answer ({type(exc).__name__})") from None
    if not isinstance(obj, dict) or not isinstance(obj.get("kind"), str):
        raise ChildDied("an answer that is not a message")
    return obj




def _str(obj: Mapping[str, Any], key: str, limit: int = 20000) -> str:
    v = obj.get(key, "")
    return (v if isinstance(v, str) else repr(v))[:limit]


class RemoteCompensator:
    """The scoring process's handle on one child: ``fit`` then ``predict`` per held-out run.

    Every answer is parsed strictly (:func:`recv_json`, raw float64 bytes of the announced
    shape). A child error is raised as :class:`RemoteError` (``MemoryError`` flagged), a
    ``sys.exit`` as :class:`RemoteExit`, a dead or garbled child as :class:`ChildDied`.

    Parameters
    ----------
    conn : multiprocessing.connection.Connection
        The scoring end of the child's socket.
    deadline : float, optional
        ``time.monotonic()`` value [s] past which no answer is awaited (None: wait forever).
    timeout : float, optional
        The seed's time limit [s], reported in the :class:`ChildDied` of a passed deadline.
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
        if kind == "error" and ans.get("memory") is True:
            raise MemoryExceeded(_str(ans, "message"))
        if kind == "error":
            raise RemoteError(
                _str(ans, "message"), remote_type=_str(ans, "type", 200), traceback_text=_str(ans, "traceback"),
            )
        if kind == "exit":
            raise RemoteExit(ans.get("code") if isinstance(ans.get("code"), (int, str, type(None))) else None)
        return ans

    def fit(self, X: Any, y: Any, groups: Any, random_state: int) -> None:
        """Send the training data; return when the child has fitted.

        Parameters
        ----------
        X : numpy.ndarray
            Training features, shape (n, k).
        y : numpy.ndarray
            Training target, shape (n,) [the task's unit].
        groups : numpy.ndarray or None
            Training group of each sample (runs), or None.
        random_state : int
            The compensator's seed.
        """
        ans = self._request({
            "op": "fit", "X": X, "y": y, "groups": groups, "random_state": int(random_state),
            "environ": dict(os.environ), "cwd": os.getcwd(),
        })
        if ans["kind"] != "fitted":
            raise ChildDied(f"an unexpected answer {ans['kind'][:40]!r} to fit")

    def predict(self, X: Any) -> Any:
        """The child's prediction on ``X``.

        Parameters
        ----------
        X : numpy.ndarray
            Held-out features, shape (n, k).

        Returns
        -------
        numpy.ndarray
            A float64 array of the announced shape, or an empty complex array of the child's
            dtype when it predicted complex values (refused by the scorer).
        """
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
        """Ask for the child's reads (its manifest) and let it exit.

        Returns
        -------
        dict
            The modules, files and environment variables the child read; ``{}`` if it cannot
            answer.
        """
        try:
            ans = self._request({"op": "end"})
        except (ChildDied, RemoteError, RemoteExit):
            return {}
        reads = ans.get("reads")
        return reads if ans["kind"] == "reads" and isinstance(reads, dict) else {}
