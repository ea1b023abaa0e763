"""A gyro part from its datasheet figures, and the documented solve onto the simulator's models.

A :class:`Datasheet` holds a part's public figures in the units datasheets use; a
:class:`Part` maps them onto the IEEE Std 952 :class:`gyrobench.sim.noise.NoiseModel` and a
deterministic error layer, draws units (:meth:`Part.realize`) and simulates records through
the :class:`gyrobench.sim.sensor.Environment` interface.

The solve (one figure sets one parameter; SI inside)
----------------------------------------------------
* ARW N [rad/sqrt(s)]: an ARW figure [deg/sqrt(h)] converts directly; a rate noise density
  ND [deg/s/sqrt(Hz)] gives N = ND for a two-sided density and N = ND/sqrt(2) for a
  one-sided one (white rate noise of two-sided PSD S has AVAR S/tau = N^2/tau; the one-sided
  PSD is 2 S). IEEE Std 952-1997 Annex C.
* Bias instability B (IEEE coefficient) [rad/s]: datasheets quote the minimum of the Allan
  deviation ("in-run bias stability"), which for flicker rate noise is
  sqrt(2 ln2/pi) B = 0.664 B, so B = figure / 0.664 (IEEE Std 952 Table C.2); a sheet that
  quotes B itself (``bias_instability_is_b``) is taken as is.
* Turn-on bias b0 ~ N(0, bias repeatability) per unit; bias temperature coefficient c_T:
  b_T(t) = c_T (T(t) - T_ref).
* Scale-factor error e_K ~ N(0, scale-factor repeatability) per unit, plus its temperature
  coefficient: error e_K(t) omega(t), e_K(t) = e_K + k_T (T(t) - T_ref).
* g-sensitivity g_s [rad/s per m/s^2]: error g_s f(t), f the specific force along the axis.
* Range: the output saturates at +-range (error: clipped - unclipped); no range given, no clipping.
* Resolution q [rad/s]: the output is rounded to multiples of q (error: rounded - unrounded).
* Bandwidth f_c [Hz] and output rate fs: the part's output filter, a causal Butterworth low-pass
  of order ``filter_order`` (2 unless the sheet says; an ASSUMPTION: no sheet read states it,
  noise bandwidth 1.11 f_c) at the internal rate k fs, k = ceil(8 f_c / fs) (at most 8: the
  filter is simulated where f_c < fs; at or above the output rate it only shapes the noise within
  each output interval, and is left out, said so in the metadata), its state settled on the first
  sample; each output sample is the mean of the filtered signal over
  its interval (a decimating sensor's output). Every term goes through the same filter (it is
  linear, so the terms still sum) and the filter's effect on the true rate is the term
  ``bandwidth`` (filtered - true). White rate noise of one-sided density ND then has rms
  ND sqrt(1.11 f_c) at the output (the sheets' "rms noise in the bandwidth"). No bandwidth on
  the sheet: no filter, white noise to fs/2, as before any filter.

Units, one convention per kind of field: rate biases in deg/h (bias instability, repeatability,
offset, Gauss-Markov sigma, sine amplitude), their sensitivities in deg/h/K and deg/h/g; rate
full scales in deg/s (range, resolution, rms noise) and the noise density in deg/s/sqrt(Hz); ARW
deg/sqrt(h), K deg/h/sqrt(h), R deg/h^2, Q arcsec; relative errors ppm and ppm/K; Hz and s.

Output: y = H[omega + b0 + b_T + e_K omega + g_s f + n_IEEE], then clipped and rounded; every
term is a truth channel and their sum is y - omega up to float64 rounding. The technology's
physics model (:mod:`gyrobench.sim.sensor`) is not used by this layer: the datasheet figures
fix the error budget directly, not the physical parameters behind it; the physics path is
:func:`gyrobench.sim.parts.simulate_part` (``model="physics"``, :mod:`gyrobench.sim.parts._device`).

Accelerometers
--------------
An IMU's sheet also prints its accelerometers: the ``accel_*`` fields, in the sheet's units
(g, ug, mg, m/s/sqrt(h), ug/sqrt(Hz), ppm, Hz). :meth:`Part.accelerometer` maps them onto the
datasheet-level :class:`gyrobench.sim.imu.AccelerometerSpec` in SI by the same rules as the
gyro: VRW [m/s/sqrt(s)] = figure / 60, or from the noise density (two- or one-sided, as
``noise_density_sided``); B = ADEV minimum / 0.664 unless ``bias_instability_is_b``; the
turn-on bias and scale-factor error drawn from their 1 sigma figures; range, bandwidth and
resolution as the output's limit, low-pass and LSB. A figure the sheet does not give leaves its
term out. The accelerometers are not part of :meth:`PartUnit.simulate` (one gyro axis); a
triad (:class:`gyrobench.sim.imu.TriadSpec`) carries them.

Mapping onto the physics models
-------------------------------
The part's own record keeps N and B as IEEE 952 terms whose values are the sheet's, which is
what a user comparing the part with its datasheet needs. The same sheet also maps onto its
technology's physics model by a documented solve (:mod:`gyrobench.sim.parts._physics`,
:data:`PHYSICS_MAPPING`): every physical parameter at the model's default design (an
assumption: no sheet read publishes them) and ONE parameter solved for the sheet's ARW (a
second one first where the sheet is below the default design's floor), the bias instability
the model's 1/f term at the sheet's B:

* FOG: N = sqrt(S_phi/2) / SF0 (:meth:`gyrobench.sim.fog_loop.LoopSpec.arw`) solved for the
  source power, and the coil's L D below the default coil's reach
  (:func:`gyrobench.sim.parts.fog_spec`, ``fog_spec(sheet).realize(rng=rng)``).
* MEMS: N^2 = N_B^2 + N_e^2 (:func:`gyrobench.sim.mems_resonator.electronic_arw`) solved for
  the pick-off noise, and the proof mass below the default Brownian floor
  (:func:`gyrobench.sim.parts.mems_spec`, ``mems_spec(sheet).realize(rng=rng)``).
* RLG: N = Omega_L / sqrt(2 pi K Omega_D) (:func:`gyrobench.sim.rlg.dither_arw`) solved for the
  lock-in rate (:func:`gyrobench.sim.parts.rlg_spec`, ``rlg_spec(sheet).realize(rng=rng)``).

Records of those physics devices meet the sheet's N and B (tests); a user who knows the
physical parameters builds the physics device through :mod:`gyrobench.sim.sensor` instead.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, fields
from typing import ClassVar

import numpy as np
from numpy.typing import NDArray
from scipy.signal import butter, sosfilt, sosfilt_zi

from gyrobench.base import units
from gyrobench.base.ranges import Constraint, FieldChoice, FieldRange, validate
from gyrobench.base.validate import check_fs, check_rng
from gyrobench.io.recording import Channel, Recording
from gyrobench.sim.imu import AccelerometerSpec
from gyrobench.sim.noise import GaussMarkov, NoiseModel, Sinusoid
from gyrobench.sim.sensor import Environment

__all__ = [
    "Datasheet",
    "Part",
    "PartUnit",
    "ERROR_COMPONENTS",
    "TECHNOLOGIES",
    "GRADES",
    "ADEV_MIN_PER_B",
    "PHYSICS_MAPPING",
]

ADEV_MIN_PER_B = math.sqrt(2.0 * math.log(2.0) / math.pi)
"""Allan deviation minimum of flicker rate noise per IEEE coefficient B: sqrt(2 ln2/pi) = 0.664."""

TECHNOLOGIES = ("MEMS", "FOG", "RLG")
GRADES = ("consumer", "industrial", "tactical", "navigation")

ERROR_COMPONENTS = (
    "turn_on_bias",
    "bias_temperature",
    "scale_factor_error",
    "g_sensitivity",
    "ieee_noise",
    "bandwidth",
    "saturation",
    "quantization",
)
"""Truth channels of a part's record, in order; their sum is ``output - true_rate``."""

