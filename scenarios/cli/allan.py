"""``gyrobench allan``: Allan deviation and the noise fit of an HDF5 recording or any IMU's CSV log."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from gyrobench.scenarios.cli.common import (
    MAX_FLAG_VALUE,
    BadInput,
    add_force,
    check_outputs,
    input_file,
    nonneg_float,
    positive_float,
)

__all__ = ["add_parser", "read_csv"]

#: default of --bandwidth-bias: gyrobench.analysis.allan.BANDWIDTH_BIAS, repeated so parsing
#: imports no analysis (tests/scenarios/test_cli.py pins the two)
BANDWIDTH_BIAS = 0.1


def read_csv(path: Path, column: str | None, fs: float | None, unit: str | None):
    """One rate column of a CSV: (rate in rad/s, fs [Hz], column label); see scenarios.logs.read_csv_log.

    Parameters
    ----------
    path : Path
        The CSV file.
    column : str or None
        The rate column (None: the log reader's choice).
    fs : float or None
        Sample rate [Hz] (None: from the time column).
    unit : str or None
        The rate column's unit (None: from its header).

    Returns
    -------
    tuple of (ndarray, float, str)
        (rate [rad/s], fs [Hz], column label).
    """
    from gyrobench.io.logs import read_csv_log

    log = read_csv_log(path, [column] if column is not None else None, fs, unit)
    ch = log.channels[0]
    return ch.data, log.fs, ch.label


def _read_hdf5(path: Path, name: str | None, columns: list[str] | None, start: float | None = None,
               stop: float | None = None):
    """The named channels of a gyrobench HDF5 recording, in SI, between ``start`` and ``stop`` [s after the
    first sample]; only those samples are read. Without names: its outputs (:func:`default_columns`)."""
    import numpy as np

    from gyrobench.io.logs import Channel, Log
    from gyrobench.io.recording import load_hdf5

    rec = load_hdf5(path, name, start=start, stop=stop)
    chans = []
    wanted = list(columns) if columns else default_columns(rec)
    if not wanted:
        raise BadInput(f"name the channel with --column; {rec.name!r} has {sorted(rec.channels)}")
    for ch in wanted:
        try:
            channel = rec.channel(ch)
        except KeyError as exc:
            raise BadInput(f"{str(path)!r}: {exc.args[0]}") from None
        data, unit = channel.data, channel.unit
        if unit in ("rad", "m/s"):  # a triad's increments (simulate imu --increments): x fs is the mean rate
            data, unit = data * rec.fs, {"rad": "rad/s", "m/s": "m/s^2"}[unit]
        quantity = "accel" if unit in ("m/s^2", "m/s/s") else "rate"
        if quantity == "rate" and unit != "rad/s":
            from gyrobench.base import units

            try:
                data = units.rate_to_si(data, unit)
            except ValueError as exc:  # name the file and the channel, not only the unit
                raise BadInput(f"{str(path)!r}: channel {rec.name}/{ch}: {exc}") from None
        chans.append(Channel(label=f"{rec.name}/{ch}", quantity=quantity, data=np.asarray(data, dtype=float),
                             unit=unit))
    notes = []
    if start is not None or stop is not None:
        notes.append(f"segment {start or 0.0:g} s to {(start or 0.0) + rec.n_samples / rec.fs:g} s (--start/--stop)")
    return Log(path=path, fs=rec.fs, channels=chans, fmt="hdf5", t0=rec.t0, notes=notes)


def default_columns(rec) -> list[str]:
    """The channels ``allan`` and ``twin`` read of a recording given no ``--column``: ``output`` (a file of
    the first format's ``rate`` is read as ``output``), or a triad's outputs (the keys of the metadata's
    ``error_components``), or the only channel; empty when none of these applies."""
    from collections.abc import Mapping

    if "output" in rec.channels:
        return ["output"]
    comps = rec.metadata.get("error_components")
    if isinstance(comps, Mapping) and all(k in rec.channels for k in comps):
        return list(comps)
    return list(rec.channels) if len(rec.channels) == 1 else []


def _analyse_pieces(ch, log, args):
    """``--gaps split``: the gap-aware overlapping Allan deviation of ``ch`` over ``log.pieces`` and its fit.

    The stationarity check runs on the longest piece (a step across a gap is not motion).
    """
    import numpy as np

    from gyrobench.analysis.allan import allan_deviation_gaps, bandwidth_range, fit_noise, fit_range
    from gyrobench.scenarios.reports import allan as rep

    if args.segments is not None:
        raise BadInput("--segments auto is not available with --gaps split (the record has gaps): give --gaps fill")
    if args.kind != "overlapping" or args.taus == "all":
        raise BadInput(f"--gaps split computes the overlapping Allan deviation at octave or decade taus; got --kind "
                       f"{args.kind} --taus {args.taus}: give --gaps fill for the other statistics")
    pieces = [ch.data[a:b] for a, b in log.pieces]
    curve = allan_deviation_gaps(pieces, log.fs, taus=args.taus)
    if len(curve.tau) < len(args.terms):
        raise BadInput(f"{ch.label}: the pieces between the gaps give {len(curve.tau)} Allan deviation point(s); the "
                       f"{'/'.join(args.terms)} fit needs at least {len(args.terms)}: use fewer --terms")
    longest = pieces[int(np.argmax([len(p) for p in pieces]))]
    warn, moving, _ = rep.stationarity(longest, log.fs, curve, ch.label)
    fit = fit_noise(curve, terms=args.terms, tau_min=args.tau_min, tau_max=args.tau_max, bandwidth=args.bandwidth,
                    bandwidth_bias=args.bandwidth_bias)
    fr = fit_range(curve, n_terms=len(args.terms)) if args.tau_min == "auto" else None
    bw = bandwidth_range(curve, args.bandwidth, bias=args.bandwidth_bias) if args.bandwidth is not None else None
    return rep.ChannelResult(ch, curve, fit=fit, fit_range=fr, bandwidth_range=bw, warnings=warn, nonstationary=moving)


def _terms_arg(text: str) -> tuple[str, ...]:
    from gyrobench.analysis.allan import TERMS

    names = tuple(t.strip().upper() for t in text.split(",") if t.strip())
    bad = [t for t in names if t not in TERMS]
    if bad or not names or len(set(names)) != len(names):
        raise argparse.ArgumentTypeError(f"--terms must be distinct names from {','.join(TERMS)}; got {text!r}")
    return names


def _tau_min_arg(text: str):
    return "auto" if text == "auto" else positive_float("--tau-min", MAX_FLAG_VALUE)(text)


#: the smallest largest-sample size ``allan`` analyses: the fit squares deviations and sums their
#: powers of tau; records of N(0, 1e-70) still fit exactly (N to 4 digits), 1e-90 fails in the
#: NNLS and 1e-180 underflowed to a ZeroDivisionError: 1e-60 keeps a 1e10 margin
MIN_MAGNITUDE = 1e-60


def _check_allan_input(rate, fs: float, label: str, kind: str) -> None:
    """Refuse, before the analysis, a sample rate outside any gyro's (the fit's tau**-2 .. tau**2
    terms overflow far outside it), samples too large to square and a run that needs more memory
    than is available."""
    from gyrobench.base import memory
    from gyrobench.io.recording import FS_RANGE_HZ, check_magnitude

    if not FS_RANGE_HZ[0] <= fs <= FS_RANGE_HZ[1]:
        raise BadInput(f"the sample rate of {label} must be in [{FS_RANGE_HZ[0]:g}, {FS_RANGE_HZ[1]:g}] Hz "
                        f"(no gyro samples outside it); got {fs:g} Hz")
    check_magnitude(rate, label)
    import numpy as np

    peak = float(np.max(np.abs(rate))) if len(rate) else 0.0
    if 0.0 < peak < MIN_MAGNITUDE:  # the fit's squared deviations underflow (1e-180 ended in ZeroDivisionError)
        raise BadInput(f"the samples of {label} are at most {peak:.3g} in size, too small to analyse in float64 "
                       f"(the fit squares deviations of them; it needs samples above {MIN_MAGNITUDE:g}): "
                       "check its unit and scale")
    memory.check_memory(memory.allan_bytes(len(rate), kind), f"the {kind} Allan analysis of {label} "
                        f"({len(rate)} samples)", hint="analyse a shorter segment")


# ----------------------------------------------------------------------------- output safety
#: the suffixes of allan's outputs
PLOT_SUFFIXES = (".png",)
KALIBR_SUFFIXES = (".yaml", ".yml")


def _check_allan_outputs(args, path: Path) -> None:
    """--plot and --kalibr through the output rule (gyrobench.base.safety), before anything is read."""
    from gyrobench.base.safety import Output

    outs = [Output(Path(args.plot), "--plot", suffixes=PLOT_SUFFIXES, create_parents=False)] if args.plot else []
    outs += _yaml_outputs(args)
    check_outputs(args, outs, [("FILE", path)])


def _yaml_outputs(args) -> list:
    """--kalibr and --filter-model as outputs of the rule (YAML files)."""
    from gyrobench.base.safety import Output

    return [Output(Path(target), flag, suffixes=KALIBR_SUFFIXES, create_parents=False)
            for flag, target in (("--kalibr", args.kalibr), ("--filter-model", getattr(args, "filter_model", None)))
            if target]


def _check_plot_files(args, path: Path, log) -> list[Path]:
    """The figure file of each channel of ``log`` (``FILE_<channel>.png`` for several), each through the
    output rule before the analysis; [] without --plot."""
    import types

    from gyrobench.base.safety import Output
    from gyrobench.scenarios.reports import allan_text as txt

    if not args.plot:
        return []
    named = [types.SimpleNamespace(channel=ch) for ch in log.channels]  # plot_paths reads only the label
    plots = [p for p, _ in txt.plot_paths(Path(args.plot), named)]  # type: ignore[arg-type]
    if len(plots) > 1:
        outs = [Output(p, "--plot", suffixes=PLOT_SUFFIXES, create_parents=False) for p in plots]
        check_outputs(args, outs + _yaml_outputs(args), [("FILE", path)])
    return plots


def _temperature_columns(path: Path) -> list[str]:
    """Header cells of a CSV that name a temperature ("temp" in the name), from its first non-comment line."""
    import gzip
    import re

    try:
        opener = gzip.open if path.suffix.lower() == ".gz" else open
        with opener(path, "rt", errors="replace") as fh:
            for _, line in zip(range(50), fh, strict=False):
                if line.strip() and not line.lstrip().startswith(("#", "%")):
                    cells = [c.strip().strip('"') for c in re.split(r"[,;\t]", line)]
                    return [c for c in cells if re.search("temp", c, re.IGNORECASE)]
    except OSError:
        return []
    return []


def _temperature_hints(path: Path, args, results) -> None:
    """A warning on each channel with an identified rate ramp R when the file has a temperature column
    that --temperature did not name: a thermal drift reads as R."""
    if args.temperature is not None or path.suffix.lower() in (".h5", ".hdf5"):
        return
    cols = None
    for res in results:
        c = res.fit.coefficients.get("R") if res.fit is not None else None
        if c is None or not c.identifiable:
            continue
        cols = _temperature_columns(path) if cols is None else cols
        if cols:
            res.warnings.append(f"{res.channel.label}: a rate ramp R is identified and {path.name} has a temperature "
                                f"column ({', '.join(repr(x) for x in cols)}): a thermal drift reads as R; try "
                                f"--temperature {cols[0].split('[')[0].strip()!r}")


def _cmd_allan(args) -> int:
    from gyrobench.scenarios.reports import allan as rep
    from gyrobench.scenarios.reports import allan_text as txt

    path = input_file(args.file, "recording file")  # not found, a folder, a FIFO, a device: one line
    _check_allan_outputs(args, path)  # before any work
    columns = args.column or None
    if path.suffix.lower() in (".h5", ".hdf5"):
        if args.fs is not None or args.units is not None:
            raise BadInput("--fs and --units apply to CSV input; an HDF5 recording carries its own")
        if args.gaps != "refuse":
            raise BadInput("--gaps applies to CSV input; an HDF5 recording is uniformly sampled")
        log = _read_hdf5(path, args.recording, columns, args.start, args.stop)
    else:
        from gyrobench.io.logs import read_csv_log

        log = read_csv_log(path, columns, args.fs, args.units, all_axes=args.all_axes, start=args.start,
                           stop=args.stop, temperature=args.temperature, decimal=args.decimal, gaps=args.gaps)
    plots = _check_plot_files(args, path, log)  # one figure per channel, each checked before the analysis
    if args.bandwidth is None and args.bandwidth_bias != BANDWIDTH_BIAS:
        raise BadInput("--bandwidth-bias applies with --bandwidth HZ")
    if args.bandwidth is not None and not args.bandwidth < log.fs / 2:
        raise BadInput(f"--bandwidth must be < the Nyquist frequency fs/2 = {log.fs / 2:g} Hz of {path.name} "
                        f"(sampled at {log.fs:g} Hz); got {args.bandwidth:g} Hz")
    results = []
    for ch in log.channels:
        rep.check_finite(ch)
        _check_allan_input(ch.data, log.fs, ch.label, args.kind)  # magnitudes that overflow, memory
        if log.pieces is not None:
            results.append(_analyse_pieces(ch, log, args))
            continue
        results.append(rep.analyse(ch, log.fs, taus=args.taus, kind=args.kind, terms=args.terms,
                                   tau_min=args.tau_min, tau_max=args.tau_max, temperature=log.temperature,
                                   bandwidth=args.bandwidth, bandwidth_bias=args.bandwidth_bias,
                                   segments=args.segments))
    _temperature_hints(path, args, results)
    if any(n.startswith("--gaps fill:") for n in log.notes):
        for res in results:
            res.warnings.append(
                f"{res.channel.label}: the filled samples are interpolated, not measured: a straight line across a "
                "gap removes its noise and adds a ramp-like error at taus near the gap's length (B, K and R are "
                "biased); --gaps split analyses the contiguous pieces instead (pooled per tau)")
    if args.kalibr:
        from gyrobench.base.atomic import atomic_path

        text = txt.kalibr_yaml(log, results)
        with atomic_path(Path(args.kalibr)) as tmp:
            Path(tmp).write_text(text)
    if args.filter_model:
        from gyrobench.base.atomic import atomic_path

        text = txt.filter_yaml(log, results, overbound=args.overbound)
        with atomic_path(Path(args.filter_model)) as tmp:
            Path(tmp).write_text(text)
    if args.json:
        print(json.dumps(txt.log_json(log, results)))
    else:
        print("\n".join(txt.log_text(log, results)))
    if args.plot:
        from gyrobench.base.atomic import atomic_path
        from gyrobench.base.safety import PNG_METADATA
        from gyrobench.scenarios.reports.figures import allan_figure

        for plot, res in zip(plots, results, strict=True):  # one file per channel
            fig = allan_figure(res.curve, res.fit, title=txt.plot_title(log, res), quantity=res.channel.quantity)
            with atomic_path(plot) as tmp:
                fig.savefig(tmp, format="png", dpi=120, bbox_inches="tight", metadata=PNG_METADATA)
            if not args.json:
                print(f"wrote {plot}")
    if any(r.nonstationary for r in results) and not args.accept_nonstationary:
        from gyrobench.scenarios.cli import exits

        return exits.NONSTATIONARY
    return 0


def add_parser(sub) -> None:
    """Add ``allan`` to the subparsers ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The ``gyrobench`` command's subparsers.
    """
    s = sub.add_parser("allan", help="Allan deviation and Q/N/B/K/R fit of a recording (HDF5 or CSV)",
                       epilog="exit status: 0 ok; 2 bad input; 5 a channel is not stationary (motion or steps: "
                              "the report is written, its first line says so; --accept-nonstationary exits 0)")
    s.add_argument("file", help="gyrobench HDF5 recording, or CSV (.csv or .csv.gz) from any gyro (EuRoC, Kalibr, "
                                "ROS exports included)")
    s.add_argument("--column", action="append", help="channel (HDF5, default 'rate') or CSV column name or index; "
                                                     "repeat for several (one table)")
    s.add_argument("--all-axes", action="store_true", help="CSV: every gyro and accelerometer column")
    s.add_argument("--recording", help="HDF5: recording name when the file holds several")
    s.add_argument("--fs", type=positive_float("--fs"), help="CSV without a time column: sample rate [Hz]")
    s.add_argument("--units", help="CSV: unit per column kind, e.g. gyro=deg/s,accel=g, or one unit (deg/s, deg/h, "
                                   "rad/s, m/s^2, g) for the columns of its kind; a column's kind comes from its "
                                   "name or header (gyro, omega, acc, ax ...), and one reading gravity is never "
                                   "taken as a gyro (default: from the header '[unit]' or the format)")
    s.add_argument("--start", type=nonneg_float("--start", MAX_FLAG_VALUE),
                   help="analyse from this time [s after the first sample]")
    s.add_argument("--stop", type=nonneg_float("--stop", MAX_FLAG_VALUE),
                   help="analyse up to this time [s after the first sample]")
    s.add_argument("--gaps", choices=("refuse", "fill", "split"), default="refuse",
                   help="CSV: missing samples in the time column: refuse (default, naming the first gap), fill "
                        "(linear interpolation; the count is reported) or split (the Allan variance over each "
                        "contiguous piece, pooled per tau)")
    s.add_argument("--temperature", help="CSV: temperature column [degC]; its explained part (c_T (T - Tbar) + "
                                         "c_dT dT/dt, least squares) is removed before the analysis")
    s.add_argument("--decimal", choices=(".", ","),
                   help="CSV: decimal mark of the numbers (default: detected; a decimal comma needs ';' or tab "
                        "separators to be detected)")
    s.add_argument("--kind", default="overlapping",
                   choices=("overlapping", "standard", "modified", "hadamard", "overlapping_hadamard", "total"),
                   help="overlapping (default) or standard Allan deviation, fitted; modified, hadamard, "
                        "overlapping_hadamard, total: the curve only (no fit: their term coefficients differ)")
    s.add_argument("--taus", default="octave", choices=("octave", "decade", "all"),
                   help="octave (default), decade or all (every m; the fit uses the octave taus among them)")
    s.add_argument("--terms", type=_terms_arg, default=("Q", "N", "B", "K", "R"),
                   help="terms to fit, e.g. N,B,K (default Q,N,B,K,R)")
    s.add_argument("--tau-min", type=_tau_min_arg, default="auto",
                   help="shortest tau to fit [s], or 'auto' (default: above the filter-shaped short-tau region)")
    s.add_argument("--tau-max", type=positive_float("--tau-max", MAX_FLAG_VALUE), help="longest tau to fit [s]")
    s.add_argument("--bandwidth", type=positive_float("--bandwidth"), metavar="HZ",
                   help="the sensor's bandwidth [Hz], 0 < HZ < fs/2: taus its low-pass still biases are not fitted "
                        "(with --tau-min the larger limit wins; the output names the rule that set it)")
    s.add_argument("--bandwidth-bias", type=positive_float("--bandwidth-bias"), default=BANDWIDTH_BIAS,
                   metavar="FRACTION",
                   help="with --bandwidth: largest filter bias of a fitted white-noise point, as a fraction of its "
                        f"standard error (default {BANDWIDTH_BIAS:g})")
    s.add_argument("--segments", choices=("auto",),
                   help="auto: on a channel with motion or steps, also fit each quiet stretch between them on "
                        "its own (SEGMENTS lines, JSON 'segments') and all of them in one pooled fit (POOLED line, "
                        "JSON 'pooled')")
    s.add_argument("--accept-nonstationary", action="store_true",
                   help="exit 0 also when motion or steps are found (default: exit status 5)")
    s.add_argument("--json", action="store_true", help="print the curve and fit as JSON")
    s.add_argument("--plot", help="write the ADEV figure (PNG); with several channels one file per channel, "
                                  "FILE_<channel>.png")
    s.add_argument("--kalibr", help="write the Kalibr IMU noise file (imu.yaml: noise densities and random walks "
                                    "from N and K, largest over the axes)")
    s.add_argument("--filter-model", metavar="FILE",
                   help="write the fitted model as a filter's process noise (YAML: white and random-walk densities, "
                        "B as Gauss-Markov and random-walk equivalent, Kalibr, OpenVINS and ROS conventions, units "
                        "in every key)")
    s.add_argument("--overbound", action="store_true",
                   help="with --filter-model: scale the model to lie on or above the data's upper 95 %% bound at "
                        "every tau")
    add_force(s)
    s.set_defaults(func=_cmd_allan)
