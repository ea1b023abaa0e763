"""The ``gyrobench`` command line.

::

    gyrobench list
    gyrobench simulate noise --N 0.01 --B 0.05 --fs 100 --duration 2h --seed 1 -o rec.h5
    gyrobench simulate SCENARIO --seed 1 --out DIR [--config FILE.toml]
    gyrobench allan FILE [--column NAME] [--fs HZ] [--units deg/s] [--json] [--plot FILE.png]
    gyrobench reproduce --all --out DIR [--seed S]
    gyrobench reproduce SCENARIO [SCENARIO ...] --out DIR
    gyrobench bench SCENARIO --compensator module:attr --seeds 0:100

Exit status (:mod:`gyrobench.scenarios.exits`): 0 on success, 1 when ``bench`` finds
a significant regression, 2 on bad input, 3 when ``bench``'s compensator failed on
some seeds, 4 on an internal failure, 130 when interrupted. Every error is one
readable line on stderr, no traceback (``GYROBENCH_TRACEBACK=1`` shows it).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import re
import shlex
import sys
import time
import warnings
from pathlib import Path

import numpy as np

__all__ = ["main"]

#: exceptions that mean "bad input": reported in one line, exit 2
_INPUT_ERRORS: tuple[type[BaseException], ...] = (ValueError, TypeError, KeyError, FileNotFoundError, IsADirectoryError, PermissionError)


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line, exit 2
        self.exit(2, f"gyrobench: error: {message} (see '{self.prog} --help')\n")


class _BadInput(ValueError):
    pass


@contextlib.contextmanager
def _closing(bar):
    """Close a tqdm ``bar`` on leaving; on an error erase it first, so the one-line error is the
    last thing on the terminal (a bar left open redraws itself after the error)."""
    try:
        yield bar
    except BaseException:
        bar.leave = False
        raise
    finally:
        bar.close()


# ----------------------------------------------------------------------------- list
def _cmd_list(args) -> int:
    from gyrobench.scenarios import registry

    for name in registry.available():
        mod = registry.get(name)
        bench = " [bench]" if hasattr(mod, "compensation_task") else ""
        print(f"{name:<20} {mod.TITLE}{bench}")
    return 0


# ----------------------------------------------------------------------------- simulate
def _float_arg(name: str, *, allow_zero: bool):
    """argparse type: a finite float > 0 (or >= 0 with ``allow_zero``), errors naming the flag."""
    bound = ">= 0" if allow_zero else "> 0"

    def conv(text: str) -> float:
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be a number; got {text!r}") from None
        if not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
            raise argparse.ArgumentTypeError(f"{name} must be a finite number {bound}; got {text!r}")
        return v

    return conv


def _positive_float(name: str):
    return _float_arg(name, allow_zero=False)


def _nonneg_float(name: str):
    return _float_arg(name, allow_zero=True)


def _duration(text: str) -> float:
    from gyrobench.sim.units import parse_duration

    if text.strip().startswith("-"):
        raise argparse.ArgumentTypeError(f"--duration must be > 0 s; got {text!r}")
    try:
        value = parse_duration(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"--{exc}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"--duration must be a finite number of seconds; got {text!r}")
    return value


def _positive_int(name: str):
    def conv(text: str) -> int:
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be an integer > 0; got {text!r}") from None
        if v <= 0:
            raise argparse.ArgumentTypeError(f"{name} must be an integer > 0; got {text!r}")
        return v

    return conv


#: flags of 'simulate noise' and of 'simulate SCENARIO' (dest -> flag); the others are shared
_NOISE_FLAGS = {"Q": "--Q", "N": "--N", "B": "--B", "K": "--K", "R": "--R", "fs": "--fs",
                "duration": "--duration", "output": "-o/--output", "chunk": "--chunk"}
_SCENARIO_FLAGS = {"out": "--out", "config": "--config"}


def _given(args, flags: dict[str, str]) -> list[str]:
    return [flag for dest, flag in flags.items() if getattr(args, dest, None) is not None]


def _simulate_noise(args) -> int:
    """Stream one noise record to ``-o FILE.h5|.csv``.

    The record is static: the true rate is 0 rad/s and every sample of channel
    ``rate`` is error. The HDF5 ``truth`` group is therefore left empty rather
    than doubling the file with a zero channel or with each noise term (use
    ``simulate static_noise`` for records with per-term truth); instead the
    metadata states ``truth.true_rate_rad_s = 0`` and holds the generating
    model (``noise_model_si``: Q [rad], N [rad/sqrt(s)], B [rad/s],
    K [rad/s/sqrt(s)], R [rad/s^2]) besides the datasheet values and the seed.
    """
    from tqdm import tqdm

    from gyrobench.scenarios.outputs import check_output
    from gyrobench.scenarios.static_noise import MIN_SAMPLES
    from gyrobench.sim import memory
    from gyrobench.sim.noise import NoiseModel
    from gyrobench.sim.recording import (
        HDF5StreamWriter,
        atomic_path,
        check_magnitude,
        ensure_free_space,
        package_version,
    )

    if extra := _given(args, _SCENARIO_FLAGS):
        raise _BadInput(f"simulate noise: {', '.join(extra)} apply to 'simulate SCENARIO'; "
                        "a noise record is written to the one file named by -o")
    if args.output is None:
        raise _BadInput("simulate noise needs -o FILE.h5 or FILE.csv")
    out = Path(args.output)
    suffix = "".join(out.suffixes[-1:]).lower()
    if suffix not in (".h5", ".hdf5", ".csv"):
        raise _BadInput(f"-o must end in .h5, .hdf5 or .csv; got {str(out)!r}")
    check_output(out, what="-o", kind="file")
    if args.duration is None:
        raise _BadInput("simulate noise needs --duration (e.g. 10h, 30min, 600s)")
    fs = 100.0 if args.fs is None else args.fs
    datasheet = {"Q_arcsec": args.Q or 0.0, "N_deg_sqrt_h": args.N or 0.0, "B_deg_h": args.B or 0.0,
                 "K_deg_h_sqrt_h": args.K or 0.0, "R_deg_h2": args.R or 0.0}
    model = NoiseModel.from_datasheet(
        quantization=datasheet["Q_arcsec"], angle_random_walk=datasheet["N_deg_sqrt_h"],
        bias_instability=datasheet["B_deg_h"], rate_random_walk=datasheet["K_deg_h_sqrt_h"],
        rate_ramp=datasheet["R_deg_h2"],
    )
    n_float = args.duration * fs
    if not n_float < 2.0**62:  # inf or beyond any disk: said here, not as an OverflowError
        raise _BadInput(f"--duration x --fs = {args.duration:g} s x {fs:g} Hz gives {n_float:.3g} samples; "
                        "a record holds at most 2**62 (and must fit on the disk)")
    n = int(round(n_float))
    if n < MIN_SAMPLES:
        raise _BadInput(f"--duration x --fs = {args.duration:g} s x {fs:g} Hz gives {n} samples; a record needs "
                        f"at least {MIN_SAMPLES} (the fewest for the five octave taus of an Allan fit)")
    if suffix == ".csv":  # a row "%.12g,%.17g\n" is at most about 42 characters (HDF5StreamWriter checks its own)
        ensure_free_space(out, 42 * n)
    seed = 0 if args.seed is None else args.seed
    chunk = args.chunk or 1 << 20
    # streamed: only one chunk is in memory (the five terms, their sum, the time column, copies)
    memory.check_memory(memory.series_bytes(min(chunk, n), 12), f"simulate noise (chunks of {min(chunk, n)} samples)",
                        hint="lower --chunk")
    stream = model.stream(fs, rng=np.random.default_rng(seed))
    meta = {
        "source": "gyrobench simulate noise", "datasheet": datasheet, "seed": seed, "version": package_version(),
        "truth": {"true_rate_rad_s": 0.0,
                  "note": "static record: the true rate is 0 rad/s, every sample of 'rate' is error; "
                          "the noise terms are not stored separately"},
        "noise_model_si": {"quantization_rad": model.quantization,
                           "angle_random_walk_rad_per_sqrt_s": model.angle_random_walk,
                           "bias_instability_rad_per_s": model.bias_instability,
                           "rate_random_walk_rad_per_s_sqrt_s": model.rate_random_walk,
                           "rate_ramp_rad_per_s2": model.rate_ramp},
    }
    too_big = "the noise coefficients --Q/--N/--B/--K/--R are far too large for any gyro"
    bar = tqdm(total=n, unit="sa", unit_scale=True, disable=n < 5 * chunk or args.quiet, desc="simulate")
    with _closing(bar):
        if suffix == ".csv":
            with atomic_path(out) as tmp, open(tmp, "w") as fh:
                fh.write("# gyrobench simulate noise; " + json.dumps(meta) + "\n")
                fh.write("time [s],rate [rad/s]\n")
                k = 0
                for y in stream.chunks(n, chunk):
                    check_magnitude(y, "simulate noise: the record", n_total=n, hint=too_big)
                    t = (k + np.arange(len(y))) / fs
                    np.savetxt(fh, np.column_stack([t, y]), delimiter=",", fmt=["%.12g", "%.17g"])
                    k += len(y)
                    bar.update(len(y))
        else:
            with HDF5StreamWriter(out, name="noise", fs=fs, channels={"rate": "rad/s"}, metadata=meta,
                                  expected_samples=n) as w:
                for y in stream.chunks(n, chunk):
                    check_magnitude(y, "simulate noise: the record", n_total=n, hint=too_big)
                    w.append(rate=y)
                    bar.update(len(y))
    print(f"wrote {n} samples ({n / fs:.6g} s at {fs:g} Hz) to {out}")
    return 0


def _simulate_scenario(args) -> int:
    from gyrobench.scenarios import registry
    from gyrobench.scenarios.outputs import check_output
    from gyrobench.scenarios.static_noise import MIN_SAMPLES
    from gyrobench.sim.recording import ensure_free_space, save_hdf5

    if extra := _given(args, _NOISE_FLAGS):
        raise _BadInput(f"simulate {args.target}: {', '.join(extra)} apply to 'simulate noise' only; "
                        f"set a scenario's parameters with --config FILE.toml")
    mod = registry.get(args.target)
    config = registry.load_config(mod, args.config)
    if args.out is None:
        raise _BadInput(f"simulate {args.target} needs --out DIR")
    check_output(Path(args.out) / mod.NAME, what="--out", kind="folder")
    seed = 0 if args.seed is None else args.seed
    recs = mod.simulate(config, seed)
    for r in recs:  # check them all before writing any
        if r.n_samples < MIN_SAMPLES:
            raise _BadInput(
                f"simulate {args.target}: recording {r.name!r} would have {r.n_samples} samples "
                f"({r.n_samples / r.fs:.3g} s at {r.fs:g} Hz); a record needs at least {MIN_SAMPLES}: "
                f"lengthen it in the config"
            )
    out = Path(args.out) / mod.NAME
    ensure_free_space(out / "all recordings", sum(r.nbytes for r in recs))
    for r in recs:
        path = save_hdf5(out / f"{r.name}.h5", r)
        print(f"wrote {path} ({r.n_samples} samples at {r.fs:g} Hz; channels {', '.join(r.channels)}; "
              f"truth {', '.join(r.truth)})")
    return 0


def _cmd_simulate(args) -> int:
    if args.target == "noise":
        return _simulate_noise(args)
    return _simulate_scenario(args)


# ----------------------------------------------------------------------------- allan
#: time-column names (case-insensitive, after removing a "[unit]" or "(unit)"): time, t, timestamp,
#: optionally with the unit as a suffix (time_s, t_s, time_ms)
_TIME_NAME = re.compile(r"^(?:time|t|timestamp|times)(?:[ _-]?(s|sec|secs|seconds|ms|us))?$", re.IGNORECASE)
_TIME_UNITS = {"s": 1.0, "sec": 1.0, "secs": 1.0, "second": 1.0, "seconds": 1.0, "ms": 1e-3, "us": 1e-6,
               "µs": 1e-6, "ns": 1e-9, "min": 60.0, "h": 3600.0}
#: a time step larger than this multiple of the median step is a gap in the record
_GAP_FACTOR = 1.5
#: fewer data rows than this cannot give any Allan deviation (the analysis asks for more per tau)
_MIN_CSV_ROWS = 2


def _split_header(cell: str) -> tuple[str, str | None]:
    """``"gyro [deg/s]"`` or ``"Time (s)"`` -> (name, unit); the unit may itself hold parentheses."""
    cell = cell.strip()
    close = cell[-1:] if cell[-1:] in ")]" else None
    if close is None:
        return cell, None
    opening = "(" if close == ")" else "["
    depth = 0
    for i in range(len(cell) - 1, -1, -1):
        depth += (cell[i] == close) - (cell[i] == opening)
        if depth == 0:
            return cell[:i].strip(), cell[i + 1 : -1].strip() or None
    return cell, None


def _time_column(names: list[str], hdr_units: list[str | None]) -> tuple[int | None, float | None]:
    """Index of the time column and its unit in seconds (None when the unit is not a time unit)."""
    for i, nm in enumerate(names):
        m = _TIME_NAME.match(nm)
        if m:
            unit = hdr_units[i] or m.group(1) or "s"  # no unit anywhere: seconds
            return i, _TIME_UNITS.get(unit.lower())
    return None, None


def _read_csv(path: Path, column: str | None, fs: float | None, unit: str | None):
    """Read one rate column of a CSV (``#`` comments, optional header, .gz allowed).

    Rate column: ``--column`` (name or 0-based index), else the only column
    that is not the time column. Time column: a header such as ``time``,
    ``t``, ``timestamp``, ``t_s``, ``Time (s)``, ``time [ms]`` (any case). It
    gives fs (1 / median step) unless ``--fs`` is given, and it must be
    uniform: a step that is not positive, or larger than 1.5 x the median
    step (a gap), is refused, naming the row, since Allan analysis assumes
    uniform sampling.

    Returns (rate in rad/s, fs [Hz], column label).
    """
    from gyrobench.sim import units

    opener = __import__("gzip").open if path.suffix == ".gz" else open
    header: list[str] | None = None
    first: list[str] | None = None
    skip = 0
    with opener(path, "rt") as fh:
        for line in fh:
            skip += 1
            s = line.strip()
            if not s or s.startswith("#"):
                continue
            cells = [c.strip() for c in s.split(",")]
            try:
                [float(c) for c in cells]
                skip -= 1  # first data line: no header
                first = cells
            except ValueError:
                header = cells
            break
        else:
            raise _BadInput(f"CSV {str(path)!r} has 0 data rows; need at least {_MIN_CSV_ROWS}")
    if header is not None:
        names, hdr_units = (list(t) for t in zip(*(_split_header(h) for h in header), strict=True))
    else:
        names, hdr_units = [], [None] * len(first or [])
    ncols = len(header or first or [])
    time_idx, time_scale = _time_column(names, hdr_units)
    listing = names if names else f"{ncols} unnamed columns, no header: give an index 0..{ncols - 1}"
    if column is None:
        candidates = [i for i in range(ncols) if i != time_idx]
        if len(candidates) != 1:
            raise _BadInput(f"{str(path)!r} has {len(candidates)} data columns: name the rate column with "
                            f"--column (columns: {listing})")
        idx = candidates[0]
    elif column in names:
        idx = names.index(column)
    elif header and column in header:
        idx = header.index(column)
    elif [nm.lower() for nm in names].count(column.lower()) == 1:
        idx = [nm.lower() for nm in names].index(column.lower())
    else:
        try:
            idx = int(column)
        except ValueError:
            raise _BadInput(f"--column {column!r} is not in {str(path)!r}; columns: {listing}") from None
        if not 0 <= idx < ncols:
            raise _BadInput(f"--column {idx} is out of range for {str(path)!r}: it has {ncols} columns (0..{ncols - 1})")
    if idx == time_idx:
        raise _BadInput(f"--column {column!r} is the time column of {str(path)!r}; name the rate column")
    if fs is None and time_idx is None:
        raise _BadInput(f"{str(path)!r} has no time column (a header such as 'time [s]'): give --fs (sample rate in Hz)")
    if fs is None and time_scale is None:
        raise _BadInput(f"the time column {header[time_idx]!r} of {str(path)!r} has no time unit "
                        f"({'|'.join(_TIME_UNITS)}): give --fs (sample rate in Hz)")
    cols = [idx] + ([time_idx] if time_idx is not None else [])
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # "input contained no data": reported below
            data = np.loadtxt(path, delimiter=",", comments="#", skiprows=skip, usecols=cols, ndmin=2)
    except (ValueError, IndexError) as exc:
        raise _BadInput(f"cannot read column {column or idx!r} of {str(path)!r}: {exc}") from None
    rows = data.shape[0]
    if rows < _MIN_CSV_ROWS:
        raise _BadInput(f"CSV {str(path)!r} has {rows} data row{'s' if rows != 1 else ''}; need at least "
                        f"{_MIN_CSV_ROWS} (and many more for an Allan analysis)")
    rate = data[:, 0]
    if time_idx is not None:
        t = data[:, 1]
        dt = np.diff(t)
        tname = header[time_idx]
        bad = np.flatnonzero(~(dt > 0))
        if len(bad):
            i = int(bad[0])
            raise _BadInput(f"time column {tname!r} of {str(path)!r} must increase strictly: data row {i + 2} "
                            f"has {t[i + 1]:.12g} after {t[i]:.12g} in row {i + 1}")
        step = float(np.median(dt))
        gaps = np.flatnonzero(dt > _GAP_FACTOR * step)
        if len(gaps):
            i = int(gaps[0])
            raise _BadInput(
                f"time column {tname!r} of {str(path)!r} has a gap before data row {i + 2}: step {dt[i]:.6g} "
                f"({t[i]:.12g} -> {t[i + 1]:.12g}) is {dt[i] / step:.3g} x the median step {step:.6g} "
                f"({len(gaps)} such gap{'s' if len(gaps) > 1 else ''}); Allan analysis needs uniform sampling: "
                f"analyse the segments separately"
            )
        if fs is None:
            fs = 1.0 / (step * time_scale)
    unit = unit or hdr_units[idx]
    if unit is None:
        raise _BadInput(f"the unit of column {names[idx] if names else idx!r} is unknown: "
                        f"give --units ({'|'.join(units.RATE_UNITS)})")
    label = names[idx] if names else f"column {idx}"
    return units.rate_to_si(rate, unit), fs, label


def _read_hdf5(path: Path, name: str | None, column: str | None):
    from gyrobench.sim.recording import load_hdf5

    rec = load_hdf5(path, name)
    ch = column or ("rate" if "rate" in rec.channels else None)
    if ch is None:
        raise _BadInput(f"name the channel with --column; {rec.name!r} has {sorted(rec.channels)}")
    data = rec[ch]
    unit = rec.channels[ch].unit if ch in rec.channels else rec.truth[ch.removeprefix("truth/")].unit
    if unit != "rad/s":
        from gyrobench.sim import units

        data = units.rate_to_si(data, unit)
    return data, rec.fs, f"{rec.name}/{ch}"


def _check_allan_input(rate, fs: float, label: str, kind: str) -> None:
    """Refuse, before the analysis, a sample rate outside any gyro's (the fit's tau**-2 .. tau**2
    terms overflow far outside it), samples too large to square and a run that needs more memory
    than is available (issue 15)."""
    from gyrobench.sim import memory
    from gyrobench.sim.recording import FS_RANGE_HZ, check_magnitude

    if not FS_RANGE_HZ[0] <= fs <= FS_RANGE_HZ[1]:
        raise _BadInput(f"the sample rate of {label} must be in [{FS_RANGE_HZ[0]:g}, {FS_RANGE_HZ[1]:g}] Hz "
                        f"(no gyro samples outside it); got {fs:g} Hz")
    check_magnitude(rate, label)
    memory.check_memory(memory.allan_bytes(len(rate), kind), f"the {kind} Allan analysis of {label} "
                        f"({len(rate)} samples)", hint="analyse a shorter segment")


def _cmd_allan(args) -> int:
    from gyrobench.analysis.allan import allan_deviation, fit_noise
    from gyrobench.scenarios.allan_report import TERMS, coefficients_json
    from gyrobench.scenarios.outputs import check_output

    path = Path(args.file)
    if not path.is_file():
        raise FileNotFoundError(f"recording file not found: {str(path)!r}")
    if args.plot:  # issue 15: outputs before any work
        check_output(args.plot, what="--plot")
    if path.suffix.lower() in (".h5", ".hdf5"):
        if args.fs is not None or args.units is not None:
            raise _BadInput("--fs and --units apply to CSV input; an HDF5 recording carries its own")
        rate, fs, label = _read_hdf5(path, args.recording, args.column)
    else:
        rate, fs, label = _read_csv(path, args.column, args.fs, args.units)
    bad = np.flatnonzero(~np.isfinite(rate))
    if len(bad):
        # float(): print nan / inf, not np.float64(nan)
        raise _BadInput(f"{label} contains {float(rate[bad[0]])} at sample {bad[0]} ({len(bad)} non-finite "
                        f"sample{'s' if len(bad) > 1 else ''}): the data must be finite")
    _check_allan_input(rate, fs, label, args.kind)  # issue 15: magnitudes that overflow, memory
    curve = allan_deviation(rate, fs, taus=args.taus, kind=args.kind)
    if len(curve.tau) < len(TERMS):
        raise _BadInput(
            f"{label}: {len(rate)} samples at {fs:g} Hz give {len(curve.tau)} {curve.kind} Allan deviation "
            f"point(s) at taus={args.taus!r} (up to {curve.tau[-1]:.3g} s); the Q/N/B/K/R fit needs "
            f"at least {len(TERMS)}: use a longer record or --taus all"
        )
    fit = fit_noise(curve)
    js = coefficients_json(fit)
    if args.json:
        print(json.dumps({k: {kk: d[kk] for kk in ("value", "low", "high", "unit")} for k, d in js.items()}))
    else:
        print(f"{label}: {len(rate)} samples at {fs:g} Hz ({len(rate) / fs / 3600:.3g} h); {curve.kind} Allan deviation, "
              f"{len(curve.tau)} taus from {curve.tau[0]:.3g} to {curve.tau[-1]:.3g} s")
        print(f"{'term':<5}{'value':>14}  {'95 % interval':<28}{'unit'}")
        for name, d in js.items():
            if d["value"] is None:
                print(f"{name:<5}{'n/i':>14}  {'< ' + format(d['high'], '.3g'):<28}{d['unit']}   (not identifiable from this record)")
            else:
                print(f"{name:<5}{d['value']:>14.4g}  [{d['low']:.4g}, {d['high']:.4g}]".ljust(49) + f"{d['unit']}")
    if args.plot:
        from gyrobench.scenarios.figures import allan_figure
        from gyrobench.sim.recording import atomic_path

        fig = allan_figure(curve, fit, title=label)
        plot = Path(args.plot)
        with atomic_path(plot) as tmp:
            fig.savefig(tmp, format=(plot.suffix.lstrip(".") or "png"), dpi=120, bbox_inches="tight")
        if not args.json:
            print(f"wrote {plot}")
    return 0


# ----------------------------------------------------------------------------- reproduce
def _cmd_reproduce(args) -> int:
    from tqdm import tqdm

    from gyrobench.scenarios import registry
    from gyrobench.scenarios.outputs import check_output, write_report_as_a_set

    names = registry.available() if args.all else list(args.scenarios)
    if not names:
        raise _BadInput("name at least one scenario or give --all (see 'gyrobench list')")
    if args.all and args.scenarios:
        raise _BadInput("give either --all or scenario names, not both")
    if args.config and len(names) != 1:
        raise _BadInput("--config applies to one scenario; name exactly one")
    mods = [registry.get(n) for n in names]  # fails fast on an unknown name
    configs = [registry.load_config(m, args.config) for m in mods]
    check_output(args.out, what="--out", kind="report")  # issue 15: before any work
    outcomes = []
    t0 = time.perf_counter()
    bar = tqdm(list(zip(mods, configs, strict=True)), desc="reproduce", unit="scenario", disable=args.quiet)
    with _closing(bar):
        for mod, cfg in bar:
            bar.set_postfix_str(mod.NAME)
            outcomes.append(mod.run(cfg, args.seed, progress=not args.quiet))
    index = write_report_as_a_set(outcomes, args.out, command="gyrobench " + " ".join(shlex.quote(a) for a in args.argv))
    held = sum(1 for o in outcomes for h in o.headlines if h.holds is True)
    total = sum(1 for o in outcomes for h in o.headlines if h.holds is not None)
    print(f"{len(outcomes)} scenario(s) in {time.perf_counter() - t0:.1f} s; {held}/{total} testable headline conclusions hold")
    for o in outcomes:
        print(f"  {o.scenario:<20} {o.runtime_s:7.1f} s   {Path(args.out) / o.scenario / 'results.json'}")
    print(f"report: {index}")
    return 0


# ----------------------------------------------------------------------------- parser
def _seed(text: str) -> int:
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"--seed must be an integer >= 0; got {text!r}") from None
    if v < 0:
        raise argparse.ArgumentTypeError(f"--seed must be an integer >= 0; got {text!r}")
    return v


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="gyrobench", description="Gyroscope simulator and test bench.",
                epilog="exit status: 0 ok; 1 bench: significant regression; 2 bad input (one line on "
                       "stderr); 3 bench: the compensator failed on some seeds (non-finite output); "
                       "4 internal failure (a worker died, non-deterministic runs, a bug); "
                       "130 interrupted. GYROBENCH_TRACEBACK=1 prints the traceback of an error.")
    p.add_argument("--version", action="version", version=f"gyrobench {_version()}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)

    s = sub.add_parser("list", help="list the registered scenarios")
    s.set_defaults(func=_cmd_list)

    s = sub.add_parser("simulate", help="simulate a noise record or every recording of a scenario",
                       description="'simulate noise' streams one record with the given IEEE-952 coefficients; "
                                   "'simulate SCENARIO' writes every recording of a scenario (HDF5 with truth).")
    s.add_argument("target", help="'noise' or a scenario name (see 'gyrobench list')")
    # noise-only flags default to None so that giving one to a scenario (or the reverse) can be refused
    s.add_argument("--Q", type=_nonneg_float("--Q"), help="noise: quantization [arcsec] (default 0)")
    s.add_argument("--N", type=_nonneg_float("--N"), help="noise: angle random walk [deg/sqrt(h)] (default 0)")
    s.add_argument("--B", type=_nonneg_float("--B"), help="noise: bias instability [deg/h] (default 0)")
    s.add_argument("--K", type=_nonneg_float("--K"), help="noise: rate random walk [deg/h/sqrt(h)] (default 0)")
    s.add_argument("--R", type=_nonneg_float("--R"), help="noise: rate ramp [deg/h^2] (default 0)")
    s.add_argument("--fs", type=_positive_float("--fs"), help="noise: sample rate [Hz] (default 100)")
    s.add_argument("--duration", type=_duration, help="noise: record length > 0: 10h, 30min, 600s")
    s.add_argument("--seed", type=_seed, help="random seed (default 0)")
    s.add_argument("-o", "--output", help="noise: output file, .h5 or .csv")
    s.add_argument("--out", help="scenario: output folder")
    s.add_argument("--config", help="scenario: TOML file overriding the scenario's parameters")
    s.add_argument("--chunk", type=_positive_int("--chunk"), help=argparse.SUPPRESS)
    s.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    s.set_defaults(func=_cmd_simulate)

    s = sub.add_parser("allan", help="Allan deviation and Q/N/B/K/R fit of a recording (HDF5 or CSV)")
    s.add_argument("file", help="gyrobench HDF5 recording, or CSV (.csv or .csv.gz) from any gyro")
    s.add_argument("--column", help="channel (HDF5, default 'rate') or CSV column name or index")
    s.add_argument("--recording", help="HDF5: recording name when the file holds several")
    s.add_argument("--fs", type=_positive_float("--fs"), help="CSV without a time column: sample rate [Hz]")
    s.add_argument("--units", help="CSV: rate unit, one of deg/s, deg/h, rad/s (default: from the header '[unit]')")
    s.add_argument("--kind", default="overlapping", help="overlapping (default), standard, modified, hadamard, total")
    s.add_argument("--taus", default="octave", help="octave (default), decade or all")
    s.add_argument("--json", action="store_true", help="print the coefficients as JSON")
    s.add_argument("--plot", help="write the ADEV figure (PNG)")
    s.set_defaults(func=_cmd_allan)

    s = sub.add_parser("reproduce", help="run scenarios and write the report (Markdown, HTML, PNG, results.json)")
    s.add_argument("scenarios", nargs="*", help="scenario names (see 'gyrobench list')")
    s.add_argument("--all", action="store_true", help="every registered scenario")
    s.add_argument("--out", default="gyrobench-report", help="output folder (default gyrobench-report)")
    s.add_argument("--seed", type=_seed, default=0, help="random seed (default 0)")
    s.add_argument("--config", help="TOML file overriding one scenario's parameters")
    s.add_argument("-q", "--quiet", action="store_true", help="no progress bars")
    s.set_defaults(func=_cmd_reproduce)

    try:
        from gyrobench.scenarios import bench_cli
    except ImportError:  # pragma: no cover - bench not installed
        bench_cli = None
    if bench_cli is not None:
        bench_cli.add_parser(sub)
    return p


def _version() -> str:
    from gyrobench.sim.recording import package_version

    return package_version()


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


def _one_line(text: object) -> str:
    """``text`` on one line (a message from a library may hold newlines)."""
    return " ".join(str(text).split())


def _error_status(exc: BaseException) -> tuple[int, str]:
    """(exit status, one-line message) for an exception leaving a verb (see scenarios.exits)."""
    from gyrobench.scenarios import exits

    bench = sys.modules.get("gyrobench.scenarios.bench")
    if bench is not None and isinstance(exc, bench.FailedSeedsError):
        return exits.FAILED_SEEDS, _one_line(exc)
    if isinstance(exc, exits.InternalError):
        return exits.INTERNAL, f"internal failure: {_one_line(exc)}"
    if isinstance(exc, _INPUT_ERRORS):
        msg = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
        return exits.BAD_INPUT, _one_line(msg)
    if isinstance(exc, OverflowError):  # a number too large for the computation: an input value
        return exits.BAD_INPUT, f"a value is too large to compute with ({_one_line(exc)}); check the inputs"
    if isinstance(exc, MemoryError):
        return exits.BAD_INPUT, ("out of memory: the run needs more memory than is available "
                                 "(shorten the record, lower fs or use fewer seeds)")
    if isinstance(exc, OSError):  # a failed write (AtomicWriteError names the target), an unreadable input
        return exits.BAD_INPUT, _one_line(exc)
    import sqlite3

    if isinstance(exc, sqlite3.Error):
        return exits.BAD_INPUT, f"database error: {_one_line(exc)}"
    return exits.INTERNAL, (f"internal failure ({type(exc).__name__}: {_one_line(exc) or 'no message'}); "
                            f"this is a bug: please report it with the output of GYROBENCH_TRACEBACK=1")


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """Warnings in one line each, without the source line Python prints under them."""
    where = Path(str(filename)).name
    print(f"gyrobench: warning: {_one_line(message)} ({category.__name__} in {where}:{lineno})",
          file=sys.stderr if file is None else file)


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``gyrobench`` console script; returns the exit status.

    Exit statuses are listed in :mod:`gyrobench.scenarios.exits`: 0 ok, 1 significant
    regression, 2 bad input, 3 failed seeds, 4 internal failure, 130 interrupted. Every
    error is one line on stderr; ``GYROBENCH_TRACEBACK=1`` prints the traceback first.
    """
    from gyrobench.scenarios import exits

    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser()
    args = parser.parse_args(_attach_negative_values(argv))
    args.argv = argv
    try:
        with warnings.catch_warnings():
            warnings.showwarning = _show_warning
            return int(args.func(args) or 0)
    except KeyboardInterrupt:
        print("gyrobench: interrupted", file=sys.stderr)
        return exits.INTERRUPTED
    except Exception as exc:
        code, msg = _error_status(exc)
        if exits.traceback_wanted():
            text = getattr(exc, "traceback_text", "")  # a compensator's, from its worker process
            if text:
                sys.stderr.write(text)
            else:
                import traceback

                traceback.print_exception(exc, file=sys.stderr)
        print(f"gyrobench: error: {msg}", file=sys.stderr)
        return code


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
