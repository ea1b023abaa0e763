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
import typing
import warnings
from pathlib import Path

__all__ = ["main"]

#: exceptions that mean "bad input": reported in one line, exit 2
_INPUT_ERRORS: tuple[type[BaseException], ...] = (
    ValueError, TypeError, KeyError, FileNotFoundError, IsADirectoryError, PermissionError
)


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> typing.NoReturn:  # one line, exit 2
        self.exit(2, f"gyrobench: error: {message} (see '{self.prog} --help')\n")


class _BadInput(ValueError):
    pass


#: default of --bandwidth-bias: gyrobench.analysis.allan.BANDWIDTH_BIAS, repeated so parsing
#: imports no analysis (tests/scenarios/test_cli.py pins the two)
_BANDWIDTH_BIAS = 0.1


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
    from gyrobench.scenarios.papers import citation

    for name in registry.available():
        info = registry.describe(name)
        bench = " [bench]" if info.bench else ""
        print(f"{name:<20} {info.title}{bench}")
        if info.paper is not None:
            print(f"{'':<20}   paper {info.paper}: {citation(info.paper)}")
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


def _units_or_auto(text: str) -> int | str:
    """``--units``: a positive integer, or ``auto``."""
    return "auto" if text == "auto" else _positive_int("--units (or 'auto')")(text)


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
    import numpy as np
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
    from tqdm import tqdm

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


# ----------------------------------------------------------------------------- device and parts
#: flags of 'simulate device' only (dest -> flag)
_DEVICE_FLAGS = {"rate_csv": "--rate-csv", "temperature_csv": "--temperature-csv", "profile": "--profile"}


def _profile_from_csv(path: str, flag: str, convert) -> tuple[typing.Any, float]:
    """A (time [s], value) CSV as a PiecewiseLinear in SI, and its last time [s].

    The file has a header row and two columns: time [s] (strictly increasing) and the value
    in the flag's field unit (``--rate-csv`` deg/s, ``--temperature-csv`` degC).
    """
    import numpy as np
    from gyrobench.sim.environment import PiecewiseLinear

    p = Path(path)
    if not p.is_file():
        raise _BadInput(f"{flag}: file {path!r} does not exist")
    try:
        data = np.loadtxt(p, delimiter=",", skiprows=1, ndmin=2, dtype=float)
    except ValueError as exc:
        raise _BadInput(f"{flag}: {path!r} is not a CSV of numbers under one header row: {_one_line(exc)}") from None
    if data.shape[1] != 2 or data.shape[0] < 2:
        raise _BadInput(f"{flag}: {path!r} must hold >= 2 rows of two columns (time [s], value); got {data.shape}")
    if not np.all(np.isfinite(data)):
        raise _BadInput(f"{flag}: {path!r} holds NaN or inf")
    t = data[:, 0]
    if not np.all(np.diff(t) > 0):
        raise _BadInput(f"{flag}: {path!r}: the time column must increase strictly")
    return PiecewiseLinear(t - t[0], convert(data[:, 1])), float(t[-1] - t[0])


def _profile_value(v, key: str, path: str, convert):
    """A profile TOML value: a number or a list of [time_s, value] knots (linear between them)."""
    import numpy as np
    from gyrobench.sim.environment import PiecewiseLinear

    if isinstance(v, (int, float)) and not isinstance(v, bool):
        return float(convert(np.array([float(v)]))[0])
    if isinstance(v, list) and v and all(isinstance(k, list) and len(k) == 2 for k in v):
        arr = np.asarray(v, dtype=float)
        return PiecewiseLinear(arr[:, 0], convert(arr[:, 1]))
    raise _BadInput(f"--profile {path!r}: {key} must be a number or a list of [time_s, value] pairs; got {v!r}")


