"""The ``gyrobench`` command line.

::

    gyrobench list
    gyrobench simulate noise --N 0.01 --B 0.05 --fs 100 --duration 2h --seed 1 -o rec.h5
    gyrobench simulate SCENARIO --seed 1 --out DIR [--config FILE.toml]
    gyrobench allan FILE [--column NAME ...|--all-axes] [--fs HZ] [--units deg/s] [--start S --stop S]
                    [--tau-min S|auto --tau-max S --bandwidth HZ --terms N,B,K] [--temperature COL]
                    [--kind K] [--json] [--plot FILE.png] [--kalibr FILE.yaml]
    gyrobench reproduce --all --out DIR [--seed S] [--units N] [--workers N | --scheduler ADDR] [--db FILE]
    gyrobench reproduce SCENARIO [SCENARIO ...] --out DIR
    gyrobench bench SCENARIO --compensator module:attr --seeds 0:100

Exit status: the codes of :mod:`gyrobench.scenarios.cli.exits`, listed in ``gyrobench --help``
(built from them). Every error is one readable line on stderr, no traceback
(``GYROBENCH_TRACEBACK=1`` shows it).
"""

from __future__ import annotations

import argparse
import re
import sys
import typing
import warnings
from pathlib import Path

from gyrobench.scenarios.cli import exits
from gyrobench.scenarios.cli.common import Parser, one_line

__all__ = ["main"]

#: exceptions that mean "bad input": reported in one line, exit 2
_INPUT_ERRORS: tuple[type[BaseException], ...] = (
    ValueError, TypeError, KeyError, FileNotFoundError, IsADirectoryError, PermissionError
)


