"""The map machinery (scenarios/maps) on a toy paper whose region and claim verdicts are known by
construction (tests/scenarios/toy_map_paper.py), map.json recomputed independently, the CLI's bad input."""

from __future__ import annotations

import dataclasses
import json
import math
import types

import numpy as np
import pytest
from scipy.stats import beta

from gyrobench.scenarios import registry
from gyrobench.scenarios.maps import build, region
from gyrobench.scenarios.maps.family import Family, Parameter, design
from gyrobench.scenarios.maps.run import run_map, unit_seed
from tests.scenarios import toy_map_paper as toy
from tests.scenarios.test_cli import assert_one_line_error, run

pytestmark = pytest.mark.usefixtures("user_files")


def _map(tmp_path, points=16, k=3, workers=0, db_name="u.db"):
    fam = types.SimpleNamespace(FAMILY=toy.FAMILY, DESIGN_SEED=toy.DESIGN_SEED, MAP_CLAIMS=toy.MAP_CLAIMS,
                                MAP_CONSTRAINTS=toy.MAP_CONSTRAINTS)
    return build.map_paper(toy, points=points, units_per_point=k, workers=workers, db=tmp_path / db_name,
                           family=fam)


@pytest.fixture(scope="module")
def toy_map(tmp_path_factory):
    """One 16-point x 3-unit map of the toy paper, shared by the tests that only read it."""
    return _map(tmp_path_factory.mktemp("toy_map"))


def _reanalysed(mapped, constraints):
    """The same units judged against other constraints (no unit is rerun)."""
    r = mapped.result
    return region.analyse(r.family, r.design, r.seeds, mapped.units.quantities[:len(r.design)], constraints,
                          toy.MAP_CLAIMS)


def test_design_sobol_for_a_power_of_two_lhs_otherwise_within_the_ranges():
    d = design(toy.FAMILY, 16, 3)
    assert d.method == "sobol" and len(d) == 16
    xs = np.array([v["x"] for v in d.values])
    ys = np.array([v["y"] for v in d.values])
    assert xs.min() >= 0 and xs.max() <= 1 and ys.min() >= 1e-2 and ys.max() <= 1
    # a scrambled Sobol net in base 2: each of the 16 intervals of width 1/16 holds one point per axis
    assert sorted(np.floor(d.unit[:, 0] * 16).astype(int)) == list(range(16))
    np.testing.assert_allclose(np.log10(ys), -2 + 2 * d.unit[:, 1], rtol=0, atol=1e-12)  # log scale
    lhs = design(toy.FAMILY, 10, 3)
    assert lhs.method == "lhs"
    for j in range(2):  # a Latin hypercube: one point in each of the 10 strata of each axis
        assert sorted(np.floor(lhs.unit[:, j] * 10).astype(int)) == list(range(10))
    assert design(toy.FAMILY, 16, 3).unit.tobytes() == d.unit.tobytes()  # the seed fixes the design


def test_family_refuses_a_point_outside_its_range_and_unknown_fields():
    with pytest.raises(ValueError, match="x must be in"):
        toy.FAMILY.config({"x": 1.5, "y": 0.1})
    with pytest.raises(ValueError, match="not a field"):
        Family(paper="t", base=toy.Config(), parameters=(
            Parameter(field="z", range=toy.FAMILY.parameters[0].range, scale="linear", source="s", label="z"),))


def test_unit_seeds_depend_on_point_and_unit_index_only():
    seeds = {unit_seed(0, i, j) for i in range(50) for j in range(1000)}
    assert len(seeds) == 50_000  # no two (point, unit) pairs share a seed
    with pytest.raises(ValueError):
        unit_seed(0, 0, 1000)