def _device_environment(args, part):
    """(Environment, fs) from --profile or --rate-csv/--temperature-csv, --duration and --fs."""
    import math

    import numpy as np
    from gyrobench.sim.sensor import Environment

    if args.profile is not None and (args.rate_csv is not None or args.temperature_csv is not None):
        raise _BadInput("simulate device: give --profile or --rate-csv/--temperature-csv, not both")
    dps = np.radians
    kelvin = lambda c: np.asarray(c, dtype=float) + 273.15  # noqa: E731
    g0 = lambda g: np.asarray(g, dtype=float) * 9.80665  # noqa: E731
    rate: typing.Any = 0.0
    temp: typing.Any = None
    force: typing.Any = 0.0
    duration = args.duration
    if args.profile is not None:
        data = _read_toml(args.profile, "--profile")
        allowed = {"duration_s", "rate_dps", "temperature_c", "specific_force_g"}
        if unknown := sorted(set(data) - allowed):
            raise _BadInput(f"--profile {args.profile!r}: unknown key(s) {unknown}; allowed: {sorted(allowed)}")
        if "rate_dps" in data:
            rate = _profile_value(data["rate_dps"], "rate_dps", args.profile, dps)
        if "temperature_c" in data:
            temp = _profile_value(data["temperature_c"], "temperature_c", args.profile, kelvin)
        if "specific_force_g" in data:
            force = _profile_value(data["specific_force_g"], "specific_force_g", args.profile, g0)
        if duration is None and "duration_s" in data:
            duration = float(data["duration_s"])
    else:
        if args.rate_csv is not None:
            rate, span = _profile_from_csv(args.rate_csv, "--rate-csv", dps)
            duration = span if duration is None else duration
        if args.temperature_csv is not None:
            temp, span = _profile_from_csv(args.temperature_csv, "--temperature-csv", kelvin)
            duration = span if duration is None else duration
    if duration is None:
        raise _BadInput("simulate device needs --duration (or a profile's duration_s, or a CSV's time span)")
    fs = args.fs if args.fs is not None else (part.datasheet.output_rate or 100.0)
    if not (math.isfinite(duration * fs) and duration * fs < 2**31):
        raise _BadInput(f"--duration x --fs = {duration:g} s x {fs:g} Hz is too many samples for one record in memory")
    try:
        return Environment(duration, true_rate=rate, temperature=temp, specific_force=force), fs
    except (TypeError, ValueError) as exc:
        raise _BadInput(f"simulate device: {_one_line(exc)}") from None


def _read_toml(path: str, flag: str) -> dict:
    import sys

    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover
        import tomli as tomllib
    try:
        with open(path, "rb") as fh:
            return tomllib.load(fh)
    except FileNotFoundError:
        raise _BadInput(f"{flag}: file {path!r} does not exist") from None
    except tomllib.TOMLDecodeError as exc:
        raise _BadInput(f"{flag}: {path!r} is not valid TOML: {_one_line(exc)}") from None


def _simulate_device(args) -> int:
    """One record of a part (built-in name or FILE.toml) in a rate/temperature profile -> -o FILE.h5|.csv."""
    import numpy as np
    from gyrobench.scenarios.outputs import check_output
    from gyrobench.scenarios.static_noise import MIN_SAMPLES
    from gyrobench.sim import memory, parts
    from gyrobench.sim.recording import save_hdf5, to_csv

    if extra := [f for f in _given(args, _NOISE_FLAGS) if f not in ("--fs", "--duration", "-o/--output")]:
        raise _BadInput(f"simulate device: {', '.join(extra)} apply to 'simulate noise' only")
    if extra := _given(args, _SCENARIO_FLAGS):
        raise _BadInput(f"simulate device: {', '.join(extra)} apply to 'simulate SCENARIO' only")
    if args.part is None:
        raise _BadInput(f"simulate device needs a PART: one of {', '.join(parts.names())}, or a FILE.toml")
    try:
        part = parts.get(args.part)
    except ValueError as exc:
        raise _BadInput(_one_line(exc)) from None
    if args.output is None:
        raise _BadInput("simulate device needs -o FILE.h5 or FILE.csv")
    out = Path(args.output)
    suffix = out.suffix.lower()
    if suffix not in (".h5", ".hdf5", ".csv"):
        raise _BadInput(f"-o must end in .h5, .hdf5 or .csv; got {str(out)!r}")
    check_output(out, what="-o", kind="file")
    env, fs = _device_environment(args, part)
    n = env.n_samples(fs)
    if n < MIN_SAMPLES:
        raise _BadInput(f"simulate device: {env.duration:g} s at {fs:g} Hz gives {n} samples; "
                        f"a record needs at least {MIN_SAMPLES}")
    # output, true rate, 7 error components, temperature, force, plus the model's temporaries
    memory.check_memory(memory.series_bytes(n, 20), "simulate device", hint="shorten --duration or lower --fs")
    seed = 0 if args.seed is None else args.seed
    rec = part.simulate(env, fs=fs, rng=np.random.default_rng(seed))
    path = to_csv(out, rec) if suffix == ".csv" else save_hdf5(out, rec)
    print(f"wrote {path} ({rec.n_samples} samples at {fs:g} Hz; channels {', '.join(rec.channels)}; "
          f"truth {', '.join(rec.truth)})")
    return 0


