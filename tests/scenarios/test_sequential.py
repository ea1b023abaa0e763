"""``--units auto``'s group-sequential verdict: at a true pass rate of 50 % a claim is decided at some
look with probability at most the nominal 5 % (exact computation and simulation), while 1.96 at every
look is not."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import binom

from gyrobench.scenarios.claims import sequential_error, sequential_z, verdict
from gyrobench.scenarios.runner.units import auto_looks

LOOKS = auto_looks(20, 60)  # the default --units auto schedule: 20, 30, 40, 50, 60
ALPHA = 1e-3  # false-alarm rate of the simulation checks
N_SIM = 4000


def _simulated_error(z: float, p: float = 0.5, seed: int = 20261201) -> int:
    """Replications (of N_SIM) in which the claim is decided at some look, each unit passing with p."""
    rng = np.random.default_rng(seed)
    passes = rng.random((N_SIM, LOOKS[-1])) < p
    cum = np.cumsum(passes, axis=1)
    decided = np.zeros(N_SIM, dtype=bool)
    for n in LOOKS:
        k = cum[:, n - 1]
        decided |= np.array([verdict(int(x), n, z) != "undecided" for x in k])
    return int(decided.sum())


def test_the_schedule_is_the_cli_default():
    from gyrobench.scenarios.cli.reproduce import AUTO_START_UNITS, MAX_UNITS

    assert auto_looks(AUTO_START_UNITS, MAX_UNITS) == LOOKS == (20, 30, 40, 50, 60)


def test_the_sequential_z_keeps_the_exact_error_at_or_below_nominal():
    z = sequential_z(LOOKS)
    assert sequential_error(LOOKS, z) <= 0.05 < sequential_error(LOOKS, z - 2e-4)
    assert sequential_error(LOOKS, 1.959963984540054) > 0.10  # uncorrected looks: 12 %


def test_simulated_error_rate_at_a_true_50_percent_is_nominal():
    z = sequential_z(LOOKS)
    k = _simulated_error(z)
    # the exact crossing probability is what the simulation measures (two-sided binomial band at ALPHA)
    p = sequential_error(LOOKS, z)
    assert binom.ppf(ALPHA / 2, N_SIM, p) <= k <= binom.isf(ALPHA / 2, N_SIM, p)
    assert k <= binom.isf(ALPHA, N_SIM, 0.05)  # at or below the nominal 5 %


def test_uncorrected_looks_inflate_the_error():
    """The check above can fail: judging every look at 1.96 decides far more than 5 % of the claims."""
    assert _simulated_error(1.959963984540054) > binom.isf(ALPHA, N_SIM, 0.05)


def test_a_real_effect_is_still_decided():
    """Power: at a true pass rate of 80 % the corrected procedure decides almost every claim by 60 units."""
    z = sequential_z(LOOKS)
    assert _simulated_error(z, p=0.8) > 0.99 * N_SIM


def test_sequential_z_rejects_bad_looks():
    with pytest.raises(ValueError, match="looks must be increasing"):
        sequential_z((30, 20))
