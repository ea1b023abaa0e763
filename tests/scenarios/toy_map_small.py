"""The toy paper of tests/scenarios/toy_map_paper.py with a small region (the refinement tests only).

Its facts are ``x > 0.9`` and ``y < 0.02`` (y log-scaled over [1e-2, 1]: about 1.5 % of the
family), so an 8-point first stage has an empty or small region and the map's second stage
(scenarios/maps/refine.py) runs. Everything else is the toy paper's.
"""

from __future__ import annotations

from gyrobench.scenarios.claims import above, below
from gyrobench.scenarios.maps.region import Constraint
from tests.scenarios.toy_map_paper import CLAIMS, DESIGN_SEED, FAMILY, MAP_CLAIMS, Config, experiment, report

__all__ = ["CLAIMS", "DESIGN_SEED", "FAMILY", "MAP_CLAIMS", "MAP_CONSTRAINTS", "NAME", "ONE_POINT", "Config",
           "experiment", "report"]

NAME = "toy_map_small"
TITLE = "Toy paper with a small region (map refinement tests only)"
PAPER = "toy"

MAP_CONSTRAINTS = (
    Constraint(id="toy.far_x", fact="x above 0.9", source="Table 1", quantity="fact_x", comparator=above(0.9)),
    Constraint(id="toy.low_y", fact="y below 0.02", source="Table 2", quantity="fact_y", comparator=below(0.02)),
)

#: facts whose region is one first-stage point of an 8-point design (x > 0.8 and y < 0.05: point 3,
#: x 0.81, y 0.016): the second stage's box around it reaches x up to 0.935, so it holds region points
ONE_POINT = (
    Constraint(id="toy.high_x", fact="x above 0.8", source="Table 1", quantity="fact_x", comparator=above(0.8)),
    Constraint(id="toy.small_y", fact="y below 0.05", source="Table 2", quantity="fact_y", comparator=below(0.05)),
)