def test_region_and_claim_verdicts_known_by_construction(toy_map):
    r = toy_map.result
    xs = [v["x"] for v in r.design.values]
    ys = [v["y"] for v in r.design.values]
    expected = tuple(i for i in range(16) if xs[i] > 0.3 and ys[i] < 0.5)
    assert 0 < len(expected) < 16  # the design straddles the region's edges
    assert r.region == expected
    assert r.counts() == {"toy.fact_x": sum(x > 0.3 for x in xs), "toy.fact_y": sum(y < 0.5 for y in ys)}
    assert region.conflicts(r) == ()
    q = next(m for m in r.claims if m.claim.id == "toy.q")
    # points farther than 4 sigma (0.2) from the claim's edge at 0.6: every unit on the same side
    # (a false alarm per unit of 6e-5, 48 units)
    clear = [i for i in expected if abs(xs[i] - 0.6) > 0.2]
    assert clear
    for i in clear:
        assert q.point_verdicts[i] == ("holds" if xs[i] > 0.6 else "fails")
    assert q.region_n == len(expected)  # every region point has x > 0.3 > 0.1: all could test it
    assert q.sensitivity[0].field == "x" and q.sensitivity[0].rho > 0  # q rises with x, not with y
    s = next(m for m in r.claims if m.claim.id == "toy.score")
    fails = [i for i in expected if s.point_verdicts[i] == "fails"]
    assert all(ys[i] > 0.2 for i in fails)  # the score is y + 0.01 e: only y above 0.25 (-5 sigma) can miss
    assert s.misses == ({"above": len(fails)} if fails else {})
    low_x = [i for i in range(16) if xs[i] <= 0.1]
    assert all(q.point_verdicts[i] == "not testable" for i in low_x)


def test_empty_region_is_a_finding_naming_the_conflicting_and_the_impossible_facts(toy_map):
    r = _reanalysed(toy_map, (*toy.MAP_CONSTRAINTS, toy.CONFLICTING))
    assert r.region == ()
    assert ("toy.fact_x", "toy.wide") in region.conflicts(r)
    text = region.region_finding(r)
    assert "No point" in text and "toy.fact_x and toy.wide" in text
    r2 = _reanalysed(toy_map, (*toy.MAP_CONSTRAINTS, toy.NEVER))
    assert r2.region == ()
    assert "Never satisfied on the family: toy.never (needs > 2; closest: " in region.region_finding(r2)
    assert all(m.region_n == 0 and m.interval95 is None for m in r2.claims)


def _recount(doc):
    """The region, the counts, the conflicts and each claim's region verdict from map.json alone."""
    def ok(c, v):
        if v is None:
            return False
        lo = -math.inf if c["lo"] is None else c["lo"]
        hi = math.inf if c["hi"] is None else c["hi"]
        return {"above": v > lo, "below": v < hi, "is_true": v == 1.0}.get(c["kind"], lo <= v <= hi)

    cons = doc["constraints"]
    sat = [[ok(c, p["constraint_medians"][c["id"]]) for c in cons] for p in doc["points"]]
    reg = [p["index"] for p, row in zip(doc["points"], sat, strict=True) if all(row)]
    counts = {c["id"]: sum(row[j] for row in sat) for j, c in enumerate(cons)}
    verdicts = {}
    for c in doc["claims"]:
        got = [doc["points"][i]["claims"][c["id"]] for i in reg]
        tested = [g for g in got if g["testable"] > 0]
        k = sum(2 * g["holds"] > g["testable"] for g in tested)
        n = len(tested)
        ci = None
        if n:  # Clopper-Pearson from the beta quantiles
            ci = [0.0 if k == 0 else beta.ppf(0.025, k, n - k + 1), 1.0 if k == n else beta.ppf(0.975, k + 1, n - k)]
        everywhere = [p["claims"][c["id"]] for p in doc["points"] if p["claims"][c["id"]]["testable"] > 0]
        verdicts[c["id"]] = (k, n, ci, sum(2 * g["holds"] > g["testable"] for g in everywhere), len(everywhere))
    return reg, counts, verdicts


