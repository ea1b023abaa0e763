"""Paper 000's compensation task for ``gyrobench bench``: the bias model's features and targets.

Any regressor the bench runs is trained on one unit's sweep record and scored on another run of
the same unit (fresh noise and shaker control: the paper models and compensates one gyro), its
sweep and fixed-frequency records (block means, see :func:`compensation_task`).
"""

from __future__ import annotations

from functools import partial
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gyrobench.analysis.wavelet import MultiscaleDecomposition, decompose
from gyrobench.base import units
from gyrobench.io.recording import Recording
from gyrobench.scenarios.base import CompensationTask, HeldOutRun, mse_scores
from gyrobench.scenarios.bench.primary import PrimaryScore, ScenarioScores

from . import NAME
from .config import Config
from .experiment import simulate
from .pipeline import _near_edges, block_means

__all__ = ["BENCH_SCORES", "FogVibrationBias", "compensation_task", "fog_vibration_rbf"]

#: the primary scores, the score units and the paper's method
BENCH_SCORES = ScenarioScores(
    primary=(
        PrimaryScore(
            name="mean/rms",
            unit="deg/h",
            direction=-1,
            meaning="RMS error left by the vibration-bias model, mean over the held-out records",
        ),
    ),
    units={"mse": "(deg/h)^2", "rms": "deg/h"},
    paper=f"{__name__}:fog_vibration_rbf",
    paper_label="RBF on frequency bins (paper)",
)


