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
versions) and of the compensator (its class or function and parameters; the
source of the module defining it, with the same import closure for user code).
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
"""

from __future__ import annotations

import concurrent.futures as cf
import copy
import dataclasses
import functools
import hashlib
import importlib
import importlib.util
import inspect
import json
import math
import os
import pickle
import sqlite3
import time
import types
import warnings
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from gyrobench.scenarios import exits
from gyrobench.scenarios.base import check_pool
from numpy.typing import NDArray

__all__ = [
    "DEFAULT_DB",
    "CompensatorError",
    "FailedSeedsError",
    "Campaign",
    "ScoreSummary",
    "ScoreComparison",
    "Comparison",
    "parse_seeds",
    "resolve_scenario",
    "resolve_compensator",
    "compensator_identity",
    "score_seed",
    "campaign_id",
    "run_campaign",
    "score_direction",
    "score_is_nonnegative",
    "check_baseline_path",
    "check_baseline_matches",
    "save_baseline",
    "load_baseline",
    "compare",
    "format_summary",
]

#: default campaign database (in the current directory)
DEFAULT_DB = "gyrobench-bench.sqlite"

BASELINE_FORMAT = "gyrobench-baseline"
BASELINE_VERSION = 1

# ----------------------------------------------------------------------------- score directions
#: Tokens of a score name (last path component split at "_") meaning "lower is better".
LOWER_IS_BETTER_TOKENS = frozenset(
    {"mse", "rms", "rmse", "mae", "error", "err", "residual", "stability", "instability"}
    | {"nonlinearity", "asymmetry", "drift", "std", "adev", "avar", "bias", "max", "peak"}
)
#: Tokens meaning "higher is better"; they win over the lower-is-better tokens
#: ("mse_reduction_pct" is higher-is-better).
HIGHER_IS_BETTER_TOKENS = frozenset({"improvement", "reduction", "r2", "gain", "snr", "accuracy"})


#: Tokens of a score name meaning the score is >= 0 by nature (errors squared or in
#: magnitude, spreads, deviations); :func:`score_is_nonnegative`. A name holding a
#: higher-is-better token ("mse_reduction_pct") is a difference and may be negative.
NONNEGATIVE_TOKENS = frozenset(
    {"mse", "rmse", "rms", "mae", "std", "sigma", "var", "avar", "adev", "dev"}
    | {"stability", "instability", "nonlinearity"}
)


def score_is_nonnegative(name: str) -> bool:
    """Whether the score ``name`` is non-negative by nature (its confidence interval must be).

    Decided from the tokens of the name's last path component, as in
    :func:`score_direction`: True if one is in :data:`NONNEGATIVE_TOKENS` and none is
    in :data:`HIGHER_IS_BETTER_TOKENS` (improvements and reductions can be negative).
    """
    tokens = _name_tokens(name)
    return bool(tokens & NONNEGATIVE_TOKENS) and not tokens & HIGHER_IS_BETTER_TOKENS


def _name_tokens(name: str) -> set[str]:
    """The tokens every score-name rule reads: the last path component, lower-cased, split
    at ``"_"``."""
    return set(name.rsplit("/", 1)[-1].lower().split("_"))


def score_direction(name: str, overrides: Mapping[str, int] | None = None) -> int:
    """Which way is better for the score ``name``: -1 lower, +1 higher, 0 unknown.

    This is the one place the bench decides it. The score's last path component
    (``"val1/bias_stability_100s"`` -> ``"bias_stability_100s"``) is lower-cased and
    split at ``"_"``; if any token is in :data:`HIGHER_IS_BETTER_TOKENS` the score is
    higher-is-better, else if any token is in :data:`LOWER_IS_BETTER_TOKENS` it is
    lower-is-better (errors: mse, rms, stability, nonlinearity, ...), else unknown.
    A score of unknown direction is still tested, and reported as "changed", but
    never counts as a regression. ``overrides`` maps a full score name or a last
    component to -1/+1/0 and takes precedence.
    """
    key = name.rsplit("/", 1)[-1]
    if overrides:
        for k in (name, key):
            if k in overrides:
                v = overrides[k]
                if v not in (-1, 0, 1):
                    raise ValueError(f"direction of {k!r} must be -1, 0 or +1; got {v!r}")
                return int(v)
    tokens = _name_tokens(name)
    if tokens & HIGHER_IS_BETTER_TOKENS:
        return 1
    if tokens & LOWER_IS_BETTER_TOKENS:
        return -1
    return 0


# ----------------------------------------------------------------------------- seeds
def parse_seeds(text: str) -> tuple[int, ...]:
    """Parse a seed list: ``"0:100"`` (half-open range, like Python), ``"0:100:5"``,
    ``"1,5,9"`` (a comma list) or ``"7"``.

    Raises
    ------
    ValueError
        If the text is not of these forms, a seed is negative, the list is empty or
        holds a seed twice.
    """
    if not isinstance(text, str):
        raise TypeError(f"seeds must be a string like '0:100' or '1,5,9'; got {text!r}")
    s = text.strip()
    usage = (
        "seeds must be 'START:STOP' (half-open range), 'START:STOP:STEP' or a comma list "
        f"like '1,5,9' of integers >= 0; got {text!r}"
    )
    try:
        if ":" in s:
            parts = [int(p) for p in s.split(":")]
            if len(parts) not in (2, 3):
                raise ValueError
            if len(parts) == 3 and parts[2] <= 0:
                raise ValueError
            span = range(*parts)
            _check_count(len(span), what=text)  # before building a tuple of 10**12 ints
            seeds = tuple(span)
        else:
            seeds = tuple(int(p) for p in s.split(","))
    except ValueError as exc:
        if str(exc).startswith("seeds must"):
            raise
        raise ValueError(usage) from None
    return _check_seeds(seeds, what=text)


#: most seeds one campaign may hold. The bound is what the calling process holds at once:
#: every seed is a submitted future (~1 kB) and a row of scores read back (~1-2 kB for the
#: scenarios' 10-40 scores), so 10**6 seeds take about 2-3 GB, checked against the memory
#: limit too (gyrobench.sim.memory); at ~0.5 s per seed it is also ~6 CPU-days of work.
MAX_SEEDS = 10**6
#: largest seed: the database stores seeds as SQLite INTEGER (signed 64-bit)
MAX_SEED = 2**63 - 1
#: bytes one seed costs the calling process (a future and its scores), for the memory check
BYTES_PER_SEED = 3000


def _check_count(n: int, *, what: Any) -> None:
    if n > MAX_SEEDS:
        raise ValueError(
            f"seeds must number at most {MAX_SEEDS} per campaign (each is a future and a row of "
            f"scores held by this process); got {n} in {what!r}: split the campaign"
        )
    from gyrobench.sim import memory

    memory.check_memory(
        n * BYTES_PER_SEED, f"a campaign of {n} seeds", hint="use fewer seeds per campaign"
    )


def _check_seeds(seeds: Iterable[int], *, what: Any = None) -> tuple[int, ...]:
    seeds = tuple(seeds)
    what = seeds if what is None else what
    _check_count(len(seeds), what=what if len(seeds) < 20 else f"{len(seeds)} seeds")
    for s in seeds:
        if isinstance(s, (bool, np.bool_)) or not isinstance(s, (int, np.integer)):
            raise TypeError(f"seeds must be integers >= 0; got {s!r} in {what!r}")
        if s < 0:
            raise ValueError(f"seeds must be integers >= 0; got {int(s)} in {what!r}")
        if s > MAX_SEED:
            raise ValueError(
                f"seeds must be <= 2**63 - 1 = {MAX_SEED} (the database stores them as 64-bit "
                f"integers); got {int(s)} in {what!r}"
            )
    if not seeds:
        raise ValueError(f"seeds must hold at least one seed; got {what!r}")
    seeds = tuple(int(s) for s in seeds)
    if len(set(seeds)) != len(seeds):
        dup = sorted({s for s in seeds if seeds.count(s) > 1})
        raise ValueError(f"seeds must be distinct; got {dup} more than once in {what!r}")
    return seeds


# ----------------------------------------------------------------------------- resolution
def resolve_scenario(scenario: str | types.ModuleType) -> types.ModuleType:
    """The scenario module for a registered name, an importable module path or a module.

    Raises
    ------
    ValueError
        If the name is unknown or the scenario has no compensation stage.
    """
    from gyrobench.scenarios import registry

    if isinstance(scenario, types.ModuleType):
        module = scenario
    elif isinstance(scenario, str):
        if scenario in registry.SCENARIOS or "." not in scenario:
            if scenario not in registry.available():
                raise ValueError(
                    "scenario must be one of the scenarios with a compensation stage "
                    f"{_bench_scenarios()} or an importable module path; got {scenario!r}"
                )
            module = registry.get(scenario)
        else:
            try:
                module = importlib.import_module(scenario)
            except ModuleNotFoundError as exc:
                raise ValueError(
                    f"scenario must be a registered name {registry.available()} or an importable "
                    f"module; got {scenario!r} ({exc})"
                ) from None
    else:
        raise TypeError(
            f"scenario must be a name or a module; got {type(scenario).__name__} {scenario!r}"
        )
    if not callable(getattr(module, "compensation_task", None)):
        raise ValueError(
            f"scenario {getattr(module, 'NAME', module.__name__)!r} has no compensation stage "
            f"(no compensation_task); scenarios with one: {_bench_scenarios()}"
        )
    return module


def _bench_scenarios() -> list[str]:
    """Registered scenarios defining ``compensation_task`` (read from the source, not imported)."""
    import re

    from gyrobench.scenarios import registry

    out = []
    for name in registry.available():
        path = _module_file(registry.SCENARIOS[name])
        try:
            text = Path(path).read_text() if path else ""
        except OSError:
            continue
        if re.search(r"^def compensation_task\b", text, re.MULTILINE):
            out.append(name)
    return out


def prepend_import_path(folder: str | os.PathLike) -> None:
    """Put ``folder`` first on ``sys.path`` (once), so ``"module:attr"`` compensators and
    module-path scenarios are found there before anywhere else, as ``python -m`` finds
    modules in the current folder. Worker processes inherit the path (``spawn`` and
    ``forkserver`` pass ``sys.path`` to the child)."""
    import sys

    path = os.fspath(folder)
    if path in sys.path:
        sys.path.remove(path)
    sys.path.insert(0, path)
    importlib.invalidate_caches()


def _import_attr(spec: str) -> Any:
    if spec.count(":") != 1 or not all(spec.split(":")):
        raise ValueError(f"compensator must be 'package.module:attr'; got {spec!r}")
    mod_name, attr = spec.split(":")
    try:
        obj: Any = importlib.import_module(mod_name)
    except ModuleNotFoundError as exc:
        raise ValueError(
            f"compensator {spec!r}: cannot import module {mod_name!r} ({exc})"
        ) from None
    except SyntaxError as exc:
        raise CompensatorImportError(
            f"compensator {spec!r}: module {mod_name!r} has a syntax error: {exc.msg} "
            f"({exc.filename}, line {exc.lineno})",
            exc,
        ) from exc
    except Exception as exc:  # noqa: BLE001 - whatever the user's module raises while importing
        detail = " ".join(str(exc).split()) or "(no message)"
        raise CompensatorImportError(
            f"compensator {spec!r}: importing module {mod_name!r} raised "
            f"{type(exc).__name__}: {detail}",
            exc,
        ) from exc
    for part in attr.split("."):
        try:
            obj = getattr(obj, part)
        except AttributeError:
            raise ValueError(
                f"compensator {spec!r}: module {mod_name!r} has no attribute {attr!r}"
            ) from None
    return obj


class CompensatorImportError(ValueError):
    """The compensator's module failed to import (a syntax error, an exception at import time).

    Bad input (exit 2); ``traceback_text`` holds the import's traceback, which the
    command line prints with ``GYROBENCH_TRACEBACK=1``.
    """

    def __init__(self, message: str, cause: BaseException) -> None:
        import traceback

        super().__init__(message)
        self.traceback_text = "".join(traceback.format_exception(cause))


def _is_estimator(obj: Any) -> bool:
    return callable(getattr(obj, "fit", None)) and callable(getattr(obj, "predict", None))


def resolve_compensator(compensator: Any) -> Any:
    """Check ``compensator`` is one of the accepted forms (module docstring) and import strings.

    Returns the estimator instance, estimator class or fit function.

    Raises
    ------
    ValueError
        If a ``"module:attr"`` string does not resolve.
    TypeError
        If the object is not an estimator, an estimator class or a callable.
    """
    obj = _import_attr(compensator) if isinstance(compensator, str) else compensator
    if isinstance(obj, type):
        if not _is_estimator(obj):
            raise TypeError(f"compensator class {obj.__qualname__} must define fit and predict")
        return obj
    if _is_estimator(obj) or callable(obj):
        return obj
    raise TypeError(
        "compensator must be a scikit-learn estimator, an estimator class, a fit function "
        f"f(X, y) -> predictor, or 'module:attr'; got {type(obj).__name__} {obj!r}"
    )


def _seed_int(seed: int) -> int:
    """An integer in [0, 2**32) derived from the campaign seed, for ``random_state``."""
    return int(np.random.SeedSequence([int(seed), 0x62656E63]).generate_state(1)[0])


#: environment variable: when set (to anything but "" or "0"), ``gyrobench bench`` prints the
#: traceback of a failing compensator on stderr before its one-line error
TRACEBACK_ENV = exits.TRACEBACK_ENV


class CompensatorError(ValueError):
    """The compensator failed on a seed: its fit or predict raised, or its prediction is unusable.

    Raised by :func:`score_seed` (and so by :func:`run_campaign`, after the seeds
    already finished are committed). A ``ValueError``, so the command line reports it
    in one line and exits 2, distinct from exit 1 ("significant regression"). The
    message reads ``"compensator <name> failed on seed <s> (<stage>): <Type>: <message>"``.

    Attributes
    ----------
    compensator : str
        The compensator's label (``"module:attr"`` or its class name).
    seed : int or None
        The seed it failed on.
    stage : str
        ``"fit"`` or ``"predict on run <label>"``.
    traceback_text : str
        The formatted traceback of the original exception (a string, so it survives
        the trip back from a worker process, where the exception chain is lost).
        ``gyrobench bench`` prints it when :data:`TRACEBACK_ENV` is set.
    """

    def __init__(
        self,
        message: str,
        *,
        compensator: str = "",
        seed: int | None = None,
        stage: str = "",
        traceback_text: str = "",
    ) -> None:
        super().__init__(message)  # args == (message,): pickles and unpickles as is
        self.compensator = compensator
        self.seed = seed
        self.stage = stage
        self.traceback_text = traceback_text

    def with_context(self, text: str) -> CompensatorError:
        """A copy whose message ends with ``"; " + text`` (raise it ``from`` this one)."""
        return CompensatorError(
            f"{self.args[0]}; {text}",
            compensator=self.compensator,
            seed=self.seed,
            stage=self.stage,
            traceback_text=self.traceback_text,
        )


class FailedSeedsError(ValueError):
    """A campaign with failed seeds was to be saved as a baseline or compared (exit 3).

    ``seeds`` holds the failed seeds.
    """

    def __init__(self, message: str, *, seeds: Sequence[int] = ()) -> None:
        super().__init__(message)
        self.seeds = tuple(seeds)


def _compensator_failed(label: str, seed: int, stage: str, exc: BaseException) -> CompensatorError:
    import traceback

    detail = " ".join(str(exc).split()) or "(no message)"
    return CompensatorError(
        f"compensator {label} failed on seed {seed} ({stage}): {type(exc).__name__}: {detail}",
        compensator=label,
        seed=seed,
        stage=stage,
        traceback_text="".join(traceback.format_exception(exc)),
    )


def _fit(
    compensator: Any,
    X: NDArray[np.float64],
    y: NDArray[np.float64],
    seed: int,
    *,
    label: str,
) -> Callable:
    """Fit a fresh copy of ``compensator`` and return ``predict(X) -> ndarray``.

    Any exception raised by the user's code (instantiation, cloning, fit, the fit
    function) becomes a :class:`CompensatorError` naming ``label`` and ``seed``; a
    fit function returning something that cannot predict is a ``TypeError``.
    """
    try:
        predictor = _fit_user_code(compensator, X, y, seed)
    except Exception as exc:
        raise _compensator_failed(label, seed, "fit", exc) from exc
    if callable(getattr(predictor, "predict", None)):
        return predictor.predict
    if callable(predictor):
        return predictor
    raise TypeError(
        f"fit function {getattr(compensator, '__qualname__', compensator)!r} must return "
        f"a callable predict(X) or an object with .predict(X); got {type(predictor).__name__} "
        f"(compensator {label}, seed {seed})"
    )


def _fit_user_code(
    compensator: Any, X: NDArray[np.float64], y: NDArray[np.float64], seed: int
) -> Any:
    """The user's code in :func:`_fit`: the fitted estimator's predict, or what a fit
    function returned."""
    rs = _seed_int(seed)
    if isinstance(compensator, type):
        compensator = compensator()
    if _is_estimator(compensator):
        if hasattr(compensator, "get_params"):
            from sklearn.base import clone

            est = clone(compensator)
            params = est.get_params(deep=True)
            seeded = {
                k: rs
                for k, v in params.items()
                if (k == "random_state" or k.endswith("__random_state")) and v is None
            }
            if seeded:
                est.set_params(**seeded)
        else:
            est = copy.deepcopy(compensator)
        fitted = est.fit(X, y)
        return (est if fitted is None else fitted).predict
    kwargs = {}
    try:
        if "random_state" in inspect.signature(compensator).parameters:
            kwargs["random_state"] = rs
    except (TypeError, ValueError):  # builtins without a signature
        pass
    return compensator(X, y, **kwargs)


# ----------------------------------------------------------------------------- one seed
def score_seed(
    scenario: str | types.ModuleType, compensator: Any, seed: int, config: Any = None
) -> dict[str, float]:
    """Fit ``compensator`` on the scenario's training run for ``seed`` and score every held-out run.

    Parameters
    ----------
    scenario : str or module
        Registered scenario name, importable module path, or module object.
    compensator : estimator, estimator class, fit function or "module:attr"
        See the module docstring.
    seed : int
        Seed of the scenario's simulation (>= 0); also seeds the compensator.
    config : scenario Config, optional
        Defaults to the scenario's ``Config()`` (the paper's setup).

    Returns
    -------
    dict
        ``"<run label>/<score>"`` for every held-out run and ``"mean/<score>"``, the
        mean over the runs that report that score; keys sorted.

    Raises
    ------
    CompensatorError
        If the compensator's fit or predict raises (the message names the
        compensator, the seed, the stage and the original exception; the original
        is chained as ``__cause__``), its prediction has the wrong size, or its
        prediction or a score is not finite (NaN or inf: in a campaign such a seed
        is recorded as failed instead, see :func:`run_campaign`).
    TypeError
        If a fit function returns something that cannot predict.
    """
    comp = resolve_compensator(compensator)
    label = _compensator_label(comp, compensator, short=True)
    scores, failure = _score(scenario, comp, seed, config, label)
    if failure is not None:
        raise CompensatorError(
            f"compensator {label} failed on seed {seed}: {failure}",
            compensator=label,
            seed=seed,
            stage="score",
        )
    return scores


def _score(
    scenario: str | types.ModuleType,
    compensator: Any,
    seed: int,
    config: Any = None,
    label: str | None = None,
) -> tuple[dict[str, float], str | None]:
    """:func:`score_seed`, naming the compensator ``label`` in errors (default: from the object).

    Returns the scores and, for a failed seed, why it failed (:func:`_nonfinite`); else None.
    A seed fails at the first held-out run whose prediction or scores are not all finite;
    the runs after it are not scored.
    """
    from threadpoolctl import threadpool_limits

    module = resolve_scenario(scenario)
    comp = resolve_compensator(compensator)
    (seed,) = _check_seeds([seed])
    if config is None:
        config = module.Config()
    if label is None:
        label = _compensator_label(comp, compensator, short=True)
    with threadpool_limits(limits=1):
        task = module.compensation_task(config, seed)
        predict = _fit(comp, task.X_train, task.y_train, seed, label=label)
        scores: dict[str, float] = {}
        per_key: dict[str, list[float]] = {}
        for run in task.heldout:
            if run.label == "mean" or "/" in run.label:
                raise ValueError(
                    f"held-out run labels must not be 'mean' or contain '/'; got {run.label!r}"
                )
            stage = f"predict on run {run.label}"
            try:
                pred = np.asarray(predict(run.X), dtype=float)
            except Exception as exc:
                raise _compensator_failed(label, seed, stage, exc) from exc
            if pred.size != len(run.output):
                raise CompensatorError(
                    f"compensator {label} failed on seed {seed} ({stage}): the prediction must "
                    f"have {len(run.output)} values (one per sample of X); got shape {pred.shape}",
                    compensator=label,
                    seed=seed,
                    stage=stage,
                )
            failure = _nonfinite(f"the prediction on run {run.label}", pred)
            if failure is None:
                compensated = task.compensate(pred, run)
                with np.errstate(all="ignore"):  # an overflow is reported as a failed seed
                    run_scores = {k: float(v) for k, v in task.scorer(compensated, run).items()}
                bad = [k for k, v in run_scores.items() if not math.isfinite(v)]
                if bad:
                    failure = (
                        f"score {run.label}/{bad[0]} is {run_scores[bad[0]]!r}"
                        + (f" ({len(bad)} non-finite scores)" if len(bad) > 1 else "")
                    )
                for k, v in run_scores.items():
                    scores[f"{run.label}/{k}"] = v
                    per_key.setdefault(k, []).append(v)
            if failure is not None:
                return dict(sorted(scores.items())), failure
    for k, vals in per_key.items():
        scores[f"mean/{k}"] = math.fsum(vals) / len(vals)
    return dict(sorted(scores.items())), None


def _nonfinite(what: str, values: NDArray[np.float64]) -> str | None:
    """``"<what> has 3 non-finite values of 300 (nan at sample 0)"``, or None if all are finite."""
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size == 0:
        return None
    i = int(bad[0])
    return (
        f"{what} has {bad.size} non-finite value{'s' if bad.size > 1 else ''} of {values.size} "
        f"({float(values.flat[i])!r} at sample {i})"
    )


def _score_job(
    module_name: str, compensator: Any, seed: int, config: Any, label: str | None = None
) -> tuple[int, dict[str, float], float, str | None]:
    """Worker entry point (module level so it pickles by reference):
    (seed, scores, elapsed [s], failure or None)."""
    t0 = time.perf_counter()
    scores, failure = _score(importlib.import_module(module_name), compensator, seed, config, label)
    return seed, scores, time.perf_counter() - t0, failure


# ----------------------------------------------------------------------------- identity
#: gyrobench's own packages: a scenario's or compensator's imports are followed into these
_OWN_PACKAGES = frozenset({"gyrobench"})


def _file_hash(path: str) -> str:
    try:
        return hashlib.sha256(Path(path).read_bytes()).hexdigest()[:16]
    except OSError:
        return "unreadable"


def _module_file(name: str) -> str | None:
    """The source file of module ``name``, found without importing the module itself.

    Parent packages are imported (their ``__init__`` files only: for gyrobench these are
    cheap) because a package's ``__path__`` is the only reliable way to its submodules when
    setuptools maps folders to packages (an editable install's finder).
    """
    import importlib.util
    import sys

    mod = sys.modules.get(name)
    path = getattr(mod, "__file__", None) if mod is not None else None
    if path:
        return path
    parent, _, leaf = name.rpartition(".")
    if not parent:
        try:
            spec = importlib.util.find_spec(name)  # a top-level find_spec imports nothing
        except (ImportError, ValueError, AttributeError):
            return None
        return spec.origin if spec is not None and spec.has_location else None
    try:
        package = importlib.import_module(parent)
    except Exception:  # a user package that fails to import has no file to hash
        return None
    for d in map(Path, getattr(package, "__path__", None) or []):
        if (d / leaf / "__init__.py").is_file():
            return str(d / leaf / "__init__.py")
        if (d / f"{leaf}.py").is_file():
            return str(d / f"{leaf}.py")
    return None


def _is_third_party(path: str) -> bool:
    import sysconfig

    parts = Path(path).parts
    if "site-packages" in parts or "dist-packages" in parts:
        return True
    stdlib = sysconfig.get_paths().get("stdlib")
    if not stdlib:
        return False
    return Path(path).resolve().is_relative_to(Path(stdlib).resolve())


def _imports(path: str, name: str, is_pkg: bool) -> frozenset[str]:
    """Module names imported anywhere in the file (relative imports resolved)."""
    try:
        st = os.stat(path)
    except OSError:
        return frozenset()
    return _imports_cached(path, st.st_mtime_ns, st.st_size, name, is_pkg)


@functools.lru_cache(maxsize=1024)
def _imports_cached(path: str, mtime_ns: int, size: int, name: str, is_pkg: bool) -> frozenset[str]:
    """:func:`_imports`, cached on the file's modification time and size."""
    import ast

    try:
        tree = ast.parse(Path(path).read_bytes())
    except (OSError, SyntaxError, ValueError):
        return frozenset()
    package = name if is_pkg else name.rpartition(".")[0]
    out: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            try:
                base = (
                    importlib.util.resolve_name("." * node.level + (node.module or ""), package)
                    if node.level
                    else node.module
                )
            except (ImportError, ValueError):
                continue
            if not base:
                continue
            out.add(base)
            out.update(f"{base}.{a.name}" for a in node.names if a.name != "*")  # may be submodules
    return frozenset(out)


def _source_closure(name: str) -> list[tuple[str, str]]:
    """(module, file hash) for ``name`` and every module it imports, transitively, within its own
    top-level package and the gyrobench package; package ``__init__``
    files included. Third-party and standard-library modules are represented by their versions
    in the campaign identity instead."""
    roots = _OWN_PACKAGES | {name.partition(".")[0]}
    seen: dict[str, str] = {}
    todo = [name]
    while todo:
        mod = todo.pop()
        if mod in seen or mod.partition(".")[0] not in roots:
            continue
        path = _module_file(mod)
        if path is None or not path.endswith(".py"):
            continue
        seen[mod] = _file_hash(path)
        parent = mod.rpartition(".")[0]
        if parent:
            todo.append(parent)
        todo.extend(_imports(path, mod, Path(path).name == "__init__.py"))
    return sorted(seen.items())


def _module_hash(module_name: str | None) -> str:
    """Hash of a module's source: with its closure (:func:`_source_closure`) for user and
    gyrobench code, the file alone for third-party modules (their version is in the identity)."""
    if not module_name:
        return "none"
    path = _module_file(module_name)
    if not path:
        return "builtin"
    if _is_third_party(path):
        return _file_hash(path)
    return hashlib.sha256(json.dumps(_source_closure(module_name)).encode()).hexdigest()[:16]


def _versions() -> str:
    import scipy
    import sklearn
    from gyrobench.sim.recording import package_version

    return (
        f"gyrobench {package_version()} numpy {np.__version__} scipy {scipy.__version__} "
        f"sklearn {sklearn.__version__}"
    )


def _canonical(obj: Any, depth: int = 0) -> Any:
    """A JSON-able description of ``obj`` that is stable across processes and runs."""
    if depth > 20:
        return "..."
    if obj is None or isinstance(obj, (bool, int, str)):
        return obj
    if isinstance(obj, float):
        return repr(obj)
    if isinstance(obj, np.generic):
        return _canonical(obj.item(), depth + 1)
    if isinstance(obj, np.ndarray):
        return {
            "ndarray": list(obj.shape),
            "dtype": str(obj.dtype),
            "sha": hashlib.sha256(np.ascontiguousarray(obj).tobytes()).hexdigest()[:16],
        }
    if isinstance(obj, (list, tuple)):
        return [_canonical(o, depth + 1) for o in obj]
    if isinstance(obj, dict):
        return {
            str(k): _canonical(v, depth + 1)
            for k, v in sorted(obj.items(), key=lambda kv: str(kv[0]))
        }
    if isinstance(obj, type) or inspect.isroutine(obj):
        mod = getattr(obj, "__module__", None)
        return {
            "object": f"{mod}:{getattr(obj, '__qualname__', repr(obj))}",
            "source": _module_hash(mod),
        }
    if isinstance(obj, functools.partial):
        return {
            "partial": _canonical(obj.func, depth + 1),
            "args": _canonical(obj.args, depth + 1),
            "kwargs": _canonical(obj.keywords, depth + 1),
        }
    if hasattr(obj, "get_params"):
        cls = type(obj)
        return {
            "class": _canonical(cls, depth + 1),
            "params": _canonical(obj.get_params(deep=False), depth + 1),
        }
    if dataclasses.is_dataclass(obj):
        return {
            "dataclass": _canonical(type(obj), depth + 1),
            "fields": {
                f.name: _canonical(getattr(obj, f.name), depth + 1) for f in dataclasses.fields(obj)
            },
        }
    text = repr(obj)
    if " at 0x" in text:  # default object repr: the address changes every run
        return {"object": _canonical(type(obj), depth + 1)}
    return text


def compensator_identity(compensator: Any) -> str:
    """A stable JSON description of a compensator (class or function, parameters, source hash)."""
    return json.dumps(
        _canonical(resolve_compensator(compensator)), sort_keys=True, separators=(",", ":")
    )


def _compensator_label(comp: Any, given: Any, *, short: bool = False) -> str:
    """How the db and messages name a compensator: the string it was given as, else
    ``module:qualname`` of a class or function, else its repr (``short``: its class name)."""
    if isinstance(given, str):
        return given
    if isinstance(comp, type) or inspect.isroutine(comp):
        return f"{comp.__module__}:{comp.__qualname__}"
    if short:
        if isinstance(comp, functools.partial):
            return f"partial({_compensator_label(comp.func, None, short=True)})"
        return type(comp).__name__
    text = " ".join(repr(comp).split())
    return text if len(text) <= 200 else text[:197] + "..."


def campaign_id(scenario: str | types.ModuleType, compensator: Any, config: Any = None) -> str:
    """Hash of scenario (config, source closure, versions) and compensator (16 hex digits)."""
    module = resolve_scenario(scenario)
    if config is None:
        config = module.Config()
    ident = {
        "scenario": module.__name__,
        "scenario_source": _module_hash(module.__name__),
        "bench_source": _file_hash(__file__),
        "versions": _versions(),
        "config": _canonical(config),
        "compensator": json.loads(compensator_identity(compensator)),
    }
    return hashlib.sha256(json.dumps(ident, sort_keys=True).encode()).hexdigest()[:16]


# ----------------------------------------------------------------------------- results
@dataclass(frozen=True, slots=True, kw_only=True)
class ScoreSummary:
    """Mean of one score over seeds with its 95 % confidence interval (see :func:`_summary`).

    ``method`` says how the interval was computed: ``"t"``, ``"lognormal"`` or
    ``"t, clipped at 0"``.
    """

    name: str
    mean: float
    low: float
    high: float
    std: float
    n: int
    method: str = "t"


def _summary(name: str, values: NDArray[np.float64], level: float = 0.95) -> ScoreSummary:
    """Mean of the finite ``values`` and a ``level`` confidence interval for the mean.

    Notes
    -----
    A score that can take either sign (an improvement in %, a bias) gets the
    Student t interval ``mean +- t_{n-1} s / sqrt(n)``.

    A score that is non-negative by nature (:func:`score_is_nonnegative`: MSE, RMS,
    std, bias stability, nonlinearity, ...) is positive and right-skewed over seeds,
    and with few seeds the t interval routinely reaches below zero. If all its values
    are > 0 it gets the modified Cox interval for the mean of a lognormal variable
    (Olsson 2005, eq. 4): with ``m`` and ``s2`` the mean and variance (n - 1) of
    ``log(values)``,

        exp(m + s2/2 +- t_{n-1} sqrt(s2/n + s2**2 / (2 (n - 1)))),

    an interval for the arithmetic mean (not the geometric one), always > 0. In a
    simulation (20000 draws per case, lognormal sigma 0.1-1, n = 2-20) it covered
    the true mean 93-95 % of the time (t: 82-95 %, and its lower bound was
    negative up to 91 % of the time for n = 2), and always contained the sample
    mean. For small spread it tends to the t interval. A non-negative score with an
    exact zero among its values (log undefined) gets the t interval with its lower
    bound clipped at 0; one with a negative value (the name misled) gets the plain t.

    References
    ----------
    U. Olsson, "Confidence intervals for the mean of a log-normal distribution",
    Journal of Statistics Education 13(1), 2005.
    """
    from scipy import stats

    v = values[np.isfinite(values)]
    n = int(v.size)
    if n == 0:
        return ScoreSummary(
            name=name, mean=math.nan, low=math.nan, high=math.nan, std=math.nan, n=0
        )
    mean = float(np.mean(v))
    if n < 2:
        return ScoreSummary(name=name, mean=mean, low=math.nan, high=math.nan, std=math.nan, n=1)
    std = float(np.std(v, ddof=1))
    t = float(stats.t.ppf(0.5 + level / 2, n - 1))
    nonneg = score_is_nonnegative(name)
    if nonneg and bool(np.all(v > 0)):
        lv = np.log(v)
        m, s2 = float(np.mean(lv)), float(np.var(lv, ddof=1))
        half = t * math.sqrt(s2 / n + s2 * s2 / (2 * (n - 1)))
        low, high = math.exp(m + s2 / 2 - half), math.exp(m + s2 / 2 + half)
        return ScoreSummary(
            name=name, mean=mean, low=low, high=high, std=std, n=n, method="lognormal"
        )
    half = t * std / math.sqrt(n)
    low, high = mean - half, mean + half
    if nonneg and bool(np.all(v >= 0)):
        return ScoreSummary(
            name=name,
            mean=mean,
            low=max(0.0, low),
            high=high,
            std=std,
            n=n,
            method="t, clipped at 0",
        )
    return ScoreSummary(name=name, mean=mean, low=low, high=high, std=std, n=n)


def _order(names: Iterable[str]) -> list[str]:
    """``mean/*`` scores first, then the per-run ones, each alphabetically."""
    return sorted(names, key=lambda s: (not s.startswith("mean/"), s))


@dataclass(frozen=True, slots=True, kw_only=True)
class Campaign:
    """Scores of one compensator on one scenario over a set of seeds.

    Attributes
    ----------
    campaign_id : str
        Hash identifying scenario + configuration + code + compensator.
    scenario, compensator, config : str
        Human-readable descriptions.
    scores : mapping
        seed -> {score name: value}, in seed order (a failed seed's scores are those
        computed before it failed, possibly non-finite).
    computed, reused : int
        Seeds computed by this call / read back from the database.
    failed : mapping
        seed -> why it failed (a non-finite prediction or score), for the failed seeds.
        Summaries leave them out; :func:`compare` and :func:`save_baseline` refuse them.
    """

    campaign_id: str
    scenario: str
    compensator: str
    config: str
    scores: Mapping[int, Mapping[str, float]]
    computed: int = 0
    reused: int = 0
    db: str = ""
    failed: Mapping[int, str] = dataclasses.field(default_factory=dict)

    @property
    def seeds(self) -> tuple[int, ...]:
        return tuple(self.scores)

    @property
    def score_names(self) -> list[str]:
        names: set[str] = set()
        for s in self.scores.values():
            names.update(s)
        return _order(names)

    @property
    def ok_seeds(self) -> tuple[int, ...]:
        """The seeds that did not fail."""
        return tuple(s for s in self.scores if s not in self.failed)

    def values(self, name: str, seeds: Sequence[int] | None = None) -> NDArray[np.float64]:
        """The score ``name`` for each seed (NaN where a seed lacks it)."""
        seeds = self.seeds if seeds is None else seeds
        return np.array([self.scores[s].get(name, math.nan) for s in seeds], dtype=float)

    def summary(self, level: float = 0.95) -> dict[str, ScoreSummary]:
        """Per score: mean over the seeds that did not fail, with a ``level`` confidence interval.

        Student t for scores of either sign; for scores non-negative by nature a
        lognormal (modified Cox) interval that stays > 0 (see :func:`_summary`).
        """
        ok = self.ok_seeds
        return {n: _summary(n, self.values(n, ok), level) for n in self.score_names}

    def failure_text(self, limit: int = 10) -> str:
        """One line naming the failed seeds and the first reasons ("" when none failed)."""
        if not self.failed:
            return ""
        seeds = sorted(self.failed)
        first = seeds[0]
        return (
            f"compensator {self.compensator} failed on {len(seeds)} of {len(self.scores)} seeds "
            f"of {self.scenario} (seeds {_seed_text(seeds, limit)}); seed {first}: "
            f"{self.failed[first]}"
        )


def format_summary(campaign: Campaign) -> str:
    """A plain-text table of every score's mean, 95 % CI, how the CI was computed, and n.

    The header states the interval methods (see :func:`_summary`): Student t for
    scores of either sign; for scores non-negative by nature (mse, rms, std,
    stability, ...) the lognormal (modified Cox) interval for the mean, which is
    always > 0 (or the t interval clipped at 0 when a value is exactly 0).
    """
    rows = [("score", "mean", "95% CI", "CI", "n")]
    for s in campaign.summary().values():
        ci = "n/a" if math.isnan(s.low) else f"[{s.low:.6g}, {s.high:.6g}]"
        rows.append((s.name, f"{s.mean:.6g}", ci, s.method if s.n > 1 else "-", str(s.n)))
    w = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    head = (
        f"campaign {campaign.campaign_id}: scenario {campaign.scenario}, "
        f"compensator {campaign.compensator}; {len(campaign.scores)} seeds "
        f"({campaign.computed} computed, {campaign.reused} from the database)"
    )
    if campaign.failed:
        head += (
            f"; {len(campaign.failed)} FAILED (non-finite prediction or score: "
            f"seeds {_seed_text(sorted(campaign.failed))}), left out of the summary"
        )
    how = [
        "95% CI of the mean over seeds, by CI method: 't' = Student t; 'lognormal' = modified Cox",
        "interval, always > 0, for scores non-negative by nature (mse, rms, std, stability, ...);",
        "'t, clipped at 0' = such a score with a value of exactly 0",
    ]
    lines = [head, *how] + [
        "  ".join(c.ljust(w[i]) if i in (0, 3) else c.rjust(w[i]) for i, c in enumerate(r))
        for r in rows
    ]
    return "\n".join(lines)


# ----------------------------------------------------------------------------- database
_SCHEMA = """
CREATE TABLE IF NOT EXISTS campaigns (
    campaign_id TEXT PRIMARY KEY,
    scenario TEXT NOT NULL,
    compensator TEXT NOT NULL,
    config TEXT NOT NULL,
    identity TEXT NOT NULL,
    created REAL NOT NULL
);
CREATE TABLE IF NOT EXISTS seed_scores (
    campaign_id TEXT NOT NULL REFERENCES campaigns(campaign_id),
    seed INTEGER NOT NULL,
    scores TEXT NOT NULL,
    elapsed_s REAL NOT NULL,
    finished REAL NOT NULL,
    session_id INTEGER NOT NULL REFERENCES sessions(session_id),
    PRIMARY KEY (campaign_id, seed)
);
CREATE TABLE IF NOT EXISTS seed_failures (
    campaign_id TEXT NOT NULL REFERENCES campaigns(campaign_id),
    seed INTEGER NOT NULL,
    reason TEXT NOT NULL,
    PRIMARY KEY (campaign_id, seed)
);
CREATE TABLE IF NOT EXISTS sessions (
    session_id INTEGER PRIMARY KEY AUTOINCREMENT,
    campaign_id TEXT NOT NULL REFERENCES campaigns(campaign_id),
    started REAL NOT NULL,
    n_requested INTEGER NOT NULL,
    n_reused INTEGER NOT NULL,
    pid INTEGER NOT NULL
);
"""


def connect_db(path: str | os.PathLike, schema: str | None = None) -> sqlite3.Connection:
    """Open (or create) a results database: WAL, synchronous=FULL, ``schema`` (default the
    bench's) applied; bad paths and unwritable folders are one-line ValueErrors.

    Shared by the bench and :mod:`gyrobench.scenarios.units` (each with its own schema).
    """
    schema = _SCHEMA if schema is None else schema
    p = _check_output_file(path, what="db")
    try:
        conn = sqlite3.connect(str(p), timeout=60.0, isolation_level=None)  # explicit BEGIN/COMMIT
    except sqlite3.Error as exc:
        raise ValueError(f"db {str(p)!r} cannot be opened: {exc}") from None
    try:
        conn.execute("PRAGMA busy_timeout = 60000")
        mode = conn.execute("PRAGMA journal_mode = WAL").fetchone()[0]
        if str(mode).lower() != "wal":
            raise ValueError(f"db {str(p)!r}: cannot switch to WAL journal mode (got {mode!r})")
        conn.execute("PRAGMA synchronous = FULL")
        conn.executescript(schema)
    except sqlite3.OperationalError as exc:  # an unwritable folder or file, a read-only file system
        conn.close()
        writable = os.access(p.parent, os.W_OK) and (not p.exists() or os.access(p, os.W_OK))
        why = "" if writable else " (no write permission)"
        raise ValueError(
            f"db {str(p)!r} cannot be opened for writing{why}: {exc}; "
            "give --db in a writable folder"
        ) from None
    except sqlite3.DatabaseError as exc:
        conn.close()
        raise ValueError(f"db {str(p)!r} is not a usable SQLite database: {exc}") from None
    return conn


def _dumps_scores(scores: Mapping[str, float]) -> str:
    # JSON floats round-trip exactly (repr); NaN/inf as strings so the text stays valid JSON
    return json.dumps(
        {k: (v if math.isfinite(v) else repr(v)) for k, v in scores.items()}, sort_keys=True
    )


def _loads_scores(text: str) -> dict[str, float]:
    return {k: float(v) for k, v in json.loads(text).items()}


# ----------------------------------------------------------------------------- campaign
def _default_workers() -> int:
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def run_campaign(
    scenario: str | types.ModuleType,
    compensator: Any,
    seeds: Iterable[int] | str,
    *,
    config: Any = None,
    executor: cf.Executor | None = None,
    workers: int | None = None,
    db: str | os.PathLike = DEFAULT_DB,
    progress: bool = True,
) -> Campaign:
    """Score ``compensator`` on ``scenario`` for every seed, resuming from ``db``.

    Parameters
    ----------
    scenario : str or module
        Registered name, importable module path or module with ``compensation_task``.
    compensator : estimator, estimator class, fit function or "module:attr"
        See the module docstring. It must pickle (module-level functions and
        classes do; lambdas do not) unless ``workers=0``.
    seeds : iterable of int or str
        Distinct seeds >= 0, or the text forms of :func:`parse_seeds`.
    config : scenario Config, optional
        Defaults to ``Config()``.
    executor : concurrent.futures.Executor, optional
        Where seeds run, e.g. ``distributed.Client(addr).get_executor()``; it must
        be able to import the scenario module and the compensator's module. Not
        shut down by this function.
    workers : int, optional
        Size of the local process pool when ``executor`` is None (default: the
        usable CPUs). ``0`` runs the seeds one after another in this process.
    db : path
        SQLite file holding every finished seed (created if absent, in an
        existing folder: folders are not created).
    progress : bool
        Show a tqdm progress bar on stderr.

    Returns
    -------
    Campaign
        Scores for ``seeds`` in the order given.

    Raises
    ------
    CompensatorError
        If the compensator fails on a seed (see :func:`score_seed`); the message
        adds how many finished seeds are kept in ``db``. Seeds finished before the
        failure are committed; a rerun resumes from them.
    ValueError, TypeError
        Bad scenario, compensator, seeds or db. Any other exception inside a seed
        (a bug in the scenario) is re-raised as is, with a note naming the seed,
        after the seeds already finished are committed.
    """
    module = resolve_scenario(scenario)
    comp = resolve_compensator(compensator)
    seeds = parse_seeds(seeds) if isinstance(seeds, str) else _check_seeds(seeds)
    if config is None:
        config = module.Config()
    check_pool(executor, workers)
    cid = campaign_id(module, comp, config)
    label = _compensator_label(comp, compensator)
    short = _compensator_label(comp, compensator, short=True)
    scen_name = getattr(module, "NAME", module.__name__)

    conn = connect_db(db)
    try:
        conn.execute("BEGIN IMMEDIATE")
        conn.execute(
            "INSERT OR IGNORE INTO campaigns VALUES (?, ?, ?, ?, ?, ?)",
            (cid, scen_name, label, repr(config), compensator_identity(comp), time.time()),
        )
        done: dict[int, dict[str, float]] = {}
        wanted = set(seeds)
        failed: dict[int, str] = {}
        for seed, text in conn.execute(
            "SELECT seed, scores FROM seed_scores WHERE campaign_id = ?", (cid,)
        ):
            if seed in wanted:
                done[seed] = _loads_scores(text)
        for seed, reason in conn.execute(
            "SELECT seed, reason FROM seed_failures WHERE campaign_id = ?", (cid,)
        ):
            if seed in done:
                failed[seed] = reason
        cur = conn.execute(
            "INSERT INTO sessions (campaign_id, started, n_requested, n_reused, pid) "
            "VALUES (?, ?, ?, ?, ?)",
            (cid, time.time(), len(seeds), len(done), os.getpid()),
        )
        session = cur.lastrowid
        conn.execute("COMMIT")
        todo = [s for s in seeds if s not in done]
        reused = len(done)

        def record(
            seed: int, scores: dict[str, float], elapsed: float, failure: str | None
        ) -> None:
            text = _dumps_scores(scores)
            conn.execute("BEGIN IMMEDIATE")
            try:
                conn.execute(
                    "INSERT INTO seed_scores "
                    "(campaign_id, seed, scores, elapsed_s, finished, session_id) "
                    "VALUES (?, ?, ?, ?, ?, ?)",
                    (cid, seed, text, elapsed, time.time(), session),
                )
                if failure is not None:
                    conn.execute(
                        "INSERT INTO seed_failures (campaign_id, seed, reason) VALUES (?, ?, ?)",
                        (cid, seed, failure),
                    )
            except sqlite3.IntegrityError:
                # another process running the same campaign on this file stored it meanwhile;
                # scores are deterministic, so it must be the same
                conn.execute("ROLLBACK")
                (other,) = conn.execute(
                    "SELECT scores FROM seed_scores WHERE campaign_id = ? AND seed = ?", (cid, seed)
                ).fetchone()
                if other != text:
                    raise exits.InternalError(
                        f"seed {seed} of campaign {cid} gave different scores in two runs on "
                        f"db {str(db)!r}: the scenario or compensator is not deterministic "
                        "(it must give the same scores for the same seed)"
                    ) from None
                row = conn.execute(
                    "SELECT reason FROM seed_failures WHERE campaign_id = ? AND seed = ?",
                    (cid, seed),
                ).fetchone()
                failure = row[0] if row else failure
            except BaseException:
                conn.execute("ROLLBACK")
                raise
            else:
                conn.execute("COMMIT")
            done[seed] = _loads_scores(text)  # exactly what a resume reads back
            if failure is not None:
                failed[seed] = failure

        def kept() -> str:
            n = len(done)
            if n == 0:
                return f"no seed had finished (nothing stored in {str(db)!r})"
            return (
                f"the {n} finished seed{'s are' if n != 1 else ' is'} kept in {str(db)!r} "
                "(a rerun resumes from them)"
            )

        if todo:
            from tqdm import tqdm

            bar = tqdm(
                total=len(seeds),
                initial=reused,
                disable=not progress,
                desc=f"{scen_name} seeds",
                unit="seed",
                dynamic_ncols=True,
            )
            try:
                if executor is None and workers == 0:
                    for seed in todo:
                        try:
                            result = _score_job(module.__name__, comp, seed, config, short)
                        except CompensatorError as exc:
                            raise exc.with_context(kept()) from exc
                        except Exception as exc:
                            _note(exc, f"while scoring seed {seed} of {scen_name} ({kept()})")
                            raise
                        record(*result)
                        bar.update(1)
                else:
                    _check_picklable(comp, config)
                    own = executor is None
                    if own:  # every local worker holds one seed's task in memory at once
                        from gyrobench.scenarios import units

                        units.check_unit_memory(
                            module,
                            config,
                            concurrent=units.concurrent_units(len(todo), workers),
                            source="its configuration (bench seeds)",
                        )
                    ex: cf.Executor = (
                        cf.ProcessPoolExecutor(max_workers=workers or _default_workers())
                        if executor is None
                        else executor
                    )
                    futures: dict[cf.Future, int] = {}
                    try:
                        futures = {
                            ex.submit(_score_job, module.__name__, comp, s, config, short): s
                            for s in todo
                        }
                        for fut in cf.as_completed(futures):
                            seed = futures[fut]
                            try:
                                result = fut.result()
                            except CompensatorError as exc:
                                raise exc.with_context(kept()) from exc
                            except cf.BrokenExecutor as exc:
                                raise exits.InternalError(
                                    f"a worker process died while scoring seed {seed} of "
                                    f"{scen_name} (killed, or out of memory: see 'dmesg'); "
                                    f"{kept()}"
                                ) from exc
                            except Exception as exc:
                                _note(
                                    exc, f"while scoring seed {seed} of {scen_name} ({kept()})"
                                )
                                raise
                            record(*result)
                            bar.update(1)
                    finally:
                        for f in futures:
                            f.cancel()
                        if own:
                            ex.shutdown(wait=True, cancel_futures=True)
            finally:
                bar.close()
        return Campaign(
            campaign_id=cid,
            scenario=scen_name,
            compensator=label,
            config=repr(config),
            scores={s: done[s] for s in seeds},
            computed=len(todo),
            reused=reused,
            db=str(db),
            failed={s: failed[s] for s in seeds if s in failed},
        )
    finally:
        conn.close()


def _note(exc: BaseException, text: str) -> None:
    if hasattr(exc, "add_note"):  # Python >= 3.11
        exc.add_note(text)


def _check_picklable(comp: Any, config: Any) -> None:
    for what, obj in (("compensator", comp), ("config", config)):
        try:
            pickle.dumps(obj)
        except Exception as exc:  # noqa: BLE001 - pickling raises many kinds
            raise TypeError(
                f"{what} must pickle to run in worker processes (use a module-level function "
                "or class, "
                f"not a lambda or closure, or workers=0); got {obj!r}: {exc}"
            ) from None


# ----------------------------------------------------------------------------- baselines
def _check_output_file(path: str | os.PathLike, *, what: str) -> Path:
    """``path`` as a Path if it can be written as a file: not a folder, its folder exists
    and accepts new files (:func:`gyrobench.scenarios.outputs.check_output`).

    Missing folders are never created: a typo (or ``/nonexist/dir/b.json`` run as
    root) must not scatter folders over the file system.
    """
    from gyrobench.scenarios.outputs import check_output

    return check_output(path, what=what, kind="file", create_parents=False)


def check_baseline_path(path: str | os.PathLike, *, what: str = "baseline path") -> Path:
    """Check, before a campaign, that :func:`save_baseline` can write ``path``.

    Raises
    ------
    IsADirectoryError
        If ``path`` is a folder.
    FileNotFoundError
        If its folder does not exist (it is not created).
    PermissionError
        If its folder does not accept new files.
    """
    return _check_output_file(path, what=what)


def check_baseline_matches(
    baseline: Campaign,
    scenario: str | types.ModuleType,
    seeds: Iterable[int] | str | None = None,
    *,
    what: str = "baseline",
    seeds_what: str = "seeds",
) -> None:
    """Check, before a campaign, that its result can be compared with ``baseline``.

    :func:`compare` needs the same scenario and at least one common seed; this
    refuses a mismatch before anything is computed. ``what`` and ``seeds_what`` name
    the baseline and the seeds in the messages (``"--baseline 'b.json'"``, ``"--seeds"``).

    Raises
    ------
    ValueError
        If ``baseline`` is of another scenario, or ``seeds`` (when given) share no
        seed with it.
    """
    module = resolve_scenario(scenario)
    name = getattr(module, "NAME", module.__name__)
    if baseline.scenario != name:
        raise ValueError(
            f"{what} is of scenario {baseline.scenario!r}, not {name!r}; "
            "a paired comparison needs the same scenario"
        )
    if seeds is not None:
        seeds = parse_seeds(seeds) if isinstance(seeds, str) else _check_seeds(seeds)
        if not set(seeds) & set(baseline.seeds):
            raise ValueError(
                f"{seeds_what} must share seeds with {what} (its seeds: "
                f"{_seed_text(baseline.seeds)}); got {_seed_text(seeds)} "
                f"(omit {seeds_what} to use the baseline's)"
            )


def _json_float(v: float) -> float | None:
    return v if math.isfinite(v) else None


def save_baseline(path: str | os.PathLike, campaign: Campaign) -> Path:
    """Write ``campaign``'s per-seed scores to a JSON baseline (atomically).

    Raises
    ------
    TypeError
        If ``campaign`` is not a :class:`Campaign`.
    IsADirectoryError, FileNotFoundError
        If ``path`` is a folder or its folder does not exist (folders are never
        created).
    """
    from gyrobench.sim.recording import atomic_path, package_version

    if not isinstance(campaign, Campaign):
        raise TypeError(f"campaign must be a Campaign; got {type(campaign).__name__}")
    path = check_baseline_path(path)
    if campaign.failed:
        raise FailedSeedsError(
            f"not saving baseline {str(path)!r}: {campaign.failure_text()}",
            seeds=sorted(campaign.failed),
        )
    doc = {
        "format": BASELINE_FORMAT,
        "format_version": BASELINE_VERSION,
        "gyrobench_version": package_version(),
        "campaign_id": campaign.campaign_id,
        "scenario": campaign.scenario,
        "compensator": campaign.compensator,
        "config": campaign.config,
        "seeds": list(campaign.seeds),
        "scores": {
            str(s): {k: (v if math.isfinite(v) else None) for k, v in sc.items()}
            for s, sc in campaign.scores.items()
        },
        "summary": {
            n: {
                "mean": _json_float(s.mean),
                "low": _json_float(s.low),  # None: no interval (one seed)
                "high": _json_float(s.high),
                "n": s.n,
                "interval": s.method,
            }
            for n, s in campaign.summary().items()
        },
    }
    text = json.dumps(doc, indent=1, allow_nan=False, default=lambda o: None) + "\n"
    with atomic_path(path) as tmp:
        tmp.write_text(text)
    return path


def load_baseline(path: str | os.PathLike) -> Campaign:
    """Read a baseline written by :func:`save_baseline`.

    Raises
    ------
    FileNotFoundError
        If the file does not exist.
    ValueError
        If it is not a gyrobench baseline.
    """
    p = Path(path)
    if not p.is_file():
        raise FileNotFoundError(f"baseline file not found: {str(p)!r}")
    try:
        doc = json.loads(p.read_text())
        if doc.get("format") != BASELINE_FORMAT:
            raise ValueError(f"format is {doc.get('format')!r}, not {BASELINE_FORMAT!r}")
        if int(doc.get("format_version", 1)) > BASELINE_VERSION:
            raise ValueError(
                f"format_version must be <= {BASELINE_VERSION} (written by a newer gyrobench?); "
                f"got {doc.get('format_version')!r}"
            )
        scores = {
            int(s): {k: (math.nan if v is None else float(v)) for k, v in sc.items()}
            for s, sc in doc["scores"].items()
        }
        return Campaign(
            campaign_id=str(doc["campaign_id"]),
            scenario=str(doc["scenario"]),
            compensator=str(doc["compensator"]),
            config=str(doc["config"]),
            scores=dict(sorted(scores.items())),
            db=str(p),
        )
    except (ValueError, KeyError, TypeError, AttributeError) as exc:
        raise ValueError(f"baseline {str(p)!r} is not a gyrobench baseline file: {exc}") from None


@dataclass(frozen=True, slots=True, kw_only=True)
class ScoreComparison:
    """One score of a candidate campaign against the baseline, over the matching seeds.

    ``effect`` is the Hodges-Lehmann estimate of the paired shift (candidate - baseline,
    in the score's unit); ``relative`` = (mean candidate - mean baseline) / |mean baseline|.
    ``status`` is "improved", "regressed", "changed" (significant, direction unknown)
    or "unchanged".
    """

    name: str
    direction: int
    n: int
    baseline_mean: float
    candidate_mean: float
    effect: float
    relative: float
    p_value: float
    p_adjusted: float
    status: str


@dataclass(frozen=True, slots=True, kw_only=True)
class Comparison:
    """All scores compared; ``regressions`` non-empty means a significant regression.

    ``failed_seeds`` non-empty means the candidate failed on those seeds (a non-finite
    prediction or score): the comparison then fails whatever the scores say (``passed`` is
    False; the command line exits :data:`gyrobench.scenarios.exits.FAILED_SEEDS`), and
    ``failure`` says so in one line. The paired test runs on the other seeds.
    """

    scores: tuple[ScoreComparison, ...]
    seeds: tuple[int, ...]
    alpha: float
    test: str
    missing: tuple[str, ...] = ()
    note: str = ""
    failed_seeds: tuple[int, ...] = ()
    failure: str = ""

    @property
    def passed(self) -> bool:
        """No failed seed and no significant regression."""
        return not self.failed_seeds and not self.regressions

    @property
    def regressions(self) -> tuple[ScoreComparison, ...]:
        return tuple(s for s in self.scores if s.status == "regressed")

    @property
    def improvements(self) -> tuple[ScoreComparison, ...]:
        return tuple(s for s in self.scores if s.status == "improved")

    def format(self) -> str:
        """Plain text: one line per score, then the verdict."""
        lines = [
            f"comparison with the baseline over {len(self.seeds)} matching seeds: {self.test}, "
            f"Holm-adjusted over {len(self.scores)} scores, alpha {self.alpha:g}"
        ]
        if self.note:
            lines.append(f"note: {self.note}")
        rows = [("score", "status", "baseline", "candidate", "shift", "change", "p (Holm)")]
        for s in self.scores:
            rel = "n/a" if not math.isfinite(s.relative) else f"{100 * s.relative:+.3g}%"
            rows.append(
                (
                    s.name,
                    s.status,
                    f"{s.baseline_mean:.6g}",
                    f"{s.candidate_mean:.6g}",
                    f"{s.effect:+.3g}",
                    rel,
                    f"{s.p_adjusted:.3g}",
                )
            )
        w = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
        lines += [
            "  ".join(c.ljust(w[i]) if i < 2 else c.rjust(w[i]) for i, c in enumerate(r))
            for r in rows
        ]
        if self.missing:
            lines.append(f"not compared (in only one campaign): {', '.join(self.missing)}")
        reg, imp = self.regressions, self.improvements
        if self.failed_seeds:
            lines.append(f"FAILED: {self.failure}")
        if reg:
            lines.append(
                f"REGRESSION: {len(reg)} score(s) significantly worse: "
                + ", ".join(s.name for s in reg)
            )
        elif self.failed_seeds:
            lines.append(
                f"no significant regression on the {len(self.seeds)} seeds compared, but the "
                "comparison FAILS: the compensator failed on the seeds named above"
            )
        else:
            lines.append(f"no significant regression ({len(imp)} score(s) significantly better)")
        return "\n".join(lines)


def _holm(p: NDArray[np.float64]) -> NDArray[np.float64]:
    """Holm-Bonferroni step-down adjusted p-values (controls the family-wise error rate)."""
    m = p.size
    order = np.argsort(p, kind="stable")
    adj = np.empty(m)
    running = 0.0
    for rank, i in enumerate(order):
        running = max(running, min(1.0, (m - rank) * p[i]))
        adj[i] = running
    return adj


def _hodges_lehmann(d: NDArray[np.float64]) -> float:
    """Median of the Walsh averages (d_i + d_j)/2, i <= j (median of d for very long campaigns)."""
    if d.size > 3000:
        return float(np.median(d))
    i, j = np.triu_indices(d.size)
    return float(np.median((d[i] + d[j]) / 2))


def compare(
    baseline: Campaign | str | os.PathLike,
    campaign: Campaign | str | os.PathLike,
    *,
    alpha: float = 0.05,
    directions: Mapping[str, int] | None = None,
) -> Comparison:
    """Compare a candidate campaign with a baseline, seed by seed.

    Parameters
    ----------
    baseline, campaign : Campaign or path to a baseline JSON
    alpha : float
        Family-wise error rate over all compared scores.
    directions : mapping, optional
        Overrides for :func:`score_direction`.

    Returns
    -------
    Comparison

    Notes
    -----
    Both campaigns ran the same seeds, so seed ``s`` gives both compensators the
    same simulated data: the comparison is paired, on the per-seed differences
    ``d_s = candidate_s - baseline_s`` over the seeds both hold (seeds where either
    score is NaN are dropped).

    The test is the two-sided Wilcoxon signed-rank test (``scipy.stats.wilcoxon``,
    zeros dropped, exact null distribution for small n). It is chosen over the
    paired t-test because per-seed error scores (MSE, RMS, stability) are skewed
    and heavy-tailed, while the null hypothesis "the two compensators are
    interchangeable" makes ``d`` symmetric about zero, which is all the
    signed-rank test needs for its level to hold without a normality assumption.
    A score whose differences are all exactly zero (the same compensator: scores
    are deterministic) is "unchanged" with p = 1.

    A candidate seed that failed (listed in ``campaign.failed``, or with a non-finite
    score: a campaign read from JSON) is never dropped silently: it is named in
    ``failed_seeds`` and the comparison does not pass, whatever the other seeds say. A
    baseline seed with a non-finite score is left out of the paired test (with a note);
    if no seed is left, the comparison is refused.

    Many scores are tested at once (each held-out run and the mean), so the
    p-values are adjusted by Holm's step-down method, which keeps the probability
    of any false "regressed" or "improved" at most ``alpha``. A significant score
    is "improved" or "regressed" by the sign of the signed-rank statistic
    (``W+ - W-``) and the score's direction; the reported effect is the
    Hodges-Lehmann shift. With n nonzero differences the smallest attainable
    two-sided p is 2 / 2**n: use at least ~10 seeds (a note says when n is too
    small to ever reach significance).
    """
    from scipy import stats

    if not (isinstance(alpha, (int, float)) and 0 < alpha < 1):
        raise ValueError(f"alpha must be in (0, 1); got {alpha!r}")
    base = baseline if isinstance(baseline, Campaign) else load_baseline(baseline)
    cand = campaign if isinstance(campaign, Campaign) else load_baseline(campaign)
    if base.scenario != cand.scenario:
        raise ValueError(
            f"baseline is of scenario {base.scenario!r}, campaign of {cand.scenario!r}; "
            "a paired comparison needs the same scenario"
        )
    common = tuple(s for s in cand.seeds if s in base.scores)
    if not common:
        raise ValueError(
            f"baseline and campaign share no seed (baseline seeds {_seed_text(base.seeds)}, "
            f"campaign seeds {_seed_text(cand.seeds)}); run the campaign on the baseline's seeds"
        )
    bnames, cnames = set(base.score_names), set(cand.score_names)
    names = _order(bnames & cnames)
    if not names and set(cand.failed) >= set(common):  # failed before any score: compare all
        names, cnames = _order(bnames), bnames
    missing = tuple(_order(bnames ^ cnames))
    if not names:
        raise ValueError(
            "baseline and campaign have no score in common; were they run on the same scenario?"
        )
    cand_failed = dict(cand.failed)
    base_failed = set(base.failed)
    for s in common:
        if s not in cand_failed:
            bad = [n for n in names if not math.isfinite(cand.scores[s].get(n, math.nan))]
            if bad:
                cand_failed[s] = f"score {bad[0]} is {cand.scores[s].get(bad[0], math.nan)!r}"
        if any(not math.isfinite(base.scores[s].get(n, math.nan)) for n in names):
            base_failed.add(s)
    failed_seeds = tuple(sorted(s for s in cand_failed if s in cand.scores))
    seeds = tuple(s for s in common if s not in cand_failed and s not in base_failed)
    if not seeds and not failed_seeds:
        raise ValueError(
            f"the baseline has no finite scores on the seeds it shares with the campaign "
            f"({_seed_text(common)}): re-save it from a compensator that works"
        )
    rows: list[dict[str, Any]] = []
    pvals = []
    for name in names:
        b, c = base.values(name, seeds), cand.values(name, seeds)
        d = c - b
        nz = d[d != 0]
        if nz.size == 0:
            p, sign = 1.0, 0.0
        else:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # small-sample / ties notices
                res = stats.wilcoxon(nz, zero_method="wilcox", alternative="two-sided")
            p = float(res.pvalue) if np.isfinite(res.pvalue) else 1.0
            ranks = stats.rankdata(np.abs(nz))
            sign = float(np.sign(ranks[nz > 0].sum() - ranks[nz < 0].sum()))
        pvals.append(p)
        bm = float(np.mean(b)) if b.size else math.nan
        cm = float(np.mean(c)) if c.size else math.nan
        rows.append(
            dict(
                name=name,
                direction=score_direction(name, directions),
                n=int(d.size),
                baseline_mean=bm,
                candidate_mean=cm,
                effect=_hodges_lehmann(d) if d.size else math.nan,
                relative=(cm - bm) / abs(bm) if bm != 0 and math.isfinite(bm) else math.nan,
                p_value=p,
                sign=sign,
            )
        )
    adj = _holm(np.array(pvals))
    out = []
    for r, pa in zip(rows, adj, strict=True):
        sign = r.pop("sign")
        if pa < alpha and sign != 0:
            status = (
                "changed"
                if r["direction"] == 0
                else ("improved" if sign * r["direction"] > 0 else "regressed")
            )
        else:
            status = "unchanged"
        out.append(ScoreComparison(**r, p_adjusted=float(pa), status=status))
    n_min = min(r.n for r in out)
    notes = []
    dropped = sorted(s for s in base_failed if s in common and s not in cand_failed)
    if dropped:
        notes.append(
            f"baseline seeds {_seed_text(dropped)} have non-finite scores and are not compared"
        )
    if base.config != cand.config:
        notes.append("the two campaigns ran different scenario configurations")
    if 2.0 / 2.0**n_min * len(out) >= alpha:
        notes.append(
            f"only {n_min} paired seeds: the smallest attainable Holm-adjusted p is "
            f"{min(1.0, len(out) * 2.0 / 2.0**n_min):.3g} >= alpha {alpha:g}, "
            "so no change can be significant; use more seeds"
        )
    note = "; ".join(notes)
    failure = ""
    if failed_seeds:
        first = failed_seeds[0]
        failure = (
            f"compensator {cand.compensator} failed on {len(failed_seeds)} of {len(common)} "
            f"compared seeds (seeds {_seed_text(failed_seeds)}; seed {first}: "
            f"{cand_failed[first]}): a campaign with a failed seed never passes the comparison"
        )
    return Comparison(
        scores=tuple(out),
        seeds=seeds,
        alpha=float(alpha),
        test="two-sided Wilcoxon signed-rank on paired per-seed scores",
        missing=missing,
        note=note,
        failed_seeds=failed_seeds,
        failure=failure,
    )


def _seed_text(seeds: Sequence[int], limit: int = 10) -> str:
    s = list(seeds)
    if len(s) > 1 and s == list(range(s[0], s[-1] + 1)):
        return f"{s[0]}:{s[-1] + 1}"
    return ",".join(map(str, s[:limit])) + (f",... ({len(s)} seeds)" if len(s) > limit else "")
