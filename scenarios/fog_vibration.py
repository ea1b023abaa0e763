"""Seed paper 000: a FOG under linear vibration, wavelet multiscale split, RBF bias model vs 4th-order LS.

Protocol (Fang, Shen, Chen; summary in shared/seeds/README.md): a FOG with its
sense axis horizontal sits on a shaker at a fixed acceleration level. Two records,
each static -> vibration -> static:

(a) a sine sweep 1 -> 500 Hz; (b) a fixed 500 Hz dwell.

Analysis, as the paper:

* Table 1: Allan coefficients (Q, N, B, K, R) of the three phases of record (b).
* Figure 2: FFT spectrum vs continuous-wavelet time-frequency map of record (b).
  The paper's third panel, EMD, is not drawn. Maintained EMD packages exist (PyPI
  ``EMD-signal`` = PyEMD 1.x, and ``emd`` 0.8), but we do not add a dependency (PyEMD
  brings extra dependencies of its own) for one figure panel whose only role in the
  paper is negative: it shows that EMD does not separate the three phases, which the
  FFT panel already shows for a method without time resolution.
* Figure 3: multiscale (db4, 10 levels, Mallat) view of record (a).
* Figure 4, Table 2: record (a) split into the level-6 approximation A6 ("bias")
  and D1 + ... + D6 ("drift + noise"), Allan coefficients of each.
* Figure 6: the bias of record (a) against the drive frequency, modelled by an RBF
  network (newrb, spread 1.2 Hz, goal 1e-4 (deg/h)^2) and by a 4th-order
  least-squares polynomial.
* Figures 7-8, Table 3: record (b) denoised (A6), then bias-compensated with each
  model; Allan coefficients of original, denoised, RBF- and LS-compensated.

Choices the paper does not state (documented here and in the report)
--------------------------------------------------------------------
* Output rate 400 Hz, physics 4 kHz (so 500 Hz and its rectified 1 kHz component
  are resolved); integrate-and-dump output (a closed-loop FOG outputs angle
  increments), so the 500 Hz tone aliases to 100 Hz and its 2f to 200 Hz.
* Records of 600 s + 300 s + 600 s (the paper gives no durations). The static phases
  are long enough for bias instability to be identified in each: with N = 0.005
  deg/sqrt(h) and B = 0.2 deg/h, B overtakes white noise near tau = 5 s and a fit
  needs it to dominate up to T/4; with 200 s phases (tau <= 50 s) B of phases 1 and 3
  was identifiable on 2 of 10 seeds, so "B rises in phase 2" was mostly not testable;
  with 600 s it is testable on every seed tried (0-5). The whole scenario stays well
  under a minute. The sweep is linear, 1 -> 500 Hz in
  300 s (1.66 Hz/s): the paper's RBF spread of 1.2 Hz needs training points about
  1 Hz apart over the whole band, which a linear sweep supplies evenly (a log sweep
  spends only 0.1 s per Hz near 500 Hz). 12.7 mm (0.5 in) stroke limit below ~5 Hz.
* Acceleration 2 g peak. Gyro: Q 0.1 arcsec, N 0.005 deg/sqrt(h), B 0.2 deg/h,
  K 0.05 deg/h/sqrt(h) and R 0.01 deg/h^2 static (a mid-grade FOG; K as the project's
  FOG-grade budget in scenarios/static_noise, R an order of magnitude typical of FOG
  thermal-drift ramps; FOG datasheets seldom quote K and R: unverified). K and R are
  NOT identifiable in this scenario: on the Allan curve K overtakes B only beyond
  tau = 3 (2 ln2/pi) B^2 / K^2 = 21 h and R beyond tau = sqrt(2 (2 ln2/pi)) B / R = 19 h,
  and a fit needs records of about 4 tau, i.e. days, which the 3-minute runtime budget
  (phases of 300-600 s) does not allow. Their Table 1 entries are 95 % upper bounds,
  set by the white and flicker noise of the segment, not by K or R. Structural modes at 180 Hz (Q 15, mount) and 460 Hz (Q 10, coil
  potting) put the rectified bias peak (about 40 deg/h) in the 300-500 Hz band the
  paper's figure 3 points to; about 8 deg/h remain at 500 Hz. During vibration the
  white and flicker noise grow by sqrt(1 + sum_k d_k a^2 |H_k|^2 / g^2) (x2.7 at
  500 Hz). Parameters are phenomenological (PHYSICS.md 4, unverified).
* The shaker controller holds the amplitude to 1 % rms (correlation 30 s).
* Table 1 phases are cut with a 5 s guard after each switching edge (the on/off
  transients belong to neither steady state).
* RBF training pairs are means of the A6 bias over 1 Hz frequency bins of the
  sweep (about 500 pairs; the newrb design matrix is n x n), leaving out the
  shaker's 0.5 s soft start and stop (``train_edge_s`` = ``ramp_time_s``), so the
  pairs cover the whole steady-amplitude sweep, 1.8-499.2 Hz (the soft stop takes the
  last 0.8 Hz). On the noise-free record these bin means equal the true bias to
  0.01 deg/h up to the last bin; the A6 smear of the on/off step is negligible because
  the step is the 0.5 s raised-cosine ramp (excluding only 0.25 s biases the last bin by
  -1.8 deg/h). A bin holding fewer than half the samples of a full bin (the partial
  last one) is merged into its neighbour. The target is A6 minus its phase-1 mean (the gyro's own static bias is
  not a vibration error). "Spread 1.2" is taken in Hz, the unit of the paper's
  input (MATLAB newrb does not scale inputs); goal 1e-4 in (deg/h)^2. Both models
  are evaluated with the frequency clipped to the training range (no extrapolation;
  500 Hz is read at ~499 Hz, where the true bias differs by < 1 deg/h).
  With spread 1.2 Hz on bins 1 Hz apart the newrb network nearly interpolates its
  training pairs, and each pair is a noisy 0.6 s mean (a few deg/h of white and
  flicker noise, grown by the vibration, near the 460 Hz mode). The network therefore
  reproduces that noise: its value at 500 Hz is essentially the last bin's noisy mean.
  That is the paper's method (goal 1e-4 on noisy targets), reported as it is; the
  report gives the mean residual of the compensated 500 Hz vibration phase against
  the true bias for both models.
* The bias-model MSE is scored against the true steady rectified bias (known to
  the simulator) at the bin frequencies; the MSE against the noisy A6 target is
  reported beside it.
* Compensation applies the model only while the shaker runs (its frequency is
  logged by the controller).
* Allan curves: overlapping ADEV at octave taus up to T/4, fitted jointly
  (analysis.allan.fit_noise), coefficients with 95 % intervals, or "not
  identifiable" with a 95 % upper bound. For Tables 2 and 3, whose columns include
  wavelet approximations, Q and N come from the fit on the full tau range and B, K,
  R from the fit on tau >= 2^(j+1)/fs (0.32 s): below that an approximation A_j is
  smooth by construction and its ADEV (slope +1) would be read as a huge spurious
  rate ramp. The same rule is applied to every column, the original included.

How the headlines decide (a conclusion "holds" only when the data demonstrate it)
-------------------------------------------------------------------------------
* "A higher than B" needs A identified: A's lower 95 % bound above B's upper 95 % bound
  (B's interval, or B's 95 % upper bound when B is not identifiable: the coefficient is
  below it either way). When A is only an upper bound ("not identifiable", set by the
  other noise terms of the segment) the comparison is NOT TESTABLE: the headline's
  ``holds`` is None (printed '-') with the note "not identifiable in this record:
  95 % bounds only". This is always the case for K and R in phase 2 here (see above).
* "Higher in phase 2" (Table 1): the rule above with A = phase 2, for every term.
* "Phases 1 and 3 agree": their 95 % intervals overlap.
* "Bias part keeps B" (Table 2): the bias part's B inside the original's 95 % interval.
* "x times lower" (Tables 2 and 3, Q and N): the original's lower 95 % bound over the
  processed signal's upper 95 % bound (an upper bound is a valid denominator for a
  "lower" claim; a non-identifiable original is not testable).
* "RBF lower than LS" (Table 3): the rule above with A = the LS column (so the RBF
  column may be a bound).
The conclusion counts "N of M testable conclusions".
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, field
from typing import Any, Literal

import numpy as np
from matplotlib.figure import Figure

from gyrobench.analysis.compensation.rbf import RBFNetwork
from gyrobench.analysis.metrics import segment_noise_fits
from gyrobench.analysis.wavelet import amplitude_spectrum, cwt_map, decompose
from gyrobench.scenarios.allan_report import TERMS, coefficients_json
from gyrobench.scenarios.base import (
    CompensationTask,
    FigureSpec,
    Headline,
    HeldOutRun,
    Outcome,
    Table,
    mse_scores,
)
from gyrobench.sim import units
from gyrobench.sim.noise import NoiseModel
from gyrobench.sim.recording import Recording
from gyrobench.sim.shaker import FixedSine, Phased, SineSweep
from gyrobench.sim.vibration import FogVibrationModel, StructuralMode

NAME = "fog_vibration"
TITLE = "FOG under vibration (seed 000): Allan terms by phase, db4 wavelet bias split, RBF vs 4th-order LS bias model"

_G = units.g(1.0)
_DEG_H = units.deg_per_h(1.0)


# ------------------------------------------------------------------------------------------ config
@dataclass(frozen=True, slots=True, kw_only=True)
class ModeSpec:
    """A structural mode in field units.

    frequency_hz [Hz], quality [-], rectification [deg/h per g^2 of modal acceleration],
    tone [deg/h per g of modal acceleration], noise_weight [-] (see sim.vibration).
    """

    frequency_hz: float
    quality: float
    rectification_deg_h_per_g2: float = 0.0
    tone_deg_h_per_g: float = 0.0
    noise_weight: float = 0.0

    def to_si(self) -> StructuralMode:
        return StructuralMode(
            frequency=self.frequency_hz,
            quality=self.quality,
            rectification=self.rectification_deg_h_per_g2 * _DEG_H / _G**2,
            tone_gain=self.tone_deg_h_per_g * _DEG_H / _G,
            noise_weight=self.noise_weight,
        )


@dataclass(frozen=True, slots=True, kw_only=True)
class FogSpec:
    """The gyro: static noise budget and vibration response, field units (SI conversion in :meth:`model`)."""

    Q_arcsec: float = 0.1
    N_deg_sqrt_h: float = 0.005
    B_deg_h: float = 0.2
    K_deg_h_sqrt_h: float = 0.05
    R_deg_h2: float = 0.01
    modes: tuple[ModeSpec, ...] = (
        ModeSpec(frequency_hz=180.0, quality=15.0, rectification_deg_h_per_g2=0.011, tone_deg_h_per_g=5.0,
                 noise_weight=0.05),
        ModeSpec(frequency_hz=460.0, quality=10.0, rectification_deg_h_per_g2=0.1, tone_deg_h_per_g=20.0,
                 noise_weight=0.08),
    )
    linear_deg_h_per_g: float = 0.25
    noise_ref_g: float = 1.0
    flicker_growth: bool = True
    heating_deg_h_per_g2: float = 0.0
    heating_time_s: float = 120.0
    transient_deg_h_per_g2: float = 0.05
    transient_time_s: float = 1.0
    physics_rate_hz: float = 4000.0
    output_rate_hz: float = 400.0
    decimation: Literal["integrate", "sample"] = "integrate"

    def __post_init__(self) -> None:
        self.model()  # the SI model validates every value

    def noise(self) -> NoiseModel:
        return NoiseModel.from_datasheet(
            quantization=self.Q_arcsec,
            angle_random_walk=self.N_deg_sqrt_h,
            bias_instability=self.B_deg_h,
            rate_random_walk=self.K_deg_h_sqrt_h,
            rate_ramp=self.R_deg_h2,
        )

    def model(self) -> FogVibrationModel:
        return FogVibrationModel(
            noise=self.noise(),
            modes=tuple(m.to_si() for m in self.modes),
            linear_g=self.linear_deg_h_per_g * _DEG_H / _G,
            noise_ref=units.g(self.noise_ref_g),
            noise_bias_instability=None if self.flicker_growth else 0.0,
            heating_gain=self.heating_deg_h_per_g2 * _DEG_H / _G**2,
            heating_time=self.heating_time_s,
            transient_gain=self.transient_deg_h_per_g2 * _DEG_H / _G**2,
            transient_time=self.transient_time_s,
            physics_rate=self.physics_rate_hz,
            output_rate=self.output_rate_hz,
            decimation=self.decimation,
        )


@dataclass(frozen=True, slots=True, kw_only=True)
class Config:
    """Seed 000's experiment; values the paper leaves open are documented in the module docstring."""

    fog: FogSpec = field(default_factory=FogSpec)
    acceleration_g: float = 2.0
    sweep_start_hz: float = 1.0
    sweep_end_hz: float = 500.0
    sweep_spacing: Literal["log", "linear"] = "linear"
    fixed_hz: float = 500.0
    static_before_s: float = 600.0
    vibration_s: float = 300.0
    static_after_s: float = 600.0
    max_displacement_mm: float = 12.7
    ramp_time_s: float = 0.5
    control_error: float = 0.01
    control_time_s: float = 30.0
    guard_s: float = 5.0
    wavelet: str = "db4"
    level: int = 10
    bias_level: int = 6
    bin_width_hz: float = 1.0
    train_edge_s: float = 0.5
    rbf_spread_hz: float = 1.2
    rbf_goal_deg_h2: float = 1e-4
    rbf_max_neurons: int | None = None
    ls_order: int = 4
    bench_rate_hz: float = 2.0

    def __post_init__(self) -> None:
        def pos(name: str, unit: str) -> None:
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not (math.isfinite(v) and v > 0):
                raise ValueError(f"Config.{name} must be > 0 {unit}; got {v!r}")

        if isinstance(self.acceleration_g, (int, float)) and self.acceleration_g < 0:
            raise ValueError(f"Config.acceleration_g must be >= 0 g; got {self.acceleration_g!r}")
        for name, unit in (("acceleration_g", "g"), ("sweep_start_hz", "Hz"), ("sweep_end_hz", "Hz"),
                           ("fixed_hz", "Hz"), ("static_before_s", "s"), ("vibration_s", "s"),
                           ("static_after_s", "s"), ("max_displacement_mm", "mm"), ("control_time_s", "s"),
                           ("bin_width_hz", "Hz"), ("train_edge_s", "s"), ("rbf_spread_hz", "Hz"), ("bench_rate_hz", "Hz")):
            pos(name, unit)
        if not 0 <= self.guard_s < min(self.static_before_s, self.vibration_s, self.static_after_s) / 2:
            raise ValueError(f"Config.guard_s must be in [0, shortest phase/2) s; got {self.guard_s!r}")
        if not 1 <= self.bias_level <= self.level:
            raise ValueError(f"Config.bias_level must be in [1, level={self.level}]; got {self.bias_level!r}")
        if not 1 <= self.ls_order <= 12:
            raise ValueError(f"Config.ls_order must be in [1, 12]; got {self.ls_order!r}")
        if self.control_error < 0:
            raise ValueError(f"Config.control_error must be >= 0; got {self.control_error!r}")
        if self.rbf_goal_deg_h2 < 0:
            raise ValueError(f"Config.rbf_goal_deg_h2 must be >= 0 (deg/h)^2; got {self.rbf_goal_deg_h2!r}")
        fmax = max(self.sweep_start_hz, self.sweep_end_hz, self.fixed_hz)
        if fmax > self.fog.physics_rate_hz / 4:
            raise ValueError(
                f"Config: vibration up to {fmax!r} Hz needs fog.physics_rate_hz >= {4 * fmax!r} Hz; "
                f"got {self.fog.physics_rate_hz!r} Hz"
            )
        n_vib = self.vibration_s * self.fog.output_rate_hz
        n_min = (8 - 1) * 2**self.level  # db4: pywt.dwt_max_level needs len >= 7 * 2^level
        n_tot = (self.static_before_s + self.vibration_s + self.static_after_s) * self.fog.output_rate_hz
        if n_tot < n_min:
            raise ValueError(
                f"Config.level = {self.level} needs records of >= {n_min} samples; got {int(n_tot)} "
                f"(lengthen the phases or lower the level)"
            )
        del n_vib

    # -------------------------------------------------------------- profiles
    def _common(self) -> dict[str, Any]:
        return dict(
            acceleration=units.g(self.acceleration_g),
            max_displacement=self.max_displacement_mm * 1e-3,
            ramp_time=self.ramp_time_s,
            control_error=self.control_error,
            control_time=self.control_time_s,
        )

    def sweep(self) -> Phased:
        s = SineSweep(f_start=self.sweep_start_hz, f_end=self.sweep_end_hz, duration=self.vibration_s,
                      spacing=self.sweep_spacing, **self._common())
        return Phased(vibration=s, static_before=self.static_before_s, static_after=self.static_after_s)

    def fixed(self) -> Phased:
        s = FixedSine(frequency=self.fixed_hz, duration=self.vibration_s, **self._common())
        return Phased(vibration=s, static_before=self.static_before_s, static_after=self.static_after_s)


