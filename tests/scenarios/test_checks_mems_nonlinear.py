"""scenarios/checks/mems_nonlinear.py: the stiffening and read-out checks pass, declare their kinds, and can fail."""

from __future__ import annotations

import numpy as np
import pytest

from gyrobench.scenarios.checks import mems_nonlinear as cmn
from gyrobench.scenarios.checks.core import CHECK_MODULES, Check

EXPECTED = {
    "mems.sense_stiffening_full_ode": "second method",
    "mems.readout_slow_vs_full_bend": "second method",
    "mems.readout_pickoff_small_amplitude": "closed form",
    "mems.nonlinear_cubic_coefficient": "consistency",
}


@pytest.fixture(scope="module")
def out():
    return cmn.checks(np.random.default_rng(0))


def test_every_check_passes_and_is_registered(out):
    assert all(isinstance(c, Check) for c in out)
    assert {c.id: c.kind for c in out} == EXPECTED
    failed = [(c.id, c.rel_error, c.tolerance) for c in out if not c.passed]
    assert not failed, failed
    assert "gyrobench.scenarios.checks.mems_nonlinear" in CHECK_MODULES


def test_the_stiffening_check_fails_when_the_harmonic_balance_drops_the_cubic_term(monkeypatch):
    """A model whose amplitude ignores k3 (the linear response) is far outside the tolerance at 2 Omega_d."""
    from gyrobench.sim import mems_nonlinear

    def linear(self, rate):
        f = np.abs(self.coriolis_force(rate))
        return np.sign(rate) * f / np.hypot(self.detuning_stiffness, self.damping * self.drive_omega)

    monkeypatch.setattr(mems_nonlinear.DuffingSense, "amplitude", linear)
    c = cmn._stiffening_ode()
    assert not c.passed and c.rel_error > 10 * c.tolerance


def test_the_readout_check_fails_on_a_chain_without_its_rail(monkeypatch):
    """The slow flow with the rail's describing function replaced by 1 (no clipping) misses the bend."""
    from gyrobench.sim import mems_readout

    monkeypatch.setattr(mems_readout.SenseChain, "describing_gain", lambda self, a: np.ones_like(np.asarray(a)))
    c = cmn._readout_bend()
    assert not c.passed and c.rel_error > 100 * c.tolerance


def test_rng_must_be_a_generator():
    with pytest.raises(TypeError, match="rng must be a numpy.random.Generator"):
        cmn.checks(0)  # type: ignore[arg-type]
