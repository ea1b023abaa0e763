"""What every ``gyrobench`` verb shares: the one-line parser, the bad-input error, argparse value types
with messages naming the flag, a progress bar that leaves nothing behind on an error, and the TOML reader."""

from __future__ import annotations

import argparse
import contextlib
import math
import typing

__all__ = ["FORCE_HELP", "MAX_FLAG_INT", "MAX_FLAG_VALUE", "MAX_WORKERS", "TOML_DEPTH", "BadInput", "Parser",
           "add_force", "bounded_recursion", "check_outputs", "closing", "duration", "given", "input_file",
           "nonneg_float", "one_line", "positive_float", "positive_int", "ranged", "read_toml", "seed",
           "units_or_auto"]


class Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line (control characters escaped) and exit 2."""
    def error(self, message: str) -> typing.NoReturn:  # one line, exit 2, control characters escaped
        from gyrobench.base.safety import escape_controls

        self.exit(2, f"gyrobench: error: {escape_controls(one_line(message))} (see '{self.prog} --help')\n")


class BadInput(ValueError):
    """Bad input found by a verb: one line, exit 2."""


@contextlib.contextmanager
def closing(bar):
    """Close a tqdm progress bar on leaving the block, erasing it first on an error.

    Close a tqdm ``bar`` on leaving; on an error erase it first, so the one-line error is the
    last thing on the terminal (a bar left open redraws itself after the error).

    Parameters
    ----------
    bar : tqdm.tqdm
        The bar.

    Yields
    ------
    tqdm.tqdm
        ``bar``.
    """
    try:
        yield bar
    except BaseException:
        bar.leave = False
        raise
    finally:
        bar.close()



#: the largest time [s] or tau [s] flag (``allan --start/--stop/--tau-min/--tau-max``): 3e7 years, far
#: past any record, and far below where float64 arithmetic on it overflows
MAX_FLAG_VALUE = 1e15
#: the largest integer flag (a seed, a count): a signed 64-bit integer, as the stores keep them
MAX_FLAG_INT = 2**63 - 1
#: the most local worker processes a verb starts (``--workers``): far past any machine's cores
MAX_WORKERS = 1024


def ranged(name: str, low: float, high: float, *, low_open: bool = False, high_open: bool = False,
           integer: bool = False, unit: str = ""):
    """argparse type: a finite number in a documented range, errors naming the flag and the range.

    argparse type: a finite number (or integer) in the documented range ``[low, high]`` (each end
    open if asked) in ``unit``, errors naming the flag and the range in one line.

    Parameters
    ----------
    name : str
        The flag, for the messages.
    low, high : float
        The range's bounds, in ``unit``.
    low_open, high_open : bool
        The bound is exclusive.
    integer : bool
        Accept integers only.
    unit : str
        The flag's unit, for the message.

    Returns
    -------
    callable
        ``text -> float`` (or int) for ``argparse``'s ``type``.
    """
    from gyrobench.base.ranges import FieldRange

    rng = FieldRange(low, high, unit, low_open=low_open, high_open=high_open, integer=integer)

    def conv(text: str) -> float | int:
        try:
            v: float | int = int(text) if integer else float(text)
        except ValueError:
            v = math.nan
        if not rng.contains(v):
            kind = "" if integer else "a finite number in "
            raise argparse.ArgumentTypeError(f"{name} must be {kind}{rng.text()}; got {_int_text(text)!r}")
        return v

    return conv


def float_arg(name: str, *, allow_zero: bool, high: float | None = None):
    """argparse type: a finite float > 0 (or >= 0 with ``allow_zero``), at most ``high`` if given,
    errors naming the flag."""
    bound = ">= 0" if allow_zero else "> 0"

    def conv(text: str) -> float:
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be a number; got {text[:40]!r}") from None
        if not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
            raise argparse.ArgumentTypeError(f"{name} must be a finite number {bound}; got {text[:40]!r}")
        if high is not None and v > high:
            raise argparse.ArgumentTypeError(f"{name} must be at most {high:g}; got {text[:40]!r}")
        return v

    return conv


def positive_float(name: str, high: float | None = None):
    """argparse type: a finite number > 0 (at most ``high``), errors naming the flag.

    Parameters
    ----------
    name : str
        The flag, for the messages.
    high : float or None
        The largest value accepted (None: no bound).

    Returns
    -------
    callable
        ``text -> float`` for ``argparse``'s ``type``.
    """
    return float_arg(name, allow_zero=False, high=high)


def nonneg_float(name: str, high: float | None = None):
    """argparse type: a finite number >= 0 (at most ``high``), errors naming the flag.

    Parameters
    ----------
    name : str
        The flag, for the messages.
    high : float or None
        The largest value accepted (None: no bound).

    Returns
    -------
    callable
        ``text -> float`` for ``argparse``'s ``type``.
    """
    return float_arg(name, allow_zero=True, high=high)


def duration(text: str) -> float:
    """argparse type of ``--duration``: a finite duration > 0 [s], with or without a unit.

    Parameters
    ----------
    text : str
        The flag's text, seconds or a number with a unit (:func:`gyrobench.base.units.parse_duration`).

    Returns
    -------
    float
        The duration [s].

    Raises
    ------
    argparse.ArgumentTypeError
        A negative, unparsable or infinite duration, in one line naming the flag.
    """
    from gyrobench.base.units import parse_duration

    if text.strip().startswith("-"):
        raise argparse.ArgumentTypeError(f"--duration must be > 0 s; got {text!r}")
    try:
        value = parse_duration(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"--{exc}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"--duration must be a finite number of seconds; got {text!r}")
    return value


def _int_text(text: str) -> str:
    return text if len(text) <= 40 else f"an integer of {len(text)} digits"


def positive_int(name: str):
    """argparse type: an integer > 0, errors naming the flag.

    argparse type: an integer > 0, errors naming the flag (a size is bounded where it is used:
    ``reproduce --units`` by :data:`gyrobench.scenarios.runner.units.MAX_UNITS`).

    Parameters
    ----------
    name : str
        The flag, for the messages.

    Returns
    -------
    callable
        ``text -> int`` for ``argparse``'s ``type``.
    """

    def conv(text: str) -> int:
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be an integer > 0; got {_int_text(text)!r}") from None
        if v <= 0:
            raise argparse.ArgumentTypeError(f"{name} must be an integer > 0; got {text!r}")
        return v

    return conv


def units_or_auto(text: str) -> int | str:
    """``--units``: a positive integer, or ``auto``.

    Parameters
    ----------
    text : str
        The flag's text.

    Returns
    -------
    int or str
        The number of units, or ``"auto"``.
    """
    return "auto" if text == "auto" else positive_int("--units (or 'auto')")(text)




def given(args, flags: dict[str, str]) -> list[str]:
    """The flags among ``flags`` that the user gave.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed arguments.
    flags : dict of str to str
        Destination -> its flag (``{"fs": "--fs"}``).

    Returns
    -------
    list of str
        The flags whose value is not None, in the order of ``flags``.
    """
    return [flag for dest, flag in flags.items() if getattr(args, dest, None) is not None]



def seed(text: str) -> int:
    """argparse type of ``--seed``: an integer in [0, :data:`MAX_FLAG_INT`] (64-bit, as stored).

    Parameters
    ----------
    text : str
        The flag's text.

    Returns
    -------
    int
        The seed.
    """
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"--seed must be an integer >= 0; got {_int_text(text)!r}") from None
    if v < 0:
        raise argparse.ArgumentTypeError(f"--seed must be an integer >= 0; got {text!r}")
    if v > MAX_FLAG_INT:
        raise argparse.ArgumentTypeError(f"--seed must be at most {MAX_FLAG_INT} (64-bit); got {_int_text(text)!r}")
    return v



def one_line(text: object) -> str:
    """``text`` on one line (a message from a library may hold newlines).

    Parameters
    ----------
    text : object
        A message (its ``str``).

    Returns
    -------
    str
        The message with its newlines folded to spaces.
    """
    return " ".join(str(text).split())



# ----------------------------------------------------------------------------- outputs and inputs
#: the help of every writing verb's --force (gyrobench.base.safety states the rule)
FORCE_HELP = ("replace existing output files that gyrobench did not write (default: refused); never an input of "
              "the command, never a foreign --db, never a folder that is not a gyrobench report")


def add_force(parser) -> None:
    """Add ``--force`` (:data:`FORCE_HELP`) to a writing verb's parser.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        A writing verb's parser.
    """
    parser.add_argument("--force", action="store_true", help=FORCE_HELP)


def check_outputs(args, outputs, inputs=()) -> None:
    """Check every output of a verb by the output rule before any work.

    Every output of a verb through the rule of :func:`gyrobench.base.safety.check_outputs`, before any
    work; ``args.force`` is the verb's ``--force``; a database output is checked against gyrobench's tables.

    Parameters
    ----------
    args : argparse.Namespace
        The verb's arguments (``args.force`` is its ``--force``).
    outputs : sequence of Output
        The verb's outputs (:func:`gyrobench.base.safety.check_outputs`).
    inputs : iterable of (flag, path)
        The verb's inputs, never to be overwritten.
    """
    from gyrobench.base import safety

    tables: tuple[str, ...] = ()
    if any(o.kind == "database" for o in outputs):
        from gyrobench.scenarios.runner.store import database_tables

        tables = database_tables()
    safety.check_outputs(outputs, inputs, force=bool(getattr(args, "force", False)), tables=tables)


def input_file(path, what: str):
    """An input path checked to be a readable regular file.

    ``path`` as a Path if it is a readable regular file, else one line (not found, a folder, a FIFO, a
    device: :func:`gyrobench.base.safety.check_input`).

    Parameters
    ----------
    path : path-like
        The input.
    what : str
        How the user named it (a flag), for the message.

    Returns
    -------
    Path
        ``path`` as a Path (else :class:`BadInput`, one line: not found, a folder, a FIFO, a device).
    """
    from gyrobench.base import safety

    return safety.check_input(path, what)


#: frames a TOML reader may use above its caller: files nested deeper are refused, whatever recursion limit
#: the interpreter was given (a raised limit would let the reader exhaust the C stack instead)
TOML_DEPTH = 1000


@contextlib.contextmanager
def bounded_recursion(frames: int = TOML_DEPTH):
    """Hold the recursion limit a known depth above the current one for a block.

    Hold the recursion limit at the current depth + ``frames`` (never above the current limit) for the
    block, so a recursive reader fails with RecursionError at a known depth.

    Parameters
    ----------
    frames : int
        Frames allowed above the current depth (never above the current limit).

    Yields
    ------
    None
        The block runs with the lowered limit; the old limit is restored on leaving.
    """
    import sys
    import types

    depth = 0
    f: types.FrameType | None = sys._getframe()
    while f is not None:
        depth, f = depth + 1, f.f_back
    old = sys.getrecursionlimit()
    sys.setrecursionlimit(min(old, depth + frames))
    try:
        yield
    finally:
        sys.setrecursionlimit(old)


def read_toml(path: str, flag: str) -> dict:
    """Read a TOML file given by a flag, refusing bad input in one line.

    Parameters
    ----------
    path : str
        The file.
    flag : str
        The flag that named it, for the messages.

    Returns
    -------
    dict
        The parsed document.

    Raises
    ------
    BadInput
        Not a readable regular file, not UTF-8, not valid TOML, or nested too deep.
    """
    import sys

    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover
        import tomli as tomllib
    input_file(path, flag)  # a FIFO or /dev/zero would never end
    try:
        with open(path, "rb") as fh, bounded_recursion():
            return tomllib.load(fh)
    except FileNotFoundError:
        raise BadInput(f"{flag}: file {path!r} does not exist") from None
    except UnicodeDecodeError as exc:
        raise BadInput(f"{flag}: {path!r} is not UTF-8 text: {one_line(exc)}") from None
    except tomllib.TOMLDecodeError as exc:
        raise BadInput(f"{flag}: {path!r} is not valid TOML: {one_line(exc)}") from None
    except RecursionError:  # arrays or tables nested thousands deep
        raise BadInput(f"{flag}: {path!r} nests arrays or tables too deeply to read") from None

