"""Parts with their environmental figures: the sheets' values pinned, the output filter's rms, the
physics model's thermal and g terms against the sheet, and the CLI's model choice."""

from __future__ import annotations

import math

import h5py
import numpy as np
import pytest
from scipy.signal import group_delay, sos2tf, sosfilt

from gyrobench.base import units
from gyrobench.io.recording import load_hdf5
from gyrobench.scenarios.cli.main import main
from gyrobench.sim import parts
from gyrobench.sim.coil2d import Coil2D
from gyrobench.sim.environment import PiecewiseLinear
from gyrobench.sim.fog2d import coil_diameter_tempco
from gyrobench.sim.parts._part import output_filter
from gyrobench.sim.sensor import Environment

T_REF = 298.15  # K, the sheets' 25 degC

# ------------------------------------------------------------------ each figure as its sheet prints it
# (part, field, the value as printed, its printed unit -> the field's unit); a change of a part's
# figure, or of a field's unit convention, fails here
PRINTED = [
    # Bosch BST-BMI088-DS000-19 rev 1.9, Table 5 (p. 10) and Table 4 (p. 9)
    ("bmi088", "range_dps", 2000.0, 1.0),
    ("bmi088", "resolution", 16.384, lambda lsb: 1.0 / lsb),  # LSB/(deg/s)
    ("bmi088", "noise_density", 0.014, 1.0),  # deg/s/sqrt(Hz)
    ("bmi088", "rms_noise", 0.1, 1.0),  # deg/s rms at BW = 47 Hz
    ("bmi088", "bandwidth", 47.0, 1.0),
    ("bmi088", "output_rate", 400.0, 1.0),
    ("bmi088", "bias_repeatability", 1.0, 3600.0),  # deg/s -> deg/h
    ("bmi088", "bias_tempco", 0.015, 3600.0),  # deg/s per K -> deg/h/K
    ("bmi088", "scale_factor_repeatability", 1.0, 1e4),  # % -> ppm
    ("bmi088", "scale_factor_tempco", 0.03, 1e4),  # %/K -> ppm/K
    ("bmi088", "g_sensitivity", 0.1, 3600.0),  # deg/s/g -> deg/h/g
    ("bmi088", "accel_noise_density_ug", 160.0, 1.0),
    ("bmi088", "accel_bias_tempco_mg_per_k", 0.2, 1.0),
    ("bmi088", "accel_scale_factor_tempco_ppm_per_k", 0.002, 1e4),
    ("bmi088", "accel_resolution_mg", 10920.0, lambda lsb: 1000.0 / lsb),  # LSB/g
    # TDK DS-000347 rev 1.8, Table 1 (p. 11) and Table 2 (p. 12)
    ("icm-42688-p", "range_dps", 2000.0, 1.0),
    ("icm-42688-p", "resolution", 16.4, lambda lsb: 1.0 / lsb),
    ("icm-42688-p", "noise_density", 0.0028, 1.0),
    ("icm-42688-p", "rms_noise", 0.028, 1.0),  # deg/s-rms at bandwidth 100 Hz
    ("icm-42688-p", "bandwidth", 100.0, 1.0),
    ("icm-42688-p", "scale_factor_repeatability", 0.5, 1e4),
    ("icm-42688-p", "scale_factor_tempco", 0.005, 1e4),  # %/degC
    ("icm-42688-p", "bias_repeatability", 0.5, 3600.0),
    ("icm-42688-p", "bias_tempco", 0.005, 3600.0),  # deg/s/degC
    ("icm-42688-p", "accel_noise_density_ug", 65.0, 1.0),
    ("icm-42688-p", "accel_bias_tempco_mg_per_k", 0.15, 1.0),
    ("icm-42688-p", "accel_resolution_mg", 2048.0, lambda lsb: 1000.0 / lsb),
    # the same document's family table (p. 1), ICM-42686-P column
    ("icm-42686-p", "noise_density", 5.3, 1e-3),  # mdps/sqrt(Hz)
    ("icm-42686-p", "bias_tempco", 10.0, 3.6),  # mdps/degC -> deg/h/K
    ("icm-42686-p", "range_dps", 4000.0, 1.0),
]


