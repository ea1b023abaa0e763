"""The profiles of ``gyrobench simulate device``: a TOML profile (rate table, chamber, specific force,
the Earth's rate, a shaker) or rate and temperature CSV histories, read into an
:class:`~gyrobench.sim.sensor.Environment` in SI units, every bad value refused in one line."""

from __future__ import annotations

import argparse
import math
import typing

from gyrobench.scenarios.cli.common import BadInput, input_file, one_line, read_toml

__all__ = ["DEVICE_FLAGS", "device_environment"]

#: flags of 'simulate device' only (dest -> flag)
DEVICE_FLAGS = {"rate_csv": "--rate-csv", "temperature_csv": "--temperature-csv", "profile": "--profile"}


def _profile_from_csv(path: str, flag: str, convert) -> tuple[typing.Any, float]:
    """A (time [s], value) CSV as a PiecewiseLinear in SI, and its last time [s].

    The file has a header row and two columns: time [s] (strictly increasing) and the value
    in the flag's field unit (``--rate-csv`` deg/s, ``--temperature-csv`` degC).
    """
    import numpy as np

    from gyrobench.sim.environment import PiecewiseLinear

    p = input_file(path, flag)  # not found, a folder, a FIFO, a device: one line
    try:
        data = np.loadtxt(p, delimiter=",", skiprows=1, ndmin=2, dtype=float)
    except (ValueError, UnicodeDecodeError) as exc:
        raise BadInput(f"{flag}: {path!r} is not a CSV of numbers under one header row: {one_line(exc)}") from None
    if data.shape[1] != 2 or data.shape[0] < 2:
        raise BadInput(f"{flag}: {path!r} must hold >= 2 rows of two columns (time [s], value); got {data.shape}")
    if not np.all(np.isfinite(data)):
        raise BadInput(f"{flag}: {path!r} holds NaN or inf")
    t = data[:, 0]
    if not np.all(np.diff(t) > 0):
        raise BadInput(f"{flag}: {path!r}: the time column must increase strictly")
    return PiecewiseLinear(t - t[0], convert(data[:, 1])), float(t[-1] - t[0])


def _profile_value(v, key: str, path: str, convert):
    """A profile TOML value: a number or a list of [time_s, value] knots (linear between them)."""
    import numpy as np

    from gyrobench.sim.environment import PiecewiseLinear

    if isinstance(v, (int, float)) and not isinstance(v, bool):
        return float(convert(np.array([float(v)]))[0])
    if isinstance(v, list) and v and all(isinstance(k, list) and len(k) == 2 for k in v):
        try:
            arr = np.asarray(v, dtype=float)
            return PiecewiseLinear(arr[:, 0], convert(arr[:, 1]))
        except (TypeError, ValueError) as exc:
            raise BadInput(f"--profile {path!r}: {key}: {one_line(exc)}") from None
    raise BadInput(f"--profile {path!r}: {key} must be a number or a list of [time_s, value] pairs; got {v!r}")


#: the keys of a profile file: top-level values and the [earth] and [shaker] tables
_PROFILE_KEYS = ("duration_s", "rate_dps", "temperature_c", "specific_force_g", "earth", "shaker")
_EARTH_KEYS = ("latitude_deg", "heading_deg", "elevation_deg")
#: [shaker] keys per kind (besides kind, start_s, duration_s and max_displacement_mm)
_SHAKER_KEYS = {
    "sine": ("frequency_hz", "acceleration_g", "ramp_s"),
    "sweep": ("f_start_hz", "f_end_hz", "acceleration_g", "spacing", "ramp_s"),
    "random": ("psd",),
}


def _table(data: dict, name: str, allowed: typing.Iterable[str], path: str) -> dict:
    tbl = data[name]
    if not isinstance(tbl, dict):
        raise BadInput(f"--profile {path!r}: {name} must be a table [{name}]; got {tbl!r}")
    if unknown := sorted(set(tbl) - set(allowed)):
        raise BadInput(f"--profile {path!r}: [{name}] unknown key(s) {unknown}; allowed: {sorted(allowed)}")
    return tbl


