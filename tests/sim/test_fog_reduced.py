"""Reduced (output-rate) closed-loop FOG against the full loop and the closed forms."""

import math

import numpy as np
import pytest
from scipy import stats

from gyrobench.base import units
from gyrobench.sim.earth import sensed_earth_rate
from gyrobench.sim.fiber_strain import StrainMode
from gyrobench.sim.fog_loop import ClosedLoopFOG, LoopSpec, loop_average, run_loop
from gyrobench.sim.fog_optics import OpticalBudget
from gyrobench.sim.sensor import Environment
from gyrobench.sim.shaker import FixedSine

ALPHA = 1e-6  # false-alarm rate of every statistical bound below
Z = stats.norm.isf(ALPHA / 2)  # two-sided normal quantile (5.33)


def _chi2_bounds(dof: float) -> tuple[float, float]:
    return stats.chi2.ppf(ALPHA / 2, dof) / dof, stats.chi2.isf(ALPHA / 2, dof) / dof


def test_reduced_arw_matches_optical_budget(rng):
    unit = ClosedLoopFOG(modes=())
    fs, dur = 400.0, 900.0
    rec = unit.simulate(Environment(dur), fs=fs, rng=rng)
    noise = rec["output"] - rec["truth/true_rate"]
    np.testing.assert_allclose(noise, rec["truth/optical_noise"], rtol=0, atol=1e-20)
    # 1 s angle increments: var = N^2 * 1 s (1 - c/(400 M)), c/(400 M) ~ 4e-5 (neglected)
    ang = noise.reshape(-1, 400).sum(axis=1) / fs
    n2_hat = float(np.mean(ang**2))  # zero-mean: dof = number of blocks
    lo, hi = _chi2_bounds(len(ang))
    assert lo < n2_hat / unit.arw**2 < hi


def test_full_loop_block_noise_matches_ma1_form(rng):
    # few transits per sample so the loop's correction c is large: var s^2 (M - c), lag-1 s^2 c/2
    spec = LoopSpec(gain_loop=False)
    optics = OpticalBudget()
    m, n_out = 16, 40000  # the loop's memory (~1/g = 10 transits) exceeds M
    run = run_loop(spec, np.zeros(m * n_out), samples_per_output=m, optics=optics, rng=rng)
    tau = spec.transit_time
    s2 = spec.noise_phase_psd(optics) / (2 * tau) * (tau / spec.scale_factor) ** 2
    ang = run.rate[10:] / run.fs
    v, cv = spec.block_noise_moments(m)
    var_th, cov_th = s2 * v, s2 * cv
    # the reduced form's MA(1) (M - c, c/2) is the large-M limit of these exact moments
    c = spec.block_noise_correction()
    v512, c512 = spec.block_noise_moments(512)
    assert abs(v512 - (512 - c)) < 1e-9 * 512 and abs(c512 - c / 2) < 1e-9 * c
    rho = cov_th / var_th
    var_hat = float(np.mean(ang**2))
    # variance of the sample second moment of an MA(1): (2/n) var^2 (1 + 2 rho^2)
    sd = math.sqrt(2 * (1 + 2 * rho**2) / len(ang))
    assert abs(var_hat / var_th - 1) < Z * sd
    cov_hat = float(np.mean(ang[1:] * ang[:-1]))
    # sd of the lag-1 product mean of an MA(1) (lags up to 2 correlated): sqrt((1 + 3 rho^2)/n) var
    sd_c = math.sqrt((1 + 3 * rho**2) / len(ang)) * var_th
    assert abs(cov_hat - cov_th) < Z * sd_c
    assert cov_th > 10 * sd_c  # the test resolves the correlation


