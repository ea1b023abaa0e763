"""The bench: score a compensator on a scenario over many seeds, keep every seed's scores, compare.

A scenario with a compensation stage defines ``compensation_task(config, seed)``
(see :mod:`gyrobench.scenarios.base`): a training set and held-out runs whose truth is known.
The bench fits the user's compensator on the training set, compensates every
held-out run, and scores the result against the truth with the task's scorer.

Compensators
------------
:func:`resolve_compensator` accepts exactly these forms:

1. a scikit-learn estimator instance (anything with ``fit``, ``predict`` and
   ``get_params``: a regressor, a :class:`~sklearn.pipeline.Pipeline`, a grid
   search). It is copied with :func:`sklearn.base.clone` for every seed, and every
   parameter named ``random_state`` or ``*__random_state`` that is ``None`` is set
   to an integer derived from the seed, so stochastic regressors are reproducible.
   Objects with ``fit``/``predict`` but no ``get_params`` are deep-copied instead.
2. an estimator class (a type with ``fit`` and ``predict``): instantiated with
   no arguments for every seed, then treated as in 1.
3. a fit function ``f(X_train, y_train) -> predictor``, where the predictor is
   either a callable ``predictor(X) -> ndarray (n,)`` or an object with
   ``predictor.predict(X)``. If ``f`` accepts a keyword ``random_state``, it
   receives the seed-derived integer.
4. a string ``"package.module:attr"`` (``attr`` may be dotted), imported and then
   handled as 1-3. This is the form the command line takes.

The prediction on a held-out run's ``X`` is turned into the compensated output by
the task (``target="error"``: output - prediction; ``"rate"``: prediction).

Where the compensator runs: in a campaign, in its own process
(:mod:`~gyrobench.scenarios.bench.sandbox`), which receives only the training data and the
held-out features; the scores are computed outside it, and a score below the scenario's noise
floor (:mod:`~gyrobench.scenarios.bench.floor`) fails the seed. :func:`score_seed` and
:func:`~gyrobench.scenarios.bench.scoring.score_task` run it in the calling process, for code
you trust (debugging a compensator, the bench's own references).

Groups: a task may label its training rows (``CompensationTask.groups_train``; ifog_thermal
labels each row with its segment of the identification run: 0 settle, 1 heat + hold,
2 cool + hold). The bench passes them the scikit-learn way, ``fit(X, y, groups=...)``, only to
an estimator whose ``fit`` names a ``groups`` parameter, to a fit function ``f(X, y, groups)``
and to a scikit-learn search (``GridSearchCV(..., cv=LeaveOneGroupOut())`` selects by leave
one segment out); every other compensator is fitted with ``fit(X, y)``.

Determinism: the same (scenario, config, compensator, seed) always gives the same
scores, bit for bit, whatever executor runs it: every seed runs with the BLAS and
OpenMP thread pools limited to one thread (threadpoolctl, a scikit-learn
dependency), so the floating-point summation order does not depend on how many
threads a worker has (and N workers use N cores without oversubscription).

Campaigns
---------
:func:`run_campaign` scores many seeds on any :class:`concurrent.futures.Executor`
(local processes by default; ``distributed.Client(address).get_executor()`` for a
dask cluster). Only the calling process writes the SQLite database: one
transaction per finished seed, WAL journal, ``synchronous=FULL``. A campaign is
identified by a hash of the scenario (its configuration; the source of its
module and of every module it imports, transitively, from its own package and
from gyrobench.sim, analysis and scenarios; the gyrobench, numpy, scipy and scikit-learn
versions), of the compensator (its class or function and parameters; the
source of the module defining it, with the same import closure for user code) and of what
the compensator read while it ran (the modules, files and environment variables its process
recorded, :mod:`~gyrobench.scenarios.bench.sandbox`).
Running the same campaign again reads the seeds already in the database and
computes only the others, so a campaign killed at any
moment (even SIGKILL) resumes where it stopped; changing the code or the
configuration starts a new campaign rather than mixing results.

Baselines
---------
:func:`save_baseline` writes a campaign's per-seed scores to JSON;
:func:`compare` tests a new campaign against it, seed by seed (see its Notes for
the test and the multiple-comparison correction). Which way is "better" for each
score is decided in one place, :func:`score_direction`.

Modules
-------
:mod:`~gyrobench.scenarios.bench.seeds` (seed lists),
:mod:`~gyrobench.scenarios.bench.compensators` (the user's compensator, fitting it),
:mod:`~gyrobench.scenarios.bench.scoring` (one seed scored in this process),
:mod:`~gyrobench.scenarios.bench.jobs` (a seed as a campaign's job: time limit, sandbox, noise floor),
:mod:`~gyrobench.scenarios.bench.sandbox` and :mod:`~gyrobench.scenarios.bench.sandbox_child`
(the compensator's own processes), :mod:`~gyrobench.scenarios.bench.sandbox_protocol` (the
scoring side of their wire protocol), :mod:`~gyrobench.scenarios.bench.sandboxed` (sandboxed seeds
on local processes, what the compensator read), :mod:`~gyrobench.scenarios.bench.floor` (the
noise floor), :mod:`~gyrobench.scenarios.bench.margin` (the gate's equivalence margin),
:mod:`~gyrobench.scenarios.bench.identity` (campaign id),
:mod:`~gyrobench.scenarios.runner.store` (the SQLite store, shared with the units runner),
:mod:`~gyrobench.scenarios.runner.executors` (local pools, shared with the units runner),
:mod:`~gyrobench.scenarios.bench.statistics` (intervals, paired test, correction),
:mod:`~gyrobench.scenarios.bench.campaign` (:func:`run_campaign`),
:mod:`~gyrobench.scenarios.bench.baseline_file` (save, load, check a baseline file),
:mod:`~gyrobench.scenarios.bench.baseline` (compare),
:mod:`~gyrobench.scenarios.bench.primary` (each scenario's primary, gated, scores and units),
:mod:`~gyrobench.scenarios.bench.power` (smallest attainable p, seeds needed, ``--seeds auto``),
:mod:`~gyrobench.scenarios.bench.gate` (the power check before a run),
:mod:`~gyrobench.scenarios.bench.references` (the uncompensated reference, papers' methods),
:mod:`~gyrobench.scenarios.bench.formatting` (text tables) and
:mod:`~gyrobench.scenarios.cli.bench` (the ``gyrobench bench`` verb). Every public name is
importable from this package; the package loads its modules on first use, so the
command line's parser does not import numpy.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from gyrobench.base.lazy import attach

#: public name -> module of this package that defines it (imported on first access)
_LAZY: dict[str, str] = {
    "DEFAULT_MEMORY_BYTES": "gyrobench.scenarios.bench.sandbox",
    "Zygote": "gyrobench.scenarios.bench.sandbox",
    "noise_floor": "gyrobench.scenarios.bench.floor",
    "DetectableChange": "gyrobench.scenarios.bench.margin",
    "DEFAULT_MIN_CHANGE": "gyrobench.scenarios.bench.power",
    "reference_campaigns": "gyrobench.scenarios.bench.gate",
    "UnderpoweredWarning": "gyrobench.scenarios.bench.power",
    "Uncompensated": "gyrobench.scenarios.bench.references",
    "UNCOMPENSATED": "gyrobench.scenarios.bench.references",
    "score_unit": "gyrobench.scenarios.bench.primary",
    "gated_scores": "gyrobench.scenarios.bench.primary",
    "declared_scores": "gyrobench.scenarios.bench.primary",
    "PrimaryScore": "gyrobench.scenarios.bench.primary",
    "seeds_needed": "gyrobench.scenarios.bench.power",
    "min_attainable_p": "gyrobench.scenarios.bench.power",
    "UnderpoweredError": "gyrobench.scenarios.bench.power",
    "detectable": "gyrobench.scenarios.bench.gate",
    "plan_power": "gyrobench.scenarios.bench.gate",
    "PowerPlan": "gyrobench.scenarios.bench.gate",
    "BASELINE_FORMAT": "gyrobench.scenarios.bench.baseline_file",
    "BASELINE_VERSION": "gyrobench.scenarios.bench.baseline_file",
    "BYTES_PER_SEED": "gyrobench.scenarios.bench.seeds",
    "DEFAULT_DB": "gyrobench.scenarios.runner.store",
    "HIGHER_IS_BETTER_TOKENS": "gyrobench.scenarios.bench.statistics",
    "LOWER_IS_BETTER_TOKENS": "gyrobench.scenarios.bench.statistics",
    "MAX_SEED": "gyrobench.scenarios.bench.seeds",
    "MAX_SEEDS": "gyrobench.scenarios.bench.seeds",
    "NONNEGATIVE_TOKENS": "gyrobench.scenarios.bench.statistics",
    "TRACEBACK_ENV": "gyrobench.scenarios.bench.compensators",
    "Campaign": "gyrobench.scenarios.bench.campaign",
    "Comparison": "gyrobench.scenarios.bench.baseline",
    "ComparisonError": "gyrobench.scenarios.bench.baseline",
    "CompensatorError": "gyrobench.scenarios.bench.compensators",
    "CompensatorImportError": "gyrobench.scenarios.bench.compensators",
    "FailedSeedsError": "gyrobench.scenarios.bench.compensators",
    "ScoreComparison": "gyrobench.scenarios.bench.baseline",
    "ScoreSummary": "gyrobench.scenarios.bench.statistics",
    "campaign_id": "gyrobench.scenarios.bench.identity",
    "check_baseline_matches": "gyrobench.scenarios.bench.baseline_file",
    "check_baseline_path": "gyrobench.scenarios.bench.baseline_file",
    "compare": "gyrobench.scenarios.bench.baseline",
    "compensator_identity": "gyrobench.scenarios.bench.identity",
    "connect_db": "gyrobench.scenarios.runner.store",
    "format_summary": "gyrobench.scenarios.bench.formatting",
    "load_baseline": "gyrobench.scenarios.bench.baseline_file",
    "parse_seeds": "gyrobench.scenarios.bench.seeds",
    "prepend_import_path": "gyrobench.scenarios.bench.compensators",
    "resolve_compensator": "gyrobench.scenarios.bench.compensators",
    "resolve_scenario": "gyrobench.scenarios.bench.scoring",
    "run_campaign": "gyrobench.scenarios.bench.campaign",
    "save_baseline": "gyrobench.scenarios.bench.baseline_file",
    "score_direction": "gyrobench.scenarios.bench.statistics",
    "score_is_nonnegative": "gyrobench.scenarios.bench.statistics",
    "score_seed": "gyrobench.scenarios.bench.scoring",
    "check_seed_timeout": "gyrobench.scenarios.bench.jobs",
    "DEFAULT_SEED_TIMEOUT_S": "gyrobench.scenarios.bench.jobs",
}

__all__ = [
    "DEFAULT_MEMORY_BYTES",
    "Zygote",
    "noise_floor",
    "DetectableChange",
    "DEFAULT_MIN_CHANGE",
    "check_seed_timeout",
    "DEFAULT_SEED_TIMEOUT_S",
    "reference_campaigns",
    "UnderpoweredWarning",
    "Uncompensated",
    "UNCOMPENSATED",
    "score_unit",
    "gated_scores",
    "declared_scores",
    "PrimaryScore",
    "seeds_needed",
    "min_attainable_p",
    "UnderpoweredError",
    "detectable",
    "plan_power",
    "PowerPlan",
    "BASELINE_FORMAT",
    "BASELINE_VERSION",
    "BYTES_PER_SEED",
    "DEFAULT_DB",
    "HIGHER_IS_BETTER_TOKENS",
    "LOWER_IS_BETTER_TOKENS",
    "MAX_SEED",
    "MAX_SEEDS",
    "NONNEGATIVE_TOKENS",
    "TRACEBACK_ENV",
    "Campaign",
    "Comparison",
    "ComparisonError",
    "CompensatorError",
    "CompensatorImportError",
    "FailedSeedsError",
    "ScoreComparison",
    "ScoreSummary",
    "campaign_id",
    "check_baseline_matches",
    "check_baseline_path",
    "compare",
    "compensator_identity",
    "connect_db",
    "format_summary",
    "load_baseline",
    "parse_seeds",
    "prepend_import_path",
    "resolve_compensator",
    "resolve_scenario",
    "run_campaign",
    "save_baseline",
    "score_direction",
    "score_is_nonnegative",
    "score_seed",
]

if TYPE_CHECKING:  # pragma: no cover - for type checkers and IDEs only
    from gyrobench.scenarios.bench.baseline import Comparison, ComparisonError, ScoreComparison, compare
    from gyrobench.scenarios.bench.baseline_file import (
        BASELINE_FORMAT,
        BASELINE_VERSION,
        check_baseline_matches,
        check_baseline_path,
        load_baseline,
        save_baseline,
    )
    from gyrobench.scenarios.bench.campaign import Campaign, run_campaign
    from gyrobench.scenarios.bench.compensators import (
        TRACEBACK_ENV,
        CompensatorError,
        CompensatorImportError,
        FailedSeedsError,
        prepend_import_path,
        resolve_compensator,
    )
    from gyrobench.scenarios.bench.floor import noise_floor
    from gyrobench.scenarios.bench.formatting import format_summary
    from gyrobench.scenarios.bench.gate import PowerPlan, detectable, plan_power, reference_campaigns
    from gyrobench.scenarios.bench.identity import campaign_id, compensator_identity
    from gyrobench.scenarios.bench.jobs import DEFAULT_SEED_TIMEOUT_S, check_seed_timeout
    from gyrobench.scenarios.bench.margin import DetectableChange
    from gyrobench.scenarios.bench.power import (
        DEFAULT_MIN_CHANGE,
        UnderpoweredError,
        UnderpoweredWarning,
        min_attainable_p,
        seeds_needed,
    )
    from gyrobench.scenarios.bench.primary import PrimaryScore, declared_scores, gated_scores, score_unit
    from gyrobench.scenarios.bench.references import UNCOMPENSATED, Uncompensated
    from gyrobench.scenarios.bench.sandbox import DEFAULT_MEMORY_BYTES, Zygote
    from gyrobench.scenarios.bench.scoring import resolve_scenario, score_seed
    from gyrobench.scenarios.bench.seeds import BYTES_PER_SEED, MAX_SEED, MAX_SEEDS, parse_seeds
    from gyrobench.scenarios.bench.statistics import (
        HIGHER_IS_BETTER_TOKENS,
        LOWER_IS_BETTER_TOKENS,
        NONNEGATIVE_TOKENS,
        ScoreSummary,
        score_direction,
        score_is_nonnegative,
    )
    from gyrobench.scenarios.runner.store import DEFAULT_DB, connect_db


__getattr__, __dir__ = attach(__name__, _LAZY)