def _number(tbl: dict, table: str, key: str, path: str, unit: str, *, default: float | None = None,
            lo: float | None = None, hi: float | None = None, positive: bool = False) -> float:
    """A finite number from a profile table, inside [lo, hi] (and > 0 when ``positive``), or its default."""
    if key not in tbl:
        if default is None:
            raise BadInput(f"--profile {path!r}: [{table}] needs {key} [{unit}]")
        return default
    v = tbl[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise BadInput(f"--profile {path!r}: {table}.{key} must be a finite number [{unit}]; got {v!r}")
    if positive and not v > 0:
        raise BadInput(f"--profile {path!r}: {table}.{key} must be > 0 {unit}; got {v!r}")
    if (lo is not None and v < lo) or (hi is not None and v > hi):
        raise BadInput(f"--profile {path!r}: {table}.{key} must be in [{lo:g}, {hi:g}] {unit}; got {v!r}")
    return float(v)


def _profile_earth(data: dict, path: str) -> float:
    """The Earth's rate about the sense axis [rad/s] from the profile's [earth] table.

    Omega_E (cos(lat) cos(e) cos(heading) + sin(lat) sin(e)) (:func:`gyrobench.sim.earth.sensed_earth_rate`):
    ``latitude_deg`` (required, [-90, 90]), ``heading_deg`` the sense axis' azimuth from north toward
    east (default 0: north), ``elevation_deg`` above the horizontal ([-90, 90], default 0).
    """
    from gyrobench.sim.earth import sensed_earth_rate

    tbl = _table(data, "earth", _EARTH_KEYS, path)
    lat = _number(tbl, "earth", "latitude_deg", path, "deg", lo=-90.0, hi=90.0)
    heading = _number(tbl, "earth", "heading_deg", path, "deg", default=0.0)
    elevation = _number(tbl, "earth", "elevation_deg", path, "deg", default=0.0, lo=-90.0, hi=90.0)
    return float(sensed_earth_rate(math.radians(lat), azimuth=math.radians(heading),
                                   elevation=math.radians(elevation)))


def _profile_shaker(data: dict, path: str) -> tuple[float, typing.Any]:
    """(start [s], the vibration profile) of the profile's [shaker] table (SI inside).

    ``kind`` "sine" (:class:`~gyrobench.sim.shaker.FixedSine`: frequency_hz, acceleration_g),
    "sweep" (:class:`~gyrobench.sim.shaker.SineSweep`: f_start_hz, f_end_hz, acceleration_g,
    spacing "log" or "linear") or "random" (:class:`~gyrobench.sim.shaker.RandomVibration`: psd, a
    list of [frequency_hz, g^2/Hz] breakpoints); ``duration_s`` of the vibration, ``start_s``
    (default 0: the record is static before and after it), optional ``max_displacement_mm``
    (the shaker's stroke limit, peak) and, for sine and sweep, ``ramp_s`` (soft start and stop).
    """
    from gyrobench.base import units
    from gyrobench.sim.shaker import FixedSine, RandomVibration, SineSweep

    raw = data["shaker"]
    kind = raw.get("kind") if isinstance(raw, dict) else None
    if kind not in _SHAKER_KEYS:
        raise BadInput(f"--profile {path!r}: shaker.kind must be one of {sorted(_SHAKER_KEYS)}; got {kind!r}")
    common = ("kind", "start_s", "duration_s", "max_displacement_mm")
    tbl = _table(data, "shaker", common + _SHAKER_KEYS[kind], path)
    start = _number(tbl, "shaker", "start_s", path, "s", default=0.0, lo=0.0, hi=math.inf)
    dur = _number(tbl, "shaker", "duration_s", path, "s", positive=True)
    d_max = (None if "max_displacement_mm" not in tbl
             else _number(tbl, "shaker", "max_displacement_mm", path, "mm", positive=True) * 1e-3)
    try:
        if kind == "random":
            psd = tbl.get("psd")
            pairs: list = psd if isinstance(psd, list) else []
            if len(pairs) < 2 or not all(
                isinstance(k, list) and len(k) == 2
                and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in k) for k in pairs
            ):
                raise BadInput(f"--profile {path!r}: shaker.psd must be >= 2 [frequency_hz, g^2/Hz] pairs; "
                               f"got {psd!r}")
            return start, RandomVibration(breakpoints=tuple((float(f), float(g)) for f, g in pairs), duration=dur,
                                          max_displacement=d_max)
        acc = units.g(_number(tbl, "shaker", "acceleration_g", path, "g", lo=0.0, hi=math.inf))
        ramp = _number(tbl, "shaker", "ramp_s", path, "s", default=0.0, lo=0.0, hi=dur / 2)
        if kind == "sine":
            f = _number(tbl, "shaker", "frequency_hz", path, "Hz", positive=True)
            return start, FixedSine(frequency=f, duration=dur, acceleration=acc, max_displacement=d_max,
                                    ramp_time=ramp)
        spacing = tbl.get("spacing", "log")
        if spacing not in ("log", "linear"):
            raise BadInput(f"--profile {path!r}: shaker.spacing must be 'log' or 'linear'; got {spacing!r}")
        return start, SineSweep(
            f_start=_number(tbl, "shaker", "f_start_hz", path, "Hz", positive=True),
            f_end=_number(tbl, "shaker", "f_end_hz", path, "Hz", positive=True),
            duration=dur, acceleration=acc, spacing=spacing, max_displacement=d_max, ramp_time=ramp,
        )
    except (TypeError, ValueError) as exc:
        raise BadInput(f"--profile {path!r}: [shaker] {one_line(exc)}") from None


