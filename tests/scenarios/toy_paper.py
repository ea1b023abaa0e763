"""A tiny paper scenario (the shape of CONTRACT13), used only by the runner tests.

Each unit draws its own gain ``g ~ lognormal(0, sigma)`` and a noisy record
``y = g x + w``; it "reproduces" a fictitious paper whose claims are that the fitted
gain is about 1 (within 2x), that the residual is below a level, and that the
fit is sane in every run. One claim is only testable on even seeds (None on odd
ones) to exercise the None path. ``GYROBENCH_TOY_CALL_LOG``: each ``experiment``
call appends ``"<seed>\\n"`` to that file (the resume test counts them);
``GYROBENCH_TOY_FAIL_SEED``: ``experiment`` raises for that seed (an interrupted run).
"""

from __future__ import annotations

import os
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from gyrobench.scenarios.base import Outcome, Table
from gyrobench.scenarios.claims import Claim, ClaimResult, Deviation, below, is_true, within_factor

NAME = "toy_paper"
TITLE = "Toy paper: a gain fitted on noisy records (runner tests only)"
PAPER = "toy"


@dataclass(frozen=True, slots=True, kw_only=True)
class Config:
    n_samples: int = 200
    gain_sigma: float = 0.5
    noise: float = 0.1
    sleep_s: float = (
        0.0  # wall time added per unit (the SIGKILL test needs units that take a while)
    )


def control_config(config: Config) -> Config:
    """The control population: the same units with no measurement noise."""
    import dataclasses

    return dataclasses.replace(config, noise=0.0)


def simulate(config: Config, seed: int) -> list:
    return []


def experiment(config: Config, seed: int) -> dict[str, Any]:
    log = os.environ.get("GYROBENCH_TOY_CALL_LOG")
    if log:
        fd = os.open(log, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
        try:
            os.write(fd, f"{seed}\n".encode())
        finally:
            os.close(fd)
    if os.environ.get("GYROBENCH_TOY_FAIL_SEED") == str(seed):
        raise RuntimeError(f"toy_paper: failing on purpose at seed {seed}")
    if config.sleep_s:
        time.sleep(config.sleep_s)
    rng = np.random.default_rng(seed)
    g = float(rng.lognormal(0.0, config.gain_sigma))
    x = rng.standard_normal(config.n_samples)
    y = g * x + config.noise * rng.standard_normal(config.n_samples)
    A = np.column_stack([x, np.ones_like(x)])
    coef = np.linalg.lstsq(A, y, rcond=None)[0]
    resid = float(np.std(y - A @ coef))
    return {
        "quantities": {
            "gain": float(coef[0]),
            "residual": resid,
            "sane": 1.0 if np.isfinite(coef).all() else 0.0,
            "even_only": float(coef[0]) if seed % 2 == 0 else None,
        },
        "trace": y[:20],
    }


CLAIMS = (
    Claim(
        id="toy.gain",
        paper=PAPER,
        where="Table 1",
        statement="The gain is about 1.",
        kind="emergent",
        quantity="gain",
        comparator=within_factor(1.0, 2.0),
        paper_value=1.0,
    ),
    Claim(
        id="toy.residual",
        paper=PAPER,
        where="Sec. 3",
        statement="The residual is below 0.05.",
        kind="calibrated",
        calibrated_input="Config.noise set from the paper's residual",
        quantity="residual",
        comparator=below(0.05),
        paper_value=0.05,
    ),
    Claim(
        id="toy.sane",
        paper=PAPER,
        where="Sec. 4",
        statement="The fit is finite in every run.",
        kind="emergent",
        quantity="sane",
        comparator=is_true(),
    ),
    Claim(
        id="toy.even",
        paper=PAPER,
        where="Fig. 2",
        statement="Even runs give a gain above 1.",
        kind="emergent",
        quantity="even_only",
        comparator=within_factor(1.5, 1.5),
    ),
)

DEVIATIONS = (
    Deviation(
        paper=PAPER,
        what="record length",
        paper_says="1000 samples",
        we_do="200 samples",
        reason="speed",
        variant="paper_length",
    ),
    Deviation(
        paper=PAPER,
        what="noise level",
        paper_says="not stated",
        we_do="0.1",
        reason="a choice",
        variant="paper_noise",
    ),
)


def variant_config(config: Config, name: str) -> Config:
    """The paper's protocol for a deviation: ``paper_length`` (1000 samples) or ``paper_noise`` (10x the noise)."""
    import dataclasses

    if name == "paper_length":
        return dataclasses.replace(config, n_samples=1000)
    if name == "paper_noise":
        return dataclasses.replace(config, noise=10 * config.noise)
    raise ValueError(f"toy_paper variant must be 'paper_length' or 'paper_noise'; got {name!r}")


def report(
    config: Config, units: Sequence[dict[str, Any]], claims: Sequence[ClaimResult]
) -> Outcome:
    rows = [[i, u["quantities"]["gain"], u["quantities"]["residual"]] for i, u in enumerate(units)]
    return Outcome(
        scenario=NAME,
        title=TITLE,
        seed=0,
        config=config,
        results={"gains": [u["quantities"]["gain"] for u in units]},
        tables=[Table("Gains per unit", ["unit", "gain", "residual"], rows)],
        conclusion="toy",
    )
