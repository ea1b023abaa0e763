"""scenarios/checks_rlg_cavity.py: every check passes with its derived tolerance."""

from __future__ import annotations

import numpy as np
import pytest
from gyrobench.scenarios import checks_rlg_cavity as m
from gyrobench.scenarios.checks import Check, collect


@pytest.fixture(scope="module")
def results() -> list[Check]:
    return collect(np.random.default_rng(2026), ("gyrobench.scenarios.checks_rlg_cavity",))


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
