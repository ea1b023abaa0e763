"""Ring laser gyro from cavity mechanisms: backscatter lock-in, path-length control, mode hops,
Langmuir flow, and a thermal network whose nodes the two temperature sensors read.

All parameters are SI: angles [rad], rates [rad/s], time [s], temperature [K], lengths [m],
currents [A], powers [W]. Field units appear only in docstrings and in the defaults' comments.

What this module adds to :mod:`gyrobench.sim.rlg` (whose geometry, Adler integration, dither,
dither random walk, pulse counting and temperature sensors it imports and reuses):

* **Backscatter lock-in** (:class:`Backscatter`, :func:`lock_in_from_backscatter`):
  Omega_L = c lambda |r_net| / (8 pi A), r_net = sum_i r_i exp(j (2 k s_i + theta_i))
  (coupled-mode form of Aronowitz, "The laser gyro" (1971) and Chow et al., Rev. Mod. Phys.
  57, 61 (1985), Sec. III; prefactor as derived in docs/physics.md 6.6). The path positions
  s_i of the mirrors change with the block's thermal expansion and with the path-length
  control (PLC) mirror, so Omega_L changes with temperature and at every mode hop.
* **Path-length control and mode hops** (:class:`PathLengthControl`): the block's free
  perimeter P (1 + alpha (T_block - T_ref)) is held at the gain peak by a piezo mirror whose
  travel (in path units) is finite; when the needed correction leaves the travel the PLC
  relocks one wavelength away (mode hop). Hops are spaced Delta T = lambda / (P alpha) and,
  since the travel exceeds one wavelength, the hop temperatures on heating and on cooling
  differ by (S - lambda)/(P alpha) (hysteresis). The mode acquired at turn-on is drawn
  among those inside the travel, so hop temperatures also change from turn-on to turn-on.
* **Langmuir flow** (:class:`Discharge`): the gas in each anode leg flows with a speed
  proportional to its current over the gas viscosity; the bias is k_LF times the net
  (leg A minus leg B) effective current,
  Omega_LF = k_LF [I_A (T_ref/T_gA)^m - I_B (T_ref/T_gB)^m],
  with the gas temperature of each leg set by its own block node (so a temperature
  difference across the block gives a bias) and the current imbalance set at turn-on and
  drifting with the housing temperature through the current regulators' sense resistors.
* **Backscatter null shift**: the dissipative part of the backscatter leaves a bias
  eta Omega_L sin(arg r_net - phi_d) (stated assumption, see :class:`Backscatter`); it varies
  with temperature through the mirror phases and steps at every hop.
* **Thermal network** (:class:`CavityThermal`): housing node (sensor T1), two block nodes
  (leg-A side, which carries the cavity sensor T2, and leg-B side), conductances and heat
  capacities with unit-to-unit mounting asymmetry.

No term of the thermal bias is written in the form of paper 004's regressors (T, dT/dt,
products, gradients of the logged readings): the bias is a function of the network's node
temperatures through the mechanisms above, and the PLC state.

The long-record output (:meth:`CavityRLG.simulate`) is the statistical mode of
:mod:`gyrobench.sim.rlg` (random walk from dithering through lock-in, now with the
time-varying Omega_L, then pulse counting with the dither stripped), run by the same code
(the private ``gyrobench.sim._rlg_common``, shared by both models). Its validity against the
full Adler equation (>= 100 dither cycles with the Earth's rate present) and the dead band of
an unrandomized dither are checked in :mod:`gyrobench.scenarios.checks.rlg_cavity`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.base import units
from gyrobench.base.ranges import Constraint, FieldRange, validate
from gyrobench.base.units import SPEED_OF_LIGHT  # exact SI, re-exported
from gyrobench.base.validate import nonneg_field as _nonneg
from gyrobench.io.recording import Channel, Recording
from gyrobench.sim._rlg_common import (
    _CavityScale,
    _chamber_samples,
    _check_rng,
    _finish_run,
    _pos,
    _sensor_pair,
    _start_run,
    _Terms,
    _Wording,
    dither_margin,
)
from gyrobench.sim.rlg import (
    HENE_WAVELENGTH,
    CavityGeometry,
    Dither,
    TemperatureSensor,
    _default_dither,
    _default_geometry,
    _first_order_foh,
    _lognormal,
)
from gyrobench.sim.sensor import RLG_ERROR_COMPONENTS

__all__ = [
    "SPEED_OF_LIGHT",
    "ZERODUR_CTE_CLASS_2",
    "LANGMUIR_COEFFICIENT",
    "LANGMUIR_COEFFICIENT_PRINTED",
    "LANGMUIR_VELOCITY_SENSITIVITY",
    "lock_in_from_backscatter",
    "Backscatter",
    "PathLengthControl",
    "SwingDither",
    "swing_dither_arw",
    "mode_index",
    "CavityThermal",
    "Discharge",
    "CavityRLGSpec",
    "CavityRLG",
    "CavityRLGFamily",
    "CAVITY_RLG_FAMILY",
]

#: ZERODUR expansion class 2 tolerance, |alpha(0..50 degC)| <= 0.10e-6 /K
#: (SCHOTT, "Technical Details of ZERODUR", CTE classes; docs/physics.md 6.6)
ZERODUR_CTE_CLASS_2 = 0.10e-6
#: Langmuir-flow null shift per unit of leg-current imbalance as its source prints it
#: [rad/s per A]: Aronowitz & Lim, "Dispersion and gas flow effects in the ring laser gyro",
#: Opt. Eng. 18(4) 376 (1979), abstract: "A nullshift sensitivity of 0.0066 deg/hr/mamp of
#: unbalance was found" (43.4 cm and 21.7 cm visible laser gyros). Pinned in
#: tests/sim/test_rlg_sources.py.
LANGMUIR_COEFFICIENT_PRINTED = units.deg_per_h(0.0066) / 1e-3
#: the default Langmuir-flow coefficient k_LF of :class:`Discharge` [rad/s per A]: the printed
#: value, :data:`LANGMUIR_COEFFICIENT_PRINTED` (0.0066 deg/h per mA)
LANGMUIR_COEFFICIENT = LANGMUIR_COEFFICIENT_PRINTED
#: Null shift per unit of gas-velocity unbalance [rad/s per (m/s)], same source: "the nullshift
#: sensitivity to velocity flow to be 4.4 deg/hr/cm/sec of velocity unbalance". Not used by the
#: model (it works in current imbalance); kept as the source's second printed figure.
LANGMUIR_VELOCITY_SENSITIVITY = units.deg_per_h(4.4) / 1e-2


@dataclass(frozen=True, slots=True)
class CavityRLGFamily:
    """The cavity RLG's mechanism sizes that no source prints, as ranges [SI] (the family a map sweeps).

    Each field is a :class:`~gyrobench.base.ranges.FieldRange` in SI units; ``why`` states what
    sets the bounds. These are family parameters, not defaults: a study picks a value inside
    the range (paper 004 identifies ``dissipative`` to its gyro and says so), and
    :class:`CavityRLGSpec` leaves the unsourced mechanism off (``dissipative = 0``) unless
    asked. Sizes that do have a source are not here: the Langmuir coefficient
    (:data:`LANGMUIR_COEFFICIENT_PRINTED`, Aronowitz & Lim 1979) and the block expansion
    (:data:`ZERODUR_CTE_CLASS_2`, SCHOTT).

    Attributes
    ----------
    dissipative : FieldRange
        eta, backscatter null shift per unit lock-in (:class:`Backscatter`). The bounds follow
        from the bias scale: variable-temperature bias 0.001 deg/h (navigation grade) to
        ~1 deg/h (small tactical rings) over lock-in rates 0.01-0.1 deg/s (36-360 deg/h)
        gives eta ~ 3e-6 .. 3e-2; the range is [1e-6, 3e-2] (STATED RANGE).
    mount_asymmetry : FieldRange
        Log-normal spread of each block mount's conductance (:class:`CavityThermal`): the
        coupling that turns a housing temperature change into a block gradient A - B, which
        the Langmuir term reads. [0, 0.5] (STATED RANGE: machined mounts of equal design).
    gas_rise : FieldRange
        Discharge gas temperature above its block node [K] (:class:`Discharge`): [10, 100] K
        (STATED RANGE: a DC He-Ne capillary at ~1 mA runs tens of K above its wall).
    tcr_mismatch_std : FieldRange
        Std of the two current regulators' sense-resistor TCR difference [1/K]: [0, 25e-6]
        (metal-film resistor TCR classes of 5-25 ppm/K).
    imbalance_repeatability : FieldRange
        Std of the leg-current imbalance set at turn-on [A]: [0, 1e-5] (up to 1.7 % of a
        0.6 mA leg current; STATED RANGE).
    walk_phase_std : FieldRange
        Std of the PLC mirror's scatter-phase walk [rad per wavelength of travel]: [0, 3]
        (STATED RANGE: up to about one half turn per wavelength).
    """

    dissipative: FieldRange = FieldRange(1e-6, 3e-2, "1", "variable-temperature bias / lock-in of He-Ne RLGs")
    mount_asymmetry: FieldRange = FieldRange(0.0, 0.5, "1", "machined mounts of one design")
    gas_rise: FieldRange = FieldRange(10.0, 100.0, "K", "DC He-Ne capillary above its wall")
    tcr_mismatch_std: FieldRange = FieldRange(0.0, 25e-6, "1/K", "metal-film resistor TCR classes")
    imbalance_repeatability: FieldRange = FieldRange(0.0, 1e-5, "A", "turn-on leg imbalance")
    walk_phase_std: FieldRange = FieldRange(0.0, 3.0, "rad", "PLC mirror beam walk per wavelength")


#: the cavity RLG's unsourced sizes as ranges (:class:`CavityRLGFamily`)
CAVITY_RLG_FAMILY = CavityRLGFamily()


# ============================================================================ backscatter
def lock_in_from_backscatter(r_net: ArrayLike, *, area: float, wavelength: float) -> NDArray:
    """Lock-in rate [rad/s] from the net complex backscatter amplitude per round trip.

    Parameters
    ----------
    r_net : array_like
        Net complex backscatter amplitude per round trip [-].
    area : float
        Enclosed area A [m^2], > 0.
    wavelength : float
        Laser wavelength lambda [m], > 0.

    Returns
    -------
    ndarray
        Omega_L [rad/s].

    Notes
    -----
    Omega_L = c lambda |r_net| / (8 pi A) (docs/physics.md 6.6 from the coupled-
    mode equations of Aronowitz 1971 / Chow et al. 1985: lock-in frequency (c/L)|r_net|/(2 pi),
    divided by the scale factor 4A/(lambda L)). 10 cm square, 632.8 nm: 0.05 deg/s needs
    |r_net| = 1.16e-6.
    """
    a = _pos("lock_in_from_backscatter", "area", area, "m^2")
    lam = _pos("lock_in_from_backscatter", "wavelength", wavelength, "m")
    return SPEED_OF_LIGHT * lam * np.abs(np.asarray(r_net)) / (8.0 * math.pi * a)


@dataclass(frozen=True, slots=True, kw_only=True)
class Backscatter:
    """The mirrors' backscatter: amplitudes, phases and path positions.

    Parameters
    ----------
    amplitudes : tuple of float
        |r_i| per mirror (field amplitude per reflection, dimensionless), in path order.
    phases : tuple of float
        theta_i [rad], each mirror's own scatter phase.
    positions : tuple of float
        s_i / P: each mirror's position along the path as a fraction of the perimeter,
        measured from the PLC mirror (index 0, position 0).
    walk_phase : float
        gamma [rad per wavelength of PLC travel]: change of the PLC mirror's scatter phase as
        its diaphragm tilts and the beam spot walks over its surface (STATED ASSUMPTION).
    dissipative : float
        eta (dimensionless): null shift per unit lock-in from the dissipative part of the
        coupling (STATED ASSUMPTION; see Notes).
    dissipative_phase : float
        phi_d [rad].

    Notes
    -----
    With block strain e = alpha (T_block - T_ref) and PLC correction u [m of path] (the PLC
    mirror lengthens its two adjacent legs by u/2 each):

        s_0 = 0,  s_i = s_i0 (1 + e) + u/2            (i >= 1)
        r_net = sum_i r_i exp(j (2 k s_i + theta_i)) x exp(j gamma u/lambda) [i = 0 only]
        Omega_L = c lambda |r_net| / (8 pi A)

    A hop changes u by one wavelength: 2 k (u/2) changes by 2 pi (no change), so the lock-in
    steps only through gamma; between hops the phases drift by 2 k alpha dT (s_i0 - P/2).
    Null shift from the dissipative (non-conservative) part of the coupling, which
    unbalances the two beams' intensities (Chow et al. 1985, Sec. III.B); no closed form for
    its size is used here: Omega_ns = eta Omega_L sin(arg r_net - phi_d) (STATED ASSUMPTION,
    form and size; eta ~ 1e-4 gives ~0.02 deg/h at 0.05 deg/s lock-in, the order of the
    variable-temperature bias of precision RLGs).
    """

    amplitudes: tuple[float, ...]
    phases: tuple[float, ...]
    positions: tuple[float, ...]
    walk_phase: float = 0.0
    dissipative: float = 0.0
    dissipative_phase: float = 0.0

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "amplitudes": FieldRange(0, math.inf, "1", "|r_i|, field amplitude per reflection, >= 0"),
        "phases": FieldRange(-math.inf, math.inf, "rad", "each mirror's scatter phase theta_i"),
        "positions": FieldRange(0, 1, "1", "s_i / P from the PLC mirror, in [0, 1)", high_open=True),
        "walk_phase": FieldRange(-math.inf, math.inf, "rad", "gamma, per wavelength of PLC travel"),
        "dissipative": FieldRange(-math.inf, math.inf, "1", "eta, null shift per unit lock-in"),
        "dissipative_phase": FieldRange(-math.inf, math.inf, "rad", "phi_d of the dissipative coupling"),
    }
    #: one amplitude, phase and position per mirror, and at least two mirrors
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "len(amplitudes) == len(phases) == len(positions) >= 2",
            lambda c: len(c.amplitudes) >= 2 and len(c.phases) == len(c.positions) == len(c.amplitudes),
            lambda c: "amplitudes, phases and positions must hold one value per mirror, >= 2 mirrors; "
            f"got {len(c.amplitudes)}, {len(c.phases)}, {len(c.positions)}",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above

    def net(self, strain: ArrayLike, plc: ArrayLike, *, perimeter: float, wavelength: float):
        """r_net (complex) for block strain ``strain`` and PLC correction ``plc`` [m]."""
        e = np.asarray(strain, dtype=float)[..., None]
        u = np.asarray(plc, dtype=float)[..., None]
        s0 = np.asarray(self.positions) * perimeter
        moved = (s0 > 0).astype(float)
        k = 2.0 * math.pi / wavelength
        ph = 2.0 * k * (s0 * (1.0 + e) + moved * u / 2.0) + np.asarray(self.phases)
        ph = ph + (1.0 - moved) * self.walk_phase * u / wavelength
        return np.sum(np.asarray(self.amplitudes) * np.exp(1j * ph), axis=-1)

    def null_shift(self, r_net: ArrayLike, lock_in: ArrayLike) -> NDArray[np.float64]:
        """Omega_ns = eta Omega_L sin(arg r_net - phi_d) [rad/s]."""
        arg = np.angle(np.asarray(r_net))
        return self.dissipative * np.asarray(lock_in) * np.sin(arg - self.dissipative_phase)


# ============================================================================ PLC
@dataclass(frozen=True, slots=True, kw_only=True)
class PathLengthControl:
    """Piezo path-length control of finite travel.

    Parameters
    ----------
    travel : float
        S [m of path]: total path correction the piezo mirror can make, centred on its rest
        position; must exceed one wavelength so a hop lands back inside the travel.

    Notes
    -----
    The free perimeter change x = P alpha (T_block - T_ref) is corrected by u = n lambda - x
    with the mode index n changed by +-1 only when |u| would exceed S/2 (:func:`mode_index`).
    Hop spacing Delta T = lambda / (P alpha); on heating (alpha > 0) hops happen where
    x - n lambda = S/2, on cooling where it is -S/2: the up and down hop temperatures differ
    by (S - lambda)/(P alpha) (hysteresis).
    """

    travel: float

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "travel": FieldRange(0, math.inf, "m", "total PLC path correction S (> a wavelength)", low_open=True),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared specs above



def mode_index(
    excursion: NDArray[np.float64], *, wavelength: float, travel: float, n0: int
) -> NDArray[np.int64]:
    """Mode index n(t) of the PLC for free-perimeter excursions ``excursion`` [m].

    n changes by the fewest whole steps that bring |n lambda - x| back to <= travel/2, and
    only when it is exceeded (hysteresis). Sequential in time (a play operator); loops only
    over the samples where the bound is exceeded.

    Parameters
    ----------
    excursion : ndarray
        Free-perimeter excursion x(t) [m].
    wavelength : float
        Laser wavelength lambda [m].
    travel : float
        PLC travel S [m of path].
    n0 : int
        Mode index at the first sample.

    Returns
    -------
    ndarray of int
        n(t) at each sample.
    """
    if not travel > wavelength:
        raise ValueError(
            f"PLC travel must be > one wavelength {wavelength!r} m; got {travel!r} m"
        )
    x = np.asarray(excursion, dtype=float) / wavelength
    w = travel / (2.0 * wavelength)
    n = np.empty(len(x), dtype=np.int64)
    cur = int(n0)
    k = 0
    while k < len(x):
        # next sample where the current mode leaves the travel
        out = np.flatnonzero(np.abs(x[k:] - cur) > w)
        if out.size == 0:
            n[k:] = cur
            break
        j = k + int(out[0])
        n[k:j] = cur
        d = x[j] - cur
        cur += int(math.ceil(d - w)) if d > w else -int(math.ceil(-d - w))
        k = j
    return n


# ============================================================================ thermal network
@dataclass(frozen=True, slots=True, kw_only=True)
class CavityThermal:
    """Three-node network: housing H, block side A (leg A, cavity sensor), block side B (leg B).

    Parameters
    ----------
    c_housing, c_block : float
        Heat capacities [J/K]: housing; each half of the block.
    g_air : float
        Housing to chamber air [W/K].
    g_mount_a, g_mount_b : float
        Housing to block side A / B through the mounts [W/K] (unequal: mounting asymmetry).
    g_block : float
        Across the block, A to B [W/K].
    p_housing : float
        Electronics power dissipated in the housing [W].
    p_leg : float
        Discharge power dissipated in each leg's side of the block [W].

    Notes
    -----
    C_H T_H' = g_air (T_ch - T_H) + g_a (T_A - T_H) + g_b (T_B - T_H) + P_H
    C_b T_A' = g_a (T_H - T_A) + g_AB (T_B - T_A) + P_leg
    C_b T_B' = g_b (T_H - T_B) + g_AB (T_A - T_B) + P_leg
    Solved by modal decomposition (real negative eigenvalues: a conduction network), each
    mode by the exact first-order-hold recursion of :mod:`gyrobench.sim.rlg`.
    Defaults (STATED ASSUMPTIONS, no published RLG network): aluminium housing ~2 kg
    (C = 1800 J/K), air 3 W/K (tau ~10 min); ZERODUR block 0.6 kg, c_p 0.8 J/(g K) (SCHOTT
    data sheet) -> 240 J/K per half; mounts 0.15 W/K each (block tau ~13 min); across the block
    ZERODUR k = 1.46 W/(m K) (SCHOTT) over a 4e-3 m^2 section and 0.07 m -> 0.08 W/K;
    electronics 5 W, discharge 2 x 0.6 W (1 kV x 0.6 mA per leg).
    """

    c_housing: float = 1800.0
    c_block: float = 240.0
    g_air: float = 3.0
    g_mount_a: float = 0.15
    g_mount_b: float = 0.15
    g_block: float = 0.08
    p_housing: float = 5.0
    p_leg: float = 0.6

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "c_housing": FieldRange(0, math.inf, "J/K", "housing heat capacity C_H", low_open=True),
        "c_block": FieldRange(0, math.inf, "J/K", "heat capacity C_b of each block half", low_open=True),
        "g_air": FieldRange(0, math.inf, "W/K", "housing to chamber air conductance", low_open=True),
        "g_mount_a": FieldRange(0, math.inf, "W/K", "housing to block side A through its mount", low_open=True),
        "g_mount_b": FieldRange(0, math.inf, "W/K", "housing to block side B through its mount", low_open=True),
        "g_block": FieldRange(0, math.inf, "W/K", "across the block, A to B", low_open=True),
        "p_housing": FieldRange(0, math.inf, "W", "electronics power in the housing, >= 0"),
        "p_leg": FieldRange(0, math.inf, "W", "discharge power per leg, >= 0"),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared specs above

    def matrices(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(M, B): d[T_H, T_A, T_B]/dt = M T + B [T_ch, 1]."""
        ga, gb, gab = self.g_mount_a, self.g_mount_b, self.g_block
        ch, cb = self.c_housing, self.c_block
        m = np.array(
            [
                [-(self.g_air + ga + gb) / ch, ga / ch, gb / ch],
                [ga / cb, -(ga + gab) / cb, gab / cb],
                [gb / cb, gab / cb, -(gb + gab) / cb],
            ]
        )
        b = np.array(
            [[self.g_air / ch, self.p_housing / ch], [0.0, self.p_leg / cb], [0.0, self.p_leg / cb]]
        )
        return m, b

    def temperatures(self, chamber: ArrayLike, fs: float) -> NDArray[np.float64]:
        """Node temperatures [K], shape (3, n): housing, block A, block B; powered at t = 0.

        The unit starts soaked at the first chamber sample.
        """
        tc, h = _chamber_samples("CavityThermal.temperatures", chamber, fs)
        m, b = self.matrices()
        lam, v = np.linalg.eig(m)
        lam, v = lam.real, v.real
        vinv = np.linalg.inv(v)
        drive = vinv @ b  # (3, 2)
        x0 = vinv @ np.full(3, tc[0])
        z = np.empty((3, len(tc)))
        for i in range(3):
            tau = -1.0 / lam[i]
            u = tau * (drive[i, 0] * tc + drive[i, 1])
            z[i] = _first_order_foh(u, x0[i], tau, h)
        return v @ z


