"""One config system: every configuration class declares its fields and validates from the declaration.

The configuration classes are every scenario's ``Config`` with every dataclass reachable from it
(nested fields and tuples of dataclasses: the FOG loop, optics, strain modes and mount of paper
000, the MEMS population of paper 001, ...), and the profiles and parts a user builds directly
(shaker profiles, thermal program segments, datasheets and parts) and the device specs the paper
configs build (the 2-D FOG and its temperature sensor, the RLG's dither). For each:

* its ``__post_init__`` calls :func:`gyrobench.base.ranges.validate` and has no hand-written check
  left (no ``raise``, ``if``, loop or ``assert`` of its own; what it builds after validating, the
  sim model it delegates to, validates itself);
* every numeric field has a declared :class:`~gyrobench.base.ranges.FieldRange` with a unit and a
  ``why`` (what the field is and what bounds it); a text field that takes a few values has a
  :class:`~gyrobench.base.ranges.FieldChoice` or a ``Literal`` annotation;
* the configuration layer (TOML and ``--set``: :func:`gyrobench.scenarios.registry.override`) and a
  direct construction refuse a value with the same one-line message.
"""

from __future__ import annotations

import ast
import dataclasses
import inspect
import textwrap
import typing

import pytest

from gyrobench.base.ranges import Constraint, FieldChoice, FieldRange, _field_hints, field_spec
from gyrobench.scenarios import registry
from gyrobench.sim.coil2d import Coil2DSpec
from gyrobench.sim.earth import Site
from gyrobench.sim.environment import PiecewiseLinear, Ramp, Soak
from gyrobench.sim.fog2d import FOG2DSpec, FOG2DUnit, TemperatureSensorSpec
from gyrobench.sim.fog_loop import ClosedLoopFOG
from gyrobench.sim.imu import AccelerometerSpec, TriadSpec
from gyrobench.sim.mems_nonlinear import DuffingSense, RateTransfer
from gyrobench.sim.noise import GaussMarkov, NoiseModel, Sinusoid
from gyrobench.sim.parts import Datasheet, Part
from gyrobench.sim.rlg import CavityGeometry, Dither, RLGSpec, RLGUnit, TemperatureSensor, ThermalBias, TwoNodeThermal
from gyrobench.sim.rlg_cavity import Backscatter, CavityRLG, CavityRLGSpec, CavityThermal, Discharge, PathLengthControl
from gyrobench.sim.sensor import Environment
from gyrobench.sim.shaker import FixedSine, Phased, RandomVibration, SineSweep
from gyrobench.sim.trajectory import ConingMotion, RockingMotion, SampledMotion, Segment, SegmentedMotion

#: classes a user builds directly, beside the ones reachable from a scenario's Config: profiles, parts and
#: the device specs the paper configs build
PROFILES_AND_PARTS = (
    SineSweep, FixedSine, RandomVibration, Phased, Ramp, Soak, Datasheet, Part, FOG2DSpec, TemperatureSensorSpec,
    Dither,
)
#: the sim device models and their specs (FOG, MEMS, RLG, accelerometer), built directly or by the parts
SIM_SPECS = (
    ClosedLoopFOG, Coil2DSpec, FOG2DUnit, DuffingSense, RateTransfer, AccelerometerSpec,
    CavityGeometry, TwoNodeThermal, ThermalBias, TemperatureSensor, RLGUnit, RLGSpec,
    Backscatter, PathLengthControl, CavityThermal, Discharge, CavityRLG, CavityRLGSpec,
)
#: the inputs every device model takes (site, environment and its profiles, motions) and the noise model
INPUTS_AND_NOISE = (
    Site, PiecewiseLinear, Environment, TriadSpec, NoiseModel, GaussMarkov, Sinusoid,
    Segment, SegmentedMotion, ConingMotion, RockingMotion, SampledMotion,
)


def _reachable(obj: typing.Any, out: dict[type, None]) -> None:
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        if type(obj) in out:
            return
        out[type(obj)] = None
        for f in dataclasses.fields(obj):
            _reachable(getattr(obj, f.name), out)
    elif isinstance(obj, tuple):
        for v in obj:
            _reachable(v, out)


def config_classes() -> list[type]:
    out: dict[type, None] = {}
    for name in registry.available():
        _reachable(registry.get(name).Config(), out)
    for cls in PROFILES_AND_PARTS + SIM_SPECS + INPUTS_AND_NOISE:
        out[cls] = None
    return list(out)


def hand_written_checks(cls: type) -> list[str]:
    """What in ``cls.__post_init__`` is not the derived validation (:func:`findings`)."""
    return findings(textwrap.dedent(inspect.getsource(cls)))


def findings(class_source: str) -> list[str]:
    """Every raise, if, loop, try or assert in the ``__post_init__`` of the first class in
    ``class_source``, and a missing ``validate(self)`` call."""
    body = next(n for n in ast.parse(class_source).body if isinstance(n, ast.ClassDef))
    posts = [f for f in body.body if isinstance(f, ast.FunctionDef) and f.name == "__post_init__"]
    if not posts:
        return ["no __post_init__ (validate is never called)"]
    found = [
        f"line {n.lineno}: {type(n).__name__.lower()}"
        for n in ast.walk(posts[0])
        if isinstance(n, (ast.Raise, ast.If, ast.IfExp, ast.For, ast.While, ast.Assert, ast.Try))
    ]
    calls = [
        n for n in ast.walk(posts[0])
        if isinstance(n, ast.Call) and isinstance(n.func, ast.Name) and n.func.id == "validate"
        and len(n.args) == 1 and isinstance(n.args[0], ast.Name) and n.args[0].id == "self"
    ]
    if not calls:
        found.append("no validate(self) call")
    return found


