"""Built-in parts mapped onto their technology's physics model: the sheet's ARW solved for physical parameters.

Each physics model sets the angle random walk N from physical parameters by a closed form. A
datasheet gives one number for it, so each mapping fixes every parameter at the model's
DEFAULT DESIGN (an assumption: the sheets read publish none of them) and solves ONE named
parameter for the sheet's N; where that parameter cannot reach N inside its physical range
(the sheet is below the default design's floor), a SECOND one, named below, is solved first
inside its stated range. The bias instability is the model's flicker (1/f) term at the
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
    mechanisms (sizes 0: no source prints them). The random walk of this statistical form is
    the one validated against the full Adler equation of the cavity (checks
    ``rlg.dither_random_walk``, ``rlg_cavity.dither_random_walk``). The count quantization of
    the default cavity (pulse weight 1.61 arcsec) adds the model's Q term.

FOG (:func:`fog_spec`), the source power, and the coil below the default coil's reach
    The closed-loop FOG on the (r, z) coil (:class:`gyrobench.sim.fog2d.FOG2DSpec`) has
    N = sqrt(S_phi / 2) / SF0 (:meth:`gyrobench.sim.fog_loop.LoopSpec.arw`), SF0 = 2 pi L D /
    (lambda c) of the coil and S_phi the one-sided phase-noise PSD of the
    :class:`gyrobench.sim.fog_optics.OpticalBudget` at the loop's bias phase. At source power
    P, with x = P0 / P against the budget's P0, the three terms scale as

        S_phi(x) = S_shot0 x + S_rin + S_th0 x^2      (shot ~ 1/P, excess RIN ~ P^0, thermal ~ 1/P^2)

    so the sheet's N_s gives S* = 2 (N_s SF0)^2 and the positive root
    x = (-S_shot0 + sqrt(S_shot0^2 + 4 S_th0 (S* - S_rin))) / (2 S_th0), P = P0 / x. On the
    default coil (1.01 km, D 0.099 m) it exists only above the RIN floor
    N_rin = sqrt(S_rin / 2) / SF0 (1.31e-3 deg/sqrt(h)), and P grows without bound toward it.

    Second parameter, the coil's L D: when P would exceed :data:`FOG_POWER_MAX` (15 mW), the
    source sits at that cap and the coil is solved. The excess RIN does not depend on the
    coil or the power, shot and thermal noise only through the power at the detector, so
    N ~ 1/SF0 ~ 1/(L D) at a fixed budget: L D = (L D)_0 N_0 / N_s, iterated because the
    added fibre adds its loss (:data:`FIBRE_LOSS_DB_PER_M`, 1 dB/km, to the budget's 20 dB).
    L grows first at the default diameter up to :data:`FOG_LENGTH_MAX` (5 km), then D at 5 km
    up to :data:`FOG_DIAMETER_MAX` (0.2 m); the coil is rewound with the default pack's
    pitches (40 layers, radii shifted by (D - D0)/2, the height growing with the turns per
    layer): at the default D the fewest turns reaching L D, at the length limit the most turns
    keeping L <= 5 km with D grown in 0.1 mm steps until L D is reached, so neither limit is
    passed by the integer turns; P is then solved again on that coil (<= 15 mW). Beyond
    5 km x 0.2 m = 1000 m^2 (N below about 1.3e-4 deg/sqrt(h)) the part is refused with the
    L D it would need (ValueError). No sheet read gives its coil: astrix-200 (2e-4
    deg/sqrt(h)) maps to L 5.0 km, D 0.134 m, P 12.6 mW, an ASSUMED design.

    The additive IEEE term is the sheet's B only (the default design's assumed 0.05 deg/h
    bias and 0.003 deg/h B are replaced); the turn-on bias and scale-factor repeatabilities
    have no term in this model (the datasheet layer :class:`~gyrobench.sim.parts.Part` draws
    them). Each drawn unit winds its own coil, so its SF0 and N differ from the nominal
    coil's by the winding spread.

MEMS (:func:`mems_spec`), the pick-off (front-end) noise, and the proof mass below the Brownian floor
    The resonator model (:mod:`gyrobench.sim.mems_resonator`) has N^2 = N_B^2 + N_e^2, the
    Brownian N_B = sqrt(k_B T c_y) / (m w X0) (:func:`~gyrobench.sim.mems_resonator.brownian_arw`)
    and the pick-off N_e = sqrt(S_n) / (|R| 2 m w X0)
    (:func:`~gyrobench.sim.mems_resonator.electronic_arw`). With the default resonator
    (mass, drive, Q, split: a +-3600 deg/s design) N_B is fixed and the sheet's N fixes the
    pick-off noise sqrt(S_n) = sqrt(N^2 - N_B^2) |R| 2 m w X0
    (:meth:`~gyrobench.sim.mems_population.MemsResonatorSpec.from_datasheet`, which performs this
    solve); it exists only above the default Brownian floor, 0.327 deg/sqrt(h), a light
    high-range resonator (most tactical and industrial sheets are below it).

    Second parameter, the proof mass m: with c_y = m w_y / Q_y, N_B = sqrt(k_B T w_y / (m Q_y)) /
    (w X0) goes as m^(-1/2), while N_e does not depend on m (|R| = 1 / (m |w_y^2 - w^2 + j w_y
    w / Q_y|), so |R| m is fixed): the mass moves the Brownian term alone. Frequencies, Q,
    mode split and drive amplitude stay (a heavier mass of the same design: stiffness grows
    with it), and its electrode area grows in proportion (a larger plate at the same
    thickness and gap), which keeps the rebalance loop's R G, its DAC limit per unit range
    and the g-sensitivity of the default design. Below the default floor the mass is solved
    so that N_B = :data:`BROWNIAN_SHARE` N (1/sqrt 2: Brownian and pick-off noise equal, an
    ASSUMPTION, the sheets splitting N nowhere), m = m0 (N_B0 / (N/sqrt 2))^2, and the
    pick-off noise gives the rest; m <= :data:`MEMS_MASS_MAX` (5 mg), so N down to about
    0.0093 deg/sqrt(h) is reached, a lower sheet is refused with the mass it would need
    (ValueError). The other two handles were rejected: the drive amplitude X0 moves N_B and
    N_e together and would need 30x its 5 um for sch16t-k01 (150 um, beyond a drive comb's
    travel), and a higher sense Q narrows the sense bandwidth f_y/(2 Q_y) below the 40 Hz
    rebalance loop (unstable: :func:`~gyrobench.sim.mems_resonator.operating_point` refuses).
    Solved masses: stim300 0.019 mg, openrtk330 0.0047 mg, sch16t-k01 1.9 mg, adis16495-1
    0.053 mg, lsm6dsv 0.015 mg.

    Range: the sheet's (the output full scale 10/9 of it, the rebalance authority 1.3 x; the
    default +-3600 deg/s when the sheet gives none); the output word is the model's 20 bits
    over that full scale, not the sheet's resolution (its quantization adds q/sqrt(12 fs) to
    the white noise at output rate fs). Turn-on bias and scale-factor repeatability: the
    sheet's (1 sigma, 0 when not given). The population spreads (mass, frequency, Q, gap,
    quadrature, ...) are set to 0: the sheet gives none, and a spread would move each unit's
    N off the sheet's.
"""

