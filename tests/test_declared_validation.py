"""No ``__post_init__`` in the package checks its fields by hand: validation is declared.

An AST scan over every module of ``gyrobench`` (base, io, sim, analysis, scenarios) finds, in each
dataclass's ``__post_init__``,

* a ``raise`` statement of its own;
* a call to one of the hand-written helpers of :mod:`gyrobench.base.validate` (``positive_number``,
  ``nonneg_field``, ``nonneg_coefficient``, ...);
* a call, before ``validate(self)``, to a function of the package that raises (a local checking
  helper such as ``_vec3``). After ``validate(self)`` a call may build what the class delegates to,
  which validates itself.

The only validator a ``__post_init__`` runs is :func:`gyrobench.base.ranges.validate`, from the
class's ``RANGES`` and ``CONSTRAINTS``; no class is exempt. The scan is shown to find a planted
check. Then each check moved to the declarations is shown, case by case, to refuse its bad
value in one line that names the class and field, the constraint and the value.
"""

from __future__ import annotations

import ast
import math
from pathlib import Path

import numpy as np
import pytest

import gyrobench

PACKAGE = Path(gyrobench.__file__).parent  # not resolved: sim, analysis, scenarios are links
LAYERS = ("base", "io", "sim", "analysis", "scenarios")
#: the one validator a __post_init__ may call before it builds anything
VALIDATOR = ("gyrobench.base.ranges", "validate")
#: the module of hand-written checking helpers, never called from a __post_init__
HELPERS = "gyrobench.base.validate"

