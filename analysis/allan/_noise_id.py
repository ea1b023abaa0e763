"""Power-law noise identification by the lag-1 autocorrelation (Riley & Greenhall 2004).

References
----------
W. J. Riley and C. A. Greenhall, "Power law noise identification using the lag 1
autocorrelation", EFTF 2004; allantools.ci.autocorr_noise_id.
"""

from __future__ import annotations

import numpy as np
from gyrobench.analysis.allan._blas import _dot
from gyrobench.analysis.allan._kinds import STATISTICS
from numpy.typing import NDArray

#: noise identification uses at most this many block averages (see ``identify_noise``)
_NOISE_ID_MAX = 1 << 16
_NOISE_ID_MIN = 30


def _lag1_acf(z: NDArray[np.float64]) -> float:
    """Lag-1 autocorrelation (Riley & Greenhall 2004 eq. 2), as allantools.ci.lag1_acf, vectorised."""
    d = z - z.mean()
    return _dot(d[:-1], d[1:]) / _dot(d, d)


def _detrend1(z: NDArray[np.float64]) -> NDArray[np.float64]:
    """Remove the least-squares line (allantools.ci.detrend(deg=1), in closed form)."""
    t = np.arange(z.size, dtype=float)
    t -= t.mean()
    zc = z - z.mean()
    return zc - t * (_dot(t, zc) / _dot(t, t))


def _noise_id_blocks(z: NDArray[np.float64], dmax: int) -> int:
    """Lag-1 ACF noise identification (Riley & Greenhall 2004) of block means z of the rate.

    Block means that are exactly a line after detrending (e.g. a constant rate: every
    S_m[j m] is the same sum) have no noise to identify: 0 (white rate) is returned instead
    of a 0/0 autocorrelation. (A noise-free ramp leaves rounding residue, which gets some
    alpha; its deviation is exact, only its bounds depend on that alpha.)
    """
    z = _detrend1(z)
    d = 0
    while True:
        if not np.any(z):
            return 0
        r1 = _lag1_acf(z)
        rho = r1 / (1.0 + r1)
        if rho < 0.25 or d >= dmax:
            return int(-1.0 * np.round(2 * rho) - 2.0 * d)
        z = np.diff(z)
        d += 1


def _noise_id_one(x: NDArray[np.float64], m: int, dmax: int) -> int | None:
    """Lag-1 ACF noise identification at averaging factor m from the phase x (None if < 30 points)."""
    nb = min((x.size - 1) // m, _NOISE_ID_MAX)
    if nb < _NOISE_ID_MIN:
        return None
    return _noise_id_blocks(np.diff(x[: nb * m + 1 : m]) / m, dmax)  # non-overlapping block means



def _identify(x: NDArray[np.float64], ms: NDArray[np.int64], kind: str) -> NDArray[np.int64]:
    stat = STATISTICS[kind]
    dmax, lo = stat.noise_id_dmax, stat.alpha_min
    out = np.zeros(ms.size, dtype=np.int64)
    last = 0
    for i, m in enumerate(ms):
        a = _noise_id_one(x, int(m), dmax)
        if a is not None:
            last = int(np.clip(a, lo, 2))
        out[i] = last
    return out
