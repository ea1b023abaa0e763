"""Tests of sim/mems.py: closed-form scale-factor path, calibration, decomposition, noise, bad input."""

from __future__ import annotations

import dataclasses
import zlib

import numpy as np
import pytest
from gyrobench.sim import units
from gyrobench.sim.mems import (
    KNEE_WIDTH_DPS,
    MemsSpec,
    MemsUnit,
    die_temperature,
    scale_factor_output,
    simulate_output,
)
from gyrobench.sim.noise import NoiseModel
from scipy import stats

GRID_DPS = np.arange(3600.0, -3601.0, -360.0)


@pytest.fixture
def rng(request) -> np.random.Generator:
    """The same stream on every run, a different one for every test."""
    key = zlib.crc32(request.node.nodeid.encode())
    return np.random.default_rng([20261121, key])


def _linear_spec(**kw) -> MemsSpec:
    """A gyro without nonlinearity, noise, quantization or turn-on scatter."""
    base = dict(
        knee_rate=1e6,
        cubic=0.0,
        asymmetry=0.0,
        sign_offset=0.0,
        resolution=0.0,
        measurement_range=1e7,
        bias_repeatability=0.0,
        noise=NoiseModel(),
    )
    base.update(kw)
    return dataclasses.replace(MemsSpec(), **base)


def _kn(w, f):
    """IEEE K_n computed here by numpy (sim tests do not import analysis)."""
    k, f0 = np.polyfit(w, f, 1)
    return np.max(np.abs(f - (k * w + f0))) / np.max(np.abs(f))


# ------------------------------------------------------------------ closed form
def test_linear_spec_is_exactly_proportional():
    spec = _linear_spec(scale_factor=1.25)
    w = units.deg_per_s(GRID_DPS)
    np.testing.assert_allclose(scale_factor_output(spec, w), 1.25 * w, rtol=1e-12, atol=0)


def test_scale_factor_temperature_coefficient():
    spec = _linear_spec(scale_factor_tc=units.ppm(300.0))
    w = units.deg_per_s(GRID_DPS)
    t = spec.reference_temperature + 4.0
    np.testing.assert_allclose(scale_factor_output(spec, w, t), (1 + 1.2e-3) * w, rtol=1e-12)


def test_asymmetry_and_sign_offset_closed_form():
    spec = _linear_spec(asymmetry=0.02, sign_offset=0.1)
    w = np.array([-2.0, -1.0, 0.0, 1.0, 2.0])
    expected = np.array([-2 * 0.99 - 0.1, -0.99 - 0.1, 0.0, 1.01 + 0.1, 2 * 1.01 + 0.1])
    np.testing.assert_allclose(scale_factor_output(spec, w), expected, rtol=1e-12)


def test_knee_closed_form_and_c1_at_the_knee():
    spec = _linear_spec(knee_rate=2.0, knee_width=0.5)
    w = np.array([1.0, 2.0, 3.0, -3.0])
    expected = np.array([1.0, 2.0, 2.0 + 0.5 * np.tanh(2.0), -(2.0 + 0.5 * np.tanh(2.0))])
    np.testing.assert_allclose(scale_factor_output(spec, w), expected, rtol=1e-12)
    h = 1e-6
    left = (scale_factor_output(spec, 2.0) - scale_factor_output(spec, 2.0 - h)) / h
    right = (scale_factor_output(spec, 2.0 + h) - scale_factor_output(spec, 2.0)) / h
    # slope 1 on both sides; the one-sided difference errs by O(h^2 / Ws^2) past the knee (s'' = 0 there)
    assert abs(left - 1.0) < 1e-9 and abs(right - 1.0) < 1e-8


def test_default_calibration_reproduces_paper_nonlinearity():
    """The noise-free default unit on the paper's grid has K_n = 15.71 % (module docstring calibration)."""
    f = units.to_deg_per_s(scale_factor_output(MemsSpec(), units.deg_per_s(GRID_DPS)))
    assert abs(100 * _kn(GRID_DPS, f) - 15.71) < 0.005  # Ws is printed to 0.01 deg/s
    assert KNEE_WIDTH_DPS == pytest.approx(units.to_deg_per_s(MemsSpec().knee_width), rel=1e-12)