CLASSES = config_classes()


def _id(cls: type) -> str:
    return f"{cls.__module__}.{cls.__qualname__}"


def test_the_config_classes_include_every_paper_and_the_nested_sim_specs():
    names = {_id(c) for c in CLASSES}
    for must in (
        "gyrobench.scenarios.papers.p003_ifog_thermal.config.Config",
        "gyrobench.scenarios.papers.p000_fog_vibration.config.FogSpec",
        "gyrobench.sim.fog_loop.LoopSpec",
        "gyrobench.sim.mems_resonator.MemsResonator",
        "gyrobench.sim.fiber_strain.StrainMode",
        "gyrobench.sim.parts._part.Datasheet",
        "gyrobench.sim.rlg_cavity.CavityRLGSpec",
        "gyrobench.sim.fog_loop.ClosedLoopFOG",
    ):
        assert must in names, must
    assert len(CLASSES) >= 20


@pytest.mark.parametrize("cls", CLASSES, ids=_id)
def test_no_hand_written_check_is_left(cls):
    assert not hand_written_checks(cls), (_id(cls), hand_written_checks(cls))


def test_the_scan_finds_a_hand_written_check():
    """The scan above can fail: a planted range check is found."""
    source = textwrap.dedent(
        """
        @dataclasses.dataclass(frozen=True)
        class Planted:
            fs_hz: float = 1.0

            def __post_init__(self):
                if self.fs_hz <= 0:
                    raise ValueError("fs_hz must be > 0")
        """
    )
    found = findings(source)
    assert any("raise" in f for f in found) and any(": if" in f for f in found)
    assert "no validate(self) call" in found


def _numeric(hint: typing.Any) -> bool:
    if hint in (int, float):
        return True
    args = [a for a in typing.get_args(hint) if a is not type(None)]
    if typing.get_origin(hint) is tuple:
        return bool(args) and all(a in (int, float) or a is Ellipsis for a in args)
    return typing.get_origin(hint) in (typing.Union, getattr(__import__("types"), "UnionType", None)) and (
        len(args) == 1 and _numeric(args[0])
    )


@pytest.mark.parametrize("cls", CLASSES, ids=_id)
def test_every_numeric_field_has_a_spec_with_a_unit_and_a_doc(cls):
    try:
        hints = typing.get_type_hints(cls)
    except NameError:  # a base's annotation under TYPE_CHECKING (the RLG units' _CavityScale)
        hints = _field_hints(cls)
    missing = []
    for f in dataclasses.fields(cls):
        spec = field_spec(cls, f.name)
        if _numeric(hints[f.name]):
            if not (isinstance(spec, FieldRange) and spec.unit.strip() and spec.why.strip() and spec.low <= spec.high):
                missing.append(f.name)
        elif spec is not None:
            assert isinstance(spec, (FieldRange, FieldChoice)) and spec.why.strip(), (f.name, spec)
    assert not missing, f"{_id(cls)}: numeric fields without a declared range, unit and doc: {missing}"
    for c in getattr(cls, "CONSTRAINTS", ()):
        assert isinstance(c, Constraint) and c.name.strip(), c


@pytest.mark.parametrize(
    ("name", "values"),
    [
        ("ifog_thermal", {"fibre_length_m": -1.0}),
        ("ifog_thermal", {"derivative_estimator": "finite"}),
        ("ifog_thermal", {"low_degC": 50.0}),
        ("rlg_thermal", {"block_s": 100.05}),
        ("fog_vibration", {"edge_window_s": 9.0}),
        ("mems_scale_factor", {"rates_dps": (1.0, 3.0, 2.0)}),
    ],
)
def test_the_configuration_layer_and_the_class_give_the_same_message(name, values):
    config = registry.get(name).Config()
    with pytest.raises(ValueError) as direct:
        dataclasses.replace(config, **values)
    with pytest.raises(ValueError) as layered:
        registry.override(config, values)
    assert str(direct.value) == str(layered.value)
    assert "\n" not in str(direct.value) and next(iter(values)) in str(direct.value)


@pytest.mark.parametrize(
    ("build", "phrase"),
    [
        (lambda: TemperatureSensor(noise=-0.1), "TemperatureSensor.noise must be >= 0 K; got -0.1"),
        (lambda: Discharge(current=0.0), "Discharge.current must be > 0 A; got 0.0"),
        (lambda: RateTransfer(rail_rate=-1.0), "RateTransfer.rail_rate must be > 0 rad/s or inf; got -1.0"),
        (lambda: RateTransfer(rail_rate=float("nan")), "RateTransfer.rail_rate must be > 0 rad/s or inf; got nan"),
        (lambda: AccelerometerSpec(range=0.0), "AccelerometerSpec.range must be > 0 m/s^2 or inf; got 0.0"),
        (lambda: Coil2DSpec(t_lo=320.0), "Coil2DSpec.t_lo must be < t_hi [K]; got 320.0 and 313.15"),
        (lambda: ClosedLoopFOG(index=1.0), "ClosedLoopFOG.index must be > 1 1; got 1.0"),
    ],
)
def test_a_sim_spec_refuses_in_one_line_from_its_declaration(build, phrase):
    with pytest.raises(ValueError) as err:
        build()
    assert str(err.value) == phrase


def test_an_infinite_value_passes_only_where_the_range_admits_it():
    assert RateTransfer(rail_rate=float("inf")).rail_rate == float("inf")
    assert not FieldRange(0, float("inf"), "rad/s").contains(float("inf"))
    assert not FieldRange(0, float("inf"), "rad/s", infinite=True).contains(float("-inf"))
