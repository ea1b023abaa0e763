"""Tests of sim.fog2d: the FOG on the (r, z) coil records with the layout of every FOG recording."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from gyrobench.base import units
from gyrobench.sim import coil2d
from gyrobench.sim.environment import Ramp, Soak, thermal_profile
from gyrobench.sim.fog2d import FOG2DSpec, FOG2DUnit, TemperatureSensorSpec
from gyrobench.sim.fog_loop import sagnac_scale_factor
from gyrobench.sim.sensor import Environment

PROFILE = thermal_profile(
    units.celsius(-10.0),
    [Soak(duration=1800.0), Ramp(target=units.celsius(40.0), rate=1 / 60), Soak(duration=1800.0)],
)
SPEC = FOG2DSpec(coil=coil2d.Coil2DSpec(grid_pack_r=4, grid_pack_z=4))
ENV = Environment(PROFILE.duration, temperature=PROFILE)


def test_recording_layout_and_sum():
    unit = SPEC.realize(rng=np.random.default_rng(0))
    rec = unit.simulate(ENV, fs=0.1, rng=np.random.default_rng(1))
    for ch in (
        "output",
        "coil_temperature",
        "truth/true_rate",
        "detail/thermal_drift",
        "detail/shupe",
        "detail/txdt_product",
        "detail/noise",
        "truth/scale_factor_error",
    ):
        assert len(rec[ch]) == len(rec["output"])
    np.testing.assert_allclose(
        rec["detail/thermal_drift"], rec["detail/shupe"] + rec["detail/txdt_product"]
    )
    total = (
        rec["truth/true_rate"]
        + rec["truth/scale_factor_error"]
        + rec["detail/thermal_drift"]
        + rec["detail/noise"]
    )
    np.testing.assert_allclose(rec["output"], total, rtol=0, atol=1e-18)


def test_scale_factor_uses_the_mapped_fibre():
    unit = FOG2DUnit(spec=SPEC, coil=coil2d.Coil2D(spec=SPEC.coil))
    fm = unit.coil.fibre()
    assert unit.scale_factor == pytest.approx(sagnac_scale_factor(fm.length, fm.diameter, 1550e-9))


def test_deterministic_in_seed():
    a = SPEC.realize(rng=np.random.default_rng(4)).simulate(ENV, fs=0.1, rng=np.random.default_rng(5)
    )
    b = SPEC.realize(rng=np.random.default_rng(4)).simulate(ENV, fs=0.1, rng=np.random.default_rng(5)
    )
    np.testing.assert_array_equal(a["output"], b["output"])
    np.testing.assert_array_equal(a["coil_temperature"], b["coil_temperature"])


def test_bad_input():
    with pytest.raises(ValueError, match="sensor.location"):
        FOG2DSpec(sensor=TemperatureSensorSpec(location="spool"))
    with pytest.raises(ValueError, match="thermal_step"):
        FOG2DSpec(thermal_step=0.0)
    unit = FOG2DUnit(spec=SPEC, coil=coil2d.Coil2D(spec=SPEC.coil))
    with pytest.raises(ValueError, match="fs"):
        unit.simulate(ENV, fs=0.0, rng=np.random.default_rng(0))
    with pytest.raises(TypeError, match="rng"):
        unit.simulate(ENV, fs=1.0, rng=3)
    with pytest.raises(TypeError, match="PiecewiseLinear"):
        unit.thermal_response([0, 1])


def test_the_output_is_the_closed_loop_fogs():
    # issue 17: one FOG class; the coil's thermal term is the loop's nonreciprocal input
    from gyrobench.sim.fog_loop import ClosedLoopFOG

    unit = SPEC.realize(rng=np.random.default_rng(2))
    assert isinstance(unit.fog, ClosedLoopFOG)
    fm = unit.coil.fibre()
    assert unit.fog.loop.length == fm.length and unit.fog.loop.diameter == fm.diameter
    rec = unit.simulate(replace(ENV, true_rate=1e-3), fs=0.1, rng=np.random.default_rng(3)
    )
    run = unit.thermal_response(PROFILE)
    t = rec.time + 5.0  # block centres
    np.testing.assert_allclose(
        rec["detail/thermal_drift"], np.interp(t, run.t, run.shupe + run.product), atol=1e-20
    )
    np.testing.assert_array_equal(rec["detail/thermal_drift"], rec["truth/nonreciprocal"])
    np.testing.assert_allclose(
        rec["detail/noise"], rec["truth/optical_noise"] + rec["truth/ieee_noise"], atol=0
    )
    # SF(T)/SF0 = (1 + alpha_D dT_coil)^2 / (1 + alpha_lambda dT_housing) at the true rate
    dc = rec["inputs/coil_mean_temperature"] - SPEC.scale_factor_ref_temperature
    ds = rec["inputs/housing_temperature"] - SPEC.scale_factor_ref_temperature
    a_d, a_l = unit.fog.diameter_tempco, SPEC.wavelength_tempco
    ratio = (1 + a_d * dc) ** 2 / (1 + a_l * ds)
    np.testing.assert_allclose(
        rec["truth/scale_factor_error"], 1e-3 * (ratio - 1), rtol=1e-9, atol=1e-22
    )
    # the white noise is the optical budget's ARW (not an IEEE-952 N term)
    assert rec.metadata["arw_rad_per_sqrt_s"] == pytest.approx(
        unit.fog.loop.arw(SPEC.optics), rel=1e-12
    )


def test_diameter_tempco_is_the_coils_hoop_expansion():
    from gyrobench.sim.fog2d import coil_diameter_tempco

    coil = coil2d.Coil2D(spec=SPEC.coil)
    fm = coil.fibre()
    b = fm.bonded
    h = SPEC.coil.hoop_strain_rate(fm.r[b], SPEC.coil.t_ref)
    want = float(np.sum(h * fm.ds[b]) / np.sum(fm.ds[b]))
    assert coil_diameter_tempco(SPEC.coil) == pytest.approx(want, rel=1e-12)
    assert FOG2DUnit(spec=SPEC, coil=coil).fog.diameter_tempco == pytest.approx(want, rel=1e-12)
    fixed = FOG2DSpec(coil=SPEC.coil, diameter_tempco=7e-6)
    assert FOG2DUnit(spec=fixed, coil=coil).fog.diameter_tempco == 7e-6


def test_earth_rate_follows_the_axis():
    coil = coil2d.Coil2D(spec=SPEC.coil)
    east = FOG2DUnit(spec=SPEC, coil=coil).fog  # default: horizontal east at Harbin
    assert abs(east.earth_rate) < 1e-19
    north = FOG2DUnit(spec=FOG2DSpec(coil=SPEC.coil, azimuth=0.0), coil=coil).fog
    assert units.to_deg_per_h(north.earth_rate) == pytest.approx(
        15.041 * np.cos(np.radians(45.75)), abs=0.01
    )