PHYSICS_MAPPING = {
    "FOG": ("gyrobench.sim.fog_loop.LoopSpec.arw", "N = sqrt(S_phi/2)/SF0: solved for the source power with the "
            "default coil, source width, losses and detector (fog_spec; those are not on the sheets read); below "
            "the default coil's reach the power is capped at 15 mW and the coil's L D solved (L <= 5 km, "
            "D <= 0.2 m), B the loop's additive 1/f term"),
    "MEMS": ("gyrobench.sim.mems_resonator.electronic_arw", "N^2 = N_B^2 + N_e^2: solved for the pick-off noise "
             "with the default resonator's mass, drive, Q and split (mems_spec; those are not on the sheets read); "
             "below the default Brownian floor the proof mass is solved for N_B = N/sqrt 2 (m <= 5 mg), B the "
             "model's 1/f term"),
    "RLG": ("gyrobench.sim.rlg.dither_arw", "N = Omega_L/sqrt(2 pi K Omega_D): solved for the lock-in rate with the "
            "model's default cavity and dither (rlg_spec; K and Omega_D are not on the sheets read), B the model's "
            "flicker term"),
}
"""Per technology: the physics model's ARW closed form (a dotted name) and the parameters solved for the
sheet's ARW, the others at the default design (:mod:`gyrobench.sim.parts._physics`)."""

_T_REF = 298.15  # K, 25 degC: the reference temperature of datasheet figures

_INF = math.inf
#: the noise terms a fitted part may carry without a white-noise term
_FIT_NOISE = ("bias_instability_dph", "rate_random_walk", "rate_ramp", "quantization", "gauss_markov_sigma",
              "sine_amplitude")
#: the text fields a datasheet cannot leave empty
_TEXT = ("name", "manufacturer", "model", "source")


#: the output filter runs at least this many times its -3 dB bandwidth (the white noise it passes
#: beyond that is 0.5 % of its power for the second-order default)
FILTER_OVERSAMPLING = 8.0