# ============================================================================ discharge
@dataclass(frozen=True, slots=True, kw_only=True)
class Discharge:
    """Two-leg DC discharge and its Langmuir-flow bias.

    Parameters
    ----------
    current : float
        I_0 [A], regulated current per leg (0.6 mA; STATED ASSUMPTION, typical He-Ne RLG).
    imbalance : float
        Delta I_0 [A], this turn-on's leg current difference I_A - I_B at T_ref.
    sense_tcr_mismatch : float
        delta [1/K], difference of the two regulators' sense-resistor temperature coefficients
        (read at the housing node).
    gas_rise : float
        Gas temperature above its block node [K] (discharge heating; STATED ASSUMPTION 30 K).
    viscosity_exponent : float
        m: He-Ne viscosity ~ T^m; flow speed at fixed current ~ 1/viscosity. m = 0.7 is the
        kinetic-theory temperature exponent of helium's viscosity (Chapman-Enskog, ~0.66-0.7;
        STATED ASSUMPTION for the mixture).
    coefficient : float
        k_LF [rad/s per A] (:data:`LANGMUIR_COEFFICIENT`).
    reference_temperature : float
        T_ref [K].

    Notes
    -----
    I_A = I_0 + Delta I / 2, I_B = I_0 - Delta I / 2, Delta I = Delta I_0 + I_0 delta (T_H - T_ref)
    Omega_LF = k_LF [I_A (T_ref/T_gA)^m - I_B (T_ref/T_gB)^m],  T_g = T_node + gas_rise
    (Langmuir flow: null shift linear in the current imbalance and odd in it, Aronowitz & Lim
    1979; docs/physics.md 6.6). For small differences
    Omega_LF ~ k_LF [Delta I - I_0 m (T_gA - T_gB)/T_ref].
    """

    current: float = 0.6e-3
    imbalance: float = 0.0
    sense_tcr_mismatch: float = 0.0
    gas_rise: float = 30.0
    viscosity_exponent: float = 0.7
    coefficient: float = LANGMUIR_COEFFICIENT
    reference_temperature: float = units.celsius(25.0)

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "current": FieldRange(0, math.inf, "A", "regulated current per leg I_0", low_open=True),
        "imbalance": FieldRange(-math.inf, math.inf, "A", "this turn-on's leg current difference, signed"),
        "sense_tcr_mismatch": FieldRange(-math.inf, math.inf, "1/K", "sense-resistor TCR difference delta"),
        "gas_rise": FieldRange(-math.inf, math.inf, "K", "gas temperature above its block node"),
        "viscosity_exponent": FieldRange(-math.inf, math.inf, "1", "m of viscosity ~ T^m (helium ~0.7)"),
        "coefficient": FieldRange(-math.inf, math.inf, "rad/s/A", "Langmuir-flow coefficient k_LF"),
        "reference_temperature": FieldRange(0, math.inf, "K", "T_ref of the discharge", low_open=True),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared specs above

    def bias(self, t_housing: ArrayLike, t_a: ArrayLike, t_b: ArrayLike) -> NDArray[np.float64]:
        """Omega_LF [rad/s] at node temperatures [K]."""
        th, ta, tb = (np.asarray(x, dtype=float) for x in (t_housing, t_a, t_b))
        tr, m = self.reference_temperature, self.viscosity_exponent
        di = self.imbalance + self.current * self.sense_tcr_mismatch * (th - tr)
        ia, ib = self.current + di / 2.0, self.current - di / 2.0
        fa = (tr / (ta + self.gas_rise)) ** m
        fb = (tr / (tb + self.gas_rise)) ** m
        return self.coefficient * (ia * fa - ib * fb)


