"""Built-in parts mapped onto their technology's physics model: one parameter solved for the sheet's ARW.

Each physics model sets the angle random walk N from physical parameters by a closed form. A
datasheet gives one number for it, so each mapping fixes every parameter at the model's
DEFAULT DESIGN (an assumption: the sheets read publish none of them) and solves ONE named
parameter for the sheet's N. The bias instability is the model's flicker (1/f) term at the
sheet's B (:meth:`Datasheet.bias_instability`; none when the sheet gives none). What the
sheet does not give is left out, not invented. :func:`physics_summary` says in one line what
a part maps to, or why it does not (``gyrobench parts``).

RLG (:func:`rlg_spec`), the lock-in rate
    The statistical RLG model (:mod:`gyrobench.sim.rlg`) sets N by dithering through lock-in,
    N = Omega_L sqrt((1 + j^2) / (2 pi K Omega_D)) (:func:`gyrobench.sim.rlg.dither_arw`,
    docs/physics.md 6.3; K the scale factor [counts/rad] of the cavity geometry, Omega_D the
    dither peak rate, j its amplitude jitter). With the default cavity and dither the sheet's
    N_s fixes Omega_L = N_s / sqrt((1 + j^2) / (2 pi K Omega_D)). The turn-on bias spread is
    the sheet's bias repeatability (0 when not given); no lock-in spread, no thermal
    mechanisms (sizes 0). The count quantization of the default cavity (pulse weight 1.61
    arcsec) adds the model's Q term.

FOG (:func:`fog_spec`), the source power
    The closed-loop FOG on the (r, z) coil (:class:`gyrobench.sim.fog2d.FOG2DSpec`) has
    N = sqrt(S_phi / 2) / SF0 (:meth:`gyrobench.sim.fog_loop.LoopSpec.arw`), SF0 = 2 pi L D /
    (lambda c) of the default coil and S_phi the one-sided phase-noise PSD of the
    :class:`gyrobench.sim.fog_optics.OpticalBudget` at the loop's bias phase. At source power
    P, with x = P0 / P against the default P0 = 10 mW, the three terms scale as

        S_phi(x) = S_shot0 x + S_rin + S_th0 x^2      (shot ~ 1/P, excess RIN ~ P^0, thermal ~ 1/P^2)

    so the sheet's N_s gives S* = 2 (N_s SF0)^2 and the positive root
    x = (-S_shot0 + sqrt(S_shot0^2 + 4 S_th0 (S* - S_rin))) / (2 S_th0), P = P0 / x. It exists
    only above the RIN floor N_rin = sqrt(S_rin / 2) / SF0 of the default source's spectral
    width and coil (1.3e-3 deg/sqrt(h) at the defaults): a sheet below it needs a longer coil
    or a wider source, which one figure cannot choose (ValueError). The additive IEEE term is
    the sheet's B only (the default design's assumed 0.05 deg/h bias and 0.003 deg/h B are
    replaced); the turn-on bias and scale-factor repeatabilities have no term in this model
    (the datasheet layer :class:`~gyrobench.sim.parts.Part` draws them). Each drawn unit winds
    its own coil, so its SF0 and N differ from the nominal coil's by the winding spread.

MEMS (:func:`mems_spec`), the pick-off (front-end) noise
    The resonator model (:mod:`gyrobench.sim.mems_resonator`) has N^2 = N_B^2 + N_e^2, the
    Brownian N_B = sqrt(k_B T c_y) / (m w X0) (:func:`~gyrobench.sim.mems_resonator.brownian_arw`)
    and the pick-off N_e = sqrt(S_n) / (|R| 2 m w X0)
    (:func:`~gyrobench.sim.mems_resonator.electronic_arw`). With the default resonator
    (mass, drive, Q, split: a +-3600 deg/s design) N_B is fixed and the sheet's N fixes the
    pick-off noise sqrt(S_n) = sqrt(N^2 - N_B^2) |R| 2 m w X0
    (:meth:`~gyrobench.sim.mems_resonator.MemsResonatorSpec.from_datasheet`, which performs this
    solve); a sheet at or below the Brownian floor (0.327 deg/sqrt(h) for the default design, a
    light high-range resonator: most tactical and industrial sheets are below it) would need a
    heavier or larger-amplitude resonator, which one figure cannot choose (ValueError). Range: the sheet's (the output
    full scale 10/9 of it, the rebalance authority 1.3 x; the default +-3600 deg/s when the
    sheet gives none); the output word is the model's 20 bits over that full scale, not the
    sheet's resolution. Turn-on bias and scale-factor repeatability: the sheet's (1 sigma, 0
    when not given). The population spreads (mass, frequency, Q, gap, quadrature, ...) are set
    to 0: the sheet gives none, and a spread would move each unit's N off the sheet's.
"""

