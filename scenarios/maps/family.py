"""A paper's device family: the parameters the paper leaves open, with ranges and sources.

A :class:`Family` is a frozen spec of the open parameters (:class:`Parameter`: a paper ``Config``
field, or a dotted path into its nested frozen dataclasses such as ``"fog.mount.x.frequency"``,
its physical range as a :class:`~gyrobench.base.ranges.FieldRange` in the field's unit, a
linear or logarithmic scale, and the source of the range or the stated assumption), the fixed
parameters (:class:`Fixed`: the field and the source of its value) and the base configuration the
points replace fields of. :meth:`Family.config` maps a point to the paper's ``Config``
(a nested field by :func:`dataclasses.replace` at each level); :meth:`Family.nominal` is the
point whose values are the base configuration's own, so ``config(nominal())`` is the base.

:func:`design` places N points in the family with a space-filling design from
:mod:`scipy.stats.qmc`: a scrambled Sobol sequence (Owen scrambling, the first N points of
base 2; N a power of two keeps its balance properties) when N is a power of two, otherwise a
scrambled Latin hypercube (McKay, Beckman & Conover 1979), both with a fixed seed. A unit
coordinate u in [0, 1) maps to ``low + u (high - low)`` on a linear scale and to
``low (high / low)**u`` on a logarithmic one, rounded to a parameter's ``step`` when it has one.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar, Literal

import numpy as np
from scipy.stats import qmc

from gyrobench.base.ranges import Constraint, FieldRange, field_range, validate

__all__ = ["MAX_POINTS", "Design", "Family", "Fixed", "Parameter", "design", "get_path", "replace_path"]

#: the most points one design holds (a map's points are all held in memory with their units)
MAX_POINTS = 4096


@dataclass(frozen=True, slots=True, kw_only=True)
class Parameter:
    """One open parameter of a family.

    Attributes
    ----------
    field : str
        The paper ``Config`` field it sets, or a dotted path through nested frozen dataclasses
        (``"readout.nominal.rail"``).
    range : FieldRange
        Its physical range in the field's unit (``range.unit``), both ends inclusive.
    scale : "linear" or "log"
        How the design spreads points over the range (log: uniform in the logarithm; low > 0).
    source : str
        Where the range comes from: a cited value or a STATED ASSUMPTION (say which).
    label : str
        Axis label, e.g. ``"null-shift ratio eta"``.
    step : float, optional
        A grid the values are rounded to (the nearest multiple of ``step`` inside the range), for a
        field that takes whole units (e.g. a record's phase in whole seconds); None: continuous.
    """

    field: str
    range: FieldRange
    scale: Literal["linear", "log"]
    source: str
    label: str
    step: float | None = None

    #: ``range`` is a FieldRange and ``scale`` one of its Literal values (from the annotations);
    #: what ties the fields together:
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "range.low < range.high, both finite",
            lambda c: math.isfinite(c.range.low) and math.isfinite(c.range.high) and c.range.low < c.range.high,
            lambda c: f"range of {c.field!r} needs finite low < high; got {c.range.low!r}, {c.range.high!r}",
        ),
        Constraint(
            "scale 'log' needs range.low > 0",
            lambda c: c.scale != "log" or c.range.low > 0,
            lambda c: f"scale of {c.field!r}: a log scale needs range.low > 0; got {c.range.low!r}",
        ),
        Constraint(
            "source is not blank",
            lambda c: bool(c.source.strip()),
            lambda c: f"source of {c.field!r} must give the range's source or the stated assumption; got {c.source!r}",
        ),        Constraint(
            "step, when given, in (0, high - low]",
            lambda c: c.step is None or (math.isfinite(c.step) and 0 < c.step <= c.range.high - c.range.low),
            lambda c: f"step of {c.field!r} must be in (0, high - low]; got {c.step!r}",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared types and constraints above

    def value(self, u: float) -> float:
        """The parameter's value at unit coordinate ``u`` in [0, 1] (its scale, see the module)."""
        lo, hi = self.range.low, self.range.high
        v = lo * (hi / lo) ** u if self.scale == "log" else lo + u * (hi - lo)
        if self.step is not None:  # the nearest grid value inside the range
            v = min(max(round(v / self.step) * self.step, math.ceil(lo / self.step) * self.step),
                    math.floor(hi / self.step) * self.step)
        return float(v)

    def coordinate(self, value: float) -> float:
        """The unit coordinate of ``value`` (the inverse of :meth:`value`; outside [0, 1] when the value
        lies outside the range)."""
        lo, hi = self.range.low, self.range.high
        if self.scale == "log":
            return float(math.log(value / lo) / math.log(hi / lo))
        return float((value - lo) / (hi - lo))

    def axis_label(self) -> str:
        """``"label [unit]"`` (no brackets for a pure number)."""
        u = self.range.unit
        return self.label if u in ("", "1") else f"{self.label} [{u}]"


@dataclass(frozen=True, slots=True, kw_only=True)
class Fixed:
    """A parameter the family keeps at the base configuration's value, with that value's source.

    Parameters
    ----------
    field : str
        The paper ``Config`` field (or a dotted path, as :class:`Parameter`).
    source : str
        Where its value comes from, or the stated assumption.
    """

    field: str
    source: str

    #: what ties the fields together (both are text: no range)
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "source is not blank",
            lambda c: bool(c.source.strip()),
            lambda c: f"source of {c.field!r} must give the value's source or the stated assumption; got {c.source!r}",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared constraint above


def _names(family: Family) -> list[str]:
    return [p.field for p in family.parameters] + [f.field for f in family.fixed]


def _has_path(obj: Any, path: str) -> bool:
    try:
        get_path(obj, path)
    except ValueError:
        return False
    return True


def _path_error(obj: Any, path: str) -> str:
    try:
        get_path(obj, path)
    except ValueError as exc:
        return str(exc)
    return ""


def _declared(family: Family, path: str) -> FieldRange | None:
    """The declared range of the field at ``path`` (a dotted path: in the dataclass that holds it)."""
    head, _, last = path.rpartition(".")
    holder = get_path(family.base, head) if head else family.base
    return field_range(type(holder), last)


def _inside_declared(family: Family, p: Parameter) -> bool:
    """Whether ``p``'s range lies inside the base Config's declared range of its field, in its unit."""
    declared = _declared(family, p.field)
    if declared is None:
        return True
    return p.range.unit == declared.unit and declared.contains(p.range.low) and declared.contains(p.range.high)


def _outside_declared(family: Family) -> str:
    p = next(p for p in family.parameters if not _inside_declared(family, p))
    declared = _declared(family, p.field)
    assert declared is not None
    return (
        f"parameters: {p.field} range [{p.range.low:g}, {p.range.high:g}] {p.range.unit} must lie in the "
        f"Config's declared {declared.text()}"
    )


def _ends_are_configs(family: Family) -> None:
    """Build the base Config at both ends of every parameter's range: its validation refuses an
    end that is no valid configuration, in the Config's own one-line message."""
    for p in family.parameters:
        for end in (p.range.low, p.range.high):
            replace_path(family.base, p.field, end)


@dataclass(frozen=True, slots=True, kw_only=True)
class Family:
    """A paper's device family: its open parameters, its fixed ones and the base configuration.

    Attributes
    ----------
    paper : str
        The paper's key (``"004"``).
    base : Any
        The paper's frozen ``Config`` the points replace fields of (its other fields are the
        protocol and the fixed parameters).
    parameters : tuple of Parameter
        The open parameters (at least one; distinct fields of ``base``).
    fixed : tuple of Fixed
        The mechanism sizes kept fixed, with their sources.
    nominal_device : str
        What the nominal device (``base``, the default ``reproduce``'s) is, in a few words (its
        source, e.g. the identification it comes from); "" when not stated.
    """

    paper: str
    base: Any
    parameters: tuple[Parameter, ...]
    fixed: tuple[Fixed, ...] = ()
    nominal_device: str = ""

    #: what ties the fields together; the Config's own declared ranges (``RANGES``) bound each
    #: parameter's range
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "parameters is a non-empty tuple of Parameter, fixed a tuple of Fixed",
            lambda c: bool(c.parameters) and all(isinstance(p, Parameter) for p in c.parameters)
            and all(isinstance(f, Fixed) for f in c.fixed),
            lambda c: f"parameters must be at least one Parameter and fixed Fixed entries (family of paper {c.paper}); "
            f"got {len(c.parameters)} parameters",
        ),
        Constraint(
            "each field listed once",
            lambda c: len(set(_names(c))) == len(_names(c)),
            lambda c: f"parameters: a field is listed twice in {_names(c)} (family of paper {c.paper})",
        ),
        Constraint(
            "each field is a field (or a dotted path of fields) of base",
            lambda c: all(_has_path(c.base, n) for n in _names(c)),
            lambda c: f"parameters: {_path_error(c.base, next(n for n in _names(c) if not _has_path(c.base, n)))} "
            f"(family of paper {c.paper})",
        ),
        Constraint(
            "each parameter's range inside the Config's declared range, same unit",
            lambda c: all(_inside_declared(c, p) for p in c.parameters),
            _outside_declared,
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared constraints above
        _ends_are_configs(self)  # both ends of every range build a valid Config (its own message)

    @property
    def names(self) -> tuple[str, ...]:
        """The open parameters' fields, in order."""
        return tuple(p.field for p in self.parameters)

    @property
    def nominal(self) -> dict[str, float] | None:
        """The nominal device (``base``, what the default ``reproduce`` runs) as a point of the family:
        its value of every open parameter, or None when one of them is not a number inside the
        parameter's range (the nominal device is then no point of the family)."""
        out = {}
        for p in self.parameters:
            v = get_path(self.base, p.field)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not p.range.contains(float(v)):
                return None
            out[p.field] = float(v)
        return out

    def config(self, values: Mapping[str, float]) -> Any:
        """The paper's ``Config`` at the point ``values`` (one value per open parameter, field units)."""
        if set(values) != set(self.names):
            raise ValueError(f"family of paper {self.paper}: a point sets exactly {self.names}; got {tuple(values)}")
        for p in self.parameters:
            v = values[p.field]
            if not p.range.contains(v):
                raise ValueError(f"family of paper {self.paper}: {p.field} must be in {p.range.text()}; got {v!r}")
        out = self.base
        for p in self.parameters:
            out = replace_path(out, p.field, float(values[p.field]))
        return out

    def as_dict(self) -> dict[str, Any]:
        """The family as map.json lists it (ranges in field units, the fixed values from ``base``)."""
        return {
            "paper": self.paper,
            "parameters": [{"field": p.field, "label": p.label, "low": p.range.low, "high": p.range.high,
                            "unit": p.range.unit, "scale": p.scale, "step": p.step, "source": p.source}
                           for p in self.parameters],
            "fixed": [{"field": f.field, "value": _json_value(get_path(self.base, f.field)), "source": f.source}
                      for f in self.fixed],
            "nominal": self.nominal,
            "nominal_device": self.nominal_device,
        }


def get_path(obj: Any, path: str, *, owner: str = "") -> Any:
    """The value at a dotted field path of nested dataclasses (``"fog.mount.x.frequency"``).

    Parameters
    ----------
    obj : dataclass instance
        Where the path starts.
    path : str
        Field names joined by dots.
    owner : str
        Named first in the error message.

    Returns
    -------
    Any
        The field's value.

    Raises
    ------
    ValueError
        When a step of the path is not a field of the dataclass it is taken from.
    """
    cur = obj
    for i, name in enumerate(path.split(".")):
        if not dataclasses.is_dataclass(cur) or name not in {f.name for f in dataclasses.fields(cur)}:
            lead = f"{owner}: " if owner else ""
            if i == 0:
                raise ValueError(f"{lead}{name!r} is not a field of {type(obj).__name__}")
            where = ".".join(path.split(".")[:i])
            raise ValueError(f"{lead}{path!r}: {name!r} is not a field of {where} ({type(cur).__name__})")
        cur = getattr(cur, name)
    return cur


def replace_path(obj: Any, path: str, value: Any) -> Any:
    """A copy of nested frozen dataclasses with the field at a dotted path replaced.

    :func:`dataclasses.replace` at each level, so each level's own validation runs.

    Parameters
    ----------
    obj : dataclass instance
        Where the path starts.
    path : str
        Field names joined by dots.
    value : Any
        The field's new value.

    Returns
    -------
    dataclass instance
        ``obj`` with the field replaced (``obj`` itself unchanged).
    """
    head, _, rest = path.partition(".")
    if not rest:
        return dataclasses.replace(obj, **{head: value})
    return dataclasses.replace(obj, **{head: replace_path(getattr(obj, head), rest, value)})


def _json_value(v: Any) -> Any:
    """A fixed field's value for map.json: numbers and strings as they are, anything else by repr."""
    if v is None or isinstance(v, (bool, int, float, str)):
        return v
    return repr(v)


@dataclass(frozen=True, slots=True, kw_only=True)
class Design:
    """N points of a family: unit coordinates and the values they map to.

    Attributes
    ----------
    method : str
        ``"sobol"`` (scrambled Sobol, N a power of two) or ``"lhs"`` (scrambled Latin hypercube).
    seed : int
        The design's seed.
    unit : ndarray, shape (N, d)
        Coordinates in [0, 1).
    values : tuple of dict
        Each point's values in field units, one per open parameter.
    stage : tuple of int
        Each point's stage (1: the space-filling design, 2: a refinement, :mod:`.refine`); empty
        when every point is of stage 1.
    """

    method: str
    seed: int
    unit: np.ndarray
    values: tuple[dict[str, float], ...]
    stage: tuple[int, ...] = ()

    def stage_of(self, i: int) -> int:
        """Point ``i``'s stage (1 when the design has no second stage)."""
        return self.stage[i] if self.stage else 1

    def __len__(self) -> int:
        return len(self.values)


def design(family: Family, n: int, seed: int) -> Design:
    """Space-filling points of a family (see the module): Sobol for a power of two, else LHS.

    Parameters
    ----------
    family : Family
        The family whose open parameters the points set.
    n : int
        Points, in ``[2, MAX_POINTS]``.
    seed : int
        The scramble's seed.

    Returns
    -------
    Design
        The points' unit coordinates and values.
    """
    if isinstance(n, bool) or not isinstance(n, int) or not 2 <= n <= MAX_POINTS:
        raise ValueError(f"points must be an integer in [2, {MAX_POINTS}]; got {n!r}")
    d = len(family.parameters)
    if n & (n - 1) == 0:
        u = qmc.Sobol(d, scramble=True, rng=np.random.default_rng(seed)).random_base2(int(math.log2(n)))
        method = "sobol"
    else:
        u = qmc.LatinHypercube(d, scramble=True, rng=np.random.default_rng(seed)).random(n)
        method = "lhs"
    values = tuple({p.field: p.value(float(x)) for p, x in zip(family.parameters, row, strict=True)} for row in u)
    return Design(method=method, seed=int(seed), unit=np.asarray(u, float), values=values)
