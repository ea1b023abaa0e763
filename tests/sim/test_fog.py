"""Tests of sim.fog: Sagnac scale factor, FOG thermal run, logged temperature sensor."""

from __future__ import annotations

import math
import zlib

import numpy as np
import pytest
from gyrobench.sim import units
from gyrobench.sim.coil import CoilSpec, CoilThermalModel, Winding, shupe_terms
from gyrobench.sim.environment import PiecewiseLinear, Ramp, Soak, thermal_profile
from gyrobench.sim.fog import SPEED_OF_LIGHT, FOGSpec, FOGUnit, TemperatureSensorSpec, sagnac_scale_factor
from gyrobench.sim.noise import NoiseModel
from scipy import stats


@pytest.fixture
def rng(request) -> np.random.Generator:
    key = zlib.crc32(request.node.nodeid.encode())
    return np.random.default_rng([20261121, key])


def _profile(rate_K_min=1.0):
    C = units.celsius
    return thermal_profile(
        C(-10.0),
        [Soak(duration=600.0), Ramp(target=C(40.0), rate=rate_K_min / 60.0), Soak(duration=1200.0)],
    )


def _quiet_spec(**kw) -> FOGSpec:
    return FOGSpec(
        noise=NoiseModel(), sensor=TemperatureSensorSpec(noise=0.0, resolution=0.0), **kw
    )


def test_sagnac_scale_factor_closed_form():
    sf = sagnac_scale_factor(1000.0, 0.1, 1550e-9)
    assert sf == pytest.approx(2 * math.pi * 1000.0 * 0.1 / (1550e-9 * SPEED_OF_LIGHT), rel=1e-15)
    assert sf == pytest.approx(1.352, abs=0.0005)  # docs/physics.md 3.1, printed precision
    assert FOGSpec().scale_factor == pytest.approx(sf, rel=1e-12)  # default coil D = 0.1 m


def test_scale_factor_ratio_closed_form():
    spec = FOGSpec(diameter_tempco=1e-5, wavelength_tempco=3e-6)
    Tr = spec.scale_factor_ref_temperature
    got = spec.scale_factor_ratio(Tr + 10.0, Tr - 5.0)
    assert got == pytest.approx((1 + 5.5e-7 * 10) * (1 + 1e-5 * 10) / (1 - 3e-6 * 5), rel=1e-15)
    assert spec.scale_factor_ratio(Tr, Tr) == 1.0


def test_noise_free_output_is_sum_of_truth_parts(rng):
    """Without noise the output is true rate + SF error + coil drift, sample by sample."""
    spec = _quiet_spec()
    unit = spec.realize(rng=rng)
    a = units.deg_per_h(180.0)
    rec = unit.simulate(_profile(), fs=0.5, rng=rng, true_rate=a)
    parts = (
        rec["truth/rate"]
        + rec["truth/scale_factor_error"]
        + rec["truth/thermal_drift"]
        + rec["truth/noise"]
    )
    np.testing.assert_allclose(rec["rate"], parts, rtol=1e-14, atol=1e-18)
    np.testing.assert_array_equal(rec["truth/noise"], 0.0)
    np.testing.assert_array_equal(rec["coil_temperature"], rec["truth/sensor_temperature"])
    drift = rec["truth/shupe"] + rec["truth/dndT_product"] + rec["truth/strain"]
    np.testing.assert_allclose(rec["truth/thermal_drift"], drift, rtol=1e-14, atol=1e-20)
    sf = (
        spec.scale_factor_ratio(
            rec["truth/coil_mean_temperature"], rec["truth/housing_temperature"]
        )
        - 1.0
    )
    np.testing.assert_allclose(rec["truth/scale_factor_error"], a * sf, rtol=1e-12, atol=1e-20)


def test_drift_comes_from_the_thermal_grid():
    """The drift in the recording is the Shupe integral of the diffusion solution, interpolated."""
    spec = _quiet_spec(thermal_step=10.0)
    unit = FOGUnit(spec=spec, winding=Winding.ideal("quadrupolar", 40, 1000.0))
    t, x, xdot, terms = unit.thermal_response(_profile())
    direct = shupe_terms(spec.coil, unit.winding.weights, x[:, 2:], xdot[:, 2:])
    np.testing.assert_array_equal(terms.total, direct.total)
    rec = unit.simulate(_profile(), fs=0.1, rng=np.random.default_rng(0))
    np.testing.assert_allclose(
        rec["truth/thermal_drift"], np.interp(rec.time, t, terms.total), rtol=1e-12, atol=1e-20
    )


def test_constant_temperature_gives_no_drift(rng):
    spec = _quiet_spec()
    unit = spec.realize(rng=rng)
    flat = PiecewiseLinear(np.array([0.0, 3600.0]), np.array([300.0, 300.0]))
    rec = unit.simulate(flat, fs=0.1, rng=rng)
    # only the rounding of A x + b u at 300 K (~1e-16 relative) remains: far below 1e-8 deg/h
    np.testing.assert_allclose(rec["truth/thermal_drift"], 0.0, atol=units.deg_per_h(1e-8))


