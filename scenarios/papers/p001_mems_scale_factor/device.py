"""Paper 001's device: units of the MEMS resonator population, their read-out, and their noise-free static output.

The resonator (:mod:`gyrobench.sim.mems_resonator`): a lumped 2-DOF Coriolis vibratory gyro.
``Config.variant`` selects the read-out (docs/physics.md 5.1, 5.2):

* ``"identified"`` (default) and ``"readout_design"``: OPEN LOOP through the physical sense
  chain of :mod:`gyrobench.sim.mems_readout` (the sense mode's amplitude-dependent stiffness,
  the differential pick-off's 1/(g - y), the charge amplifier's rail), one chain per unit
  drawn from ``Config.readout`` (:class:`~gyrobench.sim.mems_readout.SenseChainSpec`: the
  manufacturing tolerances), and the output word's range as the ADC. "identified" sets the
  nominal feedback capacitor to the one identified from the paper's raw K_n
  (:data:`~.identify.IDENTIFIED`, CALIBRATED); "readout_design" keeps the design value.
* ``"design"`` and ``"calibrated"``: FORCE REBALANCE, whose high-range knee is the rebalance
  DAC's authority, Omega_max = sqrt(F_max^2 - F_q^2) / (2 m w X0), flat beyond it (the
  closed loop holds y ~ 0, where the chain is linear); "calibrated" sets v_max from the
  paper's raw K_n.
* ``"rapp"``: PHENOMENOLOGICAL, labelled: the force-rebalanced unit's output through a fitted
  two-parameter amplifier (Rapp) curve (:data:`~.identify.RAPP_IDENTIFIED`), not a read-out.

Unit ``seed``'s resonator is drawn from the first child stream of
``numpy.random.default_rng(seed)``, its chain from the third (the second is the runs').
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from gyrobench.analysis.scale_factor import fit_scale_factor
from gyrobench.base import units
from gyrobench.sim import mems_population
from gyrobench.sim import mems_resonator as mr
from gyrobench.sim.mems_nonlinear import RateTransfer
from gyrobench.sim.mems_population import MemsResonatorSpec
from gyrobench.sim.mems_readout import SenseChainSpec
from gyrobench.sim.mems_resonator import MemsResonator
from gyrobench.sim.sensor import Environment

from .config import CALIBRATED_V_MAX_V, OPEN_LOOP_VARIANTS, PAPER_RAW_KN, Config, default_rates

__all__ = [
    "DeviceSpec",
    "calibrated_v_max",
    "clip_onset_dps",
    "device_spec",
    "draw_unit",
    "rate_authority_dps",
    "rate_transfer",
    "static_output",
]


@dataclass(frozen=True, slots=True, kw_only=True)
class DeviceSpec:
    """A variant's population: the resonators and, open loop, their sense chains (None: rebalanced).

    Parameters
    ----------
    resonator : MemsResonatorSpec
        The resonators' population.
    chain : SenseChainSpec or None
        Their sense chains' population (None: force rebalance).
    """

    resonator: MemsResonatorSpec
    chain: SenseChainSpec | None = None

    @property
    def nominal(self) -> MemsResonator:
        """The nominal resonator (with the read-out of the variant; the chain not attached)."""
        return self.resonator.nominal


def device_spec(config: Config) -> DeviceSpec:
    """The population of ``config.variant`` (module docstring).

    Parameters
    ----------
    config : Config
        The configuration.

    Returns
    -------
    DeviceSpec
        The variant's population.
    """
    if config.variant in OPEN_LOOP_VARIANTS:
        nom = replace(config.gyro.nominal, readout="open_loop")
        chain = config.readout
        if config.variant == "identified":
            from .identify import identified_chain_spec

            chain = identified_chain_spec(chain)
        return DeviceSpec(resonator=replace(config.gyro, nominal=nom), chain=chain)
    if config.variant == "calibrated":
        nom = replace(config.gyro.nominal, dac_full_scale=CALIBRATED_V_MAX_V)
        return DeviceSpec(resonator=replace(config.gyro, nominal=nom))
    return DeviceSpec(resonator=config.gyro)


def rate_transfer(config: Config) -> RateTransfer:
    """The static rate transfer applied after the resonator: the identity but for "rapp".

    "rapp": the fitted Rapp curve of :data:`~.identify.RAPP_IDENTIFIED` (PHENOMENOLOGICAL,
    CALIBRATED), applied to the resonator's rate output (noise, bias and turn-on errors pass
    through it). Every other variant's nonlinearity is inside the unit (its read-out).

    Parameters
    ----------
    config : Config
        The configuration.

    Returns
    -------
    RateTransfer
        The identity, or the fitted Rapp curve for the "rapp" variant.
    """
    if config.variant == "rapp":
        from .identify import transfer_of

        return transfer_of()
    return RateTransfer()


def draw_unit(spec: DeviceSpec | MemsResonatorSpec, seed: int) -> MemsResonator:
    """Draw unit ``seed`` of a population.

    Unit ``seed``: the resonator realized from the first child of default_rng(seed), and, for
    an open-loop population, its sense chain from the third (then factory-trimmed at T0).

    Parameters
    ----------
    spec : DeviceSpec or MemsResonatorSpec
        The population.
    seed : int
        The unit's seed.

    Returns
    -------
    MemsResonator
        The resonator realized from the first child of default_rng(seed) and, open loop, its
        sense chain from the third (then factory-trimmed at T0).
    """
    res = spec.resonator if isinstance(spec, DeviceSpec) else spec
    r_unit, _, r_chain = np.random.default_rng(seed).spawn(3)
    unit = res.realize(rng=r_unit)
    if isinstance(spec, DeviceSpec) and spec.chain is not None:
        unit = replace(unit, sense_chain=spec.chain.realize(rng=r_chain))
        if res.factory_trim:
            unit = mems_population.factory_trim(unit)
    return unit


def clip_onset_dps(unit: MemsResonator) -> float:
    """The positive rate [deg/s] at which an open-loop unit's front end reaches its rail (T0, noise-free).

    The rate where the stiffened sense envelope |B| (quadrature included) reaches the clip
    displacement y_c of :class:`~gyrobench.sim.mems_readout.SenseChain` (scipy brentq); inf when
    it is not reached below 10^5 deg/s.

    Parameters
    ----------
    unit : MemsResonator
        An open-loop unit.

    Returns
    -------
    float
        The rate [deg/s]; inf when the rail is never reached.
    """
    from scipy.optimize import brentq

    chain = unit.sense_chain
    if chain is None:
        raise ValueError("clip_onset_dps needs an open-loop unit with a sense_chain")
    op = mr.operating_point(unit)

    def excess(dps: float) -> float:
        b = op.receptance * mr.external_force(op, np.array([units.deg_per_s(dps)]), np.zeros(1))
        return float(np.abs(chain.stiffened_envelope(b, op.receptance))[0]) - chain.clip_displacement

    if excess(0.0) >= 0:
        return 0.0
    hi = 1e5
    while True:  # the largest rate below 1e5 deg/s whose sense amplitude has a stable root
        try:
            top = excess(hi)
            break
        except ValueError:
            hi *= 0.5
    if top < 0:
        return float("inf")
    return float(brentq(excess, 0.0, hi, xtol=1e-6))


def rate_authority_dps(unit: MemsResonator) -> float:
    """The unit's knee at its reference temperature [deg/s].

    The unit's knee at its reference temperature [deg/s]: the rebalance authority, or, open
    loop through a sense chain, the rate at which its front end reaches the rail.

    Parameters
    ----------
    unit : MemsResonator
        The unit.

    Returns
    -------
    float
        The rebalance authority or, open loop, the rate where the front end reaches its rail.
    """
    if unit.sense_chain is not None:
        return clip_onset_dps(unit)
    return float(units.to_deg_per_s(mr.rate_authority(unit)))


#: rates one slow-flow call of :func:`static_output` holds at once (200 samples each): its
#: working set is bounded by ``200 STATIC_CHUNK`` samples whatever the sweep's length
STATIC_CHUNK = 512


def static_output(
    unit: MemsResonator,
    rates_dps: NDArray[np.float64],
    temperature: float,
    transfer: RateTransfer | None = None,
) -> NDArray[np.float64]:
    """Noise-free settled output [deg/s] of one power-on at constant rates and temperature [K].

    The unit's ``idealization="noise_free_analog"`` twin (no noise, 1/f term or ADC) through
    ``simulate``, 1 s at 200 Hz from each rate's (clamped) equilibrium, the rates as the
    independent columns of an (n, k) ``true_rate``; the mean of the last 0.1 s. Linear columns start at their
    equilibrium; saturated ones settle within the loop's time constants (tens of ms). Equals
    SF Omega + ZRO below the authority and ``mems_resonator.saturated_output`` beyond it (test).
    ``transfer`` (default none) is the read-out's static rate transfer (:func:`rate_transfer`).

    Parameters
    ----------
    unit : MemsResonator
        One power-on.
    rates_dps : ndarray
        Constant rates [deg/s].
    temperature : float
        Die temperature [K].
    transfer : RateTransfer or None
        The static transfer applied after the resonator (None: none).

    Returns
    -------
    ndarray
        The settled output per rate [deg/s].
    """
    w = units.deg_per_s(np.asarray(rates_dps, dtype=float))
    out = np.empty(w.size)
    quiet = replace(unit, idealization="noise_free_analog", error_split="total")  # draws nothing from its rng
    for lo in range(0, w.size, STATIC_CHUNK):  # the columns are independent: a bounded block at a time
        k = min(STATIC_CHUNK, w.size - lo)
        col = np.ascontiguousarray(np.broadcast_to(w[lo : lo + STATIC_CHUNK], (200, k)))
        rec = quiet.simulate(
            Environment(1.0, true_rate=col if k > 1 else col[:, 0], temperature=temperature),
            fs=200.0, rng=np.random.default_rng(0),
        )
        settled = np.ascontiguousarray(rec["output"].reshape(k, 200).T)  # the record holds column after column
        out[lo : lo + STATIC_CHUNK] = settled[-20:].mean(axis=0)
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

    Parameters
    ----------
    spec : MemsResonatorSpec or None
        The population (None: the default variant's).
    seeds : sequence of int
        The units the median is over.
    rates_dps : sequence of float or None
        The table rates [deg/s] (None: the paper's).

    Returns
    -------
    float
        v_max [V].
    """
    from scipy.optimize import brentq

    base = MemsResonatorSpec() if spec is None else spec
    rates = np.asarray(default_rates() if rates_dps is None else rates_dps, dtype=float)
    drawn = [draw_unit(base, s) for s in seeds]  # the resonators only (rebalanced)
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
