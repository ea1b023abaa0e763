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
    claim (``identity``: "no different from the control" or "below the control"). Extensions (ours) are counted apart.
    ``device_calibrated`` counts the device claims that are calibrated (an input was set from
    them), which ``calibrated`` (method claims only) does not. A claim with ``same_effect_as``
    (another quantity of the effect its group's lead shows) is not counted by status: it is in
    ``same_effect`` only.

    Attributes
    ----------
    device : int
        Device claims.
    device_matched : int
        Device claims that hold.
    device_calibrated : int
        Device claims that are calibrated (an input was set from them).
    method : int
        Method claims.
    reproduced : int
        Emergent method claims reproduced.
    contradicted : int
        Method claims contradicted.
    not_reproducible : int
        Method claims not reproducible on this device.
    identity : int
        Method claims no different from (or below) the control.
    undecided : int
        Method claims undecided.
    not_testable : int
        Method claims no unit could test.
    calibrated : int
        Calibrated method claims (they hold by construction).
    extension : int
        Extensions (ours).
    extension_reproduced : int
        Extensions that hold.
    same_effect : int
        Claims showing the same effect as their group's lead (not counted by status).
    """

    device: int = 0
    device_matched: int = 0
    device_calibrated: int = 0
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
    same_effect: int = 0

    def __add__(self, other: ClaimTally) -> ClaimTally:
        from dataclasses import fields

        return ClaimTally(**{f.name: getattr(self, f.name) + getattr(other, f.name) for f in fields(self)})


_METHOD_FIELD = {
    "contradicted": "contradicted",
    "not reproducible on this device": "not_reproducible",
    "no different from the control": "identity",
    "below the control": "identity",
    "undecided": "undecided",
    "not testable": "not_testable",
}


def tally(results: Sequence[ClaimResult]) -> ClaimTally:
    """Count judged claims by role and :attr:`ClaimResult.status`.

    Parameters
    ----------
    results : sequence of ClaimResult
        Judged claims.

    Returns
    -------
    ClaimTally
        Their counts.
    """
    n: dict[str, int] = {}

    def add(key: str) -> None:
        n[key] = n.get(key, 0) + 1

    for r in results:
        role, status = r.claim.role, r.status
        if r.claim.same_effect_as is not None:
            add("same_effect")
            continue
        if role == "device":
            add("device")
            if status == "device matched":
                add("device_matched")
            if r.claim.kind == "calibrated":
                add("device_calibrated")
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
    """A deviation's effect measured by the run: every claim under our protocol and the paper's.

    A deviation's effect, measured by the run: every claim's pass count and median quantity with our
    protocol and with the paper's (the deviation's config variant), over the same ``units`` seeds.

    ``changes`` holds ``(claim id, holds, testable, holds under the variant, testable under the
    variant)`` for every claim; ``medians`` ``(median, median under the variant)`` in the same
    order (None where no unit could test the claim).

    Attributes
    ----------
    variant : str
        The deviation's config variant.
    units : int
        The seeds both protocols ran.
    changes : tuple of (str, int, int, int, int)
        (claim id, holds, testable, holds under the variant, testable under the variant).
    medians : tuple of (float or None, float or None)
        (median, median under the variant), in the order of ``changes``.
    """

    variant: str
    units: int
    changes: tuple[tuple[str, int, int, int, int], ...]
    medians: tuple[tuple[float | None, float | None], ...] = ()

    #: a median moving by more than this factor (either way) is a change even at the same pass count
    MEDIAN_FACTOR = 2.0

    def _median_moved(self, i: int) -> bool:
        if i >= len(self.medians):
            return False
        a, b = self.medians[i]
        if a is None or b is None:
            return (a is None) != (b is None)
        if a == b:
            return False
        if a == 0 or b == 0 or (a > 0) != (b > 0):
            return True
        r = abs(b / a)
        return r > self.MEDIAN_FACTOR or r < 1.0 / self.MEDIAN_FACTOR

    @property
    def changed(self) -> tuple[tuple[str, int, int, int, int], ...]:
        """The claims whose pass count or testable count the variant changes, or whose median it moves
        by more than :attr:`MEDIAN_FACTOR`."""
        return tuple(c for i, c in enumerate(self.changes) if c[1:3] != c[3:5] or self._median_moved(i))

    def text(self) -> str:
        """One phrase for the report: the changed claims (pass count and median), or that none changed."""
        if not self.changed:
            return (f"no claim's pass count changes and no median moves by more than {self.MEDIAN_FACTOR:g}x "
                    f"over {self.units} unit(s)")
        meds = dict(zip((c[0] for c in self.changes), self.medians, strict=False))

        def med(cid: str) -> str:
            if cid not in meds:
                return ""
            a, b = meds[cid]
            return f" (median {_g(a)} -> {_g(b)})"

        return f"over {self.units} unit(s): " + "; ".join(
            f"{cid} {h}/{t} -> {hv}/{tv}{med(cid)}" for cid, h, t, hv, tv in self.changed
        )

    def as_dict(self) -> dict[str, Any]:
        meds = list(self.medians) + [(None, None)] * (len(self.changes) - len(self.medians))
        return {
            "variant": self.variant,
            "units": self.units,
            "changes": [
                {"claim": cid, "holds": h, "testable": t, "holds_variant": hv, "testable_variant": tv,
                 "median": m, "median_variant": mv}
                for (cid, h, t, hv, tv), (m, mv) in zip(self.changes, meds, strict=True)
            ],
        }


def _g(x: float | None) -> str:
    return "n/a" if x is None else f"{x:.4g}"


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
        The paired pass counts and medians (claims in both).
    """
    by_id = {r.claim.id: r for r in theirs}
    paired = [r for r in ours if r.claim.id in by_id]
    changes = tuple(
        (r.claim.id, r.holds, r.testable, by_id[r.claim.id].holds, by_id[r.claim.id].testable) for r in paired
    )
    medians = tuple((r.median, by_id[r.claim.id].median) for r in paired)
    return DeviationEffect(variant=variant, units=ours[0].units if ours else 0, changes=changes, medians=medians)
