"""Tests of sim/rlg_cavity.py: backscatter lock-in, PLC mode hops, thermal network, Langmuir."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from gyrobench.base import units
from gyrobench.sim import rlg_cavity as rc
from gyrobench.sim.environment import Ramp, Soak, thermal_profile
from gyrobench.sim.rlg import HENE_WAVELENGTH, CavityGeometry
from gyrobench.sim.sensor import Environment

LAM = HENE_WAVELENGTH


# ----------------------------------------------------------------------------- backscatter
def test_lock_in_formula_ten_cm_square():
    """docs/physics.md 6.6: 0.05 deg/s in a 10 cm square needs |r_net| = 1.16e-6."""
    g = CavityGeometry.square(0.10)
    r = units.deg_per_s(0.05) * 8 * math.pi * g.area / (rc.SPEED_OF_LIGHT * LAM)
    assert r == pytest.approx(1.16e-6, rel=5e-3)
    wl = rc.lock_in_from_backscatter(r * np.exp(1j * 0.3), area=g.area, wavelength=LAM)
    assert float(wl) == pytest.approx(units.deg_per_s(0.05), rel=1e-12)


def _bs(walk: float = 0.0) -> rc.Backscatter:
    return rc.Backscatter(
        amplitudes=(1e-6, 2e-6, 0.5e-6),
        phases=(0.1, 2.0, 4.0),
        positions=(0.0, 1 / 3, 2 / 3),
        walk_phase=walk,
        dissipative=1e-4,
        dissipative_phase=0.7,
    )


def test_net_backscatter_phases():
    """At zero strain and PLC, r_net = sum r_i e^{j theta_i} (positions are whole half-waves
    only modulo lambda/2, so compare against the explicit sum)."""
    b, p = _bs(), 0.42
    k = 2 * math.pi / LAM
    expect = sum(
        a * np.exp(1j * (2 * k * s * p + th))
        for a, s, th in zip(b.amplitudes, b.positions, b.phases, strict=True)
    )
    assert complex(b.net(0.0, 0.0, perimeter=p, wavelength=LAM)) == pytest.approx(expect, rel=1e-9)


def test_hop_changes_lock_in_only_through_beam_walk():
    """A PLC step of one wavelength leaves every 2 k s_i unchanged modulo 2 pi (no walk) and
    turns the PLC mirror's phase by gamma (walk)."""
    p = 0.42
    r0 = complex(_bs().net(1e-7, 0.1 * LAM, perimeter=p, wavelength=LAM))
    r1 = complex(_bs().net(1e-7, 1.1 * LAM, perimeter=p, wavelength=LAM))
    assert abs(r1 - r0) < 1e-9 * abs(r0)
    w = _bs(walk=0.8)
    d = complex(w.net(1e-7, 1.1 * LAM, perimeter=p, wavelength=LAM)) - complex(
        w.net(1e-7, 0.1 * LAM, perimeter=p, wavelength=LAM)
    )
    # only mirror 0's term turns: |delta| = 2 r_0 |sin(gamma/2)|
    assert abs(d) == pytest.approx(2 * 1e-6 * abs(math.sin(0.4)), rel=1e-6)


def test_null_shift_form():
    b = _bs()
    r = np.array([1e-6 * np.exp(1j * 2.0)])
    assert b.null_shift(r, np.array([0.01]))[0] == pytest.approx(1e-4 * 0.01 * math.sin(2.0 - 0.7))


# ----------------------------------------------------------------------------- PLC
def test_mode_index_hysteresis_closed_form():
    """Triangle excursion 0 -> 5 lambda -> 0: hops up where x - n lambda = +S/2, down where
    it is -S/2: (S - lambda)/2 of hysteresis on each side."""
    s = 1.5 * LAM
    x = np.concatenate((np.linspace(0, 5, 50001), np.linspace(5, 0, 50001))) * LAM
    n = rc.mode_index(x, wavelength=LAM, travel=s, n0=0)
    assert np.all(np.abs(n * LAM - x) <= s / 2 + 1e-18)
    up = np.flatnonzero(np.diff(n[:50001]) == 1) + 1
    down = np.flatnonzero(np.diff(n[50001:]) == -1) + 50002
    assert len(up) == 5 and len(down) == 5
    step = 5 * LAM / 50000
    np.testing.assert_allclose(x[up] - n[up - 1] * LAM, s / 2, atol=step)
    np.testing.assert_allclose(x[down] - n[down - 1] * LAM, -s / 2, atol=step)
    # hysteresis: up-hops at x = (n + 0.75) lambda, down-hops at (n + 0.25) lambda
    np.testing.assert_allclose(np.sort(x[up]) / LAM, [0.75, 1.75, 2.75, 3.75, 4.75], atol=1e-4)
    np.testing.assert_allclose(np.sort(x[down]) / LAM, [0.25, 1.25, 2.25, 3.25, 4.25], atol=1e-4)


