"""Tests of sim/parts: the datasheet solve, the one truth layout, the fit-back of every part, TOML parts."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import norm

from gyrobench.analysis.allan import fit_noise
from gyrobench.io.recording import load_hdf5, save_hdf5
from gyrobench.sim import parts
from gyrobench.sim.sensor import Environment

EPS = np.finfo(float).eps
NAMES = parts.names()


def test_catalogue_spans_the_technologies_and_names_its_sources():
    sheets = parts.datasheets()
    assert len({d.name for d in sheets}) == len(sheets)
    assert {d.technology for d in sheets} >= {"MEMS", "RLG"}
    for d in sheets:
        assert d.source.strip() and (d.bias_instability_dph is None or d.bias_instability_dph > 0)
    # issue 29: a high-range MEMS part (>= +-2000 deg/s full scale)
    assert any(d.technology == "MEMS" and (d.range_dps or 0) >= 2000 for d in sheets)


def test_solve_noise_density_sidedness():
    # white rate noise: two-sided PSD S = N^2, one-sided 2 S (module docstring)
    two = parts.Datasheet(name="x", manufacturer="m", model="x", technology="MEMS", grade="consumer",
                          source="s", bias_instability_dph=1.0, noise_density=0.01, noise_density_sided="two")
    one = parts.Datasheet(name="x", manufacturer="m", model="x", technology="MEMS", grade="consumer",
                          source="s", bias_instability_dph=1.0, noise_density=0.01, noise_density_sided="one")
    assert two.angle_random_walk() == pytest.approx(math.radians(0.01), rel=1e-12)
    assert one.angle_random_walk() == pytest.approx(math.radians(0.01) / math.sqrt(2), rel=1e-12)


@pytest.mark.parametrize("name", NAMES)
def test_truth_components_sum_to_the_error(name, tmp_path):
    part = parts.get(name)
    fs, dur = 50.0, 20.0
    n = int(fs * dur)
    rng = np.random.default_rng(3)
    d = part.datasheet
    # a rate sweep past the range (when there is one), a temperature ramp and 1 g: every term acts
    top = math.radians(1.5 * (d.range_dps or 100.0))
    env = Environment(dur, true_rate=np.linspace(-top, top, n), temperature=np.linspace(283.15, 313.15, n),
                      specific_force=9.80665)
    rec = part.simulate(env, fs=fs, rng=rng)
    out, true = rec["output"], rec["truth/true_rate"]
    comps = [rec["truth/" + k] for k in rec.metadata["error_components"]]
    assert rec.metadata["error_components"] == list(parts.ERROR_COMPONENTS)
    # an identity up to rounding: each of the len + 2 terms rounded at eps of the largest magnitude,
    # a factor 16 for the intermediate operations
    scale = max(np.max(np.abs(a)) for a in (out, true, *comps))
    assert np.max(np.abs(out - true - np.sum(comps, axis=0))) <= 16 * (len(comps) + 2) * EPS * scale
    if d.range_dps is not None:
        assert np.max(np.abs(out)) <= math.radians(d.range_dps) * (1 + 4 * EPS) + math.radians(d.resolution or 0)
        assert np.any(rec["truth/saturation"] != 0)
    if d.resolution:
        q = math.radians(d.resolution)
        assert np.allclose(out / q, np.round(out / q), atol=1e-6)
    for k in rec.truth:
        assert rec.truth[k].unit in ("rad/s", "K", "m/s^2")
    back = load_hdf5(save_hdf5(tmp_path / "r.h5", rec))
    assert np.array_equal(back["output"], out)


# The fit-back: a static record 300 crossover times long (tau_c = (N / 0.664 B)^2, where the ARW
# and flicker ADEVs meet) at 3e5 samples; each part's N and B must lie within z standard errors
# of the fit, z for a 1 % family-wise false-alarm rate over the 2 x len(NAMES) checks
# (Bonferroni). The standard error is the 95 % interval's half-width / 1.96.
# (parts without a bias-instability figure: test_part_without_b_meets_its_arw)
Z = float(norm.ppf(1 - 0.01 / (2 * 2 * len([n for n in NAMES if parts.get(n).datasheet.bias_instability_dph]))))


WITH_B = [n for n in NAMES if parts.get(n).datasheet.bias_instability_dph is not None]
Z_N_ONLY = float(norm.ppf(1 - 0.01 / (2 * max(1, len(NAMES) - len(WITH_B)))))


@pytest.mark.parametrize("name", WITH_B)
def test_simulated_part_meets_its_datasheet(name):
    part = parts.get(name)
    d = part.datasheet
    n_true, b_true = d.angle_random_walk(), d.bias_instability()
    tc = (n_true / (parts.ADEV_MIN_PER_B * b_true)) ** 2
    dur = 300 * tc
    fs = min(200.0, 3e5 / dur)
    rec = part.simulate(Environment(dur), fs=fs, rng=np.random.default_rng(20261127))
    if d.resolution:
        # rounding to q adds white rate noise of variance q^2/12 per sample: N^2 += q^2 / (12 fs)
        # (valid while the per-sample noise N sqrt(fs) is well above q, checked here)
        q = math.radians(d.resolution)
        assert n_true * math.sqrt(fs) > 2 * q
        n_true = math.sqrt(n_true**2 + q**2 / (12 * fs))
    # the output filter bends the short taus: they are left out where the part has a bandwidth (a
    # bandwidth above fs/2 correlates neighbouring output means through the filter's memory: the
    # first 8 sample intervals are left out)
    kw: dict = {}
    if d.bandwidth is not None:
        kw = {"bandwidth": d.bandwidth} if d.bandwidth < fs / 2 else {"tau_min": 8.0 / fs}
    fit = fit_noise(rec["output"], fs, terms=("Q", "N", "B", "K"), **kw)
    assert not fit.misfit
    for key, truth in (("N", n_true), ("B", b_true)):
        c = fit.coefficients[key]
        se = (c.ci95[1] - c.ci95[0]) / (2 * 1.96)
        assert c.value is not None and abs(c.value - truth) <= Z * se, (key, c.value, truth, se)


def test_toml_part_round_trip_and_one_line_errors(tmp_path):
    good = tmp_path / "mine.toml"
    good.write_text(
        '[part]\nname = "mine"\nmanufacturer = "me"\nmodel = "M1"\ntechnology = "FOG"\ngrade = "tactical"\n'
        'source = "my sheet rev A"\nbias_instability_dph = 0.1\narw = 0.01\nrange_dps = 500\n'
    )
    part = parts.get(str(good))
    assert part.datasheet.range_dps == 500.0 and part.datasheet.technology == "FOG"
    rec = part.simulate(Environment(10.0), fs=10.0, rng=np.random.default_rng(0))
    assert rec.n_samples == 100
    bad = tmp_path / "bad.toml"
    bad.write_text('name = "b"\nmanufacturer = "m"\nmodel = "b"\ntechnology = "MEMS"\ngrade = "x"\nsource = "s"\n'
                   'bias_instability_dph = 1\narw = 1\n')
    with pytest.raises(ValueError, match=r"bad.toml.*grade") as e:
        parts.load_toml(bad)
    assert "\n" not in str(e.value)
    bad.write_text('name = "b"\nbias_instabilty_dph = 1\n')
    with pytest.raises(ValueError, match=r"unknown key.*bias_instabilty_dph"):
        parts.load_toml(bad)
    with pytest.raises(ValueError, match="does not exist"):
        parts.load_toml(tmp_path / "none.toml")
    with pytest.raises(ValueError, match="unknown part 'nope'"):
        parts.get("nope")


def test_three_line_python_form_and_the_sensor_protocol(tmp_path):
    import gyrobench.sim.parts
    from gyrobench.sim.sensor import Sensor, SensorUnit

    part = gyrobench.sim.parts.get("hg9900")
    rec = part.simulate(Environment(60.0), fs=10.0, rng=np.random.default_rng(1))
    save_hdf5(tmp_path / "hg9900.h5", rec)
    assert load_hdf5(tmp_path / "hg9900.h5").n_samples == 600
    assert isinstance(part, Sensor)
    assert isinstance(part.realize(rng=np.random.default_rng(0)), SensorUnit)


def test_a_unit_is_one_draw_of_the_population():
    # turn-on bias and scale-factor error are the unit's: the same unit repeats them, and over
    # 2000 units their spread is the repeatability within 5 sigma of the sample-std error
    # (std of a sample std ~ sigma / sqrt(2 n))
    sheet = parts.Datasheet(name="x", manufacturer="m", model="x", technology="FOG", grade="tactical", source="s",
                            bias_instability_dph=0.1, arw=0.01, bias_repeatability=2.0, scale_factor_repeatability=50.0)
    part = parts.Part(sheet)
    rng = np.random.default_rng(11)
    units_ = [part.realize(rng=rng) for _ in range(2000)]
    b = np.array([u.turn_on_bias for u in units_])
    k = np.array([u.scale_factor_error for u in units_])
    tol = 5 / math.sqrt(2 * len(units_))
    assert abs(np.std(b) / math.radians(2.0 / 3600) - 1) < tol
    assert abs(np.std(k) / 50e-6 - 1) < tol
    rec = units_[0].simulate(Environment(1.0, true_rate=0.1), fs=10.0, rng=rng)
    assert np.all(rec["truth/turn_on_bias"] == units_[0].turn_on_bias)
    assert np.allclose(rec["truth/scale_factor_error"], units_[0].scale_factor_error * 0.1, rtol=1e-12)


def test_every_technology_names_its_physics_arw_solve():
    # the mapping names a closed form that exists (a renamed function would leave the docs wrong)
    import importlib

    assert set(parts.PHYSICS_MAPPING) == set(parts.TECHNOLOGIES)
    for tech, (dotted, why) in parts.PHYSICS_MAPPING.items():
        mod, _, attr = dotted.rpartition(".")
        try:
            obj = importlib.import_module(mod)
        except ModuleNotFoundError:  # a method: module.Class.method
            mod, _, cls = mod.rpartition(".")
            obj = getattr(importlib.import_module(mod), cls)
        assert callable(getattr(obj, attr)), (tech, dotted)
        assert "N" in why and "not on" in why


RLG = [n for n in NAMES if parts.get(n).datasheet.technology == "RLG"]
Z_RLG = float(norm.ppf(1 - 0.01 / (2 * 2 * len(RLG))))


@pytest.mark.parametrize("name", RLG)
def test_an_rlg_part_on_the_rlg_model_meets_its_datasheet(name):
    # the sheet's ARW solved for the lock-in rate (sim/parts/_physics.py); the record comes from
    # the RLG model's dither random walk, counting and flicker, and its fit must give the sheet's
    # N and B back within Z_RLG standard errors (1 % family-wise over 2 x len(RLG) checks); the
    # record is 300 crossover times long as in test_simulated_part_meets_its_datasheet

    d = parts.get(name).datasheet
    spec = parts.rlg_spec(d)
    assert spec.lock_in_rate > 0 and spec.lock_in_spread == 0
    n_true, b_true = d.angle_random_walk(), d.bias_instability()
    dur = 300 * (n_true / (parts.ADEV_MIN_PER_B * b_true)) ** 2
    fs = min(200.0, 3e5 / dur)
    rng = np.random.default_rng(20261127)
    rec = spec.realize(rng=rng).simulate(Environment(dur), fs=fs, rng=rng)
    fit = fit_noise(rec["output"], fs, terms=("Q", "N", "B", "K"))
    assert not fit.misfit
    for key, truth in (("N", n_true), ("B", b_true)):
        c = fit.coefficients[key]
        se = (c.ci95[1] - c.ci95[0]) / (2 * 1.96)
        assert c.value is not None and abs(c.value - truth) <= Z_RLG * se, (key, c.value, truth, se)


def test_rlg_spec_refuses_other_technologies():
    with pytest.raises(ValueError, match="needs an RLG part"):
        parts.rlg_spec(parts.get("stim300").datasheet)
    with pytest.raises(TypeError, match="must be a Datasheet"):
        parts.rlg_spec("hg1700")


@pytest.mark.parametrize("name", [n for n in NAMES if parts.get(n).datasheet.bias_instability_dph is None])
def test_part_without_b_meets_its_arw(name):
    # a sheet without bias instability (the high-range part): no 1/f term is drawn, so the static
    # record is white rate noise plus the output rounding, and only N is fitted back (Z_N_ONLY: 1 %
    # family-wise over these parts). The record is at the fastest of 200 Hz and the rate where the
    # per-sample noise N sqrt(fs) reaches the LSB q (rounding a Gaussian of sigma >= q leaves an
    # error uniform within exp(-2 pi^2) = 3e-9, white, variance q^2/12: N^2 += q^2/(12 fs))
    part = parts.get(name)
    d = part.datasheet
    assert d.bias_instability() == 0.0
    n_true = d.angle_random_walk()
    q = math.radians(d.resolution or 0.0)
    fs = max(200.0, (q / n_true) ** 2)
    rec = part.simulate(Environment(3e5 / fs), fs=fs, rng=np.random.default_rng(20261127))
    n_true = math.sqrt(n_true**2 + q**2 / (12 * fs))
    kw = {}
    if d.bandwidth is not None:  # as test_simulated_part_meets_its_datasheet
        kw = {"bandwidth": d.bandwidth} if d.bandwidth < fs / 2 else {"tau_min": 8.0 / fs}
    fit = fit_noise(rec["output"], fs, terms=("Q", "N", "B", "K"), **kw)
    assert not fit.misfit
    c = fit.coefficients["N"]
    se = (c.ci95[1] - c.ci95[0]) / (2 * 1.96)
    assert c.value is not None and abs(c.value - n_true) <= Z_N_ONLY * se, (c.value, n_true, se)


def test_bias_instability_is_optional_but_positive_when_given():
    kw = dict(name="x", manufacturer="m", model="x", technology="MEMS", grade="consumer", source="s", arw=0.1)
    assert parts.Datasheet(**kw).noise_model().bias_instability == 0.0
    with pytest.raises(ValueError, match=r"bias_instability_dph must be \(0, .*got 0"):
        parts.Datasheet(**kw, bias_instability_dph=0.0)


def test_parts_listing_says_when_no_bias_instability_is_drawn(capsys):
    from gyrobench.scenarios.cli.simulate import _cmd_parts

    assert _cmd_parts(None) == 0
    out = capsys.readouterr().out
    block = out[out.index("lsm6dsv:"):]
    assert "range 4000 deg/s" in block and "not on the sheet (no 1/f term drawn)" in block


# ------------------------------------------------------------------ FOG and MEMS on their physics models
def _mapped(tech: str, to_spec) -> list[str]:
    out = []
    for n in NAMES:
        d = parts.get(n).datasheet
        if d.technology != tech:
            continue
        try:
            to_spec(d)
        except ValueError:
            continue
        out.append(n)
    return out


FOG_MAPPED = _mapped("FOG", parts.fog_spec)
MEMS_MAPPED = _mapped("MEMS", parts.mems_spec)
# 1 % family-wise over the 2 (N, B) checks of every mapped FOG and MEMS part (Bonferroni), and
# 1 % family-wise for the fits' goodness-of-fit test (one per part)
Z_PHYS = float(norm.ppf(1 - 0.01 / (2 * 2 * (len(FOG_MAPPED) + len(MEMS_MAPPED)))))
MISFIT_P = 0.01 / (len(FOG_MAPPED) + len(MEMS_MAPPED))


def _fit_back(rate, fs, n_true, b_true, **kw):
    # b_true 0 (a sheet without bias instability, no 1/f term drawn): N alone is checked
    fit = fit_noise(rate, fs, terms=("Q", "N", "B", "K") if b_true else ("Q", "N", "K"), misfit_p=MISFIT_P, **kw)
    assert not fit.misfit
    for key, truth in (("N", n_true), ("B", b_true)) if b_true else (("N", n_true),):
        c = fit.coefficients[key]
        se = (c.ci95[1] - c.ci95[0]) / (2 * 1.96)
        assert c.value is not None and abs(c.value - truth) <= Z_PHYS * se, (key, c.value, truth, se)


def test_every_part_maps_onto_its_physics_model():
    rlg = [n for n in NAMES if parts.get(n).datasheet.technology == "RLG"]
    assert sorted(FOG_MAPPED + MEMS_MAPPED + rlg) == sorted(NAMES)
    for n in NAMES:
        assert not parts.physics_summary(parts.get(n).datasheet).startswith("not mapped"), n


@pytest.mark.parametrize("name", FOG_MAPPED)
def test_a_fog_part_on_the_fog_model_meets_its_datasheet(name):
    # the sheet's ARW solved for the source power (sim/parts/_physics.py); the record is the
    # closed-loop FOG2D model's (optical budget noise through the loop, the sheet's B as its
    # additive 1/f term, a drawn coil), static at a constant chamber; 300 crossover times long
    # (rounded up to the thermal step),
    # 3e5 samples, and its fit must give the sheet's N and B back within Z_PHYS standard errors

    d = parts.get(name).datasheet
    spec = parts.fog_spec(d)
    n_true, b_true = d.angle_random_walk(), d.bias_instability()
    step = spec.thermal_step
    dur = step * math.ceil(300 * (n_true / (parts.ADEV_MIN_PER_B * b_true)) ** 2 / step)
    fs = 3e5 / dur
    rng = np.random.default_rng(20261127)
    rec = spec.realize(rng=rng).simulate(Environment(dur), fs=fs, rng=rng)
    _fit_back(rec["output"], fs, n_true, b_true)


@pytest.mark.parametrize("name", MEMS_MAPPED)
def test_a_mems_part_on_the_resonator_model_meets_its_datasheet(name):
    # the sheet's ARW solved for the pick-off noise, and below the default resonator's Brownian
    # floor for the proof mass too (sim/parts/_physics.py); the record is the resonator slow
    # flow's (Brownian and pick-off noise through the 40 Hz rebalance loop, the sheet's B as the
    # 1/f term, the 20-bit output), static, at 20 Hz over 15000 s or 100 crossover times, the
    # longer. Expected white noise: the sheet's N and the output word's quantization q/sqrt(12 fs)
    # (MemsResonator.output_bits). The loop's low-pass lowers the Allan variance of the short
    # taus (lowpass_avar_bias); the fit starts at the first octave tau where that deficit is
    # <= 1 % (0.8 s), half a percent of N at most, under its standard error at these lengths
    from gyrobench.analysis.allan import lowpass_avar_bias

    d = parts.get(name).datasheet
    spec = parts.mems_spec(d)
    n_true, b_true = d.angle_random_walk(), d.bias_instability()
    crossover = (n_true / (parts.ADEV_MIN_PER_B * b_true)) ** 2 if b_true else 0.0
    fs = 20.0
    dur = max(15000.0, 100 * crossover)
    taus = 2.0 ** np.arange(20) / fs
    tau_min = float(taus[np.argmax(lowpass_avar_bias(taus, spec.nominal.loop_bandwidth) <= 0.01)])
    rng = np.random.default_rng(20261127)
    rec = spec.realize(rng=rng).simulate(Environment(dur), fs=fs, rng=rng)
    n_expected = math.hypot(n_true, spec.nominal.resolution / math.sqrt(12 * fs))
    _fit_back(rec["output"], fs, n_expected, b_true, tau_min=tau_min)


def test_the_fog_and_mems_solves_refuse_what_the_physical_ranges_cannot_reach():
    # beyond the coil (5 km x 0.2 m at the 15 mW source cap) and the proof mass (5 mg) ranges no
    # design gives the sheet's ARW: refused in one line naming the part, the need and the limit
    base = dict(manufacturer="m", model="x", grade="navigation", source="s", bias_instability_dph=0.01)
    with pytest.raises(ValueError, match=r"'f'.*needs a coil L D = .* m\^2 .* beyond the 5 km x 0.2 m coil limit") as e:
        parts.fog_spec(parts.Datasheet(name="f", technology="FOG", arw=1e-4, **base))
    assert "\n" not in str(e.value)
    with pytest.raises(ValueError, match=r"'m'.*needs a proof mass .* mg .*above the 5 mg limit"):
        parts.mems_spec(parts.Datasheet(name="m", technology="MEMS", arw=0.005, **base))
    with pytest.raises(ValueError, match="needs an FOG part"):
        parts.fog_spec(parts.get("adxrs646").datasheet)
    with pytest.raises(ValueError, match="needs an MEMS part"):
        parts.mems_spec(parts.get("dsp-1760").datasheet)
    with pytest.raises(TypeError, match="must be a Datasheet"):
        parts.mems_spec("adxrs646")


def test_the_mems_solve_puts_the_brownian_floor_at_its_share_below_the_default_floor():
    # above the default resonator's Brownian floor only the pick-off noise is solved; below it
    # the proof mass (with its electrode area) is, so that the model's own brownian_arw is
    # BROWNIAN_SHARE x N and its electronic_arw the rest; the loop's R G, hence the DAC limit
    # per unit range, does not move
    from gyrobench.sim.mems_resonator import MemsResonator, brownian_arw, electronic_arw, operating_point

    default = MemsResonator()
    floor = brownian_arw(default)
    op0 = operating_point(default)
    heavy = 0
    for name in MEMS_MAPPED:
        d = parts.get(name).datasheet
        unit = parts.mems_spec(d).nominal
        n = d.angle_random_walk()
        n_b, n_e = brownian_arw(unit), electronic_arw(unit)
        assert math.hypot(n_b, n_e) == pytest.approx(n, rel=1e-9)
        if n > floor:
            assert unit.mass == default.mass and n_b == pytest.approx(floor, rel=1e-12)
            continue
        heavy += 1
        assert n_b == pytest.approx(parts.BROWNIAN_SHARE * n, rel=1e-9)
        assert default.mass < unit.mass <= parts.MEMS_MASS_MAX
        assert unit.electrode_area / unit.mass == pytest.approx(default.electrode_area / default.mass, rel=1e-12)
        op = operating_point(unit)
        assert abs(op.receptance) * op.gain == pytest.approx(abs(op0.receptance) * op0.gain, rel=1e-9)
    assert heavy == 7  # stim300, openrtk330, sch16t-k01, adis16495-1, lsm6dsv, icm-42688-p, icm-42686-p


def test_the_fog_solve_winds_a_longer_coil_only_when_the_source_cannot_reach():
    # the sheets above the default coil's reach keep it and solve the power; astrix-200's
    # 0.0002 deg/sqrt(h) needs L D ~ 6.6x the default's: L at its 5 km limit, D grown, the
    # power (<= the 15 mW cap) re-solved so the nominal coil's loop ARW is the sheet's
    from gyrobench.sim.coil2d import Coil2D
    from gyrobench.sim.fog2d import FOG2DSpec

    default = FOG2DSpec().coil
    for name in FOG_MAPPED:
        d = parts.get(name).datasheet
        s = parts.fog_spec(d)
        fibre = Coil2D(spec=s.coil).fibre()
        loop = s.loop_spec(length=fibre.length, diameter=fibre.diameter)
        assert loop.arw(s.optics) == pytest.approx(d.angle_random_walk(), rel=1e-9)
        assert s.optics.source_power <= parts.FOG_POWER_MAX
        if name != "astrix-200":
            assert s.coil == default and s.optics.loss_db == FOG2DSpec().optics.loss_db
            continue
        assert parts.FOG_LENGTH_MAX - 10.0 <= fibre.length <= parts.FOG_LENGTH_MAX
        assert 0.1 < fibre.diameter <= parts.FOG_DIAMETER_MAX
        extra_km = (fibre.length - Coil2D(spec=default).fibre().length) / 1e3
        assert s.optics.loss_db == pytest.approx(FOG2DSpec().optics.loss_db + extra_km, rel=1e-12)


def test_the_fog_solve_lowers_the_source_power_with_the_sheet_noise():
    # shot and thermal noise grow as the power falls, the RIN floor does not: a noisier sheet
    # needs a weaker source, and the budget's own ARW at the nominal coil is the sheet's
    from gyrobench.sim.coil2d import Coil2D

    def spec_for(arw):
        return parts.fog_spec(parts.Datasheet(name="f", manufacturer="m", model="x", technology="FOG",
                                              grade="tactical", source="s", bias_instability_dph=0.05, arw=arw))

    p = [spec_for(a).optics.source_power for a in (0.002, 0.005, 0.012, 0.05)]
    assert np.all(np.diff(p) < 0)
    s = spec_for(0.012)
    fibre = Coil2D(spec=s.coil).fibre()
    loop = s.loop_spec(length=fibre.length, diameter=fibre.diameter)
    assert loop.arw(s.optics) == pytest.approx(math.radians(0.012 / 60.0), rel=1e-9)
    assert s.noise.bias_instability == pytest.approx(math.radians(0.05 / 3600.0) / parts.ADEV_MIN_PER_B, rel=1e-12)
    assert s.noise.angle_random_walk == 0.0


@pytest.mark.parametrize("arw", [1.2e-3, 5e-4, 1.4e-4, 1.34e-4])
def test_the_fog_coil_solve_stays_inside_its_ranges_up_to_their_limit(arw):
    # L grows at the default D up to 5 km, then D at the most turns that keep L <= 5 km; the
    # integer turns never carry L or D past their limits, and the sheet's N is met exactly
    from gyrobench.sim.coil2d import Coil2D

    d = parts.Datasheet(name="f", manufacturer="m", model="x", technology="FOG", grade="navigation", source="s",
                        bias_instability_dph=0.01, arw=arw)
    s = parts.fog_spec(d)
    fibre = Coil2D(spec=s.coil).fibre()
    assert fibre.length <= parts.FOG_LENGTH_MAX and fibre.diameter <= parts.FOG_DIAMETER_MAX
    assert s.optics.source_power <= parts.FOG_POWER_MAX
    loop = s.loop_spec(length=fibre.length, diameter=fibre.diameter)
    assert loop.arw(s.optics) == pytest.approx(d.angle_random_walk(), rel=1e-9)


def test_physics_solve_limits_are_their_sources_printed_values():
    """The bounds of the coil and proof-mass solves, pinned to what their sources print (with
    units): the Er superfluorescent source of the default optics, 15 mW (from 70 mW of pump,
    sim.fog_optics' cited source); 1 dB/km, the upper end of the 0.5-1 dB/km the default budget
    states; coils "as long as 5 km"; the assumed 0.2 m coil inside Astrix 200's 300 mm core; a
    silicon proof mass filling a 5 mm x 5 mm x 100 um device layer (2329 kg/m^3) rounded down."""
    from gyrobench.sim import fog_optics

    assert parts.FOG_POWER_MAX == pytest.approx(15e-3, rel=1e-12)  # W
    assert "15 mW" in (fog_optics.__doc__ or "")
    assert parts.FIBRE_LOSS_DB_PER_M == pytest.approx(1.0 / 1000.0, rel=1e-12)  # dB/m = 1 dB/km
    assert parts.FOG_LENGTH_MAX == pytest.approx(5000.0, rel=1e-12)  # m
    assert parts.FOG_DIAMETER_MAX < 0.3  # m, inside the 300 mm core
    silicon_mass = 2329.0 * 5e-3 * 5e-3 * 100e-6  # kg
    assert 0.8 * silicon_mass < parts.MEMS_MASS_MAX <= silicon_mass
    assert parts.BROWNIAN_SHARE == pytest.approx(1.0 / math.sqrt(2.0), rel=1e-15)  # N_B = N_e
