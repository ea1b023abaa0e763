"""Tests of sim/imu.py: a triad of parts on a block, its truth, its fit and its alignment."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import norm

from gyrobench.analysis.allan import fit_noise
from gyrobench.sim import parts
from gyrobench.sim.earth import Site
from gyrobench.sim.imu import AccelerometerSpec, TriadSpec, sensitivity_matrix
from gyrobench.sim.trajectory import Segment, SegmentedMotion

PART = parts.get("adxrs646")
ACCEL = AccelerometerSpec.from_datasheet(vrw_m_s_sqrt_h=0.05, bias_instability_ug=20.0, bias_repeatability_mg=2.0,
                                         scale_factor_repeatability_ppm=300.0, range_g=16.0, resolution_mg=0.01)
#: 1 % family-wise over the 6 (axis, term) checks of the static fit, two-sided
Z = float(norm.ppf(1 - 0.01 / (2 * 6)))
MISFIT_P = 1e-4


def _triad(**kw) -> TriadSpec:
    return TriadSpec(gyros=(PART, PART, PART), accelerometer=ACCEL, **kw)


def test_every_channel_closes_on_its_truth():
    unit = _triad(misalignment=1e-3, cross_axis=5e-4, gg_sensitivity=[1e-6, 0, 0]).realize(rng=np.random.default_rng(1))
    motion = SegmentedMotion((Segment(duration=3.0), Segment(duration=4.0, rate=[0.2, -0.1, 0.5])))
    rec = unit.simulate(motion, fs=100.0, rng=np.random.default_rng(2), site=Site(latitude=0.7)).recording
    assert sorted(rec.channels) == ["accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z"]
    for ch, comps in rec.metadata["error_components"].items():
        out, true = rec[ch], rec[f"truth/{ch}.true"]
        terms = [rec[f"truth/{c}"] for c in comps]
        scale = max(np.max(np.abs(x)) for x in (out, true, *terms))
        resid = out - true - np.sum(terms, axis=0)
        assert np.max(np.abs(resid)) <= 16 * (len(terms) + 2) * np.finfo(float).eps * scale, ch
        assert np.max(np.abs(np.sum(terms, axis=0))) > 0  # the errors are there


def test_a_seed_gives_the_same_bits():
    spec = _triad(misalignment=1e-3)
    motion = SegmentedMotion((Segment(duration=2.0, rate=[0, 0, 0.3]),))
    a, b = (spec.realize(rng=np.random.default_rng(5)).simulate(motion, fs=50.0, rng=np.random.default_rng(6))
            for _ in range(2))
    for ch in a.recording.channels:
        np.testing.assert_array_equal(a.recording[ch], b.recording[ch])


def test_increments_are_the_rates_times_the_interval():
    spec = _triad()
    motion = SegmentedMotion((Segment(duration=2.0, rate=[0, 0, 0.3]),))
    r = spec.realize(rng=np.random.default_rng(5)).simulate(motion, fs=50.0, rng=np.random.default_rng(6))
    d = spec.realize(rng=np.random.default_rng(5)).simulate(motion, fs=50.0, rng=np.random.default_rng(6),
                                                            as_increments=True)
    np.testing.assert_array_equal(d.recording["dtheta_z"], r.recording["gyro_z"] / 50.0)
    assert d.recording.channels["dv_x"].unit == "m/s"


@pytest.mark.slow
def test_a_static_triad_fit_recovers_each_axis_n_and_b():
    """300 crossover times of the part (N/(0.664 B))^2 = 9 s at 20 Hz; the block's Earth rate and
    gravity are constants the fit's bias absorbs."""
    n_true, b_true = PART.datasheet.angle_random_walk(), PART.datasheet.bias_instability()
    dur = 300 * (n_true / (parts.ADEV_MIN_PER_B * b_true)) ** 2
    fs = 20.0
    unit = _triad(misalignment=1e-3).realize(rng=np.random.default_rng(20261201))
    rec = unit.simulate(SegmentedMotion((Segment(duration=dur),)), fs=fs, rng=np.random.default_rng(7),
                        site=Site(latitude=0.5)).recording
    for axis in "xyz":
        fit = fit_noise(rec[f"gyro_{axis}"], fs, terms=("Q", "N", "B", "K"), misfit_p=MISFIT_P)
        assert not fit.misfit
        for key, truth in (("N", n_true), ("B", b_true)):
            c = fit.coefficients[key]
            se = (c.ci95[1] - c.ci95[0]) / (2 * 1.96)
            assert c.value is not None and abs(c.value - truth) <= Z * se, (axis, key, c.value, truth, se)


