"""The ``gyrobench`` command line.

::

    gyrobench list
    gyrobench simulate noise --N 0.01 --B 0.05 --fs 100 --duration 2h --seed 1 -o rec.h5
    gyrobench simulate SCENARIO --seed 1 --out DIR [--config FILE.toml]
    gyrobench allan FILE [--column NAME] [--fs HZ] [--units deg/s] [--json] [--plot FILE.png]
    gyrobench reproduce --all --out DIR [--seed S]
    gyrobench reproduce SCENARIO [SCENARIO ...] --out DIR
    gyrobench bench SCENARIO --compensator module:attr --seeds 0:100

Exit status: 0 on success, 2 on bad input (one readable line on stderr, no
traceback), 1 when ``bench`` finds a significant regression.
"""

from __future__ import annotations

import argparse
import json
import math
import shlex
import sys
import time
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


# ----------------------------------------------------------------------------- list
def _cmd_list(args) -> int:
    from scenarios import registry

    for name in registry.available():
        mod = registry.get(name)
        bench = " [bench]" if hasattr(mod, "compensation_task") else ""
        print(f"{name:<20} {mod.TITLE}{bench}")
    return 0


# ----------------------------------------------------------------------------- simulate
def _positive_float(name: str):
    def conv(text: str) -> float:
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be a number; got {text!r}") from None
        if not math.isfinite(v) or v <= 0:
            raise argparse.ArgumentTypeError(f"{name} must be a finite number > 0; got {text!r}")
        return v

    return conv


def _nonneg_float(name: str):
    def conv(text: str) -> float:
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be a number; got {text!r}") from None
        if not math.isfinite(v) or v < 0:
            raise argparse.ArgumentTypeError(f"{name} must be a finite number >= 0; got {text!r}")
        return v

    return conv


