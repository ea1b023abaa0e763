"""FOG output under vibration: structural modes, rectified bias, noise growth, aliased tones, on/off transients.

All parameters are in SI (rad/s, m/s^2, Hz, s).

Paper 000 (``scenarios.fog_vibration``) no longer uses this model: it runs on the closed-loop
FOG (:class:`gyrobench.sim.fog_loop.ClosedLoopFOG`) whose vibration error comes from strain
along the fibre (:mod:`gyrobench.sim.fiber_strain`). This phenomenological model is kept for
user code.

Physical picture (docs/physics.md 4): the table acceleration a(t) excites structural
modes of the coil, its potting and the housing. Mode k responds as a base-excited
second-order system with unit static gain

    H_k(s) = w_k^2 / (s^2 + s w_k/Q_k + w_k^2),   w_k = 2 pi f_k,
    |H_k(f)| = 1 / sqrt((1 - (f/f_k)^2)^2 + (f/(Q_k f_k))^2),

so x_k = H_k * a [m/s^2] is the modal acceleration. The gyro's rate error is

    tone        w_t(t) = sum_k g_k x_k(t)                       (linear pick-up: strain-rate
                                                                  non-reciprocity, docs/physics.md 3.5)
    rectified   w_r(t) = sum_k 2 c_k x_k(t)^2 + c_lin (pi/2) |a(t)|
                mean over a cycle of a sine of amplitude a at f:
                bias_vib(f, a) = sum_k c_k a^2 |H_k(f)|^2 + c_lin a
    noise       extra white (and flicker) rate noise during vibration, so that the total ARW is
                N(f, a) = N_0 sqrt(1 + sum_k d_k E_k / a_ref^2),  E_k = <2 x_k^2> = a^2 |H_k|^2
                and, when B_0 > 0, the bias instability grows by the same factor: the extra
                noise is u(t) (white N_0 + flicker B_0), u = sqrt(sum_k d_k E_k)/a_ref
    heating     w_h = h * LP(sum_k E_k; T_h): first-order lag (time constant T_h) of the
                dissipated modal energy: a slow drift while shaking that relaxes after
    transient   w_tr = kappa * (P - LP(P; T_tr)), P = <2 a^2> (the table's acceleration power,
                a^2 for a sine): a first-order high-pass of the vibration level: a spike at
                switch-on and an opposite one at switch-off, decaying with T_tr (the settling
                of coil stress when the load changes). Driven by the table level, not the
                modal energy, so sweeping through a resonance at a constant level adds none.

plus the static noise of :class:`gyrobench.sim.noise.NoiseModel` (Q, N, B, K, R) at the output rate.

Sampling
--------
The modes, the tone and the rectification (which makes 2f components) are
simulated at ``physics_rate`` during vibration and after it (ring-down); the
output is then decimated by M = physics_rate/output_rate (an integer) as a real
FOG's digital output is:

* ``decimation="integrate"`` (default): integrate-and-dump. A closed-loop FOG
  accumulates the feedback phase and outputs the angle increment of each output
  period divided by the period, i.e. the block mean of M physics samples. A tone
  at f is aliased to f_a = |f - fs_out round(f/fs_out)| with the gain of the
  M-point moving average, |sin(pi f M/fs) / (M sin(pi f/fs))| (fs = physics rate).
* ``decimation="sample"``: every M-th physics sample (a point-sampled output);
  a tone is aliased to f_a at full amplitude.

The energies E_k, the noise growth, heating and transient are slow and are
computed at the output rate from the block means of 2 x_k^2.

The modal filters are discretised by the bilinear transform with the analog
frequency prewarped to f_k (the discrete resonance is at f_k exactly); the
methods :meth:`FogVibrationModel.rectified_bias` etc. evaluate the *discrete*
filters, so they are the exact steady state of what :meth:`simulate` produces.

The physics rate must be at least 4x the highest drive frequency, so that the
rectified 2f component is below the physics Nyquist frequency.

References
----------
docs/physics.md section 4; seed paper 000 (Fang, Shen, Chen); IEEE Std 952-1997
(FOG test procedures, vibration sensitivity); "Analysis of vibration error in
fiber optic gyroscope" (abstract, mechanisms). Parameters are phenomenological
(unverified): tune them to a measured unit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from gyrobench.sim.noise import NoiseModel
from gyrobench.sim.recording import Channel, Recording, package_version
from gyrobench.sim.shaker import Phased, VibrationProfile
from numpy.typing import ArrayLike, NDArray
from scipy import signal

__all__ = ["StructuralMode", "FogVibrationModel", "alias_frequency", "decimate", "moving_average_gain"]


def _real(owner: str, name: str, v, unit: str, *, positive: bool = False, nonneg: bool = False) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
        raise TypeError(f"{owner}.{name} must be a real number [{unit}]; got {v!r}")
    v = float(v)
    if not math.isfinite(v):
        raise ValueError(f"{owner}.{name} must be finite [{unit}]; got {v!r}")
    if positive and v <= 0:
        raise ValueError(f"{owner}.{name} must be > 0 {unit}; got {v!r}")
    if nonneg and v < 0:
        raise ValueError(f"{owner}.{name} must be >= 0 {unit}; got {v!r}")
    return v


def alias_frequency(f: ArrayLike, fs: float) -> NDArray[np.float64]:
    """Apparent frequency [Hz] of a tone at ``f`` [Hz] sampled at ``fs`` [Hz]: |f - fs round(f/fs)|, in [0, fs/2]."""
    f = np.asarray(f, dtype=float)
    return np.abs(f - fs * np.round(f / fs))


def moving_average_gain(f: ArrayLike, m: int, fs: float) -> NDArray[np.float64]:
    """|sin(pi f m/fs) / (m sin(pi f/fs))|: amplitude gain of an m-point block mean at ``fs`` [Hz] (1 at f = 0)."""
    f = np.asarray(f, dtype=float)
    x = np.pi * f / fs
    num = np.sin(m * x)
    den = m * np.sin(x)
    with np.errstate(invalid="ignore", divide="ignore"):
        g = np.where(np.abs(den) < 1e-300, 1.0, np.abs(num / np.where(den == 0, 1.0, den)))
    return g


def decimate(x: NDArray[np.float64], factor: int, method: str = "integrate") -> NDArray[np.float64]:
    """Decimate by an integer ``factor``: block mean (``"integrate"``) or every factor-th sample (``"sample"``).

    ``len(x)`` must be a multiple of ``factor``.
    """
    if method not in ("integrate", "sample"):
        raise ValueError(f"decimation must be one of ['integrate', 'sample']; got {method!r}")
    if len(x) % factor:
        raise ValueError(f"len(x) = {len(x)} must be a multiple of the decimation factor {factor}")
    if method == "sample":
        return x[::factor].copy()
    return x.reshape(-1, factor).mean(axis=1)


@dataclass(frozen=True, slots=True, kw_only=True)
class StructuralMode:
    """One structural mode of the coil / mount and how it couples into the rate output.

    Parameters
    ----------
    frequency : float
        Natural frequency f_k [Hz], > 0.
    quality : float
        Quality factor Q_k [-], > 0.5 (typically 5-50).
    rectification : float
        c_k [(rad/s) / (m/s^2)^2]: steady bias c_k a^2 |H_k|^2 (may be negative).
    tone_gain : float
        g_k [(rad/s) / (m/s^2)]: rate error at the drive frequency per unit modal acceleration.
    noise_weight : float
        d_k [-], >= 0: ARW inflation weight.
    """

    frequency: float
    quality: float
    rectification: float = 0.0
    tone_gain: float = 0.0
    noise_weight: float = 0.0

    def __post_init__(self) -> None:
        o = "StructuralMode"
        _real(o, "frequency", self.frequency, "Hz", positive=True)
        q = _real(o, "quality", self.quality, "-", positive=True)
        if q <= 0.5:
            raise ValueError(f"{o}.quality must be > 0.5 (an underdamped mode); got {self.quality!r}")
        _real(o, "rectification", self.rectification, "(rad/s)/(m/s^2)^2")
        _real(o, "tone_gain", self.tone_gain, "(rad/s)/(m/s^2)")
        _real(o, "noise_weight", self.noise_weight, "-", nonneg=True)

    def response(self, f: ArrayLike, fs: float | None = None) -> NDArray[np.complex128]:
        """H_k at ``f`` [Hz]: the analog transfer function, or the discrete filter at rate ``fs`` [Hz]."""
        f = np.asarray(f, dtype=float)
        if fs is None:
            r = f / self.frequency
            return np.asarray(1.0 / (1.0 - r**2 + 1j * r / self.quality), dtype=np.complex128)
        b, a = self.filter(fs)
        _, h = signal.freqz(b, a, worN=np.atleast_1d(f), fs=fs)
        return h.reshape(f.shape)

    def filter(self, fs: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Discrete (b, a) at ``fs`` [Hz]: bilinear transform with prewarping at f_k (unit DC gain)."""
        if self.frequency >= fs / 2:
            raise ValueError(
                f"StructuralMode.frequency = {self.frequency!r} Hz must be below the physics Nyquist {fs / 2!r} Hz"
            )
        wp = 2.0 * fs * math.tan(math.pi * self.frequency / fs)  # prewarped [rad/s]
        b, a = signal.bilinear([wp**2], [1.0, wp / self.quality, wp**2], fs=fs)
        return b, a


