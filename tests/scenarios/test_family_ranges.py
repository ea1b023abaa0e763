"""A device family's parameters and fixed values validate from their declarations (base.ranges).

A :class:`~gyrobench.scenarios.maps.family.Parameter` is checked by
:func:`gyrobench.base.ranges.validate` (its ``range`` a FieldRange and its ``scale`` one of its
Literal values, from the annotations; its named constraints), and a
:class:`~gyrobench.scenarios.maps.family.Family` refuses a parameter range that leaves the paper
Config's own declared range of that field or is in another unit.
"""

from __future__ import annotations

import dataclasses

import pytest

from gyrobench.base.ranges import FieldRange
from gyrobench.scenarios.maps.family import Family, Fixed, Parameter
from gyrobench.scenarios.papers.p004_rlg_thermal.family import FAMILY


def _param(**kw):
    base = dict(field="x", range=FieldRange(0.0, 1.0, "1"), scale="linear", source="STATED", label="x")
    return Parameter(**{**base, **kw})


@pytest.mark.parametrize(
    ("kw", "error", "phrase"),
    [
        (dict(range=FieldRange(1.0, 0.0, "1")), ValueError, "Parameter.range of 'x' needs finite low < high"),
        (dict(scale="log"), ValueError, "Parameter.scale of 'x': a log scale needs range.low > 0; got 0.0"),
        (dict(scale="cubic"), ValueError, "Parameter.scale must be one of ['linear', 'log']; got 'cubic'"),
        (dict(range=(0.0, 1.0)), TypeError, "Parameter.range must be a FieldRange; got tuple"),
        (dict(source=" "), ValueError, "Parameter.source of 'x' must give the range's source"),
    ],
)
def test_a_parameter_refuses_in_one_line(kw, error, phrase):
    with pytest.raises(error) as err:
        _param(**kw)
    assert str(err.value).startswith(phrase) and "\n" not in str(err.value)


def test_a_fixed_value_needs_its_source():
    with pytest.raises(ValueError, match="Fixed.source of 'y' must give"):
        Fixed(field="y", source="")


def test_a_family_range_must_lie_in_the_configs_declared_range_and_unit():
    wide = dataclasses.replace(FAMILY.parameters[0], range=FieldRange(1e-6, 3.0, "1"))
    with pytest.raises(ValueError, match=r"Family.parameters: dissipative range \[1e-06, 3\] 1 must lie in"):
        dataclasses.replace(FAMILY, parameters=(wide, *FAMILY.parameters[1:]))
    other_unit = dataclasses.replace(FAMILY.parameters[1], range=FieldRange(0.0066, 6.6, "deg/h/uA"))
    with pytest.raises(ValueError, match="langmuir_deg_h_per_ma range"):
        dataclasses.replace(FAMILY, parameters=(FAMILY.parameters[0], other_unit, *FAMILY.parameters[2:]))
    assert isinstance(dataclasses.replace(FAMILY), Family)
