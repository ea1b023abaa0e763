"""A three-axis IMU: a gyro triad of any device (part or physics model) and an accelerometer
triad, on one block, driven by a trajectory.

What axis i of the block reports (SI; ``e_i`` its nominal axis, C the drawn sensitivity matrix):

    gyro i:  y_i = device_i(u_i),  u_i = (C_g omega_ib^b)_i + (G_g f^b)_i + G2_i (f^b_i)^2     [rad/s]
    accel i: a_i = q((1 + s_i + k_s,i dT) (C_a f^b)_i + b_i + k_b,i dT + n_i(t))                [m/s^2]

where omega_ib^b and f^b are the interval means of the motion's exact increments
(:func:`gyrobench.sim.trajectory.increments`), C = I + E with E's off-diagonal elements the
misalignment and non-orthogonality of the axes together with their cross-axis sensitivity (the
two act alike on a rigid block: one small-angle matrix, IEEE Std 1431-2004 sec. 6.3 and
IEEE Std 1293-2018 sec. 7; drawn N(0, m^2 + c^2) per element from the stated misalignment m
[rad] and cross-axis c [-], or given), G_g the off-axis g-sensitivity [rad/s per m/s^2] (the
on-axis g-sensitivity is the device's own: a part carries its sheet's figure), G2 the g x g
sensitivity along each axis [rad/s per (m/s^2)^2], device_i the gyro's own model run on u_i
with the block temperature (:meth:`gyrobench.sim.sensor.SensorUnit.simulate`: its noise, bias,
scale factor and its own g-sensitivity to f^b_i), s_i and b_i the accelerometer's turn-on
scale-factor error and bias, k_s and k_b its temperature coefficients, n_i its IEEE-952 noise
(velocity random walk, bias instability, acceleration random walk), q its output low-pass,
quantization and range. The accelerometers are at the datasheet level (no proof-mass model): their figures are
what a sheet prints. Shared physics is shared: one block temperature, one motion (so a
vibration reaches every axis coherently), one drawn block.

Every term is kept: the record's truth holds, per channel, ``<channel>.true`` (the ideal
sensed value along the nominal axis) and each error term, summing to ``output - true``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from typing import ClassVar

import numpy as np
from numpy.typing import NDArray

from gyrobench.base import units
from gyrobench.base.ranges import Constraint, FieldRange, as_array, as_tuple, finite_array, shown, validate
from gyrobench.base.validate import check_fs, check_rng
from gyrobench.io.recording import Channel, Recording, package_version
from gyrobench.sim.earth import Site
from gyrobench.sim.noise import NoiseModel
from gyrobench.sim.sensor import Environment, Sensor, SensorUnit
from gyrobench.sim.trajectory import Increments, Motion, increments

__all__ = ["AXES", "AccelerometerSpec", "TriadSpec", "TriadUnit", "ImuRecord", "sensitivity_matrix"]

AXES = ("x", "y", "z")


@dataclass(frozen=True, slots=True, kw_only=True)
class AccelerometerSpec:
    """One accelerometer design at the datasheet level; every field in SI.

    Parameters
    ----------
    bias_repeatability : float
        Turn-on to turn-on bias, 1 sigma [m/s^2].
    scale_factor_repeatability : float
        Turn-on scale-factor error, 1 sigma [-].
    velocity_random_walk : float
        VRW, white acceleration noise [m/s/sqrt(s)].
    bias_instability : float
        B, flicker floor of the Allan deviation / 0.664 [m/s^2] (IEEE Std 952's definition).
    acceleration_random_walk : float
        Random walk of the bias [m/s^2/sqrt(s)].
    bias_tempco : float
        Bias temperature coefficient [m/s^2/K].
    scale_factor_tempco : float
        Scale-factor temperature coefficient [1/K].
    range : float
        Full scale, +-range [m/s^2]; beyond it the output saturates (inf: none).
    bandwidth : float
        -3 dB corner of the output's first-order low-pass [Hz] (inf: none). Discretised
        step-invariant at the output rate: y_k = a y_{k-1} + (1 - a) x_k, a = exp(-2 pi f_c / fs)
        (exact for an input held over each sample), started at its steady state.
    resolution : float
        Output LSB [m/s^2] (0: not quantized).
    reference_temperature : float
        Temperature at which the tempcos are zero [K].
    """

    bias_repeatability: float = 0.0
    scale_factor_repeatability: float = 0.0
    velocity_random_walk: float = 0.0
    bias_instability: float = 0.0
    acceleration_random_walk: float = 0.0
    bias_tempco: float = 0.0
    scale_factor_tempco: float = 0.0
    range: float = math.inf
    bandwidth: float = math.inf
    resolution: float = 0.0
    reference_temperature: float = units.celsius(25.0)

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "bias_repeatability": FieldRange(0, math.inf, "m/s^2", "turn-on bias, 1 sigma, >= 0"),
        "scale_factor_repeatability": FieldRange(0, math.inf, "1", "turn-on scale-factor error, 1 sigma, >= 0"),
        "velocity_random_walk": FieldRange(0, math.inf, "m/s/sqrt(s)", "white acceleration noise VRW, >= 0"),
        "bias_instability": FieldRange(0, math.inf, "m/s^2", "flicker coefficient B (IEEE 952), >= 0"),
        "acceleration_random_walk": FieldRange(0, math.inf, "m/s^2/sqrt(s)", "random walk of the bias, >= 0"),
        "bias_tempco": FieldRange(-math.inf, math.inf, "m/s^2/K", "bias temperature coefficient, signed"),
        "scale_factor_tempco": FieldRange(-math.inf, math.inf, "1/K", "scale-factor tempco, signed"),
        "range": FieldRange(0, math.inf, "m/s^2", "full scale +-range; inf: no limit", True, infinite=True),
        "bandwidth": FieldRange(0, math.inf, "Hz", "-3 dB corner of the output filter; inf: none", True, infinite=True),
        "resolution": FieldRange(0, math.inf, "m/s^2", "output LSB; 0: not quantized"),
        "reference_temperature": FieldRange(0, math.inf, "K", "where the tempcos are zero", low_open=True),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared specs above

    @classmethod
    def from_datasheet(
        cls,
        *,
        bias_repeatability_mg: float = 0.0,
        scale_factor_repeatability_ppm: float = 0.0,
        vrw_m_s_sqrt_h: float = 0.0,
        bias_instability_ug: float = 0.0,
        bias_tempco_mg_per_k: float = 0.0,
        scale_factor_tempco_ppm_per_k: float = 0.0,
        range_g: float = math.inf,
        bandwidth_hz: float = math.inf,
        resolution_mg: float = 0.0,
    ) -> AccelerometerSpec:
        """A spec from a sheet's field units (mg, ppm, m/s/sqrt(h), ug, g = 9.80665 m/s^2).

        Parameters
        ----------
        bias_repeatability_mg, scale_factor_repeatability_ppm : float
            Turn-on bias [mg] and scale-factor [ppm] repeatability, 1 sigma.
        vrw_m_s_sqrt_h : float
            Velocity random walk [m/s/sqrt(h)].
        bias_instability_ug : float
            Bias instability B [ug]: the IEEE coefficient (ADEV minimum / 0.664), as
            :meth:`gyrobench.sim.noise.NoiseModel.from_datasheet` takes it. A part's sheet figure
            (``accel_bias_instability_ug``, an ADEV minimum) goes through
            :meth:`gyrobench.sim.parts.Part.accelerometer` instead.
        bias_tempco_mg_per_k, scale_factor_tempco_ppm_per_k : float
            Temperature coefficients [mg/K], [ppm/K].
        range_g, bandwidth_hz, resolution_mg : float
            Full scale [g], -3 dB bandwidth [Hz] and LSB [mg].

        Returns
        -------
        AccelerometerSpec
        """
        g = units.G0
        return cls(
            bias_repeatability=bias_repeatability_mg * 1e-3 * g,
            scale_factor_repeatability=scale_factor_repeatability_ppm * 1e-6,
            velocity_random_walk=vrw_m_s_sqrt_h / 60.0,
            bias_instability=bias_instability_ug * 1e-6 * g,
            bias_tempco=bias_tempco_mg_per_k * 1e-3 * g,
            scale_factor_tempco=scale_factor_tempco_ppm_per_k * 1e-6,
            range=range_g * g,
            bandwidth=bandwidth_hz,
            resolution=resolution_mg * 1e-3 * g,
        )

    def to_metadata(self) -> dict[str, float | None]:
        """The fields in SI as a JSON-ready dict (None for an unlimited range or bandwidth)."""
        return {f.name: (None if math.isinf(getattr(self, f.name)) else float(getattr(self, f.name)))
                for f in fields(self)}

    def low_pass(self, x: NDArray[np.float64], fs: float) -> NDArray[np.float64]:
        """The output filter (``bandwidth``) applied to samples ``x`` at ``fs`` [Hz], from its steady state."""
        if math.isinf(self.bandwidth):
            return x
        from scipy.signal import lfilter

        a = math.exp(-2 * math.pi * self.bandwidth / fs)
        y, _ = lfilter([1 - a], [1.0, -a], x, zi=[a * x[0]])
        return np.asarray(y)

    def noise(self) -> NoiseModel:
        """The IEEE-952 terms as a noise model (VRW as N, B, acceleration random walk as K)."""
        return NoiseModel(
            angle_random_walk=self.velocity_random_walk,
            bias_instability=self.bias_instability,
            rate_random_walk=self.acceleration_random_walk,
        )


def sensitivity_matrix(
    *, misalignment: float, cross_axis: float, rng: np.random.Generator
) -> NDArray[np.float64]:
    """C = I + E, E's six off-diagonal elements drawn N(0, misalignment^2 + cross_axis^2).

    Parameters
    ----------
    misalignment : float
        1 sigma of an axis' misalignment and non-orthogonality, per element [rad].
    cross_axis : float
        1 sigma of the cross-axis sensitivity, per element [-].
    rng : numpy.random.Generator
        Six standard normals, drawn row by row (xy, xz, yx, yz, zx, zy).

    Returns
    -------
    ndarray, shape (3, 3)
    """
    check_rng(rng)
    sigma = math.hypot(misalignment, cross_axis)
    z = rng.standard_normal(6)
    c = np.eye(3)
    c[~np.eye(3, dtype=bool)] = sigma * z
    return c


@dataclass(frozen=True, slots=True, kw_only=True)
class TriadSpec:
    """An IMU design: three gyro axes of any device, an accelerometer triad, their alignment.

    Parameters
    ----------
    gyros : tuple of three Sensor
        The x, y and z gyro designs (a datasheet part, :mod:`gyrobench.sim.parts`, or a device
        model's spec); each axis draws its own unit with its own stream.
    accelerometer : AccelerometerSpec or None
        The accelerometer design (all three axes alike); None: no accelerometers.
    misalignment, cross_axis : float
        1 sigma per off-diagonal element of the gyro triad's C [rad], [-] (module docstring).
    accel_misalignment, accel_cross_axis : float
        The same for the accelerometer triad.
    gyro_matrix, accel_matrix : array_like, shape (3, 3), optional
        A given C instead of a drawn one (e.g. a calibration's result).
    g_sensitivity : array_like, shape (3, 3), optional
        Off-axis g-sensitivity G_g [rad/s per m/s^2] (its diagonal adds to the device's own).
    gg_sensitivity : array_like, shape (3,), optional
        g x g sensitivity along each axis [rad/s per (m/s^2)^2].
    """

    gyros: tuple[Sensor, Sensor, Sensor]
    accelerometer: AccelerometerSpec | None = None
    misalignment: float = 0.0
    cross_axis: float = 0.0
    accel_misalignment: float = 0.0
    accel_cross_axis: float = 0.0
    gyro_matrix: NDArray[np.float64] | None = None
    accel_matrix: NDArray[np.float64] | None = None
    g_sensitivity: NDArray[np.float64] | None = None
    gg_sensitivity: NDArray[np.float64] | None = None

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "misalignment": FieldRange(0, 0.1, "rad", "1 sigma off-diagonal misalignment; <= 0.1: a small-angle matrix"),
        "cross_axis": FieldRange(0, 0.1, "1", "1 sigma cross-axis sensitivity; <= 0.1: a small-angle matrix"),
        "accel_misalignment": FieldRange(0, 0.1, "rad", "the accelerometer triad's misalignment, as above"),
        "accel_cross_axis": FieldRange(0, 0.1, "1", "the accelerometer triad's cross-axis sensitivity, as above"),
    }
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "gyros are three sensor specs",
            lambda c: isinstance(c.gyros, tuple) and len(c.gyros) == 3 and all(hasattr(g, "realize") for g in c.gyros),
            lambda c: f"gyros must be three sensor specs (each with realize(rng=...)); got {shown(c.gyros)}",
            TypeError,
        ),
        Constraint(
            "accelerometer is an AccelerometerSpec or None",
            lambda c: c.accelerometer is None or isinstance(c.accelerometer, AccelerometerSpec),
            lambda c: f"accelerometer must be an AccelerometerSpec or None; got {shown(c.accelerometer)}",
            TypeError,
        ),
        finite_array("gyro_matrix", (3, 3), "1", optional=True),
        finite_array("accel_matrix", (3, 3), "1", optional=True),
        finite_array("g_sensitivity", (3, 3), "rad/s per m/s^2", optional=True),
        finite_array("gg_sensitivity", (3,), "rad/s per (m/s^2)^2", optional=True),
    )

    def __post_init__(self) -> None:
        object.__setattr__(self, "gyros", as_tuple(self.gyros))
        object.__setattr__(self, "gyro_matrix", as_array(self.gyro_matrix))
        object.__setattr__(self, "accel_matrix", as_array(self.accel_matrix))
        object.__setattr__(self, "g_sensitivity", as_array(self.g_sensitivity))
        object.__setattr__(self, "gg_sensitivity", as_array(self.gg_sensitivity))
        validate(self)  # the declared specs and constraints above

    def realize(self, *, rng: np.random.Generator) -> TriadUnit:
        """Draw one IMU: three gyro units, the accelerometers' turn-on terms, both matrices.

        Parameters
        ----------
        rng : numpy.random.Generator
            Five children: the three gyros, the alignment, the accelerometers.

        Returns
        -------
        TriadUnit
        """
        check_rng(rng)
        r_g = rng.spawn(3)
        r_align, r_acc = rng.spawn(2)
        gx, gy, gz = (spec.realize(rng=r) for spec, r in zip(self.gyros, r_g, strict=True))
        gyros = (gx, gy, gz)
        ra, rb = r_align.spawn(2)
        c_g = self.gyro_matrix if self.gyro_matrix is not None else sensitivity_matrix(
            misalignment=self.misalignment, cross_axis=self.cross_axis, rng=ra)
        c_a = self.accel_matrix if self.accel_matrix is not None else sensitivity_matrix(
            misalignment=self.accel_misalignment, cross_axis=self.accel_cross_axis, rng=rb)
        acc = self.accelerometer
        z = r_acc.standard_normal(6)
        bias = (acc.bias_repeatability if acc else 0.0) * z[:3]
        sf = (acc.scale_factor_repeatability if acc else 0.0) * z[3:]
        return TriadUnit(spec=self, gyros=gyros, gyro_matrix=c_g, accel_matrix=c_a, accel_bias=bias,
                         accel_scale_factor=sf)


@dataclass(frozen=True, slots=True)
class ImuRecord:
    """An IMU record: the triad's recording and the ideal increments it was driven by.

    Attributes
    ----------
    recording : Recording
        Channels ``gyro_x..z`` [rad/s] and ``accel_x..z`` [m/s^2] (or ``dtheta_*`` [rad] and
        ``dv_*`` [m/s] as increments), ``temperature`` [K]; truth per channel (module docstring).
    ideal : Increments
        The motion's exact increments, attitude and velocity at the sample edges.
    """

    recording: Recording
    ideal: Increments


@dataclass(frozen=True, slots=True, kw_only=True)
class TriadUnit:
    """One drawn IMU (:meth:`TriadSpec.realize`).

    Parameters
    ----------
    spec : TriadSpec
    gyros : tuple of three SensorUnit
    gyro_matrix, accel_matrix : ndarray, shape (3, 3)
        The drawn (or given) C of each triad.
    accel_bias : ndarray, shape (3,)
        This turn-on's accelerometer biases [m/s^2].
    accel_scale_factor : ndarray, shape (3,)
        This turn-on's accelerometer scale-factor errors [-].
    """

    spec: TriadSpec
    gyros: tuple[SensorUnit, SensorUnit, SensorUnit]
    gyro_matrix: NDArray[np.float64]
    accel_matrix: NDArray[np.float64]
    accel_bias: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    accel_scale_factor: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))

    def simulate(
        self,
        motion: Motion,
        *,
        fs: float,
        rng: np.random.Generator,
        site: Site | None = None,
        temperature: float | None = None,
        as_increments: bool = False,
    ) -> ImuRecord:
        """One record of the IMU along ``motion`` at output rate ``fs`` [Hz].

        Parameters
        ----------
        motion : Motion
            The trajectory (:mod:`gyrobench.sim.trajectory`).
        fs : float
            Output rate [Hz].
        rng : numpy.random.Generator
            Four children: the three gyro records and the accelerometers' noise.
        site : Site, optional
            Latitude and height (default: the equator at sea level).
        temperature : float, optional
            Block temperature [K], shared by every axis (None: each device's reference).
        as_increments : bool
            Channels as increments (``dtheta_*`` [rad], ``dv_*`` [m/s]) instead of rates, and their
            truth and components likewise (``truth/dtheta_x.true``, ...).

        Returns
        -------
        ImuRecord
        """
        fs = check_fs(fs)
        check_rng(rng)
        ideal = increments(motion, fs, site=site)
        n = len(ideal.dtheta)
        w_true, f_true = ideal.rate, ideal.specific_force
        w_sensed = w_true @ self.gyro_matrix.T
        spec = self.spec
        g_term = np.zeros((n, 3))
        if spec.g_sensitivity is not None:
            g_term += f_true @ spec.g_sensitivity.T
        if spec.gg_sensitivity is not None:
            g_term += spec.gg_sensitivity * f_true**2
        r_axes = rng.spawn(3)
        (r_acc,) = rng.spawn(1)
        channels: dict[str, Channel] = {}
        truth: dict[str, Channel] = {}
        components: dict[str, list[str]] = {}
        rs = "rad/s"
        for i, (axis, unit, r) in enumerate(zip(AXES, self.gyros, r_axes, strict=True)):
            env = Environment(n / fs, true_rate=w_sensed[:, i] + g_term[:, i], temperature=temperature,
                              specific_force=f_true[:, i])
            rec = unit.simulate(env, fs=fs, rng=r)
            out = rec["output"]
            drive = rec["truth/true_rate"]
            ch = f"gyro_{axis}"
            channels[ch] = Channel(out, rs, f"gyro {axis} output")
            terms = {
                "true": Channel(w_true[:, i], rs, f"omega_ib^b along the nominal {axis} axis"),
                "misalignment": Channel(w_sensed[:, i] - w_true[:, i], rs, "(C_g - I) omega_ib^b"),
                "g_sensitivity": Channel(g_term[:, i], rs, "off-axis and g x g sensitivity"),
            }
            comps = list(rec.metadata.get("error_components") or [])
            if comps:
                for c in comps:
                    terms[f"device.{c}"] = Channel(rec[f"truth/{c}"], rs, f"the device's {c}")
                # the device's true rate beyond its input (e.g. the FOG's Earth rate) stays in its own truth
                extra = drive - (w_sensed[:, i] + g_term[:, i])
                if np.any(extra != 0):
                    terms["device.true_rate_offset"] = Channel(extra, rs, "the device's own true-rate terms")
            else:
                terms["device.error"] = Channel(out - drive, rs, "the device's error (its model keeps no terms)")
            for k, v in terms.items():
                truth[f"{ch}.{k}"] = v
            components[ch] = [f"{ch}.{k}" for k in terms if k != "true"]
        acc = spec.accelerometer
        if acc is not None:
            temp = acc.reference_temperature if temperature is None else float(temperature)
            d_t = temp - acc.reference_temperature
            f_sensed = f_true @ self.accel_matrix.T
            noise_gen = acc.noise()
            r_noise = r_acc.spawn(3)
            ms2 = "m/s^2"
            for i, axis in enumerate(AXES):
                ch = f"accel_{axis}"
                sf = self.accel_scale_factor[i] + acc.scale_factor_tempco * d_t
                bias = self.accel_bias[i] + acc.bias_tempco * d_t
                noise = noise_gen.generate(n, fs, rng=r_noise[i])
                unfiltered = (1 + sf) * f_sensed[:, i] + bias + noise
                ideal_out = acc.low_pass(unfiltered, fs)
                out = np.clip(ideal_out, -acc.range, acc.range)
                if acc.resolution > 0:
                    out = acc.resolution * np.round(out / acc.resolution)
                terms = {
                    "true": Channel(f_true[:, i], ms2, f"f^b along the nominal {axis} axis"),
                    "misalignment": Channel(f_sensed[:, i] - f_true[:, i], ms2, "(C_a - I) f^b"),
                    "scale_factor_error": Channel(sf * f_sensed[:, i], ms2, "(s + k_s dT) (C_a f^b)"),
                    "bias": Channel(np.full(n, bias), ms2, "turn-on bias + k_b dT"),
                    "noise": Channel(noise, ms2, "VRW, bias instability, acceleration random walk"),
                    "filter": Channel(ideal_out - unfiltered, ms2, "the output low-pass's change"),
                    "output_rounding": Channel(out - ideal_out, ms2, "range limit and quantization"),
                }
                channels[ch] = Channel(out, ms2, f"accelerometer {axis} output")
                for k, v in terms.items():
                    truth[f"{ch}.{k}"] = v
                components[ch] = [f"{ch}.{k}" for k in terms if k != "true"]
        if as_increments:  # outputs, their truth and components as increments (x 1/fs): the sums still close

            def inc(k: str) -> str:
                return k.replace("gyro_", "dtheta_").replace("accel_", "dv_")

            def as_inc(k: str, v: Channel) -> Channel:
                return Channel(v.data / fs, "rad" if k.startswith("gyro") else "m/s",
                               v.description + " x 1/fs (increment)")

            channels = {inc(k): as_inc(k, v) for k, v in channels.items()}
            truth = {inc(k): as_inc(k, v) for k, v in truth.items()}
            components = {inc(k): [inc(c) for c in v] for k, v in components.items()}
        if temperature is not None:
            channels["temperature"] = Channel(np.full(n, float(temperature)), "K", "block temperature")
        meta = {
            "model": "gyrobench.sim.imu.TriadUnit",
            "accelerometer": None if acc is None else acc.to_metadata(),
            "gyro_matrix": self.gyro_matrix.tolist(),
            "accel_matrix": self.accel_matrix.tolist(),
            "error_components": components,
            "increments": as_increments,
            "package_version": package_version(),
        }
        rec = Recording(fs=fs, channels=channels, truth=truth, t0=0.5 / fs, metadata=meta, name="imu")
        return ImuRecord(recording=rec, ideal=ideal)
