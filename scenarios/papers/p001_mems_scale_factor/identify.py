"""Identification of paper 001's prototype: the front-end rail of its open-loop sense chain.

The paper reports about its device (section 3): raw K_n 15.71 % over the 21 rates (+-3600
deg/s, mean over runs), the low rates nearly linear ("order 1e-3"), the nonlinearity growing
fast past a critical rate, and similar curves run to run. Our device is the default resonator
read out open loop through the physical sense chain of :mod:`gyrobench.sim.mems_readout`
(amplitude-dependent stiffness, the differential pick-off's 1/(g - y), the charge amplifier's
rail; every other size a design value with its reasoning in :class:`~gyrobench.sim.mems_readout.SenseChain`).
One number fixes one parameter, CALIBRATED:

* ``feedback_capacitance_f`` (C_f of the charge amplifier, which sets where the front end
  reaches its rail: the clip displacement y_c solves V_c dC(y_c)/C_f = V_rail),

solved (scipy brentq on log C_f) so that the noise-free output of the NOMINAL unit (no
unit-to-unit spread: zero quadrature, nominal chain; factory-trimmed) has K_n = 15.71 % on the
paper's 21 rates. Nothing else is set from the paper: the low-rate K_n, the bend's shape and
position, the unit-to-unit spread (from the chain's manufacturing tolerances and the
resonator's, quadrature included) and the run-to-run similarity are outputs.

:data:`IDENTIFIED` is the stored result with its inputs; a test re-runs
:func:`identify_p001_device` and checks it equals the constant.

The previous phenomenological device, a two-parameter amplifier (Rapp) curve solved from the
raw and low-rate K_n, is kept as the labelled variant ``"rapp"`` (:data:`RAPP_IDENTIFIED`,
:func:`transfer_of`): it is a fitted curve, not a read-out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from gyrobench.analysis.scale_factor import fit_scale_factor
from gyrobench.base import units
from gyrobench.sim import mems_population
from gyrobench.sim import mems_resonator as mr
from gyrobench.sim.mems_nonlinear import RateTransfer
from gyrobench.sim.mems_readout import SenseChain, SenseChainSpec

from .config import PAPER_RAW_KN, default_rates

__all__ = [
    "IDENTIFIED",
    "LOW_RATE_LIMIT_DPS",
    "PAPER_LOW_RATE_KN",
    "RAPP_IDENTIFIED",
    "Identification",
    "RappIdentification",
    "identify_p001_device",
    "nominal_open_loop_unit",
    "transfer_of",
]

#: the paper's low-rate nonlinearity ("order 1e-3", read as 1e-3) [-] (an output of the chain)
PAPER_LOW_RATE_KN = 1e-3
#: the paper's low-rate segment: between its breakpoints [deg/s]
LOW_RATE_LIMIT_DPS = 1800.0


@dataclass(frozen=True, slots=True, kw_only=True)
class Identification:
    """Inputs and result of the identification: the raw K_n target, the rates [deg/s], C_f [F].

    Attributes
    ----------
    raw_kn : float
        The raw K_n target [-].
    rates_dps : tuple of float
        The table rates [deg/s].
    feedback_capacitance_f : float
        The identified C_f [F].
    """

    raw_kn: float
    rates_dps: tuple[float, ...]
    feedback_capacitance_f: float


#: CALIBRATED: the stored result of identify_p001_device() (rtol 1e-9 on C_f)
IDENTIFIED = Identification(
    raw_kn=PAPER_RAW_KN, rates_dps=default_rates(), feedback_capacitance_f=1.8655385494588412e-15
)


def nominal_open_loop_unit(chain: SenseChain, resonator: mr.MemsResonator | None = None) -> mr.MemsResonator:
    """The nominal resonator read out open loop through ``chain``, factory-trimmed at T0.

    Parameters
    ----------
    chain : SenseChain
        The sense chain.
    resonator : MemsResonator or None
        The resonator (None: the default's).

    Returns
    -------
    MemsResonator
        The trimmed open-loop unit.
    """
    base = mr.MemsResonator() if resonator is None else resonator
    return mems_population.factory_trim(replace(base, readout="open_loop", sense_chain=chain))


def _nominal_kn(c_f: float, rates: np.ndarray, chain: SenseChain) -> float:
    unit = nominal_open_loop_unit(replace(chain, feedback_capacitance=c_f))
    out = units.to_deg_per_s(mr.static_rate_output(unit, units.deg_per_s(rates)))
    return fit_scale_factor(rates, out).nonlinearity


def identify_p001_device(
    raw_kn: float = PAPER_RAW_KN,
    rates_dps: tuple[float, ...] | None = None,
    chain: SenseChain | None = None,
) -> Identification:
    """Solve C_f for the given raw K_n on the nominal open-loop unit (module docstring).

    K_n grows as C_f shrinks (the rail is reached at a smaller displacement); brentq on
    log C_f between 1 fF and 1 pF.

    Parameters
    ----------
    raw_kn : float
        The raw K_n target [-].
    rates_dps : tuple of float or None
        The table rates [deg/s] (None: the paper's).
    chain : SenseChain or None
        The nominal chain (None: the default's).

    Returns
    -------
    Identification
        The target and the identified C_f.
    """
    from scipy.optimize import brentq

    rates = np.asarray(default_rates() if rates_dps is None else rates_dps, dtype=float)
    base = SenseChain() if chain is None else chain
    lo, hi = math.log(1.0001e-15), math.log(1e-12)
    x = brentq(lambda s: _nominal_kn(math.exp(s), rates, base) - raw_kn, lo, hi, xtol=1e-12, rtol=1e-12)
    return Identification(raw_kn=raw_kn, rates_dps=tuple(float(r) for r in rates), feedback_capacitance_f=math.exp(x))


def identified_chain_spec(spec: SenseChainSpec, ident: Identification | None = None) -> SenseChainSpec:
    """``spec`` with its nominal C_f the identified one (the unit-to-unit tolerances kept)."""
    i = IDENTIFIED if ident is None else ident
    return replace(spec, nominal=replace(spec.nominal, feedback_capacitance=i.feedback_capacitance_f))


# ------------------------------------------------------------------ the labelled phenomenological variant
@dataclass(frozen=True, slots=True, kw_only=True)
class RappIdentification:
    """The phenomenological Rapp curve of the ``"rapp"`` variant (field units: deg/s).

    Attributes
    ----------
    raw_kn : float
        The raw K_n target [-].
    low_rate_kn : float
        The low-rate K_n target [-].
    low_rate_limit_dps : float
        The low-rate span's limit [deg/s].
    rail_rate_dps : float
        The fitted saturation Omega_s [deg/s].
    rail_order : float
        The fitted smoothness p [-].
    """

    raw_kn: float
    low_rate_kn: float
    low_rate_limit_dps: float
    rail_rate_dps: float
    rail_order: float


#: PHENOMENOLOGICAL, CALIBRATED: a two-parameter amplifier curve solved from the raw and the
#: low-rate K_n (xtol 1e-6); the ``"rapp"`` variant only
RAPP_IDENTIFIED = RappIdentification(
    raw_kn=PAPER_RAW_KN,
    low_rate_kn=PAPER_LOW_RATE_KN,
    low_rate_limit_dps=LOW_RATE_LIMIT_DPS,
    rail_rate_dps=2773.690877906105,
    rail_order=4.62075899206396,
)


def transfer_of(ident: RappIdentification = RAPP_IDENTIFIED) -> RateTransfer:
    """The Rapp rate transfer (SI) of the ``"rapp"`` variant.

    Parameters
    ----------
    ident : RappIdentification
        The identified curve.

    Returns
    -------
    RateTransfer
        Its transfer in rad/s.
    """
    return RateTransfer(rail_rate=math.radians(ident.rail_rate_dps), rail_order=ident.rail_order)
