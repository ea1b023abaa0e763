"""MEMS Coriolis vibratory gyro from resonator physics: 2-DOF rotating-frame model, force rebalance.

All parameters are in SI: m, kg, s, rad, rad/s, N, V, K. Field units enter only through
:meth:`MemsResonatorSpec.from_datasheet`.

Equations of motion (drive x, sense y; frame rotating at Omega about z)::

    m x'' + c_x x' + k_x x + k_xy y + c_xy y' = F_d + 2 m Omega y' + m Omega^2 x + m Omega' y + f_x
    m y'' + c_y y' + k_y y + k_yx x + c_yx x' = F_fb - 2 m Omega x' + m Omega^2 y - m Omega' x + f_y

m modal (= Coriolis) mass [kg]; k = m w^2 [N/m]; c = m w / Q [kg/s]; k_xy = k_yx = kappa k_x
anisoelastic (quadrature) coupling, symmetric [N/m]; c_xy = c_yx = eps_c c_y anisodamping
coupling [kg/s]; f_x, f_y Brownian forces, one-sided PSD 4 k_B T c [N^2/Hz]
(fluctuation-dissipation). The inertial terms come from a_inertial = a_rel + 2 Omega x v +
Omega x (Omega x r) + Omega' x r (docs/physics.md 5.1).

Drive: a self-oscillation loop (force proportional to the drive velocity, F_d = c_a x') whose
gain c_a is set by a PI amplitude controller on the demodulated amplitude
X_hat = sqrt(x^2 + (x'/w_x)^2), holding X_hat = X0. At equilibrium c_a = c_x and the drive
runs at its resonance without a separate PLL.

Sense: force rebalance. The pick-off y_m = y + n (front-end displacement noise n, one-sided
PSD S_n [m^2/Hz]) is demodulated against the drive references (the complex envelope
B_m = <2 y_m e^{-j w t}>); two integral controllers (rate channel u_I, quadrature channel u_Q,
one complex command u = u_I + j u_Q [V]) null it through a differential parallel-plate
electrode pair on a carrier at the drive frequency::

    F_fb = Re{ j G e^{j theta_e} u e^{j w t} },   G = 2 eps0 A_e V_b / g^2   [N/V]
    u'   = j (2 pi f_c) (B_m) / (R_c G_c)          (R_c, G_c: design values at T0)

theta_e is the phase error of the rebalance carrier against the drive velocity (the
demodulation phase error of the rate channel); f_c the closed-loop bandwidth [Hz].
The rate output is the rate-channel command: Omega_hat = K_out u_I with
K_out = s_trim G(T0) / (2 m w_x(T0) X0).

Equilibrium (B = 0) gives (docs/physics.md 5.1)::

    u_I G = 2 m w X0 (Omega + Omega_b) cos(theta_e) - (k_yx + m Omega') X0 sin(theta_e)
    Omega_hat = SF (Omega + Omega_b - Omega_q' tan(theta_e))     (low rates)
    SF = s_trim (w/w0) (G0/G) cos(theta_e),  Omega_q = k_yx / (2 m w),  Omega_b = c_yx / (2 m)

Saturation (the high-range knee). The rebalance DAC's carrier amplitude is limited to
|u| <= v_max; the quadrature channel is served first (it holds a large fixed force), the rate
channel gets the rest, |u_I| <= sqrt(v_max^2 - u_Q^2) (integrator clamp = anti-windup). The
knee is therefore sharp and the output flat beyond it::

    Omega_max = sqrt(F_max^2 - F_q^2) / (2 m w X0) (cos theta_e ~ 1),  F_max = G v_max

the force-rebalance authority of docs/physics.md 5.1 item 1; a closed-loop high-range
design's measurement range is set by it (Saukoski 2008, ch. 2-3: the feedback force range
limits the input range of a force-feedback gyro; Acar & Shkel 2009, ch. 2). The default
design puts it above the +-3600 deg/s range with a margin, so the default raw
nonlinearity over +-3600 deg/s is small. An output-referred odd cubic ``output_cubic``
(rebalance-DAC/actuator gain nonlinearity; default 0) is the only nonlinearity below the knee.

Noise and its closed forms [docs/physics.md 5.1; the factor 2 of synchronous
demodulation is Leland 2005]::

    N_B = sqrt(k_B T c_y) / (m w X0)            Brownian ARW [rad/sqrt(s)] (input-referred)
    N_e = sqrt(S_n) / (|R| 2 m w X0),  R = 1 / (m (w_y^2 - w^2) + j c_y w)   pick-off ARW
    N   = sqrt(N_B^2 + N_e^2),  one-sided rate PSD 2 N^2

Output: ``Omega_hat (1 + e_on) + a3 Omega_hat^3/R^2 + b_on - b_trim + flicker + rrw``, clipped
to +-``output_range`` and rounded to 2 R / 2^bits (ADC quantization and range). flicker and rrw
are the IEEE 952 bias-instability (1/f over :data:`FLICKER_BAND_HZ`) and rate-random-walk terms
of :class:`gyrobench.sim.noise.NoiseModel`. The defaults are one part's, cited
(:data:`NOISE_FIGURES`, ADXRS646): N = 0.01 deg/sqrt(s) (Brownian plus pick-off), B = 18.06
deg/h, K = 0; a 20-bit word (a design choice; LSB below the sample noise at every fs >= 1 Hz:
the noise dithers it).

Open-loop read-out (``readout="open_loop"``): no rebalance force; the sense mass moves,
B = R F_ext at low rates, and the rate channel is the demodulated pick-off envelope
against the design Coriolis phase, Omega_hat = K_ol Re{w_c sat(B_m)}, w_c = j e^{-j theta}/R_c,
K_ol = s_trim/(2 m w0 X0)::

    SF_ol = s_trim (w/w0) Re{e^{-j theta} R(T)/R_c}          (follows the mode split and Q)
    H(f)  = [c_+ G(jW) + conj(c_- G(-jW))] / (2 Re c_0),  G(s) = -p/(s - p)   (bandwidth ~ split)

sat limits |B_m| to the pick-off front end's full scale Y_fs (phase kept): the open-loop knee
Omega_max solves |R F_ext(Omega)| = Y_fs (:func:`rate_authority`).

g-sensitivity: a specific force f along the sense axis displaces the mass, y_s = -m f/k_y;
the forcer plates' overlap changes with the drive motion (A_e(x) = A_e (1 + eps_A x)), so
their electrostatic spring k_e = 2 eps0 A_e V_b^2/g^3 gives the force k_e eps_A x y_s at the
carrier: a quadrature stiffness dk_yx = (k_e eps_A m/k_y) f, which leaks into the rate output
through the phase error, dOmega_hat/df = -SF tan(theta) dk_yx/df/(2 m w)
(:func:`electrostatic_cross_stiffness`, :func:`g_sensitivity`). A drive-axis specific force
f_d shifts x statically, x_s = -m f_d/k_x, and changes k_y by -k_e eps_A x_s (about 1e-5 of
k_y - m w^2 per g: an open-loop SF change of -12.4 ppm/g, none in force rebalance;
:func:`drive_axis_sensitivity`, ``drive_specific_force`` of :func:`operating_point`,
:func:`slow_flow`, :func:`simulate_full`).

Two integrators of the same equations
-------------------------------------
* :func:`simulate_full`: the equations above with the carrier, a fixed-step RK4 vectorised over
  independent cases (short records; the Brownian and pick-off noises are held over a step,
  variance S/(2 dt) per step for one-sided S).
* :func:`slow_flow`: the demodulated slow flow (complex envelopes, drive held at X0 by the AGC)
  at the output rate, exact discretisation of the linear part (matrix exponential; Van Loan
  for the noise) with the output the exact average of u_I over each output interval. The
  rebalance clamp is applied at the step ends. Validated against :func:`simulate_full` in
  tests and in :mod:`gyrobench.scenarios.checks.mems`.

Slow flow (x = Re{A e^{jwt}}, y = Re{B e^{jwt}}, A = X0; "improved" form, docs/physics.md 5.1)::

    B' = p (B - R F~),  p = -w_y/(2 Q_y) + j (w_y sqrt(1 - 1/(4 Q_y^2)) - w)
    F~ = -j 2 m w X0 (Omega + Omega_b) - (k_yx + m Omega') X0 + j G e^{j theta} u + f~
    u' = j (2 pi f_c) (B + n~) / (R_c G_c)

with f~, n~ the envelopes of f_y and n: independent real and imaginary parts, each white with
one-sided PSD 2 S_F (resp. 2 S_n).

Temperature (per call, constant over a record): w(T) = w0 (1 + a_f dT) (both modes);
1/Q(T) = (1/Q0)(1 + b_Q dT); G(T) = G0 (1 + a_G dT) (bias-voltage / DAC reference);
theta(T) = theta0 + g_th dT; Brownian noise at T. Low-rate SF tempco ~ a_f - a_G;
bias tempco through Omega_b ~ 1/Q and Omega_q sin(theta).

References
----------
R. P. Leland, "Mechanical-thermal noise in MEMS gyroscopes", IEEE Sensors J. 5(3):493-500 (2005).
C. Acar, A. Shkel, *MEMS Vibratory Gyroscopes: Structural Approaches to Improve Robustness*,
Springer (2009), ch. 2 (dynamics, quadrature, Brownian noise).
V. Kaajakari, *Practical MEMS* (2009), ch. 6-7 (parallel-plate force, electrostatic spring).
M. Saukoski, *System and circuit design for a capacitive MEMS gyroscope*, Helsinki Univ. of
Technology doctoral thesis (2008), ch. 2-3 (force feedback, quadrature, drive AGC).
M. A. Hopcroft, W. D. Nix, T. W. Kenny, "What is the Young's modulus of silicon?", JMEMS
19(2):229-238 (2010) (TCE about -60 ppm/K, so TCf about -30 ppm/K).
docs/physics.md 5.1.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.base import units
from gyrobench.base.ranges import Constraint, FieldChoice, FieldRange, validate
from gyrobench.base.units import BOLTZMANN  # exact SI, re-exported
from gyrobench.base.validate import check_rng as _check_rng
from gyrobench.base.validate import real_field
from gyrobench.io.recording import Channel, Recording
from gyrobench.sim.mems_readout import SenseChain
from gyrobench.sim.sensor import Environment, check_call

__all__ = [
    "ADEV_MIN_PER_B",
    "BOLTZMANN",
    "DEFAULT_PICKOFF_NOISE",
    "DatasheetFigure",
    "FLICKER_BAND_HZ",
    "LIMIT_SIGMAS",
    "NOISE_FIGURES",
    "EPSILON_0",
    "MemsResonator",
    "OperatingPoint",
    "operating_point",
    "brownian_arw",
    "electronic_arw",
    "quadrature_rate",
    "electrostatic_cross_stiffness",
    "g_sensitivity",
    "low_rate_scale_factor",
    "open_loop_response",
    "open_loop_noise_psd",
    "drive_axis_sensitivity",
    "READOUTS",
    "ERROR_SPLITS",
    "IDEALIZATIONS",
    "external_force",
    "static_rate_output",
    "zero_rate_output",
    "rate_authority",
    "saturated_output",
    "TEMPERATURE_BLOCK",
]

#: length [s] of the blocks over which :meth:`MemsResonator.simulate` holds a varying
#: temperature at its block mean (long against the loop's settling, ms, and short against
#: a chamber's thermal time constants, minutes)
TEMPERATURE_BLOCK = 1.0

#: vacuum permittivity [F/m] (CODATA 2018)
EPSILON_0 = 8.8541878128e-12


#: sigmas a datasheet's +- (or max) limit is read as: the convention of this module's cited
#: defaults and of ``MemsResonatorSpec.from_datasheet(repeatability_convention="limit")``
#: (an assumption: a limit screened in production covers nearly every unit; a "typical"
#: figure is read as 1 sigma, as Analog Devices' EngineerZone note DOC-16082 says their
#: typical specification-table metrics "often reflect one standard deviation")
LIMIT_SIGMAS = 3.0



@dataclass(frozen=True, slots=True)
class DatasheetFigure:
    """One printed datasheet figure behind a default: its value and unit as printed, and where.

    ``value`` is in ``unit`` (field units, exactly as the source prints them); ``source`` names
    the document, its revision and the copy read; ``reading`` says how the default uses it.

    Attributes
    ----------
    value : float
        The figure as printed, in ``unit``.
    unit : str
        The printed unit (field units).
    source : str
        The document, its revision and the copy read.
    reading : str
        How the default uses the figure.
    """

    value: float
    unit: str
    source: str
    reading: str


#: ADEV minimum of a flicker (bias-instability) term over its coefficient B: sqrt(2 ln 2 / pi)
#: = 0.6643 (IEEE Std 952-1997 Annex C; docs/physics.md 1.2). Analog Devices' "in-run bias
#: stability" / "null bias stability" is the ADEV minimum (EngineerZone note DOC-16082: "In run
#: bias stability is the lowest point of the Allan Variance"), so B = figure / 0.6643.
ADEV_MIN_PER_B = math.sqrt(2.0 * math.log(2.0) / math.pi)

#: the cited figures the default noise is set from (docs/physics.md 5.1): both from ONE part,
#: the Analog Devices ADXRS646 (+-250 deg/s, extendable to +-450 deg/s), its data sheet's front
#: page (copy at manualmachine.com, datasheet/adxrs646/8430208). A +-3600 deg/s design is not
#: quieter than this part, so the default noise is an optimistic (lower) bound for the range.
NOISE_FIGURES: dict[str, DatasheetFigure] = {
    "angle_random_walk": DatasheetFigure(
        0.01, "deg/sqrt(s)",
        "ADXRS646 data sheet (Analog Devices), front page feature list: '0.01 deg/sqrt(sec) angle random "
        "walk' (copy at manualmachine.com, datasheet/adxrs646/8430208)",
        "ARW N = 0.01 deg/sqrt(s) = 0.6 deg/sqrt(h); the default pick-off noise makes up what the "
        "Brownian floor (0.33 deg/sqrt(h)) leaves",
    ),
    "bias_drift": DatasheetFigure(
        12.0, "deg/h",
        "ADXRS646 data sheet (Analog Devices), front page general description: 'a low bias drift of "
        "12 deg/hr (typical)' (same copy)",
        "read as the ADEV minimum (Analog Devices EngineerZone note DOC-16082: in-run bias stability "
        "is the lowest point of the Allan deviation); B = 12 / 0.6643 = 18.06 deg/h",
    ),
}

#: band of the default 1/f (bias-instability) term [Hz]: :class:`~gyrobench.sim.noise.NoiseModel`'s
#: (f_low, f_high) with f_high capped at fs/2 when generated; the ADEV is flat within +-1 %
#: for 3.5/fs <= tau <= 0.014/f_low = 3.9 h
FLICKER_BAND_HZ: tuple[float, float] = (1e-6, math.inf)

#: default front-end (pick-off) displacement noise [m/sqrt(Hz)]: with the default resonator's
#: Brownian ARW it gives N = NOISE_FIGURES["angle_random_walk"] (0.01 deg/sqrt(s)), to the
#: 5 digits stored (test): sqrt(N^2 - N_B^2) |R| 2 m w X0 = 2.2658e-13 m/sqrt(Hz)
DEFAULT_PICKOFF_NOISE = 2.2658e-13

#: fields of MemsResonator that must be > 0
_POSITIVE = (
    "mass", "drive_frequency", "drive_q", "sense_q", "drive_amplitude", "electrode_area",
    "electrode_gap", "bias_voltage", "dac_full_scale", "loop_bandwidth", "agc_bandwidth",
    "output_range", "reference_temperature", "pickoff_full_scale",
)
#: the sense read-outs (MemsResonator.readout)
READOUTS = ("force_rebalance", "open_loop")
#: what a record's truth holds of its error (:attr:`MemsResonator.error_split`)
ERROR_SPLITS = ("components", "total")
#: the declared idealisations of a unit (:attr:`MemsResonator.idealization`)
IDEALIZATIONS = ("none", "noise_free", "noise_free_analog")
#: the slow flow's switches each idealisation sets (``slow_flow(noise=, flicker=, adc=)``)
_IDEAL_FLAGS: Mapping[str, Mapping[str, bool]] = {
    "none": {},
    "noise_free": {"noise": False, "flicker": False},
    "noise_free_analog": {"noise": False, "flicker": False, "adc": False},
}
#: fields of MemsResonator that must be >= 0
_NON_NEGATIVE = ("pickoff_noise", "bias_instability", "rate_random_walk", "bias_repeatability",
                 "scale_factor_repeatability")


@dataclass(frozen=True, slots=True, kw_only=True)
class MemsResonator:
    """One MEMS gyro unit: resonator, electrodes and electronics at T0; every field in SI.

    Defaults: a plausible +-3600 deg/s force-rebalance design (module docstring and
    docs/physics.md section 5.1): 2 ug modal mass, 15 kHz drive, +500 Hz mode split, Q = 2000,
    5 um drive amplitude (the docs/physics.md 5.1 example scaled to a lower-Q high-range part),
    parallel-plate rebalance electrodes 1e-8 m^2 at 2 um gap with 5 V bias, a 0.7 V DAC carrier
    limit (rate authority about 4700 deg/s: a 1.3x margin over the range, design choice),
    40 Hz rebalance loop, 20-bit output over +-4000 deg/s. An ASSUMED design, not a
    particular part (docs/physics.md 5.1 says what each value is sized for). Its noise is ONE
    cited part's (:data:`NOISE_FIGURES`, the ADXRS646 data sheet): ARW 0.01 deg/sqrt(s), bias
    instability from its 12 deg/h bias drift read as the ADEV floor, no rate random walk.

    Parameters
    ----------
    mass : float
        m, modal and Coriolis mass of both modes [kg], > 0.
    drive_frequency : float
        f_x, drive resonance at T0 [Hz], > 0.
    mode_split : float
        f_y - f_x at T0 [Hz]; f_y must stay > 0.
    drive_q, sense_q : float
        Q_x, Q_y at T0 [-], > 0.
    drive_amplitude : float
        X0, AGC set point [m], > 0.
    quadrature_coupling : float
        kappa = k_yx / k_x [-] (anisoelasticity; symmetric k_xy = k_yx).
    damping_coupling : float
        eps_c = c_yx / c_y [-] (anisodamping; gives the Coriolis-phase bias c_yx/(2m)).
    phase_error : float
        theta_e, rebalance/demodulation phase error of the rate channel at T0 [rad].
    electrode_area, electrode_gap : float
        A_e [m^2] and g [m] of each plate of the differential rebalance pair, > 0.
    bias_voltage : float
        V_b [V], > 0.
    dac_full_scale : float
        v_max, largest rebalance carrier amplitude [V], > 0.
    loop_bandwidth : float
        f_c, closed-loop bandwidth of the rebalance integrators [Hz], > 0.
    agc_bandwidth : float
        Drive amplitude-loop bandwidth [Hz], > 0 (full integration only).
    pickoff_noise : float
        sqrt(S_n), one-sided displacement-equivalent front-end noise density [m/sqrt(Hz)], >= 0.
        Default :data:`DEFAULT_PICKOFF_NOISE` (2.2658e-13): the cited part's ARW
        N = 0.01 deg/sqrt(s) of :data:`NOISE_FIGURES` with the Brownian floor.
    output_range : float
        R, output full scale [rad/s], > 0.
    output_bits : int or None
        Output word length; q = 2 R / 2^bits (None: not quantized). Default 20, a design
        choice (the cited part's output is analog): LSB 0.0076 deg/s over +-4000 deg/s, below
        the sample noise N sqrt(fs) at every fs >= 1 Hz (0.58 Hz with N = 0.01 deg/sqrt(s)), so
        the noise dithers the quantizer: its error is then uniform on +-q/2, white, variance
        q^2/12 per sample (an ARW of q/sqrt(12 fs): 6.9e-4 deg/sqrt(s) at 10 Hz, 6.9 % of N,
        0.5 % of its variance).
    output_cubic : float
        a3, output-referred odd cubic of the rebalance path [-]: + a3 Omega^3 / R^2.
    forcer_area_gradient : float
        eps_A = (1/A_e) dA_e/dx [1/m]: relative change of the rebalance plates' overlap area
        per metre of drive displacement (the g-sensitivity mechanism, :func:`g_sensitivity`).
        1/L_p for single-ended plates of overlap L_p along the drive; 0 for a double-ended
        arrangement whose overlap changes cancel. Default 2.5e4 1/m: single-ended plates of
        40 um overlap (8x the drive amplitude), a design choice.
    readout : {"force_rebalance", "open_loop"}
        Sense read-out. "force_rebalance": the rebalance loop nulls the sense motion and the
        rate is its rate-channel command. "open_loop": no rebalance; the rate is the sense
        envelope demodulated against the design Coriolis phase, K_ol Re{j e^{-j theta} B_m/R_c}
        with K_ol = s_trim / (2 m w0 X0) (see :func:`open_loop_response`).
    pickoff_full_scale : float
        Y_fs, largest sense envelope amplitude |B_m| the pick-off front end passes [m], > 0
        (open loop only: the envelope is limited to Y_fs, phase kept). Default 1.25e-7 m: the
        nominal open-loop knee 4630 deg/s, beside the rebalance authority 4710 deg/s; a design
        choice (6 % of the 2 um gap). Not used when ``sense_chain`` is given.
    sense_chain : SenseChain or None
        Open loop only: the physical sense chain (:class:`gyrobench.sim.mems_readout.SenseChain`:
        amplitude-dependent stiffness, the differential pick-off's 1/(g - y), the front end's
        rail) applied to the demodulated envelope in place of the ideal limit Y_fs. None
        (default): the ideal limit.
    bias_instability : float
        B of an electronic 1/f term added to the output [rad/s] (IEEE 952: PSD B^2/(2 pi f) over
        :data:`FLICKER_BAND_HZ`, ADEV floor 0.6643 B), >= 0. Default 12/0.6643 deg/h = 18.06
        deg/h: the ADXRS646's 12 deg/h bias drift read as the ADEV minimum
        (:data:`NOISE_FIGURES`).
    rate_random_walk : float
        K of a rate random walk added to the output [rad/s/sqrt(s)] (IEEE 952: AVAR K^2 tau/3),
        >= 0. Default 0: the cited part's front page prints no rate random walk, and a figure
        that could not be read is not used.
    reference_temperature : float
        T0 [K], > 0.
    frequency_tc : float
        a_f, relative resonant-frequency tempco of both modes [1/K].
    q_tc : float
        b_Q, relative tempco of 1/Q (damping) [1/K].
    gain_tc : float
        a_G, relative tempco of the rebalance gain G (bias voltage, DAC reference) [1/K].
    phase_tc : float
        g_th, phase-error tempco [rad/K].
    scale_factor_trim : float
        s_trim, factory scale-factor trim [-], > 0.
    bias_trim : float
        b_trim, factory bias trim subtracted from the output [rad/s].
    bias_repeatability, scale_factor_repeatability : float
        1-sigma turn-on bias [rad/s] and relative scale-factor error [-] drawn per power-on
        by :meth:`power_on`, >= 0. Defaults for a +-3600 deg/s rate (industrial) grade part,
        read from these sources with the convention of :data:`LIMIT_SIGMAS` (a datasheet's
        +- or max limit is 3 sigma; a "typical" value or a grade table's class figure is
        1 sigma):

        * 0.1 deg/s = 360 deg/h: inside the rate-grade bias range 10-1000 deg/h of the grade
          table in A. Norouzpour-Shirazi, "Interface circuits and systems for inertial
          sensors", IEEE Sensors 2013 tutorial (Georgia Tech), in its upper half because a
          high-range part has a coarse output and a large quadrature to reject. Bracketed by
          the ADXRS453 data sheet Rev. B (Analog Devices 2011; +-300 deg/s, 16 deg/h null bias
          stability, an in-run figure: lower bound) and the consumer InvenSense MPU-6050
          initial ZRO tolerance +-20 deg/s (untrimmed, upper bound).
        * 1000 ppm: the lower end of the same table's rate-grade scale-factor accuracy
          0.1-1 %; the tactical Sensonor STIM202 (+-400 deg/s) states +-2000 ppm (Sensonor FAQ
          "functional differences from STIM202 to STIM210"), i.e. 667 ppm at 3 sigma, and a
          rate-grade high-range part is not better than it.
    turn_on_bias, turn_on_scale_factor : float
        b_on [rad/s] and e_on [-] of this power-on (set by :meth:`power_on`; e_on > -1).
    error_split : {"components", "total"}
        What a record of :meth:`simulate` keeps of its error in ``truth``. "components"
        (default): ``deterministic_error`` and ``noise``, which costs a second, noise-free slow
        flow of the whole record. "total": one component ``total_error`` = output - true rate
        (it closes the record alike), without that second run: for a user who reads the output
        only (a rate table's dwell means). The output is the same bit for bit either way.
    idealization : {"none", "noise_free", "noise_free_analog"}
        A declared idealisation of the unit, for reference runs through :meth:`simulate`.
        "none" (default): the unit as built. "noise_free": without its noise sources (the
        Brownian force noise 4 k_B T c_y, the pick-off noise, the 1/f term and the rate random
        walk): the deterministic part of its output (scale factor and nonlinearity, bias,
        quadrature, rails, ADC), the record a ``deterministic_error`` channel is computed from.
        "noise_free_analog": also without the output word (no clip to +-R, no rounding): the
        settled analog output a static sweep reads. A record of an idealised unit is its own
        noise-free run: ``noise`` is zero and no second run is made. It acts on
        :meth:`simulate` only; the analytic noise figures (:func:`brownian_arw`, ...) describe
        the unit as built.
    """

    mass: float = 2e-9
    drive_frequency: float = 15e3
    mode_split: float = 500.0
    drive_q: float = 2000.0
    sense_q: float = 100.0
    drive_amplitude: float = 5e-6
    quadrature_coupling: float = 0.0
    damping_coupling: float = 0.0
    phase_error: float = 0.0
    electrode_area: float = 1e-8
    electrode_gap: float = 2e-6
    bias_voltage: float = 5.0
    dac_full_scale: float = 0.7
    loop_bandwidth: float = 40.0
    agc_bandwidth: float = 100.0
    pickoff_noise: float = DEFAULT_PICKOFF_NOISE
    output_range: float = units.deg_per_s(4000.0)
    output_bits: int | None = 20
    output_cubic: float = 0.0
    forcer_area_gradient: float = 2.5e4
    readout: str = "force_rebalance"
    pickoff_full_scale: float = 1.25e-7
    sense_chain: SenseChain | None = None
    bias_instability: float = units.deg_per_h(12.0 / ADEV_MIN_PER_B)
    rate_random_walk: float = 0.0
    reference_temperature: float = units.celsius(25.0)
    frequency_tc: float = -30e-6
    q_tc: float = 2e-3
    gain_tc: float = 50e-6
    phase_tc: float = 1e-5
    scale_factor_trim: float = 1.0
    bias_trim: float = 0.0
    bias_repeatability: float = units.deg_per_s(0.1)
    scale_factor_repeatability: float = 1e-3
    turn_on_bias: float = 0.0
    turn_on_scale_factor: float = 0.0
    error_split: str = "components"
    idealization: str = "none"

    RANGES: ClassVar[Mapping[str, FieldRange | FieldChoice]] = {
        "mass": FieldRange(0, 1e-3, "kg", "modal mass of a MEMS proof mass: ng to mg", low_open=True),
        "drive_frequency": FieldRange(0, 1e6, "Hz", "MEMS drive resonances are kHz to 100s of kHz", low_open=True),
        "mode_split": FieldRange(-1e5, 1e5, "Hz", "f_y - f_x; __post_init__ keeps f_y > 0"),
        "drive_q": FieldRange(0, 1e7, "1", "air-damped ~10 to vacuum-sealed ~1e6", low_open=True),
        "sense_q": FieldRange(0, 1e7, "1", "air-damped ~10 to vacuum-sealed ~1e6", low_open=True),
        "drive_amplitude": FieldRange(0, 1e-3, "m", "AGC set point: um, well under a mm structure", low_open=True),
        "quadrature_coupling": FieldRange(-1, 1, "1", "k_yx/k_x, a small relative stiffness"),
        "damping_coupling": FieldRange(-1, 1, "1", "c_yx/c_y, a small relative damping"),
        "phase_error": FieldRange(-math.pi / 2, math.pi / 2, "rad", "|theta_e| < pi/2 (__post_init__)", True, True),
        "electrode_area": FieldRange(0, 1e-4, "m^2", "plate area of a MEMS electrode (< 1 cm^2)", low_open=True),
        "electrode_gap": FieldRange(0, 1e-3, "m", "capacitive gap: um", low_open=True),
        "bias_voltage": FieldRange(0, 1000, "V", "electrode bias: volts to tens of V", low_open=True),
        "dac_full_scale": FieldRange(0, 1000, "V", "rebalance carrier limit", low_open=True),
        "loop_bandwidth": FieldRange(0, 1e5, "Hz", "rebalance loop bandwidth", low_open=True),
        "agc_bandwidth": FieldRange(0, 1e5, "Hz", "drive amplitude loop bandwidth", low_open=True),
        "pickoff_noise": FieldRange(0, 1e-6, "m/sqrt(Hz)", "displacement-equivalent front-end noise, >= 0"),
        "output_range": FieldRange(0, 1e4, "rad/s", "output full scale (1e4 rad/s = 573 000 deg/s)", low_open=True),
        "output_bits": FieldRange(2, 64, "bits", "output word length (None: not quantized)", integer=True),
        "output_cubic": FieldRange(-10, 10, "1", "odd cubic a3 of the output, relative to full scale"),
        "forcer_area_gradient": FieldRange(-1e8, 1e8, "1/m", "1/overlap: |eps_A| = 1e8 1/m is a 10 nm overlap"),
        "pickoff_full_scale": FieldRange(0, 1e-3, "m", "largest sense envelope the front end passes", low_open=True),
        "bias_instability": FieldRange(0, 10, "rad/s", "B of the 1/f term (10 rad/s = 2e6 deg/h), >= 0"),
        "rate_random_walk": FieldRange(0, 10, "rad/s/sqrt(s)", "K of the rate random walk, >= 0"),
        "reference_temperature": FieldRange(0, 1000, "K", "trim temperature T0", low_open=True),
        "frequency_tc": FieldRange(-0.01, 0.01, "1/K", "silicon's is -30 ppm/K; 1 %/K bounds any material"),
        "q_tc": FieldRange(-0.1, 0.1, "1/K", "relative tempco of 1/Q; a few 1e-3 /K measured"),
        "gain_tc": FieldRange(-0.1, 0.1, "1/K", "relative tempco of the rebalance gain"),
        "phase_tc": FieldRange(-0.1, 0.1, "rad/K", "phase-error tempco"),
        "scale_factor_trim": FieldRange(0, 10, "1", "factory scale-factor trim near 1, > 0", low_open=True),
        "bias_trim": FieldRange(-1e3, 1e3, "rad/s", "factory bias trim; untrimmed quadrature biases are ~10 rad/s"),
        "bias_repeatability": FieldRange(0, 100, "rad/s", "1-sigma turn-on bias, >= 0"),
        "scale_factor_repeatability": FieldRange(0, 0.3, "1", "1-sigma turn-on SF error; e_on > -1"),
        "turn_on_bias": FieldRange(-1e3, 1e3, "rad/s", "this power-on's bias (power_on draws it)"),
        "turn_on_scale_factor": FieldRange(-1, 1, "1", "this power-on's relative SF error, > -1 (__post_init__)", True),
        "readout": FieldChoice(READOUTS, "force rebalance (closed loop) or open loop"),
        "error_split": FieldChoice(ERROR_SPLITS, "a record's error as its two components, or as one total"),
        "idealization": FieldChoice(IDEALIZATIONS, "the unit as built, without its noise, or also without its ADC"),
    }

    #: the constraints across fields (:class:`~gyrobench.base.ranges.Constraint`)
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "drive_frequency + mode_split > 0",
            lambda c: c.drive_frequency + c.mode_split > 0,
            lambda c: f"mode_split must keep f_y = f_x + split > 0 Hz; got {c.mode_split!r}",
        ),
        Constraint(
            "sense_chain only with readout open_loop",
            lambda c: c.sense_chain is None or c.readout == "open_loop",
            lambda c: "sense_chain needs readout 'open_loop' (a rebalanced mass does not move); "
            f"got readout {c.readout!r}",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above

    @property
    def resolution(self) -> float:
        """Output LSB q = 2 R / 2^bits [rad/s] (0 when not quantized)."""
        return 0.0 if self.output_bits is None else 2.0 * self.output_range / 2**self.output_bits

    def power_on(self, *, rng: np.random.Generator) -> MemsResonator:
        """This unit after one power-on: turn-on bias and scale-factor error drawn anew.

        Two standard normals are drawn, z_b then z_s: b_on = sigma_b z_b,
        e_on = sigma_s z_s (both always drawn, so either is the same whatever the other sigma).
        """
        _check_rng(rng)
        z_b, z_s = rng.standard_normal(2)
        e_on = self.scale_factor_repeatability * float(z_s)
        if not e_on > -1:
            raise ValueError(f"drawn turn-on scale-factor error must be > -1; got {e_on!r}")
        return replace(
            self, turn_on_bias=self.bias_repeatability * float(z_b), turn_on_scale_factor=e_on
        )

    def simulate(self, environment: Environment, *, fs: float, rng: np.random.Generator) -> Recording:
        """One record at ``fs`` [Hz] from the slow flow (:func:`slow_flow`), noise and ADC on.

        Parameters
        ----------
        environment : Environment
            ``true_rate`` [rad/s] and ``specific_force`` [m/s^2] along the sense axis, taken at
            the sample centres and held over each output interval (the slow flow's
            zero-order hold); ``temperature`` [K] of the die (None: the unit's T0). A constant
            temperature runs the record in one call. A varying one is quasi-static: the
            record is cut into blocks of :data:`TEMPERATURE_BLOCK` seconds, each simulated at
            its mean temperature from the noise-free equilibrium of its first rate, with its
            own child stream of ``rng``; the loop's transient at a block start (a few loop
            time constants, ms) and the 1/f term's memory across blocks are lost. The model
            has no vibration input: a set ``vibration`` is listed in ``ignored_inputs``.
            ``true_rate`` as an (n, k) array runs k independent segments of n samples side
            by side (one slow-flow call, each column from the noise-free equilibrium of its
            first rate: a rate table's dwells), at a constant temperature.
        fs : float
            Output rate [Hz].
        rng : numpy.random.Generator
            The slow flow's streams (one child per temperature block).

        Returns
        -------
        Recording
            Channels ``output`` [rad/s] and ``temperature`` [K]; truth ``true_rate`` and the
            two components of ``error_components``: ``deterministic_error``, the error of the
            same slow flow run without noise (``noise=False, flicker=False``; the scale factor
            and its nonlinearity, bias, quadrature, rails and ADC), and ``noise``, the record
            minus that noise-free run (Brownian and pick-off noise and the 1/f term, through
            the nonlinear read-out, with the ADC's rounding of them); inputs ``temperature``
            and ``specific_force``. The noise-free run draws nothing from ``rng``. With
            ``error_split="total"`` the truth holds ``total_error`` (output - true rate) in
            their place and the noise-free run is not made.
            An idealised unit (``idealization``) runs once, with its noise (and, for
            "noise_free_analog", its ADC) off: its ``deterministic_error`` is its whole error
            and its ``noise`` is zero.
            With k segments the channels hold them one after another (column by column, n k
            samples) and the metadata's ``segments`` is k (1 for one record).

        Raises
        ------
        ValueError
            Fewer than 2 samples, or segments with a varying temperature.
        """
        from gyrobench.sim.mems_slow_flow import slow_flow  # it imports this module

        fs = check_call(environment, fs, rng, columns=True)
        n = environment.n_samples(fs)
        if n < 2:
            raise ValueError(f"duration * fs must give >= 2 samples; got {environment.duration!r} s at {fs!r} Hz")
        rate = environment.sampled("true_rate", fs)
        force = environment.sampled("specific_force", fs)
        temp = environment.sampled("temperature", fs, default=self.reference_temperature)
        flags = _IDEAL_FLAGS[self.idealization]
        quiet = {"noise": False, "flicker": False}
        ideal = self.idealization != "none"  # the record is its own noise-free run: no second run
        split = self.error_split == "components"  # else no noise-free run: the truth is the total error
        calm_run = split and not ideal
        k = environment.columns
        if rate.ndim == 2 and k == 1:  # one (n, 1) segment is the 1-D record
            rate = rate[:, 0]
        if k > 1:
            if not np.all(temp == temp[0]):
                raise ValueError("Environment.temperature must be constant for independent segments (k columns)")
            columns = slow_flow(self, rate, fs=fs, rng=rng, temperature=float(temp[0]), specific_force=force[:, None],
                                **flags)
            if calm_run:
                calm = slow_flow(self, rate, fs=fs, rng=np.random.default_rng(0), temperature=float(temp[0]),
                                 specific_force=force[:, None], **quiet).output.T.reshape(-1)
            out, rate = (a.T.reshape(-1) for a in (columns.output, rate))
            temp, force = np.full(n * k, temp[0]), np.tile(force, k)
            blocks = 1
        elif np.all(temp == temp[0]):
            out = np.empty(n)
            calm = np.empty(n)  # the same run without noise: the deterministic part of the error
            out[:] = slow_flow(self, rate, fs=fs, rng=rng, temperature=float(temp[0]), specific_force=force,
                               **flags).output
            if calm_run:
                calm[:] = slow_flow(self, rate, fs=fs, rng=np.random.default_rng(0), temperature=float(temp[0]),
                                    specific_force=force, **quiet).output
            blocks = 1
        else:
            out = np.empty(n)
            calm = np.empty(n)
            m = max(2, int(round(TEMPERATURE_BLOCK * fs)))
            starts = list(range(0, n, m))
            if n - starts[-1] < 2 and len(starts) > 1:  # a last block of one sample joins the one before
                starts.pop()
            stops = starts[1:] + [n]
            for (a, b), child in zip(zip(starts, stops, strict=True), rng.spawn(len(starts)), strict=True):
                res = slow_flow(
                    self, rate[a:b], fs=fs, rng=child, temperature=float(np.mean(temp[a:b])), specific_force=force[a:b],
                    **flags,
                )
                out[a:b] = res.output
                if calm_run:
                    calm[a:b] = slow_flow(self, rate[a:b], fs=fs, rng=np.random.default_rng(0),
                                          temperature=float(np.mean(temp[a:b])), specific_force=force[a:b],
                                          **quiet).output
            blocks = len(starts)
        if split and ideal:
            calm = out
        if split:
            errors = {
                "deterministic_error": Channel(calm - rate, "rad/s", "the noise-free slow flow's error: scale "
                                               "factor and nonlinearity, bias, quadrature, rails, ADC"),
                "noise": Channel(out - calm, "rad/s", "the record minus its noise-free run: Brownian, pick-off "
                                 "and 1/f noise through the read-out"),
            }
        else:
            errors = {"total_error": Channel(out - rate, "rad/s", "output - true rate (error_split 'total': "
                                             "not split into deterministic error and noise)")}
        return Recording(
            fs=fs,
            channels={
                "output": Channel(out, "rad/s", "gyro output"),
                "temperature": Channel(temp, "K", "die temperature (as driven)"),
            },
            truth={"true_rate": Channel(rate, "rad/s", "input rate about the sense axis"), **errors},
            inputs={
                "temperature": Channel(temp, "K", "die temperature"),
                "specific_force": Channel(force, "m/s^2", "specific force along the sense axis"),
            },
            t0=0.5 / fs,
            metadata={
                "model": "gyrobench.sim.mems_resonator.MemsResonator (slow flow)",
                "temperature_blocks": blocks,
                "segments": k,
                "ignored_inputs": environment.ignored("vibration"),
                "error_components": list(errors),
            },
            name="mems",
        )


@dataclass(frozen=True, slots=True)
class OperatingPoint:
    """The unit's physical constants at one temperature (SI); see :func:`operating_point`.

    Every field in SI (below).

    Attributes
    ----------
    m : float
        Modal mass [kg].
    wx, wy : float
        Drive and sense natural frequencies [rad/s].
    cx, cy : float
        Drive and sense damping [kg/s].
    kx, ky, kyx : float
        Drive, sense and quadrature (cross) stiffness [N/m].
    cyx : float
        Cross damping [kg/s].
    x0 : float
        Drive amplitude [m].
    gain : float
        Forcer gain G [N/V].
    theta : float
        Phase error [rad].
    temperature : float
        Die temperature [K].
    k_out : float
        Output conversion [rad/s per V], fixed at T0.
    kappa_c : complex
        Controller constant j 2 pi f_c / (R_c G_c) [V/(m s)].
    v_max : float
        Rebalance command limit [V].
    kyx_g : float
        dk_yx/df [N/m per m/s^2], the electrostatic cross-stiffness per specific force along the
        sense axis (:func:`g_sensitivity`).
    r_design : complex
        R_c [m/N], the T0 receptance the controller and the open-loop demodulator are designed with.
    open_loop : bool
        The readout is open loop.
    y_fs : float
        Pick-off full scale [m].
    chain : SenseChain or None
        The open-loop sense chain (None: the ideal pick-off).
    """

    m: float
    wx: float
    wy: float
    cx: float
    cy: float
    kx: float
    ky: float
    kyx: float
    cyx: float
    x0: float
    gain: float
    theta: float
    temperature: float
    k_out: float
    kappa_c: complex
    v_max: float
    kyx_g: float = 0.0
    r_design: complex = 0j
    open_loop: bool = False
    y_fs: float = math.inf
    chain: SenseChain | None = None

    @property
    def receptance(self) -> complex:
        """R = 1 / (m (w_y^2 - w^2) + j c_y w) [m/N] at the drive frequency."""
        return 1.0 / (self.ky - self.m * self.wx**2 + 1j * self.cy * self.wx)

    @property
    def pole(self) -> complex:
        """Sense envelope pole p = -w_y/(2Q_y) + j(w_y sqrt(1 - 1/(4Q_y^2)) - w) [1/s]."""
        zeta = self.cy / (2.0 * self.m * self.wy)
        return -zeta * self.wy + 1j * (self.wy * math.sqrt(1.0 - zeta * zeta) - self.wx)

    @property
    def loop_poles(self) -> NDArray[np.complex128]:
        """Closed-loop poles of the slow flow: roots of s^2 - p s + c p [1/s].

        c = kappa_c R j G e^{j theta}.

        The integral controller on the first-order sense envelope: the two real parts sum to
        Re p = -w_y/(2 Q_y), so the loop bandwidth must stay below the sense half-bandwidth.
        """
        c = self.kappa_c * self.receptance * 1j * self.gain * complex(np.exp(1j * self.theta))
        return np.roots([1.0, -self.pole, c * self.pole]).astype(np.complex128)

    @property
    def coriolis_gain(self) -> float:
        """2 m w X0 [N s/rad]: Coriolis force amplitude per rad/s."""
        return 2.0 * self.m * self.wx * self.x0


def _gain(unit: MemsResonator) -> float:
    return 2.0 * EPSILON_0 * unit.electrode_area * unit.bias_voltage / unit.electrode_gap**2


def operating_point(
    unit: MemsResonator, temperature: float | None = None, *, drive_specific_force: float = 0.0
) -> OperatingPoint:
    """The unit's constants at die temperature ``temperature`` [K] (default T0).

    ``drive_specific_force`` f_d [m/s^2], constant: specific force along the drive axis. It
    displaces the drive statically, x_s = -m f_d/k_x, and the forcer plates' overlap term
    k_e eps_A x y (:func:`electrostatic_cross_stiffness`) then changes the sense stiffness,
    k_y -> k_y + k_e eps_A m f_d / k_x [DERIVED] (w_y follows; c_y does not). The open-loop
    scale factor follows R (:func:`drive_axis_sensitivity`); force rebalance nulls the motion
    and keeps its scale factor. The full integration gets this from its own equations.

    Parameters
    ----------
    unit : MemsResonator
        The unit.
    temperature : float or None
        Die temperature [K]; None: the unit's T0.
    drive_specific_force : float
        Constant specific force f_d along the drive axis [m/s^2].

    Returns
    -------
    OperatingPoint
        The unit's physical constants at that temperature.
    """
    if not isinstance(unit, MemsResonator):
        raise TypeError(f"unit must be a MemsResonator; got {type(unit).__name__}")
    f_d = real_field("operating_point", "drive_specific_force", drive_specific_force)
    t0 = unit.reference_temperature
    t = t0 if temperature is None else real_field("operating_point", "temperature", temperature)
    if not t > 0:
        raise ValueError(f"temperature must be > 0 K; got {t!r}")
    dt = t - t0
    m = unit.mass
    wx0 = 2.0 * math.pi * unit.drive_frequency
    wy0 = 2.0 * math.pi * (unit.drive_frequency + unit.mode_split)
    sf = 1.0 + unit.frequency_tc * dt
    dq = 1.0 + unit.q_tc * dt
    if not (sf > 0 and dq > 0):
        raise ValueError(f"temperature {t!r} K is outside the linear tempco range of this unit")
    wx, wy = wx0 * sf, wy0 * sf
    cx = m * wx / unit.drive_q * dq
    cy = m * wy / unit.sense_q * dq
    kx, ky = m * wx * wx, m * wy * wy
    g0 = _gain(unit)
    gain = g0 * (1.0 + unit.gain_tc * dt)
    # electrostatic spring times overlap gradient k_e eps_A [N/m per m]
    ke_eps = gain * unit.bias_voltage / unit.electrode_gap * unit.forcer_area_gradient
    kyx_g = ke_eps * m / ky
    ky_d = ky + ke_eps * m * f_d / kx  # sense stiffness with the drive displaced by x_s
    if not ky_d > 0:
        raise ValueError(f"drive_specific_force {f_d!r} m/s^2 leaves no sense stiffness")
    # controller designed at T0 with theta = 0: R_c the T0 receptance
    rc = 1.0 / (m * (wy0**2 - wx0**2) + 1j * (m * wy0 / unit.sense_q) * wx0)
    kappa_c = 1j * 2.0 * math.pi * unit.loop_bandwidth / (rc * g0)
    open_loop = unit.readout == "open_loop"
    k_out = unit.scale_factor_trim * (1.0 if open_loop else g0) / (
        2.0 * m * wx0 * unit.drive_amplitude)
    op = OperatingPoint(
        m=m, wx=wx, wy=wy if f_d == 0 else math.sqrt(ky_d / m), cx=cx, cy=cy, kx=kx, ky=ky_d,
        kyx=unit.quadrature_coupling * kx, cyx=unit.damping_coupling * cy,
        x0=unit.drive_amplitude, gain=gain, theta=unit.phase_error + unit.phase_tc * dt,
        temperature=t, k_out=k_out, kappa_c=complex(kappa_c), v_max=unit.dac_full_scale,
        kyx_g=kyx_g,
        r_design=complex(rc), open_loop=open_loop, y_fs=unit.pickoff_full_scale,
        chain=unit.sense_chain,
    )
    roots = op.loop_poles
    if not open_loop and not np.all(roots.real < 0):
        raise ValueError(
            f"rebalance loop unstable at {t!r} K: loop_bandwidth {unit.loop_bandwidth!r} Hz "
            "must stay below about the sense half-bandwidth f_y/(2 Q_y) = "
            f"{op.cy / (2 * op.m) / (2 * math.pi):.3g} Hz"
        )
    return op


# ----------------------------------------------------------------------------- closed forms
def brownian_arw(unit: MemsResonator, temperature: float | None = None) -> float:
    """Input-referred Brownian ARW N_B = sqrt(k_B T c_y) / (m w X0) [rad/sqrt(s)].

    Equivalently sqrt(k_B T w_y / (m Q_y)) / (w X0); -> sqrt(k_B T / (m Q_y X0^2 w)) when
    mode-matched. One-sided rate PSD 2 N_B^2. Leland (2005) (the in-phase demodulated channel
    carries half the band-pass noise power), docs/physics.md 5.1.

    Parameters
    ----------
    unit : MemsResonator
        The unit.
    temperature : float or None
        Die temperature [K]; None: the unit's T0.

    Returns
    -------
    float
        N_B [rad/sqrt(s)].
    """
    op = operating_point(unit, temperature)
    return math.sqrt(BOLTZMANN * op.temperature * op.cy) / (op.m * op.wx * op.x0)


def electronic_arw(unit: MemsResonator, temperature: float | None = None) -> float:
    """Input-referred pick-off ARW N_e = sqrt(S_n) / (|R| 2 m w X0) [rad/sqrt(s)].

    Parameters
    ----------
    unit : MemsResonator
        The unit.
    temperature : float or None
        Die temperature [K]; None: the unit's T0.

    Returns
    -------
    float
        N_e [rad/sqrt(s)].
    """
    op = operating_point(unit, temperature)
    return unit.pickoff_noise / (abs(op.receptance) * op.coriolis_gain)


def quadrature_rate(unit: MemsResonator, temperature: float | None = None) -> float:
    """Quadrature-equivalent rate Omega_q = k_yx / (2 m w) [rad/s] (docs/physics.md 5.1).

    Parameters
    ----------
    unit : MemsResonator
        The unit.
    temperature : float or None
        Die temperature [K]; None: the unit's T0.

    Returns
    -------
    float
        Omega_q [rad/s].
    """
    op = operating_point(unit, temperature)
    return op.kyx / (2.0 * op.m * op.wx)


def electrostatic_cross_stiffness(unit: MemsResonator, temperature: float | None = None) -> float:
    """dk_yx/df [N/m per m/s^2]: quadrature stiffness per unit specific force along the sense axis.

    The differential forcer pair (gap g, bias V_b, area A_e(x) = A_e (1 + eps_A x)) has the
    co-energy W = (eps0 A_e(x) V_b^2 / 2) [1/(g - y) + 1/(g + y)], so
    F_y = dW/dy = k_e (1 + eps_A x) y + O(y^3/g^3) with the electrostatic spring
    k_e = 2 eps0 A_e V_b^2 / g^3 = G V_b / g, and F_x = dW/dx = k_e eps_A y^2 / 2 + const.
    A specific force f along the sense axis displaces the mass statically, y_s = -m f / k_y,
    and the term k_e eps_A x y_s is a force at the carrier in phase with the drive
    displacement: a quadrature stiffness dk_yx = -k_e eps_A y_s = k_e eps_A m f / k_y
    [DERIVED; Kaajakari 2009 ch. 6-7 for the parallel-plate force and spring]. Quadrature
    reaches the rate output only through the phase error (:func:`g_sensitivity`).

    Parameters
    ----------
    unit : MemsResonator
        The unit.
    temperature : float or None
        Die temperature [K]; None: the unit's T0.

    Returns
    -------
    float
        dk_yx/df [N/m per m/s^2].
    """
    return operating_point(unit, temperature).kyx_g


def g_sensitivity(unit: MemsResonator, temperature: float | None = None) -> float:
    """d Omega_hat / d f [rad/s per m/s^2]: output change per specific force along the sense axis.

    Force rebalance: -SF tan(theta) dk_yx/df / (2 m w) (the quadrature leak of
    :func:`zero_rate_output`); open loop: the same quadrature force read through
    Re{e^{-j theta} R/R_c} (:func:`zero_rate_output`). Exact for the linear model
    (from the noise-free equilibrium at f = 0 and 1 m/s^2).

    Parameters
    ----------
    unit : MemsResonator
        The unit.
    temperature : float or None
        Die temperature [K]; None: the unit's T0.

    Returns
    -------
    float
        d Omega_hat / d f [rad/s per m/s^2].
    """
    return zero_rate_output(unit, temperature, specific_force=1.0) - zero_rate_output(
        unit, temperature
    )


def _equilibrium_command(
    op: OperatingPoint, rate: NDArray, accel: NDArray, force: NDArray | float = 0.0
) -> NDArray:
    """u (complex) that nulls the sense envelope: j G e^{j theta} u = -F_ext."""
    return -_f_ext(op, rate, accel, force) / (1j * op.gain * np.exp(1j * op.theta))


def _f_ext(op: OperatingPoint, rate: NDArray, accel: NDArray, force: NDArray | float = 0.0):
    """The external sense force envelope F_ext [N] (complex)."""
    return (-1j * op.coriolis_gain * rate - 1j * op.wx * op.cyx * op.x0
            - (op.kyx + op.kyx_g * force + op.m * accel) * op.x0)


def _readout_weight(op: OperatingPoint) -> complex:
    """w_c = j e^{-j theta} / R_c [N/m]: the open-loop demodulator (rate channel Re{w_c B_m})."""
    return complex(1j * np.exp(-1j * op.theta) / op.r_design)


def _limit(b: NDArray, y_fs: float) -> NDArray:
    """Front-end limit of the envelope amplitude: b min(1, Y_fs/|b|) (phase kept)."""
    mag = np.abs(b)
    return b * np.minimum(1.0, y_fs / np.maximum(mag, 1e-300))


def _front_end(op: OperatingPoint, b: NDArray) -> NDArray:
    """The open-loop front end on the linear envelope ``b`` [m]: the unit's sense chain
    (:meth:`SenseChain.envelope`) when it has one, else the ideal limit Y_fs."""
    if op.chain is not None:
        return op.chain.envelope(b, op.receptance)
    return _limit(b, op.y_fs)


def _static_channels(
    op: OperatingPoint, rate: NDArray, accel: NDArray, force: NDArray | float = 0.0
) -> NDArray:
    """Noise-free settled channels (complex; the real part is the rate channel), unclamped in
    force rebalance (the equilibrium command u [V]); open loop w_c sat(R F_ext) [N]."""
    if op.open_loop:
        return _readout_weight(op) * _front_end(op, op.receptance * _f_ext(op, rate, accel, force))
    return _equilibrium_command(op, rate, accel, force)


def external_force(
    op: OperatingPoint, rate: NDArray, accel: NDArray | float = 0.0, force: NDArray | float = 0.0
) -> NDArray:
    """The external sense-force envelope F_ext [N] (complex) at rate, rate derivative and force.

    F_ext = -j G_c Omega - j w_x c_yx X0 - (k_yx + (dk_yx/df) f + m Omega') X0: the Coriolis
    force, the anisodamping and quadrature forces and the Euler term (docs/physics.md 5.1).
    The sense envelope of an open-loop unit is R F_ext before its front end.

    Parameters
    ----------
    op : OperatingPoint
        The unit at its temperature (:func:`operating_point`).
    rate : ndarray
        Omega, the rate about the sense axis [rad/s].
    accel : ndarray or float
        Omega', its derivative [rad/s^2] (0: a constant rate).
    force : ndarray or float
        f, the specific force along the sense axis [m/s^2].

    Returns
    -------
    ndarray
        F_ext [N], complex (real: in phase with the drive velocity).
    """
    return _f_ext(op, rate, np.asarray(accel, dtype=float), force)


def static_rate_output(
    unit: MemsResonator, rate: NDArray, temperature: float | None = None
) -> NDArray:
    """Noise-free settled rate output Omega_hat [rad/s] at constant rates, before the turn-on bias.

    The output map of the static rate channel: in force rebalance the equilibrium command
    (unclamped: below the rate authority), open loop the demodulated envelope
    Re{w_c sat(R F_ext)} through the unit's front end; then k_out (1 + e_on) and the output
    cubic. Without the turn-on bias, the bias trim, the 1/f term and the ADC: the shape of a
    noise-free rate table (its nonlinearity), at zero specific force.

    Parameters
    ----------
    unit : MemsResonator
        The unit.
    rate : ndarray
        Constant rates [rad/s].
    temperature : float or None
        Die temperature [K] (None: T0).

    Returns
    -------
    ndarray
        Omega_hat per rate [rad/s].
    """
    op = operating_point(unit, temperature)
    w = np.asarray(rate, dtype=float)
    return _output_map(unit, op, _static_channels(op, w, np.zeros(w.shape)).real)


def low_rate_scale_factor(
    unit: MemsResonator, temperature: float | None = None, *, drive_specific_force: float = 0.0
) -> float:
    """Low-rate scale factor d Omega_hat / d Omega [-] below the knee (noise-free).

    Force rebalance: SF = (1 + e_on) s_trim (w/w0) (G0/G) cos(theta)  [DERIVED from the
    equilibrium u]. Open loop: SF = (1 + e_on) s_trim (w/w0) Re{e^{-j theta} R(T)/R_c}, the
    sense receptance R = 1/(m (w_y^2 - w^2) + j c_y w) at the drive frequency relative to its
    design value [DERIVED from B = R F_ext]: it follows the mode split and Q.
    ``drive_specific_force`` [m/s^2] along the drive axis: see :func:`operating_point`.

    Parameters
    ----------
    unit : MemsResonator
        The unit.
    temperature : float or None
        Die temperature [K]; None: the unit's T0.
    drive_specific_force : float
        Constant specific force along the drive axis [m/s^2].

    Returns
    -------
    float
        SF [-].
    """
    op = operating_point(unit, temperature, drive_specific_force=drive_specific_force)
    if op.open_loop:
        return (1.0 + unit.turn_on_scale_factor) * op.k_out * op.coriolis_gain * float(
            (np.exp(-1j * op.theta) * op.receptance / op.r_design).real)
    return (1.0 + unit.turn_on_scale_factor) * op.k_out * op.coriolis_gain * math.cos(
        op.theta
    ) / op.gain


def drive_axis_sensitivity(unit: MemsResonator, temperature: float | None = None) -> float:
    """Relative scale-factor change per specific force along the drive axis [1/(m/s^2)].

    The static drive displacement x_s = -m f_d/k_x changes the sense stiffness through the
    forcer plates' overlap gradient, dk_y/df_d = k_e eps_A m/k_x (:func:`operating_point`).
    Open loop: SF ~ Re{e^{-j theta} R/R_c}, dR = -R^2 dk_y, so

        d ln SF / d f_d = -(k_e eps_A m/k_x) Re{e^{-j theta} R^2/R_c} / Re{e^{-j theta} R/R_c}
                        ~ -(k_e eps_A / w_x^2) / (m (w_y^2 - w_x^2))   (Q_y >> 1, theta ~ 0)

    [DERIVED]: -12.4 ppm/g for the defaults (-12.7 with the Q_y >> 1 form). Force
    rebalance: 0 (the loop nulls the sense motion; only its loop poles move). Returned as the
    secant of the noise-free scale factor between f_d = 0 and 1 m/s^2 (the stiffness change
    is linear in f_d; the response's curvature leaves ~1e-5 relative).

    Parameters
    ----------
    unit : MemsResonator
        The unit.
    temperature : float or None
        Die temperature [K]; None: the unit's T0.

    Returns
    -------
    float
        d ln SF / d f_d [1/(m/s^2)] (0 for force rebalance).
    """
    s0 = low_rate_scale_factor(unit, temperature)
    return low_rate_scale_factor(unit, temperature, drive_specific_force=1.0) / s0 - 1.0


def open_loop_response(
    unit: MemsResonator, frequency: ArrayLike, temperature: float | None = None
) -> NDArray[np.complex128]:
    """Open-loop rate-to-output frequency response relative to DC, H(f)/H(0) [-] (complex).

    The sense envelope obeys B' = p (B - R F) (:func:`slow_flow`), so a force component
    e^{j W t} reaches B through G(jW) = -p/(jW - p). A real rate cos(W t) applies the Coriolis
    and the angular-acceleration (Euler) forces, F = -j 2 m w X0 Omega - m X0 Omega', i.e.
    F_+- = -j m X0 (2 w +- W) on e^{+-j W t}; the output Re{w_c B} is Re{H e^{j W t}} with
    H = [c_+ G(jW) + conj(c_- G(-jW))]/2, c_+- = w_c R F_+- [DERIVED], returned divided by the
    DC gain Re{c_0}. |H| peaks near the mode split |Im p| and falls beyond it: the open-loop
    bandwidth is set by the split and the sense half-bandwidth w_y/(2 Q_y).

    Parameters
    ----------
    unit : MemsResonator
        The unit (open-loop readout).
    frequency : array_like
        Rate frequencies f [Hz].
    temperature : float or None
        Die temperature [K]; None: the unit's T0.

    Returns
    -------
    ndarray of complex
        H(f)/H(0) [-] at each frequency.
    """
    op = operating_point(unit, temperature)
    f = np.asarray(frequency, dtype=float)
    if not np.all(np.isfinite(f)):
        raise ValueError("frequency must be finite [Hz]")
    p = op.pole
    cw = _readout_weight(op) * op.receptance * (-1j * op.m * op.x0)

    def g(s: NDArray) -> NDArray:
        return -p / (s - p)

    w = 2.0 * math.pi * f
    h = (cw * (2 * op.wx + w) * g(1j * w) + np.conj(cw * (2 * op.wx - w) * g(-1j * w))) / 2.0
    return np.asarray(h / (cw * 2 * op.wx).real, dtype=np.complex128)


def open_loop_noise_psd(
    unit: MemsResonator, frequency: ArrayLike, temperature: float | None = None
) -> NDArray[np.float64]:
    """One-sided PSD of the open-loop output noise [(rad/s)^2/Hz] (slow flow, continuous time).

    The envelope noises of :func:`slow_flow` (force f~ and pick-off n~: independent real and
    imaginary parts, each of two-sided intensity S_F = 4 k_B T c_y [N^2/Hz] resp.
    S_n [m^2/Hz]) reach the output K Re{w_c (B + n~)}, K = k_out (1 + e_on),
    through B = G R f~, G(s) = -p/(s - p). The real part of a circular process keeps the mean of
    its two sidebands [DERIVED]::

        S(f) = 2 K^2 [ |w_c R|^2 S_F (|G(jW)|^2 + |G(-jW)|^2)/2 + |w_c|^2 S_n ],  W = 2 pi f

    At f = 0, T = T0: S(0) = 2 SF^2 (N_B^2 + N_e^2)/cos^2(theta) (:func:`brownian_arw`,
    :func:`electronic_arw`). The Brownian part peaks near the mode split (|G| up to
    |p|/|Re p|); the pick-off part is white. This is the PSD before the output's interval
    mean; sampled at fs it becomes sum_k S(f + k fs) sinc^2((f + k fs)/fs). The full
    equations differ from it by O(f/f_x): the slow flow's first-order envelope and its ideal
    demodulator (docs/physics.md 5.1; ``mems.open_loop_noise_psd_vs_full``).

    Parameters
    ----------
    unit : MemsResonator
        The unit (open-loop readout).
    frequency : array_like
        Frequencies f [Hz].
    temperature : float or None
        Die temperature [K]; None: the unit's T0.

    Returns
    -------
    ndarray
        S(f) [(rad/s)^2/Hz], one-sided.
    """
    op = operating_point(unit, temperature)
    if not op.open_loop:
        raise ValueError(f"unit.readout must be 'open_loop'; got {unit.readout!r}")
    brown, white = _open_loop_noise_parts(unit, op, frequency)
    return np.asarray(brown + white, dtype=np.float64)


def _open_loop_noise_parts(
    unit: MemsResonator, op: OperatingPoint, frequency: ArrayLike
) -> tuple[NDArray[np.float64], float]:
    """(Brownian part S_B(f), white pick-off level) of :func:`open_loop_noise_psd`, one-sided."""
    f = np.asarray(frequency, dtype=float)
    if not np.all(np.isfinite(f)):
        raise ValueError("frequency must be finite [Hz]")
    k = op.k_out * (1.0 + unit.turn_on_scale_factor)
    wc = _readout_weight(op)
    p = op.pole
    s_f = 4.0 * BOLTZMANN * op.temperature * op.cy
    w = 2.0 * math.pi * f
    g2 = (np.abs(p / (1j * w - p)) ** 2 + np.abs(p / (-1j * w - p)) ** 2) / 2.0
    brown = 2.0 * k**2 * abs(wc * op.receptance) ** 2 * s_f * g2
    white = 2.0 * k**2 * abs(wc) ** 2 * unit.pickoff_noise**2
    return np.asarray(brown, dtype=np.float64), float(white)


def zero_rate_output(
    unit: MemsResonator, temperature: float | None = None, *, specific_force: float = 0.0
) -> float:
    """Noise-free output at Omega = 0 [rad/s]: SF (Omega_b - Omega_q tan theta) + b_on - b_trim.

    Omega_b = c_yx / (2 m) (anisodamping, Coriolis phase), Omega_q sin(theta) the quadrature
    leaking through the phase error; Omega_q includes the specific-force part
    (dk_yx/df) f / (2 m w) (``specific_force`` f [m/s^2] along the sense axis).

    Parameters
    ----------
    unit : MemsResonator
        The unit.
    temperature : float or None
        Die temperature [K]; None: the unit's T0.
    specific_force : float
        Constant specific force f along the sense axis [m/s^2].

    Returns
    -------
    float
        The output at zero rate [rad/s].
    """
    op = operating_point(unit, temperature)
    f = real_field("zero_rate_output", "specific_force", specific_force)
    u = _static_channels(op, np.zeros(1), np.zeros(1), f)[0]
    return _output_map(unit, op, np.array([u.real]))[0] + unit.turn_on_bias - unit.bias_trim


def rate_authority(unit: MemsResonator, temperature: float | None = None) -> float:
    """Largest rate the rebalance holds, Omega_max [rad/s] (positive side, noise-free).

    Solves |u_I(Omega)| = sqrt(v_max^2 - u_Q^2) with u_Q the equilibrium quadrature command;
    for theta = 0 this is sqrt(F_max^2 - F_q^2) / (2 m w X0) - Omega_b (docs/physics.md 5.1).
    Returns 0 if the quadrature alone uses up the authority. Open loop: the rate where the
    sense envelope |R F_ext| reaches the pick-off full scale Y_fs (the quadrature shares it).

    Parameters
    ----------
    unit : MemsResonator
        The unit.
    temperature : float or None
        Die temperature [K]; None: the unit's T0.

    Returns
    -------
    float
        Omega_max [rad/s], >= 0.
    """
    op = operating_point(unit, temperature)
    # u is affine in Omega: u = u0 + u1 Omega; the clamp: |u_Q| <= v, |u_I| <= sqrt(v^2 - u_Q^2)
    if op.open_loop:
        u0 = complex(op.receptance * _f_ext(op, np.zeros(1), np.zeros(1))[0])
        u1 = complex(op.receptance * _f_ext(op, np.ones(1), np.zeros(1))[0]) - u0
        lim = op.y_fs
    else:
        u0 = _equilibrium_command(op, np.zeros(1), np.zeros(1))[0]
        u1 = _equilibrium_command(op, np.ones(1), np.zeros(1))[0] - u0
        lim = op.v_max
    # |u0 + u1 W| = v (a quadratic in W; with Q-priority the rate channel saturates when
    # u_I^2 + u_Q^2 = v^2 as long as |u_Q| < v)
    a = abs(u1) ** 2
    b = 2.0 * (u0.real * u1.real + u0.imag * u1.imag)
    c = abs(u0) ** 2 - lim**2
    disc = b * b - 4 * a * c
    if c >= 0 or disc < 0:
        return 0.0
    return float((-b + math.sqrt(disc)) / (2 * a))


def saturated_output(unit: MemsResonator, rate: float, temperature: float | None = None) -> float:
    """Noise-free output [rad/s] for a constant rate beyond the authority (rebalance saturated).

    With u_I clamped at sign(Omega) sqrt(v_max^2 - u_Q^2), the sense mass moves,
    B = R (F_ext + j G e^{j theta} u), and the quadrature integrator settles where its input
    vanishes, Im{kappa_c B} = 0; solved for u_Q (scipy brentq). The plateau therefore drifts
    slightly with the rate (the uncancelled force rotates B).

    Parameters
    ----------
    unit : MemsResonator
        The unit.
    rate : float
        Constant input rate [rad/s], beyond :func:`rate_authority`.
    temperature : float or None
        Die temperature [K]; None: the unit's T0.

    Returns
    -------
    float
        The saturated output [rad/s].
    """
    from scipy.optimize import brentq

    op = operating_point(unit, temperature)
    if abs(rate) <= rate_authority(unit, temperature):
        raise ValueError(f"rate must exceed the rate authority; got {rate!r} rad/s")
    if op.open_loop:  # the front end limits |B| to Y_fs, phase kept
        ch = _static_channels(op, np.array([float(rate)]), np.zeros(1))[0]
        return (float(_output_map(unit, op, np.array([ch.real]))[0]) + unit.turn_on_bias
                - unit.bias_trim)
    sgn = math.copysign(1.0, rate)
    f_ext = complex(-1j * op.coriolis_gain * rate - 1j * op.wx * op.cyx * op.x0 - op.kyx * op.x0)
    gz = 1j * op.gain * complex(np.exp(1j * op.theta))
    v = op.v_max

    def resid(uq: float) -> float:
        ui = sgn * math.sqrt(max(v * v - uq * uq, 0.0))
        return (op.kappa_c * op.receptance * (f_ext + gz * (ui + 1j * uq))).imag

    lo, hi = -v * (1 - 1e-12), v * (1 - 1e-12)
    r_lo, r_hi = resid(lo), resid(hi)
    if r_lo * r_hi > 0:  # the quadrature channel itself is at the DAC limit
        uq = lo if abs(r_lo) < abs(r_hi) else hi
    else:
        uq = brentq(resid, lo, hi, xtol=1e-15 * v)
    ui = sgn * math.sqrt(max(v * v - uq * uq, 0.0))
    return float(_output_map(unit, op, np.array([ui]))[0]) + unit.turn_on_bias - unit.bias_trim


def _output_map(unit: MemsResonator, op: OperatingPoint, u_i: NDArray) -> NDArray:
    """Omega_hat from the rate-channel command (before turn-on bias, trim, flicker, ADC)."""
    w = op.k_out * u_i * (1.0 + unit.turn_on_scale_factor)
    return w + unit.output_cubic * w**3 / unit.output_range**2


def _adc(unit: MemsResonator, w: NDArray) -> NDArray:
    out = np.clip(w, -unit.output_range, unit.output_range)
    q = unit.resolution
    return q * np.round(out / q) if q > 0 else out


def _clamp(u_i: NDArray, u_q: NDArray, v_max: float) -> tuple[NDArray, NDArray, NDArray]:
    """Rebalance DAC limit with quadrature priority; returns (u_I, u_Q, clamped mask)."""
    u_q = np.clip(u_q, -v_max, v_max)
    lim = np.sqrt(np.maximum(v_max * v_max - u_q * u_q, 0.0))
    hit = np.abs(u_i) > lim
    return np.clip(u_i, -lim, lim), u_q, hit
