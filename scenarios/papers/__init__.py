"""The paper scenarios: one subpackage per paper, discovered, and the record of each source paper.

A paper is one folder, ``p<key>_<scenario>/``, in this package's path: its package ``__init__``
states the contract's literals (``NAME``, ``TITLE``, ``PAPER`` and ``SOURCE``, a :class:`Paper`)
and re-exports the contract's functions (:mod:`gyrobench.scenarios.papers.contract`).
:func:`discover` finds the folders with :mod:`pkgutil` over ``__path__`` and reads the literals
with :mod:`ast`, so ``gyrobench list`` imports no paper (nor numpy). Titles are given in the
original Chinese with an English rendering; fields the seed texts do not give are ``None`` and
printed as "not given in the source text".
"""

from __future__ import annotations

import ast
import pkgutil
from dataclasses import dataclass
from pathlib import Path
from typing import Any

__all__ = ["DiscoveredPaper", "Paper", "citation", "discover", "sources"]

@dataclass(frozen=True, slots=True, kw_only=True)
class Paper:
    """One source paper. ``None`` marks what the seed text does not give.

    Attributes
    ----------
    key : str
        The paper's key.
    authors : str
        Romanised, family name last as printed in the paper's English front matter.
    authors_zh : str
        As printed in Chinese.
    affiliation : str
        The authors' institution.
    topic : str
        What the paper does, in one line.
    title_en, title_zh : str or None
        The English and Chinese titles.
    journal : str or None
        The journal.
    year : int or None
        The year.
    volume_issue : str or None
        Volume and issue.
    doi : str or None
        The DOI.
    source_note : str
        Where a field came from when not from the seed text.
    """

    key: str
    authors: str  # romanised, family name last as printed in the paper's English front matter
    authors_zh: str
    affiliation: str
    topic: str  # one line in our words: what the paper does
    title_en: str | None
    title_zh: str | None
    journal: str | None
    year: int | None
    volume_issue: str | None = None
    doi: str | None = None
    source_note: str = ""  # where a field came from when not from the seed text itself


@dataclass(frozen=True, slots=True)
class DiscoveredPaper:
    """A paper package found in this package's path, as its ``__init__`` states it.

    ``module`` is its dotted import path, ``origin`` its ``__init__.py``; ``bench`` says whether
    it exports ``compensation_task`` (``gyrobench bench`` can score a compensator on it).

    Attributes
    ----------
    module : str
        Its dotted import path.
    name : str
        Its scenario name (``NAME``).
    title : str
        Its ``TITLE``.
    paper : str
        Its paper key (``PAPER``).
    source : Paper or None
        Its ``SOURCE`` (None: not stated).
    bench : bool
        It exports ``compensation_task``.
    origin : str
        Its ``__init__.py``.
    """

    module: str
    name: str
    title: str
    paper: str
    source: Paper | None
    bench: bool
    origin: str


#: discovered papers by the tuple of folders searched (the path a test extends is a new key)
_FOUND: dict[tuple[str, ...], tuple[DiscoveredPaper, ...]] = {}


def discover() -> tuple[DiscoveredPaper, ...]:
    """Every paper package in this package's ``__path__``, in folder-name order.

    A subpackage is a paper; its ``__init__`` is parsed, not imported.

    Returns
    -------
    tuple of DiscoveredPaper
        The papers, in folder-name order.

    Raises
    ------
    ValueError
        If a subpackage does not set ``NAME``, ``TITLE`` and ``PAPER`` to string literals, or
        two papers share a ``NAME``.
    """
    key = tuple(str(p) for p in __path__)
    if key not in _FOUND:
        found: dict[str, DiscoveredPaper] = {}
        for info in sorted(pkgutil.iter_modules(list(__path__)), key=lambda m: m.name):
            if not info.ispkg:
                continue
            spec = info.module_finder.find_spec(info.name, None)
            if spec is None or not spec.origin:
                continue
            paper = _read(f"{__name__}.{info.name}", Path(spec.origin))
            if paper.name in found:
                raise ValueError(
                    f"paper NAME {paper.name!r} is declared twice: {found[paper.name].origin} and {paper.origin}"
                )
            found[paper.name] = paper
        _FOUND[key] = tuple(found.values())
    return _FOUND[key]


def _read(module: str, origin: Path) -> DiscoveredPaper:
    """The contract literals of the paper package whose ``__init__`` is ``origin``."""
    tree = ast.parse(origin.read_bytes(), filename=str(origin))
    constants: dict[str, Any] = {}
    source: Paper | None = None
    bench = False
    for node in tree.body:
        if isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name):
            target = node.targets[0].id
            if target in ("NAME", "TITLE", "PAPER"):
                try:
                    constants[target] = ast.literal_eval(node.value)
                except ValueError:
                    pass
            elif target == "SOURCE":
                source = _paper_literal(node.value, origin)
        elif isinstance(node, ast.FunctionDef) and node.name == "compensation_task":
            bench = True
        elif isinstance(node, ast.ImportFrom) and any(
            (a.asname or a.name) == "compensation_task" for a in node.names
        ):
            bench = True
    for name in ("NAME", "TITLE", "PAPER"):
        if not isinstance(constants.get(name), str):
            raise ValueError(f"paper package {module}: {name} must be a string literal in {origin}")
    return DiscoveredPaper(
        module, constants["NAME"], constants["TITLE"], constants["PAPER"], source, bench, str(origin)
    )


def _paper_literal(node: ast.expr, origin: Path) -> Paper:
    """``Paper(key=..., ...)`` with literal keyword arguments, built without importing the package."""
    if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "Paper"):
        raise ValueError(f"{origin}: SOURCE must be a Paper(...) call with literal keyword arguments")
    try:
        kwargs = {k.arg: ast.literal_eval(k.value) for k in node.keywords if k.arg is not None}
    except ValueError:
        raise ValueError(f"{origin}: SOURCE's arguments must be literals") from None
    return Paper(**kwargs)


def sources() -> dict[str, Paper]:
    """The source paper of every discovered paper package, by paper key.

    Returns
    -------
    dict of str to Paper
        Paper key -> source paper.
    """
    return {p.paper: p.source for p in discover() if p.source is not None}


def citation(key: str, *, short: bool = False) -> str:
    """``"Du et al."`` (short) or the full reference line, saying what the source text lacks.

    Parameters
    ----------
    key : str
        A paper key.
    short : bool
        The short form.

    Returns
    -------
    str
        The citation.

    Raises
    ------
    KeyError
        If no discovered paper package has the paper key ``key``.
    """
    p = sources()[key]
    first = p.authors.split(",")[0].split()[0]
    if short:
        return f"{first} et al." + (f" ({p.year})" if p.year else "")
    title = (
        f'"{p.title_en}" ({p.title_zh})' if p.title_en else f"[title not in the source text; {p.topic}]"
    )
    where = p.journal or "journal and year not given in the source text"
    if p.journal:
        where += f" {p.volume_issue}" if p.volume_issue else ""
        where += f", {p.year}" if p.year else ""
    doi = f", doi:{p.doi}" if p.doi else ""
    return f"{p.authors} ({p.affiliation}), {title}, {where}{doi}"