@dataclass(frozen=True, slots=True, kw_only=True)
class FogVibrationModel:
    """A FOG on a shaker: static noise plus the structural-mode vibration response.

    Parameters
    ----------
    noise : NoiseModel
        Static noise (Q, N, B, K, R, ...) [SI], generated at ``output_rate``.
    modes : tuple of StructuralMode
        Structural modes.
    linear_g : float
        c_lin [(rad/s)/(m/s^2)]: bias proportional to the acceleration amplitude
        (rectification by a one-sided nonlinearity, (pi/2)|a| averages to a).
    noise_ref : float
        a_ref [m/s^2] of the ARW inflation, > 0.
    noise_arw : float or None
        N_0 [rad/sqrt(s)] that the inflation multiplies; None = ``noise.angle_random_walk``.
    noise_bias_instability : float or None
        B_0 [rad/s] of the flicker part of the inflation (same band as ``noise``);
        None = ``noise.bias_instability``; 0 = white inflation only.
    heating_gain : float
        h [(rad/s)/(m/s^2)^2]: slow drift per unit modal energy.
    heating_time : float
        T_h [s], > 0.
    transient_gain : float
        kappa [(rad/s)/(m/s^2)^2]: on/off transient per unit change of the table's acceleration power.
    transient_time : float
        T_tr [s], > 0.
    physics_rate : float
        Rate of the vibration physics [Hz]; an integer multiple of ``output_rate``.
    output_rate : float
        Gyro output data rate [Hz].
    decimation : {"integrate", "sample"}
        How the digital output is formed (module docstring).
    """

    noise: NoiseModel = field(default_factory=NoiseModel)
    modes: tuple[StructuralMode, ...] = ()
    linear_g: float = 0.0
    noise_ref: float = 9.80665
    noise_arw: float | None = None
    noise_bias_instability: float | None = None
    heating_gain: float = 0.0
    heating_time: float = 300.0
    transient_gain: float = 0.0
    transient_time: float = 1.0
    physics_rate: float = 4000.0
    output_rate: float = 400.0
    decimation: Literal["integrate", "sample"] = "integrate"

    def __post_init__(self) -> None:
        o = "FogVibrationModel"
        if not isinstance(self.noise, NoiseModel):
            raise TypeError(f"{o}.noise must be a NoiseModel; got {type(self.noise).__name__}")
        if not isinstance(self.modes, tuple) or not all(isinstance(m, StructuralMode) for m in self.modes):
            raise TypeError(f"{o}.modes must be a tuple of StructuralMode; got {self.modes!r}")
        _real(o, "linear_g", self.linear_g, "(rad/s)/(m/s^2)")
        _real(o, "noise_ref", self.noise_ref, "m/s^2", positive=True)
        if self.noise_arw is not None:
            _real(o, "noise_arw", self.noise_arw, "rad/sqrt(s)", nonneg=True)
        if self.noise_bias_instability is not None:
            _real(o, "noise_bias_instability", self.noise_bias_instability, "rad/s", nonneg=True)
        _real(o, "heating_gain", self.heating_gain, "(rad/s)/(m/s^2)^2")
        _real(o, "heating_time", self.heating_time, "s", positive=True)
        _real(o, "transient_gain", self.transient_gain, "(rad/s)/(m/s^2)^2")
        _real(o, "transient_time", self.transient_time, "s", positive=True)
        fp = _real(o, "physics_rate", self.physics_rate, "Hz", positive=True)
        fo = _real(o, "output_rate", self.output_rate, "Hz", positive=True)
        ratio = fp / fo
        if abs(ratio - round(ratio)) > 1e-9 * ratio or round(ratio) < 1:
            raise ValueError(
                f"{o}.physics_rate must be an integer multiple of output_rate = {fo!r} Hz; got {fp!r} Hz"
            )
        if self.decimation not in ("integrate", "sample"):
            raise ValueError(f"{o}.decimation must be one of ['integrate', 'sample']; got {self.decimation!r}")
        for k, m in enumerate(self.modes):
            if m.frequency >= fp / 2:
                raise ValueError(f"{o}.modes[{k}].frequency = {m.frequency!r} Hz must be below physics_rate/2 = {fp / 2!r} Hz")

    # ------------------------------------------------------------------ properties
    @property
    def factor(self) -> int:
        """Decimation factor M = physics_rate / output_rate."""
        return int(round(self.physics_rate / self.output_rate))

    @property
    def max_drive_frequency(self) -> float:
        """Highest drive frequency [Hz] the physics rate resolves: physics_rate/4 (2f below Nyquist)."""
        return self.physics_rate / 4.0

    def _arw0(self) -> float:
        return self.noise.angle_random_walk if self.noise_arw is None else self.noise_arw

    def _bi0(self) -> float:
        return self.noise.bias_instability if self.noise_bias_instability is None else self.noise_bias_instability

    def _check_amp(self, a: ArrayLike) -> NDArray[np.float64]:
        a = np.asarray(a, dtype=float)
        if np.any(~np.isfinite(a)) or np.any(a < 0):
            raise ValueError(f"acceleration amplitude must be finite and >= 0 m/s^2; got {a!r}")
        return a

    # ------------------------------------------------------------------ steady state
    def modal_energy(self, f: ArrayLike, a: ArrayLike) -> NDArray[np.float64]:
        """E_k = a^2 |H_k(f)|^2 [(m/s^2)^2], shape (n_modes, *broadcast(f, a).shape), discrete filters."""
        a = self._check_amp(a)
        f, a = np.broadcast_arrays(np.asarray(f, dtype=float), a)
        return np.array([a**2 * np.abs(m.response(f, self.physics_rate)) ** 2 for m in self.modes]).reshape(
            (len(self.modes),) + f.shape
        )

    def rectified_bias(self, f: ArrayLike, a: ArrayLike) -> NDArray[np.float64]:
        """Steady rectified bias [rad/s] of a sine of amplitude ``a`` [m/s^2] at ``f`` [Hz].

        bias = sum_k c_k a^2 |H_k(f)|^2 + c_lin a (block means over whole cycles).
        """
        a = self._check_amp(a)
        f, a = np.broadcast_arrays(np.asarray(f, dtype=float), a)
        out = self.linear_g * a
        if self.modes:
            e = self.modal_energy(f, a)
            out = out + np.tensordot(np.array([m.rectification for m in self.modes]), e, axes=1)
        return out

    def noise_gain(self, f: ArrayLike, a: ArrayLike) -> NDArray[np.float64]:
        """N(f, a)/N_0 = B(f, a)/B_0 = sqrt(1 + sum_k d_k a^2 |H_k(f)|^2 / a_ref^2) [-]."""
        a = self._check_amp(a)
        f, a = np.broadcast_arrays(np.asarray(f, dtype=float), a)
        s = np.zeros(f.shape)
        if self.modes:
            s = np.tensordot(np.array([m.noise_weight for m in self.modes]), self.modal_energy(f, a), axes=1)
        return np.sqrt(1.0 + s / self.noise_ref**2)

    def tone_amplitude(self, f: ArrayLike, a: ArrayLike) -> NDArray[np.float64]:
        """Amplitude [rad/s] of the rate tone at ``f`` at the physics rate: a |sum_k g_k H_k(f)|."""
        a = self._check_amp(a)
        f, a = np.broadcast_arrays(np.asarray(f, dtype=float), a)
        h = np.zeros(f.shape, dtype=complex)
        for m in self.modes:
            h = h + m.tone_gain * m.response(f, self.physics_rate)
        return a * np.abs(h)

    def output_tone(self, f: ArrayLike, a: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(alias frequency [Hz], amplitude [rad/s]) of the drive tone in the decimated output."""
        f = np.asarray(f, dtype=float)
        amp = self.tone_amplitude(f, a)
        if self.decimation == "integrate":
            amp = amp * moving_average_gain(f, self.factor, self.physics_rate)
        return alias_frequency(f, self.output_rate), amp

    # ------------------------------------------------------------------ simulation
    def simulate(
        self, profile: Phased | VibrationProfile, *, rng: np.random.Generator, name: str = "fog_vibration"
    ) -> Recording:
        """Simulate the gyro output over a shaker profile.

        Parameters
        ----------
        profile : Phased or a shaker profile
            A bare profile is treated as ``Phased(vibration=profile)`` (vibration only).
        rng : numpy.random.Generator
            Spawns independent streams: shaker, static noise, vibration white noise, vibration flicker.
        name : str
            Recording name.

        Returns
        -------
        Recording
            At ``output_rate``. Channels: ``rate`` [rad/s] (gyro output),
            ``shaker_frequency`` [Hz] (drive frequency; 0 when the shaker is off),
            ``shaker_amplitude`` [m/s^2] (envelope), ``shaker_on`` [-] (1/0).
            Truth: ``true_rate`` (zero: static base), every static noise term, and
            ``vibration_bias`` (rectified), ``vibration_tone``, ``vibration_noise``,
            ``vibration_heating``, ``vibration_transient``; they sum to ``rate``.

        Raises
        ------
        ValueError
            If the profile's highest frequency exceeds physics_rate/4.
        """
        if not isinstance(rng, np.random.Generator):
            raise TypeError(f"rng must be a numpy.random.Generator; got {type(rng).__name__}")
        if not isinstance(profile, Phased):
            if not isinstance(profile, VibrationProfile):
                raise TypeError(f"profile must be a shaker profile or Phased; got {type(profile).__name__}")
            profile = Phased(vibration=profile)
        fmax = profile.max_frequency
        if fmax > self.max_drive_frequency:
            raise ValueError(
                f"vibration up to {fmax!r} Hz needs physics_rate >= {4 * fmax!r} Hz (the rectified 2f "
                f"component must stay below the physics Nyquist); got physics_rate={self.physics_rate!r} Hz"
            )
        r_shaker, r_static, r_vib, r_flicker = rng.spawn(4)
        fo, fp, m = self.output_rate, self.physics_rate, self.factor
        n1 = int(round(profile.static_before * fo))
        nv = int(round(profile.vibration.duration * fo))
        n3 = int(round(profile.static_after * fo))
        n = n1 + nv + n3
        # --- physics from switch-on to the end of the record (before: no excitation)
        vib = profile.vibration.sample(fp, rng=r_shaker)
        npv = (nv + n3) * m
        acc = np.zeros(npv)
        k = min(len(vib.acceleration), nv * m)
        acc[:k] = vib.acceleration[:k]
        tone = np.zeros(npv)
        rect = self.linear_g * (np.pi / 2.0) * np.abs(acc)
        energies = []
        place_power = decimate(2.0 * acc * acc, m, "integrate")
        for mode in self.modes:
            b, a = mode.filter(fp)
            x = signal.lfilter(b, a, acc)
            tone += mode.tone_gain * x
            e2 = 2.0 * x * x
            rect += mode.rectification * e2
            energies.append(decimate(e2, m, "integrate"))
        dec = self.decimation

        def place(y_after_on: NDArray) -> NDArray:
            out = np.zeros(n)
            out[n1:] = y_after_on
            return out

        comps: dict[str, NDArray[np.float64]] = {}
        comps["vibration_bias"] = place(decimate(rect, m, dec))
        comps["vibration_tone"] = place(decimate(tone, m, dec))
        e_out = [place(e) for e in energies]
        s_tot = np.sum(e_out, axis=0) if e_out else np.zeros(n)
        d_sum = np.zeros(n)
        for mode, e in zip(self.modes, e_out, strict=True):
            d_sum += mode.noise_weight * e
        u = np.sqrt(d_sum) / self.noise_ref
        comps["vibration_noise"] = self._arw0() * math.sqrt(fo) * u * r_vib.standard_normal(n)
        if self._bi0() > 0 and np.any(u > 0):
            flk = NoiseModel(bias_instability=self._bi0(), flicker_band=self.noise.flicker_band)
            comps["vibration_noise"] += u * flk.generate(n, fo, rng=r_flicker)
        comps["vibration_heating"] = self.heating_gain * _lowpass(s_tot, fo, self.heating_time)
        p_tot = place(place_power)
        comps["vibration_transient"] = self.transient_gain * (p_tot - _lowpass(p_tot, fo, self.transient_time))
        static = self.noise.components(n, fo, rng=r_static)
        rate = np.zeros(n)
        for v in static.values():
            rate += v
        for v in comps.values():
            rate += v
        # --- what the shaker controller logs, at the output rate (block means)
        def log(x: NDArray, fill: float) -> NDArray:
            y = np.full(nv * m, fill)
            kk = min(len(x), nv * m)
            y[:kk] = x[:kk]
            return np.concatenate([np.full(n1, fill), decimate(y, m, "integrate"), np.full(n3, fill)])

        freq = log(np.nan_to_num(vib.frequency, nan=0.0), 0.0)
        amp = log(vib.amplitude, 0.0)
        on = np.zeros(n)
        on[n1 : n1 + nv] = 1.0
        truth = {"true_rate": Channel(np.zeros(n), "rad/s", "table rate (static base)")}
        truth.update({k: Channel(v, "rad/s", f"static {k}") for k, v in static.items()})
        truth.update({k: Channel(v, "rad/s", k.replace("_", " ")) for k, v in comps.items()})
        return Recording(
            fs=fo,
            channels={
                "rate": Channel(rate, "rad/s", "gyro output"),
                "shaker_frequency": Channel(freq, "Hz", "drive frequency (0 when off)"),
                "shaker_amplitude": Channel(amp, "m/s^2", "acceleration envelope"),
                "shaker_on": Channel(on, "1", "1 while the shaker drives"),
            },
            truth=truth,
            metadata={
                "model": "gyrobench.sim.vibration.FogVibrationModel",
                "physics_rate": fp,
                "output_rate": fo,
                "decimation": dec,
                "phase_bounds_s": [list(b) for b in profile.phase_bounds],
                "version": package_version(),
            },
            name=name,
        )


def _lowpass(x: NDArray[np.float64], fs: float, tau: float) -> NDArray[np.float64]:
    """First-order lag y_k = phi y_{k-1} + (1 - phi) x_k, phi = exp(-1/(fs tau)), y_{-1} = 0."""
    phi = math.exp(-1.0 / (fs * tau))
    return signal.lfilter([1.0 - phi], [1.0, -phi], x)