def _recount_nominal(doc):
    """The nominal device's region membership and the region's medoid from map.json alone."""
    def ok(c, v):
        lo = -math.inf if c["lo"] is None else c["lo"]
        hi = math.inf if c["hi"] is None else c["hi"]
        return v is not None and {"above": v > lo, "below": v < hi, "is_true": v == 1.0}.get(c["kind"], lo <= v <= hi)

    reg = [p for p in doc["points"] if all(ok(c, p["constraint_medians"][c["id"]]) for c in doc["constraints"])]
    total = [sum(math.dist(p["unit_coordinates"], q["unit_coordinates"]) for q in reg) for p in reg]
    medoid = reg[total.index(min(total))]["index"] if reg else None
    nom = doc["nominal"]
    inside = None if nom is None else all(ok(c, nom["constraint_medians"][c["id"]]) for c in doc["constraints"])
    return inside, medoid


def test_map_json_recomputed_independently(toy_map, tmp_path):
    path = build.write_map(toy_map, tmp_path / "out")
    doc = json.loads(path.read_text())
    assert next(iter(doc)) == "format" and doc["format"] == region.MAP_FORMAT
    assert "command" not in doc and "unit_run" not in doc  # how the run went: map_run.json beside it
    assert json.loads((tmp_path / "out" / build.RUN_FILE).read_text())["computed"] == 16 * 3 + 3
    reg, counts, verdicts = _recount(doc)
    assert reg == doc["region"] and counts == doc["constraint_counts"]
    assert [p["index"] for p in doc["points"] if p["in_region"]] == reg
    inside, medoid = _recount_nominal(doc)
    assert (inside, medoid) == (doc["nominal"]["in_region"], doc["medoid"]["index"])
    for c in doc["claims"]:
        k, n, ci, fk, fn = verdicts[c["id"]]
        assert (c["region_holds"], c["region_testable"]) == (k, n)
        assert (c["family_holds"], c["family_testable"]) == (fk, fn)
        np.testing.assert_allclose(c["interval95"], ci, rtol=1e-9, atol=1e-12)
    assert (tmp_path / "out" / "phase_diagrams.png").stat().st_size > 10_000
    assert (tmp_path / "out" / "specification_curves.png").stat().st_size > 10_000


def test_a_resumed_map_recomputes_nothing_and_gives_the_same_result(tmp_path):
    first = _map(tmp_path, points=4, k=2)
    again = _map(tmp_path, points=4, k=2)
    assert (first.units.computed, again.units.computed, again.units.reused) == (10, 0, 10)  # 4 x 2 + nominal
    assert first.result.as_dict() == again.result.as_dict()
    # a point's run id is the one `reproduce` gives its config: a map and a reproduce share stored units
    cfg = toy.FAMILY.config(first.result.design.values[3])
    from gyrobench.scenarios.runner import units

    assert first.units.run_ids[3] == units.run_id(toy, cfg)[0]


@pytest.mark.slow  # two local process pools: several seconds
def test_workers_0_and_2_give_identical_maps(tmp_path):
    a = _map(tmp_path, points=4, k=2, workers=0, db_name="a.db")
    b = _map(tmp_path, points=4, k=2, workers=2, db_name="b.db")
    assert json.dumps(a.result.as_dict()) == json.dumps(b.result.as_dict())
    assert a.units.computed == b.units.computed == 10


def test_run_map_refuses_bad_sizes(tmp_path):
    with pytest.raises(ValueError, match="units per point"):
        run_map(toy, [toy.Config()], units_per_point=0, workers=0, db=tmp_path / "u.db")
    with pytest.raises(ValueError, match="points must be"):
        design(toy.FAMILY, 1, 0)
    cfg = dataclasses.replace(toy.Config(), x=0.9)
    got = run_map(toy, [cfg], units_per_point=1, workers=0, db=tmp_path / "u.db")
    assert got.quantities[0][0]["fact_x"] == 0.9


@pytest.fixture
def toy_map_registered(monkeypatch):
    monkeypatch.setitem(registry.SCENARIOS, "toy_map_paper", "tests.scenarios.toy_map_paper")


