"""Earth rate along a sense axis (sim/earth.py) against its closed forms."""

import math

import numpy as np
import pytest

from gyrobench.base import units
from gyrobench.sim import earth

EPS = float(np.finfo(float).eps)


def test_earth_rate_is_iers_value():
    assert earth.EARTH_RATE == 7.2921150e-5


@pytest.mark.parametrize("lat_deg", [-60.0, 0.0, 32.06, 39.9, 45.8, 89.0])
def test_north_up_east_closed_forms(lat_deg):
    phi = units.deg(lat_deg)
    om = 7.2921150e-5
    north = earth.sensed_earth_rate(phi)
    up = earth.sensed_earth_rate(phi, elevation=math.pi / 2)
    east = earth.sensed_earth_rate(phi, azimuth=math.pi / 2)
    assert abs(north - om * math.cos(phi)) <= 4 * EPS * om
    assert abs(up - om * math.sin(phi)) <= 4 * EPS * om
    assert abs(east) <= 4 * EPS * om
    assert abs(north**2 + up**2 - om**2) <= 8 * EPS * om**2


def test_table_values_to_five_figures():
    # docs/physics.md 8 table (deg/h): Beijing 11.539 / 9.648, Harbin 10.486 / 10.783
    for site, n_dh, u_dh in ((earth.BEIJING, 11.539, 9.648), (earth.HARBIN, 10.486, 10.783)):
        n, u = earth.earth_rate_components(site.latitude)
        assert round(units.to_deg_per_h(float(n)), 3) == n_dh
        assert round(units.to_deg_per_h(float(u)), 3) == u_dh


def test_azimuth_turn_is_cosine_of_amplitude_north():
    phi = earth.HARBIN.latitude
    psi = np.linspace(0, 2 * math.pi, 73)
    w = earth.sensed_earth_rate(phi, azimuth=psi)
    np.testing.assert_allclose(
        w, earth.EARTH_RATE * math.cos(phi) * np.cos(psi), rtol=0, atol=8 * EPS * 1e-4
    )


def test_tilted_axis_general_form():
    phi, psi, e = 0.7, 0.3, 0.2
    u = np.array([math.cos(e) * math.sin(psi), math.cos(e) * math.cos(psi), math.sin(e)])
    w_enu = earth.EARTH_RATE * np.array([0.0, math.cos(phi), math.sin(phi)])
    got = earth.sensed_earth_rate(phi, azimuth=psi, elevation=e)
    assert abs(got - u @ w_enu) <= 8 * EPS * earth.EARTH_RATE


def test_paper_sites_from_affiliations():
    assert earth.PAPER_SITES["000"] is earth.NANJING
    assert earth.PAPER_SITES["003"] is earth.HARBIN
    assert earth.PAPER_SITES["001"] is earth.PAPER_SITES["004"] is earth.BEIJING
    for s in earth.PAPER_SITES.values():
        assert s.source


def test_bad_latitude():
    with pytest.raises(ValueError, match="latitude must be"):
        earth.sensed_earth_rate(2.0)
    with pytest.raises(ValueError, match="Site.latitude"):
        earth.Site(name="x", latitude=float("nan"))
    with pytest.raises(ValueError, match="azimuth must be finite"):
        earth.sensed_earth_rate(0.5, azimuth=float("inf"))
