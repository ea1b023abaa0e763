"""Paper 000's configuration: the gyro (:class:`FogSpec`) and the experiment (:class:`Config`).

Defaults are the paper's protocol where it states one; the values it leaves open are listed
in the package docstring and in :data:`~.claims.DEVIATIONS`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any, ClassVar, Literal

import numpy as np

from gyrobench.base import units
from gyrobench.base.ranges import Constraint, FieldRange, ordered, validate
from gyrobench.sim.earth import NANJING
from gyrobench.sim.fiber_strain import StrainMode
from gyrobench.sim.fog_loop import ClosedLoopFOG, LoopSpec
from gyrobench.sim.fog_optics import OpticalBudget
from gyrobench.sim.mount_coning import MountConing, RockingMode
from gyrobench.sim.noise import NoiseModel
from gyrobench.sim.shaker import FixedSine, Phased, SineSweep

from .identify import IDENTIFIED, INPUTS, mount_factors

__all__ = ["Config", "FogSpec", "split_level_m"]


def _default_modes() -> tuple[StrainMode, ...]:
    """The closed-loop FOG's assumed structural modes (:mod:`gyrobench.sim.fog_loop` defaults)."""
    return ClosedLoopFOG().modes


@dataclass(frozen=True, slots=True, kw_only=True)
class FogSpec:
    """The gyro: a closed-loop FOG (:class:`~gyrobench.sim.fog_loop.ClosedLoopFOG`), unit spread.

    The loop, optics and structural modes are the module defaults of :mod:`gyrobench.sim.fog_loop`
    (1 km, 10 cm coil; ARW from the optical budget; modes assumed, no paper number used).
    ``mount``: the two rocking modes of the gyro's mount whose coning rectifies vibration into a
    DC rate (:mod:`gyrobench.sim.mount_coning`; identified in :mod:`.identify`; None: no mount
    modes, the earlier device). Additive IEEE-952 terms (what the optics do not produce;
    intermediate grade, B chosen so the static phases identify it, :mod:`.identify`):
    ``Q_arcsec`` readout quantization, ``B_deg_h`` bias instability, ``K_deg_h_sqrt_h`` rate
    random walk, ``R_deg_h2`` rate ramp. Site: ``latitude_deg`` (paper 000's lab, Southeast
    University, Nanjing: :data:`gyrobench.sim.earth.PAPER_SITES`), sense axis horizontal as
    the paper says, ``azimuth_deg`` from north toward east (not stated by the paper; north
    assumed: Earth-rate component Omega_e cos(lat) = 12.7 deg/h, constant through the record).

    Unit-to-unit spread (one seed = one drawn FOG; assumed, no source: assembly tolerances):
    each mode's frequency x (1 + ``mode_frequency_spread`` N(0, 1)), its strain, rocking and
    loss couplings x exp(``coupling_spread`` N(0, 1)) independently.
    ``physics_rate_hz`` is the shaker's sampling rate (an even multiple of ``output_rate_hz``).

    Attributes
    ----------
    loop : LoopSpec
        The closed loop (coil, modulation, gains).
    optics : OpticalBudget
        The optical budget (its ARW).
    modes : tuple of StrainMode
        The structural modes that strain the coil.
    mount : MountConing or None
        The mount's two rocking modes (None: no mount modes).
    Q_arcsec : float
        Readout quantization Q [arcsec].
    B_deg_h : float
        Bias instability B [deg/h].
    K_deg_h_sqrt_h : float
        Rate random walk K [deg/h/sqrt(h)].
    R_deg_h2 : float
        Rate ramp R [deg/h^2].
    latitude_deg : float
        Site latitude [deg].
    azimuth_deg : float
        Sense-axis azimuth from north toward east [deg].
    mode_frequency_spread : float
        Relative 1-sigma of each mode's frequency between units [-].
    coupling_spread : float
        1-sigma of each coupling's log factor between units [-].
    physics_rate_hz : float
        The shaker's sampling rate [Hz].
    output_rate_hz : float
        The gyro's output rate [Hz].
    """

    loop: LoopSpec = field(default_factory=LoopSpec)
    optics: OpticalBudget = field(default_factory=OpticalBudget)
    modes: tuple[StrainMode, ...] = field(default_factory=_default_modes)
    mount: MountConing | None = field(default_factory=IDENTIFIED.mount)
    Q_arcsec: float = INPUTS.Q_arcsec
    B_deg_h: float = INPUTS.B_deg_h
    K_deg_h_sqrt_h: float = INPUTS.K_deg_h_sqrt_h
    R_deg_h2: float = INPUTS.R_deg_h2
    latitude_deg: float = units.to_deg(NANJING.latitude)
    azimuth_deg: float = 0.0
    mode_frequency_spread: float = INPUTS.frequency_spread
    coupling_spread: float = INPUTS.compliance_spread
    physics_rate_hz: float = 3200.0
    output_rate_hz: float = 400.0

    #: documented ranges; the loop, optics and mount state theirs in :mod:`gyrobench.sim`
    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "Q_arcsec": FieldRange(0, 1000, "arcsec", "readout quantization; a FOG's is < 1 arcsec"),
        "B_deg_h": FieldRange(0, 1e4, "deg/h", "bias instability, navigation (0.001) to rate grade (1000)"),
        "K_deg_h_sqrt_h": FieldRange(0, 1e4, "deg/h/sqrt(h)", "rate random walk, >= 0"),
        "R_deg_h2": FieldRange(0, 1e5, "deg/h^2", "rate ramp, >= 0"),
        "latitude_deg": FieldRange(-90, 90, "deg", "geographic latitude"),
        "azimuth_deg": FieldRange(-360, 360, "deg", "sense-axis azimuth from north toward east"),
        "mode_frequency_spread": FieldRange(0, 0.3, "1", "relative 1-sigma; draws clipped to 0.5-1.5x", high_open=True),
        "coupling_spread": FieldRange(0, 2, "1", "1-sigma of the log coupling factor", high_open=True),
        "physics_rate_hz": FieldRange(0, 1e5, "Hz", "shaker sampling, >= 4x the vibration", low_open=True),
        "output_rate_hz": FieldRange(0, 5e4, "Hz", "output rate = physics_rate_hz / even n", low_open=True),
    }

    #: the constraints across fields (:class:`~gyrobench.base.ranges.Constraint`)
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "physics_rate_hz = 2 n x output_rate_hz",
            lambda c: (m := c.physics_rate_hz / c.output_rate_hz) >= 2 and abs(m - 2 * round(m / 2)) < 1e-9,
            lambda c: "physics_rate_hz must be an even integer multiple of output_rate_hz = "
            f"{c.output_rate_hz!r} Hz; got {c.physics_rate_hz!r} Hz",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above
        self.unit(self.modes)  # the SI model validates every value

    def noise(self) -> NoiseModel:
        return NoiseModel.from_datasheet(
            quantization=self.Q_arcsec,
            bias_instability=self.B_deg_h,
            rate_random_walk=self.K_deg_h_sqrt_h,
            rate_ramp=self.R_deg_h2,
        )

    def unit(self, modes: tuple[StrainMode, ...]) -> ClosedLoopFOG:
        """The FOG with the given (drawn) structural modes."""
        return ClosedLoopFOG(
            loop=self.loop,
            optics=self.optics,
            noise=self.noise(),
            modes=modes,
            latitude=units.deg(self.latitude_deg),
            azimuth=units.deg(self.azimuth_deg),
            elevation=0.0,
        )

    def draw(self, rng: np.random.Generator) -> ClosedLoopFOG:
        """One unit: the modes' frequencies and couplings drawn with the stated spreads."""
        n = len(self.modes)
        fs = np.clip(1.0 + self.mode_frequency_spread * rng.standard_normal(n), 0.5, 1.5)
        cs = np.exp(self.coupling_spread * rng.standard_normal((n, 3)))
        modes = tuple(
            replace(
                md,
                frequency=md.frequency * float(fs[i]),
                strain=md.strain * float(cs[i, 0]),
                rocking=md.rocking * float(cs[i, 1]),
                loss=md.loss * float(cs[i, 2]),
            )
            for i, md in enumerate(self.modes)
        )
        return self.unit(modes)

    def draw_mount(self, rng: np.random.Generator) -> MountConing | None:
        """The unit's mount: each rocking mode's frequency x (1 + ``mode_frequency_spread`` N(0, 1))
        and compliance x exp(``coupling_spread`` N(0, 1)) (None without a mount)."""
        if self.mount is None:
            return None
        fs, cs = mount_factors(rng, self.mode_frequency_spread, self.coupling_spread)

        def one(m: RockingMode, i: int) -> RockingMode:
            return replace(m, frequency=m.frequency * float(fs[i]), compliance=m.compliance * float(cs[i]))

        return MountConing(x=one(self.mount.x, 0), y=one(self.mount.y, 1))


