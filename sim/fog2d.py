"""Interferometric FOG on the (r, z) coil of :mod:`gyrobench.sim.coil2d`, in a thermal chamber.

Same recording layout as :mod:`gyrobench.sim.fog` (channels ``rate`` [rad/s] and
``coil_temperature`` [K]; truth ``rate``, ``thermal_drift`` and its parts, the scale-factor
error, noise and the temperatures), so scenarios can switch coil models without changing
their analysis. Output model (SI):

    output = Omega_true * SF(T)/SF0 + Omega_E(t) + noise(t)                          [rad/s]

with Omega_E = Shupe map + T x dT form of :class:`gyrobench.sim.coil2d.Coil2D` (its thermal
network solved once per chamber program on the coarse step ``thermal_step``, then
interpolated linearly to the output rate), SF = 2 pi L D/(lambda c) from
:func:`gyrobench.sim.fog.sagnac_scale_factor` and SF(T)/SF0 as in :mod:`gyrobench.sim.fog`
with the mean pack temperature and the housing temperature. The logged sensor sits on the
outer potting surface at the unit's drawn axial position.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from numbers import Real

import numpy as np
from gyrobench.sim import units
from gyrobench.sim.coil2d import Coil2D, Coil2DSpec, ThermalRun
from gyrobench.sim.environment import PiecewiseLinear
from gyrobench.sim.fog import TemperatureSensorSpec, sagnac_scale_factor
from gyrobench.sim.noise import NoiseModel
from gyrobench.sim.recording import Channel, Recording
from numpy.typing import NDArray

__all__ = ["FOG2DSpec", "FOG2DUnit"]


def _default_noise() -> NoiseModel:
    return NoiseModel.from_datasheet(angle_random_walk=0.001, bias_instability=0.003, bias=0.05)


@dataclass(frozen=True, slots=True, kw_only=True)
class FOG2DSpec:
    """Datasheet-level FOG on the (r, z) coil (SI).

    Parameters
    ----------
    coil : Coil2DSpec
    noise : NoiseModel
    sensor : TemperatureSensorSpec
        Noise, resolution and bias of the logged temperature (its ``location`` must be
        ``"outer"``: the sensor is on the outer potting surface).
    diameter_tempco, wavelength_tempco : float
        As :class:`gyrobench.sim.fog.FOGSpec` [1/K] (unverified there).
    scale_factor_ref_temperature : float
        [K].
    thermal_step : float
        Coarse step of the thermal solve [s] (20 s; the solve is exact for chamber knots on
        the step grid and checked against dt/2 otherwise, :meth:`Coil2D.run`).
    """

    coil: Coil2DSpec = field(default_factory=Coil2DSpec)
    noise: NoiseModel = field(default_factory=_default_noise)
    sensor: TemperatureSensorSpec = field(default_factory=TemperatureSensorSpec)
    diameter_tempco: float = 5.0e-6
    wavelength_tempco: float = 4.0e-6
    scale_factor_ref_temperature: float = units.celsius(20.0)
    thermal_step: float = 20.0

    def __post_init__(self) -> None:
        for name, kind in (
            ("coil", Coil2DSpec),
            ("noise", NoiseModel),
            ("sensor", TemperatureSensorSpec),
        ):
            if not isinstance(getattr(self, name), kind):
                got = type(getattr(self, name)).__name__
                raise TypeError(f"FOG2DSpec.{name} must be a {kind.__name__}; got {got}")
        if self.sensor.location != "outer":
            raise ValueError(
                f"FOG2DSpec.sensor.location must be 'outer' (on the potting); got "
                f"{self.sensor.location!r}"
            )
        for name in ("diameter_tempco", "wavelength_tempco"):
            v = getattr(self, name)
            if (
                isinstance(v, bool)
                or not isinstance(v, (int, float, Real))
                or not (math.isfinite(float(v)) and abs(float(v)) < 1e-3)
            ):
                raise ValueError(
                    f"FOG2DSpec.{name} must be finite with |value| < 1e-3 /K; got {v!r}"
                )
        v = self.thermal_step
        if isinstance(v, bool) or not isinstance(v, Real) or not (math.isfinite(v) and v > 0):
            raise ValueError(f"FOG2DSpec.thermal_step must be > 0 s; got {v!r}")

    def realize(self, *, rng: np.random.Generator) -> FOG2DUnit:
        """One built unit (potting properties, winding imperfections, sensor position drawn)."""
        return FOG2DUnit(spec=self, coil=self.coil.realize(rng=rng))


@dataclass(frozen=True, slots=True, kw_only=True)
class FOG2DUnit:
    """One FOG: its spec and its drawn coil."""

    spec: FOG2DSpec
    coil: Coil2D

    @property
    def scale_factor(self) -> float:
        fm = self.coil.fibre()
        return sagnac_scale_factor(fm.length, fm.diameter, self.coil.spec.wavelength)

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

    def simulate(
        self,
        chamber: PiecewiseLinear,
        *,
        fs: float,
        rng: np.random.Generator,
        true_rate: float | Callable[[NDArray[np.float64]], NDArray[np.float64]] = 0.0,
        chamber_scale: float = 1.0,
        name: str = "fog2d_thermal",
        metadata: dict | None = None,
    ) -> Recording:
        """One chamber run logged at ``fs`` [Hz] (``rng``: two children, rate and sensor noise)."""
        if isinstance(fs, bool) or not isinstance(fs, Real) or not (math.isfinite(fs) and fs > 0):
            raise ValueError(f"fs must be a finite number > 0 Hz; got {fs!r}")
        if not isinstance(rng, np.random.Generator):
            raise TypeError(f"rng must be a numpy.random.Generator; got {type(rng).__name__}")
        spec = self.spec
        run = self.thermal_response(chamber, chamber_scale=chamber_scale)
        n = int(math.floor((run.t[-1] - run.t[0]) * fs + 1e-9))
        t0 = float(run.t[0])
        t = t0 + np.arange(n) / fs

        def at(y):
            return np.interp(t, run.t, y)

        if callable(true_rate):
            omega = np.asarray(true_rate(t), dtype=float).reshape(n)
        elif isinstance(true_rate, Real) and math.isfinite(true_rate):
            omega = np.full(n, float(true_rate))
        else:
            raise ValueError(
                f"true_rate must be a finite number [rad/s] or a callable; got {true_rate!r}"
            )
        housing, mean_coil = at(run.housing), at(run.coil_mean)
        dc = mean_coil - spec.scale_factor_ref_temperature
        ds = housing - spec.scale_factor_ref_temperature
        a_f = float(self.coil.spec.glass.alpha(spec.scale_factor_ref_temperature))
        ratio = (1 + a_f * dc) * (1 + spec.diameter_tempco * dc) / (1 + spec.wavelength_tempco * ds)
        sf_err = omega * (ratio - 1.0)
        shupe, product = at(run.shupe), at(run.product)
        drift = shupe + product
        rng_noise, rng_sensor = rng.spawn(2)
        noise = spec.noise.generate(n, fs, rng=rng_noise, t0=t0)
        sensor_true = at(run.sensor)
        logged = spec.sensor.read(sensor_true, rng=rng_sensor)
        rs = "rad/s"
        truth = {
            "rate": Channel(omega, rs, "true input rate"),
            "thermal_drift": Channel(drift, rs, "coil non-reciprocity, total"),
            "shupe": Channel(
                shupe, rs, "Shupe map with beta_T(T0) (dn/dT, expansion, elasto-optic strain)"
            ),
            "txdt_product": Channel(
                product, rs, "T x dT term from the material temperature dependences"
            ),
            "scale_factor_error": Channel(sf_err, rs, "true rate x (SF(T)/SF0 - 1)"),
            "noise": Channel(noise, rs, "random noise and constant bias"),
            "sensor_temperature": Channel(sensor_true, "K", "noise-free temperature at the sensor"),
            "coil_mean_temperature": Channel(mean_coil, "K", "mean over the fibre pack"),
            "housing_temperature": Channel(housing, "K", "housing"),
            "chamber_temperature": Channel(at(run.chamber), "K", "chamber program"),
        }
        channels = {
            "rate": Channel(omega + sf_err + drift + noise, rs, "FOG output"),
            "coil_temperature": Channel(logged, "K", "coil temperature sensor (outer potting)"),
        }
        meta = {
            "model": "gyrobench.sim.fog2d.FOG2DUnit",
            "thermal_step_s": run.dt,
            "thermal_convergence": run.convergence,
            "winding": self.coil.spec.winding,
            "scale_factor_s": self.scale_factor,
            **(metadata or {}),
        }
        return Recording(
            fs=float(fs), channels=channels, truth=truth, t0=t0, metadata=meta, name=name
        )
