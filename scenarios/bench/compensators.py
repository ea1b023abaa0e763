"""Compensators: the user's estimator, estimator class, fit function or ``"module:attr"``.

:func:`resolve_compensator` accepts exactly the forms listed in
:mod:`gyrobench.scenarios.bench`; :func:`fit_compensator` fits a fresh copy on one seed's
training set (seeding any ``random_state`` left at None from the seed) and returns its
``predict``. Whatever the user's code raises becomes a :class:`CompensatorError` naming
the compensator, the seed and the stage.
"""

from __future__ import annotations

import copy
import functools
import importlib
import inspect
import os
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gyrobench.scenarios.cli import exits

__all__ = [
    "TRACEBACK_ENV",
    "CompensatorError",
    "CompensatorImportError",
    "FailedSeedsError",
    "accepts_groups",
    "compensator_failed",
    "compensator_label",
    "fit_compensator",
    "fit_user_code",
    "predictor_of",
    "prepend_import_path",
    "resolve_compensator",
    "seed_int",
]


def prepend_import_path(folder: str | os.PathLike) -> None:
    """Put a folder first on ``sys.path`` (once) for compensators and module-path scenarios.

    Put ``folder`` first on ``sys.path`` (once), so ``"module:attr"`` compensators and
    module-path scenarios are found there before anywhere else, as ``python -m`` finds
    modules in the current folder. Worker processes inherit the path (``spawn`` and
    ``forkserver`` pass ``sys.path`` to the child).

    Parameters
    ----------
    folder : path-like
        The folder.
    """
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

    Parameters
    ----------
    message : str
        The one-line message.
    cause : BaseException or None
        The import's exception.
    traceback_text : str
        The import's traceback.
    """

    def __init__(self, message: str, cause: BaseException | None = None, *, traceback_text: str = "") -> None:
        import traceback

        super().__init__(message)
        self.traceback_text = traceback_text or ("".join(traceback.format_exception(cause)) if cause else "")


def _is_estimator(obj: Any) -> bool:
    return callable(getattr(obj, "fit", None)) and callable(getattr(obj, "predict", None))


def resolve_compensator(compensator: Any) -> Any:
    """Check ``compensator`` is one of the accepted forms (module docstring) and import strings.

    Returns the estimator instance, estimator class or fit function.

    Parameters
    ----------
    compensator : object
        An estimator instance or class, a fit function, or a ``"module:attr"`` string.

    Returns
    -------
    object
        The estimator instance, estimator class or fit function.

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


