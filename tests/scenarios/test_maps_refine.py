"""A map's second stage (scenarios/maps/refine.py) on toy papers whose regions are small by construction
(tests/scenarios/toy_map_small.py): when it runs, where its points go, what it finds; resumable, the
same bits on any executor and after SIGKILL."""

from __future__ import annotations

import json
import math
import os
import signal
import time
import types

import numpy as np
import pytest

from gyrobench.scenarios.maps import build, refine
from tests.scenarios import toy_map_paper
from tests.scenarios import toy_map_small as toy
from tests.scenarios.test_map_report import _stored, _toy_cli
from tests.scenarios.test_maps import _recount

pytestmark = pytest.mark.usefixtures("user_files")


def _fam(constraints):
    return types.SimpleNamespace(FAMILY=toy.FAMILY, DESIGN_SEED=toy.DESIGN_SEED, MAP_CLAIMS=toy.MAP_CLAIMS,
                                 MAP_CONSTRAINTS=constraints)


def _map(tmp_path, constraints=toy.MAP_CONSTRAINTS, points=8, k=2, workers=0, db="u.db", **kw):
    return build.map_paper(toy, points=points, units_per_point=k, workers=workers, db=tmp_path / db,
                           family=_fam(constraints), **kw)


def _inside(doc, point, low):
    side = doc["refinement"]["box_side"]
    return all(lo - 1e-12 <= u <= lo + side + 1e-12 for u, lo in zip(point["unit_coordinates"], low, strict=True))


