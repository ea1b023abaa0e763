"""Model terms beyond Q/N/B/K/R chosen by the data: Gauss-Markov, sinusoid, the sensor's own low-pass.

:func:`select_model` starts from an IEEE 952 fit (:func:`gyrobench.analysis.allan.fit_noise`)
and asks, by a stated test, whether the Allan variance needs

* a first-order Gauss-Markov process (sigma [u], correlation time Tc [s]), AVAR
  sigma^2 g(r) / r^2, r = tau / Tc, g(r) = 2 r - 3 + 4 e^-r - e^-2r (IEEE Std 952-1997 Annex C,
  exponentially correlated noise; docs/physics.md 1.2);
* a sinusoid (amplitude A [u], period P [s]), the phase-averaged AVAR of its samples
  A^2 sin^4(pi tau / P) / (m sin(pi / (P fs)))^2, m = tau fs (IEEE Std 952-1997 Annex C.7
  in continuous time, A^2 (sin^2(pi f0 tau) / (pi f0 tau))^2);
* the sensor's own low-pass on the white rate noise: a digital Butterworth of order n and
  corner f_c applied once or forward and backward (``scipy.signal.filtfilt``), whose AVAR on
  white noise N^2 is exact from the filter's autocovariance (:func:`filter_shape`); it
  replaces the N column N^2 / tau by N^2 g_f(tau) / tau, so the filter-bent short taus are
  fitted, not thrown away.

Criterion (forward selection, each step a likelihood-ratio test): on the fitted points, the
generalised least squares (NNLS) of the IEEE columns plus a candidate's column (its time
scale on a log grid, its amplitude by NNLS) with the base fit's modelled covariance V of the
Allan points (:attr:`gyrobench.analysis.allan.NoiseFit.point_covariance`, correlated across
tau) gives chi2 = r' V^-1 r. At a fixed time scale a family is linear in its amplitude, so
the drop D = chi2_before - chi2_after is chi2(1) when the term is absent (V as modelled, the
amplitude away from its bound 0); over the G time scales of the grid (G = :data:`GRID`) the
largest drop is compared with the chi2(1) quantile at ``level`` / G (Bonferroni: a family
false-alarm rate of at most ``level``, default 0.01, and at most 1 - (1 - level)^2 for the
two families). The larger drop goes first, then the other family is tried once more. V's
modelled correlations are too high (see ``fit_noise``), so the bound is checked by simulation:
benchmarks/model_select_false_alarm.py (200 records of the five-term model).
The low-pass is tested on the points the range rule excluded plus the fitted ones, against
the five terms on those points (Bonferroni over its grid of orders, passes and corners),
with diagonal weights var_i = 2 A_model(tau_i)^2 / edf_i
(V is modelled on the fitted points only) scaled by s = chi2_expected / dof of the base fit.
The amplitudes' intervals are conditional on the chosen time scale: (X' V^-1 X)^-1.

Reference for the approach (the generalised method of wavelet moments does the same on the
wavelet variance with a Wavelet Information Criterion): S. Guerrier et al., "Wavelet-variance-
based estimation for composite stochastic processes", JASA 108 (2013) 1021-1030.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from gyrobench.analysis.allan import NoiseFit

__all__ = ["ExtraTerm", "ModelChoice", "filter_shape", "gm_shape", "select_model", "sine_shape"]

#: the level of each forward step's test (a false alarm per family on a five-term record)
LEVEL = 0.01
#: time scales tried per family (the Bonferroni count of the criterion): 40 Gauss-Markov
#: correlation times, 48 sinusoid periods; the larger is used for both
GRID = 48
_POWERS = {"Q": -2, "N": -1, "B": 0, "K": 1, "R": 2}
#: filter orders and passes tried when the low-pass is identified from the data
FILTER_ORDERS = (1, 2, 4)
FILTER_PASSES = (1, 2)


@dataclass(frozen=True, slots=True, kw_only=True)
class ExtraTerm:
    """One term beyond the IEEE five, with its parameters in SI.

    Attributes
    ----------
    kind : {"gauss_markov", "sinusoid", "lowpass"}
    params : dict of str to float
        gauss_markov: ``sigma`` [u], ``tc`` [s]; sinusoid: ``amplitude`` [u], ``period`` [s];
        lowpass: ``corner`` [Hz], ``order``, ``passes`` (1 or 2: forward/backward), the model's
        ``N`` it acts on, and ``C_Q``, the quantization AVAR coefficient refitted with it.
    interval : tuple of float
        95 % interval of the amplitude parameter (sigma or amplitude): the GLS standard error of
        its square, conditional on the time scale, about the refitted value; for the low-pass
        that of N.
    drop : float
        The criterion's scaled chi2 drop D when it was added.
    given : bool
        True for a low-pass given by the user (not chosen).
    """

    kind: str
    params: dict[str, float]
    interval: tuple[float, float]
    drop: float
    given: bool = False

    def describe(self, rate_unit: float = 1.0, unit: str = "u") -> str:
        """One line, amplitudes divided by ``rate_unit`` and labelled ``unit``."""
        p = self.params
        if self.kind == "gauss_markov":
            return (f"Gauss-Markov sigma {p['sigma'] / rate_unit:.4g} [{self.interval[0] / rate_unit:.3g}, "
                    f"{self.interval[1] / rate_unit:.3g}] {unit}, Tc {p['tc']:.4g} s")
        if self.kind == "sinusoid":
            return (f"sinusoid amplitude {p['amplitude'] / rate_unit:.4g} [{self.interval[0] / rate_unit:.3g}, "
                    f"{self.interval[1] / rate_unit:.3g}] {unit}, period {p['period']:.4g} s")
        return (f"low-pass: Butterworth order {int(p['order'])}, corner {p['corner']:.4g} Hz, "
                f"{'forward and backward' if int(p['passes']) == 2 else 'one pass'}")


@dataclass(frozen=True, slots=True, kw_only=True)
class ModelChoice:
    """Result of :func:`select_model`.

    Attributes
    ----------
    extra : tuple of ExtraTerm
        The chosen terms (empty: the five IEEE terms suffice).
    avar_coefficients : dict of str to float
        C_n of the IEEE terms in the chosen model (on the fitted points).
    chi2, dof, scale : float
        The chosen model's GLS chi2 on the fitted points, its degrees of freedom, and the
        scale s used by the low-pass test's diagonal chi2.
    p_value : float
        P(chi2(dof) >= chi2) of the GLS chi2 (approximate: V's correlations are modelled too
        high, so this p runs low); small means the chosen model still misfits.
    drops : dict of str to float
        Every family's best chi2 drop D at the first step (for the report).
    threshold : float
        The chi-square(1) quantile at level / GRID the drops were compared with.
    criterion : str
        The rule in one line.
    """

    extra: tuple[ExtraTerm, ...]
    avar_coefficients: dict[str, float]
    chi2: float
    dof: int
    scale: float
    p_value: float
    drops: dict[str, float] = field(default_factory=dict)
    threshold: float = float("nan")
    criterion: str = ""

    @property
    def misfit(self) -> bool:
        """The chosen model misfits at the level of the criterion."""
        return bool(self.dof > 0 and self.p_value < LEVEL)

    def term(self, kind: str) -> ExtraTerm | None:
        """The chosen term of ``kind``, or None."""
        return next((t for t in self.extra if t.kind == kind), None)


def gm_shape(tau: NDArray[np.float64], tc: float) -> NDArray[np.float64]:
    """AVAR of a unit-variance first-order Gauss-Markov process, g(r) / r^2, r = tau / Tc (no cancellation).

    Parameters
    ----------
    tau : ndarray
        Cluster times [s].
    tc : float
        Correlation time Tc [s], > 0.

    Returns
    -------
    ndarray
        AVAR(tau) / sigma^2 [-], with g(r) = 2 r + 4 (e^-r - 1) - (e^-2r - 1); a series for r < 0.5.
    """
    r = np.asarray(tau, dtype=float) / tc
    out = np.empty_like(r)
    small = r < 0.5
    rs = r[small]
    acc = np.zeros_like(rs)
    term = rs**3 / 6.0
    for k in range(3, 24):  # g(r) = sum_k>=3 (-1)^k (4 - 2^k) r^k / k!
        acc += (-1) ** k * (4.0 - 2.0**k) * term
        term = term * rs / (k + 1)
    out[small] = acc
    rl = r[~small]
    out[~small] = 2.0 * rl + 4.0 * np.expm1(-rl) - np.expm1(-2.0 * rl)
    return out / r**2


def sine_shape(tau: NDArray[np.float64], period: float, fs: float) -> NDArray[np.float64]:
    """Phase-averaged AVAR of the samples of a unit sine of ``period``: sin^4(pi tau/P) / (m sin(pi/(P fs)))^2.

    Parameters
    ----------
    tau : ndarray
        Cluster times [s], multiples of 1/fs.
    period : float
        The sine's period P [s].
    fs : float
        Sample rate [Hz].

    Returns
    -------
    ndarray
        AVAR(tau) / A^2 of a unit-amplitude sine [-], averaged over its phase.
    """
    tau = np.asarray(tau, dtype=float)
    m = tau * fs
    sx = math.sin(math.pi / (period * fs))
    return np.sin(np.pi * tau / period) ** 4 / (m * sx) ** 2


@functools.lru_cache(maxsize=512)
def _filter_acov(order: int, corner_frac: float, passes: int, n_fft: int = 1 << 15) -> NDArray[np.float64]:
    """Autocovariance r_k (r_0 ... ) of unit white noise through the digital Butterworth, |H|^(2 passes)."""
    from scipy.signal import butter, sosfreqz

    sos = butter(order, corner_frac, output="sos")  # corner as a fraction of Nyquist
    _, h = sosfreqz(sos, worN=n_fft // 2 + 1, whole=False)
    p = np.abs(h) ** (2 * passes)
    return np.fft.irfft(p, n=n_fft)[: n_fft // 2]


def filter_shape(m: NDArray[np.int64], order: int, corner: float, fs: float, passes: int = 1) -> NDArray[np.float64]:
    """g_f(m) = AVAR(m) / (sigma^2 / m) of white noise of variance sigma^2 through a Butterworth low-pass.

    Parameters
    ----------
    m : array of int
        Averaging factors (tau = m / fs).
    order : int
        Butterworth order n (``scipy.signal.butter``).
    corner : float
        -3 dB frequency of one pass [Hz], 0 < corner < fs / 2.
    fs : float
        Sample rate [Hz].
    passes : {1, 2}
        1: the filter once; 2: forward and backward (zero phase, |H|^4).

    Returns
    -------
    ndarray
        g_f(m) at each averaging factor [-] (1 for an all-pass filter).

    Notes
    -----
    With r_k the output autocovariance (the inverse DFT of |H|^(2 passes) on 2^15 points,
    sigma = 1, r summing to |H(0)|^2 = 1) the variance of a sum of m samples is
    D(m) = sum_{|k|<m} (m - |k|) r_k and the overlapping AVAR expectation is
    (4 D(m) - D(2m)) / (2 m^2) (docs/physics.md 1.7, as in
    :func:`gyrobench.analysis.allan.lowpass_avar_bias`); beyond the 2^14 stored lags
    D(m) = m - sum |k| r_k, exact once r has died out.
    """
    acov = _filter_acov(int(order), float(corner / (fs / 2.0)), int(passes))
    k = np.arange(acov.size, dtype=float)
    two_sided = np.concatenate([[acov[0]], 2.0 * acov[1:]])
    c0 = np.cumsum(two_sided)  # sum_{|k| <= K} r_k
    c1 = np.cumsum(k * two_sided)  # sum_{|k| <= K} |k| r_k

    def d(mm: NDArray[np.float64]) -> NDArray[np.float64]:
        idx = np.minimum(mm.astype(np.int64) - 1, acov.size - 1)
        return mm * c0[idx] - c1[idx]

    mf = np.asarray(m, dtype=float)
    return (4.0 * d(mf) - d(2.0 * mf)) / (2.0 * mf)


def _nnls(a: NDArray[np.float64], b: NDArray[np.float64]) -> tuple[NDArray[np.float64], float]:
    """argmin_{c >= 0} ||a c - b|| and the residual norm: Lawson-Hanson (numpy) up to 6 columns, else scipy."""
    from gyrobench.analysis.allan._nnls import _NNLS_ENUM, _nnls_enumerate

    if a.shape[1] <= _NNLS_ENUM:
        c = _nnls_enumerate(a, b)
    else:  # two extra terms on the five: rare, scipy's solver
        from scipy.optimize import nnls

        c, _ = nnls(a, b, maxiter=100 * a.shape[1])
    return c, float(np.linalg.norm(a @ c - b))


def _wls(
    x: NDArray[np.float64], a: NDArray[np.float64], nu: NDArray[np.float64]
) -> tuple[NDArray[np.float64], float, NDArray[np.float64]]:
    """NNLS with weights 1/var, var = 2 A_model^2 / nu, reweighted twice from the data's own weights."""
    var = 2.0 * a**2 / nu
    c = np.zeros(x.shape[1])
    for _ in range(3):
        sw = 1.0 / np.sqrt(var)
        xw = x * sw[:, None]
        sc = np.linalg.norm(xw, axis=0)
        sc[sc == 0] = 1.0
        cs, _ = _nnls(xw / sc, a * sw)
        c = cs / sc
        model = x @ c
        var = np.where(model > 0, 2.0 * model**2 / nu, var)
    r = a - x @ c
    return c, float(np.sum(r**2 / var)), var


