"""Interferometric FOG in a thermal chamber: Sagnac scale factor, coil thermal drift, noise, logged temperature.

What one simulated run produces (a :class:`gyrobench.sim.recording.Recording`):

channels (what a real test logs)
    ``rate`` [rad/s]: the gyro output; ``coil_temperature`` [K]: one sensor on the coil
    with its own white noise and ADC resolution.
truth (what only the simulator knows)
    ``rate`` (true input), ``thermal_drift`` (all coil non-reciprocity) and its parts
    ``shupe``, ``dndT_product``, ``strain``, ``strain_product``; ``scale_factor_error``;
    ``noise`` (the :class:`gyrobench.sim.noise.NoiseModel` sum incl. its constant bias);
    ``sensor_temperature`` (noise-free value at the sensor), ``coil_mean_temperature``,
    ``housing_temperature``, ``chamber_temperature`` [K].

Output model (SI):

    output = Omega_true * SF(T)/SF0 + Omega_E(t) + noise(t)                     [rad/s]

with Omega_E from :mod:`gyrobench.sim.coil` (heat diffusion + Shupe integral with strain and
T-dependent dn/dT) and the Sagnac scale factor (docs/physics.md 3.1, 3.6)

    SF = 2 pi L D / (lambda c)                                                  [s]
    SF(T)/SF0 = (1 + alpha_f dT_c)(1 + alpha_D dT_c) / (1 + alpha_lambda dT_s)

where dT_c is the mean-coil and dT_s the source (housing) temperature change from
``scale_factor_ref_temperature``; the closed-loop FOG divides the measured phase by the
nominal SF0, so the output gains the ratio.

Rates (documented for the scenario): the thermal network is stepped at
``thermal_step`` (default 5 s, implicit Euler; the fastest driven dynamics, the housing
lag, are 20 min), and the thermal quantities are interpolated linearly to the output
samples at ``fs``; the noise is generated at ``fs`` directly.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from numbers import Real

import numpy as np
from gyrobench.sim import units
from gyrobench.sim.coil import CoilSpec, CoilThermalModel, Winding, shupe_terms
from gyrobench.sim.environment import PiecewiseLinear
from gyrobench.sim.fog2d import TemperatureSensorSpec  # its home: the FOG on the (r, z) coil
from gyrobench.sim.fog_loop import sagnac_scale_factor  # its home: the closed-loop FOG
from gyrobench.sim.noise import NoiseModel
from gyrobench.sim.recording import Channel, Recording
from gyrobench.sim.units import SPEED_OF_LIGHT  # exact SI, re-exported
from numpy.typing import NDArray

__all__ = ["SPEED_OF_LIGHT", "TemperatureSensorSpec", "FOGSpec", "FOGUnit", "sagnac_scale_factor"]


def _default_noise() -> NoiseModel:
    # navigation-grade FOG (0.01 deg/h class): ARW 0.001 deg/sqrt(h), B 0.003 deg/h, bias 0.05 deg/h
    return NoiseModel.from_datasheet(angle_random_walk=0.001, bias_instability=0.003, bias=0.05)


@dataclass(frozen=True, slots=True, kw_only=True)
class FOGSpec:
    """Datasheet-level description of an IFOG for thermal tests (SI).

    Parameters
    ----------
    thermal : CoilThermalModel
        Coil (geometry, winding, optics, strain) in its housing.
    noise : NoiseModel
        Random rate noise and constant bias (IEEE 952 terms).
    sensor : TemperatureSensorSpec
        The logged coil temperature.
    diameter_tempco : float
        alpha_D, relative coil-diameter change per K of mean coil temperature [1/K]
        (potted coil on an aluminium spool; unverified, docs/physics.md 3.6).
    wavelength_tempco : float
        Relative source mean-wavelength change per K of housing temperature [1/K]
        (Er-doped fibre source, a few ppm/K; unverified).
    scale_factor_ref_temperature : float
        Temperature at which SF = SF0 [K].
    thermal_step : float
        Step of the heat-diffusion model [s].
    scheme : {"implicit", "crank-nicolson"}
        Time stepping of the heat-diffusion model.
    """

    thermal: CoilThermalModel = field(default_factory=CoilThermalModel)
    noise: NoiseModel = field(default_factory=_default_noise)
    sensor: TemperatureSensorSpec = field(default_factory=TemperatureSensorSpec)
    diameter_tempco: float = 5.0e-6
    wavelength_tempco: float = 4.0e-6
    scale_factor_ref_temperature: float = units.celsius(20.0)
    thermal_step: float = 5.0
    scheme: str = "implicit"

    def __post_init__(self) -> None:
        for name, kind in (
            ("thermal", CoilThermalModel),
            ("noise", NoiseModel),
            ("sensor", TemperatureSensorSpec),
        ):
            if not isinstance(getattr(self, name), kind):
                raise TypeError(
                    f"FOGSpec.{name} must be a {kind.__name__}; got {type(getattr(self, name)).__name__}"
                )
        for name in ("diameter_tempco", "wavelength_tempco"):
            v = getattr(self, name)
            if (
                isinstance(v, bool)
                or not isinstance(v, Real)
                or not (math.isfinite(float(v)) and abs(float(v)) < 1e-3)
            ):
                raise ValueError(f"FOGSpec.{name} must be finite with |value| < 1e-3 /K; got {v!r}")
        v = self.scale_factor_ref_temperature
        if not (isinstance(v, Real) and math.isfinite(v) and v > 0):
            raise ValueError(f"FOGSpec.scale_factor_ref_temperature must be > 0 K; got {v!r}")
        v = self.thermal_step
        if isinstance(v, bool) or not isinstance(v, Real) or not (math.isfinite(v) and v > 0):
            raise ValueError(f"FOGSpec.thermal_step must be > 0 s; got {v!r}")
        if self.scheme not in ("implicit", "crank-nicolson"):
            raise ValueError(
                f"FOGSpec.scheme must be 'implicit' or 'crank-nicolson'; got {self.scheme!r}"
            )

    @property
    def coil(self) -> CoilSpec:
        return self.thermal.coil

    @property
    def scale_factor(self) -> float:
        """Nominal Sagnac scale factor SF0 [s]."""
        c = self.coil
        return sagnac_scale_factor(c.length, c.diameter, c.wavelength)

    def scale_factor_ratio(self, coil_temperature, source_temperature):
        """SF(T)/SF0 [-] for mean coil and source (housing) temperatures [K]."""
        dc = np.asarray(coil_temperature, dtype=float) - self.scale_factor_ref_temperature
        ds = np.asarray(source_temperature, dtype=float) - self.scale_factor_ref_temperature
        return (
            (1 + self.coil.fibre_cte * dc)
            * (1 + self.diameter_tempco * dc)
            / (1 + self.wavelength_tempco * ds)
        )

    def realize(self, *, rng: np.random.Generator) -> FOGUnit:
        """One built unit: draws the winding defects (if any) with ``rng``."""
        if not isinstance(rng, np.random.Generator):
            raise TypeError(f"rng must be a numpy.random.Generator; got {type(rng).__name__}")
        return FOGUnit(spec=self, winding=self.coil.realize_winding(rng=rng))


@dataclass(frozen=True, slots=True, kw_only=True)
class FOGUnit:
    """One FOG: its spec and its drawn winding."""

    spec: FOGSpec
    winding: Winding

    def thermal_response(self, chamber: PiecewiseLinear, *, duration: float | None = None):
        """Thermal states and coil rate-error terms on the thermal grid.

        Returns
        -------
        t : ndarray, shape (k,)
            Times [s] (chamber.times[0] + i * thermal_step).
        x, xdot : ndarray, shape (k, layers + 2)
            [housing, spool, layers...] temperatures [K] and rates [K/s].
        terms : ShupeTerms
            Rate-error components [rad/s].

        Raises
        ------
        ValueError
            If the thermal step cannot resolve the chamber profile (see
            :meth:`gyrobench.sim.coil.CoilThermalModel.check_step`).
        """
        if not isinstance(chamber, PiecewiseLinear):
            raise TypeError(
                f"chamber must be a sim.environment.PiecewiseLinear; got {type(chamber).__name__}"
            )
        spec = self.spec
        dt = spec.thermal_step
        slopes = (
            np.diff(chamber.values) / np.diff(chamber.times)
            if len(chamber.times) > 1
            else np.zeros(1)
        )
        spec.thermal.check_step(dt, float(np.max(np.abs(slopes))))
        dur = chamber.duration if duration is None else float(duration)
        if not (math.isfinite(dur) and dur > 0):
            raise ValueError(f"duration must be > 0 s; got {dur!r}")
        k = int(math.ceil(dur / dt)) + 1
        t = chamber.times[0] + dt * np.arange(k)
        x, xdot = spec.thermal.network().simulate(chamber(t), dt, scheme=spec.scheme)
        terms = shupe_terms(spec.coil, self.winding.weights, x[:, 2:], xdot[:, 2:])
        return t, x, xdot, terms

    def simulate(
        self,
        chamber: PiecewiseLinear,
        *,
        fs: float,
        rng: np.random.Generator,
        true_rate: float | Callable[[NDArray[np.float64]], NDArray[np.float64]] = 0.0,
        duration: float | None = None,
        name: str = "fog_thermal",
        metadata: dict | None = None,
    ) -> Recording:
        """One chamber run logged at ``fs`` [Hz].

        Parameters
        ----------
        chamber : PiecewiseLinear
            Chamber temperature program [K] (``gyrobench.sim.environment.thermal_profile``).
        fs : float
            Output and sensor sample rate [Hz].
        rng : numpy.random.Generator
            Two child streams are spawned: rate noise, temperature-sensor noise.
        true_rate : float or callable
            True input rate [rad/s], constant or a function of time.
        duration : float, optional
            Run length [s]; default the chamber program's length.
        """
        if isinstance(fs, bool) or not isinstance(fs, Real) or not (math.isfinite(fs) and fs > 0):
            raise ValueError(f"fs must be a finite number > 0 Hz; got {fs!r}")
        if not isinstance(rng, np.random.Generator):
            raise TypeError(f"rng must be a numpy.random.Generator; got {type(rng).__name__}")
        spec = self.spec
        t_th, x, _, terms = self.thermal_response(chamber, duration=duration)
        dur = t_th[-1] - t_th[0] if duration is None else float(duration)
        n = int(math.floor(dur * fs + 1e-9))
        t0 = float(chamber.times[0])
        t = t0 + np.arange(n) / fs

        def at(y):
            return np.interp(t, t_th, y)

        housing = at(x[:, 0])
        layers = x[:, 2:]
        mean_coil = at(layers.mean(axis=1))
        loc = spec.sensor.location
        src = {
            "outer": layers[:, -1],
            "inner": layers[:, 0],
            "mean": layers.mean(axis=1),
            "spool": x[:, 1],
            "housing": x[:, 0],
        }[loc]
        sensor_true = at(src)
        rng_noise, rng_sensor = rng.spawn(2)

        if callable(true_rate):
            omega = np.asarray(true_rate(t), dtype=float).reshape(n)
        else:
            if not (isinstance(true_rate, Real) and math.isfinite(true_rate)):
                raise ValueError(
                    f"true_rate must be a finite number [rad/s] or a callable; got {true_rate!r}"
                )
            omega = np.full(n, float(true_rate))
        sf_err = omega * (spec.scale_factor_ratio(mean_coil, housing) - 1.0)
        parts = {
            "shupe": at(terms.shupe),
            "dndT_product": at(terms.dndT_product),
            "strain": at(terms.strain),
            "strain_product": at(terms.strain_product),
        }
        drift = parts["shupe"] + parts["dndT_product"] + parts["strain"]
        noise = spec.noise.generate(n, fs, rng=rng_noise, t0=t0)
        output = omega + sf_err + drift + noise
        logged_T = spec.sensor.read(sensor_true, rng=rng_sensor)

        rs = "rad/s"
        truth = {
            "rate": Channel(omega, rs, "true input rate"),
            "thermal_drift": Channel(drift, rs, "coil non-reciprocity (Shupe + strain), total"),
            "shupe": Channel(parts["shupe"], rs, "Shupe term with dn/dT at T0"),
            "dndT_product": Channel(parts["dndT_product"], rs, "T x dT term from dn/dT(T)"),
            "strain": Channel(
                parts["strain"], rs, "elasto-optic strain term (incl. its T x dT part)"
            ),
            "strain_product": Channel(
                parts["strain_product"], rs, "T x dT part of the strain term"
            ),
            "scale_factor_error": Channel(sf_err, rs, "true rate x (SF(T)/SF0 - 1)"),
            "noise": Channel(noise, rs, "random noise and constant bias"),
            "sensor_temperature": Channel(
                sensor_true, "K", f"noise-free temperature at the sensor ({loc})"
            ),
            "coil_mean_temperature": Channel(mean_coil, "K", "mean over the fibre layers"),
            "housing_temperature": Channel(housing, "K", "housing"),
            "chamber_temperature": Channel(chamber(t), "K", "chamber program"),
        }
        channels = {
            "rate": Channel(output, rs, "FOG output"),
            "coil_temperature": Channel(logged_T, "K", f"coil temperature sensor ({loc})"),
        }
        meta = {
            "model": "gyrobench.sim.fog.FOGUnit",
            "thermal_step_s": spec.thermal_step,
            "scheme": spec.scheme,
            "winding": self.winding.pattern,
            "winding_z0_m": self.winding.z0.tolist(),
            "scale_factor_s": spec.scale_factor,
            **(metadata or {}),
        }
        return Recording(
            fs=float(fs), channels=channels, truth=truth, t0=t0, metadata=meta, name=name
        )
