"""src/gyrobench/base/validate.py: one line naming the parameter, the constraint and the value, per helper."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gyrobench.base import validate as v
from gyrobench.sim import mems_full


def test_field_helpers_name_owner_field_constraint_and_value():
    assert v.real_field("Dither", "frequency", np.float32(2.5)) == 2.5
    with pytest.raises(TypeError, match=r"^Dither\.frequency must be a real number; got '1'$"):
        v.real_field("Dither", "frequency", "1")
    with pytest.raises(ValueError, match=r"^Dither\.frequency must be finite; got inf$"):
        v.real_field("Dither", "frequency", math.inf)
    with pytest.raises(ValueError, match=r"^Dither\.frequency must be > 0 Hz; got 0$"):
        v.positive_field("Dither", "frequency", 0, "Hz")
    with pytest.raises(ValueError, match=r"^RLG\.bias must be >= 0 rad/s; got -1e-09$"):
        v.nonneg_field("RLG", "bias", -1e-9, "rad/s")
    assert v.nonneg_field("RLG", "bias", 0, "rad/s") == 0.0


def test_nonneg_fields_checks_every_named_attribute():
    class Spec:
        a, b = 1.0, -2.0

    v.nonneg_fields("Spec", Spec(), ("a",), "m")
    with pytest.raises(ValueError, match=r"^Spec\.b must be >= 0 m; got -2\.0$"):
        v.nonneg_fields("Spec", Spec(), ("a", "b"), "m")


def test_number_where_words_the_predicate():
    assert v.number_where("Coil", "length", 3, "> 0", "m", lambda x: x > 0) == 3.0
    for bad in (True, "3", math.nan, -1.0):
        with pytest.raises(ValueError, match=r"^Coil\.length must be > 0 m; got "):
            v.number_where("Coil", "length", bad, "> 0", "m", lambda x: x > 0)


def test_nonneg_coefficient_refuses_kind_sign_and_overflowing_size():
    v.nonneg_coefficient("NoiseModel", "N", 0.0, 1e100)
    with pytest.raises(TypeError, match=r"^NoiseModel\.N must be a real number; got None$"):
        v.nonneg_coefficient("NoiseModel", "N", None, 1e100)
    with pytest.raises(ValueError, match=r"^NoiseModel\.N must be finite and >= 0; got -1$"):
        v.nonneg_coefficient("NoiseModel", "N", -1, 1e100)
    with pytest.raises(ValueError, match=r"^NoiseModel\.N must be <= 1e\+100 \(SI; "):
        v.nonneg_coefficient("NoiseModel", "N", 1e101, 1e100)


def test_mems_resonator_uses_the_shared_field_validator_with_its_message():
    """Issue 23 item 5 leftovers: mems_resonator's private _real moved here as real_field."""
    from gyrobench.sim import mems_resonator as mr

    assert not hasattr(mr, "_real")
    with pytest.raises(TypeError, match=r"^simulate_full\.duration must be a real number; got 'x'$"):
        mems_full.simulate_full(mr.MemsResonator(), 0.0, duration="x", rng=np.random.default_rng(0))  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"^operating_point\.temperature must be finite; got nan$"):
        mr.operating_point(mr.MemsResonator(), float("nan"))
