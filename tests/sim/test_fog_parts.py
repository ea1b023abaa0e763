"""The FOG pieces paper 003's (r, z) FOG uses outside the coil: the Sagnac scale factor
(sim.fog_loop) and the logged temperature sensor (sim.fog2d)."""

from __future__ import annotations

import math
import zlib

import numpy as np
import pytest
from scipy import stats

from gyrobench.sim.fog2d import TemperatureSensorSpec
from gyrobench.sim.fog_loop import sagnac_scale_factor


@pytest.fixture
def rng(request) -> np.random.Generator:
    key = zlib.crc32(request.node.nodeid.encode())
    return np.random.default_rng([20261121, key])


def test_sagnac_scale_factor_printed_value():
    """Lefevre's SF = 2 pi L D/(lambda c) for L = 1000 m, D = 0.1 m, 1550 nm: 1.352 s printed in
    docs/physics.md 3.1; c is the SI's exact 299 792 458 m/s."""
    sf = sagnac_scale_factor(1000.0, 0.1, 1550e-9)
    assert sf == pytest.approx(1.352, abs=0.0005)
    assert sf == pytest.approx(2 * math.pi * 100.0 / (1550e-9 * 299_792_458.0), rel=1e-15)


@pytest.mark.parametrize("bad", [0.0, -1.0, math.inf, math.nan])
def test_sagnac_scale_factor_refuses_bad_geometry(bad):
    with pytest.raises(ValueError, match="length must be a finite number > 0 m"):
        sagnac_scale_factor(bad, 0.1, 1550e-9)


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


def test_bad_sensor_location():
    with pytest.raises(ValueError, match=r"location must be one of"):
        TemperatureSensorSpec(location="lid")