from __future__ import annotations

import math
from dataclasses import replace

from gyrobench.sim import units
from gyrobench.sim.coil2d import Coil2D
from gyrobench.sim.fog2d import FOG2DSpec
from gyrobench.sim.mems_resonator import MemsResonator, MemsResonatorSpec, brownian_arw
from gyrobench.sim.noise import NoiseModel
from gyrobench.sim.parts._part import Datasheet
from gyrobench.sim.rlg import RLGSpec, ThermalBias

__all__ = ["rlg_spec", "fog_spec", "mems_spec", "physics_summary"]


def _check(datasheet: object, technology: str, caller: str) -> Datasheet:
    if not isinstance(datasheet, Datasheet):
        raise TypeError(f"datasheet must be a Datasheet; got {type(datasheet).__name__}")
    if datasheet.technology != technology:
        raise ValueError(f"{caller} needs an {technology} part; {datasheet.name!r} is {datasheet.technology}")
    return datasheet


def rlg_spec(datasheet: Datasheet) -> RLGSpec:
    """The :class:`RLGSpec` of an RLG part: lock-in rate from the sheet's ARW (module docstring).

    Raises
    ------
    TypeError
        ``datasheet`` is not a Datasheet.
    ValueError
        The part is not an RLG, or the solved lock-in rate is not below the dither peak rate.
    """
    datasheet = _check(datasheet, "RLG", "rlg_spec")
    base = RLGSpec()
    d = base.dither
    lock_in = datasheet.angle_random_walk() / math.sqrt(
        (1.0 + d.amplitude_jitter**2) / (2.0 * math.pi * base.geometry.scale_factor * d.peak_rate)
    )
    if not lock_in < d.peak_rate:
        raise ValueError(
            f"{datasheet.name!r}: ARW {datasheet.arw!r} deg/sqrt(h) needs a lock-in rate {lock_in!r} rad/s not below "
            f"the default dither peak rate {d.peak_rate!r} rad/s"
        )
    return RLGSpec(
        lock_in_rate=lock_in,
        lock_in_spread=0.0,
        thermal_bias=ThermalBias(),
        bias_spread=units.deg_per_h(datasheet.bias_repeatability or 0.0),
        bias_repeatability=0.0,
        bias_instability=datasheet.bias_instability(),
    )


