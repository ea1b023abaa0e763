"""The physics_checks scenario and the check modules (noise, FOG, RLG)."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

from gyrobench.scenarios import physics_checks, registry
from gyrobench.scenarios.checks import coil as checks_coil
from gyrobench.scenarios.checks import noise as checks_noise
from gyrobench.scenarios.checks import rlg as checks_rlg
from gyrobench.scenarios.checks.core import CHECK_MODULES, collect
from gyrobench.scenarios.reports.report import write_report


@pytest.fixture(scope="module")
def outcome():
    return physics_checks.run(physics_checks.Config(), 0)


@pytest.mark.slow  # every model's checks, the full-equation MEMS and loop ones included (~1 min)
def test_every_check_passes_and_is_reported(outcome, tmp_path):
    ids = [c["id"] for c in outcome.results["checks"]]
    # each check module contributes its ids, in CHECK_MODULES order
    assert [m.rsplit(".", 1)[1].removeprefix("checks_") for m in CHECK_MODULES] == [
        "noise", "fog", "rlg", "mems", "rlg_cavity", "fog_loop", "coil", "mems_nonlinear", "mount_coning",
        "fog_strain", "shaker", "trajectory",
    ]
    assert ids[:9] == [
        "noise.avar_Q",
        "noise.avar_N",
        "noise.avar_B",
        "noise.avar_K",
        "noise.avar_R",
        "fog.sagnac_scale_factor",
        "rlg.adler_beat_1.1x_lock_in",
        "rlg.adler_beat_2x_lock_in",
        "rlg.dither_random_walk",
    ]
    failed = [c for c in outcome.results["checks"] if not c["passed"]]
    assert not failed, failed
    write_report([outcome], tmp_path)
    doc = json.loads((tmp_path / "physics_checks" / "results.json").read_text())
    for c in doc["checks"]:
        assert {
            "id",
            "kind",
            "formula",
            "expected",
            "simulated",
            "rel_error",
            "tolerance",
            "reference",
            "passed",
        } <= set(c)
        assert c["rel_error"] <= c["tolerance"] and c["tolerance_derivation"]
    n = len(ids)
    assert f"| physics checks passed | {n}/{n} | {n}/{n} | yes |" in (tmp_path / "report.md").read_text()


#: a published source carries its year; a bare module path or the project's own docs are not one
_YEAR = re.compile(r"\b(1[89]\d\d|20\d\d)\b")
_INTERNAL_ONLY = re.compile(r"[\s\w.:/()-]*(gyrobench|docs/physics\.md|sim\.|scenarios\.)[\s\w.:/()-]*")


@pytest.mark.slow  # shares the module fixture: every registered check, run once
def test_every_check_cites_an_outside_reference(outcome):
    """Issue 23 item 5: each check names where its expected value comes from outside the code."""
    checks = outcome.results["checks"]
    assert len(checks) >= 63
    missing = [c["id"] for c in checks if not c["reference"].strip()]
    internal = [c["id"] for c in checks if _INTERNAL_ONLY.fullmatch(c["reference"])]
    undated = [c["id"] for c in checks if not _YEAR.search(c["reference"])]
    assert not missing and not internal and not undated, (missing, internal, undated)
    second = [c for c in checks if c["reference"].startswith("second method:")]
    assert all(len(c["reference"]) > len("second method: ") + 20 for c in second)


def test_a_check_without_a_reference_is_refused():
    from gyrobench.scenarios.checks.core import Check

    with pytest.raises(ValueError, match="reference must be a non-empty string"):
        Check(id="x.y", formula="a = b", expected=1.0, simulated=1.0, tolerance=0.1, derivation="d", reference=" ",
              kind="closed form")


def test_a_check_without_a_known_reference_kind_is_refused():
    from gyrobench.scenarios.checks.core import Check

    with pytest.raises(ValueError, match="kind must be one of"):
        Check(id="x.y", formula="a = b", expected=1.0, simulated=1.0, tolerance=0.1, derivation="d",
              reference="A. Book (1999)", kind="validated")


@pytest.mark.slow  # shares the module fixture: every registered check, run once
def test_every_check_declares_a_reference_kind_and_the_report_counts_them(outcome, tmp_path):
    from gyrobench.scenarios.checks.core import KINDS, VALIDATION_KINDS

    checks = outcome.results["checks"]
    assert all(c["kind"] in KINDS for c in checks), [c["id"] for c in checks if c["kind"] not in KINDS]
    counts = outcome.results["kind_counts"]
    assert list(counts) == list(KINDS) and sum(counts.values()) == len(checks)
    for k in KINDS:
        assert counts[k] == sum(c["kind"] == k for c in checks)
    write_report([outcome], tmp_path)
    md = (tmp_path / "report.md").read_text()
    n_valid = sum(counts[k] for k in VALIDATION_KINDS)
    assert f"| checks with an outside reference (validation) | {n_valid}/{len(checks)} |" in md


def test_registered_last_and_part_of_all():
    assert list(registry.SCENARIOS)[-1] == "physics_checks"
    assert "physics_checks" in registry.available()
    assert physics_checks.Config().modules == CHECK_MODULES


def test_same_seed_same_numbers_and_modules_have_own_streams():
    a = physics_checks.run_checks(physics_checks.Config(modules=CHECK_MODULES[:1]), 7)
    b = physics_checks.run_checks(physics_checks.Config(modules=CHECK_MODULES[:1]), 7)
    assert [c.simulated for c in a] == [c.simulated for c in b]
    c = physics_checks.run_checks(physics_checks.Config(modules=CHECK_MODULES[:1]), 8)
    assert [x.simulated for x in a] != [x.simulated for x in c]


def test_a_wrong_model_fails_the_noise_checks(monkeypatch):
    """The checks can fail: AVAR theory off by 10 % is outside every statistical band but K's."""
    real = checks_noise._theory
    monkeypatch.setattr(
        checks_noise, "_theory", lambda term, model, tau: 1.1 * real(term, model, tau)
    )
    res = {c.id: c.passed for c in checks_noise.checks(np.random.default_rng(0))}
    assert res == {
        "noise.avar_Q": False,
        "noise.avar_N": False,
        "noise.avar_B": False,
        "noise.avar_K": True,
        "noise.avar_R": False,
    }


