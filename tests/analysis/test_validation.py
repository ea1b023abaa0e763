"""Reference-value tests of analysis.allan against published data.

The subset in tests/data (see its README: Stable32 tables of PHASE.DAT and the pink-frequency
set, the NBS14 values, a 1 Hz excerpt of the six ADIS16405 records) runs in any clone; the
full sets in ../shared/validation (more Stable32 tables, the 100 Hz ADIS16405 records, the
NavChip curves) run when that folder is present and skip otherwise.

Tolerances are the precision the sources print (see each folder's README):
- Stable32 tables: 5 significant digits -> 1e-4 relative on Sigma (README recommendation),
  term counts exact; the two ocxo octave tables were produced by Stable32 with a slightly
  different normalisation and agree only to 1.5e-4 (README "What was checked here").
- ADIS16405 maximum-overlap AVAR computed by the R package avar: 1e-5 relative (README).
- NavChip AVLR fit printed with 7 significant digits: agree after rounding to 7 digits.
"""

from __future__ import annotations

import functools
import gzip
import math
from decimal import Decimal
from pathlib import Path
from statistics import NormalDist

import numpy as np
import pytest

from gyrobench.analysis import allan
from gyrobench.analysis.allan import AllanCurve, allan_deviation, fit_noise, slope_readoff

#: the reference data shipped with the tests (tests/data/README.md)
REFERENCE = Path(__file__).resolve().parents[1] / "data"

STABLE32_KIND = {
    "adev": "standard",
    "oadev": "overlapping",
    "mdev": "modified",
    "hdev": "hadamard",
    "ohdev": "overlapping_hadamard",
    "totdev": "total",
}


def read_stable32(path: Path) -> np.ndarray:
    """Rows AF, Tau, #, Alpha, MinSigma, Sigma, MaxSigma of a Stable32 result file."""
    return np.loadtxt(path, comments="#", ndmin=2)


def read_csv(path: Path) -> np.ndarray:
    """A CSV with '#' comment lines and a header row, as a structured array."""
    with open(path, encoding="utf-8") as fh:
        lines = [ln for ln in fh if not ln.startswith("#")]
    return np.genfromtxt(lines, delimiter=",", names=True, dtype=None, encoding="utf-8")


def check_table(rate: np.ndarray, fs: float, table: Path, kind: str, rtol: float) -> None:
    ref = read_stable32(table)
    curve = allan_deviation(rate, fs, taus=ref[:, 1], kind=kind)
    np.testing.assert_array_equal(curve.m, ref[:, 0].astype(int))
    np.testing.assert_array_equal(curve.n_terms, ref[:, 2].astype(int))
    np.testing.assert_allclose(curve.deviation, ref[:, 5], rtol=rtol, atol=0)


# ---------------------------------------------------------------------------- Stable32 / frequency
@pytest.mark.parametrize("dev", sorted(STABLE32_KIND))
def test_ocxo_all_tau_tables(validation, dev):
    folder = validation / "allantools_stable32" / "ocxo"
    y = np.loadtxt(folder / "ocxo_frequency.txt", comments="#") / 1e7 - 1.0
    check_table(y, 1.0, folder / f"stable32_{dev}_alltau.txt", STABLE32_KIND[dev], rtol=1e-4)


@pytest.mark.parametrize("dev", ["adev", "hdev"])
def test_ocxo_octave_tables(validation, dev):
    folder = validation / "allantools_stable32" / "ocxo"
    y = np.loadtxt(folder / "ocxo_frequency.txt", comments="#") / 1e7 - 1.0
    check_table(y, 1.0, folder / f"{dev}_octave.txt", STABLE32_KIND[dev], rtol=1.5e-4)


@pytest.mark.parametrize("dev", sorted(STABLE32_KIND))
def test_pink_frequency_tables(dev):
    folder = REFERENCE / "stable32" / "pink_frequency"
    y = np.loadtxt(folder / "pink_frequency.txt", comments="#")
    name = "totdev_alpha0.txt" if dev == "totdev" else f"{dev}.txt"
    check_table(y, 1.0 / 42.0, folder / name, STABLE32_KIND[dev], rtol=1e-4)


