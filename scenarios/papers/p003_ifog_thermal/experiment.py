"""Paper 003's experiment: one unit (seed) through the paper's pipeline, as a typed result.

:func:`experiment` simulates the unit's chamber runs (:mod:`.runs`), trains the networks
on identification run 1 with the paper's target Q and, as a labelled diagnostic, with
the truth, scores every held-out run (:mod:`.pipeline`), and adds the coil studies
(:mod:`.coil`). No formatting: the report reads the :class:`.results.UnitResult`.
"""

from __future__ import annotations

import numpy as np

from .coil import point_heating_result, winding_comparison
from .config import Config
from .pipeline import (
    drift_estimate_error_val1,
    drift_peak_val1,
    drift_to_noise_val1,
    fit_protocol,
    float32_check,
    protocol_result,
    scores,
    streaming_deviation,
    traces,
    txdt_share,
)
from .results import UnitResult
from .runs import compensation_task, memory_estimate, prepare, simulate

__all__ = ["compensation_task", "experiment", "memory_estimate", "simulate"]


def experiment(config: Config, seed: int) -> UnitResult:
    """One unit (seed) through the paper's pipeline: simulate, train on Q, select, score ERR.

    Returns the claim quantities (``UnitResult.quantities``), the paper protocol's details
    (``paper``), the labelled diagnostic with the truth target (``diagnostic_truth_target``),
    the exported network, the float32 deployment check, the streaming check, the
    point-heating curve, the winding comparison and downsampled traces for figures.

    Parameters
    ----------
    config : Config
        The configuration.
    seed : int
        The unit's seed.

    Returns
    -------
    UnitResult
        The unit's quantities and details.
    """
    runs = {r.name: prepare(r, config) for r in simulate(config, seed)}
    paper = fit_protocol(config, runs, "paper")
    truth = fit_protocol(config, runs, "truth")
    s_paper = scores(runs, paper.comp_imp, paper.comp_trad)
    s_truth = scores(runs, truth.comp_imp, truth.comp_trad)
    point = point_heating_result(config)
    r0 = runs["val1_run1"]
    return UnitResult(
        seed=int(seed),
        txdt_point_max_deg_h=float(np.max(np.abs(point.product))),
        drift_peak_val1_deg_h=drift_peak_val1(runs),
        val1_drift_to_noise=drift_to_noise_val1(runs),
        val1_drift_estimate_error=drift_estimate_error_val1(runs, paper.comp_imp),
        txdt_share=txdt_share(config, runs["ident_1"]),
        paper=protocol_result(paper, s_paper),
        diagnostic_truth_target=protocol_result(truth, s_truth),
        deployment_json=paper.improved.to_json(),
        float32=float32_check(config, runs, paper),
        streaming_max_abs_deviation_deg_h=streaming_deviation(config, paper.improved, r0, paper.comp_imp[r0.name]),
        point_heating=point,
        windings=winding_comparison(config),
        traces=traces(config, runs, paper),
    )
