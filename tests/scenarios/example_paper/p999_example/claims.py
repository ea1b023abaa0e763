"""The example paper's claim and its one deviation, as data."""

from __future__ import annotations

from typing import Any

from gyrobench.scenarios.claims import Claim, Deviation, below

__all__ = ["CLAIMS", "DEVIATIONS", "claims_for"]

PAPER = "999"

CLAIMS = (
    Claim(
        id="999.bias",
        paper=PAPER,
        where="Sec. 2",
        statement="The record mean is within three standard errors of the bias.",
        kind="emergent",
        quantity="abs_z",
        comparator=below(3.0),
        paper_value=3.0,
    ),
)

DEVIATIONS = (
    Deviation(
        paper=PAPER,
        what="record length",
        paper_says="one hour",
        we_do="ten minutes",
        reason="a fast test",
        variant="paper_length",
    ),
)


def claims_for(config: Any) -> tuple[Claim, ...]:
    """Every claim, for any config."""
    return CLAIMS
