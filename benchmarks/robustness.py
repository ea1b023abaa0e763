"""How often each paper's conclusion holds across seeds (not only on the report's seed 0).

``gyrobench reproduce`` runs every scenario on one seed (0 by default) and says, per
headline, whether the paper's conclusion holds there. A conclusion that holds on seed 0
but on few other seeds is a fragile reproduction; this script measures that. For each
scenario and each seed it runs the scenario as ``gyrobench reproduce`` does
(default configuration, ``run(config, seed)``) and counts, per headline, how many seeds
give "holds", "does not hold" and "not testable" (``holds is None``). Two default
extras that decide no headline are switched off (:data:`NO_EXTRAS`): rlg_thermal's
seed table (it reruns the pipeline on seeds seed+1..seed+10, which this script runs
anyway) and mems_scale_factor's Table 4 sweep; every headline's ``holds`` is unchanged.

Seeds run on a local process pool; every seed is independent and deterministic, so the
counts do not depend on ``--workers``. Nothing is asserted: the counts go into README.md.

Run::

    python benchmarks/robustness.py [--seeds 20] [--workers 2] [--scenario NAME ...]
                                    [--seeds-for fog_vibration=8] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from collections import defaultdict
from concurrent.futures import ProcessPoolExecutor

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

PAPERS = ("mems_scale_factor", "ifog_thermal", "rlg_thermal", "fog_vibration")

#: config overrides that drop work no headline's ``holds`` depends on (module docstring)
NO_EXTRAS = {
    "rlg_thermal": {"seed_summary_count": 1},
    "mems_scale_factor": {"sf_repeatability_sweep_ppm": (0.0,), "sweep_replicates": 1},
}


def run_one(name: str, seed: int) -> tuple[str, int, list[tuple[str, bool | None]], float]:
    """Run scenario ``name`` on ``seed``; return its headlines' (quantity, holds) and runtime."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from gyrobench.scenarios import registry

    mod = registry.get(name)
    t0 = time.perf_counter()
    outcome = mod.run(mod.Config(**NO_EXTRAS.get(name, {})), seed)
    dt = time.perf_counter() - t0
    plt.close("all")
    return name, seed, [(h.quantity, h.holds) for h in outcome.headlines], dt


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seeds", type=int, default=20, help="seeds 0..N-1 per scenario")
    ap.add_argument("--seeds-for", action="append", default=[], metavar="NAME=N",
                    help="a different seed count for one scenario (e.g. fog_vibration=8)")
    ap.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--scenario", action="append", default=None, help="default: the four papers")
    ap.add_argument("--json", default=None, help="also write the counts here")
    args = ap.parse_args(argv)

    names = args.scenario or list(PAPERS)
    n_for = {n: args.seeds for n in names}
    for item in args.seeds_for:
        key, _, val = item.partition("=")
        if key not in n_for or not val.isdigit():
            ap.error(f"--seeds-for must be NAME=N with NAME in {names}; got {item!r}")
        n_for[key] = int(val)

    jobs = [(n, s) for n in names for s in range(n_for[n])]
    # counts[name][quantity] = [holds, fails, untestable]; keep first-seen headline order
    counts: dict[str, dict[str, list[int]]] = {n: {} for n in names}
    fails: dict[str, dict[str, list[int]]] = defaultdict(lambda: defaultdict(list))
    runtimes: dict[str, list[float]] = defaultdict(list)
    t0 = time.perf_counter()
    with ProcessPoolExecutor(max_workers=max(1, args.workers)) as ex:
        futures = [ex.submit(run_one, n, s) for n, s in jobs]
        for fut in futures:
            name, seed, heads, dt = fut.result()
            runtimes[name].append(dt)
            for quantity, holds in heads:
                c = counts[name].setdefault(quantity, [0, 0, 0])
                c[0 if holds is True else 1 if holds is False else 2] += 1
                if holds is False:
                    fails[name][quantity].append(seed)
    wall = time.perf_counter() - t0

    print(f"# conclusions across seeds ({len(jobs)} runs, {wall:.0f} s wall, {args.workers} workers)\n")
    for name in names:
        rt = sorted(runtimes[name])
        print(f"## {name}: seeds 0..{n_for[name] - 1}, median runtime {rt[len(rt) // 2]:.1f} s\n")
        print("| headline | holds | does not hold | not testable | failing seeds |")
        print("|---|---|---|---|---|")
        for quantity, (h, f, u) in counts[name].items():
            if h + f == 0:
                continue  # informational rows (no pass/fail meaning on any seed)
            seeds = ", ".join(map(str, fails[name][quantity][:12]))
            print(f"| {quantity} | {h} | {f} | {u} | {seeds} |")
        print()
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"seeds": n_for, "counts": counts, "failing_seeds": fails}, fh, indent=1)


if __name__ == "__main__":
    main()
