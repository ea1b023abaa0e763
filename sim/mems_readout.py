"""Open-loop capacitive sense read-out of a MEMS vibratory gyro: where its scale-factor nonlinearity arises.

An open-loop (not rebalanced) sense channel lets the proof mass move, y(t) = Re{B e^{j w t}}
with B the complex sense envelope [m] (:mod:`gyrobench.sim.mems_resonator`, slow flow
B = R F_ext at equilibrium: the Coriolis force of the rate and the quadrature force together).
Three parts of the chain are nonlinear in y; the chain here carries each with its own
equation, and nothing in it is written in the form of a rate transfer. SI units throughout:
m, F, V, N, N/m, N/m^3.

1. **The sense mode's amplitude-dependent stiffness** (the mass is not held at zero).

   * Mechanical cubic stiffness k3 [N/m^3] (hardening of a stretching flexure; Nayfeh & Mook,
     *Nonlinear Oscillations*, Wiley 1979, ch. 4; Kaajakari et al., JMEMS 13(5) 715 (2004)).
   * The biased sense electrodes: a differential parallel-plate pair of area A_s and gap g at
     a voltage V_s to the mass pulls it with (Kaajakari, *Practical MEMS*, 2009, ch. 6)

         F_e(y) = (eps0 A_s V_s^2 / 2) [1/(g - y)^2 - 1/(g + y)^2]            [N],

     whose linear part k_e = 2 eps0 A_s V_s^2 / g^3 is part of the tuned mode split the
     resonator carries; the rest, F_e(y) - k_e y = k_e y (2 (y/g)^2 + 3 (y/g)^4 + ...),
     softens the mode as the amplitude grows (the forcer's displacement-dependent gain).

   First harmonic balance of m y'' + c y' + k_y y + k3 y^3 - (F_e(y) - k_e y) = Re{F e^{jwt}}
   (Nayfeh & Mook ch. 4) gives, with a = |B|,

       B (1/R + dk(a)) = F,   dk(a) = (3/4) k3 a^2 - (F_e1(a)/a - k_e)        [N/m],
       F_e1(a) = (4/pi) int_0^{pi/2} F_e(a cos t) cos t dt
               = 2 eps0 A_s V_s^2 a / (g^2 - a^2)^(3/2)                         [N],

   the closed form from (1/2 pi) int_0^{2 pi} dt / (g - a cos t) = (g^2 - a^2)^(-1/2)
   (Gradshteyn & Ryzhik 3.613.2) differentiated in a (its a -> 0 limit is k_e a),

   i.e. B = B_lin / (1 + R dk(|B|)), B_lin = R F the linear envelope; solved for |B| by
   fixed-point iteration (a contraction while |R dk'| a < 1, far below pull-in and the Duffing
   jump; refused otherwise). Quasi-static: the envelope relaxes at the sense pole |p| (about
   2 pi x the mode split), far faster than any output interval of a rate table.

2. **The differential capacitive pick-off** (Saukoski 2008, ch. 3; Kaajakari 2009, ch. 6):

       dC(y) = eps0 A_s [1/(g - y) - 1/(g + y)] = 2 eps0 A_s y / (g^2 - y^2)   [F],

   odd and expansive: +(y/g)^2 relative, 3/4 of it on the fundamental.

3. **The front end's rail**: a charge amplifier with feedback capacitor C_f reads the pick-off
   on a carrier of amplitude V_c, v = V_c dC(y(t)) / C_f [V], and its output stage clips at
   +-V_rail (a hard rail). The clip acts on the carrier envelope, i.e. on dC(y(t)) itself
   within each drive cycle; the synchronous demodulator then keeps the fundamental at w
   (the describing function of the memoryless odd map y -> clip(V_c dC(y)/C_f); Gelb & Vander
   Velde, *Multiple-Input Describing Functions and Nonlinear System Design*, McGraw-Hill 1968,
   ch. 2). For y = a cos t the fundamental is in phase with y and

       V_1(a) = (4/pi) int_0^{pi/2} clip(V_c dC(a cos t)/C_f) cos t dt        [V],

   exact in two pieces: V_rail sin(t_c) on the clipped arc t < t_c = arccos(y_c/a) (y_c the
   displacement at which the amplifier reaches its rail) and Gauss-Legendre quadrature of the
   smooth rest. :meth:`SenseChain.envelope` returns it as an envelope in metres of unit
   small-signal gain: E(B) = (V_1(|B|) / (K_0 |B|)) B, K_0 = 2 eps0 A_s V_c / (g^2 C_f) [V/m].

The quadrature force is in the envelope B (its phase is 90 deg from the Coriolis force's), so
it shares the rail with the rate: the rate channel Re{w_c E(B)} compresses by the total
amplitude |B|. The ADC that digitises the demodulated channel is the resonator's output word
(``MemsResonator.output_range``, ``output_bits``: a hard clip and rounding).

A closed (force-rebalance) loop holds y ~ 0, where the pick-off and the sense-electrode force
are linear; its carrier push-pull forcer, F = (eps0 A_e/2)[(V_b + v)^2 - (V_b - v)^2]/g^2 =
2 eps0 A_e V_b v / g^2 at y = 0, is linear in the command v (the v^2 terms cancel between the
plates and, on a carrier at w, leave no force at w), so the closed loop's bend is the rebalance
DAC's authority (:func:`gyrobench.sim.mems_resonator.rate_authority`), not this chain.

:class:`SenseChainSpec` is a production population of chains: nominal values with the
manufacturing tolerances (1 sigma) of the gap (etch), the feedback capacitor, the rail, the
sense bias and the cubic stiffness, and every field's documented range (``RANGES``) for maps.

References: M. Saukoski, *System and circuit design for a capacitive MEMS gyroscope*, Helsinki
Univ. of Technology doctoral thesis (2008), ch. 2-3; V. Kaajakari, *Practical MEMS* (2009),
ch. 6-7; A. H. Nayfeh, D. T. Mook, *Nonlinear Oscillations* (Wiley, 1979), ch. 4; A. Gelb,
W. E. Vander Velde (1968), ch. 2; C. Acar, A. Shkel, *MEMS Vibratory Gyroscopes* (Springer,
2009), ch. 2.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.base.ranges import FieldRange, validate
from gyrobench.base.validate import check_rng as _check_rng

__all__ = ["EPSILON_0", "SenseChain", "SenseChainSpec", "TOLERANCE_SOURCES"]

#: vacuum permittivity [F/m] (CODATA 2018)
EPSILON_0 = 8.8541878128e-12

#: Gauss-Legendre nodes and weights on [-1, 1] for the smooth parts of the harmonic integrals
_GL_X, _GL_W = np.polynomial.legendre.leggauss(32)
#: samples per chunk of :meth:`SenseChain.envelope` (32 nodes each: 4 MB of float64 per array)
_CHUNK = 1 << 14

#: where each manufacturing tolerance of :class:`SenseChainSpec` comes from
TOLERANCE_SOURCES: dict[str, str] = {
    "gap_spread": "deep-reactive-ion-etch critical-dimension variation of ~0.05 um across a wafer on a 2 um "
    "gap (STATED ASSUMPTION, the order Saukoski 2008 ch. 2 and Acar & Shkel 2009 ch. 2 give for "
    "fabrication imperfections)",
    "feedback_capacitance_spread": "absolute tolerance of an on-chip poly/MIM capacitor, ~5 % 1-sigma "
    "(STATED ASSUMPTION; ratios match to ~0.1 %, absolute values do not)",
    "rail_spread": "front-end supply/reference tolerance, 1 % 1-sigma (STATED ASSUMPTION)",
    "sense_bias_spread": "bias-voltage reference tolerance, 1 % 1-sigma (STATED ASSUMPTION)",
    "k3_spread": "relative 1-sigma of the flexure's cubic stiffness, 10 % (STATED ASSUMPTION: it scales "
    "with the beam width cubed over its length)",
}


def _harmonic(fun, a: NDArray[np.float64], lo: NDArray[np.float64]) -> NDArray[np.float64]:
    """(4/pi) int_lo^{pi/2} fun(a cos t) cos t dt, Gauss-Legendre on [lo, pi/2] (vectorised in a)."""
    hi = 0.5 * math.pi
    half = 0.5 * (hi - lo)
    t = lo[..., None] + half[..., None] * (_GL_X + 1.0)
    vals = fun(a[..., None] * np.cos(t)) * np.cos(t)
    return (4.0 / math.pi) * half * np.sum(vals * _GL_W, axis=-1)


@dataclass(frozen=True, slots=True, kw_only=True)
class SenseChain:
    """One unit's open-loop sense chain (SI; module docstring for the equations).

    Parameters
    ----------
    gap : float
        g, sense (pick-off) electrode gap at rest [m], > 0.
    sense_area : float
        A_s, overlap area of each plate of the differential pick-off pair [m^2], > 0.
    sense_bias : float
        V_s, effective (rms) voltage between the mass and each sense plate [V], >= 0 (the DC
        bias and the carrier's V_c/sqrt(2) in quadrature): sets the electrostatic softening.
    k3 : float
        Mechanical cubic stiffness of the sense mode [N/m^3], >= 0 (hardening).
    carrier : float
        V_c, pick-off carrier amplitude [V], > 0.
    feedback_capacitance : float
        C_f, charge-amplifier feedback capacitor [F], > 0. Default 6.3e-15 F, a design rule
        (STATED): the default resonator's envelope at the +-3600 deg/s full scale with a
        3-sigma quadrature of its population (1620 deg/s), 1.07e-7 m, reaches half the rail,
        C_f = 2 eps0 A_s V_c y / (g^2 V_rail / 2).
    rail : float
        V_rail, the front end's output rail [V], > 0. Default 1.5 V (a 3.3 V supply less
        the output stage's headroom; STATED).

    The gap, area and bias defaults are the default resonator's electrodes
    (:class:`gyrobench.sim.mems_resonator.MemsResonator`: 2 um, 1e-8 m^2, 5 V); the carrier
    1 V and k3 = 0 (folded flexures, whose stretching is negligible at 0.1 um) are STATED.
    """

    gap: float = 2e-6
    sense_area: float = 1e-8
    sense_bias: float = 5.0
    k3: float = 0.0
    carrier: float = 1.0
    feedback_capacitance: float = 6.3e-15
    rail: float = 1.5

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "gap": FieldRange(0.5e-6, 10e-6, "m", "capacitive MEMS gaps: 0.5-10 um (Kaajakari 2009 ch. 6)"),
        "sense_area": FieldRange(1e-10, 1e-6, "m^2", "sense comb/plate overlap areas"),
        "sense_bias": FieldRange(0.0, 30.0, "V", "MEMS electrode bias: volts to tens of V"),
        "k3": FieldRange(0.0, 1e12, "N/m^3", "cubic stiffness of a flexure, 0 (folded) upward"),
        "carrier": FieldRange(0.01, 10.0, "V", "pick-off carrier amplitude"),
        "feedback_capacitance": FieldRange(1e-15, 1e-10, "F", "charge-amplifier feedback capacitor: fF-100 pF"),
        "rail": FieldRange(0.1, 10.0, "V", "front-end output swing of a 1.8-15 V supply"),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared ranges above (every lower bound of a size is > 0)

    # ------------------------------------------------------------------ pieces
    @property
    def electrostatic_stiffness(self) -> float:
        """k_e = 2 eps0 A_s V_s^2 / g^3 [N/m] (linear part, inside the resonator's tuned split)."""
        return 2.0 * EPSILON_0 * self.sense_area * self.sense_bias**2 / self.gap**3

    @property
    def small_signal_gain(self) -> float:
        """K_0 = 2 eps0 A_s V_c / (g^2 C_f) [V/m]: front-end output per metre at small y."""
        return 2.0 * EPSILON_0 * self.sense_area * self.carrier / (self.gap**2 * self.feedback_capacitance)

    def capacitance_difference(self, y: ArrayLike) -> NDArray[np.float64]:
        """dC(y) = eps0 A_s [1/(g - y) - 1/(g + y)] [F] for |y| < g."""
        y = np.asarray(y, dtype=float)
        return EPSILON_0 * self.sense_area * (1.0 / (self.gap - y) - 1.0 / (self.gap + y))

    def electrode_force(self, y: ArrayLike) -> NDArray[np.float64]:
        """F_e(y) = (eps0 A_s V_s^2 / 2) [1/(g - y)^2 - 1/(g + y)^2] [N] for |y| < g."""
        y = np.asarray(y, dtype=float)
        c = 0.5 * EPSILON_0 * self.sense_area * self.sense_bias**2
        return c * (1.0 / (self.gap - y) ** 2 - 1.0 / (self.gap + y) ** 2)

    def frontend_output(self, y: ArrayLike) -> NDArray[np.float64]:
        """clip(V_c dC(y) / C_f, +-V_rail) [V]: the charge amplifier's carrier envelope at y."""
        v = self.carrier * self.capacitance_difference(y) / self.feedback_capacitance
        return np.clip(v, -self.rail, self.rail)

    @property
    def clip_displacement(self) -> float:
        """y_c [m]: V_c dC(y_c) / C_f = V_rail (the root of c y^2 + 2 eps0 A_s y - c g^2 = 0, c = V_rail C_f/V_c)."""
        c = self.rail * self.feedback_capacitance / self.carrier
        e = EPSILON_0 * self.sense_area
        return (-e + math.sqrt(e * e + (c * self.gap) ** 2)) / c

    def stiffness_change(self, amplitude: ArrayLike) -> NDArray[np.float64]:
        """dk(a) = (3/4) k3 a^2 - (F_e1(a)/a - k_e) [N/m] at first-harmonic amplitude a [m] (< g)."""
        a = np.abs(np.asarray(amplitude, dtype=float))
        g2 = self.gap * self.gap
        # F_e1(a) / a - k_e = k_e [(1 - (a/g)^2)^(-3/2) - 1] (module docstring), as expm1/log1p:
        # no cancellation at small a
        soft = self.electrostatic_stiffness * np.expm1(-1.5 * np.log1p(-(a * a) / g2))
        return 0.75 * self.k3 * a * a - soft

    def describing_gain(self, amplitude: ArrayLike) -> NDArray[np.float64]:
        """V_1(a) / (K_0 a) [-]: the front end's fundamental per unit small-signal output (1 at a -> 0)."""
        a = np.abs(np.asarray(amplitude, dtype=float))
        if np.any(a >= self.gap):
            raise ValueError(f"sense amplitude must stay below the gap {self.gap!r} m; got {float(np.max(a))!r} m")
        safe = np.maximum(a, 1e-300)
        yc = self.clip_displacement
        tc = np.arccos(np.clip(yc / safe, 0.0, 1.0))  # 0 when a <= y_c (no clipping)
        v1 = self.rail * (4.0 / math.pi) * np.sin(tc) + self._smooth_harmonic(safe, tc)
        return np.where(a > 0, v1 / (self.small_signal_gain * safe), 1.0)

    def _smooth_harmonic(self, a: NDArray[np.float64], lo: NDArray[np.float64]) -> NDArray[np.float64]:
        """(4/pi) int_lo^{pi/2} frontend_output(a cos t) cos t dt, Gauss-Legendre (:func:`_harmonic`).

        The same arithmetic as ``_harmonic(self.frontend_output, a, lo)``, element for element and in
        the same order (so the same values), with the nodes' cosines computed once for the
        unclipped amplitudes (lo = 0, the same nodes for all) and the integrand built in place.
        """
        a = np.asarray(a, dtype=float)
        lo = np.asarray(lo, dtype=float)
        if a.ndim != 1 or lo.shape != a.shape:
            return _harmonic(self.frontend_output, a, lo)
        hi = 0.5 * math.pi
        half = 0.5 * (hi - lo)
        cos_t = np.empty((a.size, _GL_X.size))
        flat = lo == 0.0
        cos_t[flat] = np.cos(0.0 + (0.5 * (hi - 0.0)) * (_GL_X + 1.0))
        rest = ~flat
        if np.any(rest):
            cos_t[rest] = np.cos(lo[rest, None] + half[rest, None] * (_GL_X + 1.0))
        vals = np.multiply(a[:, None], cos_t)  # y = a cos t
        inner = np.add(self.gap, vals)
        np.subtract(self.gap, vals, out=vals)
        np.divide(1.0, vals, out=vals)
        np.divide(1.0, inner, out=inner)
        np.subtract(vals, inner, out=vals)  # 1/(g - y) - 1/(g + y)
        del inner
        vals = np.multiply(EPSILON_0 * self.sense_area, vals, out=vals)  # capacitance_difference
        np.multiply(self.carrier, vals, out=vals)
        np.divide(vals, self.feedback_capacitance, out=vals)
        np.clip(vals, -self.rail, self.rail, out=vals)  # frontend_output
        vals *= cos_t
        vals *= _GL_W
        return (4.0 / math.pi) * half * np.sum(vals, axis=-1)

    # ------------------------------------------------------------------ the chain
    def stiffened_envelope(self, linear: ArrayLike, receptance: complex) -> NDArray[np.complex128]:
        """B solving B (1 + R dk(|B|)) = B_lin (harmonic balance), from the linear envelope B_lin = R F [m].

        Fixed-point iteration on |B| from |B_lin|; refused when it does not converge (near
        pull-in or the Duffing jump).
        """
        b_lin = np.asarray(linear, dtype=complex)
        if self.k3 == 0 and self.sense_bias == 0:
            return b_lin.copy()
        r = complex(receptance)
        s = np.abs(b_lin)
        for _ in range(200):
            new = np.abs(b_lin) / np.abs(1.0 + r * self.stiffness_change(np.minimum(s, 0.999 * self.gap)))
            done = np.all(np.abs(new - s) <= 1e-14 * np.maximum(new, 1e-30))
            s = new
            if done:
                break
        else:
            raise ValueError(
                "SenseChain: the sense amplitude does not settle (harmonic balance has no stable "
                f"root: pull-in or a Duffing jump); largest |B_lin| {float(np.max(np.abs(b_lin)))!r} m"
            )
        if np.any(s >= self.gap):
            raise ValueError(f"SenseChain: the sense amplitude reaches the gap {self.gap!r} m (pull-in)")
        return b_lin / (1.0 + r * self.stiffness_change(s))

    def envelope(self, linear: ArrayLike, receptance: complex) -> NDArray[np.complex128]:
        """The demodulated front-end output as an envelope of unit small-signal gain [m].

        E = g_1(|B|) B with B :meth:`stiffened_envelope` of the linear envelope ``linear`` and
        g_1 :meth:`describing_gain` (pick-off and rail; the phase of B is kept: the map is odd
        and memoryless within a cycle). Evaluated in chunks of :data:`_CHUNK` samples (the
        quadrature holds 32 nodes per sample).
        """
        b_lin = np.asarray(linear, dtype=complex)
        flat = b_lin.reshape(-1)
        out = np.empty_like(flat)
        for i in range(0, flat.size, _CHUNK):
            b = self.stiffened_envelope(flat[i : i + _CHUNK], receptance)
            out[i : i + _CHUNK] = self.describing_gain(np.abs(b)) * b
        return out.reshape(b_lin.shape)


_SPREADS = ("gap_spread", "feedback_capacitance_spread", "rail_spread", "sense_bias_spread", "k3_spread")


@dataclass(frozen=True, slots=True, kw_only=True)
class SenseChainSpec:
    """A production population of sense chains: the nominal chain and its manufacturing tolerances.

    Each tolerance is a relative 1-sigma (normal, clipped to +-3 sigma) of one field of
    :class:`SenseChain`; the source of each is :data:`TOLERANCE_SOURCES`. The sense area,
    carrier and range stay at the nominal (set by layout and design, matched to ~0.1 %).

    Parameters
    ----------
    nominal : SenseChain
        The nominal chain (the design).
    gap_spread : float
        Relative 1-sigma of the electrode gap [-].
    feedback_capacitance_spread : float
        Relative 1-sigma of the charge amplifier's feedback capacitance [-].
    rail_spread : float
        Relative 1-sigma of the front end's output rail [-].
    sense_bias_spread : float
        Relative 1-sigma of the sense bias voltage [-].
    k3_spread : float
        Relative 1-sigma of the cubic stiffness [-].
    """

    nominal: SenseChain = field(default_factory=SenseChain)
    gap_spread: float = 0.025
    feedback_capacitance_spread: float = 0.05
    rail_spread: float = 0.01
    sense_bias_spread: float = 0.01
    k3_spread: float = 0.10

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        name: FieldRange(0.0, 0.3, "1", "relative 1-sigma manufacturing tolerance") for name in _SPREADS
    }

    def __post_init__(self) -> None:
        validate(self)  # the spreads' ranges; nominal must be a SenseChain (its annotation)

    def realize(self, *, rng: np.random.Generator) -> SenseChain:
        """One unit's chain: five standard normals (gap, C_f, rail, bias, k3, in that order), clipped to +-3."""
        _check_rng(rng)
        z = np.clip(rng.standard_normal(5), -3.0, 3.0)
        n = self.nominal
        return SenseChain(
            gap=n.gap * (1.0 + self.gap_spread * z[0]),
            sense_area=n.sense_area,
            sense_bias=n.sense_bias * (1.0 + self.sense_bias_spread * z[3]),
            k3=n.k3 * (1.0 + self.k3_spread * z[4]),
            carrier=n.carrier,
            feedback_capacitance=n.feedback_capacitance * (1.0 + self.feedback_capacitance_spread * z[1]),
            rail=n.rail * (1.0 + self.rail_spread * z[2]),
        )
