"""The one device interface, checked over every device (as scikit-learn's test_common runs over
every estimator): each device model and each built-in datasheet part draws a unit with
``realize(rng=...)`` and simulates with ``simulate(environment, *, fs, rng) -> Recording``."""

from __future__ import annotations

import inspect
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pytest

from gyrobench.io.recording import Recording, schema_problems
from gyrobench.sim import mems_population, mems_slow_flow, parts
from gyrobench.sim.environment import PiecewiseLinear
from gyrobench.sim.fog2d import FOG2DSpec
from gyrobench.sim.fog_loop import ClosedLoopFOG
from gyrobench.sim.rlg import RLGSpec
from gyrobench.sim.rlg_cavity import CavityRLGSpec
from gyrobench.sim.sensor import Environment, Sensor, SensorUnit

EPS = np.finfo(float).eps


@dataclass(frozen=True)
class Device:
    """One device of the common checks: how to draw a unit, and a record length that suits it."""

    name: str
    draw: Callable[[np.random.Generator], SensorUnit]
    spec: Sensor | None
    fs: float
    duration: float
    uses: frozenset[str]  # the inputs the model responds to


def _spec_device(name, spec, fs, duration, uses):
    return Device(name, lambda rng: spec.realize(rng=rng), spec, fs, duration, frozenset(uses))


MODELS = [
    _spec_device("fog2d", FOG2DSpec(), 10.0, 20.0, {"true_rate", "temperature", "vibration"}),
    Device("fog_loop", lambda rng: ClosedLoopFOG(), None, 400.0, 2.0,
           frozenset({"true_rate", "temperature", "vibration"})),
    _spec_device("mems_resonator", mems_population.MemsResonatorSpec(), 200.0, 1.0,
                 {"true_rate", "temperature", "specific_force"}),
    _spec_device("rlg", RLGSpec(), 10.0, 20.0, {"true_rate", "temperature", "vibration"}),
    _spec_device("rlg_cavity", CavityRLGSpec(), 10.0, 20.0, {"true_rate", "temperature"}),
]
PARTS = [
    _spec_device(f"part:{name}", parts.get(name), 100.0, 2.0, {"true_rate", "temperature", "specific_force"})
    for name in parts.names()
]
DEVICES = MODELS + PARTS
IDS = [d.name for d in DEVICES]


def _output(rec: Recording) -> np.ndarray:
    return rec["output"]


def _environment(device: Device) -> Environment:
    n = int(math.floor(device.duration * device.fs))
    return Environment(
        device.duration,
        true_rate=PiecewiseLinear(np.array([0.0, device.duration]), np.array([0.0, 0.02])),  # ramp to 0.02 rad/s
        temperature=np.linspace(293.15, 298.15, n),  # an array sampled at fs: every model must take it
        specific_force=9.80665,
    )


def _record(device: Device, seed: int = 20261201, env: Environment | None = None) -> Recording:
    rng = np.random.default_rng(seed)
    unit = device.draw(rng)
    return unit.simulate(env or _environment(device), fs=device.fs, rng=rng)


@pytest.mark.parametrize("device", DEVICES, ids=IDS)
def test_the_interface_is_the_same_for_every_device(device):
    unit = device.draw(np.random.default_rng(0))
    assert isinstance(unit, SensorUnit)
    if device.spec is not None:
        assert isinstance(device.spec, Sensor)
        rng_param = inspect.signature(device.spec.realize).parameters["rng"]
        assert rng_param.kind is inspect.Parameter.KEYWORD_ONLY, inspect.signature(device.spec.realize)
    sig = inspect.signature(unit.simulate)
    params = list(sig.parameters.values())
    assert [p.name for p in params] == ["environment", "fs", "rng"], sig
    assert params[0].kind in (inspect.Parameter.POSITIONAL_ONLY, inspect.Parameter.POSITIONAL_OR_KEYWORD)
    assert [p.kind for p in params[1:]] == [inspect.Parameter.KEYWORD_ONLY] * 2, sig


def _device_classes() -> set[type]:
    """Every public class of gyrobench.sim whose ``simulate`` takes ``(environment, *, fs, rng)``."""
    import importlib
    import pkgutil

    import gyrobench.sim

    found = set()
    for info in pkgutil.walk_packages(gyrobench.sim.__path__, prefix="gyrobench.sim."):
        module = importlib.import_module(info.name)
        for obj in vars(module).values():
            if not (inspect.isclass(obj) and obj.__module__ == module.__name__) or obj.__name__.startswith("_"):
                continue
            if obj is SensorUnit or getattr(obj, "_is_protocol", False):
                continue
            sim = getattr(obj, "simulate", None)
            if callable(sim) and list(inspect.signature(sim).parameters)[1:] == ["environment", "fs", "rng"]:
                found.add(obj)
    return found


