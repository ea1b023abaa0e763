"""The 'gyrobench parts' and 'gyrobench simulate device' verbs: files with the one truth layout, one-line errors."""

from __future__ import annotations

import math

import h5py
import numpy as np
import pytest

from gyrobench.io.recording import load_hdf5
from gyrobench.scenarios.cli.main import main
from gyrobench.sim import parts

# every test runs among planted user files and fails if one changes (tests/conftest.py)
pytestmark = pytest.mark.usefixtures("user_files")

EPS = np.finfo(float).eps


def test_parts_lists_every_part_with_its_source(capsys):
    assert main(["parts"]) == 0
    text = capsys.readouterr().out
    for d in parts.datasheets():
        assert f"{d.name}: {d.manufacturer} {d.model}" in text
        assert d.source in text


def _sum_residual(rec) -> tuple[float, float]:
    out, true = rec["output"], rec["truth/true_rate"]
    comps = [rec["truth/" + k] for k in rec.metadata["error_components"]]
    scale = max(np.max(np.abs(a)) for a in (out, true, *comps))
    return float(np.max(np.abs(out - true - np.sum(comps, axis=0)))), 16 * (len(comps) + 2) * EPS * scale


def test_simulate_device_from_csv_profiles_to_hdf5(tmp_path, capsys):
    (tmp_path / "rate.csv").write_text("time [s],rate [deg/s]\n0,0\n50,10\n100,-10\n")
    (tmp_path / "temp.csv").write_text("time [s],temperature [degC]\n0,20\n100,40\n")
    out = tmp_path / "stim.h5"
    rc = main(["simulate", "device", "stim300", "--rate-csv", str(tmp_path / "rate.csv"), "--temperature-csv",
               str(tmp_path / "temp.csv"), "--fs", "10", "--seed", "3", "-o", str(out), "-q", "--model", "budget"])
    assert rc == 0
    rec = load_hdf5(out)
    assert rec.n_samples == 1000 and rec.fs == 10.0
    # the rate CSV reaches the truth: linear between the rows, at the sample centres
    t = rec.time
    expect = np.radians(np.interp(t, [0, 50, 100], [0, 10, -10]))
    assert np.allclose(rec["truth/true_rate"], expect, rtol=0, atol=1e-12)
    assert np.allclose(rec["inputs/temperature"], np.interp(t, [0, 100], [293.15, 313.15]), atol=1e-9)
    resid, tol = _sum_residual(rec)
    assert resid <= tol
    with h5py.File(out) as f:  # units as attributes, readable without gyrobench
        grp = f["recordings"][rec.name]
        assert grp["channels/output"].attrs["unit"] == "rad/s"
        for k in ("true_rate", *parts.ERROR_COMPONENTS):
            assert grp["truth"][k].attrs["unit"] == "rad/s"
            assert np.array_equal(grp["truth"][k][()], rec["truth/" + k])