def _shaker_force(vibration, start: float, duration: float, fs: float, *, rng, path: str) -> typing.Any:
    """The shaker's specific force [m/s^2], one mean per output interval
    (:func:`gyrobench.sim.shaker.interval_mean_acceleration`), its errors in the profile's words."""
    from gyrobench.sim.shaker import ShakerWindowError, interval_mean_acceleration

    try:
        return interval_mean_acceleration(vibration, duration=duration, fs=fs, rng=rng, start=start)
    except ShakerWindowError as exc:
        raise BadInput(f"--profile {path!r}: shaker.start_s + shaker.duration_s = {exc.end:g} s must lie inside the "
                       f"record (0, {exc.duration:g}] s and hold >= 1 sample at {exc.fs:g} Hz") from None
    except ValueError as exc:
        raise BadInput(f"--profile {path!r}: [shaker] {one_line(exc)}") from None


def _shaker_signal(vibration, start: float, duration: float, fs: float, *, seed: int, path: str) -> typing.Any:
    """The shaker's table acceleration over the record (:func:`gyrobench.sim.shaker.record_signal`), drawn
    from the stream of :func:`_shaker_force`, its errors in the profile's words."""
    import numpy as np

    from gyrobench.sim.shaker import record_signal

    try:
        return record_signal(vibration, duration=duration, fs=fs, start=start,
                             rng=np.random.default_rng(np.random.SeedSequence(seed).spawn(1)[0]))
    except ValueError as exc:
        raise BadInput(f"--profile {path!r}: [shaker] {one_line(exc)}") from None


