"""scenarios/checks/rlg_cavity.py: every check passes with its derived tolerance."""

from __future__ import annotations

import numpy as np
import pytest

from gyrobench.scenarios.checks import rlg_cavity as m
from gyrobench.scenarios.checks.core import Check, collect


@pytest.fixture(scope="module")
def results() -> list[Check]:
    return collect(np.random.default_rng(2026), ("gyrobench.scenarios.checks.rlg_cavity",))


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_ids_and_records(results):
    ids = [c.id for c in results]
    assert ids == [
        "rlg_cavity.lock_in_backscatter",
        "rlg_cavity.mode_hop_spacing",
        "rlg_cavity.mode_hop_hysteresis",
        "rlg_cavity.dead_band_width",
        "rlg_cavity.dither_random_walk",
        "rlg_cavity.no_dead_band_with_swing_dither",
    ]
    for c in results:
        assert c.derivation and c.tolerance < 0.5
        d = c.as_dict()
        assert d["id"] == c.id and d["passed"] == c.passed


@pytest.mark.parametrize("i", range(6))
def test_each_check_passes(results, i):
    c = results[i]
    assert c.passed, (c.id, c.expected, c.simulated, c.rel_error, c.tolerance)


def test_hand_r_net_matches_model():
    """The check's hand-written sum and the model's vectorized one agree (both are used)."""
    from gyrobench.sim.rlg_cavity import CavityRLGSpec

    u = CavityRLGSpec().realize(rng=np.random.default_rng(1))
    g = u.geometry
    r = complex(u.backscatter.net(3e-6, 0.3e-6, perimeter=g.perimeter, wavelength=g.wavelength))
    assert m._hand_r_net(u, 3e-6, 0.3e-6) == pytest.approx(r, rel=1e-9)


@pytest.mark.parametrize("factor", [0.9, 1.1])
def test_a_wrong_lock_in_in_the_model_fails_the_lock_in_check(monkeypatch, factor):
    """The check reads the lock-in off the simulated counts: a model whose lock-in is 10 % off
    (the closed form untouched) is caught."""
    from gyrobench.sim import rlg_cavity
    from gyrobench.sim.rlg_cavity import CavityRLGSpec

    r_unit, _, _, r_lock = np.random.default_rng(1).spawn(4)
    u = CavityRLGSpec().realize(rng=r_unit, label="check unit")
    assert m._check_lock_in(u, np.random.default_rng(5)).passed
    real = rlg_cavity.lock_in_from_backscatter
    monkeypatch.setattr(rlg_cavity, "lock_in_from_backscatter", lambda *a, **k: factor * real(*a, **k))
    c = m._check_lock_in(u, r_lock)
    assert c.tolerance < 0.03 and not c.passed, (c.rel_error, c.tolerance)
