"""``gyrobench simulate`` (noise, a scenario's recordings, a datasheet part in a profile) and ``gyrobench parts``."""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

from gyrobench.scenarios.cli.common import (
    BadInput,
    add_force,
    bounded_recursion,
    check_outputs,
    closing,
    duration,
    given,
    input_file,
    nonneg_float,
    one_line,
    positive_float,
    positive_int,
    ranged,
    seed,
)
from gyrobench.scenarios.cli.profile import DEVICE_FLAGS, device_environment

__all__ = ["add_parsers"]

#: the noise terms of 'simulate noise', in the order of its --Q/--N/--B/--K/--R (NoiseModel's field names)
_NOISE_TERMS = ("quantization", "angle_random_walk", "bias_instability", "rate_random_walk", "rate_ramp")

#: flags of 'simulate noise' and of 'simulate SCENARIO' (dest -> flag); the others are shared
_NOISE_FLAGS = {"Q": "--Q", "N": "--N", "B": "--B", "K": "--K", "R": "--R", "fs": "--fs",
                "duration": "--duration", "output": "-o/--output", "chunk": "--chunk", "terms": "--no-terms"}
_SCENARIO_FLAGS = {"out": "--out", "config": "--config"}


#: the suffixes of a record file (-o)
_RECORD_SUFFIXES = (".h5", ".hdf5", ".csv")

#: how far inside FS_RANGE_HZ a CSV record's rate must lie: 'allan' infers the rate from the time
#: column, printed to 12 significant digits, so the rate it reads differs from --fs by up to about
#: (samples x 1e-12) relative; 1e-6 covers a million rows at the range's edges
CSV_FS_MARGIN = 1e-6