def _cmd_parts(args) -> int:
    """List the built-in parts with their datasheet figures, sources and the notes on what was assumed."""
    from gyrobench.sim import parts

    def fmt(v, unit: str) -> str:
        return "-" if v is None else f"{v:g} {unit}"

    for d in parts.datasheets():
        noise = (fmt(d.arw, "deg/sqrt(h)") if d.arw is not None
                 else f"{fmt(d.noise_density, 'deg/s/sqrt(Hz)')} ({d.noise_density_sided}-sided)")
        print(f"{d.name}: {d.manufacturer} {d.model} [{d.technology}, {d.grade}]")
        print(f"    range {fmt(d.range_dps, 'deg/s')}; bias instability {fmt(d.bias_instability_dph, 'deg/h')}; "
              f"noise {noise}; bias repeatability {fmt(d.bias_repeatability, 'deg/h')}; "
              f"scale factor {fmt(d.scale_factor_repeatability, 'ppm')}; g-sensitivity "
              f"{fmt(d.g_sensitivity, 'deg/h/g')}; bandwidth {fmt(d.bandwidth, 'Hz')}; "
              f"resolution {fmt(d.resolution, 'deg/s')}")
        print(f"    source: {d.source}")
        if d.notes:
            print(f"    notes: {d.notes}")
    return 0


def _cmd_simulate(args) -> int:
    if args.target == "device":
        return _simulate_device(args)
    if args.part is not None:
        raise _BadInput(f"simulate {args.target}: a second positional ({args.part!r}) is taken "
                        "by 'simulate device PART' only")
    if extra := _given(args, _DEVICE_FLAGS):
        raise _BadInput(f"simulate {args.target}: {', '.join(extra)} apply to 'simulate device' only")
    if args.target == "noise":
        return _simulate_noise(args)
    return _simulate_scenario(args)


# ----------------------------------------------------------------------------- allan
# CSV/log reading lives in scenarios/logs.py; these names stay for callers of the old helpers
def _read_csv(path: Path, column: str | None, fs: float | None, unit: str | None):
    """One rate column of a CSV: (rate in rad/s, fs [Hz], column label); see scenarios.logs.read_csv_log."""
    from gyrobench.scenarios.logs import read_csv_log

    log = read_csv_log(path, [column] if column is not None else None, fs, unit)
    ch = log.channels[0]
    return ch.data, log.fs, ch.label


