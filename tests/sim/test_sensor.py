"""Tests of sim/sensor.py: every device model through the one Sensor interface."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gyrobench.sim import mems_resonator as mr
from gyrobench.sim.environment import PiecewiseLinear
from gyrobench.sim.fog2d import FOG2DSpec
from gyrobench.sim.rlg import RLGSpec
from gyrobench.sim.rlg_cavity import CavityRLGSpec
from gyrobench.sim.sensor import (
    Environment,
    FogSensor,
    MemsSensor,
    RlgSensor,
    Sensor,
    SensorUnit,
)

EPS = np.finfo(float).eps

# (id, sensor factory, fs [Hz], duration [s]): short records at each model's usual output rate
DEVICES = [
    ("fog2d", lambda: FogSensor(FOG2DSpec()), 10.0, 20.0),
    ("mems_resonator", lambda: MemsSensor(mr.MemsResonatorSpec()), 200.0, 1.0),
    ("rlg", lambda: RlgSensor(RLGSpec()), 10.0, 20.0),
    ("rlg_cavity", lambda: RlgSensor(CavityRLGSpec()), 10.0, 20.0),
]


def _environment(duration: float, fs: float) -> Environment:
    n = int(math.floor(duration * fs))
    return Environment(
        duration,
        true_rate=PiecewiseLinear(np.array([0.0, duration]), np.array([0.0, 0.02])),  # ramp to 0.02 rad/s
        temperature=np.linspace(293.15, 298.15, n),  # an array sampled at fs: every model must take it
        specific_force=9.80665,
    )


@pytest.mark.parametrize(("name", "make", "fs", "duration"), DEVICES, ids=[d[0] for d in DEVICES])
def test_every_device_through_the_protocol(name, make, fs, duration):
    sensor = make()
    assert isinstance(sensor, Sensor)
    rng = np.random.default_rng(20261127)
    unit = sensor.realize(rng)
    assert isinstance(unit, SensorUnit)
    env = _environment(duration, fs)
    rec = unit.simulate(env, fs=fs, rng=rng)

    n = int(math.floor(duration * fs))
    assert rec.fs == fs
    assert rec.n_samples == n
    out = rec["rate"]
    assert np.all(np.isfinite(out))
    true = rec["truth/true_rate"]
    assert len(true) == n
    # the table ramp reaches the truth (the FOG adds the Earth's rate, constant): its rise
    # over the record is the ramp's over the sample span, (n - 1)/fs x 0.02/duration
    rise = (true[-1] - true[0]) / ((n - 1) / fs * 0.02 / duration)
    assert abs(rise - 1.0) < 1e-9, rise

    comps = rec.metadata["error_components"]
    if name == "mems_resonator":
        assert comps == []  # the slow flow does not split its output
    else:
        assert comps, "a model that keeps components must name them"
        parts = [rec["truth/" + k] for k in comps]
        # an identity up to float64 rounding: a sum of len(parts) + 2 terms each rounded at
        # eps relative to the largest magnitude in play (the RLG's cumulative angle
        # differenced: |theta| fs); a factor 16 for the model's intermediate operations
        scale = max(np.max(np.abs(p)) for p in (out, true, *parts))
        if name.startswith("rlg"):
            scale = max(scale, float(np.sum(np.abs(true))) + np.max(np.abs(out)) * n)
        tol = 16 * (len(parts) + 2) * EPS * scale
        resid = out - true - np.sum(parts, axis=0)
        assert np.max(np.abs(resid)) <= tol, (np.max(np.abs(resid)), tol)
        # and the components are not all zero (the identity would hold trivially)
        assert np.max(np.abs(np.sum(parts, axis=0))) > 1e3 * tol

    # g-sensitivity: the FOG and RLG models have none and say so
    expected_ignored = [] if name == "mems_resonator" else ["specific_force"]
    assert rec.metadata["ignored_inputs"] == expected_ignored


def test_mems_temperature_array_reaches_the_physics():
    """A temperature step given as an array: each half equals a scalar-temperature run.

    Noise, ADC and 1/f off, so the slow flow is deterministic: a block at constant
    temperature must equal :func:`mems_resonator.simulate` at that temperature started from
    the equilibrium of its first rate (the documented block rule) to rounding, and the two
    temperatures must give outputs that differ (else the equality would not show the
    temperature was used).
    """
    fs, duration = 1000.0, 2.0
    n = int(duration * fs)
    sensor = MemsSensor(mr.MemsResonatorSpec(), temperature_block=1.0, noise=False, adc=False, flicker=False)
    unit = sensor.realize(np.random.default_rng(3))
    t_a, t_b = 293.15, 343.15
    temp = np.where(np.arange(n) < n // 2, t_a, t_b)
    rate = 0.5  # rad/s
    rec = unit.simulate(Environment(duration, true_rate=rate, temperature=temp), fs=fs, rng=np.random.default_rng(4))
    assert rec.metadata["temperature_blocks"] == 2
    out = rec["rate"]
    for sl, temp_k in ((slice(0, n // 2), t_a), (slice(n // 2, n), t_b)):
        ref = mr.simulate(
            unit.unit, np.full(n // 2, rate), fs=fs, rng=np.random.default_rng(0), temperature=temp_k,
            noise=False, adc=False, flicker=False,
        ).output
        np.testing.assert_allclose(out[sl], ref, rtol=1e-12, atol=0)
    # settled outputs of the two temperatures differ by far more than rounding
    assert abs(out[n // 2 - 1] - out[-1]) > 1e-9 * rate


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
        ({"duration": -1.0}, ValueError, r"Environment.duration must be a finite number > 0 s; got -1.0"),
        ({"duration": 1.0, "true_rate": "fast"}, TypeError, r"Environment.true_rate must be a number"),
        ({"duration": 1.0, "temperature": math.nan}, ValueError, r"Environment.temperature must be finite \[K\]"),
        (
            {"duration": 1.0, "specific_force": np.zeros((2, 2))},
            ValueError,
            r"Environment.specific_force must be a finite 1-D array",
        ),
    ],
)
def test_environment_bad_input(kwargs, err, match):
    with pytest.raises(err, match=match):
        Environment(**kwargs)


def test_array_of_wrong_length_and_bad_fs_rng():
    env = Environment(1.0, temperature=np.full(5, 300.0))
    with pytest.raises(ValueError, match=r"Environment.temperature as an array must have .* = 10 samples; got 5"):
        env.sampled("temperature", 10.0)
    unit = MemsSensor(mr.MemsResonatorSpec()).realize(np.random.default_rng(0))
    with pytest.raises(ValueError, match=r"fs must be a finite number > 0 Hz; got 0.0"):
        unit.simulate(Environment(1.0), fs=0.0, rng=np.random.default_rng(0))
    with pytest.raises(TypeError, match=r"rng must be a numpy.random.Generator; got int"):
        unit.simulate(Environment(1.0), fs=10.0, rng=0)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"MemsSensor.temperature_block must be a finite number > 0 s; got 0"):
        MemsSensor(mr.MemsResonatorSpec(), temperature_block=0)
    with pytest.raises(TypeError, match=r"RlgSensor.spec must be an RLGSpec or CavityRLGSpec; got FOG2DSpec"):
        RlgSensor(FOG2DSpec())  # type: ignore[arg-type]


def test_static_fog_runs_for_any_duration():
    """A constant chamber off the thermal step grid (610 s, 20 s steps) is exact under the first-order
    hold: the run is accepted and its thermal drift is rounding (< 1e-18 rad/s), where the relative
    convergence check once refused it ("did not converge")."""
    from gyrobench.sim.fog2d import FOG2DSpec

    unit = FogSensor(FOG2DSpec()).realize(np.random.default_rng(0))
    rec = unit.simulate(Environment(610.0), fs=10.0, rng=np.random.default_rng(1))
    assert rec.n_samples == 6100  # the whole 610 s, not the 600 s of whole thermal steps
    assert np.max(np.abs(rec["truth/thermal_drift"])) < 1e-18