def test_pink_frequency_octave_oadev_and_bounds():
    """s32_oadev_octave (tau0 = 1 s) including Stable32's 68.3 % bounds with its own alpha."""
    folder = REFERENCE / "stable32" / "pink_frequency"
    y = np.loadtxt(folder / "pink_frequency.txt", comments="#")
    ref = read_stable32(folder / "s32_oadev_octave.txt")
    curve = allan_deviation(y, 1.0, taus=ref[:, 1], alpha=ref[:, 3].astype(int), confidence=0.683)
    np.testing.assert_allclose(curve.deviation, ref[:, 5], rtol=1e-4)
    np.testing.assert_array_equal(curve.n_terms, ref[:, 2].astype(int))
    # The bounds cannot match to the 5 printed digits: Stable32's edf is not the Greenhall
    # edf we use (allantools.ci.edf_greenhall). Inverting its printed MinSigma for the edf
    # gives 0.0-1.5 % more than Greenhall's (4409 vs 4392 at m = 2, 2317 vs 2283 at m = 4,
    # alpha = -2) and it is not Stein's NIST SP 1065 Table 5 edf either (4998, 2498); the
    # README says the bounds were not re-verified. A 1.5 % edf difference moves a 68 % bound
    # by at most 4.4e-4 relative here (measured; the same when the bounds are recomputed
    # from Stable32's own printed Sigma), so 5e-4 is the tightest tolerance this supports.
    np.testing.assert_allclose(curve.low, ref[:, 4], rtol=5e-4)
    np.testing.assert_allclose(curve.high, ref[:, 6], rtol=5e-4)


# ---------------------------------------------------------------------------- Stable32 / phase
def phase_to_rate(x: np.ndarray, tau0: float) -> np.ndarray:
    """Rate (fractional frequency) from phase [s]: y_k = (x_{k+1} - x_k) / tau0."""
    return np.diff(x) / tau0


@pytest.mark.parametrize("dev", sorted(STABLE32_KIND))
@pytest.mark.parametrize("suffix", ["", "_octave"])
def test_phasedat_tables_via_rate(dev, suffix):
    folder = REFERENCE / "stable32" / "phasedat"
    y = phase_to_rate(np.loadtxt(folder / "PHASE.DAT", comments="#"), 1.0)
    check_table(y, 1.0, folder / f"phase_dat_{dev}{suffix}.txt", STABLE32_KIND[dev], rtol=1e-4)


def test_phasedat_angle_and_rate_routes_agree():
    """PHASE.DAT is the integral of a 1000-point rate series: ADEV(1 s) = 2.9223e-01 either way."""
    x = np.loadtxt(REFERENCE / "stable32" / "phasedat" / "PHASE.DAT", comments="#")
    curve = allan_deviation(phase_to_rate(x, 1.0), 1.0, taus=[1.0], kind="standard")
    assert curve.deviation[0] == pytest.approx(2.9223e-01, rel=0.5e-4 / 2.9223)
    second = x[2:] - 2 * x[1:-1] + x[:-2]  # the angle route, NIST SP 1065 eq. 7 at m = 1
    assert np.sqrt(np.mean(second**2) / 2) == pytest.approx(curve.deviation[0], rel=1e-12)


@pytest.mark.parametrize("dev", sorted(STABLE32_KIND))
def test_keysight_tic_tables_via_rate(validation, dev):
    folder = validation / "allantools_stable32" / "keysight53230A_tic"
    y = phase_to_rate(np.loadtxt(folder / "tic_phase.txt", comments="#"), 1.0)
    check_table(y, 1.0, folder / f"tic_{dev}.txt", STABLE32_KIND[dev], rtol=1e-4)


# ---------------------------------------------------------------------------- NBS14
def test_nbs14_published_deviations():
    """NIST SP 1065's NBS14 9-point set: every statistic at tau = 1, 2 s to the printed digits.

    The tolerance is one unit in the last printed digit, not half: the source prints the same
    quantity (HDEV and OHDEV at tau = 1 s are one statistic) as 70.80608 and 70.80607, so its
    own rounding is good to one unit (the exact value is 70.806073).
    """
    y = np.loadtxt(REFERENCE / "nbs14" / "nbs14_frequency.txt", comments="#")
    with open(REFERENCE / "nbs14" / "nbs14_deviations.csv", encoding="utf-8") as fh:
        rows = [ln.strip().split(",") for ln in fh if not ln.startswith("#")][1:]
    assert {r[0] for r in rows} == set(STABLE32_KIND.values())
    for kind, tau, printed in rows:
        got = allan_deviation(y, 1.0, taus=[float(tau)], kind=kind).deviation[0]
        ulp = float(Decimal(1).scaleb(Decimal(printed).as_tuple().exponent))
        assert abs(got - float(printed)) <= ulp, (kind, tau, got, printed)


