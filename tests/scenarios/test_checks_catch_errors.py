"""The checks shortened for speed (issue 23 item 5) still catch a 10 % error in the model.

Each test runs one check as the physics_checks scenario does, with the model (not the closed
form) made 10 % wrong, and expects the check to fail; the unperturbed check passing is in the
modules' own tests. Fixed seeds: every case is deterministic.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from gyrobench.scenarios.checks import (
    mems as checks_mems,
)
from gyrobench.scenarios.checks import (
    mems_noise as checks_mems_noise,
)
from gyrobench.scenarios.checks import (
    mems_psd as checks_mems_psd,
)
from gyrobench.scenarios.checks import (
    rlg as checks_rlg,
)
from gyrobench.scenarios.checks import (
    rlg_cavity as checks_rlg_cavity,
)


def _noisier(simulate_full, factor: float):
    """simulate_full whose output noise PSD is ``factor`` times the model's (deviations scaled)."""

    def wrapped(*a, **k):
        res = simulate_full(*a, **k)
        mean = res.output.mean()
        return replace(res, output=mean + math.sqrt(factor) * (res.output - mean))

    return wrapped


@pytest.mark.slow  # two open-loop noise integrations (~4 s each)
@pytest.mark.parametrize("factor", [0.9, 1.1])
def test_a_10_percent_psd_error_fails_the_open_loop_noise_checks(monkeypatch, factor):
    monkeypatch.setattr(checks_mems_psd, "simulate_full", _noisier(checks_mems_psd.simulate_full, factor))
    out = checks_mems_psd.open_loop_noise_checks(np.random.default_rng(0))
    assert [c.id for c in out if c.passed] == []


@pytest.mark.slow  # one closed-loop noise integration (~3 s)
@pytest.mark.parametrize("factor", [0.9**2, 1.1**2])
def test_a_10_percent_noise_amplitude_error_fails_the_closed_loop_noise_check(monkeypatch, factor):
    zro = checks_mems.zero_rate_output(checks_mems.check_unit())
    real = checks_mems_noise.simulate_full

    def wrapped(*a, **k):
        res = real(*a, **k)
        return replace(res, output=zro + math.sqrt(factor) * (res.output - zro))

    monkeypatch.setattr(checks_mems_noise, "simulate_full", wrapped)
    assert not checks_mems_noise._noise_vs_full(np.random.default_rng(0)).passed


@pytest.mark.parametrize("factor", [0.9, 1.1])
def test_a_10_percent_arw_error_fails_the_brownian_arw_check(monkeypatch, factor):
    real = checks_mems.brownian_arw
    assert checks_mems._arw_check(np.random.default_rng(0)).passed
    monkeypatch.setattr(checks_mems, "brownian_arw", lambda *a, **k: factor * real(*a, **k))
    assert not checks_mems._arw_check(np.random.default_rng(0)).passed


def _lock_in_off(module, monkeypatch, factor: float) -> None:
    """``module.integrate_adler`` with the lock-in rate ``factor`` times the one it is given."""
    real = module.integrate_adler
    monkeypatch.setattr(module, "integrate_adler",
                        lambda *a, lock_in_rate, **k: real(*a, lock_in_rate=factor * lock_in_rate, **k))


@pytest.mark.slow  # Adler integrations of 3000 realizations (~1.5 s each)
@pytest.mark.parametrize("factor", [0.9, 1.1])
def test_a_10_percent_lock_in_error_fails_the_rlg_dither_check(monkeypatch, factor):
    from gyrobench.sim import rlg

    assert checks_rlg._dither(np.random.default_rng(0)).passed
    _lock_in_off(rlg, monkeypatch, factor)  # checks_rlg calls rlg.integrate_adler
    assert not checks_rlg._dither(np.random.default_rng(0)).passed