def _simulate_noise(args) -> int:
    """Stream one noise record to ``-o FILE.h5|.csv`` in the recording schema (docs/recording.md).

    The record is static: ``truth/true_rate`` is 0 rad/s and ``output`` is the sum of the noise
    terms, each stored as ``truth/<term>`` (``quantization``, ``angle_random_walk``,
    ``bias_instability``, ``rate_random_walk``, ``rate_ramp``: those with a coefficient > 0,
    named in the metadata's ``error_components``); with ``--no-terms`` their sum alone, as the one
    component ``noise`` (``terms_drawn`` in the metadata still names the terms). The metadata also
    holds the generating model (``noise_model_si``: Q [rad], N [rad/sqrt(s)], B [rad/s],
    K [rad/s/sqrt(s)], R [rad/s^2]), the datasheet values and the seed. ``--compress gzip|lzf``
    compresses the HDF5 datasets.
    """
    import numpy as np
    from tqdm import tqdm

    from gyrobench.base import memory
    from gyrobench.base.atomic import atomic_path, ensure_free_space
    from gyrobench.base.safety import Output, comment_marker
    from gyrobench.io.recording import (
        FS_RANGE_HZ,
        Channel,
        HDF5StreamWriter,
        Recording,
        check_magnitude,
        metadata_json,
        package_version,
    )
    from gyrobench.io.write_rules import check_closes
    from gyrobench.scenarios.cli.allan import MIN_MAGNITUDE
    from gyrobench.scenarios.static_noise import MIN_SAMPLES, GradeSpec
    from gyrobench.sim.noise import NoiseModel

    if extra := given(args, _SCENARIO_FLAGS):
        raise BadInput(f"simulate noise: {', '.join(extra)} apply to 'simulate SCENARIO'; "
                        "a noise record is written to the one file named by -o")
    if args.output is None:
        raise BadInput("simulate noise needs -o FILE.h5 or FILE.csv")
    out = Path(args.output)
    suffix = "".join(out.suffixes[-1:]).lower()
    if suffix not in (".h5", ".hdf5", ".csv"):
        raise BadInput(f"-o must end in .h5, .hdf5 or .csv; got {str(out)!r}")
    check_outputs(args, [Output(out, "-o", suffixes=_RECORD_SUFFIXES)])  # before any work
    if args.duration is None:
        raise BadInput("simulate noise needs --duration (e.g. 10h, 30min, 600s)")
    fs = 100.0 if args.fs is None else args.fs
    lo, hi = FS_RANGE_HZ
    if not lo <= fs <= hi:  # 'gyrobench allan' refuses any other rate: never written
        raise BadInput(f"--fs must be in [{lo:g}, {hi:g}] Hz (the sample rates 'gyrobench allan' reads; no gyro "
                       f"samples outside it); got {fs:g} Hz")
    if suffix == ".csv" and not lo * (1 + CSV_FS_MARGIN) <= fs <= hi * (1 - CSV_FS_MARGIN):
        raise BadInput(f"--fs must be inside [{lo:g}, {hi:g}] Hz by a relative {CSV_FS_MARGIN:g} for a CSV (the rate "
                       f"'gyrobench allan' infers from its 12-digit time column could fall outside); got {fs:g} Hz")
    datasheet = {"Q_arcsec": args.Q or 0.0, "N_deg_sqrt_h": args.N or 0.0, "B_deg_h": args.B or 0.0,
                 "K_deg_h_sqrt_h": args.K or 0.0, "R_deg_h2": args.R or 0.0}
    for (key, value), flag in zip(datasheet.items(), ("--Q", "--N", "--B", "--K", "--R"), strict=True):
        rng = GradeSpec.RANGES[key]  # the same documented ranges as a static_noise grade's coefficients
        if not rng.contains(value):
            raise BadInput(f"{flag} must be {rng.text()} (any gyro grade's); got {value:g}")
    if not any(datasheet.values()):  # an all-zero record: 'gyrobench allan' refuses it (zero variance)
        raise BadInput("simulate noise needs at least one noise coefficient > 0 (--Q, --N, --B, --K or --R)")
    model = NoiseModel.from_datasheet(
        quantization=datasheet["Q_arcsec"], angle_random_walk=datasheet["N_deg_sqrt_h"],
        bias_instability=datasheet["B_deg_h"], rate_random_walk=datasheet["K_deg_h_sqrt_h"],
        rate_ramp=datasheet["R_deg_h2"],
    )
    n_float = args.duration * fs
    if not n_float < 2.0**62:  # inf or beyond any disk: said here, not as an OverflowError
        raise BadInput(f"--duration x --fs = {args.duration:g} s x {fs:g} Hz gives {n_float:.3g} samples; "
                        "a record holds at most 2**62 (and must fit on the disk)")
    n = int(round(n_float))
    if n < MIN_SAMPLES:
        raise BadInput(f"--duration x --fs = {args.duration:g} s x {fs:g} Hz gives {n} samples; a record needs "
                        f"at least {MIN_SAMPLES} (the fewest for the five octave taus of an Allan fit)")
    drawn = [name for name, v in zip(_NOISE_TERMS, datasheet.values(), strict=True) if v > 0]
    # --no-terms: one component, their sum `noise` (= output, the true rate being 0), so the file still closes
    terms = drawn if args.terms is not False else ["noise"]
    n_series = 2 + len(terms)  # output, true rate, the terms
    # the disk is checked here, before the progress bar draws, so a refusal is the one line on stderr: a CSV row
    # "%.12g" then n_series times ",%.17g" is at most 16 + 25 n_series characters, an HDF5 sample 8 bytes per
    # float64 series (what HDF5StreamWriter allocates, which checks the same again when it opens)
    ensure_free_space(out, (16 + 25 * n_series if suffix == ".csv" else 8 * n_series) * n)
    seed = 0 if args.seed is None else args.seed
    chunk = args.chunk or 1 << 20
    # streamed: only one chunk is in memory (the five terms, their sum, the time column, copies)
    memory.check_memory(memory.series_bytes(min(chunk, n), 14), f"simulate noise (chunks of {min(chunk, n)} samples)",
                        hint="lower --chunk")
    stream = model.stream(fs, rng=np.random.default_rng(seed))
    meta = {
        "source": "gyrobench simulate noise", "datasheet": datasheet, "seed": seed, "version": package_version(),
        "error_components": terms,
        "terms_drawn": drawn,
        "noise_model_si": {"quantization_rad": model.quantization,
                           "angle_random_walk_rad_per_sqrt_s": model.angle_random_walk,
                           "bias_instability_rad_per_s": model.bias_instability,
                           "rate_random_walk_rad_per_s_sqrt_s": model.rate_random_walk,
                           "rate_ramp_rad_per_s2": model.rate_ramp},
    }
    too_big = "the noise coefficients --Q/--N/--B/--K/--R are far too large for any gyro"
    peak = [0.0]

    def checked(parts):
        """One chunk (output, its terms), refused if too large to analyse; the largest sample kept for the end."""
        y = np.zeros(len(next(iter(parts.values()))))
        for v in parts.values():  # in NoiseStream.take's order: the same output bits
            y += v
        check_magnitude(y, "simulate noise: the record", n_total=n, hint=too_big)
        peak[0] = max(peak[0], float(np.max(np.abs(y))) if len(y) else 0.0)
        return y, parts

    def split(y, parts):
        """The stored components of one chunk: each drawn term, or (--no-terms) their sum."""
        return {k: parts[k] for k in terms} if args.terms is not False else {"noise": y}

    def chunks():
        left = n
        while left > 0:
            k = min(chunk, left)
            yield checked(stream.take_components(k))
            left -= k

    def check_not_tiny() -> None:
        """Refuse (before the file is committed) a record 'gyrobench allan' would refuse as too small."""
        if peak[0] < MIN_MAGNITUDE:
            raise BadInput(f"simulate noise: the record's samples are at most {peak[0]:.3g} rad/s, too small for "
                           f"'gyrobench allan' (it needs samples above {MIN_MAGNITUDE:g}): the noise coefficients "
                           "--Q/--N/--B/--K/--R are far too small for any gyro")

    bar = tqdm(total=n, unit="sa", unit_scale=True, disable=n < 5 * chunk or args.quiet, desc="simulate")
    with closing(bar):
        if suffix == ".csv":
            with atomic_path(out) as tmp, open(tmp, "w") as fh:
                fh.write(comment_marker(f"recording 'noise'; fs {fs!r} Hz; metadata {metadata_json(meta)}") + "\n")
                fh.write(",".join(["time [s]", "output [rad/s]", "truth/true_rate [rad/s]",
                                   *(f"truth/{k} [rad/s]" for k in terms)]) + "\n")
                k = 0
                for y, parts in chunks():
                    t = (k + np.arange(len(y))) / fs
                    stored = split(y, parts)
                    # the rule of every writer (gyrobench.io.write_rules): the chunk closes, or nothing is committed
                    check_closes(Recording(fs=fs, name="noise", metadata={"error_components": terms},
                                           channels={"output": Channel(y, "rad/s")},
                                           truth={"true_rate": Channel(np.zeros(len(y)), "rad/s"),
                                                  **{c: Channel(v, "rad/s") for c, v in stored.items()}}), out)
                    np.savetxt(fh, np.column_stack([t, y, np.zeros(len(y)), *stored.values()]),
                               delimiter=",", fmt=["%.12g"] + ["%.17g"] * n_series)
                    k += len(y)
                    bar.update(len(y))
                check_not_tiny()
        else:
            with HDF5StreamWriter(out, name="noise", fs=fs, channels={"output": "rad/s"}, metadata=meta,
                                  truth={"true_rate": "rad/s", **dict.fromkeys(terms, "rad/s")},
                                  expected_samples=n, compression=args.compress, overwrite=args.force) as w:
                for y, parts in chunks():
                    w.append(output=y, truth={"true_rate": np.zeros(len(y)), **split(y, parts)})
                    bar.update(len(y))
                check_not_tiny()
    print(f"wrote {n} samples ({n / fs:.6g} s at {fs:g} Hz) to {out}")
    return 0


