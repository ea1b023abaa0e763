"""False-alarm rate of the model-term selection (analysis.model_select) on records that follow the five-term model.

Each seed simulates 2 h at 10 Hz of N 0.3 deg/sqrt(h), B 3 deg/h and K 3 deg/h/sqrt(h) (no
Gauss-Markov process, no sinusoid, no filter) and runs the shared analysis
(:func:`gyrobench.analysis.record.analyse_record`); a false alarm is any Gauss-Markov or
sinusoid term chosen. The nominal bound is that of the Bonferroni rule for the two families,
1 - (1 - LEVEL)^2. Prints the count, the rate and its exact (Clopper-Pearson)
95 % interval.

    python benchmarks/model_select_false_alarm.py [SEEDS]
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np
from scipy.stats import beta

from gyrobench.analysis.model_select import LEVEL
from gyrobench.analysis.record import analyse_record
from gyrobench.base import units
from gyrobench.sim.noise import NoiseModel


def main(seeds: int = 200) -> None:
    dph = units.deg_per_h(1.0)
    model = NoiseModel(angle_random_walk=0.3 * math.radians(1) / 60, bias_instability=3 * dph,
                       rate_random_walk=3 * dph / 60)
    fs, n = 10.0, 72_000
    alarms = 0
    t0 = time.process_time()
    for s in range(seeds):
        y = model.generate(n, fs, rng=np.random.default_rng([46, s]))
        ra = analyse_record(y, fs)
        alarms += any(t.kind in ("gauss_markov", "sinusoid") for t in ra.model.extra)
    lo = beta.ppf(0.025, alarms, seeds - alarms + 1) if alarms else 0.0
    hi = beta.ppf(0.975, alarms + 1, seeds - alarms)
    nominal = 1 - (1 - LEVEL) ** 2
    print(f"{alarms}/{seeds} records got a Gauss-Markov or sinusoid term: rate {alarms / seeds:.3g} "
          f"[{lo:.3g}, {hi:.3g}] (95 %), nominal bound {nominal:.3g}; {time.process_time() - t0:.1f} s CPU")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 200)
