"""The time column of a CSV log: its unit, uniform steps, the sample rate and the --start/--stop segment."""

from __future__ import annotations

import io
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from gyrobench.io.logs._layout import _Header, _Layout
from gyrobench.io.logs._names import _ISO, _SI_FORMATS, GAP_FACTOR, MIN_ROWS, TIME_UNITS


# ----------------------------------------------------------------------------- time column
def _check_time_base(path: Path, hdr: _Header, fs: float | None) -> None:
    """Without --fs the log needs a time column with a time unit."""
    if fs is None and hdr.time_idx is None:
        raise ValueError(
            f"{str(path)!r} has no time column (a header such as 'time [s]'): give --fs (sample rate in Hz)"
        )
    if fs is None and hdr.time_scale is None:
        raise ValueError(
            f"the time column {(hdr.header or hdr.names)[hdr.time_idx or 0]!r} of {str(path)!r} has no time unit "
            f"({'|'.join(TIME_UNITS)}): give --fs (sample rate in Hz)"
        )


def _time_unit(
    t_first: float, raw_step: float, tname: str, hdr: _Header
) -> tuple[float | None, str | None]:
    """Seconds per unit of the time column and a note on how it was chosen (None: stated in the header)."""
    time_scale = hdr.time_scale
    if hdr.time_stated or time_scale is None:
        return time_scale, None
    time_scale, note = _time_scale_from_magnitude(t_first, tname)
    if note is None and hdr.fmt in _SI_FORMATS:  # Kalibr, ROS and EuRoC write nanoseconds
        time_scale, note = (
            1e-9,
            f"time column {tname!r} read in ns (the {hdr.fmt} format's unit)",
        )
    elif note is None and raw_step >= 1.0:
        note = (
            f"time column {tname!r} has no unit and steps of {raw_step:.6g}: read as "
            f"seconds; give the unit in the header (e.g. 'time [ns]') if it is not"
        )
    return time_scale, note


@dataclass(frozen=True)
class TimeGrid:
    """Where each row of a log sits on its uniform time grid, and the gaps between rows.

    ``index[k]`` is row k's sample number on the grid t0 + j step (consecutive rows differ by
    1 except across a gap); ``gaps`` holds the rows after which ``missing`` samples are absent.
    """

    step: float
    index: NDArray[np.int64]
    gaps: NDArray[np.int64]
    missing: NDArray[np.int64]

    @property
    def n_grid(self) -> int:
        """Samples of the record with its gaps filled."""
        return int(self.index[-1]) + 1


def _time_base(
    path: Path,
    body: str,
    layout: _Layout,
    hdr: _Header,
    t: NDArray[np.float64],
    fs: float | None,
    notes: list[str],
    gaps: str = "refuse",
) -> tuple[float | None, float, TimeGrid]:
    """The sample rate [Hz], the first time [s] and the grid (:func:`_check_uniform`) of the time column ``t``.

    The rate is 1 / the grid step (the time from the first to the last row over the samples
    between them, gaps counted); a given ``fs`` must agree with it to 1 %. How the time unit
    was chosen, when the header does not state it, is appended to ``notes``.
    """
    assert hdr.time_idx is not None
    t_first = float(t[0])
    if abs(t_first) > 2.0**53:  # integer epoch ns (ROS, Kalibr, EuRoC): float64 keeps 256 ns steps only
        t = _exact_time(body, layout.delim, hdr.time_idx, t)
    tname = hdr.header[hdr.time_idx] if hdr.header else str(hdr.time_idx)
    raw_step = float(np.median(np.diff(t)))  # in the column's own unit
    time_scale, note = _time_unit(t_first, raw_step, tname, hdr)
    if note:
        notes.append(note)
    grid = _check_uniform(path, t, tname, gaps)
    step = grid.step * (time_scale or 1.0)
    if fs is None:
        fs = 1.0 / step
    elif time_scale is not None and abs(fs * step - 1.0) > 0.01:
        raise ValueError(
            f"--fs {fs:g} Hz disagrees with the time column {tname!r} of {str(path)!r}, whose "
            f"step gives {1.0 / step:.6g} Hz; drop --fs or fix the time unit"
        )
    return fs, t_first * (time_scale or 1.0), grid