# ------------------------------------------------------------------------------------------ simulate
def simulate(config: Config, seed: int) -> list[Recording]:
    """Record (a) the sweep and (b) the fixed-frequency dwell, each static -> vibration -> static."""
    r_sweep, r_fixed = np.random.default_rng(seed).spawn(2)
    model = config.fog.model()
    recs = []
    for key, prof, rng in (("sweep", config.sweep(), r_sweep), ("fixed", config.fixed(), r_fixed)):
        rec = model.simulate(prof, rng=rng, name=f"fog_vibration_{key}")
        meta = dict(rec.metadata)
        meta.update({"scenario": NAME, "record": key, "seed": seed, "config": asdict(config)})
        recs.append(Recording(fs=rec.fs, channels=rec.channels, truth=rec.truth, t0=rec.t0, metadata=meta,
                              name=rec.name))
    return recs


# ------------------------------------------------------------------------------------------ analysis helpers
def _fit(rate_rad_s: np.ndarray, fs: float, *, min_m: int = 1):
    """Joint IEEE fit on the overlapping ADEV at octave taus m = min_m, 2 min_m, ... <= n/4.

    A wavelet approximation A_j is smooth below 2^j samples by construction (its ADEV there
    rises with slope +1 and would read as a huge rate ramp), so its curve starts at m = 2^j.
    """
    return segment_noise_fits(rate_rad_s, fs, {"record": np.ones(len(rate_rad_s), dtype=bool)},
                              min_m=min_m)["record"].fit