def seed_int(seed: int) -> int:
    """An integer in [0, 2**32) derived from the campaign seed, for ``random_state``.

    Parameters
    ----------
    seed : int
        The campaign seed.

    Returns
    -------
    int
        In [0, 2**32).
    """
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
    message : str
        The one-line message.
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

    Parameters
    ----------
    message : str
        The one-line message.
    seeds : sequence of int
        The failed seeds.
    """

    def __init__(self, message: str, *, seeds: Sequence[int] = ()) -> None:
        super().__init__(message)
        self.seeds = tuple(seeds)


def compensator_failed(label: str, seed: int, stage: str, exc: BaseException) -> CompensatorError:
    """The error for an exception the user's code raised on a seed.

    The :class:`CompensatorError` for ``exc`` raised by the user's code on ``seed`` at ``stage``,
    its traceback kept as text (raise it ``from exc``).

    Parameters
    ----------
    label : str
        The compensator's label.
    seed : int
        The seed.
    stage : str
        ``"fit"`` or ``"predict on run <label>"``.
    exc : BaseException
        What the user's code raised.

    Returns
    -------
    CompensatorError
        The error to raise.
    """
    import traceback

    detail = " ".join(str(exc).split()) or "(no message)"
    # an exception raised in the compensator's own process arrives as text: its class name and traceback
    name = getattr(exc, "remote_type", None) or type(exc).__name__
    text = getattr(exc, "traceback_text", None) or "".join(traceback.format_exception(exc))
    return CompensatorError(
        f"compensator {label} failed on seed {seed} ({stage}): {name}: {detail}",
        compensator=label,
        seed=seed,
        stage=stage,
        traceback_text=text,
    )


def fit_compensator(
    compensator: Any,
    X: NDArray[np.float64],
    y: NDArray[np.float64],
    seed: int,
    *,
    label: str,
    groups: NDArray[np.int_] | None = None,
) -> Callable:
    """Fit a fresh copy of ``compensator`` and return ``predict(X) -> ndarray``.

    ``groups`` (the task's ``groups_train``, one label per row of ``X``) is passed as
    ``groups=`` only to a compensator that takes it (:func:`accepts_groups`); others are
    fitted as ``fit(X, y)``. Any exception raised by the user's code (instantiation, cloning, fit, the fit
    function) becomes a :class:`CompensatorError` naming ``label`` and ``seed``; a
    fit function returning something that cannot predict is a ``TypeError``.

    Parameters
    ----------
    compensator : object
        The resolved compensator.
    X : ndarray
        Training features.
    y : ndarray
        Training target.
    seed : int
        The campaign seed.
    label : str
        The compensator's label, for errors.
    groups : ndarray of int or None
        The task's training groups.

    Returns
    -------
    callable
        ``predict(X) -> ndarray``.
    """
    try:
        predictor = fit_user_code(compensator, X, y, seed_int(seed), groups)
    except Exception as exc:
        raise compensator_failed(label, seed, "fit", exc) from exc
    try:
        return predictor_of(compensator, predictor)
    except TypeError as exc:
        raise TypeError(f"{exc} (compensator {label}, seed {seed})") from None


def predictor_of(compensator: Any, predictor: Any) -> Callable:
    """The ``predict(X)`` of what fitting returned: its ``.predict``, or itself if callable.

    Parameters
    ----------
    compensator : object
        The resolved compensator, for the message.
    predictor : object
        What fitting returned.

    Returns
    -------
    callable
        ``predict(X)``.

    Raises
    ------
    TypeError
        If it can do neither (a fit function that returned a number).
    """
    if callable(getattr(predictor, "predict", None)):
        return predictor.predict
    if callable(predictor):
        return predictor
    raise TypeError(
        f"fit function {getattr(compensator, '__qualname__', compensator)!r} must return "
        f"a callable predict(X) or an object with .predict(X); got {type(predictor).__name__}"
    )


def accepts_groups(fit: Any) -> bool:
    """Whether the bench passes a task's training groups to a ``fit``.

    Whether the bench passes a task's training groups to ``fit`` (an estimator's bound ``fit``
    or a fit function): when its signature names a ``groups`` parameter, or it is the ``fit`` of
    a scikit-learn hyper-parameter search (``GridSearchCV``, ``RandomizedSearchCV``, ...), which
    routes ``groups`` to its ``cv`` splitter (e.g. ``LeaveOneGroupOut``) through ``**params``.

    Parameters
    ----------
    fit : callable
        A bound ``fit`` or a fit function.

    Returns
    -------
    bool
        True when it takes ``groups``.
    """
    try:
        from sklearn.model_selection._search import BaseSearchCV
    except ImportError:  # pragma: no cover - scikit-learn is a dependency
        BaseSearchCV = ()  # noqa: N806
    if isinstance(getattr(fit, "__self__", None), BaseSearchCV):
        return True
    try:
        params = inspect.signature(fit).parameters
    except (TypeError, ValueError):  # builtins without a signature
        return False
    p = params.get("groups")
    return p is not None and p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)


def fit_user_code(
    compensator: Any,
    X: NDArray[np.float64],
    y: NDArray[np.float64],
    rs: int,
    groups: NDArray[np.int_] | None = None,
) -> Any:
    """Run the user's fit on the training data.

    The user's code in :func:`fit_compensator` (and in the sandbox's child): the fitted
    estimator's predict, or what a fit function returned; ``rs`` is the ``random_state`` given
    to every ``random_state`` left at None (:func:`seed_int` of the seed).

    Parameters
    ----------
    compensator : object
        The resolved compensator.
    X : ndarray
        Training features.
    y : ndarray
        Training target.
    rs : int
        The ``random_state`` given.
    groups : ndarray of int or None
        The task's training groups.

    Returns
    -------
    object
        The fitted estimator, or what the fit function returned.
    """
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
        fit_kw = {"groups": groups} if groups is not None and accepts_groups(est.fit) else {}
        fitted = est.fit(X, y, **fit_kw)
        return (est if fitted is None else fitted).predict
    kwargs: dict[str, Any] = {}
    try:
        if "random_state" in inspect.signature(compensator).parameters:
            kwargs["random_state"] = rs
    except (TypeError, ValueError):  # builtins without a signature
        pass
    if groups is not None and accepts_groups(compensator):
        kwargs["groups"] = groups
    return compensator(X, y, **kwargs)


def compensator_label(comp: Any, given: Any, *, short: bool = False) -> str:
    """How the database and the messages name a compensator.

    How the db and messages name a compensator: the string it was given as, else
    ``module:qualname`` of a class or function, else its repr (``short``: its class name).

    Parameters
    ----------
    comp : object
        The resolved compensator.
    given : object
        What the user gave.
    short : bool
        The class name only.

    Returns
    -------
    str
        The label.
    """
    if isinstance(given, str):
        return given
    if isinstance(comp, type) or inspect.isroutine(comp):
        return f"{comp.__module__}:{comp.__qualname__}"
    if short:
        if isinstance(comp, functools.partial):
            return f"partial({compensator_label(comp.func, None, short=True)})"
        return type(comp).__name__
    text = " ".join(repr(comp).split())
    return text if len(text) <= 200 else text[:197] + "..."
