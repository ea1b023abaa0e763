"""Independent segments through the device interface: an (n, k) ``true_rate``.

:meth:`MemsResonator.simulate` runs the k columns in one slow-flow call (a rate table's dwells,
each from its own equilibrium) and returns them one after another; the other models refuse
columns in one line.
"""

from __future__ import annotations

import numpy as np
import pytest

from gyrobench.base import units
from gyrobench.sim.fog_loop import ClosedLoopFOG
from gyrobench.sim.mems_resonator import MemsResonator
from gyrobench.sim.mems_slow_flow import slow_flow
from gyrobench.sim.sensor import Environment

FS = 200.0


def _columns(n: int = 400) -> np.ndarray:
    w = units.deg_per_s(np.array([-100.0, 0.0, 250.0]))
    return np.ascontiguousarray(np.broadcast_to(w, (n, w.size)))


def test_segments_are_the_columns_of_one_slow_flow_call_dwell_after_dwell():
    unit, col, temp = MemsResonator(), _columns(), units.celsius(30.0)
    rec = unit.simulate(Environment(col.shape[0] / FS, true_rate=col, temperature=temp), fs=FS,
                        rng=np.random.default_rng(7))
    direct = slow_flow(unit, col, fs=FS, rng=np.random.default_rng(7), temperature=temp).output
    assert rec.metadata["segments"] == 3
    np.testing.assert_array_equal(rec["output"], direct.T.reshape(-1))
    np.testing.assert_array_equal(rec.truth["true_rate"].data, col.T.reshape(-1))


def test_segments_need_a_constant_temperature():
    col = _columns()
    ramp = np.linspace(300.0, 301.0, col.shape[0])
    with pytest.raises(ValueError, match="temperature must be constant for independent segments"):
        MemsResonator().simulate(Environment(col.shape[0] / FS, true_rate=col, temperature=ramp), fs=FS,
                                 rng=np.random.default_rng(0))


def test_a_model_without_segments_refuses_columns_in_one_line():
    col = _columns()
    with pytest.raises(ValueError, match=r"true_rate must be 1-D for this model .*got shape \(400, 3\)"):
        ClosedLoopFOG().simulate(Environment(col.shape[0] / FS, true_rate=col), fs=FS, rng=np.random.default_rng(0))
