"""The closed-loop FOG check module (not yet in CHECK_MODULES: the lead wires it)."""

import numpy as np
from gyrobench.scenarios import checks_fog_loop
from gyrobench.scenarios.checks import collect

IDS = [
    "fog.optical_budget_closed_form_90deg",
    "fog.optical_budget_closed_form_135deg",
    "fog.loop_arw_optical_budget",
    "fog.loop_full_arw_optical_budget",
    "fog.loop_frequency_response",
    "fog.loop_step_response",
    "fog.loop_reset_count",
    "fog.loop_reset_rate",
    "fog.loop_v2pi_scale_factor",
    "fog.loop_blanked_reset_scale_factor",
    "fog.strain_uniform_zero",
    "fog.strain_mode_linear",
    "fog.strain_kernel_exact",
    "fog.strain_reduced_vs_full_loop",
    "fog.vibration_strain_tone",
    "fog.vibration_reduced_vs_full_loop",
    "fog.vibration_random_psd_variance",
    "fog.vibration_rectification_full_loop",
]


def test_every_check_passes_with_a_derivation():
    out = collect(np.random.default_rng(0), ("gyrobench.scenarios.checks_fog_loop",))
    assert [c.id for c in out] == IDS
    failed = [c.as_dict() for c in out if not c.passed]
    assert not failed, failed
    assert all(c.derivation and c.tolerance < 0.2 for c in out)


def test_seeded_checks_are_reproducible():
    a = checks_fog_loop.checks(np.random.default_rng(5))
    b = checks_fog_loop.checks(np.random.default_rng(5))
    assert [c.simulated for c in a] == [c.simulated for c in b]


def test_exact_kernel_improves_the_agreement_with_the_full_loop():
    # the derivation reports the small-tau kernel's miss; the exact kernel must beat it by far
    import re

    (ex,) = [c for c in checks_fog_loop._strain_exact_kernel() if "full_loop" in c.id]
    miss_small = float(re.search(r"misses by ([0-9.e+-]+) of", ex.derivation).group(1))
    miss_exact = (ex.simulated - ex.expected) / ex.expected
    assert miss_exact < miss_small / 100
