"""Wavelet multiscale analysis of a rate record.

Mallat decomposition, single-branch reconstructions, CWT map, FFT spectrum.

A thin validated layer over PyWavelets: the functions take a plain array and a
sample rate and work the same on a real gyro's CSV as on simulated data.

Mallat pyramid (docs/physics.md 7.1): a_{j+1}[k] = sum_n h[n - 2k] a_j[n],
d_{j+1}[k] = sum_n g[n - 2k] a_j[n]; the synthesis filters reconstruct exactly,
so the single-branch reconstructions (MATLAB ``wrcoef``: every other coefficient
array set to zero, then ``waverec``) sum back to the signal:

    x = A_L + D_L + ... + D_1.

The approximation at a level j <= L is A_j = A_L + D_L + ... + D_{j+1}, and
x = A_j + (D_j + ... + D_1). With sampling rate fs, D_j covers roughly
[fs/2^(j+1), fs/2^j] and A_j [0, fs/2^(j+1)].

Depth
-----
A level deeper than ``pywt.dwt_max_level(n, filter_length)`` makes every
coefficient feel the boundary extension (PyWavelets only warns); here it is an
error that names the largest usable level, unless ``level="max"`` is passed,
which uses that largest level (documented lower level). For db4 (8 taps) ten
levels need at least 7168 samples.

References
----------
S. Mallat, "A theory for multiresolution signal decomposition: the wavelet
representation", IEEE PAMI 11(7), 1989. G. R. Lee et al., "PyWavelets: A Python
package for wavelet analysis", JOSS 4(36), 2019. Seed paper 000 (db4, 10 levels,
A6 as the bias, D1..D6 as drift + noise).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pywt
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "MultiscaleDecomposition",
    "max_level",
    "decompose",
    "TimeFrequencyMap",
    "cwt_map",
    "amplitude_spectrum",
]


def _check_signal(x: ArrayLike) -> NDArray[np.float64]:
    a = np.asarray(x, dtype=float)
    if a.ndim != 1:
        raise ValueError(f"x must be 1-D; got shape {a.shape}")
    if len(a) < 2:
        raise ValueError(f"x must hold at least 2 samples; got {len(a)}")
    if not np.all(np.isfinite(a)):
        bad = int(np.flatnonzero(~np.isfinite(a))[0])
        raise ValueError(f"x must be finite; got {float(a[bad])!r} at index {bad}")
    return a


def _check_fs(fs) -> float:
    if isinstance(fs, bool) or not isinstance(fs, (int, float, np.integer, np.floating)) or not (
        math.isfinite(fs) and fs > 0
    ):
        raise ValueError(f"fs must be a finite number > 0 Hz; got {fs!r}")
    return float(fs)


def _discrete_wavelet(wavelet) -> pywt.Wavelet:
    if isinstance(wavelet, pywt.Wavelet):
        return wavelet
    if not isinstance(wavelet, str) or wavelet not in pywt.wavelist(kind="discrete"):
        raise ValueError(
            f"wavelet must be a discrete wavelet name (run pywt.wavelist(kind='discrete')); got {wavelet!r}"
        )
    return pywt.Wavelet(wavelet)


def _check_mode(mode: str) -> str:
    if mode not in pywt.Modes.modes:
        raise ValueError(f"mode must be one of {pywt.Modes.modes}; got {mode!r}")
    return mode


def max_level(n: int, wavelet="db4") -> int:
    """Deepest level without boundary effects for ``n`` samples: ``pywt.dwt_max_level(n, filter_length)``.

    Parameters
    ----------
    n : int
        Record length [samples].
    wavelet : str or pywt.Wavelet
        Discrete wavelet (default Daubechies 4).

    Returns
    -------
    int
        The level.
    """
    return int(pywt.dwt_max_level(int(n), _discrete_wavelet(wavelet).dec_len))


@dataclass(frozen=True, slots=True)
class MultiscaleDecomposition:
    """Single-branch reconstructions of a multilevel DWT, each as long as the signal.

    Attributes
    ----------
    approximation : ndarray
        A_L, the reconstructed approximation at the deepest level L.
    details : tuple of ndarray
        (D_1, ..., D_L): ``details[j - 1]`` is the reconstructed detail at level j.
    fs : float
        Sample rate [Hz].
    wavelet : str
        Wavelet name.
    mode : str
        Signal extension mode.
    """

    approximation: NDArray[np.float64]
    details: tuple[NDArray[np.float64], ...]
    fs: float
    wavelet: str
    mode: str

    @property
    def level(self) -> int:
        """Decomposition depth L."""
        return len(self.details)

    def _check_j(self, j: int, lo: int) -> int:
        if isinstance(j, bool) or not isinstance(j, (int, np.integer)) or not lo <= j <= self.level:
            raise ValueError(f"level j must be an integer in [{lo}, {self.level}]; got {j!r}")
        return int(j)

    def approx(self, j: int) -> NDArray[np.float64]:
        """A_j = A_L + D_L + ... + D_{j+1} (j = 0 returns the whole signal)."""
        j = self._check_j(j, 0)
        out = self.approximation.copy()
        for d in self.details[j:][::-1]:
            out += d
        return out

    def detail(self, j: int) -> NDArray[np.float64]:
        """D_j, the reconstructed detail at level j (1 <= j <= L)."""
        return self.details[self._check_j(j, 1) - 1]

    def detail_sum(self, j: int) -> NDArray[np.float64]:
        """D_1 + ... + D_j (j = 0 returns zeros); x = approx(j) + detail_sum(j)."""
        j = self._check_j(j, 0)
        out = np.zeros_like(self.approximation)
        for d in self.details[:j]:
            out += d
        return out

    def reconstruct(self) -> NDArray[np.float64]:
        """A_L + D_L + ... + D_1: the signal back."""
        return self.approx(0)

    def band(self, j: int, kind: str = "d") -> tuple[float, float]:
        """Nominal band [Hz] of D_j (``kind="d"``: [fs/2^(j+1), fs/2^j]) or A_j (``"a"``: [0, fs/2^(j+1)])."""
        j = self._check_j(j, 0 if kind == "a" else 1)
        if kind == "a":
            return 0.0, self.fs / 2 ** (j + 1)
        if kind != "d":
            raise ValueError(f"kind must be 'a' or 'd'; got {kind!r}")
        return self.fs / 2 ** (j + 1), self.fs / 2**j


def decompose(
    x: ArrayLike, fs: float, *, wavelet="db4", level: int | str = 10, mode: str = "symmetric"
) -> MultiscaleDecomposition:
    """Mallat decomposition and single-branch reconstruction of every branch.

    Parameters
    ----------
    x : array_like
        The record (any unit; the branches keep it).
    fs : float
        Sample rate [Hz].
    wavelet : str or pywt.Wavelet
        Discrete wavelet (default db4, as seed 000).
    level : int or "max"
        Depth L >= 1 (default 10, as seed 000); ``"max"`` uses :func:`max_level`.
    mode : str
        PyWavelets extension mode (default ``"symmetric"``, MATLAB's ``"sym"``).

    Returns
    -------
    MultiscaleDecomposition

    Raises
    ------
    ValueError
        If ``level`` exceeds the deepest level the record supports (the message
        names it), or the record is too short for even one level.

    Notes
    -----
    Branch j is ``pywt.waverec`` of the coefficient list with every array but
    that branch's zeroed, truncated to ``len(x)`` (``wrcoef`` in MATLAB). Do not
    use ``pywt.upcoef(..., take=n)``: it aligns differently (docs/physics.md 7.1).

    Examples
    --------
    >>> import numpy as np
    >>> x = np.random.default_rng(0).standard_normal(8192)
    >>> dec = decompose(x, fs=100.0, level=6)
    >>> bool(np.allclose(dec.approx(6) + dec.detail_sum(6), x, rtol=0, atol=1e-12))
    True
    """
    a = _check_signal(x)
    fs = _check_fs(fs)
    w = _discrete_wavelet(wavelet)
    mode = _check_mode(mode)
    top = max_level(len(a), w)
    if level == "max":
        level = top
    if isinstance(level, bool) or not isinstance(level, (int, np.integer)):
        raise TypeError(f"level must be an integer >= 1 or 'max'; got {level!r}")
    if top < 1:
        raise ValueError(
            f"x has {len(a)} samples, too few for one level of {w.name} (needs >= {w.dec_len - 1}); got level={level!r}"
        )
    if not 1 <= level <= top:
        raise ValueError(
            f"level must be in [1, {top}] for {len(a)} samples and {w.name} (pywt.dwt_max_level); got {level!r}: "
            f"use a lower level, level='max', or a record of >= {(w.dec_len - 1) * 2**int(level)} samples"
        )
    coeffs = pywt.wavedec(a, w, mode=mode, level=int(level))
    zeros = [np.zeros_like(c) for c in coeffs]

    def branch(i: int) -> NDArray[np.float64]:
        cs = list(zeros)
        cs[i] = coeffs[i]
        return pywt.waverec(cs, w, mode=mode)[: len(a)]

    approx = branch(0)
    # coeffs = [cA_L, cD_L, ..., cD_1] -> details ordered D_1 .. D_L
    details = tuple(branch(len(coeffs) - j) for j in range(1, int(level) + 1))
    return MultiscaleDecomposition(approx, details, fs, w.name, mode)


@dataclass(frozen=True, slots=True)
class TimeFrequencyMap:
    """|CWT| on a time x frequency grid.

    Attributes
    ----------
    time : ndarray, shape (n_t,)
        Block-centre times [s] from the first sample.
    frequency : ndarray, shape (n_f,)
        Pseudo-frequencies [Hz] (descending scales -> ascending frequencies).
    magnitude : ndarray, shape (n_f, n_t)
        Block-mean of |W(scale, t)| [unit of x].
    """

    time: NDArray[np.float64]
    frequency: NDArray[np.float64]
    magnitude: NDArray[np.float64]


def cwt_map(
    x: ArrayLike,
    fs: float,
    *,
    frequencies: ArrayLike | None = None,
    n_frequencies: int = 40,
    f_min: float | None = None,
    wavelet: str = "cmor1.5-1.0",
    time_block: int | None = None,
) -> TimeFrequencyMap:
    """Continuous-wavelet time-frequency map (magnitude), block-averaged in time for plotting.

    Parameters
    ----------
    x : array_like
        The record.
    fs : float
        Sample rate [Hz].
    frequencies : array_like, optional
        Pseudo-frequencies [Hz] in (0, fs/2]; default ``n_frequencies`` log-spaced
        from ``f_min`` (default 20 fs/len(x)) to fs/2.
    n_frequencies : int
        Number of default frequencies.
    f_min : float, optional
        Lowest default frequency [Hz].
    wavelet : str
        Continuous wavelet (``pywt.wavelist(kind='continuous')``); default complex Morlet.
    time_block : int, optional
        Samples per output column (default: about 600 columns).

    Returns
    -------
    TimeFrequencyMap
        Block-centre times [s], pseudo-frequencies [Hz] and the block-mean |W| [unit of x].

    Notes
    -----
    scale = f_c fs / f, f_c = ``pywt.central_frequency(wavelet)``; W = ``pywt.cwt`` by
    FFT convolution, one scale at a time so memory stays O(len(x)).
    """
    a = _check_signal(x)
    fs = _check_fs(fs)
    if wavelet not in pywt.wavelist(kind="continuous") and not any(
        wavelet.startswith(p) for p in ("cmor", "fbsp", "shan", "cgau")
    ):
        raise ValueError(f"wavelet must be continuous (run pywt.wavelist(kind='continuous')); got {wavelet!r}")
    if frequencies is None:
        lo = f_min if f_min is not None else 20.0 * fs / len(a)
        if not (0 < lo < fs / 2):
            raise ValueError(f"f_min must be in (0, fs/2 = {fs / 2}) Hz; got {lo!r}")
        freqs = np.geomspace(lo, fs / 2, int(n_frequencies))
    else:
        freqs = np.asarray(frequencies, dtype=float)
        if freqs.ndim != 1 or np.any(~(freqs > 0)) or np.any(freqs > fs / 2):
            raise ValueError(f"frequencies must be 1-D in (0, fs/2 = {fs / 2}] Hz; got {frequencies!r}")
    blk = time_block or max(1, len(a) // 600)
    n_t = len(a) // blk
    fc = pywt.central_frequency(wavelet)
    mag = np.empty((len(freqs), n_t))
    xm = a - a.mean()
    for i, f in enumerate(freqs):
        coef, _ = pywt.cwt(xm, [fc * fs / f], wavelet, sampling_period=1.0 / fs, method="fft")
        mag[i] = np.abs(coef[0, : n_t * blk]).reshape(n_t, blk).mean(axis=1)
    t = (np.arange(n_t) + 0.5) * blk / fs
    return TimeFrequencyMap(np.asarray(t, dtype=np.float64), np.asarray(freqs, dtype=np.float64), mag)


def amplitude_spectrum(x: ArrayLike, fs: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """One-sided FFT amplitude spectrum of the mean-removed record.

    Parameters
    ----------
    x : array_like
        The record (any unit).
    fs : float
        Sample rate [Hz].

    Returns
    -------
    f : ndarray
        Frequencies [Hz], 0 .. fs/2.
    amplitude : ndarray
        2 |X_k| / n [unit of x] (|X_0|/n at DC): a sine of amplitude A on a bin reads A.
    """
    a = _check_signal(x)
    fs = _check_fs(fs)
    n = len(a)
    spec = np.abs(np.fft.rfft(a - a.mean())) / n
    spec[1:] *= 2.0
    if n % 2 == 0:
        spec[-1] /= 2.0
    return np.asarray(np.fft.rfftfreq(n, 1.0 / fs), dtype=np.float64), spec