def _simulate_scenario(args) -> int:
    from gyrobench.base.atomic import ensure_free_space
    from gyrobench.base.safety import Output, mark_folder
    from gyrobench.io.recording import save_hdf5
    from gyrobench.scenarios import registry
    from gyrobench.scenarios.static_noise import MIN_SAMPLES

    if extra := given(args, _NOISE_FLAGS):
        raise BadInput(f"simulate {args.target}: {', '.join(extra)} apply to 'simulate noise' only; "
                        f"set a scenario's parameters with --config FILE.toml")
    mod = registry.get(args.target)
    inputs = [("--config", input_file(args.config, "--config") if args.config is not None else None)]
    config = registry.load_config(mod, args.config)
    if args.out is None:
        raise BadInput(f"simulate {args.target} needs --out DIR")
    folder = Output(Path(args.out) / mod.NAME, "--out", kind="folder")
    check_outputs(args, [folder], inputs)  # before any work: a new or empty folder, or one gyrobench made
    seed = 0 if args.seed is None else args.seed
    recs = mod.simulate(config, seed)
    for r in recs:  # check them all before writing any
        if r.n_samples < MIN_SAMPLES:
            raise BadInput(
                f"simulate {args.target}: recording {r.name!r} would have {r.n_samples} samples "
                f"({r.n_samples / r.fs:.3g} s at {r.fs:g} Hz); a record needs at least {MIN_SAMPLES}: "
                f"lengthen it in the config"
            )
    out = Path(args.out) / mod.NAME
    # each file, before any is written: never an input, never a file gyrobench did not write (without --force)
    check_outputs(args, [Output(out / f"{r.name}.h5", "--out", suffixes=(".h5",)) for r in recs], inputs)
    ensure_free_space(out / "all recordings", sum(r.nbytes for r in recs))
    mark_folder(out)
    for r in recs:
        path = save_hdf5(out / f"{r.name}.h5", r, compression=args.compress, overwrite=args.force)
        print(f"wrote {path} ({r.n_samples} samples at {r.fs:g} Hz; channels {', '.join(r.channels)}; "
              f"truth {', '.join(r.truth)})")
    return 0