def _modules() -> dict[str, ast.Module]:
    out = {}
    for layer in LAYERS:
        for path in sorted((PACKAGE / layer).rglob("*.py")):
            parts = list(path.relative_to(PACKAGE).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts = parts[:-1]
            out["gyrobench." + ".".join(parts)] = ast.parse(path.read_text(), filename=str(path))
    return out


def _raising_functions(tree: ast.Module) -> set[str]:
    """The module-level functions whose body holds a ``raise``."""
    return {
        n.name for n in tree.body
        if isinstance(n, ast.FunctionDef) and any(isinstance(x, ast.Raise) for x in ast.walk(n))
    }


def _imported(tree: ast.Module) -> dict[str, tuple[str, str]]:
    """Local name -> (module, name) for every ``from gyrobench... import name``."""
    out = {}
    for n in ast.walk(tree):
        if isinstance(n, ast.ImportFrom) and n.module and n.module.startswith("gyrobench") and not n.level:
            for a in n.names:
                out[a.asname or a.name] = (n.module, a.name)
    return out


def _is_validate(call: ast.Call, imported: dict[str, tuple[str, str]]) -> bool:
    return isinstance(call.func, ast.Name) and imported.get(call.func.id) == VALIDATOR


def post_init_findings(module: str, tree: ast.Module, raising: dict[str, set[str]]) -> dict[str, list[str]]:
    """Class qualname -> what its ``__post_init__`` checks by hand (empty classes left out).

    Parameters
    ----------
    module : str
        The module's dotted name.
    tree : ast.Module
        Its parsed source.
    raising : dict
        Module name -> its raising module-level functions (:func:`_raising_functions`).

    Returns
    -------
    dict of str to list of str
        ``"line N: raise"``, ``"line N: calls <helper>"`` entries per class.
    """
    imported = _imported(tree)
    out: dict[str, list[str]] = {}
    for cls in ast.walk(tree):
        if not isinstance(cls, ast.ClassDef):
            continue
        for fn in cls.body:
            if not (isinstance(fn, ast.FunctionDef) and fn.name == "__post_init__"):
                continue
            found = [f"line {n.lineno}: raise" for n in ast.walk(fn) if isinstance(n, ast.Raise)]
            calls = sorted((n for n in ast.walk(fn) if isinstance(n, ast.Call)), key=lambda n: (n.lineno, n.col_offset))
            validated_at = min((c.lineno for c in calls if _is_validate(c, imported)), default=math.inf)
            for c in calls:
                if not isinstance(c.func, ast.Name) or _is_validate(c, imported):
                    continue
                name = c.func.id
                source = imported.get(name)
                if source is not None and source[0] == HELPERS:
                    found.append(f"line {c.lineno}: calls {name} (a hand-written check of {HELPERS})")
                elif c.lineno < validated_at and (
                    name in raising.get(module, set())
                    or (source is not None and source[1] in raising.get(source[0], set()))
                ):
                    found.append(f"line {c.lineno}: calls {name}, which raises, before validate(self)")
            if found:
                out[f"{module}.{cls.name}"] = found
    return out


@pytest.fixture(scope="module")
def scanned() -> dict[str, list[str]]:
    trees = _modules()
    raising = {m: _raising_functions(t) for m, t in trees.items()}
    out: dict[str, list[str]] = {}
    for m, t in trees.items():
        out.update(post_init_findings(m, t, raising))
    return out


def test_no_post_init_checks_by_hand(scanned):
    assert not scanned, "a __post_init__ checks by hand; declare RANGES / CONSTRAINTS and call validate(self):\n" + (
        "\n".join(f"{k}: {v}" for k, v in sorted(scanned.items()))
    )


PLANTED = '''
from dataclasses import dataclass
from gyrobench.base.ranges import validate
from gyrobench.base.validate import positive_number


def _check(v):
    if v <= 0:
        raise ValueError("bad")
    return v


def _build(v):
    if v is None:
        raise ValueError("cannot build")
    return v


@dataclass(frozen=True)
class Direct:
    x: float = 1.0

    def __post_init__(self):
        if self.x <= 0:
            raise ValueError("x must be > 0")


@dataclass(frozen=True)
class Helper:
    x: float = 1.0

    def __post_init__(self):
        positive_number("Helper.x", self.x, "m")


@dataclass(frozen=True)
class LocalBefore:
    x: float = 1.0

    def __post_init__(self):
        _check(self.x)
        validate(self)


@dataclass(frozen=True)
class Declared:
    x: float = 1.0

    def __post_init__(self):
        validate(self)
        _build(self.x)
'''


def test_the_scan_finds_each_planted_kind_of_hand_written_check():
    tree = ast.parse(PLANTED)
    found = post_init_findings("planted", tree, {"planted": _raising_functions(tree)})
    assert set(found) == {"planted.Direct", "planted.Helper", "planted.LocalBefore"}, found
    assert found["planted.Direct"] == ["line 25: raise"]
    assert "positive_number" in found["planted.Helper"][0]
    assert "_check, which raises, before validate(self)" in found["planted.LocalBefore"][0]


# ------------------------------------------------------------------ each moved check, in one line
def _moved_cases():
    from gyrobench.io.recording import Channel, Recording
    from gyrobench.scenarios.base import Table
    from gyrobench.scenarios.bench.primary import PrimaryScore
    from gyrobench.scenarios.checks.core import KINDS, Check
    from gyrobench.sim.earth import Site
    from gyrobench.sim.environment import PiecewiseLinear
    from gyrobench.sim.imu import TriadSpec
    from gyrobench.sim.noise import GaussMarkov, NoiseModel, Sinusoid
    from gyrobench.sim.rlg import CavityGeometry
    from gyrobench.sim.sensor import Environment
    from gyrobench.sim.shaker import RandomVibration
    from gyrobench.sim.trajectory import ConingMotion, RockingMotion, SampledMotion, Segment, SegmentedMotion

    def triad(**kw):
        from gyrobench.sim import parts

        g = parts.get("adxrs646")
        return TriadSpec(gyros=kw.pop("gyros", (g, g, g)), **kw)

    t4 = np.arange(4.0)
    q4 = np.tile([1.0, 0.0, 0.0, 0.0], (4, 1))
    v4 = np.zeros((4, 3))
    seg = Segment(duration=1.0)
    gm = GaussMarkov(sigma=1.0, correlation_time=1.0)
    # (build, exception, the one-line message)
    return [
        (lambda: Site(latitude=2.0), ValueError, "Site.latitude must be [-1.5708, 1.5708] rad; got 2.0"),
        (lambda: Site(height=math.nan), ValueError, "Site.height must be [-10000, 100000] m; got nan"),
        (lambda: PiecewiseLinear([0.0, 1.0], [1.0]), ValueError,
         "PiecewiseLinear.times and values must be 1-D arrays of equal length >= 1 [s], [SI]; "
         "got an array of shape (2,) and an array of shape (1,)"),
        (lambda: PiecewiseLinear([0.0, 1.0], [1.0, math.inf]), ValueError,
         "PiecewiseLinear.times and values must be finite [s], [SI]; got an array of shape (2,) and an array of "
         "shape (2,) with a non-finite value"),
        (lambda: PiecewiseLinear([0.0, 2.0, 1.0], [0.0, 0.0, 0.0]), ValueError,
         "PiecewiseLinear.times must be strictly increasing [s]; got 2.0 then 1.0 s"),
        (lambda: Environment(0.0), ValueError, "Environment.duration must be > 0 s; got 0.0"),
        (lambda: Environment(1.0, true_rate="fast"), TypeError,
         "Environment.true_rate must be a number, a callable of time or a 1-D or (n, k) array [rad/s]; got str"),
        (lambda: Environment(1.0, true_rate=np.zeros((2, 2, 2))), ValueError,
         "Environment.true_rate must be a finite 1-D or (n, k) array [rad/s]; got an array of shape (2, 2, 2)"),
        (lambda: Environment(1.0, temperature=math.nan), ValueError,
         "Environment.temperature must be finite [K]; got nan"),
        (lambda: Environment(1.0, specific_force=np.zeros((2, 2))), ValueError,
         "Environment.specific_force must be a finite 1-D array [m/s^2]; got an array of shape (2, 2)"),
        (lambda: Environment(1.0, vibration=3.0), TypeError,
         "Environment.vibration must be a sim.shaker.ShakerSignal or None; got float"),
        (lambda: triad(gyros=(1, 2)), TypeError,
         "TriadSpec.gyros must be three sensor specs (each with realize(rng=...)); got (1, 2)"),
        (lambda: triad(accelerometer="adxl"), TypeError,
         "TriadSpec.accelerometer must be an AccelerometerSpec or None; got 'adxl'"),
        (lambda: triad(cross_axis=0.2), ValueError, "TriadSpec.cross_axis must be [0, 0.1] 1; got 0.2"),
        (lambda: triad(accel_matrix=np.full((3, 3), math.nan)), ValueError,
         "TriadSpec.accel_matrix must be a finite array of shape (3, 3) [1] or None; "
         "got an array of shape (3, 3) with a non-finite value"),
        (lambda: GaussMarkov(sigma=-1.0, correlation_time=1.0), ValueError,
         "GaussMarkov.sigma must be [0, 1e+100] rad/s; got -1.0"),
        (lambda: GaussMarkov(sigma=1.0, correlation_time=0.0), ValueError,
         "GaussMarkov.correlation_time must be (0, 1e+100] s; got 0.0"),
        (lambda: Sinusoid(amplitude=1.0, frequency=0.0), ValueError,
         "Sinusoid.frequency must be (0, 1e+100] Hz; got 0.0"),
        (lambda: Sinusoid(amplitude=1.0, frequency=1.0, phase=math.inf), ValueError,
         "Sinusoid.phase must be a finite number [rad]; got inf"),
        (lambda: NoiseModel(rate_random_walk=1e101), ValueError,
         "NoiseModel.rate_random_walk must be [0, 1e+100] rad/s/sqrt(s); got 1e+101"),
        (lambda: NoiseModel(flicker_band=(1.0, 0.5)), ValueError,
         "NoiseModel.flicker_band must satisfy 0 < f_low < f_high [Hz]; got (1.0, 0.5)"),
        (lambda: NoiseModel(flicker_band=[1e-6, 1.0]), TypeError,
         "NoiseModel.flicker_band must be a tuple; got list [1e-06, 1.0]"),
        (lambda: NoiseModel(bias=math.inf), ValueError, "NoiseModel.bias must be a finite number [rad/s]; got inf"),
        (lambda: NoiseModel(sinusoids=(gm,)), TypeError,
         "NoiseModel.sinusoids must be a tuple of Sinusoid; got (GaussMarkov(sigma=1.0, correlation_time=1.0),)"),
        (lambda: NoiseModel(gauss_markov=(gm,) * 57), ValueError,
         "NoiseModel.gauss_markov holds at most 56 terms; got 57"),
        (lambda: Segment(duration=-1.0), ValueError, "Segment.duration must be > 0 s; got -1.0"),
        (lambda: Segment(duration=1.0, rate=[1.0, 2.0]), ValueError,
         "Segment.rate must be a finite array of shape (3,) [rad/s]; got an array of shape (2,)"),
        (lambda: SegmentedMotion(()), TypeError,
         "SegmentedMotion.segments must be a non-empty sequence of Segment; got ()"),
        (lambda: SegmentedMotion((seg,), velocity="north"), ValueError,
         "SegmentedMotion.velocity must be a finite array of shape (3,) [m/s]; got 'north'"),
        (lambda: ConingMotion(half_angle=math.pi, frequency=1.0, duration=1.0), ValueError,
         "ConingMotion.half_angle must be (0, 3.14159) rad; got 3.141592653589793"),
        (lambda: RockingMotion(amplitude=0.1, frequency=1.0, duration=0.0), ValueError,
         "RockingMotion.duration must be > 0 s; got 0.0"),
        (lambda: SampledMotion(t4 + 1.0, q4, v4), ValueError,
         "SampledMotion.times must be >= 4 finite, strictly increasing times [s] from 0; got an array of shape (4,)"),
        (lambda: SampledMotion(t4, q4[:, :3], v4), ValueError,
         "SampledMotion.quaternions must be (4, 4) and velocities (4, 3), finite; "
         "got an array of shape (4, 3) and an array of shape (4, 3)"),
        (lambda: SampledMotion(t4, 2 * q4, v4), ValueError,
         "SampledMotion.quaternions must be unit quaternions (|q| within 1e-3 of 1); got |q| from 2 to 2"),
        (lambda: CavityGeometry(vertices="abc"), TypeError,
         "CavityGeometry.vertices must be a sequence of (x, y) pairs [m]; got 'abc'"),
        (lambda: CavityGeometry(vertices=((0, 0), (1, 0))), ValueError,
         "CavityGeometry.vertices must hold >= 3 (x, y) pairs [m]; got shape (2, 2)"),
        (lambda: RandomVibration(breakpoints=((20, 0.01), (10, 0.01)), duration=1.0), ValueError,
         "RandomVibration.breakpoints must have frequencies > 0 Hz, strictly increasing; got [20.0, 10.0]"),
        (lambda: RandomVibration(breakpoints=((20, 0.01), (30, -1.0)), duration=1.0), ValueError,
         "RandomVibration.breakpoints must have PSD levels finite and > 0 g^2/Hz; got [0.01, -1.0]"),
        (lambda: _curve(confidence=1.0), ValueError, "AllanCurve.confidence must be (0, 1) 1; got 1.0"),
        (lambda: _curve(edf=np.ones(2)), ValueError, "AllanCurve.edf must have the shape of tau (3,); got (2,)"),
        (lambda: Table(title="T", columns=("a", "b"), rows=(("1", "2"), ("3",))), ValueError,
         "Table.rows must each have 2 cells (one per column); rows [1] of table 'T' do not"),
        (lambda: PrimaryScore(name="mean/rms", unit="rad/s", direction=0), ValueError,
         "PrimaryScore.direction must be -1 or +1; got 0"),
        (lambda: Check(id="c", formula="f", expected=1.0, simulated=1.0, tolerance=0.0, derivation="d",
                       reference="r", kind=KINDS[0]), ValueError,
         "Check.tolerance must be finite and > 0; got 0.0 (check 'c')"),
        (lambda: Channel(np.zeros((2, 2)), "K"), ValueError, "Channel.data must be 1-D; got shape (2, 2)"),
        (lambda: Recording(fs=1.0, channels={}), ValueError,
         "Recording.channels must hold at least one channel; got none"),
        (lambda: Recording(fs=1.0, channels={"a": Channel(np.zeros(3), "K")}, inputs={"b": Channel(np.zeros(2), "K")}),
         ValueError, "Recording.channels must all have the same length; got {'a': 3, 'inputs/b': 2}"),
    ]


def _curve(**kw):
    from gyrobench.analysis.allan import AllanCurve

    n = np.ones(3)
    args = dict(tau=n, deviation=n, low=n, high=n, n_terms=n, edf=n, kind="overlapping", confidence=0.683, fs=1.0,
                n_samples=10)
    return AllanCurve(**{**args, **kw})


MOVED = _moved_cases()


@pytest.mark.parametrize(("build", "error", "message"), MOVED, ids=[m[2].split(" ")[0] for m in MOVED])
def test_a_moved_check_refuses_its_bad_value_in_one_line(build, error, message):
    with pytest.raises(error) as caught:
        build()
    assert type(caught.value) is error
    assert str(caught.value) == message
    assert "\n" not in message


def test_the_moved_classes_still_take_good_values():
    from gyrobench.sim.earth import Site
    from gyrobench.sim.environment import PiecewiseLinear
    from gyrobench.sim.noise import NoiseModel
    from gyrobench.sim.sensor import Environment
    from gyrobench.sim.trajectory import SampledMotion, Segment, SegmentedMotion

    assert Site(latitude=-math.pi / 2, height=-1e4).latitude == -math.pi / 2
    p = PiecewiseLinear([0, 1], [2, 3])
    assert p.times.dtype == np.float64 and p.duration == 1.0
    assert Environment(1.0, true_rate=np.zeros((5, 2)), temperature=p).columns == 2
    assert NoiseModel(flicker_band=(1e-6, math.inf)).flicker_band == (1e-6, math.inf)
    m = SegmentedMotion([Segment(duration=1.0, rate=[0, 0, 1])])
    assert isinstance(m.segments, tuple) and m.duration == 1.0
    q = np.tile([1.0, 0.0, 0.0, 0.0], (4, 1))
    q[2] *= -1  # a sign flip between samples is undone
    s = SampledMotion(np.arange(4.0), q, np.zeros((4, 3)))
    assert np.all(s.quaternions[:, 0] == 1.0)
