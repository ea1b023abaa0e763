"""Tests of sim/trajectory.py: the exact increments of known motions against their closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.special import j0

from gyrobench.sim.earth import EARTH_RATE, Site, normal_gravity
from gyrobench.sim.trajectory import (
    ConingMotion,
    RockingMotion,
    Segment,
    SegmentedMotion,
    increments,
    rotation_matrix,
    segments_from_table,
)

NO_EARTH = Site(earth_rotation=False)
EPS = np.finfo(float).eps


def test_wgs84_normal_gravity_at_the_equator_and_the_pole():
    # NIMA TR8350.2 (2000) table 3.4: gamma_e 9.7803253359, gamma_p 9.8321849378 m/s^2
    assert normal_gravity(0.0) == pytest.approx(9.7803253359, abs=1e-10)
    assert normal_gravity(math.pi / 2 - 1e-12) == pytest.approx(9.8321849378, abs=1e-9)
    assert normal_gravity(0.0, 1000.0) == pytest.approx(9.7803253359 - 3.086e-3, abs=1e-10)


def test_a_level_block_at_rest_senses_the_earths_rate_and_gravity():
    """Exact to rounding over 5e4 samples: each interval is [0, 1/fs] in its own time, so its length
    does not carry the rounding of t (which at t = 500 s would be 1e-11 of it)."""
    phi = math.radians(45.75)
    site = Site(latitude=phi)
    inc = increments(SegmentedMotion((Segment(duration=500.0),)), 100.0, site=site)
    want_w = EARTH_RATE * np.array([math.cos(phi), 0.0, -math.sin(phi)])
    want_f = np.array([0.0, 0.0, -normal_gravity(phi)])
    np.testing.assert_allclose(inc.rate, np.broadcast_to(want_w, inc.rate.shape), rtol=1e-13, atol=1e-25)
    np.testing.assert_allclose(inc.specific_force, np.broadcast_to(want_f, inc.rate.shape), rtol=1e-14)


def test_coning_increments_equal_the_integrals_of_the_closed_form_rate():
    """Over [t, t + T]: dtheta = sin(b) [cos w t1 - cos w t0, sin w t1 - sin w t0, 0] - w (1 - cos b) T z."""
    beta, f, fs = 0.01, 10.0, 200.0
    inc = increments(ConingMotion(half_angle=beta, frequency=f, duration=1.0), fs, site=NO_EARTH)
    w, n = 2 * math.pi * f, len(inc.dtheta)
    t0 = np.arange(n) / fs
    t1 = t0 + 1 / fs
    want = np.stack(
        [math.sin(beta) * (np.cos(w * t1) - np.cos(w * t0)), math.sin(beta) * (np.sin(w * t1) - np.sin(w * t0)),
         np.full(n, -w * (1 - math.cos(beta)) / fs)], axis=-1)
    # rounding: the phases w t (up to w x 1 s = 63 rad) carry eps w t each, so both sides' cosines
    # and sines are good to ~eps w t; times sin(b) and a factor 8 for the two sides' operations
    np.testing.assert_allclose(inc.dtheta, want, rtol=0, atol=8 * EPS * w * 1.0 * math.sin(beta))


def test_the_coning_rate_integrates_to_the_coning_attitude():
    """A second method: the quaternion kinematics of the closed-form rate, integrated by an ODE
    solver, reach the attitude exp([a(t) x]) the motion defines (rtol 1e-12 of the solver)."""
    beta, f = 0.3, 2.0
    m = ConingMotion(half_angle=beta, frequency=f, duration=1.0)

    def rhs(t, c_flat):
        c = c_flat.reshape(3, 3)
        _, w, _, _ = m.state(np.array([t]))
        wx = np.array([[0, -w[0, 2], w[0, 1]], [w[0, 2], 0, -w[0, 0]], [-w[0, 1], w[0, 0], 0]])
        return (c @ wx).ravel()

    c0 = m.state(np.array([0.0]))[0][0]
    sol = solve_ivp(rhs, (0.0, 1.0), c0.ravel(), rtol=1e-12, atol=1e-13, t_eval=[0.25, 0.5, 1.0])
    for k, t in enumerate(sol.t):
        np.testing.assert_allclose(sol.y[:, k].reshape(3, 3), m.state(np.array([t]))[0][0], atol=1e-9)


def test_the_two_sample_coning_correction_leaves_the_published_residual():
    """The increments carry the coning: with the two-sample correction phi = d1 + d2 + (2/3) d1 x d2
    (Miller 1983) the residual per 2T interval is w b^2 h (w h)^4 / 960 (h = 2T; Ignagni, J. Guid.
    Control Dyn. 13(2) 363 (1990), table 1), within 5 % at w h = 0.63, the size of the series' next
    term; uncorrected, the error is ~200x larger."""
    beta, f, fs = 0.01, 10.0, 200.0
    inc = increments(ConingMotion(half_angle=beta, frequency=f, duration=1.0), fs, site=NO_EARTH)
    d1, d2 = inc.dtheta[0::2], inc.dtheta[1::2]
    phi = d1 + d2 + (2 / 3) * np.cross(d1, d2)
    c = inc.attitude
    exact = np.array([_log(c[2 * i].T @ c[2 * i + 2]) for i in range(len(d1))])
    w, h = 2 * math.pi * f, 2 / fs
    residual = np.mean(np.abs(phi - exact)[:, 2])
    assert residual == pytest.approx(w * beta**2 * h * (w * h) ** 4 / 960, rel=0.05)
    assert np.mean(np.abs(d1 + d2 - exact)[:, 2]) > 100 * residual


def _log(c):
    th = math.acos(max(-1.0, min(1.0, (np.trace(c) - 1) / 2)))
    v = np.array([c[2, 1] - c[1, 2], c[0, 2] - c[2, 0], c[1, 0] - c[0, 1]])
    return v * (0.5 if th < 1e-12 else th / (2 * math.sin(th)))


def test_rocking_velocity_increments_over_whole_periods_follow_bessel():
    """Gravity rotating in the body y-z plane: over a whole period dv = [0, 0, -g T J0(A)].

    Eight samples a period (w T = pi/4, where the quadrature's bound is 1e-16), summed per period."""
    amp, f = 0.4, 5.0
    site = Site(earth_rotation=False)
    inc = increments(RockingMotion(amplitude=amp, frequency=f, duration=2.0), 8 * f, site=site)
    g, period = site.gravity, 1 / f
    dv = inc.dv.reshape(-1, 8, 3).sum(axis=1)
    dth = inc.dtheta.reshape(-1, 8, 3).sum(axis=1)
    np.testing.assert_allclose(dv[:, 2], -g * period * j0(amp), rtol=1e-13)
    np.testing.assert_allclose(dv[:, :2], 0.0, atol=1e-13 * g * period)
    np.testing.assert_allclose(dth, 0.0, atol=1e-14)


def test_segments_turn_exactly_and_integrate_across_their_breakpoints():
    """A 9 s turn at 10 deg/s off the sample grid (fs 7 Hz) ends at exactly 90 deg of heading;
    the angle increments sum to the turn; a level acceleration is sensed as f = a - g."""
    r = math.radians(10.0)
    m = SegmentedMotion((Segment(duration=1.05), Segment(duration=9.0, rate=[0, 0, r]),
                         Segment(duration=0.95, acceleration=[2.0, 0.0, 0.0])))
    inc = increments(m, 7.0, site=NO_EARTH)
    np.testing.assert_allclose(m.state(np.array([10.05]))[0][0], rotation_matrix([0, 0, math.pi / 2]), atol=1e-15)
    assert inc.dtheta[:, 2].sum() == pytest.approx(math.pi / 2, rel=1e-14)
    last = inc.specific_force[-1]
    heading = rotation_matrix([0, 0, math.pi / 2]).T
    np.testing.assert_allclose(last, heading @ np.array([2.0, 0.0, -NO_EARTH.gravity]), rtol=1e-13)


def test_chunking_changes_no_bit():
    m = ConingMotion(half_angle=0.2, frequency=3.0, duration=1.0)
    a, b = increments(m, 333.0, chunk=7), increments(m, 333.0)
    np.testing.assert_array_equal(a.dtheta, b.dtheta)
    np.testing.assert_array_equal(a.dv, b.dv)


@pytest.mark.parametrize(
    ("row", "match"),
    [
        ({"duration_s": 1.0, "rate_dps": [1, 2]}, r"motion\[0\].rate_dps must be 3 finite numbers \[deg/s\]"),
        ({"rate_dps": [0, 0, 1]}, r"motion\[0\] needs duration_s \[s\]"),
        ({"duration_s": -1.0}, r"Segment.duration must be > 0 s; got -1.0"),
        ({"duration_s": 1.0, "spin": 3}, r"motion\[0\] has unknown keys \['spin'\]"),
        ({"duration_s": 1.0, "acceleration_mps2": [0, 0, 1e9]}, r"acceleration_mps2 must be within \+-1e5 m/s\^2"),
    ],
)
def test_a_bad_motion_row_is_refused_in_one_line(row, match):
    with pytest.raises(ValueError, match=match):
        segments_from_table([row])


def test_site_ranges():
    with pytest.raises(ValueError, match=r"^Site.latitude must be \[-1.5708, 1.5708\] rad; got 2.0$"):
        Site(latitude=2.0)
    with pytest.raises(ValueError, match=r"the transport rate is not defined at a pole"):
        Site(latitude=math.pi / 2).transport_rate_n(np.zeros((1, 3)))
    with pytest.raises(ValueError, match=r"^Site.height must be \[-10000, 100000\] m; got 1000000.0$"):
        Site(height=1e6)


def test_a_sampled_attitude_gives_the_motions_increments_at_fourth_order():
    """Coning sampled at 500 and 1000 Hz as quaternions: the splines' increments at 100 Hz match the
    closed form within the cubic spline's derivative bound 2 h^3 |q''''| / 24 (Hall & Meyer, J.
    Approx. Theory 16, 105 (1976)) and converge as h^4 (the increments integrate the h^3 error of
    the derivative over each interval): the observed order between 3.5 and 4.5."""
    from scipy.spatial.transform import Rotation

    from gyrobench.sim.trajectory import SampledMotion

    beta, f = 0.1, 2.0
    m = ConingMotion(half_angle=beta, frequency=f, duration=2.0)
    ref = increments(m, 100.0, site=NO_EARTH)
    w = 2 * math.pi * f
    errors = []
    for h in (2e-3, 1e-3):
        t = np.arange(0.0, 2.0 + h / 2, h)
        q = Rotation.from_matrix(m.state(t)[0]).as_quat()[:, [3, 0, 1, 2]]
        sampled = SampledMotion(t, q, np.zeros((len(t), 3)))
        err = np.max(np.abs(increments(sampled, 100.0, site=NO_EARTH).dtheta - ref.dtheta))
        assert err <= (1 / 100) * 2 * h**3 * w**4 * math.sin(beta / 2) / 24, (h, err)
        errors.append(err)
    assert 3.5 <= math.log2(errors[0] / errors[1]) <= 4.5, errors


def test_a_bad_sampled_motion_is_refused():
    from gyrobench.sim.trajectory import SampledMotion

    t = np.arange(5.0)
    with pytest.raises(ValueError, match=r"must be unit quaternions"):
        SampledMotion(t, np.full((5, 4), 2.0), np.zeros((5, 3)))
    with pytest.raises(ValueError, match=r"strictly increasing times \[s\] from 0"):
        SampledMotion(t[::-1], np.tile([1.0, 0, 0, 0], (5, 1)), np.zeros((5, 3)))
