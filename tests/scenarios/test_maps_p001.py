"""Paper 001's device family (scenarios/papers/p001_mems_scale_factor/family.py): its parameters reach
the device inside the models' documented ranges, its nominal point is ``reproduce``'s device, its
breakpoint facts hold exactly the table rate +-1800 deg/s, no corner of it reaches pull-in, and a
tiny map through the CLI recounts from map.json."""

from __future__ import annotations

import dataclasses
import itertools
import json
import math

import numpy as np
import pytest

from gyrobench.scenarios.maps.family import design, get_path
from gyrobench.scenarios.papers import p001_mems_scale_factor as ms
from gyrobench.scenarios.papers.p001_mems_scale_factor import family as f001
from tests.scenarios.test_cli import run
from tests.scenarios.test_maps import _recount

pytestmark = pytest.mark.usefixtures("user_files")


def _documented_range(path: str):
    """The RANGES entry of the dataclass that owns the last field of ``path`` (its parent's class)."""
    head, _, name = path.rpartition(".")
    parent = get_path(ms.Config(), head) if head else ms.Config()
    return type(parent).RANGES[name]


def test_every_parameter_lies_inside_its_models_documented_range_and_unit():
    for p in f001.FAMILY.parameters:
        spec = _documented_range(p.field)
        assert spec.contains(p.range.low) and spec.contains(p.range.high), p.field
        assert spec.unit == p.range.unit, (p.field, spec.unit, p.range.unit)
        assert p.source.strip() and p.label.strip()
    for fx in f001.FAMILY.fixed:  # a fixed field names a real field, with a source
        get_path(ms.Config(), fx.field)
        assert fx.source.strip()


def test_the_nominal_point_is_reproduces_default_device():
    nominal = f001.FAMILY.nominal
    cfg = f001.FAMILY.config(nominal)
    # equal configs: the same run id (runner.units.run_id hashes the module and the config), so the
    # map's nominal point and `reproduce mems_scale_factor` judge the same device
    assert cfg == ms.Config()
    assert nominal == {p.field: get_path(ms.Config(), p.field) for p in f001.FAMILY.parameters}


def test_a_point_reaches_the_device_the_identified_variant_builds():
    from gyrobench.scenarios.papers.p001_mems_scale_factor.device import device_spec
    from gyrobench.scenarios.papers.p001_mems_scale_factor.identify import IDENTIFIED

    point = {p.field: p.value(0.25) for p in f001.FAMILY.parameters}
    spec = device_spec(f001.FAMILY.config(point))
    chain = spec.chain.nominal
    assert (chain.rail, chain.sense_bias, chain.k3, chain.gap) == tuple(
        point[f"readout.nominal.{k}"] for k in ("rail", "sense_bias", "k3", "gap"))
    assert chain.feedback_capacitance == IDENTIFIED.feedback_capacitance_f  # the identified C_f is kept
    assert spec.resonator.quadrature_spread == point["gyro.quadrature_spread"]
    assert spec.nominal.pickoff_noise == point["gyro.nominal.pickoff_noise"]
    assert spec.nominal.scale_factor_repeatability == point["gyro.nominal.scale_factor_repeatability"]


def test_a_value_outside_a_range_is_one_line_naming_the_parameter_range_and_value():
    point = f001.FAMILY.nominal
    point["readout.nominal.rail"] = 5.0
    with pytest.raises(ValueError) as exc:
        f001.FAMILY.config(point)
    msg = str(exc.value)
    assert "\n" not in msg
    assert "readout.nominal.rail must be in [1, 3] V" in msg and "5.0" in msg
    with pytest.raises(ValueError, match=r"'rial' is not a field of readout.nominal \(SenseChain\)"):
        bad = dataclasses.replace(f001.FAMILY.fixed[0], field="readout.nominal.rial")
        dataclasses.replace(f001.FAMILY, fixed=(bad,))


def test_constraints_are_the_device_claims_and_the_breakpoints_which_hold_exactly_the_table_rate():
    device = [(c.id, c.quantity, c.comparator) for c in ms.CLAIMS if c.role == "device"]
    cons = f001.MAP_CONSTRAINTS
    assert [(c.id, c.quantity, c.comparator) for c in cons[: len(device)]] == device
    by_id = {c.id: c for c in cons}
    rates = ms.config.default_rates()
    for side, sign in (("positive", 1.0), ("negative", -1.0)):
        fact = by_id[f"001.breakpoint_{side}"]
        misses = [abs(r - sign * 1800.0) for r in rates if sign * r > 0]
        assert [m for m in misses if fact.holds(m)] == [0.0]  # the table rate 1800 only
        assert not fact.holds(math.nan)  # no unit split that side
        # a median of two units averages two misses: only two splits at 1800 give a median in the band
        for a, b in itertools.combinations_with_replacement(misses, 2):
            assert fact.holds((a + b) / 2) == (a == b == 0.0)
    assert f001.MAP_CLAIMS and all(c.role != "device" for c in f001.MAP_CLAIMS)


