"""Exit statuses of the ``gyrobench`` command line, in one place.

=====  ==============================================================================
code   meaning
=====  ==============================================================================
0      success
1      ``bench --baseline``: a score is significantly worse than the baseline
2      bad input: an argument, file, configuration or compensator module is wrong, or
       the run would need more memory or disk than there is (one line on stderr)
3      ``bench``: the compensator failed on some seeds (non-finite or complex
       predictions or scores, ``sys.exit``/``os._exit``, a crash, past the seed time
       limit); the line names the seeds and the reasons. A campaign with a failed seed never passes
       a ``--baseline`` comparison and is never saved as a baseline; or the
       ``--baseline`` comparison cannot be made once the campaign has run (no seed or
       no score can be paired)
4      internal failure: a worker process was killed (SIGKILL, out of memory), two runs of
       the same campaign on one database disagree (a non-deterministic scenario or
       compensator), or an unexpected error (a bug: please report it)
5      ``allan``: a channel is not stationary (motion or steps found): its noise terms
       describe the motion too. The report is still written; ``--accept-nonstationary``
       exits 0 instead
130    interrupted (Ctrl-C, SIGINT): one line; local worker processes are killed
143    terminated (SIGTERM): one line; local worker processes are killed
=====  ==============================================================================

Every failure prints one line ``gyrobench: error: ...`` on stderr; with
``GYROBENCH_TRACEBACK=1`` in the environment the traceback is printed before it.
"""

from __future__ import annotations

import os

__all__ = [
    "OK",
    "REGRESSION",
    "BAD_INPUT",
    "FAILED_SEEDS",
    "INTERNAL",
    "NONSTATIONARY",
    "INTERRUPTED",
    "TERMINATED",
    "PIPE_CLOSED",
    "Terminated",
    "TRACEBACK_ENV",
    "InternalError",
    "traceback_wanted",
]

OK = 0
REGRESSION = 1
BAD_INPUT = 2
FAILED_SEEDS = 3
INTERNAL = 4
NONSTATIONARY = 5
INTERRUPTED = 130
TERMINATED = 143  # 128 + SIGTERM, as a shell reports a process killed by it
PIPE_CLOSED = 141  # 128 + SIGPIPE: the reader of stdout went away (``| head``); nothing is printed

#: environment variable: when set (to anything but "" or "0"), errors print their traceback
TRACEBACK_ENV = "GYROBENCH_TRACEBACK"


class Terminated(KeyboardInterrupt):
    """Raised in the main thread by SIGTERM while a verb runs (exit 143).

    Raised in the main thread by SIGTERM while a verb runs (exit 143). A KeyboardInterrupt, so
    every cleanup that Ctrl-C runs (killing local workers, closing stores) runs for it too.
    """


class InternalError(RuntimeError):
    """A failure that is not the user's input: a worker died, runs disagree (exit 4)."""


def traceback_wanted() -> bool:
    """Whether :data:`TRACEBACK_ENV` asks for tracebacks.

    Returns
    -------
    bool
        True when the variable is set to anything but ``""`` or ``"0"``.
    """
    return os.environ.get(TRACEBACK_ENV, "") not in ("", "0")