def fog_spec(datasheet: Datasheet) -> FOG2DSpec:
    """The :class:`FOG2DSpec` of a FOG part: source power from the sheet's ARW (module docstring).

    Raises
    ------
    TypeError
        ``datasheet`` is not a Datasheet.
    ValueError
        The part is not a FOG, or its ARW is at or below the default design's RIN floor.
    """
    datasheet = _check(datasheet, "FOG", "fog_spec")
    base = FOG2DSpec()
    fibre = Coil2D(spec=base.coil).fibre()  # the nominal (ideal) winding
    loop = base.loop_spec(length=fibre.length, diameter=fibre.diameter)
    psd = base.optics.phase_psd(loop.bias_phase, loop.wavelength)
    sf0 = loop.scale_factor
    target = 2.0 * (datasheet.angle_random_walk() * sf0) ** 2
    floor = math.sqrt(psd["rin"] / 2.0) / sf0
    if not target > psd["rin"]:
        raise ValueError(
            f"{datasheet.name!r}: ARW {units.to_deg_per_s(datasheet.angle_random_walk()) * 60.0:.3g} deg/sqrt(h) is "
            f"not above the RIN floor {units.to_deg_per_s(floor) * 60.0:.3g} deg/sqrt(h) of the default FOG design"
        )
    a, b = psd["thermal"], psd["shot"]
    x = (-b + math.sqrt(b * b + 4.0 * a * (target - psd["rin"]))) / (2.0 * a)
    optics = replace(base.optics, source_power=base.optics.source_power / x)
    return replace(base, optics=optics, noise=NoiseModel(bias_instability=datasheet.bias_instability()))


def mems_spec(datasheet: Datasheet) -> MemsResonatorSpec:
    """The :class:`MemsResonatorSpec` of a MEMS part: pick-off noise from the sheet's ARW (module docstring).

    Raises
    ------
    TypeError
        ``datasheet`` is not a Datasheet.
    ValueError
        The part is not a MEMS gyro, or its ARW is below the default resonator's Brownian floor.
    """
    datasheet = _check(datasheet, "MEMS", "mems_spec")
    floor = brownian_arw(MemsResonator())
    if not datasheet.angle_random_walk() > floor:
        raise ValueError(
            f"{datasheet.name!r}: ARW {units.to_deg_per_s(datasheet.angle_random_walk()) * 60.0:.3g} deg/sqrt(h) is "
            f"not above the Brownian floor {units.to_deg_per_s(floor) * 60.0:.3g} deg/sqrt(h) of the default MEMS "
            "resonator"
        )
    try:
        spec = MemsResonatorSpec.from_datasheet(
            range_dps=datasheet.range_dps or 3600.0,
            noise_density_dps_rthz=units.to_deg_per_s(datasheet.angle_random_walk()),
            noise_density_convention="two-sided",
            bias_instability_dph=units.to_deg_per_h(datasheet.bias_instability()),
            bias_repeatability_dps=(datasheet.bias_repeatability or 0.0) / 3600.0,
            scale_factor_repeatability_ppm=datasheet.scale_factor_repeatability or 0.0,
            repeatability_convention="1-sigma",
        )
    except ValueError as exc:
        raise ValueError(f"{datasheet.name!r}: {exc}") from None
    return replace(
        spec, mass_spread=0.0, frequency_spread=0.0, split_spread=0.0, q_spread=0.0, gap_spread=0.0,
        quadrature_spread=0.0, damping_coupling_spread=0.0, phase_error_spread=0.0, phase_tc_spread=0.0,
    )


def physics_summary(datasheet: Datasheet) -> str:
    """One line: the physics parameter the sheet's ARW solves for and its value, or why it cannot.

    E.g. ``"fog_spec: source power 0.0367 mW (default FOG2D design otherwise)"``, or
    ``"not mapped: ..."`` with the solve's refusal (module docstring).
    """
    if not isinstance(datasheet, Datasheet):
        raise TypeError(f"datasheet must be a Datasheet; got {type(datasheet).__name__}")
    try:
        if datasheet.technology == "FOG":
            p = fog_spec(datasheet).optics.source_power
            return f"fog_spec: source power {p * 1e3:.4g} mW (default FOG2D design otherwise)"
        if datasheet.technology == "MEMS":
            x = mems_spec(datasheet).nominal.pickoff_noise
            return f"mems_spec: pick-off noise {x:.4g} m/sqrt(Hz) (default resonator otherwise)"
        w = rlg_spec(datasheet).lock_in_rate
        return f"rlg_spec: lock-in rate {units.to_deg_per_s(w):.4g} deg/s (default cavity and dither otherwise)"
    except ValueError as exc:
        return f"not mapped: {exc}"
