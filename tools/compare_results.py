"""Compare two reports' results.json, scenario by scenario, ignoring timings.

The house refactor must not change a result: every value of every scenario's results.json
is identical before and after, except wall-clock timings and identifiers derived from
module paths. Usage::

    python tools/compare_results.py BEFORE_DIR AFTER_DIR [--ignore REGEX ...] [scenario ...]

Exits 0 when every compared value is identical, 1 otherwise (each differing path printed).
"""

from __future__ import annotations

import argparse
import json
import math
import re
import sys
from pathlib import Path
from typing import Any

#: paths (joined with '/') that hold timings or run identifiers, not results
DEFAULT_IGNORE = (
    r"(^|/)runtime_s$",
    r"(^|/)unit_runtime_s(/|$)",
    r"(^|/)run_id$",
    r"(^|/)gyrobench_version$",
    r"(^|/)computed$",
    r"(^|/)reused$",
    r"time_ms",
    r"elapsed",
)


def _same(a: Any, b: Any) -> bool:
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    return bool(a == b)


def diff(a: Any, b: Any, path: str, ignore: list[re.Pattern[str]]) -> list[str]:
    """Paths under ``path`` where ``a`` and ``b`` differ (ignored paths skipped)."""
    if any(p.search(path) for p in ignore):
        return []
    if isinstance(a, dict) and isinstance(b, dict):
        out = [
            f"{path}/{k}: only in {'before' if k in a else 'after'}"
            for k in set(a) ^ set(b)
            if not any(p.search(f"{path}/{k}") for p in ignore)
        ]
        for k in a.keys() & b.keys():
            out += diff(a[k], b[k], f"{path}/{k}", ignore)
        return out
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f"{path}: length {len(a)} != {len(b)}"]
        return [d for i, (x, y) in enumerate(zip(a, b, strict=True)) for d in diff(x, y, f"{path}/{i}", ignore)]
    return [] if _same(a, b) else [f"{path}: {a!r} != {b!r}"]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("before", type=Path)
    ap.add_argument("after", type=Path)
    ap.add_argument("scenarios", nargs="*")
    ap.add_argument("--ignore", action="append", default=[], help="extra path regex to ignore")
    args = ap.parse_args(argv)
    ignore = [re.compile(p) for p in (*DEFAULT_IGNORE, *args.ignore)]
    names = args.scenarios or sorted(p.parent.name for p in args.after.glob("*/results.json"))
    bad = 0
    for name in names:
        a = json.loads((args.before / name / "results.json").read_text())
        b = json.loads((args.after / name / "results.json").read_text())
        d = diff(a, b, name, ignore)
        print(f"{name}: {'identical' if not d else f'{len(d)} differences'}")
        for line in d[:50]:
            print("  " + line)
        bad += bool(d)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