def _bench_arrays(
    rec: Recording, config: Config, dec: MultiscaleDecomposition | None = None
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
    """Block means at ``bench_rate_hz``: X = [frequency Hz, acceleration g], output [deg/h],
    truth [deg/h], the a_{train_level} bias [deg/h]; and which blocks hold a sample within
    ``train_edge_s`` of a shaker on/off edge."""
    k = max(1, int(round(rec.fs / config.bench_rate_hz)))
    y = units.to_deg_per_h(rec["output"])
    if dec is None:
        dec = decompose(y, rec.fs, wavelet=config.wavelet, level=config.level)
    bias = dec.approx(config.train_level)
    vb = units.to_deg_per_h(rec["detail/vibration_bias"])
    f = block_means(rec["shaker_frequency"], k)
    a = block_means(units.to_g(rec["shaker_amplitude"]), k)
    near = block_means(_near_edges(rec["shaker_on"] > 0.5, rec.fs, config.train_edge_s).astype(float), k) > 0
    x = np.column_stack([f, a])
    return x, block_means(y, k), block_means(y - vb, k), block_means(bias, k), near


def compensation_task(config: Config, seed: int) -> CompensationTask:
    """Train on the sweep's bias against [frequency, acceleration]; hold out another run of the same unit.

    Samples are block means at ``config.bench_rate_hz`` (2 Hz: the wavelet approximations hold
    nothing above fs/2^7 = 3.1 Hz). Target (``"error"``): what paper 000's RBF and LS bias
    models are fitted to (:func:`~.pipeline.fit_bias_models`), the a_{``train_level``}
    approximation minus its phase-1 mean [deg/h], 0 on static blocks (no vibration error to
    learn); blocks within ``train_edge_s`` of a shaker on/off edge are left out of the
    training set, as the paper's models leave those samples out. Held-out truth: the output
    with the true vibration bias removed (``detail/vibration_bias``: rectification, loop error,
    strain nonreciprocity and mount coning), so the default MSE score [(deg/h)^2] is the bias
    model's error alone: an identity (no compensation) scores the true bias.

    Parameters
    ----------
    config : Config
        The paper's configuration.
    seed : int
        The unit's seed.

    Returns
    -------
    CompensationTask
        The training and held-out runs of one unit.
    """
    sweep, _ = simulate(config, seed)
    x, _, _, bias, near = _bench_arrays(sweep, config)
    on = x[:, 1] > 0
    first_on = int(np.argmax(on)) if on.any() else len(on)
    y = bias - (np.mean(bias[:first_on]) if first_on else 0.0)
    y = np.where(on, y, 0.0)  # static samples: no vibration error to learn
    held = []
    h_sweep, h_fixed = simulate(config, seed, record_seed=seed + 1_000_003)
    for label, rec in (("sweep", h_sweep), ("fixed", h_fixed)):
        xh, out, truth, _, _ = _bench_arrays(rec, config)
        held.append(HeldOutRun(label=label, X=xh, output=out, truth=truth))
    return CompensationTask(
        scenario=NAME,
        feature_names=("frequency_hz", "acceleration_g"),
        X_train=x[~near],
        y_train=y[~near],
        heldout=tuple(held),
        target="error",
        unit="deg/h",
        scorer=mse_scores,
    )


class FogVibrationBias:
    """A fitted paper-000 bias model as a bench predictor.

    A fitted paper-000 bias model as a bench predictor: ``predict(X)`` with X = [frequency Hz,
    acceleration g] is the model's bias [deg/h] at the frequency clipped to the training range
    [``lo``, ``hi``] Hz while the shaker runs (acceleration > 0), 0 when it is off, as the paper
    compensates (:func:`gyrobench.scenarios.papers.p000_fog_vibration.pipeline.predict_on`).

    Parameters
    ----------
    model : callable
        The fitted bias model, frequency [Hz] -> bias [deg/h].
    lo, hi : float
        The training frequency range [Hz] the input is clipped to.
    """

    def __init__(self, model: Any, lo: float, hi: float) -> None:
        self.model, self.lo, self.hi = model, lo, hi

    def predict(self, X: NDArray[np.float64]) -> NDArray[np.float64]:
        X = np.asarray(X, dtype=float)
        out = np.zeros(len(X))
        on = X[:, 1] > 0
        if on.any():
            out[on] = np.asarray(self.model(np.clip(X[on, 0], self.lo, self.hi)), dtype=float).reshape(-1)
        return out


def fog_vibration_rbf(
    X: NDArray[np.float64], y: NDArray[np.float64], random_state: int | None = None
) -> FogVibrationBias:
    """The paper's method as a bench compensator: an RBF network of the bias against frequency.

    The fog_vibration paper's method: an RBF network with randomly fixed centres of the bias
    [deg/h] against the drive frequency [Hz], fitted to the means of the target in
    ``Config().bin_width_hz`` frequency bins over the rows where the shaker runs (acceleration > 0),
    spread ``rbf_spread_hz``, goal ``rbf_goal_deg_h2``, ``rbf_max_neurons``
    (:class:`gyrobench.analysis.compensation.random_rbf.RandomCentreRBF`; the paper's Fig. 6
    model, :func:`~gyrobench.scenarios.papers.p000_fog_vibration.pipeline.fit_bias_models`).
    Predicts 0 while the shaker is off (:class:`FogVibrationBias`).

    Parameters
    ----------
    X : ndarray
        Rows of [frequency Hz, acceleration g].
    y : ndarray
        The target bias [deg/h].
    random_state : int or None
        Seed of the randomly fixed centres.

    Returns
    -------
    FogVibrationBias
        The fitted predictor.
    """
    from gyrobench.analysis.compensation.random_rbf import RandomCentreRBF
    from gyrobench.analysis.sweep import bin_means

    c = Config()
    X = np.asarray(X, dtype=float)
    on = X[:, 1] > 0
    if not on.any():
        raise ValueError("fog_vibration_rbf needs training rows with the shaker on (acceleration > 0); got none")
    lo, hi = min(c.sweep_start_hz, c.sweep_end_hz), max(c.sweep_start_hz, c.sweep_end_hz)
    fb, yb = bin_means(X[on, 0], np.asarray(y, dtype=float)[on], lo=lo, hi=hi, width=c.bin_width_hz)
    net = RandomCentreRBF(
        spread=c.rbf_spread_hz, goal=c.rbf_goal_deg_h2, max_neurons=c.rbf_max_neurons, random_state=random_state
    ).fit(fb[:, None], yb)
    column = partial(_predict_column, net)
    return FogVibrationBias(column, float(fb[0]), float(fb[-1]))


def _predict_column(model: Any, u: NDArray[np.float64]) -> NDArray[np.float64]:
    """A fitted regressor of one input column on the 1-D input ``u``."""
    return np.asarray(model.predict(np.asarray(u, dtype=float).reshape(-1, 1)), dtype=float)