def split_band_coefficients(rate_rad_s: np.ndarray, fs: float, min_m: int) -> dict[str, dict]:
    """Q and N from the fit on the full tau range, B, K and R from the fit on tau >= min_m/fs (field units).

    Used for wavelet-processed signals and what they are compared with: an approximation
    A_j has no content above fs/2^(j+1), so its short-tau ADEV measures the filter (slope +1,
    read as a spurious R); the low-frequency terms are read where A_j is faithful, the
    high-frequency terms where they live. Each entry carries its ``tau_min_s``.
    """
    full = coefficients_json(_fit(rate_rad_s, fs))
    low = coefficients_json(_fit(rate_rad_s, fs, min_m=min_m))
    out = {}
    for t in TERMS:
        d = dict(full[t] if t in ("Q", "N") else low[t])
        d["tau_min_s"] = 1.0 / fs if t in ("Q", "N") else min_m / fs
        out[t] = d
    return out


def segment_coefficients(rate: np.ndarray, fs: float, bounds, *, guard_s: float = 0.0) -> dict[str, dict]:
    """Allan coefficient tables (field units) of each [start, end) segment [s] of a rate record [rad/s].

    ``guard_s`` is cut after each segment's start (except the first) so switching
    transients stay out of the steady phases. The fits are
    :func:`gyrobench.analysis.metrics.segment_noise_fits` (each segment on its own samples).
    """
    segs = {str(i): (t0 + (guard_s if i > 1 else 0.0), t1) for i, (t0, t1) in enumerate(bounds, start=1)}
    return {k: coefficients_json(f.fit) for k, f in segment_noise_fits(rate, fs, segs).items()}