def test_the_misalignment_is_recovered_from_a_rate_table_run():
    """Six dwells (+-200 deg/s about each body axis, 20 s each at 100 Hz) and a least-squares fit
    y = M omega + b per axis give M's off-diagonal elements back; each element's standard error is
    sigma / (W sqrt(2 n_dwell)) with sigma = N sqrt(fs) the per-sample noise, W the dwell rate and
    n_dwell its samples; checked at 5 sigma (false alarm 6e-7 per element, 3.4e-6 over the six)."""
    w = math.radians(200.0)
    dwell, fs = 20.0, 100.0
    segs = tuple(Segment(duration=dwell, rate=s * w * np.eye(3)[i]) for i in range(3) for s in (1, -1))
    unit = _triad(misalignment=2e-3, cross_axis=1e-3).realize(rng=np.random.default_rng(11))
    out = unit.simulate(SegmentedMotion(segs), fs=fs, rng=np.random.default_rng(12), site=Site(earth_rotation=False))
    rec = out.recording
    w_true = out.ideal.rate
    design = np.column_stack([w_true, np.ones(len(w_true))])
    sigma = PART.datasheet.angle_random_walk() * math.sqrt(fs)
    se = sigma / (w * math.sqrt(2 * dwell * fs))
    for i, axis in enumerate("xyz"):
        coef, *_ = np.linalg.lstsq(design, rec[f"gyro_{axis}"], rcond=None)
        for j in range(3):
            if i != j:
                assert abs(coef[j] - unit.gyro_matrix[i, j]) <= 5 * se, (axis, j, coef[j], unit.gyro_matrix[i, j], se)


def test_the_drawn_matrix_has_the_stated_spread():
    """Over 2000 draws each off-diagonal element's variance is m^2 + c^2, within the chi-square
    bounds of 2000 x 6 samples at a 1e-6 false-alarm rate."""
    from scipy.stats import chi2

    rng = np.random.default_rng(3)
    m, c = 2e-3, 1e-3
    e = np.array([sensitivity_matrix(misalignment=m, cross_axis=c, rng=rng) for _ in range(2000)])
    off = e[:, ~np.eye(3, dtype=bool)].ravel()
    k = off.size
    lo, hi = chi2.ppf(5e-7, k) / k, chi2.ppf(1 - 5e-7, k) / k
    assert lo <= np.mean(off**2) / (m * m + c * c) <= hi
    np.testing.assert_array_equal(e[:, np.eye(3, dtype=bool)], 1.0)


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"misalignment": 0.5}, r"^TriadSpec.misalignment must be \[0, 0.1\] rad; got 0.5$"),
        ({"gyro_matrix": np.eye(2)}, r"^TriadSpec.gyro_matrix must be a finite array of shape \(3, 3\) \[1\] or None; "
         r"got an array of shape \(2, 2\)$"),
        ({"gg_sensitivity": [1, 2]}, r"^TriadSpec.gg_sensitivity must be a finite array of shape \(3,\) "
         r"\[rad/s per \(m/s\^2\)\^2\] or None; got an array of shape \(2,\)$"),
    ],
)
def test_bad_triad_fields_are_refused(kw, match):
    with pytest.raises(ValueError, match=match):
        _triad(**kw)


def test_bad_accelerometer_fields_are_refused():
    with pytest.raises(ValueError, match=r"AccelerometerSpec.range must be > 0 m/s\^2"):
        AccelerometerSpec(range=0.0)
    with pytest.raises(ValueError, match=r"AccelerometerSpec.velocity_random_walk"):
        AccelerometerSpec(velocity_random_walk=-1.0)


def test_the_accelerometer_bandwidth_filters_white_noise_as_its_closed_form():
    """White noise through y_k = a y_{k-1} + (1 - a) x_k has variance (1 - a)/(1 + a) of its input's.
    The variance estimate of an AR(1) record of n samples has n (1 - a^2)/(1 + a^2) = n/6.4 degrees
    of freedom at a = 0.855; the chi-square bounds are taken at n/7 (wider), 1e-6 false-alarm rate."""
    from scipy.stats import chi2

    fs, fc = 1000.0, 25.0
    spec = AccelerometerSpec(bandwidth=fc)
    x = np.random.default_rng(4).standard_normal(200_000)
    y = spec.low_pass(x, fs)
    a = math.exp(-2 * math.pi * fc / fs)
    k = len(x) / 7
    lo, hi = chi2.ppf(5e-7, k) / k, chi2.ppf(1 - 5e-7, k) / k
    assert lo <= np.var(y) / ((1 - a) / (1 + a)) <= hi
    step = spec.low_pass(np.r_[np.zeros(10), np.ones(200)], fs)
    np.testing.assert_allclose(step[10 + 40 - 1], 1 - a**40, rtol=1e-12)  # the step response 1 - a^k