# ---------------------------------------------------------------------------- ADIS16405 (real gyro)
def test_adis16405_overlapping_avar(validation):
    folder = validation / "smac_imudata_adis16405"
    with gzip.open(folder / "adis16405_imu1_100Hz.csv.gz", "rt") as fh:
        lines = (ln for ln in fh if ln[:1] not in ("#", "g"))  # drop comments and the header row
        data = np.loadtxt(lines, delimiter=",")
    assert data.shape == (1_000_000, 6)
    ref = read_csv(folder / "adis16405_imu1_avar_reference.csv")
    channels = ["Gyro_X", "Gyro_Y", "Gyro_Z", "Accel_X", "Accel_Y", "Accel_Z"]
    assert sorted(set(ref["channel"])) == sorted(channels)
    for col, ch in enumerate(channels):
        r = ref[ref["channel"] == ch]
        curve = allan_deviation(data[:, col], 100.0, taus=r["tau_s"], kind="overlapping")
        np.testing.assert_array_equal(curve.m, r["m"].astype(int))
        np.testing.assert_allclose(curve.variance, r["avar"], rtol=1e-5, err_msg=ch)


# ---------------------------------------------------------------------------- NavChip AVLR fit
def navchip_curves(validation, group: str) -> tuple[list[AllanCurve], np.ndarray]:
    ref = read_csv(validation / "smac_avar_allan_curves" / "navchip_av.csv")
    curves = []
    for axis in "XYZ":
        r = ref[ref["channel"] == f"{group}_{axis}"]
        nan = np.full(r.size, np.nan)
        curves.append(AllanCurve(tau=r["tau_s"], deviation=r["adev"], low=nan, high=nan,
                                 n_terms=np.zeros(r.size, dtype=np.int64), edf=nan, kind="overlapping",
                                 confidence=0.683, fs=250.0, n_samples=3105250))
    return curves, curves[0].tau


def levels(tau: np.ndarray, spec: str) -> tuple[float, float]:
    """tau range of 1-based level indices 'a:b' (R notation)."""
    a, b = (int(v) for v in spec.split(":"))
    return float(tau[a - 1]), float(tau[b - 1])


def same_to_digits(value: float, published: float, digits: int = 7) -> bool:
    return float(f"{value:.{digits - 1}e}") == published


def test_navchip_published_fixed_slope_fit(validation):
    pub = read_csv(validation / "smac_avar_allan_curves" / "navchip_avlr_published_fit.csv")
    name = {"WN": "N", "QN": "Q", "RW": "K"}
    for group, label in (("gyro", "Gyro"), ("accel", "Accel")):
        curves, tau = navchip_curves(validation, label)
        rows = pub[pub["sensor_group"] == group]
        ranges = {name[r["coefficient"]]: levels(tau, r["scale_indices"]) for r in rows}
        got = slope_readoff(curves, fit_ranges=ranges)
        for r in rows:
            v = got[name[r["coefficient"]]]
            assert same_to_digits(v, float(r["published_value"])), (group, r["coefficient"], v, r["published_value"])


# ---------------------------------------------------------------------------- ADIS16405 noise fits
#: false-alarm rate of each comparison below (two-sided), Bonferroni-split over the comparisons
ADIS_FALSE_ALARM = 1e-6
ADIS_AXES = ("gyro_x", "gyro_y", "gyro_z")
#: the ADIS16405 quantization (LSB 0.05 deg/s at 100 Hz: Q = LSB / (fs sqrt(12)) = 1.4e-4 deg)
#: gives sqrt(3) Q / tau < 1.5 % of the measured ADEV at every fitted tau (>= 0.04 s), so Q is
#: left out of these comparisons: with it, the relative-weight NNLS trades Q against N on the
#: filter-bent first points (N 6 % apart on imu5 x) while neither estimate is the sensor's
ADIS_TERMS = ("N", "B", "K", "R")


def _read_gyro(path: Path) -> np.ndarray:
    """The three gyro columns [rad/s] of an ADIS16405 CSV (gz; '#' comments, one header row)."""
    with gzip.open(path, "rt") as fh:
        lines = (ln for ln in fh if ln[:1] not in ("#", "g"))  # drop comments and the header row
        return np.deg2rad(np.loadtxt(lines, delimiter=",", usecols=(0, 1, 2)))


