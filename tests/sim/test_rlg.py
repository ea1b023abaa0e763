"""Tests of sim/rlg.py: geometry, Adler lock-in, dither random walk, pulse counting, thermal model."""

from __future__ import annotations

import math
import zlib
from dataclasses import replace

import allantools
import numpy as np
import pytest
from scipy import stats

from gyrobench.base import units
from gyrobench.sim import rlg
from gyrobench.sim.environment import Ramp, Soak, thermal_profile
from gyrobench.sim.sensor import Environment

LAMBDA = rlg.HENE_WAVELENGTH


@pytest.fixture
def rng(request) -> np.random.Generator:
    """The same stream on every run, a different one for every test."""
    key = zlib.crc32(request.node.nodeid.encode())
    return np.random.default_rng([20261121, key])


def _quiet_unit(**kw) -> rlg.RLGUnit:
    """A unit with no thermal bias, no flicker: only lock-in/dither random walk and counting."""
    base = dict(
        geometry=rlg.CavityGeometry.triangle(0.14),
        lock_in_rate=units.deg_per_s(0.05),
        dither=rlg.Dither(frequency=400.0, amplitude=units.arcsec(150.0), amplitude_jitter=0.1),
    )
    base.update(kw)
    return rlg.RLGUnit(**base)


# ------------------------------------------------------------------ geometry (closed form)
@pytest.mark.parametrize("side", [0.05, 0.10, 0.14, 0.2])
def test_triangle_scale_factor_closed_form(side):
    g = rlg.CavityGeometry.triangle(side)
    assert g.scale_factor == pytest.approx(side / (math.sqrt(3.0) * LAMBDA), rel=1e-12)
    assert g.pulse_weight == pytest.approx(math.sqrt(3.0) * LAMBDA / side, rel=1e-12)
    assert g.quantization == pytest.approx(g.pulse_weight / math.sqrt(12.0), rel=1e-12)
    assert g.perimeter == pytest.approx(3 * side, rel=1e-12)
    assert g.area == pytest.approx(math.sqrt(3.0) / 4 * side**2, rel=1e-12)


@pytest.mark.parametrize("side", [0.05, 0.10, 0.2])
def test_square_scale_factor_closed_form(side):
    g = rlg.CavityGeometry.square(side)
    assert g.scale_factor == pytest.approx(side / LAMBDA, rel=1e-12)


def test_reference_values_physics_md():
    """docs/physics.md 6.1: triangle 0.10 m -> 91 237 counts/rad, 2.26 arcsec; 0.14 m -> 1.62 arcsec;
    square 0.10 m -> 1.31."""
    assert round(rlg.CavityGeometry.triangle(0.10).scale_factor) == 91237
    assert round(units.to_arcsec(rlg.CavityGeometry.triangle(0.10).pulse_weight), 2) == 2.26
    assert round(units.to_arcsec(rlg.CavityGeometry.triangle(0.10).quantization), 2) == 0.65
    assert (
        round(units.to_arcsec(rlg.CavityGeometry.triangle(0.14).pulse_weight), 2) == 1.61
    )  # 1.615 -> text "1.62"
    assert round(units.to_arcsec(rlg.CavityGeometry.square(0.10).pulse_weight), 2) == 1.31


def test_polygon_area_is_orientation_independent():
    v = ((0.0, 0.0), (0.1, 0.0), (0.1, 0.1), (0.0, 0.1))
    a = rlg.CavityGeometry(vertices=v)
    b = rlg.CavityGeometry(vertices=tuple(reversed(v)))
    assert a.area == b.area == pytest.approx(0.01, rel=1e-12)


def test_bad_geometry_zero_side():
    with pytest.raises(ValueError, match=r"area must be > 0 m\^2.*side must be > 0 m; got 0"):
        rlg.CavityGeometry.triangle(0.0)


def test_bad_geometry_negative_side():
    with pytest.raises(ValueError, match=r"area must be > 0 m\^2.*got -0.1"):
        rlg.CavityGeometry.square(-0.1)


def test_bad_geometry_collinear_mirrors():
    with pytest.raises(ValueError, match=r"area must be > 0 m\^2"):
        rlg.CavityGeometry(vertices=((0.0, 0.0), (0.1, 0.0), (0.2, 0.0)))


def test_bad_geometry_too_few_vertices():
    with pytest.raises(ValueError, match=r">= 3 \(x, y\) pairs"):
        rlg.CavityGeometry(vertices=((0.0, 0.0), (0.1, 0.0)))