def test_mode_index_refuses_short_travel():
    with pytest.raises(ValueError, match="travel must be > one wavelength"):
        rc.mode_index(np.zeros(3), wavelength=LAM, travel=0.9 * LAM, n0=0)


# ----------------------------------------------------------------------------- thermal
def test_network_steady_state_and_step():
    """Constant chamber: nodes settle at the solution of M T + B u = 0 (energy balance:
    g_air (T_H - T_ch) = P_H + 2 P_leg)."""
    th = rc.CavityThermal(g_mount_a=0.1, g_mount_b=0.2)
    fs, n = 0.1, 100_000  # ~ 11.6 days, >> slowest time constant
    t = th.temperatures(np.full(n, 300.0), fs)
    m, b = th.matrices()
    ss = np.linalg.solve(m, -b @ np.array([300.0, 1.0]))
    np.testing.assert_allclose(t[:, -1], ss, rtol=0, atol=1e-9)
    assert th.g_air * (ss[0] - 300.0) == pytest.approx(th.p_housing + 2 * th.p_leg, rel=1e-9)
    np.testing.assert_allclose(t[:, 0], 300.0)


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_network_matches_fine_euler():
    """Exact FOH recursion vs a fine explicit Euler integration of the same ODE on a ramp."""
    th = rc.CavityThermal(g_mount_a=0.1, g_mount_b=0.25)
    fs = 1.0
    tt = np.arange(7201) / fs
    tc = 250.0 + tt / 180.0
    t = th.temperatures(tc, fs)
    m, b = th.matrices()
    h = 0.01
    x = np.full(3, 250.0)
    for i in range(720_000):
        x = x + h * (m @ x + b @ np.array([250.0 + i * h / 180.0, 1.0]))
    np.testing.assert_allclose(t[:, -1], x, atol=2e-3)


# ----------------------------------------------------------------------------- Langmuir
def test_langmuir_linear_and_odd_in_imbalance():
    d = rc.Discharge(imbalance=0.0)
    tr = d.reference_temperature
    t = np.array([tr - 30.0])  # gas at T_ref
    assert d.bias(t, t, t)[0] == pytest.approx(0.0, abs=1e-30)
    b1 = rc.Discharge(imbalance=1e-6).bias(t, t, t)[0]
    b2 = rc.Discharge(imbalance=2e-6).bias(t, t, t)[0]
    bm = rc.Discharge(imbalance=-1e-6).bias(t, t, t)[0]
    assert b1 == pytest.approx(rc.LANGMUIR_COEFFICIENT * 1e-6, rel=1e-12)
    assert b2 == pytest.approx(2 * b1, rel=1e-12) and bm == pytest.approx(-b1, rel=1e-12)


def test_langmuir_gradient_small_signal():
    """Equal currents, gas legs dT apart: Omega ~ -k I0 m dT / T_ref."""
    d = rc.Discharge()
    tr = d.reference_temperature
    ta, tb = np.array([tr - 30.0 + 0.05]), np.array([tr - 30.0 - 0.05])
    expect = -d.coefficient * d.current * d.viscosity_exponent * 0.1 / tr
    assert d.bias(ta, ta, tb)[0] == pytest.approx(expect, rel=1e-3)


# ----------------------------------------------------------------------------- chamber run
def _cycle_profile():
    return thermal_profile(
        units.celsius(-40.0),
        [
            Soak(duration=1800.0),
            Ramp(target=units.celsius(65.0), rate=1 / 180.0),
            Soak(duration=3600.0),
            Ramp(target=units.celsius(-40.0), rate=1 / 180.0),
            Soak(duration=1800.0),
        ],
    )


def _hop_temperatures(u: rc.CavityRLG, prof, seed: int) -> tuple[np.ndarray, np.ndarray, dict]:
    fs = 1.0
    tt = np.arange(int(prof.duration * fs) + 1) / fs
    nodes = u.thermal.temperatures(prof(tt), fs)
    on = u.turn_on(np.random.default_rng(seed), 0.5 * (nodes[1, 0] + nodes[2, 0]))
    st = u.cavity_state(nodes, n0=on["mode0"])
    tb = 0.5 * (nodes[1] + nodes[2])
    j = np.flatnonzero(np.diff(st["mode"])) + 1
    heating = np.diff(tb)[j - 1] > 0
    return tb[j][heating], tb[j][~heating], {"nodes": nodes, "state": st, "j": j, "tb": tb}


