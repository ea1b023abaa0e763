"""The built-in parts' accelerometer figures: pinned to their sources, mapped to SI, and met by a static record."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import norm

from gyrobench.analysis.allan import fit_noise
from gyrobench.sim import parts
from gyrobench.sim.earth import Site
from gyrobench.sim.imu import TriadSpec
from gyrobench.sim.trajectory import Segment, SegmentedMotion

G0 = 9.80665  # m/s^2 per g: the g of the sheets' mg and ug

#: source unit -> factor to the catalogue field's unit (the field named beside it below)
_TO_FIELD = {
    "g": 1.0, "ug": 1.0, "mg": 1.0, "ppm": 1.0, "Hz": 1.0, "m/s/sqrt(h)": 1.0, "ug/sqrt(Hz)": 1.0,
    "m/s^2->g": 1.0 / G0, "m/s^2->ug": 1e6 / G0, "m/s^2->mg": 1e3 / G0, "mm/s^2->ug": 1e3 / G0,
    "mm/s^2/sqrt(Hz)->ug/sqrt(Hz)": 1e3 / G0, "mm/s/sqrt(h)->m/s/sqrt(h)": 1e-3,
    "ft/s/sqrt(h)->m/s/sqrt(h)": 0.3048, "%->ppm": 1e4,
}

#: every accelerometer figure of a built-in part as its source prints it: (field, value, unit)
SOURCES = {
    # NavToolkit ImuModel.cpp stim300_model: accel_random_walk_sigma 0.06/60 m/s^(3/2),
    # accel_bias_sigma 0.05 * 9.81/1000 m/s^2 (0.05 mg), accel_scale_factor 300 ppm
    "stim300": [("accel_vrw_m_s_sqrt_h", 0.06, "m/s/sqrt(h)"), ("accel_bias_instability_ug", 0.05 * 1000, "ug"),
                ("accel_scale_factor_repeatability_ppm", 300.0, "ppm")],
    # NavToolkit hg1700_model: 0.065 * 0.3048 / 60 (0.065 ft/s/sqrt(h)), accel_bias_sigma 9.81e-3 m/s^2 (1 mg)
    "hg1700": [("accel_vrw_m_s_sqrt_h", 0.065, "ft/s/sqrt(h)->m/s/sqrt(h)"),
               ("accel_bias_instability_ug", 1000.0, "ug")],
    # NavToolkit hg9900_model: accel_bias_sigma 25 * 9.81e-6 m/s^2 (25 ug), accel_scale_factor 100 ppm
    "hg9900": [("accel_bias_instability_ug", 25.0, "ug"), ("accel_scale_factor_repeatability_ppm", 100.0, "ppm")],
    # Aceinna docs_openrtk 300ZA/imu-sensors.rst, ACCELERATION table
    "openrtk330": [("accel_range_g", 8.0, "g"), ("accel_bias_instability_ug", 20.0, "ug"),
                   ("accel_resolution_mg", 0.5, "mg"), ("accel_scale_factor_repeatability_ppm", 0.1, "%->ppm"),
                   ("accel_vrw_m_s_sqrt_h", 0.05, "m/s/sqrt(h)"), ("accel_bandwidth_hz", 50.0, "Hz")],
    # Transactions on Aerospace Research doi:10.2478/tar-2023-0022, table of the MTi-1 characteristics
    "mti-1": [("accel_range_g", 16.0, "g"), ("accel_bias_instability_ug", 0.03 * 1000, "ug"),
              ("accel_bandwidth_hz", 324.0, "Hz"), ("accel_noise_density_ug", 120.0, "ug/sqrt(Hz)")],
    # gnss-ins-sim gnss_ins_sim/sim/imu_model.py, accel_low_accuracy (from the AHRS380SA sheet):
    # 'b_drift' 2.0e-4 m/s^2, 'vrw' 0.05 / 60 (0.05 m/s/sqrt(h))
    "ahrs380": [("accel_bias_instability_ug", 2.0e-4, "m/s^2->ug"), ("accel_vrw_m_s_sqrt_h", 0.05, "m/s/sqrt(h)")],
    # Murata SCH16T-K01 Doc.No. 11624 Rev. 2, Table 6: range +-80 m/s^2, offset +-0.14 m/s^2 at 3 sigma,
    # 3200 LSB/(m/s^2) (20-bit), noise density 0.8 (mm/s^2)/sqrt(Hz), VRW 30 (mm/s)/sqrt(h), B 0.20 mm/s^2
    "sch16t-k01": [("accel_range_g", 80.0, "m/s^2->g"), ("accel_bias_repeatability_mg", 0.14 / 3, "m/s^2->mg"),
                   ("accel_resolution_mg", 1 / 3200, "m/s^2->mg"),
                   ("accel_noise_density_ug", 0.8, "mm/s^2/sqrt(Hz)->ug/sqrt(Hz)"),
                   ("accel_vrw_m_s_sqrt_h", 30.0, "mm/s/sqrt(h)->m/s/sqrt(h)"),
                   ("accel_bias_instability_ug", 0.20, "mm/s^2->ug")],
    # ADIS16495 data sheet Rev. C, Features: "Triaxial, digital accelerometer, +-8 g", "3.2 ug in run bias stability"
    "adis16495-1": [("accel_range_g", 8.0, "g"), ("accel_bias_instability_ug", 3.2, "ug")],
    # Luxonis LSM6DSV page, 'Native silicon characteristics': +-16 g option, 0.488 mg/LSB, 60 ug/sqrt(Hz)
    "lsm6dsv": [("accel_range_g", 16.0, "g"), ("accel_resolution_mg", 0.488, "mg"),
                ("accel_noise_density_ug", 60.0, "ug/sqrt(Hz)")],
    # Bosch BST-BMI088-DS000-19, Table 4: +-3 g, 10920 LSB/g, 160 ug/sqrt(Hz) (x, y), zero-g offset 20 mg,
    # offset drift < 0.2 mg/K, sensitivity drift 0.002 %/K
    "bmi088": [("accel_range_g", 3.0, "g"), ("accel_resolution_mg", 1000.0 / 10920.0, "mg"),
               ("accel_noise_density_ug", 160.0, "ug/sqrt(Hz)"), ("accel_bias_repeatability_mg", 20.0, "mg"),
               ("accel_bias_tempco_mg_per_k", 0.2, "mg"), ("accel_scale_factor_tempco_ppm_per_k", 20.0, "ppm")],
    # TDK DS-000347 rev 1.8, Table 2: +-16 g, 2048 LSB/g, 65 ug/sqrt(Hz) (x, y), +-0.5 %, +-0.005 %/degC,
    # zero-g +-20 mg, +-0.15 mg/degC
    "icm-42688-p": [("accel_range_g", 16.0, "g"), ("accel_resolution_mg", 1000.0 / 2048.0, "mg"),
                    ("accel_noise_density_ug", 65.0, "ug/sqrt(Hz)"), ("accel_bias_repeatability_mg", 20.0, "mg"),
                    ("accel_bias_tempco_mg_per_k", 0.15, "mg"), ("accel_scale_factor_repeatability_ppm", 5000.0, "ppm"),
                    ("accel_scale_factor_tempco_ppm_per_k", 50.0, "ppm")],
    # the same document's p. 1 family table, ICM-42686-P column: 70 ug/sqrt(Hz), +-32 g
    "icm-42686-p": [("accel_range_g", 32.0, "g"), ("accel_noise_density_ug", 70.0, "ug/sqrt(Hz)")],
}

ACCEL_FIELDS = [f for f in parts.Datasheet.__dataclass_fields__ if f.startswith("accel_")]


@pytest.mark.parametrize("name", parts.names())
def test_each_accelerometer_figure_is_its_sources_printed_value(name):
    """Every ``accel_*`` figure equals the number its source prints (converted from the source's
    unit to the field's), and a figure the source does not give is left None."""
    sheet = {d.name: d for d in parts.datasheets()}[name]
    given = SOURCES.get(name, [])
    for field, value, unit in given:
        assert getattr(sheet, field) == pytest.approx(value * _TO_FIELD[unit], rel=1e-12), (name, field)
    for field in set(ACCEL_FIELDS) - {f for f, _, _ in given}:
        assert getattr(sheet, field) is None, (name, field)
    assert sheet.has_accelerometer == bool(given)


@pytest.mark.parametrize(
    ("name", "field", "si"),
    [
        ("stim300", "velocity_random_walk", 1.0e-3),  # 0.06 m/s/sqrt(h) / 60
        ("stim300", "bias_instability", 50e-6 * 9.80665 / 0.664282),  # ADEV minimum / sqrt(2 ln2/pi)
        ("stim300", "scale_factor_repeatability", 3.0e-4),
        ("sch16t-k01", "bias_instability", 2.0e-4),  # the sheet's B itself (Allan minimum / 0.664)
        ("sch16t-k01", "velocity_random_walk", 5.0e-4),  # 30 mm/s/sqrt(h)
        ("sch16t-k01", "range", 80.0),
        ("sch16t-k01", "bias_repeatability", 0.14 / 3),
        ("sch16t-k01", "resolution", 1 / 3200),
        ("lsm6dsv", "velocity_random_walk", 60e-6 * 9.80665),  # two-sided density = VRW
        ("lsm6dsv", "resolution", 0.488e-3 * 9.80665),
        ("openrtk330", "range", 8 * 9.80665),
        ("openrtk330", "bandwidth", 50.0),
        ("hg1700", "velocity_random_walk", 0.065 * 0.3048 / 60),
    ],
)
def test_a_parts_accelerometer_is_its_figures_in_si(name, field, si):
    acc = parts.get(name).accelerometer()
    assert acc is not None
    assert getattr(acc, field) == pytest.approx(si, rel=2e-6), (name, field)


def test_a_gyro_only_part_has_no_accelerometer_and_unset_terms_stay_out():
    assert parts.get("adxrs646").accelerometer() is None
    acc = parts.get("adis16495-1").accelerometer()
    assert acc.velocity_random_walk == 0.0 and math.isinf(acc.bandwidth) and acc.bias_repeatability == 0.0
    assert acc.reference_temperature == parts.get("adis16495-1").reference_temperature


def test_bad_accelerometer_figures_are_one_line(tmp_path):
    base = ('name = "u"\nmanufacturer = "m"\nmodel = "u"\ntechnology = "MEMS"\ngrade = "consumer"\n'
            'source = "my sheet rev A"\narw = 0.1\n')
    for line, match in (("accel_vrw_m_s_sqrt_h = -0.1", r"accel_vrw_m_s_sqrt_h"),
                        ("accel_range_g = 0", r"accel_range_g"),
                        ("accel_bias_instability_ug = 'x'", r"accel_bias_instability_ug")):
        p = tmp_path / "u.toml"
        p.write_text(base + line + "\n")
        with pytest.raises(ValueError, match=match) as info:
            parts.load_toml(p)
        assert "\n" not in str(info.value) and "u.toml" in str(info.value)
    p.write_text(base + "accel_vrw_m_s_sqrt_h = 0.05\naccel_range_g = 4\n")
    acc = parts.load_toml(p).accelerometer()
    assert acc.velocity_random_walk == pytest.approx(0.05 / 60) and acc.range == pytest.approx(4 * 9.80665)


#: 1 % false-alarm rate per part over its 6 (axis, term) checks, two-sided (Bonferroni)
Z = float(norm.ppf(1 - 0.01 / (2 * 6)))


def _static_fit_meets_the_sheet(name: str, fs: float) -> None:
    """A static triad of 300 crossover times (N/(0.664 B))^2 of the part's accelerometer: the fit of
    each axis gives its VRW and B within Z standard errors (the fit's own intervals). The rounding
    to the resolution q adds white noise of variance q^2/12 per sample when the noise spans a few
    LSB (Widrow's quantization theorem; sigma/q >= 1.2 here), so the VRW the record carries is
    sqrt(N^2 + q^2/(12 fs)). Gravity and the turn-on terms are constants the fit ignores."""
    part = parts.get(name)
    acc = part.accelerometer()
    n_true = math.sqrt(acc.velocity_random_walk**2 + acc.resolution**2 / (12 * fs))
    b_true = acc.bias_instability
    dur = 300 * (acc.velocity_random_walk / (parts.ADEV_MIN_PER_B * b_true)) ** 2
    unit = TriadSpec(gyros=(part, part, part), accelerometer=acc).realize(rng=np.random.default_rng(20261202))
    rec = unit.simulate(SegmentedMotion((Segment(duration=dur),)), fs=fs, rng=np.random.default_rng(8),
                        site=Site(latitude=0.5)).recording
    for axis in "xyz":
        fit = fit_noise(rec[f"accel_{axis}"], fs, terms=("Q", "N", "B", "K"), misfit_p=1e-4)
        assert not fit.misfit, axis
        for key, truth in (("N", n_true), ("B", b_true)):
            c = fit.coefficients[key]
            se = (c.ci95[1] - c.ci95[0]) / (2 * 1.96)
            assert c.value is not None and abs(c.value - truth) <= Z * se, (name, axis, key, c.value, truth, se)


@pytest.mark.parametrize("name", ["stim300", "sch16t-k01", "ahrs380", "mti-1"])
def test_a_parts_static_accelerometers_give_back_its_vrw_and_b(name):
    _static_fit_meets_the_sheet(name, 20.0)


@pytest.mark.slow
def test_a_quantized_parts_static_accelerometers_give_back_its_vrw_and_b():
    """OpenRTK330: a 0.5 mg LSB against 0.6 mg of per-sample noise at 50 Hz (its 50 Hz low-pass is
    negligible there, a = exp(-2 pi) = 0.002): the q^2/12 term is 6 % of N^2, 20 standard errors."""
    _static_fit_meets_the_sheet("openrtk330", 50.0)


def test_a_part_whose_sheet_gives_b_but_no_vrw_gives_back_its_b():
    """HG9900: flicker only (its source gives no VRW). 600 s at 20 Hz; each axis's B within Z3
    standard errors, Z3 at 1 % over the 3 checks, two-sided."""
    z3 = float(norm.ppf(1 - 0.01 / (2 * 3)))
    part = parts.get("hg9900")
    acc = part.accelerometer()
    assert acc.velocity_random_walk == 0.0
    unit = TriadSpec(gyros=(part, part, part), accelerometer=acc).realize(rng=np.random.default_rng(20261202))
    rec = unit.simulate(SegmentedMotion((Segment(duration=600.0),)), fs=20.0, rng=np.random.default_rng(8),
                        site=Site(latitude=0.5)).recording
    for axis in "xyz":
        fit = fit_noise(rec[f"accel_{axis}"], 20.0, terms=("N", "B", "K"), misfit_p=1e-4)
        c = fit.coefficients["B"]
        se = (c.ci95[1] - c.ci95[0]) / (2 * 1.96)
        assert not fit.misfit and abs(c.value - acc.bias_instability) <= z3 * se, (axis, c.value, se)
