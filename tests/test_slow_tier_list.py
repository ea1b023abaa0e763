"""Every test tests/data/slow_tier.txt moves to the slow tier still exists (a renamed test would
otherwise return silently to the default tier)."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_every_listed_slow_test_exists():
    lines = (ROOT / "tests" / "data" / "slow_tier.txt").read_text(encoding="utf-8").splitlines()
    ids = [ln.split("  #", 1)[0].strip() for ln in lines if ln.strip() and not ln.startswith("#")]
    assert ids
    missing = []
    for nid in ids:
        path, _, name = nid.partition("::")
        func = re.split(r"[\[:]", name, maxsplit=1)[0]
        file = ROOT / path
        if not (file.is_file() and re.search(rf"^\s*def {re.escape(func)}\(", file.read_text(), flags=re.M)):
            missing.append(nid)
    assert not missing, missing