def _gls(x: NDArray[np.float64], a: NDArray[np.float64], li: NDArray[np.float64]) -> tuple[NDArray[np.float64], float]:
    """argmin_{C >= 0} (a - X C)' V^-1 (a - X C) with li = L^-1, V = L L'; returns C and the minimum."""
    xw, aw = li @ x, li @ a
    sc = np.linalg.norm(xw, axis=0)
    sc[sc == 0] = 1.0
    cs, rn = _nnls(xw / sc, aw)
    return cs / sc, float(rn**2)


def _diag_nnls(x: NDArray[np.float64], a: NDArray[np.float64], var: NDArray[np.float64]) -> NDArray[np.float64]:
    """argmin_{C >= 0} sum_i (a_i - x_i C)^2 / var_i."""
    sw = 1.0 / np.sqrt(var)
    xw = x * sw[:, None]
    sc = np.linalg.norm(xw, axis=0)
    sc[sc == 0] = 1.0
    cs, _ = _nnls(xw / sc, a * sw)
    return cs / sc


def _gls_cov(x: NDArray[np.float64], li: NDArray[np.float64], c: NDArray[np.float64]) -> NDArray[np.float64]:
    keep = c > 0
    out = np.zeros((x.shape[1], x.shape[1]))
    if keep.any():
        xw = li @ x[:, keep]
        out[np.ix_(keep, keep)] = np.linalg.pinv(xw.T @ xw)
    return out