def _wrap(x, period):
    """x modulo period, into [-period/2, period/2)."""
    return (np.asarray(x) + period / 2) % period - period / 2


def test_chamber_run_mode_hops_unit_dependent_with_hysteresis():
    """A -40..+65..-40 degC cycle: hops at block temperatures given by lambda/(P alpha) and the
    travel, different for two units, and shifted between heating and cooling by
    (S - lambda)/(P |alpha|)."""
    spec = rc.CavityRLGSpec()
    prof = _cycle_profile()
    found = []
    for s in range(40):
        u = spec.realize(rng=np.random.default_rng(s))
        if u.hop_spacing < 30.0:
            found.append(u)
        if len(found) == 2:
            break
    assert len(found) == 2
    ups = []
    for u in found:
        up, down, d = _hop_temperatures(u, prof, 1)
        assert len(up) >= 3 and len(down) >= 3
        # spacing of successive hops in one direction = lambda/(P alpha) (within the
        # block-temperature change of one 1-s sample, 1/180 K)
        np.testing.assert_allclose(np.diff(np.sort(up)), u.hop_spacing, atol=0.02)
        np.testing.assert_allclose(np.diff(np.sort(down)), u.hop_spacing, atol=0.02)
        # closed form: heating hops where P alpha (T - T_ref) = n lambda + sign(alpha) S/2,
        # i.e. at T_ref + S/(2 P |alpha|) modulo the spacing; cooling at T_ref - S/(2 P |alpha|)
        dsp, half = u.hop_spacing, u.plc.travel / (2 * u.geometry.perimeter * abs(u.cte))
        tr = u.reference_temperature
        np.testing.assert_allclose(_wrap(up - tr - half, dsp), 0.0, atol=0.02)
        np.testing.assert_allclose(_wrap(down - tr + half, dsp), 0.0, atol=0.02)
        # so heating minus cooling hop temperatures = (S - lambda)/(P |alpha|) modulo the spacing
        np.testing.assert_allclose(
            _wrap(np.sort(up)[0] - np.sort(down) - u.hysteresis, dsp), 0.0, atol=0.04
        )
        assert u.hysteresis > 1.0
        ups.append(np.sort(up))
    # unit-dependent hop temperatures
    assert abs(ups[0][0] - ups[1][0]) > 0.5
    assert abs(np.diff(ups[0]).mean() - np.diff(ups[1]).mean()) > 0.1


def test_hop_steps_lock_in_and_bias():
    """At each hop the lock-in and the backscatter null shift step (beam walk), while the
    Langmuir bias is continuous."""
    spec = rc.CavityRLGSpec()
    u = next(
        x
        for x in (spec.realize(rng=np.random.default_rng(s)) for s in range(40))
        if x.hop_spacing < 30
    )
    _, _, d = _hop_temperatures(u, _cycle_profile(), 1)
    lock = d["state"]["lock_in"]
    j = d["j"]
    typical = np.median(np.abs(np.diff(lock)))
    steps = np.abs(lock[j] - lock[j - 1])
    assert np.all(steps > 20 * typical)


def test_simulate_truth_adds_up_and_is_deterministic():
    spec = rc.CavityRLGSpec()
    u = spec.realize(rng=np.random.default_rng(3))
    prof = _cycle_profile()
    a = u.simulate(Environment(7200.0, temperature=prof), fs=10.0, rng=np.random.default_rng(5))
    b = u.simulate(Environment(7200.0, temperature=prof), fs=10.0, rng=np.random.default_rng(5))
    np.testing.assert_array_equal(a["output"], b["output"])
    parts = ("bias_langmuir", "bias_backscatter")
    np.testing.assert_allclose(
        np.asarray(a["truth/thermal_bias"]), sum(np.asarray(a[f"detail/{p}"]) for p in parts)
    )
    # cumulative output angle = cumulative true angle + counting error (bounded by q + dither)
    q = u.pulse_weight
    k = np.asarray(a["inputs/scale_factor_ratio"])
    true = k * (
        np.asarray(a["truth/true_rate"]) + np.asarray(a["truth/turn_on_bias"])
        + np.asarray(a["truth/thermal_bias"]) + np.asarray(a["truth/flicker_rrw"])
    ) + np.asarray(a["truth/dither_random_walk"])
    err = np.cumsum(np.asarray(a["output"]) - true) / 10.0
    assert np.max(np.abs(err)) <= q + 1e-12
    assert "T_block_b" in a.inputs