@pytest.mark.parametrize(("name", "field", "printed", "conv"), PRINTED, ids=[f"{p[0]}-{p[1]}" for p in PRINTED])
def test_part_figure_is_the_value_its_sheet_prints(name, field, printed, conv):
    want = conv(printed) if callable(conv) else printed * conv
    assert math.isclose(getattr(parts.get(name).datasheet, field), want, rel_tol=1e-12)


def test_every_part_says_where_its_figures_come_from():
    kinds = {d.name: d.source_kind for d in parts.datasheets()}
    assert len(kinds) >= 16
    assert set(kinds.values()) <= {"primary", "secondary"}
    for d in parts.datasheets():  # a secondary quote names the page it was read from
        if d.source_kind == "secondary":
            assert "quot" in d.source or "as used in" in d.source or "tabulated in" in d.source, d.name
    techs = {d.technology for d in parts.datasheets()}
    assert techs == {"MEMS", "FOG", "RLG"}


def test_the_bosch_and_tdk_densities_are_one_sided_by_their_own_rms():
    # the sheet's two figures fix the convention: rms = ND sqrt(bandwidth) holds one-sided (and is
    # off by sqrt 2 two-sided), to the sheet's printed precision (0.1 is one digit: +-5 %)
    for name in ("bmi088", "icm-42688-p"):
        d = parts.get(name).datasheet
        assert d.noise_density_sided == "one"
        assert abs(d.noise_density * math.sqrt(d.bandwidth) / d.rms_noise - 1) < 0.05
        assert abs(d.noise_density * math.sqrt(2 * d.bandwidth) / d.rms_noise - 1) > 0.3


def test_bmi088_gives_its_sheet_rms_noise_in_its_bandwidth():
    """The output noise of the budget at the sheet's ODR and filter against the sheet's 0.1 deg/s rms.

    Expected: ND^2 x (noise bandwidth of the simulated filter), the filter's own impulse response
    (sum h^2) times the white sample variance ND^2 fs / 2. Tolerance: the sample std of n samples
    correlated over the filter's time scale, n_eff = n 2 B_n / fs, relative SE 1/sqrt(2 n_eff), at
    z = 3.9 (1e-4 false alarms)."""
    part = parts.get("bmi088")
    d = part.datasheet
    fs = d.output_rate
    rec = part.simulate(Environment(60.0), fs=fs, rng=np.random.default_rng(7))
    noise = np.degrees(rec["truth/ieee_noise"])
    assert rec.metadata["output_filter"]["applied"]
    impulse = np.zeros(4096)
    impulse[0] = 1.0
    h2 = float(np.sum(sosfilt(output_filter(d, fs), impulse) ** 2))
    enbw = h2 * fs / 2.0  # Hz, one-sided noise bandwidth of the simulated filter
    expect = d.noise_density * math.sqrt(enbw)
    n_eff = len(noise) * 2 * enbw / fs
    assert abs(noise.std() / expect - 1) <= 3.9 / math.sqrt(2 * n_eff)
    # and the sheet's figure (0.1 printed to one digit): within its +-5 %
    assert abs(noise.std() / d.rms_noise - 1) < 0.05
    # the unfiltered white noise at 400 Hz is what the issue measured: 0.198 deg/s, not the sheet's
    assert abs(d.noise_density * math.sqrt(fs / 2) - 0.198) < 0.001


def test_budget_output_filter_closes_and_passes_slow_rates():
    part = parts.get("bmi088")
    env = Environment(10.0, true_rate=PiecewiseLinear([0, 5, 10], [0.0, 0.5, 0.5]),
                      temperature=PiecewiseLinear([0, 10], [T_REF, T_REF + 10]), specific_force=units.G0)
    rec = part.simulate(env, fs=400.0, rng=np.random.default_rng(1))
    total = sum(rec["truth/" + k] for k in parts.ERROR_COMPONENTS)
    assert np.max(np.abs(rec["output"] - rec["truth/true_rate"] - total)) < 1e-12
    # the filter lags a ramp by its group delay at DC (the digital Butterworth's, from scipy's
    # group_delay: 4.57 ms at 47 Hz and 400 Hz; the analog sqrt 2/(2 pi f_c) is 4.79 ms), so the
    # term is -0.1 rad/s^2 x that delay on the ramp, and 0 on the plateau once settled
    b, a = sos2tf(output_filter(parts.get("bmi088").datasheet, 400.0))
    delay = float(group_delay((b, a), w=[1e-6])[1][0]) / 400.0
    assert 4.4e-3 < delay < 4.8e-3
    bw = rec["truth/bandwidth"]
    t = rec.time
    assert abs(np.median(bw[(t > 1) & (t < 4)]) + 0.1 * delay) < 1e-3 * 0.1 * delay
    assert np.max(np.abs(bw[t > 6])) < 1e-9


