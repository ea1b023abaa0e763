"""A tiny, fast scenario with a compensation stage, used only by the bench tests.

A static gyro whose bias follows the temperature of a chamber cycle:

    e(t) = a (T - T0) + b dT/dt + c (T - T0) dT/dt + w(t)        [deg/h]

with white noise w of standard deviation ``noise_deg_h``. The truth is a zero
rate. Features: (T - T0) [K], dT/dt [K/min] and their product. A compensator that
drops the product feature leaves the c-term in the output, so it must score
worse. Each seed draws its own temperature cycles (phase and amplitude) and noise.

``GYROBENCH_TOY_CALL_LOG``: if set, each call of :func:`compensation_task`
appends ``"<seed>\\n"`` to that file (the kill/resume test counts them).
``Config.work`` adds a sleep-free CPU load (dense SVDs) for throughput benchmarks.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

import numpy as np
from sklearn.compose import ColumnTransformer
from sklearn.linear_model import LinearRegression
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler

from gyrobench.scenarios.base import CompensationTask, HeldOutRun

NAME = "toy"
TITLE = "Toy thermal bias (bench tests only)"
FEATURES = ("dT", "dTdt", "dT_x_dTdt")


@dataclass(frozen=True, slots=True, kw_only=True)
class Config:
    n_samples: int = 300
    fs_hz: float = 1.0 / 10.0
    coef: tuple[float, float, float] = (
        0.02,
        0.5,
        0.05,
    )  # a [deg/h/K], b [deg/h/(K/min)], c [deg/h/(K K/min)]
    noise_deg_h: float = 0.02
    n_heldout: int = 2
    work: int = 0  # extra CPU load: number of 120x120 SVDs per call

    def __post_init__(self) -> None:
        if self.n_samples < 10:
            raise ValueError(f"Config.n_samples must be >= 10; got {self.n_samples!r}")


def _run(config: Config, rng: np.random.Generator):
    t = np.arange(config.n_samples) / config.fs_hz
    period = t[-1] / rng.uniform(1.0, 2.5)
    amp = rng.uniform(5.0, 15.0)
    phase = rng.uniform(0, 2 * math.pi)
    dT = amp * np.sin(2 * math.pi * t / period + phase)
    dTdt = amp * 2 * math.pi / period * np.cos(2 * math.pi * t / period + phase) * 60.0  # K/min
    a, b, c = config.coef
    err = a * dT + b * dTdt + c * dT * dTdt
    out = err + config.noise_deg_h * rng.standard_normal(t.size)
    X = np.column_stack([dT, dTdt, dT * dTdt])
    return X, out


def compensation_task(config: Config, seed: int) -> CompensationTask:
    log = os.environ.get("GYROBENCH_TOY_CALL_LOG")
    if log:
        fd = os.open(log, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
        try:
            os.write(fd, f"{seed}\n".encode())
        finally:
            os.close(fd)
    rng = np.random.default_rng(seed)
    streams = rng.spawn(1 + config.n_heldout + 1)
    for _ in range(config.work):
        m = streams[-1].standard_normal((120, 120))
        np.linalg.svd(m)
    X_train, y_train = _run(config, streams[0])
    heldout = []
    for k in range(config.n_heldout):
        X, out = _run(config, streams[1 + k])
        heldout.append(HeldOutRun(label=f"run{k + 1}", X=X, output=out, truth=np.zeros_like(out)))
    return CompensationTask(
        scenario=NAME,
        feature_names=FEATURES,
        X_train=X_train,
        y_train=y_train,
        heldout=tuple(heldout),
        target="error",
        unit="deg/h",
        scorer=scorer,
    )


def scorer(compensated, run: HeldOutRun) -> dict[str, float]:
    err = np.asarray(compensated) - run.truth
    mse = float(np.mean(err**2))
    blocks = err[: err.size // 10 * 10].reshape(10, -1).mean(axis=1)
    return {"mse": mse, "rms": math.sqrt(mse), "bias_stability": float(np.std(blocks, ddof=1))}


# compensators used by the tests (module level so they pickle and resolve as "module:attr")
good = make_pipeline(StandardScaler(), LinearRegression())
#: drops the product feature (column 2)
degraded = make_pipeline(
    ColumnTransformer([("keep", "passthrough", [0, 1])]), StandardScaler(), LinearRegression()
)


def fit_least_squares(X, y):
    """A plain fit function: ordinary least squares with an intercept, returns predict(X)."""
    A = np.column_stack([X, np.ones(len(X))])
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    return lambda Xn: np.column_stack([Xn, np.ones(len(Xn))]) @ coef


def fit_returning_nonsense(X, y):
    """A broken fit function (returns a number, not a predictor)."""
    return 3.0


NOT_A_COMPENSATOR = 42