# ----------------------------------------------------------------------------- device and parts
def _simulate_device(args) -> int:
    """One record of a part (built-in name or FILE.toml) in a rate/temperature profile -> -o FILE.h5|.csv."""
    import numpy as np

    from gyrobench.base import memory
    from gyrobench.base.safety import Output
    from gyrobench.io.recording import save_hdf5, to_csv
    from gyrobench.scenarios.static_noise import MIN_SAMPLES
    from gyrobench.sim import parts

    if extra := [f for f in given(args, _NOISE_FLAGS) if f not in ("--fs", "--duration", "-o/--output")]:
        raise BadInput(f"simulate device: {', '.join(extra)} apply to 'simulate noise' only")
    if extra := given(args, _SCENARIO_FLAGS):
        raise BadInput(f"simulate device: {', '.join(extra)} apply to 'simulate SCENARIO' only")
    if args.part is None:
        raise BadInput(f"simulate device needs a PART: one of {', '.join(parts.names())}, or a FILE.toml")
    part = load_part(args.part, "PART")
    if args.output is None:
        raise BadInput("simulate device needs -o FILE.h5 or FILE.csv")
    out = Path(args.output)
    suffix = out.suffix.lower()
    if suffix not in (".h5", ".hdf5", ".csv"):
        raise BadInput(f"-o must end in .h5, .hdf5 or .csv; got {str(out)!r}")
    inputs = [("PART", args.part if args.part.lower().endswith(".toml") else None),
              *((flag, getattr(args, dest)) for dest, flag in DEVICE_FLAGS.items())]
    for flag, p in inputs:
        if p is not None:
            input_file(p, flag)
    check_outputs(args, [Output(out, "-o", suffixes=_RECORD_SUFFIXES)], inputs)  # before any work
    env, fs, added = device_environment(args, part)
    n = env.n_samples(fs)
    if n < MIN_SAMPLES:
        raise BadInput(f"simulate device: {env.duration:g} s at {fs:g} Hz gives {n} samples; "
                        f"a record needs at least {MIN_SAMPLES}")
    model = args.model or part.datasheet.default_model
    # output, true rate, the error components, temperature, force, plus the model's temporaries, at the
    # part's internal rate (its output filter oversamples)
    k = parts.oversampling(part.datasheet, fs) if model == "budget" else 1
    memory.check_memory(memory.series_bytes(n * k, 30), "simulate device", hint="shorten --duration or lower --fs")
    seed = 0 if args.seed is None else args.seed
    try:
        rec = parts.simulate_part(part, env, fs=fs, rng=np.random.default_rng(seed), model=model)
    except ValueError as exc:  # the sheet cannot be mapped onto the model, or fs beyond the model's reach
        raise BadInput(f"simulate device {args.part} --model {model}: {one_line(exc)} (--model budget runs the "
                       "datasheet budget)") from None
    if added:  # what the profile's [earth] and [shaker] tables put into true_rate and specific_force
        rec = dataclasses.replace(rec, metadata={**rec.metadata, "profile": added})
    path = (to_csv(out, rec, overwrite=args.force) if suffix == ".csv"
            else save_hdf5(out, rec, compression=args.compress, overwrite=args.force))
    ran = rec.metadata.get("device_model") if model == "physics" else rec.metadata.get("model")
    print(f"wrote {path} ({rec.n_samples} samples at {fs:g} Hz; model {model}: {ran}; channels "
          f"{', '.join(rec.channels)}; truth {', '.join(rec.truth)})")
    return 0