def test_doubling_source_power_of_shot_limited_budget_lowers_arw_by_sqrt2(rng):
    # shot-limited: RIN/shot = i_b/(q dnu) ~ 2e-3 (polarised RIN 2/dnu), thermal/shot ~ 1e-3
    base = OpticalBudget(
        source_power=10e-3,
        spectral_width=100e-9,
        loss_db=60.0,
        feedback_resistance=1e10,
        amplifier_current_noise=0.0,
    )
    spec = LoopSpec(gain_loop=False)
    psd = base.phase_psd(spec.bias_phase, spec.wavelength)
    assert psd["rin"] < 3e-3 * psd["shot"] and psd["thermal"] < 2e-3 * psd["shot"]
    m, n_out = 64, 8000
    r1, r2 = rng.spawn(2)
    out = []
    for p, r in ((base.source_power, r1), (2 * base.source_power, r2)):
        from dataclasses import replace

        run = run_loop(
            spec,
            np.zeros(m * n_out),
            samples_per_output=m,
            optics=replace(base, source_power=p),
            rng=r,
        )
        out.append(float(np.mean(run.rate[10:] ** 2)))
    ratio = math.sqrt(out[1] / out[0])
    # F bound on the variance ratio with the MA(1) effective dof n/(1 + 2 rho^2)
    v, cv = spec.block_noise_moments(m)
    rho = cv / v
    dof = (n_out - 10) / (1 + 2 * rho**2)
    lo, hi = stats.f.ppf(ALPHA / 2, dof, dof), stats.f.isf(ALPHA / 2, dof, dof)
    assert lo < (ratio * math.sqrt(2)) ** 2 < hi
    assert hi < 1.2  # resolves sqrt(2) (a factor 2 in variance)


def test_reduced_loop_average_matches_full_loop(rng):
    spec = LoopSpec(gain_loop=False)
    m = 512
    fs = 1 / (m * spec.transit_time)
    n_out = 200
    k_phys = 16  # physics Nyquist 3.2 kHz above every test tone
    for f_req in (37.0, 500.0, 2000.0):
        f = round(f_req * n_out / fs) * fs / n_out  # whole cycles in the record
        amp = 1e-3  # rad/s
        t_phys = np.arange(n_out * k_phys) / (k_phys * fs)
        x = amp * np.sin(2 * np.pi * f * t_phys)
        red = loop_average(np.fft.rfft(x), len(x), k_phys * fs, fs, spec)
        k = np.arange(n_out * m)
        phase = spec.scale_factor * amp * np.sin(2 * np.pi * f * (k + 0.5) * spec.transit_time)
        full = run_loop(spec, phase, samples_per_output=m).rate
        # midpoint rule O((w tau)^2/24) (twice) plus 1e-6 of float/transient slack; the start
        # transient (loop at rest while the tone runs) is over within 2 blocks
        tol = amp * (1e-6 + (2 * np.pi * f * spec.transit_time) ** 2 / 24 * 2)
        np.testing.assert_allclose(full[2:], red[2:], rtol=0, atol=tol)


def test_strain_tone_follows_closed_form(rng):
    mode = StrainMode(frequency=300.0, quality=30.0, strain=3e-12, weight=500.0)
    unit = ClosedLoopFOG(modes=(mode,))
    fs, kp, dur = 400.0, 8, 20.0
    a0 = units.g(2.0)
    k = unit.strain_coefficient()
    for f in (1.0, 37.5, 150.0, 300.0, 500.0):
        sh = FixedSine(frequency=f, duration=dur, acceleration=a0).sample(kp * fs, rng=rng)
        rec = unit.simulate(Environment(dur, vibration=sh), fs=fs, rng=rng)
        y = rec["truth/strain_nonreciprocity"]
        w = 2 * np.pi * f
        cf = k * mode.strain * mode.weight * w * a0 * abs(mode.response(f)[()])
        cf *= abs(unit.loop.transfer(f)) * abs(np.sinc(f / fs))
        fa = abs(f - fs * round(f / fs))  # alias of the block-centre samples
        t = rec.time + 0.5 / fs
        if fa == 0:
            continue
        basis = np.column_stack([np.sin(2 * np.pi * fa * t), np.cos(2 * np.pi * fa * t)])
        c, *_ = np.linalg.lstsq(basis, y, rcond=None)
        assert abs(math.hypot(*c) / cf - 1) < 1e-9, f