@pytest.mark.slow  # Adler integrations (~1 s each)
@pytest.mark.parametrize("factor", [0.9, 1.1])
def test_a_10_percent_lock_in_error_fails_the_cavity_random_walk_and_dead_band(monkeypatch, factor):
    _lock_in_off(checks_rlg_cavity, monkeypatch, factor)
    assert not checks_rlg_cavity._check_random_walk(np.random.default_rng(0)).passed
    assert not checks_rlg_cavity._check_dead_band().passed


@pytest.mark.slow  # Adler integration of 2000 realizations (~1 s each)
@pytest.mark.parametrize("factor", [0.9, 1.1])
def test_a_10_percent_rate_error_fails_the_no_dead_band_check(monkeypatch, factor):
    """The gyro integrates its constant input 10 % off: the mean output no longer equals it."""
    real = checks_rlg_cavity._swing_adler_angles

    def wrong_input(k, wl, fd, beta, sigma, m, n_cyc, rate, rng):
        return real(k, wl, fd, beta, sigma, m, n_cyc, factor * rate, rng)

    monkeypatch.setattr(checks_rlg_cavity, "_swing_adler_angles", wrong_input)
    assert not checks_rlg_cavity._check_randomized_dead_band(np.random.default_rng(0)).passed


@pytest.mark.parametrize("factor", [0.99, 1.01])
def test_a_1_percent_lock_in_error_fails_the_dead_band_check(monkeypatch, factor):
    """A 1 % lock-in error scales the simulated edge by 1 % (the band is proportional to Omega_L): the
    interpolated edge moves with it, to |factor x edge / band - 1| (the unperturbed edge is 0.06 %
    off the first-order closed form), beyond the check's half-cell tolerance."""
    base = checks_rlg_cavity._check_dead_band()
    assert base.passed
    _lock_in_off(checks_rlg_cavity, monkeypatch, factor)
    out = checks_rlg_cavity._check_dead_band()
    assert not out.passed
    assert out.rel_error == pytest.approx(abs(factor * base.simulated / base.expected - 1.0), rel=0.02)


def _fog_resets_with(monkeypatch, change) -> dict:
    """checks_fog_loop._resets with every loop spec passed through ``change``."""
    from gyrobench.scenarios.checks import fog_loop as checks_fog_loop
    from gyrobench.sim import fog_loop

    real = fog_loop.run_loop
    monkeypatch.setattr(fog_loop, "run_loop", lambda spec, *a, **k: real(change(spec), *a, **k))
    return {c.id: c.passed for c in checks_fog_loop._resets(np.random.default_rng(0))}


def test_the_shortened_fog_scale_factor_records_still_catch_errors(monkeypatch):
    """400 outputs (was 1200): no V_2pi control fails the gain-loop check; a modulator gain error
    10 % larger than specified fails the blanked-reset check (the gain loop absorbs it: passes)."""
    off = _fog_resets_with(monkeypatch, lambda s: replace(s, gain_loop=False))
    assert not off["fog.loop_v2pi_scale_factor"]
    monkeypatch.undo()
    wrong = _fog_resets_with(monkeypatch, lambda s: replace(s, modulator_gain_error=1.1 * s.modulator_gain_error))
    assert not wrong["fog.loop_blanked_reset_scale_factor"] and wrong["fog.loop_v2pi_scale_factor"]


@pytest.mark.parametrize("factor", [0.9, 1.1])
def test_a_10_percent_noise_error_fails_the_low_output_rate_check(monkeypatch, factor):
    """The slow flow's noise at 4 Hz made 10 % too small or too large (21 % in variance) fails."""
    assert checks_mems_noise._low_rate_noise(np.random.default_rng(0)).passed
    zro = checks_mems.zero_rate_output(checks_mems.check_unit())
    real = checks_mems_noise.slow_flow

    def wrapped(*a, **k):
        res = real(*a, **k)
        return replace(res, output=zro + factor * (res.output - zro))

    monkeypatch.setattr(checks_mems_noise, "slow_flow", wrapped)
    assert not checks_mems_noise._low_rate_noise(np.random.default_rng(0)).passed