def load_part(name: str, what: str):
    """The part ``name`` (built-in or a FILE.toml, :func:`gyrobench.sim.parts.get`) or one line naming ``what``:
    a missing or non-regular file, bad TOML, or TOML nested too deeply to read."""
    from gyrobench.sim import parts

    if name.lower().endswith(".toml"):
        input_file(name, what)
    try:
        with bounded_recursion():
            return parts.get(name)
    except ValueError as exc:
        raise BadInput(one_line(exc)) from None
    except RecursionError:  # arrays or tables nested thousands deep
        raise BadInput(f"{what} {name!r} nests arrays or tables too deeply to read") from None
    except UnicodeDecodeError as exc:
        raise BadInput(f"{what} {name!r} is not UTF-8 text: {one_line(exc)}") from None


def _cmd_parts(args) -> int:
    """List the built-in parts with their datasheet figures, sources and the notes on what was assumed."""
    from gyrobench.sim import parts

    def fmt(v, unit: str) -> str:
        return "-" if v is None else f"{v:g} {unit}"

    for d in parts.datasheets():
        noise = (fmt(d.arw, "deg/sqrt(h)") if d.arw is not None
                 else f"{fmt(d.noise_density, 'deg/s/sqrt(Hz)')} ({d.noise_density_sided}-sided)")
        print(f"{d.name}: {d.manufacturer} {d.model} [{d.technology}, {d.grade}]")
        b = ("not on the sheet (no 1/f term drawn)" if d.bias_instability_dph is None
             else fmt(d.bias_instability_dph, "deg/h"))
        print(f"    range {fmt(d.range_dps, 'deg/s')}; bias instability {b}; "
              f"noise {noise}; bias repeatability {fmt(d.bias_repeatability, 'deg/h')}; "
              f"scale factor {fmt(d.scale_factor_repeatability, 'ppm')}; g-sensitivity "
              f"{fmt(d.g_sensitivity, 'deg/h/g')}; bandwidth {fmt(d.bandwidth, 'Hz')}; "
              f"resolution {fmt(d.resolution, 'deg/s')}")
        print(f"    bias tempco {fmt(d.bias_tempco, 'deg/h/K')}; scale-factor tempco "
              f"{fmt(d.scale_factor_tempco, 'ppm/K')}; output rate {fmt(d.output_rate, 'Hz')}; rms noise "
              f"{fmt(d.rms_noise, 'deg/s')}; figures: {d.source_kind} source")
        if d.has_accelerometer:
            acc_noise = (fmt(d.accel_vrw_m_s_sqrt_h, "m/s/sqrt(h)") if d.accel_vrw_m_s_sqrt_h is not None
                         else f"{fmt(d.accel_noise_density_ug, 'ug/sqrt(Hz)')} ({d.noise_density_sided}-sided)")
            print(f"    accelerometers: range {fmt(d.accel_range_g, 'g')}; bias instability "
                  f"{fmt(d.accel_bias_instability_ug, 'ug')}; noise {acc_noise}; bias repeatability "
                  f"{fmt(d.accel_bias_repeatability_mg, 'mg')}; scale factor "
                  f"{fmt(d.accel_scale_factor_repeatability_ppm, 'ppm')}; bandwidth {fmt(d.accel_bandwidth_hz, 'Hz')}; "
                  f"resolution {fmt(d.accel_resolution_mg, 'mg')}")
        else:
            print("    accelerometers: none on the sheet (a triad of this part has ideal accelerometers)")
        print(f"    source: {d.source}")
        print(f"    physics model: {parts.physics_summary(d)}")
        if d.notes:
            print(f"    notes: {d.notes}")
    return 0