def _bins(f: np.ndarray, y: np.ndarray, lo: float, hi: float, width: float):
    """Means of f and y over frequency bins of ``width`` [Hz].

    Empty bins are dropped; a bin holding fewer than half the median count (a partial bin
    at the end of the data, whose mean would be several times noisier) is merged into its
    lower neighbour (the upper one for the first bin).
    """
    edges = np.arange(lo, hi + width, width)
    idx = np.digitize(f, edges) - 1
    ok = (idx >= 0) & (idx < len(edges) - 1)
    cnt = np.bincount(idx[ok], minlength=len(edges) - 1)
    sf = np.bincount(idx[ok], f[ok], minlength=len(edges) - 1)
    sy = np.bincount(idx[ok], y[ok], minlength=len(edges) - 1)
    keep = cnt > 0
    cnt, sf, sy = cnt[keep].astype(float), sf[keep], sy[keep]
    small = np.flatnonzero(cnt < 0.5 * np.median(cnt)) if cnt.size > 1 else np.array([], dtype=int)
    for i in small[::-1]:  # from the top, so indices below stay valid
        j = i - 1 if i > 0 else i + 1
        cnt[j] += cnt[i]
        sf[j] += sf[i]
        sy[j] += sy[i]
        cnt[i] = 0.0
    keep = cnt > 0
    return sf[keep] / cnt[keep], sy[keep] / cnt[keep]


def _near_edges(on: np.ndarray, fs: float, width_s: float) -> np.ndarray:
    """True within ``width_s`` [s] of any switching edge of the boolean ``on``."""
    edges = np.flatnonzero(np.diff(on.astype(np.int8))) + 1
    near = np.zeros_like(on)
    w = int(round(width_s * fs))
    for e in edges:
        near[max(0, e - w) : e + w] = True
    return near