# ============================================================================ dither swing
@dataclass(frozen=True, slots=True)
class SwingDither:
    """Dither whose amplitude is redrawn at every angle extreme (each half-cycle's swing random).

    Parameters
    ----------
    dither : Dither
        Frequency f_d, nominal amplitude theta_D and relative jitter sigma.
    extremes : ndarray, shape (2 n + 2, ...)
        Signed angle extremes e_k = (-1)^k theta_D a_k [rad], a_k = 1 + sigma eps_k.

    Notes
    -----
    Angle (continuous, rate zero at each extreme): for t < 1/(4 f_d),
    theta = e_0 sin(w t); in half-cycle k >= 1, t in [t_k, t_k + 1/(2 f_d)), t_k =
    (k/2 - 1/4)/f_d,

        theta(t) = (e_{k-1} + e_k)/2 + (e_{k-1} - e_k)/2 cos(w (t - t_k)),   w = 2 pi f_d

    so the rate reversal (lock-in crossing) in the middle of half-cycle k has slope
    w^2 |e_{k-1} - e_k|/2 = w^2 theta_D (a_{k-1} + a_k)/2, and successive crossings see
    independent swings. :class:`gyrobench.sim.rlg.DitherRealization` instead changes the
    amplitude where the angle crosses zero, which repeats the crossing phases within a
    cycle: at low input rate its random walk is ~1/3 of the formula after 100 cycles
    (docs/physics.md 6.6: "randomisation must change the swing between
    successive crossings"). Random walk of this dither (stationary phase, 2 f_d independent
    crossings per second): N = Omega_L sqrt((1 + sigma^2/2)/(2 pi K Omega_D)) [rad/sqrt(s)]
    (E[2/(a_{k-1} + a_k)] = 1 + sigma^2/2 to second order).
    """

    dither: Dither
    extremes: NDArray[np.float64]

    @classmethod
    def draw(
        cls, dither: Dither, n_cycles: int, *, rng: np.random.Generator, size: int = 1
    ) -> SwingDither:
        """Draw the extremes of ``n_cycles`` cycles for ``size`` realizations."""
        _check_rng(rng)
        if not (isinstance(n_cycles, (int, np.integer)) and n_cycles >= 1):
            raise ValueError(f"n_cycles must be an integer >= 1; got {n_cycles!r}")
        a = 1.0 + dither.amplitude_jitter * rng.standard_normal((2 * int(n_cycles) + 2, size))
        sign = np.where(np.arange(len(a)) % 2 == 0, 1.0, -1.0)[:, None]
        return cls(dither, dither.amplitude * np.maximum(a, 0.05) * sign)

    def _half(self, t: float) -> tuple[int, float]:
        f = self.dither.frequency
        k = min(int(math.floor(2.0 * t * f + 0.5)), len(self.extremes) - 1)
        return k, (k / 2.0 - 0.25) / f

    def angle(self, t: float) -> NDArray[np.float64]:
        """theta_d(t) [rad], one value per realization."""
        w = 2.0 * math.pi * self.dither.frequency
        k, tk = self._half(t)
        if k == 0:
            return self.extremes[0] * math.sin(w * t)
        e0, e1 = self.extremes[k - 1], self.extremes[k]
        return 0.5 * (e0 + e1) + 0.5 * (e0 - e1) * math.cos(w * (t - tk))

    def rate(self, t: float) -> NDArray[np.float64]:
        """Omega_d(t) [rad/s], one value per realization."""
        w = 2.0 * math.pi * self.dither.frequency
        k, tk = self._half(t)
        if k == 0:
            return self.extremes[0] * w * math.cos(w * t)
        e0, e1 = self.extremes[k - 1], self.extremes[k]
        return -0.5 * (e0 - e1) * w * math.sin(w * (t - tk))