_IMU_FLAGS = {"trajectory": "--trajectory", "misalignment": "--misalignment", "cross_axis": "--cross-axis",
              "euroc": "--euroc", "kalibr": "--kalibr", "rosbag": "--rosbag", "increments": "--increments",
              "latitude": "--latitude"}


def _cmd_simulate(args) -> int:
    if args.target == "imu":
        from gyrobench.scenarios.cli.imu import simulate_imu

        bad = [f for f in given(args, {**_NOISE_FLAGS, **_SCENARIO_FLAGS, **DEVICE_FLAGS})
               if f not in ("--fs", "-o/--output")]
        if bad:
            raise BadInput(f"simulate imu: {', '.join(bad)} do not apply to 'simulate imu'")
        return simulate_imu(args)
    if extra := [f for f in given(args, _IMU_FLAGS) if f != "--increments" or args.increments]:
        raise BadInput(f"simulate {args.target}: {', '.join(extra)} apply to 'simulate imu' only")
    if args.target == "device":
        return _simulate_device(args)
    if getattr(args, "model", None) is not None:
        raise BadInput(f"simulate {args.target}: --model applies to 'simulate device' only")
    if args.part is not None:
        raise BadInput(f"simulate {args.target}: a second positional ({args.part!r}) is taken "
                        "by 'simulate device PART' only")
    if extra := given(args, DEVICE_FLAGS):
        raise BadInput(f"simulate {args.target}: {', '.join(extra)} apply to 'simulate device' only")
    if args.target == "noise":
        return _simulate_noise(args)
    return _simulate_scenario(args)


