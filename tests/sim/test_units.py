"""Unit conversions: closed-form values from docs/physics.md section 0 and round trips."""

import math

import numpy as np
import pytest

from gyrobench.base import units


@pytest.mark.parametrize(
    ("fn", "value", "expected"),
    [
        (units.deg_per_h, 1.0, math.pi / 180 / 3600),
        (units.arcsec, 1.0, math.pi / 180 / 3600),
        (units.deg_per_sqrt_h, 1.0, math.pi / 180 / 60),
        (units.deg_per_h_per_sqrt_h, 1.0, math.pi / 180 / 3600 / 60),
        (units.deg_per_h2, 1.0, math.pi / 180 / 3600**2),
        (units.celsius, 0.0, 273.15),
        (units.g, 1.0, 9.80665),
        (units.ppm, 1.0, 1e-6),
    ],
)
def test_closed_form_values(fn, value, expected):
    assert fn(value) == pytest.approx(expected, rel=1e-12)


def test_physics_md_printed_values():
    # docs/physics.md section 0 prints these to 5 significant digits
    assert units.deg_per_h(1.0) == pytest.approx(4.8481e-6, rel=1e-4)
    assert units.deg_per_sqrt_h(1.0) == pytest.approx(2.9089e-4, rel=1e-4)
    assert units.deg_per_h_per_sqrt_h(1.0) == pytest.approx(8.0802e-8, rel=1e-4)
    assert units.deg_per_h2(1.0) == pytest.approx(1.3467e-9, rel=1e-4)


@pytest.mark.parametrize(
    ("to_si", "from_si"),
    [
        (units.deg, units.to_deg),
        (units.arcsec, units.to_arcsec),
        (units.deg_per_s, units.to_deg_per_s),
        (units.deg_per_h, units.to_deg_per_h),
        (units.deg_per_sqrt_h, units.to_deg_per_sqrt_h),
        (units.deg_per_h_per_sqrt_h, units.to_deg_per_h_per_sqrt_h),
        (units.deg_per_h2, units.to_deg_per_h2),
        (units.celsius, units.to_celsius),
        (units.g, units.to_g),
        (units.ppm, units.to_ppm),
    ],
)
def test_round_trip_scalar_and_array(to_si, from_si):
    x = np.array([-3.5, 0.0, 1e-3, 7.25e4])
    np.testing.assert_allclose(from_si(to_si(x)), x, rtol=1e-12, atol=1e-12)
    assert from_si(to_si(2.5)) == pytest.approx(2.5, rel=1e-12)


def test_identity_deg_per_h_is_arcsec_per_s():
    # docs/physics.md 0: rate in deg/h equals angle in arcsec per second
    assert units.deg_per_h(1.0) == pytest.approx(units.arcsec(1.0), rel=1e-15)


def test_rate_to_si_and_unknown_unit():
    assert units.rate_to_si(1.0, "deg/s") == pytest.approx(math.pi / 180, rel=1e-15)
    with pytest.raises(ValueError, match=r"rate unit must be one of .*got 'furlong/fortnight'"):
        units.rate_to_si(1.0, "furlong/fortnight")


@pytest.mark.parametrize(
    ("text", "seconds"), [("10h", 36000.0), ("30min", 1800.0), ("600s", 600.0), ("2.5", 2.5), ("1e3ms", 1.0)]
)
def test_parse_duration(text, seconds):
    assert units.parse_duration(text) == seconds


@pytest.mark.parametrize("text", ["", "ten hours", "-5s", "0s", "5 parsecs"])
def test_parse_duration_rejects(text):
    with pytest.raises(ValueError, match="duration must be"):
        units.parse_duration(text)


def test_coefficient_to_field():
    assert units.coefficient_to_field("R", units.deg_per_h2(0.3)) == pytest.approx(0.3, rel=1e-12)
    assert units.coefficient_to_field("B", None) is None
    with pytest.raises(ValueError, match="coefficient name must be one of"):
        units.coefficient_to_field("X", 1.0)
