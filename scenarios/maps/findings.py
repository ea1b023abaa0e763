"""What a map says in words: which reported facts conflict, the region's finding, the nominal device.

:func:`conflicts` (pairs of facts each satisfied somewhere, never together), :func:`region_finding`
(the region's size, or which facts cannot hold together, with each never-satisfied fact's closest
point) and :func:`nominal_text` (whether the nominal device lies in the region, and the region's
medoid); :mod:`.region` re-exports them and writes them into map.json.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from .region import MapResult

__all__ = ["conflicts", "nominal_text", "region_finding"]


def conflicts(result: MapResult) -> tuple[tuple[str, str], ...]:
    """Pairs of constraints each satisfied on some point and never both on one point.

    Parameters
    ----------
    result : MapResult
        A map.

    Returns
    -------
    tuple of (str, str)
        The conflicting pairs' ids, in constraint order.
    """
    ids = [c.id for c in result.constraints]
    sat = np.asarray(result.satisfied, bool).reshape(len(result.satisfied), len(ids))
    out = []
    for a in range(len(ids)):
        for b in range(a + 1, len(ids)):
            if sat[:, a].any() and sat[:, b].any() and not (sat[:, a] & sat[:, b]).any():
                out.append((ids[a], ids[b]))
    return tuple(out)


def region_finding(result: MapResult) -> str:
    """The region's size, or, when it is empty, which reported facts cannot hold together.

    Parameters
    ----------
    result : MapResult
        A map.

    Returns
    -------
    str
        One paragraph: never-satisfied facts with their closest point, conflicting pairs, or a
        joint conflict.
    """
    n, region = len(result.satisfied), result.region
    ref = result.refinement
    inner = ""
    if ref is not None and ref.triggered:
        st = result.stages()
        around = "its points" if ref.basis == "region" else "the closest misses"
        inner = (f"first stage {st['1']['region']} of {st['1']['points']}, refined stage {st['2']['region']} of "
                 f"{st['2']['points']} around {around} {', '.join(map(str, ref.seeds))}")
    staged = f" ({inner})" if inner else ""
    if region:
        return f"{len(region)} of {n} family points satisfy every reported device fact{staged}."
    counts = result.counts()
    never = [c.id for c in result.constraints if counts[c.id] == 0]
    pairs = conflicts(result)
    joint = f"{n} points; {inner}" if inner else f"{n} points"
    parts = [f"No point of the family satisfies every reported device fact ({joint})."]
    if never:
        parts.append("Never satisfied on the family: " + "; ".join(_closest(result, c) for c in never) + ".")
    if pairs:
        parts.append("Conflicting (each holds somewhere, never together): "
                     + "; ".join(f"{a} and {b}" for a, b in pairs) + ".")
    if not never and not pairs:
        parts.append("Every pair holds together somewhere; the facts conflict only jointly: "
                     + ", ".join(c.id for c in result.constraints) + ".")
    return " ".join(parts)


def _closest(result: MapResult, cid: str) -> str:
    """``"<id> (needs <band>; closest: <median> at point i)"``: the point whose median comes nearest the band."""
    j = [c.id for c in result.constraints].index(cid)
    c = result.constraints[j]
    best, at = math.inf, None
    for i, row in enumerate(result.constraint_medians):
        v = row[j]
        if math.isfinite(v):
            gap = max(c.comparator.lo - v, v - c.comparator.hi, 0.0) if c.comparator.kind != "is_true" else 1.0 - v
            if gap < best:
                best, at = gap, i
    if at is None:
        return f"{cid} (needs {c.comparator.text()}; no point gives a finite {c.quantity})"
    return f"{cid} (needs {c.comparator.text()}; closest: {result.constraint_medians[at][j]:.4g} at point {at})"


def _values_text(result: MapResult, values: Mapping[str, float]) -> str:
    """``"field = value unit, ..."`` of a point's open parameters."""
    def unit(p: Any) -> str:
        return "" if p.range.unit in ("", "1") else f" {p.range.unit}"

    return ", ".join(f"{p.field} = {values[p.field]:.4g}{unit(p)}" for p in result.family.parameters)


def nominal_text(result: MapResult) -> str:
    """Whether the nominal device (the default ``reproduce``'s) lies in the region, and the region's medoid.

    Parameters
    ----------
    result : MapResult
        A map.

    Returns
    -------
    str
        One sentence or two: the nominal's membership (or that the family has no nominal point),
        then the medoid's parameters, or that the region is empty.
    """
    n, med = result.nominal, result.medoid
    if n is None:
        first = "The nominal device is no point of the family (its base configuration lies outside a range)."
    elif n.in_region:
        first = f"The nominal device lies in the region (every reported fact holds over its {len(n.seeds)} units)."
    else:
        missed = [c.id for c, ok in zip(result.constraints, n.satisfied, strict=True) if not ok]
        first = (f"The nominal device lies outside the region ({', '.join(missed)} not satisfied over its "
                 f"{len(n.seeds)} units).")
    if med is None:
        return first + " The region is empty: no region device can be named."
    return first + f" Region medoid: point {med} ({_values_text(result, result.design.values[med])})."
