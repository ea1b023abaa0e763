"""Allan fits in field units: the coefficient table and the ``--json`` document.

:mod:`gyrobench.analysis.allan` returns coefficients in the units of the rate it was given
(rad/s here, so Q [rad], N [rad/sqrt(s)], ...); this edge module converts them to
the IEEE-952 field units of :data:`gyrobench.sim.units.COEFFICIENT_FIELD_UNITS`.
"""

from __future__ import annotations

from typing import Any

from gyrobench.scenarios.base import Table
from gyrobench.sim import units

__all__ = ["coefficients_json", "coefficient_table", "TERMS"]

TERMS = ("Q", "N", "B", "K", "R")


def _field(name: str, v: float | None) -> float | None:
    f = units.coefficient_to_field(name, v)
    return None if f is None else float(f)


def coefficients_json(fit) -> dict[str, dict[str, Any]]:
    """``{"Q": {"value", "low", "high", "unit", ...}, ...}`` in field units.

    ``low``/``high`` are the 95 % interval; ``low68``/``high68`` the 68 % one.
    ``value`` is None when the term is not identifiable from the record; then
    ``high`` holds the 95 % upper bound and ``low`` is 0.
    """
    out = {}
    for name in TERMS:
        c = fit.coefficients.get(name)
        unit = units.COEFFICIENT_FIELD_UNITS[name][0]
        if c is None:
            continue
        if c.identifiable and c.value is not None:
            out[name] = {
                "value": _field(name, c.value),
                "low": _field(name, c.ci95[0]),
                "high": _field(name, c.ci95[1]),
                "low68": _field(name, c.ci68[0]),
                "high68": _field(name, c.ci68[1]),
                "unit": unit,
                "identifiable": True,
            }
        else:
            out[name] = {
                "value": None,
                "low": 0.0,
                "high": _field(name, c.upper_bound),
                "low68": None,
                "high68": None,
                "unit": unit,
                "identifiable": False,
            }
    return out


def _interval_text(d: dict[str, Any]) -> tuple[str, str]:
    if d["value"] is None:
        return "not identifiable", f"< {d['high']:.3g}"
    return f"{d['value']:.4g}", f"[{d['low']:.3g}, {d['high']:.3g}]"


def coefficient_table(fit, *, title: str, truth: dict[str, float] | None = None) -> Table:
    """A report table of the fitted coefficients (and the true values, when known)."""
    js = coefficients_json(fit)
    cols = ["term", "unit", "fitted", "95 % interval"] + (["true", "true inside"] if truth else [])
    rows = []
    for name, d in js.items():
        v, ci = _interval_text(d)
        row = [name, d["unit"], v, ci]
        if truth is not None:
            t = truth.get(name, 0.0)
            inside = (d["low"] <= t <= d["high"]) if d["value"] is not None else t <= d["high"]
            row += [t, inside]
        rows.append(row)
    return Table(title, cols, rows)