def test_no_corner_of_the_family_reaches_pull_in_at_full_scale():
    """The read-out's ranges are stated to keep every drawn chain clear of the harmonic balance's
    pull-in: every corner of (rail, bias, k3, gap, quadrature), with the chain's tolerances at 3 sigma
    the worst way (gap small, bias large, k3 either way) and the quadrature at 3 sigma, settles at
    the table's 3600 deg/s."""
    from gyrobench.base import units as u
    from gyrobench.scenarios.papers.p001_mems_scale_factor.identify import IDENTIFIED
    from gyrobench.sim import mems_resonator as mr
    from gyrobench.sim.mems_readout import SenseChain

    spec = ms.Config().readout
    r = {p.field.rpartition(".")[2]: p.range for p in f001.FAMILY.parameters}
    w = u.deg_per_s(np.array([-3600.0, 3600.0]))
    for rail, bias, k3, gap, q in itertools.product(*((r[k].low, r[k].high) for k in (
            "rail", "sense_bias", "k3", "gap", "quadrature_spread"))):
        for k3_z in (-3.0, 3.0):
            chain = SenseChain(
                gap=gap * (1 - 3 * spec.gap_spread), sense_bias=bias * (1 + 3 * spec.sense_bias_spread),
                k3=k3 * (1 + k3_z * spec.k3_spread), rail=rail,
                feedback_capacitance=IDENTIFIED.feedback_capacitance_f,
            )
            unit = dataclasses.replace(mr.MemsResonator(readout="open_loop", sense_chain=chain),
                                       quadrature_coupling=3 * q)
            op = mr.operating_point(unit)
            ch = mr._static_channels(op, w, np.zeros(2))  # raises at pull-in or a Duffing jump
            assert np.all(np.isfinite(ch.real))


def test_the_default_design_stays_inside_the_family():
    d = design(f001.FAMILY, f001.DEFAULT_POINTS, f001.DESIGN_SEED)
    assert d.method == "sobol" and len(d) == 32
    for v in d.values:
        f001.FAMILY.config(v)


@pytest.mark.slow  # two paper-001 units (about 4 s of CPU each) and the map's figures
def test_a_tiny_map_through_the_cli_writes_map_json_that_recounts(tmp_path, capsys):
    code, out, err = run(["reproduce", "mems_scale_factor", "--map", "--points", "2", "--units-per-point", "1",
                          "--workers", "0", "-q", "--out", tmp_path / "r"], capsys)
    assert code == 0, err
    doc = json.loads((tmp_path / "r" / "mems_scale_factor" / "map.json").read_text())
    ref = doc.get("refinement") or {}  # a region this small is refined: a second stage after the first 2
    refined = ref.get("points", 0) if ref.get("triggered") else 0
    assert ref.get("first_points", 2) == 2
    assert doc["design"] == {"method": "sobol", "seed": f001.DESIGN_SEED, "points": 2 + refined,
                            "units_per_point": 1}
    assert [c["id"] for c in doc["constraints"]] == [c.id for c in f001.MAP_CONSTRAINTS]
    reg, counts, verdicts = _recount(doc)
    assert reg == doc["region"] and counts == doc["constraint_counts"]
    for c in doc["claims"]:
        assert (c["region_holds"], c["region_testable"]) == verdicts[c["id"]][:2]
        assert (c["family_holds"], c["family_testable"]) == verdicts[c["id"]][3:]
    for p in doc["points"]:  # each point's breakpoint medians are what its unit reported
        assert set(p["constraint_medians"]) == {c.id for c in f001.MAP_CONSTRAINTS}


def test_the_noise_free_table_is_the_slow_flows_settled_output():
    """noise_free_table (static channels) against the slow flow run from equilibrium without noise
    (device.static_output): the same table to 1e-6 deg/s at three points of the family."""
    from gyrobench.scenarios.papers.p001_mems_scale_factor.device import device_spec, static_output
    from gyrobench.scenarios.papers.p001_mems_scale_factor.identify import nominal_open_loop_unit

    for u in (0.05, 0.5, 0.95):
        cfg = f001.FAMILY.config({p.field: p.value(u) for p in f001.FAMILY.parameters})
        spec = device_spec(cfg)
        unit = nominal_open_loop_unit(spec.chain.nominal, spec.nominal)
        slow = static_output(unit, np.asarray(cfg.rates_dps), unit.reference_temperature)
        np.testing.assert_allclose(f001.noise_free_table(cfg), slow, rtol=0, atol=1e-6)


def test_the_noise_free_breakpoint_scan_counts_every_point_once():
    scan = f001.noise_free_breakpoints(16)
    assert scan.points == 16 == sum(scan.splits.values())
    assert scan.at_1800 == scan.splits.get("(-1800.0, 1800.0)", 0)
    assert scan.k_n_facts == sum(scan.k_n_facts_splits.values()) <= 16
    assert all(scan.splits[k] >= v for k, v in scan.k_n_facts_splits.items())