def test_steady_ramp_leaves_only_the_strain_term():
    """Deep into a long ramp Tdot is uniform (transients ~ exp(-t / 1200 s)): the Shupe
    term vanishes, the strain (Mohr) term stays at its closed form
    pre n xi rate sum_j w_j (alpha_c_j (1 + kappa (T_j - T0)) - alpha_f)."""
    spec = _quiet_spec(thermal=CoilThermalModel(coil=CoilSpec(winding="helical")))
    unit = FOGUnit(spec=spec, winding=Winding.ideal("helical", 40, 1000.0))
    rate = 0.2 / 60.0
    C = units.celsius
    prof = thermal_profile(C(-10.0), [Ramp(target=C(38.0), rate=rate)])
    t, x, xdot, terms = unit.thermal_response(prof)
    k = -2  # just before the ramp's end, 4 h in
    np.testing.assert_allclose(xdot[k, 2:], rate, rtol=1e-4)
    c = spec.coil
    pre = c.index / (c.length * c.diameter) * c.index * c.xi
    ac = c.constraint_cte() * (1 + c.constraint_cte_tempco * (x[k, 2:] - c.dn_dT_ref)) - c.fibre_cte
    expected = pre * rate * np.sum(unit.winding.weights * ac)
    assert terms.strain[k] == pytest.approx(expected, rel=1e-3)
    assert abs(terms.shupe[k]) < 1e-3 * abs(terms.strain[k])


def test_sensor_quantizes_to_resolution(rng):
    s = TemperatureSensorSpec(noise=0.01, resolution=0.002)
    y = s.read(np.full(1000, 293.1234), rng=rng)
    np.testing.assert_allclose(y / 0.002, np.round(y / 0.002), atol=1e-6)


def test_sensor_noise_std(rng):
    """Sample variance of n white samples: (n-1) s^2/sigma^2 ~ chi2(n-1); two-sided 1e-6 false alarm."""
    n, sigma = 4000, 0.01
    y = TemperatureSensorSpec(noise=sigma, resolution=0.0).read(np.zeros(n), rng=rng)
    q = (n - 1) * np.var(y, ddof=1) / sigma**2
    lo, hi = stats.chi2.ppf([0.5e-6, 1 - 0.5e-6], n - 1)
    assert lo < q < hi


def test_same_seed_same_recording():
    spec = FOGSpec(thermal=CoilThermalModel(coil=CoilSpec(winding_defect_rms=0.01)))
    a = spec.realize(rng=np.random.default_rng(3)).simulate(
        _profile(), fs=0.2, rng=np.random.default_rng(4)
    )
    b = spec.realize(rng=np.random.default_rng(3)).simulate(
        _profile(), fs=0.2, rng=np.random.default_rng(4)
    )
    np.testing.assert_array_equal(a["rate"], b["rate"])
    np.testing.assert_array_equal(a["coil_temperature"], b["coil_temperature"])


def test_recording_layout(rng):
    rec = FOGSpec().realize(rng=rng).simulate(_profile(), fs=1.0, rng=rng, name="r1")
    assert set(rec.channels) == {"rate", "coil_temperature"}
    assert {"rate", "thermal_drift", "shupe", "strain", "noise", "chamber_temperature"} <= set(
        rec.truth
    )
    assert rec.n_samples == int(_profile().duration)
    assert rec.name == "r1" and rec.fs == 1.0


# ----------------------------------------------------------------------------- bad input


def test_profile_with_a_gap_is_an_error():
    with pytest.raises(ValueError, match=r"a gap in the profile"):
        PiecewiseLinear.from_segments(
            [(0.0, 100.0, 263.15, 263.15), (200.0, 300.0, 263.15, 313.15)]
        )


def test_unresolvable_chamber_rate_is_an_error(rng):
    unit = FOGSpec().realize(rng=rng)
    with pytest.raises(
        ValueError,
        match=r"chamber rate 30 K/min changes the temperature by 2.5 K per diffusion step",
    ):
        unit.simulate(_profile(30.0), fs=1.0, rng=rng)


def test_bad_sensor_location():
    with pytest.raises(ValueError, match=r"location must be one of"):
        TemperatureSensorSpec(location="lid")


def test_bad_scheme():
    with pytest.raises(ValueError, match=r"scheme must be 'implicit' or 'crank-nicolson'"):
        FOGSpec(scheme="euler")


def test_bad_fs(rng):
    with pytest.raises(ValueError, match=r"fs must be a finite number > 0 Hz"):
        FOGSpec().realize(rng=rng).simulate(_profile(), fs=0.0, rng=rng)


def test_crank_nicolson_and_implicit_agree_on_slow_ramps():
    """A 0.5 K/min ramp is slow against both schemes' errors: the drifts agree to 2 %."""
    a = FOGUnit(
        spec=_quiet_spec(thermal_step=2.0), winding=Winding.ideal("quadrupolar", 40, 1000.0)
    )
    b = FOGUnit(spec=_quiet_spec(thermal_step=2.0, scheme="crank-nicolson"), winding=a.winding)
    da = a.thermal_response(_profile(0.5))[3].total
    db = b.thermal_response(_profile(0.5))[3].total
    assert np.max(np.abs(da - db)) < 0.02 * np.max(np.abs(da))


def test_thermal_step_is_converged():
    """The default 5-s implicit step is within 1 % (of the peak) of a 1-s step on a 1 K/min run."""
    w = Winding.ideal("quadrupolar", 40, 1000.0)
    coil = CoilSpec(constraint_decay_length=1e-3)
    drift = {}
    for dt in (1.0, 5.0):
        spec = _quiet_spec(thermal=CoilThermalModel(coil=coil), thermal_step=dt)
        t, _, _, terms = FOGUnit(spec=spec, winding=w).thermal_response(_profile(1.0))
        drift[dt] = np.interp(np.arange(0.0, t[-1], 5.0), t, terms.total)
    n = min(len(drift[1.0]), len(drift[5.0]))
    assert np.max(np.abs(drift[5.0][:n] - drift[1.0][:n])) < 0.01 * np.max(np.abs(drift[1.0]))
