"""What every recording writer checks before it writes a byte: the record closes, the target may be replaced.

:func:`~gyrobench.io.recording.save_hdf5`, :func:`~gyrobench.io.recording.to_csv` and
:class:`~gyrobench.io.recording.HDF5StreamWriter` (chunk by chunk) call :func:`check_closes` and
:func:`check_replaceable`; the command-line verbs write through them, so the rules hold for every
file gyrobench writes, from Python or the command line.

**The record closes.** A recording whose metadata names its error components
(``error_components``, docs/recording.md) promises ``output - true_rate = sum(components)``.
The residual ``r = max_k |output_k - true_k - sum_j c_jk|`` of a float64 record is the rounding of
``m + 2`` terms, each of magnitude at most ``scale`` (the largest magnitude among the summed
channels), so ``|r| <= (m + 2) eps scale`` for a sum formed once; the models form their terms
through a few intermediate operations, hence the factor 16 of :data:`ROUNDING_FACTOR`:

    tolerance = 16 (m + 2) eps scale

(``eps`` = 2.22e-16, float64's machine epsilon). An output differenced from a counted angle (a
ring-laser gyro's pulses: a ``counts`` channel in the record) rounds at ``eps`` times that angle,
so its ``scale`` is ``2 n max|output|`` (the angle reached after ``n`` samples, times ``fs``,
twice for the difference). A record that misses by more is refused in one line naming the file,
the residual and the tolerance (:class:`RecordingClosureError`, a ``ValueError``: exit 2 at the
command line), and nothing is written. A recording whose metadata names no components (a real
log, read back from a file) promises nothing and is written as it is.

**The target may be replaced.** The command-line rule of :mod:`gyrobench.base.safety`: an
existing file is replaced only if gyrobench wrote it (its format's marker,
:func:`~gyrobench.base.safety.written_by_gyrobench`); any other existing file is refused
(:class:`~gyrobench.base.safety.OutputRefused`) unless the caller passes ``overwrite=True`` (the
verbs pass their ``--force``). A folder is never replaced.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from gyrobench.io.recording import Recording

__all__ = ["ROUNDING_FACTOR", "RecordingClosureError", "check_closes", "check_replaceable", "closure_tolerance"]

#: the factor on ``(m + 2) eps scale`` for the models' intermediate operations (module docstring)
ROUNDING_FACTOR = 16.0

_EPS = float(np.finfo(np.float64).eps)


class RecordingClosureError(ValueError):
    """A recording whose error components do not sum to ``output - true_rate``: one line, nothing written."""


def _outputs(rec: Recording) -> list[str]:
    comps = rec.metadata.get("error_components")
    return [str(k) for k in comps] if isinstance(comps, Mapping) else ["output"]


def closure_tolerance(rec: Recording, output: str, scale: float) -> float:
    """The rounding bound on :func:`~gyrobench.io.recording.closure`'s residual (module docstring).

    Parameters
    ----------
    rec : Recording
        The recording (its component list and, for a counting output, its length).
    output : str
        The output channel.
    scale : float
        The largest magnitude among the summed channels [the output's unit].

    Returns
    -------
    float
        ``16 (m + 2) eps scale`` [the output's unit]; ``scale`` raised to ``2 n max|output|`` for
        an output differenced from counted pulses.
    """
    comps = rec.metadata.get("error_components")
    names = comps.get(output, []) if isinstance(comps, Mapping) else (comps or [])
    m = len(names)
    if any(c.unit == "counts" for c in rec.channels.values()):
        scale = max(scale, 2.0 * rec.n_samples * float(np.max(np.abs(rec.channels[output].data), initial=0.0)))
    return ROUNDING_FACTOR * (m + 2) * _EPS * scale


def check_closes(rec: Recording, path: str | os.PathLike) -> None:
    """Refuse, in one line naming ``path``, a recording whose components miss ``output - true_rate``.

    Parameters
    ----------
    rec : Recording
        The recording about to be written.
    path : str or os.PathLike
        The file it would be written to (for the message).

    Raises
    ------
    RecordingClosureError
        If the metadata names components the truth lacks, or the residual exceeds
        :func:`closure_tolerance`.
    """
    from gyrobench.io.recording import closure, truth_names

    names = truth_names(rec.metadata)
    if names is None:
        return
    if missing := sorted(names - set(rec.truth)):
        raise RecordingClosureError(
            f"{str(path)!r} not written: recording {rec.name!r} names error components whose truth it lacks "
            f"({', '.join(missing)})"
        )
    for out in _outputs(rec):
        if out not in rec.channels:
            raise RecordingClosureError(
                f"{str(path)!r} not written: recording {rec.name!r} lists components of {out!r} but has no such channel"
            )
        resid, scale = closure(rec, out)
        tol = closure_tolerance(rec, out, scale)
        if not resid <= tol:
            unit = rec.channels[out].unit
            raise RecordingClosureError(
                f"{str(path)!r} not written: recording {rec.name!r} does not close: {out} - true value - its "
                f"error components misses by {resid:.3g} {unit} at most, beyond the rounding tolerance "
                f"{tol:.3g} {unit} (16 (m + 2) eps x {scale:.3g})"
            )


def check_replaceable(path: str | os.PathLike, *, overwrite: bool) -> None:
    """Refuse to replace an existing file gyrobench did not write, unless ``overwrite`` (module docstring).

    Parameters
    ----------
    path : str or os.PathLike
        The target.
    overwrite : bool
        Replace any existing file.

    Raises
    ------
    OutputRefused
        If ``path`` is a folder, or an existing file without gyrobench's marker and not ``overwrite``.
    """
    from gyrobench.base.safety import OutputRefused, written_by_gyrobench

    p = Path(path)
    if p.is_dir():
        raise OutputRefused(f"{str(p)!r} is a folder; a recording is written to a file")
    if overwrite or not (p.exists() or p.is_symlink()):
        return
    if not written_by_gyrobench(p):
        raise OutputRefused(
            f"{str(p)!r} exists and gyrobench did not write it (no gyrobench marker); not replaced: pass "
            "overwrite=True (the command line's --force) or choose another path"
        )
