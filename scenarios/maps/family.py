"""A paper's device family: the parameters the paper leaves open, with ranges and sources.

A :class:`Family` is a frozen spec of the open parameters (:class:`Parameter`: a paper ``Config``
field, its physical range as a :class:`~gyrobench.base.ranges.FieldRange` in the field's unit, a
linear or logarithmic scale, and the source of the range or the stated assumption), the fixed
parameters (:class:`Fixed`: the field and the source of its value) and the base configuration the
points replace fields of. :meth:`Family.config` maps a point to the paper's ``Config``.

:func:`design` places N points in the family with a space-filling design from
:mod:`scipy.stats.qmc`: a scrambled Sobol sequence (Owen scrambling, the first N points of
base 2; N a power of two keeps its balance properties) when N is a power of two, otherwise a
scrambled Latin hypercube (McKay, Beckman & Conover 1979), both with a fixed seed. A unit
coordinate u in [0, 1) maps to ``low + u (high - low)`` on a linear scale and to
``low (high / low)**u`` on a logarithmic one.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from scipy.stats import qmc

from gyrobench.base.ranges import FieldRange

__all__ = ["MAX_POINTS", "Design", "Family", "Fixed", "Parameter", "design"]

#: the most points one design holds (a map's points are all held in memory with their units)
MAX_POINTS = 4096


@dataclass(frozen=True, slots=True, kw_only=True)
class Parameter:
    """One open parameter of a family.

    Attributes
    ----------
    field : str
        The paper ``Config`` field it sets.
    range : FieldRange
        Its physical range in the field's unit (``range.unit``), both ends inclusive.
    scale : "linear" or "log"
        How the design spreads points over the range (log: uniform in the logarithm; low > 0).
    source : str
        Where the range comes from: a cited value or a STATED ASSUMPTION (say which).
    label : str
        Axis label, e.g. ``"null-shift ratio eta"``.
    """

    field: str
    range: FieldRange
    scale: Literal["linear", "log"]
    source: str
    label: str

    def __post_init__(self) -> None:
        lo, hi = self.range.low, self.range.high
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            raise ValueError(f"parameter {self.field!r}: range needs finite low < high; got {lo!r}, {hi!r}")
        if self.scale not in ("linear", "log"):
            raise ValueError(f"parameter {self.field!r}: scale must be 'linear' or 'log'; got {self.scale!r}")
        if self.scale == "log" and lo <= 0:
            raise ValueError(f"parameter {self.field!r}: a log scale needs low > 0; got {lo!r}")
        if not self.source.strip():
            raise ValueError(f"parameter {self.field!r}: give the range's source or the stated assumption")

    def value(self, u: float) -> float:
        """The parameter's value at unit coordinate ``u`` in [0, 1] (its scale, see the module)."""
        lo, hi = self.range.low, self.range.high
        if self.scale == "log":
            return float(lo * (hi / lo) ** u)
        return float(lo + u * (hi - lo))

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
        The paper ``Config`` field.
    source : str
        Where its value comes from, or the stated assumption.
    """

    field: str
    source: str


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
    """

    paper: str
    base: Any
    parameters: tuple[Parameter, ...]
    fixed: tuple[Fixed, ...] = ()

    def __post_init__(self) -> None:
        if not self.parameters:
            raise ValueError(f"family of paper {self.paper}: give at least one open parameter")
        names = [p.field for p in self.parameters] + [f.field for f in self.fixed]
        if len(set(names)) != len(names):
            raise ValueError(f"family of paper {self.paper}: a field is listed twice in {names}")
        fields = {f.name for f in dataclasses.fields(self.base)}
        for n in names:
            if n not in fields:
                raise ValueError(f"family of paper {self.paper}: {n!r} is not a field of {type(self.base).__name__}")
        for p in self.parameters:  # both ends must be valid configurations
            for end in (p.range.low, p.range.high):
                dataclasses.replace(self.base, **{p.field: end})

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
            v = getattr(self.base, p.field)
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
        return dataclasses.replace(self.base, **{k: float(v) for k, v in values.items()})

    def as_dict(self) -> dict[str, Any]:
        """The family as map.json lists it (ranges in field units, the fixed values from ``base``)."""
        return {
            "paper": self.paper,
            "parameters": [{"field": p.field, "label": p.label, "low": p.range.low, "high": p.range.high,
                            "unit": p.range.unit, "scale": p.scale, "source": p.source} for p in self.parameters],
            "fixed": [{"field": f.field, "value": getattr(self.base, f.field), "source": f.source}
                      for f in self.fixed],
            "nominal": self.nominal,
        }


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
    """

    method: str
    seed: int
    unit: np.ndarray
    values: tuple[dict[str, float], ...]

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
