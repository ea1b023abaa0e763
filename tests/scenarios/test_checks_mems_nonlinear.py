"""scenarios/checks/mems_nonlinear.py: the nonlinear mechanism's closed-form checks pass, fast, and can fail."""

from __future__ import annotations

import numpy as np
import pytest

from gyrobench.scenarios.checks import mems_nonlinear as cmn
from gyrobench.scenarios.checks.core import CHECK_MODULES, Check

EXPECTED_IDS = [
    "mems.nonlinear_small_signal_scale_factor",
    "mems.nonlinear_cubic_coefficient",
    "mems.nonlinear_monotone_3600",
    "mems.nonlinear_no_clip_3600",
]


def test_every_check_passes_and_is_registered():
    out = cmn.checks(np.random.default_rng(0))
    assert all(isinstance(c, Check) for c in out)
    assert [c.id for c in out] == EXPECTED_IDS
    failed = [(c.id, c.rel_error, c.tolerance) for c in out if not c.passed]
    assert not failed, failed
    assert "gyrobench.scenarios.checks.mems_nonlinear" in CHECK_MODULES


def test_no_clip_check_fails_on_a_device_that_clips_inside_the_range(monkeypatch):
    """The check can fail: the rebalance DAC of the "calibrated" variant (v_max solved for 15.71 %)
    clamps near 3000 deg/s, and its flat output is far outside the tolerance."""
    from gyrobench.scenarios.papers.p001_mems_scale_factor import config as cfg

    real = cfg.Config
    monkeypatch.setattr(cfg, "Config", lambda: real(variant="calibrated"))
    c = cmn._no_clip()
    assert not c.passed and c.rel_error > 100 * c.tolerance


def test_rng_must_be_a_generator():
    with pytest.raises(TypeError, match="rng must be a numpy.random.Generator"):
        cmn.checks(0)  # type: ignore[arg-type]
