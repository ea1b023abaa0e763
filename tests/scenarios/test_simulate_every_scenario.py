"""Every scenario is a dataset generator: 'gyrobench simulate NAME' writes its recordings and they
read back, finite, in the recording schema (docs/recording.md): `output`, `truth/true_rate` and the
components the metadata names, summing to `output - true_rate` to rounding; `allan` reads the first
file without flags."""

from __future__ import annotations

import numpy as np
import pytest

from gyrobench.io.recording import closure, list_hdf5, load_hdf5, schema_problems
from gyrobench.scenarios import registry

from .test_cli import run

# every test runs among planted user files and fails if one changes (tests/conftest.py)
pytestmark = pytest.mark.usefixtures("user_files")

#: physics_checks keeps no recordings (its simulate returns none; each check simulates internally)
GENERATORS = [name for name in registry.available() if name != "physics_checks"]


def test_every_paper_is_a_generator():
    assert {"fog_vibration", "mems_scale_factor", "ifog_thermal", "rlg_thermal", "static_noise"} <= set(GENERATORS)


@pytest.mark.slow
@pytest.mark.parametrize("name", GENERATORS)
def test_simulate_scenario_writes_what_reads_back(tmp_path, capsys, name):
    code, out, err = run(["simulate", name, "--seed", "1", "--out", tmp_path / "out", "-q"], capsys)
    assert code == 0, err
    files = sorted((tmp_path / "out").rglob("*.h5"))
    assert files, out
    for path in files:
        for rec_name in list_hdf5(path):
            rec = load_hdf5(path, rec_name)
            assert rec.n_samples > 0 and rec.truth, (path, rec_name)
            for ch in rec.columns().values():
                assert np.all(np.isfinite(ch.data)), (path, rec_name)
            assert schema_problems(rec) == [], (path, rec_name, schema_problems(rec))
            resid, scale = closure(rec)
            m = len(rec.metadata["error_components"])
            # m + 2 terms rounded at eps of the largest magnitude, x16 for the models' operations; an RLG's
            # output differences a cumulative angle: its rounding is eps x n max|output|
            if name == "rlg_thermal":
                scale = max(scale, 2 * rec.n_samples * float(np.max(np.abs(rec["output"]))))
            assert resid <= 16 * (m + 2) * np.finfo(float).eps * scale, (path, rec_name, resid, scale)
    code, out, err = run(["allan", files[0], "--accept-nonstationary"], capsys)
    assert code == 0 and "output" in out, err