def swing_dither_arw(*, scale_factor: float, lock_in_rate: float, dither: Dither) -> float:
    """N = Omega_L sqrt((1 + sigma^2/2)/(2 pi K Omega_D)) [rad/sqrt(s)] (:class:`SwingDither`).

    Parameters
    ----------
    scale_factor : float
        K [counts/rad], > 0.
    lock_in_rate : float
        Omega_L [rad/s], >= 0.
    dither : Dither
        The dither (f_d, theta_D, amplitude jitter sigma).

    Returns
    -------
    float
        N [rad/sqrt(s)].
    """
    k = _pos("swing_dither_arw", "scale_factor", scale_factor, "counts/rad")
    wl = _nonneg("swing_dither_arw", "lock_in_rate", lock_in_rate, "rad/s")
    s = dither.amplitude_jitter
    return wl * math.sqrt((1.0 + 0.5 * s * s) / (2.0 * math.pi * k * dither.peak_rate))


# ============================================================================ unit
def _mirror_positions(geometry: CavityGeometry) -> tuple[float, ...]:
    """Each mirror's path position from mirror 0, as a fraction of the perimeter."""
    v = np.asarray(geometry.vertices)
    legs = np.hypot(*(np.roll(v, -1, axis=0) - v).T)
    return tuple(float(s) for s in np.concatenate(([0.0], np.cumsum(legs)[:-1])) / legs.sum())