def test_one_hz_two_g_error_below_0p1_deg_h(rng):
    unit = ClosedLoopFOG()
    sh = FixedSine(frequency=1.0, duration=20.0, acceleration=units.g(2.0)).sample(3200.0, rng=rng)
    rec = unit.simulate(Environment(20.0, vibration=sh), fs=400.0, rng=rng)
    err = rec["truth/strain_nonreciprocity"] + rec["truth/rectification"] + rec["truth/loop_error"]
    assert units.to_deg_per_h(np.max(np.abs(err))) < 0.1
    # nothing else: output - true rate - optical noise is that error
    rest = rec["output"] - rec["truth/true_rate"] - rec["truth/optical_noise"] - err
    assert np.max(np.abs(rest)) < 1e-18


def test_earth_rate_and_scale_factor_tempco(rng):
    unit = ClosedLoopFOG(modes=(), optics=OpticalBudget(source_power=1e3))  # near noise-free
    assert unit.earth_rate == float(sensed_earth_rate(unit.latitude))
    om = units.deg_per_s(10.0)
    tc = lambda t: unit.reference_temperature + 0.01 * t  # noqa: E731
    rec = unit._record(100.0, 100.0, rng=rng, true_rate=om, coil_temperature=tc)
    true = om + unit.earth_rate
    np.testing.assert_allclose(rec["truth/true_rate"], true, rtol=1e-15)
    expected = true * unit.scale_factor_ratio(tc(rec.time + 0.005), unit.reference_temperature)
    np.testing.assert_allclose(rec["output"] - rec["truth/optical_noise"], expected, rtol=1e-14)
    # (1/SF) dSF/dT = 2 alpha_D - alpha_lambda
    dT = 1e-3
    d_coil = (
        unit.scale_factor_ratio(unit.reference_temperature + dT, unit.reference_temperature) - 1
    ) / dT
    d_src = (
        unit.scale_factor_ratio(unit.reference_temperature, unit.reference_temperature + dT) - 1
    ) / dT
    assert abs(d_coil + d_src - unit.scale_factor_tempco) < 1e-3 * unit.scale_factor_tempco


def test_bad_inputs():
    with pytest.raises(ValueError, match="even integer multiple"):
        unit = ClosedLoopFOG()
        sh = FixedSine(frequency=10.0, duration=1.0, acceleration=1.0).sample(
            1000.0, rng=np.random.default_rng(0)
        )
        unit.simulate(Environment(1.0, vibration=sh), fs=400.0, rng=np.random.default_rng(0))
    with pytest.raises(TypeError, match="rng must be"):
        ClosedLoopFOG().simulate(Environment(1.0), fs=400.0, rng=None)


def test_rectification_matches_full_loop_with_loss_modulation():
    # intensity-phase correlation (docs/physics.md 4.1): the full nonlinear loop with a loss
    # modulation m(t) against the reduced form's +m phi_res/SF through H and the decimation
    spec = LoopSpec(gain_loop=False)
    m, n_out, kp = 512, 400, 16
    fs = 1 / (m * spec.transit_time)
    f = round(500 * n_out / fs) * fs / n_out
    om0, m0, th = 0.05, 1e-2, 0.3
    tk = (np.arange(n_out * m) + 0.5) * spec.transit_time
    ph = spec.scale_factor * om0 * np.sin(2 * np.pi * f * tk)
    mk = m0 * np.cos(2 * np.pi * f * tk + th)
    full = run_loop(spec, ph, samples_per_output=m, intensity=mk).rate
    full0 = run_loop(spec, ph, samples_per_output=m).rate
    tp = np.arange(n_out * kp) / (kp * fs)
    fr = np.fft.rfftfreq(len(tp), 1 / (kp * fs))
    h = spec.transfer(fr)
    u = om0 * np.sin(2 * np.pi * f * tp)
    phi_res = spec.scale_factor * np.fft.irfft((1 - h) * np.fft.rfft(u), len(tp))
    mm = m0 * np.cos(2 * np.pi * f * tp + th)
    rect = loop_average(np.fft.rfft(mm * phi_res / spec.scale_factor), len(tp), kp * fs, fs, spec)
    hf = complex(spec.transfer(f))
    closed = np.real(m0 * np.exp(1j * th) * np.conj(spec.scale_factor * om0 * (1 - hf) * -1j))
    closed /= 2 * spec.scale_factor
    x_res = spec.scale_factor * om0 * abs(1 - hf)
    tol = m0 + x_res**2 / 6  # neglected orders: m^2 x_res and the sin curvature
    # FFT chain vs closed form: whole cycles of f and 2f in the record, so the mean is exact
    assert abs(rect.mean() / closed - 1) < 1e-9
    assert abs((full - full0)[2:].mean() / closed - 1) < tol
    assert np.max(np.abs((full - full0)[2:] - rect[2:])) < tol * np.max(np.abs(rect))