def add_parsers(sub) -> None:
    """Add ``simulate`` and ``parts`` to the subparsers ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The ``gyrobench`` command's subparsers.
    """
    s = sub.add_parser("simulate", help="simulate a noise record or every recording of a scenario",
                       description="'simulate noise' streams one record with the given IEEE-952 coefficients; "
                                   "'simulate device PART' simulates a datasheet part in a rate/temperature profile; "
                                   "'simulate imu PART --trajectory FILE.toml' a triad of the part on a moving block; "
                                   "'simulate SCENARIO' writes every recording of a scenario (HDF5 with truth).")
    s.add_argument("target", help="'noise', 'device', 'imu' or a scenario name (see 'gyrobench list')")
    s.add_argument("part", nargs="?", help="device: a part (see 'gyrobench parts') or a FILE.toml of its datasheet")
    # noise-only flags default to None so that giving one to a scenario (or the reverse) can be refused
    s.add_argument("--Q", type=nonneg_float("--Q"), help="noise: quantization [arcsec] (default 0)")
    s.add_argument("--N", type=nonneg_float("--N"), help="noise: angle random walk [deg/sqrt(h)] (default 0)")
    s.add_argument("--B", type=nonneg_float("--B"), help="noise: bias instability [deg/h] (default 0)")
    s.add_argument("--K", type=nonneg_float("--K"), help="noise: rate random walk [deg/h/sqrt(h)] (default 0)")
    s.add_argument("--R", type=nonneg_float("--R"), help="noise: rate ramp [deg/h^2] (default 0)")
    s.add_argument("--fs", type=positive_float("--fs"), help="noise: sample rate [Hz] (default 100)")
    s.add_argument("--duration", type=duration, help="noise: record length > 0: 10h, 30min, 600s")
    s.add_argument("--seed", type=seed, help="random seed (default 0)")
    s.add_argument("-o", "--output", help="noise: output file, .h5 or .csv")
    s.add_argument("--out", help="scenario: output folder")
    s.add_argument("--config", help="scenario: TOML file overriding the scenario's parameters")
    s.add_argument("--chunk", type=positive_int("--chunk"), help=argparse.SUPPRESS)
    s.add_argument("--compress", choices=("gzip", "lzf"),
                   help="HDF5 output: compress every dataset (gzip: deflate, read by any HDF5 tool; lzf: faster, "
                        "h5py's own filter); simulated noise barely shrinks, constant channels do")
    s.add_argument("--no-terms", dest="terms", action="store_const", const=False, default=None,
                   help="noise: store the noise terms' sum as the one component 'noise' instead of each term under "
                        "truth/ (the file is 3 series, not 2 + the terms: docs/recording.md)")
    s.add_argument("--rate-csv", help="device: CSV of time [s], rate [deg/s] (linear between rows)")
    s.add_argument("--temperature-csv", help="device: CSV of time [s], temperature [degC]")
    s.add_argument("--profile", help="device: TOML with rate_dps, temperature_c, specific_force_g (numbers or "
                   "[time_s, value] knots), duration_s, and the tables [earth] (latitude_deg, heading_deg, "
                   "elevation_deg: the Earth's rate added to the rate) and [shaker] (kind = sine, sweep or random: "
                   "vibration added to the specific force)")
    s.add_argument("--model", choices=("physics", "budget"),
                   help="device: run the part on its technology's physics model with the sheet's figures mapped "
                        "onto it (physics, the default) or on the datasheet error budget (budget)")
    s.add_argument("--trajectory", help="imu: TOML motion definition ([site], [initial], [[motion]] segments of "
                   "constant body rate and NED acceleration, [accelerometer]; see gyrobench.scenarios.cli.imu)")
    s.add_argument("--misalignment", type=nonneg_float("--misalignment", 100.0),
                   help="imu: 1-sigma misalignment of each axis pair [mrad] (default 0)")
    s.add_argument("--cross-axis", type=nonneg_float("--cross-axis", 10.0),
                   help="imu: 1-sigma cross-axis sensitivity [%%] (default 0)")
    s.add_argument("--latitude", type=ranged("--latitude", -89.9, 89.9, unit="deg"),
                   help="imu: the site's latitude [deg] for a CSV trajectory (default 0)")
    s.add_argument("--increments", action="store_true", help="imu: write angle and velocity increments, not rates")
    s.add_argument("--euroc", help="imu: also write a EuRoC/ASL imu0 data.csv")
    s.add_argument("--kalibr", help="imu: also write a Kalibr imu.yaml from the part's and accelerometer's figures")
    s.add_argument("--rosbag", help="imu: also write a ROS bag of sensor_msgs/msg/Imu on /imu0: NAME.bag is a ROS 1 "
                   "bag, any other new path a ROS 2 bag folder (needs the extra: pip install 'gyrobench[ros]')")
    s.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    add_force(s)
    s.set_defaults(func=_cmd_simulate)

    s = sub.add_parser("parts", help="list the built-in gyro parts with their datasheet figures and physics mapping")
    s.set_defaults(func=_cmd_parts)