# ------------------------------------------------------------------ the physics path
def _chamber(duration, step_at, d_t, rate=0.0):
    return Environment(duration, true_rate=rate,
                       temperature=PiecewiseLinear([0.0, step_at, step_at + 1.0, duration],
                                                   [T_REF, T_REF, T_REF + d_t, T_REF + d_t]))


def _closes(rec):
    total = sum(rec["truth/" + k] for k in rec.metadata["error_components"])
    scale = max(1.0, float(np.max(np.abs(rec["output"]))))
    return float(np.max(np.abs(rec["output"] - rec["truth/true_rate"] - total))) <= 1e-12 * scale


def test_fog_part_on_its_physics_has_its_own_shupe_drift_and_scale_factor_error():
    """dsp-1760 in a 10 K chamber ramp under a 90 deg/s table: non-zero non-reciprocal (Shupe)
    drift, and a scale-factor error matching the first-order law of the coil and source,
    e_K = 2 alpha_D dT_coil - alpha_lambda dT_housing (alpha_D the coil's own expansion)."""
    part = parts.get("dsp-1760")
    env = Environment(600.0, true_rate=math.radians(90.0),
                      temperature=PiecewiseLinear([0.0, 600.0], [293.15, 303.15]))
    rec = parts.simulate_part(part, env, fs=10.0, rng=np.random.default_rng(1))
    assert rec.metadata["model_kind"] == "physics" and "FOG2DUnit" in rec.metadata["device_model"]
    assert _closes(rec)
    shupe = np.degrees(rec["truth/nonreciprocal"]) * 3600
    assert np.sqrt(np.mean(shupe**2)) > 0.01  # deg/h: the coil's own drift in the ramp
    spec = parts.physics_spec(part.datasheet)
    alpha_d = rec.metadata["diameter_tempco_per_K"]  # the drawn coil's (its winding spread)
    nominal = coil_diameter_tempco(Coil2D(spec=spec.coil))
    assert abs(alpha_d / nominal - 1) < 0.1
    assert rec.metadata["wavelength_tempco_per_K"] == spec.wavelength_tempco
    t_sf = spec.scale_factor_ref_temperature
    e_k = rec["truth/scale_factor_error"] / rec["truth/true_rate"]
    first = 2 * alpha_d * (rec["truth/coil_mean_temperature"] - t_sf) - spec.wavelength_tempco * (
        rec["truth/housing_temperature"] - t_sf)
    late = rec.time > 300
    assert np.max(np.abs(e_k[late])) > 1e-6
    # second-order terms (alpha dT)^2 ~ 1e-9 and the loop's own terms: 1e-3 of the law's size
    assert np.max(np.abs(e_k[late] - first[late])) < 1e-3 * np.max(np.abs(first[late]))


def test_rlg_sheet_tempco_reaches_the_cavity_coefficient():
    """An RLG sheet's bias tempco is the cavity coefficient: warmed up at 25 degC, then held 10 K above
    until the cavity has followed (20 000 s, 22 cavity time constants), the thermal bias moves by the
    sheet's 0.01 deg/h/K x 10 K (the unit's own self-heating, drawn with its spread, cancels)."""
    import dataclasses

    d = parts.get("hg9900").datasheet
    mine = parts.Part(dataclasses.replace(d, name="rlg-tc", bias_tempco=0.01))
    rec = parts.simulate_part(mine, _chamber(40000.0, 20000.0, 10.0), fs=1.0, rng=np.random.default_rng(2))
    assert _closes(rec)
    cav = np.degrees(rec["truth/thermal_bias"]) * 3600  # the cavity mechanism alone, noise-free
    assert abs((np.mean(cav[-100:]) - np.mean(cav[19900:20000])) - 0.1) < 1e-4


