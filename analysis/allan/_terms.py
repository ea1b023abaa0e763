"""The five IEEE Std 952 rate-noise terms, one record each.

A term is AVAR(tau) = scale * coefficient**2 * tau**power; its noise type (the exponent
alpha of S_y(f) ~ f^alpha, as in NIST SP 1065) picks the edf and the correlation model of
the fit. Everything else (the term list, the conversions, the read-off's slopes and read
taus) is derived from these records, so a term is described in one place.

References
----------
IEEE Std 952-1997, Annex C; docs/physics.md 1.5.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["TERM_RECORDS", "TERMS", "FLICKER_FLOOR", "Term", "avar_to_coefficient", "coefficient_to_avar"]

#: 2 ln2 / pi = 0.4413: flicker AVAR plateau / B^2
_FLICKER = 2.0 * math.log(2.0) / math.pi


@dataclass(frozen=True, slots=True, kw_only=True)
class Term:
    """One IEEE 952 term: AVAR(tau) = ``scale`` * coefficient^2 * tau^``power``.

    Attributes
    ----------
    name : str
        "Q", "N", "B", "K" or "R".
    description : str
        What the term is ("angle random walk", ...).
    unit : str
        Unit of the coefficient for a rate in unit u and tau in s ("u*s^0.5", ...).
    power : int
        Power of tau in the AVAR term.
    scale : float
        C = scale * coefficient^2 (3, 1, 2 ln2/pi, 1/3, 1/2).
    alpha : int
        Power-law exponent of S_y(f) of the term's noise (+2 Q, 0 N, -1 B, -2 K); the ramp
        is deterministic and treated as random-walk FM (-2) for the edf.
    random : bool
        False for a deterministic term (the ramp): no chi-square variance of its own.
    """

    name: str
    description: str
    unit: str
    power: int
    scale: float
    alpha: int
    random: bool = True


#: the terms, in order of their AVAR power of tau (module docstring of gyrobench.analysis.allan)
TERM_RECORDS = (
    Term(name="Q", description="quantization", unit="u*s", power=-2, scale=3.0, alpha=2),
    Term(name="N", description="angle random walk", unit="u*s^0.5", power=-1, scale=1.0, alpha=0),
    Term(name="B", description="bias instability", unit="u", power=0, scale=_FLICKER, alpha=-1),
    Term(name="K", description="rate random walk", unit="u/s^0.5", power=1, scale=1.0 / 3.0, alpha=-2),
    Term(name="R", description="rate ramp", unit="u/s", power=2, scale=0.5, alpha=-2, random=False),
)
#: IEEE 952 terms, in order of their AVAR power of tau
TERMS = tuple(t.name for t in TERM_RECORDS)
#: the record of each term by name
TERM = {t.name: t for t in TERM_RECORDS}
#: AVAR = C * tau**power for each term
_POWER = {t.name: t.power for t in TERM_RECORDS}
#: C = _SCALE * coefficient**2  (docs/physics.md 1.5)
_SCALE = {t.name: t.scale for t in TERM_RECORDS}
#: power-law exponent alpha of S_y(f) of each term, used to pick the edf formula
_ALPHA = {t.name: t.alpha for t in TERM_RECORDS}
#: sqrt(2 ln 2 / pi) = 0.6643: ADEV plateau of unit bias instability
FLICKER_FLOOR = math.sqrt(_FLICKER)


def coefficient_to_avar(name: str, value: float) -> float:
    """Convert an IEEE-952 coefficient into its Allan-variance coefficient.

    C_n = scale value^2 for term ``name``: 3 Q^2, N^2, (2 ln 2/pi) B^2 = 0.4413 B^2, K^2/3,
    R^2/2 (IEEE Std 952-1997 Annex C).

    Parameters
    ----------
    name : str
        ``"Q"``, ``"N"``, ``"B"``, ``"K"`` or ``"R"``.
    value : float
        The coefficient [Q: u s, N: u s^0.5, B: u, K: u s^-0.5, R: u s^-1 for a rate in u].

    Returns
    -------
    float
        C_n [u^2 s^-n] of AVAR(tau) = sum_n C_n tau^n.
    """
    return _SCALE[name] * value * value


def avar_to_coefficient(name: str, c: float) -> float:
    """Convert an Allan-variance coefficient into the IEEE-952 coefficient.

    The inverse of :func:`coefficient_to_avar`; a negative ``c`` maps to 0.

    Parameters
    ----------
    name : str
        ``"Q"``, ``"N"``, ``"B"``, ``"K"`` or ``"R"``.
    c : float
        C_n [u^2 s^-n].

    Returns
    -------
    float
        The coefficient, sqrt(max(c, 0) / scale).
    """
    return math.sqrt(max(c, 0.0) / _SCALE[name])
