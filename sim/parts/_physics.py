"""A built-in RLG part mapped onto the ring-laser-gyro model: the ARW solved for the lock-in rate.

The statistical RLG model (:mod:`gyrobench.sim.rlg`) sets the angle random walk by dithering
through lock-in, N = Omega_L sqrt((1 + j^2) / (2 pi K Omega_D)) (:func:`gyrobench.sim.rlg.dither_arw`,
docs/physics.md 6.3; K the scale factor [counts/rad] of the cavity geometry, Omega_D the
dither peak rate, j its amplitude jitter). With the model's default cavity and dither, a
datasheet ARW N_s fixes the lock-in rate

    Omega_L = N_s / sqrt((1 + j^2) / (2 pi K Omega_D)),

the one physical parameter the figure sets; B is the model's flicker term, set to the sheet's
B (:meth:`Datasheet.bias_instability`); the turn-on bias spread is the sheet's bias
repeatability (0 when not given). What the sheet does not give is left out, not invented:
no lock-in spread, no thermal mechanisms (sizes 0). The count quantization of the default
cavity (pulse weight 1.61 arcsec) adds the model's Q term. The FOG and MEMS models have no
such one-parameter solve (:data:`gyrobench.sim.parts.PHYSICS_MAPPING`).
"""

from __future__ import annotations

import math

from gyrobench.sim import units
from gyrobench.sim.parts._part import Datasheet
from gyrobench.sim.rlg import RLGSpec, ThermalBias

__all__ = ["rlg_spec"]


def rlg_spec(datasheet: Datasheet) -> RLGSpec:
    """The :class:`RLGSpec` of an RLG part: lock-in rate from the sheet's ARW (module docstring).

    Raises
    ------
    TypeError
        ``datasheet`` is not a Datasheet.
    ValueError
        The part is not an RLG, or the solved lock-in rate is not below the dither peak rate.
    """
    if not isinstance(datasheet, Datasheet):
        raise TypeError(f"datasheet must be a Datasheet; got {type(datasheet).__name__}")
    if datasheet.technology != "RLG":
        raise ValueError(f"rlg_spec needs an RLG part; {datasheet.name!r} is {datasheet.technology}")
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