def test_built_in_rlg_on_its_physics_has_thermal_bias_in_a_chamber():
    rec = parts.simulate_part(parts.get("hg9900"), _chamber(3600.0, 600.0, 10.0), fs=10.0,
                              rng=np.random.default_rng(3))
    assert _closes(rec)
    assert "THERMAL_BIAS_CALIBRATED" in rec.metadata["physics_mapping"]
    assert np.max(np.abs(rec["truth/thermal_bias"])) > 0


@pytest.mark.slow
def test_mems_part_on_its_physics_shifts_by_its_sheet_tempco_and_g_sensitivity():
    """bmi088 on the resonator: the slow flow's output moves by the sheet's 54 deg/h/K x 10 K between a
    25 degC and a 35 degC hold, and by its 360 deg/h/g x 2 g when 2 g is applied along the axis.

    Each hold is 10 s at 100 Hz (1 s blocks of the slow flow), the first second of each dropped;
    the noise is white at 0.014/sqrt 2 deg/s/sqrt(Hz) (one-sided 0.014), so a 9 s mean has SE
    0.0099/3 = 0.0033 deg/s = 11.9 deg/h, the difference of two 16.8 deg/h; z = 4 (6e-5)."""
    part = parts.get("bmi088")
    t = [0.0, 10.0, 10.01, 20.0, 20.01, 30.0]
    env = Environment(30.0, temperature=PiecewiseLinear(t, [T_REF, T_REF, T_REF + 10, T_REF + 10, T_REF, T_REF]),
                      specific_force=PiecewiseLinear(t, [0, 0, 0, 0, 2 * units.G0, 2 * units.G0]))
    rec = parts.simulate_part(part, env, fs=100.0, rng=np.random.default_rng(4))
    assert _closes(rec) and rec.metadata["model_kind"] == "physics"
    y = np.degrees(rec["output"]) * 3600
    tt = rec.time
    cold, hot, shaken = (np.mean(y[(tt > a + 1) & (tt < a + 10)]) for a in (0.0, 10.0, 20.0))
    se = 4 * 16.8
    assert abs((hot - cold) - 540.0) < se
    assert abs((shaken - cold) - 720.0) < se
    # the record's own thermal term says the same, noise-free, to the model's curvature over 10 K (its
    # 1/Q law and SF(T) x Omega_b are not linear: 0.4 % at +10 K; the tempco is matched at T0)
    bt = np.degrees(rec["truth/bias_temperature"]) * 3600
    assert abs(np.mean(bt[(tt > 12) & (tt < 19)]) / 540.0 - 1) < 0.01


def test_mems_mapping_reaches_the_sheet_tempcos_and_g_sensitivity():
    from gyrobench.sim.mems_resonator import g_sensitivity, low_rate_scale_factor, zero_rate_output

    d = parts.get("bmi088").datasheet
    u = parts.physics_spec(d).nominal
    t0 = u.reference_temperature
    slope = (zero_rate_output(u, t0 + 5) - zero_rate_output(u, t0 - 5)) / 10
    assert math.isclose(units.to_deg_per_h(slope), d.bias_tempco, rel_tol=2e-3)
    sf = (low_rate_scale_factor(u, t0 + 5) / low_rate_scale_factor(u, t0 - 5) - 1) / 10
    assert math.isclose(sf * 1e6, d.scale_factor_tempco, rel_tol=5e-3)
    assert math.isclose(units.to_deg_per_h(g_sensitivity(u)) * units.G0, d.g_sensitivity, rel_tol=5e-3)


