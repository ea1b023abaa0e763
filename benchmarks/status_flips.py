"""Status flips between two seed sets: measured on the papers, beside what the model expects.

Run by hand: ``python benchmarks/status_flips.py [--seeds 0,1000] [--units 20] [--workers 2]``
runs ``gyrobench reproduce --all`` once per seed (seeds S..S+units-1, each with its control) in a
temporary folder, or ``python benchmarks/status_flips.py --reports DIR_A DIR_B`` compares two
report folders already written. It prints (never asserts) a markdown table per paper: claims,
the measured status changes, and the expected number from each report alone
(:func:`gyrobench.scenarios.reports.stability.expected_flips`, the posterior predictive of each
claim's counts, with its standard deviation ``sqrt(sum p (1 - p))``), then every changed claim
with its two words and the model's probability, and the expected number at 10, 20, 40 and 60
units, so the unit count can be chosen for a stated flip rate. About 2 x the main job's time
(``reproduce --all``), plus ~1 min of CPU for the model.
"""

from __future__ import annotations

import argparse
import datetime
import os
import subprocess
import sys
import tempfile

import numpy as np

from gyrobench.scenarios.reports.readme_table import load_report
from gyrobench.scenarios.reports.stability import expected_flips, status_changes


def _run(seed: int, units: int, workers: int, root: str) -> str:
    out = os.path.join(root, f"seed{seed}")
    exe = os.path.join(os.path.dirname(sys.executable), "gyrobench")
    cmd = [exe, "reproduce", "--all", "--seed", str(seed), "--units",
           str(units), "--workers", str(workers), "--out", out, "-q"]
    subprocess.run(cmd, check=True)
    return out


def _by_paper(docs):
    return {d["scenario"]: d for d in docs if d.get("claims")}


def _flips(docs, units=None, seed=0):
    return expected_flips(docs, units=units, rng=np.random.default_rng(seed))


def _sum(flips):
    p = np.array([f.probability for f in flips])
    return float(p.sum()), float(np.sqrt(np.sum(p * (1 - p)))), p.size


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seeds", default="0,1000", help="the two first seeds (default 0,1000)")
    ap.add_argument("--units", type=int, default=20)
    ap.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--reports", nargs=2, metavar="DIR", help="compare two report folders instead of running")
    args = ap.parse_args()
    print(f"# status flips, {datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC; "
          f"load average at the start: {', '.join(f'{x:.1f}' for x in os.getloadavg())}")
    with tempfile.TemporaryDirectory() as tmp:
        if args.reports:
            dirs = args.reports
        else:
            a, b = (int(s) for s in args.seeds.split(","))
            dirs = [_run(a, args.units, args.workers, tmp), _run(b, args.units, args.workers, tmp)]
        first, second = (load_report(d) for d in dirs)
    pa, pb = _by_paper(first), _by_paper(second)
    print(f"\nreports: {dirs[0]} against {dirs[1]}\n")
    print("| paper | claims | status changes measured | expected from report A | expected from report B |")
    print("|---|---|---|---|---|")
    flips_a, flips_b = _flips(first), _flips(second)  # the model once per report, claims in order
    by_id_a = {f.claim_id: f for f in flips_a}
    by_id_b = {f.claim_id: f for f in flips_b}
    changes_all = []
    for name in pa:
        changes = status_changes([pa[name]], [pb[name]])
        changes_all += changes
        ids = [r["id"] for r in pa[name]["claims"]]
        ea, sa, n = _sum([by_id_a[i] for i in ids])
        eb, sb, _ = _sum([by_id_b[i] for i in ids])
        print(f"| {name} | {n} | {len(changes)} | {ea:.1f} +- {sa:.1f} | {eb:.1f} +- {sb:.1f} |")
    ea, sa, n = _sum(flips_a)
    eb, sb, _ = _sum(flips_b)
    print(f"| all | {n} | **{len(changes_all)}** | {ea:.1f} +- {sa:.1f} | {eb:.1f} +- {sb:.1f} |")
    print("\n| claim | report A | report B | model's flip probability |\n|---|---|---|---|")
    for c in changes_all:
        print(f"| {c.claim_id} | {c.before} | {c.after} | {by_id_a[c.claim_id].probability:.2f} |")
    print("\nexpected status changes from report A at other unit counts:\n")
    print("| units | expected | share of the claims |\n|---|---|---|")
    for units in (10, 20, 40, 60):
        same = all(int(d["units"]) == units for d in pa.values())  # the report's own count: reuse it
        e, s, n = _sum(flips_a if same else _flips(first, units=units))
        print(f"| {units} | {e:.1f} +- {s:.1f} | {100 * e / n:.0f} % |")


if __name__ == "__main__":
    main()
