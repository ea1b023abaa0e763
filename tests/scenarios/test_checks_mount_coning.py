"""The mount-coning check module: every check passes on the model and fails on a broken one."""

from __future__ import annotations

import numpy as np
import pytest

from gyrobench.scenarios.checks import mount_coning as checks_mount_coning
from gyrobench.sim import mount_coning


def test_every_check_passes_within_a_second():
    checks_mount_coning.checks(np.random.default_rng(0))  # imports (scipy) are not the checks' time
    out = checks_mount_coning.checks(np.random.default_rng(0))
    assert [c.id for c in out] == [
        "mount_coning.rectified_bias_50hz",
        "mount_coning.rectified_bias_400hz",
        "mount_coning.rectified_bias_430hz",
        "mount_coning.rectified_bias_460hz",
        "mount_coning.rectified_bias_2000hz",
        "mount_coning.q_half_power_width",
    ]
    assert all(c.passed for c in out), [(c.id, c.rel_error, c.tolerance) for c in out if not c.passed]


def _response_with_damping_doubled(self, f):  # the damping term read as f f0 / (2 Q): Q twice too high
    f = np.asarray(f, dtype=float)
    f0 = self.frequency
    return self.compliance * f0**2 / (f0**2 - f**2 + 1j * f * f0 / (2.0 * self.quality))


@pytest.mark.parametrize("check_id", ["mount_coning.q_half_power_width", "mount_coning.rectified_bias_430hz"])
def test_a_wrong_damping_fails(monkeypatch, check_id):
    monkeypatch.setattr(mount_coning.RockingMode, "response", _response_with_damping_doubled)
    c = {c.id: c for c in checks_mount_coning.checks(np.random.default_rng(0))}[check_id]
    assert not c.passed


def test_a_flipped_commutation_sign_fails(monkeypatch):
    real = mount_coning.MountConing.rate
    monkeypatch.setattr(mount_coning.MountConing, "rate", lambda self, a, fs: -real(self, a, fs))
    out = checks_mount_coning.checks(np.random.default_rng(0))
    assert not any(c.passed for c in out if c.id.startswith("mount_coning.rectified_bias"))
