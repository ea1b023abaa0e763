"""gyrobench: a physics-based gyroscope simulator and test bench.

Subpackages
-----------
gyrobench.sim
    The physics: what a gyro outputs in a given environment (noise engine, FOG, MEMS and
    RLG models, rate table, thermal chamber, shaker). SI units inside.
gyrobench.analysis
    Methods for any recording, simulated or real: Allan deviations and the Q/N/B/K/R fit,
    wavelets, the papers' compensators as scikit-learn estimators, scores.
gyrobench.scenarios
    The papers' experiments, the ``gyrobench`` command line, reports and the bench.

The names a user reaches for first are importable from here and load on first use, so
``import gyrobench`` stays cheap::

    import numpy as np
    import gyrobench

    model = gyrobench.NoiseModel.from_datasheet(angle_random_walk=0.01)
    rate = model.generate(100_000, fs=100.0, rng=np.random.default_rng(1))
    fit = gyrobench.fit_noise(gyrobench.allan_deviation(rate, fs=100.0))
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from gyrobench.base.lazy import attach

__version__ = "0.6.1"

#: public name -> module that defines it (imported on first access)
_LAZY: dict[str, str] = {
    "NoiseModel": "gyrobench.sim.noise",
    "Recording": "gyrobench.io.recording",
    "load_hdf5": "gyrobench.io.recording",
    "save_hdf5": "gyrobench.io.recording",
    "allan_deviation": "gyrobench.analysis.allan",
    "fit_noise": "gyrobench.analysis.allan",
    "run_campaign": "gyrobench.scenarios.bench",
    "format_summary": "gyrobench.scenarios.bench",
}

__all__ = ["__version__", *_LAZY]

if TYPE_CHECKING:  # pragma: no cover - for type checkers and IDEs only
    from gyrobench.analysis.allan import allan_deviation as allan_deviation
    from gyrobench.analysis.allan import fit_noise as fit_noise
    from gyrobench.io.recording import Recording as Recording
    from gyrobench.io.recording import load_hdf5 as load_hdf5
    from gyrobench.io.recording import save_hdf5 as save_hdf5
    from gyrobench.scenarios.bench import format_summary as format_summary
    from gyrobench.scenarios.bench import run_campaign as run_campaign
    from gyrobench.sim.noise import NoiseModel as NoiseModel


__getattr__, __dir__ = attach(__name__, _LAZY)
