"""The shared analysis (analysis.record) on synthetic analogues of real-record classes with known truth.

Tolerances: the truth must lie inside the reported 95 % interval. With independent seeds that
fails 5 % of the time per coefficient for an honest interval, so each test uses one fixed seed
and checks the interval, not a tighter band; the seeds were not chosen (seed 1 for each class).
"""

from __future__ import annotations

import numpy as np
import pytest

from gyrobench.analysis.record import analyse_record
from tests.analysis.record_classes import hvac_record, motion_record, phone_record


@pytest.fixture(scope="module")
def phone():
    y, fs, truth = phone_record(np.random.default_rng(1))
    return y, fs, truth, analyse_record(y, fs)


def test_phone_record_gives_n_and_b_with_intervals_by_default(phone):
    """6 h at 10 Hz, filtfilt-decimated, 0.5 % of 0.8 s windows bumped: flagged non-stationary, its quiet
    stretches are fitted, and N and B are identified with 95 % intervals holding the truth."""
    y, fs, truth, ra = phone
    assert ra.nonstationary and ra.basis == "quiet stretches"
    for name in ("N", "B"):
        c = ra.fit.coefficients[name]
        assert c.identifiable, (name, c)
        assert c.ci95[0] <= truth[name] <= c.ci95[1], (name, c.ci95, truth[name])
    q = ra.quiet
    # the left-out samples are the flagged windows (about the bumped share) and they are stated
    assert 0.5 * truth["bumps"] * 8 <= q.n_excluded <= 3 * truth["bumps"] * 8 + 8
    assert "left out" in q.describe(fs)
    # pooled per tau over every stretch long enough, not capped at the shortest: taus beyond the
    # shortest stretch's reach are present
    shortest = min(b - a for a, b in q.stretches) / fs
    assert q.curve.tau[-1] > 4 * shortest
    assert q.spread.n_stretches[0] == len(q.stretches)


def test_phone_record_filter_is_identified_as_a_model_term(phone):
    """The Butterworth order 4 at 2 Hz applied forward and backward is found as the low-pass term."""
    _, _, truth, ra = phone
    lp = ra.model.term("lowpass")
    assert lp is not None
    assert int(lp.params["passes"]) == 2 and int(lp.params["order"]) == int(truth["order"])
    assert 0.8 * truth["corner_hz"] <= lp.params["corner"] <= 1.25 * truth["corner_hz"]


def test_hvac_sine_is_reported():
    """1 h at 100 Hz, N 0.3, B 3, K 3 plus a 20 deg/h sine of period 1200 s: the sinusoid term is chosen
    (the five terms alone pass the misfit test), with its period within a factor 1.5."""
    y, fs, truth = hvac_record(np.random.default_rng(1))
    ra = analyse_record(y, fs)
    s = ra.model.term("sinusoid")
    assert s is not None, ra.model.drops
    assert truth["sine_period"] / 1.5 <= s.params["period"] <= 1.5 * truth["sine_period"]
    assert truth["sine_amplitude"] / 2 <= s.params["amplitude"] <= 2 * truth["sine_amplitude"]


def test_sine_free_record_gets_no_extra_term():
    y, fs, _ = hvac_record(np.random.default_rng(1), sine_dph=0.0)
    ra = analyse_record(y, fs)
    assert not [t for t in ra.model.extra if t.kind != "lowpass"], ra.model.extra


def test_motion_record_is_analysed_from_its_quiet_stretches():
    """A tenth of the record moves: the verdict is non-stationary, the motion is left out and N is recovered."""
    y, fs, truth = motion_record(np.random.default_rng(2))
    ra = analyse_record(y, fs)
    assert ra.nonstationary and ra.basis == "quiet stretches"
    a, b = truth["motion"]
    left = [(s / fs, e / fs) for s, e in ra.quiet.excluded]
    assert any(s <= a + 60 and e >= a for s, e in left)  # the motion's start is left out
    c = ra.fit.coefficients["N"]
    assert c.identifiable and c.ci95[0] <= truth["N"] <= c.ci95[1]


def test_the_old_whole_record_fit_stays_available():
    y, fs, _ = motion_record(np.random.default_rng(2))
    ra = analyse_record(y, fs, quiet=False)
    assert ra.nonstationary and ra.basis == "whole record (motion kept)" and ra.quiet is None
