"""The trajectory checks fail on a broken increment (the check is not a tautology)."""

from __future__ import annotations

import numpy as np

from gyrobench.scenarios.checks import trajectory


def test_every_trajectory_check_passes_with_its_reference_kind():
    got = trajectory.checks(np.random.default_rng(0))
    assert [c.id for c in got] == [
        "trajectory.coning_increments", "trajectory.coning_drift", "trajectory.coning_attitude_ode",
        "trajectory.two_sample_coning_residual", "trajectory.rocking_gravity_bessel",
    ]
    assert all(c.passed and c.validates for c in got), [c.as_dict() for c in got if not c.passed]


def test_a_midpoint_rule_fails_the_increment_check(monkeypatch):
    """Increments by the interval-midpoint rate (second order) instead of the 8-node quadrature:
    the coning increments are off by ~(w T)^2/24 of themselves, far beyond the rounding tolerance
    (the z drift, a constant rate, stays exact under any rule)."""
    from gyrobench.sim import trajectory as traj

    real = traj.increments

    def midpoint(motion, fs, *, site=None, chunk=1 << 15):
        inc = real(motion, fs, site=site, chunk=chunk)
        t = (np.arange(len(inc.dtheta)) + 0.5) / fs
        _, w, _, _ = motion.state(t)
        return traj.Increments(fs=inc.fs, dtheta=w / fs, dv=inc.dv, attitude=inc.attitude, velocity=inc.velocity)

    monkeypatch.setattr(traj, "increments", midpoint)
    got = {c.id: c for c in trajectory.checks(np.random.default_rng(0))}
    assert not got["trajectory.coning_increments"].passed
    assert got["trajectory.coning_drift"].passed