def test_bad_input_refused():
    with pytest.raises(ValueError, match="plc_travel"):
        rc.CavityRLGSpec(plc_travel=(0.5 * LAM, 1.5 * LAM))
    with pytest.raises(ValueError, match="g_air"):
        rc.CavityThermal(g_air=0.0)
    with pytest.raises(TypeError, match="Discharge.current"):
        rc.Discharge(current="1 mA")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="Backscatter"):
        rc.Backscatter(amplitudes=(1e-6,), phases=(0.0,), positions=(0.0,))
    u = rc.CavityRLGSpec().realize(rng=np.random.default_rng(0))
    with pytest.raises(ValueError, match="fs must be <="):
        u.simulate(Environment(10.0, temperature=_cycle_profile()), fs=200.0, rng=np.random.default_rng(0))
    with pytest.raises(TypeError, match="rng"):
        u.simulate(Environment(10.0, temperature=_cycle_profile()), fs=10.0, rng=0)  # type: ignore[arg-type]


def test_dither_margin_refused_just_below_and_accepted_just_above():
    """Statistical-mode validity: the dither peak rate at -3 sigma of its jitter must be
    >= 10 x the lock-in, for the spec (Rayleigh 1e-6 quantile, all mirrors in phase:
    Omega_L = c lambda n sigma sqrt(2 ln 1e6) / (8 pi A)) and for a unit (sum of |r_i|)."""
    spec = rc.CavityRLGSpec()
    g, d = spec.geometry, spec.dither
    low = d.peak_rate * (1.0 - 3.0 * d.amplitude_jitter)
    quantile = len(g.vertices) * math.sqrt(2.0 * math.log(1e6))
    per_sigma = rc.SPEED_OF_LIGHT * LAM * quantile / (8.0 * math.pi * g.area)
    crit = low / (10.0 * per_sigma)
    rc.CavityRLGSpec(backscatter_sigma=0.99 * crit)
    with pytest.raises(ValueError, match=r"too small for lock-in.*10 x the largest likely"):
        rc.CavityRLGSpec(backscatter_sigma=1.01 * crit)
    u = spec.realize(rng=np.random.default_rng(0))
    amps = np.asarray(u.backscatter.amplitudes)
    scale = (low / 10.0) / u.max_lock_in_rate
    ok = replace(u.backscatter, amplitudes=tuple(0.99 * scale * amps))
    assert replace(u, backscatter=ok).max_lock_in_rate < low / 10.0
    bad = replace(u.backscatter, amplitudes=tuple(1.01 * scale * amps))
    with pytest.raises(ValueError, match=r"too small for lock-in.*10 x the largest possible"):
        replace(u, backscatter=bad)


def test_network_refuses_a_chamber_that_is_not_a_series():
    with pytest.raises(ValueError, match=r"chamber must be 1-D with >= 2 samples; got shape \(2,"):
        rc.CavityThermal().temperatures(np.full((2, 2), 300.0), 1.0)
    with pytest.raises(ValueError, match=r"CavityThermal.temperatures.fs must be > 0 Hz"):
        rc.CavityThermal().temperatures(np.full(3, 300.0), 0.0)


def test_counterfactual_without_hops_differs_only_by_the_hops():
    spec = rc.CavityRLGSpec()
    u = next(
        x
        for x in (spec.realize(rng=np.random.default_rng(s)) for s in range(40))
        if x.hop_spacing < 30
    )
    prof = _cycle_profile()
    a = u.simulate(Environment(prof.duration, temperature=prof), fs=1.0, rng=np.random.default_rng(9))
    b = replace(u, mode_hops=False).simulate(
        Environment(prof.duration, temperature=prof), fs=1.0, rng=np.random.default_rng(9)
    )
    assert np.count_nonzero(np.diff(a["inputs/mode"])) >= 3
    assert np.count_nonzero(np.diff(b["inputs/mode"])) == 0
    np.testing.assert_array_equal(a["detail/bias_langmuir"], b["detail/bias_langmuir"])
    np.testing.assert_array_equal(a["truth/flicker_rrw"], b["truth/flicker_rrw"])
    # before the first hop the two runs are the same gyro
    j = int(np.flatnonzero(np.diff(a["inputs/mode"]))[0])
    np.testing.assert_allclose(a["detail/lock_in_rate"][:j], b["detail/lock_in_rate"][:j], rtol=1e-12)
