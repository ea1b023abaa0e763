"""Radial-basis-function network trained as MATLAB ``newrb`` does, its deployment form, and a streaming compensator.

The network (docs/physics.md 7.2; MATLAB ``newrb`` / ``designrb``):

    a1_i = radbas(||c_i - p|| * b1_i),   radbas(n) = exp(-n^2),   b1_i = sqrt(-ln 0.5) / spread
    a2   = LW a1 + b2

so a basis function falls to 0.5 at a distance of ``spread`` from its centre.
Centres are chosen among the training inputs by orthogonal least squares forward
selection (Chen, Cowan & Grant, IEEE Trans. Neural Netw. 2(2), 1991), one neuron per
iteration, and the linear output layer (LW, b2) is re-solved by least squares after
every addition; training stops when the training MSE falls below ``goal`` or the
network has ``max_neurons`` neurons.

Input scaling
-------------
MATLAB ``newrb`` does not scale its inputs (no ``processFcns``; docs/physics.md 7.2 assumes
the same), so ``spread`` is in the units of the raw inputs. ``normalize="none"`` (the
default) reproduces that exactly: a paper that says "spread 1.2" with a frequency input
in Hz means 1.2 Hz. ``normalize="minmax"`` first maps every input column to [-1, 1]
with the training minimum and maximum (the MATLAB ``mapminmax`` convention), so
``spread`` is in those normalized units; use it when the inputs have different units
(e.g. T, dT/dt, T x dT/dt). A constant training column is mapped to 0.

The scaling is part of the exported deployment form (``x_offset``, ``x_gain``):

    p = (x - x_offset) .* x_gain        (identity for normalize="none")

References
----------
MathWorks, ``newrb`` documentation and ``newrb.m`` (``designrb``), Neural Network Toolbox.
S. Chen, C. F. N. Cowan, P. M. Grant, "Orthogonal least squares learning algorithm for
radial basis function networks", IEEE Trans. Neural Networks 2(2), 302-309, 1991.
Cheng, Qi, Zhao (seed paper 003): deployment as a1 = radbas(||IW - p|| .* b1), a2 = LW a1 + b2.
"""

from __future__ import annotations

import json
import math
from numbers import Integral, Real
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import solve_triangular
from scipy.spatial.distance import cdist
from sklearn.base import BaseEstimator, RegressorMixin
from sklearn.utils.validation import check_is_fitted, validate_data

from gyrobench.analysis.features import thermal_features

__all__ = ["RBFNetwork", "StreamingCompensator", "batch_compensate", "RADBAS_B"]

#: sqrt(-ln 0.5) = 0.8326: radbas(RADBAS_B) = 0.5, so b1 = RADBAS_B / spread.
RADBAS_B = math.sqrt(-math.log(0.5))

_NORMALIZE = ("none", "minmax")
_JSON_FORMAT = "gyrobench.rbf/1"


def _radbas(n: NDArray[np.float64]) -> NDArray[np.float64]:
    """MATLAB ``radbas``: exp(-n^2)."""
    return np.exp(-(n * n))


