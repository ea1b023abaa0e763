"""The FOG's and RLG's own vibration errors on their physics models (sim.coil_vibration, sim.rlg_vibration)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gyrobench.base import units
from gyrobench.sim import parts
from gyrobench.sim.coil2d import Coil2D
from gyrobench.sim.coil_vibration import coil_modes, inertial_strain, shape_weight
from gyrobench.sim.fiber_strain import strain_rate_coefficient
from gyrobench.sim.fog2d import FOG2DSpec
from gyrobench.sim.parts._physics import fog_spec
from gyrobench.sim.rlg import RLGSpec
from gyrobench.sim.rlg_vibration import DitherMount, dither_mount_error
from gyrobench.sim.sensor import Environment
from gyrobench.sim.shaker import FixedSine, ShakerSignal, interval_mean_acceleration, record_signal

EPS = np.finfo(float).eps


def _sine_signal(f: float, amp: float, fs_out: float, m: int, duration: float) -> ShakerSignal:
    """A table sine over the whole record (integer cycles: the circular transforms are exact)."""
    n = int(round(duration * fs_out)) * m
    t = np.arange(n) / (m * fs_out)
    return ShakerSignal(m * fs_out, amp * np.sin(2 * math.pi * f * t), np.full(n, f), np.full(n, amp),
                        np.ones(n, dtype=bool))


def _tone_amplitude(y: np.ndarray, f: float, fs: float) -> float:
    """Least-squares amplitude of the tone at ``f`` in ``y`` sampled at ``fs`` (block centres)."""
    t = (np.arange(len(y)) + 0.5) / fs
    x = np.column_stack([np.sin(2 * math.pi * f * t), np.cos(2 * math.pi * f * t)])
    c, *_ = np.linalg.lstsq(x, y, rcond=None)
    return float(np.hypot(*c))


def test_uniform_strain_on_the_winding_map_has_no_weight():
    # a translation that strains every turn alike: W = sum ds (L - 2s) = 0; the bound is the
    # rounding of the sum, N eps sum |w_i|
    coil = Coil2D(spec=fog_spec(parts.get("dsp-1760").datasheet).coil)
    fm = coil.fibre()
    w = shape_weight(coil, lambda z: np.ones_like(z))
    bonded = np.asarray(fm.bonded)
    # the bonded pieces alone: sum over the leads removed, which is exactly what the leads' weights sum to
    leads = float(np.sum(fm.weights[~bonded]))
    assert abs(w + leads) <= len(fm.ds) * EPS * float(np.sum(np.abs(fm.weights)))


def test_fog_static_acceleration_gives_no_error():
    # eps_dot = 0: a constant table acceleration has no strain-rate term (no first-order g-sensitivity)
    unit = FOG2DSpec(coil=fog_spec(parts.get("dsp-1760").datasheet).coil).realize(rng=np.random.default_rng(3))
    fs, m, dur = 100.0, 2, 20.0
    n = int(dur * fs) * m
    sig = ShakerSignal(m * fs, np.full(n, units.g(2.0)), np.full(n, np.nan), np.zeros(n), np.ones(n, dtype=bool))
    rec = unit.simulate(Environment(dur, vibration=sig), fs=fs, rng=np.random.default_rng(1))
    scale = units.g(2.0) * unit.fog.strain_coefficient() * sum(abs(md.strain * md.weight) for md in unit.fog.modes)
    # rounding only: the transform's eps sqrt(N) per bin, times j omega up to the grid's Nyquist pi m fs
    bound = 8 * math.sqrt(n) * EPS * scale * math.pi * m * fs
    assert np.max(np.abs(rec["truth/strain_nonreciprocity"])) <= bound


def test_fog_sine_gives_the_closed_form_strain_tone():
    # Omega_eps = K omega A |sum_k kappa_k W_k H_k(f)| |H_loop| sinc(f/fs) (docs/physics.md 4.1, 4.3),
    # written from the modes' parameters (small-tau kernel: relative error <= (omega tau/2)^2/6)
    unit = FOG2DSpec(coil=fog_spec(parts.get("dsp-1760").datasheet).coil).realize(rng=np.random.default_rng(1))
    f, amp, fs, m, dur = 20.0, units.g(2.0), 100.0, 2, 40.0
    rec = unit.simulate(Environment(dur, vibration=_sine_signal(f, amp, fs, m, dur)), fs=fs,
                        rng=np.random.default_rng(2))
    fog = unit.fog
    lp = fog.loop
    k = strain_rate_coefficient(lp.length, lp.diameter, lp.group_index, fog.index)
    r = [f / md.frequency for md in fog.modes]
    modal = sum(md.strain * md.weight / (1 - ri**2 + 1j * ri / md.quality) for md, ri in zip(fog.modes, r, strict=True))
    expected = k * 2 * math.pi * f * amp * abs(modal) * abs(lp.transfer(np.array([f]))[0]) * np.sinc(f / fs)
    got = _tone_amplitude(rec["truth/strain_nonreciprocity"], f, fs)
    tau = lp.transit_time
    assert abs(got / expected - 1) <= (2 * math.pi * f * tau / 2) ** 2 / 6 + 1e-9
    # the inertial mode dominates at 20 Hz: its strain is ~70x the pigtail's
    assert fog.modes[0].strain == inertial_strain(unit.coil)


def test_fog2d_without_vibration_is_unchanged_by_the_modes():
    # the modes act only through a shaker run: a record without one is bit-identical to the loop without modes
    from dataclasses import replace

    unit = FOG2DSpec().realize(rng=np.random.default_rng(5))
    env = Environment(30.0)
    a = unit.simulate(env, fs=10.0, rng=np.random.default_rng(6))
    fog0 = replace(unit.fog, modes=())
    unit.__dict__["fog"] = fog0  # the cached loop replaced by the one without modes
    b = unit.simulate(env, fs=10.0, rng=np.random.default_rng(6))
    assert np.array_equal(a["output"], b["output"])
    assert len(coil_modes(unit.coil)) == 3


def test_rlg_without_mount_compliance_has_no_vibration_error():
    sig = _sine_signal(20.0, units.g(2.0), 100.0, 2, 10.0)
    assert not np.any(dither_mount_error(DitherMount(offset=0.0), 400.0, sig, 1000, 100.0))
    spec = RLGSpec(dither_mount=DitherMount(offset=0.0))
    unit = spec.realize(rng=np.random.default_rng(1))
    with_vib = unit.simulate(Environment(10.0, vibration=sig), fs=100.0, rng=np.random.default_rng(2))
    without = unit.simulate(Environment(10.0), fs=100.0, rng=np.random.default_rng(2))
    assert np.array_equal(with_vib["output"], without["output"])


def test_rlg_sine_gives_the_closed_form_twist_rate():
    # phi = (1 - B) c H_d A sin(w t): the angle increment over 1/fs has amplitude 2 fs sin(pi f/fs) |phi|
    mount = DitherMount()
    f_d, f, amp, fs = 400.0, 20.0, units.g(2.0), 100.0
    err = dither_mount_error(mount, f_d, _sine_signal(f, amp, fs, 2, 20.0), 2000, fs)
    r = f / f_d
    c = mount.offset / (mount.gyration_radius**2 * (2 * math.pi * f_d) ** 2)
    h_d = 1 / (1 - r**2 + 1j * r / mount.dither_quality)
    b = (1j * r / mount.stripper_quality) / (1 - r**2 + 1j * r / mount.stripper_quality)
    expected = 2 * fs * math.sin(math.pi * f / fs) * c * amp * abs((1 - b) * h_d)
    # deterministic, circular and exact: rounding of the transforms (relative 1e-12)
    t = np.arange(2000) / fs  # the increments sit on the interval edges: fit on t_k + 1/(2 fs)
    x = np.column_stack([np.sin(2 * math.pi * f * (t + 0.5 / fs)), np.cos(2 * math.pi * f * (t + 0.5 / fs))])
    got = float(np.hypot(*np.linalg.lstsq(x, err, rcond=None)[0]))
    assert got == pytest.approx(expected, rel=1e-9)
    assert abs(float(np.mean(err))) <= 1e-12 * expected  # a bounded angle: no bias


def test_rlg_twist_at_the_dither_frequency_is_stripped():
    mount = DitherMount()
    resp = mount.response(np.array([400.0, 20.0]), 400.0)
    assert abs(resp[0]) <= 1e-15 * abs(resp[1])


def test_record_signal_block_means_are_the_interval_means():
    vib = FixedSine(frequency=125.0, duration=3.0, acceleration=units.g(1.0))  # m = 10 for both: even
    kw = dict(duration=10.0, fs=50.0, start=2.0)
    a = interval_mean_acceleration(vib, rng=np.random.default_rng(0), **kw)
    sig = record_signal(vib, rng=np.random.default_rng(0), **kw)
    m = int(round(sig.fs / 50.0))
    assert m % 2 == 0 and len(sig.acceleration) == 500 * m
    means = sig.acceleration.reshape(500, m).mean(axis=1)
    assert np.max(np.abs(means - a)) <= 8 * m * EPS * units.g(1.0)


@pytest.mark.parametrize("name", ["dsp-1760", "hg9900"])
def test_part_on_the_shaker_closes_with_its_vibration_term(name):
    fs = 100.0
    vib = FixedSine(frequency=20.0, duration=20.0, acceleration=units.g(2.0))
    sig = record_signal(vib, duration=40.0, fs=fs, start=10.0, rng=np.random.default_rng(0))
    rec = parts.simulate_part(parts.get(name), Environment(40.0, vibration=sig), fs=fs, rng=np.random.default_rng(1))
    term = "strain_nonreciprocity" if name == "dsp-1760" else "dither_mount_vibration"
    comps = rec.metadata["error_components"]
    assert term in comps and "vibration" not in rec.metadata["ignored_inputs"]
    e = rec["truth/" + term]
    assert np.sqrt(np.mean(e[1000:3000] ** 2)) > 100 * np.sqrt(np.mean(e[:900] ** 2))  # on while the table shakes
    resid = rec["output"] - rec["truth/true_rate"] - sum(rec["truth/" + k] for k in comps)
    scale = float(np.max(np.abs(rec["output"]))) + 1e-300
    assert np.max(np.abs(resid)) <= 16 * (len(comps) + 2) * EPS * scale


@pytest.mark.parametrize(("name", "term"), [
    pytest.param("dsp-1760", "strain_nonreciprocity", marks=pytest.mark.slow),  # ~3 s: the coil solve and heat flow
    ("hg9900", "dither_mount_vibration"),
])
def test_simulate_device_on_a_shaker_profile_gives_the_part_its_vibration_term(tmp_path, name, term):
    from gyrobench.io.recording import load_hdf5
    from gyrobench.scenarios.cli.main import main

    (tmp_path / "p.toml").write_text(
        "duration_s = 30.0\ntemperature_c = [[0.0, 20.0], [30.0, 20.5]]\nspecific_force_g = 1.0\n"
        "[shaker]\nkind = \"sine\"\nfrequency_hz = 20.0\nacceleration_g = 2.0\nstart_s = 10.0\nduration_s = 10.0\n")
    out = tmp_path / "r.h5"
    assert main(["simulate", "device", name, "--profile", str(tmp_path / "p.toml"), "--fs", "100", "--seed", "1",
                 "-o", str(out), "-q"]) == 0
    rec = load_hdf5(out)
    assert rec.metadata["model_kind"] == "physics" and term in rec.metadata["error_components"]
    e = np.asarray(rec["truth/" + term])
    inside, before = e[1100:1900], e[100:800]  # away from the abrupt edges' band-limited ringing
    assert np.sqrt(np.mean(inside**2)) > 1e3 * np.sqrt(np.mean(before**2))
    comps = rec.metadata["error_components"]
    resid = rec["output"] - rec["truth/true_rate"] - sum(np.asarray(rec["truth/" + k]) for k in comps)
    assert np.max(np.abs(resid)) <= 16 * (len(comps) + 2) * EPS * float(np.max(np.abs(rec["output"])))