@pytest.mark.parametrize("argv, needle", [
    (["reproduce", "toy_map_paper", "rlg_thermal", "--map"], "name exactly one"),
    (["reproduce", "toy_map_paper", "--map", "--points", "1"], "--points"),
    (["reproduce", "toy_map_paper", "--points", "8"], "go with --map"),
    (["reproduce", "toy_map_paper", "--map", "--deviations"], "--deviations does not apply"),
    (["reproduce", "static_noise", "--map"], "defines no device family"),
])
def test_map_cli_bad_input_is_one_line_exit_2(toy_map_registered, tmp_path, capsys, argv, needle):
    code, out, err = run([*argv, "--out", tmp_path / "r"], capsys)
    assert_one_line_error(code, err, needle)
    assert not (tmp_path / "r").exists()


def test_map_cli_writes_map_json_and_pngs_into_a_report_folder(toy_map_registered, tmp_path, capsys):
    code, out, err = run(["reproduce", "toy_map_paper", "--map", "--points", "8", "--units-per-point", "2",
                          "--workers", "0", "-q", "--out", tmp_path / "r"], capsys)
    assert code == 0, err
    doc = json.loads((tmp_path / "r" / "toy_map_paper" / "map.json").read_text())
    assert doc["design"] == {"method": "sobol", "seed": toy.DESIGN_SEED, "points": 8, "units_per_point": 2}
    assert _recount(doc)[0] == doc["region"]
    code, out, err = run(["reproduce", "toy_map_paper", "--map", "--points", "8", "--units-per-point", "2",
                          "--workers", "0", "-q", "--out", tmp_path / "r"], capsys)
    assert code == 0, err  # an earlier map's folder is replaced; its units come from the store
    assert "0 computed, 18 reused" in out  # 8 x 2 and the nominal's 2


@pytest.mark.slow  # a dask.distributed LocalCluster: several seconds
def test_dask_localcluster_map_equals_the_local_map(tmp_path):
    pytest.importorskip("distributed")
    from distributed import Client, LocalCluster

    ref = _map(tmp_path, points=4, k=2, workers=0, db_name="ref.db")
    fam = types.SimpleNamespace(FAMILY=toy.FAMILY, DESIGN_SEED=toy.DESIGN_SEED, MAP_CLAIMS=toy.MAP_CLAIMS,
                                MAP_CONSTRAINTS=toy.MAP_CONSTRAINTS)
    with (
        LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster,
        Client(cluster) as client,
    ):
        got = build.map_paper(toy, points=4, units_per_point=2, executor=client.get_executor(),
                              db=tmp_path / "d.db", family=fam)
    assert json.dumps(got.result.as_dict()) == json.dumps(ref.result.as_dict())


def test_paper_004_family_is_its_config_fields_with_sources_and_its_device_facts():
    from gyrobench.scenarios.papers.p004_rlg_thermal import CLAIMS, Config
    from gyrobench.scenarios.papers.p004_rlg_thermal import family as f004
    from gyrobench.scenarios.papers.p004_rlg_thermal.identify import IDENTIFIED

    for p in f004.FAMILY.parameters:  # every range lies inside the Config's documented range
        spec = Config.RANGES[p.field]
        assert spec.contains(p.range.low) and spec.contains(p.range.high), p.field
        assert p.range.unit == spec.unit, p.field
    eta = next(p for p in f004.FAMILY.parameters if p.field == "dissipative")
    assert eta.range.contains(IDENTIFIED.dissipative)  # the nominal device lies in the family
    assert "ASSUMPTION" in eta.source
    device = [c for c in CLAIMS if c.role == "device"]
    assert [(c.id, c.quantity, c.comparator) for c in f004.MAP_CONSTRAINTS] == [
        (c.id, c.quantity, c.comparator) for c in device]
    assert f004.MAP_CLAIMS and all(c.role != "device" and c.precondition is not None for c in f004.MAP_CLAIMS)


