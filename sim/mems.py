"""High-range MEMS (Coriolis vibratory) gyro: saturating scale factor, thermal terms, noise.

Paper 001 (scenario ``mems_scale_factor``) no longer uses this module: it runs on the
resonator-physics model :mod:`gyrobench.sim.mems_resonator`, whose knee is the force-rebalance
authority. This phenomenological curve, and its defaults calibrated from paper 001 below, stay
for user code that wants a cheap saturating MEMS output (nothing in the package imports it now).

All parameters are in SI (see :mod:`gyrobench.sim.units`): rates [rad/s], temperature [K],
acceleration [m/s^2]. Field units enter only through :meth:`MemsSpec.from_datasheet`.

Output model (one sense axis), evaluated sample by sample::

    s(W)   = W                                          |W| <= Ok
           = sign(W) (Ok + Ws tanh((|W| - Ok)/Ws))      |W| >  Ok      (saturation knee)
    c(W)   = s(W) - c3 W^3                                             (small cubic)
    F_sf   = K0 (1 + e_on) (1 + s1 (T - T0)) (1 + (a/2) sign(W)) c(W) + d sign(W)
                                                               (scale-factor path, e_on per run)
    b(T)   = b0 + b_on + b1 (T - T0) + b2 (T - T0)^2                   (bias, b_on per run)
    v      = F_sf + b(T) + bg a_s + n(t)                               (+ g-sensitivity, noise)
    F      = q round(clip(v, -R, R) / q)                               (range, quantization)

W true rate [rad/s]; Ok knee rate and Ws knee width [rad/s]; c3 [s^2/rad^2];
K0 nominal scale factor [-] (output rad/s per input rad/s); e_on the turn-on
scale-factor error [-] drawn per run (per power-on) with standard deviation
``scale_factor_repeatability`` (IEEE Std 1431 scale-factor repeatability);
s1 scale-factor temperature coefficient [1/K]; a asymmetry [-] (K+ - K-)/K0; d rate-sign-dependent
offset [rad/s] (a step at zero rate: the dead-band/threshold behaviour of a
Coriolis vibratory gyro, IEEE Std 1431 "threshold"); b1 [rad/s/K], b2 [rad/s/K^2];
bg g-sensitivity [rad/s per m/s^2] times the acceleration a_s along the sense
axis [m/s^2]; n(t) the IEEE-952 noise of :class:`gyrobench.sim.noise.NoiseModel`; R the
measurement range [rad/s]; q the output resolution [rad/s] (0: no quantization).

One power-on of the gyro is a :class:`MemsUnit` drawn by :meth:`MemsSpec.realize`
(turn-on bias b_on and scale-factor error e_on); :func:`simulate_output` draws one
per call unless it is given a unit.

The knee is C2 at Ok (s' = 1 and s'' = 0 on both sides). Die temperature follows
first-order self-heating after power-on, T(t) = T_amb + dT (1 - exp(-t_on/tau)),
see :func:`die_temperature`.

Calibration of the defaults (docs/physics.md section 5, seed paper 001)
-----------------------------------------------------------------
Ok = 1800 deg/s; c3 = 1e-10 (deg/s)^-2; a = 5e-4; d = 2 deg/s; Ws chosen with
``scipy.optimize.brentq`` so that the noise-free curve on the paper's grid
(+-3600 deg/s, step 360) has K_n = 15.71 % (IEEE definition, F_m = max |F|):
Ws = 987.61 deg/s (F(3600) = 2735 deg/s). The rate-sign offset d makes the
low-rate part (|W| <= 1800 deg/s) nonlinear at the 1e-3 level the paper reports
(K_n about 9e-4) with a deviation concentrated at zero rate, so that the
interval nonlinearity of the paper's breakpoint heuristic falls with the
interval in the linear range. Calibration study (300-400 simulated rate tables
per setting, per-rate noise 0.01 deg/s): without d, with only the cubic and
noise or with an irregular ADC integral nonlinearity of 0.7 deg/s rms, the
heuristic found +-1800 in only 34-43 % of the tables (stopping early at
1440 or 1080 deg/s); with d = 2 deg/s it found +-1800 in 100 % (no INL), 96 %
(INL 0.3 deg/s) and 67 % (INL 0.7 deg/s). The paper's rule needs the interval
nonlinearity to fall, not merely stay small, below the knee; no INL is modelled.
Noise and thermal numbers are typical
industrial MEMS values (docs/physics.md 5; unverified datasheet defaults).

The scale-factor repeatability defaults to 0: neither the paper nor docs/physics.md
gives a value for this part, and 0 keeps the calibrated defaults and their
simulated tables unchanged (the turn-on stream draws e_on after b_on, so b_on is
the same whatever the repeatability). With 0, the scale factor still changes from
run to run through temperature (s1 x the ambient spread of a scenario). When
paper 001's scenario ran on this model it measured the effect on its claims at 0-1000 ppm.

References
----------
IEEE Std 1431-2004 (Coriolis vibratory gyros: scale factor, nonlinearity,
asymmetry, threshold); docs/physics.md section 5; Du, Su, Liu, Li (seed 001).

Examples
--------
>>> import numpy as np
>>> from gyrobench.sim import units
>>> spec = MemsSpec()
>>> w = units.deg_per_s(np.array([0.0, 1800.0, 3600.0]))
>>> np.round(units.to_deg_per_s(scale_factor_output(spec, w)), 1)
array([   0. , 1801.9, 2735.4])
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields

import numpy as np
from gyrobench.sim import units
from gyrobench.sim.noise import NoiseModel
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "MemsSpec",
    "MemsUnit",
    "MemsOutput",
    "scale_factor_output",
    "die_temperature",
    "simulate_output",
]

#: default knee width [deg/s], calibrated to K_n = 15.71 % (module docstring)
KNEE_WIDTH_DPS = 987.61


def _real(owner: str, name: str, v: float) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
        raise TypeError(f"{owner}.{name} must be a real number; got {v!r}")
    if not math.isfinite(v):
        raise ValueError(f"{owner}.{name} must be finite; got {v!r}")
    return float(v)


#: upper bound of MemsSpec.scale_factor_repeatability [-]: 10 % (1 + e_on > 0 at 10 sigma)
_MAX_SF_REPEATABILITY = 0.1

#: field -> (lower bound, inclusive?, unit) for the positivity checks of MemsSpec
_BOUNDS = {
    "scale_factor": (0.0, False, "[-]"),
    "knee_rate": (0.0, False, "rad/s"),
    "knee_width": (0.0, False, "rad/s"),
    "cubic": (0.0, True, "s^2/rad^2"),
    "measurement_range": (0.0, False, "rad/s"),
    "resolution": (0.0, True, "rad/s"),
    "bias_repeatability": (0.0, True, "rad/s"),
    "scale_factor_repeatability": (0.0, True, "[-]"),
    "reference_temperature": (0.0, False, "K"),
    "self_heating": (0.0, True, "K"),
    "self_heating_tau": (0.0, False, "s"),
}


@dataclass(frozen=True, slots=True, kw_only=True)
class MemsSpec:
    """A high-range MEMS gyro's datasheet budget; every field in SI.

    Parameters
    ----------
    scale_factor : float
        K0, nominal scale factor [-] (output rad/s per input rad/s), > 0.
    knee_rate : float
        Ok, end of the linear range [rad/s], > 0.
    knee_width : float
        Ws, width of the tanh saturation past the knee [rad/s], > 0.
    cubic : float
        c3, cubic coefficient [s^2/rad^2], >= 0 (a compressive term).
    asymmetry : float
        a = (K+ - K-)/K0 [-], |a| < 1.
    sign_offset : float
        d, rate-sign-dependent offset [rad/s] (step of 2d at zero rate).
    measurement_range : float
        R, the output is clipped to [-R, R] [rad/s], > 0.
    resolution : float
        q, output LSB [rad/s], >= 0 (0: not quantized).
    bias : float
        b0, bias at the reference temperature [rad/s].
    bias_repeatability : float
        Standard deviation of the turn-on bias b_on drawn per run [rad/s], >= 0.
    scale_factor_repeatability : float
        Standard deviation of the turn-on scale-factor error e_on drawn per run
        [-] (1 sigma, relative; a datasheet gives it in ppm), in [0, 0.1).
    bias_tc : float
        b1 [rad/s/K].
    bias_tc2 : float
        b2 [rad/s/K^2].
    scale_factor_tc : float
        s1 [1/K].
    reference_temperature : float
        T0 [K], > 0.
    g_sensitivity : float
        bg [rad/s per m/s^2] along the sense axis.
    self_heating : float
        Die temperature rise above ambient at steady state [K], >= 0.
    self_heating_tau : float
        Self-heating time constant after power-on [s], > 0.
    noise : NoiseModel
        The random part (ARW, bias instability, ...).
    """

    scale_factor: float = 1.0
    knee_rate: float = units.deg_per_s(1800.0)
    knee_width: float = units.deg_per_s(KNEE_WIDTH_DPS)
    cubic: float = 1e-10 / units.DEG**2
    asymmetry: float = 5e-4
    sign_offset: float = units.deg_per_s(2.0)
    measurement_range: float = units.deg_per_s(4000.0)
    resolution: float = units.deg_per_s(4000.0 / 2**15)
    bias: float = units.deg_per_s(0.5)
    bias_repeatability: float = units.deg_per_s(0.05)
    scale_factor_repeatability: float = 0.0
    bias_tc: float = units.deg_per_s(0.01)
    bias_tc2: float = units.deg_per_s(2e-4)
    scale_factor_tc: float = units.ppm(100.0)
    reference_temperature: float = units.celsius(25.0)
    g_sensitivity: float = units.deg_per_s(0.05) / units.G0
    self_heating: float = 5.0
    self_heating_tau: float = 600.0
    noise: NoiseModel = field(
        default_factory=lambda: NoiseModel(
            angle_random_walk=units.deg_per_s_per_sqrt_hz(0.015),
            bias_instability=units.deg_per_h(20.0),
        )
    )

    def __post_init__(self) -> None:
        for f in fields(self):
            if f.name == "noise":
                continue
            v = _real("MemsSpec", f.name, getattr(self, f.name))
            if f.name in _BOUNDS:
                lo, inclusive, unit = _BOUNDS[f.name]
                if v < lo or (v == lo and not inclusive):
                    op = ">=" if inclusive else ">"
                    raise ValueError(f"MemsSpec.{f.name} must be {op} {lo:g} {unit}; got {v!r}")
        if not self.scale_factor_repeatability < _MAX_SF_REPEATABILITY:
            raise ValueError(
                f"MemsSpec.scale_factor_repeatability must be < {_MAX_SF_REPEATABILITY:g} [-] "
                f"(1 + e_on stays positive at 10 sigma); got {self.scale_factor_repeatability!r}"
            )
        if not abs(self.asymmetry) < 1.0:
            raise ValueError(f"MemsSpec.asymmetry must satisfy |a| < 1 [-]; got {self.asymmetry!r}")
        if self.resolution >= self.measurement_range:
            raise ValueError(
                f"MemsSpec.resolution must be < measurement_range = {self.measurement_range!r} rad/s; "
                f"got {self.resolution!r}"
            )
        if not isinstance(self.noise, NoiseModel):
            raise TypeError(f"MemsSpec.noise must be a NoiseModel; got {type(self.noise).__name__}")

    def realize(self, *, rng: np.random.Generator) -> MemsUnit:
        """Draw one power-on of this gyro: turn-on bias and turn-on scale-factor error.

        Parameters
        ----------
        rng : numpy.random.Generator
            The turn-on stream. Two standard normals are drawn, in this order:
            b_on / ``bias_repeatability`` then e_on / ``scale_factor_repeatability``;
            both are always drawn, so each draw is the same whatever the other sigma.

        Returns
        -------
        MemsUnit

        Examples
        --------
        >>> unit = MemsSpec(scale_factor_repeatability=1e-4).realize(rng=np.random.default_rng(1))
        >>> round(unit.scale_factor_error * 1e6, 1)  # ppm
        82.2
        """
        if not isinstance(rng, np.random.Generator):
            raise TypeError(f"rng must be a numpy.random.Generator; got {type(rng).__name__}")
        z_bias, z_sf = rng.standard_normal(2)
        return MemsUnit(
            spec=self,
            turn_on_bias=float(self.bias_repeatability * z_bias),
            scale_factor_error=float(self.scale_factor_repeatability * z_sf),
        )

    @classmethod
    def from_datasheet(
        cls,
        *,
        scale_factor: float = 1.0,
        knee_rate_dps: float = 1800.0,
        knee_width_dps: float = KNEE_WIDTH_DPS,
        cubic_per_dps2: float = 1e-10,
        asymmetry_ppm: float = 500.0,
        sign_offset_dps: float = 2.0,
        range_dps: float = 4000.0,
        resolution_bits: int | None = 16,
        bias_dps: float = 0.5,
        bias_repeatability_dps: float = 0.05,
        scale_factor_repeatability_ppm: float = 0.0,
        bias_tc_dps_per_k: float = 0.01,
        bias_tc2_dps_per_k2: float = 2e-4,
        scale_factor_tc_ppm_per_k: float = 100.0,
        reference_temperature_c: float = 25.0,
        g_sensitivity_dps_per_g: float = 0.05,
        self_heating_k: float = 5.0,
        self_heating_tau_s: float = 600.0,
        noise_density_dps_rthz: float = 0.015,
        bias_instability_dph: float = 20.0,
    ) -> MemsSpec:
        """Build a spec from field units (deg/s, ppm, degC, g, bits).

        ``scale_factor_repeatability_ppm`` is the 1-sigma turn-on-to-turn-on
        scale-factor repeatability [ppm]. ``resolution_bits`` sets q = 2 R / 2^bits
        (None: no quantization); the noise density [deg/s/sqrt(Hz)] is the IEEE
        two-sided value (ADEV at 1 s).
        """
        if resolution_bits is not None and (
            isinstance(resolution_bits, bool)
            or not isinstance(resolution_bits, int)
            or resolution_bits < 2
        ):
            raise ValueError(
                f"resolution_bits must be an integer >= 2 or None; got {resolution_bits!r}"
            )
        q = 0.0 if resolution_bits is None else 2.0 * range_dps / 2**resolution_bits
        return cls(
            scale_factor=scale_factor,
            knee_rate=units.deg_per_s(knee_rate_dps),
            knee_width=units.deg_per_s(knee_width_dps),
            cubic=cubic_per_dps2 / units.DEG**2,
            asymmetry=units.ppm(asymmetry_ppm),
            sign_offset=units.deg_per_s(sign_offset_dps),
            measurement_range=units.deg_per_s(range_dps),
            resolution=units.deg_per_s(q),
            bias=units.deg_per_s(bias_dps),
            bias_repeatability=units.deg_per_s(bias_repeatability_dps),
            scale_factor_repeatability=units.ppm(scale_factor_repeatability_ppm),
            bias_tc=units.deg_per_s(bias_tc_dps_per_k),
            bias_tc2=units.deg_per_s(bias_tc2_dps_per_k2),
            scale_factor_tc=units.ppm(scale_factor_tc_ppm_per_k),
            reference_temperature=units.celsius(reference_temperature_c),
            g_sensitivity=units.deg_per_s(g_sensitivity_dps_per_g) / units.G0,
            self_heating=self_heating_k,
            self_heating_tau=self_heating_tau_s,
            noise=NoiseModel(
                angle_random_walk=units.deg_per_s_per_sqrt_hz(noise_density_dps_rthz),
                bias_instability=units.deg_per_h(bias_instability_dph),
            ),
        )


@dataclass(frozen=True, slots=True, kw_only=True)
class MemsUnit:
    """One power-on of a MEMS gyro: its spec and the turn-on values drawn for this run.

    Parameters
    ----------
    spec : MemsSpec
        The datasheet budget the unit was drawn from.
    turn_on_bias : float
        b_on [rad/s].
    scale_factor_error : float
        e_on [-]: the scale-factor path is multiplied by 1 + e_on; > -1.
    """

    spec: MemsSpec
    turn_on_bias: float = 0.0
    scale_factor_error: float = 0.0

    def __post_init__(self) -> None:
        if not isinstance(self.spec, MemsSpec):
            raise TypeError(f"MemsUnit.spec must be a MemsSpec; got {type(self.spec).__name__}")
        _real("MemsUnit", "turn_on_bias", self.turn_on_bias)
        e = _real("MemsUnit", "scale_factor_error", self.scale_factor_error)
        if not e > -1.0:
            raise ValueError(f"MemsUnit.scale_factor_error must be > -1 [-]; got {e!r}")


def _knee(spec: MemsSpec, w: NDArray[np.float64]) -> NDArray[np.float64]:
    a = np.abs(w)
    ok, ws = spec.knee_rate, spec.knee_width
    s = w.copy()
    m = a > ok  # tanh only where needed: most samples of a rate table are not past the knee
    s[m] = np.sign(w[m]) * (ok + ws * np.tanh((a[m] - ok) / ws))
    return s


def scale_factor_output(
    spec: MemsSpec | MemsUnit, rate: ArrayLike, temperature: ArrayLike | None = None
) -> NDArray[np.float64]:
    """Deterministic scale-factor path F_sf(W, T) [rad/s] (no bias, noise, range or quantization).

    Parameters
    ----------
    spec : MemsSpec or MemsUnit
        A spec gives the nominal path (e_on = 0); a unit its own (1 + e_on) K0.
    rate : array_like
        True rate W [rad/s].
    temperature : array_like, optional
        Die temperature T [K] (broadcast with ``rate``); default the reference T0.

    Returns
    -------
    ndarray
        K0 (1 + e_on) (1 + s1 (T - T0)) (1 + (a/2) sign(W)) (s(W) - c3 W^3) + d sign(W) [rad/s].
    """
    e_on = 0.0
    if isinstance(spec, MemsUnit):
        e_on = spec.scale_factor_error
        spec = spec.spec
    w = np.asarray(rate, dtype=float)
    t = spec.reference_temperature if temperature is None else np.asarray(temperature, dtype=float)
    sgn = np.sign(w)
    k = (spec.scale_factor * (1.0 + e_on)) * (
        1.0 + spec.scale_factor_tc * (t - spec.reference_temperature)
    )
    return (
        k * (1.0 + 0.5 * spec.asymmetry * sgn) * (_knee(spec, w) - spec.cubic * (w * w * w))
        + spec.sign_offset * sgn
    )


def die_temperature(
    spec: MemsSpec, ambient: ArrayLike, time_since_power_on: ArrayLike
) -> NDArray[np.float64]:
    """Die temperature [K] with first-order self-heating after power-on.

    T(t) = T_amb + dT (1 - exp(-t / tau)), t = time since power-on [s] (>= 0),
    dT = ``spec.self_heating`` [K], tau = ``spec.self_heating_tau`` [s].
    """
    t = np.asarray(time_since_power_on, dtype=float)
    bad = ~(t >= 0)  # also catches NaN
    if np.any(bad):
        i = int(np.flatnonzero(bad.ravel())[0])
        raise ValueError(
            f"time_since_power_on must be >= 0 s; got {float(t.ravel()[i])!r} at index {i}"
        )
    return np.asarray(ambient, dtype=float) + spec.self_heating * -np.expm1(
        -t / spec.self_heating_tau
    )


@dataclass(frozen=True, slots=True)
class MemsOutput:
    """Gyro output [rad/s] and its exact decomposition (``output = rate + sum(components)``).

    ``components``: ``scale_factor`` (F_sf - W), ``bias`` (b(T) incl. the turn-on
    bias), ``g_sensitivity``, ``noise``, ``range_quantization`` (clip + rounding).
    ``unit`` is the power-on simulated (drawn for this run unless given);
    ``turn_on_bias`` [rad/s] and ``scale_factor_error`` [-] are its values.
    """

    output: NDArray[np.float64]
    components: dict[str, NDArray[np.float64]]
    unit: MemsUnit

    @property
    def turn_on_bias(self) -> float:
        """b_on of this run [rad/s]."""
        return self.unit.turn_on_bias

    @property
    def scale_factor_error(self) -> float:
        """e_on of this run [-]."""
        return self.unit.scale_factor_error


def simulate_output(
    spec: MemsSpec | MemsUnit,
    rate: ArrayLike,
    *,
    fs: float,
    temperature: ArrayLike,
    acceleration: ArrayLike = 0.0,
    rng: np.random.Generator,
) -> MemsOutput:
    """One run's output samples for true rate samples ``rate`` [rad/s] at ``fs`` [Hz].

    Parameters
    ----------
    spec : MemsSpec or MemsUnit
        A spec: a unit is drawn for this run (``spec.realize`` on the turn-on
        stream). A unit: simulated as given (the turn-on stream is not used).
    rate : array_like, shape (n,)
        True rate along the sense axis [rad/s].
    fs : float
        Sample rate [Hz], > 0.
    temperature : array_like
        Die temperature [K], scalar or shape (n,).
    acceleration : array_like
        Specific force along the sense axis [m/s^2], scalar or shape (n,).
    rng : numpy.random.Generator
        Two child streams are spawned: turn-on (b_on, e_on), noise.

    Returns
    -------
    MemsOutput
    """
    if not isinstance(spec, (MemsSpec, MemsUnit)):
        raise TypeError(f"spec must be a MemsSpec or MemsUnit; got {type(spec).__name__}")
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator; got {type(rng).__name__}")
    w = np.asarray(rate, dtype=float)
    if w.ndim != 1 or w.size == 0 or not np.all(np.isfinite(w)):
        raise ValueError(
            f"rate must be a non-empty 1-D array of finite values [rad/s]; got shape {w.shape}"
        )
    if isinstance(fs, bool) or not (isinstance(fs, (int, float)) and math.isfinite(fs) and fs > 0):
        raise ValueError(f"fs must be a finite number > 0 Hz; got {fs!r}")
    n = w.size
    temp = np.broadcast_to(np.asarray(temperature, dtype=float), (n,))
    acc = np.broadcast_to(np.asarray(acceleration, dtype=float), (n,))
    bad = ~(np.isfinite(temp) & (temp > 0))
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(
            f"temperature must be finite and > 0 K; got {float(temp[i])!r} at index {i}"
        )
    bad = ~np.isfinite(acc)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"acceleration must be finite [m/s^2]; got {float(acc[i])!r} at index {i}")
    r_on, r_noise = rng.spawn(2)
    unit = spec if isinstance(spec, MemsUnit) else spec.realize(rng=r_on)
    spec = unit.spec
    dt = temp - spec.reference_temperature
    sf = scale_factor_output(unit, w, temp) - w
    bias = spec.bias + unit.turn_on_bias + spec.bias_tc * dt + spec.bias_tc2 * dt**2
    gsens = spec.g_sensitivity * acc
    noise = spec.noise.generate(n, fs, rng=r_noise)
    v = w + sf + bias + gsens + noise
    out = np.clip(v, -spec.measurement_range, spec.measurement_range)
    if spec.resolution > 0:
        out = spec.resolution * np.round(out / spec.resolution)
    comps = {
        "scale_factor": sf,
        "bias": np.array(bias, dtype=float),
        "g_sensitivity": np.array(gsens, dtype=float),
        "noise": noise,
        "range_quantization": out - v,
    }
    return MemsOutput(out, comps, unit)