def test_vibration_span_equals_whole_record_transform(rng):
    # the reduced form transforms only the moving span plus a ring-down margin
    from gyrobench.sim.shaker import Phased

    unit = ClosedLoopFOG()
    fs, kp = 400.0, 8
    ph = Phased(
        vibration=FixedSine(frequency=290.0, duration=3.0, acceleration=units.g(2.0)),
        static_before=4.0,
        static_after=6.0,
    )
    sh = ph.sample(kp * fs, rng=rng)
    rec = unit.simulate(Environment(ph.duration, vibration=sh), fs=fs, rng=rng)
    f = np.fft.rfftfreq(len(sh.acceleration), 1 / sh.fs)
    big_a = np.fft.rfft(sh.acceleration)
    whole = loop_average(
        unit.vibration_spectra(f)["strain"] * big_a, len(big_a) * 2 - 2, sh.fs, fs, unit.loop
    )
    y = rec["truth/strain_nonreciprocity"]
    assert np.max(np.abs(y - whole)) < 1e-9 * np.max(np.abs(whole))
    assert np.all(y[: int(3.0 * fs)] == 0.0)  # before the span (4 s - 0.96 s margin): no term


def test_truth_parts_sum_to_the_output(rng):
    from gyrobench.sim.noise import NoiseModel

    unit = ClosedLoopFOG(
        noise=NoiseModel.from_datasheet(bias_instability=0.003, rate_random_walk=0.0005, bias=0.05)
    )
    sh = FixedSine(frequency=290.0, duration=5.0, acceleration=units.g(2.0)).sample(3200.0, rng=rng)
    rec = unit.simulate(Environment(5.0, true_rate=0.01, vibration=sh), fs=400.0, rng=rng)
    parts = [
        "true_rate",
        "scale_factor_error",
        "loop_error",
        "strain_nonreciprocity",
        "rectification",
        "optical_noise",
        "ieee_noise",
    ]
    total = sum(rec[f"truth/{p}"] for p in parts)
    np.testing.assert_allclose(rec["output"], total, rtol=0, atol=1e-15)
    ieee = sum(rec[f"detail/ieee_{k}"] for k in ("bias_instability", "rate_random_walk", "bias"))
    np.testing.assert_allclose(rec["truth/ieee_noise"], ieee, rtol=0, atol=1e-18)
    np.testing.assert_allclose(
        rec["truth/true_rate"],
        rec["detail/table_rate"] + rec["detail/earth_rate"] + rec["detail/rocking_rate"],
        rtol=0,
        atol=1e-18,
    )
    assert np.all(rec["vibration_frequency"] == 290.0)


def test_integrate_and_dump_has_no_dc_error_at_multiples_of_the_output_rate(rng):
    # docs/physics.md 4.1: a rate tone at exactly m f_o integrates to zero in every block
    mode = StrainMode(frequency=900.0, quality=10.0, rocking=1e-8)
    unit = ClosedLoopFOG(modes=(mode,))
    fs = 400.0
    sh = FixedSine(frequency=2 * fs, duration=5.0, acceleration=units.g(2.0)).sample(
        8 * fs, rng=rng
    )
    rec = unit.simulate(Environment(5.0, vibration=sh), fs=fs, rng=rng)
    peak = mode.rocking * 2 * np.pi * 2 * fs * units.g(2.0) * abs(mode.response(2 * fs)[()])
    assert np.max(np.abs(rec["detail/rocking_rate"])) < 1e-9 * peak
    assert np.max(np.abs(rec["truth/loop_error"])) < 1e-9 * peak