@dataclass(frozen=True, slots=True, kw_only=True)
class CavityRLG(_CavityScale):
    """One drawn cavity-model RLG (all SI). Build with :meth:`CavityRLGSpec.realize`.

    Parameters
    ----------
    geometry : CavityGeometry
    dither : Dither
    backscatter : Backscatter
    cte : float
        alpha [1/K], the block's linear expansion coefficient.
    plc : PathLengthControl
    thermal : CavityThermal
    discharge : Discharge
        Nominal discharge; turn-on draws replace ``imbalance`` and scale ``gas_rise``.
    imbalance_repeatability : float
        Std of the leg-current imbalance set at each turn-on [A].
    gas_rise_repeatability : float
        Relative std of the gas temperature rise at each turn-on.
    bias : float
        Constant bias [rad/s].
    bias_repeatability : float
        Turn-on to turn-on std of the constant bias [rad/s].
    bias_instability, rate_random_walk : float
        Flicker B [rad/s] and K [rad/s/sqrt(s)] (IEEE 952).
    sensor_housing, sensor_cavity : TemperatureSensor
        T1 reads the housing node, T2 the block node on leg A's side.
    reference_temperature : float
        T_ref [K] of the block's length and the PLC's rest position.
    label : str
        The unit's name in records.
    mode_hops : bool
        False runs the counterfactual PLC of unlimited travel (same draws): no mode hops.
    """

    geometry: CavityGeometry
    dither: Dither
    backscatter: Backscatter
    cte: float
    plc: PathLengthControl
    thermal: CavityThermal = field(default_factory=CavityThermal)
    discharge: Discharge = field(default_factory=Discharge)
    imbalance_repeatability: float = 0.0
    gas_rise_repeatability: float = 0.0
    bias: float = 0.0
    bias_repeatability: float = 0.0
    bias_instability: float = 0.0
    rate_random_walk: float = 0.0
    sensor_housing: TemperatureSensor = field(default_factory=TemperatureSensor)
    sensor_cavity: TemperatureSensor = field(default_factory=TemperatureSensor)
    reference_temperature: float = units.celsius(25.0)
    label: str = "RLG"
    mode_hops: bool = True

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "cte": FieldRange(-math.inf, math.inf, "1/K", "the block's linear expansion coefficient alpha"),
        "imbalance_repeatability": FieldRange(0, math.inf, "A", "turn-on std of the leg-current imbalance"),
        "gas_rise_repeatability": FieldRange(0, math.inf, "1", "turn-on relative std of the gas rise"),
        "bias": FieldRange(-math.inf, math.inf, "rad/s", "constant bias, signed"),
        "bias_repeatability": FieldRange(0, math.inf, "rad/s", "turn-on std of the constant bias"),
        "bias_instability": FieldRange(0, math.inf, "rad/s", "flicker coefficient B (IEEE 952), >= 0"),
        "rate_random_walk": FieldRange(0, math.inf, "rad/s/sqrt(s)", "rate random walk K, >= 0"),
        "reference_temperature": FieldRange(-math.inf, math.inf, "K", "T_ref of the block length and PLC rest"),
    }
    #: a hop lands back inside the PLC travel; the dither clears the largest possible lock-in
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "plc.travel > geometry.wavelength",
            lambda c: c.plc.travel > c.geometry.wavelength,
            lambda c: f"plc.travel must be > one wavelength {c.geometry.wavelength!r} m; got {c.plc.travel!r}",
        ),
        dither_margin(lambda c: c.max_lock_in_rate, "the largest possible lock-in"),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above

    # scale_factor K and pulse_weight q at T_ref, mode 0 [counts/rad, rad/count]: _CavityScale

    @property
    def max_lock_in_rate(self) -> float:
        """Omega_L with every mirror's scatter in phase [rad/s]."""
        return float(
            lock_in_from_backscatter(
                sum(self.backscatter.amplitudes),
                area=self.geometry.area,
                wavelength=self.geometry.wavelength,
            )
        )

    @property
    def hop_spacing(self) -> float:
        """Delta T_hop = lambda / (P |alpha|) [K] (inf for alpha = 0)."""
        d = self.geometry.perimeter * abs(self.cte)
        return self.geometry.wavelength / d if d > 0 else math.inf

    @property
    def hysteresis(self) -> float:
        """Difference of heating and cooling hop temperatures, (S - lambda)/(P |alpha|) [K]."""
        return (self.plc.travel / self.geometry.wavelength - 1.0) * self.hop_spacing

    def cavity_state(
        self, nodes: NDArray[np.float64], *, n0: int, mode_hops: bool = True
    ) -> dict[str, NDArray[np.float64]]:
        """Block strain, PLC mode and correction, r_net and lock-in at node temperatures (3, n).

        ``mode_hops=False`` is a counterfactual: a PLC of unlimited travel stays on mode n0.
        """
        p, lam = self.geometry.perimeter, self.geometry.wavelength
        strain = self.cte * (0.5 * (nodes[1] + nodes[2]) - self.reference_temperature)
        if mode_hops:
            n = mode_index(p * strain, wavelength=lam, travel=self.plc.travel, n0=n0)
        else:
            n = np.full(len(strain), int(n0), dtype=np.int64)
        u = n * lam - p * strain
        r = self.backscatter.net(strain, u, perimeter=p, wavelength=lam)
        lock = lock_in_from_backscatter(r, area=self.geometry.area, wavelength=lam)
        return {"strain": strain, "mode": n.astype(float), "plc": u, "r_net": r, "lock_in": lock}

    def acquired_modes(self, t_block: float) -> NDArray[np.int64]:
        """Modes the PLC can lock at turn-on: |n lambda - x| <= S/2 at block temperature [K]."""
        lam = self.geometry.wavelength
        x = self.geometry.perimeter * self.cte * (t_block - self.reference_temperature) / lam
        w = self.plc.travel / (2.0 * lam)
        return np.arange(math.ceil(x - w), math.floor(x + w) + 1)

    def turn_on(self, rng: np.random.Generator, t_block: float) -> dict[str, float]:
        """This turn-on's draws: constant bias, leg imbalance, gas rise, acquired mode."""
        modes = self.acquired_modes(t_block)
        return {
            "bias": self.bias + self.bias_repeatability * rng.standard_normal(),
            "imbalance": self.discharge.imbalance
            + self.imbalance_repeatability * rng.standard_normal(),
            "gas_rise": self.discharge.gas_rise
            * (1.0 + self.gas_rise_repeatability * rng.standard_normal()),
            "mode0": int(rng.choice(modes)),
        }

    def thermal_bias(
        self, nodes: NDArray[np.float64], on: dict[str, float], *, mode_hops: bool = True
    ) -> dict[str, NDArray[np.float64]]:
        """Mechanism biases [rad/s] and the cavity state at node temperatures (3, n) [K]."""
        st = self.cavity_state(nodes, n0=int(on["mode0"]), mode_hops=mode_hops)
        dis = replace(self.discharge, imbalance=on["imbalance"], gas_rise=on["gas_rise"])
        return st | {
            "bias_langmuir": dis.bias(nodes[0], nodes[1], nodes[2]),
            "bias_backscatter": self.backscatter.null_shift(st["r_net"], st["lock_in"]),
        }

    def _with_model_terms(self, rec: Recording) -> tuple[Recording, list[str]]:
        """The cavity's scale-factor error as a truth term, beside the shared components."""
        tr = rec.truth
        drive = sum(tr[k].data for k in ("true_rate", "turn_on_bias", "thermal_bias", "flicker_rrw"))
        truth = {
            **tr,
            "scale_factor_error": Channel(
                (tr["scale_factor_ratio"].data - 1.0) * drive,
                "rad/s",
                "(K/K_ref - 1) x (true rate + turn-on, thermal and flicker bias)",
            ),
        }
        return replace(rec, truth=truth), [*RLG_ERROR_COMPONENTS, "scale_factor_error"]

    def _record(
        self,
        chamber: Callable[[NDArray[np.float64]], NDArray[np.float64]],
        duration: float,
        fs: float,
        *,
        rng: np.random.Generator,
        rate: float | Callable[[NDArray[np.float64]], NDArray[np.float64]] = 0.0,
        name: str = "rlg",
        mode_hops: bool | None = None,
    ) -> Recording:
        """Statistical mode over a thermal run: pulse counts at ``fs`` (gyro on at t = 0).

        Parameters and output channels as :meth:`gyrobench.sim.rlg.RLGUnit.simulate`
        (``output``, ``counts``, ``dither_angle``, ``T1`` housing, ``T2`` cavity). Truth adds the
        node temperatures, ``lock_in_rate``, ``mode`` (PLC mode index), ``plc`` [m],
        ``bias_langmuir``, ``bias_backscatter`` and ``scale_factor_ratio``.
        ``mode_hops``: None takes the unit's own; False runs the counterfactual PLC of
        unlimited travel (same draws).

        Notes
        -----
        theta_k [counts] = sum_{j<k} K_j (Omega_j + b_j)/fs + K N_j sqrt(1/fs) eps_j,
        N_j = Omega_L,j sqrt((1 + sigma^2/2)/(2 pi K Omega_D)) (:func:`swing_dither_arw`, the
        dither redrawing its swing at every extreme, :class:`SwingDither`, with the lock-in of
        the sample; checked against the Adler equation in
        :mod:`gyrobench.scenarios.checks.rlg_cavity`),
        K_j = 4 A (1 + e_j)^2 / (lambda (P + n_j lambda))
        (PLC holds the path at the mode, the area follows the block); counts and dither
        stripping as in :mod:`gyrobench.sim.rlg`.
        """
        run = _start_run("CavityRLG.simulate", self.dither, chamber, duration, fs, rng)
        tch = run.chamber
        nodes = self.thermal.temperatures(tch, run.fs)
        on = self.turn_on(run.turn_on_rng, 0.5 * (nodes[1, 0] + nodes[2, 0]))
        mech = self.thermal_bias(nodes, on, mode_hops=self.mode_hops if mode_hops is None else mode_hops)
        mid = {k: 0.5 * (mech[k][1:] + mech[k][:-1]) for k in ("bias_langmuir", "bias_backscatter")}
        thermal = mid["bias_langmuir"] + mid["bias_backscatter"]
        lock = 0.5 * (mech["lock_in"][1:] + mech["lock_in"][:-1])
        g, lam = self.geometry, self.geometry.wavelength
        k_ratio = (
            (1.0 + mech["strain"][:-1]) ** 2 * g.perimeter / (g.perimeter + mech["mode"][:-1] * lam)
        )
        n_unit = swing_dither_arw(
            scale_factor=self.scale_factor, lock_in_rate=1.0, dither=self.dither
        )
        sl = slice(None, -1)
        terms = _Terms(
            turn_on_bias=on["bias"],
            thermal_bias=thermal,
            random_walk=n_unit * lock,
            scale_ratio=k_ratio,
            t_housing=nodes[0, sl],
            t_cavity=nodes[1, sl],
            truth={
                "T1": Channel(nodes[0, sl], "K", "housing node"),
                "T2": Channel(nodes[1, sl], "K", "block node A (cavity sensor)"),
                "T_block_b": Channel(nodes[2, sl], "K", "block node B"),
                "chamber": Channel(tch[sl], "K", "chamber air temperature"),
                "thermal_bias": Channel(thermal, "rad/s", "Langmuir flow + backscatter null shift"),
                "bias_langmuir": Channel(mid["bias_langmuir"], "rad/s", "Langmuir flow"),
                "bias_backscatter": Channel(
                    mid["bias_backscatter"], "rad/s", "backscatter null shift"
                ),
                "lock_in_rate": Channel(lock, "rad/s", "lock-in rate from backscatter"),
                "mode": Channel(mech["mode"][sl], "1", "PLC mode index"),
                "plc": Channel(mech["plc"][sl], "m", "PLC path correction"),
                "scale_factor_ratio": Channel(k_ratio, "1", "K / K(T_ref, mode 0)"),
            },
            truth_last={},
            metadata={
                "model": "gyrobench.sim.rlg_cavity statistical mode",
                "unit": self.label,
                "scale_factor_counts_per_rad": self.scale_factor,
                "pulse_weight_rad": self.pulse_weight,
                "turn_on": on,
                "cte_per_k": self.cte,
                "hop_spacing_k": self.hop_spacing,
            },
        )
        return _finish_run(self, run, rate, terms, _WORDING, name)


