"""The package's code and docstrings are reference, not lab notes.

No tracker references ("issue 30", "issues 17 and 26", "#32"), no commit hashes ("commit 5994ca9",
a bare 7-40 digit hexadecimal word) and no history phrases ("until issue", "before commit",
"the last stop") in any module of sim/, analysis/, scenarios/ or src/. The reasoning behind a
model or a default lives in docs/ (docs/design-notes.md, docs/physics.md).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
FOLDERS = ("sim", "analysis", "scenarios", "src")

PATTERNS = {
    "an issue reference": re.compile(r"(?i)\bissues?\s+#?\d+"),
    "a tracker number": re.compile(r"(?<![\w:&#/])#\d{2,}\b"),
    "a commit reference": re.compile(r"(?i)\bcommits?\s+[0-9a-f]{6,40}\b"),
    # a hexadecimal word of 7-40 characters with a letter and a digit, not part of a number
    # (7.292115e-5) or a name
    "a commit hash": re.compile(r"(?<![\w.+-])(?=[0-9a-f]*[a-f])(?=[0-9a-f]*[0-9])[0-9a-f]{7,40}(?![\w.+-])"),
    "history": re.compile(r"(?i)\buntil (?:issue|commit|round)\b|\bbefore (?:issue|commit)\b|\bthe last stop\b"
                          r"|\bchanged with issue\b|\bafter the last round\b"),
}


def lab_notes(text: str) -> list[tuple[int, str, str]]:
    """(line number, kind, matched text) of every lab note in ``text``."""
    out = []
    for i, line in enumerate(text.splitlines(), 1):
        for kind, pattern in PATTERNS.items():
            out.extend((i, kind, m.group(0)) for m in pattern.finditer(line))
    return out


@pytest.mark.parametrize(
    "line",
    [
        "(Until issue 30 the default was 1e-3)",
        "reason='issues 17 and 26: the vibration error'",
        "the fixed registry (#32)",
        "Before commit 5994ca9 it was given random-walk-rate variance",
        "measured at 3f2a9c1 on main",
        "as fixed in commit deadbeef",
        "the last stop before release",
    ],
)
def test_each_kind_of_lab_note_is_found(line):
    assert lab_notes(line), line


@pytest.mark.parametrize(
    "line",
    [
        "OMEGA_E = 7.292115e-5  # rad/s",
        "color:#222; background:#fafafa",
        "github.com/tim-balloon/TIMflight/issues/77",
        "SHA-256 of the config, 64 hex digits",
        "runs until the first step whose end crosses the limit",
    ],
)
def test_reference_text_is_not_a_lab_note(line):
    assert not lab_notes(line), lab_notes(line)


def test_no_lab_notes_in_the_package():
    found = []
    for folder in FOLDERS:
        for path in sorted((ROOT / folder).rglob("*.py")):
            for i, kind, text in lab_notes(path.read_text(encoding="utf-8")):
                found.append(f"{path.relative_to(ROOT)}:{i}: {kind}: {text!r}")
    assert not found, "lab notes in the package (move the reasoning to docs/):\n" + "\n".join(found)
