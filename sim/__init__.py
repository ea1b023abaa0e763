"""The physics: what a gyro outputs in a given environment. SI units inside.

One module per physical effect or device; this package exports the names a user reaches for
first (loaded on first use). Everything else is public in its module.

Modules
-------
noise
    the IEEE Std 952 noise terms (Q, N, B, K, R), Gauss-Markov terms and sinusoids, streamed.
environment, earth, shaker
    rate and temperature histories, the Earth's rate at a site, shaker vibration profiles.
sensor, parts
    the device interface (a spec, a drawn unit, ``simulate(environment, fs=, rng=)``) and the
    built-in datasheet parts.
fog_loop, fog_optics, fog2d, fiber_strain, mount_coning
    the closed-loop interferometric FOG, its optical noise budget, the FOG on its coil in
    (r, z), strain along the fibre under vibration, mount coning.
coil2d, coil_materials, coil_pack, coil_heat, coil_winding
    the fibre coil: its materials, the pack as a composite, heat conduction in (r, z), the
    winding; the Shupe and T x dT rate errors.
mems_resonator, mems_nonlinear
    the vibratory MEMS gyro from resonator physics; a smooth scale-factor nonlinearity.
rlg, rlg_cavity
    the dithered ring laser gyro; its cavity model (backscatter, path-length control, mode
    hops, Langmuir flow).
trajectory, imu
    rigid-body motion of an IMU block on the Earth; a three-axis IMU (gyro and accelerometer
    triads) driven by it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from gyrobench.base.lazy import attach

#: public name -> the submodule that defines it (imported on first access, so importing
#: this package costs nothing until a name is used)
_LAZY: dict[str, str] = {
    "NoiseModel": "gyrobench.sim.noise",
    "NoiseStream": "gyrobench.sim.noise",
    "GaussMarkov": "gyrobench.sim.noise",
    "Sinusoid": "gyrobench.sim.noise",
    "PiecewiseLinear": "gyrobench.sim.environment",
    "Ramp": "gyrobench.sim.environment",
    "Soak": "gyrobench.sim.environment",
    "RateSteps": "gyrobench.sim.environment",
    "thermal_profile": "gyrobench.sim.environment",
    "rate_steps": "gyrobench.sim.environment",
    "EARTH_RATE": "gyrobench.sim.earth",
    "Site": "gyrobench.sim.earth",
    "sensed_earth_rate": "gyrobench.sim.earth",
    "SineSweep": "gyrobench.sim.shaker",
    "FixedSine": "gyrobench.sim.shaker",
    "RandomVibration": "gyrobench.sim.shaker",
    "interval_mean_acceleration": "gyrobench.sim.shaker",
    "Environment": "gyrobench.sim.sensor",
    "Sensor": "gyrobench.sim.sensor",
    "SensorUnit": "gyrobench.sim.sensor",
    "LoopSpec": "gyrobench.sim.fog_loop",
    "ClosedLoopFOG": "gyrobench.sim.fog_loop",
    "sagnac_scale_factor": "gyrobench.sim.fog_loop",
    "FOG2DSpec": "gyrobench.sim.fog2d",
    "FOG2DUnit": "gyrobench.sim.fog2d",
    "Coil2DSpec": "gyrobench.sim.coil2d",
    "Coil2D": "gyrobench.sim.coil2d",
    "MemsResonatorSpec": "gyrobench.sim.mems_population",
    "MemsResonator": "gyrobench.sim.mems_resonator",
    "RLGSpec": "gyrobench.sim.rlg",
    "RLGUnit": "gyrobench.sim.rlg",
    "CavityRLGSpec": "gyrobench.sim.rlg_cavity",
    "CavityRLG": "gyrobench.sim.rlg_cavity",
}

__all__ = [
    "NoiseModel",
    "NoiseStream",
    "GaussMarkov",
    "Sinusoid",
    "PiecewiseLinear",
    "Ramp",
    "Soak",
    "RateSteps",
    "thermal_profile",
    "rate_steps",
    "EARTH_RATE",
    "Site",
    "sensed_earth_rate",
    "SineSweep",
    "FixedSine",
    "RandomVibration",
    "interval_mean_acceleration",
    "Environment",
    "Sensor",
    "SensorUnit",
    "LoopSpec",
    "ClosedLoopFOG",
    "sagnac_scale_factor",
    "FOG2DSpec",
    "FOG2DUnit",
    "Coil2DSpec",
    "Coil2D",
    "MemsResonatorSpec",
    "MemsResonator",
    "RLGSpec",
    "RLGUnit",
    "CavityRLGSpec",
    "CavityRLG",
]

if TYPE_CHECKING:  # pragma: no cover - for type checkers and IDEs only
    from gyrobench.sim.coil2d import Coil2D as Coil2D
    from gyrobench.sim.coil2d import Coil2DSpec as Coil2DSpec
    from gyrobench.sim.earth import EARTH_RATE as EARTH_RATE
    from gyrobench.sim.earth import Site as Site
    from gyrobench.sim.earth import sensed_earth_rate as sensed_earth_rate
    from gyrobench.sim.environment import PiecewiseLinear as PiecewiseLinear
    from gyrobench.sim.environment import Ramp as Ramp
    from gyrobench.sim.environment import RateSteps as RateSteps
    from gyrobench.sim.environment import Soak as Soak
    from gyrobench.sim.environment import rate_steps as rate_steps
    from gyrobench.sim.environment import thermal_profile as thermal_profile
    from gyrobench.sim.fog2d import FOG2DSpec as FOG2DSpec
    from gyrobench.sim.fog2d import FOG2DUnit as FOG2DUnit
    from gyrobench.sim.fog_loop import ClosedLoopFOG as ClosedLoopFOG
    from gyrobench.sim.fog_loop import LoopSpec as LoopSpec
    from gyrobench.sim.fog_loop import sagnac_scale_factor as sagnac_scale_factor
    from gyrobench.sim.mems_population import MemsResonatorSpec as MemsResonatorSpec
    from gyrobench.sim.mems_resonator import MemsResonator as MemsResonator
    from gyrobench.sim.noise import GaussMarkov as GaussMarkov
    from gyrobench.sim.noise import NoiseModel as NoiseModel
    from gyrobench.sim.noise import NoiseStream as NoiseStream
    from gyrobench.sim.noise import Sinusoid as Sinusoid
    from gyrobench.sim.rlg import RLGSpec as RLGSpec
    from gyrobench.sim.rlg import RLGUnit as RLGUnit
    from gyrobench.sim.rlg_cavity import CavityRLG as CavityRLG
    from gyrobench.sim.rlg_cavity import CavityRLGSpec as CavityRLGSpec
    from gyrobench.sim.sensor import Environment as Environment
    from gyrobench.sim.sensor import Sensor as Sensor
    from gyrobench.sim.sensor import SensorUnit as SensorUnit
    from gyrobench.sim.shaker import FixedSine as FixedSine
    from gyrobench.sim.shaker import RandomVibration as RandomVibration
    from gyrobench.sim.shaker import SineSweep as SineSweep
    from gyrobench.sim.shaker import interval_mean_acceleration as interval_mean_acceleration


__getattr__, __dir__ = attach(__name__, _LAZY)