def _adis_records(source: str) -> tuple[list[np.ndarray], float]:
    """The six records of ``source`` ("excerpt_1hz": tests/data; "full_100hz": shared) and fs [Hz]."""
    if source == "excerpt_1hz":
        folder = REFERENCE / "adis16405_1hz"
        return [_read_gyro(folder / f"adis16405_imu{k}_1Hz.csv.gz") for k in range(1, 7)], 1.0
    from tests.analysis.conftest import VALIDATION as validation

    folder = validation / "smac_imudata_adis16405"
    if not folder.is_dir():
        pytest.skip(f"reference data folder {folder} not found")
    return [_read_gyro(folder / f"adis16405_imu{k}_100Hz.csv.gz") for k in range(1, 7)], 100.0


# the 100 Hz records' fits are ~8 s of set-up: slow tier (the 1 Hz excerpt keeps the default tier's check)
@pytest.fixture(scope="module", params=["excerpt_1hz", pytest.param("full_100hz", marks=pytest.mark.slow)])
def adis_fits(request):
    """(curve, unrestricted fit, auto-range fit) for each of the 6 records x 3 gyro axes.

    ``excerpt_1hz`` (tests/data, any clone) is the block-mean decimation of ``full_100hz``
    (../shared/validation, optional): the same gyros' N and B, without the sensor filter's
    bend at the shortest taus.
    """
    records, fs = _adis_records(request.param)
    out = {}
    for k, data in enumerate(records, start=1):
        for ax, name in enumerate(ADIS_AXES):
            curve = allan_deviation(data[:, ax], fs)
            out[(k, name)] = (curve, fit_noise(curve), fit_noise(curve, tau_min="auto", terms=ADIS_TERMS))
    return out


def _nnls_relative(tau, avar, terms):
    """allan-variance (N. Mayorov) style fit: NNLS of sum_n C_n tau^n / avar_i = 1 (relative errors)."""
    from scipy import optimize

    x = np.stack([tau ** float(allan._POWER[t]) for t in terms], axis=1)
    c = optimize.nnls(x / avar[:, None], np.ones(avar.size))[0]
    return c, x


def _sandwich(x, w, v):
    """Covariance of the weighted LS estimate with weights w under point covariance v."""
    xw = x * w[:, None]
    bread = np.linalg.pinv(x.T @ xw)
    return bread @ (xw.T @ v @ xw) @ bread


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_adis16405_unrestricted_fit_is_flagged(adis_fits):
    """The filter-bent first octaves make the all-tau fit a misfit on every record, widened, never tight."""
    if next(iter(adis_fits.values()))[0].fs != 100.0:
        pytest.skip("the sensor filter's bend is visible only in the 100 Hz records")
    flagged = [key for key, (_, full, _) in adis_fits.items() if full.misfit]
    assert set(flagged) == set(adis_fits)
    for key in flagged:
        full = adis_fits[key][1]
        # widened by sqrt(chi2/E[chi2]) (2.0e3-1.3e4 measured), never left at the tight width
        assert full.inflation > 1.0, (key, full.chi2_per_dof)


def test_adis16405_auto_fit_agrees_with_nnls(adis_fits, request):
    """N and B of the auto-range fit vs the relative-weight NNLS on the same points.

    Combined uncertainty: sqrt(se_fit^2 + se_nnls^2), se_nnls the sandwich standard error of
    the NNLS under the fit's modelled point covariance. The two estimates use the same
    points and are positively correlated, so this overstates the spread of their difference
    (the check is conservative).
    """
    if next(iter(adis_fits.values()))[0].fs == 1.0:
        # Known defect, kept visible: on the 1 Hz excerpt N differs from the relative-weight
        # NNLS by 4.4-8.1 combined standard errors on 6 of 18 axes (imu2 x, imu4 z, imu5 x/y,
        # imu6 x/z), also where the fit does not misfit (p = 0.08-0.6 on imu5 x/y, imu6 x):
        # widening at p < 0.05 (issue 30 item 2) widens imu2 x and imu4 z (x1.6) and is not
        # the cause. Open: the two estimators weight the filter-free 1 Hz points differently
        # and one of them is biased there.
        request.applymarker(pytest.mark.xfail(strict=True, reason="N off the NNLS on the 1 Hz excerpt"))
    pairs = [(key, name) for key in adis_fits for name in ("N", "B")]
    z = NormalDist().inv_cdf(1.0 - ADIS_FALSE_ALARM / 2.0 / len(pairs))
    for key, name in pairs:
        curve, _, fit = adis_fits[key]
        terms = list(fit.avar_coefficients)
        a = curve.variance[fit.used]
        c_ref, x = _nnls_relative(fit.tau_used, a, terms)
        cov_ref = _sandwich(x, 1.0 / a**2, fit.point_covariance)
        j = terms.index(name)
        diff = fit.avar_coefficients[name] - c_ref[j]
        se = math.sqrt(fit.covariance[j, j] + cov_ref[j, j])
        assert abs(diff) <= z * se, (key, name, fit.avar_coefficients[name], c_ref[j], diff / se)