class RBFNetwork(RegressorMixin, BaseEstimator):
    """RBF network grown neuron by neuron as MATLAB ``newrb`` (orthogonal least squares).

    Parameters
    ----------
    spread : float, default 1.0
        Distance [input units, or normalized units with ``normalize="minmax"``] at which
        a basis function has fallen to 0.5 (``newrb`` SPREAD). Must be > 0.
    goal : float, default 0.0
        Mean-squared-error goal [target units^2] (``newrb`` GOAL): training stops as soon
        as the training MSE is below it. Must be >= 0.
    max_neurons : int or None, default None
        Maximum number of neurons (``newrb`` MN); None means the number of training
        samples (the ``newrb`` default).
    normalize : {"none", "minmax"}, default "none"
        Input scaling before the distance is taken (see the module docstring).
        ``"none"`` is MATLAB ``newrb``; ``"minmax"`` maps each column to [-1, 1].

    Attributes
    ----------
    centers_ : ndarray, shape (n_neurons, n_features)
        Centres (``IW``), in the network's input space, i.e. after the input scaling.
    b1_ : ndarray, shape (n_neurons,)
        Hidden-layer biases, all equal to 0.8326 / spread (MATLAB ``net.b{1}``).
    weights_ : ndarray, shape (n_outputs, n_neurons)
        Output-layer weights (``LW``).
    bias_ : ndarray, shape (n_outputs,)
        Output-layer bias (``b2``).
    n_neurons_ : int
        Number of neurons selected.
    mse_history_ : ndarray, shape (n_neurons,)
        Training MSE after each added neuron (the ``newrb`` progress record).
    selected_ : ndarray of int, shape (n_neurons,)
        Index of the training sample used as each centre, in selection order.
    x_offset_, x_gain_ : ndarray, shape (n_features,)
        Input scaling p = (x - x_offset_) * x_gain_.
    n_features_in_ : int
        Number of input columns.

    Notes
    -----
    Selection (``designrb``): with P[i, j] = radbas(||p_i - p_j|| b) (rows samples,
    columns candidate centres) and target matrix d, the error-reduction ratio of a
    candidate is e_j = (P_j' d)^2 / ((d' d)(P_j' P_j)) (summed in squares over outputs,
    MATLAB ``findLargeColumn``); the largest is picked, and all remaining columns are
    Gram-Schmidt orthogonalized against it before the next pick. After each pick the
    output layer [LW b2] is the least-squares solution of [LW b2] [a1; 1] = t.

    Deviation from ``newrb.m``, stated: a remaining candidate whose orthogonalized
    column has lost all but 1e-10 of its original squared norm (numerically dependent
    on the centres already chosen, e.g. a duplicated training input) is not eligible,
    and growth stops early when no eligible candidate is left. MATLAB would pick such
    a column on rounding noise. The output layer is solved with ``numpy.linalg.lstsq``
    (minimum norm) where MATLAB uses ``mrdivide``.

    Cost: the candidate matrix is n x n (n training samples), so memory is 8 n^2 bytes
    and each neuron costs O(n^2); decimate long records (block means) before fitting.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.linspace(-1.0, 1.0, 41)[:, None]
    >>> net = RBFNetwork(spread=0.5, goal=1e-6).fit(x, np.sin(3 * x[:, 0]))
    >>> bool(net.mse_history_[-1] < 1e-6)
    True
    """

    def __init__(self, spread=1.0, goal=0.0, max_neurons=None, normalize="none"):
        self.spread = spread
        self.goal = goal
        self.max_neurons = max_neurons
        self.normalize = normalize

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.target_tags.multi_output = True
        return tags

    # ------------------------------------------------------------------ params
    def _check_params(self) -> None:
        s = self.spread
        if isinstance(s, bool) or not isinstance(s, Real) or not (math.isfinite(float(s)) and float(s) > 0):
            raise ValueError(
                f"RBFNetwork.spread must be a finite number > 0 (input units); got {s!r}"
            )
        g = self.goal
        if isinstance(g, bool) or not isinstance(g, Real) or not (math.isfinite(float(g)) and float(g) >= 0):
            raise ValueError(
                f"RBFNetwork.goal must be a finite number >= 0 (target units^2); got {g!r}"
            )
        m = self.max_neurons
        if m is not None and (isinstance(m, bool) or not isinstance(m, Integral) or m < 1):
            raise ValueError(f"RBFNetwork.max_neurons must be None or an integer >= 1; got {m!r}")
        if self.normalize not in _NORMALIZE:
            raise ValueError(
                f"RBFNetwork.normalize must be one of {_NORMALIZE}; got {self.normalize!r}"
            )

    def _scale(self, X: NDArray[np.float64]) -> NDArray[np.float64]:
        return (X - self.x_offset_) * self.x_gain_

    # --------------------------------------------------------------------- fit
    def fit(self, X: ArrayLike, y: ArrayLike) -> RBFNetwork:
        """Grow the network on (X, y) as ``newrb(X', y', goal, spread, max_neurons)``.

        Parameters
        ----------
        X : array_like, shape (n_samples, n_features)
            Inputs.
        y : array_like, shape (n_samples,) or (n_samples, n_outputs)
            Targets.

        Returns
        -------
        self : RBFNetwork
        """
        self._check_params()
        X, y = validate_data(self, X, y, y_numeric=True, multi_output=True)
        X = np.asarray(X, dtype=float)
        y = np.asarray(y, dtype=float)
        self._y_ndim = y.ndim
        d = y.reshape(len(y), -1)
        q = X.shape[0]

        if self.normalize == "minmax":
            lo, hi = X.min(axis=0), X.max(axis=0)
            rng = hi - lo
            self.x_offset_ = 0.5 * (lo + hi)
            self.x_gain_ = np.where(rng > 0, 2.0 / np.where(rng > 0, rng, 1.0), 0.0)
        else:
            self.x_offset_ = np.zeros(X.shape[1])
            self.x_gain_ = np.ones(X.shape[1])
        Z = self._scale(X)

        b = RADBAS_B / float(self.spread)
        P = _radbas(cdist(Z, Z) * b)  # P[i, j]: sample i, candidate centre j
        pp0 = np.einsum("ij,ij->j", P, P)
        dd = np.einsum("ij,ij->j", d, d)
        mn = q if self.max_neurons is None else min(int(self.max_neurons), q)

        eligible = np.ones(q, dtype=bool)
        used: list[int] = []
        history: list[float] = []
        lw = np.zeros((d.shape[1], 0))
        b2 = d.mean(axis=0)
        last_w: NDArray[np.float64] | None = None
        # Output layer by an incrementally grown QR of G = [1, a1_1, a1_2, ...] (same least-squares
        # solution as re-solving from scratch, O(q k) per neuron); falls back to lstsq if G
        # becomes numerically rank-deficient.
        Qb = np.empty((q, mn + 1))
        Rb = np.zeros((mn + 1, mn + 1))
        Qb[:, 0] = 1.0 / math.sqrt(q)
        Rb[0, 0] = math.sqrt(q)
        qd = Qb[:, :1].T @ d
        use_lstsq = False
        for _ in range(mn):
            if last_w is not None:
                # Gram-Schmidt: remove the last picked (orthogonalized) column from all candidates.
                a = (last_w @ P) / (last_w @ last_w)
                P -= np.outer(last_w, a)
            pp = np.einsum("ij,ij->j", P, P)
            eligible &= pp > 1e-10 * pp0
            if not eligible.any():
                break
            with np.errstate(divide="ignore", invalid="ignore"):
                e = (P.T @ d) ** 2 / (pp[:, None] * dd[None, :])
            e[~np.isfinite(e)] = 0.0
            score = np.sum(e * e, axis=1)
            score[~eligible] = -1.0
            pick = int(np.argmax(score))
            used.append(pick)
            eligible[pick] = False
            last_w = P[:, pick].copy()

            m = len(used)
            g = _radbas(cdist(Z, Z[pick : pick + 1]) * b)[:, 0]
            if not use_lstsq:
                Qm = Qb[:, :m]
                v = g.copy()
                r = Qm.T @ v
                v -= Qm @ r
                r2 = Qm.T @ v  # second pass (re-orthogonalization)
                v -= Qm @ r2
                nv = float(np.linalg.norm(v))
                if nv > 1e-8 * float(np.linalg.norm(g)):
                    Qb[:, m] = v / nv
                    Rb[:m, m] = r + r2
                    Rb[m, m] = nv
                    qd = np.vstack([qd, Qb[:, m : m + 1].T @ d])
                    sol = solve_triangular(Rb[: m + 1, : m + 1], qd)
                    resid = d - Qb[:, : m + 1] @ qd
                else:
                    use_lstsq = True
            if use_lstsq:
                G = np.column_stack([np.ones(q), _radbas(cdist(Z, Z[used]) * b)])
                sol, *_ = np.linalg.lstsq(G, d, rcond=None)
                resid = d - G @ sol
            b2, lw = sol[0], sol[1:].T
            mse = float(np.mean(resid**2))
            history.append(mse)
            if mse < self.goal:
                break

        k = len(used)
        self.selected_ = np.asarray(used, dtype=int)
        self.centers_ = Z[self.selected_].copy()
        self.b1_ = np.full(k, b)
        self.weights_ = np.asarray(lw, dtype=float).reshape(d.shape[1], k)
        self.bias_ = np.asarray(b2, dtype=float).reshape(d.shape[1])
        self.n_neurons_ = k
        self.mse_history_ = np.asarray(history, dtype=float)
        return self

    # ----------------------------------------------------------------- predict
    def _forward(self, P: NDArray[np.float64]) -> NDArray[np.float64]:
        a1 = (
            _radbas(cdist(P, self.centers_) * self.b1_[None, :])
            if self.n_neurons_
            else np.zeros((len(P), 0))
        )
        return a1 @ self.weights_.T + self.bias_[None, :]

    def predict(self, X: ArrayLike) -> NDArray[np.float64]:
        """Network output a2 for the rows of X.

        Returns
        -------
        ndarray, shape (n_samples,) or (n_samples, n_outputs)
            Same dimensionality as the ``y`` given to ``fit``.
        """
        check_is_fitted(self, "centers_")
        X = validate_data(self, X, reset=False)
        out = self._forward(self._scale(np.asarray(X, dtype=float)))
        return out[:, 0] if self._y_ndim == 1 else out

    # -------------------------------------------------------------- deployment
    def to_json(self) -> str:
        """The fitted network in its deployment form, as a JSON string.

        The document holds ``x_offset``, ``x_gain`` (p = (x - x_offset) .* x_gain),
        ``IW`` (n_neurons x n_features), ``b1`` (n_neurons), ``LW`` (n_outputs x
        n_neurons), ``b2`` (n_outputs), so that a DSP computes

            a1 = radbas(||IW - p|| .* b1),  a2 = LW a1 + b2,  radbas(n) = exp(-n^2).

        Floats are written with ``repr`` precision, so ``from_json(to_json())``
        predicts bit for bit as the original.
        """
        check_is_fitted(self, "centers_")
        doc: dict[str, Any] = {
            "format": _JSON_FORMAT,
            "form": "p = (x - x_offset) .* x_gain; a1 = radbas(||IW - p|| .* b1); a2 = LW a1 + b2; "
            "radbas(n) = exp(-n^2)",
            "params": {
                "spread": float(self.spread),
                "goal": float(self.goal),
                "max_neurons": None if self.max_neurons is None else int(self.max_neurons),
                "normalize": self.normalize,
            },
            "n_features": int(self.n_features_in_),
            "y_ndim": int(self._y_ndim),
            "x_offset": self.x_offset_.tolist(),
            "x_gain": self.x_gain_.tolist(),
            "IW": self.centers_.tolist(),
            "b1": self.b1_.tolist(),
            "LW": self.weights_.tolist(),
            "b2": self.bias_.tolist(),
            "mse_history": self.mse_history_.tolist(),
        }
        return json.dumps(doc)

    @classmethod
    def from_json(cls, text: str) -> RBFNetwork:
        """Rebuild a fitted network from :meth:`to_json` output.

        Raises
        ------
        ValueError
            If the document is not a ``gyrobench.rbf/1`` network or its arrays disagree in shape.
        """
        doc = json.loads(text)
        if not isinstance(doc, dict) or doc.get("format") != _JSON_FORMAT:
            raise ValueError(
                f"RBF JSON must have format {_JSON_FORMAT!r}; "
                f"got {doc.get('format') if isinstance(doc, dict) else doc!r}"
            )
        p = doc["params"]
        net = cls(
            spread=p["spread"],
            goal=p["goal"],
            max_neurons=p["max_neurons"],
            normalize=p["normalize"],
        )
        nf = int(doc["n_features"])
        iw = np.asarray(doc["IW"], dtype=float).reshape(-1, nf)
        k = iw.shape[0]
        lw = np.asarray(doc["LW"], dtype=float)
        b2 = np.asarray(doc["b2"], dtype=float).reshape(-1)
        lw = lw.reshape(len(b2), k)
        b1 = np.asarray(doc["b1"], dtype=float).reshape(-1)
        xo = np.asarray(doc["x_offset"], dtype=float).reshape(-1)
        xg = np.asarray(doc["x_gain"], dtype=float).reshape(-1)
        if len(b1) != k or len(xo) != nf or len(xg) != nf:
            raise ValueError(
                f"RBF JSON arrays disagree: IW {iw.shape}, b1 {b1.shape}, x_offset {xo.shape}, x_gain {xg.shape}"
            )
        net.centers_, net.b1_, net.weights_, net.bias_ = iw, b1, lw, b2
        net.x_offset_, net.x_gain_ = xo, xg
        net.n_neurons_ = k
        net.n_features_in_ = nf
        net.mse_history_ = np.asarray(doc.get("mse_history", []), dtype=float)
        net.selected_ = np.full(
            k, -1, dtype=int
        )  # training indices are not part of the deployment form
        net._y_ndim = int(doc.get("y_ndim", 1))
        return net


