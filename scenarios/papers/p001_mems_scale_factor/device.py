"""Paper 001's device: units of the MEMS resonator population and their noise-free static output.

The device (:mod:`gyrobench.sim.mems_resonator`): a lumped 2-DOF Coriolis vibratory gyro with
force rebalance whose high-range knee is the rebalance DAC's authority,
Omega_max = sqrt(F_max^2 - F_q^2) / (2 m w X0), flat beyond it (docs/physics.md 5.1). Unit
``seed`` is drawn from the first child stream of ``numpy.random.default_rng(seed)``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from gyrobench.analysis.scale_factor import fit_scale_factor
from gyrobench.base import units
from gyrobench.sim import mems_resonator as mr
from gyrobench.sim.mems_nonlinear import RateTransfer
from gyrobench.sim.mems_resonator import MemsResonator, MemsResonatorSpec

from .config import CALIBRATED_V_MAX_V, PAPER_RAW_KN, Config, default_rates

__all__ = ["calibrated_v_max", "device_spec", "draw_unit", "rate_authority_dps", "rate_transfer", "static_output"]


def device_spec(config: Config) -> MemsResonatorSpec:
    """The population of ``config.variant`` (the calibrated one has v_max = CALIBRATED_V_MAX_V)."""
    if config.variant == "calibrated":
        nom = replace(config.gyro.nominal, dac_full_scale=CALIBRATED_V_MAX_V)
        return replace(config.gyro, nominal=nom)
    return config.gyro


def rate_transfer(config: Config) -> RateTransfer:
    """The static rate transfer of ``config.variant``'s read-out (identity but for "identified").

    "identified": the Rapp front-end compression of :data:`~.identify.IDENTIFIED` (CALIBRATED),
    applied to the resonator's rate output (noise, bias and turn-on errors pass through it).
    """
    if config.variant == "identified":
        from .identify import IDENTIFIED, transfer_of

        return transfer_of(IDENTIFIED)
    return RateTransfer()


def draw_unit(spec: MemsResonatorSpec, seed: int) -> MemsResonator:
    """Unit ``seed`` of the population: realized from the first child of default_rng(seed)."""
    r_unit, _ = np.random.default_rng(seed).spawn(2)
    return spec.realize(rng=r_unit)


def rate_authority_dps(unit: MemsResonator) -> float:
    """The unit's rate authority (the knee) at its reference temperature [deg/s]."""
    return float(units.to_deg_per_s(mr.rate_authority(unit)))


def static_output(
    unit: MemsResonator,
    rates_dps: NDArray[np.float64],
    temperature: float,
    transfer: RateTransfer | None = None,
) -> NDArray[np.float64]:
    """Noise-free settled output [deg/s] of one power-on at constant rates and temperature [K].

    The slow flow without noise, 1/f term and ADC, run for 1 s at 200 Hz from each rate's
    (clamped) equilibrium; the mean of the last 0.1 s. Linear columns start at their
    equilibrium; saturated ones settle within the loop's time constants (tens of ms). Equals
    SF Omega + ZRO below the authority and ``mems_resonator.saturated_output`` beyond it (test).
    ``transfer`` (default none) is the read-out's static rate transfer (:func:`rate_transfer`).
    """
    w = units.deg_per_s(np.asarray(rates_dps, dtype=float))
    col = np.broadcast_to(w, (200, w.size))
    res = mr.slow_flow(
        unit, col, fs=200.0, rng=np.random.default_rng(0), temperature=temperature,
        noise=False, adc=False, flicker=False,
    )
    out = res.output[-20:].mean(axis=0)
    if transfer is not None:
        out = transfer(out)
    return units.to_deg_per_s(out)


def calibrated_v_max(
    spec: MemsResonatorSpec | None = None,
    seeds: Sequence[int] = tuple(range(20)),
    rates_dps: Sequence[float] | None = None,
) -> float:
    """v_max [V] such that the median noise-free raw K_n of the units ``seeds`` is 15.71 %.

    The units are those the experiment draws (:func:`draw_unit`), trimmed, at T0, without
    turn-on errors; K_n (IEEE, F_m = max |F|) of the noise-free table (:func:`static_output`)
    on the paper's 21 rates. The draws do not depend on v_max, so the same units are
    evaluated at each trial value (scipy brentq between 0.3 and 1 x the nominal v_max).
    This is the CALIBRATION behind :data:`~.config.CALIBRATED_V_MAX_V`.
    """
    from scipy.optimize import brentq

    base = MemsResonatorSpec() if spec is None else spec
    rates = np.asarray(default_rates() if rates_dps is None else rates_dps, dtype=float)
    drawn = [draw_unit(base, s) for s in seeds]
    t0 = base.nominal.reference_temperature

    def excess(v: float) -> float:
        kns = [
            fit_scale_factor(rates, static_output(replace(u, dac_full_scale=v), rates, t0))
            .nonlinearity
            for u in drawn
        ]
        return float(np.median(kns)) - PAPER_RAW_KN

    v0 = base.nominal.dac_full_scale
    return float(brentq(excess, 0.3 * v0, v0, xtol=1e-5))
