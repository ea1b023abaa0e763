"""The example paper's report, from the units' results only."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from gyrobench.scenarios.base import Outcome, Table
from gyrobench.scenarios.claims import ClaimResult

__all__ = ["report"]


def report(config: Any, units: Sequence[Any], claims: Sequence[ClaimResult]) -> Outcome:
    """One table: each unit's bias estimate and its error in standard errors."""
    rows = [[u.seed, u.estimate_deg_h, u.z] for u in units]
    return Outcome(
        scenario="example_bias",
        title="Example paper: a gyro's bias as the mean of a static record (tests only)",
        seed=0,
        config=config,
        results={"estimates_deg_h": [u.estimate_deg_h for u in units]},
        tables=[Table("Bias estimate per unit", ["seed", "estimate [deg/h]", "z"], rows)],
        conclusion="the record mean estimates the bias",
        claims=list(claims),
        units=len(units),
    )