#: how this model describes the recording channels common to both RLG models
_WORDING = _Wording(
    dither_angle="dither angle at the end of each sample",
    housing_sensor="housing sensor",
    cavity_sensor="cavity sensor",
    turn_on_bias="bias of this turn-on",
    dither_random_walk="random walk from dither and lock-in",
    quantization="counting error",
)


# ============================================================================ spec
def _rayleigh_amplitudes(rng: np.random.Generator, n: int, sigma: float) -> NDArray[np.float64]:
    return sigma * np.sqrt(-2.0 * np.log1p(-rng.uniform(0.0, 1.0, n)))


def _worst_lock_in(geometry: CavityGeometry, backscatter_sigma: float) -> float:
    """The largest likely lock-in [rad/s]: every mirror's amplitude at the Rayleigh quantile of
    exceedance 1e-6, all scattering in phase."""
    amplitude = len(geometry.vertices) * backscatter_sigma * math.sqrt(2.0 * math.log(1e6))
    return float(lock_in_from_backscatter(amplitude, area=geometry.area, wavelength=geometry.wavelength))


@dataclass(frozen=True, slots=True, kw_only=True)
class CavityRLGSpec:
    """A cavity-model RLG budget (nominal values, SI) and the unit-to-unit spread of each.

    Parameters
    ----------
    geometry : CavityGeometry
        Default: equilateral triangle of side 0.14 m (P = 0.42 m), He-Ne 632.8 nm.
    dither : Dither
        Default 400 Hz x 150 arcsec, 10 % amplitude jitter (as :class:`gyrobench.sim.rlg.RLGSpec`).
    backscatter_sigma : float
        Rayleigh scale of each mirror's |r_i| (random-phase scatterers, Rayleigh-distributed
        backscatter in He-Ne rings: docs/physics.md 6.6). Default 4.0e-7:
        STATED ASSUMPTION chosen so the rms lock-in of the triangle is ~0.05 deg/s
        (E|r_net|^2 = 3 x 2 sigma^2), the lock-in of :class:`gyrobench.sim.rlg.RLGSpec`.
    walk_phase_std : float
        Std of gamma [rad per wavelength of PLC travel] (STATED ASSUMPTION, 1 rad).
    dissipative : float
        Nominal eta, log-normal spread ``dissipative_spread``. No source prints it: default 0
        (the backscatter null shift off); its range is :data:`CAVITY_RLG_FAMILY`
        ``.dissipative`` and a study sets it (paper 004 identifies it to its gyro).
    dissipative_spread : float
        Log-normal unit-to-unit spread of eta [-].
    cte_bound : float
        alpha is drawn uniform in [-cte_bound, +cte_bound]: a block of ZERODUR expansion class 2
        (|alpha| <= 0.10e-6 /K, :data:`ZERODUR_CTE_CLASS_2`).
    plc_travel : tuple of float
        PLC travel drawn uniform in this range [m of path]; default 1.2..1.8 wavelengths
        (STATED ASSUMPTION; must exceed one wavelength).
    thermal : CavityThermal
        Nominal network (spreads: ``mount_asymmetry``, STATED ASSUMPTION 0.3, and
        ``thermal_spread``, 0.1).
    thermal_spread : float
        Relative (log-normal) spread of the network's capacities and the air conductance [-].
    mount_asymmetry : float
        Log-normal spread of each block mount's conductance [-].
    discharge : Discharge
        Nominal discharge.
    tcr_mismatch_std : float
        Std of the regulators' sense-resistor TCR difference [1/K] (STATED ASSUMPTION 5e-6/K:
        matched metal-film sense resistors).
    imbalance_repeatability : float
        Std of the leg-current imbalance set at each turn-on [A] (1e-6 A, 0.17 % of the leg
        current, STATED ASSUMPTION).
    gas_rise_repeatability : float
        Relative std of the gas temperature rise at each turn-on [-] (0.1, STATED ASSUMPTION).
    bias_spread, bias_repeatability, bias_instability, rate_random_walk : float
        [rad/s], [rad/s], [rad/s], [rad/s/sqrt(s)]; as :class:`gyrobench.sim.rlg.RLGSpec`.
    sensor : TemperatureSensor
        Both sensors.
    sensor_offset_spread : float
        Std of each sensor's drawn calibration offset [K].
    """

    geometry: CavityGeometry = field(default_factory=_default_geometry)
    dither: Dither = field(default_factory=_default_dither)
    backscatter_sigma: float = 4.0e-7
    walk_phase_std: float = 1.0
    dissipative: float = 0.0
    dissipative_spread: float = 0.5
    cte_bound: float = ZERODUR_CTE_CLASS_2
    plc_travel: tuple[float, float] = (1.2 * HENE_WAVELENGTH, 1.8 * HENE_WAVELENGTH)
    thermal: CavityThermal = field(default_factory=CavityThermal)
    thermal_spread: float = 0.1
    mount_asymmetry: float = 0.3
    discharge: Discharge = field(default_factory=Discharge)
    tcr_mismatch_std: float = 5e-6
    imbalance_repeatability: float = 1e-6
    gas_rise_repeatability: float = 0.1
    bias_spread: float = units.deg_per_h(0.5)
    bias_repeatability: float = units.deg_per_h(0.01)
    bias_instability: float = units.deg_per_h(0.002)
    rate_random_walk: float = 0.0
    sensor: TemperatureSensor = field(default_factory=TemperatureSensor)
    sensor_offset_spread: float = 0.2

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "backscatter_sigma": FieldRange(0, math.inf, "1", "Rayleigh scale of each mirror's |r_i|, >= 0"),
        "walk_phase_std": FieldRange(0, math.inf, "rad", "std of gamma per wavelength of PLC travel"),
        "dissipative": FieldRange(0, math.inf, "1", "nominal eta (log-normal draw), >= 0"),
        "dissipative_spread": FieldRange(0, math.inf, "1", "log-normal spread of eta"),
        "cte_bound": FieldRange(0, math.inf, "1/K", "alpha drawn uniform in [-bound, +bound]"),
        "plc_travel": FieldRange(0, math.inf, "m", "PLC travel range, drawn uniform (> one wavelength)", low_open=True),
        "thermal_spread": FieldRange(0, math.inf, "1", "relative spread of the thermal network"),
        "mount_asymmetry": FieldRange(0, math.inf, "1", "log-normal spread of each mount's conductance"),
        "tcr_mismatch_std": FieldRange(0, math.inf, "1/K", "std of the sense-resistor TCR mismatch"),
        "imbalance_repeatability": FieldRange(0, math.inf, "A", "turn-on std of the leg-current imbalance"),
        "gas_rise_repeatability": FieldRange(0, math.inf, "1", "turn-on relative std of the gas rise"),
        "bias_spread": FieldRange(0, math.inf, "rad/s", "std of a unit's constant bias"),
        "bias_repeatability": FieldRange(0, math.inf, "rad/s", "turn-on std of the constant bias"),
        "bias_instability": FieldRange(0, math.inf, "rad/s", "flicker coefficient B (IEEE 952), >= 0"),
        "rate_random_walk": FieldRange(0, math.inf, "rad/s/sqrt(s)", "rate random walk K, >= 0"),
        "sensor_offset_spread": FieldRange(0, math.inf, "K", "std of the drawn sensor offsets"),
    }
    #: every unit is dithered well above its largest likely lock-in; the PLC travel exceeds a
    #: wavelength and is an ordered range
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        dither_margin(
            lambda c: _worst_lock_in(c.geometry, c.backscatter_sigma),
            "the largest likely lock-in",
            lambda c: f" (backscatter_sigma {c.backscatter_sigma!r})",
        ),
        Constraint(
            "geometry.wavelength < plc_travel[0] <= plc_travel[1]",
            lambda c: len(c.plc_travel) == 2 and c.geometry.wavelength < c.plc_travel[0] <= c.plc_travel[1],
            lambda c: f"plc_travel must satisfy wavelength < low <= high [m]; got {c.plc_travel!r}",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above

    def realize(self, *, rng: np.random.Generator, label: str = "RLG") -> CavityRLG:
        """Draw one unit (a child stream per group: optics, block, thermal, discharge, sensors)."""
        _check_rng(rng)
        r_opt, r_blk, r_th, r_dis, r_sens = rng.spawn(5)
        n_m = len(self.geometry.vertices)
        bs = Backscatter(
            amplitudes=tuple(_rayleigh_amplitudes(r_opt, n_m, self.backscatter_sigma)),
            phases=tuple(r_opt.uniform(0.0, 2.0 * math.pi, n_m)),
            positions=_mirror_positions(self.geometry),
            walk_phase=self.walk_phase_std * float(r_opt.standard_normal()),
            dissipative=_lognormal(r_opt, self.dissipative, self.dissipative_spread),
            dissipative_phase=float(r_opt.uniform(0.0, 2.0 * math.pi)),
        )
        th, s, a = self.thermal, self.thermal_spread, self.mount_asymmetry
        thermal = CavityThermal(
            c_housing=_lognormal(r_th, th.c_housing, s),
            c_block=_lognormal(r_th, th.c_block, s),
            g_air=_lognormal(r_th, th.g_air, s),
            g_mount_a=_lognormal(r_th, th.g_mount_a, a),
            g_mount_b=_lognormal(r_th, th.g_mount_b, a),
            g_block=_lognormal(r_th, th.g_block, s),
            p_housing=_lognormal(r_th, th.p_housing, s),
            p_leg=_lognormal(r_th, th.p_leg, s),
        )
        dis = replace(
            self.discharge,
            sense_tcr_mismatch=self.tcr_mismatch_std * float(r_dis.standard_normal()),
        )
        housing, cavity = _sensor_pair(self.sensor, self.sensor_offset_spread, r_sens)
        return CavityRLG(
            geometry=self.geometry,
            dither=self.dither,
            backscatter=bs,
            cte=float(r_blk.uniform(-self.cte_bound, self.cte_bound)),
            plc=PathLengthControl(travel=float(r_blk.uniform(*self.plc_travel))),
            thermal=thermal,
            discharge=dis,
            imbalance_repeatability=self.imbalance_repeatability,
            gas_rise_repeatability=self.gas_rise_repeatability,
            bias=self.bias_spread * float(r_dis.standard_normal()),
            bias_repeatability=self.bias_repeatability,
            bias_instability=self.bias_instability,
            rate_random_walk=self.rate_random_walk,
            sensor_housing=housing,
            sensor_cavity=cavity,
            label=label,
        )