def test_adis16405_auto_fit_agrees_with_slope_readoff(adis_fits):
    """IEEE 952 read-off vs the fit. The read-off of a term is biased high by the other terms'
    share s of the AVAR where it reads (the line through the data carries them too), so the
    fit must lie in [sqrt(1 - s) read-off, read-off], widened by z times the read-off's
    statistical error 1/sqrt(2 edf) (relative, Var ln ADEV = 1/(2 edf); for N the mean of the
    segment's two points). s is taken from the fit's own term split.
    """
    checks = [(key, name) for key in adis_fits for name in ("N", "B")]
    z = NormalDist().inv_cdf(1.0 - ADIS_FALSE_ALARM / 2.0 / len(checks))
    for key, name in checks:
        curve, _, fit = adis_fits[key]
        ro = slope_readoff(curve)[name]
        tau, dev, edf = curve.tau, curve.deviation, curve.edf
        if name == "B":
            i = int(np.argmin(dev))
            t_read, rel = tau[i], 1.0 / math.sqrt(2.0 * edf[i])
        else:
            slope = np.diff(np.log(dev)) / np.diff(np.log(tau))
            i = int(np.argmin(np.abs(slope + 0.5)))
            t_read = math.sqrt(tau[i] * tau[i + 1])
            rel = 0.5 * math.sqrt(0.5 / edf[i] + 0.5 / edf[i + 1])
        share = 1.0 - float(fit.term_avar(name, t_read) / fit.avar(t_read))
        got = fit.coefficients[name]
        value = got.value if got.value is not None else 0.0
        lo = ro * math.sqrt(max(1.0 - share, 0.0)) * (1.0 - z * rel)
        hi = ro * (1.0 + z * rel)
        flo, fhi = fit.interval(name, 1.0 - ADIS_FALSE_ALARM / len(checks))
        assert flo <= hi and fhi >= lo, (key, name, value, ro, share, rel, (flo, fhi))


def test_adis16405_records_agree_on_b(adis_fits):
    """The six replicate records of each axis: their B agree within their intervals.

    Homogeneity test: sum ((B_k - B_w) / se_k)^2 against chi2(k - 1) at the false-alarm rate,
    se_k half the 68 % interval, B_w the inverse-variance mean; records whose B is not
    identifiable enter with value 0 and their one-sided bound as 2 se (they only widen it).
    """
    from scipy import stats

    for name in ADIS_AXES:
        vals, ses = [], []
        for k in range(1, 7):
            c = adis_fits[(k, name)][2].coefficients["B"]
            if c.identifiable:
                vals.append(c.value)
                ses.append((c.ci68[1] - c.ci68[0]) / 2.0)
            else:
                vals.append(0.0)
                ses.append(c.upper_bound / 2.0)
        v, s = np.array(vals), np.array(ses)
        w = 1.0 / s**2
        mean = float(np.sum(w * v) / np.sum(w))
        chi2 = float(np.sum(((v - mean) / s) ** 2))
        limit = stats.chi2.isf(ADIS_FALSE_ALARM / len(ADIS_AXES), len(v) - 1)
        assert chi2 <= limit, (name, np.round(v * 180 / np.pi * 3600, 1), chi2, limit)
        # and in field units the published range: B of the x/y axes 25-45 deg/h (issue 14)
        assert 10.0 < mean * 180 / np.pi * 3600 < 60.0, (name, mean)


# ---------------------------------------------------------------------------- halves of real records
#: the target of issue 30: 95 % intervals of the two halves of a record overlap on >= 95 % of term pairs
HALVES_TARGET = 0.95