def _read_hdf5(path: Path, name: str | None, columns: list[str] | None):
    import numpy as np
    from gyrobench.scenarios.logs import Channel, Log
    from gyrobench.sim.recording import load_hdf5

    rec = load_hdf5(path, name)
    chans = []
    wanted: list[str | None] = list(columns) if columns else ["rate" if "rate" in rec.channels else None]
    for ch in wanted:
        if ch is None:
            raise _BadInput(f"name the channel with --column; {rec.name!r} has {sorted(rec.channels)}")
        data = rec[ch]
        unit = rec.channels[ch].unit if ch in rec.channels else rec.truth[ch.removeprefix("truth/")].unit
        if unit != "rad/s":
            from gyrobench.sim import units

            try:
                data = units.rate_to_si(data, unit)
            except ValueError as exc:  # name the file and the channel, not only the unit
                raise _BadInput(f"{str(path)!r}: channel {rec.name}/{ch}: {exc}") from None
        chans.append(Channel(label=f"{rec.name}/{ch}", quantity="rate", data=np.asarray(data, dtype=float), unit=unit))
    return Log(path=path, fs=rec.fs, channels=chans, fmt="hdf5")


def _terms_arg(text: str) -> tuple[str, ...]:
    from gyrobench.analysis.allan import TERMS

    names = tuple(t.strip().upper() for t in text.split(",") if t.strip())
    bad = [t for t in names if t not in TERMS]
    if bad or not names or len(set(names)) != len(names):
        raise argparse.ArgumentTypeError(f"--terms must be distinct names from {','.join(TERMS)}; got {text!r}")
    return names


def _tau_min_arg(text: str):
    return "auto" if text == "auto" else _positive_float("--tau-min")(text)


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
    from gyrobench.scenarios import allan_report as rep
    from gyrobench.scenarios.outputs import check_output

    path = Path(args.file)
    if not path.is_file():
        raise FileNotFoundError(f"recording file not found: {str(path)!r}")
    for flag, target in (("--plot", args.plot), ("--kalibr", args.kalibr)):  # before any work
        if target:
            check_output(target, what=flag, create_parents=False)
    columns = args.column or None
    if path.suffix.lower() in (".h5", ".hdf5"):
        if args.fs is not None or args.units is not None:
            raise _BadInput("--fs and --units apply to CSV input; an HDF5 recording carries its own")
        log = _read_hdf5(path, args.recording, columns)
    else:
        from gyrobench.scenarios.logs import read_csv_log

        log = read_csv_log(path, columns, args.fs, args.units, all_axes=args.all_axes, start=args.start,
                           stop=args.stop, temperature=args.temperature, decimal=args.decimal)
    if args.bandwidth is None and args.bandwidth_bias != _BANDWIDTH_BIAS:
        raise _BadInput("--bandwidth-bias applies with --bandwidth HZ")
    if args.bandwidth is not None and not args.bandwidth < log.fs / 2:
        raise _BadInput(f"--bandwidth must be < the Nyquist frequency fs/2 = {log.fs / 2:g} Hz of {path.name} "
                        f"(sampled at {log.fs:g} Hz); got {args.bandwidth:g} Hz")
    results = []
    for ch in log.channels:
        rep.check_finite(ch)
        _check_allan_input(ch.data, log.fs, ch.label, args.kind)  # magnitudes that overflow, memory
        results.append(rep.analyse(ch, log.fs, taus=args.taus, kind=args.kind, terms=args.terms,
                                   tau_min=args.tau_min, tau_max=args.tau_max, temperature=log.temperature,
                                   bandwidth=args.bandwidth, bandwidth_bias=args.bandwidth_bias,
                                   segments=args.segments))
    if args.kalibr:
        from gyrobench.sim.recording import atomic_path

        text = rep.kalibr_yaml(log, results)
        with atomic_path(Path(args.kalibr)) as tmp:
            Path(tmp).write_text(text)
    if args.json:
        print(json.dumps(rep.log_json(log, results)))
    else:
        print("\n".join(rep.log_text(log, results)))
    if args.plot:
        from gyrobench.scenarios.figures import allan_figure
        from gyrobench.sim.recording import atomic_path

        for plot, res in rep.plot_paths(Path(args.plot), results):  # one file per channel
            fig = allan_figure(res.curve, res.fit, title=rep.plot_title(log, res), quantity=res.channel.quantity)
            with atomic_path(plot) as tmp:
                fig.savefig(tmp, format=(plot.suffix.lstrip(".") or "png"), dpi=120, bbox_inches="tight")
            if not args.json:
                print(f"wrote {plot}")
    if any(r.nonstationary for r in results) and not args.accept_nonstationary:
        from gyrobench.scenarios import exits

        return exits.NONSTATIONARY
    return 0


