"""Paper 001's rate table on the resonator-physics MEMS gyro (sim/mems_resonator.py), by hand.

Run: ``python benchmarks/mems_resonator_rate_table.py [--units 20] [--seed 0]``.
Prints (never asserts), for the default population (``MemsResonatorSpec()``) and for a
variant whose rebalance DAC limit v_max is CALIBRATED so that the median noise-free raw K_n
of the same drawn units is the paper's 15.71 %:

* the time to simulate one unit's table (21 rates, +-3600 deg/s step 360, 200 Hz, 90 s
  averaged after 0.5 s settling, one power-on per table);
* the raw K_n (IEEE, F_m = max |F|) of each unit, its median and range;
* where the paper's heuristic breakpoint search (analysis.scale_factor.breakpoint_search)
  splits each table.
"""

from __future__ import annotations

import argparse
import os
import time
from dataclasses import replace

import numpy as np

from gyrobench.analysis.scale_factor import breakpoint_search, fit_scale_factor
from gyrobench.base import units
from gyrobench.sim.mems_population import MemsResonatorSpec
from gyrobench.sim.mems_resonator import (
    MemsResonator,
    low_rate_scale_factor,
    rate_authority,
    saturated_output,
    zero_rate_output,
)
from gyrobench.sim.mems_slow_flow import rate_table

RATES_DPS = np.arange(3600.0, -3601.0, -360.0)
PAPER_KN = 0.1571


def noise_free_table(unit: MemsResonator, rates: np.ndarray) -> np.ndarray:
    """Closed-form noise-free table: linear below the authority, the plateau beyond."""
    sf, zro = low_rate_scale_factor(unit), zero_rate_output(unit)
    auth = rate_authority(unit)
    out = sf * rates + zro
    for i, w in enumerate(rates):
        if abs(w) > auth:
            out[i] = saturated_output(unit, float(w))
    return out


def draw_units(spec: MemsResonatorSpec, n_units: int, seed: int) -> list[MemsResonator]:
    """The units of :func:`run` (same streams): realize, then one power-on each."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n_units):
        r_unit, r_on, _ = rng.spawn(3)
        out.append(spec.realize(rng=r_unit).power_on(rng=r_on))
    return out


def calibrated_vmax(spec: MemsResonatorSpec, n_units: int, seed: int,
                    target: float = PAPER_KN) -> float:
    """v_max [V] such that the median noise-free raw K_n of the drawn units equals ``target``.

    The draws of :meth:`MemsResonatorSpec.realize` do not depend on v_max, so the same units
    are evaluated at each trial v_max (closed-form noise-free tables).
    """
    from scipy.optimize import brentq

    w = units.deg_per_s(RATES_DPS)
    drawn = draw_units(spec, n_units, seed)

    def kn(v: float) -> float:
        vals = [fit_scale_factor(w, noise_free_table(replace(u, dac_full_scale=v), w)).nonlinearity
                for u in drawn]
        return float(np.median(vals)) - target

    return brentq(kn, 0.4 * spec.nominal.dac_full_scale, spec.nominal.dac_full_scale, xtol=1e-7)


def run(spec: MemsResonatorSpec, n_units: int, seed: int, label: str) -> None:
    rng = np.random.default_rng(seed)
    w = units.deg_per_s(RATES_DPS)
    kns, bps, times = [], [], []
    for _ in range(n_units):
        r_unit, r_on, r_run = rng.spawn(3)
        unit = spec.realize(rng=r_unit).power_on(rng=r_on)
        t0 = time.perf_counter()
        table = rate_table(unit, w, rng=r_run, fs=200.0, average_s=90.0, settle_s=0.5)
        times.append(time.perf_counter() - t0)
        f_dps = units.to_deg_per_s(table)
        kns.append(fit_scale_factor(RATES_DPS, f_dps).nonlinearity)
        bs = breakpoint_search(RATES_DPS, f_dps)
        bps.append((bs.negative, bs.positive))
        print(
            f"  unit: authority {units.to_deg_per_s(rate_authority(unit)):7.0f} deg/s, "
            f"raw K_n {1e6 * kns[-1]:10.2f} ppm, breakpoints {bps[-1]}, {times[-1]:.2f} s"
        )
    kn = np.array(kns)
    print(f"{label}: {n_units} units, time per unit median {np.median(times):.2f} s "
          f"(min {min(times):.2f}, max {max(times):.2f})")
    print(f"  raw K_n ppm: median {1e6 * np.median(kn):.2f}, min {1e6 * kn.min():.2f}, "
          f"max {1e6 * kn.max():.2f}")
    pos = [b[1] for b in bps]
    neg = [b[0] for b in bps]
    for name, vals in (("positive", pos), ("negative", neg)):
        vals_s = [str(v) for v in vals]
        uniq = sorted(set(vals_s))
        print(f"  {name} breakpoints: " + ", ".join(f"{u} x{vals_s.count(u)}" for u in uniq))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--units", type=int, default=20)
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args()
    print(f"nproc {os.cpu_count()}, load {os.getloadavg()}")
    spec = MemsResonatorSpec()
    run(spec, a.units, a.seed, "default design")
    v = calibrated_vmax(spec, a.units, a.seed)
    auth = rate_authority(replace(spec.nominal, dac_full_scale=v))
    print(f"calibrated v_max = {v:.5f} V (default {spec.nominal.dac_full_scale} V): nominal "
          f"authority {units.to_deg_per_s(auth):.0f} deg/s")
    run(replace(spec, nominal=replace(spec.nominal, dac_full_scale=v)), a.units, a.seed,
        "v_max calibrated to K_n = 15.71 %")


if __name__ == "__main__":
    main()
