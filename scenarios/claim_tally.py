"""Counting and comparing judged claims (:mod:`gyrobench.scenarios.claims`): the tally by role and
status that the report's first screen and the README table show, and the effect of a deviation's
config variant on every claim."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from gyrobench.scenarios.claims import ClaimResult

__all__ = ["ClaimTally", "DeviationEffect", "deviation_effect", "tally"]


@dataclass(frozen=True, slots=True, kw_only=True)
class ClaimTally:
    """A paper's judged claims counted by role and status (the report's first screen).

    Method claims: ``reproduced`` counts only emergent ones (a calibrated claim holds by
    construction and is counted in ``calibrated``); the other statuses count every method
    claim. Extensions (ours) are counted apart.

    Attributes
    ----------
    device, device_matched : int
        Device claims, and those matched.
    method : int
        Method claims.
    reproduced, contradicted, not_reproducible, identity, undecided, not_testable : int
        Method claims by status (``reproduced``: emergent ones only).
    calibrated : int
        Calibrated method claims that hold.
    extension, extension_reproduced : int
        Our extensions, and those that hold.
    """

    device: int = 0
    device_matched: int = 0
    method: int = 0
    reproduced: int = 0
    contradicted: int = 0
    not_reproducible: int = 0
    identity: int = 0
    undecided: int = 0
    not_testable: int = 0
    calibrated: int = 0
    extension: int = 0
    extension_reproduced: int = 0

    def __add__(self, other: ClaimTally) -> ClaimTally:
        from dataclasses import fields

        return ClaimTally(**{f.name: getattr(self, f.name) + getattr(other, f.name) for f in fields(self)})


_METHOD_FIELD = {
    "contradicted": "contradicted",
    "not reproducible on this device": "not_reproducible",
    "identity of the analysis": "identity",
    "undecided": "undecided",
    "not testable": "not_testable",
}


def tally(results: Sequence[ClaimResult]) -> ClaimTally:
    """Count judged claims by role and :attr:`ClaimResult.status`.

    Parameters
    ----------
    results : sequence of ClaimResult
        A paper's judged claims.

    Returns
    -------
    ClaimTally
        The counts.
    """
    n: dict[str, int] = {}

    def add(key: str) -> None:
        n[key] = n.get(key, 0) + 1

    for r in results:
        role, status = r.claim.role, r.status
        if role == "device":
            add("device")
            if status == "device matched":
                add("device_matched")
        elif role == "extension":
            add("extension")
            if status == "reproduced":
                add("extension_reproduced")
        else:
            add("method")
            if status == "reproduced":
                add("calibrated" if r.claim.kind == "calibrated" else "reproduced")
            else:
                add(_METHOD_FIELD[status])
    return ClaimTally(**n)


@dataclass(frozen=True, slots=True, kw_only=True)
class DeviationEffect:
    """A deviation's effect, measured by the run over the same units under both protocols.

    Every claim's pass count with our protocol and with the paper's (the deviation's config
    variant), over the same ``units`` seeds.

    Attributes
    ----------
    variant : str
        The deviation's config variant.
    units : int
        Units run under both.
    changes : tuple of (str, int, int, int, int)
        ``(claim id, holds, testable, holds under the variant, testable under the variant)`` for
        every claim.
    """

    variant: str
    units: int
    changes: tuple[tuple[str, int, int, int, int], ...]

    @property
    def changed(self) -> tuple[tuple[str, int, int, int, int], ...]:
        """The claims whose pass count or testable count the variant changes."""
        return tuple(c for c in self.changes if c[1:3] != c[3:5])

    def text(self) -> str:
        """One phrase for the report: the changed claims, or that none changed."""
        if not self.changed:
            return f"no claim's pass count changes over {self.units} unit(s)"
        return f"over {self.units} unit(s): " + "; ".join(
            f"{cid} {h}/{t} -> {hv}/{tv}" for cid, h, t, hv, tv in self.changed
        )

    def as_dict(self) -> dict[str, Any]:
        return {
            "variant": self.variant,
            "units": self.units,
            "changes": [
                {"claim": cid, "holds": h, "testable": t, "holds_variant": hv, "testable_variant": tv}
                for cid, h, t, hv, tv in self.changes
            ],
        }


def deviation_effect(
    variant: str, ours: Sequence[ClaimResult], theirs: Sequence[ClaimResult]
) -> DeviationEffect:
    """Pair the claims judged on the same units under our protocol (``ours``) and the variant's.

    Parameters
    ----------
    variant : str
        The deviation's config variant.
    ours : sequence of ClaimResult
        The claims judged under our protocol.
    theirs : sequence of ClaimResult
        The same claims judged under the variant, on the same units.

    Returns
    -------
    DeviationEffect
        Every claim's pass counts under both.
    """
    by_id = {r.claim.id: r for r in theirs}
    changes = tuple(
        (r.claim.id, r.holds, r.testable, by_id[r.claim.id].holds, by_id[r.claim.id].testable)
        for r in ours
        if r.claim.id in by_id
    )
    return DeviationEffect(variant=variant, units=ours[0].units if ours else 0, changes=changes)
