"""Closed-form checks of the cavity RLG model (:mod:`gyrobench.sim.rlg_cavity`).

``checks(rng)`` returns:

* ``rlg_cavity.lock_in_backscatter``: the lock-in a drawn unit's counts carry (its statistical
  mode run in a chamber: the random walk of the angle increments over the swing-dither ARW
  per unit lock-in) against Omega_L = c lambda |r_net| / (8 pi A) evaluated by hand from the
  mirrors' amplitudes, phases and path positions at the logged block temperatures.
* ``rlg_cavity.mode_hop_spacing``: heating hop spacing in a chamber ramp against
  lambda / (P alpha).
* ``rlg_cavity.mode_hop_hysteresis``: heating minus cooling temperature of the same mode
  transition against (S - lambda) / (P alpha).
* ``rlg_cavity.dead_band_width``: edge of the locked band of an unrandomized dithered gyro
  near zero input against Omega_L |J_0(beta_D)|: inputs 0.885-1.115 x the band in 1 % steps,
  each locked when the one-period map of the Adler integration has a fixed point (128 start
  phases side by side over one dither period, 0.06 s; 150 periods of one phase per input took
  0.85 s and left a half-slip resolution term of 0.031 in the tolerance, now 0.005); a 1 %
  error in the lock-in is caught (a 10 % one lands 10 % off, inside the grid).
* ``rlg_cavity.dither_random_walk``: angle-error variance after 5 dither cycles with the
  Earth's rate present (Adler integration, swing-randomized dither, 3200 realizations) against
  the statistical model's N^2 T. The Adler integration's cost is set by its time steps more
  than by the realizations it carries side by side, so short records with many realizations
  are cheap: 5 x 3200 runs in 60 % of the time of 25 x 800 and its tolerance (sample
  variance, z sqrt((kurtosis - 1)/M)) is half as wide (0.12 vs 0.25), so a 10 % error in the
  lock-in (21 % in the variance) is caught; the random walk is already linear in T after 5
  cycles (10 crossings: 3 x 16000 realizations agree with N^2 T to -1.5 +- 0.6 %).
* ``rlg_cavity.no_dead_band_with_swing_dither``: at half the fixed-amplitude dead band, the
  swing-randomized gyro's mean output equals the input (the statistical mode has no dead band);
  7 cycles x 2000 realizations: standard error N/sqrt(T M) 1.4 times that of 63 x 400 at a
  third of the cost; the band (0.045) still puts a 10 % error in the output 6 standard errors
  out (tests/scenarios/test_checks_catch_errors.py).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from gyrobench.base import units
from gyrobench.scenarios.checks.core import CLOSED_FORM, CONSISTENCY, Check, Part, run_parts
from gyrobench.sim.environment import Ramp, Soak, thermal_profile
from gyrobench.sim.rlg import Dither, integrate_adler
from gyrobench.sim.rlg_cavity import (
    SPEED_OF_LIGHT,
    ZERODUR_CTE_CLASS_2,
    CavityRLG,
    CavityRLGSpec,
    SwingDither,
    swing_dither_arw,
)
from gyrobench.sim.sensor import Environment

__all__ = ["checks", "parts"]

#: two-sided false-alarm rate of the statistical checks
FALSE_ALARM = 1e-6
#: standard-normal quantile for FALSE_ALARM two-sided
Z_FALSE_ALARM = 4.8916
#: latitude of the Earth-rate check (Beijing, docs/physics.md 8) [rad]
LATITUDE = math.radians(39.9)
#: outside references of the checks
CHOW = "W. W. Chow et al., 'The ring laser gyro', Rev. Mod. Phys. 57(1) 61 (1985)"
ARONOWITZ = "F. Aronowitz, 'The laser gyro', in Laser Applications vol. 1 (Academic Press, 1971)"
KILLPATRICK = "J. E. Killpatrick, 'The laser gyro', IEEE Spectrum 4(10) (1967): randomized dither"
SIEGMAN = "A. E. Siegman, Lasers (University Science Books, 1986)"


def _hand_r_net(u: CavityRLG, strain: float, plc: float) -> complex:
    """r_net written out mirror by mirror (independent of Backscatter.net)."""
    b, g = u.backscatter, u.geometry
    k = 2.0 * math.pi / g.wavelength
    total = 0j
    for i, (a, th, pos) in enumerate(zip(b.amplitudes, b.phases, b.positions, strict=True)):
        if i == 0:
            ph = th + b.walk_phase * plc / g.wavelength
        else:
            ph = th + 2.0 * k * (pos * g.perimeter * (1.0 + strain) + plc / 2.0)
        total += a * complex(math.cos(ph), math.sin(ph))
    return total


#: lock-in check: record per sample [s] (one angle increment each) and samples
LOCK_IN_TAU = 10000.0
LOCK_IN_SAMPLES = 40000


def _check_lock_in(u: CavityRLG, rng: np.random.Generator) -> Check:
    """The lock-in the simulated counts carry against the mirror-by-mirror closed form.

    The unit runs in its own statistical mode (:meth:`CavityRLG.simulate`, flicker off) in a
    chamber held 12 K above the reference, one sample per LOCK_IN_TAU: nothing is handed to
    the model but the chamber. The angle increments' variance is N^2 tau + 2 var(e) (e the
    counting error, uniform over one pulse under the dither: q^2/12 each end), and N is
    Omega_L times the swing-dither ARW per unit lock-in (checked against the Adler
    equation by ``rlg_cavity.dither_random_walk``), so the counts give
    Omega_L = sqrt((var - q^2/6)/tau) / n_unit. The closed form takes the logged block
    temperatures and the acquired mode (the turn-on's draw) and sums the mirrors by hand.
    """
    from scipy import stats

    quiet = replace(u, bias_instability=0.0, rate_random_walk=0.0)
    g, q = quiet.geometry, quiet.pulse_weight
    t_chamber = quiet.reference_temperature + 12.0
    fs = 1.0 / LOCK_IN_TAU
    rec = quiet.simulate(Environment(LOCK_IN_SAMPLES / fs, temperature=t_chamber), fs=fs, rng=rng)
    keep = slice(LOCK_IN_SAMPLES // 10, None)  # the warm-up (hours) dropped
    inc = rec.channels["output"].data[keep] / fs  # angle increments [rad]
    var = float(np.var(inc, ddof=1))
    n_unit = swing_dither_arw(scale_factor=quiet.scale_factor, lock_in_rate=1.0, dither=quiet.dither)
    simulated = math.sqrt((var - q * q / 6.0) / LOCK_IN_TAU) / n_unit
    # closed form at each kept sample: strain from the logged block nodes, PLC at the mode
    t_block = 0.5 * (rec.inputs["T2"].data[keep] + rec.inputs["T_block_b"].data[keep])
    strain = quiet.cte * (t_block - quiet.reference_temperature)
    mode = rec.inputs["mode"].data[keep]
    plc = mode * g.wavelength - g.perimeter * strain
    wl_hand = np.array([
        SPEED_OF_LIGHT * g.wavelength * abs(_hand_r_net(quiet, float(e), float(p))) / (8.0 * math.pi * g.area)
        for e, p in zip(strain[::100], plc[::100], strict=True)
    ])
    expected = float(np.sqrt(np.mean(wl_hand**2)))
    spread = float(np.ptp(wl_hand) / expected)  # the lock-in's drift over the kept record
    dof = inc.size - 1
    lo, hi = stats.chi2.ppf([FALSE_ALARM / 2, 1 - FALSE_ALARM / 2], dof) / dof
    quant = q * q / 6.0 / var  # the counting term, taken as uncertain by 100 %
    tol = float(max(1 - math.sqrt(lo), math.sqrt(hi) - 1)) + quant / 2 + spread
    return Check(
        id="rlg_cavity.lock_in_backscatter",
        kind=CONSISTENCY,
        reference=CHOW + "; " + ARONOWITZ + " (lock-in from the net backscatter amplitude)",
        formula="Omega_L = c lambda |sum_i r_i exp(j(2 k s_i + theta_i))| / (8 pi A) [rad/s] "
        "against the lock-in the simulated counts carry: sqrt((var(angle increment) - q^2/6)/tau) "
        f"/ n_unit, tau = {LOCK_IN_TAU:g} s",
        expected=expected,
        simulated=simulated,
        tolerance=tol,
        derivation=(
            f"sample variance of {inc.size} independent {LOCK_IN_TAU:g}-s angle increments: "
            f"chi2({dof})/{dof} band at {FALSE_ALARM:g} two-sided, square-rooted; plus half the "
            f"counting term q^2/6 / var = {quant:.2g} (100 % uncertain) and the closed form's "
            f"spread over the kept samples ({spread:.1g})"
        ),
    )


def _chamber_cycle() -> object:
    return thermal_profile(
        units.celsius(-40.0),
        [
            Soak(duration=1800.0),
            Ramp(target=units.celsius(65.0), rate=1.0 / 180.0),
            Soak(duration=3600.0),
            Ramp(target=units.celsius(-40.0), rate=1.0 / 180.0),
            Soak(duration=1800.0),
        ],
    )


def _hop_checks(u: CavityRLG) -> list[Check]:
    fs = 1.0
    prof = _chamber_cycle()
    tt = np.arange(int(prof.duration * fs) + 1) / fs  # type: ignore[attr-defined]
    nodes = u.thermal.temperatures(prof(tt), fs)  # type: ignore[operator]
    tb = 0.5 * (nodes[1] + nodes[2])
    st = u.cavity_state(nodes, n0=int(u.acquired_modes(float(tb[0]))[0]))
    mode = st["mode"]
    j = np.flatnonzero(np.diff(mode)) + 1
    up = mode[j] > mode[j - 1]  # alpha > 0: up-steps of the mode index happen on heating
    heating = np.diff(tb)[j - 1] > 0
    res = float(np.max(np.abs(np.diff(tb))))  # block temperature change per sample [K]
    th = np.sort(tb[j][heating])
    spacing = (th[-1] - th[0]) / (len(th) - 1)
    expect_sp = u.geometry.wavelength / (u.geometry.perimeter * abs(u.cte))
    # the same transition n <-> n+1 on heating and on cooling
    pairs = []
    for lo in np.unique(np.minimum(mode[j], mode[j - 1])):
        a = [tb[i] for i in j[(np.minimum(mode[j], mode[j - 1]) == lo) & heating]]
        b = [tb[i] for i in j[(np.minimum(mode[j], mode[j - 1]) == lo) & ~heating]]
        if a and b:
            pairs.append(a[0] - b[0])
    assert np.all(up == heating) or np.all(up != heating)
    expect_h = (u.plc.travel - u.geometry.wavelength) / (u.geometry.perimeter * abs(u.cte))
    return [
        Check(
            id="rlg_cavity.mode_hop_spacing",
            kind=CLOSED_FORM,
            reference=(
                SIEGMAN + " (a ring resonates at P = n lambda) with P(T) = P0 (1 + alpha dT); alpha: SCHOTT Zerodur "
                "datasheet (expansion classes)"
            ),
            formula="Delta T_hop = lambda / (P alpha) [K]",
            expected=expect_sp,
            simulated=float(spacing),
            tolerance=2.0 * res / (len(th) - 1) / expect_sp,
            derivation=(
                f"{len(th)} heating hops of a -40..+65 degC ramp at 1 degC/3 min, 1-s samples: "
                "each "
                f"hop temperature is resolved to the block's change over one sample ({res:.4f} K), "
                "so the mean spacing (last - first)/(n - 1) is within 2 x that / (n - 1)"
            ),
        ),
        Check(
            id="rlg_cavity.mode_hop_hysteresis",
            kind=CLOSED_FORM,
            reference=(
                SIEGMAN + " (a ring resonates at P = n lambda): a path-length control of travel S re-acquires one "
                "wavelength away"
            ),
            formula="T_hop,heating - T_hop,cooling = (S - lambda) / (P alpha) [K]",
            expected=expect_h,
            simulated=float(np.mean(pairs)),
            tolerance=2.0 * res / expect_h,
            derivation=(
                f"mean over {len(pairs)} transitions seen both heating and cooling; each "
                f"temperature resolved to one sample's block change ({res:.4f} K)"
            ),
        ),
    ]


#: dead-band check: inputs from DB_LOW band in DB_STEP steps (the closed form sits mid-cell), and
#: the start phases of the one-period map on [0, 2 pi)
DB_LOW, DB_STEP, DB_INPUTS = 0.885, 0.01, 24
DB_PHASES = 128


def _check_dead_band() -> Check:
    """The locked band of a fixed-amplitude dithered gyro from the one-period map of the Adler
    equation.

    The dither is periodic, so one dither period of the RK4 integration is a map P of the beat
    phase, a lift of an orientation-preserving circle map (P(psi + 2 pi) = P(psi) + 2 pi). By
    Poincare's theorem its rotation number (the mean slips per period) is 0 exactly when
    D(psi) = P(psi) - psi has a zero, i.e. when the gyro is locked: so each input is integrated
    over one period from DB_PHASES start phases side by side (instead of one phase over many
    periods, which sees a slow slip just above the edge only after a long time) and is locked
    when min D <= 0 <= max D. The sampled minimum exceeds the true one by at most
    max|D''| delta^2/8 (delta = 2 pi/DB_PHASES), which can make the last locked input look
    unlocked: the edge estimate then moves down by at most that over dmin D/dOmega.
    """
    from scipy.special import j0

    k, wl, fd, beta = 1000.0, 0.01, 50.0, 20.0
    theta = beta / (2.0 * math.pi * k)
    w = 2.0 * math.pi * fd
    od = w * theta
    band = wl * abs(float(j0(beta)))
    grid = band * (DB_LOW + DB_STEP * np.arange(DB_INPUTS))
    col = grid[:, None]

    def rate(t: float) -> np.ndarray:
        return col + od * math.cos(w * t)

    n_per = int(math.ceil(16.0 * k * od * 1.05 / fd))
    phases = 2.0 * math.pi * np.arange(DB_PHASES) / DB_PHASES
    psi = integrate_adler(
        rate, 1.0 / fd, scale_factor=k, lock_in_rate=wl, dt=1.0 / (fd * n_per),
        psi0=np.broadcast_to(phases, (DB_INPUTS, DB_PHASES)), sample_every=n_per,
    )
    d = psi[-1] - psi[0]  # D(psi) per input (rows) and start phase (columns)
    d_min = d.min(axis=1)
    locked = (d_min <= 0.0) & (d.max(axis=1) >= 0.0)
    unlocked = np.flatnonzero(~locked)
    # an edge outside the grid (every input slips, or none does) is no edge: NaN fails the check.
    # Inside the cell [last locked, first slipping] the edge is where min D crosses 0 (linear
    # interpolation: min D is smooth in the input through the saddle-node), never outside the cell
    edge = math.nan
    if unlocked.size and unlocked[0] > 0:
        i = int(unlocked[0])
        lo, hi = float(d_min[i - 1]), float(d_min[i])
        frac = -lo / (hi - lo) if lo <= 0.0 < hi else 0.5
        edge = float(grid[i - 1] + frac * (grid[i] - grid[i - 1]))
    # sampling bound: max |D''| delta^2 / 8 (D'' from second differences), over the smallest
    # slope of min D against the input between neighbouring inputs. min D rises with the input
    # (a larger input advances P(psi) at every psi); where it does not, the model is wrong and the
    # bound has no premise: the edge is NaN, a failed check (an infinite tolerance would make Check
    # raise, and physics_checks would stop with an internal error instead of reporting the failure)
    delta = 2.0 * math.pi / DB_PHASES
    d2 = float(np.max(np.abs(np.roll(d, 1, axis=1) - 2.0 * d + np.roll(d, -1, axis=1)))) / delta**2
    slope = float(np.min(np.diff(d_min) / np.diff(grid)))
    sampling = d2 * delta**2 / 8.0 / slope / band if slope > 0 else 0.0
    if not slope > 0:
        edge = math.nan
    return Check(
        id="rlg_cavity.dead_band_width",
        kind=CLOSED_FORM,
        reference=CHOW + " (dithered lock-in: the dead band scales with |J_0| of the dither amplitude); " + ARONOWITZ,
        formula="dead band half-width = Omega_L |J_0(2 pi K theta_D)| [rad/s] (fixed dither)",
        expected=band,
        simulated=edge,
        tolerance=DB_STEP / 2.0 + sampling,
        derivation=(
            f"Adler RK4, K = {k:g}/rad, Omega_L = {wl} rad/s, f_d = {fd:g} Hz, beta_D = {beta:g}, "
            f"{DB_INPUTS} inputs {DB_LOW:g}-{DB_LOW + DB_STEP * (DB_INPUTS - 1):g} x the band in "
            f"steps of {DB_STEP:.0%} (the closed form mid-cell); an input is locked when the "
            f"one-period map's phase advance P(psi) - psi has a zero over {DB_PHASES} start "
            "phases (Poincare: rotation number 0); edge = the zero of min P(psi) - psi interpolated "
            "between the last locked and first slipping input, so within their cell: half the grid "
            "step plus the phase-sampling bound "
            f"max|D''| delta^2/8 / (dmin D/dOmega) = {sampling:.1g} of the band. First-order "
            "(Jacobi-Anger) averaging is what is tested, so its own error is not in the tolerance"
        ),
    )


def _check_randomized_dead_band(rng: np.random.Generator) -> Check:
    from scipy.special import j0

    # phase jitter per swing sigma beta_D = 6 rad (the default gyro: 0.1 x 5.9e3 rad); at
    # sigma = 0.1 here (2 rad) a residual compression of ~4 % (5 standard errors) remains
    k, wl, fd, beta, sigma = 1000.0, 0.01, 50.0, 20.0, 0.3
    m, n_cyc = 2000, 7
    omega = 0.5 * wl * abs(float(j0(beta)))  # half the fixed-amplitude dead band
    dith, dur, angle = _swing_adler_angles(k, wl, fd, beta, sigma, m, n_cyc, omega, rng)
    rate = angle / dur
    n_stat = swing_dither_arw(scale_factor=k, lock_in_rate=wl, dither=dith)
    return Check(
        id="rlg_cavity.no_dead_band_with_swing_dither",
        kind=CLOSED_FORM,
        reference=KILLPATRICK + "; " + CHOW,
        formula="mean output rate = input rate (no dead band), input = Omega_L |J_0(beta_D)| / 2",
        expected=omega,
        simulated=float(np.mean(rate)),
        tolerance=Z_FALSE_ALARM * n_stat / math.sqrt(dur * m) / omega,
        derivation=(
            f"Adler RK4 over {n_cyc} cycles, {m} realizations of the swing-randomized dither "
            f"(sigma = {sigma}, phase jitter per swing sigma beta_D = {sigma * beta:g} rad; the "
            "same gyro with a fixed amplitude locks at this input, see "
            "rlg_cavity.dead_band_width): the mean of M recovered rates has sd N/sqrt(T M) "
            f"(N = {n_stat:.3e} rad/sqrt(s)), times z = {Z_FALSE_ALARM} (false alarm "
            f"{FALSE_ALARM:g}); this is what lets the statistical mode omit the dead band"
        ),
    )


def _swing_adler_angles(
    k: float,
    wl: float,
    fd: float,
    beta: float,
    sigma: float,
    m: int,
    n_cyc: int,
    rate: float,
    rng: np.random.Generator,
) -> tuple[Dither, float, NDArray[np.float64]]:
    """m realizations of the Adler equation (RK4, 16 steps per beat at the jittered peak rate)
    under a constant ``rate`` plus a swing-randomized dither of beta_D = ``beta`` (K = k/rad,
    Omega_L = ``wl``, f_d = ``fd``, amplitude jitter ``sigma``) for ``n_cyc`` dither cycles.

    Returns the dither, the duration T [s] and each realization's recovered angle over T
    [rad]: the counted phase / (2 pi K) minus the dither's own angle.
    """
    dith = Dither(frequency=fd, amplitude=beta / (2.0 * math.pi * k), amplitude_jitter=sigma)
    r_sw, r_psi = rng.spawn(2)
    sw = SwingDither.draw(dith, n_cyc, rng=r_sw, size=m)
    psi0 = r_psi.uniform(0.0, 2.0 * math.pi, m)
    n_per = int(math.ceil(16.0 * k * dith.peak_rate * (1.0 + 3.0 * sigma) / fd))
    dur = n_cyc / fd
    psi = integrate_adler(
        lambda t: rate + sw.rate(t), dur, scale_factor=k, lock_in_rate=wl,
        dt=1.0 / (fd * n_per), psi0=psi0, sample_every=n_per * n_cyc,
    )
    return dith, dur, (psi[-1] - psi0) / (2.0 * math.pi * k) - sw.angle(dur)


def _check_random_walk(rng: np.random.Generator) -> Check:
    k, wl, fd, beta, sigma = 1000.0, 0.05, 50.0, 30.0, 0.1
    m, n_cyc = 3200, 5
    earth = units.EARTH_RATE * math.cos(LATITUDE)
    dith, dur, angle = _swing_adler_angles(k, wl, fd, beta, sigma, m, n_cyc, earth, rng)
    err = angle - earth * dur
    n_stat = swing_dither_arw(scale_factor=k, lock_in_rate=wl, dither=dith)
    expected = n_stat**2 * dur
    var = float(np.var(err, ddof=1))
    kurt = float(np.mean((err - err.mean()) ** 4) / np.mean((err - err.mean()) ** 2) ** 2)
    rel_sd = math.sqrt((kurt - 1.0 + 2.0 / (m - 1)) / m)
    return Check(
        id="rlg_cavity.dither_random_walk",
        kind=CLOSED_FORM,
        reference=KILLPATRICK + "; " + CHOW,
        formula=(
            "var(angle error after T) = N^2 T, N = Omega_L sqrt((1 + sigma^2/2)/(2 pi K Omega_D))"
        ),
        expected=expected,
        simulated=var,
        tolerance=Z_FALSE_ALARM * rel_sd,
        derivation=(
            f"Adler RK4 over {n_cyc} dither cycles, {m} realizations (swing-randomized dither, "
            f"sigma = {sigma}, K = {k:g}/rad, Omega_L = {wl} rad/s, f_d = {fd:g} Hz, beta_D = "
            f"{beta:g}) with the Earth's north rate at 39.9 N ({earth:.4e} rad/s) as input; "
            f"sample variance: relative sd sqrt((kurtosis - 1)/M) with the measured kurtosis "
            f"{kurt:.2f}, times z = {Z_FALSE_ALARM} (two-sided false alarm {FALSE_ALARM:g})"
        ),
    )


def parts(rng: np.random.Generator) -> list[Part]:
    """The checks in five independent parts (streams drawn here, in a fixed order).

    Parameters
    ----------
    rng : numpy.random.Generator
        The module's stream (the collector's contract; a deterministic module does not draw from it).

    Returns
    -------
    list of Part
        Independent parts, each with its own arguments (children of ``rng`` where it draws).
    """
    r_unit, r_rw, r_db, r_lock = rng.spawn(4)  # r_lock last: the others keep their streams
    u = CavityRLGSpec().realize(rng=r_unit, label="check unit")
    # a block at 0.8 x the class-2 bound: several hops in the -40..+65 degC cycle
    hop_unit = replace(u, cte=0.8 * ZERODUR_CTE_CLASS_2)
    return [
        Part("lock_in", _check_lock_in, (u, r_lock)),
        Part("mode_hops", _hop_checks, (hop_unit,)),
        Part("dead_band", _check_dead_band),
        Part("random_walk", _check_random_walk, (r_rw,)),
        Part("no_dead_band", _check_randomized_dead_band, (r_db,)),
    ]


def checks(rng: np.random.Generator) -> list[Check]:
    """The cavity RLG's closed-form checks (see module docstring).

    Parameters
    ----------
    rng : numpy.random.Generator
        The module's stream (the collector's contract; a deterministic module does not draw from it).

    Returns
    -------
    list of Check
        The module's checks.
    """
    return run_parts(parts(rng))