#: ranges shared by several fields of :class:`Config`: a shaker frequency and a phase length
_SHAKER_HZ = FieldRange(0, 2e4, "Hz", "shaker band; also <= fog.physics_rate_hz / 4", low_open=True)
_PHASE_S = FieldRange(0, 3.6e7, "s", "<= 1e4 h; the memory estimate refuses long runs", low_open=True)


def _wavelet_samples(level: int) -> int:
    """The shortest record a db4 decomposition to ``level`` takes: ``pywt.dwt_max_level`` needs
    ``len >= (8 - 1) x 2^level``."""
    return (8 - 1) * 2**level


def _record_samples(c: Config) -> float:
    """Samples in one record (static, vibration, static) at the FOG's output rate."""
    return (c.static_before_s + c.vibration_s + c.static_after_s) * c.fog.output_rate_hz


@dataclass(frozen=True, slots=True, kw_only=True)
class Config:
    """Paper 000's experiment; values the paper leaves open are documented in the package docstring.

    ``bias_level`` (6) is the approximation taken as the bias for Table 2 and the denoising of
    Table 3, ``train_level`` (7) the one the bias models are trained on, as the paper's text
    says (package docstring). ``rbf_centres``: ``"random"`` (the paper's randomly fixed centres)
    or ``"ols"`` (MATLAB newrb's orthogonal least squares; a labelled variant).
    ``acceleration_g`` 0 is the control (:func:`~.variants.control_config`: the shaker's
    controller still switches and logs its frequency, the table does not move).
    ``split_fit_range``: B, K, R of wavelet-processed signals from tau >= 2^(bias_level+1)/fs
    (True) or from the full tau range (False, a labelled variant). ``n_tone_free``: N of Table 3's
    columns from the octave taus where the dwell's aliased tones leave no Allan variance
    (:func:`~.pipeline.tone_free_m`; True) or from the full tau range (False, a labelled variant);
    the control runs the same rule (its ``fixed_hz`` is the vibrated units').

    Attributes
    ----------
    fog : FogSpec
        The gyro and its unit-to-unit spread.
    acceleration_g : float
        Sine table acceleration amplitude [g] (0: the control).
    sweep_start_hz, sweep_end_hz : float
        The sweep's start and end frequencies [Hz].
    sweep_spacing : {"log", "linear"}
        How the sweep's frequency moves between them.
    fixed_hz : float
        The fixed-frequency dwell's frequency [Hz].
    static_before_s, vibration_s, static_after_s : float
        The three phases of each record [s]: static, vibration, static.
    max_displacement_mm : float
        Shaker stroke limit [mm] (the acceleration is reduced below the frequency it caps).
    ramp_time_s : float
        Shaker amplitude ramp at each switch [s].
    control_error : float
        Relative amplitude error of the shaker's controller [-].
    control_time_s : float
        The controller's update interval [s].
    guard_s : float
        Cut after each phase's start so switching transients stay out of the steady phases [s].
    wavelet : str
        The multiscale decomposition's wavelet (a PyWavelets name).
    level : int
        Decomposition depth j.
    bias_level : int
        The approximation taken as the bias (Table 2, Table 3's denoising).
    train_level : int
        The approximation the bias models are trained on.
    bin_width_hz : float
        Frequency bin of the bias models' training tables [Hz].
    train_edge_s : float
        Excluded ends of the training record [s].
    rbf_spread_hz : float
        RBF width in the frequency input [Hz].
    rbf_goal_deg_h2 : float
        The RBF network's mean-square-error goal [(deg/h)^2].
    rbf_max_neurons : int or None
        RBF size cap (None: no cap).
    rbf_centres : {"random", "ols"}
        The RBF centres: randomly fixed (the paper) or newrb's orthogonal least squares.
    ls_order : int
        Order of the least-squares polynomial bias model.
    edge_window_s : float
        Half-width of the windows around the on/off edges scored for spikes [s].
    offset_block_s : float
        Block length of the offsets' scatter estimate [s].
    bench_rate_hz : float
        Rate the bench's samples are block means at [Hz].
    split_fit_range : bool
        B, K, R of wavelet-processed signals from tau >= 2^(bias_level+1)/fs (else the full range).
    n_tone_free : bool
        N of Table 3 from the taus the dwell's tones leave alone (else the full range).
    """

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
    train_level: int = 7
    bin_width_hz: float = 1.0
    train_edge_s: float = 0.5
    rbf_spread_hz: float = 1.2
    rbf_goal_deg_h2: float = 1e-4
    rbf_max_neurons: int | None = None
    rbf_centres: Literal["random", "ols"] = "random"
    ls_order: int = 4
    edge_window_s: float = 3.0
    offset_block_s: float = 10.0
    bench_rate_hz: float = 2.0
    split_fit_range: bool = True
    n_tone_free: bool = True

    #: documented ranges: physical (the shaker, the wavelet) or practical (one run)
    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "acceleration_g": FieldRange(0, 100, "g", "sine amplitude; 0 is the control, shakers reach ~100 g"),
        "sweep_start_hz": _SHAKER_HZ,
        "sweep_end_hz": _SHAKER_HZ,
        "fixed_hz": _SHAKER_HZ,
        "static_before_s": _PHASE_S,
        "vibration_s": _PHASE_S,
        "static_after_s": _PHASE_S,
        "max_displacement_mm": FieldRange(0, 1000, "mm", "shaker stroke limit (25.4 mm p-p is typical)", low_open=True),
        "ramp_time_s": FieldRange(0, 3600, "s", "shaker amplitude ramp"),
        "control_error": FieldRange(0, 1, "1", "relative amplitude error of the shaker controller"),
        "control_time_s": FieldRange(0, 86400, "s", "controller interval", low_open=True),
        "guard_s": FieldRange(0, 43200, "s", "excluded phase edges; also < shortest phase / 2"),
        "level": FieldRange(1, 30, "levels", "wavelet depth; records hold >= 7 x 2^level", integer=True),
        "bias_level": FieldRange(1, 30, "levels", "approximation taken as the bias; also <= level", integer=True),
        "train_level": FieldRange(1, 30, "levels", "bias models' training level; <= level", integer=True),
        "bin_width_hz": FieldRange(0, 1e4, "Hz", "frequency bin of the bias tables", low_open=True),
        "train_edge_s": FieldRange(0, 3600, "s", "excluded ends of the training record", low_open=True),
        "rbf_spread_hz": FieldRange(0, 1e5, "Hz", "RBF width in the frequency input", low_open=True),
        "rbf_goal_deg_h2": FieldRange(0, 1e6, "(deg/h)^2", "newrb's mean-square-error goal"),
        "rbf_max_neurons": FieldRange(1, 1e4, "neurons", "RBF size cap (None: no cap)", integer=True),
        "ls_order": FieldRange(1, 12, "1", "least-squares polynomial order (__post_init__)", integer=True),
        "edge_window_s": FieldRange(0, 43200, "s", "edge windows; also < guard_s", low_open=True),
        "offset_block_s": FieldRange(0, 86400, "s", "block length of the offset estimate", low_open=True),
        "bench_rate_hz": FieldRange(0, 5e4, "Hz", "rate the bench target is decimated to", low_open=True),
    }

    #: the constraints across fields (:class:`~gyrobench.base.ranges.Constraint`)
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "guard_s < shortest phase / 2",
            lambda c: c.guard_s < min(c.static_before_s, c.vibration_s, c.static_after_s) / 2,
            lambda c: "guard_s must be in [0, shortest phase/2) s = [0, "
            f"{min(c.static_before_s, c.vibration_s, c.static_after_s) / 2!r}) s; got {c.guard_s!r}",
        ),
        ordered("bias_level", "level", strict=False, unit="levels"),
        ordered("train_level", "level", strict=False, unit="levels"),
        Constraint(
            "edge_window_s < guard_s",
            lambda c: c.edge_window_s < c.guard_s,
            lambda c: f"edge_window_s must be < guard_s = {c.guard_s!r} s (edge windows and steady phases "
            f"must not overlap); got {c.edge_window_s!r}",
        ),
        Constraint(
            "max(sweep_start_hz, sweep_end_hz, fixed_hz) <= fog.physics_rate_hz / 4",
            lambda c: max(c.sweep_start_hz, c.sweep_end_hz, c.fixed_hz) <= c.fog.physics_rate_hz / 4,
            lambda c: f"fog.physics_rate_hz must be >= 4 x the highest vibration frequency "
            f"({max(c.sweep_start_hz, c.sweep_end_hz, c.fixed_hz)!r} Hz) = "
            f"{4 * max(c.sweep_start_hz, c.sweep_end_hz, c.fixed_hz)!r} Hz; got {c.fog.physics_rate_hz!r} Hz",
        ),
        Constraint(
            "record samples >= 7 x 2^level",
            lambda c: _record_samples(c) >= _wavelet_samples(c.level),
            lambda c: f"level = {c.level} needs records of >= {_wavelet_samples(c.level)} samples; got "
            f"{int(_record_samples(c))} (lengthen the phases or lower the level)",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above

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
        s = SineSweep(
            f_start=self.sweep_start_hz,
            f_end=self.sweep_end_hz,
            duration=self.vibration_s,
            spacing=self.sweep_spacing,
            **self._common(),
        )
        return Phased(
            vibration=s, static_before=self.static_before_s, static_after=self.static_after_s
        )

    def fixed(self) -> Phased:
        s = FixedSine(frequency=self.fixed_hz, duration=self.vibration_s, **self._common())
        return Phased(
            vibration=s, static_before=self.static_before_s, static_after=self.static_after_s
        )


def split_level_m(config: Config) -> int:
    """Smallest cluster size [samples] of the B, K, R fits of wavelet-processed signals.

    Smallest cluster size [samples] for B, K, R of wavelet-processed signals: 2^(bias_level + 1)
    (1, the full tau range, when ``config.split_fit_range`` is False: the labelled variant).

    Parameters
    ----------
    config : Config
        The configuration.

    Returns
    -------
    int
        2^(bias_level + 1), or 1 when ``config.split_fit_range`` is False.
    """
    return 2 ** (config.bias_level + 1) if config.split_fit_range else 1
