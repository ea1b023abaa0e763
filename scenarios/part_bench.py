"""Your own part on the bench: calibrate a compensator in one chamber program, score it in another.

``gyrobench bench --part FILE.toml|NAME --compensator module:attr`` runs this scenario on a part
file (``twin --save-part`` writes one; ``gyrobench parts`` lists the built-in ones). Each seed is
one unit of the part (its turn-on bias, scale-factor error and, on the physics model, its build
spread drawn once) recorded twice, as an inertial-sensor lab would:

- **training: the calibration run** (``train_*``): a thermal chamber program over the part's
  temperature span (linear between equally spaced knots; default 25 -> -20 -> -20 -> 60 -> 60 ->
  25 degC), while a rate table steps through ``train_rates_dps`` (equal segments, 1 s ramps) and
  the sense axis is tumbled through ``train_force_g`` (equal segments of specific force along the
  axis, 10 s turns);
- **held out: the test run** (``test_*``): another program the compensator never saw, inside the
  calibration's span (default 25 -> 50 -> 0 -> 35 degC, other rates, other orientations).

Features (what the test logs, never the truth): chamber temperature [degC], its rate of change
[degC/min] (central differences of the logged temperature), the table rate [deg/s] and the
specific force along the sense axis [g]. Target: the output's error, ``output - true rate``
[deg/h]; the compensated output is ``output - prediction``, scored against the true rate by its
RMS [deg/h] (``mean/rms``, the primary score; lower is better).

The part runs on the model ``simulate device`` would run it on (``model = "default"``: the part's
``default_model``, physics for every built-in part: the FOG's coil heat flow, the MEMS resonator,
the RLG cavity, with the sheet's figures mapped onto them, :func:`gyrobench.sim.parts.simulate_part`;
budget for a part file ``twin --save-part`` wrote), or on the one named (``"physics"``,
``"budget"``). The part
itself travels in the configuration: ``part`` names a built-in part, or is ``"file"`` with the
part file's text in ``part_toml``, so the campaign's identity (a hash of the configuration)
changes with the file's content, and the workers never read the file.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from gyrobench.base.ranges import Constraint, FieldChoice, FieldRange, validate
from gyrobench.io.recording import Recording
from gyrobench.scenarios.base import CompensationTask, HeldOutRun, Outcome, Table
from gyrobench.scenarios.bench.primary import PrimaryScore, ScenarioScores

__all__ = ["BENCH_SCORES", "FEATURES", "NAME", "TITLE", "Config", "compensation_task", "model_of", "part_of", "run",
           "simulate"]

NAME = "part"
TITLE = "Your own part: a compensator calibrated in one chamber program, scored in another"

#: the compensator's features, in column order
FEATURES = ("temperature_c", "temperature_rate_c_per_min", "table_rate_dps", "specific_force_g")

#: the gated score (lower is better) and the score units
BENCH_SCORES = ScenarioScores(
    primary=(PrimaryScore(name="mean/rms", unit="deg/h", direction=-1,
                          meaning="RMS error of the compensated output in the held-out chamber program"),),
    units={"mse": "(deg/h)^2", "rms": "deg/h"},
)

_DEG_H = 180.0 / math.pi * 3600.0  # rad/s -> deg/h
_G0 = 9.80665  # m/s^2 per g (standard gravity)
_RATE_RAMP_S = 1.0  # the rate table's transition between steps [s]
_TUMBLE_S = 10.0  # the turn between orientations [s]


def _builtin_parts() -> tuple[str, ...]:
    from gyrobench.sim import parts

    return tuple(parts.names())


def _temps_ok(c: Config) -> bool:
    return len(c.train_temperatures_c) >= 2 and len(c.test_temperatures_c) >= 2


def _steps_ok(c: Config) -> bool:
    return all(len(v) >= 1 for v in (c.train_rates_dps, c.test_rates_dps, c.train_force_g, c.test_force_g))


def _segments_ok(c: Config) -> bool:
    """Each rate step and orientation lasts longer than its transition."""
    return all(d / len(v) > 2 * t for d, v, t in (
        (c.train_duration_s, c.train_rates_dps, _RATE_RAMP_S), (c.test_duration_s, c.test_rates_dps, _RATE_RAMP_S),
        (c.train_duration_s, c.train_force_g, _TUMBLE_S), (c.test_duration_s, c.test_force_g, _TUMBLE_S)))


@dataclass(frozen=True, slots=True, kw_only=True)
class Config:
    """The part, its model, and the calibration (training) and test (held-out) programs.

    Attributes
    ----------
    part : str
        A built-in part (``gyrobench parts``), or ``"file"``: the part is ``part_toml``.
    part_toml : str
        The part file's text (``"file"`` only; ``bench --part FILE.toml`` fills it).
    model : {"default", "physics", "budget"}
        The part's physics model or its datasheet budget; ``"default"``: the part's own
        ``default_model``, as ``simulate device`` runs it (physics for every built-in part; a part
        file ``twin --save-part`` wrote says budget: the physics models carry no K, Gauss-Markov or
        sine term).
    fs_hz : float
        Output rate of both records [Hz].
    train_duration_s, test_duration_s : float
        Length of each run [s].
    train_temperatures_c, test_temperatures_c : tuple of float
        Chamber temperature at equally spaced knots over the run, linear between [degC].
    train_rates_dps, test_rates_dps : tuple of float
        Rate-table steps, equal segments, 1 s ramps [deg/s].
    train_force_g, test_force_g : tuple of float
        Specific force along the sense axis, equal segments, 10 s turns [g].
    """

    part: str = "dsp-1760"
    part_toml: str = ""
    model: str = "default"
    fs_hz: float = 10.0
    train_duration_s: float = 3600.0
    test_duration_s: float = 3600.0
    train_temperatures_c: tuple[float, ...] = (25.0, -20.0, -20.0, 60.0, 60.0, 25.0)
    test_temperatures_c: tuple[float, ...] = (25.0, 50.0, 0.0, 35.0)
    train_rates_dps: tuple[float, ...] = (0.0, 20.0, -20.0, 90.0, -90.0, 0.0)
    test_rates_dps: tuple[float, ...] = (0.0, 45.0, -45.0, 10.0)
    train_force_g: tuple[float, ...] = (1.0, -1.0, 1.0)
    test_force_g: tuple[float, ...] = (1.0, 0.0)

    RANGES: ClassVar[dict[str, FieldRange | FieldChoice]] = {
        "part": FieldChoice((*_builtin_parts(), "file"), "a built-in part, or 'file' for the part file in part_toml"),
        "model": FieldChoice(("default", "physics", "budget"),
                             "the part's own default model, its physics model or its datasheet budget"),
        "fs_hz": FieldRange(0.5, 1000.0, "Hz", why="output rate; the records stay a few million samples at most"),
        "train_duration_s": FieldRange(120.0, 86400.0, "s", why="a calibration run of minutes to a day"),
        "test_duration_s": FieldRange(120.0, 86400.0, "s", why="a test run of minutes to a day"),
        "train_temperatures_c": FieldRange(-60.0, 125.0, "degC", why="a thermal chamber's span"),
        "test_temperatures_c": FieldRange(-60.0, 125.0, "degC", why="a thermal chamber's span"),
        "train_rates_dps": FieldRange(-3000.0, 3000.0, "deg/s", why="a rate table's span"),
        "test_rates_dps": FieldRange(-3000.0, 3000.0, "deg/s", why="a rate table's span"),
        "train_force_g": FieldRange(-20.0, 20.0, "g", why="a tumble (+-1 g) to a centrifuge"),
        "test_force_g": FieldRange(-20.0, 20.0, "g", why="a tumble (+-1 g) to a centrifuge"),
    }
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint("part == 'file' iff part_toml", lambda c: (c.part == "file") == bool(c.part_toml.strip()),
                   lambda c: f"part_toml must be given exactly when part is 'file'; got part {c.part!r} and "
                             f"{len(c.part_toml)} characters of part_toml"),
        Constraint("at least 2 temperature knots", _temps_ok,
                   lambda c: "train_temperatures_c and test_temperatures_c need at least 2 knots each [degC]"),
        Constraint("at least 1 step", _steps_ok,
                   lambda c: "train/test_rates_dps and train/test_force_g need at least 1 step each"),
        Constraint("segments longer than their transitions", _segments_ok,
                   lambda c: f"each rate step must last over {2 * _RATE_RAMP_S:g} s and each orientation over "
                             f"{2 * _TUMBLE_S:g} s; shorten the step lists or lengthen the runs"),
    )

    def __post_init__(self) -> None:
        validate(self)


def part_of(config: Config) -> Any:
    """The configuration's part (:class:`gyrobench.sim.parts.Part`): built in, or read from ``part_toml``.

    Parameters
    ----------
    config : Config

    Returns
    -------
    Part
        The part.
    """
    from gyrobench.sim import parts

    if config.part == "file":
        return parts.loads_toml(config.part_toml, source="the part file")
    return parts.get(config.part)


def model_of(config: Config) -> str:
    """The model the configuration runs: ``model``, or the part's ``default_model`` for ``"default"``.

    Parameters
    ----------
    config : Config

    Returns
    -------
    str
        ``"physics"`` or ``"budget"``.
    """
    return str(part_of(config).datasheet.default_model) if config.model == "default" else config.model


def _steps(values: tuple[float, ...], duration: float, ramp: float, scale: float) -> Any:
    """Equal segments of ``values`` x ``scale``, joined by linear ramps of ``ramp`` seconds."""
    from gyrobench.sim.environment import PiecewiseLinear

    if len(values) == 1:
        return values[0] * scale
    edges = np.linspace(0.0, duration, len(values) + 1)
    t, v = [0.0], [values[0] * scale]
    for i in range(1, len(values)):
        t += [edges[i] - ramp / 2, edges[i] + ramp / 2]
        v += [values[i - 1] * scale, values[i] * scale]
    t.append(duration)
    v.append(values[-1] * scale)
    return PiecewiseLinear(np.array(t), np.array(v))


def _environment(config: Config, which: str) -> Any:
    from gyrobench.sim.environment import PiecewiseLinear
    from gyrobench.sim.sensor import Environment

    duration = getattr(config, f"{which}_duration_s")
    temps = np.asarray(getattr(config, f"{which}_temperatures_c"), dtype=float) + 273.15
    temperature = PiecewiseLinear(np.linspace(0.0, duration, len(temps)), temps)
    rate = _steps(getattr(config, f"{which}_rates_dps"), duration, _RATE_RAMP_S, math.pi / 180.0)
    force = _steps(getattr(config, f"{which}_force_g"), duration, _TUMBLE_S, _G0)
    return Environment(duration, true_rate=rate, temperature=temperature, specific_force=force)


def _records(config: Config, seed: int) -> tuple[list[Recording], list[Any]]:
    """(the calibration and test records of seed's unit, their environments)."""
    from gyrobench.sim import parts

    part = part_of(config)
    r_unit, r_train, r_test = np.random.default_rng(seed).spawn(3)
    unit = parts.draw_unit(part, rng=r_unit, model=model_of(config))
    recs, envs = [], []
    for which, rng in (("train", r_train), ("test", r_test)):
        env = _environment(config, which)
        rec = parts.simulate_unit(part, unit, env, fs=config.fs_hz, rng=rng)
        meta = {**rec.metadata, "bench_run": which, "seed": seed}
        recs.append(Recording(fs=rec.fs, channels=rec.channels, truth=rec.truth, inputs=rec.inputs,
                              detail=rec.detail, t0=rec.t0, metadata=meta, name=f"{part.datasheet.name}_{which}"
                              .replace("/", "_")))
        envs.append(env)
    return recs, envs


def simulate(config: Config, seed: int) -> list[Recording]:
    """The calibration and test records of one unit of the part (``gyrobench simulate part``).

    Parameters
    ----------
    config : Config
    seed : int
        The unit's seed.

    Returns
    -------
    list of Recording
        ``<part>_train`` and ``<part>_test``, each in the recording schema (docs/recording.md).
    """
    return _records(config, seed)[0]


def _features(rec: Recording, env: Any, fs: float) -> NDArray[np.float64]:
    n = rec.n_samples
    temp_c = env.sampled("temperature", fs)[:n] - 273.15
    dtemp = np.gradient(temp_c) * fs * 60.0 if n > 1 else np.zeros(n)
    rate = np.degrees(env.sampled("true_rate", fs)[:n])
    force = env.sampled("specific_force", fs)[:n] / _G0
    return np.column_stack([temp_c, dtemp, rate, force])


def compensation_task(config: Config, seed: int) -> CompensationTask:
    """Training = the calibration run; held out = the test run (module docstring).

    Parameters
    ----------
    config : Config
    seed : int
        The unit's seed.

    Returns
    -------
    CompensationTask
        Features (:data:`FEATURES`), target ``output - true rate`` [deg/h].
    """
    (train, test), (e_train, e_test) = _records(config, seed)
    out_train, true_train = train["output"] * _DEG_H, train["truth/true_rate"] * _DEG_H
    held = HeldOutRun(label="test", X=_features(test, e_test, config.fs_hz), output=test["output"] * _DEG_H,
                      truth=test["truth/true_rate"] * _DEG_H)
    return CompensationTask(scenario=NAME, feature_names=FEATURES, X_train=_features(train, e_train, config.fs_hz),
                            y_train=out_train - true_train, heldout=(held,), target="error", unit="deg/h")


def run(config: Config, seed: int, *, progress: bool = False) -> Outcome:
    """Each error component's RMS in the calibration and the test run of one unit (the part's own budget).

    Parameters
    ----------
    config : Config
    seed : int
        The unit's seed.
    progress : bool
        Unused (two records).

    Returns
    -------
    Outcome
        One table: component, RMS in each run [deg/h].
    """
    recs = simulate(config, seed)
    names = list(dict.fromkeys(k for r in recs for k in r.metadata.get("error_components", [])))

    def rms(rec: Recording, k: str) -> float:
        return float(np.sqrt(np.mean(rec.truth[k].data ** 2))) * _DEG_H if k in rec.truth else 0.0

    rows = [[k, f"{rms(recs[0], k):.4g}", f"{rms(recs[1], k):.4g}"] for k in names]
    err = [float(np.sqrt(np.mean((r["output"] - r["truth/true_rate"]) ** 2))) * _DEG_H for r in recs]
    rows.append(["total error", f"{err[0]:.4g}", f"{err[1]:.4g}"])
    label = config.part if config.part != "file" else part_of(config).datasheet.name
    table = Table(title=f"{label} on its {model_of(config)} model: error components [deg/h rms]",
                  columns=["component", "calibration run", "test run"], rows=rows)
    return Outcome(scenario=NAME, title=TITLE, seed=seed, config=config,
                   results={"rms_deg_h": {"train": err[0], "test": err[1]}}, tables=[table])
