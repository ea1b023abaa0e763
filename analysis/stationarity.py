"""Checks that a static record is static, and removal of its temperature-explained part.

Allan analysis assumes a stationary noise process (plus at most a rate ramp). A record with
handling motion or a step, or with a temperature swing, violates that: the motion or the
thermal drift is then reported as noise terms (a rate ramp or random walk with a tight
interval). Two tools:

* :func:`stationarity_check`: windows of length tau_w; flags windows whose variance is
  far above the record's median window variance (motion) and jumps between adjacent
  window means far above what the record's own Allan deviation at tau_w allows (steps).
* :func:`remove_temperature`: least-squares fit of the rate on the temperature and its
  rate of change, y = c0 + c_T (T - Tbar) + c_dT dT/dt + e, and the rate minus the
  explained part.

References: IEEE Std 952-1997 Annex C (AVAR(tau) = 1/2 E[(ybar_{k+1} - ybar_k)^2]);
IEEE Std 952-1997 Annex A / Std 1431 (thermal sensitivity and its rate term, the
"temperature-rate" or Shupe-type term of a gyro model).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from statistics import NormalDist

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "StationarityReport",
    "stationarity_check",
    "window_variance_dof",
    "quiet_stretches",
    "TemperatureFit",
    "remove_temperature",
]


#: allowance on the motion test's white-noise variance limit for the non-white share of a
#: window's variance (flicker and random-walk wander); stated, not derived
NON_WHITE_MARGIN = 2.0
#: most windows whose autocorrelations set the effective degrees of freedom (window_variance_dof)
DOF_WINDOWS = 256


@dataclass(frozen=True)
class StationarityReport:
    """Result of :func:`stationarity_check`.

    Attributes
    ----------
    window : float
        Window length tau_w [s].
    motion : list of (start_s, stop_s, ratio)
        Windows whose variance exceeds the median window variance by the test's factor;
        ratio = window variance / median.
    steps : list of (time_s, z)
        Boundaries between adjacent windows whose means differ by z standard deviations
        sqrt(2 AVAR(tau_w)) with z beyond the test's limit.
    tested : bool
        False when the record is too short to test (fewer than 4 windows of 8 samples):
        nothing was checked, so :attr:`stationary` says nothing either.
    """

    window: float
    motion: list[tuple[float, float, float]]
    steps: list[tuple[float, float]]
    tested: bool = True

    @property
    def stationary(self) -> bool:
        """True when the record was tested and nothing was flagged."""
        return self.tested and not self.motion and not self.steps

    def warnings(self, label: str) -> list[str]:
        """One line per finding kind, for the report."""
        if not self.tested:
            return [f"{label}: too short to test for motion or steps (needs 4 windows of 8 samples)"]
        out = []
        if self.motion:
            a, b, r = max(self.motion, key=lambda t: t[2])
            out.append(
                f"{label}: {len(self.motion)} {self.window:g} s window(s) with variance far above the record's "
                f"(worst {r:.3g}x at {a:g}-{b:g} s): motion or vibration? Analyse a quiet segment (--start/--stop)"
            )
        if self.steps:
            t, z = max(self.steps, key=lambda s: abs(s[1]))
            out.append(
                f"{label}: {len(self.steps)} step(s) between {self.window:g} s windows beyond the Allan deviation "
                f"(largest {abs(z):.3g} sigma at {t:g} s): the record is not stationary; the fit treats the step "
                "as noise"
            )
        return out


def stationarity_check(
    rate: ArrayLike, fs: float, adev_at: float, *, window: float, false_alarm: float = 1e-3
) -> StationarityReport:
    """Flag motion (variance bursts) and steps (jumps of the window mean) in a static record.

    Returns
    -------
    StationarityReport
        The windows flagged for motion and the window boundaries flagged as steps.

    Parameters
    ----------
    rate : array_like
        Rate samples [any unit u].
    fs : float
        Sample rate [Hz].
    adev_at : float
        The record's Allan deviation at tau = ``window`` [u] (from its curve).
    window : float
        Window length [s]; a multiple of 1/fs, at least 8 samples.
    false_alarm : float
        Probability of any flag on a stationary Gaussian record (Bonferroni over the K motion
        and K - 1 step tests).

    Notes
    -----
    Motion: with w samples per window, a window's sample variance s^2 is taken as
    sigma^2 chi2(nu)/nu, nu the effective degrees of freedom of :func:`window_variance_dof`
    (w - 1 for white noise; fewer when a filter correlates neighbouring samples: about 12
    for a 16-sample moving average at w = 128, where w - 1 = 127 made filtered white noise
    trip the test); sigma^2 is estimated robustly as median(s^2) divided by the median of
    chi2(nu)/nu (which is below 1: 0.91 at nu = 7), and a window is flagged
    when s^2 / sigma^2 exceeds chi2_{1-p}(nu)/nu with p = false_alarm / (2K - 1), times
    ``NON_WHITE_MARGIN`` = 2 for the non-white share (a stated allowance, not derived: it
    keeps flicker and random-walk wander inside a window from firing it).
    Steps: AVAR(tau) = 1/2 E[(ybar_{k+1} - ybar_k)^2] (IEEE 952 C.1), so the difference of
    adjacent window means has standard deviation sqrt(2) ADEV(tau_w) whatever the noise
    mix; a difference beyond z = Phi^-1(1 - p/2) of that (Gaussian, same p) is flagged.
    Heavier tails than Gaussian (e.g. flicker) raise the false-alarm rate.
    """
    from gyrobench.analysis.allan._chi2 import chi2_isf  # numpy only: no scipy.special import

    y = np.asarray(rate, dtype=float)
    w = int(round(window * fs))
    k = y.size // w
    if w < 8 or k < 4:
        return StationarityReport(window=window, motion=[], steps=[], tested=False)
    blocks = y[: k * w].reshape(k, w)
    means = blocks.mean(axis=1)
    var = blocks.var(axis=1, ddof=1)
    nu = window_variance_dof(blocks)
    med = float(np.median(var)) / (float(chi2_isf(0.5, nu)) / nu)
    p = false_alarm / (2 * k - 1)
    limit = NON_WHITE_MARGIN * float(chi2_isf(p, nu)) / nu
    motion = (
        [
            (i * window, (i + 1) * window, float(var[i] / med))
            for i in np.flatnonzero(var > limit * med)
        ]
        if med > 0
        else []
    )
    sd = math.sqrt(2.0) * adev_at
    z_lim = NormalDist().inv_cdf(1.0 - p / 2.0)
    steps = []
    if sd > 0:
        z = np.diff(means) / sd
        steps = [((i + 1) * window, float(z[i])) for i in np.flatnonzero(np.abs(z) > z_lim)]
    return StationarityReport(window=window, motion=motion, steps=steps)


def window_variance_dof(blocks: NDArray[np.float64]) -> float:
    """Effective degrees of freedom of the sample variance of one window of a record.

    Parameters
    ----------
    blocks : ndarray, shape (K, w)
        The record cut into K windows of w samples (K >= 1, w >= 2).

    Returns
    -------
    float
        nu = w / S with S = 1 + 2 sum_{j=1}^{w-1} (1 - j/w) r_j^2, in [1, w - 1].

    Notes
    -----
    The window's sample variance is x' A x / (w - 1), A = I - 1 1'/w; for a Gaussian window of
    covariance Sigma, matching a scaled chi-square's first two moments (Satterthwaite 1946)
    gives nu = tr(M)^2 / tr(M^2), M = A Sigma A the covariance of the mean-removed window.
    Taking M as constant along its diagonals, M_il = m_|i-l|, gives nu = w / S with
    r_j = m_j / m_0 (Bartlett 1946; Priestley 1981, 5.3): exactly w - 1 for white noise
    (m_j = -sigma^2 / w). m_j is estimated per window from its mean-removed lag products
    (zero-padded FFT, divided by the w - j products) and r_j is the median over the K
    windows, so windows with motion (a minority) do not set it. A low-pass filter
    (neighbouring samples correlated over about fs / f_c samples) lowers nu: about 12 for a
    16-sample moving average at w = 128. The estimation noise of r_j adds about 3 / K to S
    (a few % fewer degrees of freedom at K >= 32: a slightly more lenient limit); at most
    :data:`DOF_WINDOWS` evenly spaced windows are used (about 1 % at that many).
    """
    k, w = blocks.shape
    if k > DOF_WINDOWS:  # evenly spaced windows: the median needs no more (and 1e6 samples cost 0.5 s)
        blocks = blocks[np.linspace(0, k - 1, DOF_WINDOWS).astype(np.int64)]
    x = blocks - blocks.mean(axis=1, keepdims=True)
    spec = np.fft.rfft(x, n=2 * w, axis=1)
    acov = np.fft.irfft(spec.real**2 + spec.imag**2, n=2 * w, axis=1)[:, :w]
    j = np.arange(1, w)
    with np.errstate(invalid="ignore", divide="ignore"):
        rho = (acov[:, 1:] / (w - j)) / (acov[:, :1] / w)
    rho = np.median(rho[np.isfinite(rho[:, 0])], axis=0) if np.isfinite(rho[:, 0]).any() else np.zeros(w - 1)
    s = 1.0 + 2.0 * float(np.sum((1.0 - j / w) * rho**2))
    return float(min(max(w / s, 1.0), w - 1))


def quiet_stretches(report: StationarityReport, n: int, fs: float, *, min_windows: int = 32) -> list[tuple[int, int]]:
    """The stretches of a record between its flagged motion windows and steps, as sample ranges.

    Parameters
    ----------
    report : StationarityReport
        The record's :func:`stationarity_check` (window length tau_w).
    n : int
        Samples in the record.
    fs : float
        Sample rate [Hz].
    min_windows : int
        Shortest stretch kept, in windows of tau_w (>= 4): shorter ones hold too few
        octaves for a fit.

    Returns
    -------
    list of (start, stop)
        Half-open sample ranges [start, stop) of the maximal runs of unflagged windows that
        cross no flagged step, in time order; the samples after the last whole window are
        left out. Empty when the record was not tested.
    """
    if isinstance(min_windows, bool) or not isinstance(min_windows, int) or min_windows < 4:
        raise ValueError(f"min_windows must be an integer >= 4; got {min_windows!r}")
    w = int(round(report.window * fs))
    if not report.tested or w < 1:
        return []
    k = n // w
    bad = np.zeros(k, dtype=bool)
    for a, _, _ in report.motion:
        bad[int(round(a / report.window))] = True
    cut = {int(round(t / report.window)) for t, _ in report.steps}  # a step before window i
    out: list[tuple[int, int]] = []
    start = None
    for i in range(k + 1):
        end_run = i == k or bad[i] or i in cut
        if end_run and start is not None:
            if i - start >= min_windows:
                out.append((start * w, i * w))
            start = None
        if i < k and not bad[i] and start is None:
            start = i
    return out


@dataclass(frozen=True)
class TemperatureFit:
    """Result of :func:`remove_temperature`.

    Attributes
    ----------
    c_temperature : float
        Sensitivity to temperature [u/degC].
    c_rate : float
        Sensitivity to the rate of change of temperature [u/(degC/s)].
    se_temperature, se_rate : float
        Ordinary least-squares standard errors (white residuals assumed: with correlated
        residuals, as bias instability gives, the true errors are larger).
    explained : float
        Fraction of the rate variance the two terms explain.
    """

    c_temperature: float
    c_rate: float
    se_temperature: float
    se_rate: float
    explained: float


def remove_temperature(
    rate: ArrayLike, temperature: ArrayLike, fs: float, *, smooth: float = 1.0
) -> tuple[NDArray[np.float64], TemperatureFit]:
    """Remove the temperature-explained part y = c0 + c_T (T - Tbar) + c_dT dT/dt of a rate.

    Parameters
    ----------
    rate : array_like
        Rate samples [u].
    temperature : array_like
        Temperature samples [degC], same length.
    fs : float
        Sample rate [Hz].
    smooth : float
        dT/dt is the central difference of T averaged over this window [s] (temperature
        sensors are quantized; a raw difference is mostly quantization noise).

    Returns
    -------
    (rate minus c_T (T - Tbar) + c_dT dT/dt, TemperatureFit)
        The constant c0 is left in (Allan analysis ignores it).
    """
    y = np.asarray(rate, dtype=float)
    t = np.asarray(temperature, dtype=float)
    if t.shape != y.shape:
        raise ValueError(f"temperature must have the rate's length {y.size}; got {t.size}")
    if not np.all(np.isfinite(t)):
        i = int(np.flatnonzero(~np.isfinite(t))[0])
        raise ValueError(f"temperature must be finite; got {float(t[i])} at sample {i}")
    if np.ptp(t) == 0:
        raise ValueError("temperature column is constant: nothing to regress on")
    w = min(max(1, int(round(smooth * fs))), y.size)
    if (
        w > 1
    ):  # moving average, normalised at the ends (no zero padding: that would fake a slope there)
        ker = np.ones(w)
        ts = np.convolve(t, ker, mode="same") / np.convolve(np.ones_like(t), ker, mode="same")
    else:
        ts = t
    dtdt = np.gradient(ts) * fs
    x = np.column_stack([np.ones_like(t), t - t.mean(), dtdt - dtdt.mean()])
    coef, *_ = np.linalg.lstsq(x, y, rcond=None)
    resid = y - x @ coef
    dof = max(y.size - 3, 1)
    s2 = float(resid @ resid) / dof
    cov = s2 * np.linalg.pinv(x.T @ x)
    explained = 1.0 - float(np.var(resid)) / float(np.var(y)) if np.var(y) > 0 else 0.0
    fit = TemperatureFit(
        c_temperature=float(coef[1]),
        c_rate=float(coef[2]),
        se_temperature=math.sqrt(max(cov[1, 1], 0.0)),
        se_rate=math.sqrt(max(cov[2, 2], 0.0)),
        explained=explained,
    )
    return y - x[:, 1:] @ coef[1:], fit
