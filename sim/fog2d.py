"""The closed-loop FOG of :mod:`gyrobench.sim.fog_loop` on the (r, z) coil of ``sim.coil2d``.

An adapter, not a second FOG model: :class:`FOG2DUnit` pairs one drawn :class:`Coil2D` with
the :class:`gyrobench.sim.fog_loop.ClosedLoopFOG` built on that coil (fibre length L and
mean diameter D of its fibre map, the coil's wavelength and phase index), and feeds the
coil's thermal nonreciprocity to the loop as one more nonreciprocal phase input:

    phi_nr(t) = SF0 Omega_E(t),   Omega_E = Shupe map + T x dT form of Coil2D   [rad, rad/s]

(:meth:`Coil2D.run`: the thermal network solved once per chamber program on the coarse
step ``thermal_step``, interpolated linearly to the output block centres). The output is
the loop's (reduced form, :class:`ClosedLoopFOG`): Sagnac phase of the true rate (table +
Earth component of the sense axis) times SF(T)/SF0, plus phi_nr/SF0, through H(0) = 1, plus
the optical budget's white noise and the additive IEEE-952 terms of ``noise`` (what the
optics do not produce: bias instability, constant bias). Scale factor vs temperature:

    SF(T)/SF0 = (1 + alpha_D (T_coil - T_ref))^2 / (1 + alpha_lambda (T_source - T_ref))

with T_coil the coil's mean pack temperature, T_source the housing temperature (the source
sits in the housing), alpha_D by default the coil's own hoop expansion (fibre-length mean
of the composite-cylinder d eps_theta/dT of :meth:`Coil2DSpec.hoop_strain_rate` at T_ref:
the winding radius and the wound fibre length both follow the hoop strain, so SF ~ L D
~ D^2).

Recording layout (docs/recording.md): channels ``output`` [rad/s] and ``coil_temperature`` [K];
truth ``true_rate`` and the loop's error components; detail ``thermal_drift`` = ``shupe`` +
``txdt_product`` and ``noise`` = optical + IEEE-952; inputs: the temperatures. The
logged sensor sits on the outer potting surface at the unit's drawn axial position.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import ClassVar

import numpy as np
from numpy.typing import NDArray

from gyrobench.base import units
from gyrobench.base.ranges import Constraint, FieldChoice, FieldRange, validate
from gyrobench.io.recording import Channel, Recording
from gyrobench.sim.coil2d import Coil2D, Coil2DSpec, ThermalRun
from gyrobench.sim.coil_vibration import coil_modes
from gyrobench.sim.earth import HARBIN
from gyrobench.sim.environment import PiecewiseLinear
from gyrobench.sim.fog_loop import ClosedLoopFOG, LoopSpec
from gyrobench.sim.fog_optics import OpticalBudget
from gyrobench.sim.noise import NoiseModel
from gyrobench.sim.sensor import FOG_ERROR_COMPONENTS, Environment, chamber_program, check_call, with_metadata
from gyrobench.sim.shaker import ShakerSignal

__all__ = ["TemperatureSensorSpec", "FOG2DSpec", "FOG2DUnit", "coil_diameter_tempco"]


_SENSOR_LOCATIONS = ("outer", "inner", "mean", "spool", "housing")


@dataclass(frozen=True, slots=True, kw_only=True)
class TemperatureSensorSpec:
    """The logged coil temperature sensor (PT1000 + ADC in paper 003).

    Parameters
    ----------
    location : {"outer", "inner", "mean", "spool", "housing"}
        Outer or inner fibre layer, mean of all layers, spool, or housing.
    noise : float
        White noise rms per sample [K].
    resolution : float
        Quantization step [K] (0 = none). 18-bit ADC over ~100 K: ~0.4 mK.
    bias : float
        Constant offset [K].
    """

    location: str = "outer"
    noise: float = 0.003
    resolution: float = 0.001
    bias: float = 0.0

    RANGES: ClassVar[Mapping[str, FieldRange | FieldChoice]] = {
        "location": FieldChoice(_SENSOR_LOCATIONS, "where on the coil the sensor reads"),
        "noise": FieldRange(0, math.inf, "K", "1-sigma white noise of a reading"),
        "resolution": FieldRange(0, math.inf, "K", "quantization step of a reading (0: none)"),
        "bias": FieldRange(-math.inf, math.inf, "K", "constant offset of the readings"),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared specs above

    def read(
        self, true_temperature: NDArray[np.float64], *, rng: np.random.Generator
    ) -> NDArray[np.float64]:
        """Logged value: quantize(T + bias + noise) [K]."""
        y = true_temperature + self.bias + self.noise * rng.standard_normal(len(true_temperature))
        if self.resolution > 0:
            y = np.round(y / self.resolution) * self.resolution
        return y


def _default_noise() -> NoiseModel:
    # additive IEEE-952 terms the optics do not produce (the white noise is the budget's)
    return NoiseModel.from_datasheet(bias_instability=0.003, bias=0.05)


def _default_optics() -> OpticalBudget:
    return OpticalBudget()


def coil_diameter_tempco(coil: Coil2DSpec | Coil2D, temperature: float | None = None) -> float:
    """alpha_D of a coil: fibre-length mean of d eps_theta/dT over the bonded fibre [1/K].

    The composite-cylinder hoop strain rate of the pack on its spool
    (:meth:`Coil2DSpec.hoop_strain_rate`, at ``temperature``, default the coil's t_ref [K]),
    averaged over the fibre pieces in the pack with their lengths as weights (an ideal
    winding when a spec is given). It is the relative change of the winding radius, hence of
    the mean diameter D and of the wound length L (turns fixed): SF ~ L D changes by 2 alpha_D.

    Parameters
    ----------
    coil : Coil2DSpec or Coil2D
        A coil spec (an ideal winding) or a drawn coil.
    temperature : float, optional
        Temperature at which the strain rate is taken [K]; None: the coil's t_ref.

    Returns
    -------
    float
        alpha_D [1/K].
    """
    if not isinstance(coil, (Coil2D, Coil2DSpec)):
        raise TypeError(f"coil must be a Coil2DSpec or Coil2D; got {type(coil).__name__}")
    c = coil if isinstance(coil, Coil2D) else Coil2D(spec=coil)
    t = c.spec.t_ref if temperature is None else float(temperature)
    fm = c.fibre()
    b = fm.bonded
    h = c.spec.hoop_strain_rate(fm.r[b], t)
    return float(np.sum(h * fm.ds[b]) / np.sum(fm.ds[b]))


@dataclass(frozen=True, slots=True, kw_only=True)
class FOG2DSpec:
    """A closed-loop FOG on the (r, z) coil, in a thermal chamber (SI): the build of a unit.

    Parameters
    ----------
    coil : Coil2DSpec
    noise : NoiseModel
        Additive IEEE-952 terms (:class:`ClosedLoopFOG` ``noise``): what the optics do not
        produce. Default bias instability 0.003 deg/h and bias 0.05 deg/h, no ARW (the ARW is
        the optical budget's: an N term given here adds to it); ASSUMED navigation-grade sizes.
    optics : OpticalBudget
        Source, losses, detector of the loop (the white noise).
    bias_phase : float
        Modulation depth phi_b [rad] of the loop (pi/2 default).
    loop_gain : float
        Normalised rate-loop gain g [-] (:class:`LoopSpec`).
    sensor : TemperatureSensorSpec
        Noise, resolution and bias of the logged temperature (its ``location`` must be
        ``"outer"``: the sensor is on the outer potting surface).
    diameter_tempco : float or None
        alpha_D [1/K]; None (default): the coil's own hoop expansion
        (:func:`coil_diameter_tempco` of the drawn coil at its t_ref). The scale-factor law is
        the loop's (1 + alpha_D dT)^2 (SF ~ L D, both following the winding radius; the glass
        expansion alpha_f does not enter separately, docs/design-notes.md).
    wavelength_tempco : float
        (1/lambda) dlambda/dT of the source [1/K] (4 ppm/K; ASSUMED).
    scale_factor_ref_temperature : float
        T_ref, where SF = SF0 [K].
    thermal_step : float
        Coarse step of the thermal solve [s] (20 s; the solve is exact for chamber knots on
        the step grid and checked against dt/2 otherwise, :meth:`Coil2D.run`).
    latitude, azimuth, elevation : float
        Site latitude and the sense axis' azimuth (from north toward east) and elevation
        [rad]. Default Harbin (paper 003's lab), axis horizontal pointing east, where the
        Earth-rate component is 0 (:func:`gyrobench.sim.earth.sensed_earth_rate`).
    """

    coil: Coil2DSpec = field(default_factory=Coil2DSpec)
    noise: NoiseModel = field(default_factory=_default_noise)
    optics: OpticalBudget = field(default_factory=_default_optics)
    bias_phase: float = math.pi / 2
    loop_gain: float = 0.1
    sensor: TemperatureSensorSpec = field(default_factory=TemperatureSensorSpec)
    diameter_tempco: float | None = None
    wavelength_tempco: float = 4.0e-6
    scale_factor_ref_temperature: float = units.celsius(20.0)
    thermal_step: float = 20.0
    latitude: float = HARBIN.latitude
    azimuth: float = math.pi / 2
    elevation: float = 0.0

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        # bias_phase, loop_gain and the site angles: finite here, their ranges checked by the loop
        # and the unit the spec builds
        "bias_phase": FieldRange(-math.inf, math.inf, "rad", "modulation depth (LoopSpec checks (0, pi))"),
        "loop_gain": FieldRange(-math.inf, math.inf, "1", "rate-loop gain (LoopSpec checks its stability)"),
        "diameter_tempco": FieldRange(-1e-3, 1e-3, "1/K", "alpha_D (None: the coil's own)", True, True),
        "wavelength_tempco": FieldRange(-1e-3, 1e-3, "1/K", "alpha_lambda of the source", True, True),
        "scale_factor_ref_temperature": FieldRange(0, math.inf, "K", "where the scale factor is nominal",
                                                   low_open=True),
        "thermal_step": FieldRange(0, math.inf, "s", "thermal solver step", low_open=True),
        "latitude": FieldRange(-math.inf, math.inf, "rad", "site latitude (ClosedLoopFOG checks it)"),
        "azimuth": FieldRange(-math.inf, math.inf, "rad", "sense-axis azimuth from north"),
        "elevation": FieldRange(-math.inf, math.inf, "rad", "sense-axis elevation (ClosedLoopFOG checks it)"),
    }
    #: the constraints across fields (:class:`~gyrobench.base.ranges.Constraint`)
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "sensor.location == 'outer'",
            lambda c: c.sensor.location == "outer",
            lambda c: f"sensor.location must be 'outer' (on the potting); got {c.sensor.location!r}",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above
        # the loop validates bias_phase / loop_gain, the unit latitude / azimuth / elevation
        self.loop_spec(length=1000.0, diameter=0.1)
        ClosedLoopFOG(latitude=self.latitude, azimuth=self.azimuth, elevation=self.elevation)

    def loop_spec(self, *, length: float, diameter: float) -> LoopSpec:
        """The loop on a coil of fibre length ``length`` and mean diameter ``diameter`` [m]."""
        return LoopSpec(
            length=length,
            diameter=diameter,
            wavelength=self.coil.wavelength,
            bias_phase=self.bias_phase,
            loop_gain=self.loop_gain,
        )

    def realize(self, *, rng: np.random.Generator) -> FOG2DUnit:
        """One built unit (potting properties, winding imperfections, sensor position drawn)."""
        return FOG2DUnit(spec=self, coil=self.coil.realize(rng=rng))


@dataclass(frozen=True, kw_only=True)
class FOG2DUnit:
    """One FOG: its spec, its drawn coil, and the closed loop on that coil (:attr:`fog`).

    Parameters
    ----------
    spec : FOG2DSpec
        The design the unit was drawn from.
    coil : Coil2D
        The drawn coil (winding, defects, materials).
    chamber_scale : float
        Factor on the chamber-housing conductance for this run's mounting and airflow [-]
        (:meth:`Coil2D.network`); 1 by default. A run-to-run variation is
        ``dataclasses.replace(unit, chamber_scale=...)``.
    """

    spec: FOG2DSpec
    coil: Coil2D
    chamber_scale: float = 1.0

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "chamber_scale": FieldRange(0, math.inf, "1", "factor on the chamber-housing conductance", low_open=True),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared spec above (and the types of spec and coil)

    @cached_property
    def fog(self) -> ClosedLoopFOG:
        """The unit's closed-loop FOG: loop on this coil's L, D, wavelength; spec's optics."""
        s = self.spec
        fm = self.coil.fibre()
        alpha_d = (
            coil_diameter_tempco(self.coil) if s.diameter_tempco is None else s.diameter_tempco
        )
        return ClosedLoopFOG(
            loop=s.loop_spec(length=fm.length, diameter=fm.diameter),
            optics=s.optics,
            noise=s.noise,
            diameter_tempco=float(alpha_d),
            wavelength_tempco=s.wavelength_tempco,
            reference_temperature=s.scale_factor_ref_temperature,
            modes=coil_modes(self.coil),
            index=self.coil.spec.index,
            latitude=s.latitude,
            azimuth=s.azimuth,
            elevation=s.elevation,
        )

    @property
    def scale_factor(self) -> float:
        """SF0 = 2 pi L D/(lambda c) of the mapped fibre [s]."""
        return self.fog.scale_factor

    def thermal_response(
        self, chamber: PiecewiseLinear, *, chamber_scale: float = 1.0
    ) -> ThermalRun:
        """The coil's thermal run for a chamber program (:meth:`Coil2D.run`)."""
        if not isinstance(chamber, PiecewiseLinear):
            raise TypeError(
                f"chamber must be a sim.environment.PiecewiseLinear; got {type(chamber).__name__}"
            )
        return self.coil.run(
            chamber.times, chamber.values, dt=self.spec.thermal_step, chamber_scale=chamber_scale
        )

    def simulate(self, environment: Environment, *, fs: float, rng: np.random.Generator) -> Recording:
        """One chamber run logged at ``fs`` [Hz] through the unit's closed loop (:attr:`fog`).

        Parameters
        ----------
        environment : Environment
            ``duration`` [s]; ``temperature``, the chamber program [K] (a number or None: the
            spec's scale-factor reference temperature, held; a :class:`PiecewiseLinear`; an
            array or callable, linear between the sample centres), run through the coil's
            (r, z) heat flow (:meth:`thermal_response`, with the unit's ``chamber_scale``);
            ``true_rate``, the table rate [rad/s] (the sense axis' Earth component is added
            by the loop); ``vibration``, a shaker run along the sense axis (from t = 0, its rate an
            even multiple of ``fs``): the coil's own modes (:func:`gyrobench.sim.coil_vibration.coil_modes`:
            the spool's inertial strain on the winding map, the pigtail, the fixture) through the
            loop, as the terms ``strain_nonreciprocity``, ``rectification`` and ``loop_error``. The
            model has no static g-sensitive term: a set ``specific_force`` is listed in the
            metadata's ``ignored_inputs``.
        fs : float
            Output rate [Hz].
        rng : numpy.random.Generator
            Two children: the loop (optical and IEEE-952 noise) and the temperature sensor.

        Returns
        -------
        Recording
            Channels ``output`` [rad/s] and ``coil_temperature`` [K] (the logged sensor); truth
            ``true_rate`` and the loop's terms named by the metadata's ``error_components``
            (summing to ``output - true_rate``); detail: the coil's thermal drift and its Shupe
            and T x dT parts, the loop's sub-terms; inputs: the coil, housing, sensor and
            chamber temperatures. Samples are block means over 1/fs at the
            block centres (k + 1/2)/fs, where the temperatures are also taken.
        """
        fs = check_call(environment, fs, rng)
        chamber = chamber_program(environment, fs, self.spec.scale_factor_ref_temperature)
        if chamber.times[0] != 0.0 or chamber.times[-1] < environment.duration:
            raise ValueError(
                "Environment.temperature as a chamber program must span the record [0, duration] = "
                f"[0, {environment.duration!r}] s; got [{float(chamber.times[0])!r}, {float(chamber.times[-1])!r}] s"
            )
        rec = self._chamber_run(chamber, environment.duration, fs, rng, environment.profile("true_rate", fs),
                                shaker=environment.vibration)
        return with_metadata(
            rec,
            ignored_inputs=environment.ignored("specific_force"),
            error_components=list(FOG_ERROR_COMPONENTS),
        )

    def _chamber_run(
        self,
        chamber: PiecewiseLinear,
        duration: float,
        fs: float,
        rng: np.random.Generator,
        true_rate: float | Callable[[NDArray[np.float64]], NDArray[np.float64]] | None,
        shaker: ShakerSignal | None = None,
    ) -> Recording:
        true_rate = 0.0 if true_rate is None else true_rate
        run = self.thermal_response(chamber, chamber_scale=self.chamber_scale)
        t0 = float(run.t[0])

        def interp(y: NDArray[np.float64]) -> Callable[[NDArray[np.float64]], NDArray[np.float64]]:
            return lambda t: np.interp(t, run.t, y)

        rng_fog, rng_sensor = rng.spawn(2)
        rec = self.fog._record(
            duration,
            float(fs),
            rng=rng_fog,
            true_rate=true_rate,
            coil_temperature=interp(run.coil_mean),
            source_temperature=interp(run.housing),
            nonreciprocal_rate=interp(run.shupe + run.product),
            t0=t0,
            shaker=shaker,
        )
        n = len(rec["output"])
        t = t0 + (np.arange(n) + 0.5) / fs
        shupe, product = np.interp(t, run.t, run.shupe), np.interp(t, run.t, run.product)
        sensor_true = np.interp(t, run.t, run.sensor)
        logged = self.spec.sensor.read(sensor_true, rng=rng_sensor)
        rs = "rad/s"
        tr = dict(rec.truth)
        noise = tr["optical_noise"].data + tr["ieee_noise"].data
        truth = {
            **tr,
            "thermal_drift": Channel(
                tr["nonreciprocal"].data, rs, "coil non-reciprocity, total (the loop's input)"
            ),
            "shupe": Channel(
                shupe, rs, "Shupe map with beta_T(T0) (dn/dT, expansion, elasto-optic strain)"
            ),
            "txdt_product": Channel(
                product, rs, "T x dT term from the material temperature dependences"
            ),
            "noise": Channel(noise, rs, "optical (budget ARW) + IEEE-952 terms incl. bias"),
            "sensor_temperature": Channel(sensor_true, "K", "noise-free temperature at the sensor"),
            "coil_mean_temperature": Channel(
                np.interp(t, run.t, run.coil_mean), "K", "mean over the fibre pack (alpha_D)"
            ),
            "housing_temperature": Channel(
                np.interp(t, run.t, run.housing), "K", "housing (source, alpha_lambda)"
            ),
            "chamber_temperature": Channel(np.interp(t, run.t, run.chamber), "K", "chamber"),
        }
        channels = {
            "output": rec.channels["output"],
            "coil_temperature": Channel(logged, "K", "coil temperature sensor (outer potting)"),
            **{k: c for k, c in rec.channels.items() if k.startswith("vibration_")},  # the shaker's log
        }
        meta = {
            **rec.metadata,
            "model": "gyrobench.sim.fog2d.FOG2DUnit -> gyrobench.sim.fog_loop.ClosedLoopFOG",
            "thermal_step_s": run.dt,
            "thermal_convergence": run.convergence,
            "winding": self.coil.spec.winding,
            "diameter_tempco_per_K": self.fog.diameter_tempco,
            "wavelength_tempco_per_K": self.fog.wavelength_tempco,
        }
        return Recording(
            fs=float(fs), channels=channels, truth=truth, t0=t0, metadata=meta, name="fog2d"
        )