def test_die_temperature_closed_form():
    spec = MemsSpec()
    t = np.array([0.0, spec.self_heating_tau, 1e9])
    got = die_temperature(spec, 300.0, t)
    np.testing.assert_allclose(
        got, 300.0 + spec.self_heating * np.array([0.0, 1 - np.exp(-1.0), 1.0]), rtol=1e-12
    )


def test_output_decomposes_exactly(rng):
    spec = MemsSpec()
    w = units.deg_per_s(np.repeat([3600.0, 0.0, -1000.0], 200))
    temp = spec.reference_temperature + np.linspace(0.0, 3.0, w.size)
    out = simulate_output(spec, w, fs=200.0, temperature=temp, acceleration=units.G0, rng=rng)
    total = w + sum(out.components.values())
    np.testing.assert_allclose(total, out.output, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(
        out.output / spec.resolution, np.round(out.output / spec.resolution), atol=1e-6
    )


def test_noise_free_output_is_the_model():
    spec = _linear_spec(
        bias=0.01, bias_tc=1e-3, bias_tc2=1e-4, g_sensitivity=1e-4, scale_factor_tc=0.0
    )
    w = np.linspace(-1.0, 1.0, 11)
    dt = 2.0
    out = simulate_output(
        spec,
        w,
        fs=10.0,
        temperature=spec.reference_temperature + dt,
        acceleration=9.0,
        rng=np.random.default_rng(0),
    )
    expected = w + 0.01 + 1e-3 * dt + 1e-4 * dt**2 + 9e-4
    np.testing.assert_allclose(out.output, expected, rtol=1e-12)


def test_range_clip():
    spec = _linear_spec(measurement_range=units.deg_per_s(1000.0), bias=0.0, g_sensitivity=0.0)
    w = units.deg_per_s(np.array([-3000.0, 500.0, 3000.0]))
    out = simulate_output(
        spec, w, fs=1.0, temperature=spec.reference_temperature, rng=np.random.default_rng(0)
    )
    np.testing.assert_allclose(units.to_deg_per_s(out.output), [-1000.0, 500.0, 1000.0], rtol=1e-12)


def test_unit_scale_factor_error_scales_the_whole_path():
    """A unit with e_on: (1 + e_on) times the knee/cubic/asymmetry path; d is not scaled."""
    spec = MemsSpec()
    unit = MemsUnit(spec=spec, scale_factor_error=3e-4)
    w = units.deg_per_s(GRID_DPS)
    d = spec.sign_offset * np.sign(w)
    np.testing.assert_allclose(
        scale_factor_output(unit, w) - d,
        (1 + 3e-4) * (scale_factor_output(spec, w) - d),
        rtol=1e-12,
    )


def test_simulate_a_given_unit_is_that_unit():
    spec = _linear_spec(bias=0.0, g_sensitivity=0.0, scale_factor_repeatability=0.01)
    unit = MemsUnit(spec=spec, turn_on_bias=0.002, scale_factor_error=-0.004)
    w = np.linspace(-1.0, 1.0, 11)
    out = simulate_output(
        unit, w, fs=10.0, temperature=spec.reference_temperature, rng=np.random.default_rng(0)
    )
    assert out.unit is unit
    np.testing.assert_allclose(out.output, (1 - 0.004) * w + 0.002, rtol=1e-12)


def test_scale_factor_repeatability_zero_keeps_the_turn_on_bias_draw():
    """The turn-on stream draws b_on first: a scale-factor repeatability leaves b_on as it was."""
    a = MemsSpec().realize(rng=np.random.default_rng(7))
    b = dataclasses.replace(MemsSpec(), scale_factor_repeatability=1e-3).realize(
        rng=np.random.default_rng(7)
    )
    assert a.turn_on_bias == b.turn_on_bias and a.scale_factor_error == 0.0
    assert b.scale_factor_error != 0.0


def test_simulate_draws_the_scale_factor_error_per_run():
    spec = _linear_spec(bias=0.0, g_sensitivity=0.0, scale_factor_repeatability=1e-3)
    w = np.linspace(-1.0, 1.0, 5)
    outs = [
        simulate_output(spec, w, fs=1.0, temperature=spec.reference_temperature, rng=r)
        for r in np.random.default_rng(3).spawn(2)
    ]
    assert outs[0].scale_factor_error != outs[1].scale_factor_error
    for o in outs:
        np.testing.assert_allclose(
            o.output, (1 + o.scale_factor_error) * w + o.turn_on_bias, rtol=1e-12
        )


def test_from_datasheet_scale_factor_repeatability_in_ppm():
    spec = MemsSpec.from_datasheet(scale_factor_repeatability_ppm=300.0)
    assert spec.scale_factor_repeatability == pytest.approx(3e-4, rel=1e-12)


def test_from_datasheet_defaults_equal_spec_defaults():
    a, b = MemsSpec.from_datasheet(), MemsSpec()
    for f in dataclasses.fields(MemsSpec):
        if f.name == "noise":
            assert a.noise.angle_random_walk == pytest.approx(b.noise.angle_random_walk, rel=1e-12)
            assert a.noise.bias_instability == pytest.approx(b.noise.bias_instability, rel=1e-12)
        else:
            assert getattr(a, f.name) == pytest.approx(getattr(b, f.name), rel=1e-12), f.name


# ------------------------------------------------------------------ statistical
def test_white_noise_variance(rng):
    """Output at zero rate with ARW only: sample variance N^2 fs; chi-square bound at false-alarm 1e-6."""
    n_dens = 0.02
    spec = _linear_spec(noise=NoiseModel(angle_random_walk=units.deg_per_s_per_sqrt_hz(n_dens)))
    fs, n = 200.0, 20000
    out = simulate_output(spec, np.zeros(n), fs=fs, temperature=spec.reference_temperature, rng=rng)
    sigma2 = units.deg_per_s_per_sqrt_hz(n_dens) ** 2 * fs
    stat = np.sum((out.output - spec.bias) ** 2) / sigma2  # chi-square with n dof (known mean)
    lo, hi = stats.chi2.ppf([0.5e-6, 1 - 0.5e-6], n)
    assert lo < stat < hi


def test_turn_on_bias_scatter(rng):
    """Turn-on bias over 400 runs: variance against bias_repeatability^2, chi-square bound at 1e-6."""
    spec = dataclasses.replace(_linear_spec(), bias_repeatability=0.3)
    draws = np.array(
        [
            simulate_output(
                spec, np.zeros(1), fs=1.0, temperature=spec.reference_temperature, rng=r
            ).turn_on_bias
            for r in rng.spawn(400)
        ]
    )
    stat = np.sum(draws**2) / 0.3**2
    lo, hi = stats.chi2.ppf([0.5e-6, 1 - 0.5e-6], draws.size)
    assert lo < stat < hi


def test_turn_on_scale_factor_scatter(rng):
    """e_on over 400 draws: variance vs scale_factor_repeatability^2, chi-square bound at 1e-6."""
    sigma = 5e-4
    spec = dataclasses.replace(MemsSpec(), scale_factor_repeatability=sigma)
    draws = np.array([spec.realize(rng=r).scale_factor_error for r in rng.spawn(400)])
    stat = np.sum(draws**2) / sigma**2
    lo, hi = stats.chi2.ppf([0.5e-6, 1 - 0.5e-6], draws.size)
    assert lo < stat < hi


# ------------------------------------------------------------------ bad input
@pytest.mark.parametrize("value", [-1e-4, 0.1, 0.5])
def test_rejects_out_of_range_scale_factor_repeatability(value):
    with pytest.raises(
        ValueError, match=rf"MemsSpec.scale_factor_repeatability must be .* got {value!r}"
    ):
        MemsSpec(scale_factor_repeatability=value)


def test_unit_rejects_scale_factor_error_of_minus_one():
    with pytest.raises(
        ValueError, match=r"MemsUnit.scale_factor_error must be > -1 \[-\]; got -1.0"
    ):
        MemsUnit(spec=MemsSpec(), scale_factor_error=-1.0)


def test_unit_rejects_wrong_spec_type():
    with pytest.raises(TypeError, match="MemsUnit.spec must be a MemsSpec; got dict"):
        MemsUnit(spec={})


def test_realize_rejects_legacy_random_state():
    with pytest.raises(TypeError, match="rng must be a numpy.random.Generator; got RandomState"):
        MemsSpec().realize(rng=np.random.RandomState(0))


#: one bad argument of simulate_output at a time: (argument, exception, message naming it)
_SIMULATE_BAD = {
    "spec-type": ({"spec": {}}, TypeError, "spec must be a MemsSpec or MemsUnit; got dict"),
    "nan-rate": (
        {"rate": np.array([0.0, np.nan])},
        ValueError,
        "rate must be a non-empty 1-D array of finite values",
    ),
    "fs-zero": ({"fs": 0.0}, ValueError, "fs must be a finite number > 0 Hz; got 0.0"),
    "negative-temperature": (
        {"temperature": [300.0, -5.0, 300.0]},
        ValueError,
        r"temperature must be finite and > 0 K; got -5.0 at index 1",
    ),
    "nan-temperature": (
        {"temperature": np.nan},
        ValueError,
        r"temperature must be finite and > 0 K; got nan at index 0",
    ),
    "inf-acceleration": (
        {"acceleration": [0.0, 0.0, np.inf]},
        ValueError,
        r"acceleration must be finite \[m/s\^2\]; got inf at index 2",
    ),
    "legacy-rng": (
        {"rng": np.random.RandomState(0)},
        TypeError,
        "rng must be a numpy.random.Generator; got RandomState",
    ),
}


@pytest.mark.parametrize(
    ("bad", "exc", "msg"), list(_SIMULATE_BAD.values()), ids=list(_SIMULATE_BAD)
)
def test_simulate_rejects(bad, exc, msg):
    args = {"spec": MemsSpec(), "rate": np.zeros(3), "fs": 1.0, "temperature": 300.0}
    args |= {"rng": np.random.default_rng(0), **bad}
    with pytest.raises(exc, match=msg):
        simulate_output(args.pop("spec"), args.pop("rate"), **args)


def test_rejects_nonpositive_knee_rate():
    with pytest.raises(ValueError, match=r"MemsSpec.knee_rate must be > 0 rad/s; got -1.0"):
        MemsSpec(knee_rate=-1.0)


def test_rejects_asymmetry_of_one():
    with pytest.raises(ValueError, match=r"MemsSpec.asymmetry must satisfy \|a\| < 1"):
        MemsSpec(asymmetry=1.0)


def test_rejects_resolution_above_range():
    with pytest.raises(ValueError, match="MemsSpec.resolution must be < measurement_range"):
        MemsSpec(resolution=1.0, measurement_range=0.5)


def test_rejects_nan_field():
    with pytest.raises(ValueError, match="MemsSpec.bias must be finite"):
        MemsSpec(bias=float("nan"))


def test_rejects_string_field():
    with pytest.raises(TypeError, match="MemsSpec.cubic must be a real number"):
        MemsSpec(cubic="1e-10")


def test_rejects_bad_noise_type():
    with pytest.raises(TypeError, match="MemsSpec.noise must be a NoiseModel"):
        MemsSpec(noise={"N": 0.1})


def test_rejects_bad_resolution_bits():
    with pytest.raises(ValueError, match="resolution_bits must be an integer >= 2"):
        MemsSpec.from_datasheet(resolution_bits=1)


def test_rejects_negative_time_since_power_on():
    with pytest.raises(
        ValueError, match=r"time_since_power_on must be >= 0 s; got -1.0 at index 1"
    ):
        die_temperature(MemsSpec(), 300.0, [0.0, -1.0])


def test_rejects_nan_time_since_power_on():
    with pytest.raises(ValueError, match=r"time_since_power_on must be >= 0 s; got nan at index 0"):
        die_temperature(MemsSpec(), 300.0, np.nan)