def test_the_common_checks_cover_every_device_model_and_part():
    """A new device model is caught here until it joins MODELS (a unit it draws, or its spec)."""
    rng = np.random.default_rng(0)
    covered = {type(d.draw(rng)) for d in DEVICES} | {type(d.spec) for d in DEVICES if d.spec is not None}
    missing = {c for c in _device_classes() if not any(issubclass(t, c) for t in covered)}
    assert not missing, f"device models the common checks do not run: {sorted(c.__qualname__ for c in missing)}"
    assert {"FOG2DUnit", "ClosedLoopFOG", "MemsResonator", "RLGUnit", "CavityRLG", "PartUnit", "Part"} <= {
        c.__name__ for c in _device_classes()
    }


@pytest.mark.parametrize("device", DEVICES, ids=IDS)
def test_a_record_has_its_length_its_truth_and_closes(device):
    rec = _record(device)
    n = int(math.floor(device.duration * device.fs))
    assert rec.fs == device.fs and rec.n_samples == n
    out = _output(rec)
    assert np.all(np.isfinite(out))
    true = rec["truth/true_rate"]
    # the table ramp reaches the truth (the FOGs add the Earth's rate, constant): its rise over
    # the record is the ramp's over the sample span, (n - 1)/fs x 0.02/duration
    rise = (true[-1] - true[0]) / ((n - 1) / device.fs * 0.02 / device.duration)
    assert abs(rise - 1.0) < 1e-9, rise
    comps = rec.metadata.get("error_components")
    assert isinstance(comps, list)
    assert comps, "every model names its components"
    assert schema_problems(rec) == [], schema_problems(rec)
    terms = [rec["truth/" + k] for k in comps]
    # an identity up to float64 rounding: a sum of len(terms) + 2 numbers each rounded at eps
    # relative to the largest magnitude in play (the RLG's cumulative angle differenced:
    # |theta| fs); a factor 16 for the model's intermediate operations
    scale = max(np.max(np.abs(p)) for p in (out, true, *terms))
    if device.name.startswith("rlg"):
        scale = max(scale, float(np.sum(np.abs(true))) + np.max(np.abs(out)) * n)
    tol = 16 * (len(terms) + 2) * EPS * scale
    resid = out - true - np.sum(terms, axis=0)
    assert np.max(np.abs(resid)) <= tol, (np.max(np.abs(resid)), tol)
    assert np.max(np.abs(np.sum(terms, axis=0))) > 1e3 * tol  # not closing trivially


@pytest.mark.parametrize("device", DEVICES, ids=IDS)
def test_a_seed_gives_the_same_bits_and_another_seed_other_bits(device):
    a, b, c = _record(device, 7), _record(device, 7), _record(device, 8)
    np.testing.assert_array_equal(_output(a), _output(b))
    assert not np.array_equal(_output(a), _output(c))


@pytest.mark.parametrize("device", MODELS, ids=[d.name for d in MODELS])
def test_a_model_names_the_inputs_it_ignores(device):
    rec = _record(device)
    expected = sorted({"specific_force"} - device.uses)
    assert sorted(rec.metadata["ignored_inputs"]) == expected
    quiet = _record(device, env=Environment(device.duration))
    assert quiet.metadata["ignored_inputs"] == []


@pytest.mark.parametrize("device", DEVICES, ids=IDS)
def test_bad_calls_are_refused_in_one_line(device):
    unit = device.draw(np.random.default_rng(0))
    env = Environment(device.duration)
    with pytest.raises(TypeError, match=r"environment must be a gyrobench.sim.sensor.Environment; got float|"
                       r"environment must be an Environment; got float"):
        unit.simulate(1.0, fs=device.fs, rng=np.random.default_rng(0))  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"fs must be a finite number > 0 Hz; got 0.0"):
        unit.simulate(env, fs=0.0, rng=np.random.default_rng(0))
    with pytest.raises(TypeError, match=r"rng must be a numpy.random.Generator; got int"):
        unit.simulate(env, fs=device.fs, rng=0)  # type: ignore[arg-type]