def _predict(fn, f: np.ndarray, on: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """Model bias [deg/h] while ``on``, 0 otherwise; inputs clipped to the training range [lo, hi] Hz.

    Evaluated once per distinct frequency (a record holds few), then mapped back.
    """
    out = np.zeros(len(f))
    if on.any():
        u, inv = np.unique(np.clip(f[on], lo, hi), return_inverse=True)
        out[on] = np.asarray(fn(u), dtype=float).reshape(-1)[inv]
    return out


def _phase_mask(rec: Recording) -> tuple[np.ndarray, np.ndarray]:
    on = rec["shaker_on"] > 0.5
    first_on = int(np.argmax(on)) if on.any() else len(on)
    static1 = np.zeros_like(on)
    static1[:first_on] = True
    return on, static1


def _text(d: dict) -> str:
    if d["value"] is None:
        return f"< {d['high']:.3g}"
    return f"{d['value']:.3g} [{d['low']:.3g}, {d['high']:.3g}]"


def _coef_table(title: str, cols: dict[str, dict], note: str = "") -> Table:
    names = list(cols)
    rows = []
    for t in TERMS:
        unit = next(iter(cols.values()))[t]["unit"]
        rows.append([t, unit] + [_text(cols[n][t]) for n in names])
    return Table(title, ["term", "unit"] + names, rows, note)


#: note of every headline that cannot be decided because a coefficient is only bounded
NOT_TESTABLE = "not identifiable in this record: 95 % bounds only"


def _ident(*ds: dict) -> bool:
    return all(d["value"] is not None for d in ds)


def _higher(p2: dict, other: dict) -> tuple[bool | None, str]:
    """Whether ``p2`` is shown higher than ``other`` for one term, and on what basis (module docstring).

    Decided by ``p2``'s lower 95 % bound against ``other``'s upper 95 % bound (its interval's
    upper end, or its upper bound when it is not identifiable: either way the coefficient is
    below it). None (not testable) when ``p2`` itself is only an upper bound: nothing then
    shows it is above anything.
    """
    if not _ident(p2):
        return None, NOT_TESTABLE
    basis = "95 % intervals" if _ident(other) else "95 % interval above the other's 95 % upper bound"
    if p2["low"] > other["high"]:
        return True, f"{basis} do not overlap" if _ident(other) else basis
    return False, f"{basis} overlap" if _ident(other) else f"{basis}: NOT above it"


def _overlap(a: dict, b: dict) -> bool:
    return a["low"] <= b["high"] and b["low"] <= a["high"]


def _all_or_none(results: list[bool | None]) -> bool | None:
    """A conjunction of sub-conclusions: None when any part is not testable, else all()."""
    return None if any(r is None for r in results) else all(results)


# ------------------------------------------------------------------------------------------ models
@dataclass(frozen=True)
class BiasModels:
    """The fitted bias-vs-frequency models and their training data (deg/h, Hz)."""

    f_bins: np.ndarray
    y_bins: np.ndarray
    truth_bins: np.ndarray
    rbf: RBFNetwork
    ls: np.polynomial.Polynomial
    static_mean: float


def fit_bias_models(rec: Recording, config: Config, dec=None) -> BiasModels:
    """RBF (newrb) and 4th-order LS models of the A6 bias [deg/h] against drive frequency [Hz] on a sweep record."""
    fs = rec.fs
    if dec is None:
        dec = decompose(units.to_deg_per_h(rec["rate"]), fs, wavelet=config.wavelet, level=config.level)
    bias = dec.approx(config.bias_level)
    on, static1 = _phase_mask(rec)
    static_mean = float(np.mean(bias[static1])) if static1.any() else 0.0
    f = rec["shaker_frequency"]
    lo, hi = min(config.sweep_start_hz, config.sweep_end_hz), max(config.sweep_start_hz, config.sweep_end_hz)
    use = on & ~_near_edges(on, fs, config.train_edge_s)
    fb, yb = _bins(f[use], bias[use] - static_mean, lo, hi, config.bin_width_hz)
    model = config.fog.model()
    amp = config.sweep().vibration.amplitude
    # steady amplitude at each bin frequency (displacement limit), then the true rectified bias
    s = config.sweep().vibration
    t_of_f = (np.log(fb / s.f_start) / np.log(s.f_end / s.f_start) * s.duration if s.spacing == "log"
              else (fb - s.f_start) / (s.f_end - s.f_start) * s.duration)
    a_b = amp(np.clip(t_of_f, s.ramp_time, s.duration - s.ramp_time))
    truth = units.to_deg_per_h(model.rectified_bias(fb, a_b))
    rbf = RBFNetwork(spread=config.rbf_spread_hz, goal=config.rbf_goal_deg_h2,
                     max_neurons=config.rbf_max_neurons).fit(fb[:, None], yb)
    ls = np.polynomial.Polynomial.fit(fb, yb, config.ls_order)
    return BiasModels(fb, yb, truth, rbf, ls, static_mean)


# ------------------------------------------------------------------------------------------ figures
def _fig_records(recs, config) -> Figure:
    fig = Figure(figsize=(8.0, 5.0))
    for i, rec in enumerate(recs):
        ax = fig.add_subplot(2, 1, i + 1)
        t = rec.time
        y = units.to_deg_per_h(rec["rate"])
        k = max(1, len(y) // 4000)
        n = len(y) // k * k
        ax.plot(t[:n:k], y[:n].reshape(-1, k).mean(axis=1), lw=0.6)
        ax.set_ylabel("rate [deg/h]")
        ax.set_title((f"(a) sweep {config.sweep_start_hz:g}-{config.sweep_end_hz:g} Hz") if i == 0
                     else f"(b) fixed {config.fixed_hz:g} Hz", fontsize=9)
    ax.set_xlabel("time [s]")
    fig.tight_layout()
    return fig


def _fig_spectrum_cwt(rec: Recording) -> Figure:
    fs = rec.fs
    y = units.to_deg_per_h(rec["rate"])
    f, a = amplitude_spectrum(y, fs)
    tf = cwt_map(y, fs, n_frequencies=32, f_min=0.5)
    fig = Figure(figsize=(8.0, 6.0))
    ax1 = fig.add_subplot(2, 1, 1)
    ax1.semilogy(f[1:], a[1:], lw=0.4)
    ax1.set_xlabel("frequency [Hz]")
    ax1.set_ylabel("amplitude [deg/h]")
    ax1.set_title("(a) FFT amplitude spectrum: no time information", fontsize=9)
    ax2 = fig.add_subplot(2, 1, 2)
    rel = tf.magnitude / np.median(tf.magnitude, axis=1, keepdims=True)  # each frequency against its median
    pc = ax2.pcolormesh(tf.time, tf.frequency, 20 * np.log10(rel + 1e-12), shading="nearest", cmap="viridis")
    ax2.set_yscale("log")
    ax2.set_xlabel("time [s]")
    ax2.set_ylabel("pseudo-frequency [Hz]")
    ax2.set_title("(c) continuous wavelet transform (complex Morlet): |W| against its median at each frequency; "
                  "EMD panel omitted", fontsize=9)
    fig.colorbar(pc, ax=ax2, label="[dB]")
    fig.tight_layout()
    return fig


def _block(x: np.ndarray, k: int) -> np.ndarray:
    n = len(x) // k * k
    return x[:n].reshape(-1, k).mean(axis=1)


def _fig_multiscale(dec, t: np.ndarray) -> Figure:
    fig = Figure(figsize=(8.0, 8.0))
    ax = fig.add_subplot()
    k = max(1, len(t) // 3000)
    tt = _block(t, k)
    rows = [(f"a{dec.level}", dec.approximation)] + [(f"d{j}", dec.detail(j)) for j in range(dec.level, 0, -1)]
    for i, (label, x) in enumerate(rows):
        xb = _block(x, k) if label.startswith("a") else np.sqrt(_block(x**2, k))
        xb = xb - np.median(xb)
        span = np.ptp(xb) or 1.0
        ax.plot(tt, i + 0.8 * xb / span, lw=0.6)
        ax.text(tt[-1] * 1.01, i, label, fontsize=8, va="center")
    ax.set_yticks([])
    ax.set_xlabel("time [s]")
    ax.set_title("Sweep record, db4 10-level Mallat decomposition: a10 and rms envelope of each detail "
                 "(each trace scaled to its own range)", fontsize=9)
    fig.tight_layout()
    return fig


def _fig_split(dec, t, config) -> Figure:
    fig = Figure(figsize=(8.0, 7.0))
    j = config.bias_level
    k = max(1, len(t) // 4000)
    traces = [(f"a{j + 1}", dec.approx(j + 1)), (f"a{j} (bias)", dec.approx(j)), (f"d{j}", dec.detail(j)),
              ("d1", dec.detail(1)), (f"d = d1+...+d{j} (drift + noise)", dec.detail_sum(j))]
    for i, (label, x) in enumerate(traces):
        ax = fig.add_subplot(len(traces), 1, i + 1)
        if label.startswith("a"):
            ax.plot(_block(t, k), _block(x, k), lw=0.5)
        else:  # every k-th sample: a block mean would hide the high-frequency amplitude
            ax.plot(t[::k], x[::k], lw=0.3)
        ax.set_ylabel(label, fontsize=8)
        if i < len(traces) - 1:
            ax.set_xticklabels([])
    ax.set_xlabel("time [s]")
    fig.suptitle("Sweep record: low-frequency approximation (bias) and reconstructed details [deg/h]", fontsize=9)
    fig.tight_layout()
    return fig


def _fig_models(bm: BiasModels, model: FogVibrationModel, config) -> Figure:
    fig = Figure(figsize=(8.0, 4.8))
    ax = fig.add_subplot()
    ff = np.linspace(bm.f_bins[0], bm.f_bins[-1], 3000)
    ax.plot(bm.f_bins, bm.y_bins, ".", ms=2.5, color="tab:blue", label="A6 bias (1 Hz bin means)")
    ax.plot(bm.f_bins, bm.truth_bins, "k--", lw=0.8, label="true rectified bias")
    ax.plot(ff, bm.rbf.predict(ff[:, None]), color="tab:red", lw=1, label=f"RBF ({bm.rbf.n_neurons_} neurons)")
    ax.plot(ff, bm.ls(ff), color="tab:green", lw=1.2, label=f"{config.ls_order}th-order LS")
    ax.set_xlabel("vibration frequency [Hz]")
    ax.set_ylabel("bias [deg/h]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("Bias against vibration frequency: RBF network vs least-squares polynomial", fontsize=9)
    return fig


def _fig_compensation(t, original, denoised, rbf_c, ls_c) -> Figure:
    fig = Figure(figsize=(8.0, 6.5))
    ax = fig.add_subplot(2, 1, 1)
    # both as samples (every 4th): block means of the original would hide the noise the a6 removes
    ax.plot(t[::4], original[::4], lw=0.3, color="tab:blue", label="original")
    ax.plot(t[::4], denoised[::4], lw=0.8, color="tab:red", label="denoised (a6)")
    ax.set_ylabel("rate [deg/h]")
    ax.legend(fontsize=8)
    ax.set_title("Fig. 7: 500 Hz record, original and after removing drift + noise", fontsize=9)
    ax2 = fig.add_subplot(2, 1, 2)
    ax2.plot(t[::4], denoised[::4], lw=0.8, color="tab:blue", label="denoised (bias error)")
    ax2.plot(t[::4], rbf_c[::4], lw=0.8, color="tab:red", label="RBF-compensated")
    ax2.plot(t[::4], ls_c[::4], lw=0.8, color="tab:green", alpha=0.8, label="LS-compensated")
    ax2.set_xlabel("time [s]")
    ax2.set_ylabel("rate [deg/h]")
    ax2.legend(fontsize=8)
    ax2.set_title("Fig. 8: bias compensation during vibration", fontsize=9)
    fig.tight_layout()
    return fig


# ------------------------------------------------------------------------------------------ run
def run(config: Config, seed: int, *, progress: bool = False) -> Outcome:
    """Simulate both records, reproduce Tables 1-3 and figures 2, 3, 4, 6, 7-8, and test the paper's conclusions."""
    t_start = time.perf_counter()
    steps = ["simulate", "table 1", "figure 2", "wavelet split", "bias models", "compensation"]
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=len(steps), desc=NAME, unit="step")

    def tick():
        if bar is not None:
            bar.update(1)

    sweep, fixed = simulate(config, seed)
    fs = fixed.fs
    model = config.fog.model()
    tick()

    # --- Table 1: phases of the fixed-frequency record
    bounds = config.fixed().phase_bounds
    phases = segment_coefficients(fixed["rate"], fs, bounds, guard_s=config.guard_s)
    tick()

    # --- Figure 2
    fig2 = _fig_spectrum_cwt(fixed)
    tick()

    # --- Figure 3/4, Table 2: multiscale split of the sweep record
    y_sweep = units.to_deg_per_h(sweep["rate"])
    dec_s = decompose(y_sweep, fs, wavelet=config.wavelet, level=config.level)
    j = config.bias_level
    m_low = 2 ** (j + 1)  # B, K, R read from tau >= 2^(j+1)/fs, where a_j is faithful
    bias_s = dec_s.approx(j)
    dn_s = dec_s.detail_sum(j)
    decomposition = {
        "original": split_band_coefficients(sweep["rate"], fs, m_low),
        "bias": split_band_coefficients(units.deg_per_h(bias_s), fs, m_low),
        "drift_noise": split_band_coefficients(units.deg_per_h(dn_s), fs, m_low),
    }
    tick()

    # --- Figure 6: bias models on the sweep
    bm = fit_bias_models(sweep, config, dec_s)
    mse_rbf = float(np.mean((bm.rbf.predict(bm.f_bins[:, None]) - bm.truth_bins) ** 2))
    mse_ls = float(np.mean((bm.ls(bm.f_bins) - bm.truth_bins) ** 2))
    mse_rbf_t = float(np.mean((bm.rbf.predict(bm.f_bins[:, None]) - bm.y_bins) ** 2))
    mse_ls_t = float(np.mean((bm.ls(bm.f_bins) - bm.y_bins) ** 2))
    tick()

    # --- Table 3: compensation of the fixed record
    y_fixed = units.to_deg_per_h(fixed["rate"])
    dec_f = decompose(y_fixed, fs, wavelet=config.wavelet, level=config.level)
    den = dec_f.approx(j)
    on = fixed["shaker_on"] > 0.5
    f_fixed = fixed["shaker_frequency"]
    lo_t, hi_t = float(bm.f_bins[0]), float(bm.f_bins[-1])
    pred_rbf = _predict(lambda u: bm.rbf.predict(u[:, None]), f_fixed, on, lo_t, hi_t)
    pred_ls = _predict(bm.ls, f_fixed, on, lo_t, hi_t)
    rbf_c = den - pred_rbf
    ls_c = den - pred_ls
    compensation = {
        "original": split_band_coefficients(fixed["rate"], fs, m_low),
        "denoised": split_band_coefficients(units.deg_per_h(den), fs, m_low),
        "rbf": split_band_coefficients(units.deg_per_h(rbf_c), fs, m_low),
        "ls": split_band_coefficients(units.deg_per_h(ls_c), fs, m_low),
    }
    fv = config.fixed().vibration
    a_fixed = float(fv.amplitude(fv.duration / 2))  # displacement-limited steady amplitude [m/s^2]
    true_fixed_bias = float(units.to_deg_per_h(model.rectified_bias(config.fixed_hz, a_fixed)))
    # residual of each compensated vibration phase against the truth: mean of (model - true
    # vibration bias) over the steady dwell (guard after switching on, before switching off)
    (_, _), (v0, v1), (_, _) = bounds
    steady = slice(int(round((v0 + config.guard_s) * fs)), int(round((v1 - config.guard_s) * fs)))
    vb_true = units.to_deg_per_h(fixed["truth/vibration_bias"])[steady]
    residual = {
        "rbf": float(np.mean(pred_rbf[steady] - vb_true)),
        "ls": float(np.mean(pred_ls[steady] - vb_true)),
        "uncompensated": float(np.mean(-vb_true)),
        "unit": "deg/h",
        "definition": ("mean over the steady vibration phase (guard after each edge) of the model's bias "
                       "minus the true vibration bias; = the step the compensated record keeps"),
    }
    tick()
    if bar is not None:
        bar.close()

    results: dict[str, Any] = {
        "phases": phases,
        "decomposition": decomposition,
        "compensation": compensation,
        "tau_min_s_for_B_K_R": m_low / fs,
        "bias_model_mse": {
            "rbf": mse_rbf,
            "ls": mse_ls,
            "unit": "(deg/h)^2",
            "against": "true steady rectified bias at the 1 Hz bin frequencies of the sweep",
            "rbf_vs_target": mse_rbf_t,
            "ls_vs_target": mse_ls_t,
            "rbf_neurons": int(bm.rbf.n_neurons_),
        },
        "bias_at_fixed_hz": {
            "frequency_hz": config.fixed_hz,
            "true": true_fixed_bias,
            "denoised_mean_during_vibration": float(np.mean(den[on]) - np.mean(den[: int(np.argmax(on))])),
            "rbf": float(bm.rbf.predict(np.array([[min(max(config.fixed_hz, lo_t), hi_t)]]))[0]),
            "ls": float(bm.ls(min(max(config.fixed_hz, lo_t), hi_t))),
            "training_range_hz": [lo_t, hi_t],
            "unit": "deg/h",
        },
        "compensation_residual": residual,
        "record": {
            "output_rate_hz": fs,
            "physics_rate_hz": config.fog.physics_rate_hz,
            "phase_durations_s": [config.static_before_s, config.vibration_s, config.static_after_s],
            "guard_s": config.guard_s,
        },
    }

    # --- tables
    tables = [
        _coef_table("Table 1. Allan coefficients of the three phases of the 500 Hz record (95 % intervals)",
                    {f"phase {k}": v for k, v in phases.items()},
                    note=(f"Phase 1 static, 2 vibration, 3 static; a guard of {config.guard_s:g} s after each switching edge is "
                          "excluded. '< x' = not identifiable from the segment, 95 % upper bound (set by the "
                          "segment's white and flicker noise). The simulated gyro has static K = "
                          f"{config.fog.K_deg_h_sqrt_h:g} deg/h/sqrt(h) and R = {config.fog.R_deg_h2:g} deg/h^2, "
                          "which only records of days could identify (they overtake B beyond ~20 h on the "
                          "Allan curve); with the 3-minute runtime budget (phases of minutes) K and R are "
                          "reported as bounds and their comparisons as not testable. Paper: every "
                          "coefficient rises in phase 2; phases 1 and 3 nearly equal.")),
        _coef_table(f"Table 2. Sweep record: original vs reconstructed bias (a{j}) vs drift + noise (d1..d{j})",
                    decomposition,
                    note=(f"Q, N from the full tau range; B, K, R from tau >= 2^{j + 1}/fs = {m_low / fs:.3g} s, for "
                          f"every column (the bias part's ADEV below ~2^{j} samples rises with slope +1, a smooth "
                          "signal, which a fit would read as a large R: an artefact of the low-pass). Paper: the bias "
                          "part loses most of Q, N and R and keeps B and K; drift + noise the opposite.")),
        _coef_table("Table 3. 500 Hz record: original, wavelet-denoised, RBF- and LS-compensated",
                    compensation,
                    note=(f"Q, N from the full tau range; B, K, R from tau >= 2^{j + 1}/fs = {m_low / fs:.3g} s, for "
                          f"every column (a{j} is smooth below ~2^{j} samples by construction and its ADEV there would "
                          "read as a spurious rate ramp). Paper: denoising lowers Q and N; compensation lowers B, K, R; "
                          "RBF lower than LS.")),
        Table("Bias model error against vibration frequency",
              ["model", "MSE vs true bias [(deg/h)^2]", "MSE vs A6 target [(deg/h)^2]", f"bias at {config.fixed_hz:g} Hz [deg/h]"],
              [[f"RBF (newrb, spread {config.rbf_spread_hz:g} Hz, goal {config.rbf_goal_deg_h2:g})", mse_rbf,
                mse_rbf_t, results["bias_at_fixed_hz"]["rbf"]],
               [f"{config.ls_order}th-order least squares", mse_ls, mse_ls_t, results["bias_at_fixed_hz"]["ls"]],
               ["truth", 0.0, float(np.mean((bm.truth_bins - bm.y_bins) ** 2)), true_fixed_bias]],
              note=(f"RBF neurons: {bm.rbf.n_neurons_}; training range {lo_t:.4g}-{hi_t:.4g} Hz (the steady-"
                    f"amplitude sweep; {config.fixed_hz:g} Hz is read at the top of it). With spread "
                    f"{config.rbf_spread_hz:g} Hz on 1 Hz bins the network nearly interpolates its noisy "
                    "targets (MSE vs target ~ goal, vs truth ~ the targets' own noise): the paper's method, "
                    "as it is. Paper: the RBF approximation is far better than the 4th-order fit.")),
        Table("Residual bias of the compensated 500 Hz vibration phase against the truth",
              ["compensation", "mean residual [deg/h]"],
              [["none (true bias removed by nothing)", residual["uncompensated"]],
               ["RBF", residual["rbf"]], [f"{config.ls_order}th-order LS", residual["ls"]]],
              note=residual["definition"] + "."),
    ]

    # --- headlines (decision rules: module docstring)
    headlines = []
    p1, p2, p3 = phases["1"], phases["2"], phases["3"]
    for t in TERMS:
        (ok1, why1), (ok3, why3) = _higher(p2[t], p1[t]), _higher(p2[t], p3[t])
        basis = why1 if why1 == why3 else f"vs phase 1: {why1}; vs phase 3: {why3}"
        headlines.append(Headline(
            f"Table 1 {t}: phase 2 higher than phases 1 and 3 [{p2[t]['unit']}]",
            f"{_text(p1[t])} / {_text(p2[t])} / {_text(p3[t])}",
            "phase 2 clearly higher",
            _all_or_none([ok1, ok3]),
            basis,
        ))
    testable = [t for t in TERMS if _ident(p1[t], p3[t])]
    bounded = [t for t in TERMS if t not in testable]
    if testable:
        headlines.append(Headline(
            f"Table 1 {', '.join(testable)}: phases 1 and 3 agree",
            ", ".join(f"{t} {'overlap' if _overlap(p1[t], p3[t]) else 'DIFFER'}" for t in testable),
            "nearly equal", all(_overlap(p1[t], p3[t]) for t in testable), "95 % intervals overlap"))
    if bounded:
        headlines.append(Headline(
            f"Table 1 {', '.join(bounded)}: phases 1 and 3 agree",
            ", ".join(f"{t} {_text(p1[t])} / {_text(p3[t])}" for t in bounded),
            "nearly equal" + (" (K, R slightly lower after)" if {"K", "R"} & set(bounded) else ""),
            None, NOT_TESTABLE))

    def lower_by(orig: dict, proc: dict, factor: float) -> tuple[str, bool | None, str]:
        """Conservative ratio original / processed: original's lower bound over processed's upper bound."""
        if orig["value"] is None:
            return f"original {_text(orig)}", None, NOT_TESTABLE
        ratio = orig["low"] / proc["high"] if proc["high"] > 0 else math.inf
        return (f">= {ratio:.3g}x ({_text(orig)} vs {_text(proc)})", ratio >= factor,
                "original's lower 95 % bound / processed upper 95 % bound")

    o, b = decomposition["original"], decomposition["bias"]
    for t in ("Q", "N"):
        txt, ok, why = lower_by(o[t], b[t], 5.0)
        headlines.append(Headline(f"Table 2 {t}: original / bias part", txt, ">= 5x lower", ok, why))
    if _ident(b["B"], o["B"]):
        b_in = o["B"]["low"] <= b["B"]["value"] <= o["B"]["high"]
        why = "bias value inside the original's 95 % interval"
    else:
        b_in, why = None, NOT_TESTABLE
    headlines.append(Headline("Table 2 B: bias part keeps B", f"{_text(b['B'])} vs original {_text(o['B'])}",
                              "within the original's interval", b_in, why))
    do, dd = compensation["original"], compensation["denoised"]
    for t in ("Q", "N"):
        txt, ok, why = lower_by(do[t], dd[t], 5.0)
        headlines.append(Headline(f"Table 3 {t}: original / denoised", txt, "clearly lower (>= 5x)", ok, why))
    cr, cl = compensation["rbf"], compensation["ls"]
    for t in ("B", "K", "R"):
        ok, why = _higher(cl[t], cr[t])  # "RBF lower" = LS shown higher than RBF
        headlines.append(Headline(f"Table 3 {t}: RBF-compensated below LS-compensated [{cr[t]['unit']}]",
                                  f"{_text(cr[t])} vs {_text(cl[t])}", "RBF lower", ok, why))
    headlines.append(Headline("Bias model MSE RBF / LS (vs truth)", f"{mse_rbf:.3g} / {mse_ls:.3g} (deg/h)^2",
                              "RBF <= LS / 5", mse_rbf <= mse_ls / 5.0, f"ratio {mse_rbf / mse_ls:.3g}"))
    headlines.append(Headline(
        f"Residual bias of the compensated {config.fixed_hz:g} Hz vibration phase vs truth, RBF / LS [deg/h]",
        f"{residual['rbf']:+.3g} / {residual['ls']:+.3g} (uncompensated {residual['uncompensated']:+.3g})",
        "RBF residual smaller than LS", abs(residual["rbf"]) < abs(residual["ls"]),
        f"{config.fixed_hz:g} Hz read at {hi_t:.4g} Hz; RBF value = one noisy bin mean (interpolating network)"))

    figures = [
        FigureSpec("fig1_records", "Fig. 1: the two records (block means), static -> vibration -> static",
                   _fig_records([sweep, fixed], config)),
        FigureSpec("fig2_spectrum_cwt",
                   "Fig. 2: FFT spectrum vs continuous-wavelet time-frequency map, 500 Hz record. The paper's EMD "
                   "panel is not drawn: maintained EMD packages exist (PyPI EMD-signal/PyEMD, emd), but we do not "
                   "add a dependency with extra dependencies of its own for one panel whose only role in the paper "
                   "is to show that EMD does not separate the three phases.",
                   fig2),
        FigureSpec("fig3_multiscale", "Fig. 3: multiscale view of the sweep record (db4, 10 levels)",
                   _fig_multiscale(dec_s, sweep.time)),
        FigureSpec("fig4_split", f"Fig. 4: a{j + 1}, a{j} (bias), d{j}, d1 and the reconstructed drift + noise",
                   _fig_split(dec_s, sweep.time, config)),
        FigureSpec("fig6_bias_models", "Fig. 6: RBF vs 4th-order LS bias model against vibration frequency",
                   _fig_models(bm, model, config)),
        FigureSpec("fig7_8_compensation", "Figs. 7-8: denoising and bias compensation of the 500 Hz record",
                   _fig_compensation(fixed.time, y_fixed, den, rbf_c, ls_c)),
    ]
    held = sum(1 for h in headlines if h.holds is True)
    n_testable = sum(1 for h in headlines if h.holds is not None)
    n_untestable = len(headlines) - n_testable
    return Outcome(
        scenario=NAME,
        title=TITLE,
        seed=seed,
        config=config,
        results=results,
        tables=tables,
        figures=figures,
        headlines=headlines,
        conclusion=(
            f"{held} of {n_testable} testable conclusions of the paper hold on the simulated records; "
            f"{n_untestable} are not testable here (K and R, and B where it is only bounded: not identifiable "
            "in records of minutes, 95 % bounds only; K and R need records of days). Vibration "
            "raises Q, N and B through noise growth, the aliased drive tone and the controller-driven "
            "fluctuation of the rectified bias; the a6 approximation removes the high-frequency terms and "
            "keeps the bias; an RBF network follows the resonant bias curve that a 4th-order polynomial cannot, "
            "but with spread 1.2 Hz it also reproduces the noise of its binned training targets, so the bias it "
            f"removes at {config.fixed_hz:g} Hz is one noisy bin mean (residual in the table above). "
            "Residual spikes remain at the vibration on/off edges, as in the paper's figure 8."
        ),
        runtime_s=time.perf_counter() - t_start,
    )


# ------------------------------------------------------------------------------------------ bench
def _bench_arrays(rec: Recording, config: Config, dec=None):
    """Block means at ``bench_rate_hz``: X = [frequency Hz, acceleration g], output [deg/h], truth [deg/h], a6 [deg/h]."""
    k = max(1, int(round(rec.fs / config.bench_rate_hz)))
    y = units.to_deg_per_h(rec["rate"])
    if dec is None:
        dec = decompose(y, rec.fs, wavelet=config.wavelet, level=config.level)
    a6 = dec.approx(config.bias_level)
    vb = units.to_deg_per_h(rec["truth/vibration_bias"])
    f = _block(rec["shaker_frequency"], k)
    a = _block(units.to_g(rec["shaker_amplitude"]), k)
    x = np.column_stack([f, a])
    return x, _block(y, k), _block(y - vb, k), _block(a6, k)


def compensation_task(config: Config, seed: int) -> CompensationTask:
    """Train on the sweep's a6 bias against [frequency, acceleration]; hold out another seed's sweep and 500 Hz records.

    Samples are block means at ``config.bench_rate_hz`` (2 Hz: a6 holds nothing above
    fs/2^7 = 3.1 Hz). Target (``"error"``): the a6 bias minus its phase-1 mean [deg/h].
    Held-out truth: the output with the true rectified bias removed, so the default
    MSE score [(deg/h)^2] is the bias model's error alone.
    """
    sweep, _ = simulate(config, seed)
    x, _, _, a6 = _bench_arrays(sweep, config)
    on = x[:, 1] > 0
    first_on = int(np.argmax(on)) if on.any() else len(on)
    y = a6 - (np.mean(a6[:first_on]) if first_on else 0.0)
    y = np.where(on, y, 0.0)  # static samples: no vibration error to learn
    held = []
    h_sweep, h_fixed = simulate(config, seed + 1_000_003)
    for label, rec in (("sweep", h_sweep), ("fixed", h_fixed)):
        xh, out, truth, _ = _bench_arrays(rec, config)
        held.append(HeldOutRun(label=label, X=xh, output=out, truth=truth))
    return CompensationTask(
        scenario=NAME,
        feature_names=("frequency_hz", "acceleration_g"),
        X_train=x,
        y_train=y,
        heldout=tuple(held),
        target="error",
        unit="deg/h",
        scorer=mse_scores,
    )