# --------------------------------------------------------------------------------------
# Compensation of (output, temperature) records: batch and streaming give the same result
# --------------------------------------------------------------------------------------


def _drift_model_input(temperature: NDArray[np.float64], fs: float, window_s: float, product: bool):
    return thermal_features(temperature, fs, window_s=window_s, product=product)


def batch_compensate(
    model: Any,
    output: ArrayLike,
    temperature: ArrayLike,
    fs: float,
    *,
    window_s: float = 300.0,
    product: bool = True,
) -> NDArray[np.float64]:
    """Compensated output = output - model(T, dT/dt[, T x dT/dt]) over a whole record.

    Parameters
    ----------
    model : fitted regressor
        Predicts the output's drift from the thermal features (same units as ``output``).
    output : array_like, shape (n,)
        Gyro output [any unit; the model's target unit].
    temperature : array_like, shape (n,)
        Logged temperature [the unit the model was fitted in].
    fs : float
        Sample rate [Hz].
    window_s : float
        Derivative smoothing window [s] of :func:`gyrobench.analysis.features.thermal_features`.
    product : bool
        Include T x dT/dt (improved model) or not (traditional model).

    Returns
    -------
    ndarray, shape (n,)
    """
    out = np.asarray(output, dtype=float)
    T = np.asarray(temperature, dtype=float)
    if out.shape != T.shape or out.ndim != 1:
        raise ValueError(
            f"output and temperature must be 1-D of equal length; got {out.shape} and {T.shape}"
        )
    X = _drift_model_input(T, fs, window_s, product)
    return out - np.asarray(model.predict(X), dtype=float).reshape(-1)


