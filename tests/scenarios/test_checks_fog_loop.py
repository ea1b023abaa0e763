"""The closed-loop FOG check modules (checks_fog_loop; checks_fog_strain, split from it)."""

import numpy as np
import pytest

from gyrobench.scenarios.checks import fog_loop as checks_fog_loop
from gyrobench.scenarios.checks.core import collect

IDS = [
    "fog.optical_budget_shot",
    "fog.optical_budget_rin",
    "fog.optical_budget_johnson",
    "fog.loop_arw_optical_budget",
    "fog.loop_full_arw_optical_budget",
    "fog.loop_frequency_response",
    "fog.loop_step_response",
    "fog.loop_reset_count",
    "fog.loop_reset_rate",
    "fog.loop_v2pi_scale_factor",
    "fog.loop_blanked_reset_scale_factor",
    "fog.vibration_strain_tone",
    "fog.vibration_reduced_vs_full_loop",
    "fog.vibration_random_psd_variance",
    "fog.vibration_rectification_full_loop",
]


def test_every_check_passes_with_a_derivation():
    out = collect(np.random.default_rng(0), ("gyrobench.scenarios.checks.fog_loop",))
    assert [c.id for c in out] == IDS
    failed = [c.as_dict() for c in out if not c.passed]
    assert not failed, failed
    assert all(c.derivation and c.tolerance < 0.2 for c in out)


STRAIN_IDS = ["fog.strain_uniform_zero", "fog.strain_mode_linear", "fog.strain_kernel_exact",
              "fog.strain_reduced_vs_full_loop"]


def test_the_strain_kernel_checks_pass_in_their_own_module():
    out = collect(np.random.default_rng(0), ("gyrobench.scenarios.checks.fog_strain",))
    assert [c.id for c in out] == STRAIN_IDS
    failed = [c.as_dict() for c in out if not c.passed]
    assert not failed, failed


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_seeded_checks_are_reproducible():
    a = checks_fog_loop.checks(np.random.default_rng(5))
    b = checks_fog_loop.checks(np.random.default_rng(5))
    assert [c.simulated for c in a] == [c.simulated for c in b]


def test_exact_kernel_improves_the_agreement_with_the_full_loop():
    # the derivation reports the small-tau kernel's miss; the exact kernel must beat it by far
    import re

    from gyrobench.scenarios.checks import fog_strain as checks_fog_strain

    (ex,) = [c for c in checks_fog_strain._strain_exact_kernel() if "full_loop" in c.id]
    miss_small = float(re.search(r"misses by ([0-9.e+-]+) of", ex.derivation).group(1))
    miss_exact = (ex.simulated - ex.expected) / ex.expected
    assert miss_exact < miss_small / 100


def test_a_wrong_optical_budget_fails_its_checks(monkeypatch):
    """Each budget term off by the classic convention slips (RIN 1/dnu instead of 2/dnu, shot
    q i instead of 2 q i, Johnson 2 k T/R instead of 4 k T/R) fails its own check, not the others."""
    from gyrobench.sim.fog_optics import OpticalBudget

    real = OpticalBudget.current_psd
    for term in ("shot", "rin", "thermal"):
        def halved(self, bias_phase, wavelength, term=term):
            out = dict(real(self, bias_phase, wavelength))
            out[term] = out[term] / 2
            return out

        monkeypatch.setattr(OpticalBudget, "current_psd", halved)
        res = {c.id: c.passed for c in checks_fog_loop._optical_budget(np.random.default_rng(1))}
        name = {"shot": "shot", "rin": "rin", "thermal": "johnson"}[term]
        assert res == {f"fog.optical_budget_{n}": n != name for n in ("shot", "rin", "johnson")}, term
    monkeypatch.setattr(OpticalBudget, "current_psd", real)