def test_simulate_device_profile_toml_to_csv(tmp_path):
    (tmp_path / "p.toml").write_text(
        "duration_s = 60\nrate_dps = [[0, 0], [30, 5], [60, 5]]\ntemperature_c = 30\nspecific_force_g = 1\n")
    out = tmp_path / "m.csv"
    assert main(["simulate", "device", "mti-1", "--profile", str(tmp_path / "p.toml"), "--fs", "50",
                 "-o", str(out), "-q", "--model", "budget"]) == 0
    data = np.loadtxt(out, delimiter=",", skiprows=2)
    header = out.read_text().splitlines()[1].split(",")
    col = {h.split(" [")[0]: i for i, h in enumerate(header)}
    err = data[:, col["output"]] - data[:, col["truth/true_rate"]]
    comps = sum(data[:, col["truth/" + k]] for k in parts.ERROR_COMPONENTS)
    # CSV holds %.17g: the identity survives to float64 rounding
    assert np.max(np.abs(err - comps)) <= 64 * EPS * np.max(np.abs(data[:, 1:10]))
    assert np.allclose(data[:, col["inputs/specific_force"]], 9.80665)
    g = parts.get("mti-1").datasheet.g_sensitivity
    assert g is None and np.all(data[:, col["truth/g_sensitivity"]] == 0)  # the sheet gives none
    assert math.isclose(data[-1, col["truth/true_rate"]], math.radians(5.0), rel_tol=1e-12)


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["simulate", "device", "nope", "--duration", "10s", "-o", "x.h5"], "unknown part 'nope'"),
        (["simulate", "device", "stim300", "-o", "x.h5"], "needs --duration"),
        (["simulate", "device", "stim300", "--duration", "10s", "-o", "x.txt"], "-o must end in"),
        (["simulate", "device", "stim300", "--duration", "10s", "--N", "1", "-o", "x.h5"], "--N apply to"),
        (["simulate", "noise", "extra", "--duration", "10s", "-o", "x.h5"], "second positional"),
        (["simulate", "noise", "--profile", "p.toml", "--duration", "10s", "-o", "x.h5"], "--profile apply to"),
        (["simulate", "device", "stim300", "--rate-csv", "missing.csv", "-o", "x.h5"], "does not exist"),
    ],
)
def test_simulate_device_bad_input_is_one_line_exit_2(argv, needle, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert needle in err and "\n" not in err, err


def test_parts_names_each_part_s_physics_solve_or_why_not(capsys):
    # one 'physics model:' line per part: the solved parameters (every built-in part maps)
    assert main(["parts"]) == 0
    lines = [ln for ln in capsys.readouterr().out.splitlines() if ln.strip().startswith("physics model:")]
    assert len(lines) == len(parts.names())
    text = "\n".join(lines)
    assert "fog_spec: source power" in text and "mems_spec: pick-off noise" in text and "rlg_spec: lock-in" in text
    assert "fog_spec: coil L" in text and "mems_spec: proof mass" in text and "not mapped" not in text
    # a second solved parameter is an assumed design, and the line says so
    assert all("ASSUMED design" in ln for ln in lines if "fog_spec: coil L" in ln)
    assert all("ASSUMED split" in ln for ln in lines if "mems_spec: proof mass" in ln)


# ------------------------------------------------------------------ profile [earth] and [shaker] tables
def _device(tmp_path, part: str, profile: str, *extra: str):
    (tmp_path / "p.toml").write_text(profile)
    out = tmp_path / "r.h5"
    # the datasheet budget: these tests read its terms (the physics model's are in test_parts_physics)
    rc = main(["simulate", "device", part, "--profile", str(tmp_path / "p.toml"), "-o", str(out), "-q",
               "--model", "budget", *extra])
    return rc, out


@pytest.mark.parametrize(
    ("table", "expect"),
    [
        # closed forms of the sensed Earth rate (sim/earth.py): horizontal north Omega cos(lat),
        # vertical up Omega sin(lat), horizontal east 0
        ("latitude_deg = 45.8", lambda lat: math.cos(lat)),
        ("latitude_deg = 45.8\nheading_deg = 90", lambda lat: 0.0),
        ("latitude_deg = -30\nelevation_deg = 90", lambda lat: math.sin(lat)),
    ],
)
def test_profile_earth_rate_is_added_to_the_table_rate(tmp_path, table, expect):
    from gyrobench.sim.earth import EARTH_RATE

    lat = math.radians(float(table.split("\n")[0].split("=")[1]))
    rc, out = _device(tmp_path, "hg1700", f"duration_s = 10\nrate_dps = [[0, 0], [10, 1]]\n[earth]\n{table}\n",
                      "--fs", "10")
    assert rc == 0
    rec = load_hdf5(out)
    earth = EARTH_RATE * expect(lat)
    table_rate = np.radians(rec.time / 10.0)
    assert np.allclose(rec["truth/true_rate"], table_rate + earth, rtol=0, atol=1e-15)
    assert rec.metadata["profile"]["earth_rate_rad_s"] == pytest.approx(earth, rel=1e-12, abs=1e-20)
    resid, tol = _sum_residual(rec)
    assert resid <= tol


def test_profile_shaker_sine_is_placed_in_its_window_on_top_of_the_static_force(tmp_path):
    # 5 Hz at 100 Hz output: 4 f_max <= fs, one shaker sample per output sample (m = 1), so the
    # record holds 1 g + a sin(2 pi f j/fs) from sample round(start fs) for duration fs samples
    from gyrobench.base.units import G0

    rc, out = _device(tmp_path, "stim300", "duration_s = 10\nspecific_force_g = 1\n[shaker]\nkind = \"sine\"\n"
                      "start_s = 2\nduration_s = 4\nfrequency_hz = 5\nacceleration_g = 0.5\n", "--fs", "100")
    assert rc == 0
    rec = load_hdf5(out)
    f = rec["inputs/specific_force"]
    j = np.arange(400)
    assert np.allclose(f[200:600], G0 + 0.5 * G0 * np.sin(2 * np.pi * 5 * j / 100), rtol=0, atol=1e-12)
    assert np.all(f[:200] == G0) and np.all(f[600:] == G0)
    # stim300's sheet g-sensitivity (1 deg/h/g) turns it into its error term
    assert np.allclose(rec["truth/g_sensitivity"], math.radians(1 / 3600) / G0 * f, rtol=1e-12, atol=0)
    resid, tol = _sum_residual(rec)
    assert resid <= tol
    assert rec.metadata["profile"]["shaker"]["kind"] == "FixedSine"


def test_profile_shaker_above_the_output_rate_is_averaged_over_each_interval_not_aliased(tmp_path):
    # Random vibration, flat G = 0.04 g^2/Hz on [200, 400] Hz (grms = 2.83 g), at a 50 Hz output. Each
    # output sample is the mean of m = ceil(4 x 400/50) = 32 shaker samples, whose gain at f is the m-point
    # moving average's |H(f)| = |sin(pi f/fs) / (m sin(pi f/(m fs)))| (0 at multiples of fs: no mean), so the
    # record's rms is sigma = g0 sqrt(Int_200^400 G |H(f)|^2 df) = 0.118 g = 0.042 grms; a point sampler
    # would fold the full grms into the band (23.9 sigma).
    # Spread: the record's variance over T = 60 s estimates sigma^2 with normalised variance <= 1/(B_s T)
    # (Bendat & Piersol, Random Data, 4th ed., ch. 8: the random error of a mean-square estimate; equality
    # for Gaussian lines, while the synthesis's lines of fixed amplitude and random phase only lower it:
    # exactly, nu = 2332 here), B_s = (Int P df)^2 / Int P^2 df the statistical bandwidth of the folded output
    # PSD P on [0, fs/2] (each output frequency fo collects the band's lines at j fs +- fo). So
    # sigma_hat^2/sigma^2 ~ chi2_nu/nu with nu = 2 B_s T = 2005 (B_s = 16.7 Hz of the 25 Hz band; removing
    # the sample mean costs 1 of them), and at a false-alarm rate of 1e-6 two-sided sigma_hat/sigma lies in
    # [0.924, 1.078]. The former bound, std < 0.2 grms (= 4.8 sigma), could not see a factor sqrt(2) in
    # grms; this one can (asserted below; checked by hand: A_k = sqrt(G df) or sqrt(4 G df) fail).
    from scipy import stats

    from gyrobench.base.units import G0
    from gyrobench.sim.shaker import OVERSAMPLING, grms

    psd = [[200, 0.04], [400, 0.04]]
    fs, t_rec, g_psd = 50.0, 60.0, 0.04
    m = math.ceil(OVERSAMPLING * 400 / fs)

    def band_power(f):  # G0^2 G(f) |H(f)|^2 [(m/s^2)^2/Hz], 0 outside the band
        x = np.pi * f / fs
        inside = (f >= 200) & (f <= 400)
        return np.where(inside, G0**2 * g_psd * (np.sin(x) / (m * np.sin(x / m))) ** 2, 0.0)

    f = np.linspace(200, 400, 400_001)
    sigma = math.sqrt(np.trapezoid(band_power(f), f))
    fo = np.linspace(0, fs / 2, 50_001)
    folded = sum(band_power(j * fs + s * fo) for j in range(1, 9) for s in (-1, 1))
    b_s = np.trapezoid(folded, fo) ** 2 / np.trapezoid(folded**2, fo)
    nu = 2 * b_s * t_rec
    lo, hi = np.sqrt(stats.chi2.ppf([0.5e-6, 1 - 0.5e-6], nu) / nu)
    assert math.isclose(np.trapezoid(folded, fo), sigma**2, rel_tol=1e-6)  # folding keeps the power
    assert hi < math.sqrt(2) and lo > 1 / math.sqrt(2)  # the test can see a factor sqrt(2) in grms
    assert grms(psd) * G0 > 20 * hi * sigma  # ... and a point sampler

    rc, out = _device(tmp_path, "stim300", f"duration_s = 60\n[shaker]\nkind = \"random\"\nduration_s = 60\n"
                      f"psd = {psd}\n", "--fs", "50")
    assert rc == 0
    force = load_hdf5(out)["inputs/specific_force"]
    assert lo * sigma <= np.std(force) <= hi * sigma, (np.std(force) / sigma, lo, hi)


def test_profile_shaker_draws_from_its_own_stream(tmp_path):
    # the part's noise is the same with and without a shaker (one child stream per effect), and a
    # sweep's random draw (here none: an ideal controller) does not move it
    base = "duration_s = 20\n"
    shaker = "[shaker]\nkind = \"sweep\"\nduration_s = 10\nf_start_hz = 1\nf_end_hz = 20\nacceleration_g = 2\n"
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    rc_a, out_a = _device(tmp_path / "a", "stim300", base, "--fs", "100", "--seed", "7")
    rc_b, out_b = _device(tmp_path / "b", "stim300", base + shaker, "--fs", "100", "--seed", "7")
    assert rc_a == rc_b == 0
    a, b = load_hdf5(out_a), load_hdf5(out_b)
    assert np.array_equal(a["truth/ieee_noise"], b["truth/ieee_noise"])
    assert np.any(b["inputs/specific_force"] != 0) and np.all(a["inputs/specific_force"] == 0)


def test_profile_shaker_is_the_python_api_s_interval_mean_acceleration(tmp_path):
    # the CLI only parses [shaker]: its specific force is the static part plus
    # sim.shaker.interval_mean_acceleration drawn from the seed's first child stream, bit for bit
    from gyrobench.base.units import G0
    from gyrobench.sim.shaker import RandomVibration, interval_mean_acceleration

    rc, out = _device(tmp_path, "stim300", "duration_s = 30\nspecific_force_g = 1\n[shaker]\nkind = \"random\"\n"
                      "start_s = 3\nduration_s = 25\nmax_displacement_mm = 3\n"
                      "psd = [[20, 0.01], [80, 0.04], [350, 0.04], [2000, 0.007]]\n", "--fs", "333", "--seed", "11")
    assert rc == 0
    vib = RandomVibration(breakpoints=((20, 0.01), (80, 0.04), (350, 0.04), (2000, 0.007)), duration=25.0,
                          max_displacement=3e-3)
    rng = np.random.default_rng(np.random.SeedSequence(11).spawn(1)[0])
    expect = G0 + interval_mean_acceleration(vib, duration=30.0, fs=333.0, start=3.0, rng=rng)
    assert np.array_equal(load_hdf5(out)["inputs/specific_force"], expect)


@pytest.mark.parametrize(
    ("profile", "needle"),
    [
        ("duration_s = 10\nearth = 3\n", "earth must be a table [earth]; got 3"),
        ("duration_s = 10\n[earth]\nlat = 40\n", "[earth] unknown key(s) ['lat']"),
        ("duration_s = 10\n[earth]\nheading_deg = 0\n", "[earth] needs latitude_deg [deg]"),
        ("duration_s = 10\n[earth]\nlatitude_deg = 95\n", "earth.latitude_deg must be in [-90, 90] deg; got 95"),
        ("duration_s = 10\n[earth]\nlatitude_deg = 40\nheading_deg = 'n'\n",
         "earth.heading_deg must be a finite number [deg]; got 'n'"),
        ("duration_s = 'x'\n", "profile.duration_s must be a finite number [s]; got 'x'"),
        ("duration_s = 10\n[shaker]\nkind = 'bump'\n", "shaker.kind must be one of ['random', 'sine', 'sweep']"),
        ("duration_s = 10\n[shaker]\nkind = 'sine'\nduration_s = 5\nacceleration_g = 1\n",
         "[shaker] needs frequency_hz [Hz]"),
        ("duration_s = 10\n[shaker]\nkind = 'sine'\nduration_s = 5\nacceleration_g = 1\nfrequency_hz = -1\n",
         "shaker.frequency_hz must be > 0 Hz; got -1"),
        ("duration_s = 10\n[shaker]\nkind = 'sine'\nduration_s = 5\nacceleration_g = 1\nfrequency_hz = 5\n"
         "psd = [[1, 1], [2, 1]]\n", "[shaker] unknown key(s) ['psd']"),
        ("duration_s = 10\n[shaker]\nkind = 'sine'\nduration_s = 5\nacceleration_g = 1\nfrequency_hz = 5\n"
         "ramp_s = 3\n", "shaker.ramp_s must be in [0, 2.5] s; got 3"),
        ("duration_s = 10\n[shaker]\nkind = 'sweep'\nduration_s = 5\nacceleration_g = 1\nf_start_hz = 1\n"
         "f_end_hz = 9\nspacing = 'cubic'\n", "shaker.spacing must be 'log' or 'linear'; got 'cubic'"),
        ("duration_s = 10\n[shaker]\nkind = 'random'\nduration_s = 5\npsd = [[20]]\n",
         "shaker.psd must be >= 2 [frequency_hz, g^2/Hz] pairs"),
        ("duration_s = 10\n[shaker]\nkind = 'random'\nduration_s = 5\npsd = [[80, 0.01], [20, 0.01]]\n",
         "[shaker] RandomVibration.breakpoints must have frequencies > 0 Hz, strictly increasing; got [80.0, 20.0]"),
        ("duration_s = 10\n[shaker]\nkind = 'sine'\nstart_s = 8\nduration_s = 5\nacceleration_g = 1\n"
         "frequency_hz = 5\n", "shaker.start_s + shaker.duration_s = 13 s must lie inside the record (0, 10] s"),
        # start_s x fs overflows: once the generic "a value is too large to compute with" from round(inf)
        ("duration_s = 10\n[shaker]\nkind = 'sine'\nstart_s = 1e308\nduration_s = 5\nacceleration_g = 1\n"
         "frequency_hz = 5\n", "shaker.start_s + shaker.duration_s = 1e+308 s must lie inside the record (0, 10] s"),
        ("duration_s = 10\nrate_dps = [[0, 0], [0, 1]]\n",
         "rate_dps: PiecewiseLinear.times must be strictly increasing [s]; got 0.0 then 0.0 s"),
    ],
)
def test_profile_tables_refuse_bad_input_in_one_line_exit_2(tmp_path, capsys, profile, needle):
    rc, _ = _device(tmp_path, "stim300", profile, "--fs", "100")
    assert rc == 2
    err = capsys.readouterr().err.strip()
    assert needle in err and "\n" not in err and "p.toml" in err, err
