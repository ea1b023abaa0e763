"""The example paper's configuration: declared field specs, no hand-written checks."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass
from typing import ClassVar

from gyrobench.base.ranges import Constraint, FieldRange, validate

__all__ = ["Config", "control_config", "variant_config"]


@dataclass(frozen=True, slots=True, kw_only=True)
class Config:
    """A static record of a gyro with a constant bias and white rate noise (field units in the names)."""

    bias_deg_h: float = 1.0
    arw_deg_sqrt_h: float = 0.1
    fs_hz: float = 10.0
    duration_s: float = 600.0

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "bias_deg_h": FieldRange(-1e4, 1e4, "deg/h", "the gyro's constant bias; any grade"),
        "arw_deg_sqrt_h": FieldRange(0.0, 100.0, "deg/sqrt(h)", "angle random walk; any grade"),
        "fs_hz": FieldRange(0.0, 1e4, "Hz", "output rate", low_open=True),
        "duration_s": FieldRange(0.0, 86400.0, "s", "record length, one day at most", low_open=True),
    }
    CONSTRAINTS: ClassVar[tuple[Constraint, ...]] = (
        Constraint(
            "duration_s x fs_hz >= 2",
            lambda c: c.duration_s * c.fs_hz >= 2,
            lambda c: f"duration_s x fs_hz must give >= 2 samples; got {c.duration_s!r} s at {c.fs_hz!r} Hz",
        ),
    )

    def __post_init__(self) -> None:
        validate(self)

    @property
    def n_samples(self) -> int:
        """Samples in the record."""
        return int(round(self.duration_s * self.fs_hz))


def control_config(config: Config) -> Config:
    """The control population: the same units with no bias."""
    return dataclasses.replace(config, bias_deg_h=0.0)


def variant_config(config: Config, name: str) -> Config:
    """The paper's protocol for a deviation: ``paper_length`` (a one-hour record)."""
    if name == "paper_length":
        return dataclasses.replace(config, duration_s=3600.0)
    raise ValueError(f"example variant must be 'paper_length'; got {name!r}")