def filtered(datasheet: Datasheet, fs: float) -> bool:
    """Whether the output filter is simulated at output rate ``fs`` [Hz]: the sheet gives a bandwidth below fs.

    A bandwidth at or above the output rate only shapes the noise inside each output interval,
    which the interval mean averages out (the filter's memory 1/(2 pi f_c) is below 1/(2 pi fs)):
    such a record is simulated without the filter, and its metadata says so.
    """
    return datasheet.bandwidth is not None and datasheet.bandwidth < fs


def oversampling(datasheet: Datasheet, fs: float) -> int:
    """Internal samples per output sample: ceil(8 bandwidth / fs) (at most 8) where the filter is simulated, else 1.

    Parameters
    ----------
    datasheet : Datasheet
        The part's sheet (its ``bandwidth``).
    fs : float
        Output rate [Hz].

    Returns
    -------
    int
        k >= 1; the internal rate is k fs.
    """
    if not filtered(datasheet, fs):
        return 1
    return int(max(1, math.ceil(FILTER_OVERSAMPLING * float(datasheet.bandwidth) / fs)))  # type: ignore[arg-type]


def output_filter(datasheet: Datasheet, fi: float) -> NDArray[np.float64]:
    """The output low-pass as second-order sections at the internal rate ``fi`` [Hz].

    A Butterworth of order ``filter_order`` with its -3 dB point at ``bandwidth`` (scipy.signal.butter);
    a bandwidth at or above 0.45 fi is capped there (the internal rate is then the limit).
    """
    wn = min(float(datasheet.bandwidth), 0.45 * fi) / (fi / 2.0)  # type: ignore[arg-type]
    return np.asarray(butter(datasheet.filter_order, wn, output="sos"))


def settled_filter(sos: NDArray[np.float64], x: NDArray[np.float64]) -> NDArray[np.float64]:
    """``x`` through the causal filter ``sos``, its state settled on x[0] (a part switched on before the record)."""
    y, _ = sosfilt(sos, x, zi=sosfilt_zi(sos) * x[0])
    return np.asarray(y)


def filter_metadata(datasheet: Datasheet, fs: float) -> dict[str, object]:
    """What the record's output filter and sampling were (for the file's metadata)."""
    if datasheet.bandwidth is None:
        return {"applied": False, "why": "no bandwidth on the sheet: the noise is white to fs/2"}
    if not filtered(datasheet, fs):
        return {"applied": False, "why": f"the sheet's bandwidth {datasheet.bandwidth:g} Hz is not below the output "
                                         f"rate {fs:g} Hz: each output sample is the interval mean, no filter"}
    k = oversampling(datasheet, fs)
    return {"applied": True, "kind": "butterworth", "order": datasheet.filter_order,
            "bandwidth_hz": datasheet.bandwidth, "internal_rate_hz": fs * k, "output_rate_hz": fs,
            "oversampling": k}


def _input_at(environment: Environment, name: str, fs: float, k: int, default: float = 0.0) -> NDArray[np.float64]:
    """Input ``name`` at the internal rate k fs: an array given per output sample is held over its interval."""
    if k == 1:
        return environment.sampled(name, fs, default=default)
    if isinstance(getattr(environment, name), np.ndarray):
        return np.repeat(environment.sampled(name, fs, default=default), k)
    n = environment.n_samples(fs)
    return environment.sampled(name, fs * k, default=default)[: n * k]


