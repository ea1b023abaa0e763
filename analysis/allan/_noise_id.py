"""Power-law noise identification by the lag-1 autocorrelation (Riley & Greenhall 2004).

References
----------
W. J. Riley and C. A. Greenhall, "Power law noise identification using the lag 1
autocorrelation", EFTF 2004; allantools.ci.autocorr_noise_id.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from gyrobench.analysis.allan._blas import _dot
from gyrobench.analysis.allan._kinds import STATISTICS

#: noise identification uses at most this many block averages (see ``identify_noise``)
_NOISE_ID_MAX = 1 << 16
_NOISE_ID_MIN = 30


#: block of the in-place detrend (a 64 kB ramp buffer: below malloc's mmap threshold, so it is
#: reused without page faults, where n-sized temporaries were faulted in afresh on every call)
_RAMP_BLOCK = 8192


def _lag1_acf(z: NDArray[np.float64]) -> float:
    """Lag-1 autocorrelation (Riley & Greenhall 2004 eq. 2), as allantools.ci.lag1_acf, vectorised.

    Subtracts the mean from ``z`` in place (the callers own ``z``), so no temporary is made.
    """
    z -= z.mean()
    return _dot(z[:-1], z[1:]) / _dot(z, z)


def _detrend1(z: NDArray[np.float64]) -> NDArray[np.float64]:
    """Remove the least-squares line from ``z`` in place (allantools.ci.detrend(deg=1), in closed form); returns z.

    With t_k = k - (n - 1)/2 the centred index, z - mean(z) - b t, b = sum t (z - mean) / sum t^2;
    t is made block by block in one small buffer, not as an n-array.
    """
    n = z.size
    z -= z.mean()
    c = (n - 1) / 2.0
    ramp = np.arange(min(n, _RAMP_BLOCK), dtype=float)
    t = np.empty_like(ramp)
    tz = 0.0
    tt = 0.0
    for a in range(0, n, _RAMP_BLOCK):
        w = t[: min(n, a + _RAMP_BLOCK) - a]
        np.add(ramp[: w.size], a - c, out=w)
        tz += float(np.dot(w, z[a : a + w.size]))
        tt += float(np.dot(w, w))
    b = tz / tt if tt > 0 else 0.0
    for a in range(0, n, _RAMP_BLOCK):
        w = t[: min(n, a + _RAMP_BLOCK) - a]
        np.add(ramp[: w.size], a - c, out=w)
        w *= b
        z[a : a + w.size] -= w
    return z


def _diff_in_place(z: NDArray[np.float64]) -> NDArray[np.float64]:
    """np.diff(z) written over z[:-1] (ascending blocks: each reads z[a .. b] before the next block writes)."""
    buf = np.empty(min(z.size - 1, _RAMP_BLOCK))
    for a in range(0, z.size - 1, _RAMP_BLOCK):
        b = min(z.size - 1, a + _RAMP_BLOCK)
        np.subtract(z[a + 1 : b + 1], z[a:b], out=buf[: b - a])
        z[a:b] = buf[: b - a]
    return z[:-1]


def _noise_id_blocks(z: NDArray[np.float64], dmax: int, *, overwrite: bool = False) -> int:
    """Lag-1 ACF noise identification (Riley & Greenhall 2004) of block means z of the rate.

    Block means that are exactly a line after detrending (e.g. a constant rate: every
    S_m[j m] is the same sum) have no noise to identify: 0 (white rate) is returned instead
    of a 0/0 autocorrelation. (A noise-free ramp leaves rounding residue, which gets some
    alpha; its deviation is exact, only its bounds depend on that alpha.)
    ``overwrite``: ``z`` may be used as the work array (the detrend, mean removal and
    differences are done in place); otherwise a copy is.
    """
    z = _detrend1(z if overwrite else np.array(z, dtype=float))
    d = 0
    while True:
        if not np.any(z):
            return 0
        r1 = _lag1_acf(z)
        rho = r1 / (1.0 + r1)
        if rho < 0.25 or d >= dmax:
            return int(-1.0 * np.round(2 * rho) - 2.0 * d)
        z = _diff_in_place(z)
        d += 1


def _noise_id_one(x: NDArray[np.float64], m: int, dmax: int) -> int | None:
    """Lag-1 ACF noise identification at averaging factor m from the phase x (None if < 30 points)."""
    nb = min((x.size - 1) // m, _NOISE_ID_MAX)
    if nb < _NOISE_ID_MIN:
        return None
    z = np.diff(x[: nb * m + 1 : m])
    z /= m
    return _noise_id_blocks(z, dmax, overwrite=True)  # non-overlapping block means



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
