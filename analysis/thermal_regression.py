"""Stepwise thermal-bias regression on block means of a two-sensor temperature log.

The glue a test engineer needs between a variable-temperature run of a gyro with a housing
(T1) and a cavity (T2) temperature sensor and :class:`~gyrobench.analysis.compensation.
stepwise.StepwiseRegression`:

:func:`two_sensor_blocks`
    block means of the two logged temperatures (e.g. the 100-s means of GJB practice) and
    the eleven candidate regressors x1..x11 of :mod:`gyrobench.analysis.regressors` on them;
:func:`block_bias_stability`
    bias stability of block means against a reference rate: the sample standard deviation
    (``n - 1``) of ``values - reference``;
:class:`StepwiseTable` / :func:`stepwise_table`
    a fitted stepwise model's regression table (Multiple R, R^2, adjusted R^2, RMSE, F,
    significance F), coefficients, p-values and steps, by term label, as a frozen value
    that can be applied to another run's regressors (:meth:`StepwiseTable.predict`);
:func:`selection_frequency`
    over many fitted models (gyros, runs): the fraction that selected each term.

They take plain arrays in the caller's units (degC and deg/h are usual; say which): nothing
here knows about simulation.

References
----------
GJB 2427-95 (laser gyro test methods): bias stability as the standard deviation of 100-s
means. MathWorks ``stepwisefit`` and Draper & Smith, *Applied Regression Analysis*, 3rd ed.,
ch. 15, for the stepwise procedure and its table statistics.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from sklearn.utils.validation import check_is_fitted

from gyrobench.analysis.compensation.stepwise import StepwiseRegression
from gyrobench.analysis.features import block_means
from gyrobench.analysis.regressors import two_sensor_regressors

__all__ = [
    "TwoSensorBlocks",
    "two_sensor_blocks",
    "block_bias_stability",
    "StepwiseTable",
    "stepwise_table",
    "selection_frequency",
]


@dataclass(frozen=True, slots=True, kw_only=True)
class TwoSensorBlocks:
    """Block means of a housing/cavity temperature log and the candidate regressors on them.

    Attributes
    ----------
    t1, t2 : ndarray, shape (n,)
        Block means of the housing and cavity temperatures [the log's unit, e.g. degC].
    X : ndarray, shape (n, 11)
        x1..x11 of :func:`gyrobench.analysis.regressors.two_sensor_regressors` on the block
        means (temperatures in the log's unit, rates in that unit per second).
    """

    t1: NDArray[np.float64]
    t2: NDArray[np.float64]
    X: NDArray[np.float64]


def two_sensor_blocks(
    t1: ArrayLike, t2: ArrayLike, fs: float, *, block_s: float, window_s: float
) -> TwoSensorBlocks:
    """Block means of two logged temperatures and the eleven candidate regressors on them.

    Parameters
    ----------
    t1, t2 : array_like, shape (m,)
        Housing and cavity temperatures as logged, same unit (e.g. degC), at ``fs``.
    fs : float
        Sample rate of the log [Hz].
    block_s : float
        Block length [s] (100 s in GJB practice); the incomplete tail is dropped.
    window_s : float
        Savitzky-Golay window of the temperature rates, on the block means [s].

    Returns
    -------
    TwoSensorBlocks

    Raises
    ------
    ValueError
        If a series is not 1-D or not finite, the log is shorter than one block, or shorter
        than the derivative window once block-averaged.

    Notes
    -----
    ``T_k = mean(T[k m : (k + 1) m])`` with ``m = round(block_s fs)``; the regressors are
    then computed on the block means sampled at ``1 / block_s``
    (:func:`gyrobench.analysis.features.block_means`,
    :func:`gyrobench.analysis.regressors.two_sensor_regressors`).

    Examples
    --------
    >>> t = np.arange(0.0, 2000.0, 1.0)
    >>> b = two_sensor_blocks(20 + 0.005 * t, 18 + 0.005 * t, 1.0, block_s=100.0, window_s=500.0)
    >>> b.X.shape, float(b.t1[0]), float(round(b.X[3, 2], 12)), float(b.X[3, 8])
    ((20, 11), 20.2475, 0.005, 2.0)
    """
    b1 = block_means(t1, fs, block_s=block_s)
    b2 = block_means(t2, fs, block_s=block_s)
    X = two_sensor_regressors(b1, b2, 1.0 / block_s, window_s=window_s)
    return TwoSensorBlocks(t1=b1, t2=b2, X=X)


def block_bias_stability(values: ArrayLike, reference: ArrayLike) -> float:
    """Bias stability of block means against a reference: ``std(values - reference)``, ``n - 1``.

    Parameters
    ----------
    values : array_like, shape (n,)
        Block means of a gyro output, raw or compensated [e.g. deg/h].
    reference : array_like, shape (n,)
        Block means of the reference rate (the turntable's, or zero for a static test),
        same unit.

    Returns
    -------
    float
        The 1-sigma bias stability in the unit of ``values``.

    Raises
    ------
    ValueError
        If the two series differ in shape, are not 1-D, or hold fewer than 2 blocks.

    Notes
    -----
    ``s = sqrt(sum((e_k - mean(e))^2) / (n - 1))`` with ``e_k = values_k - reference_k``:
    :func:`gyrobench.analysis.metrics.bias_stability` of the error when the block means are
    already taken (GJB 2427-95).

    Examples
    --------
    >>> block_bias_stability([1.0, 2.0, 3.0], [0.0, 0.0, 0.0])
    1.0
    """
    v = np.asarray(values, dtype=float)
    r = np.asarray(reference, dtype=float)
    if v.ndim != 1 or v.shape != r.shape:
        raise ValueError(
            f"values and reference must be 1-D of the same length; got shapes {v.shape} and {r.shape}"
        )
    if len(v) < 2:
        raise ValueError(f"bias stability needs at least 2 blocks; got {len(v)}")
    return float(np.std(v - r, ddof=1))


@dataclass(frozen=True, slots=True, kw_only=True)
class StepwiseTable:
    """A fitted stepwise model as a value: its regression table, coefficients and steps.

    Attributes
    ----------
    selected : tuple of str
        Labels of the selected terms, in column order.
    multiple_r, r2, adj_r2 : float
        Multiple R, R^2 and adjusted R^2 of the final model.
    rmse : float
        Residual standard error ``sqrt(RSS / (n - p - 1))`` [unit of the response].
    f_statistic, significance_f : float
        The regression's F and its p-value (NaN when nothing is selected).
    intercept : float
        [unit of the response].
    coef, coef_stderr, pvalues : tuple of float
        Per candidate term, in column order: coefficient (0 when excluded), its standard
        error (NaN when excluded), and the p-value of removing it (included) or adding it
        (excluded), as MATLAB's ``stepwisefit`` PVAL.
    steps : tuple of (str, str, float)
        ``("enter" | "remove", label, p-value)`` per step.
    """

    selected: tuple[str, ...]
    multiple_r: float
    r2: float
    adj_r2: float
    rmse: float
    f_statistic: float
    significance_f: float
    intercept: float
    coef: tuple[float, ...]
    coef_stderr: tuple[float, ...]
    pvalues: tuple[float, ...]
    steps: tuple[tuple[str, str, float], ...]

    def predict(self, X: ArrayLike) -> NDArray[np.float64]:
        """The model's response ``intercept + X @ coef`` on regressors ``X`` (n, len(coef)).

        Raises
        ------
        ValueError
            If ``X`` is not 2-D with one column per coefficient.
        """
        A = np.asarray(X, dtype=float)
        if A.ndim != 2 or A.shape[1] != len(self.coef):
            raise ValueError(f"X must have shape (n, {len(self.coef)}); got {A.shape}")
        return self.intercept + A @ np.asarray(self.coef)


def stepwise_table(model: StepwiseRegression, labels: Sequence[str]) -> StepwiseTable:
    """The regression table of a fitted :class:`StepwiseRegression`, terms named by ``labels``.

    Parameters
    ----------
    model : StepwiseRegression
        A fitted model.
    labels : sequence of str
        One label per column of the model's ``X`` (e.g. ``REGRESSOR_LABELS``).

    Returns
    -------
    StepwiseTable

    Raises
    ------
    sklearn.exceptions.NotFittedError
        If ``model`` is not fitted.
    ValueError
        If ``labels`` does not have one label per column.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> X = rng.standard_normal((200, 3))
    >>> m = StepwiseRegression().fit(X, 1.0 + 2.0 * X[:, 1] + 0.1 * rng.standard_normal(200))
    >>> t = stepwise_table(m, ["a", "b", "c"])
    >>> t.selected, t.steps[0][:2], round(t.r2, 2)
    (('b',), ('enter', 'b'), 1.0)
    """
    check_is_fitted(model, "coef_")
    labels = list(labels)
    if len(labels) != len(model.coef_):
        raise ValueError(f"labels must name each of the {len(model.coef_)} columns; got {len(labels)} labels")
    return StepwiseTable(
        selected=tuple(labels[j] for j in np.flatnonzero(model.support_)),
        multiple_r=float(model.multiple_r_),
        r2=float(model.r2_),
        adj_r2=float(model.adj_r2_),
        rmse=float(model.rmse_),
        f_statistic=float(model.f_statistic_),
        significance_f=float(model.significance_f_),
        intercept=float(model.intercept_),
        coef=tuple(float(c) for c in model.coef_),
        coef_stderr=tuple(float(c) for c in model.coef_stderr_),
        pvalues=tuple(float(p) for p in model.pvalues_),
        steps=tuple((a, labels[j], float(p)) for a, j, p in model.history_),
    )


def selection_frequency(selections: Iterable[Iterable[str]], labels: Sequence[str]) -> dict[str, float]:
    """Fraction of the models (gyros, runs) whose selection holds each term.

    Parameters
    ----------
    selections : iterable of iterable of str
        Each model's selected term labels.
    labels : sequence of str
        Every candidate term (the keys of the result, in this order).

    Returns
    -------
    dict
        ``{label: k / n}``, ``k`` models of ``n`` selected the term.

    Raises
    ------
    ValueError
        If there is no selection, or a selection names a term not in ``labels``.

    Examples
    --------
    >>> selection_frequency([["x1", "x3"], ["x3"]], ["x1", "x2", "x3"])
    {'x1': 0.5, 'x2': 0.0, 'x3': 1.0}
    """
    sels = [list(s) for s in selections]
    if not sels:
        raise ValueError("selections must hold at least one model's selection; got none")
    cnt = Counter(t for s in sels for t in s)
    unknown = sorted(set(cnt) - set(labels))
    if unknown:
        raise ValueError(f"selections name terms that are not in labels: {unknown}")
    n = len(sels)
    return {lab: cnt.get(lab, 0) / n for lab in labels}