from __future__ import annotations

import math
from dataclasses import replace

from gyrobench.base import units
from gyrobench.sim.coil2d import Coil2D, Coil2DSpec
from gyrobench.sim.fog2d import FOG2DSpec
from gyrobench.sim.fog_optics import OpticalBudget
from gyrobench.sim.mems_population import MemsResonatorSpec
from gyrobench.sim.mems_resonator import MemsResonator, brownian_arw
from gyrobench.sim.noise import NoiseModel
from gyrobench.sim.parts._part import Datasheet
from gyrobench.sim.rlg import RLGSpec, ThermalBias

__all__ = [
    "rlg_spec",
    "fog_spec",
    "mems_spec",
    "physics_summary",
    "FOG_POWER_MAX",
    "FOG_LENGTH_MAX",
    "FOG_DIAMETER_MAX",
    "FIBRE_LOSS_DB_PER_M",
    "MEMS_MASS_MAX",
    "BROWNIAN_SHARE",
]

FOG_POWER_MAX = 15e-3
"""Largest source power of the FOG solve [W]: the Er superfluorescent source the default budget
cites (:mod:`gyrobench.sim.fog_optics`: up to 15 mW from 70 mW of pump)."""

FOG_LENGTH_MAX = 5000.0
"""Longest coil fibre of the FOG solve [m]: FOG coils are "as long as 5 kilometres" (Wikipedia,
'Fibre-optic gyroscope'); ASSUMED as the physical range, no sheet read gives its coil."""

FOG_DIAMETER_MAX = 0.2
"""Largest mean coil diameter of the FOG solve [m]: ASSUMED; the largest unit read, Airbus's
Astrix 200, holds its four coils in a 300 mm diameter inertial core (product page), so a coil
is below 0.3 m; 0.2 m keeps it inside with its spool and housing."""

