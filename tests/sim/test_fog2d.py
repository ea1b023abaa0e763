"""Tests of sim.fog2d: the FOG on the (r, z) coil keeps sim.fog's recording layout."""

from __future__ import annotations

import numpy as np
import pytest
from gyrobench.sim import coil2d, units
from gyrobench.sim.environment import Ramp, Soak, thermal_profile
from gyrobench.sim.fog import TemperatureSensorSpec, sagnac_scale_factor
from gyrobench.sim.fog2d import FOG2DSpec, FOG2DUnit

PROFILE = thermal_profile(
    units.celsius(-10.0),
    [Soak(duration=1800.0), Ramp(target=units.celsius(40.0), rate=1 / 60), Soak(duration=1800.0)],
)
SPEC = FOG2DSpec(coil=coil2d.Coil2DSpec(grid_pack_r=4, grid_pack_z=4))


def test_recording_layout_and_sum():
    unit = SPEC.realize(rng=np.random.default_rng(0))
    rec = unit.simulate(PROFILE, fs=0.1, rng=np.random.default_rng(1))
    for ch in (
        "rate",
        "coil_temperature",
        "truth/rate",
        "truth/thermal_drift",
        "truth/shupe",
        "truth/txdt_product",
        "truth/noise",
        "truth/scale_factor_error",
    ):
        assert len(rec[ch]) == len(rec["rate"])
    np.testing.assert_allclose(
        rec["truth/thermal_drift"], rec["truth/shupe"] + rec["truth/txdt_product"]
    )
    total = (
        rec["truth/rate"]
        + rec["truth/scale_factor_error"]
        + rec["truth/thermal_drift"]
        + rec["truth/noise"]
    )
    np.testing.assert_allclose(rec["rate"], total, rtol=0, atol=1e-18)


def test_scale_factor_uses_the_mapped_fibre():
    unit = FOG2DUnit(spec=SPEC, coil=coil2d.Coil2D(spec=SPEC.coil))
    fm = unit.coil.fibre()
    assert unit.scale_factor == pytest.approx(sagnac_scale_factor(fm.length, fm.diameter, 1550e-9))


def test_deterministic_in_seed():
    a = SPEC.realize(rng=np.random.default_rng(4)).simulate(
        PROFILE, fs=0.1, rng=np.random.default_rng(5)
    )
    b = SPEC.realize(rng=np.random.default_rng(4)).simulate(
        PROFILE, fs=0.1, rng=np.random.default_rng(5)
    )
    np.testing.assert_array_equal(a["rate"], b["rate"])
    np.testing.assert_array_equal(a["coil_temperature"], b["coil_temperature"])


def test_bad_input():
    with pytest.raises(ValueError, match="sensor.location"):
        FOG2DSpec(sensor=TemperatureSensorSpec(location="spool"))
    with pytest.raises(ValueError, match="thermal_step"):
        FOG2DSpec(thermal_step=0.0)
    unit = FOG2DUnit(spec=SPEC, coil=coil2d.Coil2D(spec=SPEC.coil))
    with pytest.raises(ValueError, match="fs"):
        unit.simulate(PROFILE, fs=0.0, rng=np.random.default_rng(0))
    with pytest.raises(TypeError, match="rng"):
        unit.simulate(PROFILE, fs=1.0, rng=3)
    with pytest.raises(TypeError, match="PiecewiseLinear"):
        unit.thermal_response([0, 1])
