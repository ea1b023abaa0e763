"""Static noise records of a FOG-grade and a MEMS-grade gyro: simulate, fit, compare with truth.

The simplest end-to-end check of the noise engine and the Allan analysis: each
grade's IEEE-952 coefficients (field units, as a datasheet gives them) are
simulated on a static base, the overlapping Allan deviation is computed with its
confidence band, the five terms are fitted jointly, and the fitted values and
their 95 % intervals are set beside the truth. A term the record cannot show is
reported as "not identifiable" with an upper bound; the true value must then lie
below the bound.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field
from typing import Any, ClassVar

import numpy as np

from gyrobench.analysis.allan import allan_deviation, fit_noise
from gyrobench.base import units
from gyrobench.base.ranges import Constraint, FieldRange, validate
from gyrobench.io.recording import Channel, Recording, package_version
from gyrobench.scenarios.base import FigureSpec, Headline, Outcome, Table
from gyrobench.scenarios.reports.allan import TERMS, coefficient_table, coefficients_json
from gyrobench.scenarios.reports.figures import allan_figure
from gyrobench.sim.noise import NoiseModel

NAME = "static_noise"
TITLE = "Static noise records: fitted IEEE-952 coefficients against the truth (FOG and MEMS grade)"


#: IEEE-952 term -> its GradeSpec field, in the term's field unit (sim.units.COEFFICIENT_FIELD_UNITS)
_FIELDS = {"Q": "Q_arcsec", "N": "N_deg_sqrt_h", "B": "B_deg_h", "K": "K_deg_h_sqrt_h", "R": "R_deg_h2"}
#: fewest samples a record may have: the joint Q/N/B/K/R fit needs one tau per term (5), and
#: the default octave taus m = 1, 2, 4, ... of the overlapping deviation stop at T/4
#: (analysis.allan), so m = 16 needs 4 x 16 = 64 samples (a test pins this against analysis.allan).
#: The CLI imports it for 'simulate noise' and 'simulate SCENARIO'.
MIN_SAMPLES = 4 * 2 ** (len(TERMS) - 1)


@dataclass(frozen=True, slots=True, kw_only=True)
class GradeSpec:
    """A datasheet noise budget in field units.

    Attributes
    ----------
    label : str
        Name of the grade in the report.
    Q_arcsec : float
        Quantization Q [arcsec].
    N_deg_sqrt_h : float
        Angle random walk N [deg/sqrt(h)].
    B_deg_h : float
        Bias instability B [deg/h].
    K_deg_h_sqrt_h : float
        Rate random walk K [deg/h/sqrt(h)].
    R_deg_h2 : float
        Rate ramp R [deg/h^2].
    fs_hz : float
        Sample rate [Hz].
    duration_h : float
        Record length [h].
    """

    label: str = "grade"
    Q_arcsec: float = 0.0
    N_deg_sqrt_h: float = 0.0
    B_deg_h: float = 0.0
    K_deg_h_sqrt_h: float = 0.0
    R_deg_h2: float = 0.0
    fs_hz: float = 100.0
    duration_h: float = 1.0

    #: every numeric field's documented range, in its field unit (:class:`~gyrobench.scenarios.base.FieldRange`):
    #: noise coefficients of any gyro grade (up to a consumer MEMS part's and past it), rates and durations one
    #: record can hold (the memory estimate refuses a long record at a high rate first)
    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "Q_arcsec": FieldRange(0.0, 1e4, "arcsec", "quantization of any gyro grade"),
        "N_deg_sqrt_h": FieldRange(0.0, 1e4, "deg/sqrt(h)", "angle random walk of any gyro grade"),
        "B_deg_h": FieldRange(0.0, 1e5, "deg/h", "bias instability of any gyro grade"),
        "K_deg_h_sqrt_h": FieldRange(0.0, 1e6, "deg/h/sqrt(h)", "rate random walk of any gyro grade"),
        "R_deg_h2": FieldRange(0.0, 1e8, "deg/h^2", "rate ramp of any gyro grade"),
        "fs_hz": FieldRange(1e-3, 1e6, "Hz", "a gyro's output rate"),
        "duration_h": FieldRange(0.0, 1e4, "h", "one record", low_open=True),
    }

    #: the constraints across fields (:class:`~gyrobench.base.ranges.Constraint`)
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            f"duration_h x fs_hz >= {MIN_SAMPLES} samples",
            lambda c: c.n_samples >= MIN_SAMPLES,
            lambda c: f"duration_h x fs_hz must give >= {MIN_SAMPLES} samples (five octave taus for the fit); "
            f"got {c.duration_h!r} h at {c.fs_hz!r} Hz = {c.n_samples}",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)  # the declared specs and constraints above
        self.model()

    def model(self) -> NoiseModel:
        return NoiseModel.from_datasheet(
            quantization=self.Q_arcsec,
            angle_random_walk=self.N_deg_sqrt_h,
            bias_instability=self.B_deg_h,
            rate_random_walk=self.K_deg_h_sqrt_h,
            rate_ramp=self.R_deg_h2,
        )

    def truth(self) -> dict[str, float]:
        return {term: getattr(self, name) for term, name in _FIELDS.items()}

    @property
    def n_samples(self) -> int:
        return int(round(self.duration_h * units.HOUR * self.fs_hz))


@dataclass(frozen=True, slots=True, kw_only=True)
class Config:
    """Two grades, typical datasheet budgets (tactical FOG, industrial MEMS).

    Attributes
    ----------
    fog, mems : GradeSpec
        The two noise budgets.
    """

    fog: GradeSpec = field(
        default_factory=lambda: GradeSpec(
            label="FOG grade", Q_arcsec=0.5, N_deg_sqrt_h=0.005, B_deg_h=0.05, K_deg_h_sqrt_h=0.05,
            R_deg_h2=0.0, fs_hz=100.0, duration_h=8.0,
        )
    )
    mems: GradeSpec = field(
        default_factory=lambda: GradeSpec(
            label="MEMS grade", Q_arcsec=2.0, N_deg_sqrt_h=0.2, B_deg_h=5.0, K_deg_h_sqrt_h=20.0,
            R_deg_h2=0.0, fs_hz=100.0, duration_h=2.0,
        )
    )

    def __post_init__(self) -> None:
        validate(self)  # fog and mems must be GradeSpecs


def _grades(config: Config) -> dict[str, GradeSpec]:
    return {"fog": config.fog, "mems": config.mems}


def simulate(config: Config, seed: int) -> list[Recording]:
    """One static record per grade: output rate [rad/s], truth = zero true rate + each noise term.

    Parameters
    ----------
    config : Config
        The scenario's configuration.
    seed : int
        Seed of the record's random streams.

    Returns
    -------
    list of Recording
        One per grade.
    """
    children = np.random.default_rng(seed).spawn(2)
    recs = []
    for (key, spec), rng in zip(_grades(config).items(), children, strict=True):
        n = spec.n_samples
        comps = spec.model().components(n, spec.fs_hz, rng=rng)
        out = np.zeros(n)
        for v in comps.values():
            out += v
        truth = {"true_rate": Channel(np.zeros(n), "rad/s", "table rate (static)")}
        truth.update({k: Channel(v, "rad/s", f"{k} error term") for k, v in comps.items()})
        recs.append(
            Recording(
                fs=spec.fs_hz,
                channels={"output": Channel(out, "rad/s", "gyro output")},
                truth=truth,
                metadata={
                    "scenario": NAME, "grade": key, "spec": asdict(spec), "seed": seed, "version": package_version(),
                    "error_components": list(comps),
                },
                name=f"static_{key}",
            )
        )
    return recs


def run(config: Config, seed: int, *, progress: bool = False) -> Outcome:
    """Simulate both grades, fit, and compare each fitted coefficient with its true value.

    Parameters
    ----------
    config : Config
        The scenario's configuration.
    seed : int
        Seed of the record's random streams.
    progress : bool
        Show progress bars.

    Returns
    -------
    Outcome
        Tables, figures and each coefficient's fitted and true value.
    """
    t_start = time.perf_counter()
    recs = simulate(config, seed)
    tables: list[Table] = []
    figures: list[FigureSpec] = []
    headlines: list[Headline] = []
    results: dict[str, Any] = {"grades": {}}
    for rec, (key, spec) in zip(recs, _grades(config).items(), strict=True):
        curve = allan_deviation(rec["output"], rec.fs, taus="octave")
        fit = fit_noise(curve)
        truth = spec.truth()
        js = coefficients_json(fit)
        results["grades"][key] = {"label": spec.label, "true": truth, "fitted": js}
        tables.append(coefficient_table(fit, title=f"{spec.label}: fitted vs true coefficients", truth=truth))
        model = spec.model()
        figures.append(
            FigureSpec(
                f"adev_{key}",
                f"{spec.label}: overlapping ADEV with its confidence band, the fitted model, each term "
                "and the true curve",
                allan_figure(
                    curve, fit, title=spec.label,
                    true_avar=lambda t, m=model, fs=spec.fs_hz: m.theoretical_avar(t, fs=fs),
                ),
            )
        )
        for name in TERMS:
            d = js[name]
            t = truth[name]
            if d["value"] is None:
                ok = t <= d["high"]
                rep = f"not identifiable (< {d['high']:.3g})"
            else:
                ok = d["low"] <= t <= d["high"]
                rep = f"{d['value']:.4g} [{d['low']:.3g}, {d['high']:.3g}]"
            headlines.append(
                Headline(f"{spec.label} {name} [{d['unit']}]", rep, f"true {t:.4g}", ok,
                         "true value inside the 95 % interval" if d["value"] is not None
                         else "true value below the 95 % bound")
            )
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
            "Each grade is simulated from its datasheet coefficients and fitted by weighted NNLS on the overlapping "
            "Allan variance; a true value outside its 95 % interval is expected in about 1 of 20 terms."
        ),
        runtime_s=time.perf_counter() - t_start,
    )


def memory_estimate(config: Config) -> float:
    """Peak memory of :func:`run` (and of :func:`simulate`) [bytes], before allocating.

    9 float64 series per sample of both grades together: :func:`simulate` holds the
    output, the zero true rate and the five noise terms (7) plus the working copies of
    the term being generated; the Allan analysis in :func:`run` stays below that peak.
    Measured: 8.09 series (peak RSS increase, 7.2e6 samples: 2 h at 1 kHz) for both
    simulate and run; 9 is that rounded up. Computed in floats, so an absurd duration
    gives a huge (or infinite) estimate, never an overflow.

    Parameters
    ----------
    config : Config
        The scenario's configuration.

    Returns
    -------
    float
        The estimate [bytes].
    """
    from gyrobench.base import memory

    n = sum(float(s.duration_h) * units.HOUR * float(s.fs_hz) for s in _grades(config).values())
    return memory.series_bytes(n, 9)