def _cov(x: NDArray[np.float64], var: NDArray[np.float64], c: NDArray[np.float64], scale: float) -> NDArray[np.float64]:
    keep = c > 0
    out = np.zeros((x.shape[1], x.shape[1]))
    if keep.any():
        xk = x[:, keep]
        info = xk.T @ (xk / var[:, None])
        out[np.ix_(keep, keep)] = np.linalg.pinv(info) * scale
    return out


def _interval(c: float, var_c: float) -> tuple[float, float]:
    se = math.sqrt(max(var_c, 0.0))
    return math.sqrt(max(c - 1.96 * se, 0.0)), math.sqrt(max(c + 1.96 * se, 0.0))


def select_model(
    fit: NoiseFit,
    *,
    level: float = LEVEL,
    families: tuple[str, ...] = ("gauss_markov", "sinusoid", "lowpass"),
    lowpass: tuple[int, float, int] | None = None,
) -> ModelChoice:
    """Choose the extra terms a fitted Allan variance needs (module docstring for the criterion).

    Parameters
    ----------
    fit : NoiseFit
        The IEEE 952 fit (overlapping or standard Allan variance).
    level : float
        Level of each forward step's test, in (0, 1).
    families : tuple of str
        Families to try, of "gauss_markov", "sinusoid", "lowpass".
    lowpass : (order, corner [Hz], passes), optional
        A known low-pass: evaluated on the excluded plus fitted points, not chosen.

    Returns
    -------
    ModelChoice
    """
    from gyrobench.analysis.allan._chi2 import chi2_isf, chi2_sf  # numpy only: no scipy.stats import

    if not (0.0 < level < 1.0):
        raise ValueError(f"level must be in (0, 1); got {level!r}")
    curve = fit.curve
    names = tuple(fit.avar_coefficients)
    tau_all = np.asarray(curve.tau, dtype=float)
    a_all = np.asarray(curve.variance, dtype=float)
    nu_all = np.maximum(np.asarray(curve.edf, dtype=float), 1.0)
    used = np.asarray(fit.used, dtype=bool)
    tau, a = tau_all[used], a_all[used]
    base = np.column_stack([tau ** _POWERS[t] for t in names])
    scale = fit.chi2_expected / fit.dof if fit.dof > 0 and math.isfinite(fit.chi2_expected) else 1.0
    scale = max(scale, 1e-3)
    threshold = float(chi2_isf(level / GRID, 1.0))
    v = np.asarray(fit.point_covariance, dtype=float)
    try:
        li = np.linalg.inv(np.linalg.cholesky(v + np.eye(v.shape[0]) * 1e-12 * float(np.trace(v)) / v.shape[0]))
    except np.linalg.LinAlgError:
        li = np.diag(1.0 / np.sqrt(np.maximum(np.diag(v), 1e-300)))
    _, chi0 = _gls(base, a, li)
    columns: list[NDArray[np.float64]] = []
    extra: list[ExtraTerm] = []
    drops: dict[str, float] = {}
    chi_cur = chi0
    n_pts = tau.size
    t_rec = curve.n_samples / curve.fs
    candidates = [f for f in families if f in ("gauss_markov", "sinusoid")]
    for step in range(len(candidates)):
        if n_pts < len(names) + len(columns) + 3:
            break
        tried = {fam: _family_best(fam, tau, a, li, np.column_stack([base, *columns]), curve.fs, t_rec)
                 for fam in candidates if not any(e.kind == fam for e in extra)}
        found = {fam: b for fam, b in tried.items() if b is not None}
        if step == 0:
            drops = {fam: chi_cur - b[0] if b is not None else 0.0 for fam, b in tried.items()}
        if not found:
            break
        fam = min(found, key=lambda f: found[f][0])
        chi, s_par, c, col = found[fam]
        drop = chi_cur - chi
        if not drop > threshold:
            break
        x = np.column_stack([base, *columns, col])
        cov = _gls_cov(x, li, c)
        amp = float(c[-1])
        lo, hi = _interval(amp, float(cov[-1, -1]))
        params = {"sigma": math.sqrt(amp), "tc": s_par} if fam == "gauss_markov" else {"amplitude": math.sqrt(amp),
                                                                                        "period": s_par}
        extra.append(ExtraTerm(kind=fam, params=params, interval=(lo, hi), drop=float(drop)))
        columns.append(col)
        chi_cur = chi
    xf = np.column_stack([base, *columns])
    cg, chif = _gls(xf, a, li)
    dof = max(n_pts - int(np.sum(cg > 0)), 0)
    # the chosen model's coefficients: weighted NNLS with the points' own variances diag(V), as fit_noise
    # weights (the GLS solution follows V's too-high correlations into the near-null directions)
    cf = _diag_nnls(xf, a, np.maximum(np.diag(v), 1e-300)) if extra else np.array(
        [fit.avar_coefficients[t] for t in names])
    if extra:  # the extra amplitudes, refitted alike
        for j, e in enumerate(extra):
            amp = float(cf[len(names) + j])
            key = "sigma" if e.kind == "gauss_markov" else "amplitude"
            se = (e.interval[1] ** 2 - e.params[key] ** 2) / 1.96  # the GLS standard error of the squared amplitude
            extra[j] = ExtraTerm(kind=e.kind, params={**e.params, key: math.sqrt(max(amp, 0.0))},
                                 interval=_interval(amp, se**2), drop=e.drop)
    p = float(chi2_sf(chif, float(dof))) if dof > 0 else float("nan")
    lp = None
    if "lowpass" in families or lowpass is not None:
        n_lp = len(FILTER_ORDERS) * len(FILTER_PASSES) * 28
        lp = _lowpass(fit, names, cf, tau_all, a_all, nu_all, used, scale, float(chi2_isf(level / n_lp, 1.0)),
                      lowpass, tuple(extra))
        if lp is not None:
            extra.append(lp)
    return ModelChoice(
        extra=tuple(extra),
        avar_coefficients={t: float(v) for t, v in zip(names, cf[: len(names)], strict=True)},
        chi2=chif, dof=dof, scale=scale, p_value=p, drops=drops, threshold=threshold,
        criterion=(f"forward selection: a Gauss-Markov or sinusoid term is added when its GLS chi2 drop (the fit's "
                   f"correlated point covariance) exceeds {threshold:.3g}, the chi2(1) quantile at level {level:g} / "
                   f"{GRID} time scales (Bonferroni)"),
    )