@pytest.mark.slow  # paper 004's real units (about 1 s of CPU each): a 4-point map through the CLI
def test_paper_004_map_through_the_cli_recounts_from_map_json(tmp_path, capsys):
    code, out, err = run(["reproduce", "rlg_thermal", "--map", "--points", "4", "--units-per-point", "1",
                          "--workers", "0", "-q", "--out", tmp_path / "r"], capsys)
    assert code == 0, err
    folder = tmp_path / "r" / "rlg_thermal"
    doc = json.loads((folder / "map.json").read_text())
    reg, counts, verdicts = _recount(doc)
    assert reg == doc["region"] and counts == doc["constraint_counts"]
    for c in doc["claims"]:
        assert (c["region_holds"], c["region_testable"]) == verdicts[c["id"]][:2]
    for name in ("phase_diagrams.png", "specification_curves.png", "constraints.png"):
        assert (folder / name).stat().st_size > 10_000


def test_map_cli_refuses_a_foreign_out_folder_and_leaves_it_alone(toy_map_registered, tmp_path, capsys):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    code, _, err = run(["reproduce", "toy_map_paper", "--map", "--points", "4", "--workers", "0", "-q",
                        "--out", out], capsys)
    assert_one_line_error(code, err, "--out")
    assert [p.name for p in out.iterdir()] == ["notes.txt"] and (out / "notes.txt").read_text() == "mine"


def test_nominal_device_runs_as_its_own_point_and_the_medoid_is_the_central_region_point(toy_map):
    from scipy.spatial.distance import cdist

    from gyrobench.scenarios.maps.run import NOMINAL_POINT

    r = toy_map.result
    n = r.nominal
    assert n is not None and n.values == {"x": 0.5, "y": 0.1}  # the toy's Config()
    assert n.seeds == tuple(unit_seed(0, NOMINAL_POINT, j) for j in range(3))
    assert not set(n.seeds) & {s for row in r.seeds for s in row}  # no design point's seed
    assert n.constraint_medians == (0.5, 0.1) and n.in_region  # x > 0.3 and y < 0.5 by construction
    assert n.unit_coordinates == pytest.approx((0.5, 0.5))  # 0.1 is the log-midpoint of [1e-2, 1]
    # x = 0.5: each unit passes q when 0.05 e > 0.1 (2 sigma), so a majority of 3 passes with
    # probability about 2e-3: the nominal device fails toy.q
    assert n.verdicts[0] == "fails" and n.testable == (3, 3)
    reg = list(r.region)
    d = cdist(r.design.unit[reg], r.design.unit[reg]).sum(axis=1)
    assert r.medoid == reg[int(np.argmin(d))]
    text = region.nominal_text(r)
    assert "lies in the region" in text and f"Region medoid: point {r.medoid}" in text
    r2 = _reanalysed(toy_map, (*toy.MAP_CONSTRAINTS, toy.NEVER))
    assert r2.medoid is None and "The region is empty" in region.nominal_text(r2)


def test_a_family_whose_base_lies_outside_a_range_has_no_nominal_point():
    off = Family(paper="toy", base=dataclasses.replace(toy.Config(), y=2.0), parameters=toy.FAMILY.parameters)
    assert off.nominal is None
    assert toy.FAMILY.nominal == {"x": 0.5, "y": 0.1}
    p = toy.FAMILY.parameters[1]
    assert p.coordinate(p.value(0.3)) == pytest.approx(0.3)  # the inverse of the design's mapping


def test_map_json_does_not_depend_on_how_its_units_ran(tmp_path):
    first = _map(tmp_path, points=4, k=2, db_name="a.db")
    again = _map(tmp_path, points=4, k=2, db_name="a.db")  # every unit read back from the store
    assert (first.units.computed, again.units.computed) == (10, 0)
    # map.json is json.dumps(as_dict()) (build.write_map): the run's counts and command are not in it
    assert json.dumps(first.result.as_dict(), indent=1) == json.dumps(again.result.as_dict(), indent=1)