# ------------------------------------------------------------------ lock-in (Adler)
K_TEST = 1e5  # counts/rad
WL_TEST = units.deg_per_s(0.05)


def test_below_lock_in_no_pulses(rng):
    """|Omega| < Omega_L, no dither: psi settles at arcsin(Omega/Omega_L); no pulse after settling."""
    omega = np.array([0.0, 0.3, -0.6, 0.9]) * WL_TEST
    psi0 = rng.uniform(0, 2 * math.pi, (16, 4))
    dt = 2e-5
    psi = rlg.integrate_adler(
        lambda t: omega,
        0.2,
        scale_factor=K_TEST,
        lock_in_rate=WL_TEST,
        dt=dt,
        psi0=psi0,
        sample_every=100,
    )
    counts = rlg.count_pulses(psi)
    # from any start the phase reaches the stable point without a full slip: at most one counter step
    assert np.all(np.abs(counts.sum(axis=0)) <= 1)
    # after 0.1 s (>= 40 locking time constants 1/(2 pi K sqrt(Omega_L^2 - Omega^2))) nothing is counted
    assert np.all(counts[len(counts) // 2 :] == 0)
    settled = np.mod(psi[-1], 2 * math.pi)
    target = np.mod(np.arcsin(omega / WL_TEST), 2 * math.pi)
    d = np.angle(np.exp(1j * (settled - target)))
    assert np.max(np.abs(d)) < 1e-9


@pytest.mark.parametrize("ratio", [1.1, 2.0, 5.0, -3.0])
def test_above_lock_in_beat_period_closed_form(ratio):
    """The Adler phase is periodic: psi(t + T_b) = psi(t) + 2 pi, T_b = 1/(K sqrt(Omega^2 - Omega_L^2))."""
    omega = ratio * WL_TEST
    f_b = float(rlg.beat_frequency(omega, scale_factor=K_TEST, lock_in_rate=WL_TEST))
    assert f_b == pytest.approx(
        math.copysign(K_TEST * WL_TEST * math.sqrt(ratio**2 - 1), ratio), rel=1e-12
    )
    m = 5
    period = 1.0 / abs(f_b)
    n_per = 4000
    psi = rlg.integrate_adler(
        lambda t: omega,
        m * period,
        scale_factor=K_TEST,
        lock_in_rate=WL_TEST,
        dt=period / n_per,
        psi0=0.3,
        sample_every=n_per,
    )
    # RK4, 4000 steps per slip: global phase error << 1e-8 rad per cycle
    np.testing.assert_allclose(
        psi - 0.3, math.copysign(2 * math.pi, ratio) * np.arange(m + 1), rtol=0, atol=1e-8
    )
    assert rlg.count_pulses(psi[[0, -1]])[0] == math.copysign(m, ratio)


def test_beat_frequency_zero_inside_lock_in():
    w = np.array([-1.0, -0.5, 0.0, 0.5, 1.0]) * WL_TEST
    assert np.all(rlg.beat_frequency(w, scale_factor=K_TEST, lock_in_rate=WL_TEST) == 0.0)


def test_unit_adler_counts_track_input_above_lock_in():
    """The unit's Adler mode counts K sqrt(Omega^2 - Omega_L^2) per second (+-1 count of phase)."""
    u = _quiet_unit()
    omega = 4.0 * u.lock_in_rate
    c = u.adler_counts(lambda t: omega, 0.02, fs=1000.0, dt=1e-6)
    expected = u.scale_factor * math.sqrt(omega**2 - u.lock_in_rate**2) * 0.02
    assert abs(c.sum() - expected) <= 1.0


# ------------------------------------------------------------------ dither random walk: Adler vs statistical mode
def _adler_vs_statistical(rng, *, k, lock_in, dither, n_cyc, r):
    """Integrate R realizations over n_cyc whole dither cycles; check the angle-error variance.

    The angle error after whole cycles has variance T N^2 (statistical mode); its sample
    variance over R realizations is chi-square(R - 1) distributed (a sum of 2 n_cyc
    independent kicks is close to Gaussian). Two-sided bounds at a false-alarm rate of 1e-3.
    """
    real = dither.draw(n_cyc, rng=rng, size=r)
    psi0 = rng.uniform(0.0, 2 * math.pi, r)
    duration = n_cyc / dither.frequency
    n = int(
        math.ceil(duration * 16 * 1.3 * k * dither.peak_rate)
    )  # >= 16 steps per fastest beat cycle
    psi = rlg.integrate_adler(
        real.rate,
        duration,
        scale_factor=k,
        lock_in_rate=lock_in,
        dt=duration / n,
        psi0=psi0,
        sample_every=n,
    )
    err = (psi[-1] - psi[0]) / (2 * math.pi * k)  # true angle change over whole cycles is 0
    s2 = err.var(ddof=1)
    lo, hi = stats.chi2.ppf([0.0005, 0.9995], r - 1) / (r - 1)
    # against the per-crossing stationary-phase sum for the drawn amplitudes
    expected = float(
        np.mean(
            real.expected_angle_variance(
                scale_factor=k, lock_in_rate=lock_in, n_crossings=2 * n_cyc
            )
        )
    )
    assert lo <= s2 / expected <= hi, (s2 / expected, lo, hi)
    # against the ARW the statistical mode uses
    n_stat = rlg.dither_arw(scale_factor=k, lock_in_rate=lock_in, dither=dither)
    assert lo <= s2 / (n_stat**2 * duration) <= hi, (s2 / (n_stat**2 * duration), lo, hi)
    # zero mean: |mean| / (s/sqrt(R)) below the 1e-3 two-sided normal quantile
    assert abs(err.mean()) / math.sqrt(s2 / r) < stats.norm.ppf(1 - 0.0005)


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_dither_random_walk_matches_statistical_mode(rng):
    """Adler integration with randomized dither vs N = Omega_L/sqrt(2 pi K Omega_D).

    K = 1e5, dither 400 Hz x 20 counts (+-10 %), Omega_L 0.05 deg/s: phase kick per
    crossing 0.03 rad (small-kick regime of the formula); 1000 realizations x 10 cycles.
    """
    dither = rlg.Dither(frequency=400.0, amplitude=20.0 / K_TEST, amplitude_jitter=0.1)
    _adler_vs_statistical(rng, k=K_TEST, lock_in=WL_TEST, dither=dither, n_cyc=10, r=1000)


@pytest.mark.slow
def test_dither_random_walk_matches_statistical_mode_production_unit(rng):
    """The same check at the scenario's nominal unit: triangle 0.14 m, 400 Hz x 150 arcsec, 0.05 deg/s."""
    u = rlg.RLGSpec().nominal()
    _adler_vs_statistical(
        rng, k=u.scale_factor, lock_in=u.lock_in_rate, dither=u.dither, n_cyc=8, r=1000
    )


def test_statistical_mode_arw_value_physics_md():
    """docs/physics.md 6.3 example: Omega_L 0.05 deg/s, K 1e5, Omega_D 100 deg/s -> 0.0029 deg/sqrt(h)."""
    d = rlg.Dither(
        frequency=400.0,
        amplitude=units.deg_per_s(100.0) / (2 * math.pi * 400.0),
        amplitude_jitter=0.0,
    )
    n = rlg.dither_arw(scale_factor=1e5, lock_in_rate=units.deg_per_s(0.05), dither=d)
    assert round(units.to_deg_per_sqrt_h(n), 4) == 0.0029


# ------------------------------------------------------------------ pulse counting (statistical mode)
def _run_quiet(u, rng, duration, fs):
    prof = thermal_profile(units.celsius(20.0), [Soak(duration=duration)])
    return u.simulate(Environment(duration, temperature=prof), fs=fs, rng=rng)


def test_counted_angle_within_one_pulse_of_true_angle(rng):
    """Closed form: sum(output)/fs = true angle - (e_k - e_0) with 0 <= e < q, so |difference| < q."""
    u = _quiet_unit(bias_instability=units.deg_per_h(0.01))
    rec = _run_quiet(u, rng, 200.0, 50.0)
    true_increment = sum(
        rec[f"truth/{k}"]
        for k in ("true_rate", "turn_on_bias", "thermal_bias", "flicker_rrw", "dither_random_walk")
    )
    diff = np.cumsum(rec["output"] - true_increment) / rec.fs
    assert np.max(np.abs(diff)) < u.pulse_weight
    np.testing.assert_array_equal(rec["counts"], np.round(rec["counts"]))
    np.testing.assert_allclose(
        rec["output"] - true_increment, rec["truth/quantization"], rtol=0, atol=1e-12
    )


def test_quantization_slope_with_dither(rng):
    """With dither, short-tau AVAR = 3 Q^2/tau^2 + N^2/tau, Q = pulse weight/sqrt(12).

    Overlapping ADEV (allantools.oadev) at tau = 1, 2, 4, 10 samples of a 100 Hz record;
    bounds from chi-square with Greenhall's equivalent degrees of freedom for white
    phase noise (alpha = 2), false-alarm rate 1e-6 per tau.
    """
    u = _quiet_unit()
    fs = 100.0
    rec = _run_quiet(u, rng, 1500.0, fs)
    y = rec["output"]
    m = np.array([1, 2, 4, 10])
    taus, dev, _, _ = allantools.oadev(y, rate=fs, data_type="freq", taus=m / fs)
    q, n = u.geometry.quantization, u.angle_random_walk
    theory = 3 * q**2 / taus**2 + n**2 / taus
    for mi, t, d, th in zip(m, taus, dev, theory, strict=True):
        edf = allantools.edf_greenhall(
            alpha=2, d=2, m=int(mi), N=len(y) + 1, overlapping=True, modified=False
        )
        lo, hi = stats.chi2.ppf([5e-7, 1 - 5e-7], edf) / edf
        assert lo <= d**2 / th <= hi, (t, d**2 / th, lo, hi)


def test_no_dither_randomization_breaks_white_quantization_assumption_is_rejected():
    """A dither smaller than 10 pulse weights cannot randomize the count: rejected."""
    with pytest.raises(ValueError, match="dither amplitude must be >= 10 pulse weights"):
        _quiet_unit(
            lock_in_rate=0.0,
            dither=rlg.Dither(frequency=400.0, amplitude=units.arcsec(5.0), amplitude_jitter=0.1),
        )


def test_bad_dither_below_lock_in_needs():
    """Peak dither rate below 10 x lock-in rate: the gyro would spend the cycle locked."""
    with pytest.raises(
        ValueError, match=r"dither amplitude too small for lock-in.*>= 10 x lock-in rate"
    ):
        _quiet_unit(
            dither=rlg.Dither(frequency=400.0, amplitude=units.arcsec(30.0), amplitude_jitter=0.1),
            lock_in_rate=units.deg_per_s(3.0),
        )


def test_bad_sample_rate_above_dither_quarter(rng):
    with pytest.raises(ValueError, match=r"fs must be <= dither frequency / 4 = 100.0 Hz"):
        _run_quiet(_quiet_unit(), rng, 10.0, 200.0)


def test_rng_must_be_generator():
    with pytest.raises(TypeError, match="rng must be a numpy.random.Generator"):
        _quiet_unit().simulate(Environment(10.0, temperature=293.0), fs=10.0, rng=1)


# ------------------------------------------------------------------ thermal model (closed form)
def test_two_node_ramp_closed_form():
    """Ramp r from a soaked start, no self-heating: exact cascade solution.

    T1 = Tc - r tau1 (1 - e^{-t/tau1});
    T2 = Tc - r (tau1 + tau2) + r (tau1^2 e^{-t/tau1} - tau2^2 e^{-t/tau2}) / (tau1 - tau2).
    Housing node: FOH is exact (to rounding). Cavity node: T1 is taken linear within a
    sample, error <= h^2 max|T1''|/8 = h^2 r/(8 tau1) (unit-gain filter).
    """
    th = rlg.TwoNodeThermal(
        tau_housing=600.0, tau_cavity=900.0, heating_housing=0.0, heating_cavity=0.0
    )
    fs, r = 2.0, 1.0 / 180.0
    t = np.arange(int(4 * 3600 * fs)) / fs
    tc = r * t
    t1, t2 = rlg.two_node_temperatures(tc, fs, th)
    a, b = th.tau_housing, th.tau_cavity
    t1_exact = tc - r * a * (1 - np.exp(-t / a))
    t2_exact = tc - r * (a + b) + r * (a**2 * np.exp(-t / a) - b**2 * np.exp(-t / b)) / (a - b)
    np.testing.assert_allclose(t1, t1_exact, rtol=0, atol=1e-10)
    h = 1 / fs
    assert np.max(np.abs(t2 - t2_exact)) <= h**2 * r / (8 * a) + 1e-10


def test_two_node_self_heating_closed_form():
    """Constant chamber, powered at t = 0: T1 = Tc + H1 (1 - e^{-t/tau1}), exact; T2 -> Tc + H1 + H2."""
    th = rlg.TwoNodeThermal(
        tau_housing=500.0, tau_cavity=700.0, heating_housing=3.0, heating_cavity=1.2
    )
    fs = 1.0
    t = np.arange(40000) / fs
    tc = np.full_like(t, 250.0)
    t1, t2 = rlg.two_node_temperatures(tc, fs, th)
    np.testing.assert_allclose(t1, 250.0 + 3.0 * (1 - np.exp(-t / 500.0)), rtol=0, atol=1e-10)
    assert t2[-1] == pytest.approx(250.0 + 4.2, abs=1e-9)


def test_thermal_bias_equation():
    tb = rlg.ThermalBias(
        cavity=1.0,
        cavity_quadratic=0.1,
        gradient=2.0,
        flux=3.0,
        flux_quadratic=4.0,
        gas_temperature_coefficient=0.01,
        reference_temperature=300.0,
    )
    t1, t2, d1 = np.array([310.0]), np.array([305.0]), np.array([0.5])
    gas = 1 + 0.01 * 5.0
    expected = 1.0 * 5 + 0.1 * 25 + gas * (2.0 * 5 + 3.0 * 0.5) + 4.0 * 0.25
    assert float(tb(t1, t2, d1)[0]) == pytest.approx(expected, rel=1e-12)


# ------------------------------------------------------------------ sensors
def test_sensor_resolution_and_noise(rng):
    s = rlg.TemperatureSensor(offset=0.3, noise=0.05, resolution=0.01)
    y = s.measure(np.full(20000, 300.0), rng=rng)
    np.testing.assert_allclose(y / 0.01, np.round(y / 0.01), rtol=0, atol=1e-6)
    # mean: offset; variance: noise^2 + resolution^2/12 (Sheppard), chi-square bound at 1e-6
    n = len(y)
    var_true = 0.05**2 + 0.01**2 / 12
    lo, hi = stats.chi2.ppf([5e-7, 1 - 5e-7], n - 1) / (n - 1)
    assert lo <= y.var(ddof=1) / var_true <= hi
    assert abs(y.mean() - 300.3) < stats.norm.ppf(1 - 5e-7) * math.sqrt(var_true / n)


# ------------------------------------------------------------------ unit-to-unit variation
def test_realize_is_reproducible_and_units_differ():
    spec = rlg.RLGSpec(thermal_bias=rlg.THERMAL_BIAS_CALIBRATED)
    a = spec.realize(rng=np.random.default_rng(7))
    b = spec.realize(rng=np.random.default_rng(7))
    c = spec.realize(rng=np.random.default_rng(8))
    assert a == b
    assert (
        a.lock_in_rate != c.lock_in_rate
        and a.thermal_bias != c.thermal_bias
        and a.thermal != c.thermal
    )


def test_realize_without_spread_gives_nominal():
    spec = rlg.RLGSpec(
        lock_in_spread=0.0,
        bias_spread=0.0,
        thermal_spread=0.0,
        mechanism_spread=0.0,
        sensor_offset_spread=0.0,
    )
    u = spec.realize(rng=np.random.default_rng(1))
    assert u.lock_in_rate == spec.lock_in_rate
    assert u.thermal == spec.thermal
    assert u.thermal_bias == spec.thermal_bias


def test_simulate_reproducible_and_thermal_bias_in_truth(rng):
    spec = rlg.RLGSpec(thermal_bias=rlg.THERMAL_BIAS_CALIBRATED)
    u = spec.realize(rng=np.random.default_rng(3))
    prof = thermal_profile(
        units.celsius(-40.0),
        [Soak(duration=600.0), Ramp(target=units.celsius(-20.0), rate=1 / 180)],
    )
    r1 = u.simulate(Environment(prof.duration, temperature=prof), fs=10.0, rng=np.random.default_rng(5))
    r2 = u.simulate(Environment(prof.duration, temperature=prof), fs=10.0, rng=np.random.default_rng(5))
    np.testing.assert_array_equal(r1["output"], r2["output"])
    mech = sum(
        r1[f"detail/{k}"]
        for k in ("bias_cavity_temperature", "bias_discharge_gradient", "bias_heat_flux")
    )
    np.testing.assert_allclose(mech, r1["truth/thermal_bias"], rtol=1e-12, atol=0)
    assert r1.n_samples == int(prof.duration * 10)


def test_spec_rejects_negative_spread():
    with pytest.raises(ValueError, match=r"RLGSpec.lock_in_spread must be >= 0"):
        replace(rlg.RLGSpec(), lock_in_spread=-0.1)
