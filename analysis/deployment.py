"""A fitted RBF network evaluated as a single-precision embedded target would run it.

Temperature compensations are trained on a PC in double precision and deployed on a DSP
or microcontroller with a single-precision FPU (e.g. the TMS320F28335 of Cheng, Qi and
Zhao 2016). :func:`deployment_float32` evaluates the exported network
(:meth:`gyrobench.analysis.compensation.rbf.RBFNetwork.to_json`) with every array and
every operation in IEEE 754 binary32, so the effect of deployment precision on a
compensation can be measured before it is flashed.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["deployment_float32"]

_KEYS = ("x_offset", "x_gain", "IW", "b1", "LW", "b2")


def deployment_float32(doc: Mapping[str, Any] | str, X: ArrayLike) -> NDArray[np.float32]:
    """Evaluate an exported network (``RBFNetwork.to_json`` document) entirely in float32.

    p = (x - x_offset) .* x_gain; a1 = radbas(||IW - p|| .* b1) with radbas(n) = exp(-n^2);
    a2 = LW a1 + b2 (MATLAB newrb's form), every array and every operation in IEEE single
    precision. The inputs are rounded to float32 first.

    Parameters
    ----------
    doc : mapping or str
        The exported document (parsed, or its JSON text).
    X : array_like, shape (n, k)
        Inputs in their field units, as the network was trained on.

    Returns
    -------
    ndarray of float32, shape (n,)
        The first output of the network.

    Raises
    ------
    ValueError
        If ``doc`` lacks one of the network's arrays or ``X`` is not 2-D.
    """
    d = json.loads(doc) if isinstance(doc, str) else doc
    missing = [k for k in _KEYS if k not in d]
    if missing:
        raise ValueError(f"deployment_float32: doc must hold {list(_KEYS)}; missing {missing}")
    f = np.float32
    x = np.asarray(X, dtype=f)
    if x.ndim != 2:
        raise ValueError(f"deployment_float32: X must have shape (n, k); got {x.shape}")
    p = (x - np.asarray(d["x_offset"], dtype=f)) * np.asarray(d["x_gain"], dtype=f)
    iw = np.asarray(d["IW"], dtype=f).reshape(-1, x.shape[1])
    dist = np.sqrt(np.sum((p[:, None, :] - iw[None, :, :]) ** 2, axis=2, dtype=f), dtype=f)
    n = dist * np.asarray(d["b1"], dtype=f)[None, :]
    a1 = np.exp(-(n * n), dtype=f)
    lw = np.asarray(d["LW"], dtype=f).reshape(-1, iw.shape[0])
    a2 = a1 @ lw.T + np.asarray(d["b2"], dtype=f)[None, :]
    return a2[:, 0]