def _exact_time(body: str, delim: str, idx: int, t: NDArray[np.float64]) -> NDArray[np.float64]:
    """Integer timestamps re-read as int64, relative to the first (exact steps); ``t - t[0]`` otherwise."""
    try:
        ti = np.loadtxt(
            io.StringIO(body),
            delimiter=delim,
            comments="#",
            usecols=[idx],
            dtype=np.int64,
            quotechar='"',
            ndmin=1,
        )
    except (ValueError, OverflowError):
        return t - t[0]
    return (ti - ti[0]).astype(np.float64)


def _iso_times(
    path: Path, body: str, delim: str, idx: int, first: int, tname: str, notes: list[str]
) -> tuple[NDArray[np.float64], float]:
    """An ISO-8601 time column read as seconds after its first time (exact to the ns), and that time [s, Unix].

    Times without an offset or with "Z" are read as UTC; a UTC offset is refused (a log whose
    offset changes, at a daylight-saving switch, would jump by an hour), as is a cell that is
    not an ISO-8601 date-time, each naming its line.
    """
    cells: list[str] = []
    lines: list[int] = []
    for j, ln in enumerate(body.rstrip("\n").split("\n")):
        s = ln.strip()
        if s and not s.startswith("#"):
            parts = s.split(delim)
            cells.append(parts[idx].strip().strip('"') if idx < len(parts) else "")
            lines.append(first + j + 1)
    for cell, line in zip(cells, lines, strict=True):
        m = _ISO.match(cell)
        if m is None:
            raise ValueError(
                f"time column {tname!r} of {str(path)!r} line {line}: {cell!r} is neither a number nor an ISO-8601 "
                f"date-time (YYYY-MM-DDThh:mm:ss[.fff][Z]); convert the times to seconds or to ISO-8601"
            )
        if m.group(3) not in (None, "Z"):
            raise ValueError(
                f"time column {tname!r} of {str(path)!r} line {line}: {cell!r} has a UTC offset; ISO-8601 times "
                f"are read only in UTC ('Z' or no offset): convert them to UTC or to seconds"
            )
    clean = [c.rstrip("Z").replace(",", ".") for c in cells]
    try:
        ns = np.array(clean, dtype="datetime64[ns]").astype(np.int64)
    except ValueError as exc:  # e.g. month 13: the pattern matched, the calendar did not
        raise ValueError(f"time column {tname!r} of {str(path)!r}: {exc}; convert the times to seconds") from None
    notes.append(f"time column {tname!r} read as ISO-8601 UTC date-times from {cells[0]}")
    return (ns - ns[0]).astype(np.float64) * 1e-9, float(ns[0]) * 1e-9


def _time_scale_from_magnitude(first: float, name: str) -> tuple[float, str | None]:
    """Unit of a time column without one: Unix epoch times by the magnitude of the first, else seconds."""
    t0 = abs(first)
    if t0 < 1e8:
        return 1.0, None
    # 1e8 s = 1973; the present is ~1.7e9 s, ~1.7e12 ms, ~1.7e15 us, ~1.7e18 ns
    for scale, unit in ((1e-9, "ns"), (1e-6, "us"), (1e-3, "ms"), (1.0, "s")):
        if 1e8 <= t0 * scale < 1e11:
            return scale, (
                f"time column {name!r} has no unit; its values ({t0:.4g}) are Unix epoch times in "
                f"{unit} by their magnitude"
            )
    return 1.0, None


#: a sample may sit at most this fraction of a step from its place t0 + j step on the uniform grid
UNIFORM_TOLERANCE = 0.5
#: --gaps choices: refuse (default), fill (linear interpolation), split (the Allan variance per piece)
GAP_CHOICES = ("refuse", "fill", "split")