def device_environment(args: argparse.Namespace, part: typing.Any) -> tuple[typing.Any, float, typing.Any]:
    """The environment of ``simulate device`` from ``--profile`` or ``--rate-csv``/``--temperature-csv``.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed ``simulate device`` arguments (``profile``, ``rate_csv``, ``temperature_csv``,
        ``duration``, ``fs``, ``seed``).
    part : Part
        The part to simulate (its technology decides whether the shaker's table acceleration is
        built: only a FOG or RLG on its physics model reads it).

    Returns
    -------
    tuple
        ``(environment, fs, added)``: the :class:`~gyrobench.sim.sensor.Environment` in SI units,
        the sample rate [Hz] and what the profile's tables added (for the summary line).

    Raises
    ------
    BadInput
        A profile or CSV that breaks a constraint, in one line naming the file, the key and the value.
    """

    import numpy as np

    from gyrobench.sim.environment import PiecewiseLinear
    from gyrobench.sim.sensor import Environment

    if args.profile is not None and (args.rate_csv is not None or args.temperature_csv is not None):
        raise BadInput("simulate device: give --profile or --rate-csv/--temperature-csv, not both")
    dps = np.radians
    kelvin = lambda c: np.asarray(c, dtype=float) + 273.15  # noqa: E731
    g0 = lambda g: np.asarray(g, dtype=float) * 9.80665  # noqa: E731
    rate: typing.Any = 0.0
    temp: typing.Any = None
    force: typing.Any = 0.0
    earth = None
    shaker = None
    signal = None
    duration = args.duration
    if args.profile is not None:
        path = args.profile
        data = read_toml(path, "--profile")
        if unknown := sorted(set(data) - set(_PROFILE_KEYS)):
            raise BadInput(f"--profile {path!r}: unknown key(s) {unknown}; allowed: {sorted(_PROFILE_KEYS)}")
        if "rate_dps" in data:
            rate = _profile_value(data["rate_dps"], "rate_dps", path, dps)
        if "temperature_c" in data:
            temp = _profile_value(data["temperature_c"], "temperature_c", path, kelvin)
        if "specific_force_g" in data:
            force = _profile_value(data["specific_force_g"], "specific_force_g", path, g0)
        if "earth" in data:
            earth = _profile_earth(data, path)
            rate = (rate + earth if not isinstance(rate, PiecewiseLinear)
                    else PiecewiseLinear(rate.times, rate.values + earth))
        if "shaker" in data:
            shaker = _profile_shaker(data, path)
        if duration is None and "duration_s" in data:
            duration = _number(data, "profile", "duration_s", path, "s", positive=True)
    else:
        if args.rate_csv is not None:
            rate, span = _profile_from_csv(args.rate_csv, "--rate-csv", dps)
            duration = span if duration is None else duration
        if args.temperature_csv is not None:
            temp, span = _profile_from_csv(args.temperature_csv, "--temperature-csv", kelvin)
            duration = span if duration is None else duration
    if duration is None:
        raise BadInput("simulate device needs --duration (or a profile's duration_s, or a CSV's time span)")
    fs = args.fs if args.fs is not None else (part.datasheet.output_rate or 100.0)
    if not (math.isfinite(duration * fs) and duration * fs < 2**31):
        raise BadInput(f"--duration x --fs = {duration:g} s x {fs:g} Hz is too many samples for one record in memory")
    added: dict[str, typing.Any] = {}
    if earth is not None:
        added["earth_rate_rad_s"] = earth
    if shaker is not None:
        start, vibration = shaker
        seed = 0 if args.seed is None else args.seed
        # the shaker's own stream: a child of the seed, so the part's noise is the same with or without it
        rng = np.random.default_rng(np.random.SeedSequence(seed).spawn(1)[0])
        vib = _shaker_force(vibration, start, duration, fs, rng=rng, path=args.profile)
        # the physics models' table acceleration (the FOG's coil modes, the RLG's dither flexure):
        # the same profile from the same stream, on an even multiple of fs (shaker.record_signal);
        # MEMS and the budget take the specific force only
        if part.datasheet.technology in ("FOG", "RLG") and (args.model or part.datasheet.default_model) == "physics":
            signal = _shaker_signal(vibration, start, duration, fs, seed=seed, path=args.profile)
        n = len(vib)
        base = force((np.arange(n) + 0.5) / fs) if isinstance(force, PiecewiseLinear) else np.full(n, force)
        force = base + vib
        added["shaker"] = {"kind": type(vibration).__name__, "start_s": start, "duration_s": vibration.duration,
                           "max_frequency_hz": vibration.max_frequency}
    try:
        return Environment(duration, true_rate=rate, temperature=temp, specific_force=force,
                           vibration=signal if shaker is not None else None), fs, added
    except (TypeError, ValueError) as exc:
        raise BadInput(f"simulate device: {one_line(exc)}") from None
