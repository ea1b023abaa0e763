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
    """One source paper. ``None`` marks what the seed text does not give."""

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


PAPERS: dict[str, Paper] = {
    p.key: p
    for p in (
        Paper(
            key="000",
            authors="Fang Lin, Shen Chong, Chen Xiyuan",
            authors_zh="方琳, 申冲, 陈熙源",
            affiliation="Southeast University, Nanjing",
            topic="FOG under linear vibration: Allan terms by phase, db4 wavelet multiscale "
            "denoising and an RBF bias model against a 4th-order least-squares fit",
            title_en=None,
            title_zh=None,
            journal=None,
            year=None,
            source_note="the seed text starts at the author line; its latest reference is from 2011",
        ),
        Paper(
            key="001",
            authors="Du Renjie, Su Zhong, Liu Ning, Li Ling",
            authors_zh="杜仁杰, 苏中, 刘宁, 李羚",
            affiliation="Beijing Information Science and Technology University, "
            "Beijing Key Laboratory of High Dynamic Navigation Technology",
            topic="high-range MEMS gyro: scale-factor nonlinearity and heuristic piecewise "
            "polynomial regression",
            title_en="Research on the compensation of the scale-factor nonlinearity error of MEMS gyros",
            title_zh="MEMS陀螺标度因数非线性误差补偿方法研究",
            journal=None,
            year=None,
            source_note="the seed text has no title; the title is the one a public abstract "
            "listing gives for this abstract (15.71 % -> 0.14 %, 0.247 ms); journal and year not found",
        ),
        Paper(
            key="003",
            authors="Cheng Jianhua, Qi Bing, Zhao Lin",
            authors_zh="程建华, 齐兵, 赵琳",
            affiliation="College of Automation, Harbin Engineering University, Harbin",
            topic="IFOG temperature drift: RBF network with a T x dT product term, real-time "
            "compensation on a DSP",
            title_en="Design of compensation system for temperature drift errors of "
            "interferometric fiber optical gyroscopes",
            title_zh="干涉式光纤陀螺仪温漂误差补偿系统的设计",
            journal="Systems Engineering and Electronics (系统工程与电子技术)",
            year=2016,
            volume_issue="38(6)",
            doi="10.3969/j.issn.1001-506X.2016.06.25",
            source_note="journal from the ISSN 1001-506X in the DOI the text prints; received "
            "2015-04-20, online 2016-02-15",
        ),
        Paper(
            key="004",
            authors="Chen Jian, Liu Liying, Chen Junjun",
            authors_zh="陈剑, 刘黎映, 陈军军",
            affiliation="Naval Equipment Department pricing centre; Beijing Institute of "
            "Automatic Control Equipment",
            topic="dithered RLG variable-temperature bias (-40..+65 degC): stepwise multiple "
            "linear regression on housing and cavity temperatures",
            title_en=None,
            title_zh=None,
            journal=None,
            year=None,
            source_note="the seed text starts at the author line",
        ),
    )
}


def citation(key: str, *, short: bool = False) -> str:
    """``"Du et al."`` (short) or the full reference line, saying what the source text lacks."""
    p = PAPERS[key]
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