@pytest.mark.slow  # five noise-free full integrations (~1 s each)
@pytest.mark.parametrize(
    ("change", "caught"),
    [
        ("rate", {"mems.low_rate_scale_factor", "mems.sense_envelope_saturated", "mems.slow_flow_vs_full"}),
        ("mass", {"mems.rate_authority", "mems.g_sensitivity", "mems.slow_flow_vs_full"}),
        ("drive_amplitude", {"mems.rate_authority", "mems.drive_amplitude", "mems.slow_flow_vs_full"}),
        ("quadrature_coupling", {"mems.quadrature_rejection", "mems.slow_flow_vs_full"}),
        ("phase_error", {"mems.quadrature_rejection", "mems.g_sensitivity", "mems.slow_flow_vs_full"}),
    ],
)
def test_a_10_percent_error_in_the_full_model_fails_the_noise_free_checks(monkeypatch, change, caught):
    """At 16 RK4 steps per period (tolerance 6e-4) each noise-free full-integration check still
    fails when the quantity it measures is 10 % off in the full model (the rate it integrates,
    or one parameter of the unit it is given), and every check is caught by one of the changes."""
    real = checks_mems.simulate_full

    def wrong(unit, rate, **k):
        if change == "rate":
            return real(unit, 1.1 * np.asarray(rate), **k)
        return real(replace(unit, **{change: 1.1 * getattr(unit, change)}), rate, **k)

    monkeypatch.setattr(checks_mems, "simulate_full", wrong)
    failed = {c.id for c in checks_mems._full_checks(np.random.default_rng(1)) if not c.passed}
    assert caught <= failed


def test_a_locked_band_that_is_not_monotone_in_the_input_fails_the_dead_band_check(monkeypatch):
    """Two locked inputs far below the edge answered in swapped order (min P(psi) - psi no longer rising
    with the input): the edge itself is unmoved, but the sampling bound's premise is gone. Its
    tolerance was then infinite, which Check refuses: physics_checks stopped with a ValueError
    instead of reporting a failed check."""
    base = checks_rlg_cavity._check_dead_band()
    real = checks_rlg_cavity.integrate_adler

    def swapped(*a, **k):
        psi = real(*a, **k).copy()
        psi[:, [0, 1]] = psi[:, [1, 0]]  # rows 0 and 1: inputs 0.885 and 0.895 of the band, both locked
        return psi

    monkeypatch.setattr(checks_rlg_cavity, "integrate_adler", swapped)
    out = checks_rlg_cavity._check_dead_band()
    assert base.passed and math.isnan(out.simulated) and math.isfinite(out.tolerance)
    assert not out.passed


def test_the_shaker_gain_check_catches_a_point_sampler_and_a_10_percent_level(monkeypatch):
    """shaker.interval_mean_gain: a shaker input sampled at the output instants (no interval mean: the
    137 Hz tone kept at its full level) and a profile 10 % above its stated level both fail."""
    from gyrobench.scenarios.checks import shaker as checks_shaker
    from gyrobench.sim import shaker

    assert checks_shaker.checks(np.random.default_rng(0))[0].passed
    real = shaker.FixedSine.sample
    monkeypatch.setattr(shaker.FixedSine, "sample", lambda self, fs, **kw: replace(
        real(self, fs, **kw), acceleration=1.1 * real(self, fs, **kw).acceleration))
    assert not checks_shaker.checks(np.random.default_rng(0))[0].passed
    monkeypatch.undo()
    real_mean = shaker.interval_mean_acceleration

    def point_sampler(vib, *, duration, fs, rng, start=0.0):  # each output the profile at its interval's start
        out = real_mean(vib, duration=duration, fs=fs, rng=rng, start=start)
        k0, n = round(start * fs), round(vib.duration * fs)
        t = np.arange(n) / fs
        out[k0:k0 + n] = vib.acceleration * np.sin(2 * np.pi * vib.frequency * t + vib.phase)
        return out

    monkeypatch.setattr(shaker, "interval_mean_acceleration", point_sampler)
    out = checks_shaker.checks(np.random.default_rng(0))[0]
    assert not out.passed and out.simulated > 4.0 * out.expected