def _duration(text: str) -> float:
    from sim.units import parse_duration

    try:
        return parse_duration(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def _simulate_noise(args) -> int:
    from tqdm import tqdm

    from sim.noise import NoiseModel
    from sim.recording import HDF5StreamWriter, atomic_path, package_version

    if args.output is None:
        raise _BadInput("simulate noise needs -o FILE.h5 or FILE.csv")
    out = Path(args.output)
    suffix = "".join(out.suffixes[-1:]).lower()
    if suffix not in (".h5", ".hdf5", ".csv"):
        raise _BadInput(f"-o must end in .h5, .hdf5 or .csv; got {str(out)!r}")
    if args.duration is None:
        raise _BadInput("simulate noise needs --duration (e.g. 10h, 30min, 600s)")
    field = {"quantization": args.Q, "angle_random_walk": args.N, "bias_instability": args.B,
             "rate_random_walk": args.K, "rate_ramp": args.R}
    model = NoiseModel.from_datasheet(**field)
    n = int(round(args.duration * args.fs))
    if n < 2:
        raise _BadInput(f"--duration x --fs must give at least 2 samples; got {n}")
    seed = 0 if args.seed is None else args.seed
    stream = model.stream(args.fs, rng=np.random.default_rng(seed))
    meta = {"source": "gyrobench simulate noise", "datasheet": {"Q_arcsec": args.Q, "N_deg_sqrt_h": args.N,
            "B_deg_h": args.B, "K_deg_h_sqrt_h": args.K, "R_deg_h2": args.R}, "seed": seed, "version": package_version()}
    chunk = args.chunk
    bar = tqdm(total=n, unit="sa", unit_scale=True, disable=n < 5 * chunk or args.quiet, desc="simulate")
    if suffix == ".csv":
        with atomic_path(out) as tmp, open(tmp, "w") as fh:
            fh.write("# gyrobench simulate noise; " + json.dumps(meta) + "\n")
            fh.write("time [s],rate [rad/s]\n")
            k = 0
            for y in stream.chunks(n, chunk):
                t = (k + np.arange(len(y))) / args.fs
                np.savetxt(fh, np.column_stack([t, y]), delimiter=",", fmt=["%.12g", "%.17g"])
                k += len(y)
                bar.update(len(y))
    else:
        with HDF5StreamWriter(out, name="noise", fs=args.fs, channels={"rate": "rad/s"}, metadata=meta) as w:
            for y in stream.chunks(n, chunk):
                w.append(rate=y)
                bar.update(len(y))
    bar.close()
    print(f"wrote {n} samples ({n / args.fs:.6g} s at {args.fs:g} Hz) to {out}")
    return 0


def _simulate_scenario(args) -> int:
    from scenarios import registry
    from sim.recording import save_hdf5

    mod = registry.get(args.target)
    config = registry.load_config(mod, args.config)
    if args.out is None:
        raise _BadInput(f"simulate {args.target} needs --out DIR")
    seed = 0 if args.seed is None else args.seed
    recs = mod.simulate(config, seed)
    out = Path(args.out) / mod.NAME
    for r in recs:
        path = save_hdf5(out / f"{r.name}.h5", r)
        print(f"wrote {path} ({r.n_samples} samples at {r.fs:g} Hz; channels {', '.join(r.channels)}; truth {', '.join(r.truth)})")
    return 0


def _cmd_simulate(args) -> int:
    if args.target == "noise":
        return _simulate_noise(args)
    return _simulate_scenario(args)


# ----------------------------------------------------------------------------- allan
def _read_csv(path: Path, column: str | None, fs: float | None, unit: str | None):
    """Read one rate column of a CSV (``#`` comments, optional header, .gz allowed).

    Returns (rate in rad/s, fs [Hz], column label).
    """
    from sim import units

    opener = __import__("gzip").open if path.suffix == ".gz" else open
    header: list[str] | None = None
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
            except ValueError:
                header = cells
            break
        else:
            raise _BadInput(f"{str(path)!r} holds no data rows")
    names = [h.split("[")[0].strip() for h in header] if header else []
    hdr_units = [h[h.index("[") + 1 : h.rindex("]")].strip() if header and "[" in h and "]" in h else None for h in (header or [])]
    if column is None:
        candidates = [i for i, nm in enumerate(names) if not nm.lower().startswith("time")]
        if header is None or len(candidates) != 1:
            raise _BadInput(f"name the rate column with --column (columns: {names or 'unnamed, use an index'})")
        idx = candidates[0]
    elif column in names:
        idx = names.index(column)
    elif header and column in header:
        idx = header.index(column)
    else:
        try:
            idx = int(column)
        except ValueError:
            raise _BadInput(f"--column {column!r} is not in {str(path)!r}; columns: {names}") from None
    time_idx = next((i for i, nm in enumerate(names) if nm.lower() in ("time", "t", "time_s")), None)
    cols = [idx] + ([time_idx] if time_idx is not None and fs is None else [])
    try:
        data = np.loadtxt(path, delimiter=",", comments="#", skiprows=skip, usecols=cols, ndmin=2)
    except (ValueError, IndexError) as exc:
        raise _BadInput(f"cannot read column {column or idx!r} of {str(path)!r}: {exc}") from None
    rate = data[:, 0]
    if fs is None:
        if time_idx is None:
            raise _BadInput(f"{str(path)!r} has no time column: give --fs (sample rate in Hz)")
        dt = np.diff(data[:, 1])
        if len(dt) < 1 or not np.all(dt > 0):
            raise _BadInput(f"time column of {str(path)!r} must be strictly increasing")
        fs = 1.0 / float(np.median(dt))
    unit = unit or (hdr_units[idx] if hdr_units and hdr_units[idx] else None)
    if unit is None:
        raise _BadInput(f"the unit of column {names[idx] if names else idx!r} is unknown: give --units ({'|'.join(units.RATE_UNITS)})")
    label = names[idx] if names else f"column {idx}"
    return units.rate_to_si(rate, unit), fs, label


def _read_hdf5(path: Path, name: str | None, column: str | None):
    from sim.recording import load_hdf5

    rec = load_hdf5(path, name)
    ch = column or ("rate" if "rate" in rec.channels else None)
    if ch is None:
        raise _BadInput(f"name the channel with --column; {rec.name!r} has {sorted(rec.channels)}")
    data = rec[ch]
    unit = rec.channels[ch].unit if ch in rec.channels else rec.truth[ch.removeprefix("truth/")].unit
    if unit != "rad/s":
        from sim import units

        data = units.rate_to_si(data, unit)
    return data, rec.fs, f"{rec.name}/{ch}"


def _cmd_allan(args) -> int:
    from analysis.allan import allan_deviation, fit_noise
    from scenarios.allan_report import coefficients_json

    path = Path(args.file)
    if not path.is_file():
        raise FileNotFoundError(f"recording file not found: {str(path)!r}")
    if path.suffix.lower() in (".h5", ".hdf5"):
        if args.fs is not None or args.units is not None:
            raise _BadInput("--fs and --units apply to CSV input; an HDF5 recording carries its own")
        rate, fs, label = _read_hdf5(path, args.recording, args.column)
    else:
        rate, fs, label = _read_csv(path, args.column, args.fs, args.units)
    bad = np.flatnonzero(~np.isfinite(rate))
    if len(bad):
        raise _BadInput(f"{label} contains {rate[bad[0]]!r} at sample {bad[0]}: the data must be finite")
    curve = allan_deviation(rate, fs, taus=args.taus, kind=args.kind)
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
        from scenarios.figures import allan_figure
        from sim.recording import atomic_path

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

    from scenarios import registry
    from scenarios.report import write_report

    names = registry.available() if args.all else list(args.scenarios)
    if not names:
        raise _BadInput("name at least one scenario or give --all (see 'gyrobench list')")
    if args.all and args.scenarios:
        raise _BadInput("give either --all or scenario names, not both")
    if args.config and len(names) != 1:
        raise _BadInput("--config applies to one scenario; name exactly one")
    mods = [registry.get(n) for n in names]  # fails fast on an unknown name
    configs = [registry.load_config(m, args.config) for m in mods]
    outcomes = []
    t0 = time.perf_counter()
    bar = tqdm(list(zip(mods, configs)), desc="reproduce", unit="scenario", disable=args.quiet)
    for mod, cfg in bar:
        bar.set_postfix_str(mod.NAME)
        outcomes.append(mod.run(cfg, args.seed, progress=not args.quiet))
    bar.close()
    index = write_report(outcomes, args.out, command="gyrobench " + " ".join(shlex.quote(a) for a in args.argv))
    held = sum(1 for o in outcomes for h in o.headlines if h.holds is True)
    total = sum(1 for o in outcomes for h in o.headlines if h.holds is not None)
    print(f"{len(outcomes)} scenario(s) in {time.perf_counter() - t0:.1f} s; {held}/{total} headline conclusions hold")
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
    p = _Parser(prog="gyrobench", description="Gyroscope simulator and test bench.")
    p.add_argument("--version", action="version", version=f"gyrobench {_version()}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)

    s = sub.add_parser("list", help="list the registered scenarios")
    s.set_defaults(func=_cmd_list)

    s = sub.add_parser("simulate", help="simulate a noise record or every recording of a scenario",
                       description="'simulate noise' streams one record with the given IEEE-952 coefficients; "
                                   "'simulate SCENARIO' writes every recording of a scenario (HDF5 with truth).")
    s.add_argument("target", help="'noise' or a scenario name (see 'gyrobench list')")
    s.add_argument("--Q", type=_nonneg_float("--Q"), default=0.0, help="quantization [arcsec]")
    s.add_argument("--N", type=_nonneg_float("--N"), default=0.0, help="angle random walk [deg/sqrt(h)]")
    s.add_argument("--B", type=_nonneg_float("--B"), default=0.0, help="bias instability [deg/h]")
    s.add_argument("--K", type=_nonneg_float("--K"), default=0.0, help="rate random walk [deg/h/sqrt(h)]")
    s.add_argument("--R", type=_nonneg_float("--R"), default=0.0, help="rate ramp [deg/h^2]")
    s.add_argument("--fs", type=_positive_float("--fs"), default=100.0, help="sample rate [Hz] (default 100)")
    s.add_argument("--duration", type=_duration, help="record length: 10h, 30min, 600s")
    s.add_argument("--seed", type=_seed, help="random seed (default 0)")
    s.add_argument("-o", "--output", help="noise: output file, .h5 or .csv")
    s.add_argument("--out", help="scenario: output folder")
    s.add_argument("--config", help="scenario: TOML file overriding the scenario's parameters")
    s.add_argument("--chunk", type=int, default=1 << 20, help=argparse.SUPPRESS)
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
        from scenarios import bench_cli
    except ImportError:  # pragma: no cover - bench not installed
        bench_cli = None
    if bench_cli is not None:
        bench_cli.add_parser(sub)
    return p


def _version() -> str:
    from sim.recording import package_version

    return package_version()


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``gyrobench`` console script; returns the exit status."""
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser()
    args = parser.parse_args(argv)
    args.argv = argv
    try:
        return int(args.func(args) or 0)
    except _INPUT_ERRORS as exc:
        msg = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
        print(f"gyrobench: error: {msg}", file=sys.stderr)
        return 2
    except OSError as exc:
        from sim.recording import RecordingFormatError  # noqa: F401  (a ValueError, caught above)

        print(f"gyrobench: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("gyrobench: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
