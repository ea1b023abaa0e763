"""The four source papers: who wrote them, their titles, where and when they appeared.

Each paper scenario names its paper by key (``PAPER = "001"``); ``gyrobench list``,
the report headers and the README cite them from here. Titles are given in the
original Chinese with an English rendering; fields the seed texts do not give are
``None`` and printed as "not given in the source text".
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["PAPERS", "Paper", "citation"]


@dataclass(frozen=True, slots=True, kw_only=True)
class Paper:
    key: str
    authors: str
    affiliation: str
    title_zh: str
    title_en: str
    journal: str | None
    year: int | None
    volume_issue: str | None = None
    doi: str | None = None


PAPERS: dict[str, Paper] = {}  # filled in below


def citation(key: str, *, short: bool = False) -> str:
    """``"Du, Su, Liu, Li (2018)"`` (short) or the full reference line."""
    p = PAPERS[key]
    year = str(p.year) if p.year else "n.d."
    if short:
        return f"{p.authors.split(',')[0].split()[-1]} et al. ({year})"
    journal = p.journal or "journal not given in the source text"
    vi = f", {p.volume_issue}" if p.volume_issue else ""
    doi = f", doi:{p.doi}" if p.doi else ""
    return f"{p.authors}, \"{p.title_en}\" ({p.title_zh}), {journal}{vi}, {year}{doi}"