def test_a_wrong_winding_fails_the_shupe_checks(monkeypatch):
    """A (r, z) coil that winds 'quadrupolar' coils dipolar (AB instead of ABBA) is caught."""
    from gyrobench.sim import coil_winding

    real = coil_winding.winding_sequence
    monkeypatch.setattr(
        coil_winding, "winding_sequence", lambda p, m: real("dipolar" if p == "quadrupolar" else p, m)
    )
    res = {c.id: c.passed for c in checks_coil.checks(np.random.default_rng(0))}
    assert not res["coil.shupe_radial_quadrupolar"] and not res["coil.shupe_radial_cancellation_ratio"]
    assert res["coil.shupe_radial_helical"]


def test_adler_check_uses_the_model(monkeypatch):
    """A lock-in rate 1 % off in the model moves the beat frequency outside the tolerance."""
    from gyrobench.sim import rlg

    real = rlg.integrate_adler
    monkeypatch.setattr(
        rlg,
        "integrate_adler",
        lambda *a, lock_in_rate, **k: real(*a, lock_in_rate=1.01 * lock_in_rate, **k),
    )
    checks = {c.id: c for c in [checks_rlg._adler(1.1)]}
    assert not checks["rlg.adler_beat_1.1x_lock_in"].passed


def test_collect_refuses_duplicate_ids():
    with pytest.raises(ValueError, match="check ids must be unique"):
        collect(
            np.random.default_rng(0),
            ("gyrobench.scenarios.checks.fog", "gyrobench.scenarios.checks.fog"),
        )


def test_config_refuses_bad_modules():
    with pytest.raises(ValueError, match="at least one check module"):
        physics_checks.Config(modules=())
    with pytest.raises(ValueError, match=r"Config.modules\[1\] must be one of \('gyrobench.scenarios.checks.noise'.*"):
        physics_checks.Config(modules=(CHECK_MODULES[0], 3))


@pytest.mark.slow  # runs the check modules twice, in process and on workers (tens of seconds): slow tier
def test_checks_on_worker_processes_equal_checks_in_process():
    """The modules' numbers do not depend on where they run (each has its own child stream)."""
    cfg = physics_checks.Config(modules=CHECK_MODULES[:3])
    here = physics_checks.run_checks(cfg, 3)
    pooled = physics_checks.run_checks(cfg, 3, workers=2)
    assert [(c.id, c.simulated) for c in here] == [(c.id, c.simulated) for c in pooled]


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_progress_bar_moves_per_part_and_changes_no_number(capsys):
    """The bar reports each module, or each part of a module with parts, as it finishes; the
    checks are those of a run without it, and those of the modules' own ``checks``."""
    cfg = physics_checks.Config(
        modules=("gyrobench.scenarios.checks.fog", "gyrobench.scenarios.checks.rlg", "gyrobench.scenarios.checks.coil")
    )
    plain = physics_checks.run_checks(cfg, 3)
    shown = physics_checks.run_checks(cfg, 3, progress=True)
    assert [c.as_dict() for c in shown] == [c.as_dict() for c in plain]
    err = capsys.readouterr().err
    assert "fog: 1/1 passed" in err and "coil: 10/10 passed" in err
    assert "rlg.adler_1.1: 1/1 passed" in err and "rlg.dither: 1/1 passed" in err
    assert "1/5" in err and "4/5" in err  # fog, three rlg parts, coil
    children = np.random.default_rng(3).spawn(3)
    assert [c.simulated for c in checks_rlg.checks(children[1])] == [c.simulated for c in plain[1:4]]


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_parts_on_workers_equal_parts_in_process():
    """A module split in parts gives the same numbers on a pool as in process."""
    cfg = physics_checks.Config(modules=("gyrobench.scenarios.checks.rlg",))
    here = physics_checks.run_checks(cfg, 4)
    pooled = physics_checks.run_checks(cfg, 4, workers=2)
    assert [(c.id, c.simulated) for c in here] == [(c.id, c.simulated) for c in pooled]