@dataclass(frozen=True, slots=True, kw_only=True)
class Datasheet:
    """A gyro's public datasheet figures, in datasheet units (1 sigma unless the source says otherwise).

    Parameters
    ----------
    name : str
        Part key (lower case, e.g. ``"stim300"``).
    manufacturer, model : str
    technology : str
        "MEMS", "FOG" or "RLG".
    grade : str
        "consumer", "industrial", "tactical" or "navigation".
    source : str
        The datasheet (title, document number, revision) the figures come from, and where
        they were read if not from the document itself.
    bias_instability_dph : float, optional
        In-run bias stability: the Allan-deviation minimum [deg/h], > 0 when given. None: the
        sheet prints none (high-range parts often do not); no 1/f term is drawn, B = 0.
    bias_instability_is_b : bool
        True when the sheet quotes the IEEE coefficient B itself (ADEV minimum / 0.664, as
        Murata does) rather than the ADEV minimum. Default False.
    range_dps : float, optional
        Input range [deg/s] (the output saturates at +-range); None: not given, no saturation.
    arw : float, optional
        Angle random walk [deg/sqrt(h)].
    noise_density : float, optional
        Rate noise density [deg/s/sqrt(Hz)] (used when ``arw`` is not given).
    noise_density_sided : str
        "one" or "two": the PSD convention of ``noise_density`` (module docstring).
    bias_repeatability : float, optional
        Turn-on bias 1 sigma [deg/h].
    bias_tempco : float, optional
        Bias temperature coefficient [deg/h/K].
    scale_factor_repeatability : float, optional
        Scale-factor error 1 sigma [ppm].
    scale_factor_tempco : float, optional
        Scale-factor temperature coefficient [ppm/K].
    g_sensitivity : float, optional
        Linear-acceleration effect on the bias [deg/h/g].
    bandwidth : float, optional
        -3 dB bandwidth of the part's output filter [Hz]: simulated as a causal Butterworth
        low-pass of order ``filter_order`` on the oversampled signal, the output taken from it
        at the output rate (module docstring); None: no filter, the noise white to fs/2.
    output_rate : float, optional
        Output data rate [Hz] the sheet pairs with ``bandwidth`` (the default ``fs`` of
        ``simulate device``).
    resolution : float, optional
        Output resolution (LSB) [deg/s].
    rms_noise : float, optional
        Output noise rms [deg/s] the sheet prints for its ``bandwidth`` (a check of the PSD
        convention: with a one-sided density ND, rms = ND sqrt(ENBW)); recorded, not used.
    filter_order : int
        Order of the output Butterworth low-pass (default 2: an ASSUMPTION, no sheet read
        states its filter's order; its noise bandwidth is 1.11 x the -3 dB bandwidth).
    rate_random_walk : float, optional
        K [deg/h/sqrt(h)] (IEEE 952).
    rate_ramp : float, optional
        R [deg/h^2] (IEEE 952).
    quantization : float, optional
        Angle quantization Q [arcsec] (IEEE 952).
    gauss_markov_sigma, gauss_markov_tau : float, optional
        A first-order Gauss-Markov bias term: its stationary 1 sigma [deg/h] and correlation
        time [s]; both or neither.
    sine_amplitude, sine_frequency : float, optional
        A sinusoidal rate error: amplitude [deg/h] and frequency [Hz]; both or neither.
    bias_offset : float, optional
        A constant bias every unit has [deg/h] (a fitted record's mean); the turn-on bias is
        drawn around it.
    source_kind : str
        "primary" (the figures were read from the maker's own document), "secondary" (from a
        page quoting it, named in ``source``), "fit" (fitted to a record by ``gyrobench twin``)
        or "user" (default: the user's own figures).
    default_model : str
        The model ``simulate device`` runs the part on unless ``--model`` says otherwise:
        "physics" (default) or "budget" (a fitted part: its Q, K, R, Gauss-Markov, sine and
        filter terms are budget terms, which the physics models do not carry).
    accel_range_g : float, optional
        Accelerometer full scale, +-range [g] (the output saturates there); None: no saturation.
    accel_bias_instability_ug : float, optional
        Accelerometer in-run bias stability, the Allan-deviation minimum [ug] (the IEEE B itself
        when ``bias_instability_is_b``: one sheet, one convention for both sensors).
    accel_vrw_m_s_sqrt_h : float, optional
        Accelerometer velocity random walk [m/s/sqrt(h)].
    accel_noise_density_ug : float, optional
        Accelerometer noise density [ug/sqrt(Hz)], of the sidedness ``noise_density_sided`` (used
        when ``accel_vrw_m_s_sqrt_h`` is not given).
    accel_bias_repeatability_mg : float, optional
        Accelerometer turn-on bias 1 sigma [mg].
    accel_bias_tempco_mg_per_k : float, optional
        Accelerometer bias temperature coefficient [mg/K].
    accel_scale_factor_repeatability_ppm : float, optional
        Accelerometer scale-factor error 1 sigma [ppm].
    accel_scale_factor_tempco_ppm_per_k : float, optional
        Accelerometer scale-factor temperature coefficient [ppm/K].
    accel_bandwidth_hz : float, optional
        Accelerometer -3 dB bandwidth [Hz]: the output's first-order low-pass
        (:class:`gyrobench.sim.imu.AccelerometerSpec`).
    accel_resolution_mg : float, optional
        Accelerometer output resolution (LSB) [mg].
    notes : str
        What was assumed where the source was silent.

    Notes
    -----
    The ``accel_*`` figures are the part's accelerometers (an IMU's sheet): None where the sheet
    gives none. A part with at least one of them builds its accelerometer triad with
    :meth:`Part.accelerometer`; a gyro-only part has none.
    """

    name: str
    manufacturer: str
    model: str
    technology: str
    grade: str
    source: str
    bias_instability_dph: float | None = None
    bias_instability_is_b: bool = False
    range_dps: float | None = None
    arw: float | None = None
    noise_density: float | None = None
    noise_density_sided: str = "two"
    bias_repeatability: float | None = None
    bias_tempco: float | None = None
    scale_factor_repeatability: float | None = None
    scale_factor_tempco: float | None = None
    g_sensitivity: float | None = None
    bandwidth: float | None = None
    output_rate: float | None = None
    resolution: float | None = None
    rms_noise: float | None = None
    filter_order: int = 2
    rate_random_walk: float | None = None
    rate_ramp: float | None = None
    quantization: float | None = None
    gauss_markov_sigma: float | None = None
    gauss_markov_tau: float | None = None
    sine_amplitude: float | None = None
    sine_frequency: float | None = None
    bias_offset: float | None = None
    source_kind: str = "user"
    default_model: str = "physics"
    accel_range_g: float | None = None
    accel_bias_instability_ug: float | None = None
    accel_vrw_m_s_sqrt_h: float | None = None
    accel_noise_density_ug: float | None = None
    accel_bias_repeatability_mg: float | None = None
    accel_bias_tempco_mg_per_k: float | None = None
    accel_scale_factor_repeatability_ppm: float | None = None
    accel_scale_factor_tempco_ppm_per_k: float | None = None
    accel_bandwidth_hz: float | None = None
    accel_resolution_mg: float | None = None
    notes: str = ""

    RANGES: ClassVar[Mapping[str, FieldRange | FieldChoice]] = {
        "technology": FieldChoice(TECHNOLOGIES, "the gyro's technology"),
        "grade": FieldChoice(GRADES, "the gyro's grade"),
        "bias_instability_dph": FieldRange(0, 3.6e5, "deg/h", "in-run bias stability (ADEV minimum); <= 100 deg/s",
                                           low_open=True),
        "range_dps": FieldRange(0, 1e5, "deg/s", "input range; the widest MEMS parts reach 4000 deg/s", low_open=True),
        "arw": FieldRange(0, 600, "deg/sqrt(h)", "angle random walk; <= 10 deg/sqrt(s)", low_open=True),
        "noise_density": FieldRange(0, 10, "deg/s/sqrt(Hz)", "rate noise density", low_open=True),
        "noise_density_sided": FieldChoice(("one", "two"), "the PSD convention of noise_density"),
        "bias_repeatability": FieldRange(0, 3.6e6, "deg/h", "turn-on bias 1 sigma; <= 1000 deg/s"),
        "bias_tempco": FieldRange(0, 3.6e4, "deg/h/K", "bias temperature coefficient; <= 10 deg/s/K"),
        "scale_factor_repeatability": FieldRange(0, 1e5, "ppm", "scale-factor error 1 sigma; <= 10 %"),
        "scale_factor_tempco": FieldRange(0, 1e4, "ppm/K", "scale-factor temperature coefficient; <= 1 %/K"),
        "g_sensitivity": FieldRange(0, 3.6e5, "deg/h/g", "linear-acceleration effect on the bias; <= 100 deg/s/g"),
        "bandwidth": FieldRange(0, 1e5, "Hz", "-3 dB bandwidth of the output filter", low_open=True),
        "output_rate": FieldRange(0, 1e6, "Hz", "output data rate", low_open=True),
        "resolution": FieldRange(0, 100, "deg/s", "output resolution (LSB); below the range (a constraint)",
                                 low_open=True),
        "rms_noise": FieldRange(0, 1e3, "deg/s", "output noise rms in the sheet's bandwidth", low_open=True),
        "filter_order": FieldRange(1, 8, "1", "Butterworth order of the output filter", integer=True),
        "rate_random_walk": FieldRange(0, 3.6e5, "deg/h/sqrt(h)", "rate random walk K"),
        "rate_ramp": FieldRange(-3.6e6, 3.6e6, "deg/h^2", "rate ramp R"),
        "default_model": FieldChoice(("physics", "budget"), "the model simulate device runs by default"),
        "quantization": FieldRange(0, 3.6e5, "arcsec", "angle quantization Q"),
        "gauss_markov_sigma": FieldRange(0, 3.6e6, "deg/h", "Gauss-Markov bias 1 sigma", low_open=True),
        "gauss_markov_tau": FieldRange(0, 1e9, "s", "Gauss-Markov correlation time", low_open=True),
        "sine_amplitude": FieldRange(0, 3.6e6, "deg/h", "sinusoidal rate error amplitude", low_open=True),
        "sine_frequency": FieldRange(0, 1e6, "Hz", "sinusoidal rate error frequency", low_open=True),
        "bias_offset": FieldRange(-3.6e6, 3.6e6, "deg/h", "constant bias of every unit; |b| <= 1000 deg/s"),
        "source_kind": FieldChoice(("primary", "secondary", "fit", "user"), "where the figures come from"),
        "accel_range_g": FieldRange(0, _INF, "g", "accelerometer full scale", low_open=True),
        "accel_bias_instability_ug": FieldRange(0, _INF, "ug", "accelerometer in-run bias stability (ADEV minimum)",
                                                low_open=True),
        "accel_vrw_m_s_sqrt_h": FieldRange(0, _INF, "m/s/sqrt(h)", "accelerometer velocity random walk"),
        "accel_noise_density_ug": FieldRange(0, _INF, "ug/sqrt(Hz)", "accelerometer noise density"),
        "accel_bias_repeatability_mg": FieldRange(0, _INF, "mg", "accelerometer turn-on bias 1 sigma"),
        "accel_bias_tempco_mg_per_k": FieldRange(0, _INF, "mg/K", "accelerometer bias temperature coefficient"),
        "accel_scale_factor_repeatability_ppm": FieldRange(0, _INF, "ppm", "accelerometer scale-factor error 1 sigma"),
        "accel_scale_factor_tempco_ppm_per_k": FieldRange(0, _INF, "ppm/K",
                                                          "accelerometer scale-factor temperature coefficient"),
        "accel_bandwidth_hz": FieldRange(0, _INF, "Hz", "accelerometer -3 dB bandwidth", low_open=True),
        "accel_resolution_mg": FieldRange(0, _INF, "mg", "accelerometer output resolution (LSB)", low_open=True),
    }
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "name, manufacturer, model and source are non-empty text",
            lambda c: all(isinstance(getattr(c, k), str) and getattr(c, k).strip() for k in _TEXT),
            lambda c: next(
                f"{k} must be a non-empty string; got {getattr(c, k)!r}"
                for k in _TEXT
                if not (isinstance(getattr(c, k), str) and getattr(c, k).strip())
            ),
        ),
        Constraint(
            "arw or noise_density given (or, for a fitted part, another noise term)",
            lambda c: c.arw is not None or c.noise_density is not None or (
                c.source_kind == "fit" and any(getattr(c, k) for k in _FIT_NOISE)),
            lambda c: f"arw [deg/sqrt(h)] or noise_density [deg/s/sqrt(Hz)] must be given (part {c.name!r}); "
            "got neither",
        ),
        Constraint(
            "resolution < range_dps",
            lambda c: c.resolution is None or c.range_dps is None or c.resolution < c.range_dps,
            lambda c: f"resolution must be below range_dps [deg/s]; got resolution {c.resolution!r}, range_dps "
            f"{c.range_dps!r}",
        ),
        Constraint(
            "gauss_markov_sigma and gauss_markov_tau both or neither",
            lambda c: (c.gauss_markov_sigma is None) == (c.gauss_markov_tau is None),
            lambda c: "gauss_markov_sigma [deg/h] and gauss_markov_tau [s] must be given together; got "
            f"{c.gauss_markov_sigma!r} and {c.gauss_markov_tau!r}",
        ),
        Constraint(
            "sine_amplitude and sine_frequency both or neither",
            lambda c: (c.sine_amplitude is None) == (c.sine_frequency is None),
            lambda c: f"sine_amplitude [deg/h] and sine_frequency [Hz] must be given together; got "
            f"{c.sine_amplitude!r} and {c.sine_frequency!r}",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above

    # ------------------------------------------------------------------ the solve
    def angle_random_walk(self) -> float:
        """N [rad/sqrt(s)] (module docstring: from ARW, or from the noise density and its sidedness)."""
        if self.arw is not None:
            return units.deg_per_sqrt_h(self.arw)
        if self.noise_density is None:  # a fitted part without white noise
            return 0.0
        nd = math.radians(float(self.noise_density))
        return nd if self.noise_density_sided == "two" else nd / math.sqrt(2.0)

    def bias_instability(self) -> float:
        """IEEE coefficient B [rad/s] = ADEV minimum / 0.664 (or the figure itself, ``bias_instability_is_b``).

        0 when the sheet gives no bias instability (no 1/f term is drawn).
        """
        if self.bias_instability_dph is None:
            return 0.0
        b = units.deg_per_h(self.bias_instability_dph)
        return b if self.bias_instability_is_b else b / ADEV_MIN_PER_B

    def noise_model(self) -> NoiseModel:
        """The IEEE 952 model: N and B from the figures (module docstring), Q, K, the Gauss-Markov and
        sine terms where given (SI: Q [rad], K [rad/s/sqrt(s)], R [rad/s^2], sigma [rad/s], amplitude [rad/s])."""
        gm: tuple[GaussMarkov, ...] = ()
        if self.gauss_markov_sigma is not None and self.gauss_markov_tau is not None:
            gm = (GaussMarkov(sigma=units.deg_per_h(self.gauss_markov_sigma), correlation_time=self.gauss_markov_tau),)
        sines: tuple[Sinusoid, ...] = ()
        if self.sine_amplitude is not None and self.sine_frequency is not None:
            sines = (Sinusoid(amplitude=units.deg_per_h(self.sine_amplitude), frequency=self.sine_frequency),)
        return NoiseModel(
            quantization=units.arcsec(self.quantization or 0.0),
            angle_random_walk=self.angle_random_walk(),
            bias_instability=self.bias_instability(),
            rate_random_walk=units.deg_per_h_per_sqrt_h(self.rate_random_walk or 0.0),
            rate_ramp=units.deg_per_h2(self.rate_ramp or 0.0),
            gauss_markov=gm,
            sinusoids=sines,
        )

    @property
    def has_accelerometer(self) -> bool:
        """Whether the sheet gives any accelerometer figure (an ``accel_*`` field)."""
        return any(getattr(self, f.name) is not None for f in fields(self) if f.name.startswith("accel_"))

    def accel_velocity_random_walk(self) -> float:
        """VRW [m/s/sqrt(s)]: the VRW figure / 60, or the noise density [ug/sqrt(Hz)] x 1e-6 g0 for a
        two-sided density and / sqrt(2) more for a one-sided one (as :meth:`angle_random_walk`);
        0 when the sheet gives neither (no white acceleration noise is drawn)."""
        if self.accel_vrw_m_s_sqrt_h is not None:
            return self.accel_vrw_m_s_sqrt_h / 60.0
        if self.accel_noise_density_ug is None:
            return 0.0
        nd = self.accel_noise_density_ug * 1e-6 * units.G0
        return nd if self.noise_density_sided == "two" else nd / math.sqrt(2.0)

    def accel_bias_instability(self) -> float:
        """Accelerometer IEEE coefficient B [m/s^2] = ADEV minimum / 0.664 (or the figure itself,
        ``bias_instability_is_b``); 0 when the sheet gives none (no 1/f term is drawn)."""
        if self.accel_bias_instability_ug is None:
            return 0.0
        b = self.accel_bias_instability_ug * 1e-6 * units.G0
        return b if self.bias_instability_is_b else b / ADEV_MIN_PER_B

    def figures(self) -> dict[str, object]:
        """The datasheet fields as a flat dict (for listing and metadata)."""
        return {f.name: getattr(self, f.name) for f in fields(self)}


@dataclass(frozen=True, slots=True)
class Part:
    """A part's population: draws units whose errors follow its datasheet (module docstring).

    Parameters
    ----------
    datasheet : Datasheet
        The datasheet figures the units follow.
    reference_temperature : float
        Temperature at which the sheet's figures hold [K] (default 25 degC).
    """

    datasheet: Datasheet
    reference_temperature: float = _T_REF

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "reference_temperature": FieldRange(0, _INF, "K", "temperature of the datasheet figures", low_open=True),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared spec above; the datasheet field must be a Datasheet

    @property
    def name(self) -> str:
        return self.datasheet.name

    def accelerometer(self) -> AccelerometerSpec | None:
        """The part's accelerometer design from its ``accel_*`` figures, in SI; None for a gyro-only sheet.

        One figure sets one field of :class:`gyrobench.sim.imu.AccelerometerSpec` (g0 = 9.80665 m/s^2):
        VRW and B as :meth:`Datasheet.accel_velocity_random_walk` and
        :meth:`Datasheet.accel_bias_instability`; bias repeatability [mg] x 1e-3 g0; scale factor
        [ppm] x 1e-6; tempcos [mg/K] x 1e-3 g0 and [ppm/K] x 1e-6; range [g] x g0; resolution [mg]
        x 1e-3 g0; the bandwidth as is. A figure the sheet does not give leaves its term out (0, or
        no limit for the range and bandwidth); the tempcos hold from this part's reference
        temperature. No acceleration random walk: no sheet read prints one.

        Returns
        -------
        AccelerometerSpec or None
        """
        ds = self.datasheet
        if not ds.has_accelerometer:
            return None
        g = units.G0

        def si(v: float | None, k: float, default: float = 0.0) -> float:
            return default if v is None else v * k

        return AccelerometerSpec(
            bias_repeatability=si(ds.accel_bias_repeatability_mg, 1e-3 * g),
            scale_factor_repeatability=si(ds.accel_scale_factor_repeatability_ppm, 1e-6),
            velocity_random_walk=ds.accel_velocity_random_walk(),
            bias_instability=ds.accel_bias_instability(),
            bias_tempco=si(ds.accel_bias_tempco_mg_per_k, 1e-3 * g),
            scale_factor_tempco=si(ds.accel_scale_factor_tempco_ppm_per_k, 1e-6),
            range=si(ds.accel_range_g, g, _INF),
            bandwidth=si(ds.accel_bandwidth_hz, 1.0, _INF),
            resolution=si(ds.accel_resolution_mg, 1e-3 * g),
            reference_temperature=self.reference_temperature,
        )

    def realize(self, *, rng: np.random.Generator) -> PartUnit:
        """Draw one unit: turn-on bias and scale-factor error from their repeatabilities.

        Parameters
        ----------
        rng : numpy.random.Generator
            The unit's stream (two standard normals).

        Returns
        -------
        PartUnit
            The drawn unit.
        """
        check_rng(rng)
        ds = self.datasheet
        b0 = units.deg_per_h(ds.bias_offset or 0.0) + units.deg_per_h(ds.bias_repeatability or 0.0) * float(
            rng.standard_normal()
        )
        ek = (ds.scale_factor_repeatability or 0.0) * 1e-6 * float(rng.standard_normal())
        return PartUnit(self, turn_on_bias=b0, scale_factor_error=ek)

    def simulate(self, environment: Environment, *, fs: float, rng: np.random.Generator) -> Recording:
        """Draw a unit from ``rng`` and simulate one record with it (:meth:`PartUnit.simulate`)."""
        return self.realize(rng=rng).simulate(environment, fs=fs, rng=rng)


@dataclass(frozen=True, slots=True)
class PartUnit:
    """One drawn unit of a :class:`Part` (a :class:`gyrobench.sim.sensor.SensorUnit`).

    Parameters
    ----------
    part : Part
    turn_on_bias : float
        b0 [rad/s].
    scale_factor_error : float
        e_K [1] at the reference temperature.
    """

    part: Part
    turn_on_bias: float = 0.0
    scale_factor_error: float = 0.0

    def simulate(self, environment: Environment, *, fs: float, rng: np.random.Generator) -> Recording:
        """One record at ``fs`` [Hz]: channel ``output`` [rad/s], truth ``true_rate`` and every error term.

        Inputs are taken at the sample centres (:meth:`Environment.sampled`); temperature
        None is the reference temperature (25 degC).
        """
        check_rng(rng)
        fs = check_fs(fs)
        if not isinstance(environment, Environment):
            raise TypeError(f"environment must be an Environment; got {type(environment).__name__}")
        n = environment.n_samples(fs)
        if n < 2:
            raise ValueError(f"duration * fs must give >= 2 samples; got {environment.duration!r} s at {fs!r} Hz")
        ds = self.part.datasheet
        t_ref = self.part.reference_temperature
        k = oversampling(ds, fs)
        fi = fs * k
        omega = _input_at(environment, "true_rate", fs, k)
        temp = _input_at(environment, "temperature", fs, k, default=t_ref)
        force = _input_at(environment, "specific_force", fs, k)
        d_t = temp - t_ref
        comps: dict[str, NDArray[np.float64]] = {
            "turn_on_bias": np.full(n * k, self.turn_on_bias),
            "bias_temperature": units.deg_per_h(ds.bias_tempco or 0.0) * d_t,
            "scale_factor_error": (self.scale_factor_error + (ds.scale_factor_tempco or 0.0) * 1e-6 * d_t) * omega,
            "g_sensitivity": units.deg_per_h(ds.g_sensitivity or 0.0) / units.G0 * force,
            "ieee_noise": ds.noise_model().generate(n * k, fi, rng=rng),
        }
        if filtered(ds, fs):
            # the part's output filter on the oversampled signal, then its output sampling: every term
            # through the same causal filter (linear, so the terms still sum), the true rate's own
            # filtering the "bandwidth" term; each output sample the mean over its interval
            sos = output_filter(ds, fi)

            def block(x: NDArray[np.float64]) -> NDArray[np.float64]:  # the mean over each output interval
                return np.asarray(x.reshape(n, k).mean(axis=1))

            through = {name: block(settled_filter(sos, v)) for name, v in comps.items()}
            omega_f = block(settled_filter(sos, omega))
            omega, temp, force = block(omega), block(temp), block(force)
            comps = {**through, "bandwidth": omega_f - omega}
        else:
            comps["bandwidth"] = np.zeros(n)
        raw = omega + sum(comps.values())
        if ds.range_dps is not None:
            limit = math.radians(ds.range_dps)
            clipped = np.clip(raw, -limit, limit)
        else:
            clipped = raw.copy()
        comps["saturation"] = clipped - raw
        if ds.resolution:
            q = math.radians(ds.resolution)
            out = np.round(clipped / q) * q
        else:
            out = clipped
        comps["quantization"] = out - clipped
        descr = {
            "turn_on_bias": "turn-on bias b0 (drawn from the bias repeatability)",
            "bias_temperature": "bias temperature coefficient x (T - T_ref)",
            "scale_factor_error": "(e_K + k_T (T - T_ref)) x true rate",
            "g_sensitivity": "g-sensitivity x specific force",
            "ieee_noise": "IEEE 952 noise (N, B from the datasheet)",
            "bandwidth": "the output filter's effect on the true rate (filtered - true)",
            "saturation": "clipping at +-range",
            "quantization": "rounding to the output resolution",
        }
        truth = {"true_rate": Channel(omega, "rad/s", "input rate about the sense axis")}
        truth.update({k: Channel(comps[k], "rad/s", descr[k]) for k in ERROR_COMPONENTS})
        truth["temperature"] = Channel(temp, "K", "unit temperature")
        truth["specific_force"] = Channel(force, "m/s^2", "specific force along the sense axis")
        return Recording(
            fs=fs,
            channels={"output": Channel(out, "rad/s", f"{ds.manufacturer} {ds.model} output")},
            truth=truth,
            t0=0.5 / fs,
            metadata={
                "model": "gyrobench.sim.parts.PartUnit",
                "model_kind": "budget",
                "output_filter": filter_metadata(ds, fs),
                "part": ds.name,
                "datasheet": ds.figures(),
                "unit": {"turn_on_bias_rad_s": self.turn_on_bias, "scale_factor_error": self.scale_factor_error},
                "noise_model": ds.noise_model().to_datasheet(),
                "error_components": list(ERROR_COMPONENTS),
                "ignored_inputs": [],
            },
            name=ds.name.replace("/", "_"),
        )