class StreamingCompensator:
    """Block-wise compensation of (output, temperature) equal to :func:`batch_compensate`.

    The derivative of the features is a centred Savitzky-Golay filter, so a sample can
    be compensated once ``h = window // 2`` later samples have arrived; the first
    samples wait until a full window exists (their derivative is the polynomial fit of
    the first window, as in batch), and :meth:`flush` releases the last ``h`` samples at
    the end of the record (fit of the last window). The latency is therefore ``h``
    samples (``window_s / 2``). The concatenation of everything :meth:`push` and
    :meth:`flush` return equals ``batch_compensate`` on the whole record, for any block
    partition (the same filter coefficients are applied to the same samples).

    Parameters
    ----------
    model : fitted regressor
        E.g. :class:`RBFNetwork` or ``RBFNetwork.from_json(...)`` on the DSP side.
    fs, window_s, product
        As in :func:`batch_compensate`.
    """

    def __init__(
        self, model: Any, fs: float, *, window_s: float = 300.0, product: bool = True
    ) -> None:
        if (
            isinstance(fs, bool)
            or not isinstance(fs, (int, float, Real))
            or not (math.isfinite(float(fs)) and float(fs) > 0)
        ):
            raise ValueError(f"fs must be a finite number > 0 Hz; got {fs!r}")
        if not (isinstance(window_s, (int, float, Real)) and math.isfinite(float(window_s)) and float(window_s) > 0):
            raise ValueError(f"window_s must be > 0 s; got {window_s!r}")
        self.model = model
        self.fs = float(fs)
        self.window_s = float(window_s)
        self.product = bool(product)
        w = max(5, int(round(window_s * fs)) | 1)  # as analysis.features.smoothed_derivative
        self._w = w
        self._h = w // 2
        self._T = np.zeros(0)  # temperature samples from absolute index self._t0
        self._out = np.zeros(0)  # outputs of the pending samples (absolute index self._next ...)
        self._t0 = 0
        self._next = 0  # first sample not yet emitted
        self._n = 0  # samples received
        self._closed = False

    @property
    def latency_samples(self) -> int:
        """Samples a pushed sample waits before it is returned (h = window // 2)."""
        return self._h

    def _emit(self, upto: int) -> NDArray[np.float64]:
        """Compensate pending samples [self._next, upto) using the buffered temperature."""
        if upto <= self._next:
            return np.zeros(0)
        seg = self._T  # absolute indices [self._t0, self._n)
        X = _drift_model_input(seg, self.fs, self.window_s, self.product)
        i0, i1 = self._next - self._t0, upto - self._t0
        drift = np.asarray(self.model.predict(X[i0:i1]), dtype=float).reshape(-1)
        k = upto - self._next
        res = self._out[:k] - drift
        self._out = self._out[k:]
        self._next = upto
        # keep only what later windows still need: h samples before the next pending one
        # and the last full window, which flush() fits for the final h samples
        keep_from = max(self._t0, min(self._next - self._h, self._n - self._w))
        self._T = self._T[keep_from - self._t0 :]
        self._t0 = keep_from
        return res

    def push(self, output: ArrayLike, temperature: ArrayLike) -> NDArray[np.float64]:
        """Add a block; return the compensated samples that are now final (possibly none)."""
        if self._closed:
            raise RuntimeError("StreamingCompensator.push after flush(); create a new compensator")
        out = np.atleast_1d(np.asarray(output, dtype=float))
        T = np.atleast_1d(np.asarray(temperature, dtype=float))
        if out.shape != T.shape or out.ndim != 1:
            raise ValueError(
                f"output and temperature blocks must be 1-D of equal length; got {out.shape} and {T.shape}"
            )
        self._T = np.concatenate([self._T, T])
        self._out = np.concatenate([self._out, out])
        self._n += len(T)
        if self._n < self._w:
            return np.zeros(0)
        return self._emit(self._n - self._h)

    def flush(self) -> NDArray[np.float64]:
        """End of record: return the last pending samples.

        Raises
        ------
        ValueError
            If the whole record is shorter than one derivative window (batch fails too).
        """
        if self._n < self._w:
            raise ValueError(
                f"record of {self._n} samples is shorter than the derivative window of {self._w} samples "
                f"({self.window_s} s at {self.fs} Hz)"
            )
        self._closed = True
        return self._emit(self._n)