# ------------------------------------------------------------------ the command line
@pytest.mark.slow
def test_simulate_device_says_which_model_ran(tmp_path, capsys):
    (tmp_path / "p.toml").write_text("duration_s = 600\nrate_dps = 90\ntemperature_c = [[0, 20], [600, 30]]\n")
    for model, needle in ((None, "model physics: gyrobench.sim.rlg statistical mode"),
                          ("budget", "model budget: gyrobench.sim.parts.PartUnit")):
        out = tmp_path / f"{model}.h5"
        argv = ["simulate", "device", "hg9900", "--profile", str(tmp_path / "p.toml"), "--fs", "10", "-o", str(out)]
        assert main(argv + ([] if model is None else ["--model", model])) == 0
        assert needle in capsys.readouterr().out
        rec = load_hdf5(out)
        assert rec.metadata["model_kind"] == (model or "physics")
        with h5py.File(out) as f:
            assert f["recordings"][rec.name]["channels/output"].attrs["unit"] == "rad/s"
        assert _closes(rec)
    # the physics model has the cavity's thermal bias; the budget, with no tempco on the sheet, has none
    phys, budget = load_hdf5(tmp_path / "None.h5"), load_hdf5(tmp_path / "budget.h5")
    assert np.max(np.abs(phys["truth/thermal_bias"])) > 0
    assert np.all(budget["truth/bias_temperature"] == 0)


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("resolution = 1e30", "resolution"),
        ("bias_tempco = -1", "bias_tempco"),
        ("range_dps = 1e9", "range_dps"),
        ("range_dps = 50\nresolution = 60", "resolution must be below range_dps"),
        ("gauss_markov_sigma = 1.0", "gauss_markov_tau"),
        ("source_kind = \"hearsay\"", "source_kind"),
    ],
)
def test_part_file_fields_are_range_checked_in_one_line(tmp_path, capsys, text, needle):
    p = tmp_path / "bad.toml"
    head = 'name = "bad"\nmanufacturer = "m"\nmodel = "b"\ntechnology = "MEMS"\ngrade = "consumer"\nsource = "s"\n'
    p.write_text(f"{head}arw = 0.5\nrange_dps = 500\n{text}\n".replace("range_dps = 500\nrange_dps", "range_dps"))
    assert main(["simulate", "device", str(p), "--duration", "10s", "-o", str(tmp_path / "x.h5")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and needle in err and "bad.toml" in err
    assert not (tmp_path / "x.h5").exists()


# ------------------------------------------------------------------ the fit-your-part loop
@pytest.mark.slow
def test_twin_save_part_loop_gives_back_its_fitted_noise(tmp_path, capsys):
    """simulate a part -> twin it with --save-part -> simulate the saved part -> fit again: the two fits'
    N, B and K agree within their stated 95 % intervals (difference within 1.96 x the root sum of the
    two standard errors, each the half-width / 1.96) at z = 2.94, a 1 % family-wise false-alarm rate over
    the three two-sided checks; the saved file is a part simulate device reads."""
    from gyrobench.analysis.allan import fit_noise

    (tmp_path / "mine.toml").write_text(
        'name = "mine"\nmanufacturer = "me"\nmodel = "M1"\ntechnology = "MEMS"\ngrade = "industrial"\n'
        'source = "my sheet"\narw = 0.1\nbias_instability_dph = 5.0\nrate_random_walk = 30.0\n')
    # each term dominates a stretch of the 4 h curve: N below 3 s, B 3-130 s, K above
    rec1 = tmp_path / "rec1.h5"
    assert main(["simulate", "device", str(tmp_path / "mine.toml"), "--model", "budget", "--duration", "4h",
                 "--fs", "10", "--seed", "1", "-o", str(rec1), "-q"]) == 0
    saved = tmp_path / "fitted.toml"
    rc = main(["twin", str(rec1), "--column", "output", "-o", str(tmp_path / "twin.h5"), "--save-part", str(saved)])
    assert rc in (0, 1)
    assert f"the part file {saved}" in capsys.readouterr().out
    text = saved.read_text()
    assert text.startswith("# written by gyrobench twin") and 'default_model = "budget"' in text
    rec2 = tmp_path / "rec2.h5"
    assert main(["simulate", "device", str(saved), "--duration", "4h", "--seed", "2", "-o", str(rec2), "-q"]) == 0
    out2 = load_hdf5(rec2)
    assert out2.metadata["model_kind"] == "budget" and out2.fs == 10.0
    f1 = fit_noise(load_hdf5(rec1)["output"], 10.0, terms=("Q", "N", "B", "K"))
    f2 = fit_noise(out2["output"], 10.0, terms=("Q", "N", "B", "K"))
    for key in ("N", "B", "K"):
        a, b = f1.coefficients[key], f2.coefficients[key]
        assert a.identifiable and b.identifiable, key
        se = math.hypot(a.ci95[1] - a.ci95[0], b.ci95[1] - b.ci95[0]) / (2 * 1.96)
        assert abs(a.value - b.value) <= 2.94 * se, (key, a.value, b.value, se)
