"""One unit of the example paper: a static record and its mean."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from gyrobench.base import units
from gyrobench.io.recording import Channel, Recording

from .config import Config

__all__ = ["UnitResult", "experiment", "memory_estimate", "simulate"]


@dataclass(frozen=True, slots=True, kw_only=True)
class UnitResult:
    """One unit: its bias estimate [deg/h] and the estimate's error in standard errors."""

    seed: int
    estimate_deg_h: float
    z: float

    @property
    def quantities(self) -> Mapping[str, float | None]:
        return {"abs_z": abs(self.z), "estimate_deg_h": self.estimate_deg_h}


def _rate_deg_h(config: Config, seed: int) -> np.ndarray:
    """The record [deg/h]: b + (60 N sqrt(fs)) w, w standard normal (module docstring)."""
    rng = np.random.default_rng(seed)
    sigma = 60.0 * config.arw_deg_sqrt_h * math.sqrt(config.fs_hz)
    return config.bias_deg_h + sigma * rng.standard_normal(config.n_samples)


def simulate(config: Config, seed: int) -> list[Recording]:
    """The unit's static record with its truth (SI: rad/s)."""
    y = _rate_deg_h(config, seed)
    bias = np.full(y.shape, units.deg_per_h(config.bias_deg_h))
    return [
        Recording(
            fs=config.fs_hz,
            channels={"rate": Channel(units.deg_per_h(y), "rad/s")},
            truth={"bias": Channel(bias, "rad/s")},
            metadata={"seed": seed},
            name="static",
        )
    ]


def experiment(config: Config, seed: int) -> UnitResult:
    """The bias estimate (record mean) and its error over the standard error 60 N / sqrt(T)."""
    y = _rate_deg_h(config, seed)
    estimate = float(np.mean(y))
    se = 60.0 * config.arw_deg_sqrt_h / math.sqrt(config.n_samples / config.fs_hz)
    z = (estimate - config.bias_deg_h) / se if se > 0 else 0.0
    return UnitResult(seed=seed, estimate_deg_h=estimate, z=float(z))


def memory_estimate(config: Config) -> float:
    """Peak bytes of one unit: the record and its truth in float64, twice over."""
    return 4.0 * 8 * config.n_samples