# ----------------------------------------------------------------------------- reproduce
#: units each deviation's variant runs over with a bare ``reproduce --deviations``
DEVIATION_UNITS = 5
#: ``--units auto``: the first batch, and the default ceiling (``--max-units``)
AUTO_START_UNITS = 20
MAX_UNITS = 60


def _cmd_reproduce(args) -> int:
    """Run the scenarios; a paper scenario (``experiment`` + ``CLAIMS``) over ``--units`` units
    through the shared runner (:mod:`gyrobench.scenarios.units`), any other by its ``run``."""
    from gyrobench.scenarios import registry
    from gyrobench.scenarios.outputs import check_output, output_lock

    names = registry.available() if args.all else list(args.scenarios)
    if not names:
        raise _BadInput("name at least one scenario or give --all (see 'gyrobench list')")
    if args.all and args.scenarios:
        raise _BadInput("give either --all or scenario names, not both")
    if args.config and len(names) != 1:
        raise _BadInput("--config applies to one scenario; name exactly one")
    if args.workers is not None and args.workers < 0:
        raise _BadInput(f"--workers must be an integer >= 0; got {args.workers}")
    if args.units == "auto":
        start_units, max_units = min(AUTO_START_UNITS, args.max_units), args.max_units
    elif args.max_units != MAX_UNITS:
        raise _BadInput(f"--max-units goes with --units auto; got --units {args.units}")
    else:
        start_units, max_units = args.units, None
    mods = [registry.get(n) for n in names]  # fails fast on an unknown name
    configs = [registry.load_config(m, args.config) for m in mods]
    check_output(args.out, what="--out", kind="report")  # before any work
    with output_lock(args.out, what="--out"):  # a second reproduce into the same --out is refused
        return _reproduce(args, mods, configs, start_units, max_units)


