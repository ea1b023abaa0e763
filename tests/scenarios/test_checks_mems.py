"""scenarios/checks/mems.py: every MEMS resonator check passes with its derived tolerance."""

from __future__ import annotations

import numpy as np
import pytest

from gyrobench.scenarios.checks.core import Check
from gyrobench.scenarios.checks.mems import checks

EXPECTED_IDS = {
    "mems.brownian_arw",
    "mems.low_rate_scale_factor",
    "mems.quadrature_rejection",
    "mems.rate_authority",
    "mems.slow_flow_vs_full",
    "mems.drive_amplitude",
    "mems.sense_envelope_saturated",
    "mems.slow_flow_noise_vs_full",
    "mems.zero_rate_continuity",
    "mems.g_sensitivity",
    "mems.open_loop_scale_factor",
    "mems.open_loop_slow_vs_full",
    "mems.open_loop_frequency_response",
    "mems.open_loop_noise_vs_full",
    "mems.open_loop_noise_psd_vs_full",
    "mems.low_output_rate_noise",
}


@pytest.mark.slow  # about 10 s on an idle core: four full RK4 integrations with the carrier
def test_every_mems_check_passes():
    out = checks(np.random.default_rng(20261123))
    assert all(isinstance(c, Check) for c in out)
    assert {c.id for c in out} == EXPECTED_IDS
    failed = [(c.id, c.rel_error, c.tolerance) for c in out if not c.passed]
    assert not failed, failed
