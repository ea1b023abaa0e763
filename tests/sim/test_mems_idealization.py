"""MemsResonator.idealization: the declared noise-free twins a user's reference runs go through simulate with.

The twins must be the noise-free part of the unit as built (bit for bit, so a paper's records
do not change when it stops calling the slow flow with its switches), draw nothing from their
generator, and, for the analog twin, read the output before the ADC. The static output
(:func:`static_rate_output`) is checked against the settled slow flow of the analog twin.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gyrobench.base import units
from gyrobench.io.recording import schema_problems
from gyrobench.sim.mems_resonator import MemsResonator, static_rate_output
from gyrobench.sim.sensor import Environment

FS = 200.0


def _environment(shape: str) -> Environment:
    if shape == "columns":
        return Environment(0.5, true_rate=np.tile(units.deg_per_s(np.array([-100.0, 0.0, 250.0])), (100, 1)),
                           temperature=units.celsius(30.0))
    if shape == "temperature_blocks":
        n = 400
        return Environment(n / FS, true_rate=np.full(n, 0.3), temperature=units.celsius(np.linspace(20.0, 40.0, n)))
    return Environment(1.0, true_rate=np.linspace(-1.0, 1.0, 200))


@pytest.mark.parametrize("shape", ["one", "columns", "temperature_blocks"])
def test_noise_free_twin_is_the_records_deterministic_part(shape):
    """The twin's record holds, bit for bit, the as-built record's deterministic error; its noise is 0."""
    env = _environment(shape)
    unit = MemsResonator(turn_on_bias=units.deg_per_s(0.05))
    built = unit.simulate(env, fs=FS, rng=np.random.default_rng(3))
    twin = dataclasses.replace(unit, idealization="noise_free")
    a = twin.simulate(env, fs=FS, rng=np.random.default_rng(3))
    b = twin.simulate(env, fs=FS, rng=np.random.default_rng(99))  # draws nothing: any stream gives it
    assert np.array_equal(a["truth/deterministic_error"], built["truth/deterministic_error"])
    assert np.array_equal(a["output"], b["output"])
    assert not np.any(a["truth/noise"])
    assert np.any(built["truth/noise"])  # the unit as built is noisy: the twin differs from it
    assert schema_problems(a) == []
    total = dataclasses.replace(twin, error_split="total").simulate(env, fs=FS, rng=np.random.default_rng(3))
    assert np.array_equal(total["output"], a["output"])


def test_analog_twin_reads_the_output_before_the_adc():
    """Beyond the output range the word clips at R and the analog output does not; inside it they
    differ by the rounding only (at most q/2)."""
    unit = MemsResonator()
    r, q = unit.output_range, unit.resolution
    w = units.deg_per_s(np.array([1234.5, 4300.0]))  # inside the range; beyond it, below the 4700 deg/s authority
    env = Environment(0.5, true_rate=np.tile(w, (100, 1)))
    word = dataclasses.replace(unit, idealization="noise_free").simulate(env, fs=FS, rng=np.random.default_rng(0))
    analog = dataclasses.replace(unit, idealization="noise_free_analog").simulate(
        env, fs=FS, rng=np.random.default_rng(0))
    yw, ya = (rec["output"].reshape(2, 100) for rec in (word, analog))
    assert np.all(yw[1] == r) and np.all(ya[1] > r)
    assert np.all(np.abs(yw[0] - ya[0]) <= q / 2 * (1 + 1e-9))
    assert np.any(np.abs(ya[0] / q - np.round(ya[0] / q)) > 1e-3)  # not on the LSB grid


@pytest.mark.parametrize("readout", ["force_rebalance", "open_loop"])
def test_static_rate_output_is_the_settled_analog_output(readout):
    """static_rate_output + turn-on bias - trim = the analog twin's output at constant rates.

    Each column starts at its equilibrium, so the slow flow stays there; rtol 1e-12 (~4500 eps)
    bounds the rounding of its 100-step recursion (measured 1.4e-14), far below the 20-bit LSB
    (2.4e-6 of full scale).
    """
    unit = MemsResonator(readout=readout, bias_trim=0.01, turn_on_bias=0.002)
    w = units.deg_per_s(np.array([-3000.0, -100.0, 0.0, 250.0, 3500.0]))
    env = Environment(0.5, true_rate=np.tile(w, (100, 1)))
    rec = dataclasses.replace(unit, idealization="noise_free_analog").simulate(env, fs=FS, rng=np.random.default_rng(1))
    expect = static_rate_output(unit, w) + unit.turn_on_bias - unit.bias_trim
    np.testing.assert_allclose(rec["output"].reshape(5, 100), np.repeat(expect[:, None], 100, axis=1),
                               rtol=1e-12, atol=1e-12 * np.max(np.abs(expect)))


def test_one_column_is_the_one_dimensional_record():
    """An (n, 1) true_rate is the 1-D record (it used to fail on the force's shape)."""
    rate = np.linspace(-0.5, 0.5, 100)
    unit = MemsResonator()
    one = unit.simulate(Environment(1.0, true_rate=rate), fs=100.0, rng=np.random.default_rng(5))
    col = unit.simulate(Environment(1.0, true_rate=rate[:, None]), fs=100.0, rng=np.random.default_rng(5))
    assert np.array_equal(one["output"], col["output"])
    assert col.metadata["segments"] == 1


def test_idealization_is_a_declared_choice():
    with pytest.raises(ValueError, match="idealization"):
        MemsResonator(idealization="quiet")