def _reproduce(args, mods, configs, start_units: int, max_units: int | None) -> int:
    """The work of ``reproduce`` once its inputs are checked and its output is locked."""
    from gyrobench.scenarios import units
    from gyrobench.scenarios.bench.cli import scheduler_executor
    from gyrobench.scenarios.outputs import write_report_as_a_set
    from gyrobench.scenarios.report import claim_tally, tally_text
    from tqdm import tqdm

    if not args.scheduler:  # local units share this machine's memory: one per worker at once
        source = f"config file {args.config!r}" if args.config else "its default configuration"
        for m, cfg in zip(mods, configs, strict=True):
            if units.is_paper_scenario(m):
                n_at_once = units.concurrent_units(start_units, args.workers)
                units.check_unit_memory(m, cfg, concurrent=n_at_once, source=source)
    out = Path(args.out)
    db = Path(args.db) if args.db else units.default_db(out)
    executor, close = scheduler_executor(args)
    workers = args.workers
    from gyrobench.scenarios.bench.executors import local_pool, stop_pool

    pool = None
    if executor is None and workers != 0 and any(units.is_paper_scenario(m) for m in mods):
        # one local pool for every paper scenario (workers start and import once, not per scenario);
        # its workers die with this process, and are killed on Ctrl-C, SIGTERM or an error
        pool = local_pool(workers)
        executor, workers = pool, None
    outcomes = []
    t0 = time.perf_counter()
    ok = False
    try:
        bar = tqdm(list(zip(mods, configs, strict=True)), desc="reproduce", unit="scenario", disable=args.quiet)
        with _closing(bar):
            for mod, cfg in bar:
                bar.set_postfix_str(mod.NAME)
                if units.is_paper_scenario(mod):
                    outcomes.append(units.run_paper(mod, cfg, seed=args.seed, n_units=start_units, executor=executor,
                                                    workers=workers, db=db, progress=not args.quiet,
                                                    deviation_units=args.deviations or 0, max_units=max_units))
                else:
                    outcomes.append(mod.run(cfg, args.seed, progress=not args.quiet))
        ok = True
    finally:
        if pool is not None:
            stop_pool(pool, kill=not ok)
        elif close is not None:
            close()
    index = write_report_as_a_set(outcomes, out, command="gyrobench " + " ".join(shlex.quote(a) for a in args.argv))
    print(f"{len(outcomes)} scenario(s) in {time.perf_counter() - t0:.1f} s")
    for o in outcomes:
        if o.claims:
            what = f"{o.units} unit(s); {tally_text(claim_tally(o.claims))}"
        else:
            held = sum(1 for h in o.headlines if h.holds is True)
            what = f"{held}/{sum(1 for h in o.headlines if h.holds is not None)} testable headline conclusions hold"
        print(f"  {o.scenario:<20} {o.runtime_s:7.1f} s   {what}")
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
                                   "'simulate device PART' simulates a datasheet part in a rate/temperature profile; "
                                   "'simulate SCENARIO' writes every recording of a scenario (HDF5 with truth).")
    s.add_argument("target", help="'noise', 'device' or a scenario name (see 'gyrobench list')")
    s.add_argument("part", nargs="?", help="device: a part (see 'gyrobench parts') or a FILE.toml of its datasheet")
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
    s.add_argument("--rate-csv", help="device: CSV of time [s], rate [deg/s] (linear between rows)")
    s.add_argument("--temperature-csv", help="device: CSV of time [s], temperature [degC]")
    s.add_argument("--profile", help="device: TOML with rate_dps, temperature_c, specific_force_g (numbers or "
                   "[time_s, value] knots) and duration_s")
    s.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    s.set_defaults(func=_cmd_simulate)

    s = sub.add_parser("parts", help="list the built-in gyro parts with their datasheet figures")
    s.set_defaults(func=_cmd_parts)

    s = sub.add_parser("allan", help="Allan deviation and Q/N/B/K/R fit of a recording (HDF5 or CSV)",
                       epilog="exit status: 0 ok; 2 bad input; 5 a channel is not stationary (motion or steps: "
                              "the report is written, its first line says so; --accept-nonstationary exits 0)")
    s.add_argument("file", help="gyrobench HDF5 recording, or CSV (.csv or .csv.gz) from any gyro (EuRoC, Kalibr, "
                                "ROS exports included)")
    s.add_argument("--column", action="append", help="channel (HDF5, default 'rate') or CSV column name or index; "
                                                     "repeat for several (one table)")
    s.add_argument("--all-axes", action="store_true", help="CSV: every gyro and accelerometer column")
    s.add_argument("--recording", help="HDF5: recording name when the file holds several")
    s.add_argument("--fs", type=_positive_float("--fs"), help="CSV without a time column: sample rate [Hz]")
    s.add_argument("--units", help="CSV: unit of the named columns, e.g. deg/s, deg/h, rad/s, m/s^2, g "
                                   "(default: from the header '[unit]' or the format)")
    s.add_argument("--start", type=_nonneg_float("--start"),
                   help="CSV: analyse from this time [s after the first sample]")
    s.add_argument("--stop", type=_nonneg_float("--stop"),
                   help="CSV: analyse up to this time [s after the first sample]")
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
    s.add_argument("--tau-max", type=_positive_float("--tau-max"), help="longest tau to fit [s]")
    s.add_argument("--bandwidth", type=_positive_float("--bandwidth"), metavar="HZ",
                   help="the sensor's bandwidth [Hz], 0 < HZ < fs/2: taus its low-pass still biases are not fitted "
                        "(with --tau-min the larger limit wins; the output names the rule that set it)")
    s.add_argument("--bandwidth-bias", type=_positive_float("--bandwidth-bias"), default=_BANDWIDTH_BIAS,
                   metavar="FRACTION",
                   help="with --bandwidth: largest filter bias of a fitted white-noise point, as a fraction of its "
                        f"standard error (default {_BANDWIDTH_BIAS:g})")
    s.add_argument("--segments", choices=("auto",),
                   help="auto: on a channel with motion or steps, also fit each quiet stretch between them on "
                        "its own (SEGMENTS lines, JSON 'segments')")
    s.add_argument("--accept-nonstationary", action="store_true",
                   help="exit 0 also when motion or steps are found (default: exit status 5)")
    s.add_argument("--json", action="store_true", help="print the curve and fit as JSON")
    s.add_argument("--plot", help="write the ADEV figure (PNG); with several channels one file per channel, "
                                  "FILE_<channel>.png")
    s.add_argument("--kalibr", help="write the Kalibr IMU noise file (imu.yaml: noise densities and random walks "
                                    "from N and K, largest over the axes)")
    s.set_defaults(func=_cmd_allan)

    s = sub.add_parser("reproduce", help="run scenarios and write the report (Markdown, HTML, PNG, results.json)")
    s.add_argument("scenarios", nargs="*", help="scenario names (see 'gyrobench list')")
    s.add_argument("--all", action="store_true", help="every registered scenario")
    s.add_argument("--out", default="gyrobench-report", help="output folder (default gyrobench-report)")
    s.add_argument("--seed", type=_seed, default=0, help="seed of the first unit (default 0)")
    s.add_argument("--max-units", type=_positive_int("--max-units"), default=MAX_UNITS,
                   help=f"with --units auto: the most units a claim may use (default {MAX_UNITS})")
    s.add_argument("--units", type=_units_or_auto, default=20,
                   help="paper scenarios: units simulated, seeds SEED..SEED+N-1 (default 20; 1 = quick look; "
                   "'auto': 20, then batches of 10 while a claim's interval straddles 50 %%, up to --max-units)")
    s.add_argument("--workers", type=int, default=None,
                   help="local worker processes for the units (default: usable CPUs; 0 = in this process)")
    s.add_argument("--scheduler", metavar="ADDRESS", help="dask.distributed scheduler address; units run there")
    s.add_argument("--db", help="SQLite file keeping every finished unit, so a rerun resumes "
                                "(default OUT/units.sqlite)")
    s.add_argument("--config", help="TOML file overriding one scenario's parameters")
    s.add_argument("--deviations", nargs="?", const=DEVIATION_UNITS, type=_positive_int("--deviations"),
                   metavar="N", help="also run each deviation's config variant (the paper's protocol) over the "
                   f"first N units (default {DEVIATION_UNITS}) and report every claim's measured change")
    s.add_argument("-q", "--quiet", action="store_true", help="no progress bars")
    s.set_defaults(func=_cmd_reproduce)

    from gyrobench.scenarios.bench import cli as bench_cli

    bench_cli.add_parser(sub)
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


def _one_line(text: object) -> str:
    """``text`` on one line (a message from a library may hold newlines)."""
    return " ".join(str(text).split())


def _error_status(exc: BaseException) -> tuple[int, str]:
    """(exit status, one-line message) for an exception leaving a verb (see scenarios.exits)."""
    from gyrobench.scenarios import exits

    bench = sys.modules.get("gyrobench.scenarios.bench")
    if bench is not None and isinstance(exc, (bench.FailedSeedsError, bench.ComparisonError)):
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
    restore = _raise_on_sigterm()
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
    finally:
        restore()


def _raise_on_sigterm() -> typing.Callable[[], None]:
    """Make SIGTERM raise :class:`~gyrobench.scenarios.exits.Terminated` in the main thread while a
    verb runs (its cleanups run, the exit is 143 with one line); returns what restores the previous
    handler. Nothing outside the main thread (signal handlers can only be set there)."""
    import signal
    import threading

    from gyrobench.scenarios import exits

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