# ----------------------------------------------------------------------------- list
def _cmd_list(args) -> int:
    from gyrobench.scenarios import registry
    from gyrobench.scenarios.papers import citation

    for name in registry.available():
        info = registry.describe(name)
        bench = " [bench]" if info.bench else ""
        print(f"{name:<20} {info.title}{bench}")
        if info.paper is not None:
            print(f"{'':<20}   paper {info.paper}: {citation(info.paper)}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    p = Parser(prog="gyrobench", description="Gyroscope simulator and test bench.",
               epilog=f"exit status: {exits.OK} ok; {exits.REGRESSION} bench: significant regression; "
                       f"{exits.BAD_INPUT} bad input (one line on stderr); {exits.FAILED_SEEDS} bench: the "
                       "compensator failed on some seeds, or a --baseline comparison could not be made; "
                       f"{exits.INTERNAL} internal failure (a worker died, non-deterministic runs, a bug); "
                       f"{exits.NONSTATIONARY} allan: a channel is not stationary (motion or steps; "
                       f"--accept-nonstationary exits {exits.OK}); {exits.INTERRUPTED} interrupted; "
                       f"{exits.PIPE_CLOSED} the output pipe closed (| head); {exits.TERMINATED} terminated. "
                       f"{exits.TRACEBACK_ENV}=1 prints the traceback of an error.")
    p.add_argument("--version", action="version", version=f"gyrobench {_version()}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=Parser)

    s = sub.add_parser("list", help="list the registered scenarios")
    s.set_defaults(func=_cmd_list)

    from gyrobench.scenarios.cli import (
        allan as cli_allan,
    )
    from gyrobench.scenarios.cli import bench as bench_cli
    from gyrobench.scenarios.cli import (
        reproduce as cli_reproduce,
    )
    from gyrobench.scenarios.cli import (
        simulate as cli_simulate,
    )
    from gyrobench.scenarios.cli import (
        twin as cli_twin,
    )

    cli_simulate.add_parsers(sub)
    cli_allan.add_parser(sub)
    cli_reproduce.add_parser(sub)
    bench_cli.add_parser(sub)
    cli_twin.add_parser(sub)
    return p


def _version() -> str:
    from gyrobench import __version__

    return __version__


#: options whose value may start with "-" (argparse would take "--duration -5s" for two options)
_VALUE_OPTIONS = ("--duration", "--fs", "--Q", "--N", "--B", "--K", "--R", "--seed", "--chunk")
_NEGATIVE_VALUE = re.compile(r"^-(?:[0-9.]|inf|nan)", re.IGNORECASE)


def _attach_negative_values(argv: list[str]) -> list[str]:
    """``--duration -5s`` -> ``--duration=-5s``, so the value is parsed and refused with its own message."""
    out: list[str] = []
    i = 0
    while i < len(argv):
        a = argv[i]
        if a == "--":
            out.extend(argv[i:])
            break
        if a in _VALUE_OPTIONS and i + 1 < len(argv) and _NEGATIVE_VALUE.match(argv[i + 1]):
            out.append(f"{a}={argv[i + 1]}")
            i += 2
            continue
        out.append(a)
        i += 1
    return out


def _error_status(exc: BaseException) -> tuple[int, str]:
    """(exit status, one-line message) for an exception leaving a verb (see scenarios.exits)."""
    from gyrobench.scenarios.cli import exits

    bench = sys.modules.get("gyrobench.scenarios.bench")
    if bench is not None and isinstance(exc, (bench.FailedSeedsError, bench.ComparisonError)):
        return exits.FAILED_SEEDS, one_line(exc)
    if isinstance(exc, exits.InternalError):
        return exits.INTERNAL, f"internal failure: {one_line(exc)}"
    if isinstance(exc, _INPUT_ERRORS):
        msg = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
        return exits.BAD_INPUT, one_line(msg)
    if isinstance(exc, OverflowError):  # a number too large for the computation: an input value
        return exits.BAD_INPUT, f"a value is too large to compute with ({one_line(exc)}); check the inputs"
    if isinstance(exc, MemoryError):
        return exits.BAD_INPUT, ("out of memory: the run needs more memory than is available "
                                 "(shorten the record, lower fs or use fewer seeds)")
    if isinstance(exc, OSError):  # a failed write (AtomicWriteError names the target), an unreadable input
        return exits.BAD_INPUT, one_line(exc)
    import sqlite3

    if isinstance(exc, sqlite3.Error):
        return exits.BAD_INPUT, f"database error: {one_line(exc)}"
    return exits.INTERNAL, (f"internal failure ({type(exc).__name__}: {one_line(exc) or 'no message'}); "
                            f"this is a bug: please report it with the output of GYROBENCH_TRACEBACK=1")


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """Warnings in one line each, without the source line Python prints under them."""
    where = Path(str(filename)).name
    from gyrobench.base.safety import escape_controls

    print(f"gyrobench: warning: {escape_controls(one_line(message))} ({category.__name__} in {where}:{lineno})",
          file=sys.stderr if file is None else file)


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``gyrobench`` console script; returns the exit status.

    Exit statuses are listed in :mod:`gyrobench.scenarios.cli.exits`: 0 ok, 1 significant
    regression, 2 bad input, 3 failed seeds, 4 internal failure, 130 interrupted. Every
    error is one line on stderr; ``GYROBENCH_TRACEBACK=1`` prints the traceback first.

    Parameters
    ----------
    argv : list of str or None
        The arguments (None: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status.
    """
    from gyrobench.base.safety import escape_controls
    from gyrobench.scenarios.cli import exits

    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser()
    args = parser.parse_args(_attach_negative_values(argv))
    args.argv = argv
    restore = _raise_on_sigterm()
    stdout = sys.stdout
    sys.stdout = _EscapedStream(stdout)  # text from files (a column name, a label) never drives the terminal
    try:
        with warnings.catch_warnings():
            warnings.showwarning = _show_warning
            return int(args.func(args) or 0)
    except exits.Terminated:
        print("gyrobench: error: terminated (SIGTERM)", file=sys.stderr)
        return exits.TERMINATED
    except KeyboardInterrupt:
        print("gyrobench: interrupted", file=sys.stderr)
        return exits.INTERRUPTED
    except BrokenPipeError:  # stdout's reader left (``| head``): stop quietly, as a shell tool does
        _silence_stdout()
        return exits.PIPE_CLOSED
    except Exception as exc:
        code, msg = _error_status(exc)
        if exits.traceback_wanted():
            text = getattr(exc, "traceback_text", "")  # a compensator's, from its worker process
            if text:
                sys.stderr.write(text)
            else:
                import traceback

                traceback.print_exception(exc, file=sys.stderr)
        print(f"gyrobench: error: {escape_controls(msg)}", file=sys.stderr)
        return code
    finally:
        if isinstance(sys.stdout, _EscapedStream):
            sys.stdout = stdout
        restore()


class _EscapedStream:
    """A text stream whose writes have their control characters escaped
    (:func:`gyrobench.base.safety.escape_controls`); everything else is the wrapped stream's."""

    def __init__(self, stream: typing.Any) -> None:
        self._stream = stream

    def write(self, text: str) -> int:
        from gyrobench.base.safety import escape_controls

        self._stream.write(escape_controls(text))
        return len(text)

    def __getattr__(self, name: str) -> typing.Any:
        return getattr(self._stream, name)


def _silence_stdout() -> None:
    """Point stdout at /dev/null, so the interpreter's final flush of a closed pipe raises nothing."""
    import os

    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):  # stdout is not a file (a test's capture): nothing to flush
        pass


def _raise_on_sigterm() -> typing.Callable[[], None]:
    """Make SIGTERM raise :class:`~gyrobench.scenarios.cli.exits.Terminated` in the main thread while a
    verb runs (its cleanups run, the exit is 143 with one line); returns what restores the previous
    handler. Nothing outside the main thread (signal handlers can only be set there)."""
    import signal
    import threading

    from gyrobench.scenarios.cli import exits

    if threading.current_thread() is not threading.main_thread():
        return lambda: None

    def _terminated(signum: int, frame: typing.Any) -> None:
        raise exits.Terminated

    previous = signal.signal(signal.SIGTERM, _terminated)

    def restore() -> None:
        signal.signal(signal.SIGTERM, previous)

    return restore


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
