"""How stable a report's status words are: the expected and the measured changes between seed sets.

A claim's status (:attr:`gyrobench.scenarios.claims.ClaimResult.status`) is a function of a
handful of counts over the units: how many lack the precondition, how many could test the
claim, how many pass, and the same on the control. Re-running ``reproduce`` on another seed
set redraws those counts, so a status near a boundary (a pass rate near 50 %, a Fisher p near
5 %) may change. This module gives

* the **expected** number of status changes between two independent seed sets of ``n`` units,
  from one report alone: the posterior predictive probability that two independent replicates
  of a claim's counts give different status words (:func:`flip_probability`), summed over the
  claims (:func:`expected_flips`);
* the **measured** changes between two reports of the same scenarios on different seeds
  (:func:`status_changes`).

The model
---------
Each unit falls in one of four categories for a claim: it passes, it fails, it lacks the
precondition, or it cannot test the claim (the quantity is NaN); each control unit passes,
fails or cannot test it. The category probabilities get the Jeffreys prior (Dirichlet with
all concentrations 1/2; Berger, Bernardo & Sun, Ann. Stat. 37, 905 (2009) sec. 3 for the
binomial case) updated by the report's counts, except for structural zeros, which stay
zero: the precondition category of a claim without one, the NaN category when no unit gave a
NaN, and pass and fail when no unit could test the claim (its quantity cannot be formed on
this device, so another seed set cannot form it either). For
each of ``draws`` posterior samples, two replicate populations of ``n`` units and ``n``
control units are drawn as multinomials and each is judged by the claims machinery itself
(:class:`~gyrobench.scenarios.claims.ClaimResult` built from the counts, so the status rule is
never restated here); the flip probability is the fraction of samples whose two status words
differ. Its Monte-Carlo standard error is ``sqrt(p (1 - p) / draws)``. Units are independent
given the device population (each seed draws its own parameters and noise), which is what
makes the counts multinomial.

The expected number from one report is itself an estimate: with counts at the edge of a
band (20 of 20) the posterior keeps some chance of a lower pass rate, so it is not zero.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from gyrobench.scenarios.claims import Claim, ClaimResult, Comparator, ControlResult, Precondition

__all__ = [
    "ClaimFlip",
    "StatusChange",
    "claim_from_row",
    "expected_flips",
    "flip_probability",
    "status_changes",
]

_PRIOR = 0.5  # Jeffreys: Dirichlet(1/2, ..., 1/2)


@dataclass(frozen=True, slots=True)
class ClaimFlip:
    """One claim's chance of a different status word on another seed set.

    Attributes
    ----------
    claim_id : str
        The claim's id.
    status : str
        Its status word in the report.
    probability : float
        Posterior predictive probability that two independent seed sets of ``units`` units
        give different status words.
    units : int
        The number of units (and control units) per seed set.
    """

    claim_id: str
    status: str
    probability: float
    units: int


@dataclass(frozen=True, slots=True)
class StatusChange:
    """A claim whose status word differs between two reports.

    Attributes
    ----------
    claim_id : str
        The claim's id.
    before, after : str
        Its status in the first and the second report.
    """

    claim_id: str
    before: str
    after: str


def _comparator(criterion: Mapping[str, Any]) -> Comparator:
    """A criterion as written to results.json (``float`` reads +-inf from the strings ``"inf"``)."""
    return Comparator(kind=criterion["kind"], lo=float(criterion["lo"]), hi=float(criterion["hi"]))


def claim_from_row(row: Mapping[str, Any]) -> Claim:
    """Rebuild a claim from its results.json entry (what its status rule reads, and its criterion).

    Parameters
    ----------
    row : mapping
        One entry of a results.json ``claims`` list
        (:meth:`gyrobench.scenarios.claims.ClaimResult.as_dict`).

    Returns
    -------
    Claim
        With the entry's id, role, kind, criterion and precondition (its first condition's
        criterion; the status reads only whether the claim has one).

    Raises
    ------
    KeyError
        If the entry lacks a field a claim needs.
    """
    pre = row.get("precondition")
    return Claim(
        id=row["id"], paper=row["paper"], where=row["where"], statement=row["statement"],
        kind=row["kind"], quantity=row["quantity"], comparator=_comparator(row["criterion"]),
        paper_value=row.get("paper_value"), unit=row.get("unit", ""),
        calibrated_input=row.get("calibrated_input"), role=row["role"],
        precondition=None if pre is None else Precondition(
            text=pre["text"], quantity=pre["quantity"], comparator=_comparator(pre["criterion"])),
        same_effect_as=row.get("same_effect_as"),
    )


def _unit_categories(row: Mapping[str, Any], claim: Claim) -> tuple[np.ndarray, np.ndarray]:
    """Counts and prior of (pass, fail, precondition absent, NaN) on the units."""
    n, t, h, a = (int(row[k]) for k in ("units", "testable", "holds", "precondition_absent"))
    nan = n - t - a
    if min(t - h, nan, a, h) < 0:
        raise ValueError(
            f"claim {row.get('id')!r}: inconsistent counts units={n} testable={t} holds={h} "
            f"precondition_absent={a}"
        )
    counts = np.array([h, t - h, a, nan], dtype=float)
    testable = _PRIOR if t > 0 else 0.0
    prior = np.array([testable, testable, _PRIOR if claim.precondition is not None else 0.0,
                      _PRIOR if nan > 0 else 0.0])
    return counts, prior


def _control_categories(row: Mapping[str, Any]) -> tuple[np.ndarray, np.ndarray] | None:
    """Counts and prior of (pass, fail, NaN) on the control units; None without a control."""
    c = row.get("control")
    if c is None:
        return None
    n, t, h = int(c["units"]), int(c["testable"]), int(c["holds"])
    nan = n - t
    counts = np.array([h, t - h, nan], dtype=float)
    testable = _PRIOR if t > 0 else 0.0
    prior = np.array([testable, testable, _PRIOR if nan > 0 else 0.0])
    return counts, prior


def _posterior(counts: np.ndarray, prior: np.ndarray, draws: int, rng: np.random.Generator) -> np.ndarray:
    """Dirichlet posterior samples (draws x k); structural zeros stay exactly 0."""
    alpha = counts + prior
    keep = alpha > 0
    p = np.zeros((draws, counts.size))
    p[:, keep] = rng.dirichlet(alpha[keep], size=draws)
    return p


def _status(claim: Claim, z: float, units: np.ndarray, control: np.ndarray | None) -> str:
    h, f, a, _ = (int(x) for x in units)
    ctrl = None
    if control is not None:
        ch, cf, cn = (int(x) for x in control)
        ctrl = ControlResult(units=ch + cf + cn, testable=ch + cf, holds=ch)
    return ClaimResult(
        claim=claim, units=int(units.sum()), testable=h + f, holds=h, median=None, spread=None,
        precondition_absent=a, control=ctrl, z=z,
    ).status


def flip_probability(
    row: Mapping[str, Any],
    *,
    units: int | None = None,
    draws: int = 2000,
    rng: np.random.Generator,
) -> ClaimFlip:
    """The posterior predictive probability that a claim's status differs on another seed set.

    Parameters
    ----------
    row : mapping
        The claim's entry in results.json (its role and precondition decide the status rule;
        ``units``, ``testable``, ``holds``, ``precondition_absent``, ``control``,
        ``interval_z`` and ``status`` are its counts and word).
    units : int, optional
        Units (and control units) per replicate seed set; default the report's.
    draws : int, default 2000
        Posterior samples; the Monte-Carlo standard error is ``sqrt(p (1 - p) / draws)``.
    rng : numpy.random.Generator
        The random source.

    Returns
    -------
    ClaimFlip

    Raises
    ------
    ValueError
        If ``units`` or ``draws`` is below 1, or the row's counts are inconsistent.
    """
    n = int(row["units"]) if units is None else units
    if isinstance(n, bool) or n < 1:
        raise ValueError(f"units must be an integer >= 1; got {units!r}")
    if isinstance(draws, bool) or not isinstance(draws, int) or draws < 1:
        raise ValueError(f"draws must be an integer >= 1; got {draws!r}")
    claim = claim_from_row(row)
    z = float(row.get("interval_z") or 1.959963984540054)
    counts, prior = _unit_categories(row, claim)
    pu = _posterior(counts, prior, draws, rng)
    ctrl = _control_categories(row)
    pc = None if ctrl is None else _posterior(*ctrl, draws, rng)
    rows = [rng.multinomial(n, pu), rng.multinomial(n, pu)]  # two replicate seed sets
    if pc is not None:
        rows = [np.hstack([r, rng.multinomial(n, pc)]) for r in rows]
    unique, inverse = np.unique(np.vstack(rows), axis=0, return_inverse=True)
    k = counts.size
    words = np.array([_status(claim, z, u[:k], u[k:] if pc is not None else None) for u in unique])
    judged = words[inverse.reshape(-1)]
    flips = int(np.count_nonzero(judged[:draws] != judged[draws:]))
    return ClaimFlip(claim_id=claim.id, status=str(row["status"]), probability=flips / draws, units=n)


def expected_flips(
    docs: Sequence[Mapping[str, Any]],
    *,
    units: int | None = None,
    draws: int = 2000,
    rng: np.random.Generator,
) -> tuple[ClaimFlip, ...]:
    """Every claim's flip probability over a report's results.json documents.

    Parameters
    ----------
    docs : sequence of mapping
        results.json documents (those without ``claims`` are skipped).
    units : int, optional
        Units per replicate seed set; default each report's.
    draws : int, default 2000
        Posterior samples per claim.
    rng : numpy.random.Generator
        The random source (claims are drawn in the documents' order, so a seed fixes the result).

    Returns
    -------
    tuple of ClaimFlip
        One per claim; their probabilities sum to the expected number of status changes.

    Raises
    ------
    KeyError
        If a claim's entry lacks a field (:func:`claim_from_row`).
    """
    out = []
    for doc in docs:
        for row in doc.get("claims") or ():
            out.append(flip_probability(row, units=units, draws=draws, rng=rng))
    return tuple(out)


def status_changes(
    before: Sequence[Mapping[str, Any]], after: Sequence[Mapping[str, Any]]
) -> tuple[StatusChange, ...]:
    """The claims whose status word differs between two reports.

    Parameters
    ----------
    before, after : sequence of mapping
        results.json documents of the same scenarios (e.g. seeds 0-19 and 1000-1019).

    Returns
    -------
    tuple of StatusChange
        In the order of ``before``'s claims.

    Raises
    ------
    ValueError
        If the two reports do not hold the same claims.
    """
    a = {r["id"]: r["status"] for d in before for r in d.get("claims", ())}
    b = {r["id"]: r["status"] for d in after for r in d.get("claims", ())}
    if a.keys() != b.keys():
        raise ValueError(
            f"the two reports hold different claims: {sorted(a.keys() ^ b.keys())[:5]}"
        )
    return tuple(StatusChange(k, a[k], b[k]) for k in a if a[k] != b[k])