def test_an_empty_region_is_refined_around_the_points_satisfying_the_most_facts(tmp_path):
    doc = _map(tmp_path).result.as_dict()
    ref, first = doc["refinement"], [p for p in doc["points"] if p["stage"] == 1]
    assert ref["triggered"] and ref["basis"] == "closest misses" and ref["first_region"] == 0
    assert ref["threshold"] == 2 and len(first) == 8  # max(2, 8 // 8)
    n_sat = {p["index"]: sum(p["constraints_satisfied"].values()) for p in first}
    best = max(n_sat.values())
    assert best == 1  # x > 0.9 and y < 0.02 never together on the 8 points; each alone somewhere
    seeds = ref["seeds"]
    assert len(seeds) == refine.CLOSEST_MISSES and {i for i, s in n_sat.items() if s == best} <= set(seeds)
    assert all(n_sat[s] >= n_sat[i] for s in seeds for i in n_sat if i not in seeds)
    second = [p for p in doc["points"] if p["stage"] == 2]
    per_box = 2 ** math.floor(math.log2(8 // len(seeds)))
    assert len(second) == ref["points"] == per_box * len(seeds)
    for b, low in enumerate(ref["box_lows"]):  # each box holds its points and its seed
        assert all(_inside(doc, p, low) for p in second[b * per_box:(b + 1) * per_box])
        assert _inside(doc, doc["points"][seeds[b]], low)
    assert [p["index"] for p in doc["points"]] == list(range(16))
    reg, counts, _ = _recount(doc)
    assert reg == doc["region"] == [] and counts == doc["constraint_counts"]
    for st in ("1", "2"):  # the region and the facts counted per stage
        pts = [p for p in doc["points"] if str(p["stage"]) == st]
        assert doc["stages"][st]["points"] == len(pts)
        assert doc["stages"][st]["constraint_counts"] == {
            c: sum(p["constraints_satisfied"][c] for p in pts) for c in counts}
    assert "refined stage 0 of 8" in doc["finding"]


def test_a_one_point_region_is_refined_around_it_and_its_box_finds_region_points(tmp_path):
    doc = _map(tmp_path, toy.ONE_POINT).result.as_dict()
    ref = doc["refinement"]
    assert ref["triggered"] and ref["basis"] == "region" and ref["seeds"] == [3] and ref["first_region"] == 1
    second = [p for p in doc["points"] if p["stage"] == 2]
    assert len(second) == 8
    # by construction: a point is in the region exactly when x > 0.8 and y < 0.05 (the quantities are x, y)
    for p in doc["points"]:
        assert p["in_region"] == (p["parameters"]["x"] > 0.8 and p["parameters"]["y"] < 0.05)
    # the box around point 3 (x 0.81, y 0.016) spans x 0.685-0.935 and y below 0.03: about half its points
    # have x > 0.8; a Sobol batch of 8 over it cannot miss them all (its first 2 points split x at 0.81)
    assert doc["stages"]["2"]["region"] >= 1
    assert len(doc["region"]) == 1 + doc["stages"]["2"]["region"]


def test_a_large_region_is_not_refined(tmp_path):
    fam = types.SimpleNamespace(FAMILY=toy_map_paper.FAMILY, DESIGN_SEED=toy_map_paper.DESIGN_SEED,
                                MAP_CLAIMS=toy_map_paper.MAP_CLAIMS, MAP_CONSTRAINTS=toy_map_paper.MAP_CONSTRAINTS)
    doc = build.map_paper(toy_map_paper, points=8, units_per_point=1, workers=0, db=tmp_path / "u.db",
                          family=fam).result.as_dict()
    assert not doc["refinement"]["triggered"] and doc["refinement"]["points"] == 0
    assert len(doc["region"]) >= doc["refinement"]["threshold"] and set(doc["stages"]) == {"1"}
    assert {p["stage"] for p in doc["points"]} == {1}


def test_a_resumed_refined_map_recomputes_nothing_and_refine_false_runs_the_first_stage_only(tmp_path):
    first = _map(tmp_path)
    again = _map(tmp_path)
    assert (first.units.computed, again.units.computed, again.units.reused) == (34, 0, 34)  # 8x2 + 8x2 + nominal 2
    assert json.dumps(first.result.as_dict()) == json.dumps(again.result.as_dict())
    plain = _map(tmp_path, refine=False)
    assert plain.units.computed == 0 and len(plain.result.design) == 8 and plain.result.refinement is None


def test_band_distance_is_zero_inside_and_grows_away_from_the_band():
    from gyrobench.scenarios.claims import above, below, in_range, is_true, within_factor

    for comp, inside, near, far in ((above(1.0), 1.5, 0.9, 0.2), (below(2.0), 1.0, 2.5, 9.0),
                                    (in_range(1.0, 3.0), 2.0, 3.5, 8.0), (within_factor(10.0), 12.0, 25.0, 400.0),
                                    (is_true(), 1.0, 0.5, 0.0)):
        d = [refine.band_distance(comp, v) for v in (inside, near, far)]
        assert d[0] == 0.0 < d[1] < d[2], (comp, d)
    assert refine.band_distance(above(1.0), math.nan) == math.inf
    assert refine.refine_threshold(8) == 2 and refine.refine_threshold(32) == 4 and refine.refine_threshold(64) == 8


@pytest.mark.slow  # two local process pools: several seconds
def test_refined_maps_on_0_and_2_workers_are_identical(tmp_path):
    a = _map(tmp_path, workers=0, db="a.db")
    b = _map(tmp_path, workers=2, db="b.db")
    assert json.dumps(a.result.as_dict()) == json.dumps(b.result.as_dict()) and a.units.computed == 34


@pytest.mark.slow  # a dask.distributed LocalCluster: several seconds
def test_a_refined_dask_map_equals_the_local_map(tmp_path):
    pytest.importorskip("distributed")
    from distributed import Client, LocalCluster

    ref = _map(tmp_path, db="ref.db")
    with (
        LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster,
        Client(cluster) as client,
    ):
        got = build.map_paper(toy, points=8, units_per_point=2, executor=client.get_executor(),
                              db=tmp_path / "d.db", family=_fam(toy.MAP_CONSTRAINTS))
    assert json.dumps(got.result.as_dict()) == json.dumps(ref.result.as_dict())


def _small_cli(args, env=None):
    """``gyrobench`` with the small-region toy registered, in a child process."""
    return _toy_cli(args, env, name="toy_map_small", module="tests.scenarios.toy_map_small")


@pytest.mark.slow  # three child processes (imports ~3 s each) and a 0.2-s unit delay
def test_a_refined_map_killed_in_its_second_stage_resumes_to_the_uninterrupted_map_json(tmp_path):
    args = ["reproduce", "toy_map_small", "--map", "--points", "8", "--units-per-point", "2", "--workers", "0", "-q"]
    env = dict(os.environ, TOY_MAP_UNIT_DELAY_S="0.2")
    db = tmp_path / "k.db"
    child = _small_cli([*args, "--db", str(db), "--out", str(tmp_path / "k")], env)
    t0 = time.monotonic()
    while _stored(db) < 22 and child.poll() is None and time.monotonic() - t0 < 180:
        time.sleep(0.05)  # the first stage and the nominal are 18 units: 22 is inside the second stage
    assert child.poll() is None, child.communicate()
    child.send_signal(signal.SIGKILL)
    child.wait(timeout=60)
    done = _stored(db)
    assert 22 <= done < 34 and not (tmp_path / "k").exists()
    resumed = _small_cli([*args, "--db", str(db), "--out", str(tmp_path / "k")])
    out, err = resumed.communicate(timeout=300)
    assert resumed.returncode == 0, err
    assert f"{34 - done} computed, {done} reused" in out.decode()
    whole = _small_cli([*args, "--db", str(tmp_path / "w.db"), "--out", str(tmp_path / "w")])
    out, err = whole.communicate(timeout=300)
    assert whole.returncode == 0, err
    a = (tmp_path / "k" / "toy_map_small" / "map.json").read_bytes()
    assert a == (tmp_path / "w" / "toy_map_small" / "map.json").read_bytes()
    assert np.asarray(json.loads(a)["refinement"]["seeds"]).size == refine.CLOSEST_MISSES


def test_the_report_section_and_results_json_give_the_region_per_stage(tmp_path):
    from gyrobench.scenarios.reports.map_section import map_tables, results_link

    doc = _map(tmp_path, toy.ONE_POINT).result.as_dict()
    region_table, _ = map_tables(doc, {})
    st = doc["stages"]
    for row, c in zip(region_table.rows, doc["constraints"], strict=True):
        got = (st["1"]["constraint_counts"][c["id"]], st["2"]["constraint_counts"][c["id"]])
        assert row[3] == f"{doc['constraint_counts'][c['id']]} of 16 ({got[0]} of 8 + {got[1]} of 8)"
    assert f"{st['1']['region']} of 8 (space-filling), {st['2']['region']} of 8 (refined" in region_table.note
    link = results_link(doc)
    assert link["refinement"]["triggered"] and link["refinement"]["stages"] == st
    assert link["nominal_in_region"] is False  # the toy's nominal (x 0.5, y 0.1) misses both facts
    assert link["nominal_missed"] == ["toy.high_x", "toy.small_y"]