def _check_uniform(path: Path, t: NDArray[np.float64], tname: str, gaps: str = "refuse") -> TimeGrid:
    """The uniform grid of the time column ``t``, every step checked; a gap refused unless ``gaps`` allows it.

    A step over :data:`GAP_FACTOR` x the median step is a gap of round(step / median) - 1
    missing samples. Every row k must then lie within :data:`UNIFORM_TOLERANCE` of a step of
    its place t_0 + j_k step, the step being (t_last - t_0) / j_last: jitter of the time stamps
    passes, a clock that runs at another rate for some steps (every third step a tenth of the
    others) or a gap that is not a whole number of steps does not.
    """
    if gaps not in GAP_CHOICES:
        raise ValueError(f"--gaps must be one of {'|'.join(GAP_CHOICES)}; got {gaps!r}")
    dt = np.diff(t)
    bad = np.flatnonzero(~(dt > 0))
    if len(bad):
        i = int(bad[0])
        raise ValueError(
            f"time column {tname!r} of {str(path)!r} must increase strictly: data row {i + 2} "
            f"has {t[i + 1]:.12g} after {t[i]:.12g} in row {i + 1}"
        )
    median = float(np.median(dt))
    gap_rows = np.flatnonzero(dt > GAP_FACTOR * median)
    if len(gap_rows) and gaps == "refuse":
        i = int(gap_rows[0])
        raise ValueError(
            f"time column {tname!r} of {str(path)!r} has a gap before data row {i + 2}: step {dt[i]:.6g} "
            f"({t[i]:.12g} -> {t[i + 1]:.12g}) is {dt[i] / median:.3g} x the median step {median:.6g} "
            f"({len(gap_rows)} such gap{'s' if len(gap_rows) > 1 else ''}); Allan analysis needs uniform sampling: "
            f"give --gaps fill (linear interpolation) or --gaps split (the Allan variance over each contiguous "
            f"piece), or analyse the segments separately"
        )
    missing = np.rint(dt[gap_rows] / median).astype(np.int64) - 1
    jumps = np.ones(dt.size, dtype=np.int64)
    jumps[gap_rows] += missing
    index = np.zeros(t.size, dtype=np.int64)
    np.cumsum(jumps, out=index[1:])
    step = float(t[-1] - t[0]) / float(index[-1])
    off = np.abs((t - t[0]) - index * step)
    k = int(np.argmax(off))
    if not off[k] <= UNIFORM_TOLERANCE * step:
        raise ValueError(
            f"time column {tname!r} of {str(path)!r} is not uniform: data row {k + 1} ({t[k]:.12g}) lies "
            f"{off[k] / step:.3g} of a step from its place on the grid of step {step:.6g} (the tolerance is "
            f"{UNIFORM_TOLERANCE:g} step; the median step is {median:.6g}): Allan analysis needs uniform sampling"
        )
    return TimeGrid(step=step, index=index, gaps=gap_rows, missing=missing)


def _fill(data: NDArray[np.float64], grid: TimeGrid) -> NDArray[np.float64]:
    """The rows of ``data`` on the whole grid, each missing sample linearly interpolated between its neighbours."""
    j = np.arange(grid.n_grid, dtype=float)
    out = np.empty((grid.n_grid, data.shape[1]))
    for c in range(data.shape[1]):
        out[:, c] = np.interp(j, grid.index.astype(float), data[:, c])
    return out


def _pieces(index: NDArray[np.int64]) -> tuple[tuple[int, int], ...]:
    """Row ranges [a, b) of the contiguous runs of the grid indices ``index``."""
    breaks = np.flatnonzero(np.diff(index) > 1) + 1
    edges = [0, *breaks.tolist(), int(index.size)]
    return tuple((edges[i], edges[i + 1]) for i in range(len(edges) - 1))


def _segment(rows: int, fs: float, start: float | None, stop: float | None) -> tuple[int, int]:
    """Sample range of the --start/--stop segment [s from the first sample]."""
    for name, v in (("--start", start), ("--stop", stop)):
        if v is not None and not (math.isfinite(v) and v >= 0):
            raise ValueError(f"{name} must be a finite time >= 0 s; got {v!r}")
    a = 0 if start is None else int(math.ceil(start * fs - 1e-9))
    b = rows if stop is None else min(rows, int(math.floor(stop * fs + 1e-9)))
    if b - a < MIN_ROWS:
        raise ValueError(
            f"--start/--stop keep {max(b - a, 0)} samples of the {rows / fs:g} s record; need at least {MIN_ROWS}"
        )
    return a, b
