"""Paper 000's device family (scenarios/papers/p000_fog_vibration/family.py): its parameters reach
the drawn unit inside the models' documented ranges, its nominal point is ``reproduce``'s device,
the device facts kept out of the region are the unreachable ones, and a tiny map through the CLI
recounts from map.json."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from gyrobench.scenarios.maps.family import design, get_path
from gyrobench.scenarios.papers import p000_fog_vibration as fv
from gyrobench.scenarios.papers.p000_fog_vibration import family as f000
from gyrobench.scenarios.papers.p000_fog_vibration.identify import INPUTS, required_record_s
from tests.scenarios.test_cli import run
from tests.scenarios.test_maps import _recount

pytestmark = pytest.mark.usefixtures("user_files")


def _documented_range(path: str):
    head, _, name = path.rpartition(".")
    parent = get_path(fv.Config(), head) if head else fv.Config()
    return type(parent).RANGES[name]


def test_every_parameter_lies_inside_its_models_documented_range_and_unit():
    for p in f000.FAMILY.parameters:
        spec = _documented_range(p.field)
        assert spec.contains(p.range.low) and spec.contains(p.range.high), p.field
        assert spec.unit == p.range.unit, (p.field, spec.unit, p.range.unit)
        assert p.source.strip() and p.label.strip()
    for fx in f000.FAMILY.fixed:
        get_path(fv.Config(), fx.field)
        assert fx.source.strip()


def test_the_nominal_point_is_reproduces_default_device():
    nominal = f000.FAMILY.nominal
    assert f000.FAMILY.config(nominal) == fv.Config()  # equal configs: the same run id as reproduce's
    assert nominal["fog.mount.x.frequency"] == 400.0 and nominal["vibration_s"] == 300.0


def test_a_point_reaches_the_drawn_mount_and_the_record():
    point = {p.field: p.value(0.7) for p in f000.FAMILY.parameters}
    cfg = f000.FAMILY.config(point)
    # the unit-to-unit law multiplies the point's mount (FogSpec.draw_mount), the same factors either way
    mount = cfg.fog.draw_mount(np.random.default_rng(5))
    nominal_mount = fv.Config().fog.draw_mount(np.random.default_rng(5))
    for axis in ("x", "y"):
        got, ref = getattr(mount, axis), getattr(nominal_mount, axis)
        for name in ("frequency", "compliance"):
            want = point[f"fog.mount.{axis}.{name}"] / get_path(fv.Config(), f"fog.mount.{axis}.{name}")
            assert getattr(got, name) / getattr(ref, name) == pytest.approx(want, rel=1e-12)
        assert got.quality == point[f"fog.mount.{axis}.quality"]
    fixed = cfg.fixed()
    assert (fixed.static_before, fixed.vibration.duration, fixed.static_after) == tuple(
        point[k] for k in ("static_before_s", "vibration_s", "static_after_s"))
    assert cfg.fog.noise() != fv.Config().fog.noise()  # B reaches the noise model


def test_a_value_outside_a_range_is_one_line_naming_the_parameter_range_and_value():
    point = f000.FAMILY.nominal
    point["vibration_s"] = 30.0
    with pytest.raises(ValueError) as exc:
        f000.FAMILY.config(point)
    msg = str(exc.value)
    assert "\n" not in msg and "vibration_s must be in [150, 900] s" in msg and "30.0" in msg


def test_constraints_are_the_device_facts_less_the_ones_no_record_of_the_family_reaches():
    device = {c.id for c in fv.CLAIMS if c.role == "device"}
    cons = {c.id for c in f000.MAP_CONSTRAINTS}
    assert set(f000.KEPT_OUT) <= device and cons == device - set(f000.KEPT_OUT)
    longest = max(f000.FAMILY.parameters[i].range.high for i in range(6, 9))  # the phases
    low_b = f000.FAMILY.parameters[-1].range.low

    for t in ("K", "R"):  # each kept out for a record length the family cannot give, at its lowest B too
        assert required_record_s(t, dataclasses.replace(INPUTS, B_deg_h=low_b)) > 1000 * longest
    # B is reachable: the family's longest phase at its highest B spans the record B needs
    high_b = dataclasses.replace(INPUTS, B_deg_h=f000.FAMILY.parameters[-1].range.high)
    assert required_record_s("B", high_b) < longest
    ids = [c.id for c in f000.MAP_CLAIMS]
    assert len(ids) == len(set(ids)) and set(f000.KEPT_OUT) <= set(ids)
    assert {c.id for c in fv.CLAIMS if c.role != "device"} <= set(ids)


def test_the_default_design_stays_inside_the_family_and_two_workers_fit_in_4_gb():
    d = design(f000.FAMILY, f000.DEFAULT_POINTS, f000.DESIGN_SEED)
    assert d.method == "sobol" and len(d) == 32
    longest = {**f000.FAMILY.nominal, "static_before_s": 900.0, "vibration_s": 900.0, "static_after_s": 900.0}
    worst = fv.memory_estimate(f000.FAMILY.config(longest))  # the family's largest record
    assert max(fv.memory_estimate(f000.FAMILY.config(v)) for v in d.values) <= worst
    assert 2 * worst < 4e9  # the default map's two local workers on a 4 GB share of the machine


@pytest.mark.slow  # two paper-000 units (about 3 s of CPU each) and the map's figures
def test_a_tiny_map_through_the_cli_writes_map_json_that_recounts(tmp_path, capsys):
    code, out, err = run(["reproduce", "fog_vibration", "--map", "--points", "2", "--units-per-point", "1",
                          "--workers", "0", "-q", "--out", tmp_path / "r"], capsys)
    assert code == 0, err
    doc = json.loads((tmp_path / "r" / "fog_vibration" / "map.json").read_text())
    ref = doc.get("refinement") or {}  # a region this small is refined: a second stage after the first 2
    refined = ref.get("points", 0) if ref.get("triggered") else 0
    assert ref.get("first_points", 2) == 2
    assert doc["design"] == {"method": "sobol", "seed": f000.DESIGN_SEED, "points": 2 + refined,
                            "units_per_point": 1}
    assert [c["id"] for c in doc["constraints"]] == [c.id for c in f000.MAP_CONSTRAINTS]
    reg, counts, verdicts = _recount(doc)
    assert reg == doc["region"] and counts == doc["constraint_counts"]
    for c in doc["claims"]:
        assert (c["region_holds"], c["region_testable"]) == verdicts[c["id"]][:2]
        assert (c["family_holds"], c["family_testable"]) == verdicts[c["id"]][3:]


def test_the_phases_are_whole_seconds_on_every_sample_grid():
    """A phase off the output's sample grid ends between samples (the record holds floor(T fs) of them):
    the family's phases take whole seconds, on the 400 Hz output's and the 3.2 kHz shaker's grid."""
    d = design(f000.FAMILY, f000.DEFAULT_POINTS, f000.DESIGN_SEED)
    fog = fv.Config().fog
    for v in d.values:
        for k in ("static_before_s", "vibration_s", "static_after_s"):
            assert v[k] == round(v[k]) and f000.FAMILY.config(v)  # whole seconds, a valid config
            assert (v[k] * fog.output_rate_hz).is_integer() and (v[k] * fog.physics_rate_hz).is_integer()
    p = next(p for p in f000.FAMILY.parameters if p.field == "vibration_s")
    assert (p.value(0.0), p.value(1.0), p.value(0.5)) == (150.0, 900.0, 525.0)
    assert p.value(0.3331) == round(150.0 + 0.3331 * 750.0)  # the nearest whole second