FIBRE_LOSS_DB_PER_M = 1e-3
"""Loss of the fibre a solved coil adds to the default 1 km [dB/m]: 1 dB/km, the upper end of the
0.5-1 dB/km the default 20 dB budget states for its 1 km (:mod:`gyrobench.sim.fog_optics`)."""

MEMS_MASS_MAX = 5e-6
"""Heaviest proof mass of the MEMS solve [kg]: ASSUMED bound, a silicon proof mass filling a
5 mm x 5 mm die in a 100 um device layer, 2329 kg/m^3 x 2.5e-9 m^3 = 5.8 mg, rounded down."""

BROWNIAN_SHARE = 1.0 / math.sqrt(2.0)
"""N_B / N of a MEMS part whose mass is solved: ASSUMED equal Brownian and pick-off noise
(N_B = N_e = N/sqrt 2), the sheets splitting N nowhere."""


def _check(datasheet: object, technology: str, caller: str) -> Datasheet:
    if not isinstance(datasheet, Datasheet):
        raise TypeError(f"datasheet must be a Datasheet; got {type(datasheet).__name__}")
    if datasheet.technology != technology:
        raise ValueError(f"{caller} needs an {technology} part; {datasheet.name!r} is {datasheet.technology}")
    return datasheet


def rlg_spec(datasheet: Datasheet) -> RLGSpec:
    """The :class:`RLGSpec` of an RLG part: lock-in rate from the sheet's ARW (module docstring).

    Parameters
    ----------
    datasheet : Datasheet
        The part's datasheet.

    Returns
    -------
    RLGSpec
        The RLG model with the solved lock-in rate; the default design otherwise.

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


def _rewound(base: Coil2DSpec, shift: float, turns: int) -> Coil2DSpec:
    """``base`` with every radius (bore, inner, outer) moved by ``shift`` [m] and ``turns`` turns per layer.

    The layer count and the axial pitch H0/N0 stay (the height grows with the turns): the pack's
    cross-section pitches are the default's.
    """
    return replace(
        base,
        bore_radius=base.bore_radius + shift,
        inner_radius=base.inner_radius + shift,
        outer_radius=base.outer_radius + shift,
        turns_per_layer=turns,
        height=base.height / base.turns_per_layer * turns,
    )


def _wound_coil(base: Coil2DSpec, product: float) -> Coil2DSpec | None:
    """The coil whose wound L D reaches ``product`` [m^2]: L first, at the default D, up to
    FOG_LENGTH_MAX, then D at the most turns that keep L <= FOG_LENGTH_MAX; None beyond
    FOG_DIAMETER_MAX.

    The turns per layer are integers, so L D lands at or just above ``product``; at the length
    limit the diameter grows in 0.1 mm steps until the wound L D reaches it.
    """
    fibre0 = Coil2D(spec=base).fibre()

    def wound(shift: float, turns: int) -> tuple[Coil2DSpec, float, float]:
        coil = _rewound(base, shift, turns)
        f = Coil2D(spec=coil).fibre()
        return coil, f.length, f.diameter

    turns = max(2, math.floor(base.turns_per_layer * product / (fibre0.length * fibre0.diameter)))
    coil, length, diameter = wound(0.0, turns)
    while length * diameter < product:
        turns += 1
        coil, length, diameter = wound(0.0, turns)
    if length <= FOG_LENGTH_MAX:
        return coil
    shift = max(0.0, 0.5 * (product / FOG_LENGTH_MAX - fibre0.diameter))
    while True:
        turns = max(2, math.floor(base.turns_per_layer * FOG_LENGTH_MAX / fibre0.length
                                  * fibre0.diameter / (fibre0.diameter + 2.0 * shift)))
        coil, length, diameter = wound(shift, turns)
        while length > FOG_LENGTH_MAX:
            turns -= 1
            coil, length, diameter = wound(shift, turns)
        while True:
            nxt, n_length, n_diameter = wound(shift, turns + 1)
            if n_length > FOG_LENGTH_MAX:
                break
            coil, length, diameter, turns = nxt, n_length, n_diameter, turns + 1
        if diameter > FOG_DIAMETER_MAX:
            return None
        if length * diameter >= product:
            return coil
        shift += 1e-4


def _fog_coil(datasheet: Datasheet, base: FOG2DSpec) -> tuple[Coil2DSpec, OpticalBudget]:
    """The coil (and its loss budget) whose N at the capped source power is at most the sheet's.

    SF0 ~ L D, and the phase-noise PSD at FOG_POWER_MAX depends on the coil only through the
    extra fibre's loss, so L D = L D(current) x N(current) / N_s is iterated until the
    wound coil's N <= N_s (the loss grows with L: a few passes). L grows first at the
    default diameter up to FOG_LENGTH_MAX, then D at FOG_LENGTH_MAX up to FOG_DIAMETER_MAX.
    """
    n = datasheet.angle_random_walk()
    fibre0 = Coil2D(spec=base.coil).fibre()
    coil = base.coil
    for _ in range(50):
        fibre = Coil2D(spec=coil).fibre()
        optics = replace(
            base.optics,
            source_power=FOG_POWER_MAX,
            loss_db=base.optics.loss_db + FIBRE_LOSS_DB_PER_M * (fibre.length - fibre0.length),
        )
        arw = base.loop_spec(length=fibre.length, diameter=fibre.diameter).arw(optics)
        if arw <= n:
            return coil, optics
        product = fibre.length * fibre.diameter * arw / n
        wound = _wound_coil(base.coil, product)
        if wound is None:
            raise ValueError(
                f"{datasheet.name!r}: ARW {units.to_deg_per_s(n) * 60.0:.3g} deg/sqrt(h) needs a coil "
                f"L D = {product:.5g} m^2 at the {FOG_POWER_MAX * 1e3:g} mW source cap, beyond the "
                f"{FOG_LENGTH_MAX / 1e3:g} km x {FOG_DIAMETER_MAX:g} m coil limit"
            )
        coil = wound
    raise RuntimeError(f"{datasheet.name!r}: the coil solve did not settle in 50 passes")  # pragma: no cover


def _power_for(target: float, psd: dict[str, float], power: float) -> float:
    """The source power whose S_phi(P) is ``target`` (module docstring), given the PSDs at ``power``."""
    a, b = psd["thermal"], psd["shot"]
    x = (-b + math.sqrt(b * b + 4.0 * a * (target - psd["rin"]))) / (2.0 * a)
    return power / x


def fog_spec(datasheet: Datasheet) -> FOG2DSpec:
    """The :class:`FOG2DSpec` of a FOG part: source power from the sheet's ARW, the coil when it must.

    The source power is solved on the default coil; when it would exceed FOG_POWER_MAX (the
    sheet is at or near the default coil's RIN floor) the power is capped there and the
    coil's L D is solved, then the power again on the wound coil (module docstring).

    Parameters
    ----------
    datasheet : Datasheet
        The part's datasheet.

    Returns
    -------
    FOG2DSpec
        The FOG model with the solved source power (and coil); the default design otherwise.

    Raises
    ------
    TypeError
        ``datasheet`` is not a Datasheet.
    ValueError
        The part is not a FOG, or its ARW needs a coil beyond FOG_LENGTH_MAX x FOG_DIAMETER_MAX.
    """
    datasheet = _check(datasheet, "FOG", "fog_spec")
    base = FOG2DSpec()
    n = datasheet.angle_random_walk()
    coil, optics = base.coil, base.optics
    fibre = Coil2D(spec=coil).fibre()  # the nominal (ideal) winding
    loop = base.loop_spec(length=fibre.length, diameter=fibre.diameter)
    target = 2.0 * (n * loop.scale_factor) ** 2
    psd = optics.phase_psd(loop.bias_phase, loop.wavelength)
    if not (target > psd["rin"] and _power_for(target, psd, optics.source_power) <= FOG_POWER_MAX):
        coil, optics = _fog_coil(datasheet, base)
        fibre = Coil2D(spec=coil).fibre()
        loop = base.loop_spec(length=fibre.length, diameter=fibre.diameter)
        target = 2.0 * (n * loop.scale_factor) ** 2
        psd = optics.phase_psd(loop.bias_phase, loop.wavelength)
    optics = replace(optics, source_power=_power_for(target, psd, optics.source_power))
    return replace(base, coil=coil, optics=optics, noise=NoiseModel(bias_instability=datasheet.bias_instability()))


def mems_spec(datasheet: Datasheet) -> MemsResonatorSpec:
    """The :class:`MemsResonatorSpec` of a MEMS part: pick-off noise from the sheet's ARW, the mass when it must.

    A sheet at or below the default resonator's Brownian floor gets the proof mass that puts
    the floor at BROWNIAN_SHARE x N (module docstring); the pick-off noise gives the rest.

    Parameters
    ----------
    datasheet : Datasheet
        The part's datasheet.

    Returns
    -------
    MemsResonatorSpec
        The resonator with the solved pick-off noise (and proof mass); the default design otherwise.

    Raises
    ------
    TypeError
        ``datasheet`` is not a Datasheet.
    ValueError
        The part is not a MEMS gyro, or its ARW needs a proof mass above MEMS_MASS_MAX.
    """
    datasheet = _check(datasheet, "MEMS", "mems_spec")
    n = datasheet.angle_random_walk()
    nominal = MemsResonator()
    floor = brownian_arw(nominal)
    if not n > floor:
        # N_B = sqrt(k_B T c_y)/(m w X0) with c_y = m w_y/Q_y goes as m^(-1/2) (brownian_arw)
        mass = nominal.mass * (floor / (BROWNIAN_SHARE * n)) ** 2
        if not mass <= MEMS_MASS_MAX:
            raise ValueError(
                f"{datasheet.name!r}: ARW {units.to_deg_per_s(n) * 60.0:.3g} deg/sqrt(h) needs a proof mass "
                f"{mass * 1e6:.3g} mg (Brownian floor {BROWNIAN_SHARE:.3g} N), above the {MEMS_MASS_MAX * 1e6:g} mg "
                f"limit; the default resonator's floor is {units.to_deg_per_s(floor) * 60.0:.3g} deg/sqrt(h)"
            )
        # a larger plate of the same design: its electrode area grows with its mass (fixed
        # thickness and gap), which keeps R G, the rebalance loop, DAC limit and g-sensitivity
        nominal = replace(nominal, mass=mass, electrode_area=nominal.electrode_area * mass / nominal.mass)
    try:
        spec = MemsResonatorSpec.from_datasheet(
            range_dps=datasheet.range_dps or 3600.0,
            noise_density_dps_rthz=units.to_deg_per_s(n),
            noise_density_convention="two-sided",
            bias_instability_dph=units.to_deg_per_h(datasheet.bias_instability()),
            bias_repeatability_dps=(datasheet.bias_repeatability or 0.0) / 3600.0,
            scale_factor_repeatability_ppm=datasheet.scale_factor_repeatability or 0.0,
            repeatability_convention="1-sigma",
            nominal=nominal,
        )
    except ValueError as exc:
        raise ValueError(f"{datasheet.name!r}: {exc}") from None
    return replace(
        spec, mass_spread=0.0, frequency_spread=0.0, split_spread=0.0, q_spread=0.0, gap_spread=0.0,
        quadrature_spread=0.0, damping_coupling_spread=0.0, phase_error_spread=0.0, phase_tc_spread=0.0,
    )


def physics_summary(datasheet: Datasheet) -> str:
    """One line: the physics parameters the sheet's ARW solves for and their values, or why it cannot.

    E.g. ``"fog_spec: source power 0.0367 mW (default FOG2D design otherwise)"``, or
    ``"not mapped: ..."`` with the solve's refusal (module docstring).

    Parameters
    ----------
    datasheet : Datasheet
        The part's datasheet.

    Returns
    -------
    str
        The one line.
    """
    if not isinstance(datasheet, Datasheet):
        raise TypeError(f"datasheet must be a Datasheet; got {type(datasheet).__name__}")
    try:
        if datasheet.technology == "FOG":
            fog = fog_spec(datasheet)
            p = fog.optics.source_power
            if fog.coil == FOG2DSpec().coil:
                return f"fog_spec: source power {p * 1e3:.4g} mW (default FOG2D design otherwise)"
            fibre = Coil2D(spec=fog.coil).fibre()
            return (
                f"fog_spec: coil L {fibre.length / 1e3:.4g} km x D {fibre.diameter:.4g} m, source power "
                f"{p * 1e3:.4g} mW, loss {fog.optics.loss_db:.4g} dB (an ASSUMED design: the sheet gives no coil, "
                f"solved at the {FOG_POWER_MAX * 1e3:g} mW source cap, L <= {FOG_LENGTH_MAX / 1e3:g} km first; "
                "default FOG2D design otherwise)"
            )
        if datasheet.technology == "MEMS":
            nom = mems_spec(datasheet).nominal
            if nom.mass == MemsResonator().mass:
                return f"mems_spec: pick-off noise {nom.pickoff_noise:.4g} m/sqrt(Hz) (default resonator otherwise)"
            return (
                f"mems_spec: proof mass {nom.mass * 1e6:.4g} mg (electrode area in proportion; solved for Brownian "
                f"noise = {BROWNIAN_SHARE:.3g} x the sheet's ARW, an ASSUMED split the sheet does not give), pick-off "
                f"noise {nom.pickoff_noise:.4g} m/sqrt(Hz), rebalance limit {nom.dac_full_scale:.3g} V (default "
                "resonator otherwise)"
            )
        w = rlg_spec(datasheet).lock_in_rate
        return f"rlg_spec: lock-in rate {units.to_deg_per_s(w):.4g} deg/s (default cavity and dither otherwise)"
    except ValueError as exc:
        return f"not mapped: {exc}"