def test_paper_003_family_is_its_config_fields_with_sources_device_facts_and_the_txdt_share():
    from gyrobench.scenarios.papers.p003_ifog_thermal import CLAIMS, Config
    from gyrobench.scenarios.papers.p003_ifog_thermal import family as f003
    from gyrobench.scenarios.papers.p003_ifog_thermal.identify import IDENTIFIED

    for p in f003.FAMILY.parameters:  # every range lies inside the Config's documented range, in its unit
        spec = Config.RANGES[p.field]
        assert spec.contains(p.range.low) and spec.contains(p.range.high), p.field
        assert p.source.strip(), p.field
    assert f003.FAMILY.nominal is not None  # the default reproduction's device is a point of the family
    assert f003.FAMILY.nominal["lead_difference_rms_m"] == IDENTIFIED.lead_difference_rms_m
    device = [c for c in CLAIMS if c.role == "device"]
    assert [(c.id, c.quantity, c.comparator) for c in f003.MAP_CONSTRAINTS] == [
        (c.id, c.quantity, c.comparator) for c in device]
    assert {c.id for c in f003.MAP_CLAIMS} >= {"003.val2_lowest", "003.val1_every_run"}
    assert all(c.role != "device" for c in f003.MAP_CLAIMS)
    assert [v.quantity for v in f003.MAP_COVARIATES] == ["txdt_share", "txdt_unabsorbed"]


def test_coil_defect_sizes_reach_the_drawn_unit():
    from gyrobench.sim.coil2d import Coil2DSpec
    from gyrobench.sim.coil_winding import Imperfections

    def draw(**kw):
        return Imperfections.draw(dataclasses.replace(Coil2DSpec(), **kw), rng=np.random.default_rng(5))

    base = draw()
    assert np.count_nonzero(base.turn_errors) > 0 and np.all(draw(turn_error_probability=0.0).turn_errors == 0)
    assert np.all(draw(radius_error_rms=0.0).radius_errors == 0.0)
    np.testing.assert_allclose(draw(radius_error_rms=0.06).radius_errors, 2 * base.radius_errors, rtol=1e-12)
    # the sensor stays on the surface within 1 - |c| of the centre c
    zs = [Imperfections.draw(dataclasses.replace(Coil2DSpec(), sensor_z_center=0.8),
                             rng=np.random.default_rng(s)).sensor_z for s in range(200)]
    assert min(zs) >= 0.6 - 1e-12 and max(zs) <= 1.0 + 1e-12 and max(zs) - min(zs) > 0.3
    with pytest.raises(ValueError, match="turn_error_probability"):
        Coil2DSpec(turn_error_probability=0.6)


def test_txdt_share_is_zero_for_an_additive_drift_and_does_not_depend_on_the_temperature_origin():
    from gyrobench.scenarios.papers.p003_ifog_thermal import Config
    from gyrobench.scenarios.papers.p003_ifog_thermal.pipeline import txdt_share
    from gyrobench.scenarios.papers.p003_ifog_thermal.runs import Run, features

    cfg = Config()
    t = np.arange(400) * 100.0  # 100-s blocks: a ramp from -10 to 40 degC and back
    T = 15.0 + 25.0 * (1 - np.abs((t / t[-1]) * 2 - 1)) * 2 - 25.0

    def run(drift, T=T):
        return Run(name="ident_1", t_h=t / 3600, T=T, output=drift, truth=0 * t, drift=drift, fs=0.01,
                   reference=0.0, scored=None)

    X = features(run(0 * t), cfg)
    additive = 0.3 * X[:, 0] + 50.0 * X[:, 1]
    assert abs(txdt_share(cfg, run(additive))) < 1e-9
    product = additive + 40.0 * X[:, 2]
    share = txdt_share(cfg, run(product))
    assert share > 0.01
    shifted = run(product, T=T + 20.0)  # the same drift, the temperature read from another origin
    assert txdt_share(cfg, shifted) == pytest.approx(share, rel=1e-9)