def _grid(fam: str, tau: NDArray[np.float64], fs: float, t_rec: float) -> NDArray[np.float64]:
    """Time scales tried: Tc over the fitted taus (40), or periods from 2 tau_1 to 1.5 x the record (48)."""
    if fam == "gauss_markov":
        return np.geomspace(tau[0], tau[-1], 40)
    return np.geomspace(max(2.0 * tau[0], 4.0 / fs), 1.5 * t_rec, 48)


def _family_best(fam: str, tau, a, li, x0, fs: float, t_rec: float):
    """(chi2, time scale, C, column) of the family's best time scale with a positive amplitude, or None."""
    best = None
    for s_par in _grid(fam, tau, fs, t_rec):
        col = gm_shape(tau, s_par) if fam == "gauss_markov" else sine_shape(tau, s_par, fs)
        c, chi = _gls(np.column_stack([x0, col]), a, li)
        if c[-1] > 0 and (best is None or chi < best[0]):
            best = (chi, float(s_par), c, col)
    return best


def _lowpass(fit: NoiseFit, names, coef: NDArray[np.float64], tau_all, a_all, nu_all, used, scale: float,
             threshold: float, given: tuple[int, float, int] | None,
             others: tuple[ExtraTerm, ...] = ()) -> ExtraTerm | None:
    """The low-pass term on the excluded + fitted points: chosen on a grid, or the given one evaluated.

    The chosen model's coefficients ``coef`` (in the order of ``names``) and ``others`` (its
    Gauss-Markov and sinusoid terms) are held but for N, refitted within its 95 % interval from
    the fitted taus, and the quantization coefficient C_Q (noise added after the filter, at the
    bent taus), refitted >= 0 (bounded least squares, ``scipy.optimize.lsq_linear``). So the
    filter explains the bend, and a feature of the short taus that it cannot (a tone above the
    fitted range) does not pull N outside what the fitted taus allow.
    """
    if "N" not in names:
        return None
    last = int(np.flatnonzero(used)[-1])
    first = 0
    if fit.range_rule == "user":
        first = int(np.flatnonzero(used)[0])
    sel = np.zeros(tau_all.size, dtype=bool)
    sel[first : last + 1] = True
    if given is None and (fit.range_rule != "data" or sel.sum() <= used.sum()):
        return None  # no filter-shaped region was excluded: no bend to identify
    tau, a, nu = tau_all[sel], a_all[sel], nu_all[sel]
    fs = fit.curve.fs
    m = np.rint(tau * fs).astype(np.int64)
    jn = names.index("N")
    held = np.zeros(tau.size)
    for j, t in enumerate(names):
        if t not in ("N", "Q"):
            held = held + coef[j] * tau ** _POWERS[t]
    for e in others:
        held = held + (e.params["sigma"] ** 2 * gm_shape(tau, e.params["tc"]) if e.kind == "gauss_markov"
                       else e.params["amplitude"] ** 2 * sine_shape(tau, e.params["period"], fs))
    from scipy.optimize import lsq_linear

    q_col = tau**-2.0 if "Q" in names else np.zeros(tau.size)
    c_n = fit.coefficients.get("N")
    # N may move within its 95 % interval from the fitted taus (as an AVAR coefficient), no further
    n_lo, n_hi = (coef[jn], coef[jn]) if c_n is None else (float(c_n.ci95[0]) ** 2, float(c_n.ci95[1]) ** 2)
    n_lo, n_hi = min(n_lo, coef[jn]), max(n_hi, coef[jn] * (1 + 1e-12))

    def chi_of(g: NDArray[np.float64]) -> tuple[float, float, float]:
        x = np.column_stack([g / tau, q_col])
        var = 2.0 * a**2 / nu
        sol = np.array([coef[jn], 0.0])
        for _ in range(3):
            sw = 1.0 / np.sqrt(var)
            xs = x * sw[:, None]
            sc = np.where(np.linalg.norm(xs, axis=0) > 0, np.linalg.norm(xs, axis=0), 1.0)
            res = lsq_linear(xs / sc, (a - held) * sw, bounds=([n_lo * sc[0], 0.0], [n_hi * sc[0], np.inf]))
            sol = res.x / sc
            model = held + x @ sol
            var = np.where(model > 0, 2.0 * model**2 / nu, var)
        r = a - held - x @ sol
        return float(np.sum(r**2 / var)), float(sol[1]), float(sol[0])

    chi0 = chi_of(np.ones(tau.size))[0]
    trials = ([given] if given is not None else
              [(o, fc, p) for o in FILTER_ORDERS for p in FILTER_PASSES
               for fc in np.geomspace(0.01 * fs, 0.45 * fs, 28)])
    best = None
    for order, fc, passes in trials:
        chi, cq, cn = chi_of(filter_shape(m, int(order), float(fc), fs, int(passes)))
        if best is None or chi < best[0]:
            best = (chi, (int(order), float(fc), int(passes)), cq, cn)
    assert best is not None
    if given is None:  # refine the corner between its grid neighbours (bounded scalar minimisation in log f_c)
        from scipy.optimize import minimize_scalar

        o0, f0, p0 = best[1]
        step = (0.45 / 0.01) ** (1.0 / 27.0)
        hi_fc = min(math.log(f0 * step), math.log(0.45 * fs))
        r = minimize_scalar(lambda lf: chi_of(filter_shape(m, o0, math.exp(lf), fs, p0))[0],
                            bounds=(math.log(f0 / step), hi_fc), method="bounded", options={"xatol": 1e-4})
        if r.fun < best[0]:
            chi, cq, cn = chi_of(filter_shape(m, o0, math.exp(r.x), fs, p0))
            best = (chi, (o0, float(math.exp(r.x)), p0), cq, cn)
    chi, (order, fc, passes), cq, cn = best
    drop = (chi0 - chi) / scale
    if given is None and not drop > threshold:
        return None
    interval = (0.0, 0.0) if c_n is None else (float(c_n.ci95[0]), float(c_n.ci95[1]))
    return ExtraTerm(kind="lowpass", params={"corner": fc, "order": float(order), "passes": float(passes),
                                             "N": math.sqrt(max(cn, 0.0)), "C_Q": cq},
                     interval=interval, drop=float(drop), given=given is not None)
