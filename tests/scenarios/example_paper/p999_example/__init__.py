"""Example paper 999: a gyro at rest, its bias estimated as the record mean (tests only).

The smallest folder that meets the paper contract (:mod:`gyrobench.scenarios.papers.contract`).
``tests/scenarios/test_example_paper.py`` adds this folder's parent to the papers package path
and nothing else: the paper is then listed, reproduced and checked by the contract test like
the four real ones.

The model: a gyro at rest with a constant bias ``b`` [deg/h] and white rate noise of angle
random walk ``N`` [deg/sqrt(h)] (IEEE Std 952-1997, annex C: a white rate noise of ARW N has
the one-sided PSD N^2 and, sampled at fs, the per-sample standard deviation
sigma = 60 N sqrt(fs) deg/h with N in deg/sqrt(h) and fs in Hz). The record mean of T seconds
estimates ``b`` with standard error 60 N / sqrt(T) deg/h. The fictitious paper claims that the
estimate lies within three standard errors of the bias.
"""

from __future__ import annotations

from gyrobench.scenarios.papers import Paper

NAME = "example_bias"
TITLE = "Example paper: a gyro's bias as the mean of a static record (tests only)"
PAPER = "999"

#: the paper itself (fictitious)
SOURCE = Paper(
    key="999",
    authors="A. Example, B. Example",
    authors_zh="",
    affiliation="the gyrobench test suite",
    topic="a gyro's bias estimated as the mean of a static record",
    title_en=None,
    title_zh=None,
    journal=None,
    year=None,
    source_note="a fictitious paper: the example of a paper folder",
)

from .bench import BENCH_SCORES, compensation_task  # noqa: E402
from .claims import CLAIMS, DEVIATIONS, claims_for  # noqa: E402
from .config import Config, control_config, variant_config  # noqa: E402
from .experiment import UnitResult, experiment, memory_estimate, simulate  # noqa: E402
from .report import report  # noqa: E402

__all__ = [
    "BENCH_SCORES",
    "CLAIMS",
    "DEVIATIONS",
    "NAME",
    "PAPER",
    "SOURCE",
    "TITLE",
    "Config",
    "UnitResult",
    "claims_for",
    "compensation_task",
    "control_config",
    "experiment",
    "memory_estimate",
    "report",
    "simulate",
    "variant_config",
]