def _read_all(path: Path) -> np.ndarray:
    """All six columns of an ADIS16405 CSV (gz): gyro [deg/s] and accelerometer [g], as printed."""
    with gzip.open(path, "rt") as fh:
        return np.loadtxt((ln for ln in fh if ln[:1] not in ("#", "g")), delimiter=",")


@functools.lru_cache(maxsize=1)
def _full_records() -> tuple[np.ndarray, ...]:
    """The six 100 Hz ADIS16405 records, all six columns (skips without ../shared/validation)."""
    from tests.analysis.conftest import VALIDATION as validation

    folder = validation / "smac_imudata_adis16405"
    if not folder.is_dir():
        pytest.skip(f"reference data folder {folder} not found")
    return tuple(_read_all(folder / f"adis16405_imu{k}_100Hz.csv.gz") for k in range(1, 7))


@pytest.mark.parametrize(
    "source", ["excerpt_1hz", pytest.param("full_100hz", marks=pytest.mark.slow)]  # 100 Hz: ~15 s
)
def test_adis16405_halves_intervals_overlap(source):
    """The two halves of each real record: their 95 % intervals overlap on >= 95 % of term pairs.

    A pair is a term identified in at least one half (the other half enters with [0, its
    one-sided bound]); the fits are the CLI's (five terms, ``tau_min="auto"``). The 1 Hz
    excerpt has the gyro axes only; the full records also the accelerometer axes. Two
    consistent 95 % intervals overlap far more often than 95 % of the time, so the check is
    that the non-overlapping pairs are not significantly more than 5 %: their count must not
    exceed the binomial(pairs, 0.05) quantile at false-alarm 1e-3. Measured (docs/physics.md
    1.8): 39/39 pairs on the excerpt, 78/79 on the full records (75/100 before issue 30).
    """
    from scipy import stats

    records, fs = _adis_records(source) if source == "excerpt_1hz" else (_full_records(), 100.0)
    pairs, apart = 0, []
    for k, data in enumerate(records, start=1):
        for col in range(data.shape[1]):
            found = allan.halves_agreement(data[:, col], fs, tau_min="auto")
            pairs += len(found)
            apart += [(k, col, p.term, p.first, p.second) for p in found if not p.overlap]
    assert pairs >= 30, pairs
    limit = int(stats.binom.isf(1e-3, pairs, 1.0 - HALVES_TARGET))
    assert len(apart) <= limit, (pairs, limit, apart)


@pytest.mark.slow  # fits every segment of the six 100 Hz records (~20 s)
def test_adis16405_open_bounds_not_below_other_segments():
    """No upper bound of the whole record's fit below what another stretch of it shows (issue 30).

    :func:`floor_bounds` raises an open term's bound to the values its halves, quarters and eighths
    identify; here stretches it did not fit (the thirds, the first and last 2000 s) are fitted
    alike, and wherever they identify a term the whole record leaves open, the bound must not
    sit below that stretch's 95 % interval (bound >= its lower end: the data of the stretch
    do not contradict it). Before: 26 of 47 such bounds sat below the stretch's value itself,
    e.g. accelerometer VRW 0.186 vs 0.30 m/s/sqrt(h) on the first 2000 s of imu1.
    """
    below = []
    checked = 0
    for k, data in enumerate(_full_records(), start=1):
        for col in range(data.shape[1]):
            y = data[:, col]
            fit = allan.floor_bounds(fit_noise(allan_deviation(y, 100.0), tau_min="auto"), y, 100.0, tau_min="auto")
            third = y.size // 3
            for seg in (y[:200_000], y[-200_000:], y[:third], y[third : 2 * third], y[2 * third :]):
                sub = fit_noise(allan_deviation(seg, 100.0), tau_min="auto")
                for name, c in fit.coefficients.items():
                    s = sub.coefficients[name]
                    if c.identifiable or not s.identifiable:
                        continue
                    checked += 1
                    if c.upper_bound < s.ci95[0]:
                        below.append((k, col, name, seg.size, c.upper_bound, s.ci95))
    assert checked >= 20, checked
    assert not below, below


def test_floor_bounds_refuses_bad_parts():
    y = np.random.default_rng(0).normal(size=4096)
    fit = fit_noise(y, 1.0)
    with pytest.raises(ValueError, match=r"parts must be integers >= 2 \(segments per split\); got \[1\]"):
        allan.floor_bounds(fit, y, 1.0, parts=[1])
