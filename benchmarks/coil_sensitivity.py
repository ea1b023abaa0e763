"""Effect of the coil model's assumed (uncited) inputs on paper 003's quantities.

Every constant of :mod:`gyrobench.sim.coil2d` either has a cited source or is listed as
assumed in docs/physics.md 9. For each assumed input this script halves and doubles it (the
silica expansion slope: its verified bound instead) and prints, against the defaults:

- the T x dT term of paper 003's Table-1 case (10 m of free fibre at 0.25 L, 1 degC/min,
  -10 -> 40 degC), peak over the ramp [deg/h];
- the same stretch bonded in the pack at mid radius [deg/h];
- the median over ``--units`` drawn units of the peak drift under paper 003's validation-1
  program (10 degC/h from -10 to 40 degC with 1 h holds) [deg/h].

Run: ``python benchmarks/coil_sensitivity.py [--units 8]`` (about 1 s per unit and case).
"""

from __future__ import annotations

import argparse
import dataclasses
import time

import numpy as np

from gyrobench.base import units
from gyrobench.sim.coil2d import Coil2D, Coil2DSpec, heated_stretch
from gyrobench.sim.coil_materials import SILICA_CTE_SLOPE_BOUNDS
from gyrobench.sim.coil_winding import Imperfections

_HOUR = 3600.0


def _material(spec: Coil2DSpec, which: str, **changes: float) -> Coil2DSpec:
    return dataclasses.replace(spec, **{which: dataclasses.replace(getattr(spec, which), **changes)})


def cases(base: Coil2DSpec) -> list[tuple[str, Coil2DSpec]]:
    """(label, spec) for the defaults and each assumed input at its low and high value."""
    out = [("defaults", base)]
    lo, hi = SILICA_CTE_SLOPE_BOUNDS
    for v in (lo, hi):
        a300 = base.glass.cte + base.glass.cte_slope * (300.0 - 293.15)
        out.append(
            (f"silica d(alpha)/dT = {v:.2g}",
             _material(base, "glass", cte_slope=v, cte=a300 - v * (300.0 - 293.15)))
        )
    for f in (0.5, 2.0):
        c = base.coating
        out += [
            (f"acrylate k x{f}", _material(base, "coating", conductivity=c.conductivity * f)),
            (f"acrylate rho c x{f}",
             _material(base, "coating", volumetric_heat_capacity=c.volumetric_heat_capacity * f)),
            (f"epoxy slope x{f}", _material(base, "matrix", cte_slope=base.matrix.cte_slope * f)),
            (f"gap h x{f}", dataclasses.replace(base, gap_coefficient=base.gap_coefficient * f)),
            (f"mount h_c x{f}",
             dataclasses.replace(base, mount_coefficient=base.mount_coefficient * f)),
            (f"chamber G x{f}",
             dataclasses.replace(base, chamber_conductance=base.chamber_conductance * f)),
        ]
    return out


def txdt_point(spec: Coil2DSpec, radius: float | None) -> float:
    """Peak T x dT term [deg/h] of paper 003's Table-1 heated stretch."""
    T = units.celsius(np.linspace(-10.0, 40.0, 51))
    _, prod = heated_stretch(
        spec, T, 1.0 / 60.0, fibre_length=1000.0, diameter=0.1, z_center=250.0,
        seg_length=10.0, radius=radius,
    )
    return float(np.max(np.abs(units.to_deg_per_h(prod))))


def median_drift(spec: Coil2DSpec, n_units: int) -> float:
    """Median over drawn units of the peak drift [deg/h] under validation-1's program."""
    tk = np.array([0.0, 1.0, 6.0, 7.0]) * _HOUR
    vk = units.celsius(np.array([-10.0, -10.0, 40.0, 40.0]))
    peaks = []
    for seed in range(n_units):
        imp = Imperfections.draw(spec, rng=np.random.default_rng(seed))
        run = Coil2D(spec=spec, imperfections=imp).run(tk, vk)
        peaks.append(np.max(np.abs(units.to_deg_per_h(run.total))))
    return float(np.median(peaks))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--units", type=int, default=8)
    args = ap.parse_args()
    base = Coil2DSpec()
    mid = 0.5 * (base.inner_radius + base.outer_radius)
    ref = None
    print(f"{'case':32s} {'TxdT free':>10s} {'TxdT bonded':>12s} {'drift med':>10s}  (deg/h;"
          f" change vs defaults)")
    t0 = time.perf_counter()
    for label, spec in cases(base):
        row = (txdt_point(spec, None), txdt_point(spec, mid), median_drift(spec, args.units))
        ref = ref or row
        rel = [f"{v:.4f} ({100 * (v / r - 1):+.1f} %)" for v, r in zip(row, ref, strict=True)]
        print(f"{label:32s} " + "  ".join(rel), flush=True)
    print(f"{time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
