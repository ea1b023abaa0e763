"""The winding of a fibre coil: layer patterns (helical, dipolar, quadrupolar, octupolar) and the
map of every turn to (r, z, s along the fibre, ds), with drawn imperfections.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from numbers import Integral
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from gyrobench.sim.coil2d import Coil2DSpec

__all__ = [
    "WINDING_PATTERNS",
    "winding_sequence",
    "Imperfections",
    "FibreMap",
    "fibre_map",
]


#: winding name -> the repeating A/B layer sequence (inner -> outer); helical has none.
WINDING_PATTERNS: dict[str, str | None] = {
    "helical": None,
    "dipolar": "AB",
    "quadrupolar": "ABBA",
    "octupolar": "ABBABAAB",
}


def winding_sequence(pattern: str, layers: int) -> str | None:
    """The A/B sequence of ``layers`` layers (inner -> outer), or None for helical.

    Parameters
    ----------
    pattern : str
        A key of :data:`WINDING_PATTERNS` (``"helical"``, ``"dipolar"``, ``"quadrupolar"``,
        ``"octupolar"``).
    layers : int
        Number of layers.

    Returns
    -------
    str or None
        One letter per layer, ``"A"`` or ``"B"`` (the half of the fibre it belongs to); None for
        a helical winding.

    Raises
    ------
    ValueError
        Unknown pattern, or a layer count that is not a multiple of the pattern's period
        (dipolar 2, quadrupolar 4, octupolar 8).
    """
    if pattern not in WINDING_PATTERNS:
        raise ValueError(
            f"winding pattern must be one of {sorted(WINDING_PATTERNS)}; got {pattern!r}"
        )
    if isinstance(layers, bool) or not isinstance(layers, Integral) or layers < 1:
        raise ValueError(f"coil layers must be an integer >= 1; got {layers!r}")
    period = WINDING_PATTERNS[pattern]
    if period is None:
        return None
    if layers % len(period):
        raise ValueError(
            f"{pattern} winding needs a layer count that is a multiple of {len(period)} "
            f"(pattern {period}); got {layers} layers"
        )
    return period * (layers // len(period))


# ======================================================================================
# materials
# ======================================================================================



@dataclass(frozen=True, slots=True, kw_only=True)
class Imperfections:
    """Drawn departures of one wound coil from its drawing (all stated, none from a paper).

    Parameters
    ----------
    turn_errors : ndarray of int, shape (M,)
        Extra (+1) or missing (-1) turns per layer; each layer +-1 with probability
        ``Coil2DSpec.turn_error_probability`` each (0.15: a turn gained or lost at the flange at a
        layer change; stated).
    radius_errors : ndarray, shape (M,)
        Radial displacement of each layer [m]; N(0, (``Coil2DSpec.radius_error_rms`` p_r)^2)
        (0.03: tension variation; stated).
    lead_difference : float
        Lead A minus lead B length [m]; N(0, ``Coil2DSpec.lead_difference_rms``^2) (CALIBRATED
        rms, see there).
    sensor_z : float
        Axial position of the logged temperature sensor on the outer potting surface,
        as a fraction of the half height in [-1, 1]: c + (1 - |c|) u, u uniform in [-1, 1] and
        c = ``Coil2DSpec.sensor_z_center`` (0: uniform over the height; stated).
    """

    turn_errors: NDArray[np.int64]
    radius_errors: NDArray[np.float64]
    lead_difference: float = 0.0
    sensor_z: float = 0.0

    @classmethod
    def none(cls, layers: int) -> Imperfections:
        return cls(turn_errors=np.zeros(layers, dtype=np.int64), radius_errors=np.zeros(layers))

    @classmethod
    def draw(cls, spec: Coil2DSpec, *, rng: np.random.Generator) -> Imperfections:
        M = spec.layers
        q = spec.turn_error_probability
        te = rng.choice(np.array([-1, 0, 1]), size=M, p=[q, 1.0 - 2.0 * q, q])
        c = spec.sensor_z_center
        return cls(
            turn_errors=te.astype(np.int64),
            radius_errors=spec.radius_error_rms * spec.layer_pitch * rng.standard_normal(M),
            lead_difference=float(spec.lead_difference_rms * rng.standard_normal()),
            sensor_z=float(c + (1.0 - abs(c)) * rng.uniform(-1.0, 1.0)),
        )


@dataclass(frozen=True, slots=True)
class FibreMap:
    """The fibre as pieces: radius r, axial z, fibre coordinate s (from port A), length ds [m].

    ``bonded`` is False for the leads (free fibre); ``layer`` is -1 for leads and
    crossovers. ``length`` L = sum ds; ``diameter`` D = sum_{turns} ds 2 r / L (Sagnac:
    L D = sum of 2 x enclosed area over the turns).

    Attributes
    ----------
    r, z : ndarray
        Radius and axial position of each piece [m].
    s : ndarray
        Fibre coordinate of each piece from port A [m].
    ds : ndarray
        Length of each piece [m].
    bonded : ndarray of bool
        False for the leads (free fibre).
    layer : ndarray of int
        Layer of each piece; -1 for leads and crossovers.
    length : float
        L [m].
    diameter : float
        D [m].
    """

    r: NDArray[np.float64]
    z: NDArray[np.float64]
    s: NDArray[np.float64]
    ds: NDArray[np.float64]
    bonded: NDArray[np.bool_]
    layer: NDArray[np.int64]
    length: float
    diameter: float

    @property
    def weights(self) -> NDArray[np.float64]:
        """w_i = ds_i (L - 2 s_i) [m^2] (exact Int (L - 2z) dz over each piece)."""
        return self.ds * (self.length - 2.0 * self.s)


def _layer_pieces(spec: Coil2DSpec, j: int, up: bool, imp: Imperfections):
    N = spec.turns_per_layer + int(imp.turn_errors[j])
    r = spec.inner_radius + (j + 0.5) * spec.layer_pitch + float(imp.radius_errors[j])
    p = spec.height / N
    u = (np.arange(N) + 0.5) * p - 0.5 * spec.height
    z = u if up else -u
    return np.full(N, r), z, np.full(N, 2 * math.pi * r)


def fibre_map(spec: Coil2DSpec, imperfections: Imperfections | None = None) -> FibreMap:
    """Map every turn (and crossover, lead) of the winding to (r, z, s, ds).

    Symmetric patterns (:data:`WINDING_PATTERNS`): both halves start at
    the fibre midpoint on the spool at the bottom flange; each half reverses its traverse
    direction at every one of its own layers (so a half's next layer starts where its last
    ended); a crossover of ``crossover_turns`` turns joins successive layers of a half at
    the flange, at the mean radius of the two layers. Half A runs from the midpoint toward
    port A (s decreasing), half B toward port B. Helical: one fibre, layer after layer,
    alternating direction. Leads: at the top outer corner, in the skin.

    Parameters
    ----------
    spec : Coil2DSpec
        The coil's drawing.
    imperfections : Imperfections, optional
        Drawn departures from it; None: the ideal winding.

    Returns
    -------
    FibreMap
        The fibre's pieces.
    """
    imp = Imperfections.none(spec.layers) if imperfections is None else imperfections
    if len(imp.turn_errors) != spec.layers or len(imp.radius_errors) != spec.layers:
        raise ValueError(f"imperfections must have one entry per layer ({spec.layers})")
    seq = winding_sequence(spec.winding, spec.layers)
    halves = ["A"] * spec.layers if seq is None else list(seq)
    pieces: dict[str, list[tuple]] = {"A": [], "B": []}
    count = {"A": 0, "B": 0}
    last: dict[str, float | None] = {"A": None, "B": None}
    r_start = spec.inner_radius + 0.5 * spec.layer_pitch
    for j, h in enumerate(halves):
        up = count[h] % 2 == 0 if seq is not None else j % 2 == 0
        r, z, ds = _layer_pieces(spec, j, up, imp)
        prev_r = last[h] if last[h] is not None else (None if h == "A" else r_start)
        if prev_r is not None and spec.crossover_turns > 0:
            rx = 0.5 * (prev_r + r[0])
            zx = -0.5 * spec.height if up else 0.5 * spec.height
            pieces[h].append(
                (
                    np.array([rx]),
                    np.array([zx]),
                    np.array([spec.crossover_turns * 2 * math.pi * rx]),
                    np.array([-1]),
                )
            )
        pieces[h].append((r, z, ds, np.full(len(r), j)))
        count[h] += 1
        last[h] = float(r[0])

    def cat(h):
        if not pieces[h]:
            return (np.zeros(0),) * 3 + (np.zeros(0, dtype=np.int64),)
        return tuple(np.concatenate([p[k] for p in pieces[h]]) for k in range(4))

    rA, zA, dA, lA = cat("A")
    rB, zB, dB, lB = cat("B")
    lead_r = spec.outer_radius + 0.5 * spec.skin
    lead_z = 0.5 * spec.height + 0.5 * spec.skin
    lead_a = max(spec.lead_length + 0.5 * imp.lead_difference, 0.0)
    lead_b = max(spec.lead_length - 0.5 * imp.lead_difference, 0.0)
    if seq is None:  # helical: port A at the first turn; the A list is in s order
        s_A = lead_a + np.cumsum(dA) - 0.5 * dA
        s_mid = lead_a + dA.sum()
        s_B = np.zeros(0)
    else:  # A from the midpoint toward port A, B toward port B
        s_mid = lead_a + dA.sum()
        s_A = s_mid - (np.cumsum(dA) - 0.5 * dA)
        s_B = s_mid + np.cumsum(dB) - 0.5 * dB
    L = s_mid + dB.sum() + lead_b
    r = np.concatenate([[lead_r], rA, rB, [lead_r]])
    z = np.concatenate([[lead_z], zA, zB, [lead_z]])
    s = np.concatenate([[0.5 * lead_a], s_A, s_B, [L - 0.5 * lead_b]])
    ds = np.concatenate([[lead_a], dA, dB, [lead_b]])
    layer = np.concatenate([[-1], lA, lB, [-1]]).astype(np.int64)
    bonded = np.ones(len(r), bool)
    bonded[0] = bonded[-1] = False
    turns = layer >= 0
    D = float(np.sum(ds[turns] * 2 * r[turns]) / L)
    keep = ds > 0
    return FibreMap(
        r=r[keep],
        z=z[keep],
        s=s[keep],
        ds=ds[keep],
        bonded=bonded[keep],
        layer=layer[keep],
        length=float(L),
        diameter=D,
    )


# ======================================================================================
# the coil in its housing: thermal network, Shupe map, runs
# ======================================================================================
