"""Calibrate the bench's gate: detection and false-alarm rates for known regressions, per scenario.

For every seed of a scenario the reference compensator (ifog_thermal: the README's Ridge
pipeline; the others: the paper's method the bench prints) is fitted once, in this process,
and its prediction on every held-out run is degraded by a known fraction ``lam`` of itself,
toward the uncompensated output:

    prediction_lam = (1 - lam) prediction + lam raw

(``raw`` = 0 for an error target, the output for a rate target), which leaves ``lam`` of the
compensated error in the output. Each ``lam`` is scored with the bench's own scoring
(:func:`gyrobench.scenarios.bench.scoring.score_predictions`). The change of a primary score
is measured over all the seeds three ways: the change of the mean score (mean c_s / mean b_s - 1,
what the gate judges), the mean per-seed change (mean of c_s / b_s - 1, by which the cases are
chosen) and the *typical* seed's change (the Hodges-Lehmann location of c_s / b_s - 1). A
partial regression degrades a random half of the seeds only. Then, for random subsets of
``--n`` seeds (the README's 12), the gate itself (:func:`gyrobench.scenarios.bench.compare`,
with the margin ``--margin``) decides; the table gives, per ``lam``, the true change and the
fraction of subsets the gate calls a regression (a false alarm when the true change is within
the margin, a detection above it), beside what the baseline file claims its seeds detect
(:func:`gyrobench.scenarios.bench.gate.detectable`, margin included) and what the comparison
prints (:attr:`~gyrobench.scenarios.bench.Comparison.power_line`, its median over subsets), and
the seed count ``--seeds auto`` asks for from a baseline of ``--n`` seeds (median over 50
subsets) with the fraction of comparisons of that many seeds, drawn with replacement from the
simulated ones, that the gate calls a regression.

Run: ``python benchmarks/bench_calibrate.py [--scenarios ifog_thermal,rlg_thermal] [--seeds 40]
[--n 12] [--draws 300] [--margin 0.05] [--cache DIR]`` (simulating: 0.3-3.7 s of CPU per seed;
the gate on the cached scores: 15 s to 2 min of CPU per scenario).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

#: target true changes of the primary score (the gate's margin is --margin)
TARGETS = (0.0, 0.002, 0.01, 0.02, 0.04, 0.06, 0.08, 0.10, 0.15, 0.20)
#: degradation factors searched for each target: prediction scaled by (1 - lam) toward the raw
#: output; negative lam overshoots (whichever branch first reaches the target is used)
#: partial regressions: (mean per-seed change over all the seeds, degradation branches tried)
PARTIAL = ((0.05, (1,)), (0.10, (1,)), (0.19, (-1, 1)))
LAMS = tuple(sorted({0.0, *np.round(np.geomspace(1e-4, 1.0, 36), 6), *(-np.round(np.geomspace(1e-4, 1.0, 36), 6))}))


def _base(name: str) -> Any:
    from gyrobench.scenarios.bench.compensators import resolve_compensator
    from gyrobench.scenarios.bench.primary import scenario_scores

    if name == "ifog_thermal":
        from sklearn.linear_model import Ridge
        from sklearn.pipeline import make_pipeline
        from sklearn.preprocessing import PolynomialFeatures, StandardScaler

        return make_pipeline(StandardScaler(), PolynomialFeatures(2), Ridge(alpha=1e-3))
    declared = scenario_scores(name)
    return resolve_compensator(declared.paper)


def _seed_scores(module: Any, comp: Any, seed: int) -> dict[float, dict[str, float]]:
    from threadpoolctl import threadpool_limits

    from gyrobench.scenarios.bench.compensators import fit_compensator
    from gyrobench.scenarios.bench.scoring import score_predictions

    with threadpool_limits(limits=1):
        task = module.compensation_task(module.Config(), seed)
        predict = fit_compensator(
            comp, task.X_train, task.y_train, seed, label="base", groups=getattr(task, "groups_train", None)
        )
        preds = {id(run.X): np.asarray(predict(run.X), dtype=float).reshape(-1) for run in task.heldout}
        raws = {id(run.X): (np.zeros(len(run.output)) if task.target == "error" else np.asarray(run.output, float))
                for run in task.heldout}
        out = {}
        for lam in LAMS:
            def degraded(X, lam=lam):
                return (1 - lam) * preds[id(X)] + lam * raws[id(X)]

            scores, failure = score_predictions(task, degraded, seed, "base")
            if failure is not None:
                raise RuntimeError(f"seed {seed} lam {lam}: {failure}")
            out[lam] = scores
    return out


def _campaign(name: str, scores: dict[int, dict[str, float]], label: str) -> Any:
    """A campaign of the primary scores only (the gate reads nothing else)."""
    from gyrobench.scenarios import bench
    from gyrobench.scenarios.bench.primary import gated_scores

    first = next(iter(scores.values()))
    keep = {g.name for g in gated_scores(name, list(first))}
    scores = {s: {k: v for k, v in sc.items() if k in keep} for s, sc in scores.items()}
    return bench.Campaign(campaign_id=label, scenario=name, compensator=label, config="", scores=scores)


def _scored(
    name: str, n_seeds: int, cache: Path | None
) -> tuple[dict[int, dict[float, dict[str, float]]], float, float]:
    """Per seed, per degradation: the scores (read from ``cache`` when it holds these seeds), and
    the wall and CPU seconds per seed of computing them."""
    from gyrobench.scenarios import bench

    path = cache / f"{name}.json" if cache is not None else None
    if path is not None and path.exists():
        doc = json.loads(path.read_text())
        if doc["seeds"] >= n_seeds and [float(v) for v in doc["lams"]] == [float(v) for v in LAMS]:
            per_seed = {int(s): {_lam(k): v for k, v in by.items()} for s, by in doc["scores"].items()}
            return {s: per_seed[s] for s in range(n_seeds)}, doc["seed_s"], doc["seed_cpu_s"]
    module = bench.resolve_scenario(name)
    comp = _base(name)
    t0, c0 = time.perf_counter(), time.process_time()
    per_seed = {}
    for s in range(n_seeds):
        per_seed[s] = _seed_scores(module, comp, s)
        print(f"  {name}: seed {s} scored", file=sys.stderr, flush=True)
    took, cpu = (time.perf_counter() - t0) / n_seeds, (time.process_time() - c0) / n_seeds
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        doc = {"seeds": n_seeds, "lams": [float(v) for v in LAMS], "seed_s": took, "seed_cpu_s": cpu,
               "scores": {str(s): {repr(float(k)): v for k, v in by.items()} for s, by in per_seed.items()}}
        path.write_text(json.dumps(doc))
    return per_seed, took, cpu


def _lam(key: str) -> float:
    """A degradation factor from its key in the cache (``"-0.5"``, or numpy's ``"np.float64(-0.5)"``)."""
    return float(key.removeprefix("np.float64(").removesuffix(")"))


def calibrate(
    name: str, n_seeds: int, n: int, draws: int, margin: float, alpha: float, cache: Path | None = None
) -> list[dict]:
    from gyrobench.scenarios import bench
    from gyrobench.scenarios.bench import gate
    from gyrobench.scenarios.bench.power import auto_seeds, spread, std_upper_bound
    from gyrobench.scenarios.bench.primary import gated_scores
    from gyrobench.scenarios.bench.statistics import hodges_lehmann

    per_seed, took, cpu = _scored(name, n_seeds, cache)
    by_lam = {lam: {s: per_seed[s][lam] for s in per_seed} for lam in LAMS}
    names = list(by_lam[0.0][0])
    gates = [g.name for g in gated_scores(name, names)]
    directions = {g.name: g.direction for g in gated_scores(name, names)}

    def true_change(lam: float, seeds: Any = range(n_seeds)) -> dict[str, float]:
        out = {}
        for g in gates:
            b = np.array([by_lam[0.0][s][g] for s in seeds])
            c = np.array([by_lam[lam][s][g] for s in seeds])
            out[g] = float(np.mean(c / b - 1))
        return out

    curve = {lam: max(true_change(lam).values()) for lam in LAMS}
    rng = np.random.default_rng(20261201)
    subsets = [sorted(rng.choice(n_seeds, size=n, replace=False).tolist()) for _ in range(draws)]
    claims: dict[str, list[float]] = {}
    autos = []
    for sub in subsets[:50]:
        base = _campaign(name, {s: by_lam[0.0][s] for s in sub}, "base")
        for d in gate.detectable(base, alpha=alpha, min_change=margin):
            claims.setdefault(d.name, []).append(margin + d.relative)
        spreads = {g: (*spread(base.values(g)), std_upper_bound(base.values(g))) for g in gates}
        autos.append(auto_seeds(len(gates), alpha, spreads=spreads, min_change=margin).n)
    n_auto = int(np.median(autos))
    cases = [(t, _lam_for(curve, t), None) for t in TARGETS]
    cases = [c for c in cases if c[0] == 0 or c[1] != 0]  # no degradation reaches that change
    half = sorted(rng.choice(n_seeds, size=n_seeds // 2, replace=False).tolist())  # a partial regression
    for target, branches in PARTIAL:  # overshoot / toward the raw output, on half the seeds
        for branch in branches:
            lam = min((k for k in curve if k * branch > 0), key=lambda k: abs(curve[k] - 2 * target))
            if abs(curve[lam] - 2 * target) <= 0.15 * 2 * target:
                cases.append((target, lam, half))
    rows = []
    for target, lam, only in cases:
        cand_scores = {s: (by_lam[lam][s] if only is None or s in only else by_lam[0.0][s]) for s in range(n_seeds)}
        true, typical, of_mean = {}, {}, {}
        for g in gates:
            b = np.array([by_lam[0.0][s][g] for s in range(n_seeds)])
            c = np.array([cand_scores[s][g] for s in range(n_seeds)])
            true[g] = float(np.mean(c / b - 1))
            typical[g] = hodges_lehmann(c / b - 1)
            of_mean[g] = float(np.mean(c) / np.mean(b) - 1)
        hits, printed = 0, []
        for sub in subsets:
            base = _campaign(name, {s: by_lam[0.0][s] for s in sub}, "base")
            cand = _campaign(name, {s: cand_scores[s] for s in sub}, f"lam{lam}")
            res = bench.compare(base, cand, alpha=alpha, min_change=margin)
            hits += bool(res.regressions)
            printed.append(max(d.change for d in res.detectable) if res.detectable else math.nan)
        rows.append({
            "scenario": name, "target": target, "lam": lam, "partial": only is not None, "true": true,
            "typical": typical, "of_mean": of_mean, "rate": hits / draws, "n_auto": n_auto,
            "rate_auto": _resampled_rate(by_lam[0.0], cand_scores, directions, n_auto, alpha, margin, rng),
            "printed": float(np.nanmedian(printed)) if np.isfinite(printed).any() else math.inf,
            "claimed": {k: float(np.median(v)) for k, v in claims.items()},
            "seed_s": took, "seed_cpu_s": cpu,
        })
    return rows


def _resampled_rate(
    base: dict[int, dict[str, float]], cand: dict[int, dict[str, float]], gates: dict[str, int], n: int,
    alpha: float, margin: float, rng: np.random.Generator, draws: int = 100,
) -> float:
    """Fraction of ``draws`` comparisons of ``n`` seeds drawn with replacement from the simulated
    ones (a comparison longer than the seeds simulated, as --seeds auto may ask) that the gate's
    test (:func:`~gyrobench.scenarios.bench.margin.margin_test`, Holm over ``gates``: name -> direction)
    calls a regression."""
    from gyrobench.scenarios.bench.margin import margin_test

    seeds = sorted(base)
    b_all = {g: np.array([base[s][g] for s in seeds]) for g in gates}
    c_all = {g: np.array([cand[s][g] for s in seeds]) for g in gates}
    hits = 0
    for _ in range(draws):
        idx = rng.integers(0, len(seeds), n)
        tests = []
        for g, direction in gates.items():
            p, sign = margin_test(c_all[g][idx] - b_all[g][idx], b_all[g][idx], direction, margin)
            tests.append((p, sign * direction < 0))
        for k, (p, worse) in enumerate(sorted(tests)):  # Holm: step down while p < alpha / (m - k)
            if p >= alpha / (len(tests) - k):
                break
            if worse:
                hits += 1
                break
    return hits / draws


def _lam_for(curve: dict[float, float], target: float) -> float:
    """The degradation whose true change is closest to ``target``, among the smallest ones."""
    if target == 0:
        return 0.0
    best = min(curve, key=lambda lam: (abs(curve[lam] - target) > 0.15 * target + 5e-4, abs(lam)))
    return best


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenarios", default="ifog_thermal,rlg_thermal,mems_scale_factor,fog_vibration")
    ap.add_argument("--seeds", type=int, default=40, help="seeds simulated per scenario")
    ap.add_argument("--n", type=int, default=12, help="seeds per comparison (the README's 12)")
    ap.add_argument("--draws", type=int, default=300, help="random subsets of --n seeds")
    ap.add_argument("--margin", type=float, default=0.05, help="the gate's --min-change")
    ap.add_argument("--alpha", type=float, default=0.05)
    ap.add_argument("--cache", type=Path, default=None,
                    help="folder for the per-seed scores (reused by a later run with as many seeds)")
    args = ap.parse_args(argv)
    print(f"gate calibration: {args.n} of {args.seeds} seeds per comparison, {args.draws} subsets, margin "
          f"{100 * args.margin:g} %, alpha {args.alpha:g}")
    print(f"| scenario | degraded by | change of the mean primary score(s) (mean per-seed, typical seed) "
          f"| called a regression at {args.n} seeds | "
          "detectable (comparison prints, median) | detectable (baseline file claims) | "
          "--seeds auto (median) | called a regression at that count |")
    print("|---|---|---|---|---|---|---|---|")
    for name in args.scenarios.split(","):
        rows = calibrate(name, args.seeds, args.n, args.draws, args.margin, args.alpha, args.cache)
        for r in rows:
            true = ", ".join(f"{k.split('/')[-1]} {100 * r['of_mean'][k]:+.2f} % (per seed {100 * v:+.2f} %, "
                             f"typical seed {100 * r['typical'][k]:+.2f} %)" for k, v in r["true"].items())
            claimed = ", ".join(f"{100 * v:.3g} %" for v in r["claimed"].values())
            what = f"{100 * r['lam']:+.3g} %" + (" on half the seeds" if r["partial"] else "")
            print(f"| {name} | {what} | {true} | {100 * r['rate']:.1f} % | "
                  f"{100 * r['printed']:.3g} % | {claimed} | {r['n_auto']} | {100 * r['rate_auto']:.1f} % |",
                  flush=True)
        print(f"({name}: {rows[0]['seed_s']:.2f} s wall, {rows[0]['seed_cpu_s']:.2f} s CPU per seed, in process)",
              file=sys.stderr, flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
