"""Write the contents list of docs/physics.md from its numbered sections.

Usage: ``python tools/physics_toc.py`` (rewrites the lines between ``## Contents`` and the
next ``---`` rule; inserts the list after the introduction when it is missing).
``tests/test_docs.py`` fails when the list and the sections disagree.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

DOC = Path(__file__).resolve().parents[1] / "docs" / "physics.md"
RULE = "-" * 87


def anchor(title: str) -> str:
    """GitHub's heading anchor: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"[^\w\- ]", "", title.replace("`", "").lower())
    return text.replace(" ", "-")


def contents(text: str) -> str:
    """The contents list (Markdown) of ``text``'s ``## N.`` sections and ``### N.M`` subsections."""
    lines = ["## Contents", ""]
    for m in re.finditer(r"^(#{2,3}) ((\d+)(?:\.\d+)?\.? .+)$", text, re.M):
        indent = "" if len(m.group(1)) == 2 else "  "
        title = m.group(2).strip()
        lines.append(f"{indent}- [{title}](#{anchor(title)})")
    return "\n".join(lines) + "\n"


def main() -> int:
    text = DOC.read_text(encoding="utf-8")
    toc = contents(text)
    if "\n## Contents\n" in text:
        head, rest = text.split("\n## Contents\n", 1)
        rest = rest[rest.index(RULE):]
        text = f"{head}\n{toc}\n{rest}"
    else:
        head, rest = text.split(f"\n{RULE}\n", 1)
        text = f"{head}\n\n{toc}\n{RULE}\n{rest}"
    DOC.write_text(text, encoding="utf-8")
    print(f"wrote the contents list of {DOC}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
