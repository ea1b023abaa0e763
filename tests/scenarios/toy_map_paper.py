"""A tiny paper scenario with a device family whose region and claim verdicts are known by construction
(the map tests only).

A point sets ``x`` in [0, 1] and ``y`` in [1e-2, 1] (log scale). Each unit reports

* ``fact_x`` = x and ``fact_y`` = y exactly (no noise: the region is ``x > 0.3 and y < 0.5``),
* ``wide`` = x (the conflicting fact's quantity: ``wide < 0.2`` never holds with ``fact_x > 0.3``),
* ``claim_q`` = 1 when x + 0.05 e > 0.6 (e standard normal per unit): most units of a point with
  x well above 0.6 pass, well below fail; the claim depends on x, not on y,
* ``score`` = y + 0.01 e (a banded claim that misses above on points with y > 0.25),
* ``pre`` = x: the claims' precondition (``pre > 0.1``): points with x <= 0.1 cannot test them.

Its nominal device (``Config()``: x = 0.5, y = 0.1) lies in the region. ``report`` makes it
reportable by ``reproduce`` (no tables). A unit sleeps ``TOY_MAP_UNIT_DELAY_S`` seconds (an
environment variable, default 0) first, so a test can kill a map mid-run.
"""

from __future__ import annotations

import os
import time
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from gyrobench.base.ranges import FieldRange
from gyrobench.scenarios.base import Outcome
from gyrobench.scenarios.claims import Claim, Precondition, above, below, in_range, is_true
from gyrobench.scenarios.maps.family import Family, Parameter
from gyrobench.scenarios.maps.region import Constraint

NAME = "toy_map_paper"
TITLE = "Toy paper with a device family (map tests only)"
PAPER = "toy"


@dataclass(frozen=True, slots=True, kw_only=True)
class Config:
    x: float = 0.5
    y: float = 0.1


def experiment(config: Config, seed: int) -> dict[str, Any]:
    delay = float(os.environ.get("TOY_MAP_UNIT_DELAY_S", "0"))
    if delay > 0:
        time.sleep(delay)
    rng = np.random.default_rng(seed)
    e1, e2 = rng.standard_normal(2)
    return {"quantities": {
        "fact_x": config.x,
        "fact_y": config.y,
        "wide": config.x,
        "claim_q": float(config.x + 0.05 * e1 > 0.6),
        "score": config.y + 0.01 * e2,
        "pre": config.x,
    }}


PRE = Precondition(text="x above 0.1", quantity="pre", comparator=above(0.1))

CLAIMS = (
    Claim(id="toy.q", paper=PAPER, where="Sec. 1", statement="q holds.", kind="emergent",
          quantity="claim_q", comparator=is_true(), precondition=PRE),
    Claim(id="toy.score", paper=PAPER, where="Sec. 2", statement="score in [-1, 0.25].", kind="emergent",
          quantity="score", comparator=in_range(-1.0, 0.25), paper_value=0.1, precondition=PRE),
)

FAMILY = Family(
    paper="toy",
    base=Config(),
    parameters=(
        Parameter(field="x", range=FieldRange(0.0, 1.0, "1"), scale="linear", source="by construction", label="x"),
        Parameter(field="y", range=FieldRange(1e-2, 1.0, "m"), scale="log", source="by construction", label="y"),
    ),
)
DESIGN_SEED = 7
MAP_CLAIMS = CLAIMS
MAP_CONSTRAINTS = (
    Constraint(id="toy.fact_x", fact="x above 0.3", source="Table 1", quantity="fact_x", comparator=above(0.3)),
    Constraint(id="toy.fact_y", fact="y below 0.5", source="Table 2", quantity="fact_y", comparator=below(0.5)),
)
#: a fact that cannot hold together with toy.fact_x (the empty-region test)
CONFLICTING = Constraint(id="toy.wide", fact="x below 0.2", source="Fig. 3", quantity="wide", comparator=below(0.2))
#: a fact no point satisfies
NEVER = Constraint(id="toy.never", fact="x above 2", source="Fig. 4", quantity="fact_x", comparator=above(2.0))


def report(config: Config, results: list[Any], claims: list[Any]) -> Outcome:
    """The toy's report: no tables, the claims filled in by the runner."""
    return Outcome(scenario=NAME, title=TITLE, seed=0, config=asdict(config), results={})