def test_mems_temperature_array_reaches_the_physics():
    """A temperature step given as an array: each block equals a slow flow at that temperature.

    The record's blocks (:data:`mems_resonator.TEMPERATURE_BLOCK`) each run the slow flow at the
    block's mean temperature from the equilibrium of its first rate; with the block's child
    stream the block must equal :func:`mems_slow_flow.slow_flow` run alone to the last bit, and
    the two temperatures must give outputs that differ (else the equality would not show the
    temperature was used).
    """
    fs, duration = 1000.0, 2.0
    n = int(duration * fs)
    unit = mems_population.MemsResonatorSpec().realize(rng=np.random.default_rng(3))
    t_a, t_b = 293.15, 343.15
    temp = np.where(np.arange(n) < n // 2, t_a, t_b)
    rate = 0.5  # rad/s
    rec = unit.simulate(Environment(duration, true_rate=rate, temperature=temp), fs=fs, rng=np.random.default_rng(4))
    assert rec.metadata["temperature_blocks"] == 2
    out = rec["output"]
    children = np.random.default_rng(4).spawn(2)
    for sl, temp_k, child in ((slice(0, n // 2), t_a, children[0]), (slice(n // 2, n), t_b, children[1])):
        # the block's mean temperature, as the record takes it (np.mean of 1000 x 343.15 is 1 ulp below
        # 343.15, and the slow flow's noise discretisation is not continuous in the temperature bit by bit)
        t_block = float(np.mean(temp[sl]))
        assert t_block == pytest.approx(temp_k, rel=1e-14)
        ref = mems_slow_flow.slow_flow(unit, np.full(n // 2, rate), fs=fs, rng=child, temperature=t_block,
                           specific_force=np.zeros(n // 2)).output
        np.testing.assert_array_equal(out[sl], ref)
    assert abs(np.mean(out[: n // 2]) - np.mean(out[n // 2 :])) > 1e-6 * rate


def test_constant_inputs_and_profiles_agree_with_arrays():
    """A number, a profile and the equivalent array give the same samples."""
    fs, duration = 10.0, 3.0
    n = 30
    t = (np.arange(n) + 0.5) / fs
    prof = PiecewiseLinear(np.array([0.0, duration]), np.array([290.0, 300.0]))
    for v in (prof, prof(t)):
        np.testing.assert_array_equal(Environment(duration, temperature=v).sampled("temperature", fs), prof(t))
    np.testing.assert_array_equal(Environment(duration, true_rate=0.1).sampled("true_rate", fs), np.full(n, 0.1))
    env = Environment(duration)
    assert np.all(env.sampled("temperature", fs, default=280.0) == 280.0)


@pytest.mark.parametrize(
    ("kwargs", "err", "match"),
    [
        ({"duration": -1.0}, ValueError, r"Environment.duration must be > 0 s; got -1.0"),
        ({"duration": 1.0, "true_rate": "fast"}, TypeError, r"Environment.true_rate must be a number"),
        ({"duration": 1.0, "temperature": math.nan}, ValueError, r"Environment.temperature must be finite \[K\]"),
        (
            {"duration": 1.0, "specific_force": np.zeros((2, 2))},
            ValueError,
            r"Environment.specific_force must be a finite 1-D array",
        ),
        ({"duration": 1.0, "vibration": 3.0}, TypeError, r"Environment.vibration must be a sim.shaker.ShakerSignal"),
    ],
)
def test_environment_bad_input(kwargs, err, match):
    with pytest.raises(err, match=match):
        Environment(**kwargs)


def test_array_of_wrong_length():
    env = Environment(1.0, temperature=np.full(5, 300.0))
    with pytest.raises(ValueError, match=r"Environment.temperature as an array must have .* = 10 samples; got 5"):
        env.sampled("temperature", 10.0)


def test_a_chamber_program_must_span_the_record():
    unit = FOG2DSpec().realize(rng=np.random.default_rng(0))
    short = PiecewiseLinear(np.array([0.0, 10.0]), np.array([300.0, 300.0]))
    with pytest.raises(ValueError, match=r"must span the record \[0, duration\] = \[0, 20.0\] s; got \[0.0, 10.0\] s"):
        unit.simulate(Environment(20.0, temperature=short), fs=10.0, rng=np.random.default_rng(1))


def test_static_fog_runs_for_any_duration():
    """A constant chamber off the thermal step grid (610 s, 20 s steps) is exact under the first-order
    hold: the run is accepted and its thermal drift is rounding (< 1e-18 rad/s)."""
    unit = FOG2DSpec().realize(rng=np.random.default_rng(0))
    rec = unit.simulate(Environment(610.0), fs=10.0, rng=np.random.default_rng(1))
    assert rec.n_samples == 6100  # the whole 610 s, not the 600 s of whole thermal steps
    assert np.max(np.abs(rec["detail/thermal_drift"])) < 1e-18
